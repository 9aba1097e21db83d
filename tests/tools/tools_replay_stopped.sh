# A replay stopped by Ctrl-C (SIGINT) says that its outputs are partial, and exits 130.
. "$(dirname "$0")/common.sh"
run "$BIN/cleanslam-sim" default-room "$WORK/ds" --set duration_s=300 >/dev/null 2>&1 ||
  fail "cleanslam-sim"
# exec: the signal goes to the program, not to a shell around it.
# shellcheck disable=SC2086
(exec $EMU "$BIN/cleanslam-replay" "$WORK/ds" --out "$WORK/run" 2>"$WORK/replay.err" </dev/null) &
pid=$!
# Interrupted once it is under way (its first progress line after 0 %).
for _ in $(seq 1 600); do
  grep -q "^cleanslam-replay: *[1-9][0-9]* % (t=" "$WORK/replay.err" 2>/dev/null && break
  sleep 0.05
done
kill -INT "$pid" 2>/dev/null || true
status=0
wait "$pid" || status=$?
if grep -q "^cleanslam-replay: 100 % (t=" "$WORK/replay.err"; then
  echo "SKIP: the replay ended before the signal arrived"
  exit 77
fi
[ "$status" -eq 130 ] || { cat "$WORK/replay.err"; fail "stopped replay exited $status, expected 130"; }
grep -q "^cleanslam-replay: stopped by a signal at t=[0-9.]* s of 300\.[0-9] s: outputs in $WORK/run are partial$" \
  "$WORK/replay.err" || { cat "$WORK/replay.err"; fail "no line saying the outputs are partial"; }
echo "PASS"
