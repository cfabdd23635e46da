#!/usr/bin/env bash
# `rpfem sweep` end to end on a small study (flat-die upsetting, penalty at
# three betas against ipopt, two meshes for Richardson's refusal): the table
# in CSV and HDF5 with a row per run and the measured columns, the usable
# window in sweep.json, a regularization axis read against a reference run;
# and a bad study file gives exit 2 naming the file and the key.
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib/check.bash"
cat > "$tmp/study.toml" <<TOML
[study]
description = "upsetting, penalty beta"
case = "upsetting_dies_frictionless_axisym"
formulation = "penalty"
load = "top_die.Fy"
set = ["stepping.end_stroke=0.5", "run.mesh_factor=0.25"]
[[study.axis]]
key = "formulations.penalty.beta_factor"
values = [1e-4, 1.0, 1e4]
quick = [1e-4, 1.0]
[study.reference]
kind = "formulation"
formulation = "ipopt"
[study.window]
axis = "formulations.penalty.beta_factor"
max_penetration_rel = 1e-3
TOML
"$rpfem" sweep "$tmp/study.toml" --out "$tmp/out" --jobs 2 --quiet; rc=$?
check "sweep exits 0" '[ $rc -eq 0 ]'
csv=$tmp/out/sweep.csv
check "three rows and a header" '[ "$(wc -l < "$csv")" -eq 4 ]'
check "measured columns" 'head -1 "$csv" | grep -q "formulations.penalty.beta_factor,exit_code,finished,.*penetration_rel,load_error,.*rcond,wall_time_s"'
/usr/bin/python3 - "$tmp/out" <<'PY' || fail=1
import csv, json, sys, h5py
d = sys.argv[1]
rows = list(csv.DictReader(open(d + "/sweep.csv")))
pen = [float(r["penetration_rel"]) for r in rows]
err = [float(r["load_error"]) for r in rows]
ok = all(r["finished"] == "1" for r in rows)
# Penetration and load error fall with beta (the penalty's compliance).
ok &= pen[0] > 1e2 * pen[1] > 1e4 * pen[2] > 0 and err[0] > err[1] > 0
ok &= all(float(r["rcond"]) > 0 for r in rows) and float(rows[2]["rcond"]) < float(rows[0]["rcond"])
ok &= all(float(r["iterations_discarded"]) >= 0 for r in rows)  # read from each run's summary.json
with h5py.File(d + "/sweep.h5") as f:
    ok &= list(f["table/finished"][:]) == [1, 1, 1]
    ok &= f["table"].attrs["columns"].decode().startswith("run,dir,formulation,")
w = json.load(open(d + "/sweep.json"))["window"]
ok &= w["usable"] == [1.0, 1e4] and abs(w["decades"] - 4) < 1e-12
print("ok   table values (penetration %s, load error %s, window %s)" % (pen, err, w["usable"]) if ok else "FAIL table values")
sys.exit(0 if ok else 1)
PY
# The pool starts the costliest run first (planned steps times elements to
# the 1.5): on one worker the finer mesh, listed last, finishes first.
cat > "$tmp/order.toml" <<TOML
[study]
description = "the pool's order"
case = "upsetting_dies_frictionless_axisym"
formulation = "penalty"
load = "top_die.Fy"
set = ["stepping.end_stroke=0.2"]
[[study.axis]]
key = "run.mesh_factor"
values = [0.25, 0.5]
TOML
"$rpfem" sweep "$tmp/order.toml" --out "$tmp/order" --jobs 1 > "$tmp/order.log" 2>&1
first=$(grep -m1 '^\[1/2\]' "$tmp/order.log")
check "costliest first ($first)" 'printf "%s" "$first" | grep -q "mesh_factor=0.5:"'
"$rpfem" sweep "$tmp/study.toml" --out "$tmp/quick" --quick --quiet
check "--quick takes the quick values" '[ "$(wc -l < "$tmp/quick/sweep.csv")" -eq 3 ]'
sed 's/^kind = "formulation"/kind = "formulations"/' "$tmp/study.toml" > "$tmp/bad.toml"
err=$("$rpfem" sweep "$tmp/bad.toml" --out "$tmp/bad" 2>&1); rc=$?
check "bad kind: exit 2 naming file and key ($err)" '[ $rc -eq 2 ] && printf "%s" "$err" | grep -q "bad.toml" && printf "%s" "$err" | grep -q "study.reference.kind"'
sed 's/^values = \[1e-4, 1.0, 1e4\]/values = [1e-4, 1.0, 1e4]\nvalue = 3/' "$tmp/study.toml" > "$tmp/unknown.toml"
err=$("$rpfem" sweep "$tmp/unknown.toml" --out "$tmp/bad2" 2>&1); rc=$?
check "unknown key: exit 2 ($err)" '[ $rc -eq 2 ] && printf "%s" "$err" | grep -q "study.axis"'
sed -e 's/^kind = "formulation"/kind = "richardson"\naxis = "formulations.penalty.beta_factor"\nmeasure = "mean"/' \
  -e 's/^formulation = "ipopt"/formulation = "direct"/' "$tmp/study.toml" > "$tmp/common.toml"
err=$("$rpfem" sweep "$tmp/common.toml" --out "$tmp/bad3" 2>&1); rc=$?
check "a Richardson reference formulation off the formulation axis: exit 2 ($err)" \
  '[ $rc -eq 2 ] && printf "%s" "$err" | grep -q "study.reference.formulation"'
# Checked before any run: a load column the scene does not have, an axis key the case does not know.
sed 's/^load = .*/load = "nosuch.Fy"/' "$tmp/study.toml" > "$tmp/load.toml"
err=$("$rpfem" sweep "$tmp/load.toml" --out "$tmp/bad4" 2>&1); rc=$?
check "a load column the scene lacks: exit 2 before any run ($err)" \
  '[ $rc -eq 2 ] && printf "%s" "$err" | grep -q "study.load" && [ ! -d "$tmp/bad4/runs" ]'
sed 's/formulations.penalty.beta_factor/formulations.penalty.beta_factr/g' "$tmp/study.toml" > "$tmp/axis.toml"
err=$("$rpfem" sweep "$tmp/axis.toml" --out "$tmp/bad5" 2>&1); rc=$?
check "an axis key the case does not know: exit 2 before any run ($err)" \
  '[ $rc -eq 2 ] && printf "%s" "$err" | grep -q "beta_factr" && [ ! -d "$tmp/bad5/runs" ]'
# A monitor the case lacks, a regularization axis without a reference run or
# off the axes, a default off the axis's values: exit 2 naming the key.
printf 'monitor = "nosuch"\n' > "$tmp/monitor_line"
sed "/^load = /r $tmp/monitor_line" "$tmp/study.toml" > "$tmp/monitor.toml"
err=$("$rpfem" sweep "$tmp/monitor.toml" --out "$tmp/bad6" 2>&1); rc=$?
check "a monitor the case lacks: exit 2 before any run ($err)" \
  '[ $rc -eq 2 ] && printf "%s" "$err" | grep -q "study.monitor" && [ ! -d "$tmp/bad6/runs" ]'
printf '[study.regularization]\naxis = "formulations.penalty.beta_factor"\ndefault = 1.0\n' > "$tmp/reg_table"
cat "$tmp/study.toml" "$tmp/reg_table" > "$tmp/reg.toml"
"$rpfem" sweep "$tmp/reg.toml" --out "$tmp/reg" --quick --quiet; rc=$?
check "a regularization axis against a reference run: read ($rc)" \
  '[ $rc -eq 0 ] && grep -q "\"regularization\"" "$tmp/reg/sweep.json"'
sed 's/^default = 1.0/default = 3.0/' "$tmp/reg.toml" > "$tmp/reg_default.toml"
err=$("$rpfem" sweep "$tmp/reg_default.toml" --out "$tmp/bad7" 2>&1); rc=$?
check "a regularization default off the axis's values: exit 2 ($err)" \
  '[ $rc -eq 2 ] && printf "%s" "$err" | grep -q "study.regularization.default"'
sed '/^\[study.regularization\]/,$ s/^axis = .*/axis = "solver.alpha"/' "$tmp/reg.toml" > "$tmp/reg_axis.toml"
err=$("$rpfem" sweep "$tmp/reg_axis.toml" --out "$tmp/bad8" 2>&1); rc=$?
check "a regularization axis that is not one of the study's: exit 2 ($err)" \
  '[ $rc -eq 2 ] && printf "%s" "$err" | grep -q "study.regularization.axis"'
sed -e 's/^kind = "formulation"/kind = "none"/' -e '/^formulation = "ipopt"/d' "$tmp/reg.toml" > "$tmp/reg_none.toml"
err=$("$rpfem" sweep "$tmp/reg_none.toml" --out "$tmp/bad9" 2>&1); rc=$?
check "a regularization axis without a reference run: exit 2 ($err)" \
  '[ $rc -eq 2 ] && printf "%s" "$err" | grep -q "study.regularization.axis" && printf "%s" "$err" | grep -q "formulation"'
exit $fail
