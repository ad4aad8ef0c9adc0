"""Graded hot spots and motion, and the sky-to-ground ratio, in the scenario core.

Expected values come from the range cases (:func:`targetacq.core.cases.case_acquisition`, an
independent path from the scalar inputs through :mod:`targetacq.core.cases`), from the switched
model (``hot_spot = true``, ``moving = true``) as the limit, and from properties (no motion cue
without angular speed; a 1 % input change moves P by < 0.05).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from targetacq import core
from targetacq.core.cases import RangeCase, case_acquisition
from targetacq.core.engines.numba_engine import supported
from targetacq.run.model_chain import ModelChain
from targetacq.run.simulation import Simulation
from targetacq.scenario.schema import Scenario, ScenarioError

IFOV = 1e-4  # [rad]: one cycle is 2 IFOV (no aperture)
SIDE = 4.0  # [m]: a cube, the same side from every horizontal aspect
RANGE = 12_000.0  # [m]: N = 4 / (12 km · 0.2 mrad) = 1.67 cycles
SCR = 0.5  # high clutter: the hot spot's and motion's cues matter


def _target(name: str, **extra: object) -> dict[str, object]:
    return {
        "name": name,
        "dimensions": [f"{SIDE} m"] * 3,
        "temperature": "305 K",
        "position": ["0 m", f"{RANGE} m", "0 m"],
        **extra,
    }


def _crossing(name: str, speed: float, **extra: object) -> dict[str, object]:
    """A target crossing east at ``speed`` [m/s], due north of the sensor at t = 50 s."""
    half = 50.0 * speed
    return {
        "name": name,
        "dimensions": [f"{SIDE} m"] * 3,
        "temperature": "305 K",
        "waypoints": [
            {"time": "0 s", "position": [f"{-half} m", f"{RANGE} m", "0 m"]},
            {"time": "100 s", "position": [f"{half} m", f"{RANGE} m", "0 m"]},
        ],
        **extra,
    }


def _scenario(*targets: dict[str, object], **background: object) -> Scenario:
    return Scenario.model_validate(
        {
            "sensors": [
                {"name": "ir", "band": "lwir", "ifov": f"{IFOV} rad", "position": ["0 m"] * 3}
            ],
            "targets": list(targets),
            "background": {"temperature": "295 K", "scr": SCR, **background},
        }
    )


def _detection(scenario: Scenario, time: float = 50.0) -> np.ndarray:
    return np.asarray(ModelChain(scenario).compute([time])["detection"])[0, :, 0]


def _case(**cues: object) -> float:
    case = RangeCase(SIDE, IFOV, scr=SCR, **cues)  # type: ignore[arg-type]
    return float(case_acquisition(case, RANGE).detection)


# -- hot spots --------------------------------------------------------------------------------


@pytest.mark.parametrize("ratio", [0.5, 3.0, 30.0])
def test_a_graded_hot_spot_is_the_range_case_with_the_same_ratio(ratio):
    p = _detection(_scenario(_target("t", hot_spot_ratio=ratio)))
    assert p[0] == pytest.approx(_case(hot_spot_ratio=ratio), rel=1e-12)


def test_a_hot_spot_smaller_than_its_element_is_the_range_case_with_its_size():
    # 0.5 m at 12 km: 0.5 / (12 km · 0.1 mrad) = 0.42 pixel across, diluted to 0.17 of its SCR.
    p = _detection(_scenario(_target("t", hot_spot_ratio=20.0, hot_spot_size="0.5 m")))
    expected = _case(hot_spot_ratio=20.0, hot_spot_size=0.5)
    assert p[0] == pytest.approx(expected, rel=1e-12)
    assert expected < _case(hot_spot_ratio=20.0) - 0.05  # the dilution matters here


def test_the_flags_give_todays_numbers_and_targets_without_cues_are_untouched():
    flags = _scenario(_target("hot", hot_spot=True), _target("plain"))
    p = _detection(flags)
    assert p[0] == pytest.approx(_case(hot_spot=True), rel=1e-12)
    assert flags.targets[0].hot_spot and core.compile_scenario(flags).scene.targets.graded is False
    # A graded target beside them changes nothing of theirs, to the last bit.
    mixed = _detection(
        _scenario(_target("hot", hot_spot=True), _target("plain"), _target("g", hot_spot_ratio=3.0))
    )
    assert mixed[0] == p[0] and mixed[1] == p[1]


def test_hot_spot_weight_changes_p_by_less_than_005_per_percent():
    scenario = _scenario(*(_target(f"t{k}", hot_spot_ratio=1.0) for k in range(2)))
    compiled = core.compile_scenario(scenario).scene
    ratios = np.geomspace(0.01, 1e3, 400)
    s_pos = np.zeros((1, 1, 3))
    t_pos = np.tile([0.0, RANGE, 0.0], (2, 1, 1))

    def p(ratio: float) -> float:
        targets = dataclasses.replace(compiled.targets, hot_spot_ratio=np.array([ratio, 1.0]))
        scene = dataclasses.replace(compiled, targets=targets)
        return float(core.evaluate(scene, s_pos, t_pos)[1].detection[0, 0, 0])

    values = np.array([p(r) for r in ratios])
    stepped = np.array([p(r * 1.01) for r in ratios])
    assert values[-1] - values[0] > 0.3  # the cue spans a large change of P
    assert np.max(np.abs(stepped - values)) < 0.05


# -- motion -----------------------------------------------------------------------------------


def test_a_crossing_target_is_the_range_case_with_its_speed():
    p = _detection(_scenario(_crossing("c", 1.0, graded_motion=True)))
    # Due north at t = 50 s, crossing east: all of its 1 m/s is across the line of sight.
    assert p[0] == pytest.approx(_case(target_speed=1.0), rel=1e-12)
    assert 0.1 < (p[0] - _case()) / (_case(moving=True) - _case()) < 0.9  # graded, not switched


def test_no_angular_speed_gives_no_motion_cue():
    standing = _target("still", graded_motion=True)
    toward = {  # driving straight at the sensor along the line of sight
        **_target("toward", graded_motion=True),
        "position": None,
        "waypoints": [
            {"time": "0 s", "position": ["0 m", f"{RANGE + 500} m", "0 m"]},
            {"time": "100 s", "position": ["0 m", f"{RANGE - 500} m", "0 m"]},
        ],
    }
    toward.pop("position")
    p = _detection(_scenario(standing, toward, _target("plain")))
    plain = _case()
    assert p[0] == plain and p[2] == plain
    # Toward: at t = 50 s the range is RANGE again, and no speed across it.
    assert p[1] == pytest.approx(plain, rel=1e-12)


def test_a_fast_crossing_target_approaches_the_moving_switch():
    # 60 m/s at 12 km: 60 / (12 km · 0.1 mrad) = 50 pixels/s, w = 1 − 4e-5.
    p = _detection(_scenario(_crossing("fast", 60.0, graded_motion=True)))
    switched = _case(moving=True)
    assert p[0] == pytest.approx(switched, abs=1e-4)
    assert p[0] < switched
    moving = _detection(_scenario(_crossing("m", 60.0, moving=True)))
    assert moving[0] == pytest.approx(switched, rel=1e-12)  # the flag: today's number


def test_motion_weight_changes_p_by_less_than_005_per_percent():
    compiled = core.compile_scenario(_scenario(_target("t", graded_motion=True))).scene
    s_pos, t_pos = np.zeros((1, 1, 3)), np.array([[[0.0, RANGE, 0.0]]])
    found = core.factors(compiled, s_pos, t_pos)
    speeds = np.geomspace(1e-3, 100.0, 400)

    def p(speed: np.ndarray) -> np.ndarray:
        crossing = np.reshape(speed, (1, 1, -1))
        batch = dataclasses.replace(
            found,
            range=np.broadcast_to(found.range, crossing.shape),
            critical_dimension=np.broadcast_to(found.critical_dimension, crossing.shape),
            cycles=np.broadcast_to(found.cycles, crossing.shape),
            in_view=np.broadcast_to(found.in_view, crossing.shape),
            crossing_speed=crossing,
        )
        return np.asarray(core.probabilities(compiled, batch).detection)[0, 0]

    values, stepped = p(speeds), p(speeds * 1.01)
    assert values[-1] - values[0] > 0.3
    assert np.max(np.abs(stepped - values)) < 0.05


# -- the step API, the engines ----------------------------------------------------------------


def test_the_step_api_grades_motion_by_the_targets_velocity_each_step():
    sim = Simulation.from_scenario(_scenario(_target("t", graded_motion=True)), seed=1)
    here = np.array([[0.0, RANGE, 0.0]])
    sensor = np.zeros((1, 3))
    first = sim.step(0.0, 1.0, sensor, here)  # first step: standing
    assert first.detection[0, 0] == pytest.approx(_case(), rel=1e-12)
    # One second later 1 m east: 1 m/s across the line of sight (the step's own motion).
    moved = sim.step(1.0, 1.0, sensor, here + np.array([[1.0, 0.0, 0.0]]))
    # At range hypot(12 km, 1 m), 1 m/s almost all across it.
    crossing = RANGE / np.hypot(RANGE, 1.0)
    expected = float(
        case_acquisition(
            RangeCase(SIDE, IFOV, scr=SCR, target_speed=crossing), np.hypot(RANGE, 1.0)
        ).detection
    )
    assert moved.detection[0, 0] == pytest.approx(expected, rel=1e-9)
    given = sim.step(2.0, 1.0, sensor, here, target_velocities=np.array([[0.0, 0.0, 0.0]]))
    assert given.detection[0, 0] == pytest.approx(_case(), rel=1e-12)
    with pytest.raises(ValueError, match="target_velocities"):
        sim.step(3.0, 1.0, sensor, here, target_velocities=np.zeros((2, 3)))


def test_numba_refuses_graded_cues_and_auto_falls_back_to_numpy():
    scene = core.compile_scenario(_scenario(_target("t", hot_spot_ratio=3.0))).scene
    reason = supported(scene)
    assert reason is not None and "graded" in reason
    chain = ModelChain(_scenario(_target("t", hot_spot_ratio=3.0)), engine="auto")
    assert chain.bound(chain.compiled.scene).engine == "numpy"


def test_jax_traces_graded_cues():
    jax = pytest.importorskip("jax")
    jax.config.update("jax_enable_x64", True)
    from targetacq.core.records import as_jax

    scenario = _scenario(
        _target("h", hot_spot_ratio=3.0, hot_spot_size="0.5 m"), _target("m", graded_motion=True)
    )
    scene = core.compile_scenario(scenario).scene
    s_pos = np.zeros((1, 3))
    t_pos = np.array([[0.0, RANGE, 0.0], [100.0, RANGE, 0.0]])
    velocity = np.array([[0.0, 0.0, 0.0], [1.5, 0.0, 0.0]])
    expected = core.evaluate(scene, s_pos, t_pos, target_velocities=velocity)[1].detection
    run = jax.jit(lambda sc, s, t, v: core.evaluate(sc, s, t, target_velocities=v)[1].detection)
    got = run(as_jax(scene), s_pos, t_pos, velocity)
    np.testing.assert_allclose(np.asarray(got), expected, rtol=1e-12)
    assert expected[0, 1] > float(core.evaluate(scene, s_pos, t_pos)[1].detection[0, 1])


# -- the scenario file ------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        ({"hot_spot": True, "hot_spot_ratio": 3.0}, "not both"),
        ({"hot_spot_size": "1 m"}, "hot_spot_ratio"),
        ({"hot_spot_ratio": -1.0}, "hot_spot_ratio"),
        ({"hot_spot_ratio": 3.0, "hot_spot_size": "0 m"}, "hot_spot_size"),
    ],
)
def test_contradictory_or_bad_cues_are_refused(extra, message):
    with pytest.raises((ValueError, ScenarioError), match=message):
        _scenario(_target("t", **extra))


def test_moving_and_graded_motion_together_are_refused():
    with pytest.raises((ValueError, ScenarioError), match="not both"):
        _scenario(_crossing("t", 1.0, moving=True, graded_motion=True))


# -- the sky-to-ground ratio ------------------------------------------------------------------


def test_sky_to_ground_reaches_a_tv_cameras_noise_as_the_range_case():
    extinction, nec, k = 0.05e-3, 0.02, 3.0  # [Np/m], [1], [1]
    distance = RANGE / 2  # N = 3.3 cycles through τ = 0.74
    rho_t, rho_b = 0.3, 0.1  # contrast 2

    def scenario(**background: object) -> Scenario:
        return Scenario.model_validate(
            {
                "sensors": [
                    {
                        "name": "tv",
                        "type": "tv",
                        "ifov": f"{IFOV} rad",
                        "nec": nec,
                        "position": ["0 m"] * 3,
                    }
                ],
                "targets": [{**_target("t"), "temperature": None, "reflectance": rho_t}],
                "background": {"reflectance": rho_b, "irradiance": "300 W/m^2", **background},
                "atmosphere": {"extinction": f"{extinction * 1e3} /km"},
            }
        )

    def case(**extra: object) -> float:
        found = RangeCase(
            SIDE,
            IFOV,
            extinction=extinction,
            contrast=abs(rho_t - rho_b) / rho_b,
            noise_equivalent_contrast=nec,
            target_area=SIDE * SIDE,
            **extra,  # type: ignore[arg-type]
        )
        return float(case_acquisition(found, distance).detection)

    def p(s: Scenario) -> float:
        chain = ModelChain(s)
        s_pos = np.zeros((1, 1, 3))
        t_pos = np.array([[[0.0, distance, 0.0]]])
        bound = chain.bound(chain.compiled.scene)
        return float(bound.probabilities(bound.factors(s_pos, t_pos)).detection[0, 0, 0])

    with_k = p(scenario(sky_to_ground=k))
    assert with_k == pytest.approx(case(sky_to_ground=k), rel=1e-9)
    assert p(scenario()) == pytest.approx(case(), rel=1e-9)
    assert with_k < p(scenario()) - 0.01  # a background darker than the sky loses contrast


def test_sky_to_ground_leaves_a_thermal_camera_as_it_was():
    plain = _detection(_scenario(_target("t")), 0.0)
    with_k = _detection(_scenario(_target("t"), sky_to_ground=3.0), 0.0)
    np.testing.assert_allclose(with_k, plain, rtol=1e-14)


def test_the_chains_range_cases_carry_the_graded_cues():
    scenario = _scenario(
        _target("h", hot_spot_ratio=3.0, hot_spot_size="0.5 m"),
        _crossing("c", 1.0, graded_motion=True),
    )
    chain = ModelChain(scenario)
    cases = chain.range_cases(50.0)
    assert cases["ir → h"].hot_spot_size == 0.5
    assert cases["ir → c"].target_speed == pytest.approx(1.0, rel=1e-12)
    p = _detection(scenario)
    for k, name in enumerate(("h", "c")):
        found = case_acquisition(cases[f"ir → {name}"], RANGE).detection
        assert float(found) == pytest.approx(p[k], rel=1e-12)


def test_the_environment_takes_graded_cues_and_its_flying_platform_gives_no_motion_cue():
    pytest.importorskip("gymnasium")
    from targetacq.envs import SensorPointingEnv

    def episode(overrides: dict[str, object]) -> tuple[np.ndarray, list[float]]:
        env = SensorPointingEnv(targets=3, duration=20.0, scenario_overrides=overrides)
        obs, _ = env.reset(seed=2)
        trace, rewards, done = [obs], [], False
        while not done:
            obs, reward, terminated, truncated, _ = env.step(env.greedy_action())
            trace.append(obs)
            rewards.append(float(reward))
            done = terminated or truncated
        assert env.scenario.targets[0].graded_motion == bool(overrides)
        return np.array(trace), rewards

    base = episode({})
    assert sum(base[1]) > 0  # the seed's episode acquires something
    # The targets stand still under a platform flying at 40 m/s: graded motion adds nothing.
    graded = episode({"target": {"graded_motion": True}})
    np.testing.assert_array_equal(graded[0], base[0])
    assert graded[1] == base[1]
    env = SensorPointingEnv(targets=3, scenario_overrides={"target": {"hot_spot_ratio": 5.0}})
    env.reset(seed=2)
    assert env.scenario.targets[0].hot_spot_ratio == 5.0
    assert env._sim.compiled.scene.targets.graded
