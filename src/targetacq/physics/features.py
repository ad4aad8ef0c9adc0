"""Signature features of a target region, Eqs. (2.6)–(2.12) in Sonesson (2004), §2.8.2.

The thesis lists these features from the image-processing literature without fixing every
detail; the choices made here are stated per feature:

- (2.6) aspect ``d_min / d_max`` of the smallest axis-aligned rectangle around the target;
- (2.7) ``σ_I / I_mean`` over the target's pixels;
- (2.8) ``A / (P² Z(A))`` with ``Z = 1/(4π)``, i.e. the isoperimetric quotient ``4πA/P²`` (1 for a
  disc in the continuous limit), P the crack length (pixel edges between target and
  background);
- (2.9) mean edge strength ``Σ_k E_k / A``, ``E_k = 1`` where the Sobel gradient magnitude exceeds
  the background's mean plus two standard deviations (an edge is a gradient unusual for the
  surroundings), the detector named ``sobel``;
- (2.10) FORM factor ``A / d̄²``, d̄ the mean Euclidean distance of the target's pixels to the
  nearest background pixel (area over mean shortest distance to the perimeter, squared);
- (2.11) ``I_mean = Σ_k I_k / A``;
- (2.12) contrast ``(I_mean − B_median) / sqrt(σ_I² + σ_B² + ε)`` against the surrounding
  background (the cells of :func:`targetacq.physics.clutter.image_clutter`), ε = 1e-12 by default.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from targetacq.base.arrays import Array
from targetacq.physics.clutter import as_boxes, image_clutter

__all__ = ["EDGE_DETECTORS", "TargetFeatures", "target_features"]


def _sobel_magnitude(image: np.ndarray) -> np.ndarray:
    return np.hypot(ndimage.sobel(image, axis=1), ndimage.sobel(image, axis=0))


EDGE_DETECTORS = {"sobel": _sobel_magnitude}
"""Edge detectors for (2.9), by name: gradient magnitude images."""


@dataclass(frozen=True)
class TargetFeatures:
    """Features of one target (see the module docstring for each definition)."""

    aspect: float
    std_over_mean: float
    compactness: float
    edge_strength: float
    form_factor: float
    mean_intensity: float
    contrast: float
    area: int
    perimeter: int


def _crack_length(mask: np.ndarray) -> int:
    padded = np.pad(mask, 1)
    return int(np.sum(padded[1:, :] != padded[:-1, :]) + np.sum(padded[:, 1:] != padded[:, :-1]))


def target_features(
    image: Array,
    box: Array,
    mask: Array = None,
    cell_factor: float = 2.0,
    edge_detector: str = "sobel",
    eps: float = 1e-12,
) -> TargetFeatures:
    """Signature features of a target, Eqs. (2.6)–(2.12).

    Parameters
    ----------
    image : array_like
        2-D image.
    box : array_like
        (x, y, width, height) of the target in pixels.
    mask : array_like of bool, optional
        The target's silhouette inside the box, shape (height, width); default: the whole box.
    cell_factor : float
        Cell size for the surrounding background, as in
        :func:`targetacq.physics.clutter.image_clutter`.
    edge_detector : str
        A name from :data:`EDGE_DETECTORS`.
    eps : float
        ε of (2.12), >= 0.

    Returns
    -------
    TargetFeatures
    """
    if edge_detector not in EDGE_DETECTORS:
        raise ValueError(
            f"edge_detector must be one of {', '.join(EDGE_DETECTORS)}; got {edge_detector!r}"
        )
    if not eps >= 0:
        raise ValueError(f"eps must be >= 0, got {eps!r}")
    img = np.asarray(image, dtype=np.float64)
    if img.ndim != 2:
        raise ValueError(f"image must be 2-D (one channel); got shape {img.shape}")
    ((x, y, w, h),) = as_boxes(box, img.shape, cell_factor)
    silhouette = np.ones((h, w), dtype=bool) if mask is None else np.asarray(mask, dtype=bool)
    if silhouette.shape != (h, w):
        raise ValueError(f"mask must have the box's shape (height, width) = ({h}, {w})")
    if not silhouette.any():
        raise ValueError("mask selects no pixel")
    full = np.zeros(img.shape, dtype=bool)
    full[y : y + h, x : x + w] = silhouette
    background = np.zeros(img.shape, dtype=bool)
    for x0, y0, x1, y1 in image_clutter(img, [(x, y, w, h)], cell_factor).cells[0]:
        background[y0:y1, x0:x1] = True
    background &= ~full

    target = img[full]
    rows, cols = np.nonzero(silhouette)
    sides = sorted((rows.max() - rows.min() + 1, cols.max() - cols.min() + 1))
    mean = float(target.mean())
    std = float(target.std())
    area = int(silhouette.sum())
    perimeter = _crack_length(silhouette)
    distance = ndimage.distance_transform_edt(np.pad(silhouette, 1))[1:-1, 1:-1][silhouette]
    magnitude = EDGE_DETECTORS[edge_detector](img)
    if background.any():
        bg = img[background]
        bg_magnitude = magnitude[background]
        threshold = float(bg_magnitude.mean() + 2.0 * bg_magnitude.std())
        b_median, b_std = float(np.median(bg)), float(bg.std())
    else:
        threshold, b_median, b_std = math.inf, math.nan, math.nan
    edges = magnitude[full] > threshold
    denominator = math.sqrt(std**2 + b_std**2 + eps)
    return TargetFeatures(
        aspect=float(sides[0] / sides[1]),
        std_over_mean=std / mean if mean != 0 else math.inf,
        compactness=4.0 * math.pi * area / perimeter**2,
        edge_strength=float(edges.sum() / area),
        form_factor=float(area / float(distance.mean()) ** 2),
        mean_intensity=mean,
        contrast=(mean - b_median) / denominator if denominator > 0 else math.inf,
        area=area,
        perimeter=perimeter,
    )
