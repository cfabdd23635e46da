#!/usr/bin/env bash
# A quick suite runs the shipped Test II studies and the friction
# smoothing studies (their reduced grids) beside one small scene and the
# report carries their figures and tables: the penalty sensitivity, speed
# against accuracy, mesh and step convergence with an observed order, and
# the errors against the exact friction law with their orders as the
# smoothing falls (tests/cli/suite.sh: a suite without studies builds its
# report with no Studies section). About 50 s on 2 cores, the friction
# studies 8 s of it.
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib/check.bash"
o=$tmp/o
out=$("$rpfem" suite --out "$o" --jobs 2 --quick --scene upsetting_dies_frictionless_axisym \
  --study penalty_beta_test2 --study speed_accuracy_test2 --study mesh_convergence_test2 \
  --study step_convergence_test2 --study friction_smoothing_ring_m01 --study friction_smoothing_ring_m1 \
  --study friction_smoothing_ring_mu01 --study friction_smoothing_upsetting_mu01 2>&1); rc=$?
echo "$out" | grep -E "^(  study|studies:|penalty_beta|speed_acc|mesh_conv|step_conv|friction_smoothing|  Richardson|  usable|  formulation=|report:)"
# penalty_beta_test2's largest betas stop (its table says so): exit 0 all the same.
check "suite exits 0 ($rc)" '[ $rc -eq 0 ]'
friction="friction_smoothing_ring_m01 friction_smoothing_ring_m1 friction_smoothing_ring_mu01 friction_smoothing_upsetting_mu01"
for s in penalty_beta_test2:7 speed_accuracy_test2:6 mesh_convergence_test2:3 step_convergence_test2:3 \
         $(printf "%s:6 " $friction); do
  name=${s%:*}; rows=${s#*:}
  check "$name: quick grid of $rows rows" '[ "$(($(wc -l < "$o/studies/$name/sweep.csv") - 1))" -eq $rows ]'
  check "$name in suite.json" 'grep -q "\"table\" : \"studies/$name/sweep.csv\"" "$o/suite.json"'
done
stopped=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "finished") c = i } NR > 1 && $c == 0' \
  "$o/studies/penalty_beta_test2/sweep.csv" | wc -l)
check "the runs that stopped, counted in suite.json ($stopped)" \
  '[ $stopped -gt 0 ] && grep -q "\"stopped\" : $stopped" "$o/suite.json"'
check "progress lines name the studies' runs" \
  'echo "$out" | grep -q "^\[[0-9]*/[0-9]*\] penalty_beta_test2 beta_factor=1e+12: stopped"'
for f in penalty_beta_test2_sensitivity speed_accuracy_test2_pareto mesh_convergence_test2_convergence \
         step_convergence_test2_convergence; do
  check "figure $f" '[ -s "$o/report_files/study_$f.png" ] && grep -q "(report_files/study_$f.png)" "$o/report.md"'
done
embedded() { grep -o "<img alt='$1, $2' src='report_files/study_$2_[a-z]*.png'" "$o/report.html" | wc -l; }
check "figures shown in the HTML" '[ "$(embedded "penalty sensitivity" penalty_beta_test2)" -eq 1 ] &&
  [ "$(embedded "speed against accuracy" speed_accuracy_test2)" -eq 1 ] &&
  [ "$(embedded convergence mesh_convergence_test2)" -eq 1 ] && [ "$(embedded convergence step_convergence_test2)" -eq 1 ]'
check "studies' tables in the report" 'grep -q "^| beta_factor | finished | steps |" "$o/report.md" &&
  grep -q "^| formulation | mesh_factor | finished |" "$o/report.md"'
# Midpoint stepping: the observed order in the stroke increment is about 2;
# the mean load over the stroke gives the mesh an order too.
order=$(grep -o "observed order [0-9.]*, extrapolated final load" "$o/report.md" | head -1 | awk '{print $3}')
check "step convergence: observed order $order in [1.5, 2.5]" 'awk -v p="$order" "BEGIN { exit !(p >= 1.5 && p <= 2.5) }"'
check "mesh convergence: an observed order" 'grep -q "observed order [0-9.]*, extrapolated mean load" "$o/report.md"'
check "speed against accuracy: penalty's errors against the direct runs' estimate" \
  '[ "$(awk -F, "NR == 1 { for (i = 1; i <= NF; i++) if (\$i == \"load_error_final\") c = i }
                 NR > 1 && \$3 == \"penalty\" && \$c > 0" "$o/studies/speed_accuracy_test2/sweep.csv" | wc -l)" -eq 3 ]'
check "the usable window stated" 'grep -q "^Usable beta_factor (penetration / element size <= 0.001" "$o/report.md"'
for f in $friction; do
  check "figure study_${f}_regularization" '[ -s "$o/report_files/study_${f}_regularization.png" ] &&
    grep -q "(report_files/study_${f}_regularization.png)" "$o/report.md" &&
    [ "$(embedded regularization $f)" -eq 1 ]'
done
check "the friction studies' tables: errors, orders, the monitor, iterations, wall time, the reference's row" \
  '[ "$(grep -c "^| formulation | a | finished | steps | \(final load (kN) | load error\|mean load (kN) | mean load error\) | load order | \(inner_diameter_mid (%)\|top_corner_radius (mm)\) | error (\(percentage points\|mm\)) | [a-z_]* order | iterations median | iterations max | iterations mean | wall time (s) |" "$o/report.md")" -eq 4 ] &&
   [ "$(grep -c "^| ssn (reference) | - | yes |" "$o/report.md")" -eq 4 ]'
# At m = 0.1 the ring's face slides everywhere: the errors fall with order 1
# (0.97 to 1.00 on the half mesh from a = 0.1 to 1e-3), under both enforcements.
/usr/bin/python3 - "$o/studies/friction_smoothing_ring_m01/sweep.json" <<'PY' || fail=1
import json, sys
reg = json.load(open(sys.argv[1]))["regularization"]
orders = [(g["group"], part, g[part].get("fit_order")) for g in reg["groups"] for part in ("load", "monitor")]
at = [g[part]["error_at_default"] for g in reg["groups"] for part in ("load", "monitor")]
ok = len(orders) == 4 and all(p is not None and 0.85 <= p <= 1.15 for _, _, p in orders) and all(e > 0 for e in at)
print("%s  ring m = 0.1, quick: orders %s, errors at a = 1e-3 %s" % ("ok  " if ok else "FAIL", orders, at))
sys.exit(0 if ok else 1)
PY
check "the orders and the error at the default in the report" \
  'grep -q "^penalty, as a falls: the final load error order [0-9.]* (least squares over the 3 values above the floor 1e-06)" "$o/report.md" &&
   grep -q "At the default 0.001: load error [0-9.e-]*, inner_diameter_mid error [0-9.e-]* percentage points." "$o/report.md"'
exit $fail
