"""The report's Studies section (reports/make_report.py): for each study
`rpfem suite` ran (OUT/suite.json, "studies"), its figure
(study_figures.py), what its sweep.json concludes (Richardson's observed
order and extrapolated load, the usable window, a regularization axis's
observed orders, its errors at the default value and the reference run's
own cost), and a table of its runs (sweep.csv's essentials; loads in kN,
times in s; "-": not measured; a regularization study's with the orders
between successive values and the reference run last). A study of more
than ROWS_SHOWN runs gets, in place of a row per run, its axes' ranges,
the least, median and largest value of each column over its finished
runs, and the runs that did not finish (at most ROWS_SHOWN of them, each
reason counted): the full table is its sweep.csv, named under it. A
study whose table cannot be read, or whose figure the data do not allow,
gets a note saying why."""
import html
import math

from plotting import draw_or_skip
from report_html import anchor, figure, html_table, md_table, note
from study_figures import DRAW, compared, finished, formulation_curves, group_name, richardson_groups
from study_results import TOLERANCE, kind, load_study, regularization_groups, short, size

ALT = {"sensitivity": "penalty sensitivity", "convergence": "convergence", "pareto": "speed against accuracy",
       "regularization": "regularization", "tolerance": "achieved error against tolerance",
       "grid": "final load and wall time over the grid"}
ROWS_SHOWN = 60  # a study with more runs is summarized (aggregates, stopped runs); its sweep.csv has every row


def caption(s, k):
    ref = s["meta"].get("reference", {})
    measure = "mean load over the stroke (work / stroke)" if ref.get("measure") == "mean" else "final load"
    if k == "regularization":
        reg, monitor = s["meta"]["regularization"], s["meta"].get("monitor")
        return ("Against %s, falling to the right (log axes), per formulation: top, the relative difference of the "
                "%s from the %s reference run's%s, the legend giving the least-squares order over the values above "
                "the floor (dashed: errors at or below it are not counted); dotted vertical: the default %g. "
                "Bottom: Newton iterations per step (median, max; step 0 left out) and each run's wall time, the "
                "reference run's as black lines. x: runs that did not finish."
                % (short(reg["axis"]), measure, ref.get("formulation", ""),
                   " and of %s at the last stroke, in %s" % (monitor["column"], monitor["unit"]) if monitor else "",
                   reg.get("default", -1)))
    if k == "tolerance":
        against = ("the exact load" if ref.get("kind") == "exact" else "the %s reference run's load"
                   % s["meta"].get("reference_run", {}).get("formulation", ""))
        return ("Step control by a local error estimate, one curve per formulation, tighter tolerances to the right "
                "(log axes). Left: the achieved error, max over the stroke of |F_h - F| / max |F| against %s, no "
                "stroke within one step of a landing compared (what stepping.tolerance bounds, docs/theory.md), "
                "against the stated tolerance; solid black y = x, shaded a factor 3 either side. Right: each run's "
                "wall time. x: runs that did not finish." % against)
    if k == "sensitivity":
        w = s["meta"].get("window", {})
        return ("Against %s (log axis): the largest penetration over the element size (dashed: the %g limit); the "
                "load's relative difference from the %s reference run, largest over the strokes and at the last "
                "stroke; Newton iterations per step, median and max (dashed: the %g limit); the least reciprocal "
                "condition estimate of the tangents. Shaded: the usable window (finished, both limits met). x: runs "
                "that did not finish (the reason is in the notes under the table)."
                % (short(s["axes"][0]), w.get("max_penetration_rel", 1e-3), ref.get("formulation", ""),
                   w.get("max_iterations", 10)))
    if k == "convergence":
        return ("Left: the relative difference of the %s from Richardson's extrapolation against the size, "
                "log-log (dotted, below the points: the observed order's slope over the three finest sizes); right: "
                "the %s itself (dashed: the extrapolated value)." % (measure, measure))
    if k == "grid":
        return ("Each finished run as a square at its two axis values (%s against %s), coloured by its final load "
                "(left) and its wall time (right). x: runs that did not finish." % (short(s["axes"][1]),
                                                                                   short(s["axes"][0])))
    common = ref.get("formulation")
    return ("Each run's error against its wall time, log-log: the relative difference of its %s from Richardson's "
            "extrapolation of the %s mesh sequence%s; labels: the mesh factor (1: the case's mesh). Dashed: the "
            "Pareto front, the runs no other run beats in both time and error."
            % (measure, "%s runs'" % common if common else "same formulation's",
               " (one reference for every formulation)" if common else ""))


def coarser_order(hs, fs):
    """Richardson's order from the three coarsest sizes, when there are four
    or more at a constant ratio; None otherwise or when refused (the check
    that the finest three are in the asymptotic range)."""
    pts = sorted(zip(hs, fs), reverse=True)
    if len(pts) < 4:
        return None
    (h3, f3), (h2, f2), (h1, f1) = pts[:3]
    r = h2 / h1
    if abs(h3 / h2 / r - 1) > 1e-6 or f2 == f1 or (f3 - f2) / (f2 - f1) <= 1:
        return None
    return math.log((f3 - f2) / (f2 - f1)) / math.log(r)


def order_words(orders):
    """The fitted and successive orders of a part ("load" or "monitor") of a
    regularization group, as text, and its error at the default value."""
    fit = orders.get("fit_order")
    text = ("order %.2f (least squares over the %d values above the floor %g)" % (fit, orders["fit_points"],
                                                                              orders["floor"])
            if fit is not None else "no order (fewer than two values above the floor %g)" % orders["floor"])
    pairs = ", ".join("%.2f" % p["order"] if "order" in p else "-" for p in orders.get("successive", []))
    return text + "; between successive values %s" % pairs, orders.get("error_at_default", -1)


LEVEL = 0.3  # a successive order below it: the error no longer falls with the parameter


def levels_off(orders):
    """The value from which the error no longer falls: the first of the
    trailing pairs of successive values, two or more, whose measured
    orders are all below LEVEL; None otherwise."""
    pairs = orders.get("successive", [])
    k = len(pairs)
    while k > 0 and "order" in pairs[k - 1] and pairs[k - 1]["order"] < LEVEL:
        k -= 1
    return pairs[k]["from"] if len(pairs) - k >= 2 else None


def regularization_findings(s):
    """Per group: the observed orders, the errors at the default value; the
    reference run's own cost."""
    meta, lines = s["meta"], []
    reg, monitor = meta["regularization"], meta.get("monitor")
    for label, g, _ in regularization_groups(s):
        text, at = order_words(g["load"])
        line = "%s, as %s falls: the %s load error %s." % (group_name(label), short(reg["axis"]),
                                                            "mean" if reg.get("load_error") == "mean_load_error"
                                                            else "final", text)
        flat = [("load", levels_off(g["load"]))]
        if monitor and g.get("monitor"):
            mtext, mat = order_words(g["monitor"])
            line += " The %s error %s." % (monitor["column"], mtext)
            flat.append((monitor["column"], levels_off(g["monitor"])))
        else:
            mat = -1
        for what, a in flat:
            if a is not None:
                line += (" The %s error no longer falls from %s = %g on (successive orders below %g): what is left "
                         "is not the parameter's, and the least-squares order counts it." % (what, short(reg["axis"]),
                                                                                             a, LEVEL))
        if reg.get("default", -1) > 0:
            line += " At the default %g: load error %s%s." % (
                reg["default"], "%.2e" % at if at >= 0 else "not measured",
                (", %s error %s" % (monitor["column"], "%.3g %s" % (mat, monitor["unit"]) if mat >= 0
                                    else "not measured")) if monitor else "")
        lines.append(line)
    r = meta.get("reference_run")
    if r:
        text = ("The reference run (%s): %s, %d steps, final load %.4f kN, mean load %.4f kN%s; Newton iterations "
                "per step median %g, max %g (mean %.1f); wall time %.1f s."
                % (r["formulation"], "finished" if r["finished"] else "stopped (%s)" % r.get("reason", ""),
                   r["steps"], r["final_load_kN"], r["mean_load_kN"],
                   ", %s %.4f" % (monitor["column"], r["monitor_final"]) if monitor and "monitor_final" in r else "",
                   r["iterations_median"], r["iterations_max"], r["iterations_mean"], r["wall_time_s"]))
        lines.append(text)
    return lines


def tolerance_findings(s):
    """Per formulation: the effectivity (achieved error / tolerance) at each
    tolerance; the reference's cost."""
    lines = []
    ex = s["meta"].get("exact")
    if ex:
        lines.append("Against the exact load (%s, D0 = %g mm, H0 = %g mm, H = H0 - %g stroke; K = %.2f MPa, n = %g, "
                     "eps0 = %g)." % (ex["solution"], ex["diameter_mm"], ex["height_mm"], ex["height_per_stroke"],
                                      ex["K_MPa"], ex["n"], ex["eps0"]))
    for f, done, _ in formulation_curves(s["rows"]):
        eff = ["%g: %s" % (r[TOLERANCE], "%.2f" % (r["load_error_max_rel"] / r[TOLERANCE])
                           if r.get("load_error_max_rel") is not None else "-") for r in reversed(done)]
        if eff:
            lines.append("%s, achieved error / tolerance at %s." % (f, ", ".join(eff)))
    r = s["meta"].get("reference_run")
    if r:
        lines.append("The reference run (%s, %s): %d steps, wall time %.1f s." % (
            r["formulation"], ", ".join(s["meta"].get("reference", {}).get("set", [])) or "the study's set",
            r["steps"], r["wall_time_s"]))
    return lines


def findings(s):
    """Lines of what the study's sweep.json concludes."""
    meta, lines = s["meta"], []
    done = finished(s["rows"])
    if len(done) < len(s["rows"]):
        lines.append("%d of %d runs did not finish (the reasons are in the notes under the table)."
                     % (len(s["rows"]) - len(done), len(s["rows"])))
    if meta.get("regularization"):
        lines += regularization_findings(s)
    if kind(s) == "tolerance":
        lines += tolerance_findings(s)
    ref = meta.get("reference", {})
    for label, g, rows in richardson_groups(s):
        # The group names the other axes' values; "(all runs)" when there are none.
        group = "" if label in ("", "(all runs)") else " (%s)" % label
        if not g["ok"]:
            lines.append("Richardson's estimate%s: refused, %s; no observed order." % (group, g["note"]))
            continue
        text = ("Richardson's estimate%s: observed order %.2f, extrapolated %s load %.4f kN (size ratio %g)."
                % (group, g["observed_order"], ref.get("measure", "final"), g["extrapolated_load_kN"],
                   g["ratio"]))
        key = ref["axis"]
        q = coarser_order([size(key, r[key]) for r in rows], [compared(s, r) for r in rows])
        if q is not None:
            text += (" The three coarsest sizes give %.2f (where the two orders differ, the coarsest size is not in "
                     "the asymptotic range)." % q)
        lines.append(text)
    w = meta.get("window")
    if w:
        limits = "penetration / element size <= %g and median iterations per step <= %g" % (
            w["max_penetration_rel"], w["max_iterations"])
        if w.get("usable"):
            lines.append("Usable %s (%s): %g to %g, %.1f decades." % (short(w["axis"]), limits, w["from"], w["to"],
                                                                      w.get("decades", 0)))
        else:
            pen = sum(1 for r in done if r["penetration_rel"] is not None
                      and r["penetration_rel"] <= w["max_penetration_rel"])
            it = sum(1 for r in done if r["iterations_median"] is not None
                     and r["iterations_median"] <= w["max_iterations"])
            lines.append("Usable %s (%s): none. Of the %d finished runs, %d meet the penetration limit and %d the "
                         "iteration limit." % (short(w["axis"]), limits, len(done), pen, it))
    return lines


def cell(r, col, spec):
    """A table cell: yes / no for finished, text as is, "-" for a value not measured."""
    v = r.get(col)
    if col.startswith("iterations") and not r.get("steps"):
        return "-"  # no step after step 0
    if spec is None:
        return "yes" if v == 1 else "no"
    if spec == "%s":
        return v or ""
    return "-" if v is None else spec % v


def regularization_table(s):
    """The columns of a regularization study: per run its errors and their
    orders as the value falls, the monitor's value, iterations, wall time."""
    reg, monitor = s["meta"]["regularization"], s["meta"].get("monitor")
    mean = reg.get("load_error") == "mean_load_error"
    cols = [("formulation", "formulation", "%s")] if any(a["key"] == "formulation"
                                                         for a in s["meta"].get("axes", [])) else []
    cols += [(short(k), k, "%g") for k in s["axes"]]
    cols += [("finished", "finished", None), ("steps", "steps", "%d"),
             ("mean load (kN)" if mean else "final load (kN)", "mean_load_kN" if mean else "final_load_kN", "%.3f"),
             ("mean load error" if mean else "load error", reg["load_error"], "%.2e"),
             ("load order", "load_order", "%.2f")]
    if monitor:
        cols += [("%s (%s)" % (monitor["column"], "%" if monitor["unit"] == "percentage points" else
                               monitor["unit"]), "monitor_final", "%.4f"),
                 ("error (%s)" % monitor["unit"], "monitor_error_final", "%.2e"),
                 ("%s order" % monitor["column"], "monitor_order", "%.2f")]
    cols += [("iterations median", "iterations_median", "%g"), ("iterations max", "iterations_max", "%g"),
             ("iterations mean", "iterations_mean", "%.1f"), ("wall time (s)", "wall_time_s", "%.1f"),
             ("reason", "reason", "%s")]
    return cols


def tolerance_table(s):
    """The columns of a study measuring what a tolerance bounds: the error
    over the stroke, steps, rejected steps, wall time."""
    cols = [("formulation", "formulation", "%s")] if any(a["key"] == "formulation"
                                                         for a in s["meta"].get("axes", [])) else []
    cols += [(short(k), k, "%g") for k in s["axes"]]
    cols += [("finished", "finished", None), ("steps", "steps", "%d"), ("rejected steps", "step_rejections", "%d"),
             ("final load (kN)", "final_load_kN", "%.3f"), ("max |F_h - F| / max |F|", "load_error_max_rel", "%.2e"),
             ("iterations median", "iterations_median", "%g"), ("wall time (s)", "wall_time_s", "%.1f"),
             ("reason", "reason", "%s")]
    return [c for c in cols if c[2] is None or any(r.get(c[1]) not in (None, "") for r in s["rows"])]


def table(s):
    """Header and rows of the study's table; columns nobody measured left out."""
    cols, rows = table_columns(s)
    return [c[0] for c in cols], [[cell(r, col, spec) for _, col, spec in cols] for r in rows]


def table_columns(s):
    """The study table's columns (header, column, format; columns nobody
    measured left out) and the rows they are read from."""
    ref = s["meta"].get("reference", {})
    if s["meta"].get("regularization"):
        # The reference run last, its own values (its errors are zero by definition: not shown).
        ref_run = s["meta"].get("reference_run")
        rows = s["rows"] + ([dict({k: None if v == -1 else v for k, v in ref_run.items()},
                                  formulation=ref_run["formulation"] + " (reference)")] if ref_run else [])
        cols = regularization_table(s)
        return [c for c in cols if c[2] is None or any(r.get(c[1]) not in (None, "") for r in rows)], rows
    rich = ref.get("kind") == "richardson"
    if ref.get("measure") == "max_relative":
        return tolerance_table(s), s["rows"]
    cols = [("formulation", "formulation", "%s")] if any(a["key"] == "formulation"
                                                         for a in s["meta"].get("axes", [])) else []
    cols += [(short(k), k, "%g") for k in s["axes"]]
    cols += [("finished", "finished", None), ("steps", "steps", "%d"), ("final stroke (mm)", "final_stroke_mm", "%.3g"),
             ("final load (kN)", "final_load_kN", "%.4f" if rich and ref.get("measure") != "mean" else "%.2f")]
    if ref.get("measure") == "mean":
        cols.append(("mean load (kN)", "mean_load_kN", "%.4f"))
    cols += [("penetration / element size", "penetration_rel", "%.1e")]
    if not rich:
        cols.append(("load error, largest", "load_error", "%.1e"))
    cols += [("error vs extrapolated" if rich else "load error, last stroke", "load_error_final", "%.1e"),
             ("iterations median", "iterations_median", "%g"), ("iterations max", "iterations_max", "%g"),
             ("rcond", "rcond", "%.1e"), ("wall time (s)", "wall_time_s", "%.1f"), ("reason", "reason", "%s")]
    return [c for c in cols if c[2] is None or any(r.get(c[1]) not in (None, "") for r in s["rows"])], s["rows"]


def footnoted(header, rows, counted=False):
    """The table with its reasons (the last column, prose) as numbered notes
    under it, one number per distinct reason: header, rows, notes (with
    counted, each note ends with its number of runs)."""
    if not header or header[-1] != "reason":
        return header, rows, []
    number, count = {}, {}
    for r in rows:
        if r[-1]:
            number.setdefault(r[-1], len(number) + 1)
            count[r[-1]] = count.get(r[-1], 0) + 1
    notes = [x + (" (%d run%s)" % (count[x], "" if count[x] == 1 else "s") if counted else "") for x in number]
    return header[:-1] + ["note"], [r[:-1] + ["(%d)" % number[r[-1]] if r[-1] else ""] for r in rows], notes


def median(xs):
    xs = sorted(xs)
    n = len(xs)
    return xs[n // 2] if n % 2 else 0.5 * (xs[n // 2 - 1] + xs[n // 2])


def summary_tables(s):
    """A large study's tables: (axes and aggregates: header, rows), (its
    runs that did not finish: header, rows, notes, how many left out)."""
    cols, rows = table_columns(s)
    done = finished(rows)
    agg = []
    for k in s["axes"]:
        vs = sorted({r[k] for r in rows if r.get(k) is not None})
        if vs:
            agg.append(["%s (axis, %d values)" % (short(k), len(vs)), "%d" % len(rows), "%g" % vs[0],
                        "%g" % median(vs), "%g" % vs[-1]])
    for head, col, spec in cols:
        if spec in (None, "%s") or col in s["axes"]:
            continue
        vs = [r[col] for r in done if r.get(col) is not None and not (col.startswith("iterations") and not r.get("steps"))]
        if vs:
            agg.append([head, "%d" % len(vs), spec % min(vs), spec % median(vs), spec % max(vs)])
    # Every stopped run's reason numbered and counted, shown in the table or not.
    stopped = [[cell(r, col, spec) for _, col, spec in cols] for r in rows if r.get("finished") != 1]
    header, stopped, notes = footnoted([c[0] for c in cols], stopped, counted=True)
    return ((["quantity", "runs", "least", "median", "largest"], agg),
            (header, stopped[:ROWS_SHOWN], notes, max(0, len(stopped) - ROWS_SHOWN)))


def summary_block(s, entry):
    """A large study's tables in place of its row per run: (HTML, Markdown)."""
    (ah, arows), (sh, srows, notes, more) = summary_tables(s)
    done = len(finished(s["rows"]))
    intro = ("%d runs, %d finished, %d did not. Each row: a column of the table over the finished runs (the axes over "
             "all runs); the table of every run is %s (%d rows)." % (len(s["rows"]), done, len(s["rows"]) - done,
                                                                  entry["table"], len(s["rows"])))
    h, m = "<p>%s</p>" % html.escape(intro) + html_table(ah, arows), "%s\n\n" % intro + md_table(ah, arows) + "\n"
    if srows:
        line = "The runs that did not finish%s:" % (" (the first %d; %d more in the table)" % (len(srows), more)
                                                    if more else "")
        h += "<p>%s</p>" % html.escape(line) + html_table(sh, srows)
        m += "%s\n\n" % line + md_table(sh, srows) + "\n"
        h += "<ol class='footnotes'>%s</ol>" % "".join("<li>%s</li>" % html.escape(x) for x in notes) if notes else ""
        m += "".join("%d. %s\n" % (i + 1, x) for i, x in enumerate(notes)) + "\n" if notes else ""
    return h, m


def study_block(out, entry):
    """One study's part of the section: (HTML, Markdown)."""
    s = load_study(out, entry)
    title = "%s (%s%s)" % (entry["study"], entry.get("case", ""), ", quick grid" if entry.get("quick") else "")
    h, m = "<h3 id='%s'>%s</h3><p>%s</p>" % (anchor("study", entry["study"]), html.escape(title),
                                             html.escape(entry.get("description", ""))), \
        "### %s\n\n%s\n\n" % (title, entry.get("description", ""))
    if s["error"]:
        nh, nm = note("No table: %s" % s["error"])
        return h + nh, m + nm
    k = kind(s)
    if k:
        alt = "%s, %s" % (ALT[k], entry["study"])
        png, why = draw_or_skip(lambda: DRAW[k](s), alt, "study " + entry["study"])
        if not png and not why:
            why = "%s: not drawn, no finished run has the values" % alt
        fh, fm = (figure(out, "report_files/study_%s_%s.png" % (entry["study"], k), png, alt, caption(s, k))
                  if png else note(why))
        h, m = h + fh, m + fm
    lines = findings(s)
    h += "".join("<p>%s</p>" % html.escape(x) for x in lines)
    m += "".join("%s\n\n" % x for x in lines)
    if len(s["rows"]) > ROWS_SHOWN:
        sh, sm = summary_block(s, entry)
        return h + sh + "<p>Table: %s</p>" % html.escape(entry["table"]), m + sm + "Table: %s\n\n" % entry["table"]
    header, rows = table(s)
    header, rows, notes = footnoted(header, rows)
    foot_h = "<ol class='footnotes'>%s</ol>" % "".join("<li>%s</li>" % html.escape(x) for x in notes) if notes else ""
    foot_m = "".join("%d. %s\n" % (i + 1, x) for i, x in enumerate(notes)) + "\n" if notes else ""
    return (h + html_table(header, rows) + foot_h + "<p>Table: %s</p>" % html.escape(entry["table"]),
            m + md_table(header, rows) + "\n" + foot_m + "Table: %s\n\n" % entry["table"])


def studies_section(out, entries):
    """The Studies section: (HTML, Markdown); empty when no study ran."""
    if not entries:
        return "", ""
    intro = ("Studies of cases/studies run by the suite (rpfem sweep's tables, docs/sweeps.md): one scene over a "
             "grid of numerical parameters, a row per run.")
    blocks = [study_block(out, e) for e in entries]
    return ("<h2 id='studies'>Studies</h2><p>%s</p>%s" % (html.escape(intro), "".join(b[0] for b in blocks)),
            "## Studies\n\n%s\n\n%s" % (intro, "".join(b[1] for b in blocks)))
