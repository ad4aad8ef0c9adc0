"""Uncertainty bands (:mod:`targetacq.run.uncertainty`): the lognormal draws, the bands over
the one vectorised solve, their reproducibility and their checks."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from targetacq.core import ranges
from targetacq.core.cases import RangeCase, case_acquisition
from targetacq.run import uncertainty as unc
from targetacq.run.uncertainty import (
    TABLE_N50_SPREAD,
    Uncertainty,
    lognormal_factors,
    parse_spread,
    read_uncertainty,
    uncertainty_curves,
    uncertainty_ranges,
)

CLEAR = RangeCase(2.3, 2e-4)  # closed form: R = d / (N50 · 2 IFOV), 5,750 m for detection
HAZE = RangeCase(2.3, 2e-4, extinction=0.4e-3, contrast=2.0, noise_equivalent_contrast=0.05)


def test_table_spread_is_table_3_2s_25_percent():
    # Sonesson (2004) Table 3.2: "±25 %" for every task.
    assert pytest.approx(0.25) == TABLE_N50_SPREAD
    assert Uncertainty().n50_spread == pytest.approx(0.25)


def test_lognormal_factors_have_median_one_and_the_stated_relative_spread():
    f = lognormal_factors(0.25, 7, 1, 40_000)
    assert np.median(f) == pytest.approx(1.0, abs=0.01)
    assert f.std() / f.mean() == pytest.approx(0.25, rel=0.03)
    assert np.all(f > 0)
    assert np.all(lognormal_factors(0.0, 7, 1, 10) == 1.0)


def test_closed_form_band_is_the_lognormal_quantiles():
    # R = R0 / f with f lognormal(σ = sqrt(ln(1 + s²))): the 95 % point is R0 · exp(1.645 σ).
    found = uncertainty_ranges(CLEAR, [0.5], Uncertainty(20_000, seed=3))["detection"]
    sigma = math.sqrt(math.log(1 + 0.25**2))
    assert found["nominal"][0] == pytest.approx(5750.0)
    assert found["p95"][0] == pytest.approx(5750.0 * math.exp(1.6449 * sigma), rel=0.02)
    assert found["p05"][0] == pytest.approx(5750.0 * math.exp(-1.6449 * sigma), rel=0.02)
    assert found["p50"][0] == pytest.approx(5750.0, rel=0.01)


@settings(max_examples=12)
@given(
    spread=st.floats(0.02, 0.5),
    wider=st.floats(1.2, 2.0),
    seed=st.integers(0, 2**32),
    p=st.sampled_from([0.5, 0.8]),
    drawn=st.sampled_from(
        [
            (CLEAR, "n50_spread"),
            (CLEAR, "observer_spread"),
            (HAZE, "netd_spread"),
            (HAZE, "extinction_spread"),
        ]
    ),
)
def test_band_contains_the_nominal_range_and_grows_with_the_spread(spread, wider, seed, p, drawn):
    case, knob = drawn
    # one input drawn: the range is monotone in it, so the same draws spread wider
    others = {"n50_spread": 0.0}
    narrow_u = Uncertainty(100, seed=seed, **{**others, knob: spread})
    wide_u = Uncertainty(100, seed=seed, **{**others, knob: min(1.0, spread * wider)})
    narrow = uncertainty_ranges(case, [p], narrow_u)
    wide = uncertainty_ranges(case, [p], wide_u)
    for task in ("detection", "recognition", "identification"):
        a, b = narrow[task], wide[task]
        assert a["p05"][0] <= a["nominal"][0] <= a["p95"][0]
        assert b["p05"][0] <= b["nominal"][0] <= b["p95"][0]
        assert b["p95"][0] - b["p05"][0] > a["p95"][0] - a["p05"][0]


def test_every_input_spread_widens_the_band():
    base = uncertainty_ranges(HAZE, [0.5], Uncertainty(200, n50_spread=0.0))["detection"]
    assert base["p05"][0] == base["p95"][0] == pytest.approx(base["nominal"][0])
    for knob in ("observer_spread", "netd_spread", "extinction_spread"):
        u = Uncertainty(200, n50_spread=0.0, **{knob: 0.3})
        band = uncertainty_ranges(HAZE, [0.5], u)["detection"]
        assert band["p05"][0] < base["nominal"][0] < band["p95"][0], knob


def test_reproducible_from_the_seed_and_independent_of_the_sample_count():
    u = Uncertainty(500, seed=11, netd_spread=0.1, extinction_spread=0.2)
    first = uncertainty_ranges(HAZE, [0.5, 0.8], u)
    again = uncertainty_ranges(HAZE, [0.5, 0.8], u)
    fewer = uncertainty_ranges(
        HAZE, [0.5, 0.8], Uncertainty(100, seed=11, netd_spread=0.1, extinction_spread=0.2)
    )
    other = uncertainty_ranges(
        HAZE, [0.5, 0.8], Uncertainty(500, seed=12, netd_spread=0.1, extinction_spread=0.2)
    )
    for task in first:
        np.testing.assert_array_equal(first[task]["samples"], again[task]["samples"])
        # sample i is a function of (seed, i) only: counter-based streams
        np.testing.assert_allclose(first[task]["samples"][:100], fewer[task]["samples"], rtol=1e-9)
        assert not np.array_equal(first[task]["samples"], other[task]["samples"])


def test_samples_are_one_vectorised_solve(monkeypatch):
    calls = []
    original = ranges.case_ranges

    def counting(case, probability, tolerance=1e-9):
        calls.append(np.shape(case.critical_dimension))
        return original(case, probability, tolerance)

    monkeypatch.setattr(ranges, "case_ranges", counting)
    uncertainty_ranges(HAZE, [0.5, 0.9], Uncertainty(300, extinction_spread=0.2))
    assert calls == [(), (300, 1)]  # the nominal case, then every sample as one array


def test_samples_agree_with_a_case_solved_alone():
    u = Uncertainty(40, seed=5, netd_spread=0.2, extinction_spread=0.3)
    found = uncertainty_ranges(HAZE, [0.5], u)["recognition"]["samples"]
    f = lognormal_factors(0.25, 5, 1, 40)
    g_netd = lognormal_factors(0.2, 5, 3, 40)
    g_ext = lognormal_factors(0.3, 5, 4, 40)
    for i in (0, 17, 39):  # an N50 × f is the same as recognition needing 4 f cycles
        alone = RangeCase(
            2.3,
            2e-4,
            criterion={"detection": f[i], "recognition": 4.0 * f[i]},
            extinction=0.4e-3 * g_ext[i],
            contrast=2.0,
            noise_equivalent_contrast=0.05 * g_netd[i],
            target_area=2.3**2,
        )
        assert found[i, 0] == pytest.approx(
            float(ranges.case_ranges(alone, 0.5)["recognition"]), rel=1e-6
        )


def test_curve_bands_contain_the_nominal_curve():
    grid = np.linspace(100.0, 8000.0, 50)
    bands = uncertainty_curves(HAZE, grid, Uncertainty(200, extinction_spread=0.2))
    nominal = case_acquisition(HAZE, grid)
    for task in ("detection", "recognition", "identification"):
        curve = np.asarray(getattr(nominal, task))
        assert np.all(bands[f"{task}_p05"] <= curve + 1e-12)
        assert np.all(curve <= bands[f"{task}_p95"] + 1e-12)
    assert np.any(bands["detection_p95"] - bands["detection_p05"] > 0.05)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"netd_spread": math.nan}, r"netd_spread must be a relative spread in \[0, 1\]"),
        ({"extinction_spread": -0.1}, r"extinction_spread must be a relative spread in \[0, 1\]"),
        ({"observer_spread": 1.5}, r"observer_spread must be a relative spread in \[0, 1\]"),
        ({"n50_spread": math.inf}, r"n50_spread must be a relative spread in \[0, 1\]"),
        ({"samples": 5}, r"samples must be a whole number in \[20, 100000\]"),
        ({"samples": True}, r"samples must be a whole number"),
        ({"seed": -1}, r"seed must be an integer"),
    ],
)
def test_invalid_settings_raise_naming_the_input_and_its_range(kwargs, message):
    with pytest.raises(ValueError, match=message):
        Uncertainty(**kwargs)


@pytest.mark.parametrize("text", ["nan%", "25", "-5%", "101%", "inf%", "%", "ten%"])
def test_spread_text_needs_a_percentage_in_range(text):
    with pytest.raises(ValueError, match=r"--netd-spread must be a percentage from 0% to 100%"):
        parse_spread(text, "--netd-spread")


def test_read_uncertainty_reads_the_options_and_refuses_knobs_alone():
    u = read_uncertainty({"uncertainty": "300", "seed": "9", "extinction_spread": "20%"})
    assert (u.samples, u.seed, u.extinction_spread) == (300, 9, pytest.approx(0.2))
    with pytest.raises(ValueError, match="--seed go with --uncertainty"):
        read_uncertainty({"uncertainty": None, "seed": "1"})
    with pytest.raises(ValueError, match=r"--seed must be an integer"):
        read_uncertainty({"uncertainty": "100", "seed": "-3"})


def test_spreads_of_inputs_the_case_lacks_raise():
    with pytest.raises(ValueError, match=r"netd_spread \(--netd-spread\) needs"):
        uncertainty_ranges(CLEAR, [0.5], Uncertainty(50, netd_spread=0.1))
    with pytest.raises(ValueError, match=r"extinction_spread \(--extinction-spread\) needs"):
        uncertainty_ranges(CLEAR, [0.5], Uncertainty(50, extinction_spread=0.1))
    with pytest.raises(ValueError, match="criterion with probabilities"):
        uncertainty_ranges(RangeCase(2.3, 2e-4, criterion="en62676-4"), [0.5], Uncertainty(50))


def test_module_draws_have_one_stream_per_input():
    purposes = {unc._N50, unc._OBSERVER, unc._NETD, unc._EXTINCTION}
    assert len(purposes) == 4


def test_mrtd_samples_are_cases_with_the_n50s_scaled():
    # The MRTD's cycles are f*(τ ΔT) · d / R: an N50 × f is the critical dimension ÷ f.
    from targetacq.physics.mrtd import MrtdCurve

    curve = MrtdCurve(frequency=(500.0, 1000.0, 1500.0), mrtd=(0.05, 0.1, 0.4))
    case = RangeCase(2.3, 2e-4, mrtd=curve, contrast=1.0, extinction=0.3e-3)
    found = uncertainty_ranges(case, [0.5], Uncertainty(30, seed=2))["identification"]
    f = lognormal_factors(0.25, 2, 1, 30)
    for i in (0, 29):
        n50 = {"detection": f[i], "recognition": 4.0 * f[i], "identification": 6.4 * f[i]}
        alone = RangeCase(2.3, 2e-4, mrtd=curve, contrast=1.0, extinction=0.3e-3, criterion=n50)
        expected = float(ranges.case_ranges(alone, 0.5)["identification"])
        assert found["samples"][i, 0] == pytest.approx(expected, rel=1e-6)
    assert found["p05"][0] < found["nominal"][0] < found["p95"][0]


def test_band_contains_the_nominal_range_with_every_input_drawn():
    # four inputs, each median at its nominal value: at least 2^-4 of the samples on each side
    u = Uncertainty(300, seed=21, observer_spread=0.3, netd_spread=0.3, extinction_spread=0.3)
    for task, band in uncertainty_ranges(HAZE, [0.5, 0.9], u).items():
        assert np.all(band["p05"] < band["nominal"]), task
        assert np.all(band["nominal"] < band["p95"]), task
