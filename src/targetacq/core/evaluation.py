"""The pure core: positions, pointing and headings → factors → probabilities → fused.

Every function here is a pure function of arrays and the records of
:mod:`targetacq.core.records`: no scenario objects, no files, no writes into its inputs, no
Python loops over sensors or targets. It is written against the array API, so NumPy arrays stay
NumPy and JAX arrays stay JAX (under ``jax.jit``, ``vmap`` and ``grad``; see
:mod:`targetacq.base.arrays` for the validation policy). The physics is in the topic modules; this
module wires them together:

1. geometry: line of sight, slant range, the outline seen and the critical dimension
   (:func:`targetacq.physics.geometry.box_outline`,
   :func:`targetacq.physics.geometry.critical_dimension_seen`), the field of view
   (:func:`targetacq.physics.geometry.view_offsets`);
2. resolution: cycles on target ``N = d / (R · cycle)`` (§3.5; the cycle from the sensor type),
   or MRTD-limited ``N = f*(τ ΔT) · d / R`` for a thermal sensor with an MRTD curve
   (:mod:`targetacq.core.mrtd_rows`), or the TTP metric's ``V`` under the ``ttp`` resolution
   model (:mod:`targetacq.core.ttp_rows`);
3. path: optical depth with segments, local clouds
   (:func:`targetacq.physics.atmosphere.segmented_optical_depth`,
   :func:`targetacq.physics.atmosphere.sphere_chord_length`) and foliage in front of a target (§6.8,
   ``−ln τ_f``), transmittance and the SNR of Eq. (7.7);
4. probabilities: the transforms with the noise model and, for detection in clutter, the
   Schmieder–Weathersby transform (:func:`task_probabilities`), ordered
   ``P_id <= P_rec <= P_det``, zero outside the field of view and where the contrast is below
   the sensor's digitiser step (§6.8);
5. sensor-level fusion (8.4).

NumPy. With NumPy arrays :func:`factors` computes the pairs block by block (temporaries in the
CPU cache) and :func:`probabilities` runs the transforms on the pairs in view only, with the noise
from the optical depth as an amplitude ratio (``1/SNR_lin = e^d − 1``) rather than through the
decibels; what a scene fixes (its model choices resolved, its targets grouped by criterion, its
sensors' frames) is derived once per record (:func:`targetacq.core.records.derived`). The numbers
are those of the whole-array computation to about 1e-14 relative.

Shapes: ``sensor_positions`` ``(n_s, *batch, 3)``, ``target_positions`` ``(n_g, *batch, 3)``; every
result is ``(n_s, n_g, *batch)``, the fused ones ``(n_g, *batch)``. ``batch`` is the time axis of
:class:`targetacq.run.model_chain.ModelChain` and empty for one step of
:class:`targetacq.Simulation`.

JAX. With a scene of JAX arrays (:func:`targetacq.core.records.as_jax`) every function here
except :func:`footprint_scr` runs under ``jax.jit``, ``vmap`` and ``grad``; :class:`Factors` and
:class:`Probabilities` are pytrees. Enable float64 (``jax.config.update("jax_enable_x64",
True)``) for numbers equal to NumPy's to about 1e-12; in float32 they agree to about 1e-5.
Terrain maps are NumPy only (their SCR is looked up per position on the host).

Differentiability. The model is piecewise smooth. Where it is smooth, ``jax.grad`` gives its
exact derivative; at the places below the derivative is one-sided, zero or, where noted, NaN:

- the field of view: ``in_view`` is a step, so a probability does not change with the pointing
  (azimuth, depression, look_at) except across the field-of-view edge, and its gradient with
  respect to the pointing is zero everywhere else;
- the table transforms: C2NVEO and Schmieder–Weathersby curves are piecewise linear in
  ``log N``, with kinks at the printed points; the clutter region switches at SCR = 1 and 10
  and the stretch starts at SCR = 0.33 (in SCR, not in the positions, unless noise moves the
  effective SCR across them); the noise factor's slope jumps at R = 1 and 10;
- the ``min`` of the critical dimension (horizontal side against the visible vertical one) and
  the caps ``P_rec <= P_det``, ``P_id <= P_rec`` of the ordering;
- the outline's ``|sin a|`` and ``|cos a|`` at aspects that are multiples of π/2 (one-sided
  derivatives), and a target straight above or below a sensor (ρ = 0), where the outline is not
  continuous and the gradient is NaN;
- the path: the ends of atmospheric segments (``clip`` of the range) and lines of sight that
  graze a cloud;
- the TTPF where ``|E ln x| > 700`` (P is 0 or 1 to double precision; the gradient is 0).

Gradients are NaN-safe elsewhere: a masked branch that would divide by zero, take a square root
at 0 or ``10^(SNR/20)`` at SNR = +inf gets a harmless argument (the double-``where``), since
JAX differentiates both branches of a ``where``.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, NamedTuple

import numpy as np

from targetacq.acquisition import transforms as _transforms
from targetacq.acquisition.fusion import fuse, fuse_groups, fused_along
from targetacq.acquisition.path_noise import (
    NoiseModel,
    get_noise_model,
    get_snr_law,
    noise_ratio,
    seen_of_ratio,
)
from targetacq.acquisition.probabilities import (
    Clutter,
    MotionRule,
    Semantics,
    get_motion_rule,
    get_semantics,
    ordered_probabilities,
)
from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.core import active, mrtd_rows, ttp_rows
from targetacq.core.pair_factors import SensorNoise, imager_factors
from targetacq.core.records import (
    AspectArrays,
    ModelChoices,
    SceneArrays,
    SensorArrays,
    TargetArrays,
    derived,
    pytree_record,
)
from targetacq.physics import aspect, atmosphere, detector_noise, geometry, named_atmospheres
from targetacq.physics.clutter import signal_to_clutter_ratio

__all__ = [
    "Factors",
    "GradedCues",
    "Probabilities",
    "boresight",
    "check_moving",
    "check_visible_fraction",
    "crossing_speeds",
    "evaluate",
    "evaluate_step",
    "factors",
    "footprint_scr",
    "graded_cues",
    "pair_shape",
    "probabilities",
    "task_probabilities",
]

TASKS = ("detection", "recognition", "identification")
_POSITIONS = ("sensor_positions", "target_positions")


@pytree_record
@dataclass(frozen=True)
class Factors:
    """The descriptive factors of every sensor-target pair, ``(n_s, n_g, *batch)`` each.

    Attributes
    ----------
    range : array
        Slant range [m].
    critical_dimension : array
        [m].
    cycles : array
        N [cycles].
    in_view : array of bool
    optical_depth : array
        [Np]: the atmosphere's and, where a target has foliage, ``−ln τ_f`` (§6.8).
    transmittance : array
        τ [1].
    snr : array
        Total SNR [dB]: the path's of Eq. (7.7) and, where a sensor has noise of its own, the
        sensor's (:func:`targetacq.physics.detector_noise.sensor_snr`), added in variance.
    scr : array or None
        Signal-to-clutter ratio, where a clutter measure is given.
    crossing_speed : array or None
        The target's speed over the ground across the line of sight [m/s]
        (:func:`crossing_speeds`), for the targets with a graded motion cue
        (:attr:`targetacq.core.records.TargetArrays.graded_motion`); None: they stand still
        (:func:`factors` knows positions only; the callers that know velocities set it).
    """

    range: Any
    critical_dimension: Any
    cycles: Any
    in_view: Any
    optical_depth: Any
    transmittance: Any
    snr: Any
    scr: Any
    crossing_speed: Any = None

    def __getstate__(self) -> dict[str, Any]:
        # The fields only: what factors() keeps beside them for probabilities() (the noise
        # ratio, room for the probabilities) is not part of a copy or a pickle.
        return {item.name: getattr(self, item.name) for item in dataclasses.fields(self)}

    def __setstate__(self, state: dict[str, Any]) -> None:
        for name, value in state.items():
            object.__setattr__(self, name, value)


@pytree_record
@dataclass(frozen=True)
class Probabilities:
    """Per-pair probabilities ``(n_s, n_g, *batch)``; sensor-level fusion ``(n_g, *batch)``."""

    detection: Any
    recognition: Any
    identification: Any
    fused_detection: Any
    fused_recognition: Any
    fused_identification: Any


def _per_sensor(value: Any, batch: int, xp: Any) -> Any:
    return xp.reshape(value, (value.shape[0], 1) + (1,) * batch)


def _per_target(value: Any, batch: int, xp: Any) -> Any:
    return xp.reshape(value, (1, value.shape[0]) + (1,) * batch)


def boresight(
    sensor_positions: Array, sensors: SensorArrays, pointing: Array = None
) -> tuple[tuple[Any, Any, Any], Any]:
    """Boresight of each sensor and whether it is pointed.

    A sensor points at its ``look_at`` point, or at its azimuth and depression
    (:func:`targetacq.physics.geometry.pointing_direction`); ``pointing`` (n_s, 2), where given and
    finite, replaces both. A sensor pointed no way sees every target.

    Parameters
    ----------
    sensor_positions : array ``(n_s, *batch, 3)``
        [m].
    sensors : SensorArrays
    pointing : array (n_s, 2), optional
        Azimuth and depression [rad]; a NaN row keeps the sensor's own pointing.

    Returns
    -------
    (east, north, up), pointed
        Boresight components ``(n_s, *batch)`` and a bool array ``(n_s, 1, *[1]*batch)`` for the
        field-of-view test.
    """
    xp, (pos, look_at, angles) = _arrays.arrays(sensor_positions, sensors.look_at, sensors.pointing)
    batch = pos.ndim - 2
    pointed = xp.asarray(np.asarray(sensors.pointed, dtype=bool))
    if pointing is not None:
        _, (given,) = _arrays.arrays(pointing)
        chosen = xp.isfinite(given[:, 0]) & xp.isfinite(given[:, 1])
        angles = xp.where(chosen[:, None], given, angles)
        look_at = xp.where(chosen[:, None], xp.nan, look_at)
        pointed = pointed | chosen
    by_point = xp.isfinite(look_at[:, 0])
    by_angles = xp.isfinite(angles[:, 0])
    direction = geometry.pointing_direction(
        xp.where(by_angles, angles[:, 0], 0.0), xp.where(by_angles, angles[:, 1], 0.0)
    )

    def alone(value: Any) -> Any:  # (n_s,) → (n_s, *[1]*batch), against the positions
        return xp.reshape(value, (value.shape[0],) + (1,) * batch)

    forward = []
    for k in range(3):
        toward = alone(xp.where(by_point, look_at[:, k], 0.0)) - pos[..., k]
        fixed = alone(_arrays.as_float(direction[k], xp))
        forward.append(xp.where(alone(by_point), toward, fixed))
    has_view = xp.isfinite(_arrays.as_float(sensors.half_tangents, xp)[:, 0])
    return (forward[0], forward[1], forward[2]), _per_sensor(pointed & has_view, batch, xp)


# --------------------------------------------------------------------------------------------
# Per-call inputs that replace the scene's own: a visible fraction, moving flags
# --------------------------------------------------------------------------------------------


def check_visible_fraction(visible_fraction: Array, shape: tuple[int, ...], xp: Any = None) -> Any:
    """A visible fraction given per call, checked and shaped against the pairs ``shape``.

    Parameters
    ----------
    visible_fraction : array_like
        Fraction of each target's height in view, in (0, 1] [1]; NaN gives NaN probabilities
        for the pairs it reaches. A scalar (every pair), shape ``(n_g,)`` (one per target), or
        an array whose axes are the pairs' from the left, each of its size or 1: ``(n_s,
        n_g)``, ``(1, n_g, n_t)``, ``(n_s, n_g, *batch)``, ... (missing trailing batch axes
        are added).
    shape : tuple of int
        The pairs, ``(n_s, n_g, *batch)``.
    xp : module, optional
        The array namespace of the result (default: the input's).

    Returns
    -------
    array
        ``len(shape)`` axes, each of ``shape``'s size or 1.

    Raises
    ------
    ValueError
        A shape that does not fit the pairs, or a value outside (0, 1].
    """
    space, (value,) = _arrays.arrays(visible_fraction, names=("visible_fraction",))
    xp = space if xp is None else xp
    if isinstance(value, np.ndarray) and xp is not np and xp is not _arrays.NUMPY:
        value = xp.asarray(value)
    full = len(shape)
    per = "(n_s, n_g, *batch) = " + str(tuple(shape))
    if value.ndim == 0:
        value = xp.reshape(value, (1,) * full)
    elif value.ndim == 1 and value.shape[0] == shape[1]:
        value = xp.reshape(value, (1, shape[1]) + (1,) * (full - 2))
    elif 2 <= value.ndim <= full and all(
        v in (1, n) for v, n in zip(value.shape, shape, strict=False)
    ):
        value = xp.reshape(value, tuple(value.shape) + (1,) * (full - value.ndim))
    else:
        raise ValueError(
            f"visible_fraction must have shape ({shape[1]},) (one per target), be a scalar, or "
            f"have axes of the pairs {per} from the left, each of its size or 1; got "
            f"{tuple(value.shape)}"
        )
    if not _arrays.is_traced(value):
        bad = (value <= 0) | (value > 1)
        if _arrays.any_known(bad, xp):
            first = float(xp.reshape(value[bad], (-1,))[0])
            raise ValueError(f"visible_fraction must be in (0, 1] (NaN for unknown); got {first:g}")
    return value


def check_moving(moving: Any, count: int) -> Any:
    """Moving flags given per call: a bool array (n_g,), as NumPy where it is not JAX's.

    Raises
    ------
    ValueError
        Not booleans, or not one per target.
    """
    value = moving if hasattr(moving, "dtype") and not isinstance(moving, np.ndarray) else None
    if value is None:
        value = np.asarray(moving)
    if str(value.dtype) != "bool":
        raise ValueError(
            f"moving must be booleans (True/False), one per target, shape ({count},); got "
            f"{value.dtype} values"
        )
    if tuple(value.shape) != (count,):
        raise ValueError(
            f"moving must have shape ({count},): one flag per target; got {tuple(value.shape)}"
        )
    return value


# --------------------------------------------------------------------------------------------
# NumPy: what a scene fixes, once; the factors block by block; the probabilities in view only
# --------------------------------------------------------------------------------------------

# Triples per block of the NumPy factors: the block's temporaries (32 KiB each) stay in the CPU
# cache and are reused from the heap, where larger ones are fresh pages (page faults) on every
# block and call.
_BLOCK = 1 << 12
# Elements per call of the transforms on the pairs in view, for the same reason.
_PROBABILITY_BLOCK = 1 << 12
# The private attribute of a Factors made by factors() with NumPy: where its probabilities take
# the noise-to-signal amplitude ratio 1/SNR_lin from (see _noise_ratio).
_RATIO = "_noise_ratio"
_FROM_DEPTH = "optical depth"  # ρ = e^d − 1, from the path alone (no noise of the sensors)
# The private attribute of a Factors made by factors() with NumPy where its outputs are large:
# room for the three task probabilities in the same allocation (see _outputs), taken once.
_SPARE = "_probability_room"
# Triples from which the NumPy factors carve their outputs from one allocation (128 KiB arrays:
# the allocator maps memory of that size afresh on every call).
_SHARED_OUTPUTS = 1 << 14


@dataclass(frozen=True)
class _Choices:
    """A scene's model choices, resolved once (registry look-ups, the options as a mapping)."""

    transform: _transforms.Transform
    options: Mapping[str, Any]
    noise: NoiseModel
    motion: MotionRule
    semantics: Semantics


def _resolve(choices: ModelChoices) -> _Choices:
    return _Choices(
        _transforms.get_transform(choices.transform),
        MappingProxyType(dict(choices.options)),
        get_noise_model(choices.noise_model),
        get_motion_rule(choices.motion),
        get_semantics(choices.semantics),
    )


_resolved = functools.cache(_resolve)


def _choices(choices: ModelChoices) -> _Choices:
    try:
        return _resolved(choices)
    except TypeError:  # an option that cannot be hashed: resolved on every call
        return _resolve(choices)


def _scene_choices(scene: SceneArrays) -> _Choices:
    return _choices(scene.choices)


@dataclass(frozen=True)
class _TargetGroups:
    """The targets grouped by their N50s, and their flags, from a TargetArrays (NumPy)."""

    rows: tuple[tuple[float, float, float], ...]  # each group's N50s
    group: np.ndarray | None  # (n_g,) each target's group; None: one group
    hot: np.ndarray  # (n_g,) bool
    moving: np.ndarray
    # Per group, the flag of all its targets, or None where they differ: as task_probabilities
    # passes them (one bool, else one per target), whichever of the group's pairs are evaluated.
    hot_same: tuple[bool | None, ...]
    moving_same: tuple[bool | None, ...]

    def flag(self, name: str, k: int, targets: Callable[[], np.ndarray]) -> Any:
        """Group ``k``'s flag: one bool, else the flags of ``targets()`` (their indices)."""
        same = (self.hot_same if name == "hot" else self.moving_same)[k]
        if same is not None:
            return same
        return (self.hot if name == "hot" else self.moving)[targets()]

    def with_moving(self, moving: np.ndarray | None) -> _TargetGroups:
        """The same groups with other moving flags (n_g,) bool; None: these."""
        if moving is None or np.array_equal(moving, self.moving):
            return self
        if self.group is None:
            same: tuple[bool | None, ...] = (_same(moving),)
        else:
            same = tuple(_same(moving[self.group == k]) for k in range(len(self.rows)))
        return dataclasses.replace(self, moving=moving, moving_same=same)


def _same(values: np.ndarray) -> bool | None:
    if values.size and bool(np.all(values == values[0])):
        return bool(values[0])
    return None


def _group_targets(targets: TargetArrays) -> _TargetGroups:
    table = np.asarray(targets.n50, dtype=float).reshape(-1, 3)
    hot = np.asarray(targets.hot_spot, dtype=bool).reshape(-1)
    moving = np.asarray(targets.moving, dtype=bool).reshape(-1)
    if table.shape[0] == 0 or bool(np.all(table == table[0])):
        row = tuple(float(v) for v in table[0]) if table.shape[0] else (1.0, 1.0, 1.0)
        return _TargetGroups((row,), None, hot, moving, (_same(hot),), (_same(moving),))  # type: ignore[arg-type]
    rows, group = np.unique(table, axis=0, return_inverse=True)
    group = group.reshape(-1)
    members = [group == k for k in range(rows.shape[0])]
    return _TargetGroups(
        tuple(tuple(float(v) for v in row) for row in rows),  # type: ignore[misc]
        group,
        hot,
        moving,
        tuple(_same(hot[m]) for m in members),
        tuple(_same(moving[m]) for m in members),
    )


def _groups(targets: TargetArrays) -> _TargetGroups:
    return derived(targets, "groups", _group_targets)


def _is_numpy_record(record: Any) -> bool:
    """Whether every array of a record (and of the records in it) is a float64 NumPy array."""
    for item in dataclasses.fields(record):
        if item.metadata.get("static"):
            continue
        value = getattr(record, item.name)
        if value is None:
            continue
        if dataclasses.is_dataclass(value):
            if not _is_numpy_record(value):
                return False
        elif not (isinstance(value, np.ndarray) and value.dtype == np.float64):
            return False
    return True


def _numpy_scene(scene: SceneArrays) -> bool:
    return derived(scene, "numpy", _is_numpy_record)


@dataclass(frozen=True)
class _Pointing:
    """What a sensor's own pointing fixes (NumPy): the boresight where it is a direction."""

    by_point: np.ndarray  # (n_s,) bool: pointed at a look_at point
    look_at: np.ndarray  # (n_s, 3)
    direction: tuple[np.ndarray, np.ndarray, np.ndarray]  # (n_s,) each, where by angles
    viewing: np.ndarray  # (n_s,) bool: pointed and with a field of view
    half_tangents: tuple[np.ndarray, np.ndarray]  # (n_s, 1, 1) each
    frame: tuple[np.ndarray, ...] | None  # (n_s, 1) each where no sensor points at a place


def _fixed_pointing(sensors: SensorArrays, pointing: Any = None) -> _Pointing:
    """:func:`boresight`'s per-sensor part, with NumPy (the same arithmetic)."""
    look_at = np.asarray(sensors.look_at, dtype=float).reshape(-1, 3)
    angles = np.asarray(sensors.pointing, dtype=float).reshape(-1, 2)
    pointed = np.asarray(sensors.pointed, dtype=bool).reshape(-1)
    if pointing is not None:
        given = np.asarray(pointing, dtype=float)
        chosen = np.isfinite(given[:, 0]) & np.isfinite(given[:, 1])
        angles = np.where(chosen[:, None], given, angles)
        look_at = np.where(chosen[:, None], np.nan, look_at)
        pointed = pointed | chosen
    by_point = np.isfinite(look_at[:, 0])
    by_angles = np.isfinite(angles[:, 0])
    east, north, up = geometry.pointing_direction(
        np.where(by_angles, angles[:, 0], 0.0), np.where(by_angles, angles[:, 1], 0.0)
    )
    half = np.asarray(sensors.half_tangents, dtype=float).reshape(-1, 2)
    direction = (np.asarray(east), np.asarray(north), np.asarray(up))
    frame = None
    if not by_point.any():  # the boresight is a direction: the frame does not move
        east_, north_, up_ = (d[:, None] for d in direction)
        frame = geometry.sensor_frame(east_, north_, up_, np)
    return _Pointing(
        by_point,
        look_at,
        direction,
        pointed & np.isfinite(half[:, 0]),
        (half[:, 0, None, None], half[:, 1, None, None]),
        frame,
    )


def _sensor_frames(
    s3: np.ndarray, sensors: SensorArrays, pointing: Any
) -> tuple[tuple[np.ndarray, ...], _Pointing]:
    """Each sensor's frame (:func:`targetacq.physics.geometry.sensor_frame`), ``(n_s, B)`` or
    ``(n_s, 1)`` where no sensor points at a place (the frame does not move then), and its
    pointing."""
    fixed = (
        derived(sensors, "pointing", _fixed_pointing)
        if pointing is None
        else _fixed_pointing(sensors, pointing)
    )
    if fixed.frame is not None:
        return fixed.frame, fixed
    forward = []
    for k in range(3):  # toward the point, from where the sensor is, else the direction
        toward = np.where(fixed.by_point, fixed.look_at[:, k], 0.0)[:, None] - s3[:, :, k]
        forward.append(np.where(fixed.by_point[:, None], toward, fixed.direction[k][:, None]))
    return geometry.sensor_frame(forward[0], forward[1], forward[2], np), fixed


def _blocks(n_s: int, n_g: int, n_b: int) -> Iterator[tuple[slice, slice, slice]]:
    """Blocks of about :data:`_BLOCK` triples of the ``(n_s, n_g, n_b)`` grid, each contiguous
    in a C-ordered array: whole sensor rows, else a sensor's targets, else a pair's batch."""
    if n_s * n_g * n_b == 0:
        return
    whole = slice(None)
    if n_g * n_b <= _BLOCK:
        step = max(1, _BLOCK // (n_g * n_b))
        for s in range(0, n_s, step):
            yield slice(s, min(s + step, n_s)), whole, whole
    elif n_b <= _BLOCK:
        step = max(1, _BLOCK // n_b)
        for s in range(n_s):
            for g in range(0, n_g, step):
                yield slice(s, s + 1), slice(g, min(g + step, n_g)), whole
    else:
        for s in range(n_s):
            for g in range(n_g):
                for b in range(0, n_b, _BLOCK):
                    yield slice(s, s + 1), slice(g, g + 1), slice(b, min(b + _BLOCK, n_b))


@dataclass(frozen=True)
class _Parts:
    """A scene's arrays shaped for the blocks of :func:`_factors_numpy` (NumPy), made once."""

    length: np.ndarray  # (n_g, 1) each: against (k_s, k_g, k_b) blocks
    width: np.ndarray
    height: np.ndarray
    visible: np.ndarray
    sin_h: np.ndarray  # (n_g, 1): the targets' own headings
    cos_h: np.ndarray
    cycle: np.ndarray  # (n_s, 1, 1) each
    extinction: np.ndarray
    ifov: np.ndarray
    noise_equivalent: np.ndarray
    segments: tuple[np.ndarray, ...]  # (n_s, 1, 1) each segment's extinction
    lengths: tuple[float, ...]
    contrast: np.ndarray  # (n_s, n_g, 1)
    foliage: np.ndarray | None = None  # (n_g, 1): −ln τ_f of the targets' foliage; None: none
    path_contrast: np.ndarray | None = None  # (n_s, 1, 1): σ_path of the contrast law; None: off


def _scene_parts(scene: SceneArrays) -> _Parts:
    sensors, targets, path = scene.sensors, scene.targets, scene.path
    n_s, n_g = scene.shape
    dims = targets.dimensions.reshape(n_g, 3)
    heading = targets.heading.reshape(n_g, 1)
    lengths = tuple(float(v) for v in path.segment_length)
    segments = sensors.segment_extinction.reshape(n_s, len(lengths))

    def per_sensor(value: np.ndarray) -> np.ndarray:
        return value.reshape(n_s, 1, 1)

    return _Parts(
        dims[:, 0:1],
        dims[:, 1:2],
        dims[:, 2:3],
        targets.visible_fraction.reshape(n_g, 1),
        np.sin(heading),
        np.cos(heading),
        per_sensor(sensors.cycle),
        per_sensor(sensors.extinction),
        per_sensor(sensors.ifov),
        per_sensor(sensors.noise_equivalent),
        tuple(per_sensor(segments[:, j]) for j in range(len(lengths))),
        lengths,
        scene.signature.contrast.reshape(n_s, n_g, 1),
        foliage=None if targets.foliage is None else _foliage_depth(targets.foliage, np)[:, None],
        path_contrast=None if not _contrast_law(scene) else per_sensor(sensors.path_contrast),
    )


def _contrast_law(scene: SceneArrays) -> bool:
    """Whether the scene's SNR is formed by a contrast-aware law
    (:func:`targetacq.physics.detector_noise.contrast_snr`): its choice says so, some sensor has
    a noise of its own, and the sensors' reference contrasts are known."""
    return (
        scene.sensors.has_noise
        and scene.sensors.path_contrast is not None
        and get_snr_law(scene.choices.snr_law).contrast_aware
    )


def _thresholds(scene: SceneArrays, xp: Any) -> Any:
    """``(n_s,)`` k of each sensor row's detection threshold
    (:func:`targetacq.acquisition.path_noise.seen_probability`): the SNR law's where the row has
    a noise of its own, −inf (none) where not; None where no threshold acts in the scene."""
    threshold = get_snr_law(scene.choices.snr_law).threshold
    if threshold is None or not _contrast_law(scene):
        return None
    nec = _arrays.as_float(scene.sensors.noise_equivalent, xp)
    return xp.where(nec > 0, threshold, -xp.inf)


def _foliage_depth(foliage: Any, xp: Any) -> Any:
    """The optical depth ``−ln τ_f`` of foliage of transmittance ``τ_f`` (§6.8): it multiplies
    the path's transmittance ``e^−d``, so it adds to the depth (+inf where τ_f = 0)."""
    with np.errstate(divide="ignore"):
        return -xp.log(_arrays.as_float(foliage, xp))


def _factors_numpy(
    scene: SceneArrays,
    s_pos: np.ndarray,
    t_pos: np.ndarray,
    headings: np.ndarray | None,
    pointing: Any,
    scr: Any,
    visible_fraction: np.ndarray | None = None,
) -> Factors:
    """:func:`factors` with NumPy, block by block (:func:`_blocks`), the same arithmetic.

    Sets the Factors' private noise-to-signal ratio (:data:`_RATIO`) for :func:`probabilities`.
    """
    sensors, path = scene.sensors, scene.path
    n_s, n_g = s_pos.shape[0], t_pos.shape[0]
    batch = s_pos.shape[1:-1]
    n_b = math.prod(batch)
    s3, t3 = s_pos.reshape(n_s, n_b, 3), t_pos.reshape(n_g, n_b, 3)
    # The components apart, each contiguous: the blocks' differences run on contiguous rows.
    s_east, s_north, s_up = s3.transpose(2, 0, 1).copy()
    t_east, t_north, t_up = t3.transpose(2, 0, 1).copy()
    parts: _Parts = derived(scene, "parts", _scene_parts)
    if headings is None:
        sin_h, cos_h = parts.sin_h, parts.cos_h
    else:
        heading = np.broadcast_to(headings, (n_g, *batch)).reshape(n_g, n_b)
        _arrays.require_finite("heading", heading, np, "rad")
        sin_h, cos_h = np.sin(heading), np.cos(heading)
    frame, fixed = _sensor_frames(s3, sensors, pointing)
    moving_frame = frame[0].shape[1] > 1
    tan_h, tan_v = fixed.half_tangents
    noisy = sensors.has_noise
    shape3 = (n_s, n_g, n_b)
    floats, in_view, spare = _outputs(7 if noisy else 6, shape3)
    rng, critical, cycles, depth_out, tau_out, snr_out = floats[:6]
    ratio_out = floats[6] if noisy else None
    per_batch = sin_h.shape[1] > 1
    visible = _visible_blocks(visible_fraction, parts.visible, batch)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for sb, gb, bb in _blocks(n_s, n_g, n_b):
            block = (sb, gb, bb)
            seen_part = visible(sb, gb, bb)
            x = t_east[None, gb, bb] - s_east[sb, None, bb]  # (ks, kg, kb)
            y = t_north[None, gb, bb] - s_north[sb, None, bb]
            z = t_up[None, gb, bb] - s_up[sb, None, bb]
            h_b = bb if per_batch else slice(None)
            chain = _Chain(
                sin_h[gb, h_b],
                cos_h[gb, h_b],
                parts.length[gb],
                parts.width[gb],
                parts.height[gb],
                seen_part,
                parts.cycle[sb],
                parts.extinction[sb],
                tuple(g[sb] for g in parts.segments),
                parts.ifov[sb],
                parts.noise_equivalent[sb],
                parts.contrast[sb, gb],
                None if parts.foliage is None else parts.foliage[gb],
                None if parts.path_contrast is None else parts.path_contrast[sb],
            )

            def ends(
                sb: slice = sb, gb: slice = gb, bb: slice = bb
            ) -> tuple[np.ndarray, np.ndarray]:
                return s3[sb, None, bb], t3[None, gb, bb]

            r, seen, _, depth, tau, snr, pair_ratio = _chain_numpy(
                x, y, z, chain, parts.lengths, path, ends, noisy, cycles[block]
            )
            rng[block] = r
            critical[block] = seen
            # The field of view, for the pointed sensors with one; NaN lines of sight are out.
            known = r == r
            viewing = fixed.viewing[sb]
            if viewing.any():
                f_b = bb if moving_frame else slice(None)
                inside = geometry.within_numpy(
                    x, y, z, tuple(c[sb, None, f_b] for c in frame), tan_h[sb], tan_v[sb]
                )
                if not viewing.all():
                    inside |= ~viewing[:, None, None]
                np.logical_and(inside, known, out=in_view[block])
            else:
                in_view[block] = known
            depth_out[block] = depth
            tau_out[block] = tau
            if noisy:
                ratio_out[block] = pair_ratio  # type: ignore[index]
            snr_out[block] = snr
    full = (n_s, n_g, *batch)
    if scr is None and scene.signature.scr is not None:
        scr = scene.signature.scr.reshape((n_s, n_g) + (1,) * len(batch))
    found = Factors(
        range=rng.reshape(full),
        critical_dimension=critical.reshape(full),
        cycles=cycles.reshape(full),
        in_view=in_view.reshape(full),
        optical_depth=depth_out.reshape(full),
        transmittance=tau_out.reshape(full),
        snr=snr_out.reshape(full),
        scr=scr,
    )
    ratio = _FROM_DEPTH if ratio_out is None else ratio_out.reshape(full)
    object.__setattr__(found, _RATIO, ratio)
    if spare is not None:
        object.__setattr__(found, _SPARE, spare.reshape((len(TASKS), *full)))
    return found


class _Chain(NamedTuple):
    """What the chain of :func:`_chain_numpy` takes of the targets and sensors of its pairs,
    each array broadcasting against the pairs' line-of-sight components (a named tuple: made
    once per block, cheaply)."""

    sin_h: Any
    cos_h: Any
    length: Any
    width: Any
    height: Any
    visible: Any
    cycle: Any
    extinction: Any
    segments: tuple[Any, ...]
    ifov: Any
    noise_equivalent: Any
    contrast: Any
    foliage: Any = None  # −ln τ_f of the targets' foliage (§6.8); None: none
    path_contrast: Any = None  # σ_path of the contrast SNR law; None: the sonesson law


def _chain_numpy(
    x: np.ndarray,
    y: np.ndarray,
    z: np.ndarray,
    chain: _Chain,
    lengths: tuple[float, ...],
    path: Any,
    ends: Callable[[], tuple[np.ndarray, np.ndarray]],
    noisy: bool,
    cycles: np.ndarray,
) -> tuple[Any, ...]:
    """Range, critical dimension, cycles (into ``cycles``), optical depth, transmittance, SNR
    [dB] and the noise-to-signal amplitude ratio (None without a sensor's own noise) of pairs
    seen along ``(x, y, z)`` (NumPy, called under an ``errstate`` that ignores divisions by
    zero, invalid values and overflows). ``ends()``: the sensors' and targets' positions
    ``(…, 3)`` of the pairs, for the local clouds.

    The chain of the NumPy core, the same for a block of :func:`_factors_numpy` and for the
    pairs in view of :func:`step`: geometry (:func:`targetacq.physics.geometry.box_outline`), N, the
    path (segments, clouds; Eq. (7.7)) and the sensor's own noise.
    """
    r, horizontal, vertical = geometry.outline_numpy(
        x, y, z, chain.sin_h, chain.cos_h, chain.length, chain.width, chain.height
    )
    seen = vertical * chain.visible
    np.minimum(horizontal, seen, out=seen)
    footprint = np.maximum(r, 1e-9)
    footprint *= chain.cycle
    np.divide(seen, footprint, out=cycles)
    # The path: optical depth, transmittance, SNR of Eq. (7.7).
    depth = atmosphere.segmented_depth(r, chain.extinction, lengths, list(chain.segments), np)
    clouds = path.cloud_center.reshape(-1, 3).shape[0]
    if clouds:
        start, end = ends()
        for c in range(clouds):
            chord = atmosphere.sphere_chord_length(
                start, end, path.cloud_center[c], path.cloud_radius[c]
            )
            depth = depth + path.cloud_extinction[c] * chord
    if chain.foliage is not None:  # foliage in front of the targets: τ_f more (§6.8)
        depth = depth + chain.foliage
    tau = np.negative(depth)
    np.exp(tau, out=tau)
    snr = atmosphere.snr_db(depth, np)
    ratio = None
    if noisy:
        # The area seen: the outline's horizontal side times the visible part of its height.
        area = horizontal * vertical * chain.visible
        pixels = detector_noise.pixels_on_target_unchecked(area, np.maximum(r, 1e-9), chain.ifov)
        path_inverse = np.expm1(depth)  # Eq. (7.7) in amplitude: (1 − τ)/τ = e^d − 1
        if chain.path_contrast is not None:  # the contrast law; NEC = 0 rows keep Eq. (7.7)
            aware, inverse, unknown = detector_noise.contrast_db(
                chain.contrast, chain.noise_equivalent, chain.path_contrast, tau, pixels, np
            )
            quiet = chain.noise_equivalent == 0
            snr = np.where(quiet, snr, aware)
            total = np.where(quiet, path_inverse, inverse)
        else:
            own, inverse, unknown = detector_noise.sensor_db(
                chain.contrast, chain.noise_equivalent, tau, pixels, np
            )
            snr = detector_noise.combined_db([snr, own], np)
            # 1/SNR_lin² = Σ 1/SNR_i², in amplitude ratios: the path's is e^d − 1.
            total = path_inverse * path_inverse
            total += inverse * inverse
            np.sqrt(total, out=total)
        ratio = np.where(unknown | np.isnan(depth), np.nan, total)
    return r, seen, cycles, depth, tau, snr, ratio


def _visible_blocks(
    given: np.ndarray | None, own: np.ndarray, batch: tuple[int, ...]
) -> Callable[[slice, slice, slice], np.ndarray]:
    """The visible fraction of a block ``(sb, gb, bb)`` of :func:`_factors_numpy`: the targets'
    own ``(n_g, 1)``, else the one given per call (:func:`check_visible_fraction`, axes of the
    pairs of their size or 1), its axes of size 1 kept."""
    if given is None:
        return lambda sb, gb, bb: own[gb]
    lead = given.shape[:2]
    if all(n == 1 for n in given.shape[2:]):
        flat = given.reshape(*lead, 1)
    else:
        flat = np.broadcast_to(given, (*lead, *batch)).reshape(*lead, math.prod(batch))
    whole = slice(None)

    def part(sb: slice, gb: slice, bb: slice) -> np.ndarray:
        return flat[
            sb if flat.shape[0] > 1 else whole,
            gb if flat.shape[1] > 1 else whole,
            bb if flat.shape[2] > 1 else whole,
        ]

    return part


def _outputs(count: int, shape: tuple[int, ...]) -> tuple[list[np.ndarray], np.ndarray, Any]:
    """``count`` float arrays and a bool array of ``shape`` for :func:`_factors_numpy`, and
    room for the three task probabilities (or None).

    Large outputs are carved from one allocation: fresh memory is mapped page by page on its
    first write, a fault per 4 KiB page that costs more than the arithmetic of the pairs on it,
    while NumPy asks the kernel for 2 MiB pages for an allocation of 4 MiB or more. The room
    for the probabilities is only written (so only mapped) if :func:`probabilities` takes it
    (:data:`_SPARE`). Small outputs are arrays of their own (reused from the heap).
    """
    size = math.prod(shape)
    if size < _SHARED_OUTPUTS:
        return [np.empty(shape) for _ in range(count)], np.empty(shape, dtype=bool), None
    floats = count + len(TASKS)
    raw = np.empty(floats * size * 8 + size, dtype=np.uint8)
    block = raw[: floats * size * 8].view(np.float64).reshape((floats, *shape))
    flags = raw[floats * size * 8 :].view(np.bool_).reshape(shape)
    return list(block[:count]), flags, block[count:]


def _numpy_path(
    scene: SceneArrays, s_pos: Any, t_pos: Any, headings: Any, pointing: Any, scr: Any
) -> bool:
    """Whether :func:`factors` takes the NumPy path: float64 NumPy positions of one batch shape
    (and headings, pointing and SCR NumPy or absent) with a scene of NumPy arrays."""
    if not (isinstance(s_pos, np.ndarray) and isinstance(t_pos, np.ndarray)):
        return False
    if s_pos.dtype != np.float64 or t_pos.dtype != np.float64:
        return False
    if s_pos.ndim < 2 or s_pos.shape[1:] != t_pos.shape[1:] or s_pos.shape[-1] != 3:
        return False
    batch = s_pos.shape[1:-1]
    if headings is not None:
        if not isinstance(headings, np.ndarray) or headings.dtype != np.float64:
            return False
        try:
            np.broadcast_shapes(headings.shape, (t_pos.shape[0], *batch))
        except ValueError:
            return False
        if np.broadcast_shapes(headings.shape, (t_pos.shape[0], *batch)) != (
            t_pos.shape[0],
            *batch,
        ):
            return False
    for value in (pointing, scr):
        if value is not None and not isinstance(value, np.ndarray):
            return False
    if scene.path.named_depths is not None:  # a named atmosphere: the generic chain has it
        return False
    if scene.sensors.ttp is not None:  # TTP rows: an integral per pair, on the whole arrays
        return False
    if scene.sensors.sky_to_ground is not None:  # airlight on the contrast: the generic chain
        return False
    if scene.signature.aspect is not None:  # signature tables: a contrast per pair and batch
        return False
    return _numpy_scene(scene)


def _numpy_factors(scene: SceneArrays, found: Factors) -> bool:
    """Whether :func:`probabilities` takes the NumPy path: NumPy factors and scene."""
    if not (isinstance(found.range, np.ndarray) and isinstance(found.cycles, np.ndarray)):
        return False
    if found.range.ndim < 2 or found.range.dtype != np.float64:
        return False
    for value in (found.in_view, found.snr, found.scr, found.optical_depth):
        if value is not None and not isinstance(value, (np.ndarray, bool)):
            return False
    if scene.targets.graded:  # graded cues per pair: the whole-array path has them
        return False
    return _numpy_scene(scene)


def _pair_values(value: Any, shape: tuple[int, ...], picked: np.ndarray | None) -> np.ndarray:
    """The elements ``picked`` (flat indices into ``shape``; None: all) of an array that
    broadcasts to ``shape``, as a flat array."""
    value = np.asarray(value, dtype=float)
    if value.shape == shape:
        flat = value.reshape(-1)
        return flat if picked is None else flat[picked]
    pair = shape[:2] + (1,) * (len(shape) - 2)
    if value.shape == pair and picked is not None:  # one value per pair, e.g. the SCR
        return value.reshape(-1)[picked // math.prod(shape[2:])]
    flat = np.broadcast_to(value, shape).reshape(-1)
    return flat if picked is None else flat[picked]


def _noise_ratio(found: Factors, shape: tuple[int, ...], picked: np.ndarray | None) -> Any:
    """The noise-to-signal amplitude ratio ``ρ = 1/SNR_lin`` at ``picked``, without decibels
    where ``factors`` left it (:data:`_RATIO`); None where the Factors were made otherwise (the
    transforms then take it from the SNR in dB)."""
    source = found.__dict__.get(_RATIO)
    if source is None:
        return None
    if isinstance(source, str):  # the path's alone: Eq. (7.7) in amplitude, e^d − 1
        with np.errstate(over="ignore"):
            return np.expm1(_pair_values(found.optical_depth, shape, picked))
    return _pair_values(source, shape, picked)


def _probabilities_numpy(
    scene: SceneArrays, found: Factors, moving: np.ndarray | None = None
) -> Probabilities:
    """:func:`probabilities` with NumPy: the transforms run on the pairs in view only."""
    rng = np.asarray(found.range)
    shape = rng.shape
    in_view = np.asarray(found.in_view, dtype=bool)
    if in_view.shape != shape:
        in_view = np.broadcast_to(in_view, shape)
    everywhere = bool(in_view.all())
    picked = None if everywhere else np.flatnonzero(in_view)
    count = rng.size if picked is None else picked.size
    noisy = scene.path.attenuates or scene.sensors.has_noise
    cycles = _pair_values(found.cycles, shape, picked)
    snr = _pair_values(found.snr, shape, picked) if noisy else None
    ratio = _noise_ratio(found, shape, picked) if noisy else None
    scr = None if found.scr is None else _pair_values(found.scr, shape, picked)

    def target() -> np.ndarray:  # each element's target
        n_g, per_pair = shape[1], math.prod(shape[2:])
        index = np.arange(rng.size) if picked is None else picked
        return (index // per_pair) % n_g

    tasks = _in_view_tasks(cycles, snr, ratio, scr, target, scene, moving)
    if noisy:

        def sensor() -> np.ndarray:  # each element's sensor row
            per_sensor = rng.size // shape[0]
            index = np.arange(rng.size) if picked is None else picked
            return index // per_sensor

        tasks = _seen_tasks(scene, tasks, ratio, snr, sensor)
    unknown = np.isnan(rng)
    cycles_all = np.asarray(found.cycles, dtype=float)
    unknown |= np.isnan(
        cycles_all if cycles_all.shape == shape else np.broadcast_to(cycles_all, shape)
    )
    some_unknown = bool(unknown.any())
    room = found.__dict__.pop(_SPARE, None)  # once: a second call allocates its own
    if picked is not None and (room is None or room.shape[1:] != shape):
        room = np.zeros((len(TASKS), *shape))
    elif picked is not None:
        room.fill(0.0)
    out, fused = [], []
    for k, p in enumerate(tasks):
        if picked is None:  # every pair in view: the task's own (new) array
            whole = np.asarray(p, dtype=float).reshape(shape)
        else:
            whole = room[k]
            if count:
                whole.reshape(-1)[picked] = p
        if some_unknown:
            whole[unknown] = np.nan
        out.append(whole)
        if picked is None or 2 * count > rng.size:
            fused.append(fused_along(whole, 0, np))
        else:
            fused.append(_fused_sparse(whole, picked, unknown if some_unknown else None))
    return Probabilities(*out, *fused)


def _seen_tasks(
    scene: SceneArrays,
    tasks: list[np.ndarray],
    ratio: np.ndarray | None,
    snr: np.ndarray | None,
    sensor: Callable[[], np.ndarray],
) -> list[np.ndarray]:
    """The tasks of flat arrays of pairs (``sensor()``: each element's sensor row) times the
    probability that the target is seen above the noise
    (:func:`targetacq.acquisition.path_noise.seen_probability`), where the scene's SNR law has a
    threshold; as they are where not."""
    k = _thresholds(scene, np)
    if k is None or (ratio is None and snr is None):
        return tasks
    # From the SNR in dB where it is there, as the other engines read it (the same rounding).
    rho = ratio if snr is None else np.asarray(noise_ratio(snr))
    seen = seen_of_ratio(rho, k[sensor()], np)
    return [np.asarray(p, dtype=float) * seen for p in tasks]


def _fused_sparse(p: np.ndarray, picked: np.ndarray, unknown: np.ndarray | None) -> np.ndarray:
    """:func:`targetacq.acquisition.fusion.fuse` over the sensors (axis 0) of ``p``, zero but at
    ``picked`` (flat indices, increasing) and NaN at ``unknown``: the product of ``1 − p`` taken
    over those elements only, sensor after sensor as the reduction takes it (a factor 1 changes
    nothing), without reading the zeros."""
    per_sensor = p[0].size
    product = np.ones(per_sensor)
    np.multiply.at(product, picked % per_sensor, 1.0 - p.reshape(-1)[picked])
    if unknown is not None:
        product[unknown.reshape(p.shape[0], -1).any(axis=0)] = np.nan
    return (1.0 - product).reshape(p.shape[1:])


def _in_view_tasks(
    cycles: np.ndarray,
    snr: np.ndarray | None,
    ratio: np.ndarray | None,
    scr: np.ndarray | None,
    target: Callable[[], np.ndarray],
    scene: SceneArrays,
    moving: np.ndarray | None = None,
) -> list[np.ndarray]:
    """Ordered probabilities of flat arrays of pairs (``target()``: each element's target), the
    targets that share a criterion together, in blocks of :data:`_PROBABILITY_BLOCK`; the same
    calls as :func:`task_probabilities` makes for them, element by element."""
    groups = _groups(scene.targets).with_moving(moving)
    chosen: _Choices = derived(scene, "choices", _scene_choices)
    noise = None if snr is None else chosen.noise
    size = cycles.size
    flags_differ = None in groups.hot_same or None in groups.moving_same
    of = target() if groups.group is not None or flags_differ else None
    members: list[np.ndarray | None] = [None]
    if groups.group is not None and of is not None:
        members = [np.flatnonzero(groups.group[of] == k) for k in range(len(groups.rows))]
    out: list[np.ndarray] | None = None
    for k, (row, chosen_members) in enumerate(zip(groups.rows, members, strict=True)):
        count = size if chosen_members is None else chosen_members.size
        for start in range(0, count, _PROBABILITY_BLOCK):
            where: Any = slice(start, min(start + _PROBABILITY_BLOCK, count))
            if chosen_members is not None:
                where = chosen_members[where]

            def part(value: Any, where: Any = where) -> Any:
                return None if value is None else value[where]

            def at(where: Any = where) -> np.ndarray:
                return of[where]  # type: ignore[index]

            found = ordered_probabilities(
                part(cycles),
                list(row),
                chosen.transform,
                chosen.options,
                clutter=Clutter(
                    scr=part(scr),
                    region=scene.choices.region,
                    hot_spot=groups.flag("hot", k, at),
                    moving=groups.flag("moving", k, at),
                ),
                snr=part(snr),
                noise=noise,
                motion=chosen.motion,
                semantics=chosen.semantics,
                noise_ratio=part(ratio),
            )
            if out is None and count == size <= _PROBABILITY_BLOCK:
                return [np.asarray(p, dtype=float) for p in found]  # one call: its arrays
            if out is None:
                out = [np.empty(size) for _ in TASKS]
            for whole, p in zip(out, found, strict=True):
                whole[where] = p
    return out if out is not None else [np.empty(size) for _ in TASKS]


def factors(
    scene: SceneArrays,
    sensor_positions: Array,
    target_positions: Array,
    headings: Array = None,
    pointing: Array = None,
    scr: Array = None,
    visible_fraction: Array = None,
) -> Factors:
    """Range, critical dimension, cycles, field of view, path and clutter of every pair.

    Parameters
    ----------
    scene : SceneArrays
    sensor_positions : array ``(n_s, *batch, 3)``
        [m] (east, north, up).
    target_positions : array ``(n_g, *batch, 3)``
        [m].
    headings : array ``(n_g, *batch)``, optional
        Direction of each target's long axis [rad]; default the targets' own.
    pointing : array (n_s, 2), optional
        See :func:`boresight`.
    scr : array ``(n_s, n_g, *batch)``, optional
        SCR per pair, replacing the scene's (e.g. :func:`footprint_scr` of a terrain map).
    visible_fraction : array, optional
        Fraction of each target's height in view for this call, in (0, 1] [1], replacing the
        targets' own (:attr:`TargetArrays.visible_fraction`): ``(n_g,)``, ``(n_s, n_g)`` or
        axes of ``(n_s, n_g, *batch)`` from the left, each of its size or 1
        (:func:`check_visible_fraction`). It scales the critical dimension's vertical side,
        the area a sensor's own noise sees and a laser radar's relief SCR; NaN gives NaN
        probabilities for the pairs it reaches.

    Returns
    -------
    Factors

    Raises
    ------
    ValueError
        Infinite positions, or a visible fraction of the wrong shape or outside (0, 1].

    Notes
    -----
    With NumPy (float64 positions and a scene of NumPy arrays) the pairs are computed in blocks
    of a few thousand triples whose temporaries stay in the CPU cache, with each scene's fixed
    parts (the sensors' frames where they point by angles) computed once; the numbers are those
    of the whole-array computation.
    """
    xp, (s_pos, t_pos) = _arrays.arrays(
        sensor_positions, target_positions, names=_POSITIONS, broadcast=False
    )
    # Infinite positions have no geometry (inf − inf); NaN ones give NaN probabilities.
    for name, value in zip(_POSITIONS, (s_pos, t_pos), strict=True):
        if type(value) is not np.ndarray or not value.ndim or np.isinf(value).any():
            _arrays.require_finite(name, value, xp, "m")
    visible = None
    if visible_fraction is not None:
        visible = check_visible_fraction(
            visible_fraction, pair_shape(scene.shape, s_pos, t_pos), xp
        )
    if _numpy_path(scene, s_pos, t_pos, headings, pointing, scr) and (
        visible is None or isinstance(visible, np.ndarray)
    ):
        found = _factors_numpy(scene, s_pos, t_pos, headings, pointing, scr, visible)
    else:
        found = _factors_generic(scene, s_pos, t_pos, headings, pointing, scr, xp, visible)
    if scene.sensors.mrtd is not None:  # MRTD-limited thermal rows: their cycles from the curve
        found = mrtd_rows.mrtd_factors(scene, found)
        if not scene.choices.snr_on_mrtd:  # the curve holds the noise and τ: no SNR on top
            found = _without_snr(found, scene.sensors.mrtd.rows)
    if scene.sensors.ttp is not None:  # TTP rows: V from the TTP metric, no SNR on top
        found = ttp_rows.ttp_factors(scene, found, s_pos, t_pos, headings, visible)
        if ttp_rows.HOLDS_NOISE:  # the TTP threshold holds the NETD and τ: no SNR on top
            found = _without_snr(found, scene.sensors.ttp.rows)
    if active.has_active(scene):  # radars and laser radars: their rows' own factors
        return active.active_factors(scene, found, s_pos, t_pos, visible)
    return found


def _without_snr(found: Factors, rows: tuple[int, ...]) -> Factors:
    """``found`` with no noise at the sensor rows ``rows`` (SNR +inf): the MRTD-limited rows
    under the default noise handling (:attr:`targetacq.core.records.ModelChoices.snr_on_mrtd`)
    and the TTP rows."""
    xp, (snr,) = _arrays.arrays(found.snr)
    n_s = snr.shape[0]
    mask = np.zeros((n_s,) + (1,) * (snr.ndim - 1), dtype=bool)
    mask[list(rows)] = True
    quiet = dataclasses.replace(found, snr=xp.where(mask, xp.inf, snr))
    source = found.__dict__.get(_RATIO)
    if source is not None:  # the NumPy core's noise-to-signal ratio: 0 there
        with np.errstate(over="ignore"):
            ratio = np.expm1(found.optical_depth) if isinstance(source, str) else source
        object.__setattr__(quiet, _RATIO, np.where(mask, 0.0, ratio))
    spare = found.__dict__.get(_SPARE)
    if spare is not None:
        object.__setattr__(quiet, _SPARE, spare)
    return quiet


def pair_shape(scene_shape: tuple[int, int], s_pos: Array, t_pos: Array) -> tuple[int, ...]:
    """``(n_s, n_g, *batch)`` of a scene of shape ``(n_s, n_g)`` at positions
    ``(n_s, *batch_s, 3)`` and ``(n_g, *batch_g, 3)``, their batch axes broadcast together.

    Raises
    ------
    ValueError
        Batch axes that do not broadcast (both shapes named).

    Examples
    --------
    >>> import numpy as np
    >>> pair_shape((2, 3), np.zeros((2, 5, 1, 3)), np.zeros((3, 4, 3)))
    (2, 3, 5, 4)
    """
    try:
        batch = np.broadcast_shapes(tuple(s_pos.shape[1:-1]), tuple(t_pos.shape[1:-1]))
    except ValueError:
        raise ValueError(
            f"sensor_positions {tuple(s_pos.shape)} and target_positions {tuple(t_pos.shape)}: "
            "their batch dimensions (between the first and the last) do not broadcast"
        ) from None
    return (*scene_shape, *batch)


def _factors_generic(
    scene: SceneArrays,
    s_pos: Any,
    t_pos: Any,
    headings: Any,
    pointing: Any,
    scr: Any,
    xp: Any,
    visible: Any = None,
) -> Factors:
    """:func:`factors` of checked positions in any array namespace (whole arrays at once)."""
    sensors, targets, path = scene.sensors, scene.targets, scene.path
    batch = s_pos.ndim - 2
    if visible is None:
        visible = _per_target(targets.visible_fraction, batch, xp)
    # Components (n_s, n_g, *batch), each contiguous in memory.
    x, y, z = (t_pos[None, ..., k] - s_pos[:, None, ..., k] for k in range(3))
    heading = _per_target(targets.heading, batch, xp) if headings is None else headings[None]
    dims = _arrays.as_float(targets.dimensions, xp)
    rng, horizontal, vertical = geometry.box_outline(
        x,
        y,
        z,
        heading,
        _per_target(dims[:, 0], batch, xp),
        _per_target(dims[:, 1], batch, xp),
        _per_target(dims[:, 2], batch, xp),
    )
    critical = geometry.critical_dimension_seen(horizontal, vertical, visible)

    forward, pointed = boresight(s_pos, sensors, pointing)
    half = _arrays.as_float(sensors.half_tangents, xp)
    in_fov = geometry.within_field_of_view(
        x,
        y,
        z,
        (forward[0][:, None], forward[1][:, None], forward[2][:, None]),
        (_per_sensor(half[:, 0], batch, xp), _per_sensor(half[:, 1], batch, xp)),
    )
    in_view = xp.where(pointed, in_fov, True) & ~xp.isnan(rng)

    segment = _arrays.as_float(sensors.segment_extinction, xp)
    lengths = path.segment_length
    depth = atmosphere.segmented_optical_depth(
        rng,
        _per_sensor(sensors.extinction, batch, xp),
        # Python floats for NumPy; 0-d arrays otherwise (traced under jit, no host read).
        [float(v) for v in lengths]
        if isinstance(lengths, np.ndarray)
        else [lengths[j] for j in range(lengths.shape[0])],
        [_per_sensor(segment[:, j], batch, xp) for j in range(segment.shape[1])],
    )
    centers = _arrays.as_float(path.cloud_center, xp)
    for c in range(centers.shape[0]):
        chord = atmosphere.sphere_chord_length(
            s_pos[:, None], t_pos[None], centers[c], path.cloud_radius[c]
        )
        depth = depth + path.cloud_extinction[c] * chord
    if path.named_depths is not None:  # a named atmosphere: each band's table of d(R)
        named = _arrays.as_float(path.named_depths, xp)
        depth = depth + named_atmospheres.tabulated_depth(
            rng,
            path.named_ranges,
            [_per_sensor(named[:, k], batch, xp) for k in range(named.shape[1])],
            xp,
        )
    if targets.foliage is not None:  # foliage in front of the targets: τ_f more (§6.8)
        depth = depth + _per_target(_foliage_depth(targets.foliage, xp), batch, xp)
    contrast = xp.reshape(
        _arrays.as_float(scene.signature.contrast, xp), (*scene.shape,) + (1,) * batch
    )
    if scene.signature.aspect is not None:  # signature tables: each pair's at its aspect
        contrast, aspect_scr = _aspect_contrast(scene.signature.aspect, x, y, z, heading, xp)
        if scr is None:
            scr = aspect_scr
    if scr is None and scene.signature.scr is not None:
        scr = xp.reshape(_arrays.as_float(scene.signature.scr, xp), (*scene.shape,) + (1,) * batch)
    noise = None
    if sensors.has_noise:
        noise = SensorNoise(
            contrast=contrast,
            noise_equivalent=_per_sensor(sensors.noise_equivalent, batch, xp),
            ifov=_per_sensor(sensors.ifov, batch, xp),
            # The area seen: the outline's horizontal side times the visible part of its height.
            area=horizontal * vertical * visible,
            path_contrast=1.0
            if sensors.path_contrast is None
            else _per_sensor(sensors.path_contrast, batch, xp),
            law=scene.choices.snr_law if _contrast_law(scene) else "sonesson",
            sky_to_ground=None
            if sensors.sky_to_ground is None
            else _per_sensor(_arrays.as_float(sensors.sky_to_ground, xp), batch, xp),
        )
    cycles, tau, snr = imager_factors(
        rng, critical, _per_sensor(sensors.cycle, batch, xp), depth, noise
    )
    return Factors(
        range=rng,
        critical_dimension=critical,
        cycles=cycles,
        in_view=in_view,
        optical_depth=depth,
        transmittance=tau,
        snr=snr,
        scr=scr,
    )


def _aspect_contrast(
    table: AspectArrays, x: Any, y: Any, z: Any, heading: Any, xp: Any
) -> tuple[Any, Any]:
    """Each pair's contrast at the aspect the sensor sees the target from ``(n_s, n_g, *batch)``
    [W/m²] (:func:`targetacq.physics.aspect.interpolate_aspect` of the scene's tables), and
    the SCR that follows it where the clutter is a spread (None otherwise: the scene's)."""
    azimuth, elevation = aspect.observer_aspect(x, y, z, heading)
    contrast = aspect.interpolate_aspect(
        _arrays.as_float(table.azimuth, xp),
        _arrays.as_float(table.elevation, xp),
        _arrays.as_float(table.contrast, xp),
        azimuth,
        elevation,
    )
    if table.clutter is None:
        return contrast, None
    clutter = _arrays.as_float(table.clutter, xp)
    spread = xp.reshape(clutter, tuple(clutter.shape) + (1,) * (contrast.ndim - 2))
    return contrast, signal_to_clutter_ratio(contrast, 0.0, spread)


def crossing_speeds(
    sensor_positions: Array, target_positions: Array, target_velocities: Array
) -> Any:
    """Each pair's speed of the target across its line of sight [m/s], ``(n_s, n_g, *batch)``.

    :func:`targetacq.physics.geometry.transverse_speed` of the line of sight (sensor to target)
    and the target's own velocity over the ground: over the range it is the target's angular
    speed against its background, the input of the graded motion cue. The sensor's own motion
    does not enter: it moves the background in the image as much as the target (a platform
    flying past a parked truck sees no motion cue), and what separates a moving target from its
    background is its motion against that background (§1.3, §7.5).

    Parameters
    ----------
    sensor_positions : array ``(n_s, *batch, 3)``
        [m].
    target_positions : array ``(n_g, *batch, 3)``
        [m].
    target_velocities : array ``(n_g, *batch, 3)``
        Over the ground [m/s].

    Returns
    -------
    array
        v_⊥ >= 0 [m/s].

    Examples
    --------
    A sensor at the origin; a target 1 km north driving east at 10 m/s, one 1 km east driving
    at the sensor:

    >>> import numpy as np
    >>> from targetacq.core import crossing_speeds
    >>> s = np.zeros((1, 3))
    >>> g = np.array([[0.0, 1000.0, 0.0], [1000.0, 0.0, 0.0]])
    >>> v = np.array([[10.0, 0.0, 0.0], [-10.0, 0.0, 0.0]])
    >>> crossing_speeds(s, g, v).tolist()
    [[10.0, 0.0]]
    """
    _, (s_pos, t_pos, t_vel) = _arrays.arrays(
        sensor_positions,
        target_positions,
        target_velocities,
        names=(*_POSITIONS, "target_velocities"),
        broadcast=False,
    )
    if tuple(t_vel.shape) != tuple(t_pos.shape):
        raise ValueError(
            f"target_velocities must have the shape of the target positions, "
            f"{tuple(t_pos.shape)}; got {tuple(t_vel.shape)}"
        )
    line = [t_pos[None, ..., k] - s_pos[:, None, ..., k] for k in range(3)]
    return geometry.transverse_speed(*line, *(t_vel[None, ..., k] for k in range(3)))


@dataclass(frozen=True)
class GradedCues:
    """The graded cues of every pair, as :class:`targetacq.acquisition.probabilities.Clutter`
    takes them, each ``(n_s, n_g, *batch)`` or None (that cue is absent).

    Attributes
    ----------
    hot_spot_ratio : array or None
        The hot spot's own SCR [1] (0 where a target has none).
    hot_spot_size : array or None
        Its size over the critical dimension seen [1] (huge where a target gives none: no
        dilution).
    speed : array or None
        The speed across the line of sight over the critical dimension seen [1/s] (0 for the
        targets without a graded motion cue); at N cycles ``2 N · speed`` pixels per second.
    """

    hot_spot_ratio: Any = None
    hot_spot_size: Any = None
    speed: Any = None

    def rows(self, rows: tuple[int, ...], xp: Any) -> GradedCues:
        """The cues of some sensor rows (axis 0)."""
        return GradedCues(
            *(
                None if value is None else xp.take(value, xp.asarray(rows), axis=0)
                for value in (self.hot_spot_ratio, self.hot_spot_size, self.speed)
            )
        )


# A size over the critical dimension that no hot spot reaches: 2 N times it is above 1 (the
# hot spot fills its resolution element) at any N > 1e-90 and finite up to N ~ 1e150.
_UNDILUTED = 1e100


def graded_cues(scene: SceneArrays, found: Factors) -> GradedCues | None:
    """The graded hot-spot and motion cues of every pair (None where no target has one).

    The sizes and speeds are per critical dimension seen, as the cycles count them
    (:class:`targetacq.acquisition.probabilities.Clutter`): a hot spot of size ``s`` covers
    ``2 N s / d`` resolution elements across, and a target crossing the line of sight at
    ``v_⊥`` moves ``2 N v_⊥ / d = v_⊥ / (R · cycle / 2)`` pixels per second (half a
    resolvable cycle, Fig. 3.3) with the geometric N. The targets without a graded cue get
    weight 0, so their detection is exactly as without.
    """
    targets = scene.targets
    if not targets.graded:
        return None
    xp, (cycles, critical) = _arrays.arrays(found.cycles, found.critical_dimension)
    shape = tuple(np.broadcast_shapes(tuple(cycles.shape), tuple(critical.shape)))
    batch = len(shape) - 2

    def full(value: Any) -> Any:
        return xp.broadcast_to(value, shape)

    ratio = size = speed = None
    if targets.hot_spot_ratio is not None:
        ratio = full(_per_target(_arrays.as_float(targets.hot_spot_ratio, xp), batch, xp))
        if targets.hot_spot_size is not None:
            given = _per_target(_arrays.as_float(targets.hot_spot_size, xp), batch, xp)
            has = ~xp.isnan(given)
            size = full(xp.where(has, xp.where(has, given, 1.0) / critical, _UNDILUTED))
    if any(targets.graded_motion):
        graded = _per_target(xp.asarray(np.asarray(targets.graded_motion, dtype=bool)), batch, xp)
        crossing = found.crossing_speed
        if crossing is None:
            speed = full(xp.zeros_like(critical))
        else:
            moving = xp.where(graded, _arrays.as_float(crossing, xp), 0.0)
            speed = full(moving / critical)
    return GradedCues(ratio, size, speed)


def task_probabilities(
    cycles: Array,
    snr: Array,
    scr: Array,
    scene: SceneArrays,
    moving: Array = None,
    rows: tuple[int, ...] | None = None,
    cues: GradedCues | None = None,
) -> tuple[Any, Any, Any]:
    """Ordered probabilities of detection, recognition and identification of every pair.

    :func:`targetacq.acquisition.probabilities.ordered_probabilities` with each target's N50s,
    hot-spot and moving flags and the scene's transform, noise model and clutter. With NumPy the
    targets that share a criterion go through together (scalar N50s, the fused TTPF path), so a
    target's numbers do not depend on which other targets are evaluated with it; with other array
    libraries the N50s are arrays along the target axis.

    Parameters
    ----------
    cycles : array ``(n_s, n_g, *batch)``
    snr : array or None
        [dB]; None for no path noise.
    scr : array or None
    scene : SceneArrays
    moving : array of bool (n_g,), optional
        The targets' moving flags for this call (:func:`check_moving`); default their own.
    rows : tuple of int, optional
        The scene's sensor rows that the first axis holds (default all, in order).
    cues : GradedCues, optional
        The graded hot-spot and motion cues of the pairs (:func:`graded_cues`); None: none.

    Returns
    -------
    detection, recognition, identification : array
        Under a contrast SNR law with a threshold, times the probability that the target is
        seen above the noise (:func:`targetacq.acquisition.path_noise.seen_probability`).
    """
    found = _transform_probabilities(cycles, snr, scr, scene, moving, cues)
    xp, (n,) = _arrays.arrays(cycles)
    k = None if snr is None else _thresholds(scene, xp)
    if k is None:
        return found
    if rows is not None:
        k = xp.stack([k[row] for row in rows]) if rows else k[:0]
    seen = seen_of_ratio(noise_ratio(snr), _per_sensor(k, n.ndim - 2, xp), xp)
    return found[0] * seen, found[1] * seen, found[2] * seen


def _transform_probabilities(
    cycles: Array,
    snr: Array,
    scr: Array,
    scene: SceneArrays,
    moving: Array = None,
    cues: GradedCues | None = None,
) -> tuple[Any, Any, Any]:
    """:func:`task_probabilities` before the threshold."""
    xp, (n,) = _arrays.arrays(cycles)
    choices, targets = scene.choices, scene.targets
    batch = n.ndim - 2
    numpy = isinstance(targets.n50, np.ndarray) and isinstance(n, np.ndarray)
    resolved = _choices(choices) if numpy else _resolve(choices)
    noise = None if snr is None else resolved.noise
    if numpy and moving is not None:
        moving = np.asarray(moving, dtype=bool)
    groups = _groups(targets).with_moving(moving) if numpy else None
    traced_moving = moving is not None and not isinstance(moving, np.ndarray)

    def run(members: Any, n50: list[Any], k: int = 0) -> tuple[Any, Any, Any]:
        def pick(value: Any) -> Any:
            return value if value is None or members is None else value[:, members]

        def flag(name: str) -> Any:  # one bool when all agree, else per target
            if groups is not None:
                same = (groups.hot_same if name == "hot" else groups.moving_same)[k]
                if same is not None:
                    return same
            if name == "moving" and traced_moving:  # JAX's flags: per target, as they come
                return _per_target(moving if members is None else moving[members], batch, xp)
            own = targets.moving if moving is None else moving
            values = np.asarray(targets.hot_spot if name == "hot" else own, dtype=bool)
            chosen = values if members is None else values[members]
            if chosen.size and bool(np.all(chosen == chosen[0])):
                return bool(chosen[0])
            return _per_target(xp.asarray(chosen), batch, xp)

        return ordered_probabilities(
            pick(n),
            n50,
            resolved.transform,
            resolved.options,
            clutter=Clutter(
                scr=pick(scr),
                region=choices.region,
                hot_spot=flag("hot"),
                moving=flag("moving"),
                hot_spot_ratio=None if cues is None else pick(cues.hot_spot_ratio),
                hot_spot_size=None if cues is None else pick(cues.hot_spot_size),
                speed=None if cues is None else pick(cues.speed),
            ),
            snr=pick(snr),
            noise=noise,
            motion=resolved.motion,
            semantics=resolved.semantics,
        )

    if groups is None:
        table_xp = _arrays.as_float(targets.n50, xp)
        return run(None, [_per_target(table_xp[:, k], batch, xp) for k in range(3)])
    if groups.group is None:
        return run(None, list(groups.rows[0]))
    out = [np.empty(n.shape) for _ in TASKS]
    for k, row in enumerate(groups.rows):
        members = np.flatnonzero(groups.group == k)
        for whole, part in zip(out, run(members, list(row), k), strict=True):
            whole[:, members] = part
    return out[0], out[1], out[2]


def probabilities(scene: SceneArrays, found: Factors, moving: Array = None) -> Probabilities:
    """Probabilities of every pair from its factors, zero outside the field of view and where
    the contrast is below the sensor's digitiser step (:attr:`SensorArrays.quantisation_step`),
    NaN where the geometry (the range or the cycles) is NaN, and their sensor-level fusion
    (8.4).

    With NumPy the transforms run on the pairs in view only, and the noise comes from the optical
    depth without the decibels where ``found`` was made by :func:`factors`; the numbers are the
    same.

    Parameters
    ----------
    scene : SceneArrays
    found : Factors
    moving : array of bool (n_g,), optional
        Which targets move in this call, replacing the targets' own flags
        (:attr:`TargetArrays.moving`): the motion rule of the scene's choices detects the
        moving ones (§3.9).

    Returns
    -------
    Probabilities

    Raises
    ------
    ValueError
        ``moving`` not booleans, one per target.
    """
    if moving is not None:
        moving = check_moving(moving, scene.shape[1])
    if active.has_active(scene):
        cues = graded_cues(scene, found)
        found_p = _probabilities_generic(
            scene,
            found,
            active.active_probabilities(scene, found, task_probabilities, moving, cues),
        )
    elif _numpy_factors(scene, found):
        found_p = _probabilities_numpy(scene, found, _host_flags(moving))
    else:
        found_p = _probabilities_generic(scene, found, moving=moving)
    if scene.sensors.quantisation_step is not None:  # contrasts below a digitiser's step
        found_p = _quantised(scene, found_p)
    if scene.sensors.groups:  # colour cameras: their bands are one look, not several
        groups = scene.sensors.groups
        found_p = dataclasses.replace(
            found_p,
            fused_detection=fuse_groups(found_p.detection, groups),
            fused_recognition=fuse_groups(found_p.recognition, groups),
            fused_identification=fuse_groups(found_p.identification, groups),
        )
    return found_p


def _below_step(scene: SceneArrays, xp: Any) -> Any:
    """``(n_s, n_g)`` bool: the pairs whose contrast at the scene is below their sensor's
    digitiser step (:attr:`SensorArrays.quantisation_step`; §6.8): they are not seen."""
    step = _arrays.as_float(scene.sensors.quantisation_step, xp)
    return _arrays.as_float(scene.signature.contrast, xp) < xp.reshape(step, (-1, 1))


def _quantised(scene: SceneArrays, found: Probabilities) -> Probabilities:
    """The probabilities with every task 0 at the pairs below their sensor's digitiser step
    (NaN stays NaN), and their fusion (8.4) again."""
    xp, (p,) = _arrays.arrays(found.detection)
    below = _below_step(scene, xp)
    below = xp.reshape(below, tuple(below.shape) + (1,) * (p.ndim - 2))
    tasks = [
        xp.where(below, 0.0 * task, task)
        for task in (found.detection, found.recognition, found.identification)
    ]
    return Probabilities(*tasks, *(fuse(task, axis=0) for task in tasks))


def _host_flags(moving: Any) -> np.ndarray | None:
    """Checked moving flags as a NumPy array (None stays None)."""
    return None if moving is None else np.asarray(moving, dtype=bool)


def _probabilities_generic(
    scene: SceneArrays,
    found: Factors,
    tasks: tuple[Any, Any, Any] | None = None,
    moving: Any = None,
) -> Probabilities:
    """:func:`probabilities` in any array namespace: every pair, then the field of view."""
    xp, (rng, cycles) = _arrays.arrays(found.range, found.cycles)
    if tasks is None:
        snr = found.snr if scene.path.attenuates or scene.sensors.has_noise else None
        cues = graded_cues(scene, found)
        tasks = task_probabilities(found.cycles, snr, found.scr, scene, moving=moving, cues=cues)
    unknown = xp.isnan(rng) | xp.isnan(cycles)
    out = [
        xp.where(unknown, xp.nan, xp.where(found.in_view, _arrays.as_float(p, xp), 0.0))
        for p in tasks
    ]
    fused = [fuse(p, axis=0) for p in out]
    return Probabilities(*out, *fused)


def evaluate(
    scene: SceneArrays,
    sensor_positions: Any,
    target_positions: Any,
    headings: Any = None,
    pointing: Any = None,
    scr: Any = None,
    visible_fraction: Any = None,
    moving: Any = None,
    target_velocities: Any = None,
) -> tuple[Factors, Probabilities]:
    """Factors and probabilities of every pair (:func:`factors`, then :func:`probabilities`).

    ``visible_fraction`` goes to :func:`factors`, ``moving`` to :func:`probabilities`: both
    replace the targets' own for this call. ``target_velocities`` ``(n_g, *batch, 3)`` [m/s]
    give the targets with a graded motion cue their speed across each line of sight
    (:func:`crossing_speeds`); without them those targets stand still.
    """
    found = factors(
        scene, sensor_positions, target_positions, headings, pointing, scr, visible_fraction
    )
    if any(scene.targets.graded_motion) and target_velocities is not None:
        found = dataclasses.replace(
            found,
            crossing_speed=crossing_speeds(sensor_positions, target_positions, target_velocities),
        )
    return found, probabilities(scene, found, moving)


def evaluate_step(
    scene: SceneArrays,
    sensor_positions: Array,
    target_positions: Array,
    headings: Array = None,
    pointing: Array = None,
    visible_fraction: Array = None,
    moving: Array = None,
    scr: Array = None,
) -> tuple[Any, Any, Any]:
    """One time of the core: which pairs are in view, their probabilities and their fusion.

    :func:`evaluate` of positions of one time, with only what a step of the step API uses.
    With NumPy the geometry and the field of view are computed for every pair, and the rest of
    the chain (critical dimension, path, noise, the transforms) for the pairs in view (and
    those of unknown geometry) only: the numbers of :func:`evaluate`, elementwise.

    Parameters
    ----------
    scene : SceneArrays
    sensor_positions : array (n_s, 3)
        [m].
    target_positions : array (n_g, 3)
        [m].
    headings : array (n_g,), optional
        [rad]; default the targets' own.
    pointing : array (n_s, 2), optional
        Azimuth and depression [rad] (:func:`boresight`).
    visible_fraction : array, optional
        ``(n_g,)`` or ``(n_s, n_g)``, in (0, 1] (:func:`check_visible_fraction`).
    moving : array of bool (n_g,), optional
        (:func:`check_moving`).
    scr : array (n_s, n_g), optional
        SCR per pair, replacing the scene's.

    Returns
    -------
    in_view : array of bool (n_s, n_g)
    probabilities : array (3, n_s, n_g)
        Detection, recognition, identification: zero outside the field of view, NaN where the
        geometry (range or cycles) is NaN.
    fused : array (3, n_g)
        Their sensor-level fusion (8.4) (colour cameras: each camera's best band first).

    Raises
    ------
    ValueError
        Positions not of one time (``(n_s, 3)``, ``(n_g, 3)``), infinite positions or
        headings, a visible fraction or moving flags that do not fit (:func:`factors`,
        :func:`probabilities`).
    """
    n_s, n_g = scene.shape
    xp, (s_pos, t_pos) = _arrays.arrays(
        sensor_positions, target_positions, names=_POSITIONS, broadcast=False
    )
    for name, value, count in zip(_POSITIONS, (s_pos, t_pos), (n_s, n_g), strict=True):
        if tuple(value.shape) != (count, 3):
            raise ValueError(
                f"{name} must have shape ({count}, 3) for one time (east, north, up [m]); got "
                f"{tuple(value.shape)}"
            )
    if (
        not active.has_active(scene)
        and not scene.targets.graded  # graded cues: the whole-array path
        and scene.sensors.mrtd is None  # MRTD-limited rows: the cycles of factors()
        and scene.sensors.ttp is None  # TTP rows: their V and SNR of factors()
        and _numpy_path(scene, s_pos, t_pos, headings, pointing, scr)
        and (visible_fraction is None or isinstance(visible_fraction, np.ndarray))
        and (moving is None or isinstance(moving, (np.ndarray, list, tuple)))
    ):
        return _step_numpy(scene, s_pos, t_pos, headings, pointing, visible_fraction, moving, scr)
    found, p = evaluate(scene, s_pos, t_pos, headings, pointing, scr, visible_fraction, moving)
    in_view = xp.broadcast_to(xp.asarray(found.in_view), (n_s, n_g))
    tasks = xp.stack([p.detection, p.recognition, p.identification])
    fused = xp.stack([p.fused_detection, p.fused_recognition, p.fused_identification])
    return in_view, tasks, fused


# Pairs from which the NumPy step computes the chain on the pairs in view only (fewer pairs
# than this: on all of them, saving the gathers).
_COMPACT_FROM = 64


def _step_numpy(
    scene: SceneArrays,
    s_pos: np.ndarray,
    t_pos: np.ndarray,
    headings: Any,
    pointing: Any,
    visible_fraction: Any,
    moving: Any,
    scr: Any,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`evaluate_step` with NumPy: the field of view of every pair, the chain
    (:func:`_chain_numpy`) and the transforms (:func:`_in_view_tasks`) of the pairs in view."""
    sensors, path = scene.sensors, scene.path
    n_s, n_g = scene.shape
    for name, value in zip(_POSITIONS, (s_pos, t_pos), strict=True):
        if np.isinf(value).any():
            _arrays.require_finite(name, value, np, "m")
    flags = None if moving is None else np.asarray(check_moving(moving, n_g), dtype=bool)
    parts: _Parts = derived(scene, "parts", _scene_parts)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        if headings is None:
            sin_h, cos_h, odd = parts.sin_h[:, 0], parts.cos_h[:, 0], None
        else:
            heading = np.broadcast_to(np.asarray(headings, dtype=float), (n_g,))
            _arrays.require_finite("heading", heading, np, "rad")
            sin_h, cos_h = np.sin(heading), np.cos(heading)
            odd = np.isnan(heading)  # known geometry, unknown outline
        visible: np.ndarray = parts.visible[:, 0]
        if visible_fraction is not None:
            given = check_visible_fraction(visible_fraction, (n_s, n_g), np)
            visible = np.broadcast_to(given, (given.shape[0], n_g))
            nan_visible = np.isnan(visible)
            if nan_visible.any():
                odd = nan_visible if odd is None else odd | nan_visible
        # The field of view of every pair (exactly as factors() has it).
        x = t_pos[:, 0] - s_pos[:, 0, None]  # (n_s, n_g)
        y = t_pos[:, 1] - s_pos[:, 1, None]
        z = t_pos[:, 2] - s_pos[:, 2, None]
        frame, fixed = _sensor_frames(s_pos.reshape(n_s, 1, 3), sensors, pointing)
        unknown = np.isnan(s_pos).any(axis=1)[:, None] | np.isnan(t_pos).any(axis=1)
        viewing = fixed.viewing
        if viewing.any():
            tan_h, tan_v = fixed.half_tangents
            in_view = geometry.within_numpy(x, y, z, frame, tan_h[:, :, 0], tan_v[:, :, 0])
            if not viewing.all():
                in_view |= ~viewing[:, None]
            in_view &= ~unknown
        else:
            in_view = ~unknown
        needed = in_view | unknown
        if odd is not None:
            needed |= odd
        size = n_s * n_g
        picked = None
        if size >= _COMPACT_FROM and not needed.all():
            picked = np.flatnonzero(needed)
        # The chain of the pairs needed: every pair (broadcast), or the picked ones (gathered).
        if picked is None:
            s_of: Any = slice(None)
            g_of: Any = slice(None)
            xs, ys, zs = x, y, z
            shape: tuple[int, ...] = (n_s, n_g)
            seen_visible = visible
            contrast = parts.contrast[:, :, 0]
        else:
            s_of, g_of = np.divmod(picked, n_g)
            xs, ys, zs = x.reshape(-1)[picked], y.reshape(-1)[picked], z.reshape(-1)[picked]
            shape = (picked.size,)
            seen_visible = (
                visible[g_of] if visible.ndim == 1 else visible[s_of % visible.shape[0], g_of]
            )
            contrast = parts.contrast[s_of, g_of, 0]

        def per_sensor(value: np.ndarray) -> np.ndarray:  # (n_s, 1, 1) of the parts
            return value[:, :, 0] if picked is None else value[s_of, 0, 0]

        chain = _Chain(
            sin_h[g_of],
            cos_h[g_of],
            parts.length[g_of, 0],
            parts.width[g_of, 0],
            parts.height[g_of, 0],
            seen_visible,
            per_sensor(parts.cycle),
            per_sensor(parts.extinction),
            tuple(per_sensor(g) for g in parts.segments),
            per_sensor(parts.ifov),
            per_sensor(parts.noise_equivalent),
            contrast,
            None if parts.foliage is None else parts.foliage[g_of, 0],
            None if parts.path_contrast is None else per_sensor(parts.path_contrast),
        )
        cycles = np.empty(shape)
        r, _, cycles, depth, _, snr, ratio = _chain_numpy(
            xs,
            ys,
            zs,
            chain,
            parts.lengths,
            path,
            lambda: (s_pos[s_of] if picked is not None else s_pos[:, None], t_pos[g_of]),
            sensors.has_noise,
            cycles,
        )
        noisy = path.attenuates or sensors.has_noise
        if noisy and ratio is None:  # the path's alone: Eq. (7.7) in amplitude, e^d − 1
            ratio = np.expm1(depth)
        if scr is None:
            scr = scene.signature.scr
        scr_of = None
        if scr is not None:
            full = np.broadcast_to(np.asarray(scr, dtype=float).reshape(n_s, n_g), (n_s, n_g))
            scr_of = full.reshape(-1) if picked is None else full.reshape(-1)[picked]
        flat = cycles.reshape(-1)

        def target() -> np.ndarray:
            return np.tile(np.arange(n_g), n_s) if picked is None else g_of

        tasks = _in_view_tasks(
            flat,
            snr.reshape(-1) if noisy else None,
            None if ratio is None or not noisy else ratio.reshape(-1),
            scr_of,
            target,
            scene,
            flags,
        )
        if noisy:
            tasks = _seen_tasks(
                scene,
                tasks,
                None if ratio is None else ratio.reshape(-1),
                snr.reshape(-1),
                lambda: np.repeat(np.arange(n_s), n_g) if picked is None else s_of,
            )
        lost = np.isnan(r.reshape(-1))  # NaN geometry: NaN probabilities
        lost |= np.isnan(flat)
        where = slice(None) if picked is None else picked
        values = np.where(in_view.reshape(-1)[where], np.stack(tasks), 0.0)
        values[:, lost] = np.nan
        if picked is None:
            probabilities_ = values.reshape(len(TASKS), n_s, n_g)
        else:
            out = np.zeros((len(TASKS), size))
            out[:, picked] = values
            probabilities_ = out.reshape(len(TASKS), n_s, n_g)
        if sensors.quantisation_step is not None:  # contrasts below a digitiser's step
            probabilities_ = np.where(_below_step(scene, np), 0.0 * probabilities_, probabilities_)
        if sensors.groups:  # colour cameras: their bands are one look, not several
            fused = np.stack([np.asarray(fuse_groups(p, sensors.groups)) for p in probabilities_])
        else:
            fused = 1.0 - np.multiply.reduce(1.0 - probabilities_, axis=1)
    return in_view, probabilities_, fused


def footprint_scr(
    terrain: Any, range: Array, target_positions: Array, target_signal: Array, ifov: Array
) -> Array:
    """SCR of each pair from a terrain map at the sensor's ground footprint, (6.9)-(6.11).

    The window around each target weighs the classes
    (:meth:`targetacq.physics.terrain.TerrainMap.weights`); each class's variance is seen at the
    footprint ``R · IFOV`` (:func:`targetacq.physics.terrain.resolution_variance`); clutter and mean
    are the weighted sums. NumPy only (the map lookup is a host operation).

    Parameters
    ----------
    terrain : targetacq.core.compile.TerrainArrays
    range : numpy.ndarray ``(n_s, n_g, *batch)``
        [m].
    target_positions : numpy.ndarray ``(n_g, *batch, 3)``
        [m].
    target_signal : numpy.ndarray (n_s, n_g)
        [W/m²].
    ifov : numpy.ndarray (n_s,)
        [rad].

    Returns
    -------
    numpy.ndarray ``(n_s, n_g, *batch)``
    """
    from targetacq.physics.terrain import resolution_variance

    if not all(isinstance(a, np.ndarray) for a in (range, target_positions, target_signal, ifov)):
        raise ValueError(
            "terrain maps are evaluated with NumPy only: footprint_scr looks up the map per "
            "position on the host; give NumPy arrays (not JAX arrays or tracers), or a scenario "
            "whose clutter is an SCR (background.scr or clutter_std)"
        )
    batch = range.ndim - 2
    window = terrain.window.reshape((-1,) + (1,) * batch)
    weights = terrain.terrain.weights(
        target_positions[..., 0], target_positions[..., 1], window
    )  # (n_g, *batch, K)
    footprint = range * ifov.reshape((-1, 1) + (1,) * batch)
    lead = (slice(None), None) + (None,) * batch
    seen = resolution_variance(terrain.variance[lead], terrain.resolution, footprint[..., None])
    clutter = np.sqrt(np.sum(weights[None] * seen, axis=-1))
    mean = np.sum(weights[None] * terrain.mean[lead], axis=-1)
    signal = target_signal.reshape(target_signal.shape + (1,) * batch)
    return np.asarray(signal_to_clutter_ratio(signal, mean, clutter))
