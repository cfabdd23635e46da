#!/usr/bin/env bash
# A run killed with SIGKILL at any moment (nothing of rpfem runs after the
# signal) leaves results that open and agree: result.h5 opens with every
# step its index lists; every dataset result.xdmf names is in result.h5
# with the shape it states; history.csv's rows are whole, numbered in
# order, and reach at least result.h5's last step (a step's row is written
# first). 20 kills at times spread over the run, from its start to near
# its end.
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib/check.bash"
case_file=$src/cases/upsetting_dies_frictionless_axisym.toml
# About 2 s on this machine: 200 steps of 0.025 mm, every step recorded.
args=(--quiet --set stepping.stroke_increment=0.025 --set stepping.output_every=1)
start=$(date +%s.%N)
"$rpfem" run "$case_file" --out "$tmp/full" "${args[@]}" > /dev/null 2>&1
full=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')
for i in $(seq 1 20); do
  out=$tmp/k$i
  # Kill times from 2 % to 95 % of a whole run's time, with a jitter.
  at=$(awk -v t="$full" -v i="$i" -v r="$RANDOM" 'BEGIN { printf "%.3f", t * (0.02 + 0.93 * (i - 1) / 19) + (r % 50) / 1000 }')
  "$rpfem" run "$case_file" --out "$out" "${args[@]}" > /dev/null 2>&1 &
  pid=$!
  sleep "$at"
  kill -KILL $pid 2>/dev/null; wait $pid 2>/dev/null
  /usr/bin/python3 - "$out" <<'PY' > "$tmp/k$i.check" 2>&1
import csv, os, re, sys, h5py
d = sys.argv[1]
rows = []
if os.path.exists(d + "/history.csv"):
    text = open(d + "/history.csv").read()
    assert text == "" or text.endswith("\n"), "history.csv ends in a partial row"
    rows = list(csv.DictReader(text.splitlines()))
    width = len(text.splitlines()[0].split(",")) if text else 0
    for r in rows:
        assert None not in r.values() and len(r) == width, r
    steps = [int(r["step"]) for r in rows]
    assert steps == list(range(len(steps))), steps[:5]
last_h5 = -1
if os.path.exists(d + "/result.h5"):
    with h5py.File(d + "/result.h5", "r") as f:
        idx = list(f["steps/index"][:]) if "steps/index" in f else []
        for s in idx:
            assert "steps/%06d/coordinates" % s in f, s
        last_h5 = idx[-1] if idx else -1
        if os.path.exists(d + "/result.xdmf"):
            xdmf = open(d + "/result.xdmf").read()
            for dims, path in re.findall(r'Dimensions="([\d ]+)">result\.h5:(/[^<]+)<', xdmf):
                assert path in f, path
                assert list(f[path].shape) == [int(x) for x in dims.split()], (path, f[path].shape, dims)
else:
    assert not os.path.exists(d + "/result.xdmf"), "result.xdmf without result.h5"
assert len(rows) - 1 >= last_h5, (len(rows), last_h5)
print("history rows", len(rows), "result.h5 last step", last_h5)
PY
  rc=$?
  check "kill $i at ${at} s: results agree ($(tail -1 "$tmp/k$i.check"))" '[ $rc -eq 0 ]'
done
exit $fail
