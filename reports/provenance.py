"""The report's provenance block (reports/make_report.py): which rpfem made
the runs (the version in each run's summary.json; the executable and its
compiler from suite.json's "program", written by newer suites), when
(suite.json's time), on what machine, and the BLAS library the runs ran
on (each run's summary.json "blas", from the process's own mappings: an
LD_LIBRARY_PATH that ldd of the executable does not see is in it; for
older suites what ldd resolves libblas.so.3 to)."""
import datetime
import os
import platform
import socket
import subprocess


def blas_of(program):
    """The BLAS library `program` loads: libblas.so.3's target as ldd
    resolves it, followed through its symlinks (Debian's alternatives:
    .../blas/ for the reference BLAS, .../openblas-pthread/ for OpenBLAS)."""
    if not program or not os.path.exists(program):
        return "unknown (the rpfem executable is not named in suite.json or is gone)"
    try:
        text = subprocess.run(["ldd", program], capture_output=True, text=True, timeout=20).stdout
    except (OSError, subprocess.SubprocessError) as e:
        return "unknown (ldd failed: %s)" % e
    for line in text.splitlines():
        parts = line.split()
        if parts and parts[0].startswith(("libblas", "libopenblas", "libmkl_rt")) and len(parts) >= 3:
            return "%s (%s)" % (os.path.realpath(parts[2]), parts[2])
    return "none linked directly (ldd lists no libblas)"


def blas_of_runs(runs):
    """The BLAS libraries the runs recorded (summary.json "blas"), joined;
    "" where none did."""
    return ", ".join(sorted({r["summary"].get("blas", "") for r in runs} - {"", "unknown"}))


def cpu():
    try:
        with open("/proc/cpuinfo") as f:
            name = next((line.split(":", 1)[1].strip() for line in f if line.startswith("model name")), "")
    except OSError:
        name = ""
    return "%s, %d cores" % (name or platform.processor() or "unknown CPU", os.cpu_count() or 0)


def provenance_rows(out, suite, runs):
    """[(what, value)] for the provenance block."""
    program = suite.get("program", {})
    versions = sorted({r["summary"].get("version", "") for r in runs} - {""})
    made = datetime.datetime.fromtimestamp(os.path.getmtime(os.path.join(out, "suite.json")))
    return [
        ("rpfem version (runs' summary.json)", ", ".join(versions) or "unknown"),
        ("rpfem executable", program.get("path", "unknown (not recorded in suite.json)")),
        ("compiler", program.get("compiler", "unknown (not recorded in suite.json)")),
        ("BLAS loaded", blas_of_runs(runs) or blas_of(program.get("path"))),
        ("suite.json written", made.strftime("%Y-%m-%d %H:%M")),
        ("report made", datetime.datetime.now().strftime("%Y-%m-%d %H:%M")),
        ("machine", "%s: %s, %s" % (socket.gethostname(), platform.platform(), cpu())),
        ("suite folder", os.path.abspath(out)),
    ]
