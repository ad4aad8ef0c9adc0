"""SWIR imagers: reflected plus emitted radiation in a band within 0.9–2.5 µm.

A short-wave infrared camera sees, like a TV camera, sunlight and skylight reflected by the scene
(§6.2, ``M = r · E``) and, like a thermal imager, the scene's own emission (Eqs. (6.4), (6.12),
``ε · M_band(T)``); in the short-wave IR the second is small for a scene at ambient temperature
and large for a hot one (an exhaust, a fire). Sonesson (2004) treats the two cases apart (§6.2:
the visible band's signal is reflection; ch. 6: the infrared's is emission); a SWIR imager adds
them. The signal of a target or a background is

    ``S = r · E + (1 − r) · M_band(T)``,

with ``E`` the scenario's irradiance **in the sensor's band** [W/m²] and the emissivity of an
opaque surface from its reflectance, ``ε = 1 − r`` (Eq. (6.5) with Kirchhoff's law,
:func:`targetacq.physics.radiometry.emissivity_from_reflectance`): one reflectance says both how
much of the sunlight a surface returns and how much it emits in the same band. A scenario's
``emissivity`` or ``material`` is that of the thermal band (Table 6.1 has no short-wave column) and
does not enter a SWIR signal.

The sensor's noise is a noise-equivalent contrast ``nec`` relative to the background's signal,
as for a TV camera (:func:`targetacq.sensors.tv.noise_equivalent`). The path is the project's
atmosphere model in the sensor's band: an ``extinction``, or an ``obscurant`` read from Table 7.1
between its visible and mid-wave cells (:func:`targetacq.physics.atmosphere.obscurant_extinction`);
a ``visibility`` gives the visible band's extinction and is refused, as for a thermal imager.
Clutter: a Table 3.5 region, an SCR or an image, as for a TV camera.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from targetacq.base.arrays import Array
from targetacq.physics import radiometry
from targetacq.sensors.imaging import reflective_requirements
from targetacq.sensors.signature import Signature

SWIR_BAND: tuple[float, float] = (0.9e-6, 2.5e-6)
"""The short-wave IR band [m]: a SWIR sensor's band lies within it (and is it when not given)."""


def exitance(reflectance: Array, irradiance: Array, temperature: Array, band: Any) -> Any:
    """Signal of an opaque surface in a SWIR band: reflected plus emitted [W/m²].

    ``S = r · E + (1 − r) · M_band(T)``: the reflected exitance of §6.2
    (:func:`targetacq.physics.radiometry.reflected_exitance`) plus the grey-body band exitance of
    Eqs. (6.4), (6.12) (:func:`targetacq.physics.radiometry.grey_body_exitance`) with the emissivity
    of an opaque body, ``ε = 1 − r`` (Eq. (6.5), Kirchhoff; Sonesson 2004 §6.1).

    Parameters
    ----------
    reflectance : array_like
        r in [0, 1], in the band.
    irradiance : array_like
        E on the surface in the band [W/m²], >= 0.
    temperature : array_like
        T [K], >= 0.
    band : str or (float, float)
        Band limits [m].

    Returns
    -------
    array_like
        [W/m²].

    Examples
    --------
    Olive paint (r = 0.1) under 300 W/m² of in-band sunlight: at 300 K the emission adds little
    (≈ 0.0025 W/m²); at 700 K (an exhaust) it outshines the reflection (≈ 413 W/m²).

    >>> from targetacq.sensors.swir import exitance
    >>> print(f"{exitance(0.1, 300.0, 300.0, (0.9e-6, 2.5e-6)):.2f}")
    30.00
    >>> print(f"{exitance(0.1, 300.0, 700.0, (0.9e-6, 2.5e-6)):.0f}")
    443
    """
    emissivity = radiometry.emissivity_from_reflectance(reflectance)
    reflected = radiometry.reflected_exitance(reflectance, irradiance)
    return reflected + radiometry.grey_body_exitance(emissivity, temperature, band)


def signature(sensor: Any, background: Any, targets: Sequence[Any]) -> Any:
    """Reflected plus emitted signals of the targets and the background for one sensor."""
    band = sensor.limits
    irradiance = background.irradiance
    m_b = float(exitance(background.reflectance, irradiance, background.temperature, band))
    reflectance = np.array([t.reflectance for t in targets], dtype=float)
    temperatures = np.array([t.temperature for t in targets], dtype=float)
    m_t = np.asarray(exitance(reflectance, irradiance, temperatures, band))
    return Signature(m_t, m_b, None)


def requirements(scenario: Any) -> list[str]:
    """What a scenario lacks for SWIR sensors, each problem located (``table.key: what``)."""
    problems = reflective_requirements(scenario, "SWIR", "a SWIR sensor", emitting=True)
    if scenario.atmosphere.visibility is not None and scenario.atmosphere.named_path() is None:
        problems.append(
            "atmosphere.visibility: gives the visible-band extinction; with SWIR sensors give "
            "extinction or obscurant, or a named atmosphere (model, aerosol)"
        )
    return problems
