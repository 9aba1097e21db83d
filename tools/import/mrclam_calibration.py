"""A MRCLAM robot's commanded speed and turn rate, and its camera's bearings, measured against its
Vicon track: the calibration a user would do with a motion-capture run.

Method (on a 20 Hz grid over the span where both odometry and Vicon exist; grid intervals that
touch a Vicon gap of more than 0.1 s are left out):
- the Vicon distance of an interval is its displacement along the mean heading, its turn the
  change of the unwrapped heading; the commanded ones integrate the commands, each held until
  the next (zero-order hold);
- lag: the delay of the commands (0 to 0.5 s in 10 ms steps) that minimizes the squared turn
  residual; scale: least squares through the origin of the Vicon turn (distance) on the commanded
  one at that lag;
- the noise figures are taken from the raw commands (no lag, no scale: what an estimator fed with
  them faces), matched over 1 s windows: the heading error accumulated in a 1 s window has the
  std. dev. noise_density * sqrt(1 s) (white rate noise), and the relative distance error of a
  1 s window is distance_noise / sqrt(20) (independent errors in its 20 encoder intervals); the
  rate bias is the mean rate error;
- bearings: each landmark sighting against the bearing from the Vicon pose (interpolated at its
  stamp) to the landmark's surveyed position; the spread is 1.4826 x the median absolute deviation
  (robust to misidentified barcodes), and the camera delay (-0.5 to 0.5 s in 10 ms steps) that
  minimizes it is reported."""

import numpy as np

GRID_S = 0.05
WINDOW_S = 1.0
MAX_VICON_GAP_S = 0.1
MOVING_M_PER_S = 0.02


def cumulative(t, rate):
    """Integral of a rate held from each stamp to the next, at the stamps."""
    return np.concatenate([[0.0], np.cumsum(rate[:-1] * np.diff(t))])


def unwrapped_heading(gt):
    return np.unwrap(gt[:, 3])


def valid_intervals(gt, grid):
    ok = np.ones(len(grid) - 1, dtype=bool)
    gap = np.diff(gt[:, 0])
    for b in np.nonzero(gap > MAX_VICON_GAP_S)[0]:
        ok &= ~((grid[1:] > gt[b, 0]) & (grid[:-1] < gt[b + 1, 0]))
    return ok


def vicon_steps(gt, grid):
    """Distance along the heading and turn per grid interval."""
    th = np.interp(grid, gt[:, 0], unwrapped_heading(gt))
    x = np.interp(grid, gt[:, 0], gt[:, 1])
    y = np.interp(grid, gt[:, 0], gt[:, 2])
    dth = np.diff(th)
    mid = th[:-1] + 0.5 * dth
    return np.diff(x) * np.cos(mid) + np.diff(y) * np.sin(mid), dth


def commanded_steps(odo, grid, lag=0.0):
    t = odo[:, 0] + lag
    dist = np.diff(np.interp(grid, t, cumulative(t, odo[:, 1])))
    turn = np.diff(np.interp(grid, t, cumulative(t, odo[:, 2])))
    return dist, turn


def through_origin(x, y):
    d = float(np.sum(x * x))
    return float(np.sum(x * y)) / d if d > 0 else 1.0


def robust_sd(x):
    return 1.4826 * float(np.median(np.abs(x - np.median(x)))) if len(x) else 0.0


def wrap(a):
    return (a + np.pi) % (2.0 * np.pi) - np.pi


def bearing_residuals(gt, sightings, landmarks, offset=0.0):
    """Measured minus Vicon bearing of each sighting of a landmark, radians."""
    rows = [r for r in sightings if int(r[1]) in landmarks]
    if not rows:
        return np.zeros(0)
    s = np.array(rows)
    t = s[:, 0] + offset
    inside = (t >= gt[0, 0]) & (t <= gt[-1, 0])
    s, t = s[inside], t[inside]
    x = np.interp(t, gt[:, 0], gt[:, 1])
    y = np.interp(t, gt[:, 0], gt[:, 2])
    th = np.interp(t, gt[:, 0], unwrapped_heading(gt))
    lm = np.array([landmarks[int(k)] for k in s[:, 1]]).reshape(-1, 2)
    return wrap(s[:, 3] - (np.arctan2(lm[:, 1] - y, lm[:, 0] - x) - th))


def calibrate(odo, gt, t0, t1, sightings=None, landmarks=None):
    """The figures of the module's docstring as a dict. sightings: (t, subject, range, bearing)
    rows of landmarks, landmarks: {subject: (x, y)}."""
    grid = np.arange(t0, t1, GRID_S)
    if len(grid) < 2 * int(WINDOW_S / GRID_S):
        raise ValueError(f"calibration: {t1 - t0:.1f} s of odometry and Vicon together is too "
                         "short")
    ok = valid_intervals(gt, grid)
    vd, vt = vicon_steps(gt, grid)
    best = None
    for lag in np.arange(0.0, 0.501, 0.01):
        cd, ct = commanded_steps(odo, grid, lag)
        cost = float(np.sum((ct - vt)[ok] ** 2))
        if best is None or cost < best[0]:
            best = (cost, float(lag), cd, ct)
    _, lag, cd_lag, ct_lag = best
    cd, ct = commanded_steps(odo, grid, 0.0)
    k = int(round(WINDOW_S / GRID_S))
    e_turn = np.cumsum(np.where(ok, ct - vt, 0.0))
    e_dist = np.cumsum(np.where(ok, cd - vd, 0.0))
    length = np.cumsum(np.where(ok, np.abs(cd), 0.0))
    w_turn = e_turn[k:] - e_turn[:-k]
    w_dist = e_dist[k:] - e_dist[:-k]
    w_len = length[k:] - length[:-k]
    moving = w_len > MOVING_M_PER_S * WINDOW_S
    rel = w_dist[moving] / w_len[moving]
    rel_rms = float(np.sqrt(np.mean(rel**2))) if len(rel) else 0.0
    span = float(np.sum(ok)) * GRID_S
    r = {
        "span_s": span,
        "vicon_path_m": float(np.sum(np.abs(vd[ok]))),
        "commanded_path_m": float(np.sum(np.abs(cd[ok]))),
        "lag_s": lag,
        "turn_scale": through_origin(ct_lag[ok], vt[ok]),
        "distance_scale": through_origin(cd_lag[ok], vd[ok]),
        "rate_bias_rad_s": float(np.sum((ct - vt)[ok])) / span if span > 0 else 0.0,
        "heading_error_1s_rad": float(np.std(w_turn)),
        "noise_density": float(np.std(w_turn)) / np.sqrt(WINDOW_S),
        "distance_error_1s": rel_rms,
        "distance_noise": min(1.0, rel_rms * np.sqrt(WINDOW_S / GRID_S)),
    }
    if sightings is not None and landmarks:
        res = bearing_residuals(gt, sightings, landmarks)
        offsets = np.arange(-0.5, 0.501, 0.01)
        spread = [robust_sd(bearing_residuals(gt, sightings, landmarks, o)) for o in offsets]
        r |= {"bearings": len(res), "bearing_bias_rad": float(np.median(res)) if len(res) else 0.0,
              "bearing_sd_rad": robust_sd(res),
              "camera_delay_s": float(offsets[int(np.argmin(spread))]),
              "bearing_sd_at_delay_rad": float(min(spread))}
    return r


def describe(r, focal_px):
    lines = [
        f"{r['span_s']:.0f} s of commands against Vicon, Vicon path {r['vicon_path_m']:.1f} m, "
        f"commanded {r['commanded_path_m']:.1f} m",
        f"commands lag the motion by {r['lag_s']:.2f} s; at that lag Vicon = "
        f"{r['turn_scale']:.3f} x the commanded turn and {r['distance_scale']:.3f} x the commanded "
        "distance",
        f"raw commands: mean turn rate error {r['rate_bias_rad_s'] * 1e3:+.2f} mrad/s, heading "
        f"error over 1 s {r['heading_error_1s_rad']:.4f} rad (noise_density "
        f"{r['noise_density']:.4f} rad/s/sqrt(Hz)), relative distance error over 1 s "
        f"{r['distance_error_1s']:.3f} (distance_noise {r['distance_noise']:.3f} per 50 ms "
        "interval)",
    ]
    if "bearings" in r:
        lines.append(
            f"bearings: {r['bearings']} landmark sightings, median error "
            f"{r['bearing_bias_rad'] * 1e3:+.1f} mrad, spread {r['bearing_sd_rad'] * 1e3:.1f} "
            f"mrad ({r['bearing_sd_rad'] * focal_px:.2f} px at f = {focal_px:g} px); a camera "
            f"delay of {r['camera_delay_s']:+.2f} s would make it "
            f"{r['bearing_sd_at_delay_rad'] * 1e3:.1f} mrad")
    return lines
