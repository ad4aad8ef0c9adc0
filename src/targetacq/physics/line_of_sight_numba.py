"""The loops of :func:`targetacq.physics.line_of_sight.line_of_sight` compiled by numba.

The scalar twin of :func:`targetacq.physics.line_of_sight._visible_numpy`: the same samples, the
same bilinear interpolation and the same arithmetic in the same order, so the two give the same
numbers. One pair at a time, its profile in one pass (from the target back, chunk by chunk)
with no temporary arrays. Importing this
module imports numba (the ``fast`` extra).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["BLOCK", "block_maxima", "visible_fractions"]


BLOCK = 8
"""Posts per side of a block of :func:`block_maxima`; also the samples of a chunk, so that a
chunk (at most one post apart along the track's major axis) touches at most 2 × 2 blocks."""

_MARGIN = 1e-9
"""A chunk is skipped only where its bound lies this far below the best slope, relative, plus
1e-12 of the altitudes over the distance: far beyond the few units in the last place by which
the rounding of a sample's slope can exceed the exact bound."""


def block_maxima(grid: np.ndarray) -> np.ndarray:
    """The highest post of each block of ``BLOCK`` × ``BLOCK`` cells (its edge posts included),
    an upper bound of the bilinear terrain over the block; NaN where the block has a void."""
    rows, cols = grid.shape
    n_i, n_j = -(-(rows - 1) // BLOCK), -(-(cols - 1) // BLOCK)
    out = np.empty((n_i, n_j))
    for i in range(n_i):
        band = grid[i * BLOCK : min(i * BLOCK + BLOCK, rows - 1) + 1]
        for j in range(n_j):
            out[i, j] = band[:, j * BLOCK : min(j * BLOCK + BLOCK, cols - 1) + 1].max()
    return out


@njit(cache=True, error_model="numpy", nogil=True)
def visible_fractions(
    grid: np.ndarray,
    blocks: np.ndarray,
    spacing: float,
    x0: float,
    y0: float,
    observers: np.ndarray,
    targets: np.ndarray,
    heights: np.ndarray,
    curvature: float,
    out: np.ndarray,
) -> None:  # pragma: no cover - compiled
    """Write the visible fraction of each pair ``k`` (observer row, target row, height) to
    ``out[k]``; ``curvature`` is ``1 / (2 k R_e)`` [1/m] (0: a flat Earth); ``blocks`` is
    :func:`block_maxima` of ``grid``.

    The chunks run from the target back to the observer (the maximum does not depend on the
    order; the terrain near a target is the likelier to hide it, and the slopes of far samples
    are the higher, so the best slope is found early, against which the near chunks are then
    skipped). Two shortcuts leave the numbers those of the NumPy path, to the bit. A chunk of
    ``BLOCK`` samples is skipped where no sample in it can raise the highest slope so far: its
    terrain is at most ``M``, the highest post of the blocks it touches, so its slopes are at
    most ``(M − z_o)/d − c d_a`` (``d`` the chunk's first distance ``d_a`` where ``M >= z_o``,
    else its last; ``c`` the curvature), skipped where that bound lies :data:`_MARGIN` below the
    best (rounding cannot bridge that). A void makes ``M`` NaN: never skipped. And on a grid
    without voids a pair stops as soon as the highest sight line hides the whole target: its
    fraction is 0 whatever the rest of the profile (the fraction only falls as the maximum
    slope grows, and the check is the final formula itself)."""
    rows, cols = grid.shape
    voids = bool(np.isnan(grid).any())
    for k in range(heights.size):
        zo = observers[k, 2]
        base = targets[k, 2]
        h = heights[k]
        u0 = (observers[k, 0] - x0) / spacing
        v0 = (observers[k, 1] - y0) / spacing
        u1 = (targets[k, 0] - x0) / spacing
        v1 = (targets[k, 1] - y0) / spacing
        if not (
            u0 >= 0 and u0 <= cols - 1 and v0 >= 0 and v0 <= rows - 1
            and u1 >= 0 and u1 <= cols - 1 and v1 >= 0 and v1 <= rows - 1
            and not math.isnan(zo) and not math.isnan(base) and not math.isnan(h)
        ):  # fmt: skip
            out[k] = math.nan
            continue
        du = u1 - u0
        dv = v1 - v0
        steps = np.int64(math.ceil(max(abs(du), abs(dv))))
        distance = spacing * math.sqrt(du * du + dv * dv)
        far = curvature * distance * distance
        best = -math.inf
        void = False
        fraction = 1.0
        chunks = (steps - 1 + BLOCK - 1) // BLOCK
        for chunk in range(chunks - 1, -1, -1):  # from the target back to the observer
            first = 1 + chunk * BLOCK
            last = min(np.int64(first + BLOCK), steps) - 1
            if best > -math.inf:
                # The blocks the chunk's samples fall in: its end samples' cells (2 x 2 at most).
                fa, fb = first / steps, last / steps
                ua, ub = u0 + du * fa, u0 + du * fb
                va, vb = v0 + dv * fa, v0 + dv * fb
                ja = min(np.int64(min(ua, ub)), cols - 2) // BLOCK
                jb = min(np.int64(max(ua, ub)), cols - 2) // BLOCK
                ia = min(np.int64(min(va, vb)), rows - 2) // BLOCK
                ib = min(np.int64(max(va, vb)), rows - 2) // BLOCK
                top = blocks[ia, ja]
                for bi in range(ia, ib + 1):
                    for bj in range(ja, jb + 1):
                        m = blocks[bi, bj]
                        if m != m or m > top:  # NaN, once met, stays: never skipped
                            top = m
                d_a = distance * fa
                d_b = distance * fb
                rise = top - zo
                bound = rise / (d_a if rise >= 0 else d_b) - curvature * d_a
                slack = _MARGIN * (abs(bound) + abs(best)) + 1e-12 * (abs(top) + abs(zo)) / d_a
                if bound + slack < best:
                    continue
            for i in range(first, last + 1):
                frac = i / steps
                u = u0 + du * frac
                v = v0 + dv * frac
                j = min(np.int64(u), cols - 2)
                r = min(np.int64(v), rows - 2)
                fu = u - j
                fv = v - r
                south = grid[r, j] + fu * (grid[r, j + 1] - grid[r, j])
                north = grid[r + 1, j] + fu * (grid[r + 1, j + 1] - grid[r + 1, j])
                z = south + fv * (north - south)
                d = distance * frac
                slope = (z - curvature * d * d - zo) / d
                void |= slope != slope
                best = slope if slope > best else best
            if best > -math.inf:
                hidden_to = zo + best * distance + far
                fraction = min(max((base + h - hidden_to) / h, 0.0), 1.0)
                if fraction == 0.0 and not voids:
                    break
        out[k] = math.nan if void else fraction
