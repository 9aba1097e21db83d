# cleanslam-calibrate on logs the firmware recorded (cleanslam --record), as a robot maker copies
# them from the robot: the same figures as the folder recorded from, the camera and the mount from
# the frames' images (thinned with --every), a later file of a rotated recording warned, refusals
# naming the file and the fix.
. "$(dirname "$0")/common.sh"
CAL="$BIN/cleanslam-calibrate"
record() {  # record DATASET LOG [--set k=v ...]
  dataset=$1 log=$2
  shift 2
  run "$BIN/cleanslam" --dataset "$dataset" --record "$log" "$@" >/dev/null 2>&1 ||
    fail "cleanslam --dataset $dataset --record $log"
}
run "$BIN/cleanslam-sim" calibration-wheels "$WORK/drive" >/dev/null 2>&1 || fail "cleanslam-sim drive"
record "$WORK/drive" "$WORK/drive.log"
run "$CAL" wheels "$WORK/drive" --straight 3 >"$WORK/folder.yaml" 2>/dev/null || fail "wheels folder"
run "$CAL" wheels "$WORK/drive.log" --straight 3 >"$WORK/log.yaml" 2>"$WORK/wheels.err" ||
  { cat "$WORK/wheels.err" >&2; fail "wheels log"; }
grep -v '^#' "$WORK/folder.yaml" >"$WORK/folder.keys"
grep -v '^#' "$WORK/log.yaml" >"$WORK/log.keys"
cmp -s "$WORK/folder.keys" "$WORK/log.keys" || fail "the log's keys differ from the folder's"
grep -q "gyro and .* encoder samples" "$WORK/wheels.err" || fail "no sample counts"
# The drive's camera gives features only: the camera refuses, saying how to record images.
expect 1 "$WORK/features.err" "drive.log: none of its" \
  "$CAL" camera "$WORK/drive.log" --board 9x6 --square 0.03
grep -qF "recorder.frame_every 1" "$WORK/features.err" || fail "the refusal does not name frame_every"
# The gyro from a log: messages name the log's records.
expect 1 "$WORK/moving.err" "drive.log (its encoder records): encoder record" \
  "$CAL" gyro "$WORK/drive.log"
# The camera from a log of the rendered board; --every thins; a rotated recording warned.
run "$BIN/cleanslam-sim" calibration-camera "$WORK/board" >/dev/null 2>&1 || fail "cleanslam-sim board"
record "$WORK/board" "$WORK/board.log"
run "$CAL" camera "$WORK/board.log" --board 9x6 --square 0.03 >"$WORK/camera.yaml" \
  2>"$WORK/camera.err" || { cat "$WORK/camera.err" >&2; fail "camera log"; }
grep -q "20 of its 20 frames with an image used" "$WORK/camera.err" || fail "not all 20 frames used"
grep -q "^    fx: 26[45]\." "$WORK/camera.yaml" || fail "fx not about 265"
expect 1 "$WORK/every.err" "5 of its 20 frames with an image used (--every 4" \
  "$CAL" camera "$WORK/board.log" --board 9x6 --square 0.03 --every 4
grep -q "at least 8 views" "$WORK/every.err" || fail "5 views not refused as too few"
expect 1 "$WORK/everybad.err" "--every: expected a positive whole number" \
  "$CAL" camera "$WORK/board.log" --board 9x6 --square 0.03 --every 0
record "$WORK/board" "$WORK/rotated.log" --set recorder.max_file_mb=1
run "$CAL" camera "$WORK/rotated.log" --board 9x6 --square 0.03 --min-views 2 >/dev/null \
  2>"$WORK/rotated.err" || true
grep -qF "rotated.log is file 1 of a rotated recording" "$WORK/rotated.err" ||
  { cat "$WORK/rotated.err" >&2; fail "no rotation warning"; }
grep -qF "cat $WORK/rotated.log.1 $WORK/rotated.log > joined.log" "$WORK/rotated.err" ||
  fail "no join"
# The mount from a log of the board on the floor, through the recording's intrinsics.
run "$BIN/cleanslam-sim" calibration-mount "$WORK/floor" >/dev/null 2>&1 || fail "cleanslam-sim floor"
record "$WORK/floor" "$WORK/floor.log"
run "$CAL" mount "$WORK/floor.log" --board 9x6 --square 0.03 --at 0.475,-0.02 --yaw 90 \
  --intrinsics "$WORK/floor/sensors.yaml" --form sensors >"$WORK/mount.yaml" 2>"$WORK/mount.err" ||
  { cat "$WORK/mount.err" >&2; fail "mount log"; }
grep -q "the camera is 0.25[0-9] m up" "$WORK/mount.yaml" || fail "the camera's height is not 0.25 m"
# A file that is not a log.
echo "not a log" >"$WORK/notes.txt"
expect 1 "$WORK/notalog.err" "notes.txt: not a cleanslam log" \
  "$CAL" wheels "$WORK/notes.txt" --straight 3
echo "PASS"
