"""Exponential and logarithm for numba kernels, written so that LLVM vectorises them.

numba compiles ``math.exp`` and ``math.log`` to calls into the C library, one element at a time:
a loop that calls them cannot use the CPU's vector units (numba's own route to vectorised
transcendentals, Intel's SVML, needs a patched LLVM that the PyPI wheels do not have). The
functions here are plain arithmetic instead — range reduction by bit manipulation and a
polynomial — which LLVM turns into SIMD code inside a loop, with no branches (every special case
is a select at the end).

Accuracy: a few units in the last place over the whole double range (tested against NumPy to
4e-16 relative in ``tests/core/test_engines.py``):

- ``exp(x) = 2^k · e^r``, ``k = round(x / ln 2)``, ``r = x − k ln 2`` (ln 2 split in two parts so
  that ``k ln 2`` is exact), ``|r| <= ln 2 / 2``, ``e^r`` by its Taylor series to ``r^13``
  (truncation below 5e-18 relative); ``2^k`` assembled from its exponent bits in two halves so
  that results between 2^-1074 and 2^-1022 keep their subnormal precision.
- ``log(x) = e ln 2 + ln m``, ``x = 2^e · m`` with ``m`` in [√½, √2), and
  ``ln m = 2 atanh(s) = 2 (s + s³/3 + … + s²³/23)``, ``s = (m − 1)/(m + 1)``, ``|s| < 0.172``
  (truncation below 2e-19).
- ``expm1(x)``: the Taylor series to ``x^14`` for ``|x| < ln 2 / 2``, else ``exp(x) − 1``.

These are internal to the numba engine; importing this module imports numba.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from llvmlite import ir
from numba import njit, types
from numba.extending import intrinsic

__all__ = [
    "compiled",
    "exp",
    "expm1",
    "inline",
    "kernel",
    "log",
    "log10",
    "readonly",
    "writable",
]


def compiled(function: Callable[..., Any]) -> Any:
    """A kernel compiled by numba: cached on disk, NumPy's error model (a division by zero gives
    inf or NaN, as in NumPy, instead of raising, which also lets loops vectorise), no GIL."""
    return njit(cache=True, error_model="numpy", nogil=True)(function)


def readonly(ndim: int, dtype: Any = types.float64) -> Any:
    """The numba type of a kernel's input: a C-contiguous array the kernel only reads. Typed
    read-only, so that NumPy arrays of either kind convert to it (a writable array converts to a
    read-only type, not the reverse)."""
    return types.Array(dtype, ndim, "C", readonly=True)


def writable(ndim: int, dtype: Any = types.float64) -> Any:
    """The numba type of a kernel's output or work space: a C-contiguous writable array."""
    return types.Array(dtype, ndim, "C")


def kernel(*arguments: Any, returns: Any = types.void) -> Callable[[Callable[..., Any]], Any]:
    """:func:`compiled` with one signature, given: compiled when the module is imported (or loaded
    from numba's cache on disk), and never again for other argument types. Without it numba
    compiles one specialisation per combination of the arguments' types it meets (a read-only
    view and a writable array are two types), tens of seconds of CPU each; with it, arrays
    convert to the signature's types (C-contiguous arrays of the dtype and rank;
    :func:`readonly`), and anything else is a ``TypeError`` (the engine makes its arrays
    contiguous)."""
    signature = returns(*arguments)
    return njit(signature, cache=True, error_model="numpy", nogil=True)


def inline(function: Callable[..., Any]) -> Any:
    """:func:`compiled`, and inlined into its callers (so loops that call it vectorise)."""
    return njit(inline="always", cache=True, error_model="numpy", nogil=True)(function)


_LN2_HI = 6.93147180369123816490e-01  # ln 2 with its last 32 bits clear: k · _LN2_HI is exact
_LN2_LO = 1.90821492927058770002e-10  # ln 2 − _LN2_HI
_INV_LN2 = 1.0 / math.log(2.0)
_INV_LN10 = 1.0 / math.log(10.0)
_ROUND = 6755399441055744.0  # 1.5 · 2^52: x + _ROUND − _ROUND rounds x to an integer
_SMALLEST_NORMAL = 2.2250738585072014e-308
_SQRT2 = math.sqrt(2.0)
_INF = math.inf


@intrinsic
def _float_from_bits_ir(typingctx, bits):
    """Reinterpret the 64 bits of an int64 as a float64 (no conversion)."""
    if not isinstance(bits, types.Integer):
        return None

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.DoubleType())

    return types.float64(types.int64), codegen


@intrinsic
def _bits_from_float_ir(typingctx, value):
    """Reinterpret the 64 bits of a float64 as an int64 (no conversion)."""
    if not isinstance(value, types.Float):
        return None

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.IntType(64))

    return types.int64(types.float64), codegen


# Typed as Any: mypy sees the intrinsics' typing signature, not the call inside a kernel.
_float_from_bits: Any = _float_from_bits_ir
_bits_from_float: Any = _bits_from_float_ir


@inline
def _power_of_two(k):
    """2^k for an integer ``k`` in [-1022, 1023], from its exponent bits."""
    return _float_from_bits((k + 1023) << 52)


@inline
def exp(x):
    """e^x [1] (NaN → NaN, −inf → 0, +inf → +inf)."""
    clamped = x if x > -746.0 else -746.0  # also NaN → −746 (restored below)
    clamped = clamped if clamped < 710.0 else 710.0
    k = (clamped * _INV_LN2 + _ROUND) - _ROUND
    r = (clamped - k * _LN2_HI) - k * _LN2_LO
    p = 1.0 / 6227020800.0
    p = p * r + 1.0 / 479001600.0
    p = p * r + 1.0 / 39916800.0
    p = p * r + 1.0 / 3628800.0
    p = p * r + 1.0 / 362880.0
    p = p * r + 1.0 / 40320.0
    p = p * r + 1.0 / 5040.0
    p = p * r + 1.0 / 720.0
    p = p * r + 1.0 / 120.0
    p = p * r + 1.0 / 24.0
    p = p * r + 1.0 / 6.0
    p = p * r + 0.5
    p = p * r + 1.0
    p = p * r + 1.0
    whole = int(k)
    half = whole >> 1
    out = p * _power_of_two(half) * _power_of_two(whole - half)
    return x if x != x else out


@inline
def expm1(x):
    """e^x − 1 [1], accurate for small ``|x|``."""
    p = 1.0 / 87178291200.0
    p = p * x + 1.0 / 6227020800.0
    p = p * x + 1.0 / 479001600.0
    p = p * x + 1.0 / 39916800.0
    p = p * x + 1.0 / 3628800.0
    p = p * x + 1.0 / 362880.0
    p = p * x + 1.0 / 40320.0
    p = p * x + 1.0 / 5040.0
    p = p * x + 1.0 / 720.0
    p = p * x + 1.0 / 120.0
    p = p * x + 1.0 / 24.0
    p = p * x + 1.0 / 6.0
    p = p * x + 0.5
    p = p * x + 1.0
    small = p * x
    large = exp(x) - 1.0
    return small if abs(x) < 0.34657359027997264 else large


@inline
def log(x):
    """Natural logarithm [1] (0 → −inf, negative → NaN, +inf → +inf, NaN → NaN)."""
    tiny = x < _SMALLEST_NORMAL
    scaled = x * 4503599627370496.0 if tiny else x  # 2^52: subnormals become normal
    bits = _bits_from_float(scaled)
    exponent = ((bits >> 52) & 0x7FF) - 1023 - (52 if tiny else 0)
    m = _float_from_bits((bits & 0xFFFFFFFFFFFFF) | (1023 << 52))  # in [1, 2)
    big = m > _SQRT2
    m = m * 0.5 if big else m
    e = float(exponent + (1 if big else 0))
    s = (m - 1.0) / (m + 1.0)
    s2 = s * s
    q = 1.0 / 23.0
    q = q * s2 + 1.0 / 21.0
    q = q * s2 + 1.0 / 19.0
    q = q * s2 + 1.0 / 17.0
    q = q * s2 + 1.0 / 15.0
    q = q * s2 + 1.0 / 13.0
    q = q * s2 + 1.0 / 11.0
    q = q * s2 + 1.0 / 9.0
    q = q * s2 + 1.0 / 7.0
    q = q * s2 + 1.0 / 5.0
    q = q * s2 + 1.0 / 3.0
    log_m = 2.0 * s + 2.0 * s * s2 * q
    out = e * _LN2_HI + (log_m + e * _LN2_LO)
    out = -_INF if x == 0.0 else out
    out = _INF if x == _INF else out
    return out if x > 0.0 or x == 0.0 else (x if x != x else math.nan)


@inline
def log10(x):
    """Base-10 logarithm [1]."""
    return log(x) * _INV_LN10
