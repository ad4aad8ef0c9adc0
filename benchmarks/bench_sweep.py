"""A 10⁴-point trade study (100 focal lengths × 100 critical dimensions, one probability):
serially, then on a local Dask cluster of 1 and of 2 worker processes.

Every point is computed as ``targetacq dri`` computes it (``range_setup`` then ``case_ranges``),
so the time per point is that of a single ``dri`` run without its start-up; the Dask runs include
starting the cluster. The results of every run are checked equal to the serial run's.

Prints one JSON object per line: ``points``, ``workers`` (0: serial), ``seconds``,
``points_per_second``. Arguments: focal_lengths critical_dimensions [workers ...] (defaults
100 100 1 2); add ``--weather`` for a fog path (bisection: about 40× slower per point).
"""

from __future__ import annotations

import json
import sys
import time

import numpy as np

from targetacq.studies import sweep


def options(n_focal: int, n_dim: int, weather: bool) -> dict[str, object]:
    focal = [f"{f:.2f}mm" for f in np.linspace(20.0, 300.0, n_focal)]
    dims = [f"{d:.4f}m" for d in np.linspace(0.5, 3.0, n_dim)]
    extra = {"band": "lwir", "obscurant": "fog:low"} if weather else {}
    return {"pitch": "12um", "focal_length": focal, "critical_dimension": dims, **extra}


def main(argv: list[str]) -> None:
    weather = "--weather" in argv
    numbers = [int(a) for a in argv if not a.startswith("--")]
    n_focal, n_dim = [*numbers, 100, 100][:2]
    worker_counts = numbers[2:] or [1, 2]
    chosen = options(n_focal, n_dim, weather)
    points = n_focal * n_dim
    start = time.perf_counter()
    serial = sweep(chosen, workers=None) if points <= 1000 else None
    if serial is None:  # above the serial limit: force the serial path through one block
        from targetacq import studies

        limit, studies.SERIAL_LIMIT = studies.SERIAL_LIMIT, points
        try:
            serial = sweep(chosen)
        finally:
            studies.SERIAL_LIMIT = limit
    seconds = time.perf_counter() - start
    runs = [(0, seconds)]
    for workers in worker_counts:
        start = time.perf_counter()
        found = sweep(chosen, workers=workers)
        runs.append((workers, time.perf_counter() - start))
        np.testing.assert_array_equal(found["range"].values, serial["range"].values)
    for workers, seconds in runs:
        record = {
            "benchmark": "sweep" + ("_fog" if weather else ""),
            "points": points,
            "workers": workers,
            "seconds": round(seconds, 3),
            "points_per_second": round(points / seconds, 1),
        }
        print(json.dumps(record), flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
