# cleanslam-replay: two runs on the same dataset give byte-identical outputs.
. "$(dirname "$0")/common.sh"
simulate
run "$REPLAY" "$WORK/ds" --out "$WORK/a" 2>"$WORK/a.err" || { cat "$WORK/a.err" >&2; fail "first replay"; }
run "$REPLAY" "$WORK/ds" --out "$WORK/b" 2>"$WORK/b.err" || { cat "$WORK/b.err" >&2; fail "second replay"; }
for f in trajectory.tum trajectory.tum.cov dead_reckoning.tum landmarks.csv diagnostics.csv; do
  [ -s "$WORK/a/$f" ] || fail "$f missing or empty"
  cmp "$WORK/a/$f" "$WORK/b/$f" || fail "$f differs between two replays"
done
[ "$(wc -l <"$WORK/a/trajectory.tum")" -gt 20 ] || fail "too few trajectory poses"
[ "$(wc -l <"$WORK/a/landmarks.csv")" -gt 3 ] || fail "no landmarks"
cat "$WORK/a.err"
echo PASS
