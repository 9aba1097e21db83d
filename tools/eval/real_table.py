#!/usr/bin/python3
"""Markdown table of SLAM on real recordings: the robots of a UTIAS MRCLAM dataset, each imported
with tools/import/mrclam.py in every gyro choice, replayed and evaluated against Vicon.

  tools/eval/real_table.py [--data DIR] [--robots 1-5] [--gyro commanded,mems] [--seed N]
                           [--set section.key=value ...] [--no-bound] [--jobs J] [--out DIR]
                           [--json] [--plot FILE.png] [--bin DIR]

Per robot and gyro choice: the Vicon path length, dead reckoning's and SLAM's ATE RMSE
(cleanslam-eval --align none), SLAM's mean position NEES per degree of freedom (1 if consistent),
full_slam_bound.py --wheel-heading's filtering standard deviation (what a causal estimator can
expect on those data) and its smoothed trajectory's ATE, from the truth, and cleanslam-replay's
run time; the means last. --data defaults to ../shared/data/mrclam/MRCLAM_Dataset6 beside the
repository (or beside the folder of its worktree); --set goes to cleanslam-replay for every run.
--plot draws, per run, SLAM ATE, DR ATE and the bound's two figures, and the NEES per dof.
Progress on stderr, the table on stdout. Exit status 0 unless a run failed to execute (1) or the
arguments are wrong (2).
"""

import argparse
import json
import math
import os
import shlex
import shutil
import statistics
import signal
import sys
import tempfile
import time

import numpy as np

import monte_carlo as mc
import scenario_table as st
from cleanslam_eval import nees_note, processes, trajectory

IMPORTER = os.path.join(mc.REPO, "tools", "import", "mrclam.py")
# ../shared beside the repository, or beside the folder of the worktree it is checked out in.
DEFAULT_DATA = next((p for p in (os.path.join(up, "shared", "data", "mrclam", "MRCLAM_Dataset6")
                                 for up in (os.path.dirname(mc.REPO),
                                            os.path.dirname(os.path.dirname(mc.REPO))))
                     if os.path.isdir(p)),
                    os.path.join(os.path.dirname(mc.REPO), "shared", "data", "mrclam",
                                 "MRCLAM_Dataset6"))
GYROS = ("commanded", "mems")


def find_tools(bin_dir):
    tools = {k: os.path.join(bin_dir, f"cleanslam-{k}") for k in ("replay", "eval")}
    missing = [p for p in tools.values() if not os.access(p, os.X_OK)]
    if missing:
        raise mc.RunError("not found or not executable: " + ", ".join(missing) +
                          " (build with cmake --preset host-release, or give --bin)")
    return tools


def import_robot(data, robot, gyro, seed, dataset, log):
    cmd = [sys.executable, IMPORTER, data, str(robot), dataset, "--gyro", gyro, "--seed",
           str(seed), "--force"]
    p = processes.run(cmd)
    with open(log, "a", encoding="utf-8") as f:
        f.write("$ " + shlex.join(cmd) + "\n" + p.stdout + p.stderr)
    if p.returncode != 0:
        raise mc.RunError(f"mrclam.py robot {robot} --gyro {gyro}: exit {p.returncode}: "
                          f"{p.stderr.strip()[-300:]}")


def progress(msg):
    print(f"real_table: {msg}", file=sys.stderr, flush=True)


def run(tools, data, robot, gyro, seed, sets, base, bound, emulator, diagnose=False):
    os.makedirs(base, exist_ok=True)
    log = os.path.join(base, "log.txt")
    progress(f"robot {robot} --gyro {gyro}: importing, replaying")
    dataset, run_dir = os.path.join(base, "dataset"), os.path.join(base, "run")
    import_robot(data, robot, gyro, seed, dataset, log)
    start = time.monotonic()
    r = mc.replay_and_evaluate(tools, dataset, run_dir, sets, emulator, log)
    r["run_time_s"] = time.monotonic() - start  # with its two cleanslam-eval calls
    r["nees_per_dof"] = None if r["nees_mean"] is None else r["nees_mean"] / mc.NEES_DOF
    for k in ("pose_nees_times_s", "pose_nees"):
        r.pop(k)
    if diagnose:
        r |= yaw_diagnostics(dataset, run_dir)
        r["statuses"] = sighting_statuses(run_dir)
    if bound:
        progress(f"robot {robot} --gyro {gyro}: SLAM ATE {r['slam_ate_m']:.3f} m; "
                 "full_slam_bound.py (about 30 s)")
        b = st.full_slam_bound(dataset, run_dir)
        r["filtering_sd_m"] = b["filtering_sd_m"]
        r["full_slam_ate_m"] = b["full_slam_ate_m"]
        r["smoothing_sd_m"] = b["smoothing_sd_m"]
    return r


STATUSES = ("updated", "initialized", "merged", "gated", "depth_bound", "behind_camera", "skipped")


def yaw_diagnostics(dataset, run_dir):
    """The SLAM heading's error against its std. dev. (both relative to the first pose, as
    --align none), and the dead reckoner's heading error: RMS in degrees, the fraction of poses
    whose error exceeds 3 std. dev., the mean (x, y, yaw) NEES per dof."""
    gt = trajectory.read_groundtruth(os.path.join(dataset, "groundtruth.csv"))

    def errors(name):
        return trajectory.planar_errors(gt, trajectory.read_tum(os.path.join(run_dir, name)))

    keep, _, err = errors("trajectory.tum")
    e = err[:, 2]
    cov = np.loadtxt(os.path.join(run_dir, "trajectory.tum.cov"), ndmin=2)[keep]
    P = cov[:, 1:].reshape(-1, 6, 6)[:, [0, 1, 5]][:, :, [0, 1, 5]]
    nees = [float(v @ np.linalg.solve(p, v)) / 3.0 for v, p in zip(err, P)
            if np.all(np.linalg.eigvalsh(p) > 0)]
    sd = np.sqrt(np.maximum(P[:, 2, 2], 0.0))
    e_dr = errors("dead_reckoning.tum")[2][:, 2]
    return {"slam_yaw_rms_deg": math.degrees(float(np.sqrt(np.mean(e * e)))),
            "slam_yaw_sd_rms_deg": math.degrees(float(np.sqrt(np.mean(sd * sd)))),
            "yaw_beyond_3sd": float(np.mean(np.abs(e) > 3.0 * sd)),
            "pose_nees_per_dof": float(np.mean(nees)) if nees else None,
            "dr_yaw_rms_deg": math.degrees(float(np.sqrt(np.mean(e_dr * e_dr))))}


def sighting_statuses(run_dir):
    """Counts of cleanslam-replay's update records (diagnostics.csv) by status."""
    counts = dict.fromkeys(STATUSES, 0)
    with open(os.path.join(run_dir, "diagnostics.csv"), encoding="utf-8") as f:
        next(f, None)
        for line in f:
            parts = line.split(",")
            if len(parts) > 3:
                counts[parts[3]] = counts.get(parts[3], 0) + 1
    return counts


def parse_list(text, allowed, what):
    items = [s.strip() for s in text.split(",") if s.strip()]
    bad = [s for s in items if s not in allowed]
    if bad or not items:
        raise ValueError(f"--{what} '{text}': expected a comma-separated list of "
                         + ", ".join(allowed))
    return items


def _mean(xs):
    xs = [x for x in xs if x is not None]
    return statistics.fmean(xs) if xs else None


COLUMNS = [("path m", "path_length_m", ".1f"), ("DR ATE m", "dr_ate_m", ".3f"),
           ("SLAM ATE m", "slam_ate_m", ".3f"), ("NEES/dof", "nees_per_dof", ".3g"),
           ("filtering std. dev. m", "filtering_sd_m", ".3f"),
           ("full SLAM ATE m", "full_slam_ate_m", ".3f"), ("run time s", "run_time_s", ".2f")]


def columns(bound):
    return [c for c in COLUMNS if bound or c[1] not in ("filtering_sd_m", "full_slam_ate_m")]


def row(robot, g, results, failures, bound):
    """One Markdown row: the run's figures, its failure, or "not finished"."""
    r = results.get((robot, g))
    if r is None:
        what = (f"failed: {failures[(robot, g)][:80]}" if (robot, g) in failures
                else "not finished")
        return f"| {robot} | {g} | {what} |"
    cells = [st._f(r.get(k), f) for _, k, f in columns(bound)]
    if r["slam_ate_m"] < r["dr_ate_m"]:
        cells[2] = f"**{cells[2]}**"
    return f"| {robot} | {g} | " + " | ".join(cells) + " |"


def markdown(robots, gyros, results, failures, bound, sets):
    cols = columns(bound)
    lines = ["replay settings: " + (", ".join(f"`{s}`" for s in sets) if sets else "defaults"), "",
             "| robot | gyro | " + " | ".join(c[0] for c in cols) + " |",
             "|---:|---|" + "|".join(["---:"] * len(cols)) + "|"]
    for robot in robots:
        for g in gyros:
            lines.append(row(robot, g, results, failures, bound))
    for g in gyros:
        ran = [results[(robot, g)] for robot in robots if (robot, g) in results]
        lines.append(f"| mean | {g} | " +
                     " | ".join(st._f(_mean([r.get(k) for r in ran]), f) for _, k, f in cols) +
                     " |")
    lines += ["", "SLAM ATE in bold where it beats dead reckoning. ATE RMSE with --align none "
              "(both trajectories relative to their first pose). NEES/dof: mean position NEES "
              "over the run's poses / 3. " + nees_note.PER_DOF +
              (" Filtering std. dev.: full_slam_bound.py --wheel-heading's RMS position std. "
               "dev. given the data up to each frame; full SLAM ATE: its smoothed trajectory's "
               "ATE, started from the truth." if bound else "") +
              " Run time: cleanslam-replay and the two cleanslam-eval calls."]
    return "\n".join(lines)


def json_table(a, results, failures):
    return json.dumps({"data": a.data, "replay_sets": a.sets, "seed": a.seed,
                       "rows": [{"robot": k[0], "gyro": k[1]} | r
                                for k, r in sorted(results.items())],
                       "failures": [{"robot": k[0], "gyro": k[1], "error": v}
                                    for k, v in sorted(failures.items())]}, indent=1) + "\n"


def write_atomically(path, write):
    """write(file) into path.tmp, then renamed to path: a reader never sees half a table."""
    with open(path + ".tmp", "w", encoding="utf-8") as f:
        write(f)
    os.replace(path + ".tmp", path)


def diagnosis_markdown(robots, gyros, results):
    head = ["robot", "gyro", "SLAM yaw RMS deg", "its std. dev. RMS deg", "yaw beyond 3 sd",
            "(x, y, yaw) NEES/dof", "DR yaw RMS deg"] + list(STATUSES)
    lines = ["| " + " | ".join(head) + " |", "|---:|---|" + "|".join(["---:"] * (len(head) - 2)) +
             "|"]
    for robot in robots:
        for g in gyros:
            r = results.get((robot, g))
            if r is None or "statuses" not in r:
                continue
            lines.append(f"| {robot} | {g} | {r['slam_yaw_rms_deg']:.1f} | "
                         f"{r['slam_yaw_sd_rms_deg']:.1f} | {r['yaw_beyond_3sd']:.0%} | "
                         f"{st._f(r['pose_nees_per_dof'], '.3g')} | {r['dr_yaw_rms_deg']:.1f} | " +
                         " | ".join(str(r["statuses"].get(k, 0)) for k in STATUSES) + " |")
    lines += ["", "Heading errors relative to the first pose (as --align none); yaw beyond 3 sd: "
              "fraction of poses whose heading error exceeds three times the filter's heading "
              "std. dev.; statuses: cleanslam-replay's update records (diagnostics.csv): one per "
              "sighting in a frame, plus merges."]
    return "\n".join(lines)


LOG_TICKS = (1.0, 2.0, 5.0)


def log_limits(lo, hi):
    """lo and hi widened to the nearest labelled ticks (1, 2, 5 times a power of ten) outside
    them, so that the log axis has a label at both ends."""
    def ticks(v):
        e = math.floor(math.log10(v))
        return [m * 10.0 ** k for k in (e - 1, e, e + 1) for m in LOG_TICKS]
    return (max(t for t in ticks(lo) if t <= lo * (1 + 1e-9)),
            min(t for t in ticks(hi) if t >= hi * (1 - 1e-9)))


def plot(robots, gyros, results, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter, LogLocator
    fig, (ax_ate, ax_nees) = plt.subplots(1, 2, figsize=(14, 5.2),
                                          gridspec_kw={"width_ratios": [3, 2]})
    keys = [(r, g) for r in robots for g in gyros]
    xs = range(len(keys))
    short = {"commanded": "cmd", "mems": "mems"}
    labels = [f"R{r}\n{short[g]}" for r, g in keys]
    series = [("dr_ate_m", "DR ATE", "tab:gray", "s"), ("slam_ate_m", "SLAM ATE", "tab:blue", "o"),
              ("filtering_sd_m", "bound: filtering std. dev.", "k", "D"),
              ("full_slam_ate_m", "bound: full SLAM ATE", "tab:green", "v")]
    drawn = []
    for key, label, color, marker in series:
        pts = [(x, results[k][key]) for x, k in zip(xs, keys)
               if k in results and results[k].get(key) is not None]
        if pts:
            ax_ate.plot([p[0] for p in pts], [p[1] for p in pts], marker, color=color, ms=8,
                        label=label, ls="none")
            drawn.append(key)
    bound = any(k in drawn for k in ("filtering_sd_m", "full_slam_ate_m"))
    ax_ate.set_yscale("log")
    ax_ate.set_ylabel("ATE" + (" and bound" if bound else "") + " [m] (log)")
    ax_ate.set_title("ATE (--align none)" + (" and the full-SLAM bound" if bound else ""))
    pts = [(x, results[k]["nees_per_dof"]) for x, k in zip(xs, keys)
           if k in results and results[k].get("nees_per_dof") is not None]
    colors = {"commanded": "tab:orange", "mems": "tab:blue"}
    for g in gyros:
        sel = [(x, v) for (x, v), k in zip(pts, [keys[x] for x, _ in pts]) if k[1] == g]
        ax_nees.bar([p[0] for p in sel], [p[1] for p in sel], 0.6, color=colors[g],
                    label=f"gyro {g}")
    ax_nees.set_yscale("log")
    ax_nees.axhline(1.0, color="k", ls=":", lw=1.0, label="consistent (1)")
    ax_nees.axhspan(0.5, 2.0, color="g", alpha=0.15, label="[0.5, 2]")
    ax_nees.set_ylabel("mean position NEES per dof (log)")
    ax_nees.set_title("SLAM consistency")
    for ax in (ax_ate, ax_nees):
        ax.set_ylim(*log_limits(*ax.get_ylim()))
        ax.yaxis.set_major_locator(LogLocator(base=10, subs=LOG_TICKS))
        ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        ax.yaxis.set_minor_formatter(FuncFormatter(lambda v, _: ""))
        for k in range(1, len(robots)):
            ax.axvline(k * len(gyros) - 0.5, color="0.8", lw=0.8)
        ax.set_xticks(list(xs), labels, fontsize=9)
        ax.set_xlabel("robot, gyro")
        ax.grid(True, which="major", axis="y", alpha=0.3)
        ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", default=DEFAULT_DATA, help="a MRCLAM dataset folder")
    ap.add_argument("--robots", default="1-5", help="e.g. 1-5 or 1,3 (default 1-5)")
    ap.add_argument("--gyro", default=",".join(GYROS), help="commanded, mems or both (default)")
    ap.add_argument("--seed", type=int, default=1, help="the mems gyro's errors (default 1)")
    ap.add_argument("--set", dest="sets", action="append", default=[], metavar="K=V",
                    help="cleanslam-replay --set key=value for every run (repeatable)")
    ap.add_argument("--no-bound", dest="bound", action="store_false",
                    help="leave out full_slam_bound.py (about 30 s a run)")
    ap.add_argument("--diagnose", action="store_true",
                    help="a second table: heading error against its std. dev., dead reckoning's "
                    "heading error, and the update records by status")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", help="keep datasets and runs here (default: temporary)")
    ap.add_argument("--json", action="store_true", help="one JSON object instead of Markdown")
    ap.add_argument("--plot", metavar="PNG", help="write a PNG of the table")
    ap.add_argument("--bin", default=mc.DEFAULT_BIN)
    ap.add_argument("--emulator", default="", help="command prefix for the programs")
    a = ap.parse_args(argv)
    try:
        robots = st.parse_seeds(a.robots)
        gyros = parse_list(a.gyro, GYROS, "gyro")
    except ValueError as e:
        ap.error(str(e).replace("--seeds", "--robots"))
    for kv in a.sets:
        if "=" not in kv:
            ap.error(f"--set '{kv}': expected section.key=value")
    if not os.path.isdir(a.data):
        ap.error(f"--data {a.data}: not a folder")
    if a.plot and not os.path.isdir(os.path.dirname(os.path.abspath(a.plot))):
        ap.error(f"--plot {a.plot}: its folder does not exist")
    try:
        tools = find_tools(a.bin)
    except mc.RunError as e:
        print(f"real_table: {e}", file=sys.stderr)
        return 1
    emulator = shlex.split(a.emulator)
    work = os.path.abspath(a.out) if a.out else tempfile.mkdtemp(prefix="cleanslam_real_")
    os.makedirs(work, exist_ok=True)
    table = os.path.join(work, "table.json" if a.json else "table.md") if a.out else None
    if table:
        progress(f"the table grows in {table} as the runs finish")
    results, failures = {}, {}

    def report(output):
        if a.json:
            output.write(json_table(a, results, failures))
        else:
            output.write(markdown(robots, gyros, results, failures, a.bound, a.sets) + "\n")
            if a.diagnose:
                output.write("\n" + diagnosis_markdown(robots, gyros, results) + "\n")

    def finished(key):
        progress(row(key[0], key[1], results, failures, a.bound))
        if table:
            write_atomically(table, report)

    processes.raise_on_sigterm()
    try:
        tasks = [((robot, g), lambda robot=robot, g=g: run(
            tools, a.data, robot, g, a.seed, a.sets, os.path.join(work, f"robot{robot}_{g}"),
            a.bound, emulator, a.diagnose)) for robot in robots for g in gyros]
        mc.run_parallel(a.jobs, tasks, "import, replay" + (", bound" if a.bound else ""),
                        finished, results, failures)
    except (KeyboardInterrupt, processes.Stopped) as e:
        name = e.args[0] if isinstance(e, processes.Stopped) else "SIGINT"
        report(sys.stdout)
        sys.stdout.flush()
        progress(f"stopped by {name}: {len(results)} of {len(robots) * len(gyros)} runs "
                 "finished, in the "
                 "table above" + (f" and in {table}" if table else "") +
                 "; the others are marked not finished")
        return 128 + signal.Signals[name].value
    finally:
        if not a.out:
            shutil.rmtree(work, ignore_errors=True)
    plot_failed = False
    if a.plot:
        try:
            plot(robots, gyros, results, a.plot)
            print(f"real_table: wrote {a.plot}", file=sys.stderr)
        except OSError as e:
            print(f"real_table: --plot {a.plot}: {e}", file=sys.stderr)
            plot_failed = True
    report(sys.stdout)
    if not a.json:
        for k, v in sorted(failures.items()):
            print(f"\nFAILED robot {k[0]} --gyro {k[1]}: {v}")
    return 1 if failures or plot_failed else 0


if __name__ == "__main__":
    sys.exit(main())
