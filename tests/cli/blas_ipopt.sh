#!/usr/bin/env bash
# The ipopt formulation's results do not depend on the BLAS: Test II's die
# at mesh factor 0.5 (with Debian's OpenBLAS it once stopped at step 0,
# "maximum number of iterations exceeded ... complementarity 8.8e+07")
# runs under the reference BLAS and under OpenBLAS, each selected by
# LD_LIBRARY_PATH, finishes under both, and both end at the same load to
# Ipopt's tolerance. OpenBLAS: the installed libopenblas0-pthread, else
# the package unpacked into a scratch folder (apt-get download; the
# system's BLAS is left as it is); neither, or no reference BLAS: fails,
# saying so, unless RPFEM_ALLOW_SKIP=1 skips it (exit 77).
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib/check.bash"
. "$(dirname "$0")/lib/skip.bash"
arch=$(gcc -print-multiarch 2>/dev/null || echo x86_64-linux-gnu)
reference=/usr/lib/$arch/blas:/usr/lib/$arch/lapack
openblas=/usr/lib/$arch/openblas-pthread
if [ ! -f "$openblas/libblas.so.3" ]; then
  (cd "$tmp" && apt-get download libopenblas0-pthread > /dev/null 2>&1) &&
    dpkg -x "$tmp"/libopenblas0-pthread_*.deb "$tmp/root" 2> /dev/null
  openblas=$tmp/root/usr/lib/$arch/openblas-pthread
fi
[ -f "/usr/lib/$arch/blas/libblas.so.3" ] || cannot_test "Debian's reference BLAS (libblas3) is not installed"
[ -f "$openblas/libblas.so.3" ] || cannot_test "OpenBLAS neither installed nor downloadable"
case_file=$src/cases/paper_test2_die.toml
for blas in reference openblas; do
  path=$([ $blas = reference ] && echo "$reference" || echo "$openblas")
  used=$(LD_LIBRARY_PATH=$path ldd "$rpfem" | awk '/libblas.so.3/ { print $3 }')
  check "$blas: rpfem loads $used" '[ "${used#$path}" != "$used" ] || [ "${used#${path%%:*}}" != "$used" ]'
  LD_LIBRARY_PATH=$path "$rpfem" run "$case_file" --formulation ipopt --set run.mesh_factor=0.5 \
    --out "$tmp/$blas" --quiet > "$tmp/$blas.log" 2>&1
  rc=$?
  check "$blas: ipopt on Test II's die at mesh factor 0.5 finishes (exit $rc)" '[ $rc -eq 0 ]'
  # summary.json names the BLAS the run was on (from the process's own
  # mappings: ldd of the executable cannot tell).
  recorded=$(/usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["blas"])' "$tmp/$blas/summary.json")
  want=$([ $blas = reference ] && echo "/usr/lib/$arch/blas/" || echo "$openblas/")
  check "$blas: summary.json records $recorded" '[ "${recorded#$(readlink -f "$want")/}" != "$recorded" ]'
done
/usr/bin/python3 - "$tmp" <<'PY' > "$tmp/compare.log" 2>&1
import json, sys
a, b = (json.load(open("%s/%s/summary.json" % (sys.argv[1], n))) for n in ("reference", "openblas"))
fa, fb = a["final_load_N"]["punch"][1], b["final_load_N"]["punch"][1]
assert a["status"] == b["status"] == "finished"
assert abs(fa / fb - 1) < 1e-6, (fa, fb)
print("final punch load %.6g N and %.6g N, %.1e apart" % (fa, fb, abs(fa / fb - 1)))
PY
rc=$?
check "both BLAS end at the same load ($(tail -1 "$tmp/compare.log"))" '[ $rc -eq 0 ]'
# solver.blas_threads: OpenBLAS kept to one thread unless asked (its
# results change with its thread count), whatever OPENBLAS_NUM_THREADS
# says; the reference BLAS has no threads to set. summary.json records the
# count in effect.
blas_threads() { /usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["blas_threads"])' "$1/summary.json"; }
small=(run "$src/cases/upsetting_frictionless_axisym.toml" --quiet --set stepping.end_stroke=0.2)
OPENBLAS_NUM_THREADS=2 LD_LIBRARY_PATH=$openblas "$rpfem" "${small[@]}" --out "$tmp/t_default" > /dev/null 2>&1
check "OpenBLAS: one thread by default ($(blas_threads "$tmp/t_default"))" '[ "$(blas_threads "$tmp/t_default")" = 1 ]'
LD_LIBRARY_PATH=$openblas "$rpfem" "${small[@]}" --out "$tmp/t_two" --set solver.blas_threads=2 > /dev/null 2>&1
check "OpenBLAS: solver.blas_threads=2 gives two ($(blas_threads "$tmp/t_two"))" '[ "$(blas_threads "$tmp/t_two")" = 2 ]'
LD_LIBRARY_PATH=$reference "$rpfem" "${small[@]}" --out "$tmp/t_ref" --set solver.blas_threads=2 > /dev/null 2>&1
check "reference BLAS: one thread ($(blas_threads "$tmp/t_ref"))" '[ "$(blas_threads "$tmp/t_ref")" = 1 ]'
[ $fail -eq 0 ] || { cat "$tmp"/*.log; exit 1; }
echo "ok: ipopt under both BLAS; OpenBLAS's threads as solver.blas_threads says"
