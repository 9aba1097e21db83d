"""Shared by the Python replay tests: their arguments (EMULATOR, which may be empty, BIN_DIR,
WORK_DIR), a clean work folder, and checks that are collected and printed as they fail."""

import os
import shutil
import sys


def arguments():
    emulator, bin_dir, work = sys.argv[1], sys.argv[2], sys.argv[3]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    return emulator, bin_dir, work


class Checks:
    def __init__(self):
        self.failures = []

    def __call__(self, cond, what):
        if not cond:
            self.failures.append(what)
            print(f"FAIL: {what}", file=sys.stderr)
