#!/usr/bin/python3
"""tools/eval/monte_carlo.py, scenario_table.py, sighting_bound.py, known_map_bound.py and
full_slam_bound.py on short simulated runs: output format, exit status, failures reported, the
script's per-pose NEES equal to cleanslam-eval's, chi-square band. Not accuracy, except the bounds'
on the default room.
Arguments: EMULATOR (may be empty) BIN_DIR WORK_DIR."""

import json
import math
import os
import re
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
EVAL = os.path.join(HERE, "..", "..", "tools", "eval")
sys.path.insert(0, EVAL)
import full_slam_bound  # noqa: E402
import monte_carlo  # noqa: E402
import numpy as np  # noqa: E402
import replay_checks  # noqa: E402

emulator, bin_dir, work = replay_checks.arguments()
check = replay_checks.Checks()
failures = check.failures


# The tools' own output goes to this transcript, so that the failures lead the test's output
# (CI shows its beginning); the transcript's tail follows them.
transcript_path = os.path.join(work, "transcript.txt")
transcript = open(transcript_path, "w", encoding="utf-8")


def run(script, *args):
    cmd = [sys.executable, os.path.join(EVAL, script), "--bin", bin_dir, "--emulator", emulator,
           *args]
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, check=False)
    transcript.write(f"$ {' '.join(cmd)}\n-> {p.returncode}\n{p.stdout}{p.stderr}\n")
    transcript.flush()
    return p


# Chi-square band: N = 1 gives cleanslam-eval's per-pose bounds; large N agrees with
# Wilson-Hilferty; the band narrows around 3 as N grows.
lo1, hi1 = monte_carlo.anees_band(1)
check(abs(lo1 - 0.2158) < 1e-3 and abs(hi1 - 9.3484) < 1e-3, f"band N=1: {lo1} {hi1}")
for n in (20, 50, 200):
    k = 3 * n
    for p, z in ((0.025, -1.959964), (0.975, 1.959964)):
        wh = k * (1 - 2 / (9 * k) + z * math.sqrt(2 / (9 * k))) ** 3
        got = monte_carlo.chi2_ppf(p, k)
        check(abs(got - wh) / wh < 2e-3, f"chi2_ppf({p}, {k}) = {got}, Wilson-Hilferty {wh}")
lo50, hi50 = monte_carlo.anees_band(50)
check(lo1 < lo50 < 3 < hi50 < hi1, f"band N=50 {lo50} {hi50} not inside N=1's around 3")

# Five short runs, JSON.
short = ["--sim-set", "duration_s=40"]
p = run("monte_carlo.py", "default-room", "--runs", "5", "--first-seed", "3", "--jobs", "2",
        *short, "--out", os.path.join(work, "mc"), "--json")
check(p.returncode == 0, f"monte_carlo --json exit status {p.returncode}")
try:
    out = json.loads(p.stdout)
except json.JSONDecodeError as e:
    out = None
    check(False, f"monte_carlo --json: not JSON: {e}")
if out:
    runs = out["runs"]
    check([r["seed"] for r in runs] == [3, 4, 5, 6, 7], f"seeds {[r['seed'] for r in runs]}")
    for r in runs:
        for key in ("path_length_m", "dr_ate_m", "slam_ate_m", "dr_final_m", "slam_final_m",
                    "nees_mean", "final_pose_nees", "pose_nees_mean"):
            check(isinstance(r.get(key), float) and math.isfinite(r[key]) and r[key] >= 0,
                  f"seed {r['seed']}: {key} = {r.get(key)}")
        if isinstance(r.get("pose_nees_mean"), float) and isinstance(r.get("nees_mean"), float):
            check(abs(r["pose_nees_mean"] - r["nees_mean"]) <= 1e-5 * max(1.0, r["nees_mean"]),
                  f"seed {r['seed']}: script NEES {r['pose_nees_mean']} != eval {r['nees_mean']}")
        check(os.path.isfile(os.path.join(work, "mc", f"seed_{r['seed']}", "run",
                                          "trajectory.tum")), f"--out keeps seed {r['seed']}")
    s = out["summary"]
    check(s["runs"] == 5, "summary runs")
    check(abs(s["anees_band_95"][0] - monte_carlo.anees_band(5)[0]) < 1e-9, "summary band")
    check(0 <= s["slam_beats_dr_ate"] <= 5, "slam_beats_dr_ate")
    med = sorted(r["slam_ate_m"] for r in runs)[2]
    check(abs(s["slam_ate_m"]["median"] - med) < 1e-12, "median SLAM ATE")
    check(abs(s["nees_per_dof"] * 3 - s["nees_mean_all_poses"]) < 1e-9, "NEES per dof")
    check(s["anees_time_steps"] >= 30, f"anees_time_steps {s['anees_time_steps']}")
    check(out["failures"] == {}, "no failures")

# Text output (and a plot).
png = os.path.join(work, "mc.png")
p = run("monte_carlo.py", "default-room", "--runs", "5", *short, "--plot", png)
check(p.returncode == 0, f"monte_carlo text exit status {p.returncode}")
rows = [ln for ln in p.stdout.splitlines()
        if re.fullmatch(r"\s*\d+(\s+-?\d+\.\d+){5}\s+\S+\s+\S+", ln)]
check(len(rows) == 5, f"{len(rows)} per-run rows, expected 5")
check(re.search(r"SLAM beat DR in \d/5 runs by ATE", p.stdout) is not None, "beat line")
check(re.search(r"95 % band of the average over 5 runs: \[1\.25\d, 5\.49\d\]", p.stdout)
      is not None, "band line")
check("per dof" in p.stdout, "per-dof line")
check(os.path.getsize(png) > 1000 if os.path.exists(png) else False, "plot written")
check(re.search(r"\[5/5\] seed \d done", p.stderr) is not None, "progress on stderr")

# Failures are reported with a non-zero exit status.
p = run("monte_carlo.py", "default-room", "--runs", "2", *short, "--set", "filter.no_such_key=1")
check(p.returncode == 1 and "unknown key" in p.stdout + p.stderr,
      f"unknown replay key: exit {p.returncode}")
p = run("monte_carlo.py", "no-such-scenario", "--runs", "1")
check(p.returncode == 1 and "FAILED" in p.stdout, f"unknown scenario: exit {p.returncode}")
p = subprocess.run([sys.executable, os.path.join(EVAL, "monte_carlo.py"), "default-room",
                    "--runs", "1", "--bin", os.path.join(work, "empty")],
                   stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, check=False)
check(p.returncode == 1 and "cleanslam-sim" in p.stderr, f"missing programs: exit {p.returncode}")
p = run("monte_carlo.py", "default-room", "--runs", "0")
check(p.returncode == 2, f"--runs 0: exit {p.returncode}")

# Scenario table: two configurations, Markdown.
table_out = os.path.join(work, "table")
table_png = os.path.join(work, "table.png")
p = run("scenario_table.py", "--seeds", "1-2", "--sim-set", "duration_s=60", "--config",
        "defaults", "--config", "gate1:frontend.min_inliers=1,filter.eps_ct_m=100", "--out",
        table_out, "--plot", table_png)
check(p.returncode == 0, f"scenario_table exit status {p.returncode}")
check(os.path.getsize(table_png) > 1000 if os.path.exists(table_png) else False,
      "table plot written")
check("| seed | path m | DR ATE m | SLAM ATE m (defaults) | NEES (defaults) | "
      "SLAM ATE m (gate1) | NEES (gate1) |" in p.stdout, "table header")
for seed in ("1", "2", "mean"):
    check(re.search(rf"^\| {seed} \|( [^|]+ \|){{6}}$", p.stdout, re.M) is not None,
          f"table row {seed}")
check("`frontend.min_inliers=1`, `filter.eps_ct_m=100`" in p.stdout, "config listed")
# Configurations whose dead reckonings differ (the heading fusion is part of it: a gate no
# interval passes leaves the gyro's heading alone) get a DR column each, and each is compared
# with its own.
p = run("scenario_table.py", "--seeds", "1", "--sim-set", "duration_s=60", "--config",
        "fused", "--config", "gyro:odometry.wheel_yaw_gate_chi2=1e-9", "--out", table_out)
check(p.returncode == 0 and "| seed | path m | DR ATE m (fused) | SLAM ATE m (fused) | "
      "NEES (fused) | DR ATE m (gyro) | SLAM ATE m (gyro) | NEES (gyro) |" in p.stdout,
      f"table with dead reckonings of their own: exit {p.returncode}\n{p.stdout}")
row = re.search(r"^\| 1 \| [^|]+ \| ([0-9.]+) \| [^|]+ \| [^|]+ \| ([0-9.]+) \|", p.stdout, re.M)
check(row is not None and row.group(1) != row.group(2),
      f"the two dead reckonings are the same: {row and row.groups()}")
p = run("scenario_table.py", "--seeds", "1", "--sim-set", "duration_s=30", "--config",
        "x:frontend.no_such=1")
check(p.returncode == 1 and "FAILED" in p.stdout, f"table bad key: exit {p.returncode}")
p = run("scenario_table.py", "--config", "bad name:a=1")
check(p.returncode == 2, f"table bad config name: exit {p.returncode}")
# --bound: full_slam_bound.py's result on each dataset and the first configuration's run, in the
# JSON and as a column of the table.
bound_out = os.path.join(work, "table_bound")
p = run("scenario_table.py", "--seeds", "1", "--sim-set", "duration_s=30", "--out", bound_out,
        "--bound", "--json")
check(p.returncode == 0, f"scenario_table --bound exit status {p.returncode}")
tb = json.loads(p.stdout)["bounds"] if p.returncode == 0 else []
direct = subprocess.run(
    [sys.executable, os.path.join(EVAL, "full_slam_bound.py"),
     os.path.join(bound_out, "sparse-poor-odometry_seed_1", "dataset"),
     os.path.join(bound_out, "sparse-poor-odometry_seed_1", "run_defaults"), "--json",
     "--wheel-heading"],
    stdout=subprocess.PIPE, text=True, check=False)
# The same computation twice: equal up to the floating-point summation order of a threaded BLAS.
check(len(tb) == 1 and direct.returncode == 0 and
      json.loads(direct.stdout)["filtering_sd_m"] > 0 and
      math.isclose(tb[0]["filtering_sd_m"], json.loads(direct.stdout)["filtering_sd_m"],
                   rel_tol=1e-9),
      f"--bound JSON {tb} against full_slam_bound.py's own {direct.stdout}")
p = run("scenario_table.py", "--seeds", "1", "--sim-set", "duration_s=30", "--bound")
check(p.returncode == 0 and "| DR ATE m | filtering std. dev. m | SLAM ATE m (defaults) |"
      in p.stdout, f"--bound table: exit {p.returncode}")
missing_png = os.path.join(work, "no_such_folder", "table.png")
p = run("scenario_table.py", "--plot", missing_png)
check(p.returncode == 2 and missing_png in p.stderr,
      f"table plot folder missing: exit {p.returncode}")

# sighting_bound.py: its DR ATE is cleanslam-eval's; restarted from the truth at every sighting
# dead reckoning does better; with a perfect dead reckoner both are zero.
ds = os.path.join(table_out, "sparse-poor-odometry_seed_1", "dataset")
rd = os.path.join(table_out, "sparse-poor-odometry_seed_1", "run_defaults")
bound_cmd = [sys.executable, os.path.join(EVAL, "sighting_bound.py"), ds, rd, "--json"]
p = subprocess.run(bound_cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                   check=False)
check(p.returncode == 0, f"sighting_bound exit {p.returncode}: {p.stderr}")
if p.returncode == 0:
    b = json.loads(p.stdout)
    ev = subprocess.run([*emulator.split(), os.path.join(bin_dir, "cleanslam-eval"), "--gt",
                         os.path.join(ds, "groundtruth.csv"), "--est",
                         os.path.join(rd, "dead_reckoning.tum"), "--json"],
                        stdout=subprocess.PIPE, text=True, check=False)
    ate = json.loads(ev.stdout)["ate_rmse_m"] if ev.returncode == 0 else float("nan")
    check(abs(b["dr_ate_m"] - ate) <= 0.02 * ate + 1e-3, f"bound's DR ATE {b} vs eval {ate}")
    check(0.0 <= b["bound_ate_m"] < b["dr_ate_m"], f"bound not below DR: {b}")
perfect = os.path.join(work, "perfect_dr")
os.makedirs(perfect, exist_ok=True)
with open(os.path.join(ds, "groundtruth.csv"), encoding="utf-8") as f, \
        open(os.path.join(perfect, "dead_reckoning.tum"), "w", encoding="utf-8") as out:
    for i, line in enumerate(f):
        if not line.startswith("#") and i % 50 == 1:
            t, x, y, z, qw, qx, qy, qz = line.strip().split(",")
            out.write(f"{int(t) * 1e-9:.9f} {x} {y} {z} {qx} {qy} {qz} {qw}\n")
p = subprocess.run([sys.executable, os.path.join(EVAL, "sighting_bound.py"), ds, perfect,
                    "--json"], stdout=subprocess.PIPE, text=True, check=False)
b = json.loads(p.stdout) if p.returncode == 0 else {}
check(b.get("dr_ate_m", 1.0) < 1e-6 and b.get("bound_ate_m", 1.0) < 1e-6,
      f"perfect dead reckoning: {b}")
p = subprocess.run([sys.executable, os.path.join(EVAL, "sighting_bound.py"), ds,
                    os.path.join(work, "no_such_run")], stderr=subprocess.PIPE, text=True,
                   check=False)
check(p.returncode == 1 and "dead_reckoning.tum" in p.stderr, f"missing run: {p.returncode}")

# known_map_bound.py: on the true map the particle filter is far better than dead reckoning in the
# default room; on a map displaced by 0.5 m it is not; the same seed gives the same result; bad
# input names the file or key at fault.
ds = os.path.join(work, "mc", "seed_3", "dataset")
rd = os.path.join(work, "mc", "seed_3", "run")


def bound_tool(script, dataset, *args):
    cmd = [sys.executable, os.path.join(EVAL, script), dataset, rd, *args]
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                          check=False)


def known_map(dataset, *args):
    return bound_tool("known_map_bound.py", dataset, "--particles", "500", *args)


def bound_json(tool, tum):
    """The tool's process and its JSON on the default room, writing its poses to `tum`."""
    r = tool(ds, "--json", "--out", tum)
    check(r.returncode == 0, f"{tool.__name__} exit {r.returncode}: {r.stderr}")
    return r, (json.loads(r.stdout) if r.returncode == 0 else {})


tum = os.path.join(work, "known_map.tum")
p, k = bound_json(known_map, tum)
check(0.0 <= k.get("known_map_ate_m", 1.0) < 0.5 * k.get("dr_ate_m", 0.0),
      f"known map not below half of DR: {k}")
with open(tum, encoding="utf-8") as f:
    check(sum(1 for _ in f) == k.get("frames", -1), "known_map_bound --out: one pose per frame")
check(known_map(ds, "--json").stdout == p.stdout, "known_map_bound not deterministic")
shifted = os.path.join(work, "shifted_map")
shutil.copytree(ds, shifted)
with open(os.path.join(ds, "sim_landmarks.csv"), encoding="utf-8") as f, \
        open(os.path.join(shifted, "sim_landmarks.csv"), "w", encoding="utf-8") as out:
    for line in f:
        if not line.startswith("#"):
            i, x, rest = line.split(",", 2)
            line = f"{i},{float(x) + 0.5},{rest}"
        out.write(line)
p = known_map(shifted, "--json")
k2 = json.loads(p.stdout) if p.returncode == 0 else {}
check(k2.get("known_map_ate_m", 0.0) > 0.3, f"displaced map still accurate: {k2}")
os.remove(os.path.join(shifted, "sim_landmarks.csv"))
p = known_map(shifted)
check(p.returncode == 1 and "sim_landmarks.csv" in p.stderr, f"no landmarks: {p.returncode}")
shutil.copy(os.path.join(ds, "sim_landmarks.csv"), shifted)
with open(os.path.join(ds, "sensors.yaml"), encoding="utf-8") as f:
    text = f.read()


def check_bad_sensors(tool, sensors_text, key):
    """The tool on `shifted` with this sensors.yaml exits 1 and names the key."""
    with open(os.path.join(shifted, "sensors.yaml"), "w", encoding="utf-8") as f:
        f.write(sensors_text)
    r = tool(shifted)
    check(r.returncode == 1 and f"'{key}'" in r.stderr, f"bad {key}: {r.returncode} {r.stderr}")


check_bad_sensors(known_map, re.sub(r"^(\s*)fx:.*$", r"\1fx: fast", text, count=1, flags=re.M),
                  "fx")
check_bad_sensors(known_map, re.sub(r"T_body_cam:\s*\[\s*[^,\]]+", "T_body_cam: [x", text, count=1),
                  "T_body_cam")
p = known_map(ds, "--particles", "5")
check(p.returncode == 2, f"too few particles: exit {p.returncode}")

# full_slam_bound.py: smoothing the whole default-room run from the truth is far better than dead
# reckoning, and started from dead reckoning it reaches the same optimum (so the solver converges
# and uses the observations); its cost's gradient is the finite-difference one; bad input is named.


def full_slam(dataset, *args):
    return bound_tool("full_slam_bound.py", dataset, *args)


tum = os.path.join(work, "full_slam.tum")
p, f_truth = bound_json(full_slam, tum)
check(0.0 <= f_truth.get("full_slam_ate_m", 1.0) < 0.5 * f_truth.get("dr_ate_m", 0.0),
      f"full SLAM from the truth not below half of DR: {f_truth}")
check(0.0 < f_truth.get("smoothing_sd_m", 0.0) <= f_truth.get("filtering_sd_m", 0.0) <
      0.5 * f_truth.get("dr_ate_m", 0.0) and
      f_truth.get("full_slam_ate_m", 1.0) < 3.0 * f_truth.get("smoothing_sd_m", 0.0),
      f"full SLAM std. devs. not ordered or not consistent with its error: {f_truth}")
with open(tum, encoding="utf-8") as f:
    check(sum(1 for _ in f) == f_truth.get("frames", -1),
          "full_slam_bound --out: one pose per frame")
check(full_slam(ds, "--json", "--out", tum).stdout == p.stdout, "full_slam_bound not deterministic")
p = full_slam(ds, "--json", "--start", "dr")
f_dr = json.loads(p.stdout) if p.returncode == 0 else {}
check(f_dr.get("full_slam_ate_m", 1.0) < 0.5 * f_dr.get("dr_ate_m", 0.0) and
      abs(f_dr.get("full_slam_ate_m", 1.0) - f_truth.get("full_slam_ate_m", 0.0)) < 0.01,
      f"full SLAM from dead reckoning {f_dr} does not reach the optimum from the truth {f_truth}")
rng = np.random.default_rng(5)


def check_gradient(problem, label, selections):
    """The cost's analytic gradient against central differences along random directions within
    each (name, slice) of the unknowns."""
    _, _, grad = problem.cost(problem.x, True)
    for name, sel in selections:
        v = np.zeros(len(problem.x))
        v[sel] = rng.normal(0.0, 1.0, v[sel].shape)
        v /= np.linalg.norm(v)
        eps = 1e-6
        numeric = (problem.cost(problem.x + eps * v)[0] -
                   problem.cost(problem.x - eps * v)[0]) / (2 * eps)
        analytic = 2.0 * float(grad @ v)
        check(abs(numeric - analytic) <= 1e-4 * abs(analytic) + 1e-3,
              f"{label} gradient along {name}: analytic {analytic}, numeric {numeric}")


fs, _ = full_slam_bound.problem(ds, "dr")
npose = 4 * fs.n
check_gradient(fs, "full_slam_bound", (("poses", slice(0, npose)),
                                       ("landmarks", slice(npose, len(fs.x))),
                                       ("all", slice(0, len(fs.x)))))

# Given the data so far, the last frame is known as well as given all of it, and no frame better.
fv = full_slam_bound.filtering_variances(fs)
sv = full_slam_bound.smoothing_variances(fs)
check(len(fv) == len(sv) == fs.n - 1 and abs(fv[-1] - sv[-1]) <= 1e-6 * sv[-1] and
      bool(np.all(fv >= sv * (1 - 1e-6))),
      f"filtering variances {fv[-3:]} against smoothing {sv[-3:]}")

# --wheel-heading: the wheels' turn as a second heading measurement, with the wheels' heading scale
# and drift as two more unknowns. Its gradient (along them too) is the numerical one, the two
# variances stay ordered, and more data leave no frame less known than without it.
fw, _ = full_slam_bound.problem(ds, "dr", wheel=True)
check(len(fw.x) == len(fs.x) + 2, f"--wheel-heading: {len(fw.x)} unknowns against {len(fs.x)} + 2")
fw.x[-2:] = (0.03, -0.02)
check_gradient(fw, "--wheel-heading", (("the wheel calibration", slice(len(fw.x) - 2, len(fw.x))),
                                       ("all", slice(0, len(fw.x)))))
fw.x[-2:] = 0.0
fwv = full_slam_bound.filtering_variances(fw)
swv = full_slam_bound.smoothing_variances(fw)
check(bool(np.all(fwv >= swv * (1 - 1e-6))) and bool(np.all(fwv <= fv * (1 + 1e-6))) and
      bool(np.all(swv <= sv * (1 + 1e-6))) and float(np.mean(fwv)) < float(np.mean(fv)),
      f"--wheel-heading variances: filtering {fwv[-3:]} (without {fv[-3:]}), smoothing "
      f"{swv[-3:]} (without {sv[-3:]})")
p = full_slam(ds, "--json", "--wheel-heading")
f_wheel = json.loads(p.stdout) if p.returncode == 0 else {}
check(0.0 < f_wheel.get("filtering_sd_m", 0.0) <= f_truth.get("filtering_sd_m", 0.0),
      f"--wheel-heading filtering std. dev. {f_wheel} above the gyro's {f_truth}")

shutil.rmtree(shifted)
shutil.copytree(ds, shifted)
os.remove(os.path.join(shifted, "sim_landmarks.csv"))
p = full_slam(shifted)
check(p.returncode == 1 and "sim_landmarks.csv" in p.stderr,
      f"full SLAM no landmarks: {p.returncode}")
shutil.copy(os.path.join(ds, "sim_landmarks.csv"), shifted)
check_bad_sensors(full_slam, re.sub(r"distortion:.*", "distortion: [0.1, 0.0, 0.0, 0.0]", text,
                                    count=1), "distortion")
p = full_slam(ds, "--iterations", "0")
check(p.returncode == 2, f"full SLAM no iterations: exit {p.returncode}")

transcript.close()
if failures:
    print(f"{len(failures)} failure(s):", *failures, sep="\n  ", file=sys.stderr)
    with open(transcript_path, encoding="utf-8") as f:
        tail = f.readlines()[-150:]
    print(f"the tools' output, last {len(tail)} lines of {transcript_path}:", file=sys.stderr)
    sys.stderr.writelines(tail)
else:
    print(f"all checks passed; the tools' output is in {transcript_path}", file=sys.stderr)
sys.exit(1 if failures else 0)
