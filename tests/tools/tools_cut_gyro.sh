# A gyro.csv cut at a line boundary halfway through: cleanslam-replay prints the firmware's
# health report and exits non-zero naming the file, unless --accept-gaps.
. "$(dirname "$0")/common.sh"
features_dataset "$WORK/ds"
run "$BIN/cleanslam-replay" "$WORK/ds" --out "$WORK/intact" 2>"$WORK/intact.err" ||
  { cat "$WORK/intact.err" >&2; fail "the intact dataset was refused"; }
! grep -q "gyro silent" "$WORK/intact.err" || fail "gyro silent on the intact dataset"
cp -r "$WORK/ds" "$WORK/cut"
lines=$(wc -l <"$WORK/ds/gyro.csv")
head -n $((lines / 2)) "$WORK/ds/gyro.csv" >"$WORK/cut/gyro.csv"
expect 1 "$WORK/cut.err" "$WORK/cut/gyro.csv: gyro silent 1 time(s) for longer than loop.gyro_timeout_s" \
  "$BIN/cleanslam-replay" "$WORK/cut" --out "$WORK/cut_run"
grep -q "cleanslam-replay: t=[0-9.]* s: gyro silent (heading from encoders)" "$WORK/cut.err" ||
  fail "no health report line"
grep -q "accept-gaps" "$WORK/cut.err" || fail "the error does not say how to accept the gap"
run "$BIN/cleanslam-replay" "$WORK/cut" --out "$WORK/accepted" --accept-gaps 2>"$WORK/accepted.err" ||
  fail "--accept-gaps still failed"
grep -q "warning: $WORK/cut/gyro.csv: gyro silent" "$WORK/accepted.err" || fail "no warning with --accept-gaps"
echo "PASS"
