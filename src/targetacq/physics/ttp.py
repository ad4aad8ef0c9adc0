"""Resolution from contrast and MTF: the Targeting Task Performance (TTP) metric.

The TTP metric of the NVESD range models (R. H. Vollmerhausen and E. Jacobs, "The Targeting
Task Performance (TTP) Metric: A New Model for Predicting Target Acquisition Performance",
NVESD Technical Report AMSEL-NV-TR-230 (2004); R. H. Vollmerhausen, E. Jacobs and
R. G. Driggers, "New metric for predicting target acquisition performance", Opt. Eng. 43(11)
(2004) 2806) counts how much of the target's spatial-frequency content the observer sees
above threshold:

    Φ = ∫ sqrt(C / CTF_sys(ξ)) dξ   over the frequencies ξ where C > CTF_sys(ξ),
    V = d / R · Φ,

with ``C`` the target's apparent contrast at the display (:func:`apparent_contrast`),
``CTF_sys`` the observer's contrast threshold through the imager (:func:`system_ctf`: the eye's
threshold :func:`eye_ctf` over the system MTF of :mod:`targetacq.physics.mtf`, raised by the
imager's noise, :func:`noise_factor`), ``d = sqrt(A_target)`` the target's characteristic
dimension and ``R`` the range. ``V`` (resolvable cycles on target, :func:`ttp_cycles`) then
goes through the TTPF of the TTP metric, ``P = (V/V50)^E / (1 + (V/V50)^E)`` with
``E = 1.51 + 0.24 V/V50`` (:func:`targetacq.acquisition.transforms.ttp_transform`), with a V50 per
task (the ``ttp-vehicles`` criterion, ``data/ttp_v50.csv``).

In SI units, Φ is in cycles/rad and ``d/R`` in rad, so V is in cycles; the papers' Φ in
cycles/mrad with ``d`` in m and ``R`` in km gives the same number.

The sensor is described by one typed record, :class:`TtpSystem`. The integral is evaluated by
the midpoint rule on a fixed grid of frequencies from 0 to the system's first MTF zero, so the
kernels are array-API code that broadcasts over ranges and contrasts (and traces under JAX).

What this implementation leaves out or simplifies (each is stated where it is used): the
display and eye MTFs (the display is taken as ideal, the eye's optics are inside its CTF);
aliasing (sampling enters as the phase-averaged sampling MTF); the noise bandwidths of the
NVESD noise model are taken in closed form (:func:`noise_factor`).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.physics import mtf as _mtf

__all__ = [
    "BARTEN_C",
    "DEFAULT_DISPLAY_LUMINANCE",
    "DEFAULT_EYE_PIXEL_ANGLE",
    "DEFAULT_FIELD_ANGLE",
    "DEFAULT_SCENE_CONTRAST",
    "NOISE_ALPHA",
    "TtpSystem",
    "apparent_contrast",
    "eye_ctf",
    "eye_ctf_minimum",
    "noise_factor",
    "system_ctf",
    "ttp_cycles",
    "ttp_value",
    "ttp_value_bound",
]

NOISE_ALPHA = 169.6
"""α of the NVESD noise model [Hz^(1/2)], the empirical constant that relates display noise to
the rise of the eye's contrast threshold (NVThermIP; Vollmerhausen & Jacobs (2004), the noise
model of the CTF)."""

BARTEN_C = 0.06
"""The constant ``c`` of Barten's simplified contrast-sensitivity formula."""

DEFAULT_DISPLAY_LUMINANCE = 34.26
"""Average display luminance [cd/m²]: 10 fL, the luminance the NVESD models assume for a
typical display (project default)."""

DEFAULT_FIELD_ANGLE = math.radians(15.0)
"""Angular size of the displayed field at the eye [rad] for Barten's formula (project default:
15°)."""

DEFAULT_EYE_PIXEL_ANGLE = math.radians(2.0 / 60.0)
"""Angle one detector pixel subtends at the observer's eye [rad] (project default: 2 arcmin,
a display viewed so that its pixels are just below the eye's acuity); it fixes the system
magnification ``SMAG = eye_pixel_angle / ifov``."""

DEFAULT_SCENE_CONTRAST = 5.0
"""Scene contrast temperature [K] (project default): the scene temperature difference that the
display's gain maps to its average luminance, so that ``C = τ ΔT / (2 SCN_tmp)``."""

DEFAULT_SAMPLES = 512
"""Frequencies of the midpoint rule of the TTP integral."""

_KAPPA = math.sqrt(math.pi / 4.4) * math.exp(1.0 / 17.6)  # ∫ B(ξ'/ξ)² dξ' / ξ, see noise_factor


# --------------------------------------------------------------------------------------------
# Checks (NaN kept, out-of-range values raise for the whole call).


# --------------------------------------------------------------------------------------------
# The observer.


def eye_ctf(
    frequency: Array,
    luminance: Array = DEFAULT_DISPLAY_LUMINANCE,
    field_angle: Array = DEFAULT_FIELD_ANGLE,
) -> Any:
    """The naked eye's contrast threshold function: Barten's simplified formula.

    ``CTF(u) = 1 / (a u exp(−b u) sqrt(1 + c exp(b u)))`` with ``u`` in cycles/degree at the eye,
    ``a = 540 (1 + 0.7/L)^(−0.2) / (1 + 12 / (w (1 + u/3)²))``, ``b = 0.3 (1 + 100/L)^0.15``,
    ``c = 0.06``, ``L`` the luminance [cd/m²] and ``w`` the angular size of the field [deg]
    (P. G. J. Barten, *Contrast Sensitivity of the Human Eye and Its Effects on Image Quality*,
    SPIE (1999), §3.9, the simplified formula; Barten, "Evaluation of subjective image quality
    with the square-root integral method", J. Opt. Soc. Am. A 7(10) (1990) 2024). It is the eye
    CTF of the NVESD models' TTP calculation (Vollmerhausen & Jacobs (2004), the eye CTF).

    Parameters
    ----------
    frequency : array_like
        Spatial frequency at the eye [cycles/rad], >= 0.
    luminance : array_like
        Average display luminance L [cd/m²], > 0; default 34.26 (10 fL).
    field_angle : array_like
        Angular size of the displayed field w [rad], > 0; default 15°.

    Returns
    -------
    array_like
        The threshold modulation [-], > 0; +inf at frequency 0.

    Examples
    --------
    The threshold is lowest, near 1/500, a few cycles per degree:

    >>> import math
    >>> round(float(eye_ctf(3.0 * 180.0 / math.pi)), 5)
    0.00207
    """
    xp, (f, lum, w) = _arrays.arrays(frequency, luminance, field_angle)
    _arrays.require_nonnegative_or_nan("frequency", f, xp, "cycles/rad")
    _arrays.require_positive_or_nan("luminance", lum, xp, "cd/m²")
    _arrays.require_positive_or_nan("field_angle", w, xp, "rad")
    return _arrays.result(_eye_ctf(f, lum, w, xp))


def eye_ctf_minimum(
    luminance: float = DEFAULT_DISPLAY_LUMINANCE, field_angle: float = DEFAULT_FIELD_ANGLE
) -> float:
    """A lower bound of :func:`eye_ctf` over all frequencies (scalars).

    The minimum over a fine logarithmic grid of 0.01–100 cycles/degree, less 1 % (the grid's
    step changes the CTF by far less near its minimum). With ``C <= 1``, ``MTF <= 1`` and a noise
    factor ``>= 1``, ``Φ <= sqrt(1 / min CTF_eye) / IFOV`` (the integral stops at ``1/IFOV``):
    a bound a solver can bracket the IFOV with.

    Examples
    --------
    >>> round(eye_ctf_minimum(), 5)
    0.00202
    """
    u = np.geomspace(0.01, 100.0, 4001) * (180.0 / math.pi)
    return 0.99 * float(np.min(eye_ctf(u, luminance, field_angle)))


def _eye_ctf(f: Array, lum: Array, w: Array, xp: Any) -> Array:
    u = f * (math.pi / 180.0)  # cycles/rad → cycles/degree
    w_deg = w * (180.0 / math.pi)
    a = 540.0 * (1.0 + 0.7 / lum) ** -0.2 / (1.0 + 12.0 / (w_deg * (1.0 + u / 3.0) ** 2))
    b = 0.3 * (1.0 + 100.0 / lum) ** 0.15
    bu = xp.minimum(b * u, 700.0)  # exp overflows beyond: the threshold is +inf there anyway
    sensitivity = a * u * xp.exp(-bu) * xp.sqrt(1.0 + BARTEN_C * xp.exp(bu))
    with np.errstate(divide="ignore"):
        return 1.0 / sensitivity


def noise_factor(
    frequency: Array, netd: Array, ifov: Array, frame_rate: Array, scene_contrast: Array
) -> Any:
    """How much the imager's noise raises the eye's contrast threshold.

    The NVESD noise model (Vollmerhausen & Jacobs (2004), the CTF in noise; NVThermIP):

        CTF_n(ξ) = CTF(ξ) · sqrt(1 + α² ρ² Q_H(ξ) Q_V / SCN²),

    with ``α = 169.6 Hz^(1/2)`` (:data:`NOISE_ALPHA`), ``ρ`` the noise spectral density of the
    imager and ``Q_H``, ``Q_V`` the noise bandwidths that the eye integrates at the bar
    frequency ξ, the noise being relative to the scene contrast ``SCN`` that sets the display's
    gain. This project takes them in closed form for a staring array of white noise:
    ``ρ² = NETD² · IFOV² / F_R`` [K² rad² s] (the noise of one pixel in one frame spread over its
    solid angle and frame time); ``Q_H = κ ξ`` with ``κ = ∫ B(x)² dx = sqrt(π/4.4) e^(1/17.6)``
    for the eye's bar-frequency filter ``B(x) = exp(−2.2 ln² x)`` of the NVESD model; and
    ``Q_V = 1/(2 IFOV)``, the noise bandwidth of a display that reconstructs each sample as a
    pixel-sized square (``∫ sinc²(η IFOV) dη``). The display's and the eye's MTFs inside the
    bandwidths are left out.

    Parameters
    ----------
    frequency : array_like
        Spatial frequency in object space [cycles/rad], >= 0.
    netd : array_like
        The imager's noise-equivalent contrast per pixel and frame, in the unit of
        ``scene_contrast`` (a thermal imager: NETD [K]), >= 0.
    ifov : array_like
        Detector angular pitch [rad], > 0.
    frame_rate : array_like
        F_R [Hz], > 0.
    scene_contrast : array_like
        SCN, in the unit of ``netd`` (a thermal imager: the scene contrast temperature [K]),
        > 0.

    Returns
    -------
    array_like
        The factor [-], >= 1.

    Examples
    --------
    >>> round(float(noise_factor(1000.0, 0.05, 3.4e-4, 30.0, 5.0)), 5)
    1.00726
    """
    xp, (f, n, i, fr, scn) = _arrays.arrays(frequency, netd, ifov, frame_rate, scene_contrast)
    _arrays.require_nonnegative_or_nan("frequency", f, xp, "cycles/rad")
    _arrays.require_nonnegative_or_nan("netd", n, xp)
    _arrays.require_positive_or_nan("ifov", i, xp, "rad")
    _arrays.require_positive_or_nan("frame_rate", fr, xp, "Hz")
    _arrays.require_positive_or_nan("scene_contrast", scn, xp)
    return _arrays.result(_noise_factor(f, n, i, fr, scn, xp))


def _noise_factor(f: Array, n: Array, i: Array, fr: Array, scn: Array, xp: Any) -> Array:
    rho2 = n * n * i * i / fr
    q_h = _KAPPA * f
    q_v = 0.5 / i
    return xp.sqrt(1.0 + NOISE_ALPHA**2 * rho2 * q_h * q_v / (scn * scn))


def apparent_contrast(contrast: Array, transmittance: Array, scene_contrast: Array) -> Any:
    """The target's contrast at the display after the path: ``C = min(1, τ |ΔT| / (2 SCN))``.

    The NVESD thermal models' target contrast, the target–background temperature difference
    over twice the scene contrast temperature (NVThermIP; Vollmerhausen & Jacobs (2004), the
    target contrast), with the path's transmittance ``τ`` on the temperature difference. A
    reflective sensor's Weber contrast is used as it is with ``scene_contrast = 0.5``. A
    display cannot show a modulation above 1: ``C`` is clipped there.

    Parameters
    ----------
    contrast : array_like
        ΔT at the target [K] (or another contrast in the unit of ``scene_contrast``); its sign is
        ignored.
    transmittance : array_like
        τ of the path, in [0, 1].
    scene_contrast : array_like
        SCN [K] (or the unit of ``contrast``), > 0.

    Returns
    -------
    array_like
        C in [0, 1].

    Examples
    --------
    >>> float(apparent_contrast(2.0, 0.5, 5.0))
    0.1
    """
    xp, (c, tau, scn) = _arrays.arrays(contrast, transmittance, scene_contrast)
    _arrays.require_where("transmittance", tau, (tau < 0) | (tau > 1), xp, "in [0, 1]")
    _arrays.require_positive_or_nan("scene_contrast", scn, xp)
    return _arrays.result(_apparent_contrast(c, tau, scn, xp))


def _apparent_contrast(c: Array, tau: Array, scn: Array, xp: Any) -> Array:
    value = tau * xp.abs(c) / (2.0 * scn)
    return xp.where(value > 1.0, 1.0, value)


# --------------------------------------------------------------------------------------------
# The sensor record and the system CTF.


@dataclass(frozen=True)
class TtpSystem:
    """What the TTP metric needs of an imager, its display and its observer.

    Fields are SI floats or arrays that broadcast with each other and with the ranges.

    Attributes
    ----------
    ifov : array_like
        Detector angular pitch [rad], > 0 (pixel pitch over focal length): the sampling pitch.
    aperture : array_like
        Entrance-pupil diameter D [m], > 0 (focal length over f-number).
    wavelength : array_like
        λ for the diffraction and turbulence MTFs [m], > 0 (the band's centre).
    netd : array_like
        Noise-equivalent contrast per pixel and frame [K for a thermal imager], >= 0.
    frame_rate : array_like
        F_R [Hz], > 0; default 30.
    fill_factor : array_like
        Fraction of the pixel that is active, in (0, 1]; the detector footprint is
        ``ifov · sqrt(fill_factor)`` wide. Default 1.
    blur_sigma : array_like
        Gaussian optics blur σ [rad], >= 0; default 0.
    jitter : array_like
        RMS line-of-sight jitter per axis [rad], >= 0; default 0.
    smear : array_like
        Linear image motion during one integration [rad], >= 0; default 0.
    cn2 : array_like
        Refractive-index structure constant of the path Cn² [m^(−2/3)], >= 0; default 0.
    exposure : {"long", "short"}
        The turbulence MTF's form (:func:`targetacq.physics.mtf.turbulence_mtf`); default long.
    scene_contrast : array_like
        The scene contrast temperature SCN [K], > 0; default 5 K.
    luminance : array_like
        Display luminance [cd/m²], > 0; default 34.26 (10 fL).
    eye_pixel_angle : array_like
        Angle of one pixel at the eye [rad], > 0; default 2 arcmin (the magnification).
    field_angle : array_like
        Angular size of the display at the eye [rad], > 0; default 15°.

    Examples
    --------
    >>> system = TtpSystem(ifov=17e-6 / 0.1, aperture=0.1, wavelength=10e-6, netd=0.05)
    >>> round(float(system.cutoff), 1)  # the detector's first zero, 1/IFOV, below D/λ = 10 000
    5882.4
    >>> TtpSystem(ifov=1e-4, aperture=0.1, wavelength=10e-6, netd=0.05, jitter=-1.0)
    Traceback (most recent call last):
    ...
    ValueError: jitter must be >= 0 rad, got -1
    """

    ifov: Any
    aperture: Any
    wavelength: Any
    netd: Any
    frame_rate: Any = 30.0
    fill_factor: Any = 1.0
    blur_sigma: Any = 0.0
    jitter: Any = 0.0
    smear: Any = 0.0
    cn2: Any = 0.0
    exposure: str = "long"
    scene_contrast: Any = DEFAULT_SCENE_CONTRAST
    luminance: Any = DEFAULT_DISPLAY_LUMINANCE
    eye_pixel_angle: Any = DEFAULT_EYE_PIXEL_ANGLE
    field_angle: Any = DEFAULT_FIELD_ANGLE

    def __post_init__(self) -> None:
        if self.exposure not in _mtf.EXPOSURES:
            raise ValueError(
                f"exposure must be one of {', '.join(_mtf.EXPOSURES)}; got {self.exposure!r}"
            )
        positive = {
            "ifov": "rad",
            "aperture": "m",
            "wavelength": "m",
            "frame_rate": "Hz",
            "scene_contrast": "K",
            "luminance": "cd/m²",
            "eye_pixel_angle": "rad",
            "field_angle": "rad",
        }
        nonnegative = {"netd": "K", "blur_sigma": "rad", "jitter": "rad", "smear": "rad"}
        for name, unit in positive.items():
            xp, (value,) = _arrays.arrays(getattr(self, name), names=(name,))
            _arrays.require_positive_or_nan(name, value, xp, unit)
        for name, unit in nonnegative.items():
            xp, (value,) = _arrays.arrays(getattr(self, name), names=(name,))
            _arrays.require_nonnegative_or_nan(name, value, xp, unit)
        xp, (cn2,) = _arrays.arrays(self.cn2, names=("cn2",))
        _arrays.require_nonnegative_or_nan("cn2", cn2, xp, "m^-2/3")
        xp, (fill,) = _arrays.arrays(self.fill_factor, names=("fill_factor",))
        _arrays.require_where("fill_factor", fill, (fill <= 0) | (fill > 1), xp, "in (0, 1]")

    @property
    def magnification(self) -> Any:
        """System magnification SMAG = eye_pixel_angle / ifov [-]."""
        return self.eye_pixel_angle / self.ifov

    @property
    def cutoff(self) -> Any:
        """The highest frequency the TTP integral covers [cycles/rad]: the first zero of the
        system MTF (optics ``D/λ``, detector ``1/width``, sampling ``1/pitch``, motion
        ``1/smear``)."""
        xp, (i, d, lam, fill, smear) = _arrays.arrays(
            self.ifov, self.aperture, self.wavelength, self.fill_factor, self.smear
        )
        return _arrays.result(self._cutoff(i, d, lam, fill, smear, xp))

    @staticmethod
    def _cutoff(i: Array, d: Array, lam: Array, fill: Array, smear: Array, xp: Any) -> Array:
        limit = xp.minimum(d / lam, 1.0 / (i * xp.sqrt(fill)))
        limit = xp.minimum(limit, 1.0 / i)
        with np.errstate(divide="ignore"):
            motion = xp.where(smear > 0, 1.0 / xp.where(smear > 0, smear, 1.0), xp.inf)
        return xp.minimum(limit, motion)

    def mtf(self, frequency: Array, range: Array) -> Any:
        """The system MTF at a range [-] (turbulence depends on it):
        :func:`targetacq.physics.mtf.system_mtf` of this record's components."""
        return _mtf.system_mtf(frequency, self._components(range))

    def _components(self, range: Any) -> dict[str, dict[str, Any]]:
        width = self.ifov * self.fill_factor**0.5
        return {
            "diffraction": {"wavelength": self.wavelength, "aperture": self.aperture},
            "detector": {"ifov": width},
            "sampling": {"pitch": self.ifov},
            "blur": {"blur_sigma": self.blur_sigma},
            "jitter": {"jitter": self.jitter},
            "motion": {"smear": self.smear},
            "turbulence": {
                "range": range,
                "wavelength": self.wavelength,
                "cn2": self.cn2,
                "aperture": self.aperture,
                "exposure": self.exposure,
            },
        }


def system_ctf(frequency: Array, range: Array, system: TtpSystem) -> Any:
    """The observer's contrast threshold through the imager at a range.

    ``CTF_sys(ξ) = CTF_eye(ξ / SMAG) / MTF_sys(ξ, R) · noise_factor(ξ)`` (Vollmerhausen & Jacobs
    (2004), the system CTF; Vollmerhausen, Jacobs & Driggers (2004)): the eye's threshold
    (:func:`eye_ctf`) at the frequency the display shows it, divided by the system MTF
    (:meth:`TtpSystem.mtf`), raised by the noise (:func:`noise_factor`).

    Parameters
    ----------
    frequency : array_like
        Object-space frequency [cycles/rad], >= 0.
    range : array_like
        [m], >= 0 (for the turbulence MTF).
    system : TtpSystem

    Returns
    -------
    array_like
        CTF_sys [-], > 0; +inf where the MTF is 0.

    Examples
    --------
    >>> system = TtpSystem(ifov=1.7e-4, aperture=0.1, wavelength=10e-6, netd=0.05)
    >>> round(float(system_ctf(1000.0, 1000.0, system)), 5)
    0.00284
    """
    xp, (f, r) = _arrays.arrays(frequency, range)
    _arrays.require_nonnegative_or_nan("frequency", f, xp, "cycles/rad")
    _arrays.require_nonnegative_or_nan("range", r, xp, "m")
    return _arrays.result(_system_ctf(f, r, system, xp))


def _system_ctf(f: Array, r: Array, system: TtpSystem, xp: Any) -> Array:
    eye = _eye_ctf(f / system.magnification, system.luminance, system.field_angle, xp)
    mtf = system.mtf(f, r)
    noise = _noise_factor(f, system.netd, system.ifov, system.frame_rate, system.scene_contrast, xp)
    with np.errstate(divide="ignore"):
        return xp.where(mtf > 0, eye / xp.where(mtf > 0, mtf, 1.0), xp.inf) * noise


# --------------------------------------------------------------------------------------------
# The metric.


def ttp_value(
    range: Array,
    contrast: Array,
    transmittance: Array,
    system: TtpSystem,
    samples: int = DEFAULT_SAMPLES,
) -> Any:
    """The TTP value ``Φ = ∫ sqrt(C / CTF_sys(ξ)) dξ`` over the frequencies where ``C > CTF_sys``.

    Vollmerhausen, Jacobs & Driggers (2004), the TTP metric; Vollmerhausen & Jacobs (2004). ``C``
    is :func:`apparent_contrast` of the target's ΔT through the path and ``CTF_sys`` is
    :func:`system_ctf` at the range. The integral runs from 0 to :attr:`TtpSystem.cutoff` by the
    midpoint rule on ``samples`` frequencies (the integrand is bounded and vanishes at 0).

    Parameters
    ----------
    range : array_like
        [m], > 0.
    contrast : array_like
        The target's ΔT [K] (or the unit of ``system.scene_contrast``).
    transmittance : array_like
        τ of the path at the range, in [0, 1].
    system : TtpSystem
    samples : int
        Frequencies of the midpoint rule (default 512).

    Returns
    -------
    array_like
        Φ [cycles/rad], >= 0.

    Examples
    --------
    >>> system = TtpSystem(ifov=1.7e-4, aperture=0.1, wavelength=10e-6, netd=0.05)
    >>> round(float(ttp_value(1000.0, 2.0, 1.0, system)), 0)
    19768.0
    """
    xp, (r, c, tau) = _arrays.arrays(range, contrast, transmittance)
    _arrays.require_positive_or_nan("range", r, xp, "m")
    _arrays.require_where("transmittance", tau, (tau < 0) | (tau > 1), xp, "in [0, 1]")
    if not isinstance(samples, int) or samples < 2:
        raise ValueError(f"samples must be an integer >= 2, got {samples!r}")
    return _arrays.result(_ttp_value(r, c, tau, system, samples, xp))


def _ttp_value(r: Array, c: Array, tau: Array, system: TtpSystem, samples: int, xp: Any) -> Array:
    i, d, lam, fill, smear = (
        _arrays.as_float(v, xp)
        for v in (system.ifov, system.aperture, system.wavelength, system.fill_factor, system.smear)
    )
    cutoff = TtpSystem._cutoff(i, d, lam, fill, smear, xp)
    target = _apparent_contrast(c, tau, system.scene_contrast, xp)
    shape = xp.broadcast_arrays(r, target, cutoff)[0].shape
    r_, target_, cutoff_ = (xp.broadcast_to(v, shape)[..., None] for v in (r, target, cutoff))
    u = (xp.arange(samples, dtype=r.dtype) + 0.5) / samples
    f = u * cutoff_
    threshold = _system_ctf(f, r_, _expand(system, xp), xp)
    seen = target_ > threshold
    ratio = xp.where(seen, target_ / xp.where(seen, threshold, 1.0), 0.0)
    value = xp.sum(xp.sqrt(ratio), axis=-1) * (cutoff_[..., 0] / samples)
    return xp.where(xp.isnan(r + target + cutoff), xp.nan, value)


def ttp_value_bound(system: TtpSystem) -> Any:
    """An upper bound of :func:`ttp_value` at any range and contrast [cycles/rad].

    Φ for the largest contrast a display shows (``C = 1``), a clear path and no turbulence:
    Φ cannot exceed it, since a lower contrast, transmittance or MTF only lowers the integrand
    and shrinks the frequencies where ``C > CTF_sys``. A range solver's bracket
    (``V(R) <= d · bound / R``).

    Examples
    --------
    >>> system = TtpSystem(ifov=1.7e-4, aperture=0.1, wavelength=10e-6, netd=0.05)
    >>> bool(ttp_value_bound(system) >= ttp_value(1000.0, 2.0, 1.0, system))
    True
    """
    clear = dataclasses.replace(system, cn2=0.0)
    return ttp_value(1.0, 2.0 * system.scene_contrast, 1.0, clear)


def _expand(system: TtpSystem, xp: Any) -> TtpSystem:
    """The record with each array field given a trailing axis for the frequency grid."""
    changes = {}
    for name in TtpSystem.__dataclass_fields__:
        value = getattr(system, name)
        if name == "exposure":
            continue
        array = _arrays.as_float(value, xp)
        if array.ndim:
            changes[name] = array[..., None]
    if not changes:
        return system
    fields = {name: getattr(system, name) for name in TtpSystem.__dataclass_fields__}
    fields.update(changes)
    return TtpSystem(**fields)


def ttp_cycles(
    range: Array,
    critical_dimension: Array,
    contrast: Array,
    transmittance: Array,
    system: TtpSystem,
) -> Any:
    """Resolvable cycles on target by the TTP metric, ``V = d / R · Φ``.

    Vollmerhausen, Jacobs & Driggers (2004): ``V = sqrt(A_tgt) · TTP / R`` with the target's
    area ``A_tgt`` (``d = sqrt(A_tgt)`` its characteristic dimension) and Φ = :func:`ttp_value`.

    Parameters
    ----------
    range : array_like
        [m], > 0.
    critical_dimension : array_like
        d = sqrt(A_tgt) [m], > 0.
    contrast : array_like
        ΔT at the target [K].
    transmittance : array_like
        τ of the path at the range, in [0, 1].
    system : TtpSystem

    Returns
    -------
    array_like
        V [cycles], >= 0.

    Examples
    --------
    >>> system = TtpSystem(ifov=1.7e-4, aperture=0.1, wavelength=10e-6, netd=0.05)
    >>> round(float(ttp_cycles(1000.0, 2.3, 2.0, 1.0, system)), 2)
    45.47
    """
    xp, (r, d, c, tau) = _arrays.arrays(range, critical_dimension, contrast, transmittance)
    _arrays.require_positive_or_nan("range", r, xp, "m")
    _arrays.require_positive_or_nan("critical_dimension", d, xp, "m")
    return _arrays.result(d / r * ttp_value(r, c, tau, system))
