"""What a sensor sees of the targets and the background: the record every sensor type's
``signature`` returns (:data:`targetacq.sensors.SENSOR_TYPES`).

It lives in its own module, below the sensor-type modules and the registry that collects them,
so that each type module can build one without importing the registry back.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

__all__ = ["Signature"]


@dataclass(frozen=True)
class Signature:
    """What one sensor sees of the targets and the background, in its band.

    Attributes
    ----------
    target : numpy.ndarray
        (n_targets,) target signals [W/m²] at the scene.
    background : float
        Mean background signal [W/m²].
    clutter : float or None
        Spread of the background signal [W/m²], where the scenario gives one.
    """

    target: Any
    background: float
    clutter: float | None
