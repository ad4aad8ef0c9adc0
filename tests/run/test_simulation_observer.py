"""The step API's per-run observer (``Simulation(..., observer_spread=...)``): one lognormal
N50 factor per run, reproducible from the seed and the run."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from targetacq import Simulation
from targetacq.run.uncertainty import lognormal_factors, observer_factor
from targetacq.scenario.schema import Background, Sensor, Target

SENSOR = Sensor(name="ir", band="lwir", ifov=0.25e-3, position=(0.0, 0.0, 5.0))
TRUCK = Target(name="truck", dimensions=(7.0, 2.5, 3.0), temperature=305.0, position=(0, 0, 0))
AT = (np.array([[0.0, 0.0, 5.0]]), np.array([[3000.0, 0.0, 0.0]]))


def _sim(**kwargs):
    return Simulation([SENSOR], [TRUCK], background=Background(temperature=295.0), **kwargs)


def test_no_spread_is_the_criterions_observer():
    sim = _sim(seed=4)
    assert sim.observer == 1.0
    sim.reset(run=9)
    assert sim.observer == 1.0


def test_a_runs_observer_is_a_criterion_with_its_n50s_scaled():
    sim = _sim(seed=4, observer_spread=0.3)
    for run in (0, 1, 2):
        sim.reset(run=run)
        f = sim.observer
        assert (
            f
            == observer_factor(0.3, 4, run)
            == pytest.approx(float(lognormal_factors(0.3, 4, 2, run + 1)[run]))
        )
        # independently: the same scene with Johnson's N50s (1, 4, 6.4) times f as its n50
        scaled = _sim(seed=4, model={"n50": [1.0 * f, 4.0 * f, 6.4 * f]})
        np.testing.assert_allclose(
            sim.probabilities(0.0, *AT).detection, scaled.probabilities(0.0, *AT).detection
        )
        # the step's own path (the bound engine's one-call step) too
        np.testing.assert_allclose(
            sim.step(0.0, 0.1, *AT).recognition, scaled.step(0.0, 0.1, *AT).recognition
        )
    factors = {observer_factor(0.3, 4, run) for run in range(20)}
    assert len(factors) == 20 and min(factors) < 1.0 < max(factors)


def test_runs_are_reproducible_from_the_seed():
    first, second = _sim(seed=8, observer_spread=0.25), _sim(seed=8, observer_spread=0.25)
    first.reset(run=5)
    second.reset(run=5)
    assert first.observer == second.observer
    p = [s.probabilities(0.0, *AT).detection for s in (first, second)]
    np.testing.assert_array_equal(p[0], p[1])
    first.reset(seed=9, run=5)
    assert first.observer != second.observer


def test_a_harder_observer_lowers_the_probabilities():
    sim = _sim(seed=1, observer_spread=0.4)
    values = []
    for run in range(6):
        sim.reset(run=run)
        values.append((sim.observer, float(sim.probabilities(0.0, *AT).detection[0, 0])))
    values.sort()
    assert all(a[1] > b[1] for a, b in itertools.pairwise(values))


@pytest.mark.parametrize("spread", [math.nan, -0.1, 1.5])
def test_invalid_spread_raises_naming_it(spread):
    with pytest.raises(ValueError, match=r"observer_spread must be a relative spread in \[0, 1\]"):
        _sim(observer_spread=spread)
