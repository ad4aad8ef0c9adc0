"""Noise in the transforms: how a signal-to-noise ratio moves the N50 of each task.

The thesis found no published SNR transform (Sonesson 2004 ch. 4, §9.1) and states only the
intent: noise should shift the resolution-to-probability transform "in a similar way to that of
clutter" (§3.10), and its effects should show below about 10 dB. This module is the project's
documented assumption, replaceable through the registry :data:`NOISE_MODELS`. The SNR it takes
is the total one: the atmosphere's of Eq. (7.7) and the sensor's own
(:mod:`targetacq.physics.detector_noise`), added in variance
(:func:`targetacq.physics.detector_noise.combined_snr`).

``variance-sum`` (default)
    Noise raises every task's threshold in quadrature: each N50 is multiplied by

    ``f = sqrt(1 + k² / SNR_lin²)``,  ``SNR_lin = 10^(SNR_dB / 20)``,  ``k = √3``.

    Why this form. In the NVESD perception models noise enters the observer's threshold as a
    variance added to the eye's own: the system contrast threshold is the eye's times
    ``sqrt(1 + α²σ²)`` (the noise term of the targeting task performance metric; Vollmerhausen,
    Jacobs & Driggers, "New metric for predicting target acquisition performance", Opt. Eng. 43
    (2004) 2806). Cycles needed grow with the threshold, so the N50 scales by the same root. The
    constant ``k = √3`` makes ``f = 2`` at SNR = 1 (0 dB): the thesis's only quantitative
    statement of the kind, "a doubling of resolution is needed when SCR drops from 10 to 1"
    (§3.7), read for noise as §3.10 asks. Then ``f = 1.015`` at 20 dB, 1.16 at 10 dB, 5.3 at
    −9.6 dB, and ``f ≈ k / SNR_lin`` below, so ``P → 0`` as the signal vanishes (``τ → 0`` or a
    zero contrast); ``f → 1`` exactly as SNR → +inf, so the model is the noise-free one there.
    ``f`` is smooth and strictly decreasing in SNR: probabilities are continuous, and strictly
    better for a stronger signal (a hotter target is recognised farther).

    Detection in clutter: noise and clutter are independent disturbances that add in variance,
    ``1/R_eff² = 1/SCR² + 1/SNR_lin²`` (:func:`effective_scr`); the Schmieder–Weathersby
    transform is read at ``R_eff`` with the noise-free N (capped by the uncluttered value, see
    :mod:`targetacq.acquisition.probabilities`).
``clutter-analogue``
    The previous default: ``f = N50_R(SNR_lin) / N50_R(∞)`` with :func:`ratio_n50` the 50 % point
    of Table 3.5 made continuous in the ratio R (0.5 cycles for R >= 10, ``0.5 · (10/R)^log10(2)``
    on [1, 10), ``R^(−α)`` below 1). Exactly 1 from 20 dB up, so a signal above 20 dB has no
    effect at all; kinks at 0 and 20 dB. Combines with clutter as ``variance-sum`` does.
``none``
    Noise is ignored (``f = 1``).

A user model is any function ``f(snr_db) -> N50 factor >= 1``, passed as ``noise_model=``; it
multiplies every task's N50 (detection in clutter too, at the clutter's own SCR).

Which SNR, and a threshold: :data:`SNR_LAWS`
--------------------------------------------
Where the target's contrast and the sensor's noise are known, the SNR law says how the SNR is
formed and whether a detection threshold acts:

``contrast`` (default)
    The apparent contrast against the sensor's noise plus the path radiance's,
    ``SNR = τ|C| / sqrt((NEC/g)² + ((1 − τ) σ_path)²)``
    (:func:`targetacq.physics.detector_noise.contrast_snr`), τ counted once; and the probability
    that the target is seen above the noise at all (:func:`seen_probability`),
    ``P_seen = Φ(SNR_lin − k)``, multiplying the probabilities of detection, recognition and
    identification (so their order is kept). Φ is the standard normal distribution: the
    threshold-detection form of a signal in Gaussian noise, ``P_D = ½[1 + erf((SNR − TNR)/√2)]``
    with TNR the threshold-to-noise ratio (G. C. Holst, *Electro-Optical Imaging System
    Performance*, the probability of detection of a threshold detector). ``k`` =
    :data:`THRESHOLD_SNR` = 3 is the threshold SNR of the Rose model of visual detection over the
    target's area (A. Rose, J. Opt. Soc. Am. 38 (1948) 196–208, who put the constant ``k`` between
    about 3 and 7 and took about 5 for a certain detection): ``P_seen`` is 0.5 at the low end,
    SNR = 3, and 0.98 at Rose's 5. The project's reading (stated assumption): the lower end as the
    50 % point. ``P_seen`` is smooth in SNR (no cliff): a 1 % change of the contrast moves it by at
    most ``0.01 · max x φ(x − 3) ≈ 0.013``.
``sonesson``
    The thesis's Eq. (7.7), ``20 log10(τ/(1 − τ))``, which ignores the contrast, added in variance
    to the sensor's own ``τ|C|g/NEC`` (:func:`targetacq.physics.detector_noise.combined_snr`); no
    threshold. The numbers of earlier releases.

Where no contrast or sensor noise is known, both laws are Eq. (7.7) of the path alone, and no
threshold acts.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import numpy as np
from scipy import special

from targetacq.acquisition.transforms import clutter_n50, sw_high_anchor
from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.base.registry import lookup

__all__ = [
    "NOISE_MODELS",
    "QUADRATURE_CONSTANT",
    "SNR_LAWS",
    "THRESHOLD_SNR",
    "NoiseModel",
    "SnrLaw",
    "effective_scr",
    "get_noise_model",
    "get_snr_law",
    "noise_n50_factor",
    "noise_ratio",
    "ratio_n50",
    "seen_probability",
    "snr_ratio",
]


def _amplitude(s: Any, xp: Any) -> Any:
    """``10^(s/20)`` (+inf beyond the float range); off NumPy with a zero, not NaN, gradient at
    s = ±inf.

    The slope of ``10^(s/20)`` is infinite at s = +inf, where the models downstream are flat
    (f = 1 from 20 dB up): the chain rule gives 0 · inf = NaN. JAX differentiates both branches
    of a ``where``, so the infinite values are taken from a constant branch instead.
    """
    if isinstance(s, np.ndarray):
        # An SNR of thousands of dB (a path of subnormal optical depth) overflows to inf: the
        # exact limit, no noise, not an error.
        with np.errstate(over="ignore"):
            return 10.0 ** (s / 20.0)
    finite = xp.isfinite(s)
    infinite = xp.where(s > 0, xp.inf, xp.zeros_like(s))  # constant: no slope to multiply
    lin = xp.where(finite, 10.0 ** (xp.where(finite, s, 0.0) / 20.0), infinite)
    return xp.where(xp.isnan(s), s, lin)


def snr_ratio(snr: Any) -> Any:
    """Amplitude ratio of an SNR in decibels, ``10^(SNR/20)`` (the dB of Eq. (7.6)).

    Examples
    --------
    >>> from targetacq.acquisition.path_noise import snr_ratio
    >>> print([round(float(x), 4) for x in snr_ratio([0.0, 20.0, 6.0])])
    [1.0, 10.0, 1.9953]
    """
    xp, (s,) = _arrays.arrays(snr, names=("snr",))
    return _arrays.result(_amplitude(s, xp))


def effective_scr(scr: Array, snr: Array) -> Any:
    """Clutter and noise added in variance: ``R_eff = (1/SCR² + 1/SNR_lin²)^(−1/2)``.

    Parameters
    ----------
    scr : array_like
        Signal-to-clutter ratio, >= 0 (+inf: no clutter).
    snr : array_like
        Signal-to-noise ratio [dB] (+inf: no noise; −inf: no signal).

    Returns
    -------
    array_like
        R_eff, equal to SCR exactly where SNR = +inf.

    Examples
    --------
    SCR 3 and an SNR of 4 (12.04 dB) add in variance: ``(1/9 + 1/16)^(-1/2) = 2.4``.

    >>> import math
    >>> import targetacq as ta
    >>> print(f"{ta.effective_scr(3.0, 20 * math.log10(4.0)):.4f}")
    2.4000
    """
    xp, (c, s) = _arrays.arrays(scr, snr, names=("scr", "snr"))
    _arrays.require_nonnegative("scr", c, xp)
    return _arrays.result(_combined_ratio(c, _amplitude(s, xp), xp))


def _combined_ratio(c: Any, lin: Any, xp: Any) -> Any:
    """:func:`effective_scr` of a checked SCR and the linear SNR ``lin = 10^(SNR/20)``.

    ``lin`` is +inf exactly where there is no noise (R_eff = SCR exactly) and NaN where the SNR
    is. NumPy takes the formula alone where both ratios are positive and finite.
    """
    # R = a / sqrt(1 + (a/b)²) with a = min, b = max of the two ratios: no overflow for tiny or
    # infinite ratios (1/R² = 1/a² + 1/b²).
    a, b = xp.minimum(c, lin), xp.maximum(c, lin)
    if isinstance(b, np.ndarray) and b.ndim and b.size and b.min() > 0 and b.max() < math.inf:
        ratio = a / b  # every pair usable, no NaN (which the minimum would have)
        ratio *= ratio
        ratio += 1.0
        np.sqrt(ratio, out=ratio)
        return np.divide(a, ratio, out=ratio)
    usable = (b > 0) & xp.isfinite(b)
    ratio = xp.where(usable, xp.where(usable, a, 0.0) / xp.where(usable, b, 1.0), 0.0)
    combined = a / xp.sqrt(1.0 + ratio * ratio)
    exact = xp.where(xp.isinf(lin) & (lin > 0), c, combined)
    return xp.where(xp.isnan(lin), lin, exact)


def effective_scr_of_ratio(c: Any, inverse: Any, xp: Any) -> Any:
    """:func:`effective_scr` of a checked SCR and the noise-to-signal amplitude ratio
    ``ρ = 1/SNR_lin`` (:func:`noise_ratio`: 0 without noise, +inf without signal), as the array
    core has it (NumPy)."""
    with np.errstate(divide="ignore"):
        lin = 1.0 / inverse
    return _combined_ratio(c, lin, xp)


@functools.cache
def ratio_anchors() -> tuple[float, float, float]:
    """Table 3.5's low- and medium-clutter 50 % points and the high-clutter exponent α (once)."""
    low = float(clutter_n50(float("inf")))  # 0.5, Table 3.5 low clutter
    medium = float(clutter_n50(1.0))  # 1.0, Table 3.5 medium clutter
    return low, medium, sw_high_anchor()[2]


def ratio_n50(ratio: Array) -> Any:
    """Continuous 50 % point of detection against a clutter or noise ratio R [cycles].

    See the module docstring: 0.5 for R >= 10, ``0.5 · (10/R)^log10(2)`` on [1, 10),
    ``R^(−α)`` below 1 (α ≈ 0.83, through 2.5 cycles at R = 0.33); +inf at R = 0.

    Parameters
    ----------
    ratio : array_like
        R >= 0 (+inf allowed).

    Examples
    --------
    Table 3.5's 50 % points at the region anchors (0.5 cycles at R = 10, 1.0 at 1, 2.5 at
    0.33), and between them ``0.5 · (10/R)^log10(2)``:

    >>> from targetacq.acquisition.path_noise import ratio_n50
    >>> print([round(float(x), 4) for x in ratio_n50([10.0, 1.0, 0.33, 3.0])])
    [0.5, 1.0, 2.5, 0.7184]
    """
    xp, (r,) = _arrays.arrays(ratio, names=("ratio",))
    _arrays.require_nonnegative("ratio", r, xp)
    return _arrays.result(_ratio_n50(r, xp))


def _ratio_n50(r: Any, xp: Any) -> Any:
    """:func:`ratio_n50` of a checked float array."""
    low, medium, alpha = ratio_anchors()
    safe = xp.where(r > 0, r, 1.0)
    mid = low * (10.0 / xp.minimum(xp.maximum(safe, 1.0), 10.0)) ** (
        math.log(medium / low) / math.log(10.0)
    )
    out = xp.where(r >= 1.0, mid, medium * safe ** (-alpha))
    return xp.where(r > 0, out, xp.where(xp.isnan(r), r, xp.inf))


QUADRATURE_CONSTANT = math.sqrt(3.0)
"""k of the ``variance-sum`` law: ``f(0 dB) = sqrt(1 + k²) = 2`` (module docstring)."""


def noise_ratio(snr: Any) -> Any:
    """Noise-to-signal amplitude ratio ``ρ = 1/SNR_lin = 10^(−SNR/20)`` of an SNR in dB.

    0 at +inf (no noise), +inf at −inf (no signal). The built-in noise models act on ``ρ``
    (:attr:`NoiseModel.ratio_factor`); the array core takes it from the optical depth directly,
    ``ρ = e^d − 1`` for Eq. (7.7), without the decibels. NumPy: no checks, no overflow warning.

    Examples
    --------
    >>> from targetacq.acquisition.path_noise import noise_ratio
    >>> print([float(x) for x in noise_ratio([0.0, 20.0, float("inf")])])
    [1.0, 0.1, 0.0]
    """
    xp, (s,) = _arrays.arrays(snr, names=("snr",))
    if isinstance(s, np.ndarray):
        with np.errstate(over="ignore"):
            return _arrays.result(10.0 ** (-s / 20.0))
    return _amplitude(-s, xp)  # a zero, not NaN, gradient at ±inf


def _variance_sum_factor(snr: Any) -> Any:
    """``f = sqrt(1 + k²/SNR_lin²)``, written as ``hypot(1, k·10^(−SNR/20))`` (no overflow)."""
    xp, (s,) = _arrays.arrays(snr, names=("snr",))
    # 10^(-SNR/20) is the noise-to-signal amplitude: 0 at +inf (f = 1), +inf at -inf (f = inf).
    return _arrays.result(_variance_sum_of_ratio(noise_ratio(s), xp))


def _variance_sum_of_ratio(inverse: Any, xp: Any = None) -> Any:
    """The ``variance-sum`` factor of the noise-to-signal amplitude ratio (:func:`noise_ratio`)."""
    xp = xp or _arrays.namespace(inverse)
    with np.errstate(over="ignore"):  # a vanishing signal: ρ near the float limit, f = inf
        ratio = QUADRATURE_CONSTANT * inverse
    if isinstance(ratio, np.ndarray) and not bool(np.any(ratio > 1.0)):
        ratio *= ratio  # every ratio <= 1 (or NaN): the small branch alone, as below
        ratio += 1.0
        return np.sqrt(ratio, out=ratio)
    # sqrt(1 + r²) as r · sqrt(1 + 1/r²) for r > 1: no overflow for a vanishing signal.
    big = ratio > 1.0
    safe = xp.where(big, ratio, 1.0)
    shrink = 1.0 / safe
    large = safe * xp.sqrt(1.0 + shrink * shrink)
    small = xp.sqrt(1.0 + xp.where(big, 0.0, ratio) ** 2)
    return xp.where(big, large, small)


def _clutter_analogue_factor(snr: Any) -> Any:
    xp, (s,) = _arrays.arrays(snr, names=("snr",))
    lin = _amplitude(s, xp)
    uncluttered = ratio_anchors()[0]  # ratio_n50(+inf), Table 3.5's low clutter
    return _arrays.result(ratio_n50(lin) / uncluttered)


def _clutter_analogue_of_ratio(inverse: Any, xp: Any = None) -> Any:
    xp = xp or _arrays.namespace(inverse)
    with np.errstate(divide="ignore"):
        lin = 1.0 / inverse  # SNR_lin: +inf without noise
    return _ratio_n50(lin, xp) / ratio_anchors()[0]


def _no_noise_factor(snr: Any) -> Any:
    xp, (s,) = _arrays.arrays(snr, names=("snr",))
    return _arrays.result(xp.where(xp.isnan(s), s, xp.ones_like(s)))


def _no_noise_of_ratio(inverse: Any, xp: Any = None) -> Any:
    xp = xp or _arrays.namespace(inverse)
    return xp.where(xp.isnan(inverse), inverse, xp.ones_like(inverse))


@dataclass(frozen=True)
class NoiseModel:
    """How noise acts on the transforms.

    Attributes
    ----------
    name : str
    n50_factor : callable
        ``f(snr_db) -> factor >= 1`` multiplying the N50s.
    combines_with_clutter : bool
        Whether detection in clutter is read at ``R_eff`` (:func:`effective_scr`) instead of
        applying ``n50_factor`` at the clutter's own SCR.
    source : str
    ratio_factor : callable or None
        The same factor as a function of the noise-to-signal amplitude ratio
        ``ρ = 10^(−SNR/20)`` (:func:`noise_ratio`), ``ratio_factor(ρ, xp) -> f``: what the array
        core uses with NumPy, which has ``ρ`` from the optical depth without the decibels.
        None (a user's model): the core converts to decibels and calls ``n50_factor``.
    """

    name: str
    n50_factor: Callable[[Any], Any]
    combines_with_clutter: bool = False
    source: str = ""
    ratio_factor: Callable[..., Any] | None = None


NOISE_MODELS: Mapping[str, NoiseModel] = MappingProxyType(
    {
        "variance-sum": NoiseModel(
            "variance-sum",
            _variance_sum_factor,
            combines_with_clutter=True,
            ratio_factor=_variance_sum_of_ratio,
            source="project assumption: noise raises the N50s in quadrature, f = sqrt(1 + 3/SNR²) "
            "(the noise term of Vollmerhausen, Jacobs & Driggers 2004); noise and clutter add "
            "in variance",
        ),
        "clutter-analogue": NoiseModel(
            "clutter-analogue",
            _clutter_analogue_factor,
            combines_with_clutter=True,
            ratio_factor=_clutter_analogue_of_ratio,
            source="project assumption: noise moves the N50 as clutter does in Table 3.5 "
            "(Sonesson 2004 §3.7, §3.10); no effect above 20 dB",
        ),
        "none": NoiseModel(
            "none", _no_noise_factor, source="noise ignored", ratio_factor=_no_noise_of_ratio
        ),
    }
)
"""Noise models by name (read-only)."""


def get_noise_model(noise_model: str | NoiseModel | Callable[[Any], Any]) -> NoiseModel:
    """Resolve a noise model by name, as a :class:`NoiseModel`, or from a user function."""
    if isinstance(noise_model, NoiseModel):
        return noise_model
    if isinstance(noise_model, str):
        return lookup(NOISE_MODELS, noise_model, "noise model")
    if callable(noise_model):
        return NoiseModel(getattr(noise_model, "__name__", "user"), noise_model, source="user")
    raise TypeError(f"noise_model must be a name, a NoiseModel or a function, got {noise_model!r}")


def noise_n50_factor(
    snr: Array, noise_model: str | NoiseModel | Callable[[Any], Any] = "variance-sum"
) -> Any:
    """Factor >= 1 by which noise multiplies the N50s (see the module docstring).

    Parameters
    ----------
    snr : array_like
        SNR [dB]; +inf for no noise.
    noise_model : str, NoiseModel or callable

    Returns
    -------
    array_like
        f >= 1 (+inf where no signal is left); exactly 1 at SNR = +inf for the built-in models.

    Examples
    --------
    ``sqrt(1 + 3 / SNR_lin²)``: no noise, 0 dB (the factor 2 of §3.7), 10 dB and 20 dB.

    >>> import math
    >>> import numpy as np
    >>> import targetacq as ta
    >>> print(np.round(ta.noise_n50_factor([math.inf, 0.0, 10.0, 20.0]), 4))
    [1.     2.     1.1402 1.0149]
    """
    model = get_noise_model(noise_model)
    factor = model.n50_factor(snr)
    xp, (f,) = _arrays.arrays(factor)
    if not _arrays.is_traced(f) and _arrays.any_known(f < 1, xp):
        raise ValueError(f"noise model {model.name!r} returned an N50 factor below 1")
    return _arrays.result(f)


THRESHOLD_SNR = 3.0
"""k of the ``contrast`` law's threshold, ``P_seen = Φ(SNR_lin − k)`` (module docstring)."""


def seen_probability(snr: Array, threshold: Array = THRESHOLD_SNR) -> Any:
    """Probability that a target is seen above the noise: ``P = Φ(SNR_lin − k)``.

    The threshold-detection form (Holst) with the Rose threshold ``k`` (module docstring, the
    ``contrast`` law). Smooth and increasing in SNR; ``Φ(−k)`` without signal (0.0013 at the
    default k = 3), 1 without noise.

    Parameters
    ----------
    snr : array_like
        The total SNR [dB] (+inf: no noise; −inf: no signal).
    threshold : array_like
        k, the SNR (amplitude ratio) at which P = 0.5, >= 0 (−inf: no threshold, P = 1).

    Returns
    -------
    array_like
        P in [0, 1].

    Examples
    --------
    0.5 at SNR = k = 3 (9.54 dB), 0.977 two noise units above, ~0 at SNR = 0.5:

    >>> import math
    >>> from targetacq.acquisition.path_noise import seen_probability
    >>> snr = [20 * math.log10(x) for x in (3.0, 5.0, 0.5)]
    >>> print([round(float(p), 4) for p in seen_probability(snr)])
    [0.5, 0.9772, 0.0062]
    """
    xp, (s, k) = _arrays.arrays(snr, threshold, names=("snr", "threshold"))
    if _arrays.any_known((k < 0) & ~xp.isinf(k), xp):
        raise ValueError(f"threshold must be >= 0 (or -inf for none), got {threshold!r}")
    return _arrays.result(seen_of_ratio(noise_ratio(s), k, xp))


def seen_of_ratio(inverse: Any, k: Any, xp: Any) -> Any:
    """:func:`seen_probability` of the noise-to-signal amplitude ratio ``ρ = 1/SNR_lin``
    (:func:`noise_ratio`) and a checked threshold (the arithmetic kernel)."""
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        lin = 1.0 / inverse  # +inf without noise, 0 without signal
        # −inf threshold (none): P = 1 whatever the SNR, NaN kept.
        x = xp.where(xp.isinf(k) & (k < 0), xp.inf, lin - xp.where(xp.isinf(k), 0.0, k))
    out = _normal_cdf(x, xp)
    return xp.where(xp.isnan(inverse), xp.nan, out)


def _normal_cdf(x: Any, xp: Any) -> Any:
    if isinstance(x, np.ndarray | float | np.floating):
        return special.ndtr(x)
    from jax.scipy.special import ndtr  # the JAX array core: its own, differentiable

    return ndtr(x)


@dataclass(frozen=True)
class SnrLaw:
    """How the SNR of a pair with a known contrast and sensor noise is formed (module docstring).

    Attributes
    ----------
    name : str
    contrast_aware : bool
        Whether the path's noise is the contrast-aware ``(1 − τ) σ_path``
        (:func:`targetacq.physics.detector_noise.contrast_snr`); else Eq. (7.7) added in variance
        to the sensor's (:func:`targetacq.physics.detector_noise.combined_snr`).
    threshold : float or None
        k of :func:`seen_probability`; None: no threshold.
    source : str
    """

    name: str
    contrast_aware: bool
    threshold: float | None
    source: str


SNR_LAWS: Mapping[str, SnrLaw] = MappingProxyType(
    {
        "contrast": SnrLaw(
            "contrast",
            True,
            THRESHOLD_SNR,
            "project assumption: apparent contrast τ|C| against sensor noise NEC/g plus "
            "path-radiance noise (1 − τ)·σ_path (σ_path 1 K, or a contrast ratio of 1; a target "
            "of that contrast gets Eq. (7.7) of Sonesson 2004), and P_seen = Φ(SNR − 3) "
            "(threshold detection, Holst; Rose 1948's k)",
        ),
        "sonesson": SnrLaw(
            "sonesson",
            False,
            None,
            "Sonesson 2004 Eq. (7.7), 20 log10(τ/(1 − τ)) regardless of contrast, added in "
            "variance to the sensor's τ|C|g/NEC; no threshold",
        ),
    }
)
"""SNR laws by name (read-only); ``contrast`` is the default."""


def get_snr_law(snr_law: str | SnrLaw) -> SnrLaw:
    """Resolve an SNR law by name (``ValueError`` with the choices) or return it as given.

    Examples
    --------
    >>> get_snr_law("sonesson").threshold is None
    True
    """
    if isinstance(snr_law, SnrLaw):
        return snr_law
    if isinstance(snr_law, str):
        return lookup(SNR_LAWS, snr_law, "SNR law")
    raise TypeError(f"snr_law must be a name or an SnrLaw, got {snr_law!r}")
