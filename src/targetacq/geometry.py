"""Viewing geometry: slant range, solid angle and the critical dimension seen by a sensor.

Sources: Sonesson (2004) ch. 3 (§3.1–3.2, Eqs. (3.1)–(3.5), Fig. 3.3). The projected box
extents are elementary orthographic projection; see :func:`projected_extents`.
"""

from __future__ import annotations

from collections.abc import Callable
from types import MappingProxyType
from typing import Any

from targetacq import _arrays
from targetacq._arrays import Array

__all__ = [
    "CRITICAL_DIMENSION_METHODS",
    "critical_dimension",
    "projected_extents",
    "slant_range",
    "solid_angle",
]


def slant_range(height: Any, ground_distance: Any) -> Any:
    """Slant range from a sensor at a height above the ground to a point on the ground.

    Parameters
    ----------
    height : array_like
        Sensor height above the target's ground level [m], >= 0.
    ground_distance : array_like
        Horizontal distance from the sensor's nadir to the target [m], >= 0.

    Returns
    -------
    array_like
        Slant range ``s = sqrt(h² + r²)`` [m] (Sonesson 2004, §3.2 and Fig. 3.1).
    """
    xp, (h, r) = _arrays.arrays(height, ground_distance)
    _arrays.require_nonnegative("height", h, xp, "m")
    _arrays.require_nonnegative("ground_distance", r, xp, "m")
    return _arrays.result(xp.sqrt(h * h + r * r))


def solid_angle(height: Any, ground_distance: Any, area: Any) -> Any:
    """Solid angle of a flat target on the ground seen from an airborne sensor.

    ``φ = h·A_T / (π (h² + r²)^(3/2))``, Eq. (3.5) in Sonesson (2004), written as printed
    (the thesis's own normalisation, with π, of the projected area over the cube of the slant
    range). The thesis discards ``P_det = k1·φ`` (3.6); this is kept as a geometric utility.

    Parameters
    ----------
    height : array_like
        Sensor height [m], >= 0.
    ground_distance : array_like
        Horizontal distance to the target [m], >= 0.
    area : array_like
        Target area on the ground ``A_T`` [m²], >= 0.

    Returns
    -------
    array_like
        φ [sr] as defined by Eq. (3.5).
    """
    xp, (h, r, a) = _arrays.arrays(height, ground_distance, area)
    _arrays.require_nonnegative("height", h, xp, "m")
    _arrays.require_nonnegative("ground_distance", r, xp, "m")
    _arrays.require_nonnegative("area", a, xp, "m²")
    s2 = h * h + r * r
    _arrays.require_positive("slant range", s2, xp, "m")
    return _arrays.result(h * a / (xp.pi * s2 * xp.sqrt(s2)))


def projected_extents(
    length: Any, width: Any, height: Any, aspect: Any = 1.5707963267948966, depression: Any = 0.0
) -> tuple[Any, Any]:
    """Sides of the rectangle circumscribing a box target as seen by the sensor.

    The target is a box ``length × width × height`` standing on the ground. The line of sight
    makes the horizontal angle ``aspect`` with the box's long axis (π/2 = broadside, 0 = head-on)
    and looks down at ``depression`` below the horizontal. In orthographic projection (target
    small against its range), the extent of a box along an image axis ``u`` is the sum over the
    box's edges of ``|u · edge|``, which gives

    - horizontal: ``L |sin a| + W |cos a|``
    - vertical: ``H cos e + (L |cos a| + W |sin a|) sin e``

    Parameters
    ----------
    length, width, height : array_like
        Box dimensions [m], >= 0.
    aspect : array_like, optional
        Horizontal angle between the line of sight and the long axis [rad]; default broadside.
    depression : array_like, optional
        Angle of the line of sight below the horizontal [rad], in [0, π/2]; default 0.

    Returns
    -------
    horizontal, vertical : array_like
        Sides of the circumscribing rectangle [m].
    """
    xp, (ln, wd, ht, a, e) = _arrays.arrays(length, width, height, aspect, depression)
    for name, value in (("length", ln), ("width", wd), ("height", ht)):
        _arrays.require_nonnegative(name, value, xp, "m")
    _arrays.require_nonnegative("depression", e, xp, "rad")
    if bool(xp.any(e > xp.pi / 2)):
        raise ValueError("depression must be in [0, π/2] rad")
    sin_a, cos_a = xp.abs(xp.sin(a)), xp.abs(xp.cos(a))
    horizontal = ln * sin_a + wd * cos_a
    vertical = ht * xp.cos(e) + (ln * cos_a + wd * sin_a) * xp.sin(e)
    return _arrays.result(horizontal), _arrays.result(vertical)


def _minimum_side(horizontal: Array, vertical: Array, xp: Any) -> Array:
    # Sonesson (2004) §3.2, Fig. 3.3: Johnson counts cycles across the minimum dimension.
    return xp.minimum(horizontal, vertical)


def _geometric_mean_side(horizontal: Array, vertical: Array, xp: Any) -> Array:
    # The characteristic dimension sqrt(A) of the NVESD target task performance (TTP) metric
    # (Vollmerhausen & Jacobs 2004); offered for comparison, not used by the thesis.
    return xp.sqrt(horizontal * vertical)


CRITICAL_DIMENSION_METHODS: MappingProxyType[str, Callable[[Array, Array, Any], Array]] = (
    MappingProxyType({"minimum": _minimum_side, "geometric-mean": _geometric_mean_side})
)
"""Ways to reduce the seen rectangle to one critical dimension, by name."""


def critical_dimension(
    length: Any,
    width: Any,
    height: Any,
    aspect: Any = 1.5707963267948966,
    depression: Any = 0.0,
    method: str = "minimum",
) -> Any:
    """Critical dimension of a box target as seen by the sensor.

    ``method="minimum"`` (default) is the smallest side of the rectangle circumscribing the
    target as seen by the sensor (Sonesson 2004, §3.2 and Fig. 3.3: Johnson's cycles are
    counted across the minimum dimension). ``"geometric-mean"`` is ``sqrt(horizontal·vertical)``.
    See :func:`projected_extents` for the geometry and the parameters.

    Returns
    -------
    array_like
        Critical dimension [m].
    """
    if method not in CRITICAL_DIMENSION_METHODS:
        raise ValueError(
            f"method must be one of {', '.join(CRITICAL_DIMENSION_METHODS)}; got {method!r}"
        )
    horizontal, vertical = projected_extents(length, width, height, aspect, depression)
    xp, (h, v) = _arrays.arrays(horizontal, vertical)
    return _arrays.result(CRITICAL_DIMENSION_METHODS[method](h, v, xp))


def positions_at(times: Any, waypoint_times: Any, waypoint_positions: Any) -> Any:
    """Positions along a path at times, linear between waypoints, held outside them.

    Parameters
    ----------
    times : array_like
        (n_t,) [s].
    waypoint_times : array_like
        (n_w,) increasing [s].
    waypoint_positions : array_like
        (n_w, 3) [m].

    Returns
    -------
    numpy.ndarray
        (n_t, 3) [m].
    """
    import numpy as np

    t = np.asarray(times, dtype=float)
    wt = np.asarray(waypoint_times, dtype=float)
    wp = np.asarray(waypoint_positions, dtype=float)
    return np.stack([np.interp(t, wt, wp[:, k]) for k in range(3)], axis=-1)


def heading_along(times: Any, waypoint_times: Any, waypoint_positions: Any, default: float) -> Any:
    """Direction of motion (from north, clockwise) [rad] along a path; ``default`` where still."""
    import numpy as np

    t = np.asarray(times, dtype=float)
    wt = np.asarray(waypoint_times, dtype=float)
    wp = np.asarray(waypoint_positions, dtype=float)
    leg = np.clip(np.searchsorted(wt, t, side="right") - 1, 0, len(wt) - 2)
    d = wp[leg + 1] - wp[leg]
    still = np.hypot(d[:, 0], d[:, 1]) == 0
    return np.where(still, default, np.arctan2(d[:, 0], d[:, 1]))


def viewing_angles(line_of_sight: Any, heading: Any) -> tuple[Any, Any, Any]:
    """Range, aspect and depression of lines of sight from sensors to targets.

    Parameters
    ----------
    line_of_sight : array_like
        (..., 3) vectors from sensor to target [m] (x east, y north, z up).
    heading : array_like
        Target heading (long axis, from north clockwise) [rad], broadcasting with ``...``.

    Returns
    -------
    range, aspect, depression : numpy.ndarray
        Slant range [m]; horizontal angle between the line of sight and the long axis [rad];
        the magnitude of the line of sight's angle to the horizontal [rad], in [0, π/2] (a box
        looks the same from below as from above, for its outline).
    """
    import numpy as np

    los = np.asarray(line_of_sight, dtype=float)
    rng = np.linalg.norm(los, axis=-1)
    azimuth = np.arctan2(los[..., 0], los[..., 1])
    horizontal = np.hypot(los[..., 0], los[..., 1])
    depression = np.abs(np.arctan2(los[..., 2], horizontal))
    return rng, azimuth - heading, depression


def in_field_of_view(line_of_sight: Any, forward: Any, field_of_view: tuple[float, float]) -> Any:
    """Whether lines of sight fall inside a sensor's rectangular field of view.

    The sensor frame: ``forward`` (the boresight), ``right`` = forward × up (horizontal),
    ``up'`` = right × forward. A target is in view when it is in front and its horizontal and
    vertical angles off the boresight are within half the fields of view.

    Parameters
    ----------
    line_of_sight : array_like
        (..., 3) [m].
    forward : array_like
        (..., 3) boresight directions, broadcasting with ``line_of_sight``.
    field_of_view : (float, float)
        Full horizontal and vertical fields of view [rad].
    """
    import numpy as np

    los = np.asarray(line_of_sight, dtype=float)
    f = np.asarray(forward, dtype=float)
    f = f / np.linalg.norm(f, axis=-1, keepdims=True)
    up = np.array([0.0, 0.0, 1.0])
    right = np.cross(f, up)
    norm = np.linalg.norm(right, axis=-1, keepdims=True)
    # Looking straight down or up: any horizontal "right" will do.
    right = np.where(norm > 1e-12, right / np.where(norm > 1e-12, norm, 1.0), [1.0, 0.0, 0.0])
    up_sensor = np.cross(right, f)
    ahead = np.sum(los * f, axis=-1)
    across = np.sum(los * right, axis=-1)
    vertical = np.sum(los * up_sensor, axis=-1)
    half_h, half_v = field_of_view[0] / 2.0, field_of_view[1] / 2.0
    return (
        (ahead > 0)
        & (np.abs(across) <= np.tan(half_h) * ahead)
        & (np.abs(vertical) <= np.tan(half_v) * ahead)
    )
