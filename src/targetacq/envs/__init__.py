"""Gymnasium environments (optional extra ``rl``: ``pip install targetacq[rl]``).

Importing this package registers:

``targetacq/SensorPointing-v0``
    Gimballed cameras on a moving platform point at targets on the ground; the reward counts
    new detections, recognitions and identifications (:class:`SensorPointingEnv`, which steps
    a :class:`targetacq.Simulation`; its vector entry is :func:`sensor_pointing_vector`).
``targetacq/SearchIdentify-v0``, ``targetacq/RouteIdentify-v0``, ``targetacq/ZoomIdentify-v0``
    The tasks of :data:`targetacq.envs.tasks.TASKS` (:class:`AcquisitionEnv`: a discrete
    ``track`` action, the ``dense`` reward and track observations by default), each with a
    native vector environment (:class:`AcquisitionVectorEnv`).

Use ``gymnasium.make("targetacq/SearchIdentify-v0")`` or ``gymnasium.make_vec(
"targetacq/SearchIdentify-v0", num_envs=64, vectorization_mode="vector_entry_point")`` after
``import targetacq.envs``.
"""

from __future__ import annotations

try:
    import gymnasium
except ImportError as error:  # the optional extra is missing: say how to get it
    raise ImportError("targetacq.envs needs Gymnasium: pip install 'targetacq[rl]'") from error

from targetacq.envs.acquisition import (
    AcquisitionEnv,
    AcquisitionVectorEnv,
    sensor_pointing_vector,
)
from targetacq.envs.pointing import SensorPointingEnv
from targetacq.envs.tasks import ACTIONS, REWARDS, TASKS

__all__ = [
    "ACTIONS",
    "REWARDS",
    "TASKS",
    "AcquisitionEnv",
    "AcquisitionVectorEnv",
    "SensorPointingEnv",
    "sensor_pointing_vector",
]

if "targetacq/SensorPointing-v0" not in gymnasium.registry:
    gymnasium.register(
        id="targetacq/SensorPointing-v0",
        entry_point="targetacq.envs.pointing:SensorPointingEnv",
        vector_entry_point="targetacq.envs.acquisition:sensor_pointing_vector",
    )
for _task in TASKS.values():
    if _task.gym_id not in gymnasium.registry:
        gymnasium.register(
            id=_task.gym_id,
            entry_point="targetacq.envs.acquisition:AcquisitionEnv",
            vector_entry_point="targetacq.envs.acquisition:AcquisitionVectorEnv",
            kwargs={"task": _task.name},
        )
