"""Thermal and reflected radiation: Planck, band exitance, emissivity, signal at the sensor.

Sources: Sonesson (2004) ch. 6, Eqs. (6.1)–(6.18) with the erratum ``2π h c²`` to Eqs. (6.12)
and (6.13) (see the user guide's errata), Table 6.1; CODATA constants via
:mod:`targetacq.base.constants`.

Band exitance is computed in closed form, with no quadrature, through the integral
``Q(x) = ∫_x^∞ t³ / (e^t − 1) dt`` with ``x = c2 / (λ T)``; the exitance between λ1 and λ2 is
``2π k⁴ T⁴ / (h³ c²) · (Q(x2) − Q(x1))`` (so ``Q(0) = π⁴/15`` gives ``σ T⁴``). Two series:

- ``x >= 2``: ``Q(x) = Σ_{n>=1} e^{−n x} (x³/n + 3x²/n² + 6x/n³ + 6/n⁴)`` (expand ``1/(e^t − 1)``
  as ``Σ e^{−n t}`` and integrate each term by parts). Every term is positive and the n-th is
  below ``e^{−n x}`` times the first term's polynomial, so the remainder after N terms is below
  ``e^{−(N+1)x}/(1 − e^{−x}) · (x³ + 3x² + 6x + 6)``; N = ⌈37.5 / x⌉ (≤ 19 at x = 2) leaves a
  relative error under 1e-16.
- ``x < 2``: ``Q(x) = π⁴/15 − Σ_k B_k x^{k+3} / (k! (k+3))`` (integrate the Bernoulli series of
  ``t/(e^t − 1)``), which converges for ``|x| < 2π``; at ``x = 2`` its terms fall by
  ``(x/2π)² ≈ 0.1`` every two orders, so 40 orders reach double precision.

Where both ends lie below x = 2 the difference is taken between the two small-x partial
integrals directly, so no large constant cancels. Large x (short λT) is safe: ``e^{−n x}``
underflows to zero, nothing overflows.

These series are what :func:`band_exitance` evaluates for arrays of other namespaces (the
array API, JAX under ``jit``) and for float32, and what :func:`band_exitance_derivative` uses.
For float64 NumPy input (the common case), :func:`band_exitance` reads the same functions from
tables instead, several times faster (benchmarks/bench_band_exitance.py), in chunks of 16384
temperatures, each chunk taking only the branches its temperatures need:

- Tables. ``Q`` on [0, 20) and ``S(x) = x⁻³ ∫_0^x t³/(e^t − 1) dt = (π⁴/15 − Q(x))/x³`` on
  [0, 2), on intervals of width 1/64: in each, the degree-5 polynomial that interpolates the
  function at the 6 Chebyshev points of the interval, evaluated by Horner in ``64x − ⌊64x⌋``.
  The tables are built on the first call (about 40 ms) from the two series above, summed in
  ``np.longdouble`` (80-bit on x86-64) with the Bernoulli numbers exact (``fractions``), well
  past double precision. Chebyshev interpolation of degree 5 on an interval of half-width h
  errs by at most ``h⁶ / (2⁵ 6!) · max |f⁽⁶⁾|``: with h = 1/128 and ``|f⁽⁶⁾| <~ |f|`` (``Q``
  decays like ``x³ e^{−x}``), below 1e-17 relative. The tables are within 2.1e-16 (one unit
  in the last place) of the 45-digit reference of the tests (in float64 long double, where the
  platform has no wider one, within about 1e-15).
- ``x >= 20``: two terms of the large-x series, ``e^{−x}[P(x) + e^{−x} P(2x)/16]`` with
  ``P(y) = y³ + 3y² + 6y + 6`` (the third term is below 2e-18 relative at x = 20; from x = 37.5
  on, the second is below 2⁻⁵⁴ of the first and is left out: the same rounded number).
- Hot, ``x1 < 2`` (both edges on the small-x side): ``K T (c2/λ1)³ [S(x1) − (λ1/λ2)³ S(x2)]``,
  which is ``K T⁴ ∫_{x2}^{x1}`` with ``T⁴ x³`` written as ``T (c2/λ)³``, finite up to T = inf.
- Otherwise ``K T⁴ [Q(x2) − Q(x1)]`` with ``K T⁴ = (K^{1/4} T)⁴``; where ``e^{−x2}`` would be
  subnormal (x2 >= 700) or ``(K^{1/4} T)⁴`` overflow (above 1e77 K), in logarithms:
  ``exp(4 ln(K^{1/4} T) + ln Q(x2) + ln(1 − Q(x1)/Q(x2)))`` with ``ln Q(x) = ln P(x) − x``
  there, so that a normal result keeps its precision when ``e^{−x}`` alone would underflow.
- T = 0 gives 0, T = inf gives inf, NaN gives NaN.

Accuracy of the NumPy path, against the 45-digit reference of
``tests/physics/test_band_exitance_accuracy.py`` (T from 1e-3 K to 1.7e308 K, the named bands and
others): below 1e-12 relative everywhere the exitance is a normal number, about 1e-15 where
both x are below 20, and at most about 2e-13 near the underflow (x ≈ 700), where the rounding
of ``x = c2/(λT)`` itself, a relative error of order ``x · 2⁻⁵²`` in ``e^{−x}``, dominates (the
series above have the same). The difference of two values of ``Q`` loses, as any evaluation of
this closed form does, ``Q(x2)/(Q(x2) − Q(x1))`` of its precision: narrow bands less accurate.

The visible band is sunlight reflected, ``M = r · E`` (§6.2), not emission.
"""

from __future__ import annotations

import decimal
import functools
import math
from fractions import Fraction
from typing import Any

import numpy as np

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.base.constants import (
    BOLTZMANN,
    FIRST_RADIATION_CONSTANT,
    PLANCK,
    SECOND_RADIATION_CONSTANT,
    SPEED_OF_LIGHT,
    STEFAN_BOLTZMANN,
    WIEN_DISPLACEMENT,
)
from targetacq.base.tables import load_table
from targetacq.physics.bands import band_limits, band_name

__all__ = [
    "BAND_EXITANCE_METHODS",
    "MATERIALS",
    "band_exitance",
    "band_exitance_derivative",
    "diurnal_temperature",
    "emissivity",
    "emissivity_from_reflectance",
    "grey_body_exitance",
    "irradiance_at_sensor",
    "lambert_intensity",
    "material_emissivity",
    "material_reflectance",
    "peak_wavelength",
    "quantisation_step",
    "reflected_exitance",
    "sky_reflected_exitance",
    "spectral_exitance",
    "stefan_boltzmann_exitance",
    "target_signal",
    "wien_spectral_exitance",
]

BAND_CONSTANT = 2.0 * math.pi * BOLTZMANN**4 / (PLANCK**3 * SPEED_OF_LIGHT**2)
Q0 = math.pi**4 / 15.0
SMALL_X = 2.0
X_CAP = 1.0e4  # e^{-x} is 0 in float64 long before this; caps inf (T = 0, λ = 0) safely


@functools.cache
def _small_x_coefficients() -> tuple[float, ...]:
    from scipy.special import bernoulli, factorial

    b = bernoulli(40)
    return tuple(float(b[k] / (factorial(k, exact=True) * (k + 3))) for k in range(41))


def _small_series(x: Any, xp: Any) -> Any:
    """``S(x) = x⁻³ ∫_0^x t³/(e^t − 1) dt`` for 0 <= x <= 2 (S(0) = 1/3), by Horner in x."""
    acc = xp.zeros_like(x)
    for c in reversed(_small_x_coefficients()):
        acc = acc * x + c
    return acc


def _partial_small(x: Any, xp: Any) -> Any:
    """∫_0^x t³/(e^t − 1) dt for 0 <= x <= 2, by the Bernoulli series (module doc)."""
    return _small_series(x, xp) * x * x * x


def _tail_large(x: Any, xp: Any) -> Any:
    """∫_x^∞ t³/(e^t − 1) dt for x >= 2 (elements below 2 give garbage that is not used)."""
    finite = xp.where(x >= SMALL_X, x, SMALL_X)
    x_min = float(xp.min(finite)) if finite.size else SMALL_X
    terms = max(1, math.ceil(37.5 / x_min))
    decay = xp.exp(-finite)
    power = decay
    # Σ_n e^{-nx}(x³/n + 3x²/n² + 6x/n³ + 6/n⁴) = x³ S1 + 3x² S2 + 6x S3 + 6 S4,
    # with S_k = Σ_n e^{-nx} / n^k.
    s1, s2, s3, s4 = power, power, power, power
    for n in range(2, terms + 1):
        power = power * decay
        s1 = s1 + power / n
        s2 = s2 + power / n**2
        s3 = s3 + power / n**3
        s4 = s4 + power / n**4
    return ((finite * s1 + 3.0 * s2) * finite + 6.0 * s3) * finite + 6.0 * s4


def _x_from(lam_t: Any, xp: Any) -> Any:
    """x = c2 / (λT), capped at X_CAP (also where λT = 0), without division warnings; NaN
    where λT is NaN."""
    safe = xp.where(lam_t > 0, lam_t, 1.0)
    capped = xp.where(xp.isnan(lam_t), lam_t, X_CAP)
    return xp.where(lam_t > 0, xp.minimum(SECOND_RADIATION_CONSTANT / safe, X_CAP), capped)


def _x_of(wavelength: float, t: Any, xp: Any) -> Any:
    """c2 / (λ T) for a band edge: capped where λT = 0, 0 where λ = inf."""
    if math.isinf(wavelength):
        return xp.zeros_like(t)
    if wavelength == 0:  # x = +inf at any T, capped (0 · T would be NaN at T = inf)
        return xp.where(xp.isnan(t), t, xp.full_like(t, X_CAP))
    return _x_from(wavelength * t, xp)


def _band_integral_planck(x_short: Any, x_long: Any, xp: Any) -> Any:
    """∫_{x_long}^{x_short} t³/(e^t−1) dt (x_short = c2/(λ1 T) >= x_long = c2/(λ2 T))."""
    # Each series is evaluated only where some element needs it (most bands need one only).
    small_long_any = bool(xp.any(x_long < SMALL_X))
    large_short_any = bool(xp.any(x_short >= SMALL_X))
    if not small_long_any:  # both ends in the large-x series
        return _tail_large(x_long, xp) - _tail_large(x_short, xp)
    small_long = _partial_small(xp.minimum(x_long, SMALL_X), xp)
    tail_long = xp.where(x_long < SMALL_X, Q0 - small_long, _tail_large(x_long, xp))
    if not large_short_any:  # both ends in the small-x series: no large constant cancels
        return _partial_small(xp.minimum(x_short, SMALL_X), xp) - small_long
    both_small = x_short < SMALL_X
    small_short = _partial_small(xp.minimum(x_short, SMALL_X), xp)
    tail_short = xp.where(both_small, 0.0, _tail_large(x_short, xp))
    return xp.where(both_small, small_short - small_long, tail_long - tail_short)


def _band_integral_wien(x_short: Any, x_long: Any, xp: Any) -> Any:
    # Wien (6.13): 1/(e^t − 1) → e^{−t}; the first term of the large-x series, exactly.
    def tail(x: Any) -> Any:
        return xp.exp(-x) * (((x + 3.0) * x + 6.0) * x + 6.0)

    return tail(x_long) - tail(x_short)


BAND_EXITANCE_METHODS = {"planck": _band_integral_planck, "wien": _band_integral_wien}
"""Ways to integrate the spectral exitance over a band: Planck (6.12) or Wien (6.13)."""


# ---------------------------------------------------------------------------------------------
# Fast NumPy path of band_exitance (method "planck", float64 arrays): tables of Q and S.
# ---------------------------------------------------------------------------------------------

TABLE_STEPS = 64.0  # intervals per unit of x: interval i covers [i/64, (i+1)/64)
TABLE_DEGREE = 5
TABLE_END = 20.0  # Q is tabulated on [0, 20), S on [0, 2); beyond 20, two terms of the series
LOG_X = 700.0  # e^{-x} is subnormal above 708: from here on the exitance is taken in logarithms
KQ = BAND_CONSTANT**0.25  # K T⁴ = (K^{1/4} T)⁴, which overflows only where K T⁴ does
HUGE_KQT = 1.0e76  # (K^{1/4} T)⁴ overflows above 1.16e77: in logarithms there as well
_CHUNK = 16384
_EXTENDED_PI = "3.14159265358979323846264338327950288419716939937510"


@functools.cache
def _exact_small_x_coefficients(count: int) -> list[Fraction]:
    """``B_k / (k! (k + 3))`` for k < count, with the Bernoulli numbers exact (B_1 = −1/2)."""
    bernoulli = [Fraction(1)]
    for m in range(1, count):
        total = sum((math.comb(m + 1, k) * bernoulli[k] for k in range(m)), Fraction(0))
        bernoulli.append(-total / (m + 1))
    return [b / (math.factorial(k) * (k + 3)) for k, b in enumerate(bernoulli)]


def _extended(value: Fraction) -> Any:
    """``value`` rounded to np.longdouble (from 30 significant digits)."""
    digits = decimal.Context(prec=30).divide(value.numerator, value.denominator)
    return np.longdouble(str(digits))


def _s_extended(x: Any) -> Any:
    """S(x) for 0 <= x <= 2 in np.longdouble: the Bernoulli series to order 47 (the terms fall
    like ``2 (x/2π)^k``: below 1e-21 relative at x = 2)."""
    acc = np.zeros_like(x)
    for c in reversed(_exact_small_x_coefficients(48)):
        acc = acc * x + _extended(c)
    return acc


def _q_extended(rows: Any) -> Any:
    """Q(x) in np.longdouble for an (intervals, nodes) array sorted by interval: the small-x
    series below x = 2, the large-x series with ⌈50/x⌉ terms (remainder below e^{-50}) above."""
    q = np.empty_like(rows)
    small = np.max(rows, axis=1) < SMALL_X  # whole intervals: 2 is an interval boundary
    x = rows[small]
    q[small] = np.longdouble(_EXTENDED_PI) ** 4 / 15 - x**3 * _s_extended(x)
    large = rows[~small]
    decay = np.exp(-large)
    power = np.ones_like(large)
    acc = np.zeros_like(large)
    starts = np.min(large, axis=1)  # increasing
    for n in range(1, math.ceil(50.0 / SMALL_X) + 1):
        # The intervals that still need the n-th term (x < 50/(n − 1)): a prefix.
        active = int(np.searchsorted(starts, 50.0 / (n - 1))) if n > 1 else len(starts)
        power[:active] *= decay[:active]
        y = n * large[:active]
        acc[:active] += power[:active] * (((y + 3) * y + 6) * y + 6) / np.longdouble(n) ** 4
    q[~small] = acc
    return q


def _chebyshev_table(function: Any, end: float) -> np.ndarray:
    """Coefficients (in t = 64 x − i, Horner order) of the degree-5 Chebyshev interpolants of
    ``function`` on the intervals [i/64, (i+1)/64) below ``end``, computed in np.longdouble."""
    d = TABLE_DEGREE
    pi = np.longdouble(_EXTENDED_PI)
    angles = pi * (np.arange(d + 1) + np.longdouble(0.5)) / (d + 1)
    nodes = (1 + np.cos(angles)) / 2  # Chebyshev points of [0, 1]
    starts = np.arange(round(end * TABLE_STEPS), dtype=np.longdouble)
    values = function((starts[:, None] + nodes[None, :]) / np.longdouble(TABLE_STEPS))
    # Chebyshev coefficients b_n = 2/(d+1) Σ_k f_k T_n(u_k) (b_0 halved), then the power basis
    # of t through the shifted Chebyshev polynomials T_n(2t − 1) (integer coefficients).
    chebyshev = np.cos(np.outer(np.arange(d + 1), angles))
    b = values @ chebyshev.T * (np.longdouble(2) / (d + 1))
    b[:, 0] /= 2
    shifted = [[1], [-1, 2]]
    for _ in range(2, d + 1):
        nxt = [0] * (len(shifted[-1]) + 1)
        for p, c in enumerate(shifted[-1]):
            nxt[p] -= 2 * c
            nxt[p + 1] += 4 * c
        for p, c in enumerate(shifted[-2]):
            nxt[p] -= c
        shifted.append(nxt)
    power_basis = np.zeros((d + 1, d + 1), dtype=np.longdouble)
    for n, row in enumerate(shifted):
        power_basis[n, : len(row)] = row
    return np.ascontiguousarray((b @ power_basis).astype(np.float64))


@functools.cache
def band_tables() -> tuple[np.ndarray, np.ndarray]:
    """The tables of Q on [0, 20) and of S on [0, 2) (module docstring), built on first use."""
    with np.errstate(all="ignore"):
        q = _chebyshev_table(_q_extended, TABLE_END)
        s = _chebyshev_table(_s_extended, SMALL_X)
    q.flags.writeable = False
    s.flags.writeable = False
    return q, s


@functools.cache
def _split_tables() -> tuple[tuple[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]:
    """Each table as its coefficients 0–3 and 4–5: rows of 32 and 16 bytes, which ``np.take``
    copies by its fast paths (a 48-byte row goes through ``memmove``, 1.5 times slower)."""
    return tuple(  # type: ignore[return-value]
        (np.ascontiguousarray(table[:, :4]), np.ascontiguousarray(table[:, 4:]))
        for table in band_tables()
    )


def _tabulated(table: tuple[np.ndarray, np.ndarray], scaled: np.ndarray) -> np.ndarray:
    """The table's polynomial of interval ⌊scaled⌋ at ``scaled − ⌊scaled⌋`` (0 <= scaled < rows),
    by Horner; ``table`` from :func:`_split_tables`."""
    index = scaled.astype(np.int32)
    t = np.floor(scaled)
    np.subtract(scaled, t, out=t)
    low, high = table[0].take(index, axis=0), table[1].take(index, axis=0)
    acc = high[:, 1] * t
    acc += high[:, 0]
    for k in range(3, -1, -1):
        acc *= t
        acc += low[:, k]
    return acc


def _p(y: Any) -> Any:
    """``y³ + 3y² + 6y + 6``."""
    return ((y + 3.0) * y + 6.0) * y + 6.0


def _q_asymptotic(x: np.ndarray, x_min: float, x_max: float) -> np.ndarray:
    """Q(x) for x >= 20 (``x_min`` and ``x_max`` the least and greatest; ``x`` is overwritten):
    two terms of the large-x series (the third is below 2e-18 relative). From x = 37.5 on the
    second is below 2^-54 of the first, so that the sum rounds to the first: it is left out
    where no element is below 37.5 (the same numbers)."""
    if x_max > X_CAP:
        np.minimum(x, X_CAP, out=x)
    decay = np.negative(x)
    np.exp(decay, out=decay)
    value = x + 3.0  # x³ + 3x² + 6x + 6 by Horner, in place
    value *= x
    value += 6.0
    value *= x
    value += 6.0
    if x_min < 37.5:
        y = x * 2.0
        second = y + 3.0
        second *= y
        second += 6.0
        second *= y
        second += 6.0
        second *= decay
        second *= 1.0 / 16.0
        value += second
    value *= decay
    return value


def _q_fast(scaled: np.ndarray, low: float, high: float) -> np.ndarray:
    """Q(scaled / 64) for scaled >= 0 (inf allowed) whose least and greatest are low and high."""
    end = TABLE_END * TABLE_STEPS
    if high < end:
        return _tabulated(_split_tables()[0], scaled)
    x = scaled / TABLE_STEPS
    if low >= end:
        return _q_asymptotic(x, low / TABLE_STEPS, high / TABLE_STEPS)
    inside = scaled < end
    table = _tabulated(_split_tables()[0], np.where(inside, scaled, 0.0))
    outside = _q_asymptotic(np.maximum(x, TABLE_END), TABLE_END, high / TABLE_STEPS)
    return np.where(inside, table, outside)


def _log_q(x: np.ndarray) -> np.ndarray:
    """ln Q(x) for x >= 0, also where Q underflows: ``−x + ln(x³ + 3x² + 6x + 6)`` from 700 on
    (the second term of the series is e^{-700} times the first there)."""
    x = np.minimum(x, X_CAP)
    inside = np.minimum(x, LOG_X) * TABLE_STEPS
    direct = np.log(_q_fast(inside, float(np.min(inside)), float(np.max(inside))))
    return np.where(x < LOG_X, direct, np.log(_p(x)) - x)


def _cool_chunk(
    t: np.ndarray, t_min: float, t_max: float, u_short: float, u_long: float
) -> np.ndarray:
    """``K T⁴ [Q(x_long) − Q(x_short)]`` for 0 < T < inf (where x_short >= 2)."""
    steps_short = u_short * TABLE_STEPS  # x · 64 = (u · 64) / T, exactly 64 x
    steps_long = u_long * TABLE_STEPS
    if u_long == 0.0:  # λ2 = inf: Q(0) = π⁴/15
        integral = np.full_like(t, Q0)
    else:
        integral = _q_fast(steps_long / t, steps_long / t_max, steps_long / t_min)
    if not math.isinf(u_short):  # else λ1 = 0: Q(inf) = 0
        integral -= _q_fast(steps_short / t, steps_short / t_max, steps_short / t_min)
    power = t * KQ
    power *= power
    power *= power
    integral *= power
    if u_long / t_min >= LOG_X or KQ * t_max > HUGE_KQT:
        far = (u_long / t >= LOG_X) | (t * KQ > HUGE_KQT)
        if bool(np.any(far)):
            integral[far] = _cool_in_logs(t[far], u_short, u_long)
    return integral


def _cool_in_logs(t: np.ndarray, u_short: float, u_long: float) -> np.ndarray:
    """``K T⁴ [Q(x_long) − Q(x_short)]`` as ``exp(4 ln(K^{1/4} T) + ln Q(x_long) + ln(1 − r))``
    with ``r = Q(x_short)/Q(x_long)``: e^{-x} subnormal or (K^{1/4} T)⁴ overflowing."""
    log_long = _log_q(u_long / t)
    ratio = np.zeros_like(t) if math.isinf(u_short) else np.exp(_log_q(u_short / t) - log_long)
    return np.exp(4.0 * np.log(t * KQ) + log_long + np.log1p(-ratio))


def _hot_chunk(t: np.ndarray, u_short: float, u_long: float, mixed: bool) -> np.ndarray:
    """``K T u1³ [S(x_short) − (λ1/λ2)³ S(x_long)]`` for 0 < T < inf where x_short < 2 (in a
    ``mixed`` chunk, the elements where it is not give numbers that are not used)."""
    s_table = _split_tables()[1]
    last = math.nextafter(SMALL_X * TABLE_STEPS, 0.0)
    scaled = (u_short * TABLE_STEPS) / t
    short = _tabulated(s_table, np.minimum(scaled, last) if mixed else scaled)
    if u_long > 0.0:
        ratio = (u_long / u_short) ** 3
        scaled = (u_long * TABLE_STEPS) / t
        long = _tabulated(s_table, np.minimum(scaled, last) if mixed else scaled)
        long *= ratio
        short -= long
    short *= t
    short *= BAND_CONSTANT * (u_short * u_short * u_short)  # inf, not OverflowError
    return short


def _band_exitance_chunk(t: np.ndarray, low: float, high: float) -> np.ndarray:
    """``band_exitance`` (method "planck") of a float64 chunk of T >= 0 or NaN."""
    t_min, t_max = float(t.min()), float(t.max())
    if not (t_min > 0.0 and t_max < math.inf):  # 0, inf or NaN: each is its own exitance
        special = ~((t > 0.0) & (t < math.inf))
        if bool(np.all(special)):
            return t.copy()
        regular = np.where(special, t[int(np.argmin(special))], t)
        return np.where(special, t, _band_exitance_chunk(regular, low, high))
    u_short = SECOND_RADIATION_CONSTANT / low if low > 0.0 else math.inf
    u_long = 0.0 if math.isinf(high) else SECOND_RADIATION_CONSTANT / high
    if u_short / t_max >= SMALL_X:  # every element on the large-x side at λ1 (the usual case)
        return _cool_chunk(t, t_min, t_max, u_short, u_long)
    if u_short / t_min < SMALL_X:  # hot: both edges on the small-x side
        return _hot_chunk(t, u_short, u_long, mixed=False)
    hot = u_short / t < SMALL_X
    return np.where(
        hot,
        _hot_chunk(t, u_short, u_long, mixed=True),
        _cool_chunk(t, t_min, t_max, u_short, u_long),
    )


def _band_exitance_numpy(t: np.ndarray, low: float, high: float) -> np.ndarray:
    """``band_exitance`` (method "planck") of a float64 NumPy array, in chunks of 16384."""
    flat = t.reshape(-1)
    out = np.empty(flat.shape)
    with np.errstate(all="ignore"):
        for start in range(0, flat.size, _CHUNK):
            out[start : start + _CHUNK] = _band_exitance_chunk(
                flat[start : start + _CHUNK], low, high
            )
    return out.reshape(t.shape)


def spectral_exitance(wavelength: Array, temperature: Array) -> Any:
    """Planck's spectral exitance of a blackbody, Eq. (6.2) in Sonesson (2004).

    ``M_λ = 2π h c² / λ⁵ · 1 / (exp(hc / (λ k T)) − 1)``.

    Parameters
    ----------
    wavelength : array_like
        λ [m], > 0.
    temperature : array_like
        T [K], >= 0.

    Returns
    -------
    array_like
        M_λ [W m⁻² m⁻¹] (per metre of wavelength).

    Examples
    --------
    A 300 K blackbody at 10 µm, checked against Planck's law written out with CODATA constants
    (scipy.constants):

    >>> import math
    >>> from scipy.constants import c, h, k
    >>> import targetacq as ta
    >>> print(f"{ta.spectral_exitance(10e-6, 300.0):.6e}")
    3.117727e+07
    >>> print(f"{2 * math.pi * h * c**2 / 10e-6**5 / math.expm1(h * c / (10e-6 * k * 300.0)):.6e}")
    3.117727e+07
    """
    xp, (lam, t) = _arrays.arrays(wavelength, temperature, names=("wavelength", "temperature"))
    _arrays.require_positive("wavelength", lam, xp, "m")
    _arrays.require_finite("wavelength", lam, xp, "m")
    _arrays.require_nonnegative("temperature", t, xp, "K")
    x = _x_from(lam * t, xp)
    # e^{-x} / (1 − e^{-x}) = 1 / (e^x − 1), without overflow at short λT; +inf at T = inf.
    safe = xp.where(x > 0, x, 1.0)
    planck = xp.where(x > 0, xp.exp(-safe) / -xp.expm1(-safe), xp.inf)
    return _arrays.result(FIRST_RADIATION_CONSTANT / lam**5 * xp.where(xp.isnan(x), x, planck))


def wien_spectral_exitance(wavelength: Any, temperature: Any) -> Any:
    """Wien's approximation, Eq. (6.13): ``M_λ ≈ 2π h c² / λ⁵ · exp(−hc / (λ k T))``.

    Valid where ``hc/λ ≫ kT``. Units as :func:`spectral_exitance`.

    Examples
    --------
    At 10 µm and 300 K, ``hc/(λkT) ≈ 4.8``: Wien's form is 0.8 % below Planck's (Eq. (6.2)).

    >>> from targetacq.physics.radiometry import spectral_exitance, wien_spectral_exitance
    >>> print(f"{wien_spectral_exitance(10e-6, 300.0) / spectral_exitance(10e-6, 300.0):.4f}")
    0.9917
    """
    xp, (lam, t) = _arrays.arrays(wavelength, temperature, names=("wavelength", "temperature"))
    _arrays.require_positive("wavelength", lam, xp, "m")
    _arrays.require_finite("wavelength", lam, xp, "m")
    _arrays.require_nonnegative("temperature", t, xp, "K")
    return _arrays.result(FIRST_RADIATION_CONSTANT / lam**5 * xp.exp(-_x_from(lam * t, xp)))


def band_exitance(temperature: Array, band: Any, method: str = "planck") -> Any:
    """Blackbody exitance in a spectral band, Eq. (6.12) (``method="wien"``: Eq. (6.13)).

    Closed form (module docstring): for float64 NumPy input, tables of the series with a
    relative error below 1e-12 for any T >= 0 (about 1e-15 for the thermal bands at ordinary
    temperatures), about 20 ns a temperature; for other array namespaces and float32, the
    series themselves (about 1e-15).

    Parameters
    ----------
    temperature : array_like
        T [K], >= 0.
    band : (float, float) or str
        (λ1, λ2) [m] with ``0 <= λ1 < λ2`` (λ2 may be ``inf``), or a name from
        :data:`targetacq.physics.bands.BANDS` ("visible", "mwir", "lwir").
    method : {"planck", "wien"}

    Returns
    -------
    array_like
        M [W/m²]. Check values: 8–12 µm at 300 K ≈ 120.95 W/m²; (0, ∞) gives σT⁴.

    Examples
    --------
    The user guide's check values (numerical quadrature of Eq. (6.2) with CODATA constants):
    8–12 µm at 300 K ≈ 120.95 W/m², 3–5 µm ≈ 5.862 W/m², and the whole spectrum σT⁴ =
    459.30 W/m² (Eq. (6.1)).

    >>> import targetacq as ta
    >>> print(f"{ta.band_exitance(300.0, 'lwir'):.2f}")
    120.95
    >>> print(f"{ta.band_exitance(300.0, 'mwir'):.3f}")
    5.862
    >>> print(f"{ta.band_exitance(300.0, (1e-9, 1.0)):.2f}")
    459.30
    """
    if method not in BAND_EXITANCE_METHODS:
        raise ValueError(
            f"method must be one of {', '.join(BAND_EXITANCE_METHODS)}; got {method!r}"
        )
    low, high = band_limits(band)
    xp, (t,) = _arrays.arrays(temperature, names=("temperature",))
    _arrays.require_nonnegative("temperature", t, xp, "K")
    if method == "planck" and isinstance(t, (np.ndarray, np.generic)) and t.dtype == np.float64:
        return _arrays.result(_band_exitance_numpy(np.asarray(t), low, high))
    integrate = BAND_EXITANCE_METHODS[method]

    def kernel(part: Any) -> Any:
        x_short, x_long = _x_of(low, part, xp), _x_of(high, part, xp)
        if method == "planck" and _arrays.any_known(x_short < SMALL_X, xp):
            return _planck_hot_or_cool(part, x_short, x_long, low, high, xp)
        integral = integrate(x_short, x_long, xp)
        with np.errstate(over="ignore", invalid="ignore"):  # T⁴ beyond 1e308: inf, or NaN
            t2 = part * part
            return BAND_CONSTANT * t2 * t2 * integral

    return _arrays.result(_arrays.chunked_elementwise(kernel, t))


def _planck_hot_or_cool(t: Any, x_short: Any, x_long: Any, low: float, high: float, xp: Any) -> Any:
    """``K T⁴ ∫_{x_long}^{x_short} t³/(e^t − 1) dt`` for any finite T, and +inf at T = inf.

    Where both band edges lie on the small-x series (hot: ``x1 = c2/(λ1 T) < 2``), T⁴ would
    overflow above about 1e77 K while the integral underflows; there ``T⁴ x³ = T (c2/λ)³``, so
    ``K T⁴ I = K T [(c2/λ1)³ S(x1) − (c2/λ2)³ S(x2)]`` with ``S = I/x³`` (:func:`_small_series`):
    the same numbers, scaled before they are multiplied (Rayleigh–Jeans side of the band).
    """
    hot = x_short < SMALL_X
    u_short = SECOND_RADIATION_CONSTANT / low  # low > 0 wherever x_short is below the cap
    u_long = 0.0 if math.isinf(high) else SECOND_RADIATION_CONSTANT / high
    small_short = xp.minimum(x_short, SMALL_X)
    small_long = xp.minimum(x_long, SMALL_X)
    scaled = u_short**3 * _small_series(small_short, xp) - u_long**3 * _small_series(small_long, xp)
    cool_t = xp.where(hot, 0.0, t)
    cool = _band_integral_planck(xp.where(hot, X_CAP, x_short), xp.where(hot, X_CAP, x_long), xp)
    with np.errstate(over="ignore"):
        t2 = cool_t * cool_t
        cooled = BAND_CONSTANT * t2 * t2 * cool
    return xp.where(hot, BAND_CONSTANT * t * scaled, cooled)


def grey_body_exitance(emissivity: Array, temperature: Array, band: Any) -> Any:
    """Exitance of a grey body in a band, ``ε · M_band(T)`` [W/m²], Eqs. (6.4) and (6.12).

    Parameters
    ----------
    emissivity : array_like
        ε in [0, 1].
    temperature : array_like
        T [K], >= 0.
    band : str or (float, float)
        Band name or limits [m].

    Returns
    -------
    array_like
        [W/m²].

    Examples
    --------
    >>> bool(grey_body_exitance(0.5, 300.0, "lwir") == 0.5 * band_exitance(300.0, "lwir"))
    True
    """
    xp, (eps, t) = _arrays.arrays(emissivity, temperature, names=("emissivity", "temperature"))
    _arrays.require_unit_interval("emissivity", eps, xp)
    return _arrays.result(eps * band_exitance(t, band))


def band_exitance_derivative(temperature: Array, band: Any) -> Any:
    """Temperature derivative of the blackbody band exitance, ``dM/dT`` [W m⁻² K⁻¹].

    Differentiating the closed form (module docstring) under ``x = c2/(λT)``, ``dx/dT = −x/T``:
    ``dM/dT = K T³ [4 I + g(x2) − g(x1)]`` with ``I = ∫_{x2}^{x1} t³/(e^t − 1) dt``,
    ``g(x) = x⁴/(e^x − 1)`` and ``K = 2π k⁴/(h³c²)``. Over all wavelengths it is ``4σT³``.
    Used to turn a background temperature spread into an exitance clutter.

    Parameters
    ----------
    temperature : array_like
        T [K], >= 0.
    band : (float, float) or str
        As in :func:`band_exitance`.

    Examples
    --------
    About 1.98 W m⁻² K⁻¹ in 8–12 µm at 300 K (a central difference of :func:`band_exitance` over
    ±0.01 K gives the same to 1e-9):

    >>> from targetacq.physics.radiometry import band_exitance, band_exitance_derivative
    >>> print(f"{band_exitance_derivative(300.0, 'lwir'):.4f}")
    1.9783
    >>> print(f"{(band_exitance(300.01, 'lwir') - band_exitance(299.99, 'lwir')) / 0.02:.4f}")
    1.9783
    """
    low, high = band_limits(band)
    xp, (t,) = _arrays.arrays(temperature, names=("temperature",))
    _arrays.require_nonnegative("temperature", t, xp, "K")
    x_short, x_long = _x_of(low, t, xp), _x_of(high, t, xp)
    # Hot (both edges on the small-x series): T³ I and T³ g(x) as (c2/λ)³ S(x) and
    # (c2/λ)³ x/(e^x − 1), finite up to T = inf (the Rayleigh–Jeans limit), as in band_exitance.
    hot = x_short < SMALL_X
    cool_t = xp.where(hot, 0.0, t)
    x_short_cool, x_long_cool = xp.where(hot, X_CAP, x_short), xp.where(hot, X_CAP, x_long)
    integral = _band_integral_planck(x_short_cool, x_long_cool, xp)

    def g(x: Any) -> Any:
        safe = xp.where(x > 0, x, 1.0)
        value = safe**4 * xp.exp(-safe) / -xp.expm1(-safe)
        return xp.where(x > 0, value, xp.zeros_like(x))

    def scaled(u: float, x: Any) -> Any:  # (c2/λ)³ [4 S(x) − x/(e^x − 1)]; 1/(e^x−1)·x → 1
        small = xp.minimum(x, SMALL_X)
        safe = xp.where(small > 0, small, 1.0)
        ratio = xp.where(small > 0, safe / xp.expm1(safe), xp.ones_like(small))
        return u**3 * (4.0 * _small_series(small, xp) - ratio)

    u_short = SECOND_RADIATION_CONSTANT / low if low > 0 else math.inf
    u_long = 0.0 if math.isinf(high) else SECOND_RADIATION_CONSTANT / high
    with np.errstate(over="ignore", invalid="ignore"):  # T³ beyond 1e308 where not hot
        cool = cool_t**3 * (4.0 * integral + g(x_long_cool) - g(x_short_cool))
    if not math.isinf(u_short) and _arrays.any_known(hot, xp):
        cool = xp.where(hot, scaled(u_short, x_short) - scaled(u_long, x_long), cool)
    return _arrays.result(BAND_CONSTANT * cool)


def stefan_boltzmann_exitance(temperature: Any) -> Any:
    """Total exitance of a blackbody, ``M = σ T⁴``, Eq. (6.1) [W/m²]; T [K] >= 0.

    Examples
    --------
    >>> from targetacq.physics.radiometry import stefan_boltzmann_exitance
    >>> print(f"{stefan_boltzmann_exitance(300.0):.2f}")
    459.30
    """
    xp, (t,) = _arrays.arrays(temperature, names=("temperature",))
    _arrays.require_nonnegative("temperature", t, xp, "K")
    return _arrays.result(STEFAN_BOLTZMANN * t**4)


def peak_wavelength(temperature: Array) -> Any:
    """Wavelength of maximum spectral exitance, ``λ_peak = b / T`` (Wien's displacement law).

    Parameters
    ----------
    temperature : array_like
        T [K], > 0.

    Returns
    -------
    array_like
        λ_peak [m]; 300 K → 9.659 µm.

    Examples
    --------
    Wien's displacement law at 300 K: ``2.8978e-3 / 300`` m, in the 8–12 µm band.

    >>> from targetacq.physics.radiometry import peak_wavelength
    >>> print(f"{peak_wavelength(300.0) * 1e6:.3f} um")
    9.659 um
    """
    xp, (t,) = _arrays.arrays(temperature, names=("temperature",))
    _arrays.require_positive("temperature", t, xp, "K")
    return _arrays.result(WIEN_DISPLACEMENT / t)


def emissivity(exitance: Any, blackbody_exitance: Any) -> Any:
    """Emissivity ``ε = M / M_blackbody``, Eq. (6.4); both [W/m²], the second > 0.

    Examples
    --------
    >>> from targetacq.physics.radiometry import emissivity
    >>> print(f"{emissivity(400.0, 459.3):.4f}")
    0.8709
    """
    xp, (m, mb) = _arrays.arrays(
        exitance, blackbody_exitance, names=("exitance", "blackbody_exitance")
    )
    _arrays.require_nonnegative("exitance", m, xp, "W/m²")
    _arrays.require_positive("blackbody_exitance", mb, xp, "W/m²")
    eps = m / mb
    _arrays.require_unit_interval("emissivity (exitance / blackbody_exitance)", eps, xp)
    return _arrays.result(eps)


def emissivity_from_reflectance(reflectance: Array, transmittance: Array = 0.0) -> Any:
    """``ε = a = 1 − r − t``: Eq. (6.5) ``r + a + t = 1`` with Kirchhoff's law ``ε = a``.

    Parameters
    ----------
    reflectance : array_like
        r in [0, 1].
    transmittance : array_like, optional
        t in [0, 1]; 0 for an opaque body (then ``ε = 1 − r``).

    Examples
    --------
    Opaque with r = 0.2, then with 10 % transmitted as well:

    >>> from targetacq.physics.radiometry import emissivity_from_reflectance
    >>> print(f"{emissivity_from_reflectance(0.2):.2f} {emissivity_from_reflectance(0.2, 0.1):.2f}")
    0.80 0.70
    """
    xp, (r, tr) = _arrays.arrays(reflectance, transmittance, names=("reflectance", "transmittance"))
    _arrays.require_unit_interval("reflectance", r, xp)
    _arrays.require_unit_interval("transmittance", tr, xp)
    if bool(xp.any(r + tr > 1.0)):
        raise ValueError("reflectance + transmittance must be <= 1 (Eq. (6.5): r + a + t = 1)")
    return _arrays.result(1.0 - r - tr)


@functools.cache
def _reflectance_table() -> dict[tuple[str, ...], tuple[float, float]]:
    # Percent in the table, fractions inside.
    return load_table("reflectance").keyed_ranges(
        ("material", "band"), "low_percent", "high_percent", scale=1e-2
    )


MATERIALS: tuple[str, ...] = tuple(dict.fromkeys(m for m, _ in _reflectance_table()))
"""Materials of Table 6.1."""

REFLECTANCE_BOUNDS = ("low", "nominal", "high")


def material_reflectance(material: str, band: Any, bound: str = "nominal") -> float:
    """Reflectance of a Table 6.1 material in a band, as a fraction.

    Parameters
    ----------
    material : str
        One of :data:`MATERIALS` (olive-paint, white-paint, vegetation, loam, ice).
    band : str or (float, float)
        "visible", "mwir" or "lwir" (or their limits in metres).
    bound : {"low", "nominal", "high"}
        Low or high end of the printed range, or its midpoint (reflectances are fractions of
        order one; a midpoint is the natural centre, unlike the log-scale extinctions).

    Raises
    ------
    ValueError
        Unknown material, band or bound, or a cell the table leaves empty (ice, visible).

    Examples
    --------
    Olive paint in 8–12 µm, printed 17–23 % in Table 6.1:

    >>> from targetacq.physics.radiometry import material_reflectance
    >>> print([material_reflectance("olive-paint", "lwir", b) for b in ("low", "nominal", "high")])
    [0.17, 0.2, 0.23]
    """
    if material not in MATERIALS:
        raise ValueError(f"unknown material {material!r}; materials: {', '.join(MATERIALS)}")
    if bound not in REFLECTANCE_BOUNDS:
        raise ValueError(f"bound must be one of {', '.join(REFLECTANCE_BOUNDS)}; got {bound!r}")
    name = band_name(band)
    low, high = _reflectance_table()[material, name]
    if math.isnan(low):
        raise ValueError(f"Table 6.1 gives no reflectance for {material} in the {name} band")
    return {"low": low, "high": high, "nominal": 0.5 * (low + high)}[bound]


def material_emissivity(material: str, band: Any, bound: str = "nominal") -> float:
    """Emissivity ``1 − r`` of an opaque Table 6.1 material (Kirchhoff, Eq. (6.5)).

    ``bound`` refers to the reflectance: "low" reflectance gives the high emissivity.

    Examples
    --------
    >>> from targetacq.physics.radiometry import material_emissivity
    >>> print(f"{material_emissivity('olive-paint', 'lwir'):.2f}")
    0.80
    """
    return 1.0 - material_reflectance(material, band, bound)


def reflected_exitance(reflectance: Array, irradiance: Array) -> Any:
    """Exitance of reflected light, ``M = r · E`` (visible band, §6.2) [W/m²].

    Parameters
    ----------
    reflectance : array_like
        r in [0, 1].
    irradiance : array_like
        E on the surface [W/m²], >= 0 (e.g. sunlight in the band).

    Examples
    --------
    >>> from targetacq.physics.radiometry import reflected_exitance
    >>> print(f"{reflected_exitance(0.3, 1000.0):.1f}")
    300.0
    """
    xp, (r, e) = _arrays.arrays(reflectance, irradiance, names=("reflectance", "irradiance"))
    _arrays.require_unit_interval("reflectance", r, xp)
    _arrays.require_nonnegative("irradiance", e, xp, "W/m²")
    return _arrays.result(r * e)


def lambert_intensity(intensity: Array, angle: Array) -> Any:
    """Lambert's cosine law, ``I_φ = I_object cos φ``, Eq. (6.14).

    Parameters
    ----------
    intensity : array_like
        Intensity along the surface normal [W/sr].
    angle : array_like
        φ, angle between the normal and the line of sight [rad], in [0, π/2].

    Examples
    --------
    >>> import math
    >>> from targetacq.physics.radiometry import lambert_intensity
    >>> print(f"{lambert_intensity(10.0, math.radians(60.0)):.4f}")
    5.0000
    """
    xp, (i, phi) = _arrays.arrays(intensity, angle, names=("intensity", "angle"))
    _arrays.require_nonnegative("angle", phi, xp, "rad")
    _arrays.require_finite("angle", phi, xp, "rad")
    return _arrays.result(i * xp.cos(phi))


def irradiance_at_sensor(
    intensity: Array,
    range: Array,
    emission_angle: Array = 0.0,
    off_axis_angle: Array = 0.0,
    lens: bool = True,
) -> Any:
    """Irradiance at the sensor from a Lambertian source, Eqs. (6.15)–(6.17).

    Pinhole (6.16): ``E = I cos φ cos θ / R²``; lens (6.17): ``E = I cos⁴θ / R²`` (the cos⁴ fall-off
    of the image irradiance with the off-axis angle θ; the thesis drops cos φ there).

    Parameters
    ----------
    intensity : array_like
        I_object [W/sr].
    range : array_like
        R [m], > 0.
    emission_angle : array_like
        φ [rad] (pinhole only).
    off_axis_angle : array_like
        θ [rad]; cos⁴: 30° → 0.5625, 10° → 0.9406.
    lens : bool
        Eq. (6.17) when True, (6.16) when False.

    Examples
    --------
    10 W/sr at 100 m on axis, then 30° off axis through a lens (``cos⁴ 30° = 0.5625``,
    Eq. (6.17)):

    >>> import math
    >>> from targetacq.physics.radiometry import irradiance_at_sensor
    >>> print(f"{irradiance_at_sensor(10.0, 100.0):.4e}")
    1.0000e-03
    >>> print(f"{irradiance_at_sensor(10.0, 100.0, off_axis_angle=math.radians(30.0)):.4e}")
    5.6250e-04
    """
    xp, (i, r, phi, theta) = _arrays.arrays(
        intensity,
        range,
        emission_angle,
        off_axis_angle,
        names=("intensity", "range", "emission_angle", "off_axis_angle"),
    )
    _arrays.require_positive("range", r, xp, "m")
    _arrays.require_finite("emission_angle", phi, xp, "rad")
    _arrays.require_finite("off_axis_angle", theta, xp, "rad")
    c = xp.cos(theta)
    factor = c**4 if lens else xp.cos(phi) * c
    return _arrays.result(i * factor / (r * r))


def target_signal(
    emissivity: Array, exitance: Array, range: Array, off_axis_angle: Array = 0.0
) -> Any:
    """Signal of a homogeneous target at the sensor, ``o_max = ε M cos⁴θ / R²``, Eq. (6.18).

    The same applies to background cells; only ratios (SCR) and differences of such signals are
    used by the model, so the thesis's mixed normalisation is kept as printed.

    Parameters
    ----------
    emissivity : array_like
        ε in [0, 1].
    exitance : array_like
        Blackbody band exitance M [W/m²] (e.g. :func:`band_exitance`).
    range : array_like
        R [m], > 0.
    off_axis_angle : array_like
        θ [rad].

    Returns
    -------
    array_like
        o_max [W/m² per m²].

    Examples
    --------
    ε = 0.9 and 120.95 W/m² (8–12 µm at 300 K) at 1 km on axis: ``0.9 · 120.95 / 1000²``.

    >>> from targetacq.physics.radiometry import target_signal
    >>> print(f"{target_signal(0.9, 120.95, 1000.0):.4e}")
    1.0886e-04
    """
    xp, (eps, m, r, theta) = _arrays.arrays(
        emissivity,
        exitance,
        range,
        off_axis_angle,
        names=("emissivity", "exitance", "range", "off_axis_angle"),
    )
    _arrays.require_unit_interval("emissivity", eps, xp)
    _arrays.require_positive("range", r, xp, "m")
    _arrays.require_finite("off_axis_angle", theta, xp, "rad")
    return _arrays.result(eps * m * xp.cos(theta) ** 4 / (r * r))


def diurnal_temperature(hour: Array, mean: Array, amplitude: Array, peak_hour: Array = 14.0) -> Any:
    """A simple thermal daily cycle (§6.5): ``T = mean + amplitude · cos(2π (hour − peak)/24)``.

    The thesis names the daily cycle without a formula; a sinusoid per material with its own
    mean, amplitude and hour of maximum (default 14:00, the usual afternoon maximum of surface
    temperature) is this project's documented assumption. Materials that heat and cool fast
    (leaves) get a larger amplitude than slow ones (stone, §6.5).

    Parameters
    ----------
    hour : array_like
        Local solar time [h].
    mean : array_like
        Daily mean temperature [K], > 0.
    amplitude : array_like
        Half the daily swing [K], >= 0 and < mean.
    peak_hour : array_like
        Hour of the maximum [h].

    Returns
    -------
    array_like
        T [K].

    Examples
    --------
    A mean of 290 K and an amplitude of 5 K: the maximum at 14:00, the minimum twelve hours
    later, the mean six hours before the maximum:

    >>> from targetacq.physics.radiometry import diurnal_temperature
    >>> print([round(float(t), 6) for t in diurnal_temperature([14.0, 2.0, 8.0], 290.0, 5.0)])
    [295.0, 285.0, 290.0]
    """
    xp, (h, m, a, p) = _arrays.arrays(
        hour, mean, amplitude, peak_hour, names=("hour", "mean", "amplitude", "peak_hour")
    )
    _arrays.require_positive("mean", m, xp, "K")
    _arrays.require_nonnegative("amplitude", a, xp, "K")
    _arrays.require_finite("hour", h, xp, "h")
    _arrays.require_finite("peak_hour", p, xp, "h")
    if bool(xp.any(a >= m)):
        raise ValueError("amplitude must be smaller than the mean temperature [K]")
    return _arrays.result(m + a * xp.cos(2.0 * xp.pi * (h - p) / 24.0))


def quantisation_step(bits: int, span: Array) -> Any:
    """Smallest contrast step of an n-bit detector over its signal span (§6.8).

    ``step = span / (2ⁿ − 1)``: an n-bit detector has 2ⁿ levels, 2ⁿ − 1 steps between the
    lowest and highest signal it records. A contrast below one step can be lost entirely
    (both signals fall on the same level), so it is invisible to the model.

    Parameters
    ----------
    bits : int
        Bits per sample, >= 1.
    span : array_like
        Signal span covered by the levels (same unit as the contrast), > 0.

    Examples
    --------
    A 14-bit detector over a span of 100 (``100 / 16383``), an 8-bit one over 255:

    >>> from targetacq.physics.radiometry import quantisation_step
    >>> print(f"{quantisation_step(14, 100.0):.6f} {quantisation_step(8, 255.0):.1f}")
    0.006104 1.0
    """
    if not isinstance(bits, int) or isinstance(bits, bool) or bits < 1:
        raise ValueError(f"bits must be an integer >= 1, got {bits!r}")
    xp, (s,) = _arrays.arrays(span, names=("span",))
    _arrays.require_positive("span", s, xp)
    return _arrays.result(s / (2.0**bits - 1.0))


def sky_reflected_exitance(
    emissivity: Array, temperature: Array, sky_temperature: Array, band: Any
) -> Any:
    """Apparent band exitance of an opaque grey surface that reflects the sky [W/m²].

    ``M_app = ε M_band(T) + (1 − ε) M_band(T_sky)``: the surface emits ``ε M_band(T)``, Eqs.
    (6.4) and (6.12) in Sonesson (2004), and, being opaque, reflects ``r = 1 − ε`` (Eq. (6.5)
    with ``t = 0`` and Kirchhoff's ``a = ε``) of the sky's radiation, the sky taken as a
    blackbody at an effective sky temperature ``T_sky`` (the temperature of the blackbody whose
    band exitance equals the sky's downwelling radiation in the band, e.g. measured with a
    radiometer pointed at the sky). This is the effect of §6.3: a low-emissivity (highly
    reflective) surface under a clear, cold sky appears colder than its surroundings, "a large
    negative contrast to the background"; under an overcast sky at about the air's temperature
    it almost vanishes. Reflection is taken as diffuse (Lambertian), the sky as uniform.

    ``ε = 1`` gives ``M_band(T)`` exactly, whatever the sky (:func:`grey_body_exitance`);
    ``T_sky = 0`` gives ``ε M_band(T)``, a surface that reflects nothing.

    Parameters
    ----------
    emissivity : array_like
        ε in [0, 1].
    temperature : array_like
        T of the surface [K], >= 0.
    sky_temperature : array_like
        Effective sky temperature T_sky [K], >= 0.
    band : str or (float, float)
        Band name or limits [m].

    Returns
    -------
    array_like
        [W/m²].

    Examples
    --------
    A surface of ε = 0.1 at 300 K under a 250 K sky in 8–12 µm appears colder than a blackbody
    background at 295 K (a negative contrast):

    >>> m_t = sky_reflected_exitance(0.1, 300.0, 250.0, "lwir")
    >>> bool(m_t < band_exitance(295.0, "lwir"))
    True
    >>> bool(sky_reflected_exitance(1.0, 300.0, 250.0, "lwir") == band_exitance(300.0, "lwir"))
    True
    """
    xp, (eps, t, t_sky) = _arrays.arrays(
        emissivity,
        temperature,
        sky_temperature,
        names=("emissivity", "temperature", "sky_temperature"),
    )
    _arrays.require_unit_interval("emissivity", eps, xp)
    _arrays.require_nonnegative("sky_temperature", t_sky, xp, "K")
    emitted = eps * band_exitance(t, band)
    # ε = 1 reflects nothing: leave the sky's term out there, so ε = 1 is M(T) to the last bit.
    reflected = xp.where(eps == 1.0, 0.0, (1.0 - eps) * band_exitance(t_sky, band))
    return _arrays.result(emitted + reflected)
