"""Calibration to trial data (targetacq.acquisition.calibration): N50 and the TTPF's exponent by
maximum likelihood, profile-likelihood intervals, and the fitted criterion in the registry.

Expected values come from the synthetic truth the trials were drawn with, or from a brute-force
grid of the log-likelihood written out here (the TTPF of ACQUIRE / NVTherm,
``P = x^E / (1 + x^E)``, ``x = N/N50``, ``E = s (2.7 + 0.7 x)``), never from the fit itself.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

import targetacq as ta
from targetacq.acquisition.calibration import fit_criterion
from targetacq.acquisition.criteria import (
    BUNDLED_CRITERIA,
    CRITERIA,
    register_criterion,
    unregister_criterion,
)
from targetacq.scenario.schema import ModelChoices

TTPF_E50 = 2.7 + 0.7  # the exponent at N = N50 of the registered TTPF


def ttpf_probability(cycles, n50, e50=TTPF_E50, e0=2.7, e1=0.7):
    """The TTPF written out, with its exponent law scaled to ``e50`` at N50."""
    x = np.asarray(cycles, dtype=float) / n50
    z = (e50 / (e0 + e1)) * (e0 + e1 * x) * np.log(x)
    return 1.0 / (1.0 + np.exp(-z))


def grid_log_likelihood(cycles, outcomes, n50, e50, e0=2.7, e1=0.7):
    """ℓ on a grid: n50 (G, 1, 1), e50 (1, K, 1) → (G, K)."""
    x = np.asarray(cycles, dtype=float) / n50
    z = (e50 / (e0 + e1)) * (e0 + e1 * x) * np.log(x)
    return np.sum(outcomes * z - np.logaddexp(0.0, z), axis=-1)


def trials(rng, cycles, n50, e50, repeat):
    n = np.repeat(np.asarray(cycles, dtype=float), repeat)
    return n, (rng.random(n.size) < ttpf_probability(n, n50, e50)).astype(float)


@pytest.fixture
def registered():
    """Names registered by a test, taken out again afterwards (the registry is global)."""
    names: list[str] = []
    yield names
    for name in names:
        if name in CRITERIA and name not in BUNDLED_CRITERIA:
            unregister_criterion(name)


# --- the maximum and the intervals against an independent computation ---------------------------


def test_the_fit_is_the_grid_maximum_and_its_intervals_the_grid_level_set():
    rng = np.random.default_rng(7)
    n, y = trials(rng, [1.5, 2.5, 3.5, 4.5, 5.5, 7.0], 4.0, 4.5, 20)
    fit = fit_criterion(n, y, "recognition", base=None)

    n50 = np.linspace(3.0, 5.5, 251)[:, None, None]
    e50 = np.linspace(1.5, 12.0, 351)[None, :, None]
    ll = grid_log_likelihood(n, y, n50, e50)
    i, j = np.unravel_index(np.argmax(ll), ll.shape)
    step_n, step_e = 2.5 / 250, 10.5 / 350
    assert fit.n50 == pytest.approx(n50[i, 0, 0], abs=step_n)
    assert fit.exponent == pytest.approx(e50[0, j, 0], abs=step_e)
    assert fit.log_likelihood >= ll.max() - 1e-9  # no grid point beats the fit
    assert fit.log_likelihood == pytest.approx(ll.max(), abs=1e-2)

    inside = ll >= ll.max() - 0.5 * stats.chi2.ppf(0.9, 1)
    n50_in = n50[:, 0, 0][inside.any(axis=1)]
    e50_in = e50[0, :, 0][inside.any(axis=0)]
    assert n50_in.min() > n50[0, 0, 0] and n50_in.max() < n50[-1, 0, 0]  # inside the grid
    assert e50_in.min() > e50[0, 0, 0] and e50_in.max() < e50[0, -1, 0]
    assert fit.n50_interval[0] == pytest.approx(n50_in.min(), abs=step_n)
    assert fit.n50_interval[1] == pytest.approx(n50_in.max(), abs=step_n)
    assert fit.exponent_interval[0] == pytest.approx(e50_in.min(), abs=step_e)
    assert fit.exponent_interval[1] == pytest.approx(e50_in.max(), abs=step_e)
    assert (fit.trials, fit.successes) == (n.size, int(y.sum()))


def test_n50_alone_is_the_one_dimensional_grid_maximum_with_the_exponent_fixed():
    rng = np.random.default_rng(11)
    n, y = trials(rng, [2.0, 3.0, 4.0, 5.0, 6.0], 3.5, TTPF_E50, 12)
    fit = fit_criterion(n, y, "recognition", fit_exponent=False)
    n50 = np.linspace(2.0, 6.0, 40001)[:, None]
    ll = grid_log_likelihood(n, y, n50, TTPF_E50)
    assert fit.n50 == pytest.approx(n50[np.argmax(ll), 0], abs=1e-4)
    inside = n50[ll >= ll.max() - 0.5 * stats.chi2.ppf(0.9, 1), 0]
    assert fit.n50_interval == pytest.approx((inside.min(), inside.max()), abs=1e-4)
    assert fit.exponent == pytest.approx(TTPF_E50)
    assert fit.exponent_interval == pytest.approx((TTPF_E50, TTPF_E50))
    assert not fit.exponent_fitted


def test_a_wider_confidence_gives_a_wider_interval_around_the_same_estimate():
    rng = np.random.default_rng(3)
    n, y = trials(rng, [2.0, 3.0, 4.0, 5.0, 6.0], 4.0, 3.4, 10)
    narrow = fit_criterion(n, y, "recognition", confidence=0.5)
    wide = fit_criterion(n, y, "recognition", confidence=0.99)
    assert narrow.n50 == pytest.approx(wide.n50, rel=1e-6)
    assert wide.n50_interval[0] < narrow.n50_interval[0] < narrow.n50
    assert narrow.n50 < narrow.n50_interval[1] < wide.n50_interval[1]
    assert wide.exponent_interval[0] < narrow.exponent_interval[0]
    assert narrow.exponent_interval[1] < wide.exponent_interval[1]


# --- recovery and coverage on synthetic trials -------------------------------------------------


def test_many_trials_recover_the_n50_and_exponent_they_were_drawn_with():
    rng = np.random.default_rng(2026)
    n, y = trials(rng, np.linspace(1.5, 9.0, 16), 4.0, 5.0, 250)  # 4000 trials
    fit = fit_criterion(n, y, "recognition")
    assert fit.n50 == pytest.approx(4.0, rel=0.03)
    assert fit.exponent == pytest.approx(5.0, rel=0.08)
    assert fit.n50_interval[0] < 4.0 < fit.n50_interval[1]
    assert fit.exponent_interval[0] < 5.0 < fit.exponent_interval[1]
    assert fit.n50_interval[1] - fit.n50_interval[0] < 0.2  # 4000 trials pin N50 down


def test_the_90_percent_intervals_cover_the_truth_in_85_to_95_percent_of_200_data_sets():
    # 200 synthetic data sets of 60 trials, drawn with N50 = 4 and E50 = 4 (not the TTPF's
    # 3.4, so the exponent is really fitted). A 90 % interval covers the truth in a fraction
    # p = 0.9 of data sets; over 200 sets the count of covers is Binomial(200, 0.9): sd
    # sqrt(0.9 * 0.1 / 200) = 2.1 %, so 85-95 % is 0.9 ± 2.4 sd (a correct method falls
    # outside with probability about 2 %; the seed is fixed, so the test is deterministic).
    # Profile-likelihood intervals are asymptotic; with 60 trials their coverage is close to
    # nominal. A method whose true coverage is 97 % or more (the chi-squared quantile of two
    # degrees of freedom instead of one: P(χ²₁ <= 4.61) = 0.968) or 83 % or less (intervals a
    # fifth too narrow) falls outside the band in most seeds.
    rng = np.random.default_rng(20261127)
    covered_n50 = covered_exponent = 0
    sets = 200
    for _ in range(sets):
        n, y = trials(rng, [2.0, 3.0, 4.0, 5.0, 6.0, 8.0], 4.0, 4.0, 10)
        fit = fit_criterion(n, y, "recognition", base=None)
        covered_n50 += fit.n50_interval[0] <= 4.0 <= fit.n50_interval[1]
        covered_exponent += fit.exponent_interval[0] <= 4.0 <= fit.exponent_interval[1]
    assert 0.85 <= covered_n50 / sets <= 0.95
    assert 0.85 <= covered_exponent / sets <= 0.95


def test_the_ttp_transform_fits_its_own_exponent_law():
    # The TTP metric's TTPF, E = s (1.51 + 0.24 x): drawn with V50 = 20 and E50 = 2.5.
    rng = np.random.default_rng(5)
    v = np.repeat(np.linspace(5.0, 60.0, 12), 300)
    p = ttpf_probability(v, 20.0, 2.5, e0=1.51, e1=0.24)
    y = (rng.random(v.size) < p).astype(float)
    fit = fit_criterion(v, y, "identification", transform="ttp", base=None)
    assert fit.n50 == pytest.approx(20.0, rel=0.05)
    assert fit.exponent == pytest.approx(2.5, rel=0.1)
    assert fit.exponent_scale == pytest.approx(fit.exponent / 1.75)
    fixed = fit_criterion(v, y, "identification", transform="ttp", fit_exponent=False, base=None)
    assert fixed.exponent == pytest.approx(1.51 + 0.24)


def test_a_table_transform_fits_its_n50_alone():
    # Trials drawn from the C2NVEO curve itself (Table 3.3) stretched to N50 = 5: its N50 comes
    # back, and a table has no exponent to fit.
    rng = np.random.default_rng(9)
    n = np.repeat(np.linspace(2.0, 12.0, 11), 300)
    y = (rng.random(n.size) < ta.c2nveo(n, 5.0, "recognition")).astype(float)
    fit = fit_criterion(n, y, "recognition", transform="c2nveo", base=None)
    assert fit.n50 == pytest.approx(5.0, rel=0.05)
    assert fit.n50_interval[0] < 5.0 < fit.n50_interval[1]
    assert math.isnan(fit.exponent) and not fit.exponent_fitted
    with pytest.raises(ValueError, match="no exponent to fit"):
        fit_criterion(n, y, "recognition", transform="c2nveo", fit_exponent=True)


def test_the_fitted_curve_is_one_half_at_n50_and_the_transform_when_the_exponent_is_its_own():
    rng = np.random.default_rng(1)
    n, y = trials(rng, [2.0, 3.0, 4.0, 5.0, 6.0], 4.0, 3.4, 10)
    fit = fit_criterion(n, y, "recognition")
    assert fit.probability(fit.n50) == pytest.approx(0.5)
    cycles = np.array([2.0, 4.0, 8.0])
    assert fit.probability(cycles) == pytest.approx(
        ttpf_probability(cycles, fit.n50, fit.exponent), rel=1e-9
    )
    fixed = fit_criterion(n, y, "recognition", fit_exponent=False)
    assert fixed.probability(cycles) == pytest.approx(ta.ttpf(cycles, fixed.n50), rel=1e-12)


# --- data that fix no N50, and bad input -------------------------------------------------------


@pytest.mark.parametrize("outcome", [0, 1])
def test_every_trial_with_one_outcome_is_refused(outcome):
    with pytest.raises(ValueError, match="fix no N50"):
        fit_criterion([2.0, 3.0, 4.0], [outcome] * 3, "recognition", fit_exponent=False)


def test_separated_outcomes_refuse_the_exponent_but_fit_n50_alone():
    cycles, seen = [1.0, 2.0, 3.0, 5.0, 6.0, 7.0], [0, 0, 0, 1, 1, 1]
    with pytest.raises(ValueError, match="separated by the cycles"):
        fit_criterion(cycles, seen, "recognition")
    fit = fit_criterion(cycles, seen, "recognition", fit_exponent=False)
    n50 = np.linspace(1.0, 10.0, 90001)
    ll = grid_log_likelihood(cycles, np.asarray(seen, float), n50[:, None], TTPF_E50)
    assert fit.n50 == pytest.approx(n50[np.argmax(ll)], abs=2e-4)


def test_trials_at_one_number_of_cycles_refuse_the_exponent():
    with pytest.raises(ValueError, match="same cycles"):
        fit_criterion([4.0] * 4, [0, 1, 1, 0], "recognition")


@pytest.mark.parametrize(
    ("cycles", "outcomes", "options", "message"),
    [
        ([1.0, 2.0], [0, 1, 1], {}, "one value per trial"),
        ([], [], {}, "no trials"),
        ([1.0, -2.0], [0, 1], {}, r"trial 2 \(counting from 1\) has -2.0"),
        ([1.0, math.nan], [0, 1], {}, "finite and > 0"),
        ([1.0, 2.0], [0, 2], {}, "0 .failure. or 1"),
        ([1.0, 2.0], ["no", "yes"], {}, "0 .failure. or 1"),
        ([1.0, 2.0], [0, 1], {"confidence": 1.0}, "confidence"),
        ([1.0, 2.0], [0, 1], {"transform": "ttpff"}, "unknown transform"),
        ([1.0, 2.0], [0, 1], {"task": "spotting"}, "task must be one of"),
        ([1.0, 2.0], [0, 1], {"base": "en62676-4"}, "pixel densities"),
    ],
)
def test_bad_input_is_refused_naming_it(cycles, outcomes, options, message):
    arguments = {"task": "recognition", "fit_exponent": False, **options}
    with pytest.raises(ValueError, match=message):
        fit_criterion(cycles, outcomes, **arguments)


def test_a_fitted_n50_out_of_order_with_the_base_is_refused():
    # Identification at 2 cycles, below Johnson's recognition N50 of 4.
    rng = np.random.default_rng(4)
    n, y = trials(rng, [1.0, 1.5, 2.0, 2.5, 3.0], 2.0, 3.4, 40)
    with pytest.raises(ValueError, match="harder task"):
        fit_criterion(n, y, "identification", fit_exponent=False)
    assert fit_criterion(n, y, "identification", fit_exponent=False, base=None).criterion.tasks == (
        "identification",
    )


# --- the fitted criterion in the registry ------------------------------------------------------


def test_a_named_fit_is_registered_and_used_by_name_everywhere(registered):
    rng = np.random.default_rng(12)
    n, y = trials(rng, [2.0, 3.0, 4.0, 5.0, 6.0], 3.0, 3.4, 20)
    with pytest.raises(ValueError, match="unknown criterion"):
        ModelChoices(criterion="calibration-test")
    registered.append("calibration-test")
    fit = fit_criterion(n, y, "recognition", fit_exponent=False, name="calibration-test")
    assert CRITERIA["calibration-test"] is fit.criterion
    assert ta.get_criterion("calibration-test").n50("recognition") == fit.n50
    assert ta.get_criterion("calibration-test").n50("identification") == 6.4  # Johnson's
    assert ModelChoices(criterion="calibration-test").criterion == "calibration-test"
    p = ta.probability(fit.n50, "recognition", criterion="calibration-test")
    assert p == pytest.approx(0.5)
    again = fit_criterion(
        n[:60], y[:60], "recognition", fit_exponent=False, name="calibration-test"
    )  # replaces
    assert CRITERIA["calibration-test"] is again.criterion


def test_the_registry_refuses_bundled_names_and_silent_replacement(registered):
    mine = ta.Criterion("calibration-mine", {"detection": 1.0})
    registered.append("calibration-mine")
    assert register_criterion(mine) is mine
    with pytest.raises(ValueError, match="registered already"):
        register_criterion(ta.Criterion("calibration-mine", {"detection": 2.0}))
    with pytest.raises(ValueError, match="bundled"):
        register_criterion(ta.Criterion("johnson", {"detection": 2.0}))
    with pytest.raises(ValueError, match="bundled"):
        unregister_criterion("johnson")
    with pytest.raises(ValueError, match="criterion name"):
        register_criterion(ta.Criterion("has space", {"detection": 2.0}))
    with pytest.raises(TypeError):
        register_criterion({"detection": 1.0})  # type: ignore[arg-type]
    unregister_criterion("calibration-mine")
    assert "calibration-mine" not in CRITERIA
    with pytest.raises(ValueError, match="no registered criterion"):
        unregister_criterion("calibration-mine")


def test_the_band_of_n50_alone_is_the_transform_at_the_interval_ends():
    # P falls as N50 grows, so with the exponent fixed the pointwise band is the TTPF at the
    # upper end of the N50 interval (low) and at its lower end (high).
    rng = np.random.default_rng(21)
    n, y = trials(rng, [2.0, 3.0, 4.0, 5.0, 6.0], 4.0, 3.4, 12)
    fit = fit_criterion(n, y, "recognition", fit_exponent=False)
    cycles = np.array([1.0, 3.0, 5.0, 9.0])
    low, high = fit.probability_interval(cycles, points=201)
    assert low == pytest.approx(ttpf_probability(cycles, fit.n50_interval[1]), rel=1e-6)
    assert high == pytest.approx(ttpf_probability(cycles, fit.n50_interval[0]), rel=1e-6)


def test_the_band_holds_the_fitted_curve_and_the_half_at_n50():
    rng = np.random.default_rng(22)
    n, y = trials(rng, [2.0, 3.0, 4.0, 5.0, 6.0], 4.0, 4.0, 12)
    fit = fit_criterion(n, y, "recognition")
    cycles = np.linspace(1.0, 10.0, 19)
    low, high = fit.probability_interval(cycles)
    curve = fit.probability(cycles)
    assert np.all(low <= curve + 1e-12) and np.all(curve <= high + 1e-12)
    assert np.all(high - low > 0.01)
    low50, high50 = fit.probability_interval([fit.n50])
    assert low50[0] < 0.5 < high50[0]


def test_ends_the_data_do_not_bound_are_zero_and_infinity_and_the_band_still_draws():
    # Four trials whose outcomes fall as the cycles grow: no N50 is ruled out at 90 %, and the
    # exponent may be as small as the search allows.
    fit = fit_criterion([3.0, 4.0, 5.0, 6.0], [1, 0, 1, 0], "recognition", base=None)
    assert fit.n50_interval == (0.0, math.inf)
    assert fit.exponent_interval[0] == 0.0
    low, high = fit.probability_interval(np.array([1.0, 4.0]))
    assert np.all((low >= 0.0) & (low <= high) & (high <= 1.0))


def test_a_name_with_the_exponent_fitted_is_refused_not_registered_without_it():
    # A criterion holds N50s only: registering a fit whose exponent is not the transform's would
    # give evaluations another curve than the one fitted.
    with pytest.raises(ValueError, match="name registers a criterion, which holds N50 only"):
        fit_criterion([2, 3, 4, 5, 6], [0, 0, 1, 0, 1], "recognition", name="never-registered")
    assert "never-registered" not in CRITERIA
