#!/usr/bin/env bash
# `cmake --install` puts rpfem under a prefix with its cases, report
# scripts and checks; the installed program finds them next to itself and
# runs from any folder: a case, and a one-scene suite with its report.
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib/check.bash"
build=$(cd "$(dirname "$rpfem")" && pwd)
cmake --install "$build" --prefix "$tmp/prefix" > "$tmp/install.log" 2>&1
rc=$?
check "cmake --install (exit $rc)" '[ $rc -eq 0 ]'
bin=$tmp/prefix/bin/rpfem
share=$tmp/prefix/share/rpfem
check "installed: bin/rpfem, share/rpfem/{cases,reports,verification}" \
  '[ -x "$bin" ] && [ -f "$share/cases/upsetting_frictionless_axisym.toml" ] && [ -f "$share/reports/make_report.py" ] && [ -f "$share/verification/checks.toml" ]'
mkdir -p "$tmp/elsewhere" && cd "$tmp/elsewhere"
help=$("$bin" suite --help)
check "suite's defaults are the installed cases and checks" \
  'echo "$help" | grep -q -- "--cases TEXT=$share/cases" && echo "$help" | grep -q -- "--checks TEXT=$share/verification/checks.toml"'
"$bin" run "$share/cases/upsetting_frictionless_axisym.toml" --out run --quiet --set stepping.end_stroke=0.5
rc=$?
check "a case runs from another folder (exit $rc)" '[ $rc -eq 0 ] && [ -f run/summary.json ]'
# A remeshing run loads gmsh's module from lib/rpfem beside bin/, not the
# build tree's, and records which (summary.json's gmsh_module).
module=$tmp/prefix/lib/rpfem/librpfem_gmsh.so
check "installed: lib/rpfem/librpfem_gmsh.so" '[ -f "$module" ]'
"$bin" run "$share/cases/upsetting_sticking_remeshed.toml" --out remeshed --quiet \
  --set stepping.end_stroke=0.5 --set remesh.stroke_interval=0.25 > remeshed.log 2>&1
rc=$?
check "a remeshing run with the installed module (exit $rc)" \
  '[ $rc -eq 0 ] && grep -q "remesh.stroke_interval reached" remeshed/summary.json && grep -q "\"gmsh_module\" : \"$(realpath "$module")\"" remeshed/summary.json'
"$bin" suite --quick --scene upsetting_frictionless_axisym --no-studies --no-variants --quiet --out suite \
  > suite.log 2>&1
rc=$?
check "a one-scene suite with its report (exit $rc)" '[ $rc -eq 0 ] && [ -s suite/report.html ] && [ -f suite/verification.json ]'
[ $fail -eq 0 ] || { cat "$tmp/install.log" "$tmp/elsewhere/suite.log" 2>/dev/null; cat "$tmp/elsewhere/remeshed.log" "$tmp/elsewhere/remeshed/summary.json"; exit 1; }
echo "ok: installed rpfem"
