#!/usr/bin/python3
"""A study in which one run's worker was killed (SIGKILL): sweep.csv has
ROWS rows, exactly one with exit code 137, at index FIRST or later, not
finished (with --exit-code-file, as the Slurm engine writes, its folder's
exit_code 137 too); every other run exit 0 and finished. Prints ok/FAIL,
writes the killed run's folder to DIR/killed, exits 1 on failure.
Usage: one_run_killed.py DIR ROWS FIRST [--exit-code-file]"""
import csv
import sys

out, n, first = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
rows = list(csv.DictReader(open(out + "/sweep.csv")))
codes = [int(float(r["exit_code"])) for r in rows]
finished = [r["finished"] for r in rows]
killed = [i for i, c in enumerate(codes) if c == 137]
ok = len(rows) == n and len(killed) == 1 and killed[0] >= first and finished[killed[0]] == "0"
ok &= codes.count(0) == n - 1 and finished.count("1") == n - 1
if "--exit-code-file" in sys.argv[4:]:
    ok &= bool(killed) and open(out + "/" + rows[killed[0]]["dir"] + "/exit_code").read().split()[0] == "137"
print("%s  exit codes %s" % ("ok  " if ok else "FAIL", codes))
open(out + "/killed", "w").write(rows[killed[0]]["dir"] if killed else "")
sys.exit(0 if ok else 1)
