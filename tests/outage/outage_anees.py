#!/usr/bin/python3
"""An outage's consistency over Monte-Carlo runs: outage_check.py on several seeds (each seed's ATE
bound and health sequence checked as there), then the position NEES per dof averaged over the seeds
at each instant (the ANEES of Bar-Shalom et al., 2001, section 5.4.2) checked against a bound from
the outage's start to the run's end. One seed's NEES in a short window is close to a single
chi-square sample (3 dof per pose): a consistent filter exceeds 3 per dof in some 5 s window of a
long run; the average over N seeds has 3N dof, and its 99 % quantile is printed with the figures.

usage: outage_anees.py BINDIR WORKDIR MODE SENSOR START_S SECONDS --seeds A-B [--ate-max M]
                       [--anees-max 3] [--set K=V ...]
Exit 0 when every seed's checks and the ANEES bound pass; prints the figures either way.
"""
import argparse
import json
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
GRID_S = 0.5


def chi2_99(dof):
    # Wilson-Hilferty: within 0.1 % of the exact quantile from a few degrees of freedom on.
    z = 2.3263479
    return dof * (1.0 - 2.0 / (9.0 * dof) + z * (2.0 / (9.0 * dof)) ** 0.5) ** 3


def seeds_of(text):
    a, _, b = text.partition("-")
    return list(range(int(a), int(b or a) + 1))


def read_nees(path):
    rows = np.loadtxt(path, delimiter=",", comments="#", ndmin=2)
    return rows[:, 0], rows[:, 1]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("bindir")
    ap.add_argument("workdir")
    ap.add_argument("mode", choices=["features", "images"])
    ap.add_argument("sensor", choices=["encoders", "gyro", "camera"])
    ap.add_argument("start_s", type=float)
    ap.add_argument("seconds", type=float)
    ap.add_argument("--seeds", required=True, help="A-B, inclusive")
    ap.add_argument("--ate-max", type=float, default=None, help="per seed")
    ap.add_argument("--anees-max", type=float, default=3.0, help="per degree of freedom")
    ap.add_argument("--set", action="append", default=[])
    a = ap.parse_args()
    seeds = seeds_of(a.seeds)
    os.makedirs(a.workdir, exist_ok=True)
    fails = []
    series = []
    reports = []
    for k, seed in enumerate(seeds):
        work = os.path.join(a.workdir, "seed%d" % seed)
        nees_file = os.path.join(a.workdir, "nees_seed%d.csv" % seed)
        args = [sys.executable, os.path.join(HERE, "outage_check.py"), a.bindir, work, a.mode,
                a.sensor, str(a.start_s), str(a.seconds), "--seed", str(seed),
                "--nees-max", "inf", "--nees-out", nees_file]
        if a.ate_max is not None:
            args += ["--ate-max", str(a.ate_max)]
        for s in a.set:
            args += ["--set", s]
        p = subprocess.run(args, capture_output=True, text=True)
        print("[%d/%d] seed %d done" % (k + 1, len(seeds), seed), file=sys.stderr, flush=True)
        lines = [line for line in p.stdout.splitlines() if line.startswith("{")]
        if not lines or not os.path.exists(nees_file):
            sys.exit("outage_check.py failed on seed %d:\n%s" % (seed, p.stderr))
        rep = json.loads(lines[0])
        reports.append({"seed": seed, "ate_m": rep["ate_m"],
                        "worst_5s_nees_per_dof": round(rep["nees_per_dof_worst_5s"], 3)})
        for f in p.stderr.splitlines():
            if f.startswith("FAIL: "):
                fails.append("seed %d: %s" % (seed, f[6:]))
        series.append(read_nees(nees_file))
    # Each seed's NEES held from one pose to the next on a common grid, averaged over the seeds.
    t_end = min(t[-1] for t, _ in series)
    grid = np.arange(a.start_s, t_end, GRID_S)
    stack = []
    for t, n in series:
        i = np.clip(np.searchsorted(t, grid, side="right") - 1, 0, len(t) - 1)
        stack.append(n[i])
    anees = np.mean(np.array(stack), axis=0)
    dof = 3 * len(seeds)
    q99 = chi2_99(dof) / dof
    worst = int(np.argmax(anees))
    out = {"mode": a.mode, "sensor": a.sensor, "seconds": a.seconds, "seeds": a.seeds,
           "per_seed": reports, "mean_ate_m": float(np.mean([r["ate_m"] for r in reports])),
           "anees_per_dof_max": float(anees[worst]), "at_s": float(grid[worst]),
           "anees_per_dof_mean": float(np.mean(anees)), "chi2_99_per_dof": q99,
           "fraction_above_99": float(np.mean(anees > q99))}
    print(json.dumps(out))
    if not anees[worst] < a.anees_max:
        fails.append("ANEES per dof over seeds %s reaches %.2f at %.1f s (>= %.2f)"
                     % (a.seeds, anees[worst], grid[worst], a.anees_max))
    for f in fails:
        print("FAIL: " + f, file=sys.stderr)
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
