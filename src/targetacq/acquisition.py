"""From cycles on target (and clutter) to the probabilities of detection, recognition and
identification for one sensor.

Sources: Sonesson (2004) ch. 2–3: the tasks and their criteria (§3.5–3.6), clutter acting on
detection only (§3.7–3.8), hot spots (§3.9), moving targets (§1.3, §7.5) and the combined
probability ``P_effect = P_det · P_rec · P_id``, Eq. (2.5).

Ordering. Johnson's probabilities are marginal ones, but nothing is recognised that was not
detected, nor identified that was not recognised. In heavy clutter the detection curve of
Table 3.5 can fall below the recognition curve (§3.7: "detection levels are closing in on
recognition levels"), so :func:`acquisition_probabilities` caps
``P_rec <= P_det`` and ``P_id <= P_rec`` for each N; :func:`probability` of a single task is the
uncapped marginal value of its curve.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from targetacq import _arrays
from targetacq import transforms as _transforms
from targetacq.criteria import Criterion, get_criterion
from targetacq.noise import NoiseModel, effective_scr, get_noise_model, noise_n50_factor

__all__ = ["Acquisition", "acquisition_probabilities", "effect_probability", "probability"]

_CLUTTER_KEYWORDS = ("scr", "region", "hot_spot", "moving")


@dataclass(frozen=True)
class _Conditions:
    """Clutter and noise around a target, validated once, shared by the tasks."""

    scr: Any
    region: str | None
    hot_spot: bool
    moving: bool
    snr: Any
    noise: NoiseModel | None

    @property
    def clutter_given(self) -> bool:
        return self.scr is not None or self.region is not None or self.hot_spot or self.moving


def _conditions(
    scr: Any, region: str | None, hot_spot: bool, moving: bool, snr: Any, noise_model: Any
) -> _Conditions:
    noise = get_noise_model(noise_model) if snr is not None else None
    return _Conditions(scr, region, hot_spot, moving, snr, noise)


def _noisy(n: Any, cond: _Conditions, xp: Any) -> Any:
    """N / f: multiplying every N50 by the noise factor f is dividing N by it (noise.py)."""
    if cond.noise is None:
        return n
    factor = _arrays.as_float(noise_n50_factor(_arrays.as_float(cond.snr, xp), cond.noise), xp)
    infinite = xp.isinf(factor)
    return xp.where(infinite, 0.0 * n, n / xp.where(infinite, 1.0, factor))


def _detection_in_clutter(n: Any, n_noisy: Any, n50: float, cond: _Conditions) -> Any:
    """P(detection) from Table 3.5 (Schmieder–Weathersby), with noise per the noise model."""
    scr = cond.scr
    if cond.noise is not None and cond.noise.combines_with_clutter and scr is not None:
        scr = effective_scr(scr, cond.snr)  # read at R_eff, with the noise-free N
    else:
        n = n_noisy
    return _transforms.schmieder_weathersby(
        n, n50, scr=scr, region=cond.region, hot_spot=cond.hot_spot, moving=cond.moving
    )


def probability(
    cycles: Any,
    task: str,
    criterion: str | Criterion | Mapping[str, float] = "johnson",
    transform: str = "ttpf",
    *,
    scr: Any = None,
    region: str | None = None,
    hot_spot: bool = False,
    moving: bool = False,
    snr: Any = None,
    noise_model: Any = "variance-sum",
    **options: Any,
) -> Any:
    """Probability of one task from cycles on target (the task's marginal curve).

    Detection in clutter (``scr``, ``region``, ``hot_spot`` or ``moving`` given) comes from the
    Schmieder–Weathersby transform (§3.8); everything else from ``transform``. Noise (``snr``)
    moves the curves as the noise model says (:mod:`targetacq.noise`).

    Parameters
    ----------
    cycles : array_like
        N, resolvable cycles across the critical dimension [cycles], >= 0.
    task : str
        "detection", "orientation", "recognition" or "identification" (as the criterion has).
    criterion : str, Criterion or mapping
        Criteria set giving N50 for the task (see :data:`targetacq.criteria.CRITERIA`), or a
        user-defined task → N50 mapping.
    transform : str
        A name from :data:`targetacq.transforms.TRANSFORMS`.
    scr, region, hot_spot, moving
        The clutter, see :func:`targetacq.transforms.schmieder_weathersby`; ignored for tasks
        other than detection (clutter acts on detection, §3.8).
    snr : array_like, optional
        Signal-to-noise ratio [dB]; None or +inf for no noise.
    noise_model : str, NoiseModel or callable
        See :mod:`targetacq.noise`.
    **options
        The transform's options (e.g. ``bound=`` for c2nveo); anything else raises ``ValueError``.

    Returns
    -------
    array_like
        P in [0, 1].
    """
    n50 = get_criterion(criterion).n50(task)
    chosen = _transforms.get_transform(transform)
    cond = _conditions(scr, region, hot_spot, moving, snr, noise_model)
    chosen.check(task, options)
    xp, (n,) = _arrays.arrays(cycles)
    _arrays.require_nonnegative("cycles", n, xp)
    n_noisy = _noisy(n, cond, xp)
    if task == "detection" and cond.clutter_given:
        return _arrays.result(_detection_in_clutter(n, n_noisy, n50, cond))
    return chosen.forward(n_noisy, n50, task, **options)


def effect_probability(detection: Any, recognition: Any, identification: Any) -> Any:
    """Combined probability ``P_effect = P_det · P_rec · P_id``, Eq. (2.5) in Sonesson (2004).

    Parameters
    ----------
    detection, recognition, identification : array_like
        Probabilities in [0, 1].
    """
    xp, (d, r, i) = _arrays.arrays(detection, recognition, identification)
    for name, p in (("detection", d), ("recognition", r), ("identification", i)):
        _arrays.require_unit_interval(name, p, xp)
    return _arrays.result(d * r * i)


@dataclass(frozen=True)
class Acquisition:
    """Per-task probabilities for one sensor (arrays of the broadcast input shape).

    Attributes
    ----------
    detection, recognition, identification : array_like
        Probabilities with ``identification <= recognition <= detection``.
    """

    detection: Any
    recognition: Any
    identification: Any

    @property
    def effect(self) -> Any:
        """``P_effect = P_det · P_rec · P_id``, Eq. (2.5), computed when asked for."""
        return effect_probability(self.detection, self.recognition, self.identification)


def _ttpf_three_numpy(n: np.ndarray, n50s: tuple[float, ...]) -> list[np.ndarray]:
    """TTPF for three N50s over a float64 NumPy array, fused and chunked to stay in cache.

    The same arithmetic as :func:`targetacq.transforms.ttpf` (logistic of ``E·ln x``), with
    ``ln N`` taken once for the three tasks. Since the N50s increase with the task, the TTPF
    already gives ``P_id <= P_rec <= P_det`` here.
    """
    e0, e1, limit = _transforms.TTPF_E0, _transforms.TTPF_E1, _transforms._LOGIT_LIMIT
    flat = n.reshape(-1)
    outs = [np.empty(flat.shape, dtype=np.float64) for _ in n50s]
    chunk = 1 << 14
    log_n = np.empty(min(chunk, flat.size))
    tmp = np.empty_like(log_n)
    for start in range(0, flat.size, chunk):
        part = flat[start : start + chunk]
        m = part.size
        ln, t = log_n[:m], tmp[:m]
        with np.errstate(divide="ignore"):
            np.log(part, out=ln)  # -inf at N = 0, which the clip turns into P = 0
        for out, n50 in zip(outs, n50s, strict=True):
            o = out[start : start + m]
            np.multiply(part, e1 / n50, out=t)
            t += e0
            np.subtract(ln, np.log(n50), out=o)
            o *= t  # z = E · ln x
            np.clip(o, -limit, limit, out=o)
            np.negative(o, out=o)
            np.exp(o, out=o)
            o += 1.0
            np.reciprocal(o, out=o)
    zero = flat == 0
    if zero.any():
        for out in outs:
            out[zero] = 0.0
    return [out.reshape(n.shape) for out in outs]


def acquisition_probabilities(
    cycles: Any,
    criterion: str | Criterion | Mapping[str, float] = "johnson",
    transform: str = "ttpf",
    *,
    scr: Any = None,
    region: str | None = None,
    hot_spot: bool = False,
    moving: bool = False,
    snr: Any = None,
    noise_model: Any = "variance-sum",
    **options: Any,
) -> Acquisition:
    """Probabilities of detection, recognition and identification, ordered, and P_effect.

    Recognition and identification come from ``transform``; so does detection, unless the
    clutter is given (``scr``, ``region``, ``hot_spot`` or ``moving``), in which case detection
    comes from the Schmieder–Weathersby transform (clutter acts on detection, §3.8).
    The result is capped so that ``P_id <= P_rec <= P_det`` (module docstring).

    Parameters
    ----------
    cycles : array_like
        N [cycles], >= 0.
    criterion : str, Criterion or mapping
        Needs N50 for detection, recognition and identification.
    transform : str
        Transform for the tasks (not "schmieder-weathersby", which covers detection only: give
        the clutter instead).
    scr : array_like, optional
        Signal-to-clutter ratio, broadcasting with ``cycles``.
    region : {"low", "medium", "high"}, optional
        Clutter region instead of ``scr``.
    hot_spot, moving : bool
        See :func:`targetacq.transforms.schmieder_weathersby`.
    snr : array_like, optional
        Signal-to-noise ratio [dB] (e.g. from :func:`targetacq.atmosphere.snr_from_transmittance`),
        broadcasting with ``cycles``; None or +inf for no noise.
    noise_model : str, NoiseModel or callable
        How noise moves the transforms, see :mod:`targetacq.noise` (default "variance-sum").
    **options
        Options of ``transform`` (e.g. ``bound=``).

    Returns
    -------
    Acquisition
        ``detection``, ``recognition``, ``identification`` and, on demand, ``effect``.
    """
    chosen = _transforms.get_transform(transform)
    if chosen.tasks is not None and "recognition" not in chosen.tasks:
        raise ValueError(
            f"transform {chosen.name!r} covers {', '.join(chosen.tasks)} only; use it for "
            "detection by giving the clutter (scr=, region=, hot_spot= or moving=) with a "
            "transform for all tasks, e.g. 'ttpf'"
        )
    crit = get_criterion(criterion)
    tasks = ("detection", "recognition", "identification")
    n50s = tuple(crit.n50(task) for task in tasks)
    for task in tasks:
        chosen.check(task, options)
    cond = _conditions(scr, region, hot_spot, moving, snr, noise_model)

    xp, (n,) = _arrays.arrays(cycles)
    _arrays.require_nonnegative("cycles", n, xp)
    n_noisy = _noisy(n, cond, xp)
    fast = (
        chosen.name == "ttpf" and isinstance(n_noisy, np.ndarray) and n50s[0] <= n50s[1] <= n50s[2]
    )
    if fast:
        # The simulation hot path; increasing N50s already give ordered probabilities.
        det, rec, ide = _ttpf_three_numpy(n_noisy, n50s)
    else:
        det, rec, ide = (
            chosen.forward(n_noisy, n50, task, **options)
            for task, n50 in zip(tasks, n50s, strict=True)
        )
    if cond.clutter_given:
        det = _detection_in_clutter(n, n_noisy, n50s[0], cond)
    if cond.clutter_given or not fast:
        xp, (det, rec, ide) = _arrays.arrays(det, rec, ide)
        rec = xp.minimum(rec, det)
        ide = xp.minimum(ide, rec)
    return Acquisition(
        detection=_arrays.result(det),
        recognition=_arrays.result(rec),
        identification=_arrays.result(ide),
    )
