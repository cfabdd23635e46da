"""The studies' figures in the suite report (reports/study_section.py), from
a study read by study_results.load_study; each returns a PNG, or None when
the table has nothing to draw. Values not measured (None) are never drawn;
runs that did not finish are marked x at the foot of the panel (the reason
is in the study's table).
- sensitivity: against one axis on log axes (the penalty's beta factor),
  penetration / element size, load error against the reference, Newton
  iterations per step and the tangent's rcond, the usable window shaded;
- convergence: Richardson's error against the size h and the compared load
  against h, the observed order annotated;
- pareto: the load error against wall time, a marker per formulation, the
  mesh labelled, the Pareto front drawn;
- regularization: against a regularization parameter falling to the
  reference's limit (the friction's smoothing speed against the exact
  law), log-log, per formulation, the load and monitor errors with their
  fitted orders, Newton iterations per step and wall time, the reference
  run's as horizontal lines;
- tolerance: step control by a local error estimate, per formulation the
  achieved error (what the tolerance bounds) against the stated tolerance
  with the line y = x, and the wall time against it;
- grid: a study of two numeric axes and no reference (a grid of hundreds
  or thousands of runs), each run a cell coloured by its final load and by
  its wall time over the two axes, stopped runs marked x."""
import math
import textwrap

from matplotlib.ticker import FuncFormatter
from matplotlib.transforms import blended_transform_factory

from curve_figures import floored
from plotting import missing_panel, plt, png_bytes
from study_results import TOLERANCE, regularization_groups, short, size

MARKERS = {"direct": "o", "penalty": "s", "auglag": "v", "ipopt": "^", "ssn": "*"}
NAN = float("nan")


def finished(rows):
    return [r for r in rows if r["finished"] == 1]


def mark_stopped(ax, xs):
    """x marks at the foot of the panel at the axis values xs."""
    if xs:
        ax.plot(xs, [0.03] * len(xs), "x", color="C3", markersize=8, clip_on=False,
                transform=blended_transform_factory(ax.transData, ax.transAxes), label="did not finish")


def plain_x_ticks(ax):
    """Tick labels of a log x axis spanning less than two decades as plain
    numbers (2, 0.05) instead of 2 x 10^0."""
    ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: "%g" % v))
    ax.xaxis.set_minor_formatter(FuncFormatter(lambda v, _: "%g" % v if round(v / 10 ** math.floor(math.log10(v)))
                                               in (2, 3, 4, 5) else ""))


def window_span(values, usable):
    """The usable window (lo, hi) on a log axis: from half-way (in log) to
    the grid's next value below the first usable value to half-way to the
    next above the last (at the grid's ends, as far as to the inner
    neighbour); None when nothing is usable."""
    if not usable:
        return None
    vs = sorted(values)
    lo, hi = min(usable), max(usable)
    below = [v for v in vs if v < lo] or [lo * lo / ([v for v in vs if v > lo] or [lo * 10])[0]]
    above = [v for v in vs if v > hi] or [hi * hi / ([v for v in vs if v < hi] or [hi / 10])[-1]]
    return math.sqrt(lo * below[-1]), math.sqrt(hi * above[0])


# Panels of the sensitivity figure: y label, title, [(column, legend)], log y, limit from the window (key, default).
SENSITIVITY_PANELS = [
    ("max penetration / element size", "penetration", [("penetration_rel", "largest over the run")], True,
     ("max_penetration_rel", 1e-3)),
    ("relative load difference", "load error against the reference run",
     [("load_error", "largest over the strokes"), ("load_error_final", "at the last stroke")], True, None),
    ("Newton iterations per step", "iterations per step (step 0 left out)",
     [("iterations_median", "median"), ("iterations_max", "max")], False, ("max_iterations", 10.0)),
    ("rcond (least over the run)", "tangent's reciprocal condition estimate", [("rcond", "rcond")], True, None),
]


def log_axes(ax, log_y, ylabel, title):
    """A log x axis; a log y axis, or a linear one from 0; the labels."""
    ax.set_xscale("log")
    if log_y:
        ax.set_yscale("log")
    else:
        ax.set_ylim(bottom=0)
    ax.set(ylabel=ylabel)
    ax.set_title(title, fontsize=9)


def sensitivity_png(s):
    key = s["axes"][0]
    rows = sorted(s["rows"], key=lambda r: r[key])
    if not rows:
        return None
    window = s["meta"].get("window", {})
    span = window_span([r[key] for r in rows], window.get("usable", []))
    xs = [r[key] for r in rows]
    fig, axes = plt.subplots(2, 2, figsize=(10.4, 7.2), dpi=110, sharex=True)
    for ax, (ylabel, title, cols, log, limit) in zip(axes.ravel(), SENSITIVITY_PANELS):
        drawn = False
        for i, (col, legend) in enumerate(cols):
            ys = [r[col] if r["finished"] == 1 and r[col] is not None else NAN for r in rows]
            if any(y == y for y in ys):
                ax.plot(xs, floored(ys) if log else ys, "o-", color="C%d" % i, label=legend, markersize=4)
                drawn = True
        if limit:
            value = window.get(limit[0], limit[1])
            ax.axhline(value, color="k", linestyle="--", linewidth=0.8, label="limit %g" % value)
        if span:
            ax.axvspan(*span, color="C2", alpha=0.15, label="usable window")
        mark_stopped(ax, [r[key] for r in rows if r["finished"] != 1])
        if not drawn:
            missing_panel(ax, "not measured in any finished run")
        log_axes(ax, log, ylabel, title)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    for ax in axes[-1]:
        ax.set_xlabel(short(key) + " (times the default)" if key.endswith("beta_factor") else key)
    fig.suptitle("%s: %s" % (s["study"], s["meta"].get("description", "")), fontsize=10)
    fig.tight_layout()
    return png_bytes(fig)


def richardson_groups(s):
    """(label, Richardson entry of sweep.json, finished rows it speaks of)
    per group: the rows of the group's formulation if the label names one,
    else every row."""
    out = []
    for g in s["meta"].get("richardson", []):
        label = g.get("group", "")
        f = label.split("formulation=", 1)[1].split()[0] if "formulation=" in label else None
        rows = [r for r in finished(s["rows"]) if f is None or r["formulation"] == f]
        out.append((label, g, rows))
    return out


def compared(s, r):
    """The load Richardson compares (kN): the mean or the final load."""
    return r["mean_load_kN"] if s["meta"]["reference"].get("measure") == "mean" else r["final_load_kN"]


def convergence_png(s):
    key = s["meta"]["reference"]["axis"]
    groups = richardson_groups(s)
    if not groups or not any(rows for _, _, rows in groups):
        return None
    measure = s["meta"]["reference"].get("measure", "final")
    xlabel = "relative element size h = 1 / mesh_factor" if key == "run.mesh_factor" else short(key) + " (mm)"
    fig, (left, right) = plt.subplots(1, 2, figsize=(10.4, 4.4), dpi=110)
    notes = []
    for i, (label, g, rows) in enumerate(groups):
        label = label if len(groups) > 1 else "runs"
        hs = [size(key, r[key]) for r in rows]
        right.plot(hs, [compared(s, r) for r in rows], "o-", color="C%d" % i, label=label)
        if not g["ok"]:
            notes.append(("%s: " % label if len(groups) > 1 else "") + "Richardson's estimate refused:\n"
                         + textwrap.fill(g["note"], 48))
            continue
        right.axhline(g["extrapolated_load_kN"], color="C%d" % i, linestyle="--", linewidth=0.8,
                      label="extrapolated %.4g kN" % g["extrapolated_load_kN"])
        pts = sorted((h, r["load_error_final"]) for h, r in zip(hs, rows) if r["load_error_final"])
        left.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", color="C%d" % i, label=label)
        # The observed order's slope over the three finest sizes, a factor 2 below them.
        h0, e0 = pts[min(1, len(pts) - 1)]
        hr = [pts[0][0], pts[min(2, len(pts) - 1)][0]]
        left.loglog(hr, [0.5 * e0 * (h / h0) ** g["observed_order"] for h in hr], "k:", linewidth=1)
        left.annotate("observed order %.2f" % g["observed_order"], (h0, 0.5 * e0), textcoords="offset points",
                      xytext=(8, -12), fontsize=8)
    if notes:
        missing_panel(left, "\n\n".join(notes) + "\n\nno observed order")
        if not left.lines:
            left.set(xticks=[], yticks=[])
    left.set(xlabel=xlabel, ylabel="|%s load / extrapolated - 1|" % measure)
    left.set_title("error against Richardson's estimate (%s load)" % measure, fontsize=9)
    right.set_xscale("log")
    right.set(xlabel=xlabel, ylabel="%s load (kN)" % measure)
    right.set_title("the compared load", fontsize=9)
    for ax in (left, right):
        plain_x_ticks(ax)
        ax.grid(True, which="both", alpha=0.3)
        if ax.lines:
            ax.legend(fontsize=7)
    fig.suptitle("%s: %s" % (s["study"], s["meta"].get("description", "")), fontsize=10)
    fig.tight_layout()
    return png_bytes(fig)


def pareto_front(points):
    """The points no other point beats in both time and error, by time."""
    front, best = [], float("inf")
    for t, e in sorted(points):
        if e < best:
            front.append((t, e))
            best = e
    return front


def pareto_png(s):
    key = s["meta"]["reference"]["axis"]
    rows = [r for r in finished(s["rows"]) if r["load_error_final"] is not None and r["wall_time_s"]]
    if not rows:
        return None
    fig, ax = plt.subplots(figsize=(7.4, 5.0), dpi=110)
    formulations = []
    for r in rows:
        if r["formulation"] not in formulations:
            formulations.append(r["formulation"])
    for i, f in enumerate(formulations):
        mine = [r for r in rows if r["formulation"] == f]
        ax.scatter([r["wall_time_s"] for r in mine], floored([r["load_error_final"] for r in mine]),
                   marker=MARKERS.get(f, "D"), color="C%d" % i, label=f, zorder=3)
        for r in mine:
            ax.annotate("%g" % r[key], (r["wall_time_s"], max(r["load_error_final"], 1e-16)),
                        textcoords="offset points", xytext=(5, 3), fontsize=7)
    front = pareto_front([(r["wall_time_s"], max(r["load_error_final"], 1e-16)) for r in rows])
    ax.step([p[0] for p in front], [p[1] for p in front], where="post", color="k", linestyle="--", linewidth=0.9,
            label="Pareto front")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set(xlabel="wall time (s)", ylabel="|%s load / reference - 1|" % s["meta"]["reference"].get("measure", "final"))
    ax.set_title("%s: error against wall time (labels: %s)" % (s["study"], short(key)), fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return png_bytes(fig)


def group_name(label):
    """A regularization group's legend: the formulation alone where the
    label names only it."""
    return label.split("=", 1)[1] if label.startswith("formulation=") and " " not in label else label


def error_panel(ax, s, part, column, ylabel, title):
    """The errors of one part ("load" or "monitor") against the axis, per
    group, log-log, the fitted order in the legend; the floor dashed; runs
    that did not finish marked x."""
    reg = s["meta"]["regularization"]
    drawn = False
    for i, (label, g, rows) in enumerate(regularization_groups(s)):
        orders = g.get(part)
        if not orders:
            continue
        pts = [(r[reg["axis"]], r[column]) for r in rows if r["finished"] == 1 and r.get(column) is not None]
        fit = orders.get("fit_order")
        legend = group_name(label) + (" (order %.2f over %d)" % (fit, orders["fit_points"]) if fit is not None
                                      else " (no order)")
        if pts:
            ax.loglog([p[0] for p in pts], floored([p[1] for p in pts]), "-", color="C%d" % i,
                      marker=MARKERS.get(group_name(label), "D"), markersize=5, label=legend)
            drawn = True
        mark_stopped(ax, [r[reg["axis"]] for r in rows if r["finished"] != 1])
    if not drawn:
        missing_panel(ax, "not measured in any finished run")
        return
    floor = next((g[part]["floor"] for _, g, _ in regularization_groups(s) if g.get(part)), 0)
    if floor > 0:
        ax.axhline(floor, color="k", linestyle="--", linewidth=0.8, label="floor %g" % floor)
    if reg.get("default", -1) > 0:
        ax.axvline(reg["default"], color="0.5", linestyle=":", linewidth=1, label="default %g" % reg["default"])
    log_axes(ax, True, ylabel, title)


def cost_panel(ax, s, columns, ylabel, title, log):
    """Per group, columns [(column, line style, legend)] against the axis; the
    reference run's values as horizontal lines."""
    reg, ref = s["meta"]["regularization"], s["meta"].get("reference_run", {})
    for i, (label, _, rows) in enumerate(regularization_groups(s)):
        done = [r for r in rows if r["finished"] == 1]
        for col, style, legend in columns:
            pts = [(r[reg["axis"]], r[col]) for r in done if r.get(col) is not None]
            if pts:
                ax.plot([p[0] for p in pts], [p[1] for p in pts], linestyle=style, color="C%d" % i,
                        marker=MARKERS.get(group_name(label), "D"), markersize=4,
                        label="%s%s" % (group_name(label), legend))
    for col, style, legend in columns:
        if ref.get(col, -1) >= 0 and ref.get("finished"):
            ax.axhline(ref[col], color="k", linestyle=style, linewidth=0.9,
                       label="%s (reference)%s" % (ref.get("formulation", ""), legend))
    log_axes(ax, log, ylabel, title)


def regularization_png(s):
    reg = s["meta"]["regularization"]
    if not any(rows for _, _, rows in regularization_groups(s)):
        return None
    monitor = s["meta"].get("monitor", {})
    ref = s["meta"].get("reference_run", {}).get("formulation", "the reference")
    mean = reg.get("load_error") == "mean_load_error"
    fig, axes = plt.subplots(2, 2, figsize=(10.4, 7.6), dpi=110, sharex=True)
    error_panel(axes[0, 0], s, "load", reg["load_error"],
                "|%s load / %s's - 1|" % ("mean" if mean else "final", ref),
                "%s load error against %s" % ("mean" if mean else "final", ref))
    if monitor:
        error_panel(axes[0, 1], s, "monitor", reg["monitor_error"],
                    "|%s - %s's| (%s)" % (monitor["column"], ref, monitor["unit"]),
                    "%s at the last stroke against %s" % (monitor["column"], ref))
    else:
        missing_panel(axes[0, 1], "the study compares no monitor")
    cost_panel(axes[1, 0], s, [("iterations_median", "-", " median"), ("iterations_max", ":", " max")],
               "Newton iterations per step", "iterations per step (step 0 left out)", True)
    cost_panel(axes[1, 1], s, [("wall_time_s", "-", "")], "wall time (s)", "wall time per run", True)
    for ax in axes.ravel():
        ax.grid(True, which="both", alpha=0.3)
        if ax.lines:
            ax.legend(fontsize=7)
    axes[0, 0].invert_xaxis()  # shared: every panel's parameter falls to the right
    for ax in axes[-1]:
        ax.set_xlabel("%s (falling to the right)" % short(reg["axis"]))
    fig.suptitle(textwrap.fill("%s: %s" % (s["study"], s["meta"].get("description", "")), 110), fontsize=10)
    fig.tight_layout()
    return png_bytes(fig)


def axis_scale(ax, which, values):
    """A log scale on the axis when its positive values span more than two
    decades."""
    vs = [v for v in values if v > 0]
    if vs and len(vs) == len(values) and max(vs) / min(vs) > 100:
        (ax.set_xscale if which == "x" else ax.set_yscale)("log")


def grid_png(s):
    """Final load and wall time of each run over the study's two axes: one
    scatter point per run (its grid cell), a colour bar per panel."""
    kx, ky = s["axes"][:2]
    done = finished(s["rows"])
    if not done:
        return None
    fig, axes = plt.subplots(1, 2, figsize=(10.4, 4.2), dpi=110)
    for ax, (col, label) in zip(axes, [("final_load_kN", "final load (kN)"), ("wall_time_s", "wall time (s)")]):
        pts = [(r[kx], r[ky], r[col]) for r in done if r[col] is not None]
        if pts:
            xs, ys, cs = zip(*pts)
            sc = ax.scatter(xs, ys, c=cs, s=max(4.0, 3000.0 / len(pts)), marker="s", cmap="viridis")
            fig.colorbar(sc, ax=ax, label=label)
        else:
            missing_panel(ax, "not measured in any finished run")
        stopped = [(r[kx], r[ky]) for r in s["rows"] if r["finished"] != 1]
        if stopped:
            ax.plot(*zip(*stopped), "x", color="C3", markersize=5, label="did not finish (%d)" % len(stopped))
            ax.legend(fontsize=7, loc="upper right")  # "best" searches every point: slow for thousands
        axis_scale(ax, "x", [r[kx] for r in s["rows"]])
        axis_scale(ax, "y", [r[ky] for r in s["rows"]])
        ax.set(xlabel=short(kx), ylabel=short(ky))
        ax.set_title("%s of each finished run" % label, fontsize=9)
    fig.suptitle(textwrap.fill("%s: %s" % (s["study"], s["meta"].get("description", "")), 110), fontsize=10)
    fig.tight_layout()
    return png_bytes(fig)


def formulation_curves(rows):
    """(formulation, its finished runs by tolerance, its stopped runs) in the
    order the table first names each formulation."""
    names = []
    for r in rows:
        if r["formulation"] not in names:
            names.append(r["formulation"])
    return [(f, sorted((r for r in finished(rows) if r["formulation"] == f), key=lambda r: r[TOLERANCE]),
             [r for r in rows if r["formulation"] == f and r["finished"] != 1]) for f in names]


def tolerance_png(s):
    """Left: the achieved error (sweep.csv load_error_max_rel: max over the
    stroke of |F_h - F| / max |F| away from the landings) against the stated
    tolerance, log-log, one curve per formulation, the line y = x and the
    band of a factor 3 about it; right: each run's wall time."""
    rows = s["rows"]
    curves = formulation_curves(rows)
    if not any(done for _, done, _ in curves):
        return None
    ref = s["meta"].get("reference", {})
    against = ("the exact load" if ref.get("kind") == "exact" else
               "the %s reference run" % s["meta"].get("reference_run", {}).get("formulation", ""))
    fig, axes = plt.subplots(1, 2, figsize=(10.4, 4.4), dpi=110)
    tols = sorted({r[TOLERANCE] for r in rows})
    for i, (f, done, stopped) in enumerate(curves):
        pts = [(r[TOLERANCE], r["load_error_max_rel"], r["wall_time_s"]) for r in done
               if r.get("load_error_max_rel") is not None]
        style = dict(color="C%d" % i, marker=MARKERS.get(f, "D"), markersize=5, label=f)
        if pts:
            axes[0].loglog([p[0] for p in pts], floored([p[1] for p in pts]), "-", **style)
            axes[1].loglog([p[0] for p in pts], [p[2] for p in pts], "-", **style)
        for ax in axes:
            mark_stopped(ax, [r[TOLERANCE] for r in stopped])
    lo, hi = tols[0] / 2, tols[-1] * 2
    axes[0].loglog([lo, hi], [lo, hi], "k-", linewidth=0.9, label="y = x")
    axes[0].fill_between([lo, hi], [lo / 3, hi / 3], [3 * lo, 3 * hi], color="0.5", alpha=0.12,
                         label="factor 3")
    axes[0].set(xlabel="stated tolerance", ylabel="achieved max |F_h - F| / max |F|")
    axes[0].set_title("achieved error against %s" % against, fontsize=9)
    axes[1].set(xlabel="stated tolerance", ylabel="wall time (s)")
    axes[1].set_title("wall time per run", fontsize=9)
    for ax in axes:
        ax.invert_xaxis()  # tighter to the right
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(textwrap.fill("%s: %s" % (s["study"], s["meta"].get("description", "")), 110), fontsize=10)
    fig.tight_layout()
    return png_bytes(fig)


DRAW = {"tolerance": tolerance_png, "sensitivity": sensitivity_png, "convergence": convergence_png, "pareto": pareto_png,
        "regularization": regularization_png, "grid": grid_png}
