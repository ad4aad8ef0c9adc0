"""Graded detection cues: how much a hot spot and a target's motion help detection.

Sonesson (2004) treats both as switches: a hot spot ("a strong signal source on a uniform
background", §3.9) is detected as if it had no clutter, and a moving target is "always detected"
(§1.3, §7.5). As switches they move P(detection) by up to 0.5 at a fixed range and jump where a
flag flips. Here each is a weight ``w`` in [0, 1] that grows smoothly with what makes the cue
visible, and the switched probability is reached only in the limit ``w = 1``
(:mod:`targetacq.acquisition.probabilities` applies them):

- hot spot: ``P = (1 − w_hot) P_base + w_hot P_hot``, ``P_hot`` the low-clutter curve;
- motion: ``P = (1 − w_move) P + w_move max(P_motion, P)``, ``P_motion`` the motion rule's
  (:data:`targetacq.acquisition.probabilities.MOTION_RULES`; ``always``: 1).

A flag (``hot_spot=True``, ``moving=True``) is the full weight, so the thesis's switches are the
limits of the graded forms.

Both weights are logistic in the logarithm of a ratio ``x`` to its 50 % point ``x50``,
``w = 1 / (1 + (x / x50)^−k)`` with ``k = ln 19 / ln √10 ≈ 2.557``: ``w`` runs from 0.05 at
``x50/√10`` to 0.95 at ``√10 · x50``, one decade for the transition. Its steepest slope is
``dw/d ln x = k/4 ≈ 0.64``, so a 1 % change of ``x`` moves ``w`` by at most 0.0064 and the
probability by at most that (the probabilities it blends lie in [0, 1]).

Hot spot (:func:`hot_spot_weight`). ``x`` is the hot spot's own signal-to-clutter ratio, Eq. (3.14)
with ``g_0,max`` the hot spot's peak (its contrast against the background's clutter and noise),
diluted where the hot spot is smaller than a resolution element: a source covering a fraction
``a < 1`` of an element spreads its contrast over the element, ``x = SCR_hot · min(1, a)`` (the
fill factor; the same dilution as the sensor noise's pixel gain below one pixel,
:func:`targetacq.physics.detector_noise.pixel_gain`). ``x50 = √10``: Table 3.5 splits the
clutter into high (SCR < 1), medium (1 ≤ SCR ≤ 10) and low (SCR > 10), and §3.9 models hot spots
"as objects without clutter", i.e. on the low-clutter curve; the weight puts the transition
across the medium region, 0.05 at its lower edge (SCR 1) and 0.95 at its upper edge (SCR 10).
The logistic and its width are this project's assumption.

Motion (:func:`motion_weight`). ``x`` is the target's angular speed across the line of sight in
the sensor's pixels (half a resolvable cycle, Fig. 3.3) per second. The eye's threshold for
seeing motion is about 1–2 arcmin/s against a stationary reference (the background scene is
one) and about 10–20 arcmin/s without one (H. Aubert 1886; H. W. Leibowitz, "The relation
between the rate threshold for the perception of movement and luminance for various durations
of exposure", J. Exp. Psychol. 49 (1955) 209–214; C. H. Graham, *Vision and Visual Perception*,
Wiley 1965, ch. 20). With the display magnified so that one pixel subtends about the eye's
acuity, 1–2 arcmin (the usual matching of an imager's display to the eye), this is about one
pixel per second: ``x50 = 1`` pixel/s, so a target crossing 0.3 pixel/s gains 5 % of the motion
cue and one crossing 3 pixels/s 95 %. The display magnification is this project's assumption;
give another 50 % point where it differs.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array

__all__ = [
    "CUE_SLOPE",
    "HOT_SPOT_RATIO_50",
    "MOTION_RATE_50",
    "cue_weight",
    "hot_spot_weight",
    "motion_weight",
]

CUE_SLOPE = math.log(19.0) / math.log(math.sqrt(10.0))
"""``k`` of the logistic weights: 0.05 to 0.95 over one decade of the ratio (≈ 2.557)."""

HOT_SPOT_RATIO_50 = math.sqrt(10.0)
"""A hot spot's SCR at half weight: the middle (in log) of Table 3.5's medium-clutter region."""

MOTION_RATE_50 = 1.0
"""Angular speed [pixels/s] at half weight of the motion cue (module docstring)."""


def cue_weight(ratio: Array, ratio50: Array, slope: float = CUE_SLOPE) -> Any:
    """Logistic weight in the log of a ratio: ``1 / (1 + (ratio / ratio50)^−slope)`` [1].

    Parameters
    ----------
    ratio : array_like
        x >= 0 (0 gives 0, +inf gives 1).
    ratio50 : array_like
        x50 > 0, the ratio at half weight.
    slope : float
        k > 0; ``dw/d ln x`` is at most ``k/4``.

    Returns
    -------
    array_like
        w in [0, 1].

    Examples
    --------
    >>> from targetacq.acquisition.cues import cue_weight
    >>> print(round(float(cue_weight(1.0, 1.0)), 4), round(float(cue_weight(10.0, 10**0.5)), 4))
    0.5 0.95
    """
    if not slope > 0:
        raise ValueError(f"slope must be > 0, got {slope!r}")
    xp, (x, x50) = _arrays.arrays(ratio, ratio50, names=("ratio", "ratio50"))
    _arrays.require_nonnegative("ratio", x, xp)
    _arrays.require_positive("ratio50", x50, xp)
    return _arrays.result(weight_of(x, x50, slope, xp))


def weight_of(x: Any, x50: Any, slope: float, xp: Any) -> Any:
    """:func:`cue_weight` of checked float arrays (the arithmetic kernel): ``(x/x50)^k`` over
    ``1 + (x/x50)^k``, taken as a logistic of ``k ln(x/x50)`` clipped so nothing overflows."""
    positive = x > 0
    with np.errstate(divide="ignore"):
        z = slope * (xp.log(xp.where(positive, x, 1.0)) - xp.log(x50))
    z = xp.minimum(xp.maximum(z, -50.0), 50.0)  # e^−50 < 2^−53: w rounds to 1 there
    w = 1.0 / (1.0 + xp.exp(-z))
    w = xp.where(positive, w, 0.0)
    return xp.where(xp.isnan(x) | xp.isnan(x50), xp.nan, w)


def hot_spot_weight(ratio: Array, elements: Array = 1.0, ratio50: Array = HOT_SPOT_RATIO_50) -> Any:
    """How much of the hot-spot cue a source gives: ``w(SCR_hot · min(1, a))`` [1].

    The logistic weight (:func:`cue_weight`) of the hot spot's signal-to-clutter ratio, diluted
    by the fraction ``a`` of a resolution element it covers when it is smaller than one (module
    docstring: 0.05 at SCR 1, 0.5 at √10, 0.95 at SCR 10, the edges of Table 3.5's medium
    region).

    Parameters
    ----------
    ratio : array_like
        The hot spot's SCR [1], >= 0: its peak contrast over the background's clutter and noise
        (Eq. (3.14) in Sonesson (2004)), when it fills a resolution element.
    elements : array_like, optional
        Resolution elements (pixels) the hot spot covers [1], >= 0; default 1 (no dilution).
    ratio50 : array_like, optional
        The SCR at half weight, > 0.

    Returns
    -------
    array_like
        w_hot in [0, 1].

    Examples
    --------
    A hot spot at SCR 10 filling its pixel gets 0.95 of the cue; covering a quarter of a pixel,
    its contrast is diluted to SCR 2.5:

    >>> from targetacq.acquisition.cues import hot_spot_weight
    >>> print(round(float(hot_spot_weight(10.0)), 4), round(float(hot_spot_weight(10.0, 0.25)), 4))
    0.95 0.3541
    """
    xp, (x, a, x50) = _arrays.arrays(
        ratio, elements, ratio50, names=("ratio", "elements", "ratio50")
    )
    _arrays.require_nonnegative("ratio", x, xp)
    _arrays.require_nonnegative("elements", a, xp)
    _arrays.require_positive("ratio50", x50, xp)
    return _arrays.result(weight_of(x * xp.minimum(a, 1.0), x50, CUE_SLOPE, xp))


def motion_weight(rate: Array, rate50: Array = MOTION_RATE_50) -> Any:
    """How much of the motion cue a target's angular speed gives: ``w(rate)`` [1].

    The logistic weight (:func:`cue_weight`) of the angular speed across the line of sight in
    pixels per second against the eye's motion threshold (module docstring: 1 pixel/s at half
    weight, 0.05 at 0.32 and 0.95 at 3.2 pixels/s).

    Parameters
    ----------
    rate : array_like
        Angular speed across the line of sight [pixels/s], >= 0: ``v_⊥ / (R · IFOV)``.
    rate50 : array_like, optional
        The speed at half weight [pixels/s], > 0.

    Returns
    -------
    array_like
        w_move in [0, 1].

    Examples
    --------
    >>> from targetacq.acquisition.cues import motion_weight
    >>> print([round(float(w), 4) for w in motion_weight([0.0, 1.0, 10**0.5])])
    [0.0, 0.5, 0.95]
    """
    xp, (x, x50) = _arrays.arrays(rate, rate50, names=("rate", "rate50"))
    _arrays.require_nonnegative("rate", x, xp)
    _arrays.require_positive("rate50", x50, xp)
    return _arrays.result(weight_of(x, x50, CUE_SLOPE, xp))
