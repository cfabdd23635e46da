"""The field figures of the suite report (reports/make_report.py), from each
run's result.h5: the deformed meshes coloured by the effective strain rate
at the recorded steps nearest to 25, 50, 75 and 100 % of the stroke, a row
per formulation (paper Fig. 6, 9), and the velocity magnitude with vectors
near the contact at the end, formulations side by side (paper Fig. 7, 10).
The formulations shown are the base runs, the reference first, at most
MAX_ROWS; a run without a step near a column's stroke gets a note there."""
import numpy as np
from matplotlib.cm import ScalarMappable
from matplotlib.collections import PolyCollection
from matplotlib.colors import Normalize

from plotting import missing_panel, plt, png_bytes
from results import REFERENCE_ORDER, initial_height, label, read_step, recorded_steps

FRACTIONS = (0.25, 0.5, 0.75, 1.0)  # of the final stroke: the columns of the mesh grid
MAX_ROWS = 4  # formulations shown in the field figures


def shown_runs(rs):
    """The runs the field figures show: the base runs (every run if none
    is), the reference order first, at most MAX_ROWS."""
    base = [r for r in rs if not r["variant"]] or rs
    rank = {name: i for i, name in enumerate(REFERENCE_ORDER)}
    return sorted(base, key=lambda r: rank.get(r["formulation"], len(rank)))[:MAX_ROWS]


def nearest(steps, stroke):
    return min(steps, key=lambda s: abs(s[0] - stroke))


def columns_of(steps):
    """steps' recorded strokes nearest to FRACTIONS of its final stroke (each
    once; the start only if nothing else was recorded)."""
    moved = [s for s in steps if s[0] > 0] or steps
    cols = []
    for fraction in FRACTIONS:
        s = nearest(moved, fraction * steps[-1][0])[0]
        if s not in cols:
            cols.append(s)
    return cols


def column_strokes(recorded):
    """The strokes the field figures show: those of columns_of one of the
    runs that got to the end, the one whose columns the other runs'
    recorded strokes match best (recorded strokes differ where steps were
    cut)."""
    final = max((steps[-1][0] for steps in recorded if steps), default=0.0)
    if not final > 0:
        return []
    candidates = [columns_of(steps) for steps in recorded if steps and steps[-1][0] >= 0.99 * final]
    return min(candidates, key=lambda cols: sum(abs(nearest(steps, c)[0] - c)
                                                for steps in recorded if steps for c in cols))


def match_step(out, r, steps, stroke, final):
    """Run r's recorded step nearest to `stroke`, read; None if it has none
    within a tenth of the final stroke (a run that stopped early)."""
    if not steps:
        return None
    s, key = nearest(steps, stroke)
    return read_step(out, r, key, s) if abs(s - stroke) <= 0.1 * final else None


def field_cells(out, rs):
    """The field figures' data: shown runs, column strokes, and per run and
    column the matched step (None where missing)."""
    runs = shown_runs(rs)
    recorded = [recorded_steps(out, r) for r in runs]
    cols = column_strokes(recorded) if runs else []
    cells = [[match_step(out, r, steps, s, cols[-1]) for s in cols] for r, steps in zip(runs, recorded)]
    return runs, cols, cells


def stroke_text(stroke, height):
    """The stroke, and the workpiece's height reduction (stroke / initial
    height) when there is one workpiece."""
    return "stroke %.2f mm" % stroke + (", reduction %.1f %%" % (100 * stroke / height) if height else "")


def axis_names(r):
    """The mesh axes' names: r and z in axisymmetry, x and y in plane strain."""
    geometry = r["summary"].get("parameters", {}).get("run", {}).get("geometry", "")
    return ("r (mm)", "z (mm)") if geometry.startswith("axisym") else ("x (mm)", "y (mm)")


def finite_max(arrays):
    vals = np.concatenate([np.ravel(a) for a in arrays]) if arrays else np.zeros(0)
    vals = vals[np.isfinite(vals)]
    return float(vals.max()) if vals.size and vals.max() > 0 else 1.0


def bounds(cells, pad=None):
    """Lower and upper corner (mm) of a box around every cell's mesh, pad
    (mm; default 3 % of the larger side) away from it."""
    x = np.concatenate([c["x"] for c in cells])
    lo, hi = x.min(axis=0), x.max(axis=0)
    pad = 0.03 * (hi - lo).max() if pad is None else pad
    return lo - pad, hi + pad


def field_axes(nrows, ncols, lo, hi, w, names):
    """Figure and a grid of panels, equal aspect, shared limits lo to hi
    (mm), panels w inches wide, axes (names: horizontal, vertical) on the
    outer panels."""
    ratio = (hi[1] - lo[1]) / (hi[0] - lo[0])
    w = min(w, 5.0 / ratio)  # tall meshes: narrower panels, at most 5 inches high
    h = max(w * ratio, 1.6)
    fig, axes = plt.subplots(nrows, ncols, figsize=(max(w * ncols + 2.0, 6.4), h * nrows + 1.4), dpi=110,
                             squeeze=False, sharex=True, sharey=True, layout="constrained")
    for ax in axes.ravel():
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_aspect("equal")
    for ax in axes[-1]:
        ax.set_xlabel(names[0])
    for ax in axes[:, 0]:
        ax.set_ylabel(names[1])
    return fig, axes


def no_step_panel(ax, r, stroke, height):
    missing_panel(ax, "%s:\nno recorded step\nnear %s" % (label(r), stroke_text(stroke, height)))


def strain_rate_png(out, rs, title):
    """Deformed meshes coloured by the effective strain rate (1/s): a row
    per shown formulation, a column per chosen stroke, one colour scale."""
    runs, cols, cells = field_cells(out, rs)
    present = [c for row in cells for c in row if c]
    if not present:
        return None
    height = initial_height(out, runs[0])
    vmax = finite_max([c["rate"] for c in present])
    fig, axes = field_axes(len(runs), len(cols), *bounds(present), 3.0, axis_names(runs[0]))
    for r, row, ax_row in zip(runs, cells, axes):
        for s, c, ax in zip(cols, row, ax_row):
            if c is None:
                no_step_panel(ax, r, s, height)
                continue
            pc = PolyCollection(c["x"][c["conn"]], array=c["rate"], cmap="viridis", edgecolors="k", linewidths=0.1)
            pc.set_clim(0, vmax)
            ax.add_collection(pc)
            ax.set_title("%s, %s" % (label(r), stroke_text(c["stroke"], height)), fontsize=9)
    fig.colorbar(ScalarMappable(Normalize(0, vmax), "viridis"), ax=axes, label="effective strain rate (1/s)",
                 shrink=0.8)
    fig.suptitle("%s: effective strain rate at the recorded strokes nearest to 25, 50, 75, 100 %% of the final "
                 "stroke\n(%s)" % (title, stroke_text(cols[-1], height).replace("stroke", "final stroke", 1)
                                  .replace("reduction", "height reduction", 1)), fontsize=10)
    return png_bytes(fig)


def element_size(c):
    """Median edge length of the deformed mesh (mm)."""
    q = c["x"][c["conn"]]
    return float(np.median(np.linalg.norm(q - np.roll(q, 1, axis=1), axis=2)))


def contact_nodes(c):
    """Nodes near the contact: those with contact pressure and those within
    two element sizes of them; without contact data, the top 20 % of the
    mesh."""
    x, p = c["x"], c["p"]
    touching = np.flatnonzero(np.nan_to_num(p) != 0) if p is not None else []
    if len(touching) == 0:
        y = x[:, 1]
        return np.flatnonzero(y >= y.max() - 0.2 * (y.max() - y.min()))
    d = np.full(len(x), np.inf)
    for n in touching:
        d = np.minimum(d, np.linalg.norm(x - x[n], axis=1))
    return np.flatnonzero(d <= 2 * element_size(c))


def velocity_panel(ax, c, vmax, arrow):
    """Nodal velocity magnitude (Gouraud-shaded on the quads split in two
    triangles), the mesh, and the velocity vectors near the contact."""
    x, conn = c["x"], c["conn"]
    tris = np.vstack([conn[:, [0, 1, 2]], conn[:, [0, 2, 3]]])
    speed = np.linalg.norm(c["v"], axis=1)
    ax.tripcolor(x[:, 0], x[:, 1], tris, speed, shading="gouraud", cmap="YlOrRd", vmin=0, vmax=vmax)
    ax.add_collection(PolyCollection(x[conn], facecolors="none", edgecolors="0.4", linewidths=0.15))
    n = contact_nodes(c)
    return ax.quiver(x[n, 0], x[n, 1], c["v"][n, 0], c["v"][n, 1], angles="xy", scale_units="xy",
                     scale=vmax / arrow, units="inches", width=0.015, color="k")


def velocity_axes(n, cells, arrow, names):
    """Figure and n panels for the velocity: side by side, one above the
    other for flat parts; limits with room for the arrows."""
    lo, hi = bounds(cells, arrow)
    wide = hi[1] - lo[1] < 0.5 * (hi[0] - lo[0])
    return field_axes(n, 1, lo, hi, 8.0, names) if wide else field_axes(1, n, lo, hi, 4.0, names)


def velocity_png(out, rs, title):
    """Velocity magnitude (mm/s) with vectors near the contact at the last
    column's stroke, formulations side by side (one above the other for
    flat parts), one colour scale."""
    runs, cols, cells = field_cells(out, rs)
    last = [row[-1] if row else None for row in cells]
    present = [c for c in last if c]
    if not present:
        return None
    height = initial_height(out, runs[0])
    vmax = finite_max([np.linalg.norm(c["v"], axis=1) for c in present])
    arrow = 1.5 * min(element_size(c) for c in present)
    fig, axes = velocity_axes(len(runs), present, arrow, axis_names(runs[0]))
    for r, c, ax in zip(runs, last, axes.ravel()):
        if c is None:
            no_step_panel(ax, r, cols[-1], height)
            continue
        velocity_panel(ax, c, vmax, arrow)
        ax.set_title("%s, %s" % (label(r), stroke_text(c["stroke"], height)), fontsize=9)
    fig.colorbar(ScalarMappable(Normalize(0, vmax), "YlOrRd"), ax=axes, label="velocity magnitude (mm/s)",
                 shrink=0.8)
    fig.suptitle("%s: velocity, vectors at the nodes near the contact\n(arrow length %.2g mm for %.2g mm/s)"
                 % (title, arrow, vmax), fontsize=10)
    return png_bytes(fig)


# The report's entries (see make_report.FIGURES): alt text, file tag, drawing, caption.
MESH_FIGURE = (
    "deformed meshes coloured by effective strain rate", "mesh", strain_rate_png,
    "Deformed meshes coloured by the effective strain rate (1/s), one colour scale: a row per formulation (base "
    "runs, reference first, at most %d), a column per recorded step nearest to 25, 50, 75 and 100 %% of the final "
    "stroke (paper Fig. 6 and 9). Panel titles give each run's own stroke and, for one workpiece, the height "
    "reduction (stroke over the workpiece's initial height). Axes r, z in axisymmetric scenes, x, y in plane "
    "strain." % MAX_ROWS)
VELOCITY_FIGURE = (
    "velocity magnitude with vectors near the contact", "velocity", velocity_png,
    "Nodal velocity magnitude (mm/s) at the last column's stroke, formulations side by side, one colour scale; "
    "arrows at the nodes with contact pressure and those within two element sizes of them (without contact "
    "data: the top 20 % of the mesh), one arrow scale (in the title) (paper Fig. 7 and 10).")
