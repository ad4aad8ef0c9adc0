"""The environment under the TTP resolution model: ``scenario_overrides={"model":
{"resolution_model": "ttp"}}`` (with the camera's aperture) reaches an episode, and the episode
steps the core's TTP scenario (issue 25, item 1)."""

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

from targetacq import Simulation  # noqa: E402
from targetacq.envs import SensorPointingEnv  # noqa: E402
from targetacq.scenario.schema import ScenarioError  # noqa: E402

TTP = {
    "model": {"resolution_model": "ttp"},
    "sensor": {"f_number": 1.5, "netd": "50 mK", "jitter": "0.02 mrad"},
}


def _episode(env, seed):
    env.reset(seed=seed)
    rewards, done = [], False
    while not done:
        _, reward, terminated, truncated, _ = env.step(env.greedy_action())
        rewards.append(reward)
        done = terminated or truncated
    return rewards


def _recognition(sim, env):
    """P(recognition) of each target by the first camera pointed at it."""
    platform = env._platform(0.0)[None]
    offsets = env._targets - platform
    azimuth = np.arctan2(offsets[:, 0], offsets[:, 1])
    depression = np.arctan2(-offsets[:, 2], np.hypot(offsets[:, 0], offsets[:, 1]))
    return np.array(
        [
            sim.probabilities(
                0.0, platform, env._targets, env._headings, np.array([[azimuth[j], depression[j]]])
            ).recognition[0, j]
            for j in range(env.n_targets)
        ]
    )


def test_the_ttp_model_reaches_the_episode():
    env = SensorPointingEnv(targets=3, duration=3.0, scenario_overrides=TTP)
    rewards = _episode(env, seed=5)
    assert len(rewards) == 3 and all(np.isfinite(rewards))
    scenario = env.scenario
    assert scenario.model.resolution_model == "ttp"
    assert (scenario.model.criterion, scenario.model.transform) == ("ttp-vehicles", "ttp")
    assert env._sim.compiled.scene.sensors.ttp is not None
    # The episode's model is the core's TTP scenario, built here from its records ...
    got = _recognition(env._sim, env)
    np.testing.assert_array_equal(got, _recognition(Simulation.from_scenario(scenario), env))
    assert np.all(got > 0.0)
    # ... and not the Johnson one of the same cameras.
    johnson = _recognition(
        Simulation.from_scenario(
            scenario.model_copy(
                update={
                    "model": scenario.model.model_copy(
                        update={
                            "resolution_model": None,
                            "criterion": "johnson",
                            "transform": "ttpf",
                        }
                    ),
                    "sensors": [s.model_copy(update={"jitter": None}) for s in scenario.sensors],
                }
            )
        ),
        env,
    )
    assert not np.allclose(got, johnson)


def test_ttp_without_an_aperture_is_refused_at_the_option():
    with pytest.raises(ScenarioError, match=r"scenario_overrides: sensor\.aperture: .*f_number"):
        SensorPointingEnv(targets=2, scenario_overrides={"model": {"resolution_model": "ttp"}})
