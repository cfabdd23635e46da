#!/usr/bin/env bash
# Requirement: a step whose Newton iteration fails is retried with half the
# step; a run that cannot go on stops (exit 3), says why, and keeps every
# finished step in history.csv, result.h5 and summary.json.
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
# A stroke beyond the billet's half height (10 mm) must flatten the
# elements: the steps near 10 mm invert elements, each retry is logged, and
# after max_cuts = 2 the run stops.
out=$("$rpfem" run "$src/cases/upsetting_frictionless_axisym.toml" --out "$tmp/o" \
  --set stepping.end_stroke=12.0 --set stepping.stroke_increment=0.5 --set stepping.max_cuts=2 2>&1); rc=$?
echo "$out" | tail -4
[ "$rc" -eq 3 ] || { echo "FAIL: exit code $rc, expected 3"; exit 1; }
echo "$out" | grep -q "retry with dt" || { echo "FAIL: no retry reported"; exit 1; }
echo "$out" | grep -q "run stopped: step .* failed after 2 step halvings" || { echo "FAIL: no reason"; exit 1; }
rows=$(($(wc -l < "$tmp/o/history.csv") - 1))
[ "$rows" -ge 1 ] || { echo "FAIL: no finished step in history.csv"; exit 1; }
grep -q '"status" *: *"stopped"' "$tmp/o/summary.json" || { echo "FAIL: summary.json status"; exit 1; }
grep -q '"reason"' "$tmp/o/summary.json" || { echo "FAIL: summary.json reason"; exit 1; }
grep -q '"time_per_step_s" *: *[0-9]' "$tmp/o/summary.json" || { echo "FAIL: summary.json time_per_step_s"; exit 1; }
h5dump -g /steps/000000 "$tmp/o/result.h5" > /dev/null || { echo "FAIL: step 0 not in result.h5"; exit 1; }
grep -qi nan "$tmp/o/history.csv" && { echo "FAIL: NaN in history"; exit 1; }
echo "ok: stopped cleanly with $rows finished step(s) saved"
