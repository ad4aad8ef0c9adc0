"""Aspect-dependent signatures: where an observer sees a target from, and a table over it.

A target's thermal signature depends on the side it shows: an engine deck, an exhaust or a
sunlit flank is warmer than the front. Signature tables (infrared signature tables of
engagement simulations, az/el grids of radiant intensity of target-modelling tools) give it
over the *aspect*: the direction from the target to the observer, in the target's own frame.

Conventions (stated here once, used everywhere the tables are read):

- **azimuth** of the observer, clockwise seen from above, from the target's heading (the
  direction its long axis points, :attr:`targetacq.scenario.schema.Target.heading`): 0 is
  head-on (the observer in front), π/2 its right side, π its rear, 3π/2 its left side; taken
  modulo 2π, the table is periodic in it;
- **elevation** of the observer above the target's horizontal plane: 0 level, π/2 straight
  above; outside the table's range the nearest row is used (the table is held constant beyond
  its first and last elevation, not extrapolated).

Between the nodes the table is interpolated bilinearly (linear in azimuth, across the 2π wrap
too, and linear in elevation). A table with a single azimuth (or elevation) is constant along
that axis, so a 1 × 1 table is the target's one temperature.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.base.inputs import read_input_text

__all__ = ["ASPECT_QUANTITIES", "AspectTable", "interpolate_aspect", "observer_aspect"]

ASPECT_QUANTITIES: dict[str, str] = {
    "temperature": "the target's temperature [K] seen from that aspect",
    "contrast": "the target's temperature minus the background's [K] seen from that aspect",
}
"""What a signature table may tabulate (its value column), and what it means."""

_TURN = 2.0 * math.pi


def observer_aspect(x: Array, y: Array, z: Array, heading: Array) -> tuple[Any, Any]:
    """The aspect from which a sensor sees a target: azimuth and elevation in its frame.

    Parameters
    ----------
    x, y, z : array_like
        Target position minus sensor position [m] (east, north, up), broadcasting.
    heading : array_like
        The target's heading [rad], from north clockwise.

    Returns
    -------
    azimuth : array
        ``(atan2(−x, −y) − heading) mod 2π`` [rad], in [0, 2π): the bearing of the sensor as
        seen from the target, from the target's heading, clockwise (0 head-on, π/2 its right).
    elevation : array
        ``atan2(−z, sqrt(x² + y²))`` [rad], in [−π/2, π/2]: positive for a sensor above.

    Examples
    --------
    A truck heading north, seen from a sensor to its east, 1 km away and 1 km up:

    >>> import math
    >>> azimuth, elevation = observer_aspect(-1000.0, 0.0, -1000.0, 0.0)
    >>> round(math.degrees(float(azimuth)), 6), round(math.degrees(float(elevation)), 6)
    (90.0, 45.0)
    """
    xp, (x, y, z, heading) = _arrays.arrays(x, y, z, heading, names=("x", "y", "z", "heading"))
    bearing = xp.atan2(-x, -y)
    azimuth = xp.remainder(bearing - heading, _TURN)
    # remainder can round a tiny negative up to exactly 2π: keep the half-open interval.
    azimuth = xp.where(azimuth >= _TURN, azimuth - _TURN, azimuth)
    elevation = xp.atan2(-z, xp.sqrt(x * x + y * y))
    return azimuth, elevation


def interpolate_aspect(
    azimuth_nodes: Array,
    elevation_nodes: Array,
    values: Array,
    azimuth: Array,
    elevation: Array,
) -> Any:
    """A signature table at given aspects: bilinear, periodic in azimuth, held in elevation.

    Parameters
    ----------
    azimuth_nodes : array (n_az,)
        The table's azimuths [rad], strictly ascending within [0, 2π).
    elevation_nodes : array (n_el,)
        The table's elevations [rad], strictly ascending.
    values : array (*lead, n_az, n_el)
        The tabulated quantity at the nodes; ``lead`` axes (a table per sensor and target, say)
        go with the leading axes of ``azimuth``.
    azimuth, elevation : array (*lead, *rest)
        Where to read the table [rad] (:func:`observer_aspect`), broadcasting together; their
        leading axes broadcast with ``lead``.

    Returns
    -------
    array (*lead, *rest)
        ``(1−u)(1−v) f₀₀ + u(1−v) f₁₀ + (1−u) v f₀₁ + u v f₁₁`` with ``u`` the fraction of the
        azimuth between its two nodes (the last node and the first + 2π across the wrap) and
        ``v`` of the elevation between its nodes (the elevation clipped to the table first).
        NaN where the azimuth or the elevation is NaN.

    Examples
    --------
    A table warmer from the rear (π) than the front, at one elevation:

    >>> import math
    >>> import numpy as np
    >>> nodes = np.radians([0.0, 90.0, 180.0, 270.0])
    >>> table = np.array([[300.0], [304.0], [310.0], [304.0]])
    >>> values = interpolate_aspect(nodes, np.array([0.0]), table,
    ...                             np.radians([45.0, 315.0, 180.0]), np.zeros(3))
    >>> [float(v) for v in values]
    [302.0, 302.0, 310.0]
    """
    xp, (az_nodes, el_nodes, table, az, el) = _arrays.arrays(
        azimuth_nodes,
        elevation_nodes,
        values,
        azimuth,
        elevation,
        names=("azimuth_nodes", "elevation_nodes", "values", "azimuth", "elevation"),
        broadcast=False,
    )
    n_az, n_el = int(az_nodes.shape[0]), int(el_nodes.shape[0])
    if table.ndim < 2 or tuple(table.shape[-2:]) != (n_az, n_el):
        raise ValueError(
            f"values must end in the table's axes ({n_az}, {n_el}) (azimuth, elevation), got "
            f"shape {tuple(table.shape)}"
        )
    lead = tuple(table.shape[:-2])
    shape = np.broadcast_shapes(tuple(az.shape), tuple(el.shape))
    if len(shape) < len(lead):
        shape = (1,) * (len(lead) - len(shape)) + shape
    shape = np.broadcast_shapes(shape, lead + (1,) * (len(shape) - len(lead)))
    az = xp.broadcast_to(az, shape)
    el = xp.broadcast_to(el, shape)

    # Azimuth: the nodes extended by one on each side across the wrap.
    phi = xp.remainder(az, _TURN)
    extended = xp.concat([az_nodes[-1:] - _TURN, az_nodes, az_nodes[:1] + _TURN])
    k = xp.searchsorted(extended, xp.where(xp.isnan(phi), 0.0, phi), side="right") - 1
    k = xp.clip(k, 0, n_az)
    low, high = xp.take(extended, k), xp.take(extended, k + 1)
    u = (phi - low) / (high - low)
    i0 = xp.remainder(k - 1 + n_az, n_az)
    i1 = xp.remainder(k, n_az)

    # Elevation: clipped to the table, then linear between its nodes.
    if n_el == 1:
        j0 = j1 = xp.zeros(shape, dtype=k.dtype)
        v = xp.where(xp.isnan(el), xp.nan, 0.0)
    else:
        theta = xp.clip(el, el_nodes[0], el_nodes[-1])
        j = xp.searchsorted(el_nodes, xp.where(xp.isnan(theta), el_nodes[0], theta), side="right")
        j0 = xp.clip(j - 1, 0, n_el - 2)
        j1 = j0 + 1
        v = (theta - xp.take(el_nodes, j0)) / (xp.take(el_nodes, j1) - xp.take(el_nodes, j0))

    size = n_az * n_el
    count = math.prod(lead)
    offset = xp.reshape(
        xp.arange(count, dtype=k.dtype) * size, lead + (1,) * (len(shape) - len(lead))
    )
    flat = xp.reshape(table, (-1,))

    def at(i: Any, j: Any) -> Any:
        return xp.reshape(xp.take(flat, xp.reshape(offset + i * n_el + j, (-1,))), shape)

    return (
        (1.0 - u) * (1.0 - v) * at(i0, j0)
        + u * (1.0 - v) * at(i1, j0)
        + (1.0 - u) * v * at(i0, j1)
        + u * v * at(i1, j1)
    )


@dataclass(frozen=True)
class AspectTable:
    """A signature table over aspect (see the module's conventions).

    Attributes
    ----------
    azimuth : tuple of float
        Strictly ascending azimuths [rad] in [0, 2π).
    elevation : tuple of float
        Strictly ascending elevations [rad] in [−π/2, π/2].
    values : tuple of tuple of float
        ``values[i][j]`` at ``azimuth[i]``, ``elevation[j]`` [K].
    quantity : str
        One of :data:`ASPECT_QUANTITIES`: ``temperature`` or ``contrast``.
    source : str
        Where the table came from (a file's path), said first in its errors; empty for a table
        written in the scenario (its place there is said instead).
    """

    azimuth: tuple[float, ...]
    elevation: tuple[float, ...]
    values: tuple[tuple[float, ...], ...]
    quantity: str = "temperature"
    source: str = ""

    def __post_init__(self) -> None:
        where = f"{self.source}: " if self.source else ""
        if self.quantity not in ASPECT_QUANTITIES:
            raise ValueError(
                f"{where}the quantity must be one of {', '.join(ASPECT_QUANTITIES)}, got "
                f"{self.quantity!r}"
            )
        for name, nodes, low, high in (
            ("azimuth", self.azimuth, 0.0, _TURN),
            ("elevation", self.elevation, -math.pi / 2, math.pi / 2),
        ):
            if len(nodes) < 1:
                raise ValueError(f"{where}{name}: at least one value, got none")
            if not all(math.isfinite(a) for a in nodes):
                raise ValueError(f"{where}{name}: values must be finite")
            if any(b <= a for a, b in itertools.pairwise(nodes)):
                raise ValueError(f"{where}{name}: values must be strictly ascending")
            closed = name == "elevation"
            if nodes[0] < low - 1e-12 or (
                nodes[-1] > high + 1e-12 if closed else nodes[-1] >= high - 1e-12
            ):
                bounds = "[-90, 90] deg" if closed else "[0, 360) deg"
                raise ValueError(f"{where}{name}: values must lie in {bounds}")
        shape = (len(self.azimuth), len(self.elevation))
        if len(self.values) != shape[0] or any(len(row) != shape[1] for row in self.values):
            raise ValueError(
                f"{where}the values must form a grid of {shape[0]} azimuths × {shape[1]} elevations"
            )
        flat = [v for row in self.values for v in row]
        if not all(math.isfinite(v) for v in flat):
            raise ValueError(f"{where}the {self.quantity} values must be finite")
        if self.quantity == "temperature" and min(flat) <= 0.0:
            raise ValueError(f"{where}temperatures must be > 0 K, got {min(flat)!r}")

    @property
    def grid(self) -> np.ndarray:
        """The values as an array (n_az, n_el) [K]."""
        return np.array(self.values, dtype=float)

    @classmethod
    def from_rows(
        cls,
        azimuth: Array,
        elevation: Array,
        values: Array,
        quantity: str = "temperature",
        source: str = "",
    ) -> AspectTable:
        """A table from one row per node (any order): azimuth, elevation [rad], value [K].

        Every azimuth must appear with every elevation exactly once (a full grid).

        Examples
        --------
        >>> import math
        >>> table = AspectTable.from_rows([0.0, math.pi, 0.0, math.pi], [0.0, 0.0, 1.0, 1.0],
        ...                               [300.0, 310.0, 301.0, 311.0])
        >>> table.values
        ((300.0, 301.0), (310.0, 311.0))
        """
        where = f"{source}: " if source else ""
        az = np.asarray(azimuth, dtype=float).ravel()
        el = np.asarray(elevation, dtype=float).ravel()
        val = np.asarray(values, dtype=float).ravel()
        if not (az.size == el.size == val.size) or az.size == 0:
            raise ValueError(f"{where}azimuth, elevation and values need one row per node")
        if not (np.isfinite(az).all() and np.isfinite(el).all()):
            raise ValueError(f"{where}azimuths and elevations must be finite")
        if az.min() < 0.0 or az.max() >= _TURN or abs(el).max() > math.pi / 2:
            raise ValueError(
                f"{where}azimuths must lie in [0, 360) deg and elevations in [-90, 90] deg"
            )
        az_nodes, el_nodes = np.unique(az), np.unique(el)
        grid = np.full((az_nodes.size, el_nodes.size), np.nan)
        seen = np.zeros(grid.shape, dtype=int)
        i, j = np.searchsorted(az_nodes, az), np.searchsorted(el_nodes, el)
        np.add.at(seen, (i, j), 1)
        if (seen != 1).any():
            a, e = np.argwhere(seen != 1)[0]
            what = "twice" if seen[a, e] > 1 else "missing"
            raise ValueError(
                f"{where}the rows must form a full grid of azimuth × elevation: the node "
                f"azimuth {math.degrees(az_nodes[a]):g} deg, elevation "
                f"{math.degrees(el_nodes[e]):g} deg is {what}"
            )
        grid[i, j] = val
        return cls(
            tuple(float(a) for a in az_nodes),
            tuple(float(e) for e in el_nodes),
            tuple(tuple(float(v) for v in row) for row in grid),
            quantity,
            source,
        )

    @classmethod
    def from_csv(cls, path: str | Path, state: str | None = None) -> AspectTable:
        """Read a signature table from a CSV file, one row per node.

        The header names the columns ``azimuth`` and ``elevation`` (in **degrees**, the
        module's conventions), one value column ``temperature`` or ``contrast`` (in **K**), and
        optionally ``state`` (e.g. ``engine-on``, ``engine-off``: one grid per state, ``state``
        picks one). Lines starting with ``#`` are comments (the provenance); blank lines are
        skipped; other columns are ignored. UTF-8, at most 10 MB
        (:func:`targetacq.base.inputs.read_input_text`).

        Raises
        ------
        ValueError
            Naming the file (and the line): no such file, a missing column, a cell that is
            not a number, a grid with a node missing or repeated, a state that is not in the
            file (the file's states listed), or a file with states and no ``state`` chosen.

        Examples
        --------
        >>> import pathlib, tempfile
        >>> text = ("# exhaust at the rear\\nazimuth,elevation,temperature\\n"
        ...         "0,0,300\\n180,0,320\\n0,30,302\\n180,30,318\\n")
        >>> with tempfile.TemporaryDirectory() as folder:
        ...     path = pathlib.Path(folder) / "tank.csv"
        ...     _ = path.write_text(text)
        ...     table = AspectTable.from_csv(path)
        >>> table.values, [round(math.degrees(e)) for e in table.elevation]
        (((300.0, 302.0), (320.0, 318.0)), [0, 30])
        """
        name = str(path)
        text = read_input_text(path, "signature table")
        lines = [
            (number, line.strip())
            for number, line in enumerate(text.splitlines(), start=1)
            if line.strip() and not line.lstrip().startswith("#")
        ]
        if not lines:
            raise ValueError(f"{name}: no header line (azimuth, elevation, temperature)")
        header = [cell.strip().lower() for cell in lines[0][1].split(",")]
        quantities = [q for q in ASPECT_QUANTITIES if q in header]
        missing = [c for c in ("azimuth", "elevation") if c not in header]
        if missing or len(quantities) != 1:
            raise ValueError(
                f"{name}: the header must name the columns azimuth, elevation and one of "
                f"{', '.join(ASPECT_QUANTITIES)}, got {', '.join(header)}"
            )
        quantity = quantities[0]
        column = {c: header.index(c) for c in ("azimuth", "elevation", quantity)}
        state_column = header.index("state") if "state" in header else None
        rows: list[tuple[float, float, float]] = []
        states: list[str] = []
        for number, line in lines[1:]:
            cells = [cell.strip() for cell in line.split(",")]
            if len(cells) < len(header):
                raise ValueError(f"{name}, line {number}: {len(header)} cells expected")
            try:
                rows.append(tuple(float(cells[column[c]]) for c in column))  # type: ignore[arg-type]
            except ValueError:
                raise ValueError(
                    f"{name}, line {number}: azimuth, elevation and {quantity} must be numbers"
                ) from None
            states.append(cells[state_column] if state_column is not None else "")
        known = sorted(set(states))
        if state_column is None:
            if state is not None:
                raise ValueError(
                    f"{name}: has no state column, so state {state!r} cannot be chosen"
                )
            chosen = rows
        else:
            if state is None or state not in known:
                raise ValueError(
                    f"{name}: choose a state, one of {', '.join(known)}"
                    + ("" if state is None else f" (got {state!r})")
                )
            chosen = [row for row, s in zip(rows, states, strict=True) if s == state]
        if not chosen:
            raise ValueError(f"{name}: no rows")
        data = np.array(chosen, dtype=float)
        return cls.from_rows(
            np.radians(data[:, 0]),
            np.radians(data[:, 1]),
            data[:, 2],
            quantity,
            name if state is None else f"{name} (state {state})",
        )
