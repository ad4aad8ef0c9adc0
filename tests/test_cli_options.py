"""The range-case option group: one definition, every command that takes it lists it."""

from __future__ import annotations

import inspect

import pytest
import typer.main

from targetacq.cli import app
from targetacq.services.options import RANGE_CASE_OPTIONS, option_coverage
from targetacq.services.range_case import range_setup


def test_every_range_setup_keyword_is_an_option():
    missing, extra = option_coverage()
    assert missing == set() and extra == set()
    assert "example" in inspect.signature(range_setup).parameters


@pytest.mark.parametrize("command", ["dri", "plot", "report"])
def test_command_lists_every_range_case_option(command):
    click_command = typer.main.get_command(app).commands[command]
    flags = {flag for param in click_command.params for flag in param.opts}
    assert {spec.flag for spec in RANGE_CASE_OPTIONS} | {"--example"} <= flags
