"""Probability of detection from the observations of Table 3.4 in Sonesson (2004).

Table 3.4 in Sonesson (2004) (p. 22, from Schmieder & Weathersby 1983) prints the observed
probability of detection at seven resolutions N (0.25 to 6 cycles across the target) for four
signal-to-clutter ratios (SCR 0.33, 1.2, 5.8 and 39). This module is a monotone fit through
those observed points, ``P(N, SCR)``, meant to be set beside the binned curves of Table 3.5
(the ``schmieder-weathersby`` transform). The two differ most at low clutter: the observations
give 0.93 at 0.25 cycles and 0.96 at 0.5 cycles for SCR 39, where Table 3.5's low-clutter curve
gives about 0.25 and 0.5.

The fit is this project's; its assumptions, each with its reason:

1. **Each SCR row is a curve in N.** ``P = 0`` at ``N = 0``; linear in ``N`` from there to the
   row's first observed point; linear in ``log N`` between observed points; held at the last
   observed probability beyond the last observed point. This is how the project reads every
   printed table of cycles (the thesis plots such curves on a logarithmic cycles axis, Figs.
   3.5 and 3.7), and holding the last value is the least the data say. A cell printed "–" is
   not an observation and is skipped: the SCR 39 row, observed up to 2 cycles, is held at 1.0
   beyond; the other rows, first observed at 0.5 cycles, rise linearly from ``P = 0`` at
   ``N = 0``. At SCR 0.33 that first point is itself 0, so ``P = 0`` up to 1 cycle.
2. **Monotone in N.** A row that falls somewhere with N is replaced by its running maximum
   along ascending N (never lowering an observation, only raising the later, lower cells to
   the earlier value). Table 3.4's rows are already non-decreasing in N: this step changes no
   cell.
3. **Ordered in SCR.** More contrast against the clutter should never make detection harder,
   but the observations break this: at 2 cycles SCR 5.8 gives 0.95 and SCR 1.2 gives 0.96. At
   each N the row curves of steps 1 and 2 are replaced by their running maximum over ascending
   SCR (pointwise at every N, not only at the printed N). The reversal is read as observation
   scatter (a difference of 0.01 in a detection rate), not as an effect of clutter. This changes
   one observed cell, **SCR 5.8, N = 2.0: 0.95 → 0.96** (the SCR 1.2 value), and between the
   printed N the SCR 5.8 curve follows the SCR 1.2 curve from 2^(41/42) ≈ 1.967 to
   2 · 1.5^(1/3) ≈ 2.289 cycles, where the two cross. Every other printed cell is kept;
   :func:`adjusted_cells` lists the changes.
4. **Between and outside the rows.** Between two rows ``P`` is linear in ``log SCR`` (the SCRs
   are spread over two decades, roughly evenly in ``log SCR``). Outside [0.33, 39] the SCR is
   clamped: an SCR below 0.33 is treated as 0.33, above 39 as 39, because the data say nothing
   there. (``schmieder-weathersby`` instead continues its high-clutter curve so that
   ``P → 0`` as ``SCR → 0``; this fit extrapolates nothing.)
5. **Scaling by the criterion.** As the ``schmieder-weathersby`` transform does,
   ``P(N) = fit(N · 1.0 / N50)``: the table's reference N50 is Johnson's detection N50,
   1.0 cycle. With ``n50 = 1.0`` the observations are reproduced.
6. **Inverse.** The smallest N with ``P(N) >= p``; +inf where the curve never reaches p (it
   tops out at 0.84 at SCR 0.33). Below the first observed N of any row (0.25 cycles) every
   row curve is linear in N, so there the inverse is exact; above, it is a bisection in
   ``log N`` (64 halvings, down to the spacing of doubles), so that the forward of the inverse
   is p to about 1e-15.

Since steps 2 and 3 are running maxima of continuous non-decreasing curves and step 4 takes
convex combinations of them, the fit is continuous, non-decreasing in N and in SCR, and lies
in [0, 1]. The kernels are array-API generic (NumPy, array_api_strict, JAX, ...) like the
other transforms.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.base.tables import load_table

__all__ = [
    "NAME",
    "adjusted_cells",
    "forward",
    "inverse",
    "observed_detection",
    "observed_detection_inverse",
]

NAME = "schmieder-weathersby-observed"
"""The name of this transform in the transforms registry."""

_TABLE = "schmieder_weathersby_observed"
_REFERENCE_N50 = 1.0  # [cycles] Johnson's detection N50, the table's reference (module doc, 5)
_BISECTIONS = 64  # halvings of [log 0.25, log 6]: width 3.2 / 2^64, below the spacing of doubles


@dataclass(frozen=True)
class _Row:
    """One SCR row as a monotone curve: observed N ascending (> 0), probabilities."""

    scr: float
    cycles: tuple[float, ...]
    probabilities: tuple[float, ...]

    def forward(self, n: Array, xp: Any) -> Array:
        """P at N >= 0 (assumption 1), for N of any shape; NaN where N is NaN."""
        ns, ps = self.cycles, self.probabilities
        u = xp.log(xp.where(n > 0, xp.minimum(n, ns[-1]), 1.0))  # segments only: no inf · 0
        out = xp.where(n >= ns[-1], ps[-1], xp.zeros_like(n))
        first = ps[0] * xp.where(n < ns[0], n, ns[0]) / ns[0]  # (0 · inf would be NaN)
        first = xp.where(first > ps[0], ps[0], first)  # no overshoot from rounding
        out = xp.where(n < ns[0], first, out)
        for k in range(len(ns) - 1):
            lo, width = math.log(ns[k]), math.log(ns[k + 1]) - math.log(ns[k])
            segment = ps[k] + (u - lo) / width * (ps[k + 1] - ps[k])
            segment = xp.where(segment > ps[k + 1], ps[k + 1], segment)
            out = xp.where((n >= ns[k]) & (n < ns[k + 1]), segment, out)
        return xp.where(xp.isnan(n), n, out)


@dataclass(frozen=True)
class _Fit:
    """The rows of Table 3.4 after assumptions 1 and 2, by ascending SCR."""

    rows: tuple[_Row, ...]

    @functools.cached_property
    def log_scr(self) -> tuple[float, ...]:
        return tuple(math.log(row.scr) for row in self.rows)

    @functools.cached_property
    def linear_end(self) -> float:
        """Below this N every row is linear in N (the first observed N of any row)."""
        return min(row.cycles[0] for row in self.rows)

    @functools.cached_property
    def top(self) -> float:
        """From this N on every row is constant (the last observed N of any row)."""
        return max(row.cycles[-1] for row in self.rows)

    def ordered(self, n: Array, xp: Any) -> list[Array]:
        """Each row's P at N after the running maximum over ascending SCR (assumption 3)."""
        values: list[Array] = []
        for row in self.rows:
            value = row.forward(n, xp)
            if values:
                value = xp.where(values[-1] > value, values[-1], value)
            values.append(value)
        return values

    def clamped_log_scr(self, scr: Array, xp: Any) -> Array:
        """log SCR, clamped to the observed rows (assumption 4); NaN stays NaN."""
        lo, hi = self.rows[0].scr, self.rows[-1].scr
        s = xp.where(scr < lo, lo, xp.where(scr > hi, hi, scr))
        return xp.log(s)

    def forward(self, n: Array, log_scr: Array, xp: Any) -> Array:
        """P at unscaled N >= 0 and clamped log SCR (both may be NaN; they broadcast)."""
        values = self.ordered(n, xp)
        ls = self.log_scr
        out = xp.zeros_like(values[0] + log_scr)
        for k in range(len(ls) - 1):
            t = (log_scr - ls[k]) / (ls[k + 1] - ls[k])
            segment = (1.0 - t) * values[k] + t * values[k + 1]
            out = xp.where((log_scr >= ls[k]) & (log_scr <= ls[k + 1]), segment, out)
        return xp.where(xp.isnan(n) | xp.isnan(log_scr), xp.nan, out)

    def inverse(self, p: Array, log_scr: Array, xp: Any) -> Array:
        """Smallest unscaled N with P(N) >= p, for p in (0, 1) (assumption 6)."""
        p, log_scr = xp.broadcast_arrays(p, log_scr)
        ones = xp.ones_like(p)
        p_linear = self.forward(self.linear_end * ones, log_scr, xp)
        p_top = self.forward(self.top * ones, log_scr, xp)
        slope = p_linear / self.linear_end
        exact = p / xp.where(slope > 0, slope, 1.0)
        lo = math.log(self.linear_end) * ones
        hi = math.log(self.top) * ones
        for _ in range(_BISECTIONS):
            mid = 0.5 * (lo + hi)
            reached = self.forward(xp.exp(mid), log_scr, xp) >= p
            hi = xp.where(reached, mid, hi)
            lo = xp.where(reached, lo, mid)
        out = xp.where(p <= p_linear, exact, xp.exp(hi))
        out = xp.where(p > p_top, xp.inf, out)
        return xp.where(xp.isnan(p) | xp.isnan(log_scr), xp.nan, out)


def _column_cycles(column: str) -> float:
    """N of a column named ``n_<cycles>``."""
    return float(column.removeprefix("n_"))


@functools.cache
def _table() -> tuple[tuple[float, ...], tuple[float, ...], tuple[tuple[float, ...], ...]]:
    """(SCRs ascending, N of the columns, printed P by row with NaN for "–")."""
    table = load_table(_TABLE)
    columns = [c for c in table.columns if c.startswith("n_")]
    cycles = tuple(_column_cycles(c) for c in columns)
    by_column = [table.numbers(c) for c in columns]
    printed = [
        (scr, tuple(col[i] for col in by_column)) for i, scr in enumerate(table.numbers("scr"))
    ]
    printed.sort()
    return (
        tuple(scr for scr, _ in printed),
        cycles,
        tuple(values for _, values in printed),
    )


@functools.cache
def _fit() -> _Fit:
    scrs, cycles, printed = _table()
    rows = []
    for scr, values in zip(scrs, printed, strict=True):
        points = sorted(
            (n, p) for n, p in zip(cycles, values, strict=True) if not math.isnan(p) and n > 0
        )
        running: list[float] = []
        for _, p in points:  # assumption 2: running maximum along ascending N
            running.append(max(p, running[-1]) if running else p)
        rows.append(_Row(scr, tuple(n for n, _ in points), tuple(running)))
    return _Fit(tuple(rows))


@functools.cache
def adjusted_cells() -> Mapping[tuple[float, float], tuple[float, float]]:
    """The observed cells of Table 3.4 that the monotone fit changes.

    Returns
    -------
    Mapping[tuple[float, float], tuple[float, float]]
        ``(SCR [1], N [cycles]) -> (printed P, fitted P)`` for every printed (not "–") cell
        whose fitted value differs from the printed one: ``{(5.8, 2.0): (0.95, 0.96)}``.

    Examples
    --------
    >>> from targetacq.acquisition.observed_detection import adjusted_cells
    >>> dict(adjusted_cells())
    {(5.8, 2.0): (0.95, 0.96)}
    """
    xp = _arrays.namespace()
    scrs, cycles, printed = _table()
    fit = _fit()
    changed = {}
    for scr, values in zip(scrs, printed, strict=True):
        log_scr = fit.clamped_log_scr(_arrays.as_float(scr, xp), xp)
        for n, p in zip(cycles, values, strict=True):
            if math.isnan(p):
                continue
            fitted = float(fit.forward(_arrays.as_float(n, xp), log_scr, xp))
            if fitted != p:
                changed[scr, n] = (p, fitted)
    return changed


def _scr(scr: Any, xp: Any) -> Array:
    if scr is None:
        raise ValueError(
            f"{NAME} needs scr, the target's signal-to-clutter ratio [1] (>= 0); got None"
        )
    s = _arrays.as_float(scr, xp, "scr")
    _arrays.require_nonnegative("scr", s, xp)
    return s


def observed_detection(cycles: Array, n50: Array = 1.0, *, scr: Array) -> Any:
    """Probability of detection from the observations of Table 3.4 in Sonesson (2004).

    A monotone fit through the observed points (module doc): per SCR row linear in ``log N``
    between observations, ordered across SCR, linear in ``log SCR`` between rows, SCR clamped
    to the observed [0.33, 39].

    Parameters
    ----------
    cycles : array_like
        N, resolvable cycles across the target's critical dimension [cycles], >= 0.
    n50 : array_like, optional
        The criterion's detection N50 [cycles], > 0. The table's reference is Johnson's, 1.0:
        ``P(N) = fit(N · 1.0 / n50)``.
    scr : array_like
        Signal-to-clutter ratio [1], >= 0 (+inf allowed); broadcasts with ``cycles``.

    Returns
    -------
    array_like
        P(detection) [1] in [0, 1]; 0 at N = 0; NaN where an input element is NaN.

    Raises
    ------
    ValueError
        If ``scr`` is missing (None) or negative, ``cycles`` is negative or ``n50`` is not > 0.

    Examples
    --------
    >>> from targetacq.acquisition.observed_detection import observed_detection
    >>> [round(float(p), 12) for p in observed_detection([0.25, 0.5, 1.0], scr=39.0)]
    [0.93, 0.96, 1.0]
    >>> round(float(observed_detection(6.0, scr=0.33)), 12)  # high clutter tops out at 0.84
    0.84
    >>> round(float(observed_detection(2.0, scr=5.8)), 12)  # printed 0.95, raised (module doc)
    0.96
    >>> round(float(observed_detection(1.0, 2.0, scr=1.2)), 12)  # N50 = 2: read at 0.5 cycles
    0.04
    """
    xp, (n, n50_) = _arrays.arrays(cycles, n50, names=("cycles", "n50"))
    s = _scr(scr, xp)
    _arrays.require_nonnegative("cycles", n, xp)
    _arrays.require_positive("n50", n50_, xp)
    fit = _fit()
    scaled = n * (_REFERENCE_N50 / n50_)
    return _arrays.result(fit.forward(scaled, fit.clamped_log_scr(s, xp), xp))


def observed_detection_inverse(probability: Array, n50: Array = 1.0, *, scr: Array) -> Any:
    """Cycles needed for a probability of detection (inverse of :func:`observed_detection`).

    Parameters
    ----------
    probability : array_like
        P(detection) [1] in the open interval (0, 1).
    n50 : array_like, optional
        The criterion's detection N50 [cycles], > 0 (1.0: the table's own).
    scr : array_like
        Signal-to-clutter ratio [1], >= 0; broadcasts with ``probability``.

    Returns
    -------
    array_like
        The smallest N [cycles] with ``observed_detection(N, n50, scr=scr) >= probability``;
        +inf where the curve never reaches it; NaN where an input element is NaN.

    Raises
    ------
    ValueError
        If ``scr`` is missing (None) or negative, ``probability`` is outside (0, 1) or ``n50``
        is not > 0.

    Examples
    --------
    >>> from targetacq.acquisition.observed_detection import observed_detection_inverse
    >>> round(float(observed_detection_inverse(0.5, scr=1.2)), 6)  # 2^0.08, between 1 and 2
    1.057018
    >>> float(observed_detection_inverse(0.9, scr=0.33))  # never reached in high clutter
    inf
    """
    xp, (p, n50_) = _arrays.arrays(probability, n50, names=("probability", "n50"))
    s = _scr(scr, xp)
    _arrays.require_open_unit_interval("probability", p, xp)
    _arrays.require_positive("n50", n50_, xp)
    fit = _fit()
    needed = fit.inverse(p, fit.clamped_log_scr(s, xp), xp)
    return _arrays.result(needed * (n50_ / _REFERENCE_N50))


def _options(task: str, options: Mapping[str, Any]) -> Any:
    """The ``scr`` option of the registry adapters, after checking the task and options."""
    if task != "detection":
        raise ValueError(f"transform {NAME!r} has no curve for task {task!r}; its tasks: detection")
    unknown = sorted(set(options) - {"scr"})
    if unknown:
        raise ValueError(
            f"transform {NAME!r} takes no option(s) {', '.join(unknown)}; its options: scr"
        )
    return options.get("scr")


def forward(cycles: Array, n50: Array, task: str = "detection", **options: Any) -> Any:
    """Registry adapter: :func:`observed_detection` with option ``scr`` (required).

    Parameters
    ----------
    cycles : array_like
        N [cycles], >= 0.
    n50 : array_like
        The criterion's detection N50 [cycles], > 0.
    task : {"detection"}
    **options
        ``scr``: signal-to-clutter ratio [1], >= 0 (required).

    Examples
    --------
    >>> from targetacq.acquisition import observed_detection as od
    >>> round(float(od.forward(0.5, 1.0, "detection", scr=39.0)), 12)
    0.96
    """
    return observed_detection(cycles, n50, scr=_options(task, options))


def inverse(probability: Array, n50: Array, task: str = "detection", **options: Any) -> Any:
    """Registry adapter: :func:`observed_detection_inverse` with option ``scr`` (required).

    Parameters
    ----------
    probability : array_like
        P(detection) [1] in (0, 1).
    n50 : array_like
        The criterion's detection N50 [cycles], > 0.
    task : {"detection"}
    **options
        ``scr``: signal-to-clutter ratio [1], >= 0 (required).

    Examples
    --------
    >>> from targetacq.acquisition import observed_detection as od
    >>> round(float(od.inverse(0.96, 1.0, "detection", scr=39.0)), 9)
    0.5
    """
    return observed_detection_inverse(probability, n50, scr=_options(task, options))
