"""The studies' tables for the suite report (reports/study_section.py): each
study `rpfem suite` ran, as listed in OUT/suite.json, read from its
sweep.csv (a row per run) and sweep.json (axes, reference, Richardson's
estimates, usable window, the reference run's own values, the errors'
orders along a regularization axis); docs/sweeps.md describes both. A value of -1 in
sweep.csv was not measured: it is read as None, never as a number."""
import csv
import json
import os

TEXT_COLUMNS = ("dir", "formulation", "reason")


def number(text):
    """A sweep.csv cell as a float, None for -1 (not measured) or empty."""
    try:
        x = float(text)
    except (TypeError, ValueError):
        return None
    return None if x == -1 else x


def load_study(out, entry):
    """A study of suite.json's "studies" with its table: entry's keys, plus
    rows (a dict per run: text columns as text, the others number()),
    meta (sweep.json), axes (numeric axis keys), error (why nothing could
    be read, else None)."""
    s = dict(entry, rows=[], meta={}, axes=[], error=None)
    try:
        with open(os.path.join(out, entry["table"]), newline="") as f:
            s["rows"] = [{k: v if k in TEXT_COLUMNS else number(v) for k, v in r.items()} for r in csv.DictReader(f)]
        with open(os.path.join(out, entry["metadata"])) as f:
            s["meta"] = json.load(f)
    except (OSError, ValueError, KeyError) as e:
        s["error"] = "%s: %s" % (type(e).__name__, e)
        return s
    s["axes"] = [a["key"] for a in s["meta"].get("axes", []) if a["key"] != "formulation"]
    attach_orders(s)
    return s


def attach_orders(s):
    """Per row, what sweep.json has of the run beyond sweep.csv: the
    monitor's value at the last stroke (monitor_final, any sign, so not a
    table column), and along a regularization axis the observed orders of
    the load and monitor errors between the next larger value and the
    run's (load_order, monitor_order; None where not measured or for the
    largest value)."""
    by_dir = {r["dir"]: r for r in s["rows"]}
    for r, entry in zip(s["rows"], s["meta"].get("runs", [])):
        r["monitor_final"] = entry.get("monitor_final")
    for g in s["meta"].get("regularization", {}).get("groups", []):
        for part in ("load", "monitor"):
            pairs = g.get(part, {}).get("successive", [])
            for d, pair in zip(g["dirs"][1:], pairs):
                if d in by_dir:
                    by_dir[d][part + "_order"] = pair.get("order")


def regularization_groups(s):
    """(label, group of sweep.json's regularization, its rows falling along
    the axis) per group: one per formulation (and other axes' values)."""
    by_dir = {r["dir"]: r for r in s["rows"]}
    return [(g["group"], g, [by_dir[d] for d in g["dirs"] if d in by_dir])
            for g in s["meta"].get("regularization", {}).get("groups", [])]


TOLERANCE = "stepping.tolerance"


def kind(s):
    """Which figure a study gets: "regularization" (a [study.regularization]
    axis: the errors against it per formulation, iterations and wall time),
    "tolerance" (a stepping.tolerance axis, the error the tolerance bounds
    measured: achieved error and wall time against the stated tolerance,
    per formulation),
    "pareto" (Richardson per formulation, the formulation an axis: error
    against wall time), "convergence" (Richardson along a size axis),
    "sensitivity" (one numeric axis against a reference run), "grid" (two
    numeric axes, no reference: each run's final load and wall time over
    them), or None (only the table)."""
    if s["meta"].get("regularization"):
        return "regularization"
    ref = s["meta"].get("reference", {}).get("kind")
    if TOLERANCE in s["axes"] and s["meta"].get("reference", {}).get("measure") == "max_relative":
        return "tolerance"
    formulation_axis = any(a["key"] == "formulation" for a in s["meta"].get("axes", []))
    if ref == "richardson":
        return "pareto" if formulation_axis else "convergence"
    if ref == "formulation" and len(s["axes"]) == 1:
        return "sensitivity"
    if ref in (None, "none") and len(s["axes"]) == 2 and not formulation_axis:
        return "grid"
    return None


def size(key, value):
    """The size Richardson's estimate goes along: h = 1 / mesh_factor
    (relative element size), the value itself for any other key."""
    return 1.0 / value if key == "run.mesh_factor" else value


def short(key):
    """An axis key's last part (formulations.penalty.beta_factor:
    beta_factor)."""
    return key.rsplit(".", 1)[-1]
