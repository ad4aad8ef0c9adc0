"""Sky reflection of low-emissivity surfaces and the negative contrast it can give (§6.3).

Expected values from an independent computation: Planck's law integrated by quadrature with
scipy's CODATA constants, not the project's closed form.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import constants, integrate

from targetacq.physics.radiometry import band_exitance, sky_reflected_exitance
from targetacq.run.range_options import range_setup
from targetacq.run.scene import scene_signature

LWIR = (8e-6, 12e-6)


def planck_band(temperature: float, band: tuple[float, float]) -> float:
    """∫ 2π h c² / λ⁵ / (exp(hc/λkT) − 1) dλ over the band, by adaptive quadrature [W/m²]."""
    h, c, k = constants.h, constants.c, constants.k

    def spectral(lam: float) -> float:
        return 2 * math.pi * h * c**2 / lam**5 / math.expm1(h * c / (lam * k * temperature))

    value, _ = integrate.quad(spectral, *band, epsabs=0.0, epsrel=1e-12)
    return value


@pytest.mark.parametrize(
    ("eps", "t", "t_sky"), [(0.1, 300.0, 240.0), (0.5, 290.0, 260.0), (0.9, 310.0, 200.0)]
)
def test_apparent_exitance_is_emission_plus_reflected_sky_by_quadrature(eps, t, t_sky):
    expected = eps * planck_band(t, LWIR) + (1 - eps) * planck_band(t_sky, LWIR)
    assert float(sky_reflected_exitance(eps, t, t_sky, LWIR)) == pytest.approx(expected, rel=1e-9)


def test_blackbody_reflects_nothing_exactly():
    got = sky_reflected_exitance(np.array([1.0, 1.0]), 300.0, np.array([0.0, 250.0]), "lwir")
    assert np.all(got == band_exitance(300.0, "lwir"))


def test_low_emissivity_hot_target_under_cold_sky_has_negative_contrast():
    # A 300 K target of ε = 0.1 on a 295 K blackbody ground, under a 240 K clear sky: colder.
    m_t = 0.1 * planck_band(300.0, LWIR) + 0.9 * planck_band(240.0, LWIR)
    m_b = planck_band(295.0, LWIR)
    assert m_t < m_b  # the independent numbers say negative
    seen = scene_signature(LWIR, 300.0, 295.0, target_emissivity=0.1, sky_temperature=240.0)
    assert float(seen.sign) == -1.0
    assert float(seen.contrast) == pytest.approx(m_b - m_t, rel=1e-9)
    # Without the sky (or under an overcast sky at the target's own temperature) it is positive.
    assert float(scene_signature(LWIR, 300.0, 295.0, target_emissivity=1.0).sign) == 1.0
    overcast = scene_signature(LWIR, 300.0, 295.0, target_emissivity=0.1, sky_temperature=300.0)
    assert float(overcast.sign) == 1.0


def test_contrast_is_continuous_through_the_sign_change():
    eps = np.linspace(0.05, 1.0, 2001)
    seen = scene_signature(LWIR, 300.0, 295.0, target_emissivity=eps, sky_temperature=240.0)
    signed = np.asarray(seen.sign) * np.asarray(seen.contrast)
    assert signed[0] < 0 < signed[-1]
    # Linear in ε: each step of Δε moves the signed contrast by (M(T) − M(T_sky)) Δε at most.
    step = (planck_band(300.0, LWIR) - planck_band(240.0, LWIR)) * (eps[1] - eps[0])
    assert np.max(np.abs(np.diff(signed))) <= step * (1 + 1e-9)


def test_default_scene_is_the_grey_body_of_today():
    eps = np.array([0.3, 0.9, 1.0])
    seen = scene_signature(LWIR, 305.0, 295.0, target_emissivity=eps, background_emissivity=0.8)
    expected = np.abs(eps * band_exitance(305.0, LWIR) - 0.8 * band_exitance(295.0, LWIR))
    assert np.array_equal(seen.contrast, expected)


def test_sky_temperature_is_checked():
    with pytest.raises(ValueError, match="sky_temperature"):
        sky_reflected_exitance(0.5, 300.0, -1.0, "lwir")


def _dri(**extra):
    base = {
        "pitch": "17um",
        "focal_length": "75mm",
        "critical_dimension": "2.3m",
        "band": "lwir",
        "target_temperature": "300K",
        "background_temperature": "295K",
        "netd": "50mK",
    }
    return range_setup({**base, **extra})


def test_range_options_report_the_sign_and_use_the_magnitude():
    plain = _dri()
    assert "contrast_sign" not in plain.scene  # today's output, unchanged
    assert plain.case.contrast == _dri(emissivity=1.0, sky_temperature="240K").case.contrast
    cold = _dri(emissivity=0.1, sky_temperature="240K")
    assert cold.scene["contrast_sign"] == -1
    m_t = 0.1 * planck_band(300.0, LWIR) + 0.9 * planck_band(240.0, LWIR)
    assert cold.scene["contrast_w_per_m2"] == pytest.approx(
        planck_band(295.0, LWIR) - m_t, rel=1e-9
    )
    assert cold.case.contrast > 0  # the acquisition sees |contrast|


def test_sky_temperature_needs_the_temperatures():
    with pytest.raises(ValueError, match="--sky-temperature"):
        range_setup(
            {
                "pitch": "17um",
                "focal_length": "75mm",
                "critical_dimension": "2.3m",
                "sky_temperature": "240K",
            }
        )


def test_scenario_background_sky_reaches_the_thermal_signature():
    from targetacq.scenario.schema import Background, Target
    from targetacq.sensors import thermal

    class Sensor:
        limits = LWIR

    target = Target(
        name="t", dimensions=(4, 2, 2), position=(0, 0, 0), temperature="300 K", emissivity=0.1
    )
    plain = Background(temperature="295 K")
    sky = Background(temperature="295 K", sky_temperature="240 K")
    seen = thermal.signature(Sensor(), sky, [target])
    assert float(seen.target[0]) == pytest.approx(
        0.1 * planck_band(300.0, LWIR) + 0.9 * planck_band(240.0, LWIR), rel=1e-9
    )
    assert seen.background == thermal.signature(Sensor(), plain, [target]).background  # ε_b = 1
    assert float(seen.target[0]) < seen.background
