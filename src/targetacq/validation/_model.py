"""The records of the validation page: one check, one section, the summary.

A *check* puts one published value next to the model's value. Its tolerance is what the printed
precision implies: half a unit in the last printed digit (a probability printed "0.95" is known
to ±0.005; a range printed "6765" m to ±0.5 m). Where the reference is not printed but computed
(a numerical quadrature), the tolerance is stated with the check.

A check is either a *reproduction* (the model is built to give the printed value: a table it
reads, an equation's check value) or a *comparison* (the model is not expected to agree, e.g. the
individual observations of Table 3.4 against the binned Table 3.5 the model reads). The summary
counts reproductions; comparisons are reported with their residuals and not counted.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

from matplotlib.figure import Figure

__all__ = ["Check", "Section", "Summary", "half_unit", "new_figure", "summarise"]

# Rounding slack on top of a tolerance: a printed 188 m for a computed 187.5 m is a round-half-up,
# a residual of 0.5 m to within the last bit, and is within ±0.5 m.
_SLACK = 1e-9


def half_unit(printed: str) -> float:
    """Half a unit in the last printed digit of a number as printed.

    Parameters
    ----------
    printed : str
        The number as printed, e.g. ``"0.95"``, ``"1.0"``, ``"6765"``, ``"1.0e-4"``.

    Returns
    -------
    float
        The implied absolute precision, in the number's own unit: 0.005, 0.05, 0.5, 5e-6.

    Examples
    --------
    >>> half_unit("0.95"), half_unit("20"), half_unit("1.0e-4")
    (0.005, 0.5, 5e-06)
    """
    text = printed.strip().lstrip("≈~<> ").replace("−", "-")
    mantissa, _, exponent = text.lower().partition("e")
    _, dot, decimals = mantissa.partition(".")
    digits = len(decimals) if dot else 0
    return 0.5 * 10.0 ** (int(exponent or 0) - digits)


def _normalised(text: str) -> str:
    """Text compared without case and white space ("< 2km" is "< 2 km")."""
    return re.sub(r"\s+", "", text.lower())


@dataclass(frozen=True)
class Check:
    """One published value against the model's.

    Attributes
    ----------
    item : str
        What is compared, e.g. ``"detection, optimistic: N = 0.75"``.
    published : float or str
        The published (or reference) value; text for a categorical value (a descriptive term,
        "–" for a cell the source leaves empty).
    model : float or str
        What the package gives.
    tolerance : float
        Absolute, in ``unit``: the printed precision (:func:`half_unit`) or a stated one.
    unit : str
        Unit of ``published``, ``model`` and ``tolerance``.
    printed : str
        The value as printed in the source (default: ``published`` formatted).
    note : str
        Anything a reader needs to judge the row.
    exact : bool
        True: a reproduction, counted in the summary. False: a comparison, not expected to agree.
    alternatives : Mapping[str, float]
        Other models' values for the same published value (e.g. a transform fitted to it),
        by name; reported with their residuals, never counted.
    """

    item: str
    published: float | str
    model: float | str
    tolerance: float = 0.0
    unit: str = ""
    printed: str = ""
    note: str = ""
    exact: bool = True
    alternatives: Mapping[str, float] = field(default_factory=lambda: MappingProxyType({}))

    @property
    def residual(self) -> float | None:
        """``model − published`` (0 where both are the same infinity); None for text."""
        return _residual(self.model, self.published)

    @property
    def ratio(self) -> float:
        """``|residual| / tolerance``: <= 1 within tolerance; 0 or inf for text (equal or not)."""
        residual = self.residual
        if residual is None:
            model, published = self.model, self.published
            if isinstance(model, str) and isinstance(published, str):
                return 0.0 if _normalised(model) == _normalised(published) else math.inf
            return math.inf
        if math.isnan(residual):
            return math.inf
        if residual == 0:
            return 0.0
        return abs(residual) / self.tolerance if self.tolerance > 0 else math.inf

    @property
    def within(self) -> bool:
        """Whether the model is within the tolerance of the published value."""
        return self.ratio <= 1.0 + _SLACK

    def alternative_residual(self, name: str) -> float | None:
        """Residual of an alternative model's value (None if it has none or it is text)."""
        if name not in self.alternatives:
            return None
        return _residual(self.alternatives[name], self.published)


def _residual(model: float | str, published: float | str) -> float | None:
    if isinstance(model, str) or isinstance(published, str):
        return None
    if model == published:
        return 0.0
    return float(model) - float(published)


@dataclass(frozen=True)
class Section:
    """One published table or equation and its checks.

    Attributes
    ----------
    key : str
        Short name, also the HTML anchor (``"table-3-3"``).
    title : str
        Heading, naming the table or equation.
    source : str
        Where the published values come from (publication, table, page).
    method : str
        What the model column is: the package function and its arguments.
    checks : tuple of Check
    notes : str
        What a sceptical reader should know (inferences, known disagreements).
    provenance : str
        The header of the bundled data file the published values were read from, if any.
    figure : callable, optional
        Draws the section's figure (model curves and the published points).
    """

    key: str
    title: str
    source: str
    method: str
    checks: tuple[Check, ...]
    notes: str = ""
    provenance: str = ""
    figure: Callable[[], Figure] | None = None

    @property
    def alternative_names(self) -> tuple[str, ...]:
        """Names of the alternative models some check of the section carries."""
        return tuple(dict.fromkeys(name for c in self.checks for name in c.alternatives))


@dataclass(frozen=True)
class Summary:
    """Counts over all sections.

    Attributes
    ----------
    checks : int
        Reproductions (checks that must agree).
    within : int
        Reproductions within their tolerance.
    worst : Check or None
        The reproduction with the largest ``|residual| / tolerance``.
    worst_section : str
        Title of its section.
    comparisons : int
        Comparisons (not counted above).
    comparison_worst : Check or None
        The comparison with the largest ``|residual|``.
    comparison_rms : float
        Root-mean-square residual of the numeric comparisons.
    """

    checks: int
    within: int
    worst: Check | None
    worst_section: str
    comparisons: int
    comparison_worst: Check | None
    comparison_rms: float

    def line(self) -> str:
        """One line: checks, how many within tolerance, the worst residual."""
        text = f"{self.within} of {self.checks} checks within the printed precision"
        if self.worst is not None:
            text += (
                f"; worst: {self.worst_section}, {self.worst.item}: residual "
                f"{format_residual(self.worst.residual)} {self.worst.unit}".rstrip()
                + f" ({self.worst.ratio:.2g} × tolerance)"
            )
        return text


def format_residual(value: float | None) -> str:
    """A residual for display: ``0`` when exact, else three significant digits with sign."""
    if value is None:
        return "—"
    if value == 0:
        return "0"
    return f"{value:+.3g}"


def summarise(sections: tuple[Section, ...] | list[Section]) -> Summary:
    """Count the reproductions within tolerance and find the worst residuals.

    Parameters
    ----------
    sections : sequence of Section

    Returns
    -------
    Summary
    """
    exact = [(s.title, c) for s in sections for c in s.checks if c.exact]
    compared = [c for s in sections for c in s.checks if not c.exact]
    worst_title, worst = max(exact, key=lambda pair: pair[1].ratio, default=("", None))
    numeric = [c for c in compared if c.residual is not None]
    comparison_worst = max(numeric, key=lambda c: abs(c.residual or 0.0), default=None)
    rms = (
        math.sqrt(sum((c.residual or 0.0) ** 2 for c in numeric) / len(numeric))
        if numeric
        else math.nan
    )
    return Summary(
        checks=len(exact),
        within=sum(c.within for _, c in exact),
        worst=worst,
        worst_section=worst_title,
        comparisons=len(compared),
        comparison_worst=comparison_worst,
        comparison_rms=rms,
    )


def new_figure(
    width: float,
    height: float,
    columns: int = 1,
    *,
    left: float = 0.75,
    bottom: float = 0.55,
    top: float = 0.4,
) -> tuple[Figure, Any]:
    """A figure with ``columns`` axes side by side and fixed margins [inches].

    Fixed margins rather than matplotlib's constrained layout: the page draws nine figures and
    the layout solver would be most of their cost.
    """
    fig = Figure(figsize=(width, height), dpi=90)
    fig.subplots_adjust(
        left=left / width,
        right=1 - 0.15 / width,
        bottom=bottom / height,
        top=1 - top / height,
        wspace=0.08 if columns > 1 else 0.2,
    )
    axes = fig.subplots(1, columns, sharey=True) if columns > 1 else fig.add_subplot()
    return fig, axes


def as_float(value: Any) -> float:
    """A model output (NumPy scalar or 0-d array) as a Python float."""
    return float(value)
