"""The suite report's building blocks (reports/make_report.py): tables and
figures as HTML and as Markdown. Figures are written to OUT/report_files/
and referenced from both; with INLINE["on"] (make_report.py --single-file)
the HTML embeds them as base64 PNG instead."""
import base64
import html
import os
import re

INLINE = {"on": False}  # embed figures in report.html (set by make_report.py --single-file)
NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?( \(.*\))?$|^-$")


def html_table(header, rows):
    """A table in a horizontally scrolling wrapper; cells holding a number
    (or "-") are right-aligned, text left-aligned."""
    h = "".join("<th>%s</th>" % html.escape(c) for c in header)
    b = "".join("<tr>%s</tr>" % "".join("<td%s>%s</td>" % (" class='num'" if NUMBER.match(c) else "", html.escape(c))
                                        for c in r) for r in rows)
    return "<div class='scroll'><table><tr>%s</tr>%s</table></div>" % (h, b)


def md_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines) + "\n"


def figure(out, fname, png, alt, caption):
    """The PNG written to OUT/fname; (HTML showing it, captioned: the file,
    or embedded with INLINE; Markdown referencing the file)."""
    with open(os.path.join(out, fname), "wb") as f:
        f.write(png)
    src = "data:image/png;base64," + base64.b64encode(png).decode() if INLINE["on"] else fname
    return (("<figure><img alt='%s' src='%s'/><figcaption>%s</figcaption></figure>"
             % (html.escape(alt), src, html.escape(caption))),
            "![%s](%s)\n\n*%s*\n\n" % (alt, fname, caption))


def note(text):
    """A note in place of a figure: (HTML, Markdown)."""
    return "<p><em>%s</em></p>" % html.escape(text), "*%s*\n\n" % text


def anchor(kind, name):
    """The id of a section's heading: scene-NAME, study-NAME."""
    return "%s-%s" % (kind, re.sub(r"[^A-Za-z0-9_-]", "-", name))
