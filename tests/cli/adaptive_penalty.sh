#!/usr/bin/env bash
# The adaptive penalty (formulations.penalty.adapt): Test II's coarse cone
# at 1e-3 times the default beta misses run.penetration_tolerance (1e-3)
# with beta fixed (a beta_factor given turns adapt off: the warning); with
# adapt = true every step ends within it, the raised steps re-solved and
# counted (history.csv penalty_factor, penalty_raises; summary.json
# total_contact_retunes), the keys in the recorded parameters; a case that
# gives no beta runs adaptive by default. Over a remesh (the sticking
# upsetting, remeshed twice to 3.3 mm, at 1e-3 times the default beta) the
# rows' factors carry over to the new mesh by position: the first step on
# each new mesh has factors above 1 and ends within the tolerance without
# a raise (before, each such step raised again from 1).
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib/check.bash"
case=$src/cases/extremes/penalty_beta.toml
err=$("$rpfem" run "$case" --variant beta_1e-3 --out "$tmp/fixed" --quiet 2>&1 >/dev/null); rc=$?
check "fixed beta: exit 0" '[ $rc -eq 0 ]'
check "fixed beta: the penetration warning" 'echo "$err" | grep -q "penetration unacceptable"'
check "fixed beta: adapt recorded false" 'grep -q "\"adapt\" *: *false" "$tmp/fixed/summary.json"'
err=$("$rpfem" run "$case" --variant beta_1e-3 --out "$tmp/adapt" --quiet --set formulations.penalty.adapt=true \
      2>&1 >/dev/null); rc=$?
check "adaptive: exit 0, no warning" '[ $rc -eq 0 ] && [ -z "$err" ]'
check "adaptive: keys recorded" 'grep -q "\"adapt\" *: *true" "$tmp/adapt/summary.json" &&
  grep -q "\"beta_max_factor\" *: *1000" "$tmp/adapt/summary.json"'
/usr/bin/python3 - "$tmp/fixed" "$tmp/adapt" <<'PY' || fail=1
import csv, json, sys
fixed, adapt = (list(csv.DictReader(open(d + "/history.csv"))) for d in sys.argv[1:3])
pf = max(float(r["max_penetration_rel"]) for r in fixed)
pa = [float(r["max_penetration_rel"]) for r in adapt]
raises = sum(int(float(r["penalty_raises"])) for r in adapt)
factor = max(float(r["penalty_factor"]) for r in adapt)
total = json.load(open(sys.argv[2] + "/summary.json"))["total_contact_retunes"]
print("[measured] fixed beta: largest penetration %.3g; adaptive: %.3g, %d re-solves, largest factor %.3g"
      % (pf, max(pa), raises, factor))
ok = pf > 1e-3 and all(p <= 1e-3 for p in pa) and raises > 0 and raises == total and factor > 1
ok = ok and "penalty_factor" not in fixed[0] and len(fixed) == len(adapt)
print(("ok  " if ok else "FAIL") + " adaptive: every step within the tolerance, the re-solves counted")
sys.exit(0 if ok else 1)
PY
# No beta given: adaptive by default (a short run of the same scene).
"$rpfem" run "$case" --out "$tmp/default" --quiet --set stepping.end_stroke=0.1 2>/dev/null; rc=$?
check "no beta given: adapt on by default" '[ $rc -eq 0 ] && grep -q "\"adapt\" *: *true" "$tmp/default/summary.json"'
# Over a remesh.
"$rpfem" run "$src/cases/upsetting_sticking_remeshed.toml" --out "$tmp/remeshed" --quiet -f penalty \
  --set formulations.penalty.beta_factor=1e-3 --set formulations.penalty.adapt=true \
  --set stepping.end_stroke=3.3 2>/dev/null; rc=$?
check "remeshed: exit 0" '[ $rc -eq 0 ]'
/usr/bin/python3 - "$tmp/remeshed" <<'PY' || fail=1
import csv, sys
rows = {int(float(r["step"])): r for r in csv.DictReader(open(sys.argv[1] + "/history.csv"))}
remeshes = sorted({int(r["step"]) for r in csv.DictReader(open(sys.argv[1] + "/events.csv"))
                   if r["event"].startswith("remesh (")})
first = [rows[s + 1] for s in remeshes if s + 1 in rows]
after = [(float(r["penalty_factor"]), int(float(r["penalty_raises"])), float(r["max_penetration_rel"])) for r in first]
print("[measured] remeshes after steps %s; the first step on each new mesh (factor, raises, depth): %s" %
      (remeshes, after))
ok = len(remeshes) >= 2 and len(first) == len(remeshes)
ok &= all(f > 1 and n == 0 and d <= 1e-3 for f, n, d in after)
ok &= all(float(r["max_penetration_rel"]) <= 1e-3 for r in rows.values())
print(("ok  " if ok else "FAIL") + " remeshed: the factors carried over, no raise on a new mesh's first step")
sys.exit(0 if ok else 1)
PY
exit $fail
