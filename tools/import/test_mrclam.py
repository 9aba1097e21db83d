#!/usr/bin/python3
"""tools/import/mrclam.py on a small MRCLAM-format recording this test writes itself (a robot that
drives exactly as commanded, bearings computed from its track): pixels, frames, dropped sightings,
encoder ticks, both gyros, ground truth, landmarks and the calibration's figures; malformed input
names the file and line; a non-empty OUT_DIR is left alone without --force; cleanslam-replay reads
the result. Arguments: BIN_DIR WORK_DIR."""

import math
import os
import re
import shutil
import subprocess
import sys

import mrclam
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))

bin_dir, work = sys.argv[1], sys.argv[2]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print(f"FAIL: {what}", file=sys.stderr)


T0 = 1248444175.0
HEAD = "# UTIAS Multi-Robot Cooperative Localization and Mapping Dataset\n# Format\n"
LANDMARKS = {6: (3.0, 0.5), 7: (2.0, 2.5), 8: (-1.0, 2.0), 9: (0.5, -2.0)}
BARCODES = {1: 5, 2: 14, 6: 63, 7: 81, 8: 7, 9: 70}


def command(t):
    """(v, w) at t seconds after T0: still, straight, a left turn, straight, still."""
    s = t - T0
    if s < 2.0 or s > 40.0:
        return 0.0, 0.0
    if 10.0 <= s < 20.0:
        return 0.1, 0.3
    return 0.1, 0.0


def write(folder, robot=1, odometry_extra="", bad_time=False, lag=0.0, turn=1.0, dist=1.0,
          yaw=0.0):
    """The track executes each command lag s late, turn x its turn and dist x its distance; the
    camera is turned by yaw."""
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "Barcodes.dat"), "w") as f:
        f.write(HEAD + "".join(f"  {s} \t {c}\n" for s, c in BARCODES.items()))
    with open(os.path.join(folder, "Landmark_Groundtruth.dat"), "w") as f:
        f.write(HEAD + "".join(f"  {s} \t {x:.8f} \t {y:.8f} \t 0.0001 \t 0.0001\n"
                               for s, (x, y) in LANDMARKS.items()))
    # Odometry at about 67 Hz (uneven), one repeated stamp as in the published files.
    t_odo = T0 + 0.5 + np.cumsum(np.where(np.arange(3000) % 3 == 0, 0.02, 0.0145))
    t_odo = t_odo[t_odo < T0 + 44.0]
    rows = [f"{t:.3f} \t {command(t)[0]:.3f} \t {command(t)[1]:.3f}\n" for t in t_odo]
    rows.insert(100, rows[100])
    if bad_time:
        rows[200], rows[201] = rows[201], rows[200]
    with open(os.path.join(folder, f"Robot{robot}_Odometry.dat"), "w") as f:
        f.write(HEAD + "".join(rows[:5]) + odometry_extra + "".join(rows[5:]))
    # The exact track of those commands (each held until the next) at 100 Hz.
    t_odo = np.round(t_odo, 3)
    dt = 0.001
    tt = np.arange(T0, T0 + 45.0, dt)
    vw = np.array([command(t_odo[max(0, np.searchsorted(t_odo, t - lag, side="right") - 1)])
                   if t - lag >= t_odo[0] else (0.0, 0.0) for t in tt]) * [dist, turn]
    th = 0.3 + np.concatenate([[0.0], np.cumsum(vw[:-1, 1] * dt)])
    x = np.concatenate([[0.0], np.cumsum(vw[:-1, 0] * np.cos(th[:-1] + 0.5 * vw[:-1, 1] * dt)
                                         * dt)])
    y = np.concatenate([[0.0], np.cumsum(vw[:-1, 0] * np.sin(th[:-1] + 0.5 * vw[:-1, 1] * dt)
                                         * dt)])
    gt = [(tt[k], x[k], y[k], math.remainder(th[k], 2 * math.pi)) for k in range(0, len(tt), 10)]
    with open(os.path.join(folder, f"Robot{robot}_Groundtruth.dat"), "w") as f:
        f.write(HEAD + "".join(f"{t:.3f} \t {a:.8f} \t {b:.8f} \t {c:.5f}\n" for t, a, b, c in gt))
    # Images every 0.235 s; the bearing of every landmark in front; one image split by 1 ms, a
    # sighting of robot 2, an unknown barcode, a landmark out of the field of view.
    meas = []
    for k, t in enumerate(np.arange(T0 + 1.0, T0 + 43.0, 0.235)):
        i = int(round((t - T0) / dt))
        for s, (lx, ly) in LANDMARKS.items():
            b = math.remainder(math.atan2(ly - y[i], lx - x[i]) - th[i] - yaw, 2 * math.pi)
            if abs(b) < 0.6:
                stamp = t + (0.001 if k == 7 and s == 8 else 0.0)
                meas.append((stamp, BARCODES[s], math.hypot(lx - x[i], ly - y[i]), b))
        if k == 3:
            meas.append((t, 14, 2.0, 0.1))
        if k == 4:
            meas.append((t, 99, 2.0, 0.1))
        if k == 5:
            meas.append((t, 63, 2.0, 0.8))
    meas.sort(key=lambda r: r[0])
    with open(os.path.join(folder, f"Robot{robot}_Measurement.dat"), "w") as f:
        f.write(HEAD + "".join(f"{t:.3f} \t {c} \t {r:.3f} \t {b:.4f}\n" for t, c, r, b in meas))
    return t_odo, (tt, x, y, th), meas


def importer(*args):
    return subprocess.run([sys.executable, os.path.join(HERE, "mrclam.py"), *args],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, check=False)


def csv(path):
    return np.loadtxt(path, delimiter=",", comments="#", ndmin=2)


src = os.path.join(work, "mrclam")
t_odo, (tt, x, y, th), meas = write(src)
out = os.path.join(work, "commanded")
p = importer(src, "1", out)
check(p.returncode == 0, f"import exit status {p.returncode}: {p.stderr}")
check("1 other robots, 1 unknown barcode" in p.stderr, f"dropped sightings reported: {p.stderr}")
check("1 outside the field of view" in p.stderr, "the sighting at 0.8 rad is outside the image")

# Features: pixel column of the bearing, middle row, track id = subject, frames >= 0.45 s apart.
f = csv(os.path.join(out, "features.csv"))
t_frames = np.unique(f[:, 0])
check(len(t_frames) > 30, f"{len(t_frames)} frames")
check(np.all(np.diff(t_frames) >= 0.45e9 - 1), "frames at least 0.45 s apart")
check(set(f[:, 1].astype(int)) <= set(LANDMARKS), f"track ids are subjects: {set(f[:, 1])}")
check(np.all(f[:, 3] == 119.5), "the middle row")
origin = math.floor(min(t_odo[0], tt[0])) - 1.0
subject_of = {c: s for s, c in BARCODES.items()}
by_key = {(round((t - origin) * 1e3), subject_of.get(c)): round(b, 4) for t, c, _, b in meas}
matched = 0
for t_ns, s, u, _ in f:
    b = by_key.get((round(t_ns * 1e-6), int(s)))
    if b is not None:
        matched += 1
        check(abs(u - (159.5 - 220.0 * math.tan(b))) < 1e-9, f"pixel of {s} at {t_ns}: {u}")
check(matched == len(f), f"every feature is a sighting at its own stamp: {matched}/{len(f)}")
# Sightings 1 ms apart are one image, stamped with the first; a landmark twice keeps the first.
imgs, repeated = mrclam.images([(10.0, 6, 1.0), (10.001, 8, 2.0), (10.001, 6, 3.0),
                                (10.235, 6, 4.0)])
check(imgs == [(10.0, {6: 1.0, 8: 2.0}), (10.235, {6: 4.0})] and repeated == 1,
      f"images: {imgs}, {repeated}")
# Of images 0.235 s apart, the set at least 0.45 s apart with the most sightings.
imgs = [(0.0, {6: 0}), (0.235, {6: 0, 7: 0, 8: 0}), (0.47, {6: 0}), (0.705, {6: 0}),
        (0.94, {6: 0, 7: 0})]
chosen = [i[0] for i in mrclam.frames(imgs)]
check(chosen == [0.235, 0.94], f"frames chosen: {chosen}")
check(len(f) >= 0.45 * sum(1 for m in meas if m[1] in (63, 81, 7, 70) and abs(m[3]) < 0.6),
      f"frames keep about half of the sightings or more: {len(f)}")

# Encoders: cumulative ticks of the commanded wheel distances at 4000 per metre, 20 Hz.
e = csv(os.path.join(out, "encoders.csv"))
check(np.allclose(np.diff(e[:, 0]), 50e6, atol=1e3), "encoders at 20 Hz")
dist = 0.1 * 38.0  # 38 s at 0.1 m/s
turn = 0.3 * 10.0
left, right = e[-1, 1] - e[0, 1], e[-1, 2] - e[0, 2]
check(abs((left + right) / 2 / 4000 - dist) < 0.01, f"distance {(left + right) / 8000} m")
check(abs((right - left) / 4000 / 0.235 - turn) < 0.01, f"turn {(right - left) / 940} rad")

# Gyro commanded: the commanded rate at 100 Hz.
g = csv(os.path.join(out, "gyro.csv"))
check(np.allclose(np.diff(g[:, 0]), 10e6, atol=1e3), "gyro at 100 Hz")
check(abs(np.sum(g[:, 1]) * 0.01 - turn) < 0.01, f"commanded gyro turn {np.sum(g[:, 1]) * 0.01}")
check(np.all((g[:, 1] > -1e-9) & (g[:, 1] < 0.3 + 1e-9)), "commanded rates within [0, 0.3]")

# Ground truth, landmarks.
gt = csv(os.path.join(out, "groundtruth.csv"))
yaw = 2 * np.arctan2(gt[:, 7], gt[:, 4])
check(np.allclose(np.cos(yaw), np.cos(np.interp((gt[:, 0] * 1e-9 + origin), tt, th)), atol=1e-3),
      "groundtruth.csv's yaw is the Vicon heading")
lm = csv(os.path.join(out, "sim_landmarks.csv"))
check(sorted(lm[:, 0].astype(int).tolist()) == sorted(LANDMARKS), "sim_landmarks.csv ids")
check(all(np.allclose(r[1:3], LANDMARKS[int(r[0])]) and r[3] == 0 for r in lm),
      "sim_landmarks.csv positions")

# The calibration of an exact recording: no lag, unit scales, no noise.
p = importer(src, "1", "--calibrate")
check(p.returncode == 0, f"--calibrate: {p.stderr}")
print(p.stdout, end="")
check("commands lag the motion by 0.00 s" in p.stdout, "no lag")
check("1.000 x the commanded turn and 1.000 x the commanded distance" in p.stdout, "unit scales")
spread = re.search(r"spread ([0-9.]+) mrad", p.stdout)
check(spread is not None and float(spread.group(1)) <= 0.1, "bearings exact to their rounding")
yaml_text = open(os.path.join(out, "sensors.yaml")).read()
check("# - lag: the delay of the commands" in yaml_text, "the method in sensors.yaml's comments")

# A robot that executes its commands 0.2 s late, turns 0.85 x and travels 0.9 x what it is
# commanded, its camera turned by 0.02 rad: the calibration measures it and sensors.yaml states it.
cal_src = os.path.join(work, "mrclam_cal")
write(cal_src, lag=0.2, turn=0.85, dist=0.9, yaw=0.02)
p = importer(cal_src, "1", "--calibrate")
check("commands lag the motion by 0.20 s" in p.stdout, f"lag measured: {p.stdout}")
check("0.850 x the commanded turn and 0.900 x the commanded distance" in p.stdout,
      f"scales measured: {p.stdout}")
check("median error -20.0 mrad" in p.stdout, f"the camera's yaw measured: {p.stdout}")
p = importer(cal_src, "1", os.path.join(work, "cal"))
cal_yaml = open(os.path.join(work, "cal", "sensors.yaml")).read()
for key, value in [("time_offset_s", -0.2), ("ticks_per_meter_left", 4000 / 0.9),
                   ("wheel_base", 0.235 * 0.9 / 0.85), ("pixel_noise", 0.1)]:
    m = re.search(rf"{key}: ([-0-9.]+)", cal_yaml)
    check(m is not None and abs(float(m.group(1)) - value) < 2e-3 * max(1.0, abs(value)),
          f"sensors.yaml {key}: {m and m.group(1)}, expected {value:.4f}")
body_cam = re.search(r"T_body_cam:\s*\[([^\]]*)\]", cal_yaml)
R = np.array([float(v) for v in body_cam.group(1).split(",")]).reshape(4, 4)[:3, :3]
check(abs(math.atan2(R[1, 2], R[0, 2]) - 0.02) < 1e-3, "T_body_cam turned by the camera's yaw")
check(np.abs(R.T @ R - np.eye(3)).max() < 1e-12, "T_body_cam exactly orthonormal")
ce = csv(os.path.join(work, "cal", "encoders.csv"))
cg = csv(os.path.join(work, "cal", "gyro.csv"))
check(abs(np.sum(cg[:, 1]) * 0.01 - 0.85 * 3.0) < 0.02, "the commanded gyro times the turn scale")
check(abs((ce[-1, 1] + ce[-1, 2]) / 2 / (4000 / 0.9) - 0.9 * 3.8) < 0.01,
      "encoder ticks over ticks_per_meter: the travelled distance")

# The mems gyro: the Vicon rate with the drawn errors; the seed decides them.
p = importer(src, "1", os.path.join(work, "mems1"), "--gyro", "mems", "--seed", "5")
check(p.returncode == 0, f"--gyro mems: {p.stderr}")
g1 = csv(os.path.join(work, "mems1", "gyro.csv"))
t_g1 = g1[:, 0] * 1e-9 + origin
still = (t_g1 > T0 + 41.0) | (t_g1 < T0 + 2.0)  # Vicon shows the robot still before T0 + 0.5
bias = float(np.mean(g1[still, 1]))
drawn = re.search(r"drawn: bias ([-+0-9.]+) mrad/s",
                  open(os.path.join(work, "mems1", "sensors.yaml")).read())
check(drawn is not None and 2.0 <= abs(float(drawn.group(1))) <= 4.0, "drawn bias stated")
check(drawn is not None and abs(bias - float(drawn.group(1)) * 1e-3) < 4 * 0.05 / math.sqrt(
    np.sum(still)), f"mems bias {bias}: the drawn one plus the noise's mean")
check(0.03 < np.std(g1[still, 1]) < 0.07, f"mems noise {np.std(g1[still, 1])} rad/s at 100 Hz")
check(abs(np.sum(g1[:, 1] - bias) * 0.01 - turn) < 0.1, "mems turn")
check("noise_density: 0.00500" in open(os.path.join(work, "mems1", "sensors.yaml")).read(),
      "mems noise density stated")
importer(src, "1", os.path.join(work, "mems2"), "--gyro", "mems", "--seed", "5")
importer(src, "1", os.path.join(work, "mems3"), "--gyro", "mems", "--seed", "6")
g2 = csv(os.path.join(work, "mems2", "gyro.csv"))
g3 = csv(os.path.join(work, "mems3", "gyro.csv"))
check(np.array_equal(g1, g2), "the same seed gives the same gyro")
check(not np.array_equal(g1, g3), "another seed another gyro")

# A non-empty OUT_DIR is left alone without --force.
before = open(os.path.join(out, "features.csv")).read()
p = importer(src, "1", out, "--gyro", "mems")
check(p.returncode == 1 and "not empty" in p.stderr, f"non-empty OUT_DIR: {p.stderr}")
check(open(os.path.join(out, "features.csv")).read() == before, "OUT_DIR untouched")
p = importer(src, "1", out, "--force")
check(p.returncode == 0, "--force replaces")

# Malformed input names the file and line.
for name, kwargs, expect in [
        ("text", {"odometry_extra": "1248444175.600 \t abc \t 0.0\n"},
         "Robot1_Odometry.dat:8: forward velocity: expected a finite number"),
        ("fields", {"odometry_extra": "1248444175.600 \t 0.1\n"},
         "Robot1_Odometry.dat:8: expected 3 fields"),
        ("order", {"bad_time": True}, "Robot1_Odometry.dat:204: time")]:
    bad = os.path.join(work, f"bad_{name}")
    write(bad, **kwargs)
    p = importer(bad, "1", os.path.join(work, f"out_{name}"))
    check(p.returncode == 1 and expect in p.stderr, f"{name}: expected '{expect}': {p.stderr}")
    check(not os.path.exists(os.path.join(work, f"out_{name}")), f"{name}: nothing written")
p = importer(src, "3", os.path.join(work, "out_missing"))
check(p.returncode == 1 and "Robot3_Odometry.dat" in p.stderr, f"missing robot: {p.stderr}")

# cleanslam-replay reads the dataset.
replay = os.path.join(bin_dir, "cleanslam-replay")
p = subprocess.run([replay, out, "--out", os.path.join(work, "run")], stdout=subprocess.PIPE,
                   stderr=subprocess.PIPE, text=True, check=False)
check(p.returncode == 0, f"cleanslam-replay: {p.stderr[-500:]}")
check(p.returncode != 0 or "warning" not in p.stderr.lower(), f"replay warnings: {p.stderr}")

if failures:
    print(f"{len(failures)} check(s) failed", file=sys.stderr)
    sys.exit(1)
print("mrclam import: all checks passed")
