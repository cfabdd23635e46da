"""The suite runs' results for the report (reports/make_report.py): each
run's history.csv and summary.json, its press load, the scene's reference
run, and the recorded steps and initial mesh in its
result.h5, all read through python/rpfem_results.py."""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
import rpfem_results  # noqa: E402

REFERENCE_ORDER = ["direct", "ipopt", "auglag", "penalty", "none"]


def press_column(hist, summary):
    """The press load's column: the stroke's reference (stepping.reference,
    the die or velocity group that drives the press) where it has a load,
    else the load with the largest final |Fy| (a die's reaction may be the
    larger, as the container's bottom under a backward extrusion)."""
    ref = summary.get("parameters", {}).get("stepping", {}).get("reference")
    if isinstance(ref, str) and hist.get(ref + ".Fy"):
        return ref + ".Fy"
    best, value = None, -1.0
    for name in summary.get("final_load_N", {}):
        col = name + ".Fy"
        if col in hist and hist[col] and abs(hist[col][-1]) > value:
            best, value = col, abs(hist[col][-1])
    return best


def load_run(out, run):
    """A suite run (an entry of suite.json) with its files read: summary
    (dict), history ({column: [values]}), results (an rpfem_results.Run),
    load_col (the press load's column)."""
    r = dict(run)
    r["results"] = rpfem_results.load_run(os.path.join(out, run["dir"]))
    r["summary"] = r["results"].summary
    h = r["results"].history  # as lists, the figures' and tables' input
    r["history"] = {k: [float(v) for v in h[k]] for k in h.dtype.names or ()} if h is not None else {}
    r["load_col"] = press_column(r["history"], r["summary"]) if r["history"] else None
    return r


def label(r):
    return r["formulation"] + (" / " + r["variant"] if r["variant"] else "")


def final_load_kN(r):
    c = r["load_col"]
    return abs(r["history"][c][-1]) / 1000 if c else float("nan")


def interp(x, xs, ys):
    if not xs:
        return float("nan")
    if x <= xs[0]:
        return ys[0]
    for i in range(1, len(xs)):
        if x <= xs[i]:
            t = (x - xs[i - 1]) / (xs[i] - xs[i - 1]) if xs[i] > xs[i - 1] else 0
            return ys[i - 1] + t * (ys[i] - ys[i - 1])
    return ys[-1]


def reference_run(base):
    """The scene's reference run among its base runs: the first formulation
    of REFERENCE_ORDER that finished with a load."""
    return next((r for name in REFERENCE_ORDER for r in base
                 if r["formulation"] == name and r["exit_code"] == 0 and r["load_col"]), None)


def recorded_steps(out, r):
    """(stroke in mm, step key) of every step recorded in r's result.h5, by
    stroke, the stroke from history.csv; [] when either is missing."""
    h = r["history"]
    strokes = {int(n): s for n, s in zip(h.get("step", []), h.get("stroke", [])) if s == s}
    return sorted((strokes[n], "%06d" % n) for n in r["results"].steps if n in strokes)


def read_step(out, r, key, stroke):
    """Run r's deformed mesh and fields at recorded step `key`: node
    coordinates x, connectivity conn, strain rate per element, nodal
    velocity v (mm/s), nodal contact pressure p (None if not written)."""
    run = r["results"]
    if not run.has_result:
        return None
    step = int(key)
    m = run.mesh(step)  # on the step's own mesh (a remesh starts a new one)
    p = run.field("contact_pressure", step) if "contact_pressure" in run.fields(step) else None
    return {"stroke": stroke, "x": m.coordinates, "conn": m.connectivity, "rate": run.field("strain_rate", step),
            "v": run.field("velocity", step), "p": p}


def workpieces(r, element_body):
    """Body ids of the workpieces: the bodies that are not virtual rigid
    (bodies are numbered in the order of their sorted names)."""
    bodies = r["summary"].get("parameters", {}).get("bodies", {})
    ids = {int(b) for b in np.unique(element_body)}
    if len(bodies) != len(ids):
        return ids
    return {i for i, name in enumerate(sorted(bodies))
            if bodies[name].get("material", {}).get("library") != "VIRTUAL_RIGID"}


def initial_height(out, r):
    """Height of the workpiece at the start (mm), from result.h5; None when
    it is missing or the scene has several workpieces."""
    if not r["results"].has_result:
        return None
    m = r["results"].initial_mesh()
    work = workpieces(r, m.element_body)
    if len(work) != 1:
        return None
    y = m.coordinates[np.unique(m.connectivity[m.element_body == work.pop()]), 1]
    return float(y.max() - y.min())
