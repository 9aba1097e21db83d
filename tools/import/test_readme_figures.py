"""The importer README's table of dataset 6 is what its command prints: tools/eval/real_table.py
--no-bound (every robot, both gyro choices, seed 1, the defaults) is run and each row, less the
run-time column, must be the README's. The programs from $CLEANSLAM_BIN; extra cleanslam-replay
settings from $CLEANSLAM_REPLAY_SETS (space-separated section.key=value), to see the test fail;
skipped when ../shared/data/mrclam or the programs are absent."""

import os
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
pytestmark = [
    pytest.mark.skipif(DATA is None, reason="../shared/data/mrclam/MRCLAM_Dataset6 is absent"),
    pytest.mark.skipif(not all(os.access(os.path.join(BIN, f"cleanslam-{p}"), os.X_OK)
                               for p in ("replay", "eval")),
                       reason="CLEANSLAM_BIN has no cleanslam-replay and cleanslam-eval"),
]


def readme_rows():
    with open(README, encoding="utf-8") as f:
        text = f.read()
    start = text.index(BEGIN)
    block = text[text.index("\n", start) + 1:text.index(END, start)]
    return [line for line in block.splitlines() if line.startswith("|")]


def without_run_time(line):
    cells = line.split("|")
    return "|".join(cells[:-2]) + "|"


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
