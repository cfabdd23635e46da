# Sourced by the command-line tests that compare two sweeps' tables:
# same_table A.csv B.csv succeeds when both have the same rows, equal in
# every column but the wall times.
same_table() {
  /usr/bin/python3 - "$1" "$2" <<'PY'
import csv, sys
a, b = (list(csv.DictReader(open(p))) for p in sys.argv[1:3])
assert len(a) == len(b) > 0, (len(a), len(b))
for ra, rb in zip(a, b):
    for k in ra:
        if k.endswith("_s") or "second" in k:  # wall times
            continue
        assert ra[k] == rb[k], (k, ra[k], rb[k])
PY
}
