#!/usr/bin/env bash
# A Slurm array task's runs in one process (src/app/slurm_task.hpp), and
# --runs-per-task's automatic choice (src/app/run_engine.cpp,
# choose_runs_per_task), on the local test cluster (scripts/slurm-local):
# - without --runs-per-task, the cheapest run goes first as a task of its
#   own and its time chooses N: the line "runs per task: N (auto: ...)",
#   the rest submitted as tasks of up to N runs, sweep.json's engine record
#   the same N and rule, every run finished with its exit code;
# - a bundled task's runs go through one forked worker (the same process
#   at the first run and the third), and a worker killed in the middle of
#   a run (the third or, where the kill comes late, a later one) costs that
#   run alone: exit 137 in its folder and the table, the task's other runs
#   finished (the later ones on a new worker), the sweep exit 3.
# Skipped (exit 77) where the cluster cannot be had.
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d)
. "$(dirname "$0")/lib/slurm_cluster.bash"
. "$(dirname "$0")/lib/check.bash"
cat > "$tmp/auto.toml" <<TOML
[study]
description = "upsetting, one or two steps"
case = "upsetting_frictionless_axisym"
load = "top_platen.Fy"
set = ["stepping.end_stroke=0.05", "bodies.billet.mesh.nx=2", "bodies.billet.mesh.ny=2"]
[[study.axis]]
key = "solver.alpha"
values = [1e2, 1e3, 1e4, 1e5]
[[study.axis]]
key = "stepping.stroke_increment"
values = [0.03, 0.04, 0.05]
TOML
"$rpfem" sweep "$tmp/auto.toml" --cases "$src/cases" --out "$tmp/auto" --engine slurm > "$tmp/auto.log" 2>&1; rc=$?
cat "$tmp/auto.log"
n=$(grep -o "runs per task: [0-9]* (auto: the probe run" "$tmp/auto.log" | awk '{print $4}')
check "auto: exit 0, N chosen after the probe run ($n)" '[ $rc -eq 0 ] && [ -n "$n" ] && [ "$n" -ge 1 ]'
check "auto: the probe a task of one run, the other 11 runs as ceil(11 / N) tasks of up to N" \
  '[ "$(grep -c "submitted job array [0-9]*: 1 tasks$" "$tmp/auto.log")" -ge 1 ] &&
   [ "$(grep -o "submitted job array [0-9]*: [0-9]* tasks" "$tmp/auto.log" | tail -1 | awk "{print \$5}")" -eq $(((11 + n - 1) / n)) ]'
check "auto: every run its own exit code 0" \
  '[ "$(cat "$tmp"/auto/runs/*/exit_code | awk "\$1 == 0" | wc -l)" -eq 12 ]'
/usr/bin/python3 - "$tmp/auto/sweep.json" "$n" <<'PY' || fail=1
import json, sys
e = json.load(open(sys.argv[1]))["engine"]
ok = e["name"] == "slurm" and e["runs_per_task"] == int(sys.argv[2]) and e["runs_per_task_rule"] == "auto"
ok &= e["probe_run_s"] > 0 and e["estimated_run_s"] >= e["probe_run_s"] and e["cpus"] >= 1
print("%s  sweep.json engine %s" % ("ok  " if ok else "FAIL", e))
sys.exit(0 if ok else 1)
PY
# Five runs of 80 steps on a 16 x 16 mesh (0.7 to 1 s each here) in one task; its
# worker killed in the third.
cat > "$tmp/crash.toml" <<TOML
[study]
description = "upsetting, 5 runs of 80 steps"
case = "upsetting_frictionless_axisym"
load = "top_platen.Fy"
set = ["stepping.end_stroke=0.4", "stepping.stroke_increment=0.005", "bodies.billet.mesh.nx=16", "bodies.billet.mesh.ny=16"]
[[study.axis]]
key = "solver.alpha"
values = [1e3, 2e3, 3e3, 4e3, 5e3]
TOML
"$rpfem" sweep "$tmp/crash.toml" --cases "$src/cases" --out "$tmp/crash" --engine slurm --runs-per-task 5 \
  > "$tmp/crash.log" 2>&1 &
sweep=$!
worker_of_task() { pgrep -P "$(pgrep -f "slurm-task $tmp/crash/slurm/runs.txt" | head -1)" 2>/dev/null | head -1; }
first=""; third=""
for _ in $(seq 3000); do
  kill -0 $sweep 2>/dev/null || break
  [ -z "$first" ] && [ -f "$tmp/crash/runs/000/history.csv" ] && first=$(worker_of_task)
  if [ -f "$tmp/crash/runs/002/history.csv" ] && [ "$(wc -l < "$tmp/crash/runs/002/history.csv")" -ge 5 ]; then
    third=$(worker_of_task); break
  fi
  sleep 0.02
done
[ -n "$third" ] && kill -KILL "$third"
wait $sweep; rc=$?
cat "$tmp/crash.log"
check "one worker process for the task's first three runs ($first, $third)" '[ -n "$first" ] && [ "$first" = "$third" ]'
check "sweep exits 3: a run stopped ($rc)" '[ $rc -eq 3 ]'
/usr/bin/python3 "$(dirname "$0")/lib/one_run_killed.py" "$tmp/crash" 5 2 --exit-code-file || fail=1
exit $fail
