#!/usr/bin/python3
"""tools/eval/kidnap.py's figures on a run made here, without the simulator: ground truth that
jumps 2 m at a set-down 10 s into the run, and an estimate that stays 2 m off until it is
relocalized 3 s after the set-down, then keeps a 5 cm error (a 5 cm standard deviation, NEES 1
per axis used); the replay log claims the pose 2.5 s after the set-down, when the estimate is
still 2 m off with the same covariance (a confident wrong pose). Also a run never relocalized,
one that leaves 10 cm again within the hold, the set-down from lift.csv, and bad arguments (exit
status 2). Argument: WORK_DIR."""

import math
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import kidnap as k  # noqa: E402
from checks import check, exit_status, near  # noqa: E402

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


def main():
    work = sys.argv[1]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)

    lift = os.path.join(work, "lift.csv")
    with open(lift, "w", encoding="utf-8") as f:
        f.write("#t_ns,lifted\n7000000000,1\n10000000000,0\n")
    near(k.set_down_s(lift), 10.0, 1e-9, "set-down from lift.csv")
    with open(lift, "w", encoding="utf-8") as f:
        f.write("#t_ns,lifted\n7000000000,1\n")
    try:
        k.set_down_s(lift)
        check(False, "lift.csv without a set-down accepted")
    except ValueError as e:
        check("lift.csv" in str(e), f"the error names the file: {e}")

    log = ("cleanslam-replay: t=7.000 s: lifted\ncleanslam-replay: t=3.000 s: recovered: pose lost\n"
           "cleanslam-replay: t=12.500 s: recovered: pose lost\n")
    near(k.claimed_s(log, 10.0), 12.5, 1e-9, "claim after the set-down")
    check(k.claimed_s("nothing", 10.0) is None, "no claim")

    gt, tum = write_run(os.path.join(work, "ok"), relocalize_at=13.0)
    times, errs = k.planar_errors(gt, tum)
    nt, nees = k.mc.pose_nees(gt, tum, tum + ".cov")
    r = k.assess(10.0, times, errs, nt, nees, claim_s=None)
    near(r["relocalized_after_s"], 3.0, 1e-6, "relocalized 3 s after the set-down")
    near(r["error_at_within_m"], 0.05, 1e-9, "error at +10 s")
    near(r["final_error_m"], 0.05, 1e-9, "final error")
    check(len(r["first_nees"]) == 3, "three NEES")
    for n in r["first_nees"]:
        near(n, 1.0, 1e-6, "NEES of a 1-sigma error on one axis")
    check(r["passed"] and not r["confident_wrong"], "a consistent relocalization passes")
    near(r["nees_bound_99"], 11.345, 0.01, "99 % bound, 3 dof")

    # Claimed 2.5 s after the set-down, still 2 m off with a 5 cm standard deviation.
    r = k.assess(10.0, times, errs, nt, nees, claim_s=12.5)
    near(r["claimed_after_s"], 2.5, 1e-6, "claim")
    near(r["first_nees"][0], (2.0 / 0.05) ** 2, 1e-3, "NEES of the claimed wrong pose")
    check(r["confident_wrong"] and not r["passed"], "a confident wrong pose fails")

    gt, tum = write_run(os.path.join(work, "never"), relocalize_at=None)
    times, errs = k.planar_errors(gt, tum)
    nt, nees = k.mc.pose_nees(gt, tum, tum + ".cov")
    r = k.assess(10.0, times, errs, nt, nees, claim_s=None)
    check(r["relocalized_after_s"] is None and not r["passed"], "never relocalized")
    near(r["error_at_within_m"], 2.0, 1e-9, "2 m off at +10 s")

    gt, tum = write_run(os.path.join(work, "leaves"), relocalize_at=13.0, leave_at=20.0)
    times, errs = k.planar_errors(gt, tum)
    nt, nees = k.mc.pose_nees(gt, tum, tum + ".cov")
    r = k.assess(10.0, times, errs, nt, nees, claim_s=None)
    # 13 s does not hold for 10 s; from 20 s the error is 0.3 m: never within 10 cm and held.
    check(r["relocalized_after_s"] is None, f"an error that leaves 10 cm within the hold: {r}")

    for args in (["--seeds", "x"], ["--jobs", "0"], ["--set", "novalue"], ["--tolerance", "0"]):
        p = subprocess.run([sys.executable, TOOL] + args, capture_output=True, text=True,
                           check=False)
        check(p.returncode == 2, f"kidnap.py {' '.join(args)}: exit {p.returncode}, expected 2")
    p = subprocess.run([sys.executable, TOOL, "--bin", os.path.join(work, "nothing")],
                       capture_output=True, text=True, check=False)
    check(p.returncode == 1 and "not found" in p.stderr, f"missing programs: {p.stderr}")

    if exit_status():
        return 1
    print("kidnap.py: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
