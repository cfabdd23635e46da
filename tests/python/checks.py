"""A line per check ("ok   ..." or "FAIL ..."), and the exit code of all
of them (the test scripts of tests/python; pvpython imports it too)."""
import sys

failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def finish():
    sys.exit(1 if failures else 0)
