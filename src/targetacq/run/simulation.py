"""The step API: acquisition driven one time step at a time by another simulation.

:class:`Simulation` holds a compiled scenario (:func:`targetacq.core.compile_scenario`: sensors,
targets, background, atmosphere and model, everything that does not depend on where things are)
and the sampled state of every sensor-target pair. Each call of :meth:`Simulation.step` gets the
positions of that moment from the caller, evaluates the array core once
(:func:`targetacq.core.evaluate`) and advances the state::

    sim = Simulation.from_scenario(scenario, seed=7)
    out = sim.step(time, dt, sensor_positions, target_positions)
    out.detection                  # (n_sensors, n_targets) P at `time`
    out.detected                   # (n_sensors, n_targets) detected at some time so far
    out.events                     # what happened within the step, with its times
    out.false_detections           # clutter declared a target within the step ([false_targets])

:meth:`Simulation.probabilities` is the pure part (no draws, no state): the per-pair and fused
probabilities for positions, with NumPy or JAX arrays.

Law. The random outcomes follow the field-of-view search model of :mod:`targetacq.run.search`, the
one implementation shared with :func:`targetacq.run.search.simulate`:

- a step ``step(time, dt, ...)`` covers the interval ``(time − dt, time]``, with the positions
  given at ``time``; ``time − dt`` must be the previous step's time;
- within it each probability is taken **linear in time** between its value at the previous step
  and at this one, and the hazard ``P∞/t_s`` is integrated over the interval in closed form
  (the detection time solves a quadratic), so coarse steps do not bias an approaching target;
  recognition and identification happen at the first moment, at or after detection, at which
  the capability draw of the viewing episode is below their (linear) probability;
- a target that enters or leaves a sensor's field of view within a step is in view from (or
  until) the moment it crosses the edge, solved from the positions and pointing at both ends
  (:func:`targetacq.acquisition.engagement.view_crossings`), with the probabilities of the end at
  which it is in view; a visit shorter than a step warns once per run
  (:class:`targetacq.run.search.ShortVisitWarning`);
- draws belong to the engagement: a pair's capability draw and search clock are kept while the
  target is out of view, and drawn again only under the model's ``redraw`` rule
  (:data:`targetacq.acquisition.engagement.REDRAW_RULES`; ``never`` by default), so no pointing
  pattern or step raises the share of runs acquired; each event says whether it is the ``first`` of
  its sensor, target and task since the reset or ``reacquired`` (:data:`EVENT_KINDS`);
- the first step after :meth:`Simulation.reset` (and after construction) only starts the clock:
  it evaluates the probabilities at its time and starts the viewing episodes of the targets then
  in view; nothing happens in it, whatever ``dt``;
- a NaN position gives NaN probabilities for its pairs, and nothing happens for a pair in a step
  with a NaN probability at either end; its episode goes on unchanged.

False targets. With a ``[false_targets]`` table (:mod:`targetacq.run.false_targets`), each step
also draws the false detections of the sensors with a field of view: a Poisson count with mean
``density · A · probability · dt / t_s`` per sensor, ``A`` the ground in view at the step's time
within ``max_range``, each with a time uniform in the step's interval and a position uniform in
that area (none in the first step after a reset).

Draws come from counter-based streams keyed by the seed and the sensor's and target's names, so
a pair's outcomes do not depend on the order of the sensors or on which other sensors and
targets are simulated; run ``r`` of :meth:`Simulation.reset` is run ``r`` of
:func:`targetacq.run.search.simulate` with the same seed and steps (false detections included).
"""

from __future__ import annotations

import dataclasses
import warnings
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
from pydantic import ValidationError

from targetacq import core
from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.base.limits import MAX_ANGLE_TURN, MAX_DEPRESSION, check_finite
from targetacq.core import engines
from targetacq.core.evaluation import footprint_scr
from targetacq.core.terrain_view import hide, terrain_view
from targetacq.run.false_targets import FalseDetections, FalseTargetSampler
from targetacq.run.search import (
    SearchState,
    ShortVisitWarning,
    Streams,
    check_seed,
    pair_crossings,
    short_visit_message,
)
from targetacq.run.uncertainty import Uncertainty, observer_factor
from targetacq.scenario.schema import Scenario, ScenarioError, Sensor, load_scenario
from targetacq.sensors import get_sensor_type

__all__ = ["EVENT_KINDS", "TASKS", "Event", "Events", "Simulation", "StepResult"]

TASKS = ("detection", "recognition", "identification")
"""The tasks, in the order of :attr:`Events.task` codes."""

EVENT_KINDS = ("first", "reacquired")
"""What an event is, in the order of :attr:`Events.kind` codes: ``first``, the first time since
the last reset that the sensor did the task on the target (at most once per sensor, target and
task); ``reacquired``, the task done again after the target was out of the sensor's view and
came back (the observer finds it again: a new search for detection, then recognition and
identification as soon as the kept capability draw allows)."""

_INPUT_NAMES = ("sensor_positions", "target_positions", "target_headings", "sensor_pointing")


class Event(NamedTuple):
    """One acquisition: ``sensor`` did ``task`` on ``target`` at ``time`` [s], for the first
    time since the last reset (``kind`` ``"first"``) or again after the target was out of view
    (``"reacquired"``; :data:`EVENT_KINDS`)."""

    sensor: str
    target: str
    task: str
    time: float
    kind: str


@dataclass(frozen=True)
class Events:
    """The events of one step, ordered by time (then sensor, target and task).

    Arrays, so that a step with many events stays cheap; iterating gives :class:`Event` records.

    Attributes
    ----------
    sensor, target : numpy.ndarray of int (k,)
        Indices into :attr:`Simulation.sensors` and :attr:`Simulation.targets`.
    task : numpy.ndarray of int (k,)
        Indices into :data:`TASKS`.
    time : numpy.ndarray of float (k,)
        When it happened [s], within the step's interval.
    kind : numpy.ndarray of int (k,)
        Indices into :data:`EVENT_KINDS`: 0 the first time since the reset, 1 a reacquisition.
    sensor_names, target_names : tuple of str
    """

    sensor: np.ndarray
    target: np.ndarray
    task: np.ndarray
    time: np.ndarray
    kind: np.ndarray
    sensor_names: tuple[str, ...]
    target_names: tuple[str, ...]

    def __len__(self) -> int:
        return int(self.time.size)

    def __iter__(self) -> Iterator[Event]:
        for s, g, k, t, c in zip(
            self.sensor.tolist(),
            self.target.tolist(),
            self.task.tolist(),
            self.time.tolist(),
            self.kind.tolist(),
            strict=True,
        ):
            yield Event(self.sensor_names[s], self.target_names[g], TASKS[k], t, EVENT_KINDS[c])

    @property
    def first(self) -> Events:
        """The events that are the first of their sensor, target and task since the reset."""
        keep = self.kind == 0
        return Events(
            self.sensor[keep],
            self.target[keep],
            self.task[keep],
            self.time[keep],
            self.kind[keep],
            self.sensor_names,
            self.target_names,
        )


@dataclass(frozen=True)
class StepResult:
    """What one :meth:`Simulation.step` gives.

    Attributes
    ----------
    time : float
        The step's time [s].
    detection, recognition, identification : numpy.ndarray (n_sensors, n_targets)
        Probabilities at ``time`` (zero outside the field of view, NaN for a NaN position).
    fused_detection, fused_recognition, fused_identification : numpy.ndarray (n_targets,)
        Their sensor-level fusion (8.4).
    in_view : numpy.ndarray of bool (n_sensors, n_targets)
        Whether each target is in each sensor's field of view at ``time``.
    detected, recognised, identified : numpy.ndarray of bool (n_sensors, n_targets)
        Whether the sensor has detected (recognised, identified) the target at some time since
        the last reset.
    fused_detected, fused_recognised, fused_identified : numpy.ndarray of bool (n_targets,)
        The same by any sensor.
    events : Events
        What happened within this step, with its times.
    false_detections : targetacq.run.false_targets.FalseDetections
        Clutter declared a target within this step, ordered by time, with positions on the
        ground (empty without a ``[false_targets]`` table, and in a first step).
    """

    time: float
    detection: np.ndarray
    recognition: np.ndarray
    identification: np.ndarray
    fused_detection: np.ndarray
    fused_recognition: np.ndarray
    fused_identification: np.ndarray
    in_view: np.ndarray
    detected: np.ndarray
    recognised: np.ndarray
    identified: np.ndarray
    fused_detected: np.ndarray
    fused_recognised: np.ndarray
    fused_identified: np.ndarray
    events: Events
    false_detections: FalseDetections = dataclasses.field(default_factory=FalseDetections.empty)


def _record(item: Any) -> Any:
    """A sensor or target record or mapping; a mapping without a place stands at the origin
    (the step gives the positions)."""
    if isinstance(item, Mapping) and item.get("position") is None and not item.get("waypoints"):
        return {**item, "position": (0.0, 0.0, 0.0)}
    return item


def _located(error: ValidationError) -> str:
    detail = error.errors()[0]
    where = "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in detail["loc"])
    return f"{where.lstrip('.') or 'scenario'}: {detail['msg'].removeprefix('Value error, ')}"


class Simulation:
    """Acquisition by sensors of targets, stepped in time by the caller.

    Parameters
    ----------
    sensors : sequence of targetacq.scenario.schema.Sensor or mapping
        The sensors (type, band, resolution, field of view, pointing). Positions are given per
        step; a mapping may leave out ``position``.
    targets : sequence of targetacq.scenario.schema.Target or mapping
        The targets (box, heading, signature, criterion); positions likewise optional.
    background : targetacq.scenario.schema.Background or mapping, optional
    atmosphere : targetacq.scenario.schema.Atmosphere or mapping, optional
    model : targetacq.scenario.schema.ModelChoices or mapping, optional
        Criterion, transform, noise model and the search time ``search_time`` [s].
    false_targets : targetacq.scenario.schema.FalseTargets or mapping, optional
        Clutter objects declared targets (:mod:`targetacq.run.false_targets`): ``density``
        [1/m²], ``probability``, ``max_range`` [m] and optionally ``sensors``.
    terrain : targetacq.scenario.schema.Elevation or mapping, optional
        Terrain relief (the ``[terrain]`` table: ``elevation`` a ``.npy`` grid or a GeoTIFF,
        ``spacing``, ``origin``, ``earth_radius_factor``): each step's pairs then see the
        fraction of their target's height above the terrain
        (:func:`targetacq.line_of_sight`); a target hidden from a sensor is out of its view.
        The positions' third coordinate is then an altitude on the grid's datum: put targets
        on the ground with :meth:`targetacq.physics.line_of_sight.ElevationModel.height_at`
        (``sim.compiled.elevation``).
    seed : int
        Seed of the random outcomes, >= 0.
    observer_spread : float
        Relative spread [1], in [0, 1], of the observer's N50s from run to run (default 0: the
        criterion's N50s in every run). Each run (:meth:`reset`) draws one lognormal factor of
        median 1 (:func:`targetacq.run.uncertainty.observer_factor`, from the seed and the run
        by the counter-based streams, so a run is reproducible) that multiplies every target's
        and task's N50: an observer harder or easier to satisfy, for every sensor of the run.
        With a spread, run ``r`` is no longer :func:`targetacq.run.search.simulate`'s run ``r``.
    engine : str
        The compute engine for NumPy positions (:data:`targetacq.core.engines.ENGINES`: ``numpy``,
        the default and reference, ``numba``, ``jax`` or ``auto``, which is ``numba`` where it
        is installed and compiles the scene: :func:`targetacq.core.engines.for_steps`). A step of
        one camera and a few targets costs the numba engine's core about 10 µs against a few
        hundred for NumPy's (``benchmarks/bench_step.py``): simulations that step often want
        ``engine="auto"``. JAX positions always go through the array core in JAX.

    Attributes
    ----------
    sensors, targets : tuple of str
        Names, in the order of the arrays' axes.
    scenario : targetacq.scenario.schema.Scenario
    compiled : targetacq.core.CompiledScenario
    seed : int
    time : float or None
        The last step's time [s] (None before the first step).

    Raises
    ------
    ValueError
        An unknown sensor type, or records that do not make a valid scenario (the message
        says where).

    Examples
    --------
    >>> import numpy as np
    >>> from targetacq import Simulation
    >>> from targetacq.scenario.schema import Background, Sensor, Target
    >>> sim = Simulation(
    ...     [Sensor(name="ir", band="lwir", ifov=0.25e-3, position=(0.0, 0.0, 5.0))],
    ...     [Target(name="truck", dimensions=(7.0, 2.5, 3.0), temperature=305.0,
    ...             position=(0.0, 0.0, 0.0))],
    ...     background=Background(temperature=295.0),
    ...     seed=7,
    ... )
    >>> out = sim.step(0.0, 0.1, np.array([[0.0, 0.0, 5.0]]), np.array([[2000.0, 0.0, 0.0]]))
    >>> out.detection.shape, bool(out.detected[0, 0])
    ((1, 1), False)
    """

    def __init__(
        self,
        sensors: Sequence[Any],
        targets: Sequence[Any],
        background: Any = None,
        atmosphere: Any = None,
        model: Any = None,
        seed: int = 0,
        engine: str = "numpy",
        false_targets: Any = None,
        terrain: Any = None,
        *,
        observer_spread: float = 0.0,
    ) -> None:
        chosen = engines.for_steps(engine)
        for name, items in (("sensors", sensors), ("targets", targets)):
            if isinstance(items, (str, bytes, Mapping)) or not isinstance(items, Sequence):
                raise ScenarioError(
                    f"{name} must be a list of records (mappings or targetacq.scenario.schema "
                    f"objects), got {type(items).__name__}"
                )
        sensors = [_record(s) for s in sensors]
        targets = [_record(t) for t in targets]
        for k, sensor in enumerate(sensors):
            if not isinstance(sensor, (Mapping, Sensor)):
                raise ScenarioError(
                    f"sensors[{k}]: a sensor is a targetacq.scenario.schema.Sensor or a mapping of "
                    f"its "
                    f"fields (name, band, ...), got {type(sensor).__name__} {sensor!r:.40}"
                )
            kind = sensor.get("type", "thermal") if isinstance(sensor, Mapping) else sensor.type
            try:
                get_sensor_type(kind)
            except ValueError as error:
                raise ScenarioError(f"sensors[{k}].type: {error}") from None
        data: dict[str, Any] = {"sensors": sensors, "targets": targets}
        for name, value in (("background", background), ("atmosphere", atmosphere)):
            if value is not None:
                data[name] = value
        if model is not None:
            data["model"] = model
        if false_targets is not None:
            data["false_targets"] = false_targets
        if terrain is not None:
            data["terrain"] = terrain
        try:
            scenario = Scenario.model_validate(data)
        except ValidationError as error:
            raise ScenarioError(f"Simulation: {_located(error)}") from None
        self._setup(scenario, seed, chosen, observer_spread)

    @classmethod
    def from_scenario(
        cls,
        scenario: Scenario | str | Path,
        seed: int = 0,
        engine: str = "numpy",
        *,
        observer_spread: float = 0.0,
    ) -> Simulation:
        """A simulation of a scenario's sensors, targets, background, atmosphere and model.

        Parameters
        ----------
        scenario : targetacq.scenario.schema.Scenario or path
            A validated scenario, or a scenario file
            (:func:`targetacq.scenario.schema.load_scenario`). Its positions, waypoints and time
            grid are not used: the steps give the positions
            (:func:`targetacq.core.scenario_positions` turns its scripted paths into them).
        seed : int
            >= 0.
        engine, observer_spread
            As for :class:`Simulation`.

        Returns
        -------
        Simulation
        """
        chosen = engines.for_steps(engine)
        if not isinstance(scenario, Scenario):
            scenario = load_scenario(scenario)
        sim = cls.__new__(cls)
        sim._setup(scenario, seed, chosen, observer_spread)
        return sim

    def _setup(
        self, scenario: Scenario, seed: int, engine: engines.Engine, observer_spread: float = 0.0
    ) -> None:
        self.observer_spread = Uncertainty(observer_spread=observer_spread).observer_spread
        self._engine, self._observer = engine, 1.0
        self.scenario = scenario
        self.compiled = core.compile_scenario(scenario)
        scene = self.compiled.scene
        self._scene = scene
        self._bound = engine.bind(scene)
        self.engine: str = self._bound.engine
        self._terrain = self.compiled.terrain
        self._elevation = self.compiled.elevation
        self._jax_scene: Any = None
        self._subsets: dict[bytes, tuple[Any, Any, np.ndarray]] = {}
        self._signal = np.asarray(scene.signature.target)
        self._ifov = np.asarray(scene.sensors.ifov)
        self.sensors: tuple[str, ...] = tuple(scene.sensors.names)
        self.targets: tuple[str, ...] = tuple(scene.targets.names)
        self._shape = (len(self.sensors), len(self.targets))
        # The bands of a colour camera draw from the camera's streams: one look, not several.
        self._stream_names = scene.sensors.group_names
        self._streams = Streams(check_seed(seed), self._stream_names, self.targets)
        none = np.empty(0, dtype=np.int64)
        self._empty = Events(none, none, none, np.empty(0), none, self.sensors, self.targets)
        self._false = self._false_targets(self.seed)
        self.reset()

    def _false_targets(self, seed: int) -> FalseTargetSampler | None:
        table = self.scenario.false_targets
        if table is None:
            return None
        try:
            elevation = self.compiled.elevation
            return FalseTargetSampler(
                table,
                self._scene.sensors,
                self._scene.choices.search_time,
                seed,
                None if elevation is None else (elevation, self.compiled.earth_radius_factor),
            )
        except ValueError as error:
            raise ScenarioError(str(error)) from None

    @property
    def seed(self) -> int:
        """The seed of the random outcomes."""
        return self._streams.seed

    @property
    def time(self) -> float | None:
        """The last step's time [s], or None before the first step."""
        return None if self._state.p is None else self._state.time

    def reset(self, seed: int | None = None, run: int = 0) -> None:
        """Start again: forget the state, and the next step is a first step.

        Parameters
        ----------
        seed : int, optional
            A new seed (>= 0); default: keep the current one.
        run : int
            Which run of the seed's counter-based streams, >= 0 (run ``r`` equals run ``r`` of
            :func:`targetacq.run.search.simulate`).
        """
        if seed is not None and check_seed(seed) != self._streams.seed:
            self._streams = Streams(seed, self._stream_names, self.targets)
            self._false = self._false_targets(self._streams.seed)
        if not isinstance(run, (int, np.integer)) or isinstance(run, bool) or not 0 <= run < 2**32:
            raise ValueError(f"run must be an integer in [0, 2**32), got {run!r}")
        model = self.scenario.model
        self._state = SearchState(
            self._streams,
            np.array([run]),
            self._scene.choices.search_time,
            model.redraw,
            model.decorrelation_time,
        )
        self._previous: tuple[np.ndarray, np.ndarray, np.ndarray | None] | None = None
        self._warned = False
        self._observe(observer_factor(self.observer_spread, self.seed, int(run)))

    @property
    def observer(self) -> float:
        """This run's observer: the factor on every N50 (1.0 without ``observer_spread``)."""
        return self._observer

    def _observe(self, factor: float) -> None:
        """Evaluate with the compiled scene's N50s times ``factor`` (the engine bound again)."""
        if factor == self._observer:
            return
        nominal = self.compiled.scene
        targets = dataclasses.replace(nominal.targets, n50=np.asarray(nominal.targets.n50) * factor)
        self._scene = dataclasses.replace(nominal, targets=targets)
        self._bound = self._engine.bind(self._scene)
        self._jax_scene = None
        self._subsets.clear()
        self._observer = factor

    # -- the pure part -------------------------------------------------------------------------

    def _inputs(
        self,
        sensor_positions: Any,
        target_positions: Any,
        headings: Any,
        pointing: Any,
        n_targets: int | None = None,
    ) -> tuple[Any, Any, Any, Any]:
        """Check the shapes (on ``.shape`` only, so traced arrays pass) and make arrays.

        ``n_targets``: the targets' rows expected (default the simulation's targets)."""
        given = (sensor_positions, target_positions, headings, pointing)
        names = [n for n, v in zip(_INPUT_NAMES, given, strict=True) if v is not None]
        xp, arrays = _arrays.arrays(
            *(v for v in given if v is not None), names=names, broadcast=False
        )
        values = iter(arrays)
        s_pos, t_pos, head, point = (None if v is None else next(values) for v in given)
        n_s = self._shape[0]
        n_g = self._shape[1] if n_targets is None else n_targets
        for name, value, shape, what in (
            ("sensor_positions", s_pos, (n_s, 3), "(n_sensors, 3): east, north, up [m]"),
            ("target_positions", t_pos, (n_g, 3), "(n_targets, 3): east, north, up [m]"),
            ("target_headings", head, (n_g,), "(n_targets,) [rad]"),
            ("sensor_pointing", point, (n_s, 2), "(n_sensors, 2): azimuth, depression [rad]"),
        ):
            if value is None or tuple(value.shape) == shape:
                continue
            got = tuple(value.shape)
            if len(shape) == 2 and len(got) >= 1 and got[-1] != shape[1]:
                raise ValueError(
                    f"{name}: the last dimension must be {shape[1]}, got shape {got}; "
                    f"expected {shape} = {what}"
                )
            raise ValueError(f"{name} must have shape {shape} = {what}, got {got}")
        # Positions are checked finite by the core (core.factors); NaN anywhere gives NaN.
        if head is not None:
            _arrays.require_in_range(
                "target_headings", head, xp, -MAX_ANGLE_TURN, MAX_ANGLE_TURN, "rad"
            )
        if point is not None:
            self._check_pointing(point, xp)
        if self._scene.sensors.groups and isinstance(s_pos, np.ndarray):
            self._check_bands(s_pos, point)
        return s_pos, t_pos, head, point

    def _per_step(self, moving: Any, visible_fraction: Any) -> dict[str, Any]:
        """The per-step inputs given, checked: ``moving`` (n_targets,) bool and
        ``visible_fraction`` (n_targets,) or (n_sensors, n_targets) in (0, 1] or NaN."""
        given: dict[str, Any] = {}
        n_s, n_g = self._shape
        if moving is not None:
            flags = np.asarray(moving)
            if flags.shape != (n_g,) or flags.dtype != np.bool_:
                raise ValueError(
                    f"moving must be a bool array of shape ({n_g},) = (n_targets,), got "
                    f"{flags.dtype} of shape {flags.shape}"
                )
            given["moving"] = flags
        if visible_fraction is not None:
            fraction = np.asarray(visible_fraction, dtype=float)
            if fraction.shape not in ((n_g,), (n_s, n_g)):
                raise ValueError(
                    f"visible_fraction must have shape ({n_g},) = (n_targets,) or ({n_s}, {n_g}) "
                    f"= (n_sensors, n_targets), got {fraction.shape}"
                )
            bad = ~np.isnan(fraction) & ~((fraction > 0) & (fraction <= 1))
            if bad.any():
                raise ValueError(
                    f"visible_fraction must be in (0, 1] (or NaN), got {fraction[bad][0]!r}"
                )
            given["visible_fraction"] = fraction
        return given

    def _terrain_view(
        self, scene: Any, s_pos: np.ndarray, t_pos: np.ndarray, per_step: Mapping[str, Any]
    ) -> tuple[dict[str, Any], np.ndarray]:
        """The per-step inputs with each pair's visible fraction over the ``[terrain]``
        relief, and the pairs it hides entirely (n_s, n_g)
        (:func:`targetacq.core.terrain_view.terrain_view`: the smaller of the terrain's and the
        occlusion the fraction already says, the targets' own or the one given to the step)."""
        assert self._elevation is not None
        own = per_step.get("visible_fraction")
        view = terrain_view(
            self._elevation,
            self.compiled.earth_radius_factor,
            s_pos,
            t_pos,
            np.asarray(scene.targets.dimensions, dtype=float)[:, 2],
            scene.targets.visible_fraction if own is None else own,
        )
        return {**per_step, "visible_fraction": view.visible_fraction}, view.hidden

    def _check_bands(self, s_pos: np.ndarray, point: Any) -> None:
        """The bands of a colour camera are one camera: one position and one pointing."""
        groups = self._scene.sensors.groups
        for name in dict.fromkeys(groups):
            rows = [k for k, g in enumerate(groups) if g == name]
            for label, value in (("sensor_positions", s_pos), ("sensor_pointing", point)):
                if value is None:
                    continue
                part = np.asarray(value)[rows]
                if not np.array_equal(part, np.broadcast_to(part[:1], part.shape), equal_nan=True):
                    raise ValueError(
                        f"{label}: the rows of colour camera {name!r} (rows {rows[0]} to "
                        f"{rows[-1]}, one per band) must be equal: the bands are one camera"
                    )

    @staticmethod
    def _check_pointing(point: Any, xp: Any) -> None:
        """Azimuths within a turn, depressions within ±90°; a row NaN in both or in neither."""
        azimuth, depression = point[:, 0], point[:, 1]
        if _arrays.any_known(xp.isnan(azimuth) != xp.isnan(depression), xp):
            raise ValueError(
                "sensor_pointing: give both the azimuth and the depression of a sensor, or NaN "
                "for both (the sensor keeps its own pointing)"
            )
        _arrays.require_in_range(
            "sensor_pointing azimuth", azimuth, xp, -MAX_ANGLE_TURN, MAX_ANGLE_TURN, "rad"
        )
        _arrays.require_in_range(
            "sensor_pointing depression", depression, xp, -MAX_DEPRESSION, MAX_DEPRESSION, "rad"
        )

    def _evaluate(
        self,
        inputs: tuple[Any, Any, Any, Any],
        per_step: Mapping[str, Any] | None = None,
        subset: tuple[Any, Any, np.ndarray] | None = None,
    ) -> tuple[Any, Any]:
        """Factors and probabilities of the scene (or of ``subset``: a scene of picked targets,
        its bound engine and the picked indices) at the inputs, with the per-step inputs."""
        s_pos, t_pos, head, point = inputs
        scene, bound = (self._scene, self._bound) if subset is None else subset[:2]
        per_step = per_step or {}
        if isinstance(s_pos, np.ndarray) and isinstance(t_pos, np.ndarray):
            hidden = None
            if self._elevation is not None:
                per_step, hidden = self._terrain_view(scene, s_pos, t_pos, per_step)
            if per_step:
                found = bound.factors(
                    s_pos, t_pos, head, point, visible_fraction=per_step.get("visible_fraction")
                )
            else:
                found = bound.factors(s_pos, t_pos, head, point)
            if self._terrain is not None:
                signal = self._signal if subset is None else self._signal[:, subset[2]]
                scr = footprint_scr(self._terrain, found.range, t_pos, signal, self._ifov)
                found = dataclasses.replace(found, scr=scr)
            if hidden is not None:  # behind the terrain: out of that sensor's view
                found = hide(found, hidden)
            velocities = per_step.get("target_velocities")
            if velocities is not None:  # graded motion: each pair's speed across its sight
                found = dataclasses.replace(
                    found, crossing_speed=core.crossing_speeds(s_pos, t_pos, velocities)
                )
            if "moving" in per_step:
                return found, bound.probabilities(found, moving=per_step["moving"])
            return found, bound.probabilities(found)
        if self._terrain is not None:
            raise ValueError(
                "a scenario with a terrain map (background.terrain) is evaluated with NumPy "
                "arrays only: its clutter is looked up in the map per position on the host"
            )
        if self._elevation is not None:
            raise ValueError(
                "a scenario with an elevation model ([terrain]) is evaluated with NumPy arrays "
                "only: its lines of sight are traced over the grid on the host"
            )
        # JAX arrays (or tracers): the scene's arrays in JAX too, made once.
        from targetacq.core import records

        if subset is None:
            if self._jax_scene is None:
                self._jax_scene = records.as_jax(self._scene)
            jax_scene = self._jax_scene
        else:
            jax_scene = records.as_jax(scene)
        return core.evaluate(jax_scene, s_pos, t_pos, head, point, **per_step)

    def probabilities(
        self,
        time: Any,
        sensor_positions: Array,
        target_positions: Array,
        target_headings: Array = None,
        sensor_pointing: Array = None,
    ) -> core.Probabilities:
        """The probabilities of every pair at positions: pure (no draws, no change of state).

        Only the array core runs on the inputs (:func:`targetacq.core.evaluate`), so NumPy
        arrays give NumPy and JAX arrays give JAX, under ``jax.jit`` too: with JAX positions
        the core gets the scene in JAX arrays (:func:`targetacq.core.records.as_jax`, made
        once). A scenario with a terrain map needs NumPy arrays. Positions alone carry no
        velocity: targets with a graded motion cue are taken as standing still here (their
        motion is graded in :meth:`targetacq.Simulation.step`, or by
        :func:`targetacq.core.evaluate` with ``target_velocities``).

        Parameters
        ----------
        time : float
            [s]. The compiled signatures do not change with time; it is checked (finite) and
            names the moment.
        sensor_positions : array (n_sensors, 3)
            East, north, up [m].
        target_positions : array (n_targets, 3)
            [m]; a NaN row gives NaN probabilities for that target.
        target_headings : array (n_targets,), optional
            Direction of each target's long axis [rad]; default the targets' own heading.
        sensor_pointing : array (n_sensors, 2), optional
            Azimuth (from north, clockwise) and depression [rad]; default the scenario's own
            pointing (look_at, azimuth and depression, or none); a NaN row keeps that sensor's
            own pointing.

        Returns
        -------
        targetacq.core.Probabilities
            ``detection``, ``recognition``, ``identification`` (n_sensors, n_targets) and
            ``fused_detection``, ``fused_recognition``, ``fused_identification`` (n_targets,).

        Raises
        ------
        ValueError
            A non-finite time, or arrays of the wrong shape.

        Examples
        --------
        >>> import numpy as np
        >>> from targetacq import Simulation
        >>> from targetacq.scenario.schema import Background, Sensor, Target
        >>> sim = Simulation(
        ...     [Sensor(name="ir", band="lwir", ifov=0.25e-3, position=(0.0, 0.0, 5.0))],
        ...     [Target(name="truck", dimensions=(7.0, 2.5, 3.0), temperature=305.0,
        ...             position=(0.0, 0.0, 0.0))],
        ...     background=Background(temperature=295.0),
        ... )
        >>> p = sim.probabilities(0.0, np.zeros((1, 3)), np.array([[1500.0, 0.0, 0.0]]))
        >>> bool(p.detection[0, 0] >= p.recognition[0, 0] >= p.identification[0, 0])
        True
        """
        if not _arrays.is_traced(time):
            self._check_time(time)
        inputs = self._inputs(sensor_positions, target_positions, target_headings, sensor_pointing)
        return self._evaluate(inputs)[1]

    def _subset(self, index: np.ndarray) -> tuple[Any, Any, np.ndarray]:
        """The scene of the targets ``index`` and its bound engine (the last few kept)."""
        key = index.tobytes()
        found = self._subsets.get(key)
        if found is None:
            scene = core.take_targets(self._scene, index)
            found = (scene, engines.get_engine(self.engine).bind(scene), index)
            if len(self._subsets) >= 8:
                self._subsets.pop(next(iter(self._subsets)))
            self._subsets[key] = found
        return found

    def probabilities_at(
        self,
        time: Any,
        sensor_positions: Array,
        target_positions: Array,
        targets: Array,
        target_headings: Array = None,
        sensor_pointing: Array = None,
    ) -> core.Probabilities:
        """The probabilities of targets at arbitrary positions: pure (no draws, no state).

        For a tracker asking "P_d of this track at x" or a planner asking "what if it were
        there": each query is a target (its signature, size and criterion) at a position, a
        target may be asked at several positions at once, and each is seen by every sensor.
        Equal to :meth:`probabilities` where the positions are the targets' own.

        Parameters
        ----------
        time : float
            [s], finite (names the moment, as for :meth:`probabilities`).
        sensor_positions : array (n_sensors, 3)
            East, north, up [m].
        target_positions : array (M, 3)
            Where each query puts its target [m].
        targets : array of int (M,)
            Which target each query is (indices into :attr:`targets`; repeats allowed).
        target_headings : array (M,), optional
            [rad]; default each target's own heading.
        sensor_pointing : array (n_sensors, 2), optional
            As for :meth:`probabilities`.

        Returns
        -------
        targetacq.core.Probabilities
            ``detection``, ``recognition``, ``identification`` (n_sensors, M) and the fused
            ones (M,).

        Raises
        ------
        ValueError
            ``targets`` not integers in [0, n_targets), or arrays of the wrong shape.

        Examples
        --------
        >>> import numpy as np
        >>> from targetacq import Simulation
        >>> from targetacq.scenario.schema import Background, Sensor, Target
        >>> sim = Simulation(
        ...     [Sensor(name="ir", band="lwir", ifov=0.25e-3, position=(0.0, 0.0, 5.0))],
        ...     [Target(name="truck", dimensions=(7.0, 2.5, 3.0), temperature=305.0,
        ...             position=(0.0, 0.0, 0.0))],
        ...     background=Background(temperature=295.0),
        ... )
        >>> tracks = np.array([[1000.0, 0.0, 0.0], [3000.0, 0.0, 0.0]])
        >>> p = sim.probabilities_at(0.0, np.zeros((1, 3)), tracks, np.array([0, 0]))
        >>> p.detection.shape, bool(p.detection[0, 0] > p.detection[0, 1])
        ((1, 2), True)
        """
        if not _arrays.is_traced(time):
            self._check_time(time)
        index = np.asarray(targets)
        n_g = self._shape[1]
        if (
            index.ndim != 1
            or not (np.issubdtype(index.dtype, np.integer) or index.size == 0)
            or (index.size and not (index.min() >= 0 and index.max() < n_g))
        ):
            raise ValueError(
                f"targets must be a 1-d array of integer indices in [0, {n_g}) (the targets: "
                f"{', '.join(self.targets[:5])}{', ...' if n_g > 5 else ''}), got "
                f"{index.dtype} of shape {index.shape}"
                + (f" with values {index.min()} to {index.max()}" if index.size else "")
            )
        index = index.astype(np.int64)
        inputs = self._inputs(
            sensor_positions, target_positions, target_headings, sensor_pointing, index.size
        )
        return self._evaluate(inputs, subset=self._subset(index))[1]

    @staticmethod
    def _check_time(time: Any, name: str = "time") -> float:
        """A time [s] as a float: a real number (TypeError otherwise), finite (ValueError)."""
        value = _arrays.as_float(time, _arrays.namespace(), name)
        if value.ndim != 0:
            raise ValueError(f"{name} must be one number of seconds, got shape {value.shape}")
        return check_finite(name, value)

    # -- the step ------------------------------------------------------------------------------

    def _step_arrays(
        self, inputs: tuple[Any, Any, Any, Any], per_step: Mapping[str, Any] | None
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """In view (n_s, n_g), the probabilities (3, n_s, n_g) and their fusion (3, n_g) of a
        step, as fresh NumPy arrays: the bound engine's one-call step for NumPy positions
        without a terrain map (whose clutter needs every pair's range), else the core's factors
        and probabilities."""
        s_pos, t_pos, head, point = inputs
        per_step = per_step or {}
        if (
            self._terrain is None
            and self._elevation is None  # lines of sight: the factors' path
            and "target_velocities" not in per_step  # graded motion: the factors' path
            and isinstance(s_pos, np.ndarray)
            and isinstance(t_pos, np.ndarray)
        ):
            in_view, p3, fused = self._bound.step(s_pos, t_pos, head, point, **per_step)
            return np.asarray(in_view, dtype=bool), np.asarray(p3), np.asarray(fused)
        found, probs = self._evaluate(inputs, per_step)
        p3 = np.stack([np.asarray(getattr(probs, task), dtype=float) for task in TASKS])
        fused = np.stack(
            [np.asarray(getattr(probs, f"fused_{task}"), dtype=float) for task in TASKS]
        )
        in_view = np.broadcast_to(np.asarray(found.in_view, dtype=bool), self._shape).copy()
        return in_view, p3, fused

    def step(
        self,
        time: float,
        dt: float,
        sensor_positions: Any,
        target_positions: Any,
        target_headings: Any = None,
        sensor_pointing: Any = None,
        *,
        moving: Array = None,
        visible_fraction: Array = None,
        target_velocities: Array = None,
    ) -> StepResult:
        """Advance over ``(time − dt, time]`` with the positions at ``time``.

        See the module docstring for the law. Host-side (NumPy): JAX inputs are evaluated by
        the core and brought to the host for the draws.

        Parameters
        ----------
        time : float
            [s], not before the previous step's time.
        dt : float
            [s], >= 0; ``time − dt`` must be the previous step's time (any value on the first
            step after a reset, which only starts the clock).
        sensor_positions, target_positions, target_headings, sensor_pointing
            As for :meth:`probabilities`.
        moving : array of bool (n_targets,), optional
            Whether each target moves at ``time`` (the motion rule,
            :data:`targetacq.acquisition.probabilities.MOTION_RULES`); default the targets' own
            ``moving``.
        visible_fraction : array (n_targets,) or (n_sensors, n_targets), optional
            Fraction of each target's height in view at ``time``, in (0, 1] (occlusion from
            the caller's own world; NaN: unknown, NaN probabilities); default the targets' own.
            With a ``[terrain]`` elevation model, each pair sees the smaller of this and the
            fraction above the terrain (:meth:`_terrain_view`), and a pair the terrain hides
            is out of view.
        target_velocities : array (n_targets, 3), optional
            Each target's velocity over the ground at ``time`` [m/s] (east, north, up), for the
            targets with a graded motion cue (``graded_motion``): their angular speed across
            each sensor's line of sight weights the motion rule
            (:func:`targetacq.core.crossing_speeds`). Default: the change of their positions
            over the step, ``(p(time) − p(time − dt)) / dt`` (0 on the first step after a
            reset). Ignored where no target has a graded motion cue.

        Returns
        -------
        StepResult

        Raises
        ------
        ValueError
            A non-finite time, a negative or non-finite ``dt``, a step back in time or one that
            does not start at the previous step, or arrays of the wrong shape.

        Warns
        -----
        targetacq.run.search.ShortVisitWarning
            Once per run (until the next reset), the first time a target is in a sensor's view
            for less than one step.

        Examples
        --------
        >>> import numpy as np
        >>> from targetacq import Simulation
        >>> from targetacq.scenario.schema import Background, Sensor, Target
        >>> sim = Simulation(
        ...     [Sensor(name="ir", band="lwir", ifov=0.25e-3, position=(0.0, 0.0, 5.0))],
        ...     [Target(name="truck", dimensions=(7.0, 2.5, 3.0), temperature=305.0,
        ...             position=(0.0, 0.0, 0.0))],
        ...     background=Background(temperature=295.0),
        ...     seed=3,
        ... )
        >>> sensor, truck = np.array([[0.0, 0.0, 5.0]]), np.array([[800.0, 0.0, 0.0]])
        >>> for k in range(601):  # one minute at 10 Hz
        ...     out = sim.step(0.1 * k, 0.1, sensor, truck)
        >>> bool(out.fused_detected[0]), [e.kind for e in out.events]
        (True, [])
        """
        t = self._check_time(time)
        dt = self._check_time(dt, "dt")
        if dt < 0:
            raise ValueError(f"dt must be >= 0 s, got {dt!r}")
        state = self._state
        if state.p is not None:
            if t < state.time:
                raise ValueError(
                    f"time must not go back: the previous step was at {state.time!r} s, got "
                    f"{t!r} s (reset() to start again)"
                )
            if abs((t - dt) - state.time) > 1e-9 * max(1.0, abs(t), abs(dt)):
                raise ValueError(
                    f"dt must be the time since the previous step ({t - state.time!r} s: "
                    f"{state.time!r} s to {t!r} s), got {dt!r} s"
                )
        inputs = self._inputs(sensor_positions, target_positions, target_headings, sensor_pointing)
        per_step = (
            self._per_step(moving, visible_fraction)
            if moving is not None or (visible_fraction is not None)
            else None
        )
        if any(self._scene.targets.graded_motion):
            velocities = self._target_velocities(target_velocities, inputs[1], t, dt)
            per_step = {**(per_step or {}), "target_velocities": velocities}
        in_view, p3, fused = self._step_arrays(inputs, per_step)
        started = state.p is not None and t > state.time
        current = (
            np.asarray(inputs[0], dtype=float),
            np.asarray(inputs[1], dtype=float),
            None if inputs[3] is None else np.asarray(inputs[3], dtype=float),
        )
        false = FalseDetections.empty()
        if self._false is not None and started:
            false = self._false.sample(
                state.index, state.time, t, state.runs[:, 0], current[0], current[2]
            )
        p = p3.reshape(3, -1)
        view = in_view.reshape(-1)
        crossings = None
        if started and self._previous is not None:
            changed = (view != state.view) & ~np.isnan(p[0])
            if changed.any():
                pairs = np.flatnonzero(changed)
                crossings = np.full(view.size, np.nan)
                crossings[pairs] = pair_crossings(
                    self._scene.sensors, self._previous, current, pairs, view[pairs]
                )
        self._previous = current
        interval = state.advance(t, p, view, crossings)
        if state.short is not None and not self._warned:
            self._warned = True
            warnings.warn(
                short_visit_message(state.short, self.sensors, self.targets),
                ShortVisitWarning,
                stacklevel=2,
            )
        done = np.isfinite(state.first[:, 0]).reshape(3, *self._shape)
        return StepResult(
            time=t,
            detection=p3[0],
            recognition=p3[1],
            identification=p3[2],
            fused_detection=fused[0],
            fused_recognition=fused[1],
            fused_identification=fused[2],
            in_view=in_view,
            detected=done[0],
            recognised=done[1],
            identified=done[2],
            fused_detected=done[0].any(axis=0),
            fused_recognised=done[1].any(axis=0),
            fused_identified=done[2].any(axis=0),
            events=self._events(interval),
            false_detections=false,
        )

    def _target_velocities(self, given: Any, positions: Any, time: float, dt: float) -> Any:
        """The targets' velocities of a step [m/s] (n_g, 3): ``given`` (checked), else the
        change of their positions since the previous step over ``dt`` (0 on a first step)."""
        n_g = self._shape[1]
        if given is not None:
            xp, (value,) = _arrays.arrays(given, names=("target_velocities",))
            if tuple(value.shape) != (n_g, 3):
                raise ValueError(
                    f"target_velocities must have shape ({n_g}, 3) = (n_targets, 3): east, "
                    f"north, up [m/s]; got {tuple(value.shape)}"
                )
            _arrays.require_finite("target_velocities", value, xp, "m/s")
            return value
        now = np.asarray(positions, dtype=float)
        state = self._state
        if self._previous is None or state.p is None or not time > state.time or not dt > 0:
            return np.zeros((n_g, 3))
        return (now - self._previous[1]) / dt

    def _events(self, interval: Any) -> Events:
        if interval is None:
            return self._empty
        times = interval.times[:, 0]  # (3, m): the one run
        task, column = np.nonzero(np.isfinite(times))
        if task.size == 0:
            return self._empty
        at = times[task, column]
        sensor, target = np.divmod(interval.pairs[column], self._shape[1])
        order = np.lexsort((task, target, sensor, at))
        kind = np.where(interval.first[:, 0][task, column], 0, 1)
        return Events(
            sensor=sensor[order],
            target=target[order],
            task=task[order],
            time=at[order],
            kind=kind[order],
            sensor_names=self.sensors,
            target_names=self.targets,
        )
