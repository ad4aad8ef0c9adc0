"""Quantities with units at the boundary."""

import math

import pytest

from targetacq.units import is_quantity, parse_quantity, si_magnitude, to_si


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


ureg = __import__("pint").UnitRegistry()


@pytest.mark.parametrize(
    ("value", "kind", "si"),
    [
        ("17 um", "length", 17e-6),
        (17e-6, "length", 17e-6),
        (3, "time", 3.0),
        (ureg.Quantity(17, "um"), "length", 17e-6),
        (ureg.Quantity(2.5, "km"), "length", 2500.0),
        (ureg.Quantity(12, "deg"), "angle", math.radians(12)),
        (ureg.Quantity(22, "degC"), "temperature", 295.15),
        (ureg.Quantity(32, "degF"), "temperature", 273.15),
        # A difference in degC is that many kelvin, as for the text "2 degC".
        (ureg.Quantity(2, "degC"), "temperature difference", 2.0),
        (ureg.Quantity(2, "delta_degC"), "temperature difference", 2.0),
        (ureg.Quantity(0.4, "1/km"), "extinction", 4e-4),
        (ureg.Quantity(2, "min"), "time", 120.0),
        (ureg.Quantity(0.05, "W/cm^2"), "irradiance", 500.0),
    ],
)
def test_to_si_accepts_text_quantities_and_si_numbers(value, kind, si):
    assert to_si(value, kind, "x") == pytest.approx(si, rel=1e-12)


def test_to_si_strict_refuses_bare_numbers_but_not_quantities():
    with pytest.raises(ValueError, match=r"^pitch: missing unit: got 17; .*length.*17 um"):
        to_si(17, "length", "pitch", strict=True)
    assert to_si(ureg.Quantity(17, "um"), "length", "pitch", strict=True) == pytest.approx(17e-6)
    assert to_si("17 um", "length", "pitch", strict=True) == pytest.approx(17e-6)


@pytest.mark.parametrize(
    ("value", "match"),
    [
        (
            ureg.Quantity(17, "K"),
            r"pitch: 17 kelvin is not a length: expected dimension \[length\]",
        ),
        (ureg.Quantity(17, "um/mm"), r"pitch: .* is not a length: .*got dimensionless"),
        (ureg.Quantity([1.0, 2.0], "um"), "pitch: expected one real length"),
        (float("nan"), "pitch must be finite, got nan"),
        (float("-inf"), "pitch must be finite, got -inf"),
        (ureg.Quantity(float("inf"), "um"), "pitch must be finite, got inf"),
        ("1e999 m", "pitch must be finite, got inf"),
        (True, "pitch: expected a length with a unit, or a number in meter"),
        ([17e-6], "pitch: expected a length .*; got list"),
    ],
)
def test_to_si_errors_name_the_input(value, match):
    with pytest.raises(ValueError, match=match):
        to_si(value, "length", "pitch")


def test_to_si_unknown_kind():
    with pytest.raises(ValueError, match="kind must be one of length, area, angle"):
        to_si(1.0, "mass", "x")


def test_is_quantity_and_si_magnitude():
    assert is_quantity(ureg.Quantity(1, "m"))
    assert not is_quantity(1.0)
    assert not is_quantity("1 m")
    # 1 W/cm² = 1e4 kg s⁻³ in SI base units; 1 mrad is dimensionless 1e-3.
    assert si_magnitude(ureg.Quantity(1, "W/cm^2")) == pytest.approx(1e4, rel=1e-15)
    assert si_magnitude(ureg.Quantity(1, "mrad")) == pytest.approx(1e-3, rel=1e-15)
    assert si_magnitude(ureg.Quantity(-40, "degC")) == pytest.approx(233.15, rel=1e-15)
