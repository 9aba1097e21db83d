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
/usr/bin/python3 tools/eval/demo_summary.py "$out/slam.json" "$out/dead_reckoning.json"

step "plots -> $out/"
/usr/bin/python3 tools/eval/plot_run.py "$out/run" --gt "$out/dataset/groundtruth.csv" --out "$out" \
  --title "${scenario_name:-$scenario}, seed ${seed_used:-?}, $mode mode"
echo "demo: done; in $out: dataset/ (the simulated sensors), run/ (the estimate), slam.json and"
echo "dead_reckoning.json (cleanslam-eval), trajectory_xy.png and position_error.png (the plots)"
