"""Every command and every Python block of README.md runs as written.

The README is read when the tests are collected, so a command added to it is covered without
touching this file. Each test runs in a temporary folder holding a copy of the repository's
``examples/`` (the README's paths are relative to the repository root), so outputs land there.

- shell commands: every ``targetacq ...`` line of a ```` ```sh ```` block, every ``$ targetacq
  ...`` line of a ```` ```console ```` block (``\\`` continuations joined, ``#`` comments
  dropped), and every inline ```targetacq ...``` span of the prose (unless it has a placeholder
  such as ``NAME``); ``make ...`` lines are left to CI. Each must exit with status 0 under umask
  022, and each file it writes (``--out``, ``--overlay``, ``--figure``) must exist with mode
  0644 (a Zarr folder 0755);
- Python: the ```` ```python ```` blocks, in order, in one interpreter (they share names), in
  an empty folder: a bundled example is found with ``targetacq.example_path``, as from a wheel.
"""

from __future__ import annotations

import contextlib
import os
import re
import shlex
import shutil
import stat
import subprocess
import sys
import textwrap
import time
import warnings
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[2]
README = ROOT / "README.md"
EXAMPLES = ROOT / "examples"

# Options naming a file the command writes.
OUTPUT_OPTIONS = ("--out", "--overlay", "--figure")
SHELL_OPERATORS = {"|", "||", "&&", ";", ">", ">>", "<", "2>", "&"}
PLACEHOLDER = re.compile(r"^[A-Z][A-Z0-9_]{1,}$")
FENCE = re.compile(r"^```(\S*)\s*$")
INLINE = re.compile(r"`(targetacq [^`]+)`")
SLOW_SECONDS = 20.0


@dataclass(frozen=True)
class Command:
    line: int  # where it starts in README.md
    text: str  # as written, continuations joined

    @property
    def argv(self) -> list[str]:
        return shlex.split(self.text, comments=True)

    def __str__(self) -> str:
        return f"README.md:{self.line}: {self.text}"


@dataclass(frozen=True)
class Block:
    line: int  # the first line of code
    language: str
    code: str


def blocks(text: str) -> list[Block]:
    """The fenced code blocks of a Markdown text."""
    found = []
    lines = text.splitlines()
    k = 0
    while k < len(lines):
        opened = FENCE.match(lines[k])
        if opened is None:
            k += 1
            continue
        start = k + 1
        end = start
        while end < len(lines) and not lines[end].startswith("```"):
            end += 1
        found.append(Block(start + 1, opened.group(1).lower(), "\n".join(lines[start:end]) + "\n"))
        k = end + 1
    return found


def _joined(block: Block) -> Iterator[tuple[int, str]]:
    """(line number, line) of a block with ``\\`` continuations joined."""
    pending: list[str] = []
    first = 0
    for offset, line in enumerate(block.code.splitlines()):
        if not pending:
            first = block.line + offset
        stripped = line.rstrip()
        if stripped.endswith("\\"):
            pending.append(stripped[:-1].strip())
            continue
        pending.append(stripped.strip())
        yield first, " ".join(p for p in pending if p)
        pending = []
    if pending:
        yield first, " ".join(p for p in pending if p)


def shell_commands(text: str) -> list[Command]:
    """The ``targetacq`` commands of a README text (see the module docstring)."""
    commands = []
    for block in blocks(text):
        if block.language in ("sh", "bash", "shell"):
            prompt = ""
        elif block.language == "console":
            prompt = "$ "
        else:
            continue
        for line, joined in _joined(block):
            if joined.startswith(prompt + "targetacq ") or joined == prompt + "targetacq":
                commands.append(Command(line, joined[len(prompt) :]))
    # Inline spans in the prose (outside code blocks), e.g. `targetacq atmosphere --range 1km`.
    fenced = {n for b in blocks(text) for n in range(b.line - 1, b.line + b.code.count("\n") + 1)}
    prose = "\n".join("" if n in fenced else line for n, line in enumerate(text.splitlines(), 1))
    for match in INLINE.finditer(prose):
        span = " ".join(match.group(1).split())
        if any(PLACEHOLDER.match(word) for word in span.split()[1:]):
            continue  # a synopsis such as `targetacq examples copy NAME DIR`
        commands.append(Command(prose.count("\n", 0, match.start()) + 1, span))
    return commands


README_TEXT = README.read_text(encoding="utf-8")
COMMANDS = shell_commands(README_TEXT)
PYTHON_BLOCKS = [b for b in blocks(README_TEXT) if b.language in ("python", "py")]


@pytest.fixture
def workdir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A temporary folder with a copy of ``examples/``, as the current directory."""
    shutil.copytree(EXAMPLES, tmp_path / "examples", ignore=shutil.ignore_patterns("__pycache__"))
    monkeypatch.chdir(tmp_path)
    return tmp_path


@contextlib.contextmanager
def umask(mask: int) -> Iterator[None]:
    previous = os.umask(mask)
    try:
        yield
    finally:
        os.umask(previous)


def outputs(argv: list[str]) -> list[str]:
    """The files a command names with an output option."""
    found = []
    for k, arg in enumerate(argv):
        for option in OUTPUT_OPTIONS:
            if arg == option and k + 1 < len(argv):
                found.append(argv[k + 1])
            elif arg.startswith(option + "="):
                found.append(arg.split("=", 1)[1])
    return found


def run_in_process(capsys: pytest.CaptureFixture[str], argv: list[str]) -> tuple[Any, str, str]:
    """``targetacq argv[1:]`` through its entry point: (exit status, stdout, stderr)."""
    from targetacq.cli import main

    capsys.readouterr()
    code: Any = None
    with warnings.catch_warnings():
        warnings.simplefilter("default")  # the entry point records and prints them itself
        try:
            main(argv[1:])
        except SystemExit as done:
            code = done.code
        else:
            code = 0
    out, err = capsys.readouterr()
    return code, out, err


def run_in_shell(command: str) -> tuple[Any, str, str]:
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"}
    done = subprocess.run(
        ["bash", "-c", command], capture_output=True, text=True, env=env, timeout=600, check=False
    )
    return done.returncode, done.stdout, done.stderr


def test_the_readme_has_commands_and_python_blocks() -> None:
    """The parser finds the README's examples (a parser finding nothing would pass every run)."""
    assert len(COMMANDS) >= 10, [str(c) for c in COMMANDS]
    assert len(PYTHON_BLOCKS) >= 3
    names = {c.argv[1] for c in COMMANDS if len(c.argv) > 1}
    assert {"dri", "evaluate", "clutter", "plot", "report"} <= names, names


def test_the_parser_joins_continuations_and_drops_prompts_and_comments() -> None:
    text = textwrap.dedent(
        """\
        Run `targetacq atmosphere --range
        1km --band lwir` or `targetacq examples copy NAME DIR`.

        ```sh
        make run    # not ours
        targetacq plot curves --example \\
            --out curves.png      # a comment
        ```

        ```console
        $ targetacq dri --example
        targetacq: output, not a command
        ```
        """
    )
    got = [(c.line, c.text, c.argv) for c in shell_commands(text)]
    assert got == [
        (
            6,
            "targetacq plot curves --example --out curves.png      # a comment",
            ["targetacq", "plot", "curves", "--example", "--out", "curves.png"],
        ),
        (11, "targetacq dri --example", ["targetacq", "dri", "--example"]),
        (
            1,
            "targetacq atmosphere --range 1km --band lwir",
            ["targetacq", "atmosphere", "--range", "1km", "--band", "lwir"],
        ),
    ]


def _id(command: Command) -> str:
    return f"line{command.line}:{' '.join(command.argv[1:])[:60]}"


@pytest.mark.parametrize("command", COMMANDS, ids=[_id(c) for c in COMMANDS])
def test_readme_command_runs_as_written(
    command: Command, workdir: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = command.argv
    start = time.perf_counter()
    with umask(0o022):
        if SHELL_OPERATORS & set(argv):
            code, out, err = run_in_shell(command.text)
        else:
            code, out, err = run_in_process(capsys, argv)
    seconds = time.perf_counter() - start
    assert code == 0, f"{command}\nexit status {code}\nstderr: {err[-2000:]}"
    assert "Traceback" not in err, f"{command}\n{err[-2000:]}"
    assert out.strip() or outputs(argv), f"{command}: printed nothing and wrote nothing"
    for name in outputs(argv):
        path = workdir / name
        if path.is_dir():  # a Zarr store: a folder of files
            written = [p for p in path.rglob("*") if p.is_file()]
            assert written, f"{command}: {name} is an empty folder"
            expected = {path: 0o755, **dict.fromkeys(written, 0o644)}
        else:
            assert path.is_file() and path.stat().st_size > 0, f"{command}: no {name} written"
            expected = {path: 0o644}
        for item, want in expected.items():
            mode = stat.S_IMODE(item.stat().st_mode)
            assert mode == want, (
                f"{command}: {item.relative_to(workdir)} has mode {mode:o} under umask 022, "
                f"not {want:o}"
            )
    if seconds > SLOW_SECONDS:  # worth knowing; not a failure
        print(f"slow README command ({seconds:.0f} s): {command}")


# The Python blocks run in one interpreter, in order, each reported by its README line.
RUNNER = """\
import sys, traceback
blocks = {blocks!r}
namespace = {{"__name__": "__main__"}}
for line, code in blocks:
    try:
        exec(compile(code, f"README.md (python block at line {{line}})", "exec"), namespace)
    except BaseException:
        traceback.print_exc()
        print(f"README.md: the python block at line {{line}} failed", file=sys.stderr)
        sys.exit(1)
"""


def test_readme_python_blocks_run_in_order(tmp_path: Path) -> None:
    """In an empty folder, as a user of the installed package runs them: a block that needs a
    bundled example finds it with ``targetacq.example_path``, not in ``./examples``."""
    # Each block starts at its README line number, so tracebacks point into README.md.
    code = RUNNER.format(blocks=[(b.line, "\n" * (b.line - 1) + b.code) for b in PYTHON_BLOCKS])
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


def test_clutter_overlay_gets_the_umask_mode(
    workdir: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """`clutter --overlay` (not covered by the bad-input catalogue's umask cases) writes 0644
    under umask 022 and 0640 under 027."""
    for mask, expected in ((0o022, 0o644), (0o027, 0o640)):
        out = workdir / f"cells-{mask:o}.png"
        argv = ["targetacq", "clutter", "examples/scene.png", "--box", "412,118,20,20"]
        with umask(mask):
            code, _, err = run_in_process(capsys, [*argv, "--overlay", str(out)])
        assert code == 0, err
        mode = stat.S_IMODE(out.stat().st_mode)
        assert mode == expected, f"umask {mask:03o}: mode {mode:o}, expected {expected:o}"
