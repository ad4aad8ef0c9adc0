"""Range performance of a scenario's sensor-target pairs through the array core.

The one evaluator of a scenario's DRI ranges (``targetacq dri SCENARIO`` and a scenario's
report, on the command line and the web), for every sensor type: :func:`pair_performance`
moves each target along the ground, away from the sensor along the bearing it has at the
scenario's start (its height and heading kept), evaluates the core at every slant range of a
grid, and finds each task's range for each probability by bisection on the core itself. So
everything the core knows is in the ranges: the outline seen from each position, MRTD curves, a
sensor's own noise over the target's outline, path segments and local clouds where the target
would stand, the radar equation and resolution cell, a laser radar's two-way path. A slant
range shorter than the height between sensor and target has no place on the line (NaN).

What the line of ranges does with the rest of a scenario:

- **field of view**: ignored (``in_view`` true): the ranges are what the sensor can do where
  it looks at the target. A scenario's pointing and field of view decide *when* a target is in
  view (``evaluate``, ``simulate``), not how far it is seen: wherever the target is in view at
  a DRI range, ``evaluate`` gives the asked probability there.
- **terrain map**: used, around the target where it stands at the start: the SCR is the map's
  window at the target's start position, its classes seen at the footprint ``R · IFOV`` of
  each range (:func:`targetacq.core.evaluation.footprint_scr`). The target keeps its own
  surroundings: moved along the line, it would cross other cells of the map (or leave it),
  and a range curve would jump at their edges, so that a DRI range would be an edge of the
  map rather than a range of the sensor.
- **false targets** (``[false_targets]``): not in a pair's probabilities (they are a
  simulation's false detections, as ``evaluate`` leaves them out too), so not in its ranges.

Its result is a :class:`targetacq.core.cases.RangePerformance`, as the analyst's range cases give,
so the report and the figures take it as they take those.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from targetacq.core.cases import RangePerformance
from targetacq.core.compile import scenario_positions
from targetacq.core.evaluation import factors, footprint_scr, probabilities

__all__ = ["pair_performance"]

TASKS = ("detection", "recognition", "identification")
_FLOOR = 0.02  # the automatic grid ends where every task of every pair is below this
_BISECTIONS = 48  # a range to 2^-48 of its bracket: far below a metre


class _Pairs:
    """The start geometry of the chosen sensor rows and every target."""

    def __init__(self, chain: Any, rows: Sequence[int]) -> None:
        self.chain, self.rows = chain, list(rows)
        t0 = chain.scenario.time.start
        s_pos, t_pos, heading = scenario_positions(chain.scenario, [t0])
        self.sensors, self.targets, self.heading = s_pos[:, 0], t_pos[:, 0], heading[:, 0]

    def along(self, row: int, slant: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Target positions ``(n_g, n, 3)`` at slant ranges ``(n,)`` (or ``(n_g, n)``, a
        range per target) from sensor ``row`` along each target's start bearing (NaN where a
        range is shorter than the height difference), and the sensors' ``(n_s, n, 3)``."""
        s = self.sensors[row]
        offset = self.targets - s
        flat = np.hypot(offset[:, 0], offset[:, 1])[:, None]
        safe = np.where(flat > 0, flat, 1.0)
        east = np.where(flat > 0, offset[:, :1] / safe, 1.0)
        north = np.where(flat > 0, offset[:, 1:2] / safe, 0.0)
        r = np.broadcast_to(slant, (len(offset), slant.shape[-1]))
        dz = offset[:, 2:3]
        with np.errstate(invalid="ignore"):
            ground = np.sqrt(r * r - dz * dz)
        positions = np.stack(
            [
                s[0] + east * ground,
                s[1] + north * ground,
                np.broadcast_to(self.targets[:, 2:3], ground.shape),
            ],
            axis=-1,
        )
        sensors = np.broadcast_to(self.sensors[:, None, :], (len(self.sensors), slant.shape[-1], 3))
        return np.ascontiguousarray(sensors), positions

    def probabilities(self, row: int, slant: np.ndarray) -> np.ndarray:
        """(3, n_g, n): the row's ordered probabilities at slant ranges ``(n,)`` or
        ``(n_g, n)``."""
        scene = self.chain.compiled.scene
        sensors, targets = self.along(row, slant)
        headings = np.ascontiguousarray(np.broadcast_to(self.heading[:, None], targets.shape[:-1]))
        found = factors(scene, sensors, targets, headings)
        found = dataclasses.replace(found, in_view=np.ones(found.range.shape, dtype=bool))
        terrain = self.chain.compiled.terrain
        if terrain is not None:  # the map around the target where it stands, at each footprint
            start = np.broadcast_to(self.targets[:, None, :], targets.shape)
            scr = footprint_scr(
                terrain,
                found.range,
                np.ascontiguousarray(start),
                scene.signature.target,
                np.asarray(scene.sensors.ifov),
            )
            found = dataclasses.replace(found, scr=scr)
        p = probabilities(scene, found)
        return np.stack([getattr(p, task)[row] for task in TASKS])


def _max_range(pairs: _Pairs, limit: float) -> float:
    """The first of 1, 2, 4, … km at which every task of every pair is below the floor (a
    range with no place on the line for any target, NaN everywhere, does not count)."""
    r = 1e3
    while r < limit:
        found = [pairs.probabilities(row, np.array([r])) for row in pairs.rows]
        if all(not np.any(p >= _FLOOR) for p in found) and not all(
            np.isnan(p).all() for p in found
        ):
            return r
        r *= 2.0
    return limit


_BELOW = 96  # search ranges below the curves' first range, spaced evenly in log range
_BEYOND = 1.1  # ratio of the search ranges beyond the curves' last one, up to the limit


def _search_ranges(pairs: _Pairs, row: int, grid: np.ndarray, limit: float) -> np.ndarray:
    """(n_g, n) slant ranges [m] on which each target's DRI ranges are bracketed: from just
    above the height between sensor and target (the shortest slant range the line has) up to
    the first range of ``grid``, evenly in log range; ``grid`` itself; and beyond its last
    range up to ``limit`` in steps of 10 %. So a DRI range does not depend on how far the
    curves are drawn."""
    dz = np.abs(pairs.targets[:, 2] - pairs.sensors[row, 2])
    lowest = np.maximum(dz * (1.0 + 1e-9), grid[0] * 1e-6)
    # per target, from its lowest range (or the first grid range, if that is lower) upwards
    fractions = np.linspace(0.0, 1.0, _BELOW, endpoint=False)
    start = np.minimum(lowest, grid[0])[:, None]
    below = start * (grid[0] / start) ** fractions
    steps = max(0, math.ceil(math.log(max(limit, grid[-1]) / grid[-1]) / math.log(_BEYOND)))
    beyond = np.minimum(grid[-1] * _BEYOND ** np.arange(1, steps + 1), max(limit, grid[-1]))
    ranges = np.concatenate(
        [
            below,
            np.broadcast_to(grid, (len(dz), grid.size)),
            np.broadcast_to(beyond, (len(dz), steps)),
        ],
        axis=1,
    )
    return np.ascontiguousarray(ranges)


def _ranges(pairs: _Pairs, row: int, search: np.ndarray, probs: np.ndarray) -> np.ndarray:
    """(3, n_g, n_p) range at which each task reaches each probability: the farthest of a
    target's search ranges (:func:`_search_ranges`) with ``P >= p``, refined by bisection on the
    core against the next one; NaN where never reached, +inf where still reached at the last
    (the search limit)."""
    curve = pairs.probabilities(row, search)  # (3, n_g, n)
    n_g, n = search.shape
    targets = np.arange(n_g)[None, :]
    low = np.full((3, n_g, probs.size), np.nan)
    high = np.full_like(low, np.nan)
    for k, p in enumerate(probs):
        above = curve >= p  # (3, n_g, n)
        last = np.where(above.any(axis=-1), n - 1 - np.argmax(above[..., ::-1], -1), -1)
        reached = last >= 0
        beyond = last == n - 1
        low[..., k] = np.where(
            beyond, np.inf, np.where(reached, search[targets, np.maximum(last, 0)], np.nan)
        )
        high[..., k] = np.where(
            reached & ~beyond, search[targets, np.minimum(last + 1, n - 1)], np.nan
        )
    refine = ~np.isnan(high)
    n_p = probs.size
    for _ in range(_BISECTIONS):
        if not refine.any():
            break
        mid = np.where(refine, np.sqrt(np.where(refine, low * high, 1.0)), search[0, -1])
        # Every (task, probability) bracket of a target as one batch column of the core.
        found = pairs.probabilities(row, mid.transpose(1, 0, 2).reshape(n_g, 3 * n_p))
        p_mid = np.stack([found[t][:, t * n_p : (t + 1) * n_p] for t in range(3)])
        hit = p_mid >= probs
        low = np.where(refine & hit, mid, low)
        high = np.where(refine & ~hit, mid, high)
    return low


def pair_performance(
    chain: Any,
    rows: Sequence[int],
    probabilities: Any = (0.5, 0.8, 0.95),
    max_range: float | None = None,
    limit: float = 200e3,
    beyond_dri: float | None = None,
) -> Any:
    """Range curves and DRI ranges of sensor rows against every target, through the core.

    Each target moves away from the sensor along its start bearing (see the module's notes on
    the field of view, terrain maps and false targets); a DRI range is the farthest of the
    search ranges at which the task reaches the probability, refined by 48 bisections on the
    core against the next one (to well below a millimetre). The search ranges are the curves'
    grid, 96 ranges below it down to the shortest slant range the line has (the height between
    sensor and target), and ranges beyond it up to ``limit`` in steps of 10 %: so a DRI range
    does not depend on how far the curves are drawn. NaN where a task never reaches the
    probability; +inf where it still does at ``limit``.

    Parameters
    ----------
    chain : targetacq.run.model_chain.ModelChain
    rows : sequence of int
        Sensor rows of the compiled scene.
    probabilities : sequence of float
        In (0, 1), for the DRI table.
    max_range : float, optional
        The grid's last slant range [m]; default the first of 1, 2, 4, … km where every
        task of every pair is below 0.02 (at most ``limit``).
    limit : float
        The farthest range [m] searched for a DRI range, and of the automatic grid.
    beyond_dri : float, optional
        Draw the curves out to this many times the farthest DRI range found (at most
        ``limit``; e.g. 1.25, a quarter beyond it) instead of ``max_range``: the DRI ranges are
        searched once, on the automatic grid, and only the curves are evaluated again. Ignored
        where no DRI range is finite and > 0.

    Returns
    -------
    targetacq.core.cases.RangePerformance
        Cases labelled ``"sensor → target"``, with no :class:`RangeCase` behind them.

    Examples
    --------
    >>> from targetacq.run.model_chain import ModelChain
    >>> from targetacq.scenario.schema import load_scenario
    >>> chain = ModelChain(load_scenario("examples/two_sensors_fused.toml"))
    >>> dri = pair_performance(chain, [1], [0.5]).dri  # row 1: the thermal sensor
    >>> row = dri[(dri["case"] == "thermal → soldier") & (dri["task"] == "detection")]
    >>> bool(row["reached"].iloc[0]), bool(row["range_m"].iloc[0] > 1e3)
    (True, True)
    """
    import pandas as pd
    import xarray as xr

    probs = np.asarray(probabilities, dtype=float).reshape(-1)
    if not np.all((probs > 0) & (probs < 1)):
        raise ValueError(f"probabilities must be in (0, 1); got {probs.tolist()}")
    pairs = _Pairs(chain, rows)
    r_max = _max_range(pairs, limit) if max_range is None else float(max_range)
    if not (r_max > 0 and math.isfinite(r_max)):
        raise ValueError(f"max_range must be a finite range > 0 m; got {max_range!r}")
    grid = r_max * np.arange(1, 601) / 600.0
    scene = chain.compiled.scene
    found = {
        row: _ranges(pairs, row, _search_ranges(pairs, row, grid, limit), probs)
        for row in pairs.rows
    }
    if beyond_dri is not None:
        finite = [r for reached in found.values() for r in reached.ravel() if 0 < r < math.inf]
        if finite:
            grid = min(beyond_dri * max(finite), limit) * np.arange(1, 601) / 600.0
    curves, labels, dri = [], [], []
    for row in pairs.rows:
        curve = pairs.probabilities(row, grid)  # (3, n_g, n_r)
        reached = found[row]
        for g, target in enumerate(scene.targets.names):
            label = f"{scene.sensors.names[row]} → {target}"
            labels.append(label)
            curves.append(
                xr.Dataset(
                    {task: ("range", curve[t, g]) for t, task in enumerate(TASKS)},
                    coords={"range": grid},
                )
            )
            for t, task in enumerate(TASKS):
                for k, p in enumerate(probs):
                    r = float(reached[t, g, k])
                    dri.append(
                        {
                            "case": label,
                            "task": task,
                            "probability": float(p),
                            "range_m": r,
                            "reached": not math.isnan(r),
                        }
                    )
    dataset = xr.concat(curves, dim=pd.Index(labels, name="case"))
    dataset["range"].attrs["units"] = "m"
    return RangePerformance(curves=dataset, dri=pd.DataFrame(dri), cases={})
