"""Reproducible random numbers from counters: Philox4x32-10, vectorised in NumPy.

Random outcomes must not depend on how a simulation is batched or ordered: the draw for one
sensor, target, step and run must be the same whether the run is simulated alone or among a
thousand, and whatever order the sensors are listed in. A counter-based generator gives exactly
that: each number is a pure function of a *key* (the seed and the names of the sensor and the
target, hashed) and a *counter* (the step, the run, the purpose of the draw). No generator state
is carried from one draw to the next and nothing is global.

The generator is Philox4x32 with 10 rounds (Salmon, Moraes, Dror & Shaw, "Parallel random
numbers: as easy as 1, 2, 3", SC'11, 2011), the same family as NumPy's ``Philox``; it is checked
against the Random123 known-answer vectors in the tests.
"""

from __future__ import annotations

import hashlib
from typing import Any

import numpy as np

from targetacq.base.arrays import Array
from targetacq.base.limits import check_seed

__all__ = ["philox4x32", "stream_key", "uniforms"]

_M0, _M1 = np.uint64(0xD2511F53), np.uint64(0xCD9E8D57)
_W0, _W1 = np.uint32(0x9E3779B9), np.uint32(0xBB67AE85)
_LOW32 = np.uint64(0xFFFFFFFF)
_SHIFT = np.uint64(32)


def philox4x32(counter: Any, key: Any, rounds: int = 10) -> tuple[np.ndarray, ...]:
    """The Philox4x32 bijection: four 32-bit words of output per counter.

    Parameters
    ----------
    counter : sequence of 4 array_like of uint32
        The counter words, broadcasting together.
    key : sequence of 2 array_like of uint32
        The key words, broadcasting with the counter.
    rounds : int
        10 for Philox4x32-10.

    Returns
    -------
    tuple of 4 numpy.ndarray of uint32
    """
    c0, c1, c2, c3 = (np.asarray(c, dtype=np.uint32) for c in counter)
    k0, k1 = (np.asarray(k, dtype=np.uint32) for k in key)
    c0, c1, c2, c3, k0, k1 = np.broadcast_arrays(c0, c1, c2, c3, k0, k1)
    k0, k1 = k0.copy(), k1.copy()
    with np.errstate(over="ignore"):
        for r in range(rounds):
            if r:
                k0 = k0 + _W0
                k1 = k1 + _W1
            p0 = _M0 * c0.astype(np.uint64)
            p1 = _M1 * c2.astype(np.uint64)
            hi0, lo0 = (p0 >> _SHIFT).astype(np.uint32), (p0 & _LOW32).astype(np.uint32)
            hi1, lo1 = (p1 >> _SHIFT).astype(np.uint32), (p1 & _LOW32).astype(np.uint32)
            c0, c1, c2, c3 = hi1 ^ c1 ^ k0, lo1, hi0 ^ c3 ^ k1, lo0
    return c0, c1, c2, c3


def stream_key(seed: int, *names: str) -> tuple[int, int]:
    """A 64-bit Philox key from a seed and names (e.g. a sensor and a target), as two words.

    BLAKE2b of the seed and the names: the same on every machine and Python version, and
    independent of the order in which things are listed in a scenario. The seed is hashed as 16
    bytes, so it is an integer in [0, 2**128 - 1] (:func:`targetacq.base.limits.check_seed`).
    """
    check_seed(seed)
    digest = hashlib.blake2b(digest_size=8)
    digest.update(seed.to_bytes(16, "little", signed=False))
    for name in names:
        encoded = name.encode("utf-8")
        digest.update(len(encoded).to_bytes(4, "little") + encoded)
    value = int.from_bytes(digest.digest(), "little")
    return value & 0xFFFFFFFF, value >> 32


def uniforms(key: Any, step: Array, run: Array, purpose: int) -> np.ndarray:
    """Uniform numbers in (0, 1) for counters (step, run, purpose), 53 random bits each.

    Parameters
    ----------
    key : (array_like, array_like)
        Key words (from :func:`stream_key`), broadcasting with the counters.
    step, run : array_like of int
        Counter words, < 2³².
    purpose : int
        Which draw (a small integer naming its use), < 2³².

    Returns
    -------
    numpy.ndarray
        Floats in the open interval (0, 1), broadcast shape.
    """
    out = philox4x32(
        (
            np.asarray(step, dtype=np.uint32),
            np.asarray(run, dtype=np.uint32),
            np.uint32(purpose),
            np.uint32(0),
        ),
        key,
    )
    high = out[0].astype(np.uint64) >> np.uint64(5)  # 27 bits
    low = out[1].astype(np.uint64) >> np.uint64(6)  # 26 bits
    mantissa = (high << np.uint64(26)) | low
    return (mantissa.astype(np.float64) + 0.5) / 2.0**53
