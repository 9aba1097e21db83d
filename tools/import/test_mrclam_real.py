#!/usr/bin/python3
"""tools/import/mrclam.py on robot 1 of the real MRCLAM dataset 6, both gyro choices: what it
keeps and drops, what it measures against Vicon, and that cleanslam-replay reads the result.
Skips (exit 77) when ../shared/data/mrclam is absent. Arguments: BIN_DIR WORK_DIR."""

import os
import re
import shutil
import subprocess
import sys

import numpy as np
import mrclam_data

HERE = os.path.dirname(os.path.abspath(__file__))

data = mrclam_data.dataset6()
if data is None:
    print("SKIP: ../shared/data/mrclam/MRCLAM_Dataset6 is absent")
    sys.exit(mrclam_data.SKIP)
bin_dir, work = sys.argv[1], sys.argv[2]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print(f"FAIL: {what}", file=sys.stderr)


def number(pattern, text):
    m = re.search(pattern, text)
    check(m is not None, f"'{pattern}' in the output")
    return float(m.group(1)) if m else float("nan")


for gyro in ("commanded", "mems"):
    out = os.path.join(work, gyro)
    p = subprocess.run([sys.executable, os.path.join(HERE, "mrclam.py"), data, "1", out,
                        "--gyro", gyro], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                       text=True, check=False)
    print(p.stderr, end="")
    check(p.returncode == 0, f"--gyro {gyro}: exit status {p.returncode}")
    # Robot 1 sees the other robots (407 of its 1942 sightings in the published files).
    check(number(r"(\d+) other robots", p.stderr) > 100, "other robots' sightings dropped")
    frames = number(r"(\d+) frames at least", p.stderr)
    check(500 < frames < 1000, f"{frames} frames")
    lag = number(r"commands lag the motion by ([0-9.]+) s", p.stderr)
    check(0.05 <= lag <= 0.3, f"commands lag {lag} s")
    turn = number(r"Vicon = ([0-9.]+) x the commanded turn", p.stderr)
    check(0.7 < turn < 1.0, f"turn scale {turn}")
    spread = number(r"spread ([0-9.]+) mrad", p.stderr)
    check(3.0 < spread < 30.0, f"bearing spread {spread} mrad")
    f = np.loadtxt(os.path.join(out, "features.csv"), delimiter=",", comments="#", ndmin=2)
    check(set(f[:, 1].astype(int)) <= set(range(6, 21)), "track ids are landmark subjects")
    check(np.all(np.diff(np.unique(f[:, 0])) >= 0.45e9 - 1), "frames at least 0.45 s apart")
    check(np.all((f[:, 2] >= -0.5) & (f[:, 2] <= 319.5)), "pixels inside the image")
    r = subprocess.run([os.path.join(bin_dir, "cleanslam-replay"), out, "--out",
                        os.path.join(work, f"run_{gyro}")], stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True, check=False)
    check(r.returncode == 0, f"cleanslam-replay --gyro {gyro}: {r.stderr[-400:]}")
    check("unknown key" not in r.stderr, f"sensors.yaml keys known: {r.stderr[-400:]}")

if failures:
    print(f"{len(failures)} check(s) failed", file=sys.stderr)
    sys.exit(1)
print("mrclam import on dataset 6: all checks passed")
