"""A line per check ("ok   ..." or "FAIL ..."), and the exit code of all
of them (the test scripts of tests/python; pvpython imports it too). A
check that cannot run on this machine fails, saying why, unless the
environment sets RPFEM_ALLOW_SKIP=1 (docs/testing.md)."""
import os
import sys
import unittest

failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def finish():
    sys.exit(1 if failures else 0)


def skip_allowed():
    return os.environ.get("RPFEM_ALLOW_SKIP", "0") == "1"


def cannot_check(what):
    """A check that cannot run here: skipped where allowed, else failed."""
    if skip_allowed():
        print("skipped: %s (RPFEM_ALLOW_SKIP=1)" % what)
    else:
        check(False, "cannot run: %s (RPFEM_ALLOW_SKIP=1 skips it)" % what)


def cannot_test(what):
    """The same in a unittest test (or its setUpClass): raises its skip
    where allowed, else its failure."""
    if skip_allowed():
        raise unittest.SkipTest(what + " (RPFEM_ALLOW_SKIP=1)")
    raise AssertionError("cannot run: %s (RPFEM_ALLOW_SKIP=1 skips it)" % what)
