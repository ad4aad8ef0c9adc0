"""The `examples` commands: list the bundled examples, and copy them into a folder.

The examples are the package data in ``targetacq/examples`` (scenario files, scripts, images
and the box files of the ``clutter`` command): :func:`targetacq.base.bundled.example_files` finds
them in an installed wheel as in a checkout, and :func:`targetacq.example_path` gives one's path
to Python code. Each one's description is the first
sentence of its leading comment or docstring; a file without one (an image) is described by
the line that names it in another example's docstring (``- ``scene.png``: ...``).
"""

from __future__ import annotations

import contextlib
import functools
import re
from pathlib import Path
from typing import Annotated

import typer

from targetacq.base.bundled import example_files, example_name
from targetacq.base.registry import unknown_name
from targetacq.cli import app

__all__ = ["example_descriptions", "example_files"]

examples_app = typer.Typer(
    no_args_is_help=True,
    help="List the bundled examples, or copy them into a folder.\n\n"
    "Example: targetacq examples copy uav_haze.toml my-study",
)
app.add_typer(examples_app, name="examples")

_TEXT_SUFFIXES = {".toml", ".py", ".csv", ".txt", ".md", ".json"}
_LISTED = re.compile(r"^\s*[-*]\s+``([^`]+)``\s*:\s*(.+)$")


def _first_sentence(lines: list[str]) -> str:
    """The first sentence: up to a full stop followed by a capital letter or the end (so
    ``Eq. (8.4)`` and ``e.g. 17um`` do not end it)."""
    text = " ".join(line.strip() for line in lines if line.strip())
    match = re.match(r"(.+?[.!?])(\s+(?=[A-Z])|$)", text)
    return (match.group(1) if match else text).strip()


def _leading_text(name: str, text: str) -> list[str]:
    """The leading comment block (``#`` lines) or docstring of a text file."""
    lines = text.splitlines()
    if name.endswith(".py"):
        stripped = text.lstrip()
        for quote in ('"""', "'''"):
            if stripped.startswith(quote):
                body = stripped[3:].split(quote, 1)[0]
                return body.split("\n\n", 1)[0].splitlines()
    comments = []
    for line in lines:
        if line.startswith("#"):
            comments.append(line.lstrip("#"))
        elif comments or line.strip():
            break
    return comments


def example_descriptions() -> dict[str, str]:
    """Each bundled example's one-line description: name → text.

    Examples
    --------
    >>> example_descriptions()["uav_haze.toml"]  # doctest: +ELLIPSIS
    'A UAV with an uncooled long-wave thermal camera ... (Table 7.1, 8-12 um: 0.4 Np/km).'
    """
    files = example_files()
    texts: dict[str, str] = {}
    for name, entry in files.items():
        if Path(name).suffix in _TEXT_SUFFIXES:
            with contextlib.suppress(UnicodeDecodeError, OSError):
                texts[name] = entry.read_text(encoding="utf-8")
    named: dict[str, str] = {}  # "- ``scene.png``: ..." lines of the other examples
    for text in texts.values():
        lines = text.splitlines()
        for number, line in enumerate(lines):
            match = _LISTED.match(line)
            if match and match.group(1) in files:
                item = [match.group(2)]  # with its continuation lines, up to the first ";"
                for more in lines[number + 1 :]:
                    if not more.startswith("  ") or _LISTED.match(more):
                        break
                    item.append(more)
                joined = " ".join(part.strip() for part in item)
                named.setdefault(match.group(1), joined.split(";")[0].rstrip(",. "))
    out = {}
    for name in files:
        lines = _leading_text(name, texts[name]) if name in texts else []
        description = _first_sentence(lines) if lines else named.get(name, "")
        out[name] = description or f"{Path(name).suffix.lstrip('.').upper()} file"
    return out


def _complete_example(incomplete: str) -> list[str]:
    return [name for name in ("all", *example_files()) if name.startswith(incomplete)]


@examples_app.command("list")
def list_command() -> None:
    """List the bundled examples, one a line: name and description.

    Example: targetacq examples list
    """
    descriptions = example_descriptions()
    width = max(map(len, descriptions), default=0)
    for name, description in descriptions.items():
        typer.echo(f"{name:<{width}}  {description}")


@examples_app.command("copy")
def copy_command(
    name: Annotated[
        str,
        typer.Argument(
            metavar="NAME",
            help="An example's name (see `targetacq examples list`; the suffix may be left "
            "out), or all.",
            autocompletion=_complete_example,
        ),
    ],
    folder: Annotated[
        str, typer.Argument(metavar="DIR", help="Folder to copy into (made if needed).")
    ],
    force: Annotated[
        bool, typer.Option("--force", help="Replace files that already exist.")
    ] = False,
) -> None:
    """Copy a bundled example, or all, into a folder (an existing file is kept: see --force).

    Example: targetacq examples copy all my-examples
    """
    from targetacq.io.files import write_atomically

    files = example_files()
    if name == "all":
        chosen = list(files)
    elif name in files or name in {Path(file).stem for file in files}:
        chosen = [example_name(name)]  # its file name (the suffix may be left out)
    else:
        raise unknown_name(name, ["all", *files], "example")
    target = Path(folder)
    if target.exists() and not target.is_dir():
        raise ValueError(f"cannot copy into {folder!r}: it is not a folder")
    existing = [n for n in chosen if (target / n).exists()]
    if existing and not force:
        raise ValueError(
            f"{', '.join(str(target / n) for n in existing)} already "
            f"{'exists' if len(existing) == 1 else 'exist'}; give --force to replace"
        )
    target.mkdir(parents=True, exist_ok=True)
    for n in chosen:
        written = write_atomically(target / n, functools.partial(_write, files[n].read_bytes()))
        typer.echo(f"wrote {written}")


def _write(data: bytes, path: Path) -> None:
    path.write_bytes(data)
