#!/usr/bin/python3
"""Plots a CSV written by cleanslam-paper: plot_paper.py FIGURE CSV PNG (FIGURE: fig7..fig10)."""
import csv
import math
import sys

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Ellipse
except ImportError as e:
    sys.exit(f"{sys.argv[0]}: {e} for {sys.executable}; install python3-matplotlib, "
             "or point CLEANSLAM_PYTHON at a python3 that has it")


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise ValueError(f"{path}: no rows")
    return [{k: float(v) for k, v in row.items()} for row in rows]


def fig10(rows, ax):
    x = [r["true_depth_cm"] for r in rows]
    for column, label, style in [
        ("proposed_cm", "proposed", "o-"),
        ("conventional_cm", "conventional", "s-"),
        ("inverse_depth_cm", "inverse depth", "^-"),
        ("multi_hypothesis_cm", "multiple hypothesis", "d-"),
    ]:
        ax.plot(x, [r[column] for r in rows], style, label=label)
    ax.set_yscale("symlog", linthresh=1e-5)
    ax.set_ylim(bottom=0.0)
    ax.set_xlabel("true depth (cm), assumed depth 1000 cm")
    ax.set_ylabel("landmark position error after one update (cm)")
    ax.set_title("Fig. 10: one-step estimation of a landmark")
    ax.legend()


def fig8(rows, ax):
    for diff in sorted({r["depth_diff_cm"] for r in rows}):
        sel = [r for r in rows if r["depth_diff_cm"] == diff]
        ax.plot([r["ect_cm"] for r in sel], [r["rms_cm"] for r in sel], "o-",
                label=f"assumed - true = {diff:.0f} cm")
    ax.set_xscale("log")
    ax.set_yscale("symlog", linthresh=1e-3)
    ax.set_ylim(bottom=0.0)
    ax.set_xlabel("eps_ct (cm)")
    ax.set_ylabel("RMS landmark error (cm)")
    ax.set_title("Fig. 8: ideal situation, 15 cm forward, one update")
    ax.legend()


def fig9(rows, ax):
    ax.plot([r["ect_cm"] for r in rows], [r["rms_cm"] for r in rows], "o-")
    ax.set_xscale("log")
    ax.set_xlabel("eps_ct (cm)")
    ax.set_ylabel("mean RMS landmark error (cm)")
    ax.set_title("Fig. 9: noise, eleven frames over 150 cm")


def fig7(rows, ax):
    # Top view: forward (world x) up, left (world y) to the left.
    for i, r in enumerate(rows):
        ax.plot(-r["true_y_cm"], r["true_x_cm"], "bD", label="true" if i == 0 else None)
        ax.plot(-r["est_y_cm"], r["est_x_cm"], "ro", mfc="none",
                label="estimated" if i == 0 else None)
        # covariance of (-y, x)
        a, b, c = r["cov_yy_cm2"], -r["cov_xy_cm2"], r["cov_xx_cm2"]
        half = math.sqrt(((a - c) / 2) ** 2 + b * b)
        l1, l2 = (a + c) / 2 + half, max((a + c) / 2 - half, 0.0)
        angle = math.degrees(0.5 * math.atan2(2 * b, a - c))
        ax.add_patch(Ellipse((-r["est_y_cm"], r["est_x_cm"]), 2 * math.sqrt(l1),
                             2 * math.sqrt(l2), angle=angle, fill=False, color="r",
                             label="1 sigma" if i == 0 else None))
    ax.plot([0, -rows[0]["robot_y_cm"]], [0, rows[0]["robot_x_cm"]], "k^-", label="robot")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("right (cm)")
    ax.set_ylabel("forward (cm)")
    ax.set_title("Fig. 7: one update, eps_ct = 1e4 cm, assumed depth 2000 cm")
    ax.legend()


def main(argv):
    plots = {"fig7": fig7, "fig8": fig8, "fig9": fig9, "fig10": fig10}
    if len(argv) != 4 or argv[1] not in plots:
        print(f"usage: {argv[0]} {{{'|'.join(plots)}}} CSV PNG", file=sys.stderr)
        return 2
    try:
        rows = read(argv[2])
    except (OSError, ValueError, KeyError) as e:
        print(f"{argv[0]}: cannot read {argv[2]}: {e}", file=sys.stderr)
        return 1
    fig, ax = plt.subplots(figsize=(8, 6))
    try:
        plots[argv[1]](rows, ax)
    except KeyError as e:
        print(f"{argv[0]}: {argv[2]} lacks column {e} for {argv[1]}", file=sys.stderr)
        return 1
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(argv[3], dpi=100)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
