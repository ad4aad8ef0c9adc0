"""Thermal imagers: emitted radiation in an infrared band (Sonesson 2004 ch. 5-6).

Signature: grey-body band exitances ``ε · M_band(T)`` of target and background (6.4), (6.12),
plus ``(1 − ε)`` of the sky's where the background gives a ``sky_temperature`` (§6.3);
clutter from the background's temperature spread, ``ε · dM/dT · σ_T``
(:func:`targetacq.physics.clutter.temperature_spread_clutter`).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from targetacq.physics import clutter, radiometry
from targetacq.sensors import imaging
from targetacq.sensors.signature import Signature


def signature(sensor: Any, background: Any, targets: Sequence[Any]) -> Any:
    """Band exitances of the targets and the background, and the clutter, for one sensor."""
    band = sensor.limits
    eps_b = imaging.emissivity(background, band)
    eps_t = np.array([imaging.emissivity(t, band) for t in targets])
    temperatures = np.array([t.temperature for t in targets], dtype=float)
    sky = getattr(background, "sky_temperature", None)
    if sky is None:
        m_b = float(radiometry.grey_body_exitance(eps_b, background.temperature, band))
        m_t = np.asarray(radiometry.grey_body_exitance(eps_t, temperatures, band))
    else:  # surfaces of ε < 1 reflect the sky (§6.3)
        m_b = float(radiometry.sky_reflected_exitance(eps_b, background.temperature, sky, band))
        m_t = np.asarray(radiometry.sky_reflected_exitance(eps_t, temperatures, sky, band))
    spread = None
    if background.clutter_std is not None:
        spread = float(
            clutter.temperature_spread_clutter(
                eps_b, background.temperature, background.clutter_std, band
            )
        )
    return Signature(m_t, m_b, spread)


def noise_equivalent(sensor: Any, seen: Any) -> float:
    """``NETD · ∂M_bb,band/∂T`` at the NETD's reference temperature [W/m²]; 0 without a NETD
    (:func:`targetacq.physics.detector_noise.netd_exitance`)."""
    from targetacq.physics.detector_noise import netd_exitance

    if sensor.netd is None:
        return 0.0
    return float(netd_exitance(sensor.netd, sensor.limits, sensor.netd_temperature))


def path_contrast(sensor: Any, seen: Any) -> float:
    """``σ_path`` of the ``contrast`` SNR law [W/m²]: the reference target's 1 K as an exitance
    difference, ``1 K · ∂M_bb,band/∂T`` at the NETD's reference temperature (the same slope as
    the NETD's, :func:`targetacq.physics.detector_noise.netd_exitance`)."""
    from targetacq.physics.detector_noise import netd_exitance

    return float(netd_exitance(1.0, sensor.limits, sensor.netd_temperature))


def class_signature(sensor: Any, background: Any, classes: Sequence[Any]) -> tuple[Any, Any]:
    """Mean exitance and exitance variance of each terrain class in the sensor's band (§6.7)."""
    band = sensor.limits
    eps = imaging.emissivity(background, band)
    temperatures = np.array([c.temperature for c in classes])
    spread = np.array([c.temperature_std for c in classes])
    mean = np.asarray(radiometry.grey_body_exitance(eps, temperatures, band))
    sigma = np.asarray(clutter.temperature_spread_clutter(eps, temperatures, spread, band))
    return mean, sigma**2


def requirements(scenario: Any) -> list[str]:
    """What a scenario lacks for thermal sensors, each problem located (``table.key: what``)."""
    problems = []
    if scenario.background.temperature is None:
        problems.append(
            "background.temperature: missing: background.temperature is needed for thermal sensors"
        )
    problems += [
        f"targets[{k}].temperature: thermal sensors need a temperature (or a signature_table) "
        "for every target"
        for k, t in enumerate(scenario.targets)
        if t.temperature is None and t.signature_table is None
    ]
    if scenario.atmosphere.visibility is not None and scenario.atmosphere.named_path() is None:
        problems.append(
            "atmosphere.visibility: gives the visible-band extinction; with thermal sensors give "
            "extinction or obscurant, or a named atmosphere (model, aerosol)"
        )
    return problems
