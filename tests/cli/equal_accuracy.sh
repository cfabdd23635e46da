#!/usr/bin/env bash
# The comparison at equal accuracy, its quick grids end to end: a quick
# suite runs the equal-accuracy studies of the frictionless upsetting
# (against its exact load) and of the ring (against the direct midpoint
# reference run), each enforcement of the quick grid under step control;
# every run's achieved error (max over the stroke of |F_h - F| / max |F|
# away from the landings, sweep.csv load_error_max_rel) lies within a
# factor 3 of its tolerance and falls with it, and the report carries the
# figure (achieved error and wall time against the tolerance) and the
# table. And ipopt's die load under Euler steps on a half model: an
# interior point's small multiplier on a free row at the symmetry plane
# (the billet's bottom corner) no longer zeroes it. About 13 s of CPU
# (75 s of wall on the 2 cores shared with ten times as many jobs).
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib/check.bash"
o=$tmp/o
studies="equal_accuracy_upsetting equal_accuracy_ring"
out=$("$rpfem" suite --out "$o" --jobs 2 --quick --scene upsetting_dies_frictionless_axisym -f direct --no-variants \
  --checks "" $(printf -- "--study %s " $studies) 2>&1); rc=$?
echo "$out" | grep -E "^(equal_accuracy|report:)"
check "suite exits 0 ($rc)" '[ $rc -eq 0 ]'
for s in equal_accuracy_upsetting:4 equal_accuracy_ring:4; do
  name=${s%:*}; rows=${s#*:}
  check "$name: quick grid of $rows rows" '[ "$(($(wc -l < "$o/studies/$name/sweep.csv") - 1))" -eq $rows ]'
  check "figure study_${name}_tolerance" '[ -s "$o/report_files/study_${name}_tolerance.png" ] &&
    grep -q "(report_files/study_${name}_tolerance.png)" "$o/report.md" &&
    grep -q "<img alt=.achieved error against tolerance, $name. src=.report_files/study_${name}_tolerance.png." "$o/report.html"'
done
check "the tables: steps, rejected steps, the achieved error, wall time" \
  '[ "$(grep -c "^| formulation | tolerance | finished | steps | rejected steps | final load (kN) | max |F_h - F| / max |F| | iterations median | wall time (s) |" "$o/report.md")" -eq 2 ]'
check "the effectivities stated" 'grep -q "^direct, achieved error / tolerance at 0.01: [0-9.]*, 0.001: [0-9.]*\.$" "$o/report.md"'
/usr/bin/python3 - "$o/studies" $studies <<'PY' || fail=1
import csv, sys
ok = True
for name in sys.argv[2:]:
    rows = list(csv.DictReader(open("%s/%s/sweep.csv" % (sys.argv[1], name))))
    last = {}
    for r in sorted(rows, key=lambda r: -float(r["stepping.tolerance"])):
        tol, err, f = float(r["stepping.tolerance"]), float(r["load_error_max_rel"]), r["formulation"]
        good = r["finished"] == "1" and tol / 3 <= err <= 3 * tol and err < last.get(f, 1.0)
        last[f] = err
        ok = ok and good
        print("%s  %s %s tolerance %g: achieved %.3e (%.2f of it) in %s steps, %s s"
              % ("ok  " if good else "FAIL", name, f, tol, err, err / tol, r["steps"], r["wall_time_s"]))
sys.exit(0 if ok else 1)
PY
# Bad input: exit 2 naming the file and the key, before any run.
up="$src/cases/studies/equal_accuracy_upsetting.toml"
sed '/^diameter/d' "$up" > "$tmp/no_d.toml"
sed 's/^kind = "exact"/kind = "richardson"\naxis = "stepping.tolerance"/' "$up" | sed '/^solution\|^diameter\|^height/d' > "$tmp/rich.toml"
sed 's/^height_per_stroke = 2.0/height_per_stroke = 4.0/' "$up" > "$tmp/deep.toml"
for b in no_d:study.reference.diameter rich:study.reference.measure deep:study.reference.height_per_stroke; do
  f=${b%%:*}; key=${b#*:}
  err=$("$rpfem" sweep "$tmp/$f.toml" --cases "$src/cases" --out "$tmp/bad_$f" 2>&1); rc=$?
  check "$f: exit 2 naming $f.toml and $key ($err)" \
    '[ $rc -eq 2 ] && printf "%s" "$err" | grep -q "$f.toml" && printf "%s" "$err" | grep -q "$key" && [ ! -d "$tmp/bad_$f/runs" ]'
done
"$rpfem" run "$src/cases/upsetting_dies_frictionless_axisym.toml" -f ipopt --out "$tmp/ipopt" -q \
  --set stepping.integration=euler --set stepping.end_stroke=0.1 --set bodies.billet.mesh.nx=4 \
  --set bodies.billet.mesh.ny=4 >/dev/null 2>&1
check "ipopt under Euler: the die's load is the billet's contact load, not 0" \
  'awk -F, "NR == 1 { for (i = 1; i <= NF; i++) { if (\$i == \"top_die.Fy\") d = i; if (\$i == \"billet.contact_Fy\") b = i } }
            NR > 1 { n++; if (\$d < -1e5 && (\$d - \$b) ^ 2 < 1e-6 * \$b ^ 2) ok++ } END { exit !(n == 3 && ok == n) }" \
   "$tmp/ipopt/history.csv"'
exit $fail
