"""Sensor types: a small protocol and the registry :data:`SENSOR_TYPES`.

A sensor type says how a sensor of its kind turns a scene into the three factors of the model
(Sonesson 2004 §9.3): the **resolution** (the angle of one resolvable cycle, hence the cycles on
target), the **signature** (target and background signals in the sensor's band, their contrast
and the clutter, hence the SCR) and the **path** (the noise the atmosphere adds, hence the SNR),
and what it needs from a scenario. The scenario's ``type`` choices, its checks and the
compilation into the array core all come from this registry, so a new sensor type is one module
and one entry here.

``thermal``
    Emitted radiation in an infrared band (:mod:`targetacq.sensors.thermal`).
``tv``
    Reflected light in the visible band (:mod:`targetacq.sensors.tv`).
``colour``
    A TV camera per colour band, merged as correlated (:mod:`targetacq.sensors.colour`).
``radar``
    A pulse radar: cells on target, σ⁰ clutter, the radar equation
    (:mod:`targetacq.sensors.radar`).
``laser_radar``
    A laser radar: detector spacing, 3-D clutter, two-way path and receiver noise
    (:mod:`targetacq.sensors.laser_radar`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

from targetacq.registry import lookup
from targetacq.sensors import colour, imaging, laser_radar, radar, thermal, tv
from targetacq.sensors.signature import Signature

__all__ = ["SENSOR_TYPES", "SensorType", "Signature", "get_sensor_type"]


@dataclass(frozen=True)
class SensorType:
    """A kind of sensor in the registry.

    Attributes
    ----------
    name : str
    description : str
    signature : callable
        ``signature(sensor, background, targets) -> Signature`` from the scenario's records.
    requirements : callable
        ``requirements(scenario) -> list of str``: what the scenario lacks for sensors of this
        type (empty when nothing), each problem located as ``table[index].key: what``.
    class_signature : callable or None
        ``class_signature(sensor, background, classes) -> (mean, variance)`` of terrain classes
        [W/m²], [W²/m⁴]; None where the type cannot use a terrain map.
    cycle_angle : callable
        ``cycle_angle(sensor) -> float`` [rad]: the resolution model.
    noise_equivalent : callable
        ``noise_equivalent(sensor, signature) -> float`` [W/m²]: the signal difference equal
        to the sensor's own noise (0: none given), :mod:`targetacq.sensor_noise`.
    source : str
    kind : str
        How the core computes the type's pairs: "imaging" (the thesis's imaging model),
        "radar" or "laser_radar" (:mod:`targetacq.core.active`).
    rows : callable
        ``rows(sensor) -> list``: the rows of the array core a scenario sensor becomes (itself;
        a colour camera: one per band).
    """

    name: str
    description: str
    signature: Callable[[Any, Any, Sequence[Any]], Signature]
    requirements: Callable[[Any], list[str]]
    class_signature: Callable[[Any, Any, Sequence[Any]], tuple[Any, Any]] | None
    cycle_angle: Callable[[Any], float] = imaging.cycle_angle
    noise_equivalent: Callable[[Any, Signature], float] = imaging.no_noise
    source: str = ""
    kind: str = "imaging"
    rows: Callable[[Any], list[Any]] = imaging.one_row


SENSOR_TYPES: Mapping[str, SensorType] = MappingProxyType(
    {
        "thermal": SensorType(
            "thermal",
            "thermal imager: emitted radiation in an infrared band",
            thermal.signature,
            thermal.requirements,
            thermal.class_signature,
            noise_equivalent=thermal.noise_equivalent,
            source="Sonesson (2004) ch. 5-6",
        ),
        "tv": SensorType(
            "tv",
            "TV camera: reflected light in the visible band",
            tv.signature,
            tv.requirements,
            None,
            noise_equivalent=tv.noise_equivalent,
            source="Sonesson (2004) §6.2, §9.4.1",
        ),
        "colour": SensorType(
            "colour",
            "colour camera: a TV camera per colour band, merged as correlated",
            colour.signature,
            colour.requirements,
            None,
            noise_equivalent=colour.noise_equivalent,
            source="Sonesson (2004) §9.4.2; the merge is the project's (comonotone bands)",
            rows=colour.rows,
        ),
        "radar": SensorType(
            "radar",
            "pulse radar: resolution cells, sigma0 clutter, the radar equation",
            radar.signature,
            radar.requirements,
            None,
            cycle_angle=radar.cycle_angle,
            source="Sonesson (2004) §9.4.3, Eqs. (9.1)-(9.2); Albersheim (1981)",
            kind="radar",
        ),
        "laser_radar": SensorType(
            "laser_radar",
            "laser radar: detector spacing, 3-D clutter, two-way path and receiver noise",
            laser_radar.signature,
            laser_radar.requirements,
            None,
            source="Sonesson (2004) §9.4.4; the clutter and noise laws are the project's",
            kind="laser_radar",
        ),
    }
)
"""Sensor types by name (read-only)."""


def get_sensor_type(name: str | SensorType) -> SensorType:
    """Resolve a sensor type by name; ``ValueError`` with "did you mean" if unknown."""
    if isinstance(name, SensorType):
        return name
    return lookup(SENSOR_TYPES, name, "sensor type")
