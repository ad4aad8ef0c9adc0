"""The commands and Python blocks of the documentation's pages run as written, and print what the
pages show.

The pages (``docs/*.rst``, ``docs/user_guide/*.rst``) are read when the tests are collected:

- every ``$ targetacq ...`` line of a ``.. code-block:: console`` (``\\`` continuations joined)
  runs through the command's entry point in an empty temporary folder, and must exit with status
  0 and write the files it names (``--out``, ``--figure``). The lines shown after it are its
  output, shortened where a line is ``...``: each other line must be a line of the real output
  (spaces collapsed), so that a page never shows numbers the program no longer prints;
- the ``.. code-block:: python`` blocks of a page run in order in one interpreter (they share
  names), in an empty folder, with warnings as errors.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
import textwrap
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
PAGES = sorted([*DOCS.glob("*.rst"), *(DOCS / "user_guide").glob("*.rst")])
DIRECTIVE = re.compile(r"^(?P<indent>\s*)\.\. code-block::\s*(?P<language>\S+)\s*$")
OUTPUT_OPTIONS = ("--out", "--figure", "--overlay")
ELISION = "..."


@dataclass(frozen=True)
class Block:
    page: Path
    line: int  # the first line of code, 1-based
    language: str
    code: str


@dataclass(frozen=True)
class Command:
    page: Path
    line: int
    text: str  # continuations joined
    shown: tuple[str, ...]  # the output lines the page shows after it

    @property
    def argv(self) -> list[str]:
        return shlex.split(self.text)

    def __str__(self) -> str:
        return f"{self.page.relative_to(ROOT)}:{self.line}: $ {self.text}"


def code_blocks(page: Path, text: str | None = None) -> list[Block]:
    """The ``.. code-block::`` directives of a reStructuredText page, their code dedented."""
    lines = (page.read_text(encoding="utf-8") if text is None else text).splitlines()
    found = []
    k = 0
    while k < len(lines):
        match = DIRECTIVE.match(lines[k])
        k += 1
        if match is None:
            continue
        indent = len(match.group("indent"))
        while k < len(lines) and re.match(r"^\s+:\w[\w-]*:", lines[k]):  # directive options
            k += 1
        body: list[str] = []
        start = k
        while k < len(lines) and (
            not lines[k].strip() or len(lines[k]) - len(lines[k].lstrip()) > indent
        ):
            body.append(lines[k])
            k += 1
        while body and not body[0].strip():
            body.pop(0)
            start += 1
        code = textwrap.dedent("\n".join(body)).strip("\n") + "\n"
        found.append(Block(page, start + 1, match.group("language").lower(), code))
    return found


def console_commands(block: Block) -> list[Command]:
    """The ``$ targetacq`` commands of a console block, each with the output lines it shows."""
    commands: list[Command] = []
    lines = block.code.splitlines()
    k = 0
    while k < len(lines):
        if not lines[k].startswith("$ "):
            k += 1
            continue
        first = k
        parts = [lines[k][2:].rstrip()]
        while parts[-1].endswith("\\") and k + 1 < len(lines):
            parts[-1] = parts[-1][:-1].strip()
            k += 1
            parts.append(lines[k].strip())
        k += 1
        shown = []
        while k < len(lines) and not lines[k].startswith("$ "):
            shown.append(lines[k])
            k += 1
        text = " ".join(p for p in parts if p)
        if text.split()[0] == "targetacq":
            commands.append(Command(block.page, block.line + first, text, tuple(shown)))
    return commands


BLOCKS = [block for page in PAGES for block in code_blocks(page)]
COMMANDS = [c for b in BLOCKS if b.language == "console" for c in console_commands(b)]
PYTHON_PAGES = sorted({b.page for b in BLOCKS if b.language == "python"})


def _collapse(line: str) -> str:
    return " ".join(line.split())


def test_the_parser_reads_directives_continuations_and_outputs(tmp_path: Path) -> None:
    text = textwrap.dedent(
        """\
        Text.

        .. code-block:: console
           :caption: two commands

           $ targetacq dri --pitch 17um \\
               --focal-length 50mm
           criterion johnson
           ...
           $ make docs

        .. code-block:: python

           import targetacq
        after
        """
    )
    page = tmp_path / "page.rst"
    blocks = code_blocks(page, text)
    assert [(b.line, b.language) for b in blocks] == [(6, "console"), (14, "python")]
    assert blocks[1].code == "import targetacq\n"
    commands = console_commands(blocks[0])
    assert [(c.line, c.text, c.shown) for c in commands] == [
        (6, "targetacq dri --pitch 17um --focal-length 50mm", ("criterion johnson", "..."))
    ]


def test_the_pages_have_the_trade_study_commands() -> None:
    """The parser finds the how-to's commands (a parser finding nothing would pass every run)."""
    howto = [c for c in COMMANDS if c.page.name == "trade_study.rst"]
    assert {c.argv[1] for c in howto} >= {"design", "sweep", "report", "atmosphere"}
    assert any("," in arg for c in howto if c.argv[1] == "report" for arg in c.argv)  # multi-case
    assert all(c.shown for c in howto)
    assert DOCS / "trade_study.rst" in PYTHON_PAGES


def _run(capsys: pytest.CaptureFixture[str], argv: list[str]) -> tuple[Any, str, str]:
    from targetacq.cli import main

    capsys.readouterr()
    code: Any = 0
    with warnings.catch_warnings():
        warnings.simplefilter("default")  # the entry point records and prints them itself
        try:
            main(argv[1:])
        except SystemExit as done:
            code = done.code
    out, err = capsys.readouterr()
    return code, out, err


def _id(command: Command) -> str:
    return f"{command.page.stem}:{command.line}:{' '.join(command.argv[1:])[:50]}"


@pytest.mark.parametrize("command", COMMANDS, ids=[_id(c) for c in COMMANDS])
def test_docs_command_runs_as_written_and_prints_what_the_page_shows(
    command: Command,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    monkeypatch.chdir(tmp_path)
    code, out, err = _run(capsys, command.argv)
    assert code == 0, f"{command}\nexit status {code}\nstderr: {err[-2000:]}"
    argv = command.argv
    for k, arg in enumerate(argv[:-1]):
        if arg in OUTPUT_OPTIONS:
            written = tmp_path / argv[k + 1]
            assert written.exists() and written.stat().st_size > 0, f"{command}: no {written}"
    printed = {_collapse(line) for line in (out + err).splitlines()}
    missing = [
        line
        for line in command.shown
        if line.strip() and line.strip() != ELISION and _collapse(line) not in printed
    ]
    assert not missing, (
        f"{command}\nthe page shows lines the command does not print (update the page):\n"
        + "\n".join(missing)
        + f"\n--- it prints:\n{out}{err}"
    )


RUNNER = """\
import sys, traceback
namespace = {"__name__": "__main__"}
for line, code in BLOCKS:
    try:
        exec(compile(code, f"PAGE (python block at line {line})", "exec"), namespace)
    except BaseException:
        traceback.print_exc()
        print(f"PAGE: the python block at line {line} failed", file=sys.stderr)
        sys.exit(1)
"""


@pytest.mark.parametrize("page", PYTHON_PAGES, ids=[p.stem for p in PYTHON_PAGES])
def test_docs_python_blocks_run_in_order(page: Path, tmp_path: Path) -> None:
    python = [b for b in BLOCKS if b.page == page and b.language == "python"]
    blocks = [(b.line, "\n" * (b.line - 1) + b.code) for b in python]
    code = RUNNER.replace("PAGE", str(page.relative_to(ROOT))).replace("BLOCKS", repr(blocks), 1)
    env = {**os.environ, "MPLBACKEND": "Agg", "PYTHONWARNINGS": "error"}
    done = subprocess.run(
        [sys.executable, "-c", code],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
        check=False,
    )
    assert done.returncode == 0, done.stderr[-4000:]
