"""Environment steps per second: the single environments against the native vector one.

``targetacq/SearchIdentify-v0`` (one camera, six targets, 120 s episodes of 1 s steps, the
``track`` action, the ``dense`` reward) is stepped with random actions drawn beforehand, for
``STEPS`` steps after a reset (not timed: it compiles every environment's first scene at
once): more than one episode, so the resets that follow (and the compiling of the new
episodes' scenes) are in the figures. Measured in each run, in this order:

- ``SensorPointingEnv`` (``targetacq/SensorPointing-v0``: a :class:`targetacq.Simulation` per
  environment, absolute action), the reference of the ratios;
- ``AcquisitionEnv`` (the single environment of the task);
- ``AcquisitionVectorEnv`` with 1, 64 and 256 environments (one array pass per step).

Environment steps per second are ``num_envs × steps`` over the time taken, by CPU time
(``time.process_time``: one process, one thread, what the steps cost the core they run on) and
by wall time (``time.perf_counter``). One JSON line per environment: the medians over the runs
(default 3), the spread (minimum, median, maximum) and the ratio of its CPU rate to the
``SensorPointingEnv``'s of the same runs.

Usage::

    OMP_NUM_THREADS=1 python benchmarks/bench_env.py [--runs 3] [--steps 150]
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
from collections.abc import Callable

import numpy as np

import _timing  # noqa: F401 - one thread for NumPy, set before it loads
from targetacq.envs import AcquisitionEnv, AcquisitionVectorEnv, SensorPointingEnv

TARGETS = 6
STEPS = 150
SIZES = (1, 64, 256)


def _single(env: object, steps: int, actions: np.ndarray) -> Callable[[], Callable[[], None]]:
    def start() -> Callable[[], None]:
        env.reset(seed=0)  # type: ignore[attr-defined]
        return run

    def run() -> None:
        for k in range(steps):
            _, _, terminated, truncated, _ = env.step(actions[k])  # type: ignore[attr-defined]
            if terminated or truncated:
                env.reset()  # type: ignore[attr-defined]

    return start


def _vector(n: int, steps: int, actions: np.ndarray) -> Callable[[], Callable[[], None]]:
    envs = AcquisitionVectorEnv(n, targets=TARGETS)

    def start() -> Callable[[], None]:
        envs.reset(seed=0)
        return run

    def run() -> None:
        for k in range(steps):
            envs.step(actions[k, :n])

    return start


def _timed(run: Callable[[], None]) -> tuple[float, float]:
    cpu, wall = time.process_time(), time.perf_counter()
    run()
    return time.process_time() - cpu, time.perf_counter() - wall


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--steps", type=int, default=STEPS)
    args = parser.parse_args()
    steps = args.steps
    rng = np.random.default_rng(0)
    track = rng.integers(0, TARGETS, (steps, max(SIZES)))
    absolute = rng.uniform(-1, 1, (steps, 1, 2)).astype(np.float32)
    cases: list[tuple[str, int, Callable[[], Callable[[], None]]]] = [
        ("SensorPointingEnv", 1, _single(SensorPointingEnv(targets=TARGETS), steps, absolute)),
        ("AcquisitionEnv", 1, _single(AcquisitionEnv(targets=TARGETS), steps, track[:, 0])),
    ]
    cases += [("AcquisitionVectorEnv", n, _vector(n, steps, track)) for n in SIZES]
    rates: dict[tuple[str, int], list[tuple[float, float]]] = {}
    for _ in range(args.runs):
        for name, n, start in cases:
            cpu, wall = _timed(start())
            rates.setdefault((name, n), []).append((n * steps / cpu, n * steps / wall))
    reference = statistics.median(cpu for cpu, _ in rates[("SensorPointingEnv", 1)])
    for (name, n), found in rates.items():
        cpu_rates = sorted(cpu for cpu, _ in found)
        wall_rates = sorted(wall for _, wall in found)
        cpu = statistics.median(cpu_rates)
        print(
            json.dumps(
                {
                    "env": name,
                    "num_envs": n,
                    "cameras": 1,
                    "targets": TARGETS,
                    "steps": steps,
                    "runs": args.runs,
                    "steps_per_cpu_s": round(cpu),
                    "steps_per_wall_s": round(statistics.median(wall_rates)),
                    "cpu_spread": [round(cpu_rates[0]), round(cpu), round(cpu_rates[-1])],
                    "ratio_to_sensor_pointing_cpu": round(cpu / reference, 2),
                }
            )
        )


if __name__ == "__main__":
    main()
