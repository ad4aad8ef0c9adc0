"""The command-line reference, generated from the ``targetacq`` command itself at build time.

The command tree is walked through its click commands (typer builds on click): every command and
sub-command, in the order of ``targetacq --help``, with its help text, usage line, arguments and
options. Each option's cell is the line ``targetacq COMMAND --help`` prints for it (its
metavar, its help with the choices the registries give, its default, whether it is required), so
the page cannot drift from the program. Options are grouped under the headings of ``--help``
(Options, Sensor, Target, Model, ...). :func:`commands` walks the tree, :func:`render` writes
the reStructuredText; the Sphinx hook writes ``docs/generated/cli.rst.inc``, included by
``docs/cli.rst``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

__all__ = ["CommandDoc", "ParameterDoc", "commands", "render", "write_reference"]

PROGRAM = "targetacq"
_HEADINGS = "-~^"
_EXTRA = re.compile(r"^(?P<text>.*?)(?:\s{2}\[(?P<extra>[^\[\]]*)\])?$", re.DOTALL)
_EXAMPLE = re.compile(r"^Examples?:\s*(?P<commands>.+)$", re.DOTALL)


@dataclass(frozen=True)
class ParameterDoc:
    """One argument or option, as ``--help`` shows it."""

    kind: str  # "argument" or "option"
    names: str  # "--pitch LENGTH[,...]", "NAME <str>"
    help: str  # the help text without the bracketed extras
    default: str | None  # as --help prints it, or None
    required: bool
    panel: str  # the heading --help lists it under: "Arguments", "Options", "Sensor", ...


@dataclass(frozen=True)
class CommandDoc:
    """One command or sub-command: its path (``("examples", "copy")``), texts and parameters."""

    path: tuple[str, ...]
    summary: str
    help: str
    usage: str
    parameters: tuple[ParameterDoc, ...]
    subcommands: tuple[str, ...]

    @property
    def name(self) -> str:
        return " ".join((PROGRAM, *self.path))

    @property
    def label(self) -> str:
        """The reference label of its section: ``cli-examples-copy`` (``cli`` for the root)."""
        return "-".join(("cli", *self.path))


def _parameter(param: Any, ctx: Any) -> ParameterDoc | None:
    record = param.get_help_record(ctx)
    if record is None or getattr(param, "hidden", False):
        return None
    names, text = record
    match = _EXTRA.match(text)
    assert match is not None  # the pattern matches any text
    extras = [e.strip() for e in (match.group("extra") or "").split(";") if e.strip()]
    default = next((e.split(":", 1)[1].strip() for e in extras if e.startswith("default:")), None)
    return ParameterDoc(
        kind=param.param_type_name,
        names=names,
        help=" ".join(match.group("text").split()),
        default=default,
        required=bool(param.required),
        panel=getattr(param, "rich_help_panel", None)
        or ("Arguments" if param.param_type_name == "argument" else "Options"),
    )


def _usage(command: Any, ctx: Any) -> str:
    usage = " ".join(command.get_usage(ctx).split())
    return usage.removeprefix("Usage:").strip()


def _walk(command: Any, ctx: Any, path: tuple[str, ...]) -> list[CommandDoc]:
    import typer

    names: list[str] = []
    if hasattr(command, "list_commands"):  # a group
        names = [n for n in command.list_commands(ctx) if not command.get_command(ctx, n).hidden]
    parameters = tuple(
        p
        for p in (_parameter(param, ctx) for param in command.get_params(ctx))
        if p is not None and p.names.split()[0] != "--help"
    )
    doc = CommandDoc(
        path=path,
        summary=command.get_short_help_str(limit=200),
        help=(command.help or "").strip(),
        usage=_usage(command, ctx),
        parameters=parameters,
        subcommands=tuple(names),
    )
    found = [doc]
    for name in names:
        sub = command.get_command(ctx, name)
        found += _walk(sub, typer.Context(sub, info_name=name, parent=ctx), (*path, name))
    return found


def commands() -> list[CommandDoc]:
    """Every command of ``targetacq``, the root first, then each in the order of its ``--help``
    (a group followed by its sub-commands)."""
    import typer
    import typer.main

    from targetacq.cli import app

    root = typer.main.get_command(app)
    return _walk(root, typer.Context(root, info_name=PROGRAM), ())


def _prose(text: str) -> str:
    """Help text as reStructuredText: ```x``` spans become literals, markup characters are
    escaped, lines are joined."""
    parts = re.split(r"(`[^`]+`)", " ".join(text.split()))
    out = []
    for part in parts:
        if part.startswith("`") and part.endswith("`") and len(part) > 2:
            out.append(f"``{part[1:-1]}``")
            continue
        for char in ("\\", "*", "|", "_", "`"):
            part = part.replace(char, "\\" + char)
        out.append(part)
    return "".join(out)


def _help_blocks(text: str) -> list[str]:
    """The paragraphs of a command's help: an ``Example:`` paragraph becomes a console block."""
    blocks = []
    for paragraph in re.split(r"\n\s*\n", text):
        paragraph = "\n".join(line for line in paragraph.splitlines() if line.strip() != "\b")
        if not paragraph.strip():
            continue
        example = _EXAMPLE.match(paragraph.strip())
        if example:
            command = " ".join(example.group("commands").split())
            blocks.append(f"Example:\n\n.. code-block:: console\n\n   $ {command}")
        else:
            blocks.append(_prose(paragraph))
    return blocks


def _table(title: str, parameters: list[ParameterDoc]) -> list[str]:
    lines = [
        f"**{title}**",
        "",
        ".. list-table::",
        "   :header-rows: 1",
        "   :widths: 28 56 16",
        "   :class: cli-options",
        "",
        "   * - name",
        "     - what it is",
        "     - default",
    ]
    for p in parameters:
        default = "required" if p.required else (f"``{p.default}``" if p.default else "")
        lines += [
            f"   * - ``{p.names}``",
            f"     - {_prose(p.help) or ' '}",
            f"     - {default or ' '}",
        ]
    return [*lines, ""]


def render(docs: list[CommandDoc]) -> str:
    """The reStructuredText of the reference: one section per command, sub-commands nested."""
    lines: list[str] = []
    summaries = {d.path: d.summary for d in docs}
    for doc in docs:
        title = f"``{doc.name}``"
        level = max(len(doc.path) - 1, 0)
        lines += [f".. _{doc.label}:", "", title, _HEADINGS[level] * len(title), ""]
        first = " ".join(doc.help.split())
        if doc.path and not first.startswith(doc.summary.rstrip(".")):
            lines += [f"*{_prose(doc.summary)}*", ""]
        for block in _help_blocks(doc.help):
            lines += [block, ""]
        lines += ["Usage:", "", ".. code-block:: text", "", f"   {doc.usage}", ""]
        if doc.subcommands:  # as --help lists them: name and summary
            lines += ["Commands:" if not doc.path else "Sub-commands:", ""]
            for sub in doc.subcommands:
                summary = _prose(summaries[(*doc.path, sub)])
                lines.append(f"- :ref:`{sub} <{doc.label}-{sub}>`: {summary}")
            lines.append("")
        panels: dict[str, list[ParameterDoc]] = {}  # as --help groups them, in its order
        for p in doc.parameters:
            panels.setdefault(p.panel, []).append(p)
        for panel, parameters in panels.items():
            lines += _table(panel, parameters)
    return "\n".join(lines).rstrip() + "\n"


def write_reference(path: Path) -> Path:
    """Write the reference to ``path``, only if its text changed (Sphinx re-reads a page whose
    include changed)."""
    text = render(commands())
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")
    return path


def _on_builder_inited(app: Any) -> None:
    write_reference(Path(app.srcdir) / "generated" / "cli.rst.inc")


def setup(app: Any) -> dict[str, Any]:
    """Sphinx entry point."""
    app.connect("builder-inited", _on_builder_inited)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
