"""Batched evaluation of a large scenario: 100 sensors × 10,000 targets × 100 time steps (10⁸
sensor–target–time triples) through the whole pipeline (geometry, field of view, optics,
radiometry, clutter, atmosphere with noise, transforms, fusion), chunked so memory stays bounded,
with each available compute engine (numpy, numba; ``targetacq.core.engines``).

Each engine runs in a child process of its own (so that its peak resident memory is its own),
one after the other in this run; one JSON line per engine with ``engine``, ``triples``,
``triples_per_second``, ``peak_rss_mib`` and ``speedup_vs_numpy`` (against the NumPy engine's
line of the same run), and the ratio of the throughput to the core kernel (cycles → three
probabilities, bench_core.py) measured in the child. Arguments: sensors targets steps (defaults
100 10000 100), then optionally the engines (default ``numpy,numba`` where numba is installed).
"""

from __future__ import annotations

import json
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

import targetacq as ta
from _timing import best_of
from targetacq.run.model_chain import ModelChain
from targetacq.scenario.schema import parse_scenario


def scenario(n_sensors: int, n_targets: int, n_steps: int, engine: str = "numpy") -> ModelChain:
    rng = np.random.default_rng(1)
    sensors = [
        {
            "name": f"s{i}",
            "band": "lwir",
            "pixels": [640, 512],
            "pitch": "17 um",
            "focal_length": "35 mm",
            "position": [f"{x:.1f} m", f"{y:.1f} m", f"{z:.1f} m"],
            "azimuth": f"{az:.2f} deg",
            "depression": "30 deg",
        }
        for i, (x, y, z, az) in enumerate(
            zip(
                rng.uniform(-5e3, 5e3, n_sensors),
                rng.uniform(-5e3, 5e3, n_sensors),
                rng.uniform(1e3, 3e3, n_sensors),
                rng.uniform(0, 360, n_sensors),
                strict=True,
            )
        )
    ]
    targets = [
        {
            "name": f"t{j}",
            "dimensions": ["7 m", "2.5 m", "3 m"],
            "temperature": f"{temp:.2f} K",
            "heading": f"{h:.1f} deg",
            "position": [f"{x:.1f} m", f"{y:.1f} m", "0 m"],
        }
        for j, (x, y, h, temp) in enumerate(
            zip(
                rng.uniform(-8e3, 8e3, n_targets),
                rng.uniform(-8e3, 8e3, n_targets),
                rng.uniform(0, 360, n_targets),
                rng.uniform(295, 315, n_targets),
                strict=True,
            )
        )
    ]
    return ModelChain(
        parse_scenario(
            {
                "sensors": sensors,
                "targets": targets,
                "background": {"temperature": "293 K", "clutter_std": "2 K"},
                "atmosphere": {"obscurant": "haze"},
                "time": {"start": "0 s", "stop": f"{n_steps - 1} s", "step": "1 s"},
            }
        ),
        # Only when asked, so that bench_versions.py can run this script on versions before
        # the engines.
        **({} if engine == "numpy" else {"engine": engine}),
    )


def measure(engine: str, n_s: int, n_g: int, n_t: int) -> dict[str, object]:
    """One engine's run (in this process)."""
    start = time.perf_counter()
    chain = scenario(n_s, n_g, n_t, engine)
    next(iter(chain.evaluate_chunks(times=[0.0], targets_per_chunk=10)))  # compile, warm up
    setup = time.perf_counter() - start
    triples = n_s * n_g * n_t
    peak_detection = np.zeros(n_g)
    start = time.perf_counter()
    for targets, _, arrays in chain.evaluate_chunks(targets_per_chunk=10, times_per_chunk=100):
        peak_detection[targets] = np.maximum(
            peak_detection[targets], arrays["fused_detection"].max(axis=-1)
        )
    elapsed = time.perf_counter() - start
    rss_mib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    cycles = np.random.default_rng(0).uniform(0.0, 20.0, 4_000_000)
    t_core = best_of(lambda: ta.acquisition_probabilities(cycles))
    core_rate = cycles.size / t_core
    rate = triples / elapsed
    return {
        "benchmark": "evaluate: ModelChain.evaluate_chunks, full pipeline",
        "engine": engine,
        "sensors": n_s,
        "targets": n_g,
        "steps": n_t,
        "triples": triples,
        "seconds": elapsed,
        "setup_seconds": setup,
        "triples_per_second": rate,
        "peak_rss_mib": rss_mib,
        "core_pairs_per_second": core_rate,
        "ratio_to_core_kernel": core_rate / rate,
        "mean_peak_fused_detection": float(peak_detection.mean()),
    }


def main() -> None:
    args = sys.argv[1:]
    if args and args[0] == "--child":
        print(json.dumps(measure(args[1], *(int(a) for a in args[2:5]))))
        return
    size = (args + ["100", "10000", "100"][len(args) :])[:3]
    from targetacq.core.engines import ENGINES

    default = ",".join(e for e in ("numpy", "numba") if ENGINES[e].available())
    engines = (args[3] if len(args) > 3 else default).split(",")
    lines = []
    for engine in engines:
        out = subprocess.run(
            [sys.executable, str(Path(__file__)), "--child", engine, *size],
            capture_output=True,
            text=True,
            check=True,
        ).stdout
        lines.append(json.loads(out.strip().splitlines()[-1]))
    numpy_rate = next(
        (float(line["triples_per_second"]) for line in lines if line["engine"] == "numpy"), None
    )
    for line in lines:
        rate = float(line["triples_per_second"])
        line["speedup_vs_numpy"] = None if numpy_rate is None else rate / numpy_rate
        print(
            f"{line['engine']}: {line['triples']:.3g} triples in {line['seconds']:.1f} s: "
            f"{rate / 1e6:.2f} M triples/s, peak memory {line['peak_rss_mib']:.0f} MiB",
            file=sys.stderr,
        )
        print(json.dumps(line), flush=True)


if __name__ == "__main__":
    main()
