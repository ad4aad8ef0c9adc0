"""Sweeps by blocks of points against one point at a time, in clear air and in fog.

1. A 600-point sweep (30 focal lengths × 20 critical dimensions, probability 0.5) in clear air
   and in fog (``--band lwir --obscurant fog:low``: a bisection per point), through
   :func:`targetacq.run.studies.sweep`: the block path (each block's points read one by one into
   SI numbers and choices, then stacked into arrays, made into one case per group and solved
   together) against the per-point path (each point set up and solved alone, as the previous
   version did: ``studies._point`` per point) in the same run, with the same assembly of the
   dataset. The numbers of both are checked equal (≤ 1e-12 relative, NaN where NaN). Also
   timed: the reading of the 600 points' options alone
   (:func:`targetacq.run.range_options.read_range_options`, the part of the block path that
   stays per point), and their whole set-up one at a time (``range_setup``: reading, the optics
   kernels and the case's checks, per point as the per-point path does).
2. ``targetacq sweep`` as a subprocess (``python -m targetacq``): 400 points (20 × 20) against 1
   point of the same options, CPU time of the child (user + system; one untimed run first to
   warm the file cache). The aim: 400 points cost at most 20× the CPU of 1 point.
3. The fog sweep on a local Dask cluster of each worker count given (``--workers``, default
   1 and 2; at most one per CPU), ``--dask-points`` points (default 6,000) in the default
   blocks, on a cluster started (its start printed apart) and warmed by a small sweep; checked
   equal to the serial block path, timed in this process as well.

Each case runs ``--runs`` times (default 3); wall (``perf_counter``) and CPU (``process_time``,
this process only: a Dask worker's CPU is its own) are printed for every run, and the best.
Ratios are of the best CPU times of the same run. One JSON object per line.

Arguments: ``--runs N``, ``--workers 1,2`` (``--workers 0``: no Dask), ``--dask-points N``,
``--skip-cli``.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import resource
import statistics
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np

from targetacq.run import studies
from targetacq.run.option_table import option_product
from targetacq.run.range_options import read_range_options
from targetacq.run.studies import sweep

FOG = {"band": "lwir", "obscurant": "fog:low"}


def options(n_focal: int, n_dim: int, weather: bool) -> dict[str, Any]:
    focal = [f"{f:.2f}mm" for f in np.linspace(20.0, 300.0, n_focal)]
    dims = [f"{d:.4f}m" for d in np.linspace(0.5, 3.0, n_dim)]
    return {"pitch": "12um", "focal_length": focal, "critical_dimension": dims} | (
        FOG if weather else {}
    )


@contextlib.contextmanager
def per_point() -> Iterator[None]:
    """The sweep with the previous version's block: every point set up and solved alone."""
    block = studies._block
    studies._block = lambda points, grid, default: [
        studies._point(dict(p), grid, default) for p in points
    ]
    try:
        yield
    finally:
        studies._block = block


def timed(function: Callable[[], Any], runs: int) -> tuple[Any, list[float], list[float]]:
    """The last result, and the wall and CPU times [s] of ``runs`` calls."""
    walls, cpus = [], []
    result = None
    for _ in range(runs):
        wall, cpu = time.perf_counter(), time.process_time()
        result = function()
        cpus.append(time.process_time() - cpu)
        walls.append(time.perf_counter() - wall)
    return result, walls, cpus


def same(a: np.ndarray, b: np.ndarray) -> None:
    """Equal to 1e-12 relative, NaN where NaN, inf where inf."""
    np.testing.assert_array_equal(np.isnan(a), np.isnan(b))
    np.testing.assert_array_equal(np.isinf(a), np.isinf(b))
    finite = np.isfinite(a)
    np.testing.assert_allclose(a[finite], b[finite], rtol=1e-12, atol=0)


def blocks_against_points(weather: bool, runs: int) -> dict[str, Any]:
    chosen = options(30, 20, weather)
    points = [full for _, full in option_product(studies._text_options(chosen))]
    _, _, read_cpus = timed(lambda: [read_range_options(p, "0.5") for p in points], runs)
    _, _, setup_cpus = timed(lambda: [studies._setup(p, "0.5") for p in points], runs)
    new, walls, cpus = timed(lambda: sweep(chosen), runs)
    with per_point():
        old, old_walls, old_cpus = timed(lambda: sweep(chosen), runs)
    same(new["range"].values, old["range"].values)
    n = len(points)
    return {
        "benchmark": "sweep: blocks vs per point",
        "path": "fog:low (lwir)" if weather else "clear",
        "points": n,
        "runs": runs,
        "blocks_wall_seconds": [round(t, 4) for t in walls],
        "blocks_cpu_seconds": [round(t, 4) for t in cpus],
        "per_point_wall_seconds": [round(t, 4) for t in old_walls],
        "per_point_cpu_seconds": [round(t, 4) for t in old_cpus],
        "read_cpu_seconds": [round(t, 4) for t in read_cpus],
        "setup_cpu_seconds": [round(t, 4) for t in setup_cpus],
        "blocks_points_per_second": round(n / min(cpus), 1),
        "per_point_points_per_second": round(n / min(old_cpus), 1),
        "blocks_us_per_point": round(min(cpus) / n * 1e6, 1),
        "read_us_per_point": round(min(read_cpus) / n * 1e6, 1),
        "setup_us_per_point": round(min(setup_cpus) / n * 1e6, 1),
        "per_point_us_per_point": round(min(old_cpus) / n * 1e6, 1),
        "speedup_cpu": round(min(old_cpus) / min(cpus), 1),
        "speedup_wall": round(min(old_walls) / min(walls), 1),
    }


def cli_cpu(args: list[str], runs: int) -> list[float]:
    """CPU times (user + system) [s] of ``targetacq ARGS`` in a new interpreter."""
    command = [sys.executable, "-m", "targetacq", *args]
    subprocess.run(command, capture_output=True, check=True)  # warm the file cache
    cpus = []
    for _ in range(runs):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        subprocess.run(command, capture_output=True, check=True)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpus.append(after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
    return cpus


def cli_400_against_1(weather: bool, runs: int) -> dict[str, Any]:
    def args(chosen: dict[str, Any]) -> list[str]:
        out = ["sweep", "--format", "csv", "--no-progress"]
        for name, value in chosen.items():
            text = ",".join(value) if isinstance(value, list) else value
            out += [f"--{name.replace('_', '-')}", text]
        return out

    many = options(20, 20, weather)
    one = {**many, "focal_length": "50mm", "critical_dimension": "2.3m"}
    cpu_one = cli_cpu(args(one), runs)
    cpu_many = cli_cpu(args(many), runs)
    ratio = statistics.median(cpu_many) / statistics.median(cpu_one)
    return {
        "benchmark": "targetacq sweep: 400 points vs 1 point (CPU of the child)",
        "path": "fog:low (lwir)" if weather else "clear",
        "runs": runs,
        "one_point_cpu_seconds": [round(t, 3) for t in cpu_one],
        "points_400_cpu_seconds": [round(t, 3) for t in cpu_many],
        "ratio_of_medians": round(ratio, 2),
        "aim": "<= 20",
        "load_average_1min": os.getloadavg()[0] if hasattr(os, "getloadavg") else None,
    }


def on_dask(worker_counts: list[int], points: int, runs: int) -> list[dict[str, Any]]:
    n_dim = 20
    chosen = options(max(1, points // n_dim), n_dim, True)
    n = (points // n_dim) * n_dim
    limit, studies.SERIAL_LIMIT = studies.SERIAL_LIMIT, n  # the serial path, in one process
    try:
        serial, walls, cpus = timed(lambda: sweep(chosen), runs)
    finally:
        studies.SERIAL_LIMIT = limit
    records = [
        {
            "benchmark": "sweep on Dask (fog, blocks)",
            "points": n,
            "workers": 0,
            "wall_seconds": [round(t, 3) for t in walls],
            "cpu_seconds": [round(t, 3) for t in cpus],
            "points_per_second": round(n / min(walls), 1),
        }
    ]
    for workers in worker_counts:
        start = time.perf_counter()
        with studies.local_cluster(workers) as cluster:
            started = time.perf_counter() - start
            sweep(options(2, 2, True), scheduler=cluster)  # untimed: the workers import
            found, walls, cpus = timed(lambda c=cluster: sweep(chosen, scheduler=c), runs)
        same(found["range"].values, serial["range"].values)
        records.append(
            {
                "benchmark": "sweep on Dask (fog, blocks)",
                "points": n,
                "workers": workers,
                "cluster_start_seconds": round(started, 3),
                "wall_seconds": [round(t, 3) for t in walls],
                "client_cpu_seconds": [round(t, 3) for t in cpus],
                "points_per_second": round(n / min(walls), 1),
                "cpus": len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else None,
            }
        )
    return records


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--workers", default="1,2")
    parser.add_argument("--dask-points", type=int, default=6000)
    parser.add_argument("--skip-cli", action="store_true")
    given = parser.parse_args(argv)
    sweep(options(2, 2, True))  # untimed: the first call imports xarray and the datasets' code
    for weather in (False, True):
        print(json.dumps(blocks_against_points(weather, given.runs)), flush=True)
    if not given.skip_cli:
        for weather in (False, True):
            print(json.dumps(cli_400_against_1(weather, given.runs)), flush=True)
    workers = [int(w) for w in given.workers.split(",") if int(w) > 0]
    if workers:
        for record in on_dask(workers, given.dask_points, given.runs):
            print(json.dumps(record), flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
