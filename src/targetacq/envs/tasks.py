"""The environments' registries: tasks, actions and rewards.

Each is a read-only mapping of names (:func:`targetacq.base.registry.lookup` turns an unknown
name into the ``ValueError`` a user sees). A task is what the agent controls in the scene of
:class:`targetacq.envs.SensorPointingEnv` (a platform over an area with cued targets); an action
is how it says it; a reward is what it earns. :class:`targetacq.envs.AcquisitionEnv` and
:class:`targetacq.envs.AcquisitionVectorEnv` take one of each.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

from targetacq.base.registry import lookup

__all__ = ["ACTIONS", "REWARDS", "TASKS", "Task", "get_action", "get_reward", "get_task"]


@dataclass(frozen=True)
class Task:
    """A task of the environments.

    Attributes
    ----------
    name : str
    gym_id : str
        Its Gymnasium id (``gymnasium.make(gym_id)`` after ``import targetacq.envs``).
    steers : str
        What the action moves: ``"gimbal"`` (the cameras' pointing; the platform flies east) or
        ``"platform"`` (the platform's heading; each camera looks at the nearest target not yet
        identified).
    actions : tuple of str
        The actions it takes (:data:`ACTIONS`); the first is its default.
    zoom : tuple of float
        Focal lengths [m] the action chooses among per camera (empty: the scene's one lens).
    description : str
    """

    name: str
    gym_id: str
    steers: str
    actions: tuple[str, ...]
    zoom: tuple[float, ...]
    description: str


TASKS = MappingProxyType(
    {
        "search": Task(
            "search",
            "targetacq/SearchIdentify-v0",
            "gimbal",
            ("track", "sector", "relative", "absolute"),
            (),
            "point gimballed cameras on a platform flying east so that the cued targets are "
            "identified",
        ),
        "route": Task(
            "route",
            "targetacq/RouteIdentify-v0",
            "platform",
            ("track", "sector", "relative", "absolute"),
            (),
            "steer the platform's heading (turn rate bounded) while each camera looks at the "
            "nearest target not yet identified",
        ),
        "zoom": Task(
            "zoom",
            "targetacq/ZoomIdentify-v0",
            "gimbal",
            ("track", "sector"),
            (0.05, 0.1, 0.2, 0.4),
            "point the cameras (discrete) and choose each one's zoom: focal lengths of 0.05, "
            "0.1, 0.2 and 0.4 m (fields of view from wide to narrow)",
        ),
    }
)
"""The tasks, by name (:class:`Task`)."""

ACTIONS = MappingProxyType(
    {
        "track": "Discrete per camera (or steer): look at (fly toward) cued target j",
        "sector": "Discrete per camera (or steer): one of 8 azimuth sectors relative to the "
        "platform's heading (times 3 depressions, 15, 30 and 60 degrees, for a camera)",
        "relative": "Box [-1, 1] per camera (azimuth, depression change) or steer (heading "
        "change): a fraction of the largest change in one step",
        "absolute": "Box [-1, 1] per camera: azimuth pi*a0, depression (pi/4)(a1 + 1) (the "
        "first environment's action; wraps at +-pi); steer: heading pi*a",
    }
)
"""The actions, by name, with what each is."""

REWARDS = MappingProxyType(
    {
        "sparse": "the number of new detections, recognitions and identifications of the step",
        "dense": "the step's gain in the expected-identification potential V_j summed over "
        "targets (V_j = 1 once identified, else the model's expected probability of "
        "identification so far); at most the number of targets over an episode",
    }
)
"""The rewards, by name, with what each is (the environments' docstring has the laws)."""


def get_task(name: Any) -> Task:
    """The task ``name`` of :data:`TASKS`, else ``ValueError`` naming ``task`` and the choices.

    Examples
    --------
    >>> get_task("zoom").zoom
    (0.05, 0.1, 0.2, 0.4)
    """
    return lookup(TASKS, name, "task")


def get_action(name: Any, task: Task) -> str:
    """``name`` if it is an action of :data:`ACTIONS` that ``task`` takes, else ``ValueError``
    naming ``action`` and the choices.

    Examples
    --------
    >>> get_action("track", get_task("search"))
    'track'
    """
    lookup(ACTIONS, name, "action")
    if name not in task.actions:
        raise ValueError(
            f"action {name!r} is not one of task {task.name!r}'s; valid: {', '.join(task.actions)}"
        )
    return str(name)


def get_reward(name: Any) -> str:
    """``name`` if it is a reward of :data:`REWARDS`, else ``ValueError`` naming ``reward``.

    Examples
    --------
    >>> get_reward("dense")
    'dense'
    """
    lookup(REWARDS, name, "reward")
    return str(name)
