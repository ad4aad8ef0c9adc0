"""From physics to probabilities in one broadcasting call.

:func:`scene_acquisition` chains the topic modules: radiometry gives the target and background
signals and their contrast (ch. 6), the clutter the SCR (§3.7, (6.9)) — both in
:func:`scene_signature` — and the range case of :mod:`targetacq.core.cases` the rest: geometry
and optics the cycles on target (ch. 3, 5), the atmosphere the transmittance and SNR (ch. 7),
and the transforms with the noise model the three probabilities (ch. 3, and the noise law of the
user guide's assumptions). It adds no physics of its own.

Atmosphere and SCR: target and background are attenuated alike along the same path, and the
1/R² and cos⁴ factors of (6.18) are the same for neighbouring cells, so the SCR is the ratio of
exitances at the scene. The atmosphere enters through the SNR of Eq. (7.7).

The scene is a :class:`Scene` record, the sensor, path and model a
:class:`targetacq.core.cases.RangeCase`. Clutter is given as the background's temperature spread
in kelvin (``Scene.clutter_std``), as in scenarios and the CLI, or as an exitance spread in W/m²
(``Scene.clutter_exitance_std``).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

from targetacq.acquisition.probabilities import Acquisition
from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.base.limits import MAX_TEMPERATURE
from targetacq.core.cases import RangeCase, case_acquisition
from targetacq.physics import clutter, radiometry

_TASKS = ("detection", "recognition", "identification")

__all__ = ["Scene", "SceneAcquisition", "SceneSignature", "scene_acquisition", "scene_signature"]


@dataclass(frozen=True)
class SceneSignature:
    """Target and background signals at the scene, their contrast and the clutter.

    Attributes
    ----------
    target, background : array_like
        Exitances at the scene [W/m²].
    contrast : array_like
        ``|target − background|`` [W/m²].
    clutter : array_like or None
        Standard deviation of the background exitance [W/m²]; None where none was given.
    scr : array_like or None
        Signal-to-clutter ratio [1], Eq. (6.9); None where no clutter was given.
    sign : array_like or None
        The contrast's sign, ``sign(target − background)``: +1 a target brighter (warmer) than
        its background, −1 a negative contrast (e.g. a low-emissivity surface reflecting a cold
        sky, §6.3), 0 none. The acquisition uses ``|contrast|`` either way (Eq. (3.15)).
    """

    target: Any
    background: Any
    contrast: Any
    clutter: Any
    scr: Any
    sign: Any = None


@dataclass(frozen=True)
class Scene:
    """The physical scene of :func:`scene_acquisition`: a target and its background in a band.

    The inputs of :func:`scene_signature`, as one record; all array fields broadcast together.

    Attributes
    ----------
    band : (float, float) or str
        Sensor band (λ1, λ2) [m] or a name ("mwir", "lwir", "visible").
    target_temperature, background_temperature : array_like
        [K], >= 0.
    target_emissivity, background_emissivity : array_like
        In [0, 1]; default blackbodies.
    target_exitance, background_exitance : array_like, optional
        [W/m²], >= 0; given, they replace ``ε · M_band(T)`` (e.g. reflected sunlight ``r·E`` in
        the visible band, :func:`targetacq.physics.radiometry.reflected_exitance`).
    clutter_std : array_like, optional
        The background's temperature spread σ_T [K], >= 0, as in scenarios and the CLI (not with
        ``background_exitance``); the clutter is ``ε_b · dM/dT · σ_T`` in the band
        (:func:`targetacq.physics.clutter.temperature_spread_clutter`).
    clutter_exitance_std : array_like, optional
        The clutter as the standard deviation of the background exitance [W/m²], >= 0, instead
        of ``clutter_std``.
    sky_temperature : array_like, optional
        Effective sky temperature [K], >= 0: surfaces of emissivity ε < 1 then also reflect
        ``(1 − ε)`` of the sky's band exitance (§6.3,
        :func:`targetacq.physics.radiometry.sky_reflected_exitance`); None for no reflection.

    Examples
    --------
    >>> seen = Scene("lwir", 305.0, 295.0, clutter_std=2.0).signature()
    >>> bool(seen.scr > 1)
    True
    """

    band: str | tuple[float, float]
    target_temperature: Array
    background_temperature: Array
    target_emissivity: Array = 1.0
    background_emissivity: Array = 1.0
    target_exitance: Array | None = None
    background_exitance: Array | None = None
    clutter_std: Array | None = None
    clutter_exitance_std: Array | None = None
    sky_temperature: Array | None = None

    def signature(self) -> SceneSignature:
        """The scene's signals, contrast, clutter and SCR (:func:`scene_signature`)."""
        return scene_signature(
            self.band,
            self.target_temperature,
            self.background_temperature,
            target_emissivity=self.target_emissivity,
            background_emissivity=self.background_emissivity,
            target_exitance=self.target_exitance,
            background_exitance=self.background_exitance,
            clutter_std=self.clutter_std,
            clutter_exitance_std=self.clutter_exitance_std,
            sky_temperature=self.sky_temperature,
        )


def scene_signature(
    band: Any,
    target_temperature: Array,
    background_temperature: Array,
    *,
    target_emissivity: Array = 1.0,
    background_emissivity: Array = 1.0,
    target_exitance: Array = None,
    background_exitance: Array = None,
    clutter_std: Array = None,
    clutter_exitance_std: Array = None,
    sky_temperature: Array = None,
) -> SceneSignature:
    """Signals of a target and its background in a band, their contrast, clutter and SCR.

    Grey-body band exitances ``ε · M_band(T)``, Eqs. (6.4) and (6.12) in Sonesson (2004)
    (:func:`targetacq.physics.radiometry.grey_body_exitance`); the clutter of a background
    temperature spread σ_T is ``ε_b · dM/dT · σ_T``
    (:func:`targetacq.physics.clutter.temperature_spread_clutter`), and ``SCR = |M_t − M_b| /
    clutter``, Eq. (6.9) (:func:`targetacq.physics.clutter.signal_to_clutter_ratio`). All array
    inputs broadcast
    together.

    Parameters
    ----------
    band : (float, float) or str
        Sensor band (λ1, λ2) [m] or a name ("mwir", "lwir", "visible").
    target_temperature, background_temperature : array_like
        [K], >= 0.
    target_emissivity, background_emissivity : array_like
        In [0, 1]; default blackbodies.
    target_exitance, background_exitance : array_like, optional
        [W/m²], >= 0; given, they replace ``ε · M_band(T)`` (e.g. reflected sunlight ``r·E`` in
        the visible band, :func:`targetacq.physics.radiometry.reflected_exitance`).
    clutter_std : array_like, optional
        The background's temperature spread σ_T [K], >= 0 (not with ``background_exitance``).
    clutter_exitance_std : array_like, optional
        The clutter as the standard deviation of the background exitance [W/m²], >= 0, instead
        of ``clutter_std``.
    sky_temperature : array_like, optional
        Effective sky temperature [K], >= 0: the emitted exitances become
        ``ε M_band(T) + (1 − ε) M_band(T_sky)`` (§6.3,
        :func:`targetacq.physics.radiometry.sky_reflected_exitance`), so a low-emissivity target
        under a cold sky can be colder than its background (``sign`` −1); None for no reflection
        (``ε M_band(T)``).

    Returns
    -------
    SceneSignature

    Examples
    --------
    >>> from targetacq.physics.radiometry import band_exitance, band_exitance_derivative
    >>> seen = scene_signature("lwir", 305.0, 295.0, clutter_std=2.0)
    >>> contrast = band_exitance(305.0, "lwir") - band_exitance(295.0, "lwir")
    >>> bool(abs(seen.scr - contrast / (band_exitance_derivative(295.0, "lwir") * 2.0)) < 1e-12)
    True
    """
    if clutter_std is not None and clutter_exitance_std is not None:
        raise ValueError("give one of clutter_std [K] and clutter_exitance_std [W/m²]")
    if target_exitance is None:
        target_exitance = _emitted(
            "target", target_emissivity, target_temperature, band, sky_temperature
        )
    if background_exitance is None:
        background_exitance = _emitted(
            "background", background_emissivity, background_temperature, band, sky_temperature
        )
    elif clutter_std is not None:
        raise ValueError(
            "clutter_std is a temperature spread [K] of the emitting background; with "
            "background_exitance give clutter_exitance_std [W/m²]"
        )
    xp, (m_t, m_b) = _arrays.arrays(target_exitance, background_exitance)
    _arrays.require_nonnegative("target_exitance", m_t, xp, "W/m²")
    _arrays.require_nonnegative("background_exitance", m_b, xp, "W/m²")
    spread = None
    if clutter_std is not None:
        _arrays.require_nonnegative("clutter_std", _arrays.as_float(clutter_std, xp), xp, "K")
        spread = clutter.temperature_spread_clutter(
            background_emissivity, background_temperature, clutter_std, band
        )
    elif clutter_exitance_std is not None:
        spread = clutter_exitance_std
        _arrays.require_nonnegative(
            "clutter_exitance_std", _arrays.as_float(spread, xp), xp, "W/m²"
        )
    return SceneSignature(
        target=target_exitance,
        background=background_exitance,
        contrast=_arrays.result(xp.abs(m_t - m_b)),
        clutter=spread,
        scr=None if spread is None else clutter.signal_to_clutter_ratio(m_t, m_b, spread),
        sign=_arrays.result(xp.sign(m_t - m_b)),
    )


def _emitted(
    name: str, emissivity: Any, temperature: Any, band: Any, sky_temperature: Any = None
) -> Any:
    xp, (eps, kelvin) = _arrays.arrays(
        emissivity, temperature, names=(f"{name}_emissivity", f"{name}_temperature")
    )
    _arrays.require_unit_interval(f"{name}_emissivity", eps, xp)
    # The scene's domain (limits.MAX_TEMPERATURE): far above it Planck's law overflows and a
    # later check would blame a derived quantity (the SCR) the user never gave.
    _arrays.require_in_range(f"{name}_temperature", kelvin, xp, 0.0, MAX_TEMPERATURE, "K")
    if sky_temperature is not None:
        sky = _arrays.as_float(sky_temperature, xp, "sky_temperature")
        _arrays.require_in_range("sky_temperature", sky, xp, 0.0, MAX_TEMPERATURE, "K")
        return radiometry.sky_reflected_exitance(eps, kelvin, sky, band)
    return radiometry.grey_body_exitance(eps, kelvin, band)


@dataclass(frozen=True)
class SceneAcquisition(Acquisition):
    """Descriptive factors and probabilities, each an array of the broadcast input shape.

    The probabilities (``detection``, ``recognition``, ``identification``, ``effect``) as in
    :class:`targetacq.acquisition.probabilities.Acquisition`, and:

    Attributes
    ----------
    cycles : array_like
        N, resolvable cycles across the critical dimension [cycles].
    contrast : array_like
        ``|ε_t M_t − ε_b M_b|`` at the scene [W/m²].
    scr : array_like
        Signal-to-clutter ratio [1] (+inf where no clutter was given).
    transmittance : array_like
        τ of the path [1].
    snr : array_like
        SNR of Eq. (7.7) [dB].
    """

    cycles: Any
    contrast: Any
    scr: Any
    transmittance: Any
    snr: Any


def scene_acquisition(
    range: Array,
    case: RangeCase,
    scene: Scene,
    *,
    netd: Array | None = None,
    netd_temperature: Array = 300.0,
    quantisation_step: Array | None = None,
) -> SceneAcquisition:
    """Probabilities of detection, recognition and identification from the physical scene.

    The signature of the scene (:func:`scene_signature`) gives the case its SCR and, with the
    sensor's NETD, its contrast against the sensor's noise; then
    :func:`targetacq.core.cases.case_acquisition` of the case. All array inputs broadcast
    together.

    Parameters
    ----------
    range : array_like
        Slant range [m], > 0.
    case : RangeCase
        The sensor, the target's critical dimension, the path and the model choices
        (:class:`targetacq.core.cases.RangeCase`: critical dimension [m], IFOV [rad], optics
        limits, criterion, transform and its options, extinction [Np/m] (None: no atmosphere),
        foliage, hot spot, moving, noise model, target area [m²], motion and semantics). Its
        ``scr`` or ``region`` gives the clutter directly, instead of the scene's clutter; its
        contrast and noise-equivalent contrast come from the scene and ``netd``, so it gives
        neither (nor an MRTD curve).
    scene : Scene
        Target and background: band, temperatures [K], emissivities or exitances [W/m²], and
        the clutter as a temperature spread [K] or an exitance spread [W/m²].
    netd : array_like, optional
        The sensor's NETD [K], >= 0, quoted at ``netd_temperature`` [K]: the sensor's own noise
        against the exitance contrast (:mod:`targetacq.physics.detector_noise`); None for none.
    netd_temperature : array_like
        [K], the temperature at which ``netd`` is quoted.
    quantisation_step : array_like, optional
        Smallest contrast the detector resolves [W/m²]
        (:func:`targetacq.physics.radiometry.quantisation_step`); a smaller contrast gives
        probability 0 (§6.8).

    Returns
    -------
    SceneAcquisition

    Examples
    --------
    >>> case = RangeCase(2.3, 2e-4)
    >>> res = scene_acquisition(1150.0, case, Scene("lwir", 305.0, 295.0, clutter_std=2.0))
    >>> round(float(res.cycles), 12), bool(res.scr > 1), float(res.transmittance)
    (5.0, True, 1.0)
    """
    if not isinstance(case, RangeCase):
        raise TypeError(f"case must be a RangeCase; got {type(case).__name__}")
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a Scene; got {type(scene).__name__}")
    given = [
        v is not None
        for v in (scene.clutter_std, scene.clutter_exitance_std, case.scr, case.region)
    ]
    if sum(given) > 1:
        raise ValueError(
            "give at most one of the scene's clutter_std and clutter_exitance_std and the "
            "case's scr and region"
        )
    for name in ("contrast", "noise_equivalent_contrast", "mrtd"):
        if getattr(case, name) is not None:
            raise ValueError(
                f"the case's {name} is not for scene_acquisition: the scene gives the contrast "
                "(an exitance difference) and netd the sensor's noise"
            )
    seen = scene.signature()
    scr_value = seen.scr if seen.scr is not None else case.scr
    changes: dict[str, Any] = {"scr": scr_value}
    if netd is not None:
        from targetacq.physics.detector_noise import netd_exitance

        changes["contrast"] = seen.contrast
        changes["noise_equivalent_contrast"] = netd_exitance(netd, scene.band, netd_temperature)
    elif case.target_area is not None:
        raise ValueError("target_area is used with the sensor's noise (netd)")
    case = dataclasses.replace(case, **changes)
    found = case_acquisition(case, range)
    xp, (det, rec, ide, contrast) = _arrays.arrays(
        found.detection, found.recognition, found.identification, seen.contrast
    )
    if quantisation_step is not None:
        step = _arrays.as_float(quantisation_step, xp)
        _arrays.require_nonnegative("quantisation_step", step, xp, "W/m²")
        invisible = contrast < step
        det, rec, ide = (xp.where(invisible, 0.0 * p, p) for p in (det, rec, ide))
    scr_out = xp.full_like(contrast, xp.inf) if scr_value is None else scr_value
    # A NaN signature (a NaN temperature, emissivity or exitance) is NaN out: without noise or
    # clutter the contrast enters no factor, and the geometric answer would hide it.
    unknown = xp.isnan(contrast)
    det, rec, ide = (xp.where(unknown, xp.nan, p) for p in (det, rec, ide))
    snr = xp.where(unknown, xp.nan, _arrays.as_float(found.snr, xp))
    scr_out = xp.where(unknown, xp.nan, _arrays.as_float(scr_out, xp))
    arrays = xp.broadcast_arrays(
        *_arrays.arrays(found.cycles)[1],
        contrast,
        scr_out,
        *_arrays.arrays(found.transmittance)[1],
        snr,
        det,
        rec,
        ide,
    )
    names = ("cycles", "contrast", "scr", "transmittance", "snr", *_TASKS)
    return SceneAcquisition(
        **{name: _arrays.result(a) for name, a in zip(names, arrays, strict=True)}
    )
