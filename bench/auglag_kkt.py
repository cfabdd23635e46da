#!/usr/bin/env python3
"""The augmented Lagrangian against penalty and ipopt on the scenes of its
acceptance measurement: the Kuhn-Tucker residuals at every step, the load
against ipopt's, the augmentations per step and the wall times.

  /usr/bin/python3 bench/auglag_kkt.py build/rpfem OUT [--quick]

Runs each scene with auglag, penalty and ipopt into OUT/<scene>/<enf> (two
at a time) and prints one table. Loads are compared as `rpfem verify`
compares staircases (verification/curve_comparison.hpp): each auglag
point against the band of ipopt's loads within BAND mm of its stroke
(landing control lands each run at its own strokes, to the landing
prediction's error, and the load jumps there), relative to ipopt's load."""
import csv, json, os, subprocess, sys
from concurrent.futures import ThreadPoolExecutor

import numpy as np

SCENES = [("paper_test2_die", "punch.Fy", []),
          ("paper_test2_virtual_rigid", "ram.Fy", []),
          ("paper_test1_double_action", "top_punch.Fy", []),
          ("ring_compression", "top_die.Fy", ["--variant", "m0.1"])]


def history(d):
    rows = list(csv.reader(open(os.path.join(d, "history.csv"))))
    return {k: np.array([float(r[i]) for r in rows[1:]]) for i, k in enumerate(rows[0])}


# The initial (instantaneous) solve's load is a few hundred N against ~1e5 N
# later: its relative difference (5.5e-6 on the virtual rigid punch, 1 mN)
# is left out.
BAND, FROM = 0.002, 1e-9


def band_difference(sa, fa, sb, fb):
    """Largest distance of fa(s) to fb's band over [s - BAND, s + BAND],
    relative to |fb(s)|, over a's strokes from FROM to b's last."""
    worst = 0.0
    for s, f in zip(sa, fa):
        if s < FROM or s > sb[-1]:
            continue
        lo, hi = s - BAND, s + BAND
        inside = list(fb[(sb >= lo) & (sb <= hi)]) + [np.interp(lo, sb, fb), np.interp(hi, sb, fb)]
        ref = abs(np.interp(s, sb, fb))
        gap = max(min(inside) - f, f - max(inside), 0.0)
        if ref > 0:
            worst = max(worst, gap / ref)
    return worst


def main():
    rpfem, out = sys.argv[1], sys.argv[2]
    quick = ["--set", "run.mesh_factor=0.5"] if "--quick" in sys.argv else []
    src = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    jobs = []
    for scene, load, extra in SCENES:
        for enf in ("auglag", "penalty", "ipopt"):
            d = os.path.join(out, scene, enf)
            cmd = [rpfem, "run", os.path.join(src, "cases", scene + ".toml"), "--out", d, "--force", "-f", enf, "--quiet"] + extra + quick
            jobs.append((scene, enf, d, cmd))

    def run(job):
        return job, subprocess.run(job[3], capture_output=True, text=True).returncode
    with ThreadPoolExecutor(2) as pool:
        done = list(pool.map(run, jobs))
    print("| scene | max kkt_primal | max kkt_complementarity | load vs ipopt | augmentations per step (median, max) | "
          "wall auglag / penalty / ipopt (s) | auglag/penalty | ipopt/auglag |")
    print("|---|---|---|---|---|---|---|---|")
    for scene, load, extra in SCENES:
        d = {enf: os.path.join(out, scene, enf) for enf in ("auglag", "penalty", "ipopt")}
        rc = {j[1]: c for j, c in done if j[0] == scene}
        if any(rc[e] != 0 for e in rc):
            print(f"| {scene} | exit codes {rc} | | | | | | |")
            continue
        a, i = history(d["auglag"]), history(d["ipopt"])
        wall = {e: json.load(open(os.path.join(d[e], "summary.json")))["wall_time_s"] for e in d}
        diff = band_difference(a["stroke"], a[load], i["stroke"], i[load])
        aug = a["augmentations"]
        print(f"| {scene}{' ' + ' '.join(extra[1:]) if extra else ''} | {a['kkt_primal'].max():.2e} | "
              f"{a['kkt_complementarity'].max():.2e} | {diff:.2e} | {np.median(aug):.0f}, {aug.max():.0f} | "
              f"{wall['auglag']:.1f} / {wall['penalty']:.1f} / {wall['ipopt']:.1f} | "
              f"{wall['auglag'] / wall['penalty']:.2f} | {wall['ipopt'] / wall['auglag']:.2f} |")


if __name__ == "__main__":
    main()
