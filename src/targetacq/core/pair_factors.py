"""The factors of imaging sensor-target pairs once their geometry and path are known.

One function, :func:`imager_factors`, turns a pair's slant range, the critical dimension it
shows, the angle of one resolvable cycle of its sensor and the optical depth of its path into
the model's three factors: cycles on target, transmittance and SNR. The array core calls it for
every pair of a scene after the geometry (:func:`targetacq.core.evaluation.factors`, the
reference path that JAX runs too), and a range case calls it for its ranges along a line
(:func:`targetacq.core.cases.case_factors`): so the two see the same formulas, and a change to
the chain here reaches both. The NumPy block path and the numba engine keep fused twins of the
same arithmetic for speed; the tests hold them to this one.

1. resolution: ``N = d / (R · cycle)`` (§3.5 and Fig. 3.3 in Sonesson (2004): one cycle is two
   pixel rows, or the optics limit of Eqs. (5.2), (5.3) where coarser);
2. path: ``τ = exp(−d_opt)`` (Eq. (7.3), the optical depth summed over segments, clouds and
   foliage) and the SNR of Eq. (7.7) from the depth directly
   (:func:`targetacq.physics.atmosphere.snr_from_optical_depth`);
3. the sensor's own noise, where it has one (NEC > 0), by the SNR law
   (:data:`targetacq.acquisition.path_noise.SNR_LAWS`): ``contrast`` (default), the contrast the
   path leaves, ``τ · |C|``, against the sensor's noise-equivalent contrast over the gain of the
   pixels the target covers and the path radiance's noise ``(1 − τ) · σ_path``, in variance
   (:func:`targetacq.physics.detector_noise.contrast_snr`); ``sonesson``, the sensor's
   ``τ|C|g/NEC`` (:func:`targetacq.physics.detector_noise.sensor_snr`) added to Eq. (7.7) in
   variance (:func:`targetacq.physics.detector_noise.combined_snr`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from targetacq.acquisition.path_noise import get_snr_law
from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.physics import atmosphere, detector_noise

__all__ = ["SensorNoise", "imager_factors"]

_SHORTEST = 1e-9  # [m]: a pair at range 0 has a finite (huge) N and pixel count, not inf


@dataclass(frozen=True)
class SensorNoise:
    """What a sensor's own noise needs of a pair (arrays broadcasting with its ranges).

    Attributes
    ----------
    contrast : array_like
        The target's contrast at the scene, in the unit of ``noise_equivalent`` (a thermal
        sensor: ΔT [K] or the exitance contrast [W/m²]).
    noise_equivalent : array_like
        The sensor's noise-equivalent contrast, >= 0 (NETD, NEC).
    ifov : array_like
        The pixel IFOV [rad], > 0.
    area : array_like
        The area of the target's outline as seen [m²].
    sky_to_ground : array_like, optional
        A reflective band's sky-to-ground ratio K [1], >= 0: the path's airlight then leaves
        ``τ / (τ + (1 − τ) K)`` of a relative contrast
        (:func:`targetacq.physics.atmosphere.contrast_transmittance`) instead of ``τ``; None for
        ``τ`` (K = 1, and the thermal bands, whose path radiance adds equally to target and
        background).
    path_contrast : array_like
        ``σ_path`` of the ``contrast`` law, > 0, in the unit of ``contrast``: the contrast of the
        thesis's reference target (1 K for a ΔT in kelvin; a thermal sensor in W/m²: 1 K times
        ``∂M_bb,band/∂T``; a reflective sensor: the background's exitance).
    law : str
        The SNR law, :data:`targetacq.acquisition.path_noise.SNR_LAWS` (default ``contrast``).
    """

    contrast: Array
    noise_equivalent: Array
    ifov: Array
    area: Array
    sky_to_ground: Array | None = None
    path_contrast: Array = 1.0
    law: str = "contrast"


def imager_factors(
    range: Array,
    critical_dimension: Array,
    cycle: Array,
    optical_depth: Array,
    noise: SensorNoise | None = None,
) -> tuple[Array, Array, Array]:
    """Cycles on target, transmittance and SNR of imaging pairs.

    ``N = d / (max(R, 1 nm) · cycle)``, ``τ = exp(−d_opt)``, the SNR of Eq. (7.7) from the
    optical depth; with the sensor's noise, the SNR of its law (see the module's notes). Inputs
    are not checked here: the callers check their records once.

    Parameters
    ----------
    range : array_like
        Slant range R [m], >= 0.
    critical_dimension : array_like
        The critical dimension the target shows [m].
    cycle : array_like
        The angle of one resolvable cycle of the sensor [rad], > 0.
    optical_depth : array_like
        The path's optical depth [1], >= 0 (+inf: nothing gets through).
    noise : SensorNoise, optional
        The sensor's own noise; None for none (the SNR is then the path's, Eq. (7.7)).

    Returns
    -------
    cycles, transmittance, snr : array_like
        N [cycles], τ [1] and the SNR [dB], broadcast together.

    Examples
    --------
    A 2.3 m target at 1,150 m, one cycle of 0.4 mrad, through 1.15 Np of path: N = 5 cycles,
    τ = e^−1.15 and ``−20 log10(e^1.15 − 1)`` dB.

    >>> n, tau, snr = imager_factors(1150.0, 2.3, 4e-4, 1.15)
    >>> round(float(n), 12), round(float(tau), 6), round(float(snr), 3)
    (5.0, 0.316637, -6.682)

    With a 0.5 K target and a 50 mK NETD (default ``contrast`` law), the SNR is
    ``τ · 0.5 / sqrt((0.05/g)² + (1 − τ)²)``, g = 10 for the 100 pixels of a 2.3 m square at
    a 0.2 mrad IFOV:

    >>> noise = SensorNoise(0.5, 0.05, 2e-4, 2.3**2)
    >>> round(float(imager_factors(1150.0, 2.3, 4e-4, 1.15, noise)[2]), 3)
    -12.703
    """
    xp, (r, depth) = _arrays.arrays(range, optical_depth)
    shortest = xp.maximum(r, _SHORTEST)
    with np.errstate(divide="ignore"):
        cycles = critical_dimension / (shortest * cycle)
    tau = xp.exp(-depth)
    snr = atmosphere.snr_from_optical_depth(depth)
    if noise is not None:
        pixels = detector_noise.pixels_on_target(noise.area, shortest, noise.ifov)
        seen = tau  # the contrast the path leaves: τ, or with airlight Duntley's law (§7.2)
        if noise.sky_to_ground is not None:
            seen = atmosphere.contrast_transmittance(tau, noise.sky_to_ground)
        if get_snr_law(noise.law).contrast_aware:
            aware = detector_noise.contrast_snr(
                noise.contrast, noise.noise_equivalent, noise.path_contrast, seen, pixels
            )
            # A row without a noise of its own (NEC = 0, none given) keeps Eq. (7.7).
            quiet = _arrays.as_float(noise.noise_equivalent, xp) == 0
            snr = xp.where(quiet, snr, aware)
        else:
            own = detector_noise.sensor_snr(noise.contrast, noise.noise_equivalent, seen, pixels)
            snr = detector_noise.combined_snr(snr, own)
    return cycles, tau, snr
