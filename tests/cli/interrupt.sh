#!/usr/bin/env bash
# SIGTERM and SIGINT stop `rpfem run` at the next step boundary: exit
# 143 and 130, summary.json says "interrupted" with its reason, and the
# finished steps are all there and agree (history.csv's last step is
# summary.json's `steps` and result.h5's last step; result.xdmf names
# only steps result.h5 holds).
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib/check.bash"
case_file=$src/cases/upsetting_dies_frictionless_axisym.toml
for sig in TERM INT; do
  out=$tmp/$sig
  "$rpfem" run "$case_file" --out "$out" --quiet --set stepping.stroke_increment=0.0005 > "$tmp/$sig.log" 2>&1 &
  pid=$!
  for _ in $(seq 300); do
    [ -f "$out/history.csv" ] && [ "$(wc -l < "$out/history.csv")" -ge 6 ] && break
    sleep 0.05
  done
  kill -$sig $pid; wait $pid; rc=$?
  want=$([ $sig = TERM ] && echo 143 || echo 130)
  check "SIG$sig: exit $want ($rc)" '[ $rc -eq $want ]'
  check "SIG$sig: said so" 'grep -q "rpfem: SIG$sig: run interrupted after step" "$tmp/$sig.log"'
  /usr/bin/python3 - "$out" <<'PY' > "$tmp/$sig.check" 2>&1
import csv, json, sys, re, h5py
d = sys.argv[1]
s = json.load(open(d + "/summary.json"))
assert s["status"] == "interrupted", s["status"]
assert s["reason"].startswith("interrupted after step"), s["reason"]
rows = list(csv.DictReader(open(d + "/history.csv")))
last = int(rows[-1]["step"])
assert last == s["steps"] and last >= 5, (last, s["steps"])
with h5py.File(d + "/result.h5", "r") as f:
    idx = list(f["steps/index"][:])
    assert idx[-1] == last, (idx[-1], last)
xdmf = open(d + "/result.xdmf").read()
for ref in set(re.findall(r"result\.h5:/steps/(\d+)/", xdmf)):
    assert int(ref) in idx, ref
print("steps", last)
PY
  check "SIG$sig: interrupted, every finished step in history, result.h5 and result.xdmf ($(tail -1 "$tmp/$sig.check"))" \
    'grep -q "^steps" "$tmp/$sig.check"'
done
[ $fail -eq 0 ] || { cat "$tmp"/*.log "$tmp"/*.check; exit 1; }
echo "ok: interrupted runs"
