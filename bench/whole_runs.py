#!/usr/bin/env python3
"""Whole runs, timed: the upsetting job of the performance study (D0 = H0 =
20 mm, AISI 1010, Coulomb mu = 0.1, 50 %, 20 x 20 elements) under each
enforcement, the ring, Test II's die and Test I's single action. Per run:
wall time, steps, Newton iterations (Ipopt's iterations under ipopt), time
per iteration, and the split of summary.json's timings_s: element tangent
(assembly), element forces and energies (residual), the contact's terms,
rows and settling (contact), CHOLMOD/UMFPACK's factorization and
triangular solves, and the rest (other: Ipopt's own linear algebra under
ipopt, output, set-up).

  /usr/bin/python3 bench/whole_runs.py build/rpfem OUT [--repeat N] [--md FILE]

Runs one at a time (the timings are the machine's, not shared with another
run), each `--repeat` times (default 1), keeping the fastest, and prints one
Markdown table (also written to FILE with --md). Extra arguments after `--`
go to every run (e.g. `-- --set solver.threads=2`)."""
import json, os, subprocess, sys

JOBS = [  # (label, case, extra arguments)
    ("upsetting mu 0.1, direct", "upsetting_friction", ["--variant", "mu0.1", "--formulation", "direct"]),
    ("upsetting mu 0.1, penalty", "upsetting_friction", ["--variant", "mu0.1", "--formulation", "penalty"]),
    ("upsetting mu 0.1, auglag", "upsetting_friction", ["--variant", "mu0.1", "--formulation", "auglag"]),
    ("upsetting mu 0.1, ipopt", "upsetting_friction", ["--variant", "mu0.1", "--formulation", "ipopt"]),
    ("ring m 0.1 (default), direct", "ring_compression", ["--formulation", "direct"]),
    ("Test II die, direct", "paper_test2_die", ["--formulation", "direct"]),
    ("Test II die, penalty", "paper_test2_die", ["--formulation", "penalty"]),
    ("Test II die, ipopt", "paper_test2_die", ["--formulation", "ipopt"]),
    ("Test I single action, penalty", "paper_test1_single_action", ["--formulation", "penalty"]),
]
PARTS = ["assembly", "residual", "contact", "factorization", "triangular_solves"]


def run(rpfem, case, args, out, extra):
    src = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    cmd = [rpfem, "run", os.path.join(src, "cases", case + ".toml"), "--out", out, "--force", "--quiet"] + args + extra
    subprocess.run(cmd, check=False, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def main(argv):
    extra = []
    if "--" in argv:
        extra = argv[argv.index("--") + 1:]
        argv = argv[:argv.index("--")]
    if len(argv) < 3:
        sys.exit(__doc__)
    rpfem, out = argv[1], argv[2]
    repeat = int(argv[argv.index("--repeat") + 1]) if "--repeat" in argv else 1
    md = argv[argv.index("--md") + 1] if "--md" in argv else None
    head = ("| run | status | wall s | steps | iterations | ms / iteration | "
            + " | ".join(p.replace("_", " ") for p in PARTS) + " | other |")
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for k, (label, case, args) in enumerate(JOBS):
        best = None
        for r in range(repeat):
            s = run(rpfem, case, args, os.path.join(out, "%02d_%s" % (k, case), str(r)), extra)
            if best is None or s["wall_time_s"] < best["wall_time_s"]:
                best = s
        t = best.get("timings_s", {})
        wall, its = best["wall_time_s"], max(1, best.get("total_newton_iterations", 0))
        parts = [t.get(p, 0.0) for p in PARTS]
        other = max(0.0, wall - sum(parts) - t.get("symbolic_analysis", 0.0))
        cells = ["%.2f (%.0f %%)" % (x, 100 * x / wall) for x in parts + [other]]
        lines.append("| %s | %s | %.2f | %d | %d | %.2f | %s |" % (
            label, best.get("status", "?"), wall, best.get("steps", 0), its, 1e3 * wall / its, " | ".join(cells)))
        print(lines[-1], flush=True)
    text = "\n".join(lines) + "\n"
    if md:
        with open(md, "w") as f:
            f.write(text)
    print(text)


if __name__ == "__main__":
    main(sys.argv)
