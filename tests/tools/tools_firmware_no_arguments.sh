# cleanslam with no arguments on a PC (neither can0 nor /dev/video0) says how to run it there
# instead of retrying the robot's devices forever.
. "$(dirname "$0")/common.sh"
if [ -e /sys/class/net/can0 ] || [ -e /dev/video0 ]; then
  echo "SKIP: this machine has can0 or /dev/video0"
  exit 77
fi
status=0
# shellcheck disable=SC2086
timeout 20 $EMU "$BIN/cleanslam" >/dev/null 2>"$WORK/none.err" || status=$?
[ "$status" -eq 2 ] || { cat "$WORK/none.err" >&2; fail "cleanslam without arguments exited $status, expected 2"; }
grep -q "not the robot" "$WORK/none.err" || fail "no explanation"
grep -q "cleanslam --dataset" "$WORK/none.err" || fail "no hint at --dataset"
echo "PASS"
