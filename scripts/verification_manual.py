#!/usr/bin/python3
"""Writes docs/verification.md, the verification manual, from what the
checks themselves carry:

- the acceptance tests (tests/acceptance/*.cpp): a block of `//~` lines
  right above each TEST or TEST_P, TOML once the `//~ ` is taken off:
      feature = "upsetting"            (a key of tests/acceptance/features.toml)
      source = "..."                   (the reference: paper eq./figure, book, paper with section)
      [[check]]                        (one per tolerance the test asserts)
      what = "..."                     (the quantity, where and when)
      compares = "exact solution"      (one of COMPARES below)
      tolerance = "5e-3 (relative)"    (every number in it must occur in the test's file)
      why = "..."                      (why that tolerance: the measured value, the error it allows)
      source = "..."                   (optional: this check's own reference)
  A helper function that asserts for several tests carries its own block
  (`helper = "NAME"` and its [[check]]s) right above its definition; a
  test lists it in `uses = ["NAME"]`, and its checks come first.
- the suite's checks (verification/checks.toml, evaluated by `rpfem verify`):
  their `verifies`, `against`, `source` and `why`;
- the extreme scenes' expectations (cases/extremes/*.toml, their [expect]
  tables, each bound with its `# measured ...` comment), listed under the
  acceptance test that checks them (Extremes.EndAsTheirCasesSay);
- the features (tests/acceptance/features.toml): each section's title,
  introduction and the suite checks' scenes it holds, and the references.

    /usr/bin/python3 scripts/verification_manual.py           # writes docs/verification.md
    /usr/bin/python3 scripts/verification_manual.py --check   # exit 1 if it differs from the committed file

Bad metadata (a test without a block, an unknown feature or kind, a
tolerance whose number is not in the test's file, a suite check without its
documentation) stops it with exit code 2, naming the file and the test."""
import glob
import os
import re
import sys
import tomllib

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
ACCEPTANCE = os.path.join(ROOT, "tests", "acceptance")
FEATURES = os.path.join(ACCEPTANCE, "features.toml")
CHECKS = os.path.join(ROOT, "verification", "checks.toml")
EXTREMES = os.path.join(ROOT, "cases", "extremes")
OUTPUT = os.path.join(ROOT, "docs", "verification.md")

# What a check compares against (the kind of reference).
COMPARES = {
    "exact solution": "a closed-form solution of the same problem",
    "manufactured solution": "a solution made up and imposed through body forces and boundary values",
    "literature": "a published approximate solution or finding (slab method, upper bound, the paper's results)",
    "another formulation": "the same scene under another contact enforcement or discretization",
    "Kuhn-Tucker conditions": "the contact and friction conditions' residuals, from the run's own history",
    "conservation": "a balance the physics keeps: volume, action and reaction, nodal forces",
    "the same scene run otherwise": "one scene run with an option, a thread count or a criterion changed",
    "expected behaviour": "what must happen: a run that finishes, stops cleanly, says why, or moves one way",
}
NUMBER = re.compile(r"(?<![\w.])\d+(?:\.\d+)?(?:e[-+]?\d+)?(?![\w.])")
TEST_LINE = re.compile(r"^TEST(_P)?\((\w+),\s*(\w+)\)")


class MetadataError(Exception):
    pass


def fail(where, message):
    raise MetadataError("%s: %s" % (os.path.relpath(where, ROOT), message))


def read_tests(path):
    """The acceptance tests of one file: a dict per TEST with its metadata."""
    with open(path) as f:
        lines = f.read().split("\n")
    # The code alone, without comments (a tolerance must be what the test asserts, not what a comment says).
    text = "\n".join(re.sub(r"//.*", "", line) for line in lines)
    tests, helpers, block, block_line = [], {}, [], 0
    for number, line in enumerate(lines, 1):
        if line.startswith("//~"):
            if not block:
                block_line = number
            block.append(line[4:] if line.startswith("//~ ") else line[3:])
            continue
        m = TEST_LINE.match(line)
        if not m and not block:
            continue
        where = "%s:%d" % (os.path.relpath(path, ROOT), number)
        if m:
            where += " (%s.%s)" % (m.group(2), m.group(3))
            if not block:
                raise MetadataError("%s: no //~ metadata block above the test" % where)
        try:
            meta = tomllib.loads("\n".join(block))
        except tomllib.TOMLDecodeError as e:
            raise MetadataError("%s: the //~ block does not read as TOML: %s" % (where, e))
        block = []
        if not m:
            if "helper" not in meta:
                raise MetadataError("%s:%d: a //~ block above neither a TEST, a TEST_P nor a helper "
                                    "(helper = \"NAME\")" % (os.path.relpath(path, ROOT), block_line))
            check_checks(meta, where, text, {"helper", "check"})
            helpers[meta["helper"]] = meta["check"]
            continue
        check_metadata(meta, where, text)
        own = meta["check"]
        meta["check"] = []
        for h in meta.get("uses", []):
            if h not in helpers:
                raise MetadataError("%s: uses '%s': no helper block of that name above it in the file" % (where, h))
            meta["check"] += helpers[h]
        meta["check"] += own
        meta.update(name="%s.%s" % (m.group(2), m.group(3)), parameterized=bool(m.group(1)),
                    file=os.path.relpath(path, ROOT))
        tests.append(meta)
    if block:
        raise MetadataError("%s:%d: a //~ block at the end of the file" % (os.path.relpath(path, ROOT), block_line))
    return tests


def check_metadata(meta, where, text):
    for key in ("feature", "source"):
        if key not in meta:
            raise MetadataError("%s: no '%s' in its //~ block" % (where, key))
    if not meta.get("check") and not meta.get("uses"):
        raise MetadataError("%s: its //~ block has no [[check]] and uses no helper" % where)
    meta.setdefault("check", [])
    check_checks(meta, where, text, {"feature", "source", "check", "scene", "uses"})


def check_checks(meta, where, text, keys):
    unknown = set(meta) - keys
    if unknown:
        raise MetadataError("%s: unknown keys %s (expected %s)" % (where, sorted(unknown), ", ".join(sorted(keys))))
    for i, c in enumerate(meta.get("check", [])):
        for key in ("what", "compares", "tolerance", "why"):
            if not str(c.get(key, "")).strip():
                raise MetadataError("%s: check %d has no '%s'" % (where, i + 1, key))
        unknown = set(c) - {"what", "compares", "tolerance", "why", "source"}
        if unknown:
            raise MetadataError("%s: check %d: unknown keys %s" % (where, i + 1, sorted(unknown)))
        if c["compares"] not in COMPARES:
            raise MetadataError("%s: check %d: compares = '%s', expected one of: %s"
                                % (where, i + 1, c["compares"], ", ".join(COMPARES)))
        # The tolerance stays true: each of its numbers is in the test's file.
        for n in NUMBER.findall(c["tolerance"]):
            if not re.search(r"(?<![\w.])%s[uUlLfF]?(?![\w])" % re.escape(n), text):
                raise MetadataError("%s: check %d: tolerance '%s': %s does not occur in the test's file"
                                    % (where, i + 1, c["tolerance"], n))


def read_suite_checks():
    with open(CHECKS, "rb") as f:
        checks = tomllib.load(f)["check"]
    for i, c in enumerate(checks):
        for key in ("verifies", "against", "source") + (("why",) if c["metric"] != "finished" else ()):
            if not str(c.get(key, "")).strip():
                fail(CHECKS, "check %d (%s, %s, %s) has no '%s'" % (i + 1, c["scene"], c["formulation"], c["metric"], key))
    return checks


def read_extreme(path):
    """An extreme case's description (its first comment block) and its
    expectations as table rows: run, expected, bounds, the bound's comment."""
    lines = open(path).read().split("\n")
    description = []
    for line in lines:
        if not line.startswith("#"):
            break
        description.append(line[1:].strip())
    rows, run, cur, in_variant = [], "the case", None, False

    def flush():
        if cur is None:
            return
        note = "; ".join(cur.pop("#", []))
        if cur.get("kind") == "outcome":
            expected = "outcome " + cur.get("outcome", "?").strip('"')
            for key in ("reason_contains", "warnings"):
                if key in cur:
                    expected += ", %s %s" % (key.replace("_", " "), cur[key])
            rows.append([run, expected, "-", note or "-"])
        else:
            what = cur.get("what", "?").strip('"')
            subject = cur.get("column", cur.get("load", "")).strip('"')
            ref = ", ".join("%s %s" % (k, cur[k].strip('"')) for k in ("reference_case", "reference_formulation",
                                                                        "reference_set") if k in cur)
            bounds = ", ".join(("%s %s" % (op, cur[k])) for k, op in (("min", ">="), ("max", "<=")) if k in cur)
            rows.append([run, "%s %s%s" % (what, subject, " against " + ref if ref else ""), bounds, note or "-"])

    for line in lines:
        s = line.strip()
        if s.startswith("["):
            flush()
            cur = None
            in_variant = s == "[[variants]]"
            if s in ("[expect]", "[variants.expect]"):
                cur = {"kind": "outcome"}
            elif s in ("[[expect.measure]]", "[[variants.expect.measure]]"):
                cur = {"kind": "measure"}
        elif in_variant and s.startswith("name ="):
            run = "variant " + s.split("=", 1)[1].split("#")[0].strip().strip('"')
        elif cur is not None and "=" in s and not s.startswith("#"):
            key, rest = s.split("=", 1)
            value, _, comment = rest.partition("#")
            cur[key.strip()] = value.strip()
            if comment.strip():
                cur.setdefault("#", []).append(comment.strip())
    flush()
    return " ".join(description), rows


def suite_check_feature(order, c):
    """The section of a suite check: the first listing a word of its
    formulation or variant (a higher `suite_priority` first), else the one
    listing its scene."""
    run = c["formulation"] + "/" + c.get("variant", "")
    for f in sorted(order, key=lambda f: -f.get("suite_priority", 0)):
        if any(w in run for w in f.get("formulations", [])):
            return f["key"]
    for f in order:
        if c["scene"] in f.get("scenes", []):
            return f["key"]
    fail(FEATURES, "no feature holds the suite check (%s, %s): list its scene or formulation" % (c["scene"], run))


def suite_check_label(c):
    """The check as `rpfem verify` names it: scene, formulation, metric."""
    run = c["formulation"] + (" / " + c["variant"] if c.get("variant") else "")
    metric = c["metric"]
    if metric == "load_difference":
        ref = c.get("reference_scene", c["scene"])
        metric += " vs %s%s%s (%s)" % ("" if ref == c["scene"] else ref + " ", c["reference"],
                                       " / " + c["reference_variant"] if c.get("reference_variant") else "",
                                       c["load"] if c.get("reference_load", c["load"]) == c["load"]
                                       else c["load"] + " against " + c["reference_load"])
        if c.get("from"):
            metric += ", from %g mm" % c["from"]
        if c.get("stroke_tolerance"):
            metric += ", stroke band %g mm" % c["stroke_tolerance"]
    elif metric == "load_jump":
        metric += " " + c["load"]
    elif metric == "history_max":
        metric += " " + c["column"] + (" (floor: %s)" % c["floor"] if c.get("floor") else "")
    return run, metric


def tolerance_text(c):
    return "-" if c["metric"] == "finished" else "%g" % c["tolerance"]


def cell(s):
    return str(s).replace("|", "\\|").replace("\n", " ")


def table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(cell(x) for x in r) + " |" for r in rows]
    return "\n".join(out) + "\n"


def render(features, tests, checks, extremes):
    order = features["feature"]
    keys = [f["key"] for f in order]
    for t in tests:
        if t["feature"] not in keys:
            raise MetadataError("%s (%s): feature '%s' is not in %s (%s)"
                                % (t["file"], t["name"], t["feature"], os.path.relpath(FEATURES, ROOT), ", ".join(keys)))
    check_feature = [suite_check_feature(order, c) for c in checks]
    n_checks = sum(len(t["check"]) for t in tests)
    out = [features["intro"].strip().format(tests=len(tests), checks=n_checks, suite_checks=len(checks),
                                            extremes=len(extremes),
                                            expectations=sum(len(r) for _, (_, r) in extremes)), ""]
    out.append("## What a check compares against\n")
    out.append(table(["kind", "meaning"], [[k, v] for k, v in COMPARES.items()]))
    out.append("## Contents\n")
    for f in order:
        nt = sum(1 for t in tests if t["feature"] == f["key"])
        ns = check_feature.count(f["key"])
        out.append("- [%s](#%s): %d acceptance tests, %d suite checks" % (f["title"], f["key"], nt, ns))
    out.append("- [References](#references)\n")
    for f in order:
        out.append('<a id="%s"></a>\n\n## %s\n' % (f["key"], f["title"]))
        out.append(f["intro"].strip() + "\n")
        for t in (t for t in tests if t["feature"] == f["key"]):
            out.append("### %s\n" % t["name"])
            out.append("`%s`%s. Reference: %s.%s\n" % (
                t["file"], ", parameterized (one ctest entry per parameter)" if t["parameterized"] else "",
                t["source"].rstrip("."), (" Scene: " + t["scene"] + ".") if t.get("scene") else ""))
            rows = [[c["what"] + (" (" + c["source"] + ")" if c.get("source") else ""), c["compares"],
                     c["tolerance"], c["why"]] for c in t["check"]]
            out.append(table(["checked", "compares against", "tolerance", "why this tolerance"], rows))
            if t["name"] == "Extremes.EndAsTheirCasesSay":
                for name, (description, erows) in extremes:
                    out.append("#### %s\n\n`cases/extremes/%s.toml`: %s\n" % (name, name, description))
                    out.append(table(["run", "expected", "bounds", "why (the case's comment)"], erows))
        mine = [c for c, k in zip(checks, check_feature) if k == f["key"]]
        if mine:
            out.append("### Suite checks (`rpfem verify`, verification/checks.toml)\n")
            rows = []
            for c in mine:
                run, metric = suite_check_label(c)
                rows.append([c["scene"], run, metric, tolerance_text(c), c["verifies"], c["against"], c["source"],
                             c.get("why", "-")])
            out.append(table(["scene", "formulation", "metric", "tolerance", "verifies", "against", "source",
                              "why this tolerance"], rows))
    out.append('<a id="references"></a>\n\n## References\n')
    out += ["- %s: %s" % (k, v) for k, v in sorted(features["references"].items())]
    return "\n".join(out).rstrip() + "\n"


def generate():
    with open(FEATURES, "rb") as f:
        features = tomllib.load(f)
    tests = []
    for path in sorted(glob.glob(os.path.join(ACCEPTANCE, "*.cpp"))):
        tests += read_tests(path)
    extremes = [(os.path.splitext(os.path.basename(p))[0], read_extreme(p))
                for p in sorted(glob.glob(os.path.join(EXTREMES, "*.toml")))]
    return render(features, tests, read_suite_checks(), extremes), tests


def main(argv):
    try:
        text, _ = generate()
    except (MetadataError, OSError, tomllib.TOMLDecodeError) as e:
        print("verification_manual: %s" % e, file=sys.stderr)
        return 2
    if "--check" in argv:
        with open(OUTPUT) as f:
            if f.read() != text:
                print("verification_manual: %s differs from what the tests and checks say; run "
                      "/usr/bin/python3 scripts/verification_manual.py" % os.path.relpath(OUTPUT, ROOT), file=sys.stderr)
                return 1
        return 0
    with open(OUTPUT, "w") as f:
        f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
