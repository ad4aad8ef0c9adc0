"""Acquisition over time: the field-of-view search model and sampled outcomes.

Search model. An observer looking at a target whose static probability of detection is P∞
detects it by time t with ``P(t) = P∞ (1 − exp(−t/τ))``, ``τ = t_s / P∞`` (the NVESD
field-of-view search model; ``t_s = 3.4 s`` by default, the scenario's
``model.search_time``). Sampled per sensor, target and run:

- a *capability* draw ``u`` per viewing episode: the target can be detected while ``u < P∞(t)``,
  recognised while ``u < P_rec(t)``, identified while ``u < P_id(t)``: nested events from one
  uniform (see the user guide's errata to Eq. (2.5)), so nothing is identified that was not
  recognised and detected, and the marginal frequencies are the model's probabilities;
- an exponential *clock* ``E = −ln(v)`` per episode: detection happens when the integrated hazard
  ``Λ(t) = ∫ P∞(s)/t_s ds`` (counted while capable) first reaches ``E``;
- recognition and identification follow at the first moment (at or after detection, at or
  after recognition) at which the capability draw is below their probability.

Time steps. The state advances step by step, each step covering an interval ``(t0, t1]``
with the probabilities known at its ends. Within the interval each probability is taken
**linear in time** between its values at ``t0`` and ``t1``: the hazard is integrated over the
interval rather than held at its start, so a coarse step no longer delays the detection of a
target closing in (or hastens that of one moving away); what remains is the curvature of P
within a step, small where P changes little over one step. With ``P(s) = a + (b − a) s`` for
``s = (t − t0)/(t1 − t0)`` in [0, 1], the law is exact for that P:

- the capable set ``{s : u < P(s)}`` is one sub-interval ``[s_lo, s_hi]`` (empty unless
  ``max(a, b) > u``): ``s_lo = clip((u − a)/(b − a), 0, 1)`` where P rises, else 0;
  ``s_hi = clip((u − a)/(b − a), 0, 1)`` where P falls, else 1;
- the hazard over it is the trapezoid ``ΔΛ = (t1 − t0)/t_s · (s_hi − s_lo) ·
  (P(s_lo) + P(s_hi))/2``;
- where ``Λ + ΔΛ >= E`` detection happens at ``s_lo + x``, the root of
  ``P(s_lo) x + (b − a) x²/2 = c``, ``c = (E − Λ) t_s/(t1 − t0)``, taken in the form
  ``x = 2c / (P(s_lo) + sqrt(P(s_lo)² + 2 (b − a) c))`` (no cancellation: both terms of the
  denominator are positive, the square root being ``P`` at the crossing);
- recognition happens at ``max(start, s_lo_rec)`` if that is ``<= s_hi_rec``, with ``start`` the
  moment of detection in this step (0 if it was earlier); identification likewise after
  recognition.

For a constant P∞ this gives exactly ``P(t)`` above whatever the step. The first step (after a
reset) only starts the clock: it sets the probabilities at its time and starts the episodes of
the targets then in view; nothing can happen in it. A NaN probability (a NaN position) at
either end of an interval means nothing happens for that pair in it and its episode goes on
unchanged.

Episodes and engagements. An episode is a stretch of time with the target in view; the
engagement is everything from the first episode until a reset. A target enters (leaves) the
view somewhere inside a step; the moment is solved from the positions and pointing at the two
ends (:func:`pair_crossings`, :func:`targetacq.acquisition.engagement.view_crossings`; the middle of
the step where it cannot be), and the target is in view from (until) then with the probabilities of
the end at which it is in view held constant (the field-of-view edge is a jump, so the linear law
does not apply across it). The capability draw is kept from one episode to the next and drawn again
only under the redraw rule (:data:`targetacq.acquisition.engagement.REDRAW_RULES`: ``never`` by
default); the detection clock and the hazard accumulated so far are kept too, except that after a
detection a target that comes back must be found again (a new clock: its events are reacquisitions).
Draws come from the counter-based generator of :mod:`targetacq.base.sampling`, keyed by the seed and
the sensor's and target's names and counted by the pair's own number of draws and the run, so
outcomes do not depend on the batch size, the order of the sensors, which other pairs are simulated,
the step or the pointing pattern. A visit shorter than a step is recorded (:class:`ShortVisit`) for
the callers' warning. Fusion over sensors (sensor level): a target is detected (recognised,
identified) when the first sensor does.

:func:`simulate` runs a :class:`targetacq.run.model_chain.ModelChain`'s scripted scenario for many
runs at once; :class:`targetacq.Simulation` is the same machinery driven one step at a time by
another simulation. Both draw the false detections of a scenario's ``[false_targets]`` table
(:mod:`targetacq.run.false_targets`) in each step, from streams of their own.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from targetacq.acquisition.engagement import RedrawRule, get_redraw_rule, view_crossings
from targetacq.base import arrays as _arrays
from targetacq.base import limits
from targetacq.base.arrays import Array
from targetacq.base.sampling import stream_key, uniforms
from targetacq.core.evaluation import boresight
from targetacq.run.false_targets import FalseDetections, FalseTargetSampler

__all__ = [
    "ShortVisit",
    "ShortVisitWarning",
    "SimulationResult",
    "check_simulation_size",
    "pair_crossings",
    "search_probability",
    "short_visit_message",
    "simulate",
]

_TASKS = ("detection", "recognition", "identification")
# Purposes of the draws. The capability and the clock are counted by the pair's own draws (not
# the step), so the same seed gives the same draws whatever the step and the pointing pattern.
_CAPABILITY, _CLOCK = 3, 4
# Runs × pairs of a step up to which it is advanced element by element in Python floats
# (SearchState._interval_small), where NumPy's fixed cost per call is larger than the work.
_SMALL = 8


def search_probability(time: Array, p_infinity: Array, search_time: float = 3.4) -> Any:
    """Probability of detection by time t of the field-of-view search model.

    ``P(t) = P∞ (1 − exp(−t P∞ / t_s))``, i.e. ``τ = t_s / P∞``.

    Parameters
    ----------
    time : array_like
        t [s], >= 0.
    p_infinity : array_like
        P∞ in [0, 1], the static probability of detection.
    search_time : float
        t_s [s], > 0 (3.4 s by default).

    Returns
    -------
    array_like
        P(t) in [0, P∞].

    Examples
    --------
    >>> round(float(search_probability(3.4, 1.0)), 4)
    0.6321
    """
    if not search_time > 0:
        raise ValueError(f"search_time must be > 0 s, got {search_time!r}")
    xp, (t, p) = _arrays.arrays(time, p_infinity)
    _arrays.require_nonnegative("time", t, xp, "s")
    _arrays.require_unit_interval("p_infinity", p, xp)
    return _arrays.result(p * (1.0 - xp.exp(-t * p / search_time)))


def check_seed(seed: Any) -> int:
    """``seed`` as an int if it is an integer in [0, 2**128 - 1] (a NumPy integer too), else
    ``ValueError`` (:func:`targetacq.base.limits.check_seed`)."""
    if isinstance(seed, np.integer):
        seed = int(seed)
    return limits.check_seed(seed)


def check_simulation_size(
    duration: float,
    step: float,
    runs: int,
    pairs: int,
    advice: str = "use fewer runs, a longer step or a shorter duration",
) -> int:
    """The number of steps of a simulation, after checking that it fits in memory.

    :func:`simulate` holds the probabilities of every step and pair
    (:data:`targetacq.base.limits.BYTES_PER_EVALUATION` each, as an evaluation does) and the
    first times of every run, pair and task (two float64 arrays: per sensor and fused).

    Parameters
    ----------
    duration, step : float
        [s], > 0 and finite.
    runs, pairs : int
        Runs, and sensor-target pairs.
    advice : str
        How to make it smaller, in the caller's words.

    Returns
    -------
    int
        Steps, ``ceil(duration / step)`` (at least 1).

    Raises
    ------
    ValueError
        If either part would not fit (:func:`targetacq.base.limits.check_size`).
    """
    ratio = duration / step
    steps = max(1.0, math.ceil(ratio - 1e-9)) if math.isfinite(ratio) else math.inf
    limits.check_size(
        (steps + 1.0) * pairs,
        limits.BYTES_PER_EVALUATION,
        f"{steps:.3g} steps of {step:g} s x {pairs} sensor-target pair(s)",
        advice,
    )
    limits.check_size(
        float(runs) * pairs * len(_TASKS), 2 * 8, f"{runs} runs x {pairs} pair(s)", advice
    )
    return int(steps)


class Streams:
    """The Philox keys of every sensor-target pair (flat index ``s · n_g + g``), computed the
    first time a pair needs a draw (hashing a million names takes seconds)."""

    def __init__(self, seed: int, sensors: Sequence[str], targets: Sequence[str]) -> None:
        self.seed = check_seed(seed)
        self.sensors, self.targets = tuple(sensors), tuple(targets)
        size = len(self.sensors) * len(self.targets)
        self.k0 = np.zeros(size, dtype=np.uint32)
        self.k1 = np.zeros(size, dtype=np.uint32)
        self.ready = np.zeros(size, dtype=bool)

    def keys(self, pairs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        missing = pairs[~self.ready[pairs]]
        n_g = len(self.targets)
        for pair in missing.tolist():
            s, g = divmod(pair, n_g)
            self.k0[pair], self.k1[pair] = stream_key(self.seed, self.sensors[s], self.targets[g])
        self.ready[missing] = True
        return self.k0[pairs], self.k1[pairs]


@dataclass
class _Interval:
    """What happened in one step: the pairs looked at (flat indices) and, per task, the time of
    the event in this step for each run and pair (+inf where none), shape (3, runs, pairs), and
    whether it was the first time since the start (else a reacquisition), same shape."""

    pairs: np.ndarray
    times: np.ndarray
    first: np.ndarray


@dataclass(frozen=True)
class ShortVisit:
    """A target in a sensor's view for less than one step (the first seen in a run).

    Attributes
    ----------
    pair : int
        Flat index ``sensor · n_targets + target``.
    entered, left : float
        When it came into and went out of view [s].
    step : float
        The step [s] it was shorter than.
    """

    pair: int
    entered: float
    left: float
    step: float


class SearchState:
    """The sampled state of every run × sensor × target pair, advanced one step at a time.

    Arrays are (runs, pairs) with the pairs flattened (sensor-major); the probabilities and the
    field of view, which do not depend on the run, are (pairs,). See the module docstring for
    the law and :mod:`targetacq.acquisition.engagement` for the draw rule.
    """

    def __init__(
        self,
        streams: Streams,
        runs: np.ndarray,
        search_time: float,
        redraw: str | RedrawRule = "never",
        decorrelation_time: float | None = None,
    ) -> None:
        if not (search_time > 0 and math.isfinite(search_time)):
            raise ValueError(f"search_time must be > 0 s, got {search_time!r}")
        self.rule = get_redraw_rule(redraw)
        if self.rule.uses_time and (decorrelation_time is None or not decorrelation_time >= 0):
            raise ValueError(
                f"redraw {self.rule.name!r} needs decorrelation_time >= 0 s, got "
                f"{decorrelation_time!r}"
            )
        self.decorrelation_time = math.inf if decorrelation_time is None else decorrelation_time
        self.streams = streams
        self.runs = np.asarray(runs, dtype=np.int64).reshape(-1, 1)
        self.search_time = float(search_time)
        size = len(streams.sensors) * len(streams.targets)
        shape = (self.runs.shape[0], size)
        self.u = np.ones(shape)
        self.clock = np.zeros(shape)
        self.hazard = np.zeros(shape)
        self.level = np.zeros(shape, dtype=np.int8)  # tasks done in this episode: 0..3
        self.renew = np.zeros(shape, dtype=bool)  # the last search ended in a detection
        self.searches = np.zeros(shape, dtype=np.int64)  # clocks drawn so far
        self.draws = np.zeros(size, dtype=np.int64)  # capability draws so far (per pair)
        self.first = np.full((3, *shape), np.inf)  # first time of each task since the start
        self.view = np.zeros(size, dtype=bool)
        self.left = np.full(size, -np.inf)  # when each pair last went out of view
        self.entered = np.full(size, np.nan)  # when its current episode began
        self.p: np.ndarray | None = None  # (3, pairs) at the previous step's time
        self.time = -math.inf
        self.index = 0  # steps taken
        self.short: ShortVisit | None = None  # the first visit shorter than a step

    def _start(self, new: np.ndarray, at: np.ndarray) -> None:
        """New episodes for the pairs ``new`` (flat indices) beginning at times ``at``: new
        capability draws where the rule says so, a new search clock where the last search
        ended in a detection (or the draws are new), nothing done yet in the episode."""
        keys = self.streams.keys(new)
        fresh = self.rule.fresh(at - self.left[new], self.decorrelation_time)
        if fresh.any():
            pairs = new[fresh]
            key = (keys[0][fresh], keys[1][fresh])
            self.u[:, pairs] = uniforms(key, self.draws[pairs], self.runs, _CAPABILITY)
            self.draws[pairs] += 1
            self.renew[:, pairs] = True
        renew = self.renew[:, new]
        if renew.any():
            count = self.searches[:, new]
            clock = -np.log(uniforms(keys, count, self.runs, _CLOCK))
            self.clock[:, new] = np.where(renew, clock, self.clock[:, new])
            self.hazard[:, new] = np.where(renew, 0.0, self.hazard[:, new])
            self.searches[:, new] = count + renew
            self.renew[:, new] = False
        self.level[:, new] = 0
        self.entered[new] = at

    def advance(
        self,
        time: float,
        p: np.ndarray,
        in_view: np.ndarray,
        crossings: np.ndarray | None = None,
    ) -> _Interval | None:
        """Advance over ``(self.time, time]`` to ``time``.

        ``p`` (3, pairs): detection, recognition and identification at ``time``; ``in_view``
        (pairs,); ``crossings`` (pairs,): where a pair's view changes in this step, the moment
        it does as a fraction of the step (:func:`targetacq.acquisition.engagement.view_crossings`;
        NaN or absent: the middle). The caller checks that time does not go back. Returns what
        happened, or None where nothing could (the first step, a step of zero length, nothing in
        view).
        """
        known = ~np.isnan(p[0])
        view = np.where(known, in_view, self.view)
        dt = time - self.time
        started = self.p is not None and dt > 0
        changed = view != self.view
        fraction = None
        if started and changed.any():
            fraction = np.full(view.size, 0.5)
            if crossings is not None:
                fraction = np.where(np.isnan(crossings), 0.5, crossings)
        new = np.flatnonzero(view & ~self.view)
        if new.size:
            at = np.full(new.size, time) if fraction is None else self.time + fraction[new] * dt
            self._start(new, at)
        out = None
        previous = self.p
        if started and previous is not None:
            live = (self.view | view) & known & ~np.isnan(previous[0])
            interval = self._interval_small if live.size * self.u.shape[0] <= _SMALL else None
            if live.all():
                out = (interval or self._interval)(
                    slice(None), previous, p, view, fraction, time, dt
                )
            elif live.any():
                pairs = np.flatnonzero(live)
                part = None if fraction is None else fraction[pairs]
                out = (interval or self._interval)(
                    pairs, previous[:, pairs], p[:, pairs], view[pairs], part, time, dt
                )
        ended = np.flatnonzero(self.view & ~view)
        if ended.size:
            self.level[:, ended] = 0  # out of view: the episode is over
            gone = (
                np.full(ended.size, time) if fraction is None else self.time + fraction[ended] * dt
            )
            self.left[ended] = gone
            if self.short is None and started:
                brief = gone - self.entered[ended] < dt * (1.0 - 1e-9)
                if brief.any():
                    k = int(np.argmax(brief))
                    self.short = ShortVisit(
                        int(ended[k]), float(self.entered[ended[k]]), float(gone[k]), float(dt)
                    )
        self.view = view
        self.p = p
        self.time = time
        self.index += 1
        return out

    def _interval(
        self,
        pairs: Any,
        a: np.ndarray,
        b: np.ndarray,
        view: np.ndarray,
        fraction: np.ndarray | None,
        time: float,
        dt: float,
    ) -> _Interval:
        u = self.u[:, pairs]
        level = self.level[:, pairs]
        was = self.view[pairs]
        # The part of the interval in view: all of it, or from the crossing (entering) or up
        # to it (leaving), with the probabilities of the end in view held over it.
        window_lo: Any = 0.0
        window_hi: Any = 1.0
        if fraction is not None and not (was.all() and view.all()):
            a, b = np.where(was, a, b), np.where(view, b, a)
            window_lo = np.where(was, 0.0, fraction)
            window_hi = np.where(view, 1.0, fraction)
        slope = (b - a)[:, None]  # (3, 1, m)
        a = a[:, None]
        with np.errstate(divide="ignore", invalid="ignore"):
            root = np.minimum(np.maximum((u - a) / slope, 0.0), 1.0)  # P(s) = u, (3, runs, m)
        lo = np.maximum(np.where(slope > 0, root, 0.0), window_lo)
        hi = np.minimum(np.where(slope < 0, root, 1.0), window_hi)
        capable = (np.maximum(a, b[:, None]) > u) & (lo <= hi)
        # Detection: the hazard P/t_s integrated over the capable part of the interval.
        a0, slope0, lo0, hi0 = a[0], slope[0], lo[0], hi[0]
        p_lo = a0 + slope0 * lo0
        area = np.where(capable[0], (hi0 - lo0) * (p_lo + 0.5 * slope0 * (hi0 - lo0)), 0.0)
        scale = dt / self.search_time
        hazard = self.hazard[:, pairs]
        left = (self.clock[:, pairs] - hazard) / scale  # c, in units of P × s
        searching = level == 0
        hit = searching & capable[0] & (area >= left)
        times = np.empty((3, *u.shape))
        if hit.any():
            root_term = np.sqrt(np.maximum(p_lo * p_lo + 2.0 * slope0 * left, 0.0))
            with np.errstate(divide="ignore", invalid="ignore"):
                crossing = lo0 + 2.0 * left / (p_lo + root_term)
            times[0] = np.where(hit, np.minimum(crossing, hi0), np.inf)
            start = np.where(hit, times[0], 0.0)
            level = np.where(hit, np.int8(1), level)
            self.renew[:, pairs] |= hit
        else:
            times[0] = np.inf
            start = np.zeros(u.shape)
        self.hazard[:, pairs] = np.where(searching, hazard + scale * area, hazard)
        # Recognition, then identification: the first capable moment at or after the last task.
        for task in (1, 2):
            moment = np.maximum(start, lo[task])
            happens = (level == task) & capable[task] & (moment <= hi[task])
            times[task] = np.where(happens, moment, np.inf)
            start = np.where(happens, moment, 0.0)
            level = np.where(happens, np.int8(task + 1), level)
        self.level[:, pairs] = level
        # Fractions of the interval → times, exact at the step's own time.
        times = time - (1.0 - times) * dt
        before = self.first[:, :, pairs]
        first = np.isinf(before) & np.isfinite(times)
        self.first[:, :, pairs] = np.minimum(before, times)
        index = np.arange(self.view.size) if isinstance(pairs, slice) else pairs
        return _Interval(pairs=index, times=times, first=first)

    def _interval_small(
        self,
        pairs: Any,
        a: np.ndarray,
        b: np.ndarray,
        view: np.ndarray,
        fraction: np.ndarray | None,
        time: float,
        dt: float,
    ) -> _Interval:
        """:meth:`_interval` element by element in Python floats, for a few runs × pairs (a
        step of one run and a handful of pairs, where NumPy's per-call cost dominates): the
        same operations in the same order, so the same numbers to the last bit (tested)."""
        index = np.arange(self.view.size) if isinstance(pairs, slice) else pairs
        cols = index.tolist()
        runs = self.u.shape[0]
        was = self.view[index].tolist()
        now = view.tolist()
        frac = [0.5] * len(cols) if fraction is None else fraction.tolist()
        a_rows, b_rows = a.tolist(), b.tolist()
        u_all, level_all = self.u[:, index].tolist(), self.level[:, index].tolist()
        clock_all, hazard_all = self.clock[:, index].tolist(), self.hazard[:, index].tolist()
        first_all = self.first[:, :, index].tolist()
        scale = dt / self.search_time
        inf = math.inf
        times = np.full((3, runs, len(cols)), inf)
        first = np.zeros((3, runs, len(cols)), dtype=bool)
        for j in range(len(cols)):
            aj = [a_rows[k][j] for k in range(3)]
            bj = [b_rows[k][j] for k in range(3)]
            w_lo, w_hi = 0.0, 1.0
            if fraction is not None and not (was[j] and now[j]):
                # In view at one end only: that end's probabilities, over the window next to it.
                aj, bj = (aj if was[j] else bj), (bj if now[j] else aj)
                w_lo, w_hi = (0.0 if was[j] else frac[j]), (1.0 if now[j] else frac[j])
            for r in range(runs):
                u = u_all[r][j]
                lo, hi, capable = [0.0] * 3, [1.0] * 3, [False] * 3
                for k in range(3):
                    slope = bj[k] - aj[k]
                    low, high = 0.0, 1.0
                    if slope > 0:
                        low = min(max((u - aj[k]) / slope, 0.0), 1.0)
                    elif slope < 0:
                        high = min(max((u - aj[k]) / slope, 0.0), 1.0)
                    lo[k], hi[k] = max(low, w_lo), min(high, w_hi)
                    capable[k] = max(aj[k], bj[k]) > u and lo[k] <= hi[k]
                level = level_all[r][j]
                slope0 = bj[0] - aj[0]
                p_lo = aj[0] + slope0 * lo[0]
                width = hi[0] - lo[0]
                area = width * (p_lo + 0.5 * slope0 * width) if capable[0] else 0.0
                hazard = hazard_all[r][j]
                left = (clock_all[r][j] - hazard) / scale
                searching = level == 0
                at = [inf, inf, inf]
                start = 0.0
                if searching and capable[0] and area >= left:
                    root_term = math.sqrt(max(p_lo * p_lo + 2.0 * slope0 * left, 0.0))
                    at[0] = min(lo[0] + 2.0 * left / (p_lo + root_term), hi[0])
                    start = at[0]
                    level = 1
                    self.renew[r, cols[j]] = True
                if searching:
                    self.hazard[r, cols[j]] = hazard + scale * area
                for k in (1, 2):
                    moment = max(start, lo[k])
                    if level == k and capable[k] and moment <= hi[k]:
                        at[k] = moment
                        start = moment
                        level = k + 1
                    else:
                        start = 0.0
                self.level[r, cols[j]] = level
                for k in range(3):
                    if at[k] != inf:
                        value = time - (1.0 - at[k]) * dt
                        times[k, r, j] = value
                        if first_all[k][r][j] == inf:
                            first[k, r, j] = True
                            self.first[k, r, cols[j]] = value
                        elif value < first_all[k][r][j]:
                            self.first[k, r, cols[j]] = value
        return _Interval(pairs=index, times=times, first=first)


def pair_crossings(
    sensors: Any,
    before: tuple[np.ndarray, np.ndarray, Any],
    after: tuple[np.ndarray, np.ndarray, Any],
    pairs: np.ndarray,
    entering: np.ndarray,
) -> np.ndarray:
    """When, within a step, the view of sensor-target pairs changes, as fractions of the step.

    Parameters
    ----------
    sensors : targetacq.core.SensorArrays
        The sensors (their pointing and fields of view).
    before, after : (array (n_s, 3), array (n_g, 3), array (n_s, 2) or None)
        Sensor positions, target positions [m] and sensor pointing (azimuth, depression [rad];
        None or a NaN row: the sensor's own) at the start and at the end of the step.
    pairs : array of int (m,)
        Flat pair indices ``sensor · n_g + target`` whose view changes.
    entering : array of bool (m,)
        Whether each comes into view (else it goes out).

    Returns
    -------
    numpy.ndarray (m,)
        :func:`targetacq.acquisition.engagement.view_crossings`; NaN where a sensor is not pointed
        at one end (the change is then at an unknown moment: the caller takes the middle).
    """
    n_g = before[1].shape[0]
    sensor, target = np.divmod(pairs, n_g)
    ends = []
    for s_pos, _, pointing in (before, after):
        forward, pointed = boresight(s_pos, sensors, pointing)
        ends.append((np.stack([np.asarray(f) for f in forward], axis=-1), np.asarray(pointed)))
    los0 = before[1][target] - before[0][sensor]
    los1 = after[1][target] - after[0][sensor]
    half = np.asarray(sensors.half_tangents, dtype=float)[sensor]
    pointed = (ends[0][1].reshape(-1) & ends[1][1].reshape(-1))[sensor]
    with np.errstate(invalid="ignore", divide="ignore"):
        found = view_crossings(
            (los0, los1),
            (ends[0][0][sensor], ends[1][0][sensor]),
            (half[:, 0], half[:, 1]),
            entering,
        )
    return np.where(
        pointed & np.isfinite(los0).all(axis=1) & np.isfinite(los1).all(axis=1), found, np.nan
    )


@dataclass(frozen=True)
class SimulationResult:
    """First times of detection, recognition and identification over runs.

    Attributes
    ----------
    times : dict of str → numpy.ndarray
        Task → (runs, sensors, targets) first time [s] per sensor; +inf where it never happened
        within the duration.
    fused : dict of str → numpy.ndarray
        Task → (runs, targets) first time over all sensors (sensor-level fusion).
    sensors, targets : list of str
    duration : float
        [s]
    false_detections : targetacq.run.false_targets.FalseDetections
        Every run's false detections (the scenario's ``[false_targets]``; empty without one),
        ordered by run, time and sensor: ``run``, ``sensor``, ``time`` [s] and ``position``
        (east, north, up [m] on the ground);
        :meth:`~targetacq.run.false_targets.FalseDetections.frame` gives them as a table.
    """

    times: dict[str, np.ndarray]
    fused: dict[str, np.ndarray]
    sensors: list[str]
    targets: list[str]
    duration: float
    false_detections: FalseDetections = field(default_factory=FalseDetections.empty)

    def acquired(self, time: float | None = None) -> dict[str, np.ndarray]:
        """The cumulative flags of every run: whether each task was done by ``time``.

        Parameters
        ----------
        time : float, optional
            [s] from the scenario's start time, as the first times are; default: the end of the
            simulation.

        Returns
        -------
        dict of str → numpy.ndarray of bool
            ``detected``, ``recognised``, ``identified``: (runs, sensors, targets) per sensor;
            ``fused_detected``, ...: (runs, targets) by any sensor (as the step API's flags).

        Examples
        --------
        >>> import numpy as np
        >>> result = SimulationResult(
        ...     times={t: np.array([[[1.0]], [[np.inf]]]) for t in _TASKS},
        ...     fused={t: np.array([[1.0], [np.inf]]) for t in _TASKS},
        ...     sensors=["s"], targets=["g"], duration=5.0)
        >>> result.acquired()["fused_identified"].tolist()
        [[True], [False]]
        """
        limit = math.inf if time is None else float(time)
        if math.isnan(limit):
            raise ValueError("time must be a number of seconds, got nan")
        out = {}
        for task, flag in zip(_TASKS, ("detected", "recognised", "identified"), strict=True):
            # +inf: never done (not done "by +inf").
            out[flag] = np.isfinite(self.times[task]) & (self.times[task] <= limit)
            out[f"fused_{flag}"] = np.isfinite(self.fused[task]) & (self.fused[task] <= limit)
        return out

    def summary(self) -> Any:
        """Per target and task (fused over sensors): the fraction of runs where it happened
        within the duration, and quantiles of the first time over all runs (inf: more runs than
        that quantile never got there); the mean is over the runs where it happened."""
        import pandas as pd

        rows = []
        for g, target in enumerate(self.targets):
            for task in _TASKS:
                t = self.fused[task][:, g]
                hit = np.isfinite(t)
                row: dict[str, Any] = {
                    "target": target,
                    "task": task,
                    "runs": t.size,
                    "fraction": float(hit.mean()),
                }
                ordered = np.sort(t)
                for q in (0.1, 0.5, 0.9):
                    # Inverted CDF: the smallest time reached by at least a share q of the runs
                    # (+inf when fewer runs ever got there).
                    row[f"t{int(q * 100)}_s"] = float(ordered[math.ceil(q * t.size) - 1])
                row["mean_s"] = float(t[hit].mean()) if hit.any() else math.nan
                rows.append(row)
        return pd.DataFrame(rows)


def simulate(
    chain: Any,
    duration: float,
    step: float,
    runs: int = 1,
    seed: int = 0,
    batch: int = 256,
    progress: Callable[[int], None] | None = None,
) -> SimulationResult:
    """Simulate acquisition over time, with random outcomes, for a scenario.

    The probabilities are evaluated once at the step times ``start, start + step, …,
    start + duration`` (:meth:`targetacq.run.model_chain.ModelChain.compute`); the runs then go
    through the step machinery of the module docstring, a batch of runs at a time, exactly as
    :class:`targetacq.Simulation` steps one run.

    Parameters
    ----------
    chain : targetacq.run.model_chain.ModelChain
        The prepared scenario.
    duration : float
        Simulated time [s], > 0, from the scenario's start time.
    step : float
        Time step [s], > 0; the probabilities are taken linear in time between steps.
    runs : int
        Independent runs, >= 1.
    seed : int
        Seed in [0, 2**128 - 1]; the same seed gives the same outcomes for any ``batch`` and
        sensor order.
    batch : int
        Runs simulated together (memory only; the outcomes do not depend on it).
    progress : callable, optional
        Called with the number of runs finished after each batch.

    Returns
    -------
    SimulationResult
        With the false detections of a ``[false_targets]`` table (drawn in each step after the
        first, :mod:`targetacq.run.false_targets`), the same for any ``batch``.

    Raises
    ------
    ValueError
        For a duration, step, runs, batch or seed outside its range, or a simulation too large
        for memory (:func:`check_simulation_size`; the expected false detections too), before
        anything is allocated.

    Examples
    --------
    >>> from targetacq.run.model_chain import ModelChain
    >>> from targetacq.scenario.schema import load_scenario
    >>> chain = ModelChain(load_scenario("examples/uav_haze.toml"))  # doctest: +SKIP
    >>> simulate(chain, 60.0, 0.5, runs=100, seed=7).fused["detection"].shape  # doctest: +SKIP
    (100, 3)
    """
    if not (duration > 0 and math.isfinite(duration)):
        raise ValueError(f"duration must be > 0 s, got {duration!r}")
    if not (step > 0 and math.isfinite(step)):
        raise ValueError(f"step must be > 0 s, got {step!r}")
    if not isinstance(runs, int) or runs < 1:
        raise ValueError(f"runs must be an integer >= 1, got {runs!r}")
    if not isinstance(batch, int) or batch < 1:
        raise ValueError(f"batch must be an integer >= 1, got {batch!r}")
    check_seed(seed)
    sc = chain.scenario
    pairs = len(chain.sensor_names) * len(chain.target_names)
    n_steps = check_simulation_size(duration, step, runs, pairs)
    edges = sc.time.start + np.minimum(np.arange(n_steps + 1) * step, duration)
    arrays = chain.compute(edges)
    n_s, n_g = arrays["in_view"].shape[:2]
    # (steps, 3, pairs) and (steps, pairs): one contiguous slice per step.
    p = np.ascontiguousarray(
        np.stack([arrays[task] for task in _TASKS]).reshape(3, n_s * n_g, -1).transpose(2, 0, 1)
    )
    in_view = np.ascontiguousarray(arrays["in_view"].reshape(n_s * n_g, -1).T)
    # The bands of a colour camera draw from the camera's streams (as in the step API).
    scene = chain.compiled.scene
    streams = Streams(seed, scene.sensors.group_names, chain.target_names)
    crossings = _scripted_crossings(chain, edges, p, in_view)
    footprints = _false_target_footprints(chain, edges, runs, seed)
    false_parts: list[FalseDetections] = []
    times = {task: np.full((runs, n_s, n_g), np.inf) for task in _TASKS}
    at = edges.tolist()
    short: ShortVisit | None = None
    for first in range(0, runs, batch):
        state = SearchState(
            streams,
            np.arange(first, min(first + batch, runs)),
            sc.model.search_time,
            sc.model.redraw,
            sc.model.decorrelation_time,
        )
        for k, t in enumerate(at):
            state.advance(t, p[k], in_view[k], crossings.get(k))
        short = short or state.short
        if footprints is not None:  # every step after the first at once: counter-based
            steps = [(k, at[k - 1], at[k], footprints[1][k]) for k in range(1, len(at))]
            false_parts.append(footprints[0].draw(steps, state.runs[:, 0]))
        count = state.runs.shape[0]
        for j, task in enumerate(_TASKS):
            times[task][first : first + count] = state.first[j].reshape(count, n_s, n_g)
        if progress is not None:
            progress(count)
    if short is not None:
        warnings.warn(
            short_visit_message(short, scene.sensors.names, chain.target_names),
            ShortVisitWarning,
            stacklevel=2,
        )
    fused = {task: times[task].min(axis=1) for task in _TASKS}
    return SimulationResult(
        times=times,
        fused=fused,
        sensors=list(chain.sensor_names),
        targets=list(chain.target_names),
        duration=float(duration),
        false_detections=FalseDetections.concatenate(false_parts),
    )


def _scripted_crossings(
    chain: Any, edges: np.ndarray, p: np.ndarray, in_view: np.ndarray
) -> dict[int, np.ndarray]:
    """Per step whose view changes for some pair, the crossing fractions of every pair (NaN
    where it does not change): the scenario's scripted positions and own pointing, moving
    linearly within each step (:func:`pair_crossings`)."""
    from targetacq.core import scenario_positions

    known = ~np.isnan(p[:, 0])
    changed = (in_view[1:] != in_view[:-1]) & known[1:] & known[:-1]
    steps = np.flatnonzero(changed.any(axis=1)) + 1
    if steps.size == 0:
        return {}
    sensor_positions, target_positions, _ = scenario_positions(chain.scenario, edges)
    sensors = chain.compiled.scene.sensors
    out = {}
    for k in steps.tolist():
        pairs = np.flatnonzero(changed[k - 1])
        fractions = np.full(in_view.shape[1], np.nan)
        fractions[pairs] = pair_crossings(
            sensors,
            (sensor_positions[:, k - 1], target_positions[:, k - 1], None),
            (sensor_positions[:, k], target_positions[:, k], None),
            pairs,
            in_view[k, pairs],
        )
        out[k] = fractions
    return out


class ShortVisitWarning(UserWarning):
    """A target was in a sensor's view for less than one step: the step is too long for it."""


def short_visit_message(short: ShortVisit, sensors: Sequence[str], targets: Sequence[str]) -> str:
    """The warning for a visit shorter than the step (:class:`ShortVisitWarning`)."""
    sensor, target = divmod(short.pair, len(targets))
    return (
        f"target {targets[target]!r} was in the view of sensor {sensors[sensor]!r} for "
        f"{short.left - short.entered:.3g} s ({short.entered:.6g} s to {short.left:.6g} s), less "
        f"than one step of {short.step:.3g} s: its probabilities there were taken from one end of "
        "a step, and a target can cross the view unseen between two steps; use a shorter step"
    )


def _false_target_footprints(
    chain: Any, edges: np.ndarray, runs: int, seed: int
) -> tuple[FalseTargetSampler, list[Any]] | None:
    """The scenario's false-target sampler and, per step time, each sensor's footprint and rate
    (the same for every run: the scripted positions), after checking that the expected false
    detections of all runs fit in memory; None without a ``[false_targets]`` table."""
    sc = chain.scenario
    if sc.false_targets is None:
        return None
    from targetacq.core import scenario_positions

    scene = chain.compiled.scene
    elevation = chain.compiled.elevation  # [terrain]: reports on ground in sight only
    sampler = FalseTargetSampler(
        sc.false_targets,
        scene.sensors,
        sc.model.search_time,
        seed,
        None if elevation is None else (elevation, chain.compiled.earth_radius_factor),
    )
    positions = scenario_positions(sc, edges)[0]  # (sensor rows, steps, 3)
    footprints = [sampler.footprints(positions[:, k]) for k in range(edges.size)]
    expected = runs * sum(
        rate * (edges[k] - edges[k - 1])
        for k in range(1, edges.size)
        for _, _, rate in footprints[k]
    )
    limits.check_size(
        expected,
        96,
        f"about {expected:.3g} false detections ({runs} runs)",
        "use fewer runs, a shorter duration or a lower false_targets.density",
    )
    return sampler, footprints
