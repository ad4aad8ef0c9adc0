"""Blackbody band exitance compiled by numba: :func:`targetacq.physics.radiometry.band_exitance`'s
method, one element at a time.

The same tables (degree-5 Chebyshev interpolants of ``Q(x) = ∫_x^∞ t³/(e^t − 1) dt`` on
[0, 20) and of ``S(x) = x⁻³ ∫_0^x t³/(e^t − 1) dt`` on [0, 2), 64 intervals per unit of x,
built by :mod:`targetacq.physics.radiometry` from the series in extended precision), the same
two-term large-x series beyond x = 20 and the same logarithms where ``e^{−x}`` is subnormal, in the
same order of operations: the results equal the NumPy function's to a few units in the last place
(tested to 1e-12 in ``tests/physics/test_band_exitance_accuracy.py``). One loop with a branch per
element, so each element takes only its own regime (the NumPy function evaluates whole chunks).

``math.exp`` and ``math.log`` are called only beyond x = 20 (short wavelengths or low
temperatures); inside the tables the loop is arithmetic and one table row per band edge, about
twice as fast as the NumPy function (benchmarks/bench_band_exitance.py). Beyond x = 20 the two
``math.exp`` an element, which numba does not vectorise, make it slower than NumPy's SIMD
``exp`` (the visible band at terrestrial temperatures); ``targetacq.core.engines._simd.exp``, called
one element at a time inside this branchy loop, is slower still.

Importing this module imports numba (the ``fast`` extra: ``pip install 'targetacq[fast]'``);
``import targetacq`` never imports it.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numba import njit

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.base.constants import SECOND_RADIATION_CONSTANT
from targetacq.physics import radiometry
from targetacq.physics.bands import band_limits

__all__ = ["band_exitance_numba"]

_STEPS = radiometry.TABLE_STEPS
_DEGREE = radiometry.TABLE_DEGREE
TABLE_END = radiometry.TABLE_END * radiometry.TABLE_STEPS  # in units of 1/64 of x
_HOT_END = radiometry.SMALL_X * radiometry.TABLE_STEPS
_LAST_HOT = math.nextafter(_HOT_END, 0.0)
X_CAP = radiometry.X_CAP
LOG_X = radiometry.LOG_X
KQ = radiometry.KQ
HUGE_KQT = radiometry.HUGE_KQT
_K = radiometry.BAND_CONSTANT
Q0 = radiometry.Q0
_INF = math.inf

_compiled = njit(cache=True, error_model="numpy", nogil=True)
_inline = njit(inline="always", cache=True, error_model="numpy", nogil=True)


@_inline
def _tabulated(table: Any, scaled: float) -> float:
    """The table's polynomial of interval ⌊scaled⌋ at ``scaled − ⌊scaled⌋`` (Horner)."""
    index = int(scaled)
    t = scaled - math.floor(scaled)
    acc = table[index, _DEGREE]
    for k in range(_DEGREE - 1, -1, -1):
        acc = acc * t + table[index, k]
    return acc


@_inline
def _p(y: float) -> float:
    return ((y + 3.0) * y + 6.0) * y + 6.0


@_inline
def _q(table: Any, scaled: float) -> float:
    """Q(scaled / 64) for scaled >= 0 (inf allowed)."""
    if scaled < TABLE_END:
        return _tabulated(table, scaled)
    x = min(scaled / _STEPS, X_CAP)
    decay = math.exp(-x)
    if x >= 37.5:  # the second term is below 2^-54 of the first: the same number without it
        return decay * _p(x)
    return decay * (_p(x) + decay * _p(2.0 * x) / 16.0)


@_inline
def _log_q(table: Any, x: float) -> float:
    """ln Q(x), also where Q underflows (x >= 700: ``ln(x³ + 3x² + 6x + 6) − x``)."""
    x = min(x, X_CAP)
    if x < LOG_X:
        return math.log(_q(table, x * _STEPS))
    return math.log(_p(x)) - x


@_compiled
def _kernel(
    t: Any,
    u_short: float,
    u_long: float,
    ratio3: float,
    q_table: Any,
    s_table: Any,
    out: Any,
) -> None:  # pragma: no cover - compiled; tested through band_exitance_numba
    """``out = band_exitance(t)``; ``u = c2/λ`` of each edge, ``ratio3 = (λ1/λ2)³``."""
    steps_short = u_short * _STEPS
    steps_long = u_long * _STEPS
    hot_factor = _K * (u_short * u_short * u_short)
    for j in range(t.size):
        temperature = t[j]
        if not (temperature > 0.0 and temperature < _INF):  # 0, inf and NaN are their own value
            out[j] = temperature
            continue
        scaled_short = steps_short / temperature
        if scaled_short < _HOT_END:  # both edges on the small-x side
            short = _tabulated(s_table, scaled_short)
            if u_long > 0.0:
                short -= ratio3 * _tabulated(s_table, min(steps_long / temperature, _LAST_HOT))
            out[j] = short * temperature * hot_factor
            continue
        integral = 0.0 if u_short == _INF else -_q(q_table, min(scaled_short, X_CAP * _STEPS))
        if u_long == 0.0:
            integral += Q0
        else:
            integral += _q(q_table, steps_long / temperature)
        power = temperature * KQ
        power *= power
        power *= power
        if u_long / temperature >= LOG_X or temperature * KQ > HUGE_KQT:
            log_long = _log_q(q_table, u_long / temperature)
            ratio = (
                0.0
                if u_short == _INF
                else math.exp(_log_q(q_table, u_short / temperature) - log_long)
            )
            out[j] = math.exp(4.0 * math.log(temperature * KQ) + log_long + math.log1p(-ratio))
        else:
            out[j] = integral * power


def band_exitance_numba(temperature: Array, low: float, high: float) -> Any:
    """Blackbody exitance between two wavelengths, Eq. (6.12), compiled by numba.

    :func:`targetacq.physics.radiometry.band_exitance` (method "planck") element by element: the
    same tables and series (module docstring), equal to it to a few units in the last place.

    Parameters
    ----------
    temperature : array_like
        T [K], >= 0 (NaN gives NaN, 0 gives 0, inf gives inf).
    low, high : float
        λ1 < λ2 [m], ``0 <= λ1``; λ2 may be ``inf``.

    Returns
    -------
    numpy.ndarray or float
        M [W/m²], the shape of ``temperature`` (a float for a scalar).

    Raises
    ------
    ValueError
        A negative temperature, or not ``0 <= λ1 < λ2``.

    Examples
    --------
    8–12 µm at 300 K, the user guide's check value 120.95 W/m², as the NumPy function:

    >>> from targetacq.core.engines.numba_radiometry import band_exitance_numba
    >>> print(f"{band_exitance_numba(300.0, 8e-6, 12e-6):.2f}")
    120.95
    """
    low, high = band_limits((low, high))
    xp, (t,) = _arrays.arrays(temperature, names=("temperature",))
    if xp is not _arrays.NUMPY:
        raise TypeError("band_exitance_numba takes NumPy arrays (or Python numbers)")
    t = np.asarray(t, dtype=np.float64)
    _arrays.require_nonnegative("temperature", t, xp, "K")
    flat = np.ascontiguousarray(t.reshape(-1))
    out = np.empty_like(flat)
    u_short = SECOND_RADIATION_CONSTANT / low if low > 0.0 else math.inf
    u_long = 0.0 if math.isinf(high) else SECOND_RADIATION_CONSTANT / high
    ratio3 = (u_long / u_short) ** 3 if u_long > 0.0 else 0.0  # as radiometry's, exactly
    q_table, s_table = radiometry.band_tables()
    _kernel(flat, u_short, u_long, ratio3, q_table, s_table, out)
    return _arrays.result(out.reshape(t.shape))
