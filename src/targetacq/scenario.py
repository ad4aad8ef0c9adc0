"""The declarative scenario: sensors, targets, background, atmosphere, model choices.

A scenario is written in TOML with a unit on every quantity (``"17 um"``, ``"3 km"``,
``"305 K"``) and validated here with pydantic; errors are located ("sensors[0].pitch: ...") and an
unknown key gets a "did you mean". A file is strict: a bare number where a unit is needed is an
error saying which unit to add (:func:`load_scenario`, :func:`parse_scenario`).

Python users build the same objects directly (:class:`Scenario`, :class:`Sensor`, ...), passing
each quantity as a string with its unit, as a pint ``Quantity`` (``17 * ureg.um``; one of
another dimension is an error naming the field) or as a plain number in SI units (``17e-6``).
Inside, every quantity is a bare, finite SI float, so ``Scenario.model_validate(s.model_dump())``
gives ``s`` back. A position is a sequence of three such quantities, or one string
(``"0 0 1.5 km"``).

Positions are map coordinates in metres, x east, y north, z up. A thing either stands at
``position`` or moves along ``waypoints`` (times and positions, linear in between, held before
the first and after the last).
"""

from __future__ import annotations

import itertools
import math
import tomllib
from collections import Counter
from collections.abc import Mapping, Sequence
from difflib import get_close_matches
from pathlib import Path
from typing import Annotated, Any, Literal, get_args, get_origin

from pydantic import (
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    ValidationError,
    ValidationInfo,
    model_validator,
)

from targetacq import atmosphere as _atmosphere
from targetacq.acquisition import ACQUISITION_SEMANTICS, MOTION_RULES
from targetacq.bands import BANDS, parse_band
from targetacq.criteria import CRITERIA
from targetacq.noise import NOISE_MODELS
from targetacq.optics import FIELD_OF_VIEW_PROJECTIONS
from targetacq.radiometry import MATERIALS
from targetacq.registry import lookup, unknown_name
from targetacq.sensors import SENSOR_TYPES, get_sensor_type
from targetacq.transforms import C2NVEO_BOUNDS, TRANSFORMS
from targetacq.units import is_quantity, to_si

__all__ = [
    "Atmosphere",
    "Background",
    "Cloud",
    "ModelChoices",
    "Scenario",
    "ScenarioError",
    "Segment",
    "Sensor",
    "Target",
    "Terrain",
    "TerrainClassSpec",
    "TimeGrid",
    "Waypoint",
    "load_scenario",
    "parse_scenario",
]


class ScenarioError(ValueError):
    """A scenario that cannot be used; the message says where and what is wrong."""


def _strict_units(info: ValidationInfo) -> bool:
    """Whether bare numbers are refused: set by :func:`parse_scenario` for files."""
    return isinstance(info.context, Mapping) and bool(info.context.get("strict_units"))


def _quantity(kind: str) -> Any:
    def parse(value: Any, info: ValidationInfo) -> float:
        return to_si(value, kind, info.field_name or kind, strict=_strict_units(info))

    return BeforeValidator(parse)


Length = Annotated[float, _quantity("length")]
Angle = Annotated[float, _quantity("angle")]
Temperature = Annotated[float, _quantity("temperature")]
TemperatureDifference = Annotated[float, _quantity("temperature difference")]
Extinction = Annotated[float, _quantity("extinction")]
Time = Annotated[float, _quantity("time")]
Irradiance = Annotated[float, _quantity("irradiance")]
Fraction = Annotated[float, Field(ge=0.0, le=1.0)]


def _position(value: Any, info: ValidationInfo) -> tuple[float, float, float]:
    name = info.field_name or "position"
    if isinstance(value, str):
        *numbers, unit = value.replace(",", " ").split() or [""]
        parts: list[Any] = [f"{n} {unit}" for n in numbers]
    elif isinstance(value, Sequence) or (is_quantity(value) and getattr(value, "ndim", 0) == 1):
        parts = list(value)
    elif getattr(value, "ndim", None) == 1 and hasattr(value, "tolist"):  # a NumPy array
        parts = value.tolist()
    else:
        raise ValueError(
            f"{name}: a position is [x, y, z] with units, e.g. ['0 m', '0 m', '1.5 km']"
        )
    if len(parts) != 3:
        raise ValueError(f"{name}: a position needs three coordinates x, y, z; got {len(parts)}")
    strict = _strict_units(info)
    x, y, z = (to_si(part, "length", name, strict=strict) for part in parts)
    return x, y, z


Position = Annotated[tuple[float, float, float], BeforeValidator(_position)]


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


class Waypoint(_Strict):
    """A point of a path: ``time`` [s] and ``position`` [m]."""

    time: Time
    position: Position


def _one_place(position: Any, waypoints: Any, what: str) -> None:
    if (position is None) == (waypoints is None):
        raise ValueError(f"give the {what} either position or waypoints")
    if waypoints is not None:
        times = [w.time for w in waypoints]
        if len(times) < 2 or any(b <= a for a, b in itertools.pairwise(times)):
            raise ValueError("waypoints need at least two, with increasing times")


def _sensor_type(value: Any) -> str:
    """A name of :data:`targetacq.sensors.SENSOR_TYPES` (the registry gives the choices)."""
    if not isinstance(value, str):
        raise ValueError(f"a sensor type is a name: one of {', '.join(SENSOR_TYPES)}")
    return get_sensor_type(value).name


class Sensor(_Strict):
    """An imaging sensor.

    ``type`` "thermal" sees emitted radiation in its ``band``; "tv" sees reflected light
    (visible band, the background's ``irradiance``). ``projection`` says how ``hfov`` over
    ``pixels`` gives the IFOV: "angular" (default, IFOV = hfov / pixels, the datasheet
    convention) or "rectilinear" (a pinhole camera, 2 tan(hfov/2) / pixels). ``f_number`` gives
    the aperture as ``focal_length / f_number``. The sensor's own noise: ``netd`` of a
    thermal sensor (quoted at ``netd_temperature``, 300 K by default), ``nec`` (noise-equivalent
    contrast, relative to the background) of a TV sensor; without them only the atmosphere adds
    noise. The resolution is given one way: ``pitch``
    with ``focal_length``, ``hfov`` with ``pixels``, or ``ifov``. Pointing: ``look_at`` a point,
    or ``azimuth`` (from north, clockwise) and ``depression`` (below the horizon); with neither,
    every target is taken to be in view.
    """

    name: str
    type: Annotated[str, BeforeValidator(_sensor_type)] = "thermal"
    band: str | None = None
    pixels: tuple[Annotated[int, Field(gt=0)], Annotated[int, Field(gt=0)]] | None = None
    pitch: Length | None = None
    focal_length: Length | None = None
    hfov: Angle | None = None
    ifov: Angle | None = None
    aperture: Length | None = None
    position: Position | None = None
    waypoints: list[Waypoint] | None = None
    look_at: Position | None = None
    azimuth: Angle | None = None
    depression: Angle | None = None
    projection: str = "angular"
    f_number: Annotated[float, Field(gt=0.0, allow_inf_nan=False)] | None = None
    netd: TemperatureDifference | None = None
    netd_temperature: Temperature = 300.0
    nec: Annotated[float, Field(ge=0.0, allow_inf_nan=False)] | None = None

    @model_validator(mode="after")
    def _check(self) -> Sensor:
        ways = [
            self.pitch is not None or self.focal_length is not None,
            self.hfov is not None,
            self.ifov is not None,
        ]
        if sum(ways) != 1:
            raise ValueError("give the resolution one way: pitch and focal_length, hfov, or ifov")
        if ways[0] and (self.pitch is None or self.focal_length is None):
            raise ValueError("pitch and focal_length go together")
        for name in ("pitch", "focal_length", "ifov", "aperture"):
            value = getattr(self, name)
            if value is not None and not value > 0:
                raise ValueError(f"{name} must be > 0")
        if self.hfov is not None and not 0 < self.hfov < math.pi:
            raise ValueError("hfov must be in (0, 180) degrees")
        if self.hfov is not None and self.pixels is None:
            raise ValueError("hfov needs pixels = [width, height]")
        lookup(FIELD_OF_VIEW_PROJECTIONS, self.projection, "projection")
        if self.f_number is not None:
            if self.focal_length is None:
                raise ValueError("f_number needs focal_length (aperture = focal_length / f_number)")
            if self.aperture is not None:
                raise ValueError("give aperture or f_number, not both")
            # The aperture diameter a datasheet's F-number stands for: D = f / F#.
            object.__setattr__(self, "aperture", self.focal_length / self.f_number)
        if self.band is None and self.type == "thermal":
            raise ValueError("a thermal sensor needs its band, e.g. 'lwir' or '8-12 um'")
        if self.band is not None:
            self.limits  # noqa: B018 - validates the band
        _one_place(self.position, self.waypoints, "sensor")
        if self.look_at is not None and (self.azimuth is not None or self.depression is not None):
            raise ValueError("give look_at, or azimuth and depression, not both")
        if (self.azimuth is None) != (self.depression is None):
            raise ValueError("azimuth and depression go together")
        if self.pixels is None and (self.look_at is not None or self.azimuth is not None):
            raise ValueError("pointing needs pixels = [width, height] for the field of view")
        if self.netd is not None and not (self.netd >= 0 and math.isfinite(self.netd)):
            raise ValueError("netd must be a finite temperature difference >= 0 K, e.g. '50 mK'")
        if not (self.netd_temperature > 0 and math.isfinite(self.netd_temperature)):
            raise ValueError("netd_temperature must be > 0 K")
        if self.netd is not None and self.type != "thermal":
            raise ValueError("netd is the noise of a thermal sensor; a TV sensor takes nec")
        if self.nec is not None and self.type != "tv":
            raise ValueError("nec is the noise-equivalent contrast of a TV sensor; give netd")
        return self

    @property
    def limits(self) -> tuple[float, float]:
        """The band (λ1, λ2) [m]; the visible band for a TV sensor without one."""
        if self.band is None:
            return BANDS["visible"]
        return parse_band(self.band)

    @property
    def pixel_ifov(self) -> float:
        """IFOV [rad] of the central pixel."""
        from targetacq import optics

        if self.ifov is not None:
            return self.ifov
        if self.hfov is not None and self.pixels is not None:
            return float(optics.ifov_from_field_of_view(self.hfov, self.pixels[0], self.projection))
        assert self.pitch is not None
        assert self.focal_length is not None
        return self.pitch / self.focal_length

    @property
    def field_of_view(self) -> tuple[float, float] | None:
        """(horizontal, vertical) full field of view [rad], if pixels are given."""
        from targetacq import optics

        if self.pixels is None:
            return None
        # A pitch-and-focal-length (or IFOV) sensor is a pinhole camera; an hfov sensor follows
        # its projection.
        projection = self.projection if self.hfov is not None else "rectilinear"
        h, v = (
            float(optics.field_of_view_from_ifov(self.pixel_ifov, n, projection))
            for n in self.pixels
        )
        if h >= math.pi or v >= math.pi:
            raise ValueError("the field of view must be < 180 degrees on both sides")
        return h, v


class Target(_Strict):
    """A target: a box ``dimensions`` = [length, width, height] with its long axis along
    ``heading`` (from north, clockwise; the direction of motion when it moves along waypoints)."""

    name: str
    dimensions: tuple[Length, Length, Length]
    heading: Angle = 0.0
    criterion: str | None = None
    temperature: Temperature | None = None
    emissivity: Fraction | None = None
    material: str | None = None
    reflectance: Fraction | None = None
    position: Position | None = None
    waypoints: list[Waypoint] | None = None
    moving: bool = False
    visible_fraction: Annotated[float, Field(gt=0.0, le=1.0)] = 1.0
    hot_spot: bool = False
    image_box: tuple[int, int, int, int] | None = None

    @model_validator(mode="after")
    def _check(self) -> Target:
        if any(not d > 0 for d in self.dimensions):
            raise ValueError("dimensions must be > 0")
        _one_place(self.position, self.waypoints, "target")
        if self.criterion is not None:
            lookup(CRITERIA, self.criterion, "criterion")
        if self.material is not None and self.material not in MATERIALS:
            raise ValueError(f"material must be one of {', '.join(MATERIALS)}")
        if self.emissivity is not None and self.material is not None:
            raise ValueError("give emissivity or material, not both")
        return self


class TerrainClassSpec(_Strict):
    """A terrain class of a thermal scene: its mean temperature and its temperature spread at a
    stated ground resolution (§6.7)."""

    name: str
    temperature: Temperature
    temperature_std: TemperatureDifference
    resolution: Length

    @model_validator(mode="after")
    def _check(self) -> TerrainClassSpec:
        if not self.temperature_std >= 0:
            raise ValueError("temperature_std must be >= 0")
        if not self.resolution > 0:
            raise ValueError("resolution must be > 0")
        return self


class Terrain(_Strict):
    """A terrain map (Eqs. (6.10)–(6.11)): ``map`` a CSV file of class indices (rows northward
    from ``origin``, columns eastward), ``cell_size`` per map cell, and the ``classes``."""

    map: str
    cell_size: Length
    origin: tuple[Length, Length] = (0.0, 0.0)
    classes: Annotated[list[TerrainClassSpec], Field(min_length=1)]

    @model_validator(mode="after")
    def _check(self) -> Terrain:
        if not self.cell_size > 0:
            raise ValueError("cell_size must be > 0")
        return self


class Background(_Strict):
    """The background: its temperature and emissivity (thermal) or reflectance and the
    irradiance (TV), and the clutter as a Table 3.5 region, an SCR, a temperature spread, an
    image (``image`` with each target's ``image_box``) or a terrain map (thermal sensors)."""

    temperature: Temperature | None = None
    emissivity: Fraction | None = None
    material: str | None = None
    reflectance: Fraction | None = None
    irradiance: Irradiance | None = None
    clutter: Literal["low", "medium", "high"] | None = None
    scr: Annotated[float, Field(ge=0.0)] | None = None
    clutter_std: TemperatureDifference | None = None
    image: str | None = None
    channel: Literal["luminance", "red", "green", "blue"] | None = None
    terrain: Terrain | None = None

    @model_validator(mode="after")
    def _check(self) -> Background:
        ways = (self.clutter, self.scr, self.clutter_std, self.image, self.terrain)
        if sum(v is not None for v in ways) > 1:
            raise ValueError("give one of clutter, scr, clutter_std, image and terrain")
        if self.material is not None and self.material not in MATERIALS:
            raise ValueError(f"material must be one of {', '.join(MATERIALS)}")
        if self.clutter_std is not None and not self.clutter_std >= 0:
            raise ValueError("clutter_std must be >= 0")
        return self


class Segment(_Strict):
    """A stretch of the line of sight, from the sensor outward, with its own extinction."""

    length: Length
    extinction: Extinction | None = None
    obscurant: str | None = None

    @model_validator(mode="after")
    def _check(self) -> Segment:
        if (self.extinction is None) == (self.obscurant is None):
            raise ValueError("give a segment's extinction or obscurant")
        if not self.length >= 0:
            raise ValueError("length must be >= 0")
        _check_obscurant(self.obscurant)
        return self


class Cloud(_Strict):
    """A local obscurant cloud (spray, dust, snow behind a vehicle, §7.5–7.7): a sphere."""

    center: Position
    radius: Length
    extinction: Extinction

    @model_validator(mode="after")
    def _check(self) -> Cloud:
        if not self.radius > 0:
            raise ValueError("radius must be > 0")
        if not self.extinction >= 0:
            raise ValueError("extinction must be >= 0")
        return self


def _check_obscurant(text: str | None) -> None:
    if text is None:
        return
    name, _, level = text.partition(":")
    if name not in _atmosphere.OBSCURANTS:
        raise unknown_name(name, _atmosphere.OBSCURANTS, "obscurant")
    if level and level not in _atmosphere.EXTINCTION_LEVELS:
        raise ValueError(
            f"obscurant level must be one of {', '.join(_atmosphere.EXTINCTION_LEVELS)}"
        )


class Atmosphere(_Strict):
    """The path: one of ``extinction``, ``obscurant`` ("haze" or "haze:high", per sensor band,
    Table 7.1) or ``visibility`` with its ``visibility_convention`` (visible band only);
    ``segments`` near the sensor; local ``clouds``."""

    extinction: Extinction | None = None
    obscurant: str | None = None
    visibility: Length | None = None
    visibility_convention: Literal["koschmieder", "mor"] | None = None
    segments: list[Segment] = []
    clouds: list[Cloud] = []

    @model_validator(mode="after")
    def _check(self) -> Atmosphere:
        if sum(v is not None for v in (self.extinction, self.obscurant, self.visibility)) > 1:
            raise ValueError("give one of extinction, obscurant and visibility")
        if self.extinction is not None and not self.extinction >= 0:
            raise ValueError("extinction must be >= 0")
        if self.visibility is not None:
            if not self.visibility > 0:
                raise ValueError("visibility must be > 0")
            if self.visibility_convention is None:
                raise ValueError("visibility needs visibility_convention = 'koschmieder' or 'mor'")
        _check_obscurant(self.obscurant)
        return self

    @property
    def present(self) -> bool:
        """Whether the path attenuates at all."""
        return any(
            v is not None for v in (self.extinction, self.obscurant, self.visibility)
        ) or bool(self.segments or self.clouds)


class ModelChoices(_Strict):
    """Model choices: criterion (or a user N50 triple), transform, noise model, motion rule
    (how a moving target is detected), semantics (nested or conditional: what the three
    probabilities mean, hence what is reported and sampled), fusion, and the search model's
    time constant ``search_time`` (τ = search_time / P∞, 3.4 s by default)."""

    criterion: str = "johnson"
    n50: (
        tuple[
            Annotated[float, Field(gt=0)],
            Annotated[float, Field(gt=0)],
            Annotated[float, Field(gt=0)],
        ]
        | None
    ) = None
    transform: str = "ttpf"
    bound: str | None = None
    noise_model: str = "variance-sum"
    motion: str = "low-clutter"
    semantics: str = "nested"
    fusion: Literal["sensor-level"] = "sensor-level"
    search_time: Time = 3.4

    @model_validator(mode="after")
    def _check(self) -> ModelChoices:
        lookup(CRITERIA, self.criterion, "criterion")
        lookup(TRANSFORMS, self.transform, "transform")
        lookup(NOISE_MODELS, self.noise_model, "noise model")
        lookup(MOTION_RULES, self.motion, "motion rule")
        lookup(ACQUISITION_SEMANTICS, self.semantics, "semantics")
        if self.bound is not None and self.bound not in C2NVEO_BOUNDS:
            raise ValueError(f"bound must be one of {', '.join(C2NVEO_BOUNDS)}")
        if not self.search_time > 0:
            raise ValueError("search_time must be > 0 s")
        if not CRITERIA[self.criterion].gives_probabilities and self.n50 is None:
            raise ValueError(f"criterion {self.criterion!r} gives no probabilities")
        return self


class TimeGrid(_Strict):
    """Evaluation times: ``start`` to ``stop`` inclusive every ``step``."""

    start: Time = 0.0
    stop: Time = 0.0
    step: Time = 1.0

    @model_validator(mode="after")
    def _check(self) -> TimeGrid:
        if not self.step > 0:
            raise ValueError("step must be > 0 s")
        if self.stop < self.start:
            raise ValueError("stop must not be before start")
        return self

    def times(self) -> Any:
        import numpy as np

        count = math.floor((self.stop - self.start) / self.step + 1e-9) + 1
        return self.start + self.step * np.arange(count)


class Scenario(_Strict):
    """A whole scene. See the module docstring and ``examples/`` for files."""

    name: str = ""
    sensors: Annotated[list[Sensor], Field(min_length=1)]
    targets: Annotated[list[Target], Field(min_length=1)]
    background: Background = Background()
    atmosphere: Atmosphere = Atmosphere()
    model: ModelChoices = ModelChoices()
    time: TimeGrid = TimeGrid()

    @model_validator(mode="after")
    def _check(self) -> Scenario:
        for what, items in (("sensor", self.sensors), ("target", self.targets)):
            counts = Counter(item.name for item in items)
            duplicates = sorted(n for n, count in counts.items() if count > 1)
            if duplicates:
                raise ValueError(f"{what} names must be unique; repeated: {', '.join(duplicates)}")
        for kind in dict.fromkeys(s.type for s in self.sensors):
            problems = get_sensor_type(kind).requirements(self)
            if problems:
                raise ValueError(problems[0])
        if self.background.image is not None:
            missing = [t.name for t in self.targets if t.image_box is None]
            if missing:
                raise ValueError(
                    f"background.image needs an image_box for every target; missing: "
                    f"{', '.join(missing)}"
                )
        return self


def _fields_of(model: Any) -> dict[str, Any]:
    return (
        dict(model.model_fields) if isinstance(model, type) and issubclass(model, BaseModel) else {}
    )


def _model_at(loc: Sequence[Any]) -> Any:
    """The pydantic model class at a location of the scenario, for "did you mean" hints."""
    current: Any = Scenario
    for part in loc:
        if isinstance(part, int):
            continue
        fields = _fields_of(current)
        if part not in fields:
            return current
        annotation = fields[part].annotation
        while get_origin(annotation) is not None:
            args = [a for a in get_args(annotation) if a is not type(None)]
            models = [a for a in args if isinstance(a, type) and issubclass(a, BaseModel)]
            annotation = models[0] if models else (args[0] if args else annotation)
            if models:
                break
        current = annotation
    return current


def _location(loc: Sequence[Any]) -> str:
    text = ""
    for part in loc:
        if isinstance(part, int):
            text += f"[{part}]"
        else:
            text += ("." if text else "") + str(part)
    return text or "scenario"


def _first_error(error: ValidationError) -> str:
    detail = error.errors()[0]
    loc = [p for p in detail["loc"] if not (isinstance(p, str) and p.startswith("function-"))]
    message = detail["msg"].removeprefix("Value error, ")
    field = next((p for p in reversed(loc) if isinstance(p, str)), None)
    if field is not None:  # quantity messages name their field; the location already does
        message = message.removeprefix(f"{field}: ")
    if detail["type"] == "extra_forbidden":
        key = str(loc[-1])
        parent = _model_at(loc[:-1])
        valid = list(_fields_of(parent))
        close = get_close_matches(key, valid, 1)
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        message = f"unknown key {key!r}{hint}; valid keys: {', '.join(valid)}"
    elif detail["type"] == "missing":
        message = "required key missing"
    return f"{_location(loc)}: {message}"


def parse_scenario(data: dict[str, Any], source: str = "scenario") -> Scenario:
    """Validate a scenario given as nested dictionaries (as read from TOML).

    Units are strict, as in a file: every quantity is a string with its unit (or a pint
    ``Quantity``); a bare number where a unit is needed is an error saying which unit to add.
    Build :class:`Scenario` directly (or call ``Scenario.model_validate``) to give SI numbers.

    Raises
    ------
    ScenarioError
        With one located message: ``source: table.key: what is wrong``.
    """
    try:
        return Scenario.model_validate(data, context={"strict_units": True})
    except ValidationError as error:
        raise ScenarioError(f"{source}: {_first_error(error)}") from None


def load_scenario(path: str | Path) -> Scenario:
    """Read and validate a scenario TOML file.

    Raises
    ------
    ScenarioError
        Missing or unreadable file, malformed TOML (with its line and column), or an invalid
        scenario (located message).
    """
    source = Path(path)
    if not source.is_file():
        raise ScenarioError(f"{source}: no such scenario file")
    try:
        data = tomllib.loads(source.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as error:
        raise ScenarioError(f"{source}: malformed TOML: {error}") from None
    except UnicodeDecodeError:
        raise ScenarioError(f"{source}: not a text (UTF-8) file") from None
    scenario = parse_scenario(data, str(source))
    bg = scenario.background
    update: dict[str, Any] = {}
    if bg.image is not None and not Path(bg.image).is_absolute():
        update["image"] = str(source.parent / bg.image)
    if bg.terrain is not None and not Path(bg.terrain.map).is_absolute():
        update["terrain"] = bg.terrain.model_copy(
            update={"map": str(source.parent / bg.terrain.map)}
        )
    if update:
        scenario = scenario.model_copy(update={"background": bg.model_copy(update=update)})
    return scenario
