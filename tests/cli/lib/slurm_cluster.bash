# Sourced by the command-line tests that need a Slurm cluster: starts the
# local test cluster (scripts/slurm-local) in $tmp/slurm, stopped when the
# test exits; skips the test (exit 77, saying why) where it cannot be had:
# not root, or Slurm's Debian packages cannot be installed. Needs $src and
# $tmp; leaves SLURM_CONF exported.
export RPFEM_SLURM_DIR=$tmp/slurm
cleanup() { "$src/scripts/slurm-local" stop > /dev/null 2>&1; rm -rf "$tmp"; }
trap cleanup EXIT
[ "$(id -u)" -eq 0 ] || { echo "SKIPPED: scripts/slurm-local needs root"; exit 77; }
if ! "$src/scripts/slurm-local" start > "$tmp/start.log" 2>&1; then
  if ! command -v slurmctld > /dev/null; then
    echo "SKIPPED: Slurm's Debian packages cannot be installed here"; cat "$tmp/start.log"; exit 77
  fi
  echo "FAIL: the cluster did not start"; cat "$tmp/start.log"; exit 1
fi
cat "$tmp/start.log"
eval "$("$src/scripts/slurm-local" env)"
