"""Train a PPO pointing policy with Stable-Baselines3; compare it with random and greedy play.

The environment is ``targetacq/SearchIdentify-v0`` (:class:`targetacq.envs.AcquisitionEnv`):
one camera on a platform flying east over six cued targets, a discrete action (look at target
j), the dense reward (the gain in the expected identification) and track observations. SB3's
PPO trains on the environment's native vector environment through a small SB3 ``VecEnv``
adapter (:class:`Sb3Vector`), with SB3's actor-critic whose networks are one MLP shared by the
targets (:class:`TrackPolicy`; ``--policy mlp`` for SB3's ``MlpPolicy`` over the flat
observation). Evaluation plays the trained policy (deterministic),
random targets, the environment's greedy policy (the nearest target not yet identified) and
the scripted prospect policy of ``examples/pointing_policies.py`` on the same seeded episodes,
with seeds disjoint from the training ones. It scores each episode by its dense return (what
PPO maximises), the count of acquisitions (detections, recognitions and identifications: the
sparse reward of ``SensorPointing-v0``) and the targets identified, and tests the trained
policy against each baseline (Welch's t-test and the Mann-Whitney U test, two-sided).

Run from a checkout (the ``train`` extra pulls PyTorch: ``pip install -e '.[rl,train]'``)::

    python benchmarks/train_ppo.py --out ppo-run

It writes ``ppo-run/results.json`` (settings, scores per episode, tests, times, versions),
``ppo-run/monitor.csv`` (SB3's log of the training episodes) and
``ppo-run/training_curve.png``. Training is measured, not tested: this script is not shipped
in the package, not run by ``make bench`` (``bench_*.py``) and not imported by the tests.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import time
from pathlib import Path
from typing import Any

import gymnasium
import numpy as np
import stable_baselines3
import torch
from scipy import stats
from stable_baselines3 import PPO
from stable_baselines3.common.policies import ActorCriticPolicy
from stable_baselines3.common.vec_env import VecEnv, VecMonitor
from torch import nn

import targetacq.envs  # noqa: F401  (registers the environments)
from targetacq.envs.acquisition import CAMERA_FEATURES, PLATFORM_FEATURES, TARGET_FEATURES
from targetacq.examples.pointing_policies import prospect_policy

ENV_ID = "targetacq/SearchIdentify-v0"
ENV_KWARGS: dict[str, Any] = {"action": "track", "reward": "dense", "targets": 6}
"""The environment's settings, for training and evaluation alike (the rest its defaults)."""

EVAL_SEED0 = 1_000_000
"""The first evaluation seed. Training episodes come from the generators seeded ``--seed``
to ``--seed + n_envs - 1`` (each one's episodes follow from its generator), so evaluation
seeds from here on are never training seeds."""

POLICIES = ("ppo", "random", "greedy", "prospect")
BASELINES = POLICIES[1:]
METRICS = ("acquisitions", "identified", "dense_return")


class Sb3Vector(VecEnv):
    """A Gymnasium vector environment (next-step autoreset) as an SB3 ``VecEnv``.

    SB3 expects an ended episode's first observation in the step that ends it (the final one
    in ``info["terminal_observation"]``); the environment gives it one step later, ignoring that
    step's action, and cannot reset some episodes alone. So an ended episode is reported as
    done with its final observation standing in for the first one, and the next step, which
    the environment spends resetting it, is a transition of reward 0 from that stand-in to the
    new episode's first observation: one spurious transition per episode (SB3's monitor logs
    121 steps for an episode of 120). Where every episode ends in the same step, all are reset
    at once and there is none (they start in step, but an episode that ends early, every target
    identified, puts its slot out of step for good).
    """

    def __init__(self, vector: gymnasium.vector.VectorEnv) -> None:
        self.vector = vector
        super().__init__(
            vector.num_envs, vector.single_observation_space, vector.single_action_space
        )
        self._actions: np.ndarray | None = None

    def reset(self) -> np.ndarray:
        seeds = None if self._seeds[0] is None else [int(s) for s in self._seeds]  # type: ignore[arg-type]
        obs, _ = self.vector.reset(seed=seeds)
        self._reset_seeds()
        return obs

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = np.asarray(actions)

    def step_wait(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[dict[str, Any]]]:
        assert self._actions is not None
        obs, reward, terminated, truncated, _ = self.vector.step(self._actions)
        done = terminated | truncated
        infos: list[dict[str, Any]] = [{} for _ in range(self.num_envs)]
        for i in np.flatnonzero(done):
            infos[i]["terminal_observation"] = obs[i].copy()
            infos[i]["TimeLimit.truncated"] = bool(truncated[i] and not terminated[i])
        if done.all():
            obs, _ = self.vector.reset()  # the generators go on: new episodes, not the same ones
        return obs, reward.astype(np.float32), done, infos

    def close(self) -> None:
        self.vector.close()

    def get_attr(self, attr_name: str, indices: Any = None) -> list[Any]:
        return [getattr(self.vector, attr_name)] * len(list(self._get_indices(indices)))

    def set_attr(self, attr_name: str, value: Any, indices: Any = None) -> None:
        raise NotImplementedError("Sb3Vector holds one vector environment")

    def env_method(self, method_name: str, *args: Any, indices: Any = None, **kwargs: Any) -> list:
        raise NotImplementedError("Sb3Vector holds one vector environment")

    def env_is_wrapped(self, wrapper_class: type, indices: Any = None) -> list[bool]:
        return [False] * len(list(self._get_indices(indices)))


class TrackScorer(nn.Module):
    """The policy's and the value's networks over track observations, shared across targets.

    Each target's features, with the platform's and the cameras' (the head), go through one
    MLP (the same weights for every target): the actor scores each target (its logit: the
    policy is the softmax over targets, so it does not depend on the order the targets are
    listed in), the critic pools the targets' embeddings (mean and max) with the head.
    """

    def __init__(self, head: int, targets: int, per_target: int, width: int) -> None:
        super().__init__()
        self.head, self.targets, self.per_target = head, targets, per_target
        self.latent_dim_pi, self.latent_dim_vf = targets, width

        def embedding() -> nn.Sequential:
            return nn.Sequential(
                nn.Linear(head + per_target, width), nn.Tanh(), nn.Linear(width, width), nn.Tanh()
            )

        self.actor, self.critic = embedding(), embedding()
        self.score = nn.Linear(width, 1)
        self.pool = nn.Sequential(nn.Linear(2 * width + head, width), nn.Tanh())

    def _embed(self, net: nn.Module, x: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        head = x[:, : self.head]
        tracks = x[:, self.head :].reshape(-1, self.targets, self.per_target)
        joined = torch.cat([head.unsqueeze(1).expand(-1, self.targets, -1), tracks], dim=-1)
        return head, net(joined)

    def forward_actor(self, x: torch.Tensor) -> torch.Tensor:
        return self.score(self._embed(self.actor, x)[1]).squeeze(-1)

    def forward_critic(self, x: torch.Tensor) -> torch.Tensor:
        head, z = self._embed(self.critic, x)
        return self.pool(torch.cat([z.mean(dim=1), z.amax(dim=1), head], dim=-1))

    def forward(self, x: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        return self.forward_actor(x), self.forward_critic(x)


class TrackPolicy(ActorCriticPolicy):
    """SB3's actor-critic policy with :class:`TrackScorer` as its networks: the actor's
    scores are the logits (no further layer), the rest is SB3's (orthogonal initialisation,
    the scores' layer at gain 0.01 as SB3 does its action layer)."""

    def __init__(self, *args: Any, layout: tuple[int, int, int], width: int = 64, **kw: Any):
        self.layout, self.width = layout, width
        super().__init__(*args, **kw)

    def _build_mlp_extractor(self) -> None:
        self.mlp_extractor = TrackScorer(*self.layout, self.width)

    def _build(self, lr_schedule: Any) -> None:
        super()._build(lr_schedule)
        self.action_net = nn.Identity()
        self.init_weights(self.mlp_extractor.score, gain=0.01)
        self.optimizer = self.optimizer_class(
            self.parameters(), lr=lr_schedule(1), **self.optimizer_kwargs
        )


def track_layout(cameras: int = 1) -> tuple[int, int, int]:
    """The observation's layout: (numbers before the targets', targets, numbers per target)."""
    head = PLATFORM_FEATURES + CAMERA_FEATURES * cameras
    return head, ENV_KWARGS["targets"], TARGET_FEATURES


def make_vector(num_envs: int) -> gymnasium.vector.VectorEnv:
    """The environment's native vector environment of ``num_envs`` episodes."""
    return gymnasium.make_vec(
        ENV_ID, num_envs=num_envs, vectorization_mode="vector_entry_point", **ENV_KWARGS
    )


def cpu_seconds() -> float:
    """CPU time of this process and its finished children [s] (user + system)."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def train(args: argparse.Namespace, out: Path) -> tuple[PPO, dict[str, Any]]:
    """Train PPO for ``args.steps`` environment steps; the model and its settings."""
    venv = VecMonitor(Sb3Vector(make_vector(args.n_envs)), filename=str(out / "monitor.csv"))
    hyper: dict[str, Any] = {
        "n_steps": args.n_steps,
        "batch_size": args.batch_size,
        "n_epochs": args.n_epochs,
        "gamma": args.gamma,
        "gae_lambda": args.gae_lambda,
        "ent_coef": args.ent_coef,
        "learning_rate": args.learning_rate,
        "clip_range": args.clip_range,
    }
    policy: Any
    if args.policy == "tracks":
        policy, kwargs = TrackPolicy, {"layout": track_layout(), "width": args.width}
    else:
        policy, kwargs = "MlpPolicy", {"net_arch": [args.width, args.width]}
    model = PPO(
        policy, venv, seed=args.seed, device="cpu", verbose=0, policy_kwargs=kwargs, **hyper
    )
    model.learn(total_timesteps=args.steps, progress_bar=False)
    venv.close()
    name = "TrackPolicy" if args.policy == "tracks" else "MlpPolicy"
    return model, {**hyper, "n_envs": args.n_envs, "policy": name, "policy_kwargs": kwargs}


def evaluate(policy: str, seeds: list[int], model: PPO | None) -> dict[str, np.ndarray]:
    """Play one episode per seed under ``policy``; each metric per episode.

    Episode i runs in the vector environment's slot i, reset with ``seeds[i]``: the same
    episode as ``gymnasium.make(ENV_ID).reset(seed=seeds[i])``. Its scores are taken at the
    step that ends it; later steps of that slot (a new episode) are ignored.
    """
    vector = make_vector(len(seeds))
    obs, info = vector.reset(seed=seeds)
    draws = [np.random.default_rng(seed) for seed in seeds]
    size = int(vector.single_action_space.n)  # type: ignore[attr-defined]
    going = np.ones(len(seeds), dtype=bool)
    scores = {metric: np.zeros(len(seeds)) for metric in METRICS}
    while going.any():
        if policy == "ppo":
            assert model is not None
            action, _ = model.predict(obs, deterministic=True)
        elif policy == "random":
            action = np.array([rng.integers(size) for rng in draws])
        elif policy == "greedy":
            action = vector.unwrapped.greedy_actions()  # type: ignore[attr-defined]
        else:
            action = prospect_policy(obs, ENV_KWARGS["targets"])
        obs, reward, terminated, truncated, info = vector.step(
            np.asarray(action).reshape(vector.action_space.shape)
        )
        scores["dense_return"] += np.where(going, reward, 0.0)
        ended = going & (terminated | truncated)
        for i in np.flatnonzero(ended):
            flags = [info[key][i] for key in ("detected", "recognised", "identified")]
            scores["acquisitions"][i] = sum(int(np.count_nonzero(f)) for f in flags)
            scores["identified"][i] = int(np.count_nonzero(flags[2]))
        going &= ~ended
    vector.close()
    return scores


def compare(trained: np.ndarray, other: np.ndarray) -> dict[str, float]:
    """Two-sided Welch t-test and Mann-Whitney U test of ``trained`` against ``other`` (the
    tests of record), and the Wilcoxon signed-rank test of their differences episode by
    episode (the same seeds: a paired test, for information), with the mean difference, its
    standard error and the episodes in which ``trained`` did better and worse."""
    welch = stats.ttest_ind(trained, other, equal_var=False)
    mwu = stats.mannwhitneyu(trained, other, alternative="two-sided")
    paired = stats.wilcoxon(trained, other, zero_method="zsplit")
    difference = trained - other
    return {
        "mean_difference": float(difference.mean()),
        "mean_difference_se": float(difference.std(ddof=1) / np.sqrt(difference.size)),
        "episodes_better": int(np.count_nonzero(difference > 0)),
        "episodes_worse": int(np.count_nonzero(difference < 0)),
        "welch_t": float(welch.statistic),
        "welch_p": float(welch.pvalue),
        "mannwhitney_u": float(mwu.statistic),
        "mannwhitney_p": float(mwu.pvalue),
        "wilcoxon_paired_p": float(paired.pvalue),
    }


def plot_curve(out: Path, baselines: dict[str, float], window: int = 200) -> None:
    """Training episodes' dense return against environment steps (SB3's monitor log), with
    the evaluation means of the baselines as lines."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import pandas as pd

    log = pd.read_csv(out / "monitor.csv", skiprows=1).sort_values("t")
    steps = log["l"].cumsum().to_numpy()
    fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
    ax.plot(steps, log["r"], ".", ms=1, alpha=0.15, color="0.6", label="training episode")
    mean = log["r"].rolling(window, min_periods=1).mean()
    ax.plot(steps, mean, color="C0", label=f"PPO, mean of {window} episodes")
    for k, (name, value) in enumerate(baselines.items()):
        ax.axhline(value, color=f"C{k + 1}", ls="--", label=f"{name} (evaluation mean)")
    ax.set_xlabel("environment steps")
    ax.set_ylabel("episode return (dense reward)")
    ax.legend(loc="lower right", fontsize="small")
    fig.savefig(out / "training_curve.png", dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> dict[str, Any]:
    """Train, evaluate, test and write the results (see the module docstring)."""
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--steps", type=int, default=600_000, help="training steps")
    parser.add_argument("--seed", type=int, default=0, help="training seed")
    parser.add_argument("--episodes", type=int, default=500, help="evaluation episodes")
    parser.add_argument("--out", type=Path, default=Path("ppo-run"), help="output folder")
    parser.add_argument("--threads", type=int, default=1, help="PyTorch threads")
    parser.add_argument("--n-envs", type=int, default=64, help="episodes stepped together")
    parser.add_argument("--n-steps", type=int, default=64, help="steps per env per rollout")
    parser.add_argument("--batch-size", type=int, default=1024)
    parser.add_argument("--n-epochs", type=int, default=10)
    parser.add_argument("--gamma", type=float, default=0.95)
    parser.add_argument("--gae-lambda", type=float, default=0.9)
    parser.add_argument("--ent-coef", type=float, default=0.003)
    parser.add_argument("--learning-rate", type=float, default=1e-3)
    parser.add_argument("--clip-range", type=float, default=0.2)
    parser.add_argument(
        "--policy",
        choices=("tracks", "mlp"),
        default="tracks",
        help="tracks: one scorer shared by the targets (TrackPolicy); mlp: SB3's MlpPolicy",
    )
    parser.add_argument("--width", type=int, default=64, help="hidden units per layer (2)")
    args = parser.parse_args(argv)
    torch.set_num_threads(args.threads)
    out = args.out
    out.mkdir(parents=True, exist_ok=True)

    wall, cpu = time.perf_counter(), cpu_seconds()
    model, hyper = train(args, out)
    train_wall, train_cpu = time.perf_counter() - wall, cpu_seconds() - cpu
    model.save(out / "ppo_model")

    seeds = list(range(EVAL_SEED0, EVAL_SEED0 + args.episodes))
    wall, cpu = time.perf_counter(), cpu_seconds()
    played = {policy: evaluate(policy, seeds, model) for policy in POLICIES}
    eval_wall, eval_cpu = time.perf_counter() - wall, cpu_seconds() - cpu

    scores = {
        metric: {
            policy: {
                "mean": float(played[policy][metric].mean()),
                "sd": float(played[policy][metric].std(ddof=1)),
                "per_episode": played[policy][metric].tolist(),
            }
            for policy in POLICIES
        }
        for metric in METRICS
    }
    tests = {
        metric: {
            f"ppo_vs_{other}": compare(played["ppo"][metric], played[other][metric])
            for other in BASELINES
        }
        for metric in METRICS
    }
    results = {
        "env": {"id": ENV_ID, "kwargs": ENV_KWARGS},
        "training": {
            "steps": args.steps,
            "seed": args.seed,
            "seeds": [args.seed, args.seed + args.n_envs - 1],
            "wall_s": train_wall,
            "cpu_s": train_cpu,
            "torch_threads": args.threads,
            **hyper,
        },
        "evaluation": {
            "episodes": args.episodes,
            "seeds": [seeds[0], seeds[-1]],
            "ppo": "deterministic (the most probable action)",
            "tests": "two-sided Welch t-test and Mann-Whitney U, PPO against each baseline "
            "(and the paired Wilcoxon signed-rank test, for information)",
            "wall_s": eval_wall,
            "cpu_s": eval_cpu,
        },
        "scores": scores,
        "tests": tests,
        "machine": {"cpus": os.cpu_count(), "platform": platform.platform()},
        "versions": {
            "python": platform.python_version(),
            "torch": torch.__version__,
            "stable_baselines3": stable_baselines3.__version__,
            "gymnasium": gymnasium.__version__,
            "numpy": np.__version__,
        },
    }
    (out / "results.json").write_text(json.dumps(results, indent=1) + "\n", encoding="utf-8")
    plot_curve(out, {p: scores["dense_return"][p]["mean"] for p in BASELINES})
    for metric in METRICS:
        line = ", ".join(f"{p} {s['mean']:.2f} ± {s['sd']:.2f}" for p, s in scores[metric].items())
        versus = "; ".join(
            f"vs {other} p = {t['welch_p']:.2g} (Welch), {t['mannwhitney_p']:.2g} (MWU)"
            for other, t in ((o, tests[metric][f"ppo_vs_{o}"]) for o in BASELINES)
        )
        print(f"{metric}: {line}\n  PPO {versus}")
    print(f"training: {args.steps} steps, {train_wall:.0f} s wall, {train_cpu:.0f} s CPU")
    return results


if __name__ == "__main__":
    main()
