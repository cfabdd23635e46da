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
before's, or whose touches and releases (events.csv) change the set of
rows in contact (one node landing as another leaves, the count unchanged);
its landing interval the strokes of the two steps; the stroke s
of run r's step j is compared when no landing interval of r or of the
reference reaches into the open interval from the lesser of s_(j-1) and
the reference's stroke before s to the greater of s_(j+1) and the
reference's stroke at or after s: a step of either run on each side (a run
with short landing steps is held to the other's step). A run that lands
the same ring more than a step of either run later than the reference
keeps the strokes between: a landing that late is a difference of the
solutions."""
import bisect
import csv
import functools
import os
import re

from results import interp, label

DIFFERENCE = 0.005  # relative difference between two formulations' loads, away from the landings
DROP = 0.05  # relative drop of one run's load in one step

RULE = ("Flags: a formulation's press load more than %.1f %% from the reference formulation's (the reference "
        "interpolated linearly) at a recorded stroke away from the landings, and a load that drops by more than "
        "%.0f %% in one step. Away from the landings: no step at which either run's rows in contact change (a node "
        "lands or leaves: history.csv's contact_nodes, events.csv's touches and releases) lies within a step of "
        "either run of the stroke. Two formulations land a ring of nodes a few 1e-4 mm apart, and interpolation "
        "turns the jump of the load there into a difference of the jump's height. A flag between runs that remeshed at "
        "different strokes before it says so: each remesh moves a load by its new mesh's discretization error "
        "(summary.json's load_jump)." % (100 * DIFFERENCE, 100 * DROP))


def loads(r):
    h = r["history"]
    return h["stroke"], [abs(v) / 1000 for v in h[r["load_col"]]]


# A contact event of events.csv: "touch node 420 on die top_die", "release
# node 17 from billet-punch" (and "release node 17 on ...").
EVENT = re.compile(r"^(touch|release) node (\d+) (?:on|from) (?:die )?(\S+)")


@functools.lru_cache(maxsize=None)
def changed_steps(folder):
    """The steps of a run whose set of rows in contact (node, interface)
    differs from the step before's, replaying events.csv's touches and
    releases of the kept attempts (a step may land a node and release
    another, the count unchanged); empty without the file. Read once per folder (a report
    compares each scene's reference with every run)."""
    path = os.path.join(folder, "events.csv")
    if not os.path.exists(path):
        return frozenset()
    state, by_step = {}, {}
    with open(path) as f:
        for row in csv.DictReader(f):
            # A failed attempt's events (attempt = failed) did not happen:
            # the retry started from the state before them.
            if not (row.get("step") or "").isdigit() or row.get("attempt") == "failed":
                continue
            m = EVENT.match(row.get("event") or "")
            if m:
                by_step.setdefault(int(row["step"]), []).append(((int(m.group(2)), m.group(3)), m.group(1) == "touch"))
    changed, before = set(), frozenset()
    for step in sorted(by_step):
        for key, touch in by_step[step]:
            state[key] = touch
        now = frozenset(k for k, on in state.items() if on)
        if now != before:
            changed.add(step)
        before = now
    return frozenset(changed)


def landing_intervals(r):
    """[(stroke before, stroke)] of every step of r at which a node landed
    or left: its number of rows in contact (history.csv's contact_nodes)
    differs from the step before's, or events.csv's touches and releases
    change the set of rows in contact (changed_steps)."""
    h = r["history"]
    s, n = h.get("stroke", []), h.get("contact_nodes")
    steps = h.get("step") or list(range(len(s)))
    results = r.get("results")
    events = changed_steps(results.folder) if results is not None else set()
    return [(s[k - 1], s[k]) for k in range(1, len(s))
            if (n and k < len(n) and n[k] != n[k - 1]) or int(steps[k]) in events]


def near_landing(lo, hi, intervals):
    """Whether a landing interval reaches into the open interval (lo, hi)
    (one that ends at lo, a landing step ending where r's step before
    starts, is behind it)."""
    return any(a < hi and b > lo for a, b in intervals)


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
        i = bisect.bisect_left(xs, s)  # ref's step [xs[i-1], xs[i]] holds s
        lo = min(ss[j - 1] if j > 0 else s, xs[i - 1] if 0 < i < len(xs) else s)
        hi = max(ss[j + 1] if j + 1 < len(ss) else s, xs[i] if i < len(xs) else s)
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


def remesh_strokes(r):
    """The strokes (mm) at which run r remeshed (summary.json's remeshes)."""
    return [x["stroke_mm"] for x in r.get("summary", {}).get("remeshes", []) if "stroke_mm" in x]


def meshes_differ(r, ref, stroke):
    """(r's, ref's) remesh strokes up to `stroke` where the two runs did not
    remesh at the same strokes (within 1e-9 mm) before it, else None: their
    loads there come from different meshes, and each remesh moves a load by
    its own discretization error (summary.json's load_jump)."""
    a = [x for x in remesh_strokes(r) if x <= stroke]
    b = [x for x in remesh_strokes(ref) if x <= stroke]
    if len(a) == len(b) and all(abs(x - y) <= 1e-9 for x, y in zip(a, b)):
        return None
    return a, b


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
                differ = meshes_differ(r, ref, over[-1][0])
                if differ:
                    text = lambda xs: ", ".join("%.3g" % x for x in xs) if xs else "never"
                    lines[-1] = lines[-1][:-1] + ("; the two runs' meshes differ there (remeshed at %s mm against %s "
                                                  "mm): a difference of the meshes as much as of the formulations."
                                                  % (text(differ[0]), text(differ[1])))
    for r in with_load:
        for s0, s1, f0, f1 in drops(r):
            lines.append("%s: the load drops %.1f %% in one step, from %.2f kN at %.3g mm to %.2f kN at %.3g mm."
                         % (label(r), 100 * (1 - f1 / f0), f0, s0, f1, s1))
    return lines
