"""The task environments: registry, actions, rewards, observations, the vector environment."""

import math

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

from targetacq.envs import (  # noqa: E402
    TASKS,
    AcquisitionEnv,
    AcquisitionVectorEnv,
    SensorPointingEnv,
)
from targetacq.envs.acquisition import CAMERA_FEATURES, PLATFORM_FEATURES, TARGET_FEATURES  # noqa: E402

SMALL = {"targets": 3, "duration": 12.0}
# A small area, low: targets that can be identified within a short episode.
NEAR = {"altitude": 400.0, "half_width": 800.0, "speed": 10.0}


def _target_block(obs, n_cameras, j):
    start = PLATFORM_FEATURES + CAMERA_FEATURES * n_cameras + TARGET_FEATURES * j
    return obs[..., start : start + TARGET_FEATURES]


@pytest.mark.parametrize("task", list(TASKS))
def test_each_task_is_registered_and_passes_the_checker(task):
    from gymnasium.utils.env_checker import check_env

    env = gymnasium.make(TASKS[task].gym_id, **SMALL)
    check_env(env.unwrapped, skip_render_check=True)
    vec = gymnasium.make_vec(
        TASKS[task].gym_id, num_envs=3, vectorization_mode="vector_entry_point", **SMALL
    )
    assert isinstance(vec.unwrapped, AcquisitionVectorEnv)
    obs, _ = vec.reset(seed=0)
    assert vec.observation_space.contains(obs)


def test_sensor_pointing_keeps_its_single_env_and_gains_a_vector_entry():
    env = gymnasium.make("targetacq/SensorPointing-v0", targets=2, duration=5.0)
    assert isinstance(env.unwrapped, SensorPointingEnv)
    vec = gymnasium.make_vec(
        "targetacq/SensorPointing-v0",
        num_envs=2,
        vectorization_mode="vector_entry_point",
        targets=2,
        duration=5.0,
        altitude=1000.0,
    )
    assert vec.unwrapped.options.action == "absolute"
    assert vec.unwrapped.options.reward == "sparse"
    assert vec.unwrapped.options.scene.altitude == 1000.0
    assert vec.single_action_space.shape == (1, 2)


@pytest.mark.parametrize(
    ("task", "action"), [(t, a) for t, task in TASKS.items() for a in task.actions]
)
@pytest.mark.parametrize("reward", ["sparse", "dense"])
def test_every_task_action_and_reward_runs(task, action, reward):
    env = AcquisitionEnv(task=task, action=action, reward=reward, cameras=2, **SMALL)
    obs, _ = env.reset(seed=2)
    assert obs.shape == (PLATFORM_FEATURES + 2 * CAMERA_FEATURES + 3 * TARGET_FEATURES,)
    env.action_space.seed(0)
    for k in range(12):
        action_ = env.greedy_action() if k % 2 else env.action_space.sample()
        obs, r, terminated, truncated, _ = env.step(action_)
        assert env.observation_space.contains(obs)
        assert r >= 0.0
        if reward == "sparse":
            assert r == int(r)
        if terminated or truncated:
            break
    assert truncated or terminated


def test_bad_options_name_the_option_and_the_choices():
    with pytest.raises(
        ValueError,
        match="unknown task 'serch' \\(did you mean 'search'\\?\\); valid: search, route, zoom",
    ):
        AcquisitionEnv(task="serch")
    with pytest.raises(ValueError, match=r"unknown action 'tracks'.*valid: track, sector"):
        AcquisitionEnv(action="tracks")
    with pytest.raises(
        ValueError, match=r"action 'relative' is not one of task 'zoom'.*track, sector"
    ):
        AcquisitionEnv(task="zoom", action="relative")
    with pytest.raises(ValueError, match="unknown reward 'shaped'; valid: sparse, dense"):
        AcquisitionEnv(reward="shaped")
    with pytest.raises(ValueError, match="scene: unknown key 'height'; valid keys: altitude"):
        AcquisitionEnv(scene={"height": 3.0})
    with pytest.raises(ValueError, match="num_envs must be an integer >= 1"):
        AcquisitionVectorEnv(0)
    with pytest.raises(ValueError, match="chunk must be an integer >= 1"):
        AcquisitionVectorEnv(2, chunk=0)
    env = AcquisitionEnv(**SMALL)
    with pytest.raises(gymnasium.error.ResetNeeded):
        env.step(0)
    env.reset(seed=0)
    with pytest.raises(ValueError, match="action must be in Discrete\\(3\\)"):
        env.step(3)


def test_the_track_observation_holds_positions_flags_and_prospects():
    env = AcquisitionEnv(targets=4, duration=10.0, scene=NEAR)
    obs, _ = env.reset(seed=5)
    legacy = SensorPointingEnv(targets=4, duration=10.0, **NEAR)
    legacy_obs, _ = legacy.reset(seed=5)  # the same draws: the same layout
    legacy_targets = legacy_obs[3 + 2 :].reshape(4, 6)[:, :3]
    platform = np.array([-NEAR["half_width"], 0.0, NEAR["altitude"]])
    for j in range(4):
        block = _target_block(obs, 1, j)
        np.testing.assert_allclose(block[:3], legacy_targets[j], rtol=1e-6)
        assert block[3] == pytest.approx(np.linalg.norm(block[:3]), rel=1e-6)
        # The prospect: what the reference Simulation gives a camera pointed at the target.
        offset = legacy_targets[j] * NEAR["half_width"]
        pointing = np.array(
            [[math.atan2(offset[0], offset[1]), math.atan2(-offset[2], math.hypot(*offset[:2]))]]
        )
        p = legacy._sim.probabilities(
            0.0, platform[None], legacy._targets, sensor_pointing=pointing
        )
        expected = [p.detection[0, j], p.recognition[0, j], p.identification[0, j]]
        np.testing.assert_allclose(block[7:10], expected, rtol=1e-5, atol=1e-7)


def test_greedy_track_is_the_nearest_unidentified():
    env = AcquisitionEnv(targets=5, duration=60.0, scene=NEAR)
    obs, _ = env.reset(seed=3)
    for _ in range(60):
        blocks = np.stack([_target_block(obs, 1, j) for j in range(5)])
        distance = np.where(blocks[:, 6] > 0, np.inf, blocks[:, 3])
        if np.isinf(distance).all():
            distance = blocks[:, 3]
        assert env.greedy_action() == int(np.argmin(distance))
        obs, _, terminated, truncated, _ = env.step(env.greedy_action())
        if terminated or truncated:
            break


def _run_vector(envs, steps, seed, pick):
    obs, _ = envs.reset(seed=seed)
    out = [(obs, None, None, None)]
    for k in range(steps):
        obs, r, te, tr, _ = envs.step(pick(k))
        out.append((obs, r, te, tr))
    return out


def test_vector_env_i_is_the_single_env_seeded_s_plus_i_across_autoresets():
    n, seed = 5, 11
    vec = AcquisitionVectorEnv(n, chunk=2, targets=4, duration=15.0, scene=NEAR)
    singles = [AcquisitionEnv(targets=4, duration=15.0, scene=NEAR) for _ in range(n)]
    actions = np.random.default_rng(0).integers(0, 4, (40, n))
    trace = _run_vector(vec, 40, seed, lambda k: actions[k])
    ended = np.zeros(n, dtype=bool)
    rewarded = 0.0
    for i, env in enumerate(singles):
        obs, _ = env.reset(seed=seed + i)
        np.testing.assert_array_equal(trace[0][0][i], obs)
    for k in range(40):
        for i, env in enumerate(singles):
            if ended[i]:
                obs, _ = env.reset()
                r, te, tr = 0.0, False, False
            else:
                obs, r, te, tr, _ = env.step(int(actions[k, i]))
            v_obs, v_r, v_te, v_tr = trace[k + 1]
            np.testing.assert_array_equal(v_obs[i], obs)
            assert (v_r[i], v_te[i], v_tr[i]) == (r, te, tr)
            rewarded += r
        ended = trace[k + 1][2] | trace[k + 1][3]
    assert rewarded > 0  # something happened to compare


def test_vector_seeding_is_deterministic_and_autoreset_is_next_step():
    from gymnasium.vector import AutoresetMode

    vec = AcquisitionVectorEnv(3, targets=2, duration=3.0)
    assert vec.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP
    a = _run_vector(vec, 7, 4, lambda k: np.zeros(3, dtype=np.int64))
    b = _run_vector(vec, 7, 4, lambda k: np.zeros(3, dtype=np.int64))
    for x, y in zip(a, b, strict=True):
        for u, v in zip(x, y, strict=True):
            np.testing.assert_array_equal(u, v)
    # Three steps of 1 s end every episode; the fourth step resets them (reward 0, no flags,
    # time 0 in the observation), the seventh ends them again.
    assert a[3][3].all() and not a[3][2].any()
    assert not a[4][2].any() and not a[4][3].any() and (a[4][1] == 0).all()
    assert (a[4][0][:, 5] == 0).all()  # time over duration
    assert a[7][3].all()
    for obs, *_ in a:
        assert vec.observation_space.contains(obs)
    c = _run_vector(vec, 1, 5, lambda k: np.zeros(3, dtype=np.int64))
    assert not np.array_equal(a[0][0], c[0][0])


def test_dense_reward_is_nonnegative_and_sums_to_at_most_the_targets():
    vec = AcquisitionVectorEnv(16, targets=4, duration=40.0, scene=NEAR)
    vec.reset(seed=1)
    total, largest = np.zeros(16), 0.0
    for _ in range(60):
        _, r, te, tr, info = vec.step(vec.greedy_actions())
        assert (r >= 0).all()
        total += r
        assert (total <= 4 + 1e-9).all()  # within an episode
        ended = te | tr
        # The potential that the reward is the gain of: its sum since the episode's start.
        np.testing.assert_allclose(total, info["expected_identified"].sum(axis=1), atol=1e-9)
        largest = max(largest, total[ended].max(initial=0.0))
        total[ended] = 0.0  # the next step starts a new episode
    assert largest > 3.0  # identifications happened: the bound was tested


def _identified_fraction(dither, seeds=128, steps=30):
    """Fraction of targets identified after ``steps`` looking at the nearest one, and with
    ``dither`` every other step looking the opposite way instead."""
    vec = AcquisitionVectorEnv(
        seeds, chunk=32, action="absolute", targets=3, duration=60.0, scene=NEAR
    )
    vec.reset(seed=100)
    expected = np.zeros(seeds)
    for k in range(steps):
        action = vec.greedy_actions()
        if dither and k % 2:
            action[..., 0] = np.where(action[..., 0] > 0, action[..., 0] - 1, action[..., 0] + 1)
        _, _, _, _, info = vec.step(action)
        expected = info["expected_identified"].sum(axis=1)
    return info["identified"].mean(), expected.mean()


def test_looking_away_and_back_does_not_raise_the_identifications():
    staying, staying_expected = _identified_fraction(False)
    dithering, dithering_expected = _identified_fraction(True)
    n = 128 * 3
    spread = math.sqrt(staying * (1 - staying) / n + dithering * (1 - dithering) / n)
    assert staying > 0.05  # the scene identifies targets: the comparison can fail
    assert dithering <= staying + 3 * spread
    assert dithering_expected <= staying_expected + 1e-9


def test_a_scene_with_a_cloud_keeps_the_law_and_the_equivalence():
    # A cloud sits at a place: the environments then evaluate each episode at its own place
    # (chunks of episodes) instead of moving the targets to one camera position.
    cloud = {"clouds": [{"center": (-600.0, 0.0, 200.0), "radius": 300.0, "extinction": 0.01}]}
    scene = {**NEAR, "scenario_overrides": {"atmosphere": cloud}}
    env = AcquisitionEnv(targets=4, duration=10.0, scene=scene)
    obs, _ = env.reset(seed=8)
    legacy = SensorPointingEnv(targets=4, duration=10.0, **scene)
    legacy.reset(seed=8)
    platform = np.array([[-NEAR["half_width"], 0.0, NEAR["altitude"]]])
    for j in range(4):
        offset = legacy._targets[j] - platform[0]
        pointing = np.array(
            [[math.atan2(offset[0], offset[1]), math.atan2(-offset[2], math.hypot(*offset[:2]))]]
        )
        p = legacy._sim.probabilities(0.0, platform, legacy._targets, sensor_pointing=pointing)
        block = _target_block(obs, 1, j)
        np.testing.assert_allclose(block[7], p.detection[0, j], rtol=1e-5, atol=1e-7)
    vec = AcquisitionVectorEnv(3, chunk=2, targets=4, duration=10.0, scene=scene)
    trace = _run_vector(vec, 12, 8, lambda k: np.full(3, k % 4))
    single = AcquisitionEnv(targets=4, duration=10.0, scene=scene)
    obs, _ = single.reset(seed=10)
    np.testing.assert_array_equal(trace[0][0][2], obs)
    for k in range(9):
        obs, r, *_ = single.step(k % 4)
        np.testing.assert_array_equal(trace[k + 1][0][2], obs)
        assert trace[k + 1][1][2] == r


def test_the_example_prospect_policy_skips_identified_and_hopeless_targets():
    import runpy
    from pathlib import Path

    example = Path(__file__).parents[2] / "examples" / "pointing_policies.py"
    policy = runpy.run_path(str(example), run_name="not_main")["prospect_policy"]
    obs = np.zeros((1, PLATFORM_FEATURES + CAMERA_FEATURES + 3 * TARGET_FEATURES), np.float32)
    blocks = obs[:, PLATFORM_FEATURES + CAMERA_FEATURES :].reshape(1, 3, TARGET_FEATURES)
    blocks[0, :, 9] = [0.9, 0.0, 0.5]  # prospects of identification
    blocks[0, 0, 6] = 1.0  # the first is identified; the second is hopeless
    assert policy(obs, 3).tolist() == [2]


def test_reset_options_scene_units_and_bad_actions_are_named():
    import gymnasium

    env = gymnasium.make("targetacq/SearchIdentify-v0")
    with pytest.raises(ValueError, match=r"takes no reset options, got \{'bogus': 1\}"):
        env.reset(seed=0, options={"bogus": 1})
    env.reset(seed=0)
    with pytest.raises(ValueError, match=r"must be in Discrete\(6\), got 6 "):
        env.step(np.int64(6))
    with pytest.raises(ValueError, match=r"altitude must be a number of m \(SI"):
        gymnasium.make("targetacq/SearchIdentify-v0", scene={"altitude": "1500 m"})
