"""The pure core: positions, pointing and headings → factors → probabilities → fused.

Every function here is a pure function of arrays and the records of
:mod:`targetacq.core.records`: no scenario objects, no files, no writes into its inputs, no
Python loops over sensors or targets. It is written against the array API, so NumPy arrays stay
NumPy and JAX arrays stay JAX (under ``jax.jit``, ``vmap`` and ``grad``; see
:mod:`targetacq._arrays` for the validation policy). The physics is in the topic modules; this
module wires them together:

1. geometry: line of sight, slant range, the outline seen and the critical dimension
   (:func:`targetacq.geometry.box_outline`, :func:`targetacq.geometry.critical_dimension_seen`),
   the field of view (:func:`targetacq.geometry.view_offsets`);
2. resolution: cycles on target ``N = d / (R · cycle)`` (§3.5; the cycle from the sensor type);
3. path: optical depth with segments and local clouds
   (:func:`targetacq.atmosphere.segmented_optical_depth`,
   :func:`targetacq.atmosphere.sphere_chord_length`), transmittance and the SNR of Eq. (7.7);
4. probabilities: the transforms with the noise model and, for detection in clutter, the
   Schmieder–Weathersby transform (:func:`task_probabilities`), ordered
   ``P_id <= P_rec <= P_det``, zero outside the field of view;
5. sensor-level fusion (8.4).

Shapes: ``sensor_positions`` ``(n_s, *batch, 3)``, ``target_positions`` ``(n_g, *batch, 3)``; every
result is ``(n_s, n_g, *batch)``, the fused ones ``(n_g, *batch)``. ``batch`` is the time axis of
:class:`targetacq.model.ModelChain` and empty for one step of :class:`targetacq.Simulation`.

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

from dataclasses import dataclass
from typing import Any

import numpy as np

from targetacq import _arrays, atmosphere, geometry, sensor_noise
from targetacq import transforms as _transforms
from targetacq.acquisition import ordered_probabilities
from targetacq.clutter import signal_to_clutter_ratio
from targetacq.core.records import SceneArrays, SensorArrays, pytree_record
from targetacq.fusion import fuse
from targetacq.noise import get_noise_model

__all__ = [
    "Factors",
    "Probabilities",
    "boresight",
    "evaluate",
    "factors",
    "footprint_scr",
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
        [Np].
    transmittance : array
        τ [1].
    snr : array
        Total SNR [dB]: the path's of Eq. (7.7) and, where a sensor has noise of its own, the
        sensor's (:func:`targetacq.sensor_noise.sensor_snr`), added in variance.
    scr : array or None
        Signal-to-clutter ratio, where a clutter measure is given.
    """

    range: Any
    critical_dimension: Any
    cycles: Any
    in_view: Any
    optical_depth: Any
    transmittance: Any
    snr: Any
    scr: Any


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
    sensor_positions: Any, sensors: SensorArrays, pointing: Any = None
) -> tuple[tuple[Any, Any, Any], Any]:
    """Boresight of each sensor and whether it is pointed.

    A sensor points at its ``look_at`` point, or at its azimuth and depression
    (:func:`targetacq.geometry.pointing_direction`); ``pointing`` (n_s, 2), where given and
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


def factors(
    scene: SceneArrays,
    sensor_positions: Any,
    target_positions: Any,
    headings: Any = None,
    pointing: Any = None,
    scr: Any = None,
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

    Returns
    -------
    Factors
    """
    sensors, targets, path = scene.sensors, scene.targets, scene.path
    xp, (s_pos, t_pos) = _arrays.arrays(
        sensor_positions, target_positions, names=_POSITIONS, broadcast=False
    )
    # Infinite positions have no geometry (inf − inf); NaN ones give NaN probabilities.
    for name, value in zip(_POSITIONS, (s_pos, t_pos), strict=True):
        _arrays.require_finite(name, value, xp, "m")
    batch = s_pos.ndim - 2
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
    critical = geometry.critical_dimension_seen(
        horizontal, vertical, _per_target(targets.visible_fraction, batch, xp)
    )
    with np.errstate(divide="ignore"):
        cycles = critical / (xp.maximum(rng, 1e-9) * _per_sensor(sensors.cycle, batch, xp))

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
    if scr is None and scene.signature.scr is not None:
        scr = xp.reshape(_arrays.as_float(scene.signature.scr, xp), (*scene.shape,) + (1,) * batch)
    tau = xp.exp(-depth)
    snr = atmosphere.snr_from_optical_depth(depth)
    if sensors.has_noise:
        # The area seen: the outline's horizontal side times the visible part of its height.
        area = horizontal * vertical * _per_target(targets.visible_fraction, batch, xp)
        pixels = sensor_noise.pixels_on_target(
            area, xp.maximum(rng, 1e-9), _per_sensor(sensors.ifov, batch, xp)
        )
        own = sensor_noise.sensor_snr(
            xp.reshape(
                _arrays.as_float(scene.signature.contrast, xp), (*scene.shape,) + (1,) * batch
            ),
            _per_sensor(sensors.noise_equivalent, batch, xp),
            tau,
            pixels,
        )
        snr = sensor_noise.combined_snr(snr, own)
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


def task_probabilities(cycles: Any, snr: Any, scr: Any, scene: SceneArrays) -> tuple[Any, Any, Any]:
    """Ordered probabilities of detection, recognition and identification of every pair.

    :func:`targetacq.acquisition.ordered_probabilities` with each target's N50s, hot-spot and
    moving flags and the scene's transform, noise model and clutter. With NumPy the targets that
    share a criterion go through together (scalar N50s, the fused TTPF path), so a target's
    numbers do not depend on which other targets are evaluated with it; with other array
    libraries the N50s are arrays along the target axis.

    Parameters
    ----------
    cycles : array ``(n_s, n_g, *batch)``
    snr : array or None
        [dB]; None for no path noise.
    scr : array or None
    scene : SceneArrays

    Returns
    -------
    detection, recognition, identification : array
    """
    xp, (n,) = _arrays.arrays(cycles)
    choices, targets = scene.choices, scene.targets
    batch = n.ndim - 2
    transform = _transforms.get_transform(choices.transform)
    options = dict(choices.options)
    noise = None if snr is None else get_noise_model(choices.noise_model)
    hot = np.asarray(targets.hot_spot, dtype=bool)
    moving = np.asarray(targets.moving, dtype=bool)

    def run(members: Any, n50: list[Any]) -> tuple[Any, Any, Any]:
        def pick(value: Any) -> Any:
            return value if value is None or members is None else value[:, members]

        def flag(values: np.ndarray) -> Any:  # one bool when all agree, else per target
            chosen = values if members is None else values[members]
            if chosen.size and bool(np.all(chosen == chosen[0])):
                return bool(chosen[0])
            return _per_target(xp.asarray(chosen), batch, xp)

        return ordered_probabilities(
            pick(n),
            n50,
            transform,
            options,
            scr=pick(scr),
            region=choices.region,
            hot_spot=flag(hot),
            moving=flag(moving),
            snr=pick(snr),
            noise=noise,
            motion=choices.motion,
            semantics=choices.semantics,
        )

    table = targets.n50
    if not (isinstance(table, np.ndarray) and isinstance(n, np.ndarray)):
        table_xp = _arrays.as_float(table, xp)
        return run(None, [_per_target(table_xp[:, k], batch, xp) for k in range(3)])
    rows, group = np.unique(table, axis=0, return_inverse=True)
    if rows.shape[0] <= 1:
        return run(None, [float(v) for v in rows[0]] if rows.size else [1.0, 1.0, 1.0])
    out = [np.empty(n.shape) for _ in TASKS]
    for k, row in enumerate(rows):
        members = np.flatnonzero(group.reshape(-1) == k)
        for whole, part in zip(out, run(members, [float(v) for v in row]), strict=True):
            whole[:, members] = part
    return out[0], out[1], out[2]


def probabilities(scene: SceneArrays, found: Factors) -> Probabilities:
    """Probabilities of every pair from its factors, zero outside the field of view, NaN where
    the geometry is NaN, and their sensor-level fusion (8.4)."""
    xp, (rng,) = _arrays.arrays(found.range)
    snr = found.snr if scene.path.attenuates or scene.sensors.has_noise else None
    tasks = task_probabilities(found.cycles, snr, found.scr, scene)
    unknown = xp.isnan(rng)
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
) -> tuple[Factors, Probabilities]:
    """Factors and probabilities of every pair (:func:`factors`, then :func:`probabilities`)."""
    found = factors(scene, sensor_positions, target_positions, headings, pointing, scr)
    return found, probabilities(scene, found)


def footprint_scr(
    terrain: Any, range: Any, target_positions: Any, target_signal: Any, ifov: Any
) -> Any:
    """SCR of each pair from a terrain map at the sensor's ground footprint, (6.9)-(6.11).

    The window around each target weighs the classes (:meth:`targetacq.terrain.TerrainMap.weights`);
    each class's variance is seen at the footprint ``R · IFOV``
    (:func:`targetacq.terrain.resolution_variance`); clutter and mean are the weighted sums.
    NumPy only (the map lookup is a host operation).

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
    from targetacq.terrain import resolution_variance

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
