"""Quantities with units at the boundary."""

import math

import pytest

from targetacq.base.units import is_quantity, parse_quantity, si_magnitude, to_si


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
        for kind, units in __import__("targetacq.base.units").base.units._PLAIN_UNITS.items()
        for unit in units
    ],
)
def test_plain_units_agree_with_pint(kind, unit):
    import pint

    from targetacq.base.units import DIMENSIONS

    ureg = pint.UnitRegistry()
    pint_unit = "1" + unit if unit.startswith("/") else unit
    pint_unit = pint_unit.replace("^", "**")
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
        (float("nan"), "pitch must be a number; got NaN"),
        (float("-inf"), "pitch must be finite; got -inf"),
        (ureg.Quantity(float("inf"), "um"), "pitch must be finite; got inf"),
        (ureg.Quantity(float("nan"), "um"), "pitch must be a number; got NaN"),
        ("1e999 m", r"pitch must be finite; got '1e999 m' \(the number overflows\)"),
        # finite digits, infinite product: 1e300 light years do not fit in metres
        ("1e300 lightyear", r"pitch must be finite; got '1e300 lightyear'"),
        ("1e308 km", r"pitch must be finite; got '1e308 km'"),
        ("nan m", "pitch must be a finite number with a unit"),
        ("inf m", "pitch must be a finite number with a unit"),
        ("-Infinity m", "pitch must be a finite number with a unit"),
        ("NaN", "pitch must be a finite number with a unit"),
        (10**400, r"pitch must be finite; got a number beyond 1\.798e\+308"),
        (__import__("fractions").Fraction(10**400, 3), "pitch must be finite; got a number beyond"),
        (ureg.Quantity(10**400, "um"), "pitch must be finite; got a number of micrometer beyond"),
        (True, "pitch: expected a length with a unit, or a number in meter"),
        (__import__("numpy").bool_(True), "pitch: expected a length .*; got bool"),
        ([17e-6], "pitch: expected a length .*; got list"),
        (1 + 2j, "pitch: expected a length .*; got complex"),
        (b"17 um", "pitch: expected a length .*; got bytes"),
        (__import__("datetime").datetime(2024, 1, 1), "pitch: expected a length .*; got datetime"),
        (__import__("datetime").date(2024, 1, 1), "pitch: expected a length .*; got date"),
        (__import__("decimal").Decimal("1.5"), "pitch: expected a length .*; got Decimal"),
        (None, "pitch: expected a length .*; got NoneType"),
        ("17", "pitch needs a unit: got '17'"),
        ("2024-01-01", "pitch: cannot read '2024-01-01' as a length|pitch.*unit"),
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


@pytest.mark.parametrize("text", ["1e400 um", "1e400um", "-1e400 K", "1" + "0" * 400 + " m"])
def test_parse_quantity_refuses_literals_that_overflow(text):
    kind = "temperature" if text.endswith("K") else "length"
    with pytest.raises(
        ValueError, match=r"^--x must be finite; got '.*' \(the number overflows\)$"
    ):
        parse_quantity(text, kind, "--x")


def test_parse_quantity_underflow_is_zero_not_an_error():
    # 1e-400 m is below the smallest double: it reads as 0 m, which the range checks judge.
    assert parse_quantity("1e-400 m", "length", "--x") == 0.0


@pytest.mark.parametrize("value", [float("nan"), float("inf"), "1e400 m", True, 1j, "nan m"])
def test_to_si_strict_refuses_non_finite_and_non_numbers_too(value):
    with pytest.raises(ValueError, match=r"^pitch"):
        to_si(value, "length", "pitch", strict=True)


@pytest.mark.parametrize(("value", "si"), [(17, 17.0), (__import__("numpy").float32(0.5), 0.5)])
def test_to_si_accepts_real_numbers_of_any_type(value, si):
    assert to_si(value, "length", "pitch") == si


@pytest.mark.parametrize("text", ["4000 dB", "3083 dB", "-4000 dB", "1e400 dB", "3000.5 dB"])
def test_decibels_beyond_the_stated_range_are_refused_naming_it(text):
    # 10 ** (dB / 10) overflows a double above about 3,083 dB (an OverflowError, not a
    # ValueError, before; -4000 dB read as 0): the range is stated instead, and the input named.
    with pytest.raises(ValueError, match=r"^radar\.gain must be within ±3000 dB .*got '"):
        parse_quantity(text, "power ratio", "radar.gain")
    # The ends of the stated range are read.
    assert parse_quantity("3000 dB", "power ratio", "g") == pytest.approx(1e300, rel=1e-12)
    assert parse_quantity("-3000 dB", "power ratio", "g") == pytest.approx(1e-300, rel=1e-12)
