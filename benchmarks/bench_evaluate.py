"""Batched evaluation of a large scenario: 100 sensors × 10,000 targets × 100 time steps (10⁸
sensor–target–time triples) through the whole pipeline (geometry, field of view, optics,
radiometry, clutter, atmosphere with noise, transforms, fusion), chunked so memory stays bounded.

Prints the triples per second, the peak resident memory, and the ratio of this throughput to
the core kernel (cycles → three probabilities, bench_core.py) measured in the same run. The last
line printed is one JSON object. Arguments: sensors targets steps (defaults 100 10000 100).
"""

from __future__ import annotations

import json
import resource
import sys
import time

import numpy as np

import targetacq as ta
from _timing import best_of
from targetacq.model import ModelChain
from targetacq.scenario import parse_scenario


def scenario(n_sensors: int, n_targets: int, n_steps: int) -> ModelChain:
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
        )
    )


def main() -> None:
    n_s, n_g, n_t = (int(a) for a in (sys.argv[1:] + ["100", "10000", "100"][len(sys.argv) - 1 :]))
    start = time.perf_counter()
    chain = scenario(n_s, n_g, n_t)
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
    result = {
        "benchmark": "evaluate: ModelChain.evaluate_chunks, full pipeline",
        "sensors": n_s,
        "targets": n_g,
        "steps": n_t,
        "triples": triples,
        "seconds": elapsed,
        "setup_seconds": setup,
        "triples_per_second": rate,
        "peak_memory_mib": rss_mib,
        "core_pairs_per_second": core_rate,
        "ratio_to_core_kernel": core_rate / rate,
        "mean_peak_fused_detection": float(peak_detection.mean()),
    }
    print(
        f"{triples:.3g} triples in {elapsed:.1f} s: {rate / 1e6:.2f} M triples/s, peak memory "
        f"{rss_mib:.0f} MiB; the core kernel runs {core_rate / rate:.1f} x faster per pair"
    )
    print(json.dumps(result))


if __name__ == "__main__":
    main()
