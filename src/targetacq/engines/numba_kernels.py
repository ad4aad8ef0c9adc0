"""The numba engine's kernels: the core's pipeline, element by element, fused into two loops.

Each function here is the scalar form of a NumPy kernel of the topic modules, with the same
arithmetic in the same order where it matters (the field-of-view test is exact), so that the
numba engine gives the NumPy engine's numbers to about 1e-15 relative:

================================  ==========================================================
here                              NumPy kernel
================================  ==========================================================
:func:`box_outline`               :func:`targetacq.geometry.box_outline`
:func:`chord`                     :func:`targetacq.atmosphere.sphere_chord_length`
:func:`path_snr`                  :func:`targetacq.atmosphere.snr_from_optical_depth`
:func:`sensor_snr`                :func:`targetacq.sensor_noise.sensor_snr`
:func:`combined_snr`              :func:`targetacq.sensor_noise.combined_snr` (two SNRs)
:func:`noise_factor`              the noise models of :data:`targetacq.noise.NOISE_MODELS`
:func:`effective_scr`             :func:`targetacq.noise.effective_scr`
:func:`ttpf`                      :func:`targetacq.transforms.ttpf` (``ln N`` given)
:func:`curve`                     a table curve of :mod:`targetacq.transforms` (C2NVEO,
                                  Table 3.5), piecewise linear in ``log N``
:func:`schmieder_weathersby`      :func:`targetacq.transforms.schmieder_weathersby`
================================  ==========================================================

:func:`factors_kernel` and :func:`probabilities_kernel` are the two loops (sensors, targets,
batch) of :mod:`targetacq.engines.numba_engine`, which prepares their inputs. Importing this
module imports numba (the ``fast`` extra).
"""

from __future__ import annotations

import math

import numpy as np

from targetacq.engines import _simd
from targetacq.engines._simd import compiled, inline

# Codes of the model choices inside the kernels (numba compiles integers, not registry names).
NOISE_NONE_GIVEN, NOISE_VARIANCE_SUM, NOISE_CLUTTER_ANALOGUE, NOISE_IGNORED = 0, 1, 2, 3
TRANSFORM_TTPF, TRANSFORM_TABLE = 0, 1
MOTION_LOW_CLUTTER, MOTION_ALWAYS = 0, 1
SEMANTICS_NESTED, SEMANTICS_CONDITIONAL = 0, 1
REGION_NONE = -1  # else the index of the region's curve: 0 low, 1 medium, 2 high


_LN10 = math.log(10.0)
_TTPF_LIMIT = 700.0


@inline
def minimum(a, b):
    """``numpy.minimum`` of two floats: NaN if either is NaN."""
    return a if (a < b or a != a) else b


@inline
def maximum(a, b):
    """``numpy.maximum`` of two floats: NaN if either is NaN."""
    return a if (a > b or a != a) else b


@inline
def clip(x, low, high):
    """``numpy.clip``: NaN stays NaN."""
    return minimum(maximum(x, low), high)


@inline
def power_of_ten(x):
    """``10 ** x``."""
    return math.exp(x * _LN10)


# --------------------------------------------------------------------------------------------
# Factors
# --------------------------------------------------------------------------------------------


@inline
def box_outline(x, y, z, sin_h, cos_h, length, width, height):
    """Range and the outline (horizontal, vertical side) of a box seen along (x, y, z) [m]."""
    rho = math.sqrt(x * x + y * y)
    rng = math.sqrt(rho * rho + z * z)
    along = abs(x * sin_h + y * cos_h)
    across = abs(x * cos_h - y * sin_h)
    flat = rho == 0.0
    safe = 1.0 if flat else rho
    horizontal = (length * across + width * along) / safe
    vertical = (height * rho + (length * along + width * across) / safe * abs(z)) / (
        rng if rng > 0.0 else 1.0
    )
    if flat:
        horizontal = length
        vertical = width if rng > 0.0 else height
    return rng, horizontal, vertical


@inline
def chord(ax, ay, az, bx, by, bz, cx, cy, cz, radius):
    """Length of the segment a → b inside the sphere of centre c [m]."""
    dx, dy, dz = bx - ax, by - ay, bz - az
    length = math.sqrt(dx * dx + dy * dy + dz * dz)
    safe = length if length > 0.0 else 1.0
    ux, uy, uz = dx / safe, dy / safe, dz / safe
    mx, my, mz = ax - cx, ay - cy, az - cz
    bq = mx * ux + my * uy + mz * uz
    cq = (mx * mx + my * my + mz * mz) - radius * radius
    disc = bq * bq - cq
    root = math.sqrt(disc if disc > 0.0 else 1.0)
    t0 = clip(-bq - root, 0.0, length)
    t1 = clip(-bq + root, 0.0, length)
    out = t1 - t0 if (disc > 0.0 and length > 0.0) else 0.0 * length
    return length if length != length else out


@inline
def path_snr(depth):
    """SNR of Eq. (7.7) from the optical depth [dB]."""
    inner = depth > 0.0 and depth < math.inf
    safe = depth if inner else 1.0
    snr = 20.0 * (-safe / _LN10 - math.log10(-math.expm1(-safe)))
    snr = math.inf if depth <= 0.0 else snr
    snr = -math.inf if depth == math.inf else snr
    return depth if depth != depth else snr


@inline
def sensor_snr(contrast, noise_equivalent, tau, pixels):
    """The sensor's own SNR of a target [dB], ``20 math.log10(τ |C| g(n) / NEC)``."""
    gain = math.sqrt(maximum(pixels, 1.0)) if pixels >= 1.0 else pixels
    signal = tau * abs(contrast) * gain
    quiet = noise_equivalent == 0.0
    ratio = math.inf if quiet else signal / noise_equivalent
    db = 20.0 * math.log10(ratio)
    unknown = contrast != contrast or noise_equivalent != noise_equivalent
    unknown = unknown or tau != tau or pixels != pixels
    return math.nan if unknown else db


@inline
def combined_snr(a, b):
    """Two independent noises added in variance [dB]."""
    total = 0.0 + power_of_ten(-a / 10.0) + power_of_ten(-b / 10.0)
    db = -10.0 * math.log10(total)
    return math.nan if (a != a or b != b) else db


@inline
def path_snr_vector(depth):
    """:func:`path_snr` with the vectorisable exponential and logarithm."""
    inner = depth > 0.0 and depth < math.inf
    safe = depth if inner else 1.0
    snr = 20.0 * (-safe / _LN10 - _simd.log10(-_simd.expm1(-safe)))
    snr = math.inf if depth <= 0.0 else snr
    snr = -math.inf if depth == math.inf else snr
    return depth if depth != depth else snr


@inline
def sensor_snr_vector(contrast, noise_equivalent, tau, pixels):
    """:func:`sensor_snr` with the vectorisable logarithm."""
    gain = math.sqrt(maximum(pixels, 1.0)) if pixels >= 1.0 else pixels
    signal = tau * abs(contrast) * gain
    quiet = noise_equivalent == 0.0
    ratio = math.inf if quiet else signal / (1.0 if quiet else noise_equivalent)
    db = 20.0 * _simd.log10(ratio)
    unknown = contrast != contrast or noise_equivalent != noise_equivalent
    unknown = unknown or tau != tau or pixels != pixels
    return math.nan if unknown else db


@inline
def combined_snr_vector(a, b):
    """:func:`combined_snr` with the vectorisable exponential and logarithm."""
    total = 0.0 + _simd.exp(-a * (_LN10 / 10.0)) + _simd.exp(-b * (_LN10 / 10.0))
    db = -10.0 * _simd.log10(total)
    return math.nan if (a != a or b != b) else db


@compiled
def factors_kernel(
    sensor_positions,  # (n_s, B, 3)
    target_positions,  # (n_g, B, 3)
    sin_heading,  # (n_g, B)
    cos_heading,  # (n_g, B)
    dimensions,  # (n_g, 3)
    visible_fraction,  # (n_g,)
    cycle,  # (n_s,)
    ifov,  # (n_s,)
    frame,  # (n_s, B, 8): forward (3), right (2), up (3), unit, in east-north-up
    half_tangents,  # (n_s, 2)
    pointed,  # (n_s,) bool
    extinction,  # (n_s,)
    segment_length,  # (J,)
    segment_extinction,  # (n_s, J)
    clouds,  # (C, 5): centre (3), radius, extinction
    noise_equivalent,  # (n_s,)
    contrast,  # (n_s, n_g)
    has_noise,  # bool
    out_range,
    out_critical,
    out_cycles,
    out_in_view,
    out_depth,
    out_tau,
    out_snr,
):
    """Per pair, in passes over the batch that LLVM vectorises: the geometry, the optical
    depth (segment by segment, cloud by cloud), then transmittance and SNR."""
    n_s, n_b = sensor_positions.shape[0], sensor_positions.shape[1]
    n_g = target_positions.shape[0]
    area = np.empty(n_b)
    for s in range(n_s):
        tan_h, tan_v = half_tangents[s, 0], half_tangents[s, 1]
        gamma, sensor_cycle, pointed_s = extinction[s], cycle[s], pointed[s]
        for g in range(n_g):
            length, width, height = dimensions[g, 0], dimensions[g, 1], dimensions[g, 2]
            visible = visible_fraction[g]
            # 1. Geometry: range, outline, critical dimension, cycles, field of view.
            for b in range(n_b):
                x = target_positions[g, b, 0] - sensor_positions[s, b, 0]
                y = target_positions[g, b, 1] - sensor_positions[s, b, 1]
                z = target_positions[g, b, 2] - sensor_positions[s, b, 2]
                rng, horizontal, vertical = box_outline(
                    x, y, z, sin_heading[g, b], cos_heading[g, b], length, width, height
                )
                critical = minimum(horizontal, vertical * visible)
                out_range[s, g, b] = rng
                out_critical[s, g, b] = critical
                out_cycles[s, g, b] = critical / (maximum(rng, 1e-9) * sensor_cycle)
                area[b] = horizontal * vertical * visible
                ahead = x * frame[s, b, 0] + y * frame[s, b, 1] + z * frame[s, b, 2]
                right = x * frame[s, b, 3] + y * frame[s, b, 4]
                up = x * frame[s, b, 5] + y * frame[s, b, 6] + z * frame[s, b, 7]
                in_fov = ahead > 0.0 and abs(right) <= tan_h * ahead and abs(up) <= tan_v * ahead
                out_in_view[s, g, b] = (in_fov or not pointed_s) and rng == rng
                out_depth[s, g, b] = gamma * rng
            # 2. The optical depth: segments laid from the sensor outward, then clouds.
            start = 0.0
            for j in range(segment_length.shape[0]):
                stretch, more = segment_length[j], segment_extinction[s, j] - gamma
                for b in range(n_b):
                    out_depth[s, g, b] = out_depth[s, g, b] + more * clip(
                        out_range[s, g, b] - start, 0.0, stretch
                    )
                start = start + stretch
            for c in range(clouds.shape[0]):
                cx, cy, cz, radius, cloud = (
                    clouds[c, 0],
                    clouds[c, 1],
                    clouds[c, 2],
                    clouds[c, 3],
                    clouds[c, 4],
                )
                for b in range(n_b):
                    crossed = chord(
                        sensor_positions[s, b, 0],
                        sensor_positions[s, b, 1],
                        sensor_positions[s, b, 2],
                        target_positions[g, b, 0],
                        target_positions[g, b, 1],
                        target_positions[g, b, 2],
                        cx,
                        cy,
                        cz,
                        radius,
                    )
                    out_depth[s, g, b] = out_depth[s, g, b] + cloud * crossed
            # 3. Transmittance and SNR (the path's, and the sensor's own added in variance).
            for b in range(n_b):
                depth = out_depth[s, g, b]
                tau = _simd.exp(-depth)
                snr = path_snr_vector(depth)
                if has_noise:
                    footprint = maximum(out_range[s, g, b], 1e-9) * ifov[s]
                    pixels = area[b] / (footprint * footprint)
                    own = sensor_snr_vector(contrast[s, g], noise_equivalent[s], tau, pixels)
                    snr = combined_snr_vector(snr, own)
                out_tau[s, g, b] = tau
                out_snr[s, g, b] = snr


# --------------------------------------------------------------------------------------------
# Probabilities
# --------------------------------------------------------------------------------------------


@inline
def noise_factor(snr, model, anchors):
    """The factor >= 1 by which noise multiplies the N50s (:mod:`targetacq.noise`).

    ``anchors``: sqrt(3) (variance-sum); Table 3.5's low, medium 50 % points and α
    (clutter-analogue).
    """
    if model == NOISE_VARIANCE_SUM:
        ratio = anchors[0] * power_of_ten(-snr / 20.0)
        big = ratio > 1.0
        safe = ratio if big else 1.0
        shrink = 1.0 / safe
        large = safe * math.sqrt(1.0 + shrink * shrink)
        small_ratio = 0.0 if big else ratio
        small = math.sqrt(1.0 + small_ratio * small_ratio)
        return large if big else small
    if model == NOISE_CLUTTER_ANALOGUE:
        low, medium, alpha = anchors[1], anchors[2], anchors[3]
        r = power_of_ten(snr / 20.0)
        safe = r if r > 0.0 else 1.0
        mid = low * math.exp(
            math.log(10.0 / minimum(maximum(safe, 1.0), 10.0)) * (math.log(medium / low) / _LN10)
        )
        value = mid if r >= 1.0 else medium * math.exp(-alpha * math.log(safe))
        value = value if r > 0.0 else (r if r != r else math.inf)
        return value / low
    return snr if snr != snr else 1.0  # the "none" model: f = 1


@inline
def effective_scr(scr, snr):
    """Clutter and noise added in variance, ``(1/SCR² + 1/SNR²)^(−1/2)``."""
    lin = power_of_ten(snr / 20.0)
    a, b = minimum(scr, lin), maximum(scr, lin)
    usable = b > 0.0 and b < math.inf
    ratio = a / b if usable else 0.0
    combined = a / math.sqrt(1.0 + ratio * ratio)
    exact = scr if snr == math.inf else combined
    return snr if snr != snr else exact


@inline
def ttpf(n, log_n, n50, log_n50):
    """The TTPF of N cycles for an N50, with ``ln N`` and ``ln N50`` given."""
    z = (log_n - log_n50) * (2.7 + n * (0.7 / n50))
    z = clip(z, -_TTPF_LIMIT, _TTPF_LIMIT)
    p = 1.0 / (1.0 + math.exp(-z))
    return 0.0 if n == 0.0 else p


@inline
def curve(n, tables, row, count):
    """:func:`curve_log` taking the logarithm of N itself."""
    return curve_log(n, math.log(n) if n > 0.0 else 0.0, tables, row, count)


@inline
def curve_log(n, u, tables, row, count):
    """A table curve through ``count`` printed points, piecewise linear in ``u = ln N``, linear
    from 0 below its first point, flat after its last; a vertical step holds its higher value.

    ``tables[row]`` holds the curve's cycles, their logarithms and the probabilities (indexed,
    not sliced: a slice inside a loop would count references).
    """
    out = tables[row, 2, count - 1]
    if n != n:
        out = n
    elif n < tables[row, 0, 0]:
        out = tables[row, 2, 0] * n / tables[row, 0, 0]
    elif n < tables[row, 0, count - 1]:
        for k in range(count - 1):
            if tables[row, 0, k] <= n < tables[row, 0, k + 1]:
                low, high = tables[row, 1, k], tables[row, 1, k + 1]
                p_low, p_high = tables[row, 2, k], tables[row, 2, k + 1]
                out = p_low + (u - low) / (high - low) * (p_high - p_low)
                break
    return out


@inline
def schmieder_weathersby(n, n50, scr, region, sw, sw_count, sw_constants):
    """P(detection) in clutter of Table 3.5: the region's curve, or with ``region`` < 0 the
    curves blended in ``log SCR`` with the stretch below SCR = 0.33.

    ``sw``: (3, 3, K) cycles, log cycles, probabilities of the low, medium and high curves;
    ``sw_constants``: reference N50, lowest observed SCR, exponent α.
    """
    scaled = n * (sw_constants[0] / n50)
    if region >= 0:
        return curve(scaled, sw, region, sw_count[region])
    scr_low, alpha = sw_constants[1], sw_constants[2]
    below = scr < scr_low
    ratio = (scr if below else scr_low) / scr_low
    stretch = math.exp(alpha * math.log(ratio)) if below else 1.0
    scaled = scaled * stretch
    u = math.log(scaled) if scaled > 0.0 else 0.0
    low = curve_log(scaled, u, sw, 0, sw_count[0])
    medium = curve_log(scaled, u, sw, 1, sw_count[1])
    high = curve_log(scaled, u, sw, 2, sw_count[2])
    safe = scr if scr > 0.0 else scr_low
    upper = minimum(maximum(math.log10(safe if safe >= 1.0 else 1.0), 0.0), 1.0)
    lower = minimum(
        maximum(math.log((safe if safe < 1.0 else 1.0) / scr_low) / math.log(1.0 / scr_low), 0.0),
        1.0,
    )
    above_one = medium + upper * (low - medium)
    below_one = high + lower * (medium - high)
    out = above_one if scr >= 1.0 else below_one
    return scr if scr != scr else out


@inline
def task_curve(n, log_n, n50, log_n50, task, transform, tables, table_count, table_reference):
    """P of one task from N through the transform (TTPF, or a table curve stretched by the
    ratio of its reference N50 to the criterion's)."""
    if transform == TRANSFORM_TTPF:
        return ttpf(n, log_n, n50, log_n50)
    scaled = n * (table_reference[task] / n50)
    return curve(scaled, tables, task, table_count[task])


@inline
def ttpf_vector(n, log_n, n50, log_n50):
    """:func:`ttpf` with the vectorisable exponential (for loops LLVM vectorises)."""
    z = (log_n - log_n50) * (2.7 + n * (0.7 / n50))
    z = clip(z, -_TTPF_LIMIT, _TTPF_LIMIT)
    p = 1.0 / (1.0 + _simd.exp(-z))
    return 0.0 if n == 0.0 else p


@inline
def variance_sum_vector(snr, constant):
    """The ``variance-sum`` noise factor with the vectorisable exponential."""
    ratio = constant * _simd.exp(-snr * (_LN10 / 20.0))
    big = ratio > 1.0
    safe = ratio if big else 1.0
    shrink = 1.0 / safe
    large = safe * math.sqrt(1.0 + shrink * shrink)
    small_ratio = 0.0 if big else ratio
    small = math.sqrt(1.0 + small_ratio * small_ratio)
    return large if big else small


@inline
def noisy_cycles(n, f):
    """N / f; no signal left (f = inf): nothing resolved, N = 0 (NaN stays NaN)."""
    return (n if n != n else 0.0) if f == math.inf else n / f


@compiled
def probabilities_kernel(
    cycles,  # (n_s, n_g, B)
    snr,  # (n_s, n_g, B)
    scr,  # (n_s, n_g, B), possibly broadcast
    in_view,  # (n_s, n_g, B) bool
    rng,  # (n_s, n_g, B)
    n50,  # (n_g, 3)
    log_n50,  # (n_g, 5): ln N50 of the three tasks, the low-clutter N50 of motion, its ln
    hot_spot,  # (n_g,) bool
    moving,  # (n_g,) bool
    settings,  # int64 (7,): noise, combines, transform, region, motion, semantics, has_scr
    noise_anchors,  # (4,)
    tables,  # (3, 3, K): the transform's curves per task (cycles, log cycles, P)
    table_count,  # (3,)
    table_reference,  # (3,)
    sw,  # (3, 3, K)
    sw_count,  # (3,)
    sw_constants,  # (4,): reference N50, lowest SCR, α, low-clutter scale
    out_detection,
    out_recognition,
    out_identification,
    out_fused,  # (3, n_g, B): the products of the misses, then the fused probabilities
):
    """Per pair and batch element, in three passes over the batch: the noisy N and the three
    task curves (a loop LLVM vectorises for the TTPF), detection in clutter, hot spots and
    motion where there are any (scalar), then the semantics, the field of view and the
    fusion."""
    noise, combines, transform = settings[0], settings[1] == 1, settings[2]
    region, motion, semantics, has_scr = settings[3], settings[4], settings[5], settings[6] == 1
    clutter = has_scr or region >= 0
    n_s, n_g, n_b = cycles.shape
    noisy = np.empty(n_b)
    for g in range(n_g):
        for b in range(n_b):
            out_fused[0, g, b] = 1.0
            out_fused[1, g, b] = 1.0
            out_fused[2, g, b] = 1.0
    for s in range(n_s):
        for g in range(n_g):
            d50, r50, i50 = n50[g, 0], n50[g, 1], n50[g, 2]
            ld, lr, li, low50, llow = (
                log_n50[g, 0],
                log_n50[g, 1],
                log_n50[g, 2],
                log_n50[g, 3],
                log_n50[g, 4],
            )
            hot, move = hot_spot[g], moving[g]
            # 1. The noisy N and the curves of the three tasks.
            if noise == NOISE_VARIANCE_SUM:
                for b in range(n_b):
                    f = variance_sum_vector(snr[s, g, b], noise_anchors[0])
                    noisy[b] = noisy_cycles(cycles[s, g, b], f)
            elif noise != NOISE_NONE_GIVEN:
                for b in range(n_b):
                    f = noise_factor(snr[s, g, b], noise, noise_anchors)
                    noisy[b] = noisy_cycles(cycles[s, g, b], f)
            else:
                for b in range(n_b):
                    noisy[b] = cycles[s, g, b]
            if transform == TRANSFORM_TTPF:
                for b in range(n_b):
                    n = noisy[b]
                    log_n = _simd.log(n)
                    out_detection[s, g, b] = ttpf_vector(n, log_n, d50, ld)
                    out_recognition[s, g, b] = ttpf_vector(n, log_n, r50, lr)
                    out_identification[s, g, b] = ttpf_vector(n, log_n, i50, li)
            else:
                for b in range(n_b):
                    n = noisy[b]
                    out_detection[s, g, b] = task_curve(
                        n, 0.0, d50, ld, 0, transform, tables, table_count, table_reference
                    )
                    out_recognition[s, g, b] = task_curve(
                        n, 0.0, r50, lr, 1, transform, tables, table_count, table_reference
                    )
                    out_identification[s, g, b] = task_curve(
                        n, 0.0, i50, li, 2, transform, tables, table_count, table_reference
                    )
            # 2. Detection in clutter, of hot spots and of moving targets.
            if clutter or hot or move:
                for b in range(n_b):
                    n, n_noisy, det = cycles[s, g, b], noisy[b], out_detection[s, g, b]
                    fallback = det
                    if clutter:
                        c = scr[s, g, b] if has_scr else math.nan
                        if noise != NOISE_NONE_GIVEN and combines and has_scr:
                            ratio = effective_scr(c, snr[s, g, b])
                            seen = schmieder_weathersby(
                                n, d50, ratio, REGION_NONE, sw, sw_count, sw_constants
                            )
                        else:
                            seen = schmieder_weathersby(
                                n_noisy, d50, c, region, sw, sw_count, sw_constants
                            )
                        fallback = minimum(seen, det)
                    special = math.nan
                    if hot:
                        special = curve(n_noisy * (sw_constants[0] / d50), sw, 0, sw_count[0])
                    if move:
                        if motion == MOTION_ALWAYS:
                            go = n_noisy if n_noisy != n_noisy else 1.0
                        else:
                            go = task_curve(
                                n_noisy,
                                math.log(n_noisy),
                                low50,
                                llow,
                                0,
                                transform,
                                tables,
                                table_count,
                                table_reference,
                            )
                        special = go if special != special else maximum(special, go)
                    out_detection[s, g, b] = (
                        fallback if (special != special and n == n) else special
                    )
            # 3. The semantics, the field of view, unknown geometry, and the misses.
            for b in range(n_b):
                det, rec, ide = (
                    out_detection[s, g, b],
                    out_recognition[s, g, b],
                    out_identification[s, g, b],
                )
                if semantics == SEMANTICS_NESTED:
                    rec = minimum(rec, det)
                    ide = minimum(ide, rec)
                else:
                    rec = det * rec
                    ide = rec * ide
                seen = in_view[s, g, b]
                det = det if seen else 0.0
                rec = rec if seen else 0.0
                ide = ide if seen else 0.0
                unknown = rng[s, g, b] != rng[s, g, b]
                det = math.nan if unknown else det
                rec = math.nan if unknown else rec
                ide = math.nan if unknown else ide
                out_detection[s, g, b], out_recognition[s, g, b], out_identification[s, g, b] = (
                    det,
                    rec,
                    ide,
                )
                out_fused[0, g, b] *= 1.0 - det
                out_fused[1, g, b] *= 1.0 - rec
                out_fused[2, g, b] *= 1.0 - ide
    for k in range(3):
        for g in range(n_g):
            for b in range(n_b):
                out_fused[k, g, b] = 1.0 - out_fused[k, g, b]


@compiled
def ttpf_three(cycles, n50, out_detection, out_recognition, out_identification):
    """The core kernel: three TTPF probabilities of a flat array of N, ``ln N`` taken once."""
    d50, r50, i50 = n50[0], n50[1], n50[2]
    ld, lr, li = math.log(d50), math.log(r50), math.log(i50)
    for k in range(cycles.shape[0]):
        n = cycles[k]
        log_n = _simd.log(n)
        out_detection[k] = ttpf_vector(n, log_n, d50, ld)
        out_recognition[k] = ttpf_vector(n, log_n, r50, lr)
        out_identification[k] = ttpf_vector(n, log_n, i50, li)
