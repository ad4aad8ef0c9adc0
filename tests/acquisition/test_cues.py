"""Graded hot-spot and motion cues: the switches are their limits, and they are smooth
(issue 25: P moves by less than 0.05 per 1 % change of their inputs)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from targetacq.acquisition.cues import (
    HOT_SPOT_RATIO_50,
    MOTION_RATE_50,
    cue_weight,
    hot_spot_weight,
    motion_weight,
)
from targetacq.acquisition.probabilities import Clutter, acquisition_probabilities, probability
from targetacq.core.cases import RangeCase, case_acquisition
from targetacq.core.ranges import case_ranges
from targetacq.run.range_options import range_setup

IFOV = 17e-6 / 75e-3
RANGES = np.geomspace(100.0, 30e3, 400)


def _det(**kw):
    case = RangeCase(2.3, IFOV, scr=1.2, extinction=0.2e-3, **kw)
    return np.asarray(case_acquisition(case, RANGES).detection)


def test_logistic_weight_points_from_its_definition():
    # 0.05 a factor √10 below the 50 % point, 0.95 a factor √10 above it (one decade).
    x50 = 2.0
    got = cue_weight(np.array([x50 / math.sqrt(10), x50, x50 * math.sqrt(10)]), x50)
    assert np.allclose(got, [0.05, 0.5, 0.95], rtol=0, atol=1e-12)
    assert float(cue_weight(0.0, 1.0)) == 0.0
    assert float(cue_weight(math.inf, 1.0)) == 1.0
    # Table 3.5's medium region: SCR 1 → 0.05, SCR 10 → 0.95.
    assert np.allclose(hot_spot_weight(np.array([1.0, 10.0])), [0.05, 0.95], atol=1e-12)
    assert float(motion_weight(MOTION_RATE_50)) == pytest.approx(0.5)


def test_sub_pixel_hot_spot_is_diluted_by_its_fill():
    assert float(hot_spot_weight(10.0, 0.25)) == pytest.approx(float(hot_spot_weight(2.5)))
    assert float(hot_spot_weight(10.0, 4.0)) == float(hot_spot_weight(10.0))


def test_switches_are_the_limits_of_the_graded_cues_to_the_bit():
    plain = _det()
    assert np.array_equal(_det(hot_spot_ratio=0.0), plain)
    assert np.array_equal(_det(target_speed=0.0), plain)
    assert np.array_equal(_det(hot_spot_ratio=1e300), _det(hot_spot=True))
    assert np.array_equal(_det(target_speed=1e300), _det(moving=True))
    both = _det(hot_spot=True, moving=True)
    assert np.array_equal(_det(hot_spot_ratio=1e300, target_speed=1e300), both)


def test_motion_weight_follows_the_pixels_per_second_at_each_range():
    v = 5.0
    cued = _det(target_speed=v)
    base, full = _det(), _det(moving=True)
    w = 1.0 / (1.0 + (v / (RANGES * IFOV) / MOTION_RATE_50) ** -(math.log(19) / math.log(10**0.5)))
    assert np.allclose(cued, (1 - w) * base + w * np.maximum(full, base), rtol=0, atol=1e-12)


def test_hot_spot_weight_follows_its_pixels_at_each_range():
    size, ratio = 0.2, 30.0
    cued = _det(hot_spot_ratio=ratio, hot_spot_size=size)
    base, full = _det(), _det(hot_spot=True)
    elements = (size / (RANGES * IFOV)) ** 2
    w = hot_spot_weight(ratio * np.minimum(elements, 1.0))
    assert np.allclose(cued, (1 - w) * base + w * full, rtol=0, atol=1e-12)


@pytest.mark.parametrize("name", ["hot_spot_ratio", "hot_spot_size", "target_speed"])
def test_p_moves_less_than_005_per_percent_of_the_cue_inputs(name):
    values = np.geomspace(1e-3, 1e3, 121)
    worst = 0.0
    for x in values:
        kw = {"hot_spot_ratio": 30.0} if name == "hot_spot_size" else {}
        low = _det(**{**kw, name: x})
        high = _det(**{**kw, name: x * 1.01})
        worst = max(worst, float(np.max(np.abs(high - low))))
    assert worst < 0.05
    assert worst < 0.01  # the bound of the module: k/4 · ln 1.01 ≈ 0.0064


def test_cues_only_help_and_grow_with_their_inputs():
    base = _det()
    previous = base
    for ratio in (0.5, 2.0, 5.0, 20.0):
        now = _det(hot_spot_ratio=ratio)
        assert np.all(now >= previous - 1e-15)
        previous = now
    previous = base
    for v in (0.1, 1.0, 10.0):
        now = _det(target_speed=v)
        assert np.all(now >= previous - 1e-15)
        previous = now


def test_graded_detection_range_solves_the_curve():
    case = RangeCase(2.3, IFOV, scr=1.2, extinction=0.2e-3, target_speed=2.0)
    r = float(case_ranges(case, 0.5)["detection"])
    assert float(case_acquisition(case, r).detection) == pytest.approx(0.5, abs=1e-6)
    plain = float(case_ranges(RangeCase(2.3, IFOV, scr=1.2, extinction=0.2e-3), 0.5)["detection"])
    full = RangeCase(2.3, IFOV, scr=1.2, extinction=0.2e-3, moving=True)
    assert plain < r < float(case_ranges(full, 0.5)["detection"])


def test_probability_api_takes_the_graded_clutter():
    n = np.array([0.3, 1.0, 3.0])
    flag = probability(n, "detection", clutter=Clutter(scr=1.2, hot_spot=True))
    graded = probability(n, "detection", clutter=Clutter(scr=1.2, hot_spot_ratio=1e300))
    assert np.array_equal(flag, graded)
    acq = acquisition_probabilities(n, clutter=Clutter(scr=1.2, speed=10.0))
    assert np.all(acq.detection >= acquisition_probabilities(n, clutter=Clutter(scr=1.2)).detection)


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"hot_spot_ratio": -1.0}, "hot_spot_ratio"),
        ({"target_speed": -1.0}, "target_speed"),
        ({"hot_spot_size": 0.3}, "hot_spot_ratio"),
    ],
)
def test_bad_cue_inputs_are_refused(kw, match):
    with pytest.raises(ValueError, match=match):
        RangeCase(2.3, IFOV, **kw)


def test_cli_options_reach_the_case():
    base = {"pitch": "17um", "focal_length": "75mm", "critical_dimension": "2.3m"}
    setup = range_setup(
        {**base, "hot_spot_ratio": 10.0, "hot_spot_size": "0.3m", "target_speed": "36km/h"}
    )
    assert setup.case.hot_spot_ratio == 10.0
    assert setup.case.hot_spot_size == pytest.approx(0.3)
    assert setup.case.target_speed == pytest.approx(10.0)
    with pytest.raises(ValueError, match="--hot-spot-ratio"):
        range_setup({**base, "hot_spot_size": "0.3m"})
    assert pytest.approx(10**0.5) == HOT_SPOT_RATIO_50
