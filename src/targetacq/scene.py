"""From physics to probabilities in one broadcasting call.

:func:`scene_acquisition` chains the topic modules: geometry and optics give the cycles on
target (Sonesson 2004 ch. 3, 5), radiometry the target and background signals and their
contrast (ch. 6), the clutter the SCR (§3.7, (6.9)), the atmosphere the transmittance and SNR
(ch. 7), and the transforms with the noise model the three probabilities (ch. 3, MODEL.md §6).
It adds no physics of its own.

Atmosphere and SCR: target and background are attenuated alike along the same path, and the
1/R² and cos⁴ factors of (6.18) are the same for neighbouring cells, so the SCR is the ratio of
exitances at the scene. The atmosphere enters through the SNR of Eq. (7.7).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from targetacq import _arrays, atmosphere, clutter, optics, radiometry
from targetacq.acquisition import Acquisition, acquisition_probabilities

_TASKS = ("detection", "recognition", "identification")

__all__ = ["SceneAcquisition", "scene_acquisition"]


@dataclass(frozen=True)
class SceneAcquisition(Acquisition):
    """Descriptive factors and probabilities, each an array of the broadcast input shape.

    The probabilities (``detection``, ``recognition``, ``identification``, ``effect``) as in
    :class:`targetacq.acquisition.Acquisition`, and:

    Attributes
    ----------
    cycles : array_like
        N, resolvable cycles across the critical dimension [cycles].
    contrast : array_like
        |ε_t M_t − ε_b M_b| at the scene [W/m²].
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
    range: Any,
    critical_dimension: Any,
    ifov: Any,
    band: Any,
    target_temperature: Any,
    background_temperature: Any,
    *,
    target_emissivity: Any = 1.0,
    background_emissivity: Any = 1.0,
    target_exitance: Any = None,
    background_exitance: Any = None,
    clutter_std: Any = None,
    scr: Any = None,
    clutter_region: str | None = None,
    extinction: Any = 0.0,
    foliage: Any = 1.0,
    quantisation_step: Any = None,
    criterion: Any = "johnson",
    transform: str = "ttpf",
    noise_model: Any = "variance-sum",
    hot_spot: bool = False,
    moving: bool = False,
    wavelength: Any = None,
    aperture: Any = None,
    blur_sigma: Any = None,
    **options: Any,
) -> SceneAcquisition:
    """Probabilities of detection, recognition and identification from the physical scene.

    All array inputs broadcast together.

    Parameters
    ----------
    range : array_like
        Slant range [m], > 0.
    critical_dimension : array_like
        Critical dimension of the target as seen [m], > 0.
    ifov : array_like
        Pixel IFOV [rad], > 0.
    band : (float, float) or str
        Sensor band (λ1, λ2) [m] or a name ("mwir", "lwir", "visible").
    target_temperature, background_temperature : array_like
        [K], >= 0.
    target_emissivity, background_emissivity : array_like
        In [0, 1]; default blackbodies.
    target_exitance, background_exitance : array_like, optional
        [W/m²]; given, they replace ``ε · band_exitance(T)`` (e.g. reflected sunlight ``r·E`` in
        the visible band, :func:`targetacq.radiometry.reflected_exitance`).
    clutter_std : array_like, optional
        Clutter as the standard deviation of the background exitance [W/m²], >= 0.
    scr : array_like, optional
        The SCR directly, instead of ``clutter_std``.
    clutter_region : {"low", "medium", "high"}, optional
        The Table 3.5 region, when only that is known.
    extinction : array_like
        γ of the path [Np/m], >= 0; 0 for no atmosphere.
    foliage : array_like
        Transmittance of foliage in front of the target, in [0, 1]
        (:func:`targetacq.atmosphere.foliage_transmittance`); 1 for none.
    quantisation_step : array_like, optional
        Smallest contrast the detector resolves [W/m²]
        (:func:`targetacq.radiometry.quantisation_step`); a smaller contrast gives probability 0
        (§6.8).
    criterion, transform, noise_model
        As in :func:`targetacq.acquisition_probabilities`.
    hot_spot, moving : bool
        As in :func:`targetacq.transforms.schmieder_weathersby`.
    wavelength, aperture, blur_sigma : array_like, optional
        Optics limits on the cycle (:func:`targetacq.optics.resolvable_cycle_angle`).
    **options
        Options of ``transform``.

    Returns
    -------
    SceneAcquisition
    """
    given = [v is not None for v in (clutter_std, scr, clutter_region)]
    if sum(given) > 1:
        raise ValueError("give at most one of clutter_std, scr and clutter_region")
    n = optics.cycles_on_target(
        critical_dimension,
        range,
        ifov,
        wavelength=wavelength,
        aperture=aperture,
        blur_sigma=blur_sigma,
    )
    if target_exitance is None:
        target_exitance = _emitted(target_emissivity, target_temperature, band, "target")
    if background_exitance is None:
        background_exitance = _emitted(
            background_emissivity, background_temperature, band, "background"
        )
    xp, (m_t, m_b, n) = _arrays.arrays(target_exitance, background_exitance, n)
    _arrays.require_nonnegative("target_exitance", m_t, xp, "W/m²")
    _arrays.require_nonnegative("background_exitance", m_b, xp, "W/m²")
    contrast = xp.abs(m_t - m_b)
    if clutter_std is not None:
        scr_value = clutter.signal_to_clutter_ratio(m_t, m_b, clutter_std)
    elif scr is not None:
        scr_value = scr
    else:
        scr_value = None
    xp_f, (tau_f,) = _arrays.arrays(foliage)
    _arrays.require_unit_interval("foliage", tau_f, xp_f)
    tau = atmosphere.transmittance(extinction, range) * tau_f
    snr = atmosphere.snr_from_transmittance(tau)
    acq = acquisition_probabilities(
        n,
        criterion,
        transform,
        scr=scr_value,
        region=clutter_region,
        hot_spot=hot_spot,
        moving=moving,
        snr=snr,
        noise_model=noise_model,
        **options,
    )
    xp, (det, rec, ide, contrast) = _arrays.arrays(
        acq.detection, acq.recognition, acq.identification, contrast
    )
    if quantisation_step is not None:
        step = _arrays.as_float(quantisation_step, xp)
        _arrays.require_nonnegative("quantisation_step", step, xp, "W/m²")
        invisible = contrast < step
        det, rec, ide = (xp.where(invisible, 0.0 * p, p) for p in (det, rec, ide))
    scr_out = xp.full_like(contrast, xp.inf) if scr_value is None else scr_value
    arrays = xp.broadcast_arrays(
        n, contrast, _arrays.as_float(scr_out, xp), *_arrays.arrays(tau, snr)[1], det, rec, ide
    )
    names = ("cycles", "contrast", "scr", "transmittance", "snr", *_TASKS)
    return SceneAcquisition(
        **{name: _arrays.result(a) for name, a in zip(names, arrays, strict=True)}
    )


def _emitted(emissivity: Any, temperature: Any, band: Any, name: str) -> Any:
    """ε · M_band(T): the exitance of a grey body at the scene, Eqs. (6.4) and (6.12)."""
    xp, (eps,) = _arrays.arrays(emissivity)
    _arrays.require_unit_interval(f"{name}_emissivity", eps, xp)
    return eps * radiometry.band_exitance(temperature, band)
