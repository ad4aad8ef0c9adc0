"""Throughput of ``band_exitance`` (closed-form series, Eq. (6.12)) for many temperatures.

8–12 µm, temperatures 250–350 K, against the roofline of NumPy reading the temperature array and
writing one fresh array (one add). Single-threaded, best of several repeats; the last line printed
is one JSON object.
"""

from __future__ import annotations

import json
import sys

import numpy as np

import targetacq as ta
from _timing import REPEATS, best_of, roofline

N = int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000


def main() -> None:
    temperatures = np.random.default_rng(7).uniform(250.0, 350.0, N)
    ta.band_exitance(temperatures, "lwir")
    t_kernel = best_of(lambda: ta.band_exitance(temperatures, "lwir"))
    t_roof = best_of(roofline([temperatures], outputs=1))
    result = {
        "benchmark": "band_exitance, 8-12 um, 250-350 K",
        "temperatures": N,
        "repeats": REPEATS,
        "seconds": t_kernel,
        "temperatures_per_second": N / t_kernel,
        "roofline_seconds": t_roof,
        "roofline_ratio": t_kernel / t_roof,
    }
    print(
        f"band_exitance: {N / t_kernel / 1e6:.1f} M temperatures/s, "
        f"{t_kernel / t_roof:.0f} x roofline"
    )
    print(json.dumps(result))


if __name__ == "__main__":
    main()
