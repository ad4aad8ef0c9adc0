"""Multi-target tracking with Stone Soup (optional extra ``tracking``:
``pip install 'targetacq[tracking]'``).

targetacq says how likely an observer is to detect a target where it is, and which clutter
objects it declares targets (``[false_targets]``); a tracker (Stone Soup's PDA or JPDA with a
Kalman filter) needs exactly that per scan: the probability of detection ``P_d`` of each track's
*predicted* state and the spatial density of clutter in measurement space. This package converts
one into the other; the physics stays in targetacq.

:class:`TargetacqDetectionModel`
    ``prob_detect(state)``: targetacq's fused detection probability of a target at the state's
    position (:meth:`targetacq.Simulation.probabilities_at`); ``clutter_spatial_density(time)``:
    the expected false detections of one scan divided by the ground area in view
    (:mod:`targetacq.run.false_targets`).
:class:`TargetacqPDAHypothesiser`
    Stone Soup's :class:`~stonesoup.hypothesiser.probability.PDAHypothesiser` (for PDA and JPDA)
    with ``prob_detect`` and ``clutter_spatial_density`` from the model, per track and scan.
:class:`TargetacqDetectionSimulator`
    A Stone Soup detection reader: steps a :class:`targetacq.Simulation` along ground-truth paths
    and yields the true detections of acquired targets in view (with measurement noise) and the
    false detections as :class:`~stonesoup.types.detection.Clutter`.
:class:`ScenarioGroundTruth`
    A Stone Soup ground-truth reader of a scenario's scripted target paths.
"""

from __future__ import annotations

try:
    import stonesoup  # noqa: F401
except ImportError as error:  # the optional extra is missing: say how to get it
    raise ImportError(
        "targetacq.tracking needs Stone Soup: pip install 'targetacq[tracking]'"
    ) from error

from targetacq.tracking.adapter import (
    EPOCH,
    ScenarioGroundTruth,
    TargetacqDetectionModel,
    TargetacqDetectionSimulator,
    TargetacqPDAHypothesiser,
)

__all__ = [
    "EPOCH",
    "ScenarioGroundTruth",
    "TargetacqDetectionModel",
    "TargetacqDetectionSimulator",
    "TargetacqPDAHypothesiser",
]
