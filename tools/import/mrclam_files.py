"""The files of one UTIAS MRCLAM dataset folder (Leung et al., IJRR 30(8), 2011), read strictly:
an error names the file and line at fault."""

import math
import os

import numpy as np


class InputError(Exception):
    pass


def read_table(path, columns, names):
    """Rows of whitespace-separated numbers; '#' lines and blank lines skipped. Returns an
    (N, columns) array and the line number of each row."""
    rows, lines = [], []
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            for n, line in enumerate(f, 1):
                body = line.strip()
                if not body or body.startswith("#"):
                    continue
                fields = body.split()
                if len(fields) != columns:
                    raise InputError(f"{path}:{n}: expected {columns} fields ({', '.join(names)}), "
                                     f"got {len(fields)}: {body[:60]!r}")
                row = []
                for name, text in zip(names, fields):
                    try:
                        v = float(text)
                    except ValueError:
                        v = math.nan
                    if not math.isfinite(v):
                        raise InputError(f"{path}:{n}: {name}: expected a finite number, got "
                                         f"{text[:40]!r}")
                    row.append(v)
                rows.append(row)
                lines.append(n)
    except OSError as e:
        raise InputError(f"{path}: {e.strerror or e}") from None
    if not rows:
        raise InputError(f"{path}: no data rows")
    return np.array(rows, dtype=float), lines


def check_sorted(path, table, lines):
    """Time stamps (column 0) must not decrease; equal stamps are allowed (the published odometry
    repeats some)."""
    bad = np.nonzero(np.diff(table[:, 0]) < 0)[0]
    if len(bad):
        k = bad[0] + 1
        raise InputError(f"{path}:{lines[k]}: time {table[k, 0]:.3f} is before the previous row's "
                         f"{table[k - 1, 0]:.3f} (rows must be sorted by time)")


def last_of_equal_stamps(table):
    """Of rows with the same time stamp, the last."""
    keep = np.append(np.diff(table[:, 0]) > 0, True)
    return table[keep]


def integer_column(path, table, lines, col, name):
    v = table[:, col]
    bad = np.nonzero(v != np.round(v))[0]
    if len(bad):
        raise InputError(f"{path}:{lines[bad[0]]}: {name}: expected an integer, got {v[bad[0]]}")
    return v.astype(np.int64)


class Mrclam:
    """One robot of a MRCLAM dataset: odometry (t, v, w), Vicon track (t, x, y, heading),
    sightings (t, barcode, range, bearing), barcodes {barcode: subject} and the landmarks' true
    positions {subject: (x, y)}."""

    def __init__(self, folder, robot):
        if not os.path.isdir(folder):
            raise InputError(f"{folder}: not a folder")
        self.folder, self.robot = folder, robot
        p = os.path.join(folder, "Barcodes.dat")
        t, ln = read_table(p, 2, ["subject", "barcode"])
        subjects = integer_column(p, t, ln, 0, "subject")
        codes = integer_column(p, t, ln, 1, "barcode")
        self.barcodes = {}
        for s, c, n in zip(subjects, codes, ln):
            if int(c) in self.barcodes:
                raise InputError(f"{p}:{n}: barcode {c} is given twice")
            self.barcodes[int(c)] = int(s)
        p = os.path.join(folder, "Landmark_Groundtruth.dat")
        t, ln = read_table(p, 5, ["subject", "x", "y", "x std-dev", "y std-dev"])
        subjects = integer_column(p, t, ln, 0, "subject")
        self.landmarks = {int(s): (float(r[1]), float(r[2])) for s, r in zip(subjects, t)}
        base = os.path.join(folder, f"Robot{robot}_")
        p = base + "Odometry.dat"
        t, ln = read_table(p, 3, ["time", "forward velocity", "angular velocity"])
        check_sorted(p, t, ln)
        self.odometry = last_of_equal_stamps(t)
        p = base + "Groundtruth.dat"
        t, ln = read_table(p, 4, ["time", "x", "y", "orientation"])
        check_sorted(p, t, ln)
        self.groundtruth = last_of_equal_stamps(t)
        p = base + "Measurement.dat"
        t, ln = read_table(p, 4, ["time", "barcode", "range", "bearing"])
        check_sorted(p, t, ln)
        integer_column(p, t, ln, 1, "barcode")
        self.sightings = t
        for name, a in (("Odometry", self.odometry), ("Groundtruth", self.groundtruth)):
            if len(a) < 2:
                raise InputError(f"{base}{name}.dat: fewer than two time stamps")
