#!/usr/bin/env bash
# The main job on a PC: a simulated robot cleans a room, the firmware's own pipeline estimates its
# path from the recorded sensors, and the evaluation says how far off SLAM and dead reckoning were.
#   tools/demo.sh [SCENARIO] [images|features]
# default: default-room, rendered images through the whole front end (features: the simulator's
# projected points with track ids, much faster); results and plots in out/demo/
set -euo pipefail
cd "$(dirname "$0")/.."
scenario=${1:-default-room}
mode=${2:-images}
case $mode in images | features) ;; *) echo "demo: mode must be images or features, not '$mode'" >&2; exit 2 ;; esac
out=out/demo
bin=build/host-release/bin

step() { printf '\n== %s\n' "$*"; }

step "setup"
tools/setup.sh --host-only

step "build (host-release: the three programs the demo runs)"
cmake --preset host-release >/dev/null
if ! cmake --build --preset host-release -j "$(nproc)" --target cleanslam-sim cleanslam-replay cleanslam-eval \
  >build/demo-build.log 2>&1; then
  grep -E -A5 'error|FAILED' build/demo-build.log | head -n 40
  echo "demo: build failed (log: build/demo-build.log)" >&2
  exit 1
fi
for exe in cleanslam-sim cleanslam-replay cleanslam-eval; do
  [ -x "$bin/$exe" ] || { echo "demo: $bin/$exe was not built" >&2; exit 1; }
done

rm -rf "$out"
mkdir -p "$out"
step "simulate: $scenario ($mode) -> $out/dataset"
"$bin/cleanslam-sim" "$scenario" "$out/dataset" --set "camera.mode=$mode"

step "replay the dataset through the firmware pipeline -> $out/run"
"$bin/cleanslam-replay" "$out/dataset" --out "$out/run"

step "evaluate against ground truth"
"$bin/cleanslam-eval" --gt "$out/dataset/groundtruth.csv" --est "$out/run/trajectory.tum" --json >"$out/slam.json"
"$bin/cleanslam-eval" --gt "$out/dataset/groundtruth.csv" --est "$out/run/dead_reckoning.tum" --json >"$out/dead_reckoning.json"
python3 - "$out/slam.json" "$out/dead_reckoning.json" <<'PY'
import json, sys
slam, dr = (json.load(open(p)) for p in sys.argv[1:3])
rows = [("ATE RMSE [m]", "ate_rmse_m"), ("final position error [m]", "final_error_m"),
        ("orientation RMSE [deg]", "orientation_rmse_deg"),
        ("RPE per metre [m/m]", "rpe_translation_per_m"), ("RPE per metre [deg/m]", "rpe_rotation_deg_per_m")]
print(f"{'':28s}{'SLAM':>12s}{'dead reckoning':>18s}")
for label, key in rows:
    if key in slam and key in dr:
        print(f"{label:28s}{slam[key]:12.4f}{dr[key]:18.4f}")
if "path_length_m" in slam:
    print(f"{'path length [m]':28s}{slam['path_length_m']:12.2f}")
if "nees_mean" in slam:
    print(f"{'position NEES (3 if consistent)':28s}{slam['nees_mean']:12.1f}")
if slam.get("ate_rmse_m") and dr.get("ate_rmse_m"):
    print(f"SLAM ATE is {dr['ate_rmse_m'] / slam['ate_rmse_m']:.1f}x smaller than dead reckoning's")
PY

step "plots -> $out/"
/usr/bin/python3 tools/plot/plot_run.py "$out/run" --gt "$out/dataset/groundtruth.csv" --out "$out"
