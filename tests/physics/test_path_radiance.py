"""Path radiance (§7.2): Duntley's law of contrast reduction for reflective bands and the
thermal path's own emission. Expected values from the published laws, written out here, and
Planck's law by quadrature."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import constants, integrate

from targetacq.core.cases import RangeCase, case_factors
from targetacq.physics.atmosphere import contrast_transmittance, path_radiance
from targetacq.run.range_options import range_setup

LWIR = (8e-6, 12e-6)


def planck_band(temperature: float, band: tuple[float, float]) -> float:
    h, c, k = constants.h, constants.c, constants.k

    def spectral(lam: float) -> float:
        return 2 * math.pi * h * c**2 / lam**5 / math.expm1(h * c / (lam * k * temperature))

    return integrate.quad(spectral, *band, epsabs=0.0, epsrel=1e-12)[0]


def test_koschmieder_black_object_keeps_two_percent_at_the_visual_range():
    # Koschmieder (1924): γ V = −ln 0.02 = 3.912; a black object against the horizon sky.
    tau = math.exp(-3.912)
    assert float(contrast_transmittance(tau, 1.0)) == pytest.approx(0.02, rel=1e-3)


@pytest.mark.parametrize("k", [0.2, 1.0, 1.4, 3.0, 5.0])
@pytest.mark.parametrize("depth", [0.01, 0.5, 2.0, 6.0])
def test_middleton_form_of_the_sky_to_ground_ratio(k, depth):
    # Middleton (1952): C_R / C_0 = 1 / (1 + K (e^{γR} − 1)).
    expected = 1.0 / (1.0 + k * math.expm1(depth))
    assert float(contrast_transmittance(math.exp(-depth), k)) == pytest.approx(expected, 1e-12)


def test_contrast_transmittance_limits_and_order():
    tau = np.linspace(0.0, 1.0, 101)
    assert np.array_equal(contrast_transmittance(tau, 1.0), tau)  # K = 1: C τ, today's
    assert np.all(contrast_transmittance(tau[1:], 0.0) == 1.0)  # no airlight
    assert float(contrast_transmittance(0.0, 0.0)) == 0.0
    ks = np.array([0.2, 1.0, 3.0])[:, None]
    got = contrast_transmittance(tau[None, 1:-1], ks)
    assert np.all(np.diff(got, axis=0) < 0)  # brighter sky, less contrast
    assert np.isnan(contrast_transmittance(np.array([np.nan]), 1.0)[0])
    with pytest.raises(ValueError, match="sky_to_ground"):
        contrast_transmittance(0.5, -1.0)


def test_thermal_path_radiance_by_quadrature_and_contrast_kept():
    tau = 0.6
    l_path = float(path_radiance(tau, 285.0, LWIR))
    assert l_path == pytest.approx(0.4 * planck_band(285.0, LWIR), rel=1e-9)
    m_t, m_b = planck_band(300.0, LWIR), planck_band(295.0, LWIR)
    # Added equally to target and background: the contrast at the sensor stays τ ΔM.
    assert (tau * m_t + l_path) - (tau * m_b + l_path) == pytest.approx(tau * (m_t - m_b))


def test_tv_case_snr_follows_the_apparent_contrast():
    # The thesis's law: the sensor's SNR of the contrast Duntley's law leaves, added in variance
    # to Eq. (7.7).
    gamma, r, c, nec = 0.5e-3, 2000.0, 0.3, 0.01
    common = {
        "extinction": gamma,
        "contrast": c,
        "noise_equivalent_contrast": nec,
        "snr_law": "sonesson",
    }
    plain = RangeCase(2.3, 2e-4, **common)
    for k in (1.0, 3.0):
        _, _, snr = case_factors(RangeCase(2.3, 2e-4, sky_to_ground=k, **common), r)
        pixels = (2.3 / (r * 2e-4)) ** 2
        seen = c / (1 + k * math.expm1(gamma * r))  # Middleton: C_R = C_0 / (1 + K (e^{γR} − 1))
        own = seen * math.sqrt(pixels) / nec  # Rose gain of the pixels on target
        path = 1.0 / math.expm1(gamma * r)  # Eq. (7.7), linear
        expected = -10.0 * math.log10(1.0 / own**2 + 1.0 / path**2)
        assert float(snr) == pytest.approx(expected, rel=1e-9)
        if k == 1.0:
            assert float(snr) == float(case_factors(plain, r)[2])


def test_tv_case_contrast_law_takes_the_apparent_contrast():
    # The contrast law with airlight: the contrast's transmittance t of Duntley's law replaces τ,
    # SNR = t C / sqrt((NEC / g)² + ((1 − t) σ_path)²), σ_path = 1 (a contrast ratio of 1).
    gamma, r, c, nec = 0.5e-3, 2000.0, 0.3, 0.01
    common = {"extinction": gamma, "contrast": c, "noise_equivalent_contrast": nec}
    for k in (1.0, 3.0):
        _, _, snr = case_factors(RangeCase(2.3, 2e-4, sky_to_ground=k, **common), r)
        gain = 2.3 / (r * 2e-4)  # sqrt of the pixels on target
        t = 1.0 / (1.0 + k * math.expm1(gamma * r))
        expected = 20.0 * math.log10(t * c / math.hypot(nec / gain, 1.0 - t))
        assert float(snr) == pytest.approx(expected, rel=1e-9)


def test_sky_to_ground_needs_the_tv_noise():
    with pytest.raises(ValueError, match="noise_equivalent_contrast"):
        RangeCase(2.3, 2e-4, sky_to_ground=2.0)
    base = {"pitch": "17um", "focal_length": "75mm", "critical_dimension": "2.3m"}
    with pytest.raises(ValueError, match="--sky-to-ground"):
        range_setup({**base, "sky_to_ground": 2.0})
    setup = range_setup({**base, "nec": 0.01, "contrast": 0.3, "sky_to_ground": 2.0})
    assert setup.case.sky_to_ground == 2.0
