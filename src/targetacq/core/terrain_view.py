"""The pairs an elevation model hides: each pair's visible fraction over the terrain, for every
front end (the step API, the batch runs, the environments).

A target is hidden from the bottom up both by the terrain (:func:`targetacq.line_of_sight`,
each target's base at its position's altitude, its height the third of its dimensions) and by the
occlusion its own ``visible_fraction`` says: a pair sees the smaller of the two,
``f = min(f_own, f_terrain)`` (NaN stays NaN). A pair with ``f = 0`` is out of that sensor's
view (probability 0); the core is given 1 for it in place of 0, which it refuses
(:func:`targetacq.core.evaluation.check_visible_fraction`), and :func:`hide` then takes it out
of view.
"""

from __future__ import annotations

import dataclasses
from typing import Any, NamedTuple

import numpy as np

from targetacq.base.arrays import Array
from targetacq.core.evaluation import Factors, check_visible_fraction
from targetacq.physics.line_of_sight import ElevationModel, line_of_sight

__all__ = ["TerrainView", "hide", "terrain_view"]


class TerrainView(NamedTuple):
    """Each pair's visible fraction for the core and the pairs the terrain hides.

    Attributes
    ----------
    visible_fraction : numpy.ndarray (n_s, n_g, *batch)
        ``min(f_own, f_terrain)`` in (0, 1], 1 where the pair is hidden; NaN where unknown (off
        the grid, a void on the way, a NaN input).
    hidden : numpy.ndarray of bool (n_s, n_g, *batch)
        Pairs whose fraction is 0: out of view.
    """

    visible_fraction: np.ndarray
    hidden: np.ndarray


def terrain_view(
    elevation: ElevationModel,
    earth_radius_factor: float,
    sensor_positions: Array,
    target_positions: Array,
    target_heights: Array,
    visible_fraction: Array,
) -> TerrainView:
    """Every sensor–target pair's visible fraction over the terrain, in one kernel call.

    ``f = min(f_own, f_terrain)``, ``f_terrain`` of :func:`targetacq.line_of_sight` (the Earth
    bulge ``d_o d_t / (2 k R_e)``, ITU-R P.452); hidden where ``f = 0``.

    Parameters
    ----------
    elevation : ElevationModel
        The terrain (altitudes [m] on the positions' datum).
    earth_radius_factor : float
        ``k`` [1], > 0 (``inf``: a flat Earth).
    sensor_positions : array (n_s, *batch, 3)
        East, north, altitude of the sensors [m].
    target_positions : array (n_g, *batch, 3)
        East, north and the altitude of each target's base [m].
    target_heights : array (n_g,) or (n_g, *batch)
        Each target's height [m], > 0.
    visible_fraction : array_like
        The targets' own visible fraction in (0, 1] [1], in any shape the core takes
        (:func:`targetacq.core.evaluation.check_visible_fraction`: ``(n_g,)``, ``(n_s, n_g)``,
        ``(n_s, n_g, *batch)``, ...).

    Returns
    -------
    TerrainView
        The fraction to give the core and the hidden pairs, both ``(n_s, n_g, *batch)``.

    Examples
    --------
    A 20 m wall at 1 km between a sensor 10 m up and two 4 m targets, at 800 m and 1500 m:

    >>> from targetacq.physics.line_of_sight import ElevationModel
    >>> ground = np.zeros((3, 301)); ground[:, 100] = 20.0
    >>> model = ElevationModel(ground, 10.0, (0.0, -10.0))
    >>> view = terrain_view(model, float("inf"), [[0.0, 0.0, 10.0]],
    ...                     [[800.0, 0.0, 0.0], [1500.0, 0.0, 0.0]], [4.0, 4.0], [0.5, 1.0])
    >>> view.visible_fraction.tolist(), view.hidden.tolist()
    ([[0.5, 1.0]], [[False, True]])
    """
    s_pos = np.asarray(sensor_positions, dtype=float)
    t_pos = np.asarray(target_positions, dtype=float)
    heights = np.asarray(target_heights, dtype=float)
    batch = s_pos.ndim - 2
    shape = (
        s_pos.shape[0],
        t_pos.shape[0],
        *np.broadcast_shapes(s_pos.shape[1:-1], t_pos.shape[1:-1]),
    )
    seen = line_of_sight(
        elevation,
        None,
        None,
        s_pos[:, None],
        t_pos[None, :],
        heights.reshape((1, *heights.shape) + (1,) * (batch + 1 - heights.ndim)),
        k=earth_radius_factor,
    )
    own = check_visible_fraction(np.asarray(visible_fraction, dtype=float), shape, np)
    fraction = np.minimum(own, seen)  # NaN stays NaN
    hidden = fraction == 0.0
    return TerrainView(np.where(hidden, 1.0, fraction), hidden)


def hide(found: Factors, hidden: Any) -> Factors:
    """The factors with the pairs ``hidden`` (:func:`terrain_view`) out of view.

    Examples
    --------
    >>> found = Factors(*([np.ones((1, 2))] * 3), np.array([[True, True]]), *([None] * 4))
    >>> hide(found, np.array([[False, True]])).in_view.tolist()
    [[True, False]]
    """
    in_view = np.asarray(found.in_view, dtype=bool) & ~np.asarray(hidden, dtype=bool)
    return dataclasses.replace(found, in_view=in_view)
