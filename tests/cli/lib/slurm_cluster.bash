# Sourced by the command-line tests that need a Slurm cluster: starts the
# local test cluster (scripts/slurm-local) in $tmp/slurm, stopped when the
# test exits. Where it cannot be had (not root, or Slurm's Debian packages
# cannot be installed) the test fails, saying why, unless RPFEM_ALLOW_SKIP=1
# skips it (exit 77; skip.bash). Needs $src and $tmp; leaves SLURM_CONF
# exported.
. "$(dirname "${BASH_SOURCE[0]}")/skip.bash"
export RPFEM_SLURM_DIR=$tmp/slurm
cleanup() { "$src/scripts/slurm-local" stop > /dev/null 2>&1; rm -rf "$tmp"; }
trap cleanup EXIT
[ "$(id -u)" -eq 0 ] || cannot_test "scripts/slurm-local needs root"
if ! "$src/scripts/slurm-local" start > "$tmp/start.log" 2>&1; then
  if ! command -v slurmctld > /dev/null; then
    cat "$tmp/start.log"; cannot_test "Slurm's Debian packages cannot be installed here"
  fi
  echo "FAIL: the cluster did not start"; cat "$tmp/start.log"; exit 1
fi
cat "$tmp/start.log"
eval "$("$src/scripts/slurm-local" env)"
