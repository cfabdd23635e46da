"""Flags on the press load curves (reports/make_report.py): per scene,
where a formulation's load differs from the reference formulation's by
more than DIFFERENCE away from the landings, and where any run's load
drops by more than DROP from one step to the next.

Landings. A press load is smooth between the steps where a node lands on
(or leaves) a die or another body, and jumps at them: the contact zone
grows by a ring of nodes at a time (a staircase). Two formulations land the
same ring a few 1e-4 mm apart (each at its own velocities, landing control
ending the step at its own landing), and the reference interpolated across
its jump, or a run compared just past its own landing with a reference
just before its own, differs by the height of the step (Test II's die:
ipopt against direct 1.2 % at 2.205 mm, 2e-6 mm from the landings) though
the two curves agree to 1e-6 on either side. So a stroke is compared only
away from the landings: a run's landing step is a step whose number of
rows in contact (history.csv's contact_nodes) differs from the step
before's, its landing interval the strokes of the two steps; the stroke of
run r's step j is compared when no landing interval of r or of the
reference reaches into [s_(j-1), s_(j+1)], r's strokes before and after
it. A run that lands the same ring more than a step later than the
reference keeps the strokes between: a landing that late is a difference
of the solutions."""
from results import interp, label

DIFFERENCE = 0.005  # relative difference between two formulations' loads, away from the landings
DROP = 0.05  # relative drop of one run's load in one step

RULE = ("Flags: a formulation's press load more than %.1f %% from the reference formulation's (the reference "
        "interpolated linearly) at a recorded stroke away from the landings, and a load that drops by more than "
        "%.0f %% in one step. Away from the landings: no step of either run at which its number of rows in "
        "contact changes (a node lands or leaves; history.csv's contact_nodes) lies within a step of the "
        "stroke: a ring of nodes landed a few 1e-4 mm apart by two formulations makes a jump of the load that "
        "interpolation turns into a difference of the jump's height." % (100 * DIFFERENCE, 100 * DROP))


def loads(r):
    h = r["history"]
    return h["stroke"], [abs(v) / 1000 for v in h[r["load_col"]]]


def landing_intervals(r):
    """[(stroke before, stroke)] of every step of r whose number of rows in
    contact differs from the step before's: a node landed or left within
    it. [] when the history has no contact_nodes column."""
    s, n = r["history"].get("stroke", []), r["history"].get("contact_nodes")
    if not n:
        return []
    return [(s[k - 1], s[k]) for k in range(1, min(len(s), len(n))) if n[k] != n[k - 1]]


def near_landing(lo, hi, intervals):
    """Whether a landing interval reaches into [lo, hi]."""
    return any(a <= hi and b >= lo for a, b in intervals)


def compared(r, ref):
    """r's press load against ref's at r's recorded strokes within ref's
    range, ref interpolated linearly: [(stroke, r's load, ref's load (kN),
    relative difference, away from the landings)], where ref's load is
    positive."""
    if not (r["load_col"] and ref["load_col"] and ref["history"].get("stroke")):
        return []
    xs, ys = loads(ref)
    ss, fs = loads(r)
    lands = landing_intervals(r) + landing_intervals(ref)
    out = []
    for j, (s, f) in enumerate(zip(ss, fs)):
        if s != s or s > xs[-1] + 1e-12:
            continue
        g = interp(s, xs, ys)
        if not g > 0:
            continue
        lo = ss[j - 1] if j > 0 else s
        hi = ss[j + 1] if j + 1 < len(ss) else s
        out.append((s, f, g, f / g - 1, not near_landing(lo, hi, lands)))
    return out


def load_differences(r, ref):
    """|relative differences| of r's load from ref's at r's strokes: the
    largest, the largest and the median away from the landings, and the
    number of strokes away from the landings and of all compared."""
    nan = float("nan")
    c = compared(r, ref)
    away = sorted(abs(d) for _, _, _, d, ok in c if ok)
    return (max((abs(d) for _, _, _, d, _ in c), default=nan), away[-1] if away else nan,
            away[len(away) // 2] if away else nan, len(away), len(c))


def differences(r, ref):
    """The strokes away from the landings where r's load is more than
    DIFFERENCE from ref's: [(stroke, r's load, ref's load, relative
    difference)]."""
    return [(s, f, g, d) for s, f, g, d, ok in compared(r, ref) if ok and abs(d) > DIFFERENCE]


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
                away = sum(1 for c in compared(r, ref) if c[4])
                worst = max(over, key=lambda o: abs(o[3]))
                signs = {o[3] > 0 for o in over}
                lines.append("%s differs from %s by more than %.1f %% away from the landings at %d of its %d strokes "
                             "there, %.3g to %.3g mm, %s; largest %+.2f %% at %.3g mm (%.2f kN against %.2f kN)."
                             % (label(r), label(ref), 100 * DIFFERENCE, len(over), away, over[0][0], over[-1][0],
                                "above" if signs == {True} else "below" if signs == {False} else "above and below",
                                100 * worst[3], worst[0], worst[1], worst[2]))
    for r in with_load:
        for s0, s1, f0, f1 in drops(r):
            lines.append("%s: the load drops %.1f %% in one step, from %.2f kN at %.3g mm to %.2f kN at %.3g mm."
                         % (label(r), 100 * (1 - f1 / f0), f0, s0, f1, s1))
    return lines
