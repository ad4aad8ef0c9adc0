"""Scripted pointing policies against random pointing, over seeded episodes.

Two environments (needs the ``rl`` extra: ``pip install targetacq[rl]``):

``targetacq/SensorPointing-v0`` (:func:`compare`)
    the first environment (absolute pointing, a reward counting new detections, recognitions
    and identifications): the greedy policy points the camera at the nearest target it has not
    identified yet (``SensorPointingEnv.greedy_action``), the random policy samples the action
    space; both play the same 20 episodes (seeds 0-19).
``targetacq/SearchIdentify-v0`` (:func:`compare_tasks`)
    the search task (``track`` action: look at target j; ``dense`` reward: the gain in the
    expected identification), 50 episodes at once in the native vector environment (seeds
    1000-1049): random tracks, the greedy nearest-unidentified track
    (``AcquisitionVectorEnv.greedy_actions``; it stays on a target it can never identify), and
    a scripted policy that reads the observation: among the targets not yet identified, the one
    whose prospect of identification, less what is already expected of it, is the largest.

Run: ``python examples/pointing_policies.py``.
"""

from __future__ import annotations

import gymnasium
import numpy as np

from targetacq.envs import (  # registers the environments
    AcquisitionVectorEnv,
    SensorPointingEnv,
)
from targetacq.envs.acquisition import CAMERA_FEATURES, PLATFORM_FEATURES, TARGET_FEATURES


def play(policy: str, seed: int) -> float:
    """Total reward of one episode of SensorPointing-v0 under a policy ("greedy" or "random")."""
    env = gymnasium.make("targetacq/SensorPointing-v0")
    env.reset(seed=seed)
    env.action_space.seed(seed)
    pointing: SensorPointingEnv = env.unwrapped  # type: ignore[assignment]
    total, done = 0.0, False
    while not done:
        greedy = policy == "greedy"
        action = pointing.greedy_action() if greedy else env.action_space.sample()
        _, reward, terminated, truncated, _ = env.step(action)
        total += float(reward)
        done = terminated or truncated
    return total


def compare(episodes: int = 20) -> dict[str, float]:
    """Mean total reward per episode of each policy over the seeded episodes."""
    return {
        policy: float(np.mean([play(policy, seed) for seed in range(episodes)]))
        for policy in ("greedy", "random")
    }


def prospect_policy(observations: np.ndarray, targets: int) -> np.ndarray:
    """Per environment, the unidentified target with the most left to win: its prospect of
    identification (were the camera to look at it now) less its expected identification."""
    blocks = observations[:, PLATFORM_FEATURES + CAMERA_FEATURES :].reshape(
        len(observations), targets, TARGET_FEATURES
    )
    identified, prospect, expected = blocks[..., 6], blocks[..., 9], blocks[..., 10]
    return np.where(identified > 0, -1.0, prospect - expected).argmax(axis=1)


def compare_tasks(episodes: int = 50, targets: int = 6) -> dict[str, tuple[float, float]]:
    """Mean and standard deviation of the episode's dense reward for each policy, over the
    same seeded episodes of SearchIdentify-v0."""
    scores = {}
    for policy in ("random", "greedy", "prospect"):
        envs = AcquisitionVectorEnv(episodes, targets=targets)
        observations, _ = envs.reset(seed=1000)
        envs.action_space.seed(0)
        total = np.zeros(episodes)
        ended = np.zeros(episodes, dtype=bool)
        while not ended.all():
            if policy == "random":
                actions = envs.action_space.sample()
            elif policy == "greedy":
                actions = envs.greedy_actions()
            else:
                actions = prospect_policy(observations, targets)
            observations, reward, terminated, truncated, _ = envs.step(actions)
            total += np.where(ended, 0.0, reward)
            ended |= terminated | truncated
        scores[policy] = (float(total.mean()), float(total.std()))
    return scores


if __name__ == "__main__":
    for policy, score in compare().items():
        print(f"{policy:>8}: {score:.2f} acquisitions per episode (SensorPointing-v0, 20 episodes)")
    for policy, (mean, spread) in compare_tasks().items():
        print(
            f"{policy:>8}: {mean:.2f} ± {spread:.2f} dense reward (SearchIdentify-v0, 50 episodes)"
        )
