"""Monotone fit through the observations of Table 3.4 in Sonesson (2004)."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from targetacq.acquisition import observed_detection as od
from targetacq.acquisition.observed_detection import observed_detection, observed_detection_inverse

CYCLES = (0.25, 0.5, 1.0, 2.0, 3.0, 4.0, 6.0)
# Table 3.4 in Sonesson (2004), p. 22 (Schmieder & Weathersby 1983): observed P(detection) by
# SCR (rows) and cycles (columns, CYCLES); None = printed "-" (not observed).
TABLE_3_4 = {
    0.33: (None, 0.00, 0.00, 0.32, 0.67, 0.77, 0.84),
    1.2: (None, 0.04, 0.46, 0.96, 0.98, 1.0, 1.0),
    5.8: (None, 0.38, 0.87, 0.95, 1.0, 1.0, 1.0),
    39.0: (0.93, 0.96, 1.0, 1.0, None, None, None),
}
# The one printed cell out of order across SCR (0.95 at SCR 5.8 < 0.96 at SCR 1.2, N = 2): the
# fit raises it to the SCR 1.2 value (module doc, assumption 3).
RAISED = {(5.8, 2.0): TABLE_3_4[1.2][3]}

OBSERVED = [
    (scr, n, p)
    for scr, row in TABLE_3_4.items()
    for n, p in zip(CYCLES, row)
    if p is not None and (scr, n) not in RAISED
]

cycles_st = st.floats(0.0, 30.0)
scr_st = st.floats(0.0, 200.0)


@pytest.mark.parametrize(("scr", "n", "printed"), OBSERVED)
def test_reproduces_every_unchanged_observed_cell(scr, n, printed):
    assert observed_detection(n, scr=scr) == pytest.approx(printed, abs=1e-12)


def test_the_out_of_order_cell_is_raised_and_listed():
    assert observed_detection(2.0, scr=5.8) == pytest.approx(0.96, abs=1e-12)
    assert dict(od.adjusted_cells()) == {(5.8, 2.0): (0.95, 0.96)}


def test_reported_values():
    np.testing.assert_allclose(observed_detection([0.25, 0.5], scr=39.0), [0.93, 0.96], atol=1e-12)
    assert observed_detection(6.0, scr=0.33) == pytest.approx(0.84, abs=1e-12)


def test_interpolation_rules_by_hand():
    # Linear in N from P = 0 at N = 0 to the first observed point (0.38 at 0.5 cycles, SCR 5.8).
    assert observed_detection(0.25, scr=5.8) == pytest.approx(0.38 / 2, abs=1e-12)
    # Linear in log N: at the geometric mean of 1 and 2 cycles, the mean of 0.46 and 0.96.
    assert observed_detection(math.sqrt(2.0), scr=1.2) == pytest.approx(0.71, abs=1e-12)
    # Held beyond the last observed point; "-" is not an observation.
    assert observed_detection(5.0, scr=39.0) == pytest.approx(1.0, abs=1e-12)
    assert observed_detection(100.0, scr=0.33) == pytest.approx(0.84, abs=1e-12)
    # SCR 0.33 is 0 at 0.5 and 1 cycle, so 0 up to 1 cycle.
    assert observed_detection(0.9, scr=0.33) == 0.0
    # Linear in log SCR: halfway between SCR 1.2 and 5.8 at N = 1, the mean of 0.46 and 0.87.
    assert observed_detection(1.0, scr=math.sqrt(1.2 * 5.8)) == pytest.approx(0.665, abs=1e-12)


def test_scr_is_clamped_to_the_observed_rows():
    n = np.array([0.3, 1.0, 2.5, 6.0, 50.0])
    low, high = observed_detection(n, scr=0.33), observed_detection(n, scr=39.0)
    for scr in (0.0, 0.1, 0.3):
        np.testing.assert_array_equal(observed_detection(n, scr=scr), low)
    for scr in (40.0, 1e6, math.inf):
        np.testing.assert_array_equal(observed_detection(n, scr=scr), high)


# Monotone up to rounding: interpolating between two rows in log SCR can differ by an ulp.
@given(cycles_st, cycles_st, scr_st)
def test_monotone_in_cycles(a, b, scr):
    lo, hi = sorted((a, b))
    assert observed_detection(lo, scr=scr) <= observed_detection(hi, scr=scr) + 1e-12


@given(cycles_st, scr_st, scr_st)
def test_monotone_in_scr(n, a, b):
    lo, hi = sorted((a, b))
    assert observed_detection(n, scr=lo) <= observed_detection(n, scr=hi) + 1e-12


@given(st.floats(1e-6, 30.0), scr_st)
def test_continuous_and_in_unit_interval(n, scr):
    p, q = observed_detection(np.array([n, n * 1.001]), scr=scr)
    assert 0.0 <= p <= 1.0 and 0.0 <= q <= 1.0
    assert abs(q - p) <= 0.01


def test_zero_cycles_give_zero():
    scr = np.array([0.0, 0.33, 0.5, 1.2, 3.0, 5.8, 20.0, 39.0, 1e3])
    np.testing.assert_array_equal(observed_detection(0.0, scr=scr), np.zeros(scr.shape))


def test_dense_grid_is_monotone_and_continuous():
    n = np.geomspace(1e-3, 20.0, 4001)[:, None]
    scr = np.geomspace(0.2, 60.0, 301)[None, :]
    p = observed_detection(n, scr=scr)
    assert p.shape == (4001, 301)
    assert np.all((p >= 0) & (p <= 1))
    assert np.all(np.diff(p, axis=0) >= -1e-12)
    assert np.all(np.diff(p, axis=1) >= -1e-12)
    assert np.max(np.abs(np.diff(p, axis=0))) < 0.01


def test_inverse_of_forward_round_trip():
    p = np.linspace(0.005, 0.995, 199)[:, None]
    scr = np.array([0.0, 0.33, 0.6, 1.2, 2.0, 5.8, 12.0, 39.0, 100.0])[None, :]
    n = observed_detection_inverse(p, scr=scr)
    top = observed_detection(1e3, scr=scr)
    reached = np.broadcast_to(p <= top, n.shape)
    assert np.all(np.isinf(n[~reached])) and np.all(np.isfinite(n[reached]))
    back = observed_detection(np.where(reached, n, 0.0), scr=scr)
    np.testing.assert_allclose(back[reached], np.broadcast_to(p, n.shape)[reached], atol=1e-9)
    # The smallest such N: a little less falls short.
    below = observed_detection(np.where(reached, n, 0.0) * (1 - 1e-6), scr=scr)
    assert np.all(below[reached] < np.broadcast_to(p, n.shape)[reached])


def test_forward_of_inverse_round_trip_where_strictly_increasing():
    n = np.array([0.01, 0.1, 0.25, 0.4, 0.5, 0.7, 1.0, 1.5])
    for scr in (1.2, 3.0, 5.8):
        back = observed_detection_inverse(observed_detection(n, scr=scr), scr=scr)
        np.testing.assert_allclose(back, n, rtol=1e-9)


def test_inverse_never_reached_and_top():
    # High clutter tops out at 0.84 (Table 3.4, SCR 0.33, 6 cycles).
    assert observed_detection_inverse(0.85, scr=0.33) == math.inf
    assert observed_detection_inverse(0.84, scr=0.33) == pytest.approx(6.0, rel=1e-9)
    assert observed_detection_inverse(0.85, scr=0.01) == math.inf
    assert observed_detection_inverse(0.93, scr=39.0) == pytest.approx(0.25, rel=1e-9)


def test_criterion_scaling():
    n = np.array([0.1, 0.5, 1.3, 2.0, 4.5])
    for n50 in (0.5, 1.0, 2.0, 3.7):
        np.testing.assert_allclose(
            observed_detection(n, n50, scr=5.8), observed_detection(n / n50, scr=5.8), atol=1e-15
        )
        np.testing.assert_allclose(
            observed_detection_inverse(0.6, n50, scr=1.2),
            n50 * observed_detection_inverse(0.6, scr=1.2),
            rtol=1e-14,
        )
    # Johnson's detection N50 (1.0) is the table's own reference: the printed values.
    assert observed_detection(0.5, 1.0, scr=5.8) == pytest.approx(0.38, abs=1e-12)


def test_nan_in_nan_out():
    p = observed_detection(np.array([1.0, np.nan, 2.0]), scr=1.2)
    assert np.isnan(p[1]) and not np.isnan(p[0]) and not np.isnan(p[2])
    p = observed_detection(1.0, scr=np.array([np.nan, 1.2]))
    assert np.isnan(p[0]) and p[1] == pytest.approx(0.46, abs=1e-12)
    n = observed_detection_inverse(np.array([0.5, np.nan]), scr=1.2)
    assert np.isnan(n[1]) and not np.isnan(n[0])
    n = observed_detection_inverse(0.5, scr=np.array([1.2, np.nan]))
    assert np.isnan(n[1]) and not np.isnan(n[0])


def test_broadcasting_n_dimensional():
    n = np.array([0.3, 1.0, 2.5]).reshape(3, 1, 1)
    scr = np.array([0.5, 5.8]).reshape(1, 2, 1)
    n50 = np.array([1.0, 2.0, 0.7, 1.5]).reshape(1, 1, 4)
    p = observed_detection(n, n50, scr=scr)
    assert p.shape == (3, 2, 4)
    for i, j, k in np.ndindex(p.shape):
        assert p[i, j, k] == observed_detection(n.flat[i], n50.flat[k], scr=scr.flat[j])
    q = np.array([0.2, 0.5, 0.9]).reshape(3, 1, 1)
    needed = observed_detection_inverse(q, n50, scr=scr)
    assert needed.shape == (3, 2, 4)
    for i, j, k in np.ndindex(needed.shape):
        one = observed_detection_inverse(q.flat[i], n50.flat[k], scr=scr.flat[j])
        assert needed[i, j, k] == pytest.approx(one, rel=1e-12)


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: observed_detection(-1.0, scr=1.0), "cycles"),
        (lambda: observed_detection(np.array([1.0, -0.5]), scr=1.0), "cycles"),
        (lambda: observed_detection(1.0, scr=-2.0), "scr"),
        (lambda: observed_detection(1.0, 0.0, scr=1.0), "n50"),
        (lambda: observed_detection(1.0, scr=None), "scr"),
        (lambda: observed_detection_inverse(-0.1, scr=1.0), "probability"),
        (lambda: observed_detection_inverse(1.5, scr=1.0), "probability"),
        (lambda: observed_detection_inverse(0.5, scr=np.array([1.0, -1.0])), "scr"),
        (lambda: observed_detection_inverse(0.5, -1.0, scr=1.0), "n50"),
    ],
)
def test_bad_input_raises_naming_it(call, name):
    with pytest.raises(ValueError, match=name):
        call()


def test_registry_adapters():
    n = np.array([0.25, 1.0, 3.0])
    np.testing.assert_array_equal(
        od.forward(n, 2.0, "detection", scr=5.8), observed_detection(n, 2.0, scr=5.8)
    )
    np.testing.assert_array_equal(
        od.inverse(0.7, 2.0, "detection", scr=5.8), observed_detection_inverse(0.7, 2.0, scr=5.8)
    )
    with pytest.raises(ValueError, match=r"scr.*signal-to-clutter ratio"):
        od.forward(1.0, 1.0, "detection")
    with pytest.raises(ValueError, match=r"scr.*signal-to-clutter ratio"):
        od.inverse(0.5, 1.0, "detection", scr=None)
    with pytest.raises(ValueError, match="task 'recognition'"):
        od.forward(1.0, 1.0, "recognition", scr=1.0)
    with pytest.raises(ValueError, match="region"):
        od.forward(1.0, 1.0, "detection", scr=1.0, region="low")


def test_array_api_strict_agrees_with_numpy():
    xps = pytest.importorskip("array_api_strict")
    n = [0.0, 0.2, 0.7, 2.0, 2.1, 8.0, float("nan")]
    strict = observed_detection(xps.asarray(n, dtype=xps.float64), scr=5.8)
    assert type(strict).__module__.startswith("array_api_strict")
    np.testing.assert_allclose(
        np.asarray(strict), observed_detection(np.array(n), scr=5.8), rtol=1e-14, equal_nan=True
    )
    p = [0.1, 0.5, 0.9, float("nan")]
    strict = observed_detection_inverse(xps.asarray(p, dtype=xps.float64), scr=0.8)
    np.testing.assert_allclose(
        np.asarray(strict),
        observed_detection_inverse(np.array(p), scr=0.8),
        rtol=1e-14,
        equal_nan=True,
    )
