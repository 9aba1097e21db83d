# Long work shows progress on stderr also when it is not a terminal: a line every 10 %, up to
# 100 %.
. "$(dirname "$0")/common.sh"
run "$BIN/cleanslam-sim" default-room "$WORK/ds" --set duration_s=20 2>"$WORK/sim.err" </dev/null
grep -q "cleanslam-sim: default-room 100 %" "$WORK/sim.err" || { cat "$WORK/sim.err"; fail "sim progress"; }
run "$BIN/cleanslam-replay" "$WORK/ds" --out "$WORK/run" 2>"$WORK/replay.err" </dev/null
for p in 0 10 50 90 100; do
  grep -q "^cleanslam-replay: *$p % (t=" "$WORK/replay.err" || { cat "$WORK/replay.err"; fail "replay: no $p % line"; }
done
n=$(grep -c "^cleanslam-replay: *[0-9]* % (t=" "$WORK/replay.err")
[ "$n" -eq 11 ] || fail "replay printed $n progress lines, expected 11"
images_dataset "$WORK/im"
run "$BIN/cleanslam-track" "$WORK/im" --out "$WORK/f.csv" 2>"$WORK/track.err" </dev/null
grep -q "^cleanslam-track: 100 % (frame" "$WORK/track.err" || { cat "$WORK/track.err"; fail "track progress"; }
grep -q "^cleanslam-track:  50 % (frame" "$WORK/track.err" || { cat "$WORK/track.err"; fail "track 50 %"; }
echo "PASS"
