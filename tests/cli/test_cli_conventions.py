"""The conventions of a command-line tool: --version, shell completion, an example in every
command's help, a quick start (lazy imports), and the bundled examples listed and copied."""

from __future__ import annotations

import ast
import os
import stat
import subprocess
import sys
from pathlib import Path

import pytest

import targetacq
from targetacq.cli import COMMANDS, all_commands, main


def run(capsys, *args):
    with pytest.raises(SystemExit) as exit_:
        main(list(args))
    out, err = capsys.readouterr()
    return exit_.value.code, out, err


def _subcommands(command, path=()):
    """(path, click command) of every command and subcommand, depth first."""
    yield path, command
    for name, sub in getattr(command, "commands", {}).items():
        yield from _subcommands(sub, (*path, name))


# --- --version ---------------------------------------------------------------------------------


def test_version_prints_the_package_version(capsys):
    code, out, err = run(capsys, "--version")
    assert (code, out, err) == (0, f"targetacq {targetacq.__version__}\n", "")
    assert targetacq.__version__ == "0.1.0"


# --- an example in every command's help --------------------------------------------------------


def test_every_command_help_has_an_example(capsys):
    missing = []
    for name, command in all_commands().items():
        for path, _ in _subcommands(command, (name,)):
            code, out, _ = run(capsys, *path, "--help")
            assert code == 0
            lines = [line.strip(" │") for line in out.splitlines()]
            examples = [line for line in lines if line.startswith("Example: targetacq ")]
            if not examples:
                missing.append(" ".join(path))
    code, out, _ = run(capsys, "--help")
    if "Example: targetacq " not in out:
        missing.append("(targetacq itself)")
    assert missing == [], f"commands whose --help has no 'Example: targetacq ...' line: {missing}"


# --- the command table of the lazy root --------------------------------------------------------


def test_the_command_table_lists_every_command_and_its_module():
    commands = all_commands()
    assert set(commands) <= set(COMMANDS), "a command missing from targetacq.cli.COMMANDS"
    for name, command in commands.items():
        module = command.callback.__module__ if command.callback else None
        if module and name in COMMANDS and not hasattr(command, "commands"):
            assert module == f"targetacq.cli.{COMMANDS[name][0]}", name
    for name in set(COMMANDS) - set(commands):  # listed but not installed: no module on disk
        assert not Path(targetacq.cli.__file__).with_name(COMMANDS[name][0] + ".py").exists()


def test_the_root_help_lists_every_command_with_its_summary(capsys):
    code, out, _ = run(capsys, "--help")
    assert code == 0
    for name in all_commands():
        assert name in out
    for name, (_, summary) in COMMANDS.items():
        if name in all_commands():
            assert summary in " ".join(out.replace("│", " ").split()), out
            assert all_commands()[name].get_short_help_str(200) == summary


def test_the_help_version_and_command_completion_import_no_command_module():
    code = (
        "import os, sys\n"
        "from targetacq.cli import main\n"
        "args = sys.argv[1:]\n"
        "try:\n"
        "    main(args)\n"
        "except SystemExit:\n"
        "    pass\n"
        "heavy = [m for m in sys.modules if m.startswith(('numpy', 'scipy',\n"
        "    'targetacq.cli.dri', 'targetacq.cli.figures', 'targetacq.cli.scenarios',\n"
        "    'targetacq.run'))]\n"
        "sys.stderr.write(repr(heavy))\n"
    )
    for args, env in (
        (["--help"], {}),
        (["--version"], {}),
        (
            [],
            {
                "_TARGETACQ_COMPLETE": "complete_bash",
                "COMP_WORDS": "targetacq d",
                "COMP_CWORD": "1",
            },
        ),
    ):
        done = subprocess.run(
            [sys.executable, "-c", code, *args],
            capture_output=True,
            text=True,
            env={**os.environ, **env},
            check=False,
        )
        assert done.stderr.strip().splitlines()[-1] == "[]", (args, done.stderr)


def test_an_unknown_command_is_refused_in_one_line(capsys):
    code, _, err = run(capsys, "no-such-command")
    assert code == 2 and err.startswith("targetacq: error: ") and err.count("\n") == 1


# --- the package's names are imported on first use ---------------------------------------------


def test_every_public_name_resolves_and_type_checkers_see_the_same_names():
    for name in targetacq.__all__:
        assert getattr(targetacq, name) is not None, name
    assert set(targetacq.__all__) <= set(dir(targetacq))
    tree = ast.parse(Path(targetacq.__file__).read_text(encoding="utf-8"))
    checked = {
        alias.asname or alias.name
        for node in ast.walk(tree)
        if isinstance(node, ast.If) and getattr(node.test, "id", None) == "TYPE_CHECKING"
        for statement in node.body
        if isinstance(statement, ast.ImportFrom)
        for alias in statement.names
    }
    assert checked == set(targetacq.__all__)
    with pytest.raises(AttributeError, match="no_such_name"):
        _ = targetacq.no_such_name


def test_importing_the_package_imports_no_numerical_library():
    code = "import sys, targetacq; print([m for m in ('numpy', 'scipy') if m in sys.modules])"
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout
    assert out.strip() == "[]"


# --- shell completion ------------------------------------------------------------------------


def _complete(capsys, monkeypatch, words, shell="bash"):
    monkeypatch.setenv("_TARGETACQ_COMPLETE", f"complete_{shell}")
    monkeypatch.setenv("COMP_WORDS", words)
    monkeypatch.setenv("COMP_CWORD", str(len(words.split()) - (0 if words.endswith(" ") else 1)))
    code, out, _ = run(capsys)
    assert code == 0
    return out.split()


def test_the_completion_script_is_printed(capsys, monkeypatch):
    monkeypatch.setenv("_TARGETACQ_COMPLETE", "source_bash")
    code, out, _ = run(capsys)
    assert code == 0 and "_targetacq_completion" in out and "complete_bash" in out
    monkeypatch.delenv("_TARGETACQ_COMPLETE")
    code, out, _ = run(capsys, "--show-completion", "bash")
    assert code == 0 and "_targetacq_completion" in out


def test_criterion_values_complete_from_the_registry(capsys, monkeypatch):
    from targetacq.acquisition.criteria import CRITERIA

    offered = _complete(capsys, monkeypatch, "targetacq dri --criterion jo")
    assert offered == [name for name in CRITERIA if name.startswith("jo")]
    assert "johnson" in offered


def test_command_names_and_registry_options_complete(capsys, monkeypatch):
    from targetacq.acquisition.transforms import TRANSFORMS

    assert _complete(capsys, monkeypatch, "targetacq ex") == ["examples"]
    assert _complete(capsys, monkeypatch, "targetacq examples ") == ["list", "copy"]
    offered = _complete(capsys, monkeypatch, "targetacq plot --transform ")
    assert offered == list(TRANSFORMS)
    assert _complete(capsys, monkeypatch, "targetacq dri --format j") == ["json"]


# --- examples list / copy ----------------------------------------------------------------------


def test_examples_list_names_every_bundled_file_with_a_description(capsys):
    from targetacq.cli.examples import example_files

    code, out, _ = run(capsys, "examples", "list")
    assert code == 0
    lines = out.splitlines()
    assert [line.split()[0] for line in lines] == list(example_files())
    assert {"uav_haze.toml", "pointing_policies.py"} <= set(example_files())
    assert all(len(line.split(maxsplit=1)) == 2 for line in lines)
    assert "A UAV with an uncooled long-wave thermal camera" in out


def test_examples_copy_writes_the_files_with_the_umask_and_keeps_existing_ones(capsys, tmp_path):
    from targetacq.cli.examples import example_files

    previous = os.umask(0o022)
    try:
        code, out, _ = run(capsys, "examples", "copy", "uav_haze.toml", str(tmp_path / "new"))
    finally:
        os.umask(previous)
    copied = tmp_path / "new" / "uav_haze.toml"
    assert code == 0 and out == f"wrote {copied}\n"
    assert copied.read_bytes() == example_files()["uav_haze.toml"].read_bytes()
    assert stat.S_IMODE(copied.stat().st_mode) == 0o644

    copied.write_text("mine")
    code, _, err = run(capsys, "examples", "copy", "all", str(tmp_path / "new"))
    assert code == 2 and "already exists" in err and "--force" in err and err.count("\n") == 1
    assert copied.read_text() == "mine"  # nothing replaced, nothing else written
    assert sorted(p.name for p in (tmp_path / "new").iterdir()) == ["uav_haze.toml"]

    code, out, _ = run(capsys, "examples", "copy", "all", str(tmp_path / "new"), "--force")
    assert code == 0 and out.count("wrote ") == len(example_files())
    assert copied.read_bytes() == example_files()["uav_haze.toml"].read_bytes()


@pytest.mark.parametrize(
    ("args", "wanted"),
    [
        (["nope", "."], "unknown example 'nope'; valid: all, "),
        (["uav_hase", "."], "unknown example 'uav_hase' (did you mean 'uav_haze.toml'?)"),
        (["uav_haze.toml", "FILE"], "it is not a folder"),
    ],
)
def test_examples_copy_refuses_bad_input_in_one_line(capsys, tmp_path, args, wanted):
    (tmp_path / "FILE").write_text("x")
    args = [str(tmp_path / a) if a in (".", "FILE") else a for a in args]
    code, _, err = run(capsys, "examples", "copy", *args)
    assert code == 2 and wanted in err and err.count("\n") == 1
