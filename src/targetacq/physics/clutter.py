"""Clutter and the signal-to-clutter ratio.

Sources: Sonesson (2004) §3.7 (Eqs. (3.12)–(3.15)), §6.6 (Eqs. (6.7)–(6.11)). The SCR of a target
is its contrast against the mean of its surroundings in units of the clutter, the spatial
standard deviation of the surroundings:

- (3.14) positive contrast ``SCR = |g_0,max − g_mean| / clutter``; (3.15) negative contrast
  ``SCR = |g_0,min − g_mean| / clutter``; (6.9) from signals ``SCR = (o_max − c_mean) / clutter``;
- (6.10)–(6.11) from a terrain description: ``clutter = (Σ_i k_i σ_i²)^(1/2)``, ``Σ k_i = 1``,
  the weights being how often each class occurs around the target.

Zero clutter (a uniform background) gives an infinite SCR for any contrast; a target with no
contrast at all has SCR 0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array

__all__ = [
    "CHANNELS",
    "ImageClutter",
    "as_boxes",
    "gray",
    "image_clutter",
    "signal_to_clutter_ratio",
    "temperature_spread_clutter",
    "terrain_clutter",
]


def signal_to_clutter_ratio(target_signal: Array, background_mean: Array, clutter: Array) -> Any:
    """Signal-to-clutter ratio, Eqs. (3.14), (3.15) and (6.9) in Sonesson (2004).

    ``SCR = |target − background_mean| / clutter``. Pass the target's maximum for positive
    contrast (3.14) or its minimum for negative contrast (3.15).

    Parameters
    ----------
    target_signal : array_like
        g_0,max (or g_0,min), or o_max of Eq. (6.18), in any signal unit.
    background_mean : array_like
        g_mean or c_mean, same unit.
    clutter : array_like
        Clutter (3.12) or (6.10), same unit, >= 0.

    Returns
    -------
    array_like
        SCR >= 0; +inf where clutter is 0 and the contrast is not; 0 where the contrast is 0;
        NaN where an input is NaN or both signals are infinite.

    Examples
    --------
    A target at 12 against a background mean of 10 with clutter 0.5: ``|12 − 10| / 0.5``.

    >>> import targetacq as ta
    >>> print(f"{ta.signal_to_clutter_ratio(12.0, 10.0, 0.5):.2f}")
    4.00
    """
    xp, (t, b, c) = _arrays.arrays(
        target_signal,
        background_mean,
        clutter,
        names=("target_signal", "background_mean", "clutter"),
    )
    _arrays.require_nonnegative("clutter", c, xp)
    with np.errstate(invalid="ignore"):  # both signals infinite: the contrast is unknown, NaN
        contrast = xp.abs(t - b)
    ratio = contrast / xp.where(c > 0, c, 1.0)
    out = xp.where(c > 0, ratio, xp.where(contrast > 0, xp.inf, xp.zeros_like(contrast)))
    return _arrays.result(xp.where(xp.isnan(c) | xp.isnan(contrast), xp.nan, out))


def temperature_spread_clutter(
    emissivity: Array, temperature: Array, temperature_std: Array, band: Any
) -> Any:
    """Clutter of a thermal background given as a spread of temperatures [W/m²].

    A background of mean temperature T whose temperature varies from place to place with the
    standard deviation σ_T has, for spreads small against T, an exitance spread
    ``clutter = ε · dM_band/dT · σ_T``: the linearised (6.12) over the band. This is the clutter
    of (6.9)–(6.10) in the signal unit of the band exitance.

    Parameters
    ----------
    emissivity : array_like
        ε of the background, in [0, 1].
    temperature : array_like
        Mean background temperature T [K], >= 0.
    temperature_std : array_like
        σ_T [K], >= 0.
    band : str or (float, float)
        The sensor's band.

    Returns
    -------
    array_like
        Clutter [W/m²].

    Examples
    --------
    >>> from targetacq.physics.radiometry import band_exitance_derivative
    >>> slope = band_exitance_derivative(295.0, "lwir")
    >>> bool(abs(temperature_spread_clutter(0.9, 295.0, 2.0, "lwir") - 0.9 * slope * 2.0) < 1e-12)
    True
    """
    from targetacq.physics.radiometry import band_exitance_derivative

    xp, (eps, t, spread) = _arrays.arrays(
        emissivity,
        temperature,
        temperature_std,
        names=("emissivity", "temperature", "temperature_std"),
    )
    _arrays.require_unit_interval("emissivity", eps, xp)
    _arrays.require_nonnegative("temperature_std", spread, xp, "K")
    return _arrays.result(eps * band_exitance_derivative(t, band) * spread)


def terrain_clutter(weights: Array, variances: Array, axis: int = -1) -> Any:
    """Clutter from a terrain description, ``(Σ_i k_i σ_i²)^(1/2)``, Eqs. (6.10)–(6.11).

    Parameters
    ----------
    weights : array_like
        k_i, the fraction of the surroundings covered by each class, >= 0, summing to 1 along
        ``axis`` (Eq. (6.11)).
    variances : array_like
        σ_i² of each class's signal at the sensor's resolution [signal unit²], >= 0.
    axis : int
        The class axis.

    Returns
    -------
    array_like
        Clutter [signal unit].

    Examples
    --------
    Three quarters grass (variance 4), one quarter forest (variance 16):
    ``sqrt(0.75 · 4 + 0.25 · 16) = sqrt(7)``.

    >>> import targetacq as ta
    >>> print(f"{ta.terrain_clutter([0.75, 0.25], [4.0, 16.0]):.4f}")
    2.6458
    """
    xp, (k, v) = _arrays.arrays(weights, variances, names=("weights", "variances"))
    _arrays.require_nonnegative("weights", k, xp)
    _arrays.require_nonnegative("variances", v, xp)
    total = xp.sum(k, axis=axis)
    if bool(xp.any(xp.abs(total - 1.0) > 1e-9)):
        raise ValueError("weights must sum to 1 over the classes (Eq. (6.11))")
    return _arrays.result(xp.sqrt(xp.sum(k * v, axis=axis)))


# --- clutter measured in an image (Schmieder & Weathersby cells, Fig. 3.6) ------------------------

_CELL_OFFSETS = tuple((i, j) for j in (-1, 0, 1) for i in (-1, 0, 1))  # row-major, centre is 4
_MIN_CELL_PIXELS = 2  # a standard deviation needs two background pixels


@dataclass(frozen=True)
class ImageClutter:
    """Clutter and SCR of targets in one image, one entry per box.

    Attributes
    ----------
    clutter : numpy.ndarray
        (3.12): RMS of the cells' standard deviations [image units]; 0 for a uniform
        background. (A box with no cell of two background pixels is refused:
        :func:`as_boxes`.)
    scr_positive, scr_negative : numpy.ndarray
        (3.14) ``|g_0,max − g_mean| / clutter`` and (3.15) ``|g_0,min − g_mean| / clutter``;
        +inf where the clutter is 0 and the contrast is not.
    scr : numpy.ndarray
        The larger of the two: the target's stronger contrast, which picks its region.
    region : numpy.ndarray of str
        Table 3.5 region of ``scr``: "low", "medium", "high".
    background_mean : numpy.ndarray
        g_mean, the mean of the background pixels of the cells [image units].
    target_max, target_min : numpy.ndarray
        g_0,max and g_0,min over the box [image units].
    cells : numpy.ndarray
        (k, 9, 4) cell rectangles (x0, y0, x1, y1), clipped to the image, end-exclusive;
        row-major from the top left, the centre cell at index 4.
    cell_pixels : numpy.ndarray
        (k, 9) background pixels in each cell (0: the cell was left out).
    """

    clutter: Any
    scr_positive: Any
    scr_negative: Any
    scr: Any
    region: Any
    background_mean: Any
    target_max: Any
    target_min: Any
    cells: Any
    cell_pixels: Any


def as_boxes(boxes: Any, shape: tuple[int, int], cell_factor: float = 2.0) -> Any:
    """Validated (k, 4) integer array of (x, y, width, height) boxes inside an image, each
    with background around it for :func:`image_clutter`'s cells of ``cell_factor``.

    Raises
    ------
    ValueError
        For a box that is not four integers, has zero or negative size, or leaves the image;
        or that leaves no background to measure the clutter on: no cell of :func:`image_clutter`
        (``cell_factor`` times the box's smaller side) has two pixels outside the box, as for a
        box covering the whole image or a 1 x 1 image (whose clutter, SCR and probabilities
        would all be NaN).
    """
    import numpy as np

    array = np.asarray(boxes, dtype=float)
    if array.ndim == 1:
        array = array[None, :]
    if array.ndim != 2 or array.shape[1] != 4 or array.shape[0] == 0:
        raise ValueError("boxes must be rows of (x, y, width, height) in pixels")
    if not np.all(np.isfinite(array)) or np.any(array != np.round(array)):
        raise ValueError("boxes must be whole numbers of pixels (x, y, width, height)")
    b = array.astype(np.int64)
    height, width = shape
    for k, (x, y, w, h) in enumerate(b):
        if w < 1 or h < 1:
            raise ValueError(f"box {k} ({x}, {y}, {w}, {h}) has zero or negative size")
        if x < 0 or y < 0 or x + w > width or y + h > height:
            raise ValueError(
                f"box {k} ({x}, {y}, {w}, {h}) leaves the {width} x {height} image "
                "(x + width <= image width, y + height <= image height)"
            )
    side, _, n = _cells(b, shape, cell_factor)
    for k, used in enumerate((n >= _MIN_CELL_PIXELS).any(axis=1)):
        if not used:
            x, y, w, h = b[k]
            raise ValueError(
                f"box {k} ({x}, {y}, {w}, {h}) leaves no background in the {width} x {height} "
                "image to measure its clutter on (Eq. (3.12) takes the background pixels "
                f"around the box, in cells of {side[k]} px: none has two outside it); give a "
                "smaller box, a larger image, or (for a thin box) a larger cell factor"
            )
    return b


def _cells(b: Any, shape: tuple[int, int], cell_factor: float) -> tuple[Any, Any, Any]:
    """The cell side of each box, its 3 × 3 cells (k, 9, 4) as (x0, y0, x1, y1) clipped to the
    image, end-exclusive, and the background pixels (outside the box) in each (k, 9)."""
    import numpy as np

    height, width = shape
    x, y, w, h = (b[:, i] for i in range(4))
    side = np.maximum(1, np.round(cell_factor * np.minimum(w, h))).astype(np.int64)
    # The centre cell is centred on the box centre; the other eight tile around it.
    cx0 = np.floor(x + w / 2.0 - side / 2.0).astype(np.int64)
    cy0 = np.floor(y + h / 2.0 - side / 2.0).astype(np.int64)
    di = np.array([i for i, _ in _CELL_OFFSETS])
    dj = np.array([j for _, j in _CELL_OFFSETS])
    x0 = np.clip(cx0[:, None] + di * side[:, None], 0, width)
    y0 = np.clip(cy0[:, None] + dj * side[:, None], 0, height)
    x1 = np.clip(cx0[:, None] + (di + 1) * side[:, None], 0, width)
    y1 = np.clip(cy0[:, None] + (dj + 1) * side[:, None], 0, height)
    # The box's part in each cell, left out.
    bx0, by0 = np.maximum(x0, x[:, None]), np.maximum(y0, y[:, None])
    bx1, by1 = np.minimum(x1, (x + w)[:, None]), np.minimum(y1, (y + h)[:, None])
    bx1, by1 = np.maximum(bx1, bx0), np.maximum(by1, by0)
    n = (x1 - x0) * (y1 - y0) - (bx1 - bx0) * (by1 - by0)
    return side, np.stack([x0, y0, x1, y1, bx0, by0, bx1, by1], axis=-1), n


def _summed_area(values: Any) -> Any:
    import numpy as np

    table = np.zeros((values.shape[0] + 1, values.shape[1] + 1), dtype=np.float64)
    np.cumsum(values, axis=0, out=table[1:, 1:])
    np.cumsum(table[1:, 1:], axis=1, out=table[1:, 1:])
    return table


def _rect_sum(table: Any, x0: Any, y0: Any, x1: Any, y1: Any) -> Any:
    """Sum over [x0, x1) × [y0, y1) from a summed-area table (empty rectangles give 0)."""
    return table[y1, x1] - table[y0, x1] - table[y1, x0] + table[y0, x0]


def image_clutter(image: Array, boxes: Array, cell_factor: float = 2.0) -> ImageClutter:
    """Clutter, SCR and clutter region of targets in an image, Eqs. (3.12)–(3.15), Fig. 3.6.

    Around each box, a 3 × 3 grid of square cells of side ``round(cell_factor · min(w, h))``
    (about twice the target's minimum dimension, §3.7) is laid with the centre cell on the box's
    centre. Each cell's variance is the ordinary (population) variance of its pixels (the
    erratum to Eq. (3.13), see the user guide's errata); the clutter is the RMS of the cells'
    standard deviations (3.12).

    Choices, documented:

    - the target's own pixels (its box) are left out of every cell, so the clutter describes
      the background it must be told apart from; ``g_mean`` is the mean of those background
      pixels;
    - cells are clipped at the image edge and keep the pixels inside it; a cell with fewer than
      two background pixels is left out;
    - cell sums come from summed-area tables of the image and its square (after subtracting the
      image mean, which keeps the float64 sums well conditioned): the image is read once,
      then every cell costs O(1), so thousands of boxes cost about as much as one;
    - a cell variance within floating-point rounding of zero (below ``64 ε`` times the table's
      largest sum over the cell's pixel count) is zero; zero clutter gives an infinite SCR.

    Parameters
    ----------
    image : array_like
        2-D image of any real dtype (8- or 16-bit thermal counts included). For a colour image,
        pick a channel first (:func:`targetacq.physics.clutter.gray`).
    boxes : array_like
        (k, 4) rows of (x, y, width, height) in pixels, x to the right, y down, inside the image.
    cell_factor : float
        Cell side over the box's minimum dimension, > 0 (2 in Schmieder & Weathersby).

    Returns
    -------
    ImageClutter

    Raises
    ------
    ValueError
        For an image that is not 2-D real numbers, a ``cell_factor`` that is not > 0, or a box
        :func:`as_boxes` refuses: outside the image, or with no background around it (no cell
        with two pixels outside the box, e.g. a box covering the whole image, or a 1 x 1
        image), where the clutter would be undefined.

    Examples
    --------
    A background of alternating rows at 10 and 11 (every cell's standard deviation 0.5, mean
    10.5) and a 10 × 10 target at 14: ``SCR = |14 − 10.5| / 0.5 = 7``, medium clutter.

    >>> import numpy as np
    >>> import targetacq as ta
    >>> image = np.full((60, 60), 10.0)
    >>> image[::2, :] += 1.0
    >>> image[25:35, 25:35] = 14.0
    >>> found = ta.image_clutter(image, [(25, 25, 10, 10)])
    >>> print(np.round(found.clutter, 6), np.round(found.scr, 6), found.region)
    [0.5] [7.] ['medium']
    """
    import numpy as np

    from targetacq.acquisition.transforms import clutter_region

    img = np.asarray(image)
    if img.ndim != 2:
        raise ValueError(
            f"image must be 2-D (one channel); got shape {img.shape}: pick a channel of a colour "
            "image with targetacq.physics.clutter.gray(image, channel)"
        )
    if not (
        np.issubdtype(img.dtype, np.number) and not np.issubdtype(img.dtype, np.complexfloating)
    ):
        raise ValueError(f"image must be real numbers, got dtype {img.dtype}")
    if not (
        isinstance(cell_factor, (int, float)) and math.isfinite(cell_factor) and cell_factor > 0
    ):
        raise ValueError(f"cell_factor must be a finite number > 0, got {cell_factor!r}")
    b = as_boxes(boxes, img.shape, cell_factor)
    values = img.astype(np.float64)
    reference = float(values.mean())
    shifted = values - reference
    sat1 = _summed_area(shifted)
    sat2 = _summed_area(shifted * shifted)

    _, corners, n = _cells(b, img.shape, cell_factor)
    x0, y0, x1, y1, bx0, by0, bx1, by1 = np.moveaxis(corners, -1, 0)
    s1 = _rect_sum(sat1, x0, y0, x1, y1) - _rect_sum(sat1, bx0, by0, bx1, by1)
    s2 = _rect_sum(sat2, x0, y0, x1, y1) - _rect_sum(sat2, bx0, by0, bx1, by1)
    used = n >= _MIN_CELL_PIXELS
    safe_n = np.where(used, n, 1)
    mean = s1 / safe_n
    variance = s2 / safe_n - mean * mean
    rounding = 64.0 * np.finfo(np.float64).eps * float(sat2[-1, -1]) / safe_n
    variance = np.where(variance <= rounding, 0.0, variance)
    variance = np.where(used, variance, 0.0)
    cells_used = used.sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        clutter = np.where(
            cells_used > 0, np.sqrt(variance.sum(axis=1) / np.maximum(cells_used, 1)), np.nan
        )
        pixels = np.where(used, n, 0).sum(axis=1)
        background_mean = (
            np.where(
                pixels > 0, np.where(used, s1, 0.0).sum(axis=1) / np.maximum(pixels, 1), np.nan
            )
            + reference
        )

    target_max = np.array([values[yy : yy + hh, xx : xx + ww].max() for xx, yy, ww, hh in b])
    target_min = np.array([values[yy : yy + hh, xx : xx + ww].min() for xx, yy, ww, hh in b])
    scr_pos = np.asarray(signal_to_clutter_ratio(target_max, background_mean, _nan_safe(clutter)))
    scr_neg = np.asarray(signal_to_clutter_ratio(target_min, background_mean, _nan_safe(clutter)))
    scr_pos = np.where(np.isnan(clutter), np.nan, scr_pos)
    scr_neg = np.where(np.isnan(clutter), np.nan, scr_neg)
    scr = np.fmax(scr_pos, scr_neg)
    region = np.where(np.isnan(scr), "", clutter_region(np.where(np.isnan(scr), 0.0, scr)))
    cells = np.stack([x0, y0, x1, y1], axis=-1)
    return ImageClutter(
        clutter=clutter,
        scr_positive=scr_pos,
        scr_negative=scr_neg,
        scr=scr,
        region=region,
        background_mean=background_mean,
        target_max=target_max,
        target_min=target_min,
        cells=cells,
        cell_pixels=np.where(used, n, 0),
    )


def _nan_safe(clutter: Any) -> Any:
    import numpy as np

    return np.where(np.isnan(clutter), 1.0, clutter)


CHANNELS: tuple[str, ...] = ("luminance", "red", "green", "blue")
"""How to make one channel of a colour image: ITU-R BT.601 luminance or one colour."""


def gray(image: Array, channel: str | None = None) -> Any:
    """One channel of an image: a 2-D image unchanged; for colour (H, W, 3|4), ``channel``.

    Parameters
    ----------
    image : array_like
        2-D, or (H, W, 3) / (H, W, 4) colour (alpha ignored).
    channel : {"luminance", "red", "green", "blue"}
        Required for colour: clutter is measured on one signal. "luminance" is
        ``0.299 R + 0.587 G + 0.114 B`` (ITU-R BT.601), close to what a TV sensor records.
    """
    import numpy as np

    img = np.asarray(image)
    if img.ndim == 2:
        return img
    if img.ndim != 3 or img.shape[2] not in (3, 4):
        raise ValueError(f"image must be 2-D or (H, W, 3|4) colour; got shape {img.shape}")
    if channel is None:
        raise ValueError(
            f"a colour image needs a channel to measure clutter on: one of {', '.join(CHANNELS)}"
        )
    if channel not in CHANNELS:
        raise ValueError(f"channel must be one of {', '.join(CHANNELS)}; got {channel!r}")
    rgb = img[..., :3].astype(np.float64)
    if channel == "luminance":
        return rgb @ np.array([0.299, 0.587, 0.114])
    return rgb[..., CHANNELS.index(channel) - 1]
