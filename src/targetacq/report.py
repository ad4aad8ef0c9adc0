"""A self-contained HTML report: inputs, every model choice with its source, DRI table, figures.

The page has no external resources: figures are embedded as PNG data URIs and the style sheet is
inline, so the file can be mailed to a colleague and opened anywhere.
"""

from __future__ import annotations

import base64
import datetime as _dt
import html
import io
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from matplotlib.figure import Figure

from targetacq.outputs import output_path, write_atomically

__all__ = ["render_report", "write_report"]

_STYLE = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 62em; color: #222; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; } h2 { font-size: 1.2em; margin-top: 1.6em; }
table { border-collapse: collapse; margin: 0.6em 0; }
th, td { border: 1px solid #ccc; padding: 0.3em 0.7em; text-align: left; }
th { background: #f2f2f2; } td.num { text-align: right; font-variant-numeric: tabular-nums; }
.muted { color: #666; font-size: 0.9em; } img { max-width: 100%; }
"""


def _figure_uri(fig: Figure) -> str:
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")


def _table(rows: Sequence[Mapping[str, Any]], columns: Sequence[str], numeric: set[str]) -> str:
    head = "".join(f"<th>{html.escape(c)}</th>" for c in columns)
    body = []
    for row in rows:
        cells = []
        for c in columns:
            css = ' class="num"' if c in numeric else ""
            cells.append(f"<td{css}>{html.escape(str(row.get(c, '')))}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    return f"<table><tr>{head}</tr>{''.join(body)}</table>"


def _dri_rows(performance: Any) -> list[dict[str, str]]:
    dri = performance.dri
    rows = []
    for (case, task), group in dri.groupby(["case", "task"], sort=False):
        row = {"case": str(case), "task": str(task)}
        for _, r in group.iterrows():
            value = r["range_m"]
            if not r["reached"]:
                text = "not reached"
            elif math.isinf(value):
                text = "any range"
            else:
                text = f"{value:,.0f}"
            row[f"{r['probability']:.0%}"] = text
        rows.append(row)
    return rows


def render_report(
    performance: Any,
    sections: Mapping[str, Mapping[str, str]],
    figures: Mapping[str, Figure],
    title: str = "Range performance",
    version: str = "",
) -> str:
    """The report as one HTML string.

    Parameters
    ----------
    performance : targetacq.ranges.RangePerformance
        Curves and DRI ranges.
    sections : mapping
        Section title → (item → text), e.g. ``{"Sensor": {"IFOV": "0.227 mrad"}, "Model
        choices and sources": {...}}``; rendered as two-column tables in order.
    figures : mapping
        Caption → figure, embedded as PNG.
    title : str
        Page title, naming the sensor and the target.
    version : str
        targetacq version, printed in the footer.
    """
    stamp = _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC")
    parts = [
        "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>",
        f"<title>{html.escape(title)}</title><style>{_STYLE}</style></head><body>",
        f"<h1>{html.escape(title)}</h1>",
        f"<p class='muted'>targetacq {html.escape(version)} — generated {stamp}. Ranges are slant "
        "ranges in metres; probabilities are those of the conceptual sensor model of Sonesson "
        "(2004) with the choices listed below.</p>",
    ]
    for heading, items in sections.items():
        parts.append(f"<h2>{html.escape(heading)}</h2>")
        rows = [{"item": k, "value": v} for k, v in items.items()]
        parts.append(_table(rows, ["item", "value"], set()))
    dri_rows = _dri_rows(performance)
    probability_columns = [f"{p:.0%}" for p in sorted(set(performance.dri["probability"]))]
    parts.append("<h2>DRI ranges [m]</h2>")
    parts.append(_table(dri_rows, ["case", "task", *probability_columns], set(probability_columns)))
    parts.append(
        "<p class='muted'>Range at which each task reaches the probability. Recognition is "
        "capped at detection and identification at recognition (nothing is recognised that was "
        'not detected). "not reached": the probability is never reached at any range (e.g. '
        "detection in high clutter above 0.9, Table 3.5). Where a curve jumps across a "
        "probability (noise pushing the clutter into another region of Table 3.5), the range is "
        "that of the jump, so two probabilities can share one range.</p>"
    )
    for caption, fig in figures.items():
        parts.append(f"<h2>{html.escape(caption)}</h2>")
        parts.append(f"<img alt='{html.escape(caption)}' src='{_figure_uri(fig)}'>")
    parts.append("</body></html>")
    return "\n".join(parts)


def write_report(path: str | Path, page: str) -> Path:
    """Write the report atomically (:func:`targetacq.outputs.write_atomically`).

    Raises
    ------
    ValueError
        If the suffix is not .html or .htm, the folder does not exist, or (``OutputError``) the
        file cannot be written: the message names the file and the reason.
    """
    out, _ = output_path(path, ("html", "htm"), "the report file")
    return write_atomically(out, lambda p: p.write_text(page, encoding="utf-8"))
