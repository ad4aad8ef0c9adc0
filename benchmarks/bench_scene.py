"""Throughput of ``scene_acquisition``, physics to probabilities, for ``N`` sensor–target pairs.

Each pair has its own range and target temperature; clutter is a temperature spread and haze is
on the path. The roofline is NumPy reading the two input arrays and writing the eight output
arrays (cycles, contrast, SCR, τ, SNR, three probabilities); the ratio to the core kernel
(cycles → three probabilities, bench_core.py) is measured in the same run too.

Single-threaded, best of several repeats; the last line printed is one JSON object.
"""

from __future__ import annotations

import json
import sys

import numpy as np

import targetacq as ta
from _timing import REPEATS, best_of, roofline

N = int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000


def main() -> None:
    rng = np.random.default_rng(7)
    temperatures = rng.uniform(250.0, 350.0, N)
    ranges = rng.uniform(200.0, 10_000.0, N)
    cycles = ta.cycles_on_target(2.3, ranges, 2.27e-4)
    gamma = ta.obscurant_extinction("haze", "lwir", "high")
    clutter_std = 2.0  # K, the background's temperature spread

    def scene():
        return ta.scene_acquisition(
            ranges,
            ta.RangeCase(2.3, 2.27e-4, extinction=gamma),
            ta.Scene("lwir", temperatures, 295.0, clutter_std=clutter_std),
        )

    def core():
        return ta.acquisition_probabilities(cycles)

    scene()
    t_scene = best_of(scene)
    t_scene_roof = best_of(roofline([ranges, temperatures], outputs=8))
    t_core = best_of(core)
    result = {
        "benchmark": "physics: scene_acquisition",
        "n": N,
        "repeats": REPEATS,
        "pairs_per_second": N / t_scene,
        "scene_over_core_kernel": t_scene / t_core,
        "roofline_ratio": t_scene / t_scene_roof,
    }
    print(
        f"scene_acquisition: {N / t_scene / 1e6:.2f} M pairs/s, {t_scene / t_scene_roof:.1f} x "
        f"roofline, {t_scene / t_core:.1f} x the core kernel's time"
    )
    print(json.dumps(result))


if __name__ == "__main__":
    main()
