"""Transforms from resolution (cycles on target) to the probability of a task.

Five methods, kept in the registry :data:`TRANSFORMS` and reached through one dispatcher,
:func:`transform` (and :func:`inverse_transform` for the cycles needed for a probability):

``ttpf``
    The target transfer probability function of the NVESD models (ACQUIRE, NVTherm):
    ``P = x^E / (1 + x^E)``, ``x = N / N50``, ``E = 2.7 + 0.7 x``; ``P(N50) = 0.5``.
``ttp``
    The TTPF of the targeting task performance metric: the same form with ``x = V / V50`` and
    ``E = 1.51 + 0.24 x`` (:func:`ttp_transform`), for the TTP resolution model's cycles ``V``.
``c2nveo``
    Table 3.3 of Sonesson (2004): cycles needed for seven probabilities per task, each a range
    whose low end is the optimistic and high end the pessimistic curve (``bound``); ``nominal``
    is the geometric mean of each cell.
``schmieder-weathersby-observed``
    Table 3.4 of Sonesson (2004), the observations behind Table 3.5: a monotone fit through
    P(detection) observed at four SCRs (:mod:`targetacq.acquisition.observed_detection`). Detection
    only.
``schmieder-weathersby``
    Table 3.5 of Sonesson (2004): cycles needed for detection in low (SCR > 10), medium
    (1 <= SCR <= 10) and high (SCR < 1) clutter. Detection only (§3.8). Hot spots use the
    low-clutter curve (§3.9); here a moving target is always detected (§1.3, §7.5; the model
    chain uses the motion rules of :mod:`targetacq.acquisition.probabilities` instead).

    Continuous in the SCR. Given by ``region`` the printed curves hold as they are. Given an
    ``scr``, the curves are anchored at the lower edge of each region (low clutter for
    SCR >= 10, medium at SCR = 1, high at SCR <= 0.33, the lowest observed SCR) and the
    probability is interpolated linearly in ``log SCR`` between anchors. Table 3.5 bins
    observations (Table 3.4) into three regions, so a probability that jumps where the SCR
    crosses 1 or 10 is an artefact of the binning, and with noise the effective SCR moves
    with range: a jump in SCR became a jump in range (P from 1.00 to 0.57 over 2 m). The blend
    is this project's assumption; it keeps every printed point at its anchor, is monotone in
    SCR and N (the curves are ordered pointwise: low >= medium >= high), and follows Table 3.4
    closer than the bins (SCR 5.8, N = 1: observed 0.87, blend 0.84, medium bin 0.50).

Table curves are interpolated linearly in ``log N`` between the printed points (the thesis's
Figs. 3.5 and 3.7 use a logarithmic cycles axis), linearly in ``N`` from ``P = 0`` at ``N = 0``
to the first printed point, and held at the last printed probability beyond the last point
(1 where the table reaches 1; 0.9 for high clutter, which "never reaches 0.95"). Where a column
prints the same N for two probabilities (C2NVEO recognition, pessimistic: 12 cycles for both 0.95
and 1.00) the curve jumps at that N; the inverse gives the smallest N that reaches p.

Below the lowest SCR observed (0.33, Table 3.4) the high-clutter curve is stretched along the
cycles axis so that its 50 % point grows as ``2.5 · (SCR / 0.33)^(−α)``,
``α = ln(2.5/1.0) / ln(1/0.33) ≈ 0.83``: the slope between the medium-clutter 50 % point
(1.0 cycle at SCR = 1) and the high-clutter one (2.5 cycles at SCR = 0.33), continued. The
thesis's words: "for high clutter levels a strong increase in resolution is needed even for a
little decrease in SCR" (§3.7).
It makes ``P → 0`` as ``SCR → 0`` (no contrast left against the clutter) and leaves every printed
point as it is. This continuation is this project's; see :func:`clutter_n50`.

Scaling by the criterion: the table transforms carry their own 50 % points ``N50_ref`` (C2NVEO:
the ``c2nveo`` criterion, the geometric mean of the 0.50 row; Schmieder–Weathersby: the
medium-clutter 50 % point, 1.0 cycle). A criterion with another ``N50`` stretches the cycles axis:
``P(N) = table(N · N50_ref / N50)``. With their own criterion the printed tables are reproduced;
with Johnson's detection N50 (1.0) the Schmieder–Weathersby table is reproduced too, consistent
with Johnson's trials having been made "in significant clutter" (§3.6).
"""

from __future__ import annotations

import functools
import itertools
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import numpy as np

from targetacq.acquisition import observed_detection as _observed
from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.base.registry import lookup
from targetacq.base.tables import load_table

__all__ = [
    "C2NVEO_BOUNDS",
    "CLUTTER_REGIONS",
    "TRANSFORMS",
    "Transform",
    "c2nveo",
    "c2nveo_inverse",
    "clutter_n50",
    "clutter_region",
    "inverse_transform",
    "schmieder_weathersby",
    "schmieder_weathersby_inverse",
    "transform",
    "ttp_transform",
    "ttp_transform_inverse",
    "ttpf",
    "ttpf_inverse",
]

C2NVEO_BOUNDS: tuple[str, ...] = ("optimistic", "nominal", "pessimistic")
"""Which end of each Table 3.3 cell: low end, geometric mean, high end."""

CLUTTER_REGIONS: tuple[str, ...] = ("low", "medium", "high")
"""Table 3.5 clutter regions: SCR > 10, 1 <= SCR <= 10, SCR < 1."""

# TTPF exponent E = TTPF_E0 + TTPF_E1 · N/N50 (ACQUIRE / NVTherm).
TTPF_E0 = 2.7
TTPF_E1 = 0.7

# TTPF exponent of the TTP metric, E = TTP_E0 + TTP_E1 · V/V50 (Vollmerhausen, Jacobs & Driggers
# 2004).
TTP_E0 = 1.51
TTP_E1 = 0.24

# Beyond exp(±700) float64 over/underflows; the logistic is then 0 or 1 to double precision.
LOGIT_LIMIT = 700.0


# --------------------------------------------------------------------------------------------
# TTPF
# --------------------------------------------------------------------------------------------


def _ttpf(x: Array, xp: Any, e0: float = TTPF_E0, e1: float = TTPF_E1) -> Array:
    """TTPF of x = N/N50 >= 0 (or NaN), as the logistic of E·ln x, without warnings."""
    positive = x > 0
    log_x = xp.log(xp.where(positive | xp.isnan(x), x, 1.0))
    z = xp.clip((e0 + e1 * x) * log_x, -LOGIT_LIMIT, LOGIT_LIMIT)
    p = 1.0 / (1.0 + xp.exp(-z))
    return xp.where(x == 0, 0.0, p)


def _ttpf_inverse(p: Array, xp: Any, e0: float = TTPF_E0, e1: float = TTPF_E1) -> Array:
    """x = N/N50 with TTPF(x) = p, for p in (0, 1) (or NaN), by safeguarded Newton in ln x.

    Solves ``h(u) = (E0 + E1 e^u) u = L`` with ``L = logit(p)``. ``h`` is increasing
    (``h'(u) = E0 + E1 e^u (1 + u) > 0`` for all u, its minimum being at u = -2), and
    ``E = E0 + E1 x`` lies in [E0, E0 + E1] for x <= 1 and above E0 + E1 for x > 1, so the
    root lies in [L/E0, L/(E0+E1)] when L <= 0 and in [0, L/(E0+E1)] when L > 0.
    """
    logit = xp.log(p) - xp.log1p(-p)
    negative = logit <= 0
    lo = xp.where(negative, logit / e0, 0.0)
    hi = logit / (e0 + e1)
    u = 0.5 * (lo + hi)
    for _ in range(100):
        e_u = xp.exp(u)
        residual = (e0 + e1 * e_u) * u - logit
        lo = xp.where(residual < 0, u, lo)
        hi = xp.where(residual > 0, u, hi)
        slope = e0 + e1 * e_u * (1.0 + u)
        candidate = u - residual / slope
        outside = (candidate < lo) | (candidate > hi)
        candidate = xp.where(outside, 0.5 * (lo + hi), candidate)
        step = xp.abs(candidate - u)
        u = candidate
        if not bool(xp.any(step > 4e-16 * (1.0 + xp.abs(u)))):
            break
    return xp.exp(u)


def ttpf(cycles: Array, n50: Array) -> Any:
    """Target transfer probability function.

    ``P = x^E / (1 + x^E)`` with ``x = N / N50`` and ``E = 2.7 + 0.7 x``, the Johnson-based
    target transfer probability function of the NVESD models ACQUIRE and NVTherm (e.g.
    Driggers, Cox & Edwards, *Introduction to Infrared and Electro-Optical Systems*, ch. 12).
    It gives ``P(N50) = 0.5``, the meaning of Johnson's table values (Sonesson 2004, §3.5).

    Parameters
    ----------
    cycles : array_like
        N, resolvable cycles across the critical dimension [cycles], >= 0.
    n50 : array_like
        Cycles for a probability of 0.5 [cycles], > 0.

    Returns
    -------
    array_like
        P in [0, 1]; NaN where ``cycles`` is NaN.

    Examples
    --------
    Recognition by Johnson's N50 of 4 cycles, at a quarter, one and two times N50. At twice
    N50, ``x = 2`` and ``E = 2.7 + 1.4``, so ``P = 2^4.1 / (1 + 2^4.1) = 0.9449``:

    >>> import numpy as np
    >>> import targetacq as ta
    >>> print(np.round(ta.ttpf([1.0, 4.0, 8.0], 4.0), 4))
    [0.0182 0.5    0.9449]
    """
    xp, (n, n50_) = _arrays.arrays(cycles, n50, names=("cycles", "n50"))
    _arrays.require_nonnegative("cycles", n, xp)
    _arrays.require_positive("n50", n50_, xp)
    return _arrays.result(_ttpf(n / n50_, xp))


def ttpf_inverse(probability: Array, n50: Array) -> Any:
    """Cycles at which the TTPF reaches a probability (inverse of :func:`ttpf`).

    Parameters
    ----------
    probability : array_like
        P in the open interval (0, 1).
    n50 : array_like
        [cycles], > 0.

    Returns
    -------
    array_like
        N [cycles].

    Examples
    --------
    The cycles for 50 % are N50 itself; for 80 %, a little under 1.5 N50 (and back again):

    >>> import targetacq as ta
    >>> print(f"{ta.ttpf_inverse(0.5, 4.0):.4f}")
    4.0000
    >>> n = ta.ttpf_inverse(0.8, 4.0)
    >>> print(f"{n:.4f} {ta.ttpf(n, 4.0):.4f}")
    5.8084 0.8000
    """
    xp, (p, n50_) = _arrays.arrays(probability, n50, names=("probability", "n50"))
    _arrays.require_open_unit_interval("probability", p, xp)
    _arrays.require_positive("n50", n50_, xp)
    return _arrays.result(_ttpf_inverse(p, xp) * n50_)


def ttp_transform(cycles: Array, v50: Array) -> Any:
    """Target transfer probability function of the TTP metric.

    ``P = x^E / (1 + x^E)`` with ``x = V / V50`` and ``E = 1.51 + 0.24 x``: the TTPF that goes with
    the targeting task performance metric's resolvable cycles ``V``
    (:func:`targetacq.physics.ttp.ttp_cycles`), fitted to the NVESD identification experiments
    (R. H. Vollmerhausen, E. Jacobs and R. G. Driggers, "New metric for predicting target
    acquisition performance", Opt. Eng. 43(11) (2004) 2806; Vollmerhausen & Jacobs, NVESD
    report AMSEL-NV-TR-230 (2004)). Its slope is lower than the Johnson TTPF's
    (:func:`ttpf`, ``E = 2.7 + 0.7 x``); ``P(V50) = 0.5`` likewise.

    Parameters
    ----------
    cycles : array_like
        V, TTP cycles on target [cycles], >= 0.
    v50 : array_like
        V for a probability of 0.5 [cycles], > 0 (the ``ttp-vehicles`` criterion).

    Returns
    -------
    array_like
        P in [0, 1]; NaN where ``cycles`` is NaN.

    Examples
    --------
    At twice V50, ``E = 1.51 + 0.48 = 1.99`` and ``P = 2^1.99 / (1 + 2^1.99) = 0.7989``:

    >>> import numpy as np
    >>> print(np.round(ttp_transform([10.0, 20.0, 40.0], 20.0), 4))
    [0.2442 0.5    0.7989]
    """
    xp, (v, v50_) = _arrays.arrays(cycles, v50, names=("cycles", "v50"))
    _arrays.require_nonnegative("cycles", v, xp)
    _arrays.require_positive("v50", v50_, xp)
    return _arrays.result(_ttpf(v / v50_, xp, TTP_E0, TTP_E1))


def ttp_transform_inverse(probability: Array, v50: Array) -> Any:
    """V at which the TTP metric's TTPF reaches a probability (inverse of :func:`ttp_transform`).

    Examples
    --------
    >>> v = ttp_transform_inverse(0.8, 20.0)
    >>> print(f"{v:.4f} {ttp_transform(v, 20.0):.4f}")
    40.1194 0.8000
    """
    xp, (p, v50_) = _arrays.arrays(probability, v50, names=("probability", "v50"))
    _arrays.require_open_unit_interval("probability", p, xp)
    _arrays.require_positive("v50", v50_, xp)
    return _arrays.result(_ttpf_inverse(p, xp, TTP_E0, TTP_E1) * v50_)


# --------------------------------------------------------------------------------------------
# Table curves (C2NVEO, Schmieder–Weathersby)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class _Curve:
    """A monotone curve through printed points (N_i > 0 ascending, P_i non-decreasing)."""

    cycles: tuple[float, ...]
    probabilities: tuple[float, ...]

    @classmethod
    def from_table(cls, cycles: tuple[float, ...], probabilities: tuple[float, ...]) -> _Curve:
        points = sorted(
            (n, p)
            for n, p in zip(cycles, probabilities, strict=True)
            if not math.isnan(n) and n > 0
        )
        ns, ps = zip(*points, strict=True)
        if any(b < a for a, b in itertools.pairwise(ps)):
            raise ValueError(f"table curve is not monotone: {points}")
        return cls(tuple(ns), tuple(ps))

    @functools.cached_property
    def _strict(self) -> bool:
        return all(b > a for a, b in itertools.pairwise(self.cycles))

    @functools.cached_property
    def _log_cycles(self) -> np.ndarray:
        return np.log(self.cycles)

    def forward(self, n: Array, xp: Any, log_n: Array = None) -> Array:
        """P at N; ``log_n``, NumPy only, is ``log(n)`` where the caller has it already."""
        ns, ps = self.cycles, self.probabilities
        if isinstance(n, np.ndarray) and self._strict:
            # NumPy fast path: the same piecewise-linear curve in log N by np.interp.
            if log_n is None:
                with np.errstate(divide="ignore"):
                    log_n = np.log(n)
            out = np.interp(log_n, self._log_cycles, ps)
            below = n < ns[0]
            if out.ndim and not below.any():
                return out
            return np.where(below, ps[0] * n / ns[0], out)
        u = xp.log(xp.where(n > 0, xp.minimum(n, ns[-1]), 1.0))  # segments only: no inf · 0
        out = xp.where(n >= ns[-1], ps[-1], xp.zeros_like(n))
        out = xp.where(n < ns[0], ps[0] * n / ns[0], out)
        for k in range(len(ns) - 1):
            if ns[k + 1] == ns[k]:
                continue  # a vertical step: the higher probability holds from that N on
            lo, width = math.log(ns[k]), math.log(ns[k + 1]) - math.log(ns[k])
            segment = ps[k] + (u - lo) / width * (ps[k + 1] - ps[k])
            out = xp.where((n >= ns[k]) & (n < ns[k + 1]), segment, out)
        return xp.where(xp.isnan(n), n, out)

    def inverse(self, p: Array, xp: Any) -> Array:
        """Smallest N with P(N) >= p; +inf where p exceeds the curve's last probability."""
        ns, ps = self.cycles, self.probabilities
        out = xp.where(p > ps[-1], xp.inf, xp.zeros_like(p))
        out = xp.where(p <= ps[0], ns[0] * p / ps[0], out)
        for k in range(len(ns) - 1):
            if ps[k + 1] == ps[k]:
                continue
            lo, width = math.log(ns[k]), math.log(ns[k + 1]) - math.log(ns[k])
            segment = xp.exp(lo + (p - ps[k]) / (ps[k + 1] - ps[k]) * width)
            out = xp.where((p > ps[k]) & (p <= ps[k + 1]), segment, out)
        return xp.where(xp.isnan(p), p, out)


@functools.cache
def c2nveo_curves() -> Mapping[tuple[str, str], _Curve]:
    table = load_table("c2nveo")
    p = table.numbers("probability")
    curves = {}
    for task in ("detection", "recognition", "identification"):
        low, high = table.numbers(f"{task}_low"), table.numbers(f"{task}_high")
        nominal = tuple(math.sqrt(a * b) for a, b in zip(low, high, strict=True))
        for bound, ns in zip(C2NVEO_BOUNDS, (low, nominal, high), strict=True):
            curves[task, bound] = _Curve.from_table(ns, p)
    return MappingProxyType(curves)


@functools.cache
def c2nveo_reference_n50(task: str) -> float:
    # The nominal curve's 50 % point: the geometric mean of the 0.50 row (the c2nveo criterion).
    return float(c2nveo_curves()[task, "nominal"].inverse(_arrays.as_float(0.5, _np()), _np()))


@functools.cache
def sw_curves() -> Mapping[str, _Curve]:
    table = load_table("schmieder_weathersby")
    p = table.numbers("probability")
    return MappingProxyType(
        {region: _Curve.from_table(table.numbers(region), p) for region in CLUTTER_REGIONS}
    )


@functools.cache
def sw_reference_n50() -> float:
    return float(sw_curves()["medium"].inverse(_arrays.as_float(0.5, _np()), _np()))


def _np() -> Any:
    return _arrays.namespace()


def _check_task(name: str, task: str, tasks: tuple[str, ...]) -> None:
    if task not in tasks:
        raise ValueError(
            f"transform {name!r} has no curve for task {task!r}; its tasks: {', '.join(tasks)}"
        )


def _check_bound(bound: str) -> None:
    if bound not in C2NVEO_BOUNDS:
        raise ValueError(f"bound must be one of {', '.join(C2NVEO_BOUNDS)}; got {bound!r}")


_C2NVEO_TASKS = ("detection", "recognition", "identification")


def c2nveo(cycles: Array, n50: Array, task: str = "detection", bound: str = "nominal") -> Any:
    """C2NVEO probability of a task from cycles on target, Table 3.3 in Sonesson (2004).

    Parameters
    ----------
    cycles : array_like
        N [cycles], >= 0.
    n50 : array_like
        The criterion's 50 % point for the task [cycles], > 0. The table's own is
        ``CRITERIA["c2nveo"].n50(task)``; another N50 stretches the cycles axis (module doc).
    task : {"detection", "recognition", "identification"}
    bound : {"optimistic", "nominal", "pessimistic"}
        Low end, geometric mean or high end of each printed cell.

    Returns
    -------
    array_like
        P in [0, 1]: 0 at N = 0, 1 from the 1.00 row on.

    Examples
    --------
    With the table's own 50 % points (the ``c2nveo`` criterion) the printed cells of Table 3.3
    come back: 0.75 cycles give 0.80 for detection on the optimistic curve, 4.5 cycles 0.80 for
    recognition.

    >>> import targetacq as ta
    >>> n50 = ta.CRITERIA["c2nveo"].thresholds
    >>> print(f"{ta.c2nveo(0.75, n50['detection'], bound='optimistic'):.2f}")
    0.80
    >>> print(f"{ta.c2nveo(4.5, n50['recognition'], 'recognition', bound='optimistic'):.2f}")
    0.80
    """
    _check_task("c2nveo", task, _C2NVEO_TASKS)
    _check_bound(bound)
    xp, (n, n50_) = _arrays.arrays(cycles, n50, names=("cycles", "n50"))
    _arrays.require_nonnegative("cycles", n, xp)
    _arrays.require_positive("n50", n50_, xp)
    scaled = n * (c2nveo_reference_n50(task) / n50_)
    return _arrays.result(c2nveo_curves()[task, bound].forward(scaled, xp))


def c2nveo_inverse(
    probability: Any, n50: Any, task: str = "detection", bound: str = "nominal"
) -> Any:
    """Cycles needed for a probability on the C2NVEO curve (inverse of :func:`c2nveo`).

    Returns the smallest N whose probability reaches ``probability`` in (0, 1).

    Examples
    --------
    Table 3.3's pessimistic recognition cell at P = 0.80 is 6 cycles:

    >>> import targetacq as ta
    >>> n50 = ta.CRITERIA["c2nveo"].thresholds["recognition"]
    >>> print(f"{ta.c2nveo_inverse(0.8, n50, 'recognition', bound='pessimistic'):.4f}")
    6.0000
    """
    _check_task("c2nveo", task, _C2NVEO_TASKS)
    _check_bound(bound)
    xp, (p, n50_) = _arrays.arrays(probability, n50, names=("probability", "n50"))
    _arrays.require_open_unit_interval("probability", p, xp)
    _arrays.require_positive("n50", n50_, xp)
    n = c2nveo_curves()[task, bound].inverse(p, xp)
    return _arrays.result(n * (n50_ / c2nveo_reference_n50(task)))


def clutter_region(scr: Array) -> Any:
    """Clutter region of Table 3.5 for a signal-to-clutter ratio.

    Parameters
    ----------
    scr : array_like
        SCR [1], >= 0 (+inf for no clutter).

    Returns
    -------
    numpy.ndarray of str or str
        "low" (SCR > 10), "medium" (1 <= SCR <= 10) or "high" (SCR < 1); "" for NaN.

    Examples
    --------
    >>> import targetacq as ta
    >>> [str(r) for r in ta.clutter_region([0.5, 3.0, 20.0])]
    ['high', 'medium', 'low']
    """
    s = np.asarray(_arrays.as_float(scr, _np(), "scr"))
    _arrays.require_nonnegative("scr", s, _np())
    region = np.select([s > 10, s >= 1, s < 1], ["low", "medium", "high"], default="")
    return region[()] if region.ndim == 0 else region


@functools.cache
def sw_high_anchor() -> tuple[float, float, float]:
    """(lowest observed SCR, high-clutter N50, exponent α) of the continuation (module doc)."""
    observed = load_table("schmieder_weathersby_observed").numbers("scr")
    scr_low = min(observed)
    high_n50 = float(sw_curves()["high"].inverse(_arrays.as_float(0.5, _np()), _np()))
    medium_n50 = sw_reference_n50()  # at the medium / high boundary, SCR = 1
    return scr_low, high_n50, math.log(high_n50 / medium_n50) / math.log(1.0 / scr_low)


def _sw_stretch(scr: Array, xp: Any) -> Array:
    """Cycles-axis multiplier in (0, 1]: 1 for SCR >= 0.33, (SCR/0.33)^α below (module doc)."""
    scr_low, _, alpha = sw_high_anchor()
    below = scr < scr_low
    ratio = xp.where(below, scr, scr_low) / scr_low
    return xp.where(below, ratio**alpha, xp.ones_like(scr))


@functools.cache
def sw_region_n50() -> Mapping[str, float]:
    """The 50 % point of each Table 3.5 region's curve [cycles] (computed once)."""
    half = _arrays.as_float(0.5, _np())
    return MappingProxyType(
        {name: float(curve.inverse(half, _np())) for name, curve in sw_curves().items()}
    )


def clutter_n50(scr: Array) -> Any:
    """Cycles for P(detection) = 0.5 at a signal-to-clutter ratio, Table 3.5 and its continuation.

    0.5 cycles for SCR > 10, 1.0 for 1 <= SCR <= 10, 2.5 for 0.33 <= SCR < 1 (Table 3.5's
    50 % row by region), and ``2.5 · (SCR/0.33)^(−α)`` below the lowest observed SCR (module doc),
    growing without bound as SCR → 0.

    Parameters
    ----------
    scr : array_like
        SCR [1], >= 0 (+inf: no clutter).

    Returns
    -------
    array_like
        N50 [cycles] of the Schmieder–Weathersby detection curve with Johnson's scaling.

    Examples
    --------
    Table 3.5's 50 % points at the anchors — 0.5 (low clutter, SCR ≥ 10), 1.0 (SCR 1), 2.5
    (SCR 0.33) — the log-SCR blend between them, and the continuation below 0.33:

    >>> from targetacq.acquisition.transforms import clutter_n50
    >>> print([round(float(x), 4) for x in clutter_n50([20.0, 10.0, 1.0, 0.33, 0.1])])
    [0.5, 0.5, 1.0, 2.5, 6.7063]
    """
    xp, (s,) = _arrays.arrays(scr, names=("scr",))
    _arrays.require_nonnegative("scr", s, xp)
    n50 = {name: xp.full_like(s, value) for name, value in sw_region_n50().items()}
    base = _sw_select(n50, s, None, xp)
    stretch = _sw_stretch(s, xp)
    safe = xp.where(stretch > 0, stretch, 1.0)
    return _arrays.result(xp.where(stretch > 0, base / safe, xp.inf))


def _sw_options(
    scr: Any, region: str | None, hot_spot: bool, moving: bool, xp: Any
) -> Array | None:
    """The SCR array to pick curves by (None when one fixed region applies)."""
    if region is not None and region not in CLUTTER_REGIONS:
        raise ValueError(f"region must be one of {', '.join(CLUTTER_REGIONS)}; got {region!r}")
    if scr is not None and region is not None:
        raise ValueError("give either scr or region for schmieder-weathersby, not both")
    if scr is None and region is None and not hot_spot and not moving:
        raise ValueError(
            "schmieder-weathersby needs the clutter: a signal-to-clutter ratio (scr), "
            "a clutter region (low, medium, high), a hot spot or a moving target"
        )
    if scr is None:
        return None
    s = _arrays.as_float(scr, xp, "scr")
    _arrays.require_nonnegative("scr", s, xp)
    return s


def check_clutter(scr: Any, region: str | None, xp: Any) -> None:
    """Raise ``ValueError`` for a clutter region not in Table 3.5, both ``scr`` and ``region``,
    or a negative SCR."""
    if region is not None and region not in CLUTTER_REGIONS:
        raise ValueError(f"region must be one of {', '.join(CLUTTER_REGIONS)}; got {region!r}")
    if scr is not None and region is not None:
        raise ValueError("give either scr or region for schmieder-weathersby, not both")
    if scr is not None:
        _arrays.require_nonnegative("scr", _arrays.as_float(scr, xp, "scr"), xp)


def _sw_select(
    values: Mapping[str, Array], scr: Array | None, region: str | None, xp: Any
) -> Array:
    """The region's curve, or with an SCR the curves blended continuously in ``log SCR``.

    Anchors: the low-clutter curve for SCR >= 10, the medium-clutter curve at SCR = 1 and the
    high-clutter curve at SCR <= 0.33 (the lowest SCR observed, Table 3.4), the lower edges of
    Table 3.5's regions; between two anchors the probability is interpolated linearly in
    ``log SCR`` (module docstring).
    """
    if scr is None:
        return values[region or "low"]
    scr_low = sw_high_anchor()[0]
    if isinstance(scr, np.ndarray):
        return _sw_select_numpy(values, scr, scr_low)
    safe = xp.where(scr > 0, scr, scr_low)
    upper = xp.minimum(xp.maximum(xp.log10(xp.where(safe >= 1.0, safe, 1.0)), 0.0), 1.0)
    lower = xp.minimum(
        xp.maximum(
            xp.log(xp.where(safe < 1.0, safe, 1.0) / scr_low) / math.log(1.0 / scr_low), 0.0
        ),
        1.0,
    )
    above = values["medium"] + upper * (values["low"] - values["medium"])
    below = values["high"] + lower * (values["medium"] - values["high"])
    out = xp.where(scr >= 1.0, above, below)
    return xp.where(xp.isnan(scr), scr, out)


def _sw_select_numpy(values: Mapping[str, Array], scr: np.ndarray, scr_low: float) -> Array:
    """:func:`_sw_select` for NumPy: the same arithmetic, each side computed only where an SCR
    needs it (``values`` may then hold only the curves of that side)."""
    above = scr >= 1.0
    all_above = bool(above.all())
    none_above = not all_above and not above.any()
    if not none_above:
        upper = np.log10(np.where(scr >= 1.0, scr, 1.0) if not all_above else scr)
        upper = np.minimum(np.maximum(upper, 0.0), 1.0)
        medium = values["medium"]
        upper = medium + upper * (values["low"] - medium)
        if all_above:
            return upper
    safe = np.where(scr > 0, scr, scr_low)
    lower = np.log(np.where(safe < 1.0, safe, 1.0) / scr_low) / math.log(1.0 / scr_low)
    lower = np.minimum(np.maximum(lower, 0.0), 1.0)
    high = values["high"]
    lower = high + lower * (values["medium"] - high)
    out = lower if none_above else np.where(above, upper, lower)
    unknown = np.isnan(scr)
    return np.where(unknown, scr, out) if unknown.any() else out


def schmieder_weathersby(
    cycles: Array,
    n50: Array = 1.0,
    *,
    scr: Array = None,
    region: str | None = None,
    hot_spot: bool = False,
    moving: bool = False,
) -> Any:
    """Probability of detection in clutter, Table 3.5 in Sonesson (2004) (Schmieder–Weathersby).

    Parameters
    ----------
    cycles : array_like
        N [cycles], >= 0.
    n50 : array_like, optional
        The criterion's detection N50 [cycles], > 0; the table's own (and Johnson's) is 1.0.
    scr : array_like, optional
        Signal-to-clutter ratio [1], >= 0; picks the region per element (broadcasts with N).
    region : {"low", "medium", "high"}, optional
        The clutter region, instead of ``scr``.
    hot_spot : bool
        A strong source on a uniform background: the low-clutter curve (§3.9).
    moving : bool
        A moving target is always detected (P = 1), §1.3 and §7.5.

    Returns
    -------
    array_like
        P(detection) in [0, 1].

    Examples
    --------
    Table 3.5 in high clutter: 1.0 cycle gives 0.02 and 2.5 cycles 0.50; at 1.0 cycle the three
    regions give 0.02, 0.50 and 0.95, and an SCR at each region's anchor (0.33, 1 and 10) gives
    the same:

    >>> import numpy as np
    >>> import targetacq as ta
    >>> print(np.round(ta.schmieder_weathersby([1.0, 2.5], region="high"), 4))
    [0.02 0.5 ]
    >>> regions = ("high", "medium", "low")
    >>> print([round(float(ta.schmieder_weathersby(1.0, region=r)), 4) for r in regions])
    [0.02, 0.5, 0.95]
    >>> print(np.round(ta.schmieder_weathersby(1.0, scr=[0.33, 1.0, 10.0]), 4))
    [0.02 0.5  0.95]
    """
    xp, (n, n50_) = _arrays.arrays(cycles, n50, names=("cycles", "n50"))
    _arrays.require_nonnegative("cycles", n, xp)
    _arrays.require_positive("n50", n50_, xp)
    s = _sw_options(scr, region, hot_spot, moving, xp)
    if moving:
        return _arrays.result(xp.where(xp.isnan(n), n, xp.ones_like(n)))
    if hot_spot:
        return _arrays.result(sw_probability(n, n50_, None, "low", xp))
    return _arrays.result(sw_probability(n, n50_, s, region, xp))


def sw_probability(n: Array, n50: Any, scr: Array | None, region: str | None, xp: Any) -> Array:
    """:func:`schmieder_weathersby` of checked arrays: the region's curve (default low), or with
    an SCR array the stretched curves blended in ``log SCR`` (:func:`_sw_select`).

    The arithmetic kernel. NumPy evaluates only the curves the SCRs need, with ``log N`` taken
    once for them; the numbers are the same.
    """
    scaled = n * (sw_reference_n50() / n50)
    curves = sw_curves()
    if scr is None:
        return curves[region or "low"].forward(scaled, xp)
    if not isinstance(scaled, np.ndarray) or scaled.ndim == 0:
        scaled = scaled * _sw_stretch(scr, xp)
        values = {name: curve.forward(scaled, xp) for name, curve in curves.items()}
        return _sw_select(values, scr, None, xp)
    scr = np.asarray(scr)
    below = scr < sw_high_anchor()[0]
    if below.any():  # the stretch is 1 elsewhere: scaled · 1 is scaled
        scaled = scaled * _sw_stretch(scr, xp)
    with np.errstate(divide="ignore"):
        log_n = np.log(scaled)
    above = scr >= 1.0
    # The curves the blend reads: low and medium at SCR >= 1, medium and high below.
    wanted = ("low", "medium") if above.all() else CLUTTER_REGIONS
    if not above.any() and not np.isnan(scr).any():
        wanted = ("medium", "high")
    values = {name: curves[name].forward(scaled, np, log_n) for name in wanted}
    return _sw_select(values, scr, None, np)


def schmieder_weathersby_inverse(
    probability: Any,
    n50: Any = 1.0,
    *,
    scr: Any = None,
    region: str | None = None,
    hot_spot: bool = False,
    moving: bool = False,
) -> Any:
    """Cycles needed for a probability of detection in clutter (inverse of
    :func:`schmieder_weathersby`): the smallest N with ``P(N) >= p``; +inf where the curve
    never reaches it (high clutter above 0.9); 0 for a moving target. With an SCR (curves
    blended in ``log SCR``) it is found by bisection in ``log N`` to 1e-12 relative.

    Examples
    --------
    Table 3.5: 2.5 cycles for 50 % in high clutter, 1.7 cycles for 90 % in medium clutter.

    >>> import targetacq as ta
    >>> print(f"{ta.schmieder_weathersby_inverse(0.5, region='high'):.4f}")
    2.5000
    >>> print(f"{ta.schmieder_weathersby_inverse(0.9, region='medium'):.4f}")
    1.7000
    """
    xp, (p, n50_) = _arrays.arrays(probability, n50, names=("probability", "n50"))
    _arrays.require_open_unit_interval("probability", p, xp)
    _arrays.require_positive("n50", n50_, xp)
    s = _sw_options(scr, region, hot_spot, moving, xp)
    scale = n50_ / sw_reference_n50()
    if moving:
        return _arrays.result(xp.where(xp.isnan(p), p, xp.zeros_like(p)) * scale)
    if hot_spot:
        return _arrays.result(sw_curves()["low"].inverse(p, xp) * scale)
    if s is None:
        return _arrays.result(sw_curves()[region or "low"].inverse(p, xp) * scale)
    p, s = xp.broadcast_arrays(p, s)
    stretch = _sw_stretch(s, xp)
    curves = sw_curves()
    top = _sw_select(
        {name: xp.full_like(s, c.probabilities[-1]) for name, c in curves.items()}, s, None, xp
    )
    # Bracket [lo, hi] in ln N on the unstretched axis: every curve is below p at lo (linear
    # from 0) and at its last value from the largest printed N on.
    lo = xp.full_like(p, math.log(1e-9))
    hi = xp.full_like(p, math.log(max(c.cycles[-1] for c in curves.values())))
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        n_mid = xp.exp(mid)
        values = {name: curve.forward(n_mid, xp) for name, curve in curves.items()}
        ok = _sw_select(values, s, None, xp) >= p
        lo, hi = xp.where(ok, lo, mid), xp.where(ok, mid, hi)
    needed = xp.exp(hi) * scale
    needed = xp.where(p > top, xp.inf, needed)
    needed = xp.where(stretch > 0, needed / xp.where(stretch > 0, stretch, 1.0), xp.inf)
    return _arrays.result(xp.where(xp.isnan(p) | xp.isnan(s), xp.nan, needed))


# --------------------------------------------------------------------------------------------
# Registry and dispatcher
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Transform:
    """A resolution-to-probability transform in the registry.

    Attributes
    ----------
    name : str
    forward : callable
        ``forward(cycles, n50, task, **options) -> probability``.
    inverse : callable
        ``inverse(probability, n50, task, **options) -> cycles``.
    tasks : tuple of str or None
        Tasks the transform has curves for (None: any task with an N50).
    options : Mapping[str, object]
        Keyword options it takes, with their defaults.
    source : str
    """

    name: str
    forward: Callable[..., Any]
    inverse: Callable[..., Any]
    tasks: tuple[str, ...] | None
    options: Mapping[str, object]
    source: str

    def check(self, task: str, options: Mapping[str, object]) -> None:
        """Raise ``ValueError`` for a task it has no curve for or an option it does not take."""
        if self.tasks is not None:
            _check_task(self.name, task, self.tasks)
        unknown = sorted(set(options) - set(self.options))
        if unknown:
            valid = ", ".join(self.options) or "none"
            clutter = sorted(set(unknown) & {"scr", "region", "hot_spot", "moving"})
            hint = f" ({', '.join(clutter)}: give clutter=Clutter(...) instead)" if clutter else ""
            raise ValueError(
                f"transform {self.name!r} takes no option(s) {', '.join(unknown)}; "
                f"its options: {valid}{hint}"
            )


def _ttpf_forward(cycles: Any, n50: Any, task: str) -> Any:
    return ttpf(cycles, n50)


def _ttpf_backward(probability: Any, n50: Any, task: str) -> Any:
    return ttpf_inverse(probability, n50)


def _ttp_forward(cycles: Any, v50: Any, task: str) -> Any:
    return ttp_transform(cycles, v50)


def _ttp_backward(probability: Any, v50: Any, task: str) -> Any:
    return ttp_transform_inverse(probability, v50)


def _sw_forward(cycles: Any, n50: Any, task: str, **options: Any) -> Any:
    return schmieder_weathersby(cycles, n50, **options)


def _sw_backward(probability: Any, n50: Any, task: str, **options: Any) -> Any:
    return schmieder_weathersby_inverse(probability, n50, **options)


TRANSFORMS: Mapping[str, Transform] = MappingProxyType(
    {
        "ttpf": Transform(
            "ttpf",
            _ttpf_forward,
            _ttpf_backward,
            tasks=None,
            options=MappingProxyType({}),
            source="NVESD target transfer probability function (ACQUIRE, NVTherm)",
        ),
        "ttp": Transform(
            "ttp",
            _ttp_forward,
            _ttp_backward,
            tasks=None,
            options=MappingProxyType({}),
            source="TTPF of the TTP metric, E = 1.51 + 0.24 V/V50 (Vollmerhausen, Jacobs & "
            "Driggers, Opt. Eng. 43(11) 2004); with V from the ttp resolution model and V50s",
        ),
        "c2nveo": Transform(
            "c2nveo",
            c2nveo,
            c2nveo_inverse,
            tasks=_C2NVEO_TASKS,
            options=MappingProxyType({"bound": "nominal"}),
            source="Sonesson (2004) Table 3.3",
        ),
        "schmieder-weathersby": Transform(
            "schmieder-weathersby",
            _sw_forward,
            _sw_backward,
            tasks=("detection",),
            options=MappingProxyType(
                {"scr": None, "region": None, "hot_spot": False, "moving": False}
            ),
            source="Sonesson (2004) Table 3.5 (Schmieder & Weathersby 1983)",
        ),
        _observed.NAME: Transform(
            _observed.NAME,
            _observed.forward,
            _observed.inverse,
            tasks=("detection",),
            options=MappingProxyType({"scr": None}),
            source="Sonesson (2004) Table 3.4 (Schmieder & Weathersby 1983): a monotone fit "
            "through the observed points",
        ),
    }
)
"""All transforms, by name (read-only)."""


def get_transform(method: str | Transform) -> Transform:
    """Resolve a transform by name; ``ValueError`` listing the valid names if unknown."""
    if isinstance(method, Transform):
        return method
    return lookup(TRANSFORMS, method, "transform")


def transform(
    cycles: Array, n50: Array, task: str = "detection", method: str = "ttpf", **options: Any
) -> Any:
    """Probability of a task from cycles on target, by the named transform.

    Parameters
    ----------
    cycles : array_like
        N [cycles], >= 0.
    n50 : array_like
        The criterion's 50 % point for the task [cycles], > 0.
    task : str
        Observation task (some transforms cover only some tasks).
    method : str
        A name from :data:`TRANSFORMS`.
    **options
        The transform's own options (see ``TRANSFORMS[method].options``); any other keyword
        raises ``ValueError``.

    Examples
    --------
    Recognition at its N50 by the TTPF, and detection at 1.7 cycles in medium clutter (Table 3.5:
    0.90):

    >>> import targetacq as ta
    >>> print(f"{ta.transform(4.0, 4.0, 'recognition'):.4f}")
    0.5000
    >>> print(f"{ta.transform(1.7, 1.0, 'detection', 'schmieder-weathersby', region='medium'):.4f}")
    0.9000
    """
    chosen = get_transform(method)
    chosen.check(task, options)
    return chosen.forward(cycles, n50, task, **options)


def inverse_transform(
    probability: Any, n50: Any, task: str = "detection", method: str = "ttpf", **options: Any
) -> Any:
    """Cycles needed for a probability by the named transform (inverse of :func:`transform`).

    Examples
    --------
    Table 3.5 in low clutter: 0.75 cycles for a detection probability of 0.80.

    >>> import targetacq as ta
    >>> n = ta.inverse_transform(0.8, 1.0, "detection", "schmieder-weathersby", region="low")
    >>> print(f"{n:.4f}")
    0.7500
    """
    chosen = get_transform(method)
    chosen.check(task, options)
    return chosen.inverse(probability, n50, task, **options)
