"""The demo's summary explains the NEES it prints and says which ATE it is, on the JSON
cleanslam-eval writes for a run (skipped without $CLEANSLAM_EVAL)."""
import json
import os
import subprocess
import sys

from test_trajectory import EVAL, needs_eval, write_run

TOOL = os.path.join(os.path.dirname(os.path.abspath(__file__)), "demo_summary.py")


@needs_eval
def test_summary_explains_nees_and_names_its_ate(tmp_path):
    gt, est = write_run(tmp_path, 4)
    slam = subprocess.run([EVAL, "--gt", gt, "--est", est, "--json"], capture_output=True,
                          text=True, check=True).stdout
    (tmp_path / "slam.json").write_text(slam)
    (tmp_path / "dr.json").write_text(slam)
    p = subprocess.run([sys.executable, TOOL, str(tmp_path / "slam.json"),
                        str(tmp_path / "dr.json")], capture_output=True, text=True, check=False)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    ate = json.loads(slam)["ate_rmse_m"]
    assert any(line.startswith("ATE RMSE [m]") and f"{ate:.4f}" in line for line in lines)
    assert "ATE: cleanslam-eval's 3-D RMSE with --align none, the figure the plots show." in lines
    nees = [i for i, line in enumerate(lines) if line.startswith("position NEES: ")]
    assert nees, p.stdout
    assert "Position NEES (3 degrees of freedom): 3 on average when the covariance is honest" \
        in p.stdout[p.stdout.index("position NEES: "):]


def test_unreadable_input_names_the_file(tmp_path):
    bad = tmp_path / "slam.json"
    bad.write_text("{not json")
    p = subprocess.run([sys.executable, TOOL, str(bad), str(bad)], capture_output=True, text=True,
                       check=False)
    assert p.returncode == 1
    assert str(bad) in p.stderr
