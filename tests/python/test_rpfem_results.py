"""Unit tests of python/rpfem_results.py on a finished run of Test I (two
bodies, two dies), its folder in the environment variable RPFEM_RUN (run
by tests/cli/visualization.sh):
    RPFEM_RUN=DIR /usr/bin/python3 tests/python/test_rpfem_results.py
Without that run, pandas or meshio the tests that need them fail unless
RPFEM_ALLOW_SKIP=1 (checks.cannot_test)."""
import os
import shutil
import sys
import tempfile
import unittest

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import rpfem_results  # noqa: E402
from checks import cannot_test  # noqa: E402

RUN = os.environ.get("RPFEM_RUN", "")


def need_run():
    if not os.path.exists(os.path.join(RUN, "result.h5")):
        cannot_test("RPFEM_RUN names no run folder")


class TestRun(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        need_run()
        cls.r = rpfem_results.load_run(RUN)
        cls.last = cls.r.steps[-1]

    def test_history_is_every_step(self):
        h = self.r.history
        with open(os.path.join(RUN, "history.csv")) as f:
            rows = sum(1 for line in f if line.strip()) - 1
        self.assertEqual(len(h), rows)
        self.assertEqual(list(h["step"]), list(range(rows)))
        self.assertTrue(np.all(np.diff(h["stroke"]) > 0))
        self.assertIn("top_punch.Fy", h.dtype.names)

    def test_history_frame(self):
        try:
            import pandas  # noqa: F401
        except ImportError:
            cannot_test("pandas (python3-pandas) is not installed")
        frame = self.r.history_frame()
        self.assertEqual(len(frame), len(self.r.history))
        self.assertEqual(frame["step"].dtype.kind, "i")
        self.assertEqual(frame["top_punch.Fy"].iloc[-1], self.r.history["top_punch.Fy"][-1])

    def test_summary_and_steps(self):
        self.assertEqual(self.r.summary["status"], "finished")
        self.assertEqual(self.r.steps[0], 0)
        self.assertEqual(self.last, self.r.summary["steps"])

    def test_time_and_stroke_match_the_history(self):
        row = self.r.history_row(self.last)
        self.assertAlmostEqual(self.r.stroke(self.last), row["stroke"], delta=1e-9)
        self.assertAlmostEqual(self.r.time(self.last), row["time"], delta=1e-9 * row["time"])
        self.assertIsNone(self.r.history_row(10 ** 6))

    def test_mesh(self):
        m = self.r.mesh(self.last)
        self.assertEqual(m.body_names, ["lower", "upper"])
        self.assertEqual(m.coordinates.shape[1], 2)
        self.assertEqual(m.connectivity.shape, (len(m.element_body), 4))
        self.assertLess(m.connectivity.max(), len(m.coordinates))
        self.assertEqual(sorted(set(m.element_body.tolist())), [0, 1])
        start = self.r.mesh(self.last, deformed=False)
        self.assertTrue(np.array_equal(start.coordinates, self.r.mesh(0).coordinates))
        self.assertGreater(np.abs(m.coordinates - start.coordinates).max(), 0.1)  # mm

    def test_fields_units_and_bodies(self):
        m = self.r.mesh(self.last)
        self.assertEqual(len(self.r.field("strain_rate", self.last)), len(m.element_body))
        self.assertEqual(len(self.r.field("contact_pressure", self.last)), len(m.coordinates))
        self.assertIn("flow_stress", self.r.fields(self.last))
        self.assertEqual(self.r.units("strain_rate", self.last), "1/s")
        self.assertEqual(self.r.units("flow_stress", self.last), "MPa")
        upper = self.r.field("strain_rate", self.last, body="upper")
        self.assertTrue(np.array_equal(upper, self.r.field("strain_rate", self.last)[m.element_body == 1]))
        with self.assertRaises(KeyError):
            self.r.field("no_such_field", self.last)

    def test_dies_follow_the_stroke(self):
        dies = self.r.dies(self.last)
        self.assertEqual(sorted(dies), ["bottom_punch", "top_punch"])
        # Test I's top punch starts at y = 20 mm and travels the stroke down.
        stroke = self.r.stroke(self.last)
        self.assertTrue(np.allclose(dies["top_punch"][:, 1], 20.0 - stroke, atol=1e-12))
        self.assertTrue(np.allclose(dies["bottom_punch"][:, 1], -20.0 + stroke, atol=1e-12))

    def test_meshio(self):
        try:
            import meshio  # noqa: F401
        except ImportError:
            cannot_test("meshio (python3-meshio) is not installed")
        mesh = self.r.meshio(self.last)
        self.assertTrue(np.array_equal(mesh.points[:, :2], self.r.mesh(self.last).coordinates))
        self.assertEqual(len(mesh.cell_data["strain_rate"][0]), len(mesh.cells[0].data))
        self.assertIn("velocity", mesh.point_data)


class TestFolders(unittest.TestCase):
    def test_history_only_and_a_short_row(self):
        d = tempfile.mkdtemp()
        try:
            with open(os.path.join(d, "history.csv"), "w") as f:
                f.write("step,time,stroke\n0,0,0\n1,0.5,0.25\n2,1.0\n")
            run = rpfem_results.load_run(d)
            self.assertEqual(run.steps, [])
            self.assertEqual(run.summary, {})
            self.assertEqual(list(run.history["stroke"][:2]), [0.0, 0.25])
            self.assertTrue(np.isnan(run.history["stroke"][2]))
        finally:
            shutil.rmtree(d)

    def test_summary_from_result_h5(self):
        need_run()
        d = tempfile.mkdtemp()
        try:
            shutil.copy(os.path.join(RUN, "result.h5"), d)
            run = rpfem_results.load_run(d)
            self.assertEqual(run.summary["status"], "finished")
            self.assertIsNone(run.history)
        finally:
            shutil.rmtree(d)


if __name__ == "__main__":
    unittest.main(verbosity=2)
