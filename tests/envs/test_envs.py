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
    with pytest.raises(ValueError, match="cameras must be an integer in \\[1, 64\\]"):
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

    example = Path(__file__).parents[2] / "examples" / "pointing_policies.py"
    scores = runpy.run_path(str(example), run_name="not_main")["compare"](episodes=20)
    assert scores["greedy"] > scores["random"]


def _look_away_and_back(env):
    """Point at the nearest target for 3 steps, 57 degrees beside it for 3, and again: a target
    leaves the view and comes back, so the model reacquires it."""
    k = 0
    while True:
        action = env.greedy_action()
        if (k // 3) % 2:
            action[:, 0] = np.where(action[:, 0] < 0, action[:, 0] + 1.0, action[:, 0] - 1.0)
        k += 1
        yield action


@pytest.mark.parametrize("cameras", [1, 2])
def test_reacquisitions_are_reported_and_never_rewarded(cameras):
    from targetacq.run.simulation import EVENT_KINDS, TASKS

    env = SensorPointingEnv(cameras=cameras, targets=2, duration=120.0, dt=1.0)
    _, info = env.reset(seed=5)
    assert info["events"] == []  # the first step only starts the clock
    flags = ("detected", "recognised", "identified")
    for flag in flags:
        np.testing.assert_array_equal(info[flag], np.zeros(2, dtype=bool))
    total, kinds, firsts, done = 0.0, [], set(), False
    policy = _look_away_and_back(env)
    while not done:
        before = {flag: info[flag].copy() for flag in flags}
        _, reward, terminated, truncated, info = env.step(next(policy))
        total += reward
        for event in info["events"]:
            assert set(event) == {"sensor", "target", "task", "time", "kind"}
            assert event["task"] in TASKS and event["kind"] in EVENT_KINDS
            assert info["time"] - env.dt - 1e-9 <= event["time"] <= info["time"] + 1e-9
            kinds.append(event["kind"])
            if event["kind"] == "first":
                firsts.add((event["target"], event["task"]))
        # The reward is the flags that became true this step, and the flags never go back.
        gained = sum(int(np.sum(info[f] & ~before[f])) for f in flags)
        assert reward == gained
        for flag in flags:
            assert np.all(info[flag] >= before[flag])
        done = terminated or truncated
    assert "reacquired" in kinds  # the policy made the model reacquire, as it should
    # Each target's task counts once, whichever camera did it first and however often again.
    assert total == len(firsts) == sum(int(info[f].sum()) for f in flags)
    assert total < len(kinds)


def test_step_before_reset_says_reset():
    env = SensorPointingEnv(targets=2)
    with pytest.raises(gymnasium.error.ResetNeeded, match=r"before reset\(\)"):
        env.step(np.zeros((1, 2), dtype=np.float32))
    with pytest.raises(gymnasium.error.ResetNeeded, match=r"before reset\(\)"):
        env.greedy_action()


def test_a_short_visit_is_kept_in_info_not_emitted():
    import warnings

    counts = []
    for seed in range(6):
        env = SensorPointingEnv(targets=3, duration=60.0, dt=2.0)
        env.reset(seed=seed)
        found, done, policy = [], False, _look_away_and_back(env)
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # any warning emitted fails
            while not done:
                _, _, terminated, truncated, info = env.step(next(policy))
                found += info["warnings"]
                done = terminated or truncated
        assert all("less than one step of 2 s" in message for message in found)
        counts.append(len(found))
    assert max(counts) == 1  # some episode had one (the look-away policy makes them), never more


def test_a_complex_or_misshapen_action_and_a_huge_environment_are_clear_errors():
    import numpy as np
    import pytest

    from targetacq.envs.pointing import MAX_TARGETS, SensorPointingEnv

    env = SensorPointingEnv()
    env.reset(seed=1)
    with pytest.raises(ValueError, match=r"action must be 2 real numbers .* got complex128"):
        env.step(np.array([[0.1 + 0.2j, 0.0]]))
    with pytest.raises(ValueError, match=r"action must be 2 real numbers .* shape \(3,\)"):
        env.step(np.zeros(3))
    with pytest.raises(ValueError, match=r"targets must be an integer in \[1, 10000\]"):
        SensorPointingEnv(targets=10**9)
    assert MAX_TARGETS == 10_000
    SensorPointingEnv(targets=12).reset(seed=0)  # within the limit: fine
