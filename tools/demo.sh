#!/usr/bin/env bash
# The main job on a PC: a simulated robot cleans a room, the firmware's own pipeline estimates its
# path from the recorded sensors, and the evaluation says how far off SLAM and dead reckoning were.
set -euo pipefail
cd "$(dirname "$0")/.."

usage() {
  cat <<'USAGE'
usage: tools/demo.sh [--out DIR] [--force] [--seed N] [SCENARIO] [images|features]
  SCENARIO   a built-in scenario (sim_hal/scenarios/NAME.yaml) or a scenario YAML file;
             default default-room
  images     rendered camera images through the whole vision front end (default)
  features   the simulator's projected points with track ids: much faster
  --out DIR  where the dataset, the run, the figures and the plots go (default out/demo);
             refused when it holds anything, unless --force
  --force    replace the outputs of an earlier demo in DIR (only those: dataset/, run/,
             *.json, *.png, *.log of the demo)
  --seed N   the simulation's seed (default: the scenario's)
Installs the host packages it needs (tools/setup.sh --host-only), builds the programs of the
README's tools table into build/host-release/bin, and shows progress on stderr also when the
output is not a terminal.
USAGE
}

die() {
  echo "demo: $*" >&2
  exit 2
}

out=out/demo
force=0
seed=
positional=()
while [ $# -gt 0 ]; do
  case $1 in
    -h | --help) usage; exit 0 ;;
    --out) [ $# -ge 2 ] && [ -n "$2" ] || die "--out needs a folder"; out=$2; shift 2 ;;
    --out=*) out=${1#--out=}; [ -n "$out" ] || die "--out needs a folder"; shift ;;
    --force) force=1; shift ;;
    --seed) [ $# -ge 2 ] || die "--seed needs a value"; seed=$2; shift 2 ;;
    --seed=*) seed=${1#--seed=}; shift ;;
    -*) usage >&2; die "unknown option '$1'" ;;
    *) positional+=("$1"); shift ;;
  esac
done
[ ${#positional[@]} -le 2 ] || { usage >&2; die "too many arguments: ${positional[*]}"; }
scenario=${positional[0]:-default-room}
mode=${positional[1]:-images}

# Every argument is checked before anything is built or deleted.
case $mode in images | features) ;; *) die "mode must be images or features, not '$mode'" ;; esac
if [ ! -f "sim_hal/scenarios/$scenario.yaml" ] && [ ! -f "$scenario" ]; then
  names=$(cd sim_hal/scenarios && ls -- *.yaml | sed 's/\.yaml$//' | tr '\n' ' ')
  die "'$scenario' is neither a built-in scenario (${names% }) nor a scenario file"
fi
if [ -n "$seed" ] && ! [[ $seed =~ ^[0-9]+$ ]]; then
  die "--seed takes a non-negative integer, not '$seed'"
fi
demo_entries=(dataset run slam.json dead_reckoning.json trajectory_xy.png position_error.png
  simulate.log replay.log)
if [ -e "$out" ] && [ ! -d "$out" ]; then
  die "$out exists and is not a folder"
fi
if [ -d "$out" ] && [ -n "$(ls -A -- "$out")" ]; then
  if [ "$force" -eq 0 ]; then
    die "$out is not empty (an earlier demo?): choose another folder with --out DIR, or add --force to replace the demo's outputs there"
  fi
fi
bin=build/host-release/bin
programs=(cleanslam cleanslam-sim cleanslam-replay cleanslam-eval cleanslam-paper cleanslam-track)

step() { printf '\n== %s\n' "$*"; }

step "setup"
tools/setup.sh --host-only

step "build (host-release: the six programs of the README's tools table)"
# The first build compiles the project's libraries and the six programs (README.md says how long
# it takes); later ones only what changed. Ninja's progress lines are filtered to one every 10 %.
start=$(date +%s)
mkdir -p build
cmake --preset host-release >build/demo-configure.log 2>&1 || {
  tail -n 30 build/demo-configure.log >&2
  echo "demo: configuring failed (log: build/demo-configure.log)" >&2
  exit 1
}
set +e
cmake --build --preset host-release -j "$(nproc)" --target "${programs[@]}" 2>&1 |
  tee build/demo-build.log |
  sed -un 's/^\[\([0-9]*\)\/\([0-9]*\)\].*/\1 \2/p' | {
  shown=-1
  while read -r done total; do
    pct=$((100 * done / total / 10 * 10))
    if [ "$pct" -ne "$shown" ]; then
      shown=$pct
      printf 'demo: build %3d %% (%d of %d steps, %d s)\n' "$pct" "$done" "$total" $(($(date +%s) - start)) >&2
    fi
  done
}
status=${PIPESTATUS[0]}
set -e
if [ "$status" -ne 0 ]; then
  grep -E -A5 'error|FAILED' build/demo-build.log | head -n 40 >&2
  echo "demo: build failed (log: build/demo-build.log)" >&2
  exit 1
fi
for exe in "${programs[@]}"; do
  [ -x "$bin/$exe" ] || { echo "demo: $bin/$exe was not built" >&2; exit 1; }
done
echo "demo: build took $(($(date +%s) - start)) s; the programs are in $bin/: ${programs[*]}"

if [ "$force" -eq 1 ] && [ -d "$out" ]; then
  for e in "${demo_entries[@]}"; do rm -rf -- "${out:?}/$e"; done
fi
mkdir -p "$out"
seed_args=()
[ -z "$seed" ] || seed_args=(--seed "$seed")
step "simulate: $scenario ($mode) -> $out/dataset"
"$bin/cleanslam-sim" "$scenario" "$out/dataset" --set "camera.mode=$mode" "${seed_args[@]}" 2>&1 |
  tee "$out/simulate.log"
seed_used=$(sed -n 's/^cleanslam-sim: .* seed \([0-9]*\) -> .*/\1/p' "$out/simulate.log")
scenario_name=$(sed -n 's/^cleanslam-sim: \(.*\) seed [0-9]* -> .*/\1/p' "$out/simulate.log")

step "replay the dataset through the firmware pipeline -> $out/run"
"$bin/cleanslam-replay" "$out/dataset" --out "$out/run" 2>&1 | tee "$out/replay.log"

step "evaluate against ground truth"
"$bin/cleanslam-eval" --gt "$out/dataset/groundtruth.csv" --est "$out/run/trajectory.tum" --json >"$out/slam.json"
"$bin/cleanslam-eval" --gt "$out/dataset/groundtruth.csv" --est "$out/run/dead_reckoning_published.tum" \
  --json >"$out/dead_reckoning.json"
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
print(f"{'poses evaluated':28s}{slam['poses_evaluated']:12d}{dr['poses_evaluated']:18d}")
if "path_length_m" in slam:
    print(f"{'path length [m]':28s}{slam['path_length_m']:12.2f}")
print("SLAM is evaluated at the processed frames; dead reckoning (wheels and gyro alone) at every")
print("published pose (loop.publish_rate_hz): the same time stamps in images and features mode.")
if slam.get("nees_ratio") is not None:
    print(f"position NEES: {slam['nees_mean']:.2f}, {slam['nees_ratio']:.2f} x its consistent value 3 "
          f"(95 % band {slam['nees_ratio_low']:.2f}-{slam['nees_ratio_high']:.2f}): "
          f"{slam['nees_verdict']}")
    words = {"overconfident": "the errors are larger than the covariance claims",
             "conservative": "the covariance claims larger errors than there are",
             "consistent": "the errors match the covariance"}
    print(f"  ({words.get(slam['nees_verdict'], '')}; "
          f"{100 * slam['nees_fraction_in_95']:.0f} % of poses inside their own 95 % bounds)")
if slam.get("ate_rmse_m") and dr.get("ate_rmse_m"):
    print(f"SLAM ATE is {dr['ate_rmse_m'] / slam['ate_rmse_m']:.1f}x smaller than dead reckoning's")
PY

step "plots -> $out/"
/usr/bin/python3 tools/eval/plot_run.py "$out/run" --gt "$out/dataset/groundtruth.csv" --out "$out" \
  --title "${scenario_name:-$scenario}, seed ${seed_used:-?}, $mode mode"
echo "demo: done; in $out: dataset/ (the simulated sensors), run/ (the estimate), slam.json and"
echo "dead_reckoning.json (cleanslam-eval), trajectory_xy.png and position_error.png (the plots)"
