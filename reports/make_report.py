#!/usr/bin/python3
"""The suite's comparison report, from a suite folder written by
`rpfem suite`: OUT/report.html with its figures in OUT/report_files/
(--single-file: figures embedded, report.html alone is the report) and its
Markdown twin OUT/report.md.

At the top (report_page.py): the verdict (verification checks passed and
failed, runs finished and stopped, load flags), the contents with links to
every scene and study, and the provenance (provenance.py: rpfem version,
executable, compiler, BLAS, dates, machine). Then how far each
formulation's load is from the scene's reference formulation's (`direct`
where it ran, else `ipopt`), how long each took, and the verification
checks, if the suite ran them. Per scene: the load flags (load_flags.py:
formulations that differ by more than 0.5 % away from the strokes where
a node lands, loads that drop by more than 5 % in a step), the figures
(curve_figures.py: load against stroke beside each formulation's relative
difference from the reference on a log scale, the per-step penetration,
iterations, residual and force imbalance, for rings the calibration
curves; field_figures.py: the strain rate on the deformed meshes through
the stroke and the velocity near the contact at the end),
each with a caption, and a table of the runs (status, steps, wall time,
time per step, final load, largest penetration). Last, the studies the
suite ran (study_section.py: per study its figure, what its sweep.json
concludes and its table; a regularization study's errors against its
parameter with their observed orders, iterations and wall time). A figure the data do not allow, or that fails,
is left out with a note. The runs' files are read by results.py, the
studies' tables by study_results.py.

Run with Debian's Python: /usr/bin/python3 reports/make_report.py OUT
(from any directory: the sibling modules import from the script's own
directory, which Python puts first on sys.path).
"""
import html
import json
import multiprocessing
import os
import sys

from curve_figures import CALIBRATION_FIGURE, LOAD_FIGURE, STEPS_FIGURE, calibration_png
from field_figures import MESH_FIGURE, VELOCITY_FIGURE
from plotting import draw_or_skip
from load_flags import RULE, load_differences, scene_flags
from provenance import provenance_rows
from report_html import INLINE, anchor, figure, html_table, md_table, note
from report_page import contents, page, provenance, verdict
from study_section import studies_section
from results import final_load_kN, label, load_run, reference_run

# alt text, file tag, drawing (out, runs, scene) giving a PNG or None (no data), caption
FIGURES = [LOAD_FIGURE, MESH_FIGURE, VELOCITY_FIGURE, STEPS_FIGURE, CALIBRATION_FIGURE]


def render(draw, out, rs, sc, alt):
    """draw's PNG, or None with a note when the data do not allow it: a
    broken figure is skipped, it does not stop the report. No ring
    calibration curves is no news."""
    png, why = draw_or_skip(lambda: draw(out, rs, sc), alt, sc)
    if why:
        return None, why
    return png, "" if png or draw is calibration_png else alt + ": not drawn, no run has the data"


def scene_figures(out, sc, rs):
    """The scene's figures, written to report_files/, as HTML (embedded, with
    captions) and Markdown."""
    imgs_html, imgs_md = "", ""
    for alt, tag, draw, caption in FIGURES:
        png, text = render(draw, out, rs, sc, alt)
        h, m = (figure(out, "report_files/%s_%s.png" % (sc, tag), png, "%s, %s" % (alt, sc), caption) if png
                else note(text) if text else ("", ""))
        imgs_html += h
        imgs_md += m
    return imgs_html, imgs_md


# The scenes' figures are drawn in forked workers (the drawing is most of
# the report's time: 30 s on one core for the full suite): each worker
# finds the report's folder and the scenes' runs here, set before the fork.
_FORKED = {}


def _scene_figures_of(i):
    sc, rs = _FORKED["scenes"][i]
    return scene_figures(_FORKED["out"], sc, rs)


def all_scene_figures(out, jobs):
    """scene_figures of every (scene, its runs) in jobs, in order, over the
    machine's cores (one process where fork is not available)."""
    workers = min(len(jobs), len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else 1)
    if workers < 2 or "fork" not in multiprocessing.get_all_start_methods():
        return [scene_figures(out, sc, rs) for sc, rs in jobs]
    _FORKED.update(out=out, scenes=jobs)
    with multiprocessing.get_context("fork").Pool(workers) as pool:
        return pool.map(_scene_figures_of, range(len(jobs)), chunksize=1)


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
        # What the run could not vouch for (summary.json's warnings: a
        # penetration, an ill-conditioned tangent, a distorted mesh).
        "; ".join(s.get("warnings", [])),
    ]


HEADER = ["run", "status", "steps", "wall time (s)", "time per step (s)", "final load (kN)",
          "max penetration / element size", "warnings"]


def flags_block(lines):
    """A scene's load flags: (HTML, Markdown); empty when none."""
    if not lines:
        return "", ""
    return ("<div class='flags'><p><b>Load flags (%d)</b></p><ul>%s</ul></div>"
            % (len(lines), "".join("<li>%s</li>" % html.escape(x) for x in lines)),
            "**Load flags (%d)**\n\n%s\n" % (len(lines), "".join("- %s\n" % x for x in lines)))


def verification(out):
    """verification.json (None when the suite ran no checks) and its table's rows."""
    vpath = os.path.join(out, "verification.json")
    if not os.path.exists(vpath):
        return None, []
    with open(vpath) as f:
        ver = json.load(f)
    rows = [[c["scene"], c["formulation"] + (" / " + c["variant"] if c.get("variant") else ""),
             c["metric"], "%.3e" % c["value"] if "value" in c else "-", "%.1e" % c["tolerance"],
             ("pass" if c["pass"] else "FAIL") + (": " + c["note"] if c.get("note") else ""), c.get("against", "")]
            for c in ver["checks"]]
    return ver, rows


def main(out):
    with open(os.path.join(out, "suite.json")) as f:
        suite = json.load(f)
    runs = [load_run(out, r) for r in suite["runs"]]
    scenes = []
    for r in runs:
        if r["case"] not in scenes:
            scenes.append(r["case"])
    os.makedirs(os.path.join(out, "report_files"), exist_ok=True)
    summary_rows, sections_html, sections_md, flags = [], [], [], {}
    by_scene = [(sc, [r for r in runs if r["case"] == sc]) for sc in scenes]
    for (sc, rs), (imgs_html, imgs_md) in zip(by_scene, all_scene_figures(out, by_scene)):
        base = [r for r in rs if not r["variant"]]
        ref = reference_run(base)
        for r in base:
            diffs = load_differences(r, ref) if ref and r is not ref else (float("nan"),) * 3 + (0, 0)
            summary_rows.append([sc, r["formulation"], ref["formulation"] if ref and r is not ref else "-"]
                                + ["%.2e" % x if x == x else "-" for x in diffs[:3]]
                                + ["%d of %d" % diffs[3:] if diffs[4] else "-"]
                                + ["%.1f" % r["wall_time_s"], r["summary"].get("status", "missing")])
        lines = scene_flags(rs, ref)
        flags[sc] = len(lines)
        fh, fm = flags_block(lines)
        table = [run_row(r) for r in rs]
        desc = next((r["summary"].get("parameters", {}).get("run", {}).get("description", "") for r in rs), "")
        sections_html.append("<h2 id='%s'>%s</h2><p>%s</p>%s%s%s" % (
            anchor("scene", sc), html.escape(sc), html.escape(desc), fh, imgs_html, html_table(HEADER, table)))
        sections_md.append("## %s\n\n%s\n\n%s%s%s\n" % (sc, desc, fm, imgs_md, md_table(HEADER, table)))
    sum_header = ["scene", "formulation", "reference", "load difference: largest", "largest away from landings",
                  "median away from landings", "strokes away from landings", "wall time (s)", "status"]
    intro = ("Each scene with every formulation that applies. Load differences are relative differences of the "
             "press load from the reference formulation's (direct where it ran, else ipopt) at the recorded "
             "strokes (the reference interpolated linearly): the largest over all strokes, and the largest and the "
             "median away from the landings (strokes with no step of either run within a step of them at which a "
             "node lands or leaves: two formulations land a ring of nodes a few 1e-4 mm apart, and the jump of the "
             "load there is no difference of the curves), with the number of such strokes of all compared. " + RULE)
    ver, ver_rows = verification(out)
    ver_header = ["scene", "formulation", "metric", "value", "tolerance", "result", "against"]
    ver_title = "Verification checks: %d, %d failed" % (len(ver_rows), ver["failed"] if ver else 0)
    ver_html = ("<h2 id='verification'>%s</h2>%s" % (ver_title, html_table(ver_header, ver_rows))
                if ver_rows else "")
    ver_md = "## %s\n\n%s\n" % (ver_title, md_table(ver_header, ver_rows)) if ver_rows else ""
    studies_html, studies_md = studies_section(out, suite.get("studies", []))
    verdict_html, verdict_md = verdict(suite, runs, ver, flags)
    toc = [("summary", "Summary: load differences and wall times", [])]
    toc += [("verification", ver_title, [])] if ver_rows else []
    toc += [("scenes", "Scenes (%d)" % len(scenes),
             [(anchor("scene", sc), sc + (" (%d flags)" % flags[sc] if flags[sc] else "")) for sc in scenes])]
    toc += [("studies", "Studies (%d)" % len(suite["studies"]),
             [(anchor("study", e["study"]), e["study"]) for e in suite["studies"]])] if suite.get("studies") else []
    toc += [("provenance", "Provenance", [])]
    prov_html, prov_md = provenance(provenance_rows(out, suite, runs))
    with open(os.path.join(out, "report.html"), "w") as f:
        f.write(page("<h1>rpfem suite report</h1>%s%s%s<h2 id='summary'>Summary</h2><p>%s</p>%s%s"
                     "<h2 id='scenes'>Scenes</h2>%s%s"
                     % (verdict_html, contents(toc), prov_html, html.escape(intro),
                        html_table(sum_header, summary_rows), ver_html, "".join(sections_html), studies_html)))
    with open(os.path.join(out, "report.md"), "w") as f:
        f.write("# rpfem suite report\n\n%s\n%s\n## Summary\n\n%s\n\n%s\n%s\n%s\n%s"
                % (verdict_md, prov_md, intro, md_table(sum_header, summary_rows), ver_md,
                   "\n".join(sections_md), studies_md))
    print(os.path.abspath(os.path.join(out, "report.html")))


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if a != "--single-file"]
    if len(args) != 1:
        sys.exit("usage: make_report.py SUITE_OUT [--single-file]")
    INLINE["on"] = "--single-file" in sys.argv[1:]
    main(args[0])
