"""tools/eval/track_quality.py on a sequence made here: a textured image in two layers moving
sideways by known amounts (2 and 5 px per frame, so the geometry has a unique fundamental matrix
with horizontal epipolar lines), with tracks written so that some end mid-image, some at the
border, one is still seen in the last frame, one skips a frame and one jumps 3 px across its
epipolar line (Sampson distance 3 / sqrt(2) px). Every metric is checked against its value worked
out by hand, and --why-ended's appearance figures; then the OpenCV baseline on the same images,
its --baseline-out tracks measured again, and bad input. Skipped without python3-opencv or
python3-yaml."""

import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

cv2 = pytest.importorskip("cv2", reason="python3-opencv (tools/setup.sh)")
pytest.importorskip("yaml", reason="python3-yaml (tools/setup.sh), which the tool needs")

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
    assert p.returncode == 0, p.stderr[-500:]
    return json.loads(p.stdout)


@pytest.fixture(scope="module")
def sequence(tmp_path_factory):
    work = str(tmp_path_factory.mktemp("track_quality"))
    ds = os.path.join(work, "dataset")
    make_dataset(ds)
    tracks = os.path.join(work, "tracks.csv")
    make_tracks(tracks)
    return work, ds, tracks


def test_metrics(sequence):
    _, ds, tracks = sequence
    out = run_json(ds, tracks)
    r = out["results"]["tracks.csv"]
    assert r["frames"] == FRAMES
    assert r["tracks"] == 6
    assert r["ended_mid_image"] == 3  # 2, 4, 6
    assert r["ended_at_border"] == 2  # 3, 5
    assert r["seen_in_last_frame"] == 1
    # Tracked in frames 1..9: 5 4 6 4 2 2 2 2 1.
    assert r["tracked_per_frame_median"] == 2.0
    assert r["tracked_per_frame_min"] == 1
    assert r["tracked_per_frame_mean"] == pytest.approx(28.0 / 9.0, abs=1e-9)
    # Lengths 10 5 5 7 4 3.
    assert r["track_length_median"] == 5.0
    assert r["track_length_p90"] == pytest.approx(8.5, abs=1e-9)
    assert r["correspondences"] == 27
    assert r["correspondences_unscored"] == 0
    assert r["correspondences_across_gaps"] == 1  # the gap of track 6
    assert r["sampson_px_median"] == pytest.approx(0.0, abs=0.05)
    assert r["sampson_px_p95"] == pytest.approx(0.0, abs=0.05)
    assert r["sampson_px_max"] == pytest.approx(3.0 / math.sqrt(2.0), abs=0.05)
    worst = r["worst"][0]
    assert (worst["track_id"], worst["t_ns"]) == (4, T0_NS + 5 * DT_NS)
    assert out["reference"]["pairs_fitted"] == FRAMES - 1


def test_why_ended(sequence):
    _, ds, tracks = sequence
    # Tracks 2 and 6 were lost though their windows still match the first sighting exactly;
    # track 4 follows another point since its jump, 3 px from the one first seen.
    w = run_json(ds, tracks, "--why-ended")["results"]["tracks.csv"]["why_ended"]
    ended = {r["track_id"]: r for r in w["tracks"]}
    assert sorted(ended) == [2, 4, 6] and w["lk_followed"] == 3
    for tid in (2, 6):
        assert all(ended[tid][k] > 0.99
                   for k in ("ncc_first_last", "ncc_first_next", "ncc_last_next")), ended[tid]
    r = ended[4]
    assert r["ncc_first_last"] < 0.7 and r["ncc_first_next"] < 0.7 and r["ncc_last_next"] > 0.99
    assert w["ncc_first_next_below_min"] == 1 and w["ncc_last_next_at_least_min"] == 3


def test_margin_and_max_frames(sequence):
    _, ds, tracks = sequence
    # The margin decides border against mid-image: at 9 px track 3 (10.5 px in) ends mid-image,
    # track 5 (8.5 px in) still at the border.
    r9 = run_json(ds, tracks, "--margin", "9")
    assert r9["results"]["tracks.csv"]["ended_mid_image"] == 4
    # --max-frames 5: frame 4 is the last, so tracks 2 and 3 are seen in it.
    m = run_json(ds, tracks, "--max-frames", "5")["results"]["tracks.csv"]
    assert (m["frames"], m["seen_in_last_frame"], m["ended_mid_image"]) == (5, 4, 1)


def test_opencv_baseline(sequence):
    work, ds, tracks = sequence
    # OpenCV's tracks on the same images: the textures move rigidly, so they are geometrically
    # exact.
    base_csv = os.path.join(work, "baseline.csv")
    o = run_json(ds, tracks, "--opencv-baseline", "20", "--baseline-out",
                 base_csv)["results"]["opencv N=20"]
    assert o["tracks"] >= 20
    assert o["tracked_per_frame_min"] >= 12
    assert o["sampson_px_median"] < 0.05
    # Corners on the line where the layers meet are no physical point: LK slides along it. They
    # are the worst correspondences.
    rows = np.loadtxt(base_csv, delimiter=",", comments="#", ndmin=2)
    for w in o["worst"]:
        at = rows[(rows[:, 0] == w["t_ns"]) & (rows[:, 1] == w["track_id"])]
        assert len(at) == 1 and abs(at[0, 3] - SPLIT_ROW) < 6 and w["sampson_px"] > 0.1, (w, at)
    assert o["correspondences_across_gaps"] == 0
    a = run_json(ds, base_csv)["results"]["baseline.csv"]
    for key in ("tracks", "ended_mid_image", "tracked_per_frame_median",
                "tracked_per_frame_min", "track_length_median", "correspondences"):
        assert a[key] == o[key], key


def test_text_output(sequence):
    _, ds, tracks = sequence
    p = run(ds, tracks)
    assert p.returncode == 0 and "ended mid-image" in p.stdout and "3 (50 %)" in p.stdout
    assert "track 4 at t_ns 3500000000: 2.1" in p.stdout
    assert "Sampson residuals" in p.stderr


def test_bad_input(sequence):
    work, ds, tracks = sequence
    # Bad input names the file (and line); bad arguments exit 2.
    missing = os.path.join(work, "missing.csv")
    p = run(ds, missing)
    assert p.returncode == 1 and missing in p.stderr
    bad = os.path.join(work, "bad.csv")
    with open(bad, "w", encoding="utf-8") as f:
        f.write("#t_ns,track_id,u_px,v_px\n1000000000,1,10.0,20.0\n1000000001,1,10.0,20.0\n")
    p = run(ds, bad)
    assert p.returncode == 1 and f"{bad}:3" in p.stderr and "1000000001" in p.stderr
    with open(bad, "w", encoding="utf-8") as f:
        f.write("1000000000,1,ten,20.0\n")
    p = run(ds, bad)
    assert p.returncode == 1 and f"{bad}:1" in p.stderr
    assert run(ds).returncode == 2
    p = run(os.path.join(work, "nowhere"), tracks)
    assert p.returncode == 1 and "nowhere" in p.stderr
