# plot_run.py: one landmark with a 28 m standard deviation is drawn as a marker and counted; the
# axes stay within the room and the trajectories. Existing PNGs are replaced only with --force.
. "$(dirname "$0")/common.sh"
PLOT=$SRC/tools/eval/plot_run.py
features_dataset "$WORK/ds"
run "$BIN/cleanslam-replay" "$WORK/ds" --out "$WORK/run" 2>/dev/null || fail "replay"
echo "900,3.0,2.5,0.3,784,0,0,784,0,4" >>"$WORK/run/landmarks.csv"
/usr/bin/python3 "$PLOT" "$WORK/run" --gt "$WORK/ds/groundtruth.csv" --out "$WORK/plots" \
  --title "default-room, seed 1, features mode" >"$WORK/plot.out" 2>&1 || { cat "$WORK/plot.out"; fail "plot_run.py"; }
cat "$WORK/plot.out"
line=$(grep "^axes:" "$WORK/plot.out") || fail "no axes line"
# The room is 6 m x 5 m: with the margin the axes stay within -1..7 m and -1..6 m.
echo "$line" | awk '{ if ($3 < -1 || $4 > 7 || $6 < -1 || $7 > 6) exit 1 }' ||
  fail "axes beyond the room: $line"
grep -q "1 landmark with σ > 1 m" "$WORK/plot.out" || fail "the huge landmark is not counted"
[ -s "$WORK/plots/trajectory_xy.png" ] && [ -s "$WORK/plots/position_error.png" ] || fail "no PNGs"
status=0
/usr/bin/python3 "$PLOT" "$WORK/run" --gt "$WORK/ds/groundtruth.csv" --out "$WORK/plots" \
  >/dev/null 2>"$WORK/again.err" || status=$?
[ "$status" -eq 1 ] && grep -q "exists" "$WORK/again.err" || fail "existing PNGs were not refused"
/usr/bin/python3 "$PLOT" "$WORK/run" --gt "$WORK/ds/groundtruth.csv" --out "$WORK/plots" --force \
  >/dev/null || fail "--force"
status=0
/usr/bin/python3 "$PLOT" "$WORK/run" --gt "$WORK/ds/groundtruth.csv" --out "$WORK/ds/plots" \
  >/dev/null 2>"$WORK/inside.err" || status=$?
[ "$status" -eq 1 ] && grep -q "inside the dataset" "$WORK/inside.err" || fail "wrote into the dataset"
# Without numpy and matplotlib on its path (-S: no site packages): a clear message.
status=0
/usr/bin/python3 -S "$PLOT" "$WORK/run" --gt x >/dev/null 2>"$WORK/nomod.err" || status=$?
[ "$status" -eq 1 ] && grep -q "has no module" "$WORK/nomod.err" && ! grep -q Traceback "$WORK/nomod.err" ||
  { cat "$WORK/nomod.err"; fail "no clear message without matplotlib"; }
echo "PASS"
