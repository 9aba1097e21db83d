# A log cut at arbitrary bytes replays up to its last whole record, with a warning.
. "$(dirname "$0")/common.sh"
simulate
run "$CLEANSLAM" --dataset "$WORK/ds" --record "$WORK/run.log" 2>/dev/null || fail "recording run"
size=$(wc -c <"$WORK/run.log")
replay_cut() {
  head -c "$1" "$WORK/run.log" >"$WORK/cut.log"
  run "$CLEANSLAM" --replay "$WORK/cut.log" 2>"$WORK/cut.err" || { cat "$WORK/cut.err" >&2; fail "replay of a log cut at $1"; }
}
for frac in 13 50 77 99; do
  cut=$((size * frac / 100 + 7))
  replay_cut "$cut"
  if ! grep -q "truncated at byte" "$WORK/cut.err"; then
    # The cut fell between two records: a whole log. One byte more cuts a record.
    grep -q "reproduced bit for bit$" "$WORK/cut.err" || fail "verdict of the whole log cut at $cut"
    cut=$((cut + 1))
    replay_cut "$cut"
  fi
  grep -q "truncated at byte" "$WORK/cut.err" || { cat "$WORK/cut.err" >&2; fail "no truncation warning at $cut"; }
  grep -q "reproduced bit for bit (up to the truncation)" "$WORK/cut.err" || fail "verdict at $cut"
done
tail -2 "$WORK/cut.err"
echo PASS
