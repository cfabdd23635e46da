#!/usr/bin/env bash
# The local pool's worker processes (src/app/run_worker.hpp): a study's
# runs go through a few forked workers, not a process each, and a worker
# killed in the middle of a run costs that run alone: its row says exit 137
# (SIGKILL) and not finished, every other run finishes (the next on a new
# worker), the sweep exits 3 (a run stopped), and no other run folder keeps
# a lock file (a worker releases each run's folder as the run ends).
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
. "$(dirname "$0")/lib/check.bash"
cat > "$tmp/study.toml" <<TOML
[study]
description = "upsetting, 12 runs of 40 steps"
case = "upsetting_frictionless_axisym"
load = "top_platen.Fy"
set = ["stepping.end_stroke=0.4", "stepping.stroke_increment=0.01", "bodies.billet.mesh.nx=4", "bodies.billet.mesh.ny=4"]
[[study.axis]]
key = "solver.alpha"
values = [1e3, 2e3, 3e3, 4e3, 5e3, 6e3, 7e3, 8e3, 9e3, 1e4, 2e4, 3e4]
TOML
"$rpfem" sweep "$tmp/study.toml" --cases "$src/cases" --out "$tmp/out" --jobs 1 --quiet > "$tmp/log" 2>&1 &
sweep=$!
# The worker in the middle of its fourth run or a later one: killed.
for _ in $(seq 600); do
  kill -0 $sweep 2>/dev/null || break
  [ -f "$tmp/out/runs/003/history.csv" ] && [ "$(wc -l < "$tmp/out/runs/003/history.csv")" -ge 5 ] && break
  sleep 0.05
done
workers=$(pgrep -P $sweep | wc -l)
worker=$(pgrep -P $sweep | head -1)
[ -n "$worker" ] && kill -KILL "$worker"
wait $sweep; rc=$?
cat "$tmp/log"
check "one worker process for the first four runs ($workers)" '[ "$workers" -eq 1 ]'
check "sweep exits 3: a run stopped ($rc)" '[ $rc -eq 3 ]'
/usr/bin/python3 "$(dirname "$0")/lib/one_run_killed.py" "$tmp/out" 12 3 || fail=1
killed=$(cat "$tmp/out/killed")
check "no lock file left but in the killed run's folder" \
  '[ -z "$(find "$tmp/out/runs" -name .rpfem.lock | grep -v "/$killed/")" ]'
exit $fail
