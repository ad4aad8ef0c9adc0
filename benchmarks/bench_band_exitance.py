"""Throughput of ``band_exitance`` (Eq. (6.12)) for many temperatures: the tables of the NumPy
path, the series it replaced, and the numba version.

8–12 µm (or the band given with ``--band``), temperatures 250–350 K, against the roofline of NumPy
reading the temperature array and writing one fresh array (one add). Single-threaded; each
method is timed in the same process, the three interleaved in each of ``REPEATS`` rounds (the
best round of each counts), so a busy machine slows them alike. Wall time and CPU time (this
process's, which the other jobs of a shared machine disturb less) are both reported.

Methods, one JSON line each at the end (``method``):

``previous``
    The closed-form series evaluated on whole arrays, as ``band_exitance`` did before the
    tables (a copy below, so that the comparison does not move when the library does).
``numpy``
    ``targetacq.band_exitance``: the tables (module docstring of ``targetacq.physics.radiometry``).
``numba``
    ``targetacq.core.engines.numba_radiometry.band_exitance_numba``, where numba is installed
    (compiled before timing).

Each line has ``speedup_vs_previous`` (wall and CPU) and ``roofline_ratio``, and the largest
relative difference from the previous method's numbers. Usage:
``python bench_band_exitance.py [N] [--band NAME]``.
"""

from __future__ import annotations

import argparse
import functools
import importlib.util
import json
import math
import time
from collections.abc import Callable
from typing import Any

import numpy as np

import targetacq as ta
from _timing import REPEATS, roofline
from targetacq.base.constants import BOLTZMANN, PLANCK, SECOND_RADIATION_CONSTANT, SPEED_OF_LIGHT
from targetacq.physics.bands import band_limits

# ---------------------------------------------------------------------------------------------
# The previous implementation (targetacq.physics.radiometry before the tables), NumPy only, verbatim
# in its arithmetic: two series on whole arrays in chunks of 16384, see its module docstring then.
# ---------------------------------------------------------------------------------------------

BAND_CONSTANT = 2.0 * math.pi * BOLTZMANN**4 / (PLANCK**3 * SPEED_OF_LIGHT**2)
Q0 = math.pi**4 / 15.0
SMALL_X = 2.0
X_CAP = 1.0e4


@functools.cache
def _small_x_coefficients() -> tuple[float, ...]:
    from scipy.special import bernoulli, factorial

    b = bernoulli(40)
    return tuple(float(b[k] / (factorial(k, exact=True) * (k + 3))) for k in range(41))


def _small_series(x: Any) -> Any:
    acc = np.zeros_like(x)
    for c in reversed(_small_x_coefficients()):
        acc = acc * x + c
    return acc


def _partial_small(x: Any) -> Any:
    return _small_series(x) * x * x * x


def _tail_large(x: Any) -> Any:
    finite = np.where(x >= SMALL_X, x, SMALL_X)
    x_min = float(np.min(finite)) if finite.size else SMALL_X
    terms = max(1, math.ceil(37.5 / x_min))
    decay = np.exp(-finite)
    power = decay
    s1, s2, s3, s4 = power, power, power, power
    for n in range(2, terms + 1):
        power = power * decay
        s1 = s1 + power / n
        s2 = s2 + power / n**2
        s3 = s3 + power / n**3
        s4 = s4 + power / n**4
    return ((finite * s1 + 3.0 * s2) * finite + 6.0 * s3) * finite + 6.0 * s4


def _x_from(lam_t: Any) -> Any:
    safe = np.where(lam_t > 0, lam_t, 1.0)
    capped = np.where(np.isnan(lam_t), lam_t, X_CAP)
    return np.where(lam_t > 0, np.minimum(SECOND_RADIATION_CONSTANT / safe, X_CAP), capped)


def _x_of(wavelength: float, t: Any) -> Any:
    if math.isinf(wavelength):
        return np.zeros_like(t)
    if wavelength == 0:
        return np.where(np.isnan(t), t, np.full_like(t, X_CAP))
    return _x_from(wavelength * t)


def _band_integral_planck(x_short: Any, x_long: Any) -> Any:
    small_long_any = bool(np.any(x_long < SMALL_X))
    large_short_any = bool(np.any(x_short >= SMALL_X))
    if not small_long_any:
        return _tail_large(x_long) - _tail_large(x_short)
    small_long = _partial_small(np.minimum(x_long, SMALL_X))
    tail_long = np.where(x_long < SMALL_X, Q0 - small_long, _tail_large(x_long))
    if not large_short_any:
        return _partial_small(np.minimum(x_short, SMALL_X)) - small_long
    both_small = x_short < SMALL_X
    small_short = _partial_small(np.minimum(x_short, SMALL_X))
    tail_short = np.where(both_small, 0.0, _tail_large(x_short))
    return np.where(both_small, small_short - small_long, tail_long - tail_short)


def _planck_hot_or_cool(t: Any, x_short: Any, x_long: Any, low: float, high: float) -> Any:
    hot = x_short < SMALL_X
    u_short = SECOND_RADIATION_CONSTANT / low
    u_long = 0.0 if math.isinf(high) else SECOND_RADIATION_CONSTANT / high
    small_short = np.minimum(x_short, SMALL_X)
    small_long = np.minimum(x_long, SMALL_X)
    scaled = u_short**3 * _small_series(small_short) - u_long**3 * _small_series(small_long)
    cool_t = np.where(hot, 0.0, t)
    cool = _band_integral_planck(np.where(hot, X_CAP, x_short), np.where(hot, X_CAP, x_long))
    with np.errstate(over="ignore"):
        t2 = cool_t * cool_t
        cooled = BAND_CONSTANT * t2 * t2 * cool
    return np.where(hot, BAND_CONSTANT * t * scaled, cooled)


def previous_band_exitance(temperature: np.ndarray, band: Any) -> np.ndarray:
    """``band_exitance(temperature, band)`` as computed before the tables (float64 NumPy)."""
    low, high = band_limits(band)

    def kernel(part: np.ndarray) -> np.ndarray:
        x_short, x_long = _x_of(low, part), _x_of(high, part)
        if bool(np.any(x_short < SMALL_X)):
            return _planck_hot_or_cool(part, x_short, x_long, low, high)
        integral = _band_integral_planck(x_short, x_long)
        with np.errstate(over="ignore", invalid="ignore"):
            t2 = part * part
            return BAND_CONSTANT * t2 * t2 * integral

    chunk = 1 << 14
    if temperature.size <= chunk:
        return kernel(temperature)
    flat = temperature.reshape(-1)
    out = np.empty(flat.shape)
    for start in range(0, flat.size, chunk):
        out[start : start + chunk] = kernel(flat[start : start + chunk])
    return out.reshape(temperature.shape)


# ---------------------------------------------------------------------------------------------


def _timed(function: Callable[[], object]) -> tuple[float, float]:
    wall, cpu = time.perf_counter(), time.process_time()
    function()
    return time.perf_counter() - wall, time.process_time() - cpu


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("n", nargs="?", type=int, default=1_000_000, help="temperatures")
    parser.add_argument("--band", default="lwir", help="a named band (default lwir)")
    args = parser.parse_args()
    n, band = args.n, args.band
    temperatures = np.random.default_rng(7).uniform(250.0, 350.0, n)
    low, high = band_limits(band)

    methods: dict[str, Callable[[], Any]] = {
        "previous": lambda: previous_band_exitance(temperatures, band),
        "numpy": lambda: ta.band_exitance(temperatures, band),
    }
    if importlib.util.find_spec("numba") is not None:
        from targetacq.core.engines.numba_radiometry import band_exitance_numba

        methods["numba"] = lambda: band_exitance_numba(temperatures, low, high)
    values = {name: np.asarray(run()) for name, run in methods.items()}  # warm-up, compiles
    walls: dict[str, list[float]] = {name: [] for name in methods}
    cpus: dict[str, list[float]] = {name: [] for name in methods}
    for _ in range(REPEATS):
        for name, run in methods.items():
            wall, cpu = _timed(run)
            walls[name].append(wall)
            cpus[name].append(cpu)
    roof = roofline([temperatures], outputs=1)
    t_roof = min(_timed(roof)[0] for _ in range(REPEATS))

    previous = values["previous"]
    normal = np.abs(previous) >= np.finfo(float).tiny
    lines = []
    for name in methods:
        wall, cpu = min(walls[name]), min(cpus[name])
        difference = np.abs(values[name][normal] / previous[normal] - 1.0)
        lines.append(
            {
                "benchmark": f"band_exitance, {band}, 250-350 K",
                "method": name,
                "temperatures": n,
                "repeats": REPEATS,
                "seconds": wall,
                "cpu_seconds": cpu,
                "temperatures_per_second": n / wall,
                "roofline_seconds": t_roof,
                "roofline_ratio": wall / t_roof,
                "speedup_vs_previous": min(walls["previous"]) / wall,
                "speedup_vs_previous_cpu": min(cpus["previous"]) / cpu,
                "max_relative_difference_vs_previous": float(difference.max(initial=0.0)),
            }
        )
        print(
            f"{name:>8}: {n / wall / 1e6:6.1f} M temperatures/s, "
            f"{wall / t_roof:5.0f} x roofline, "
            f"{lines[-1]['speedup_vs_previous']:5.2f} x previous "
            f"({lines[-1]['speedup_vs_previous_cpu']:.2f} x in CPU time)",
            flush=True,
        )
    for line in lines:
        print(json.dumps(line), flush=True)


if __name__ == "__main__":
    main()
