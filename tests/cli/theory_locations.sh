#!/usr/bin/env bash
# Requirement: every code location docs/theory.md names as `path:function`
# (its index and its text) exists: the file, relative to the source tree,
# and the function's name followed by "(" in it (a qualified name such as
# `SsnStepSolver::solve` as written). Fails naming each location that no
# longer holds, and when the manual names fewer than 30 locations (the
# form of the references changed and none would be checked).
set -u
src=$2
/usr/bin/python3 - "$src" <<'EOF'
import os
import re
import sys

src = sys.argv[1]
text = open(os.path.join(src, "docs", "theory.md"), encoding="utf-8").read()
locations = sorted(set(re.findall(r"`((?:src|formulations|verification)/[\w./-]+\.(?:cpp|hpp)):([\w:~]+)`", text)))
bad = []
for path, name in locations:
    full = os.path.join(src, path)
    if not os.path.isfile(full):
        bad.append("%s:%s: no file %s" % (path, name, path))
        continue
    code = open(full, encoding="utf-8").read()
    if not re.search(r"(?<![\w:])" + re.escape(name) + r"\s*\(", code):
        bad.append("%s:%s: no function %s( in %s" % (path, name, name, path))
for b in bad:
    print("FAIL: docs/theory.md names " + b)
if len(locations) < 30:
    print("FAIL: docs/theory.md names %d code locations as `path:function`; expected at least 30" % len(locations))
    sys.exit(1)
if bad:
    sys.exit(1)
print("ok: %d code locations of docs/theory.md exist" % len(locations))
EOF
