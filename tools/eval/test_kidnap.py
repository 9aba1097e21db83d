"""tools/eval/kidnap.py's figures on a run made here, without the simulator: ground truth that
jumps 2 m at a set-down 10 s into the run, and an estimate that stays 2 m off until it is
relocalized 3 s after the set-down, then keeps a 5 cm error (a 5 cm standard deviation, NEES 1
per axis used); the replay log claims the pose 2.5 s after the set-down, when the estimate is
still 2 m off with the same covariance (a confident wrong pose). Also a run never relocalized,
one that leaves 10 cm again within the hold, the set-down from lift.csv, and bad arguments (exit
status 2)."""

import os
import subprocess
import sys

import kidnap as k
import pytest

TOOL = os.path.join(os.path.dirname(os.path.abspath(__file__)), "kidnap.py")


def write_run(work, relocalize_at, error_after=0.05, leave_at=None):
    """Truth at x = t / 10 (y = 2 after the set-down at 10 s); the estimate follows it, 2 m off
    in y after the set-down until relocalize_at, then error_after off in x (until leave_at, after
    which 0.3 m). Covariance 0.05^2 on x, y, z."""
    os.makedirs(work, exist_ok=True)
    gt = os.path.join(work, "groundtruth.csv")
    tum = os.path.join(work, "trajectory.tum")
    with open(gt, "w", encoding="utf-8") as g, open(tum, "w", encoding="utf-8") as e, \
            open(tum + ".cov", "w", encoding="utf-8") as c:
        g.write("#t_ns,x_m,y_m,z_m,qw,qx,qy,qz\n")
        for i in range(0, 401):
            t = i * 0.1
            y = 2.0 if t >= 10.0 else 0.0
            g.write(f"{round(t * 1e9)},{t / 10},{y},0,1,0,0,0\n")
            if i % 5:
                continue
            ex, ey = t / 10, y
            if t >= 10.0 and (relocalize_at is None or t < relocalize_at):
                ey = 0.0
            elif relocalize_at is not None and t >= relocalize_at:
                ex += error_after if leave_at is None or t < leave_at else 0.3
            e.write(f"{t:.6f} {ex} {ey} 0 0 0 0 1\n")
            cov = [0.0] * 36
            cov[0] = cov[7] = cov[14] = 0.05 ** 2
            cov[21] = cov[28] = cov[35] = 0.01
            c.write(f"{t:.6f} " + " ".join(map(str, cov)) + "\n")
    return gt, tum


def run_figures(work, name, claim_s=None, **kwargs):
    gt, tum = write_run(os.path.join(work, name), **kwargs)
    times, errs = k.planar_errors(gt, tum)
    nt, nees = k.mc.pose_nees(gt, tum, tum + ".cov")
    return times, errs, nt, nees


def test_set_down_from_lift(tmp_path):
    lift = tmp_path / "lift.csv"
    lift.write_text("#t_ns,lifted\n7000000000,1\n10000000000,0\n")
    assert k.set_down_s(str(lift)) == pytest.approx(10.0, abs=1e-9)
    lift.write_text("#t_ns,lifted\n7000000000,1\n")
    with pytest.raises(ValueError, match="lift.csv"):
        k.set_down_s(str(lift))


def test_claim_from_the_log():
    log = ("cleanslam-replay: t=7.000 s: lifted\n"
           "cleanslam-replay: t=3.000 s: recovered: pose lost\n"
           "cleanslam-replay: t=12.500 s: recovered: pose lost\n")
    assert k.claimed_s(log, 10.0) == pytest.approx(12.5, abs=1e-9)
    assert k.claimed_s("nothing", 10.0) is None


def test_consistent_relocalization_passes(tmp_path):
    r = k.assess(10.0, *run_figures(tmp_path, "ok", relocalize_at=13.0), claim_s=None)
    assert r["relocalized_after_s"] == pytest.approx(3.0, abs=1e-6)
    assert r["error_at_within_m"] == pytest.approx(0.05, abs=1e-9)
    assert r["final_error_m"] == pytest.approx(0.05, abs=1e-9)
    assert r["first_nees"] == pytest.approx([1.0] * 3, abs=1e-6)
    assert r["passed"] and not r["confident_wrong"]
    assert r["nees_bound_99"] == pytest.approx(11.345, abs=0.01)


def test_confident_wrong_claim_fails(tmp_path):
    # Claimed 2.5 s after the set-down, still 2 m off with a 5 cm standard deviation.
    r = k.assess(10.0, *run_figures(tmp_path, "ok", relocalize_at=13.0), claim_s=12.5)
    assert r["claimed_after_s"] == pytest.approx(2.5, abs=1e-6)
    assert r["first_nees"][0] == pytest.approx((2.0 / 0.05) ** 2, abs=1e-3)
    assert r["confident_wrong"] and not r["passed"]


def test_never_relocalized(tmp_path):
    r = k.assess(10.0, *run_figures(tmp_path, "never", relocalize_at=None), claim_s=None)
    assert r["relocalized_after_s"] is None and not r["passed"]
    assert r["error_at_within_m"] == pytest.approx(2.0, abs=1e-9)


def test_error_leaving_within_the_hold(tmp_path):
    # 13 s does not hold for 10 s; from 20 s the error is 0.3 m: never within 10 cm and held.
    r = k.assess(10.0, *run_figures(tmp_path, "leaves", relocalize_at=13.0, leave_at=20.0),
                 claim_s=None)
    assert r["relocalized_after_s"] is None


@pytest.mark.parametrize("args", [["--seeds", "x"], ["--jobs", "0"], ["--set", "novalue"],
                                  ["--tolerance", "0"]])
def test_bad_arguments(args):
    p = subprocess.run([sys.executable, TOOL] + args, capture_output=True, text=True, check=False)
    assert p.returncode == 2


def test_missing_programs(tmp_path):
    p = subprocess.run([sys.executable, TOOL, "--bin", str(tmp_path / "nothing")],
                       capture_output=True, text=True, check=False)
    assert p.returncode == 1 and "not found" in p.stderr


def test_table_explains_its_nees(tmp_path):
    figures = run_figures(tmp_path, "ok", relocalize_at=13.0)
    r = k.assess(10.0, *figures, claim_s=None) | {"set_down_s": 10.0}
    text = k.table("kidnapped", "features", [1], {1: r}, {}, 10.0, 0.1)
    assert "Position NEES (3 degrees of freedom): 3 on average when the covariance is honest" \
        in text
