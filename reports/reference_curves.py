"""Closed-form reference curves for the suite report's plots
(curve_figures.py), with their sources: the exact load of homogeneous
frictionless upsetting (verification/analytic.cpp), Prandtl's flat-punch
load in plane strain, and the ring's inner-diameter change: exact without
friction, Avitzur's upper bound with a friction factor m. The flow stress
is the run's own (summary.json: library K and n, eps0, m, rate_ref):
sigma = K (eps0 + eps)^n (rate / rate_ref)^m."""
import math

import numpy as np

# src/material/flow_stress.cpp's library (Jang & Hwang 2002, Table 1): K (kgf/mm^2), n.
LIBRARY = {"AISI1010": (72.98, 0.22), "AISI1035": (91.97, 0.17)}
KGF_PER_MM2_TO_MPA = 9.80665

# The scenes with a closed form: homogeneous upsetting of half models
# (symmetry at x = 0 and y = 0: the full height and width are twice the
# mesh's), and the plane-strain indentation (Prandtl).
UPSETTING = ("upsetting_frictionless_axisym", "upsetting_frictionless_plane", "upsetting_dies_frictionless_axisym")
PRANDTL = ("indentation_fillet_punch",)


def flow_stress(material, eps, rate):
    """sigma_bar (MPa) at effective strain eps and strain rate (1/s); None
    for a material not in the library and without K."""
    if material.get("library") in LIBRARY:
        K, n = LIBRARY[material["library"]]
        K *= KGF_PER_MM2_TO_MPA
    elif "K" in material or "K_kgf_mm2" in material:
        K = material.get("K") or material["K_kgf_mm2"] * KGF_PER_MM2_TO_MPA
        n = material.get("n", 0.0)
    else:
        return None
    m = material.get("m", 0.0)
    return K * (material.get("eps0", 0.01) + eps) ** n * ((rate / material.get("rate_ref", 1.0)) ** m if m else 1.0)


def workpiece(summary):
    """(geometry, material, mesh) of the scene's one body; None otherwise."""
    p = summary.get("parameters", {})
    bodies = list(p.get("bodies", {}).values())
    if len(bodies) != 1:
        return None
    return p.get("run", {}).get("geometry", ""), bodies[0].get("material", {}), bodies[0].get("mesh", {})


def upsetting_load(summary, strokes):
    """Exact press load (kN; kN/mm in plane strain) of homogeneous
    frictionless upsetting at the strokes: F = sigma(eps) A0 H0 / H,
    eps = ln(H0/H) (axisymmetric); F = 2/sqrt3 sigma(2/sqrt3 ln(H0/H)) w0
    H0 / H (plane strain); H = H0 - 2 stroke (both halves close), platens
    at 1 mm/s each."""
    geometry, material, mesh = workpiece(summary)
    H0, W0 = 2 * mesh["height"], 2 * mesh["width"]
    loads = []
    for s in strokes:
        H = H0 - 2 * s
        if geometry.startswith("axisym"):
            sigma = flow_stress(material, math.log(H0 / H), 2 / H)
            loads.append(None if sigma is None else sigma * math.pi * W0 ** 2 / 4 * H0 / H / 1000)
        else:
            c = 2 / math.sqrt(3)
            sigma = flow_stress(material, c * math.log(H0 / H), c * 2 / H)
            loads.append(None if sigma is None else c * sigma * W0 * H0 / H / 1000)
    return loads


def prandtl_load(summary):
    """Prandtl's flat-punch load (kN/mm) on a half-space, 2k (1 + pi/2) b,
    k = sigma(0) / sqrt3 the initial shear flow stress, b the punch's full
    width (twice its half model's widest x)."""
    geometry, material, _ = workpiece(summary)
    dies = summary.get("parameters", {}).get("dies", {})
    if len(dies) != 1 or not geometry.startswith("plane"):
        return None
    b = 2 * max(v["x"] for v in next(iter(dies.values()))["vertex"].values())
    sigma = flow_stress(material, 0.0, 1.0)
    return None if sigma is None else 2 * sigma / math.sqrt(3) * (1 + math.pi / 2) * b / 1000


def upsetting_slab_load(summary, strokes):
    """The slab method's press load (kN) of a solid cylinder upset between
    flat dies with the friction factor m (summary.json's), as
    verification/slab_comparison.cpp computes it: homogeneous height and
    radius, H = H0 - 2 stroke (half model on a symmetry plane), R = R0
    sqrt(H0/H), the flow stress at eps = ln(H0/H) and the rate 2 v / H (v
    the die's speed), and the mean pressure
        p_avg / sigma = 1 + 2 m R / (3 sqrt3 H)
    (verification/analytic.cpp; Altan, Oh and Gegel 1983, sec. 7; Avitzur),
    F = p_avg pi R^2. None where it does not apply: not one axisymmetric
    rectangular body under one flat die with a friction factor m > 0."""
    w = workpiece(summary)
    dies = summary.get("parameters", {}).get("dies", {})
    if w is None or len(dies) != 1:
        return None
    geometry, material, mesh = w
    die = next(iter(dies.values()))
    f = die.get("friction", {})
    ys = {v["y"] for v in die.get("vertex", {}).values()} if isinstance(die.get("vertex"), dict) else set()
    if (not geometry.startswith("axisym") or mesh.get("shape", "rectangle") != "rectangle" or len(ys) != 1
            or f.get("law") != "factor" or not f.get("m", 0) > 0):
        return None
    m, speed = f["m"], abs(die.get("vy", 1.0)) or 1.0
    H0, R0 = 2 * mesh["height"], mesh["width"]
    loads = []
    for st in strokes:
        H = H0 - 2 * st
        if not H > 0:
            loads.append(None)
            continue
        R = R0 * math.sqrt(H0 / H)
        sigma = flow_stress(material, math.log(H0 / H), 2 * speed / H)
        loads.append(None if sigma is None else
                     sigma * (1 + 2 * m * R / (3 * math.sqrt(3) * H)) * math.pi * R * R / 1000)
    return loads


def load_references(scene, runs):
    """[(strokes, loads, label)] for the scene's load plot: the closed form
    of frictionless upsetting and of the indentation, and the slab load for
    each friction factor of a solid cylinder's runs (upsetting_slab_load)."""
    r = next((r for r in runs if r["history"].get("stroke") and r["summary"].get("parameters")), None)
    if r is None or workpiece(r["summary"]) is None:
        return []
    strokes = r["history"]["stroke"]
    if scene in UPSETTING:
        return [(strokes, upsetting_load(r["summary"], strokes),
                 "exact, homogeneous flow (verification/analytic.cpp)")]
    if scene in PRANDTL:
        p = prandtl_load(r["summary"])
        return [([strokes[0], strokes[-1]], [p, p], "Prandtl, flat punch on a half-space: 2k(1+pi/2) b")] if p else []
    out, seen = [], set()
    for run in runs:
        m = (friction_of(run["summary"]) or ("", None))
        if m[0] != "m" or m[1] in seen or not run["history"].get("stroke"):
            continue
        loads = upsetting_slab_load(run["summary"], run["history"]["stroke"])
        if loads and any(v is not None for v in loads):
            seen.add(m[1])
            out.append((run["history"]["stroke"], loads, "slab method, m = %g (p/sigma = 1 + 2mR/(3 sqrt3 H))" % m[1]))
    return sorted(out, key=lambda t: t[2])


def ring_frictionless(reductions):
    """The ring's inner-diameter change (%) without friction: homogeneous
    flow, every diameter grows as sqrt(H0/H) - 1."""
    return [100 * (math.sqrt(1 / (1 - x / 100)) - 1) for x in reductions]


def ring_upper_bound_power(ro, ri, h, m, rn):
    """Avitzur's upper-bound power of ring compression, J / (pi sigma0 v)
    (mm^2), for the neutral radius rn; outer and inner radius ro, ri and
    full height h (mm), closing speed v, friction factor m, flow stress
    sigma0 (uniform: perfectly plastic).

    Field, uniform through the thickness (z from the mid-plane):
        u_r = v/(2h) (r - rn^2/r),   u_z = -v z / h,
    incompressible: e_r + e_t + e_z = v/(2h) (1 + a) + v/(2h) (1 - a) - v/h
    = 0 with a = rn^2/r^2, and its effective strain rate
        sqrt(2/3 e_ij e_ij) = v/h sqrt(1 + rn^4 / (3 r^4)).
    Internal power, with s = r^2 and c = rn^2/sqrt3:
        W_i = sigma0 int_V e_bar dV = 2 pi sigma0 v int r sqrt(1 + rn^4/(3 r^4)) dr
            = pi sigma0 v [G(ro^2) - G(ri^2)],
        G(s) = sqrt(s^2 + c^2) - c asinh(c / s).
    Friction on both die faces, shear m sigma0/sqrt3 against the slip |u_r|:
        W_f = 2 int m sigma0/sqrt3 |u_r| 2 pi r dr
            = (2 pi m sigma0 v / (sqrt3 h)) int_ri^ro |r^2 - rn^2| dr.
    The field has no velocity discontinuity, so J = W_i + W_f (Avitzur,
    Metal Forming: Processes and Analysis, 1968; the ring of Male and
    Cockcroft 1964). rn may lie below ri (all material flows outward)."""
    c = rn * rn / math.sqrt(3)

    def G(s):
        return s if c == 0 else math.sqrt(s * s + c * c) - c * math.asinh(c / s)

    def cube(a, b):  # int_a^b (r^2 - rn^2) dr
        return (b ** 3 - a ** 3) / 3 - rn * rn * (b - a)

    k = min(max(rn, ri), ro)  # r^2 - rn^2 < 0 on [ri, k), > 0 on (k, ro]
    slip = cube(k, ro) - cube(ri, k)
    return G(ro * ro) - G(ri * ri) + 2 * m / (math.sqrt(3) * h) * slip


def ring_neutral_radius(ro, ri, h, m):
    """The neutral radius rn in [0, ro] that minimises Avitzur's power
    (ring_upper_bound_power): scipy's bounded Brent search, against the end
    rn = 0 (where m = 0 puts it: W_i grows with rn), which Brent never
    evaluates."""
    if m == 0:
        return 0.0
    # Imported here: without scipy only the ring's calibration figure is
    # skipped (plotting.draw_or_skip), not the whole report.
    from scipy.optimize import minimize_scalar
    best = minimize_scalar(lambda rn: ring_upper_bound_power(ro, ri, h, m, rn), bounds=(0.0, ro),
                           method="bounded", options={"xatol": 1e-9 * ro})
    at0 = ring_upper_bound_power(ro, ri, h, m, 0.0)
    return best.x if best.fun < at0 else 0.0


def ring_upper_bound_path(ro, ri, h, m, reductions, step=0.2):
    """The ring through Avitzur's upper bound at the height reductions (%,
    0 <= x < 100): {"ro", "ri", "h", "rn", "power"} (mm; power J / (pi
    sigma0 v) in mm^2: the die load is pi sigma0 power), one entry per
    reduction; NaN from where the hole has closed (ri^2 < 0: the field no
    longer applies). Integrated in height steps of at most `step` per cent
    of h: on a step from h0 to h1 with rn held (taken at the step's
    midpoint state, second order), dr^2/dt = 2 r u_r = (v/h)(r^2 - rn^2)
    and dh/dt = -v give exactly r1^2 - rn^2 = (r0^2 - rn^2) h0/h1, so
    (ro^2 - ri^2) h, the volume over pi, is kept to round-off."""
    if any(not 0 <= x < 100 for x in reductions):
        raise ValueError("height reductions must lie in [0, 100) %")
    H0 = h
    state = (ro, ri, h)  # the arguments' order of ring_neutral_radius and ring_upper_bound_power

    def advance(state, h1, rn):
        f = state[2] / h1
        squares = [rn * rn + (r * r - rn * rn) * f for r in state[:2]]
        return None if min(squares) <= 0 else tuple(math.sqrt(r2) for r2 in squares) + (h1,)

    keys = ("ro", "ri", "h", "rn", "power")
    out = {}
    for x in sorted(set(float(x) for x in reductions)):
        target = H0 * (1 - x / 100)
        n = max(1, math.ceil((state[2] - target) / (step / 100 * H0) - 1e-9)) if state and target < state[2] else 0
        for i in range(n):
            h1 = state[2] + (target - state[2]) / (n - i)
            mid = advance(state, (state[2] + h1) / 2, ring_neutral_radius(*state, m))
            state = None if mid is None else advance(state, h1, ring_neutral_radius(*mid, m))
            if state is None:  # the hole has closed
                break
        if state is None:
            out[x] = dict.fromkeys(keys, float("nan"))
            continue
        rn = ring_neutral_radius(*state, m)
        out[x] = {"ro": state[0], "ri": state[1], "h": state[2], "rn": rn,
                  "power": ring_upper_bound_power(*state, m, rn)}
    return {k: np.array([out[float(x)][k] for x in reductions]) for k in keys}


def ring_upper_bound(ro, ri, h, m, reductions):
    """The ring's inner-diameter change (%) at the height reductions (%)
    under Avitzur's upper bound with friction factor m (ring_upper_bound_
    power: the field u_r = v/(2h)(r - rn^2/r), uniform through the
    thickness, rn minimising the power at every height; Avitzur 1968, the
    calibration charts of Male and Cockcroft 1964); ro, ri the initial outer
    and inner radius, h the full initial height (mm). m = 0 gives rn = 0
    and ring_frictionless."""
    path = ring_upper_bound_path(ro, ri, h, m, reductions)
    return list(100 * (path["ri"] / ri - 1))


def ring_geometry(summary):
    """(ro, ri, H) in mm of the run's ring: its mesh's outer and inner
    radius, and the full height, twice the mesh's when a symmetry plane
    normal to y lies on the mesh's bottom (the half model of
    cases/ring_compression*.toml: the mid-plane at y = 0); None for any
    other workpiece."""
    w = workpiece(summary)
    if w is None or w[2].get("shape") != "ring":
        return None
    mesh = w[2]
    planes = summary.get("parameters", {}).get("symmetry", {}).values()
    mirrored = any(p.get("normal") == "y" and p.get("at", 0.0) == mesh.get("y0", 0.0) for p in planes)
    return mesh["outer_radius"], mesh["inner_radius"], (2 if mirrored else 1) * mesh["height"]


def friction_of(summary):
    """The run's friction on its dies: ("m", factor) or ("mu", Coulomb
    coefficient) from summary.json's parameters (no law: m = 0); None when
    the dies differ."""
    laws = set()
    for die in summary.get("parameters", {}).get("dies", {}).values():
        f = die.get("friction", {})
        law = f.get("law", "none")
        laws.add(("mu", f["mu"]) if law == "coulomb" else ("m", f["m"]) if law == "factor" else ("m", 0.0))
    return laws.pop() if len(laws) == 1 else None
