# Sourced by the command-line tests: a check that cannot run on this
# machine (a tool missing, no root) fails, saying why, unless the
# environment sets RPFEM_ALLOW_SKIP=1; then it is skipped, saying why
# (docs/testing.md).
#   cannot_check REASON   one check of a test: "skipped: REASON", or
#                         "FAIL cannot run: REASON" and fail=1
#   cannot_test REASON    the whole test: exit 77 (ctest's skipped), or
#                         exit 1 with the reason
skip_allowed() { [ "${RPFEM_ALLOW_SKIP:-0}" = 1 ]; }
cannot_check() {
  if skip_allowed; then echo "skipped: $1 (RPFEM_ALLOW_SKIP=1)"
  else echo "FAIL cannot run: $1 (RPFEM_ALLOW_SKIP=1 skips it)"; fail=1; fi
}
cannot_test() {
  if skip_allowed; then echo "SKIPPED: $1 (RPFEM_ALLOW_SKIP=1)"; exit 77; fi
  echo "FAIL cannot run: $1 (RPFEM_ALLOW_SKIP=1 skips it)"; exit 1
}
