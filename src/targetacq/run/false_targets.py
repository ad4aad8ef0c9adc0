"""False targets: clutter objects that an observer declares to be targets.

The thesis leaves false targets to future work (§9.4) and points to T. J. Doll and
D. E. Schmieder, "Observer false alarm effects on detection in clutter", *Optical Engineering*
32(7), 1993 (its ref. [3]). We have not been able to read that paper, so nothing below is taken
from it: the law is **this project's assumption**, built to agree with what the issue that asked
for it says of the paper (observers' false alarms come from target-like objects in the clutter,
and there are more of them where there is more clutter) and with the field-of-view search model
of :mod:`targetacq.run.search`.

Law. The ground (the plane ``z = 0``) carries target-sized clutter objects at ``density`` objects
per area [1/m²], independently of one another (a homogeneous Poisson field). While an object is
inside a sensor's field of view, the observer declares it a target at the constant hazard

    ``λ₁ = probability / t_s``  [1/s],

``t_s`` the scene's search time (``model.search_time``): the hazard ``P∞/t_s`` of the search
model for a true target, with the per-object ``probability`` in place of P∞. So an object kept in
view for one search time is declared with probability ``1 − exp(−probability)`` (about
``probability`` where that is small), and one kept in view longer may be declared again: each
declaration is a new report (the field has no memory). Summing over the objects in view, the
false detections of one sensor form a Poisson process in time with rate

    ``λ = density · A · probability / t_s``  [1/s]   (:func:`false_target_rate`),

``A`` the ground area [m²] inside the sensor's field of view and within ``max_range`` of the
sensor (horizontal ground range, :func:`ground_area_in_view`). The rate rises linearly with the
clutter (the object density) and with the area searched. Where each report lies is uniform over
that area, independently of the others.

Time steps. A step covers ``(t0, t1]`` with the sensor's position and pointing known at ``t1``;
``A`` is that of ``t1`` and held over the step, so the count of the step is Poisson with mean
``λ (t1 − t0)``, each report's time is uniform in ``(t0, t1]`` and its position uniform in the
area in view at ``t1``. The first step after a reset only starts the clock and has none, as for
true detections. A sensor that is not pointed, or has no field of view (no ``pixels``), has no
area in view and reports nothing; one with a NaN position reports nothing in that step.

Geometry. The field of view is the rectangular pyramid of
:func:`targetacq.physics.geometry.within_field_of_view` around the boresight of
:func:`targetacq.core.evaluation.boresight`. On the ground plane it is the convex set where four
linear inequalities hold (the four faces of the pyramid), a quadrilateral or an unbounded convex
polygon; within ``max_range`` it is that set cut by a disc. :func:`ground_footprint` clips the
polygon to the square around the disc and computes the exact area of its intersection with the
disc, edge by edge (a triangle or a circular sector per piece of edge): no sampling, so the mean
count does not depend on the draws. Positions are drawn by rejection from the smallest box around
the region in the frame of the boresight's horizontal direction (the region is symmetric about
it, so at least half of the box is accepted), each candidate kept if it is within ``max_range``
and :func:`targetacq.physics.geometry.within_field_of_view` says it is in view.

Terrain. With an elevation model (a scenario's ``[terrain]``), the ground the reports fall on
is limited to what the sensor sees: the reports are drawn as above, over the field of view on
the plane ``z = 0``, and each is kept only where the ground point itself is in the sensor's
line of sight over the terrain (:func:`targetacq.physics.line_of_sight.line_of_sight`: no
terrain above the sight line to it), at the terrain's altitude there. Keeping each point of a
Poisson field with a probability that depends on its position alone leaves a Poisson field
(thinning), of rate ``density · A_seen · probability / t_s``, ``A_seen`` the part of ``A`` in
sight. The area ``A`` stays that of the field of view on the plane ``z = 0`` (the sensor's
height over that plane): over relief far from that plane the footprint is an approximation.
Ground off the grid, or behind a void of it, is not known to be seen: no report there.

Reproducibility. The draws come from the counter-based Philox generator of
:mod:`targetacq.base.sampling`, keyed by the seed and the sensor's name (of its group: the bands of
one colour camera report false targets once, as one sensor) and counted by the step index, the
run, the purpose of the draw and the report's index. Outcomes therefore do not depend on how runs
are batched, on the order of the sensors or on which targets (or other sensors) exist: run ``r``
of :func:`targetacq.run.search.simulate` gives the same reports as :class:`targetacq.Simulation`
reset to run ``r`` and stepped through the same times.

Examples
--------
A camera 1 km up looking straight down with a 0.2 × 0.2 rad (half tangents 0.1) field of view
sees 200 m × 200 m of ground; at 4 objects per km², a probability of 0.05 and a search time of
3.4 s it reports a false target every 425 s on average:

>>> from targetacq.run.false_targets import false_target_rate, ground_area_in_view
>>> area = ground_area_in_view((0.0, 0.0, 1000.0), (0.0, 0.0, -1.0), (0.1, 0.1), 5000.0)
>>> round(float(area))
40000
>>> round(1.0 / float(false_target_rate(4e-6, 0.05, area, 3.4)), 1)
425.0
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.base.limits import check_seed
from targetacq.base.sampling import philox4x32, stream_key
from targetacq.physics import geometry
from targetacq.physics.line_of_sight import ElevationModel, line_of_sight
from targetacq.scenario.schema import NO_FALSE_TARGET_SENSORS, false_target_problems

if TYPE_CHECKING:
    from targetacq.core.records import SensorArrays

__all__ = [
    "FalseDetection",
    "FalseDetections",
    "FalseTargetSampler",
    "Footprint",
    "false_target_problems",
    "false_target_rate",
    "ground_area_in_view",
    "ground_footprint",
    "sample_false_detections",
]

_STREAM = ("false targets", "poisson")  # names after the sensor's: a key no pair can have
_COUNT, _TIME, _POSITION = 1, 2, 16  # purposes (counter word 2); positions: 16 + attempt
_MAX_ATTEMPTS = 10_000  # rejection rounds; at least half of each box is accepted


# ------------------------------------------------------------------------------------------------
# The rate
# ------------------------------------------------------------------------------------------------


def false_target_rate(density: Array, probability: Array, area: Array, search_time: Array) -> Any:
    """Rate of false detections of one sensor: ``density · area · probability / search_time``.

    Parameters
    ----------
    density : array_like
        Target-sized clutter objects per area of ground [1/m²], >= 0.
    probability : array_like
        Hazard of declaring one object in view a target, in units of ``1/search_time``, in
        [0, 1] (about the probability that an object looked at for one search time is declared).
    area : array_like
        Ground area in the field of view [m²], >= 0 (:func:`ground_area_in_view`).
    search_time : array_like
        t_s [s], > 0 (the scenario's ``model.search_time``).

    Returns
    -------
    array_like
        [1/s].

    Examples
    --------
    >>> round(float(false_target_rate(4e-6, 0.05, 2e6, 3.4)), 4)
    0.1176
    """
    names = ("density", "probability", "area", "search_time")
    xp, (rho, p, a, t_s) = _arrays.arrays(density, probability, area, search_time, names=names)
    _arrays.require_nonnegative("density", rho, xp, "1/m^2")
    _arrays.require_unit_interval("probability", p, xp)
    _arrays.require_nonnegative("area", a, xp, "m^2")
    _arrays.require_positive("search_time", t_s, xp, "s")
    return _arrays.result(rho * a * p / t_s)


# ------------------------------------------------------------------------------------------------
# The ground in view
# ------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Footprint:
    """The ground in a sensor's field of view within a range: where false targets can be.

    Attributes
    ----------
    sensor_position : tuple of 3 float
        East, north, up [m].
    forward : tuple of 3 float
        The boresight (any length).
    half_tangents : tuple of 2 float
        tan(FOV_h / 2), tan(FOV_v / 2).
    max_range : float
        Horizontal ground range from the sensor [m].
    area : float
        The area of the region [m²]: exact (no sampling); 0 where nothing is in view.
    polygon : numpy.ndarray (k, 2)
        The field of view on the ground clipped to the square of side ``2 max_range`` around the
        sensor's ground point, east and north [m], counter-clockwise (empty where nothing is in
        view); the region is its intersection with the disc of radius ``max_range``.
    axes : numpy.ndarray (2, 2)
        Rows: the sensor's horizontal right and the boresight's horizontal direction (east,
        north); the frame of ``box``.
    box : tuple of 4 float
        The smallest box around the region in that frame, relative to the sensor's ground
        point: (right min, right max, ahead min, ahead max) [m].
    """

    sensor_position: tuple[float, float, float]
    forward: tuple[float, float, float]
    half_tangents: tuple[float, float]
    max_range: float
    area: float
    polygon: np.ndarray
    axes: np.ndarray
    box: tuple[float, float, float, float]

    def contains(self, x: Any, y: Any) -> np.ndarray:
        """Whether ground points (east ``x``, north ``y`` [m], on ``z = 0``) are in the region:
        within ``max_range`` and in the field of view
        (:func:`targetacq.physics.geometry.within_field_of_view`)."""
        sx, sy, sz = self.sensor_position
        dx, dy = np.asarray(x, dtype=float) - sx, np.asarray(y, dtype=float) - sy
        near = np.hypot(dx, dy) <= self.max_range
        seen = geometry.within_field_of_view(
            dx, dy, np.full(dx.shape, -sz), self.forward, self.half_tangents
        )
        return np.asarray(near & seen, dtype=bool)


Line = tuple[tuple[float, float], float]  # a · p <= c
Corner = tuple[tuple[float, float], int]  # a vertex and the line of the edge that leaves it


def _clip(polygon: list[Corner], lines: list[Line], k: int) -> list[Corner]:
    """A convex polygon cut to the half-plane of ``lines[k]`` (Sutherland-Hodgman, one edge),
    each vertex with the line its outgoing edge lies on."""
    a, c = lines[k]
    if math.hypot(*a) <= 1e-300:  # no direction: everything or nothing
        return polygon if c >= 0.0 else []
    out: list[Corner] = []
    n = len(polygon)
    for i in range(n):
        (p, edge), (q, _) = polygon[i], polygon[(i + 1) % n]
        dp = a[0] * p[0] + a[1] * p[1] - c
        dq = a[0] * q[0] + a[1] * q[1] - c
        s = dp / (dp - dq) if (dp < 0.0 < dq) or (dq < 0.0 < dp) else 0.0
        x = (p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1]))
        if dp < 0.0 < dq:  # leaving: along the new line from the crossing on
            out += [(p, edge), (x, k)]
        elif dp <= 0.0:
            out.append((p, k if dp == 0.0 and dq > 0.0 else edge))
        elif dq < 0.0:  # entering
            out.append((x, edge))
    return out


def _corners(polygon: list[Corner], lines: list[Line]) -> list[tuple[float, float]]:
    """The vertices again, each as the intersection of the lines of its two edges (a 2 × 2
    solve on the lines' own numbers: the clipping's crossings of long edges lose digits)."""
    out = []
    for i, (p, edge) in enumerate(polygon):
        (a1, c1), (a2, c2) = lines[polygon[i - 1][1]], lines[edge]
        det = a1[0] * a2[1] - a1[1] * a2[0]
        scale = math.hypot(*a1) * math.hypot(*a2)
        if abs(det) > 1e-9 * scale:
            p = ((c1 * a2[1] - c2 * a1[1]) / det, (a1[0] * c2 - a2[0] * c1) / det)
        out.append(p)
    return out


def _circle_crossings(p: Any, q: Any, radius: float) -> list[float]:
    """Fractions ``s`` in (0, 1) where the segment ``p + s (q − p)`` crosses the circle."""
    dx, dy = q[0] - p[0], q[1] - p[1]
    a = dx * dx + dy * dy
    if a == 0.0:
        return []
    b = p[0] * dx + p[1] * dy  # half of the linear coefficient
    c = p[0] * p[0] + p[1] * p[1] - radius * radius
    disc = b * b - a * c
    if disc <= 0.0:
        return []
    root = math.sqrt(disc)
    # Both roots without cancellation.
    first = -(b + math.copysign(root, b))
    roots = sorted([first / a, c / first] if first != 0.0 else [0.0])
    return [s for s in roots if 0.0 < s < 1.0]


def _edge_area(p: Any, q: Any, radius: float) -> float:
    """Signed area of the triangle (origin, p, q) within the disc of ``radius`` at the origin:
    the edge cut where it crosses the circle; a piece inside adds its triangle, a piece outside
    the circular sector it subtends."""
    crossings = _circle_crossings(p, q, radius)
    cuts = [0.0, *crossings, 1.0]
    dx, dy = q[0] - p[0], q[1] - p[1]
    r2 = radius * radius
    total = 0.0
    for s0, s1 in itertools.pairwise(cuts):
        ax, ay = p[0] + s0 * dx, p[1] + s0 * dy
        bx, by = p[0] + s1 * dx, p[1] + s1 * dy
        cross = ax * by - ay * bx
        if crossings:  # pieces between crossings: inside or outside as their middle is
            mx, my = p[0] + 0.5 * (s0 + s1) * dx, p[1] + 0.5 * (s0 + s1) * dy
            inside = mx * mx + my * my < r2
        else:  # no crossing (or a tangent): inside where both ends are (the disc is convex)
            inside = ax * ax + ay * ay <= r2 and bx * bx + by * by <= r2
        if inside:
            total += 0.5 * cross
        else:
            total += 0.5 * radius * radius * math.atan2(cross, ax * bx + ay * by)
    return total


def _region_box(
    polygon: list[tuple[float, float]], radius: float, halfplanes: list[Any]
) -> tuple[float, float, float, float] | None:
    """The smallest box around polygon ∩ disc: its vertices inside the disc, its edges'
    crossings of the circle, and the circle's extreme points where inside the polygon."""
    points = [v for v in polygon if v[0] * v[0] + v[1] * v[1] <= radius * radius]
    for i, p in enumerate(polygon):
        q = polygon[(i + 1) % len(polygon)]
        for s in _circle_crossings(p, q, radius):
            points.append((p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])))
    slack = 1e-12 * radius
    for e in ((radius, 0.0), (-radius, 0.0), (0.0, radius), (0.0, -radius)):
        if all(a[0] * e[0] + a[1] * e[1] <= c + slack for a, c in halfplanes):
            points.append(e)
    if not points:
        return None
    xs, ys = [float(v[0]) for v in points], [float(v[1]) for v in points]
    return min(xs), max(xs), min(ys), max(ys)


def ground_footprint(
    sensor_position: Sequence[float],
    forward: Sequence[float],
    half_tangents: Sequence[float],
    max_range: float,
) -> Footprint:
    """The ground (``z = 0``) in a sensor's field of view within ``max_range``, and its area.

    Parameters
    ----------
    sensor_position : sequence of 3 float
        East, north, up [m].
    forward : sequence of 3 float
        The boresight (any length; :func:`targetacq.core.evaluation.boresight`).
    half_tangents : sequence of 2 float
        tan(FOV_h / 2) and tan(FOV_v / 2), > 0.
    max_range : float
        The farthest ground searched, as horizontal range from the sensor [m], > 0.

    Returns
    -------
    Footprint
        Area 0 where nothing is in view (or the position or boresight is not finite).

    Raises
    ------
    ValueError
        For half tangents or a range that are not > 0 and finite.

    Examples
    --------
    A sensor on the ground looking level sees the sector of its horizontal field of view:
    ``(hfov / 2π) · π R²``.

    >>> import math
    >>> half = (math.tan(math.radians(10.0)), math.tan(math.radians(5.0)))
    >>> fp = ground_footprint((0.0, 0.0, 0.0), (0.0, 1.0, 0.0), half, 1000.0)
    >>> round(fp.area / (math.radians(20.0) / 2 * 1000.0**2), 12)
    1.0
    """
    tan_h, tan_v = (float(v) for v in half_tangents)
    radius = float(max_range)
    for name, value in (("half tangent", tan_h), ("half tangent", tan_v), ("max_range", radius)):
        if not (value > 0 and math.isfinite(value)):
            raise ValueError(f"{name} must be > 0 and finite, got {value!r}")
    sx, sy, sz = (float(v) for v in sensor_position)
    fwd = [float(v) for v in forward]
    frame = geometry.sensor_frame(np.float64(fwd[0]), np.float64(fwd[1]), np.float64(fwd[2]), np)
    fx, fy, fz, rx, ry, ux, uy, uz = (float(v) for v in frame)
    axes = np.array([[rx, ry], [-ry, rx]])  # right, and ahead (horizontal)
    position, boresight = (sx, sy, sz), (fwd[0], fwd[1], fwd[2])
    empty = Footprint(
        position, boresight, (tan_h, tan_v), radius, 0.0, np.empty((0, 2)), axes, (0.0,) * 4
    )
    if not all(map(math.isfinite, (sx, sy, sz, *fwd))) or fx == fy == fz == 0.0:
        return empty
    # The faces of the pyramid, g · L <= 0 for the line of sight L = (px, py, −h) to a ground
    # point p: g = ±right − tan_h forward, ±up − tan_v forward. In the frame (right, ahead):
    # (g_xy · e1) a + (g_xy · e2) b <= h g_z.
    halfplanes: list[Line] = []
    for sign in (1.0, -1.0):
        for (vx, vy, vz), t in (((rx, ry, 0.0), tan_h), ((ux, uy, uz), tan_v)):
            gx, gy, gz = sign * vx - t * fx, sign * vy - t * fy, sign * vz - t * fz
            a = (gx * rx + gy * ry, gy * rx - gx * ry)
            halfplanes.append((a, sz * gz))
    # The square around the disc (lines 4-7: its bottom, right, top and left sides), then the
    # faces.
    lines = [*halfplanes, ((0.0, -1.0), radius), ((1.0, 0.0), radius)]
    lines += [((0.0, 1.0), radius), ((-1.0, 0.0), radius)]
    square = [(-radius, -radius), (radius, -radius), (radius, radius), (-radius, radius)]
    corners: list[Corner] = [(v, 4 + k) for k, v in enumerate(square)]
    for k in range(len(halfplanes)):
        corners = _clip(corners, lines, k)
        if len(corners) < 3:
            return empty
    polygon = _corners(corners, lines)
    area = abs(
        sum(_edge_area(p, polygon[(i + 1) % len(polygon)], radius) for i, p in enumerate(polygon))
    )
    box = _region_box(polygon, radius, halfplanes)
    if box is None or not area > 0.0:
        return empty
    rotated = np.asarray(polygon)
    world = rotated @ axes + np.array([sx, sy])
    return Footprint(position, boresight, (tan_h, tan_v), radius, area, world, axes, box)


def ground_area_in_view(
    sensor_position: Sequence[float],
    forward: Sequence[float],
    half_tangents: Sequence[float],
    max_range: float,
) -> float:
    """Ground area [m²] in a sensor's field of view within ``max_range`` (horizontal range).

    :func:`ground_footprint`'s ``area``: exact, by clipping and circular sectors.

    Examples
    --------
    Straight down from height h: ``(2 h tan(FOV_h/2)) × (2 h tan(FOV_v/2))``.

    >>> round(ground_area_in_view((5.0, 5.0, 1000.0), (0.0, 0.0, -1.0), (0.1, 0.05), 1e4), 6)
    20000.0
    """
    return ground_footprint(sensor_position, forward, half_tangents, max_range).area


# ------------------------------------------------------------------------------------------------
# The draws
# ------------------------------------------------------------------------------------------------


class FalseDetection(NamedTuple):
    """One false detection: ``sensor`` declared a target at ``time`` [s] where there was none,
    at ``position`` (east, north, up [m], on the ground), in run ``run``."""

    sensor: str
    time: float
    position: tuple[float, float, float]
    run: int


@dataclass(frozen=True)
class FalseDetections:
    """False detections, as arrays (ordered by run, then time, then sensor).

    Attributes
    ----------
    run : numpy.ndarray of int (k,)
        The run of each (always 0 of a :class:`targetacq.Simulation` reset to run 0, the run it
        was reset to otherwise).
    sensor : numpy.ndarray of str (k,)
        The sensor's name (of its group, for the bands of a colour camera).
    time : numpy.ndarray of float (k,)
        When [s].
    position : numpy.ndarray of float (k, 3)
        Where: east, north, up [m], on the ground (up = 0).
    """

    run: np.ndarray
    sensor: np.ndarray
    time: np.ndarray
    position: np.ndarray

    @classmethod
    def empty(cls) -> FalseDetections:
        """No false detections."""
        return cls(
            np.empty(0, dtype=np.int64), np.empty(0, dtype=str), np.empty(0), np.empty((0, 3))
        )

    @classmethod
    def concatenate(cls, parts: Sequence[FalseDetections]) -> FalseDetections:
        """The detections of ``parts`` together, ordered by run, time and sensor."""
        parts = [p for p in parts if len(p)]
        if not parts:
            return cls.empty()
        if len(parts) == 1:
            return parts[0]
        run = np.concatenate([p.run for p in parts])
        sensor = np.concatenate([p.sensor for p in parts])
        time = np.concatenate([p.time for p in parts])
        order = np.lexsort((sensor, time, run))
        return cls(
            run[order],
            sensor[order],
            time[order],
            np.concatenate([p.position for p in parts])[order],
        )

    def __len__(self) -> int:
        return int(self.time.size)

    def __iter__(self) -> Iterator[FalseDetection]:
        for r, s, t, p in zip(
            self.run.tolist(),
            self.sensor.tolist(),
            self.time.tolist(),
            self.position.tolist(),
            strict=True,
        ):
            yield FalseDetection(s, t, (p[0], p[1], p[2]), r)

    def frame(self) -> Any:
        """A pandas DataFrame, one row per detection: run, sensor, time [s], x, y, z [m]."""
        import pandas as pd

        return pd.DataFrame(
            {
                "run": self.run,
                "sensor": self.sensor.astype(str),
                "time": self.time,
                "x": self.position[:, 0],
                "y": self.position[:, 1],
                "z": self.position[:, 2],
            }
        )


def _unit(high: np.ndarray, low: np.ndarray) -> np.ndarray:
    """Floats in (0, 1) from two 32-bit words: 27 + 26 random bits, as
    :func:`targetacq.base.sampling.uniforms` makes them."""
    mantissa = ((high.astype(np.uint64) >> np.uint64(5)) << np.uint64(26)) | (
        low.astype(np.uint64) >> np.uint64(6)
    )
    return (mantissa.astype(np.float64) + 0.5) / 2.0**53


def _words(key: tuple[int, int], step: Any, run: Any, purpose: Any, item: Any) -> tuple[Any, ...]:
    counter = (
        np.asarray(step, dtype=np.uint32),
        np.asarray(run, dtype=np.uint32),
        np.asarray(purpose, dtype=np.uint32),
        np.asarray(item, dtype=np.uint32),
    )
    return philox4x32(counter, (np.uint32(key[0]), np.uint32(key[1])))


def _poisson_quantile(u: np.ndarray, mean: np.ndarray) -> np.ndarray:
    """The smallest k with ``P(N <= k) >= u`` for N Poisson(mean), elementwise: exact
    inversion (zero where ``u <= exp(−mean)``, the common case; the continuous inverse's ceiling
    made exact at the integers elsewhere)."""
    mean = np.broadcast_to(mean, u.shape)
    k = np.zeros(u.shape, dtype=np.int64)
    some = u > np.exp(-mean)
    if not some.any():
        return k
    from scipy import special

    v, m = u[some], mean[some]
    n = np.maximum(np.ceil(np.nan_to_num(special.pdtrik(v, m), nan=1.0)), 1.0)
    for _ in range(64):
        down = (n > 1.0) & (special.pdtr(n - 1.0, m) >= v)
        up = special.pdtr(n, m) < v
        if not (down.any() or up.any()):
            break
        n = n - down + up
    k[some] = n.astype(np.int64)
    return k


def _check_interval(start: float, end: float) -> float:
    if not (math.isfinite(start) and math.isfinite(end) and end >= start):
        raise ValueError(f"need finite times with end >= start, got ({start!r}, {end!r}]")
    return end - start


@dataclass(frozen=True)
class _Steps:
    """One sensor's footprints over steps, stacked (K steps): what a draw needs."""

    step: np.ndarray  # (K,) the steps' indices (counters)
    start: np.ndarray  # (K,) [s]
    end: np.ndarray  # (K,) [s]
    mean: np.ndarray  # (K,) expected count of one run
    position: np.ndarray  # (K, 3) the sensor [m]
    forward: np.ndarray  # (K, 3)
    half: np.ndarray  # (K, 2)
    axes: np.ndarray  # (K, 2, 2)
    box: np.ndarray  # (K, 4)
    max_range: float

    @classmethod
    def of(cls, entries: Sequence[tuple[int, float, float, Footprint, float]]) -> _Steps:
        """From (step, start, end, footprint, mean) of steps with an area in view."""
        fps = [e[3] for e in entries]
        return cls(
            np.array([e[0] for e in entries], dtype=np.int64),
            np.array([e[1] for e in entries], dtype=float),
            np.array([e[2] for e in entries], dtype=float),
            np.array([e[4] for e in entries], dtype=float),
            np.array([f.sensor_position for f in fps], dtype=float),
            np.array([f.forward for f in fps], dtype=float),
            np.array([f.half_tangents for f in fps], dtype=float),
            np.array([f.axes for f in fps], dtype=float),
            np.array([f.box for f in fps], dtype=float),
            fps[0].max_range,
        )


def _draw(
    steps: _Steps,
    key: tuple[int, int],
    sensor: str,
    runs: np.ndarray,
    terrain: tuple[ElevationModel, float] | None = None,
) -> FalseDetections:
    """The reports of one sensor over steps for each run (see the module docstring). Counters:
    (step, run, purpose, report index), so a run's reports in a step depend on nothing else.
    ``terrain``: an elevation model and its Earth-radius factor; only reports on ground in the
    sensor's sight are kept, at the ground's altitude (the module docstring, Terrain)."""
    u = _unit(*_words(key, steps.step[:, None], runs[None, :], _COUNT, 0)[:2])
    counts = _poisson_quantile(u, steps.mean[:, None]).reshape(-1)  # (K · runs,) step-major
    total = int(counts.sum())
    if total == 0:
        return FalseDetections.empty()
    which = np.repeat(np.repeat(np.arange(steps.step.size), runs.size), counts)  # each's step
    run = np.repeat(np.tile(runs, steps.step.size), counts)
    item = np.arange(total) - np.repeat(np.cumsum(counts) - counts, counts)
    step = steps.step[which]
    # Times uniform in (start, end].
    start, end = steps.start[which], steps.end[which]
    at = start + (end - start) * _unit(*_words(key, step, run, _TIME, item)[:2])
    at = np.minimum(np.maximum(at, np.nextafter(start, math.inf)), end)
    # Positions uniform in the region: rejection from its box in the boresight's frame.
    where = np.empty((total, 2))
    pending = np.arange(total)
    for attempt in range(_MAX_ATTEMPTS):
        k = which[pending]
        w0, w1, w2, w3 = _words(
            key, step[pending], run[pending], _POSITION + attempt, item[pending]
        )
        box, axes, sensor_at = steps.box[k], steps.axes[k], steps.position[k]
        a = box[:, 0] + (box[:, 1] - box[:, 0]) * _unit(w0, w1)
        b = box[:, 2] + (box[:, 3] - box[:, 2]) * _unit(w2, w3)
        dx = a * axes[:, 0, 0] + b * axes[:, 1, 0]
        dy = a * axes[:, 0, 1] + b * axes[:, 1, 1]
        forward = (steps.forward[k, 0], steps.forward[k, 1], steps.forward[k, 2])
        keep = (np.hypot(dx, dy) <= steps.max_range) & geometry.within_field_of_view(
            dx, dy, -sensor_at[:, 2], forward, (steps.half[k, 0], steps.half[k, 1])
        )
        where[pending[keep]] = np.column_stack([dx, dy])[keep] + sensor_at[keep, :2]
        pending = pending[~keep]
        if pending.size == 0:
            break
    else:  # pragma: no cover - at least half of each box is accepted
        raise RuntimeError("false targets: rejection sampling did not converge")
    position = np.column_stack([where, np.zeros(total)])
    if terrain is not None:
        model, factor = terrain
        position[:, 2] = model.height_at(where[:, 0], where[:, 1])
        # A height of 1 m: the fraction is 1 exactly where nothing rises above the sight line
        # to the ground point itself (whatever the height).
        seen = line_of_sight(model, None, None, steps.position[which], position, 1.0, k=factor)
        kept = seen == 1.0  # NaN (off the grid, a void on the way): not known to be seen
        run, at, position = run[kept], at[kept], position[kept]
        total = int(kept.sum())
    order = np.lexsort((at, run))
    return FalseDetections(
        run[order].astype(np.int64), np.full(total, sensor), at[order], position[order]
    )


def _key(seed: int, sensor: str) -> tuple[int, int]:
    return stream_key(check_seed(seed), sensor, *_STREAM)


def sample_false_detections(
    footprint: Footprint,
    rate: float,
    start: float,
    end: float,
    *,
    seed: int,
    sensor: str,
    step: int,
    runs: Any = 0,
) -> FalseDetections:
    """Draw one sensor's false detections over the interval ``(start, end]``.

    The count of each run is Poisson with mean ``rate · (end − start)``; times are uniform in
    the interval and positions uniform in ``footprint``'s region. Counter-based: the result for
    a run depends only on ``seed``, ``sensor``, ``step`` and the run, whatever other runs are
    drawn with it.

    Parameters
    ----------
    footprint : Footprint
        Where (:func:`ground_footprint`), at the end of the interval.
    rate : float
        [1/s], >= 0 (:func:`false_target_rate`).
    start, end : float
        [s], finite, ``end >= start``.
    seed : int
        In [0, 2**128 - 1].
    sensor : str
        The sensor's (group's) name: names the random stream.
    step : int
        The step's index since the start of the run (its counter), in [0, 2**32).
    runs : int or array_like of int
        The runs drawn, each in [0, 2**32).

    Returns
    -------
    FalseDetections
        Ordered by run and time.

    Examples
    --------
    >>> fp = ground_footprint((0.0, 0.0, 1000.0), (0.0, 0.0, -1.0), (0.1, 0.1), 5000.0)
    >>> out = sample_false_detections(fp, 2.0, 0.0, 1.0, seed=7, sensor="ir", step=1, runs=[0, 1])
    >>> bool(fp.contains(out.position[:, 0], out.position[:, 1]).all())
    True
    """
    dt = _check_interval(float(start), float(end))
    if not (rate >= 0 and math.isfinite(rate)):
        raise ValueError(f"rate must be >= 0 per second and finite, got {rate!r}")
    if not (isinstance(step, (int, np.integer)) and 0 <= step < 2**32):
        raise ValueError(f"step must be an integer in [0, 2**32), got {step!r}")
    run = np.atleast_1d(np.asarray(runs))
    if run.dtype.kind not in "iu" or run.ndim != 1 or ((run < 0) | (run >= 2**32)).any():
        raise ValueError(f"runs must be integers in [0, 2**32), got {runs!r}")
    if not footprint.area > 0.0 or rate * dt == 0.0:
        return FalseDetections.empty()
    steps = _Steps.of([(int(step), float(start), float(end), footprint, rate * dt)])
    return _draw(steps, _key(seed, sensor), sensor, run)


# ------------------------------------------------------------------------------------------------
# A scenario's false targets
# ------------------------------------------------------------------------------------------------


class FalseTargetSampler:
    """A scenario's ``[false_targets]`` for its compiled sensors: draws per step and run.

    Parameters
    ----------
    table : targetacq.scenario.schema.FalseTargets
    sensors : targetacq.core.SensorArrays
        The compiled sensors: one row per sensor (per band of a colour camera: rows of one
        group report false targets once, under the group's name).
    search_time : float
        t_s [s], > 0.
    seed : int
    terrain : (ElevationModel, float), optional
        The scenario's ``[terrain]`` elevation model and its effective Earth-radius factor:
        reports only on ground in sight of the sensor (the module docstring, Terrain).

    Raises
    ------
    ValueError
        Where ``table.sensors`` is empty or names a sensor that is unknown or has no field of
        view (:func:`false_target_problems`'s words).
    """

    def __init__(
        self,
        table: Any,
        sensors: SensorArrays,
        search_time: float,
        seed: int,
        terrain: tuple[ElevationModel, float] | None = None,
    ) -> None:
        self.terrain = terrain
        if not (search_time > 0 and math.isfinite(search_time)):
            raise ValueError(f"search_time must be > 0 s, got {search_time!r}")
        self.table = table
        self.sensors = sensors
        self.search_time = float(search_time)
        self.seed = check_seed(seed)
        groups = tuple(getattr(sensors, "group_names", sensors.names))
        first: dict[str, int] = {}
        for row, group in enumerate(groups):
            first.setdefault(group, row)
        half = np.asarray(sensors.half_tangents, dtype=float).reshape(-1, 2)
        if table.sensors is None:
            chosen = [g for g in first if np.isfinite(half[first[g]]).all()]
        else:
            problems = [] if table.sensors else [NO_FALSE_TARGET_SENSORS]
            for k, name in enumerate(table.sensors):
                if name not in first:
                    problems.append(f"false_targets.sensors[{k}]: unknown sensor {name!r}")
                elif not np.isfinite(half[first[name]]).all():
                    problems.append(
                        f"false_targets.sensors[{k}]: sensor {name!r} has no field of view"
                    )
            if problems:
                raise ValueError("\n".join(problems))
            chosen = list(dict.fromkeys(table.sensors))
        self.groups: tuple[str, ...] = tuple(chosen)
        """The sensors (groups) that can report false targets, in the sensors' order."""
        self.rows = np.array([first[g] for g in self.groups], dtype=np.int64)
        self._half = half
        self._keys = {g: _key(self.seed, g) for g in self.groups}

    def footprints(
        self, sensor_positions: Array, pointing: Array = None
    ) -> list[tuple[str, Footprint, float]]:
        """Each reporting sensor's footprint and rate [1/s] at positions (and pointing).

        Parameters
        ----------
        sensor_positions : array (n_rows, 3)
            [m], one row per compiled sensor row.
        pointing : array (n_rows, 2), optional
            Azimuth and depression [rad] replacing a row's own pointing where finite.

        Returns
        -------
        list of (name, Footprint, rate)
            Only sensors pointed now with something in view.
        """
        from targetacq.core.evaluation import boresight

        positions = np.asarray(sensor_positions, dtype=float)
        point = None if pointing is None else np.asarray(pointing, dtype=float)
        forward, pointed = boresight(positions, self.sensors, point)
        pointed = np.asarray(pointed).reshape(-1)
        out = []
        for group, row in zip(self.groups, self.rows.tolist(), strict=True):
            if not pointed[row]:
                continue
            fp = ground_footprint(
                positions[row],
                [float(np.asarray(forward[k])[row]) for k in range(3)],
                self._half[row],
                self.table.max_range,
            )
            if fp.area > 0.0:
                rate = float(
                    false_target_rate(
                        self.table.density, self.table.probability, fp.area, self.search_time
                    )
                )
                out.append((group, fp, rate))
        return out

    def draw(
        self,
        steps: Sequence[tuple[int, float, float, Sequence[tuple[str, Footprint, float]]]],
        runs: Any,
    ) -> FalseDetections:
        """The reports of ``runs`` over steps, each ``(step, start, end, footprints)``: the
        step's index, its interval ``(start, end]`` [s] and :meth:`footprints` at ``end``.

        Returns
        -------
        FalseDetections
            Ordered by run, time and sensor.
        """
        run = np.asarray(runs, dtype=np.int64).reshape(-1)
        entries: dict[str, list[tuple[int, float, float, Footprint, float]]] = {}
        for step, start, end, found in steps:
            dt = _check_interval(start, end)
            for group, fp, rate in found:
                if dt > 0.0 and rate > 0.0:
                    entries.setdefault(group, []).append((step, start, end, fp, rate * dt))
        parts = [
            _draw(_Steps.of(listed), self._keys[group], group, run, self.terrain)
            for group, listed in entries.items()
        ]
        return FalseDetections.concatenate(parts)

    def sample(
        self,
        step: int,
        start: float,
        end: float,
        runs: Any,
        sensor_positions: Any,
        pointing: Any = None,
    ) -> FalseDetections:
        """The reports of ``runs`` over one step ``(start, end]`` with the sensors at
        ``sensor_positions`` (and ``pointing``) at ``end``: :meth:`draw` of :meth:`footprints`."""
        return self.draw([(step, start, end, self.footprints(sensor_positions, pointing))], runs)
