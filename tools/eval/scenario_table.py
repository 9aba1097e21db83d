#!/usr/bin/python3
"""Markdown table of SLAM against dead reckoning on fixed seeds, one column group per named
estimator configuration, to show what each mechanism does with and without it.

  tools/eval/scenario_table.py [--config NAME:key=value,key=value ...] [--default-room]
                               [--seeds 1-10] [--jobs J] [--out DIR] [--json] [--plot PNG]
                               [--bound]

Each dataset (sparse-poor-odometry, and default-room with --default-room, seeds --seeds) is
simulated once and replayed with every configuration; keys are cleanslam-replay --set keys
(section.key=value, see firmware/config/cleanslam.sample.yaml). Without --config one
configuration, "defaults", with no override. Progress on stderr, the table on stdout. --plot
draws, per scenario and seed, each configuration's SLAM ATE as a fraction of dead reckoning's
(against the lines at 1 and 1/2) and its position NEES per degree of freedom (against [0.5, 2]).
--bound adds, per dataset, full_slam_bound.py --wheel-heading's filtering standard deviation (what
a causal estimator that fuses the wheels' heading, as the defaults do, can expect on those data;
about 10 s a seed) to the table and the plot. Each configuration's SLAM is compared with the dead
reckoning of its own run; when the configurations' dead reckonings differ (the odometry.wheel_yaw_*
keys are part of it), the table gives each its own DR column.
Exit status 0 unless a run failed to execute (1) or the arguments are wrong (2).
"""

import argparse
import json
import os
import shlex
import shutil
import statistics
import sys
import tempfile

import monte_carlo as mc
from cleanslam_eval import nees_note, processes


def split_top_level(text, sep=","):
    """Splits at sep outside brackets and braces, so list values like [1,2] stay whole."""
    parts, depth, cur = [], 0, ""
    for ch in text:
        if ch in "[{":
            depth += 1
        elif ch in "]}":
            depth -= 1
        if ch == sep and depth == 0:
            parts.append(cur)
            cur = ""
        else:
            cur += ch
    parts.append(cur)
    return [p.strip() for p in parts if p.strip()]


def parse_config(text):
    name, _, rest = text.partition(":")
    name = name.strip()
    if not name or not all(c.isalnum() or c in "-_+." for c in name):
        raise ValueError(f"--config '{text}': expected NAME:key=value,key=value or NAME, "
                         "NAME of letters, digits and -_+.")
    sets = split_top_level(rest)
    for kv in sets:
        if "=" not in kv or not kv.split("=", 1)[0].strip():
            raise ValueError(f"--config '{text}': '{kv}' is not key=value")
    return name, sets


def parse_seeds(text):
    seeds = []
    for part in text.split(","):
        lo, dash, hi = part.partition("-")
        try:
            seeds += list(range(int(lo), int(hi) + 1)) if dash else [int(lo)]
        except ValueError:
            raise ValueError(f"--seeds '{text}': expected e.g. 1-10 or 1,3,5") from None
    if not seeds:
        raise ValueError(f"--seeds '{text}': no seed")
    return seeds


def _f(x, fmt):
    return "–" if x is None else format(x, fmt)


def full_slam_bound(dataset, run):
    """full_slam_bound.py DATASET RUN --json --wheel-heading: its result, or RunError."""
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "full_slam_bound.py")
    p = processes.run([sys.executable, script, dataset, run, "--json", "--wheel-heading"])
    if p.returncode != 0:
        raise mc.RunError(f"full_slam_bound.py {dataset}: exit {p.returncode}: "
                          f"{p.stderr.strip()[-300:]}")
    return json.loads(p.stdout)


def first_run(results, scenario, seed, names):
    """(name, result) of the first configuration that ran on this dataset, or (None, None): the
    table's path length and shared DR column, the bound's run."""
    return next(((n, results[(scenario, seed, n)]) for n in names
                 if (scenario, seed, n) in results), (None, None))


def dead_reckonings_differ(scenario, seeds, names, results):
    """Whether some configuration's run has a dead reckoning other than the first's on a seed."""
    for seed in seeds:
        drs = {results[(scenario, seed, n)]["dr_ate_m"] for n in names
               if (scenario, seed, n) in results}
        if len(drs) > 1:
            return True
    return False


def markdown(scenario, seeds, configs, results, failures, bounds=None):
    names = [n for n, _ in configs]
    lines = [f"### {scenario}", ""]
    for n, sets in configs:
        lines.append(f"- **{n}**: " + (", ".join(f"`{s}`" for s in sets) if sets
                                       else "current defaults"))
    lines.append("")
    own_dr = dead_reckonings_differ(scenario, seeds, names, results)
    head = ["seed", "path m"] + ([] if own_dr else ["DR ATE m"])
    if bounds is not None:
        head.append("filtering std. dev. m")
    for n in names:
        head += ([f"DR ATE m ({n})"] if own_dr else []) + [f"SLAM ATE m ({n})", f"NEES ({n})"]
    lines.append("| " + " | ".join(head) + " |")
    lines.append("|" + "|".join(["---:"] * len(head)) + "|")
    columns = {n: ([], [], []) for n in names}
    path_all, dr_all = [], []
    for seed in seeds:
        _, ref = first_run(results, scenario, seed, names)
        if (scenario, seed) in failures:
            lines.append(f"| {seed} | simulation failed | | " +
                         " | ".join([""] * (len(head) - 3)) + " |")
            continue
        row = [str(seed), _f(ref and ref["path_length_m"], ".1f")]
        if not own_dr:
            row.append(_f(ref and ref["dr_ate_m"], ".3f"))
        if bounds is not None:
            b = bounds.get((scenario, seed))
            row.append(_f(b and b["filtering_sd_m"], ".3f"))
        if ref:
            path_all.append(ref["path_length_m"])
            dr_all.append(ref["dr_ate_m"])
        for n in names:
            r = results.get((scenario, seed, n))
            if r is None:
                row += ["failed"] * (3 if own_dr else 2)
                continue
            if own_dr:
                row.append(_f(r["dr_ate_m"], ".3f"))
                columns[n][2].append(r["dr_ate_m"])
            columns[n][0].append(r["slam_ate_m"])
            if r["nees_mean"] is not None:
                columns[n][1].append(r["nees_mean"])
            ate = _f(r["slam_ate_m"], ".3f")
            row += [f"**{ate}**" if r["slam_ate_m"] < r["dr_ate_m"] else ate,
                    _f(r["nees_mean"], ".3g")]
        lines.append("| " + " | ".join(row) + " |")
    mean = ["mean", _f(statistics.fmean(path_all) if path_all else None, ".1f")]
    if not own_dr:
        mean.append(_f(statistics.fmean(dr_all) if dr_all else None, ".3f"))
    if bounds is not None:
        sds = [b["filtering_sd_m"] for (sc, _), b in bounds.items() if sc == scenario]
        mean.append(_f(statistics.fmean(sds) if sds else None, ".3f"))
    beats = []
    for n in names:
        ates, nees, drs = columns[n]
        if own_dr:
            mean.append(_f(statistics.fmean(drs) if drs else None, ".3f"))
        mean += [_f(statistics.fmean(ates) if ates else None, ".3f"),
                 _f(statistics.fmean(nees) if nees else None, ".3g")]
        ran = [results[(scenario, seed, n)] for seed in seeds if (scenario, seed, n) in results]
        wins = sum(1 for r in ran if r["slam_ate_m"] < r["dr_ate_m"])
        beats.append(f"{n} {wins}/{len(ran)}")
    lines.append("| " + " | ".join(mean) + " |")
    lines.append("")
    lines.append("SLAM ATE in bold where it beats its own run's dead reckoning; SLAM better than "
                 "DR: " + ", ".join(beats) + ". NEES: mean position NEES over the run's poses. "
                 + nees_note.POSITION + " ATE RMSE with --align none." +
                 (" Filtering std. dev.: full_slam_bound.py's RMS position standard deviation "
                  "given the data up to each frame." if bounds is not None else ""))
    return "\n".join(lines)


def plot(scenarios, seeds, configs, results, path, bounds=None):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter, LogLocator
    names = [n for n, _ in configs]
    fig, axes = plt.subplots(len(scenarios), 2, figsize=(13, 4.2 * len(scenarios)), squeeze=False)
    width = 0.8 / len(names)
    for row, sc in enumerate(scenarios):
        ax_ate, ax_nees = axes[row]
        for i, n in enumerate(names):
            xs, ratio, xn, nees = [], [], [], []
            for j, seed in enumerate(seeds):
                r = results.get((sc, seed, n))
                if r is None:
                    continue
                if r["dr_ate_m"] > 0:
                    xs.append(j + (i - (len(names) - 1) / 2) * width)
                    ratio.append(r["slam_ate_m"] / r["dr_ate_m"])
                if r["nees_mean"] is not None:
                    xn.append(j + (i - (len(names) - 1) / 2) * width)
                    nees.append(r["nees_mean"] / mc.NEES_DOF)
            ax_ate.bar(xs, ratio, width, label=n)
            ax_nees.bar(xn, nees, width, label=n)
        if bounds:
            xb, yb = [], []
            for j, seed in enumerate(seeds):
                b = bounds.get((sc, seed))
                _, ref = first_run(results, sc, seed, names)
                if b and ref and ref["dr_ate_m"] > 0:
                    xb.append(j)
                    yb.append(b["filtering_sd_m"] / ref["dr_ate_m"])
            ax_ate.plot(xb, yb, "kD", ms=6, label="filtering std. dev. (full SLAM)")
        ax_ate.axhline(1.0, color="k", lw=0.8, label="dead reckoning")
        ax_ate.axhline(0.5, color="r", ls="--", lw=0.8, label="half of dead reckoning")
        ax_ate.set_ylabel("SLAM ATE / DR ATE")
        ax_ate.set_title(f"{sc}: SLAM ATE over DR ATE")
        ax_nees.set_yscale("log")
        ax_nees.yaxis.set_major_locator(LogLocator(base=2))
        ax_nees.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        ax_nees.axhline(0.5, color="g", ls="--", lw=1.0, label="band [0.5, 2]")
        ax_nees.axhline(2.0, color="g", ls="--", lw=1.0)
        ax_nees.axhline(1.0, color="k", ls=":", lw=0.8)
        ax_nees.set_ylabel("mean position NEES per dof")
        ax_nees.set_title(f"{sc}: position NEES per dof (1 if consistent)")
        for ax in (ax_ate, ax_nees):
            ax.set_xticks(range(len(seeds)), [str(s) for s in seeds])
            ax.set_xlabel("seed")
            ax.legend(fontsize=8, ncol=3, loc="upper center", bbox_to_anchor=(0.5, -0.14))
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--config", action="append", default=[], metavar="NAME:K=V,K=V",
                    help="a named configuration (repeatable); NAME alone: the defaults")
    ap.add_argument("--scenario", default="sparse-poor-odometry")
    ap.add_argument("--default-room", action="store_true", help="also the default-room seeds")
    ap.add_argument("--seeds", default="1-10", help="seeds, e.g. 1-10 or 1,4,7 (default 1-10)")
    ap.add_argument("--sim-set", dest="sim_sets", action="append", default=[], metavar="K=V",
                    help="cleanslam-sim --set key=value for every dataset (repeatable)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", help="keep datasets and runs here (default: temporary)")
    ap.add_argument("--json", action="store_true", help="one JSON object instead of Markdown")
    ap.add_argument("--plot", metavar="PNG", help="write a PNG: ATE against DR's, NEES per dof")
    ap.add_argument("--bound", action="store_true",
                    help="full_slam_bound.py's filtering std. dev. per dataset (about 10 s each)")
    ap.add_argument("--bin", default=mc.DEFAULT_BIN)
    ap.add_argument("--emulator", default="", help="command prefix for the programs")
    a = ap.parse_args(argv)
    try:
        configs = [parse_config(c) for c in a.config] or [("defaults", [])]
        seeds = parse_seeds(a.seeds)
    except ValueError as e:
        ap.error(str(e))
    names = [n for n, _ in configs]
    if len(set(names)) != len(names):
        ap.error("--config: configuration names must differ: " + ", ".join(names))
    for kv in a.sim_sets:
        if "=" not in kv:
            ap.error(f"--sim-set '{kv}': expected key=value")
    if a.plot and not os.path.isdir(os.path.dirname(os.path.abspath(a.plot))):
        ap.error(f"--plot {a.plot}: its folder does not exist")
    try:
        tools = mc.find_tools(a.bin)
    except mc.RunError as e:
        print(f"scenario_table: {e}", file=sys.stderr)
        return 1
    emulator = shlex.split(a.emulator)
    scenarios = [a.scenario] + (["default-room"] if a.default_room else [])
    work = os.path.abspath(a.out) if a.out else tempfile.mkdtemp(prefix="cleanslam_table_")
    os.makedirs(work, exist_ok=True)

    def ds_dir(sc, seed):
        return os.path.join(work, f"{sc}_seed_{seed}", "dataset")

    def log(sc, seed):
        return os.path.join(work, f"{sc}_seed_{seed}", "log.txt")

    try:
        sim_tasks = []
        for sc in scenarios:
            for seed in seeds:
                os.makedirs(os.path.dirname(ds_dir(sc, seed)), exist_ok=True)
                sim_tasks.append(((sc, seed), lambda sc=sc, seed=seed: mc.simulate(
                    tools, sc, seed, ds_dir(sc, seed), a.sim_sets, emulator, log(sc, seed))))
        _, sim_failures = mc.run_parallel(a.jobs, sim_tasks, "simulate")
        run_tasks = []
        for sc in scenarios:
            for seed in seeds:
                if (sc, seed) in sim_failures:
                    continue
                for name, sets in configs:
                    run_dir = os.path.join(work, f"{sc}_seed_{seed}", f"run_{name}")
                    run_tasks.append(((sc, seed, name), lambda sc=sc, seed=seed, run_dir=run_dir,
                                      sets=sets: mc.replay_and_evaluate(
                                          tools, ds_dir(sc, seed), run_dir, sets, emulator,
                                          log(sc, seed))))
        results, run_failures = mc.run_parallel(a.jobs, run_tasks, "replay")
        bounds, bound_failures = None, {}
        if a.bound:
            bound_tasks = []
            for sc in scenarios:
                for seed in seeds:
                    name, _ = first_run(results, sc, seed, names)
                    if name is not None:
                        run_dir = os.path.join(work, f"{sc}_seed_{seed}", f"run_{name}")
                        bound_tasks.append(((sc, seed), lambda sc=sc, seed=seed, run_dir=run_dir:
                                            full_slam_bound(ds_dir(sc, seed), run_dir)))
            bounds, bound_failures = mc.run_parallel(a.jobs, bound_tasks, "full_slam_bound")
    finally:
        if not a.out:
            shutil.rmtree(work, ignore_errors=True)

    plot_failed = False
    if a.plot:
        try:
            plot(scenarios, seeds, configs, results, a.plot, bounds)
            print(f"scenario_table: wrote {a.plot}", file=sys.stderr)
        except OSError as e:
            print(f"scenario_table: --plot {a.plot}: {e}", file=sys.stderr)
            plot_failed = True
    failures = list(sim_failures.items()) + list(run_failures.items()) + \
        list(bound_failures.items())
    if a.json:
        rows = [{"scenario": k[0], "seed": k[1], "config": k[2]} |
                {f: v for f, v in r.items() if f not in ("pose_nees_times_s", "pose_nees")}
                for k, r in sorted(results.items())]
        out = {"configs": dict(configs), "seeds": seeds, "scenarios": scenarios, "rows": rows,
               "failures": [{"what": list(k), "error": v} for k, v in failures]}
        if bounds is not None:
            out["bounds"] = [{"scenario": k[0], "seed": k[1]} | b
                             for k, b in sorted(bounds.items())]
        json.dump(out, sys.stdout, indent=1)
        print()
    else:
        print("\n\n".join(markdown(sc, seeds, configs, results, sim_failures, bounds)
                          for sc in scenarios))
        for k, v in failures:
            print(f"\nFAILED {' '.join(map(str, k))}: {v}")
    return 1 if failures or plot_failed else 0


if __name__ == "__main__":
    sys.exit(main())
