#!/usr/bin/python3
"""The demo's summary: SLAM against dead reckoning from two cleanslam-eval --json files.

  tools/eval/demo_summary.py SLAM.json DEAD_RECKONING.json

The ATE printed is cleanslam-eval's (3-D RMSE, --align none), the one plot_run.py shows too.
"""

import json
import sys

from cleanslam_eval import nees_note

ROWS = [("ATE RMSE [m]", "ate_rmse_m"), ("final position error [m]", "final_error_m"),
        ("orientation RMSE [deg]", "orientation_rmse_deg"),
        ("RPE per metre [m/m]", "rpe_translation_per_m"),
        ("RPE per metre [deg/m]", "rpe_rotation_deg_per_m")]
VERDICT_WORDS = {"overconfident": "the errors are larger than the covariance claims",
                 "conservative": "the covariance claims larger errors than there are",
                 "consistent": "the errors match the covariance"}


def summary(slam, dr):
    lines = [f"{'':28s}{'SLAM':>12s}{'dead reckoning':>18s}"]
    for label, key in ROWS:
        if key in slam and key in dr:
            lines.append(f"{label:28s}{slam[key]:12.4f}{dr[key]:18.4f}")
    lines.append(f"{'poses evaluated':28s}{slam['poses_evaluated']:12d}"
                 f"{dr['poses_evaluated']:18d}")
    if "path_length_m" in slam:
        lines.append(f"{'path length [m]':28s}{slam['path_length_m']:12.2f}")
    lines.append("SLAM is evaluated at the processed frames; dead reckoning (wheels and gyro "
                 "alone) at every")
    lines.append("published pose (loop.publish_rate_hz): the same time stamps in images and "
                 "features mode.")
    lines.append("ATE: cleanslam-eval's 3-D RMSE with --align none, the figure the plots show.")
    if slam.get("nees_ratio") is not None:
        lines.append(f"position NEES: {slam['nees_mean']:.2f}, {slam['nees_ratio']:.2f} x its "
                     f"consistent value 3 (95 % band {slam['nees_ratio_low']:.2f}-"
                     f"{slam['nees_ratio_high']:.2f}): {slam['nees_verdict']}")
        lines.append(f"  ({VERDICT_WORDS.get(slam['nees_verdict'], '')}; "
                     f"{100 * slam['nees_fraction_in_95']:.0f} % of poses inside their own 95 % "
                     "bounds)")
        lines.append(f"  {nees_note.POSITION}")
    if slam.get("ate_rmse_m") and dr.get("ate_rmse_m"):
        lines.append(f"SLAM ATE is {dr['ate_rmse_m'] / slam['ate_rmse_m']:.1f}x smaller than "
                     "dead reckoning's")
    return "\n".join(lines)


def main(argv):
    if len(argv) != 3:
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    loaded = []
    for path in argv[1:]:
        try:
            with open(path, encoding="utf-8") as f:
                loaded.append(json.load(f))
        except (OSError, ValueError) as e:
            print(f"demo_summary: {path}: {e}", file=sys.stderr)
            return 1
    print(summary(*loaded))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
