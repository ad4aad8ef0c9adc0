"""The limits every front-end checks at its boundary: physical domains and resource sizes.

One place for them, so the CLI, the scenario schema and the Python records refuse the same
values with the same words. A value outside its domain is not a model result waiting to happen:
it is a typo (``"720 deg"``), an overflow (``1e400`` reads as infinity) or a unit slip, and the
user is told which input and what the valid range is.

Physical domains
----------------
Temperatures are bounded above by :data:`MAX_TEMPERATURE`: the model's materials are solids
and vegetation, and far beyond it Planck's law overflows double precision in the thermal bands,
so an answer would come from an infinity rather than from physics. Depression angles lie in
[-90°, 90°] (straight up to straight down); azimuths and headings in [-360°, 360°] (one turn
either way, enough for any convention). Lengths and coordinates are bounded in magnitude by
:data:`MAX_LENGTH`, so that the geometry's squares and products stay far from overflow.

Resources
---------
A run's size (time steps × sensors × targets × runs) is known before anything is allocated.
:func:`check_size` refuses a size whose arrays would not fit in the memory this machine has
available, with a message saying how to make it smaller, instead of failing half-way with a
``MemoryError`` (or being killed by the system). Input files are read whole, so their size is
bounded too (:data:`MAX_INPUT_BYTES`, :mod:`targetacq.base.inputs`).
"""

from __future__ import annotations

import math
import os
from typing import Any

__all__ = [
    "BYTES_PER_EVALUATION",
    "MAX_ANGLE_TURN",
    "MAX_DECIBELS",
    "MAX_DEPRESSION",
    "MAX_ELEMENTS",
    "MAX_INPUT_BYTES",
    "MAX_LENGTH",
    "MAX_SEED",
    "MAX_TEMPERATURE",
    "available_memory",
    "check_count",
    "check_finite",
    "check_length",
    "check_range",
    "check_seed",
    "check_size",
    "check_temperature",
    "check_temperature_difference",
]

MAX_TEMPERATURE = 1.0e4
"""Highest temperature [K] accepted for a target, a background or a terrain class."""

MAX_LENGTH = 1.0e9
"""Largest length or coordinate magnitude [m]: a million kilometres.

Beyond any sensor's reach (the Moon is 3.8e8 m away), so no scene needs more; and the squares
and products of such lengths (1e18 m², 1e27 m³) stay far from the overflow of double precision
(1.8e308), which a coordinate like -6.56e193 m reaches in the geometry's ``x * x``."""

MAX_DEPRESSION = math.pi / 2
"""Largest depression angle magnitude [rad]: 90° below (or above) the horizon."""

MAX_ANGLE_TURN = 2 * math.pi
"""Largest azimuth or heading magnitude [rad]: one full turn either way."""

MAX_DECIBELS = 3000.0
"""Largest magnitude [dB] of a power ratio written in decibels: 10^±300 as a linear ratio.

``10 log10`` of the largest double is about 3,083 dB, so a larger value cannot become a linear
ratio (``10 ** (dB / 10)`` overflows); below about -3,076 dB the ratio loses precision and then
reads as 0. No antenna, receiver or backscatter comes near either end."""

MAX_SEED = 2**128 - 1
"""Largest seed: seeds are hashed as 16-byte unsigned integers (:mod:`targetacq.base.sampling`)."""

MAX_ELEMENTS = 2**40
"""Largest number of elements of any one result, whatever the memory (int64 index headroom)."""

MAX_INPUT_BYTES = 10 * 1000**2
"""Largest input file [bytes] read (a scenario, a CSV of boxes, an MRTD curve, a terrain map):
10 MB, far above any hand-written or exported file (:mod:`targetacq.base.inputs`)."""

BYTES_PER_EVALUATION = 1024
"""Memory [bytes] that one sensor × target × time of
:meth:`targetacq.run.model_chain.ModelChain.evaluate` takes at its peak, all its arrays together
(the intermediate arrays of the geometry and the transforms): measured between 180 and 800 bytes on
the bundled examples, 1024 taken."""

_FALLBACK_MEMORY = 4 * 2**30  # bytes, when the system does not say


def available_memory() -> int:
    """Bytes of memory available to a new allocation (``MemAvailable`` on Linux).

    Falls back to the physical memory, then to 4 GiB, where the system does not report it.
    """
    try:
        with open("/proc/meminfo", encoding="ascii") as info:
            for line in info:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return int(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (OSError, ValueError, AttributeError):
        return _FALLBACK_MEMORY


def check_size(elements: float, bytes_per_element: float, what: str, advice: str) -> None:
    """Raise ``ValueError`` if ``elements`` × ``bytes_per_element`` would not fit in memory.

    Parameters
    ----------
    elements : float
        How many elements the run will hold (e.g. times × sensors × targets); a float so that
        products of large counts do not overflow.
    bytes_per_element : float
        Bytes each element costs, all the run's arrays together.
    what : str
        The run, for the message (e.g. ``"time.step 1 ns from 0 s to 600 s"``).
    advice : str
        How to make it smaller (e.g. ``"use a longer time.step or a shorter time span"``).

    Examples
    --------
    >>> check_size(1e3, 8, "a small run", "no advice needed")
    >>> check_size(1e18, 8, "1e18 steps", "use fewer steps")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: 1e18 steps needs about 8e+18 bytes (7.45e+09 GiB); this machine has ... GiB ...
    """
    needed = float(elements) * float(bytes_per_element)
    if not math.isfinite(needed) or elements > MAX_ELEMENTS or needed > available_memory():
        raise ValueError(
            f"{what} needs about {needed:.3g} bytes ({needed / 2**30:.3g} GiB); "
            f"this machine has {available_memory() / 2**30:.3g} GiB available: {advice}"
        )


def check_finite(name: str, value: Any) -> float:
    """``value`` as a float, or ``ValueError`` naming ``name`` if it is NaN or infinite.

    Examples
    --------
    >>> check_finite("pitch", 1.7e-5)
    1.7e-05
    >>> check_finite("pitch", float("inf"))
    Traceback (most recent call last):
    ...
    ValueError: pitch must be finite; got inf (an overflowing number?)
    """
    number = float(value)
    if math.isnan(number):
        raise ValueError(f"{name} must be a number; got NaN")
    if math.isinf(number):
        raise ValueError(f"{name} must be finite; got {number:g} (an overflowing number?)")
    return number


def check_range(
    name: str, value: float, low: float, high: float, unit: str = "", scale: float = 1.0
) -> float:
    """``value`` if finite and in [``low``, ``high``], else ``ValueError`` naming the range.

    ``scale`` converts SI values to the ``unit`` shown in the message (e.g. 180/π for degrees).

    Examples
    --------
    >>> import math
    >>> check_range("depression", math.radians(720), -MAX_DEPRESSION, MAX_DEPRESSION, "deg",
    ...             180 / math.pi)
    Traceback (most recent call last):
    ...
    ValueError: depression must be in [-90, 90] deg; got 720 deg
    """
    number = check_finite(name, value)
    if not low <= number <= high:
        suffix = f" {unit}" if unit else ""
        raise ValueError(
            f"{name} must be in [{low * scale:g}, {high * scale:g}]{suffix}; "
            f"got {number * scale:g}{suffix}"
        )
    return number


def check_seed(seed: Any, name: str = "seed") -> int:
    """``seed`` if it is an integer in [0, :data:`MAX_SEED`], else ``ValueError``.

    Examples
    --------
    >>> check_seed(42)
    42
    >>> check_seed(-1)
    Traceback (most recent call last):
    ...
    ValueError: seed must be an integer in [0, 2**128 - 1]; got -1
    """
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed <= MAX_SEED:
        raise ValueError(f"{name} must be an integer in [0, 2**128 - 1]; got {seed!r}")
    return seed


def check_temperature(name: str, value: float) -> float:
    """``value`` [K] if it is a temperature in (0, :data:`MAX_TEMPERATURE`], else
    ``ValueError`` naming ``name`` and the domain.

    Examples
    --------
    >>> check_temperature("temperature", 305.0)
    305.0
    >>> check_temperature("--target-temperature", -5.0)
    Traceback (most recent call last):
    ...
    ValueError: --target-temperature must be in (0, 10000] K; got -5 K
    """
    number = check_finite(name, value)
    if not 0.0 < number <= MAX_TEMPERATURE:
        raise ValueError(f"{name} must be in (0, {MAX_TEMPERATURE:g}] K; got {number:g} K")
    return number


def check_temperature_difference(name: str, value: float, signed: bool = False) -> float:
    """``value`` [K] if it is a temperature difference at most :data:`MAX_TEMPERATURE` in size
    and >= 0 unless ``signed`` (a target colder than its background has a negative ΔT), else
    ``ValueError`` naming ``name`` and the domain.

    Examples
    --------
    >>> check_temperature_difference("netd", 0.05)
    0.05
    >>> check_temperature_difference("netd", -0.05)
    Traceback (most recent call last):
    ...
    ValueError: netd must be in [0, 10000] K; got -0.05 K
    >>> check_temperature_difference("--delta-t", -2.0, signed=True)
    -2.0
    """
    low = -MAX_TEMPERATURE if signed else 0.0
    return check_range(name, value, low, MAX_TEMPERATURE, "K")


def check_length(name: str, value: float, what: str = "") -> float:
    """``value`` [m] if it is finite and at most :data:`MAX_LENGTH` in magnitude, else
    ``ValueError`` naming ``name`` (``what``, if given, is said instead of "NAME": e.g.
    ``"coordinates"``).

    Examples
    --------
    >>> check_length("pitch", 1.7e-5)
    1.7e-05
    >>> check_length("--pitch", 1e12)
    Traceback (most recent call last):
    ...
    ValueError: --pitch must be within ±1e+09 m; got 1e+12 m
    >>> check_length("position", -6.56e193, "coordinates")
    Traceback (most recent call last):
    ...
    ValueError: position: coordinates must be within ±1e+09 m; got -6.56e+193 m
    """
    number = check_finite(name, value)
    if not abs(number) <= MAX_LENGTH:
        subject = f"{name}: {what}" if what else name
        raise ValueError(f"{subject} must be within ±{MAX_LENGTH:g} m; got {number:.3g} m")
    return number


def check_count(name: str, value: int, low: int = 1) -> int:
    """``value`` if it is a whole number in [``low``, :data:`MAX_ELEMENTS`] (a count of pixels,
    a pixel index), else ``ValueError`` naming ``name``; a number too long to read is shown by
    its digits.

    Examples
    --------
    >>> check_count("--pixels", 640)
    640
    >>> check_count("--pixels", 2**64)
    Traceback (most recent call last):
    ...
    ValueError: --pixels must be a whole number in [1, 1.1e+12]; got a number of 20 digits
    """
    if not low <= value <= MAX_ELEMENTS:
        digits = len(str(abs(value)))
        shown = str(value) if digits <= 15 else f"a number of {digits} digits"
        raise ValueError(
            f"{name} must be a whole number in [{low}, {MAX_ELEMENTS:.4g}]; got {shown}"
        )
    return value
