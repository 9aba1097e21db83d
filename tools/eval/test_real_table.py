"""real_table.py: rows written as they finish and kept when stopped, and a plot that says what it
draws, on runs faked here (no MRCLAM data, no programs)."""
import os
import signal
import subprocess
import sys
import time

import pytest
import real_table

HERE = os.path.dirname(os.path.abspath(__file__))
ROW = {"path_length_m": 10.0, "dr_ate_m": 0.5, "slam_ate_m": 0.25, "nees_per_dof": 1.5,
       "run_time_s": 1.0}
# real_table.main with its runs faked: robot 1 finishes at once, the others run a program that
# takes 30 s.
DRIVER = f"""
import sys
import real_table


def run(tools, data, robot, gyro, *args, **kwargs):
    if robot > 1:
        real_table.mc._exec(["sleep", "30"], [], None)
    return dict({ROW!r})


real_table.run = run
real_table.find_tools = lambda bin_dir: {{}}
sys.exit(real_table.main(sys.argv[1:]))
"""


def wait_for(path, text, seconds=20.0):
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        if os.path.exists(path):
            with open(path, encoding="utf-8") as f:
                if text in f.read():
                    return True
        time.sleep(0.1)
    return False


@pytest.mark.parametrize("stop", [signal.SIGTERM, signal.SIGINT])
def test_stopped_run_keeps_the_finished_rows(tmp_path, stop):
    out = tmp_path / "out"
    p = subprocess.Popen(
        [sys.executable, "-c", DRIVER, "--data", str(tmp_path), "--robots", "1-3", "--gyro",
         "mems", "--no-bound", "--jobs", "1", "--out", str(out)],
        cwd=HERE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    table = str(out / "table.md")
    try:
        assert wait_for(table, "| 1 | mems | 10.0 | 0.500 | **0.250** | 1.5 |"), \
            "the finished row is not written while the others run"
        start = time.monotonic()
        p.send_signal(stop)
        stdout, stderr = p.communicate(timeout=20)
    finally:
        p.kill()
    assert time.monotonic() - start < 10, "the running program was not ended"
    assert p.returncode == 128 + stop.value
    assert f"stopped by {stop.name}: 1 of 3 runs finished" in stderr
    assert "real_table: | 1 | mems | 10.0 |" in stderr
    assert "[1/3] import, replay (1, 'mems') done" in stderr
    with open(table, encoding="utf-8") as f:
        written = f.read()
    for text in (written, stdout):
        assert "| 1 | mems | 10.0 |" in text
        assert "| 2 | mems | not finished |" in text and "| 3 | mems | not finished |" in text


def drawn(monkeypatch, tmp_path, results):
    """The figure real_table.plot draws (caught before it is closed)."""
    import matplotlib.pyplot as plt
    from matplotlib.figure import Figure
    figures = []
    monkeypatch.setattr(plt, "close", lambda fig=None: figures.append(fig))
    real_table.plot([1, 2], ["mems"], results, str(tmp_path / "real.png"))
    return next(f for f in figures if isinstance(f, Figure))


def labelled(ax):
    lo, hi = ax.get_ylim()
    ticks = [t for t in ax.yaxis.get_major_locator()() if lo * 0.999 <= t <= hi * 1.001]
    labels = ax.yaxis.get_major_formatter().format_ticks(ticks)
    return [t for t, label in zip(ticks, labels) if label]


def test_plot_without_the_bound_says_so(monkeypatch, tmp_path):
    results = {(1, "mems"): dict(ROW, slam_ate_m=3.3, dr_ate_m=0.8),
               (2, "mems"): dict(ROW, slam_ate_m=0.12, nees_per_dof=40.0)}
    fig = drawn(monkeypatch, tmp_path, results)
    ax_ate = fig.axes[0]
    assert "bound" not in ax_ate.get_title() and "bound" not in ax_ate.get_ylabel()
    assert "[m]" in ax_ate.get_ylabel()
    for ax in fig.axes:
        lo, hi = ax.get_ylim()
        ticks = labelled(ax)
        assert min(ticks) <= lo * 1.001 and max(ticks) >= hi * 0.999, (ax.get_ylim(), ticks)


def test_plot_with_the_bound_says_so(monkeypatch, tmp_path):
    results = {(1, "mems"): dict(ROW, filtering_sd_m=0.1, full_slam_ate_m=0.2),
               (2, "mems"): dict(ROW)}
    ax_ate = drawn(monkeypatch, tmp_path, results).axes[0]
    assert "full-SLAM bound" in ax_ate.get_title() and "bound" in ax_ate.get_ylabel()


def test_table_explains_its_nees():
    text = real_table.markdown([1], ["mems"], {(1, "mems"): dict(ROW)}, {}, False, [])
    assert "NEES per degree of freedom: 1 when the covariance is honest" in text
    assert "tools/eval/README.md" in text
