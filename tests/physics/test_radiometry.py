"""Radiometry: Planck (6.2), band exitance (6.12) by series against quadrature, (6.1)–(6.18)."""

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy import constants, integrate

import targetacq as ta
from targetacq.physics import radiometry


def planck_by_hand(lam, t):
    """Eq. (6.2) written out independently from CODATA constants."""
    h, c, k = constants.h, constants.c, constants.k
    return 2 * math.pi * h * c**2 / lam**5 / math.expm1(h * c / (lam * k * t))


def band_by_quadrature(t, low, high):
    value, _ = integrate.quad(
        planck_by_hand, low, high, args=(t,), epsrel=1e-12, epsabs=0, limit=200
    )
    return value


@pytest.mark.parametrize(
    ("t", "band", "printed", "digits"),
    [  # check values of the user guide (CODATA, numerical quadrature)
        (300.0, (8e-6, 12e-6), 120.95, 0.005),
        (270.0, (8e-6, 12e-6), 70.32, 0.005),
        (300.0, (3e-6, 5e-6), 5.862, 0.0005),
    ],
)
def test_planck_check_values(t, band, printed, digits):
    quadrature = band_by_quadrature(t, *band)
    assert quadrature == pytest.approx(printed, abs=digits)
    assert ta.band_exitance(t, band) == pytest.approx(quadrature, rel=1e-9)


@settings(max_examples=60, deadline=None)
@given(st.floats(30.0, 3000.0), st.floats(0.3e-6, 30e-6), st.floats(1.05, 20.0))
def test_band_exitance_matches_quadrature_to_1e_6(t, low, ratio):
    # Where the test's plain formula does not overflow (hc/λkT < ~290; the library's own
    # overflow guard is tested separately).
    assume(low * t > 5e-5)
    quadrature = band_by_quadrature(t, low, low * ratio)
    assert quadrature > 0
    assert ta.band_exitance(t, (low, low * ratio)) == pytest.approx(quadrature, rel=1e-6)


def test_full_band_is_stefan_boltzmann():
    t = np.array([1.0, 77.0, 300.0, 5800.0])
    sigma_t4 = constants.Stefan_Boltzmann * t**4
    np.testing.assert_allclose(ta.band_exitance(t, (0.0, math.inf)), sigma_t4, rtol=1e-13)
    assert radiometry.stefan_boltzmann_exitance(300.0) == pytest.approx(459.30, abs=0.005)


def test_peak_wavelength_at_300_k():
    assert radiometry.peak_wavelength(300.0) == pytest.approx(9.659e-6, abs=0.0005e-6)
    # The peak is a maximum of the spectral exitance (independent check).
    lam = radiometry.peak_wavelength(300.0)
    m = ta.spectral_exitance(np.array([0.99, 1.0, 1.01]) * lam, 300.0)
    assert m[1] > m[0] and m[1] > m[2]


def test_spectral_exitance_is_eq_6_2():
    for lam, t in [(10e-6, 300.0), (4e-6, 500.0), (0.5e-6, 5800.0)]:
        assert ta.spectral_exitance(lam, t) == pytest.approx(planck_by_hand(lam, t), rel=1e-13)


def test_wien_approaches_planck_at_short_lambda_t():
    lam, t = 1e-6, 300.0  # hc/λkT ≈ 48
    assert radiometry.wien_spectral_exitance(lam, t) == pytest.approx(
        planck_by_hand(lam, t), rel=1e-15
    )
    # Wien band (6.13) against quadrature of the Wien formula.
    h, c, k = constants.h, constants.c, constants.k
    wien, _ = integrate.quad(
        lambda x: 2 * math.pi * h * c**2 / x**5 * math.exp(-h * c / (x * k * 300.0)),
        3e-6,
        5e-6,
        epsrel=1e-12,
    )
    assert ta.band_exitance(300.0, (3e-6, 5e-6), method="wien") == pytest.approx(wien, rel=1e-9)


def test_no_overflow_at_short_lambda_t():
    # Visible band at 1 K: exp(hc/λkT) would overflow; the result is 0 and no warning is raised.
    assert ta.band_exitance(1.0, "visible") == 0.0
    assert ta.spectral_exitance(0.4e-6, 1.0) == 0.0
    np.testing.assert_array_equal(ta.band_exitance(np.array([0.0]), "lwir"), [0.0])


def test_band_exitance_derivative():
    t = np.array([250.0, 300.0, 350.0])
    numeric = (ta.band_exitance(t + 1e-3, "lwir") - ta.band_exitance(t - 1e-3, "lwir")) / 2e-3
    np.testing.assert_allclose(radiometry.band_exitance_derivative(t, "lwir"), numeric, rtol=1e-7)
    np.testing.assert_allclose(
        radiometry.band_exitance_derivative(t, (0.0, math.inf)),
        4 * constants.Stefan_Boltzmann * t**3,
        rtol=1e-12,
    )


def test_table_6_1_and_kirchhoff():
    assert radiometry.material_reflectance("olive-paint", "lwir", "low") == pytest.approx(0.17)
    assert radiometry.material_reflectance("olive-paint", "lwir", "high") == pytest.approx(0.23)
    assert radiometry.material_reflectance("white-paint", "visible", "nominal") == pytest.approx(
        0.75
    )
    assert radiometry.material_reflectance("loam", "lwir", "low") == 0.0
    assert radiometry.material_emissivity("vegetation", "lwir") == pytest.approx(1 - 0.075)
    assert radiometry.material_reflectance("ice", "mwir", "high") == pytest.approx(0.08)
    with pytest.raises(ValueError, match="no reflectance for ice in the visible"):
        radiometry.material_reflectance("ice", "visible")
    assert radiometry.emissivity_from_reflectance(0.2) == pytest.approx(0.8)  # ε = 1 − r
    assert radiometry.emissivity_from_reflectance(0.2, 0.1) == pytest.approx(0.7)  # (6.5)
    assert radiometry.emissivity(50.0, 100.0) == pytest.approx(0.5)  # (6.4)


def test_cos4_fall_off_and_lambert():
    # cos⁴θ: 30° → 0.5625, 10° → 0.9406 (Eq. (6.17)).
    e0 = radiometry.irradiance_at_sensor(1.0, 1.0)
    assert radiometry.irradiance_at_sensor(
        1.0, 1.0, off_axis_angle=math.radians(30)
    ) / e0 == pytest.approx(0.5625)
    assert radiometry.irradiance_at_sensor(
        1.0, 1.0, off_axis_angle=math.radians(10)
    ) / e0 == pytest.approx(0.9406, abs=5e-5)
    assert radiometry.lambert_intensity(2.0, math.pi / 3) == pytest.approx(1.0)  # (6.14)
    pinhole = radiometry.irradiance_at_sensor(4.0, 2.0, math.pi / 3, math.pi / 3, lens=False)
    assert pinhole == pytest.approx(4.0 * 0.5 * 0.5 / 4.0)  # (6.16)
    assert radiometry.target_signal(0.9, 100.0, 10.0) == pytest.approx(0.9)  # (6.18)


def test_reflected_visible_signal():
    assert radiometry.reflected_exitance(0.1, 500.0) == pytest.approx(50.0)  # M = r·E, §6.2


def test_diurnal_cycle_and_quantisation():
    assert radiometry.diurnal_temperature(14.0, 290.0, 8.0) == pytest.approx(298.0)
    assert radiometry.diurnal_temperature(2.0, 290.0, 8.0) == pytest.approx(282.0)
    assert radiometry.quantisation_step(8, 255.0) == pytest.approx(1.0)
    assert radiometry.quantisation_step(14, 16383.0) == pytest.approx(1.0)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: ta.band_exitance(-1.0, "lwir"), "temperature must be >= 0"),
        (lambda: ta.band_exitance(300.0, (12e-6, 8e-6)), "0 <= λ1 < λ2"),
        (lambda: ta.band_exitance(300.0, "swir"), "unknown band 'swir'; named bands"),
        (lambda: ta.band_exitance(300.0, "lwir", method="exact"), "method must be one of"),
        (lambda: ta.spectral_exitance(0.0, 300.0), "wavelength must be > 0"),
        (lambda: radiometry.material_reflectance("steel", "lwir"), "unknown material"),
        (lambda: radiometry.material_reflectance("loam", (1e-6, 2e-6)), "tables are given for"),
        (lambda: radiometry.emissivity_from_reflectance(1.5), r"reflectance must be in \[0, 1\]"),
        (lambda: radiometry.quantisation_step(0, 1.0), "bits must be an integer >= 1"),
        (lambda: radiometry.diurnal_temperature(1.0, 280.0, 300.0), "amplitude must be smaller"),
    ],
)
def test_bad_radiometry_input(call, match):
    with pytest.raises(ValueError, match=match):
        call()
