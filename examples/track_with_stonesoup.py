"""Track two vehicles with Stone Soup's JPDA, P_d and clutter density from targetacq.

A drone's thermal camera hovers 300 m up over two roads (``SCENE``: a truck 1.8 km away, a jeep
2.1 km away) among target-like clutter (a ``[false_targets]`` table). :class:`targetacq.Simulation`
steps the scene at 1 s scans along the scripted paths and
:class:`targetacq.tracking.TargetacqDetectionSimulator` gives the true detections of the
acquired vehicles in view (10 m measurement noise) and the false detections as clutter. A JPDA
tracker with a constant-velocity Kalman filter takes ``P_d`` of each track's predicted state and
the clutter density of each scan from :class:`targetacq.tracking.TargetacqPDAHypothesiser`.
Prints the tracks on vehicles and on clutter, their purity and the mean position error. Run:
``python examples/track_with_stonesoup.py [plot.png]`` (needs the ``tracking`` extra:
``pip install 'targetacq[tracking]'``).
"""

from __future__ import annotations

import math
import sys
from collections import Counter
from typing import Any

import numpy as np
from stonesoup.dataassociator.neighbour import GNNWith2DAssignment
from stonesoup.dataassociator.probability import JPDA
from stonesoup.deleter.error import CovarianceBasedDeleter
from stonesoup.hypothesiser.distance import DistanceHypothesiser
from stonesoup.initiator.simple import MultiMeasurementInitiator
from stonesoup.measures import Mahalanobis
from stonesoup.models.measurement.linear import LinearGaussian
from stonesoup.models.transition.linear import (
    CombinedLinearGaussianTransitionModel,
    ConstantVelocity,
)
from stonesoup.predictor.kalman import KalmanPredictor
from stonesoup.tracker.simple import MultiTargetMixtureTracker
from stonesoup.types.detection import TrueDetection
from stonesoup.types.state import GaussianState
from stonesoup.types.update import Update
from stonesoup.updater.kalman import KalmanUpdater

from targetacq import Simulation
from targetacq.scenario.schema import Scenario
from targetacq.tracking import (
    ScenarioGroundTruth,
    TargetacqDetectionModel,
    TargetacqDetectionSimulator,
    TargetacqPDAHypothesiser,
)

SCAN = 1.0  # [s]
NOISE = 10.0  # measurement noise, each axis [m]


SCENE = {
    "name": "Vehicles on roads seen from a hovering drone",
    "sensors": [
        {
            "name": "drone-lwir",
            "band": "lwir",
            "ifov": 0.5e-3,  # [rad]
            "pixels": (640, 512),
            "azimuth": math.radians(90.0),  # looking east
            "depression": math.radians(10.0),
            "position": (0.0, 0.0, 300.0),
        }
    ],
    "targets": [
        {  # north along a road 1.8 km east, 10 m/s
            "name": "truck",
            "criterion": "johnson-truck",
            "dimensions": (7.0, 2.5, 3.0),
            "temperature": 308.0,
            "waypoints": [
                {"time": 0.0, "position": (1800.0, -400.0, 0.0)},
                {"time": 80.0, "position": (1800.0, 400.0, 0.0)},
            ],
        },
        {  # south along a road 2.1 km east, 8 m/s
            "name": "jeep",
            "criterion": "johnson-jeep",
            "dimensions": (3.4, 1.6, 1.8),
            "temperature": 310.0,
            "moving": True,
            "waypoints": [
                {"time": 0.0, "position": (2100.0, 320.0, 0.0)},
                {"time": 80.0, "position": (2100.0, -320.0, 0.0)},
            ],
        },
    ],
    "background": {"temperature": 295.0, "clutter_std": 2.0},
    "atmosphere": {"extinction": 0.2e-3},  # [1/m]: clear air
    # Target-like clutter on the ground: 30 per km², each declared at the hazard 0.05 / t_s.
    "false_targets": {"density": 30e-6, "probability": 0.05, "max_range": 4000.0},
}


def run(seed: int = 2, duration: float = 80.0) -> dict[str, Any]:
    """Track the scene for ``duration`` seconds; the numbers and what a plot needs."""
    scenario = Scenario.model_validate(SCENE)
    sim = Simulation.from_scenario(scenario, seed=seed)
    model = TargetacqDetectionModel(simulation=sim, scan_interval=SCAN, target="truck")
    truth = ScenarioGroundTruth(scenario=scenario, times=np.arange(0.0, duration + SCAN, SCAN))
    measurement = LinearGaussian(ndim_state=4, mapping=(0, 2), noise_covar=np.eye(2) * NOISE**2)
    detector = TargetacqDetectionSimulator(
        groundtruth=truth, detection_model=model, measurement_model=measurement, seed=seed
    )
    transition = CombinedLinearGaussianTransitionModel([ConstantVelocity(0.5)] * 2)
    predictor = KalmanPredictor(transition)
    updater = KalmanUpdater(measurement)
    hypothesiser = TargetacqPDAHypothesiser(
        predictor=predictor, updater=updater, detection_model=model, prob_gate=0.9999
    )
    prior = GaussianState(np.zeros((4, 1)), np.diag([NOISE**2, 20.0**2, NOISE**2, 20.0**2]))
    initiator = MultiMeasurementInitiator(
        prior_state=prior,
        measurement_model=measurement,
        deleter=CovarianceBasedDeleter(covar_trace_thresh=2e4),
        data_associator=GNNWith2DAssignment(
            DistanceHypothesiser(predictor, updater, Mahalanobis(), missed_distance=3.0)
        ),
        updater=updater,
        min_points=4,
    )
    tracker = MultiTargetMixtureTracker(
        initiator=initiator,
        deleter=CovarianceBasedDeleter(covar_trace_thresh=2e4),
        detector=detector,
        data_associator=JPDA(hypothesiser),
        updater=updater,
    )
    tracks: set[Any] = set()
    detections: list[Any] = []
    densities: list[float] = []
    expected: list[float] = []
    for time, current in tracker:
        tracks |= current
        detections += list(detector.detections)
        densities.append(model.clutter_spatial_density(time))
        expected.append(model.expected_clutter(time))
    return {
        "tracks": tracks,
        "truth": truth,
        "detections": detections,
        "densities": np.array(densities),
        "expected": np.array(expected),
    }


def _source(state: Any) -> str | None:
    """The vehicle (path id) of the detection that weighs most in an update, None for clutter
    or a coasted scan."""
    hypothesis: Any = getattr(state, "hypothesis", None)
    singles: list[Any] = list(hypothesis) if hasattr(hypothesis, "__iter__") else [hypothesis]
    best = max(
        (h for h in singles if h is not None and h),
        key=lambda h: float(getattr(h, "probability", 1.0)),
        default=None,
    )
    measurement = getattr(best, "measurement", None)
    return measurement.groundtruth_path.id if isinstance(measurement, TrueDetection) else None


def score(found: dict[str, Any]) -> dict[str, float]:
    """Tracks on vehicles and on clutter, purity and mean position error [m] vs the truth.

    A track follows the vehicle whose detections weigh most in most of its updates (the most
    probable hypothesis of each JPDA update); its purity is the share of its updates on that
    vehicle; a track with no update on a vehicle is a false track."""
    purity, errors, false = [], [], 0
    paths = {p.id: p for p in found["truth"].groundtruth_paths}
    for track in found["tracks"]:
        sources = [_source(s) for s in track.states if isinstance(s, Update)]
        named = [x for x in sources if x is not None]
        if not named:
            false += 1
            continue
        name, count = Counter(named).most_common(1)[0]
        purity.append(count / len(sources))
        at = {s.timestamp: s.state_vector for s in paths[name].states}
        errors += [
            float(np.hypot(*(s.state_vector - at[s.timestamp])[[0, 2], 0]))
            for s in track.states
            if s.timestamp in at
        ]
    true = [d for d in found["detections"] if isinstance(d, TrueDetection)]
    return {
        "tracks on vehicles": float(len(purity)),
        "false tracks": float(false),
        "true detections": float(len(true)),
        "false detections": float(len(found["detections"]) - len(true)),
        "expected false detections": float(found["expected"][1:].sum()),  # none in scan 1
        "clutter density [1/km^2 per scan]": float(found["densities"].max() * 1e6),
        "mean purity": float(np.mean(purity)) if purity else float("nan"),
        "mean position error [m]": float(np.mean(errors)) if errors else float("nan"),
    }


def plot(found: dict[str, Any], path: str) -> None:
    """Truth, detections, clutter and tracks on the ground, as a PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.8), layout="constrained")
    for k, truth in enumerate(sorted(found["truth"].groundtruth_paths, key=lambda p: p.id)):
        xy = np.array([[s.state_vector[0, 0], s.state_vector[2, 0]] for s in truth.states])
        ax.plot(xy[:, 0], xy[:, 1], "k--", lw=1, label="truth" if k == 0 else None)
    true = np.array(
        [d.state_vector[:, 0] for d in found["detections"] if isinstance(d, TrueDetection)]
    ).reshape(-1, 2)
    clutter = np.array(
        [d.state_vector[:, 0] for d in found["detections"] if not isinstance(d, TrueDetection)]
    ).reshape(-1, 2)
    ax.plot(true[:, 0], true[:, 1], "o", ms=3, color="tab:blue", label="detections")
    ax.plot(clutter[:, 0], clutter[:, 1], "x", ms=3, color="tab:gray", label="false detections")
    for k, track in enumerate(sorted(found["tracks"], key=lambda t: t.states[0].timestamp)):
        xy = np.array([[s.state_vector[0, 0], s.state_vector[2, 0]] for s in track.states])
        ax.plot(
            xy[:, 0], xy[:, 1], "-", lw=1.5, color="tab:red", label="tracks" if k == 0 else None
        )
    ax.set_xlabel("east [m]")
    ax.set_ylabel("north [m]")
    ax.set_title("JPDA with P_d and clutter density from targetacq")
    ax.legend(loc="upper left", fontsize="small")
    fig.savefig(path, dpi=100)
    plt.close(fig)


if __name__ == "__main__":
    result = run()
    for key, value in score(result).items():
        print(f"{key:>36}: {value:.3f}")
    if len(sys.argv) > 1:
        plot(result, sys.argv[1])
