"""The step API (targetacq.Simulation): same outcomes as simulate(), independence of order and
of other pairs, step-size independence, purity of probabilities(), NaN, frequencies, errors."""

import doctest
import math
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

import targetacq
from targetacq import Simulation, core
from targetacq.run import simulation
from targetacq.run.model_chain import ModelChain
from targetacq.run.search import search_probability, simulate
from targetacq.scenario.schema import Background, ScenarioError, Sensor, Target, load_scenario

ROOT = Path(__file__).parents[2]
TASKS = ("detection", "recognition", "identification")


def _first_times(sim, times, sensor_positions, target_positions, headings=None, pointing=None):
    """Step a simulation through times; first time of each task per pair from the events."""
    first = np.full((3, len(sim.sensors), len(sim.targets)), np.inf)
    previous = None
    for k, t in enumerate(times):
        out = sim.step(
            t,
            0.0 if previous is None else t - previous,
            sensor_positions[:, k],
            target_positions[:, k],
            None if headings is None else headings[:, k],
            pointing,
        )
        previous = t
        for e in out.events:
            j, s, g = TASKS.index(e.task), sim.sensors.index(e.sensor), sim.targets.index(e.target)
            assert times[k - 1] < e.time <= t
            first[j, s, g] = min(first[j, s, g], e.time)
        np.testing.assert_array_equal(out.detected, np.isfinite(first[0]))
    return first


@pytest.mark.parametrize("name", ["uav_haze", "two_sensors_fused", "ground_observer_aircraft"])
def test_stepping_a_scenario_gives_the_outcomes_of_simulate(name):
    scenario = load_scenario(ROOT / "examples" / f"{name}.toml")
    duration, step, runs = 60.0, 1.0, 2
    result = simulate(ModelChain(scenario), duration, step, runs=runs, seed=7)
    times = scenario.time.start + np.arange(0.0, duration + step / 2, step)
    sensor_pos, target_pos, headings = core.scenario_positions(scenario, times)
    sim = Simulation.from_scenario(scenario, seed=7)
    for run in range(runs):
        sim.reset(run=run)
        first = _first_times(sim, times, sensor_pos, target_pos, headings)
        for j, task in enumerate(TASKS):
            np.testing.assert_array_equal(first[j], result.times[task][run])


@pytest.mark.parametrize(
    "path",
    sorted((ROOT / "examples").glob("*.toml"))
    + sorted((ROOT / "tests/data/golden").glob("*.toml")),
    ids=lambda p: p.stem,
)
def test_step_probabilities_equal_the_model_chain(path):
    # Image and terrain clutter included: the terrain's SCR is looked up per step.
    scenario = load_scenario(path)
    times = scenario.time.times()[:4]
    reference = ModelChain(scenario).compute(times)
    sensor_pos, target_pos, headings = core.scenario_positions(scenario, times)
    sim = Simulation.from_scenario(scenario)
    for k, t in enumerate(times):
        dt = t - times[k - 1] if k else 0.0
        out = sim.step(t, dt, sensor_pos[:, k], target_pos[:, k], headings[:, k])
        for name in ("detection", "identification", "fused_detection", "in_view"):
            np.testing.assert_array_equal(getattr(out, name), reference[name][..., k])


def test_some_scenario_has_events_to_compare():
    # The comparison above is not vacuous: the UAV detects targets in some runs.
    scenario = load_scenario(ROOT / "examples" / "uav_haze.toml")
    result = simulate(ModelChain(scenario), 120.0, 1.0, runs=10, seed=7)
    assert np.isfinite(result.times["detection"]).sum() >= 2


def _sensor(name, y):
    return {
        "name": name,
        "band": "lwir",
        "ifov": 0.25e-3,
        "pixels": (640, 480),
        "look_at": (2000.0, 0.0, 0.0),
        "position": (0.0, y, 10.0),
    }


_TARGETS = {
    "truck": {"name": "truck", "dimensions": (7.0, 2.5, 3.0), "temperature": 305.0},
    "jeep": {"name": "jeep", "dimensions": (3.4, 1.6, 1.8), "temperature": 302.0},
}
_ROUTE = {  # start [m], velocity [m/s]
    "truck": (np.array([3500.0, -30.0, 0.0]), np.array([-45.0, 1.0, 0.0])),
    "jeep": (np.array([2600.0, 40.0, 0.0]), np.array([-30.0, -1.5, 0.0])),
}
_MASTS = {"a": 0.0, "b": 60.0}


def _pair_times(sensors, targets, seed=11):
    sim = Simulation(
        [_sensor(s, _MASTS[s]) for s in sensors],
        [_TARGETS[g] for g in targets],
        background={"temperature": 295.0, "clutter_std": 2.0},
        atmosphere={"obscurant": "haze"},
        seed=seed,
    )
    times = np.arange(0.0, 50.0 + 1e-9, 0.5)
    sensor_pos = np.array([[[0.0, _MASTS[s], 10.0]] * times.size for s in sensors])
    target_pos = np.array([[_ROUTE[g][0] + _ROUTE[g][1] * t for t in times] for g in targets])
    first = _first_times(sim, times, sensor_pos, target_pos)
    return {
        (s, g, task): first[j, i, k]
        for j, task in enumerate(TASKS)
        for i, s in enumerate(sensors)
        for k, g in enumerate(targets)
    }


def test_pair_outcomes_do_not_depend_on_sensor_order_or_other_pairs():
    whole = _pair_times(["a", "b"], ["truck", "jeep"])
    assert sum(np.isfinite(v) for v in whole.values()) >= 4  # something happens
    reordered = _pair_times(["b", "a"], ["jeep", "truck"])
    alone = _pair_times(["b"], ["truck"])
    assert reordered == whole
    assert all(whole[key] == value for key, value in alone.items())
    assert _pair_times(["a", "b"], ["truck", "jeep"], seed=12) != whole


def _approach(distance, speed, duration):
    return ModelChain(
        targetacq.scenario.schema.parse_scenario(
            {
                "sensors": [
                    {
                        "name": "ir",
                        "band": "lwir",
                        "ifov": "0.25 mrad",
                        "position": ["0 m"] * 2 + ["5 m"],
                    }
                ],
                "targets": [
                    {
                        "name": "truck",
                        "dimensions": ["7 m", "2.5 m", "3 m"],
                        "temperature": "305 K",
                        "waypoints": [
                            {"time": "0 s", "position": [f"{distance} m", "0 m", "0 m"]},
                            {
                                "time": f"{duration} s",
                                "position": [f"{distance - speed * duration} m", "0 m", "0 m"],
                            },
                        ],
                    }
                ],
                "background": {"temperature": "295 K"},
                "atmosphere": {"obscurant": "haze"},
            }
        )
    )


@settings(max_examples=5)
@given(
    distance=st.floats(2000.0, 6000.0),
    speed=st.floats(10.0, 150.0),
    seed=st.integers(0, 2**20),
)
def test_first_detection_of_an_approaching_target_does_not_depend_on_the_step(
    distance, speed, seed
):
    # With the probability held over a step, 5 s steps delayed detection of a target closing in
    # (P rises within the step); with P linear in time the distributions agree.
    duration, runs = 20.0, 600
    chain = _approach(distance, speed, duration)
    fine = simulate(chain, duration, 0.05, runs=runs, seed=seed).fused["detection"][:, 0]
    coarse = simulate(chain, duration, 5.0, runs=runs, seed=seed + 1).fused["detection"][:, 0]
    # never = +inf is kept (as 1e9): the defective part of the distribution must agree too.
    assert stats.ks_2samp(np.minimum(fine, 1e9), np.minimum(coarse, 1e9)).pvalue > 0.001


def test_constant_p_infinity_gives_the_search_model_frequencies():
    # A standing target: P∞ constant, so detection by t has probability P∞(1 − exp(−t P∞/t_s)).
    chain = _approach(4000.0, 0.0, 30.0)
    p_inf = float(chain.compute([0.0])["detection"][0, 0, 0])
    assert 0.2 < p_inf < 0.9
    n = 3000
    first = simulate(chain, 30.0, 2.0, runs=n, seed=5).fused["detection"][:, 0]
    for t in (2.0, 5.0, 10.0, 30.0):
        expected = search_probability(t, p_inf)
        sigma = math.sqrt(expected * (1 - expected) / n)
        assert abs((first <= t).mean() - expected) < 4 * sigma


def _simple(seed=3):
    return Simulation(
        [Sensor(name="ir", band="lwir", ifov=0.25e-3, position=(0.0, 0.0, 5.0))],
        [
            Target(name="truck", dimensions=(7.0, 2.5, 3.0), temperature=305.0, position=(0, 0, 0)),
            Target(name="jeep", dimensions=(3.4, 1.6, 1.8), temperature=302.0, position=(0, 0, 0)),
        ],
        background=Background(temperature=295.0),
        seed=seed,
    )


_SENSOR_AT = np.array([[0.0, 0.0, 5.0]])


def _targets_at(t):
    return np.array([[1500.0 - 10.0 * t, 0.0, 0.0], [1200.0, 50.0 + 5.0 * t, 0.0]])


def test_probabilities_are_pure_and_equal_to_the_steps():
    stepped, probed = _simple(), _simple()
    for k in range(40):
        t = 0.5 * k
        before = probed.probabilities(t, _SENSOR_AT, _targets_at(t))
        assert probed.time == (None if k == 0 else 0.5 * (k - 1))
        out_probed = probed.step(t, 0.5, _SENSOR_AT, _targets_at(t))
        again = probed.probabilities(t, _SENSOR_AT, _targets_at(t))
        out = stepped.step(t, 0.5, _SENSOR_AT, _targets_at(t))
        for name in ("detection", "recognition", "identification", "fused_detection"):
            np.testing.assert_array_equal(getattr(before, name), getattr(out, name))
            np.testing.assert_array_equal(getattr(again, name), getattr(out, name))
        # Calling probabilities() changed nothing: the same draws, the same events.
        assert list(out_probed.events) == list(out.events)
        np.testing.assert_array_equal(out_probed.identified, out.identified)
    assert out.detected.any()


def test_nan_positions_give_nan_and_no_events_for_their_pairs():
    reference, masked = _simple(), _simple()
    gap = range(10, 30)  # the jeep's position is missing at these steps
    events = {"reference": [], "masked": []}
    for k in range(80):
        t = 0.5 * k
        where = _targets_at(t)
        out = reference.step(t, 0.5, _SENSOR_AT, where)
        events["reference"] += list(out.events)
        if k in gap:
            where = where.copy()
            where[1] = np.nan
        out = masked.step(t, 0.5, _SENSOR_AT, where)
        events["masked"] += list(out.events)
        if k in gap:
            assert np.isnan(out.detection[0, 1]) and np.isnan(out.identification[0, 1])
            assert not np.isnan(out.detection[0, 0])
            assert not any(e.target == "jeep" and e.time > 0.5 * gap[0] - 0.5 for e in out.events)
    jeep = [e for e in events["masked"] if e.target == "jeep"]
    assert all(not (0.5 * gap[0] - 0.5 < e.time <= 0.5 * (gap[-1] + 1)) for e in jeep)
    # The truck's outcomes do not depend on the jeep's gap.
    truck = [[e for e in events[k] if e.target == "truck"] for k in ("reference", "masked")]
    assert truck[0] == truck[1] and truck[0]


def test_probabilities_hand_jax_arrays_to_the_core_unchanged(monkeypatch):
    jax = pytest.importorskip("jax")
    jnp = pytest.importorskip("jax.numpy")
    sim = _simple()
    sensors = jnp.asarray(_SENSOR_AT)
    targets = jnp.asarray(_targets_at(0.0))
    headings = jnp.asarray([0.1, 0.2])
    # Traced under jit: nothing NumPy-only touches the inputs; the numbers are the NumPy core's.
    traced = jax.jit(lambda s, t, h: sim.probabilities(0.0, s, t, h))(sensors, targets, headings)
    reference = sim.probabilities(0.0, _SENSOR_AT, _targets_at(0.0), np.array([0.1, 0.2]))
    for name in ("detection", "identification", "fused_recognition"):
        assert not isinstance(getattr(traced, name), np.ndarray)  # JAX in, JAX out
        np.testing.assert_allclose(
            np.asarray(getattr(traced, name)), getattr(reference, name), rtol=1e-5, atol=1e-7
        )
    # Eager: the very arrays given reach the core.
    received = {}

    def spy(scene, sensor_positions, target_positions, headings=None, pointing=None, scr=None):
        received.update(sensors=sensor_positions, targets=target_positions, headings=headings)
        return None, "probabilities"

    monkeypatch.setattr(simulation.core, "evaluate", spy)
    assert sim.probabilities(0.0, sensors, targets, headings) == "probabilities"
    assert received["sensors"] is sensors and received["targets"] is targets
    assert received["headings"] is headings


def test_bad_input():
    sim = _simple()
    good = (_SENSOR_AT, _targets_at(0.0))
    cases = [
        ((0.0, 0.1, np.zeros((2, 3)), good[1]), r"sensor_positions must have shape \(1, 3\)"),
        ((0.0, 0.1, np.zeros((1, 2)), good[1]), r"sensor_positions: the last dimension must be 3"),
        ((0.0, 0.1, good[0], np.zeros((3, 3))), r"target_positions must have shape \(2, 3\)"),
        ((0.0, 0.1, good[0], np.zeros(6)), r"target_positions: the last dimension must be 3"),
        ((0.0, 0.1, *good, np.zeros(3)), r"target_headings must have shape \(2,\)"),
        ((0.0, 0.1, *good, None, np.zeros((1, 3))), r"sensor_pointing: the last dimension"),
        ((0.0, -0.1, *good), r"^dt must be >= 0 s, got -0\.1$"),
        ((0.0, math.nan, *good), r"^dt must be a number; got NaN$"),
        ((math.nan, 0.1, *good), r"^time must be a number; got NaN$"),
        ((math.inf, 0.1, *good), r"^time must be finite; got inf"),
    ]
    for args, match in cases:
        with pytest.raises(ValueError, match=match):
            sim.step(*args)
    assert sim.time is None  # nothing was stepped
    sim.step(1.0, 0.1, *good)
    with pytest.raises(ValueError, match=r"time must not go back: the previous step was at 1.0 s"):
        sim.step(0.9, 0.1, *good)
    with pytest.raises(ValueError, match=r"dt must be the time since the previous step"):
        sim.step(2.0, 0.5, *good)
    with pytest.raises(ValueError, match="sensor_positions must have shape"):
        sim.probabilities(0.0, np.zeros((3, 3)), good[1])
    with pytest.raises(ValueError, match=r"unknown sensor type 'sonar'.*valid: thermal, tv"):
        Simulation([{"name": "r", "type": "sonar", "ifov": 1e-3}], [_TARGETS["truck"]], seed=1)
    with pytest.raises(ScenarioError, match=r"background\.temperature is needed"):
        Simulation([_sensor("a", 0.0)], [_TARGETS["truck"]])
    for seed in (-1, 1.5):
        with pytest.raises(ValueError, match=r"seed must be an integer in \[0, 2\*\*128 - 1\]"):
            Simulation.from_scenario(ROOT / "examples" / "uav_haze.toml", seed=seed)
    with pytest.raises(ValueError, match="run must be an integer"):
        sim.reset(run=-1)


def test_readme_stepping_loop_runs_as_written(monkeypatch, capsys):
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    section = text.split("## Use it inside your simulation", 1)[1]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    monkeypatch.chdir(ROOT)
    namespace: dict = {}
    exec(compile(code, "README.md", "exec"), namespace)  # the README's own example
    out = namespace["out"]
    assert out.detection.shape == (1, 2) and out.fused_detected.all()
    assert "detection of" in capsys.readouterr().out


def test_docstring_examples_run():
    for module in (simulation, targetacq.run.search):
        failures, tried = doctest.testmod(module, optionflags=doctest.ELLIPSIS)
        assert tried > 0 and failures == 0


def _noise_sim(netd, temperature, **sensor):
    return Simulation(
        [{**_sensor("a", 0.0), "netd": netd, **sensor}],
        [{**_TARGETS["truck"], "temperature": temperature}],
        background={"temperature": 295.0},
    )


@pytest.mark.parametrize("distance", [500.0, 2000.0, 10000.0])
def test_a_target_at_the_background_temperature_is_not_detected(distance):
    # Zero contrast with a NETD: the sensor's SNR is 0, so no task succeeds at any range.
    sim = _noise_sim("50 mK", 295.0)
    out = sim.probabilities(0.0, np.array([[0.0, 0.0, 10.0]]), np.array([[distance, 0.0, 0.0]]))
    assert float(np.max(out.detection)) < 0.01
    # Without a NETD the thesis's geometry alone detects it (no path, no noise).
    quiet = Simulation(
        [_sensor("a", 0.0)],
        [{**_TARGETS["truck"], "temperature": 295.0}],
        background={"temperature": 295.0},
    )
    got = quiet.probabilities(0.0, np.array([[0.0, 0.0, 10.0]]), np.array([[distance, 0.0, 0.0]]))
    assert float(got.detection[0, 0]) > 0.1


def test_a_hotter_target_is_recognised_with_more_probability():
    sensor_pos, target_pos = np.array([[0.0, 0.0, 10.0]]), np.array([[2500.0, 0.0, 0.0]])
    cold = _noise_sim("100 mK", 295.05).probabilities(0.0, sensor_pos, target_pos)
    hot = _noise_sim("100 mK", 340.0).probabilities(0.0, sensor_pos, target_pos)
    assert float(hot.recognition[0, 0]) > float(cold.recognition[0, 0]) + 0.01
