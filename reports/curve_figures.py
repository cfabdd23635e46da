"""The curve figures of the suite report (reports/make_report.py), from each
run's history.csv: the press load against stroke for every formulation and
variant on one plot (kN; paper Fig. 11); per step against stroke the
penetration, iterations, Newton's force residual and the force imbalance
(die loads against each other, and penalty's contact pairs between bodies);
and for rings the calibration curves (inner-diameter change against height
reduction, one per friction value)."""
import numpy as np

from plotting import missing_panel, plt, png_bytes
from reference_curves import load_references, ring_frictionless
from results import initial_height, label


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
    top = max(max(100 * s / H0 for s in r["history"]["stroke"]) for r in curves if (H0 := initial_height(out, r)))
    x = list(np.linspace(0, top, 50))
    ax.plot(x, ring_frictionless(x), color="k", linewidth=2.5, linestyle=":", zorder=1,
            label="m = 0, exact: sqrt(H0/H) - 1")
    ax.axhline(0, color="k", linewidth=0.5)
    ax.set_xlabel("height reduction (%)")
    ax.set_ylabel("inner diameter change at mid-height (%)")
    ax.set_title(title + ": calibration curves")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    return png_bytes(fig)


def load_png(runs, title):
    """Press load against stroke, every run, with the scene's closed-form
    reference (reference_curves.py) where there is one."""
    fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=110)
    for strokes, loads, text in load_references(title, runs):
        ax.plot(strokes, loads, color="k", linestyle="--", linewidth=1.5, label=text, zorder=5)
    marked = False
    for r in runs:
        if r["load_col"]:
            stroke = r["history"]["stroke"]
            load = [abs(v) / 1000 for v in r["history"][r["load_col"]]]
            line, = ax.plot(stroke, load, label=label(r) + " (" + r["load_col"].rsplit(".", 1)[0] + ")")
            # Each remesh at its stroke, on the curve (summary.json's remeshes).
            at = [m["stroke_mm"] for m in r["summary"].get("remeshes", [])]
            if at:
                ax.plot(at, np.interp(at, stroke, load), linestyle="none", marker="x",
                        color=line.get_color(), markersize=6, label=None if marked else "remesh")
                marked = True
    plane = any(r["summary"].get("parameters", {}).get("run", {}).get("geometry", "").startswith("plane")
                for r in runs)
    ax.set_xlabel("stroke (mm)")
    ax.set_ylabel("load (kN/mm, per unit thickness)" if plane else "load (kN)")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    if ax.lines:
        ax.legend(fontsize=8)
    fig.tight_layout()
    return png_bytes(fig)


# The report's entries (see make_report.FIGURES): alt text, file tag, drawing, caption.
LOAD_FIGURE = (
    "load against stroke", "load", lambda out, rs, sc: load_png(rs, sc),
    "Press load (kN; plane strain: kN/mm of thickness) against stroke (mm), every formulation and variant (paper "
    "Fig. 11); an x marks each remesh of a run that remeshes. Dashed black, where the scene has one: the closed "
    "form, for frictionless upsetting the exact homogeneous load F = sigma(ln H0/H) A0 H0/H (plane strain: "
    "2/sqrt3 sigma w0 H0/H; verification/analytic.cpp), for the plane-strain indentation Prandtl's flat-punch "
    "load 2k(1 + pi/2) b on a half-space at the initial flow stress (the block is finite and the punch filleted: "
    "a guide, not the exact answer).")
STEPS_FIGURE = (
    "penetration, iterations and force imbalance per step", "steps", lambda out, rs, sc: steps_png(rs, sc),
    "Per step against stroke: largest penetration over the element size, iterations, Newton's relative force "
    "residual at convergence (Ipopt: KKT stationarity), and the force imbalance: |sum of the dies' Fy| / "
    "max |die Fy| (global equilibrium of the press, scenes with two or more loaded dies) and penalty's "
    "contact-pair imbalance between deformable bodies. Log scales show zeros at 1e-16.")
CALIBRATION_FIGURE = (
    "ring calibration curves", "calibration", calibration_png,
    "Inner-diameter change at mid-height against height reduction, one curve per run; black dotted: the exact "
    "frictionless (m = 0) curve, homogeneous flow, sqrt(H0/H) - 1.")
