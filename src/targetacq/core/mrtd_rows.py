"""The MRTD-limited rows of the array core: their cycles on target from the sensors' curves.

A thermal sensor with an MRTD curve (:attr:`targetacq.core.records.SensorArrays.mrtd`) resolves
its target to the bar frequency ``f*`` at which the target's apparent temperature difference
``τ · ΔT`` equals the curve (:mod:`targetacq.physics.mrtd`), so its cycles on target are
``N = f*(τ · |ΔT|) · d / R`` (:func:`targetacq.physics.mrtd.mrtd_cycles`) instead of the geometric
``d / (R · cycle)``, with the pair's slant range ``R``, critical dimension ``d`` and path
transmittance ``τ`` (segments and local clouds included) as
:func:`targetacq.core.evaluation.factors` computed them, and ``ΔT`` the pair's exitance contrast
over the slope ``∂M_bb,band/∂T`` at the sensor's reference temperature: the blackbody
temperature difference that gives the same contrast in the band (the range-case chain's
``contrast`` of :class:`targetacq.core.cases.RangeCase`; the CLI's ``--mrtd`` makes it the
same way from the temperatures). :func:`targetacq.core.evaluation.factors` computes every row as
a geometric imager and then :func:`mrtd_factors` replaces the cycles of these rows; the rest
(noise, transforms, field of view) is the same for every imager.

Array-API code over static rows and curves, so it runs under ``jax.jit`` (the curves' tables
are constants of the trace).
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from targetacq.base import arrays as _arrays
from targetacq.core.records import SceneArrays
from targetacq.physics.mrtd import mrtd_cycles

__all__ = ["mrtd_factors"]


def mrtd_factors(scene: SceneArrays, found: Any) -> Any:
    """The factors with the cycles of the MRTD-limited rows from their curves.

    Parameters
    ----------
    scene : SceneArrays
        With :attr:`SensorArrays.mrtd <targetacq.core.records.SensorArrays.mrtd>`.
    found : targetacq.core.Factors
        Every row computed as a geometric imager, ``(n_s, n_g, *batch)``.

    Returns
    -------
    targetacq.core.Factors
        ``found`` itself with its NumPy cycles written over at the rows (what
        :func:`targetacq.core.evaluation.factors` keeps beside them is kept), or a copy with new
        cycles in other array namespaces.

    Examples
    --------
    :func:`targetacq.core.evaluation.factors` calls it for a scene with MRTD-limited rows:

    >>> from importlib import resources
    >>> import numpy as np
    >>> from targetacq.core import compile_scenario, factors
    >>> from targetacq.scenario.schema import Scenario
    >>> curve = str(resources.files("targetacq") / "data" / "example_mrtd.csv")
    >>> scenario = Scenario.model_validate({
    ...     "sensors": [{"name": "ir", "band": "lwir", "ifov": 3.4e-4, "position": [0, 0, 2],
    ...                  "mrtd": curve}],
    ...     "targets": [{"name": "truck", "dimensions": [7, 2.5, 3], "temperature": 295.0,
    ...                  "position": [1000, 0, 2]}],
    ...     "background": {"temperature": 293.0}})
    >>> scene = compile_scenario(scenario).scene
    >>> found = factors(scene, np.array([[[0.0, 0.0, 2.0]]]), np.array([[[1000.0, 0.0, 2.0]]]))
    >>> round(float(found.cycles[0, 0, 0]), 6)  # 2 K, no atmosphere: the cut-off, 1400 × 3 / 1000
    4.2
    """
    limited = scene.sensors.mrtd
    if limited is None:
        return found
    xp, (rng, critical, tau, cycles) = _arrays.arrays(
        found.range, found.critical_dimension, found.transmittance, found.cycles
    )
    ndim = rng.ndim
    contrast = _arrays.as_float(scene.signature.contrast, xp)
    slope = _arrays.as_float(limited.exitance_slope, xp)
    parts = []
    with np.errstate(divide="ignore", invalid="ignore"):
        for k, (row, curve) in enumerate(zip(limited.rows, limited.curves, strict=True)):
            delta_t = xp.reshape(contrast[row] / slope[k], (-1,) + (1,) * (ndim - 2))
            parts.append(
                mrtd_cycles(
                    xp.maximum(rng[row], 1e-9),
                    xp.broadcast_to(critical, rng.shape)[row],
                    delta_t,
                    xp.broadcast_to(tau, rng.shape)[row],
                    curve,
                )
            )
    if isinstance(cycles, np.ndarray) and cycles is found.cycles and cycles.flags.writeable:
        for row, part in zip(limited.rows, parts, strict=True):
            cycles[row] = part
        return found
    index = dict(zip(limited.rows, parts, strict=True))
    whole = xp.broadcast_to(cycles, rng.shape)
    stacked = xp.stack(
        [_arrays.as_float(index[r], xp) if r in index else whole[r] for r in range(rng.shape[0])],
        axis=0,
    )
    return dataclasses.replace(found, cycles=stacked)
