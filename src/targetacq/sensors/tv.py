"""TV cameras: reflected light in the visible band (Sonesson 2004 §6.2, §9.4.1).

Signature: reflected exitances ``r · E`` of target and background under the scene's
irradiance E (:func:`targetacq.physics.radiometry.reflected_exitance`). Clutter is given as a Table
3.5 region, an SCR or an image; a temperature spread means nothing to a TV camera.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from targetacq.physics import radiometry
from targetacq.sensors.imaging import reflective_requirements
from targetacq.sensors.signature import Signature


def signature(sensor: Any, background: Any, targets: Sequence[Any]) -> Any:
    """Reflected exitances of the targets and the background for one sensor."""
    irradiance = background.irradiance
    m_b = float(radiometry.reflected_exitance(background.reflectance, irradiance))
    reflectance = np.array([t.reflectance for t in targets], dtype=float)
    m_t = np.asarray(radiometry.reflected_exitance(reflectance, irradiance))
    return Signature(m_t, m_b, None)


def noise_equivalent(sensor: Any, seen: Any) -> float:
    """``NEC · M_background`` [W/m²]: the noise-equivalent contrast of the camera relative to
    the background's reflected exitance; 0 without an NEC."""
    if sensor.nec is None:
        return 0.0
    return float(sensor.nec * seen.background)


def path_contrast(sensor: Any, seen: Any) -> float:
    """``σ_path`` of the ``contrast`` SNR law [W/m²]: a contrast ratio of 1 of the background's
    reflected exitance (the reference target of a reflective sensor)."""
    return float(seen.background)


def requirements(scenario: Any) -> list[str]:
    """What a scenario lacks for TV sensors, each problem located (``table.key: what``)."""
    return reflective_requirements(scenario, "TV", "a TV camera")
