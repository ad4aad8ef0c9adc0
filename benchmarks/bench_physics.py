"""Throughput of the signal and atmosphere layer.

1. ``band_exitance`` for ``N`` temperatures (8–12 µm), closed-form series, against the roofline
   of reading one array and writing one.
2. ``scene_acquisition``, physics to probabilities, for ``N`` sensor–target pairs (each its own
   range and target temperature; clutter as a temperature spread and haze on the path), against
   the roofline of reading the two input arrays and writing the eight output arrays (cycles,
   contrast, SCR, τ, SNR, three probabilities). Also the ratio to the core kernel
   (cycles → three probabilities) measured in the same run.

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
    clutter_std = float(2.0 * ta.radiometry.band_exitance_derivative(295.0, "lwir"))

    def exitance():
        return ta.band_exitance(temperatures, "lwir")

    def scene():
        return ta.scene_acquisition(
            ranges,
            2.3,
            2.27e-4,
            "lwir",
            temperatures,
            295.0,
            clutter_std=clutter_std,
            extinction=gamma,
        )

    def core():
        return ta.acquisition_probabilities(cycles)

    scene()
    t_exitance = best_of(exitance)
    t_exitance_roof = best_of(roofline([temperatures], outputs=1))
    t_scene = best_of(scene)
    t_scene_roof = best_of(roofline([ranges, temperatures], outputs=8))
    t_core = best_of(core)
    result = {
        "benchmark": "physics: band_exitance and scene_acquisition",
        "n": N,
        "repeats": REPEATS,
        "band_exitance_per_second": N / t_exitance,
        "band_exitance_roofline_ratio": t_exitance / t_exitance_roof,
        "scene_pairs_per_second": N / t_scene,
        "scene_roofline_ratio": t_scene / t_scene_roof,
        "scene_over_core_kernel": t_scene / t_core,
        "roofline_ratio": t_scene / t_scene_roof,
    }
    print(
        f"band_exitance: {N / t_exitance / 1e6:.1f} M temperatures/s, "
        f"{t_exitance / t_exitance_roof:.1f} x roofline"
    )
    print(
        f"scene_acquisition: {N / t_scene / 1e6:.2f} M pairs/s, {t_scene / t_scene_roof:.1f} x "
        f"roofline, {t_scene / t_core:.1f} x the core kernel's time"
    )
    print(json.dumps(result))


if __name__ == "__main__":
    main()
