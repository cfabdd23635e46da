#!/usr/bin/env bash
# Requirement: a run without remeshing says when its mesh can no longer be
# trusted. Below run.min_scaled_jacobian it warns (summary.json, the
# printed warning, the last line's count), naming the first step and
# element below it and [remesh]; where an element inverts in every halving
# of a step, it stops (exit 3, the finished steps saved) with one line
# naming the element and [remesh]. The same scene remeshed finishes.
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
case=$src/cases/core_in_sleeve.toml
coarse=(--set stepping.stroke_increment=0.1 --set stepping.output_every=100)
# The first step whose history.csv min_scaled_jacobian is below $2, in run $1.
first_below() {
  awk -F, -v t="$2" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "min_scaled_jacobian") c = i; next }
                     ($c + 0) < t { print $1; exit }' "$1/history.csv"
}
# 1. Upset to 50 % without [remesh]: the sleeve's outer corner folds onto
# the die (a corner of 180 degrees, the element still whole): finished,
# with the warning.
last=$("$rpfem" run "$case" --out "$tmp/half" --set remesh.enabled=false "${coarse[@]}" 2>"$tmp/half.err" | tail -1); rc=$?
err=$(cat "$tmp/half.err")
[ "$rc" -eq 0 ] || fail "50 % without remeshing: exit $rc: $err"
w=$(echo "$err" | grep "^rpfem: warning: mesh distorted: ")
[ "$(echo "$w" | grep -c .)" -eq 1 ] || fail "50 %: no mesh warning: $err"
echo "$w"
echo "$w" | grep -q "below run.min_scaled_jacobian = 0.1 from step [0-9]* (stroke [0-9.]* mm, element [0-9]* of body '[a-z]*', 0\.0[0-9]*)" ||
  fail "50 %: warning text: $w"
echo "$w" | grep -q "a \[remesh\] table with enabled = true" || fail "50 %: the warning names no [remesh]: $w"
step=$(echo "$w" | sed 's/.* from step \([0-9]*\) .*/\1/')
first=$(first_below "$tmp/half" 0.1)
[ -n "$first" ] && [ "$step" = "$first" ] || fail "50 %: warns from step $step, history.csv below 0.1 first at step $first"
echo "$last" | grep -q "^finished: .* [1-9] warnings\?; results in " || fail "50 %: last line: $last"
grep -A3 '^    "warnings" : \[' "$tmp/half/summary.json" | grep -q '"mesh distorted: ' || fail "50 %: summary.json warnings"
grep -q '"min_scaled_jacobian" *: *0\.10*1\?,\?$' "$tmp/half/summary.json" || fail "50 %: the threshold not in the parameters"
# 2. On to 80 % without [remesh]: an element inverts at 6.4 mm in every
# halving of its step; the run stops.
# At a lower threshold the warning starts at the first step below it.
err=$("$rpfem" run "$case" --out "$tmp/deep" --quiet --set remesh.enabled=false "${coarse[@]}" \
  --set stepping.end_stroke=8.0 --set run.min_scaled_jacobian=0.01 2>&1 >/dev/null); rc=$?
[ "$rc" -eq 3 ] || fail "80 % without remeshing: exit $rc, expected 3: $err"
stop=$(echo "$err" | grep "^rpfem: run stopped: ")
echo "$stop"
[ "$(echo "$stop" | grep -c .)" -eq 1 ] || fail "80 %: no stop line: $err"
echo "$stop" | grep -q "failed after [0-9]* step halvings: element [0-9]* of body '[a-z]*' inverts .*the mesh is too distorted to go on: remesh it (a \[remesh\] table with enabled = true)" ||
  fail "80 %: stop reason: $stop"
low=$(echo "$err" | grep "^rpfem: warning: mesh distorted: .*run.min_scaled_jacobian = 0.01 from step " |
  sed 's/.* from step \([0-9]*\) .*/\1/')
first=$(first_below "$tmp/deep" 0.01)
[ -n "$first" ] && [ "$low" = "$first" ] || fail "threshold 0.01: warns from step $low, history.csv below it first at $first"
grep -q '"status" *: *"stopped"' "$tmp/deep/summary.json" || fail "80 %: summary.json status"
rows=$(($(wc -l < "$tmp/deep/history.csv") - 1))
[ "$rows" -ge 50 ] || fail "80 %: $rows steps in history.csv"
grep -qi nan "$tmp/deep/history.csv" && fail "80 %: NaN in history.csv"
# 3. The same scene remeshed (the case as shipped) finishes at 50 %
# without a mesh warning.
err=$("$rpfem" run "$case" --out "$tmp/remeshed" --quiet "${coarse[@]}" 2>&1 >/dev/null); rc=$?
[ "$rc" -eq 0 ] || fail "50 % remeshed: exit $rc: $err"
echo "$err" | grep -q "mesh distorted" && fail "50 % remeshed: a mesh warning: $err"
grep -q '"remeshes"' "$tmp/remeshed/summary.json" || fail "50 % remeshed: no remesh"
echo "ok: warned from step $step (at 0.01: step $low), stopped at an inverted element, finished remeshed"
