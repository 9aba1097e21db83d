"""The importer README's figures of dataset 6 are what their commands print: its sentence on the
calibration, from `mrclam.py DATASET N --calibrate` for robots 1-5, must be the one the
figures printed make; its table, from tools/eval/real_table.py --no-bound (every robot, both
gyro choices, seed 1, the defaults), must have each row as printed, less the run-time column. The
programs from $CLEANSLAM_BIN; extra cleanslam-replay settings from $CLEANSLAM_REPLAY_SETS
(space-separated section.key=value), to see the test fail; skipped when ../shared/data/mrclam or
the programs are absent."""

import os
import re
import subprocess
import sys

import mrclam_data
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
REAL_TABLE = os.path.join(HERE, "..", "eval", "real_table.py")
README = os.path.join(HERE, "README.md")
BEGIN = "<!-- checked by test_readme_figures.py"
END = "<!-- end of the checked table -->"
DATA = mrclam_data.dataset6()
BIN = os.environ.get("CLEANSLAM_BIN", "")
needs_data = pytest.mark.skipif(DATA is None,
                                reason="../shared/data/mrclam/MRCLAM_Dataset6 is absent")
needs_programs = pytest.mark.skipif(
    not all(os.access(os.path.join(BIN, f"cleanslam-{p}"), os.X_OK) for p in ("replay", "eval")),
    reason="CLEANSLAM_BIN has no cleanslam-replay and cleanslam-eval")


def readme_text():
    with open(README, encoding="utf-8") as f:
        return f.read()


def readme_rows():
    text = readme_text()
    start = text.index(BEGIN)
    block = text[text.index("\n", start) + 1:text.index(END, start)]
    return [line for line in block.splitlines() if line.startswith("|")]


def without_run_time(line):
    cells = line.split("|")
    return "|".join(cells[:-2]) + "|"


# What `--calibrate` prints, per robot: the figure's pattern.
CALIBRATION = {
    "lag": r"commands lag the motion by ([-0-9.]+) s",
    "turn": r"Vicon = ([0-9.]+) x the commanded turn",
    "travel": r"and ([0-9.]+) x the commanded distance",
    "raw_heading": r"raw commands: .*heading error over 1 s ([0-9.]+) rad",
    "heading": r"calibrated commands: .*heading error over 1 s ([0-9.]+) rad",
    "rate": r"calibrated commands: mean turn rate error ([-+0-9.]+) mrad/s",
    "distance": r"calibrated commands: .*relative distance error over 1 s ([0-9.]+)",
    "delay": r"camera delay ([-+0-9.]+) s",
    "yaw": r"median error ([-+0-9.]+) mrad",
    "spread": r"spread ([0-9.]+) mrad",
    "spread_px": r"\(([0-9.]+) px at f",
}


def calibration_sentence(figures):
    def span(key, fmt, scale=1.0, key_of=lambda v: v):
        values = sorted((key_of(f[key]) * scale for f in figures), key=float)
        return f"{values[0]:{fmt}}-{values[-1]:{fmt}}"

    def signed(v, fmt):
        return f"{v:{fmt}}".replace("-", "−")

    yaw = sorted(f["yaw"] for f in figures)
    delay = sorted(f["delay"] for f in figures)
    return (f"Dataset 6 (robots 1-5): lag {span('lag', '.2f')} s; Vicon turns "
            f"{span('turn', '.2f')} × and travels {span('travel', '.2f')} × what is commanded; "
            f"calibrated, the heading error over 1 s is {span('heading', '.3f')} rad (raw "
            f"{span('raw_heading', '.3f')}), the mean rate error "
            f"{span('rate', '.1f', key_of=abs)} mrad/s, the relative distance error over 1 s "
            f"still {span('distance', '.0f', 100.0)} %; camera delay {signed(delay[-1], '.2f')} to "
            f"{signed(delay[0], '.2f')} s, yaw {signed(yaw[0], '.0f')} to "
            f"{signed(yaw[-1], '+.0f')} mrad, bearing spread {span('spread', '.1f')} mrad "
            f"({span('spread_px', '.1f')} px).")


@needs_data
def test_the_readme_calibration_figures_are_what_calibrate_prints():
    figures = []
    for robot in range(1, 6):
        p = subprocess.run([sys.executable, os.path.join(HERE, "mrclam.py"), DATA, str(robot),
                            "--calibrate"], capture_output=True, text=True, check=False)
        assert p.returncode == 0, p.stderr[-2000:]
        out = p.stdout + p.stderr
        figures.append({k: float(re.search(v, out).group(1)) for k, v in CALIBRATION.items()})
    want = calibration_sentence(figures)
    have = " ".join(readme_text().split())
    assert want in have, f"tools/import/README.md should say:\n{want}"


@needs_data
@needs_programs
def test_the_readme_table_is_what_its_command_prints(tmp_path):
    sets = [a for kv in os.environ.get("CLEANSLAM_REPLAY_SETS", "").split() for a in ("--set", kv)]
    p = subprocess.run([sys.executable, REAL_TABLE, "--no-bound", "--data", DATA, "--bin", BIN,
                        "--out", str(tmp_path / "runs"), *sets],
                       capture_output=True, text=True, check=False)
    assert p.returncode == 0, p.stderr[-3000:]
    printed = [without_run_time(line) for line in p.stdout.splitlines() if line.startswith("|")]
    expected = readme_rows()
    assert printed[0] == expected[0], "the columns differ"
    drifted = [f"  README:  {e}\n  printed: {g}" for e, g in zip(expected, printed) if e != g]
    assert len(printed) == len(expected) and not drifted, (
        "tools/import/README.md's table is not what `tools/eval/real_table.py --no-bound` "
        "prints; after a change that moves these figures, paste the command's rows there:\n"
        + "\n".join(drifted))
