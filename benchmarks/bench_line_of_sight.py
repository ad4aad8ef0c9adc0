"""Lines of sight over a 1024 × 1024 elevation grid (:func:`targetacq.line_of_sight`): pairs per
CPU second, numba loops against the NumPy ones, in one run.

The terrain is rough, seeded relief (a sum of random sine waves of 300 m to 10 km and 1 m noise,
±60 m; 30 m posts, 30.7 km square). Cases:

- ``random``: observers 10 m above the ground and 3 m targets on it, anywhere on the grid (the
  mean track crosses about 540 posts: the worst case for the profile method);
- ``step``: the pairs of one step of 20 sensors × 500 targets (10 000 pairs), the targets within
  5 km of the sensors (a sensor's reach).

For each case and method (``numba`` where installed, ``numpy``) the run takes the best of
:data:`_timing.REPEATS` calls (the first numba call, which compiles, is not timed): CPU time
(``time.process_time``) beside wall time, pairs per CPU second, and the share of pairs fully
hidden (those stop early in numba). Runs (default 3) repeat everything; the JSON line per case and
method gives the median over the runs and the spread (min, median, max), and the numba/numpy
ratio of the run's medians.

Usage::

    python benchmarks/bench_line_of_sight.py [--runs 3] [--pairs 200000]
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import statistics
import time

import numpy as np

from _timing import REPEATS
from targetacq.physics.line_of_sight import ElevationModel, line_of_sight

SIDE = 1024
SPACING = 30.0


def terrain(seed: int = 1) -> ElevationModel:
    """Rough relief: random sine waves of 300 m to 10 km wavelength and 1 m noise, ±60 m."""
    rng = np.random.default_rng(seed)
    x = np.arange(SIDE) * SPACING
    east, north = np.meshgrid(x, x)
    grid = rng.normal(0.0, 1.0, (SIDE, SIDE))
    for wavelength in rng.uniform(300.0, 10_000.0, 24):
        angle = rng.uniform(0.0, np.pi)
        phase = rng.uniform(0.0, 2 * np.pi)
        along = east * np.cos(angle) + north * np.sin(angle)
        grid += 8.0 * np.sqrt(wavelength / 1000.0) * np.sin(2 * np.pi * along / wavelength + phase)
    grid *= 60.0 / np.abs(grid).max()
    return ElevationModel(grid, SPACING, (0.0, 0.0))


def pairs_random(model: ElevationModel, count: int, seed: int = 2) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(seed)
    top = (SIDE - 1) * SPACING
    o = rng.uniform(0.0, top, (count, 2))
    t = rng.uniform(0.0, top, (count, 2))
    observers = np.column_stack([o, model.height_at(o[:, 0], o[:, 1]) + 10.0])
    targets = np.column_stack([t, model.height_at(t[:, 0], t[:, 1])])
    return observers, targets, np.full(count, 3.0)


def pairs_step(model: ElevationModel, seed: int = 3) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(seed)
    top = (SIDE - 1) * SPACING
    s = rng.uniform(5_000.0, top - 5_000.0, (20, 2))
    which = np.arange(500) % 20
    radius, angle = rng.uniform(200.0, 5_000.0, 500), rng.uniform(0.0, 2 * np.pi, 500)
    t = s[which] + np.column_stack([radius * np.cos(angle), radius * np.sin(angle)])
    sensors = np.column_stack([s, model.height_at(s[:, 0], s[:, 1]) + 10.0])
    targets = np.column_stack([t, model.height_at(t[:, 0], t[:, 1])])
    return sensors[:, None, :], targets[None, :, :], np.full((1, 500), 3.0)


def measure(model: ElevationModel, case: tuple[np.ndarray, ...], method: str) -> dict[str, float]:
    observers, targets, heights = case
    line_of_sight(model, None, None, observers, targets, heights, method=method)  # compile
    best_cpu, best_wall, out = np.inf, np.inf, None
    for _ in range(REPEATS if method == "numba" else 2):
        wall, cpu = time.perf_counter(), time.process_time()
        out = line_of_sight(model, None, None, observers, targets, heights, method=method)
        best_cpu = min(best_cpu, time.process_time() - cpu)
        best_wall = min(best_wall, time.perf_counter() - wall)
    values = np.asarray(out)
    return {
        "cpu": best_cpu,
        "wall": best_wall,
        "pairs": float(values.size),
        "hidden": float(np.mean(values == 0.0)),
        "partial": float(np.mean((values > 0.0) & (values < 1.0))),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--pairs", type=int, default=200_000, help="pairs of the random case")
    args = parser.parse_args()
    model = terrain()
    cases = {"random": pairs_random(model, args.pairs), "step": pairs_step(model)}
    methods = ["numpy"]
    if importlib.util.find_spec("numba") is not None:
        methods.insert(0, "numba")
    found: dict[tuple[str, str], list[dict[str, float]]] = {}
    for _ in range(args.runs):
        for name, case in cases.items():
            for method in methods:
                small = name == "random" and method == "numpy"  # NumPy: a tenth of the pairs
                part = tuple(a[: args.pairs // 10] for a in case) if small else case
                found.setdefault((name, method), []).append(measure(model, part, method))
    for (name, method), runs in found.items():
        rates = [r["pairs"] / r["cpu"] for r in runs]
        numpy_runs = found.get((name, "numpy"))
        ratio = None
        if method == "numba" and numpy_runs:
            ratio = statistics.median(rates) / statistics.median(
                [r["pairs"] / r["cpu"] for r in numpy_runs]
            )
        print(
            json.dumps(
                {
                    "benchmark": "line_of_sight: visible fractions over a 1024 x 1024 grid",
                    "case": name,
                    "method": method,
                    "pairs": runs[0]["pairs"],
                    "cpu_seconds": statistics.median(r["cpu"] for r in runs),
                    "wall_seconds": statistics.median(r["wall"] for r in runs),
                    "pairs_per_cpu_second": statistics.median(rates),
                    "pairs_per_cpu_second_spread": [
                        min(rates),
                        statistics.median(rates),
                        max(rates),
                    ],
                    "speedup_over_numpy": ratio,
                    "hidden_fraction": runs[0]["hidden"],
                    "partial_fraction": runs[0]["partial"],
                    "runs": len(runs),
                }
            ),
            flush=True,
        )


if __name__ == "__main__":
    main()
