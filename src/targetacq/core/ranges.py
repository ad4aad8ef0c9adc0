"""Ranges at which tasks reach a probability (DRI ranges), with atmosphere and clutter.

Without atmosphere, ``P`` depends on range only through the cycles on target
``N = d / (R · cycle)`` (Sonesson 2004 §3.5, Fig. 3.3), so the range for a probability has the
closed form ``R = d / (N_p · cycle)``, with ``N_p`` the transform's inverse at ``p``.

With an atmosphere, the transmittance ``τ = exp(−γR)`` lowers the SNR (7.7) as the range grows
and the noise model (:mod:`targetacq.acquisition.path_noise`) lowers ``P`` further, so ``P(R)`` is
no longer a function of N alone. It is still non-increasing in R, and never above its noise-free
value, so the range lies between 0 and the closed-form one; it is found by bisection in ``log R``,
all cases at once. Tolerance: the returned range ``R`` satisfies ``P(R) >= p`` and ``P(R · (1 +
tolerance)) < p`` (or R is the closed-form range itself). Where ``P`` jumps across ``p`` (a
Schmieder–Weathersby clutter-region boundary crossed as the noise grows with range), the range is
that of the jump.

Ordering: nothing is recognised that was not detected (the nested reading of Eq. (2.5), see the
user guide), so the recognition range is at most the detection range, and identification at
most recognition (as the capped probabilities of :func:`targetacq.acquisition_probabilities`).
Where a probability is never reached the range is NaN; where no resolution is needed (a moving
target's detection) it is +inf.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from difflib import get_close_matches
from typing import Any

from targetacq.acquisition import transforms as _transforms
from targetacq.acquisition.criteria import Criterion, get_criterion
from targetacq.acquisition.probabilities import get_motion_rule, given_clutter
from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.core.cases import (
    RangeCase,
    RangePerformance,
    case_acquisition,
    case_probability,
)
from targetacq.physics import optics
from targetacq.physics.ttp import ttp_value_bound

__all__ = [
    "CASE_KEYS",
    "RangeCase",
    "RangePerformance",
    "as_range_case",
    "case_probabilities",
    "case_ranges",
    "dri_ranges",
    "range_performance",
]

_BRACKET = 1e-12  # lower end of the search, relative to the noise-free range


def dri_ranges(
    case: RangeCase | Mapping[str, Any],
    probability: Array = 0.5,
    *,
    tolerance: float = 1e-9,
) -> dict[str, Any]:
    """Range at which each task reaches a probability, for a sensor, a target and a path.

    :func:`case_ranges` of the case: the sensor, target, path and model choices are the
    fields of a :class:`RangeCase` (critical dimension [m], IFOV [rad], optics limits, criterion,
    transform and its options, extinction [Np/m], foliage, clutter, noise model, the sensor's
    noise, MRTD curve, motion rule and semantics; see its attributes).

    Parameters
    ----------
    case : RangeCase or mapping
        The case, or a mapping with the keys of :data:`CASE_KEYS` (the fields of
        :class:`RangeCase`; ``critical_dimension`` and ``ifov`` required; an unknown key raises
        ``ValueError`` naming the closest valid one).
    probability : array_like
        In (0, 1); broadcasts with the case's arrays.
    tolerance : float
        Relative tolerance on the range when it is solved numerically (module docstring), in
        (0, 0.01).

    Returns
    -------
    dict
        Task → range [m] for every task of the criterion that the transform covers, in the
        criterion's order. For a pixel-density criterion (``en62676-4``) the range of each level
        is where the pixel density on the target falls to its threshold,
        ``R = 1 / (density · IFOV)``: thresholds, to which probability, transform, clutter,
        atmosphere and optics limits do not apply.

    Examples
    --------
    >>> r = dri_ranges(RangeCase(2.3, 2e-4))  # R = d / (N50 · 2 IFOV) at P = 0.5
    >>> round(float(r["detection"]), 6), round(float(r["identification"]), 6)
    (5750.0, 898.4375)
    >>> r = dri_ranges({"critical_dimension": 2.3, "ifov": 2e-4, "extinction": 0.4e-3}, 0.8)
    >>> bool(r["detection"] < 5750.0)  # a higher probability, and the haze's noise
    True
    """
    return case_ranges(as_range_case("case", case), probability, tolerance)


_DRI_TASKS = ("detection", "recognition", "identification")


def case_ranges(
    case: RangeCase, probability: Array = 0.5, tolerance: float = 1e-9
) -> dict[str, Any]:
    """Range at which each task of a case reaches a probability (the DRI ranges of a case).

    Without attenuation the closed form ``R = d / (N_p · cycle)`` (§3.5, Fig. 3.3), with
    ``N_p`` the inverse transform (Table 3.5 for detection in clutter); with it, the bisection
    of the module docstring on ``P(R)`` of :func:`targetacq.core.cases.case_probability`, the
    case's own curves. Then each range is capped by the one it presupposes.

    Parameters
    ----------
    case : RangeCase
    probability : array_like
        In (0, 1); broadcasts with the case's arrays.
    tolerance : float
        Relative tolerance on a range solved numerically, in (0, 0.01).

    Returns
    -------
    dict
        Task → range [m], as :func:`dri_ranges` describes.

    Examples
    --------
    >>> r = case_ranges(RangeCase(2.3, 2e-4, extinction=0.4e-3), 0.5)
    >>> bool(r["detection"] < 5750.0)  # the haze's noise shortens the closed-form 5,750 m
    True
    """
    if not 0 < tolerance < 1e-2:
        raise ValueError(f"tolerance must be in (0, 0.01), got {tolerance!r}")
    crit = get_criterion(case.criterion)
    if not crit.gives_probabilities:
        return {
            task: optics.range_for_pixel_density(crit.threshold(task), case.ifov)
            for task in crit.tasks
        }
    chosen = _transforms.get_transform(case.transform)
    tasks = [t for t in crit.tasks if chosen.tasks is None or t in chosen.tasks]
    conditional = case.semantics == "conditional" and set(_DRI_TASKS) <= set(tasks)
    ranges: dict[str, Any] = {}
    for task in tasks:
        r_free = _noise_free_range(case, crit, chosen, task, probability)
        if conditional and task in _DRI_TASKS and task != "detection":
            # P(recognised) = P_det · P_rec <= P_rec: the curve's range bounds it.
            r_free = _solve(
                lambda rr, task=task: getattr(case_acquisition(case, rr), task),
                probability,
                r_free,
                tolerance,
            )
        elif (
            case.noisy
            or case.mrtd is not None
            or case.ttp is not None
            or (task == "detection" and case.graded)
        ):
            if case.graded and task == "detection":
                r_free = _graded_bracket(case, crit, chosen, probability)
            r_free = _solve(
                lambda rr, task=task: case_probability(case, rr, task),
                probability,
                r_free,
                tolerance,
            )
        ranges[task] = r_free
    _order(ranges)
    return {task: _arrays.result(r) for task, r in ranges.items()}


def _cycles_needed(
    case: RangeCase, crit: Criterion, chosen: Any, task: str, probability: Any
) -> Any:
    """Cycles for a probability without noise (+inf: never reached), as the model reads the
    curves (:func:`targetacq.acquisition.probabilities.ordered_probabilities`): detection in clutter
    is the lesser of the transform's curve and Table 3.5's, so it needs the more cycles of the two;
    a hot spot reads the low-clutter curve, a moving target its motion rule, either the better."""
    n50 = crit.n50(task)
    if chosen.tasks == ("detection",):  # a detection-in-clutter transform chosen by name
        given = given_clutter(case.clutter)
        return chosen.inverse(probability, n50, task, **given, **case.options)
    needed = _transforms.inverse_transform(
        probability, n50, task, method=chosen.name, **case.options
    )
    if task != "detection" or not case.in_clutter:
        return needed
    xp, (needed,) = _arrays.arrays(needed)
    if case.scr is not None or case.region is not None:
        sw = _transforms.schmieder_weathersby_inverse(
            probability, n50, scr=case.scr, region=case.region
        )
        needed = xp.maximum(needed, _arrays.as_float(sw, xp))
    special = None
    if case.hot_spot:
        special = _arrays.as_float(
            _transforms.schmieder_weathersby_inverse(probability, n50, hot_spot=True), xp
        )
    if case.moving:
        go = _arrays.as_float(
            get_motion_rule(case.motion).cycles_needed(probability, n50, chosen, case.options), xp
        )
        special = go if special is None else xp.minimum(special, go)
    return needed if special is None else special


def _graded_bracket(case: RangeCase, crit: Criterion, chosen: Any, probability: Any) -> Any:
    """An upper bound of a graded case's detection range: the farther of the ranges with the
    cues switched fully on and off (a weight blends the two curves), a finite far range (N of
    1e-9 cycles) where the switched cue is never lost (motion ``always``)."""
    full = dataclasses.replace(
        case,
        hot_spot=case.hot_spot or case.hot_spot_ratio is not None,
        moving=case.moving or case.target_speed is not None,
        hot_spot_ratio=None,
        hot_spot_size=None,
        target_speed=None,
    )
    plain = dataclasses.replace(case, hot_spot_ratio=None, hot_spot_size=None, target_speed=None)
    xp, (on, off, d, cycle) = _arrays.arrays(
        _noise_free_range(full, crit, chosen, "detection", probability),
        _noise_free_range(plain, crit, chosen, "detection", probability),
        case.critical_dimension,
        case.cycle_angle,
    )
    on = xp.where(xp.isinf(on), d / (cycle * 1e-9), on)
    return xp.where(xp.isnan(on), off, xp.where(xp.isnan(off), on, xp.maximum(on, off)))


def _noise_free_range(
    case: RangeCase, crit: Criterion, chosen: Any, task: str, probability: Any
) -> Any:
    """The closed-form range of a task without noise (NaN: never reached); with an MRTD curve,
    an upper bound for the bisection."""
    needed = _cycles_needed(case, crit, chosen, task, probability)
    xp, (n,) = _arrays.arrays(needed)
    never = xp.isinf(n)
    if case.mrtd is not None:
        # N(R) <= f_cutoff · d / R: the range at the MRTD's cut-off frequency bounds it.
        xp, (d, cut, safe_n) = _arrays.arrays(
            case.critical_dimension, case.mrtd.cutoff, xp.where(never | (n == 0), 1.0, n)
        )
        r = d * cut / safe_n
    elif case.ttp is not None:
        # V(R) <= d · Φ_bound / R (physics.ttp.ttp_value_bound) bounds it likewise.
        xp, (d, bound, safe_n) = _arrays.arrays(
            case.characteristic_dimension,
            ttp_value_bound(case.ttp),
            xp.where(never | (n == 0), 1.0, n),
        )
        r = d * bound / safe_n
    else:
        r = optics.range_for_cycles(
            case.critical_dimension, xp.where(never, 1.0, n), **case.resolution()
        )
    xp, (r,) = _arrays.arrays(r)
    r = xp.where(never, xp.nan, r)
    return xp.where(n == 0, xp.inf, r)


def _solve(prob: Any, p: Any, r_free: Any, tolerance: float) -> Any:
    """Largest R in (0, r_free] with prob(R) >= p, by bisection in log R (module docstring)."""
    xp, (p_, hi) = _arrays.arrays(p, r_free)
    hi = hi + 0.0 * p_
    finite = xp.isfinite(hi) & (hi > 0)
    hi = xp.where(finite, hi, 1.0)
    lo = hi * _BRACKET
    at_hi = prob(hi) >= p_
    reachable = prob(lo) >= p_
    for _ in range(200):
        if not bool(xp.any(hi > lo * (1.0 + tolerance))):
            break
        mid = xp.sqrt(lo * hi)
        ok = prob(mid) >= p_
        lo = xp.where(ok, mid, lo)
        hi = xp.where(ok, hi, mid)
    _, (r_free_,) = _arrays.arrays(r_free)
    found = xp.where(at_hi, hi, xp.where(reachable, lo, xp.nan))
    # inf (no resolution needed) and NaN (never reached) come through from the noise-free range.
    return xp.where(finite, found, r_free_ + 0.0 * p_)


def _order(ranges: dict[str, Any]) -> None:
    """Cap each task's range by the one it presupposes (detection ← orientation, recognition;
    recognition ← identification). NaN (never reached) propagates."""
    presupposes = {
        "orientation": "detection",
        "recognition": "detection",
        "identification": "recognition",
    }
    for task, before in presupposes.items():
        if task in ranges and before in ranges:
            xp, (r, b) = _arrays.arrays(ranges[task], ranges[before])
            capped = xp.minimum(r, b)
            ranges[task] = xp.where(xp.isnan(b) | xp.isnan(r), xp.nan + 0.0 * capped, capped)


# --- range-performance curves ---------------------------------------------------------------

CASE_KEYS: tuple[str, ...] = tuple(f.name for f in dataclasses.fields(RangeCase))
"""Keys of a case of :func:`range_performance` given as a mapping: the fields of
:class:`RangeCase` (``options``: the transform's options)."""


def as_range_case(label: str, case: RangeCase | Mapping[str, Any]) -> RangeCase:
    """A case of :func:`range_performance` as a :class:`RangeCase`.

    Mappings (the cases of earlier releases) take the keys of :data:`CASE_KEYS`; an unknown key
    raises ``ValueError`` with the closest valid one.

    Parameters
    ----------
    label : str
        The case's label, for the messages.
    case : RangeCase or mapping

    Returns
    -------
    RangeCase

    Examples
    --------
    >>> as_range_case("clear", {"critical_dimension": 2.3, "ifov": 2e-4}).transform
    'ttpf'
    """
    if isinstance(case, RangeCase):
        return case
    unknown = [key for key in case if key not in CASE_KEYS]
    if unknown:
        hints = [
            f"{key!r} (did you mean {close[0]!r}?)"
            if (close := get_close_matches(key, CASE_KEYS, 1))
            else repr(key)
            for key in unknown
        ]
        raise ValueError(
            f"case {label!r}: unknown key(s) {', '.join(hints)}; valid keys: {', '.join(CASE_KEYS)}"
        )
    for key in ("critical_dimension", "ifov"):
        if key not in case:
            raise ValueError(f"case {label!r} needs {key!r}")
    return RangeCase(**case)


def case_probabilities(
    range: Any, case: RangeCase | Mapping[str, Any]
) -> tuple[Any, Any, Any, Any]:
    """Cycles, transmittance, SNR and the ordered probabilities of one case at ranges.

    Kept for one release: use :func:`targetacq.core.cases.case_acquisition`, which this calls.

    Returns
    -------
    cycles, transmittance, snr, acquisition
        The last is a :class:`targetacq.acquisition.probabilities.Acquisition`.

    Examples
    --------
    >>> n, tau, snr, acq = case_probabilities(1150.0, {"critical_dimension": 2.3, "ifov": 2e-4})
    >>> round(float(n), 12), float(tau)
    (5.0, 1.0)
    """
    found = case_acquisition(as_range_case("case", case), range)
    return found.cycles, found.transmittance, found.snr, found


def range_performance(
    range: Array,
    cases: Mapping[str, RangeCase | Mapping[str, Any]],
    probabilities: Any = (0.5, 0.8, 0.95),
    tolerance: float = 1e-9,
) -> RangePerformance:
    """Probabilities of detection, recognition and identification against range, per case.

    The curves are :func:`targetacq.core.cases.case_acquisition` of each case on the grid, the
    DRI table :func:`case_ranges` of each case: the one evaluation of a case, so the table's
    ranges are where the curves cross the probabilities.

    Parameters
    ----------
    range : array_like
        1-D grid of slant ranges [m], > 0.
    cases : mapping
        Label → :class:`RangeCase` (or, for one release, a mapping with the keys of
        :data:`CASE_KEYS`; ``critical_dimension`` [m] and ``ifov`` [rad] required). Several
        sensors, targets or weather cases side by side.
    probabilities : sequence of float
        Probabilities, in (0, 1), for the DRI table.
    tolerance : float
        Relative range tolerance of the DRI solver.

    Returns
    -------
    RangePerformance

    Examples
    --------
    >>> perf = range_performance([500.0, 1000.0], {"clear": RangeCase(2.3, 2e-4)}, [0.5])
    >>> dict(perf.curves.sizes)
    {'case': 1, 'range': 2}
    >>> round(float(perf.dri.set_index("task").loc["detection", "range_m"]), 6)
    5750.0
    """
    import numpy as np
    import pandas as pd
    import xarray as xr

    grid = np.asarray(range, dtype=float)
    if grid.ndim != 1 or grid.size < 2:
        raise ValueError("range must be a 1-D grid of at least 2 ranges [m]")
    if not cases:
        raise ValueError("cases must name at least one case")
    probs = np.asarray(probabilities, dtype=float).reshape(-1)
    _arrays.require_open_unit_interval("probabilities", probs, _arrays.namespace())
    records = {label: as_range_case(label, case) for label, case in cases.items()}
    curves, rows = [], []
    for label, case in records.items():
        found = case_acquisition(case, grid)
        curves.append(
            xr.Dataset(
                {
                    name: ("range", np.broadcast_to(getattr(found, name), grid.shape).copy())
                    for name in (*_DRI_TASKS, "cycles", "transmittance", "snr")
                },
                coords={"range": grid},
            )
        )
        reached = case_ranges(case, probs, tolerance)
        for task in _DRI_TASKS:
            if task not in reached:
                continue
            values = np.broadcast_to(reached[task], probs.shape)
            for p, r in zip(probs, values, strict=True):
                rows.append(
                    {
                        "case": label,
                        "task": task,
                        "probability": float(p),
                        "range_m": float(r),
                        "reached": not np.isnan(r),
                    }
                )
    dataset = xr.concat(curves, dim=pd.Index(list(records), name="case"))
    dataset["range"].attrs["units"] = "m"
    dataset["snr"].attrs["units"] = "dB"
    dataset["cycles"].attrs["units"] = "cycles"
    return RangePerformance(curves=dataset, dri=pd.DataFrame(rows), cases=records)
