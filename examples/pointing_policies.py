"""A scripted greedy pointing policy against random pointing, over 20 seeded episodes.

The greedy policy points the camera at the nearest target it has not identified yet
(``SensorPointingEnv.greedy_action``); the random policy samples the action space. Both play the
same 20 episodes (seeds 0-19). Run: ``python examples/pointing_policies.py`` (needs the ``rl``
extra: ``pip install targetacq[rl]``).
"""

from __future__ import annotations

import gymnasium
import numpy as np

from targetacq.envs import SensorPointingEnv  # registers targetacq/SensorPointing-v0


def play(policy: str, seed: int) -> float:
    """Total reward of one episode under a policy ("greedy" or "random")."""
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


if __name__ == "__main__":
    scores = compare()
    for policy, score in scores.items():
        print(f"{policy:>7}: {score:.2f} acquisitions per episode (mean of 20 seeded episodes)")
