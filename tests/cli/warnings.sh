#!/usr/bin/env bash
# Requirement (extremes): a run records what makes its results
# doubtful in summary.json `warnings` and the driver prints each; a run
# stopped by an ill-conditioned tangent says so, with the rcond and a hint.
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
case=$src/cases/extremes/penalty_beta.toml
fail() { echo "FAIL: $*"; exit 1; }
# beta 1e-3 x default: penetration 2.3e-3 of the element size, above the
# default run.penetration_tolerance (1e-3).
err=$("$rpfem" run "$case" --variant beta_1e-3 --out "$tmp/low" --quiet 2>&1 >/dev/null); rc=$?
[ "$rc" -eq 0 ] || fail "beta 1e-3: exit $rc"
echo "$err" | grep -q "^rpfem: warning: penetration unacceptable: .* above run.penetration_tolerance = 0.001" ||
  fail "beta 1e-3: no warning printed: $err"
# (the top-level key: the case's [expect] tables, in the parameters, name warnings too)
grep -A1 '^    "warnings" : \[' "$tmp/low/summary.json" | grep -q '"penetration unacceptable: ' ||
  fail "beta 1e-3: summary.json warnings"
# The same run with a looser tolerance: no warning, and the tolerance is
# recorded with the parameters.
err=$("$rpfem" run "$case" --variant beta_1e-3 --out "$tmp/loose" --quiet --set run.penetration_tolerance=1e-2 2>&1 >/dev/null)
[ -z "$err" ] || fail "tolerance 1e-2: unexpected output: $err"
grep -q '^    "warnings" : \[\]' "$tmp/loose/summary.json" || fail "tolerance 1e-2: warnings not empty"
grep -q '"penetration_tolerance" *: *0.01' "$tmp/loose/summary.json" || fail "tolerance not in the parameters"
# auglag warns of the configuration's penetration, not only of its
# predicted end-of-step gaps (held to 1e-9): the patch test's blocks
# starting 0.05 mm inside each other (0.05 of the element size).
err=$("$rpfem" run "$src/cases/patch_two_blocks.toml" --formulation auglag --out "$tmp/auglag" --quiet \
  --set bodies.upper.mesh.y0=4.95 --set stepping.end_stroke=0.1 2>&1 >/dev/null); rc=$?
[ "$rc" -eq 0 ] || fail "auglag overlapping: exit $rc"
echo "$err" | grep -q "^rpfem: warning: penetration unacceptable: 0.05 of the element size at step 0" ||
  fail "auglag overlapping: no penetration warning: $err"
# beta 1e12 x default: Newton stalls at the first solve.
err=$("$rpfem" run "$case" --variant beta_1e12 --out "$tmp/high" --quiet 2>&1 >/dev/null); rc=$?
[ "$rc" -eq 3 ] || fail "beta 1e12: exit $rc, expected 3"
echo "$err" | grep -q "run stopped: .*the tangent is ill-conditioned (rcond [0-9.e+-]*, below 100 x machine epsilon).*beta_factor" ||
  fail "beta 1e12: reason: $err"
grep -q '"reason" *: *".*ill-conditioned' "$tmp/high/summary.json" || fail "beta 1e12: summary.json reason"
# The last line of a run (not --quiet) gives the final loads in kN and the
# number of warnings.
last=$("$rpfem" run "$case" --variant beta_1e-3 --out "$tmp/last" 2>/dev/null | tail -1)
echo "$last" | grep -q "^finished: [0-9]* steps, [0-9]* Newton iterations\( (and [0-9]* in attempts not kept)\)\?; final load .*\.Fy -\?[0-9.]* kN; 1 warning; results in " ||
  fail "last line: $last"
last=$("$rpfem" run "$case" --variant beta_1e-3 --out "$tmp/last0" --set run.penetration_tolerance=1e-2 2>/dev/null | tail -1)
echo "$last" | grep -q "; 0 warnings; results in " || fail "last line without warnings: $last"
echo "ok: warnings recorded and printed, ill-conditioning reported, the last line"
