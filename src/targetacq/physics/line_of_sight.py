"""Line of sight over terrain: how much of each target's height an observer sees past the ground.

An elevation model is a grid of terrain altitudes [m] sampled at posts ``spacing`` apart:
post ``[i, j]`` (row ``i``, column ``j``) stands at east ``origin[0] + j · spacing``, north
``origin[1] + i · spacing``. **Row 0 is the southern edge; rows grow northward**, columns
eastward (the convention of :class:`targetacq.physics.terrain.TerrainMap`). A GeoTIFF, whose
rows run southward, is flipped on reading (:func:`read_elevation`). Between posts the terrain
is the bilinear interpolation of the four posts around.

The profile. For an observer at ``(x_o, y_o, z_o)`` and a target standing at ``(x_t, y_t)``
with its base at altitude ``z_t`` and a height ``h``, the terrain is sampled along the straight
ground track between them, once per row or column crossed: ``n = ⌈max(|Δu|, |Δv|)⌉`` steps,
``Δu, Δv`` the track's extent in posts, the samples at ``t_i = i / n`` (``i = 1 … n − 1``; the
end points are the observer's and the target's own places, not obstructions) at horizontal
distance ``d_i = t_i · D`` from the observer, ``D`` the track's length [m].

Earth curvature with refraction. Over a sphere of effective radius ``a = k R_e`` (``R_e`` =
:data:`EARTH_RADIUS`, ``k`` = :data:`STANDARD_K` = 4/3 for standard refraction: the ray's
curvature, a quarter of the Earth's, is folded into a larger Earth), a point at distance ``d``
from the observer lies ``d² / (2a)`` below the observer's tangent plane (the parabolic form of
``a − √(a² − d²)``, exact to ``(d/a)²`` relative: 1e-5 at 50 km). Measuring every altitude
from that plane, the terrain at ``d_i`` stands ``z(d_i) − d_i²/(2a)`` and the target's top
``z_t + h − D²/(2a)``; against the chord from the observer to a point at the target, the
terrain therefore rises by the Earth bulge

    ``b(d_o, d_t) = d_o · d_t / (2a)``,  ``d_o = d_i``, ``d_t = D − d_i``,

the standard form of the radio-propagation literature (ITU-R Recommendation P.452, the Earth
bulge term, with the median effective-radius factor ``k = 4/3``, ``a ≈ 8500 km``, of ITU-R
Recommendation P.834 and Bean & Dutton, *Radio Meteorology*, 1966, §1.7). Light refracts less
than radio waves (the geodetic coefficient of refraction ≈ 0.13 gives ``k ≈ 1.15``): ``k`` is
a parameter; ``k = inf`` is a flat Earth.

Visible fraction. The highest sight line from the observer over the profile has the slope
``s = max_i (z(d_i) − d_i²/(2a) − z_o) / d_i``; at the target it passes the altitude

    ``H = z_o + s · D + D²/(2a)``,

below which the target is hidden. The visible fraction of the target's vertical extent
``[z_t, z_t + h]`` is ``clip((z_t + h − H) / h, 0, 1)``: 1 fully seen (also where no sample
lies between, ``D`` under one post), 0 hidden. For a target beyond the smooth Earth's horizon
``d_h = √(2 a z_o)`` (flat terrain at altitude 0), ``H = (D − d_h)² / (2a)``: the classic hidden
height.

Rules. Positions are (east, north, altitude) [m] in the grid's frame, altitudes on the
elevation model's datum; the target's third coordinate is the altitude of its base (put a
target on the ground with :meth:`ElevationModel.height_at`). NaN in any input, or a NaN post
(a void) among the samples of a pair, gives NaN for that pair. A pair whose observer or target
lies outside the grid (``[origin, origin + (cols − 1) · spacing]`` east, likewise north) gives
NaN: the terrain there is unknown. An infinite position or a target height that is not > 0
raises ``ValueError``.

The loops run in numba where the ``fast`` extra is installed (:mod:`.line_of_sight_numba`), else
in NumPy over the flattened samples of chunks of pairs; both do the same arithmetic in the same
order and give the same numbers (tested equal).
"""

from __future__ import annotations

import importlib
import importlib.util
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array

__all__ = [
    "EARTH_RADIUS",
    "METHODS",
    "STANDARD_K",
    "ElevationModel",
    "line_of_sight",
    "read_elevation",
]

EARTH_RADIUS = 6_371_000.0
"""Mean radius of the Earth [m] (IUGG mean radius R1 = 6 371 008.8 m, rounded)."""

STANDARD_K = 4.0 / 3.0
"""Effective Earth-radius factor of standard refraction [1] (ITU-R P.834, median ``k``)."""

METHODS = ("auto", "numpy", "numba")
"""How :func:`line_of_sight` runs its loops: ``numba`` (the ``fast`` extra), ``numpy``, or
``auto`` (numba where installed)."""

_CHUNK_SAMPLES = 1 << 21  # NumPy path: samples per chunk of pairs (about 16 MB per array)


@dataclass(frozen=True, eq=False)
class ElevationModel:
    """A terrain elevation grid (module docstring: row 0 south, posts ``spacing`` apart).

    Attributes
    ----------
    elevation : numpy.ndarray
        (rows, cols) terrain altitudes [m], rows >= 2 and cols >= 2, finite or NaN (voids);
        kept as a read-only float64 copy.
    spacing : float
        Distance between neighbouring posts [m], > 0.
    origin : (float, float)
        East and north of post ``[0, 0]`` (the south-west corner) [m].
    """

    elevation: np.ndarray
    spacing: float
    origin: tuple[float, float]

    def __post_init__(self) -> None:
        grid = np.array(self.elevation, dtype=float, order="C", copy=True)
        if grid.ndim != 2 or grid.shape[0] < 2 or grid.shape[1] < 2:
            raise ValueError(
                f"elevation must be a 2-D grid of at least 2 x 2 posts, got shape {grid.shape}"
            )
        if np.isinf(grid).any():
            raise ValueError("elevation must be finite [m] (NaN marks a void), got inf")
        try:
            spacing = float(self.spacing)
        except (TypeError, ValueError):
            spacing = math.nan
        if not (math.isfinite(spacing) and spacing > 0):
            raise ValueError(f"spacing must be a finite distance > 0 m, got {self.spacing!r}")
        origin = tuple(float(v) for v in np.asarray(self.origin, dtype=float).reshape(-1))
        if len(origin) != 2 or not all(math.isfinite(v) for v in origin):
            raise ValueError(
                f"origin must be two finite numbers (east, north of post [0, 0]) [m], got "
                f"{self.origin!r}"
            )
        grid.flags.writeable = False
        object.__setattr__(self, "elevation", grid)
        object.__setattr__(self, "spacing", spacing)
        object.__setattr__(self, "origin", origin)

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """(east min, east max, north min, north max) of the posts [m]."""
        rows, cols = self.elevation.shape
        x0, y0 = self.origin
        return (x0, x0 + (cols - 1) * self.spacing, y0, y0 + (rows - 1) * self.spacing)

    def height_at(self, east: Array, north: Array) -> Any:
        """Terrain altitude at points [m], bilinear between posts; NaN outside the grid.

        Examples
        --------
        >>> grid = ElevationModel([[0.0, 10.0], [20.0, 30.0]], spacing=100.0, origin=(0.0, 0.0))
        >>> float(grid.height_at(50.0, 50.0)), bool(np.isnan(grid.height_at(-1.0, 0.0)))
        (15.0, True)
        """
        x, y = np.broadcast_arrays(np.asarray(east, dtype=float), np.asarray(north, dtype=float))
        u = (x - self.origin[0]) / self.spacing
        v = (y - self.origin[1]) / self.spacing
        rows, cols = self.elevation.shape
        inside = (u >= 0) & (u <= cols - 1) & (v >= 0) & (v <= rows - 1)
        out = _bilinear(self.elevation, np.where(inside, u, 0.0), np.where(inside, v, 0.0))
        return _arrays.result(np.where(inside, out, np.nan))


def _bilinear(grid: np.ndarray, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The grid at fractional post coordinates ``(u, v)`` inside it (the numba kernel's order)."""
    rows, cols = grid.shape
    j = np.minimum(u.astype(np.int64), cols - 2)
    i = np.minimum(v.astype(np.int64), rows - 2)
    fu = u - j
    fv = v - i
    south = grid[i, j] + fu * (grid[i, j + 1] - grid[i, j])
    north = grid[i + 1, j] + fu * (grid[i + 1, j + 1] - grid[i + 1, j])
    return south + fv * (north - south)


def _numba_available() -> bool:
    return importlib.util.find_spec("numba") is not None


def line_of_sight(
    elevation: Array | ElevationModel,
    spacing: float | None,
    origin: tuple[float, float] | None,
    observers: Array,
    targets: Array,
    target_heights: Array,
    *,
    k: float = STANDARD_K,
    method: str = "auto",
) -> Any:
    """Visible fraction of each target's height over the terrain (module docstring).

    ``H = z_o + D · max_i (z(d_i) − d_i²/(2kR_e) − z_o) / d_i + D²/(2kR_e)``,
    fraction ``= clip((z_t + h − H) / h, 0, 1)``; the Earth bulge ``d_o d_t / (2 k R_e)`` with
    ``k = 4/3`` (ITU-R P.452 and P.834).

    Parameters
    ----------
    elevation : array_like or ElevationModel
        (rows, cols) terrain altitudes [m], row 0 the southern edge (or an
        :class:`ElevationModel`, whose own ``spacing`` and ``origin`` are then used; pass None
        for both).
    spacing : float
        Distance between posts [m], > 0.
    origin : (float, float)
        East and north of post ``[0, 0]`` [m].
    observers : array_like (..., 3)
        East, north, altitude of each observer [m].
    targets : array_like (..., 3)
        East, north and the altitude of each target's base [m].
    target_heights : array_like (...)
        Each target's height [m], > 0 (or NaN).
    k : float
        Effective Earth-radius factor [1], > 0; ``inf`` for a flat Earth.
    method : {"auto", "numpy", "numba"}
        Where the loops run (:data:`METHODS`).

    Returns
    -------
    numpy.ndarray or float
        The visible fraction in [0, 1] over the broadcast of the leading axes of ``observers``
        and ``targets`` and ``target_heights``; NaN where an input is NaN, a sample is a void,
        or the observer or target is off the grid.

    Raises
    ------
    ValueError
        A grid or position of the wrong shape, an infinite position, a height not > 0, ``k``
        not > 0, an unknown ``method`` or ``numba`` asked for but not installed.

    Examples
    --------
    A 10 m wall half way between an observer 2 m up and a 4 m target on flat ground:

    >>> ground = np.zeros((3, 101)); ground[:, 50] = 10.0
    >>> observer, targets = [0.0, 10.0, 2.0], [[1000.0, 10.0, 0.0], [400.0, 10.0, 0.0]]
    >>> line_of_sight(ground, 10.0, (0.0, 0.0), observer, targets, 4.0).tolist()
    [0.0, 1.0]
    """
    if isinstance(elevation, ElevationModel):
        model = elevation
    elif spacing is None or origin is None:
        raise ValueError("a grid of elevations needs its spacing [m] and origin (east, north) [m]")
    else:
        model = ElevationModel(elevation, spacing, origin)
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    use_numba = method == "numba" or (method == "auto" and _numba_available())
    if method == "numba" and not _numba_available():
        raise ValueError(
            "method='numba' needs numba (the 'fast' extra: pip install targetacq[fast])"
        )
    if not (isinstance(k, (int, float)) and k > 0):
        raise ValueError(f"k (the effective Earth-radius factor) must be > 0 (or inf), got {k!r}")
    obs = np.asarray(observers, dtype=float)
    tgt = np.asarray(targets, dtype=float)
    height = np.asarray(target_heights, dtype=float)
    for name, value in (("observers", obs), ("targets", tgt)):
        if value.ndim < 1 or value.shape[-1] != 3:
            raise ValueError(
                f"{name} must have shape (..., 3): east, north, altitude [m]; got {value.shape}"
            )
        if np.isinf(value).any():
            raise ValueError(f"{name} must be finite [m] (or NaN), got inf")
    _arrays.require_positive_or_nan("target_heights", height, np, "m")
    if np.isinf(height).any():
        raise ValueError("target_heights must be finite [m] (or NaN), got inf")
    try:
        shape = np.broadcast_shapes(obs.shape[:-1], tgt.shape[:-1], height.shape)
    except ValueError:
        raise ValueError(
            f"observers {obs.shape}, targets {tgt.shape} and target_heights {height.shape} "
            "must broadcast over their leading axes"
        ) from None
    o = np.ascontiguousarray(np.broadcast_to(obs, (*shape, 3)).reshape(-1, 3))
    t = np.ascontiguousarray(np.broadcast_to(tgt, (*shape, 3)).reshape(-1, 3))
    h = np.ascontiguousarray(np.broadcast_to(height, shape).reshape(-1))
    curvature = 0.0 if math.isinf(k) else 1.0 / (2.0 * k * EARTH_RADIUS)
    if use_numba:
        kernel = importlib.import_module("targetacq.physics.line_of_sight_numba")
        out = np.empty(h.size)
        blocks = model.__dict__.get("_blocks")
        if blocks is None:  # made once per model (the model is frozen: kept beside its fields)
            blocks = model.__dict__["_blocks"] = kernel.block_maxima(model.elevation)
        kernel.visible_fractions(
            model.elevation, blocks, model.spacing, model.origin[0], model.origin[1], o, t, h,
            curvature, out,
        )  # fmt: skip
    else:
        out = _visible_numpy(model, o, t, h, curvature)
    return _arrays.result(out.reshape(shape))


def _visible_numpy(
    model: ElevationModel, o: np.ndarray, t: np.ndarray, h: np.ndarray, curvature: float
) -> np.ndarray:
    """The NumPy twin of :func:`targetacq.physics.line_of_sight_numba.visible_fractions`."""
    grid = model.elevation
    rows, cols = grid.shape
    x0, y0 = model.origin
    spacing = model.spacing
    u0 = (o[:, 0] - x0) / spacing
    v0 = (o[:, 1] - y0) / spacing
    u1 = (t[:, 0] - x0) / spacing
    v1 = (t[:, 1] - y0) / spacing
    du = u1 - u0
    dv = v1 - v0
    with np.errstate(invalid="ignore"):
        inside = (
            (u0 >= 0) & (u0 <= cols - 1) & (v0 >= 0) & (v0 <= rows - 1)
            & (u1 >= 0) & (u1 <= cols - 1) & (v1 >= 0) & (v1 <= rows - 1)
            & ~np.isnan(o[:, 2]) & ~np.isnan(t[:, 2]) & ~np.isnan(h)
        )  # fmt: skip
    out = np.full(h.size, np.nan)
    index = np.flatnonzero(inside)
    if index.size == 0:
        return out
    du, dv = du[index], dv[index]
    steps = np.ceil(np.maximum(np.abs(du), np.abs(dv))).astype(np.int64)
    distance = spacing * np.sqrt(du * du + dv * dv)
    counts = np.maximum(steps - 1, 0)  # interior samples per pair
    ends = np.cumsum(counts)
    start = 0
    while start < index.size:
        # A chunk of pairs with at most _CHUNK_SAMPLES samples (at least one pair).
        stop = int(np.searchsorted(ends, (ends[start - 1] if start else 0) + _CHUNK_SAMPLES))
        stop = max(stop, start + 1)
        part = slice(start, stop)
        pick = index[part]
        n = counts[part]
        total = int(n.sum())
        best = np.full(stop - start, -np.inf)
        void = np.zeros(stop - start, dtype=bool)
        if total:
            pair = np.repeat(np.arange(stop - start), n)
            first = np.cumsum(n) - n
            step = np.arange(total) - np.repeat(first, n) + 1  # i = 1 … n − 1
            frac = step / np.repeat(steps[part], n)
            u = u0[pick][pair] + du[part][pair] * frac
            v = v0[pick][pair] + dv[part][pair] * frac
            z = _bilinear(grid, u, v)
            d = distance[part][pair] * frac
            slope = (z - curvature * d * d - o[pick, 2][pair]) / d
            nan = np.isnan(slope)
            void = np.bincount(pair[nan], minlength=stop - start) > 0
            np.maximum.at(best, pair[~nan], slope[~nan])
        dist = distance[part]
        with np.errstate(invalid="ignore"):  # -inf · 0: no sample, taken just below
            hidden_to = o[pick, 2] + best * dist + curvature * dist * dist
        base = t[pick, 2]
        top = base + h[pick]
        fraction = np.minimum(np.maximum((top - hidden_to) / h[pick], 0.0), 1.0)
        fraction = np.where(best == -np.inf, 1.0, fraction)  # nothing between them
        out[pick] = np.where(void, np.nan, fraction)
        start = stop
    return out


def read_elevation(
    path: str | Path, spacing: float | None = None, origin: tuple[float, float] | None = None
) -> ElevationModel:
    """An elevation model from a ``.npy`` grid or a GeoTIFF.

    Parameters
    ----------
    path : str or Path
        ``.npy``: a (rows, cols) array of altitudes [m], row 0 the southern edge (module
        docstring), read without pickles; ``spacing`` and ``origin`` are then required.
        ``.tif`` / ``.tiff``: a single-band GeoTIFF (needs the ``terrain`` extra,
        ``tifffile``): its rows (north first) are flipped to run northward, its pixel size
        (square) is the spacing and the centre of its south-west pixel the origin (the
        ``PixelIsArea`` default; a ``PixelIsPoint`` raster's tie point is already a centre),
        both in the raster's own projected metres, unless given here; its ``GDAL_NODATA``
        value becomes NaN.
    spacing : float, optional
        Distance between posts [m], > 0.
    origin : (float, float), optional
        East and north of post ``[0, 0]`` (the south-west corner) [m].

    Raises
    ------
    ValueError
        Naming the file: missing, unreadable, not a 2-D numeric grid, an unknown suffix, a
        missing ``spacing`` / ``origin`` for a ``.npy`` grid, or a GeoTIFF without ``tifffile``
        or without its georeferencing tags.
    """
    source = Path(path)
    suffix = source.suffix.lower()
    if suffix not in (".npy", ".tif", ".tiff"):
        raise ValueError(f"{source}: an elevation model is a .npy grid or a GeoTIFF (.tif, .tiff)")
    if not source.is_file():
        raise ValueError(f"{source}: no such elevation file")
    if suffix == ".npy":
        if spacing is None or origin is None:
            raise ValueError(
                f"{source}: a .npy elevation grid needs its spacing [m] and origin (east, north "
                "of post [0, 0]) [m]"
            )
        try:
            grid = np.load(source, allow_pickle=False)
        except (OSError, ValueError) as error:
            raise ValueError(f"{source}: not a NumPy .npy grid: {error}") from None
        if not (np.issubdtype(grid.dtype, np.number) and not np.iscomplexobj(grid)):
            raise ValueError(f"{source}: the grid must hold real numbers, got {grid.dtype}")
        try:
            return ElevationModel(grid, spacing, origin)
        except ValueError as error:
            raise ValueError(f"{source}: {error}") from None
    return _read_geotiff(source, spacing, origin)


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _read_geotiff(
    source: Path, spacing: float | None, origin: tuple[float, float] | None
) -> ElevationModel:
    if importlib.util.find_spec("tifffile") is None:
        raise ValueError(
            f"{source}: reading a GeoTIFF needs tifffile (the 'terrain' extra: pip install "
            "targetacq[terrain]); or save the grid as .npy with its spacing and origin"
        )
    tifffile = importlib.import_module("tifffile")
    try:
        with tifffile.TiffFile(source) as tif:
            page = tif.pages[0]
            grid = np.asarray(page.asarray(), dtype=float)
            tags = {tag.name: tag.value for tag in page.tags.values()}
            keys = getattr(tif, "geotiff_metadata", None) or {}
    except Exception as error:  # tifffile raises several kinds on a bad file
        raise ValueError(f"{source}: not a readable TIFF: {error}") from None
    if grid.ndim != 2:
        raise ValueError(f"{source}: an elevation GeoTIFF has one band, got shape {grid.shape}")
    nodata = tags.get("GDAL_NODATA")
    if nodata is not None:
        text = str(nodata).strip("\x00 ")
        if _is_number(text):
            grid[grid == float(text)] = np.nan
    grid = grid[::-1]  # north first → row 0 south
    if spacing is None or origin is None:
        scale = tags.get("ModelPixelScaleTag")
        tie = tags.get("ModelTiepointTag")
        if scale is None or tie is None:
            raise ValueError(
                f"{source}: no GeoTIFF pixel scale and tie point: give spacing and origin"
            )
        sx, sy = float(scale[0]), float(scale[1])
        if not math.isclose(sx, sy, rel_tol=1e-9):
            raise ValueError(f"{source}: the pixels must be square, got {sx} x {sy}")
        pi, pj, _, gx, gy = (float(v) for v in tie[:5])
        west, north_edge = gx - pi * sx, gy + pj * sy  # the raster's upper-left corner
        point = (
            str(keys.get("GTRasterTypeGeoKey", "")).endswith("Point")
            or keys.get("GTRasterTypeGeoKey") == 2
        )
        half = 0.0 if point else 0.5
        rows = grid.shape[0]
        spacing = sx if spacing is None else spacing
        origin = (
            (west + half * sx, north_edge - (rows - 1 + half) * sy) if origin is None else origin
        )
    try:
        return ElevationModel(grid, spacing, origin)
    except ValueError as error:
        raise ValueError(f"{source}: {error}") from None
