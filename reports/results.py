"""The suite runs' results for the report (reports/make_report.py): each
run's history.csv and summary.json, its press load and how far it is from
the reference formulation's, and the recorded steps and initial mesh in its
result.h5."""
import csv
import json
import os

import h5py
import numpy as np

REFERENCE_ORDER = ["direct", "ipopt", "auglag", "penalty", "none"]


def read_history(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    cols = {}
    for r in rows:
        for k, v in r.items():
            try:
                cols.setdefault(k, []).append(float(v))
            except (TypeError, ValueError):
                pass
    return cols


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
    d = os.path.join(out, run["dir"])
    r = dict(run)
    r["summary"], r["history"] = {}, {}
    if os.path.exists(os.path.join(d, "summary.json")):
        with open(os.path.join(d, "summary.json")) as f:
            r["summary"] = json.load(f)
    if os.path.exists(os.path.join(d, "history.csv")):
        r["history"] = read_history(os.path.join(d, "history.csv"))
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


def load_differences(r, ref):
    """Relative differences of r's press load from ref's at r's recorded
    strokes within ref's range (ref interpolated linearly): the largest, the
    median, and the largest past the first quarter of the stroke (where the
    staircase of nodes landing one ring at a time, at different strokes in
    different formulations, no longer dominates)."""
    nan = float("nan")
    if not (r["load_col"] and ref["load_col"]):
        return nan, nan, nan
    xs, ys = ref["history"]["stroke"], [abs(v) for v in ref["history"][ref["load_col"]]]
    diffs = []
    for s, f in zip(r["history"]["stroke"], r["history"][r["load_col"]]):
        if s > xs[-1] + 1e-12:
            break
        g = interp(s, xs, ys)
        if g > 0:
            diffs.append((s, abs(abs(f) / g - 1)))
    if not diffs:
        return nan, nan, nan
    d = sorted(x for _, x in diffs)
    late = [x for s, x in diffs if s >= 0.25 * xs[-1]]
    return d[-1], d[len(d) // 2], max(late) if late else nan


def open_result(out, r):
    """Run r's result.h5 open for reading, or None (missing or unreadable)."""
    try:
        return h5py.File(os.path.join(out, r["dir"], "result.h5"), "r")
    except OSError:
        return None


def recorded_steps(out, r):
    """(stroke in mm, step key) of every step recorded in r's result.h5, by
    stroke, the stroke from history.csv; [] when either is missing."""
    h = r["history"]
    strokes = {int(n): s for n, s in zip(h.get("step", []), h.get("stroke", [])) if s == s}
    f = open_result(out, r)
    if f is None:
        return []
    with f:
        keys = [k for k in f["steps"] if k.isdigit()] if "steps" in f else []
    return sorted((strokes[int(k)], k) for k in keys if int(k) in strokes)


def read_step(out, r, key, stroke):
    """Run r's deformed mesh and fields at recorded step `key`: node
    coordinates x, connectivity conn, strain rate per element, nodal
    velocity v (mm/s), nodal contact pressure p (None if not written)."""
    f = open_result(out, r)
    if f is None:
        return None
    with f:
        g = f["steps"][key]
        p = g["node/contact_pressure"][:] if "node/contact_pressure" in g else None
        mesh = g.attrs.get("mesh", "/mesh")  # the step's mesh group (a remesh starts a new one)
        mesh = mesh.decode() if isinstance(mesh, bytes) else mesh
        return {"stroke": stroke, "x": g["coordinates"][:], "conn": f[mesh + "/connectivity"][:].astype(int),
                "rate": g["strain_rate"][:], "v": g["velocity"][:], "p": p}


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
    f = open_result(out, r)
    if f is None:
        return None
    with f:
        x, conn, body = (f["mesh/" + k][:] for k in ("initial_coordinates", "connectivity", "element_body"))
    work = workpieces(r, body)
    if len(work) != 1:
        return None
    y = x[np.unique(conn[body == work.pop()]), 1]
    return float(y.max() - y.min())
