"""The design solver: the sensor resolution a task needs at a range.

The inverse of the range question. :func:`targetacq.core.ranges.case_ranges` answers "how far does
this sensor recognise the target with probability P"; :func:`required_ifov` answers "what pixel
IFOV recognises it with probability P at range R": the largest IFOV at which the task's range,
with everything :func:`~targetacq.core.ranges.case_ranges` includes (criterion and transform,
clutter, the path's extinction and its noise, the sensor's noise, diffraction and blur), is at
least ``R``. :func:`required_focal_length` turns it into the shortest focal length for a pixel
pitch (``f = p / IFOV``, Eq. (5.1)) and :func:`required_pitch` into the largest pitch for a
focal length (``p = f · IFOV``).

Method
------
1. **Purely geometric case** (no optics limit, no noise): one cycle is two pixels (Fig. 3.3),
   so ``N = d / (2 · IFOV · R)`` (§3.5) and the closed form is

   ``IFOV = d / (2 · N_P · R)``,  ``N_P = N50 · x(P)``

   with ``x(P)`` the inverse transform (:func:`targetacq.acquisition.transforms.inverse_transform`;
   the TTPF of Eq. (3.1) by default; Table 3.5 for detection in clutter). Every range of such a case
   scales as ``1 / IFOV``, so the solver reads ``N_P`` as the model does: from
   :func:`~targetacq.core.ranges.case_ranges` at a reference IFOV, ``IFOV = IFOV_ref · R(IFOV_ref) /
   R`` (ordering of the tasks and ``semantics`` included).
2. **Otherwise** bisection on ``log IFOV`` with :func:`~targetacq.core.ranges.case_ranges`: a
   smaller IFOV never shortens a range (more cycles on target, Eqs. (5.2), (5.3); more pixels
   on target for the sensor's SNR; the path's noise does not depend on it), and optics limits
   and noise only shorten it, so the geometric IFOV of step 1 bounds the answer from above.
   The search goes down to ``1e-6`` of it, in a fixed :data:`SOLVER_ITERATIONS` halvings of
   the bracket (relative tolerance below ``1e-12``). Where even the smallest IFOV does not
   reach the range (the weather's noise at that range alone keeps ``P`` below the asked
   probability, or a fixed lens's diffraction is coarser than the cycle needed), the answer
   is NaN; :func:`unreachable_reason` says why.

Source: Sonesson (2004), §3.5 (cycles on target, Fig. 3.3), Eq. (3.1) (TTPF), §5.2 and
Eqs. (5.1)–(5.3) (IFOV, blur, diffraction), Eqs. (7.3)–(7.7) (the path's noise).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import Any

import numpy as np

from targetacq.acquisition.criteria import get_criterion
from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.core.cases import RangeCase, case_acquisition, case_probability
from targetacq.core.ranges import case_ranges
from targetacq.physics.ttp import eye_ctf_minimum

__all__ = [
    "SEARCH_DEPTH",
    "SOLVER_ITERATIONS",
    "required_focal_length",
    "required_ifov",
    "required_pitch",
    "unreachable_reason",
]

SEARCH_DEPTH = 1e-6
"""The smallest IFOV searched, relative to the geometric IFOV (the bracket's lower end)."""

SOLVER_ITERATIONS = 48
"""Halvings of the bracket ``[SEARCH_DEPTH, 1] · IFOV_geometric`` in ``log IFOV``:
``ln(1e6) / 2**48 < 1e-13``, a relative tolerance well below ``1e-9``."""

_REFERENCE_IFOV = 1e-3  # [rad]: any IFOV works for the geometric scaling
_RANGE_TOLERANCE = 1e-12  # of the ranges solved inside the bisection
_NOT_MODEL = ("critical_dimension", "ifov", "cycle", "mrtd")
_OPTICS_AND_NOISE: dict[str, Any] = {
    "wavelength": None,
    "aperture": None,
    "blur_sigma": None,
    "extinction": None,
    "path": None,
    "foliage": None,
    "contrast": None,
    "noise_equivalent_contrast": None,
    "target_area": None,
    "ttp": None,
}

CaseAt = Callable[[Any], RangeCase]


def _positive(name: str, value: Any, unit: str) -> None:
    """``value`` > 0 and finite (a scalar sensor or lens parameter)."""
    if not (
        isinstance(value, int | float | np.floating | np.integer) and not isinstance(value, bool)
    ):
        raise ValueError(f"{name} must be a number [{unit}], got {value!r}")
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be finite and > 0 {unit}, got {value!r}")


def _case_builder(
    critical_dimension: Any,
    model: dict[str, Any],
    *,
    pitch: float | None = None,
    focal_length: float | None = None,
    f_number: float | None = None,
) -> CaseAt:
    """IFOV → the :class:`RangeCase` of the design at that IFOV (the model's keywords checked
    once here, by making the case at a reference IFOV)."""
    for name in _NOT_MODEL:
        if name in model:
            what = (
                "an MRTD curve fixes the camera's resolution"
                if name == "mrtd"
                else "the design solves for the IFOV"
                if name in ("ifov", "cycle")
                else "it is an argument of its own"
            )
            raise ValueError(f"{name} is not a model keyword of the design ({what})")
    if f_number is not None:
        _positive("f_number", f_number, "")
        if model.get("aperture") is not None:
            raise ValueError("give aperture or f_number, not both")
        if model.get("wavelength") is None:
            raise ValueError("f_number gives the aperture for diffraction: give wavelength")
        if pitch is None and focal_length is None:
            raise ValueError("f_number needs the focal length (aperture = focal length / F#)")

    def case_at(ifov: Any) -> RangeCase:
        keywords = dict(model)
        if f_number is not None:
            f = focal_length if focal_length is not None else pitch / ifov
            keywords["aperture"] = f / f_number
        if keywords.get("ttp") is not None:  # the TTP system's pixels (and lens) are the design's
            lens = {} if f_number is None else {"aperture": keywords["aperture"]}
            keywords["ttp"] = dataclasses.replace(keywords["ttp"], ifov=ifov, **lens)
        return RangeCase(critical_dimension, ifov, **keywords)

    case_at(_REFERENCE_IFOV)
    return case_at


def _geometric(case: RangeCase) -> RangeCase:
    """The case without optics limits and noise: one cycle is two pixels."""
    return dataclasses.replace(case, **_OPTICS_AND_NOISE)


def _is_geometric(case: RangeCase) -> bool:
    return (
        not case.noisy and case.wavelength is None and case.blur_sigma is None and case.ttp is None
    )


def _task_range(case: RangeCase, probability: Any, task: str) -> Any:
    ranges = case_ranges(case, probability, _RANGE_TOLERANCE)
    if task not in ranges:
        raise ValueError(f"task must be one of {', '.join(ranges)}; got {task!r}")
    return np.asarray(ranges[task], dtype=float)


_PRESUPPOSES = {
    "orientation": "detection",
    "recognition": "detection",
    "identification": "recognition",
}
"""The task each task's range is capped by in :func:`targetacq.core.ranges.case_ranges`."""

_DRI_TASKS = ("detection", "recognition", "identification")


def _reaches(case: RangeCase, r: Any, p: Any, task: str, tasks: list[str]) -> Any:
    """Whether ``task``'s range in :func:`targetacq.core.ranges.case_ranges` is at least ``r``.

    That range is the largest ``R`` with ``P(R) >= p`` on the task's curve (P falls with R),
    capped by the ranges of the tasks it presupposes; so it reaches ``r`` exactly where every
    one of those curves is at least ``p`` at ``r``: one evaluation of the curves instead of a
    bisection in range per step of the bisection in IFOV. The curves are those
    :func:`~targetacq.core.ranges.case_ranges` reads: each task's own
    (:func:`~targetacq.core.cases.case_probability`), or with ``semantics="conditional"`` the
    conditional recognition and identification of :func:`~targetacq.core.cases.case_acquisition`.
    """
    conditional = case.semantics == "conditional" and set(_DRI_TASKS) <= set(tasks)
    acquisition = case_acquisition(case, r) if conditional else None
    ok = np.ones(np.broadcast_shapes(np.shape(r), np.shape(p)), dtype=bool)
    current: str | None = task
    while current is not None:
        if acquisition is not None and current in _DRI_TASKS and current != "detection":
            curve = getattr(acquisition, current)
        else:
            curve = case_probability(case, r, current)
        ok = ok & (np.asarray(curve, dtype=float) >= p)
        current = _PRESUPPOSES.get(current)
        if current not in tasks:
            current = None
    return ok


def _inputs(case_at: CaseAt, range: Any, probability: Any) -> tuple[Any, Any, Any]:
    """Range and probability as float arrays, checked; NaN (missing) replaced by safe values
    and marked."""
    r = np.asarray(range, dtype=float)
    p = np.asarray(probability, dtype=float)
    if not (np.issubdtype(r.dtype, np.floating) and np.issubdtype(p.dtype, np.floating)):
        raise ValueError("range and probability must be real numbers")
    if np.any(~np.isnan(r) & ~((r > 0) & np.isfinite(r))):
        raise ValueError(f"range must be finite and > 0 m, got {range!r}")
    if get_criterion(case_at(_REFERENCE_IFOV).criterion).gives_probabilities and np.any(
        ~np.isnan(p) & ~((p > 0) & (p < 1))
    ):
        raise ValueError(f"probability must be in the open interval (0, 1), got {probability!r}")
    missing = np.isnan(r) | np.isnan(p)
    return np.where(missing, 1.0, r), np.where(missing, 0.5, p), missing


def _solve(case_at: CaseAt, distance: Any, probability: Any, task: str) -> Any:
    """The largest IFOV [rad] at which ``task``'s range reaches ``distance`` [m] (module
    docstring)."""
    r, p, missing = _inputs(case_at, distance, probability)
    reference = _task_range(_geometric(case_at(_REFERENCE_IFOV)), p, task)
    geometric = _REFERENCE_IFOV * reference / r  # inf: any IFOV; NaN: never reached
    ttp = case_at(_REFERENCE_IFOV).ttp
    if ttp is not None:
        # The TTP metric's V <= d / (R · IFOV) · sqrt(1 / min CTF_eye) (C <= 1, MTF <= 1, noise
        # >= 1, frequencies up to 1/IFOV), against the geometric N = d / (2 R IFOV) for the same
        # cycles: the IFOV can be that many times the geometric one at most.
        geometric = (
            geometric
            * 2.0
            / math.sqrt(eye_ctf_minimum(float(ttp.luminance), float(ttp.field_angle)))
        )
    if _is_geometric(case_at(_REFERENCE_IFOV)):
        found = geometric
    else:
        bracketed = np.isfinite(geometric) & (geometric > 0)
        hi = np.where(bracketed, geometric, _REFERENCE_IFOV)
        # With the TTP metric, V is not monotone in the IFOV for a fixed aperture (at the display
        # magnification of a very fine pixel the optics' cut-off falls below the eye's peak
        # sensitivity): its search starts two decades below the bound instead.
        lo = hi * (SEARCH_DEPTH if ttp is None else 1e-2)

        tasks = list(case_ranges(_geometric(case_at(_REFERENCE_IFOV)), 0.5))

        def reaches(ifov: Any) -> Any:
            return _reaches(case_at(ifov), r, p, task, tasks)

        at_hi, at_lo = reaches(hi), reaches(lo)
        top = hi
        for _ in range(SOLVER_ITERATIONS):
            mid = np.sqrt(lo * hi)
            ok = reaches(mid)
            lo, hi = np.where(ok, mid, lo), np.where(ok, hi, mid)
        found = np.where(at_hi, top, np.where(at_lo, lo, np.nan))
        found = np.where(bracketed, found, geometric)
    return _arrays.result(np.where(missing, np.nan, found))


def required_ifov(
    critical_dimension: Array,
    range: Array,
    probability: Array = 0.5,
    task: str = "recognition",
    **model: Any,
) -> Any:
    """The largest pixel IFOV at which a task reaches a probability at a range.

    Purely geometric: ``IFOV = d / (2 · N_P · R)`` with ``N_P = N50 · x(P)`` (§3.5, Fig. 3.3,
    Eq. (3.1) of Sonesson (2004)); with optics limits or noise, bisection on
    :func:`targetacq.core.ranges.case_ranges` (module docstring).

    Parameters
    ----------
    critical_dimension : array_like
        Critical dimension of the target [m], > 0.
    range : array_like
        Slant range [m] at which the task must reach the probability, > 0.
    probability : array_like
        In (0, 1); broadcasts with ``range`` (ignored by a pixel-density criterion).
    task : str
        A task of the criterion (e.g. "detection", "recognition", "identification").
    **model
        The other keywords of :class:`targetacq.core.cases.RangeCase` (``criterion``,
        ``transform``, ``options``, ``wavelength`` and ``aperture`` [m], ``blur_sigma`` [rad],
        ``extinction`` [Np/m], ``scr``, ``region``, ``noise_equivalent_contrast`` with
        ``contrast``, ``semantics``, ...); not ``ifov``, ``cycle`` or ``mrtd``.

    Returns
    -------
    array_like
        IFOV [rad]: NaN where no IFOV reaches it (:func:`unreachable_reason`) and where an
        input is NaN; +inf where the task needs no resolution.

    Raises
    ------
    ValueError
        If ``range`` is not > 0, ``probability`` not in (0, 1), ``task`` not a task of the
        criterion, or a model keyword is out of its domain (as :class:`RangeCase`).

    Examples
    --------
    Recognise a person (0.75 m) at 1 km with probability 0.5 (Johnson: N50 = 4 cycles):

    >>> float(required_ifov(0.75, 1000.0, 0.5, "recognition"))  # 0.75 / (2 · 4 · 1000)
    9.375e-05

    Haze (0.4 Np/km) adds noise: a finer IFOV is needed.

    >>> bool(required_ifov(0.75, 1000.0, 0.5, extinction=0.4e-3) < 9.375e-05)
    True
    """
    return _solve(_case_builder(critical_dimension, model), range, probability, task)


def required_focal_length(
    pitch: float,
    critical_dimension: Any,
    range: Any,
    probability: Any = 0.5,
    task: str = "recognition",
    *,
    f_number: float | None = None,
    **model: Any,
) -> Any:
    """The shortest focal length with which a task reaches a probability at a range.

    ``f = p / IFOV`` (Eq. (5.1) of Sonesson (2004)) with the IFOV of :func:`required_ifov`.

    Parameters
    ----------
    pitch : float
        Detector pixel pitch [m], > 0.
    critical_dimension, range, probability, task, **model
        As :func:`required_ifov`.
    f_number : float, optional
        The lens's F-number: its aperture is then ``f / F#`` (diffraction with ``wavelength``);
        instead of a fixed ``aperture``.

    Returns
    -------
    array_like
        Focal length [m]; NaN where none reaches it.

    Examples
    --------
    A 12 µm pitch recognising a person (0.75 m) at 1 km with probability 0.5:

    >>> round(float(required_focal_length(12e-6, 0.75, 1000.0, 0.5, "recognition")), 12)
    0.128
    """
    _positive("pitch", pitch, "m")
    case_at = _case_builder(critical_dimension, model, pitch=pitch, f_number=f_number)
    return _arrays.result(pitch / np.asarray(_solve(case_at, range, probability, task)))


def required_pitch(
    focal_length: float,
    critical_dimension: Any,
    range: Any,
    probability: Any = 0.5,
    task: str = "recognition",
    *,
    f_number: float | None = None,
    **model: Any,
) -> Any:
    """The largest pixel pitch with which a lens reaches a probability at a range.

    ``p = f · IFOV`` (Eq. (5.1) of Sonesson (2004)) with the IFOV of :func:`required_ifov`.

    Parameters
    ----------
    focal_length : float
        Focal length [m], > 0.
    critical_dimension, range, probability, task, **model
        As :func:`required_ifov`.
    f_number : float, optional
        The lens's F-number: its aperture ``f / F#`` (diffraction with ``wavelength``).

    Returns
    -------
    array_like
        Pixel pitch [m]; NaN where none reaches it.

    Examples
    --------
    >>> round(float(required_pitch(0.128, 0.75, 1000.0)) * 1e6, 9)  # [µm]
    12.0
    """
    _positive("focal_length", focal_length, "m")
    case_at = _case_builder(critical_dimension, model, focal_length=focal_length, f_number=f_number)
    return _arrays.result(focal_length * np.asarray(_solve(case_at, range, probability, task)))


def unreachable_reason(
    critical_dimension: float,
    range: float,
    probability: float = 0.5,
    task: str = "recognition",
    *,
    pitch: float | None = None,
    focal_length: float | None = None,
    f_number: float | None = None,
    **model: Any,
) -> str | None:
    """Why no IFOV reaches a task at a range (None where one does); scalars only.

    The causes are tried in turn, each alone: the path (``extinction``, ``foliage``: the
    weather's noise at that range does not depend on the IFOV), the lens's fixed optics limit
    (diffraction ``1.22 λ/D`` and blur, Eqs. (5.2), (5.3)), then the criterion and the clutter
    (the transform never reaches the probability), then the sensor's own noise.

    Parameters
    ----------
    critical_dimension, range, probability, task, **model
        As :func:`required_ifov`.
    pitch, focal_length, f_number : float, optional
        As :func:`required_focal_length` and :func:`required_pitch`.

    Returns
    -------
    str or None

    Examples
    --------
    >>> unreachable_reason(0.75, 1000.0, 0.5) is None
    True
    >>> unreachable_reason(0.75, 1000.0, 0.5, extinction=20e-3)[:34]
    'the weather alone makes it impossi'
    """
    case_at = _case_builder(
        critical_dimension, model, pitch=pitch, focal_length=focal_length, f_number=f_number
    )
    if not math.isnan(float(_solve(case_at, range, probability, task))):
        return None
    at = f"{task} with P = {probability:g} at {range:g} m"
    if math.isnan(float(_solve(lambda x: _geometric(case_at(x)), range, probability, task))):
        return (
            f"the criterion and the clutter alone make it impossible: {task} never reaches "
            f"P = {probability:g} at any resolution"
        )
    without_path: dict[str, Any] = {"extinction": None, "path": None, "foliage": None}
    if any(model.get(name) is not None for name in without_path):
        clear = _solve(
            lambda x: dataclasses.replace(case_at(x), **without_path), range, probability, task
        )
        if not math.isnan(float(clear)):
            return (
                "the weather alone makes it impossible: through this path ("
                + (
                    "a named atmosphere"
                    if model.get("path") is not None
                    else f"extinction {(model.get('extinction') or 0.0) * 1e3:g} Np/km"
                )
                + f") {at} is out of reach at "
                "any IFOV, its noise at that range does not depend on the sensor"
            )
    no_optics: dict[str, Any] = {"wavelength": None, "aperture": None, "blur_sigma": None}
    sharp = _solve(lambda x: dataclasses.replace(case_at(x), **no_optics), range, probability, task)
    if not math.isnan(float(sharp)):
        finest = float(case_at(float(sharp) * SEARCH_DEPTH).cycle_angle)
        return (
            f"the lens's optics limit alone makes it impossible: its finest resolvable cycle "
            f"({finest * 1e3:.4g} mrad, diffraction and blur) is too coarse for {at}; a larger "
            "aperture or less blur is needed"
        )
    return f"the sensor's noise makes it impossible: {at} is out of reach at any IFOV"
