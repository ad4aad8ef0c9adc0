"""Sensor optics and sampling: IFOV, field of view, diffraction, blur, cycles on target.

Sources: Sonesson (2004) ch. 3 (§3.5, Fig. 3.3) and ch. 5 (Eqs. (5.1)–(5.4)), with two
corrections of ours: the diffraction condition of §5.5 reversed, and the Gaussian separable.

One *cycle* (line pair) is the angle of two adjacent pixel rows, ``2·IFOV`` (Fig. 3.3: a target
2.5 pixel rows high is 1.25 cycles). Optics can make the resolvable cycle coarser than that:

- diffraction: one cycle is ``1.22 λ / D`` (the Rayleigh separation, Eq. (5.3)), and the
  sensor resolves ``max(2·IFOV, 1.22 λ/D)`` (the erratum to §5.5, see the
  user guide's errata);
- a Gaussian blur of angular standard deviation σ (Eq. (5.2)) limits resolution where its
  modulation transfer function ``exp(-2π²σ²ξ²)`` falls to the modulation that the diffraction
  rule accepts at its own limit: the diffraction MTF of a circular aperture at the spatial
  frequency of one Rayleigh cycle, ``ξ = D / (1.22 λ)``, i.e. ``M* = MTF_diff(1/1.22) ≈ 0.0896``.
  The blur's cycle is then ``π σ sqrt(2 / ln(1/M*)) ≈ 2.86 σ``. Using the diffraction rule's
  own threshold keeps the two optical limits on one scale.
- the two optical blurs combine in quadrature (exact for Gaussian spots, the usual
  engineering approximation for a diffraction spot and an aberration blur, e.g. Holst,
  *Electro-Optical Imaging System Performance*), and the optics then compete with the
  sampling limit by the larger of the two, as the thesis's diffraction rule does.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from types import MappingProxyType
from typing import Any

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.base.registry import lookup

__all__ = [
    "BLUR_CYCLE_PER_SIGMA",
    "DIFFRACTION_THRESHOLD_MODULATION",
    "FIELD_OF_VIEW_PROJECTIONS",
    "RAYLEIGH_FACTOR",
    "blur_cycle_angle",
    "cycles_on_target",
    "diffraction_angle",
    "diffraction_spot",
    "field_of_view",
    "field_of_view_from_ifov",
    "gaussian_psf",
    "ifov",
    "ifov_from_field_of_view",
    "pixels_per_metre",
    "range_for_cycles",
    "range_for_pixel_density",
    "resolvable_cycle_angle",
]

RAYLEIGH_FACTOR = 1.22
"""Rayleigh factor of Eq. (5.3), Sonesson (2004): first zero of the Airy pattern, as printed."""


def _circular_aperture_mtf(normalised_frequency: float) -> float:
    # Diffraction MTF of an aberration-free circular aperture, incoherent light, at ξ/ξ_cutoff.
    nu = normalised_frequency
    return 2.0 / math.pi * (math.acos(nu) - nu * math.sqrt(1.0 - nu * nu))


DIFFRACTION_THRESHOLD_MODULATION = _circular_aperture_mtf(1.0 / RAYLEIGH_FACTOR)
"""Modulation of a diffraction-limited lens at one Rayleigh cycle (≈ 0.0896), see module doc."""

BLUR_CYCLE_PER_SIGMA = math.pi * math.sqrt(2.0 / -math.log(DIFFRACTION_THRESHOLD_MODULATION))
"""Resolvable cycle of a Gaussian blur per unit standard deviation (≈ 2.86), see module doc."""


def ifov(pitch: Array, focal_length: Array) -> Any:
    """Instantaneous field of view of one detector pixel.

    ``IFOV = p / f`` (small angle), Sonesson (2004) §5.2 with Eq. (5.1).

    Parameters
    ----------
    pitch : array_like
        Detector pixel pitch [m], > 0.
    focal_length : array_like
        Focal length [m], > 0.

    Returns
    -------
    array_like
        IFOV [rad].

    Examples
    --------
    The bundled example camera, 17 µm pixels behind a 75 mm lens (17e-6 / 75e-3):

    >>> import targetacq as ta
    >>> print(f"{ta.ifov(17e-6, 75e-3) * 1e3:.4f} mrad")
    0.2267 mrad
    """
    xp, (p, f) = _arrays.arrays(pitch, focal_length, names=("pitch", "focal_length"))
    _arrays.require_positive("pitch", p, xp, "m")
    _arrays.require_positive("focal_length", f, xp, "m")
    return _arrays.result(p / f)


def field_of_view(detector_size: Array, focal_length: Array) -> Any:
    """Full field of view of a pinhole camera, ``FOV = 2 arctan(A / (2f))``, Eq. (5.1).

    Parameters
    ----------
    detector_size : array_like
        Side of the detector array, ``A`` [m], > 0 (pixels × pitch).
    focal_length : array_like
        Focal length ``f`` [m], > 0.

    Returns
    -------
    array_like
        Full field of view [rad].

    Examples
    --------
    640 pixels of 17 µm (10.88 mm) behind a 75 mm lens, ``2 arctan(10.88 / 150)``:

    >>> import math
    >>> import targetacq as ta
    >>> print(f"{math.degrees(ta.field_of_view(640 * 17e-6, 75e-3)):.3f} deg")
    8.297 deg
    """
    xp, (a, f) = _arrays.arrays(
        detector_size, focal_length, names=("detector_size", "focal_length")
    )
    _arrays.require_positive("detector_size", a, xp, "m")
    _arrays.require_positive("focal_length", f, xp, "m")
    return _arrays.result(2.0 * xp.atan(a / (2.0 * f)))


FIELD_OF_VIEW_PROJECTIONS: Mapping[str, str] = MappingProxyType(
    {
        "angular": "IFOV = FOV / pixels: the mean angle per pixel, as thermal-camera datasheets "
        "quote it; exact for an equiangular (f-theta) lens and close to the barrel distortion "
        "of wide lenses",
        "rectilinear": "IFOV = 2 tan(FOV/2) / pixels: the central pixel of a distortion-free "
        "pinhole camera, inverting Eq. (5.1) in Sonesson (2004)",
    }
)
"""How a field of view over a number of pixels gives the IFOV, by name (read-only)."""


def ifov_from_field_of_view(
    field_of_view: Array, pixels: Array, projection: str = "angular"
) -> Any:
    """IFOV of a camera given by its field of view and pixels across it.

    ``angular`` (default): ``IFOV = FOV / n``, the mean angle per pixel (the datasheet
    convention: a 100° lens over 640 pixels is 2.727 mrad). ``rectilinear``: inverting
    Eq. (5.1), the array side is ``A = 2 f tan(FOV/2)``, so the central pixel subtends
    ``p/f = 2 tan(FOV/2) / n`` (3.724 mrad for the same lens: the centre pixel of a
    distortion-free wide lens is 37 % coarser than the mean angle per pixel, so its ranges are
    27 % shorter than a datasheet's). See :data:`FIELD_OF_VIEW_PROJECTIONS`.

    Parameters
    ----------
    field_of_view : array_like
        Full field of view along the array side [rad], in (0, π).
    pixels : array_like
        Number of pixels along that side, > 0.
    projection : {"angular", "rectilinear"}

    Returns
    -------
    array_like
        IFOV [rad].

    Examples
    --------
    >>> import math
    >>> round(float(ifov_from_field_of_view(math.radians(100.0), 640)) * 1e3, 4)  # mrad
    2.7271
    >>> round(float(ifov_from_field_of_view(math.radians(100.0), 640, "rectilinear")) * 1e3, 4)
    3.7242
    """
    lookup(FIELD_OF_VIEW_PROJECTIONS, projection, "projection")
    xp, (fov, n) = _arrays.arrays(field_of_view, pixels, names=("field_of_view", "pixels"))
    _arrays.require_positive("field_of_view", fov, xp, "rad")
    _arrays.require_positive("pixels", n, xp)
    if _arrays.any_known(fov >= xp.pi, xp):
        raise ValueError("field_of_view must be < π rad (180°)")
    if projection == "angular":
        return _arrays.result(fov / n)
    return _arrays.result(2.0 * xp.tan(fov / 2.0) / n)


def field_of_view_from_ifov(ifov: Any, pixels: Any, projection: str = "angular") -> Any:
    """Full field of view [rad] of ``pixels`` of a given IFOV: the inverse of
    :func:`ifov_from_field_of_view` (``n · IFOV``, or ``2 atan(n · IFOV / 2)`` rectilinear).

    Examples
    --------
    >>> round(float(field_of_view_from_ifov(2e-3, 100, "rectilinear")), 6)
    0.199337
    """
    lookup(FIELD_OF_VIEW_PROJECTIONS, projection, "projection")
    xp, (i, n) = _arrays.arrays(ifov, pixels, names=("ifov", "pixels"))
    _arrays.require_positive("ifov", i, xp, "rad")
    _arrays.require_positive("pixels", n, xp)
    if projection == "angular":
        return _arrays.result(n * i)
    return _arrays.result(2.0 * xp.atan(n * i / 2.0))


def diffraction_angle(wavelength: Array, aperture: Array) -> Any:
    """Smallest resolvable angle of a circular aperture, ``sin Δθ = 1.22 λ / D``, Eq. (5.3).

    Parameters
    ----------
    wavelength : array_like
        Wavelength λ [m], > 0.
    aperture : array_like
        Aperture (lens) diameter D [m], > 0, with ``1.22 λ / D <= 1``.

    Returns
    -------
    array_like
        Δθ [rad]. Check value: D = 122 mm, λ = 10 µm → 1.0e-4 rad (0.1 m at 1 km).

    Examples
    --------
    The check value of §5.5: a 122 mm aperture at 10 µm resolves 1e-4 rad (0.1 m at 1 km):

    >>> import targetacq as ta
    >>> print(f"{ta.diffraction_angle(10e-6, 0.122) * 1e3:.4f} mrad")
    0.1000 mrad
    """
    xp, (lam, d) = _arrays.arrays(wavelength, aperture, names=("wavelength", "aperture"))
    return _arrays.result(_diffraction_angle(lam, d, xp))


def _diffraction_angle(lam: Array, d: Array, xp: Any) -> Array:
    _arrays.require_positive("wavelength", lam, xp, "m")
    _arrays.require_positive("aperture", d, xp, "m")
    ratio = RAYLEIGH_FACTOR * lam / d
    if bool(xp.any(ratio > 1.0)):
        raise ValueError("aperture must be at least 1.22 × wavelength for Eq. (5.3)")
    return xp.asin(ratio)


def diffraction_spot(wavelength: Array, aperture: Array, focal_length: Array) -> Any:
    """Minimum resolvable separation on the focal plane, ``Δx = f·1.22 λ / D``, Eq. (5.4).

    Parameters
    ----------
    wavelength, aperture, focal_length : array_like
        λ, D and f [m], all > 0.

    Returns
    -------
    array_like
        Δx_min [m].

    Examples
    --------
    The same aperture behind a 0.5 m focal length: ``0.5 · 1.22 · 10e-6 / 0.122`` = 50 µm.

    >>> import targetacq as ta
    >>> print(f"{ta.diffraction_spot(10e-6, 0.122, 0.5) * 1e6:.2f} um")
    50.00 um
    """
    xp, (lam, d, f) = _arrays.arrays(
        wavelength, aperture, focal_length, names=("wavelength", "aperture", "focal_length")
    )
    _arrays.require_positive("wavelength", lam, xp, "m")
    _arrays.require_positive("aperture", d, xp, "m")
    _arrays.require_positive("focal_length", f, xp, "m")
    return _arrays.result(f * RAYLEIGH_FACTOR * lam / d)


def gaussian_psf(x: Array, y: Array, sigma_x: Array, sigma_y: Array) -> Any:
    """Gaussian point-spread function of the optics, peak-normalised to 1.

    ``h(x, y) = exp(-x²/(2σx²) - y²/(2σy²))``: Eq. (5.2) in Sonesson (2004) with the erratum
    of the user guide's errata (the printed ``exp(-(x²+y²)/(2(σx²+σy²)))`` is not a separable
    Gaussian).

    Parameters
    ----------
    x, y : array_like
        Position relative to the centre (any length or angle unit, the same as σ).
    sigma_x, sigma_y : array_like
        Standard deviations, > 0, same unit as x and y.

    Returns
    -------
    array_like
        h in [0, 1].

    Examples
    --------
    One standard deviation off the centre along each axis: ``exp(-1/2 - 1/2) = exp(-1)``.

    >>> import targetacq as ta
    >>> print(f"{ta.gaussian_psf(1.0, 2.0, 1.0, 2.0):.6f}")
    0.367879
    """
    xp, (xx, yy, sx, sy) = _arrays.arrays(
        x, y, sigma_x, sigma_y, names=("x", "y", "sigma_x", "sigma_y")
    )
    _arrays.require_positive("sigma_x", sx, xp)
    _arrays.require_positive("sigma_y", sy, xp)
    return _arrays.result(xp.exp(-(xx * xx) / (2 * sx * sx) - (yy * yy) / (2 * sy * sy)))


def blur_cycle_angle(blur_sigma: Array) -> Any:
    """Resolvable cycle of a Gaussian optics blur, ``≈ 2.86 σ`` (see the module docstring).

    Parameters
    ----------
    blur_sigma : array_like
        Angular standard deviation of the Gaussian PSF [rad], >= 0 (σ on the focal plane
        divided by the focal length).

    Returns
    -------
    array_like
        Angle of one resolvable cycle [rad]: ``π σ sqrt(2 / ln(1/M*))``.

    Examples
    --------
    A blur of σ = 0.1 mrad resolves one cycle in about 0.286 mrad:

    >>> from targetacq.physics.optics import blur_cycle_angle
    >>> print(f"{blur_cycle_angle(0.1e-3) * 1e3:.4f} mrad")
    0.2859 mrad
    """
    xp, (s,) = _arrays.arrays(blur_sigma, names=("blur_sigma",))
    _arrays.require_nonnegative("blur_sigma", s, xp, "rad")
    return _arrays.result(BLUR_CYCLE_PER_SIGMA * s)


def _cycle_angle(ifov_: Array, wavelength: Any, aperture: Any, blur_sigma: Any, xp: Any) -> Array:
    """Resolvable cycle from already-validated IFOV and optional optics (see module doc)."""
    if (wavelength is None) != (aperture is None):
        raise ValueError("give both wavelength and aperture for the diffraction limit, or neither")
    sampling = 2.0 * ifov_
    optics_sq = None
    given = {
        name: _arrays.as_float(value, xp, name)
        for name, value in (
            ("wavelength", wavelength),
            ("aperture", aperture),
            ("blur_sigma", blur_sigma),
        )
        if value is not None
    }
    _arrays.check_broadcast(("ifov", *given), (ifov_, *given.values()))
    if wavelength is not None:
        diff = _diffraction_angle(given["wavelength"], given["aperture"], xp)
        optics_sq = diff * diff
    if blur_sigma is not None:
        s = given["blur_sigma"]
        _arrays.require_nonnegative("blur_sigma", s, xp, "rad")
        blur = BLUR_CYCLE_PER_SIGMA * s
        optics_sq = blur * blur if optics_sq is None else optics_sq + blur * blur
    if optics_sq is None:
        return sampling
    return xp.maximum(sampling, xp.sqrt(optics_sq))


def resolvable_cycle_angle(
    ifov: Array, wavelength: Array = None, aperture: Array = None, blur_sigma: Array = None
) -> Any:
    """Angle of one resolvable cycle: the coarser of the sampling and the optics limits.

    ``cycle = max(2·IFOV, sqrt(θ_diff² + θ_blur²))`` with ``θ_diff = asin(1.22 λ/D)``
    (Eq. (5.3) and the erratum to §5.5 in the user guide) and ``θ_blur = 2.86 σ`` (Eq. (5.2),
    see the module docstring for the threshold and the quadrature sum).

    Parameters
    ----------
    ifov : array_like
        Pixel IFOV [rad], > 0.
    wavelength, aperture : array_like, optional
        Wavelength λ and aperture diameter D [m] for the diffraction limit; both or neither.
    blur_sigma : array_like, optional
        Angular standard deviation of a Gaussian optics blur [rad].

    Returns
    -------
    array_like
        Cycle angle [rad].

    Examples
    --------
    Sampling-limited (two pixels of the example camera), then a 25 mm aperture at 10 µm whose
    Rayleigh angle, ``asin(1.22 · 10e-6 / 0.025)`` = 0.488 mrad, is the coarser limit:

    >>> import targetacq as ta
    >>> ifov = ta.ifov(17e-6, 75e-3)
    >>> print(f"{ta.resolvable_cycle_angle(ifov) * 1e3:.4f} mrad")
    0.4533 mrad
    >>> print(f"{ta.resolvable_cycle_angle(ifov, wavelength=10e-6, aperture=0.025) * 1e3:.4f} mrad")
    0.4880 mrad
    """
    xp, (i,) = _arrays.arrays(ifov, names=("ifov",))
    _arrays.require_positive("ifov", i, xp, "rad")
    return _arrays.result(_cycle_angle(i, wavelength, aperture, blur_sigma, xp))


def cycles_on_target(
    critical_dimension: Array,
    range: Array,
    ifov: Array,
    *,
    wavelength: Array = None,
    aperture: Array = None,
    blur_sigma: Array = None,
) -> Any:
    """Resolvable cycles (line pairs) across the target's critical dimension.

    ``N = (d / R) / cycle`` with ``cycle = 2·IFOV`` (Johnson; Sonesson 2004 §3.5 and Fig. 3.3:
    a target 2.5 pixel rows high is 1.25 cycles), or the coarser optical limit when
    ``wavelength`` and ``aperture`` or ``blur_sigma`` are given (:func:`resolvable_cycle_angle`).
    The target's angular size uses the small-angle ``d / R``.

    Parameters
    ----------
    critical_dimension : array_like
        Critical dimension of the target as seen [m], > 0.
    range : array_like
        Slant range [m], > 0.
    ifov : array_like
        Pixel IFOV [rad], > 0.
    wavelength, aperture, blur_sigma : array_like, optional
        Optics limits, see :func:`resolvable_cycle_angle`.

    Returns
    -------
    array_like
        N [cycles].

    Examples
    --------
    A 2.3 m target seen by the example camera (one cycle = 0.4533 mrad): ``2.3 / R / 0.4533e-3``.

    >>> import numpy as np
    >>> import targetacq as ta
    >>> ifov = ta.ifov(17e-6, 75e-3)
    >>> print(np.round(ta.cycles_on_target(2.3, [1000.0, 5000.0], ifov), 4))
    [5.0735 1.0147]
    """
    xp, (d, r, i) = _arrays.arrays(
        critical_dimension, range, ifov, names=("critical_dimension", "range", "ifov")
    )
    _arrays.require_positive("critical_dimension", d, xp, "m")
    _arrays.require_positive("range", r, xp, "m")
    _arrays.require_positive("ifov", i, xp, "rad")
    cycle = _cycle_angle(i, wavelength, aperture, blur_sigma, xp)
    return _arrays.result(d / (r * cycle))


def range_for_cycles(
    critical_dimension: Array,
    cycles: Array,
    ifov: Array,
    *,
    wavelength: Array = None,
    aperture: Array = None,
    blur_sigma: Array = None,
) -> Any:
    """Range at which the target spans a given number of cycles: the inverse of
    :func:`cycles_on_target`, ``R = d / (N · cycle)``.

    Parameters
    ----------
    critical_dimension : array_like
        [m], > 0.
    cycles : array_like
        N [cycles], >= 0 (0 gives an infinite range; +inf gives 0).
    ifov : array_like
        [rad], > 0.
    wavelength, aperture, blur_sigma : array_like, optional
        Optics limits, see :func:`resolvable_cycle_angle`.

    Returns
    -------
    array_like
        Range [m].

    Examples
    --------
    Johnson's detection N50 (one cycle) across 2.3 m for the example camera: the 5074 m of
    ``targetacq dri --example``.

    >>> import targetacq as ta
    >>> print(round(float(ta.range_for_cycles(2.3, 1.0, ta.ifov(17e-6, 75e-3)))))
    5074
    """
    xp, (d, n, i) = _arrays.arrays(
        critical_dimension, cycles, ifov, names=("critical_dimension", "cycles", "ifov")
    )
    _arrays.require_positive("critical_dimension", d, xp, "m")
    _arrays.require_nonnegative("cycles", n, xp)
    _arrays.require_positive("ifov", i, xp, "rad")
    cycle = _cycle_angle(i, wavelength, aperture, blur_sigma, xp)
    denominator = n * cycle
    safe = xp.where(denominator == 0, 1.0, denominator)
    return _arrays.result(xp.where(denominator == 0, xp.inf, d / safe))


def pixels_per_metre(range: Array, ifov: Array) -> Any:
    """Pixel density on a target plane at a range, ``1 / (R · IFOV)`` [pixels/m].

    The quantity of the EN 62676-4 thresholds (small angle).

    Parameters
    ----------
    range : array_like
        [m], > 0.
    ifov : array_like
        [rad], > 0.

    Examples
    --------
    >>> import targetacq as ta
    >>> print(f"{ta.pixels_per_metre(1000.0, ta.ifov(17e-6, 75e-3)):.4f}")
    4.4118
    """
    xp, (r, i) = _arrays.arrays(range, ifov, names=("range", "ifov"))
    _arrays.require_positive("range", r, xp, "m")
    _arrays.require_positive("ifov", i, xp, "rad")
    return _arrays.result(1.0 / (r * i))


def range_for_pixel_density(pixel_density: Array, ifov: Array) -> Any:
    """Range at which the pixel density on the target falls to a threshold,
    ``R = 1 / (density · IFOV)`` [m]; inverse of :func:`pixels_per_metre`.

    Parameters
    ----------
    pixel_density : array_like
        [pixels/m], > 0.
    ifov : array_like
        [rad], > 0.

    Examples
    --------
    EN 62676-4's 25 pixels/m (detect) for the example camera: ``1 / (25 · 0.2267e-3)``.

    >>> import targetacq as ta
    >>> print(f"{ta.range_for_pixel_density(25.0, ta.ifov(17e-6, 75e-3)):.2f} m")
    176.47 m
    """
    xp, (q, i) = _arrays.arrays(pixel_density, ifov, names=("pixel_density", "ifov"))
    _arrays.require_positive("pixel_density", q, xp, "pixels/m")
    _arrays.require_positive("ifov", i, xp, "rad")
    return _arrays.result(1.0 / (q * i))
