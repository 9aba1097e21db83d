# Every tool refuses a non-empty output folder or an existing file unless --force, never writes
# into its input dataset, creates the folders it needs, and --force leaves no stale output.
. "$(dirname "$0")/common.sh"
features_dataset "$WORK/ds"
images_dataset "$WORK/im"

# cleanslam-replay
run "$BIN/cleanslam-replay" "$WORK/ds" --out "$WORK/a/b/run" 2>"$WORK/first.err" ||
  { cat "$WORK/first.err" >&2; fail "replay into a new nested folder"; }
[ -s "$WORK/a/b/run/trajectory.tum" ] || fail "replay wrote no trajectory.tum"
cp "$WORK/a/b/run/trajectory.tum" "$WORK/trajectory.before"
echo stale >"$WORK/a/b/run/trajectory.tum"
echo mine >"$WORK/a/b/run/notes.txt"
expect 2 "$WORK/again.err" "folder is not empty" "$BIN/cleanslam-replay" "$WORK/ds" --out "$WORK/a/b/run"
[ "$(cat "$WORK/a/b/run/trajectory.tum")" = stale ] || fail "a refused replay touched the folder"
expect 2 "$WORK/inside.err" "lies inside the input" "$BIN/cleanslam-replay" "$WORK/ds" --out "$WORK/ds/run" --force
[ ! -e "$WORK/ds/run" ] || fail "replay created a folder inside the dataset"
expect 2 "$WORK/same.err" "lies inside the input" "$BIN/cleanslam-replay" "$WORK/ds" --out "$WORK/ds/" --force
run "$BIN/cleanslam-replay" "$WORK/ds" --out "$WORK/a/b/run" --force 2>"$WORK/force.err" ||
  { cat "$WORK/force.err" >&2; fail "replay --force"; }
cmp -s "$WORK/a/b/run/trajectory.tum" "$WORK/trajectory.before" || fail "--force did not replace the outputs"
[ "$(cat "$WORK/a/b/run/notes.txt")" = mine ] || fail "--force deleted a file that is not replay's"

# cleanslam-track: --out and --overlay
run "$BIN/cleanslam-track" "$WORK/im" --out "$WORK/t/x/features.csv" --overlay "$WORK/t/ov" \
  2>"$WORK/track.err" || { cat "$WORK/track.err" >&2; fail "track into new folders"; }
frames=$(ls "$WORK/t/ov" | grep -c '^[0-9]\{6\}\.png$') || true
[ "$frames" -gt 3 ] || fail "track wrote $frames overlay images"
expect 1 "$WORK/track_out.err" "exists" "$BIN/cleanslam-track" "$WORK/im" --out "$WORK/t/x/features.csv"
expect 1 "$WORK/track_ov.err" "folder is not empty" "$BIN/cleanslam-track" "$WORK/im" --out "$WORK/t/y.csv" --overlay "$WORK/t/ov"
[ ! -e "$WORK/t/y.csv" ] || fail "a refused track wrote its --out"
expect 1 "$WORK/track_in.err" "lies inside the input" "$BIN/cleanslam-track" "$WORK/im" --out "$WORK/im/features2.csv"
touch "$WORK/t/ov/009999.png"
run "$BIN/cleanslam-track" "$WORK/im" --out "$WORK/t/x/features.csv" --overlay "$WORK/t/ov" --force \
  --max-frames 2 2>"$WORK/track_force.err" || { cat "$WORK/track_force.err" >&2; fail "track --force"; }
left=$(ls "$WORK/t/ov" | grep -c '\.png$') || true
[ "$left" -eq 2 ] || fail "track --force left $left overlay images, expected the 2 new ones"

# cleanslam-paper --plot (the CSV beside it; the PNG needs matplotlib, so only the refusal)
touch "$WORK/fig10.png"
expect 1 "$WORK/paper.err" "exists" "$BIN/cleanslam-paper" fig10 --motion forward --plot "$WORK/fig10.png"
[ ! -e "$WORK/fig10.png.csv" ] || fail "a refused cleanslam-paper wrote its CSV"
echo "PASS"
