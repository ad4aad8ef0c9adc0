"""The atmosphere between target and sensor: extinction, transmittance, noise.

Sources: Sonesson (2004) ch. 7: Beer–Lambert (7.1)–(7.3), the band mean (7.4), Tables 7.1 and 7.2,
paths through regions of different conditions (§7.8), local obscurant clouds behind vehicles
(§7.5–7.7), and the SNR from transmittance (7.5)–(7.7). Foliage in front of a target (§6.8) acts as
a transmittance. Erratum to §7.4 (see the user guide's errata): 1 dB/km = 0.2303 Np/km (not
"Np/km = 0.23 dB/km").

Units: extinction coefficients are in Np/m inside (SI); the tables and the CLI use Np/km, converted
at the boundary. Visibility conventions are in the registry :data:`VISIBILITY_CONVENTIONS`.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping
from types import MappingProxyType
from typing import Any

import numpy as np

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.base.tables import load_table
from targetacq.physics.bands import BANDS, band_limits
from targetacq.physics.radiometry import band_exitance

__all__ = [
    "DB_PER_NEPER",
    "EXTINCTION_LEVELS",
    "EXTINCTION_LEVEL_WORDS",
    "OBSCURANTS",
    "VISIBILITY_CONVENTIONS",
    "band_transmittance",
    "cloud_transmittance",
    "contrast_transmittance",
    "db_per_km_to_np_per_km",
    "extinction_for_band",
    "extinction_from_visibility",
    "extinction_term",
    "foliage_transmittance",
    "np_per_km_to_db_per_km",
    "obscurant_extinction",
    "path_radiance",
    "path_transmittance",
    "segmented_optical_depth",
    "snr_from_optical_depth",
    "snr_from_transmittance",
    "sphere_chord_length",
    "transmittance",
    "visibility_from_extinction",
]

_LN10 = math.log(10.0)

DB_PER_NEPER = 10.0 / math.log(10.0)
"""Decibels per neper for power, 10·log10(e) ≈ 4.343 (so 1 dB = 0.2303 Np; erratum to §7.4)."""

VISIBILITY_CONVENTIONS: Mapping[str, float] = MappingProxyType(
    {
        # Koschmieder's visual range: contrast threshold 2 %, γ = −ln(0.02)/V ≈ 3.912/V.
        "koschmieder": -math.log(0.02),
        # Meteorological optical range (WMO): 5 % contrast threshold, γ = −ln(0.05)/V ≈ 2.996/V.
        "mor": -math.log(0.05),
    }
)
"""Visibility conventions: name → ``−ln(contrast threshold)``, with γ = value / V."""

EXTINCTION_LEVELS: tuple[str, ...] = ("low", "nominal", "high")
"""Where in a Table 7.1 cell: low end, geometric mean (nominal), high end."""

EXTINCTION_LEVEL_WORDS: Mapping[str, str] = MappingProxyType(
    {"low": "light", "nominal": "moderate", "high": "dense"}
)
"""How each level of :data:`EXTINCTION_LEVELS` reads in words: the low end of the fog cell of
a band is light fog in that band (whatever visual range Table 7.2 gives the same Np/km)."""


def transmittance(extinction: Array, range: Array) -> Any:
    """Beer–Lambert transmittance ``τ = exp(−γ R)``, Eq. (7.3) (and (7.1) for absorption alone).

    Parameters
    ----------
    extinction : array_like
        γ = K_α + K_σ (7.2) [Np/m], >= 0.
    range : array_like
        Path length R [m], >= 0.

    Returns
    -------
    array_like
        τ in [0, 1]; τ(0) = 1.

    Examples
    --------
    High haze in the long-wave band, 0.4 Np/km, over 2 km: ``exp(-0.8)``.

    >>> import targetacq as ta
    >>> print(f"{ta.transmittance(0.4e-3, 2000.0):.4f}")
    0.4493
    """
    xp, (g, r) = _arrays.arrays(extinction, range, names=("extinction", "range"))
    _arrays.require_nonnegative("extinction", g, xp, "Np/m")
    _arrays.require_nonnegative("range", r, xp, "m")
    return _arrays.result(xp.exp(-g * r))


def path_transmittance(extinctions: Array, lengths: Array, axis: int = -1) -> Any:
    """Transmittance of a path through segments, ``τ = exp(−Σ_j γ_j R_j)`` (§7.8).

    Parameters
    ----------
    extinctions : array_like
        γ_j of each segment [Np/m], >= 0; segments along ``axis``.
    lengths : array_like
        R_j of each segment [m], >= 0; broadcasts with ``extinctions``.
    axis : int
        The segment axis.

    Returns
    -------
    array_like
        τ, equal to the product of the segments' transmittances.

    Examples
    --------
    1 km at 0.4 Np/km then 500 m of fog at 2 Np/km: ``exp(-(0.4 + 1.0))``.

    >>> import targetacq as ta
    >>> print(f"{ta.path_transmittance([0.4e-3, 2e-3], [1000.0, 500.0]):.4f}")
    0.2466
    """
    xp, (g, r) = _arrays.arrays(extinctions, lengths, names=("extinctions", "lengths"))
    _arrays.require_nonnegative("extinctions", g, xp, "Np/m")
    _arrays.require_nonnegative("lengths", r, xp, "m")
    return _arrays.result(xp.exp(-xp.sum(g * r, axis=axis)))


def cloud_transmittance(
    extinction: Array, range: Array, cloud_extinction: Array, cloud_length: Array
) -> Any:
    """Transmittance with a local obscurant cloud crossed over part of the path (§7.5–7.7).

    Spray behind a vehicle on a wet road, dust on a dirt road, snow behind a fast vehicle: a
    cloud of extra extinction ``γ_cloud`` over a length ``L`` of the line of sight (at most the
    whole path): ``τ = exp(−γ R − γ_cloud · min(L, R))``.

    Parameters
    ----------
    extinction : array_like
        Ambient γ [Np/m], >= 0.
    range : array_like
        R [m], >= 0.
    cloud_extinction : array_like
        Extra extinction inside the cloud [Np/m], >= 0.
    cloud_length : array_like
        Length of the line of sight inside the cloud [m], >= 0.

    Examples
    --------
    2 km at 0.4 Np/km with 100 m of dust at 5 Np/km: ``exp(-0.8 - 0.5)``.

    >>> from targetacq.physics.atmosphere import cloud_transmittance
    >>> print(f"{cloud_transmittance(0.4e-3, 2000.0, 5e-3, 100.0):.4f}")
    0.2725
    """
    xp, (g, r, gc, lc) = _arrays.arrays(
        extinction,
        range,
        cloud_extinction,
        cloud_length,
        names=("extinction", "range", "cloud_extinction", "cloud_length"),
    )
    _arrays.require_nonnegative("extinction", g, xp, "Np/m")
    _arrays.require_nonnegative("range", r, xp, "m")
    _arrays.require_nonnegative("cloud_extinction", gc, xp, "Np/m")
    _arrays.require_nonnegative("cloud_length", lc, xp, "m")
    return _arrays.result(xp.exp(-g * r - gc * xp.minimum(lc, r)))


def foliage_transmittance(depth: Array, extinction: Array) -> Any:
    """Transmittance through foliage in front of a target (§6.8), ``τ_f = exp(−κ d)``.

    The thesis proposes modelling occlusion by trees and leaves as a transmittance that depends
    on the kind of forest and how deep in it the target stands, without numbers. This is the
    Beer–Lambert form of that idea: ``κ`` is the foliage's extinction per metre of line of sight
    (its leaf area density times the leaves' projection, a property of the forest type) and ``d``
    the path length through the foliage. It multiplies the atmosphere's transmittance, and so
    lowers the SNR of Eq. (7.7).

    Parameters
    ----------
    depth : array_like
        Line-of-sight length through foliage [m], >= 0.
    extinction : array_like
        κ [Np/m], >= 0.

    Examples
    --------
    5 m of foliage at 0.2 per metre: ``exp(-1)``.

    >>> from targetacq.physics.atmosphere import foliage_transmittance
    >>> print(f"{foliage_transmittance(5.0, 0.2):.4f}")
    0.3679
    """
    xp, (d, k) = _arrays.arrays(depth, extinction, names=("depth", "extinction"))
    _arrays.require_nonnegative("depth", d, xp, "m")
    _arrays.require_nonnegative("extinction", k, xp, "Np/m")
    return _arrays.result(xp.exp(-k * d))


def band_transmittance(extinction: Array, wavelength: Array, range: Array) -> Any:
    """Band-mean transmittance, Eq. (7.4): ``τ = 1/(λ2−λ1) ∫ exp(−γ(λ) R) dλ``.

    γ(λ) is given on a wavelength grid spanning the band; the integral is the trapezoid rule on
    that grid (exact for γ flat over the band, where (7.4) equals (7.3)).

    Parameters
    ----------
    extinction : array_like
        γ(λ) on the grid [Np/m], >= 0, along the last axis.
    wavelength : array_like
        Increasing grid λ [m], 1-D, the same length as the last axis of ``extinction``.
    range : array_like
        R [m], >= 0; broadcasts with ``extinction[..., 0]``.

    Examples
    --------
    A flat γ of 0.4 Np/km over 8–12 µm is Eq. (7.3), ``exp(-0.8)``; γ rising linearly from 0.2
    to 0.6 Np/km gives the trapezoid ``(exp(-0.4) + exp(-1.2)) / 2`` at 2 km:

    >>> from targetacq.physics.atmosphere import band_transmittance
    >>> print(f"{band_transmittance([0.4e-3, 0.4e-3], [8e-6, 12e-6], 2000.0):.4f}")
    0.4493
    >>> print(f"{band_transmittance([0.2e-3, 0.6e-3], [8e-6, 12e-6], 2000.0):.4f}")
    0.4858
    """
    xp, (g, lam, r) = _arrays.arrays(extinction, wavelength, range)
    _arrays.require_nonnegative("extinction", g, xp, "Np/m")
    _arrays.require_nonnegative("range", r, xp, "m")
    if lam.ndim != 1 or lam.shape[0] < 2 or g.shape[-1] != lam.shape[0]:
        raise ValueError(
            "wavelength must be a 1-D grid of >= 2 points matching extinction's last axis"
        )
    steps = lam[1:] - lam[:-1]
    if bool(xp.any(steps <= 0)):
        raise ValueError("wavelength grid must be strictly increasing")
    tau = xp.exp(-g * r[..., None])
    trapezoids = 0.5 * (tau[..., 1:] + tau[..., :-1]) * steps
    return _arrays.result(xp.sum(trapezoids, axis=-1) / (lam[-1] - lam[0]))


def db_per_km_to_np_per_km(value: Any) -> Any:
    """Convert an extinction in dB/km to Np/km: ×0.2303 (the erratum to §7.4).

    Examples
    --------
    The erratum to §7.4: 1 dB/km is 0.2303 Np/km.

    >>> from targetacq.physics.atmosphere import db_per_km_to_np_per_km
    >>> print(f"{db_per_km_to_np_per_km(1.0):.4f}")
    0.2303
    """
    _, (v,) = _arrays.arrays(value, names=("value",))
    return _arrays.result(v / DB_PER_NEPER)


def np_per_km_to_db_per_km(value: Any) -> Any:
    """Convert an extinction in Np/km to dB/km: ×4.343.

    Examples
    --------
    >>> from targetacq.physics.atmosphere import np_per_km_to_db_per_km
    >>> print(f"{np_per_km_to_db_per_km(1.0):.3f}")
    4.343
    """
    _, (v,) = _arrays.arrays(value, names=("value",))
    return _arrays.result(v * DB_PER_NEPER)


def _convention(convention: str | None) -> float:
    if convention is None:
        raise ValueError(
            "a visibility needs its convention: convention='koschmieder' (2 % contrast, "
            "3.912/V) or 'mor' (meteorological optical range, 5 %, 2.996/V)"
        )
    if convention not in VISIBILITY_CONVENTIONS:
        raise ValueError(
            f"convention must be one of {', '.join(VISIBILITY_CONVENTIONS)}; got {convention!r}"
        )
    return VISIBILITY_CONVENTIONS[convention]


def extinction_from_visibility(visibility: Array, convention: str | None = None) -> Any:
    """Visible-band extinction from a visibility, ``γ = −ln(C_threshold) / V``.

    Parameters
    ----------
    visibility : array_like
        V [m], > 0.
    convention : {"koschmieder", "mor"}
        Koschmieder's 2 % contrast threshold (γ = 3.912/V) or the meteorological optical
        range's 5 % (γ = 2.996/V). Required: the two differ by 30 %.

    Returns
    -------
    array_like
        γ [Np/m] at visible wavelengths (≈ 0.55 µm); infrared extinction differs (Table 7.1).

    Examples
    --------
    A 10 km visibility: Koschmieder's ``-ln(0.02) / V`` and the MOR's ``-ln(0.05) / V`` [Np/km].

    >>> import targetacq as ta
    >>> print(f"{ta.extinction_from_visibility(10e3, 'koschmieder') * 1e3:.4f}")
    0.3912
    >>> print(f"{ta.extinction_from_visibility(10e3, 'mor') * 1e3:.4f}")
    0.2996
    """
    k = _convention(convention)
    xp, (v,) = _arrays.arrays(visibility, names=("visibility",))
    _arrays.require_positive("visibility", v, xp, "m")
    return _arrays.result(k / v)


def visibility_from_extinction(extinction: Any, convention: str | None = None) -> Any:
    """Visibility [m] from a visible-band extinction [Np/m] > 0 (inverse of the above).

    Examples
    --------
    The round trip of :func:`extinction_from_visibility`:

    >>> from targetacq.physics.atmosphere import (
    ...     extinction_from_visibility,
    ...     visibility_from_extinction,
    ... )
    >>> gamma = extinction_from_visibility(10e3, "mor")
    >>> print(f"{visibility_from_extinction(gamma, 'mor'):.1f}")
    10000.0
    """
    k = _convention(convention)
    xp, (g,) = _arrays.arrays(extinction, names=("extinction",))
    _arrays.require_positive("extinction", g, xp, "Np/m")
    return _arrays.result(k / g)


@functools.cache
def _extinction_table() -> dict[tuple[str, ...], tuple[float, float]]:
    # Np/km in the table, Np/m inside.
    return load_table("extinction").keyed_ranges(
        ("obscurant", "band"), "low_np_per_km", "high_np_per_km", scale=1e-3
    )


OBSCURANTS: tuple[str, ...] = tuple(dict.fromkeys(o for o, _ in _extinction_table()))
"""Obscurants of Table 7.1: gases, haze, fog, rain, snow, dust."""


def obscurant_extinction(obscurant: str, band: Any, level: str = "nominal") -> float:
    """Extinction coefficient of an obscurant in a band, Table 7.1 in Sonesson (2004).

    Parameters
    ----------
    obscurant : str
        One of :data:`OBSCURANTS`.
    band : str or (float, float)
        "visible", "mwir" (3–5 µm) or "lwir" (8–12 µm), or limits (λ1, λ2) in metres. A band
        inside one of these reads its cell (Eq. (7.4) with γ flat over the band); a band between
        the visible and the mid-wave IR (the near- and short-wave IR windows, e.g. 0.9–2.5 µm)
        reads the cell ends interpolated log-log at its centre wavelength between the visible
        cell (at 0.55 µm) and the mid-wave cell (at 4 µm) — the project's approximation: the
        thesis gives no column there. Other bands (across the 5–8 µm water-vapour absorption,
        beyond 12 µm) are refused.
    level : {"low", "nominal", "high"}
        Low end, geometric mean (the cells span up to two decades) or high end of the cell.

    Returns
    -------
    float
        γ [Np/m].

    Examples
    --------
    Haze in 8–12 µm, Table 7.1's cell 0.02–0.4 Np/km: the geometric mean ``sqrt(0.02 · 0.4)``
    and the high end (in Np/km):

    >>> import targetacq as ta
    >>> print(f"{ta.obscurant_extinction('haze', 'lwir') * 1e3:.5f}")
    0.08944
    >>> print(f"{ta.obscurant_extinction('haze', 'lwir', 'high') * 1e3:.2f}")
    0.40

    Haze in a short-wave IR band, 0.9–2.5 µm (centre 1.7 µm), between the visible cell
    (0.2–2.0 Np/km) and the mid-wave cell (0.02–1.0 Np/km), high end in Np/km:

    >>> print(f"{ta.obscurant_extinction('haze', (0.9e-6, 2.5e-6), 'high') * 1e3:.3f}")
    1.348
    """
    if obscurant not in OBSCURANTS:
        raise ValueError(f"unknown obscurant {obscurant!r}; obscurants: {', '.join(OBSCURANTS)}")
    if level not in EXTINCTION_LEVELS:
        raise ValueError(f"level must be one of {', '.join(EXTINCTION_LEVELS)}; got {level!r}")
    low, high = _band_cell(obscurant, band_limits(band))
    return {"low": low, "high": high, "nominal": math.sqrt(low * high)}[level]


# The gaps between Table 7.1's bands that are read by interpolation: the visible to the
# mid-wave IR (the near- and short-wave IR windows). The 5-8 um gap is not: water vapour absorbs
# there, which the two windows' cells do not describe.
_INTERPOLATED_GAPS: tuple[tuple[str, str], ...] = (("visible", "mwir"),)


def _band_cell(obscurant: str, limits: tuple[float, float]) -> tuple[float, float]:
    """Table 7.1's (low, high) [Np/m] of an obscurant for a band: the cell of the named band the
    band lies in, or the cells at the ends of an interpolated gap, log-log at its centre."""
    table = _extinction_table()
    for name, (lo, hi) in BANDS.items():
        if lo * (1 - 1e-9) <= limits[0] and limits[1] <= hi * (1 + 1e-9):
            return table[obscurant, name]
    for short, long in _INTERPOLATED_GAPS:
        (a_lo, a_hi), (b_lo, b_hi) = BANDS[short], BANDS[long]
        if a_lo <= limits[0] and limits[1] <= b_hi:
            w = math.log(sum(limits) / (a_lo + a_hi)) / math.log((b_lo + b_hi) / (a_lo + a_hi))
            ends = zip(table[obscurant, short], table[obscurant, long], strict=True)
            low, high = (a * (b / a) ** w for a, b in ends)  # log-log: exact where a == b
            return low, high
    gaps = ", ".join(f"{a} and {b}" for a, b in _INTERPOLATED_GAPS)
    raise ValueError(
        f"Table 7.1 gives the bands {', '.join(BANDS)} (and a band inside one), interpolated "
        f"between {gaps}; got {limits[0] * 1e6:g}-{limits[1] * 1e6:g} um"
    )


@functools.cache
def _terms() -> tuple[tuple[str, float, float, str], ...]:
    table = load_table("extinction_terms")
    return tuple(
        (
            term,
            0.0 if math.isnan(lo) else lo / 1000.0,
            math.inf if math.isnan(hi) else hi / 1000.0,
            vr,
        )
        for term, lo, hi, vr in zip(
            table.column("term"),
            table.numbers("low_np_per_km"),
            table.numbers("high_np_per_km"),
            table.column("visual_range"),
            strict=True,
        )
    )


def extinction_term(extinction: float) -> tuple[str, str]:
    """Descriptive term and visual range of an extinction, Table 7.2 in Sonesson (2004).

    Parameters
    ----------
    extinction : float
        γ [Np/m], >= 0 (+inf: an opaque path, "high").

    Returns
    -------
    (term, visual_range) : (str, str)
        E.g. ``("medium", "2 - 6 km, hazy")`` for 1 Np/km.

    Examples
    --------
    >>> extinction_term(1e-3)
    ('medium', '2 - 6 km, hazy')
    >>> extinction_term(float("inf"))
    ('high', '< 2 km, foggy')
    """
    value = float(_arrays.as_float(extinction, _arrays.namespace(), "extinction"))
    if math.isnan(value) or value < 0:
        raise ValueError(f"extinction must be >= 0 Np/m, got {extinction!r}")
    # The rows run up from 0; the last one is unbounded and holds +inf too (an opaque path).
    for term, _low, high, visual_range in _terms():
        if value < high or math.isinf(high):
            return term, visual_range
    raise ValueError(f"Table 7.2 has no row for an extinction of {value:g} Np/m")


def snr_from_transmittance(tau: Array) -> Any:
    """Signal-to-noise ratio of an attenuated signal, Eqs. (7.5)–(7.7) in Sonesson (2004).

    ``SNR = 20 log10(τ / (1 − τ))`` dB: the part of the signal lost, ``(1 − τ)·o``, counts as noise.
    τ = 1 → +inf, τ = 0.5 → 0 dB, τ = 0 → −inf. With ``τ = exp(−γR)`` this is
    ``−20 log10(exp(γR) − 1)`` (7.7).

    Parameters
    ----------
    tau : array_like
        Transmittance in [0, 1].

    Returns
    -------
    array_like
        SNR [dB].

    Examples
    --------
    A clear path, half the signal lost, and 90 % lost (``20 log10(0.1 / 0.9)``):

    >>> import targetacq as ta
    >>> [round(float(x), 4) for x in ta.snr_from_transmittance([1.0, 0.5, 0.1])]
    [inf, 0.0, -19.0849]
    """
    xp, (t,) = _arrays.arrays(tau, names=("tau",))
    _arrays.require_unit_interval("tau", t, xp)
    inner = (t > 0) & (t < 1)
    safe = xp.where(inner, t, 0.5)
    snr = 20.0 * (xp.log10(safe) - xp.log10(1.0 - safe))
    snr = xp.where(t >= 1, xp.inf, xp.where(t <= 0, -xp.inf, snr))
    return _arrays.result(xp.where(xp.isnan(t), t, snr))


def snr_from_optical_depth(depth: Array) -> Any:
    """SNR of Eq. (7.7) from the optical depth ``d = γR`` (or ``Σ γ_j R_j``) directly [dB].

    ``−20 log10(e^d − 1) = 20 (−d / ln 10 − log10(1 − e^{−d}))``: the same as
    :func:`snr_from_transmittance` of ``τ = e^{−d}``, with one exponential and one logarithm
    fewer, and accurate where τ rounds to 1.

    Parameters
    ----------
    depth : array_like
        d >= 0 (0: no attenuation, +inf SNR; +inf: nothing left, −inf SNR).

    Examples
    --------
    An optical depth of ln 2 (τ = 0.5) gives 0 dB; a depth of 1 gives ``-20 log10(e − 1)``.

    >>> import math
    >>> from targetacq.physics.atmosphere import snr_from_optical_depth
    >>> print([round(float(x), 4) for x in snr_from_optical_depth([math.log(2.0), 1.0])])
    [0.0, -4.7019]
    """
    xp, (d,) = _arrays.arrays(depth, names=("depth",))
    _arrays.require_nonnegative("depth", d, xp)
    return _arrays.result(snr_db(d, xp))


def snr_db(d: Any, xp: Any) -> Any:
    """:func:`snr_from_optical_depth` of a checked float array (the arithmetic kernel).

    NumPy takes the formula alone where every depth is positive and finite (no guards needed);
    the numbers are the same.
    """
    if isinstance(d, np.ndarray) and d.ndim and d.size and d.min() > 0 and d.max() < math.inf:
        snr = np.negative(d)
        np.expm1(snr, out=snr)
        np.negative(snr, out=snr)
        np.log10(snr, out=snr)
        snr += d / _LN10  # 20 (−d / ln 10 − log10(1 − e^{−d})), the same operations
        snr *= -20.0
        return snr
    inner = (d > 0) & xp.isfinite(d)
    safe = xp.where(inner, d, 1.0)
    snr = 20.0 * (-safe / _LN10 - xp.log10(-xp.expm1(-safe)))
    snr = xp.where(d <= 0, xp.inf, xp.where(xp.isinf(d), -xp.inf, snr))
    return xp.where(xp.isnan(d), d, snr)


def sphere_chord_length(start: Array, end: Array, center: Array, radius: Any) -> Any:
    """Length of the segment from ``start`` to ``end`` inside a sphere [m].

    Used for a local cloud crossed by a line of sight (:func:`cloud_transmittance`).

    Parameters
    ----------
    start, end : array_like
        (..., 3) segment ends [m].
    center : array_like
        (3,) sphere centre [m].
    radius : float
        [m], > 0.

    Examples
    --------
    >>> float(sphere_chord_length([0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [5.0, 0.0, 0.0], 2.0))
    4.0
    """
    xp, (a, b, c, rad) = _arrays.arrays(
        start, end, center, radius, names=("start", "end", "center", "radius")
    )
    d = b - a
    length = xp.sqrt(xp.sum(d * d, axis=-1))
    safe = xp.where(length > 0, length, 1.0)
    u = d / safe[..., None]
    m = a - c
    bq = xp.sum(m * u, axis=-1)
    cq = xp.sum(m * m, axis=-1) - rad * rad
    disc = bq * bq - cq
    # 1, not 0, under the root where the line misses the sphere (masked below): sqrt has an
    # infinite slope at 0, which would make the gradient NaN there even though it is unused.
    root = xp.sqrt(xp.where(disc > 0, disc, 1.0))
    t0 = xp.clip(-bq - root, 0.0, length)
    t1 = xp.clip(-bq + root, 0.0, length)
    chord = xp.where((disc > 0) & (length > 0), t1 - t0, 0.0 * length)
    return _arrays.result(xp.where(xp.isnan(length), length, chord))


def segmented_optical_depth(
    range: Array, extinction: Array, segment_lengths: Any = (), segment_extinctions: Any = ()
) -> Any:
    """Optical depth of a line of sight through stretches of different extinction (§7.8).

    The path is ``extinction`` everywhere except the ``segments`` laid one after the other from
    the sensor outward: ``d = γ R + Σ_j (γ_j − γ) · clip(R − s_j, 0, L_j)`` with ``s_j`` the
    start of segment ``j`` (the sum of the lengths before it). A segment beyond the target adds
    nothing. ``τ = exp(−d)`` is Eq. (7.3) over a path of several regions.

    Parameters
    ----------
    range : array_like
        R [m], >= 0.
    extinction : array_like
        γ outside the segments [Np/m], >= 0, broadcasting with ``range``.
    segment_lengths : sequence of float or 0-d arrays
        L_j [m], >= 0 (0-d arrays, e.g. traced by JAX, stay arrays).
    segment_extinctions : sequence of array_like
        γ_j [Np/m], one per segment, each broadcasting with ``range``.

    Returns
    -------
    array_like
        d >= 0 [Np].

    Examples
    --------
    >>> float(segmented_optical_depth(1000.0, 1e-4, [200.0], [1e-3]))  # 0.1 + 0.9e-3 · 200
    0.28
    """
    xp, (r, g) = _arrays.arrays(range, extinction, names=("range", "extinction"))
    return _arrays.result(segmented_depth(r, g, segment_lengths, segment_extinctions, xp))


def segmented_depth(r: Any, g: Any, lengths: Any, gammas: Any, xp: Any) -> Any:
    """:func:`segmented_optical_depth` of float arrays (the arithmetic kernel)."""
    depth = g * r
    start = 0.0
    for length, gamma in zip(lengths, gammas, strict=True):
        inside = xp.clip(r - start, 0.0, length)
        depth = depth + (_arrays.as_float(gamma, xp) - g) * inside
        start = start + length
    return depth


def extinction_for_band(
    band: Any,
    *,
    extinction: Any = None,
    obscurant: str | None = None,
    visibility: Any = None,
    convention: str | None = None,
) -> float:
    """The path's extinction in a band from one description of the weather.

    One of: ``extinction`` itself; an ``obscurant`` of Table 7.1 as ``"name"`` or
    ``"name:level"`` (level low, nominal, high), read for the band; or a ``visibility`` with its
    ``convention`` (:func:`extinction_from_visibility`; the visible band's extinction). None of
    them: a clear path, 0.

    Parameters
    ----------
    band : str or (float, float)
        The sensor's band (name or limits [m]).
    extinction : float, optional
        γ [Np/m], >= 0.
    obscurant : str, optional
    visibility : float, optional
        [m], > 0.
    convention : {"koschmieder", "mor"}, optional

    Returns
    -------
    float
        γ [Np/m].

    Examples
    --------
    >>> round(extinction_for_band("lwir", obscurant="haze:high") * 1e3, 6)  # Np/km
    0.4
    """
    given = [v is not None for v in (extinction, obscurant, visibility)]
    if sum(given) > 1:
        raise ValueError("give one of extinction, obscurant and visibility")
    if extinction is not None:
        return float(extinction)
    if obscurant is not None:
        name, _, level = obscurant.partition(":")
        return obscurant_extinction(name, band, level or "nominal")
    if visibility is not None:
        return float(extinction_from_visibility(visibility, convention))
    return 0.0


# --------------------------------------------------------------------------------------------
# Path radiance (§7.2): the light the path adds
# --------------------------------------------------------------------------------------------


def contrast_transmittance(transmittance: Array, sky_to_ground: Array = 1.0) -> Any:
    """How much of an inherent contrast a path with airlight leaves, ``C_R / C_0`` [1].

    The law of contrast reduction (S. Q. Duntley, "The reduction of apparent contrast by the
    atmosphere", J. Opt. Soc. Am. 38 (1948) 179–191; W. E. K. Middleton, *Vision through the
    atmosphere*, University of Toronto Press 1952, ch. 4): along a uniform path the background's
    radiance ``L_b`` is attenuated to ``τ L_b`` and the path adds airlight ``(1 − τ) L_h``, the
    horizon sky's radiance ``L_h`` (the radiance of an infinitely long path), while the
    target–background difference is only attenuated, so the apparent contrast is

    ``C_R = C_0 τ L_b / (τ L_b + (1 − τ) L_h) = C_0 τ / (τ + (1 − τ) K)``,

    ``K = L_h / L_b`` the sky-to-ground ratio (equivalently ``C_0 / (1 + K (e^{γR} − 1))``, the
    form of the NVESD TV models). ``K = 1`` (a background as bright as the horizon sky) gives
    ``C_R = C_0 τ``, the contrast that the sensor-noise model uses without a ratio
    (:mod:`targetacq.physics.detector_noise`); ``K = 1`` with a black object (``C_0 = −1``) is
    Koschmieder's law ``C_R = −e^{−γR}``, whose 2 % point is the visual range
    (:data:`VISIBILITY_CONVENTIONS`). A background darker than the horizon sky (vegetation,
    forest) has ``K > 1`` and loses contrast faster than ``τ``; a brighter one (fresh snow,
    sunlit sand) ``K < 1``.

    For the reflective bands. In the thermal bands the path's own emission, :func:`path_radiance`,
    adds the same to target and background, so the exitance contrast is ``τ ΔM``.

    Parameters
    ----------
    transmittance : array_like
        τ of the path [1], in [0, 1].
    sky_to_ground : array_like, optional
        K = L_horizon / L_background [1], >= 0 (0: no airlight, the contrast is kept).

    Returns
    -------
    array_like
        ``τ / (τ + (1 − τ) K)`` in [0, 1]; 0 where τ = 0.

    Examples
    --------
    Koschmieder: a black object against the horizon sky at the visual range (τ = 0.02) keeps
    2 % contrast; a brighter sky (K = 3) leaves less:

    >>> from targetacq.physics.atmosphere import contrast_transmittance
    >>> print(round(float(contrast_transmittance(0.02)), 6))
    0.02
    >>> print(round(float(contrast_transmittance(0.5, 3.0)), 6))
    0.25
    """
    xp, (t, k) = _arrays.arrays(
        transmittance, sky_to_ground, names=("transmittance", "sky_to_ground")
    )
    _arrays.require_unit_interval("transmittance", t, xp)
    _arrays.require_nonnegative("sky_to_ground", k, xp)
    _arrays.require_finite("sky_to_ground", k, xp)
    denominator = t + (1.0 - t) * k
    positive = denominator > 0
    out = xp.where(positive, t / xp.where(positive, denominator, 1.0), 0.0)
    return _arrays.result(xp.where(xp.isnan(t) | xp.isnan(k), xp.nan, out))


def path_radiance(transmittance: Array, air_temperature: Array, band: Any) -> Any:
    """Thermal emission of the path in a band, as an exitance [W/m²]: ``(1 − τ) M_band(T_air)``.

    An absorbing, non-scattering path at one air temperature emits what it absorbs (Kirchhoff:
    its emissivity is its absorptance ``1 − τ``), the formal solution of Schwarzschild's equation
    for an isothermal layer (e.g. K. N. Liou, *An Introduction to Atmospheric Radiation*, 2nd ed.,
    Academic Press 2002, §4.1). The sensor sees ``τ M_t + (1 − τ) M_air`` from the target and
    ``τ M_b + (1 − τ) M_air`` from the background (§7.2: "other objects … transmit radiation,
    some of this … might be scattered in to the FOV, increasing the total energy"): the path
    radiance is added equally to both, so the exitance contrast at the sensor stays ``τ ΔM``
    and only the mean level rises. That is why the model's thermal contrast is ``τ ΔM`` with no
    path term (:mod:`targetacq.physics.detector_noise`); the path radiance matters for what is
    relative to the mean level (the reflective bands' :func:`contrast_transmittance`, a sensor
    whose noise grows with the photon flux).

    Parameters
    ----------
    transmittance : array_like
        τ of the path [1], in [0, 1].
    air_temperature : array_like
        T_air [K], >= 0.
    band : str or (float, float)
        Band name or limits [m].

    Returns
    -------
    array_like
        [W/m²].

    Examples
    --------
    Half the path absorbed, air at 290 K, 8–12 µm: half a 290 K blackbody's band exitance.

    >>> from targetacq.physics.atmosphere import path_radiance
    >>> from targetacq.physics.radiometry import band_exitance
    >>> bool(path_radiance(0.5, 290.0, "lwir") == 0.5 * band_exitance(290.0, "lwir"))
    True
    """
    xp, (t, air) = _arrays.arrays(
        transmittance, air_temperature, names=("transmittance", "air_temperature")
    )
    _arrays.require_unit_interval("transmittance", t, xp)
    _arrays.require_nonnegative("air_temperature", air, xp, "K")
    return _arrays.result((1.0 - t) * band_exitance(air, band))
