"""Parameter types of the ``targetacq`` command, light enough to import at start-up.

:class:`Quantity` checks a quantity option's text as the command line is parsed;
:func:`complete_names` completes the names an option takes in the shell, read from the registry
itself (a list of choices is never written twice).

Examples
--------
>>> Quantity("length", "--focal-length")("35mm,50mm")
'35mm,50mm'
>>> complete_names(("johnson", "johnson-1958", "nvtherm"))("nvtherm,jo")
['nvtherm,johnson', 'nvtherm,johnson-1958']
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Any

import typer

from targetacq.base.units import DIMENSIONS, parse_quantity

__all__ = ["Quantity", "QuantityError", "complete_names"]


class QuantityError(typer.BadParameter):
    """A quantity option's bad value: its message alone names the option and the value (no
    ``Invalid value for ...`` prefix), as every other check of the option's value does."""

    def format_message(self) -> str:
        return self.message


class Quantity:
    """A quantity option's type: text whose every item reads as a quantity of ``kind``.

    Each item of a comma-separated list (a sweep's values) must parse with
    :func:`targetacq.base.units.parse_quantity` (a finite number with a unit of that kind) when the
    command line is parsed; the text is passed on unchanged, to be converted where it is used.
    A bad item stops the command with one line naming the option and the item
    (:class:`QuantityError`). Typer takes a parameter type as a ``parser`` callable and a
    ``metavar``: :attr:`metavar`.

    Parameters
    ----------
    kind : str
        A key of :data:`targetacq.base.units.DIMENSIONS` (``"length"``, ``"angle"``, ...).
    name : str
        The option's name in error messages, e.g. ``"--pitch"``.
    lists : bool
        Whether the option takes a comma-separated list of values (default True).

    Examples
    --------
    >>> Quantity("angle", "--hfov")("12deg"), Quantity("length", "--pitch").metavar
    ('12deg', 'LENGTH[,...]')
    >>> Quantity("length", "--pitch")("35mm,50kg")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    targetacq.cli.params.QuantityError: --pitch: '50kg' is not a length (e.g. 17 um, 75 mm, ...
    """

    def __init__(self, kind: str, name: str, *, lists: bool = True) -> None:
        if kind not in DIMENSIONS:
            raise ValueError(f"kind must be one of {', '.join(DIMENSIONS)}; got {kind!r}")
        self.kind = kind
        self.name = name
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
                continue  # an empty item is reported with its list by run.option_table
            try:
                parse_quantity(item.strip(), self.kind, self.name)
            except ValueError as error:
                raise QuantityError(str(error)) from None
        return text

    def __repr__(self) -> str:
        return f"Quantity({self.kind!r}, {self.name!r})"


def complete_names(
    names: Iterable[str],
    *,
    separator: str | None = ",",
    levels: Iterable[str] = (),
    also: Iterable[str] = (),
) -> Callable[[str], list[str]]:
    """A shell-completion callback offering ``names`` (a registry: its keys).

    Parameters
    ----------
    names : iterable of str
        The choices, e.g. a registry (read when completing, so it is never copied).
    separator : str or None
        The list separator: the item after the last one is completed, the items before kept.
    levels : iterable of str
        Suffixes a name may take after ``:`` (``fog:low``): offered with each name that
        matches, and alone once ``name:`` is typed.
    also : iterable of str
        Values the option takes besides the names, e.g. ``none`` (a clear path); no levels.

    Returns
    -------
    callable
        ``complete(incomplete) → list of str``, for ``typer.Option(autocompletion=...)``.

    Examples
    --------
    >>> complete = complete_names(("fog", "rain"), levels=("low", "high"), also=("none",))
    >>> complete("f"), complete("rain,fog:h"), complete("n")
    (['fog', 'fog:low', 'fog:high'], ['rain,fog:high'], ['none'])
    """

    def complete(incomplete: str) -> list[str]:
        head, _, last = incomplete.rpartition(separator) if separator else ("", "", incomplete)
        prefix = head + separator if head and separator else ""
        name, colon, level = last.partition(":")
        if colon:
            if name not in names:
                return []
            return [f"{prefix}{name}:{lv}" for lv in levels if lv.startswith(level)]
        found = []
        for n in [*names, *also]:
            if str(n).startswith(last):
                found.append(prefix + str(n))
                if n not in also:
                    found += [f"{prefix}{n}:{lv}" for lv in levels]
        return found

    return complete
