"""Per-task probabilities for one sensor: ordering, clutter, P_effect (2.5)."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import targetacq as ta


def test_probability_is_the_criterion_n50_through_the_transform():
    # Johnson recognition N50 = 4 (Table 3.2): TTPF gives 0.5 at 4 cycles, 0.9449 at 8.
    np.testing.assert_allclose(
        ta.probability([4.0, 8.0], "recognition"), [0.5, 0.944899], atol=1e-6
    )


def test_effect_is_the_product_eq_2_5():
    assert ta.effect_probability(0.9, 0.5, 0.2) == pytest.approx(0.09)


@given(st.lists(st.floats(0, 50), min_size=1, max_size=30), st.floats(0, 50))
def test_ordering_and_effect(ns, scr):
    n = np.array(ns)
    for kwargs in ({}, {"scr": scr}, {"hot_spot": True}, {"moving": True}):
        acq = ta.acquisition_probabilities(n, clutter=kwargs)
        assert np.all(acq.identification <= acq.recognition)
        assert np.all(acq.recognition <= acq.detection)
        # Nested: identified implies recognised and detected, so P_effect = P(identified).
        np.testing.assert_array_equal(acq.effect, acq.identification)
        # Conditional: Eq. (2.5), the product of the three curves.
        cond = ta.acquisition_probabilities(n, semantics="conditional", clutter=kwargs)
        rec, ide = (ta.probability(n, task) for task in ("recognition", "identification"))
        np.testing.assert_allclose(cond.detection, acq.detection, rtol=1e-15)
        np.testing.assert_allclose(cond.recognition, acq.detection * rec, rtol=1e-12)
        np.testing.assert_allclose(cond.effect, acq.detection * rec * ide, rtol=1e-12)


def test_heavy_clutter_caps_recognition_at_detection():
    # §3.7: high clutter holds detection at 0.9 (Table 3.5) while recognition by TTPF (N50 = 4)
    # is 0.96 at 9 cycles; nothing is recognised that was not detected.
    acq = ta.acquisition_probabilities(9.0, clutter=ta.Clutter(scr=0.33))
    marginal_rec = ta.probability(9.0, "recognition")
    detection = ta.schmieder_weathersby(9.0, scr=0.33)
    assert marginal_rec > detection
    assert acq.detection == pytest.approx(detection)
    assert acq.recognition == pytest.approx(detection)


def test_without_clutter_all_tasks_use_the_transform():
    n = np.array([0.0, 0.7, 3.0, 9.0])
    acq = ta.acquisition_probabilities(
        n, criterion="johnson", transform="c2nveo", bound="optimistic"
    )
    for task in ("detection", "recognition", "identification"):
        expected = ta.probability(n, task, transform="c2nveo", bound="optimistic")
        np.testing.assert_allclose(getattr(acq, task), expected)


def test_fast_numpy_path_equals_the_generic_transform():
    rng = np.random.default_rng(1)
    n = np.concatenate([[0.0, np.inf, np.nan], rng.uniform(0, 30, 50_000)])
    acq = ta.acquisition_probabilities(n)
    for task in ("detection", "recognition", "identification"):
        np.testing.assert_allclose(getattr(acq, task), ta.probability(n, task), rtol=1e-13, atol=0)


def test_bad_acquisition_requests():
    with pytest.raises(ValueError, match="covers detection only"):
        ta.acquisition_probabilities(1.0, transform="schmieder-weathersby")
    with pytest.raises(ValueError, match="takes no option"):
        ta.acquisition_probabilities(1.0, boundd="nominal")
    with pytest.raises(ValueError, match="pixel-density"):
        ta.acquisition_probabilities(1.0, criterion="en62676-4")
    with pytest.raises(ValueError, match="cycles must be >= 0"):
        ta.acquisition_probabilities(np.array([1.0, -1.0]))


def test_an_old_clutter_keyword_points_to_the_clutter_record():
    # scr=, region=, hot_spot=, moving= became clutter=Clutter(...): the error says so.
    from targetacq.acquisition.probabilities import probability

    with pytest.raises(ValueError, match=r"scr: give clutter=Clutter\(\.\.\.\) instead"):
        probability(5.0, "detection", scr=2.0)
