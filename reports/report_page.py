"""The top of the suite report and the page around it (reports/make_report.py):
the verdict box (verification checks, runs finished and stopped, load
flags), the table of contents with links to every section, the provenance
block, and the HTML page with its style."""
import html

from report_html import anchor

STYLE = """
body{font-family:sans-serif;max-width:74em;margin:auto;padding:0 1em;text-align:left;line-height:1.35}
table{border-collapse:collapse;font-size:0.9em}
td,th{border:1px solid #999;padding:2px 6px;text-align:left;vertical-align:top}
th{background:#eee} td.num{text-align:right;white-space:nowrap}
.scroll{max-width:100%;overflow-x:auto;margin:0.5em 0}
img{max-width:100%;height:auto} figure{margin:1em 0}
.verdict{border:2px solid;padding:0.4em 1em;margin:0.5em 0;border-radius:4px}
.verdict.pass{background:#e6f4e6;border-color:#2a7a2a} .verdict.fail{background:#fbe7e7;border-color:#b22}
.verdict h2{margin:0.2em 0}
.toc{columns:3 18em;font-size:0.92em;margin:0} .toc li{break-inside:avoid}
.flags{background:#fff4dc;border-left:4px solid #d80;padding:0.3em 1em}
.footnotes{font-size:0.85em} .provenance td:first-child{white-space:nowrap}
"""


def verdict(suite, runs, ver, flags):
    """The verdict box: HTML and Markdown. ver: verification.json (None when
    not run); flags: {scene: number of load flags}."""
    finished = sum(1 for r in runs if r["exit_code"] == 0 and r["summary"].get("status") == "finished")
    stopped = [r for r in runs if not (r["exit_code"] == 0 and r["summary"].get("status") == "finished")]
    checks = ver["checks"] if ver else []
    failed = sum(1 for c in checks if not c["pass"])
    ok = failed == 0 and not stopped
    lines = ["Verification checks: %d passed, %d failed%s." % (len(checks) - failed, failed,
                                                              "" if ver else " (the suite ran none)"),
             "Scene runs: %d finished, %d stopped%s." % (finished, len(stopped), ": " + ", ".join(
                 "%s %s%s" % (r["case"], r["formulation"], " / " + r["variant"] if r["variant"] else "")
                 for r in stopped) if stopped else "")]
    studies = suite.get("studies", [])
    if studies:
        n, st = sum(s.get("runs", 0) for s in studies), sum(s.get("stopped", 0) for s in studies)
        lines.append("Study runs: %d, %d stopped early (recorded in the studies' tables, a measurement, not a "
                     "failure)." % (n, st))
    flagged = {sc: n for sc, n in flags.items() if n}
    links = ", ".join("<a href='#%s'>%s</a> (%d)" % (anchor("scene", sc), html.escape(sc), n)
                      for sc, n in flagged.items())
    lines.append("Load flags: %d in %d scene%s%s." % (sum(flagged.values()), len(flagged),
                                                      "" if len(flagged) == 1 else "s", ": " + links if links else ""))
    title = "Verdict: %s" % ("PASS" if ok else "FAIL")
    h = "<div class='verdict %s' id='verdict'><h2>%s</h2>%s</div>" % (
        "pass" if ok else "fail", title, "".join("<p style='margin:0.2em 0'>%s</p>" % x for x in lines))
    md = "## %s\n\n%s\n" % (title, "".join("- %s\n" % x for x in lines))
    return h, md


def contents(entries):
    """The table of contents: entries [(anchor, text, [(anchor, text)])]."""
    items = []
    for a, text, subs in entries:
        sub = "<ol class='toc'>%s</ol>" % "".join("<li><a href='#%s'>%s</a></li>" % (s, html.escape(t))
                                                  for s, t in subs) if subs else ""
        items.append("<li><a href='#%s'>%s</a>%s</li>" % (a, html.escape(text), sub))
    return "<nav id='contents'><h2>Contents</h2><ul>%s</ul></nav>" % "".join(items)


def provenance(rows):
    """The provenance block: HTML and Markdown."""
    body = "".join("<tr><td>%s</td><td>%s</td></tr>" % (html.escape(k), html.escape(v)) for k, v in rows)
    return ("<h2 id='provenance'>Provenance</h2><div class='scroll provenance'><table>%s</table></div>" % body,
            "## Provenance\n\n%s\n" % "".join("- %s: %s\n" % (k, v) for k, v in rows))


def page(body):
    return ("<!DOCTYPE html><html><head><meta charset='utf-8'>"
            "<meta name='viewport' content='width=device-width, initial-scale=1'>"
            "<title>rpfem suite report</title><style>%s</style></head><body>%s</body></html>\n" % (STYLE, body))
