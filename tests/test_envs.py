"""The Gymnasium environment: the API checker, reproducibility, and a scripted policy that wins."""

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

from targetacq.envs import SensorPointingEnv  # noqa: E402


def test_check_env_passes():
    from gymnasium.utils.env_checker import check_env

    env = gymnasium.make("targetacq/SensorPointing-v0", targets=3, duration=10.0)
    check_env(env.unwrapped, skip_render_check=True)


def test_reset_with_a_seed_reproduces_the_episode():
    def episode(seed):
        env = SensorPointingEnv(targets=4, duration=30.0)
        obs, _ = env.reset(seed=seed)
        trace, rewards = [obs], []
        done = False
        while not done:
            obs, reward, terminated, truncated, _ = env.step(env.greedy_action())
            trace.append(obs)
            rewards.append(reward)
            done = terminated or truncated
        return np.array(trace), rewards

    a, ra = episode(3)
    b, rb = episode(3)
    np.testing.assert_array_equal(a, b)
    assert ra == rb
    c, _ = episode(4)
    assert not np.array_equal(a[0], c[0])


def test_rewards_count_each_acquisition_once():
    env = SensorPointingEnv(targets=5, duration=120.0)
    env.reset(seed=11)
    total, done = 0.0, False
    while not done:
        _, reward, terminated, truncated, _ = env.step(env.greedy_action())
        assert reward >= 0
        total += reward
        done = terminated or truncated
    flags = sum(int(env._acquired[task].sum()) for task in env._acquired)
    assert total == flags <= 3 * 5


def test_bad_arguments():
    with pytest.raises(ValueError, match="cameras must be an integer >= 1"):
        SensorPointingEnv(cameras=0)
    with pytest.raises(ValueError, match="dt must be finite and > 0"):
        SensorPointingEnv(dt=-1.0)
    env = SensorPointingEnv(targets=2)
    env.reset(seed=0)
    with pytest.raises(ValueError, match="action must be finite"):
        env.step(np.array([[np.nan, 0.0]], dtype=np.float32))


def test_greedy_pointing_beats_random_pointing_over_20_seeded_episodes():
    import runpy
    from pathlib import Path

    example = Path(__file__).parents[1] / "examples" / "pointing_policies.py"
    scores = runpy.run_path(str(example), run_name="not_main")["compare"](episodes=20)
    assert scores["greedy"] > scores["random"]
