"""Matplotlib for the suite report's figures (reports/make_report.py): the
Agg backend (no display needed), and what every figure shares."""
import io
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def draw_or_skip(draw, alt, where):
    """(draw()'s PNG, "") or, when drawing fails, (None, a note): a broken
    figure is skipped, it does not stop the report."""
    try:
        return draw(), ""
    except Exception as e:  # noqa: BLE001 - any failure of one figure only skips it
        plt.close("all")
        print("make_report: %s, %s skipped: %s: %s" % (where, alt, type(e).__name__, e), file=sys.stderr)
        return None, "%s: figure skipped (%s: %s)" % (alt, type(e).__name__, e)


def png_bytes(fig):
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    plt.close(fig)
    return buf.getvalue()


def missing_panel(ax, text):
    ax.text(0.5, 0.5, text, ha="center", va="center", fontsize=8, transform=ax.transAxes)
