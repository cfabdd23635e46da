"""The studies' tables for the suite report (reports/study_section.py): each
study `rpfem suite` ran, as listed in OUT/suite.json, read from its
sweep.csv (a row per run) and sweep.json (axes, reference, Richardson's
estimates, usable window); docs/sweeps.md describes both. A value of -1 in
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
    return s


def kind(s):
    """Which figure a study gets: "pareto" (Richardson per formulation, the
    formulation an axis: error against wall time), "convergence"
    (Richardson along a size axis), "sensitivity" (one numeric axis against
    a reference run), or None (only the table)."""
    ref = s["meta"].get("reference", {}).get("kind")
    formulation_axis = any(a["key"] == "formulation" for a in s["meta"].get("axes", []))
    if ref == "richardson":
        return "pareto" if formulation_axis else "convergence"
    if ref == "formulation" and len(s["axes"]) == 1:
        return "sensitivity"
    return None


def size(key, value):
    """The size Richardson's estimate goes along: h = 1 / mesh_factor
    (relative element size), the value itself for any other key."""
    return 1.0 / value if key == "run.mesh_factor" else value


def short(key):
    """An axis key's last part (formulations.penalty.beta_factor:
    beta_factor)."""
    return key.rsplit(".", 1)[-1]
