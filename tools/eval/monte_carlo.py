#!/usr/bin/python3
"""Monte Carlo over simulator seeds: simulate, replay through the firmware pipeline, evaluate SLAM
and dead reckoning against ground truth, summarise accuracy and filter consistency (NEES).

  tools/eval/monte_carlo.py SCENARIO --runs N [--first-seed S] [--jobs J] [--set k=v ...]
                            [--sim-set k=v ...] [--out DIR] [--plot FILE.png] [--json]

--set goes to cleanslam-replay (section.key=value), --sim-set to cleanslam-sim (key=value).
Progress on stderr, the tables (or one JSON object with --json) on stdout. Exit status 0 unless a
run failed to execute (1) or the arguments are wrong (2); accuracy is reported, never asserted.
"""

import argparse
import bisect
import concurrent.futures
import json
import math
import os
import shlex
import shutil
import statistics
import sys
import tempfile

import numpy as np
from cleanslam_eval import nees_note, processes, trajectory

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DEFAULT_BIN = os.path.join(REPO, "build", "host-release", "bin")
NEES_DOF = 3  # position NEES: the evaluation uses the 3x3 position block of the covariance


# ---------------------------------------------------------------------------------------------
# Chi-square quantiles without scipy: regularized lower incomplete gamma P(a, x) (series for
# x < a + 1, Lentz continued fraction for the complement otherwise), inverted by bisection.


def _gamma_p(a, x):
    if x <= 0.0:
        return 0.0
    log_front = -x + a * math.log(x) - math.lgamma(a)
    if x < a + 1.0:
        term = total = 1.0 / a
        n = a
        for _ in range(10000):
            n += 1.0
            term *= x / n
            total += term
            if abs(term) < abs(total) * 1e-15:
                break
        return total * math.exp(log_front)
    tiny = 1e-300
    b = x + 1.0 - a
    c = 1.0 / tiny
    d = 1.0 / b
    h = d
    for i in range(1, 10000):
        an = -i * (i - a)
        b += 2.0
        d = an * d + b
        d = tiny if abs(d) < tiny else d
        c = b + an / c
        c = tiny if abs(c) < tiny else c
        d = 1.0 / d
        delta = d * c
        h *= delta
        if abs(delta - 1.0) < 1e-15:
            break
    return 1.0 - math.exp(log_front) * h


def chi2_cdf(x, k):
    return _gamma_p(0.5 * k, 0.5 * x)


def chi2_ppf(p, k):
    """Quantile of the chi-square distribution with k degrees of freedom (bisection, ~1e-10)."""
    if not 0.0 < p < 1.0 or k <= 0:
        raise ValueError(f"chi2_ppf: p={p} must be in (0, 1) and k={k} > 0")
    lo, hi = 0.0, k + 40.0 * math.sqrt(2.0 * k) + 100.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if chi2_cdf(mid, k) < p:
            lo = mid
        else:
            hi = mid
        if hi - lo < 1e-10 * max(1.0, hi):
            break
    return 0.5 * (lo + hi)


def anees_band(n_runs, dof=NEES_DOF, confidence=0.95):
    """Two-sided band of the average of n_runs independent chi-square(dof) values."""
    tail = 0.5 * (1.0 - confidence)
    k = dof * n_runs
    return chi2_ppf(tail, k) / n_runs, chi2_ppf(1.0 - tail, k) / n_runs


def _read_rows(path):
    rows = []
    with open(path, encoding="utf-8") as f:
        for line_no, line in enumerate(f, 1):
            line = line.split("#", 1)[0].strip()
            if not line:
                continue
            try:
                rows.append([float(v) for v in line.replace(",", " ").split()])
            except ValueError as e:
                raise ValueError(f"{path}:{line_no}: {e}") from None
    return rows


def pose_nees(groundtruth_csv, trajectory_tum, cov_file):
    """Returns (times_s, nees) of every estimated pose inside the ground truth with a
    positive-definite covariance, as cleanslam-eval --align none."""
    e = trajectory.evaluate_files(groundtruth_csv, trajectory_tum, cov_file)
    return e.nees_t, e.nees


# ---------------------------------------------------------------------------------------------
# One run.


class RunError(Exception):
    pass


def _exec(cmd, emulator, log):
    full = list(emulator) + cmd
    proc = processes.run(full)
    if log is not None:
        with open(log, "a", encoding="utf-8") as f:
            f.write("$ " + shlex.join(full) + "\n" + proc.stdout + proc.stderr)
    if proc.returncode != 0:
        tail = (proc.stderr or proc.stdout).strip().splitlines()[-5:]
        raise RunError(f"{shlex.join(full)} exited with {proc.returncode}: " + " | ".join(tail))
    return proc


def _eval(tools, gt, est, emulator, log):
    out = _exec([tools["eval"], "--gt", gt, "--est", est, "--json"], emulator, log).stdout
    try:
        return json.loads(out)
    except json.JSONDecodeError as e:
        raise RunError(f"cleanslam-eval --est {est}: output is not JSON ({e}): {out[:200]}")


def simulate(tools, scenario, seed, dataset, sim_sets, emulator, log=None):
    cmd = [tools["sim"], scenario, dataset, "--seed", str(seed), "--force"]
    for kv in sim_sets:
        cmd += ["--set", kv]
    _exec(cmd, emulator, log)


def replay_and_evaluate(tools, dataset, run_dir, replay_sets, emulator, log=None):
    """Replays dataset into run_dir and evaluates SLAM and dead reckoning. Returns a dict."""
    if os.path.isdir(run_dir):
        shutil.rmtree(run_dir)
    cmd = [tools["replay"], dataset, "--out", run_dir]
    for kv in replay_sets:  # config=FILE loads a configuration file, section.key=value sets a key
        if kv.startswith("config="):
            cmd += ["--config", kv[len("config="):]]
    for kv in replay_sets:
        if not kv.startswith("config="):
            cmd += ["--set", kv]
    proc = _exec(cmd, emulator, log)
    # A configuration key that does not exist would leave the run at the defaults, unnoticed.
    ignored = [ln for ln in proc.stderr.splitlines() if "unknown key" in ln]
    if ignored:
        raise RunError(" | ".join(ignored))
    gt = os.path.join(dataset, "groundtruth.csv")
    slam = _eval(tools, gt, os.path.join(run_dir, "trajectory.tum"), emulator, log)
    dr = _eval(tools, gt, os.path.join(run_dir, "dead_reckoning.tum"), emulator, log)
    if slam.get("nees_not_positive_definite", 0) > 0:
        print(f"warning: {run_dir}: {slam['nees_not_positive_definite']} covariances not positive "
              "definite, left out of the NEES", file=sys.stderr)
    cov = os.path.join(run_dir, "trajectory.tum.cov")
    times, nees = pose_nees(gt, os.path.join(run_dir, "trajectory.tum"), cov) \
        if os.path.exists(cov) else ([], [])
    return {
        "path_length_m": slam["path_length_m"],
        "dr_ate_m": dr["ate_rmse_m"],
        "slam_ate_m": slam["ate_rmse_m"],
        "dr_final_m": dr["final_error_m"],
        "slam_final_m": slam["final_error_m"],
        "slam_orientation_rmse_deg": slam["orientation_rmse_deg"],
        "dr_orientation_rmse_deg": dr["orientation_rmse_deg"],
        "nees_mean": slam["nees_mean"],
        "nees_fraction_in_95": slam["nees_fraction_in_95"],
        "nees_count": slam["nees_count"],
        "nees_not_positive_definite": slam.get("nees_not_positive_definite", 0),
        "pose_nees_times_s": times,
        "pose_nees": nees,
    }


def run_one(tools, scenario, seed, work, sim_sets, replay_sets, emulator):
    base = os.path.join(work, f"seed_{seed}")
    os.makedirs(base, exist_ok=True)
    log = os.path.join(base, "log.txt")
    dataset = os.path.join(base, "dataset")
    simulate(tools, scenario, seed, dataset, sim_sets, emulator, log)
    r = replay_and_evaluate(tools, dataset, os.path.join(base, "run"), replay_sets, emulator, log)
    r["seed"] = seed
    return r


def find_tools(bin_dir):
    tools = {k: os.path.join(bin_dir, f"cleanslam-{k}") for k in ("sim", "replay", "eval")}
    missing = [p for p in tools.values() if not os.access(p, os.X_OK)]
    if missing:
        raise RunError("not found or not executable: " + ", ".join(missing) +
                       " (build with cmake --preset host-release, or give --bin)")
    return tools


def run_parallel(jobs, tasks, label, on_done=None, results=None, errors=None):
    """tasks: list of (key, callable). Returns ({key: result}, {key: error message}), filled in
    as the tasks finish (into results and errors when given); on_done(key) after each. A stop
    (KeyboardInterrupt, processes.Stopped) cancels the tasks not started, terminates the running
    ones' programs and is raised again."""
    results = {} if results is None else results
    errors = {} if errors is None else errors
    done = 0
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, jobs)) as ex:
        futures = {ex.submit(fn): key for key, fn in tasks}
        try:
            for fut in concurrent.futures.as_completed(futures):
                key = futures[fut]
                done += 1
                try:
                    results[key] = fut.result()
                    print(f"[{done}/{len(tasks)}] {label} {key} done", file=sys.stderr,
                          flush=True)
                except (RunError, OSError, ValueError, KeyError) as e:
                    errors[key] = str(e)
                    print(f"[{done}/{len(tasks)}] {label} {key} FAILED: {e}", file=sys.stderr,
                          flush=True)
                if on_done is not None:
                    on_done(key)
        except (KeyboardInterrupt, processes.Stopped):
            ex.shutdown(wait=False, cancel_futures=True)
            processes.end_children()
            raise
    return results, errors


# ---------------------------------------------------------------------------------------------
# Summary.


def _mean(xs):
    xs = [x for x in xs if x is not None]
    return statistics.fmean(xs) if xs else None


def _median(xs):
    xs = [x for x in xs if x is not None]
    return statistics.median(xs) if xs else None


def anees_over_time(runs, step_s=1.0):
    """Average over the runs of the position NEES of each run's latest pose at or before t, on a
    grid of step_s over the span every run covers. Returns (grid, anees) as lists."""
    series = [(r["pose_nees_times_s"], r["pose_nees"]) for r in runs if r["pose_nees"]]
    if not series or len(series) != len(runs):
        return [], []
    start = max(t[0] for t, _ in series)
    end = min(t[-1] for t, _ in series)
    if end < start:
        return [], []
    grid = list(np.arange(start, end + 1e-9, step_s))
    anees = []
    for g in grid:
        vals = [v[bisect.bisect_right(t, g) - 1] for t, v in series]
        anees.append(float(np.mean(vals)))
    return [float(g) for g in grid], anees


def summarize(runs):
    n = len(runs)
    s = {"runs": n}
    if n == 0:
        return s
    for key in ("dr_ate_m", "slam_ate_m", "dr_final_m", "slam_final_m"):
        vals = [r[key] for r in runs]
        s[key] = {"mean": _mean(vals), "median": _median(vals)}
    s["slam_beats_dr_ate"] = sum(1 for r in runs if r["slam_ate_m"] < r["dr_ate_m"])
    s["slam_beats_dr_final"] = sum(1 for r in runs if r["slam_final_m"] < r["dr_final_m"])
    lo, hi = anees_band(n)
    s["nees_dof"] = NEES_DOF
    s["anees_band_95"] = [lo, hi]
    with_nees = [r for r in runs if r["pose_nees"]]
    if len(with_nees) == n:
        final = [r["pose_nees"][-1] for r in runs]
        s["final_anees"] = float(np.mean(final))
        s["final_anees_in_band"] = lo <= s["final_anees"] <= hi
        grid, anees = anees_over_time(runs)
        s["anees_time_steps"] = len(grid)
        if grid:
            s["anees_time_mean"] = float(np.mean(anees))
            s["anees_fraction_in_band"] = float(np.mean([lo <= a <= hi for a in anees]))
            s["anees_fraction_above_band"] = float(np.mean([a > hi for a in anees]))
            s["anees_fraction_below_band"] = float(np.mean([a < lo for a in anees]))
        all_nees = [v for r in runs for v in r["pose_nees"]]
        s["nees_mean_all_poses"] = float(np.mean(all_nees))
        s["nees_per_dof"] = s["nees_mean_all_poses"] / NEES_DOF
        s["nees_median_all_poses"] = float(np.median(all_nees))
    return s


def _f(x, fmt):
    return "-" if x is None else format(x, fmt)


def print_text(scenario, runs, summary, failures, out=sys.stdout):
    p = lambda *a: print(*a, file=out)  # noqa: E731
    p(f"Monte Carlo: {scenario}, {len(runs)} runs" +
      (f", {len(failures)} FAILED to execute" if failures else ""))
    p(f"{'seed':>6} {'path m':>8} {'DR ATE':>8} {'SLAM ATE':>9} {'DR fin':>8} {'SLAM fin':>9}"
      f" {'NEES':>10} {'in95%':>6}")
    for r in runs:
        in95 = None if r['nees_fraction_in_95'] is None else 100 * r['nees_fraction_in_95']
        p(f"{r['seed']:>6d} {r['path_length_m']:8.2f} {r['dr_ate_m']:8.3f} {r['slam_ate_m']:9.3f}"
          f" {r['dr_final_m']:8.3f} {r['slam_final_m']:9.3f} {_f(r['nees_mean'], '10.2f')}"
          f" {_f(in95, '6.1f')}")
    for seed, msg in sorted(failures.items()):
        p(f"{seed:>6d} FAILED: {msg}")
    if not runs:
        return
    s = summary
    p("")
    p(f"{'':24s}{'mean':>10s}{'median':>10s}")
    for label, key in (("DR ATE RMSE [m]", "dr_ate_m"), ("SLAM ATE RMSE [m]", "slam_ate_m"),
                       ("DR final error [m]", "dr_final_m"),
                       ("SLAM final error [m]", "slam_final_m")):
        p(f"{label:24s}{_f(s[key]['mean'], '10.3f')}{_f(s[key]['median'], '10.3f')}")
    p(f"SLAM beat DR in {s['slam_beats_dr_ate']}/{s['runs']} runs by ATE, "
      f"{s['slam_beats_dr_final']}/{s['runs']} by final error")
    lo, hi = s["anees_band_95"]
    p(nees_note.POSITION)
    p(f"position NEES ({NEES_DOF} dof), 95 % band of the average over {s['runs']} runs: "
      f"[{lo:.3f}, {hi:.3f}]")
    if "final_anees" in s:
        p(f"  final pose: average NEES {s['final_anees']:.3f} "
          f"({'inside' if s['final_anees_in_band'] else 'OUTSIDE'} the band)")
        if "anees_time_mean" in s:
            p(f"  over time ({s['anees_time_steps']} steps of 1 s): average NEES mean "
              f"{s['anees_time_mean']:.3f}, {100 * s['anees_fraction_in_band']:.1f} % of steps "
              f"inside the band, {100 * s['anees_fraction_above_band']:.1f} % above, "
              f"{100 * s['anees_fraction_below_band']:.1f} % below")
        p(f"  all poses: mean NEES {s['nees_mean_all_poses']:.3f}, per dof "
          f"{s['nees_per_dof']:.3f} (1 if consistent), median {s['nees_median_all_poses']:.3f}")
    else:
        p("  no covariances (trajectory.tum.cov) in some run: no NEES summary")


def plot(runs, summary, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.5))
    dr = [r["dr_ate_m"] for r in runs]
    sl = [r["slam_ate_m"] for r in runs]
    ax1.scatter(dr, sl, s=14)
    m = max(dr + sl) * 1.05 if runs else 1.0
    ax1.plot([0, m], [0, m], "k--", lw=0.8)
    ax1.set_xlabel("dead-reckoning ATE RMSE [m]")
    ax1.set_ylabel("SLAM ATE RMSE [m]")
    ax1.set_title(f"{len(runs)} runs; below the line: SLAM better")
    grid, anees = anees_over_time(runs)
    if grid:
        lo, hi = summary["anees_band_95"]
        t0 = grid[0]
        ax2.semilogy([g - t0 for g in grid], anees, lw=1, label="average position NEES")
        ax2.axhline(lo, color="r", ls="--", lw=0.8, label="95 % band")
        ax2.axhline(hi, color="r", ls="--", lw=0.8)
        ax2.axhline(NEES_DOF, color="k", ls=":", lw=0.8)
        ax2.set_xlabel("time [s]")
        ax2.set_ylabel("NEES")
        ax2.legend()
    ax2.set_title("average NEES over the runs")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenario", help="built-in scenario name or scenario YAML file")
    ap.add_argument("--runs", type=int, required=True, help="number of seeds")
    ap.add_argument("--first-seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=2, help="runs in parallel (default 2)")
    ap.add_argument("--set", dest="replay_sets", action="append", default=[], metavar="K=V",
                    help="cleanslam-replay --set section.key=value (repeatable)")
    ap.add_argument("--sim-set", dest="sim_sets", action="append", default=[], metavar="K=V",
                    help="cleanslam-sim --set key=value (repeatable)")
    ap.add_argument("--out", help="keep datasets and runs here (default: a temporary folder, "
                    "deleted at the end)")
    ap.add_argument("--plot", help="write a PNG: SLAM vs DR ATE per run, average NEES over time")
    ap.add_argument("--json", action="store_true", help="one JSON object on stdout")
    ap.add_argument("--bin", default=DEFAULT_BIN, help=f"program folder (default {DEFAULT_BIN})")
    ap.add_argument("--emulator", default="", help="command prefix for the programs, e.g. "
                    "'qemu-aarch64 -L /usr/aarch64-linux-gnu'")
    a = ap.parse_args(argv)
    if a.runs < 1:
        ap.error(f"--runs {a.runs}: must be >= 1")
    for kv in a.replay_sets + a.sim_sets:
        if "=" not in kv:
            ap.error(f"'{kv}': expected key=value")
    try:
        tools = find_tools(a.bin)
    except RunError as e:
        print(f"monte_carlo: {e}", file=sys.stderr)
        return 1
    emulator = shlex.split(a.emulator)
    work = os.path.abspath(a.out) if a.out else tempfile.mkdtemp(prefix="cleanslam_mc_")
    os.makedirs(work, exist_ok=True)
    seeds = list(range(a.first_seed, a.first_seed + a.runs))
    try:
        tasks = [(s, (lambda s=s: run_one(tools, a.scenario, s, work, a.sim_sets, a.replay_sets,
                                          emulator))) for s in seeds]
        results, failures = run_parallel(a.jobs, tasks, "seed")
    finally:
        if not a.out:
            shutil.rmtree(work, ignore_errors=True)
    runs = [results[s] for s in seeds if s in results]
    summary = summarize(runs)
    if a.plot and runs:
        plot(runs, summary, a.plot)
        print(f"plot: {a.plot}", file=sys.stderr)
    if a.json:
        slim = [{k: v for k, v in r.items() if k not in ("pose_nees_times_s", "pose_nees")} |
                {"final_pose_nees": r["pose_nees"][-1] if r["pose_nees"] else None,
                 "pose_nees_mean": float(np.mean(r["pose_nees"])) if r["pose_nees"] else None}
                for r in runs]
        json.dump({"scenario": a.scenario, "seeds": seeds, "replay_sets": a.replay_sets,
                   "sim_sets": a.sim_sets, "runs": slim, "summary": summary,
                   "failures": {str(k): v for k, v in sorted(failures.items())}},
                  sys.stdout, indent=1)
        print()
    else:
        print_text(a.scenario, runs, summary, failures)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
