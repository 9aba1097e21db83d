#!/usr/bin/python3
"""tools/eval/error_timeline.py on a short default-room run: its rows, its NEES and its path
length ratio (SLAM, dead reckoning and truth), which must scale exactly with a trajectory scaled
about its first pose; bad input names the file at fault.
Arguments: EMULATOR (may be empty) BIN_DIR WORK_DIR."""

import os
import re
import shutil
import subprocess
import sys

import numpy as np
import replay_checks

HERE = os.path.dirname(os.path.abspath(__file__))
TOOL = os.path.join(HERE, "..", "..", "tools", "eval", "error_timeline.py")

emulator, bin_dir, work = replay_checks.arguments()
check = replay_checks.Checks()
failures = check.failures


def program(name, *args):
    cmd = [*emulator.split(), os.path.join(bin_dir, name), *args]
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, check=False)
    if p.returncode != 0:
        print(f"$ {' '.join(cmd)}\n{p.stdout}{p.stderr}", file=sys.stderr)
        sys.exit(1)


def timeline(dataset, run, *args):
    return subprocess.run([sys.executable, TOOL, dataset, run, *args], stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True, check=False)


RATIO = re.compile(r"^path length SLAM/true: ([0-9.]+) \(SLAM ([0-9.]+) m, truth ([0-9.]+) m, "
                   r"dead reckoning/true ([0-9.]+)\)$", re.M)

ds = os.path.join(work, "dataset")
run = os.path.join(work, "run")
program("cleanslam-sim", "default-room", ds, "--seed", "3", "--set", "duration_s=30")
program("cleanslam-replay", ds, "--out", run)

p = timeline(ds, run, "--every", "5")
check(p.returncode == 0, f"exit status {p.returncode}: {p.stderr}")
rows = [ln for ln in p.stdout.splitlines() if ln.startswith("t ")]
check(len(rows) >= 5, f"a row every 5 s of a 30 s run: {len(rows)} rows")
check(all("path SLAM/true" in r for r in rows), "every row has its path length ratio")
check(re.search(r"^mean \(x, y, yaw\) NEES per dof: [0-9.e+-]+$", p.stdout, re.M) is not None,
      "mean NEES line")
m = RATIO.search(p.stdout)
check(m is not None, f"path length line: {p.stdout[-300:]}")
base = float(m.group(1)) if m else 0.0
# The default room's odometry scale error is 1 %: SLAM and dead reckoning keep the scale there.
check(0.95 < base < 1.05, f"default-room SLAM path length ratio {base}")
check(m is not None and 0.95 < float(m.group(4)) < 1.05, "default-room dead reckoning ratio")

# The same run scaled by 0.8 about its first pose: the ratio follows exactly, the truth's length
# and the dead reckoner's ratio do not change.
scaled = os.path.join(work, "scaled")
shutil.copytree(run, scaled)
tum = np.loadtxt(os.path.join(run, "trajectory.tum"), ndmin=2)
tum[:, 1:4] = tum[0, 1:4] + 0.8 * (tum[:, 1:4] - tum[0, 1:4])
np.savetxt(os.path.join(scaled, "trajectory.tum"), tum, fmt="%.9f")
p = timeline(ds, scaled)
m2 = RATIO.search(p.stdout)
check(m is not None and m2 is not None and
      abs(float(m2.group(2)) - 0.8 * float(m.group(2))) < 1e-4 and
      m2.group(3) == m.group(3) and m2.group(4) == m.group(4),
      f"scaled by 0.8: {m2.group(0) if m2 else p.stdout[-300:]} against "
      f"{m.group(0) if m else '-'}")


# Bad input: each file replaced in turn (the others good), exit status 1 with the file named.
def bad_input(name, text, mode, expected):
    bad = os.path.join(scaled, name)
    with open(bad, mode, encoding="utf-8") as f:
        f.write(text)
    p = timeline(ds, scaled)
    check(p.returncode == 1 and expected in p.stderr,
          f"{name} with {text.strip()!r}: exit {p.returncode}, {p.stderr.strip()}")
    os.remove(bad)
    if os.path.exists(os.path.join(run, name)):
        shutil.copy(os.path.join(run, name), bad)


bad_input("trajectory.tum.cov", "1 2 3\n", "a", "trajectory.tum.cov")
bad_input("dead_reckoning.tum", "1.0 x 0 0 0 0 0 1\n", "w", "dead_reckoning.tum")
bad_input("dead_reckoning.tum", "1.0 0 0\n", "w", "dead_reckoning.tum: 3 columns")

if failures:
    print(f"{len(failures)} check(s) failed", file=sys.stderr)
    sys.exit(1)
print("error_timeline: all checks passed")
