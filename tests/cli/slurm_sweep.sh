#!/usr/bin/env bash
# `rpfem sweep --engine slurm` on the local test cluster (scripts/slurm-local):
# a 9-run study (upsetting, penalty at three betas by three meshes; two
# arrays, the cluster's MaxArraySize set to 5) gives
# the same table as the local pool in every result column (wall times
# aside); run again on its folder, it submits nothing (every run finished);
# with a run's summary removed, only that run; interrupted, it cancels the
# array and the same command resumes it. A run that stops (exit 3) and
# one Slurm kills at its time limit are reported, and the table records
# them as stopped, and the progress lines follow a running task's step and
# stroke. The suite on Slurm builds the local suite's study table and its
# report; a calibration on Slurm makes the local one's evaluations. Where
# the cluster cannot be had it fails, unless RPFEM_ALLOW_SKIP=1 skips it.
# The sweeps run a run per task (--runs-per-task 1); bundled tasks and the
# automatic choice: slurm_bundled.sh, slurm_task_runs.sh.
set -u
rpfem=$1; src=$2
tmp=$(mktemp -d)
export RPFEM_SLURM_MAX_ARRAY_SIZE=5  # the 9-run grid as two arrays
. "$(dirname "$0")/lib/slurm_cluster.bash"
. "$(dirname "$0")/lib/check.bash"
. "$(dirname "$0")/lib/same_table.bash"
cat > "$tmp/study.toml" <<TOML
[study]
description = "upsetting, penalty beta by mesh"
case = "upsetting_dies_frictionless_axisym"
formulation = "penalty"
load = "top_die.Fy"
set = ["stepping.end_stroke=0.3"]
[[study.axis]]
key = "formulations.penalty.beta_factor"
values = [0.01, 1.0, 100.0]
[[study.axis]]
key = "run.mesh_factor"
values = [0.2, 0.25, 0.3]
TOML
# A run Slurm kills at its time limit (its least, a minute, and up to half
# a minute more for slurmctld to notice) is submitted first and runs beside
# the checks below: niced (the cluster passes the submitter's nice value
# on), it takes the CPU time the other tests leave, and the test cluster
# lets two jobs share a CPU, so the arrays below still run two at a time.
cat > "$tmp/slow.toml" <<TOML
[study]
description = "slow"
case = "upsetting_dies_frictionless_axisym"
formulation = "ipopt"
load = "top_die.Fy"
set = ["stepping.end_stroke=5", "stepping.stroke_increment=0.0002"]
[[study.axis]]
key = "run.mesh_factor"
values = [1.0]
TOML
nice -n 19 "$rpfem" sweep "$tmp/slow.toml" --out "$tmp/slow" --engine slurm --time 0:02 > "$tmp/t.log" 2>&1 &
slow_pid=$!
trap 'kill $slow_pid 2>/dev/null; cleanup' EXIT
t0=$(date +%s.%N)
"$rpfem" sweep "$tmp/study.toml" --out "$tmp/local" --jobs 2 --quiet; rc=$?
t1=$(date +%s.%N)
check "local sweep exits 0" '[ $rc -eq 0 ]'
"$rpfem" sweep "$tmp/study.toml" --out "$tmp/slurm_out" --engine slurm --runs-per-task 1 > "$tmp/s1.log" 2>&1; rc=$?
t2=$(date +%s.%N)
check "slurm sweep exits 0" '[ $rc -eq 0 ]'
check "nine tasks submitted" 'grep -q "9 runs on Slurm: 9 submitted, 0 finished before" "$tmp/s1.log"'
check "as two arrays (MaxArraySize 5)" '[ "$(grep -c "submitted job array .*: [54] tasks" "$tmp/s1.log")" -eq 2 ]'
check "commands.txt holds the runs" '[ "$(grep -c " run " "$tmp/slurm_out/slurm/commands.txt")" -eq 9 ]'
check "slurm and local tables agree in every result column" 'same_table "$tmp/local/sweep.csv" "$tmp/slurm_out/sweep.csv"'
echo "measured: local $(awk "BEGIN { print $t1 - $t0 }") s, slurm $(awk "BEGIN { print $t2 - $t1 }") s for 9 runs"
# Again on the same folder with --resume: nothing to submit; with one run's
# summary gone, that run only.
"$rpfem" sweep "$tmp/study.toml" --out "$tmp/slurm_out" --engine slurm --runs-per-task 1 --resume > "$tmp/s2.log" 2>&1
check "a finished study submits nothing" 'grep -q "9 runs on Slurm: 0 submitted, 9 finished before" "$tmp/s2.log"'
victim=$tmp/slurm_out/runs/004
rm "$victim/summary.json"
"$rpfem" sweep "$tmp/study.toml" --out "$tmp/slurm_out" --engine slurm --runs-per-task 1 --resume > "$tmp/s3.log" 2>&1
check "only the unfinished run resubmitted" 'grep -q "9 runs on Slurm: 1 submitted, 8 finished before" "$tmp/s3.log"'
# Interrupted (SIGTERM, as Ctrl-C) while the array runs one task at a time:
# the array is cancelled, exit 130 (saying --resume resumes); the same
# command with --resume then submits only the runs that did not finish, and
# the table is the local one.
"$rpfem" sweep "$tmp/study.toml" --out "$tmp/cut" --engine slurm --runs-per-task 1 --array-limit 1 > "$tmp/c1.log" 2>&1 &
pid=$!
for _ in $(seq 100); do [ "$(grep -c "finished in" "$tmp/c1.log")" -ge 3 ] && break; sleep 0.1; done
kill -TERM $pid; wait $pid; rc=$?
check "interrupted: exit 130, the array cancelled" '[ $rc -eq 130 ] && grep -q "cancelled Slurm job.*--resume" "$tmp/c1.log"'
sleep 1
cut_ids=$(grep -o "submitted job array [0-9]*" "$tmp/c1.log" | awk '{print $4}' | paste -sd,)
check "nothing of its arrays left in the queue" '[ -n "$cut_ids" ] && [ -z "$(squeue -h -t PD,R,CG -j "$cut_ids" 2>/dev/null)" ]'
"$rpfem" sweep "$tmp/study.toml" --out "$tmp/cut" --engine slurm --runs-per-task 1 --resume > "$tmp/c2.log" 2>&1; rc=$?
done_before=$(grep -o "[0-9]* finished before" "$tmp/c2.log" | cut -d' ' -f1)
check "resumed: exit 0, only the unfinished submitted" '[ $rc -eq 0 ] && [ "${done_before:-0}" -ge 3 ] && [ "$done_before" -lt 9 ]'
check "resumed table as the local one" 'same_table "$tmp/local/sweep.csv" "$tmp/cut/sweep.csv"'
echo "measured: the interrupted study resumed with $done_before of 9 runs finished before"
# The suite on Slurm: one scene under each formulation and a study, the
# study's table as the local suite's and the report built.
for e in local slurm; do
  "$rpfem" suite --out "$tmp/suite_$e" --engine $e --jobs 2 --quick --scene upsetting_dies_frictionless_axisym \
    --study step_convergence_test2 --no-variants --set stepping.end_stroke=0.5 > "$tmp/suite_$e.log" 2>&1; rc=$?
  check "suite --engine $e exits 0 and builds its report" '[ $rc -eq 0 ] && [ -s "$tmp/suite_$e/report.html" ]'
done
check "the suite's study table the same on Slurm" \
  'same_table "$tmp/suite_local/studies/step_convergence_test2/sweep.csv" "$tmp/suite_slurm/studies/step_convergence_test2/sweep.csv"'
# A folder the compute nodes do not see: the probe task succeeds, but its
# file does not appear here (an srun that runs elsewhere). Bad input,
# before anything is submitted.
mkdir -p "$tmp/elsewhere"; printf '#!/bin/sh\nexit 0\n' > "$tmp/elsewhere/srun"; chmod +x "$tmp/elsewhere/srun"
PATH="$tmp/elsewhere:$PATH" "$rpfem" sweep "$tmp/study.toml" --out "$tmp/unshared" --engine slurm --runs-per-task 1 > "$tmp/u.log" 2>&1; rc=$?
check "an unshared folder: exit 2, said so, nothing submitted" \
  '[ $rc -eq 2 ] && grep -q "not writable from a compute node" "$tmp/u.log" && ! grep -q "submitted job array" "$tmp/u.log"'
# A run that stops (a step limit) and one killed at its time limit.
cat > "$tmp/bad.toml" <<TOML
[study]
description = "stops"
case = "upsetting_dies_frictionless_axisym"
formulation = "penalty"
load = "top_die.Fy"
set = ["stepping.end_stroke=0.3", "run.mesh_factor=0.25", "solver.max_iterations=1", "stepping.max_cuts=0"]
[[study.axis]]
key = "formulations.penalty.beta_factor"
values = [1.0]
TOML
"$rpfem" sweep "$tmp/bad.toml" --out "$tmp/bad" --engine slurm --runs-per-task 1 > "$tmp/b.log" 2>&1; rc=$?
check "a stopped run: exit 3, its exit code reported" '[ $rc -eq 3 ] && grep -q "stopped, exit 3" "$tmp/b.log"'
# A calibration on Slurm: one one-task array per evaluation, the same
# evaluations (values and penetrations) as on this machine.
cal=(calibrate "$src/cases/upsetting_dies_frictionless_axisym.toml" --auto-beta 1e-3 --max-evals 6
     --set stepping.end_stroke=0.3 --set run.mesh_factor=0.25 --quiet)
"$rpfem" "${cal[@]}" --out "$tmp/cal_local"; rc_local=$?
"$rpfem" "${cal[@]}" --out "$tmp/cal_slurm" --engine slurm; rc=$?
check "calibrate --engine slurm exits as the local one" '[ $rc -eq $rc_local ] && [ -s "$tmp/cal_slurm/evaluations.csv" ]'
check "calibrate: the same evaluations on Slurm" \
  '[ "$(cut -d, -f1-3,5 "$tmp/cal_local/evaluations.csv")" = "$(cut -d, -f1-3,5 "$tmp/cal_slurm/evaluations.csv")" ]'
check "calibrate: its runs went through Slurm" '[ -s "$tmp/cal_slurm/slurm/commands.txt" ]'
wait $slow_pid; rc=$?
check "a run out of time: its Slurm state reported" '[ $rc -eq 3 ] && grep -q "Slurm TIMEOUT" "$tmp/t.log"'
check "the table records it stopped" 'grep -q ",0," "$tmp/slow/sweep.csv"'
check "a running task's step and stroke in the progress lines" 'grep -q "running .*: step [0-9]* of .*, stroke " "$tmp/t.log"'
[ $fail -eq 0 ] || { cat "$tmp/s1.log" "$tmp/b.log" "$tmp/t.log"; exit 1; }
echo "ok: slurm engine"
