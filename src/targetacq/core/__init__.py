"""The array core: typed records, the scenario compiler and the pure evaluation.

See :mod:`targetacq.core.records`, :mod:`targetacq.core.compile` and
:mod:`targetacq.core.evaluation`. Every front-end (``ModelChain``, the step API
:class:`targetacq.Simulation`, ranges, the CLI) computes through here.
"""

from targetacq.core.active import has_active
from targetacq.core.compile import (
    CompiledScenario,
    compile_scenario,
    scenario_positions,
    scenario_velocities,
    sensor_rows,
)
from targetacq.core.evaluation import (
    Factors,
    Probabilities,
    crossing_speeds,
    evaluate,
    evaluate_step,
    factors,
    probabilities,
)
from targetacq.core.records import (
    AspectArrays,
    LaserArrays,
    ModelChoices,
    PathArrays,
    RadarArrays,
    SceneArrays,
    SensorArrays,
    SignatureArrays,
    TargetArrays,
    register_pytrees,
    take_targets,
)

__all__ = [
    "AspectArrays",
    "CompiledScenario",
    "Factors",
    "LaserArrays",
    "ModelChoices",
    "PathArrays",
    "Probabilities",
    "RadarArrays",
    "SceneArrays",
    "SensorArrays",
    "SignatureArrays",
    "TargetArrays",
    "compile_scenario",
    "crossing_speeds",
    "evaluate",
    "evaluate_step",
    "factors",
    "has_active",
    "probabilities",
    "register_pytrees",
    "scenario_positions",
    "scenario_velocities",
    "sensor_rows",
    "take_targets",
]
