"""The ``targetacq`` command.

Every quantity takes a unit (``--pitch 17um``); choices come from the registries.

Failures, warnings and signals
------------------------------
- **Bad input** (``ValueError``, ``TypeError``, ``KeyError``), a **file that cannot be read or
  written** (``OSError``, and :class:`targetacq.io.files.OutputError` for every output file), a
  run **too large for memory** (``MemoryError``) or **too deeply nested** input
  (``RecursionError``) print one line, ``targetacq: error: ...``, on stderr and exit with
  status 2, never a traceback. Anything else is a bug and keeps its traceback.
- **Standard output** that cannot be written (``> /dev/full``, a file-size limit) is such a
  failure too: ``targetacq: error: cannot write standard output: ...``, status 2. A reader that
  closes the pipe early (``targetacq ... | head``) ends the command quietly with status 1 (the
  convention of click, which typer builds on).
- **Warnings.** A command that fails prints only its error line. A command that succeeds
  prints each distinct ``UserWarning`` (a warning addressed to the user) after its output, as one
  line ``targetacq: warning: ...`` on stderr: among them a scenario file's plausibility
  warnings (:mod:`targetacq.scenario.plausibility`: a value no real sensor has, such as a focal
  length of ``"35 m"`` meant in mm), each located in the file. Other warnings (NumPy's
  floating-point ``RuntimeWarning``, deprecations inside libraries) are internal numeric noise: the
  results already carry NaN where a value is undefined, so they are dropped.
- **Signals.** SIGTERM ends the command with status 143 (128 + 15) after removing any
  temporary output file; a file-size limit (SIGXFSZ) is ignored so that the write fails with
  "File too large" and is reported like any write failure.

Start-up
--------
One module per group of commands (:data:`COMMANDS`): :mod:`.dri` (dri, atmosphere),
:mod:`.figures` (plot, report), :mod:`.images` (clutter), :mod:`.scenarios` (validate,
evaluate, simulate), :mod:`.examples` (examples), ... A command's module, and the libraries it
needs (NumPy, SciPy, ...), are imported only when that command runs, its help is asked for, or
its options are completed: ``targetacq --help``, ``--version`` and the completion of command
names import none of them (the list of commands shows each one's summary from
:data:`COMMANDS`).

Shell completion: ``targetacq --install-completion`` (bash, zsh, fish, PowerShell), or
``targetacq --show-completion`` to see the script; commands, options and the names the options
take (criteria, transforms, obscurants, bands, ...) complete from the registries.
"""

from __future__ import annotations

import csv
import errno
import functools
import importlib
import importlib.util
import io
import os
import signal
import sys
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING, Annotated, Any

import typer
import typer.core
import typer.main

from targetacq import __version__

if TYPE_CHECKING:
    from typer import _click

__all__ = ["COMMANDS", "all_commands", "app", "main"]

FORMATS = ("table", "json", "csv")

COMMANDS: dict[str, tuple[str, str]] = {
    "dri": ("dri", "Ranges at which each task reaches a probability (DRI ranges)."),
    "sweep": ("sweep", "Trade study: every combination of the options' lists of values."),
    "design": ("design", "The focal length, pitch or IFOV that meets a range requirement."),
    "atmosphere": ("dri", "Transmittance, SNR and Table 7.2 description of a path."),
    "plot": ("figures", "Draw a figure: probability curves, transforms, atmosphere, ..."),
    "report": ("figures", "Write a self-contained report of cases or of a scenario."),
    "clutter": ("images", "Clutter, SCR, features and P(detection) of targets in an image."),
    "calibrate": ("calibration", "Fit a task's N50 (and exponent) to trial outcomes."),
    "validate": ("scenarios", "Check a scenario file without running it."),
    "evaluate": ("scenarios", "Evaluate every sensor x target x time of a scenario."),
    "simulate": ("scenarios", "Random search over time: who is found, and when."),
    "validation": ("validation", "Write the validation page: published values vs the model's."),
    "examples": ("examples", "List the bundled examples, or copy them into a folder."),
    "serve": ("serve", "Run the local web explorer and its JSON API (loopback by default)."),
}
"""Command → (its module in ``targetacq.cli``, its summary in ``targetacq --help``), in the
order listed. A command registers itself on :data:`app` when its module is imported; a test
keeps this table equal to the commands the modules register."""


class _LazyGroup(typer.core.TyperGroup):
    """The root command: loads a command's module when the command is first needed.

    While the root's own help is written, or command names are completed, a command not yet
    loaded is stood for by its name and summary (:data:`COMMANDS`), so that neither imports
    any command module."""

    _summaries_only = False

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        for command in self.commands.values():  # those registered before the group was built
            self._summarise(command)

    @staticmethod
    def _summarise(command: _click.Command) -> None:
        if command.short_help is None and command.name in COMMANDS:
            command.short_help = COMMANDS[command.name][1]

    def list_commands(self, ctx: _click.Context) -> list[str]:
        return list(dict.fromkeys([*_available(), *self.commands]))

    def get_command(self, ctx: _click.Context, cmd_name: str) -> _click.Command | None:
        if cmd_name not in self.commands:
            if self._summaries_only and cmd_name in _available():
                return typer.core.TyperCommand(cmd_name, short_help=COMMANDS[cmd_name][1])
            _load(cmd_name if cmd_name in _available() else None)
            self._add_registered()
        return self.commands.get(cmd_name)

    def _add_registered(self) -> None:
        """Add the click commands of every command registered on :data:`app` since last time."""
        short, markup = app.pretty_exceptions_short, app.rich_markup_mode
        built: set[int] = self.__dict__.setdefault("_built", set())
        for info in app.registered_commands:
            if id(info) not in built:
                built.add(id(info))
                self._add_loaded(
                    typer.main.get_command_from_info(
                        info, pretty_exceptions_short=short, rich_markup_mode=markup
                    )
                )
        for group in app.registered_groups:
            if id(group) not in built:
                built.add(id(group))
                self._add_loaded(
                    typer.main.get_group_from_info(
                        group,
                        pretty_exceptions_short=short,
                        rich_markup_mode=markup,
                        suggest_commands=app.suggest_commands,
                    )
                )

    def _add_loaded(self, command: _click.Command) -> None:
        if command.name and command.name not in self.commands:
            self._summarise(command)
            self.add_command(command)

    def format_help(self, ctx: _click.Context, formatter: Any) -> None:
        with self._summaries():
            super().format_help(ctx, formatter)

    def shell_complete(self, ctx: _click.Context, incomplete: str) -> list[Any]:
        with self._summaries():
            return super().shell_complete(ctx, incomplete)

    @contextmanager
    def _summaries(self) -> Iterator[None]:
        self._summaries_only = True
        try:
            yield
        finally:
            self._summaries_only = False


@functools.cache
def _available() -> tuple[str, ...]:
    """The commands of :data:`COMMANDS` whose module is in this installation."""
    from importlib.util import find_spec

    return tuple(n for n, (module, _) in COMMANDS.items() if find_spec(f"{__name__}.{module}"))


def _load(command: str | None) -> None:
    """Import the module of ``command`` (every command module for None: an unknown name)."""
    if command is None:
        _import_commands()
    else:
        importlib.import_module(f"{__name__}.{COMMANDS[command][0]}")


def all_commands() -> dict[str, Any]:
    """Every command of ``targetacq``: name → its click command (every module imported).

    Examples
    --------
    >>> "dri" in all_commands()
    True
    """
    group = _click_command()
    _import_commands()
    for name in _available():
        _load(name)
    group._add_registered()
    return dict(group.commands)


DEFAULT_EXAMPLE = "uav_haze.toml"

app = typer.Typer(
    cls=_LazyGroup,
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    help="Probabilities and ranges of detection, recognition and identification for imaging "
    "sensors (Sonesson 2004 conceptual sensor model).\n\n"
    "Example: targetacq dri --example",
)


def _complete(names: Any, **kwargs: Any) -> Any:
    from targetacq.cli.params import complete_names

    return complete_names(names, **kwargs)


FormatOption = Annotated[
    str,
    typer.Option(
        "--format",
        help=f"Output: {', '.join(FORMATS)}.",
        autocompletion=_complete(FORMATS, separator=None),
    ),
]

if TYPE_CHECKING:  # built by __getattr__ below
    BandOption = Annotated[str | None, "--band"]
    ExtinctionOption = Annotated[str | None, "--extinction"]
    ObscurantOption = Annotated[str | None, "--obscurant"]
    VisibilityOption = Annotated[str | None, "--visibility"]
    ConventionOption = Annotated[str | None, "--visibility-convention"]

_SHARED_OPTIONS = (
    "BandOption",
    "ExtinctionOption",
    "ObscurantOption",
    "VisibilityOption",
    "ConventionOption",
)


def __getattr__(name: str) -> Any:
    """The option annotations shared by several commands, defined once: built on first use
    (their help texts need the registries, which a command's module imports anyway)."""
    if name not in _SHARED_OPTIONS:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    from targetacq.cli.params import Quantity
    from targetacq.physics.atmosphere import EXTINCTION_LEVELS, OBSCURANTS, VISIBILITY_CONVENTIONS
    from targetacq.physics.bands import BANDS

    length = Quantity("length", "--visibility", lists=False)
    extinction = Quantity("extinction", "--extinction", lists=False)
    options = {
        "BandOption": typer.Option(
            help=f"Sensor band: {', '.join(BANDS)} or e.g. 8-12um.",
            autocompletion=_complete(BANDS, separator=None),
        ),
        "ExtinctionOption": typer.Option(
            help="Path extinction, e.g. 0.4/km (Np/km) or 1.7dB/km.",
            parser=extinction,
            metavar=extinction.metavar,
        ),
        "ObscurantOption": typer.Option(
            help=f"Table 7.1 obscurant[:low|nominal|high]: {', '.join(OBSCURANTS)}.",
            autocompletion=_complete(OBSCURANTS, separator=None, levels=EXTINCTION_LEVELS),
        ),
        "VisibilityOption": typer.Option(
            help="Visibility (visible band), e.g. 7.5km.", parser=length, metavar=length.metavar
        ),
        "ConventionOption": typer.Option(
            help=f"Visibility convention: {', '.join(VISIBILITY_CONVENTIONS)}.",
            autocompletion=_complete(VISIBILITY_CONVENTIONS, separator=None),
        ),
    }
    for key, option in options.items():
        globals()[key] = Annotated[str | None, option]
    return globals()[name]


def _show_version(value: bool) -> None:
    if value:
        typer.echo(f"targetacq {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    version: Annotated[
        bool,
        typer.Option(
            "--version",
            callback=_show_version,
            is_eager=True,
            help="Print the version and exit.",
        ),
    ] = False,
) -> None:
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


def _model_line(report: dict[str, Any]) -> str:
    """The first line of a dri or design table: the criterion, the transform and its options."""
    return (
        f"criterion {report['criterion']}"
        + (f", transform {report['transform']}" if report["transform"] else "")
        + "".join(f", {k} {v}" for k, v in report["options"].items())
    )


def _render_rows(rows: list[dict[str, Any]], output_format: str) -> str:
    if output_format == "json":
        from targetacq.io.files import json_text

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


# Help written anywhere but a terminal (a pipe, a file, the docs) is laid out this wide:
# rich's default of 80 columns cut the longest option names ("--background-temperat…").
HELP_WIDTH = 120


def _help_width() -> None:
    """Lay the help out :data:`HELP_WIDTH` wide where stdout is not a terminal (a terminal's
    own width otherwise; ``TERMINAL_WIDTH`` in the environment wins, as typer reads it)."""
    from typer import rich_utils

    if os.environ.get("TERMINAL_WIDTH") is None and not sys.stdout.isatty():
        rich_utils.MAX_WIDTH = HELP_WIDTH


def _run(argv: list[str] | None) -> int:
    """Run the app; the exit status, after printing a failure's one line."""
    _help_width()
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


def _import_commands() -> None:
    """Import every command module (each registers its commands on :data:`app`)."""
    # The commands register themselves on `app` when their modules are imported. They are found
    # by name in COMMANDS, as plugins: each command module imports this package, never the
    # other way round.
    for module, _ in COMMANDS.values():
        if importlib.util.find_spec(f"{__name__}.{module}"):
            importlib.import_module(f"{__name__}.{module}")
