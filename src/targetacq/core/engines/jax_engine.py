"""The JAX engine: the array core under ``jax.jit``, in float64, NumPy arrays in and out.

:class:`JaxScene` converts the scene to JAX arrays once (:func:`targetacq.core.records.as_jax`)
and runs :func:`targetacq.core.evaluate` — factors, then probabilities and their fusion — as
**one** jitted function of the positions, headings and pointing: nothing returns to the host
between the factors and the probabilities, and the results of a call come back in one
device-to-host transfer (``jax.device_get``) at the end. :meth:`JaxScene.factors` runs it and
keeps the probabilities for :meth:`JaxScene.probabilities` of the factors it returned (the
``factors`` then ``probabilities`` steps of :class:`targetacq.run.model_chain.ModelChain`);
factors changed on the host in between (a terrain map's SCR, graded motion) go back to the
device and through the probabilities alone.

Fixed shapes, one compilation
    JAX compiles a function once per shape of its inputs. The engine cuts the batch axes of the
    positions (the times of a run; flattened to one axis) into chunks of a fixed length
    (:func:`chunk_length`: :data:`BATCH_PER_CALL` elements, fewer where the scene has so many
    pairs that a chunk would exceed :data:`TRIPLES_PER_CALL` sensor–target–time triples) and
    pads the last chunk with NaN positions, whose results are dropped. Every call of a bound
    scene, whatever its number of times, runs the same compiled shape; the jitted function is
    shared by every bound scene and the targets' names are not part of the compiled shape, so
    the chunks of targets of :meth:`~targetacq.run.model_chain.ModelChain.evaluate_chunks` (as
    many targets each, but the last) reuse it too. :func:`compilations` counts the traces.

Precision: float64 for the duration of each call (``jax.enable_x64``), not process-wide, so the
numbers equal the NumPy engine's to about 1e-12 relative. Device: JAX's default one, a GPU
where JAX has one (``pip install 'targetacq[jax-cuda]'``). The steps after the core (the draws
of the step API, writers) are the NumPy ones.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.core.evaluation import (
    Factors,
    Probabilities,
    check_moving,
    check_visible_fraction,
    evaluate,
    evaluate_step,
    pair_shape,
    probabilities,
)
from targetacq.core.records import SceneArrays, as_jax

__all__ = ["BATCH_PER_CALL", "TRIPLES_PER_CALL", "JaxScene", "chunk_length", "compilations"]

BATCH_PER_CALL = 64
"""The most batch elements (times) one compiled call takes: the default ``times_per_chunk`` of
:meth:`~targetacq.run.model_chain.ModelChain.evaluate_chunks`, so its chunks need no padding
but the last."""

TRIPLES_PER_CALL = 1 << 20
"""The most sensor–target–time triples one compiled call takes where the batch has more than
one element (about 100 MB of float64 results)."""

_TRACES = {"evaluate": 0, "probabilities": 0}


def compilations() -> dict[str, int]:
    """How many times the engine's two jitted functions have been traced (each trace is one
    compilation), since the process started.

    Returns
    -------
    dict
        ``{"evaluate": n, "probabilities": m}``: positions to factors and probabilities, and
        factors to probabilities (factors changed on the host).
    """
    return dict(_TRACES)


def chunk_length(pairs: int, batch: int) -> int:
    """The batch length of one compiled call for ``pairs`` sensor–target pairs and a batch of
    ``batch`` elements: ``batch`` itself where it is 1, else at least 2 and at most
    :data:`BATCH_PER_CALL`, and no more than :data:`TRIPLES_PER_CALL` triples.

    Examples
    --------
    >>> chunk_length(10, 1), chunk_length(10, 500), chunk_length(10**6, 500)
    (1, 64, 2)
    """
    if batch <= 1:
        return 1
    return max(2, min(BATCH_PER_CALL, TRIPLES_PER_CALL // max(pairs, 1)))


def _evaluate_body(
    scene: SceneArrays,
    sensor_positions: Any,
    target_positions: Any,
    headings: Any,
    pointing: Any,
    scr: Any,
    visible_fraction: Any,
    moving: Any,
) -> tuple[Factors, Probabilities]:
    _TRACES["evaluate"] += 1  # the Python body runs only when JAX traces (and compiles)
    return evaluate(
        scene,
        sensor_positions,
        target_positions,
        headings,
        pointing,
        scr,
        visible_fraction,
        moving,
    )


def _probabilities_body(scene: SceneArrays, found: Factors, moving: Any) -> Probabilities:
    _TRACES["probabilities"] += 1
    return probabilities(scene, found, moving)


_JITTED: dict[str, Any] = {}


def _jitted(jax: Any) -> dict[str, Any]:
    """The engine's jitted functions, made once per process (shared by every bound scene, so
    their compilations are too)."""
    if not _JITTED:
        _JITTED["evaluate"] = jax.jit(_evaluate_body)
        _JITTED["probabilities"] = jax.jit(_probabilities_body)
        _JITTED["step"] = jax.jit(evaluate_step)
    return _JITTED


def _per_triple(value: Any, shape: tuple[int, ...], batch: int) -> np.ndarray:
    """``value`` broadcast to the pairs ``shape`` = ``(n_s, n_g, *batch)``, batch flattened."""
    return np.broadcast_to(np.asarray(value), shape).reshape(*shape[:2], batch)


class _Chunks:
    """The flattened batch axis of a call cut into chunks of one length, the last padded."""

    def __init__(self, batch: tuple[int, ...], pairs: int, squeeze: bool) -> None:
        self.batch = batch
        self.size = math.prod(batch)
        self.length = chunk_length(pairs, self.size)
        self.count = max(1, -(-self.size // self.length))
        self.squeeze = squeeze

    def split(self, value: Any, fill: float) -> list[Any]:
        """Chunks of the last axis of ``value`` (None stays None), the last padded with
        ``fill``."""
        if value is None:
            return [None] * self.count
        padded = self.count * self.length - self.size
        if padded:
            pad = [(0, 0)] * (value.ndim - 1) + [(0, padded)]
            value = np.pad(value, pad, constant_values=fill if value.dtype.kind == "f" else 0)
        return [value[..., k * self.length : (k + 1) * self.length] for k in range(self.count)]

    def join(self, parts: list[Any]) -> Any:
        """One output leaf from its chunks: joined along the batch axis, the padding dropped,
        the batch axes of the call restored (a leaf of batch length 1 in chunks longer than
        one does not vary over the batch: the first chunk's)."""
        first = parts[0]
        if first is None:
            return None
        if first.shape[-1] == 1 and self.length > 1:
            whole = first
            batch: tuple[int, ...] = (1,) * len(self.batch)
        else:
            whole = np.concatenate(parts, axis=-1)[..., : self.size]
            batch = self.batch
        if self.squeeze:
            return whole[..., 0]
        return whole.reshape(*whole.shape[:-1], *batch)


def _joined(record_type: Any, chunks: _Chunks, parts: list[Any]) -> Any:
    """A record of the core from its chunks (host arrays)."""
    return record_type(
        **{
            f.name: chunks.join([getattr(part, f.name) for part in parts])
            for f in dataclasses.fields(record_type)
        }
    )


class JaxScene:
    """A scene bound to the JAX engine (see the module docstring).

    Parameters
    ----------
    scene : SceneArrays

    Raises
    ------
    ValueError
        A radar whose detector runs on NumPy only (SciPy).
    """

    engine = "jax"

    def __init__(self, scene: SceneArrays) -> None:
        import jax

        if scene.radar is not None:
            from targetacq.physics.radar_equation import RADAR_DETECTION_MODELS

            for row, detector in zip(scene.radar.rows, scene.radar.detectors, strict=True):
                if not RADAR_DETECTION_MODELS[detector].traceable:
                    raise ValueError(
                        f"radar {scene.sensors.names[row]!r}: detector {detector!r} runs on "
                        "NumPy only (SciPy); use engine='numpy'"
                    )

        self._jax = jax
        self._functions = _jitted(jax)
        # The targets' names select no code: left out of the compiled shape, so chunks of
        # other targets (of the same count) reuse the compilation.
        anonymous = dataclasses.replace(
            scene, targets=dataclasses.replace(scene.targets, names=("",) * scene.shape[1])
        )
        with jax.enable_x64(True):
            self.scene = as_jax(anonymous)
        self._headings = np.asarray(scene.targets.heading, dtype=float)
        self._moving = np.asarray(scene.targets.moving, dtype=bool).reshape(-1)
        self._kept: tuple[Factors, list[Any], _Chunks, Probabilities] | None = None

    @staticmethod
    def _check_positions(sensor_positions: Any, target_positions: Any) -> None:
        """Infinite positions raise on the host, as with NumPy (under jit the checks of the
        core see tracers, which they let through)."""
        for name, value in (
            ("sensor_positions", sensor_positions),
            ("target_positions", target_positions),
        ):
            given = np.asarray(value)
            if given.dtype.kind == "f" and np.isinf(given).any():
                _arrays.require_finite(name, given, np, "m")

    def evaluate(
        self,
        sensor_positions: Array,
        target_positions: Array,
        headings: Array = None,
        pointing: Array = None,
        scr: Array = None,
        visible_fraction: Array = None,
        moving: Array = None,
    ) -> tuple[Factors, Probabilities]:
        """:func:`targetacq.core.evaluate` of the bound scene in one jitted call per chunk
        of the batch and one transfer to the host, in NumPy arrays.

        Parameters
        ----------
        sensor_positions : array (n_s, *batch, 3)
            [m].
        target_positions : array (n_g, *batch, 3)
            [m].
        headings, pointing, scr, visible_fraction, moving
            As :func:`targetacq.core.evaluate`.

        Returns
        -------
        Factors, Probabilities
        """
        found, _, _, p = self._run(
            sensor_positions, target_positions, headings, pointing, scr, visible_fraction, moving
        )
        return found, p

    def _run(
        self,
        sensor_positions: Any,
        target_positions: Any,
        headings: Any,
        pointing: Any,
        scr: Any,
        visible_fraction: Any,
        moving: Any,
    ) -> tuple[Factors, list[Any], _Chunks, Probabilities]:
        self._check_positions(sensor_positions, target_positions)
        s_pos = np.asarray(sensor_positions, dtype=float)
        t_pos = np.asarray(target_positions, dtype=float)
        n_s, n_g = self.scene.shape
        for name, value, count in (
            ("sensor_positions", s_pos, n_s),
            ("target_positions", t_pos, n_g),
        ):
            if value.ndim < 2 or value.shape[0] != count or value.shape[-1] != 3:
                raise ValueError(
                    f"{name} must have shape ({count}, *batch, 3) (east, north, up [m]); got "
                    f"{value.shape}"
                )
        pairs = pair_shape((n_s, n_g), s_pos, t_pos)
        batch = pairs[2:]
        chunks = _Chunks(batch, n_s * n_g, squeeze=not batch)
        size = chunks.size
        s_flat = np.broadcast_to(s_pos, (n_s, *batch, 3)).reshape(n_s, size, 3)
        t_flat = np.broadcast_to(t_pos, (n_g, *batch, 3)).reshape(n_g, size, 3)
        own = self._headings.reshape((n_g,) + (1,) * len(batch))
        given = own if headings is None else np.asarray(headings, dtype=float)
        h_flat = np.broadcast_to(given, (n_g, *batch)).reshape(n_g, size)
        if visible_fraction is not None:  # checked on the host: values are traced under jit
            visible_fraction = _per_triple(
                check_visible_fraction(np.asarray(visible_fraction, dtype=float), pairs, np),
                pairs,
                size,
            )
        if scr is not None:
            scr = _per_triple(np.asarray(scr, dtype=float), pairs, size)
        flags = self._moving if moving is None else np.asarray(check_moving(moving, n_g))
        jnp = self._jax.numpy
        fixed = None if pointing is None else jnp.asarray(np.asarray(pointing, dtype=float))
        outputs = []
        with self._jax.enable_x64(True):
            flags_on_device = jnp.asarray(flags)
            for s, t, h, c, v in zip(
                # Padding: NaN positions, whose results (NaN) are dropped.
                chunks.split(np.moveaxis(s_flat, 1, -1), np.nan),
                chunks.split(np.moveaxis(t_flat, 1, -1), np.nan),
                chunks.split(h_flat, 0.0),
                chunks.split(scr, 1.0),
                chunks.split(visible_fraction, 1.0),
                strict=True,
            ):
                outputs.append(
                    self._functions["evaluate"](
                        self.scene,
                        jnp.asarray(np.moveaxis(s, -1, 1)),
                        jnp.asarray(np.moveaxis(t, -1, 1)),
                        jnp.asarray(h),
                        fixed,
                        None if c is None else jnp.asarray(c),
                        None if v is None else jnp.asarray(v),
                        flags_on_device,
                    )
                )
            on_host = self._jax.device_get(outputs)  # the one transfer to the host
        found = _joined(Factors, chunks, [f for f, _ in on_host])
        p = _joined(Probabilities, chunks, [q for _, q in on_host])
        return found, [f for f, _ in outputs], chunks, p

    def factors(
        self,
        sensor_positions: Any,
        target_positions: Any,
        headings: Any = None,
        pointing: Any = None,
        scr: Any = None,
        visible_fraction: Any = None,
    ) -> Factors:
        """As :func:`targetacq.core.factors` of the bound scene, in NumPy arrays (computed with
        the probabilities, which :meth:`probabilities` of the returned factors gives)."""
        kept = self._run(
            sensor_positions, target_positions, headings, pointing, scr, visible_fraction, None
        )
        self._kept = kept
        return kept[0]

    def probabilities(self, found: Factors, moving: Any = None) -> Probabilities:
        """As :func:`targetacq.core.probabilities` of the bound scene, in NumPy arrays.

        The factors :meth:`factors` returned last, unchanged: their probabilities, computed
        with them (other moving flags: from the factors still on the device). Other factors go
        to the device in chunks (as :meth:`evaluate`).
        """
        if moving is not None:  # checked on the host, then traced: one compilation for all
            moving = np.asarray(check_moving(moving, self.scene.shape[1]))
        kept = self._kept
        jnp = self._jax.numpy
        if kept is not None and found is kept[0]:
            if moving is None:
                return kept[3]
            with self._jax.enable_x64(True):
                flags = jnp.asarray(moving)
                parts = [
                    self._functions["probabilities"](self.scene, part, flags) for part in kept[1]
                ]
                return _joined(Probabilities, kept[2], self._jax.device_get(parts))
        n_s, n_g = self.scene.shape
        batch = tuple(np.shape(found.range)[2:])
        pairs = (n_s, n_g, *batch)
        chunks = _Chunks(batch, n_s * n_g, squeeze=not batch)
        names = [f.name for f in dataclasses.fields(Factors)]
        columns = {
            name: chunks.split(
                None
                if getattr(found, name) is None
                else _per_triple(getattr(found, name), pairs, chunks.size),
                np.nan,
            )
            for name in names
        }
        flags = self._moving if moving is None else moving
        with self._jax.enable_x64(True):
            on_device = jnp.asarray(flags)
            parts = []
            for k in range(chunks.count):
                part = {name: columns[name][k] for name in names}
                chunk = Factors(
                    **{name: None if v is None else jnp.asarray(v) for name, v in part.items()}
                )
                parts.append(self._functions["probabilities"](self.scene, chunk, on_device))
            return _joined(Probabilities, chunks, self._jax.device_get(parts))

    def step(
        self,
        sensor_positions: Any,
        target_positions: Any,
        headings: Any = None,
        pointing: Any = None,
        visible_fraction: Any = None,
        moving: Any = None,
        scr: Any = None,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """As :func:`targetacq.core.evaluate_step` of the bound scene, in NumPy arrays."""
        self._check_positions(sensor_positions, target_positions)
        if visible_fraction is not None:
            visible_fraction = check_visible_fraction(
                np.asarray(visible_fraction, dtype=float), self.scene.shape, np
            )
        if moving is not None:
            moving = np.asarray(check_moving(moving, self.scene.shape[1]))
        jnp = self._jax.numpy
        with self._jax.enable_x64(True):
            arrays = [
                None if v is None else jnp.asarray(v)
                for v in (
                    sensor_positions,
                    target_positions,
                    headings,
                    pointing,
                    visible_fraction,
                    moving,
                    scr,
                )
            ]
            out = self._functions["step"](self.scene, *arrays)
            in_view, p, fused = self._jax.device_get(out)
            return np.asarray(in_view), np.asarray(p), np.asarray(fused)
