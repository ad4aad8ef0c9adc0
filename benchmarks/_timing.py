"""Shared timing helpers for the benchmarks: single-threaded, best of several repeats."""

from __future__ import annotations

import os
import time
from collections.abc import Callable

# Single-threaded: NumPy's elementwise ufuncs use one core; BLAS and OpenMP are pinned too
# (effective where this module is imported before NumPy).
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

REPEATS = 7


def best_of(function: Callable[[], object], repeats: int = REPEATS) -> float:
    """Smallest wall time of ``repeats`` calls [s]."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def roofline(inputs: list, outputs: int) -> Callable[[], object]:
    """NumPy reading ``inputs`` and writing ``outputs`` fresh arrays, one add per output."""
    first = inputs[0]

    def run() -> object:
        results = []
        for k in range(outputs):
            source = inputs[k % len(inputs)] if len(inputs) > 1 else first
            results.append(source + 1.0)
        return results

    return run
