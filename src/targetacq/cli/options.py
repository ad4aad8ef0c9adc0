"""Option groups shared by commands, defined once.

The sensor, target, scene, path, noise and model options of ``targetacq dri`` are the keyword
arguments of :func:`targetacq.run.range_options.range_setup`. :func:`range_case_options` adds
all of them to a command (``dri``, ``plot``, ``report``, ``sweep``, ``design``), grouped in
``--help`` by panel, so every command that takes them lists them and parses them itself: no
command re-parses another's arguments. The command receives them as one keyword argument,
``case_options`` (name → the text given, or None).

Quantity options take a :class:`~targetacq.cli.params.Quantity` (checked as they are parsed,
the text passed on unchanged; the metavar names the kind: ``LENGTH[,...]``), and options that
take a registry's names complete them in the shell
(:func:`~targetacq.cli.params.complete_names`, from the registry itself).
"""

from __future__ import annotations

import functools
import inspect
from collections.abc import Callable
from typing import Annotated, Any, TypeVar

import typer

from targetacq.cli.params import Quantity, complete_names
from targetacq.run.option_table import (
    LIST_SEPARATORS,
    RANGE_CASE_OPTIONS,
    SENSOR,
    UNCERTAINTY_OPTIONS,
    OptionSpec,
)

__all__ = ["range_case_options", "uncertainty_options"]

F = TypeVar("F", bound=Callable[..., Any])


def _obscurant_levels() -> tuple[str, ...]:
    from targetacq.physics.atmosphere import EXTINCTION_LEVELS

    return EXTINCTION_LEVELS


def _parameter(spec: OptionSpec) -> inspect.Parameter:
    lists = LIST_SEPARATORS.get(spec.name, ",") == ","
    extra: dict[str, Any] = {}
    if spec.quantity is not None:
        quantity = Quantity(spec.quantity, spec.flag, lists=lists)
        extra.update(parser=quantity, metavar=quantity.metavar)
    if spec.choices is not None:
        obscurant = spec.name == "obscurant"
        extra["autocompletion"] = complete_names(
            spec.choices,
            levels=_obscurant_levels() if obscurant else (),
            also=("none",) if obscurant else (),  # a clear path, e.g. in --obscurant none,fog
        )
    return inspect.Parameter(
        spec.name,
        inspect.Parameter.KEYWORD_ONLY,
        default=None,
        annotation=Annotated[
            str | None,  # text: a list of values is parsed by targetacq.run.option_table
            typer.Option(spec.flag, help=spec.help, rich_help_panel=spec.panel, **extra),
        ],
    )


def range_case_options(function: F) -> F:
    """Decorate a typer command so that it takes every range-case option.

    The options reach ``function`` as one keyword argument, ``case_options``: a dict of every
    :data:`RANGE_CASE_OPTIONS` name and ``example`` → the value given (None, or False for
    ``example``, when not given), ready for ``range_setup(**case_options, ...)``.
    """
    signature = inspect.signature(function, eval_str=True)
    own = [p for p in signature.parameters.values() if p.name != "case_options"]
    added = [_parameter(spec) for spec in RANGE_CASE_OPTIONS]
    added.append(
        inspect.Parameter(
            "example",
            inspect.Parameter.KEYWORD_ONLY,
            default=False,
            annotation=Annotated[
                bool,
                typer.Option(
                    "--example",
                    help="Use the bundled example camera and target.",
                    rich_help_panel=SENSOR,
                ),
            ],
        )
    )
    names = [p.name for p in added]

    @functools.wraps(function)
    def command(**kwargs: Any) -> Any:
        case_options = {name: kwargs.pop(name) for name in names}  # numbers still text
        return function(**kwargs, case_options=case_options)

    command.__signature__ = signature.replace(  # type: ignore[attr-defined]
        parameters=[*own, *added]
    )
    return command  # type: ignore[return-value]


def uncertainty_options(function: F) -> F:
    """Decorate a typer command so that it takes the Monte Carlo's options
    (:data:`targetacq.run.option_table.UNCERTAINTY_OPTIONS`): they reach ``function`` as one
    keyword argument, ``uncertainty_options``, name → the text given or None, for
    :func:`targetacq.run.uncertainty.read_uncertainty`."""
    signature = inspect.signature(function, eval_str=True)
    own = [p for p in signature.parameters.values() if p.name != "uncertainty_options"]
    added = [_parameter(spec) for spec in UNCERTAINTY_OPTIONS]
    names = [p.name for p in added]

    @functools.wraps(function)
    def command(**kwargs: Any) -> Any:
        options = {name: kwargs.pop(name) for name in names}
        return function(**kwargs, uncertainty_options=options)

    command.__signature__ = signature.replace(  # type: ignore[attr-defined]
        parameters=[*own, *added]
    )
    return command  # type: ignore[return-value]
