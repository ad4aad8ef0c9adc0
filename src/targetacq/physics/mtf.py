"""The system MTF as a product of named components.

An imager's modulation transfer function (MTF) is the product of the MTFs of its cascaded linear
stages (G. D. Boreman, *Modulation Transfer Function in Optical and Electro-Optical Systems*,
SPIE TT52 (2001), ch. 1, the cascade property). Each component here is a pure kernel that
broadcasts, with its closed form and its source:

``diffraction``
    a circular, aberration-free aperture in incoherent light (:func:`diffraction_mtf`);
``detector``
    the footprint of a square detector, a sinc (:func:`detector_mtf`);
``sampling``
    the average over sample phase of a sampled imager, a sinc of the sample pitch
    (:func:`sampling_mtf`);
``blur``
    a Gaussian optical blur (:func:`blur_mtf`);
``jitter``
    Gaussian line-of-sight jitter (:func:`jitter_mtf`);
``motion``
    linear smear during the integration time, a sinc (:func:`motion_mtf`);
``turbulence``
    atmospheric turbulence from ``Cn²``, long or short exposure (:func:`turbulence_mtf`, with
    the Fried parameter :func:`fried_parameter`).

:data:`MTF_COMPONENTS` is the registry and :func:`system_mtf` the product of the components
given. Spatial frequency is angular, in object space, in cycles/rad (SI, like every kernel);
angles in rad, lengths in m. NaN in gives NaN out and never raises; a value out of range raises
``ValueError`` for the whole call, naming the input and its valid range.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import numpy as np

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array

__all__ = [
    "MTF_COMPONENTS",
    "MtfComponent",
    "blur_mtf",
    "detector_mtf",
    "diffraction_mtf",
    "fried_parameter",
    "jitter_mtf",
    "motion_mtf",
    "sampling_mtf",
    "system_mtf",
    "turbulence_mtf",
]

FRIED_CONSTANT = 0.423
"""The constant of the Fried parameter, ``r0 = (0.423 k² ∫ Cn² w(z) dz)^(−3/5)``."""

TURBULENCE_CONSTANT = 3.44
"""The constant of the turbulence MTF, ``exp(−3.44 (λf/r0)^(5/3) …)`` (Fried 1966)."""

WAVES: tuple[str, ...] = ("spherical", "plane")
EXPOSURES: tuple[str, ...] = ("long", "short")


# --------------------------------------------------------------------------------------------
# Checks that keep NaN as NaN (scalars too) and raise for out-of-range values.


def _choice(name: str, value: str, choices: tuple[str, ...]) -> None:
    if value not in choices:
        raise ValueError(f"{name} must be one of {', '.join(choices)}; got {value!r}")


def _sinc(x: Array, xp: Any) -> Array:
    """``|sin(πx)/(πx)|``, 1 at x = 0, NaN kept."""
    arg = math.pi * x
    safe = xp.where(arg == 0, 1.0, arg)
    return xp.where(arg == 0, 1.0, xp.abs(xp.sin(safe) / safe))


def _gaussian(f: Array, sigma: Array, xp: Any) -> Array:
    return xp.exp(-2.0 * math.pi**2 * sigma * sigma * f * f)


# --------------------------------------------------------------------------------------------
# Components.


def diffraction_mtf(frequency: Array, wavelength: Array, aperture: Array) -> Any:
    """Diffraction MTF of an aberration-free circular aperture in incoherent light.

    ``MTF(ν) = (2/π) (acos ν − ν sqrt(1 − ν²))`` for ``ν = f λ / D < 1``, 0 from the cut-off
    ``f = D/λ`` up (the autocorrelation of a circular pupil: J. W. Goodman, *Introduction to
    Fourier Optics*, ch. 6, frequency response of diffraction-limited incoherent imaging). One
    wavelength stands for the band; the aperture is the focal length over the f-number.

    Parameters
    ----------
    frequency : array_like
        Angular spatial frequency in object space [cycles/rad], >= 0.
    wavelength : array_like
        λ [m], > 0.
    aperture : array_like
        Entrance-pupil diameter D [m], > 0.

    Returns
    -------
    array_like
        MTF in [0, 1].

    Examples
    --------
    >>> round(float(diffraction_mtf(0.0, 10e-6, 0.05)), 12)
    1.0
    >>> round(float(diffraction_mtf(0.5 * 0.05 / 10e-6, 10e-6, 0.05)), 6)  # ν = 0.5
    0.391002
    """
    xp, (f, lam, d) = _arrays.arrays(frequency, wavelength, aperture)
    _arrays.require_nonnegative_or_nan("frequency", f, xp, "cycles/rad")
    _arrays.require_positive_or_nan("wavelength", lam, xp, "m")
    _arrays.require_positive_or_nan("aperture", d, xp, "m")
    return _arrays.result(_diffraction(f, lam, d, xp))


def _diffraction(f: Array, lam: Array, d: Array, xp: Any) -> Array:
    nu = f * lam / d
    inside = nu < 1.0
    nu_in = xp.where(inside, nu, 0.0)
    value = 2.0 / math.pi * (xp.acos(nu_in) - nu_in * xp.sqrt(1.0 - nu_in * nu_in))
    return xp.where(inside, value, xp.where(xp.isnan(nu), nu, 0.0))


def detector_mtf(frequency: Array, ifov: Array) -> Any:
    """MTF of the detector footprint, a square pixel of angular width IFOV.

    ``MTF(f) = |sinc(f · IFOV)| = |sin(π f IFOV) / (π f IFOV)|``, the Fourier transform of the
    rectangular footprint (Boreman (2001), ch. 2, detector footprint MTF). Zero at
    ``f = 1/IFOV``, twice the Nyquist frequency ``1/(2 IFOV)`` of a 100 %-fill array; for
    another fill factor give the active width (pitch · sqrt(fill)) over the focal length.

    Parameters
    ----------
    frequency : array_like
        [cycles/rad], >= 0.
    ifov : array_like
        Angular width of the detector's active area [rad], > 0.

    Returns
    -------
    array_like
        MTF in [0, 1].

    Examples
    --------
    >>> round(float(detector_mtf(0.5 / 3.4e-4, 3.4e-4)), 6)  # Nyquist: 2/π
    0.63662
    """
    xp, (f, i) = _arrays.arrays(frequency, ifov)
    _arrays.require_nonnegative_or_nan("frequency", f, xp, "cycles/rad")
    _arrays.require_positive_or_nan("ifov", i, xp, "rad")
    return _arrays.result(_sinc(f * i, xp))


def sampling_mtf(frequency: Array, pitch: Array) -> Any:
    """MTF of sampling, averaged over the phase of the scene against the samples.

    ``MTF(f) = |sinc(f · p)|`` for a sample pitch ``p``: a sampled imager's response to a scene
    at a random position relative to the sample grid is, on average, that of an extra
    rectangular blur one sample wide (S. E. Park, R. Schowengerdt and M.-A. Kaczynski,
    "Modulation-transfer-function analysis for sampled image systems", Appl. Opt. 23(15) (1984)
    2572; Boreman (2001), ch. 3, the sampling MTF). Aliasing itself is not modelled.

    Parameters
    ----------
    frequency : array_like
        [cycles/rad], >= 0.
    pitch : array_like
        Angular sample pitch [rad], > 0 (the pixel pitch over the focal length).

    Returns
    -------
    array_like
        MTF in [0, 1].

    Examples
    --------
    >>> round(float(sampling_mtf(0.25 / 3.4e-4, 3.4e-4)), 6)  # f p = 1/4: 2√2/π
    0.900316
    """
    xp, (f, p) = _arrays.arrays(frequency, pitch)
    _arrays.require_nonnegative_or_nan("frequency", f, xp, "cycles/rad")
    _arrays.require_positive_or_nan("pitch", p, xp, "rad")
    return _arrays.result(_sinc(f * p, xp))


def blur_mtf(frequency: Array, blur_sigma: Array) -> Any:
    """MTF of a Gaussian blur of angular standard deviation σ, ``exp(−2π² σ² f²)``.

    The Fourier transform of the Gaussian point-spread function of Eq. (5.2) in Sonesson (2004)
    (separable form, see :func:`targetacq.physics.optics.gaussian_psf`), along one axis.

    Parameters
    ----------
    frequency : array_like
        [cycles/rad], >= 0.
    blur_sigma : array_like
        σ [rad], >= 0 (0: no blur, MTF 1).

    Returns
    -------
    array_like
        MTF in (0, 1].

    Examples
    --------
    >>> import math
    >>> round(float(blur_mtf(1.0 / (math.pi * math.sqrt(2.0) * 1e-4), 1e-4)), 12)  # e^-1
    0.367879441171
    """
    xp, (f, s) = _arrays.arrays(frequency, blur_sigma)
    _arrays.require_nonnegative_or_nan("frequency", f, xp, "cycles/rad")
    _arrays.require_nonnegative_or_nan("blur_sigma", s, xp, "rad")
    return _arrays.result(_gaussian(f, s, xp))


def jitter_mtf(frequency: Array, jitter: Array) -> Any:
    """MTF of random line-of-sight jitter with Gaussian statistics, ``exp(−2π² σ_j² f²)``.

    A line of sight that wanders during the eye's (or the frame's) integration with a normal
    distribution of standard deviation ``σ_j`` per axis blurs the image by that Gaussian; its
    MTF is the Gaussian's characteristic function (Boreman (2001), ch. 5, random image motion;
    G. C. Holst, *Electro-Optical Imaging System Performance*, 5th ed., SPIE (2008), the
    jitter MTF).

    Parameters
    ----------
    frequency : array_like
        [cycles/rad], >= 0.
    jitter : array_like
        σ_j, the RMS jitter per axis [rad], >= 0.

    Returns
    -------
    array_like
        MTF in (0, 1].

    Examples
    --------
    >>> round(float(jitter_mtf(1000.0, 1e-4)), 6)  # exp(−2π² · 0.01)
    0.820869
    """
    xp, (f, s) = _arrays.arrays(frequency, jitter)
    _arrays.require_nonnegative_or_nan("frequency", f, xp, "cycles/rad")
    _arrays.require_nonnegative_or_nan("jitter", s, xp, "rad")
    return _arrays.result(_gaussian(f, s, xp))


def motion_mtf(frequency: Array, smear: Array) -> Any:
    """MTF of linear image motion during the integration time, ``|sinc(f · a)|``.

    A scene that moves uniformly by the angle ``a = ω t_int`` (angular rate times integration
    time) while the detector integrates is blurred by a rectangle ``a`` wide (Boreman (2001),
    ch. 5, linear motion MTF; Holst (2008), the linear motion MTF).

    Parameters
    ----------
    frequency : array_like
        [cycles/rad], >= 0.
    smear : array_like
        The angle moved during one integration [rad], >= 0 (0: no motion, MTF 1).

    Returns
    -------
    array_like
        MTF in [0, 1].

    Examples
    --------
    >>> round(float(motion_mtf(1000.0, 5e-4)), 6)  # f a = 1/2: 2/π
    0.63662
    """
    xp, (f, a) = _arrays.arrays(frequency, smear)
    _arrays.require_nonnegative_or_nan("frequency", f, xp, "cycles/rad")
    _arrays.require_nonnegative_or_nan("smear", a, xp, "rad")
    return _arrays.result(_sinc(f * a, xp))


def fried_parameter(range: Array, wavelength: Array, cn2: Array, wave: str = "spherical") -> Any:
    """Fried's coherence diameter ``r0`` of a horizontal path of constant ``Cn²``.

    ``r0 = (0.423 k² Cn² L · w)^(−3/5)`` with ``k = 2π/λ``, path length ``L``, and the path
    weighting ``w = ∫ (z/L)^(5/3) dz / L = 3/8`` for a spherical wave (a point at the target
    imaged by the sensor, the case of imaging) or ``w = 1`` for a plane wave (D. L. Fried,
    "Optical resolution through a randomly inhomogeneous medium for very long and very short
    exposures", J. Opt. Soc. Am. 56(10) (1966) 1372; L. C. Andrews and R. L. Phillips, *Laser
    Beam Propagation through Random Media*, 2nd ed., SPIE (2005), ch. 6, the atmospheric
    coherence width).

    Parameters
    ----------
    range : array_like
        Path length L [m], >= 0.
    wavelength : array_like
        λ [m], > 0.
    cn2 : array_like
        Refractive-index structure constant Cn² [m^(−2/3)], >= 0.
    wave : {"spherical", "plane"}
        The path weighting (default spherical).

    Returns
    -------
    array_like
        r0 [m]; +inf where ``Cn² L = 0``.

    Examples
    --------
    >>> round(float(fried_parameter(1000.0, 1e-5, 1e-14, wave="plane")), 4)
    0.7352
    """
    _choice("wave", wave, WAVES)
    xp, (r, lam, c) = _arrays.arrays(range, wavelength, cn2)
    _arrays.require_nonnegative_or_nan("range", r, xp, "m")
    _arrays.require_positive_or_nan("wavelength", lam, xp, "m")
    _arrays.require_nonnegative_or_nan("cn2", c, xp, "m^-2/3")
    return _arrays.result(_fried(r, lam, c, wave, xp))


def _fried(r: Array, lam: Array, c: Array, wave: str, xp: Any) -> Array:
    weight = 3.0 / 8.0 if wave == "spherical" else 1.0
    k = 2.0 * math.pi / lam
    strength = FRIED_CONSTANT * k * k * c * r * weight
    with np.errstate(divide="ignore"):
        return xp.where(strength == 0, xp.inf, strength ** (-0.6))


def turbulence_mtf(
    frequency: Array,
    range: Array,
    wavelength: Array,
    cn2: Array,
    aperture: Array,
    exposure: str = "long",
) -> Any:
    """Atmospheric turbulence MTF from ``Cn²``, long or short exposure (Fried 1966).

    Long exposure: ``MTF = exp(−3.44 (λf/r0)^(5/3))``. Short exposure (the image's mean tilt
    removed, the case of a frame shorter than the turbulence's time scale):
    ``MTF = exp(−3.44 (λf/r0)^(5/3) [1 − (λf/D)^(1/3)])``, Fried's near-field form; the
    bracket is clipped at 0 beyond the optics' cut-off ``f = D/λ``, where the diffraction MTF
    is 0 anyway. ``f`` is the angular frequency in object space, so ``λf`` is the separation in
    the pupil; ``r0`` is :func:`fried_parameter` for a spherical wave (D. L. Fried, J. Opt. Soc.
    Am. 56(10) (1966) 1372, Eqs. for the long- and short-exposure MTF; M. C. Roggemann and
    B. Welsh, *Imaging through Turbulence*, CRC (1996), ch. 3).

    Parameters
    ----------
    frequency : array_like
        [cycles/rad], >= 0.
    range : array_like
        Path length [m], >= 0.
    wavelength : array_like
        λ [m], > 0.
    cn2 : array_like
        Cn² [m^(−2/3)], >= 0 (0: no turbulence, MTF 1).
    aperture : array_like
        Entrance-pupil diameter D [m], > 0 (used by the short-exposure form).
    exposure : {"long", "short"}

    Returns
    -------
    array_like
        MTF in (0, 1].

    Examples
    --------
    At ``λf = r0`` the long-exposure MTF is ``e^−3.44``:

    >>> r0 = float(fried_parameter(2000.0, 4e-6, 1e-14))
    >>> round(float(turbulence_mtf(r0 / 4e-6, 2000.0, 4e-6, 1e-14, 0.1)), 6)
    0.032065
    """
    _choice("exposure", exposure, EXPOSURES)
    xp, (f, r, lam, c, d) = _arrays.arrays(frequency, range, wavelength, cn2, aperture)
    _arrays.require_nonnegative_or_nan("frequency", f, xp, "cycles/rad")
    _arrays.require_nonnegative_or_nan("range", r, xp, "m")
    _arrays.require_positive_or_nan("wavelength", lam, xp, "m")
    _arrays.require_nonnegative_or_nan("cn2", c, xp, "m^-2/3")
    _arrays.require_positive_or_nan("aperture", d, xp, "m")
    return _arrays.result(_turbulence(f, r, lam, c, d, exposure, xp))


def _turbulence(
    f: Array, r: Array, lam: Array, c: Array, d: Array, exposure: str, xp: Any
) -> Array:
    r0 = _fried(r, lam, c, "spherical", xp)
    separation = lam * f
    exponent = TURBULENCE_CONSTANT * (separation / r0) ** (5.0 / 3.0)
    if exposure == "short":
        exponent = exponent * xp.clip(1.0 - (separation / d) ** (1.0 / 3.0), 0.0, 1.0)
    return xp.exp(-exponent)


# --------------------------------------------------------------------------------------------
# Registry and product.


@dataclass(frozen=True)
class MtfComponent:
    """A named MTF component: ``kernel(frequency, **parameters)``.

    Attributes
    ----------
    name : str
    kernel : callable
        The public kernel, ``kernel(frequency, *parameters, **options)``.
    parameters : tuple of str
        Its array parameters after the frequency, in order.
    options : tuple of str
        Its string options (keywords).
    source : str
    """

    name: str
    kernel: Callable[..., Any]
    parameters: tuple[str, ...]
    options: tuple[str, ...]
    source: str


MTF_COMPONENTS: Mapping[str, MtfComponent] = MappingProxyType(
    {
        "diffraction": MtfComponent(
            "diffraction",
            diffraction_mtf,
            ("wavelength", "aperture"),
            (),
            "circular aperture, Goodman, Introduction to Fourier Optics, ch. 6",
        ),
        "detector": MtfComponent(
            "detector", detector_mtf, ("ifov",), (), "detector footprint, Boreman (2001) ch. 2"
        ),
        "sampling": MtfComponent(
            "sampling",
            sampling_mtf,
            ("pitch",),
            (),
            "phase-averaged sampling, Park, Schowengerdt & Kaczynski, Appl. Opt. 23(15) 1984",
        ),
        "blur": MtfComponent(
            "blur", blur_mtf, ("blur_sigma",), (), "Gaussian blur, Sonesson (2004) Eq. (5.2)"
        ),
        "jitter": MtfComponent(
            "jitter", jitter_mtf, ("jitter",), (), "Gaussian line-of-sight jitter, Boreman ch. 5"
        ),
        "motion": MtfComponent(
            "motion", motion_mtf, ("smear",), (), "linear motion, Boreman (2001) ch. 5"
        ),
        "turbulence": MtfComponent(
            "turbulence",
            turbulence_mtf,
            ("range", "wavelength", "cn2", "aperture"),
            ("exposure",),
            "Fried, J. Opt. Soc. Am. 56(10) (1966) 1372",
        ),
    }
)
"""The MTF components, by name (read-only)."""


def system_mtf(frequency: Array, components: Mapping[str, Mapping[str, Any]]) -> Any:
    """The system MTF: the product of the named components' MTFs.

    Parameters
    ----------
    frequency : array_like
        [cycles/rad], >= 0.
    components : mapping
        Component name (a key of :data:`MTF_COMPONENTS`) → its parameters by name (all of
        ``MtfComponent.parameters``, and any of its ``options``). Arrays broadcast with each
        other and with the frequency.

    Returns
    -------
    array_like
        MTF in [0, 1]; 1 for no components.

    Raises
    ------
    ValueError
        An unknown component, a missing or unknown parameter, or a value out of range.

    Examples
    --------
    >>> round(float(system_mtf(1000.0, {
    ...     "diffraction": {"wavelength": 10e-6, "aperture": 0.05},
    ...     "detector": {"ifov": 3.4e-4}})), 6)
    0.61289
    """
    total: Any = 1.0
    for name, given in components.items():
        if name not in MTF_COMPONENTS:
            raise ValueError(
                f"unknown MTF component {name!r}; choose from {', '.join(MTF_COMPONENTS)}"
            )
        component = MTF_COMPONENTS[name]
        missing = [p for p in component.parameters if p not in given]
        unknown = sorted(set(given) - set(component.parameters) - set(component.options))
        if missing or unknown:
            listed = f" (options: {', '.join(component.options)})" if component.options else ""
            raise ValueError(
                f"MTF component {name!r} takes {', '.join(component.parameters)}{listed}; "
                f"missing {', '.join(missing) or 'none'}, unknown {', '.join(unknown) or 'none'}"
            )
        args = [given[p] for p in component.parameters]
        options = {o: given[o] for o in component.options if o in given}
        total = total * component.kernel(frequency, *args, **options)
    if not components:
        xp, (f,) = _arrays.arrays(frequency)
        _arrays.require_nonnegative_or_nan("frequency", f, xp, "cycles/rad")
        return _arrays.result(xp.ones_like(f))
    return total
