#!/usr/bin/env bash
# `rpfem calibrate`: bad input gives one line naming the file (and line)
# and exit code 2, before any run; a run that fails stops the calibration
# with exit code 3 and says which evaluation and why.
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
fail=0
expect() {  # expect NAME CODE PATTERN -- command...
  local name=$1 code=$2 pattern=$3; shift 4
  local err rc
  err=$("$@" 2>&1 >/dev/null); rc=$?
  local lines; lines=$(printf '%s\n' "$err" | grep -c .)
  if [ "$rc" -ne "$code" ] || [ "$lines" -ne 1 ] || ! printf '%s' "$err" | grep -qF -- "$pattern"; then
    echo "FAIL $name: exit $rc, $lines line(s): $err"; fail=1
  else
    echo "ok   $name: $err"
  fi
}
ring=$src/cases/ring_compression.toml
fit=(--param dies.top_die.friction.m --bounds 0,1 --set run.mesh_factor=0.5 --quiet)
bad_target() {  # bad_target NAME CSV-TEXT PATTERN-AFTER-THE-FILE-NAME
  printf "$2" > "$tmp/$1.csv"
  expect "$1" 2 "$tmp/$1.csv$3" -- "$rpfem" calibrate "$ring" --out "$tmp/out-$1" --target "$tmp/$1.csv" "${fit[@]}"
}
expect missing-target 2 "$tmp/nope.csv: no such target file" -- \
  "$rpfem" calibrate "$ring" --out "$tmp/out-missing" --target "$tmp/nope.csv" "${fit[@]}"
bad_target malformed-cell 'stroke_mm,load_kN\n0.5,1200\n1.0,12OO\n' ":3: column 2 (load_kN): expected a number, got '12OO'"
bad_target wrong-header 'stroke,load\n0.5,1200\n1.0,1300\n' ":1: expected the header 'stroke_mm,load_kN'"
bad_target one-row 'stroke_mm,load_kN\n0.5,1200\n' ": expected at least 2 data rows after the header, got 1"
bad_target beyond-stroke 'stroke_mm,load_kN\n1.0,1300\n6.0,1900\n' ":3: column 1 (stroke_mm): 6 is beyond the simulated range"
printf 'stroke_mm,load_kN\n0.5,1200\n1.0,1300\n' > "$tmp/good.csv"
expect unused-key 2 "--param 'dies.top_die.friction.mu': expected a number this case uses" -- \
  "$rpfem" calibrate "$ring" --out "$tmp/out-mu" --target "$tmp/good.csv" --param dies.top_die.friction.mu --bounds 0,1
expect bounds-out-of-range 2 "--bounds: 2: $ring: key 'dies.top_die.friction.m': expected a number in [0, 1]" -- \
  "$rpfem" calibrate "$ring" --out "$tmp/out-bounds" --target "$tmp/good.csv" --param dies.top_die.friction.m --bounds 0,2
for o in "$tmp"/out-*; do
  [ -e "$o/evals" ] && { echo "FAIL $o: a run was started on bad input"; fail=1; }
done
# One Newton iteration cannot solve step 0: the first run stops (exit 3).
expect run-fails 3 "stopped: evaluation 1 (dies.top_die.friction.m = 0.1): the run stopped early (exit 3)" -- \
  "$rpfem" calibrate "$ring" --out "$tmp/run-fails" --target "$tmp/good.csv" "${fit[@]}" --set solver.max_iterations=1
grep -q '"status" : "stopped"' "$tmp/run-fails/calibration.json" || { echo "FAIL run-fails: calibration.json not stopped"; fail=1; }
exit $fail
