#!/usr/bin/python3
"""Plots a cleanslam run against ground truth (like Figs. 13 and 14 of Choi et al. 2012).

usage: plot_run.py RUN_DIR --gt DATASET/groundtruth.csv [--out DIR] [--force] [--no-anchor]
                   [--title T] [--max-sigma M]

Run with Debian's python3 (/usr/bin/python3, python3-matplotlib, python3-numpy).
RUN_DIR holds trajectory.tum (the SLAM estimate) and optionally trajectory.tum.cov,
dead_reckoning_published.tum or dead_reckoning.tum, and landmarks.csv (header
`slot,x,y,z,sxx,sxy,syy,...`: position and the xy covariance, m and m^2).
Writes trajectory_xy.png (XY paths, the room, landmarks with 1-sigma ellipses) and
position_error.png (position error against time, SLAM's x and y error inside its +-3 sigma band)
into --out (default RUN_DIR; created). Existing PNGs are replaced only with --force; nothing is
written into the dataset folder.

The axes fit the trajectories and the room (the extent of DATASET/sim_landmarks.csv when
present). A landmark whose 1-sigma ellipse is larger than --max-sigma (default 1 m) is drawn as
a grey marker without its ellipse, and counted in the legend; one outside the axes is counted.

The estimates are expressed in the ground truth's frame by anchoring their first pose on the
ground truth's pose at that time (as cleanslam-eval --align none does); --no-anchor plots them
as they are. The ATE printed, in the titles and in the legends is cleanslam-eval --align none's
(the 3-D position RMSE, both trajectories relative to their first pose): the figure tools/demo.sh
prints.
"""
import argparse
import math
import os
import sys

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from cleanslam_eval import trajectory
    from matplotlib.patches import Ellipse, Rectangle
except ModuleNotFoundError as e:
    print(f"plot_run.py: {sys.executable} has no module '{e.name}'. Run it with Debian's "
          "/usr/bin/python3 after 'apt-get install python3-matplotlib python3-numpy' "
          "(tools/setup.sh --host-only installs them), or install numpy and matplotlib for "
          f"{sys.executable}.", file=sys.stderr)
    sys.exit(1)


def fail(msg):
    print(f"plot_run.py: {msg}", file=sys.stderr)
    sys.exit(1)


def read_poses(reader, path):
    """The poses of a TUM file or ground truth (reader: trajectory.read_tum or
    trajectory.read_groundtruth), and their yaw."""
    try:
        poses = reader(path)
    except ValueError as e:
        fail(str(e))
    return poses, trajectory.yaw(poses.wxyz)


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


def anchor(est, yaw, gt):
    """Rigid planar transform that puts the first estimated pose on the ground truth's."""
    truth = trajectory.truth_at(gt, int(est.t_ns[0]))
    if truth is None:
        return 0.0, np.zeros(3)
    g, q = truth
    p = est.position
    rot = trajectory.yaw(q[None, :])[0] - yaw[0]
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


def read_cov_xy(path):
    """t and the xy block of each 6x6 covariance (row-major: xx at 0, xy at 1, yy at 7)."""
    rows = []
    with open(path) as f:
        for n, line in enumerate(f, 1):
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            p = s.replace(",", " ").split()
            if len(p) not in (10, 37):
                fail(f"{path}:{n}: expected t and 9 or 36 numbers, got {len(p)} fields")
            try:
                v = [float(x) for x in p]
            except ValueError:
                fail(f"{path}:{n}: expected numbers")
            k = 6 if len(p) == 37 else 3
            rows.append([v[0], v[1], v[1 + 1], v[1 + k + 1]])
    return np.array(rows).reshape(-1, 4)


def read_room(path):
    """Bounding box (xmin, ymin, xmax, ymax) of the simulator's landmarks, or None."""
    if not os.path.isfile(path):
        return None
    a = np.loadtxt(path, delimiter=",", comments="#", ndmin=2)
    if a.size == 0 or a.shape[1] < 3:
        return None
    return a[:, 1].min(), a[:, 2].min(), a[:, 1].max(), a[:, 2].max()


def check_writable(png, force, dataset_dir):
    real = os.path.realpath(png)
    ds = os.path.realpath(dataset_dir)
    if real == ds or real.startswith(ds + os.sep):
        fail(f"{png}: lies inside the dataset {dataset_dir}; choose another --out")
    if os.path.exists(png) and not force:
        fail(f"{png}: exists; choose another --out, or add --force to replace it")


def plural(n, word):
    return f"{n} {word}" + ("" if n == 1 else "s")


def errors(gt_path, tum_path):
    """The 3-D position errors of cleanslam-eval --align none (their RMSE is its ATE), or None
    when no pose lies within the ground truth."""
    try:
        return trajectory.evaluate_files(gt_path, tum_path)
    except ValueError:
        return None


def ate_text(e):
    return "-" if e is None else f"{e.ate_rmse:.4f} m"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run_dir")
    ap.add_argument("--gt", required=True, help="DATASET/groundtruth.csv")
    ap.add_argument("--out", help="folder for the PNG files (default RUN_DIR)")
    ap.add_argument("--force", action="store_true", help="replace existing PNG files")
    ap.add_argument("--no-anchor", action="store_true")
    ap.add_argument("--title", default=None, help="what was run (default: the folders' names)")
    ap.add_argument("--max-sigma", type=float, default=1.0,
                    help="landmarks with a larger 1-sigma semi-axis [m] get no ellipse")
    args = ap.parse_args()

    run = args.run_dir
    traj_path = os.path.join(run, "trajectory.tum")
    if not os.path.isfile(traj_path):
        fail(f"{traj_path}: not found")
    if not os.path.isfile(args.gt):
        fail(f"{args.gt}: not found")
    dataset_dir = os.path.dirname(os.path.abspath(args.gt))
    out = args.out or run
    xy_png = os.path.join(out, "trajectory_xy.png")
    err_png = os.path.join(out, "position_error.png")
    for png in (xy_png, err_png):
        check_writable(png, args.force, dataset_dir)
    os.makedirs(out, exist_ok=True)
    title = args.title or (f"{os.path.basename(os.path.normpath(run))} on "
                           f"{os.path.basename(dataset_dir)}")

    gt, _ = read_poses(trajectory.read_groundtruth, args.gt)
    gt_t, gt_p = gt.t, gt.position
    est, est_yaw = read_poses(trajectory.read_tum, traj_path)
    est_t = est.t
    rot, shift = (0.0, np.zeros(3)) if args.no_anchor else anchor(est, est_yaw, gt)
    est_p = apply(rot, shift, est.position)
    c, s = math.cos(rot), math.sin(rot)
    r_anchor = np.array([[c, -s], [s, c]])

    dr = None
    for name in ("dead_reckoning_published.tum", "dead_reckoning.tum"):
        dr_path = os.path.join(run, name)
        if os.path.isfile(dr_path):
            dr_poses, dr_yaw = read_poses(trajectory.read_tum, dr_path)
            r2, s2 = (0.0, np.zeros(3)) if args.no_anchor else anchor(dr_poses, dr_yaw, gt)
            dr = (dr_poses.t, apply(r2, s2, dr_poses.position), errors(args.gt, dr_path))
            break

    cov = None
    cov_path = traj_path + ".cov"
    if os.path.isfile(cov_path):
        cov = read_cov_xy(cov_path)

    lms = None
    lm_path = os.path.join(run, "landmarks.csv")
    if os.path.isfile(lm_path):
        lms = read_landmarks(lm_path)

    room = read_room(os.path.join(dataset_dir, "sim_landmarks.csv"))
    slam_err = errors(args.gt, traj_path)
    slam_ate = ate_text(slam_err)
    dr_ate = ate_text(dr[2]) if dr is not None else "-"
    ates = f"ATE SLAM {slam_ate}" + (f", dead reckoning {dr_ate}" if dr is not None else "")
    print(f"{ates} (3-D RMSE as cleanslam-eval --align none: both relative to their first pose)")
    ates += " (3-D, as cleanslam-eval)"

    # Axes: the trajectories and the room, never the landmarks' ellipses.
    pts = [gt_p[:, :2], est_p[:, :2]]
    if dr is not None:
        pts.append(dr[1][:, :2])
    if room is not None:
        pts.append(np.array([[room[0], room[1]], [room[2], room[3]]]))
    allp = np.vstack(pts)
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    pad = 0.05 * max(hi - lo) + 0.2
    lo, hi = lo - pad, hi + pad

    # Fig. 13: XY trajectories and the map.
    fig, ax = plt.subplots(figsize=(8, 7.5))
    if room is not None:
        ax.add_patch(Rectangle((room[0], room[1]), room[2] - room[0], room[3] - room[1],
                               fill=False, color="0.6", lw=1.0, ls="--", label="room"))
    ax.plot(gt_p[:, 0], gt_p[:, 1], "-", color="0.55", lw=2.6, label="ground truth")
    if dr is not None:
        ax.plot(dr[1][:, 0], dr[1][:, 1], "-", color="tab:orange", lw=0.8,
                label=f"dead reckoning (ATE {dr_ate})")
    ax.plot(est_p[:, 0], est_p[:, 1], "-", color="tab:blue", lw=1.0,
            label=f"SLAM estimate (ATE {slam_ate})")
    ax.plot(gt_p[0, 0], gt_p[0, 1], "ko", ms=6, label="start")
    if lms is not None and len(lms):
        xy = (r_anchor @ lms[:, 0:2].T).T + shift[:2]
        good, vague, outside = [], [], 0
        for (x, y), (sxx, sxy, syy) in zip(xy, lms[:, 2:5]):
            if not (lo[0] <= x <= hi[0] and lo[1] <= y <= hi[1]):
                outside += 1
                continue
            cxy = r_anchor @ np.array([[sxx, sxy], [sxy, syy]]) @ r_anchor.T
            w, v = np.linalg.eigh(cxy)
            if not np.all(np.isfinite(w)) or w[0] < 0 or math.sqrt(w[1]) > args.max_sigma:
                vague.append((x, y))
                continue
            good.append((x, y))
            ang = math.degrees(math.atan2(v[1, 1], v[0, 1]))
            ax.add_patch(Ellipse((x, y), 2 * math.sqrt(w[1]), 2 * math.sqrt(w[0]), angle=ang,
                                 fill=False, color="r", lw=0.6))
        if good:
            g = np.array(good)
            ax.plot(g[:, 0], g[:, 1], "r+", ms=6,
                    label=f"{plural(len(good), 'landmark')} (1σ ellipses)")
        if vague:
            g = np.array(vague)
            ax.plot(g[:, 0], g[:, 1], "x", color="0.5", ms=5,
                    label=f"{plural(len(vague), 'landmark')} with σ > {args.max_sigma:g} m "
                    "(no ellipse)")
        if outside:
            ax.plot([], [], " ", label=f"{plural(outside, 'landmark')} outside the plotted area")
        print(f"landmarks: {plural(len(good), 'landmark')} with ellipses, "
              f"{plural(len(vague), 'landmark')} with σ > {args.max_sigma:g} m (no ellipse), "
              f"{outside} outside the plotted area")
    print(f"axes: x {lo[0]:.2f} {hi[0]:.2f} y {lo[1]:.2f} {hi[1]:.2f} (m)")
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"{title}\ntrajectory and map: {ates}", fontsize=10)
    ax.grid(True, lw=0.3)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, borderaxespad=0.0)
    fig.savefig(xy_png, dpi=120, bbox_inches="tight")
    plt.close(fig)

    # Fig. 14: position error against time, and SLAM's x and y error within +-3 sigma.
    t0 = gt_t[0]

    def err(poses, p):
        m = (poses.t_ns >= gt.t_ns[0]) & (poses.t_ns <= gt.t_ns[-1])
        g = np.array([trajectory.truth_at(gt, int(t))[0] for t in poses.t_ns[m]])
        return m, poses.t[m] - t0, p[m, :2] - g[:, :2]

    rows = 3 if cov is not None else 1
    fig, axes = plt.subplots(rows, 1, figsize=(9, 3 + 2.2 * (rows - 1)), sharex=True,
                             squeeze=False)
    axes = axes[:, 0]
    ax = axes[0]
    if dr is not None and dr[2] is not None:
        ax.plot(dr[2].t - t0, np.linalg.norm(dr[2].error, axis=1), "-", color="tab:orange",
                lw=0.8, label=f"dead reckoning (ATE {dr_ate})")
    if slam_err is not None:
        ax.plot(slam_err.t - t0, np.linalg.norm(slam_err.error, axis=1), "-", color="tab:blue",
                lw=1.0, label=f"SLAM estimate (ATE {slam_ate})")
    m, tt, e = err(est, est_p)
    ax.set_ylabel("position error (3-D) [m]")
    ax.set_title(f"{title}\nposition error: {ates}", fontsize=10)
    ax.grid(True, lw=0.3)
    ax.legend(loc="upper left", fontsize=8)
    if cov is not None:
        # Covariances are in the frame of the first pose: rotate them with the anchor.
        ct = cov[:, 0]
        sd = np.empty((len(ct), 2))
        for i, (_, sxx, sxy, syy) in enumerate(cov):
            cxy = r_anchor @ np.array([[sxx, sxy], [sxy, syy]]) @ r_anchor.T
            sd[i] = np.sqrt(np.maximum(np.diag(cxy), 0.0))
        sd_at = np.stack([np.interp(est_t[m], ct, sd[:, k]) for k in range(2)], axis=1)
        inside = np.mean(np.all(np.abs(e) <= 3 * sd_at, axis=1)) * 100.0
        for k, name in enumerate(("x", "y")):
            a = axes[1 + k]
            a.fill_between(tt, -3 * sd_at[:, k], 3 * sd_at[:, k], color="tab:blue", alpha=0.18,
                           lw=0, label="SLAM ±3σ")
            a.plot(tt, e[:, k], "-", color="tab:blue", lw=0.9, label=f"SLAM {name} error")
            a.axhline(0.0, color="0.4", lw=0.5)
            a.set_ylabel(f"{name} error [m]")
            a.grid(True, lw=0.3)
            a.legend(loc="upper left", fontsize=8, ncol=2)
        axes[1].set_title(f"SLAM error inside its ±3σ band (x and y both) at {inside:.0f} % of "
                          "the poses", fontsize=9)
    axes[-1].set_xlabel("time [s]")
    fig.tight_layout()
    fig.savefig(err_png, dpi=120)
    plt.close(fig)
    print(xy_png)
    print(err_png)


if __name__ == "__main__":
    main()
