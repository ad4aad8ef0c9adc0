"""Calibration of a transform to trial data: N50 (and the exponent) by maximum likelihood.

Sonesson (2004) §9.4 asks for "comparisons to actual sensors" to produce the transforms. Given
trials — the cycles on target ``N_i`` of each and whether the observer succeeded (``y_i`` = 1)
or not (0) — :func:`fit_criterion` finds the N50 of a task, and for the TTPF-family transforms
its exponent, that make the outcomes most likely, with confidence intervals; the fitted N50 is a
:class:`~targetacq.acquisition.criteria.Criterion` that can be registered under a name
(:func:`~targetacq.acquisition.criteria.register_criterion`) and is then used like the bundled
ones. Trials given as ranges become cycles by the sensor's geometry first
(:func:`targetacq.physics.optics.cycles_on_target`; ``targetacq calibrate`` does it).

The model
---------
Each trial is a Bernoulli draw, ``y_i ~ Bernoulli(P(N_i))``, independent of the others. The
log-likelihood is

``ℓ = Σ_i [y_i z_i − ln(1 + e^{z_i})]``,  ``z_i = logit P(N_i)``.

``P`` is the chosen transform of the registry (:data:`~targetacq.acquisition.transforms.
TRANSFORMS`) with the N50 to be fitted. For the two TTPFs, ``P = x^E / (1 + x^E)`` with
``x = N/N50`` and ``E = E0 + E1 x`` (``ttpf``: 2.7 + 0.7 x; ``ttp``: 1.51 + 0.24 x), so
``z = E ln x``; their exponent is fitted as a scale ``s`` of that law,

``E = s (E0 + E1 x)``,  i.e. ``z = s · logit P_transform(N; N50)``,

reported as the exponent at N50, ``E50 = s (E0 + E1)`` (3.4 for ``ttpf`` as registered, 1.75 for
``ttp``); ``E50 / 4`` is the slope ``dP / d ln N`` at N50. The Johnson family's shape (the ratio
E1/E0) is kept; its steepness is what the data set. The table transforms (``c2nveo``,
``schmieder-weathersby``, ``schmieder-weathersby-observed``) have no exponent: their N50 alone
is fitted (it stretches the cycles axis, as a criterion does).

The transform gives ``P``; ``z`` is its logit, with ``P`` held in [1e-15, 1 − 1e-15] (``|z| <=
34.5``), so that an outcome where the transform gives exactly 0 or 1 (below a table's first
printed point, or from its 1.00 row on) is very unlikely rather than impossible.

Maximum likelihood
------------------
Fitted in ``u = ln N50`` over ``[min N / 100, 100 max N]``: the profile log-likelihood
``ℓp(u) = max_s ℓ(u, s)`` (``s`` in [0.01, 100]) is evaluated on a grid of 81 points, and its
maximum refined by :func:`scipy.optimize.minimize_scalar` (bounded) between the grid's
neighbours. For a given N50 the best ``s`` solves a one-dimensional concave problem
(``ℓ`` is concave in ``s``), by Newton's method safeguarded by bisection.

Confidence intervals: profile likelihood
----------------------------------------
A parameter's interval at confidence ``c`` is the set of its values whose profile
log-likelihood is within ``χ²₁(c) / 2`` of the maximum (the likelihood-ratio test inverted;
Venzon & Moolgavkar, *Appl. Statist.* 37 (1988) 87; Pawitan, *In All Likelihood* (2001)).
It is used rather than the observed Fisher information (Wald intervals) because it is
invariant to the parameterisation and keeps its coverage better with few trials, where the
likelihood of N50 is skewed. The N50 interval's ends are roots of ``ℓp(u) = ℓmax − χ²₁(c)/2``
(:func:`scipy.optimize.brentq`); the exponent's interval is the extent in ``s`` of the joint
region ``ℓ(u, s) >= ℓmax − χ²₁(c)/2``, the same set as the values of ``s`` whose profile over
N50 reaches the threshold. An end that does not lie within the search box is reported as 0 or
``inf`` (the data do not bound it at that confidence).

Data that fix no N50
--------------------
``ValueError`` when every trial succeeded or every trial failed (the N50 runs to the box's edge
whatever the transform), and, with the exponent fitted, when the outcomes are separated by the
cycles (every failure at fewer cycles than every success: the exponent runs to infinity) or all
trials are at one number of cycles; fitting N50 alone (``fit_exponent=False``) still works for
separated outcomes.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np
from scipy import optimize, special, stats

from targetacq.acquisition.criteria import (
    TASKS,
    Criterion,
    get_criterion,
    register_criterion,
)
from targetacq.acquisition.transforms import (
    TTP_E0,
    TTP_E1,
    TTPF_E0,
    TTPF_E1,
    get_transform,
)
from targetacq.base.arrays import Array

__all__ = ["EXPONENT_LAWS", "CriterionFit", "fit_criterion"]

EXPONENT_LAWS: Mapping[str, tuple[float, float]] = MappingProxyType(
    {"ttpf": (TTPF_E0, TTPF_E1), "ttp": (TTP_E0, TTP_E1)}
)
"""The transforms whose exponent can be fitted → their law ``E = E0 + E1 x`` as (E0, E1)."""

PROBABILITY_FLOOR = 1e-15
"""A transform's P is held in [floor, 1 − floor] for the likelihood (module doc)."""

N50_SPAN = 100.0
"""N50 is searched in [min N / span, span · max N]."""

SCALE_BOUNDS = (0.01, 100.0)
"""The exponent's scale ``s`` is searched in this interval."""

_GRID = 81  # points of the first profile grid over ln N50
_NEWTON_STEPS = 100


@dataclass(frozen=True)
class CriterionFit:
    """The result of :func:`fit_criterion`.

    Attributes
    ----------
    task : str
        The observation task fitted.
    transform : str
        The transform's name in :data:`~targetacq.acquisition.transforms.TRANSFORMS`.
    n50 : float
        Maximum-likelihood N50 [cycles] (V50 for the ``ttp`` transform).
    n50_interval : tuple of float
        Its profile-likelihood interval at ``confidence`` [cycles]; an end the data do not bound
        is 0 or ``inf``.
    exponent : float
        The exponent at N50, ``E50 = s (E0 + E1)`` [1] (module doc): fitted when
        ``exponent_fitted``, else the transform's own; NaN for a table transform.
    exponent_interval : tuple of float
        Its profile-likelihood interval (both ends ``exponent`` when not fitted).
    exponent_fitted : bool
    log_likelihood : float
        ``ℓ`` at the maximum [nats].
    trials, successes : int
    confidence : float
        Of the intervals, in (0, 1).
    criterion : Criterion
        The fitted N50 for ``task`` (with the other tasks of the base criterion, if any).
    options : Mapping
        The transform's options used.
    method : str
        How the intervals were found.
    data : tuple of numpy.ndarray
        The trials' cycles and outcomes (for :meth:`probability_interval`).
    """

    task: str
    transform: str
    n50: float
    n50_interval: tuple[float, float]
    exponent: float
    exponent_interval: tuple[float, float]
    exponent_fitted: bool
    log_likelihood: float
    trials: int
    successes: int
    confidence: float
    criterion: Criterion
    options: Mapping[str, Any] = field(default_factory=dict)
    method: str = "profile likelihood"
    data: tuple[np.ndarray, np.ndarray] = field(
        default=(np.zeros(0), np.zeros(0)), repr=False, compare=False
    )

    @property
    def exponent_scale(self) -> float:
        """``s``, the fitted exponent over the transform's own (1: the transform as it is)."""
        law = EXPONENT_LAWS.get(self.transform)
        return 1.0 if law is None else self.exponent / (law[0] + law[1])

    def probability(self, cycles: Array) -> Any:
        """P of the task at ``cycles`` [cycles] by the fitted curve (``s = 1``: the transform).

        Examples
        --------
        >>> from targetacq.acquisition.calibration import fit_criterion
        >>> fit = fit_criterion([2, 4, 6, 8], [0, 1, 0, 1], "recognition", fit_exponent=False)
        >>> print(f"{fit.probability(fit.n50):.3f}")
        0.500
        """
        chosen = get_transform(self.transform)
        p = chosen.forward(cycles, self.n50, self.task, **self.options)
        scale = self.exponent_scale
        if scale == 1.0:
            return p
        return special.expit(scale * _logit(np.asarray(p, dtype=float)))

    def probability_interval(self, cycles: Array, points: int = 61) -> tuple[Any, Any]:
        """Pointwise profile-likelihood interval of P at each of ``cycles`` [cycles].

        The least and the greatest ``P(N)`` over the parameters whose log-likelihood is within
        ``χ²₁(confidence) / 2`` of the maximum: the profile-likelihood interval of the function
        ``P(N)`` of the parameters (module doc), found on a grid of ``points`` values of each
        fitted parameter across its interval (``points²`` curves, the maximum among them), so a
        little narrower than the exact one.

        Returns
        -------
        tuple of numpy.ndarray
            (low, high), each shaped like ``cycles``.

        Examples
        --------
        >>> from targetacq.acquisition.calibration import fit_criterion
        >>> fit = fit_criterion([2, 3, 3, 4, 4, 5, 5, 6], [0, 0, 1, 0, 1, 1, 0, 1],
        ...                     "recognition", fit_exponent=False)
        >>> low, high = fit.probability_interval([fit.n50])
        >>> bool(low[0] < 0.5 < high[0])
        True
        """
        n = np.asarray(cycles, dtype=float)
        trials = _Trials(self.data[0], self.data[1], self.task, self.transform, self.options, False)
        top = self.log_likelihood - 0.5 * float(stats.chi2.ppf(self.confidence, 1))
        top -= 1e-8 * (1.0 + abs(top))  # the intervals' ends are roots to about 1e-9
        box = (math.log(self.data[0].min() / N50_SPAN), math.log(self.data[0].max() * N50_SPAN))
        ends = np.log(np.clip(self.n50_interval, *np.exp(box)))  # 0 and inf: the box's edges
        log_n50 = np.append(np.linspace(ends[0], ends[1], points), math.log(self.n50))
        scale = self.exponent_scale
        law = EXPONENT_LAWS.get(self.transform)
        if self.exponent_fitted and law is not None:
            low, high = np.clip(np.asarray(self.exponent_interval) / sum(law), *SCALE_BOUNDS)
            scales = np.append(np.geomspace(low, high, points), scale)
        else:
            scales = np.array([scale])
        z0 = trials.logits(log_n50)  # (G, n)
        inside = _log_likelihood(scales[:, None, None] * z0, trials.outcomes) >= top  # (K, G)
        inside[-1, -1] = True  # the maximum itself
        chosen = get_transform(self.transform)
        p = chosen.forward(n.ravel(), np.exp(log_n50)[:, None], self.task, **self.options)
        curves = special.expit(scales[:, None, None] * _logit(np.asarray(p, dtype=float)))
        if not self.exponent_fitted:
            curves = np.asarray(p, dtype=float)[None, ...]
        chosen_curves = curves[inside]  # (curves in the region, M)
        low_p, high_p = chosen_curves.min(axis=0), chosen_curves.max(axis=0)
        return low_p.reshape(n.shape), high_p.reshape(n.shape)

    def as_dict(self) -> dict[str, Any]:
        """The fit as plain numbers and strings (for JSON)."""
        return {
            "task": self.task,
            "transform": self.transform,
            "n50": self.n50,
            "n50_interval": list(self.n50_interval),
            "exponent": self.exponent,
            "exponent_interval": list(self.exponent_interval),
            "exponent_fitted": self.exponent_fitted,
            "log_likelihood": self.log_likelihood,
            "trials": self.trials,
            "successes": self.successes,
            "confidence": self.confidence,
            "method": self.method,
            "criterion": self.criterion.name,
            "thresholds": dict(self.criterion.thresholds),
        }


def _logit(p: np.ndarray) -> np.ndarray:
    q = np.clip(p, PROBABILITY_FLOOR, 1.0 - PROBABILITY_FLOOR)
    return np.log(q) - np.log1p(-q)


def _log_likelihood(z: np.ndarray, y: np.ndarray) -> np.ndarray:
    """``Σ y z − ln(1 + e^z)`` over the last axis."""
    return (y * z - np.logaddexp(0.0, z)).sum(axis=-1)


def _slope(s: np.ndarray, z0: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``dℓ/ds`` and ``−d²ℓ/ds²`` of ``ℓ(s z0)`` per row."""
    p = special.expit(s[..., None] * z0)
    return (z0 * (y - p)).sum(axis=-1), (z0 * z0 * (p * (1.0 - p))).sum(axis=-1)


def _best_scale(z0: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per row of ``z0`` (..., n): the ``s`` in :data:`SCALE_BOUNDS` maximising
    ``ℓ(s z0)``, and that ``ℓ``. ``ℓ`` is concave in ``s``: the maximum is on an edge where the
    slope there points out of the box, else found by Newton's method safeguarded by bisection."""
    shape = z0.shape[:-1]
    lo = np.full(shape, SCALE_BOUNDS[0])
    hi = np.full(shape, SCALE_BOUNDS[1])
    at_lo = _slope(lo, z0, y)[0] <= 0
    at_hi = _slope(hi, z0, y)[0] >= 0
    s = np.where(at_lo, lo, np.where(at_hi, hi, np.clip(1.0, lo, hi)))
    active = ~(at_lo | at_hi)
    for _ in range(_NEWTON_STEPS):
        if not active.any():
            break
        gradient, curvature = _slope(s, z0, y)
        lo = np.where(active & (gradient > 0), s, lo)
        hi = np.where(active & (gradient <= 0), s, hi)
        with np.errstate(divide="ignore", invalid="ignore"):
            candidate = s + gradient / curvature
        bad = ~((candidate >= lo) & (candidate <= hi))
        candidate = np.where(bad, np.sqrt(lo * hi), candidate)
        step = np.abs(candidate - s)
        s = np.where(active, candidate, s)
        active = active & (step > 1e-11 * s)
    return s, _log_likelihood(s[..., None] * z0, y)


@dataclass(frozen=True)
class _Trials:
    """Checked trials and the transform: the likelihood as a function of (ln N50, s)."""

    cycles: np.ndarray
    outcomes: np.ndarray
    task: str
    transform: str
    options: Mapping[str, Any]
    fit_exponent: bool

    def logits(self, log_n50: np.ndarray) -> np.ndarray:
        """``logit P(N_i; N50)`` for each ln N50 (shape (...,)) → (..., n)."""
        chosen = get_transform(self.transform)
        n50 = np.exp(np.asarray(log_n50, dtype=float))[..., None]
        p = chosen.forward(self.cycles, n50, self.task, **self.options)
        return _logit(np.asarray(p, dtype=float))

    def profile(self, log_n50: Any) -> tuple[np.ndarray, np.ndarray]:
        """(best s, ℓ) at each ln N50."""
        z0 = self.logits(log_n50)
        if not self.fit_exponent:
            return np.ones(z0.shape[:-1]), _log_likelihood(z0, self.outcomes)
        return _best_scale(z0, self.outcomes)

    def scale_ends(self, log_n50: np.ndarray, target: float, upper: bool) -> np.ndarray:
        """At each ln N50, the ``s`` below (above, ``upper``) the best one where
        ``ℓ(ln N50, s) = target``: the best s itself where its ``ℓ`` is below ``target``, the
        edge of :data:`SCALE_BOUNDS` where ``ℓ`` stays above it. Newton's method from the edge
        (ℓ is concave in s, so the steps approach the root from the edge's side), to a relative
        1e-11."""
        z0 = self.logits(log_n50)
        best, top = _best_scale(z0, self.outcomes)
        edge = SCALE_BOUNDS[1] if upper else SCALE_BOUNDS[0]
        # From the edge, where ℓ < target, Newton's steps approach the root monotonically: ℓ is
        # concave, so each tangent's root stays on the edge's side of the true one.
        s = np.full_like(best, edge)
        active = _log_likelihood(edge * z0, self.outcomes) < target
        active &= top > target
        for _ in range(_NEWTON_STEPS):
            if not active.any():
                break
            gradient = _slope(s, z0, self.outcomes)[0]
            gap = _log_likelihood(s[..., None] * z0, self.outcomes) - target
            with np.errstate(divide="ignore", invalid="ignore"):
                candidate = s - gap / gradient
            candidate = np.where(np.isfinite(candidate), candidate, best)
            candidate = np.maximum(candidate, best) if upper else np.minimum(candidate, best)
            step = np.abs(candidate - s)
            s = np.where(active, candidate, s)
            active &= step > 1e-11 * s
        return np.where(top <= target, best, s)


def _checked(cycles: Any, outcomes: Any) -> tuple[np.ndarray, np.ndarray]:
    n = np.asarray(cycles, dtype=float).ravel()
    raw = np.asarray(outcomes)
    if raw.dtype == bool:
        raw = raw.astype(float)
    try:
        y = raw.astype(float).ravel()
    except (TypeError, ValueError) as error:
        raise ValueError("outcomes must be 0 (failure) or 1 (success) for each trial") from error
    if n.size != y.size:
        raise ValueError(
            f"cycles and outcomes must have one value per trial; got {n.size} and {y.size}"
        )
    if n.size == 0:
        raise ValueError("no trials: give the cycles and the outcome of at least two trials")
    if not (np.all(np.isfinite(n)) and np.all(n > 0)):
        bad = int(np.flatnonzero(~(np.isfinite(n) & (n > 0)))[0])
        raise ValueError(
            f"cycles must be finite and > 0 for every trial; trial {bad + 1} (counting from 1) "
            f"has {float(n[bad])!r}"
        )
    if not np.all((y == 0) | (y == 1)):
        bad = int(np.flatnonzero(~((y == 0) | (y == 1)))[0])
        raise ValueError(
            f"outcomes must be 0 (failure) or 1 (success); trial {bad + 1} (counting from 1) "
            f"has {raw.ravel()[bad].item()!r}"
        )
    return n, y


def _check_identifiable(n: np.ndarray, y: np.ndarray, fit_exponent: bool) -> None:
    successes = int(y.sum())
    if successes in (0, y.size):
        every = "succeeded" if successes else "failed"
        raise ValueError(
            f"every one of the {y.size} trials {every}: the data fix no N50 (it runs to the edge "
            "of any range searched); give trials with both outcomes"
        )
    if not fit_exponent:
        return
    if np.unique(n).size < 2:
        raise ValueError(
            "every trial is at the same cycles: N50 and the exponent cannot both be fitted; "
            "give trials at two or more cycles, or fit N50 alone (fit_exponent=False; "
            "calibrate --fixed-exponent)"
        )
    highest_failure, lowest_success = n[y == 0].max(), n[y == 1].min()
    if highest_failure <= lowest_success:
        raise ValueError(
            f"the outcomes are separated by the cycles (every failure at <= {highest_failure:g}, "
            f"every success at >= {lowest_success:g} cycles): the exponent runs to infinity; "
            "fit N50 alone (fit_exponent=False; calibrate --fixed-exponent) or add trials where "
            "the outcomes overlap"
        )


def _base_thresholds(base: str | Criterion | Mapping[str, float] | None) -> dict[str, float]:
    if base is None:
        return {}
    chosen = get_criterion(base)
    if not chosen.gives_probabilities:
        raise ValueError(
            f"base criterion {chosen.name!r} gives pixel densities, not N50s; choose a cycles "
            "criterion (e.g. johnson) or None"
        )
    return dict(chosen.thresholds)


def _fitted_criterion(
    name: str | None, task: str, n50: float, base: str | Criterion | Mapping[str, float] | None
) -> Criterion:
    thresholds = _base_thresholds(base)
    thresholds[task] = n50
    ordered = {t: thresholds[t] for t in TASKS if t in thresholds}
    ordered.update({t: v for t, v in thresholds.items() if t not in ordered})
    values = [ordered[t] for t in TASKS if t in ordered]
    if any(b < a for a, b in itertools.pairwise(values)):
        shown = ", ".join(f"{t} {ordered[t]:.4g}" for t in TASKS if t in ordered)
        raise ValueError(
            f"the fitted {task} N50 ({n50:.4g} cycles) breaks the order of the base criterion's "
            f"N50s ({shown}): a harder task needs at least as many cycles; choose another base "
            "or none (base=None; calibrate --base none)"
        )
    source = f"fitted to trial data ({task}) by targetacq.acquisition.calibration.fit_criterion"
    if base is not None:
        source += f"; other tasks from {get_criterion(base).name!r}"
    return Criterion(name or "fitted", ordered, source=source)


def _n50_end(
    trials: _Trials, grid: np.ndarray, values: np.ndarray, best: float, target: float, upper: bool
) -> float:
    """An end of the N50 interval in ln N50: root of ``ℓp = target`` on one side of ``best``."""
    side = grid > best if upper else grid < best
    below = side & (values < target)
    if not below.any():
        return math.inf if upper else -math.inf
    outer = grid[below].min() if upper else grid[below].max()

    def gap(u: float) -> float:
        return float(trials.profile(np.asarray(u))[1]) - target

    a, b = sorted((best, float(outer)))
    return optimize.brentq(gap, a, b, xtol=1e-9, rtol=1e-9)


def fit_criterion(
    cycles: Array,
    outcomes: Array,
    task: str,
    *,
    transform: str = "ttpf",
    fit_exponent: bool | None = None,
    confidence: float = 0.9,
    base: str | Criterion | Mapping[str, float] | None = "johnson",
    name: str | None = None,
    options: Mapping[str, Any] | None = None,
) -> CriterionFit:
    """Fit a task's N50 (and the transform's exponent) to trials by maximum likelihood.

    Each trial ``i`` has ``N_i`` cycles on target and an outcome ``y_i`` (1 success, 0 failure),
    ``y_i ~ Bernoulli(P(N_i))``; ``ℓ = Σ y_i z_i − ln(1 + e^{z_i})`` with ``z_i = logit P(N_i)``,
    ``P`` the transform with the N50 sought, and for ``ttpf`` / ``ttp`` the exponent law scaled,
    ``E = s (E0 + E1 N/N50)``. Intervals by profile likelihood (module doc).

    Parameters
    ----------
    cycles : array_like
        ``N_i`` [cycles], finite and > 0, one per trial (V, TTP cycles, for ``ttp``).
    outcomes : array_like
        ``y_i``: 1 (or True) for a success, 0 (False) for a failure, one per trial.
    task : str
        The task the trials tested (a key of the criterion's thresholds, e.g. ``recognition``).
    transform : str
        A name of :data:`~targetacq.acquisition.transforms.TRANSFORMS` (default ``ttpf``).
    fit_exponent : bool, optional
        Fit the exponent too (``ttpf`` and ``ttp`` only, :data:`EXPONENT_LAWS`); default: yes
        for those, no for the table transforms.
    confidence : float
        Of the intervals, in (0, 1); default 0.9.
    base : str, Criterion, mapping or None
        The criterion whose other tasks' N50s complete the fitted one (default ``johnson``;
        a scenario's ``[model] criterion`` needs detection, recognition and identification);
        None: the fitted task alone.
    name : str, optional
        Register the fitted criterion under this name
        (:func:`~targetacq.acquisition.criteria.register_criterion`, replacing one registered
        before under it); left out, nothing is registered and the criterion is named
        ``fitted``. A criterion holds N50s, and evaluations take the transform's own exponent:
        a name needs ``fit_exponent=False`` (a ``ValueError`` otherwise), so that what is
        registered is the curve that was fitted.
    options : mapping, optional
        The transform's options (e.g. ``{"region": "medium"}`` for ``schmieder-weathersby``);
        arrays broadcast over the trials.

    Returns
    -------
    CriterionFit
        N50, exponent, their intervals, ``ℓ`` at the maximum, the counts and the criterion.

    Raises
    ------
    ValueError
        Bad trials (not one outcome per cycles value, cycles not finite and > 0, an outcome
        not 0 or 1), data that fix no N50 (all successes or all failures) or no exponent
        (outcomes separated by the cycles; every trial at one number of cycles), an exponent
        asked of a table transform, an unknown transform or task, ``confidence`` outside
        (0, 1), or a fitted N50 out of order with the base criterion's.

    Examples
    --------
    Twelve recognition trials at 2 to 7 cycles; N50 and the TTPF's exponent at N50 (3.4 as
    registered) with their 90 % intervals, and the criterion registered under a name:

    >>> import targetacq as ta
    >>> from targetacq.acquisition.calibration import fit_criterion
    >>> cycles = [2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7]
    >>> seen = [0, 0, 0, 1, 0, 1, 1, 0, 1, 1, 1, 1]
    >>> fit = fit_criterion(cycles, seen, "recognition")
    >>> print(f"N50 {fit.n50:.2f} [{fit.n50_interval[0]:.2f}, {fit.n50_interval[1]:.2f}]")
    N50 3.84 [2.25, 5.17]
    >>> print(f"E50 {fit.exponent:.2f} [{fit.exponent_interval[0]:.2f}, "
    ...       f"{fit.exponent_interval[1]:.2f}]")
    E50 4.25 [1.00, 9.47]

    The exponent is within its interval of the TTPF's own 3.4; N50 at that exponent, registered:

    >>> fit = fit_criterion(cycles, seen, "recognition", fit_exponent=False, name="my-trials")
    >>> print(f"{ta.probability(fit.n50, 'recognition', criterion='my-trials'):.3f}")
    0.500
    >>> ta.get_criterion("my-trials").n50("identification")  # Johnson's, the base
    6.4
    >>> ta.unregister_criterion("my-trials")
    """
    if not (isinstance(confidence, (int, float)) and 0.0 < confidence < 1.0):
        raise ValueError(f"confidence must be in the open interval (0, 1); got {confidence!r}")
    if task not in TASKS:
        raise ValueError(f"task must be one of {', '.join(TASKS)}; got {task!r}")
    chosen = get_transform(transform)
    chosen.check(task, dict(options or {}))
    has_law = chosen.name in EXPONENT_LAWS
    if fit_exponent is None:
        fit_exponent = has_law
    if fit_exponent and not has_law:
        raise ValueError(
            f"transform {chosen.name!r} has no exponent to fit (a table); fit its N50 alone "
            f"(fit_exponent=False), or choose one of {', '.join(EXPONENT_LAWS)}"
        )
    if name is not None and fit_exponent:
        # A criterion holds N50s only: evaluations take the transform's own exponent, so a
        # criterion registered from a fit with another exponent would not give the fitted curve.
        raise ValueError(
            f"name registers a criterion, which holds N50 only (evaluations use {chosen.name!r}'s "
            "own exponent): fit with fit_exponent=False to register it, or leave name out to "
            "fit and report the exponent"
        )
    n, y = _checked(cycles, outcomes)
    _check_identifiable(n, y, fit_exponent)
    trials = _Trials(n, y, task, chosen.name, dict(options or {}), bool(fit_exponent))

    # The maximum: the profile on a grid, then refined between the best point's neighbours.
    bounds = (math.log(n.min() / N50_SPAN), math.log(n.max() * N50_SPAN))
    grid = np.linspace(*bounds, _GRID)
    _, values = trials.profile(grid)
    i = int(np.argmax(values))
    found = optimize.minimize_scalar(
        lambda u: -float(trials.profile(np.asarray(u))[1]),
        bounds=(grid[max(i - 1, 0)], grid[min(i + 1, _GRID - 1)]),
        method="bounded",
        options={"xatol": 1e-6},
    )
    best = float(found.x)
    scale, top = (float(v) for v in trials.profile(np.asarray(best)))
    if top < values[i]:  # the grid point itself was better (a flat or kinked profile)
        best, scale, top = float(grid[i]), float(trials.profile(grid[i])[0]), float(values[i])

    # Profile-likelihood intervals.
    target = top - 0.5 * float(stats.chi2.ppf(confidence, 1))
    lower = _n50_end(trials, grid, values, best, target, upper=False)
    upper = _n50_end(trials, grid, values, best, target, upper=True)
    n50_interval = (math.exp(lower), math.exp(upper))

    law = EXPONENT_LAWS.get(chosen.name)
    e50 = math.nan if law is None else law[0] + law[1]
    if fit_exponent:
        u_lo, u_hi = max(lower, bounds[0]), min(upper, bounds[1])
        s_lo = _extreme_scale(trials, (u_lo, best, u_hi), target, upper=False)
        s_hi = _extreme_scale(trials, (u_lo, best, u_hi), target, upper=True)
        s_lo = 0.0 if s_lo <= SCALE_BOUNDS[0] else s_lo
        s_hi = math.inf if s_hi >= SCALE_BOUNDS[1] else s_hi
        exponent, exponent_interval = scale * e50, (s_lo * e50, s_hi * e50)
    else:
        exponent, exponent_interval = e50, (e50, e50)

    n50 = math.exp(best)
    criterion = _fitted_criterion(name, task, n50, base)
    if name is not None:
        register_criterion(criterion, replace=True)
    return CriterionFit(
        task=task,
        transform=chosen.name,
        n50=n50,
        n50_interval=n50_interval,
        exponent=exponent,
        exponent_interval=exponent_interval,
        exponent_fitted=bool(fit_exponent),
        log_likelihood=top,
        trials=int(n.size),
        successes=int(y.sum()),
        confidence=float(confidence),
        criterion=criterion,
        options=dict(options or {}),
        data=(n, y),
    )


def _extreme_scale(
    trials: _Trials, span: tuple[float, float, float], target: float, upper: bool
) -> float:
    """The least (greatest) ``s`` of the region ``ℓ(u, s) >= target``: the scale ends at each
    ln N50 of a grid over the N50 interval ``span = (lo, best, hi)``, then refined by a bounded
    minimisation between the extreme grid point's neighbours."""
    lo, best, hi = span
    grid = np.unique(np.concatenate([np.linspace(lo, hi, 13), [best]]))
    ends = trials.scale_ends(grid, target, upper)
    sign = -1.0 if upper else 1.0
    i = int(np.argmin(sign * ends))
    edge = SCALE_BOUNDS[1] if upper else SCALE_BOUNDS[0]
    if ends[i] == edge:
        return edge
    found = optimize.minimize_scalar(
        lambda u: sign * float(trials.scale_ends(np.asarray(u), target, upper)),
        bounds=(grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]),
        method="bounded",
        options={"xatol": 1e-4},
    )
    refined = sign * float(found.fun)
    return min(float(ends[i]), refined) if not upper else max(float(ends[i]), refined)
