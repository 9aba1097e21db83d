"""A MRCLAM robot's commanded speed and turn rate, and its camera's bearings, measured against its
Vicon track: the calibration a user would do with a motion-capture run.

Method (on a 20 Hz grid over the span where both odometry and Vicon exist; grid intervals that
touch a Vicon gap of more than 0.1 s are left out):
- the Vicon distance of an interval is its displacement along the mean heading, its turn the
  change of the unwrapped heading; the commanded ones integrate the commands, each held until
  the next (zero-order hold), none before the first;
- lag: the delay of the commands (0 to 0.5 s in 10 ms steps) that minimizes the squared turn
  residual; scale: least squares through the origin of the Vicon turn (distance) on the commanded
  one at that lag; scale error: the std. dev. of the same fit over each minute of motion;
- the noise figures come from the residuals of the calibrated commands (at the lag, times the
  scales), matched over 1 s windows: the heading error accumulated in a 1 s window has the
  std. dev. noise_density * sqrt(1 s) (white rate noise), and the relative distance error of a
  1 s window is distance_noise / sqrt(20) (independent errors in its 20 encoder intervals); the
  rate bias is the mean rate error of the calibrated commands;
- the raw commands' figures (no lag, no scale) are reported too;
- bearings: each landmark sighting against the bearing from the Vicon pose (interpolated at its
  stamp plus a camera delay) to the landmark's surveyed position; the camera delay (-0.5 to 0.5 s
  in 10 ms steps) minimizes the spread, 1.4826 x the median absolute deviation (robust to
  misidentified barcodes); the median error at that delay is the camera's yaw on the body."""

import numpy as np

GRID_S = 0.05
WINDOW_S = 1.0
MAX_VICON_GAP_S = 0.1
MOVING_M_PER_S = 0.02
SEGMENT_S = 60.0


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


def window_errors(cd, ct, vd, vt, ok, k):
    """Heading error (rad) of each k-interval window and relative distance error of the windows
    in motion."""
    e_turn = np.cumsum(np.where(ok, ct - vt, 0.0))
    e_dist = np.cumsum(np.where(ok, cd - vd, 0.0))
    length = np.cumsum(np.where(ok, np.abs(cd), 0.0))
    w_turn = e_turn[k:] - e_turn[:-k]
    w_len = length[k:] - length[:-k]
    moving = w_len > MOVING_M_PER_S * WINDOW_S
    rel = (e_dist[k:] - e_dist[:-k])[moving] / w_len[moving]
    return w_turn, rel


def noise_figures(cd, ct, vd, vt, ok, k, span):
    w_turn, rel = window_errors(cd, ct, vd, vt, ok, k)
    rel_rms = float(np.sqrt(np.mean(rel**2))) if len(rel) else 0.0
    return {
        "rate_bias_rad_s": float(np.sum((ct - vt)[ok])) / span if span > 0 else 0.0,
        "heading_error_1s_rad": float(np.std(w_turn)),
        "noise_density": float(np.std(w_turn)) / np.sqrt(WINDOW_S),
        "distance_error_1s": rel_rms,
        "distance_noise": min(1.0, rel_rms * np.sqrt(WINDOW_S / GRID_S)),
    }


def segment_scale_sd(x, y, ok, n):
    """Std. dev. of the through-origin scale fitted on consecutive segments of n intervals with
    enough motion (at least a tenth of the run's mean per segment)."""
    need = 0.1 * float(np.sum(np.abs(x[ok]))) * n / max(1, int(np.sum(ok)))
    fits = []
    for a in range(0, len(x) - n + 1, n):
        m = ok[a:a + n]
        xs, ys = x[a:a + n][m], y[a:a + n][m]
        if float(np.sum(np.abs(xs))) > need:
            fits.append(through_origin(xs, ys))
    return float(np.std(fits)) if len(fits) > 1 else 0.0


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
    span = float(np.sum(ok)) * GRID_S
    turn_scale = through_origin(ct_lag[ok], vt[ok])
    distance_scale = through_origin(cd_lag[ok], vd[ok])
    minute = int(round(SEGMENT_S / GRID_S))
    r = {
        "span_s": span,
        "vicon_path_m": float(np.sum(np.abs(vd[ok]))),
        "commanded_path_m": float(np.sum(np.abs(cd[ok]))),
        "lag_s": lag,
        "turn_scale": turn_scale,
        "distance_scale": distance_scale,
        "turn_scale_sd": segment_scale_sd(ct_lag, vt, ok, minute),
        "distance_scale_sd": segment_scale_sd(cd_lag, vd, ok, minute),
        "raw": noise_figures(cd, ct, vd, vt, ok, k, span),
    }
    r |= noise_figures(distance_scale * cd_lag, turn_scale * ct_lag, vd, vt, ok, k, span)
    if sightings is not None and landmarks:
        offsets = np.arange(-0.5, 0.501, 0.01)
        spread = [robust_sd(bearing_residuals(gt, sightings, landmarks, o)) for o in offsets]
        delay = float(offsets[int(np.argmin(spread))])
        res = bearing_residuals(gt, sightings, landmarks, delay)
        r |= {"bearings": len(res), "bearing_bias_rad": float(np.median(res)) if len(res) else 0.0,
              "bearing_sd_rad": robust_sd(res), "camera_delay_s": delay,
              "bearing_sd_raw_rad": robust_sd(bearing_residuals(gt, sightings, landmarks))}
    return r


def describe(r, focal_px):
    raw = r["raw"]
    lines = [
        f"{r['span_s']:.0f} s of commands against Vicon, Vicon path {r['vicon_path_m']:.1f} m, "
        f"commanded {r['commanded_path_m']:.1f} m",
        f"commands lag the motion by {r['lag_s']:.2f} s; at that lag Vicon = "
        f"{r['turn_scale']:.3f} x the commanded turn and {r['distance_scale']:.3f} x the commanded "
        f"distance (std. dev. over each minute {r['turn_scale_sd']:.3f}, "
        f"{r['distance_scale_sd']:.3f})",
        f"raw commands: mean turn rate error {raw['rate_bias_rad_s'] * 1e3:+.2f} mrad/s, heading "
        f"error over 1 s {raw['heading_error_1s_rad']:.4f} rad, relative distance error over 1 s "
        f"{raw['distance_error_1s']:.3f}",
        f"calibrated commands: mean turn rate error {r['rate_bias_rad_s'] * 1e3:+.2f} mrad/s, "
        f"heading error over 1 s {r['heading_error_1s_rad']:.4f} rad (noise_density "
        f"{r['noise_density']:.4f} rad/s/sqrt(Hz)), relative distance error over 1 s "
        f"{r['distance_error_1s']:.3f} (distance_noise {r['distance_noise']:.3f} per 50 ms "
        "interval)",
    ]
    if "bearings" in r:
        lines.append(
            f"bearings: {r['bearings']} landmark sightings, camera delay "
            f"{r['camera_delay_s']:+.2f} s, median error {r['bearing_bias_rad'] * 1e3:+.1f} mrad "
            "(the camera's yaw), spread "
            f"{r['bearing_sd_rad'] * 1e3:.1f} mrad ({r['bearing_sd_rad'] * focal_px:.2f} px at "
            f"f = {focal_px:g} px; {r['bearing_sd_raw_rad'] * 1e3:.1f} mrad without the delay)")
    return lines
