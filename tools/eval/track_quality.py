#!/usr/bin/python3
"""Quality of feature tracks on a dataset's camera images, measured independently of the front end
that made them, with OpenCV as the reference (python3-opencv; nothing of it is in the product).

  tools/eval/track_quality.py DATASET TRACKS.csv [options]
  tools/eval/track_quality.py DATASET --opencv-baseline N [options]
  tools/eval/track_quality.py DATASET TRACKS.csv --opencv-baseline N [options]

DATASET is a dataset folder (sensors.yaml, cam0/data.csv and its images); TRACKS.csv holds
t_ns,track_id,u_px,v_px rows (features.csv, as cleanslam-track --out writes it), every t_ns one of
the dataset's frames. With --opencv-baseline N the dataset's images are also tracked by OpenCV
(goodFeaturesToTrack + calcOpticalFlowPyrLK with the same landmark budget as the front end), and
both track sets are measured the same way and printed side by side.

Metrics (the frames are the dataset's first --max-frames frames, all of them by default):
  tracks            distinct track ids.
  ended mid-image   tracks whose last observation lies more than --margin px (default 15) inside
                    the image (the image spans -0.5 .. width-0.5 and -0.5 .. height-0.5: pixel
                    centres at integers) and that are not seen in the last frame: the track was
                    lost where the point was still in view.
  tracked / frame   in every frame but the first, the tracks observed in it that were also
                    observed in an earlier frame (a track's first sighting is not tracking):
                    median and minimum.
  track length      frames with an observation, per track: median and 90th percentile.
  Sampson           for every track observed in two consecutive frames, the Sampson distance (px,
                    the square root of the first-order geometric error, shared by both images) of
                    the correspondence to a fundamental matrix of that frame pair: median, 95th
                    percentile, maximum, and the worst correspondences. The matrix is fitted by
                    RANSAC (1 px), then by the normalized 8-point method to all RANSAC inliers, to
                    dense reference tracks: goodFeaturesToTrack corners followed by
                    calcOpticalFlowPyrLK forward and back, kept when they come back within
                    0.5 px. Points are undistorted with sensors.yaml's intrinsics first. A pair
                    with fewer than 20 reference tracks gets no matrix; its correspondences are
                    counted as unscored.
Percentiles are numpy's (linear interpolation).

The OpenCV baseline: in every frame the tracks are followed by pyramidal LK (21 x 21 window,
3 levels) and kept when LK converged, the point stays inside the image and LK back from it
returns within --baseline-fb px (default 1); then, when fewer than --refill-below tracks remain
(default N), new Shi-Tomasi corners (quality level 0.01) are added up to N tracks, at least
--min-distance px (default 20) from every track and from each other, at least 17 px from the
border and in the top --new-rows fraction of the image (default 0.7): the front end's rules for
new landmarks (min_in_view / target_in_view, exclusion_px, patch margin,
new_landmark_max_row_fraction). --baseline-out FILE writes its tracks as features.csv.

--why-ended: for every track that ended mid-image, how its appearance had changed, as the
zero-mean NCC of 15 x 15 windows (the front end's matching window; bilinear, sub-pixel): its
first-sighting window against its window at its last observation, and against the window in the
next frame where dense LK (forward-backward within 0.5 px) puts the point; and its window at the
last observation against that next window. A track lost while LK still follows the point, whose
next window still matches its last one but no longer its first, was lost to appearance change
against the first-sighting template, not to occlusion or leaving the view.

Options: --margin PX, --max-frames N, --json (one JSON object on stdout instead of the table).
Progress goes to stderr. Exit status 0, 1 when a file is missing or malformed (the message names
it, and the line), 2 on bad arguments, 3 when python3-opencv is not installed.
"""

import argparse
import json
import math
import os
import sys
import time

import numpy as np

try:
    import cv2
except ImportError:
    cv2 = None

try:
    import yaml
except ImportError:
    yaml = None

TOOL = "track_quality"
REF_MIN_POINTS = 20
REF_FB_PX = 0.5
REF_RANSAC_PX = 1.0
LK_WINDOW = (21, 21)
LK_LEVELS = 3
NEW_CORNER_BORDER_PX = 17
WORST_SHOWN = 5
NCC_RADIUS = 7


class InputError(Exception):
    pass


class Progress:
    """Progress on stderr about once a second, also when stderr is not a terminal."""

    def __init__(self, what, total):
        self.what, self.total, self.last = what, total, 0.0

    def __call__(self, done):
        now = time.monotonic()
        if now - self.last >= 1.0 or done == self.total:
            self.last = now
            print(f"{TOOL}: {self.what} {done}/{self.total}", file=sys.stderr, flush=True)


# ---------------------------------------------------------------------------------------------
# Dataset and tracks


class Dataset:
    def __init__(self, folder, max_frames):
        self.folder = folder
        sensors = os.path.join(folder, "sensors.yaml")
        try:
            with open(sensors, encoding="utf-8") as f:
                doc = yaml.safe_load(f)
        except (OSError, yaml.YAMLError) as e:
            raise InputError(f"{sensors}: {e}") from e
        cam = doc.get("camera") if isinstance(doc, dict) else None
        if not isinstance(cam, dict):
            raise InputError(f"{sensors}: no 'camera' section")

        def number(key, default=None):
            v = cam.get(key, default)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise InputError(f"{sensors}: camera '{key}' must be a number, got {v!r}")
            return float(v)

        self.width, self.height = int(number("width")), int(number("height"))
        fx, fy, cx, cy = number("fx"), number("fy"), number("cx"), number("cy")
        dist = cam.get("distortion", [0.0, 0.0, 0.0, 0.0])
        if (not isinstance(dist, list) or len(dist) != 4 or
                not all(isinstance(d, (int, float)) and math.isfinite(d) for d in dist)):
            raise InputError(f"{sensors}: camera 'distortion' must be 4 numbers, got {dist!r}")
        self.K = np.array([[fx, 0.0, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]])
        self.dist = np.array(dist, dtype=np.float64)

        index = os.path.join(folder, "cam0", "data.csv")
        self.t_ns, self.files = [], []
        try:
            with open(index, encoding="utf-8") as f:
                for n, line in enumerate(f, 1):
                    line = line.strip()
                    if not line or line.startswith("#"):
                        continue
                    parts = line.split(",")
                    if len(parts) != 2:
                        raise InputError(f"{index}:{n}: expected t_ns,filename, got '{line}'")
                    try:
                        t = int(parts[0])
                    except ValueError as e:
                        raise InputError(f"{index}:{n}: t_ns '{parts[0]}' is not an integer") from e
                    if self.t_ns and t <= self.t_ns[-1]:
                        raise InputError(f"{index}:{n}: t_ns {t} does not follow {self.t_ns[-1]}")
                    self.t_ns.append(t)
                    self.files.append(os.path.join(folder, "cam0", "data", parts[1].strip()))
        except OSError as e:
            raise InputError(f"{index}: {e}") from e
        if max_frames is not None:
            self.t_ns, self.files = self.t_ns[:max_frames], self.files[:max_frames]
        if len(self.t_ns) < 2:
            raise InputError(f"{index}: {len(self.t_ns)} frame(s): need at least 2")
        self.frame_of = {t: k for k, t in enumerate(self.t_ns)}
        self._cache = {}

    def __len__(self):
        return len(self.t_ns)

    def image(self, k):
        if k in self._cache:
            return self._cache[k]
        path = self.files[k]
        img = cv2.imread(path, cv2.IMREAD_UNCHANGED)
        if img is None:
            raise InputError(f"{path}: cannot read the image")
        if img.ndim != 2 or img.dtype != np.uint8:
            raise InputError(f"{path}: not an 8-bit grey image")
        if img.shape != (self.height, self.width):
            raise InputError(f"{path}: {img.shape[1]}x{img.shape[0]}, sensors.yaml says "
                             f"{self.width}x{self.height}")
        self._cache = {k - 1: self._cache[k - 1]} if k - 1 in self._cache else {}
        self._cache[k] = img
        return img

    def undistort(self, pts):
        if len(pts) == 0 or not self.dist.any():
            return np.asarray(pts, dtype=np.float64).reshape(-1, 2)
        p = np.asarray(pts, dtype=np.float64).reshape(-1, 1, 2)
        return cv2.undistortPoints(p, self.K, self.dist, P=self.K).reshape(-1, 2)


def read_tracks(path, ds):
    """{track id: [(frame, u, v), ...] sorted by frame} of the rows within the dataset's frames."""
    tracks = {}
    seen = set()
    last_frame = ds.t_ns[-1]
    try:
        with open(path, encoding="utf-8") as f:
            for n, line in enumerate(f, 1):
                line = line.strip()
                if not line or line.startswith("#"):
                    continue
                parts = line.split(",")
                if len(parts) < 4:
                    raise InputError(f"{path}:{n}: expected t_ns,track_id,u_px,v_px, got '{line}'")
                try:
                    t, tid = int(parts[0]), int(parts[1])
                    u, v = float(parts[2]), float(parts[3])
                except ValueError as e:
                    raise InputError(f"{path}:{n}: '{line}': {e}") from e
                if tid < 0 or not (math.isfinite(u) and math.isfinite(v)):
                    raise InputError(f"{path}:{n}: bad track id or pixel in '{line}'")
                if t > last_frame:
                    continue  # beyond --max-frames
                k = ds.frame_of.get(t)
                if k is None:
                    raise InputError(
                        f"{path}:{n}: t_ns {t} is no frame of {ds.folder}/cam0/data.csv")
                if (k, tid) in seen:
                    raise InputError(f"{path}:{n}: track {tid} observed twice at t_ns {t}")
                seen.add((k, tid))
                tracks.setdefault(tid, []).append((k, u, v))
    except OSError as e:
        raise InputError(f"{path}: {e}") from e
    for obs in tracks.values():
        obs.sort()
    return tracks


# ---------------------------------------------------------------------------------------------
# OpenCV


def lk(img0, img1, pts):
    p = np.asarray(pts, dtype=np.float32).reshape(-1, 1, 2)
    crit = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 30, 0.01)
    q, st, _ = cv2.calcOpticalFlowPyrLK(img0, img1, p, None, winSize=LK_WINDOW,
                                        maxLevel=LK_LEVELS, criteria=crit)
    return q.reshape(-1, 2), st.reshape(-1).astype(bool)


def forward_backward(img0, img1, pts):
    """LK from img0 to img1 and back: the end points and the forward-backward error (inf where
    either direction failed)."""
    pts = np.asarray(pts, dtype=np.float32).reshape(-1, 2)
    q, st = lk(img0, img1, pts)
    r, st2 = lk(img1, img0, q)
    err = np.linalg.norm(r - pts, axis=1)
    err[~(st & st2)] = np.inf
    return q, err


class ReferenceGeometry:
    """Fundamental matrices of consecutive frame pairs from dense forward-backward LK tracks."""

    def __init__(self, ds):
        self.ds = ds
        self.F = {}
        self.stats = {}

    def fit(self, k):
        """F between frames k-1 and k (undistorted pixels), or None."""
        if k in self.F:
            return self.F[k]
        ds = self.ds
        img0, img1 = ds.image(k - 1), ds.image(k)
        p0 = cv2.goodFeaturesToTrack(img0, maxCorners=2000, qualityLevel=0.001, minDistance=4,
                                     blockSize=5)
        F, n_ref, n_in, motion = None, 0, 0, float("nan")
        if p0 is not None:
            p0 = p0.reshape(-1, 2)
            p1, err = forward_backward(img0, img1, p0)
            inside = ((p1[:, 0] >= 0) & (p1[:, 0] <= ds.width - 1) & (p1[:, 1] >= 0) &
                      (p1[:, 1] <= ds.height - 1))
            keep = (err < REF_FB_PX) & inside
            n_ref = int(keep.sum())
            if n_ref > 0:
                motion = float(np.median(np.linalg.norm(p1[keep] - p0[keep], axis=1)))
            if n_ref >= REF_MIN_POINTS:
                a, b = ds.undistort(p0[keep]), ds.undistort(p1[keep])
                Fm, mask = cv2.findFundamentalMat(a, b, cv2.FM_RANSAC, REF_RANSAC_PX, 0.999, 5000)
                if Fm is not None and Fm.shape == (3, 3) and mask is not None:
                    inl = mask.reshape(-1).astype(bool)
                    n_in = int(inl.sum())
                    # RANSAC's model comes from 7 points: refit to all its inliers.
                    F8, _ = cv2.findFundamentalMat(a[inl], b[inl], cv2.FM_8POINT)
                    F = F8 if F8 is not None and F8.shape == (3, 3) else Fm
        self.F[k] = F
        self.stats[k] = (n_ref, n_in, motion)
        return F

    def summary(self):
        fitted = [k for k, f in self.F.items() if f is not None]
        refs = [self.stats[k][0] for k in self.F]
        inl = [self.stats[k][1] for k in fitted]
        mot = [self.stats[k][2] for k in self.F if math.isfinite(self.stats[k][2])]
        return {
            "pairs": len(self.F),
            "pairs_fitted": len(fitted),
            "reference_tracks_median": float(np.median(refs)) if refs else 0.0,
            "ransac_inliers_median": float(np.median(inl)) if inl else 0.0,
            "image_motion_px_median": float(np.median(mot)) if mot else float("nan"),
        }


def sampson(F, a, b):
    """Sampson distance (px) of correspondences a -> b (N x 2 each) to F (b^T F a = 0)."""
    ah = np.hstack([a, np.ones((len(a), 1))])
    bh = np.hstack([b, np.ones((len(b), 1))])
    Fa = ah @ F.T
    Ftb = bh @ F
    num = np.sum(bh * Fa, axis=1) ** 2
    den = Fa[:, 0] ** 2 + Fa[:, 1] ** 2 + Ftb[:, 0] ** 2 + Ftb[:, 1] ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.sqrt(num / den)


def opencv_baseline(ds, budget, refill_below, min_distance, new_rows, fb_px):
    """Tracks of goodFeaturesToTrack + calcOpticalFlowPyrLK over the dataset's frames, in the
    read_tracks form."""
    tracks = {}
    ids = np.zeros(0, dtype=np.int64)
    pts = np.zeros((0, 2), dtype=np.float32)
    next_id = 0
    prev = None
    W, H = ds.width, ds.height
    row_limit = new_rows * (H - 1)
    progress = Progress("OpenCV baseline, frame", len(ds))
    for k in range(len(ds)):
        img = ds.image(k)
        if prev is not None and len(pts):
            q, err = forward_backward(prev, img, pts)
            keep = ((err < fb_px) & (q[:, 0] >= 0) & (q[:, 0] <= W - 1) & (q[:, 1] >= 0) &
                    (q[:, 1] <= H - 1))
            ids, pts = ids[keep], q[keep]
        if len(pts) < refill_below:
            mask = np.zeros((H, W), dtype=np.uint8)
            top = int(math.floor(row_limit))
            mask[NEW_CORNER_BORDER_PX:min(top, H - 1 - NEW_CORNER_BORDER_PX) + 1,
                 NEW_CORNER_BORDER_PX:W - NEW_CORNER_BORDER_PX] = 255
            for u, v in pts:
                cv2.circle(mask, (int(round(u)), int(round(v))), int(math.ceil(min_distance)), 0,
                           -1)
            want = budget - len(pts)
            new = cv2.goodFeaturesToTrack(img, maxCorners=want, qualityLevel=0.01,
                                          minDistance=min_distance, mask=mask)
            if new is not None:
                new = new.reshape(-1, 2).astype(np.float32)
                ids = np.concatenate([ids, np.arange(next_id, next_id + len(new))])
                pts = np.vstack([pts, new])
                next_id += len(new)
        for tid, (u, v) in zip(ids, pts):
            tracks.setdefault(int(tid), []).append((k, float(u), float(v)))
        prev = img
        progress(k + 1)
    return tracks


def write_tracks(path, ds, tracks):
    rows = sorted((k, tid, u, v) for tid, obs in tracks.items() for (k, u, v) in obs)
    with open(path, "w", encoding="utf-8") as f:
        f.write("#t_ns,track_id,u_px,v_px\n")
        for k, tid, u, v in rows:
            f.write(f"{ds.t_ns[k]},{tid},{u:.3f},{v:.3f}\n")


# ---------------------------------------------------------------------------------------------
# Metrics


def percentile(values, q):
    return float(np.percentile(values, q)) if len(values) else float("nan")


def median(values):
    return float(np.median(values)) if len(values) else float("nan")


def window(img, u, v):
    size = (2 * NCC_RADIUS + 1, 2 * NCC_RADIUS + 1)
    return cv2.getRectSubPix(img.astype(np.float32), size, (float(u), float(v))).astype(np.float64)


def ncc(a, b):
    a, b = a - a.mean(), b - b.mean()
    d = math.sqrt(float((a * a).sum() * (b * b).sum()))
    return float((a * b).sum() / d) if d > 0.0 else float("nan")


def why_ended(ds, tracks, margin, min_ncc):
    """Appearance of the tracks that ended mid-image (see --why-ended)."""
    last = len(ds) - 1
    W, H = ds.width, ds.height
    rows = []
    for tid, obs in sorted(tracks.items()):
        k_end, u, v = obs[-1]
        if k_end == last or min(u + 0.5, v + 0.5, W - 0.5 - u, H - 0.5 - v) <= margin:
            continue
        k0, u0, v0 = obs[0]
        first = window(ds.image(k0), u0, v0)
        at_last = window(ds.image(k_end), u, v)
        q, err = forward_backward(ds.image(k_end), ds.image(k_end + 1), [(u, v)])
        qu, qv = (float(x) for x in q[0])
        followed = bool(err[0] < REF_FB_PX and
                        min(qu, qv, W - 1 - qu, H - 1 - qv) > NCC_RADIUS)
        nxt = window(ds.image(k_end + 1), qu, qv) if followed else None
        rows.append({
            "track_id": int(tid), "length": len(obs), "t_ns_last": int(ds.t_ns[k_end]),
            "u_px": u, "v_px": v, "ncc_first_last": ncc(first, at_last),
            "lk_followed": followed,
            "ncc_first_next": ncc(first, nxt) if followed else float("nan"),
            "ncc_last_next": ncc(at_last, nxt) if followed else float("nan"),
        })
    followed = [r for r in rows if r["lk_followed"]]
    first_next = [r["ncc_first_next"] for r in followed]
    return {
        "ended_mid_image": len(rows),
        "lk_followed": len(followed),
        "ncc_first_last_median": median([r["ncc_first_last"] for r in rows]),
        "ncc_first_next_median": median(first_next),
        "ncc_first_next_below_min": sum(1 for n in first_next if n < min_ncc),
        "ncc_last_next_median": median([r["ncc_last_next"] for r in followed]),
        "ncc_last_next_at_least_min": sum(1 for r in followed if r["ncc_last_next"] >= min_ncc),
        "tracks": rows,
    }


def print_why_ended(name, w, min_ncc):
    print(f"why ended mid-image ({name}): {w['ended_mid_image']} tracks, {w['lk_followed']} still "
          f"followed by LK into the next frame; NCC of the first-sighting window: median "
          f"{w['ncc_first_last_median']:.3f} at the last observation, "
          f"{w['ncc_first_next_median']:.3f} in the next frame ({w['ncc_first_next_below_min']} "
          f"below {min_ncc}); last observation's window against the next: median "
          f"{w['ncc_last_next_median']:.3f} ({w['ncc_last_next_at_least_min']} at least {min_ncc})")
    print("  track  length  t_ns_last         u      v   first/last  first/next  last/next")
    for r in w["tracks"]:
        nxt = (f"{r['ncc_first_next']:10.3f}  {r['ncc_last_next']:9.3f}" if r["lk_followed"] else
               f"{'LK lost':>10}  {'-':>9}")
        print(f"  {r['track_id']:5d}  {r['length']:6d}  {r['t_ns_last']:<14d} {r['u_px']:6.1f} "
              f"{r['v_px']:6.1f}  {r['ncc_first_last']:10.3f}  {nxt}")


def measure(ds, tracks, ref, margin):
    n_frames = len(ds)
    last = n_frames - 1
    W, H = ds.width, ds.height
    ended_mid, ended_border, alive = 0, 0, 0
    tracked = np.zeros(n_frames, dtype=np.int64)
    lengths = []
    pairs = {}  # frame k -> list of (track id, (u, v) at k-1, (u, v) at k)
    gaps = 0
    for tid, obs in tracks.items():
        lengths.append(len(obs))
        k_end, u, v = obs[-1]
        if k_end == last:
            alive += 1
        elif min(u + 0.5, v + 0.5, W - 0.5 - u, H - 0.5 - v) > margin:
            ended_mid += 1
        else:
            ended_border += 1
        for (k0, u0, v0), (k1, u1, v1) in zip(obs, obs[1:]):
            if k1 == k0 + 1:
                pairs.setdefault(k1, []).append((tid, (u0, v0), (u1, v1)))
            else:
                gaps += 1
        for k, _, _ in obs[1:]:
            tracked[k] += 1

    residuals, where = [], []
    unscored = 0
    progress = Progress("Sampson residuals, frame pair", len(pairs))
    for i, k in enumerate(sorted(pairs)):
        F = ref.fit(k)
        corr = pairs[k]
        if F is None:
            unscored += len(corr)
        else:
            a = ds.undistort([c[1] for c in corr])
            b = ds.undistort([c[2] for c in corr])
            d = sampson(F, a, b)
            for c, r in zip(corr, d):
                if math.isfinite(r):
                    residuals.append(float(r))
                    where.append((c[0], k))
                else:
                    unscored += 1
        progress(i + 1)
    residuals = np.array(residuals)
    order = np.argsort(-residuals)[:WORST_SHOWN] if len(residuals) else []
    n = len(tracks)
    per_frame = tracked[1:]
    return {
        "frames": n_frames,
        "tracks": n,
        "ended_mid_image": ended_mid,
        "ended_mid_image_fraction": ended_mid / n if n else float("nan"),
        "ended_at_border": ended_border,
        "seen_in_last_frame": alive,
        "tracked_per_frame_median": median(per_frame),
        "tracked_per_frame_min": int(per_frame.min()),
        "tracked_per_frame_mean": float(per_frame.mean()),
        "track_length_median": median(lengths),
        "track_length_p90": percentile(lengths, 90),
        "correspondences": int(len(residuals)),
        "correspondences_unscored": unscored,
        "correspondences_across_gaps": gaps,
        "sampson_px_median": median(residuals),
        "sampson_px_p95": percentile(residuals, 95),
        "sampson_px_max": float(residuals.max()) if len(residuals) else float("nan"),
        "worst": [{"track_id": int(where[j][0]), "t_ns": int(ds.t_ns[where[j][1]]),
                   "sampson_px": float(residuals[j])} for j in order],
    }


ROWS = [
    ("frames", "frames", "{:d}"),
    ("tracks", "tracks", "{:d}"),
    ("ended mid-image", None, None),
    ("ended at the border", "ended_at_border", "{:d}"),
    ("seen in the last frame", "seen_in_last_frame", "{:d}"),
    ("tracked per frame, median", "tracked_per_frame_median", "{:.1f}"),
    ("tracked per frame, min", "tracked_per_frame_min", "{:d}"),
    ("tracked per frame, mean", "tracked_per_frame_mean", "{:.2f}"),
    ("track length, median (frames)", "track_length_median", "{:.1f}"),
    ("track length, p90 (frames)", "track_length_p90", "{:.1f}"),
    ("consecutive correspondences", "correspondences", "{:d}"),
    ("  unscored (no reference F)", "correspondences_unscored", "{:d}"),
    ("  not consecutive (gaps)", "correspondences_across_gaps", "{:d}"),
    ("Sampson, median (px)", "sampson_px_median", "{:.3f}"),
    ("Sampson, p95 (px)", "sampson_px_p95", "{:.3f}"),
    ("Sampson, max (px)", "sampson_px_max", "{:.3f}"),
]


def cell(result, key, fmt):
    if key is None:
        return (f"{result['ended_mid_image']} ({100.0 * result['ended_mid_image_fraction']:.0f} %)"
                if result["tracks"] else "0")
    return fmt.format(result[key])


def print_table(results, reference):
    names = list(results)
    width = max(len(r[0]) for r in ROWS) + 2
    print(" " * width + "".join(f"{n:>18}" for n in names))
    for label, key, fmt in ROWS:
        print(f"{label:<{width}}" + "".join(f"{cell(results[n], key, fmt):>18}" for n in names))
    for n in names:
        worst = ", ".join(f"track {w['track_id']} at t_ns {w['t_ns']}: {w['sampson_px']:.2f} px"
                          for w in results[n]["worst"])
        print(f"worst Sampson ({n}): {worst or '-'}")
    print(f"reference: {reference['pairs_fitted']} of {reference['pairs']} frame pairs with a "
          f"fundamental matrix, median {reference['reference_tracks_median']:.0f} forward-backward "
          f"LK tracks ({reference['ransac_inliers_median']:.0f} RANSAC inliers), median image "
          f"motion {reference['image_motion_px_median']:.2f} px")


def main(argv=None):
    ap = argparse.ArgumentParser(prog="track_quality.py", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dataset")
    ap.add_argument("tracks", nargs="?", help="features.csv of the tracks to measure")
    ap.add_argument("--opencv-baseline", type=int, metavar="N",
                    help="also track with OpenCV, at most N tracks")
    ap.add_argument("--refill-below", type=int, metavar="M",
                    help="baseline: new corners when fewer than M tracks remain (default N)")
    ap.add_argument("--min-distance", type=float, default=20.0, metavar="PX")
    ap.add_argument("--new-rows", type=float, default=0.7, metavar="FRACTION")
    ap.add_argument("--baseline-fb", type=float, default=1.0, metavar="PX")
    ap.add_argument("--baseline-out", metavar="FILE")
    ap.add_argument("--margin", type=float, default=15.0, metavar="PX")
    ap.add_argument("--max-frames", type=int, metavar="N")
    ap.add_argument("--why-ended", action="store_true",
                    help="appearance change of the tracks that ended mid-image")
    ap.add_argument("--min-ncc", type=float, default=0.8, metavar="X",
                    help="--why-ended: the front end's NCC threshold (default 0.8)")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args(argv)
    if a.tracks is None and a.opencv_baseline is None:
        ap.error("give TRACKS.csv, --opencv-baseline N, or both")
    if a.opencv_baseline is not None and a.opencv_baseline < 1:
        ap.error(f"--opencv-baseline must be at least 1, got {a.opencv_baseline}")
    refill = a.refill_below if a.refill_below is not None else a.opencv_baseline
    if a.refill_below is not None and (a.opencv_baseline is None or
                                       not 1 <= a.refill_below <= a.opencv_baseline):
        ap.error("--refill-below M needs --opencv-baseline N and 1 <= M <= N")
    if not (a.min_distance > 0 and 0 < a.new_rows <= 1 and a.baseline_fb > 0 and a.margin >= 0):
        ap.error("--min-distance and --baseline-fb must be positive, --new-rows in (0, 1], "
                 "--margin not negative")
    if a.max_frames is not None and a.max_frames < 2:
        ap.error(f"--max-frames must be at least 2, got {a.max_frames}")
    if a.baseline_out and a.opencv_baseline is None:
        ap.error("--baseline-out needs --opencv-baseline N")
    if cv2 is None or yaml is None:
        print(f"{TOOL}: needs python3-opencv and python3-yaml (tools/setup.sh installs them)",
              file=sys.stderr)
        return 3
    try:
        ds = Dataset(a.dataset, a.max_frames)
        ref = ReferenceGeometry(ds)
        sets = {}
        if a.tracks is not None:
            name = os.path.basename(a.tracks)
            sets[name] = read_tracks(a.tracks, ds)
            if not sets[name]:
                raise InputError(f"{a.tracks}: no observation within the dataset's frames")
        if a.opencv_baseline is not None:
            sets[f"opencv N={a.opencv_baseline}"] = opencv_baseline(
                ds, a.opencv_baseline, refill, a.min_distance, a.new_rows, a.baseline_fb)
        results = {}
        for name, tracks in sets.items():
            print(f"{TOOL}: measuring {name} ({len(tracks)} tracks)", file=sys.stderr, flush=True)
            results[name] = measure(ds, tracks, ref, a.margin)
            if a.why_ended:
                results[name]["why_ended"] = why_ended(ds, tracks, a.margin, a.min_ncc)
    except InputError as e:
        print(f"{TOOL}: {e}", file=sys.stderr)
        return 1
    if a.baseline_out:
        try:
            write_tracks(a.baseline_out, ds, sets[f"opencv N={a.opencv_baseline}"])
        except OSError as e:
            print(f"{TOOL}: cannot write {a.baseline_out}: {e}", file=sys.stderr)
            return 1
    reference = ref.summary()
    if a.json:
        json.dump({"dataset": a.dataset, "margin_px": a.margin, "results": results,
                   "reference": reference}, sys.stdout, indent=1)
        print()
    else:
        print_table(results, reference)
        for name, r in results.items():
            if "why_ended" in r:
                print_why_ended(name, r["why_ended"], a.min_ncc)
    return 0


if __name__ == "__main__":
    sys.exit(main())
