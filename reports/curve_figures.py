"""The curve figures of the suite report (reports/make_report.py), from each
run's history.csv: the press load against stroke for every formulation and
variant on one plot (kN; paper Fig. 11) beside each formulation's relative
difference from the reference on a log scale with the landings marked; per
step against stroke the penetration, iterations, Newton's force residual and the force imbalance
(die loads against each other, and penalty's contact pairs between bodies);
and for rings the calibration curves (inner-diameter change against height
reduction, a colour per friction value, with Avitzur's upper bound per
friction factor and the exact frictionless curve)."""
import numpy as np

from plotting import missing_panel, plt, png_bytes
from reference_curves import friction_of, load_references, ring_frictionless, ring_geometry, ring_upper_bound
from load_flags import DIFFERENCE, compared, landing_intervals
from results import initial_height, label, reference_run


def floored(values):
    """values for a log scale: zeros shown at the floor 1e-16."""
    return [max(v, 1e-16) if v == v else v for v in values]


def die_balance(h):
    """|sum of the dies' Fy| / max |die Fy| per step over the dies that carry
    a y load (global equilibrium of the press); None with fewer than two."""
    dies = [c for c in h if c.endswith(".Fy") and c[:-3] + ".Fx" in h and any(v != 0 for v in h[c])]
    if len(dies) < 2:
        return None
    fy = np.array([h[c] for c in dies])
    peak = np.abs(fy).max(axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        return list(np.where(peak > 0, np.abs(fy.sum(axis=0)) / peak, np.nan))


def balance_curves(ax, runs):
    """The force imbalance per step: the press balance over the dies
    (solid) and penalty's contact-pair imbalance between bodies (dashed)."""
    for i, r in enumerate(runs):
        h = r["history"]
        balance = die_balance(h)
        if balance is not None:
            ax.plot(h["stroke"], floored(balance), label=label(r) + ": dies", color="C%d" % i)
        if "force_imbalance" in h:
            ax.plot(h["stroke"], floored(h["force_imbalance"]), label=label(r) + ": contact pair", color="C%d" % i,
                    linestyle="--")
    ax.set_yscale("log")


def column_curves(column, log):
    """A function drawing history column `column` of every run against
    stroke (log scale: zeros at 1e-16)."""
    def draw(ax, runs):
        for i, r in enumerate(runs):
            if column in r["history"]:
                values = r["history"][column]
                ax.plot(r["history"]["stroke"], floored(values) if log else values, label=label(r), color="C%d" % i)
        ax.set_yscale("log" if log else "linear")
    return draw


STEP_PANELS = [  # drawing, y label, title, note when there is nothing to draw
    (column_curves("max_penetration_rel", True), "max penetration / element size",
     "penetration (floor 1e-16 shown for zero)", "no contact penetration reported"),
    (column_curves("newton_iterations", False), "iterations per step (Newton or Ipopt)", "iterations per step",
     "no iteration counts"),
    (column_curves("residual", True), "force residual (relative)",
     "Newton's relative force residual at convergence\n(ipopt: its KKT stationarity)", "no residual recorded"),
    (balance_curves, "force imbalance (relative)",
     "press balance |sum of die Fy| / max |die Fy| (solid);\npenalty between bodies: |Fa + Fb| / max |F| (dashed)",
     "fewer than two dies with a y load\nand no contact pair between bodies"),
]


def steps_png(runs, title):
    """Per step against stroke, base runs: penetration per element size,
    iterations, Newton's force residual, and the force imbalance."""
    runs = [r for r in runs if r["history"].get("stroke") and not r["variant"]]
    fig, axes = plt.subplots(2, 2, figsize=(10.4, 7.2), dpi=110)
    for ax, (draw, ylabel, panel_title, empty) in zip(axes.ravel(), STEP_PANELS):
        draw(ax, runs)
        if ax.lines:
            ax.legend(fontsize=7)
        else:
            ax.set(yscale="linear", yticks=[])
            missing_panel(ax, empty)
        ax.set(xlabel="stroke (mm)", ylabel=ylabel)
        ax.set_title(panel_title, fontsize=9)
        ax.grid(True, alpha=0.3)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return png_bytes(fig)


# Colours of the friction values by rank, distinct side by side: the
# factors m from purple through blue and green to brown and grey (no red),
# the Coulomb coefficients mu in oranges, reds and pink; more values than
# colours take viridis (m) or repeat (mu).
M_COLOURS = ["#6a3d9a", "#1f78b4", "#17becf", "#1b9e77", "#66a61e", "#b79f00", "#8c564b", "#4d4d4d"]
MU_COLOURS = ["#ff7f00", "#e31a1c", "#99000d", "#e7298a"]
# Markers of the formulations past the first (drawn as a plain line).
MARKERS = ["o", "s", "^", "v", "D", "P", "X", "*"]


def friction_colours(frictions):
    """{("m" | "mu", value): colour}, in increasing order of the value."""
    ms = sorted(v for k, v in frictions if k == "m")
    mus = sorted(v for k, v in frictions if k == "mu")
    many = plt.get_cmap("viridis")
    colours = {("m", v): M_COLOURS[i] if len(ms) <= len(M_COLOURS) else many(0.9 * i / (len(ms) - 1))
               for i, v in enumerate(ms)}
    colours.update({("mu", v): MU_COLOURS[i % len(MU_COLOURS)] for i, v in enumerate(mus)})
    return colours


def friction_text(friction):
    return "unknown friction" if friction is None else "%s = %g%s" % (
        "m" if friction[0] == "m" else "\u03bc", friction[1], " (Coulomb)" if friction[0] == "mu" else "")


def calibration_png(out, runs, title):
    """Ring calibration curves: inner-diameter change (%) against height
    reduction (%), one curve per run, from the `inner_diameter_mid`
    monitor; None when the scene has none. One colour per friction value
    (summary.json's dies.*.friction: factor m or Coulomb mu), a marker per
    formulation (the first a plain line). For every factor m > 0, in its
    colour, dashed and thin: Avitzur's upper bound on the run's own ring
    (reference_curves.ring_upper_bound; ro, ri and the full height from
    summary.json); for m = 0 the exact homogeneous curve, black dotted
    (the upper bound gives the same). Coulomb runs have no closed-form
    curve: the bound is for a constant friction factor."""
    curves = [(r, H0) for r in runs if "inner_diameter_mid" in r["history"] and (H0 := initial_height(out, r))]
    if not curves:
        return None
    groups = {}  # friction -> [(run, reductions)]
    for r, H0 in curves:
        groups.setdefault(friction_of(r["summary"]), []).append((r, [100 * s / H0 for s in r["history"]["stroke"]]))
    colours = friction_colours([f for f in groups if f is not None])
    formulations = list(dict.fromkeys(r["formulation"] for r, _ in curves))
    markers = {f: MARKERS[i - 1] if i else None for i, f in enumerate(formulations[:len(MARKERS) + 1])}
    fig, ax = plt.subplots(figsize=(8.8, 5.0), dpi=110)
    friction_handles = []
    order = sorted(groups, key=lambda f: (f is None, f and f[0] == "mu", f and f[1]))
    for friction in order:
        colour = colours.get(friction, "0.5")
        for r, x in groups[friction]:
            k = formulations.index(r["formulation"])
            ax.plot(x, r["history"]["inner_diameter_mid"], color=colour, linewidth=1.4,
                    marker=markers.get(r["formulation"], "x"), markersize=4.5, fillstyle="none",
                    markevery=(0.03 * (k % 3), 0.1) if k else None)  # staggered: coinciding runs show each marker
        top = max(max(x) for _, x in groups[friction])
        geometry = ring_geometry(groups[friction][0][0]["summary"])
        if friction and friction[0] == "m" and friction[1] > 0 and geometry and top > 0:
            xs = list(np.linspace(0, top, 60))
            ax.plot(xs, ring_upper_bound(*geometry, friction[1], xs), color=colour, linewidth=1.0,
                    linestyle=(0, (5, 3)), zorder=1)
        friction_handles.append(plt.Line2D([], [], color=colour, linewidth=3, label=friction_text(friction)))
    top = max(max(x) for g in groups.values() for _, x in g)
    xs = list(np.linspace(0, top, 60))
    ax.plot(xs, ring_frictionless(xs), color="k", linewidth=2.2, linestyle=":", zorder=1)
    style_handles = [plt.Line2D([], [], color="0.3", linewidth=1.4, marker=markers.get(f, "x"), fillstyle="none",
                                label=f + " (FE)") for f in formulations]
    style_handles += [plt.Line2D([], [], color="0.3", linewidth=1.0, linestyle=(0, (5, 3)),
                                 label="upper bound, friction factor m\n(Avitzur 1968)"),
                      plt.Line2D([], [], color="k", linewidth=2.2, linestyle=":",
                                 label="m = 0, exact: sqrt(H0/H) - 1")]
    ax.axhline(0, color="k", linewidth=0.5)
    ax.set_xlabel("height reduction (%)")
    ax.set_ylabel("inner diameter change at mid-height (%)")
    ax.set_title(title + ": calibration curves")
    ax.grid(True, alpha=0.3)
    first = ax.legend(handles=friction_handles, title="friction (colour)", fontsize=8, title_fontsize=8,
                      loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.add_artist(first)
    ax.legend(handles=style_handles, title="line", fontsize=8, title_fontsize=8, loc="lower left",
              bbox_to_anchor=(1.01, 0.0))
    fig.tight_layout()
    return png_bytes(fig)


def run_colour(i, runs):
    """The colour of runs[i] on both panels of the load figure: matplotlib's
    ten-colour cycle, tab20 for more runs (the cycle would repeat)."""
    return "C%d" % i if len(runs) <= 10 else plt.get_cmap("tab20")(i % 20)


def load_curves(ax, runs, title):
    """Press load against stroke, every run (in run_colour), with
    the scene's closed-form reference (reference_curves.py) where there is
    one."""
    # Several references (the slab load per friction factor): one dash
    # pattern each, all black.
    for (strokes, loads, text), dash in zip(load_references(title, runs), ["--", "-.", ":", (0, (5, 1, 1, 1, 1, 1))]):
        ax.plot(strokes, [np.nan if v is None else v for v in loads], color="k", linestyle=dash, linewidth=1.5,
                label=text, zorder=5)
    marked = False
    for i, r in enumerate(runs):
        if r["load_col"]:
            stroke = r["history"]["stroke"]
            load = [abs(v) / 1000 for v in r["history"][r["load_col"]]]
            ax.plot(stroke, load, label=label(r) + " (" + r["load_col"].rsplit(".", 1)[0] + ")",
                    color=run_colour(i, runs))
            # Each remesh at its stroke, on the curve (summary.json's remeshes).
            at = [m["stroke_mm"] for m in r["summary"].get("remeshes", [])]
            if at:
                ax.plot(at, np.interp(at, stroke, load), linestyle="none", marker="x",
                        color=run_colour(i, runs), markersize=6, label=None if marked else "remesh")
                marked = True
    plane = any(r["summary"].get("parameters", {}).get("run", {}).get("geometry", "").startswith("plane")
                for r in runs)
    ax.set_xlabel("stroke (mm)")
    ax.set_ylabel("load (kN/mm, per unit thickness)" if plane else "load (kN)")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    if ax.lines:
        ax.legend(fontsize=8)


# |relative load difference| shown at this floor where it is zero (log scale).
DIFFERENCE_FLOOR = 1e-12


def difference_curves(ax, runs, ref):
    """|relative difference| of each run's load from the reference run's
    against the stroke, log scale, in the run's colour (load_flags.compared):
    a line through every compared stroke, dots at the strokes away from the
    landings (the ones the flags use); the landing steps of each run as
    ticks along the bottom (the reference's in black, lowest), the flag
    threshold dashed."""
    if ref is None:
        missing_panel(ax, "no reference run")
        return
    rows = [(i, r, compared(r, ref)) for i, r in enumerate(runs) if r is not ref and r["load_col"]]
    rows = [(i, r, c) for i, r, c in rows if c]
    for i, r, c in rows:
        s = [x[0] for x in c]
        d = [max(abs(x[3]), DIFFERENCE_FLOOR) for x in c]
        ax.plot(s, d, color=run_colour(i, runs), linewidth=0.8, alpha=0.6, label=label(r))
        ax.plot([x for x, ok in zip(s, (x[4] for x in c)) if ok], [y for y, x in zip(d, c) if x[4]], linestyle="none",
                marker=".", markersize=3, color=run_colour(i, runs))
    ax.set_yscale("log")
    ax.axhline(DIFFERENCE, color="k", linestyle="--", linewidth=0.8,
               label="flag threshold %.1f %%" % (100 * DIFFERENCE))
    # Room below the curves, a quarter of the height, for the landing ticks:
    # a row per run, the reference's lowest.
    lo, hi = ax.get_ylim()
    ax.set_ylim(lo / (hi / lo) ** (1 / 3), hi)
    ticks = [(ref, "k")] + [(r, run_colour(i, runs)) for i, r, _ in rows]
    pitch = min(0.04, 0.22 / len(ticks))
    for k, (r, colour) in enumerate(ticks):
        at = [b for _, b in landing_intervals(r)]
        ax.plot(at, [0.02 + pitch * k] * len(at), transform=ax.get_xaxis_transform(), linestyle="none", marker="|",
                markersize=5, color=colour, label="landings (ticks: %s lowest)" % label(ref) if k == 0 else None)
    ax.set_xlabel("stroke (mm)")
    ax.set_ylabel("|load / reference load - 1|")
    ax.set_title("difference from %s (dots: away from landings)" % label(ref), fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)


def load_png(runs, title):
    """Press load against stroke beside each run's relative difference from
    the scene's reference run (log scale, landings marked)."""
    fig, (ax, dax) = plt.subplots(1, 2, figsize=(12.8, 4.6), dpi=110)
    load_curves(ax, runs, title)
    difference_curves(dax, runs, reference_run([r for r in runs if not r["variant"]]))
    fig.tight_layout()
    return png_bytes(fig)


# The report's entries (see make_report.FIGURES): alt text, file tag, drawing, caption.
LOAD_FIGURE = (
    "load against stroke", "load", lambda out, rs, sc: load_png(rs, sc),
    "Left: press load (kN; plane strain: kN/mm of thickness) against stroke (mm), every formulation and variant "
    "(paper Fig. 11); an x marks each remesh of a run that remeshes. Dashed black, where the scene has one: the "
    "closed form, for frictionless upsetting the exact homogeneous load F = sigma(ln H0/H) A0 H0/H (plane strain: "
    "2/sqrt3 sigma w0 H0/H; verification/analytic.cpp), for the plane-strain indentation Prandtl's flat-punch "
    "load 2k(1 + pi/2) b on a half-space at the initial flow stress (the block is finite and the punch filleted: "
    "a guide, not the exact answer), for a cylinder upset with a friction factor m the slab method's load per m, "
    "F = sigma (1 + 2mR/(3 sqrt3 H)) pi R^2 at the homogeneous height, radius and strain (Altan et al. 1983; "
    "verification/slab_comparison.cpp; no barrelling and no sticking zone: an estimate, above the exact load). "
    "Right: each run's |relative difference| from the reference formulation's load (direct where it ran, else "
    "ipopt; interpolated linearly) at the run's strokes, log scale (zero shown at 1e-12), in the run's colour: a "
    "line through every stroke, dots at the strokes away from the landings (those the flags compare); ticks "
    "along the bottom mark each run's landing steps (its number of rows in contact changes; the reference's "
    "lowest, black); dashed, the flag threshold.")
STEPS_FIGURE = (
    "penetration, iterations and force imbalance per step", "steps", lambda out, rs, sc: steps_png(rs, sc),
    "Per step against stroke: largest penetration over the element size, iterations, Newton's relative force "
    "residual at convergence (Ipopt: KKT stationarity), and the force imbalance: |sum of the dies' Fy| / "
    "max |die Fy| (global equilibrium of the press, scenes with two or more loaded dies) and penalty's "
    "contact-pair imbalance between deformable bodies. Log scales show zeros at 1e-16.")
CALIBRATION_FIGURE = (
    "ring calibration curves", "calibration", calibration_png,
    "Inner-diameter change at mid-height against height reduction, one curve per run: one colour per friction "
    "value (factor m: purple, blues, greens, brown, grey; Coulomb mu: oranges, reds, pink), a marker per "
    "formulation. Dashed and thin, in the colour of its m: Avitzur's upper bound (Metal Forming: Processes and "
    "Analysis, 1968; the field u_r = v/(2h) (r - Rn^2/r), uniform through the thickness, the neutral radius Rn "
    "minimising the power at every height; perfectly plastic) on the run's own ring. Black dotted: the exact "
    "frictionless (m = 0) curve, homogeneous flow, sqrt(H0/H) - 1 (the bound's m = 0). The Coulomb runs have no "
    "reference curve: the bound assumes a constant friction factor. Runs of one formulation and friction that "
    "differ in other settings only (the remeshing variants) share colour and line: they should lie on each other.")
