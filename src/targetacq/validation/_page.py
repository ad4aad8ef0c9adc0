"""The validation page as self-contained HTML (the report's style, tables and PNG data URIs)."""

from __future__ import annotations

import datetime as _dt
import html
import math
from collections.abc import Sequence
from typing import Any

from targetacq.io.html_report import STYLE, figure_uri, html_table
from targetacq.validation._model import Check, Section, Summary, format_residual, summarise

__all__ = ["render_page"]

_EXTRA_STYLE = """
.summary { background: #f6f8fa; border: 1px solid #ccc; padding: 0.6em 1em; }
.summary p { margin: 0.3em 0; } pre { font-size: 0.8em; white-space: pre-wrap; }
td { font-size: 0.85em; } .wide { overflow-x: auto; }
"""


def _number(value: float | str) -> str:
    if isinstance(value, str):
        return value
    if math.isinf(value):
        return "∞" if value > 0 else "−∞"
    return f"{value:.6g}"


def _as_printed(check: Check) -> bool:
    """Whether the published value is just the printed text read as a number."""
    try:
        return float(check.printed) == check.published
    except ValueError:
        return False


def _rows(section: Section) -> tuple[list[dict[str, str]], list[str], set[str]]:
    names = section.alternative_names
    columns = ["item"]
    if not all(_as_printed(c) for c in section.checks):
        columns.append("printed")
    columns += ["published", "model", "residual", "tolerance"]
    if any(c.unit for c in section.checks):
        columns.append("unit")
    for name in names:
        columns += [f"model: {name}", f"residual: {name}"]
    columns.append("within")
    if any(c.note for c in section.checks):
        columns.append("note")
    numeric = {"published", "model", "residual", "tolerance"}
    numeric |= {c for c in columns if c.startswith(("model: ", "residual: "))}
    rows = []
    for check in section.checks:
        row = {
            "item": check.item,
            "printed": check.printed or _number(check.published),
            "published": _number(check.published),
            "model": _number(check.model),
            "residual": format_residual(check.residual),
            "tolerance": f"±{check.tolerance:.2g}" if check.residual is not None else "exact text",
            "unit": check.unit,
            "within": "✓" if check.within else "✗",
            "note": check.note,
        }
        for name in names:
            value = check.alternatives.get(name)
            row[f"model: {name}"] = "" if value is None else _number(value)
            row[f"residual: {name}"] = format_residual(check.alternative_residual(name))
        rows.append(row)
    return rows, columns, numeric


def _section_summary(section: Section) -> dict[str, str]:
    exact = [c for c in section.checks if c.exact]
    compared = [c for c in section.checks if not c.exact]
    worst = max(exact, key=lambda c: c.ratio, default=None)
    largest = max(compared, key=lambda c: abs(c.residual or 0.0), default=None)
    return {
        "section": section.title,
        "reproductions": str(len(exact)),
        "within tolerance": str(sum(c.within for c in exact)),
        "worst |residual| / tolerance": "—" if worst is None else f"{worst.ratio:.2g}",
        "comparisons": str(len(compared)),
        "largest comparison residual": ""
        if largest is None
        else f"{format_residual(largest.residual)} {largest.unit}".strip(),
    }


def _summary_html(summary: Summary, sections: Sequence[Section]) -> list[str]:
    parts = ["<div class='summary'>"]
    parts.append(
        f"<p><b>{summary.checks} checks</b> of published values the model is built to reproduce: "
        f"<b>{summary.within} within the tolerance</b> that each printed value's precision "
        "implies (half a unit in its last printed digit, or the stated tolerance of a computed "
        "reference).</p>"
    )
    if summary.worst is not None:
        worst = summary.worst
        parts.append(
            f"<p>Worst residual relative to its tolerance: {html.escape(summary.worst_section)} — "
            f"{html.escape(worst.item)}: published {html.escape(_number(worst.published))}, model "
            f"{html.escape(_number(worst.model))}, residual "
            f"{html.escape(format_residual(worst.residual))} {html.escape(worst.unit)} "
            f"({worst.ratio:.2g} × the tolerance ±{worst.tolerance:.2g}).</p>"
        )
    if summary.comparison_worst is not None:
        largest = summary.comparison_worst
        parts.append(
            f"<p>Besides these, {summary.comparisons} comparisons that are not expected to agree "
            "(Table 3.4's observations against the model, which reads the binned Table 3.5, and "
            "the thesis's own average row in Table 3.1): "
            f"RMS residual {summary.comparison_rms:.3g}; largest "
            f"{html.escape(format_residual(largest.residual))} ({html.escape(largest.item)}). "
            "They are shown with their residuals and not counted above.</p>"
        )
    parts.append("</div>")
    rows = [_section_summary(s) for s in sections]
    if rows:
        parts.append(html_table(rows, list(rows[0]), set(list(rows[0])[1:])))
    return parts


def render_page(sections: Sequence[Section], version: str = "") -> str:
    """The validation page as one HTML string.

    Parameters
    ----------
    sections : sequence of Section
        In page order; each becomes a heading, its source, a table of published value, model
        value and residual, its notes, its figure and the data file header.
    version : str
        targetacq version, printed under the title.

    Returns
    -------
    str
        A self-contained page: inline style, figures as PNG data URIs, no scripts or links.
    """
    title = "targetacq validation: the model against the published values"
    stamp = _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC")
    summary = summarise(list(sections))
    parts = [
        "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>",
        f"<title>{html.escape(title)}</title><style>{STYLE}{_EXTRA_STYLE}</style></head><body>",
        f"<h1>{html.escape(title)}</h1>",
        f"<p class='muted'>targetacq {html.escape(version)} — generated {stamp} by "
        "<code>targetacq validation</code>. Every table of Sonesson (2004), <i>A Probabilistic "
        "Approach to Conceptual Sensor Modeling</i>, LiTH-ISY-EX-3428, Linköping, that the model "
        "reproduces, with the check values printed in its text, a numerical check of the "
        "radiometry and a vendor's published DRI ranges. Residual = model − published.</p>",
    ]
    parts += _summary_html(summary, sections)
    for section in sections:
        parts += _section_html(section)
    parts.append("</body></html>")
    return "\n".join(parts)


def _section_html(section: Section) -> list[str]:
    parts = [f"<h2 id='{html.escape(section.key)}'>{html.escape(section.title)}</h2>"]
    parts.append(f"<p><b>Source.</b> {html.escape(section.source)}</p>")
    parts.append(f"<p><b>Model.</b> {html.escape(section.method)}</p>")
    rows, columns, numeric = _rows(section)
    parts.append(f"<div class='wide'>{html_table(rows, columns, numeric)}</div>")
    if section.notes:
        parts.append(f"<p class='muted'>{html.escape(section.notes)}</p>")
    if section.figure is not None:
        fig: Any = section.figure()
        parts.append(f"<img alt='{html.escape(section.title)}' src='{figure_uri(fig)}'>")
    if section.provenance:
        parts.append(
            "<details><summary class='muted'>Data file header (the transcription's source and "
            f"notes)</summary><pre>{html.escape(section.provenance)}</pre></details>"
        )
    return parts
