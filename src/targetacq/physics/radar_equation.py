"""Radar kernels: resolution cells, the radar range equation, rain, clutter and detection.

Sonesson (2004) §9.4.3 sketches a radar sensor for the conceptual model: the target's size in
resolution cells plays the part of the cycles on target, and the signal-to-noise and
signal-to-clutter ratios that of the thermal sensor's contrast. This module holds the physics:

* resolution along and across track, Eqs. (9.1) and (9.2), and the cells on a target;
* the radar range equation for a matched filter, with a one-way atmospheric transmittance;
* the ground-clutter cell and the signal-to-clutter ratio ``σ / (σ⁰ A)``;
* the specific attenuation of rain, Recommendation ITU-R P.838-3 (table ``rain_attenuation``);
* detection probability from SNR and false-alarm probability, in the registry
  :data:`RADAR_DETECTION_MODELS` (Albersheim, Swerling I, Marcum).

Units are SI, except the rain rate in mm/h and the specific attenuation in dB/km, the units of
the Recommendation, at that boundary. Ratios are **linear power ratios** (not the amplitude
decibels of Eq. (7.6) used by the electro-optical sensors); gains, noise figures and losses are
linear too (``10 ** (dB / 10)``). Inputs are checked as in :mod:`targetacq.base.arrays`: a bad value
raises ``ValueError`` naming the input and its valid range, NaN in an array comes out as NaN.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import array_api_compat
import numpy as np

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.base.constants import BOLTZMANN, SPEED_OF_LIGHT
from targetacq.base.registry import lookup
from targetacq.base.tables import load_table
from targetacq.physics.atmosphere import DB_PER_NEPER

__all__ = [
    "POLARIZATIONS",
    "RADAR_DETECTION_MODELS",
    "DetectionModel",
    "along_track_resolution",
    "cells_on_target",
    "clutter_area",
    "detection_probability",
    "radar_constant",
    "radar_snr",
    "rain_coefficients",
    "rain_extinction",
    "rain_specific_attenuation",
    "range_resolution",
    "required_snr",
    "signal_to_clutter",
]

_FOUR_PI_CUBED = (4.0 * math.pi) ** 3


def _require(name: str, value: Any, xp: Any, bad: Callable[[Any], Any], valid: str) -> None:
    """Raise ``ValueError`` naming the input unless no non-NaN element is ``bad`` (a scalar NaN
    raises too; nothing is checked on a traced value, as in :mod:`targetacq.base.arrays`)."""
    if _arrays.is_traced(value):
        return
    if value.ndim == 0 and _arrays.any_known(xp.isnan(value), xp):
        raise ValueError(f"{name} must be {valid}, got NaN")
    mask = bad(value)
    if _arrays.any_known(mask, xp):
        shown = value[mask] if value.ndim else value
        first = float(xp.reshape(shown, (-1,))[0])
        more = " (and possibly others)" if value.ndim else ""
        raise ValueError(f"{name} must be {valid}, got {first:g}{more}")


def _finite_positive(name: str, value: Any, xp: Any, unit: str) -> None:
    _arrays.require_positive(name, value, xp, unit)
    _arrays.require_finite(name, value, xp, unit)


def along_track_resolution(range: Array, beamwidth: Array) -> Any:
    """Resolution along track (cross range) of a real-aperture radar, Eq. (9.1) in Sonesson (2004).

    ``r_a = 2 R sin(θ_a / 2)`` [m]: the width of the beam at the target.

    Parameters
    ----------
    range : array_like
        Slant range R [m], >= 0 (+inf gives +inf).
    beamwidth : array_like
        Azimuth beamwidth θ_a [rad], in the open interval (0, π).

    Examples
    --------
    A 1° beam at 10 km is 174.5 m wide:

    >>> import math
    >>> print(f"{along_track_resolution(10e3, math.radians(1.0)):.1f}")
    174.5
    """
    xp, (r, b) = _arrays.arrays(range, beamwidth, names=("range", "beamwidth"))
    _arrays.require_nonnegative("range", r, xp, "m")
    _require("beamwidth", b, xp, lambda v: (v <= 0) | (v >= math.pi), "in (0, π) rad")
    return _arrays.result(2.0 * r * xp.sin(0.5 * b))


def range_resolution(pulse_length: Array, nadir_angle: Array) -> Any:
    """Resolution across track on the ground, Eq. (9.2) in Sonesson (2004).

    ``r_r = c τ / (2 sin θ)`` with θ the angle of the line of sight from nadir: the slant-range
    cell ``c τ / 2`` projected on the horizontal. Looking straight down (θ = 0) or up (θ = π)
    gives no ground-range resolution, +inf; above π/2 the target is above the radar, and the
    projection is that of π − θ. c is :data:`targetacq.base.constants.SPEED_OF_LIGHT` (exact).

    Parameters
    ----------
    pulse_length : array_like
        Compressed pulse length τ [s], > 0 and finite.
    nadir_angle : array_like
        θ [rad], in [0, π] (π/2: level, the slant-range cell itself).

    Returns
    -------
    array_like
        r_r [m], +inf where θ = 0 or π.

    Examples
    --------
    A 1 µs pulse seen 60° from nadir, and looking straight down:

    >>> import math
    >>> print(f"{range_resolution(1e-6, math.radians(60.0)):.2f}")
    173.09
    >>> float(range_resolution(1e-6, 0.0))
    inf
    """
    xp, (tau, theta) = _arrays.arrays(
        pulse_length, nadir_angle, names=("pulse_length", "nadir_angle")
    )
    _finite_positive("pulse_length", tau, xp, "s")
    _arrays.require_in_range("nadir_angle", theta, xp, 0.0, math.pi, "rad")
    vertical = (theta <= 0.0) | (theta >= math.pi)
    cell = 0.5 * SPEED_OF_LIGHT * tau / xp.sin(xp.where(vertical, 1.0, theta))
    cell = xp.where(vertical, xp.inf, cell)
    return _arrays.result(xp.where(xp.isnan(tau), xp.nan, cell))


def cells_on_target(critical_dimension: Array, along_track: Array, across_track: Array) -> Any:
    """Resolution cells across a target's critical dimension, ``n = d / sqrt(r_a · r_r)`` [1].

    The project's assumption (the thesis gives no formula): the cells on target are the critical
    dimension over the geometric mean of the cell's two sides. The critical dimension is itself
    the square root of the target's area, ``d = sqrt(A)`` (§3.2), so ``n`` is the square root of
    the number of cells on that area, ``sqrt(A / (r_a r_r))``: the radar analogue of the cycles
    across the critical dimension of the electro-optical sensors.

    Parameters
    ----------
    critical_dimension : array_like
        d [m], >= 0 and finite.
    along_track, across_track : array_like
        r_a and r_r [m] (:func:`along_track_resolution`, :func:`range_resolution`), > 0;
        +inf (no resolution) gives 0 cells.

    Examples
    --------
    A 2.3 m target in 1 m × 4 m cells: ``2.3 / 2``.

    >>> float(cells_on_target(2.3, 1.0, 4.0))
    1.15
    """
    xp, (d, ra, rr) = _arrays.arrays(
        critical_dimension,
        along_track,
        across_track,
        names=("critical_dimension", "along_track", "across_track"),
    )
    _arrays.require_nonnegative("critical_dimension", d, xp, "m")
    _arrays.require_finite("critical_dimension", d, xp, "m")
    _arrays.require_positive("along_track", ra, xp, "m")
    _arrays.require_positive("across_track", rr, xp, "m")
    return _arrays.result(d / (xp.sqrt(ra) * xp.sqrt(rr)))


def radar_constant(
    power: Array,
    gain: Array,
    wavelength: Array,
    pulse_length: Array,
    noise_figure: Array,
    losses: Array,
    temperature: Array = 290.0,
) -> Any:
    """The radar's constant K of the range equation, ``SNR = K σ / R⁴`` [m²].

    ``K = P_t G² λ² τ / ((4π)³ k T₀ F L)``: the radar equation of Mahafza & Elsherbeni,
    *MATLAB Simulations for Radar Systems Design* (2004), Eq. (1.56), for a monostatic radar
    (one antenna, gain G both ways) and a matched filter, whose noise bandwidth is ``B = 1/τ``
    (their Eq. (1.57) is the same equation written with τ). k is
    :data:`targetacq.base.constants.BOLTZMANN` (CODATA, exact). With ``noise_figure = 1`` the
    ``temperature`` is the system noise temperature T_s.

    Parameters
    ----------
    power : array_like
        Peak transmitted power P_t [W], >= 0 and finite.
    gain : array_like
        Antenna gain G [1, linear], > 0 and finite.
    wavelength : array_like
        λ [m], > 0 and finite.
    pulse_length : array_like
        τ [s], > 0 and finite.
    noise_figure : array_like
        F [1, linear], >= 1 and finite.
    losses : array_like
        System losses L [1, linear], >= 1 and finite.
    temperature : array_like
        Reference noise temperature T₀ [K], > 0 and finite (290 K by convention).

    Returns
    -------
    array_like
        K [m²] (m⁴ of range per m² of radar cross section).

    Examples
    --------
    1 MW, 20 dB gain, 1 GHz, 0.2 µs, no noise figure nor losses, 290 K; the SNR of 1 m² at
    50 km in dB (the first example of MathWorks' ``radareqsnr``, which prints 5.5868):

    >>> import math
    >>> k = radar_constant(1e6, 100.0, 299792458.0 / 1e9, 0.2e-6, 1.0, 1.0)
    >>> print(f"{10 * math.log10(radar_snr(50e3, 1.0, k)):.4f}")
    5.5868
    """
    names = ("power", "gain", "wavelength", "pulse_length", "noise_figure", "losses", "temperature")
    xp, values = _arrays.arrays(
        power, gain, wavelength, pulse_length, noise_figure, losses, temperature, names=names
    )
    p, g, lam, tau, f, loss, t = values
    _arrays.require_nonnegative("power", p, xp, "W")
    _arrays.require_finite("power", p, xp, "W")
    for name, value, unit in (
        ("gain", g, ""),
        ("wavelength", lam, "m"),
        ("pulse_length", tau, "s"),
    ):
        _finite_positive(name, value, xp, unit)
    for name, value in (("noise_figure", f), ("losses", loss)):
        _require(name, value, xp, lambda v: v < 1.0, ">= 1 (a linear power ratio, not dB)")
        _arrays.require_finite(name, value, xp)
    _finite_positive("temperature", t, xp, "K")
    return _arrays.result(p * g * g * lam * lam * tau / (_FOUR_PI_CUBED * BOLTZMANN * t * f * loss))


def radar_snr(range: Array, rcs: Array, constant: Array, transmittance: Array = 1.0) -> Any:
    """Signal-to-noise ratio of a target by the radar range equation, ``SNR = K σ τ² / R⁴`` [1].

    The radar equation (Mahafza & Elsherbeni 2004, Eq. (1.56); :func:`radar_constant`) with the
    path's atmosphere: the echo travels the path twice, so the **one-way** power transmittance τ
    enters squared (``τ = exp(−γ R)``, e.g. :func:`rain_extinction` in
    :func:`targetacq.physics.atmosphere.transmittance`).

    Parameters
    ----------
    range : array_like
        R [m], > 0 (+inf: nothing comes back, SNR 0).
    rcs : array_like
        Radar cross section σ [m²], >= 0 and finite.
    constant : array_like
        K [m²] (:func:`radar_constant`), >= 0 and finite.
    transmittance : array_like
        One-way atmospheric power transmittance, in [0, 1].

    Returns
    -------
    array_like
        SNR, a linear power ratio (``10 log10`` for dB).

    Examples
    --------
    Half the power lost one way costs 6 dB (a factor 4) over the two-way path:

    >>> float(radar_snr(1000.0, 1.0, 1e12)), float(radar_snr(1000.0, 1.0, 1e12, 0.5))
    (1.0, 0.25)
    """
    xp, (r, s, k, tr) = _arrays.arrays(
        range, rcs, constant, transmittance, names=("range", "rcs", "constant", "transmittance")
    )
    _arrays.require_positive("range", r, xp, "m")
    for name, value, unit in (("rcs", s, "m²"), ("constant", k, "m²")):
        _arrays.require_nonnegative(name, value, xp, unit)
        _arrays.require_finite(name, value, xp, unit)
    _arrays.require_unit_interval("transmittance", tr, xp)
    square = r * r
    with np.errstate(over="ignore", divide="ignore", under="ignore"):
        return _arrays.result(k * s * tr * tr / square / square)


def clutter_area(along_track: Array, across_track: Array) -> Any:
    """Area of the ground-clutter resolution cell, ``A = r_a · r_r`` [m²].

    The ground seen in one cell behind (or around) the target: its clutter echo is ``σ⁰ A``.

    Parameters
    ----------
    along_track, across_track : array_like
        r_a and r_r [m], > 0 (+inf gives +inf).

    Examples
    --------
    >>> float(clutter_area(3.0, 5.0))
    15.0
    """
    xp, (ra, rr) = _arrays.arrays(along_track, across_track, names=("along_track", "across_track"))
    _arrays.require_positive("along_track", ra, xp, "m")
    _arrays.require_positive("across_track", rr, xp, "m")
    return _arrays.result(ra * rr)


def signal_to_clutter(rcs: Array, sigma0: Array, area: Array) -> Any:
    """Signal-to-clutter power ratio of a target in its resolution cell, ``σ / (σ⁰ A)`` [1].

    A power ratio of echoes (unlike the Schmieder–Weathersby SCR of §3.7, a ratio of contrasts).

    Parameters
    ----------
    rcs : array_like
        The target's radar cross section σ [m²], >= 0 and finite.
    sigma0 : array_like
        The ground's normalized radar cross section σ⁰ [m²/m², linear], >= 0 and finite.
    area : array_like
        The clutter cell A [m²] (:func:`clutter_area`), >= 0 (+inf allowed).

    Returns
    -------
    array_like
        SCR: +inf where there is no clutter (σ⁰ A = 0) and σ > 0; 0 where σ = 0.

    Examples
    --------
    A 10 m² target in a 15 m² cell of σ⁰ = 0.01 (−20 dB):

    >>> print(f"{signal_to_clutter(10.0, 0.01, 15.0):.2f}")
    66.67
    """
    xp, (s, s0, a) = _arrays.arrays(rcs, sigma0, area, names=("rcs", "sigma0", "area"))
    for name, value, unit in (("rcs", s, "m²"), ("sigma0", s0, "m²/m²")):
        _arrays.require_nonnegative(name, value, xp, unit)
        _arrays.require_finite(name, value, xp, unit)
    _arrays.require_nonnegative("area", a, xp, "m²")
    none = (s0 == 0) | (a == 0)  # no clutter, even over an infinite cell
    clutter = xp.where(none, 0.0, s0 * xp.where(none, 1.0, a))
    ratio = s / xp.where(clutter > 0, clutter, 1.0)
    ratio = xp.where(clutter > 0, ratio, xp.where(s > 0, xp.inf, 0.0))
    ratio = xp.where(s == 0, 0.0, ratio)
    unknown = xp.isnan(s) | xp.isnan(s0) | xp.isnan(a)
    return _arrays.result(xp.where(unknown, xp.nan, ratio))


# ---------------------------------------------------------------------------- rain (ITU-R P.838-3)

POLARIZATIONS: Mapping[str, float] = MappingProxyType(
    {"horizontal": 1.0, "vertical": -1.0, "circular": 0.0}
)
"""Polarizations by name → ``cos 2τ`` of P.838-3 Eqs. (4)–(5), with τ the tilt of the
polarization from the horizontal: 0° (horizontal), 90° (vertical), 45° (circular)."""


@functools.cache
def _rain_table() -> dict[str, tuple[tuple[tuple[float, float, float], ...], float, float]]:
    """P.838-3 Tables 1–4: coefficient → ((a_j, b_j, c_j) per term, m, c)."""
    table = load_table("rain_attenuation")
    names = table.column("coefficient")
    a, b, c, m, c0 = (table.numbers(col) for col in ("a_j", "b_j", "c_j", "m", "c"))
    out = {}
    for name in dict.fromkeys(names):
        rows = [i for i, n in enumerate(names) if n == name]
        out[name] = (tuple((a[i], b[i], c[i]) for i in rows), m[rows[0]], c0[rows[0]])
    return out


def _regression(log_f: Any, name: str, xp: Any) -> Any:
    """``Σ_j a_j exp(−((log f − b_j)/c_j)²) + m log f + c``, P.838-3 Eqs. (2)–(3)."""
    terms, slope, constant = _rain_table()[name]
    total = slope * log_f + constant
    for a, b, c in terms:
        u = (log_f - b) / c
        total = total + a * xp.exp(-u * u)
    return total


def _rain_inputs(polarization: str, *values: Any) -> tuple[Any, list[Any], float]:
    """Check frequency, elevation (and a rain rate) in one namespace; ``cos 2τ`` by name."""
    cos_2tau = lookup(POLARIZATIONS, polarization, "polarization")
    names = ("frequency", "elevation", "rain_rate")[: len(values)]
    xp, arrays = _arrays.arrays(*values, names=names)
    _arrays.require_in_range("frequency", arrays[0], xp, 1e9, 1e12, "GHz", scale=1e-9)
    _arrays.require_in_range("elevation", arrays[1], xp, -0.5 * math.pi, 0.5 * math.pi, "rad")
    if len(arrays) > 2:
        _arrays.require_nonnegative("rain_rate", arrays[2], xp, "mm/h")
        _arrays.require_finite("rain_rate", arrays[2], xp, "mm/h")
    return xp, arrays, cos_2tau


def _coefficients(f: Any, e: Any, cos_2tau: float, xp: Any) -> tuple[Any, Any]:
    """k and α of P.838-3 Eqs. (2)–(5) for checked frequencies [Hz] and elevations [rad]."""
    log_f = xp.log10(f * 1e-9)
    kh = 10.0 ** _regression(log_f, "k_h", xp)
    kv = 10.0 ** _regression(log_f, "k_v", xp)
    ah = _regression(log_f, "alpha_h", xp)
    av = _regression(log_f, "alpha_v", xp)
    cos_e = xp.cos(e)
    tilt = cos_e * cos_e * cos_2tau
    k = 0.5 * (kh + kv + (kh - kv) * tilt)
    alpha = (kh * ah + kv * av + (kh * ah - kv * av) * tilt) / (2.0 * k)
    return k, alpha


def rain_coefficients(
    frequency: Array, polarization: str = "horizontal", *, elevation: Array = 0.0
) -> tuple[Any, Any]:
    """Coefficients k and α of the rain attenuation ``γ_R = k R^α``, ITU-R P.838-3.

    ``k_H``, ``k_V`` (Eq. (2)) and ``α_H``, ``α_V`` (Eq. (3)) from the regression constants of
    the Recommendation's Tables 1–4 (table ``rain_attenuation``), combined for the polarization
    tilt τ and path elevation θ by Eqs. (4)–(5):
    ``k = [k_H + k_V + (k_H − k_V) cos²θ cos 2τ] / 2`` and
    ``α = [k_H α_H + k_V α_V + (k_H α_H − k_V α_V) cos²θ cos 2τ] / (2k)``.

    Parameters
    ----------
    frequency : array_like
        f [Hz], in [1, 1000] GHz (the Recommendation's range).
    polarization : {"horizontal", "vertical", "circular"}
        :data:`POLARIZATIONS`.
    elevation : array_like
        Path elevation θ [rad], in [−π/2, π/2] (0: a horizontal path; only cos²θ enters).

    Returns
    -------
    k, alpha : array_like
        k [dB/km / (mm/h)^α] and α [1].

    Examples
    --------
    At 10 GHz, horizontal and vertical polarization:

    >>> k, a = rain_coefficients(10e9)
    >>> print(f"{k:.5f} {a:.4f}")
    0.01217 1.2571
    >>> k, a = rain_coefficients(10e9, "vertical")
    >>> print(f"{k:.5f} {a:.4f}")
    0.01129 1.2156
    """
    xp, (f, e), cos_2tau = _rain_inputs(polarization, frequency, elevation)
    k, alpha = _coefficients(f, e, cos_2tau, xp)
    return _arrays.result(k), _arrays.result(alpha)


def rain_specific_attenuation(
    rain_rate: Array, frequency: Array, polarization: str = "horizontal", *, elevation: Array = 0.0
) -> Any:
    """Specific attenuation of rain, ``γ_R = k R^α`` [dB/km], ITU-R P.838-3 Eq. (1).

    Parameters
    ----------
    rain_rate : array_like
        R [mm/h] (the Recommendation's unit), >= 0 and finite.
    frequency : array_like
        f [Hz], in [1, 1000] GHz.
    polarization : {"horizontal", "vertical", "circular"}
    elevation : array_like
        Path elevation [rad], in [−π/2, π/2].

    Returns
    -------
    array_like
        γ_R [dB/km] (one way, power); 0 for no rain.

    Examples
    --------
    Heavy rain, 25 mm/h, at 10 GHz: ``0.01217 · 25^1.2571``.

    >>> print(f"{rain_specific_attenuation(25.0, 10e9):.3f}")
    0.696
    """
    xp, (f, e, rate), cos_2tau = _rain_inputs(polarization, frequency, elevation, rain_rate)
    k, alpha = _coefficients(f, e, cos_2tau, xp)
    return _arrays.result(k * rate**alpha)


def rain_extinction(
    rain_rate: Any, frequency: Any, polarization: str = "horizontal", *, elevation: Any = 0.0
) -> Any:
    """Power extinction coefficient of rain [Np/m], from :func:`rain_specific_attenuation`.

    ``γ [Np/m] = γ_R [dB/km] · ln(10) / 10 / 1000``: a power attenuation of 1 dB is
    ``ln(10)/10 = 0.2303`` Np (:data:`targetacq.physics.atmosphere.DB_PER_NEPER`), and a kilometre
    is 1000 m. One way: ``τ = exp(−γ R)`` (:func:`targetacq.physics.atmosphere.transmittance`).

    Parameters
    ----------
    rain_rate, frequency, polarization, elevation
        As :func:`rain_specific_attenuation` (rain rate in mm/h, frequency in Hz).

    Examples
    --------
    1 dB/km is 0.2303 Np/km, 2.303e-4 Np/m:

    >>> gamma = rain_specific_attenuation(25.0, 10e9)
    >>> print(f"{rain_extinction(25.0, 10e9) / gamma * 1e3:.4f}")
    0.2303
    """
    db_per_km = rain_specific_attenuation(rain_rate, frequency, polarization, elevation=elevation)
    return db_per_km / DB_PER_NEPER / 1000.0


# ---------------------------------------------------------------------------------- detection


def _albersheim_pd(s: Any, pfa: Any, n: Any, xp: Any) -> Any:
    # 10^Z with Z = (10 log10 SNR + 5 log10 N) / (6.2 + 4.54/sqrt(N + 0.44)), as a power:
    # no logarithm of a zero SNR (10^Z = 0 there).
    a = xp.log(0.62 / pfa)
    scale = 6.2 + 4.54 / xp.sqrt(n + 0.44)
    power = (s * xp.sqrt(n)) ** (10.0 / scale)
    b = (power - a) / (1.7 + 0.12 * a)
    return 1.0 / (1.0 + xp.exp(-b))


def _albersheim_snr(pd: Any, pfa: Any, n: Any, xp: Any) -> Any:
    a = xp.log(0.62 / pfa)
    b = xp.log(pd / (1.0 - pd))
    argument = a + 0.12 * a * b + 1.7 * b
    usable = argument > 0
    scale = 6.2 + 4.54 / xp.sqrt(n + 0.44)
    db = scale * xp.log10(xp.where(usable, argument, 1.0)) - 5.0 * xp.log10(n)
    snr = xp.where(usable, 10.0 ** (db / 10.0), 0.0)  # at or below the floor: no signal needed
    return xp.where(xp.isnan(argument), xp.nan, snr)


def _swerling1_pd(s: Any, pfa: Any, n: Any, xp: Any) -> Any:
    return xp.where(xp.isnan(n), xp.nan, xp.exp(xp.log(pfa) / (1.0 + s)))


def _swerling1_snr(pd: Any, pfa: Any, n: Any, xp: Any) -> Any:
    snr = xp.maximum(xp.log(pfa) / xp.log(pd) - 1.0, 0.0)  # P_d <= P_fa: no signal needed
    return xp.where(xp.isnan(n), xp.nan, snr)


def _marcum_pd(s: Any, pfa: Any, n: Any, xp: Any) -> Any:
    from scipy import stats

    s, pfa, n = np.broadcast_arrays(s, pfa, n)
    unknown = np.isnan(s) | np.isnan(pfa) | np.isnan(n)
    finite = np.isfinite(s) & ~unknown
    dof = 2.0 * np.where(unknown, 1.0, n)
    threshold = stats.chi2.isf(np.where(unknown, 0.5, pfa), dof)
    pd = stats.ncx2.sf(threshold, dof, dof * np.where(finite, s, 0.0))
    return np.where(unknown, np.nan, np.where(finite, pd, 1.0))


def _marcum_snr(pd: Any, pfa: Any, n: Any, xp: Any) -> Any:
    # Bisection on ln SNR over [−40, 40] (P_d is increasing in SNR): 64 halvings, ~4e-18 wide.
    pd, pfa, n = np.broadcast_arrays(pd, pfa, n)
    low, high = np.full(pd.shape, -40.0), np.full(pd.shape, 40.0)
    for _ in range(64):
        middle = 0.5 * (low + high)
        above = _marcum_pd(np.exp(middle), pfa, n, xp) >= pd
        low, high = np.where(above, low, middle), np.where(above, middle, high)
    snr = np.where(pd <= pfa, 0.0, np.exp(0.5 * (low + high)))  # P_d(0) = P_fa
    return np.where(np.isnan(pd) | np.isnan(pfa) | np.isnan(n), np.nan, snr)


@dataclass(frozen=True)
class DetectionModel:
    """A detection model of :data:`RADAR_DETECTION_MODELS`.

    ``probability(snr, false_alarm, pulses, xp) -> P_d`` and its inverse
    ``required(detection, false_alarm, pulses, xp) -> SNR`` act on checked float arrays;
    ``single_pulse``: only ``pulses = 1`` is defined; ``traceable``: runs on any array-API
    namespace and under ``jax.jit`` (False: NumPy only).
    """

    name: str
    description: str
    source: str
    probability: Callable[..., Any]
    required: Callable[..., Any]
    single_pulse: bool = False
    traceable: bool = True


RADAR_DETECTION_MODELS: Mapping[str, DetectionModel] = MappingProxyType(
    {
        "albersheim": DetectionModel(
            "albersheim",
            "non-fluctuating target (Swerling 0), N pulses integrated non-coherently, linear "
            "detector: Albersheim's closed-form approximation, inverted for P_d",
            "W. J. Albersheim, 'A closed-form approximation to Robertson's detection "
            "characteristics', Proc. IEEE 69(7) (1981) 839; inverted as in M. A. Richards, "
            "'Alternative forms of Albersheim's equation' (2014), §2",
            _albersheim_pd,
            _albersheim_snr,
        ),
        "swerling1": DetectionModel(
            "swerling1",
            "Rayleigh-fluctuating target (Swerling I), single pulse, exact: P_d = P_fa^(1/(1+SNR))",
            "B. R. Mahafza and A. Z. Elsherbeni, MATLAB Simulations for Radar Systems Design "
            "(2004), Eq. (2.75)",
            _swerling1_pd,
            _swerling1_snr,
            single_pulse=True,
        ),
        "marcum": DetectionModel(
            "marcum",
            "non-fluctuating target (Swerling 0) in complex Gaussian noise, N pulses integrated "
            "non-coherently, square-law detector, exact (Marcum's Q; Q_1 for one pulse); NumPy "
            "and SciPy only",
            "M. A. Richards, Fundamentals of Radar Signal Processing, 2nd ed. (2014), §6.3.2, "
            "Eqs. (6.79) and (6.86)",
            _marcum_pd,
            _marcum_snr,
            traceable=False,
        ),
    }
)
"""Radar detection models by name (read-only); see :func:`detection_probability`."""


def _detection_inputs(
    method: str, p: Any, false_alarm: Any, pulses: Any, first: str
) -> tuple[DetectionModel, Any, list[Any]]:
    model = lookup(RADAR_DETECTION_MODELS, method, "radar detection model")
    xp, values = _arrays.arrays(p, false_alarm, pulses, names=(first, "false_alarm", "pulses"))
    _arrays.require_open_unit_interval("false_alarm", values[1], xp)
    n = values[2]
    whole = xp.isnan(n) | (xp.floor(n) == n)
    _require("pulses", n, xp, lambda v: (v < 1) | xp.isinf(v) | ~whole, "an integer >= 1")
    if model.single_pulse:
        _require("pulses", n, xp, lambda v: v > 1, f"1 for method {model.name!r} (single pulse)")
    if not model.traceable and not array_api_compat.is_numpy_namespace(xp):
        raise TypeError(f"method {model.name!r} runs on NumPy arrays only (it uses SciPy)")
    return model, xp, values


def detection_probability(
    snr: Array, false_alarm: Array, pulses: Any = 1, method: str = "albersheim"
) -> Any:
    """Probability of detecting a target from its per-pulse SNR and the false-alarm probability.

    ``"albersheim"`` (default; Albersheim 1981, inverted): with ``A = ln(0.62/P_fa)``,
    ``Z = (SNR_dB + 5 log10 N) / (6.2 + 4.54/sqrt(N + 0.44))``,
    ``B = (10^Z − A) / (1.7 + 0.12 A)``: ``P_d = 1 / (1 + e^(−B))``. Albersheim states an error
    under 0.2 dB in the SNR for 1e-7 <= P_fa <= 1e-3, 0.1 <= P_d <= 0.9, 1 <= N <= 8096. Checked
    against the exact Marcum form (tests), it holds within 0.2 dB for P_d >= 0.4 (N = 1), but
    not at low P_d: at P_d = 0.1 it asks 0.75 dB (P_fa = 1e-7) to 4.1 dB (P_fa = 1e-3) too
    little. Outside the range the formula is returned as it is: increasing in SNR and P_fa,
    → 1 as SNR → +inf, but as SNR → 0 it tends to a floor ``1 / (1 + e^(A/(1.7 + 0.12 A)))``
    (0.017 at P_fa = 1e-6), not to P_fa. It increases with N where ``SNR · sqrt(N) >= 1``.

    ``"swerling1"``: a Rayleigh-fluctuating target, one pulse, exact: ``P_d = P_fa^(1/(1+SNR))``
    (P_fa at SNR = 0). ``"marcum"``: exact for a steady target and a square-law detector,
    ``P_d = Q_N`` of the integrated statistic; NumPy only. See :data:`RADAR_DETECTION_MODELS`.

    Parameters
    ----------
    snr : array_like
        Mean signal-to-noise power ratio per pulse (linear), >= 0 (+inf allowed).
    false_alarm : array_like
        P_fa, in the open interval (0, 1).
    pulses : int or array_like
        Pulses integrated non-coherently, an integer >= 1 (1 for ``"swerling1"``).
    method : str
        A name of :data:`RADAR_DETECTION_MODELS`.

    Returns
    -------
    array_like
        P_d in [0, 1], increasing in SNR and in P_fa.

    Examples
    --------
    A steady target at 13.1 dB and a Swerling I target at 21.1 dB are both seen with
    P_d ≈ 0.9 at P_fa = 1e-6:

    >>> print(f"{detection_probability(10 ** 1.3115, 1e-6):.3f}")
    0.900
    >>> print(f"{detection_probability(10 ** 2.1144, 1e-6, method='swerling1'):.3f}")
    0.900
    """
    model, xp, (s, pfa, n) = _detection_inputs(method, snr, false_alarm, pulses, "snr")
    _arrays.require_nonnegative("snr", s, xp)
    return _arrays.result(model.probability(s, pfa, n, xp))


def required_snr(
    detection: Array, false_alarm: Any, pulses: Any = 1, method: str = "albersheim"
) -> Any:
    """Per-pulse SNR (linear) needed for a detection probability: the inverse of
    :func:`detection_probability`.

    ``"albersheim"``: Albersheim's equation itself,
    ``SNR_dB = −5 log10 N + (6.2 + 4.54/sqrt(N + 0.44)) log10(A + 0.12 A B + 1.7 B)`` with
    ``B = ln(P_d / (1 − P_d))``. ``"swerling1"``: ``SNR = ln P_fa / ln P_d − 1``.
    ``"marcum"``: by bisection. 0 where P_d is reached without signal (at or below the floor
    of the method, see :func:`detection_probability`).

    Parameters
    ----------
    detection : array_like
        P_d, in the open interval (0, 1).
    false_alarm, pulses, method
        As :func:`detection_probability`.

    Examples
    --------
    P_d = 0.9 at P_fa = 1e-6 with 10 pulses, Albersheim [dB] (MathWorks' example "Designing a
    Basic Monostatic Pulse Radar" prints 4.9904):

    >>> import math
    >>> print(f"{10 * math.log10(required_snr(0.9, 1e-6, 10)):.4f}")
    4.9904
    """
    model, xp, (p, pfa, n) = _detection_inputs(method, detection, false_alarm, pulses, "detection")
    _arrays.require_open_unit_interval("detection", p, xp)
    return _arrays.result(model.required(p, pfa, n, xp))
