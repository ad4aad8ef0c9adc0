"""Sensor pointing control: point gimballed cameras so that targets are acquired early.

The environment steps a :class:`targetacq.Simulation`: one or more thermal cameras (or, with
``camera_type``, TV or SWIR cameras) on one platform that flies a straight line over an area with
targets, some standing, some driving. The agent chooses each camera's pointing every step; the
model decides, with its search law and its nested detection → recognition → identification
draws, what the cameras acquire.

Scene
    the environment builds a scenario (:class:`targetacq.scenario.schema.Scenario`) at each
    reset; ``scenario_overrides`` sets fields of its records over the environment's defaults,
    as a scenario file's tables would: an MRTD curve, a NETD or a digitiser's step on every
    camera, foliage, a hot spot or a temperature on every target, an atmosphere (extinction,
    obscurant, segments, clouds), a background's clutter, the model's transform, noise model
    or redraw rule: what a scenario's sensor, target, background, atmosphere and model tables
    say reaches the episode, checked by the records themselves when the environment is made.
    ``env.scenario`` is the episode's.
Observation (float32, one flat vector)
    the platform's position over the area's half-width; each camera's pointing (azimuth / π,
    depression / (π/2)); per target its position relative to the platform over the half-width
    (east, north, up) and whether it has been detected, recognised and identified (by any
    camera). The targets' positions are a cue (from another sensor or intelligence): the task is
    to choose where to look, not to find out where things are.
Action (float32 in [−1, 1], shape (cameras, 2))
    azimuth = π · a₀ (from north, clockwise), depression = (π/2) · (a₁ + 1) / 2 (0 at the
    horizon, straight down at 1).
Reward
    the number of new acquisitions this step, summed over targets and tasks (detection,
    recognition and identification each count once per target, fused over the cameras): a
    target found again after it left the view (a ``reacquired`` event) earns nothing.
Info
    ``time`` [s]; ``detected``, ``recognised``, ``identified``: per target, whether any camera
    has done the task since the reset (bool arrays, the model's cumulative fused flags);
    ``events``: what happened within the step, ordered by time, each a dict of ``sensor``,
    ``target``, ``task``, ``time`` [s] and ``kind`` (``first`` or ``reacquired``,
    :data:`targetacq.run.simulation.EVENT_KINDS`); ``warnings``: the model's warnings of the step,
    as text (a target in a camera's view for less than a step, once per episode:
    :class:`targetacq.run.search.ShortVisitWarning`), kept here rather than emitted so that training
    over many episodes does not print one per episode.
Episode
    ``duration`` seconds in steps of ``dt``; terminated early when every target is identified.
    ``reset(seed=...)`` draws the targets' layout from Gymnasium's generator and seeds the
    model's counter-based streams, so an episode is reproducible from its seed. ``step`` before
    the first ``reset`` raises :class:`gymnasium.error.ResetNeeded`.
"""

from __future__ import annotations

import copy
import math
import os
import warnings
from collections.abc import Mapping
from difflib import get_close_matches
from pathlib import Path
from typing import Any

import gymnasium
import numpy as np
from gymnasium import spaces
from gymnasium.error import ResetNeeded

from targetacq.physics.line_of_sight import STANDARD_K, ElevationModel, read_elevation
from targetacq.run.search import ShortVisitWarning
from targetacq.scenario.plausibility import collected, emit
from targetacq.scenario.schema import (
    Atmosphere,
    Background,
    Elevation,
    ModelChoices,
    Scenario,
    ScenarioError,
    Sensor,
    Target,
    parse_scenario,
)
from targetacq.sensors import SENSOR_TYPES, get_sensor_type

__all__ = [
    "CAMERA_TYPES",
    "CONTROLLED_FIELDS",
    "MAX_CAMERAS",
    "MAX_TARGETS",
    "OVERRIDE_TABLES",
    "SensorPointingEnv",
]

MAX_CAMERAS = 64
"""Most cameras an environment takes (each adds its pointing to the observation)."""
MAX_TARGETS = 10_000
"""Most targets an environment takes (each adds six numbers to the observation and a record
to the model; 10⁹ ran out of memory)."""
CAMERA_TYPES: tuple[str, ...] = tuple(
    name for name, t in SENSOR_TYPES.items() if t.kind == "imaging" and t.table is None
)
"""The sensor types an environment's cameras can be: the imaging types of
:data:`targetacq.sensors.SENSOR_TYPES` that need no table of their own (thermal, tv, swir). The
scene gives every target a temperature and (but for thermal cameras) a reflectance, and the
background an in-band irradiance: what those types need."""

OVERRIDE_TABLES: dict[str, type[Any]] = {
    "sensor": Sensor,
    "target": Target,
    "atmosphere": Atmosphere,
    "background": Background,
    "model": ModelChoices,
    "terrain": Elevation,
}
"""The keys of an environment's ``scenario_overrides``, and the scenario record whose fields
each takes (the tables of a scenario file: ``sensor`` and ``target`` set on every camera and
every target; ``terrain`` the ``[terrain]`` elevation model)."""

CONTROLLED_FIELDS: dict[str, dict[str, str]] = {
    "sensor": {
        "name": "each camera's own",
        "type": "give camera_type",
        "position": "the platform's, per step",
        "waypoints": "the platform flies a straight line",
        "look_at": "the action points the cameras",
        "azimuth": "the action points the cameras",
        "depression": "the action points the cameras",
    },
    "target": {
        "name": "each target's own",
        "position": "drawn per episode",
        "waypoints": "the targets' positions are drawn per episode",
        "heading": "drawn per episode",
        "dimensions": "drawn per episode",
    },
}
"""The fields of a camera and of a target that the environment sets itself (with why), refused
in ``scenario_overrides``."""

_GROUPS: dict[str, tuple[str, ...]] = {
    "sensor": ("hfov", "ifov"),
    "background": ("clutter", "scr", "clutter_std", "image", "terrain"),
    "atmosphere": ("extinction", "obscurant", "visibility"),
}
"""Fields that replace a group of the environment's defaults: a camera given ``hfov`` or
``ifov`` drops the default lens (pitch and focal length); a background given one way of clutter,
or an atmosphere given one way of extinction, drops the default one (the records take one)."""
_REPLACED: dict[str, tuple[str, ...]] = {
    "sensor": ("pitch", "focal_length"),
    "background": ("clutter", "clutter_std"),
    "atmosphere": ("obscurant",),
}

_TASKS = ("detected", "recognised", "identified")
"""The cumulative fused flags of :class:`targetacq.run.simulation.StepResult` (``fused_<flag>``), in
the observation's order."""


class SensorPointingEnv(gymnasium.Env[np.ndarray, np.ndarray]):
    """Point gimballed cameras on a moving platform at targets (see the module docstring).

    Parameters
    ----------
    cameras : int
        Number of cameras on the platform, >= 1.
    targets : int
        Number of targets, >= 1.
    duration : float
        Episode length [s], > 0.
    dt : float
        Step [s], > 0.
    altitude : float
        Platform height [m], > 0: above the ground's 0 m, or, with a ``terrain`` elevation
        model, the altitude above the model's datum (the platform flies level at it, higher than
        every post of the area it can reach).
    speed : float
        Platform speed [m/s], >= 0 (flying east).
    half_width : float
        Half the side of the square area the targets stand in [m], > 0.
    scenario_overrides : mapping, optional
        The core's sensor, target, path and model features, as the tables of a scenario file:
        keys ``"sensor"``, ``"target"``, ``"atmosphere"``, ``"background"``, ``"model"`` and
        ``"terrain"`` (:data:`OVERRIDE_TABLES`), each a mapping of the fields of that scenario
        record (:class:`~targetacq.scenario.schema.Sensor`,
        :class:`~targetacq.scenario.schema.Target`,
        :class:`~targetacq.scenario.schema.Atmosphere`,
        :class:`~targetacq.scenario.schema.Background`,
        :class:`~targetacq.scenario.schema.ModelChoices`,
        :class:`~targetacq.scenario.schema.Elevation`), set over the environment's own scene
        below: ``sensor`` on every camera, ``target`` on every target. Quantities as in a file
        (``"50 mK"``, ``"0.2 /km"``) or as SI numbers. One mapping rather than six keywords
        keeps the constructor within ten parameters. Checked here, by the scenario's own
        records and the core's compiler (an MRTD curve is read): a bad value, an unknown key
        or a field the environment sets itself (:data:`CONTROLLED_FIELDS`: the cameras' names,
        type, position and pointing; the targets' names and the position, heading and
        dimensions drawn per episode) raises ``ValueError`` naming it
        (``scenario_overrides: sensor.netd: ...``). File paths (``sensor.mrtd``,
        ``background.image``, ``background.terrain.map``, ``terrain.elevation``) are relative to
        the current directory when the environment is made. A ``terrain`` elevation model
        (``{"elevation": "dem.npy", "spacing": "30 m", "origin": ["-5 km", "-5 km"]}``) must
        cover the targets' square; the drawn targets then stand on the ground (their altitude
        the terrain's at their east and north) and every camera-target pair sees the fraction
        of its target above the terrain (:func:`targetacq.line_of_sight`, the step API's
        ``terrain``): a target behind a ridge is out of view. A ``target.temperature`` replaces
        the drawn one (the draw still happens, so a seed gives the same layout with and
        without overrides); a ``sensor.hfov`` or ``sensor.ifov`` replaces the default lens; a
        background's way of clutter, or an atmosphere's extinction, obscurant or visibility,
        replaces the default one. Plausibility warnings are emitted once, here. Default: none
        (the scene of the Notes).
    render_mode : None
        No rendering.
    camera_type : str
        The cameras' sensor type, one of :data:`CAMERA_TYPES`: "thermal" (8-12 µm, clutter as
        a 2 K temperature spread), or "tv" or "swir" (the type's default band; targets of
        reflectance 0.1 on a background of 0.3 under 300 W/m², clutter a medium Table 3.5
        region).

    Notes
    -----
    The environment's own scene: cameras of 640 × 512 pixels of 17 µm behind a 0.1 m lens
    (``scenario_overrides={"sensor": {"focal_length": "0.2 m"}}`` for another one), no sensor
    noise but the path's; targets of 4-7.5 m × 2.5 m × 2.5 m at 300-315 K, headings and
    positions drawn per episode; a background at 293 K; haze (``obscurant = "haze"``); the
    default model choices.

    Examples
    --------
    >>> from targetacq.envs import SensorPointingEnv
    >>> env = SensorPointingEnv(targets=2, duration=5.0, scenario_overrides={
    ...     "sensor": {"netd": "50 mK", "quantisation_step": "1e-4 W/m^2"},
    ...     "target": {"foliage": 0.5, "hot_spot": True},
    ...     "atmosphere": {"extinction": "0.2 /km"},
    ...     "model": {"redraw": "after-out-of-view", "decorrelation_time": "30 s"},
    ... })
    >>> obs, info = env.reset(seed=1)
    >>> obs.shape, env.scenario.sensors[0].netd, env.scenario.targets[1].foliage
    ((17,), 0.05, 0.5)
    >>> try:
    ...     SensorPointingEnv(scenario_overrides={"sensor": {"nedt": "50 mK"}})
    ... except ValueError as error:  # doctest: +ELLIPSIS
    ...     print(error)
    scenario_overrides: sensor.nedt: unknown key 'nedt' (did you mean 'netd'?); valid keys: ...
    """

    metadata: dict[str, Any] = {"render_modes": []}  # noqa: RUF012 - Gymnasium's convention

    def __init__(
        self,
        cameras: int = 1,
        targets: int = 6,
        duration: float = 120.0,
        dt: float = 1.0,
        altitude: float = 1500.0,
        speed: float = 40.0,
        half_width: float = 3000.0,
        scenario_overrides: Mapping[str, Mapping[str, Any]] | None = None,
        render_mode: str | None = None,
        camera_type: str = "thermal",
    ) -> None:
        if camera_type not in CAMERA_TYPES:
            raise ValueError(
                f"camera_type must be one of {', '.join(CAMERA_TYPES)} (the sensor types whose "
                f"scene the environment builds), got {camera_type!r}"
            )
        self.camera_type = camera_type
        for label, count, most in (
            ("cameras", cameras, MAX_CAMERAS),
            ("targets", targets, MAX_TARGETS),
        ):
            if not (isinstance(count, int) and not isinstance(count, bool) and 1 <= count <= most):
                raise ValueError(
                    f"{label} must be an integer in [1, {most}] (an environment's observation "
                    f"holds every one; larger scenes are for targetacq.Simulation), got {count!r}"
                )
        units = {"duration": "s", "dt": "s", "altitude": "m", "half_width": "m", "speed": "m/s"}
        for name, value in (
            ("duration", duration),
            ("dt", dt),
            ("altitude", altitude),
            ("half_width", half_width),
            ("speed", speed),
        ):
            if not isinstance(value, (int, float)) or isinstance(value, bool):
                raise ValueError(
                    f"{name} must be a number of {units[name]} (SI, as every Python argument), "
                    f"got {value!r}"
                )
            if not (math.isfinite(value) and value > 0) and name != "speed":
                raise ValueError(f"{name} must be finite and > 0, got {value!r}")
        if not (math.isfinite(speed) and speed >= 0):
            raise ValueError(f"speed must be finite and >= 0 m/s, got {speed!r}")
        if render_mode is not None:
            raise ValueError("render_mode must be None: this environment does not render")
        self.render_mode = render_mode
        self.n_cameras, self.n_targets = cameras, targets
        self.duration, self.dt = float(duration), float(dt)
        self.altitude, self.speed, self.half_width = (
            float(altitude),
            float(speed),
            float(half_width),
        )
        self.scenario_overrides = _overrides(scenario_overrides)
        self.elevation: ElevationModel | None = None  # the terrain table's, read once
        self.earth_radius_factor = STANDARD_K
        self._check_overrides()
        size = 3 + 2 * cameras + 6 * targets
        # Positions over the half-width stay within the area plus the flight and the height.
        bound = 2.0 + (self.speed * self.duration + self.altitude) / self.half_width
        self.observation_space = spaces.Box(-bound, bound, shape=(size,), dtype=np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, shape=(cameras, 2), dtype=np.float32)
        self._sim: Any = None

    # -- set-up --------------------------------------------------------------------------------

    @property
    def scenario(self) -> Scenario | None:
        """The episode's scenario (its targets where the reset drew them), or None before the
        first reset: :meth:`targetacq.Simulation.from_scenario` of it is the episode's model."""
        return None if self._sim is None else self._sim.scenario

    def scene_tables(self, rng: np.random.Generator, cameras: int, targets: int) -> dict[str, Any]:
        """The scene as a scenario's tables: the environment's defaults, the overrides over
        them, ``cameras`` cameras and ``targets`` targets drawn from ``rng``."""
        start = (-self.half_width, 0.0, self.altitude)
        camera = {
            "type": self.camera_type,
            "band": "lwir" if get_sensor_type(self.camera_type).band_required else None,
            "pixels": (640, 512),
            "pitch": 17e-6,
            "focal_length": 0.1,
            "position": start,
            "azimuth": math.pi / 2,
            "depression": math.pi / 6,
        }
        sensors = [
            {"name": f"camera-{k}", **_over(camera, self.scenario_overrides, "sensor")}
            for k in range(cameras)
        ]
        drawn = []
        for j in range(targets):
            dimensions = (float(rng.uniform(4.0, 7.5)), 2.5, 2.5)
            heading = float(rng.uniform(0.0, 2 * math.pi))
            temperature = float(rng.uniform(300.0, 315.0))
            reflectance = None if self.camera_type == "thermal" else 0.1
            east = float(rng.uniform(-self.half_width, self.half_width))
            north = float(rng.uniform(-self.half_width, self.half_width))
            ground = 0.0 if self.elevation is None else float(self.elevation.height_at(east, north))
            position = (east, north, ground)
            target = {
                "name": f"target-{j}",
                "dimensions": dimensions,
                "heading": heading,
                "temperature": temperature,
                "reflectance": reflectance,
                "position": position,
            }
            drawn.append(_over(target, self.scenario_overrides, "target"))
        background: dict[str, Any] = (
            {"temperature": 293.0, "clutter_std": 2.0}
            if self.camera_type == "thermal"
            else {
                "temperature": 293.0,
                "reflectance": 0.3,
                "irradiance": 300.0,
                "clutter": "medium",
            }
        )
        return {
            "sensors": sensors,
            "targets": drawn,
            "background": _over(background, self.scenario_overrides, "background"),
            "atmosphere": _over({"obscurant": "haze"}, self.scenario_overrides, "atmosphere"),
            "model": _over({}, self.scenario_overrides, "model"),
            **(
                {"terrain": dict(self.scenario_overrides["terrain"])}
                if "terrain" in self.scenario_overrides
                else {}
            ),
        }

    def _check_overrides(self) -> None:
        """Validate the overrides now, as the records and the compiler will at each reset: a
        scene of one camera and one target, its problems located at the option."""
        from targetacq.core.compile import check_runnable

        data = self.scene_tables(np.random.default_rng(0), 1, 1)
        with collected() as found:
            try:
                scenario = parse_scenario(data, _SOURCE, strict_units=False)
            except ScenarioError as error:
                raise ScenarioError([_located(p) for p in error.problems]) from None
        problems = check_runnable(scenario)
        if problems:
            raise ScenarioError([_located(f"{_SOURCE}: {p}") for p in problems])
        if scenario.terrain is not None:
            relief = scenario.terrain
            self.earth_radius_factor = float(relief.earth_radius_factor)
            self.elevation = self._reachable(
                read_elevation(relief.elevation, relief.spacing, relief.origin)
            )
        emit([_located(message) for message in found], stacklevel=4)

    def _reachable(self, model: ElevationModel) -> ElevationModel:
        """The elevation model, checked to cover the targets' square and to stay under the
        platform's altitude within its reach (``half_width + speed · duration`` of the origin)."""
        reach = self.half_width + self.speed * self.duration
        west, east, south, north = model.extent
        if not (
            west <= -self.half_width <= self.half_width <= east
            and south <= -self.half_width <= self.half_width <= north
        ):
            raise ValueError(
                f"{_SOURCE}: terrain.elevation: the grid (east {west:g} to {east:g} m, north "
                f"{south:g} to {north:g} m) must cover the targets' square of +-{self.half_width:g}"
                " m around the origin"
            )
        rows, cols = model.elevation.shape
        x = model.origin[0] + model.spacing * np.arange(cols)
        y = model.origin[1] + model.spacing * np.arange(rows)
        near = (np.abs(y)[:, None] <= reach) & (np.abs(x)[None, :] <= reach)
        highest = float(np.nanmax(np.where(near, model.elevation, -np.inf)))
        if not highest < self.altitude:
            raise ValueError(
                f"altitude ({self.altitude:g} m, above the elevation model's datum) must be above "
                f"the terrain the platform can reach (up to {highest:g} m within {reach:g} m of "
                "the origin)"
            )
        return model

    def _scenario(self) -> Scenario:
        data = self.scene_tables(self.np_random, self.n_cameras, self.n_targets)
        with collected():  # warned when the environment was made
            return parse_scenario(data, _SOURCE, strict_units=False)

    def _platform(self, time: float) -> np.ndarray:
        return np.array([-self.half_width + self.speed * time, 0.0, self.altitude])

    def _observation(self) -> np.ndarray:
        platform = self._platform(self._time)
        relative = (self._targets - platform) / self.half_width
        flags = np.stack([self._acquired[task] for task in _TASKS], axis=-1)
        pointing = self._pointing / np.array([math.pi, math.pi / 2])
        return np.concatenate(
            [
                platform / self.half_width,
                pointing.reshape(-1),
                np.concatenate([relative, flags], axis=-1).reshape(-1),
            ]
        ).astype(np.float32)

    # -- Gymnasium API -------------------------------------------------------------------------

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """Draw a new layout of targets and start an episode (reproducible from ``seed``)."""
        super().reset(seed=seed)
        from targetacq.run.simulation import Simulation

        scenario = self._scenario()
        self._targets = np.array([t.position for t in scenario.targets], dtype=float)
        self._headings = np.array([t.heading for t in scenario.targets], dtype=float)
        model_seed = int(self.np_random.integers(0, 2**31 - 1))
        self._sim = Simulation.from_scenario(scenario, seed=model_seed)
        self._time = 0.0
        self._pointing = np.tile([math.pi / 2, math.pi / 6], (self.n_cameras, 1))
        self._acquired = {task: np.zeros(self.n_targets, dtype=bool) for task in _TASKS}
        _, info = self._step(self._pointing)  # the state at t = 0
        return self._observation(), info

    def _step(self, pointing: np.ndarray) -> tuple[int, dict[str, Any]]:
        """Advance the model to ``self._time``; the new fused acquisitions and the info."""
        sensors = np.tile(self._platform(self._time), (self.n_cameras, 1))
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", ShortVisitWarning)
            out = self._sim.step(
                self._time,
                self.dt,
                sensors,
                self._targets,
                target_headings=self._headings,
                sensor_pointing=pointing,
            )
        kept = []
        for warning in caught:  # the model's short visits go to info; anything else as it came
            if issubclass(warning.category, ShortVisitWarning):
                kept.append(str(warning.message))
            else:
                warnings.warn_explicit(
                    warning.message, warning.category, warning.filename, warning.lineno
                )
        new = 0
        for task in _TASKS:
            # Cumulative since the reset: a target acquired again after leaving the view
            # (a "reacquired" event) is already True here, so it is never counted twice.
            fused = np.asarray(getattr(out, f"fused_{task}"), dtype=bool)
            new += int(np.count_nonzero(fused & ~self._acquired[task]))
            self._acquired[task] = fused.copy()
        info: dict[str, Any] = {
            "time": self._time,
            **{task: self._acquired[task].copy() for task in _TASKS},
            "events": [event._asdict() for event in out.events],
            "warnings": kept,
        }
        return new, info

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        """Point the cameras, advance ``dt`` and count the new acquisitions."""
        self._require_reset("step")
        given = np.asarray(action)
        if given.dtype.kind not in "fiu" or given.size != 2 * self.n_cameras:
            raise ValueError(
                f"action must be {2 * self.n_cameras} real numbers in [-1, 1] (shape "
                f"({self.n_cameras}, 2): azimuth, depression per camera), got {given.dtype} of "
                f"shape {given.shape}"
            )
        a = given.astype(float).reshape(self.n_cameras, 2)
        if not np.all(np.isfinite(a)):
            raise ValueError("action must be finite")
        a = np.clip(a, -1.0, 1.0)
        self._pointing = np.stack([math.pi * a[:, 0], math.pi / 4 * (a[:, 1] + 1.0)], axis=-1)
        self._time += self.dt
        new, info = self._step(self._pointing)
        terminated = bool(self._acquired["identified"].all())
        truncated = self._time >= self.duration - 1e-9
        return self._observation(), float(new), terminated, truncated, info

    def _require_reset(self, what: str) -> None:
        if self._sim is None:
            raise ResetNeeded(
                f"SensorPointingEnv.{what}() before reset(): call env.reset(seed=...) first to "
                "draw the targets and start an episode"
            )

    # -- a reference policy --------------------------------------------------------------------

    def greedy_action(self) -> np.ndarray:
        """Point every camera at the nearest target not yet identified (a scripted baseline)."""
        self._require_reset("greedy_action")
        platform = self._platform(self._time)
        remaining = ~self._acquired["identified"]
        offsets = self._targets - platform
        distance = np.where(remaining, np.linalg.norm(offsets, axis=-1), np.inf)
        order = np.argsort(distance)
        action = np.zeros((self.n_cameras, 2), dtype=np.float32)
        for k in range(self.n_cameras):
            j = order[min(k, len(order) - 1)]
            east, north, up = offsets[j]
            azimuth = math.atan2(east, north)
            depression = math.atan2(-up, math.hypot(east, north))
            action[k] = azimuth / math.pi, depression / (math.pi / 4) - 1.0
        return np.clip(action, -1.0, 1.0)


_SOURCE = "scenario_overrides"
_ONE = {"sensors[0]": "sensor", "targets[0]": "target"}


def _located(problem: str) -> str:
    """A scenario's located problem as an option: ``sensors[0].netd`` is ``sensor.netd``."""
    head = f"{_SOURCE}: "
    rest = problem.removeprefix(head)
    for place, option in _ONE.items():
        if rest.startswith(place):
            return head + option + rest[len(place) :]
    return head + rest if problem.startswith(head) else problem


def _path(value: Any) -> Any:
    """A file's path from the current directory: absolute, so that a later ``chdir`` keeps it."""
    if isinstance(value, (str, os.PathLike)):
        path = Path(value)
        return str(path if path.is_absolute() else Path.cwd() / path)
    return value


def _overrides(given: Any) -> dict[str, dict[str, Any]]:
    """The checked, copied overrides: known tables, each a mapping of text keys, none of the
    fields the environment sets, file paths made absolute."""
    if given is None:
        return {}
    if not isinstance(given, Mapping):
        lens = (
            " (a lens is scenario_overrides={'sensor': {'focal_length': ...}})"
            if isinstance(given, (int, float))
            else ""
        )
        raise ValueError(
            f"{_SOURCE} must be a mapping of tables ({', '.join(OVERRIDE_TABLES)}) to mappings "
            f"of their fields, got {type(given).__name__}{lens}"
        )
    tables: dict[str, dict[str, Any]] = {}
    for key, fields in given.items():
        if key not in OVERRIDE_TABLES:
            close = get_close_matches(str(key), list(OVERRIDE_TABLES), 1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise ValueError(
                f"{_SOURCE}: unknown key {key!r}{hint}; valid keys: {', '.join(OVERRIDE_TABLES)}"
            )
        if not isinstance(fields, Mapping):
            raise ValueError(
                f"{_SOURCE}: {key} must be a mapping of {OVERRIDE_TABLES[key].__name__}'s fields, "
                f"got {type(fields).__name__}"
            )
        controlled = CONTROLLED_FIELDS.get(key, {})
        refused = [name for name in fields if name in controlled]
        if refused:
            why = "; ".join(f"{name}: {controlled[name]}" for name in refused)
            raise ValueError(
                f"{_SOURCE}: {key}.{refused[0]}: the environment sets "
                f"{', '.join(refused)} itself ({why}); leave "
                f"{'it' if len(refused) == 1 else 'them'} out"
            )
        table = copy.deepcopy(dict(fields))
        if key == "sensor" and "mrtd" in table:
            table["mrtd"] = _path(table["mrtd"])
        if key == "background":
            if "image" in table:
                table["image"] = _path(table["image"])
            terrain = table.get("terrain")
            if isinstance(terrain, Mapping) and "map" in terrain:
                table["terrain"] = {**terrain, "map": _path(terrain["map"])}
        if key == "terrain" and "elevation" in table:
            table["elevation"] = _path(table["elevation"])
        tables[key] = table
    return tables


def _over(
    defaults: dict[str, Any], overrides: Mapping[str, Mapping[str, Any]], key: str
) -> dict[str, Any]:
    """The environment's ``defaults`` of a table with the overrides of ``key`` over them (a
    field of a group dropping the group's defaults: :data:`_GROUPS`)."""
    given = overrides.get(key)
    if not given:
        return defaults
    merged = dict(defaults)
    if any(name in given for name in _GROUPS.get(key, ())):
        for name in _REPLACED[key]:
            merged.pop(name, None)
    merged.update(given)
    return merged
