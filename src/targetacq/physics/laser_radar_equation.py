"""Laser radar (ladar, lidar): range and cross-range resolution, the 3-D clutter measure, the
received power of a direct-detection laser radar and its signal-to-noise ratio.

Source: Sonesson (2004) §9.4.4 sketches the laser radar only: it takes three-dimensional pictures,
its resolution depends on how closely the detector elements sit, on the shortest time that
separates two returns and on the distance, and its background is clutter "in the same way as for
TV-like systems", but a 3-D clutter measure. As for every sensor, the atmosphere acts as noise by
Eq. (7.7) (:func:`targetacq.physics.atmosphere.snr_from_optical_depth`). The formulas below fill in
that sketch; each is **the project's assumption**, stated here with its rationale:

1. **Range resolution** ``Δr = c t / 2`` (:func:`range_resolution`): two returns are told apart
   when they arrive at least ``t`` apart (the pulse length or the detector's timing
   resolution), and the light covers the range twice. ``c`` is the speed of light in vacuum
   (:data:`targetacq.base.constants.SPEED_OF_LIGHT`); the group index of air (about 1.0003) would
   shorten ``Δr`` by 0.03 %, far below the model's precision.
2. **Cross-range resolution** ``R · IFOV`` (:func:`cross_range_resolution`): the footprint of
   one detector element, its IFOV being its spacing over the focal length
   (:func:`targetacq.physics.optics.ifov`); small angles (the exact ``2 R tan(IFOV/2)`` differs by a
   relative ``IFOV²/12``, 1e-7 at 1 mrad).
3. **The target's relief** is its height standing out of the local ground, the part of it that
   is not hidden (:func:`relief_seen`, ``f h``). We take the height rather than the depth along
   the line of sight because the background's 3-D roughness ``σ_z`` is a spread of surface
   heights (vegetation, rocks, terrain around the target): target and background are then
   measured along the same axis, whatever the viewing direction.
4. **The 3-D clutter measure** (:func:`relief_scr`): the analogue of the thesis's SCR (a signal
   over the clutter's standard deviation, Eqs. (3.12)–(3.15)) in range instead of intensity,
   ``SCR_3D = h / sqrt(σ_z² + Δr²/12)``. The background's height spread and the sensor's range
   quantisation are independent and add in variance; a uniform quantiser of step ``Δr`` has the
   standard deviation ``Δr/√12``. The range step is compared with heights as it is: exact for a
   sensor looking straight down; for an oblique view, pass the height step of one range cell,
   ``Δr / sin(depression)``, to be exact (``Δr`` itself is then optimistic).
   :func:`range_cells_on_target` counts the range cells across the relief, the depth analogue
   of the pixels on target.
5. **Range equation** (:func:`received_power`): a direct-detection laser radar and an extended
   Lambertian target that fills the beam, seen at normal incidence, in the far field:
   ``P_r = P_t ρ τ² A_r η / (π R²)``. The target, lit by ``τ P_t``, reflects ``ρ τ P_t`` with
   the radiant intensity ``ρ τ P_t / π`` along its normal (Lambert's law: the intensity
   integrated over the hemisphere is ``π`` times that along the normal); the aperture ``A_r``
   at range ``R`` takes the solid angle ``A_r / R²`` of it, and the path attenuates it by ``τ``
   again. This is the extended-target form of the LADAR range equation of R. D. Richmond and
   S. C. Cain, *Direct-Detection LADAR Systems* (SPIE Tutorial Text TT85, 2010), ch. 2 "LADAR
   Range Equation", with a Lambertian target's angular dispersion of ``π`` sr. A target that
   fills only part of the beam returns that part: multiply ``efficiency`` by it (a target much
   smaller than the beam falls off as ``1/R⁴`` instead, which this kernel does not model). An
   oblique surface would add ``cos θ``.
6. **Detector SNR** (:func:`laser_snr`): ``20 log10(P_r / NEP)`` dB. A photodetector's signal
   current is proportional to the optical power, and the noise-equivalent power is the power
   whose current equals the RMS noise current in the receiver's bandwidth; ``P_r / NEP`` is
   therefore a ratio of currents, an amplitude ratio, whose dB are ``20 log10`` as for every
   SNR of the project (Eq. (7.6)); the electrical power ratio is its square. The receiver's
   noise (thermal, dark current, background) dominates: the signal's own shot noise and laser
   speckle are not modelled.
7. **Two-way atmosphere** (:func:`two_way_optical_depth`): the return travels the path twice,
   so its transmittance is ``τ² = exp(−2d)``, and the atmosphere's noise of Eq. (7.7) for an
   active sensor is that of the optical depth ``2d``. As for the passive sensors (whose
   sensor SNR also carries ``τ``), the detector SNR and the atmosphere's Eq. (7.7) are
   separate noise terms, combined by :func:`targetacq.physics.detector_noise.combined_snr`.

Inputs follow :mod:`targetacq.base.arrays`: SI units, NumPy or any array-API namespace (JAX under
``jit`` included), broadcasting, NaN in gives NaN out, out-of-range values raise ``ValueError``
naming the input. Infinite inputs give the limits each docstring states; where there is none
(a height, a power, an area, an angle) they are refused.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.base.constants import SPEED_OF_LIGHT

__all__ = [
    "cross_range_resolution",
    "laser_snr",
    "range_cells_on_target",
    "range_resolution",
    "received_power",
    "relief_scr",
    "relief_seen",
    "two_way_optical_depth",
]

_ROOT_12 = math.sqrt(12.0)


def range_resolution(timing: Array) -> Any:
    """Range resolution of a laser radar, ``Δr = c t / 2`` [m] (module docstring, item 1).

    Parameters
    ----------
    timing : array_like
        t [s], > 0: the shortest time that separates two returns (pulse length or the
        detector's timing resolution). +inf gives +inf (nothing resolved in range).

    Returns
    -------
    array_like
        Δr [m].

    Examples
    --------
    A 1 ns pulse: ``299792458 · 1e-9 / 2``.

    >>> from targetacq.physics.laser_radar_equation import range_resolution
    >>> print(f"{range_resolution(1e-9):.6f} m")
    0.149896 m
    """
    xp, (t,) = _arrays.arrays(timing, names=("timing",))
    _arrays.require_positive("timing", t, xp, "s")
    return _arrays.result(0.5 * SPEED_OF_LIGHT * t)


def cross_range_resolution(range: Array, detector_ifov: Array) -> Any:
    """Cross-range resolution, the footprint of one detector element, ``R · IFOV`` [m].

    Parameters
    ----------
    range : array_like
        R [m], >= 0 (+inf gives +inf).
    detector_ifov : array_like
        IFOV of one detector element [rad], > 0 and finite (spacing over focal length,
        :func:`targetacq.physics.optics.ifov`).

    Returns
    -------
    array_like
        [m].

    Examples
    --------
    >>> from targetacq.physics.laser_radar_equation import cross_range_resolution
    >>> print(f"{cross_range_resolution(2000.0, 0.1e-3):.3f} m")
    0.200 m
    """
    xp, (r, i) = _arrays.arrays(range, detector_ifov, names=("range", "detector_ifov"))
    _arrays.require_nonnegative("range", r, xp, "m")
    _arrays.require_positive("detector_ifov", i, xp, "rad")
    _arrays.require_finite("detector_ifov", i, xp, "rad")
    return _arrays.result(r * i)


def relief_seen(height: Array, visible_fraction: Array) -> Any:
    """The target's relief that the laser radar sees, ``f · h`` [m] (module docstring, item 3).

    Parameters
    ----------
    height : array_like
        h [m], >= 0 and finite: the target's height above the local ground.
    visible_fraction : array_like
        f in [0, 1]: the part of that height not hidden (by vegetation, a ridge, cover).

    Returns
    -------
    array_like
        [m].

    Examples
    --------
    >>> from targetacq.physics.laser_radar_equation import relief_seen
    >>> print(f"{relief_seen(2.5, 0.8):.2f} m")
    2.00 m
    """
    xp, (h, f) = _arrays.arrays(height, visible_fraction, names=("height", "visible_fraction"))
    _check_relief("height", h, xp)
    _arrays.require_unit_interval("visible_fraction", f, xp)
    return _arrays.result(h * f)


def range_cells_on_target(relief: Array, range_resolution: Array) -> Any:
    """Range cells across the target's relief, ``h / Δr`` [1]: the depth analogue of pixels.

    Parameters
    ----------
    relief : array_like
        h [m], >= 0 and finite (:func:`relief_seen`).
    range_resolution : array_like
        Δr [m], > 0 (:func:`range_resolution`; +inf gives 0 cells).

    Returns
    -------
    array_like
        [1].

    Examples
    --------
    >>> from targetacq.physics.laser_radar_equation import range_cells_on_target
    >>> print(f"{range_cells_on_target(2.0, 0.25):.1f}")
    8.0
    """
    xp, (h, dr) = _arrays.arrays(relief, range_resolution, names=("relief", "range_resolution"))
    _check_relief("relief", h, xp)
    _arrays.require_positive("range_resolution", dr, xp, "m")
    return _arrays.result(h / dr)


def relief_scr(target_relief: Array, background_relief_std: Array, range_resolution: Array) -> Any:
    """The 3-D signal-to-clutter ratio, ``h / sqrt(σ_z² + Δr²/12)`` [1] (module docstring, item 4).

    Parameters
    ----------
    target_relief : array_like
        h [m], >= 0 and finite: the target's visible height above the ground
        (:func:`relief_seen`).
    background_relief_std : array_like
        σ_z [m], >= 0: the standard deviation of the surface heights around the target
        (+inf gives 0).
    range_resolution : array_like
        Δr [m], >= 0 (0: no quantisation; +inf gives 0). For an oblique view, its height
        equivalent ``Δr / sin(depression)``.

    Returns
    -------
    array_like
        SCR_3D >= 0: +inf where σ_z and Δr are both 0 and h > 0 (no clutter); 0 where h = 0;
        NaN where an input is NaN.

    Examples
    --------
    A 2 m relief over σ_z = 0.3 m with 1.2 m range cells: ``2 / sqrt(0.09 + 1.44/12)``.

    >>> from targetacq.physics.laser_radar_equation import relief_scr
    >>> print(f"{relief_scr(2.0, 0.3, 1.2):.4f}")
    4.3644
    >>> print(relief_scr(2.0, 0.0, 0.0), relief_scr(0.0, 0.0, 0.0))
    inf 0.0
    """
    xp, (h, s, dr) = _arrays.arrays(
        target_relief,
        background_relief_std,
        range_resolution,
        names=("target_relief", "background_relief_std", "range_resolution"),
    )
    _check_relief("target_relief", h, xp)
    _arrays.require_nonnegative("background_relief_std", s, xp, "m")
    _arrays.require_nonnegative("range_resolution", dr, xp, "m")
    clutter = xp.hypot(s, dr / _ROOT_12)
    some = clutter > 0
    ratio = h / xp.where(some, clutter, 1.0)
    out = xp.where(some, ratio, xp.where(h > 0, xp.inf, xp.zeros_like(ratio)))
    unknown = xp.isnan(h) | xp.isnan(s) | xp.isnan(dr)
    return _arrays.result(xp.where(unknown, xp.nan, out))


def received_power(
    range: Array,
    power: Array,
    reflectance: Array,
    aperture_area: Array,
    transmittance: Array,
    efficiency: Array = 1.0,
) -> Any:
    """Power received from an extended Lambertian target, ``P_t ρ τ² A_r η / (π R²)`` [W].

    The direct-detection laser radar range equation for a target that fills the beam (module
    docstring, item 5; Richmond & Cain (2010), ch. 2). A pulse energy [J] for ``power`` gives
    the received energy [J].

    Parameters
    ----------
    range : array_like
        R [m], > 0 (+inf gives 0 W).
    power : array_like
        P_t, the transmitted (peak) power [W], >= 0 and finite.
    reflectance : array_like
        ρ, the target's Lambertian (hemispherical) reflectance at the laser's wavelength,
        in [0, 1].
    aperture_area : array_like
        A_r, the receiver's aperture area [m²], >= 0 and finite.
    transmittance : array_like
        τ, the ONE-WAY transmittance of the path, in [0, 1] (squared here: the two-way path).
    efficiency : array_like
        η, the receiver optics' transmission times any other loss (the part of the beam the
        target fills), in [0, 1].

    Returns
    -------
    array_like
        P_r [W].

    Examples
    --------
    10 kW on a 10 % target at 1 km through τ = exp(−0.2), a 10 cm aperture, η = 0.5: with
    ``A_r / π = D²/4`` this is ``1e4 · 0.1 · exp(−0.4) · 0.5 · 0.1² / (4 · 1000²)``.

    >>> import math
    >>> from targetacq.physics.laser_radar_equation import received_power
    >>> p = received_power(1000.0, 1e4, 0.1, math.pi * 0.05**2, math.exp(-0.2), 0.5)
    >>> print(f"{p:.5e} W")
    8.37900e-07 W
    """
    xp, (r, p, rho, area, tau, eta) = _arrays.arrays(
        range,
        power,
        reflectance,
        aperture_area,
        transmittance,
        efficiency,
        names=("range", "power", "reflectance", "aperture_area", "transmittance", "efficiency"),
    )
    _arrays.require_positive("range", r, xp, "m")
    for name, value, unit in (("power", p, "W"), ("aperture_area", area, "m²")):
        _arrays.require_nonnegative(name, value, xp, unit)
        _arrays.require_finite(name, value, xp, unit)
    for name, value in (("reflectance", rho), ("transmittance", tau), ("efficiency", eta)):
        _arrays.require_unit_interval(name, value, xp)
    # Divided by R twice, not by R²: R² would overflow (or underflow) before the quotient does.
    with np.errstate(over="ignore", divide="ignore"):
        out = p * rho * (tau * tau) * area * eta / math.pi / r / r
    return _arrays.result(out)


def laser_snr(received_power: Array, noise_equivalent_power: Array) -> Any:
    """The detector's SNR of the return, ``20 log10(P_r / NEP)`` [dB] (module docstring, item 6).

    Parameters
    ----------
    received_power : array_like
        P_r [W], >= 0 (:func:`received_power`; 0 gives −inf, +inf gives +inf).
    noise_equivalent_power : array_like
        NEP over the receiver's bandwidth [W] (a datasheet's W/√Hz times √B), >= 0. 0: no
        receiver noise, +inf dB whatever the signal; +inf gives −inf for a finite signal.

    Returns
    -------
    array_like
        SNR [dB]; NaN where an input is NaN or both are infinite.

    Examples
    --------
    A return 100 times the NEP: 40 dB.

    >>> from targetacq.physics.laser_radar_equation import laser_snr
    >>> print(f"{laser_snr(1e-6, 1e-8):.1f} dB")
    40.0 dB
    >>> print(laser_snr(0.0, 1e-8), laser_snr(1e-9, 0.0))
    -inf inf
    """
    xp, (p, nep) = _arrays.arrays(
        received_power, noise_equivalent_power, names=("received_power", "noise_equivalent_power")
    )
    _arrays.require_nonnegative("received_power", p, xp, "W")
    _arrays.require_nonnegative("noise_equivalent_power", nep, xp, "W")
    quiet = nep == 0
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        ratio = xp.where(quiet, xp.inf, p / xp.where(quiet, 1.0, nep))
        db = 20.0 * xp.log10(ratio)
    unknown = xp.isnan(p) | xp.isnan(nep)
    return _arrays.result(xp.where(unknown, xp.nan, db))


def two_way_optical_depth(optical_depth: Array) -> Any:
    """Optical depth of the path there and back, ``2 d`` [Np] (module docstring, item 7).

    The return's transmittance is ``exp(−2d) = τ²``; the atmosphere's noise of Eq. (7.7) for a
    laser radar is :func:`targetacq.physics.atmosphere.snr_from_optical_depth` of this depth.

    Parameters
    ----------
    optical_depth : array_like
        d = γR (one way), >= 0 (+inf gives +inf).

    Returns
    -------
    array_like
        2d.

    Examples
    --------
    One way at d = ln 2 (τ = 0.5) keeps a quarter of the return, whose Eq. (7.7) SNR is
    ``20 log10(0.25 / 0.75)``:

    >>> import math
    >>> from targetacq.physics.atmosphere import snr_from_optical_depth
    >>> from targetacq.physics.laser_radar_equation import two_way_optical_depth
    >>> d = two_way_optical_depth(math.log(2.0))
    >>> print(f"{math.exp(-d):.2f}, {snr_from_optical_depth(d):.4f} dB")
    0.25, -9.5424 dB
    """
    xp, (d,) = _arrays.arrays(optical_depth, names=("optical_depth",))
    _arrays.require_nonnegative("optical_depth", d, xp)
    return _arrays.result(2.0 * d)


def _check_relief(name: str, value: Any, xp: Any) -> None:
    _arrays.require_nonnegative(name, value, xp, "m")
    _arrays.require_finite(name, value, xp, "m")
