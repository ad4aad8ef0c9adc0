"""Typed records of arrays: what the core computes from.

Every quantity is an SI float array; names carry no unit suffixes. The records are frozen
dataclasses. Their array fields are the *data* of a JAX pytree and their other fields (names,
flags, model choices) the static *metadata*, so a compiled scene can be passed through
``jax.jit``, ``vmap`` and ``grad`` (:func:`register_pytrees`; JAX is never imported unless it is
used). Nothing here holds physics: :mod:`targetacq.core.compile` fills the records from a
scenario and :mod:`targetacq.core.evaluate` computes from them.

Shapes: ``n_s`` sensors, ``n_g`` targets, ``n_seg`` path segments, ``n_c`` local clouds.
"""

from __future__ import annotations

import dataclasses
import sys
from dataclasses import dataclass, field
from typing import Any

__all__ = [
    "ModelChoices",
    "PathArrays",
    "SceneArrays",
    "SensorArrays",
    "SignatureArrays",
    "TargetArrays",
    "register_pytrees",
]


def _static(default: Any = dataclasses.MISSING) -> Any:
    if default is dataclasses.MISSING:
        return field(metadata={"static": True})
    return field(default=default, metadata={"static": True})


@dataclass(frozen=True)
class SensorArrays:
    """The sensors.

    Attributes
    ----------
    cycle : array (n_s,)
        Angle of one resolvable cycle [rad] (the resolution model of the sensor's type).
    ifov : array (n_s,)
        Pixel IFOV [rad] (the footprint on terrain clutter).
    half_tangents : array (n_s, 2)
        tan(FOV_h / 2), tan(FOV_v / 2); NaN where the sensor has no field of view.
    look_at : array (n_s, 3)
        A point the sensor is pointed at [m]; NaN where it is pointed by angles or not at all.
    pointing : array (n_s, 2)
        Azimuth (from north, clockwise) and depression (below the horizon) [rad]; NaN where
        not pointed by angles.
    extinction : array (n_s,)
        Extinction of the path in the sensor's band outside the segments [Np/m].
    segment_extinction : array (n_s, n_seg)
        Extinction of each segment in the sensor's band [Np/m].
    names : tuple of str
    types : tuple of str
        Sensor types (:data:`targetacq.sensors.SENSOR_TYPES`).
    pointed : tuple of bool
        Whether the scenario points each sensor (look_at or angles); unpointed sensors see every
        target.
    """

    cycle: Any
    ifov: Any
    half_tangents: Any
    look_at: Any
    pointing: Any
    extinction: Any
    segment_extinction: Any
    names: tuple[str, ...] = _static()
    types: tuple[str, ...] = _static()
    pointed: tuple[bool, ...] = _static()


@dataclass(frozen=True)
class TargetArrays:
    """The targets.

    Attributes
    ----------
    dimensions : array (n_g, 3)
        Box length, width, height [m].
    visible_fraction : array (n_g,)
        Fraction of the height in view, in (0, 1].
    heading : array (n_g,)
        Direction of the long axis where no heading is given per step [rad].
    n50 : array (n_g, 3)
        Cycles for P = 0.5 of detection, recognition, identification.
    names : tuple of str
    hot_spot, moving : tuple of bool
    """

    dimensions: Any
    visible_fraction: Any
    heading: Any
    n50: Any
    names: tuple[str, ...] = _static()
    hot_spot: tuple[bool, ...] = _static()
    moving: tuple[bool, ...] = _static()


@dataclass(frozen=True)
class PathArrays:
    """The path between sensors and targets, besides each band's base extinction.

    Attributes
    ----------
    segment_length : array (n_seg,)
        Lengths of the segments laid from each sensor outward [m].
    cloud_center : array (n_c, 3)
        [m].
    cloud_radius : array (n_c,)
        [m].
    cloud_extinction : array (n_c,)
        [Np/m].
    attenuates : bool
        Whether the path has an atmosphere at all (no atmosphere: no path noise).
    """

    segment_length: Any
    cloud_center: Any
    cloud_radius: Any
    cloud_extinction: Any
    attenuates: bool = _static(False)


@dataclass(frozen=True)
class SignatureArrays:
    """What each sensor sees of each target, independent of where they are.

    Attributes
    ----------
    contrast : array (n_s, n_g)
        |target − background| signal at the scene [W/m²].
    target : array (n_s, n_g)
        Target signal [W/m²].
    scr : array (n_s, n_g) or None
        Signal-to-clutter ratio where the clutter does not depend on the positions; None where
        the scenario gives no clutter measure (or a terrain map, evaluated per position).
    """

    contrast: Any
    target: Any
    scr: Any = None


@dataclass(frozen=True)
class ModelChoices:
    """The model's named choices (static: they select code, not numbers).

    Attributes
    ----------
    transform : str
        :data:`targetacq.transforms.TRANSFORMS`.
    options : tuple of (str, object)
        The transform's options.
    noise_model : str
        :data:`targetacq.noise.NOISE_MODELS`.
    region : str or None
        A Table 3.5 clutter region for every pair.
    search_time : float
        t_s of the search model [s].
    """

    transform: str = "ttpf"
    options: tuple[tuple[str, Any], ...] = ()
    noise_model: str = "variance-sum"
    region: str | None = None
    search_time: float = 3.4


@dataclass(frozen=True)
class SceneArrays:
    """Everything the core needs besides positions, pointing and headings."""

    sensors: SensorArrays
    targets: TargetArrays
    path: PathArrays
    signature: SignatureArrays
    choices: ModelChoices = field(default_factory=ModelChoices, metadata={"static": True})

    @property
    def shape(self) -> tuple[int, int]:
        """(n_sensors, n_targets)."""
        return len(self.sensors.names), len(self.targets.names)


_RECORDS = (SensorArrays, TargetArrays, PathArrays, SignatureArrays, SceneArrays)
_REGISTERED: set[type] = set()  # records already known to JAX (registration is once per process)


def register_pytrees() -> None:
    """Register the records as JAX pytrees (idempotent; imports JAX)."""
    import jax

    for record in _RECORDS:
        if record in _REGISTERED:
            continue
        fields = dataclasses.fields(record)
        data = [f.name for f in fields if not f.metadata.get("static")]
        meta = [f.name for f in fields if f.metadata.get("static")]
        jax.tree_util.register_dataclass(record, data_fields=data, meta_fields=meta)
        _REGISTERED.add(record)


if "jax" in sys.modules:  # JAX already in use: the records work under jit at once
    register_pytrees()
