"""Flags on the press load curves (reports/make_report.py): per scene,
where a formulation's load differs from the reference formulation's by
more than DIFFERENCE (the reference interpolated linearly at the other's
strokes), and where any run's load drops by more than DROP from one step
to the next."""
from results import interp, label

DIFFERENCE = 0.05  # relative difference between two formulations' loads
DROP = 0.05  # relative drop of one run's load in one step

RULE = ("Flags: a formulation's press load more than %.0f %% from the reference formulation's at a recorded stroke "
        "(the reference interpolated linearly), and a load that drops by more than %.0f %% in one step."
        % (100 * DIFFERENCE, 100 * DROP))


def loads(r):
    h = r["history"]
    return h["stroke"], [abs(v) / 1000 for v in h[r["load_col"]]]


def differences(r, ref):
    """The strokes where r's load is more than DIFFERENCE from ref's:
    [(stroke, r's load, ref's load, relative difference)]."""
    xs, ys = loads(ref)
    over = []
    for s, f in zip(*loads(r)):
        if s != s or s > xs[-1] + 1e-12:
            continue
        g = interp(s, xs, ys)
        if g > 0 and abs(f / g - 1) > DIFFERENCE:
            over.append((s, f, g, f / g - 1))
    return over


def drops(r):
    """The steps where r's load drops by more than DROP: [(stroke before,
    stroke, load before, load)]."""
    s, f = loads(r)
    return [(s[i - 1], s[i], f[i - 1], f[i]) for i in range(1, len(f)) if f[i - 1] > 0 and f[i] < (1 - DROP) * f[i - 1]]


def scene_flags(rs, ref):
    """Lines, one per flag, for a scene's runs rs and its reference run."""
    lines = []
    with_load = [r for r in rs if r["load_col"] and r["history"].get("stroke")]
    if ref is not None:
        for r in with_load:
            if r is ref or r["variant"]:
                continue
            over = differences(r, ref)
            if over:
                worst = max(over, key=lambda o: abs(o[3]))
                lines.append("%s differs from %s by more than %.0f %% at %d of its strokes, %.3g to %.3g mm; largest "
                             "%+.1f %% at %.3g mm (%.2f kN against %.2f kN)."
                             % (label(r), label(ref), 100 * DIFFERENCE, len(over), over[0][0], over[-1][0],
                                100 * worst[3], worst[0], worst[1], worst[2]))
    for r in with_load:
        for s0, s1, f0, f1 in drops(r):
            lines.append("%s: the load drops %.1f %% in one step, from %.2f kN at %.3g mm to %.2f kN at %.3g mm."
                         % (label(r), 100 * (1 - f1 / f0), f0, s0, f1, s1))
    return lines
