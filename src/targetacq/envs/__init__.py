"""Gymnasium environments (optional extra ``rl``: ``pip install targetacq[rl]``).

Importing this package registers:

``targetacq/SensorPointing-v0``
    Gimballed cameras on a moving platform point at targets on the ground; the reward counts
    new detections, recognitions and identifications (:class:`SensorPointingEnv`).

Use ``gymnasium.make("targetacq/SensorPointing-v0")`` after ``import targetacq.envs``.
"""

from __future__ import annotations

try:
    import gymnasium
except ImportError as error:  # the optional extra is missing: say how to get it
    raise ImportError("targetacq.envs needs Gymnasium: pip install 'targetacq[rl]'") from error

from targetacq.envs.pointing import SensorPointingEnv

__all__ = ["SensorPointingEnv"]

if "targetacq/SensorPointing-v0" not in gymnasium.registry:
    gymnasium.register(
        id="targetacq/SensorPointing-v0",
        entry_point="targetacq.envs.pointing:SensorPointingEnv",
    )
