#!/usr/bin/env bash
# A study of 1,040 short runs (a 40 x 26 grid over solver.alpha and
# stepping.stroke_increment on the upsetting cylinder, a 2 x 2 mesh, one or
# two steps each) through `rpfem suite` on the local pool, end to end: the
# table (sweep.csv, a row per run, every run finished), its HDF5 twin read
# back in h5py (every column's 1,040 rows; the metadata JSON, beyond the
# 64 kB an attribute in its object's header can hold, whole), and the
# report: the study summarized (axes, aggregates, the grid figure), not a
# row per run. Prints its measured wall time: 17.6 s of CPU and 57.1 s
# wall at a load of about 10 on 2 cores (farm-bench median of 3; with a
# process per run 114.9 s and 243.6 s), 25.3 s wall at a load of about 8.
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib/check.bash"
mkdir -p "$tmp/cases/studies"
ln -s "$src/cases/upsetting_frictionless_axisym.toml" "$tmp/cases/"
alphas=$(/usr/bin/python3 -c 'print(", ".join("%.6g" % 10 ** (2 + 4 * i / 39) for i in range(40)))')
increments=$(/usr/bin/python3 -c 'print(", ".join("%.6g" % (0.025 + 0.001 * i) for i in range(26)))')
cat > "$tmp/cases/studies/big.toml" <<TOML
[study]
description = "upsetting, volumetric penalty by stroke increment, 1040 short runs"
case = "upsetting_frictionless_axisym"
load = "top_platen.Fy"
set = ["stepping.end_stroke=0.05", "bodies.billet.mesh.nx=2", "bodies.billet.mesh.ny=2", "stepping.output_every=10"]
[[study.axis]]
key = "solver.alpha"
values = [$alphas]
[[study.axis]]
key = "stepping.stroke_increment"
values = [$increments]
TOML
o=$tmp/o
t0=$(date +%s.%N)
"$rpfem" suite --cases "$tmp/cases" --out "$o" --jobs 2 --quiet --scene upsetting_frictionless_axisym \
  --no-variants --study big --set stepping.end_stroke=0.05 > "$tmp/log" 2>&1; rc=$?
t1=$(date +%s.%N)
cat "$tmp/log"
check "suite exits 0 ($rc)" '[ $rc -eq 0 ]'
t=$o/studies/big
check "sweep.csv: 1040 rows" '[ "$(($(wc -l < "$t/sweep.csv") - 1))" -eq 1040 ]'
check "every run finished" '[ "$(awk -F, "NR == 1 { for (i = 1; i <= NF; i++) if (\$i == \"finished\") c = i } NR > 1 && \$c == 1" "$t/sweep.csv" | wc -l)" -eq 1040 ]'
/usr/bin/python3 - "$t" <<'PY' || fail=1
import csv, json, sys, h5py
t = sys.argv[1]
rows = list(csv.DictReader(open(t + "/sweep.csv")))
with h5py.File(t + "/sweep.h5", "r") as f:
    g = f["table"]
    cols = g.attrs["columns"].decode().split(",")
    meta = g.attrs["metadata"].decode()
    ok = cols == list(rows[0].keys()) and all(g[c].shape == (1040,) for c in cols)
    ok &= [float(x) for x in g["solver.alpha"][:]] == [float(r["solver.alpha"]) for r in rows]
    ok &= [x.decode() for x in g["dir"][:]] == [r["dir"] for r in rows]
ok &= len(meta) > 65536 and json.loads(meta) == json.load(open(t + "/sweep.json"))
ok &= len(json.loads(meta)["runs"]) == 1040
print("%s  sweep.h5: %d columns of 1040 rows as sweep.csv; /table/metadata %d bytes, sweep.json's"
      % ("ok  " if ok else "FAIL", len(cols), len(meta)))
sys.exit(0 if ok else 1)
PY
check "report: the study summarized, its table named" \
  'grep -q "^1040 runs, 1040 finished, 0 did not\. .*studies/big/sweep.csv (1040 rows)" "$o/report.md" &&
   grep -q "^| alpha (axis, 40 values) | 1040 | 100 | " "$o/report.md" && grep -q "^| final load (kN) | 1040 | " "$o/report.md"'
check "report: no row per run" '[ "$(grep -c "^| [0-9]" "$o/report.md")" -lt 100 ] && [ "$(stat -c %s "$o/report.html")" -lt 200000 ]'
check "report: the grid figure" '[ -s "$o/report_files/study_big_grid.png" ] &&
  grep -q "(report_files/study_big_grid.png)" "$o/report.md"'
echo "measured: 1040 runs, table, HDF5 and report in $(awk "BEGIN { printf \"%.1f\", $t1 - $t0 }") s (--jobs 2);" \
  "report.html $(stat -c %s "$o/report.html") bytes; sweep.json $(stat -c %s "$t/sweep.json") bytes"
exit $fail
