#!/usr/bin/python3
"""Sensor outages degrade the estimate, never freeze it: a short simulated default room with one
sensor's rows of a window deleted (encoders, gyro or camera), replayed through the firmware; the
position NEES per degree of freedom is checked inside the window and over the run, the ATE against
a bound, and the health report's sequence (degraded when the sensor goes silent, pose lost if and
only if the position std. dev. passed the configured threshold, recovered when it returns).

usage: outage_check.py BINDIR WORKDIR MODE SENSOR START_S SECONDS [--ate-max M] [--duration S]
  MODE features|images; SENSOR encoders|gyro|camera
Exit 0 when every check passes; prints the figures either way.
"""
import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools",
                                "eval"))
from cleanslam_eval import trajectory  # noqa: E402

FILES = {"encoders": "encoders.csv", "gyro": "gyro.csv", "camera": None}
THRESHOLD_KEY = "map_management.pose_lost_position_std_m"
FOUND = 0.8


def run(args):
    p = subprocess.run(args, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("%s failed (%d):\n%s" % (os.path.basename(args[0]), p.returncode, p.stderr))
    return p


def delete_window(folder, sensor, t0_ns, t1_ns):
    def keep(line):
        if line.startswith("#") or not line.strip():
            return True
        t = int(line.split(",")[0])
        return not t0_ns <= t < t1_ns
    names = [FILES[sensor]] if FILES[sensor] else ["features.csv", os.path.join("cam0", "data.csv")]
    for name in names:
        path = os.path.join(folder, name)
        if not os.path.exists(path):
            continue
        with open(path) as f:
            lines = f.read().splitlines()
        with open(path, "w") as f:
            f.write("\n".join(line for line in lines if keep(line)) + "\n")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("bindir")
    ap.add_argument("workdir")
    ap.add_argument("mode", choices=["features", "images"])
    ap.add_argument("sensor", choices=list(FILES))
    ap.add_argument("start_s", type=float)
    ap.add_argument("seconds", type=float)
    ap.add_argument("--duration", type=float, default=None)
    ap.add_argument("--ate-max", type=float, default=None)
    ap.add_argument("--nees-max", type=float, default=3.0, help="per degree of freedom")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--nees-out", help="write each pose's time from the start (s) and position "
                    "NEES per dof here (CSV), for outage_anees.py")
    a = ap.parse_args()
    duration = a.duration or (a.start_s + a.seconds + 15.0)
    work = os.path.join(a.workdir, "%s_%s_%g" % (a.mode, a.sensor, a.seconds))
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    data = os.path.join(work, "data")
    sim = [os.path.join(a.bindir, "cleanslam-sim"), "default-room", data, "--seed", str(a.seed),
           "--set", "duration_s=%g" % duration]
    if a.mode == "images":
        sim += ["--set", "camera.mode=images"]
    run(sim)
    t_first = trajectory.read_groundtruth(os.path.join(data, "groundtruth.csv")).t[0]
    t0, t1 = t_first + a.start_s, t_first + a.start_s + a.seconds
    delete_window(data, a.sensor, int(t0 * 1e9), int(t1 * 1e9))
    out = os.path.join(work, "run")
    args = [os.path.join(a.bindir, "cleanslam-replay"), data, "--out", out, "--accept-gaps"]
    for s in a.set:
        args += ["--set", s]
    rep = run(args)
    log = rep.stderr
    ev = json.loads(run([os.path.join(a.bindir, "cleanslam-eval"), "--gt",
                         os.path.join(data, "groundtruth.csv"), "--est",
                         os.path.join(out, "trajectory.tum"), "--json"]).stdout)

    # Per-pose position NEES (cleanslam-eval --align none: relative to the first pose, whose
    # covariance is essentially zero at the start).
    tum = os.path.join(out, "trajectory.tum")
    est = trajectory.read_covariances(tum + ".cov", trajectory.read_tum(tum))
    e = trajectory.evaluate(trajectory.read_groundtruth(os.path.join(data, "groundtruth.csv")),
                            est)
    if len(e.nees) != len(est.t):
        print("FAIL: %d of %d poses have a NEES (inside the ground truth, with a positive-definite "
              "covariance)" % (len(e.nees), len(est.t)), file=sys.stderr)
        return 1
    t = est.t
    nees = np.array(e.nees) / 3.0
    sigma = np.array([math.sqrt(max(c[0, 0], c[1, 1])) for c in est.covariance])
    err = np.linalg.norm(e.error[:, :2], axis=1)
    if a.nees_out:
        with open(a.nees_out, "w") as f:
            f.write("#t_s,nees_per_dof,error_m,sigma_m\n")
            for i in range(len(t)):
                f.write("%.6f,%.6g,%.6g,%.6g\n" % (t[i] - t_first, nees[i], err[i], sigma[i]))
    inside = (t >= t0) & (t < t1 + 2.0)

    sample = run([os.path.join(a.bindir, "cleanslam"), "--print-sample-config"]).stdout

    def configured(key):
        # The run's value of a key: --set, the replay's log, or the sample configuration's.
        for s in a.set:
            if "=" in s and s.split("=", 1)[0].split(".")[-1] == key.split(".")[-1]:
                return float(s.split("=", 1)[1])
        name = re.escape(key.split(".")[-1])
        value = name + r": *([0-9.eE+-]+)"
        m = re.search(value, log) or re.search(value, sample)
        return float(m.group(1)) if m else None
    threshold = configured(THRESHOLD_KEY)
    # A silence no longer than the sensor's timeout is not an outage the health report tells.
    timeout = configured("%s_timeout_s" % a.sensor.rstrip("s"))
    events = re.findall(r"t=([0-9.]+) s: (recovered: )?"
                        r"(gyro silent|encoders silent|camera silent|pose lost)", log)

    def mean_window(x, sel):
        return float(np.mean(x[sel])) if np.any(sel) else float("nan")
    # NEES per dof averaged over sliding 5 s windows through the outage (a single pose's NEES is
    # chi-square distributed: its 99th percentile per dof is 3.8).
    worst = 0.0
    for c in np.arange(t0, t1 + 2.0, 1.0):
        sel = (t >= c) & (t < c + 5.0)
        if np.any(sel):
            worst = max(worst, float(np.mean(nees[sel])))
    report = {
        "mode": a.mode, "sensor": a.sensor, "seconds": a.seconds,
        "ate_m": ev["ate_rmse_m"], "final_error_m": ev["final_error_m"],
        "nees_per_dof_run": float(np.mean(nees)),
        "nees_per_dof_outage": mean_window(nees, inside),
        "nees_per_dof_worst_5s": worst,
        "max_error_outage_m": float(np.max(err[inside])) if np.any(inside) else float("nan"),
        "max_sigma_outage_m": float(np.max(sigma[inside])) if np.any(inside) else float("nan"),
        "threshold_m": threshold, "timeout_s": timeout, "final_sigma_m": float(sigma[-1]),
        "events": [("%s%s@%s" % ("recovered " if r else "", n, t)) for t, r, n in events],
    }
    print(json.dumps(report))
    fails = []
    if a.ate_max is not None and not ev["ate_rmse_m"] <= a.ate_max:
        fails.append("ATE %.3f m > %.3f m" % (ev["ate_rmse_m"], a.ate_max))
    if not report["nees_per_dof_worst_5s"] < a.nees_max:
        fails.append("NEES per dof %.2f over 5 s in the outage >= %.2f" % (worst, a.nees_max))
    if not report["nees_per_dof_run"] < a.nees_max:
        fails.append("NEES per dof over the run %.2f >= %.2f"
                     % (report["nees_per_dof_run"], a.nees_max))
    silent = a.sensor + " silent"
    names = [(r != "", n, float(t)) for t, r, n in events]
    went = [t for r, n, t in names if n == silent and not r]
    back = [t for r, n, t in names if n == silent and r]
    if (timeout is None or a.seconds > timeout) and not went:
        fails.append("'%s' never told" % silent)
    if went and not back:
        fails.append("'%s' never recovered" % silent)
    lost = [t for r, n, t in names if n == "pose lost" and not r]
    if threshold is not None:
        passed = bool(np.any(sigma > threshold * 1.05))
        below = bool(np.all(sigma < threshold * 0.95))
        if lost and below:
            fails.append("pose lost told while the std. dev. stayed below %.3f m" % threshold)
        if passed and not lost:
            fails.append("std. dev. passed %.3f m but pose lost was never told" % threshold)
        raised_at_end = len(lost) > len([t for r, n, t in names if n == "pose lost" and r])
        # Raised above the threshold, cleared below FOUND of it (SlamSystem::kPoseFoundStdFraction).
        if (raised_at_end and sigma[-1] < FOUND * threshold * 0.95) or (
                not raised_at_end and sigma[-1] > threshold * 1.05):
            fails.append("pose lost %s at the end with the std. dev. at %.3f m (threshold %.3f m)"
                         % ("raised" if raised_at_end else "not raised", sigma[-1], threshold))
        if lost:
            if went and lost[0] < went[0]:
                fails.append("pose lost told before the sensor was silent")
    for f in fails:
        print("FAIL: " + f, file=sys.stderr)
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
