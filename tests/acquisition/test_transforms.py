"""Transforms: TTPF, C2NVEO (Table 3.3), Schmieder–Weathersby (Table 3.5), and inverses."""

import math

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

import targetacq as ta
from targetacq.acquisition.criteria import CRITERIA

C2NVEO_P = (1.00, 0.95, 0.80, 0.50, 0.30, 0.10, 0.02)
# Table 3.3, Sonesson (2004) p. 19: (low, high) cycles per row, per task.
C2NVEO_CELLS = {
    "detection": [
        (1.5, 3),
        (1, 2),
        (0.75, 1.5),
        (0.5, 1),
        (0.375, 0.75),
        (0.25, 0.5),
        (0.125, 0.25),
    ],
    "recognition": [(9, 12), (6, 12), (4.5, 6), (3, 4), (2.25, 3), (1.5, 2), (0.75, 1)],
    "identification": [(18, 24), (12, 16), (9, 12), (6, 8), (4.5, 6), (3, 4), (1.5, 2)],
}
SW_P = (1.00, 0.95, 0.90, 0.80, 0.50, 0.30, 0.10, 0.02)
# Table 3.5, Sonesson (2004) p. 22; None = "-" (never reached).
SW = {
    "low": (1.7, 1.0, 0.9, 0.75, 0.5, 0.3, 0.15, 0.05),
    "medium": (2.8, 1.9, 1.7, 1.3, 1.0, 0.75, 0.35, 0.1),
    "high": (None, None, 7.0, 5.0, 2.5, 2.0, 1.4, 1.0),
}
# The anchor of each region's curve when the SCR is given: the lower edge of its Table 3.5
# region (0.33 for high clutter, the lowest SCR of Table 3.4).
SCR_OF_REGION = {"low": 10.0, "medium": 1.0, "high": 0.33}


def _ttpf_by_hand(ratio):
    e = 2.7 + 0.7 * ratio
    return ratio**e / (1 + ratio**e)


@pytest.mark.parametrize(("ratio", "printed"), [(0.5, 0.1077), (1.0, 0.5), (2.0, 0.9449)])
def test_ttpf_values(ratio, printed):
    expected = _ttpf_by_hand(ratio)  # independent evaluation of the closed form
    assert expected == pytest.approx(printed, abs=5e-5)
    assert ta.ttpf(ratio * 4.0, 4.0) == pytest.approx(expected, rel=1e-13)


def test_ttpf_at_zero_and_infinity():
    np.testing.assert_array_equal(ta.ttpf(np.array([0.0, np.inf]), 1.0), [0.0, 1.0])


@pytest.mark.parametrize("bound", ["optimistic", "nominal", "pessimistic"])
@pytest.mark.parametrize("task", ["detection", "recognition", "identification"])
def test_c2nveo_reproduces_table_3_3(task, bound):
    n50 = CRITERIA["c2nveo"].n50(task)
    for p, (low, high) in zip(C2NVEO_P, C2NVEO_CELLS[task]):
        n = {"optimistic": low, "pessimistic": high, "nominal": math.sqrt(low * high)}[bound]
        if task == "recognition" and bound == "pessimistic" and p == 0.95:
            # "6-12" as printed: 12 cycles is also the 1.00 point, so the curve steps from 0.95
            # to 1 at 12; the smallest N reaching 0.95 is 12.
            assert ta.c2nveo_inverse(p, n50, task, bound) == pytest.approx(12.0)
            assert ta.c2nveo(11.999999, n50, task, bound) == pytest.approx(0.95, abs=1e-6)
            continue
        assert ta.c2nveo(n, n50, task, bound) == pytest.approx(p, abs=5e-3)  # printed 2 digits
        if p < 1:
            assert ta.c2nveo_inverse(p, n50, task, bound) == pytest.approx(n, rel=1e-12)


def test_c2nveo_ends_zero_at_zero_and_one_above_the_last_point():
    n50 = CRITERIA["c2nveo"].n50("detection")
    np.testing.assert_array_equal(
        ta.c2nveo(np.array([0.0, 3.0, 50.0]), n50, bound="pessimistic"), [0, 1, 1]
    )


def test_c2nveo_interpolates_in_log_n():
    n50 = CRITERIA["c2nveo"].n50("detection")
    # Geometric midpoint of 0.5 (P=0.5) and 0.75 (P=0.8) on the optimistic curve: P = 0.65.
    assert ta.c2nveo(math.sqrt(0.5 * 0.75), n50, bound="optimistic") == pytest.approx(0.65)


def test_c2nveo_scales_with_the_criterion():
    # With Johnson's N50 the nominal C2NVEO curve passes 0.5 at Johnson's N50.
    for task in ("detection", "recognition", "identification"):
        n50 = CRITERIA["johnson"].n50(task)
        assert ta.probability(n50, task, transform="c2nveo") == pytest.approx(0.5)


@pytest.mark.parametrize("region", ["low", "medium", "high"])
def test_schmieder_weathersby_reproduces_table_3_5(region):
    for p, n in zip(SW_P, SW[region]):
        if n is None:
            continue
        by_region = ta.schmieder_weathersby(n, region=region)
        by_scr = ta.schmieder_weathersby(n, scr=SCR_OF_REGION[region])
        assert by_region == pytest.approx(p, abs=5e-3)
        assert by_scr == by_region
        if p < 1:
            assert ta.schmieder_weathersby_inverse(p, region=region) == pytest.approx(n, rel=1e-12)


def test_high_clutter_never_reaches_0_95():
    assert ta.schmieder_weathersby(1e6, region="high") == pytest.approx(0.9)
    assert ta.schmieder_weathersby_inverse(0.95, region="high") == math.inf


def test_scr_blends_the_regions_in_log_scr():
    # Anchors: low from SCR 10 up, medium at 1, high at 0.33 and below (the stretch aside);
    # between them linear in log SCR.
    n = 1.0
    low, medium, high = (ta.schmieder_weathersby(n, region=r) for r in ("low", "medium", "high"))
    got = ta.schmieder_weathersby(n, scr=np.array([10.0, 1e3, np.inf, 1.0, 0.33, math.sqrt(10)]))
    np.testing.assert_allclose(got[:5], [low, low, low, medium, high], rtol=1e-14)
    assert got[5] == pytest.approx((low + medium) / 2, rel=1e-14)
    w = math.log(0.5 / 0.33) / math.log(1 / 0.33)  # SCR 0.5 between the high and medium anchors
    assert ta.schmieder_weathersby(n, scr=0.5) == pytest.approx(high + w * (medium - high))
    assert list(ta.clutter_region([11, 10, 1, 0.5])) == ["low", "medium", "medium", "high"]


def test_scr_blend_is_continuous_across_the_region_boundaries():
    n = np.geomspace(0.05, 20.0, 200)[:, None]
    for edge in (10.0, 1.0, 0.33):
        below, above = (ta.schmieder_weathersby(n, scr=edge * f) for f in (1 - 1e-9, 1 + 1e-9))
        assert np.max(np.abs(above - below)) < 1e-8


def test_scr_blend_follows_table_3_4_closer_than_the_bins():
    # Table 3.4, SCR 5.8 (a medium-clutter SCR): P observed 0.38 at N = 0.5 and 0.87 at N = 1.
    observed = np.array([0.38, 0.87])
    blend = ta.schmieder_weathersby(np.array([0.5, 1.0]), scr=5.8)
    binned = ta.schmieder_weathersby(np.array([0.5, 1.0]), region="medium")
    assert np.max(np.abs(blend - observed)) < np.max(np.abs(binned - observed))


@given(st.floats(1e-3, 1e3), st.floats(0.01, 0.99))
def test_scr_inverse_is_the_smallest_n_reaching_p(scr, p):
    n = ta.schmieder_weathersby_inverse(p, scr=scr)
    if math.isinf(n):
        assert ta.schmieder_weathersby(1e9, scr=scr) < p
        return
    assert ta.schmieder_weathersby(n, scr=scr) == pytest.approx(p, abs=1e-9)
    assert ta.schmieder_weathersby(n * (1 - 1e-6), scr=scr) < p + 1e-12


def test_hot_spot_uses_low_clutter_and_moving_is_always_detected():
    assert ta.schmieder_weathersby(0.5, hot_spot=True) == pytest.approx(0.5)  # §3.9: 0.5 LP/TGT
    np.testing.assert_array_equal(
        ta.schmieder_weathersby(np.array([0.0, 3.0]), moving=True), [1, 1]
    )
    assert ta.schmieder_weathersby_inverse(0.99, moving=True) == 0.0


def test_schmieder_weathersby_needs_the_clutter():
    with pytest.raises(ValueError, match="needs the clutter"):
        ta.schmieder_weathersby(1.0)
    with pytest.raises(ValueError, match="has no curve for task 'recognition'"):
        ta.probability(
            4.0, "recognition", transform="schmieder-weathersby", clutter=ta.Clutter(scr=3.0)
        )


# --- properties ----------------------------------------------------------------------------

cycles = st.floats(0.0, 100.0)
transforms = st.sampled_from(
    [
        ("ttpf", {}),
        ("c2nveo", {"bound": "optimistic"}),
        ("c2nveo", {"bound": "nominal"}),
        ("c2nveo", {"bound": "pessimistic"}),
    ]
)


@given(
    st.lists(cycles, min_size=2, max_size=20),
    transforms,
    st.sampled_from(["detection", "recognition", "identification"]),
)
def test_probabilities_in_unit_interval_and_non_decreasing_in_n(ns, method, task):
    name, options = method
    n = np.sort(np.array(ns))
    p = ta.probability(n, task, transform=name, **options)
    assert np.all((p >= 0) & (p <= 1))
    assert np.all(np.diff(p) >= 0)


@given(st.lists(cycles, min_size=2, max_size=20), st.floats(0, 100))
def test_schmieder_weathersby_non_decreasing_in_n_and_in_scr(ns, scr):
    n = np.sort(np.array(ns))
    p = ta.schmieder_weathersby(n, scr=scr)
    assert np.all((p >= 0) & (p <= 1)) and np.all(np.diff(p) >= 0)
    regions_in_scr_order = [ta.schmieder_weathersby(n, scr=s) for s in (0.5, 5.0, 50.0)]
    assert np.all(regions_in_scr_order[0] <= regions_in_scr_order[1])
    assert np.all(regions_in_scr_order[1] <= regions_in_scr_order[2])


@given(st.floats(0.01, 10.0), st.floats(0.1, 20.0))
def test_ttpf_inverse_of_forward_is_identity(ratio, n50):
    p = ta.ttpf(ratio * n50, n50)
    # Where P is well conditioned in float64: as P -> 1, the rounding of P itself (1e-16) moves
    # the logit by 1e-16 / (1 - P), so N is only recoverable to that relative precision.
    assume(1e-12 < p < 1 - 1e-6)
    assert ta.ttpf_inverse(p, n50) == pytest.approx(ratio * n50, rel=1e-9)


@given(
    st.floats(0.01, 30.0),
    transforms,
    st.sampled_from(["detection", "recognition", "identification"]),
)
def test_inverse_of_forward_is_identity_where_the_curve_rises(n, method, task):
    name, options = method
    n50 = CRITERIA["johnson"].n50(task)
    p = ta.transform(n, n50, task, method=name, **options)
    assume(0 < p < 1 - 1e-6)  # see test_ttpf_inverse_of_forward_is_identity
    if name == "c2nveo" and task == "recognition" and options["bound"] == "pessimistic":
        assume(p < 0.95 or n > 12)  # the vertical step of the printed "6-12" cell
    assert ta.inverse_transform(p, n50, task, method=name, **options) == pytest.approx(n, rel=1e-9)


@given(st.floats(0.001, 0.999), st.floats(0.1, 20.0))
def test_forward_of_inverse_is_identity(p, n50):
    assert ta.ttpf(ta.ttpf_inverse(p, n50), n50) == pytest.approx(p, abs=1e-12)
    n = ta.c2nveo_inverse(p, n50, "identification", "nominal")
    assert ta.c2nveo(n, n50, "identification", "nominal") == pytest.approx(p, abs=1e-12)


# --- dispatcher and bad input ----------------------------------------------------------------


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (
            lambda: ta.probability(1.0, "detection", transform="johnsn"),
            r"unknown transform 'johnsn'; valid: ttpf, ttp, c2nveo, schmieder-weathersby",
        ),
        (
            lambda: ta.probability(1.0, "detection", transform="ttpf", bound="optimistic"),
            "takes no option",
        ),
        (
            lambda: ta.probability(1.0, "detection", transform="c2nveo", bound="best"),
            "bound must be one of",
        ),
        (
            lambda: ta.probability(1.0, "orientation", transform="c2nveo"),
            "no curve for task 'orientation'",
        ),
        (lambda: ta.probability(1.0, "detect"), "has no task 'detect'"),
        (lambda: ta.ttpf(-1.0, 1.0), "cycles must be >= 0"),
        (lambda: ta.ttpf(math.nan, 1.0), "cycles must be >= 0, got NaN"),
        (lambda: ta.ttpf(1.0, 0.0), "n50 must be > 0"),
        (lambda: ta.ttpf_inverse(1.0, 1.0), r"probability must be in the open interval \(0, 1\)"),
        (lambda: ta.ttpf_inverse(0.0, 1.0), r"open interval \(0, 1\)"),
        (lambda: ta.schmieder_weathersby(1.0, scr=-1.0), "scr must be >= 0"),
        (lambda: ta.schmieder_weathersby(1.0, region="heavy"), "region must be one of"),
        (lambda: ta.schmieder_weathersby(1.0, scr=2.0, region="low"), "not both"),
    ],
)
def test_bad_input_raises_value_error_naming_it(call, match):
    with pytest.raises(ValueError, match=match):
        call()


@pytest.mark.parametrize(
    ("name", "options"),
    [("ttpf", {}), ("c2nveo", {}), ("schmieder-weathersby", {"scr": 3.0})],
)
def test_nan_in_an_array_propagates(name, options):
    p = ta.transform(np.array([1.0, np.nan, 2.0]), 1.0, "detection", method=name, **options)
    assert np.isnan(p[1]) and not np.isnan(p[0]) and not np.isnan(p[2])
    n = ta.inverse_transform(np.array([0.5, np.nan]), 1.0, "detection", method=name, **options)
    assert np.isnan(n[1]) and not np.isnan(n[0])


def test_scalar_in_scalar_out_and_broadcasting():
    assert np.ndim(ta.ttpf(1.0, 1.0)) == 0
    p = ta.ttpf(np.ones((3, 1)), np.array([1.0, 2.0]))
    assert p.shape == (3, 2)
