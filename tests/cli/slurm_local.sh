#!/usr/bin/env bash
# scripts/slurm-local: a single-node Slurm cluster starts as root without
# systemd, runs an 8-task job array (every task's output written), shows a
# failed task's state and exit code in `scontrol show job`, and stops by
# its pids (none left running). Where the cluster cannot be had (not root,
# or Debian's packages cannot be installed) it fails, saying why, unless
# RPFEM_ALLOW_SKIP=1 skips it (exit 77).
set -u
src=$2
tmp=$(mktemp -d)
. "$(dirname "$0")/lib/slurm_cluster.bash"
cat > "$tmp/task.sh" <<TASK
#!/bin/bash
echo "task \$SLURM_ARRAY_TASK_ID" > "$tmp/out_\$SLURM_ARRAY_TASK_ID"
TASK
printf '#!/bin/bash\nexit 3\n' > "$tmp/fail.sh"
array=$(sbatch --parsable --array=0-7 -o "$tmp/slurm-%A_%a.log" "$tmp/task.sh") || { echo "FAIL: sbatch"; exit 1; }
failed=$(sbatch --parsable -o /dev/null "$tmp/fail.sh") || { echo "FAIL: sbatch"; exit 1; }
for _ in $(seq 300); do
  [ -z "$(squeue -h -j "$array,$failed" 2>/dev/null)" ] && break
  sleep 0.2
done
[ -z "$(squeue -h -j "$array,$failed" 2>/dev/null)" ] || { echo "FAIL: jobs still queued after 60 s"; squeue; exit 1; }
for i in $(seq 0 7); do
  [ "$(cat "$tmp/out_$i" 2>/dev/null)" = "task $i" ] || { echo "FAIL: array task $i wrote nothing"; exit 1; }
done
scontrol show job "$failed" | grep -q "JobState=FAILED" && scontrol show job "$failed" | grep -q "ExitCode=3:0" \
  || { echo "FAIL: the failed job's state"; scontrol show job "$failed"; exit 1; }
pids=$(cat "$RPFEM_SLURM_DIR/pids")
"$src/scripts/slurm-local" stop || { echo "FAIL: stop"; exit 1; }
for p in $pids; do
  ! kill -0 "$p" 2>/dev/null || { echo "FAIL: daemon $p still running after stop"; exit 1; }
done
echo "ok: local Slurm cluster ran an 8-task array and a failing job, and stopped"
