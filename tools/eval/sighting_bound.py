#!/usr/bin/python3
"""What dead reckoning alone gives between sightings, as a reference for a SLAM run's ATE.

  tools/eval/sighting_bound.py DATASET RUN [--json]

DATASET holds groundtruth.csv and features.csv; RUN holds dead_reckoning.tum (cleanslam-replay
--out). At each pose of dead_reckoning.tum (the frames the estimator processed), the bound's pose
is the ground truth at the dead reckoner's latest pose at or before the latest earlier frame with
a feature, moved on by the dead reckoner's own motion since then. A causal estimator that knew
the truth at every sighting but had only odometry in between would have this ATE before fusing
the new frame; a SLAM estimate far above it is not limited by the odometry between sightings.
Prints the poses, the ATE RMSE of dead reckoning (as cleanslam-eval --align none: both
trajectories relative to their first pose) and of the bound, in metres. Exit status 1 when a
file is missing or malformed."""

import argparse
import json
import math
import sys

from cleanslam_eval import trajectory


def yaw_of(w, x, y, z):
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def read_rows(path, sep):
    rows = []
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            try:
                rows.append([float(v) for v in line.replace(",", " ").split()] if sep is None
                            else [float(v) for v in line.split(sep)])
            except ValueError:
                raise ValueError(f"{path}:{n}: not numbers: {line[:60]}") from None
    return rows


def moved(anchor, dr_from, dr_to):
    """anchor (x, y, yaw) moved by the planar motion from pose dr_from to dr_to."""
    dx, dy = dr_to[0] - dr_from[0], dr_to[1] - dr_from[1]
    rot = anchor[2] - dr_from[2]
    c, s = math.cos(rot), math.sin(rot)
    return anchor[0] + c * dx - s * dy, anchor[1] + s * dx + c * dy


def bound(dataset, run):
    truth = trajectory.PlanarTruth(trajectory.read_groundtruth(f"{dataset}/groundtruth.csv"))
    frames = sorted({r[0] * 1e-9 for r in read_rows(f"{dataset}/features.csv", ",")})
    dr = [(r[0], r[1], r[2], yaw_of(r[7], r[4], r[5], r[6]))
          for r in read_rows(f"{run}/dead_reckoning.tum", None)]
    if not dr or not frames:
        raise ValueError(f"{run}/dead_reckoning.tum or {dataset}/features.csv: no poses")
    first_gt = truth.at(dr[0][0])
    first_dr = dr[0][1:]
    sq_dr = sq_bound = 0.0
    j = 0
    anchor = None  # (truth pose, dead-reckoning pose) at the latest earlier sighting
    k_anchor = 0
    for k, (t, x, y, yaw) in enumerate(dr):
        while j < len(frames) and frames[j] < t - 1e-6:
            while k_anchor + 1 < len(dr) and dr[k_anchor + 1][0] <= frames[j] + 1e-6:
                k_anchor += 1
            anchor = (truth.at(dr[k_anchor][0]), dr[k_anchor][1:])
            j += 1
        gx, gy, _ = truth.at(t)
        px, py = moved(first_gt, first_dr, (x, y, yaw))
        sq_dr += (px - gx) ** 2 + (py - gy) ** 2
        bx, by = (px, py) if anchor is None else moved(anchor[0], anchor[1], (x, y, yaw))
        sq_bound += (bx - gx) ** 2 + (by - gy) ** 2
    n = len(dr)
    return {"poses": n, "dr_ate_m": math.sqrt(sq_dr / n), "bound_ate_m": math.sqrt(sq_bound / n)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dataset")
    ap.add_argument("run")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    try:
        r = bound(a.dataset, a.run)
    except (OSError, ValueError) as e:
        print(f"sighting_bound: {e}", file=sys.stderr)
        return 1
    if a.json:
        print(json.dumps(r))
    else:
        print(f"{r['poses']} poses: DR ATE {r['dr_ate_m']:.3f} m, "
              f"DR restarted from the truth at the previous sighting {r['bound_ate_m']:.3f} m")
    return 0


if __name__ == "__main__":
    sys.exit(main())
