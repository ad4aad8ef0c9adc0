"""A self-contained report: inputs, every model choice with its source, DRI table, figures.

The page has no external resources: figures are embedded as PNG data URIs and the style sheet is
inline, so the file can be mailed to a colleague and opened anywhere. :func:`write_report` writes
it as HTML, or as PDF printed by a headless Chromium (:func:`find_browser`).
"""

from __future__ import annotations

import base64
import datetime as _dt
import html
import io
import math
import os
import shutil
import subprocess
import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from matplotlib.figure import Figure

from targetacq.io.files import output_path, write_atomically

__all__ = [
    "REPORT_FORMATS",
    "THESIS_CITATION",
    "find_browser",
    "print_to_pdf",
    "render_report",
    "require_browser",
    "write_report",
]

REPORT_FORMATS = ("html", "htm", "pdf")
"""Suffixes :func:`write_report` writes."""

THESIS_CITATION = (
    "Sonesson, M. (2004). A Probabilistic Approach to Conceptual Sensor Modeling. Master's "
    "thesis LiTH-ISY-EX-3428, Linköping University. "
    "https://www.diva-portal.org/smash/get/diva2:20633/FULLTEXT01.pdf"
)
"""The full citation of the model's source, printed in every report."""

BROWSER_NAMES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
"""Programs :func:`find_browser` looks for on the PATH, in order."""

STYLE = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 62em; color: #222; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; } h2 { font-size: 1.2em; margin-top: 1.6em; }
table { border-collapse: collapse; margin: 0.6em 0; }
th, td { border: 1px solid #ccc; padding: 0.3em 0.7em; text-align: left; }
th { background: #f2f2f2; } td.num { text-align: right; font-variant-numeric: tabular-nums; }
.muted { color: #666; font-size: 0.9em; } img { max-width: 100%; }
@media print {
  body { margin: 0; max-width: none; font-size: 10pt; }
  h2 { break-after: avoid; } figure, img, tr { break-inside: avoid; }
}
figure { margin: 0; } figcaption { color: #444; font-size: 0.9em; margin: 0.3em 0 1em; }
"""


def figure_uri(fig: Figure) -> str:
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")


def html_table(rows: Sequence[Mapping[str, Any]], columns: Sequence[str], numeric: set[str]) -> str:
    head = "".join(f"<th>{html.escape(c)}</th>" for c in columns)
    body = []
    for row in rows:
        cells = []
        for c in columns:
            css = ' class="num"' if c in numeric else ""
            cells.append(f"<td{css}>{html.escape(str(row.get(c, '')))}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    return f"<table><tr>{head}</tr>{''.join(body)}</table>"


def _section_table(items: Mapping[str, str | Mapping[str, str]]) -> str:
    """A section as a table: item and value, or, where some item differs from case to case (a
    mapping case → text), item and one column per case (the shared items span them)."""
    cases = list(dict.fromkeys(c for v in items.values() if isinstance(v, Mapping) for c in v))
    if not cases:
        rows = [{"item": k, "value": v} for k, v in items.items()]
        return html_table(rows, ["item", "value"], set())
    head = "<th>item</th>" + "".join(f"<th>{html.escape(c)}</th>" for c in cases)
    body = []
    for item, value in items.items():
        cell = f"<td>{html.escape(item)}</td>"
        if isinstance(value, Mapping):
            cell += "".join(f"<td>{html.escape(str(value.get(c, '—')))}</td>" for c in cases)
        else:
            cell += f"<td colspan='{len(cases)}'>{html.escape(str(value))}</td>"
        body.append(f"<tr>{cell}</tr>")
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
            if "range_p05_m" in r and r["reached"]:  # a band: "5,750 (3,830–8,620)"
                low, high = r["range_p05_m"], r["range_p95_m"]
                low_text = "not reached" if math.isnan(low) else f"{low:,.0f}"
                high_text = "any range" if math.isinf(high) else f"{high:,.0f}"
                text += f" ({low_text}–{high_text})"
            row[_probability_column(r["probability"])] = text
        rows.append(row)
    return rows


def _probability_column(p: float) -> str:
    """The DRI table's column of a probability: "50%", "95%", "97.5%"."""
    return f"{100 * p:.4g}%"


def render_report(
    performance: Any,
    sections: Mapping[str, Mapping[str, str | Mapping[str, str]]],
    figures: Mapping[str, Figure],
    title: str = "Range performance",
    version: str = "",
    captions: Mapping[str, str] | None = None,
) -> str:
    """The report as one HTML string.

    Parameters
    ----------
    performance : targetacq.core.ranges.RangePerformance
        Curves and DRI ranges.
    sections : mapping
        Section title → (item → text), e.g. ``{"Sensor": {"IFOV": "0.227 mrad"}, "Model
        choices and sources": {...}}``; rendered as two-column tables in order. An item whose
        text differs from case to case is a mapping case → text: its section gets a column per
        case.
    figures : mapping
        Heading → figure, embedded as PNG, each under its heading.
    title : str
        Page title, naming the sensor and the target.
    version : str
        targetacq version, printed in the header.
    captions : mapping, optional
        Heading → text printed under that figure (e.g. where its curves stop).

    Returns
    -------
    str
        The page; its ``<h2>`` headings are the sections, "DRI ranges [m]" and the figures'.
    """
    stamp = _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC")
    parts = [
        "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>",
        f"<title>{html.escape(title)}</title><style>{STYLE}</style></head><body>",
        f"<h1>{html.escape(title)}</h1>",
        f"<p class='muted'>targetacq {html.escape(version)} — generated {stamp}. Ranges are slant "
        "ranges in metres; probabilities are those of the conceptual sensor model of "
        f"{html.escape(THESIS_CITATION)}, with the choices listed below (errata and assumptions: "
        "see the targetacq user guide).</p>",
    ]
    for heading, items in sections.items():
        parts.append(f"<h2>{html.escape(heading)}</h2>")
        parts.append(_section_table(items))
    dri_rows = _dri_rows(performance)
    probability_columns = [
        _probability_column(p) for p in sorted(set(performance.dri["probability"]))
    ]
    parts.append("<h2>DRI ranges [m]</h2>")
    parts.append(
        html_table(dri_rows, ["case", "task", *probability_columns], set(probability_columns))
    )
    parts.append(
        "<p class='muted'>Range at which each task reaches the probability. Recognition is "
        "capped at detection and identification at recognition (nothing is recognised that was "
        'not detected). "not reached": the probability is never reached at any range (e.g. '
        "detection in high clutter above 0.9, Table 3.5). Where a curve jumps across a "
        "probability (noise pushing the clutter into another region of Table 3.5), the range is "
        "that of the jump, so two probabilities can share one range.</p>"
    )
    for heading, fig in figures.items():
        parts.append(f"<h2>{html.escape(heading)}</h2>")
        parts.append(f"<figure><img alt='{html.escape(heading)}' src='{figure_uri(fig)}'>")
        caption = (captions or {}).get(heading)
        if caption:
            parts.append(f"<figcaption>{html.escape(caption)}</figcaption>")
        parts.append("</figure>")
    parts.append("</body></html>")
    return "\n".join(parts)


def find_browser() -> str | None:
    """The headless browser that prints PDF reports: ``$TARGETACQ_BROWSER`` if set, else the
    first of :data:`BROWSER_NAMES` on the PATH; None if there is none."""
    chosen = os.environ.get("TARGETACQ_BROWSER")
    if chosen:
        return shutil.which(chosen) or (chosen if Path(chosen).is_file() else None)
    for name in BROWSER_NAMES:
        found = shutil.which(name)
        if found:
            return found
    return None


def require_browser() -> str:
    browser = find_browser()
    if browser is None:
        raise ValueError(
            "a PDF report needs Chromium, and none was found (install the chromium package, "
            "e.g. apt-get install chromium, or set TARGETACQ_BROWSER); or write the report as "
            ".html"
        )
    return browser


HEADLESS_CHROMIUM_FLAGS = (
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    # Without these, Chromium keeps trying to reach Google's hosts (slow on a closed network).
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
)
"""The flags of a headless Chromium run that reaches nothing but the page (also the tests')."""


def print_to_pdf(page: Path, pdf: Path, browser: str | None = None, timeout: float = 120) -> None:
    """Print an HTML file to PDF with headless Chromium (``--print-to-pdf``), A4-sized pages with
    the page's own print style and no header or footer.

    Raises
    ------
    ValueError
        If no browser is found (naming the package to install) or it fails.
    """
    browser = browser or require_browser()
    with tempfile.TemporaryDirectory(prefix="targetacq-chromium-") as profile:
        command = [
            browser,
            *HEADLESS_CHROMIUM_FLAGS,
            f"--user-data-dir={profile}",
            "--no-pdf-header-footer",
            f"--print-to-pdf={pdf}",
            page.resolve().as_uri(),
        ]
        try:
            done = subprocess.run(command, capture_output=True, text=True, timeout=timeout)
        except (OSError, subprocess.TimeoutExpired) as error:
            raise ValueError(f"printing the PDF with {browser} failed: {error}") from None
    if done.returncode != 0 or not pdf.is_file() or pdf.stat().st_size == 0:
        lines = [line for line in done.stderr.splitlines() if line.strip()]
        why = lines[-1] if lines else f"exit status {done.returncode}"
        raise ValueError(f"printing the PDF with {browser} failed: {why}")


def write_report(path: str | Path, page: str) -> Path:
    """Write the report atomically (:func:`targetacq.io.files.write_atomically`): HTML for .html
    or .htm, PDF (printed by :func:`print_to_pdf`) for .pdf.

    Raises
    ------
    ValueError
        If the suffix is not .html, .htm or .pdf, the folder does not exist, no browser is found
        for a PDF, or (``OutputError``) the file cannot be written: the message names the file
        and the reason.
    """
    out, kind = output_path(path, REPORT_FORMATS, "the report file")
    if kind != "pdf":
        return write_atomically(out, lambda p: p.write_text(page, encoding="utf-8"))
    browser = require_browser()  # before any work

    def _print(target: Path) -> None:
        with tempfile.TemporaryDirectory(prefix="targetacq-report-") as folder:
            source = Path(folder) / "report.html"
            source.write_text(page, encoding="utf-8")
            printed = Path(folder) / "report.pdf"
            print_to_pdf(source, printed, browser)
            shutil.copyfile(printed, target)

    return write_atomically(out, _print)
