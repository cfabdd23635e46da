# Sourced by the command-line tests: check NAME CONDITION prints ok/FAIL
# for a shell condition and remembers a failure in $fail.
fail=0
check() { if eval "$2"; then echo "ok   $1"; else echo "FAIL $1"; fail=1; fi; }
