"""The numba engine's kernels: the core's pipeline, element by element, in loops that vectorise.

Each function here is the scalar form of a NumPy kernel of the topic modules, with the same
arithmetic in the same order where it matters (the field-of-view test is exact), so that the
numba engine gives the NumPy engine's numbers to about 1e-15 relative:

================================  ==========================================================
here                              NumPy kernel
================================  ==========================================================
:func:`box_outline`               :func:`targetacq.physics.geometry.box_outline`
:func:`chord`                     :func:`targetacq.physics.atmosphere.sphere_chord_length`
:func:`path_snr`                  :func:`targetacq.physics.atmosphere.snr_from_optical_depth`
:func:`sensor_snr`                :func:`targetacq.physics.detector_noise.sensor_snr`
:func:`combined_snr`              :func:`targetacq.physics.detector_noise.combined_snr` (two SNRs)
:func:`contrast_snr`              :func:`targetacq.physics.detector_noise.contrast_snr`
:func:`seen_probability`          :func:`targetacq.acquisition.path_noise.seen_probability`
:func:`noise_factor`              the models of :mod:`targetacq.acquisition.path_noise`
:func:`effective_scr`             :func:`targetacq.acquisition.path_noise.effective_scr`
:func:`ttpf`                      :func:`targetacq.acquisition.transforms.ttpf` (``ln N`` given)
:func:`curve`                     a table curve of :mod:`targetacq.acquisition.transforms` (C2NVEO,
                                  Table 3.5), piecewise linear in ``log N``
:func:`sw_scaled`,                :func:`targetacq.acquisition.transforms.schmieder_weathersby` (the
:func:`sw_blend`                  cycles it reads the curves at, then their blend)
================================  ==========================================================

Layout. For each sensor–target pair the kernels run over the batch (the times of a
:class:`targetacq.ModelChain`) in passes that LLVM turns into SIMD code: the model choices are
loops of their own, every branch inside a loop is a select, the table curves are read with a
fixed number of segments (:data:`CURVE_POINTS`; :func:`curve_rows` reads three curves for a
whole batch, segment by segment), and the exponentials and logarithms are
:mod:`targetacq.core.engines._simd`'s. A step of the step API has a batch of one: the engine runs
the targets that share a probability model as one row of the probabilities kernel, while the factors
kernel runs its pairs one by one.

:func:`_factors_kernel` and :func:`_probabilities_kernel` are the two kernels of
:mod:`targetacq.core.engines.numba_engine`, which prepares their inputs; :func:`ttpf_three` is the
core kernel alone (``benchmarks/bench_core.py``). Importing this module imports numba (the
``fast`` extra).
"""

from __future__ import annotations

import math

from numba import types

from targetacq.core.engines._simd import (
    compiled,
    exp,
    expm1,
    inline,
    kernel,
    log,
    log10,
    readonly,
    writable,
)

# Codes of the model choices inside the kernels (numba compiles integers, not registry names).
NOISE_NONE_GIVEN, NOISE_VARIANCE_SUM, NOISE_CLUTTER_ANALOGUE, NOISE_IGNORED = 0, 1, 2, 3
TRANSFORM_TTPF, TRANSFORM_TABLE = 0, 1
MOTION_LOW_CLUTTER, MOTION_ALWAYS = 0, 1
SEMANTICS_NESTED, SEMANTICS_CONDITIONAL = 0, 1
REGION_NONE = -1  # else the index of the region's curve: 0 low, 1 medium, 2 high

CURVE_POINTS = 12
"""Points of every table curve as the kernels read it: a curve with fewer printed points is
padded with its last point (segments of zero width, never selected). A constant, so that the
loop over the segments unrolls and the curve vectorises."""

_LN10 = math.log(10.0)
_SQRT2 = math.sqrt(2.0)
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
    return exp(x * _LN10)


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
    horizontal = length if flat else horizontal
    top = width if rng > 0.0 else height
    vertical = top if flat else vertical
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
    snr = 20.0 * (-safe / _LN10 - log10(-expm1(-safe)))
    snr = math.inf if depth <= 0.0 else snr
    snr = -math.inf if depth == math.inf else snr
    return depth if depth != depth else snr


@inline
def sensor_snr(contrast, noise_equivalent, tau, pixels):
    """The sensor's own SNR of a target [dB], ``20 log10(τ |C| g(n) / NEC)``."""
    gain = math.sqrt(maximum(pixels, 1.0)) if pixels >= 1.0 else pixels
    signal = tau * abs(contrast) * gain
    quiet = noise_equivalent == 0.0
    ratio = math.inf if quiet else signal / (1.0 if quiet else noise_equivalent)
    db = 20.0 * log10(ratio)
    unknown = contrast != contrast or noise_equivalent != noise_equivalent
    unknown = unknown or tau != tau or pixels != pixels
    return math.nan if unknown else db


@inline
def combined_snr(a, b):
    """Two independent noises added in variance [dB]."""
    total = 0.0 + exp(-a * (_LN10 / 10.0)) + exp(-b * (_LN10 / 10.0))
    db = -10.0 * log10(total)
    return math.nan if (a != a or b != b) else db


@inline
def contrast_snr(contrast, noise_equivalent, path_contrast, tau, pixels):
    """SNR of the contrast law [dB],
    ``τ|C| / sqrt((NEC/g)² + ((1 − τ) σ_path)²)``."""
    gain = math.sqrt(maximum(pixels, 1.0)) if pixels >= 1.0 else pixels
    own = 0.0 if noise_equivalent == 0.0 else noise_equivalent / gain
    path = (1.0 - tau) * path_contrast
    total = math.sqrt(own * own + path * path)
    signal = tau * abs(contrast)
    ratio = math.inf if total == 0.0 else signal / total
    db = 20.0 * log10(ratio)
    unknown = contrast != contrast or noise_equivalent != noise_equivalent
    unknown = unknown or tau != tau or pixels != pixels or path_contrast != path_contrast
    return math.nan if unknown else db


@inline
def seen_probability(snr, threshold):
    """``Φ(SNR_lin − k)``, the probability of being seen above the noise; 1 for k = −inf."""
    lin = math.inf if snr == math.inf else exp(snr * (_LN10 / 20.0))
    x = lin - threshold if threshold > -math.inf else math.inf
    p = 0.5 * math.erfc(-x / _SQRT2)
    return snr if snr != snr else p


@kernel(
    *(readonly(3), readonly(3)),  # positions
    *(readonly(2), readonly(2), readonly(2), readonly(3)),  # headings, dimensions, visible
    *(readonly(1), readonly(1), readonly(3), readonly(2), readonly(1, types.boolean)),  # sensors
    *(readonly(1), readonly(1), readonly(2), readonly(2)),  # extinction, segments, clouds
    *(readonly(1), readonly(2), types.boolean, readonly(1), types.boolean),  # the SNR
    writable(2),  # area
    *(writable(3), writable(3), writable(3), writable(3, types.boolean)),  # out: range … in view
    *(writable(3), writable(3), writable(3)),  # out: depth, tau, SNR
)
def _factors_kernel(
    sensor_positions,  # (3, n_s, B): east, north, up, component-major (unit-stride loads)
    target_positions,  # (3, n_g, B)
    sin_heading,  # (n_g, B)
    cos_heading,  # (n_g, B)
    dimensions,  # (n_g, 3)
    visible_fraction,  # (1 or n_s, n_g, 1 or B)
    cycle,  # (n_s,)
    ifov,  # (n_s,)
    frame,  # (8, n_s, B): forward (3), right (2), up (3), unit, in east-north-up
    half_tangents,  # (n_s, 2)
    pointed,  # (n_s,) bool
    extinction,  # (n_s,)
    segment_length,  # (J,)
    segment_extinction,  # (n_s, J)
    clouds,  # (C, 5): centre (3), radius, extinction
    noise_equivalent,  # (n_s,)
    contrast,  # (n_s, n_g)
    has_noise,  # bool
    path_contrast,  # (n_s,): σ_path of the contrast SNR law
    contrast_law,  # bool: the contrast law (rows with NEC = 0 keep Eq. (7.7))
    area,  # (2, B) work space
    out_range,  # (n_s, n_g, B)
    out_critical,
    out_cycles,
    out_in_view,
    out_depth,
    out_tau,
    out_snr,
):
    """Per pair, in passes over the batch: the geometry, the optical depth (segment by segment,
    cloud by cloud), then transmittance and SNR."""
    n_s, n_g, n_b = out_range.shape
    per_sensor = visible_fraction.shape[0] > 1
    per_batch = 1 if visible_fraction.shape[2] > 1 else 0
    for s in range(n_s):
        tan_h, tan_v = half_tangents[s, 0], half_tangents[s, 1]
        gamma, sensor_cycle, pointed_s = extinction[s], cycle[s], pointed[s]
        noise_s, ifov_s = noise_equivalent[s], ifov[s]
        sv = s if per_sensor else 0
        for g in range(n_g):
            length, width, height = dimensions[g, 0], dimensions[g, 1], dimensions[g, 2]
            signal = contrast[s, g]
            for b in range(n_b):  # the visible fraction of the pair, contiguous
                area[1, b] = visible_fraction[sv, g, b * per_batch]
            # 1. Geometry: range, outline, critical dimension, cycles, field of view.
            for b in range(n_b):
                visible = area[1, b]
                x = target_positions[0, g, b] - sensor_positions[0, s, b]
                y = target_positions[1, g, b] - sensor_positions[1, s, b]
                z = target_positions[2, g, b] - sensor_positions[2, s, b]
                rng, horizontal, vertical = box_outline(
                    x, y, z, sin_heading[g, b], cos_heading[g, b], length, width, height
                )
                critical = minimum(horizontal, vertical * visible)
                out_range[s, g, b] = rng
                out_critical[s, g, b] = critical
                out_cycles[s, g, b] = critical / (maximum(rng, 1e-9) * sensor_cycle)
                area[0, b] = horizontal * vertical * visible
                ahead = x * frame[0, s, b] + y * frame[1, s, b] + z * frame[2, s, b]
                right = x * frame[3, s, b] + y * frame[4, s, b]
                up = x * frame[5, s, b] + y * frame[6, s, b] + z * frame[7, s, b]
                in_fov = ahead > 0.0 and abs(right) <= tan_h * ahead and abs(up) <= tan_v * ahead
                out_in_view[s, g, b] = (in_fov or not pointed_s) and rng == rng
                out_depth[s, g, b] = gamma * rng
            # 2. The optical depth: segments laid from the sensor outward, then clouds.
            start = 0.0
            for j in range(segment_length.shape[0]):
                stretch, more = segment_length[j], segment_extinction[s, j] - gamma
                for b in range(n_b):
                    inside = clip(out_range[s, g, b] - start, 0.0, stretch)
                    out_depth[s, g, b] = out_depth[s, g, b] + more * inside
                start = start + stretch
            for c in range(clouds.shape[0]):
                cx, cy, cz = clouds[c, 0], clouds[c, 1], clouds[c, 2]
                radius, cloud = clouds[c, 3], clouds[c, 4]
                for b in range(n_b):
                    crossed = chord(
                        sensor_positions[0, s, b],
                        sensor_positions[1, s, b],
                        sensor_positions[2, s, b],
                        target_positions[0, g, b],
                        target_positions[1, g, b],
                        target_positions[2, g, b],
                        cx,
                        cy,
                        cz,
                        radius,
                    )
                    out_depth[s, g, b] = out_depth[s, g, b] + cloud * crossed
            # 3. Transmittance and SNR (the path's, and the sensor's own added in variance).
            if has_noise and contrast_law and noise_s != 0.0:
                sigma_s = path_contrast[s]
                for b in range(n_b):
                    depth = out_depth[s, g, b]
                    tau = exp(-depth)
                    footprint = maximum(out_range[s, g, b], 1e-9) * ifov_s
                    pixels = area[0, b] / (footprint * footprint)
                    out_tau[s, g, b] = tau
                    out_snr[s, g, b] = contrast_snr(signal, noise_s, sigma_s, tau, pixels)
            elif has_noise and not contrast_law:
                for b in range(n_b):
                    depth = out_depth[s, g, b]
                    tau = exp(-depth)
                    footprint = maximum(out_range[s, g, b], 1e-9) * ifov_s
                    pixels = area[0, b] / (footprint * footprint)
                    own = sensor_snr(signal, noise_s, tau, pixels)
                    out_tau[s, g, b] = tau
                    out_snr[s, g, b] = combined_snr(path_snr(depth), own)
            else:
                for b in range(n_b):
                    depth = out_depth[s, g, b]
                    out_tau[s, g, b] = exp(-depth)
                    out_snr[s, g, b] = path_snr(depth)


# --------------------------------------------------------------------------------------------
# Probabilities
# --------------------------------------------------------------------------------------------


@inline
def noise_factor(snr, model, anchors):
    """The factor >= 1 by which noise multiplies the N50s (:mod:`targetacq.acquisition.path_noise`).

    ``anchors``: sqrt(3) (variance-sum); Table 3.5's low, medium 50 % points and α
    (clutter-analogue).
    """
    if model == NOISE_VARIANCE_SUM:  # sqrt(1 + r²), r = k · 10^(−SNR/20), without overflow
        ratio = anchors[0] * exp(-snr * (_LN10 / 20.0))
        big = ratio > 1.0
        safe = ratio if big else 1.0
        shrink = 1.0 / safe
        large = safe * math.sqrt(1.0 + shrink * shrink)
        small_ratio = 0.0 if big else ratio
        small = math.sqrt(1.0 + small_ratio * small_ratio)
        return large if big else small
    if model == NOISE_CLUTTER_ANALOGUE:  # Table 3.5's continuous 50 % point at 10^(SNR/20)
        low, medium, alpha = anchors[1], anchors[2], anchors[3]
        r = exp(snr * (_LN10 / 20.0))
        positive = r if r > 0.0 else 1.0
        bounded = minimum(maximum(positive, 1.0), 10.0)
        mid = low * exp(log(10.0 / bounded) * (log(medium / low) / _LN10))
        value = mid if r >= 1.0 else medium * exp(-alpha * log(positive))
        value = value if r > 0.0 else (r if r != r else math.inf)
        return value / low
    return snr if snr != snr else 1.0  # the "none" model: f = 1


@inline
def noisy_cycles(n, f):
    """N / f; no signal left (f = inf): nothing resolved, N = 0 (NaN stays NaN)."""
    nothing = n if n != n else 0.0
    return nothing if f == math.inf else n / (1.0 if f == math.inf else f)


@inline
def effective_scr(scr, snr):
    """Clutter and noise added in variance, ``(1/SCR² + 1/SNR²)^(−1/2)``."""
    lin = power_of_ten(snr / 20.0)
    a, b = minimum(scr, lin), maximum(scr, lin)
    usable = b > 0.0 and b < math.inf
    ratio = a / (b if usable else 1.0)
    ratio = ratio if usable else 0.0
    combined = a / math.sqrt(1.0 + ratio * ratio)
    exact = scr if snr == math.inf else combined
    return snr if snr != snr else exact


@inline
def ttpf(n, log_n, n50, log_n50):
    """The TTPF of N cycles for an N50, with ``ln N`` and ``ln N50`` given."""
    z = (log_n - log_n50) * (2.7 + n * (0.7 / n50))
    z = clip(z, -_TTPF_LIMIT, _TTPF_LIMIT)
    p = 1.0 / (1.0 + exp(-z))
    return 0.0 if n == 0.0 else p


@inline
def curve(n, u, tables, row):
    """A table curve at N (``u = ln N``): piecewise linear in ``ln N`` between its printed
    points, linear from 0 below the first, flat from the last; a vertical step holds its
    higher value.

    ``tables[row]`` holds the curve's cycles, their logarithms, the probabilities and the
    slopes ``dP / d ln N`` of the segments (as ``numpy.interp`` takes them), padded to
    :data:`CURVE_POINTS` points. Read with a select per segment (no search); element by element,
    for a whole batch :func:`curve_rows`.
    """
    out = tables[row, 2, CURVE_POINTS - 1]
    for k in range(CURVE_POINTS - 1):
        value = tables[row, 3, k] * (u - tables[row, 1, k]) + tables[row, 2, k]
        out = value if (tables[row, 0, k] <= n and n < tables[row, 0, k + 1]) else out
    first = tables[row, 2, 0] * n / tables[row, 0, 0]
    out = first if n < tables[row, 0, 0] else out
    return n if n != n else out


@inline
def sw_scaled(n, n50, scr, region, sw_constants):
    """The cycles at which Table 3.5's curves are read: N scaled to the table's N50 and, with an
    SCR below 0.33 (``region`` < 0), stretched; and their logarithm."""
    scaled = n * (sw_constants[0] / n50)
    scr_low, alpha = sw_constants[1], sw_constants[2]
    below = region < 0 and scr < scr_low
    ratio = (scr if below else scr_low) / scr_low
    stretch = exp(alpha * log(ratio))
    scaled = scaled * stretch if below else scaled
    return scaled, log(scaled if scaled > 0.0 else 1.0)


@inline
def sw_blend(low, medium, high, scr, region, sw_constants):
    """P(detection) in clutter of Table 3.5 from its three curves read at :func:`sw_scaled`:
    the region's curve, or with ``region`` < 0 the curves blended in ``log SCR``."""
    scr_low = sw_constants[1]
    safe = scr if scr > 0.0 else scr_low
    upper = minimum(maximum(log10(safe if safe >= 1.0 else 1.0), 0.0), 1.0)
    lower = minimum(
        maximum(log((safe if safe < 1.0 else 1.0) / scr_low) / log(1.0 / scr_low), 0.0), 1.0
    )
    above_one = medium + upper * (low - medium)
    below_one = high + lower * (medium - high)
    out = above_one if scr >= 1.0 else below_one
    out = scr if scr != scr else out
    fixed = low if region == 0 else (medium if region == 1 else high)
    return out if region < 0 else fixed


@inline
def curve_rows(tables, work, x, u, out, n_b):
    """``work[out + r, b]`` = the curve ``tables[r]`` (r = 0, 1, 2) at ``work[x, b]``
    (``work[u, b]`` its logarithm) for ``b < n_b``: :func:`curve`, segment by segment over the
    row, the three curves in one pass per segment, so that each pass vectorises."""
    last = CURVE_POINTS - 1
    for r in range(3):
        p_last = tables[r, 2, last]
        for b in range(n_b):
            work[out + r, b] = p_last
    for k in range(last):
        c0, c1, c2 = tables[0, 0, k], tables[1, 0, k], tables[2, 0, k]
        d0, d1, d2 = tables[0, 0, k + 1], tables[1, 0, k + 1], tables[2, 0, k + 1]
        a0, a1, a2 = tables[0, 1, k], tables[1, 1, k], tables[2, 1, k]
        p0, p1, p2 = tables[0, 2, k], tables[1, 2, k], tables[2, 2, k]
        m0, m1, m2 = tables[0, 3, k], tables[1, 3, k], tables[2, 3, k]
        for b in range(n_b):
            n, log_n = work[x, b], work[u, b]
            v0 = m0 * (log_n - a0) + p0
            v1 = m1 * (log_n - a1) + p1
            v2 = m2 * (log_n - a2) + p2
            work[out, b] = v0 if (c0 <= n and n < d0) else work[out, b]
            work[out + 1, b] = v1 if (c1 <= n and n < d1) else work[out + 1, b]
            work[out + 2, b] = v2 if (c2 <= n and n < d2) else work[out + 2, b]
    for r in range(3):
        c_first, p_first = tables[r, 0, 0], tables[r, 2, 0]
        for b in range(n_b):
            n = work[x, b]
            first = p_first * n / c_first
            value = first if n < c_first else work[out + r, b]
            work[out + r, b] = n if n != n else value


@inline
def table_curve(n, n50, task, tables, table_reference):
    """P of one task from a table transform's curve, its cycles axis stretched by the ratio of
    the table's reference N50 to the criterion's."""
    scaled = n * (table_reference[task] / n50)
    return curve(scaled, log(scaled if scaled > 0.0 else 1.0), tables, task)


@kernel(
    *(readonly(3), readonly(3), readonly(3), readonly(3, types.boolean), readonly(3)),  # factors
    *(readonly(2), readonly(2), readonly(1, types.boolean), readonly(1, types.boolean)),  # targets
    readonly(1, types.int64),  # settings
    *(readonly(1), readonly(3), readonly(1), readonly(3), readonly(1), readonly(1)),  # constants
    *(writable(1), writable(2)),  # work space
    *(writable(3), writable(3), writable(3), writable(3)),  # out
)
def _probabilities_kernel(
    cycles,  # (n_s, n_g, B)
    snr,  # (n_s, n_g, B)
    scr,  # (n_s, n_g, B), contiguous
    in_view,  # (n_s, n_g, B) bool
    rng,  # (n_s, n_g, B)
    n50,  # (n_g, 3)
    log_n50,  # (n_g, 5): ln N50 of the three tasks, the low-clutter N50 of motion, its ln
    hot_spot,  # (n_g,) bool
    moving,  # (n_g,) bool
    settings,  # int64 (7,): noise, combines, transform, region, motion, semantics, has_scr
    noise_anchors,  # (4,)
    tables,  # (3, 4, CURVE_POINTS): the transform's curves per task (N, ln N, P, slope)
    table_reference,  # (3,)
    sw,  # (3, 4, CURVE_POINTS)
    sw_constants,  # (4,): reference N50, lowest SCR, α, low-clutter scale
    thresholds,  # (n_s,): k of each row's detection threshold (−inf: none)
    noisy,  # (B,) work space
    work,  # (6, B) work space
    out_detection,  # (n_s, n_g, B)
    out_recognition,
    out_identification,
    out_fused,  # (3, n_g, B): the products of the misses, then the fused probabilities
):
    """Per pair, in passes over the batch: the noisy N and the three task curves; detection in
    clutter, of hot spots and of moving targets (where there are any); then the semantics, the
    field of view and the fusion."""
    noise, combines, transform = settings[0], settings[1] == 1, settings[2]
    region, motion, semantics, has_scr = settings[3], settings[4], settings[5], settings[6] == 1
    clutter = has_scr or region >= 0
    with_noise = noise != NOISE_NONE_GIVEN
    read_effective = with_noise and combines and has_scr
    region_read = REGION_NONE if has_scr else region  # an SCR given wins over the region
    nested = semantics == SEMANTICS_NESTED
    n_s, n_g, n_b = cycles.shape
    for g in range(n_g):
        for b in range(n_b):
            out_fused[0, g, b] = 1.0
            out_fused[1, g, b] = 1.0
            out_fused[2, g, b] = 1.0
    for s in range(n_s):
        for g in range(n_g):
            d50, r50, i50 = n50[g, 0], n50[g, 1], n50[g, 2]
            ld, lr, li = log_n50[g, 0], log_n50[g, 1], log_n50[g, 2]
            low50, llow = log_n50[g, 3], log_n50[g, 4]
            hot, move = hot_spot[g], moving[g]
            # A row with nothing in view and its geometry known is all zeros (the misses stay):
            # most pairs of a large scenario never see each other.
            needed = False
            for b in range(n_b):
                unknown = rng[s, g, b] != rng[s, g, b] or cycles[s, g, b] != cycles[s, g, b]
                needed = needed or in_view[s, g, b] or unknown
            if not needed:
                for b in range(n_b):
                    out_detection[s, g, b] = 0.0
                    out_recognition[s, g, b] = 0.0
                    out_identification[s, g, b] = 0.0
                continue
            # 1. The noisy N and the curves of the three tasks (each choice a loop of its own,
            # so that every loop vectorises).
            if noise == NOISE_VARIANCE_SUM:
                for b in range(n_b):
                    f = noise_factor(snr[s, g, b], NOISE_VARIANCE_SUM, noise_anchors)
                    noisy[b] = noisy_cycles(cycles[s, g, b], f)
            elif with_noise:
                for b in range(n_b):
                    f = noise_factor(snr[s, g, b], noise, noise_anchors)
                    noisy[b] = noisy_cycles(cycles[s, g, b], f)
            else:
                for b in range(n_b):
                    noisy[b] = cycles[s, g, b]
            if transform == TRANSFORM_TTPF:
                for b in range(n_b):
                    n = noisy[b]
                    log_n = log(n)
                    out_detection[s, g, b] = ttpf(n, log_n, d50, ld)
                    out_recognition[s, g, b] = ttpf(n, log_n, r50, lr)
                    out_identification[s, g, b] = ttpf(n, log_n, i50, li)
            else:
                for b in range(n_b):
                    n = noisy[b]
                    out_detection[s, g, b] = table_curve(n, d50, 0, tables, table_reference)
                    out_recognition[s, g, b] = table_curve(n, r50, 1, tables, table_reference)
                    out_identification[s, g, b] = table_curve(n, i50, 2, tables, table_reference)
            # 2. Detection in clutter, of hot spots and of moving targets.
            if clutter:
                # The ratio and the cycles to read Table 3.5 at, its three curves, the blend.
                for b in range(n_b):
                    c = scr[s, g, b] if has_scr else math.nan
                    ratio = effective_scr(c, snr[s, g, b]) if read_effective else c
                    n = cycles[s, g, b] if read_effective else noisy[b]
                    scaled, log_scaled = sw_scaled(n, d50, ratio, region_read, sw_constants)
                    work[0, b], work[1, b], work[2, b] = scaled, log_scaled, ratio
                curve_rows(sw, work, 0, 1, 3, n_b)
                for b in range(n_b):
                    seen = sw_blend(
                        work[3, b], work[4, b], work[5, b], work[2, b], region_read, sw_constants
                    )
                    out_detection[s, g, b] = minimum(seen, out_detection[s, g, b])
            if hot or move:
                for b in range(n_b):
                    n_noisy = noisy[b]
                    scaled = n_noisy * (sw_constants[0] / d50)
                    special = curve(scaled, log(scaled), sw, 0) if hot else math.nan
                    if move:
                        if motion == MOTION_ALWAYS:
                            go = n_noisy if n_noisy != n_noisy else 1.0
                        elif transform == TRANSFORM_TTPF:
                            go = ttpf(n_noisy, log(n_noisy), low50, llow)
                        else:
                            go = table_curve(n_noisy, low50, 0, tables, table_reference)
                        special = go if special != special else maximum(special, go)
                    kept = special != special and cycles[s, g, b] == cycles[s, g, b]
                    out_detection[s, g, b] = out_detection[s, g, b] if kept else special
            # 3. The semantics, the threshold, the field of view, unknown geometry, the misses.
            k_s = thresholds[s]
            for b in range(n_b):
                det = out_detection[s, g, b]
                rec, ide = out_recognition[s, g, b], out_identification[s, g, b]
                if nested:
                    rec = minimum(rec, det)
                    ide = minimum(ide, rec)
                else:
                    rec = det * rec
                    ide = rec * ide
                if k_s > -math.inf:
                    above = seen_probability(snr[s, g, b], k_s)
                    det, rec, ide = det * above, rec * above, ide * above
                seen = in_view[s, g, b]
                unknown = rng[s, g, b] != rng[s, g, b] or cycles[s, g, b] != cycles[s, g, b]
                det = math.nan if unknown else (det if seen else 0.0)
                rec = math.nan if unknown else (rec if seen else 0.0)
                ide = math.nan if unknown else (ide if seen else 0.0)
                out_detection[s, g, b] = det
                out_recognition[s, g, b] = rec
                out_identification[s, g, b] = ide
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
        log_n = log(n)
        out_detection[k] = ttpf(n, log_n, d50, ld)
        out_recognition[k] = ttpf(n, log_n, r50, lr)
        out_identification[k] = ttpf(n, log_n, i50, li)
