#!/usr/bin/env bash
# Times the estimator's hot calls (Google Benchmark, host-release) and counts their instructions
# with callgrind. Usage: tools/bench/estimator.sh [--no-callgrind] [google benchmark flags...]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
cd "$root"
callgrind=1
if [[ "${1:-}" == "--no-callgrind" ]]; then
  callgrind=0
  shift
fi
cmake --preset host-release >/dev/null
cmake --build --preset host-release --target bench_estimator -- -j2 >/dev/null
bench="$root/build/host-release/bin/bench_estimator"
"$bench" "$@"

if [[ $callgrind -eq 0 ]]; then
  exit 0
fi
if ! command -v valgrind >/dev/null; then
  echo "estimator.sh: valgrind not found; skipping instruction counts" >&2
  exit 0
fi
calls=20
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
printf '\n%-12s %10s %16s\n' "call" "landmarks" "instructions"
count() {  # op, landmarks, function to collect
  local op=$1 n=$2 fn=$3
  valgrind --tool=callgrind --callgrind-out-file="$out/cg.$op.$n" --collect-atstart=no \
    --toggle-collect="$fn" "$bench" --count "$op" "$n" "$calls" >/dev/null 2>&1
  local total
  total=$(grep -E '^(summary|totals):' "$out/cg.$op.$n" | head -1 | awk '{print $2}')
  printf '%-12s %10d %16d\n' "$op" "$n" $((total / calls))
}
count predict 100 '*counted_predict*'
for n in 25 50 100 128; do
  count update "$n" '*counted_update*'
done
for n in 100 128; do
  count update_invariant "$n" '*counted_update*'
done
count initialize 25 '*counted_initialize*'
count initialize 100 '*counted_initialize*'
for op in merge merge_considered; do
  count "$op" 25 '*counted_merge*'
  count "$op" 100 '*counted_merge*'
done
