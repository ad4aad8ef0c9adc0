"""The loops of :func:`targetacq.physics.line_of_sight.line_of_sight` compiled by numba.

The scalar twin of :func:`targetacq.physics.line_of_sight._visible_numpy`: the same samples, the
same bilinear interpolation and the same arithmetic in the same order, so the two give the same
numbers. One pair at a time, its profile in one pass with no temporary arrays. Importing this
module imports numba (the ``fast`` extra).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["visible_fractions"]


_BLOCK = 64  # samples between the checks for a target already hidden


@njit(cache=True, error_model="numpy", nogil=True)
def visible_fractions(
    grid: np.ndarray,
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
    ``out[k]``; ``curvature`` is ``1 / (2 k R_e)`` [1/m] (0: a flat Earth).

    On a grid without voids a pair stops as soon as the highest sight line so far hides the
    whole target: its fraction is then 0 whatever the rest of the profile (the fraction only
    falls as the maximum slope grows, and the check is the final formula itself, so the result
    is the NumPy path's to the bit)."""
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
        for first in range(1, steps, _BLOCK):
            for i in range(first, min(np.int64(first + _BLOCK), steps)):
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
