"""Quantities with units at the boundary."""

import math

import pytest

from targetacq.units import parse_quantity


@pytest.mark.parametrize(
    ("text", "kind", "si"),
    [
        ("17um", "length", 17e-6),
        ("17 um", "length", 17e-6),
        ("75 mm", "length", 0.075),
        ("2.5 km", "length", 2500.0),
        ("0.227mrad", "angle", 0.227e-3),
        ("12deg", "angle", math.radians(12)),
    ],
)
def test_parse_to_si(text, kind, si):
    assert parse_quantity(text, kind, "--x") == pytest.approx(si, rel=1e-12)


@pytest.mark.parametrize(
    ("text", "kind", "match"),
    [
        ("17", "length", "--x needs a unit: got '17'"),
        ("17 s", "length", "is not a length"),
        ("2 m", "angle", "is not a angle"),
        ("seventeen", "length", "cannot read"),
        ("", "length", "needs a unit|cannot read"),
    ],
)
def test_bad_quantities(text, kind, match):
    with pytest.raises(ValueError, match=match):
        parse_quantity(text, kind, "--x")


@pytest.mark.parametrize(
    ("kind", "unit"),
    [
        (kind, unit)
        for kind, units in __import__("targetacq.units").units._PLAIN_UNITS.items()
        for unit in units
    ],
)
def test_plain_units_agree_with_pint(kind, unit):
    import pint

    from targetacq.units import DIMENSIONS

    ureg = pint.UnitRegistry()
    pint_unit = {"1/m": "1/m", "/m": "1/m", "/km": "1/km", "W/m^2": "W/m**2"}.get(unit, unit)
    expected = ureg.Quantity(2.5, pint_unit).to(DIMENSIONS[kind][0]).magnitude
    assert parse_quantity(f"2.5 {unit}", kind, "--x") == pytest.approx(expected, rel=1e-15)
