# A misspelt --set key is an error in every program, naming the nearest valid key.
. "$(dirname "$0")/common.sh"
features_dataset "$WORK/ds"
expect 2 "$WORK/replay.err" "unknown key filter.eps_ctm; did you mean filter.eps_ct_m?" \
  "$BIN/cleanslam-replay" "$WORK/ds" --out "$WORK/run" --set filter.eps_ctm=1
[ ! -e "$WORK/run" ] || fail "replay wrote outputs despite the unknown key"
expect 2 "$WORK/section.err" "unknown key filtr; did you mean filter.eps_ct_m?" \
  "$BIN/cleanslam-replay" "$WORK/ds" --out "$WORK/run" --set filtr.eps_ct_m=1
expect 2 "$WORK/firmware.err" "did you mean loop.frame_rate_hz?" \
  "$BIN/cleanslam" --dataset "$WORK/ds" --set loop.frame_rate=1
expect 1 "$WORK/sim.err" "did you mean camera.rate_hz?" \
  "$BIN/cleanslam-sim" default-room "$WORK/ds2" --set camera.rate=1
run "$BIN/cleanslam-replay" "$WORK/ds" --out "$WORK/run" --set filter.eps_ct_m=1 2>"$WORK/ok.err" ||
  { cat "$WORK/ok.err" >&2; fail "a valid --set key was refused"; }
echo "PASS"
