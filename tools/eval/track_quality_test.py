#!/usr/bin/python3
"""tools/eval/track_quality.py on a sequence made here: a textured image in two layers moving
sideways by known amounts (2 and 5 px per frame, so the geometry has a unique fundamental matrix
with horizontal epipolar lines), with tracks written so that some end mid-image, some at the
border, one is still seen in the last frame, one skips a frame and one jumps 3 px across its
epipolar line (Sampson distance 3 / sqrt(2) px). Every metric is checked against its value worked
out by hand, and --why-ended's appearance figures; then the OpenCV baseline on the same images, its --baseline-out tracks measured
again, and bad input. Exit 77 (skipped) without python3-opencv or python3-yaml.
Argument: WORK_DIR."""

import json
import math
import os
import shutil
import subprocess
import sys

try:
    import cv2
    import yaml  # noqa: F401  (the tool needs it)
except ImportError as e:
    print(f"skipped: {e} (python3-opencv and python3-yaml, tools/setup.sh)")
    sys.exit(77)
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from checks import check, exit_status, near  # noqa: E402

TOOL = os.path.join(os.path.dirname(os.path.abspath(__file__)), "track_quality.py")
W, H, FRAMES = 320, 240, 10
SHIFT_TOP, SHIFT_BOTTOM, SPLIT_ROW = 2, 5, 120
T0_NS, DT_NS = 1_000_000_000, 500_000_000


def make_dataset(root):
    os.makedirs(os.path.join(root, "cam0", "data"))
    with open(os.path.join(root, "sensors.yaml"), "w", encoding="utf-8") as f:
        f.write(f"camera:\n  width: {W}\n  height: {H}\n  fx: 280.0\n  fy: 280.0\n"
                "  cx: 159.5\n  cy: 119.5\n  distortion: [0.0, 0.0, 0.0, 0.0]\n")
    rng = np.random.default_rng(7)
    span = W + SHIFT_BOTTOM * FRAMES

    def texture():
        t = cv2.GaussianBlur(rng.uniform(0, 255, (H, span)), (0, 0), 2.0)
        return cv2.normalize(t, None, 10, 245, cv2.NORM_MINMAX)

    top, bottom = texture(), texture()
    with open(os.path.join(root, "cam0", "data.csv"), "w", encoding="utf-8") as f:
        f.write("#t_ns,filename\n")
        for k in range(FRAMES):
            # Content at canvas column c appears at u = c - shift * k.
            img = np.vstack([top[:SPLIT_ROW, SHIFT_TOP * k:SHIFT_TOP * k + W],
                             bottom[SPLIT_ROW:, SHIFT_BOTTOM * k:SHIFT_BOTTOM * k + W]])
            name = f"{T0_NS + k * DT_NS}.png"
            cv2.imwrite(os.path.join(root, "cam0", "data", name), img.astype(np.uint8))
            f.write(f"{T0_NS + k * DT_NS},{name}\n")


def point(layer_shift, canvas_u, v, k):
    return (canvas_u - layer_shift * k, v)


def make_tracks(path):
    rows = []

    def track(tid, shift, canvas_u, v, frames, jump_from=None):
        for k in frames:
            u, vv = point(shift, canvas_u, v, k)
            if jump_from is not None and k >= jump_from:
                vv += 3.0
            rows.append((T0_NS + k * DT_NS, tid, u, vv))

    track(1, SHIFT_TOP, 200, 60, range(0, 10))  # seen in the last frame
    track(2, SHIFT_TOP, 150, 40, range(0, 5))  # lost mid-image at u 142
    track(3, SHIFT_BOTTOM, 30, 180, range(0, 5))  # ends at u 10: 10.5 px from the border
    track(4, SHIFT_BOTTOM, 260, 200, range(2, 9), jump_from=5)  # 3 px jump, lost mid-image
    track(5, SHIFT_TOP, 100, 8, range(0, 4))  # ends 8.5 px from the top
    track(6, SHIFT_TOP, 280, 100, [0, 1, 3])  # skips frame 2, lost mid-image
    rows.sort()
    with open(path, "w", encoding="utf-8") as f:
        f.write("#t_ns,track_id,u_px,v_px\n")
        for t, tid, u, v in rows:
            f.write(f"{t},{tid},{u:.3f},{v:.3f}\n")


def run(*args):
    return subprocess.run([sys.executable, TOOL, *args], stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True, check=False)


def run_json(*args):
    p = run(*args, "--json")
    check(p.returncode == 0, f"{' '.join(args)}: exit {p.returncode}: {p.stderr[-500:]}")
    return json.loads(p.stdout) if p.returncode == 0 else None


work = sys.argv[1]
shutil.rmtree(work, ignore_errors=True)
ds = os.path.join(work, "dataset")
make_dataset(ds)
tracks = os.path.join(work, "tracks.csv")
make_tracks(tracks)

out = run_json(ds, tracks)
r = out["results"]["tracks.csv"] if out else {}
check(r.get("frames") == FRAMES, f"frames {r.get('frames')}")
check(r.get("tracks") == 6, f"tracks {r.get('tracks')}")
check(r.get("ended_mid_image") == 3, f"ended mid-image {r.get('ended_mid_image')} (2, 4, 6)")
check(r.get("ended_at_border") == 2, f"ended at the border {r.get('ended_at_border')} (3, 5)")
check(r.get("seen_in_last_frame") == 1, f"seen in the last frame {r.get('seen_in_last_frame')}")
# Tracked in frames 1..9: 5 4 6 4 2 2 2 2 1.
check(r.get("tracked_per_frame_median") == 2.0, f"tracked median {r.get('tracked_per_frame_median')}")
check(r.get("tracked_per_frame_min") == 1, f"tracked min {r.get('tracked_per_frame_min')}")
near(r.get("tracked_per_frame_mean"), 28.0 / 9.0, 1e-9, "tracked mean")
# Lengths 10 5 5 7 4 3.
check(r.get("track_length_median") == 5.0, f"length median {r.get('track_length_median')}")
near(r.get("track_length_p90"), 8.5, 1e-9, "length p90")
check(r.get("correspondences") == 27, f"correspondences {r.get('correspondences')}")
check(r.get("correspondences_unscored") == 0, "unscored correspondences")
check(r.get("correspondences_across_gaps") == 1, "the gap of track 6")
near(r.get("sampson_px_median"), 0.0, 0.05, "Sampson median")
near(r.get("sampson_px_p95"), 0.0, 0.05, "Sampson p95")
near(r.get("sampson_px_max"), 3.0 / math.sqrt(2.0), 0.05, "Sampson of the 3 px jump")
worst = r.get("worst", [{}])[0]
check(worst.get("track_id") == 4 and worst.get("t_ns") == T0_NS + 5 * DT_NS,
      f"worst correspondence {worst}: expected track 4 at frame 5")
if out:
    ref = out["reference"]
    check(ref["pairs_fitted"] == FRAMES - 1, f"reference F fitted for {ref['pairs_fitted']} pairs")

# --why-ended: tracks 2 and 6 were lost though their windows still match the first sighting
# exactly; track 4 follows another point since its jump, 3 px from the one first seen.
w = run_json(ds, tracks, "--why-ended")
w = w["results"]["tracks.csv"].get("why_ended", {}) if w else {}
ended = {r["track_id"]: r for r in w.get("tracks", [])}
check(sorted(ended) == [2, 4, 6] and w.get("lk_followed") == 3, f"--why-ended tracks {sorted(ended)}")
for tid in (2, 6):
    r = ended.get(tid, {})
    check(all(r.get(k, 0) > 0.99 for k in ("ncc_first_last", "ncc_first_next", "ncc_last_next")),
          f"--why-ended track {tid}: {r}")
r = ended.get(4, {})
check(r.get("ncc_first_last", 1) < 0.7 and r.get("ncc_first_next", 1) < 0.7 and
      r.get("ncc_last_next", 0) > 0.99, f"--why-ended track 4: {r}")
check(w.get("ncc_first_next_below_min") == 1 and w.get("ncc_last_next_at_least_min") == 3,
      f"--why-ended counts: {w.get('ncc_first_next_below_min')}, "
      f"{w.get('ncc_last_next_at_least_min')}")

# The margin decides border against mid-image: at 9 px track 3 (10.5 px in) ends mid-image,
# track 5 (8.5 px in) still at the border.
r9 = run_json(ds, tracks, "--margin", "9")
check(r9 is not None and r9["results"]["tracks.csv"]["ended_mid_image"] == 4, "--margin 9")
# --max-frames 5: frame 4 is the last, so tracks 2 and 3 are seen in it.
r5 = run_json(ds, tracks, "--max-frames", "5")
if r5:
    m = r5["results"]["tracks.csv"]
    check(m["frames"] == 5 and m["seen_in_last_frame"] == 4 and m["ended_mid_image"] == 1,
          f"--max-frames 5: {m['frames']} frames, {m['seen_in_last_frame']} in the last, "
          f"{m['ended_mid_image']} mid-image")

# OpenCV's tracks on the same images: the textures move rigidly, so they are geometrically exact.
base_csv = os.path.join(work, "baseline.csv")
b = run_json(ds, tracks, "--opencv-baseline", "20", "--baseline-out", base_csv)
if b:
    o = b["results"]["opencv N=20"]
    check(o["tracks"] >= 20, f"baseline tracks {o['tracks']}")
    check(o["tracked_per_frame_min"] >= 12, f"baseline tracked min {o['tracked_per_frame_min']}")
    check(o["sampson_px_median"] < 0.05, f"baseline Sampson median {o['sampson_px_median']}")
    # Corners on the line where the layers meet are no physical point: LK slides along it. They
    # are the worst correspondences.
    rows = np.loadtxt(base_csv, delimiter=",", comments="#", ndmin=2)
    for w in o["worst"]:
        at = rows[(rows[:, 0] == w["t_ns"]) & (rows[:, 1] == w["track_id"])]
        check(len(at) == 1 and abs(at[0, 3] - SPLIT_ROW) < 6 and w["sampson_px"] > 0.1,
              f"baseline worst correspondence {w} is not on the layer boundary: {at}")
    check(o["correspondences_across_gaps"] == 0, "baseline tracks have no gaps")
    again = run_json(ds, base_csv)
    if again:
        a = again["results"]["baseline.csv"]
        for key in ("tracks", "ended_mid_image", "tracked_per_frame_median",
                    "tracked_per_frame_min", "track_length_median", "correspondences"):
            check(a[key] == o[key], f"--baseline-out measured again: {key} {a[key]} != {o[key]}")

# Text output: the table and the worst correspondence.
p = run(ds, tracks)
check(p.returncode == 0 and "ended mid-image" in p.stdout and "3 (50 %)" in p.stdout,
      f"text table: {p.stdout[:400]}")
check("track 4 at t_ns 3500000000: 2.1" in p.stdout, "text names the worst correspondence")
check("Sampson residuals" in p.stderr, "progress on stderr")

# Bad input names the file (and line); bad arguments exit 2.
missing = os.path.join(work, "missing.csv")
p = run(ds, missing)
check(p.returncode == 1 and missing in p.stderr, f"missing tracks: {p.returncode} {p.stderr}")
bad = os.path.join(work, "bad.csv")
with open(bad, "w", encoding="utf-8") as f:
    f.write("#t_ns,track_id,u_px,v_px\n1000000000,1,10.0,20.0\n1000000001,1,10.0,20.0\n")
p = run(ds, bad)
check(p.returncode == 1 and f"{bad}:3" in p.stderr and "1000000001" in p.stderr,
      f"unknown frame time: {p.returncode} {p.stderr}")
with open(bad, "w", encoding="utf-8") as f:
    f.write("1000000000,1,ten,20.0\n")
p = run(ds, bad)
check(p.returncode == 1 and f"{bad}:1" in p.stderr, f"bad number: {p.returncode} {p.stderr}")
p = run(ds)
check(p.returncode == 2, f"neither tracks nor baseline: exit {p.returncode}")
p = run(os.path.join(work, "nowhere"), tracks)
check(p.returncode == 1 and "nowhere" in p.stderr, f"missing dataset: {p.stderr}")

if exit_status():
    sys.exit(1)
print("track_quality: all checks passed")
