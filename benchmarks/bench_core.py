"""Throughput of the core kernel: cycles → P(detection), P(recognition), P(identification).

The kernel is :func:`targetacq.acquisition_probabilities` with Johnson's N50s and the TTPF,
over ``PAIRS`` sensor–target pairs (one cycles value each, three probabilities out). The roofline
is the time NumPy needs to read the same input array and write the same number (3) of freshly
allocated output arrays with the cheapest elementwise operation (one add per output). Both are
timed in this run, best of ``REPEATS``, single-threaded. The last line printed is one JSON object.
"""

from __future__ import annotations

import json
import sys

import numpy as np

import targetacq as ta
from _timing import REPEATS, best_of, roofline

PAIRS = int(sys.argv[1]) if len(sys.argv) > 1 else 4_000_000


def main() -> None:
    rng = np.random.default_rng(2004)
    cycles = rng.uniform(0.0, 20.0, PAIRS)

    def kernel():
        return ta.acquisition_probabilities(cycles)

    def per_task():  # the generic array-API path, one transform call per task
        return [
            ta.probability(cycles, task) for task in ("detection", "recognition", "identification")
        ]

    kernel()  # warm-up: tables, caches
    t_kernel = best_of(kernel)
    t_roof = best_of(roofline([cycles], outputs=3))
    t_generic = best_of(per_task)
    result = {
        "benchmark": "core: cycles -> 3 TTPF probabilities (acquisition_probabilities)",
        "pairs": PAIRS,
        "repeats": REPEATS,
        "seconds": t_kernel,
        "pairs_per_second": PAIRS / t_kernel,
        "roofline_seconds": t_roof,
        "roofline_pairs_per_second": PAIRS / t_roof,
        "roofline_ratio": t_kernel / t_roof,
        "generic_per_task_seconds": t_generic,
        "speedup_over_generic": t_generic / t_kernel,
        "numpy": np.__version__,
    }
    print(
        f"{PAIRS:,} pairs: {PAIRS / t_kernel / 1e6:.1f} M pairs/s, "
        f"{t_kernel / t_roof:.2f} x the NumPy roofline ({PAIRS / t_roof / 1e6:.1f} M pairs/s), "
        f"{t_generic / t_kernel:.2f} x faster than three generic per-task calls"
    )
    print(json.dumps(result))


if __name__ == "__main__":
    main()
