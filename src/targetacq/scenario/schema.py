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

Domains. Every quantity is finite; temperatures lie in (0, ``limits.MAX_TEMPERATURE``] K,
temperature differences in [0, ``limits.MAX_TEMPERATURE``] K, depressions within
±``limits.MAX_DEPRESSION``, azimuths and headings within ±``limits.MAX_ANGLE_TURN``, lengths
and coordinates within ±``limits.MAX_LENGTH`` (a million kilometres) and pixel counts in [1,
``limits.MAX_ELEMENTS``] (:mod:`targetacq.base.limits`). Flags are ``true`` or ``false``, pixel
counts and boxes whole numbers and plain numbers (fractions, SCR, N50) numbers, never quoted
text. Contradictions are refused: two ways of giving one thing (``emissivity`` and
``material``), a choice that means nothing with the rest (``bound`` without the c2nveo
transform, ``channel`` without an ``image``, ``projection`` without ``hfov``), or that the model
cannot run (a threshold-only criterion, a detection-only transform, a sensor that looks at
itself).

Daily cycle. A target's, the background's or a terrain class's ``temperature`` may be a daily
cycle (:class:`DailyCycle`: ``{ mean = "290 K", amplitude = "6 K", peak_hour = 14 }``, §6.5)
with the scenario's local solar hour of day at its start (``[time] hour = 6.5``, in [0, 24)).
The temperature is the cycle's at that hour, held over the whole run (the signature does not
move within a run); :meth:`Scenario.temperature` and :meth:`Scenario.held` resolve it, by
:func:`held_temperature`, for every consumer.

Errors. :class:`ScenarioError` holds every problem found, each located
(``file: table[index].key: what``); its message is the first. Problems that need the files a
scenario names (its image, its terrain map, its sensors' MRTD curves) or the size of its run are
found when it is compiled (:func:`targetacq.core.compile.check_runnable`), which ``targetacq
validate`` does too.

Warnings. A valid value that no real sensor or scene has, most often a unit slip (``focal_length
= 100`` from Python, meant in mm: a 100 m lens), is emitted as a
:class:`targetacq.scenario.plausibility.PlausibilityWarning` each time a :class:`Scenario` is
validated, located and with its likely fix; the scenario still runs as given
(:data:`targetacq.scenario.plausibility.PLAUSIBLE_RANGES` is the table of limits).
"""

from __future__ import annotations

import itertools
import math
import numbers
import tomllib
from collections import Counter
from collections.abc import Callable, Mapping, Sequence
from difflib import get_close_matches
from pathlib import Path
from typing import Annotated, Any, Literal, get_args

import numpy as np
from pydantic import (
    AfterValidator,
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Discriminator,
    Field,
    Tag,
    ValidationError,
    ValidationInfo,
    field_validator,
    model_validator,
)

from targetacq.acquisition.criteria import CRITERIA
from targetacq.acquisition.engagement import REDRAW_RULES
from targetacq.acquisition.path_noise import NOISE_MODELS, SNR_LAWS
from targetacq.acquisition.probabilities import ACQUISITION_SEMANTICS, MOTION_RULES
from targetacq.acquisition.transforms import C2NVEO_BOUNDS, TRANSFORMS
from targetacq.base.inputs import read_input_text
from targetacq.base.limits import (
    MAX_ANGLE_TURN,
    MAX_DEPRESSION,
    check_count,
    check_length,
    check_range,
    check_size,
    check_temperature,
    check_temperature_difference,
)
from targetacq.base.registry import lookup, unknown_name
from targetacq.base.units import is_quantity, to_si
from targetacq.physics import atmosphere as _atmosphere
from targetacq.physics.aspect import AspectTable
from targetacq.physics.named_atmospheres import AEROSOLS, ATMOSPHERES, NamedPath
from targetacq.physics.optics import FIELD_OF_VIEW_PROJECTIONS
from targetacq.physics.radiometry import MATERIALS, diurnal_temperature
from targetacq.scenario.plausibility import collected, emit, plausibility_warnings
from targetacq.sensors import (
    SENSOR_TYPES,
    check_sensor_band,
    check_sensor_noise,
    check_sensor_tables,
    get_sensor_type,
    sensor_band,
)

__all__ = [
    "Atmosphere",
    "Background",
    "Cloud",
    "DailyCycle",
    "Elevation",
    "FalseTargets",
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
    "held_temperature",
    "load_scenario",
    "parse_scenario",
]

_TASKS = ("detection", "recognition", "identification")

_GRID_ADVICE = "use a longer time.step or a shorter span (time.start to time.stop)"


class ScenarioError(ValueError):
    """A scenario that cannot be used; the message says where and what is wrong.

    Parameters
    ----------
    problems : str or sequence of str
        One located problem, or every problem found (at least one).

    Attributes
    ----------
    problems : tuple of str
        Every problem, each located (``file: table[index].key: what``). The message is the
        first, with the count of the others (``targetacq validate`` prints them all).
    """

    def __init__(self, problems: str | Sequence[str]) -> None:
        self.problems = (problems,) if isinstance(problems, str) else tuple(problems)
        if not self.problems:
            raise TypeError("ScenarioError needs at least one problem")
        others = len(self.problems) - 1
        more = f" (and {others} more problem{'s' if others > 1 else ''})" if others else ""
        super().__init__(self.problems[0] + more)

    def in_file(self, source: str | Path) -> ScenarioError:
        """The same problems, each prefixed with the file they are in."""
        return ScenarioError([f"{source}: {problem}" for problem in self.problems])


def _strict_units(info: ValidationInfo) -> bool:
    """Whether bare numbers are refused: set by :func:`parse_scenario` for files."""
    return isinstance(info.context, Mapping) and bool(info.context.get("strict_units"))


def _quantity(kind: str, domain: Callable[[str, float], Any] | None = None) -> Any:
    """A quantity of ``kind`` in SI, checked finite (by :func:`targetacq.base.units.to_si`) and,
    where given, by ``domain(name, value)``."""

    def parse(value: Any, info: ValidationInfo) -> float:
        name = info.field_name or kind
        number = to_si(value, kind, name, strict=_strict_units(info))
        if domain is not None:
            domain(name, number)
        return number

    return BeforeValidator(parse)


def _within(limit: float) -> Callable[[str, float], Any]:
    def check(name: str, value: float) -> None:
        check_range(name, value, -limit, limit, "deg", 180.0 / math.pi)

    return check


Length = Annotated[float, _quantity("length", check_length)]
"""A length or a coordinate, within ±``limits.MAX_LENGTH``."""
Angle = Annotated[float, _quantity("angle")]
Bearing = Annotated[float, _quantity("angle", _within(MAX_ANGLE_TURN))]
"""An azimuth or heading: from north, clockwise, within one turn either way."""
Depression = Annotated[float, _quantity("angle", _within(MAX_DEPRESSION))]
Temperature = Annotated[float, _quantity("temperature", check_temperature)]
TemperatureDifference = Annotated[
    float, _quantity("temperature difference", check_temperature_difference)
]
Extinction = Annotated[float, _quantity("extinction")]
Time = Annotated[float, _quantity("time")]
Irradiance = Annotated[float, _quantity("irradiance")]
AreaDensity = Annotated[float, _quantity("area density")]
Area = Annotated[float, _quantity("area")]
Power = Annotated[float, _quantity("power")]
Frequency = Annotated[float, _quantity("frequency")]
Speed = Annotated[float, _quantity("speed")]
PowerRatio = Annotated[float, _quantity("power ratio")]
StructureConstant = Annotated[float, _quantity("structure constant")]
"""A refractive-index structure constant Cn² [m^(-2/3)] (``"1e-14 m^(-2/3)"``)."""
"""A ratio of powers, written in dB in files (``"30 dB"``); linear inside."""


def _show(value: Any) -> str:
    """A value as the user wrote it: text quoted, numbers and flags as in TOML."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return f'"{value}"'
    return repr(value)


def _flag(value: Any, info: ValidationInfo) -> bool:
    """``true`` or ``false`` only: no "yes", no 1."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise ValueError(
        f"{info.field_name} must be true or false (without quotes); got {_show(value)}"
    )


def _whole(value: Any, info: ValidationInfo) -> int:
    """A whole number: no quoted text, no 3.5 (nor 3.0), no flag."""
    if isinstance(value, numbers.Integral) and not isinstance(value, (bool, np.bool_)):
        return int(value)
    raise ValueError(f"{info.field_name} must hold whole numbers; got {_show(value)}")


def _number(value: Any, info: ValidationInfo) -> float:
    """A finite plain number: no quoted text, no flag."""
    if isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_)):
        number = float(value)
        if math.isfinite(number):
            return number
        raise ValueError(f"{info.field_name} must be a finite number; got {number:g}")
    raise ValueError(f"{info.field_name} must be a number (without quotes); got {_show(value)}")


def _name(value: Any, info: ValidationInfo) -> str:
    if not isinstance(value, str) or not value.strip():
        raise ValueError(f"{info.field_name} must be a non-empty text; got {_show(value)}")
    return value


def _pixel_count(value: int, info: ValidationInfo) -> int:
    return check_count(info.field_name or "pixels", value, 1)


def _pixel_index(value: int, info: ValidationInfo) -> int:
    # A negative one is refused with the whole box (Target), saying what a box is.
    return value if value < 0 else check_count(info.field_name or "image_box", value, 0)


Flag = Annotated[bool, BeforeValidator(_flag)]
WholeNumber = Annotated[int, BeforeValidator(_whole)]
Number = Annotated[float, BeforeValidator(_number)]
Fraction = Annotated[Number, Field(ge=0.0, le=1.0)]
Name = Annotated[str, BeforeValidator(_name)]
PixelCount = Annotated[WholeNumber, Field(gt=0), AfterValidator(_pixel_count)]
"""A number of pixels, in [1, ``limits.MAX_ELEMENTS``]."""
PixelIndex = Annotated[WholeNumber, AfterValidator(_pixel_index)]
"""A pixel position or extent of a box, at most ``limits.MAX_ELEMENTS`` (the lower bounds are
checked with the whole box)."""


def _hour_of_day(value: float, info: ValidationInfo) -> float:
    if not 0.0 <= value < 24.0:
        raise ValueError(
            f"{info.field_name} must be in [0, 24) (the local solar hour of day, e.g. 6.5 for "
            f"06:30); got {value:g}"
        )
    return value


HourOfDay = Annotated[Number, AfterValidator(_hour_of_day)]
"""A local (solar) hour of day [h], a plain number in [0, 24): 6.5 is 06:30."""


def _position(value: Any, info: ValidationInfo) -> tuple[float, float, float]:
    name = info.field_name or "position"
    if isinstance(value, str):
        *numbers_, unit = value.replace(",", " ").split() or [""]
        parts: list[Any] = [f"{n} {unit}" for n in numbers_]
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
    x, y, z = (
        check_length(name, to_si(part, "length", name, strict=strict), "coordinates")
        for part in parts
    )
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


def _band_table(kind: str | None) -> Any:
    """A value, or a table of values per named colour band (``{red = 0.2, green = 0.3}``):
    fractions in [0, 1] where ``kind`` is None, else quantities of ``kind``; each error names
    the band."""

    def parse(value: Any, info: ValidationInfo) -> Any:
        name = info.field_name or "value"

        def one(item: Any, where: str) -> float:
            if kind is not None:
                return to_si(item, kind, where, strict=_strict_units(info))
            if not isinstance(item, numbers.Real) or isinstance(item, (bool, np.bool_)):
                raise ValueError(f"{where} must be a number (without quotes); got {_show(item)}")
            number = float(item)
            if not 0.0 <= number <= 1.0:
                raise ValueError(f"{where} must be in [0, 1]; got {number:g}")
            return number

        if isinstance(value, Mapping):
            if not value:
                raise ValueError(f"{name}: a table of bands needs at least one band")
            if not all(isinstance(band, str) and band.strip() for band in value):
                raise ValueError(f"{name}: band names are non-empty texts")
            return {band: one(item, f"{name}.{band}") for band, item in value.items()}
        return one(value, name)

    return BeforeValidator(parse)


BandFractions = Annotated[float | dict[str, float], _band_table(None)]
"""A fraction, or one per named colour band (``{red = 0.2, green = 0.3, blue = 0.1}``)."""
BandIrradiances = Annotated[float | dict[str, float], _band_table("irradiance")]
"""An irradiance, or one per named colour band."""


class Radar(_Strict):
    """A pulse radar's transmitter, antenna, receiver and detector (the ``radar`` table of a
    ``type = "radar"`` sensor; the model is :mod:`targetacq.sensors.radar`).

    ``power`` peak transmitted power, ``gain`` antenna gain and ``noise_figure``, ``losses`` as
    power ratios in dB, ``frequency`` the carrier, ``pulse_length`` τ (matched filter: noise
    bandwidth 1/τ, range resolution c τ / 2), ``beamwidth`` the antenna's azimuth beamwidth θ_a,
    ``false_alarm`` the detector's P_fa, ``pulses`` integrated non-coherently, ``detector`` the
    P_d(SNR, P_fa) model, ``polarization`` for the rain attenuation, and the cells on target of
    P = 0.5 for recognition and identification (the project's criteria for radar).

    The default detector is ``swerling1`` (a fluctuating target, one pulse: exact, and P_d → P_fa
    as the SNR → 0). Albersheim's formula is stated for 0.1 <= P_d <= 0.9 (within 0.2 dB of the
    exact curve for P_d >= 0.4): below, it tends to a floor (0.017 at P_fa = 1e-6) instead of
    P_fa, so a distant target keeps a small P_d per look;
    ``marcum`` is exact for a steady target (NumPy only). See
    :data:`targetacq.physics.radar_equation.RADAR_DETECTION_MODELS`.
    """

    power: Power
    gain: PowerRatio
    frequency: Frequency
    pulse_length: Time
    beamwidth: Angle
    noise_figure: PowerRatio = 1.0
    losses: PowerRatio = 1.0
    false_alarm: Annotated[Number, Field(gt=0.0, lt=1.0)] = 1e-6
    pulses: Annotated[WholeNumber, Field(ge=1)] = 1
    detector: str = "swerling1"
    polarization: Literal["horizontal", "vertical", "circular"] = "horizontal"
    recognition_cells: Annotated[Number, Field(gt=0.0)] = 8.0
    identification_cells: Annotated[Number, Field(gt=0.0)] = 12.8

    @model_validator(mode="after")
    def _check(self) -> Radar:
        from targetacq.physics.radar_equation import RADAR_DETECTION_MODELS

        for name in ("power", "frequency", "pulse_length", "gain"):
            if not getattr(self, name) > 0:
                raise ValueError(f"radar.{name} must be > 0")
        if not 0 < self.beamwidth < math.pi:
            raise ValueError("radar.beamwidth must be in (0, 180) degrees")
        for name in ("noise_figure", "losses"):
            if not getattr(self, name) >= 1:
                raise ValueError(f"radar.{name} must be >= 0 dB")
        model = lookup(RADAR_DETECTION_MODELS, self.detector, "radar detector")
        if model.single_pulse and self.pulses > 1:
            raise ValueError(
                f"radar.detector {self.detector!r} is for one pulse; with pulses > 1 use "
                "albersheim or marcum"
            )
        if self.identification_cells <= self.recognition_cells:
            raise ValueError("radar.identification_cells must exceed recognition_cells")
        return self


class Laser(_Strict):
    """A direct-detection laser radar's transmitter and receiver (the ``laser`` table of a
    ``type = "laser_radar"`` sensor; the model is :mod:`targetacq.sensors.laser_radar`).

    ``power`` transmitted (peak) power, ``aperture`` the receiver's diameter, ``timing`` the
    shortest time that separates two returns (range resolution c t / 2), ``nep`` the receiver's
    noise-equivalent power (0: no receiver noise), ``efficiency`` of the optics and detector.
    """

    power: Power
    aperture: Length
    timing: Time
    nep: Power = 0.0
    efficiency: Annotated[Number, Field(gt=0.0, le=1.0)] = 1.0

    @model_validator(mode="after")
    def _check(self) -> Laser:
        for name in ("power", "aperture", "timing"):
            if not getattr(self, name) > 0:
                raise ValueError(f"laser.{name} must be > 0")
        if not self.nep >= 0:
            raise ValueError("laser.nep must be >= 0 W")
        return self


class Sensor(_Strict):
    """An imaging sensor.

    ``type`` "thermal" sees emitted radiation in its ``band``; "tv" sees reflected light
    (visible band, the background's ``irradiance``). ``projection`` says how ``hfov`` over
    ``pixels`` gives the IFOV: "angular" (default, IFOV = hfov / pixels, the datasheet
    convention) or "rectilinear" (a pinhole camera, 2 tan(hfov/2) / pixels); it applies to
    ``hfov`` only (left out, it stays ``None`` and :attr:`fov_projection` says "angular").
    ``f_number`` gives the aperture as ``focal_length / f_number``. The sensor's own noise:
    ``netd`` of a thermal sensor (quoted at ``netd_temperature``, 300 K by default), ``nec``
    (noise-equivalent contrast, relative to the background) of a TV sensor; without them only
    the atmosphere adds noise. The resolution is given one way: ``pitch`` with
    ``focal_length``, ``hfov`` with ``pixels``, or ``ifov``. Pointing: ``look_at`` a point,
    or ``azimuth`` (from north, clockwise) and ``depression`` (below the horizon); with neither,
    every target is taken to be in view. ``mrtd``: a thermal sensor's MRTD curve, the path of a
    CSV file (:meth:`targetacq.physics.mrtd.MrtdCurve.from_csv`; in a scenario file relative to its
    folder, :func:`load_scenario`), read when the scenario is compiled; it makes the sensor's
    resolution MRTD-limited (:mod:`targetacq.core.mrtd_rows`: the pair's contrast as a blackbody
    ΔT at ``netd_temperature``); the curve holds the sensor's noise, so no SNR acts on top of
    it unless the model table names a ``noise_model`` (then the NETD's noise adds to it).
    The digitiser (§6.8): ``quantisation_step`` (e.g. "0.01 W/m^2"), or ``adc_bits`` with
    ``adc_span`` (the signal span its levels cover, step = span / (2^bits − 1),
    :func:`targetacq.physics.radiometry.quantisation_step`); a pair whose contrast at the scene, in
    the signal unit of the sensor's type (W/m²), is below the step has every probability 0. Imaging
    sensors only. The TTP resolution model (``[model] resolution_model = "ttp"``,
    :mod:`targetacq.core.ttp_rows`) of a thermal sensor takes its aperture (``aperture`` or
    ``f_number``), ``netd`` (none: noise-free) and ``jitter`` (RMS line-of-sight jitter per
    axis, e.g. "0.02 mrad"; default 0), ``smear`` (image motion in one frame; default 0),
    ``frame_rate`` (default "30 Hz") and ``scene_contrast`` (the scene contrast temperature
    that sets the display's gain; default "5 K"), as the range commands' options do.
    """

    name: Name
    type: Annotated[str, BeforeValidator(_sensor_type)] = "thermal"
    band: str | None = None
    pixels: tuple[PixelCount, PixelCount] | None = None
    pitch: Length | None = None
    focal_length: Length | None = None
    hfov: Angle | None = None
    ifov: Angle | None = None
    aperture: Length | None = None
    position: Position | None = None
    waypoints: list[Waypoint] | None = None
    look_at: Position | None = None
    azimuth: Bearing | None = None
    depression: Depression | None = None
    projection: str | None = None
    f_number: Annotated[Number, Field(gt=0.0)] | None = None
    netd: TemperatureDifference | None = None
    netd_temperature: Temperature = 300.0
    nec: Annotated[Number, Field(ge=0.0)] | None = None
    bands: Annotated[list[Name], Field(min_length=1)] | None = None
    radar: Radar | None = None
    laser: Laser | None = None
    mrtd: str | None = None
    quantisation_step: Irradiance | None = None
    adc_bits: Annotated[WholeNumber, Field(ge=1, le=64)] | None = None
    adc_span: Irradiance | None = None
    jitter: Angle | None = None
    smear: Angle | None = None
    frame_rate: Frequency | None = None
    scene_contrast: TemperatureDifference | None = None

    @model_validator(mode="after")
    def _check(self) -> Sensor:
        self._check_type_tables()
        self._check_ttp_inputs()
        self._check_digitiser()
        if self.type == "radar":
            return self._check_radar()
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
        if self.projection is not None:
            lookup(FIELD_OF_VIEW_PROJECTIONS, self.projection, "projection")
            if self.hfov is None:
                # As the CLI says it: a projection turns a field of view into an IFOV, and a
                # pitch with a focal length (or an IFOV) is one already.
                raise ValueError("projection applies to hfov and pixels")
        if self.f_number is not None:
            if self.focal_length is None:
                raise ValueError("f_number needs focal_length (aperture = focal_length / f_number)")
            if self.aperture is not None:
                raise ValueError("give aperture or f_number, not both")
            # The aperture diameter a datasheet's F-number stands for: D = f / F#.
            object.__setattr__(self, "aperture", self.focal_length / self.f_number)
        check_sensor_band(self)  # required, or the type's default; within the type's limits
        _one_place(self.position, self.waypoints, "sensor")
        if self.look_at is not None and (self.azimuth is not None or self.depression is not None):
            raise ValueError("give look_at, or azimuth and depression, not both")
        if (self.azimuth is None) != (self.depression is None):
            raise ValueError("azimuth and depression go together")
        if self.pixels is None and (self.look_at is not None or self.azimuth is not None):
            raise ValueError("pointing needs pixels = [width, height] for the field of view")
        if self.look_at is not None and _on_path(self.look_at, self.position, self.waypoints):
            raise ValueError(
                "look_at is the sensor's own position (or lies on its waypoints' path): a "
                "sensor cannot look at itself; give a point away from it"
            )
        self.field_of_view  # noqa: B018 - refuses a field of view of 180 degrees or more
        get_sensor_type(self.type).cycle_angle(self)  # the resolution model takes the optics
        check_sensor_noise(self)  # netd or nec: the one the type takes
        return self

    def _check_digitiser(self) -> None:
        """The digitiser's step: given once, one way, by an imaging sensor (it is compared with
        the contrast, which radars and laser radars have none of)."""
        given = [
            key
            for key in ("quantisation_step", "adc_bits", "adc_span")
            if getattr(self, key) is not None
        ]
        if not given:
            return
        kind = get_sensor_type(self.type).kind
        if kind != "imaging":
            raise ValueError(
                f"{given[0]}: a digitiser's step is compared with an imaging sensor's contrast; "
                f"a {kind.replace('_', ' ')} has none (leave {given[0]} out)"
            )
        if self.quantisation_step is not None and len(given) > 1:
            raise ValueError("give quantisation_step, or adc_bits with adc_span, not both")
        if (self.adc_bits is None) != (self.adc_span is None):
            raise ValueError(
                "adc_bits and adc_span go together (step = adc_span / (2^adc_bits − 1))"
            )
        if self.quantisation_step is not None and not self.quantisation_step >= 0:
            raise ValueError("quantisation_step must be >= 0 W/m^2")
        if self.adc_span is not None and not self.adc_span > 0:
            raise ValueError("adc_span must be > 0 W/m^2")

    def _check_ttp_inputs(self) -> None:
        """The TTP metric's inputs (:data:`TTP_SENSOR_FIELDS`): in their domains."""
        for name in ("jitter", "smear"):
            value = getattr(self, name)
            if value is not None and not value >= 0:
                raise ValueError(f"{name} must be >= 0 rad (e.g. 0.02 mrad)")
        for name, example in (("frame_rate", "30 Hz"), ("scene_contrast", "5 K")):
            value = getattr(self, name)
            if value is not None and not value > 0:
                raise ValueError(f"{name} must be > 0 (e.g. {example})")

    def _check_type_tables(self) -> None:
        """The tables that belong to one sensor type: bands (colour), radar, laser."""
        check_sensor_tables(self)
        if self.bands is not None and len(set(self.bands)) != len(self.bands):
            raise ValueError("bands must be distinct names")

    def _check_radar(self) -> Sensor:
        """A radar's resolution is its antenna and pulse: no optics, no field of view."""
        optics_given = [
            key
            for key in ("pixels", "pitch", "focal_length", "hfov", "ifov", "aperture", "band")
            if getattr(self, key) is not None
        ]
        if optics_given:
            raise ValueError(
                f"{optics_given[0]} is an imaging sensor's; a radar's resolution is "
                "radar.beamwidth and radar.pulse_length"
            )
        if self.look_at is not None or self.azimuth is not None:
            raise ValueError("a radar here scans all around: it takes no look_at or azimuth")
        if self.netd is not None or self.nec is not None:
            raise ValueError("a radar's noise is its receiver: radar.noise_figure")
        _one_place(self.position, self.waypoints, "sensor")
        return self

    @property
    def limits(self) -> tuple[float, float]:
        """The band (λ1, λ2) [m]; without one, its type's default (a TV sensor: the visible)."""
        return sensor_band(self)

    @property
    def fov_projection(self) -> str:
        """The projection of ``hfov`` over ``pixels``: ``projection``, "angular" by default."""
        return self.projection or "angular"

    @property
    def pixel_ifov(self) -> float:
        """IFOV [rad] of the central pixel (a radar's: its beamwidth)."""
        from targetacq.physics import optics

        if self.radar is not None:
            return self.radar.beamwidth
        if self.ifov is not None:
            return self.ifov
        if self.hfov is not None and self.pixels is not None:
            return float(
                optics.ifov_from_field_of_view(self.hfov, self.pixels[0], self.fov_projection)
            )
        assert self.pitch is not None
        assert self.focal_length is not None
        return self.pitch / self.focal_length

    @property
    def field_of_view(self) -> tuple[float, float] | None:
        """(horizontal, vertical) full field of view [rad], if pixels are given."""
        from targetacq.physics import optics

        if self.pixels is None:
            return None
        # A pitch-and-focal-length (or IFOV) sensor is a pinhole camera; an hfov sensor follows
        # its projection.
        projection = self.fov_projection if self.hfov is not None else "rectilinear"
        h, v = (
            float(optics.field_of_view_from_ifov(self.pixel_ifov, n, projection))
            for n in self.pixels
        )
        if h >= math.pi or v >= math.pi:
            raise ValueError("the field of view must be < 180 degrees on both sides")
        return h, v


class DailyCycle(_Strict):
    """A temperature's simple daily cycle (§6.5): ``mean`` [K], ``amplitude`` [K] (half the
    daily swing, >= 0 and < mean) and ``peak_hour`` [h] (the local solar hour of the maximum,
    in [0, 24); 14 by default), the sinusoid of
    :func:`targetacq.physics.radiometry.diurnal_temperature` with its stated assumptions.

    Given for a temperature in a scenario (``temperature = { mean = "290 K", amplitude = "6 K",
    peak_hour = 14 }``), it needs the scenario's hour of day (``[time] hour``): the temperature
    is the cycle's at that hour, held over the whole run (:func:`held_temperature`).

    Examples
    --------
    >>> from targetacq.scenario.schema import DailyCycle
    >>> cycle = DailyCycle(mean="290 K", amplitude="6 K")
    >>> print(cycle.at(14.0), cycle.at(2.0), round(cycle.at(8.0), 9))
    296.0 284.0 290.0
    """

    mean: Temperature
    amplitude: TemperatureDifference
    peak_hour: HourOfDay = 14.0

    @model_validator(mode="after")
    def _check(self) -> DailyCycle:
        if not self.amplitude < self.mean:
            raise ValueError(
                f"amplitude must be smaller than mean (the temperature stays above 0 K); got "
                f"amplitude {self.amplitude:g} K, mean {self.mean:g} K"
            )
        return self

    def at(self, hour: float) -> float:
        """The temperature [K] at the local solar ``hour`` [h]
        (:func:`targetacq.physics.radiometry.diurnal_temperature`)."""
        return float(diurnal_temperature(hour, self.mean, self.amplitude, self.peak_hour))


_PLAIN, _CYCLE = "plain temperature", "daily cycle"
_TABLE_FILE, _TABLE_WRITTEN = "signature table file", "signature table written in the scenario"
_UNION_TAGS = (_PLAIN, _CYCLE, _TABLE_FILE, _TABLE_WRITTEN)  # the branches' names in pydantic's
# error locations, left out of the located messages


def _temperature_kind(value: Any) -> str:
    return _CYCLE if isinstance(value, (Mapping, DailyCycle)) else _PLAIN


TemperatureOrCycle = Annotated[
    Annotated[Temperature, Tag(_PLAIN)] | Annotated[DailyCycle, Tag(_CYCLE)],
    Discriminator(_temperature_kind),
]
"""A temperature [K], or its daily cycle (a table: :class:`DailyCycle`)."""


def held_temperature(value: float | DailyCycle | None, hour: float | None) -> float | None:
    """A scenario's temperature [K] at the local solar ``hour`` of its start, held over the run.

    The one place where a daily cycle becomes a temperature: every consumer (the compiler, the
    reports) reads temperatures through it, by :meth:`Scenario.temperature` or
    :meth:`Scenario.held`.

    Parameters
    ----------
    value : float, DailyCycle or None
        A plain temperature [K] (returned as it is), a daily cycle, or none.
    hour : float or None
        The scenario's hour of day (``time.hour``) [h]; needed by a daily cycle.

    Returns
    -------
    float or None
        ``value`` itself, or the cycle at ``hour``:
        ``mean + amplitude · cos(2π (hour − peak_hour)/24)`` (§6.5,
        :func:`targetacq.physics.radiometry.diurnal_temperature`).

    Raises
    ------
    ValueError
        A daily cycle without an hour.

    Examples
    --------
    >>> from targetacq.scenario.schema import DailyCycle, held_temperature
    >>> held_temperature(300.0, None)
    300.0
    >>> held_temperature(DailyCycle(mean=290.0, amplitude=6.0, peak_hour=14.0), 2.0)
    284.0
    """
    if not isinstance(value, DailyCycle):
        return value
    if hour is None:
        raise ValueError("a daily cycle of a temperature needs the hour of day: give [time] hour")
    return value.at(hour)


_MAX_TABLE_NODES = 3601
"""Most azimuths (or elevations) of a signature table written in a scenario (0.1 deg steps)."""


class SignatureTableSpec(_Strict):
    """A signature table written in the scenario (:mod:`targetacq.physics.aspect`): the
    observer's ``azimuth`` (from the target's heading, clockwise; 0 head-on) and ``elevation``
    (above the target's horizontal plane), each a list of angles ("0 deg", "45 deg", ...,
    strictly ascending), and ``temperature`` [K] or ``contrast`` (the target's temperature
    minus the background's [K]): one list per azimuth, of one value per elevation."""

    azimuth: Annotated[list[Angle], Field(min_length=1, max_length=_MAX_TABLE_NODES)]
    elevation: Annotated[list[Angle], Field(min_length=1, max_length=_MAX_TABLE_NODES)]
    temperature: list[list[Temperature]] | None = None
    contrast: list[list[TemperatureDifference]] | None = None

    @model_validator(mode="after")
    def _check(self) -> SignatureTableSpec:
        self.table()  # the grid's shape, order and range, said once (AspectTable's checks)
        return self

    def table(self, source: str = "") -> AspectTable:
        """The table as a :class:`targetacq.physics.aspect.AspectTable` [rad, K]."""
        given = [
            (q, v) for q, v in (("temperature", self.temperature), ("contrast", self.contrast))
        ]
        present = [(q, v) for q, v in given if v is not None]
        if len(present) != 1:
            raise ValueError("give temperature or contrast (one list per azimuth), not both")
        quantity, values = present[0]
        return AspectTable(
            tuple(self.azimuth),
            tuple(self.elevation),
            tuple(tuple(row) for row in values),
            quantity,
            source,
        )


def _table_kind(value: Any) -> str:
    return _TABLE_WRITTEN if isinstance(value, (Mapping, SignatureTableSpec)) else _TABLE_FILE


TableOrFile = Annotated[
    Annotated[str, Tag(_TABLE_FILE)] | Annotated[SignatureTableSpec, Tag(_TABLE_WRITTEN)],
    Discriminator(_table_kind),
]
"""A signature table: its CSV file's path, or the table itself (:class:`SignatureTableSpec`)."""


class Target(_Strict):
    """A target: a box ``dimensions`` = [length, width, height] with its long axis along
    ``heading`` (from north, clockwise; the direction of motion when it moves along waypoints).
    ``image_box`` = [x, y, width, height] in pixels of the background's ``image``. ``foliage``:
    the transmittance of foliage in front of the target, in [0, 1] (§6.8; 0 hides it), which
    multiplies the path's transmittance for every imaging sensor (left out: none); radars and
    laser radars take none. ``temperature``: a temperature, or its daily cycle
    (:class:`DailyCycle`, with ``[time] hour``).

    Cues (:mod:`targetacq.acquisition.cues`): ``hot_spot = true`` and ``moving = true`` are the
    thesis's switches (the full cue). Graded instead: ``hot_spot_ratio``, the hot spot's own
    signal-to-clutter ratio [1] (0.05 of the cue at 1, 0.95 at 10), with its linear size
    ``hot_spot_size`` (e.g. "0.4 m"; a hot spot smaller than a resolution element is diluted, so
    the cue fades with range); ``graded_motion = true``, a motion cue weighted by the target's
    angular speed across each sensor's line of sight in pixels per second, from its own velocity
    over the ground (its waypoints; a target standing still, or driving straight at the sensor,
    gets none; the sensor's own motion moves the background as much and gives none).

    Signature over the aspect (:mod:`targetacq.physics.aspect`): ``signature_table``, the path
    of a CSV file (columns ``azimuth``, ``elevation`` in degrees and ``temperature`` or
    ``contrast`` in K, optionally ``state``, picked by ``signature_state`` such as
    ``"engine-on"``; in a scenario file relative to its folder) or a table written in the
    scenario (:class:`SignatureTableSpec`): each sensor sees the target's temperature from the
    side it looks at (the azimuth from the target's heading, the elevation above its plane),
    interpolated bilinearly. ``temperature`` may then be left out (the table's mean stands for
    it where one number is needed)."""

    name: Name
    dimensions: tuple[Length, Length, Length]
    heading: Bearing = 0.0
    criterion: str | None = None
    temperature: TemperatureOrCycle | None = None
    emissivity: Fraction | None = None
    material: str | None = None
    reflectance: BandFractions | None = None
    rcs: Area | None = None
    position: Position | None = None
    waypoints: list[Waypoint] | None = None
    moving: Flag = False
    visible_fraction: Annotated[Number, Field(gt=0.0, le=1.0)] = 1.0
    hot_spot: Flag = False
    foliage: Fraction | None = None
    image_box: tuple[PixelIndex, PixelIndex, PixelIndex, PixelIndex] | None = None
    hot_spot_ratio: Annotated[Number, Field(ge=0.0)] | None = None
    hot_spot_size: Length | None = None
    graded_motion: Flag = False
    signature_table: TableOrFile | None = None
    signature_state: Name | None = None

    @field_validator("criterion")
    @classmethod
    def _known_criterion(cls, value: str | None) -> str | None:
        return value if value is None else _probability_criterion(value)

    @model_validator(mode="after")
    def _check(self) -> Target:
        if any(not d > 0 for d in self.dimensions):
            raise ValueError("dimensions must be > 0")
        if self.rcs is not None and not self.rcs >= 0:
            raise ValueError("rcs must be >= 0 m^2 (a radar cross-section)")
        _one_place(self.position, self.waypoints, "target")
        if self.image_box is not None:
            x, y, width, height = self.image_box
            if x < 0 or y < 0 or width < 1 or height < 1:
                raise ValueError(
                    "image_box is [x, y, width, height] in pixels with x, y >= 0 and width, "
                    f"height >= 1; got {list(self.image_box)}"
                )
        if self.material is not None and self.material not in MATERIALS:
            raise ValueError(f"material must be one of {', '.join(MATERIALS)}")
        if self.emissivity is not None and self.material is not None:
            raise ValueError("give emissivity or material, not both")
        self._check_cues()
        if self.signature_state is not None and not isinstance(self.signature_table, str):
            raise ValueError(
                "signature_state picks a state of a signature table file (its state column): "
                'give signature_table = "FILE.csv" too'
            )
        return self

    def aspect_table(self) -> AspectTable | None:
        """The target's signature table, read (a file) or converted (written in the
        scenario); None without one.

        Raises
        ------
        ValueError
            A file that cannot be read or is not a table (:meth:`AspectTable.from_csv`).
        """
        if self.signature_table is None:
            return None
        if isinstance(self.signature_table, str):
            return AspectTable.from_csv(self.signature_table, self.signature_state)
        return self.signature_table.table()

    def _check_cues(self) -> None:
        """A cue is a switch or graded, not both; a hot spot's size goes with its ratio."""
        if self.hot_spot and self.hot_spot_ratio is not None:
            raise ValueError(
                "give hot_spot = true (the full cue) or hot_spot_ratio (a graded one), not both"
            )
        if self.moving and self.graded_motion:
            raise ValueError(
                "give moving = true (the full cue) or graded_motion = true (graded by the "
                "target's angular speed), not both"
            )
        if self.hot_spot_size is not None:
            if self.hot_spot_ratio is None:
                raise ValueError("hot_spot_size grades a hot spot: give its hot_spot_ratio too")
            if not self.hot_spot_size > 0:
                raise ValueError("hot_spot_size must be > 0 m")


class TerrainClassSpec(_Strict):
    """A terrain class of a thermal scene: its mean temperature and its temperature spread at a
    stated ground resolution (§6.7). ``temperature``: a temperature, or its daily cycle
    (:class:`DailyCycle`, with ``[time] hour``)."""

    name: Name
    temperature: TemperatureOrCycle
    temperature_std: TemperatureDifference
    resolution: Length

    @model_validator(mode="after")
    def _check(self) -> TerrainClassSpec:
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


class Elevation(_Strict):
    """Terrain relief for lines of sight (:mod:`targetacq.physics.line_of_sight`): the
    ``[terrain]`` table. ``elevation`` names a ``.npy`` grid of altitudes [m] (row 0 the
    southern edge, rows northward, columns eastward; ``spacing`` between posts and ``origin``,
    the east and north of post [0, 0], required) or a GeoTIFF (``.tif``; needs the ``terrain``
    extra; its own georeferencing unless ``spacing`` / ``origin`` are given). In a file the path
    is relative to the file's folder. ``earth_radius_factor``: the effective Earth radius over
    the Earth's radius [1], > 0: 4/3 for standard refraction (ITU-R P.834), about 7/6 for light
    (the geodetic refraction coefficient 0.13), 1e6 or more for a flat Earth in practice.
    Each sensor-target pair then sees the fraction of the target's height above the terrain's
    highest sight line; a target the terrain hides entirely is out of that sensor's view."""

    elevation: str
    spacing: Length | None = None
    origin: tuple[Length, Length] | None = None
    earth_radius_factor: Annotated[Number, Field(gt=0.0)] = 4.0 / 3.0

    @field_validator("elevation")
    @classmethod
    def _suffix(cls, value: str) -> str:
        if Path(value).suffix.lower() not in (".npy", ".tif", ".tiff"):
            raise ValueError(
                f"an elevation model is a .npy grid or a GeoTIFF (.tif, .tiff); got {value!r}"
            )
        return value

    @field_validator("spacing")
    @classmethod
    def _spacing(cls, value: float | None) -> float | None:
        if value is not None and not value > 0:
            raise ValueError(f"must be > 0 m; got {value:g} m")
        return value


class Background(_Strict):
    """The background: its temperature and emissivity (thermal) or reflectance and the
    irradiance (TV), and the clutter as a Table 3.5 region, an SCR, a temperature spread, an
    image (``image`` with each target's ``image_box``) or a terrain map (thermal sensors).
    ``temperature``: a temperature, or its daily cycle (:class:`DailyCycle`, with ``[time]
    hour``). ``sky_temperature``: the effective sky temperature; thermal sensors then see
    surfaces of emissivity ε < 1 (targets and background) reflect ``1 − ε`` of the sky's band
    exitance (§6.3, :func:`targetacq.physics.radiometry.sky_reflected_exitance`).
    ``sky_to_ground``: the ratio K of the horizon sky's luminance to the background's [1], >= 0
    (Duntley 1948; about 0.2 for fresh snow, 1.4 to 5 for forest, Middleton 1952): the path's
    airlight then leaves a TV or colour camera's own noise the contrast ``C τ / (τ + (1 − τ) K)``
    instead of ``C τ`` (:func:`targetacq.physics.atmosphere.contrast_transmittance`); thermal
    sensors are not affected (the path's emission adds equally to target and background)."""

    temperature: TemperatureOrCycle | None = None
    emissivity: Fraction | None = None
    material: str | None = None
    reflectance: BandFractions | None = None
    irradiance: BandIrradiances | None = None
    sky_temperature: Temperature | None = None
    clutter: Literal["low", "medium", "high"] | None = None
    scr: Annotated[Number, Field(ge=0.0)] | None = None
    clutter_std: TemperatureDifference | None = None
    image: str | None = None
    channel: Literal["luminance", "red", "green", "blue"] | None = None
    terrain: Terrain | None = None
    sigma0: PowerRatio | None = None
    relief_std: Length | None = None
    sky_to_ground: Annotated[Number, Field(ge=0.0)] | None = None

    @model_validator(mode="after")
    def _check(self) -> Background:
        ways = (self.clutter, self.scr, self.clutter_std, self.image, self.terrain)
        if sum(v is not None for v in ways) > 1:
            raise ValueError("give one of clutter, scr, clutter_std, image and terrain")
        if self.material is not None and self.material not in MATERIALS:
            raise ValueError(f"material must be one of {', '.join(MATERIALS)}")
        if self.emissivity is not None and self.material is not None:
            raise ValueError("give emissivity or material, not both")
        irradiance = self.irradiance
        values = list(irradiance.values()) if isinstance(irradiance, dict) else [irradiance]
        if not all(v is None or v >= 0 for v in values):
            raise ValueError("irradiance must be >= 0 W/m^2")
        if self.sigma0 is not None and not self.sigma0 > 0:
            raise ValueError("sigma0 must be > 0 (a power ratio in dB, e.g. -20 dB)")
        if self.relief_std is not None and not self.relief_std >= 0:
            raise ValueError("relief_std must be >= 0 m")
        if self.channel is not None and self.image is None:
            raise ValueError("channel picks the channel of background.image; give the image")
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


def _probability_criterion(name: str) -> str:
    """``name`` if it is a criterion with N50s for the three tasks, else ``ValueError``."""
    criterion = lookup(CRITERIA, name, "criterion")
    usable = [
        key
        for key, c in CRITERIA.items()
        if c.gives_probabilities and all(task in c.tasks for task in _TASKS)
    ]
    if not criterion.gives_probabilities:
        raise ValueError(
            f"criterion {name!r} gives pixel-density thresholds, not probabilities (it is for "
            f"ranges: targetacq dri); choose one of {', '.join(usable)}"
        )
    missing = [task for task in _TASKS if task not in criterion.tasks]
    if missing:
        raise ValueError(
            f"criterion {name!r} has no N50 for {', '.join(missing)}; choose one of "
            f"{', '.join(usable)}"
        )
    return name


def _on_path(point: Sequence[float], position: Any, waypoints: Any) -> bool:
    """Whether ``point`` is ``position``, or lies on the straight legs between ``waypoints``
    (within a micrometre: where a boresight would have no direction)."""
    if position is not None:
        places = [np.asarray(position, dtype=float)]
    else:
        places = [np.asarray(w.position, dtype=float) for w in waypoints]
    p = np.asarray(point, dtype=float)
    legs = list(itertools.pairwise(places)) or [(places[0], places[0])]
    for start, end in legs:
        along = end - start
        length2 = float(along @ along)
        share = 0.0 if length2 == 0 else min(max(float((p - start) @ along) / length2, 0.0), 1.0)
        if float(np.linalg.norm(start + share * along - p)) <= 1e-6:
            return True
    return False


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
    Table 7.1) or ``visibility`` with its ``visibility_convention`` (visible band only); or a
    named atmosphere, ``model`` (e.g. "tropical") and ``aerosol`` (e.g. "rural") with the
    aerosol's ``visibility`` (any band) and the path's ``altitude`` (the LOWTRAN7 table of
    :mod:`targetacq.physics.named_atmospheres`; every line of sight is taken as a horizontal
    path at that altitude, sea level by default); ``segments`` near the sensor; local
    ``clouds``. ``rain_rate`` (e.g. "5 mm/h") attenuates radars (ITU-R P.838-3); the optical
    extinctions above do not apply to a radar. ``cn2`` (e.g. "1e-14 m^(-2/3)"): the path's
    turbulence, for the TTP resolution model's turbulence MTF (``[model] resolution_model =
    "ttp"``; default 0)."""

    extinction: Extinction | None = None
    obscurant: str | None = None
    visibility: Length | None = None
    visibility_convention: Literal["koschmieder", "mor"] | None = None
    model: str | None = None
    aerosol: str | None = None
    altitude: Length | None = None
    segments: list[Segment] = []
    clouds: list[Cloud] = []
    rain_rate: Speed | None = None
    cn2: StructureConstant | None = None

    @model_validator(mode="after")
    def _check(self) -> Atmosphere:
        if self.cn2 is not None and not self.cn2 >= 0:
            raise ValueError("cn2 must be >= 0 m^(-2/3) (e.g. 1e-14 m^(-2/3))")
        if self.model is not None or self.aerosol is not None:
            self.named_path()  # checked: names, the visibility's and altitude's ranges
        elif self.altitude is not None:
            raise ValueError("altitude goes with a named atmosphere (model, aerosol)")
        if sum(v is not None for v in (self.extinction, self.obscurant, self.visibility)) > 1:
            raise ValueError("give one of extinction, obscurant and visibility")
        if self.extinction is not None and not self.extinction >= 0:
            raise ValueError("extinction must be >= 0")
        if self.rain_rate is not None and not self.rain_rate >= 0:
            raise ValueError("rain_rate must be >= 0 (e.g. 5 mm/h)")
        if self.visibility is not None and self.named_path() is None:
            if not self.visibility > 0:
                raise ValueError("visibility must be > 0")
            if self.visibility_convention is None:
                raise ValueError('visibility needs visibility_convention = "koschmieder" or "mor"')
        elif self.visibility_convention is not None:
            raise ValueError("visibility_convention goes with visibility; give the visibility")
        _check_obscurant(self.obscurant)
        return self

    def named_path(self) -> NamedPath | None:
        """The named atmosphere (None where neither ``model`` nor ``aerosol`` is given)."""
        if self.model is None and self.aerosol is None:
            return None
        given = [
            name
            for name in ("extinction", "obscurant", "visibility_convention")
            if getattr(self, name) is not None
        ]
        if given:
            raise ValueError(
                f"{', '.join(given)} do not go with a named atmosphere (model, aerosol): its "
                "visibility is the aerosol's meteorological range"
            )
        if self.model is not None and self.model not in ATMOSPHERES:
            raise unknown_name(self.model, ATMOSPHERES, "atmosphere model")
        if self.aerosol is not None and self.aerosol not in AEROSOLS:
            raise unknown_name(self.aerosol, AEROSOLS, "aerosol")
        return NamedPath(
            self.model or "us-standard",
            self.aerosol or "rural",
            self.visibility,
            0.0 if self.altitude is None else self.altitude,
        )

    @property
    def present(self) -> bool:
        """Whether the path attenuates at all."""
        return any(
            v is not None
            for v in (self.extinction, self.obscurant, self.visibility, self.model, self.aerosol)
        ) or bool(self.segments or self.clouds)


# The model choices that name an entry of a registry: the registry and its kind for the message.
_MODEL_REGISTRIES: dict[str, tuple[Mapping[str, Any], str]] = {
    "criterion": (CRITERIA, "criterion"),
    "noise_model": (NOISE_MODELS, "noise model"),
    "snr_law": (SNR_LAWS, "SNR law"),
    "motion": (MOTION_RULES, "motion rule"),
    "semantics": (ACQUISITION_SEMANTICS, "semantics"),
    "redraw": (REDRAW_RULES, "redraw rule"),
}


TTP_SENSOR_FIELDS = ("jitter", "smear", "frame_rate", "scene_contrast")
"""A sensor's fields that only the TTP resolution model reads (``[model] resolution_model =
"ttp"``), with the atmosphere's ``cn2``."""

V50_CRITERIA = ("ttp-vehicles",)
"""The named criteria whose thresholds are V50s of the TTP metric (its cycles ``V``, not
Johnson's ``N``): the ones the ``ttp`` resolution model takes, besides a user triple ``n50``."""


class ModelChoices(_Strict):
    """Model choices: criterion (or a user N50 triple), transform, noise model (default
    ``variance-sum``, except on the rows whose MRTD curve already holds the noise and the path:
    there no SNR, unless a noise model is named), SNR law
    (``snr_law``, :data:`targetacq.acquisition.path_noise.SNR_LAWS`), motion rule
    (how a moving target is detected), semantics (nested or conditional: what the three
    probabilities mean, hence what is reported and sampled), fusion, the search model's
    time constant ``search_time`` (τ = search_time / P∞, 3.4 s by default), and when a
    sensor-target pair's random draws are drawn again (``redraw``,
    :data:`targetacq.acquisition.engagement.REDRAW_RULES`, with its ``decorrelation_time`` [s] where
    the rule takes one), and the resolution model (``resolution_model``, a name of
    :data:`targetacq.core.cases.RESOLUTION_MODELS`, checked when the scenario is compiled: left
    out, ``johnson``, or ``mrtd`` for the sensors with an MRTD curve; ``ttp``: the TTP metric for
    the thermal sensors, :mod:`targetacq.core.ttp_rows`, whose ``V`` goes with V50s: the
    criterion and transform left out become ``ttp-vehicles`` and ``ttp``, and a named criterion
    must be one of :data:`V50_CRITERIA`, or give your own V50s as ``n50``)."""

    criterion: str = "johnson"
    n50: (
        tuple[
            Annotated[Number, Field(gt=0)],
            Annotated[Number, Field(gt=0)],
            Annotated[Number, Field(gt=0)],
        ]
        | None
    ) = None
    transform: str = "ttpf"
    bound: str | None = None
    noise_model: str | None = None
    snr_law: str = "contrast"
    motion: str = "low-clutter"
    semantics: str = "nested"
    fusion: Literal["sensor-level"] = "sensor-level"
    search_time: Time = 3.4
    redraw: str = "never"
    decorrelation_time: Time | None = None
    resolution_model: str | None = None

    @field_validator("criterion", "noise_model", "snr_law", "motion", "semantics", "redraw")
    @classmethod
    def _registered(cls, value: str | None, info: ValidationInfo) -> str | None:
        if value is None:  # noise_model: the default (variance-sum; none on an MRTD curve)
            return value
        registry, kind = _MODEL_REGISTRIES[info.field_name or ""]
        lookup(registry, value, kind)
        return value

    @field_validator("transform")
    @classmethod
    def _all_tasks(cls, value: str) -> str:
        transform = lookup(TRANSFORMS, value, "transform")
        if transform.tasks is not None and any(t not in transform.tasks for t in _TASKS):
            every = [
                k for k, t in TRANSFORMS.items() if t.tasks is None or set(_TASKS) <= set(t.tasks)
            ]
            raise ValueError(
                f"transform {value!r} is for detection in clutter only, and the model's transform "
                f"serves all three tasks: choose one of {', '.join(every)}, and give the clutter "
                "in [background] (clutter, scr, clutter_std, image or terrain) for "
                "Schmieder-Weathersby detection"
            )
        return value

    @model_validator(mode="after")
    def _check(self) -> ModelChoices:
        if self.bound is not None:
            if self.bound not in C2NVEO_BOUNDS:
                raise ValueError(f"bound must be one of {', '.join(C2NVEO_BOUNDS)}")
            if self.transform != "c2nveo":
                raise ValueError('bound is an option of transform = "c2nveo"; give that transform')
        if not self.search_time > 0:
            raise ValueError("search_time must be > 0 s")
        uses_time = REDRAW_RULES[self.redraw].uses_time
        if uses_time and self.decorrelation_time is None:
            raise ValueError(
                f"redraw = {self.redraw!r} needs decorrelation_time (how long a target must be "
                'out of view before it is drawn again, e.g. "30 s")'
            )
        if not uses_time and self.decorrelation_time is not None:
            raise ValueError(
                f"decorrelation_time is an option of redraw = 'after-out-of-view', not of "
                f"redraw = {self.redraw!r}"
            )
        if self.decorrelation_time is not None and not (0 <= self.decorrelation_time < math.inf):
            raise ValueError(f"decorrelation_time must be >= 0 s, got {self.decorrelation_time!r}")
        if self.resolution_model == "ttp":
            self._ttp_defaults()
        if self.n50 is None:
            _probability_criterion(self.criterion)
        elif any(b < a for a, b in itertools.pairwise(self.n50)):
            raise ValueError(
                "n50 = [detection, recognition, identification] must not decrease (a harder "
                f"task needs at least as many cycles); got {list(self.n50)}"
            )
        return self

    def _ttp_defaults(self) -> None:
        """The TTP metric's V goes with V50s and its TTPF: the criterion and transform left out
        become ``ttp-vehicles`` and ``ttp`` (as the range commands' ``--resolution-model ttp``
        does); a named criterion of Johnson's cycles is refused."""
        given = self.model_fields_set
        if "criterion" not in given and self.n50 is None:
            object.__setattr__(self, "criterion", V50_CRITERIA[0])
        elif self.n50 is None and self.criterion not in V50_CRITERIA:
            raise ValueError(
                f"criterion {self.criterion!r} gives Johnson's N50s, and resolution_model = "
                f'"ttp" gives the TTP metric\'s V: choose one of {", ".join(V50_CRITERIA)}, '
                "or give your own V50s as n50 = [detection, recognition, identification]"
            )
        if "transform" not in given:
            object.__setattr__(self, "transform", "ttp")


class FalseTargets(_Strict):
    """False detections: target-like clutter objects declared targets (the ``[false_targets]``
    table; the law is in :mod:`targetacq.run.false_targets`).

    ``density`` [1/m²] of target-sized clutter objects on the ground, ``probability`` the hazard
    of declaring an object in view a target, in units of 1/t_s (about the probability that an
    object looked at for one search time is declared), ``max_range`` [m] the farthest ground the
    sensors search, and ``sensors`` the sensors that report false detections (default: every
    sensor with a field of view).
    """

    density: AreaDensity
    probability: Annotated[Number, Field(gt=0.0, le=1.0)]
    max_range: Length
    sensors: list[Name] | None = None

    @model_validator(mode="after")
    def _check(self) -> FalseTargets:
        if not self.density > 0:
            raise ValueError("density must be > 0 (clutter objects per area, e.g. 4 /km^2)")
        if not self.max_range > 0:
            raise ValueError("max_range must be > 0")
        return self


def _pointed(sensor: Any) -> bool:
    return sensor.look_at is not None or (
        sensor.azimuth is not None and sensor.depression is not None
    )


NO_FALSE_TARGET_SENSORS = (
    "false_targets.sensors: an empty list names no sensor, so none would report false targets; "
    "name at least one sensor, or leave sensors out for every sensor with a field of view (or "
    "remove the [false_targets] table)"
)
"""The problem with an empty ``false_targets.sensors``: it names no sensor, so no false target
would ever be drawn, without a word."""


def false_target_problems(scenario: Any) -> list[str]:
    """What is wrong with a scenario's ``[false_targets]`` table, each problem located.

    ``false_targets.sensors`` must name sensors of the scenario, at least one, each with a
    field of view (``pixels``) and a pointing (``look_at``, or ``azimuth`` and ``depression``),
    once; without ``sensors``, at least one sensor must have a field of view.

    Parameters
    ----------
    scenario : Scenario

    Returns
    -------
    list of str
        Empty where there is no table or nothing is wrong.
    """
    table = getattr(scenario, "false_targets", None)
    if table is None:
        return []
    sensors = {s.name: s for s in scenario.sensors}
    if table.sensors is None:
        if not any(s.pixels is not None for s in scenario.sensors):
            return [
                "false_targets: no sensor has a field of view (pixels = [width, height]), so "
                "none can report false targets; give one pixels and a pointing"
            ]
        return []
    if not table.sensors:
        return [NO_FALSE_TARGET_SENSORS]
    problems = []
    seen: set[str] = set()
    for k, name in enumerate(table.sensors):
        where = f"false_targets.sensors[{k}]"
        sensor = sensors.get(name)
        if name in seen:
            problems.append(f"{where}: {name!r} is listed twice")
        elif sensor is None:
            problems.append(
                f"{where}: unknown sensor {name!r}; the sensors are: {', '.join(sensors)}"
            )
        elif sensor.pixels is None:
            problems.append(
                f"{where}: sensor {name!r} has no field of view (give pixels = [width, height] "
                "and a pointing); false targets are drawn inside a field of view"
            )
        elif not _pointed(sensor):
            problems.append(
                f"{where}: sensor {name!r} is not pointed (give look_at, or azimuth and "
                "depression); false targets are drawn inside its field of view on the ground"
            )
        seen.add(name)
    return problems


class TimeGrid(_Strict):
    """Evaluation times: ``start`` to ``stop`` inclusive every ``step``; ``hour``, the local
    (solar) hour of day at ``start`` [h], a plain number in [0, 24) (6.5 is 06:30), which sets
    the temperatures given as a daily cycle (:class:`DailyCycle`). They are the cycle's at that
    hour, held over the whole run: a run of minutes does not see the day move (a study over the
    day runs one scenario per hour)."""

    start: Time = 0.0
    stop: Time = 0.0
    step: Time = 1.0
    hour: HourOfDay | None = None

    @model_validator(mode="after")
    def _check(self) -> TimeGrid:
        if not self.step > 0:
            raise ValueError("step must be > 0 s")
        if self.stop < self.start:
            raise ValueError("stop must not be before start")
        return self

    @property
    def count(self) -> float:
        """How many times the grid holds, counted without building it (a float, so that a
        grid too large to build still has a size; +inf where the span over the step
        overflows)."""
        steps = (self.stop - self.start) / self.step
        return math.floor(steps + 1e-9) + 1.0 if math.isfinite(steps) else math.inf

    def times(self) -> Any:
        """The times [s], after checking that they fit in memory."""
        check_size(self.count, 8, f"the time grid ({self.describe()})", _GRID_ADVICE)
        return self.start + self.step * np.arange(int(self.count))

    def describe(self) -> str:
        """The grid in the file's words, for messages."""
        return f"time.step {self.step:g} s from {self.start:g} s to {self.stop:g} s"


class Scenario(_Strict):
    """A whole scene. See the module docstring and ``examples/`` for files."""

    name: str = ""
    sensors: Annotated[list[Sensor], Field(min_length=1)]
    targets: Annotated[list[Target], Field(min_length=1)]
    background: Background = Background()
    atmosphere: Atmosphere = Atmosphere()
    model: ModelChoices = ModelChoices()
    time: TimeGrid = TimeGrid()
    false_targets: FalseTargets | None = None
    terrain: Elevation | None = None

    @model_validator(mode="after")
    def _check(self) -> Scenario:
        problems = self.problems()
        if problems:
            # Every problem of the whole scene at once, each located, one per line (split
            # again by the error formatter).
            raise ValueError("\n".join(problems))
        # Valid, but maybe a unit slip (a 100 m lens): warned, never refused.
        emit(plausibility_warnings(self))
        return self

    def problems(self) -> list[str]:
        """What is wrong across tables (names, the sensors' needs, image boxes), each located."""
        problems = []
        for what, items in (("sensor", self.sensors), ("target", self.targets)):
            counts = Counter(item.name for item in items)
            duplicates = sorted(n for n, count in counts.items() if count > 1)
            if duplicates:
                problems.append(
                    f"{what}s: {what} names must be unique; repeated: {', '.join(duplicates)}"
                )
        for kind in dict.fromkeys(s.type for s in self.sensors):
            problems += get_sensor_type(kind).requirements(self)
        problems += [
            f'sensors[{k}].mrtd: an MRTD curve is a thermal sensor\'s (type = "thermal"); '
            f"a {s.type} sensor's resolution is its own"
            for k, s in enumerate(self.sensors)
            if s.mrtd is not None and s.type != "thermal"
        ]
        problems += _resolution_problems(self)
        problems += _foliage_problems(self)
        problems += _daily_cycle_problems(self)
        if self.false_targets is not None:
            problems += false_target_problems(self)
        terrain = self.terrain
        if terrain is not None and Path(terrain.elevation).suffix.lower() == ".npy":
            problems += [
                f"terrain.{key}: a .npy elevation grid needs its {key} ({what})"
                for key, what in (
                    ("spacing", 'the distance between posts, e.g. "30 m"'),
                    ("origin", 'east and north of post [0, 0], e.g. ["0 m", "0 m"]'),
                )
                if getattr(terrain, key) is None
            ]
        image = self.background.image is not None
        for k, target in enumerate(self.targets):
            if image and target.image_box is None:
                problems.append(
                    f"targets[{k}].image_box: background.image needs an image_box for every "
                    "target (where the target is in the image)"
                )
            elif not image and target.image_box is not None:
                problems.append(
                    f"targets[{k}].image_box: an image_box is a box in background.image; give "
                    "the image"
                )
        return problems

    def _cycled(self) -> list[tuple[str, Any]]:
        """Each item whose temperature is a daily cycle, with its location."""
        items: list[tuple[str, Any]] = [
            (f"targets[{k}].temperature", t) for k, t in enumerate(self.targets)
        ]
        items.append(("background.temperature", self.background))
        if self.background.terrain is not None:
            items += [
                (f"background.terrain.classes[{k}].temperature", c)
                for k, c in enumerate(self.background.terrain.classes)
            ]
        return [(where, item) for where, item in items if isinstance(item.temperature, DailyCycle)]

    def temperature(self, item: Target | Background | TerrainClassSpec) -> float | None:
        """The temperature [K] of a target, the background or a terrain class of this scenario,
        at the hour of day of its start (``time.hour``) and held over the run: a plain one as
        given, a daily cycle's at the hour (:func:`held_temperature`); ``None`` where none is
        given.

        Examples
        --------
        >>> from targetacq.scenario.schema import Scenario
        >>> scenario = Scenario.model_validate({
        ...     "sensors": [{"name": "ir", "band": "lwir", "ifov": 1e-4, "position": (0, 0, 10)}],
        ...     "targets": [{"name": "truck", "dimensions": (7, 2.5, 3), "position": (2000, 0, 0),
        ...                  "temperature": {"mean": 295, "amplitude": 8, "peak_hour": 14}}],
        ...     "background": {"temperature": 290}, "time": {"hour": 2}})
        >>> scenario.temperature(scenario.targets[0]), scenario.temperature(scenario.background)
        (287.0, 290.0)
        """
        return held_temperature(item.temperature, self.time.hour)

    def held(self) -> Scenario:
        """This scenario with every daily cycle replaced by its temperature at ``time.hour``
        (:meth:`temperature`): plain temperatures, held over the run, as the core compiles them
        (:func:`targetacq.core.compile.compile_scenario`). Itself where no temperature is a
        cycle.

        Examples
        --------
        >>> from targetacq.scenario.schema import Scenario
        >>> scenario = Scenario.model_validate({
        ...     "sensors": [{"name": "ir", "band": "lwir", "ifov": 1e-4, "position": (0, 0, 10)}],
        ...     "targets": [{"name": "truck", "dimensions": (7, 2.5, 3), "position": (2000, 0, 0),
        ...                  "temperature": {"mean": 295, "amplitude": 8, "peak_hour": 14}}],
        ...     "background": {"temperature": {"mean": 290, "amplitude": 2}},
        ...     "time": {"hour": 8}})
        >>> held = scenario.held()
        >>> round(held.targets[0].temperature, 9), round(held.background.temperature, 9)
        (295.0, 290.0)
        >>> held.held() is held
        True
        """
        if not self._cycled():
            return self

        def plain(item: Any) -> Any:
            if not isinstance(item.temperature, DailyCycle):
                return item
            return item.model_copy(update={"temperature": self.temperature(item)})

        background = plain(self.background)
        terrain = background.terrain
        if terrain is not None:
            classes = [plain(c) for c in terrain.classes]
            background = background.model_copy(
                update={"terrain": terrain.model_copy(update={"classes": classes})}
            )
        return self.model_copy(
            update={"targets": [plain(t) for t in self.targets], "background": background}
        )


def _daily_cycle_problems(scenario: Scenario) -> list[str]:
    """A temperature's daily cycle needs the scenario's hour of day."""
    if scenario.time.hour is not None:
        return []
    return [
        f"{where}: a daily cycle needs the hour of day of the scenario's start: give [time] "
        "hour (the local solar hour, in [0, 24), e.g. hour = 6.5), or a plain temperature"
        for where, _ in scenario._cycled()
    ]


def _resolution_problems(scenario: Scenario) -> list[str]:
    """What the resolution model (``model.resolution_model``) cannot run with, each located:
    the TTP metric is a thermal imager's with its aperture; an MRTD curve is the ``mrtd`` model;
    the TTP inputs mean nothing to another model."""
    name = scenario.model.resolution_model
    problems = []
    for k, s in enumerate(scenario.sensors):
        if s.mrtd is not None and name not in (None, "mrtd"):
            problems.append(
                f'sensors[{k}].mrtd: an MRTD curve gives resolution_model = "mrtd", not {name!r}; '
                "leave the curve out, or the resolution model"
            )
        if name != "ttp":
            problems += [
                f'sensors[{k}].{field}: is read by resolution_model = "ttp" only (model table)'
                for field in TTP_SENSOR_FIELDS
                if getattr(s, field) is not None
            ]
        elif s.type != "thermal":
            problems.append(
                f'sensors[{k}].type: resolution_model = "ttp" is a thermal imager\'s here (its '
                f"NETD and ΔT in the TTP metric); a {s.type} sensor cannot use it: leave the "
                "sensor out or choose another resolution model"
            )
        elif s.aperture is None:
            problems.append(
                f'sensors[{k}].aperture: resolution_model = "ttp" needs the optics\' aperture '
                '(its diffraction MTF): give aperture (e.g. "50 mm") or f_number with focal_length'
            )
    if name != "ttp" and scenario.atmosphere.cn2 is not None:
        problems.append('atmosphere.cn2: is read by resolution_model = "ttp" only (model table)')
    if name == "mrtd" and all(s.mrtd is None for s in scenario.sensors):
        problems.append(
            'model.resolution_model: "mrtd" needs a thermal sensor\'s MRTD curve (sensors[].mrtd)'
        )
    if name == "ttp":
        problems += [
            f"targets[{k}].criterion: criterion {t.criterion!r} gives Johnson's N50s, and "
            f'resolution_model = "ttp" the TTP metric\'s V: choose one of '
            f"{', '.join(V50_CRITERIA)}"
            for k, t in enumerate(scenario.targets)
            if t.criterion is not None and t.criterion not in V50_CRITERIA
        ]
    return problems


def _foliage_problems(scenario: Scenario) -> list[str]:
    """Foliage (§6.8) is a transmittance in an imaging sensor's band: a scene with a radar or a
    laser radar takes none (their paths are their own)."""
    shaded = [k for k, t in enumerate(scenario.targets) if t.foliage is not None]
    active = [
        (k, s, get_sensor_type(s.type).kind)
        for k, s in enumerate(scenario.sensors)
        if get_sensor_type(s.type).kind != "imaging"
    ]
    if not shaded or not active:
        return []
    k_s, sensor, kind = active[0]
    return [
        f"targets[{k}].foliage: foliage (a transmittance in an imaging sensor's band, §6.8) "
        f"applies to imaging sensors only; target {scenario.targets[k].name!r} is seen by "
        f"sensors[{k_s}] {sensor.name!r}, a {kind.replace('_', ' ')}: leave foliage out, or "
        "evaluate the imaging sensors in a scenario of their own"
        for k in shaded
    ]


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
        current = _model_in(annotation) or annotation
    return current


def _model_in(annotation: Any) -> Any:
    """The first pydantic model class inside an annotation (through optionals, unions, lists
    and ``Annotated``), or None."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    for arg in get_args(annotation):
        found = _model_in(arg)
        if found is not None:
            return found
    return None


def _location(loc: Sequence[Any]) -> str:
    text = ""
    for part in loc:
        if isinstance(part, int):
            text += f"[{part}]"
        else:
            text += ("." if text else "") + str(part)
    return text or "scenario"


def _number_text(value: Any) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


def _count(ctx: Mapping[str, Any]) -> str:
    return str(ctx.get("actual_length", "?"))


def _message(detail: Mapping[str, Any], loc: Sequence[Any]) -> str:
    """One pydantic error in the file's words (TOML vocabulary, no Python syntax)."""
    kind, ctx = detail["type"], detail.get("ctx") or {}
    given = detail.get("input")
    if kind == "extra_forbidden":
        key = str(loc[-1])
        valid = list(_fields_of(_model_at(loc[:-1])))
        close = get_close_matches(key, valid, 1)
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        return f"unknown key {key!r}{hint}; valid keys: {', '.join(valid)}"
    if kind == "missing":
        return (
            "missing item: the list is too short"
            if loc and isinstance(loc[-1], int)
            else ("required key missing")
        )
    bounds = {
        "greater_than": ">",
        "greater_than_equal": ">=",
        "less_than": "<",
        "less_than_equal": "<=",
    }
    if kind in bounds:
        limit = next(iter(ctx.values()))
        return f"must be {bounds[kind]} {_number_text(limit)}; got {_show(given)}"
    plain = {
        "string_type": f"must be text in quotes; got {_show(given)}",
        "list_type": f"must be a list [...]; got {_show(given)}",
        "tuple_type": f"must be a list [...]; got {_show(given)}",
        "model_type": "must be a table",
        "model_attributes_type": "must be a table",
        "dict_type": "must be a table",
        "finite_number": f"must be finite; got {_show(given)}",
        "recursion_loop": "nested too deeply",
        "literal_error": f"must be {ctx.get('expected', '')}; got {_show(given)}",
        "too_short": f"needs at least {ctx.get('min_length')} item(s); got {_count(ctx)}",
        "too_long": f"takes at most {ctx.get('max_length')} items; got {_count(ctx)}",
    }
    if kind in plain:
        return plain[kind]
    message = str(detail["msg"]).removeprefix("Value error, ")
    field = next((p for p in reversed(loc) if isinstance(p, str)), None)
    if field is not None:  # quantity messages name their field; the location already does
        message = message.removeprefix(f"{field}: ")
    return message


def _problems(error: ValidationError) -> list[str]:
    """Every error of a validation, each located (``table[index].key: what``)."""
    problems: list[str] = []
    for detail in error.errors():
        loc = [
            p
            for p in detail["loc"]
            if not (isinstance(p, str) and (p.startswith("function-") or p in _UNION_TAGS))
        ]
        message = _message(detail, loc)
        if not loc and detail["type"] == "value_error":
            problems += message.splitlines()  # Scenario.problems(): located already
        else:
            problems.append(f"{_location(loc)}: {message}")
    return list(dict.fromkeys(problems))


def parse_scenario(
    data: dict[str, Any], source: str = "scenario", *, strict_units: bool = True
) -> Scenario:
    """Validate a scenario given as nested dictionaries (as read from TOML).

    Units are strict, as in a file: every quantity is a string with its unit (or a pint
    ``Quantity``); a bare number where a unit is needed is an error saying which unit to add.
    With ``strict_units=False`` a bare number is taken as SI, as Python callers give it (the
    messages are the same located ones); or build :class:`Scenario` directly (or call
    ``Scenario.model_validate``) to give SI numbers.

    A valid value beyond what any real sensor or scene has (a unit slip: ``"100 m"`` for a
    focal length) is not an error: it is emitted as a
    :class:`targetacq.scenario.plausibility.PlausibilityWarning`, located like the errors
    (``source: sensors[0].focal_length: ...``).

    Raises
    ------
    ScenarioError
        With every problem found, each located: ``source: table.key: what is wrong``.
    """
    try:
        with collected() as found:
            scenario = Scenario.model_validate(data, context={"strict_units": strict_units})
    except ValidationError as error:
        raise ScenarioError([f"{source}: {problem}" for problem in _problems(error)]) from None
    except RecursionError:
        raise ScenarioError(f"{source}: nested too deeply to be a scenario") from None
    emit([f"{source}: {message}" for message in found])  # located in the file, as errors are
    return scenario


def load_scenario(path: str | Path) -> Scenario:
    """Read and validate a scenario TOML file.

    The file is a regular file of at most :data:`targetacq.base.limits.MAX_INPUT_BYTES`, in UTF-8
    (a byte-order mark is allowed; :func:`targetacq.base.inputs.read_input_text`). Relative
    ``image`` and terrain ``map`` paths, the ``[terrain]`` ``elevation``, sensors' ``mrtd``
    curves and targets' ``signature_table`` files are taken from the file's folder.

    Raises
    ------
    ScenarioError
        Missing, unreadable or oversized file, a directory or a device, malformed or too deeply
        nested TOML (with its line and column), or an invalid scenario (every problem, each
        located).
    """
    source = Path(path)
    try:
        text = read_input_text(source, "scenario file")
    except ValueError as error:
        raise ScenarioError(str(error)) from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise ScenarioError(f"{source}: malformed TOML: {error}") from None
    except RecursionError:
        raise ScenarioError(f"{source}: malformed TOML: nested too deeply") from None
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
    relief = scenario.terrain
    if relief is not None and not Path(relief.elevation).is_absolute():
        relief = relief.model_copy(update={"elevation": str(source.parent / relief.elevation)})
        scenario = scenario.model_copy(update={"terrain": relief})
    if any(s.mrtd is not None and not Path(s.mrtd).is_absolute() for s in scenario.sensors):
        sensors = [
            s.model_copy(update={"mrtd": str(source.parent / s.mrtd)})
            if s.mrtd is not None and not Path(s.mrtd).is_absolute()
            else s
            for s in scenario.sensors
        ]
        scenario = scenario.model_copy(update={"sensors": sensors})
    if any(_relative_file(t.signature_table) for t in scenario.targets):
        targets = [
            t.model_copy(update={"signature_table": str(source.parent / t.signature_table)})
            if isinstance(t.signature_table, str) and _relative_file(t.signature_table)
            else t
            for t in scenario.targets
        ]
        scenario = scenario.model_copy(update={"targets": targets})
    return scenario


def _relative_file(value: Any) -> bool:
    """Whether ``value`` names a file by a relative path."""
    return isinstance(value, str) and not Path(value).is_absolute()
