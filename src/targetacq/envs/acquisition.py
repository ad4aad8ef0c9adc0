"""Environments worth training on: tasks, learnable actions, a dense reward, track observations.

:class:`AcquisitionEnv` is one episode at a time, :class:`AcquisitionVectorEnv` N of them in
one array pass (:class:`targetacq.envs.engagements.Engagements`); environment ``i`` of a vector
reset with ``seed=s`` is the single environment reset with ``seed=s + i`` (the same numbers).

Scene
    :class:`targetacq.envs.SensorPointingEnv`'s: a platform at ``altitude`` flying at
    ``speed`` (east, unless the task steers it) over a square of ``half_width`` with cued
    targets of drawn positions, headings, sizes and temperatures, its ``scenario_overrides``
    (but a terrain map) and ``camera_type``; the model's search law with its persistent draws
    (:mod:`targetacq.run.search`). With an elevation model (``scenario_overrides={"terrain":
    {...}}``, the ``[terrain]`` table) the targets stand on the ground, ``altitude`` is above
    the model's datum, and a target the terrain hides from the platform is out of view.
Task (``task``, :data:`targetacq.envs.tasks.TASKS`)
    ``search``: the action points the cameras; ``route``: it steers the platform's heading
    (turn rate at most π/12 rad/s) and each camera looks at the nearest target not yet
    identified; ``zoom``: it points the cameras (``track`` or ``sector``) and chooses each one's
    focal length among 0.05, 0.1, 0.2 and 0.4 m.
Action (``action``, :data:`targetacq.envs.tasks.ACTIONS`)
    ``track`` (default): ``Discrete(T)`` per camera (``MultiDiscrete`` for several): the camera
    slews within the step to target j's cued position (route: the platform turns toward it);
    ``sector``: ``Discrete(3·8)`` per camera: 8 azimuth sectors relative to the heading
    (sector k at heading + 2πk/8) times the depressions of
    :data:`~targetacq.envs.engagements.SECTOR_DEPRESSIONS` (index ``3k + d``); route:
    ``Discrete(8)`` compass headings; ``relative``: ``Box([-1, 1], (C, 2))``: azimuth and
    depression change of ``a · π/4 · dt`` (depression kept in [0, π/2]); route: ``Box(1)``,
    heading change ``a · π/12 · dt``; ``absolute``: today's ``SensorPointing-v0`` action
    (azimuth ``π a₀``, depression ``(π/4)(a₁ + 1)``; it wraps at ±π); route: heading ``π a``.
    The zoom task's action is ``MultiDiscrete([n, 4] · C)``: per camera the pointing choice
    and the zoom level.
Reward (``reward``, :data:`targetacq.envs.tasks.REWARDS`)
    ``dense`` (default): the step's gain ``Σ_j V_j(t) − V_j(t − dt)`` of the potential
    ``V_j = 1`` once target j is identified (the model's sampled outcome), else
    ``Q_j = 1 − Π_c (1 − q_cj)`` with ``q_cj = max_{t' <= t} P_id,cj(t') (1 − exp(−Λ_cj(t')))``
    and ``Λ_cj = Σ dt · P_det,cj / t_s`` over the steps camera c saw target j: the search law's
    probability of identification by t for the probabilities seen (exact for constant ones).
    V never falls, so the reward is >= 0 and an episode's sum is at most the number of
    targets; Λ grows only while a target is in view and the draws persist, so looking away and
    back gains nothing. ``sparse``: the number of new detections, recognitions and
    identifications of the step (``SensorPointing-v0``'s).
Observation (float32, flat)
    the platform (east, north, up over ``half_width``; sin and cos of its heading; time over
    ``duration``); per camera sin and cos of its azimuth relative to the heading, its
    depression over π/2 and its zoom level over the top level (0 without zoom); per target its
    position relative to the platform over ``half_width`` (east, north, up), its range over
    ``half_width``, its detected, recognised and identified flags, its *prospects* (the
    probabilities of detection, recognition and identification were a camera to look at it now,
    best over cameras and zoom levels: a target of prospect 0 is hopeless from here), its
    ``V_j`` above, its search progress ``1 − exp(−Λ_j)`` (Λ of the camera that looked
    longest: how much of the search law's clock is spent on it) and whether a camera sees it
    now (13 numbers).
Episode
    ``duration`` seconds in steps of ``dt``; terminated when every target is identified.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import gymnasium
import numpy as np
from gymnasium import spaces
from gymnasium.error import ResetNeeded
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from targetacq.envs.engagements import SECTOR_DEPRESSIONS, Engagements, EnvOptions
from targetacq.envs.pointing import SensorPointingEnv
from targetacq.envs.tasks import get_action, get_reward, get_task

__all__ = [
    "CAMERA_FEATURES",
    "PLATFORM_FEATURES",
    "SCENE_KEYS",
    "TARGET_FEATURES",
    "AcquisitionEnv",
    "AcquisitionVectorEnv",
    "make_options",
    "sensor_pointing_vector",
]

SCENE_KEYS = ("altitude", "speed", "half_width", "camera_type", "scenario_overrides")
"""The keys of an environment's ``scene`` mapping (as :class:`SensorPointingEnv` takes them)."""
PLATFORM_FEATURES = 6
"""Numbers of the platform at the head of an observation (see the module docstring)."""
CAMERA_FEATURES = 4
"""Numbers per camera, after the platform's."""
TARGET_FEATURES = 13
"""Numbers per target, after the cameras'."""


def make_options(
    task: str = "search",
    action: str | None = None,
    reward: str = "dense",
    cameras: int = 1,
    targets: int = 6,
    duration: float = 120.0,
    dt: float = 1.0,
    scene: Mapping[str, Any] | None = None,
) -> EnvOptions:
    """The checked options of an environment (the parameters of :class:`AcquisitionEnv`).

    Raises
    ------
    ValueError
        An unknown task, action or reward (naming the option and the choices), an action the
        task does not take, a ``scene`` key not in :data:`SCENE_KEYS`, or a scene value
        :class:`SensorPointingEnv` refuses.

    Examples
    --------
    >>> make_options("zoom").action
    'track'
    >>> try:
    ...     make_options(reward="shaped")
    ... except ValueError as error:
    ...     print(error)
    unknown reward 'shaped'; valid: sparse, dense
    """
    chosen = get_task(task)
    action = get_action(chosen.actions[0] if action is None else action, chosen)
    reward = get_reward(reward)
    given = dict(scene or {})
    unknown = [key for key in given if key not in SCENE_KEYS]
    if unknown:
        raise ValueError(f"scene: unknown key {unknown[0]!r}; valid keys: {', '.join(SCENE_KEYS)}")
    built = SensorPointingEnv(cameras=cameras, targets=targets, duration=duration, dt=dt, **given)
    return EnvOptions(chosen, action, reward, built)


def _spaces(o: EnvOptions) -> tuple[spaces.Space[Any], spaces.Box]:
    """The action and observation spaces of one environment."""
    scene = o.scene
    c, t = scene.n_cameras, scene.n_targets
    steer = o.task.steers == "platform"
    count = {"track": t, "sector": o.sectors if steer else 3 * o.sectors}.get(o.action)
    action: spaces.Space[Any]
    if o.task.zoom:
        assert count is not None
        action = spaces.MultiDiscrete([count, len(o.task.zoom)] * c)
    elif count is not None:
        action = spaces.Discrete(count) if steer or c == 1 else spaces.MultiDiscrete([count] * c)
    else:
        action = spaces.Box(-1.0, 1.0, shape=(1,) if steer else (c, 2), dtype=np.float32)
    size = PLATFORM_FEATURES + CAMERA_FEATURES * c + TARGET_FEATURES * t
    reach = scene.speed * scene.duration + scene.altitude
    bound = 2.0 * (3.0 + reach / scene.half_width)
    return action, spaces.Box(-bound, bound, shape=(size,), dtype=np.float32)


def _act(e: Engagements, actions: np.ndarray, envs: np.ndarray) -> None:
    """Apply the actions of episodes ``envs`` (rows of ``actions``): move and point."""
    o = e.o
    m = envs.size
    if m == 0:
        return
    if o.task.steers == "platform":
        steer = actions.reshape(m, -1)
        if o.action == "track":
            heading = e.aim(envs, np.zeros(m, dtype=int), steer[:, 0].astype(int))[:, 0]
        elif o.action == "sector":
            heading = 2 * math.pi * steer[:, 0] / o.sectors
        elif o.action == "relative":
            heading = e.heading[envs] + np.clip(steer[:, 0], -1, 1) * o.turn * e.dt
        else:
            heading = math.pi * np.clip(steer[:, 0], -1, 1)
        e.move(heading, envs)
        ranks = np.arange(e.c)
        aim_at = e.nearest(ranks)[envs]  # the cameras look at the nearest unidentified
        e.pointing[envs] = e.aim(envs[:, None], ranks[None], aim_at)
        return
    e.move(e.heading[envs], envs)
    choice: np.ndarray
    if o.task.zoom:
        a = actions.reshape(m, e.c, 2).astype(int)
        e.zoom_index[envs] = a[..., 1]
        choice = a[..., 0]
    elif o.action in ("track", "sector"):
        choice = actions.reshape(m, e.c).astype(int)
    else:
        a = np.clip(actions.reshape(m, e.c, 2).astype(float), -1.0, 1.0)
        if o.action == "relative":
            largest = o.slew * e.dt
            azimuth = e.pointing[envs, :, 0] + a[..., 0] * largest
            depression = np.clip(e.pointing[envs, :, 1] + a[..., 1] * largest, 0.0, math.pi / 2)
            e.pointing[envs] = np.stack([_wrap(azimuth), depression], -1)
        else:
            e.pointing[envs] = np.stack([math.pi * a[..., 0], math.pi / 4 * (a[..., 1] + 1)], -1)
        return
    if o.action == "track":
        e.pointing[envs] = e.aim(envs[:, None], np.arange(e.c)[None], choice)
    else:
        sector, ring = np.divmod(choice, len(SECTOR_DEPRESSIONS))
        azimuth = e.heading[envs, None] + 2 * math.pi * sector / o.sectors
        depression = np.asarray(SECTOR_DEPRESSIONS)[ring]
        e.pointing[envs] = np.stack([_wrap(azimuth), depression], -1)


def _greedy(e: Engagements, space: spaces.Space[Any]) -> np.ndarray:
    """Every episode's greedy action (N, *shape): the k-th camera (or the platform) toward the
    k-th nearest target not yet identified, in the action's own terms; the zoom task's longest
    focal length."""
    o = e.o
    shape: tuple[int, ...] = tuple(space.shape or ())
    envs = np.arange(e.n)
    choice: np.ndarray
    ranks = np.arange(1 if o.task.steers == "platform" else e.c)
    chosen = e.nearest(ranks)  # (N, k)
    aim = e.aim(envs[:, None], ranks[None], chosen)  # (N, k, 2)
    if o.action == "track":
        choice = chosen
    elif o.action == "sector":
        relative = aim[..., 0] if o.task.steers == "platform" else aim[..., 0] - e.heading[:, None]
        sector = np.round(relative / (2 * math.pi / o.sectors)).astype(int) % o.sectors
        if o.task.steers == "platform":
            choice = sector
        else:
            ring = np.argmin(
                np.abs(aim[..., 1, None] - np.asarray(SECTOR_DEPRESSIONS)[None, None]), axis=-1
            )
            choice = sector * len(SECTOR_DEPRESSIONS) + ring
    elif o.task.steers == "platform":
        if o.action == "relative":
            turn = _wrap(aim[..., 0] - e.heading[:, None]) / (o.turn * e.dt)
            return np.clip(turn, -1, 1).astype(np.float32).reshape(e.n, *shape)
        return (aim[..., 0] / math.pi).astype(np.float32).reshape(e.n, *shape)
    elif o.action == "relative":
        largest = o.slew * e.dt
        change = np.stack(
            [_wrap(aim[..., 0] - e.pointing[..., 0]), aim[..., 1] - e.pointing[..., 1]], -1
        )
        return np.clip(change / largest, -1, 1).astype(np.float32)
    else:
        absolute = np.stack([aim[..., 0] / math.pi, aim[..., 1] / (math.pi / 4) - 1.0], -1)
        return np.clip(absolute, -1, 1).astype(np.float32)
    if o.task.zoom:
        zoom = np.full_like(choice, len(o.task.zoom) - 1)
        return np.stack([choice, zoom], -1).reshape(e.n, -1).astype(np.int64)
    return choice.reshape(e.n, *shape).astype(np.int64)


def _observe(e: Engagements) -> np.ndarray:
    """Every episode's observation (N, size), float32."""
    hw = e.hw
    platform = np.concatenate(
        [
            e.platform / hw,
            np.sin(e.heading)[:, None],
            np.cos(e.heading)[:, None],
            (e.time / e.duration)[:, None],
        ],
        axis=1,
    )
    relative_azimuth = e.pointing[..., 0] - e.heading[:, None]
    top = max(e.z - 1, 1)
    cameras = np.stack(
        [
            np.sin(relative_azimuth),
            np.cos(relative_azimuth),
            e.pointing[..., 1] / (math.pi / 2),
            e.zoom_index / top,
        ],
        -1,
    ).reshape(e.n, -1)
    offset = (e.targets - e.platform[:, None]) / hw
    per_target = np.concatenate(
        [
            offset,
            np.linalg.norm(offset, axis=-1, keepdims=True),
            e.flags.transpose(1, 2, 0),
            e.prospect.transpose(1, 2, 0),
            e.potential[..., None],
            e.progress[..., None],
            e.in_view[..., None],
        ],
        axis=-1,
    ).reshape(e.n, -1)
    return np.concatenate([platform, cameras, per_target], axis=1).astype(np.float32)


def _no_options(options: Any) -> None:
    """``reset``'s options: none are taken (a key given is refused, not ignored)."""
    if options:
        raise ValueError(
            f"reset(options=...): this environment takes no reset options, got {dict(options)!r}"
        )


def _checked(given: np.ndarray, space: spaces.Space[Any], name: str) -> np.ndarray:
    """``given`` if it fits ``space`` (a box's values are clipped to it later), else
    ``ValueError`` naming ``name`` and the space."""
    if isinstance(space, spaces.Box):
        fits = given.dtype.kind in "fiu" and given.shape == space.shape
        if fits and np.all(np.isfinite(given)):
            return given
    elif given.dtype.kind in "iu" and space.contains(given.astype(space.dtype)):
        return given
    shown = np.array2string(given, threshold=8) if given.size <= 64 else f"shape {given.shape}"
    raise ValueError(
        f"{name} must be in {space}, got {shown} ({given.dtype} of shape {given.shape})"
    )


def sensor_pointing_vector(num_envs: int = 1, **kwargs: Any) -> AcquisitionVectorEnv:
    """The vector entry of ``targetacq/SensorPointing-v0``: the array core's search task with
    its ``absolute`` action and ``sparse`` reward, taking :class:`SensorPointingEnv`'s keywords.

    Its observation is the track observation of :class:`AcquisitionEnv`, not
    :class:`SensorPointingEnv`'s (which steps a :class:`targetacq.Simulation`, with other
    streams): its single twin is ``AcquisitionEnv(action="absolute", reward="sparse")``.
    """
    chunk = kwargs.pop("chunk", 16)
    scene = {key: kwargs.pop(key) for key in SCENE_KEYS if key in kwargs}
    return AcquisitionVectorEnv(
        num_envs, chunk, action="absolute", reward="sparse", scene=scene, **kwargs
    )


def _wrap(angle: Any) -> Any:
    return (np.asarray(angle) + math.pi) % (2 * math.pi) - math.pi


def _info(e: Engagements, k: int) -> dict[str, Any]:
    return {
        "time": float(e.time[k]),
        "detected": e.flags[0, k].copy(),
        "recognised": e.flags[1, k].copy(),
        "identified": e.flags[2, k].copy(),
        "expected_identified": e.potential[k].copy(),
        "prospect_identification": e.prospect[2, k].copy(),
    }


class AcquisitionEnv(gymnasium.Env[np.ndarray, Any]):
    """One episode of a task at a time (see the module docstring).

    Parameters
    ----------
    task : str
        :data:`targetacq.envs.tasks.TASKS`: ``search`` (default), ``route`` or ``zoom``.
    action : str, optional
        :data:`targetacq.envs.tasks.ACTIONS` that the task takes; default its first
        (``track``).
    reward : str
        ``dense`` (default) or ``sparse`` (:data:`targetacq.envs.tasks.REWARDS`).
    cameras, targets : int
        As for :class:`SensorPointingEnv` (>= 1).
    duration, dt : float
        Episode length and step [s], > 0.
    scene : mapping, optional
        :data:`SCENE_KEYS`: ``altitude`` [m], ``speed`` [m/s], ``half_width`` [m],
        ``camera_type`` and ``scenario_overrides``, as :class:`SensorPointingEnv` takes them
        (a terrain map is refused).
    render_mode : None
        No rendering.

    Examples
    --------
    >>> from targetacq.envs import AcquisitionEnv
    >>> env = AcquisitionEnv(targets=3, duration=10.0)
    >>> obs, info = env.reset(seed=1)
    >>> obs.shape, env.action_space
    ((49,), Discrete(3))
    >>> obs, reward, terminated, truncated, info = env.step(env.greedy_action())
    >>> 0.0 <= reward <= 3.0
    True
    """

    metadata: dict[str, Any] = {"render_modes": []}  # noqa: RUF012 - Gymnasium's convention

    def __init__(
        self,
        task: str = "search",
        action: str | None = None,
        reward: str = "dense",
        cameras: int = 1,
        targets: int = 6,
        duration: float = 120.0,
        dt: float = 1.0,
        scene: Mapping[str, Any] | None = None,
        render_mode: str | None = None,
    ) -> None:
        if render_mode is not None:
            raise ValueError("render_mode must be None: this environment does not render")
        self.render_mode = render_mode
        self.options = make_options(task, action, reward, cameras, targets, duration, dt, scene)
        self.action_space, self.observation_space = _spaces(self.options)
        self._core: Engagements | None = None

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """Draw a new episode (reproducible from ``seed``)."""
        _no_options(options)
        super().reset(seed=seed)
        if self._core is None:
            self._core = Engagements(self.options, 1, 1)
        self._core.advance(np.ones(1, dtype=bool), [self.np_random])
        return _observe(self._core)[0], _info(self._core, 0)

    def step(self, action: Any) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        """Act, advance ``dt`` and earn the reward."""
        e = self._require("step")
        given = _checked(np.asarray(action), self.action_space, "action")
        _act(e, given[None], np.zeros(1, dtype=int))
        rewards = e.advance(np.zeros(1, dtype=bool), [self.np_random])
        terminated = bool(e.flags[2, 0].all())
        truncated = bool(e.time[0] >= e.duration - 1e-9)
        reward = float(rewards[self.options.reward][0])
        return _observe(e)[0], reward, terminated, truncated, _info(e, 0)

    def greedy_action(self) -> Any:
        """The nearest target not yet identified (a scripted baseline), in the action's terms.

        ``track``: its index; ``sector``: the sector and depression nearest its direction;
        ``relative``: the slew toward it (clipped to one step's largest); ``absolute``: its
        direction; the route task steers toward it; the zoom task takes the longest focal
        length. With several cameras, camera k looks at the k-th nearest.

        What it does not do: it never asks whether the target can be identified at all. It
        stays on the nearest one until it is identified, so a target too small, too cold or
        too far for the camera (prospect of identification 0, or a capability draw that
        fails: draws persist per engagement) holds it for the rest of the episode while
        others go by. A policy that reads the prospects can do better.
        """
        e = self._require("greedy_action")
        chosen = _greedy(e, self.action_space)[0]
        if isinstance(self.action_space, spaces.Discrete):
            return int(chosen.reshape(-1)[0])
        return chosen

    def _require(self, what: str) -> Engagements:
        if self._core is None:
            raise ResetNeeded(
                f"AcquisitionEnv.{what}() before reset(): call env.reset(seed=...) first"
            )
        return self._core


class AcquisitionVectorEnv(VectorEnv[np.ndarray, np.ndarray, np.ndarray]):
    """N episodes of a task in one array pass (Gymnasium's vector API, next-step autoreset).

    Parameters
    ----------
    num_envs : int
        N, >= 1.
    chunk : int
        Episodes per call of the array core (see :mod:`targetacq.envs.engagements`), >= 1.
    **options
        The parameters of :class:`AcquisitionEnv` (``task``, ``action``, ``reward``,
        ``cameras``, ``targets``, ``duration``, ``dt``, ``scene``, ``render_mode``).

    Notes
    -----
    ``reset(seed=s)`` seeds episode i's generator with ``s + i`` (Gymnasium's convention; a
    list gives each its own), so environment i is :class:`AcquisitionEnv` reset with
    ``seed=s + i``, step for step. An episode that ends is reset at the next ``step``, whose
    action it ignores (``metadata["autoreset_mode"]`` is ``NEXT_STEP``): that step returns
    its first observation, reward 0 and neither flag.

    Examples
    --------
    >>> from targetacq.envs import AcquisitionVectorEnv
    >>> envs = AcquisitionVectorEnv(4, targets=3, duration=10.0)
    >>> obs, info = envs.reset(seed=7)
    >>> obs.shape, envs.action_space
    ((4, 49), MultiDiscrete([3 3 3 3]))
    """

    metadata: dict[str, Any] = {  # noqa: RUF012 - Gymnasium's convention
        "render_modes": [],
        "autoreset_mode": AutoresetMode.NEXT_STEP,
    }

    def __init__(self, num_envs: int = 1, chunk: int = 16, **options: Any) -> None:
        if not (isinstance(num_envs, int) and not isinstance(num_envs, bool) and num_envs >= 1):
            raise ValueError(f"num_envs must be an integer >= 1, got {num_envs!r}")
        if options.pop("render_mode", None) is not None:
            raise ValueError("render_mode must be None: this environment does not render")
        self.num_envs = num_envs
        self.options = make_options(**options)
        self.single_action_space, self.single_observation_space = _spaces(self.options)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.render_mode = None
        self._chunk = chunk
        self._core: Engagements | None = None
        self._rngs: list[np.random.Generator] = []
        self._ended = np.zeros(num_envs, dtype=bool)
        Engagements(self.options, 1, chunk)  # check the options now (a terrain map, the chunk)

    def reset(
        self, *, seed: int | list[int | None] | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        """Start every episode: episode i from ``seed + i`` (or ``seed[i]``)."""
        _no_options(options)
        n = self.num_envs
        if seed is None:
            seeds: list[int | None] = [None] * n
        elif isinstance(seed, int):
            seeds = [seed + i for i in range(n)]
        else:
            seeds = list(seed)
            if len(seeds) != n:
                raise ValueError(f"seed must be an int or a list of {n} seeds, got {len(seeds)}")
        if seed is not None or not self._rngs:
            self._rngs = [seeding.np_random(s)[0] for s in seeds]
        self._core = Engagements(self.options, n, self._chunk)
        self._core.advance(np.ones(n, dtype=bool), self._rngs)
        self._ended[:] = False
        return _observe(self._core), self._infos()

    def step(
        self, actions: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
        """Act in every episode (those that ended start again and ignore theirs)."""
        e = self._core
        if e is None:
            raise ResetNeeded("AcquisitionVectorEnv.step() before reset()")
        given = _checked(np.asarray(actions), self.action_space, "actions")
        going = np.flatnonzero(~self._ended)
        _act(e, given[going], going)
        rewards = e.advance(self._ended.copy(), self._rngs)
        reward = rewards[self.options.reward]
        terminated = e.flags[2].all(axis=1) & ~self._ended
        truncated = (e.time >= e.duration - 1e-9) & ~self._ended & ~terminated
        self._ended = terminated | truncated
        return _observe(e), reward, terminated, truncated, self._infos()

    def greedy_actions(self) -> np.ndarray:
        """Every episode's :meth:`AcquisitionEnv.greedy_action` (same limits)."""
        if self._core is None:
            raise ResetNeeded("AcquisitionVectorEnv.greedy_actions() before reset()")
        return _greedy(self._core, self.single_action_space).reshape(self.action_space.shape)

    def _infos(self) -> dict[str, Any]:
        e = self._core
        assert e is not None
        values = {
            "time": e.time.copy(),
            "detected": e.flags[0].copy(),
            "recognised": e.flags[1].copy(),
            "identified": e.flags[2].copy(),
            "expected_identified": e.potential.copy(),
        }
        every = np.ones(self.num_envs, dtype=bool)
        return {**values, **{f"_{key}": every for key in values}}
