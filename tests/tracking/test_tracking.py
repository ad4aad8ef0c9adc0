"""targetacq.tracking: Stone Soup's detection probability and clutter density from the model."""

from __future__ import annotations

import datetime
import importlib
import math
import runpy
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("stonesoup")

from stonesoup.models.measurement.linear import LinearGaussian
from stonesoup.models.transition.linear import (
    CombinedLinearGaussianTransitionModel,
    ConstantVelocity,
)
from stonesoup.predictor.kalman import KalmanPredictor
from stonesoup.types.detection import Clutter, TrueDetection
from stonesoup.types.groundtruth import GroundTruthPath, GroundTruthState
from stonesoup.types.state import GaussianState, State
from stonesoup.types.track import Track
from stonesoup.updater.kalman import KalmanUpdater

from targetacq import Simulation
from targetacq.core import scenario_positions
from targetacq.tracking import (
    EPOCH,
    ScenarioGroundTruth,
    TargetacqDetectionModel,
    TargetacqDetectionSimulator,
    TargetacqPDAHypothesiser,
)

EXAMPLE = Path(__file__).parents[2] / "examples" / "track_with_stonesoup.py"

H, N_H, N_V, IFOV = 1000.0, 400, 300, 0.5e-3  # a camera looking straight down
DENSITY, PROBABILITY, SEARCH_TIME = 25e-6, 0.04, 2.0  # [1/m²], [-], [s]


def nadir(false_targets: bool = True, seed: int = 0, density: float = DENSITY) -> Simulation:
    """A camera 1 km up looking straight down, two vehicle types, clutter on the ground."""
    return Simulation(
        [
            {
                "name": "cam",
                "band": "lwir",
                "ifov": IFOV,
                "pixels": (N_H, N_V),
                "azimuth": 0.0,
                "depression": math.pi / 2,
                "position": (0.0, 0.0, H),
            }
        ],
        [
            {"name": "truck", "dimensions": (7.0, 2.5, 3.0), "temperature": 305.0},
            {"name": "jeep", "dimensions": (3.4, 1.6, 1.8), "temperature": 303.0},
        ],
        background={"temperature": 295.0},
        model={"search_time": SEARCH_TIME},
        false_targets=(
            {"density": density, "probability": PROBABILITY, "max_range": 10_000.0}
            if false_targets
            else None
        ),
        seed=seed,
    )


def at(seconds: float) -> datetime.datetime:
    return EPOCH + datetime.timedelta(seconds=seconds)


def test_import_without_stonesoup_says_how_to_install(monkeypatch) -> None:
    for name in [m for m in sys.modules if m == "stonesoup" or m.startswith("stonesoup.")]:
        monkeypatch.delitem(sys.modules, name)
    for name in [m for m in sys.modules if m.startswith("targetacq.tracking")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "stonesoup", None)  # import stonesoup raises ImportError
    with pytest.raises(ImportError, match=r"pip install 'targetacq\[tracking\]'"):
        importlib.import_module("targetacq.tracking")


def test_prob_detect_is_the_simulations_fused_probability_at_the_states_position() -> None:
    """Independently of the wrapping: the same numbers as Simulation.probabilities_at (and, for
    a target where it stands, Simulation.probabilities), for the model's target type."""
    sim = nadir()
    model = TargetacqDetectionModel(simulation=sim, scan_interval=1.0, target="jeep")
    sensors = np.array([[0.0, 0.0, H]])
    places = np.array([[0.0, 0.0], [40.0, -30.0], [90.0, 60.0], [150.0, 0.0], [500.0, 500.0]])
    for t, (x, y) in zip([0.0, 1.0, 2.5, 4.0, 7.0], places, strict=True):
        state = State(np.array([[x], [3.0], [y], [-1.0]]), timestamp=at(t))
        expected = sim.probabilities_at(t, sensors, np.array([[x, y, 0.0]]), np.array([1]))
        assert float(model.prob_detect(state)) == pytest.approx(
            float(expected.fused_detection[0]), rel=1e-12, abs=1e-300
        )
    # Where the jeep stands, probabilities_at is probabilities (the target's own position).
    where = np.array([[40.0, -30.0, 0.0], [40.0, -30.0, 0.0]])
    own = sim.probabilities(0.0, sensors, where).fused_detection[1]
    state = State(np.array([[40.0], [0.0], [-30.0], [0.0]]), timestamp=EPOCH)
    assert float(model.prob_detect(state)) == pytest.approx(float(own), rel=1e-12)
    # Inside the view a vehicle is seen; outside (the footprint is 200 m × 150 m) never.
    assert 0.0 < float(model.prob_detect(state)) <= 1.0
    outside = State(np.array([[500.0], [0.0], [500.0], [0.0]]), timestamp=EPOCH)
    assert float(model.prob_detect(outside)) == 0.0


def test_prob_detect_follows_a_moving_sensor() -> None:
    """A sensor function of time: the state is seen from where the sensor is at its time."""
    sim = nadir()
    model = TargetacqDetectionModel(
        simulation=sim,
        scan_interval=1.0,
        sensor_positions=lambda t: np.array([[100.0 * t, 0.0, H]]),
    )
    state = State(np.array([[500.0], [0.0], [0.0], [0.0]]), timestamp=at(5.0))
    assert float(model.prob_detect(state)) > 0.0  # the sensor is above it at 5 s
    assert float(model.prob_detect(State(state.state_vector, timestamp=EPOCH))) == 0.0


def test_clutter_density_is_the_expected_count_over_the_footprint_in_closed_form() -> None:
    """Straight down, the footprint is (h·n_h·IFOV) × (h·n_v·IFOV) (the half tangents are
    n·IFOV/2); the expected count of a Δt scan is density · A · probability · Δt / t_s, and
    the density per scan is that over A: density · probability · Δt / t_s."""
    dt = 0.5
    model = TargetacqDetectionModel(simulation=nadir(), scan_interval=dt)
    area = (H * N_H * IFOV) * (H * N_V * IFOV)  # 200 m × 150 m
    expected = DENSITY * area * PROBABILITY * dt / SEARCH_TIME
    assert model.clutter_area(EPOCH) == pytest.approx(area, rel=1e-9)
    assert model.expected_clutter(EPOCH) == pytest.approx(expected, rel=1e-9)
    assert model.clutter_spatial_density(EPOCH) == pytest.approx(
        DENSITY * PROBABILITY * dt / SEARCH_TIME, rel=1e-9
    )
    [(name, a, e)] = model.clutter_footprints(EPOCH)
    assert (name, a, e) == ("cam", pytest.approx(area, rel=1e-9), pytest.approx(expected))
    # Twice the height: four times the area and the count, the same density.
    higher = TargetacqDetectionModel(
        simulation=nadir(), scan_interval=dt, sensor_positions=np.array([[0.0, 0.0, 2 * H]])
    )
    assert higher.expected_clutter(EPOCH) == pytest.approx(4 * expected, rel=1e-9)
    assert higher.clutter_spatial_density(EPOCH) == pytest.approx(
        model.clutter_spatial_density(EPOCH), rel=1e-9
    )
    # Without a [false_targets] table there is no clutter.
    none = TargetacqDetectionModel(simulation=nadir(false_targets=False), scan_interval=dt)
    assert none.clutter_footprints(EPOCH) == []
    assert none.clutter_spatial_density(EPOCH) == 0.0


def test_hypothesiser_uses_the_predicted_states_prob_detect_and_the_scan_density() -> None:
    """A track outside the view has P_d 0: only the missed-detection hypothesis has weight; in
    view its missed-detection weight is 1 − P_d·P_G before normalising (Stone Soup's PDA)."""
    sim = nadir()
    model = TargetacqDetectionModel(simulation=sim, scan_interval=1.0)
    measurement = LinearGaussian(4, (0, 2), np.eye(2) * 25.0)
    predictor = KalmanPredictor(CombinedLinearGaussianTransitionModel([ConstantVelocity(0.1)] * 2))
    hypothesiser = TargetacqPDAHypothesiser(
        predictor=predictor,
        updater=KalmanUpdater(measurement),
        detection_model=model,
        normalise=False,
    )
    detection = TrueDetection(
        np.array([[10.0], [5.0]]),
        timestamp=at(1.0),
        measurement_model=measurement,
        groundtruth_path=GroundTruthPath(),
    )
    for x, seen in ((10.0, True), (2000.0, False)):
        track = Track([GaussianState(np.array([[x], [0.0], [5.0], [0.0]]), np.eye(4), EPOCH)])
        found = hypothesiser.hypothesise(track, {detection}, at(1.0))
        p_d = float(model.prob_detect(predictor.predict(track[-1], timestamp=at(1.0))))
        missed = next(h for h in found if not h)
        assert float(missed.probability) == pytest.approx(1 - p_d * hypothesiser.prob_gate)
        if seen:
            assert p_d > 0.0
            [hit] = [h for h in found if h]
            density = model.clutter_spatial_density(at(1.0))
            pdf = math.exp(-0.5 * 0.0) / (
                2 * math.pi * math.sqrt(np.linalg.det(hit.measurement_prediction.covar))
            )
            assert float(hit.probability) == pytest.approx(pdf * p_d / density, rel=1e-6)
        else:
            assert p_d == 0.0
            assert all(float(h.probability) == 0.0 for h in found if h)


def test_detector_reports_acquired_targets_and_the_steps_false_detections() -> None:
    """The detector's clutter is the simulation's own false detections of each step (a second,
    hand-stepped simulation with the same seed), its true detections are of targets some
    sensor holds in view, within a few sigmas of the truth."""
    times = np.arange(0.0, 30.0, 1.0)
    paths = [GroundTruthPath(id=name) for name in ("truck", "jeep")]
    starts = {"truck": (-60.0, 20.0), "jeep": (30.0, -40.0)}
    measurement = LinearGaussian(4, (0, 2), np.eye(2) * 4.0)
    model = TargetacqDetectionModel(simulation=nadir(seed=3, density=500e-6), scan_interval=1.0)

    def truth():
        for t in times:
            for path in paths:
                x, y = starts[path.id]
                path.append(GroundTruthState([x + 2.0 * t, 2.0, y, 0.0], timestamp=at(t)))
            yield at(t), set(paths)

    detector = TargetacqDetectionSimulator(
        groundtruth=truth(), detection_model=model, measurement_model=measurement, seed=5
    )
    scans = list(detector)
    hand = nadir(seed=3, density=500e-6)
    reported = 0
    for k, ((now, detections), t) in enumerate(zip(scans, times, strict=True)):
        assert now == at(t)
        positions = np.array([[*starts[n], 0.0] for n in ("truck", "jeep")])
        positions[:, 0] += 2.0 * t
        out = hand.step(t, 0.0 if k == 0 else 1.0, np.array([[0.0, 0.0, H]]), positions)
        clutter = sorted(
            d.state_vector[:, 0].tolist() for d in detections if isinstance(d, Clutter)
        )
        assert clutter == sorted(p[:2] for p in out.false_detections.position.tolist())
        true = [d for d in detections if isinstance(d, TrueDetection)]
        for d in true:
            g = ("truck", "jeep").index(d.metadata["target"])
            assert out.detected[0, g] and out.in_view[0, g]
            assert np.hypot(*(d.state_vector[:, 0] - positions[g, :2])) < 5 * 2.0
        reported += len(true)
    assert reported > 0
    assert sum(len([d for d in s[1] if isinstance(d, Clutter)]) for s in scans) > 0


def test_scenario_ground_truth_follows_the_scripted_paths() -> None:
    example = runpy.run_path(str(EXAMPLE), run_name="not_main")
    from targetacq.scenario.schema import Scenario

    scenario = Scenario.model_validate(example["SCENE"])
    times = [0.0, 10.0, 20.0]
    reader = ScenarioGroundTruth(scenario=scenario, times=times)
    scans = list(reader)
    _, positions, _ = scenario_positions(scenario, times)
    paths = {p.id: p for p in scans[-1][1]}
    assert set(paths) == {"truck", "jeep"}
    truck = np.array([s.state_vector[:, 0] for s in paths["truck"].states])
    assert truck[:, [0, 2]] == pytest.approx(positions[0, :, :2])
    assert truck[:, 3] == pytest.approx([10.0] * 3)  # 800 m north in 80 s


def test_bad_inputs_raise_value_errors_naming_them() -> None:
    sim = nadir()
    for bad in (0.0, -1.0, math.nan, math.inf, "1 s", True):
        with pytest.raises(ValueError, match="scan_interval"):
            TargetacqDetectionModel(simulation=sim, scan_interval=bad)
    with pytest.raises(ValueError, match=r"target must be one of .*truck, jeep.*'tank'"):
        TargetacqDetectionModel(simulation=sim, scan_interval=1.0, target="tank")
    for mapping in ((0,), (0, 0), (0, -1), (0, 1, 2, 3)):
        with pytest.raises(ValueError, match="position_mapping"):
            TargetacqDetectionModel(simulation=sim, scan_interval=1.0, position_mapping=mapping)
    with pytest.raises(ValueError, match=r"simulation must be a targetacq\.Simulation"):
        TargetacqDetectionModel(simulation="scene.toml", scan_interval=1.0)
    model = TargetacqDetectionModel(simulation=sim, scan_interval=1.0)
    with pytest.raises(ValueError, match=r"state\.timestamp must be a datetime"):
        model.prob_detect(State(np.zeros((4, 1)), timestamp=3.0))
    with pytest.raises(ValueError, match=r"position_mapping .* reaches past"):
        model.prob_detect(State(np.zeros((2, 1)), timestamp=EPOCH))
    measurement = LinearGaussian(4, (0, 2), np.eye(2))
    updater = KalmanUpdater(measurement)
    predictor = KalmanPredictor(CombinedLinearGaussianTransitionModel([ConstantVelocity(1.0)] * 2))
    with pytest.raises(ValueError, match="detection_model must be"):
        TargetacqPDAHypothesiser(predictor=predictor, updater=updater)
    with pytest.raises(ValueError, match="measurement_model must be"):
        TargetacqDetectionSimulator(
            groundtruth=iter(()), detection_model=model, measurement_model=None
        )
    for seed in (-1, 1.5):
        with pytest.raises(ValueError, match="seed must be an integer >= 0"):
            TargetacqDetectionSimulator(
                groundtruth=iter(()),
                detection_model=model,
                measurement_model=measurement,
                seed=seed,
            )
    stranger = GroundTruthPath([GroundTruthState([0.0, 0, 0, 0], timestamp=EPOCH)], id="tank")
    detector = TargetacqDetectionSimulator(
        groundtruth=iter([(EPOCH, {stranger})]),
        detection_model=model,
        measurement_model=measurement,
    )
    with pytest.raises(ValueError, match="groundtruth: path id 'tank' is no target"):
        list(detector)
    uneven = TargetacqDetectionSimulator(
        groundtruth=iter([(EPOCH, set()), (at(2.0), set())]),
        detection_model=model,
        measurement_model=measurement,
    )
    with pytest.raises(ValueError, match=r"not scan_interval \(1.0 s\) apart"):
        list(uneven)
    for times in ([], [0.0, 0.0], [0.0, math.nan]):
        with pytest.raises(ValueError, match="times"):
            ScenarioGroundTruth(scenario=sim.scenario, times=times)


def test_jpda_tracks_both_vehicles_of_the_example_without_false_tracks() -> None:
    """End to end (the example, 40 s of 1 s scans): a track on each vehicle, none on clutter,
    tracks within a few noise sigmas of the truth, and a clutter count consistent with the
    expected count from the model (Poisson, 4 sigmas)."""
    example = runpy.run_path(str(EXAMPLE), run_name="not_main")
    found = example["run"](duration=40.0)
    numbers = example["score"](found)
    assert numbers["tracks on vehicles"] == 2
    assert numbers["false tracks"] == 0
    assert numbers["mean position error [m]"] < 3 * example["NOISE"]
    expected = numbers["expected false detections"]
    assert abs(numbers["false detections"] - expected) < 4 * math.sqrt(expected)
