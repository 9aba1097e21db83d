# A log cut at arbitrary bytes replays up to its last whole record, with a warning.
. "$(dirname "$0")/common.sh"
simulate
run "$CLEANSLAM" --dataset "$WORK/ds" --record "$WORK/run.log" 2>/dev/null || fail "recording run"
size=$(wc -c <"$WORK/run.log")
for frac in 13 50 77 99; do
  cut=$((size * frac / 100 + 7))
  head -c "$cut" "$WORK/run.log" >"$WORK/cut.log"
  run "$CLEANSLAM" --replay "$WORK/cut.log" 2>"$WORK/cut.err" || { cat "$WORK/cut.err" >&2; fail "replay of a log cut at $cut"; }
  grep -q "truncated at byte" "$WORK/cut.err" || { cat "$WORK/cut.err" >&2; fail "no truncation warning at $cut"; }
  grep -q "reproduced bit for bit (up to the truncation)" "$WORK/cut.err" || fail "verdict at $cut"
done
tail -2 "$WORK/cut.err"
echo PASS
