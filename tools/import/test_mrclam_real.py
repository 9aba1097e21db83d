"""tools/import/mrclam.py on robot 1 of the real MRCLAM dataset 6, both gyro choices: what it
keeps and drops, what it measures against Vicon, and that cleanslam-replay reads the result.
cleanslam-replay from $CLEANSLAM_BIN; skipped when ../shared/data/mrclam or the program is
absent."""

import os
import re
import subprocess
import sys

import mrclam_data
import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = mrclam_data.dataset6()
REPLAY = os.path.join(os.environ.get("CLEANSLAM_BIN", ""), "cleanslam-replay")
pytestmark = [
    pytest.mark.skipif(DATA is None, reason="../shared/data/mrclam/MRCLAM_Dataset6 is absent"),
    pytest.mark.skipif(not os.access(REPLAY, os.X_OK),
                       reason="CLEANSLAM_BIN has no cleanslam-replay"),
]


def number(pattern, text):
    m = re.search(pattern, text)
    assert m is not None, f"'{pattern}' in the output"
    return float(m.group(1))


@pytest.mark.parametrize("gyro", ["commanded", "mems"])
def test_import_robot_1(tmp_path, gyro):
    out = str(tmp_path / gyro)
    p = subprocess.run([sys.executable, os.path.join(HERE, "mrclam.py"), DATA, "1", out,
                        "--gyro", gyro], capture_output=True, text=True, check=False)
    assert p.returncode == 0, p.stderr
    # Robot 1 sees the other robots (407 of its 1942 sightings in the published files).
    assert number(r"(\d+) other robots", p.stderr) > 100
    assert 500 < number(r"(\d+) frames at least", p.stderr) < 1000
    assert 0.05 <= number(r"commands lag the motion by ([0-9.]+) s", p.stderr) <= 0.3
    assert 0.7 < number(r"Vicon = ([0-9.]+) x the commanded turn", p.stderr) < 1.0
    assert 3.0 < number(r"spread ([0-9.]+) mrad", p.stderr) < 30.0
    f = np.loadtxt(os.path.join(out, "features.csv"), delimiter=",", comments="#", ndmin=2)
    assert set(f[:, 1].astype(int)) <= set(range(6, 21)), "track ids are landmark subjects"
    assert np.all(np.diff(np.unique(f[:, 0])) >= 0.45e9 - 1), "frames at least 0.45 s apart"
    assert np.all((f[:, 2] >= -0.5) & (f[:, 2] <= 319.5)), "pixels inside the image"
    r = subprocess.run([REPLAY, out, "--out", str(tmp_path / f"run_{gyro}")],
                       capture_output=True, text=True, check=False)
    assert r.returncode == 0, r.stderr[-400:]
    assert "unknown key" not in r.stderr
