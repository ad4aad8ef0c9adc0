"""Viewing geometry: slant range, solid angle and the critical dimension seen by a sensor.

Sources: Sonesson (2004) ch. 3 (§3.1–3.2, Eqs. (3.1)–(3.5), Fig. 3.3). The projected box
extents are elementary orthographic projection; see :func:`projected_extents`.
"""

from __future__ import annotations

from collections.abc import Callable
from types import MappingProxyType
from typing import Any

import numpy as np

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array

__all__ = [
    "CRITICAL_DIMENSION_METHODS",
    "box_extents_seen",
    "box_outline",
    "critical_dimension",
    "critical_dimension_seen",
    "heading_along",
    "in_field_of_view",
    "pointing_direction",
    "positions_at",
    "projected_extents",
    "slant_range",
    "solid_angle",
    "transverse_speed",
    "velocities_at",
    "view_offsets",
    "within_field_of_view",
]


def slant_range(height: Array, ground_distance: Array) -> Any:
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

    Examples
    --------
    A sensor 1.5 km up, 2 km from the point on the ground (a 3-4-5 triangle):

    >>> import targetacq as ta
    >>> print(f"{ta.slant_range(1500.0, 2000.0):.1f}")
    2500.0
    """
    xp, (h, r) = _arrays.arrays(height, ground_distance, names=("height", "ground_distance"))
    _arrays.require_nonnegative("height", h, xp, "m")
    _arrays.require_nonnegative("ground_distance", r, xp, "m")
    return _arrays.result(xp.sqrt(h * h + r * r))


def solid_angle(height: Array, ground_distance: Array, area: Array) -> Any:
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

    Examples
    --------
    Straight down from 1 km on 10 m² (Eq. (3.5) reduces to ``A / (π h²)``):

    >>> import targetacq as ta
    >>> print(f"{ta.solid_angle(1000.0, 0.0, 10.0):.4e}")
    3.1831e-06
    """
    xp, (h, r, a) = _arrays.arrays(
        height, ground_distance, area, names=("height", "ground_distance", "area")
    )
    _arrays.require_nonnegative("height", h, xp, "m")
    _arrays.require_nonnegative("ground_distance", r, xp, "m")
    _arrays.require_nonnegative("area", a, xp, "m²")
    for name, value in (("height", h), ("ground_distance", r), ("area", a)):
        _arrays.require_finite(name, value, xp, "m²" if name == "area" else "m")
    s2 = h * h + r * r
    _arrays.require_positive("slant range", s2, xp, "m")
    return _arrays.result(h * a / (xp.pi * s2 * xp.sqrt(s2)))


def projected_extents(
    length: Array,
    width: Array,
    height: Array,
    aspect: Array = 1.5707963267948966,
    depression: Array = 0.0,
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

    Examples
    --------
    A 7 × 2.5 × 3 m truck seen from its side (aspect 90°, the default) shows its length and
    height; seen head-on (aspect 0), its width and height; seen from straight above, its
    length and width:

    >>> import math
    >>> import targetacq as ta
    >>> [round(float(x), 6) for x in ta.projected_extents(7.0, 2.5, 3.0)]
    [7.0, 3.0]
    >>> [round(float(x), 6) for x in ta.projected_extents(7.0, 2.5, 3.0, aspect=0.0)]
    [2.5, 3.0]
    >>> [round(float(x), 6) for x in ta.projected_extents(7.0, 2.5, 3.0, depression=math.pi / 2)]
    [7.0, 2.5]
    """
    xp, (ln, wd, ht, a, e) = _arrays.arrays(
        length,
        width,
        height,
        aspect,
        depression,
        names=("length", "width", "height", "aspect", "depression"),
    )
    for name, value in (("length", ln), ("width", wd), ("height", ht)):
        _arrays.require_nonnegative(name, value, xp, "m")
    _arrays.require_nonnegative("depression", e, xp, "rad")
    _arrays.require_finite("aspect", a, xp, "rad")
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

    Examples
    --------
    The smaller projected side of the same truck: its height from the side, its width head-on.

    >>> import targetacq as ta
    >>> print(round(float(ta.critical_dimension(7.0, 2.5, 3.0)), 6))
    3.0
    >>> print(round(float(ta.critical_dimension(7.0, 2.5, 3.0, aspect=0.0)), 6))
    2.5
    """
    if method not in CRITICAL_DIMENSION_METHODS:
        raise ValueError(
            f"method must be one of {', '.join(CRITICAL_DIMENSION_METHODS)}; got {method!r}"
        )
    horizontal, vertical = projected_extents(length, width, height, aspect, depression)
    xp, (h, v) = _arrays.arrays(horizontal, vertical, names=("horizontal", "vertical"))
    return _arrays.result(CRITICAL_DIMENSION_METHODS[method](h, v, xp))


def positions_at(times: Array, waypoint_times: Array, waypoint_positions: Array) -> Any:
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

    Examples
    --------
    Halfway between two waypoints 10 s apart, and held at the last one after it:

    >>> from targetacq.physics.geometry import positions_at
    >>> path = positions_at([0.0, 5.0, 20.0], [0.0, 10.0], [[0.0, 0.0, 100.0], [100.0, 0.0, 100.0]])
    >>> print(path.round(6).tolist())
    [[0.0, 0.0, 100.0], [50.0, 0.0, 100.0], [100.0, 0.0, 100.0]]
    """
    import numpy as np

    t = np.asarray(times, dtype=float)
    wt = np.asarray(waypoint_times, dtype=float)
    wp = np.asarray(waypoint_positions, dtype=float)
    return np.stack([np.interp(t, wt, wp[:, k]) for k in range(3)], axis=-1)


def velocities_at(times: Array, waypoint_times: Array, waypoint_positions: Array) -> Any:
    """Velocities along a path at times: the derivative of :func:`positions_at` [m/s].

    Constant along each leg (the leg that starts at or before the time, as
    :func:`heading_along` takes it), zero before the first waypoint and from the last one on
    (the path is held there).

    Parameters
    ----------
    times : array_like
        (n_t,) [s].
    waypoint_times : array_like
        (n_w,) increasing [s], n_w >= 2.
    waypoint_positions : array_like
        (n_w, 3) [m].

    Returns
    -------
    numpy.ndarray
        (n_t, 3) [m/s].

    Examples
    --------
    100 m east in 10 s, then held:

    >>> from targetacq.physics.geometry import velocities_at
    >>> v = velocities_at([-1.0, 5.0, 10.0], [0.0, 10.0], [[0.0, 0.0, 0.0], [100.0, 0.0, 0.0]])
    >>> print(v.tolist())
    [[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 0.0, 0.0]]
    """
    t = np.asarray(times, dtype=float)
    wt = np.asarray(waypoint_times, dtype=float)
    wp = np.asarray(waypoint_positions, dtype=float)
    leg = np.clip(np.searchsorted(wt, t, side="right") - 1, 0, len(wt) - 2)
    velocity = (wp[leg + 1] - wp[leg]) / (wt[leg + 1] - wt[leg])[:, None]
    held = (t < wt[0]) | (t >= wt[-1])
    out = np.where(held[:, None], 0.0, velocity)
    return np.where(np.isnan(t)[:, None], np.nan, out)


def transverse_speed(x: Array, y: Array, z: Array, vx: Array, vy: Array, vz: Array) -> Any:
    """Speed across the line of sight [m/s]: ``|r × v| / |r|``.

    The component of the relative velocity ``v`` (target's minus sensor's) perpendicular to
    the line of sight ``r`` (sensor to target); over the range it is the angular speed of the
    target as the sensor sees it, ``ω = |r × v| / |r|²`` [rad/s]. A target moving straight
    at the sensor (or away) has none. Where ``r = 0`` (no line of sight) it is 0.

    Parameters
    ----------
    x, y, z : array_like
        Components of the line of sight [m] (x east, y north, z up).
    vx, vy, vz : array_like
        Components of the relative velocity [m/s], broadcasting with them.

    Returns
    -------
    array_like
        v_⊥ >= 0 [m/s]; NaN where an input is NaN.

    Examples
    --------
    A target 1 km north crossing east at 10 m/s, and one driving straight at the sensor:

    >>> from targetacq.physics.geometry import transverse_speed
    >>> print(float(transverse_speed(0.0, 1000.0, 0.0, 10.0, 0.0, 0.0)))
    10.0
    >>> print(float(transverse_speed(0.0, 1000.0, 0.0, 0.0, -10.0, 0.0)))
    0.0
    """
    xp, (x_, y_, z_, u, v, w) = _arrays.arrays(x, y, z, vx, vy, vz, broadcast=False)
    cx = y_ * w - z_ * v
    cy = z_ * u - x_ * w
    cz = x_ * v - y_ * u
    r2 = x_ * x_ + y_ * y_ + z_ * z_
    c2 = cx * cx + cy * cy + cz * cz
    # The double where: no division by zero where r = 0, and no square root at 0 (nor their
    # NaN gradients) where the target moves along the line of sight or not at all.
    moving = (r2 > 0) & (c2 > 0)
    out = xp.where(moving, xp.sqrt(xp.where(moving, c2, 1.0) / xp.where(moving, r2, 1.0)), 0.0)
    return _arrays.result(xp.where(xp.isnan(r2) | xp.isnan(c2), xp.nan, out))


def heading_along(times: Any, waypoint_times: Any, waypoint_positions: Any, default: float) -> Any:
    """Direction of motion (from north, clockwise) [rad] along a path; ``default`` where still.

    Examples
    --------
    Moving east is a heading of 90°:

    >>> import math
    >>> from targetacq.physics.geometry import heading_along
    >>> heading = heading_along([5.0], [0.0, 10.0], [[0.0, 0.0, 0.0], [100.0, 0.0, 0.0]], 0.0)
    >>> print(round(math.degrees(float(heading[0])), 6))
    90.0
    """
    import numpy as np

    t = np.asarray(times, dtype=float)
    wt = np.asarray(waypoint_times, dtype=float)
    wp = np.asarray(waypoint_positions, dtype=float)
    leg = np.clip(np.searchsorted(wt, t, side="right") - 1, 0, len(wt) - 2)
    d = wp[leg + 1] - wp[leg]
    still = np.hypot(d[:, 0], d[:, 1]) == 0
    return np.where(still, default, np.arctan2(d[:, 0], d[:, 1]))


_OUTLINE_INPUTS = ("x", "y", "z", "heading", "length", "width", "height")


def box_outline(
    x: Array, y: Array, z: Array, heading: Array, length: Array, width: Array, height: Array
) -> tuple[Any, Any, Any]:
    """Range and the outline of box targets seen along lines of sight, from the components.

    The same outline as :func:`projected_extents`, with the aspect's and the depression's sines
    and cosines taken straight from the line-of-sight components instead of through angles (no
    arctangent, sine or cosine per triple):
    ``|cos a| = |x sin h + y cos h| / ρ``, ``|sin a| = |x cos h − y sin h| / ρ``,
    ``sin e = |z| / R``, ``cos e = ρ / R``, with ``ρ = hypot(x, y)``. Straight down (ρ = 0) the
    outline is the box's top, length by width.

    Parameters
    ----------
    x, y, z : array_like
        Components of the vectors from sensor to target [m] (x east, y north, z up).
    heading : array_like
        Direction of the target's long axis, from north clockwise [rad].
    length, width, height : array_like
        Box dimensions [m]. All inputs broadcast together.

    Returns
    -------
    range, horizontal, vertical : array_like
        Slant range [m] and the sides of the outline [m]; NaN where a component is NaN, and
        an infinite range with a NaN outline where one is infinite.

    Examples
    --------
    >>> rng, h, v = box_outline(0.0, 1000.0, 0.0, 1.5707963267948966, 6.0, 3.0, 2.5)
    >>> float(rng), round(float(h), 9), float(v)  # broadside at eye level: the length, the height
    (1000.0, 6.0, 2.5)
    """
    xp, (x, y, z, heading, length, width, height) = _arrays.arrays(
        x, y, z, heading, length, width, height, names=_OUTLINE_INPUTS
    )
    _arrays.require_finite("heading", heading, xp, "rad")
    # An infinite component makes inf/inf or 0·inf: the outline is NaN there (unknown).
    with np.errstate(divide="ignore", invalid="ignore"):
        rng, horizontal, vertical = _outline(
            x, y, z, xp.sin(heading), xp.cos(heading), length, width, height, xp
        )
    return _arrays.result(rng), _arrays.result(horizontal), _arrays.result(vertical)


def _outline(
    x: Array,
    y: Array,
    z: Array,
    sin_h: Array,
    cos_h: Array,
    length: Array,
    width: Array,
    height: Array,
    xp: Any,
) -> tuple[Array, Array, Array]:
    """:func:`box_outline` of checked float arrays, given the sines and cosines of the headings.

    The arithmetic kernel, without checks, conversions or a change of NumPy's error state (the
    array core calls it block by block under its own, with the headings' sines and cosines
    taken once per call). NumPy arrays of the lines of sight's full shape take
    :func:`outline_numpy`: the same operations with fewer temporaries.
    """
    if (
        isinstance(x, np.ndarray)
        and x.ndim
        and x.shape == y.shape == z.shape
        and np.broadcast_shapes(x.shape, *(np.shape(v) for v in (sin_h, length))) == x.shape
        and np.broadcast_shapes(x.shape, *(np.shape(v) for v in (cos_h, width, height))) == x.shape
    ):
        return outline_numpy(x, y, z, sin_h, cos_h, length, width, height)
    rho = xp.sqrt(x * x + y * y)
    rng = xp.sqrt(rho * rho + z * z)
    along = xp.abs(x * sin_h + y * cos_h)  # ρ |cos a|
    across = xp.abs(x * cos_h - y * sin_h)  # ρ |sin a|
    flat = rho == 0
    # Straight down or up (ρ = 0): divide by 1 there, and take the box's top below.
    safe = xp.where(flat, 1.0, rho)
    # Divisions, not a reciprocal: |cos a| and |sin a| stay exact for subnormal ρ.
    horizontal = (length * across + width * along) / safe
    vertical = (height * rho + (length * along + width * across) / safe * xp.abs(z)) / xp.where(
        rng > 0, rng, 1.0
    )
    top_h = length + 0.0 * flat
    top_v = xp.where(rng > 0, width + 0.0 * rng, height + 0.0 * rng)
    return rng, xp.where(flat, top_h, horizontal), xp.where(flat, top_v, vertical)


def outline_numpy(
    x: np.ndarray,
    y: np.ndarray,
    z: np.ndarray,
    sin_h: Any,
    cos_h: Any,
    length: Any,
    width: Any,
    height: Any,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_outline` of NumPy arrays ``x, y, z`` of the result's shape: each operation of the
    generic formula in the same order, in place where its result is new, and the ``where``
    guards only where a line of sight is vertical (ρ = 0) or of zero length."""
    tmp = y * y
    rho = x * x
    rho += tmp
    np.sqrt(rho, out=rho)
    rng = rho * rho
    np.multiply(z, z, out=tmp)
    rng += tmp
    np.sqrt(rng, out=rng)
    along = x * sin_h
    np.multiply(y, cos_h, out=tmp)
    along += tmp
    np.abs(along, out=along)  # ρ |cos a|
    across = x * cos_h
    np.multiply(y, sin_h, out=tmp)
    across -= tmp
    np.abs(across, out=across)  # ρ |sin a|
    flat = rho == 0
    guarded = bool(flat.any()) or bool(np.any(rng == 0))
    safe = np.where(flat, 1.0, rho) if guarded else rho
    horizontal = length * across
    np.multiply(width, along, out=tmp)
    horizontal += tmp
    horizontal /= safe
    along *= length
    across *= width
    along += across  # ρ (L |cos a| + W |sin a|)
    along /= safe
    np.abs(z, out=tmp)
    along *= tmp
    vertical = height * rho
    vertical += along
    vertical /= np.where(rng > 0, rng, 1.0) if guarded else rng
    if guarded:
        top_v = np.where(rng > 0, width + 0.0 * rng, height + 0.0 * rng)
        horizontal = np.where(flat, length + 0.0 * flat, horizontal)
        vertical = np.where(flat, top_v, vertical)
    return rng, horizontal, vertical


def box_extents_seen(
    line_of_sight: Array, heading: Array, length: Array, width: Array, height: Array
) -> tuple[Any, Any, Any]:
    """Range and the outline of box targets seen along lines of sight ``(..., 3)``.

    :func:`box_outline` of the vectors' components; see there for the formula.

    Parameters
    ----------
    line_of_sight : array_like
        (..., 3) vectors from sensor to target [m] (x east, y north, z up).
    heading : array_like
        Direction of the target's long axis, from north clockwise [rad], broadcasting with ``...``.
    length, width, height : array_like
        Box dimensions [m], broadcasting with ``...``.

    Returns
    -------
    range, horizontal, vertical : array_like
        Slant range [m] and the sides of the outline [m].

    Examples
    --------
    A 7 × 2.5 × 3 m truck heading north, seen from the west (its side) and from the south (its
    back):

    >>> from targetacq.physics.geometry import box_extents_seen
    >>> r, horizontal, vertical = box_extents_seen([[1000.0, 0.0, 0.0]], 0.0, 7.0, 2.5, 3.0)
    >>> print(round(float(r[0]), 6), round(float(horizontal[0]), 6), round(float(vertical[0]), 6))
    1000.0 7.0 3.0
    >>> r, horizontal, vertical = box_extents_seen([[0.0, 1000.0, 0.0]], 0.0, 7.0, 2.5, 3.0)
    >>> print(round(float(horizontal[0]), 6), round(float(vertical[0]), 6))
    2.5 3.0
    """
    _xp, (los,) = _arrays.arrays(line_of_sight, names=("line_of_sight",))
    return box_outline(los[..., 0], los[..., 1], los[..., 2], heading, length, width, height)


def critical_dimension_seen(
    horizontal: Array, vertical: Array, visible_fraction: Array = 1.0
) -> Any:
    """Critical dimension of a partly hidden target: ``min(horizontal, visible · vertical)``.

    Johnson's cycles are counted across the smaller side of the outline (Sonesson 2004, §3.2 and
    Fig. 3.3); a target partly hidden behind terrain or vegetation shows only the visible
    fraction of its height (§3.10).

    Parameters
    ----------
    horizontal, vertical : array_like
        Sides of the outline seen [m] (:func:`box_outline`).
    visible_fraction : array_like
        Fraction of the height in view, in (0, 1].

    Returns
    -------
    array_like
        Critical dimension [m].

    Examples
    --------
    >>> float(critical_dimension_seen(6.0, 2.5, 0.6))
    1.5
    """
    xp, (h, v, f) = _arrays.arrays(
        horizontal, vertical, visible_fraction, names=("horizontal", "vertical", "visible_fraction")
    )
    return _arrays.result(xp.minimum(h, v * f))


def pointing_direction(azimuth: Array, depression: Array) -> tuple[Any, Any, Any]:
    """Unit boresight vector of a sensor pointed at an azimuth and a depression.

    ``(cos e sin a, cos e cos a, −sin e)`` in (east, north, up): azimuth ``a`` from north,
    clockwise; depression ``e`` below the horizon (negative above).

    Parameters
    ----------
    azimuth, depression : array_like
        [rad], broadcasting together.

    Returns
    -------
    (east, north, up) : tuple of array_like

    Examples
    --------
    >>> [round(float(c), 12) for c in pointing_direction(1.5707963267948966, 0.0)]
    [1.0, 0.0, -0.0]
    """
    xp, (a, e) = _arrays.arrays(azimuth, depression, names=("azimuth", "depression"))
    _arrays.require_finite("azimuth", a, xp, "rad")
    _arrays.require_finite("depression", e, xp, "rad")
    ce = xp.cos(e)
    return (
        _arrays.result(ce * xp.sin(a)),
        _arrays.result(ce * xp.cos(a)),
        _arrays.result(-xp.sin(e)),
    )


def view_offsets(
    x: Array, y: Array, z: Array, forward: tuple[Any, Any, Any]
) -> tuple[Any, Any, Any]:
    """Components of lines of sight in a sensor's frame: ahead, right and up.

    The sensor frame: ``forward`` (the boresight, any length), ``right = forward × up``
    (horizontal), ``up' = right × forward``; looking straight down or up, ``right`` is east.

    Parameters
    ----------
    x, y, z : array_like
        Line-of-sight components [m].
    forward : (array_like, array_like, array_like)
        Boresight components, broadcasting with ``x``.

    Returns
    -------
    ahead, right, up : array_like
        [m].

    Examples
    --------
    A sensor looking east: a point 10 m north of the boresight is 10 m to its left (``right``
    is south), one 5 m higher is 5 m up.

    >>> from targetacq.physics.geometry import view_offsets
    >>> [round(float(c), 6) for c in view_offsets(100.0, 10.0, 5.0, (1.0, 0.0, 0.0))]
    [100.0, -10.0, 5.0]
    """
    xp, (x, y, z, fx, fy, fz) = _arrays.arrays(
        x, y, z, *forward, names=("x", "y", "z", "forward east", "forward north", "forward up")
    )
    ahead, right, up = _offsets(x, y, z, sensor_frame(fx, fy, fz, xp))
    return _arrays.result(ahead), _arrays.result(right), _arrays.result(up)


def sensor_frame(fx: Array, fy: Array, fz: Array, xp: Any) -> tuple[Array, ...]:
    """The sensor frame of :func:`view_offsets` from the boresight components (any length).

    Returns
    -------
    tuple of 8 arrays
        ``(fx, fy, fz)`` the unit boresight, ``(rx, ry)`` the horizontal right and
        ``(ux, uy, uz)`` up, each of the boresight's shape: one frame per sensor (and batch
        element), computed once and applied to every target by :func:`_offsets`.
    """
    # Square roots of 1, not 0, where masked: sqrt's infinite slope at 0 would make gradients
    # NaN there (e.g. a sensor pointed straight down) even though the value is not used.
    square = fx * fx + fy * fy + fz * fz
    norm = xp.sqrt(xp.where(square > 0, square, 1.0))
    fx, fy, fz = fx / norm, fy / norm, fz / norm
    square = fx * fx + fy * fy
    horizontal = xp.sqrt(xp.where(square > 0, square, 1.0))
    level = (square > 0) & (horizontal > 1e-12)
    safe = xp.where(level, horizontal, 1.0)
    rx = xp.where(level, fy / safe, 1.0)  # forward × up, normalised
    ry = xp.where(level, -fx / safe, 0.0)
    ux, uy, uz = ry * fz, -rx * fz, rx * fy - ry * fx  # right × forward (right has no z)
    return fx, fy, fz, rx, ry, ux, uy, uz


def _offsets(x: Array, y: Array, z: Array, frame: tuple[Array, ...]) -> tuple[Array, Array, Array]:
    """Ahead, right and up of lines of sight ``(x, y, z)`` in a sensor frame
    (:func:`sensor_frame`)."""
    fx, fy, fz, rx, ry, ux, uy, uz = frame
    return x * fx + y * fy + z * fz, x * rx + y * ry, x * ux + y * uy + z * uz


def within_numpy(
    x: np.ndarray,
    y: np.ndarray,
    z: np.ndarray,
    frame: tuple[np.ndarray, ...],
    tan_h: Any,
    tan_v: Any,
) -> np.ndarray:
    """:func:`_offsets` then :func:`_in_view` of NumPy arrays ``x, y, z`` of the result's
    shape, with the frame's and half tangents' arrays broadcasting to it: the same operations
    (the test is exact), with three temporaries."""
    fx, fy, fz, rx, ry, ux, uy, uz = frame
    tmp = y * fy
    ahead = x * fx
    ahead += tmp
    np.multiply(z, fz, out=tmp)
    ahead += tmp
    side = x * rx
    np.multiply(y, ry, out=tmp)
    side += tmp  # right
    np.abs(side, out=side)
    np.multiply(tan_h, ahead, out=tmp)
    inside = side <= tmp
    np.multiply(x, ux, out=side)
    np.multiply(y, uy, out=tmp)
    side += tmp
    np.multiply(z, uz, out=tmp)
    side += tmp  # up
    np.abs(side, out=side)
    np.multiply(tan_v, ahead, out=tmp)
    inside &= side <= tmp
    inside &= ahead > 0
    return inside


def _in_view(ahead: Array, right: Array, up: Array, tan_h: Array, tan_v: Array, xp: Any) -> Array:
    """In front, within the half tangents of the field of view (:func:`within_field_of_view`)."""
    return (ahead > 0) & (xp.abs(right) <= tan_h * ahead) & (xp.abs(up) <= tan_v * ahead)


def in_field_of_view(line_of_sight: Array, forward: Array, half_tangents: tuple[Any, Any]) -> Any:
    """Whether lines of sight fall inside sensors' rectangular fields of view.

    A target is in view when it is in front and its horizontal and vertical angles off the
    boresight are within half the fields of view (:func:`view_offsets` gives the frame).

    Parameters
    ----------
    line_of_sight : array_like
        (..., 3) [m].
    forward : array_like
        (..., 3) boresight directions (any length), broadcasting with ``line_of_sight``.
    half_tangents : (array_like, array_like)
        tan(FOV_h / 2) and tan(FOV_v / 2), broadcasting with ``line_of_sight[..., 0]``.

    Returns
    -------
    array_like of bool
        False where a component is NaN.

    Examples
    --------
    A sensor looking east with an 8° × 6° field of view: straight ahead is in view, 5.7° to
    the side (``atan(10/100)``) is not, nor is anything behind.

    >>> import math
    >>> from targetacq.physics.geometry import in_field_of_view
    >>> half = (math.tan(math.radians(4.0)), math.tan(math.radians(3.0)))
    >>> sight = [[100.0, 0.0, 0.0], [100.0, 10.0, 0.0], [-100.0, 0.0, 0.0]]
    >>> in_field_of_view(sight, [1.0, 0.0, 0.0], half).tolist()
    [True, False, False]
    """
    _, (los, f) = _arrays.arrays(line_of_sight, forward, names=("line_of_sight", "forward"))
    return within_field_of_view(
        los[..., 0], los[..., 1], los[..., 2], (f[..., 0], f[..., 1], f[..., 2]), half_tangents
    )


def within_field_of_view(
    x: Any, y: Any, z: Any, forward: tuple[Any, Any, Any], half_tangents: tuple[Any, Any]
) -> Any:
    """:func:`in_field_of_view` from the line-of-sight and boresight components.

    In front (``ahead > 0``), ``|right| <= tan(FOV_h/2) · ahead`` and
    ``|up| <= tan(FOV_v/2) · ahead`` in the sensor frame of :func:`view_offsets`.

    Examples
    --------
    >>> bool(within_field_of_view(1000.0, 50.0, 0.0, (1.0, 0.0, 0.0), (0.1, 0.1)))
    True
    >>> bool(within_field_of_view(1000.0, 150.0, 0.0, (1.0, 0.0, 0.0), (0.1, 0.1)))
    False
    """
    ahead, right, up = view_offsets(x, y, z, forward)
    xp, (tan_h, tan_v) = _arrays.arrays(
        *half_tangents, names=("horizontal half tangent", "vertical half tangent")
    )
    return _in_view(ahead, right, up, tan_h, tan_v, xp)
