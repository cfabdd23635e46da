#!/usr/bin/python3
"""A study file of NA x NI short runs for measuring rpfem's studies at
scale (docs/cluster.md, "Studies of thousands of runs"): the upsetting
cylinder (upsetting_frictionless_axisym) over solver.alpha (NA values,
log-spaced 1e2 to 1e6) and stepping.stroke_increment (NI values, 0.025 to
0.05 mm) to a stroke of 0.05 mm: one or two steps per run. --mesh N: an
N x N mesh (default: the case's 20 x 20).

  bench/large_study.py 25 20 > /tmp/s500.toml
  rpfem sweep /tmp/s500.toml --out /tmp/s500 --jobs 2
"""
import argparse

p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
p.add_argument("na", type=int)
p.add_argument("ni", type=int)
p.add_argument("--mesh", type=int, default=0)
a = p.parse_args()
alphas = ", ".join("%.6g" % 10 ** (2 + 4 * i / max(1, a.na - 1)) for i in range(a.na))
increments = ", ".join("%.6g" % (0.025 + 0.025 * i / max(1, a.ni - 1)) for i in range(a.ni))
sets = ["stepping.end_stroke=0.05"]
if a.mesh:
    sets += ["bodies.billet.mesh.nx=%d" % a.mesh, "bodies.billet.mesh.ny=%d" % a.mesh]
print('''[study]
description = "upsetting, volumetric penalty by stroke increment, %d runs"
case = "upsetting_frictionless_axisym"
load = "top_platen.Fy"
set = [%s]
[[study.axis]]
key = "solver.alpha"
values = [%s]
[[study.axis]]
key = "stepping.stroke_increment"
values = [%s]''' % (a.na * a.ni, ", ".join('"%s"' % s for s in sets), alphas, increments))
