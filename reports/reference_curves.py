"""Closed-form reference curves for the suite report's plots
(curve_figures.py), with their sources: the exact load of homogeneous
frictionless upsetting (verification/analytic.cpp), Prandtl's flat-punch
load in plane strain, and the ring's frictionless inner-diameter change.
The flow stress is the run's own (summary.json: library K and n, eps0, m,
rate_ref): sigma = K (eps0 + eps)^n (rate / rate_ref)^m."""
import math

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


def load_references(scene, runs):
    """[(strokes, loads, label)] for the scene's load plot."""
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
    return []


def ring_frictionless(reductions):
    """The ring's inner-diameter change (%) without friction: homogeneous
    flow, every diameter grows as sqrt(H0/H) - 1."""
    return [100 * (math.sqrt(1 / (1 - x / 100)) - 1) for x in reductions]
