"""Quantities with units at the boundary (CLI options, files, Python calls), parsed once with pint.

Inside the library everything is a bare SI float; this module is the only place that knows
about units. Text must carry its unit (``"17 um"``): a bare number where a unit is needed is an
error that says which unit to add. From Python, a pint ``Quantity`` of any registry is converted
to SI (:func:`si_magnitude`, :func:`to_si`); pint is imported only once a quantity or a unit
outside the plain ones needs it.
"""

from __future__ import annotations

import functools
import math
import numbers
import re
import sys
from typing import Any

from targetacq.base.limits import MAX_DECIBELS, check_finite

__all__ = [
    "DIMENSIONS",
    "is_quantity",
    "parse_quantity",
    "shown_text",
    "si_magnitude",
    "to_si",
]

DIMENSIONS: dict[str, tuple[str, str]] = {
    # kind: (SI unit it is converted to, an example for error messages)
    "length": ("meter", "17 um, 75 mm, 2.5 km"),
    "area": ("meter ** 2", "10 m^2, 4 m**2"),
    "angle": ("radian", "0.227 mrad, 12 deg"),
    "temperature": ("kelvin", "305 K, 22 degC"),
    "temperature difference": ("kelvin", "2 K, 0.05 K"),
    "extinction": ("1 / meter", "0.4 /km (Np/km), 1.7 dB/km"),
    "time": ("second", "0.1 s, 60 s, 2 min"),
    "irradiance": ("watt / meter ** 2", "500 W/m^2"),
    "power": ("watt", "100 kW, 1.5 MW, 10 mW"),
    "frequency": ("hertz", "10 GHz, 35 GHz"),
    "area density": ("1 / meter ** 2", "4 /km^2, 0.001 /m^2"),
    "speed": ("meter / second", "10 m/s, 5 mm/h (a rain rate)"),
    "power ratio": ("dimensionless", "30 dB, -20 dB, 3 dB (10 log10 of the ratio)"),
    "structure constant": ("meter ** (-2/3)", "1e-14 m^(-2/3) (a refractive-index Cn²)"),
}
"""Quantity kinds accepted at the boundary: the SI unit they become and an example."""

# Plain units converted without pint (exact SI definitions); anything else goes through pint.
# Scenario files hold thousands of quantities, and pint takes tens of microseconds for each.
_PLAIN_UNITS: dict[str, dict[str, float]] = {
    "length": {"m": 1.0, "km": 1e3, "cm": 1e-2, "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "nm": 1e-9},
    "area": {"m^2": 1.0, "m**2": 1.0, "cm^2": 1e-4},
    "angle": {"rad": 1.0, "mrad": 1e-3, "urad": 1e-6, "µrad": 1e-6, "deg": math.pi / 180.0},
    "temperature": {"K": 1.0},
    "temperature difference": {"K": 1.0, "mK": 1e-3},
    "extinction": {"/m": 1.0, "/km": 1e-3, "1/m": 1.0, "1/km": 1e-3},
    "time": {"s": 1.0, "ms": 1e-3, "min": 60.0, "h": 3600.0},
    "irradiance": {"W/m^2": 1.0, "W/m**2": 1.0},
    "power": {"W": 1.0, "mW": 1e-3, "kW": 1e3, "MW": 1e6},
    "frequency": {"Hz": 1.0, "kHz": 1e3, "MHz": 1e6, "GHz": 1e9},
    "area density": {"/m^2": 1.0, "/m**2": 1.0, "/km^2": 1e-6, "/km**2": 1e-6},
    "speed": {"m/s": 1.0, "km/h": 1.0 / 3.6, "mm/h": 1e-3 / 3600.0},
    "power ratio": {},
    "structure constant": {"m^(-2/3)": 1.0, "m**(-2/3)": 1.0},
}

# The SI unit of each pint base dimension, for converting any quantity to SI base units.
_SI_BASE: dict[str, str] = {
    "[length]": "meter",
    "[mass]": "kilogram",
    "[time]": "second",
    "[temperature]": "kelvin",
    "[current]": "ampere",
    "[substance]": "mole",
    "[luminosity]": "candela",
}

_NUMBER = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*$")
# Python's float() reads these words; a quantity never is one of them.
_NOT_FINITE = re.compile(r"^\s*[-+]?(?:nan|inf)", re.IGNORECASE)
_DB_PER_NEPER = 10.0 / math.log(10.0)  # as targetacq.physics.atmosphere.DB_PER_NEPER
# A unit as people write it: names (letters, µ, °) joined by spaces, "*" or "/", each with at
# most a one-digit power ("m^2", "m**2", "s-1"); at most 40 characters. pint gets nothing else.
_PLAIN_UNIT_TEXT = re.compile(
    r"^(?=.{1,40}$)[A-Za-zµ°Ωμ_]+(?:(?:\*\*|\^)-?\d)?"
    r"(?:\s*(?:\*|/|\s)\s*(?:1|[A-Za-zµ°Ωμ_]+)(?:(?:\*\*|\^)-?\d)?)*$"
)


def shown_text(text: str, limit: int = 80) -> str:
    """``text`` as it goes into a message: quoted, cut after ``limit`` characters."""
    return repr(text) if len(text) <= limit else repr(text[:limit]) + f"… ({len(text)} characters)"


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
        If the text is not a finite number with a unit of that kind (``"nan m"``, or
        ``"1e400 m"``, which overflows double precision), or is a power ratio beyond
        ±:data:`targetacq.base.limits.MAX_DECIBELS` dB (``"4000 dB"``, whose linear ratio
        overflows); the message names the input and gives an example or the valid range.
    """
    if kind not in DIMENSIONS:
        raise ValueError(f"kind must be one of {', '.join(DIMENSIONS)}; got {kind!r}")
    _, example = DIMENSIONS[kind]
    if _NOT_FINITE.match(text):
        raise ValueError(
            f"{name} must be a finite number with a unit (e.g. {example}); got {text!r}"
        )
    match = _NUMBER.match(text)
    if match is None:
        raise ValueError(f"{name}: cannot read {text!r} as a {kind} (e.g. {example})")
    result = _parse_match(float(match.group(1)), match.group(2), text, kind, name)
    if not math.isfinite(result):  # a literal beyond double precision (1e400) reads as inf
        raise ValueError(f"{name} must be finite; got {text!r} (the number overflows)")
    return result


def _parse_match(value: float, unit: str, text: str, kind: str, name: str) -> float:
    """The number ``value`` [``unit``] of ``text`` in the SI unit of ``kind`` (maybe inf)."""
    si_unit, example = DIMENSIONS[kind]
    if not unit:
        raise ValueError(f"{name} needs a unit: got {text!r}; write e.g. {example}")
    if kind == "extinction" and unit.replace(" ", "") in ("dB/km", "db/km"):
        return value / _DB_PER_NEPER / 1000.0
    if kind == "power ratio":
        if unit.replace(" ", "") not in ("dB", "db"):
            raise ValueError(f"{name}: a power ratio is given in dB, e.g. {example}; got {text!r}")
        if not abs(value) <= MAX_DECIBELS:
            # 10 ** (value / 10) overflows double precision above about 3,083 dB.
            raise ValueError(
                f"{name} must be within ±{MAX_DECIBELS:g} dB (a linear ratio of 10^±"
                f"{MAX_DECIBELS / 10:g}); got {shown_text(text)}"
            )
        return 10.0 ** (value / 10.0)
    plain = _PLAIN_UNITS[kind].get(unit.replace(" ", ""))
    if plain is not None:
        return value * plain
    if unit.startswith("/"):
        unit = "1" + unit
    if kind == "temperature difference":
        unit = {"degC": "delta_degC", "°C": "delta_degC", "degF": "delta_degF"}.get(unit, unit)
    if not _PLAIN_UNIT_TEXT.match(unit):
        # pint evaluates what it is given: a tower of powers ("um**2**2**2…") or a long text
        # takes minutes and gigabytes. A unit is a few names with at most small powers.
        raise ValueError(f"{name}: unknown unit in {shown_text(text)} (e.g. {example})")
    ureg = _registry()
    try:
        quantity = ureg.Quantity(value, unit)
    except Exception as error:  # pint raises several unrelated types for bad text
        raise ValueError(f"{name}: unknown unit in {shown_text(text)} (e.g. {example})") from error
    try:
        return float(quantity.to(si_unit).magnitude)
    except OverflowError:
        return math.inf
    except Exception as error:
        raise ValueError(
            f"{name}: {text!r} is not a {kind} (e.g. {example}); its unit is {quantity.units}"
        ) from error


def is_quantity(value: object) -> bool:
    """Whether ``value`` is a pint ``Quantity`` (of any registry).

    pint is not imported here: a value can only be a quantity once pint has been imported.
    """
    pint = sys.modules.get("pint")
    return pint is not None and isinstance(value, pint.Quantity)


def si_magnitude(quantity: Any) -> Any:
    """The magnitude of a pint ``Quantity`` in SI base units (m, kg, s, K, A, mol, cd).

    The conversion is explicit, not ``to_base_units()``, whose result depends on the registry's
    unit system (an imperial registry gives yards). Offset temperatures convert as
    temperatures (``20 degC`` -> 293.15 K); a dimensionless quantity, an angle included (pint's
    radian is dimensionless), becomes its plain number (``1 deg`` -> 0.01745).

    Parameters
    ----------
    quantity : pint.Quantity
        A scalar or an array quantity.

    Returns
    -------
    float or array
        The magnitude in SI base units, of the quantity's magnitude type.

    Raises
    ------
    ValueError
        If the quantity has a dimension outside the SI base dimensions (e.g. bits), or pint
        cannot convert it.
    """
    dimensions = dict(quantity.dimensionality)
    other = [d for d in dimensions if d not in _SI_BASE]
    if other:
        raise ValueError(
            f"cannot convert {quantity} to SI base units: its dimension {', '.join(other)} is "
            f"none of {', '.join(_SI_BASE)}"
        )
    unit = " * ".join(f"{_SI_BASE[d]} ** {e}" for d, e in dimensions.items()) or "dimensionless"
    try:
        return quantity.to(unit).magnitude
    except Exception as error:  # pint's offset-unit errors share no useful base class
        raise ValueError(f"cannot convert {quantity} to SI base units ({unit}): {error}") from None


def _quantity_to(value: Any, kind: str, name: str) -> Any:
    si_unit, example = DIMENSIONS[kind]
    if kind == "temperature difference":
        value = value - type(value)(0, value.units)  # 2 degC as a difference is 2 K, as in text
    try:
        return value.to(si_unit).magnitude
    except OverflowError:  # an integer magnitude too large for a float
        raise ValueError(
            f"{name} must be finite; got a number of {value.units} beyond "
            f"{sys.float_info.max:.4g} (it overflows)"
        ) from None
    except Exception as error:  # pint raises DimensionalityError or offset-unit errors
        expected = value._REGISTRY.get_dimensionality(si_unit)
        raise ValueError(
            f"{name}: {value} is not a {kind}: expected dimension {expected} ({si_unit}, e.g. "
            f"{example}), got {value.dimensionality}"
        ) from error


def to_si(value: Any, kind: str, name: str, *, strict: bool = False) -> float:
    """One quantity, given as text, a pint ``Quantity`` or an SI number, as a float in SI units.

    Parameters
    ----------
    value : str, pint.Quantity or float
        Text with a unit (``"17 um"``, see :func:`parse_quantity`), a scalar pint quantity of
        the dimension of ``kind`` (``17 * ureg.um``; a temperature difference in degC counts as
        a difference), or, unless ``strict``, a real number already in the SI unit of ``kind``.
    kind : str
        A key of :data:`DIMENSIONS`.
    name : str
        The input's name for error messages (e.g. ``"pitch"``).
    strict : bool
        Reject a bare number (a scenario file, where every quantity carries its unit).

    Returns
    -------
    float
        The finite value in the SI unit of ``kind`` (m, rad, K, Np/m, s, W/m²).

    Raises
    ------
    ValueError
        Naming the input: a bare number when ``strict`` (saying which unit to add), a quantity
        of another dimension, text that is not a quantity of ``kind``, a non-finite value, or a
        value of another type.
    """
    if kind not in DIMENSIONS:
        raise ValueError(f"kind must be one of {', '.join(DIMENSIONS)}; got {kind!r}")
    si_unit, example = DIMENSIONS[kind]
    if isinstance(value, str):
        result = parse_quantity(value, kind, name)
    elif is_quantity(value):
        magnitude = _quantity_to(value, kind, name)
        zero_dim = getattr(magnitude, "ndim", None) == 0 and magnitude.dtype.kind in "iuf"
        if not (zero_dim or isinstance(magnitude, numbers.Real)) or isinstance(magnitude, bool):
            raise ValueError(f"{name}: expected one real {kind}, got {value}")
        result = float(magnitude)
    elif isinstance(value, numbers.Real) and not isinstance(value, bool):
        if strict:
            raise ValueError(
                f"{name}: missing unit: got {value!r}; write the {kind} as a string with its "
                f"unit, e.g. {example}"
            )
        try:
            result = float(value)
        except OverflowError:  # an integer (or fraction) beyond double precision
            raise ValueError(
                f"{name} must be finite; got a number beyond {sys.float_info.max:.4g} "
                "(it overflows)"
            ) from None
    else:
        # bool, complex, bytes, dates, None, arrays...: never read as a number
        how = "as a string with a unit" if strict else f"with a unit, or a number in {si_unit}"
        raise ValueError(
            f"{name}: expected a {kind} {how} (e.g. {example}); got {type(value).__name__}"
        )
    return check_finite(name, result)
