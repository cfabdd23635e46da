#!/usr/bin/python3
"""A study of NA x NI short runs for measuring rpfem's studies at scale
(docs/sweeps.md, "Studies at scale"): the upsetting cylinder
(upsetting_frictionless_axisym) over solver.alpha (NA values, log-spaced
1e2 to 1e6) and stepping.stroke_increment (NI values, 0.025 to 0.05 mm) to
a stroke of 0.05 mm: one or two steps per run. --mesh N: an N x N mesh
(default: the case's 20 x 20).

Without --measure, prints the study file:

  bench/large_study.py 25 20 > /tmp/s500.toml
  rpfem sweep /tmp/s500.toml --out /tmp/s500 --jobs 2

With --measure DIR, runs it end to end as tests/cli/study_large.sh does
(`rpfem suite --study`, then the report by reports/make_report.py, timed
apart) in DIR (emptied) and prints what it measured: the suite's wall time
and peak memory (/usr/bin/time -v: the largest single process), the runs'
own time (each run's summary.json wall time, from its first solve to its
last file), rpfem's own overhead per run ((wall x workers - the runs' own
time) / runs: process or worker start, the case read, the files written,
the pool's and the table's work), the table's rows read back from sweep.h5
with h5py, the report's build time and size. Extra arguments after `--` go
to `rpfem suite` (e.g. `-- --engine slurm --runs-per-task 50`):

  bench/large_study.py 100 100 --mesh 2 --measure /tmp/s10k --rpfem build/rpfem
"""
import argparse
import csv
import json
import os
import re
import shutil
import subprocess
import sys
import time

p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
p.add_argument("na", type=int)
p.add_argument("ni", type=int)
p.add_argument("--mesh", type=int, default=0)
p.add_argument("--measure", metavar="DIR", help="run it end to end in DIR (emptied) and print the measurements")
p.add_argument("--rpfem", default="build/rpfem", help="the executable (--measure)")
p.add_argument("--jobs", type=int, default=2, help="local workers (--measure); also the overhead's worker count")
argv = sys.argv[1:]
extra = argv[argv.index("--") + 1:] if "--" in argv else []  # after --: more arguments of rpfem suite
a = p.parse_args(argv[:len(argv) - len(extra) - (1 if extra or "--" in argv else 0)])
alphas = ", ".join("%.6g" % 10 ** (2 + 4 * i / max(1, a.na - 1)) for i in range(a.na))
increments = ", ".join("%.6g" % (0.025 + 0.025 * i / max(1, a.ni - 1)) for i in range(a.ni))
sets = ["stepping.end_stroke=0.05"]
if a.mesh:
    sets += ["bodies.billet.mesh.nx=%d" % a.mesh, "bodies.billet.mesh.ny=%d" % a.mesh]
study = '''[study]
description = "upsetting, volumetric penalty by stroke increment, %d runs"
case = "upsetting_frictionless_axisym"
load = "top_platen.Fy"
set = [%s]
[[study.axis]]
key = "solver.alpha"
values = [%s]
[[study.axis]]
key = "stepping.stroke_increment"
values = [%s]''' % (a.na * a.ni, ", ".join('"%s"' % s for s in sets), alphas, increments)
if not a.measure:
    print(study)
    sys.exit(0)

src = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
rpfem = os.path.abspath(a.rpfem)
shutil.rmtree(a.measure, ignore_errors=True)
cases = os.path.join(a.measure, "cases")
os.makedirs(os.path.join(cases, "studies"))
os.symlink(os.path.join(src, "cases", "upsetting_frictionless_axisym.toml"),
           os.path.join(cases, "upsetting_frictionless_axisym.toml"))
open(os.path.join(cases, "studies", "big.toml"), "w").write(study + "\n")
out = os.path.join(a.measure, "out")
cmd = ["/usr/bin/time", "-v", rpfem, "suite", "--cases", cases, "--out", out, "--jobs", str(a.jobs), "--quiet",
       "--scene", "upsetting_frictionless_axisym", "--no-variants", "--study", "big", "--no-report",
       "--set", "stepping.end_stroke=0.05"] + extra
t0 = time.monotonic()
r = subprocess.run(cmd, capture_output=True, text=True)
wall = time.monotonic() - t0
peak = re.search(r"Maximum resident set size \(kbytes\): (\d+)", r.stderr)
peak_kb = int(peak.group(1)) if peak else -1
t1 = time.monotonic()
rep = subprocess.run(["/usr/bin/python3", os.path.join(src, "reports", "make_report.py"), out],
                     capture_output=True, text=True)
report_s = time.monotonic() - t1
table = os.path.join(out, "studies", "big")
rows = list(csv.DictReader(open(os.path.join(table, "sweep.csv"))))
own = 0.0
for row in rows:
    s = json.load(open(os.path.join(table, row["dir"], "summary.json")))
    own += s.get("wall_time_s", 0.0)
import h5py  # noqa: E402 (only --measure needs it)
with h5py.File(os.path.join(table, "sweep.h5"), "r") as f:
    g = f["table"]
    h5_rows = min(g[c].shape[0] for c in g.attrs["columns"].decode().split(","))
report_files = os.path.join(out, "report_files")
report_bytes = os.path.getsize(os.path.join(out, "report.html")) + sum(
    os.path.getsize(os.path.join(report_files, n)) for n in os.listdir(report_files))
n = len(rows)
print("suite exit %d, %d runs (%d finished), wall %.1f s, peak %.1f MB" %
      (r.returncode, n, sum(row["finished"] == "1" for row in rows), wall, peak_kb / 1024))
print("runs' own time %.1f s (%.4f s a run); rpfem's overhead %.4f s a run (wall x %d workers - own, over runs)" %
      (own, own / n, (wall * a.jobs - own) / n, a.jobs))
print("sweep.h5 /table: %d rows read back (h5py); sweep.csv %d bytes, sweep.h5 %d bytes, sweep.json %d bytes" %
      (h5_rows, os.path.getsize(os.path.join(table, "sweep.csv")), os.path.getsize(os.path.join(table, "sweep.h5")),
       os.path.getsize(os.path.join(table, "sweep.json"))))
print("report exit %d in %.1f s; report.html and report_files %d bytes" % (rep.returncode, report_s, report_bytes))
if r.returncode != 0 or rep.returncode != 0:
    sys.stderr.write(r.stdout + r.stderr + rep.stdout + rep.stderr)
sys.exit(1 if r.returncode != 0 or rep.returncode != 0 or h5_rows != n else 0)
