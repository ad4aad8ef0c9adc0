"""The `validation` command: the page of published values against the model's."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from targetacq.cli import app
from targetacq.io.files import output_path


@app.command("validation")
def validation_command(
    out: Annotated[str, typer.Option(help="Output file, .html.")] = "validation.html",
) -> None:
    """Write the validation page: every published table the model reproduces (Sonesson 2004,
    and a vendor's DRI ranges), published value against model value with the residuals and
    figures, as one self-contained HTML file.

    Example: targetacq validation --out validation.html
    """
    output_path(out, ("html", "htm"), "the validation page")  # before any work
    if Path(out).is_dir():
        raise ValueError(f"cannot write {out!r}: it is a folder")
    # Imported here, not when the CLI starts: pandas, matplotlib and SciPy take about 0.5 s.
    from targetacq import validation

    sections = validation.validation_sections()
    page = validation.render_validation(sections)
    try:
        written = validation.write_validation(out, page)
    except OSError as error:
        raise ValueError(f"cannot write {out!r}: {error.strerror or error}") from error
    typer.echo(f"wrote {written}: {validation.validation_summary(sections).line()}")
