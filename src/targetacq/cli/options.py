"""Option groups shared by commands, defined once.

The sensor, target, scene, path, noise and model options of ``targetacq dri`` are the keyword
arguments of :func:`targetacq.services.range_case.range_setup`. :func:`range_case_options` adds
all of them to a command (``dri``, ``plot``, ``report``, ``sweep``, ``design``), grouped in
``--help`` by panel, so every command that takes them lists them and parses them itself: no
command re-parses another's arguments. The command receives them as one keyword argument,
``case_options`` (name → the text given, or None).

Quantity options take a :class:`Quantity` (checked as they are parsed, the text passed on
unchanged; the metavar names the kind: ``LENGTH[,...]``), and options that take a registry's
names complete them in the shell (:func:`complete_names`, from the registry itself).

Examples
--------
>>> Quantity("length")("35mm,50mm")
'35mm,50mm'
>>> complete_names(("johnson", "johnson-1958", "nvtherm"))("nvtherm,jo")
['nvtherm,johnson', 'nvtherm,johnson-1958']
"""

from __future__ import annotations

import functools
import inspect
from collections.abc import Callable, Iterable
from typing import Annotated, Any, TypeVar

import typer

from targetacq.services.options import LIST_SEPARATORS, RANGE_CASE_OPTIONS, SENSOR, OptionSpec
from targetacq.units import DIMENSIONS, parse_quantity

__all__ = ["Quantity", "complete_names", "range_case_options"]

F = TypeVar("F", bound=Callable[..., Any])


class Quantity:
    """A quantity option's type: text whose every item reads as a quantity of ``kind``.

    Each item of a comma-separated list (a sweep's values) must parse with
    :func:`targetacq.units.parse_quantity` (a finite number with a unit of that kind) when the
    command line is parsed; the text is passed on unchanged, to be converted where it is used.
    A bad item stops the command with one line naming the option and the item. (Typer takes a
    parameter type as a ``parser`` callable and a ``metavar``: :attr:`metavar`.)

    Parameters
    ----------
    kind : str
        A key of :data:`targetacq.units.DIMENSIONS` (``"length"``, ``"angle"``, ...).
    lists : bool
        Whether the option takes a comma-separated list of values (default True).

    Examples
    --------
    >>> Quantity("angle")("12deg"), Quantity("length").metavar
    ('12deg', 'LENGTH[,...]')
    >>> Quantity("length")("35mm,50kg")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    typer._click.exceptions.BadParameter: '50kg' is not a length (e.g. 17 um, 75 mm, ...
    """

    def __init__(self, kind: str, *, lists: bool = True) -> None:
        if kind not in DIMENSIONS:
            raise ValueError(f"kind must be one of {', '.join(DIMENSIONS)}; got {kind!r}")
        self.kind = kind
        self.lists = lists

    @property
    def metavar(self) -> str:
        """The kind in capitals, ``[,...]`` when a list is taken: ``TEMPERATURE_DIFFERENCE``."""
        return self.kind.upper().replace(" ", "_") + ("[,...]" if self.lists else "")

    def __call__(self, value: Any) -> Any:
        if value is None:
            return None
        text = str(value)
        for item in text.split(",") if self.lists else [text]:
            if not item.strip():
                continue  # an empty item is reported with its list by services.options
            try:
                parse_quantity(item.strip(), self.kind, item.strip())
            except ValueError as error:
                message = str(error).removeprefix(f"{item.strip()}: ")
                raise typer.BadParameter(message) from None
        return text

    def __repr__(self) -> str:
        return f"Quantity({self.kind!r})"


def complete_names(
    names: Iterable[str], *, separator: str | None = ",", levels: Iterable[str] = ()
) -> Callable[[str], list[str]]:
    """A shell-completion callback offering ``names`` (a registry: its keys).

    Parameters
    ----------
    names : iterable of str
        The choices, e.g. a registry (read when completing, so it is never copied).
    separator : str or None
        The list separator: the item after the last one is completed, the items before kept.
    levels : iterable of str
        Suffixes a name may take after ``:`` (``fog:low``), offered once ``name:`` is typed.

    Returns
    -------
    callable
        ``complete(incomplete) → list of str``, for ``typer.Option(autocompletion=...)``.

    Examples
    --------
    >>> complete = complete_names(("fog", "rain"), levels=("low", "high"))
    >>> complete("f"), complete("rain,fog:h")
    (['fog'], ['rain,fog:high'])
    """

    def complete(incomplete: str) -> list[str]:
        head, _, last = incomplete.rpartition(separator) if separator else ("", "", incomplete)
        prefix = head + separator if head and separator else ""
        name, colon, level = last.partition(":")
        if colon:
            if name not in names:
                return []
            return [f"{prefix}{name}:{lv}" for lv in levels if lv.startswith(level)]
        return [prefix + str(n) for n in names if str(n).startswith(last)]

    return complete


def _obscurant_levels() -> tuple[str, ...]:
    from targetacq.atmosphere import EXTINCTION_LEVELS

    return EXTINCTION_LEVELS


def _parameter(spec: OptionSpec) -> inspect.Parameter:
    lists = LIST_SEPARATORS.get(spec.name, ",") == ","
    extra: dict[str, Any] = {}
    if spec.quantity is not None:
        quantity = Quantity(spec.quantity, lists=lists)
        extra.update(parser=quantity, metavar=quantity.metavar)
    if spec.choices is not None:
        levels = _obscurant_levels() if spec.name == "obscurant" else ()
        extra["autocompletion"] = complete_names(spec.choices, levels=levels)
    return inspect.Parameter(
        spec.name,
        inspect.Parameter.KEYWORD_ONLY,
        default=None,
        annotation=Annotated[
            str | None,  # text: a list of values is parsed by targetacq.services.options
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
