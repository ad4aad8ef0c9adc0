"""The pairs of radars and laser radars in the array core, beside the imaging sensors'.

A scene with radars or laser radars (:attr:`SceneArrays.radar`, :attr:`SceneArrays.laser`) is
evaluated in two passes over the same geometry. :func:`targetacq.core.evaluation.factors` first
computes every row as an imager (range, critical dimension, field of view, path); then
:func:`active_factors` replaces the rows of the active sensors with their own factors, and
:func:`active_probabilities` gives every row its probabilities by its kind:

- **radar rows** (:mod:`targetacq.sensors.radar`): ``cycles`` holds the resolution cells on
  target ``d / sqrt(r_a r_r)`` (Eqs. (9.1), (9.2)); ``snr`` the radar equation's SNR in dB
  (``10 log10`` of the power ratio) with the rain's two-way attenuation; ``scr`` the power ratio
  ``σ / (σ⁰ A)``; ``optical_depth`` and ``transmittance`` the rain's, one way. Detection from the
  signal-to-interference ratio ``1/(1/SNR + 1/SCR)`` by the radar's detector model;
  recognition and identification ``P_d · TTPF(cells / cells50)``.
- **laser-radar rows** (:mod:`targetacq.sensors.laser_radar`): the imager's cycles; ``scr`` the
  3-D clutter measure; ``snr`` the atmosphere's Eq. (7.7) over the two-way optical depth and
  the receiver's SNR, added in variance; the imaging transforms then, as for any imager.
- **imaging rows**: unchanged.

Everything here is array-API code over static row indices, so it runs under ``jax.jit``.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import Any

import numpy as np

from targetacq.acquisition import transforms
from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.core.records import SceneArrays
from targetacq.physics import atmosphere, detector_noise, laser_radar_equation

__all__ = ["active_factors", "active_probabilities", "has_active"]


def has_active(scene: SceneArrays) -> bool:
    """Whether a scene has radars or laser radars."""
    return scene.radar is not None or scene.laser is not None


def _rows(value: Any, rows: tuple[int, ...], xp: Any) -> Any:
    return xp.take(value, xp.asarray(rows), axis=0)


def _per_row(value: Any, ndim: int, xp: Any) -> Any:
    """(n,) → (n, 1, …) against (n, n_g, *batch) of ``ndim`` axes."""
    return xp.reshape(value, (value.shape[0],) + (1,) * (ndim - 1))


def _per_pair(value: Any, rows: tuple[int, ...], ndim: int, xp: Any) -> Any:
    """The ``rows`` of a per-pair array ``(n_s, n_g)`` → ``(n, n_g, 1, …)`` of ``ndim`` axes."""
    part = _rows(_arrays.as_float(value, xp), rows, xp)
    return xp.reshape(part, part.shape + (1,) * (ndim - 2))


def _scatter(whole: Any, rows: tuple[int, ...], part: Any, xp: Any) -> Any:
    """``whole`` with its ``rows`` replaced by ``part`` (array-API: a stack of the rows)."""
    if isinstance(whole, np.ndarray):
        out = np.array(whole, dtype=np.result_type(whole, part), copy=True)
        out[list(rows)] = part
        return out
    index = {r: k for k, r in enumerate(rows)}
    return xp.stack(
        [part[index[r]] if r in index else whole[r] for r in range(whole.shape[0])], axis=0
    )


def _geometry(s_pos: Any, t_pos: Any, rows: tuple[int, ...], xp: Any) -> tuple[Any, Any]:
    """Slant range and the angle from nadir at the sensor (π/2 looking level) of ``rows``."""
    s = _rows(s_pos, rows, xp)
    x, y, z = (t_pos[None, ..., k] - s[:, None, ..., k] for k in range(3))
    horizontal = xp.sqrt(x * x + y * y)
    return xp.sqrt(horizontal * horizontal + z * z), xp.atan2(horizontal, -z)


def active_factors(
    scene: SceneArrays, found: Any, s_pos: Array, t_pos: Array, visible_fraction: Array = None
) -> Any:
    """The factors of a scene's radar and laser-radar rows in place of the imager's.

    Parameters
    ----------
    scene : SceneArrays
        With :attr:`SceneArrays.radar` or :attr:`SceneArrays.laser`.
    found : targetacq.core.Factors
        Every row computed as an imager.
    s_pos, t_pos : array
        The checked positions ``(n_s, *batch, 3)``, ``(n_g, *batch, 3)`` [m].
    visible_fraction : array, optional
        A visible fraction given for this call, checked and with the pairs' axes
        (:func:`targetacq.core.evaluation.check_visible_fraction`). A laser radar's relief SCR
        ``f h / sqrt(σ_z² + Δr²/12)`` is proportional to it: the compiled SCR (at the targets'
        own fraction) is scaled by the ratio of the two.

    Returns
    -------
    targetacq.core.Factors
    """
    from targetacq.physics import radar_equation as radar

    xp, (rng,) = _arrays.arrays(found.range)
    ndim = rng.ndim
    cycles, snr, depth, tau = found.cycles, found.snr, found.optical_depth, found.transmittance
    scr = found.scr
    if scr is None:
        scr = xp.full(rng.shape, xp.nan)
    else:
        scr = xp.broadcast_to(_arrays.as_float(scr, xp), rng.shape)
    crit = found.critical_dimension
    if scene.radar is not None:
        arrays, rows = scene.radar, scene.radar.rows
        r, nadir = _geometry(s_pos, t_pos, rows, xp)
        r = xp.maximum(r, 1e-9)
        along = radar.along_track_resolution(r, _per_row(arrays.beamwidth, ndim, xp))
        across = radar.range_resolution(_per_row(arrays.pulse_length, ndim, xp), nadir)
        cells = radar.cells_on_target(_rows(crit, rows, xp), along, across)
        rain = _per_row(arrays.extinction, ndim, xp) * r
        one_way = xp.exp(-rain)
        rcs = _per_pair(scene.signature.target, rows, ndim, xp)  # the radar's signal: σ
        with np.errstate(divide="ignore"):
            power = radar.radar_snr(r, rcs, _per_row(arrays.constant, ndim, xp), one_way)
            ratio = radar.signal_to_clutter(
                rcs, _per_row(arrays.sigma0, ndim, xp), radar.clutter_area(along, across)
            )
            decibels = 10.0 * xp.log10(power)
        cycles = _scatter(cycles, rows, cells, xp)
        snr = _scatter(snr, rows, decibels, xp)
        scr = _scatter(scr, rows, ratio, xp)
        depth = _scatter(depth, rows, rain, xp)
        tau = _scatter(tau, rows, one_way, xp)
    if scene.laser is not None:
        laser, rows = scene.laser, scene.laser.rows
        one_way_depth = _rows(depth, rows, xp)
        reflectance = _per_pair(scene.signature.target, rows, ndim, xp)  # its signal: ρ
        received = laser_radar_equation.received_power(
            xp.maximum(_rows(rng, rows, xp), 1e-9),
            _per_row(laser.power, ndim, xp),
            reflectance,
            _per_row(laser.aperture_area, ndim, xp),
            _rows(tau, rows, xp),
            _per_row(laser.efficiency, ndim, xp),
        )
        with np.errstate(divide="ignore", over="ignore"):
            path = atmosphere.snr_from_optical_depth(
                laser_radar_equation.two_way_optical_depth(one_way_depth)
            )
            own = laser_radar_equation.laser_snr(received, _per_row(laser.nep, ndim, xp))
            total = detector_noise.combined_snr(path, own)
        snr = _scatter(snr, rows, total, xp)
        seen = _per_pair(scene.signature.scr, rows, ndim, xp)
        if visible_fraction is not None:
            given = visible_fraction
            if given.shape[0] > 1:
                given = _rows(given, rows, xp)
            own = xp.reshape(
                _arrays.as_float(scene.targets.visible_fraction, xp),
                (1, -1) + (1,) * (ndim - 2),
            )
            seen = seen * (given / own)
        scr = _scatter(scr, rows, xp.broadcast_to(seen, (len(rows), *rng.shape[1:])), xp)
    return dataclasses.replace(
        found, cycles=cycles, snr=snr, scr=scr, optical_depth=depth, transmittance=tau
    )


def _radar_tasks(scene: SceneArrays, found: Any, xp: Any) -> tuple[Any, Any, Any]:
    """Detection, recognition and identification of the radar rows."""
    from targetacq.physics import radar_equation as radar

    arrays = scene.radar
    assert arrays is not None
    rows = arrays.rows
    ndim = found.range.ndim
    snr = 10.0 ** (_rows(found.snr, rows, xp) / 10.0)
    scr = _rows(found.scr, rows, xp)
    with np.errstate(divide="ignore"):
        interference = 1.0 / (1.0 / snr + 1.0 / scr)
    interference = xp.where(xp.isnan(interference), interference, xp.maximum(interference, 0.0))
    detection = []
    for k, method in enumerate(arrays.detectors):
        detection.append(
            radar.detection_probability(
                interference[k], arrays.false_alarm[k], arrays.pulses[k], method=method
            )
        )
    p_d = xp.stack([_arrays.as_float(p, xp) for p in detection], axis=0)
    cells = _rows(found.cycles, rows, xp)
    out = [p_d]
    for task in range(2):
        n50 = _per_row(arrays.cells50[:, task], ndim, xp)
        out.append(p_d * transforms.ttpf(xp.where(xp.isnan(cells), 0.0, cells), n50))
    nan = xp.isnan(cells)
    return out[0], xp.where(nan, xp.nan, out[1]), xp.where(nan, xp.nan, out[2])


def active_probabilities(
    scene: SceneArrays,
    found: Any,
    task_probabilities: Callable[..., tuple[Any, Any, Any]],
    moving: Any = None,
    cues: Any = None,
) -> tuple[Any, Any, Any]:
    """Every row's ordered probabilities by its kind, before the field of view.

    The imaging and laser-radar rows go through ``task_probabilities`` (the imagers' own,
    :func:`targetacq.core.evaluation.task_probabilities`, which calls this module: passed in, so
    that this module does not import it back) in groups of the same clutter (an SCR or none)
    and noise (an SNR, or none where neither the path nor the sensor adds noise); the radar rows
    through :func:`_radar_tasks`.

    ``task_probabilities(cycles, snr, scr, scene, moving=moving, rows=rows, cues=cues)``: the
    imagers' ordered probabilities of the sensor rows ``rows``. ``moving``: the targets' moving
    flags for this call (default their own), for the imaging and laser-radar rows. ``cues``:
    the pairs' graded cues (:class:`targetacq.core.evaluation.GradedCues`, with
    ``rows(rows, xp)``), or None.

    Returns
    -------
    detection, recognition, identification : array ``(n_s, n_g, *batch)``
    """
    xp, (_rng,) = _arrays.arrays(found.range)
    n_s = scene.shape[0]
    radar_rows = () if scene.radar is None else scene.radar.rows
    laser_rows = () if scene.laser is None else scene.laser.rows
    clutter = scene.signature.rows_with_clutter(n_s, found.scr is not None)
    noisy = scene.path.attenuates or scene.sensors.has_noise
    groups: dict[tuple[bool, bool], list[int]] = {}
    for row in range(n_s):
        if row not in radar_rows:
            groups.setdefault((clutter[row], noisy or row in laser_rows), []).append(row)
    parts: dict[int, tuple[Any, Any, Any]] = {}
    for (has_scr, has_snr), members in groups.items():
        rows = tuple(members)
        tasks = task_probabilities(
            _rows(found.cycles, rows, xp),
            _rows(found.snr, rows, xp) if has_snr else None,
            _rows(found.scr, rows, xp) if has_scr else None,
            scene,
            moving=moving,
            rows=rows,
            cues=None if cues is None else cues.rows(rows, xp),
        )
        for k, row in enumerate(rows):
            parts[row] = (tasks[0][k], tasks[1][k], tasks[2][k])
    if radar_rows:
        tasks = _radar_tasks(scene, found, xp)
        for k, row in enumerate(radar_rows):
            parts[row] = (tasks[0][k], tasks[1][k], tasks[2][k])
    return tuple(
        xp.stack([_arrays.as_float(parts[row][t], xp) for row in range(n_s)], axis=0)
        for t in range(3)
    )
