# Rendered camera images through the front end's frame pipeline: record, replay, identical.
. "$(dirname "$0")/common.sh"
run "$SIM" default-room "$WORK/ds" --set duration_s=10 --set camera.mode=images >"$WORK/sim.log" 2>&1 ||
  { cat "$WORK/sim.log" >&2; fail "cleanslam-sim"; }
run "$CLEANSLAM" --dataset "$WORK/ds" --record "$WORK/run.log" \
  --set sinks.diagnostics="$WORK/diag.csv" 2>"$WORK/run.err" || { cat "$WORK/run.err" >&2; fail "recording run"; }
grep -q ",updated," "$WORK/diag.csv" || fail "no visual update from images"
run "$CLEANSLAM" --replay "$WORK/run.log" 2>"$WORK/replay.err" || { cat "$WORK/replay.err" >&2; fail "replay differs"; }
cat "$WORK/replay.err"
echo PASS
