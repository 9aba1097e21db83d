#!/usr/bin/python3
"""What the sensors allow with a perfect map: a particle filter localizing against the simulator's
true landmarks, as a reference for a SLAM run's ATE.

  tools/eval/known_map_bound.py DATASET RUN [--particles N] [--seed S] [--out FILE.tum] [--json]

DATASET is a simulated dataset folder (groundtruth.csv, encoders.csv, gyro.csv, features.csv,
sensors.yaml and sim_landmarks.csv, whose ids are the features' track ids); RUN holds
dead_reckoning.tum (cleanslam-replay --out), the reference. The filter starts at the ground
truth's first pose, moves its particles with the encoders' distance and the gyro's turn (with a
gyro bias taken while the wheels stand still, and per particle a distance scale error, a residual
gyro bias, a gyro scale error and white heading noise from sensors.yaml) and weighs them at every
frame with features by the pixel likelihood of the true landmarks (pixel_noise, robust to
outliers), resampling when the effective sample size falls below half. It shares no code with the
estimator.

Prints the dead reckoner's ATE (as cleanslam-eval --align none: relative to its first pose) and
the filter's ATE in the world frame (it knows the map, so it knows the frame), at the frames with
features, in metres; --out writes the filter's poses there (TUM). A SLAM estimator that builds
its own map cannot beat the bound by much; one far above it loses accuracy in its estimator, not
in its sensors. Exit status 1 when a file is missing or malformed, 2 on bad arguments."""

import argparse
import json
import math
import os
import sys
import warnings

import numpy as np
import yaml

import sighting_bound
from cleanslam_eval import trajectory

# Spread added to resampled particles (metres, radians): less lets the filter lose the truth on
# long single-landmark passes (seed 6 of sparse-poor-odometry with 0.003 m, 0.002 rad).
ROUGH_M = 0.02
ROUGH_RAD = 0.01
ESS_FRAC = 0.5


def load_csv(path, cols):
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # an empty file: reported below
            a = np.loadtxt(path, delimiter=",", comments="#", ndmin=2)
    except (OSError, ValueError) as e:
        raise ValueError(f"{path}: {e}") from None
    if a.size == 0:
        raise ValueError(f"{path}: no data rows")
    if a.shape[1] < cols:
        raise ValueError(f"{path}: expected {cols} comma-separated columns, got {a.shape[1]}")
    return a


def section(cal, name, path):
    s = cal.get(name)
    if not isinstance(s, dict):
        raise ValueError(f"{path}: no '{name}' section")
    return s


def is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def number(sec, key, path, default=None):
    v = sec.get(key, default)
    if not is_number(v):
        raise ValueError(f"{path}: '{key}' must be a number, got {v!r}")
    return float(v)


def numbers(sec, key, path, count, default=None):
    v = sec.get(key, default)
    if not isinstance(v, list) or len(v) != count or not all(is_number(e) for e in v):
        raise ValueError(f"{path}: '{key}' must be a list of {count} numbers, got {v!r}")
    return [float(e) for e in v]


class Camera:
    def __init__(self, sec, path):
        self.fx, self.fy = number(sec, "fx", path), number(sec, "fy", path)
        self.cx, self.cy = number(sec, "cx", path), number(sec, "cy", path)
        self.k1, self.k2, self.p1, self.p2 = numbers(sec, "distortion", path, 4, [0.0] * 4)
        t = np.array(numbers(sec, "T_body_cam", path, 16)).reshape(4, 4)  # row-major
        self.R_bc, self.t_bc = t[:3, :3], t[:3, 3]
        self.noise = number(sec, "pixel_noise", path, 0.5)

    def project(self, p_b):
        """Pixels of body-frame points (N, 3); in_front False where behind the camera."""
        p_c = (p_b - self.t_bc) @ self.R_bc  # R_bc^T (p_b - t_bc), row-wise
        z = p_c[:, 2]
        in_front = z > 0.05
        z = np.where(in_front, z, 1.0)
        x, y = p_c[:, 0] / z, p_c[:, 1] / z
        r2 = x * x + y * y
        radial = 1.0 + self.k1 * r2 + self.k2 * r2 * r2
        xd = x * radial + 2.0 * self.p1 * x * y + self.p2 * (r2 + 2.0 * x * x)
        yd = y * radial + self.p1 * (r2 + 2.0 * y * y) + 2.0 * self.p2 * x * y
        return self.fx * xd + self.cx, self.fy * yd + self.cy, in_front


def yaw_of_row(r):
    return sighting_bound.yaw_of(r[4], r[5], r[6], r[7])


def standstill_bias(enc, gyro_t, gyro_cum, window):
    """Per encoder interval: standing still (no tick for `window` intervals) and the gyro bias
    averaged over the still intervals so far (0 before the first)."""
    ticks = np.abs(np.diff(enc[:, 1:3].astype(np.int64), axis=0)).sum(axis=1)
    still = np.zeros(len(enc), dtype=bool)
    bias = np.zeros(len(enc))
    run = 0
    b = 0.0
    n = 0
    for k in range(1, len(enc)):
        run = run + 1 if ticks[k - 1] == 0 else 0
        still[k] = run >= window
        dt = (enc[k, 0] - enc[k - 1, 0]) * 1e-9
        if still[k] and dt > 0.0:
            rate = (np.interp(enc[k, 0], gyro_t, gyro_cum) -
                    np.interp(enc[k - 1, 0], gyro_t, gyro_cum)) / dt
            n = min(n + 1, 400)
            b += (rate - b) / n
        bias[k] = b
    return still, bias


class Odometry:
    """A dataset's encoders and gyro. Per encoder interval k (sample k-1 to k): the distance
    travelled, whether the wheels stand still, and the gyro bias taken while still so far; the
    gyro's integral between any two times."""

    def __init__(self, dataset, sen):
        self.enc = load_csv(os.path.join(dataset, "encoders.csv"), 3)
        gyr = load_csv(os.path.join(dataset, "gyro.csv"), 2)
        self.gyro_t = gyr[:, 0]
        self.gyro_cum = np.concatenate([[0.0], np.cumsum(gyr[1:, 1] * np.diff(self.gyro_t) * 1e-9)])
        self.still, self.bias_hat = standstill_bias(self.enc, self.gyro_t, self.gyro_cum, 20)
        ticks = self.enc[:, 1:3].astype(np.int64)
        d = (np.diff(ticks, axis=0) + 2**31) % 2**32 - 2**31
        # Per interval, each wheel's distance (0 before the first sample) and the body's.
        self.left = np.concatenate([[0.0], d[:, 0] / sen.tpm_l])
        self.right = np.concatenate([[0.0], d[:, 1] / sen.tpm_r])
        self.dist = 0.5 * (self.left + self.right)
        self.t = self.enc[:, 0]

    def turn(self, t0, t1):
        """Integrated gyro rate from t0 to t1 (ns), radians."""
        return float(np.interp(t1, self.gyro_t, self.gyro_cum) -
                     np.interp(t0, self.gyro_t, self.gyro_cum))


class Sensors:
    """The calibration of sensors.yaml that the bounds use; errors name the file and key."""

    def __init__(self, dataset):
        path = os.path.join(dataset, "sensors.yaml")
        try:
            with open(path, encoding="utf-8") as f:
                cal = yaml.safe_load(f)
        except (OSError, yaml.YAMLError) as e:
            raise ValueError(f"{path}: {e}") from None
        if not isinstance(cal, dict):
            raise ValueError(f"{path}: not a mapping")
        self.cam = Camera(section(cal, "camera", path), path)
        wheels = section(cal, "wheels", path)
        gyro = section(cal, "gyro", path)
        self.tpm_l = number(wheels, "ticks_per_meter_left", path)
        self.tpm_r = number(wheels, "ticks_per_meter_right", path)
        self.distance_noise = number(wheels, "distance_noise", path, 0.02)
        self.wheel_base = number(wheels, "wheel_base", path, 0.0)
        self.density = number(gyro, "noise_density", path)
        self.bias_sd = number(gyro, "bias_instability", path, 1e-4)
        self.bias_walk = number(gyro, "bias_walk", path, 0.0)
        self.gyro_scale_sd = number(gyro, "scale_error", path, 0.0)


def localize(dataset, particles=5000, seed=1, progress=None):
    sen = Sensors(dataset)
    cam = sen.cam
    gt = load_csv(os.path.join(dataset, "groundtruth.csv"), 8)
    odo = Odometry(dataset, sen)
    feats = load_csv(os.path.join(dataset, "features.csv"), 4)
    lms = load_csv(os.path.join(dataset, "sim_landmarks.csv"), 4)
    landmark = {int(r[0]): r[1:4] for r in lms}

    rng = np.random.default_rng(seed)
    n = particles
    x = np.full(n, gt[0, 1])
    y = np.full(n, gt[0, 2])
    yaw = np.full(n, yaw_of_row(gt[0]))
    scale = 1.0 + rng.normal(0.0, sen.distance_noise, n)
    bias = rng.normal(0.0, sen.bias_sd, n)
    gyro_scale = 1.0 + rng.normal(0.0, sen.gyro_scale_sd, n)

    frame_t = feats[:, 0]
    fi = 0
    out = []
    for k in range(1, len(odo.t)):
        t0, t1 = odo.t[k - 1], odo.t[k]
        dt = (t1 - t0) * 1e-9
        if odo.still[k]:
            turn = np.zeros(n)
        else:
            turn = ((odo.turn(t0, t1) - (odo.bias_hat[k] + bias) * dt) * gyro_scale +
                    rng.normal(0.0, sen.density * math.sqrt(dt), n))
            bias = bias + rng.normal(0.0, sen.bias_walk * math.sqrt(dt), n)
        step = odo.dist[k] * scale
        mid = yaw + 0.5 * turn
        x += step * np.cos(mid)
        y += step * np.sin(mid)
        yaw += turn
        while fi < len(frame_t) and frame_t[fi] <= t1:
            tf = frame_t[fi]
            logw = np.zeros(n)
            c, s = np.cos(yaw), np.sin(yaw)
            while fi < len(frame_t) and frame_t[fi] == tf:
                tid, u, v = int(feats[fi, 1]), feats[fi, 2], feats[fi, 3]
                fi += 1
                if tid not in landmark:
                    continue
                lx, ly, lz = landmark[tid]
                rx, ry = lx - x, ly - y
                p_b = np.stack([c * rx + s * ry, -s * rx + c * ry, np.full(n, lz)], axis=1)
                pu, pv, ok = cam.project(p_b)
                r2 = ((pu - u) ** 2 + (pv - v) ** 2) / (cam.noise * cam.noise)
                logw += np.where(ok, -0.5 * np.minimum(r2, 50.0), -40.0)
            w = np.exp(logw - logw.max())
            w /= w.sum()
            mean_yaw = math.atan2(float(w @ s), float(w @ c))
            out.append((tf * 1e-9, float(w @ x), float(w @ y), mean_yaw))
            if 1.0 / float(w @ w) < ESS_FRAC * n:
                idx = np.minimum(np.searchsorted(np.cumsum(w), (rng.random() + np.arange(n)) / n),
                                 n - 1)
                x = x[idx] + rng.normal(0.0, ROUGH_M, n)
                y = y[idx] + rng.normal(0.0, ROUGH_M, n)
                yaw = yaw[idx] + rng.normal(0.0, ROUGH_RAD, n)
                scale, bias, gyro_scale = scale[idx], bias[idx], gyro_scale[idx]
        if progress is not None and k % 2000 == 0:
            progress(k, len(odo.t))
    if not out:
        raise ValueError(f"{dataset}/features.csv: no frame within the encoder samples")
    return out


def world_ate(dataset, poses):
    truth = trajectory.PlanarTruth(
        trajectory.read_groundtruth(os.path.join(dataset, "groundtruth.csv")))
    sq = 0.0
    for t, x, y, _ in poses:
        gx, gy, _ = truth.at(t)
        sq += (x - gx) ** 2 + (y - gy) ** 2
    return math.sqrt(sq / len(poses))


def write_tum(path, poses):
    """Planar poses (t_s, x, y, yaw) as TUM lines."""
    with open(path, "w", encoding="utf-8") as f:
        for t, x, y, yaw in poses:
            f.write(f"{t:.9f} {x:.6f} {y:.6f} 0 0 0 {math.sin(yaw / 2):.9f} "
                    f"{math.cos(yaw / 2):.9f}\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dataset")
    ap.add_argument("run")
    ap.add_argument("--particles", type=int, default=5000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", help="write the filter's poses here (TUM)")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    if a.particles < 10:
        print("known_map_bound: --particles must be at least 10", file=sys.stderr)
        return 2

    def progress(k, total):
        print(f"known_map_bound: {100 * k // total}% of the encoder samples", file=sys.stderr)

    try:
        poses = localize(a.dataset, a.particles, a.seed, None if a.json else progress)
        dr = sighting_bound.bound(a.dataset, a.run)
    except (OSError, ValueError) as e:
        print(f"known_map_bound: {e}", file=sys.stderr)
        return 1
    r = {"frames": len(poses), "dr_ate_m": dr["dr_ate_m"],
         "known_map_ate_m": world_ate(a.dataset, poses)}
    if a.out:
        write_tum(a.out, poses)
    if a.json:
        print(json.dumps(r))
    else:
        print(f"{r['frames']} frames with features: DR ATE {r['dr_ate_m']:.3f} m, "
              f"particle filter on the true map {r['known_map_ate_m']:.3f} m")
    return 0


if __name__ == "__main__":
    sys.exit(main())
