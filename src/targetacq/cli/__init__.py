"""The ``targetacq`` command.

Every quantity takes a unit (``--pitch 17um``); choices come from the registries.

Failures, warnings and signals
------------------------------
- **Bad input** (``ValueError``, ``TypeError``, ``KeyError``), a **file that cannot be read or
  written** (``OSError``, and :class:`targetacq.outputs.OutputError` for every output file), a
  run **too large for memory** (``MemoryError``) or **too deeply nested** input
  (``RecursionError``) print one line, ``targetacq: error: ...``, on stderr and exit with
  status 2, never a traceback. Anything else is a bug and keeps its traceback.
- **Standard output** that cannot be written (``> /dev/full``, a file-size limit) is such a
  failure too: ``targetacq: error: cannot write standard output: ...``, status 2. A reader that
  closes the pipe early (``targetacq ... | head``) ends the command quietly with status 1 (the
  convention of click, which typer builds on).
- **Warnings.** A command that fails prints only its error line. A command that succeeds
  prints each distinct ``UserWarning`` (a warning addressed to the user) after its output, as one
  line ``targetacq: warning: ...`` on stderr. Other warnings (NumPy's floating-point
  ``RuntimeWarning``, deprecations inside libraries) are internal numeric noise: the results
  already carry NaN where a value is undefined, so they are dropped.
- **Signals.** SIGTERM ends the command with status 143 (128 + 15) after removing any
  temporary output file; a file-size limit (SIGXFSZ) is ignored so that the write fails with
  "File too large" and is reported like any write failure.

One module per group of commands: :mod:`.dri` (dri, atmosphere), :mod:`.figures` (plot,
report), :mod:`.images` (clutter), :mod:`.scenarios` (validate, evaluate, simulate).
"""

from __future__ import annotations

import csv
import errno
import functools
import io
import os
import signal
import sys
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Annotated, Any

import typer
import typer.main

from targetacq.atmosphere import OBSCURANTS, VISIBILITY_CONVENTIONS
from targetacq.bands import BANDS
from targetacq.outputs import json_text

__all__ = ["app", "main"]

FORMATS = ("table", "json", "csv")

DEFAULT_EXAMPLE = "uav_haze.toml"

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
        return json_text({"targets": rows}) + "\n"
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


EXIT_USAGE = 2
"""Exit status of every failure the user can fix (bad input, unwritable file, too large)."""

EXIT_CLOSED_PIPE = 1
"""Exit status when the reader of standard output has gone (click's convention)."""

EXIT_SIGTERM = 128 + signal.SIGTERM


@functools.cache
def _click_command() -> Any:
    """The click command of :data:`app`, built once (typer rebuilds it on every call of
    ``app(...)``, about 0.1 s). Every command module registers on ``app`` when this package is
    imported, before the first call; a call's state lives in its own click context."""
    return typer.main.get_command(app)


def main(argv: list[str] | None = None) -> None:
    """Entry point: run the app; every failure the user can fix → one line on stderr, exit
    status 2 (see the module docstring)."""
    with (
        _signals_handled(),
        _standard_output_watched(),
        warnings.catch_warnings(record=True) as caught,
    ):
        warnings.simplefilter("always")  # recorded, then printed once each or dropped
        code = _run(argv)
        if code == 0:
            try:
                sys.stdout.flush()
            except _StandardOutputError as error:
                code = _fail(_stdout_failure(error))
    if code == 0:
        _print_warnings(caught)
    sys.exit(code)


def _run(argv: list[str] | None) -> int:
    """Run the app; the exit status, after printing a failure's one line."""
    try:
        code = _click_command().main(args=argv, prog_name="targetacq", standalone_mode=False)
    except typer.Abort:
        sys.stderr.write("targetacq: aborted\n")
        return 1
    except typer.TyperException as error:  # usage errors: unknown option, missing value, ...
        message = error.format_message()
        if type(error).__name__ == "NoArgsIsHelpError":
            sys.stderr.write(message + "\n")
            return EXIT_USAGE
        return _fail(message)
    except (ValueError, KeyError, TypeError) as error:
        return _fail(str(error))
    except MemoryError as error:
        return _fail(f"not enough memory for this run: {str(error) or 'an allocation failed'}")
    except RecursionError:
        return _fail("input too deeply nested")
    except _StandardOutputError as error:
        return _fail(_stdout_failure(error))
    except OSError as error:
        if error.filename is not None and error.strerror:
            return _fail(f"{error.filename}: {error.strerror}")
        return _fail(str(error))
    return code if isinstance(code, int) else 0


def _fail(message: str) -> int:
    sys.stderr.write(f"targetacq: error: {_one_line(message)}\n")
    return EXIT_USAGE


class _StandardOutputError(OSError):
    """A write to standard output failed (told apart from every other ``OSError``)."""


class _WatchedOutput(io.FileIO):
    """Standard output's file descriptor, raising :class:`_StandardOutputError` when a write
    fails."""

    def write(self, data: Any) -> int:
        try:
            return super().write(data)
        except OSError as error:
            raise _StandardOutputError(error.errno, error.strerror) from None


@contextmanager
def _standard_output_watched() -> Iterator[None]:
    """Write standard output through :class:`_WatchedOutput` while a command runs (when it is
    a real file; a test's capture is left as it is)."""
    original = sys.stdout
    try:
        descriptor = original.fileno()
    except (AttributeError, OSError, ValueError):
        yield
        return
    original.flush()
    sys.stdout = io.TextIOWrapper(
        io.BufferedWriter(_WatchedOutput(descriptor, "w", closefd=False)),
        encoding=original.encoding,
        errors=original.errors,
        line_buffering=bool(original.line_buffering),
    )
    watched = sys.stdout
    try:
        yield
    finally:
        sys.stdout = original
        try:
            watched.flush()  # what a failing command printed still comes out, in order
        except OSError:
            _discard_stdout()


def _stdout_failure(error: OSError) -> str:
    """The message for a failed write to standard output; a closed pipe ends quietly."""
    _discard_stdout()
    if error.errno == errno.EPIPE:
        sys.exit(EXIT_CLOSED_PIPE)
    return f"cannot write standard output: {error.strerror or error}"


def _discard_stdout() -> None:
    """Point standard output at /dev/null, so that the last flush of the unwritten buffer
    (when the interpreter exits) does not fail again and print "Exception ignored ..."."""
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, sys.__stdout__.fileno() if sys.__stdout__ else 1)
    os.close(null)


def _print_warnings(caught: list[warnings.WarningMessage]) -> None:
    seen = set()
    for warning in caught:
        line = _one_line(str(warning.message))
        if issubclass(warning.category, UserWarning) and line not in seen:
            seen.add(line)
            sys.stderr.write(f"targetacq: warning: {line}\n")


def _terminate(signum: int, frame: Any) -> None:
    """SIGTERM: unwind (removing temporary output files on the way) and exit 143."""
    raise SystemExit(EXIT_SIGTERM)


@contextmanager
def _signals_handled() -> Iterator[None]:
    """SIGTERM unwinds with SystemExit; SIGXFSZ is ignored so a write over the file-size limit
    fails with EFBIG. The previous handlers come back afterwards (``main`` may run in-process)."""
    wanted: dict[signal.Signals, Any] = {signal.SIGTERM: _terminate}
    if hasattr(signal, "SIGXFSZ"):  # POSIX only
        wanted[signal.SIGXFSZ] = signal.SIG_IGN
    previous: dict[signal.Signals, Any] = {}
    try:
        for number, handler in wanted.items():
            previous[number] = signal.signal(number, handler)
    except ValueError:  # not the main thread: signals stay as they are
        pass
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)


# The commands register themselves on `app` when their modules are imported.
from targetacq.cli import design, dri, figures, images, scenarios, sweep, validation  # noqa: E402, F401
