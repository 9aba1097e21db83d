# tools/demo.sh checks every argument before it builds or deletes anything, and refuses a
# non-empty output folder unless --force.
. "$(dirname "$0")/common.sh"
DEMO=$SRC/tools/demo.sh
mkdir -p "$WORK/out"
echo keep >"$WORK/out/earlier.txt"
expect 2 "$WORK/mode.err" "is neither a built-in scenario" "$DEMO" --out "$WORK/out" --force features
expect 2 "$WORK/mode2.err" "mode must be images or features" "$DEMO" --out "$WORK/out" --force default-room fast
expect 2 "$WORK/seed.err" "--seed takes a non-negative integer" "$DEMO" --out "$WORK/out" --seed x
expect 2 "$WORK/opt.err" "unknown option" "$DEMO" --outt "$WORK/out"
expect 2 "$WORK/full.err" "is not empty" "$DEMO" --out "$WORK/out" default-room features
[ "$(cat "$WORK/out/earlier.txt")" = keep ] || fail "the demo touched the output folder"
! grep -q "== setup" "$WORK/full.err.out" || fail "the demo started before checking its arguments"
run "$DEMO" --help >"$WORK/help.out" 2>&1 || fail "--help"
grep -q -- "--out DIR" "$WORK/help.out" || fail "--help does not name --out"
echo "PASS"
