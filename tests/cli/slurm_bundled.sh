#!/usr/bin/env bash
# `rpfem sweep --engine slurm --runs-per-task N` on the local test cluster
# (scripts/slurm-local, MaxArraySize 3): 40 short runs as 5 tasks of 8
# runs (two arrays, 3 and 2 tasks), each run in its own folder with its
# own exit code, the table the local pool's in every result column; with
# 3 runs per task (14 tasks, the last of one run), runs that stop (exit 3)
# do not stop the later runs of their task and the table records them.
# Interrupted in the middle (SIGTERM), the arrays are cancelled and the
# same command with --resume submits only the runs that did not finish.
# Prints the bundled study's wall time (docs/cluster.md compares it with
# one run per task). Skipped (exit 77) where the cluster cannot be had.
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d)
export RPFEM_SLURM_MAX_ARRAY_SIZE=3
. "$(dirname "$0")/lib/slurm_cluster.bash"
. "$(dirname "$0")/lib/check.bash"
. "$(dirname "$0")/lib/same_table.bash"
study() {  # $1: a second axis, $2 its values, $3 more overrides
  cat <<TOML
[study]
description = "upsetting, bundled tasks"
case = "upsetting_frictionless_axisym"
load = "top_platen.Fy"
set = ["stepping.end_stroke=0.05", "bodies.billet.mesh.nx=2", "bodies.billet.mesh.ny=2"${3:-}]
[[study.axis]]
key = "solver.alpha"
values = [1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9]
[[study.axis]]
key = "$1"
values = [$2]
TOML
}
study stepping.stroke_increment "0.03, 0.035, 0.04, 0.045, 0.05" > "$tmp/study.toml"
# One Newton iteration and no step halving: the runs of the value 1 stop (exit 3).
study solver.max_iterations "20, 30, 1, 40, 50" ', "stepping.max_cuts=0"' > "$tmp/bad.toml"
"$rpfem" sweep "$tmp/study.toml" --out "$tmp/local" --jobs 2 --quiet; rc=$?
check "local sweep exits 0" '[ $rc -eq 0 ]'
t0=$(date +%s.%N)
"$rpfem" sweep "$tmp/study.toml" --out "$tmp/b8" --engine slurm --runs-per-task 8 > "$tmp/b8.log" 2>&1; rc=$?
t1=$(date +%s.%N)
check "bundled: exit 0" '[ $rc -eq 0 ]'
check "bundled: 40 runs as 5 tasks of 8, two arrays" 'grep -q "40 runs on Slurm: 40 submitted, 0 finished before" "$tmp/b8.log" &&
  [ "$(grep -c "submitted job array [0-9]*: [32] tasks of up to 8 runs" "$tmp/b8.log")" -eq 2 ]'
check "bundled: every run its own exit code" \
  '[ "$(cat "$tmp"/b8/runs/*/exit_code | awk "\$1 == 0" | wc -l)" -eq 40 ]'
check "bundled: 5 task logs" '[ "$(ls "$tmp"/b8/slurm/task-*.log | wc -l)" -eq 5 ]'
check "bundled: the local table in every result column" 'same_table "$tmp/local/sweep.csv" "$tmp/b8/sweep.csv"'
# A run that stops in the middle of a task: exit 3, the run's exit code 3
# in its folder and the table, its task's later runs finished.
# 3 runs per task: 14 tasks, the last of one run, in five arrays.
"$rpfem" sweep "$tmp/bad.toml" --out "$tmp/bad" --engine slurm --runs-per-task 3 > "$tmp/bad.log" 2>&1; rc=$?
bad_runs=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) { if ($i == "exit_code") e = i; if ($i == "finished") f = i } }
  NR > 1 && $e == 3 && $f == 0' "$tmp/bad/sweep.csv" | wc -l)
check "runs that stop in a task: exit 3, its 8 runs recorded exit 3, the 32 others finished" \
  '[ $rc -eq 3 ] && [ "$bad_runs" -eq 8 ] && [ "$(grep -c ": finished in" "$tmp/bad.log")" -eq 32 ] &&
   [ "$(grep -c "stopped, exit 3" "$tmp/bad.log")" -eq 8 ] &&
   [ "$(grep -o "submitted job array [0-9]*: [0-9]* tasks" "$tmp/bad.log" | awk "{s += \$5} END {print s}")" -eq 14 ]'
# Interrupted while its tasks run one at a time, then resumed.
"$rpfem" sweep "$tmp/study.toml" --out "$tmp/cut" --engine slurm --runs-per-task 8 --array-limit 1 > "$tmp/c1.log" 2>&1 &
pid=$!
for _ in $(seq 600); do [ "$(grep -c "finished in" "$tmp/c1.log")" -ge 10 ] && break; sleep 0.1; done
kill -TERM $pid; wait $pid; rc=$?
check "interrupted: exit 130, the arrays cancelled" '[ $rc -eq 130 ] && grep -q "cancelled Slurm job.*--resume" "$tmp/c1.log"'
sleep 1
"$rpfem" sweep "$tmp/study.toml" --out "$tmp/cut" --engine slurm --runs-per-task 8 --resume > "$tmp/c2.log" 2>&1; rc=$?
done_before=$(grep -o "[0-9]* finished before" "$tmp/c2.log" | cut -d' ' -f1)
submitted=$(grep -o "40 runs on Slurm: [0-9]* submitted" "$tmp/c2.log" | awk '{print $5}')
check "resumed: exit 0, only the unfinished submitted ($submitted; $done_before finished before)" \
  '[ $rc -eq 0 ] && [ "${done_before:-0}" -ge 10 ] && [ "$((done_before + submitted))" -eq 40 ]'
check "resumed: the local table" 'same_table "$tmp/local/sweep.csv" "$tmp/cut/sweep.csv"'
echo "measured: 40 runs on Slurm, 8 per task, $(awk "BEGIN { printf \"%.1f\", $t1 - $t0 }") s"
exit $fail
