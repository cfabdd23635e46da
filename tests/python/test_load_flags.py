"""Unit tests of the suite report's load flags (reports/load_flags.py) and
the load difference panel (reports/curve_figures.py) on synthetic pairs of
load curves; run by ctest (python.load_flags):
    /usr/bin/python3 tests/python/test_load_flags.py

The curves: a smooth load 100 (1 + s) kN with a staircase, +8 % at each
landing (1, 2 and 3 mm), steps of 0.01 mm, a landing ending its step at the
landing's stroke (landing control), the number of rows in contact one more
from the landing step on."""
import os
import sys
import tempfile
import types
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "reports"))
import load_flags  # noqa: E402
from curve_figures import DIFFERENCE_FLOOR, difference_curves  # noqa: E402
from plotting import plt  # noqa: E402

LANDINGS = [1.0, 2.0, 3.0]


def run(formulation, shift=0.0, factor=1.0, extra_jump=None, skip_contact=False):
    """A run with the staircase landing at LANDINGS + shift, its load times
    factor; extra_jump: a stroke where the load jumps 3 % with no node
    landing (a jump that is a difference); skip_contact: no contact_nodes
    column."""
    lands = [x + shift for x in LANDINGS]
    strokes = sorted(set([round(0.01 * k, 10) for k in range(401)] + lands))
    load, nodes = [], []
    for s in strokes:
        landed = sum(1 for x in lands if s >= x - 1e-12)
        jump = 1.03 if extra_jump is not None and s >= extra_jump else 1.0
        load.append(-1000 * factor * jump * 100 * (1 + s) * 1.08 ** landed)  # N, pressing: negative
        nodes.append(5 + landed)
    h = {"step": list(range(len(strokes))), "stroke": strokes, "top.Fy": load}
    if not skip_contact:
        h["contact_nodes"] = nodes
    return {"formulation": formulation, "variant": "", "history": h, "load_col": "top.Fy", "summary": {},
            "exit_code": 0}


def blind_largest(r, ref):
    """The largest |difference| over every compared stroke, landings or not
    (what the rule leaves out)."""
    return max(abs(c[3]) for c in load_flags.compared(r, ref))


class LoadFlags(unittest.TestCase):
    def test_a_shifted_landing_is_not_flagged(self):
        ref = run("direct")
        for shift in (3e-4, -3e-4, 2e-6, 0.004):
            r = run("ipopt", shift=shift)
            # Interpolated across the jumps, the curves differ by up to the
            # jump's height: what the flags leave out.
            self.assertGreater(blind_largest(r, ref), 0.05 if shift > 0 else 0.002, shift)
            self.assertEqual(load_flags.differences(r, ref), [], shift)
            self.assertEqual(load_flags.scene_flags([ref, r], ref), [], shift)
            # The agreement away from the landings is kept: round-off.
            self.assertLess(load_flags.load_differences(r, ref)[1], 1e-12, shift)

    def test_a_real_offset_of_one_percent_is_flagged(self):
        ref = run("direct")
        for shift in (0.0, 3e-4):
            r = run("penalty", shift=shift, factor=1.01)
            over = load_flags.differences(r, ref)
            away = sum(1 for c in load_flags.compared(r, ref) if c[4])
            self.assertEqual(len(over), away)  # at every stroke away from the landings
            self.assertGreater(away, 350)  # most strokes are away from the landings
            lines = load_flags.scene_flags([ref, r], ref)
            self.assertEqual(len(lines), 1)
            self.assertIn("penalty differs from direct by more than 0.5 % away from the landings", lines[0])
            self.assertIn("above; largest +1.00 %", lines[0])

    def test_a_flag_between_runs_remeshed_apart_says_so(self):
        ref = run("direct")
        r = run("ipopt", factor=1.01)
        self.assertNotIn("meshes differ", load_flags.scene_flags([ref, r], ref)[0])
        # The same remeshes: nothing to say.
        ref["summary"] = {"remeshes": [{"stroke_mm": 0.5}]}
        r["summary"] = {"remeshes": [{"stroke_mm": 0.5}]}
        self.assertNotIn("meshes differ", load_flags.scene_flags([ref, r], ref)[0])
        # One remeshed again before the flagged strokes end, the other not.
        r["summary"] = {"remeshes": [{"stroke_mm": 0.5}, {"stroke_mm": 2.5}]}
        line = load_flags.scene_flags([ref, r], ref)[0]
        self.assertIn("meshes differ there (remeshed at 0.5, 2.5 mm against 0.5 mm)", line)
        # A remesh after the last flagged stroke does not count.
        r["summary"] = {"remeshes": [{"stroke_mm": 0.5}, {"stroke_mm": 9.0}]}
        self.assertNotIn("meshes differ", load_flags.scene_flags([ref, r], ref)[0])

    def test_a_half_percent_offset_is_below_the_threshold(self):
        ref = run("direct")
        self.assertEqual(load_flags.differences(run("auglag", shift=3e-4, factor=1.004), ref), [])

    def test_a_jump_without_a_landing_is_flagged(self):
        ref = run("direct")
        over = load_flags.differences(run("penalty", extra_jump=2.505), ref)
        self.assertTrue(over)
        self.assertAlmostEqual(over[0][0], 2.51, places=9)  # from the first stroke past the jump
        self.assertAlmostEqual(over[0][3], 0.03, places=9)

    def test_a_landing_steps_late_is_flagged(self):
        # The same ring landed 0.05 mm (five steps) after the reference: the
        # strokes between are more than a step from either landing.
        ref = run("direct")
        over = load_flags.differences(run("penalty", shift=0.05), ref)
        self.assertTrue(over)
        self.assertTrue(all(1.0 < s < 1.05 or 2.0 < s < 2.05 or 3.0 < s < 3.05 for s, *_ in over))
        self.assertLess(max(d for *_, d in over), 0)  # the late run's load below

    def test_landing_intervals_from_contact_nodes(self):
        r = run("direct", shift=3e-4)
        self.assertEqual([round(b, 6) for _, b in load_flags.landing_intervals(r)], [1.0003, 2.0003, 3.0003])
        self.assertEqual(load_flags.landing_intervals(run("none", skip_contact=True)), [])

    def test_a_landing_the_count_misses_is_read_from_the_events(self):
        # The run's ring lands 0.015 mm late (more than the reference's
        # step: its own landing excludes the stroke before it) as another
        # node leaves: the number of rows in contact stays, events.csv
        # names both.
        ref = run("direct")
        r = run("auglag", shift=0.015)
        r["history"]["contact_nodes"] = [5] * len(r["history"]["stroke"])
        self.assertTrue(load_flags.differences(r, ref))  # the count alone: the staircase flagged
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(d, "events.csv"), "w") as f:
                f.write("step,time,attempt,event\n")
                for k, s in enumerate(r["history"]["stroke"]):
                    if any(abs(s - x - 0.015) < 1e-9 for x in LANDINGS):
                        f.write("%d,%g,kept,touch node %d on billet-punch\n" % (k, s, 100 + k))
                        f.write("%d,%g,kept,release node %d from billet-punch\n" % (k, s, 7))
                        f.write("%d,%g,kept,touch node %d on billet-punch\n" % (k, s, 7))  # chatter: back at once
                        f.write("%d,%g,kept,release node %d on billet-punch\n" % (k, s, 90 + k))
                # A failed attempt's touch (its retry started from before it): no landing.
                f.write("%d,%g,failed,touch node %d on billet-punch\n" % (40, 0.4, 300))
                f.write("%d,%g,kept,solved by continuation of the limiting strain rate\n" % (50, 0.5))
            r["results"] = types.SimpleNamespace(folder=d)
            self.assertEqual(len(load_flags.changed_steps(d)), 3)
            self.assertEqual([round(b, 6) for _, b in load_flags.landing_intervals(r)], [1.015, 2.015, 3.015])
            self.assertEqual(load_flags.differences(r, ref), [])

    def test_a_variant_is_not_flagged_a_drop_is(self):
        ref = run("direct")
        r = run("penalty", factor=1.02)
        r["variant"] = "one_pass"
        self.assertEqual(load_flags.scene_flags([ref, r], ref), [])
        d = run("auglag")
        d["history"]["top.Fy"][150] *= 0.9  # at 1.5 mm: a dip of one step, away from the landings
        lines = load_flags.scene_flags([ref, d], ref)
        self.assertEqual(len(lines), 2, lines)
        self.assertIn("auglag differs from direct by more than 0.5 % away from the landings at 1 of", lines[0])
        self.assertRegex(lines[1], r"^auglag: the load drops 9\.[0-9] % in one step, from [0-9.]+ kN at 1\.49 mm")


class DifferencePanel(unittest.TestCase):
    def test_agreement_and_disagreement_both_visible(self):
        ref = run("direct")
        close, off = run("auglag", shift=3e-4, factor=1 + 1e-7), run("penalty", shift=-3e-4, factor=1.01)
        fig, ax = plt.subplots()
        runs = [ref, close, off]
        difference_curves(ax, runs, ref)
        lo, hi = ax.get_ylim()
        self.assertEqual(ax.get_yscale(), "log")
        self.assertLess(lo, 1e-7)
        self.assertGreater(hi, 1e-2)
        self.assertGreater(lo, DIFFERENCE_FLOOR / 10)  # the floor does not squash the scale below
        # Dots at the strokes away from the landings: 1e-7 and 1e-2.
        dots = [l for l in ax.lines if l.get_marker() == "."]
        self.assertEqual(len(dots), 2)
        self.assertAlmostEqual(max(dots[0].get_ydata()), 1e-7, delta=1e-9)
        self.assertAlmostEqual(min(dots[1].get_ydata()), 1e-2, delta=1e-9)
        # Landing ticks: the reference's and each run's three landings.
        ticks = [l for l in ax.lines if l.get_marker() == "|"]
        self.assertEqual([len(l.get_xdata()) for l in ticks], [3, 3, 3])
        plt.close(fig)


if __name__ == "__main__":
    unittest.main()
