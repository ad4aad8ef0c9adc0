"""The numba engine's kernels for one time: every sensor–target pair of a single batch in one call.

A step of the step API (:class:`targetacq.Simulation`) evaluates positions ``(n_s, 3)`` and
``(n_g, 3)``: a batch of one. The kernels of :mod:`targetacq.core.engines.numba_kernels` loop over
the batch inside each pair, which leaves nothing to vectorise there; the kernels here take the
targets as the inner loop instead:

- :func:`_pair_factors`: per sensor, its frame (:func:`targetacq.physics.geometry.sensor_frame`'s
  arithmetic, in the same order, so that the field-of-view test is the NumPy core's to the last
  bit), then passes over its targets: range, outline, critical dimension, cycles, field of
  view, optical depth (segments, clouds), transmittance and SNR;
- :func:`_pair_probabilities`: the pairs in view (or of unknown geometry) gathered into one list,
  then each one's noisy N, the three task curves, detection in clutter, of hot spots and of
  moving targets, the semantics; zero elsewhere; and the sensor-level fusion (8.4);
- :func:`_pair_step`: both, in one call (the bound engine's ``step``).

Each pair's arithmetic is that of the per-element functions of
:mod:`targetacq.core.engines.numba_kernels` (the same order of operations), so the numbers equal the
NumPy core's to about 1e-15 relative and exactly on the field of view. Importing this module
imports numba.
"""

from __future__ import annotations

import math

import numpy as np
from numba import types

from targetacq.core.engines._simd import exp, inline, kernel, log, readonly, writable
from targetacq.core.engines.numba_kernels import (
    MOTION_ALWAYS,
    NOISE_NONE_GIVEN,
    REGION_NONE,
    SEMANTICS_NESTED,
    TRANSFORM_TTPF,
    box_outline,
    chord,
    clip,
    combined_snr,
    contrast_snr,
    curve,
    curve_rows,
    effective_scr,
    maximum,
    minimum,
    noise_factor,
    noisy_cycles,
    path_snr,
    seen_probability,
    sensor_snr,
    sw_blend,
    sw_scaled,
    table_curve,
    ttpf,
)

__all__ = ["SENSOR_COLUMNS"]

# Columns of the sensor table (one row per sensor).
CYCLE, IFOV, TAN_H, TAN_V, EXTINCTION, NOISE_EQUIVALENT, VIEWING, BY_POINT = range(8)
AIM = 8  # 8, 9, 10: the look-at point (BY_POINT) or the boresight direction
PATH_CONTRAST = 11  # σ_path of the contrast SNR law [W/m²]; −1: the sonesson law
SENSOR_COLUMNS = 12
"""Columns of the sensor table :func:`_pair_factors` reads: cycle [rad], IFOV [rad], the half
tangents, extinction [Np/m], noise-equivalent signal [W/m²], 1 where pointed with a field of
view, 1 where pointed at a point, the point [m] or the boresight direction, and ``σ_path`` of
the contrast SNR law (−1 for the sonesson law)."""

# Status codes of the kernels: 0, or the input that holds an infinite value.
OK, INFINITE_SENSOR, INFINITE_TARGET = 0, 1, 2


@inline
def _frame(fx, fy, fz, frame):
    """The sensor frame of :func:`targetacq.physics.geometry.sensor_frame` into ``frame`` (8,): the
    unit boresight, the horizontal right, the up; the same operations in the same order."""
    square = fx * fx + fy * fy + fz * fz
    norm = math.sqrt(square if square > 0.0 else 1.0)
    fx, fy, fz = fx / norm, fy / norm, fz / norm
    square = fx * fx + fy * fy
    horizontal = math.sqrt(square if square > 0.0 else 1.0)
    level = square > 0.0 and horizontal > 1e-12
    safe = horizontal if level else 1.0
    rx = fy / safe if level else 1.0
    ry = -fx / safe if level else 0.0
    frame[0], frame[1], frame[2] = fx, fy, fz
    frame[3], frame[4] = rx, ry
    frame[5], frame[6], frame[7] = ry * fz, -rx * fz, rx * fy - ry * fx


_FACTOR_INPUTS = (
    *(readonly(2), readonly(2), readonly(2), readonly(2), readonly(2)),  # positions … visible
    *(readonly(2), readonly(1), readonly(2), readonly(2), readonly(2)),  # sensors … contrast
    types.boolean,  # has_noise
)
_PROBABILITY_CONSTANTS = (
    *(readonly(2), readonly(2), readonly(1, types.boolean), readonly(1, types.boolean)),  # targets
    readonly(1, types.int64),  # settings
)
_TABLES = (readonly(1), readonly(3), readonly(1), readonly(3), readonly(1), readonly(1))


@kernel(*_FACTOR_INPUTS, writable(3), writable(2, types.boolean), returns=types.int64)
def _pair_factors(
    sensor_positions,  # (n_s, 3)
    target_positions,  # (n_g, 3)
    sin_cos,  # (2, n_g): sine and cosine of each target's heading
    dimensions,  # (3, n_g): length, width, height
    visible_fraction,  # (1 or n_s, n_g)
    sensors,  # (n_s, SENSOR_COLUMNS)
    segment_length,  # (J,)
    segment_extinction,  # (n_s, J)
    clouds,  # (C, 5): centre (3), radius, extinction
    contrast,  # (n_s, n_g)
    has_noise,  # bool
    out,  # (6, n_s, n_g): range, critical dimension, cycles, optical depth, tau, SNR
    in_view,  # (n_s, n_g) bool
):
    """The factors of every pair, the targets as the inner loop; returns :data:`OK` or the code
    of the positions that hold an infinite value (nothing is computed then)."""
    n_s, n_g = in_view.shape
    for s in range(n_s):
        for k in range(3):
            if abs(sensor_positions[s, k]) == math.inf:
                return INFINITE_SENSOR
    for g in range(n_g):
        for k in range(3):
            if abs(target_positions[g, k]) == math.inf:
                return INFINITE_TARGET
    tx, ty, tz = np.empty(n_g), np.empty(n_g), np.empty(n_g)
    for g in range(n_g):  # the targets' components apart: unit strides below
        tx[g], ty[g], tz[g] = target_positions[g, 0], target_positions[g, 1], target_positions[g, 2]
    area = np.empty(n_g)
    frame = np.empty(8)
    per_sensor = visible_fraction.shape[0] > 1
    for s in range(n_s):
        sx, sy, sz = sensor_positions[s, 0], sensor_positions[s, 1], sensor_positions[s, 2]
        ax, ay, az = sensors[s, AIM], sensors[s, AIM + 1], sensors[s, AIM + 2]
        if sensors[s, BY_POINT] == 1.0:  # toward the point from where the sensor is
            _frame(ax - sx, ay - sy, az - sz, frame)
        else:
            _frame(ax, ay, az, frame)
        f0, f1, f2, f3, f4, f5, f6, f7 = (
            frame[0],
            frame[1],
            frame[2],
            frame[3],
            frame[4],
            frame[5],
            frame[6],
            frame[7],
        )
        sensor_cycle, ifov_s = sensors[s, CYCLE], sensors[s, IFOV]
        tan_h, tan_v = sensors[s, TAN_H], sensors[s, TAN_V]
        gamma, noise_s = sensors[s, EXTINCTION], sensors[s, NOISE_EQUIVALENT]
        viewing = sensors[s, VIEWING] == 1.0
        sv = s if per_sensor else 0
        # 1. Geometry: range, outline, critical dimension, cycles, field of view.
        for g in range(n_g):
            x, y, z = tx[g] - sx, ty[g] - sy, tz[g] - sz
            rng, horizontal, vertical = box_outline(
                x,
                y,
                z,
                sin_cos[0, g],
                sin_cos[1, g],
                dimensions[0, g],
                dimensions[1, g],
                dimensions[2, g],
            )
            visible = visible_fraction[sv, g]
            critical = minimum(horizontal, vertical * visible)
            out[0, s, g] = rng
            out[1, s, g] = critical
            out[2, s, g] = critical / (maximum(rng, 1e-9) * sensor_cycle)
            area[g] = horizontal * vertical * visible
            ahead = x * f0 + y * f1 + z * f2
            right = x * f3 + y * f4
            up = x * f5 + y * f6 + z * f7
            in_fov = ahead > 0.0 and abs(right) <= tan_h * ahead and abs(up) <= tan_v * ahead
            in_view[s, g] = (in_fov or not viewing) and rng == rng
            out[3, s, g] = gamma * rng
        # 2. The optical depth: segments laid from the sensor outward, then clouds.
        start = 0.0
        for j in range(segment_length.shape[0]):
            stretch, more = segment_length[j], segment_extinction[s, j] - gamma
            for g in range(n_g):
                inside = clip(out[0, s, g] - start, 0.0, stretch)
                out[3, s, g] = out[3, s, g] + more * inside
            start = start + stretch
        for c in range(clouds.shape[0]):
            cx, cy, cz = clouds[c, 0], clouds[c, 1], clouds[c, 2]
            radius, cloud = clouds[c, 3], clouds[c, 4]
            for g in range(n_g):
                crossed = chord(sx, sy, sz, tx[g], ty[g], tz[g], cx, cy, cz, radius)
                out[3, s, g] = out[3, s, g] + cloud * crossed
        # 3. Transmittance and SNR (the contrast law's, or the path's and the sensor's own added
        # in variance; a row without a noise of its own: the path's).
        sigma_s = sensors[s, PATH_CONTRAST]
        if has_noise and sigma_s >= 0.0 and noise_s != 0.0:
            for g in range(n_g):
                depth = out[3, s, g]
                tau = exp(-depth)
                footprint = maximum(out[0, s, g], 1e-9) * ifov_s
                pixels = area[g] / (footprint * footprint)
                out[4, s, g] = tau
                out[5, s, g] = contrast_snr(contrast[s, g], noise_s, sigma_s, tau, pixels)
        elif has_noise and sigma_s < 0.0:
            for g in range(n_g):
                depth = out[3, s, g]
                tau = exp(-depth)
                footprint = maximum(out[0, s, g], 1e-9) * ifov_s
                pixels = area[g] / (footprint * footprint)
                own = sensor_snr(contrast[s, g], noise_s, tau, pixels)
                out[4, s, g] = tau
                out[5, s, g] = combined_snr(path_snr(depth), own)
        else:
            for g in range(n_g):
                depth = out[3, s, g]
                out[4, s, g] = exp(-depth)
                out[5, s, g] = path_snr(depth)
    return OK


# Rows of the probabilities kernel's work space (one column per pair of a chunk).
_N, _SNR, _SCR, _NOISY, _DET, _REC, _IDE = range(7)
_D50, _R50, _I50, _LD, _LR, _LI, _LOW50, _LLOW = range(7, 15)
_X, _U, _RATIO, _CURVES = 15, 16, 17, 18  # 18, 19, 20: Table 3.5's three curves
_ROWS = 21
CHUNK = 256
"""Pairs per pass of :func:`_pair_probabilities`: its work space stays in the CPU cache."""


@kernel(
    *(readonly(2), readonly(2), readonly(2), readonly(2, types.boolean), readonly(2)),  # factors
    *_PROBABILITY_CONSTANTS,
    types.boolean,  # has_scr
    *_TABLES,
    *(writable(3), writable(2)),  # out
)
def _pair_probabilities(
    cycles,  # (n_s, n_g)
    snr,  # (n_s, n_g)
    scr,  # (n_s, n_g)
    in_view,  # (n_s, n_g) bool
    rng,  # (n_s, n_g)
    n50,  # (n_g, 3)
    log_n50,  # (n_g, 5): ln N50 of the three tasks, the low-clutter N50 of motion, its ln
    hot_spot,  # (n_g,) bool
    moving,  # (n_g,) bool
    settings,  # int64 (7,): noise, combines, transform, region, motion, semantics, (unused)
    has_scr,  # bool
    noise_anchors,  # (4,)
    tables,  # (3, 4, CURVE_POINTS)
    table_reference,  # (3,)
    sw,  # (3, 4, CURVE_POINTS)
    sw_constants,  # (4,)
    thresholds,  # (n_s,): k of each row's detection threshold (−inf: none)
    out,  # (3, n_s, n_g): detection, recognition, identification
    fused,  # (3, n_g)
):
    """The probabilities of every pair and their fusion over the sensors.

    The pairs in view or of unknown geometry (NaN range or cycles) are gathered, in order, into
    a list; it is run in chunks of :data:`CHUNK` pairs, each step a pass over the chunk that
    vectorises (each pair's own N50s read from the work space): the noisy N, the three task
    curves, detection in clutter (:func:`~targetacq.core.engines.numba_kernels.curve_rows`), hot
    spots and moving targets, then the semantics. Every other pair is zero.
    """
    n_s, n_g = in_view.shape
    noise, combines, transform = settings[0], settings[1] == 1, settings[2]
    region, motion, nested = settings[3], settings[4], settings[5] == SEMANTICS_NESTED
    clutter = has_scr or region >= 0
    with_noise = noise != NOISE_NONE_GIVEN
    read_effective = with_noise and combines and has_scr
    region_read = REGION_NONE if has_scr else region  # an SCR given wins over the region
    for g in range(n_g):
        fused[0, g] = 1.0
        fused[1, g] = 1.0
        fused[2, g] = 1.0
    picked = np.empty(n_s * n_g, dtype=np.int64)
    count = 0
    for s in range(n_s):
        for g in range(n_g):
            out[0, s, g] = 0.0
            out[1, s, g] = 0.0
            out[2, s, g] = 0.0
            n = cycles[s, g]
            if in_view[s, g] or rng[s, g] != rng[s, g] or n != n:
                picked[count] = s * n_g + g
                count += 1
    work = np.empty((_ROWS, CHUNK))
    target = np.empty(CHUNK, dtype=np.int64)
    for first in range(0, count, CHUNK):
        m = min(CHUNK, count - first)
        special = False
        for k in range(m):
            i = picked[first + k]
            s = i // n_g
            g = i - s * n_g
            target[k] = g
            work[_N, k] = cycles[s, g]
            work[_SNR, k] = snr[s, g]
            work[_SCR, k] = scr[s, g] if has_scr else math.nan
            work[_D50, k], work[_R50, k], work[_I50, k] = n50[g, 0], n50[g, 1], n50[g, 2]
            work[_LD, k], work[_LR, k], work[_LI, k] = log_n50[g, 0], log_n50[g, 1], log_n50[g, 2]
            work[_LOW50, k], work[_LLOW, k] = log_n50[g, 3], log_n50[g, 4]
            special = special or hot_spot[g] or moving[g]
        # 1. The noisy N and the curves of the three tasks.
        if with_noise:
            for k in range(m):
                f = noise_factor(work[_SNR, k], noise, noise_anchors)
                work[_NOISY, k] = noisy_cycles(work[_N, k], f)
        else:
            for k in range(m):
                work[_NOISY, k] = work[_N, k]
        if transform == TRANSFORM_TTPF:
            for k in range(m):
                n = work[_NOISY, k]
                log_n = log(n)
                work[_DET, k] = ttpf(n, log_n, work[_D50, k], work[_LD, k])
                work[_REC, k] = ttpf(n, log_n, work[_R50, k], work[_LR, k])
                work[_IDE, k] = ttpf(n, log_n, work[_I50, k], work[_LI, k])
        else:
            for k in range(m):
                n = work[_NOISY, k]
                work[_DET, k] = table_curve(n, work[_D50, k], 0, tables, table_reference)
                work[_REC, k] = table_curve(n, work[_R50, k], 1, tables, table_reference)
                work[_IDE, k] = table_curve(n, work[_I50, k], 2, tables, table_reference)
        # 2. Detection in clutter (Table 3.5's curves read at the scaled N, blended in SCR).
        if clutter:
            for k in range(m):
                c = work[_SCR, k]
                ratio = effective_scr(c, work[_SNR, k]) if read_effective else c
                n = work[_N, k] if read_effective else work[_NOISY, k]
                scaled, log_scaled = sw_scaled(n, work[_D50, k], ratio, region_read, sw_constants)
                work[_X, k], work[_U, k], work[_RATIO, k] = scaled, log_scaled, ratio
            curve_rows(sw, work, _X, _U, _CURVES, m)
            for k in range(m):
                seen = sw_blend(
                    work[_CURVES, k],
                    work[_CURVES + 1, k],
                    work[_CURVES + 2, k],
                    work[_RATIO, k],
                    region_read,
                    sw_constants,
                )
                work[_DET, k] = minimum(seen, work[_DET, k])
        # 3. Hot spots and moving targets (pair by pair: only where a target is either).
        if special:
            for k in range(m):
                g = target[k]
                hot, move = hot_spot[g], moving[g]
                if not (hot or move):
                    continue
                noisy = work[_NOISY, k]
                scaled = noisy * (sw_constants[0] / work[_D50, k])
                found = curve(scaled, log(scaled), sw, 0) if hot else math.nan
                if move:
                    if motion == MOTION_ALWAYS:
                        go = noisy if noisy != noisy else 1.0
                    elif transform == TRANSFORM_TTPF:
                        go = ttpf(noisy, log(noisy), work[_LOW50, k], work[_LLOW, k])
                    else:
                        go = table_curve(noisy, work[_LOW50, k], 0, tables, table_reference)
                    found = go if found != found else maximum(found, go)
                kept = found != found and work[_N, k] == work[_N, k]
                work[_DET, k] = work[_DET, k] if kept else found
        # 4. The semantics, the field of view, unknown geometry, and the misses.
        for k in range(m):
            i = picked[first + k]
            s = i // n_g
            g = i - s * n_g
            det, rec, ide = work[_DET, k], work[_REC, k], work[_IDE, k]
            if nested:
                rec = minimum(rec, det)
                ide = minimum(ide, rec)
            else:
                rec = det * rec
                ide = rec * ide
            if thresholds[s] > -math.inf:
                above = seen_probability(work[_SNR, k], thresholds[s])
                det, rec, ide = det * above, rec * above, ide * above
            unknown = rng[s, g] != rng[s, g] or work[_N, k] != work[_N, k]
            seen = in_view[s, g]
            det = math.nan if unknown else (det if seen else 0.0)
            rec = math.nan if unknown else (rec if seen else 0.0)
            ide = math.nan if unknown else (ide if seen else 0.0)
            out[0, s, g] = det
            out[1, s, g] = rec
            out[2, s, g] = ide
            fused[0, g] *= 1.0 - det
            fused[1, g] *= 1.0 - rec
            fused[2, g] *= 1.0 - ide
    for k in range(3):
        for g in range(n_g):
            fused[k, g] = 1.0 - fused[k, g]


@kernel(
    *_FACTOR_INPUTS,
    *(readonly(2), types.boolean),  # scr
    *_PROBABILITY_CONSTANTS,
    *_TABLES,
    *(writable(3), writable(2, types.boolean), writable(3), writable(2)),  # work space, out
    returns=types.int64,
)
def _pair_step(
    sensor_positions,
    target_positions,
    sin_cos,
    dimensions,
    visible_fraction,
    sensors,
    segment_length,
    segment_extinction,
    clouds,
    contrast,
    has_noise,
    scr,
    has_scr,
    n50,
    log_n50,
    hot_spot,
    moving,
    settings,
    noise_anchors,
    tables,
    table_reference,
    sw,
    sw_constants,
    thresholds,
    factors,  # (6, n_s, n_g) work space: the factors of _pair_factors
    in_view,  # (n_s, n_g) bool
    out,  # (3, n_s, n_g)
    fused,  # (3, n_g)
):
    """:func:`_pair_factors` then :func:`_pair_probabilities`, in one call; the status of
    :func:`_pair_factors`."""
    status = _pair_factors(
        sensor_positions,
        target_positions,
        sin_cos,
        dimensions,
        visible_fraction,
        sensors,
        segment_length,
        segment_extinction,
        clouds,
        contrast,
        has_noise,
        factors,
        in_view,
    )
    if status != OK:
        return status
    _pair_probabilities(
        factors[2],
        factors[5],
        scr,
        in_view,
        factors[0],
        n50,
        log_n50,
        hot_spot,
        moving,
        settings,
        has_scr,
        noise_anchors,
        tables,
        table_reference,
        sw,
        sw_constants,
        thresholds,
        out,
        fused,
    )
    return OK
