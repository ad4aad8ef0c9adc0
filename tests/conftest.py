"""Test configuration: Hypothesis without per-example deadlines (shared, noisy machines), and
with a fixed example sequence on CI so that a CI run is reproducible; locally the examples vary
from run to run and keep exploring."""

import os
from collections.abc import Callable
from typing import Any

import pytest
from hypothesis import settings

settings.register_profile("default", deadline=None)
settings.register_profile("ci", deadline=None, derandomize=True, print_blob=True)
settings.load_profile("ci" if os.environ.get("CI") else "default")


@pytest.fixture
def cli(capsys: pytest.CaptureFixture[str]) -> Callable[..., tuple[Any, str, str]]:
    """The ``targetacq`` command run in this process: ``cli("dri", "--example")`` gives its exit
    status, standard output and standard error (the command always ends by ``SystemExit``)."""
    from targetacq.cli import main

    def run(*args: str) -> tuple[Any, str, str]:
        capsys.readouterr()  # what the test printed before is not the command's output
        with pytest.raises(SystemExit) as done:
            main(list(args))
        out, err = capsys.readouterr()
        return done.value.code, out, err

    return run
