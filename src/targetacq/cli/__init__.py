"""The ``targetacq`` command.

Every quantity takes a unit (``--pitch 17um``); choices come from the registries. Bad input
prints one line on stderr and exits with status 2, never a traceback.

One module per group of commands: :mod:`.dri` (dri, atmosphere), :mod:`.figures` (plot,
report), :mod:`.images` (clutter), :mod:`.scenarios` (validate, evaluate, simulate).
"""

from __future__ import annotations

import csv
import io
import json
import math
import sys
from typing import Annotated, Any

import typer

from targetacq.atmosphere import OBSCURANTS, VISIBILITY_CONVENTIONS
from targetacq.bands import BANDS

__all__ = ["app", "main"]

FORMATS = ("table", "json", "csv")

DEFAULT_EXAMPLE = "uav_haze.toml"

_SI_SUFFIX = {"aperture": "m", "wavelength": "m", "blur_sigma": "rad"}

app = typer.Typer(
    add_completion=False,
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    help="Probabilities and ranges of detection, recognition and identification for imaging "
    "sensors (Sonesson 2004 conceptual sensor model).",
)

# Options shared by several commands, defined once.
BandOption = Annotated[
    str | None, typer.Option(help=f"Sensor band: {', '.join(BANDS)} or e.g. 8-12um.")
]

ExtinctionOption = Annotated[
    str | None, typer.Option(help="Path extinction, e.g. 0.4/km (Np/km) or 1.7dB/km.")
]

ObscurantOption = Annotated[
    str | None,
    typer.Option(help=f"Table 7.1 obscurant[:low|nominal|high]: {', '.join(OBSCURANTS)}."),
]

VisibilityOption = Annotated[
    str | None, typer.Option(help="Visibility (visible band), e.g. 7.5km.")
]

ConventionOption = Annotated[
    str | None,
    typer.Option(help=f"Visibility convention: {', '.join(VISIBILITY_CONVENTIONS)}."),
]

FormatOption = Annotated[str, typer.Option("--format", help=f"Output: {', '.join(FORMATS)}.")]


@app.callback()
def _root() -> None:
    """Probabilities and ranges of detection, recognition and identification."""


def _choice(value: str, choices: Any, name: str) -> str:
    if value not in choices:
        raise ValueError(f"{name} must be one of {', '.join(choices)}; got {value!r}")
    return value


def _json_number(value: Any) -> Any:
    if isinstance(value, float) and not math.isfinite(value):
        return None if math.isnan(value) else ("inf" if value > 0 else "-inf")
    return value


def _csv(rows: list[dict[str, Any]], fieldnames: list[str] | None = None) -> str:
    """Rows as CSV text with a header (only ``fieldnames`` when given)."""
    buffer = io.StringIO()
    writer = csv.DictWriter(
        buffer, fieldnames=fieldnames or list(rows[0]), lineterminator="\n", extrasaction="ignore"
    )
    writer.writeheader()
    writer.writerows(rows)
    return buffer.getvalue()


def _render_rows(rows: list[dict[str, Any]], output_format: str) -> str:
    if output_format == "json":
        clean = [{k: _json_number(v) for k, v in row.items()} for row in rows]
        return json.dumps({"targets": clean}, indent=2) + "\n"
    if output_format == "csv":
        return _csv(rows)
    header = (
        f"{'#':>3} {'box x,y,w,h':<18}{'clutter':>9}{'SCR+':>8}{'SCR-':>8} {'region':<7}"
        f"{'cycles':>7}{'P(det)':>8}{'aspect':>7}{'σ/mean':>8}{'edges':>7}{'contrast':>9}"
    )
    lines = [header, "-" * len(header)]
    for row in rows:
        lines.append(
            f"{row['target']:>3} {row['box']:<18}{row['clutter']:>9.4g}{row['scr_positive']:>8.3g}"
            f"{row['scr_negative']:>8.3g} {row['region']:<7}{row['cycles']:>7.3g}"
            f"{row['p_detection']:>8.3f}{row['aspect']:>7.2f}{row['std_over_mean']:>8.3f}"
            f"{row['edge_strength']:>7.2f}{row['contrast']:>9.3f}"
        )
    return "\n".join(lines) + "\n"


def _one_line(message: str) -> str:
    return " ".join(str(message).split())


def main(argv: list[str] | None = None) -> None:
    """Entry point: run the app; bad input → one line on stderr, exit status 2."""
    try:
        code = app(args=argv, prog_name="targetacq", standalone_mode=False)
    except typer.Abort:
        sys.stderr.write("targetacq: aborted\n")
        sys.exit(1)
    except typer.TyperException as error:  # usage errors: unknown option, missing value, ...
        message = error.format_message()
        if type(error).__name__ == "NoArgsIsHelpError":
            sys.stderr.write(message + "\n")
        else:
            sys.stderr.write(f"targetacq: error: {_one_line(message)}\n")
        sys.exit(2)
    except (ValueError, KeyError, TypeError) as error:
        sys.stderr.write(f"targetacq: error: {_one_line(str(error))}\n")
        sys.exit(2)
    sys.exit(code if isinstance(code, int) else 0)


# The commands register themselves on `app` when their modules are imported.
from targetacq.cli import dri, figures, images, scenarios, validation  # noqa: E402, F401
