#!/usr/bin/env bash
# An output folder is owned by one rpfem process at a time (OUT/.rpfem.lock):
# a second run, sweep, suite or calibrate into it is refused (exit 2, one
# line naming the folder and the pid), and the first run still ends with a
# readable result.h5. A non-empty --out is refused (exit 2, one line) unless
# --force, which removes what rpfem wrote there (a run stopped at step 0
# leaves no result.xdmf of the previous run, a variant no longer declared
# leaves no results, a report's figures go) and keeps the user's files; a
# pool's --resume keeps the finished runs of the same request and reruns a
# changed one. The lock goes at the end of a run, also after SIGTERM, and
# a lock left by a killed process is taken over.
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d)
bg=
trap '[ -n "$bg" ] && kill -9 $bg 2>/dev/null; rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib/check.bash"
case_file=$src/cases/upsetting_dies_frictionless_axisym.toml
out=$tmp/out

wait_lock() {  # wait_lock DIR: until DIR/.rpfem.lock holds a pid
  for _ in $(seq 400); do
    [ -s "$1/.rpfem.lock" ] && return 0
    sleep 0.025
  done
  return 1
}
refused() {  # refused NAME -- command...: exit 2, one line naming $out and the pid $bg
  local name=$1; shift 2
  local err rc lines
  err=$("$@" 2>&1 >/dev/null); rc=$?
  lines=$(printf '%s\n' "$err" | grep -c .)
  check "$name refused: exit 2 ($rc), one line ($lines): $err" \
    '[ $rc -eq 2 ] && [ $lines -eq 1 ] && printf "%s" "$err" | grep -q -- "--out .$out.: in use by another rpfem process (pid $bg"'
}
# result.h5 opens, every dataset result.xdmf names is in it (a missing
# result.xdmf names none), and its last step is history.csv's and
# summary.json's: prints "steps N" (N recorded steps).
h5_check() {
  /usr/bin/python3 - "$1" <<'PY'
import csv, json, os, re, sys, h5py
d = sys.argv[1]
with h5py.File(d + "/result.h5", "r") as f:
    idx = list(f["steps/index"][:]) if "index" in f["steps"] else []
    if os.path.exists(d + "/result.xdmf"):
        for path in re.findall(r"result\.h5:(/[^<]*)<", open(d + "/result.xdmf").read()):
            assert path in f, "result.xdmf names " + path + ", not in result.h5"
rows = list(csv.DictReader(open(d + "/history.csv")))
steps = json.load(open(d + "/summary.json"))["steps"]
if idx:
    assert idx[-1] == int(rows[-1]["step"]) == steps, (idx[-1], rows[-1]["step"], steps)
else:
    assert not rows and steps == 0, (len(rows), steps)
print("steps", len(idx))
PY
}

# Two runs into one folder: the second is refused while the first runs; the
# first finishes with every step in a readable result.h5.
"$rpfem" run "$case_file" --out "$out" --quiet --set stepping.stroke_increment=0.01 > "$tmp/first.log" 2>&1 &
bg=$!
check "the first run's lock holds its pid" 'wait_lock "$out" && [ "$(cat "$out/.rpfem.lock")" = "$bg" ]'
refused "a second run" -- "$rpfem" run "$case_file" --out "$out" --quiet
refused "a sweep" -- "$rpfem" sweep "$src/cases/studies/step_convergence_test2.toml" --out "$out"
refused "a suite" -- "$rpfem" suite --out "$out" --scene upsetting_dies_frictionless_axisym
refused "a calibration" -- "$rpfem" calibrate "$case_file" --auto-beta 1e-3 --out "$out"
wait $bg; rc=$?; bg=
check "the first run finished (exit $rc)" '[ $rc -eq 0 ] && grep -q "\"status\" : \"finished\"" "$out/summary.json"'
check "the first run's result.h5 opens and agrees with history.csv ($(h5_check "$out" 2>&1 | tail -1))" \
  'h5_check "$out" | grep -q "^steps [1-9][0-9][0-9]"'
check "its lock is gone" '[ ! -e "$out/.rpfem.lock" ]'

# Into the finished run's folder without --force: refused, nothing touched.
err=$("$rpfem" run "$case_file" --out "$out" --quiet 2>&1 >/dev/null); rc=$?
check "a non-empty --out without --force: exit 2 ($rc), one line naming it and --force: $err" \
  '[ $rc -eq 2 ] && [ "$(printf "%s\n" "$err" | grep -c .)" -eq 1 ] && printf "%s" "$err" | grep -q -- "--out .$out.: not empty (.*--force" && [ -e "$out/result.h5" ]'
err=$("$rpfem" run "$case_file" --out "$out" --force --resume 2>&1 >/dev/null); rc=$?
check "run has no --resume (exit $rc)" '[ $rc -ne 0 ]'
err=$("$rpfem" sweep "$src/cases/studies/step_convergence_test2.toml" --out "$out" --force --resume 2>&1 >/dev/null); rc=$?
check "--force and --resume exclude each other (exit $rc): $err" '[ $rc -ne 0 ] && printf "%s" "$err" | grep -q "excludes"'
# An empty folder, and a folder holding only a killed run's lock file, are new.
mkdir -p "$tmp/empty"; echo 1 > "$tmp/lockonly.lock"; mkdir -p "$tmp/lockonly"; mv "$tmp/lockonly.lock" "$tmp/lockonly/.rpfem.lock"
"$rpfem" run "$case_file" --out "$tmp/empty" --quiet --set stepping.end_stroke=0.1 > /dev/null 2>&1; rc=$?
"$rpfem" run "$case_file" --out "$tmp/lockonly" --quiet --set stepping.end_stroke=0.1 > /dev/null 2>&1; rc2=$?
check "an empty folder (exit $rc) and one with only a stale lock (exit $rc2) need no --force" '[ $rc -eq 0 ] && [ $rc2 -eq 0 ]'

# A run that stops at step 0 into the same folder (--force): nothing of the
# finished run stays (no result.xdmf naming its steps, no history rows).
"$rpfem" run "$case_file" --out "$out" --force --quiet --set solver.max_iterations=1 --set stepping.max_cuts=0 \
  > "$tmp/stop.log" 2>&1; rc=$?
check "the run stopped at step 0 (exit $rc)" '[ $rc -eq 3 ] && grep -q "step 0" "$tmp/stop.log"'
check "result.xdmf names only what result.h5 holds ($(h5_check "$out" 2>&1 | tail -1))" \
  '[ "$(h5_check "$out" 2>&1 | tail -1)" = "steps 0" ]'
check "history.csv has its header only" '[ "$(wc -l < "$out/history.csv")" -eq 1 ]'
check "no temporaries left" '[ -z "$(ls "$out" | grep -E "partial|tmp")" ]'
check "no meshio file of the finished run" '[ ! -e "$out/result_meshio.xdmf" ]'

# SIGTERM: the run stops at a step boundary and gives the folder back.
"$rpfem" run "$case_file" --out "$out" --force --quiet --set stepping.stroke_increment=0.001 > "$tmp/term.log" 2>&1 &
bg=$!
wait_lock "$out"; sleep 0.5
kill -TERM $bg; wait $bg; rc=$?; bg=
check "after SIGTERM (exit $rc) the lock is gone" '[ $rc -eq 143 ] && [ ! -e "$out/.rpfem.lock" ]'
# SIGKILL leaves the file, not the lock: the next run takes it over.
"$rpfem" run "$case_file" --out "$out" --force --quiet --set stepping.stroke_increment=0.001 > "$tmp/kill.log" 2>&1 &
bg=$!
wait_lock "$out"; kill -9 $bg; wait $bg 2>/dev/null; bg=
check "SIGKILL leaves the lock file" '[ -e "$out/.rpfem.lock" ]'
"$rpfem" run "$case_file" --out "$out" --force --quiet --set stepping.end_stroke=0.2 > "$tmp/after.log" 2>&1; rc=$?
check "a run after a killed one takes the folder (exit $rc)" '[ $rc -eq 0 ] && [ ! -e "$out/.rpfem.lock" ]'

# Variants: one dropped from the case loses its results on the next
# --variant all --force (a user's file in it stays, and so does a user's
# folder).
sed -e 's/^end_stroke = 5.0/end_stroke = 0.2/' "$case_file" > "$tmp/case.toml"
printf '\n[[variants]]\nname = "a"\nset = []\n\n[[variants]]\nname = "b"\nset = []\n' >> "$tmp/case.toml"
"$rpfem" run "$tmp/case.toml" --out "$tmp/v" --variant all --quiet > "$tmp/v.log" 2>&1
mkdir -p "$tmp/v/mine"; echo keep > "$tmp/v/mine/notes.txt"
echo keep > "$tmp/v/a/notes.txt"
sed -i '/^name = "a"/,$d' "$tmp/case.toml"; sed -i '$d' "$tmp/case.toml"
printf '[[variants]]\nname = "b"\nset = []\n' >> "$tmp/case.toml"
"$rpfem" run "$tmp/case.toml" --out "$tmp/v" --variant all --force --quiet > "$tmp/v2.log" 2>&1; rc=$?
check "--variant all again (exit $rc): the dropped variant's results are gone, the user's note stays" \
  '[ $rc -eq 0 ] && [ ! -e "$tmp/v/a/result.h5" ] && [ ! -e "$tmp/v/a/result.xdmf" ] && [ -e "$tmp/v/a/notes.txt" ]'
check "the kept variant and a user's folder stay" '[ -e "$tmp/v/b/result.h5" ] && [ -e "$tmp/v/mine/notes.txt" ]'
# The suite: its scene run's variant folders go with --no-variants
# (--resume), its finished run is kept, and rerun when its --set changes.
mkdir -p "$tmp/cases"
sed -e 's/^nx = 20/nx = 4/' -e 's/^ny = 20/ny = 4/' "$tmp/case.toml" > "$tmp/cases/scene.toml"
printf '\n[[variants]]\nname = "c"\nset = []\n' >> "$tmp/cases/scene.toml"
sed -i 's/^formulation = "direct"/formulation = "direct"\nsuite_formulations = ["direct"]/' "$tmp/cases/scene.toml"
"$rpfem" suite --cases "$tmp/cases" --out "$tmp/s" --jobs 1 --no-report --quiet > "$tmp/s.log" 2>&1; rc=$?
check "a suite with variants (exit $rc)" '[ $rc -eq 0 ] && [ -e "$tmp/s/scene/direct/b/result.h5" ] && [ -e "$tmp/s/scene/direct/c/result.h5" ]'
"$rpfem" suite --cases "$tmp/cases" --out "$tmp/s" --jobs 1 --no-report > "$tmp/s1b.log" 2>&1; rc=$?
check "the suite again without --force or --resume: refused (exit $rc)" \
  '[ $rc -eq 2 ] && grep -q "not empty.*--resume" "$tmp/s1b.log"'
touch -d "2000-01-01" "$tmp/s/scene/direct/result.h5"
"$rpfem" suite --cases "$tmp/cases" --out "$tmp/s" --jobs 1 --no-report --no-variants --resume > "$tmp/s2.log" 2>&1; rc=$?
check "the suite again with --no-variants --resume (exit $rc): no variant folders, the finished run kept" \
  '[ $rc -eq 0 ] && [ ! -e "$tmp/s/scene/direct/b" ] && [ ! -e "$tmp/s/scene/direct/c" ] && [ -e "$tmp/s/scene/direct/result.h5" ] && grep -q "1 finished before, kept" "$tmp/s2.log" && [ -n "$(find "$tmp/s/scene/direct/result.h5" ! -newermt 2001-01-01)" ]'
"$rpfem" suite --cases "$tmp/cases" --out "$tmp/s" --jobs 1 --no-report --no-variants --resume \
  --set stepping.end_stroke=0.1 > "$tmp/s3.log" 2>&1; rc=$?
check "--resume with another --set reruns it (exit $rc)" \
  '[ $rc -eq 0 ] && ! grep -q "finished before" "$tmp/s3.log" && [ -n "$(find "$tmp/s/scene/direct/result.h5" -newermt 2001-01-01)" ]'
# --force on two workers: the scene's run and its variants' (folders inside
# its folder) at the same time each finish; a report's figures go, a user's
# file stays.
mkdir -p "$tmp/s/report_files"; touch "$tmp/s/report_files/f.png"; echo keep > "$tmp/s/notes.txt"
"$rpfem" suite --cases "$tmp/cases" --out "$tmp/s" --jobs 2 --no-report --force --quiet > "$tmp/s4.log" 2>&1; rc=$?
check "the suite with --force on two workers (exit $rc): every run again and finished, the variants back" \
  '[ $rc -eq 0 ] && for d in "" b c; do grep -q "\"status\" : \"finished\"" "$tmp/s/scene/direct/$d/summary.json" || exit 1; done'
check "the report's figures gone, the user's file kept" '[ ! -e "$tmp/s/report_files" ] && [ -e "$tmp/s/notes.txt" ]'
[ $fail -eq 0 ] || { tail -n 5 "$tmp"/*.log; exit 1; }
echo "ok: output folders"
