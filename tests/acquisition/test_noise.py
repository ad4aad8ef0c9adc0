"""Noise in the transforms: limits, monotonicity, registry."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import targetacq as ta
from targetacq.acquisition import path_noise as noise


def test_effective_ratio_adds_in_variance():
    # 1/R² = 1/SCR² + 1/SNR_lin², SNR_lin = 10^(SNR/20): SCR 3, SNR 20·log10(4) dB → R = 2.4.
    assert ta.effective_scr(3.0, 20 * math.log10(4.0)) == pytest.approx(2.4)
    assert ta.effective_scr(3.0, math.inf) == 3.0  # exactly, no rounding
    assert ta.effective_scr(math.inf, 0.0) == pytest.approx(1.0)


def test_noise_factor_limits():
    # f = sqrt(1 + 3 / SNR_lin²): exactly 1 without noise, 2 at 0 dB, +inf without signal.
    assert ta.noise_n50_factor(math.inf) == 1.0
    assert ta.noise_n50_factor(0.0) == pytest.approx(2.0, rel=1e-15)
    assert ta.noise_n50_factor(-math.inf) == math.inf
    # 20 dB: SNR_lin = 10, f = sqrt(1.03); −40 dB: f = sqrt(1 + 3e4).
    assert ta.noise_n50_factor(20.0) == pytest.approx(math.sqrt(1.03), rel=1e-14)
    assert ta.noise_n50_factor(-40.0) == pytest.approx(math.sqrt(30001.0), rel=1e-14)
    assert ta.noise_n50_factor(-6000.0) == pytest.approx(math.sqrt(3.0) * 1e300, rel=1e-12)


@given(st.floats(-300, 300), st.floats(-300, 300))
def test_noise_factor_strictly_decreasing_in_snr(a, b):
    low, high = sorted((a, b))
    f_low, f_high = ta.noise_n50_factor(low), ta.noise_n50_factor(high)
    assert f_low >= f_high >= 1.0
    if high - low > 1e-6 and high < 150:
        assert f_low > f_high


def test_clutter_analogue_keeps_the_table_3_5_law():
    factor = noise.NOISE_MODELS["clutter-analogue"].n50_factor
    assert factor(25.0) == 1.0  # above 20 dB noise is weaker than any clutter
    assert factor(0.0) == pytest.approx(2.0)  # N50 1.0 / 0.5 at R = 1
    assert factor(-math.inf) == math.inf


def test_ratio_n50_follows_table_3_5_anchors():
    # 0.5 cycles (low clutter) from R = 10 up; 1.0 at R = 1 (medium); 2.5 at R = 0.33 (high).
    np.testing.assert_allclose(noise.ratio_n50([10.0, 100.0, 1.0, 0.33]), [0.5, 0.5, 1.0, 2.5])
    # "a doubling of resolution is needed when SCR drops from 10 to 1" (§3.7).
    assert noise.ratio_n50(1.0) / noise.ratio_n50(10.0) == pytest.approx(2.0)


N = st.lists(st.floats(0.0, 40.0), min_size=1, max_size=10)


@given(N, st.floats(0, 50) | st.just(math.inf))
def test_noise_free_limit_is_exactly_the_core_model(ns, scr):
    n = np.array(ns)
    for kwargs in ({}, {"scr": scr}, {"region": "high"}):
        core = ta.acquisition_probabilities(n, clutter=kwargs)
        noisy = ta.acquisition_probabilities(n, snr=math.inf, clutter=kwargs)
        for task in ("detection", "recognition", "identification"):
            np.testing.assert_array_equal(getattr(noisy, task), getattr(core, task))


@given(N, st.floats(-60, 60), st.floats(-60, 60), st.floats(0, 50))
def test_non_decreasing_in_snr(ns, snr_a, snr_b, scr):
    n = np.array(ns)
    low, high = sorted((snr_a, snr_b))
    for kwargs in ({}, {"scr": scr}):
        worse = ta.acquisition_probabilities(n, snr=low, clutter=kwargs)
        better = ta.acquisition_probabilities(n, snr=high, clutter=kwargs)
        for task in ("detection", "recognition", "identification"):
            assert np.all(getattr(worse, task) <= getattr(better, task) + 1e-15)


@given(N, st.floats(0, 50), st.floats(0, 50), st.floats(-30, 40) | st.just(math.inf))
def test_non_decreasing_in_scr(ns, scr_a, scr_b, snr):
    n = np.array(ns)
    low, high = sorted((scr_a, scr_b))
    worse = ta.acquisition_probabilities(n, clutter=ta.Clutter(scr=low), snr=snr)
    better = ta.acquisition_probabilities(n, clutter=ta.Clutter(scr=high), snr=snr)
    for task in ("detection", "recognition", "identification"):
        assert np.all(getattr(worse, task) <= getattr(better, task) + 1e-15)


def test_probability_vanishes_as_transmittance_vanishes():
    n = np.array([1.0, 10.0, 100.0])
    previous = np.ones(3)
    for snr in (-40.0, -80.0, -200.0):
        acq = ta.acquisition_probabilities(n, snr=snr, clutter=ta.Clutter(scr=5.0))
        assert np.all(acq.detection < previous)
        previous = acq.detection
    assert np.all(previous < 1e-7)
    acq = ta.acquisition_probabilities(n, snr=-math.inf, clutter=ta.Clutter(scr=5.0))
    np.testing.assert_array_equal(acq.detection, 0.0)
    np.testing.assert_array_equal(acq.identification, 0.0)
    tiny = ta.acquisition_probabilities(n, snr=ta.snr_from_transmittance(1e-12))
    assert np.all(tiny.detection < 1e-6)


def test_user_noise_model_multiplies_every_n50():
    def doubling(snr_db):
        return np.where(np.asarray(snr_db) < 10.0, 2.0, 1.0)

    n = np.array([2.0, 8.0])
    got = ta.acquisition_probabilities(n, snr=5.0, noise_model=doubling)
    expected = ta.acquisition_probabilities(n / 2.0)
    np.testing.assert_allclose(got.recognition, expected.recognition)
    np.testing.assert_allclose(got.detection, expected.detection)
    none = ta.acquisition_probabilities(n, snr=-10.0, noise_model="none")
    np.testing.assert_array_equal(none.detection, ta.acquisition_probabilities(n).detection)


def test_bad_noise_models():
    with pytest.raises(
        ValueError,
        match="unknown noise model 'gaussian'; valid: variance-sum, clutter-analogue, none",
    ):
        ta.acquisition_probabilities(1.0, snr=3.0, noise_model="gaussian")
    with pytest.raises(ValueError, match="below 1"):
        ta.acquisition_probabilities(1.0, snr=3.0, noise_model=lambda s: 0.5)
