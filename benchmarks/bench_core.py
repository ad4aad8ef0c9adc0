"""Throughput of the core kernel: cycles → P(detection), P(recognition), P(identification).

The kernel is :func:`targetacq.acquisition_probabilities` with Johnson's N50s and the TTPF,
over ``PAIRS`` sensor–target pairs (one cycles value each, three probabilities out). The roofline
is the time NumPy needs to read the same input array and write the same number (3) of freshly
allocated output arrays with the cheapest elementwise operation (one add per output). Both are
timed in this run, best of ``REPEATS``, single-threaded. The line ends with the numba engine's
kernel (``targetacq.core.engines.numba_kernels.ttpf_three``: one fused loop with the vectorisable
exp/log), where numba is installed, as a second JSON line with ``speedup_vs_numpy``.
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
    print(json.dumps(result), flush=True)
    from targetacq.core.engines import ENGINES

    if not ENGINES["numba"].available():
        return
    from targetacq.core.engines.numba_kernels import ttpf_three

    n50 = np.array([1.0, 4.0, 6.4])  # Johnson's N50s, as acquisition_probabilities uses

    def fused():
        outs = [np.empty_like(cycles) for _ in range(3)]
        ttpf_three(cycles, n50, *outs)
        return outs

    fused()  # compile
    t_fused = best_of(fused)
    t_kernel = best_of(kernel)  # again, next to it: the machine is shared
    line = {
        "benchmark": "core: cycles -> 3 TTPF probabilities, numba engine (ttpf_three)",
        "engine": "numba",
        "pairs": PAIRS,
        "seconds": t_fused,
        "pairs_per_second": PAIRS / t_fused,
        "roofline_ratio": t_fused / t_roof,
        "speedup_vs_numpy": t_kernel / t_fused,
    }
    print(json.dumps(line))


if __name__ == "__main__":
    main()
