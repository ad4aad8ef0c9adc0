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

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from targetacq import _arrays
from targetacq import transforms as _transforms
from targetacq.criteria import Criterion, get_criterion
from targetacq.noise import NoiseModel, effective_scr, get_noise_model, noise_n50_factor

__all__ = [
    "Acquisition",
    "acquisition_probabilities",
    "effect_probability",
    "ordered_probabilities",
    "probability",
]

_TASKS = ("detection", "recognition", "identification")


def _noisy(n: Any, snr: Any, noise: NoiseModel | None, xp: Any) -> Any:
    """N / f: multiplying every N50 by the noise factor f is dividing N by it (noise.py)."""
    if noise is None:
        return n
    factor = _arrays.as_float(noise_n50_factor(_arrays.as_float(snr, xp), noise), xp)
    infinite = xp.isinf(factor)
    return xp.where(infinite, 0.0 * n, n / xp.where(infinite, 1.0, factor))


def _flag(value: Any, xp: Any) -> Any:
    return value if isinstance(value, bool) else xp.asarray(value)


def _detection_in_clutter(
    n: Any,
    n_noisy: Any,
    n50: Any,
    *,
    scr: Any,
    region: str | None,
    hot_spot: Any,
    moving: Any,
    snr: Any,
    noise: NoiseModel | None,
    xp: Any,
) -> Any:
    """P(detection) from Table 3.5 (Schmieder–Weathersby), with noise per the noise model.

    With a noise model that combines with clutter and an SCR, the curve is read at the effective
    ratio (:func:`targetacq.noise.effective_scr`) with the noise-free N; otherwise at the SCR with
    the noisy N. Hot spots use the low-clutter curve (§3.9); moving targets are detected
    (§1.3). ``hot_spot`` and ``moving`` are bools or bool arrays broadcasting with ``n``.
    """
    if noise is not None and noise.combines_with_clutter and scr is not None:
        scr = effective_scr(scr, snr)  # read at R_eff, with the noise-free N
    else:
        n = n_noisy
    out = None
    if scr is not None or region is not None:
        out = _transforms.schmieder_weathersby(n, n50, scr=scr, region=region)
    if hot_spot is not False:
        hot = _transforms.schmieder_weathersby(n, n50, hot_spot=True)
        out = hot if out is None or hot_spot is True else xp.where(_flag(hot_spot, xp), hot, out)
    if moving is not False:
        seen = xp.where(xp.isnan(n), n, xp.ones_like(n))
        out = seen if out is None or moving is True else xp.where(_flag(moving, xp), seen, out)
    if out is None:
        raise ValueError(
            "schmieder-weathersby needs the clutter: give scr (signal-to-clutter ratio), "
            "region ('low', 'medium', 'high'), hot_spot=True or moving=True"
        )
    return out


def ordered_probabilities(
    cycles: Any,
    n50: Sequence[Any],
    transform: _transforms.Transform,
    options: Mapping[str, Any],
    *,
    scr: Any = None,
    region: str | None = None,
    hot_spot: Any = False,
    moving: Any = False,
    snr: Any = None,
    noise: NoiseModel | None = None,
) -> tuple[Any, Any, Any]:
    """Ordered probabilities of detection, recognition and identification (no input checks).

    The one implementation behind :func:`acquisition_probabilities`, the array core and the
    range solver. Recognition and identification come from ``transform``; detection too, except
    in clutter (an SCR, a region, or where ``hot_spot`` or ``moving``), where it comes from the
    Schmieder–Weathersby transform (§3.8). Noise multiplies every N50 by the noise model's
    factor. Then ``P_rec <= P_det`` and ``P_id <= P_rec``. Traceable by JAX.

    Parameters
    ----------
    cycles : array
        N [cycles].
    n50 : sequence of 3 floats or arrays
        N50 of detection, recognition, identification, broadcasting with ``cycles``.
    transform : Transform
    options : mapping
        The transform's options.
    scr, region, hot_spot, moving, snr, noise
        The clutter (``hot_spot`` and ``moving`` bools or bool arrays), the SNR [dB] and the
        noise model (None: no noise).

    Returns
    -------
    detection, recognition, identification : array
    """
    xp, (n,) = _arrays.arrays(cycles)
    n_noisy = _noisy(n, snr, noise, xp)
    scalar = all(isinstance(v, float) for v in n50)
    if transform.name == "ttpf" and isinstance(n_noisy, np.ndarray) and scalar:
        det, rec, ide = _ttpf_three_numpy(n_noisy, tuple(n50))  # the hot path, fused
    else:
        det, rec, ide = (
            _arrays.as_float(transform.forward(n_noisy, v, task, **options), xp)
            for v, task in zip(n50, _TASKS, strict=True)
        )
    if scr is not None or region is not None:
        flagged: Any = True
    elif isinstance(hot_spot, bool) and isinstance(moving, bool):
        flagged = hot_spot or moving
    else:
        flagged = xp.asarray(hot_spot) | xp.asarray(moving)
    if flagged is not False:
        in_clutter = _detection_in_clutter(
            n,
            n_noisy,
            n50[0],
            scr=scr,
            region=region,
            hot_spot=hot_spot,
            moving=moving,
            snr=snr,
            noise=noise,
            xp=xp,
        )
        det = in_clutter if flagged is True else xp.where(flagged, in_clutter, det)
    xp, (det, rec, ide) = _arrays.arrays(det, rec, ide)
    rec = xp.minimum(rec, det)
    return det, rec, xp.minimum(ide, rec)


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
    noise = get_noise_model(noise_model) if snr is not None else None
    chosen.check(task, options)
    xp, (n,) = _arrays.arrays(cycles)
    _arrays.require_nonnegative("cycles", n, xp)
    n_noisy = _noisy(n, snr, noise, xp)
    if task == "detection" and (scr is not None or region is not None or hot_spot or moving):
        _transforms.check_clutter(scr, region, xp)
        found = _detection_in_clutter(
            n,
            n_noisy,
            n50,
            scr=scr,
            region=region,
            hot_spot=hot_spot,
            moving=moving,
            snr=snr,
            noise=noise,
            xp=xp,
        )
        return _arrays.result(found)
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
    n50s = [crit.n50(task) for task in _TASKS]
    for task in _TASKS:
        chosen.check(task, options)
    noise = get_noise_model(noise_model) if snr is not None else None
    xp, (n,) = _arrays.arrays(cycles)
    _arrays.require_nonnegative("cycles", n, xp)
    _transforms.check_clutter(scr, region, xp)
    det, rec, ide = ordered_probabilities(
        n,
        n50s,
        chosen,
        options,
        scr=scr,
        region=region,
        hot_spot=hot_spot,
        moving=moving,
        snr=snr,
        noise=noise,
    )
    return Acquisition(
        detection=_arrays.result(det),
        recognition=_arrays.result(rec),
        identification=_arrays.result(ide),
    )
