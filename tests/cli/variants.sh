#!/usr/bin/env bash
# Case variants and monitors: --variant all runs each variant into OUT/NAME
# with its overrides and the monitor columns; an unknown variant is exit 2.
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
fail=0
sed -e 's/^nx = 20/nx = 4/' -e 's/^ny = 20/ny = 4/' -e 's/^end_stroke = 5.0/end_stroke = 0.3/' \
    -e 's/^stroke_increment = 0.05/stroke_increment = 0.1/' \
    "$src/cases/upsetting_frictionless_axisym.toml" > "$tmp/case.toml"
cat >> "$tmp/case.toml" <<'TOML'

[[monitors]]
name = "radius"
side = "billet.right"
quantity = "max_x"
change = "percent"

[[variants]]
name = "short"
set = ["stepping.end_stroke=0.2"]

[[variants]]
name = "long"
set = ["stepping.end_stroke=0.4"]
TOML
"$rpfem" run "$tmp/case.toml" --out "$tmp/out" --variant all --set stepping.output_every=2 > "$tmp/log" 2>&1
rc=$?
[ "$rc" -eq 0 ] || { echo "FAIL --variant all: exit $rc"; cat "$tmp/log"; fail=1; }
for v in short long; do
  h=$tmp/out/$v/history.csv
  if ! head -1 "$h" | grep -q ',radius$'; then echo "FAIL $v: no monitor column"; fail=1; fi
  if ! grep -q "\"variant\" *: *\"$v\"" "$tmp/out/$v/summary.json"; then echo "FAIL $v: variant not in summary"; fail=1; fi
  if ! grep -q 'output_every=2' "$tmp/out/$v/summary.json"; then echo "FAIL $v: --set not applied"; fail=1; fi
done
last() { tail -1 "$tmp/out/$1/history.csv" | cut -d, -f3; }
[ "$(last short)" = "0.2" ] || { echo "FAIL short ends at $(last short)"; fail=1; }
[ "$(last long)" = "0.4" ] || { echo "FAIL long ends at $(last long)"; fail=1; }
# The homogeneous radius grows as sqrt(H0/H): 1/sqrt(1 - 0.04) - 1 = 2.06 %.
r=$(tail -1 "$tmp/out/long/history.csv" | awk -F, '{print $NF}')
awk -v r="$r" 'BEGIN { exit !(r > 2.04 && r < 2.08) }' || { echo "FAIL radius change $r %"; fail=1; }
grep -q '^  short *finished' "$tmp/log" || { echo "FAIL no summary line"; cat "$tmp/log"; fail=1; }
err=$("$rpfem" run "$tmp/case.toml" --out "$tmp/o2" --variant nope 2>&1); rc=$?
if [ "$rc" -ne 2 ] || ! printf '%s' "$err" | grep -q "'nope'.*short, long"; then
  echo "FAIL unknown variant: exit $rc: $err"; fail=1
fi
[ $fail -eq 0 ] && echo "ok variants and monitors"
exit $fail
