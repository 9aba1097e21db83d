"""cleanslam_eval.trajectory against cleanslam-eval on the same files: ATE and position NEES
agree to 1e-6 in each alignment. The binary comes from $CLEANSLAM_EVAL (set by the ctest
registration); without it the comparisons are skipped."""
import json
import math
import os
import subprocess

import numpy as np
import pytest
from cleanslam_eval import trajectory

EVAL = os.environ.get("CLEANSLAM_EVAL", "")
needs_eval = pytest.mark.skipif(not os.access(EVAL, os.X_OK),
                                reason="CLEANSLAM_EVAL names no cleanslam-eval binary")


def quaternion(roll, pitch, yaw):
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return (cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy,
            cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy)


def write_run(folder, seed, six_by_six=True, bad_covariance_at=None):
    """Ground truth at 100 Hz over 20 s of a turning, slightly tilted path; an estimate at
    irregular stamps (some outside the truth's span) with an error that drifts, and a covariance
    per pose (one not positive definite when bad_covariance_at is given)."""
    rng = np.random.default_rng(seed)
    gt = folder / "groundtruth.csv"
    with open(gt, "w", encoding="utf-8") as f:
        f.write(trajectory.GROUNDTRUTH_HEADER + "\n")
        for i in range(2001):
            t = 0.01 * i
            q = quaternion(0.05 * math.sin(t), 0.03 * math.cos(0.7 * t), 0.4 * t)
            f.write(f"{1_000_000_000 + 10_000_000 * i},{2 * math.cos(0.4 * t):.9f},"
                    f"{2 * math.sin(0.4 * t):.9f},{0.1 * math.sin(t):.9f},"
                    + ",".join(f"{v:.12f}" for v in q) + "\n")
    est = folder / "trajectory.tum"
    cov = folder / "trajectory.tum.cov"
    t = 0.9 + np.cumsum(rng.uniform(0.02, 0.09, 400))
    t = t[t < 21.2]
    drift = np.cumsum(rng.normal(0.0, 0.004, (len(t), 4)), axis=0)
    with open(est, "w", encoding="utf-8") as e, open(cov, "w", encoding="utf-8") as c:
        for k, tk in enumerate(t):
            s = tk - 1.0
            yaw = 0.4 * s + 0.3 + drift[k, 3]
            c0, s0 = math.cos(0.3), math.sin(0.3)
            x, y = 2 * math.cos(0.4 * s) + drift[k, 0], 2 * math.sin(0.4 * s) + drift[k, 1]
            q = quaternion(0.05 * math.sin(s) + 0.01, 0.03 * math.cos(0.7 * s), yaw)
            e.write(f"{tk:.9f} {c0 * x - s0 * y + 1.0:.9f} {s0 * x + c0 * y - 0.5:.9f} "
                    f"{0.1 * math.sin(s) + drift[k, 2]:.9f} "
                    f"{q[1]:.9f} {q[2]:.9f} {q[3]:.9f} {q[0]:.9f}\n")
            a = rng.normal(0.0, 0.02, (3, 3))
            p = a @ a.T + np.diag([1e-4, 2e-4, 5e-5]) * (1 + k / 50)
            if k == bad_covariance_at:
                p = -p
            if six_by_six:
                full = np.diag([1e-3] * 6)
                full[:3, :3] = p
                values = full.ravel()
            else:
                values = p.ravel()
            c.write(f"{tk:.9f} " + " ".join(f"{v:.12g}" for v in values) + "\n")
    return str(gt), str(est)


def binary(gt, est, mode):
    p = subprocess.run([EVAL, "--gt", gt, "--est", est, "--align", mode, "--json"],
                       capture_output=True, text=True, check=True)
    return json.loads(p.stdout)


@needs_eval
@pytest.mark.parametrize("mode", ["none", "se2", "se3"])
@pytest.mark.parametrize("seed,six_by_six,bad", [(1, True, None), (2, False, None),
                                                 (3, True, 7)])
def test_agrees_with_cleanslam_eval(tmp_path, mode, seed, six_by_six, bad):
    gt, est = write_run(tmp_path, seed, six_by_six, bad)
    want = binary(gt, est, mode)
    got = trajectory.evaluate_files(gt, est, est + ".cov", mode)
    assert len(got.error) == want["poses_evaluated"]
    assert got.ate_rmse == pytest.approx(want["ate_rmse_m"], abs=1e-6)
    assert len(got.nees) == want["nees_count"]
    assert got.not_positive_definite == want["nees_not_positive_definite"]
    assert got.nees_mean == pytest.approx(float(want["nees_mean"]), abs=1e-6)


def test_poses_outside_the_truth_are_left_out(tmp_path):
    gt, est = write_run(tmp_path, 1)
    e = trajectory.evaluate_files(gt, est)
    assert e.t[0] >= 1.0 and e.t[-1] <= 21.0
    assert len(e.t) < len(trajectory.read_tum(est).t)


def test_covariance_without_its_pose_is_an_error(tmp_path):
    gt, est = write_run(tmp_path, 1)
    with open(est + ".cov", "a", encoding="utf-8") as f:
        f.write("99.0 " + " ".join(["0"] * 9) + "\n")
    with pytest.raises(ValueError, match="no pose with this time stamp"):
        trajectory.evaluate_files(gt, est, est + ".cov")


def test_truth_at_interpolates_between_rows(tmp_path):
    gt, _ = write_run(tmp_path, 1)
    truth = trajectory.read_groundtruth(gt)
    p, q = trajectory.truth_at(truth, 1_005_000_000)
    assert p == pytest.approx(0.5 * (truth.position[0] + truth.position[1]))
    assert np.linalg.norm(q) == pytest.approx(1.0)
    assert trajectory.truth_at(truth, 999_999_999) is None
