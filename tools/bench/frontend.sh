#!/usr/bin/env bash
# Front end against OpenCV: quality tables, times (median CPU time of repetitions, same run),
# the ratio of our time to OpenCV's, and callgrind instruction counts per frame.
#   tools/bench/frontend.sh [--no-build] [--quick]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${here}/build/host-release"
bench="${build}/bin/bench_frontend"
reps=7
min_time=0.5
for arg in "$@"; do
  case "${arg}" in
    --no-build) no_build=1 ;;
    --quick) reps=3; min_time=0.2 ;;
    *) echo "frontend.sh: unknown argument '${arg}'" >&2; exit 2 ;;
  esac
done
if [[ -z "${no_build:-}" ]]; then
  cmake --preset host-release >/dev/null
  cmake --build --preset host-release --target bench_frontend -j2 >/dev/null
fi
out="$(mktemp -d)"
trap 'rm -rf "${out}"' EXIT

"${bench}" --quality
"${bench}" --benchmark_repetitions="${reps}" --benchmark_min_time="${min_time}" \
  --benchmark_report_aggregates_only=true --benchmark_out="${out}/times.json" \
  --benchmark_out_format=json >/dev/null 2>&1 || { echo "bench_frontend failed" >&2; exit 1; }

python3 - "${out}/times.json" <<'PY'
import json, sys
data = json.load(open(sys.argv[1]))
med = {}
for b in data["benchmarks"]:
    if b.get("aggregate_name") == "median":
        med[b["run_name"]] = b["cpu_time"]  # microseconds (Unit set per benchmark)
print("# Time per frame, median CPU time of %d repetitions (us); ratio = ours / opencv" %
      data["benchmarks"][0].get("repetitions", 0))
print("%-28s %10s %10s %8s" % ("job/case", "ours", "opencv", "ratio"))
for name in sorted(k for k in med if k.startswith("ours/")):
    peer = "opencv/" + name[len("ours/"):]
    if peer in med:
        print("%-28s %10.1f %10.1f %8.2f" % (name[len("ours/"):], med[name], med[peer],
                                              med[name] / med[peer]))
ctx = data.get("context", {})
print("# host: %s, %s CPUs at %s MHz, load %s" % (ctx.get("host_name"), ctx.get("num_cpus"),
      ctx.get("mhz_per_cpu"), ctx.get("load_avg")))
PY

echo
echo "# Callgrind: instructions per frame (case shift_4px, 20 instrumented frames)"
for job in ours opencv ours-detect opencv-detect; do
  ir=$(valgrind --tool=callgrind --instr-atstart=no --callgrind-out-file="${out}/cg.${job}" \
       "${bench}" --callgrind="${job}" 2>&1 | sed -n 's/.*Collected : \([0-9]*\).*/\1/p')
  printf "%-14s %12d\n" "${job}" $((ir / 20))
done
