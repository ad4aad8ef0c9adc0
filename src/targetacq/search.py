"""Acquisition over time: the field-of-view search model and sampled outcomes.

Search model. An observer looking at a target whose static probability of detection is P∞
detects it by time t with ``P(t) = P∞ (1 − exp(−t/τ))``, ``τ = t_s / P∞`` (the NVESD
field-of-view search model; ``t_s = 3.4 s`` by default, MODEL.md and the scenario's
``model.search_time``). Sampled per sensor, target and run:

- a *capability* draw ``u`` per viewing episode: the target can be detected while ``u < P∞(t)``,
  recognised while ``u < P_rec(t)``, identified while ``u < P_id(t)``: nested events from one
  uniform (MODEL.md §2), so nothing is identified that was not recognised and detected, and the
  marginal frequencies are the model's probabilities;
- an exponential *clock* ``E = −ln(v)`` per episode: detection happens when the integrated hazard
  ``Λ(t) = ∫ P∞(s)/t_s ds`` (counted while capable) first reaches ``E``. Between time steps the
  hazard is constant, so the crossing time is solved exactly inside the step: the distribution of
  the first-detection time does not depend on the step size (for P∞ constant it is exactly
  ``P(t)`` above, whatever the step);
- recognition and identification follow at the first moment (at or after detection) at which
  the capability draw is below their probability.

The state never goes backwards while the target stays in view; when it leaves the field of view
the episode ends, and a new one (with new draws) starts when it comes back. Draws come from the
counter-based generator of :mod:`targetacq.sampling`, keyed by the seed and the sensor's and
target's names and counted by the episode's first step and the run, so outcomes do not depend on
the batch size or the order of the sensors. Fusion over sensors (sensor level): a target is
detected (recognised, identified) when the first sensor does.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from targetacq import _arrays
from targetacq.sampling import stream_key, uniforms

__all__ = ["SimulationResult", "search_probability", "simulate"]

_TASKS = ("detection", "recognition", "identification")
_CAPABILITY, _CLOCK = 1, 2  # purposes of the draws


def search_probability(time: Any, p_infinity: Any, search_time: float = 3.4) -> Any:
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
    """
    if not search_time > 0:
        raise ValueError(f"search_time must be > 0 s, got {search_time!r}")
    xp, (t, p) = _arrays.arrays(time, p_infinity)
    _arrays.require_nonnegative("time", t, xp, "s")
    _arrays.require_unit_interval("p_infinity", p, xp)
    return _arrays.result(p * (1.0 - xp.exp(-t * p / search_time)))


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
    """

    times: dict[str, np.ndarray]
    fused: dict[str, np.ndarray]
    sensors: list[str]
    targets: list[str]
    duration: float

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

    Parameters
    ----------
    chain : targetacq.model.ModelChain
        The prepared scenario.
    duration : float
        Simulated time [s], > 0, from the scenario's start time.
    step : float
        Time step [s], > 0; probabilities are held constant within a step.
    runs : int
        Independent runs, >= 1.
    seed : int
        Seed, >= 0; the same seed gives the same outcomes for any ``batch`` and sensor order.
    batch : int
        Runs simulated together (memory only; the outcomes do not depend on it).
    progress : callable, optional
        Called with the number of runs finished after each batch.

    Returns
    -------
    SimulationResult
    """
    if not (duration > 0 and math.isfinite(duration)):
        raise ValueError(f"duration must be > 0 s, got {duration!r}")
    if not (step > 0 and math.isfinite(step)):
        raise ValueError(f"step must be > 0 s, got {step!r}")
    if not isinstance(runs, int) or runs < 1:
        raise ValueError(f"runs must be an integer >= 1, got {runs!r}")
    if not isinstance(batch, int) or batch < 1:
        raise ValueError(f"batch must be an integer >= 1, got {batch!r}")
    sc = chain.scenario
    n_steps = max(1, math.ceil(duration / step - 1e-9))
    edges = sc.time.start + np.minimum(np.arange(n_steps + 1) * step, duration)
    arrays = chain.compute(edges[:-1])  # probabilities held over each step
    p = {task: arrays[task] for task in _TASKS}  # (n_s, n_g, n_steps)
    in_view = arrays["in_view"]
    n_s, n_g = in_view.shape[:2]
    starts = in_view & ~np.concatenate([np.zeros((n_s, n_g, 1), bool), in_view[..., :-1]], axis=-1)
    keys = np.array(
        [[stream_key(seed, s, t) for t in chain.target_names] for s in chain.sensor_names],
        dtype=np.uint64,
    )  # (n_s, n_g, 2)
    k0, k1 = keys[..., 0][None], keys[..., 1][None]
    search_time = sc.model.search_time
    times = {task: np.full((runs, n_s, n_g), np.inf) for task in _TASKS}
    for first in range(0, runs, batch):
        run = np.arange(first, min(first + batch, runs)).reshape(-1, 1, 1)
        shape = (run.shape[0], n_s, n_g)
        u = np.ones(shape)
        clock = np.zeros(shape)
        hazard = np.zeros(shape)
        state = np.zeros(shape, dtype=np.int8)  # tasks done in this episode: 0..3
        found = {task: np.full(shape, np.inf) for task in _TASKS}
        for k in range(n_steps):
            t0, t1 = edges[k], edges[k + 1]
            new = starts[..., k][None] & np.ones(shape, dtype=bool)
            if new.any():
                u = np.where(new, uniforms((k0, k1), k, run, _CAPABILITY), u)
                clock = np.where(new, -np.log(uniforms((k0, k1), k, run, _CLOCK)), clock)
                hazard = np.where(new, 0.0, hazard)
                state = np.where(new, 0, state)
            view = in_view[..., k][None]
            state = np.where(view, state, 0)  # out of view: the episode is over
            p_det = p["detection"][..., k][None]
            rate = np.where(view & (u < p_det), p_det / search_time, 0.0)
            crossing = (state == 0) & (rate > 0) & (hazard + rate * (t1 - t0) >= clock)
            with np.errstate(divide="ignore", invalid="ignore"):
                at = t0 + (clock - hazard) / np.where(rate > 0, rate, 1.0)
            hazard = hazard + rate * (t1 - t0)
            detected_at = np.where(crossing, np.clip(at, t0, t1), np.inf)
            state = np.where(crossing, 1, state)
            found["detection"] = np.minimum(found["detection"], detected_at)
            moment = np.where(crossing, detected_at, t0)
            for level, task in ((1, "recognition"), (2, "identification")):
                ready = view & (state == level) & (u < p[task][..., k][None])
                found[task] = np.minimum(found[task], np.where(ready, moment, np.inf))
                state = np.where(ready, level + 1, state)
        for task in _TASKS:
            times[task][first : first + shape[0]] = found[task]
        if progress is not None:
            progress(shape[0])
    fused = {task: times[task].min(axis=1) for task in _TASKS}
    return SimulationResult(
        times=times,
        fused=fused,
        sensors=list(chain.sensor_names),
        targets=list(chain.target_names),
        duration=float(duration),
    )
