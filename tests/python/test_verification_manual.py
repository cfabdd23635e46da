"""docs/verification.md against what the checks say (scripts/verification_manual.py);
run by ctest (python.verification_manual):
    /usr/bin/python3 tests/python/test_verification_manual.py

The committed manual is what the script writes today; every check of
verification/checks.toml and every acceptance test is in it; metadata that
does not hold (a test without its block, a tolerance whose number is not
in the test's file, an unknown kind of reference) is refused."""
import glob
import os
import re
import sys
import tempfile
import tomllib
import unittest

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import verification_manual as vm  # noqa: E402

MANUAL = os.path.join(ROOT, "docs", "verification.md")


def manual():
    with open(MANUAL) as f:
        return f.read()


class CommittedManual(unittest.TestCase):
    def test_is_what_the_script_writes(self):
        text, _ = vm.generate()
        self.assertEqual(manual(), text, "docs/verification.md is behind the tests and checks: run "
                                         "/usr/bin/python3 scripts/verification_manual.py")

    def test_lists_every_suite_check(self):
        with open(os.path.join(ROOT, "verification", "checks.toml"), "rb") as f:
            checks = tomllib.load(f)["check"]
        self.assertGreater(len(checks), 0)
        rows, inside = [], False
        for line in manual().split("\n"):
            if line.startswith("#"):
                inside = line.startswith("### Suite checks")
            elif inside and line.startswith("| ") and not line.startswith("| scene |"):
                rows.append(line)
        self.assertEqual(len(rows), len(checks), "one table row per [[check]] of checks.toml")
        for i, c in enumerate(checks):
            for key in ("verifies", "against", "source"):
                self.assertTrue(c.get(key, "").strip(), "check %d (%s, %s) has no %s" % (i + 1, c["scene"],
                                                                                      c["formulation"], key))
            tol = "-" if c["metric"] == "finished" else "%g" % c["tolerance"]
            md = {k: str(c[k]).replace("|", "\\|") for k in ("verifies", "against")}  # as a Markdown cell
            found = [r for r in rows if r.startswith("| %s | %s" % (c["scene"], c["formulation"]))
                     and "| %s | %s |" % (tol, md["verifies"]) in r and md["against"] in r]
            self.assertTrue(found, "check %d (%s, %s, %s, tolerance %s) is not in docs/verification.md"
                            % (i + 1, c["scene"], c["formulation"], c["metric"], tol))

    def test_lists_every_acceptance_test(self):
        text = manual()
        names = []
        for path in glob.glob(os.path.join(ROOT, "tests", "acceptance", "*.cpp")):
            with open(path) as f:
                names += ["%s.%s" % m for m in re.findall(r"(?m)^TEST(?:_P)?\((\w+),\s*(\w+)\)", f.read())]
        self.assertGreater(len(names), 0)
        for n in names:
            self.assertIn("\n### %s\n" % n, text)

    def test_lists_every_extreme_case_with_its_bounds(self):
        text = manual()
        cases = glob.glob(os.path.join(ROOT, "cases", "extremes", "*.toml"))
        self.assertGreater(len(cases), 0)
        for path in cases:
            name = os.path.splitext(os.path.basename(path))[0]
            self.assertIn("\n#### %s\n" % name, text)
            with open(path, "rb") as f:
                case = tomllib.load(f)
            section = text.split("\n#### %s\n" % name)[1].split("\n#### ")[0].split("\n## ")[0]
            shown = [float(x) for row in section.split("\n") if row.startswith("| ") and row.count(" | ") == 3
                     for x in re.findall(r"[<>]= ([-0-9.e+]+)", row.split(" | ")[2])]
            bounds = [m[k] for e in [case.get("expect", {})] + [v.get("expect", {}) for v in case.get("variants", [])]
                      for m in e.get("measure", []) for k in ("min", "max") if k in m]
            self.assertEqual(sorted(shown), sorted(float(b) for b in bounds), name)

class Metadata(unittest.TestCase):
    """A test file's //~ blocks as the script reads them."""

    def read(self, body):
        with tempfile.NamedTemporaryFile("w", suffix=".cpp", delete=False) as f:
            f.write(body)
        try:
            return vm.read_tests(f.name)
        finally:
            os.unlink(f.name)

    BLOCK = ('//~ feature = "upsetting"\n//~ source = "a book"\n//~ [[check]]\n//~ what = "the load"\n'
             '//~ compares = "exact solution"\n//~ tolerance = "5e-3 (relative)"\n//~ why = "measured 1e-5"\n')

    def test_a_block_above_a_test_is_read(self):
        t = self.read(self.BLOCK + "TEST(A, B) {\n  EXPECT_LT(x, 5e-3);\n}\n")
        self.assertEqual([x["name"] for x in t], ["A.B"])
        self.assertEqual(t[0]["check"][0]["tolerance"], "5e-3 (relative)")

    def test_a_test_without_a_block_is_refused(self):
        with self.assertRaisesRegex(vm.MetadataError, "no //~ metadata block above the test"):
            self.read(self.BLOCK + "TEST(A, B) {\n  EXPECT_LT(x, 5e-3);\n}\nTEST(A, C) {}\n")

    def test_a_tolerance_the_test_does_not_assert_is_refused(self):
        with self.assertRaisesRegex(vm.MetadataError, "5e-3 does not occur"):
            self.read(self.BLOCK + "TEST(A, B) {\n  EXPECT_LT(x, 1e-3);\n}\n")

    def test_a_tolerance_only_a_comment_states_is_refused(self):
        with self.assertRaisesRegex(vm.MetadataError, "5e-3 does not occur"):
            self.read(self.BLOCK + "TEST(A, B) {\n  EXPECT_LT(x, 1e-3);  // was 5e-3\n}\n")

    def test_an_unknown_kind_of_reference_is_refused(self):
        with self.assertRaisesRegex(vm.MetadataError, "compares = 'a hunch'"):
            self.read(self.BLOCK.replace("exact solution", "a hunch") + "TEST(A, B) { EXPECT_LT(x, 5e-3); }\n")

    def test_a_helpers_checks_come_first(self):
        helper = self.BLOCK.replace('//~ feature = "upsetting"\n//~ source = "a book"\n', '//~ helper = "h"\n')
        t = self.read(helper + "void h() { EXPECT_LT(x, 5e-3); }\n"
                      '//~ feature = "upsetting"\n//~ source = "a book"\n//~ uses = ["h"]\nTEST(A, B) { h(); }\n')
        self.assertEqual([c["what"] for c in t[0]["check"]], ["the load"])


if __name__ == "__main__":
    unittest.main()
