"""The TTP rows of the array core: their cycles on target from the TTP metric.

Under ``[model] resolution_model = "ttp"`` a thermal sensor resolves its target by the Targeting
Task Performance metric (:mod:`targetacq.physics.ttp`): its cycles on target are the metric's
``V = sqrt(A) / R · Φ(R, ΔT, τ)`` (:func:`targetacq.physics.ttp.ttp_cycles`) instead of the
geometric ``d / (R · cycle)``, with the pair's slant range ``R`` and path transmittance ``τ``
(segments, local clouds, a named atmosphere and foliage included) as
:func:`targetacq.core.evaluation.factors` computed them, ``A`` the area of the target's outline
as seen (its horizontal side times the visible part of its height, the area the sensor's own
noise sees) and ``ΔT`` the pair's exitance contrast over the slope ``∂M_bb,band/∂T`` at the
sensor's reference temperature (as :mod:`targetacq.core.mrtd_rows` has it). The row's
:class:`targetacq.physics.ttp.TtpSystem` (compiled from the sensor, :class:`TtpArrays
<targetacq.core.records.TtpArrays>`) holds the optics, the NETD, the jitter, the smear, the
frame rate, the display and the path's Cn².

The TTP metric already holds the sensor's noise (its contrast threshold is raised by the NETD)
and the path's transmittance (on the contrast): the resolution model's ``includes_noise``
(:data:`targetacq.core.cases.RESOLUTION_MODELS`). These rows then get no separate SNR: their SNR
is +inf, so the noise model leaves their probabilities as the TTPF gives them.

Array-API code over static rows and systems, so it runs under ``jax.jit`` (the systems' numbers
are constants of the trace). It evaluates the TTP integral on a grid of frequencies per pair
(:data:`targetacq.physics.ttp.DEFAULT_SAMPLES`), so a TTP row costs some hundred times a
geometric one: the NumPy core's block paths and the numba engine leave TTP scenes to the whole-array
path (:func:`targetacq.core.evaluation.factors`).
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.core.cases import RESOLUTION_MODELS
from targetacq.core.records import SceneArrays
from targetacq.physics import geometry
from targetacq.physics.ttp import ttp_cycles

__all__ = ["HOLDS_NOISE", "outline_area", "ttp_factors"]


def ttp_factors(
    scene: SceneArrays,
    found: Any,
    sensor_positions: Array,
    target_positions: Array,
    headings: Array = None,
    visible: Array = None,
) -> Any:
    """The factors with the cycles of the TTP rows from the TTP metric.

    Parameters
    ----------
    scene : SceneArrays
        With :attr:`SensorArrays.ttp <targetacq.core.records.SensorArrays.ttp>`.
    found : targetacq.core.Factors
        Every row computed as a geometric imager, ``(n_s, n_g, *batch)``.
    sensor_positions, target_positions : array
        ``(n_s, *batch, 3)``, ``(n_g, *batch, 3)`` [m]: the positions ``found`` was computed
        at (for the outline's area).
    headings : array ``(n_g, *batch)``, optional
        [rad]; default the targets' own.
    visible : array, optional
        The visible fraction of each target's height, as :func:`targetacq.core.evaluation.factors`
        checked it; default the targets' own.

    Returns
    -------
    targetacq.core.Factors
        A copy of ``found`` with new cycles at the TTP rows (their SNR is cleared by the core
        where :data:`HOLDS_NOISE`).

    Examples
    --------
    :func:`targetacq.core.evaluation.factors` calls it for a scene with TTP rows:

    >>> import numpy as np
    >>> from targetacq.core import compile_scenario, factors
    >>> from targetacq.scenario.schema import Scenario
    >>> scenario = Scenario.model_validate({
    ...     "sensors": [{"name": "ir", "band": "lwir", "ifov": 1.7e-4, "aperture": 0.1,
    ...                  "netd": 0.05, "position": [0, 0, 2]}],
    ...     "targets": [{"name": "truck", "dimensions": [7, 2.5, 3], "temperature": 297.0,
    ...                  "position": [1000, 0, 0]}],
    ...     "background": {"temperature": 295.0},
    ...     "model": {"resolution_model": "ttp"}})
    >>> scene = compile_scenario(scenario).scene
    >>> found = factors(scene, np.array([[[0.0, 0.0, 2.0]]]), np.array([[[1000.0, 0.0, 0.0]]]))
    >>> bool(found.cycles[0, 0, 0] > 20.0), float(found.snr[0, 0, 0])  # V, not d/(R·cycle)
    (True, inf)
    """
    limited = scene.sensors.ttp
    if limited is None:
        return found
    xp, (rng, tau, cycles) = _arrays.arrays(found.range, found.transmittance, found.cycles)
    _, (s_pos, t_pos) = _arrays.arrays(sensor_positions, target_positions)
    shape = tuple(rng.shape)
    area = xp.broadcast_to(outline_area(scene, s_pos, t_pos, headings, visible), shape)
    tau = xp.broadcast_to(tau, shape)
    contrast = _arrays.as_float(scene.signature.contrast, xp)
    slope = _arrays.as_float(limited.exitance_slope, xp)
    parts = {}
    with np.errstate(divide="ignore", invalid="ignore"):
        for k, (row, system) in enumerate(zip(limited.rows, limited.systems, strict=True)):
            delta_t = xp.reshape(contrast[row] / slope[k], (-1,) + (1,) * (len(shape) - 2))
            parts[row] = ttp_cycles(
                xp.maximum(rng[row], 1e-9), xp.sqrt(area[row]), delta_t, tau[row], system
            )
    whole = xp.broadcast_to(cycles, shape)
    new_cycles = xp.stack(
        [_arrays.as_float(parts[r], xp) if r in parts else whole[r] for r in range(shape[0])],
        axis=0,
    )
    return dataclasses.replace(found, cycles=new_cycles)


HOLDS_NOISE = RESOLUTION_MODELS["ttp"].includes_noise
"""Whether the TTP rows' SNR is +inf (their threshold holds the NETD and τ already): the core
then clears it with the same step as the MRTD rows'."""


def outline_area(
    scene: SceneArrays,
    sensor_positions: Array,
    target_positions: Array,
    headings: Array = None,
    visible: Array = None,
) -> Any:
    """The area of each pair's outline as seen [m²], ``(n_s, n_g, *batch)``: the outline's
    horizontal side times the visible part of its height
    (:func:`targetacq.physics.geometry.box_outline`, as the core's factors have it): the TTP
    metric's target area ``A``.

    Parameters
    ----------
    scene : SceneArrays
    sensor_positions, target_positions : array
        ``(n_s, *batch, 3)``, ``(n_g, *batch, 3)`` [m].
    headings : array ``(n_g, *batch)``, optional
        [rad]; default the targets' own.
    visible : array, optional
        Visible fraction of each target's height, broadcasting with the pairs; default the
        targets' own.

    Returns
    -------
    array
        [m²].

    Examples
    --------
    >>> import numpy as np
    >>> from targetacq.core import compile_scenario
    >>> from targetacq.scenario.schema import Scenario
    >>> scene = compile_scenario(Scenario.model_validate({
    ...     "sensors": [{"name": "ir", "band": "lwir", "ifov": 1e-4, "position": [0, 0, 2]}],
    ...     "targets": [{"name": "truck", "dimensions": [7, 2.5, 3], "temperature": 297.0,
    ...                  "position": [1000, 0, 2]}],
    ...     "background": {"temperature": 295.0}})).scene
    >>> area = outline_area(scene, np.array([[[0.0, 0.0, 2.0]]]), np.array([[[1000.0, 0, 2]]]))
    >>> round(float(area[0, 0, 0]), 9)  # broadside at eye level: length × height
    21.0
    """
    xp, (s_pos, t_pos) = _arrays.arrays(sensor_positions, target_positions)
    targets = scene.targets
    batch = s_pos.ndim - 2
    per_target = (1, -1) + (1,) * batch
    x, y, z = (t_pos[None, ..., k] - s_pos[:, None, ..., k] for k in range(3))
    heading = (
        xp.reshape(_arrays.as_float(targets.heading, xp), per_target)
        if headings is None
        else _arrays.as_float(headings, xp)[None]
    )
    dims = _arrays.as_float(targets.dimensions, xp)
    _, horizontal, vertical = geometry.box_outline(
        x,
        y,
        z,
        heading,
        xp.reshape(dims[:, 0], per_target),
        xp.reshape(dims[:, 1], per_target),
        xp.reshape(dims[:, 2], per_target),
    )
    if visible is None:
        visible = xp.reshape(_arrays.as_float(targets.visible_fraction, xp), per_target)
    return horizontal * vertical * visible
