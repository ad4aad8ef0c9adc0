"""The environment's ``scenario_overrides``: the core's sensor, target, path and model features
reach an episode, checked by the scenario's own records when the environment is made."""

from importlib import resources
from pathlib import Path

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

from targetacq import Simulation  # noqa: E402
from targetacq.envs import SensorPointingEnv  # noqa: E402
from targetacq.envs.pointing import CONTROLLED_FIELDS, OVERRIDE_TABLES  # noqa: E402
from targetacq.scenario.schema import Sensor, Target  # noqa: E402

MRTD = Path(str(resources.files("targetacq").joinpath("data").joinpath("example_mrtd.csv")))


def _episode(env, seed):
    """Observations and rewards of a seeded episode under the greedy policy."""
    obs, _ = env.reset(seed=seed)
    trace, rewards, done = [obs], [], False
    while not done:
        obs, reward, terminated, truncated, _ = env.step(env.greedy_action())
        trace.append(obs)
        rewards.append(reward)
        done = terminated or truncated
    return np.array(trace), rewards


def _identification(scenario, env):
    """P(identification) of each target by the first camera pointed at it, from a simulation
    that the core builds from ``scenario`` (not the environment's own)."""
    sim = Simulation.from_scenario(scenario)
    platform = env._platform(0.0)[None]
    offsets = env._targets - platform
    azimuth = np.arctan2(offsets[:, 0], offsets[:, 1])
    depression = np.arctan2(-offsets[:, 2], np.hypot(offsets[:, 0], offsets[:, 1]))
    return np.array(
        [
            sim.probabilities(
                0.0, platform, env._targets, env._headings, np.array([[azimuth[j], depression[j]]])
            ).identification[0, j]
            for j in range(env.n_targets)
        ]
    )


def test_the_overrides_name_the_scenario_records():
    assert set(OVERRIDE_TABLES) == {
        "sensor",
        "target",
        "atmosphere",
        "background",
        "model",
        "terrain",
    }
    for table, fields in CONTROLLED_FIELDS.items():
        assert set(fields) <= set(OVERRIDE_TABLES[table].model_fields)
    assert {"name", "position", "azimuth", "depression", "type"} <= set(CONTROLLED_FIELDS["sensor"])
    assert {"position", "heading", "dimensions"} <= set(CONTROLLED_FIELDS["target"])


def test_a_netd_is_the_core_scenario_with_the_netd_and_never_raises_p():
    # A faint target (0.3 K over the background) on a quiet background: the NETD counts.
    faint = {"target": {"temperature": "293.3 K"}, "background": {"clutter_std": "0.05 K"}}
    base = SensorPointingEnv(targets=4, duration=5.0, scenario_overrides=faint)
    base.reset(seed=2)
    noisy = {}
    for netd in ("50 mK", "1 K"):
        env = SensorPointingEnv(
            targets=4, duration=5.0, scenario_overrides={**faint, "sensor": {"netd": netd}}
        )
        env.reset(seed=2)
        noisy[netd] = env
    # The episode's scenario is the faint one with the NETD [K] on every camera, as built
    # here by hand from the records; the layout of the seed is the same.
    for netd, value in (("50 mK", 0.05), ("1 K", 1.0)):
        scenario = noisy[netd].scenario
        expected = base.scenario.model_copy(
            update={
                "sensors": [s.model_copy(update={"netd": value}) for s in base.scenario.sensors]
            }
        )
        assert scenario == expected
        assert scenario != base.scenario
        np.testing.assert_array_equal(noisy[netd]._targets, base._targets)
    # The core's answer for the same scenarios: a larger NETD never raises P, and 1 K lowers it.
    p0 = _identification(base.scenario, base)
    p1 = _identification(noisy["50 mK"].scenario, base)
    p2 = _identification(noisy["1 K"].scenario, base)
    assert np.all(p2 <= p1) and np.all(p1 <= p0)
    assert np.any(p2 < p0 - 0.01)
    # ... and the environment steps that model: its own probabilities are the core's.
    sim = noisy["1 K"]._sim
    platform = base._platform(0.0)[None]
    np.testing.assert_array_equal(
        sim.probabilities(0.0, platform, base._targets, base._headings).identification,
        Simulation.from_scenario(noisy["1 K"].scenario)
        .probabilities(0.0, platform, base._targets, base._headings)
        .identification,
    )


def test_a_larger_netd_never_raises_the_reward_of_a_seeded_episode():
    rewards = [
        sum(
            _episode(
                SensorPointingEnv(
                    targets=3,
                    duration=20.0,
                    scenario_overrides={
                        "target": {"temperature": "293.3 K"},
                        "background": {"clutter_std": "0.05 K"},
                        **({} if netd is None else {"sensor": {"netd": netd}}),
                    },
                ),
                seed=1,
            )[1]
        )
        for netd in (None, "0.3 K", "1 K")
    ]
    assert rewards[0] > 0
    assert rewards[2] <= rewards[1] <= rewards[0]
    assert rewards[2] < rewards[0]  # 1 K loses an acquisition the quiet camera makes


def test_foliage_that_hides_the_targets_gives_no_reward():
    open_trace, open_rewards = _episode(SensorPointingEnv(targets=3, duration=20.0), seed=2)
    assert sum(open_rewards) > 0  # the seed's episode earns something in the open
    hidden = SensorPointingEnv(
        targets=3, duration=20.0, scenario_overrides={"target": {"foliage": 0.0}}
    )
    trace, rewards = _episode(hidden, seed=2)
    assert sum(rewards) == 0
    assert all(t.foliage == 0.0 for t in hidden.scenario.targets)
    flags = trace[:, 3 + 2 :].reshape(len(trace), 3, 6)[:, :, 3:]
    assert not flags.any()
    # Same layout (the positions relative to the platform), other outcomes.
    np.testing.assert_array_equal(trace[0, :-9], open_trace[0, :-9])


def test_an_mrtd_curve_is_read_from_the_current_directory(monkeypatch):
    monkeypatch.chdir(MRTD.parent)
    env = SensorPointingEnv(
        targets=3, duration=3.0, scenario_overrides={"sensor": {"mrtd": MRTD.name}}
    )
    monkeypatch.chdir(MRTD.parents[2])  # the path was taken where the environment was made
    _, rewards = _episode(env, seed=2)
    assert len(rewards) == 3
    assert Path(env.scenario.sensors[0].mrtd) == MRTD
    base = SensorPointingEnv(targets=3, duration=3.0)
    base.reset(seed=2)
    # MRTD-limited cycles: the core's P differs from the sampling-limited camera's.
    assert not np.allclose(
        _identification(env.scenario, base), _identification(base.scenario, base)
    )


def test_overrides_that_restate_the_defaults_change_nothing():
    plain = _episode(SensorPointingEnv(targets=3, duration=10.0), seed=4)
    for overrides in (
        {},
        {
            "sensor": {"pitch": "17 um", "focal_length": 0.1, "pixels": [640, 512]},
            "target": {},
            "atmosphere": {"obscurant": "haze"},
            "background": {"temperature": "293 K", "clutter_std": 2.0},
            "model": {"transform": "ttpf", "redraw": "never"},
        },
    ):
        same = _episode(
            SensorPointingEnv(targets=3, duration=10.0, scenario_overrides=overrides), seed=4
        )
        np.testing.assert_array_equal(same[0], plain[0])
        assert same[1] == plain[1]


def test_a_group_field_replaces_the_default_group():
    env = SensorPointingEnv(
        targets=2,
        duration=2.0,
        scenario_overrides={
            "sensor": {"hfov": "10 deg"},
            "atmosphere": {"extinction": "0.2 /km"},
            "background": {"scr": 3.0},
        },
    )
    env.reset(seed=0)
    sensor, atmosphere, background = (
        env.scenario.sensors[0],
        env.scenario.atmosphere,
        env.scenario.background,
    )
    assert sensor.pitch is None and sensor.focal_length is None
    assert sensor.hfov == pytest.approx(np.radians(10.0))
    assert atmosphere.obscurant is None and atmosphere.extinction == pytest.approx(2e-4)
    assert background.clutter_std is None and background.scr == 3.0


@pytest.mark.parametrize(
    ("overrides", "message"),
    [
        ({"sensor": {"netd": "-5 mK"}}, r"scenario_overrides: sensor\.netd: .*\[0, "),
        ({"sensor": {"netd": "5 m"}}, r"sensor\.netd: '5 m' is not a temperature difference"),
        ({"target": {"foliage": 1.5}}, r"scenario_overrides: target\.foliage: must be <= 1"),
        (
            {"target": {"folage": 0.5}},
            r"target\.folage: unknown key 'folage' \(did you mean 'foliage'\?\); valid keys: "
            r"name, dimensions",
        ),
        (
            {"model": {"redraw": "sometimes"}},
            r"model\.redraw: unknown redraw rule 'sometimes'; valid: never",
        ),
        ({"model": {"redraw": "after-out-of-view"}}, r"model: .* needs decorrelation_time"),
        (
            {"atmosphere": {"extinction": 1e-4, "visibility": "5 km"}},
            r"atmosphere: give one of extinction, obscurant and visibility",
        ),
        ({"sensor": {"mrtd": "no-such-curve.csv"}}, r"sensor\.mrtd: no MRTD curve"),
        (
            {"sensors": {"netd": "50 mK"}},
            r"unknown key 'sensors' \(did you mean 'sensor'\?\); valid keys: sensor, target, "
            r"atmosphere, background, model",
        ),
        ({"sensor": ["netd"]}, r"sensor must be a mapping of Sensor's fields, got list"),
        (
            {"sensor": {"azimuth": 0.3, "netd": 0.05}},
            r"sensor\.azimuth: the environment sets azimuth itself \(azimuth: the action",
        ),
        ({"sensor": {"type": "tv"}}, r"sensor\.type: .* give camera_type"),
        ({"sensor": {"position": [0, 0, 10]}}, r"sensor\.position: the environment sets"),
        (
            {"target": {"heading": 1.0, "dimensions": [1, 1, 1]}},
            r"target\.heading: the environment sets heading, dimensions itself .* drawn per "
            r"episode",
        ),
    ],
)
def test_bad_overrides_are_refused_when_the_environment_is_made(overrides, message):
    with pytest.raises(ValueError, match=message):
        SensorPointingEnv(targets=2, scenario_overrides=overrides)


def test_an_mrtd_curve_needs_a_thermal_camera_and_a_mapping_is_needed():
    with pytest.raises(ValueError, match=r"sensor\.mrtd: an MRTD curve is a thermal sensor's"):
        SensorPointingEnv(camera_type="tv", scenario_overrides={"sensor": {"mrtd": str(MRTD)}})
    with pytest.raises(ValueError, match=r"must be a mapping .* got float \(a lens is"):
        SensorPointingEnv(1, 2, 10.0, 1.0, 1500.0, 40.0, 3000.0, 0.2)  # the old focal_length


def test_every_field_of_a_record_is_reachable_but_the_controlled_ones():
    """The records list the options: nothing is kept by hand but the controlled fields."""
    for table, record in (("sensor", Sensor), ("target", Target)):
        free = set(record.model_fields) - set(CONTROLLED_FIELDS[table])
        assert {"netd", "mrtd", "quantisation_step", "nec"} <= free or table == "target"
        assert {"foliage", "hot_spot", "temperature"} <= free or table == "sensor"


def test_gymnasium_make_passes_the_overrides_through():
    env = gymnasium.make(
        "targetacq/SensorPointing-v0",
        targets=2,
        duration=3.0,
        scenario_overrides={"target": {"foliage": 0.25}, "sensor": {"netd": "50 mK"}},
    )
    env.reset(seed=1)
    scenario = env.unwrapped.scenario
    assert [t.foliage for t in scenario.targets] == [0.25, 0.25]
    assert scenario.sensors[0].netd == pytest.approx(0.05)
    with pytest.raises(ValueError, match=r"scenario_overrides: target\.foliage"):
        gymnasium.make("targetacq/SensorPointing-v0", scenario_overrides={"target": {"foliage": 2}})
