#!/usr/bin/python3
"""Relocalization after a kidnap, over simulator seeds: is the robot found again where it was set
down, how soon, and does the filter claim the pose with a covariance that admits its error?

  tools/eval/kidnap.py [--scenario kidnapped] [--seeds 1-10] [--mode images|features]
                       [--set section.key=value ...] [--sim-set key=value ...] [--jobs J]
                       [--out DIR] [--bin DIR] [--emulator CMD] [--json]

Per seed: cleanslam-sim SCENARIO --seed N --set camera.mode=MODE, cleanslam-replay (--set keys go
to it), then, against groundtruth.csv (both trajectories relative to their first pose, as
cleanslam-eval --align none) and the set-down time of lift.csv:
- claimed: when the replay says the pose is no longer lost after the set-down (its log's
  "recovered: pose lost"), seconds after the set-down;
- relocalized: the first pose within --within seconds (10) of the set-down whose planar error is
  below --tolerance (0.1 m) and stays below it for the next --hold seconds (10);
- NEES: the position NEES (3 dof) of the first three poses from the claim (else from the
  relocalization); a value above the 99 % bound is a confident wrong pose;
- the planar error at the set-down + --within and at the end.
A seed passes when it is relocalized and none of those NEES exceeds the bound.
Progress on stderr, the table (or one JSON object) on stdout. Exit status 0 unless a run failed to
execute or a file could not be read (1) or the arguments are wrong (2); accuracy is reported,
never asserted.
"""

import argparse
import json
import math
import os
import re
import shlex
import shutil
import sys
import tempfile

import numpy as np

import monte_carlo as mc
from cleanslam_eval import nees_note
from cleanslam_eval import trajectory
from scenario_table import parse_seeds

NEES_POSES = 3
RECOVERED = re.compile(r"t=([0-9.]+) s: recovered: pose lost")


def set_down_s(lift_csv):
    """The first time the wheel-drop switch reports the robot on the floor again, in seconds."""
    rows = mc._read_rows(lift_csv)
    lifted = False
    for r in rows:
        if len(r) < 2:
            raise ValueError(f"{lift_csv}: a line has {len(r)} fields, expected 2")
        if r[1] != 0:
            lifted = True
        elif lifted:
            return r[0] * 1e-9
    raise ValueError(f"{lift_csv}: no set-down (a lift followed by lifted=0)")


def planar_errors(groundtruth_csv, trajectory_tum):
    """(times_s, planar position errors) of every pose inside the ground truth, both trajectories
    relative to their first evaluated pose (cleanslam-eval --align none)."""
    e = trajectory.evaluate_files(groundtruth_csv, trajectory_tum)
    return [float(t) for t in e.t], [float(math.hypot(x, y)) for x, y, _ in e.error]


def claimed_s(log_text, down_s):
    """The first time after the set-down the replay reports the pose found again, or None."""
    for m in RECOVERED.finditer(log_text):
        t = float(m.group(1))
        if t >= down_s:
            return t
    return None


def assess(down_s, times, errs, nees_times, nees, claim_s, within_s=10.0, hold_s=10.0,
           tolerance_m=0.1, bound=None):
    """The figures of one run; times in seconds, errs and nees per pose."""
    bound = mc.chi2_ppf(0.99, mc.NEES_DOF) if bound is None else bound
    after = [(t, e) for t, e in zip(times, errs) if t >= down_s]
    relocalized = None
    for i, (t, e) in enumerate(after):
        if t - down_s > within_s:
            break
        if e < tolerance_m and all(e2 < tolerance_m for t2, e2 in after[i:] if t2 <= t + hold_s):
            relocalized = t
            break
    at_within = [e for t, e in after if t - down_s <= within_s]
    start = claim_s if claim_s is not None else relocalized
    first = [n for t, n in zip(nees_times, nees) if start is not None and t >= start][:NEES_POSES]
    confident_wrong = any(n > bound for n in first)
    return {
        "set_down_s": down_s,
        "claimed_after_s": None if claim_s is None else claim_s - down_s,
        "relocalized_after_s": None if relocalized is None else relocalized - down_s,
        "first_nees": first,
        "nees_bound_99": bound,
        "confident_wrong": confident_wrong,
        "error_at_within_m": at_within[-1] if at_within else None,
        "final_error_m": after[-1][1] if after else None,
        "passed": relocalized is not None and not confident_wrong,
    }


def run_seed(tools, scenario, seed, mode, work, sim_sets, replay_sets, emulator, within_s,
             hold_s, tolerance_m):
    base = os.path.join(work, f"seed_{seed}")
    os.makedirs(base, exist_ok=True)
    log = os.path.join(base, "log.txt")
    if os.path.exists(log):
        os.remove(log)
    dataset = os.path.join(base, "dataset")
    run = os.path.join(base, "run")
    mc.simulate(tools, scenario, seed, dataset, [f"camera.mode={mode}"] + sim_sets, emulator, log)
    mc.replay_and_evaluate(tools, dataset, run, replay_sets, emulator, log)
    gt = os.path.join(dataset, "groundtruth.csv")
    tum = os.path.join(run, "trajectory.tum")
    down = set_down_s(os.path.join(dataset, "lift.csv"))
    times, errs = planar_errors(gt, tum)
    nees_times, nees = mc.pose_nees(gt, tum, tum + ".cov")
    with open(log, encoding="utf-8") as f:
        claim = claimed_s(f.read(), down)
    r = assess(down, times, errs, nees_times, nees, claim, within_s, hold_s, tolerance_m)
    r["seed"] = seed
    return r


def _f(x, fmt):
    return "-" if x is None else format(x, fmt)


def table(scenario, mode, seeds, results, failures, within_s, tolerance_m):
    lines = [f"## {scenario}, {mode}: relocalized (error below {tolerance_m * 100:g} cm within "
             f"{within_s:g} s of the set-down, and held)", "",
             "| seed | set down s | claimed +s | relocalized +s | first NEES (3 dof) | "
             f"error at +{within_s:g} s m | final error m | pass |",
             "|---:|---:|---:|---:|---|---:|---:|:---:|"]
    for s in seeds:
        if s in failures:
            lines.append(f"| {s} | failed: {failures[s]} |||||||")
            continue
        r = results[s]
        nees = ", ".join(f"{n:.1f}" for n in r["first_nees"]) or "-"
        if r["confident_wrong"]:
            nees += f" (> {r['nees_bound_99']:.2f})"
        lines.append(f"| {s} | {r['set_down_s']:.1f} | {_f(r['claimed_after_s'], '.1f')} | "
                     f"{_f(r['relocalized_after_s'], '.1f')} | {nees} | "
                     f"{_f(r['error_at_within_m'], '.3f')} | {_f(r['final_error_m'], '.3f')} | "
                     f"{'yes' if r['passed'] else 'no'} |")
    ok = [r for r in results.values() if r["relocalized_after_s"] is not None]
    wrong = [s for s, r in results.items() if r["confident_wrong"]]
    lines += ["", nees_note.POSITION, "", f"relocalized {len(ok)}/{len(seeds)}, passed "
              f"{sum(r['passed'] for r in results.values())}/{len(seeds)}, confident wrong "
              f"poses {len(wrong)}" + (f" (seeds {', '.join(map(str, sorted(wrong)))})"
                                       if wrong else "")]
    if ok:
        lines.append("time to relocalize: median "
                     f"{float(np.median([r['relocalized_after_s'] for r in ok])):.1f} s, max "
                     f"{max(r['relocalized_after_s'] for r in ok):.1f} s")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scenario", default="kidnapped", help="built-in name or scenario file")
    ap.add_argument("--seeds", default="1-10", help="e.g. 1-10 or 1,4,7 (default 1-10)")
    ap.add_argument("--mode", choices=("images", "features"), default="images",
                    help="the simulated camera's output (default images)")
    ap.add_argument("--set", dest="sets", action="append", default=[], metavar="K=V",
                    help="cleanslam-replay --set section.key=value (repeatable; config=FILE)")
    ap.add_argument("--sim-set", dest="sim_sets", action="append", default=[], metavar="K=V",
                    help="cleanslam-sim --set key=value (repeatable)")
    ap.add_argument("--within", type=float, default=10.0, help="seconds after the set-down (10)")
    ap.add_argument("--hold", type=float, default=10.0, help="seconds the error must hold (10)")
    ap.add_argument("--tolerance", type=float, default=0.1, help="planar error, m (0.1)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", help="keep DIR/seed_N/{dataset,run,log.txt} (default: temporary)")
    ap.add_argument("--bin", default=mc.DEFAULT_BIN)
    ap.add_argument("--emulator", default="", help="command prefix for the programs")
    ap.add_argument("--json", action="store_true", help="one JSON object instead of the table")
    a = ap.parse_args(argv)
    try:
        seeds = parse_seeds(a.seeds)
    except ValueError as e:
        ap.error(str(e))
    for kv in a.sets + a.sim_sets:
        if "=" not in kv:
            ap.error(f"--set/--sim-set '{kv}': expected key=value")
    if a.jobs < 1:
        ap.error(f"--jobs {a.jobs}: at least 1")
    if not (a.within > 0 and a.hold >= 0 and a.tolerance > 0):
        ap.error("--within and --tolerance must be positive, --hold not negative")
    try:
        tools = mc.find_tools(a.bin)
    except mc.RunError as e:
        print(f"kidnap: {e}", file=sys.stderr)
        return 1
    emulator = shlex.split(a.emulator)
    work = os.path.abspath(a.out) if a.out else tempfile.mkdtemp(prefix="cleanslam_kidnap_")
    os.makedirs(work, exist_ok=True)
    try:
        tasks = [(s, lambda s=s: run_seed(tools, a.scenario, s, a.mode, work, a.sim_sets, a.sets,
                                          emulator, a.within, a.hold, a.tolerance))
                 for s in seeds]
        results, failures = mc.run_parallel(a.jobs, tasks, "seed")
    finally:
        if not a.out:
            shutil.rmtree(work, ignore_errors=True)
    if a.json:
        json.dump({"scenario": a.scenario, "mode": a.mode, "seeds": seeds, "replay_sets": a.sets,
                   "sim_sets": a.sim_sets, "runs": [results[s] for s in sorted(results)],
                   "failures": {str(k): v for k, v in failures.items()}}, sys.stdout, indent=1)
        print()
    else:
        print(table(a.scenario, a.mode, seeds, results, failures, a.within, a.tolerance))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
