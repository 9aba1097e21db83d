#!/usr/bin/env bash
# Coverage-guided fuzzing with libFuzzer: installs clang (tools/setup.sh --fuzz), builds the
# host-fuzz preset and runs each fuzz target of tests/fuzz (or those named) for SECONDS from its
# seed corpus. The corpus each run grows is kept in build/host-fuzz/corpus/NAME and is the next
# run's start; an input that fails is left in build/host-fuzz/crashes/NAME/ and named at the end.
# ctest runs the same targets without libFuzzer over the seed corpus (tests/fuzz/CMakeLists.txt).
#   tools/fuzz.sh [--seconds N] [NAME...]      NAME: ekf, firmware_config, log_reader, ...
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=60
names=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds=${2:?--seconds needs a number}; shift 2 ;;
    -h|--help) sed -n '2,7p' "$0"; exit 0 ;;
    -*) echo "fuzz: unknown option $1" >&2; exit 2 ;;
    *) names+=("$1"); shift ;;
  esac
done
case "$seconds" in
  ''|*[!0-9]*) echo "fuzz: --seconds wants a whole number of seconds, not '$seconds'" >&2; exit 2 ;;
esac
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

"$root/tools/setup.sh" --fuzz
cd "$root"
log=build/logs/host-fuzz-build.log
mkdir -p build/logs
echo "=== host-fuzz: configure and build (log: $log)"
if ! { cmake --preset host-fuzz && cmake --build --preset host-fuzz -j "$(nproc)"; } >"$log" 2>&1; then
  grep -E -A5 'error|Error' "$log" | head -n 40
  echo "fuzz: the host-fuzz build failed (log: $log)" >&2
  exit 1
fi

failed=()
for n in "${names[@]}"; do
  work=build/host-fuzz/corpus/$n
  crashes=build/host-fuzz/crashes/$n
  mkdir -p "$work" "$crashes"
  echo "=== fuzz_$n: ${seconds} s"
  rc=0
  build/host-fuzz/bin/fuzz_"$n" -max_total_time="$seconds" -print_final_stats=1 \
    -artifact_prefix="$crashes/" "$work" "tests/fuzz/corpus/$n" >"$work.log" 2>&1 || rc=$?
  grep -E '^(#[0-9]+ +(INITED|DONE)|==[0-9]+==ERROR|SUMMARY|stat::(number_of_executed_units|new_units_added))|fuzz_' \
    "$work.log" | tail -n 8 || true
  if [ "$rc" -ne 0 ] || compgen -G "$crashes/*" >/dev/null; then
    failed+=("$n (exit $rc, log $work.log): $(ls "$crashes" | head -n 3 | sed "s|^|$crashes/|" | tr '\n' ' ')")
  fi
done
if [ ${#failed[@]} -ne 0 ]; then
  echo "fuzz: failing inputs (run the target on one to reproduce):"
  printf '  %s\n' "${failed[@]}"
  exit 1
fi
echo "fuzz: ${#names[@]} target(s), ${seconds} s each, no failing input"
