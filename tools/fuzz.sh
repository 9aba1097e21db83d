#!/usr/bin/env bash
# Coverage-guided fuzzing with libFuzzer: installs clang (tools/setup.sh --fuzz), builds the
# host-fuzz preset and runs each fuzz target of tests/fuzz (or those named) from its seed corpus,
# for SECONDS (60 unless --runs is given) or RUNS inputs, whichever ends first. The corpus each run
# grows is kept in build/host-fuzz/corpus/NAME and is the next run's start; an input that fails is
# left in build/host-fuzz/crashes/NAME/ and named at the end. Each run's inputs, time and outcome
# are printed at the end and appended to build/host-fuzz/fuzz-runs.log, whose totals per target
# follow. ctest runs the same targets without libFuzzer over the seed corpus (tests/fuzz).
#   tools/fuzz.sh [--seconds N] [--runs N] [--no-build] [NAME...]
#     NAME: ekf, firmware_config, log_reader, ...   --no-build: the targets as last built
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=
runs=
build=1
names=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds=${2:?--seconds needs a number}; shift 2 ;;
    --runs) runs=${2:?--runs needs a number}; shift 2 ;;
    --no-build) build=0; shift ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    -*) echo "fuzz: unknown option $1" >&2; exit 2 ;;
    *) names+=("$1"); shift ;;
  esac
done
case "$seconds" in
  *[!0-9]*) echo "fuzz: --seconds wants a whole number of seconds, not '$seconds'" >&2; exit 2 ;;
esac
case "$runs" in
  *[!0-9]*) echo "fuzz: --runs wants a whole number of inputs, not '$runs'" >&2; exit 2 ;;
esac
if [ -z "$seconds" ] && [ -z "$runs" ]; then
  seconds=60
fi
if [ ${#names[@]} -eq 0 ]; then
  for f in "$root"/tests/fuzz/fuzz_*.cpp; do
    n=$(basename "$f" .cpp)
    names+=("${n#fuzz_}")
  done
fi
for n in "${names[@]}"; do
  if [ ! -f "$root/tests/fuzz/fuzz_$n.cpp" ]; then
    echo "fuzz: no target '$n' (tests/fuzz/fuzz_$n.cpp)" >&2
    exit 2
  fi
done

cd "$root"
if [ "$build" -eq 1 ]; then
  "$root/tools/setup.sh" --fuzz
  log=build/logs/host-fuzz-build.log
  mkdir -p build/logs
  echo "=== host-fuzz: configure and build (log: $log)"
  if ! { cmake --preset host-fuzz && cmake --build --preset host-fuzz -j "$(nproc)"; } >"$log" 2>&1; then
    grep -E -A5 'error|Error' "$log" | head -n 40
    echo "fuzz: the host-fuzz build failed (log: $log)" >&2
    exit 1
  fi
fi
for n in "${names[@]}"; do
  if [ ! -x "build/host-fuzz/bin/fuzz_$n" ]; then
    echo "fuzz: build/host-fuzz/bin/fuzz_$n not built (run without --no-build)" >&2
    exit 2
  fi
done

limits=()
what=
if [ -n "$seconds" ]; then
  limits+=(-max_total_time="$seconds")
  what="${seconds} s"
fi
if [ -n "$runs" ]; then
  limits+=(-runs="$runs")
  what="${what:+$what or }$runs inputs"
fi
runs_log=build/host-fuzz/fuzz-runs.log
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
if ! git diff --quiet HEAD 2>/dev/null; then
  commit="$commit+changes"
fi
failed=()
summary=()
for n in "${names[@]}"; do
  work=build/host-fuzz/corpus/$n
  crashes=build/host-fuzz/crashes/$n
  mkdir -p "$work" "$crashes"
  echo "=== fuzz_$n: $what (log: $work.log)"
  rc=0
  start=$(date +%s)
  # Only what this run leaves in $crashes is its failure: an earlier run's input stays there
  # until someone removes it.
  marker="$work.started"
  touch "$marker"
  build/host-fuzz/bin/fuzz_"$n" "${limits[@]}" -print_final_stats=1 \
    -artifact_prefix="$crashes/" "$work" "tests/fuzz/corpus/$n" >"$work.log" 2>&1 || rc=$?
  new_crashes=$(find "$crashes" -type f -newer "$marker" | sort)
  wall=$(($(date +%s) - start))
  grep -E '^(#[0-9]+[[:space:]]+(INITED|DONE)|==[0-9]+==ERROR|SUMMARY|stat::(number_of_executed_units|new_units_added))|fuzz_' \
    "$work.log" | tail -n 8 || true
  # libFuzzer's final count, else its last progress line's.
  inputs=$(sed -n 's/^stat::number_of_executed_units: *\([0-9]*\).*/\1/p' "$work.log" | tail -n 1)
  if [ -z "$inputs" ]; then
    inputs=$(sed -n 's/^#\([0-9][0-9]*\)[[:space:]].*/\1/p' "$work.log" | tail -n 1)
  fi
  inputs=${inputs:-0}
  outcome=ok
  if [ -z "$new_crashes" ] && [ "$rc" -ne 0 ] && grep -q 'libFuzzer: run interrupted' "$work.log"; then
    outcome=interrupted  # stopped (Ctrl-C, SIGTERM): its inputs ran without a failure
    rc=0
  fi
  if [ "$rc" -ne 0 ] || [ -n "$new_crashes" ]; then
    outcome="failed(exit $rc)"
    failed+=("$n (exit $rc, log $work.log): $(head -n 3 <<<"$new_crashes" | tr '\n' ' ')")
  fi
  rate=$((inputs / (wall > 0 ? wall : 1)))
  printf '%s fuzz_%s inputs=%s seconds=%s per_second=%s outcome=%s commit=%s\n' \
    "$(date -u +%Y-%m-%dT%H:%M:%SZ)" "$n" "$inputs" "$wall" "$rate" "$outcome" "$commit" >>"$runs_log"
  summary+=("$(printf 'fuzz_%-16s %12s inputs in %6s s (%s/s): %s' "$n" "$inputs" "$wall" "$rate" "$outcome")")
done
echo "=== this run"
printf '  %s\n' "${summary[@]}"
echo "=== all runs logged in $runs_log (inputs, runs that failed)"
for n in "${names[@]}"; do
  awk -v t="fuzz_$n" '$2 == t { sub("inputs=", "", $3); total += $3; if ($6 ~ /^outcome=failed/) bad++ }
    END { printf "  %-21s %12d inputs, %d failed run(s)\n", t, total, bad }' "$runs_log"
done
if [ ${#failed[@]} -ne 0 ]; then
  echo "fuzz: failing inputs (run the target on one to reproduce):"
  printf '  %s\n' "${failed[@]}"
  exit 1
fi
echo "fuzz: ${#names[@]} target(s), $what each, no failing input"
