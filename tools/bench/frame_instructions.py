#!/usr/bin/python3
"""Instructions the estimator spends per camera frame on a dataset, counted with callgrind.

  tools/bench/frame_instructions.py DATASET [DATASET ...] [--bin DIR] [--set key=value ...]
                                    [--keep DIR]

Each DATASET (a folder, docs/dataset-format.md) is replayed once with cleanslam-replay under
valgrind --tool=callgrind. From the profile, per frame (the calls of SlamSystem::begin_frame):
  frame    the inclusive instructions of SlamSystem::begin_frame and SlamSystem::step_frame (the
           front end, the update, the map's management, and the prediction to the frame's time)
  predict  the inclusive instructions of every SlamSystem::predict call (also those inside a
           frame), divided by the frames too
Results (one line per dataset) on stdout, progress on stderr. --set is passed to cleanslam-replay.
--keep DIR keeps the callgrind profiles there (callgrind.<dataset name>.out).
Exit status: 0 when every dataset was counted, 1 when a run failed, 2 for bad arguments.
"""

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

FUNCTIONS = {
    "begin": "cleanslam::slam_core::SlamSystem::begin_frame(",
    "step": "cleanslam::slam_core::SlamSystem::step_frame(",
    "predict": "cleanslam::slam_core::SlamSystem::predict(",
}


def inclusive_costs(profile):
    """Inclusive instruction counts of FUNCTIONS, from callgrind_annotate --inclusive=yes."""
    out = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100", profile],
                         check=True, capture_output=True, text=True).stdout
    costs = {k: 0 for k in FUNCTIONS}
    line_re = re.compile(r"^\s*([\d,]+)\s+(?:\([^)]*\)\s+)?(.*)$")
    for line in out.splitlines():
        m = line_re.match(line)
        if not m:
            continue
        name = m.group(2)
        for key, fn in FUNCTIONS.items():
            if fn in name:
                costs[key] = max(costs[key], int(m.group(1).replace(",", "")))
    return costs


def call_count(profile, function):
    """How often `function` was called: the sum of the calls= lines that follow a cfn= naming it
    (callgrind compresses names: "(id) name" the first time, "(id)" after)."""
    names = {}
    calls = 0
    target = False
    with open(profile, encoding="utf-8", errors="replace") as f:
        for line in f:
            if line.startswith(("fn=", "cfn=")):
                key, _, rest = line.rstrip("\n").partition("=")
                m = re.match(r"\((\d+)\)(?: (.*))?$", rest)
                if m:
                    if m.group(2) is not None:
                        names[m.group(1)] = m.group(2)
                    name = names.get(m.group(1), "")
                else:
                    name = rest
                target = key == "cfn" and function in name
            elif line.startswith("calls=") and target:
                calls += int(line.split("=", 1)[1].split()[0])
                target = False
    return calls


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("datasets", nargs="+")
    ap.add_argument("--bin", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                  "..", "..", "build", "host-release", "bin"))
    ap.add_argument("--set", action="append", default=[], metavar="key=value")
    ap.add_argument("--keep", metavar="DIR")
    a = ap.parse_args()
    replay = os.path.join(a.bin, "cleanslam-replay")
    if not os.access(replay, os.X_OK):
        print(f"frame_instructions.py: {replay} not found (--bin)", file=sys.stderr)
        return 2
    if shutil.which("valgrind") is None or shutil.which("callgrind_annotate") is None:
        print("frame_instructions.py: valgrind (callgrind_annotate) not found", file=sys.stderr)
        return 2
    for d in a.datasets:
        if not os.path.isdir(d):
            print(f"frame_instructions.py: dataset {d} is not a folder", file=sys.stderr)
            return 2
    status = 0
    print(f"{'dataset':<32} {'frames':>7} {'frame instr/frame':>18} {'predict instr/frame':>20}")
    with tempfile.TemporaryDirectory() as tmp:
        for i, d in enumerate(a.datasets):
            name = os.path.basename(os.path.normpath(d))
            print(f"frame_instructions.py: [{i + 1}/{len(a.datasets)}] {d} under callgrind",
                  file=sys.stderr, flush=True)
            profile = os.path.join(a.keep or tmp, f"callgrind.{name}.out")
            if a.keep:
                os.makedirs(a.keep, exist_ok=True)
            cmd = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={profile}", replay, d,
                   "--out", os.path.join(tmp, "run." + name), "--force", "--accept-gaps"]
            for s in a.set:
                cmd += ["--set", s]
            r = subprocess.run(cmd, capture_output=True, text=True)
            if r.returncode != 0:
                print(f"frame_instructions.py: {d}: cleanslam-replay failed ({r.returncode}):\n"
                      f"{r.stderr[-2000:]}", file=sys.stderr)
                status = 1
                continue
            costs = inclusive_costs(profile)
            frames = call_count(profile, FUNCTIONS["begin"])
            if frames == 0:
                print(f"frame_instructions.py: {d}: no SlamSystem::begin_frame call in the "
                      "profile", file=sys.stderr)
                status = 1
                continue
            frame = (costs["begin"] + costs["step"]) / frames
            print(f"{name:<32} {frames:>7} {frame:>18.0f} {costs['predict'] / frames:>20.0f}",
                  flush=True)
    return status


if __name__ == "__main__":
    sys.exit(main())
