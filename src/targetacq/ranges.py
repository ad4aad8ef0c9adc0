"""Ranges at which tasks reach a probability (DRI ranges), with atmosphere and clutter.

Without atmosphere, ``P`` depends on range only through the cycles on target
``N = d / (R · cycle)`` (Sonesson 2004 §3.5, Fig. 3.3), so the range for a probability has the
closed form ``R = d / (N_p · cycle)``, with ``N_p`` the transform's inverse at ``p``.

With an atmosphere, the transmittance ``τ = exp(−γR)`` lowers the SNR (7.7) as the range grows
and the noise model (:mod:`targetacq.noise`) lowers ``P`` further, so ``P(R)`` is no longer a
function of N alone. It is still non-increasing in R, and never above its noise-free value, so
the range lies between 0 and the closed-form one; it is found by bisection in ``log R``, all
cases at once. Tolerance: the returned range ``R`` satisfies ``P(R) >= p`` and
``P(R · (1 + tolerance)) < p`` (or R is the closed-form range itself). Where ``P`` jumps across
``p`` (a Schmieder–Weathersby clutter-region boundary crossed as the noise grows with range), the
range is that of the jump.

Ordering: nothing is recognised that was not detected (MODEL.md §2), so the recognition range
is at most the detection range, and identification at most recognition (as the capped
probabilities of :func:`targetacq.acquisition_probabilities`). Where a probability is never
reached the range is NaN; where no resolution is needed (a moving target's detection) it is +inf.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from difflib import get_close_matches
from typing import Any

from targetacq import _arrays, atmosphere, optics
from targetacq import transforms as _transforms
from targetacq.acquisition import acquisition_probabilities
from targetacq.acquisition import probability as task_probability
from targetacq.criteria import Criterion, get_criterion

__all__ = ["CASE_KEYS", "RangePerformance", "case_probabilities", "dri_ranges", "range_performance"]

_BRACKET = 1e-12  # lower end of the search, relative to the noise-free range


def dri_ranges(
    critical_dimension: Any,
    ifov: Any,
    criterion: str | Criterion | Mapping[str, float] = "johnson",
    probability: Any = 0.5,
    transform: str = "ttpf",
    *,
    extinction: Any = None,
    scr: Any = None,
    region: str | None = None,
    hot_spot: bool = False,
    moving: bool = False,
    noise_model: Any = "variance-sum",
    wavelength: Any = None,
    aperture: Any = None,
    blur_sigma: Any = None,
    tolerance: float = 1e-9,
    **options: Any,
) -> dict[str, Any]:
    """Range at which each task reaches a probability, for a sensor, a target and a path.

    Parameters
    ----------
    critical_dimension : array_like
        [m], > 0.
    ifov : array_like
        Pixel IFOV [rad], > 0.
    criterion : str, Criterion or mapping
        Criteria set (name, object, or task → N50 mapping).
    probability : array_like
        In (0, 1); broadcasts with the other inputs.
    transform : str
        A name from :data:`targetacq.transforms.TRANSFORMS` ("schmieder-weathersby" gives the
        detection range only).
    extinction : array_like, optional
        γ of the path [Np/m], >= 0; None or 0 for no atmosphere.
    scr, region, hot_spot, moving
        The clutter, acting on detection (§3.8); see
        :func:`targetacq.transforms.schmieder_weathersby`.
    noise_model : str, NoiseModel or callable
        How the atmosphere's noise moves the transforms (:mod:`targetacq.noise`).
    wavelength, aperture, blur_sigma : array_like, optional
        Optics limits on the cycle, see :func:`targetacq.optics.resolvable_cycle_angle`.
    tolerance : float
        Relative tolerance on the range when it is solved numerically (module docstring).
    **options
        Options of the transform (e.g. ``bound=``).

    Returns
    -------
    dict
        Task → range [m] for every task of the criterion that the transform covers, in the
        criterion's order. For a pixel-density criterion (``en62676-4``) the range of each level
        is where the pixel density on the target falls to its threshold,
        ``R = 1 / (density · IFOV)``: thresholds, to which probability, transform, clutter,
        atmosphere and optics limits do not apply.
    """
    if not 0 < tolerance < 1e-2:
        raise ValueError(f"tolerance must be in (0, 0.01), got {tolerance!r}")
    crit = get_criterion(criterion)
    clutter = {"scr": scr, "region": region, "hot_spot": hot_spot, "moving": moving}
    if not crit.gives_probabilities:
        extras = [name for name, v in {**options, **clutter, "extinction": extinction}.items() if v]
        if extras:
            raise ValueError(
                f"criterion {crit.name!r} gives pixel-density thresholds; {', '.join(extras)} "
                "do not apply"
            )
        return {
            task: optics.range_for_pixel_density(crit.threshold(task), ifov) for task in crit.tasks
        }
    chosen = _transforms.get_transform(transform)
    tasks = [t for t in crit.tasks if chosen.tasks is None or t in chosen.tasks]
    if not tasks:
        raise ValueError(
            f"transform {chosen.name!r} covers none of criterion {crit.name!r}'s tasks "
            f"({', '.join(crit.tasks)})"
        )
    optics_kw = {"wavelength": wavelength, "aperture": aperture, "blur_sigma": blur_sigma}
    clutter_given = scr is not None or region is not None or hot_spot or moving

    def noise_free_range(task: str) -> Any:
        if task == "detection" and clutter_given:
            needed = _transforms.schmieder_weathersby_inverse(
                probability, crit.n50(task), **clutter
            )
        else:
            needed = _transforms.inverse_transform(
                probability, crit.n50(task), task, method=chosen.name, **options
            )
        xp, (n,) = _arrays.arrays(needed)
        never = xp.isinf(n)
        r = optics.range_for_cycles(critical_dimension, xp.where(never, 1.0, n), ifov, **optics_kw)
        xp, (r,) = _arrays.arrays(r)
        return xp.where(never, xp.nan, r)

    def probability_at(task: str, r: Any) -> Any:
        n = optics.cycles_on_target(critical_dimension, r, ifov, **optics_kw)
        snr = atmosphere.snr_from_transmittance(atmosphere.transmittance(extinction, r))
        return task_probability(
            n,
            task,
            crit,
            chosen.name,
            snr=snr,
            noise_model=noise_model,
            **(clutter if task == "detection" else {}),
            **options,
        )

    ranges: dict[str, Any] = {}
    for task in tasks:
        r_free = noise_free_range(task)
        if extinction is None:
            r = r_free
        else:
            r = _solve(
                lambda rr, task=task: probability_at(task, rr), probability, r_free, tolerance
            )
        ranges[task] = r
    _order(ranges)
    return {task: _arrays.result(r) for task, r in ranges.items()}


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

CASE_KEYS: tuple[str, ...] = (
    "critical_dimension",
    "ifov",
    "criterion",
    "transform",
    "extinction",
    "scr",
    "region",
    "hot_spot",
    "moving",
    "noise_model",
    "wavelength",
    "aperture",
    "blur_sigma",
    "options",
)
"""Keys of one case of :func:`range_performance` (``options``: the transform's options)."""

_DRI_TASKS = ("detection", "recognition", "identification")


@dataclass(frozen=True)
class RangePerformance:
    """Range-performance curves and DRI ranges for one or several cases.

    Attributes
    ----------
    curves : xarray.Dataset
        Dims ``(case, range)``; variables ``detection``, ``recognition``, ``identification``
        (ordered probabilities), ``cycles`` [cycles], ``transmittance`` and ``snr`` [dB]; the
        ``range`` coordinate in metres.
    dri : pandas.DataFrame
        One row per case, task and probability: ``range_m`` (NaN where never reached) and
        ``reached``.
    cases : Mapping[str, Mapping[str, Any]]
        The inputs of each case, as given.
    """

    curves: Any
    dri: Any
    cases: Mapping[str, Mapping[str, Any]]


def _check_case(label: str, case: Mapping[str, Any]) -> None:
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


def case_probabilities(range: Any, case: Mapping[str, Any]) -> tuple[Any, Any, Any, Any]:
    """Cycles, transmittance, SNR and the ordered probabilities of one case at ranges.

    Returns
    -------
    cycles, transmittance, snr, acquisition
        The last is a :class:`targetacq.acquisition.Acquisition`.
    """
    n = optics.cycles_on_target(
        case["critical_dimension"],
        range,
        case["ifov"],
        wavelength=case.get("wavelength"),
        aperture=case.get("aperture"),
        blur_sigma=case.get("blur_sigma"),
    )
    extinction = case.get("extinction")
    tau = atmosphere.transmittance(0.0 if extinction is None else extinction, range)
    snr = atmosphere.snr_from_transmittance(tau)
    acq = acquisition_probabilities(
        n,
        case.get("criterion", "johnson"),
        case.get("transform", "ttpf"),
        scr=case.get("scr"),
        region=case.get("region"),
        hot_spot=case.get("hot_spot", False),
        moving=case.get("moving", False),
        snr=None if extinction is None else snr,
        noise_model=case.get("noise_model", "variance-sum"),
        **case.get("options", {}),
    )
    return n, tau, snr, acq


def range_performance(
    range: Any,
    cases: Mapping[str, Mapping[str, Any]],
    probabilities: Any = (0.5, 0.8, 0.95),
    tolerance: float = 1e-9,
) -> RangePerformance:
    """Probabilities of detection, recognition and identification against range, per case.

    Parameters
    ----------
    range : array_like
        1-D grid of slant ranges [m], > 0.
    cases : mapping
        Label → case; a case is a mapping with the keys of :data:`CASE_KEYS`
        (``critical_dimension`` [m] and ``ifov`` [rad] required; the rest as in
        :func:`dri_ranges`). Several sensors, targets or weather cases side by side.
    probabilities : sequence of float
        Probabilities, in (0, 1), for the DRI table.
    tolerance : float
        Relative range tolerance of the DRI solver.

    Returns
    -------
    RangePerformance
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
    curves, rows = [], []
    for label, case in cases.items():
        _check_case(label, case)
        n, tau, snr, acq = case_probabilities(grid, case)
        curves.append(
            xr.Dataset(
                {
                    "detection": ("range", np.asarray(acq.detection)),
                    "recognition": ("range", np.asarray(acq.recognition)),
                    "identification": ("range", np.asarray(acq.identification)),
                    "cycles": ("range", np.asarray(n)),
                    "transmittance": ("range", np.broadcast_to(tau, grid.shape).copy()),
                    "snr": ("range", np.broadcast_to(snr, grid.shape).copy()),
                },
                coords={"range": grid},
            )
        )
        found = dri_ranges(
            case["critical_dimension"],
            case["ifov"],
            case.get("criterion", "johnson"),
            probability=probs,
            transform=case.get("transform", "ttpf"),
            extinction=case.get("extinction"),
            scr=case.get("scr"),
            region=case.get("region"),
            hot_spot=case.get("hot_spot", False),
            moving=case.get("moving", False),
            noise_model=case.get("noise_model", "variance-sum"),
            wavelength=case.get("wavelength"),
            aperture=case.get("aperture"),
            blur_sigma=case.get("blur_sigma"),
            tolerance=tolerance,
            **case.get("options", {}),
        )
        for task in _DRI_TASKS:
            if task not in found:
                continue
            values = np.broadcast_to(found[task], probs.shape)
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
    dataset = xr.concat(curves, dim=pd.Index(list(cases), name="case"))
    dataset["range"].attrs["units"] = "m"
    dataset["snr"].attrs["units"] = "dB"
    dataset["cycles"].attrs["units"] = "cycles"
    return RangePerformance(curves=dataset, dri=pd.DataFrame(rows), cases=dict(cases))
