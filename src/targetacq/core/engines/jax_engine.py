"""The JAX engine: the array core under ``jax.jit``, in float64, NumPy arrays in and out.

:class:`JaxScene` converts the scene to JAX arrays once (:func:`targetacq.core.records.as_jax`)
and compiles :func:`targetacq.core.factors` and :func:`targetacq.core.probabilities` with
``jax.jit`` (once per shape of the inputs). Both run with float64 enabled for their duration
(``jax.enable_x64``), not process-wide, so the numbers equal the NumPy engine's to about 1e-12
relative; they run on JAX's default device, a GPU where JAX has one. The results come back as
NumPy arrays, so the steps after the core (terrain clutter, the draws of the step API, writers)
are the NumPy ones.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from targetacq.base import arrays as _arrays
from targetacq.core.evaluation import (
    Factors,
    Probabilities,
    check_moving,
    check_visible_fraction,
    evaluate_step,
    factors,
    probabilities,
)
from targetacq.core.records import SceneArrays, as_jax

__all__ = ["JaxScene"]


def _host(record: Any) -> Any:
    """The record with every array field a NumPy array."""
    return dataclasses.replace(
        record,
        **{
            f.name: None if getattr(record, f.name) is None else np.asarray(getattr(record, f.name))
            for f in dataclasses.fields(record)
        },
    )


class JaxScene:
    """A scene bound to the JAX engine (see the module docstring).

    Parameters
    ----------
    scene : SceneArrays
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
        with jax.enable_x64(True):
            self.scene = as_jax(scene)
        self._factors = jax.jit(factors)
        self._probabilities = jax.jit(probabilities)
        self._step = jax.jit(evaluate_step)

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

    def _device(self, value: Any) -> Any:
        return None if value is None else self._jax.numpy.asarray(value)

    def factors(
        self,
        sensor_positions: Any,
        target_positions: Any,
        headings: Any = None,
        pointing: Any = None,
        scr: Any = None,
        visible_fraction: Any = None,
    ) -> Factors:
        """As :func:`targetacq.core.factors` of the bound scene, in NumPy arrays."""
        self._check_positions(sensor_positions, target_positions)
        if visible_fraction is not None:  # checked on the host: values are traced under jit
            s_shape, t_shape = np.shape(sensor_positions), np.shape(target_positions)
            batch = np.broadcast_shapes(tuple(s_shape[1:-1]), tuple(t_shape[1:-1]))
            visible_fraction = check_visible_fraction(
                np.asarray(visible_fraction, dtype=float), (*self.scene.shape, *batch), np
            )
        with self._jax.enable_x64(True):
            arrays = [
                self._device(v)
                for v in (
                    sensor_positions,
                    target_positions,
                    headings,
                    pointing,
                    scr,
                    visible_fraction,
                )
            ]
            found = self._factors(self.scene, *arrays)
            return _host(found)

    def probabilities(self, found: Factors, moving: Any = None) -> Probabilities:
        """As :func:`targetacq.core.probabilities` of the bound scene, in NumPy arrays."""
        if moving is not None:  # checked on the host, then traced: one compilation for all
            moving = np.asarray(check_moving(moving, self.scene.shape[1]))
        with self._jax.enable_x64(True):
            on_device = dataclasses.replace(
                found,
                **{f.name: self._device(getattr(found, f.name)) for f in dataclasses.fields(found)},
            )
            return _host(self._probabilities(self.scene, on_device, self._device(moving)))

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
        with self._jax.enable_x64(True):
            arrays = [
                self._device(v)
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
            in_view, p, fused = self._step(self.scene, *arrays)
            return np.asarray(in_view), np.asarray(p), np.asarray(fused)
