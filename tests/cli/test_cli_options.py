"""The range-case option group: one definition, every command that takes it lists it."""

from __future__ import annotations

import dataclasses

import pytest

from targetacq.cli import all_commands
from targetacq.run.option_table import RANGE_CASE_OPTIONS, option_coverage
from targetacq.run.range_options import RangeOptions


def test_every_range_options_field_is_an_option():
    missing, extra = option_coverage()
    assert missing == set() and extra == set()
    assert "example" in {field.name for field in dataclasses.fields(RangeOptions)}


@pytest.mark.parametrize("command", ["dri", "plot", "report"])
def test_command_lists_every_range_case_option(command):
    click_command = all_commands()[command]
    flags = {flag for param in click_command.params for flag in param.opts}
    assert {spec.flag for spec in RANGE_CASE_OPTIONS} | {"--example"} <= flags


# --- the quantity type and the registry completions come from the option table ---------------


def test_every_quantity_kind_in_the_table_is_a_unit_kind():
    from targetacq.base.units import DIMENSIONS

    kinds = {spec.quantity for spec in RANGE_CASE_OPTIONS if spec.quantity is not None}
    assert kinds and kinds <= set(DIMENSIONS)


def test_quantity_options_show_their_kind_and_take_lists_in_help(capsys):
    from targetacq.cli import main

    with pytest.raises(SystemExit) as exit_:
        main(["dri", "--help"])
    out = capsys.readouterr().out
    assert exit_.value.code == 0
    assert "LENGTH[,...]" in out and "ANGLE[,...]" in out and "TEMPERATURE[,...]" in out


@pytest.mark.parametrize(
    ("value", "wanted"),
    [
        ("17kg", "--pitch: '17kg' is not a length"),
        ("17", "--pitch needs a unit"),
        ("nan", "--pitch must be a finite number"),
        ("1e400um", "--pitch must be finite; got '1e400um' (the number overflows)"),
        ("12um,abc", "--pitch: cannot read 'abc' as a length"),
    ],
)
def test_a_bad_quantity_fails_at_parse_time_naming_the_option(capsys, value, wanted):
    from targetacq.cli import main

    with pytest.raises(SystemExit) as exit_:
        main(["dri", "--example", "--pitch", value])
    err = capsys.readouterr().err
    assert exit_.value.code == 2
    assert err.startswith("targetacq: error: ") and err.count("\n") == 1
    assert err.startswith(f"targetacq: error: {wanted}")


def test_the_quantity_text_reaches_the_command_unchanged():
    from targetacq.cli.params import Quantity

    assert Quantity("temperature", "--t")("32degC,305 K") == "32degC,305 K"
    single = Quantity("temperature difference", "--netd", lists=False)
    assert single.metavar == "TEMPERATURE_DIFFERENCE"
    with pytest.raises(ValueError, match="kind must be one of"):
        Quantity("mass", "--m")


def test_options_with_choices_complete_the_registry_names():
    from targetacq.acquisition.criteria import CRITERIA

    dri = all_commands()["dri"]
    criterion = next(p for p in dri.params if "--criterion" in p.opts)
    ctx = dri.make_context("dri", [], resilient_parsing=True)
    offered = [item.value for item in criterion.shell_complete(ctx, "jo")]
    assert offered == [name for name in CRITERIA if name.startswith("jo")]
    assert offered and all(name.startswith("johnson") for name in offered)
    listed = [item.value for item in criterion.shell_complete(ctx, "nvtherm,jo")]
    assert listed == ["nvtherm," + name for name in offered]


def test_obscurant_completion_offers_the_levels_after_a_colon():
    from targetacq.cli.params import complete_names
    from targetacq.physics.atmosphere import EXTINCTION_LEVELS, OBSCURANTS

    complete = complete_names(OBSCURANTS, levels=EXTINCTION_LEVELS)
    name = OBSCURANTS[0]
    assert complete(name + ":") == [f"{name}:{level}" for level in EXTINCTION_LEVELS]
    assert complete("no-such-obscurant:") == []


def test_obscurant_completion_offers_none_and_the_levels_of_each_name():
    """The --obscurant option of the CLI itself: 'none' (a clear path) and each name with its
    levels are offered, from the registries."""
    import click

    from targetacq.physics.atmosphere import EXTINCTION_LEVELS, OBSCURANTS

    command = all_commands()["dri"]
    option = next(p for p in command.params if "--obscurant" in p.opts)
    ctx = click.Context(command)
    offered = [item.value for item in option.shell_complete(ctx, "")]
    assert "none" in offered
    for name in OBSCURANTS:
        assert name in offered
        assert all(f"{name}:{level}" in offered for level in EXTINCTION_LEVELS)
    assert [item.value for item in option.shell_complete(ctx, "haze,n")] == ["haze,none"]


def test_help_written_to_a_pipe_cuts_no_option_name(capsys):
    from targetacq.cli import main

    for command in ("dri", "sweep", "report", "design"):
        with pytest.raises(SystemExit):
            main([command, "--help"])
        out = capsys.readouterr().out
        assert "…" not in out, command
        assert "--background-temperature " in out
