"""The sensor's own noise: a signal-to-noise ratio from the apparent contrast and the sensor's
noise-equivalent contrast, combined with the atmosphere's.

The thesis names two sources of the SNR factor: "the atmospheric conditions and physical
properties of the sensor" (Sonesson 2004 §9.3). The atmosphere's is Eq. (7.7)
(:func:`targetacq.physics.atmosphere.snr_from_transmittance`); this module gives the sensor's, and
the rule that combines them. All three are the project's stated assumptions:

1. **Per pixel**: the contrast seen at the aperture, ``τ(R) · C``, over the sensor's
   noise-equivalent contrast ``NEC`` in the same unit: ``SNR_px = τ C / NEC``. For a thermal
   sensor ``C`` is the target–background exitance difference in its band and
   ``NEC = NETD · ∂M_bb,band/∂T`` at the NETD's reference temperature (the NETD is by definition
   the blackbody temperature difference that gives a signal equal to the noise); for small
   differences ``SNR_px = τ ΔT / NETD``. For a TV camera, ``C`` is the difference in reflected
   exitance and ``NEC`` the noise-equivalent contrast times the background's exitance. The
   atmosphere attenuates the contrast by ``τ``; its path radiance adds equally to target and
   background, so it does not change the difference (its fluctuation is the atmosphere's own
   noise term, Eq. (7.7)).
2. **Gain of the pixels on target** (:func:`pixel_gain`): an observer integrates the signal
   over the target's area, so the noise falls as the square root of the number of pixels ``n``
   it covers — the Rose model of visual detection (A. Rose, "The sensitivity performance of the
   human eye on an absolute scale", J. Opt. Soc. Am. 38 (1948) 196–208; the same spatial
   integration as the perceived SNR of thermal-imager models, G. C. Holst, *Electro-Optical
   Imaging System Performance*). ``g = sqrt(n)`` for ``n >= 1``; a target smaller than a pixel
   dilutes its contrast over the pixel, ``g = n`` for ``n < 1`` (the fill factor). Continuous at
   ``n = 1`` and increasing.
3. **Combination**: the sensor's and the atmosphere's noise are independent and add in variance,
   ``1/SNR² = Σ 1/SNR_i²`` (:func:`combined_snr`), in linear amplitude ratios
   (``SNR_lin = 10^(SNR_dB/20)``, the dB of Eq. (7.6)).

4. **Contrast-aware path noise** (:func:`contrast_snr`, the ``contrast`` law of
   :data:`targetacq.acquisition.path_noise.SNR_LAWS`): the path's own noise is the fluctuation of
   its path radiance, which is proportional to the path's emissivity ``1 − τ`` (Kirchhoff's law for
   the path; its radiance is ``(1 − τ)`` times that of a blackbody at the air's temperature,
   Sonesson 2004 §7.2). It is written as a noise-equivalent contrast ``(1 − τ) · σ_path``, with
   ``σ_path`` the contrast of the thesis's reference target, so that a target of contrast
   ``σ_path`` without sensor noise gets exactly the thesis's Eq. (7.7),
   ``SNR = τ / (1 − τ)``. Together with the sensor's noise, in variance:

   ``SNR = τ |C| / sqrt((NEC / g(n))² + ((1 − τ) σ_path)²)``

   — the apparent contrast against sensor noise plus path-radiance noise, τ counted once. The
   project's stated assumption for ``σ_path``: 1 K for a thermal sensor (in exitance, the same
   ``∂M_bb,band/∂T`` as the NETD: :func:`netd_exitance` of 1 K), a contrast ratio of 1 of the
   background's exitance for a reflective sensor. Unlike Eq. (7.7) + item 3 (the ``sonesson``
   law), a hotter target is seen farther through the same haze.

A zero contrast gives ``SNR = 0`` (−inf dB), whatever the range: the noise model then makes every
probability 0. No noise given (``NEC = 0``) gives +inf: the model is exactly the noise-free one.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array

__all__ = [
    "combined_snr",
    "contrast_snr",
    "netd_exitance",
    "pixel_gain",
    "pixels_on_target",
    "sensor_snr",
]


def netd_exitance(netd: Array, band: Any, reference_temperature: Array = 300.0) -> Any:
    """Noise-equivalent exitance difference of a thermal sensor [W/m²].

    ``NEΔM = NETD · ∂M_bb,band/∂T`` at the reference temperature at which the NETD is quoted
    (the band exitance (6.12) in Sonesson (2004), differentiated:
    :func:`targetacq.physics.radiometry.band_exitance_derivative`).

    Parameters
    ----------
    netd : array_like
        Noise-equivalent temperature difference [K], >= 0.
    band : str or (float, float)
        The sensor's band.
    reference_temperature : array_like
        Temperature at which the NETD is quoted [K], > 0 (datasheets: 300 K or 303 K).

    Returns
    -------
    array_like
        [W/m²].

    Examples
    --------
    >>> from targetacq.physics.radiometry import band_exitance_derivative
    >>> slope = float(band_exitance_derivative(300.0, "lwir"))
    >>> bool(abs(netd_exitance(0.05, "lwir") - 0.05 * slope) < 1e-12)
    True
    """
    from targetacq.physics.radiometry import band_exitance_derivative

    xp, (noise, reference) = _arrays.arrays(
        netd, reference_temperature, names=("netd", "reference_temperature")
    )
    _arrays.require_nonnegative("netd", noise, xp, "K")
    _arrays.require_positive("reference_temperature", reference, xp, "K")
    return _arrays.result(noise * band_exitance_derivative(reference, band))


def pixels_on_target(area: Array, range: Array, ifov: Array) -> Any:
    """Number of pixels a target covers, ``n = A / (R · IFOV)²`` [1].

    Parameters
    ----------
    area : array_like
        Area of the target's outline as seen [m²], >= 0.
    range : array_like
        Slant range [m], > 0.
    ifov : array_like
        Pixel IFOV [rad], > 0.

    Examples
    --------
    >>> float(pixels_on_target(2.3 * 4.6, 1000.0, 0.34e-3))
    91.522...
    """
    xp, (a, r, i) = _arrays.arrays(area, range, ifov, names=("area", "range", "ifov"))
    _arrays.require_nonnegative("area", a, xp, "m²")
    _arrays.require_positive("range", r, xp, "m")
    _arrays.require_positive("ifov", i, xp, "rad")
    return _arrays.result(pixels_on_target_unchecked(a, r, i))


def pixels_on_target_unchecked(a: Any, r: Any, i: Any) -> Any:
    """:func:`pixels_on_target` of checked float arrays (the arithmetic kernel)."""
    footprint = r * i
    return a / (footprint * footprint)


def pixel_gain(pixels: Array) -> Any:
    """SNR gain of integrating over the pixels on target: ``sqrt(n)`` for n >= 1, ``n`` below.

    The Rose model's spatial integration (module docstring, item 2).

    Parameters
    ----------
    pixels : array_like
        Pixels on target, >= 0.

    Examples
    --------
    >>> [float(g) for g in pixel_gain([0.25, 1.0, 100.0])]
    [0.25, 1.0, 10.0]
    """
    xp, (n,) = _arrays.arrays(pixels, names=("pixels",))
    _arrays.require_nonnegative("pixels", n, xp)
    return _arrays.result(_gain(n, xp))


def _gain(n: Any, xp: Any) -> Any:
    return xp.where(n >= 1.0, xp.sqrt(xp.maximum(n, 1.0)), n)


def sensor_snr(
    contrast: Array, noise_equivalent: Array, transmittance: Array, pixels: Array
) -> Any:
    """The sensor's SNR of a target [dB]: ``20 log10(τ |C| g(n) / NEC)``.

    Parameters
    ----------
    contrast : array_like
        Target–background contrast at the scene, in the unit of ``noise_equivalent``.
    noise_equivalent : array_like
        The sensor's noise-equivalent contrast, >= 0 (0: no sensor noise, +inf dB).
    transmittance : array_like
        τ of the path, in [0, 1].
    pixels : array_like
        Pixels on target (:func:`pixels_on_target`), >= 0.

    Returns
    -------
    array_like
        SNR [dB]: −inf for a zero contrast (or τ = 0) with noise, +inf without noise.

    Examples
    --------
    >>> round(float(sensor_snr(0.5, 0.05, 1.0, 1.0)), 6)  # ΔT / NETD = 10 on one pixel
    20.0
    >>> float(sensor_snr(0.0, 0.05, 1.0, 100.0))
    -inf
    """
    xp, (c, noise, tau, n) = _arrays.arrays(
        contrast,
        noise_equivalent,
        transmittance,
        pixels,
        names=("contrast", "noise_equivalent", "transmittance", "pixels"),
    )
    _arrays.require_nonnegative("noise_equivalent", noise, xp)
    _arrays.require_unit_interval("transmittance", tau, xp)
    _arrays.require_nonnegative("pixels", n, xp)
    return _arrays.result(sensor_db(c, noise, tau, n, xp)[0])


def sensor_db(c: Any, noise: Any, tau: Any, n: Any, xp: Any) -> tuple[Any, Any, Any]:
    """:func:`sensor_snr` of checked float arrays (the arithmetic kernel).

    Returns
    -------
    snr, inverse, unknown
        The SNR [dB], its noise-to-signal amplitude ratio ``NEC / (τ |C| g)`` (0 without noise,
        +inf without signal; not NaN-masked) and where an input is NaN.
    """
    signal = tau * xp.abs(c) * _gain(n, xp)
    quiet = noise == 0
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        ratio = xp.where(quiet, xp.inf, signal / xp.where(quiet, 1.0, noise))
        db = 20.0 * xp.log10(ratio)
        inverse = xp.where(quiet, 0.0, noise / xp.where(quiet, 1.0, signal))
    unknown = xp.isnan(c) | xp.isnan(noise) | xp.isnan(tau) | xp.isnan(n)
    return xp.where(unknown, xp.nan, db), inverse, unknown


def contrast_snr(
    contrast: Array,
    noise_equivalent: Array,
    path_contrast: Array,
    transmittance: Array,
    pixels: Array,
) -> Any:
    """The contrast-aware SNR of a target through a path [dB] (module docstring, item 4).

    ``SNR = τ |C| / sqrt((NEC / g(n))² + ((1 − τ) σ_path)²)``, ``g`` of :func:`pixel_gain`.

    Parameters
    ----------
    contrast : array_like
        Target–background contrast at the scene ``C``, in the unit of ``noise_equivalent``.
    noise_equivalent : array_like
        The sensor's noise-equivalent contrast ``NEC``, >= 0 (0: the path's noise alone).
    path_contrast : array_like
        ``σ_path``, the contrast whose target gets the thesis's Eq. (7.7), > 0, in the same unit
        (a thermal sensor in kelvin: 1 K).
    transmittance : array_like
        τ of the path, in [0, 1].
    pixels : array_like
        Pixels on target (:func:`pixels_on_target`), >= 0.

    Returns
    -------
    array_like
        SNR [dB]: −inf for a zero contrast (or τ = 0), +inf without any noise (``NEC = 0`` and
        ``τ = 1``).

    Examples
    --------
    Without the sensor's noise, a target of the reference contrast gets Eq. (7.7),
    ``20 log10(τ / (1 − τ))`` (0 dB at τ = 0.5); one 45 times hotter is 33 dB above it:

    >>> round(float(contrast_snr(1.0, 0.0, 1.0, 0.5, 100.0)), 6)
    0.0
    >>> round(float(contrast_snr(45.0, 0.0, 1.0, 0.5, 100.0)), 4)
    33.0643

    A 1 mK target on 100 pixels at 50 mK NETD through τ = 0.9: the path's noise (0.1 K) hides it.

    >>> round(float(contrast_snr(0.001, 0.05, 1.0, 0.9, 100.0)), 2)
    -40.93
    """
    xp, (c, noise, sigma, tau, n) = _arrays.arrays(
        contrast,
        noise_equivalent,
        path_contrast,
        transmittance,
        pixels,
        names=("contrast", "noise_equivalent", "path_contrast", "transmittance", "pixels"),
    )
    _arrays.require_nonnegative("noise_equivalent", noise, xp)
    _arrays.require_positive("path_contrast", sigma, xp)
    _arrays.require_unit_interval("transmittance", tau, xp)
    _arrays.require_nonnegative("pixels", n, xp)
    return _arrays.result(contrast_db(c, noise, sigma, tau, n, xp)[0])


def contrast_db(c: Any, noise: Any, sigma: Any, tau: Any, n: Any, xp: Any) -> tuple[Any, Any, Any]:
    """:func:`contrast_snr` of checked float arrays (the arithmetic kernel).

    Returns
    -------
    snr, inverse, unknown
        The SNR [dB], its noise-to-signal amplitude ratio
        ``sqrt((NEC/g)² + ((1 − τ) σ)²) / (τ |C|)`` (0 without any noise, +inf without signal;
        not NaN-masked) and where an input is NaN.
    """
    signal = tau * xp.abs(c)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        gain = _gain(n, xp)
        own = xp.where(noise == 0, 0.0, noise / xp.where(gain > 0, gain, 0.0))
        path = (1.0 - tau) * sigma
        total = xp.sqrt(own * own + path * path)
        quiet = total == 0
        inverse = xp.where(quiet, 0.0, total / xp.where(quiet, 1.0, signal))
        db = 20.0 * xp.log10(xp.where(quiet, xp.inf, signal / xp.where(quiet, 1.0, total)))
    unknown = xp.isnan(c) | xp.isnan(noise) | xp.isnan(tau) | xp.isnan(n) | xp.isnan(sigma)
    return xp.where(unknown, xp.nan, db), inverse, unknown


def combined_snr(*snr: Any) -> Any:
    """Independent noises added in variance: ``1/SNR² = Σ 1/SNR_i²``, in dB.

    Parameters
    ----------
    *snr : array_like
        SNRs [dB] (+inf: that source adds no noise; −inf: no signal), broadcasting together.

    Returns
    -------
    array_like
        The total SNR [dB], at most the smallest of the inputs; equal to it where the others
        are +inf.

    Examples
    --------
    >>> round(float(combined_snr(0.0, 0.0)), 4)  # two equal noises: 3 dB worse
    -3.0103
    >>> float(combined_snr(12.0, float("inf")))
    12.0
    """
    if not snr:
        raise ValueError("combined_snr needs at least one SNR")
    xp, values = _arrays.arrays(*snr, names=[f"snr {k + 1}" for k in range(len(snr))])
    if len(values) == 1:
        return _arrays.result(values[0])
    return _arrays.result(combined_db(values, xp))


def combined_db(values: list[Any], xp: Any) -> Any:
    """:func:`combined_snr` of two or more float arrays (the arithmetic kernel)."""
    # 1/SNR_lin² = 10^(−SNR/10): 0 at +inf, +inf at −inf.
    with np.errstate(over="ignore", divide="ignore"):
        total = sum((10.0 ** (-v / 10.0) for v in values), start=xp.zeros_like(values[0]))
        db = -10.0 * xp.log10(total)
    unknown = xp.zeros_like(total, dtype=bool)
    for v in values:
        unknown = unknown | xp.isnan(v)
    return xp.where(unknown, xp.nan, db)
