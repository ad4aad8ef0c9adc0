"""pint quantities given to the Python kernels are converted to SI base units."""

import math

import numpy as np
import pint
import pytest

import targetacq as ta
from targetacq.base.arrays import arrays, as_float

ureg = pint.UnitRegistry()


def test_ifov_of_quantities_is_in_si():
    # 17 um / 75 mm, written out by hand in metres.
    assert ta.ifov(17 * ureg.um, 75 * ureg.mm) == pytest.approx(17e-6 / 75e-3, rel=1e-15)
    assert ta.ifov(17 * ureg.um, 0.075) == pytest.approx(2.2666666666666667e-4, rel=1e-15)


def test_band_exitance_of_kelvin_equals_the_float_call():
    assert ta.band_exitance(300 * ureg.K, "lwir") == ta.band_exitance(300.0, "lwir")


def test_celsius_temperature_converts_to_kelvin():
    # 26.85 degC = 300 K; an offset unit must not be scaled like a difference.
    celsius = ureg.Quantity(26.85, "degC")
    assert ta.band_exitance(celsius, "lwir") == pytest.approx(
        ta.band_exitance(300.0, "lwir"), rel=1e-12
    )
    fahrenheit = ureg.Quantity(np.array([32.0, 212.0]), "degF")
    np.testing.assert_allclose(as_float(fahrenheit, np), [273.15, 373.15], rtol=1e-14)


def test_angle_in_degrees_becomes_radians():
    ifov = ta.ifov_from_field_of_view(12 * ureg.deg, 640)
    assert ifov == pytest.approx(math.radians(12) / 640, rel=1e-14)


def test_dimensionless_quantity_is_its_plain_number():
    ratio = (17 * ureg.um) / (75 * ureg.mm)  # um/mm: the magnitude 17/75 is not the ratio
    assert as_float(ratio, np) == pytest.approx(17e-6 / 75e-3, rel=1e-15)
    assert as_float(5 * ureg.percent, np) == pytest.approx(0.05, rel=1e-15)


def test_registry_unit_system_does_not_change_the_result():
    # to_base_units() of an imperial registry gives yards; the kernels need metres.
    imperial = pint.UnitRegistry(system="imperial")
    assert as_float(imperial.Quantity(3.0, "mm"), np) == pytest.approx(0.003, rel=1e-15)
    irradiance = imperial.Quantity(500.0, "W/m^2")
    assert as_float(irradiance, np) == pytest.approx(500.0, rel=1e-15)


def test_array_quantities_keep_shape_and_mix_with_plain_values():
    xp, (pitch, focal) = arrays(ureg.Quantity(np.array([12.0, 17.0]), "um"), 0.1)
    assert xp is np or xp.__name__.endswith("numpy")
    np.testing.assert_allclose(pitch, [12e-6, 17e-6], rtol=1e-15)
    assert focal == 0.1
    np.testing.assert_allclose(
        ta.ifov(ureg.Quantity([12.0, 17.0], "um"), 100 * ureg.mm), [1.2e-4, 1.7e-4], rtol=1e-14
    )


def test_quantity_outside_si_base_dimensions_raises():
    with pytest.raises(ValueError, match=r"its dimension \[printing_unit\] is none of"):
        as_float(3 * ureg.pixel, np)


def test_checks_still_apply_after_conversion():
    with pytest.raises(ValueError, match="pitch must be > 0"):
        ta.ifov(-17 * ureg.um, 75 * ureg.mm)


def test_kernels_on_plain_numbers_do_not_import_pint():
    import subprocess
    import sys

    code = (
        "import sys, targetacq as ta; ta.ifov(17e-6, 75e-3); ta.band_exitance(300.0, 'lwir'); "
        "assert 'pint' not in sys.modules, 'pint imported'"
    )
    subprocess.run([sys.executable, "-c", code], check=True)
