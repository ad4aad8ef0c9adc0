"""The numba engine: the core's pipeline compiled, two fused loops per evaluation.

:class:`NumbaScene` holds what the kernels of :mod:`targetacq.core.engines.numba_kernels` need of a
scene, made once when the engine is bound to it (the curves of the tables, the noise law's
anchors, the model choices as codes, the per-sensor and per-target arrays). Each evaluation then
prepares the positions (the boresight and the sensor frame per sensor and batch element, with the
NumPy core's own functions, so that the field-of-view test is the same to the last bit) and runs

1. :func:`~targetacq.core.engines.numba_kernels._factors_kernel`: range, outline, critical
   dimension, cycles, field of view, optical depth with segments and clouds, transmittance, SNR;
2. :func:`~targetacq.core.engines.numba_kernels._probabilities_kernel`: noise, the transforms,
   detection in clutter, hot spots and motion, the semantics, the field of view and the
   sensor-level fusion (8.4).

Positions of one time, ``(n_s, 3)`` and ``(n_g, 3)`` (a step of the step API), go through the
kernels of :mod:`targetacq.core.engines.numba_pairs` instead, which take the targets as their inner
loop and the pairs in view as the probabilities' list; :meth:`NumbaScene.step` runs both in one
call. What those kernels need of the scene (the sensor table with each sensor's aim, the
headings' sines and cosines, the targets' dimensions by component) is made when the engine is
bound, and the inputs of a call are checked in the kernel where that is cheaper (infinite
positions).

Terrain maps work as with NumPy: :func:`targetacq.core.evaluation.footprint_scr` gives the SCR per
pair between the two loops. NumPy arrays only.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from targetacq.acquisition import path_noise as noise
from targetacq.acquisition import transforms
from targetacq.acquisition.fusion import fuse_groups
from targetacq.acquisition.probabilities import low_clutter_scale
from targetacq.base import arrays as _arrays
from targetacq.core.engines import numba_kernels as kernels
from targetacq.core.engines import numba_pairs as pairs
from targetacq.core.evaluation import (
    Factors,
    Probabilities,
    boresight,
    check_moving,
    check_visible_fraction,
    pair_shape,
)
from targetacq.core.records import SceneArrays
from targetacq.physics import geometry

__all__ = ["NumbaScene", "supported"]

_NOISE_CODES = {
    "variance-sum": kernels.NOISE_VARIANCE_SUM,
    "clutter-analogue": kernels.NOISE_CLUTTER_ANALOGUE,
    "none": kernels.NOISE_IGNORED,
}
_TRANSFORM_CODES = {"ttpf": kernels.TRANSFORM_TTPF, "c2nveo": kernels.TRANSFORM_TABLE}
_MOTION_CODES = {"low-clutter": kernels.MOTION_LOW_CLUTTER, "always": kernels.MOTION_ALWAYS}
_SEMANTICS_CODES = {
    "nested": kernels.SEMANTICS_NESTED,
    "conditional": kernels.SEMANTICS_CONDITIONAL,
}
_TASKS = ("detection", "recognition", "identification")
_SHORT_BATCH = 8  # batches shorter than this run their targets as the kernel's batch


def supported(scene: SceneArrays) -> str | None:
    """Why the numba engine cannot evaluate ``scene`` (None if it can).

    It compiles the built-in choices: the transforms ``ttpf`` and ``c2nveo``, every noise model,
    motion rule and semantics of the registries. A transform, noise model, motion rule or
    semantics given as an object of one's own runs on the NumPy engine only; a scene with
    radars, laser radars, MRTD-limited sensors (a sensor's ``mrtd`` curve), the TTP resolution
    model, foliage in front of a target, a sensor's digitiser step (``quantisation_step``),
    graded cues (a target's ``hot_spot_ratio`` or ``graded_motion``) or a background's
    ``sky_to_ground`` on NumPy or JAX. Every SNR law of the registry compiles (the contrast
    law's SNR and its threshold: the kernels'
    :func:`~targetacq.core.engines.numba_kernels.contrast_snr` and
    :func:`~targetacq.core.engines.numba_kernels.seen_probability`).
    """
    if scene.radar is not None or scene.laser is not None:
        return (
            "the numba engine compiles the imaging sensors; radars and laser radars run on "
            "engine='numpy' (or 'jax')"
        )
    if scene.sensors.mrtd is not None:
        return (
            "the numba engine compiles the geometric resolution; MRTD-limited sensors (a "
            "sensor's mrtd curve) run on engine='numpy' (or 'jax')"
        )
    if scene.sensors.ttp is not None:
        return (
            "the numba engine compiles the geometric resolution; the TTP resolution model "
            "(model.resolution_model = 'ttp') runs on engine='numpy' (or 'jax')"
        )
    if scene.signature.aspect is not None:
        return (
            "the numba engine compiles one contrast per pair; signature tables over the aspect "
            "(a target's signature_table) run on engine='numpy' (or 'jax')"
        )
    if scene.targets.foliage is not None:
        return (
            "the numba engine compiles the path of the atmosphere; foliage in front of a target "
            "(a target's foliage) runs on engine='numpy' (or 'jax')"
        )
    if scene.path.named_depths is not None:
        return (
            "the numba engine compiles Beer-Lambert paths; a named atmosphere (atmosphere.model, "
            "aerosol) runs on engine='numpy' (or 'jax')"
        )
    if scene.targets.graded:
        return (
            "the numba engine compiles the hot-spot and motion switches; graded cues (a "
            "target's hot_spot_ratio or graded_motion, weighted per pair by its SCR, size and "
            "angular speed) run on engine='numpy' (or 'jax')"
        )
    if scene.sensors.sky_to_ground is not None:
        return (
            "the numba engine compiles the contrast's transmittance τ; the airlight of a "
            "background's sky_to_ground ratio runs on engine='numpy' (or 'jax')"
        )
    if scene.sensors.quantisation_step is not None:
        return (
            "the numba engine compiles the probabilities without a digitiser; a sensor's "
            "quantisation step (quantisation_step, adc_bits) runs on engine='numpy' (or 'jax')"
        )
    choices = scene.choices
    for what, value, codes in (
        ("transform", choices.transform, _TRANSFORM_CODES),
        ("noise model", choices.noise_model, _NOISE_CODES),
        ("motion rule", choices.motion, _MOTION_CODES),
        ("semantics", choices.semantics, _SEMANTICS_CODES),
    ):
        if not isinstance(value, str) or value not in codes:
            return (
                f"the numba engine compiles the {what}s {', '.join(codes)}; got {value!r}: use "
                f"engine='numpy' for it"
            )
    return None


def _curve_arrays(curves: list[Any]) -> np.ndarray:
    """(len(curves), 4, CURVE_POINTS): cycles, their logarithms, probabilities and the slopes
    ``dP / d ln N`` of the segments (0 where a segment has no width), each curve padded with its
    last point (:data:`~targetacq.core.engines.numba_kernels.CURVE_POINTS`)."""
    table = np.zeros((len(curves), 4, kernels.CURVE_POINTS))
    for k, c in enumerate(curves):
        count = len(c.cycles)
        if count > kernels.CURVE_POINTS:
            raise ValueError(
                f"a table curve of {count} points; the kernels read at most {kernels.CURVE_POINTS}"
            )
        pad = kernels.CURVE_POINTS - count
        table[k, 0] = list(c.cycles) + [c.cycles[-1]] * pad
        table[k, 1] = [math.log(n) for n in table[k, 0]]
        table[k, 2] = list(c.probabilities) + [c.probabilities[-1]] * pad
        width = np.diff(table[k, 1])
        rise = np.diff(table[k, 2])
        table[k, 3, :-1] = np.divide(rise, width, out=np.zeros_like(rise), where=width > 0)
    return table


def _float(value: Any) -> np.ndarray:
    return np.ascontiguousarray(np.asarray(value, dtype=np.float64))


class NumbaScene:
    """A scene bound to the numba engine (see the module docstring).

    Parameters
    ----------
    scene : SceneArrays
        With NumPy arrays.

    Raises
    ------
    ValueError
        A choice the engine does not compile (:func:`supported`).
    """

    engine = "numba"

    def __init__(self, scene: SceneArrays) -> None:
        reason = supported(scene)
        if reason is not None:
            raise ValueError(reason)
        self.scene = scene
        self._target_groups: list[np.ndarray] | None = None
        sensors, targets, path, choices = scene.sensors, scene.targets, scene.path, scene.choices
        self.sensor_arrays = (
            _float(sensors.cycle),
            _float(sensors.ifov),
        )
        self.half_tangents = _float(sensors.half_tangents)
        self.extinction = _float(sensors.extinction)
        self.segment_length = _float(path.segment_length).reshape(-1)
        self.segment_extinction = _float(sensors.segment_extinction).reshape(
            len(sensors.names), self.segment_length.size
        )
        n_c = np.asarray(path.cloud_radius).size
        self.clouds = _float(
            np.column_stack(
                [
                    np.asarray(path.cloud_center, dtype=float).reshape(n_c, 3),
                    np.asarray(path.cloud_radius, dtype=float).reshape(n_c),
                    np.asarray(path.cloud_extinction, dtype=float).reshape(n_c),
                ]
            ).reshape(n_c, 5)
        )
        self.noise_equivalent = _float(sensors.noise_equivalent)
        # The SNR law (:func:`targetacq.core.evaluation.factors` forms it the same way): the
        # contrast law where some row has a noise of its own and the reference contrasts are
        # known, each row's σ_path (−1: the sonesson law) and threshold k (−inf: none).
        law = noise.get_snr_law(choices.snr_law)
        self.contrast_law = bool(
            sensors.has_noise and sensors.path_contrast is not None and law.contrast_aware
        )
        n_rows = self.noise_equivalent.size
        self.path_contrast = (
            _float(sensors.path_contrast).reshape(n_rows)
            if self.contrast_law
            else np.full(n_rows, -1.0)
        )
        self.thresholds = np.full(n_rows, -np.inf)
        if self.contrast_law and law.threshold is not None:
            self.thresholds[self.noise_equivalent > 0] = law.threshold
        self.contrast = _float(scene.signature.contrast)
        self.dimensions = _float(targets.dimensions).reshape(-1, 3)
        self.visible_fraction = _float(targets.visible_fraction)
        self.heading = _float(targets.heading)
        self.n50 = _float(targets.n50).reshape(-1, 3)
        moving_n50 = self.n50[:, 0] * low_clutter_scale()  # a moving target's detection N50
        with np.errstate(divide="ignore"):
            self.log_n50 = np.ascontiguousarray(
                np.column_stack([np.log(self.n50), moving_n50, np.log(moving_n50)])
            )
        self.hot_spot = np.ascontiguousarray(np.asarray(targets.hot_spot, dtype=bool))
        self.moving = np.ascontiguousarray(np.asarray(targets.moving, dtype=bool))
        with_snr = path.attenuates or sensors.has_noise
        region = choices.region
        self.settings = np.array(
            [
                _NOISE_CODES[choices.noise_model] if with_snr else kernels.NOISE_NONE_GIVEN,
                int(noise.get_noise_model(choices.noise_model).combines_with_clutter),
                _TRANSFORM_CODES[choices.transform],
                kernels.REGION_NONE if region is None else transforms.CLUTTER_REGIONS.index(region),
                _MOTION_CODES[choices.motion],
                _SEMANTICS_CODES[choices.semantics],
                0,  # has_scr: set per evaluation
            ],
            dtype=np.int64,
        )
        low, medium, alpha = noise.ratio_anchors()
        self.noise_anchors = np.array([noise.QUADRATURE_CONSTANT, low, medium, alpha])
        sw_curves = transforms.sw_curves()
        self.sw = _curve_arrays([sw_curves[r] for r in transforms.CLUTTER_REGIONS])
        scr_low, _, sw_alpha = transforms.sw_high_anchor()
        self.sw_constants = np.array(
            [transforms.sw_reference_n50(), scr_low, sw_alpha, low_clutter_scale()]
        )
        options = dict(choices.options)
        chosen = transforms.get_transform(choices.transform)
        for task in _TASKS:
            chosen.check(task, options)  # unknown options: ValueError, as with NumPy
        if choices.transform == "c2nveo":
            bound = options.get("bound", "nominal")
            if bound not in transforms.C2NVEO_BOUNDS:
                raise ValueError(
                    f"bound must be one of {', '.join(transforms.C2NVEO_BOUNDS)}; got {bound!r}"
                )
            curves = transforms.c2nveo_curves()
            self.tables = _curve_arrays([curves[t, bound] for t in _TASKS])
            self.table_reference = np.array([transforms.c2nveo_reference_n50(t) for t in _TASKS])
        else:  # unused by the TTPF: a placeholder of the same types
            self.tables = self.sw
            self.table_reference = np.ones(3)
        # One time (single batch): the pair kernels' inputs that the scene fixes.
        self.shape = scene.shape
        self._sensor_table = self._sensors_for(None)
        self._sin_cos = np.ascontiguousarray(np.stack([np.sin(self.heading), np.cos(self.heading)]))
        self._dimensions = np.ascontiguousarray(self.dimensions.T)
        self._visible_row = self.visible_fraction.reshape(1, -1)
        signature_scr = scene.signature.scr
        self._scr = None if signature_scr is None else _float(signature_scr).reshape(self.shape)
        self._zeros = np.zeros(self.shape)
        self._zeros.flags.writeable = False
        self._has_noise = bool(sensors.has_noise)
        self._with_snr = bool(with_snr)

    # -- one time: every pair in one call ------------------------------------------------------

    def _sensors_for(self, pointing: Any) -> np.ndarray:
        """The sensor table of :mod:`targetacq.core.engines.numba_pairs` (``SENSOR_COLUMNS``), the
        sensors pointed as :func:`targetacq.core.evaluation.boresight` points them: at their
        ``look_at`` point, else along their angles; ``pointing`` (n_s, 2), where finite,
        replaces both."""
        sensors = self.scene.sensors
        n_s = len(sensors.names)
        look_at = np.asarray(sensors.look_at, dtype=float).reshape(n_s, 3)
        angles = np.asarray(sensors.pointing, dtype=float).reshape(n_s, 2)
        pointed = np.asarray(sensors.pointed, dtype=bool).reshape(n_s)
        if pointing is not None:
            given = np.asarray(pointing, dtype=float)
            if given.shape != (n_s, 2):
                raise ValueError(
                    f"pointing must have shape ({n_s}, 2): azimuth and depression [rad] of each "
                    f"sensor; got {given.shape}"
                )
            chosen = np.isfinite(given[:, 0]) & np.isfinite(given[:, 1])
            angles = np.where(chosen[:, None], given, angles)
            look_at = np.where(chosen[:, None], np.nan, look_at)
            pointed = pointed | chosen
        by_point = np.isfinite(look_at[:, 0])
        by_angles = np.isfinite(angles[:, 0])
        direction = geometry.pointing_direction(
            np.where(by_angles, angles[:, 0], 0.0), np.where(by_angles, angles[:, 1], 0.0)
        )
        table = np.empty((n_s, pairs.SENSOR_COLUMNS))
        table[:, pairs.CYCLE] = self.sensor_arrays[0]
        table[:, pairs.IFOV] = self.sensor_arrays[1]
        table[:, pairs.TAN_H : pairs.TAN_V + 1] = self.half_tangents.reshape(n_s, 2)
        table[:, pairs.EXTINCTION] = self.extinction
        table[:, pairs.NOISE_EQUIVALENT] = self.noise_equivalent
        table[:, pairs.PATH_CONTRAST] = self.path_contrast
        table[:, pairs.VIEWING] = pointed & np.isfinite(self.half_tangents.reshape(n_s, 2)[:, 0])
        table[:, pairs.BY_POINT] = by_point
        for k in range(3):
            table[:, pairs.AIM + k] = np.where(by_point, look_at[:, k], direction[k])
        return table

    def _pair_positions(self, sensor_positions: Any, target_positions: Any) -> tuple[Any, Any]:
        """Positions ``(n_s, 3)`` and ``(n_g, 3)`` as contiguous float64 arrays, else None (not
        one time: the batch kernels take them)."""
        n_s, n_g = self.shape
        out = []
        for value, count in ((sensor_positions, n_s), (target_positions, n_g)):
            if not (
                type(value) is np.ndarray
                and value.dtype == np.float64
                and value.shape == (count, 3)
            ):
                if not isinstance(value, np.ndarray) or value.ndim != 2:
                    return None, None
                value = np.asarray(value, dtype=np.float64)
                if value.shape != (count, 3):
                    return None, None
            out.append(value if value.flags.c_contiguous else np.ascontiguousarray(value))
        return out[0], out[1]

    def _pair_inputs(
        self, headings: Any, pointing: Any, visible_fraction: Any
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The headings' sines and cosines (2, n_g), the visible fraction (1 or n_s, n_g) and
        the sensor table of one call."""
        n_g = self.shape[1]
        sin_cos = self._sin_cos
        if headings is not None:
            heading = np.asarray(headings, dtype=float)
            if heading.shape != (n_g,):
                heading = np.broadcast_to(heading, (n_g,))
            _arrays.require_finite("heading", heading, np, "rad")
            sin_cos = np.stack([np.sin(heading), np.cos(heading)])
        visible = self._visible_row
        if visible_fraction is not None:
            given = np.asarray(check_visible_fraction(visible_fraction, self.shape, np), float)
            visible = np.ascontiguousarray(np.broadcast_to(given, (given.shape[0], n_g)))
        sensors = self._sensor_table if pointing is None else self._sensors_for(pointing)
        return sin_cos, visible, sensors

    def _raise_infinite(self, status: int, s_pos: np.ndarray, t_pos: np.ndarray) -> None:
        name, value = (
            ("sensor_positions", s_pos)
            if status == pairs.INFINITE_SENSOR
            else ("target_positions", t_pos)
        )
        _arrays.require_finite(name, value, np, "m")
        raise AssertionError(f"kernel status {status}")  # pragma: no cover - never reached

    def _pair_scr(self, scr: Any) -> np.ndarray | None:
        if scr is None:
            return self._scr
        return np.ascontiguousarray(np.broadcast_to(np.asarray(scr, dtype=float), self.shape))

    def _pair_factors(
        self,
        s_pos: np.ndarray,
        t_pos: np.ndarray,
        headings: Any,
        pointing: Any,
        scr: Any,
        visible_fraction: Any,
    ) -> Factors:
        """:meth:`factors` of one time:
        :func:`~targetacq.core.engines.numba_pairs._pair_factors`."""
        sin_cos, visible, sensors = self._pair_inputs(headings, pointing, visible_fraction)
        out = np.empty((6, *self.shape))
        in_view = np.empty(self.shape, dtype=bool)
        status = pairs._pair_factors(
            s_pos,
            t_pos,
            sin_cos,
            self._dimensions,
            visible,
            sensors,
            self.segment_length,
            self.segment_extinction,
            self.clouds,
            self.contrast,
            self._has_noise,
            out,
            in_view,
        )
        if status:
            self._raise_infinite(status, s_pos, t_pos)
        if scr is None:
            scr = self._scr
        return Factors(
            range=out[0],
            critical_dimension=out[1],
            cycles=out[2],
            in_view=in_view,
            optical_depth=out[3],
            transmittance=out[4],
            snr=out[5],
            scr=scr,
        )

    def _pair_probabilities(self, found: Factors, moving: np.ndarray) -> Probabilities:
        """:meth:`probabilities` of one time: the pair kernel on the pairs in view."""
        shape = self.shape

        def full(value: Any, dtype: Any = np.float64) -> np.ndarray:
            if (
                type(value) is np.ndarray
                and value.dtype == dtype
                and value.shape == shape
                and value.flags.c_contiguous
            ):
                return value
            given = np.asarray(value, dtype=dtype)
            return np.ascontiguousarray(np.broadcast_to(given, shape))

        has_scr = found.scr is not None
        p = np.empty((3, *shape))
        fused = np.empty((3, shape[1]))
        pairs._pair_probabilities(
            full(found.cycles),
            full(found.snr) if self._with_snr else self._zeros,
            full(found.scr) if has_scr else self._zeros,
            full(found.in_view, np.bool_),
            full(found.range),
            self.n50,
            self.log_n50,
            self.hot_spot,
            moving,
            self.settings,
            has_scr,
            self.noise_anchors,
            self.tables,
            self.table_reference,
            self.sw,
            self.sw_constants,
            self.thresholds,
            p,
            fused,
        )
        together = self._fused(p, fused)
        return Probabilities(p[0], p[1], p[2], together[0], together[1], together[2])

    def _fused(self, p: np.ndarray, fused: np.ndarray) -> np.ndarray:
        """The kernel's fusion, or for colour cameras each camera's best band first
        (:func:`targetacq.acquisition.fusion.fuse_groups`)."""
        groups = self.scene.sensors.groups
        if not groups:
            return fused
        return np.stack([np.asarray(fuse_groups(p[k], groups), dtype=float) for k in range(3)])

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
        """One time's field of view, probabilities and fusion in one kernel call
        (:func:`~targetacq.core.engines.numba_pairs._pair_step`); see
        :meth:`targetacq.core.engines.BoundEngine.step`."""
        s_pos, t_pos = self._pair_positions(sensor_positions, target_positions)
        if s_pos is None:
            raise ValueError(
                f"step takes sensor_positions of shape ({self.shape[0]}, 3) and "
                f"target_positions of shape ({self.shape[1]}, 3) [m] (one time); got "
                f"{np.shape(sensor_positions)} and {np.shape(target_positions)}"
            )
        sin_cos, visible, sensors = self._pair_inputs(headings, pointing, visible_fraction)
        flags = self.moving
        if moving is not None:
            flags = np.ascontiguousarray(check_moving(moving, self.shape[1]), dtype=bool)
        scr_given = self._pair_scr(scr)
        in_view = np.empty(self.shape, dtype=bool)
        p = np.empty((3, *self.shape))
        fused = np.empty((3, self.shape[1]))
        status = pairs._pair_step(
            s_pos,
            t_pos,
            sin_cos,
            self._dimensions,
            visible,
            sensors,
            self.segment_length,
            self.segment_extinction,
            self.clouds,
            self.contrast,
            self._has_noise,
            self._zeros if scr_given is None else scr_given,
            scr_given is not None,
            self.n50,
            self.log_n50,
            self.hot_spot,
            flags,
            self.settings,
            self.noise_anchors,
            self.tables,
            self.table_reference,
            self.sw,
            self.sw_constants,
            self.thresholds,
            np.empty((6, *self.shape)),
            in_view,
            p,
            fused,
        )
        if status:
            self._raise_infinite(status, s_pos, t_pos)
        return in_view, p, self._fused(p, fused)

    # -- evaluation --------------------------------------------------------------------------

    def factors(
        self,
        sensor_positions: Any,
        target_positions: Any,
        headings: Any = None,
        pointing: Any = None,
        scr: Any = None,
        visible_fraction: Any = None,
    ) -> Factors:
        """As :func:`targetacq.core.factors` of the bound scene.

        Positions of one time, ``(n_s, 3)`` and ``(n_g, 3)``, go through the pair kernel
        (:func:`~targetacq.core.engines.numba_pairs._pair_factors`, the targets as its inner loop);
        batches through :func:`~targetacq.core.engines.numba_kernels._factors_kernel`.
        """
        one_s, one_t = self._pair_positions(sensor_positions, target_positions)
        if one_s is not None and (headings is None or np.ndim(headings) <= 1):
            return self._pair_factors(one_s, one_t, headings, pointing, scr, visible_fraction)
        xp, (s_pos, t_pos) = _arrays.arrays(
            sensor_positions,
            target_positions,
            names=("sensor_positions", "target_positions"),
            broadcast=False,
        )
        if xp is not np and not (isinstance(s_pos, np.ndarray) and isinstance(t_pos, np.ndarray)):
            raise ValueError(
                "the numba engine takes NumPy arrays; for JAX arrays use engine='jax' or "
                "engine='numpy'"
            )
        # Computed in float64 whatever the input's precision (NumPy keeps float32 as float32).
        s_pos, t_pos = np.asarray(s_pos, dtype=float), np.asarray(t_pos, dtype=float)
        n_s, n_g = self.contrast.shape
        for name, value, count, what in (
            ("sensor_positions", s_pos, n_s, "sensor"),
            ("target_positions", t_pos, n_g, "target"),
        ):
            if value.ndim < 2 or value.shape[0] != count or value.shape[-1] != 3:
                raise ValueError(
                    f"{name} must have shape ({count}, ..., 3): one row per {what} of the "
                    f"scene, east, north, up [m]; got {value.shape}"
                )
            _arrays.require_finite(name, value, np, "m")
        batch = pair_shape((n_s, n_g), s_pos, t_pos)[2:]
        size = math.prod(batch)
        visible = self._visible(visible_fraction, (n_s, n_g, *batch))
        # Component-major, (3, n, size): the kernel's loops over the batch read unit strides.
        sensors = np.ascontiguousarray(
            np.moveaxis(np.broadcast_to(s_pos, (n_s, *batch, 3)).reshape(n_s, size, 3), -1, 0)
        )
        targets = np.ascontiguousarray(
            np.moveaxis(np.broadcast_to(t_pos, (n_g, *batch, 3)).reshape(n_g, size, 3), -1, 0)
        )
        if headings is None:
            heading = np.broadcast_to(self.heading[:, None], (n_g, size))
        else:
            heading = np.broadcast_to(np.asarray(headings, dtype=float), (n_g, *batch))
            heading = heading.reshape(n_g, size)
        _arrays.require_finite("heading", heading, np, "rad")
        forward, pointed = boresight(s_pos, self.scene.sensors, pointing)
        axes = (
            np.broadcast_to(forward[0], (n_s, *batch)),
            np.broadcast_to(forward[1], (n_s, *batch)),
            np.broadcast_to(forward[2], (n_s, *batch)),
        )
        east = geometry.view_offsets(1.0, 0.0, 0.0, axes)
        north = geometry.view_offsets(0.0, 1.0, 0.0, axes)
        up = geometry.view_offsets(0.0, 0.0, 1.0, axes)
        frame = np.stack(
            [east[0], north[0], up[0], east[1], north[1], east[2], north[2], up[2]]
        ).reshape(8, n_s, size)
        flat = (n_s, n_g, size)
        out = [np.empty(flat) for _ in range(6)]
        in_view = np.empty(flat, dtype=bool)
        cycle, ifov = self.sensor_arrays
        kernels._factors_kernel(
            sensors,
            targets,
            np.sin(heading),
            np.cos(heading),
            self.dimensions,
            visible,
            cycle,
            ifov,
            np.ascontiguousarray(frame),
            self.half_tangents,
            np.ascontiguousarray(np.asarray(pointed, dtype=bool).reshape(n_s)),
            self.extinction,
            self.segment_length,
            self.segment_extinction,
            self.clouds,
            self.noise_equivalent,
            self.contrast,
            bool(self.scene.sensors.has_noise),
            self.path_contrast,
            self.contrast_law,
            np.empty((2, size)),
            out[0],
            out[1],
            out[2],
            in_view,
            out[3],
            out[4],
            out[5],
        )
        shape = (n_s, n_g, *batch)
        rng, critical, cycles, depth, tau, snr = (a.reshape(shape) for a in out)
        if scr is None and self.scene.signature.scr is not None:
            scr = np.asarray(self.scene.signature.scr, dtype=float).reshape(
                (n_s, n_g) + (1,) * len(batch)
            )
        return Factors(
            range=rng,
            critical_dimension=critical,
            cycles=cycles,
            in_view=in_view.reshape(shape),
            optical_depth=depth,
            transmittance=tau,
            snr=snr,
            scr=scr,
        )

    def _visible(self, given: Any, shape: tuple[int, ...]) -> np.ndarray:
        """The visible fraction as the factors kernel takes it: ``(1 or n_s, n_g, 1 or B)``,
        contiguous (the targets' own, else the one given, checked)."""
        if given is None:
            return self.visible_fraction.reshape(1, -1, 1)
        value = np.asarray(check_visible_fraction(given, shape, np), dtype=float)
        lead = (value.shape[0], shape[1])
        if all(n == 1 for n in value.shape[2:]):
            return np.ascontiguousarray(
                np.broadcast_to(value.reshape(*value.shape[:2], 1), (*lead, 1))
            )
        full = np.broadcast_to(value, (*lead, *shape[2:]))
        return np.ascontiguousarray(full).reshape(*lead, math.prod(shape[2:]))

    def _groups(self, moving: np.ndarray | None = None) -> list[np.ndarray]:
        """The targets by their probability model (N50s, hot spot, moving), each group's
        members in order: the rows of the probabilities kernel where the batch is short."""
        if moving is not None and not np.array_equal(moving, self.moving):
            return self._group(moving)
        if self._target_groups is None:
            self._target_groups = self._group(self.moving)
        return self._target_groups

    def _group(self, moving: np.ndarray) -> list[np.ndarray]:
        if self.n50.shape[0] == 0:
            return []
        key = np.column_stack([self.n50, self.hot_spot, moving])
        _, inverse = np.unique(key, axis=0, return_inverse=True)
        inverse = inverse.reshape(-1)
        return [np.flatnonzero(inverse == k) for k in range(inverse.max() + 1)]

    def probabilities(self, found: Factors, moving: Any = None) -> Probabilities:
        """As :func:`targetacq.core.probabilities` of the bound scene.

        Factors of one time, ``(n_s, n_g)``, go through
        :func:`~targetacq.core.engines.numba_pairs._pair_probabilities`. Otherwise the kernel runs
        per sensor and target over the batch. Where the batch is short (one step of the step API),
        the targets that share a probability model go through as one row, their pairs as its batch:
        the kernel's loops then run over the targets.
        """
        rng = np.asarray(found.range, dtype=float)
        shape = rng.shape
        n_s, n_g = shape[:2]
        size = math.prod(shape[2:])
        flat = (n_s, n_g, size)
        if rng.size == 0:
            empty = [np.zeros(shape) for _ in range(3)]
            return Probabilities(*empty, *(np.zeros((n_g, *shape[2:])) for _ in range(3)))
        has_scr = found.scr is not None
        with_snr = self.settings[0] != kernels.NOISE_NONE_GIVEN
        flags = self.moving
        if moving is not None:
            flags = np.ascontiguousarray(check_moving(moving, n_g), dtype=bool)
        if shape == self.shape:  # one time: the pair kernel
            return self._pair_probabilities(found, flags)

        def full(value: Any, dtype: Any = float) -> np.ndarray:
            # Contiguous at the full shape, even where a field is per pair or a scalar: a loop
            # over a broadcast (zero-stride) array does not vectorise.
            given = np.asarray(value, dtype=dtype)
            return np.ascontiguousarray(np.broadcast_to(given, shape)).reshape(flat)

        inputs = [
            full(found.cycles),
            full(found.snr) if with_snr else np.zeros(flat),
            full(found.scr) if has_scr else np.zeros(flat),
            full(found.in_view, bool),
            np.ascontiguousarray(rng.reshape(flat)),
        ]
        out = [np.empty(flat) for _ in range(3)]
        fused = np.empty((3, n_g, size))
        if size >= _SHORT_BATCH or n_g == 1:
            self._run(inputs, slice(None), out, fused, has_scr, flags)
        else:
            for members in self._groups(flags):
                whole = members.size == n_g  # one model for all: no copies
                chosen = slice(None) if whole else members
                row = (n_s, 1, members.size * size)
                part_in = [np.ascontiguousarray(a[:, chosen]).reshape(row) for a in inputs]
                part_out = [np.empty(row) for _ in range(3)]
                part_fused = np.empty((3, 1, members.size * size))
                self._run(part_in, members[:1], part_out, part_fused, has_scr, flags)
                for whole_out, part in zip(out, part_out, strict=True):
                    whole_out[:, chosen] = part.reshape(n_s, members.size, size)
                fused[:, chosen] = part_fused.reshape(3, members.size, size)
        tasks = [a.reshape(shape) for a in out]
        if self.scene.sensors.groups:  # colour cameras: the best band of each (fuse_groups)
            together = [fuse_groups(p, self.scene.sensors.groups) for p in tasks]
        else:
            together = [f.reshape((n_g, *shape[2:])) for f in fused]
        return Probabilities(*tasks, *together)

    def _run(
        self,
        inputs: list[np.ndarray],
        targets: Any,
        out: list[np.ndarray],
        fused: np.ndarray,
        has_scr: bool,
        moving: np.ndarray,
    ) -> None:
        """The probabilities kernel on (n_s, rows, batch) inputs, the rows' targets given."""
        settings = self.settings.copy()
        settings[6] = int(has_scr)
        size = inputs[0].shape[2]
        kernels._probabilities_kernel(
            *inputs,
            self.n50[targets],
            self.log_n50[targets],
            self.hot_spot[targets],
            moving[targets],
            settings,
            self.noise_anchors,
            self.tables,
            self.table_reference,
            self.sw,
            self.sw_constants,
            self.thresholds,
            np.empty(size),
            np.empty((6, size)),
            out[0],
            out[1],
            out[2],
            fused,
        )
