"""The tool tests' checks: each failed one is printed and counted, and the test ends with
exit_status()."""
import sys

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print(f"FAIL: {what}", file=sys.stderr)


def near(value, expected, tol, what):
    check(value is not None and abs(value - expected) <= tol,
          f"{what}: {value}, expected {expected} +- {tol}")


def exit_status():
    if failures:
        print(f"{len(failures)} check(s) failed", file=sys.stderr)
        return 1
    return 0
