#!/usr/bin/python3
"""Plots a cleanslam run against ground truth (like Figs. 13 and 14 of Choi et al. 2012).

usage: plot_run.py RUN_DIR --gt DATASET/groundtruth.csv [--out DIR] [--no-anchor] [--title T]

Run with Debian's python3 (/usr/bin/python3, python3-matplotlib, python3-numpy).
RUN_DIR holds trajectory.tum (the SLAM estimate), optionally dead_reckoning.tum and
landmarks.csv (header `slot,x,y,z,sxx,sxy,syy,...`: position and the xy covariance, m and m^2).
Writes RUN_DIR/trajectory_xy.png (XY paths, landmarks with 1-sigma ellipses) and
RUN_DIR/position_error.png (position error against time), or into --out.

The estimates are expressed in the ground truth's frame by anchoring their first pose on the
ground truth's pose at that time (as cleanslam-eval --align none does); --no-anchor plots them
as they are.
"""
import argparse
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Ellipse  # noqa: E402


def fail(msg):
    print(f"plot_run.py: {msg}", file=sys.stderr)
    sys.exit(1)


def read_tum(path):
    rows = []
    with open(path) as f:
        for n, line in enumerate(f, 1):
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            p = s.replace(",", " ").split()
            if len(p) != 8:
                fail(f"{path}:{n}: expected 8 fields (t x y z qx qy qz qw), got {len(p)}")
            try:
                rows.append([float(v) for v in p])
            except ValueError:
                fail(f"{path}:{n}: expected numbers")
    if not rows:
        fail(f"{path}: no poses")
    a = np.array(rows)
    t = a[:, 0]
    qx, qy, qz, qw = a[:, 4], a[:, 5], a[:, 6], a[:, 7]
    yaw = np.arctan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))
    return t, a[:, 1:4], yaw


def read_groundtruth(path):
    rows = []
    with open(path) as f:
        header = f.readline().strip()
        if not header.startswith("#t_ns,x_m,y_m,z_m,qw,qx,qy,qz"):
            fail(f"{path}:1: expected the header #t_ns,x_m,y_m,z_m,qw,qx,qy,qz")
        for n, line in enumerate(f, 2):
            s = line.strip()
            if not s:
                continue
            p = s.split(",")
            if len(p) != 8:
                fail(f"{path}:{n}: expected 8 fields, got {len(p)}")
            try:
                rows.append([float(v) for v in p])
            except ValueError:
                fail(f"{path}:{n}: expected numbers")
    if not rows:
        fail(f"{path}: no poses")
    a = np.array(rows)
    t = a[:, 0] * 1e-9
    qw, qx, qy, qz = a[:, 4], a[:, 5], a[:, 6], a[:, 7]
    yaw = np.arctan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))
    return t, a[:, 1:4], yaw


def read_landmarks(path):
    with open(path) as f:
        header = [h.strip().lstrip("#") for h in f.readline().strip().split(",")]
        need = ["x", "y", "sxx", "sxy", "syy"]
        for k in need:
            if k not in header:
                fail(f"{path}:1: column {k} missing (header: {','.join(header)})")
        idx = [header.index(k) for k in need]
        out = []
        for n, line in enumerate(f, 2):
            s = line.strip()
            if not s:
                continue
            p = s.split(",")
            try:
                out.append([float(p[i]) for i in idx])
            except (ValueError, IndexError):
                fail(f"{path}:{n}: bad row")
    return np.array(out).reshape(-1, 5)


def interp_gt(gt_t, gt_p, t):
    return np.stack([np.interp(t, gt_t, gt_p[:, i]) for i in range(3)], axis=1)


def anchor(t, p, yaw, gt_t, gt_p, gt_yaw):
    """Rigid planar transform that puts the first estimated pose on the ground truth's."""
    if t[0] < gt_t[0] or t[0] > gt_t[-1]:
        return 0.0, np.zeros(3)
    g = interp_gt(gt_t, gt_p, t[:1])[0]
    gy = np.interp(t[0], gt_t, np.unwrap(gt_yaw))
    rot = gy - yaw[0]
    c, s = math.cos(rot), math.sin(rot)
    shift = g - np.array([c * p[0, 0] - s * p[0, 1], s * p[0, 0] + c * p[0, 1], p[0, 2]])
    return rot, shift


def apply(rot, shift, p):
    c, s = math.cos(rot), math.sin(rot)
    q = np.empty_like(p)
    q[:, 0] = c * p[:, 0] - s * p[:, 1] + shift[0]
    q[:, 1] = s * p[:, 0] + c * p[:, 1] + shift[1]
    q[:, 2] = p[:, 2] + shift[2]
    return q


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run_dir")
    ap.add_argument("--gt", required=True, help="DATASET/groundtruth.csv")
    ap.add_argument("--out", help="folder for the PNG files (default RUN_DIR)")
    ap.add_argument("--no-anchor", action="store_true")
    ap.add_argument("--title", default=None)
    args = ap.parse_args()

    run = args.run_dir
    traj_path = os.path.join(run, "trajectory.tum")
    if not os.path.isfile(traj_path):
        fail(f"{traj_path}: not found")
    if not os.path.isfile(args.gt):
        fail(f"{args.gt}: not found")
    out = args.out or run
    os.makedirs(out, exist_ok=True)
    title = args.title or os.path.basename(os.path.normpath(run))

    gt_t, gt_p, gt_yaw = read_groundtruth(args.gt)
    est_t, est_p, est_yaw = read_tum(traj_path)
    rot, shift = (0.0, np.zeros(3)) if args.no_anchor else anchor(
        est_t, est_p, est_yaw, gt_t, gt_p, gt_yaw)
    est_p = apply(rot, shift, est_p)

    dr = None
    dr_path = os.path.join(run, "dead_reckoning.tum")
    if os.path.isfile(dr_path):
        dr_t, dr_p, dr_yaw = read_tum(dr_path)
        r2, s2 = (0.0, np.zeros(3)) if args.no_anchor else anchor(
            dr_t, dr_p, dr_yaw, gt_t, gt_p, gt_yaw)
        dr = (dr_t, apply(r2, s2, dr_p))

    lms = None
    lm_path = os.path.join(run, "landmarks.csv")
    if os.path.isfile(lm_path):
        lms = read_landmarks(lm_path)

    # Fig. 13: XY trajectories and the map.
    fig, ax = plt.subplots(figsize=(8, 7))
    ax.plot(gt_p[:, 0], gt_p[:, 1], "k-", lw=1.0, label="ground truth")
    if dr is not None:
        ax.plot(dr[1][:, 0], dr[1][:, 1], "-", color="tab:orange", lw=0.8, label="dead reckoning")
    ax.plot(est_p[:, 0], est_p[:, 1], "-", color="tab:blue", lw=1.0, label="SLAM estimate")
    ax.plot(gt_p[0, 0], gt_p[0, 1], "ko", ms=6)
    if lms is not None and len(lms):
        c, s = math.cos(rot), math.sin(rot)
        r = np.array([[c, -s], [s, c]])
        xy = (r @ lms[:, 0:2].T).T + shift[:2]
        ax.plot(xy[:, 0], xy[:, 1], "r+", ms=6, label="landmarks (1σ)")
        for (x, y), (sxx, sxy, syy) in zip(xy, lms[:, 2:5]):
            cov = r @ np.array([[sxx, sxy], [sxy, syy]]) @ r.T
            w, v = np.linalg.eigh(cov)
            if not np.all(np.isfinite(w)) or w[0] < 0:
                continue
            ang = math.degrees(math.atan2(v[1, 1], v[0, 1]))
            ax.add_patch(Ellipse((x, y), 2 * math.sqrt(w[1]), 2 * math.sqrt(w[0]), angle=ang,
                                 fill=False, color="r", lw=0.6))
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"{title}: trajectory and map")
    ax.grid(True, lw=0.3)
    ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    xy_png = os.path.join(out, "trajectory_xy.png")
    fig.savefig(xy_png, dpi=120)
    plt.close(fig)

    # Fig. 14: position error against time.
    fig, ax = plt.subplots(figsize=(9, 4))
    t0 = gt_t[0]

    def err(t, p):
        m = (t >= gt_t[0]) & (t <= gt_t[-1])
        g = interp_gt(gt_t, gt_p, t[m])
        return t[m] - t0, np.linalg.norm(p[m, :2] - g[:, :2], axis=1)

    if dr is not None:
        tt, e = err(dr[0], dr[1])
        ax.plot(tt, e, "-", color="tab:orange", lw=0.8, label="dead reckoning")
    tt, e = err(est_t, est_p)
    ax.plot(tt, e, "-", color="tab:blue", lw=1.0, label="SLAM estimate")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("position error [m]")
    ax.set_title(f"{title}: position error (xy)")
    ax.grid(True, lw=0.3)
    ax.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    err_png = os.path.join(out, "position_error.png")
    fig.savefig(err_png, dpi=120)
    plt.close(fig)
    print(xy_png)
    print(err_png)


if __name__ == "__main__":
    main()
