"""Ranges at which tasks reach a probability (DRI ranges).

Geometry only for now: with no atmosphere, ``P`` depends on range only through the cycles on
target ``N = d / (R · cycle)`` (Sonesson 2004 §3.5, Fig. 3.3), so the range for a probability
has the closed form ``R = d / (N_p · cycle)``, where ``N_p`` is the transform's inverse at ``p``.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from targetacq import _arrays, optics
from targetacq import transforms as _transforms
from targetacq.criteria import Criterion, get_criterion

__all__ = ["dri_ranges"]


def dri_ranges(
    critical_dimension: Any,
    ifov: Any,
    criterion: str | Criterion | Mapping[str, float] = "johnson",
    probability: Any = 0.5,
    transform: str = "ttpf",
    *,
    wavelength: Any = None,
    aperture: Any = None,
    blur_sigma: Any = None,
    **options: Any,
) -> dict[str, Any]:
    """Range at which each task reaches a probability, for a sensor and a target.

    For a cycles criterion: ``R = d / (N_p · cycle)`` with ``N_p`` the cycles the transform needs
    for ``probability`` (its inverse) and ``cycle`` the resolvable cycle angle
    (:func:`targetacq.optics.resolvable_cycle_angle`). Where a transform never reaches the
    probability (Schmieder–Weathersby high clutter above 0.9) the range is NaN; where it needs
    no resolution at all (a moving target's detection) the range is +inf.

    For a pixel-density criterion (``en62676-4``) the range of each level is where the pixel
    density on the target falls to its threshold, ``R = 1 / (density · IFOV)``; these are
    thresholds, so ``probability`` and ``transform`` do not apply to them (the optics limits do
    not either: the standard counts pixels).

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
        A name from :data:`targetacq.transforms.TRANSFORMS`.
    wavelength, aperture, blur_sigma : array_like, optional
        Optics limits on the cycle, see :func:`targetacq.optics.resolvable_cycle_angle`.
    **options
        Options of the transform (e.g. ``bound=``, ``scr=``).

    Returns
    -------
    dict
        Task → range [m], for every task of the criterion that the transform covers, in the
        criterion's order.
    """
    crit = get_criterion(criterion)
    if not crit.gives_probabilities:
        if options:
            raise ValueError(
                f"criterion {crit.name!r} gives pixel-density thresholds; transform options "
                f"{', '.join(options)} do not apply"
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
    ranges = {}
    for task in tasks:
        needed = _transforms.inverse_transform(
            probability, crit.n50(task), task, method=chosen.name, **options
        )
        xp, (n,) = _arrays.arrays(needed)
        never = xp.isinf(n)
        reached = xp.where(never, 1.0, n)
        r = optics.range_for_cycles(
            critical_dimension,
            reached,
            ifov,
            wavelength=wavelength,
            aperture=aperture,
            blur_sigma=blur_sigma,
        )
        xp, (r,) = _arrays.arrays(r)
        ranges[task] = _arrays.result(xp.where(never, xp.nan, r))
    return ranges
