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
``swir``
    Reflected plus emitted radiation in a band within 0.9–2.5 µm
    (:mod:`targetacq.sensors.swir`).
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

from targetacq.base.registry import lookup
from targetacq.physics.bands import BANDS, parse_band
from targetacq.sensors import colour, imaging, laser_radar, radar, swir, thermal, tv
from targetacq.sensors.signature import Signature

__all__ = [
    "NOISE_KEYS",
    "SENSOR_TYPES",
    "SensorType",
    "Signature",
    "check_sensor_band",
    "check_sensor_noise",
    "check_sensor_tables",
    "get_sensor_type",
    "sensor_band",
]

NOISE_KEYS: Mapping[str, str] = MappingProxyType(
    {"netd": "noise-equivalent temperature difference", "nec": "noise-equivalent contrast"}
)
"""The scenario keys that give an imaging sensor's own noise → what each one is. A sensor type
names the one it takes (:attr:`SensorType.noise_key`); the others are refused for it."""


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
        to the sensor's own noise (0: none given), :mod:`targetacq.physics.detector_noise`.
    path_contrast : callable
        ``path_contrast(sensor, signature) -> float`` [W/m²]: ``σ_path`` of the ``contrast`` SNR
        law (:func:`targetacq.physics.detector_noise.contrast_snr`), the reference target's
        contrast (a thermal sensor: 1 K through ``∂M/∂T``; a reflective one: the background's
        exitance).
    source : str
    kind : str
        How the core computes the type's pairs: "imaging" (the thesis's imaging model),
        "radar" or "laser_radar" (:mod:`targetacq.core.active`).
    rows : callable
        ``rows(sensor) -> list``: the rows of the array core a scenario sensor becomes (itself;
        a colour camera: one per band).
    band_required : bool
        Whether a scenario must give the sensor's ``band`` (a thermal imager: its band is what
        it is); otherwise ``default_band`` stands in.
    default_band : (float, float)
        (λ1, λ2) [m] of a sensor of this type that gives no ``band``.
    band_within : (float, float) or None
        (λ1, λ2) [m] that a given ``band`` must lie within; None: any band.
    band_example : str
        How a band is written, for the message when one is missing.
    noise_key : str or None
        The scenario key of the sensor's own noise, one of :data:`NOISE_KEYS`; None: the type's
        noise is given elsewhere (``noise_elsewhere`` says where) or it has none.
    noise_elsewhere : str
        The message for a sensor of a type without a ``noise_key`` that gives one.
    table : str or None
        The scenario key of the table that belongs to this type only (``bands`` of a colour
        camera, ``radar``, ``laser``): required for it, refused for every other type.
    airlight : bool
        Whether the path's airlight reduces the contrast the type's own noise sees, by the
        background's sky-to-ground ratio (the visible band's reflected light,
        :func:`targetacq.physics.atmosphere.contrast_transmittance`); False: ``τ`` of it.
    """

    name: str
    description: str
    signature: Callable[[Any, Any, Sequence[Any]], Signature]
    requirements: Callable[[Any], list[str]]
    class_signature: Callable[[Any, Any, Sequence[Any]], tuple[Any, Any]] | None
    cycle_angle: Callable[[Any], float] = imaging.cycle_angle
    noise_equivalent: Callable[[Any, Signature], float] = imaging.no_noise
    path_contrast: Callable[[Any, Signature], float] = imaging.unit_path_contrast
    source: str = ""
    kind: str = "imaging"
    rows: Callable[[Any], list[Any]] = imaging.one_row
    band_required: bool = False
    default_band: tuple[float, float] = BANDS["visible"]
    band_within: tuple[float, float] | None = None
    band_example: str = "'lwir' or '8-12 um'"
    noise_key: str | None = None
    noise_elsewhere: str = ""
    table: str | None = None
    airlight: bool = False


SENSOR_TYPES: Mapping[str, SensorType] = MappingProxyType(
    {
        "thermal": SensorType(
            "thermal",
            "thermal imager: emitted radiation in an infrared band",
            thermal.signature,
            thermal.requirements,
            thermal.class_signature,
            noise_equivalent=thermal.noise_equivalent,
            path_contrast=thermal.path_contrast,
            source="Sonesson (2004) ch. 5-6",
            band_required=True,
            noise_key="netd",
        ),
        "tv": SensorType(
            "tv",
            "TV camera: reflected light in the visible band",
            tv.signature,
            tv.requirements,
            None,
            noise_equivalent=tv.noise_equivalent,
            path_contrast=tv.path_contrast,
            source="Sonesson (2004) §6.2, §9.4.1",
            noise_key="nec",
            airlight=True,
        ),
        "colour": SensorType(
            "colour",
            "colour camera: a TV camera per colour band, merged as correlated",
            colour.signature,
            colour.requirements,
            None,
            noise_equivalent=colour.noise_equivalent,
            path_contrast=tv.path_contrast,
            source="Sonesson (2004) §9.4.2; the merge is the project's (comonotone bands)",
            rows=colour.rows,
            noise_key="nec",
            table="bands",
            airlight=True,
        ),
        "swir": SensorType(
            "swir",
            "SWIR imager: reflected plus emitted radiation in a band within 0.9-2.5 um",
            swir.signature,
            swir.requirements,
            None,
            noise_equivalent=tv.noise_equivalent,
            path_contrast=tv.path_contrast,
            source="Sonesson (2004) §6.1-6.2, Eqs. (6.4), (6.5), (6.12); the sum is the project's",
            default_band=swir.SWIR_BAND,
            band_within=swir.SWIR_BAND,
            band_example="'1-1.7 um'",
            noise_key="nec",
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
            noise_elsewhere="a radar's noise is its receiver: radar.noise_figure",
            table="radar",
        ),
        "laser_radar": SensorType(
            "laser_radar",
            "laser radar: detector spacing, 3-D clutter, two-way path and receiver noise",
            laser_radar.signature,
            laser_radar.requirements,
            None,
            source="Sonesson (2004) §9.4.4; the clutter and noise laws are the project's",
            kind="laser_radar",
            noise_elsewhere="a laser radar's noise is its receiver's: laser.nep",
            table="laser",
        ),
    }
)
"""Sensor types by name (read-only)."""


def get_sensor_type(name: str | SensorType) -> SensorType:
    """Resolve a sensor type by name; ``ValueError`` with "did you mean" if unknown."""
    if isinstance(name, SensorType):
        return name
    return lookup(SENSOR_TYPES, name, "sensor type")


def _um(limits: tuple[float, float]) -> str:
    return f"{limits[0] * 1e6:g}-{limits[1] * 1e6:g} um"


def sensor_band(sensor: Any) -> tuple[float, float]:
    """(λ1, λ2) [m] of a scenario sensor: its ``band``, or its type's ``default_band``.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> [round(x * 1e6, 6) for x in sensor_band(SimpleNamespace(type="swir", band=None))]
    [0.9, 2.5]
    """
    if sensor.band is None:
        return get_sensor_type(sensor.type).default_band
    return parse_band(sensor.band)


def check_sensor_tables(sensor: Any) -> None:
    """Refuse a table that belongs to another sensor type (``bands``, ``radar``, ``laser``:
    :attr:`SensorType.table`), and the type's own table missing.

    Raises
    ------
    ValueError
        Naming the key and the type it belongs to.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> check_sensor_tables(SimpleNamespace(type="tv", bands=["red"], radar=None, laser=None))
    Traceback (most recent call last):
    ValueError: bands belongs to a type = "colour" sensor
    """
    kind = get_sensor_type(sensor.type)
    for other in SENSOR_TYPES.values():
        key = other.table
        if key is None:
            continue
        given = getattr(sensor, key) is not None
        if given and kind is not other:
            raise ValueError(f'{key} belongs to a type = "{other.name}" sensor')
        if not given and kind is other:
            raise ValueError(f'a type = "{other.name}" sensor needs its {key}')


def check_sensor_band(sensor: Any) -> None:
    """Refuse an imaging sensor's band that its type does not take: missing where the type
    requires one (:attr:`SensorType.band_required`), not a band, or outside
    :attr:`SensorType.band_within`.

    Raises
    ------
    ValueError
        Naming ``band`` and, where the type limits it, the range it must lie within.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> check_sensor_band(SimpleNamespace(type="swir", band="3-5 um"))
    Traceback (most recent call last):
    ValueError: band of a swir sensor must lie within 0.9-2.5 um; got 3-5 um
    """
    kind = get_sensor_type(sensor.type)
    if sensor.band is None and kind.band_required:
        raise ValueError(f"a {kind.name} sensor needs its band, e.g. {kind.band_example}")
    limits = sensor_band(sensor)  # validates a given band
    within = kind.band_within
    if within is not None and not within[0] <= limits[0] < limits[1] <= within[1]:
        raise ValueError(
            f"band of a {kind.name} sensor must lie within {_um(within)}; got {_um(limits)}"
        )


def check_sensor_noise(sensor: Any) -> None:
    """Refuse a noise key (:data:`NOISE_KEYS`) that is not the sensor type's own
    (:attr:`SensorType.noise_key`).

    Raises
    ------
    ValueError
        Naming the key, the types it belongs to and the key this type takes.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> check_sensor_noise(SimpleNamespace(type="thermal", netd=None, nec=0.01))
    ... # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ValueError: nec is the noise-equivalent contrast of a type = ... a thermal sensor takes netd
    """
    kind = get_sensor_type(sensor.type)
    for key, meaning in NOISE_KEYS.items():
        if getattr(sensor, key) is None or key == kind.noise_key:
            continue
        if kind.noise_key is None:
            raise ValueError(kind.noise_elsewhere or f"a {kind.name} sensor takes no {key}")
        names = [f'"{t.name}"' for t in SENSOR_TYPES.values() if t.noise_key == key]
        owners = " or ".join([", ".join(names[:-1]), names[-1]] if len(names) > 1 else names)
        raise ValueError(
            f"{key} is the {meaning} of a type = {owners} sensor; a {kind.name} sensor takes "
            f"{kind.noise_key}"
        )
