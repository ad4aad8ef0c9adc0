"""From cycles on target (and clutter) to the probabilities of detection, recognition and
identification for one sensor.

Sources: Sonesson (2004) ch. 2–3: the tasks and their criteria (§3.5–3.6), clutter acting on
detection only (§3.7–3.8), hot spots (§3.9), moving targets (§1.3, §7.5) and the combined
probability ``P_effect = P_det · P_rec · P_id``, Eq. (2.5).

Clutter never helps. Without a clutter measure detection comes from the chosen transform and
criterion; with one, from the Schmieder–Weathersby transform (Table 3.5), capped by the
uncluttered value: ``P_det = min(P_transform(N), P_SW(N, SCR))``. Otherwise a low clutter
(whose Table 3.5 curve, with Johnson's scaling, has its 50 % point at half the criterion's
N50) would raise detection above the uncluttered answer.

Motion (:data:`MOTION_RULES`). Motion raises detectability but creates no resolution: by
default a moving target is detected as in low clutter, at Table 3.5's most favourable 50 %
point, so its detection still falls with range; ``always`` is the thesis read literally.

Semantics (:data:`ACQUISITION_SEMANTICS`). Johnson's probabilities are marginal ones, yet
nothing is recognised that was not detected. ``nested`` (default) reads the curves as the
probabilities of the three events and caps ``P_rec <= P_det``, ``P_id <= P_rec`` (in heavy
clutter the detection curve of Table 3.5 can fall below the recognition curve, §3.7: "detection
levels are closing in on recognition levels"); ``P_effect`` is then ``P_id``. ``conditional``
reads them as Eq. (2.5) does: recognition given detection, identification given recognition;
the events have probabilities ``P_det``, ``P_det·P_rec`` and ``P_det·P_rec·P_id = P_effect``.
:func:`probability` of a single task is the uncapped value of its curve.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np

from targetacq.acquisition import cues as _cues
from targetacq.acquisition import transforms as _transforms
from targetacq.acquisition.criteria import Criterion, get_criterion
from targetacq.acquisition.path_noise import (
    NoiseModel,
    effective_scr,
    effective_scr_of_ratio,
    get_noise_model,
    noise_n50_factor,
)
from targetacq.acquisition.path_noise import noise_ratio as _noise_ratio_of
from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.base.registry import lookup

__all__ = [
    "ACQUISITION_SEMANTICS",
    "MOTION_RULES",
    "Acquisition",
    "Clutter",
    "MotionRule",
    "Semantics",
    "acquisition_probabilities",
    "effect_probability",
    "get_motion_rule",
    "get_semantics",
    "given_clutter",
    "ordered_probabilities",
    "probability",
]

_TASKS = ("detection", "recognition", "identification")


@dataclass(frozen=True)
class Clutter:
    """The clutter acting on detection (§3.7–3.9 in Sonesson (2004)): one record for the four
    inputs of the Schmieder–Weathersby transform and the motion rule.

    The functions that take it check its values (:func:`probability`,
    :func:`acquisition_probabilities`); a mapping with these keys may stand for it there.

    Attributes
    ----------
    scr : array_like, optional
        Signal-to-clutter ratio [1], >= 0 (+inf: no clutter), broadcasting with the cycles.
    region : {"low", "medium", "high"}, optional
        Table 3.5 clutter region, instead of ``scr``.
    hot_spot : bool or array of bool
        The target is a hot spot: detected on the low-clutter curve (§3.9).
    moving : bool or array of bool
        The target moves: detected by the motion rule (:data:`MOTION_RULES`).
    hot_spot_ratio : array_like, optional
        A graded hot spot (:mod:`targetacq.acquisition.cues`): the hot spot's own
        signal-to-clutter ratio [1], >= 0, when it fills a resolution element; its weight
        :func:`targetacq.acquisition.cues.hot_spot_weight` blends the low-clutter curve in.
        ``hot_spot=True`` is the full weight.
    hot_spot_size : array_like, optional
        The hot spot's linear size over the critical dimension [1], >= 0: it covers
        ``(2 N · size)²`` resolution elements at N cycles (one cycle is two, Fig. 3.3), and a
        hot spot smaller than one element is diluted; None for no dilution.
    speed : array_like, optional
        A graded motion cue: the target's speed across the line of sight over its critical
        dimension [1/s], >= 0; at N cycles it crosses ``2 N · speed`` pixels per second, whose
        weight :func:`targetacq.acquisition.cues.motion_weight` blends the motion rule in.
        ``moving=True`` is the full weight.

    Examples
    --------
    >>> Clutter(scr=5.0).given
    {'scr': 5.0}
    >>> Clutter().given
    {}
    """

    scr: Array | None = None
    region: str | None = None
    hot_spot: bool | Array = False
    moving: bool | Array = False
    hot_spot_ratio: Array | None = None
    hot_spot_size: Array | None = None
    speed: Array | None = None

    @property
    def given(self) -> dict[str, Any]:
        """The inputs given (not None, not False), as keyword arguments: the options of a
        detection-in-clutter transform chosen by name."""
        return {
            name: getattr(self, name)
            for name in _CLUTTER_KEYS
            if getattr(self, name) is not None and getattr(self, name) is not False
        }

    @property
    def cued(self) -> bool:
        """Whether a hot spot or motion acts, switched or graded."""
        return (
            self.hot_spot is not False
            or self.moving is not False
            or self.hot_spot_ratio is not None
            or self.speed is not None
        )

    def cue_weights(self, cycles: Any, xp: Any) -> tuple[Any, Any]:
        """The weights of the hot-spot and motion cues at N cycles (None: that cue is absent).

        A flag is the full weight (1 where set, 0 elsewhere); a graded input gives
        :func:`targetacq.acquisition.cues.hot_spot_weight` of the hot spot's SCR and the
        ``(2 N · hot_spot_size)²`` elements it covers, and
        :func:`targetacq.acquisition.cues.motion_weight` of ``2 N · speed`` pixels per second;
        with both, the larger.
        """
        w_hot = w_move = None
        if self.hot_spot_ratio is not None:
            ratio = _arrays.as_float(self.hot_spot_ratio, xp, "hot_spot_ratio")
            if self.hot_spot_size is not None:
                covered = 2.0 * cycles * _arrays.as_float(self.hot_spot_size, xp, "hot_spot_size")
                ratio = ratio * xp.minimum(covered * covered, 1.0)
            w_hot = _cues.weight_of(ratio, _cues.HOT_SPOT_RATIO_50, _cues.CUE_SLOPE, xp)
        if self.speed is not None:
            rate = 2.0 * cycles * _arrays.as_float(self.speed, xp, "speed")
            w_move = _cues.weight_of(rate, _cues.MOTION_RATE_50, _cues.CUE_SLOPE, xp)
        if self.hot_spot is not False:
            flag = _flag_weight(self.hot_spot, xp)
            w_hot = flag if w_hot is None else xp.maximum(w_hot, flag)
        if self.moving is not False:
            flag = _flag_weight(self.moving, xp)
            w_move = flag if w_move is None else xp.maximum(w_move, flag)
        return w_hot, w_move

    def check_cues(self, xp: Any) -> None:
        """Raise ``ValueError`` for a negative graded input, or a size without a ratio."""
        for name, unit in (("hot_spot_ratio", ""), ("hot_spot_size", ""), ("speed", "1/s")):
            value = getattr(self, name)
            if value is not None:
                checked = _arrays.as_float(value, xp, name)
                _arrays.require_nonnegative(name, checked, xp, unit)
                _arrays.require_finite(name, checked, xp, unit)
        if self.hot_spot_size is not None and self.hot_spot_ratio is None:
            raise ValueError("hot_spot_size grades a hot spot: give its hot_spot_ratio too")


_NO_CLUTTER = Clutter()
_CLUTTER_KEYS = (
    "scr",
    "region",
    "hot_spot",
    "moving",
    "hot_spot_ratio",
    "hot_spot_size",
    "speed",
)


def _as_clutter(clutter: Clutter | Mapping[str, Any] | None) -> Clutter:
    """``clutter`` as a :class:`Clutter` (None: none); a mapping's unknown key raises."""
    if clutter is None:
        return _NO_CLUTTER
    if isinstance(clutter, Clutter):
        return clutter
    if not isinstance(clutter, Mapping):
        raise TypeError(
            f"clutter must be a Clutter or a mapping of {', '.join(_CLUTTER_KEYS)}; got "
            f"{type(clutter).__name__}"
        )
    unknown = [key for key in clutter if key not in _CLUTTER_KEYS]
    if unknown:
        raise ValueError(
            f"clutter: unknown key(s) {', '.join(map(repr, unknown))}; valid keys: "
            f"{', '.join(_CLUTTER_KEYS)}"
        )
    return Clutter(**clutter)


def _noisy(n: Any, snr: Any, noise: NoiseModel | None, xp: Any, ratio: Any = None) -> Any:
    """N / f: multiplying every N50 by the noise factor f is dividing N by it (noise.py).

    ``ratio``, NumPy only, is the noise-to-signal amplitude ratio of ``snr``
    (:func:`targetacq.acquisition.path_noise.noise_ratio`): the built-in models take f from it
    directly.
    """
    if noise is None:
        return n
    if ratio is not None and noise.ratio_factor is not None:
        factor = noise.ratio_factor(ratio, np)
    else:
        factor = _arrays.as_float(noise_n50_factor(_arrays.as_float(snr, xp, "snr"), noise), xp)
    infinite = xp.isinf(factor)
    if isinstance(factor, np.ndarray) and isinstance(n, np.ndarray) and not infinite.any():
        return n / factor
    # No signal left (f = inf): nothing resolved, N = 0, whatever N (NaN stays NaN).
    nothing = xp.where(xp.isnan(n), n, xp.zeros_like(n))
    return xp.where(infinite, nothing, n / xp.where(infinite, 1.0, factor))


def _check_shapes(n: Any, snr: Any, scr: Any, xp: Any) -> None:
    """Raise ``ValueError`` naming cycles, snr and scr and their shapes unless they broadcast."""
    given = {name: v for name, v in (("snr", snr), ("scr", scr)) if v is not None}
    values = [_arrays.as_float(v, xp, name) for name, v in given.items()]
    _arrays.check_broadcast(("cycles", *given), (n, *values))


def _flag_weight(value: Any, xp: Any) -> Any:
    """A flag (bool or bool array) as a cue's weight: 1.0 where set, 0.0 elsewhere."""
    if isinstance(value, bool):
        return 1.0 if value else 0.0
    return xp.where(xp.asarray(value), 1.0, 0.0)


# --------------------------------------------------------------------------------------------
# Motion rules and acquisition semantics (registries)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class MotionRule:
    """How a moving target is detected.

    Attributes
    ----------
    name : str
    detection : callable
        ``detection(n_noisy, n50, transform, options, xp) -> P`` of a moving target.
    cycles_needed : callable
        ``cycles_needed(p, n50, transform, options) -> N``: its inverse, without noise.
    source : str
    """

    name: str
    detection: Callable[..., Any]
    cycles_needed: Callable[..., Any]
    source: str


def low_clutter_scale() -> float:
    """Table 3.5's low-clutter 50 % point over its medium-clutter reference (0.5 / 1.0)."""
    n50 = _transforms.sw_region_n50()  # computed once
    return n50["low"] / n50["medium"]


def _moving_low_clutter(n: Any, n50: Any, transform: Any, options: Any, xp: Any) -> Any:
    return _arrays.as_float(
        transform.forward(n, n50 * low_clutter_scale(), "detection", **options), xp
    )


def _moving_low_clutter_needed(p: Any, n50: Any, transform: Any, options: Any) -> Any:
    return transform.inverse(p, n50 * low_clutter_scale(), "detection", **options)


def _moving_always(n: Any, n50: Any, transform: Any, options: Any, xp: Any) -> Any:
    return xp.where(xp.isnan(n), n, xp.ones_like(n))


def _moving_always_needed(p: Any, n50: Any, transform: Any, options: Any) -> Any:
    xp, (p_,) = _arrays.arrays(p)
    return xp.where(xp.isnan(p_), p_, xp.zeros_like(p_))


MOTION_RULES: Mapping[str, MotionRule] = MappingProxyType(
    {
        "low-clutter": MotionRule(
            "low-clutter",
            _moving_low_clutter,
            _moving_low_clutter_needed,
            "project assumption: motion separates the target from its background, so it is "
            "detected as in low clutter (Table 3.5's most favourable 50 % point, 0.5 of the "
            "medium-clutter 1.0 cycle, applied to the criterion's detection N50 on the chosen "
            "transform), whatever the clutter; noise still applies and motion creates no "
            "resolution (Sonesson 2004 §1.3, §3.8, Table 3.5)",
        ),
        "always": MotionRule(
            "always",
            _moving_always,
            _moving_always_needed,
            "Sonesson (2004) §1.3, §7.5 read literally: a moving target is always detected "
            "(P = 1 at any range, with any noise)",
        ),
    }
)
"""Motion rules by name (read-only); ``low-clutter`` is the default."""


@dataclass(frozen=True)
class Semantics:
    """What the three task probabilities mean, and so what is sampled and reported.

    Attributes
    ----------
    name : str
    events : callable
        ``events(det, rec, ide, xp) -> (P(detected), P(recognised), P(identified))`` from the
        three curves' values.
    source : str
    """

    name: str
    events: Callable[..., tuple[Any, Any, Any]]
    source: str


def _nested_events(det: Any, rec: Any, ide: Any, xp: Any) -> tuple[Any, Any, Any]:
    rec = xp.minimum(rec, det)
    return det, rec, xp.minimum(ide, rec)


def _conditional_events(det: Any, rec: Any, ide: Any, xp: Any) -> tuple[Any, Any, Any]:
    recognised = det * rec
    return det, recognised, recognised * ide


ACQUISITION_SEMANTICS: Mapping[str, Semantics] = MappingProxyType(
    {
        "nested": Semantics(
            "nested",
            _nested_events,
            "Johnson's curves are marginal probabilities of each task (Sonesson 2004 §3.5); "
            "nothing is recognised that was not detected, so P_rec <= P_det and "
            "P_id <= P_rec are enforced; P(identified) = P_effect = P_id",
        ),
        "conditional": Semantics(
            "conditional",
            _conditional_events,
            "Eq. (2.5) in Sonesson (2004): recognition given detection, identification given "
            "recognition; P(recognised) = P_det·P_rec, P(identified) = P_effect = "
            "P_det·P_rec·P_id",
        ),
    }
)
"""Acquisition semantics by name (read-only); ``nested`` is the default.

Both are sampled by the same nested draw (one uniform ``u``; detected ``u < P(detected)``,
recognised ``u < P(recognised)``, identified ``u < P(identified)``): with the conditional event
probabilities this gives ``P(recognised | detected) = P_rec`` and
``P(identified | recognised) = P_id`` exactly, so the sampled frequencies are the reported
probabilities for either semantics.
"""


def get_motion_rule(name: str | MotionRule) -> MotionRule:
    """Resolve a motion rule by name (``ValueError`` listing the valid names if unknown)."""
    return name if isinstance(name, MotionRule) else lookup(MOTION_RULES, name, "motion rule")


def get_semantics(name: str | Semantics) -> Semantics:
    """Resolve acquisition semantics by name (``ValueError`` listing the valid names)."""
    return name if isinstance(name, Semantics) else lookup(ACQUISITION_SEMANTICS, name, "semantics")


def _detection_in_clutter(
    n: Any,
    n_noisy: Any,
    n50: Any,
    uncluttered: Any,
    *,
    scr: Any,
    region: str | None,
    w_hot: Any,
    w_move: Any,
    snr: Any,
    noise: NoiseModel | None,
    motion: MotionRule,
    transform: _transforms.Transform,
    options: Mapping[str, Any],
    xp: Any,
    ratio: Any = None,
) -> Any:
    """P(detection) in clutter, of hot spots and of moving targets.

    - Clutter (an SCR or a region): the Schmieder–Weathersby transform (Table 3.5, continuous
      in the SCR), read at the effective ratio of clutter and noise
      (:func:`targetacq.acquisition.path_noise.effective_scr`) with the noise-free N where the noise
      model combines with clutter, else at the SCR with the noisy N; never above the uncluttered
      probability ``uncluttered`` (clutter can only make detection harder).
    - Hot spots: the low-clutter curve (§3.9) at the noisy N, whatever the clutter, blended in
      by the hot-spot weight: ``P = (1 − w_hot) P + w_hot P_low``.
    - Moving targets: the motion rule (:data:`MOTION_RULES`) at the noisy N, whatever the
      clutter, blended in by the motion weight: ``P = (1 − w_move) P + w_move max(P_motion, P)``
      (a moving hot spot takes the better of the two).

    ``w_hot`` and ``w_move`` (:meth:`Clutter.cue_weights`; None: that cue is absent) are in
    [0, 1], broadcasting with ``n``: a flag is 1 where set and 0 elsewhere, so the switched
    model is the limit, to the last bit (:mod:`targetacq.acquisition.cues`). ``ratio`` (NumPy)
    is the noise-to-signal amplitude ratio of ``snr``
    (:func:`targetacq.acquisition.path_noise.noise_ratio`).
    """
    out = None
    if scr is not None or region is not None:
        if noise is not None and noise.combines_with_clutter and scr is not None:
            if ratio is not None:  # NumPy, with the noise-to-signal ratio at hand
                seen = _transforms.sw_probability(
                    n, n50, effective_scr_of_ratio(_arrays.as_float(scr, np), ratio, np), None, np
                )
            else:
                seen = _transforms.schmieder_weathersby(n, n50, scr=effective_scr(scr, snr))
        elif isinstance(n_noisy, np.ndarray) and (scr is None or isinstance(scr, np.ndarray)):
            seen = _transforms.sw_probability(n_noisy, n50, scr, region, np)
        else:
            seen = _transforms.schmieder_weathersby(n_noisy, n50, scr=scr, region=region)
        out = xp.minimum(_arrays.as_float(seen, xp), uncluttered)
    if w_hot is not None or w_move is not None:
        # (1 − w) a + w b: exactly a at w = 0 and exactly b at w = 1 (the switches).
        found = uncluttered if out is None else out
        if w_hot is not None:
            hot = _arrays.as_float(_transforms.sw_probability(n_noisy, n50, None, "low", xp), xp)
            found = (1.0 - w_hot) * found + w_hot * hot
        if w_move is not None:
            go = _arrays.as_float(motion.detection(n_noisy, n50, transform, options, xp), xp)
            # The motion rule is never below the plain curve; a hot spot's can be above it.
            better = go if w_hot is None else xp.where(w_hot > 0, xp.maximum(go, found), go)
            found = (1.0 - w_move) * found + w_move * better
        out = found
    if out is None:
        raise ValueError(
            "detection in clutter needs the clutter: a signal-to-clutter ratio (scr), "
            "a clutter region (low, medium, high), a hot spot or a moving target"
        )
    return out


def ordered_probabilities(
    cycles: Array,
    n50: Sequence[Any],
    transform: _transforms.Transform,
    options: Mapping[str, Any],
    *,
    clutter: Clutter | None = None,
    snr: Array | None = None,
    noise: NoiseModel | None = None,
    motion: MotionRule | str = "low-clutter",
    semantics: Semantics | str = "nested",
    noise_ratio: Array | None = None,
) -> tuple[Any, Any, Any]:
    """Probabilities of being detected, recognised and identified (no input checks).

    The one implementation behind :func:`acquisition_probabilities`, the array core and the
    range solver. Recognition and identification come from ``transform``; detection too, except
    in clutter (an SCR, a region), for hot spots and for moving targets, where it comes from
    :func:`_detection_in_clutter` (§3.8–3.9). Noise multiplies every N50 by the noise model's
    factor. The semantics then turn the three curves into the probabilities of the three events
    (:data:`ACQUISITION_SEMANTICS`; ``nested``: ``P_rec <= P_det``, ``P_id <= P_rec``).
    Traceable by JAX.

    Parameters
    ----------
    cycles : array
        N [cycles].
    n50 : sequence of 3 floats or arrays
        N50 of detection, recognition, identification, broadcasting with ``cycles``.
    transform : Transform
    options : mapping
        The transform's options.
    clutter : Clutter, optional
        The clutter (``hot_spot`` and ``moving`` bools or bool arrays); None for none.
    snr, noise
        The SNR [dB] and the noise model (None: no noise).
    motion : MotionRule or str
        How a moving target is detected (:data:`MOTION_RULES`).
    semantics : Semantics or str
        :data:`ACQUISITION_SEMANTICS`.
    noise_ratio : numpy.ndarray, optional
        The noise-to-signal amplitude ratio ``10^(−snr/20)``
        (:func:`targetacq.acquisition.path_noise.noise_ratio`), where the caller has it without the
        decibels (the array core, from the optical depth); NumPy only. By default it is taken from
        ``snr`` once, for the noise factor and the effective SCR alike.

    Returns
    -------
    detection, recognition, identification : array
    """
    given = _NO_CLUTTER if clutter is None else clutter
    scr, region = given.scr, given.region
    xp, (n,) = _arrays.arrays(cycles, names=("cycles",))
    ratio = noise_ratio
    numpy = isinstance(n, np.ndarray)
    if ratio is None and noise is not None and numpy and isinstance(snr, np.ndarray):
        ratio = _noise_ratio_of(snr)  # once: the noise factor and the effective SCR use it
    n_noisy = _noisy(n, snr, noise, xp, ratio if numpy else None)
    scalar = all(isinstance(v, float) for v in n50)
    if transform.name == "ttpf" and isinstance(n_noisy, np.ndarray) and scalar:
        det, rec, ide = _ttpf_three_numpy(n_noisy, tuple(n50))  # the hot path, fused
    else:
        det, rec, ide = (
            _arrays.as_float(transform.forward(n_noisy, v, task, **options), xp)
            for v, task in zip(n50, _TASKS, strict=True)
        )
    if scr is not None or region is not None or given.cued:
        w_hot, w_move = given.cue_weights(n, xp)
        det = _detection_in_clutter(
            n,
            n_noisy,
            n50[0],
            det,
            scr=scr,
            region=region,
            w_hot=w_hot,
            w_move=w_move,
            snr=snr,
            noise=noise,
            motion=get_motion_rule(motion),
            transform=transform,
            options=options,
            xp=xp,
            ratio=ratio if numpy else None,
        )
    xp, (det, rec, ide) = _arrays.arrays(det, rec, ide)
    return get_semantics(semantics).events(det, rec, ide, xp)


def given_clutter(clutter: Clutter | Mapping[str, Any] | None) -> dict[str, Any]:
    """The clutter inputs given (not None, not False): the options of a detection-in-clutter
    transform chosen by name (:attr:`Clutter.given`)."""
    return _as_clutter(clutter).given


def probability(
    cycles: Array,
    task: str,
    criterion: str | Criterion | Mapping[str, float] = "johnson",
    transform: str = "ttpf",
    *,
    clutter: Clutter | Mapping[str, Any] | None = None,
    snr: Array | None = None,
    noise_model: Any = "variance-sum",
    motion: str = "low-clutter",
    **options: Any,
) -> Any:
    """Probability of one task from cycles on target (the task's marginal curve).

    Detection in clutter (``clutter.scr`` or ``.region``), of a hot spot or of a moving target comes
    from the Schmieder–Weathersby transform and the motion rule (§3.8–3.9), capped in clutter
    by the uncluttered curve; everything else from ``transform``. Noise (``snr``) moves the
    curves as the noise model says (:mod:`targetacq.acquisition.path_noise`).

    Parameters
    ----------
    cycles : array_like
        N, resolvable cycles across the critical dimension [cycles], >= 0.
    task : str
        "detection", "orientation", "recognition" or "identification" (as the criterion has).
    criterion : str, Criterion or mapping
        Criteria set giving N50 for the task (see :data:`targetacq.acquisition.criteria.CRITERIA`),
        or a user-defined task → N50 mapping.
    transform : str
        A name from :data:`targetacq.acquisition.transforms.TRANSFORMS`.
    clutter : Clutter or mapping, optional
        The clutter (:class:`Clutter`, or a mapping of its fields), see
        :func:`targetacq.acquisition.transforms.schmieder_weathersby`; ignored for tasks other than
        detection (clutter acts on detection, §3.8). None for none.
    snr : array_like, optional
        Signal-to-noise ratio [dB]; None or +inf for no noise.
    noise_model : str, NoiseModel or callable
        See :mod:`targetacq.acquisition.path_noise`.
    motion : str
        How a moving target is detected, :data:`MOTION_RULES`.
    **options
        The transform's options (e.g. ``bound=`` for c2nveo); anything else raises ``ValueError``.

    Returns
    -------
    array_like
        P in [0, 1].

    Examples
    --------
    >>> round(float(probability(1.0, "detection")), 3)  # Johnson's N50 for detection
    0.5
    >>> float(probability(1.0, "detection", snr=float("-inf")))  # no signal left
    0.0
    >>> bool(probability(1.0, "detection", clutter=Clutter(scr=0.5)) < 0.5)  # high clutter
    True
    """
    given = _as_clutter(clutter)
    scr, region, hot_spot, moving = given.scr, given.region, given.hot_spot, given.moving
    n50 = get_criterion(criterion).n50(task)
    chosen = _transforms.get_transform(transform)
    noise = get_noise_model(noise_model) if snr is not None else None
    rule = get_motion_rule(motion)
    chosen.check(task, options)
    _arrays.require_flag("hot_spot", hot_spot, arrays=True)
    _arrays.require_flag("moving", moving, arrays=True)
    xp, (n,) = _arrays.arrays(cycles, names=("cycles",))
    _arrays.require_nonnegative("cycles", n, xp)
    _check_shapes(n, snr, scr, xp)
    given.check_cues(xp)
    n_noisy = _noisy(n, snr, noise, xp)
    if chosen.tasks == ("detection",):
        # A detection-in-clutter transform chosen by name: the clutter is its own input.
        chosen.check(task, {**given.given, **options})
        return chosen.forward(n_noisy, n50, task, **given.given, **options)
    plain = chosen.forward(n_noisy, n50, task, **options)
    clutter_given = scr is not None or region is not None
    if task == "detection" and (clutter_given or given.cued):
        _transforms.check_clutter(scr, region, xp)
        w_hot, w_move = given.cue_weights(n, xp)
        found = _detection_in_clutter(
            n,
            n_noisy,
            n50,
            _arrays.as_float(plain, xp),
            scr=scr,
            region=region,
            w_hot=w_hot,
            w_move=w_move,
            snr=snr,
            noise=noise,
            motion=rule,
            transform=chosen,
            options=options,
            xp=xp,
        )
        return _arrays.result(found)
    return plain


def effect_probability(detection: Array, recognition: Array, identification: Array) -> Any:
    """Combined probability ``P_effect = P_det · P_rec · P_id``, Eq. (2.5) in Sonesson (2004).

    Parameters
    ----------
    detection, recognition, identification : array_like
        Probabilities in [0, 1].

    Examples
    --------
    >>> import targetacq as ta
    >>> print(f"{ta.effect_probability(0.9, 0.5, 0.2):.4f}")
    0.0900
    """
    xp, (d, r, i) = _arrays.arrays(
        detection, recognition, identification, names=("detection", "recognition", "identification")
    )
    for name, p in (("detection", d), ("recognition", r), ("identification", i)):
        _arrays.require_unit_interval(name, p, xp)
    return _arrays.result(d * r * i)


@dataclass(frozen=True)
class Acquisition:
    """Per-task probabilities for one sensor (arrays of the broadcast input shape).

    Attributes
    ----------
    detection, recognition, identification : array_like
        Probabilities of being detected, recognised and identified under ``semantics``, with
        ``identification <= recognition <= detection``.
    semantics : str
        :data:`ACQUISITION_SEMANTICS`.

    Examples
    --------
    >>> import targetacq as ta
    >>> acq = ta.acquisition_probabilities(4.0)
    >>> print(f"{acq.detection:.4f} {acq.recognition:.4f} {acq.identification:.4f}")
    0.9995 0.5000 0.1862
    >>> acq.semantics
    'nested'
    """

    detection: Any
    recognition: Any
    identification: Any
    semantics: str = field(default="nested", kw_only=True)

    @property
    def effect(self) -> Any:
        """``P_effect``, the probability that all three tasks succeed: the probability of being
        identified under the semantics (``nested``: ``P_id``; ``conditional``: Eq. (2.5),
        ``P_det · P_rec · P_id`` of the curves)."""
        return self.identification


def _ttpf_three_numpy(n: np.ndarray, n50s: tuple[float, ...]) -> list[np.ndarray]:
    """TTPF for three N50s over a float64 NumPy array, fused and chunked to stay in cache.

    The same arithmetic as :func:`targetacq.acquisition.transforms.ttpf` (logistic of ``E·ln x``),
    with ``ln N`` taken once for the three tasks and the tasks as the rows of one array (one call of
    each operation per chunk for all three). Since the N50s increase with the task, the TTPF already
    gives ``P_id <= P_rec <= P_det`` here.
    """
    e0, limit = _transforms.TTPF_E0, _transforms.LOGIT_LIMIT
    flat = n.reshape(-1)
    size = flat.size
    scale, shift = _ttpf_constants(tuple(n50s))
    out = np.empty((len(n50s), size))
    chunk = 1 << 13
    log_n = np.empty(min(chunk, size))
    tmp = np.empty((len(n50s), log_n.size))
    with np.errstate(divide="ignore"):  # ln 0 = -inf, which the clip turns into P = 0
        for start in range(0, size, chunk):
            part = flat[start : start + chunk]
            m = part.size
            ln, t, o = log_n[:m], tmp[:, :m], out[:, start : start + m]
            np.log(part, out=ln)
            np.multiply(part, scale, out=t)
            t += e0
            np.subtract(ln, shift, out=o)
            o *= t  # z = E · ln x
            np.clip(o, -limit, limit, out=o)
            np.negative(o, out=o)
            np.exp(o, out=o)
            o += 1.0
            np.reciprocal(o, out=o)
    zero = flat == 0
    if zero.any():
        out[:, zero] = 0.0
    return [row.reshape(n.shape) for row in out]


@functools.lru_cache(maxsize=64)
def _ttpf_constants(n50s: tuple[float, ...]) -> tuple[np.ndarray, np.ndarray]:
    """Per task, ``e1 / N50`` and ``ln N50`` as columns: ``E = e0 + N · (e1 / N50)`` and
    ``ln x = ln N − ln N50``, as :func:`_ttpf_three_numpy` takes them."""
    e1 = _transforms.TTPF_E1
    scale = np.array([e1 / v for v in n50s])[:, None]
    shift = np.array([np.log(v) for v in n50s])[:, None]
    scale.flags.writeable = False
    shift.flags.writeable = False
    return scale, shift


def acquisition_probabilities(
    cycles: Array,
    criterion: str | Criterion | Mapping[str, float] = "johnson",
    transform: str = "ttpf",
    *,
    clutter: Clutter | Mapping[str, Any] | None = None,
    snr: Array | None = None,
    noise_model: Any = "variance-sum",
    motion: str = "low-clutter",
    semantics: str = "nested",
    **options: Any,
) -> Acquisition:
    """Probabilities of detection, recognition and identification, ordered, and P_effect.

    Recognition and identification come from ``transform``; so does detection, unless the
    clutter is given (``scr``, ``region``, ``hot_spot`` or ``moving`` of ``clutter``), in which
    case detection comes from the Schmieder–Weathersby transform and the motion rule (clutter
    acts on detection, §3.8), never above the uncluttered value. The semantics say what the three
    numbers mean (:data:`ACQUISITION_SEMANTICS`); either way ``P_id <= P_rec <= P_det``.

    Parameters
    ----------
    cycles : array_like
        N [cycles], >= 0.
    criterion : str, Criterion or mapping
        Needs N50 for detection, recognition and identification.
    transform : str
        Transform for the tasks (not "schmieder-weathersby", which covers detection only: give
        the clutter instead).
    clutter : Clutter or mapping, optional
        The clutter (:class:`Clutter`, or a mapping of its fields): the signal-to-clutter ratio
        ``scr`` broadcasting with ``cycles``, or a clutter ``region``; ``hot_spot`` and
        ``moving`` (see :func:`targetacq.acquisition.transforms.schmieder_weathersby`). None for
        none.
    snr : array_like, optional
        Signal-to-noise ratio [dB] (e.g. from
        :func:`targetacq.physics.atmosphere.snr_from_transmittance`), broadcasting with ``cycles``;
        None or +inf for no noise.
    noise_model : str, NoiseModel or callable
        How noise moves the transforms, see :mod:`targetacq.acquisition.path_noise` (default
        "variance-sum").
    motion : str
        How a moving target is detected, :data:`MOTION_RULES` (default "low-clutter").
    semantics : str
        :data:`ACQUISITION_SEMANTICS` (default "nested").
    **options
        Options of ``transform`` (e.g. ``bound=``).

    Returns
    -------
    Acquisition
        ``detection``, ``recognition``, ``identification`` and, on demand, ``effect``.

    Examples
    --------
    Johnson's N50s (1, 4, 6.4 cycles) through the TTPF at N = 1, 4 and 6.4: each task is 0.5 at
    its own N50.

    >>> import numpy as np
    >>> import targetacq as ta
    >>> acq = ta.acquisition_probabilities([1.0, 4.0, 6.4])
    >>> print(np.round(acq.detection, 4))
    [0.5    0.9995 1.    ]
    >>> print(np.round(acq.recognition, 4))
    [0.0182 0.5    0.8576]
    >>> print(np.round(acq.identification, 4))
    [0.0054 0.1862 0.5   ]

    Under the ``conditional`` semantics the events are the products of Eq. (2.5):

    >>> acq = ta.acquisition_probabilities(4.0, semantics="conditional")
    >>> print(f"{acq.recognition:.4f} {acq.detection * 0.5:.4f}")
    0.4998 0.4998
    """
    given = _as_clutter(clutter)
    scr, region, hot_spot, moving = given.scr, given.region, given.hot_spot, given.moving
    chosen = _transforms.get_transform(transform)
    if chosen.tasks is not None and "recognition" not in chosen.tasks:
        raise ValueError(
            f"transform {chosen.name!r} covers {', '.join(chosen.tasks)} only; for detection "
            "in clutter give the clutter (a signal-to-clutter ratio, a clutter region, a hot "
            "spot or a moving target) with a transform for all tasks, e.g. 'ttpf'"
        )
    crit = get_criterion(criterion)
    n50s = [crit.n50(task) for task in _TASKS]
    for task in _TASKS:
        chosen.check(task, options)
    noise = get_noise_model(noise_model) if snr is not None else None
    rule, meaning = get_motion_rule(motion), get_semantics(semantics)
    _arrays.require_flag("hot_spot", hot_spot, arrays=True)
    _arrays.require_flag("moving", moving, arrays=True)
    xp, (n,) = _arrays.arrays(cycles, names=("cycles",))
    _arrays.require_nonnegative("cycles", n, xp)
    _check_shapes(n, snr, scr, xp)
    _transforms.check_clutter(scr, region, xp)
    given.check_cues(xp)
    det, rec, ide = ordered_probabilities(
        n,
        n50s,
        chosen,
        options,
        clutter=given,
        snr=snr,
        noise=noise,
        motion=rule,
        semantics=meaning,
    )
    return Acquisition(
        detection=_arrays.result(det),
        recognition=_arrays.result(rec),
        identification=_arrays.result(ide),
        semantics=meaning.name,
    )
