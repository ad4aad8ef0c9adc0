"""The contrast-aware SNR kernel (targetacq.physics.detector_noise.contrast_snr) and the
probability of being seen above the noise (targetacq.acquisition.path_noise.seen_probability),
against independent computations and properties."""

from __future__ import annotations

import math

import numpy as np
import pytest

from targetacq.acquisition.path_noise import THRESHOLD_SNR, seen_probability
from targetacq.physics.detector_noise import contrast_snr


def _independent(c, nec, sigma, tau, n):
    g = math.sqrt(n) if n >= 1 else n
    return 20 * math.log10(tau * abs(c) / math.hypot(nec / g, (1 - tau) * sigma))


@pytest.mark.parametrize(
    ("c", "nec", "sigma", "tau", "n"),
    [(0.5, 0.05, 1.0, 0.8, 400.0), (45.0, 0.05, 1.0, 0.3, 9.0), (-2.0, 0.02, 1.0, 0.95, 0.25)],
)
def test_contrast_snr_is_the_stated_formula(c, nec, sigma, tau, n):
    assert float(contrast_snr(c, nec, sigma, tau, n)) == pytest.approx(
        _independent(c, nec, sigma, tau, n), rel=1e-12
    )


def test_reference_target_without_sensor_noise_is_eq_7_7():
    """σ_path is chosen so that a target of that contrast gets 20 log10(τ/(1 − τ))."""
    tau = np.array([0.1, 0.5, 0.9, 0.999])
    expected = 20 * np.log10(tau / (1 - tau))
    assert np.allclose(contrast_snr(1.0, 0.0, 1.0, tau, 50.0), expected, rtol=0, atol=1e-9)


def test_snr_decreases_with_range_and_increases_with_contrast():
    r = np.linspace(100.0, 8000.0, 200)
    tau = np.exp(-0.2e-3 * r)
    pixels = 2.3**2 / (r * 0.2267e-3) ** 2
    snr = contrast_snr(0.5, 0.05, 1.0, tau, pixels)
    assert np.all(np.diff(snr) < 0)
    contrasts = np.array([0.001, 0.01, 0.5, 5.0, 45.0])
    at = contrast_snr(contrasts, 0.05, 1.0, 0.7, 30.0)
    assert np.all(np.diff(at) > 0)


def test_a_hotter_target_is_better_seen_through_haze():
    """Unlike Eq. (7.7), the path's noise does not cap the SNR whatever the contrast."""
    tau, n = math.exp(-1.0), 10.0
    assert float(contrast_snr(45.0, 0.05, 1.0, tau, n)) - float(
        contrast_snr(0.5, 0.05, 1.0, tau, n)
    ) == pytest.approx(20 * math.log10(90.0), rel=1e-12)


def test_limits_and_nan():
    assert float(contrast_snr(0.0, 0.05, 1.0, 0.5, 10.0)) == -math.inf
    assert float(contrast_snr(1.0, 0.0, 1.0, 1.0, 10.0)) == math.inf
    assert float(contrast_snr(1.0, 0.05, 1.0, 0.0, 10.0)) == -math.inf
    assert math.isnan(float(contrast_snr(math.nan, 0.05, 1.0, 0.5, 10.0)))
    with pytest.raises(ValueError, match="path_contrast"):
        contrast_snr(1.0, 0.05, 0.0, 0.5, 10.0)


def test_seen_probability_is_the_normal_cdf_of_snr_minus_k():
    lin = np.array([0.0, 1.0, 3.0, 4.5, 10.0])
    with np.errstate(divide="ignore"):
        db = 20 * np.log10(lin)
    expected = [0.5 * math.erfc(-(x - THRESHOLD_SNR) / math.sqrt(2)) for x in lin]
    assert np.allclose(seen_probability(db), expected, rtol=1e-12, atol=1e-300)
    assert float(seen_probability(math.inf)) == 1.0
    # No signal: the threshold's own rate, Φ(−k) (the transforms then give P = 0 anyway).
    assert float(seen_probability(-math.inf)) == pytest.approx(0.5 * math.erfc(3 / math.sqrt(2)))
    assert float(seen_probability(-math.inf, -math.inf)) == 1.0
    assert math.isnan(float(seen_probability(math.nan)))
    with pytest.raises(ValueError, match="threshold"):
        seen_probability(0.0, -1.0)


def test_seen_probability_is_smooth_in_contrast():
    """A 1 % change of the contrast (so of the SNR) moves P_seen by less than 0.02 anywhere."""
    lin = np.geomspace(1e-3, 1e3, 20001)
    p = seen_probability(20 * np.log10(lin))
    p_up = seen_probability(20 * np.log10(lin * 1.01))
    assert float(np.max(np.abs(p_up - p))) < 0.02
