"""Compile a scenario, once, into the core's records.

Everything that does not change with the positions is computed here: resolution per sensor
(through its sensor type), field of view, the path's extinction in each sensor's band, the
signature of each sensor-target pair (contrast, SCR from a clutter measure, an image or nothing)
and each target's criterion. File reads (a background image, a terrain map, the ``[terrain]``
elevation model, a sensor's MRTD curve) happen here and nowhere else. The scripted paths of a
scenario are turned into positions by :func:`scenario_positions`.

Before anything is computed, every problem that would stop the scenario from running is
collected (:func:`check_runnable`): files that cannot be read, image boxes outside the image,
terrain class indices that name no class, a time grid (or a terrain map) too large for memory.
They are raised together, each located, as one :class:`targetacq.scenario.schema.ScenarioError`; the
``validate`` command reports the same list, so a scenario it accepts compiles.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np

from targetacq.acquisition.criteria import Criterion, get_criterion
from targetacq.base.arrays import Array
from targetacq.base.constants import SPEED_OF_LIGHT
from targetacq.base.limits import BYTES_PER_EVALUATION, check_size
from targetacq.core.cases import get_resolution_model
from targetacq.core.records import (
    AspectArrays,
    LaserArrays,
    ModelChoices,
    MrtdArrays,
    PathArrays,
    RadarArrays,
    SceneArrays,
    SensorArrays,
    SignatureArrays,
    TargetArrays,
    TtpArrays,
)
from targetacq.physics import atmosphere, geometry, radiometry
from targetacq.physics.aspect import AspectTable
from targetacq.physics.clutter import signal_to_clutter_ratio
from targetacq.physics.line_of_sight import STANDARD_K, ElevationModel, read_elevation
from targetacq.physics.named_atmospheres import NamedBandPath
from targetacq.physics.ttp import TtpSystem
from targetacq.scenario.schema import ScenarioError
from targetacq.sensors import Signature, get_sensor_type

__all__ = [
    "CompiledScenario",
    "TerrainArrays",
    "check_runnable",
    "compile_scenario",
    "scenario_positions",
    "scenario_velocities",
    "sensor_rows",
]

TASKS = ("detection", "recognition", "identification")


@dataclass(frozen=True)
class TerrainArrays:
    """A terrain map and its classes' signals per sensor (host-side, NumPy only).

    Attributes
    ----------
    terrain : targetacq.physics.terrain.TerrainMap
    mean : numpy.ndarray (n_s, K)
        Mean signal of each class in each sensor's band [W/m²].
    variance : numpy.ndarray (n_s, K)
        Signal variance of each class at its reference resolution [W²/m⁴].
    resolution : numpy.ndarray (K,)
        Reference resolution of each class's variance [m].
    window : numpy.ndarray (n_g,)
        Side of the window around each target [m]: the 3 × 3 cells of twice the target's
        smallest dimension (Fig. 3.6).
    """

    terrain: Any
    mean: Any
    variance: Any
    resolution: Any
    window: Any


@dataclass(frozen=True)
class CompiledScenario:
    """A scenario compiled into the core's records.

    Attributes
    ----------
    scene : SceneArrays
    criteria : tuple of Criterion
        Each target's criterion.
    terrain : TerrainArrays or None
    elevation : targetacq.physics.line_of_sight.ElevationModel or None
        The ``[terrain]`` relief that the lines of sight cross (host-side, NumPy only).
    earth_radius_factor : float
        Its effective Earth-radius factor ``k`` [1] (4/3: standard refraction).
    """

    scene: SceneArrays
    criteria: tuple[Criterion, ...]
    terrain: TerrainArrays | None
    elevation: ElevationModel | None = None
    earth_radius_factor: float = STANDARD_K


def _criteria(scenario: Any) -> tuple[Criterion, ...]:
    model = scenario.model
    default = get_criterion(
        dict(zip(TASKS, model.n50, strict=True)) if model.n50 is not None else model.criterion
    )
    return tuple(
        default if t.criterion is None else get_criterion(t.criterion) for t in scenario.targets
    )


def _n50_rows(criteria: tuple[Criterion, ...]) -> np.ndarray:
    """Each target's N50s, (n_g, 3): a row per distinct criterion, shared by its targets."""
    rows: dict[int, list[float]] = {}
    for c in criteria:
        if id(c) not in rows:
            rows[id(c)] = [c.n50(task) for task in TASKS]
    return np.array([rows[id(c)] for c in criteria], dtype=float).reshape(-1, 3)


def _owned_rows(scenario: Any) -> list[tuple[str, Any]]:
    """Each row of the array core with the name of the scenario sensor it comes from."""
    return [(s.name, row) for s in scenario.sensors for row in get_sensor_type(s.type).rows(s)]


def sensor_rows(scenario: Any) -> list[Any]:
    """The rows of the array core a scenario's sensors become, in order: each sensor itself,
    a colour camera one row per band (:attr:`targetacq.sensors.SensorType.rows`)."""
    return [row for _, row in _owned_rows(scenario)]


def _band_extinction(s: Any, atm: Any, **weather: Any) -> float:
    """The path's extinction in a sensor's band [Np/m]: 0 for a radar (the optical weather does
    not apply at its wavelength; its rain is in :class:`RadarArrays`)."""
    if get_sensor_type(s.type).kind == "radar":
        return 0.0
    return float(atmosphere.extinction_for_band(s.limits, **weather))


def _sensors(
    scenario: Any, sensors: list[Any], groups: tuple[str, ...], seen: list[Signature]
) -> SensorArrays:
    atm = scenario.atmosphere
    half = np.full((len(sensors), 2), np.nan)
    look_at = np.full((len(sensors), 3), np.nan)
    pointing = np.full((len(sensors), 2), np.nan)
    for k, s in enumerate(sensors):
        if s.field_of_view is not None:
            half[k] = np.tan(np.asarray(s.field_of_view) / 2.0)
        if s.look_at is not None:
            look_at[k] = s.look_at
        if s.azimuth is not None and s.depression is not None:
            pointing[k] = s.azimuth, s.depression
    named = atm.named_path() is not None  # then each band's d(R) is in PathArrays instead
    extinction = np.array(
        [
            0.0
            if named
            else _band_extinction(
                s,
                atm,
                extinction=atm.extinction,
                obscurant=atm.obscurant,
                visibility=atm.visibility,
                convention=atm.visibility_convention,
            )
            for s in sensors
        ]
    )
    segment_extinction = np.array(
        [
            [
                _band_extinction(s, atm, extinction=seg.extinction, obscurant=seg.obscurant)
                for seg in atm.segments
            ]
            for s in sensors
        ]
    ).reshape(len(sensors), len(atm.segments))
    noise = np.array(
        [
            get_sensor_type(s.type).noise_equivalent(s, sig)
            for s, sig in zip(sensors, seen, strict=True)
        ],
        dtype=float,
    ).reshape(len(sensors))
    return SensorArrays(
        cycle=np.array([get_sensor_type(s.type).cycle_angle(s) for s in sensors]),
        ifov=np.array([s.pixel_ifov for s in sensors]),
        half_tangents=half,
        look_at=look_at,
        pointing=pointing,
        extinction=extinction,
        segment_extinction=segment_extinction,
        noise_equivalent=noise,
        names=tuple(s.name for s in sensors),
        types=tuple(s.type for s in sensors),
        pointed=tuple(
            s.look_at is not None or (s.azimuth is not None and s.depression is not None)
            for s in sensors
        ),
        has_noise=bool(np.any(noise > 0)),
        path_contrast=np.array(
            [
                get_sensor_type(s.type).path_contrast(s, sig)
                for s, sig in zip(sensors, seen, strict=True)
            ],
            dtype=float,
        ).reshape(len(sensors)),
        groups=groups if len(sensors) > len(scenario.sensors) else (),
        quantisation_step=_quantisation_steps(sensors),
        sky_to_ground=_sky_to_ground(scenario, sensors),
    )


def _quantisation_steps(sensors: list[Any]) -> np.ndarray | None:
    """Each row's digitiser step [W/m²], 0 where it has none; None where no row has one."""
    steps = [_quantisation_step(s) for s in sensors]
    if all(step is None for step in steps):
        return None
    return np.array([0.0 if step is None else step for step in steps], dtype=float)


def _quantisation_step(sensor: Any) -> float | None:
    """A row's digitiser step [W/m²]: the step given, or that of its bits over its span
    (:func:`targetacq.physics.radiometry.quantisation_step`); None for none."""
    if sensor.quantisation_step is not None:
        return float(sensor.quantisation_step)
    if sensor.adc_bits is not None:
        return float(radiometry.quantisation_step(sensor.adc_bits, sensor.adc_span))
    return None


def _targets(scenario: Any, criteria: tuple[Criterion, ...]) -> TargetArrays:
    targets = scenario.targets
    return TargetArrays(
        dimensions=np.array([t.dimensions for t in targets], dtype=float).reshape(-1, 3),
        visible_fraction=np.array([t.visible_fraction for t in targets], dtype=float),
        heading=np.array([t.heading for t in targets], dtype=float),
        n50=_n50_rows(criteria),
        names=tuple(t.name for t in targets),
        hot_spot=tuple(bool(t.hot_spot) for t in targets),
        moving=tuple(bool(t.moving) for t in targets),
        foliage=_foliage(scenario),
        **_graded_cues(targets),
    )


def _graded_cues(targets: Any) -> dict[str, Any]:
    """The targets' graded cues as :class:`TargetArrays` fields: the hot spots' ratios (0 where
    none) and sizes (NaN where none), None where no target gives one; the graded-motion flags,
    empty where no target has one (a scene without graded cues is compiled as before)."""
    out: dict[str, Any] = {}
    if any(t.hot_spot_ratio is not None for t in targets):
        out["hot_spot_ratio"] = np.array(
            [0.0 if t.hot_spot_ratio is None else t.hot_spot_ratio for t in targets], dtype=float
        )
    if any(t.hot_spot_size is not None for t in targets):
        out["hot_spot_size"] = np.array(
            [np.nan if t.hot_spot_size is None else t.hot_spot_size for t in targets], dtype=float
        )
    if any(t.graded_motion for t in targets):
        out["graded_motion"] = tuple(bool(t.graded_motion) for t in targets)
    return out


def _sky_to_ground(scenario: Any, sensors: list[Any]) -> np.ndarray | None:
    """Each row's sky-to-ground ratio K: the background's for the rows whose type's contrast is
    reduced by the path's airlight (TV, colour), 1 for the others; None where none is given."""
    ratio = scenario.background.sky_to_ground
    if ratio is None:
        return None
    return np.array(
        [float(ratio) if get_sensor_type(s.type).airlight else 1.0 for s in sensors], dtype=float
    )


def _foliage(scenario: Any) -> np.ndarray | None:
    """Each target's foliage transmittance (n_g,), 1 where it has none; None where none has."""
    given = [t.foliage for t in scenario.targets]
    if all(f is None for f in given):
        return None
    return np.array([1.0 if f is None else f for f in given], dtype=float)


def _named_depths(scenario: Any) -> tuple[tuple[float, ...], np.ndarray | None]:
    """A named atmosphere's table ranges [m] and each sensor row's optical depths there (0 for
    a radar: the optical weather does not apply at its wavelength); ((), None) without one."""
    named = scenario.atmosphere.named_path()
    if named is None:
        return (), None
    rows: list[tuple[float, ...] | None] = []
    ranges: tuple[float, ...] = ()
    for s in sensor_rows(scenario):
        kind = get_sensor_type(s.type).kind
        if kind == "radar":
            rows.append(None)
            continue
        if kind == "laser_radar":
            raise ValueError(
                f"sensor {s.name!r}: a laser radar takes atmosphere.extinction, not a named "
                "atmosphere (model, aerosol)"
            )
        try:
            ranges, depths = NamedBandPath(named, s.limits).nodes
        except ValueError as error:
            raise ValueError(f"sensor {s.name!r}: {error}") from error
        rows.append(depths)
    if not ranges:  # radars only
        return (), None
    return ranges, np.array([[0.0] * len(ranges) if r is None else r for r in rows], dtype=float)


def _path(scenario: Any) -> PathArrays:
    atm = scenario.atmosphere
    named_ranges, named_depths = _named_depths(scenario)
    return PathArrays(
        segment_length=np.array([seg.length for seg in atm.segments], dtype=float),
        cloud_center=np.array([c.center for c in atm.clouds], dtype=float).reshape(-1, 3),
        cloud_radius=np.array([c.radius for c in atm.clouds], dtype=float),
        cloud_extinction=np.array([c.extinction for c in atm.clouds], dtype=float),
        # Foliage in front of a target attenuates the path too: its noise counts (§6.8).
        attenuates=bool(atm.present) or _foliage(scenario) is not None,
        named_ranges=named_ranges,
        named_depths=named_depths,
    )


def _image_scr(scenario: Any, pixels: np.ndarray) -> np.ndarray:
    """SCR of each target measured in the background image (Eqs. (3.12)-(3.15))."""
    from targetacq.physics.clutter import image_clutter

    return np.asarray(image_clutter(pixels, [t.image_box for t in scenario.targets]).scr)


def _signature(
    scenario: Any, sensors: list[Any], signatures: list[Signature], pixels: Any
) -> SignatureArrays:
    bg = scenario.background
    shape = (len(sensors), len(scenario.targets))
    contrast, target = np.empty(shape), np.empty(shape)
    clutter = np.full(shape, np.nan)
    for k, seen in enumerate(signatures):
        contrast[k] = np.abs(seen.target - seen.background)
        target[k] = seen.target
        if seen.clutter is not None:
            clutter[k] = seen.clutter
    scr = None
    if bg.scr is not None:
        scr = np.full(shape, bg.scr)
    elif pixels is not None:
        scr = np.broadcast_to(_image_scr(scenario, pixels), shape).copy()
    elif bg.clutter_std is not None:
        scr = np.asarray(signal_to_clutter_ratio(contrast, 0.0, clutter))
    kinds = [get_sensor_type(s.type).kind for s in sensors]
    if all(kind == "imaging" for kind in kinds):
        return SignatureArrays(contrast=contrast, target=target, scr=scr)
    # Radars and laser radars have clutter measures of their own: the rows differ.
    imaging_clutter = scr is not None or bg.terrain is not None
    rows = tuple(kind != "imaging" or imaging_clutter for kind in kinds)
    # +inf where an imager has no clutter measure (as an imaging-only scene reports it).
    full = np.full(shape, np.inf) if scr is None else np.array(scr, dtype=float)
    for k, (s, kind) in enumerate(zip(sensors, kinds, strict=True)):
        if kind == "laser_radar":
            full[k] = _relief_scr(scenario, s)
        elif kind == "radar":
            full[k] = np.nan  # per position (the resolution cell grows with range)
    return SignatureArrays(contrast=contrast, target=target, scr=full, clutter_rows=rows)


def _relief_scr(scenario: Any, sensor: Any) -> np.ndarray:
    """A laser radar's 3-D SCR of every target
    (:func:`targetacq.physics.laser_radar_equation.relief_scr`)."""
    from targetacq.physics import laser_radar_equation as laser_radar

    heights = np.array([t.dimensions[2] for t in scenario.targets], dtype=float)
    visible = np.array([t.visible_fraction for t in scenario.targets], dtype=float)
    return np.asarray(
        laser_radar.relief_scr(
            laser_radar.relief_seen(heights, visible),
            scenario.background.relief_std,
            laser_radar.range_resolution(sensor.laser.timing),
        ),
        dtype=float,
    )


def _radar(scenario: Any, sensors: list[Any]) -> RadarArrays | None:
    from targetacq.physics import radar_equation as radar

    rows = tuple(k for k, s in enumerate(sensors) if get_sensor_type(s.type).kind == "radar")
    if not rows:
        return None
    specs = [sensors[k].radar for k in rows]
    rain = scenario.atmosphere.rain_rate
    return RadarArrays(
        constant=np.array(
            [
                radar.radar_constant(
                    r.power,
                    r.gain,
                    SPEED_OF_LIGHT / r.frequency,
                    r.pulse_length,
                    r.noise_figure,
                    r.losses,
                )
                for r in specs
            ],
            dtype=float,
        ),
        beamwidth=np.array([r.beamwidth for r in specs], dtype=float),
        pulse_length=np.array([r.pulse_length for r in specs], dtype=float),
        extinction=np.array(
            [
                0.0
                if rain is None
                else float(radar.rain_extinction(rain * 3.6e6, r.frequency, r.polarization))
                for r in specs
            ],
            dtype=float,
        ),
        sigma0=np.full(len(rows), float(scenario.background.sigma0)),
        false_alarm=np.array([r.false_alarm for r in specs], dtype=float),
        pulses=np.array([r.pulses for r in specs], dtype=float),
        cells50=np.array([[r.recognition_cells, r.identification_cells] for r in specs]),
        rows=rows,
        detectors=tuple(r.detector for r in specs),
    )


def _laser(scenario: Any, sensors: list[Any]) -> LaserArrays | None:
    rows = tuple(k for k, s in enumerate(sensors) if get_sensor_type(s.type).kind == "laser_radar")
    if not rows:
        return None
    specs = [sensors[k].laser for k in rows]
    return LaserArrays(
        power=np.array([lz.power for lz in specs], dtype=float),
        aperture_area=np.array([np.pi * lz.aperture**2 / 4.0 for lz in specs], dtype=float),
        efficiency=np.array([lz.efficiency for lz in specs], dtype=float),
        nep=np.array([lz.nep for lz in specs], dtype=float),
        rows=rows,
    )


def _terrain(scenario: Any, grid: Any) -> TerrainArrays | None:
    from targetacq.physics.terrain import TerrainClass, TerrainMap

    bg = scenario.background
    if bg.terrain is None:
        return None
    spec = bg.terrain
    classes = [TerrainClass(c.name, 0.0, 0.0, c.resolution) for c in spec.classes]
    terrain = TerrainMap(classes, grid, spec.cell_size, spec.origin)
    mean = np.empty((len(scenario.sensors), len(spec.classes)))
    variance = np.empty_like(mean)
    for k, s in enumerate(scenario.sensors):
        kind = get_sensor_type(s.type)
        if kind.class_signature is None:
            raise ScenarioError(f"sensors[{k}].type: a {s.type} sensor cannot use a terrain map")
        mean[k], variance[k] = kind.class_signature(s, bg, spec.classes)
    return TerrainArrays(
        terrain=terrain,
        mean=mean,
        variance=variance,
        resolution=np.array([c.resolution for c in spec.classes]),
        window=np.array([6.0 * min(t.dimensions) for t in scenario.targets]),
    )


def _background_image(scenario: Any, problems: list[str]) -> np.ndarray | None:
    """The background image as one channel, and each target's box checked against it."""
    from targetacq.io.images import read_image
    from targetacq.physics.clutter import as_boxes, gray

    bg = scenario.background
    if bg.image is None:
        return None
    try:
        image = read_image(bg.image)
    except ValueError as error:
        problems.append(f"background.image: {error}")
        return None
    try:
        pixels = np.asarray(gray(image, bg.channel))
    except ValueError as error:
        problems.append(f"background.channel: {error}")
        return None
    for k, target in enumerate(scenario.targets):
        try:
            as_boxes(target.image_box, pixels.shape)
        except ValueError as error:  # the message counts boxes from 0: here there is one
            problems.append(f"targets[{k}].image_box: {str(error).replace('box 0 ', 'box ', 1)}")
    return pixels


def _class_map(scenario: Any, problems: list[str]) -> np.ndarray | None:
    """The terrain map's class indices, checked against the classes and the memory."""
    from targetacq.physics.terrain import read_class_map

    spec = scenario.background.terrain
    if spec is None:
        return None
    try:
        grid = read_class_map(spec.map)
    except ValueError as error:
        problems.append(f"background.terrain.map: {error}")
        return None
    count = len(spec.classes)
    wrong = np.argwhere((grid < 0) | (grid >= count))
    if wrong.size:
        row, col = (int(i) for i in wrong[0])
        problems.append(
            f"background.terrain.map: class index {int(grid[row, col])} at row {row + 1}, "
            f"column {col + 1} names none of the {count} classes (0 to {count - 1}); "
            f"{len(wrong)} cell(s) like it"
        )
        return None
    rows, cols = grid.shape
    try:  # one summed-area table per class (targetacq.physics.terrain.TerrainMap)
        check_size(
            count * (rows + 1.0) * (cols + 1.0),
            8,
            f"the terrain map ({rows} x {cols} cells, {count} classes)",
            "use a coarser map (fewer cells) or fewer classes",
        )
    except ValueError as error:
        problems.append(f"background.terrain.map: {error}")
        return None
    return grid


def _off_the_elevation_model(scenario: Any, elevation: ElevationModel) -> list[str]:
    """A problem for each sensor and target whose scripted place (its position, or a waypoint:
    the grid is a rectangle, so a path between waypoints on it stays on it) is off the
    elevation model, where no line of sight can be traced (NaN in the evaluation)."""
    east_min, east_max, north_min, north_max = elevation.extent
    problems = []
    for table, items in (("sensors", scenario.sensors), ("targets", scenario.targets)):
        for k, item in enumerate(items):
            places = (
                [("position", item.position)]
                if item.waypoints is None
                else [(f"waypoints[{j}]", w.position) for j, w in enumerate(item.waypoints)]
            )
            for where, place in places:
                if place is None:
                    continue
                east, north = float(place[0]), float(place[1])
                if not (east_min <= east <= east_max and north_min <= north <= north_max):
                    problems.append(
                        f"{table}[{k}].{where}: ({east:g} m, {north:g} m) is off the elevation "
                        f"model (terrain.elevation covers east {east_min:g} to {east_max:g} m, "
                        f"north {north_min:g} to {north_max:g} m): no line of sight there"
                    )
                    break
    return problems


def _elevation(scenario: Any, problems: list[str]) -> ElevationModel | None:
    """The ``[terrain]`` elevation model read from its file; a file that cannot be read, or is
    not a grid, is a problem located at ``terrain.elevation``."""
    spec = scenario.terrain
    if spec is None:
        return None
    try:
        return read_elevation(spec.elevation, spec.spacing, spec.origin)
    except ValueError as error:
        problems.append(f"terrain.elevation: {error}")
        return None


def _mrtd_curves(scenario: Any, problems: list[str]) -> dict[str, Any]:
    """The sensors' MRTD curves read from their files, by sensor name; a file that cannot be
    read, or is not a curve, is a problem located at ``sensors[i].mrtd``."""
    from targetacq.physics.mrtd import MrtdCurve

    curves = {}
    for k, sensor in enumerate(scenario.sensors):
        if sensor.mrtd is None:
            continue
        try:
            curves[sensor.name] = MrtdCurve.from_csv(sensor.mrtd)
        except ValueError as error:
            problems.append(f"sensors[{k}].mrtd: {error}")
    return curves


def _aspect_tables(scenario: Any, problems: list[str]) -> dict[int, AspectTable]:
    """The targets' signature tables by target index: files read, tables written in the
    scenario converted; a file that cannot be read, or is not a table, and a table on a
    feature that reads one contrast per pair, are problems located at
    ``targets[j].signature_table``."""
    tables: dict[int, AspectTable] = {}
    for j, target in enumerate(scenario.targets):
        try:
            table = target.aspect_table()
        except ValueError as error:
            problems.append(f"targets[{j}].signature_table: {error}")
            continue
        if table is not None:
            tables[j] = table
    if not tables:
        return tables
    refused = [
        (f"sensors[{k}].{name}", why)
        for k, s in enumerate(scenario.sensors)
        for name, why in (
            ("quantisation_step", "its digitiser's test reads one contrast per pair"),
            ("mrtd", "the MRTD rows read one contrast per pair"),
        )
        if getattr(s, name, None) is not None
    ]
    if scenario.model.resolution_model == "ttp":
        refused.append(("model.resolution_model", "the TTP rows read one contrast per pair"))
    first = min(tables)
    problems += [
        f"targets[{first}].signature_table: not with {where} ({why}); leave one out"
        for where, why in refused
    ]
    return tables


def _table_temperatures(scenario: Any, tables: dict[int, AspectTable]) -> Any:
    """The scenario with each target that has a signature table and no temperature given the
    table's mean (its temperature where one number stands for the target: a hot spot's, a
    report's)."""
    missing = [j for j in tables if scenario.targets[j].temperature is None]
    if not missing:
        return scenario
    targets = list(scenario.targets)
    background = scenario.background.temperature
    for j in missing:
        mean = float(np.mean(tables[j].grid))
        if tables[j].quantity == "contrast":
            mean += float(background)
        targets[j] = targets[j].model_copy(update={"temperature": mean})
    return scenario.model_copy(update={"targets": targets})


def _aspect(
    scenario: Any,
    sensors: list[Any],
    signatures: list[Signature],
    tables: dict[int, AspectTable],
    static: SignatureArrays,
    pixels: Any,
) -> AspectArrays | None:
    """Each pair's contrast over the aspect (:class:`AspectArrays`) for the targets with
    signature tables: every table resampled on the union of the tables' nodes (exact: the
    bilinear interpolant of a table is bilinear within each cell of a finer grid), each node's
    temperature turned into a signal by the sensor type's own signature, as a target's one
    temperature is; ``static``, the scene's one contrast per pair, at the nodes of targets
    without a table. None without tables."""
    if not tables:
        return None
    from targetacq.physics.aspect import interpolate_aspect

    azimuth = np.unique(np.concatenate([t.azimuth for t in tables.values()]))
    elevation = np.unique(np.concatenate([t.elevation for t in tables.values()]))
    mesh_az, mesh_el = np.meshgrid(azimuth, elevation, indexing="ij")
    n_s, n_g = len(sensors), len(scenario.targets)
    contrast = np.broadcast_to(
        static.contrast[:, :, None, None], (n_s, n_g, azimuth.size, elevation.size)
    ).copy()
    background = scenario.background.temperature
    nodes = {
        j: np.asarray(
            interpolate_aspect(
                np.asarray(t.azimuth), np.asarray(t.elevation), t.grid, mesh_az, mesh_el
            )
        )
        + (float(background) if t.quantity == "contrast" else 0.0)
        for j, t in tables.items()
    }
    virtual = [
        scenario.targets[j].model_copy(update={"temperature": float(value)})
        for j in tables
        for value in nodes[j].ravel()
    ]
    size = azimuth.size * elevation.size
    for k, s in enumerate(sensors):
        seen = get_sensor_type(s.type).signature(s, scenario.background, virtual)
        signal = np.abs(np.asarray(seen.target, dtype=float) - seen.background)
        for m, j in enumerate(tables):
            contrast[k, j] = signal[m * size : (m + 1) * size].reshape(azimuth.size, -1)
    clutter = None
    bg = scenario.background
    if bg.scr is None and pixels is None and bg.clutter_std is not None:
        clutter = np.array(
            [[np.nan if seen.clutter is None else seen.clutter] * n_g for seen in signatures]
        )
    return AspectArrays(azimuth=azimuth, elevation=elevation, contrast=contrast, clutter=clutter)


def _mrtd(owned: list[tuple[str, Any]], curves: dict[str, Any]) -> MrtdArrays | None:
    """The MRTD-limited rows: each thermal row whose sensor has a curve, with the slope
    ``∂M_bb,band/∂T`` at its ``netd_temperature`` that turns its contrast into a ΔT (as the
    CLI's ``--mrtd`` does with the temperatures)."""
    from targetacq.physics.radiometry import band_exitance_derivative

    rows = tuple(k for k, (owner, _) in enumerate(owned) if owner in curves)
    if not rows:
        return None
    return MrtdArrays(
        exitance_slope=np.array(
            [
                float(band_exitance_derivative(owned[k][1].netd_temperature, owned[k][1].limits))
                for k in rows
            ],
            dtype=float,
        ),
        rows=rows,
        curves=tuple(curves[owned[k][0]] for k in rows),
    )


def _ttp(scenario: Any, owned: list[tuple[str, Any]]) -> TtpArrays | None:
    """The rows whose resolution is the TTP metric (``[model] resolution_model = "ttp"``): each
    thermal row, with its :class:`targetacq.physics.ttp.TtpSystem` (the sensor's IFOV, aperture,
    band centre, NETD in kelvin, jitter, smear, frame rate and scene contrast temperature, the
    atmosphere's Cn²; the TTP defaults where they are left out, as the range commands' options
    have them) and the slope ``∂M_bb,band/∂T`` at its ``netd_temperature`` that turns its
    contrast into a ΔT (as :func:`_mrtd`)."""
    if scenario.model.resolution_model != "ttp":
        return None
    rows = tuple(k for k, (_, s) in enumerate(owned) if s.type == "thermal")
    if not rows:
        return None
    cn2 = scenario.atmosphere.cn2
    systems = []
    for k in rows:
        s = owned[k][1]
        given = {
            name: getattr(s, name)
            for name in ("jitter", "smear", "frame_rate", "scene_contrast")
            if getattr(s, name) is not None
        }
        systems.append(
            TtpSystem(
                ifov=float(s.pixel_ifov),
                aperture=float(s.aperture),
                wavelength=0.5 * (s.limits[0] + s.limits[1]),
                netd=0.0 if s.netd is None else float(s.netd),
                cn2=0.0 if cn2 is None else float(cn2),
                **given,
            )
        )
    return TtpArrays(
        exitance_slope=np.array(
            [
                float(
                    radiometry.band_exitance_derivative(
                        owned[k][1].netd_temperature, owned[k][1].limits
                    )
                )
                for k in rows
            ],
            dtype=float,
        ),
        rows=rows,
        systems=tuple(systems),
    )


def _size_problems(scenario: Any) -> list[str]:
    """The scenario's own time grid against the memory a chunked evaluation of it needs: all
    the times of one target at once (:meth:`targetacq.run.model_chain.ModelChain.evaluate_chunks`,
    which ``targetacq evaluate`` streams). An evaluation held in memory whole is checked by
    :meth:`targetacq.run.model_chain.ModelChain.evaluate`."""
    grid, n_s, n_g = scenario.time, len(scenario.sensors), len(scenario.targets)
    try:
        check_size(
            grid.count * n_s,
            BYTES_PER_EVALUATION,
            f"evaluating {grid.count:.3g} times ({grid.describe()}, one target at a time) x "
            f"{n_s} sensor(s) x {n_g} target(s)",
            "use a longer time.step or a shorter span (time.start to time.stop)",
        )
    except ValueError as error:
        return [f"time.step: {error}"]
    return []


def check_runnable(scenario: Any) -> list[str]:
    """Every problem that stops a validated scenario from being compiled and evaluated over its
    time grid, each located (``table[index].key: what``); empty when it runs.

    This compiles the scenario (:func:`compile_scenario`: the files it names are read) without
    evaluating anything: the ``validate`` command's check, the same as
    :class:`targetacq.run.model_chain.ModelChain` makes, so the two cannot disagree.

    Parameters
    ----------
    scenario : targetacq.scenario.schema.Scenario

    Returns
    -------
    list of str
    """
    try:
        compile_scenario(scenario)
    except ScenarioError as error:
        return list(error.problems)
    return []


def compile_scenario(scenario: Any) -> CompiledScenario:
    """Compile a validated scenario into the core's records (once; reads image and map files).

    Temperatures given as a daily cycle are compiled at the scenario's hour of day
    (``time.hour``) and held over the run (:meth:`targetacq.scenario.schema.Scenario.held`).

    Parameters
    ----------
    scenario : targetacq.scenario.schema.Scenario

    Returns
    -------
    CompiledScenario

    Raises
    ------
    targetacq.scenario.schema.ScenarioError
        With every problem found (:func:`check_runnable`), each located: an image, a terrain
        map or an elevation model that cannot be read, boxes outside the image, class indices
        naming no class, a time grid too large for memory.
    """
    scenario = scenario.held()  # daily cycles at the hour of the start: plain temperatures
    problems: list[str] = []
    pixels = _background_image(scenario, problems)
    grid = _class_map(scenario, problems)
    elevation = _elevation(scenario, problems)
    if elevation is not None:
        problems += _off_the_elevation_model(scenario, elevation)
    curves = _mrtd_curves(scenario, problems)
    tables = _aspect_tables(scenario, problems)
    if scenario.model.resolution_model is not None:
        try:  # the registry's names (the schema's layer is below it)
            get_resolution_model(scenario.model.resolution_model)
        except ValueError as error:
            problems.append(f"model.resolution_model: {error}")
    problems += _size_problems(scenario)
    if problems:
        raise ScenarioError(problems)
    scenario = _table_temperatures(scenario, tables)
    criteria = _criteria(scenario)
    owned = _owned_rows(scenario)
    sensors = [row for _, row in owned]
    # Each sensor's signature once: the contrast and SCR and the sensor's noise both read it.
    signatures = []
    for k, s in enumerate(sensors):
        try:
            signatures.append(
                get_sensor_type(s.type).signature(s, scenario.background, scenario.targets)
            )
        except ValueError as error:  # a signal the schema let through but physics refuses
            raise ScenarioError(f"sensors[{k}]: {error}") from None
    model = scenario.model
    choices = ModelChoices(
        transform=model.transform,
        options=() if model.bound is None else (("bound", model.bound),),
        noise_model=model.noise_model or "variance-sum",
        region=scenario.background.clutter,
        search_time=model.search_time,
        motion=model.motion,
        semantics=model.semantics,
        snr_law=model.snr_law,
        snr_on_mrtd=model.noise_model is not None,
    )
    signature = _signature(scenario, sensors, signatures, pixels)
    scene = SceneArrays(
        sensors=dataclasses.replace(
            _sensors(scenario, sensors, tuple(owner for owner, _ in owned), signatures),
            mrtd=_mrtd(owned, curves),
            ttp=_ttp(scenario, owned),
        ),
        targets=_targets(scenario, criteria),
        path=_path(scenario),
        signature=dataclasses.replace(
            signature, aspect=_aspect(scenario, sensors, signatures, tables, signature, pixels)
        ),
        choices=choices,
        radar=_radar(scenario, sensors),
        laser=_laser(scenario, sensors),
    )
    return CompiledScenario(
        scene=scene,
        criteria=criteria,
        terrain=_terrain(scenario, grid),
        elevation=elevation,
        earth_radius_factor=(
            STANDARD_K if scenario.terrain is None else scenario.terrain.earth_radius_factor
        ),
    )


def _path_positions(items: Any, times: np.ndarray) -> np.ndarray:
    out = np.empty((len(items), times.size, 3))
    for k, item in enumerate(items):
        if item.waypoints is None:
            out[k] = np.asarray(item.position)
        else:
            out[k] = geometry.positions_at(
                times, [w.time for w in item.waypoints], [w.position for w in item.waypoints]
            )
    return out


def _path_velocities(items: Any, times: np.ndarray) -> np.ndarray:
    out = np.zeros((len(items), times.size, 3))
    for k, item in enumerate(items):
        if item.waypoints is not None:
            out[k] = geometry.velocities_at(
                times, [w.time for w in item.waypoints], [w.position for w in item.waypoints]
            )
    return out


def scenario_velocities(scenario: Any, times: Array, targets: slice | None = None) -> np.ndarray:
    """Velocities of a scenario's targets along their scripted paths at times: the derivatives
    of :func:`scenario_positions` (:func:`targetacq.physics.geometry.velocities_at`; 0 for a
    target standing at its ``position``, and before its first and from its last waypoint).

    Parameters
    ----------
    scenario : targetacq.scenario.schema.Scenario
    times : array_like
        (n_t,) [s].
    targets : slice, optional
        The targets wanted (default all).

    Returns
    -------
    numpy.ndarray (n_g, n_t, 3)
        [m/s].
    """
    t = np.atleast_1d(np.asarray(times, dtype=float))
    chosen = scenario.targets[slice(None) if targets is None else targets]
    return _path_velocities(chosen, t)


def scenario_positions(
    scenario: Any, times: Array, targets: slice | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Positions and headings of a scenario's scripted paths at times.

    Parameters
    ----------
    scenario : targetacq.scenario.schema.Scenario
    times : array_like
        (n_t,) [s].
    targets : slice, optional
        The targets wanted (default all).

    Returns
    -------
    sensor_positions : numpy.ndarray (n_s, n_t, 3) [m]
    target_positions : numpy.ndarray (n_g, n_t, 3) [m]
    headings : numpy.ndarray (n_g, n_t) [rad]
        Along the path where the target moves, the scenario's heading where it stands still.
    """
    t = np.atleast_1d(np.asarray(times, dtype=float))
    chosen = scenario.targets[slice(None) if targets is None else targets]
    heading = np.empty((len(chosen), t.size))
    for k, target in enumerate(chosen):
        if target.waypoints is None:
            heading[k] = target.heading
        else:
            heading[k] = geometry.heading_along(
                t,
                [w.time for w in target.waypoints],
                [w.position for w in target.waypoints],
                target.heading,
            )
    return _path_positions(sensor_rows(scenario), t), _path_positions(chosen, t), heading
