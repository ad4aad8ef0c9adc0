"""The cost of uncertainty bands: ``dri --uncertainty`` against the nominal ``dri``.

One range case (one sensor-target pair), three probabilities (0.5, 0.8, 0.95), in clear air
(the closed form) and in haze with a sensor NETD (the vectorised bisection), through
:func:`targetacq.run.uncertainty.uncertainty_ranges` with ``M`` samples (default 100, 500 and
2,000) against the nominal solve (:func:`targetacq.core.ranges.case_ranges`) in the same run;
and, for the first ``M``, the samples solved one at a time (a Python loop over the solver, what
the one array pass replaces), checked equal to the array pass (≤ 1e-9 relative).

Each case runs ``--runs`` times (default 3); wall (``perf_counter``) and CPU (``process_time``)
of every run and the best are printed; the ratios are of the best CPU times of the same run.
Throughput: samples × pairs per second (one pair here), CPU. One JSON object per line.

Arguments: ``--runs N``, ``--samples 100,500,2000``.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time
from collections.abc import Callable
from typing import Any

import numpy as np

import _timing  # noqa: F401  (single-threaded BLAS/OpenMP, before NumPy does work)
from targetacq.core.cases import RangeCase
from targetacq.core.ranges import case_ranges
from targetacq.run import uncertainty as unc
from targetacq.run.uncertainty import Uncertainty, uncertainty_ranges

PROBABILITIES = np.array([0.5, 0.8, 0.95])
CASES = {
    "clear": (RangeCase(2.3, 2.27e-4), {}),
    "haze+netd": (
        RangeCase(2.3, 2.27e-4, extinction=0.4e-3, contrast=2.0, noise_equivalent_contrast=0.05),
        {"netd_spread": 0.1, "extinction_spread": 0.2},
    ),
}


def timed(function: Callable[[], Any], runs: int) -> tuple[Any, list[float], list[float]]:
    walls, cpus, result = [], [], None
    for _ in range(runs):
        wall, cpu = time.perf_counter(), time.process_time()
        result = function()
        walls.append(time.perf_counter() - wall)
        cpus.append(time.process_time() - cpu)
    return result, walls, cpus


def one_at_a_time(case: RangeCase, u: Uncertainty) -> np.ndarray:
    """(M, n_p) detection ranges, each sample's case solved alone (the reference loop)."""
    sampled = unc._sampled_case(case, u)
    rows = []
    for i in range(u.samples):
        changes = {
            f.name: value[i, 0] if isinstance(value, np.ndarray) else value
            for f in dataclasses.fields(RangeCase)
            if (value := getattr(sampled, f.name)) is not getattr(case, f.name)
        }
        alone = dataclasses.replace(case, **changes)
        rows.append(np.asarray(case_ranges(alone, PROBABILITIES)["detection"], dtype=float))
    return np.stack(rows)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--samples", default="100,500,2000")
    args = parser.parse_args()
    counts = [int(m) for m in args.samples.split(",")]
    for label, (case, spreads) in CASES.items():
        case_ranges(case, PROBABILITIES)  # warm
        _, wall0, cpu0 = timed(lambda case=case: case_ranges(case, PROBABILITIES), args.runs)
        print(json.dumps({"case": label, "what": "nominal dri", "wall_s": wall0, "cpu_s": cpu0,
                          "best_cpu_s": min(cpu0)}))  # fmt: skip
        for k, m in enumerate(counts):
            u = Uncertainty(m, seed=1, **spreads)
            found, wall, cpu = timed(
                lambda case=case, u=u: uncertainty_ranges(case, PROBABILITIES, u), args.runs
            )
            row = {
                "case": label,
                "what": "uncertainty, one array pass",
                "samples": m,
                "wall_s": wall,
                "cpu_s": cpu,
                "best_cpu_s": min(cpu),
                "ratio_to_nominal": min(cpu) / min(cpu0),
                "samples_x_pairs_per_s": m / min(cpu),
            }
            if k == 0:
                loop, lwall, lcpu = timed(lambda case=case, u=u: one_at_a_time(case, u), 1)
                np.testing.assert_allclose(loop, found["detection"]["samples"], rtol=1e-9)
                row |= {
                    "loop_wall_s": lwall,
                    "loop_cpu_s": lcpu,
                    "loop_ratio_to_array_pass": min(lcpu) / min(cpu),
                }
            print(json.dumps(row))


if __name__ == "__main__":
    main()
