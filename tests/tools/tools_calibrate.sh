# cleanslam-calibrate as a user meets it: the simulator's calibration drive and standstill in,
# YAML out; an existing file replaced only with --force, never a file in the recording; a complete
# sensors.yaml from --base; refusals naming the file and the fix.
. "$(dirname "$0")/common.sh"
CAL="$BIN/cleanslam-calibrate"
run "$BIN/cleanslam-sim" calibration-wheels "$WORK/drive" >/dev/null 2>&1 || fail "cleanslam-sim drive"
run "$CAL" wheels "$WORK/drive" --straight 3 --out "$WORK/out/wheels.yaml" 2>"$WORK/wheels.err" ||
  { cat "$WORK/wheels.err" >&2; fail "wheels"; }
grep -q "^calibration:" "$WORK/out/wheels.yaml" || fail "no calibration section"
grep -q "^    wheel_base: 0.239" "$WORK/out/wheels.yaml" || fail "wheel base not about 0.2397"
grep -q "^# .*turns in place" "$WORK/out/wheels.yaml" || fail "no method comment"
expect 1 "$WORK/again.err" "wheels.yaml: exists; choose another name, or add --force to replace it" \
  "$CAL" wheels "$WORK/drive" --straight 3 --out "$WORK/out/wheels.yaml"
run "$CAL" wheels "$WORK/drive" --straight 3 --out "$WORK/out/wheels.yaml" --force 2>/dev/null ||
  fail "--force"
expect 1 "$WORK/inside.err" "lies inside the input" \
  "$CAL" wheels "$WORK/drive" --straight 3 --out "$WORK/drive/calibration.yaml" --force
# A complete sensors.yaml from the recording's: it reads back (cleanslam-calibrate reads it with
# the new folder's gyro.csv and encoders.csv below; no camera files are needed).
mkdir -p "$WORK/new"
run "$CAL" wheels "$WORK/drive" --straight 3 --base "$WORK/drive/sensors.yaml" \
  --out "$WORK/new/sensors.yaml" 2>/dev/null || fail "--base"
grep -q "^  wheel_base: 0.239" "$WORK/new/sensors.yaml" || fail "--base: wheel base not replaced"
cp "$WORK/drive/gyro.csv" "$WORK/drive/encoders.csv" "$WORK/new/"
run "$CAL" wheels "$WORK/new" --straight 3 >/dev/null 2>&1 || fail "the new sensors.yaml does not read"
expect 2 "$WORK/nolength.err" "--straight METRES" "$CAL" wheels "$WORK/drive"
expect 2 "$WORK/badform.err" "--form: expected calibration or sensors" \
  "$CAL" wheels "$WORK/drive" --straight 3 --form yaml
# The gyro: too short a standstill is refused, saying how long it is and what is needed.
run "$BIN/cleanslam-sim" calibration-gyro "$WORK/still" --set duration_s=40 >/dev/null 2>&1 ||
  fail "cleanslam-sim still"
expect 1 "$WORK/short.err" "$WORK/still/gyro.csv: the standstill lasts 40.0 s" "$CAL" gyro "$WORK/still"
grep -qF -- "--min-duration" "$WORK/short.err" || fail "the refusal does not name --min-duration"
run "$CAL" gyro "$WORK/still" --min-duration 30 --form sensors >"$WORK/gyro.yaml" 2>/dev/null ||
  fail "gyro --min-duration 30"
grep -q "^gyro:" "$WORK/gyro.yaml" || fail "--form sensors: no top-level gyro"
grep -q "^  noise_density: 0.000" "$WORK/gyro.yaml" || fail "no noise density"
expect 1 "$WORK/moving.err" "encoders.csv: line" "$CAL" gyro "$WORK/drive"
# The mount from the board on the floor, through the recording's intrinsics.
run "$BIN/cleanslam-sim" calibration-mount "$WORK/floor" >/dev/null 2>&1 || fail "cleanslam-sim floor"
run "$CAL" mount "$WORK/floor/cam0/data" --board 9x6 --square 0.03 --at 0.475,-0.02 --yaw 90 \
  --intrinsics "$WORK/floor/sensors.yaml" --form sensors >"$WORK/mount.yaml" 2>"$WORK/mount.err" ||
  { cat "$WORK/mount.err" >&2; fail "mount"; }
grep -q "^  T_body_cam:$" "$WORK/mount.yaml" || fail "no T_body_cam"
grep -q "the camera is 0.25[0-9] m up" "$WORK/mount.yaml" || fail "the camera's height is not 0.25 m"
expect 2 "$WORK/noat.err" "--at X,Y" "$CAL" mount "$WORK/floor/cam0/data" --board 9x6 --square 0.03
expect 2 "$WORK/unknown.err" "unknown command" "$CAL" allan "$WORK/still"
echo "PASS"
