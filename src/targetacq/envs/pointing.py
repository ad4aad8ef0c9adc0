"""Sensor pointing control: point gimballed cameras so that targets are acquired early.

The environment steps a :class:`targetacq.Simulation`: one or more thermal cameras (or, with
``camera_type``, TV or SWIR cameras) on one platform that flies a straight line over an area with
targets, some standing, some driving. The agent chooses each camera's pointing every step; the
model decides, with its search law and its nested detection → recognition → identification
draws, what the cameras acquire.

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

import math
import warnings
from typing import Any

import gymnasium
import numpy as np
from gymnasium import spaces
from gymnasium.error import ResetNeeded

from targetacq.run.search import ShortVisitWarning
from targetacq.scenario.schema import Atmosphere, Background, Scenario, Sensor, Target
from targetacq.sensors import SENSOR_TYPES, get_sensor_type

__all__ = ["CAMERA_TYPES", "MAX_CAMERAS", "MAX_TARGETS", "SensorPointingEnv"]

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
        Platform height [m], > 0.
    speed : float
        Platform speed [m/s], >= 0 (flying east).
    half_width : float
        Half the side of the square area the targets stand in [m], > 0.
    focal_length : float
        The cameras' focal length [m] (17 µm pixels, 640 × 512).
    render_mode : None
        No rendering.
    camera_type : str
        The cameras' sensor type, one of :data:`CAMERA_TYPES`: "thermal" (8-12 µm, clutter as
        a 2 K temperature spread), or "tv" or "swir" (the type's default band; targets of
        reflectance 0.1 on a background of 0.3 under 300 W/m², clutter a medium Table 3.5
        region).
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
        focal_length: float = 0.1,
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
        for name, value in (
            ("duration", duration),
            ("dt", dt),
            ("altitude", altitude),
            ("half_width", half_width),
            ("focal_length", focal_length),
        ):
            if not (math.isfinite(value) and value > 0):
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
        self.focal_length = float(focal_length)
        size = 3 + 2 * cameras + 6 * targets
        # Positions over the half-width stay within the area plus the flight and the height.
        bound = 2.0 + (self.speed * self.duration + self.altitude) / self.half_width
        self.observation_space = spaces.Box(-bound, bound, shape=(size,), dtype=np.float32)
        self.action_space = spaces.Box(-1.0, 1.0, shape=(cameras, 2), dtype=np.float32)
        self._sim: Any = None

    # -- set-up --------------------------------------------------------------------------------

    def _scenario(self) -> Scenario:
        rng = self.np_random
        start = (-self.half_width, 0.0, self.altitude)
        sensors = [
            Sensor(
                name=f"camera-{k}",
                type=self.camera_type,
                band="lwir" if get_sensor_type(self.camera_type).band_required else None,
                pixels=(640, 512),
                pitch=17e-6,
                focal_length=self.focal_length,
                position=start,
                azimuth=math.pi / 2,
                depression=math.pi / 6,
            )
            for k in range(self.n_cameras)
        ]
        targets = [
            Target(
                name=f"target-{j}",
                dimensions=(float(rng.uniform(4.0, 7.5)), 2.5, 2.5),
                heading=float(rng.uniform(0.0, 2 * math.pi)),
                temperature=float(rng.uniform(300.0, 315.0)),
                reflectance=None if self.camera_type == "thermal" else 0.1,
                position=(
                    float(rng.uniform(-self.half_width, self.half_width)),
                    float(rng.uniform(-self.half_width, self.half_width)),
                    0.0,
                ),
            )
            for j in range(self.n_targets)
        ]
        return Scenario(
            sensors=sensors,
            targets=targets,
            background=Background(temperature=293.0, clutter_std=2.0)
            if self.camera_type == "thermal"
            else Background(temperature=293.0, reflectance=0.3, irradiance=300.0, clutter="medium"),
            atmosphere=Atmosphere(obscurant="haze"),
        )

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
