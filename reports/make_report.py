#!/usr/bin/python3
"""The suite's comparison report (issue 6), from a suite folder written by
`rpfem suite`: OUT/report.html (self-contained, figures embedded) and its
Markdown twin OUT/report.md (figures in OUT/report_files/).

Per scene: the press load against stroke for every formulation on one plot
(kN; paper Fig. 11), the deformed meshes at the last recorded step coloured
by effective strain rate, formulations side by side (paper Fig. 6, 9), the
penetration and iterations per step, for rings the calibration curves
(inner-diameter change against height reduction, one per friction value),
and a table of the runs (status, steps, wall time, time per step, final
load, largest penetration). At the top: how far each
formulation's load is from the scene's reference formulation (`direct`
where it ran, else `ipopt`), and how long each took.

Run with Debian's Python: /usr/bin/python3 reports/make_report.py OUT
"""
import base64
import csv
import html
import io
import json
import os
import sys

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

REFERENCE_ORDER = ["direct", "ipopt", "penalty", "none"]


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
    """The load column with the largest final |Fy|: the press load."""
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


def png_bytes(fig):
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    plt.close(fig)
    return buf.getvalue()


def mesh_png(out, runs, title):
    """Deformed meshes at each run's last recorded step, coloured by the
    effective strain rate (1/s), one panel per base run, one colour scale."""
    panels = []
    for r in runs:
        path = os.path.join(out, r["dir"], "result.h5")
        if r["variant"] or not os.path.exists(path):
            continue
        with h5py.File(path, "r") as f:
            steps = sorted(k for k in f["steps"] if k.isdigit())
            if not steps:
                continue
            g = f["steps"][steps[-1]]
            panels.append((r["formulation"], int(steps[-1]), g["coordinates"][:], f["mesh/connectivity"][:],
                           g["strain_rate"][:]))
    if not panels:
        return None
    vmax = max(float(np.max(p[4])) for p in panels) or 1.0
    fig, axes = plt.subplots(1, len(panels), figsize=(3.6 * len(panels) + 1.2, 4.0), dpi=110, squeeze=False)
    for ax, (name, step, x, conn, rate) in zip(axes[0], panels):
        pc = PolyCollection(x[conn.astype(int)], array=rate, cmap="viridis", edgecolors="k", linewidths=0.1)
        pc.set_clim(0, vmax)
        ax.add_collection(pc)
        ax.autoscale_view()
        ax.set_aspect("equal")
        ax.set_title("%s, step %d" % (name, step), fontsize=9)
        ax.set_xlabel("x or r (mm)")
        ax.set_ylabel("y (mm)")
    fig.colorbar(pc, ax=list(axes[0]), label="effective strain rate (1/s)")
    fig.suptitle(title, fontsize=10)
    return png_bytes(fig)


def steps_png(runs, title):
    """Penetration per element size (contact formulations that report it)
    and iterations per step against stroke."""
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9.6, 3.6), dpi=110)
    any_pen = False
    for r in runs:
        h = r["history"]
        if not h or r["variant"]:
            continue
        if "max_penetration_rel" in h:
            vals = [max(v, 1e-16) for v in h["max_penetration_rel"]]
            a1.semilogy(h["stroke"], vals, label=r["formulation"])
            any_pen = True
        if "newton_iterations" in h:
            a2.plot(h["stroke"], h["newton_iterations"], label=r["formulation"])
    a1.set_xlabel("stroke (mm)")
    a1.set_ylabel("max penetration / element size")
    a1.set_title("penetration (floor 1e-16 shown for zero)", fontsize=9)
    a2.set_xlabel("stroke (mm)")
    a2.set_ylabel("iterations per step (Newton or Ipopt)")
    for a in (a1, a2):
        a.grid(True, alpha=0.3)
        if a.lines:
            a.legend(fontsize=8)
    if not any_pen:
        a1.text(0.5, 0.5, "no contact penetration reported", ha="center", transform=a1.transAxes)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return png_bytes(fig)


def initial_height(out, r):
    """Height of the modelled part at the start (mm), from result.h5."""
    path = os.path.join(out, r["dir"], "result.h5")
    if not os.path.exists(path):
        return None
    with h5py.File(path, "r") as f:
        y = f["mesh/initial_coordinates"][:, 1]
    return float(y.max() - y.min())


def calibration_png(out, runs, title):
    """Ring calibration curves: inner-diameter change (%) against height
    reduction (%), one curve per run (formulation and friction variant),
    from the `inner_diameter_mid` monitor; None when the scene has none."""
    curves = [r for r in runs if "inner_diameter_mid" in r["history"]]
    if not curves:
        return None
    fig, ax = plt.subplots(figsize=(6.4, 4.6), dpi=110)
    colours = plt.get_cmap("tab20")
    for i, r in enumerate(curves):
        H0 = initial_height(out, r)
        if not H0:
            continue
        ax.plot([100 * s / H0 for s in r["history"]["stroke"]], r["history"]["inner_diameter_mid"], label=label(r),
                color=colours(i % 20), linestyle="-" if r["variant"] else "--")
    ax.axhline(0, color="k", linewidth=0.5)
    ax.set_xlabel("height reduction (%)")
    ax.set_ylabel("inner diameter change at mid-height (%)")
    ax.set_title(title + ": calibration curves")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    return png_bytes(fig)


def figure_png(runs, title):
    fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=110)
    for r in runs:
        if r["load_col"]:
            ax.plot(r["history"]["stroke"], [abs(v) / 1000 for v in r["history"][r["load_col"]]],
                    label=label(r) + " (" + r["load_col"].rsplit(".", 1)[0] + ")")
    ax.set_xlabel("stroke (mm)")
    ax.set_ylabel("load (kN)")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return png_bytes(fig)


def run_row(r):
    s, h = r["summary"], r["history"]
    pen = max(h.get("max_penetration_rel", [float("nan")]) or [float("nan")])
    return [
        label(r),
        s.get("status", "missing") + ("" if r["exit_code"] == 0 else " (exit %d)" % r["exit_code"]),
        str(s.get("steps", "")),
        "%.1f" % r["wall_time_s"],
        "%.3f" % s["time_per_step_s"] if "time_per_step_s" in s else "",
        "%.2f" % final_load_kN(r),
        "%.1e" % pen if pen == pen else "",
    ]


HEADER = ["run", "status", "steps", "wall time (s)", "time per step (s)", "final load (kN)",
          "max penetration / element size"]


def main(out):
    with open(os.path.join(out, "suite.json")) as f:
        runs = [load_run(out, r) for r in json.load(f)["runs"]]
    scenes = []
    for r in runs:
        if r["case"] not in scenes:
            scenes.append(r["case"])
    os.makedirs(os.path.join(out, "report_files"), exist_ok=True)
    summary_rows, sections_html, sections_md = [], [], []
    for sc in scenes:
        rs = [r for r in runs if r["case"] == sc]
        base = [r for r in rs if not r["variant"]]
        ref = next((r for name in REFERENCE_ORDER for r in base
                    if r["formulation"] == name and r["exit_code"] == 0 and r["load_col"]), None)
        for r in base:
            diffs = load_differences(r, ref) if ref and r is not ref else (float("nan"),) * 3
            summary_rows.append([sc, r["formulation"], ref["formulation"] if ref and r is not ref else "-"]
                                + ["%.2e" % x if x == x else "-" for x in diffs]
                                + ["%.1f" % r["wall_time_s"], r["summary"].get("status", "missing")])
        figures = [("load against stroke", "load", figure_png(rs, sc)),
                   ("deformed meshes coloured by effective strain rate", "mesh", mesh_png(out, rs, sc)),
                   ("penetration and iterations per step", "steps", steps_png(rs, sc)),
                   ("ring calibration curves", "calibration", calibration_png(out, rs, sc))]
        imgs_html, imgs_md = "", ""
        for alt, tag, png in figures:
            if png is None:
                continue
            fname = "report_files/%s_%s.png" % (sc, tag)
            with open(os.path.join(out, fname), "wb") as f:
                f.write(png)
            imgs_html += "<img alt='%s, %s' src='data:image/png;base64,%s'/>" % (
                html.escape(alt), html.escape(sc), base64.b64encode(png).decode())
            imgs_md += "![%s, %s](%s)\n\n" % (alt, sc, fname)
        table = [run_row(r) for r in rs]
        desc = next((r["summary"].get("parameters", {}).get("run", {}).get("description", "") for r in rs), "")
        sections_html.append("<h2>%s</h2><p>%s</p>%s%s" % (html.escape(sc), html.escape(desc), imgs_html,
                                                           html_table(HEADER, table)))
        sections_md.append("## %s\n\n%s\n\n%s%s\n" % (sc, desc, imgs_md, md_table(HEADER, table)))
    sum_header = ["scene", "formulation", "reference", "load difference: largest", "median",
                  "largest past 1/4 stroke", "wall time (s)", "status"]
    intro = ("Each scene with every formulation that applies. Load differences are relative differences of the "
             "press load from the reference formulation's (direct where it ran, else ipopt) at the recorded "
             "strokes: the largest, the median, and the largest past the first quarter of the stroke (early on, "
             "nodes land one ring at a time at slightly different strokes in different formulations).")
    # The verification checks (rpfem verify), if the suite ran them.
    ver_header = ["scene", "formulation", "metric", "value", "tolerance", "result", "issue"]
    ver_rows, ver_failed = [], 0
    vpath = os.path.join(out, "verification.json")
    if os.path.exists(vpath):
        with open(vpath) as f:
            ver = json.load(f)
        for c in ver["checks"]:
            ver_rows.append([c["scene"], c["formulation"] + (" / " + c["variant"] if c.get("variant") else ""),
                             c["metric"], "%.3e" % c["value"] if "value" in c else "-", "%.1e" % c["tolerance"],
                             "pass" if c["pass"] else "FAIL" + (": " + c["note"] if c.get("note") else ""),
                             c.get("issue", "")])
        ver_failed = ver["failed"]
    ver_title = "Verification checks: %d, %d failed" % (len(ver_rows), ver_failed)
    ver_html = "<h2>%s</h2>%s" % (ver_title, html_table(ver_header, ver_rows)) if ver_rows else ""
    ver_md = "## %s\n\n%s\n" % (ver_title, md_table(ver_header, ver_rows)) if ver_rows else ""
    with open(os.path.join(out, "report.html"), "w") as f:
        f.write("<!DOCTYPE html><html><head><meta charset='utf-8'><title>rpfem suite report</title>"
                "<style>body{font-family:sans-serif;max-width:60em;margin:auto}table{border-collapse:collapse}"
                "td,th{border:1px solid #999;padding:2px 6px;text-align:right}</style></head><body>"
                "<h1>rpfem suite report</h1><p>%s</p>%s%s%s</body></html>\n"
                % (html.escape(intro), html_table(sum_header, summary_rows), ver_html, "".join(sections_html)))
    with open(os.path.join(out, "report.md"), "w") as f:
        f.write("# rpfem suite report\n\n%s\n\n%s\n%s\n%s" % (intro, md_table(sum_header, summary_rows), ver_md,
                                                             "\n".join(sections_md)))
    print(os.path.abspath(os.path.join(out, "report.html")))


def html_table(header, rows):
    h = "".join("<th>%s</th>" % html.escape(c) for c in header)
    b = "".join("<tr>%s</tr>" % "".join("<td>%s</td>" % html.escape(c) for c in r) for r in rows)
    return "<table><tr>%s</tr>%s</table>" % (h, b)


def md_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: make_report.py SUITE_OUT")
    main(sys.argv[1])
