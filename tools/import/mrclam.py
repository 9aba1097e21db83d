#!/usr/bin/python3
"""One robot of a UTIAS MRCLAM dataset (Leung, Halpern, Barfoot, Liu, IJRR 30(8), 2011) as a
cleanslam dataset folder.

  tools/import/mrclam.py DATASET_DIR ROBOT OUT_DIR [--gyro commanded|mems] [--seed N] [--force]
  tools/import/mrclam.py DATASET_DIR ROBOT --calibrate

- features.csv: each identified landmark's bearing as the pixel column of a virtual pinhole camera
  (320 x 240, f = 220 px) at the body origin looking forward, on the middle row (the landmarks at
  the camera's height); track id = the landmark's subject number. Sightings of other robots, of
  barcodes that Barcodes.dat does not know and outside the image are dropped. Sightings stamped
  within 10 ms of each other are one camera image (stamped with its first sighting); of the
  images, the set at least 0.45 s apart with the most sightings is kept (the firmware takes at
  most 2 frames a second).
- encoders.csv (20 Hz): the commanded forward speed and turn rate, each held until the next
  command, integrated into wheel distances (wheel base 0.235 m) at 4000 ticks per metre.
- gyro.csv (100 Hz): --gyro commanded: the commanded turn rate (its mean over each interval);
  --gyro mems: the Vicon heading's rate with a constant bias (random sign, 2-4 mrad/s), a scale
  error (std. dev. 1 %) and white noise of 0.005 rad/s/sqrt(Hz), drawn with --seed.
- sensors.yaml: noise figures measured against the Vicon track (mrclam_calibration.py), the
  method in its comments; groundtruth.csv: the Vicon track; sim_landmarks.csv: the landmarks'
  surveyed positions (full_slam_bound.py's format).
--calibrate prints the measurement and writes nothing. Progress on stderr. Exit status 1 on a
missing or malformed input file (the error names file and line) or a non-empty OUT_DIR without
--force, 2 on bad arguments.
"""

import argparse
import math
import os
import shutil
import sys

import numpy as np

import mrclam_calibration as cal
from mrclam_files import InputError, Mrclam

WIDTH, HEIGHT, FOCAL_PX = 320, 240, 220.0
CX, CY = (WIDTH - 1) / 2.0, (HEIGHT - 1) / 2.0
WHEEL_BASE_M = 0.235
TICKS_PER_M = 4000.0
ENCODER_HZ, GYRO_HZ = 20, 100
FRAME_MIN_GAP_S = 0.45
IMAGE_SPAN_S = 0.010
ROBOTS = range(1, 6)  # subjects 1-5 are the robots
MEMS_DENSITY = 0.005
MEMS_BIAS_MIN, MEMS_BIAS_MAX, MEMS_BIAS_SD = 0.002, 0.004, 0.003
MEMS_SCALE_SD = 0.01


def log(msg):
    print(f"mrclam: {msg}", file=sys.stderr, flush=True)


STANDSTILL_M, STANDSTILL_RAD = 0.02, 0.02


def span(m):
    """Where both odometry and Vicon exist, from the start of Vicon when Vicon shows the robot
    standing still before the first command (no command is no motion)."""
    gt, first = m.groundtruth, m.odometry[0, 0]
    before = gt[gt[:, 0] <= first]
    still = len(before) > 1 and bool(
        np.all(np.hypot(before[:, 1] - before[0, 1], before[:, 2] - before[0, 2]) < STANDSTILL_M)
        and np.all(np.abs(cal.unwrapped_heading(before) - before[0, 3]) < STANDSTILL_RAD))
    return (gt[0, 0] if still else max(first, gt[0, 0]), min(m.odometry[-1, 0], gt[-1, 0]))


class Clock:
    """MRCLAM's Unix seconds to nanoseconds since a whole second at least 1 s before the start;
    vicon() for the Vicon instants, which are the commands' stamps plus the commands' lag."""

    def __init__(self, t0, lag):
        self.origin = math.floor(t0) - 1.0
        self.lag = lag

    def ns(self, t):
        return np.round((np.asarray(t, dtype=float) - self.origin) * 1e6).astype(np.int64) * 1000

    def vicon(self, t):
        return self.ns(np.asarray(t, dtype=float) - self.lag)


def encoders(m, t0, t1):
    grid = np.arange(t0, t1 + 1e-9, 1.0 / ENCODER_HZ)
    o = m.odometry
    half = 0.5 * WHEEL_BASE_M * o[:, 2]
    left = np.interp(grid, o[:, 0], cal.cumulative(o[:, 0], o[:, 1] - half))
    right = np.interp(grid, o[:, 0], cal.cumulative(o[:, 0], o[:, 1] + half))
    ticks = np.round(np.stack([left, right], axis=1) * TICKS_PER_M).astype(np.int64)
    return grid, ticks


def gyro(m, t0, t1, kind, rng, c):
    """Rates over each interval to the grid's stamps (the first one after t0), on the commands'
    clock, and the drawn errors of the mems gyro. The commanded one times the measured turn scale
    (a gyro's driver applies its calibrated scale factor); the mems one from the Vicon heading a
    lag later."""
    grid = np.arange(t0, t1 + 1e-9, 1.0 / GYRO_HZ)
    if kind == "commanded":
        o = m.odometry
        turn = np.interp(grid, o[:, 0], cal.cumulative(o[:, 0], o[:, 2]))
        return grid[1:], c["turn_scale"] * np.diff(turn) / np.diff(grid), {}
    heading = np.interp(grid + c["lag_s"], m.groundtruth[:, 0],
                        cal.unwrapped_heading(m.groundtruth))
    rate = np.diff(heading) / np.diff(grid)
    bias = float(rng.choice([-1.0, 1.0]) * rng.uniform(MEMS_BIAS_MIN, MEMS_BIAS_MAX))
    scale = float(rng.normal(0.0, MEMS_SCALE_SD))
    noise = rng.normal(0.0, MEMS_DENSITY * math.sqrt(GYRO_HZ), len(rate))
    return grid[1:], (1.0 + scale) * rate + bias + noise, {"bias_rad_s": bias, "scale": scale}


def sightings(m, t0, t1):
    """Landmark sightings (t, subject, u) in the camera, and the counts of what was dropped."""
    drop = {"other robots": 0, "unknown barcode": 0, "no surveyed position": 0,
            "outside the odometry and Vicon span": 0, "outside the field of view": 0}
    rows = []
    for t, code, _rng, bearing in m.sightings:
        subject = m.barcodes.get(int(code))
        if subject is None:
            drop["unknown barcode"] += 1
        elif subject in ROBOTS:
            drop["other robots"] += 1
        elif subject not in m.landmarks:
            drop["no surveyed position"] += 1
        elif not t0 <= t <= t1:
            drop["outside the odometry and Vicon span"] += 1
        elif abs(bearing) >= 0.5 * math.pi:
            drop["outside the field of view"] += 1
        else:
            u = CX - FOCAL_PX * math.tan(bearing)
            if -0.5 <= u <= WIDTH - 0.5:
                rows.append((t, subject, u))
            else:
                drop["outside the field of view"] += 1
    return rows, drop


def images(rows):
    """Sightings stamped within IMAGE_SPAN_S of an image's first one: [(t, {subject: u})]. A
    landmark seen twice in one image keeps its first sighting; returns the count of the others."""
    out, repeated = [], 0
    for t, subject, u in rows:
        if not out or t - out[-1][0] > IMAGE_SPAN_S:
            out.append((t, {}))
        if subject in out[-1][1]:
            repeated += 1
        else:
            out[-1][1][subject] = u
    return out, repeated


def frames(imgs):
    """The images at least FRAME_MIN_GAP_S apart with the most sightings (dynamic programming
    over the images in time order; ties keep the earlier images)."""
    n = len(imgs)
    t = np.array([i[0] for i in imgs])
    best = np.zeros(n + 1, dtype=np.int64)  # best[k]: most sightings among images[:k]
    take = np.zeros(n + 1, dtype=bool)
    prev = np.searchsorted(t, t - FRAME_MIN_GAP_S + 1e-9, side="right")
    for k in range(1, n + 1):
        with_k = best[prev[k - 1]] + len(imgs[k - 1][1])
        take[k] = with_k > best[k - 1]
        best[k] = with_k if take[k] else best[k - 1]
    chosen, k = [], n
    while k > 0:
        if take[k]:
            chosen.append(imgs[k - 1])
            k = prev[k - 1]
        else:
            k -= 1
    return chosen[::-1]


def body_cam(yaw):
    """T_body_cam of the forward-looking camera turned by yaw about the body's z axis."""
    cy, sy = math.cos(yaw), math.sin(yaw)
    rows = [[sy, 0.0, cy, 0.0], [-cy, 0.0, sy, 0.0], [0.0, -1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]]
    text = [", ".join(repr(v + 0.0) for v in r) for r in rows]  # exact: orthonormal to 1e-16
    return "[" + ",\n     ".join(text) + "]"


def sensors_yaml(c, kind, mems):
    density = MEMS_DENSITY if kind == "mems" else c["noise_density"]
    bias = MEMS_BIAS_SD if kind == "mems" else abs(c["rate_bias_rad_s"])
    scale = MEMS_SCALE_SD if kind == "mems" else c["turn_scale_sd"]
    pixel = max(0.1, c.get("bearing_sd_rad", 0.0) * FOCAL_PX)
    yaw = -c.get("bearing_bias_rad", 0.0)
    offset = c.get("camera_delay_s", 0.0) - c["lag_s"]
    ticks = TICKS_PER_M / c["distance_scale"]
    base = WHEEL_BASE_M * c["distance_scale"] / c["turn_scale"]
    method = "\n".join("# " + ln for ln in cal.__doc__.splitlines())
    measured = "\n".join("#   " + ln for ln in cal.describe(c, FOCAL_PX))
    gyro_note = (
        "# gyro: synthesized from the Vicon heading's rate with the errors stated below (drawn: "
        f"bias {mems['bias_rad_s'] * 1e3:+.2f} mrad/s, scale error {mems['scale'] * 100:+.2f} %)"
        if kind == "mems" else
        "# gyro: the commanded turn rate times the turn scale; noise_density, bias_instability "
        "(|mean rate error|)\n# and scale_error (the turn scale's std. dev. over each minute) as "
        "measured")
    return f"""# Imported from the UTIAS MRCLAM dataset by tools/import/mrclam.py (--gyro {kind}).
# Encoders: the commanded speed and turn rate integrated; camera: a virtual pinhole whose pixel
# column is the measured bearing (the landmarks at camera height).
# The noise figures below were measured on this robot's Vicon track:
{method}
# Measured:
{measured}
# Calibration: the dataset's clock is the commands' (a Vicon instant t is t - lag on it), so
# time_offset_s = camera delay - lag; T_body_cam turns the camera by minus the bearings' median
# error; pixel_noise: the bearings' spread times fx; ticks_per_meter: the importer's 4000 over
# the distance scale; wheel_base: the importer's 0.235 m times distance scale / turn scale;
# wheels.distance_noise as measured, scale_error the distance scale's std. dev. over each minute;
{gyro_note}
camera:
  width: {WIDTH}
  height: {HEIGHT}
  fx: {FOCAL_PX}
  fy: {FOCAL_PX}
  cx: {CX}
  cy: {CY}
  distortion: [0.0, 0.0, 0.0, 0.0]
  T_body_cam:
    {body_cam(yaw)}
  pixel_noise: {pixel:.3f}
  time_offset_s: {offset:.3f}
wheels:
  ticks_per_meter_left: {ticks:.2f}
  ticks_per_meter_right: {ticks:.2f}
  wheel_base: {base:.5f}
  distance_noise: {c['distance_noise']:.4f}
  scale_error: {max(c['distance_scale_sd'], 1e-4):.4f}
gyro:
  noise_density: {max(density, 1e-5):.5f}
  bias_instability: {bias:.5f}
  scale_error: {max(scale, 1e-4):.4f}
"""


def write_csv(path, header, rows):
    with open(path, "w", encoding="utf-8") as f:
        f.write(header + "\n")
        f.writelines(rows)


def landmark_sightings(m):
    return [r for r in m.sightings
            if m.barcodes.get(int(r[1])) in m.landmarks and m.barcodes[int(r[1])] not in ROBOTS]


def calibration(m, t0, t1):
    rows = [(r[0], m.barcodes[int(r[1])], r[2], r[3]) for r in landmark_sightings(m)]
    return cal.calibrate(m.odometry, m.groundtruth, t0, t1, rows, m.landmarks)


def prepare_out(out, force):
    if os.path.exists(out) and not os.path.isdir(out):
        raise InputError(f"{out}: exists and is not a folder")
    if os.path.isdir(out) and os.listdir(out):
        if not force:
            raise InputError(f"{out}: folder is not empty (--force replaces its contents)")
        for name in os.listdir(out):
            p = os.path.join(out, name)
            shutil.rmtree(p) if os.path.isdir(p) and not os.path.islink(p) else os.remove(p)
    os.makedirs(out, exist_ok=True)


def import_robot(folder, robot, out, kind="commanded", seed=1, force=False):
    log(f"reading {folder} robot {robot}")
    m = Mrclam(folder, robot)
    t0, t1 = span(m)
    if t1 - t0 < 2.0:
        raise InputError(f"{folder}: robot {robot}'s odometry and Vicon overlap for "
                         f"{t1 - t0:.2f} s only")
    log(f"{t1 - t0:.1f} s of odometry and Vicon together; measuring the commands against Vicon")
    c = calibration(m, t0, t1)
    for ln in cal.describe(c, FOCAL_PX):
        log(ln)
    clock = Clock(t0, c["lag_s"])
    rng = np.random.default_rng(seed)
    te, ticks = encoders(m, t0, t1)
    tg, rate, mems = gyro(m, t0, min(t1, m.groundtruth[-1, 0] - c["lag_s"]), kind, rng, c)
    rows, drop = sightings(m, t0, t1)
    imgs, repeated = images(rows)
    chosen = frames(imgs)
    kept = sum(len(i[1]) for i in chosen)
    seen = len(m.sightings)
    log(f"{seen} sightings: " + ", ".join(f"{v} {k}" for k, v in drop.items()) +
        f"; {len(rows)} in {len(imgs)} images ({repeated} repeated in an image dropped); "
        f"{len(chosen)} frames at least {FRAME_MIN_GAP_S} s apart keep {kept} sightings")
    prepare_out(out, force)
    log(f"writing {out}")
    write_csv(os.path.join(out, "encoders.csv"), "#t_ns,left_ticks,right_ticks",
              [f"{t},{a},{b}\n" for t, (a, b) in zip(clock.ns(te), ticks)])
    write_csv(os.path.join(out, "gyro.csv"), "#t_ns,wz_rad_s",
              [f"{t},{w!r}\n" for t, w in zip(clock.ns(tg), rate.tolist())])
    feats = []
    for t, seen_in in chosen:
        ns = int(clock.ns(t))
        feats += [f"{ns},{s},{u!r},{CY}\n" for s, u in sorted(seen_in.items())]
    write_csv(os.path.join(out, "features.csv"), "#t_ns,track_id,u_px,v_px", feats)
    gt = m.groundtruth[(m.groundtruth[:, 0] - clock.lag >= clock.origin)
                       & (m.groundtruth[:, 0] <= t1 + 1.0)]
    half = 0.5 * gt[:, 3]
    write_csv(os.path.join(out, "groundtruth.csv"), "#t_ns,x_m,y_m,z_m,qw,qx,qy,qz",
              [f"{t},{x!r},{y!r},0.0,{w!r},0.0,0.0,{z!r}\n" for t, x, y, w, z in
               zip(clock.vicon(gt[:, 0]), gt[:, 1].tolist(), gt[:, 2].tolist(),
                   np.cos(half).tolist(), np.sin(half).tolist())])
    write_csv(os.path.join(out, "sim_landmarks.csv"), "#id,x_m,y_m,z_m",
              [f"{s},{x!r},{y!r},0.0\n" for s, (x, y) in sorted(m.landmarks.items())
               if s not in ROBOTS])
    with open(os.path.join(out, "sensors.yaml"), "w", encoding="utf-8") as f:
        f.write(sensors_yaml(c, kind, mems))
    log(f"done: {len(te)} encoder samples, {len(tg)} gyro samples, {len(chosen)} frames, "
        f"{len(gt)} ground-truth poses")
    return {"calibration": c, "dropped": drop, "images": len(imgs), "frames": len(chosen),
            "sightings_kept": kept, "mems": mems}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dataset_dir")
    ap.add_argument("robot", type=int)
    ap.add_argument("out_dir", nargs="?")
    ap.add_argument("--gyro", choices=["commanded", "mems"], default="commanded")
    ap.add_argument("--seed", type=int, default=1, help="the mems gyro's errors (default 1)")
    ap.add_argument("--force", action="store_true", help="replace a non-empty OUT_DIR's contents")
    ap.add_argument("--calibrate", action="store_true",
                    help="print the commands and bearings measured against Vicon, write nothing")
    a = ap.parse_args(argv)
    if a.robot < 1:
        ap.error(f"ROBOT {a.robot}: expected a robot number (1-5 in the published datasets)")
    if not a.calibrate and a.out_dir is None:
        ap.error("OUT_DIR is required (or --calibrate)")
    try:
        if a.calibrate:
            m = Mrclam(a.dataset_dir, a.robot)
            t0, t1 = span(m)
            print("\n".join(cal.describe(calibration(m, t0, t1), FOCAL_PX)))
        else:
            import_robot(a.dataset_dir, a.robot, a.out_dir, a.gyro, a.seed, a.force)
    except (InputError, ValueError, OSError) as e:
        print(f"mrclam: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
