"""The suite report's building blocks (reports/make_report.py): tables and
figures as HTML (figures embedded as base64 PNG) and as Markdown (figures
written to OUT/report_files/)."""
import base64
import html
import os


def html_table(header, rows):
    h = "".join("<th>%s</th>" % html.escape(c) for c in header)
    b = "".join("<tr>%s</tr>" % "".join("<td>%s</td>" % html.escape(c) for c in r) for r in rows)
    return "<table><tr>%s</tr>%s</table>" % (h, b)


def md_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines) + "\n"


def figure(out, fname, png, alt, caption):
    """The PNG written to OUT/fname; (HTML with it embedded and captioned,
    Markdown referencing the file)."""
    with open(os.path.join(out, fname), "wb") as f:
        f.write(png)
    return (("<figure><img alt='%s' src='data:image/png;base64,%s'/><figcaption>%s</figcaption></figure>"
             % (html.escape(alt), base64.b64encode(png).decode(), html.escape(caption))),
            "![%s](%s)\n\n*%s*\n\n" % (alt, fname, caption))


def note(text):
    """A note in place of a figure: (HTML, Markdown)."""
    return "<p><em>%s</em></p>" % html.escape(text), "*%s*\n\n" % text
