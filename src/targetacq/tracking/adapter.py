"""Stone Soup components backed by a :class:`targetacq.Simulation` (see the package's docstring).

Measurement space. The adapter works on the ground plane: a state's position is taken from its
state vector at ``position_mapping`` (east, north and optionally up [m]; up 0 where left out),
and clutter lies on the ground (``z = 0``) uniformly over the area in view, so its density in a
measurement space of (east, north) is

    ``λ = E[N] / A = density · probability · Δt / t_s``  [1/m²]

per scan of ``Δt`` seconds: ``E[N] = density · A · probability · Δt / t_s`` the expected false
detections of the scan (:func:`targetacq.run.false_targets.false_target_rate` times ``Δt``) and
``A`` the ground in view (:func:`targetacq.run.false_targets.ground_footprint`), summed over the
sensors that report false targets. A measurement model whose measurement is not a linear image of
the ground position (bearing and range, say) needs the density in its own space: divide ``E[N]``
by that volume instead (:meth:`TargetacqDetectionModel.clutter_footprints` gives both parts).

Detection. ``P_d`` of a state is targetacq's fused detection probability (8.4) of the model's
``target`` at the state's position, seen by every sensor at its position at the state's time:
zero outside every field of view, so a track that leaves the view coasts instead of being
dragged to clutter. It is the probability that an observer detects the target given time to
search (``P∞``); the detection simulator reports a target in a scan when a sensor has acquired it
and it is still in that sensor's view (the search model's detection or reacquisition events of
:meth:`targetacq.Simulation.step`), so over many runs a target in view long enough is reported
in a share ``P∞`` of them. Within one run the reports are not independent from scan to scan
(an acquired target stays reported): Stone Soup's PDA assumes they are.
"""

from __future__ import annotations

import datetime
import math
from collections.abc import Iterator, Sequence
from typing import Any

import numpy as np
from stonesoup.base import Base, Property
from stonesoup.buffered_generator import BufferedGenerator
from stonesoup.hypothesiser.probability import PDAHypothesiser
from stonesoup.models.measurement import MeasurementModel
from stonesoup.reader.base import GroundTruthReader
from stonesoup.simulator.base import DetectionSimulator
from stonesoup.types.detection import Clutter, Detection, TrueDetection
from stonesoup.types.groundtruth import GroundTruthPath, GroundTruthState
from stonesoup.types.numeric import Probability
from stonesoup.types.state import State

from targetacq.core import scenario_positions
from targetacq.run.false_targets import FalseTargetSampler
from targetacq.run.simulation import Simulation
from targetacq.scenario.schema import Scenario, load_scenario

__all__ = [
    "EPOCH",
    "ScenarioGroundTruth",
    "TargetacqDetectionModel",
    "TargetacqDetectionSimulator",
    "TargetacqPDAHypothesiser",
]

EPOCH = datetime.datetime(2000, 1, 1)
"""The moment of simulation time 0 s (Stone Soup's timestamps are datetimes)."""


def _seconds_since(epoch: datetime.datetime, timestamp: Any, name: str) -> float:
    """A Stone Soup timestamp (a datetime) as seconds since ``epoch``."""
    if not isinstance(timestamp, datetime.datetime):
        raise ValueError(
            f"{name} must be a datetime.datetime (seconds count from the model's epoch "
            f"{epoch.isoformat()}), got {type(timestamp).__name__} {timestamp!r:.40}"
        )
    return (timestamp - epoch).total_seconds()


class TargetacqDetectionModel(Base):
    """The probability of detection and the clutter of a targetacq simulation, for a tracker.

    Parameters
    ----------
    simulation : targetacq.Simulation
        The sensors, target types, background, atmosphere, model and ``[false_targets]``.
    scan_interval : float
        Δt [s], > 0: the time between the tracker's scans, over which false detections
        accumulate (the detection simulator's step).
    target : str, optional
        The target type whose ``P_d`` a track has (a name of ``simulation.targets``; default the
        first): a tracker does not know what it tracks.
    position_mapping : tuple of int
        Indices of east, north (and optionally up) [m] in a state vector; default ``(0, 2)``, the
        positions of Stone Soup's constant-velocity state ``[x, vx, y, vy]``.
    sensor_positions : array (n_sensors, 3) or callable, optional
        East, north, up [m] of each sensor (row of ``simulation.sensors``), or a function of the
        time [s] that gives them; default the scenario's own positions and waypoints
        (:func:`targetacq.core.scenario_positions`).
    sensor_pointing : array (n_sensors, 2) or callable, optional
        Azimuth and depression [rad] (or a function of the time [s]); default the sensors' own.
    epoch : datetime.datetime
        The moment of simulation time 0 s (default :data:`EPOCH`).

    Raises
    ------
    ValueError
        ``simulation`` not a :class:`targetacq.Simulation`, ``scan_interval`` not > 0 and finite,
        ``target`` not one of the simulation's targets, or ``position_mapping`` not 2 or 3
        distinct indices >= 0 (each message names the input).

    Examples
    --------
    >>> import numpy as np
    >>> from stonesoup.types.state import State
    >>> from targetacq import Simulation
    >>> from targetacq.scenario.schema import Background, Sensor, Target
    >>> from targetacq.tracking import EPOCH, TargetacqDetectionModel
    >>> sim = Simulation(
    ...     [Sensor(name="ir", band="lwir", ifov=0.1e-3, pixels=(640, 512), azimuth=1.5708,
    ...             depression=0.2, position=(0.0, 0.0, 500.0))],
    ...     [Target(name="truck", dimensions=(7.0, 2.5, 3.0), temperature=305.0,
    ...             position=(0.0, 0.0, 0.0))],
    ...     background=Background(temperature=295.0),
    ...     false_targets={"density": 20e-6, "probability": 0.02, "max_range": 5000.0},
    ... )
    >>> model = TargetacqDetectionModel(simulation=sim, scan_interval=1.0)
    >>> ahead = State(np.array([[2400.0], [0.0], [0.0], [0.0]]), timestamp=EPOCH)
    >>> behind = State(np.array([[-2400.0], [0.0], [0.0], [0.0]]), timestamp=EPOCH)
    >>> float(model.prob_detect(ahead)) > 0.5, float(model.prob_detect(behind))
    (True, 0.0)
    >>> round(model.clutter_spatial_density(EPOCH) * 1e6, 4)  # 20/km² · 0.02 · 1 s / 3.4 s
    0.1176
    """

    simulation: Simulation = Property(doc="The targetacq simulation (sensors, targets, model).")
    scan_interval: float = Property(doc="Time between scans [s], > 0.")
    target: str = Property(default=None, doc="The target type of a track (default the first).")
    position_mapping: tuple[int, ...] = Property(
        default=(0, 2), doc="Indices of east, north (and up) [m] in a state vector."
    )
    sensor_positions: Any = Property(
        default=None, doc="(n_sensors, 3) [m], or a function of time [s]; default scripted."
    )
    sensor_pointing: Any = Property(
        default=None, doc="(n_sensors, 2) [rad], or a function of time [s]; default own."
    )
    epoch: datetime.datetime = Property(default=EPOCH, doc="The moment of time 0 s.")

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        if not isinstance(self.simulation, Simulation):
            raise ValueError(
                f"simulation must be a targetacq.Simulation, got {type(self.simulation).__name__}"
            )
        interval = self.scan_interval
        if not (
            isinstance(interval, (int, float, np.floating, np.integer))
            and not isinstance(interval, bool)
            and math.isfinite(interval)
            and interval > 0
        ):
            raise ValueError(
                f"scan_interval must be a finite number of seconds > 0, got {interval!r}"
            )
        self.scan_interval = float(interval)
        names = self.simulation.targets
        if self.target is None:
            self.target = names[0]
        if self.target not in names:
            raise ValueError(
                f"target must be one of the simulation's targets ({', '.join(names)}), "
                f"got {self.target!r}"
            )
        self._target_index = np.array([names.index(self.target)])
        mapping = tuple(self.position_mapping)
        if not (
            len(mapping) in (2, 3)
            and all(isinstance(i, (int, np.integer)) and i >= 0 for i in mapping)
            and len(set(mapping)) == len(mapping)
        ):
            raise ValueError(
                "position_mapping must be 2 or 3 distinct indices >= 0 (east, north and "
                f"optionally up in a state vector), got {self.position_mapping!r}"
            )
        self.position_mapping = tuple(int(i) for i in mapping)
        if not isinstance(self.epoch, datetime.datetime):
            raise ValueError(f"epoch must be a datetime.datetime, got {self.epoch!r}")
        sim = self.simulation
        table = sim.scenario.false_targets
        scene = sim.compiled.scene
        self._false: FalseTargetSampler | None = (
            None
            if table is None
            else FalseTargetSampler(table, scene.sensors, scene.choices.search_time, sim.seed)
        )
        self._search_time = float(scene.choices.search_time)

    # -- time and geometry ---------------------------------------------------------------------

    def seconds(self, timestamp: datetime.datetime) -> float:
        """Simulation time [s] of a Stone Soup timestamp: seconds since :attr:`epoch`."""
        return _seconds_since(self.epoch, timestamp, "timestamp")

    def sensors_at(self, time: float) -> tuple[np.ndarray, np.ndarray | None]:
        """The sensors' positions (n_sensors, 3) [m] and pointing ((n_sensors, 2) [rad] or
        None: their own) at ``time`` [s]."""
        given = self.sensor_positions
        if given is None:
            positions = scenario_positions(self.simulation.scenario, [time])[0][:, 0, :]
        else:
            positions = np.asarray(given(time) if callable(given) else given, dtype=float)
        pointing = self.sensor_pointing
        if callable(pointing):
            pointing = pointing(time)
        return positions, None if pointing is None else np.asarray(pointing, dtype=float)

    def position(self, state: State) -> np.ndarray:
        """East, north, up [m] of a state (up 0 where ``position_mapping`` has two indices)."""
        vector = np.asarray(state.state_vector, dtype=float).reshape(-1)
        if max(self.position_mapping) >= vector.size:
            raise ValueError(
                f"position_mapping {self.position_mapping} reaches past the state vector of "
                f"{vector.size} elements"
            )
        out = np.zeros(3)
        out[: len(self.position_mapping)] = vector[list(self.position_mapping)]
        return out

    # -- detection -----------------------------------------------------------------------------

    def prob_detect(self, state: State) -> Probability:
        """``P_d`` of a (predicted) state: targetacq's fused detection probability of
        :attr:`target` at the state's position and time.

        Parameters
        ----------
        state : stonesoup.types.state.State
            With a timestamp (a datetime).

        Returns
        -------
        stonesoup.types.numeric.Probability
            :meth:`targetacq.Simulation.probabilities_at`'s ``fused_detection`` (0 outside every
            field of view; NaN for a NaN position).
        """
        time = _seconds_since(self.epoch, state.timestamp, "state.timestamp")
        positions, pointing = self.sensors_at(time)
        found = self.simulation.probabilities_at(
            time,
            positions,
            self.position(state)[None, :],
            self._target_index,
            sensor_pointing=pointing,
        )
        return Probability(float(np.asarray(found.fused_detection)[0]))

    # -- clutter -------------------------------------------------------------------------------

    def clutter_footprints(self, timestamp: datetime.datetime) -> list[tuple[str, float, float]]:
        """Each reporting sensor's ground in view and expected false detections per scan.

        Parameters
        ----------
        timestamp : datetime.datetime

        Returns
        -------
        list of (sensor, area, expected)
            The sensor's name, the ground area in its view within ``max_range`` [m²]
            (:func:`targetacq.run.false_targets.ground_footprint`) and its expected false
            detections in one scan, ``rate · scan_interval``
            (:func:`targetacq.run.false_targets.false_target_rate`); only sensors with ground in
            view, none without a ``[false_targets]`` table.
        """
        if self._false is None:
            return []
        positions, pointing = self.sensors_at(self.seconds(timestamp))
        return [
            (name, footprint.area, rate * self.scan_interval)
            for name, footprint, rate in self._false.footprints(positions, pointing)
        ]

    def expected_clutter(self, timestamp: datetime.datetime) -> float:
        """Expected false detections in one scan, all sensors together (see
        :meth:`clutter_footprints`)."""
        return float(sum(expected for _, _, expected in self.clutter_footprints(timestamp)))

    def clutter_area(self, timestamp: datetime.datetime) -> float:
        """The ground in view of the sensors that report false targets [m²] (summed)."""
        return float(sum(area for _, area, _ in self.clutter_footprints(timestamp)))

    def clutter_spatial_density(self, timestamp: datetime.datetime) -> float:
        """Clutter per scan per ground area in view [1/m²]: ``E[N] / A``.

        ``E[N]`` the expected false detections of a scan and ``A`` the ground in view
        (:meth:`expected_clutter`, :meth:`clutter_area`), which is
        ``density · probability · scan_interval / search_time`` wherever something is in view
        (the module docstring); 0 where nothing is (or without a ``[false_targets]`` table).
        Where the footprints of two sensors overlap the density there is their sum: this is the
        mean over the footprints.
        """
        found = self.clutter_footprints(timestamp)
        area = sum(a for _, a, _ in found)
        return float(sum(e for _, _, e in found) / area) if area > 0 else 0.0


class TargetacqPDAHypothesiser(PDAHypothesiser):
    """Stone Soup's PDA hypothesiser (for :class:`~stonesoup.dataassociator.probability.PDA` and
    :class:`~stonesoup.dataassociator.probability.JPDA`) with ``P_d`` of each track's predicted
    state and the clutter density of the scan from a :class:`TargetacqDetectionModel`.

    ``prob_detect`` is not used: each call predicts the track to the scan's time and takes
    ``detection_model.prob_detect`` of the prediction. ``clutter_spatial_density``, where given,
    is used as it is; else each scan's is ``detection_model.clutter_spatial_density`` at its time,
    and where that is 0 (nothing in view, or no ``[false_targets]``) Stone Soup's own estimate
    from the gate (``None``) stands in for it (the PDA divides by the density).

    Raises
    ------
    ValueError
        ``detection_model`` not a :class:`TargetacqDetectionModel`.

    Examples
    --------
    A track 2 km outside the view of a camera looking straight down has ``P_d = 0``: the
    missed-detection hypothesis takes all the weight.

    >>> import math
    >>> import numpy as np
    >>> from stonesoup.models.measurement.linear import LinearGaussian
    >>> from stonesoup.models.transition.linear import (
    ...     CombinedLinearGaussianTransitionModel, ConstantVelocity)
    >>> from stonesoup.predictor.kalman import KalmanPredictor
    >>> from stonesoup.types.detection import Detection
    >>> from stonesoup.types.state import GaussianState
    >>> from stonesoup.types.track import Track
    >>> from stonesoup.updater.kalman import KalmanUpdater
    >>> from targetacq import Simulation
    >>> from targetacq.tracking import EPOCH, TargetacqDetectionModel, TargetacqPDAHypothesiser
    >>> sim = Simulation(
    ...     [{"name": "cam", "band": "lwir", "ifov": 0.5e-3, "pixels": (640, 512),
    ...       "azimuth": 0.0, "depression": math.pi / 2, "position": (0.0, 0.0, 500.0)}],
    ...     [{"name": "truck", "dimensions": (7.0, 2.5, 3.0), "temperature": 305.0}],
    ...     background={"temperature": 295.0},
    ...     false_targets={"density": 1e-4, "probability": 0.05, "max_range": 1000.0},
    ... )
    >>> measurement = LinearGaussian(4, (0, 2), np.eye(2))
    >>> hypothesiser = TargetacqPDAHypothesiser(
    ...     predictor=KalmanPredictor(
    ...         CombinedLinearGaussianTransitionModel([ConstantVelocity(0.1)] * 2)),
    ...     updater=KalmanUpdater(measurement),
    ...     detection_model=TargetacqDetectionModel(simulation=sim, scan_interval=1.0),
    ... )
    >>> for x in (0.0, 2000.0):
    ...     track = Track([GaussianState([[x], [0.0], [0.0], [0.0]], np.eye(4), EPOCH)])
    ...     seen = Detection([[x], [0.0]], timestamp=EPOCH, measurement_model=measurement)
    ...     missed = next(h for h in hypothesiser.hypothesise(track, {seen}, EPOCH) if not h)
    ...     print(round(float(missed.probability), 3))
    0.0
    1.0
    """

    detection_model: TargetacqDetectionModel = Property(
        default=None, doc="Where P_d and the clutter density come from."
    )

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        if not isinstance(self.detection_model, TargetacqDetectionModel):
            raise ValueError(
                "detection_model must be a targetacq.tracking.TargetacqDetectionModel, got "
                f"{type(self.detection_model).__name__}"
            )

    def hypothesise(self, track: Any, detections: Any, timestamp: Any, **kwargs: Any) -> Any:
        """The PDA hypotheses of ``track`` (Stone Soup's), with ``P_d`` of the track predicted to
        ``timestamp`` and the scan's clutter density."""
        prediction = self.predictor.predict(track, timestamp=timestamp, **kwargs)
        density = self.clutter_spatial_density
        if density is None:
            density = self.detection_model.clutter_spatial_density(timestamp) or None
        scan = PDAHypothesiser(
            predictor=self.predictor,
            updater=self.updater,
            clutter_spatial_density=density,
            prob_detect=self.detection_model.prob_detect(prediction),
            prob_gate=self.prob_gate,
            include_all=self.include_all and density is not None,
            normalise=self.normalise,
        )
        return scan.hypothesise(track, detections, timestamp, **kwargs)


class ScenarioGroundTruth(GroundTruthReader):
    """The scripted paths of a scenario's targets (positions and waypoints), as Stone Soup
    ground truth: one :class:`~stonesoup.types.groundtruth.GroundTruthPath` per target, its
    ``id`` the target's name, with constant-velocity states ``[x, vx, y, vy]`` ([m], [m/s]; the
    velocity by central differences of the positions over ``times``).

    Parameters
    ----------
    scenario : targetacq.scenario.schema.Scenario or path
    times : sequence of float
        [s], increasing.
    epoch : datetime.datetime
        The moment of time 0 s (default :data:`EPOCH`).

    Raises
    ------
    ValueError
        ``times`` not finite and increasing (at least one).

    Examples
    --------
    The jeep of the bundled UAV scene drives 1.2 km east in 120 s:

    >>> from targetacq import example_path
    >>> from targetacq.tracking import ScenarioGroundTruth
    >>> truth = ScenarioGroundTruth(scenario=example_path("uav_haze.toml"), times=[0, 60, 120])
    >>> for time, paths in truth:
    ...     pass
    >>> jeep = next(p for p in paths if p.id == "jeep")
    >>> len(jeep), [round(float(v), 1) for v in jeep.state_vector.ravel()]
    (3, [1200.0, 10.0, 300.0, 0.0])
    """

    scenario: Any = Property(doc="A targetacq scenario or scenario file.")
    times: Sequence[float] = Property(doc="The scan times [s].")
    epoch: datetime.datetime = Property(default=EPOCH, doc="The moment of time 0 s.")

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        if not isinstance(self.scenario, Scenario):
            self.scenario = load_scenario(self.scenario)
        times = np.asarray(self.times, dtype=float)
        if times.ndim != 1 or times.size == 0 or not np.isfinite(times).all():
            raise ValueError(f"times must be a 1-d sequence of finite seconds, got {self.times!r}")
        if (np.diff(times) <= 0).any():
            raise ValueError("times must increase")
        self.times = times.tolist()

    @BufferedGenerator.generator_method
    def groundtruth_paths_gen(self) -> Iterator[tuple[datetime.datetime, set[GroundTruthPath]]]:
        times = np.asarray(self.times, dtype=float)
        _, positions, _ = scenario_positions(self.scenario, times)
        if times.size > 1:
            velocities = np.gradient(positions, times, axis=1)
        else:
            velocities = np.zeros_like(positions)
        paths = [GroundTruthPath(id=t.name) for t in self.scenario.targets]
        for k, t in enumerate(times.tolist()):
            now = self.epoch + datetime.timedelta(seconds=t)
            for g, path in enumerate(paths):
                x, y = positions[g, k, 0], positions[g, k, 1]
                vx, vy = velocities[g, k, 0], velocities[g, k, 1]
                path.append(GroundTruthState([x, vx, y, vy], timestamp=now))
            yield now, set(paths)


class TargetacqDetectionSimulator(DetectionSimulator):
    """Detections of a :class:`targetacq.Simulation` stepped along ground truth, for a tracker.

    At each time of ``groundtruth`` the simulation steps (:meth:`targetacq.Simulation.step`, the
    first step only starts the clock) with the sensors where ``detection_model`` puts them and
    each target where its path (``id`` a target's name) is at that time (NaN, nothing happens,
    where it has no state then). The scan yields:

    - one :class:`~stonesoup.types.detection.TrueDetection` per target that some sensor has
      acquired (a detection event, first or reacquired) and still holds in view: the sensor
      keeps a target from its detection until the target leaves its view, and must search for
      it again when it comes back. The measurement is ``measurement_model`` of the true state
      plus Gaussian noise of the model's covariance (drawn from ``seed``); metadata ``target``;
    - one :class:`~stonesoup.types.detection.Clutter` per false detection of the step
      (:attr:`targetacq.StepResult.false_detections`), at its ground position, with metadata
      ``sensor`` and ``time`` (its own time within the step [s]).

    Every detection has the scan's timestamp (a scan is one moment for the tracker).

    Parameters
    ----------
    groundtruth : stonesoup.reader.base.GroundTruthReader
        Paths whose ``id`` are target names (:class:`ScenarioGroundTruth`), at times
        ``scan_interval`` apart.
    detection_model : TargetacqDetectionModel
        The simulation, sensors and the state's positions.
    measurement_model : stonesoup.models.measurement.MeasurementModel
        A linear model of the state (e.g. ``LinearGaussian(4, (0, 2), noise_covar)``).
    seed : int
        Of the measurement noise, >= 0 (the simulation has its own seed).

    Raises
    ------
    ValueError
        A bad ``detection_model``, ``measurement_model`` or ``seed``; while reading, a path
        whose ``id`` is no target's name or times not ``scan_interval`` apart.

    Examples
    --------
    A camera 500 m up looking straight down at a truck standing under it, with clutter:

    >>> import math
    >>> import numpy as np
    >>> from stonesoup.models.measurement.linear import LinearGaussian
    >>> from stonesoup.types.detection import Clutter, TrueDetection
    >>> from targetacq import Simulation
    >>> from targetacq.tracking import (
    ...     ScenarioGroundTruth, TargetacqDetectionModel, TargetacqDetectionSimulator)
    >>> sim = Simulation(
    ...     [{"name": "cam", "band": "lwir", "ifov": 0.5e-3, "pixels": (640, 512),
    ...       "azimuth": 0.0, "depression": math.pi / 2, "position": (0.0, 0.0, 500.0)}],
    ...     [{"name": "truck", "dimensions": (7.0, 2.5, 3.0), "temperature": 305.0,
    ...       "position": (0.0, 0.0, 0.0)}],
    ...     background={"temperature": 295.0},
    ...     false_targets={"density": 1e-3, "probability": 0.05, "max_range": 1000.0},
    ...     seed=1,
    ... )
    >>> detector = TargetacqDetectionSimulator(
    ...     groundtruth=ScenarioGroundTruth(scenario=sim.scenario, times=np.arange(30.0)),
    ...     detection_model=TargetacqDetectionModel(simulation=sim, scan_interval=1.0),
    ...     measurement_model=LinearGaussian(4, (0, 2), np.eye(2)),
    ... )
    >>> scans = [detections for _, detections in detector]
    >>> any(isinstance(d, TrueDetection) for d in scans[-1])
    True
    >>> sum(isinstance(d, Clutter) for scan in scans for d in scan) > 0
    True
    """

    groundtruth: GroundTruthReader = Property(doc="Ground-truth paths; ids are target names.")
    detection_model: TargetacqDetectionModel = Property(doc="The simulation and sensors.")
    measurement_model: MeasurementModel = Property(doc="Linear Gaussian model of the state.")
    seed: int = Property(default=0, doc="Seed of the measurement noise, >= 0.")

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        if not isinstance(self.detection_model, TargetacqDetectionModel):
            raise ValueError(
                "detection_model must be a targetacq.tracking.TargetacqDetectionModel, got "
                f"{type(self.detection_model).__name__}"
            )
        if not isinstance(self.measurement_model, MeasurementModel):
            raise ValueError(
                "measurement_model must be a Stone Soup MeasurementModel (e.g. LinearGaussian), "
                f"got {type(self.measurement_model).__name__}"
            )
        if not (isinstance(self.seed, (int, np.integer)) and not isinstance(self.seed, bool)):
            raise ValueError(f"seed must be an integer >= 0, got {self.seed!r}")
        if self.seed < 0:
            raise ValueError(f"seed must be an integer >= 0, got {self.seed!r}")

    def _measure(self, vector: np.ndarray, noise: np.ndarray | bool, timestamp: Any) -> Any:
        state = State(vector.reshape(-1, 1), timestamp=timestamp)
        return self.measurement_model.function(state, noise=noise)

    def _ground_state(self, east: float, north: float) -> np.ndarray:
        """A state vector with a ground position (the rest 0), for clutter's measurement."""
        vector = np.zeros(self.measurement_model.ndim_state)
        vector[list(self.detection_model.position_mapping[:2])] = (east, north)
        return vector

    @BufferedGenerator.generator_method
    def detections_gen(self) -> Iterator[tuple[datetime.datetime, set[Detection]]]:
        model = self.detection_model
        sim = model.simulation
        sim.reset()
        rng = np.random.default_rng(self.seed)
        n_s, n_g = len(sim.sensors), len(sim.targets)
        held = np.zeros((n_s, n_g), dtype=bool)
        covariance = np.asarray(self.measurement_model.covar(), dtype=float)
        zero = np.zeros(covariance.shape[0])
        previous: float | None = None
        for now, paths in self.groundtruth:
            t = model.seconds(now)
            truth: dict[int, tuple[GroundTruthPath, Any]] = {}
            for path in paths:
                if path.id not in sim.targets:
                    raise ValueError(
                        f"groundtruth: path id {path.id!r} is no target of the simulation "
                        f"({', '.join(sim.targets)})"
                    )
                if path.states and path.state.timestamp == now:
                    truth[sim.targets.index(path.id)] = (path, path.state)
            positions = np.full((n_g, 3), np.nan)
            for g, (_, state) in truth.items():
                positions[g] = model.position(state)
            dt = 0.0 if previous is None else t - previous
            if previous is not None and not math.isclose(
                dt, model.scan_interval, rel_tol=1e-6, abs_tol=1e-9
            ):
                raise ValueError(
                    f"groundtruth: times {previous!r} s and {t!r} s are not scan_interval "
                    f"({model.scan_interval!r} s) apart: the clutter density is per scan"
                )
            previous = t
            sensors, pointing = model.sensors_at(t)
            out = sim.step(t, dt, sensors, positions, sensor_pointing=pointing)
            found = out.events.task == 0
            held[out.events.sensor[found], out.events.target[found]] = True
            held &= out.in_view
            detections: set[Detection] = set()
            for g in np.flatnonzero(held.any(axis=0)).tolist():
                if g not in truth:
                    continue
                path, state = truth[g]
                noise = rng.multivariate_normal(zero, covariance).reshape(-1, 1)
                detections.add(
                    TrueDetection(
                        self._measure(np.asarray(state.state_vector, float), noise, now),
                        timestamp=now,
                        measurement_model=self.measurement_model,
                        groundtruth_path=path,
                        metadata={"target": sim.targets[g]},
                    )
                )
            for false in out.false_detections:
                vector = self._ground_state(false.position[0], false.position[1])
                detections.add(
                    Clutter(
                        self._measure(vector, False, now),
                        timestamp=now,
                        measurement_model=self.measurement_model,
                        metadata={"sensor": false.sensor, "time": false.time},
                    )
                )
            yield now, detections
