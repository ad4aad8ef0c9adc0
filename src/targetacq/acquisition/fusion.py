"""Fusion of several sensors' probabilities for one target.

Sources: Sonesson (2004) ch. 8. Sensor-level fusion of independent sensors (8.2)–(8.4):
``P_SL = 1 - Π_i (1 - p_i)``: the target is acquired unless every sensor misses it. Central-level
fusion (8.5) has no formula in the thesis, only the bounds ``P_SL <= P_CL <= 1``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array

__all__ = ["central_level_bounds", "fuse", "fuse_groups"]


def fuse(probabilities: Array, axis: int = -1) -> Any:
    """Sensor-level fusion of independent sensors, Eq. (8.4) in Sonesson (2004).

    ``P_SL = 1 - Π_i (1 - p_i)`` over ``axis``.

    Parameters
    ----------
    probabilities : array_like
        Probabilities in [0, 1]; the sensors lie along ``axis``.
    axis : int
        Axis of the sensors.

    Returns
    -------
    array_like
        Fused probability, ``axis`` removed; symmetric in the sensors and >= each input.

    Examples
    --------
    Two sensors with 0.5 and 0.3 miss together with probability ``0.5 · 0.7``; one row per
    target:

    >>> import numpy as np
    >>> import targetacq as ta
    >>> print(f"{ta.fuse([0.5, 0.3]):.2f}")
    0.65
    >>> print(np.round(ta.fuse([[0.5, 0.3], [0.9, 0.1]]), 4))
    [0.65 0.91]
    """
    xp, (p,) = _arrays.arrays(probabilities, names=("probabilities",))
    _arrays.require_unit_interval("probabilities", p, xp)
    if p.ndim == 0:
        raise ValueError("probabilities must have at least one axis (the sensors)")
    return _arrays.result(fused_along(p, axis, xp))


def fused_along(p: Any, axis: int, xp: Any) -> Any:
    """:func:`fuse` of a checked float array (the arithmetic kernel)."""
    if isinstance(p, np.ndarray):  # the product's own reduction, without its wrapper
        return 1.0 - np.multiply.reduce(1.0 - p, axis=axis)
    return 1.0 - xp.prod(1.0 - p, axis=axis)


def fuse_groups(probabilities: Array, groups: Any, axis: int = 0) -> Any:
    """Sensor-level fusion of groups of completely dependent sensors.

    Within a group (the colour bands of one camera: one look at one picture through one
    optics) the sensors are taken as comonotone, so the group finds a target exactly when its
    best member does: ``P_group = max_i p_i``, the upper Fréchet–Hoeffding bound of the
    dependence. The groups are independent sensors, fused by Eq. (8.4) in Sonesson (2004):
    ``P_SL = 1 − Π_groups (1 − P_group)``. Groups of one sensor each give :func:`fuse`.

    Parameters
    ----------
    probabilities : array_like
        Probabilities in [0, 1]; the sensors lie along ``axis``.
    groups : sequence of str
        The group of each sensor (as many as the sensors along ``axis``).
    axis : int
        Axis of the sensors.

    Returns
    -------
    array_like
        Fused probability, ``axis`` removed; NaN where a sensor's probability is NaN.

    Examples
    --------
    Three identical colour bands of one camera are the camera itself; a second camera with
    0.3 is independent of it:

    >>> import targetacq as ta
    >>> print(f"{ta.fuse_groups([0.5, 0.5, 0.5], ['rgb', 'rgb', 'rgb']):.4f}")
    0.5000
    >>> print(f"{ta.fuse_groups([0.5, 0.2, 0.5, 0.3], ['rgb', 'rgb', 'rgb', 'ir']):.4f}")
    0.6500
    """
    xp, (p,) = _arrays.arrays(probabilities, names=("probabilities",))
    _arrays.require_unit_interval("probabilities", p, xp)
    p = xp.moveaxis(p, axis, 0) if axis != 0 else p
    names = list(groups)
    if not names:
        raise ValueError("groups must name at least one sensor's group")
    if len(names) != p.shape[0]:
        raise ValueError(
            f"groups must name the group of each of the {p.shape[0]} sensors; got {len(names)}"
        )
    order = list(dict.fromkeys(names))
    best = []
    for name in order:
        members = [k for k, g in enumerate(names) if g == name]
        rows = [p[k] for k in members]
        top = rows[0]
        for row in rows[1:]:
            # NaN in any band is NaN for the camera (xp.maximum keeps NaN).
            top = xp.maximum(top, row)
        best.append(top)
    return _arrays.result(fused_along(xp.stack(best, axis=0), 0, xp))


def central_level_bounds(probabilities: Any, axis: int = -1) -> tuple[Any, Any]:
    """Bounds on central-level fusion, ``P_SL <= P_CL <= 1``, Eq. (8.5) in Sonesson (2004).

    Returns
    -------
    lower, upper : array_like
        The sensor-level fusion :func:`fuse` and 1 (NaN where the inputs have NaN).

    Examples
    --------
    >>> import targetacq as ta
    >>> low, high = ta.central_level_bounds([0.5, 0.3])
    >>> print(f"{low:.2f} {high:.2f}")
    0.65 1.00
    """
    lower = fuse(probabilities, axis=axis)
    xp, (low,) = _arrays.arrays(lower)
    upper = xp.where(xp.isnan(low), low, xp.ones_like(low))
    return lower, _arrays.result(upper)
