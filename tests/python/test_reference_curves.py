"""Unit tests of the ring's reference curves in reports/reference_curves.py:
Avitzur's upper bound (ring_upper_bound) against the exact frictionless
curve, against itself over m, and against an independent evaluation of the
same bound; run by ctest (python.reference_curves):
    /usr/bin/python3 tests/python/test_reference_curves.py

The published chart value for m = 1 at 50 % (Male and Cockcroft 1964; Male
and DePierre 1970's m curves of the 6:3:2 ring) is read off a figure, and no
number could be pinned from the sources at hand; the m = 1 check is against
an independent evaluation of the bound instead: the power integrated by
quadrature of the velocity field itself (not the closed forms), the
neutral radius by brute force over a grid, the geometry by fourth-order
Runge-Kutta on dri/dh, dro/dh (not the step that keeps the volume)."""
import math
import os
import sys
import unittest

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "reports"))
from reference_curves import (load_references, ring_frictionless, ring_upper_bound,  # noqa: E402
                              ring_upper_bound_path, ring_upper_bound_power, upsetting_slab_load)

# The standard 6:3:2 ring of cases/ring_compression.toml: OD 60, ID 30, H 20 mm.
RO, RI, H = 30.0, 15.0, 20.0
REDUCTIONS = [0, 5, 10, 20, 30, 40, 50]

# Gauss-Legendre nodes and weights on [-1, 1], for the quadrature below.
GX, GW = np.polynomial.legendre.leggauss(40)


def gauss(f, a, b):
    """int_a^b f(r) dr per column: a, b arrays of limits, f vectorised over
    r of shape (nodes, len(a))."""
    r = (a + b) / 2 + np.outer(GX, (b - a) / 2)
    return (b - a) / 2 * (f(r) * GW[:, None]).sum(axis=0)


def power_by_quadrature(ro, ri, h, m, rn):
    """J / (pi sigma0 v) from the velocity field u_r = (r - rn^2/r)/(2h)
    (v = 1): the strain rates and the slip taken from u_r, integrated over
    r (split at rn, where the slip has its kink), for an array of rn."""
    rn = np.atleast_1d(np.asarray(rn, dtype=float))

    def power(r):
        er = (1 + rn ** 2 / r ** 2) / (2 * h)  # du_r/dr
        et = (r - rn ** 2 / r) / (2 * h) / r  # u_r / r
        ez = -1 / h  # du_z/dz
        internal = 2 * r * h * np.sqrt(2 / 3 * (er ** 2 + et ** 2 + ez ** 2))  # 2 pi r h e_bar / pi
        friction = 2 * 2 * r * m / math.sqrt(3) * np.abs(r - rn ** 2 / r) / (2 * h)  # two faces: 2 pi r k |u_r| / pi
        return internal + friction

    k = np.clip(rn, ri, ro)
    return gauss(power, np.full_like(rn, ri), k) + gauss(power, k, np.full_like(rn, ro))


def neutral_radius_by_grid(ro, ri, h, m):
    """rn minimising power_by_quadrature: a grid of 201 points over
    [0, ro], then three times a grid of 201 points over the best point's
    neighbours."""
    lo, hi = 0.0, ro
    for _ in range(4):
        grid = np.linspace(lo, hi, 201)
        i = int(np.argmin(power_by_quadrature(ro, ri, h, m, grid)))
        lo, hi = grid[max(i - 1, 0)], grid[min(i + 1, 200)]
    return grid[i]


def inner_change_independent(ro, ri, h, m, reduction, steps=100):
    """The inner-diameter change (%) by RK4 on d(ri, ro)/dh = -(r - rn^2/r)/(2h)
    (u_r with dh/dt = -v), rn by neutral_radius_by_grid at every stage."""
    def rate(y, h):
        rn = neutral_radius_by_grid(y[0], y[1], h, m)
        return -(y - rn ** 2 / y) / (2 * h)

    y, h0 = np.array([ro, ri]), h
    dh = -h0 * reduction / 100 / steps
    for _ in range(steps):
        k1 = rate(y, h)
        k2 = rate(y + dh / 2 * k1, h + dh / 2)
        k3 = rate(y + dh / 2 * k2, h + dh / 2)
        k4 = rate(y + dh * k3, h + dh)
        y, h = y + dh / 6 * (k1 + 2 * k2 + 2 * k3 + k4), h + dh
    return 100 * (y[1] / ri - 1)


class TestRingUpperBound(unittest.TestCase):
    def test_power_closed_form_equals_quadrature(self):
        for m in (0.0, 0.3, 1.0):
            for rn in (0.0, 7.0, 15.0, 19.5, 26.0):
                self.assertAlmostEqual(ring_upper_bound_power(RO, RI, H, m, rn),
                                       power_by_quadrature(RO, RI, H, m, rn)[0], delta=1e-9 * 1000)

    def test_m0_is_the_exact_frictionless_curve(self):
        x = list(np.linspace(0, 60, 25))
        path = ring_upper_bound_path(RO, RI, H, 0.0, x)
        self.assertTrue(np.all(path["rn"] == 0))
        for a, b in zip(ring_upper_bound(RO, RI, H, 0.0, x), ring_frictionless(x)):
            self.assertAlmostEqual(a, b, delta=1e-6)

    def test_inner_diameter_falls_with_m(self):
        ms = [0.0, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 1.0]
        curves = np.array([ring_upper_bound(RO, RI, H, m, REDUCTIONS) for m in ms])
        self.assertTrue(np.all(curves[:, 0] == 0))
        self.assertTrue(np.all(np.diff(curves[:, 1:], axis=0) < 0), curves)

    def test_m1_at_50_percent_against_an_independent_evaluation(self):
        ub = ring_upper_bound(RO, RI, H, 1.0, [50])[0]
        independent = inner_change_independent(RO, RI, H, 1.0, 50)
        print("\nm = 1, 6:3:2 ring, 50 %%: upper bound %.3f %%, independent evaluation %.3f %%" % (ub, independent))
        self.assertAlmostEqual(ub, independent, delta=0.01)
        # and it closes the hole: far below the frictionless +41.4 %
        self.assertLess(ub, -30)

    def test_volume_is_kept(self):
        for m in (0.0, 0.1, 0.5, 1.0):
            p = ring_upper_bound_path(RO, RI, H, m, [10, 30, 50, 60])
            volume = (p["ro"] ** 2 - p["ri"] ** 2) * p["h"]
            self.assertTrue(np.all(np.abs(volume / ((RO ** 2 - RI ** 2) * H) - 1) < 1e-9), volume)
            self.assertTrue(np.allclose(p["h"], H * (1 - np.array([10, 30, 50, 60]) / 100), rtol=1e-12))

    def test_nan_once_the_hole_has_closed(self):
        a = ring_upper_bound(RO, RI, H, 1.0, [60, 80])
        self.assertGreater(a[0], -100)
        self.assertTrue(math.isnan(a[1]))

    def test_reductions_in_any_order(self):
        a = ring_upper_bound(RO, RI, H, 0.3, [50, 0, 20])
        b = ring_upper_bound(RO, RI, H, 0.3, [0, 20, 50])
        self.assertEqual(a, [b[2], b[0], b[1]])


class TestUpsettingSlab(unittest.TestCase):
    """The slab load of a cylinder upset with the friction factor m (the
    upsetting_friction scene's reference), against the formula worked by
    hand at one stroke, and where it must not be drawn."""

    @staticmethod
    def summary(m=0.5, law="factor", shape="rectangle", geometry="axisymmetric", dies=1):
        die = {"vy": -1.0, "vertex": {"0": {"x": 0.0, "y": 10.0}, "1": {"x": 30.0, "y": 10.0}},
               "friction": {"law": law, "m": m}}
        return {"parameters": {
            "run": {"geometry": geometry},
            "bodies": {"billet": {"material": {"K": 500.0, "n": 0.2, "eps0": 0.01},
                                  "mesh": {"shape": shape, "width": 10.0, "height": 10.0}}},
            "dies": {"d%d" % i: die for i in range(dies)}}}

    def test_against_the_formula_by_hand(self):
        # Stroke 2.5 mm: H = 20 - 5 = 15, R = 10 sqrt(20/15) = 11.547,
        # eps = ln(4/3) = 0.28768, sigma = 500 (0.29768)^0.2 = 392.39 MPa,
        # p/sigma = 1 + 2 0.5 11.547 / (3 sqrt3 15) = 1.14815,
        # F = 392.39 1.14815 pi 11.547^2 / 1000 = 188.72 kN.
        R = 10 * math.sqrt(20 / 15)
        sigma = 500 * (0.01 + math.log(20 / 15)) ** 0.2
        want = sigma * (1 + 2 * 0.5 * R / (3 * math.sqrt(3) * 15)) * math.pi * R * R / 1000
        self.assertAlmostEqual(want, 188.72, delta=0.01)
        got = upsetting_slab_load(self.summary(), [0.0, 2.5])
        self.assertAlmostEqual(got[1], want, places=9)
        # m = 0: not drawn (the exact homogeneous load is the reference);
        # the load grows with m.
        self.assertIsNone(upsetting_slab_load(self.summary(m=0.0), [2.5]))
        self.assertGreater(upsetting_slab_load(self.summary(m=1.0), [2.5])[0], got[1])

    def test_not_where_it_does_not_apply(self):
        for s in (self.summary(law="coulomb"), self.summary(shape="ring"), self.summary(geometry="plane_strain"),
                  self.summary(dies=2)):
            self.assertIsNone(upsetting_slab_load(s, [1.0]))

    def test_one_curve_per_friction_factor(self):
        runs = [{"summary": self.summary(m=m), "history": {"stroke": [0.0, 1.0, 2.0]}} for m in (0.5, 0.1, 0.5)]
        refs = load_references("upsetting_friction", runs)
        self.assertEqual([r[2].split(" (")[0] for r in refs], ["slab method, m = 0.1", "slab method, m = 0.5"])


if __name__ == "__main__":
    unittest.main()
