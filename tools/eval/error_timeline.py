#!/usr/bin/python3
"""Error of a run against ground truth over time, with the filter's own standard deviations, to
see when an estimate diverges and whether its covariance admits it.

  tools/eval/error_timeline.py DATASET RUN [--every SECONDS]

DATASET holds groundtruth.csv; RUN holds trajectory.tum and trajectory.tum.cov (cleanslam-replay
--out). Both trajectories are taken relative to their pose at the run's first time, as
cleanslam-eval --align none does. Prints t, planar error (x, y), its std. dev., yaw error and its
std. dev. (degrees), the (x, y, yaw) NEES per degree of freedom and the planar path length of
the estimate so far divided by the truth's (its scale: monocular SLAM takes the scale from the
odometry alone, so a ratio that leaves the odometry's scale error shows a map that shrinks or
grows; the estimate's jumps at updates count as travel). Last the mean NEES per dof and the whole
run's path length ratio, with the dead reckoner's (RUN/dead_reckoning.tum, when there) beside it.
"""

import argparse
import math
import os
import sys

import numpy as np
from cleanslam_eval import nees_note, trajectory


def load(path, columns, **kwargs):
    try:
        a = np.loadtxt(path, ndmin=2, **kwargs)
    except (OSError, ValueError) as e:
        print(f"error_timeline: {path}: {e}", file=sys.stderr)
        return None
    if a.shape[1] != columns:
        print(f"error_timeline: {path}: {a.shape[1]} columns, expected {columns}", file=sys.stderr)
        return None
    return a


def path_ratio(est_m, true_m):
    return f"{est_m / true_m:.3f}" if true_m > 0.0 else "-"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dataset")
    ap.add_argument("run")
    ap.add_argument("--every", type=float, default=30.0, help="print every this many seconds")
    a = ap.parse_args(argv)
    gt = load(os.path.join(a.dataset, "groundtruth.csv"), 8, delimiter=",", comments="#")
    est = load(os.path.join(a.run, "trajectory.tum"), 8)
    cov = load(os.path.join(a.run, "trajectory.tum.cov"), 37)
    if gt is None or est is None or cov is None:
        return 1
    if len(cov) != len(est):
        print(f"error_timeline: {a.run}/trajectory.tum.cov: expected t and 36 values per pose of "
              "trajectory.tum", file=sys.stderr)
        return 1
    truth, poses = trajectory.from_groundtruth_rows(gt), trajectory.from_tum_rows(est)
    keep, g_xy, errs = trajectory.planar_errors(truth, poses)
    if not keep.any():
        print("error_timeline: no pose of the run lies within the ground truth", file=sys.stderr)
        return 1
    t, est, cov = est[keep, 0], est[keep], cov[keep]
    gx, gy = g_xy[:, 0], g_xy[:, 1]
    est_path = np.concatenate(([0.0], np.cumsum(np.hypot(np.diff(est[:, 1]), np.diff(est[:, 2])))))
    gt_path = np.concatenate(([0.0], np.cumsum(np.hypot(np.diff(gx), np.diff(gy)))))
    nees, last = [], -math.inf
    for i, err in enumerate(errs):
        P = cov[i, 1:].reshape(6, 6)[np.ix_([0, 1, 5], [0, 1, 5])]
        try:
            q = float(err @ np.linalg.solve(P, err)) / 3.0
        except np.linalg.LinAlgError:
            q = math.nan
        nees.append(q)
        if t[i] - last >= a.every:
            last = t[i]
            print(f"t {t[i]:7.1f} s  err x {err[0]:6.2f} y {err[1]:6.2f} m (std "
                  f"{math.sqrt(max(P[0, 0] + P[1, 1], 0.0)):5.2f})  yaw {math.degrees(err[2]):7.1f}"
                  f" deg (std {math.degrees(math.sqrt(max(P[2, 2], 0.0))):6.1f})  NEES/dof {q:8.2f}"
                  f"  path SLAM/true {path_ratio(est_path[i], gt_path[i])}")
    print(f"mean (x, y, yaw) NEES per dof: {np.nanmean(nees):.3g}")
    print(nees_note.PER_DOF)
    dr_text = ""
    dr_file = os.path.join(a.run, "dead_reckoning.tum")
    if os.path.exists(dr_file):
        dr = load(dr_file, 8)
        if dr is None:
            return 1
        dr = dr[(dr[:, 0] >= t[0]) & (dr[:, 0] <= t[-1])]
        dr_m = float(np.hypot(np.diff(dr[:, 1]), np.diff(dr[:, 2])).sum()) if len(dr) > 1 else 0.0
        dr_text = f", dead reckoning/true {path_ratio(dr_m, gt_path[-1])}"
    print(f"path length SLAM/true: {path_ratio(est_path[-1], gt_path[-1])} "
          f"(SLAM {est_path[-1]:.3f} m, truth {gt_path[-1]:.3f} m{dr_text})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
