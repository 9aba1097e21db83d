"""TUM trajectories, ground truth, its interpolation, ATE and position NEES, with the definitions
of cleanslam-eval (evaluation/src/metrics.cpp): times matched in integer nanoseconds, ground truth
interpolated linearly in position and by slerp in orientation, alignment none (both trajectories
relative to their first evaluated pose), se2 or se3 (least squares, no scale)."""
import bisect
import math
from dataclasses import dataclass, field

import numpy as np

COVARIANCE_MATCH_NS = 1000
GROUNDTRUTH_HEADER = "#t_ns,x_m,y_m,z_m,qw,qx,qy,qz"


@dataclass
class Poses:
    """t (seconds as written), t_ns, positions (n x 3), quaternions (n x 4, w x y z, as written)
    and, after read_covariances, position covariances (3x3 or None per pose)."""
    t: np.ndarray
    t_ns: np.ndarray
    position: np.ndarray
    wxyz: np.ndarray
    covariance: list = field(default_factory=list)


def _numbers(path, n, fields):
    try:
        return [float(v) for v in fields]
    except ValueError:
        raise ValueError(f"{path}:{n}: expected numbers") from None


def _rows(path, width, what):
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            p = s.replace(",", " ").split()
            if len(p) not in width:
                raise ValueError(f"{path}:{n}: expected {what}, got {len(p)}")
            yield n, _numbers(path, n, p)


def read_tum(path):
    """A TUM file: "t x y z qx qy qz qw" per line, t in seconds."""
    rows = [v for _, v in _rows(path, (8,), "8 fields (t x y z qx qy qz qw)")]
    if not rows:
        raise ValueError(f"{path}: no poses")
    a = np.array(rows)
    t_ns = np.array([round(v * 1e9) for v in a[:, 0]], dtype=np.int64)
    return Poses(a[:, 0], t_ns, a[:, 1:4], a[:, [7, 4, 5, 6]])


def read_groundtruth(path):
    """A dataset's groundtruth.csv (header #t_ns,x_m,y_m,z_m,qw,qx,qy,qz)."""
    with open(path, encoding="utf-8") as f:
        if not f.readline().strip().startswith(GROUNDTRUTH_HEADER):
            raise ValueError(f"{path}:1: expected the header {GROUNDTRUTH_HEADER}")
        t_ns, rows = [], []
        for n, line in enumerate(f, 2):
            s = line.strip()
            if not s:
                continue
            p = s.split(",")
            if len(p) != 8:
                raise ValueError(f"{path}:{n}: expected 8 fields, got {len(p)}")
            rows.append(_numbers(path, n, p))
            t_ns.append(round(rows[-1][0]) if "." in p[0] or "e" in p[0] else int(p[0]))
    if not rows:
        raise ValueError(f"{path}: no poses")
    a = np.array(rows)
    return Poses(a[:, 0] * 1e-9, np.array(t_ns, dtype=np.int64), a[:, 1:4], a[:, 4:8])


def read_covariances(path, poses):
    """Attaches the position covariances of a covariance side file (t and the 3x3 or 6x6
    covariance, row-major, per line) to the poses whose time stamp is within 1 us of its."""
    poses.covariance = [None] * len(poses.t_ns)
    k = 0
    for n, v in _rows(path, (10, 37), "t and 9 or 36 numbers"):
        t = round(v[0] * 1e9)
        while k < len(poses.t_ns) and poses.t_ns[k] < t - COVARIANCE_MATCH_NS:
            k += 1
        if k >= len(poses.t_ns) or abs(int(poses.t_ns[k]) - t) > COVARIANCE_MATCH_NS:
            raise ValueError(f"{path}:{n}: t: no pose with this time stamp in the TUM file")
        stride = 3 if len(v) == 10 else 6
        poses.covariance[k] = np.array([v[1 + r * stride: 1 + r * stride + 3]
                                        for r in range(3)])
    return poses


def yaw(wxyz):
    """Heading (rotation about z) of quaternions (n x 4, w x y z)."""
    qw, qx, qy, qz = wxyz[:, 0], wxyz[:, 1], wxyz[:, 2], wxyz[:, 3]
    return np.arctan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz))


def rotation(q):
    """Rotation matrix of a quaternion w x y z (normalized first)."""
    w, x, y, z = np.asarray(q, dtype=float) / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def slerp(qa, qb, s):
    """Eigen's Quaternion::slerp, normalized."""
    d = float(np.dot(qa, qb))
    if abs(d) >= 1.0 - np.finfo(float).eps:
        s0, s1 = 1.0 - s, s
    else:
        th = math.acos(abs(d))
        s0, s1 = math.sin((1.0 - s) * th) / math.sin(th), math.sin(s * th) / math.sin(th)
    q = s0 * np.asarray(qa) + (-s1 if d < 0.0 else s1) * np.asarray(qb)
    return q / np.linalg.norm(q)


def truth_at(gt, t_ns):
    """Ground truth (position, quaternion w x y z) at t_ns, or None outside its time span."""
    if t_ns < gt.t_ns[0] or t_ns > gt.t_ns[-1]:
        return None
    i = int(np.searchsorted(gt.t_ns, t_ns, side="right"))
    qa = gt.wxyz[i - 1] / np.linalg.norm(gt.wxyz[i - 1])
    if i == len(gt.t_ns) or gt.t_ns[i - 1] == t_ns:
        return gt.position[i - 1], qa
    s = float(t_ns - gt.t_ns[i - 1]) / float(gt.t_ns[i] - gt.t_ns[i - 1])
    qb = gt.wxyz[i] / np.linalg.norm(gt.wxyz[i])
    return (1.0 - s) * gt.position[i - 1] + s * gt.position[i], slerp(qa, qb, s)


def alignment(est_p, est_r, gt_p, gt_r, mode):
    """(R, t) taking the estimate into the frame it is compared in, and the ground truth's
    positions in that frame."""
    if mode == "none":
        r = est_r[0].T
        return r, -r @ est_p[0], (gt_p - gt_p[0]) @ gt_r[0]
    me, mg = est_p.mean(axis=0), gt_p.mean(axis=0)
    if mode == "se3":
        h = (est_p - me).T @ (gt_p - mg)
        u, _, vt = np.linalg.svd(h)
        d = np.diag([1.0, 1.0, -1.0 if np.linalg.det(vt.T @ u.T) < 0.0 else 1.0])
        r = vt.T @ d @ u.T
    elif mode == "se2":
        e, g = est_p - me, gt_p - mg
        sc = float(np.sum(e[:, 0] * g[:, 0] + e[:, 1] * g[:, 1]))
        ss = float(np.sum(e[:, 0] * g[:, 1] - e[:, 1] * g[:, 0]))
        a = 0.0 if sc == 0.0 and ss == 0.0 else math.atan2(ss, sc)
        r = np.array([[math.cos(a), -math.sin(a), 0.0], [math.sin(a), math.cos(a), 0.0],
                      [0.0, 0.0, 1.0]])
        me, mg = me * [1, 1, 0], mg * [1, 1, 0]
    else:
        raise ValueError(f"alignment {mode}: expected none, se2 or se3")
    return r, mg - r @ me, gt_p


@dataclass
class Errors:
    """Per evaluated pose: t (seconds as written), the position error after alignment; and the
    position NEES of the poses with a positive-definite covariance (nees_t, nees)."""
    t: np.ndarray
    error: np.ndarray
    nees_t: list
    nees: list
    not_positive_definite: int

    @property
    def ate_rmse(self):
        return float(np.sqrt(np.mean(np.sum(self.error ** 2, axis=1))))

    @property
    def nees_mean(self):
        return float(np.mean(self.nees)) if self.nees else None


def evaluate(gt, est, mode="none"):
    """The estimate's errors against the ground truth, as cleanslam-eval --align MODE."""
    keep, truth = [], []
    for i, t in enumerate(est.t_ns):
        g = truth_at(gt, int(t))
        if g is not None:
            keep.append(i)
            truth.append(g)
    if not keep:
        raise ValueError("no estimated pose lies within the ground truth's time span")
    est_p = est.position[keep]
    est_r = np.array([rotation(q) for q in est.wxyz[keep]])
    gt_p = np.array([p for p, _ in truth])
    gt_r = np.array([rotation(q) for _, q in truth])
    r, shift, gt_in = alignment(est_p, est_r, gt_p, gt_r, mode)
    err = est_p @ r.T + shift - gt_in
    nees_t, nees, bad = [], [], 0
    for k, i in enumerate(keep):
        p = est.covariance[i] if est.covariance else None
        if p is None:
            continue
        p = r @ (0.5 * (p + p.T)) @ r.T
        try:
            chol = np.linalg.cholesky(p)
        except np.linalg.LinAlgError:
            bad += 1
            continue
        y = np.linalg.solve(chol, err[k])
        nees_t.append(float(est.t[i]))
        nees.append(float(y @ y))
    return Errors(est.t[keep], err, nees_t, nees, bad)


def evaluate_files(groundtruth_csv, trajectory_tum, cov_file=None, mode="none"):
    """evaluate() on files; the covariances from cov_file when given."""
    est = read_tum(trajectory_tum)
    if cov_file is not None:
        read_covariances(cov_file, est)
    return evaluate(read_groundtruth(groundtruth_csv), est, mode)


def from_tum_rows(rows):
    """Poses of TUM rows (n x 8: t x y z qx qy qz qw) already read."""
    t_ns = np.array([round(v * 1e9) for v in rows[:, 0]], dtype=np.int64)
    return Poses(rows[:, 0], t_ns, rows[:, 1:4], rows[:, [7, 4, 5, 6]])


def from_groundtruth_rows(rows):
    """Poses of groundtruth.csv rows (n x 8: t_ns x y z qw qx qy qz) already read."""
    return Poses(rows[:, 0] * 1e-9, np.array([round(v) for v in rows[:, 0]], dtype=np.int64),
                 rows[:, 1:4], rows[:, 4:8])


def planar_errors(gt, est):
    """The planar errors of the estimate's poses inside the ground truth, both trajectories
    relative to their first such pose as with --align none: positions in the frame of the first
    pose's heading. Returns (keep: which of est's poses, the truth's xy at them, the errors
    n x 3: x, y and yaw wrapped to [-pi, pi))."""
    keep = (est.t_ns >= gt.t_ns[0]) & (est.t_ns <= gt.t_ns[-1])
    truth = [truth_at(gt, int(t)) for t in est.t_ns[keep]]
    g_xy = np.array([p[:2] for p, _ in truth]).reshape(-1, 2)
    g_yaw = np.unwrap(yaw(np.array([q for _, q in truth]).reshape(-1, 4)))
    e_xy, e_yaw = est.position[keep, :2], np.unwrap(yaw(est.wxyz[keep]))

    def relative(xy, heading):
        c, s = math.cos(heading[0]), math.sin(heading[0])
        d = xy - xy[0]
        return np.stack([c * d[:, 0] + s * d[:, 1], -s * d[:, 0] + c * d[:, 1]], axis=1)

    dyaw = (e_yaw - e_yaw[0]) - (g_yaw - g_yaw[0])
    err = np.column_stack([relative(e_xy, e_yaw) - relative(g_xy, g_yaw),
                           (dyaw + np.pi) % (2.0 * np.pi) - np.pi])
    return keep, g_xy, err


class PlanarTruth:
    """The ground truth in the plane, (x, y, yaw) at t seconds: interpolated linearly (yaw the
    short way round) and held at its first and last pose outside its span; the bound scripts'
    reference."""

    def __init__(self, gt):
        self.t = gt.t.tolist()
        self.xy = gt.position[:, :2].tolist()
        self.yaw = [math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
                    for w, x, y, z in gt.wxyz.tolist()]

    def at(self, t):
        i = bisect.bisect_right(self.t, t)
        if i <= 0 or i >= len(self.t):
            k = 0 if i <= 0 else -1
            return self.xy[k][0], self.xy[k][1], self.yaw[k]
        (xa, ya), (xb, yb) = self.xy[i - 1], self.xy[i]
        s = (t - self.t[i - 1]) / (self.t[i] - self.t[i - 1])
        wa, wb = self.yaw[i - 1], self.yaw[i]
        turn = math.atan2(math.sin(wb - wa), math.cos(wb - wa))
        return xa + s * (xb - xa), ya + s * (yb - ya), wa + s * turn
