"""Clutter from a terrain description instead of an image, Eqs. (6.7)–(6.11) in Sonesson (2004).

A terrain map is a grid of class indices (vegetation, materials) with a cell size in metres. Each
class has a mean signal (intensity) and a signal variance measured at a stated reference
resolution. Around a target, the clutter is the square root of the occurrence-weighted variance
(6.10), ``clutter = (Σ_i k_i σ_i²)^(1/2)`` with ``Σ k_i = 1`` (6.11), the weights ``k_i`` being
the fractions of a window around the target covered by each class.

Interpolation between map points: the window may start and end anywhere, not only on grid
lines; the covered fractions are exact integrals of the piecewise-constant class map, read from
one summed-area table per class by bilinear interpolation (the integral of a piecewise-constant
field is bilinear inside each cell). Every target then costs O(1) whatever the window.

Resolution (§6.7: "variance falls as resolution coarsens"): the thesis gives no law. This module
assumes texture that is uncorrelated at scales finer than the reference resolution ``r0``: a
pixel footprint ``g`` on the ground averages ``(g/r0)²`` independent samples, so
``σ²(g) = σ²(r0) · min(1, (r0/g)²)``; a finer footprint than ``r0`` reveals no new variance.
The footprint of a pixel at range R is ``g = R · IFOV``.
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array

__all__ = ["TerrainClass", "TerrainMap", "read_class_map", "resolution_variance"]


@dataclass(frozen=True)
class TerrainClass:
    """One terrain class.

    Attributes
    ----------
    name : str
    intensity : float
        Mean signal of the class [signal unit], e.g. band exitance [W/m²].
    variance : float
        Signal variance within the class at ``resolution`` [signal unit²], >= 0.
    resolution : float
        Ground resolution at which ``variance`` holds [m], > 0.
    """

    name: str
    intensity: float
    variance: float
    resolution: float

    def __post_init__(self) -> None:
        if not self.variance >= 0:
            raise ValueError(f"terrain class {self.name!r}: variance must be >= 0")
        if not self.resolution > 0:
            raise ValueError(f"terrain class {self.name!r}: resolution must be > 0 m")


def read_class_map(path: Any) -> np.ndarray:
    """A class map from a CSV file: rows of whole class indices separated by commas.

    The file is UTF-8, with or without a byte-order mark; row 0 is the map's first row (at the
    origin's y). It must be a regular readable file of at most 10 MB
    (:func:`targetacq.base.inputs.read_input_text`).

    Returns
    -------
    numpy.ndarray of int64
        (rows, cols), not empty.

    Raises
    ------
    ValueError
        Naming the file: missing or unreadable, not whole numbers, ragged rows, empty.
    """
    from targetacq.base.inputs import read_input_text

    source = Path(path)
    text = read_input_text(source, "terrain map")
    if not text.strip():  # before NumPy, which would warn of it
        raise ValueError(f"{source}: the terrain map is empty")
    try:
        return np.loadtxt(io.StringIO(text), delimiter=",", dtype=np.int64, ndmin=2)
    except ValueError as error:
        reason = " ".join(str(error).split())
        raise ValueError(f"{source}: not a CSV map of whole class indices: {reason}") from None


def resolution_variance(variance: Array, reference: Array, footprint: Array) -> Any:
    """Variance seen at a coarser ground footprint, ``σ² · min(1, (r0/g)²)`` (module docstring).

    Parameters
    ----------
    variance : array_like
        σ² at the reference resolution, >= 0.
    reference : array_like
        r0 [m], > 0.
    footprint : array_like
        g, the pixel footprint on the ground [m], >= 0. A zero footprint (a target at the
        sensor's own position) is the limit of a fine one: the variance at ``r0``.

    Examples
    --------
    >>> float(resolution_variance(4.0, 0.5, 1.0)), float(resolution_variance(4.0, 0.5, 0.0))
    (1.0, 4.0)
    """
    xp, (v, r0, g) = _arrays.arrays(variance, reference, footprint)
    _arrays.require_nonnegative("variance", v, xp)
    _arrays.require_positive("reference", r0, xp, "m")
    _arrays.require_nonnegative("footprint", g, xp, "m")
    coarse = g > r0  # only a coarser footprint averages the texture; no division by 0
    ratio = xp.where(coarse, r0 / xp.where(coarse, g, 1.0), 1.0)
    return _arrays.result(v * ratio * ratio)


class TerrainMap:
    """A class map with per-class signal statistics.

    Parameters
    ----------
    classes : sequence of TerrainClass
        Class ``i`` is the one the map's value ``i`` refers to.
    class_map : array_like of int
        (rows, cols) class indices; row 0 at ``y = origin[1]``, column 0 at ``x = origin[0]``,
        y growing with the row.
    cell_size : float
        Side of a map cell [m], > 0.
    origin : (float, float)
        Map coordinates of the corner of cell (0, 0) [m].
    """

    def __init__(
        self,
        classes: Sequence[TerrainClass],
        class_map: Any,
        cell_size: float,
        origin: tuple[float, float] = (0.0, 0.0),
    ) -> None:
        grid = np.asarray(class_map)
        if grid.ndim != 2 or grid.size == 0:
            raise ValueError("class_map must be a non-empty 2-D grid of class indices")
        if not np.issubdtype(grid.dtype, np.integer):
            raise ValueError(f"class_map must hold integer class indices, got {grid.dtype}")
        if grid.min() < 0 or grid.max() >= len(classes):
            raise ValueError(f"class_map values must index the {len(classes)} classes")
        if not cell_size > 0:
            raise ValueError(f"cell_size must be > 0 m, got {cell_size!r}")
        self.classes = tuple(classes)
        self.class_map = grid
        self.cell_size = float(cell_size)
        self.origin = (float(origin[0]), float(origin[1]))
        rows, cols = grid.shape
        self._tables = np.zeros((len(classes), rows + 1, cols + 1))
        for i in range(len(classes)):
            np.cumsum(np.cumsum(grid == i, axis=0), axis=1, out=self._tables[i, 1:, 1:])

    def _integral(self, u: Any, v: Any) -> Any:
        """∫∫ of each class indicator over [0, u] × [0, v] (cell units), bilinear in each cell."""
        rows, cols = self.class_map.shape
        u = np.clip(u, 0.0, cols)
        v = np.clip(v, 0.0, rows)
        i = np.minimum(np.floor(u).astype(np.int64), cols - 1)
        j = np.minimum(np.floor(v).astype(np.int64), rows - 1)
        fu, fv = u - i, v - j
        t = self._tables
        return (
            (1 - fu) * (1 - fv) * t[:, j, i]
            + fu * (1 - fv) * t[:, j, i + 1]
            + (1 - fu) * fv * t[:, j + 1, i]
            + fu * fv * t[:, j + 1, i + 1]
        )

    def weights(self, x: Array, y: Array, window: Array) -> Any:
        """Occurrence fractions ``k_i`` of the classes in a square window, Eq. (6.11).

        Parameters
        ----------
        x, y : array_like
            Window centres in map coordinates [m].
        window : array_like
            Window side [m], > 0 (e.g. three cells of twice the target's minimum dimension).

        Returns
        -------
        numpy.ndarray
            (..., n_classes) fractions summing to 1 over the part of the window on the map;
            NaN where the window misses the map.
        """
        xx, yy, side = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (x, y, window)))
        if np.any(~(side > 0)):
            raise ValueError("window must be > 0 m")
        half = side / 2.0
        u0 = (xx - half - self.origin[0]) / self.cell_size
        u1 = (xx + half - self.origin[0]) / self.cell_size
        v0 = (yy - half - self.origin[1]) / self.cell_size
        v1 = (yy + half - self.origin[1]) / self.cell_size
        area = (
            self._integral(u1, v1)
            - self._integral(u0, v1)
            - self._integral(u1, v0)
            + self._integral(u0, v0)
        )
        total = area.sum(axis=0)
        with np.errstate(invalid="ignore", divide="ignore"):
            fractions = np.where(total > 0, area / np.where(total > 0, total, 1.0), np.nan)
        return np.moveaxis(fractions, 0, -1)

    def clutter(self, x: Array, y: Array, window: Array, footprint: Array) -> tuple[Any, Any]:
        """Clutter (6.10) and background mean around targets, at the sensor's resolution.

        Parameters
        ----------
        x, y, window : array_like
            As in :meth:`weights` [m].
        footprint : array_like
            Pixel footprint on the ground at the target, ``R · IFOV`` [m], > 0.

        Returns
        -------
        clutter, background_mean : numpy.ndarray
            ``(Σ k_i σ_i²(footprint))^(1/2)`` and ``Σ k_i I_i`` [signal units].
        """
        k = self.weights(x, y, window)
        variance = np.array([c.variance for c in self.classes])
        reference = np.array([c.resolution for c in self.classes])
        intensity = np.array([c.intensity for c in self.classes])
        seen = resolution_variance(
            variance, reference, np.asarray(footprint, dtype=float)[..., None]
        )
        return np.sqrt(np.sum(k * seen, axis=-1)), np.sum(k * intensity, axis=-1)
