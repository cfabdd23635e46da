#!/usr/bin/env bash
# `rpfem suite` end to end on one coarse scene: every formulation
# that treats rigid dies runs (direct, penalty, auglag, ipopt, ssn), suite.json lists
# them, and the report is built (HTML and its Markdown twin showing the
# figure files in report_files/). A broken report path breaks CI here.
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/cases"
cp "$src/cases/upsetting_dies_frictionless_axisym.toml" "$tmp/cases/"
out=$("$rpfem" suite --cases "$tmp/cases" --out "$tmp/o" --jobs 2 --set stepping.end_stroke=0.2 \
  --set bodies.billet.mesh.nx=6 --set bodies.billet.mesh.ny=6 2>&1); rc=$?
echo "$out" | tail -5
[ "$rc" -eq 0 ] || { echo "FAIL: exit code $rc"; exit 1; }
for f in direct penalty auglag ipopt ssn; do
  grep -q "\"formulation\" : \"$f\"" "$tmp/o/suite.json" || { echo "FAIL: no $f run in suite.json"; exit 1; }
  [ -s "$tmp/o/upsetting_dies_frictionless_axisym/$f/history.csv" ] || { echo "FAIL: no $f history"; exit 1; }
done
[ "$(grep -c '"exit_code" : 0' "$tmp/o/suite.json")" -eq 5 ] || { echo "FAIL: a run did not finish"; exit 1; }
echo "$out" | grep -q "report: .*report.html" || { echo "FAIL: report path not printed"; exit 1; }
# A cases folder without studies/: none run, the report has no Studies section.
[ ! -d "$tmp/o/studies" ] && ! grep -q "^## Studies" "$tmp/o/report.md" || { echo "FAIL: a Studies section without studies"; exit 1; }
grep -q "<img alt='load against stroke, upsetting_dies_frictionless_axisym' src='report_files/upsetting_dies_frictionless_axisym_load.png'" \
  "$tmp/o/report.html" || { echo "FAIL: figure not shown"; exit 1; }
grep -q "| upsetting_dies_frictionless_axisym | penalty | direct |" "$tmp/o/report.md" \
  || { echo "FAIL: no penalty-vs-direct row"; exit 1; }
for fig in load mesh velocity steps; do
  [ -s "$tmp/o/report_files/upsetting_dies_frictionless_axisym_$fig.png" ] || { echo "FAIL: no $fig figure"; exit 1; }
done
grep -q "<img alt='deformed meshes coloured by effective strain rate, upsetting_dies_frictionless_axisym'" \
  "$tmp/o/report.html" || { echo "FAIL: mesh figure not embedded"; exit 1; }
grep -q "<img alt='velocity magnitude with vectors near the contact, upsetting_dies_frictionless_axisym'" \
  "$tmp/o/report.html" || { echo "FAIL: velocity figure not embedded"; exit 1; }
grep -q "(report_files/upsetting_dies_frictionless_axisym_velocity.png)" "$tmp/o/report.md" \
  || { echo "FAIL: velocity figure not in the Markdown"; exit 1; }
# The suite ran the shipped checks of this scene: they pass, and the report
# carries the table.
grep -q '"failed" : 0' "$tmp/o/verification.json" || { echo "FAIL: suite verification"; cat "$tmp/o/verification.json"; exit 1; }
grep -q "Verification checks: [1-9][0-9]*, 0 failed" "$tmp/o/report.md" || { echo "FAIL: no verification table"; exit 1; }
# Each check says what it verifies and against what (verification/checks.toml),
# in verification.json and in the report's table.
grep -q '"against" : "direct (exact Kuhn-Tucker' "$tmp/o/verification.json" \
  && grep -q '"verifies" : "penalty: the die load of frictionless flat-die upsetting' "$tmp/o/verification.json" \
  || { echo "FAIL: verification.json without verifies/against"; exit 1; }
grep -q "| result | against |" "$tmp/o/report.md" && grep -q "| pass | direct (exact Kuhn-Tucker" "$tmp/o/report.md" \
  || { echo "FAIL: the report's verification table without its against column"; exit 1; }
# rpfem verify with its own checks passes, then fails (exit 4) once a
# result is perturbed: the penalty run's load 1 % higher at one step.
cat > "$tmp/checks.toml" <<'CHECKS'
[[check]]
scene = "upsetting_dies_frictionless_axisym"
formulation = "penalty"
metric = "load_difference"
reference = "direct"
load = "top_die.Fy"
tolerance = 1e-4
[[check]]
scene = "upsetting_dies_frictionless_axisym"
formulation = "ipopt"
metric = "history_max"
column = "kkt_stationarity"
tolerance = 1e-8
CHECKS
"$rpfem" verify "$tmp/o" --checks "$tmp/checks.toml" > "$tmp/v1" 2>&1; rc=$?
[ "$rc" -eq 0 ] || { echo "FAIL: verify exit $rc"; cat "$tmp/v1"; exit 1; }
h="$tmp/o/upsetting_dies_frictionless_axisym/penalty/history.csv"
col=$(head -1 "$h" | tr ',' '\n' | grep -n '^top_die.Fy$' | cut -d: -f1)
awk -F, -v OFS=, -v c="$col" 'NR == 3 { $c = $c * 1.01 } { print }' "$h" > "$h.new" && mv "$h.new" "$h"
"$rpfem" verify "$tmp/o" --checks "$tmp/checks.toml" > "$tmp/v2" 2>&1; rc=$?
[ "$rc" -eq 4 ] || { echo "FAIL: perturbed result passed verify (exit $rc)"; cat "$tmp/v2"; exit 1; }
grep -q "FAIL" "$tmp/v2" && grep -q '"failed" : 1' "$tmp/o/verification.json" \
  || { echo "FAIL: the failed check is not reported"; exit 1; }
# A scene that does not exist is bad input (exit 2), naming it.
"$rpfem" suite --cases "$tmp/cases" --out "$tmp/o2" --scene nosuch > "$tmp/err" 2>&1; rc=$?
[ "$rc" -eq 2 ] || { echo "FAIL: unknown scene gave exit $rc"; cat "$tmp/err"; exit 1; }
# run.suite_formulations limits the scene's runs to those named; a name
# that does not treat its contacts is bad input naming the file and key.
"$rpfem" suite --cases "$tmp/cases" --out "$tmp/o3" --jobs 2 --no-studies --no-report --set stepping.end_stroke=0.1 \
  --set bodies.billet.mesh.nx=4 --set bodies.billet.mesh.ny=4 --set 'run.suite_formulations=["direct","auglag"]' \
  > "$tmp/o3.log" 2>&1; rc=$?
[ "$rc" -eq 0 ] || { echo "FAIL: limited suite exit $rc"; cat "$tmp/o3.log"; exit 1; }
[ "$(ls "$tmp/o3/upsetting_dies_frictionless_axisym" | tr '\n' ' ')" = "auglag direct " ] \
  || { echo "FAIL: suite_formulations not followed: $(ls "$tmp/o3/upsetting_dies_frictionless_axisym")"; exit 1; }
"$rpfem" suite --cases "$tmp/cases" --out "$tmp/o4" --no-studies --set 'run.suite_formulations=["direct","nosuch"]' \
  > "$tmp/err" 2>&1; rc=$?
[ "$rc" -eq 2 ] && grep -q "upsetting_dies_frictionless_axisym.toml: key 'run.suite_formulations': 'nosuch'" "$tmp/err" \
  || { echo "FAIL: a bad suite_formulations entry gave exit $rc"; cat "$tmp/err"; exit 1; }
echo "ok: suite ran every enforcement and built the report"
