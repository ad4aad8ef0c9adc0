"""Quantities with units at the boundary (CLI options, files), parsed once with pint.

Inside the library everything is a bare SI float; this module is the only place that knows
about units. A bare number where a unit is needed is an error that says which unit to add.
"""

from __future__ import annotations

import functools
from typing import Any

__all__ = ["DIMENSIONS", "parse_quantity"]

DIMENSIONS: dict[str, tuple[str, str]] = {
    # kind: (SI unit it is converted to, an example for error messages)
    "length": ("meter", "17 um, 75 mm, 2.5 km"),
    "angle": ("radian", "0.227 mrad, 12 deg"),
}
"""Quantity kinds accepted at the boundary: the SI unit they become and an example."""


@functools.cache
def _registry() -> Any:
    import pint

    return pint.UnitRegistry()


def parse_quantity(text: str, kind: str, name: str) -> float:
    """Parse ``"17 um"``-style text into a float in SI units.

    Parameters
    ----------
    text : str
        A number followed by a unit (a space is optional: ``"17um"``).
    kind : str
        A key of :data:`DIMENSIONS` ("length", "angle").
    name : str
        The input's name for error messages (e.g. ``"--pitch"``).

    Returns
    -------
    float
        The value in the SI unit of ``kind`` (m, rad).

    Raises
    ------
    ValueError
        If the text is not a number with a unit of that kind; the message names the input and
        gives an example.
    """
    if kind not in DIMENSIONS:
        raise ValueError(f"kind must be one of {', '.join(DIMENSIONS)}; got {kind!r}")
    si_unit, example = DIMENSIONS[kind]
    ureg = _registry()
    try:
        quantity = ureg.Quantity(text.strip())
    except Exception as error:  # pint raises several unrelated types for bad text
        raise ValueError(f"{name}: cannot read {text!r} as a {kind} (e.g. {example})") from error
    if not isinstance(quantity, ureg.Quantity) or quantity.unitless:
        raise ValueError(f"{name} needs a unit: got {text!r}; write e.g. {example}")
    try:
        value = float(quantity.to(si_unit).magnitude)
    except Exception as error:
        raise ValueError(
            f"{name}: {text!r} is not a {kind} (e.g. {example}); its unit is {quantity.units}"
        ) from error
    return value
