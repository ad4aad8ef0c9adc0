"""The array core of the environments: N engagements stepped in one pass.

:class:`Engagements` holds N episodes of one task (:mod:`targetacq.envs.tasks`) and steps them
together; :class:`targetacq.envs.AcquisitionEnv` is one of them (N = 1) and
:class:`targetacq.envs.AcquisitionVectorEnv` N of them, so that environment ``i`` of a vector
seeded ``s`` is the single environment seeded ``s + i`` by construction (the same code on the
same numbers; the tests hold them equal).

Scene
    each episode's targets (positions, headings, sizes, temperatures) are drawn from the
    episode's generator exactly as :class:`targetacq.envs.SensorPointingEnv` draws them
    (:meth:`~targetacq.envs.SensorPointingEnv.scene_tables`, with its ``scenario_overrides``);
    the scenarios of the episodes that start in a step are compiled together
    (:func:`targetacq.core.compile_scenario`) and their targets' records put into a pool of
    all N × T targets.
Probabilities
    one call of the array core (:func:`targetacq.core.evaluate`) over the N × T targets of
    the pool against the cameras' rows: each episode's targets are moved by its platform's
    horizontal offset so that every camera stands at one place (the platforms fly level at one
    altitude), which leaves every pair's line of sight, and its heights, its own: N × rows × T
    pairs, no others. A scene with clouds (whose places count) is evaluated a chunk of K
    episodes per call instead, the episodes along the core's batch axis (positions
    ``(n_s, K, 3)`` and ``(K·T, K, 3)``), keeping each episode's own K × T pairs (the diagonal
    blocks). The cameras are evaluated unpointed (every pair as if looked at), which is what a
    pointed camera sees of a target inside its field of view; the field of view is then
    applied per pair with the geometry's own test
    (:func:`targetacq.physics.geometry.within_numpy`): zero outside, as the core has it. The
    unpointed probabilities are the observation's *prospects*. The tests hold both paths to
    :meth:`targetacq.Simulation.probabilities` of a camera pointed at the target. With an
    elevation model (the scene's ``terrain``) every platform-target line of sight of every
    episode is traced in one call from the true positions (not the shifted ones), each pair
    given the smaller of its own and the terrain's visible fraction, a hidden pair (or one off
    the grid) out of view (:mod:`targetacq.core.terrain_view`).
Acquisition
    one :class:`targetacq.run.search.SearchState` holds every episode's camera-target pairs
    (N × rows × T, flat); its draws are keyed by the episode's model seed and the camera's and
    target's names (:func:`targetacq.base.sampling.stream_key`), so a pair's outcomes do not
    depend on N, the chunk or the other episodes. A pair whose episode starts is put back to
    its initial state with NaN probabilities at the previous time: nothing happens to it in
    that step (as in a first step) and its view episodes start then. A view change is taken at
    the middle of the step (the environments do not solve the crossing moment). The zoom
    levels of one camera share its draws (one camera, one look).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import Any

import numpy as np

from targetacq import core
from targetacq.base.sampling import stream_key
from targetacq.core.records import SceneArrays
from targetacq.core.terrain_view import hide, terrain_view
from targetacq.physics import geometry
from targetacq.run.search import SearchState, Streams
from targetacq.scenario.plausibility import collected
from targetacq.scenario.schema import parse_scenario

__all__ = ["SECTOR_DEPRESSIONS", "Engagements", "EnvOptions"]

SECTOR_DEPRESSIONS = (math.pi / 12, math.pi / 6, math.pi / 3)
"""The depressions [rad] of a camera's ``sector`` action (15°, 30° and 60°)."""
_FLAGS = ("detected", "recognised", "identified")
_START_POINTING = (math.pi / 2, math.pi / 6)


@dataclass(frozen=True)
class EnvOptions:
    """The checked options of an environment (:class:`targetacq.envs.AcquisitionEnv`).

    Attributes
    ----------
    task : targetacq.envs.tasks.Task
    action, reward : str
    scene : targetacq.envs.SensorPointingEnv
        The scene's builder and checker (its cameras, targets, duration, step, platform,
        camera type and ``scenario_overrides``).
    sectors : int
        Azimuth sectors of the ``sector`` action.
    slew : float
        The gimbal's largest rate [rad/s] per axis under the ``relative`` action.
    turn : float
        The platform's largest turn rate [rad/s].
    """

    task: Any
    action: str
    reward: str
    scene: Any
    sectors: int = 8
    slew: float = math.pi / 4
    turn: float = math.pi / 12


class _EpisodeStreams(Streams):
    """The keys of every episode's camera-target pairs: the episode's own seed, the camera's
    name (shared by its zoom levels) and the target's name."""

    def __init__(self, n: int, cameras: list[str], targets: list[str]) -> None:
        super().__init__(0, [f"{k}:{c}" for k in range(n) for c in cameras], targets)
        self.cameras = cameras
        self.seeds = [0] * n

    def keys(self, pairs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        missing = pairs[~self.ready[pairs]]
        per = len(self.cameras) * len(self.targets)
        n_g = len(self.targets)
        for pair in missing.tolist():
            env, rest = divmod(pair, per)
            row, g = divmod(rest, n_g)
            self.k0[pair], self.k1[pair] = stream_key(
                self.seeds[env], self.cameras[row], self.targets[g]
            )
        self.ready[missing] = True
        return self.k0[pairs], self.k1[pairs]


def _put(old: Any, cols: np.ndarray, new: Any, axis: int) -> Any:
    """Record ``old`` with its per-target fields at ``cols`` (along ``axis``) from ``new``."""
    changes: dict[str, Any] = {}
    for item in fields(old):
        a, b = getattr(old, item.name), getattr(new, item.name)
        if a is None or b is None or isinstance(a, (bool, str)):
            continue
        if isinstance(a, tuple):
            if not hasattr(old, "names") or len(a) != len(old.names) or not a:
                continue
            values = list(a)
            for c, v in zip(cols.tolist(), b, strict=True):
                values[c] = v
            changes[item.name] = tuple(values)
        elif isinstance(a, np.ndarray) and a.ndim > axis:
            array = a.copy()
            index = (slice(None),) * axis + (cols,)
            array[index] = b
            changes[item.name] = array
    return replace(old, **changes)


class Engagements:
    """N episodes of a task, stepped together (see the module docstring).

    Parameters
    ----------
    options : EnvOptions
    n : int
        Episodes, >= 1.
    chunk : int
        Episodes per call of the array core, >= 1.
    """

    def __init__(self, options: EnvOptions, n: int, chunk: int = 16) -> None:
        if not (isinstance(chunk, int) and not isinstance(chunk, bool) and chunk >= 1):
            raise ValueError(
                f"chunk must be an integer >= 1 (episodes per core call), got {chunk!r}"
            )
        self.o = options
        scene = options.scene
        self.n, self.c, self.t = n, scene.n_cameras, scene.n_targets
        self.zoom = options.task.zoom or (None,)
        self.z = len(self.zoom)
        self.r = self.c * self.z
        self.chunk = min(chunk, n)
        self.dt, self.duration = scene.dt, scene.duration
        self.hw, self.alt, self.speed = scene.half_width, scene.altitude, scene.speed
        self.elevation, self.k = scene.elevation, scene.earth_radius_factor
        self.camera_of_row = np.repeat(np.arange(self.c), self.z)
        self.zoom_of_row = np.tile(np.arange(self.z), self.c)
        template = self._compile([np.random.default_rng(0)])[0]
        if template.terrain is not None:
            raise ValueError(
                "scenario_overrides: background.terrain: the environments of targetacq.envs."
                "AcquisitionEnv take no terrain map (its clutter is per position); use "
                "SensorPointingEnv"
            )
        self.search_time = float(template.scene.choices.search_time)
        self._model = self._scenario_model
        names = [f"camera-{k}" for k in range(self.c)]
        self.streams = _EpisodeStreams(
            n, [names[k] for k in self.camera_of_row], [f"target-{j}" for j in range(self.t)]
        )
        self.state = SearchState(
            self.streams,
            np.array([0]),
            self.search_time,
            self._model.redraw,
            self._model.decorrelation_time,
        )
        self.clock = 0.0
        self.pool: SceneArrays | None = None
        self._chunks: dict[int, SceneArrays] = {}
        shape = (n, self.c)
        self.platform = np.zeros((n, 3))
        self.heading = np.full(n, math.pi / 2)
        self.time = np.zeros(n)
        self.pointing = np.zeros((*shape, 2))
        self.zoom_index = np.zeros(shape, dtype=np.int64)
        self.targets = np.zeros((n, self.t, 3))
        self.flags = np.zeros((3, n, self.t), dtype=bool)
        self.hazard = np.zeros((n, self.r, self.t))
        self.expected_rows = np.zeros((n, self.r, self.t))
        self.potential = np.zeros((n, self.t))
        self.prospect = np.zeros((3, n, self.t))
        self.in_view = np.zeros((n, self.t), dtype=bool)
        self.hidden = np.zeros((n, self.t), dtype=bool)  # by the terrain, from the platform
        self.progress = np.zeros((n, self.t))
        self.started = False

    # -- scenes --------------------------------------------------------------------------------

    def _tables(self, rng: np.random.Generator) -> tuple[dict[str, Any], int]:
        """An episode's tables (the legacy scene's draws, in its order) and its model seed."""
        data = self.o.scene.scene_tables(rng, 1, self.t)
        base = {
            k: v
            for k, v in data["sensors"][0].items()
            if k not in ("name", "azimuth", "depression")
        }
        sensors = []
        for c in range(self.c):
            for z, focal in enumerate(self.zoom):
                row = dict(base)
                if focal is None:
                    row["name"] = f"camera-{c}"
                else:
                    for group in ("hfov", "ifov"):
                        if group in row:
                            raise ValueError(
                                f"scenario_overrides: sensor.{group}: the zoom task's levels "
                                "are focal lengths; leave hfov and ifov out"
                            )
                    row["name"], row["focal_length"] = f"camera-{c}-zoom-{z}", focal
                sensors.append(row)
        data["sensors"] = sensors
        # The terrain's lines of sight are traced here (probabilities), over the model the
        # scene read once: not read again at each compilation.
        data.pop("terrain", None)
        seed = int(rng.integers(0, 2**31 - 1))
        return data, seed

    def _compile(self, rngs: list[np.random.Generator]) -> tuple[Any, list[int], np.ndarray]:
        """The compiled scenario of the new episodes of ``rngs`` (their targets in order), their
        model seeds and their targets' positions (M, T, 3)."""
        drawn = [self._tables(rng) for rng in rngs]
        data = dict(drawn[0][0])
        data["targets"] = [
            {**target, "name": f"{k}:{target['name']}"}
            for k, (tables, _) in enumerate(drawn)
            for target in tables["targets"]
        ]
        with collected():  # warned when the environment was made
            scenario = parse_scenario(data, "scenario_overrides", strict_units=False)
        self._scenario_model = scenario.model
        compiled = core.compile_scenario(scenario)
        positions = np.array([t["position"] for t in data["targets"]], dtype=float)
        return compiled, [seed for _, seed in drawn], positions.reshape(len(rngs), self.t, 3)

    def _start(self, envs: np.ndarray, rngs: list[np.random.Generator]) -> None:
        """New episodes for ``envs``: draws, scene, state of their pairs."""
        compiled, seeds, positions = self._compile(rngs)
        scene = compiled.scene
        cols = (envs[:, None] * self.t + np.arange(self.t)).reshape(-1)
        if self.pool is None:
            if envs.size != self.n:
                raise RuntimeError("the first start must start every episode")
            order = np.argsort(cols)
            self.pool = core.take_targets(scene, order)
        else:
            self.pool = replace(
                self.pool,
                targets=_put(self.pool.targets, cols, scene.targets, 0),
                signature=_put(self.pool.signature, cols, scene.signature, 1),
            )
        for k in set((envs // self.chunk).tolist()):
            self._chunks.pop(k, None)
        self.targets[envs] = positions
        self.platform[envs] = (-self.hw, 0.0, self.alt)
        self.heading[envs] = math.pi / 2
        self.time[envs] = 0.0
        self.pointing[envs] = _START_POINTING
        self.zoom_index[envs] = (self.z - 1) // 2
        for name in ("flags", "prospect"):
            getattr(self, name)[:, envs] = 0
        for name in ("hazard", "expected_rows", "potential", "in_view", "progress"):
            getattr(self, name)[envs] = 0
        per = self.r * self.t
        pairs = (envs[:, None] * per + np.arange(per)).reshape(-1)
        for env, seed in zip(envs.tolist(), seeds, strict=True):
            self.streams.seeds[env] = seed
        st = self.state
        st.u[:, pairs], st.clock[:, pairs], st.hazard[:, pairs] = 1.0, 0.0, 0.0
        st.level[:, pairs], st.renew[:, pairs], st.searches[:, pairs] = 0, False, 0
        st.draws[pairs], st.first[:, :, pairs] = 0, np.inf
        st.view[pairs], st.left[pairs], st.entered[pairs] = False, -np.inf, np.nan
        self.streams.ready[pairs] = False
        if st.p is not None:
            st.p = st.p.copy()
            st.p[:, pairs] = np.nan  # nothing happens to them in this step: a first step

    def _chunk(self, k: int) -> SceneArrays:
        found = self._chunks.get(k)
        if found is None:
            assert self.pool is not None
            lo, hi = k * self.chunk, min((k + 1) * self.chunk, self.n)
            found = core.take_targets(self.pool, np.arange(lo * self.t, hi * self.t))
            self._chunks[k] = found
        return found

    # -- the step ------------------------------------------------------------------------------

    def probabilities(self) -> np.ndarray:
        """The unpointed probabilities (3, N, rows, T) at the current positions."""
        assert self.pool is not None
        fraction = self._terrain()
        if self.pool.path.cloud_center.shape[0] == 0:
            return self._shifted(fraction)
        return self._chunked(fraction)

    def _terrain(self) -> np.ndarray | None:
        """With an elevation model, each episode's targets' visible fraction for the core (N,
        T), 1 where hidden, and :attr:`hidden` set: every platform-target line of sight of every
        episode in one call (:func:`targetacq.core.terrain_view.terrain_view`), from the true
        positions. Off the grid (the terrain unknown) a target counts as hidden."""
        if self.elevation is None:
            return None
        assert self.pool is not None
        # The episodes along the batch axis: one observer (the platform) per episode.
        per_episode = (self.n, self.t)
        heights = np.asarray(self.pool.targets.dimensions, dtype=float)[:, 2]
        own = np.asarray(self.pool.targets.visible_fraction, dtype=float)
        view = terrain_view(
            self.elevation,
            self.k,
            self.platform[None],
            self.targets.transpose(1, 0, 2),
            heights.reshape(per_episode).T,
            own.reshape(per_episode).T[None],
        )
        fraction = view.visible_fraction[0].T
        self.hidden = view.hidden[0].T | np.isnan(fraction)
        return np.where(self.hidden, 1.0, fraction)

    def _shifted(self, fraction: np.ndarray | None) -> np.ndarray:
        """:meth:`probabilities` in one call of the core over the N × T targets, each episode's
        targets moved by its platform's horizontal offset so that every camera stands at one
        place, (0, 0, altitude): the lines of sight, and the heights, are each pair's own (the
        platforms fly level at one altitude), and nothing else in a scene without clouds (or a
        terrain map, refused) depends on where a pair is. The terrain's ``fraction`` (N, T)
        comes from the true positions (:meth:`_terrain`)."""
        assert self.pool is not None
        offset = self.platform * np.array([1.0, 1.0, 0.0])
        t_pos = (self.targets - offset[:, None]).reshape(self.n * self.t, 3)
        s_pos = np.tile([0.0, 0.0, self.alt], (self.r, 1))
        if fraction is None:
            _, p = core.evaluate(self.pool, s_pos, t_pos)
        else:
            found = core.factors(self.pool, s_pos, t_pos, visible_fraction=fraction.reshape(1, -1))
            found = hide(found, self.hidden.reshape(1, -1))
            p = core.probabilities(self.pool, found)
        tasks = ("detection", "recognition", "identification")
        return np.stack(
            [np.asarray(getattr(p, name)).reshape(self.r, self.n, self.t) for name in tasks]
        ).transpose(0, 2, 1, 3)

    def _chunked(self, fraction: np.ndarray | None) -> np.ndarray:
        """:meth:`probabilities` a chunk of K episodes per core call: the chunk's K × T targets
        against its cameras, the episodes along the core's batch axis, the K × T pairs of each
        episode's own targets kept (a scene with clouds, whose places count)."""
        out = np.empty((3, self.n, self.r, self.t))
        for k in range((self.n + self.chunk - 1) // self.chunk):
            lo, hi = k * self.chunk, min((k + 1) * self.chunk, self.n)
            m = hi - lo
            s_pos = np.broadcast_to(self.platform[None, lo:hi], (self.r, m, 3))
            t_pos = np.broadcast_to(
                self.targets[lo:hi].reshape(m * self.t, 1, 3), (m * self.t, m, 3)
            )
            s_pos, t_pos = np.ascontiguousarray(s_pos), np.ascontiguousarray(t_pos)
            if fraction is None:
                _, p = core.evaluate(self._chunk(k), s_pos, t_pos)
            else:  # per target (each is one episode's: its own pairs are the ones kept)
                found = core.factors(
                    self._chunk(k),
                    s_pos,
                    t_pos,
                    visible_fraction=fraction[lo:hi].reshape(1, m * self.t, 1),
                )
                found = hide(found, self.hidden[lo:hi].reshape(1, m * self.t, 1))
                p = core.probabilities(self._chunk(k), found)
            ar = np.arange(m)
            for task, name in enumerate(("detection", "recognition", "identification")):
                value = np.asarray(getattr(p, name)).reshape(self.r, m, self.t, m)
                out[task, lo:hi] = value[:, ar, :, ar]  # (m, rows, T): each episode's own
        return out

    def view(self) -> np.ndarray:
        """Whether each episode's rows see each target (N, rows, T): the camera's field of view
        at its pointing, for the chosen zoom level, and not hidden by the terrain."""
        assert self.pool is not None
        az = self.pointing[..., 0][:, self.camera_of_row]
        dep = self.pointing[..., 1][:, self.camera_of_row]
        east, north, up = geometry.pointing_direction(az, dep)
        frame = geometry.sensor_frame(
            np.asarray(east)[..., None], np.asarray(north)[..., None], np.asarray(up)[..., None], np
        )
        los = self.targets[:, None] - self.platform[:, None, None]  # (N, 1, T, 3)
        shape = (self.n, self.r, self.t)
        x, y, z = (np.broadcast_to(los[..., k], shape).copy() for k in range(3))
        half = np.asarray(self.pool.sensors.half_tangents, dtype=float)
        inside = geometry.within_numpy(
            x, y, z, frame, half[None, :, 0, None], half[None, :, 1, None]
        )
        chosen = self.zoom_index[:, self.camera_of_row] == self.zoom_of_row[None]
        return inside & chosen[..., None] & ~self.hidden[:, None, :]

    def advance(self, starting: np.ndarray, rngs: list[np.random.Generator]) -> dict[str, Any]:
        """Start the episodes ``starting`` (bool (N,)), step the others (their platform and
        pointing already moved by the caller) and return the step's rewards and flags."""
        fresh = np.flatnonzero(starting)
        if fresh.size:
            self._start(fresh, [rngs[k] for k in fresh.tolist()])
        p = self.probabilities()
        inside = self.view()
        p_step = np.where(inside[None], p, 0.0)
        self.clock += self.dt if self.started else 0.0
        self.started = True
        self.state.advance(self.clock, p_step.reshape(3, -1), inside.reshape(-1))
        done = np.isfinite(self.state.first[:, 0]).reshape(3, self.n, self.r, self.t).any(axis=2)
        new = np.count_nonzero(done & ~self.flags, axis=(0, 2))
        new[fresh] = 0
        self.flags = done
        # The expected identification: hazard P_det/t_s while in view, P_id (1 − e^−Λ) kept at
        # its best, fused over the cameras (a camera's zoom levels are one look: their best);
        # an episode's first step covers no time.
        seen = np.where(starting[:, None, None], 0.0, p_step[0])
        self.hazard += self.dt * seen / self.search_time
        self.expected_rows = np.fmax(self.expected_rows, p_step[2] * -np.expm1(-self.hazard))
        per_camera = self.expected_rows.reshape(self.n, self.c, self.z, self.t).max(axis=2)
        expected = 1.0 - np.prod(1.0 - per_camera, axis=1)
        potential = np.maximum(self.potential, np.where(done[2], 1.0, expected))
        gain = (potential - self.potential).sum(axis=1)
        gain[fresh] = 0.0
        self.potential = potential
        self.prospect = np.nan_to_num(p.max(axis=2))
        self.in_view = np.asarray(inside.any(axis=1))
        self.progress = -np.expm1(-self.hazard.max(axis=1))
        return {"sparse": new.astype(float), "dense": gain}

    # -- the actions ---------------------------------------------------------------------------

    def aim(self, envs: np.ndarray, cameras: np.ndarray, targets: np.ndarray) -> np.ndarray:
        """Azimuth and depression [rad] from each episode's platform to its target (arrays of
        the same shape), (..., 2)."""
        offset = self.targets[envs, targets] - self.platform[envs]
        east, north, up = offset[..., 0], offset[..., 1], offset[..., 2]
        return np.stack([np.arctan2(east, north), np.arctan2(-up, np.hypot(east, north))], -1)

    def nearest(self, rank: np.ndarray) -> np.ndarray:
        """Per episode the ``rank``-th nearest target not yet identified (N, len(rank)); the
        nearest of all where every one is identified."""
        distance = np.linalg.norm(self.targets - self.platform[:, None], axis=-1)
        remaining = ~self.flags[2]
        masked = np.where(remaining, distance, np.inf)
        masked = np.where(remaining.any(axis=1, keepdims=True), masked, distance)
        order = np.argsort(masked, axis=1, kind="stable")
        return order[:, np.minimum(rank, self.t - 1)]

    def move(self, heading: np.ndarray, envs: np.ndarray) -> None:
        """Turn the platforms of ``envs`` toward ``heading`` (bounded turn) and fly one step."""
        limit = self.o.turn * self.dt
        change = np.clip(_wrap(heading - self.heading[envs]), -limit, limit)
        self.heading[envs] = _wrap(self.heading[envs] + change)
        step = self.speed * self.dt
        self.platform[envs, 0] += step * np.sin(self.heading[envs])
        self.platform[envs, 1] += step * np.cos(self.heading[envs])
        self.time[envs] += self.dt


def _wrap(angle: Any) -> Any:
    """An angle in [−π, π) [rad]."""
    return (np.asarray(angle) + math.pi) % (2 * math.pi) - math.pi
