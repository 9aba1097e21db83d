"""plot_run.py gives the ATE that cleanslam-eval prints (the demo's terminal), on a run whose
height error makes the 3-D error differ from the planar one. Skipped without $CLEANSLAM_EVAL."""
import json
import os
import re
import subprocess
import sys

from test_trajectory import EVAL, needs_eval, write_run

TOOL = os.path.join(os.path.dirname(os.path.abspath(__file__)), "plot_run.py")


@needs_eval
def test_plot_gives_the_terminal_ate(tmp_path):
    (tmp_path / "run").mkdir()
    gt, est = write_run(tmp_path / "run", 4)
    p = subprocess.run([sys.executable, TOOL, str(tmp_path / "run"), "--gt", gt, "--out",
                        str(tmp_path / "plots")], capture_output=True, text=True, check=False)
    assert p.returncode == 0, p.stderr
    m = re.search(r"ATE SLAM ([0-9.]+) m \(3-D RMSE as cleanslam-eval --align none", p.stdout)
    assert m, p.stdout
    want = json.loads(subprocess.run([EVAL, "--gt", gt, "--est", est, "--json"],
                                     capture_output=True, text=True, check=True).stdout)
    assert m.group(1) == f"{want['ate_rmse_m']:.4f}"
