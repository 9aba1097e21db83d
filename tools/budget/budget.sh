#!/bin/sh
# Loop budget on the host, callgrind instruction counts standing in for a Cortex-A53 at ~1 GHz
# (1 instruction ~ 1 ns): the distribution of the instructions of single loop iterations
# (Loop::iterate, collected only inside it, one dump per call), the ticks that processed a frame,
# and the peak resident memory of a native run. The dataset reader's own work (CSV rows, PNG
# decoding: host-side stand-ins for the drivers) is left out: the inclusive cost of the calls to
# DatasetSource::read is subtracted from each iteration.
#
# usage: tools/budget/budget.sh CLEANSLAM DATASET [WORKDIR]
#   CLEANSLAM  the cleanslam executable (a release build: cmake --preset host-release)
#   DATASET    a dataset folder (e.g. cleanslam-sim default-room /tmp/ds --set duration_s=60)
#   WORKDIR    where the callgrind dumps go (default: a temporary folder, removed); when given,
#              the longest iteration's dump is named for callgrind_annotate (its parts' costs)
# Budgets: longest tick <= 5 M instructions, a whole frame <= 20 M.
set -eu
if [ $# -lt 2 ]; then
  sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
fi
CLEANSLAM=$1
DATASET=$2
WORK=${3:-}
KEEP=1
if [ -z "$WORK" ]; then
  WORK=$(mktemp -d)
  KEEP=0
fi
mkdir -p "$WORK"

echo "budget: native run for the peak resident memory" >&2
python3 - "$CLEANSLAM" "$DATASET" <<'PY'
import resource, subprocess, sys, time
t = time.monotonic()
r = subprocess.run([sys.argv[1], "--dataset", sys.argv[2]], stdout=subprocess.DEVNULL,
                   stderr=subprocess.PIPE, text=True)
wall = time.monotonic() - t
if r.returncode != 0:
    sys.stderr.write(r.stderr)
    sys.exit("budget: cleanslam failed")
ru = resource.getrusage(resource.RUSAGE_CHILDREN)
print(f"native wall time      {wall:8.2f} s")
print(f"peak resident memory  {ru.ru_maxrss / 1024:8.1f} MiB")
PY

echo "budget: callgrind run (one dump per Loop::iterate; slow)" >&2
valgrind --tool=callgrind --callgrind-out-file="$WORK/callgrind.out.%p" --collect-atstart=no \
  --toggle-collect='cleanslam::firmware::Loop::iterate(long)' \
  --dump-after='cleanslam::firmware::Loop::iterate(long)' \
  --compress-strings=no --compress-pos=no --dump-instr=no --dump-line=no \
  "$CLEANSLAM" --dataset "$DATASET" >/dev/null 2>"$WORK/valgrind.log" || {
  cat "$WORK/valgrind.log" >&2
  exit 1
}

python3 - "$WORK" "$KEEP" <<'PY'
import glob, os, re, sys
work = sys.argv[1]
keep = sys.argv[2] == "1"
ticks = []        # instructions of each iteration
frame_ticks = []  # of the iterations that ran a frame step
frames = []       # a frame: consecutive iterations with frame steps (image frames take several)
parts = []
for path in glob.glob(os.path.join(work, "callgrind.out.*")):
    m = re.search(r"callgrind\.out\.\d+\.(\d+)$", path)
    if m:  # the final dump (program end, outside iterate) has no part number
        parts.append((int(m.group(1)), path))
in_frame = False
longest = (-1, "")
for _, path in sorted(parts):
    total = None
    frame = False
    reader = 0     # inclusive cost of the dataset reader's calls
    state = 0      # 1: after a cfn= of the reader, 2: after its calls= line
    with open(path, errors="replace") as f:
        for line in f:
            if line.startswith("totals:") or line.startswith("summary:"):
                total = int(line.split()[1])
            elif line.startswith(("fn=", "cfn=")) and "step_frame" in line:
                frame = True
            if line.startswith("cfn="):
                state = 1 if "DatasetSource::read" in line else 0
            elif state == 1 and line.startswith("calls="):
                state = 2
            elif state == 2:
                reader += int(line.split()[1])
                state = 0
    if total is None:
        continue
    total -= reader
    ticks.append(total)
    if total > longest[0]:
        longest = (total, path)
    if frame:
        frame_ticks.append(total)
        if in_frame:
            frames[-1] += total
        else:
            frames.append(total)
    in_frame = frame
if not ticks:
    sys.exit("budget: no iteration dumps found")
ticks.sort()
def pct(v, p):
    return v[min(len(v) - 1, int(p / 100.0 * len(v)))]
print(f"loop iterations       {len(ticks):8d}")
print("instructions per iteration (M):")
for name, p in (("min", 0), ("median", 50), ("p90", 90), ("p99", 99), ("p99.9", 99.9)):
    print(f"  {name:8s} {pct(ticks, p) / 1e6:10.3f}")
print(f"  {'max':8s} {ticks[-1] / 1e6:10.3f}   budget 5 M: {'OK' if ticks[-1] <= 5e6 else 'OVER'}")
if keep:
    print(f"  longest: callgrind_annotate --inclusive=yes {longest[1]}")
edges = [1e4, 3e4, 1e5, 3e5, 1e6, 3e6, 5e6, 1e7, 2e7, float('inf')]
lo = 0
print("histogram:")
for e in edges:
    n = sum(1 for t in ticks if lo <= t < e)
    label = f"< {e / 1e6:g} M" if e != float('inf') else ">= 20 M"
    print(f"  {label:10s} {n:8d}")
    lo = e
if frame_ticks:
    frame_ticks.sort()
    frames.sort()
    print(f"iterations with a frame step {len(frame_ticks):8d}: median "
          f"{pct(frame_ticks, 50) / 1e6:.3f} M, max {frame_ticks[-1] / 1e6:.3f} M")
    print(f"whole frames          {len(frames):8d}: median {pct(frames, 50) / 1e6:.3f} M, "
          f"max {frames[-1] / 1e6:.3f} M   budget 20 M per frame: "
          f"{'OK' if frames[-1] <= 2e7 else 'OVER'}")
PY
if [ "$KEEP" = 0 ]; then
  rm -rf "$WORK"
fi
