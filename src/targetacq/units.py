"""Quantities with units at the boundary (CLI options, files), parsed once with pint.

Inside the library everything is a bare SI float; this module is the only place that knows
about units. A bare number where a unit is needed is an error that says which unit to add.
"""

from __future__ import annotations

import functools
import math
import re
from typing import Any

__all__ = ["DIMENSIONS", "parse_quantity"]

DIMENSIONS: dict[str, tuple[str, str]] = {
    # kind: (SI unit it is converted to, an example for error messages)
    "length": ("meter", "17 um, 75 mm, 2.5 km"),
    "angle": ("radian", "0.227 mrad, 12 deg"),
    "temperature": ("kelvin", "305 K, 22 degC"),
    "temperature difference": ("kelvin", "2 K, 0.05 K"),
    "extinction": ("1 / meter", "0.4 /km (Np/km), 1.7 dB/km"),
    "time": ("second", "0.1 s, 60 s, 2 min"),
    "irradiance": ("watt / meter ** 2", "500 W/m^2"),
}
"""Quantity kinds accepted at the boundary: the SI unit they become and an example."""

# Plain units converted without pint (exact SI definitions); anything else goes through pint.
# Scenario files hold thousands of quantities, and pint takes tens of microseconds for each.
_PLAIN_UNITS: dict[str, dict[str, float]] = {
    "length": {"m": 1.0, "km": 1e3, "cm": 1e-2, "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "nm": 1e-9},
    "angle": {"rad": 1.0, "mrad": 1e-3, "urad": 1e-6, "µrad": 1e-6, "deg": math.pi / 180.0},
    "temperature": {"K": 1.0},
    "temperature difference": {"K": 1.0, "mK": 1e-3},
    "extinction": {"/m": 1.0, "/km": 1e-3, "1/m": 1.0, "1/km": 1e-3},
    "time": {"s": 1.0, "ms": 1e-3, "min": 60.0, "h": 3600.0},
    "irradiance": {"W/m^2": 1.0, "W/m**2": 1.0},
}

_NUMBER = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*$")
_DB_PER_NEPER = 10.0 / math.log(10.0)  # as targetacq.atmosphere.DB_PER_NEPER (MODEL.md erratum)


@functools.cache
def _registry() -> Any:
    import pint

    return pint.UnitRegistry()


def parse_quantity(text: str, kind: str, name: str) -> float:
    """Parse ``"17 um"``-style text into a float in SI units.

    Parameters
    ----------
    text : str
        A number followed by a unit (a space is optional: ``"17um"``). Extinctions take
        ``/km`` (nepers per km, as Table 7.1) or ``dB/km`` (1 dB/km = 0.2303 Np/km).
    kind : str
        A key of :data:`DIMENSIONS`.
    name : str
        The input's name for error messages (e.g. ``"--pitch"``).

    Returns
    -------
    float
        The value in the SI unit of ``kind`` (m, rad, K, Np/m).

    Raises
    ------
    ValueError
        If the text is not a number with a unit of that kind; the message names the input and
        gives an example.
    """
    if kind not in DIMENSIONS:
        raise ValueError(f"kind must be one of {', '.join(DIMENSIONS)}; got {kind!r}")
    si_unit, example = DIMENSIONS[kind]
    match = _NUMBER.match(text)
    if match is None:
        raise ValueError(f"{name}: cannot read {text!r} as a {kind} (e.g. {example})")
    value, unit = float(match.group(1)), match.group(2)
    if not unit:
        raise ValueError(f"{name} needs a unit: got {text!r}; write e.g. {example}")
    if kind == "extinction" and unit.replace(" ", "") in ("dB/km", "db/km"):
        return value / _DB_PER_NEPER / 1000.0
    plain = _PLAIN_UNITS[kind].get(unit.replace(" ", ""))
    if plain is not None:
        return value * plain
    if unit.startswith("/"):
        unit = "1" + unit
    if kind == "temperature difference":
        unit = {"degC": "delta_degC", "°C": "delta_degC", "degF": "delta_degF"}.get(unit, unit)
    ureg = _registry()
    try:
        quantity = ureg.Quantity(value, unit)
    except Exception as error:  # pint raises several unrelated types for bad text
        raise ValueError(f"{name}: unknown unit in {text!r} (e.g. {example})") from error
    try:
        return float(quantity.to(si_unit).magnitude)
    except Exception as error:
        raise ValueError(
            f"{name}: {text!r} is not a {kind} (e.g. {example}); its unit is {quantity.units}"
        ) from error
