"""Clutter and the signal-to-clutter ratio.

Sources: Sonesson (2004) §3.7 (Eqs. (3.12)–(3.15)), §6.6 (Eqs. (6.7)–(6.11)). The SCR of a target
is its contrast against the mean of its surroundings in units of the clutter, the spatial
standard deviation of the surroundings:

- (3.14) positive contrast ``SCR = |g_0,max − g_mean| / clutter``; (3.15) negative contrast
  ``SCR = |g_0,min − g_mean| / clutter``; (6.9) from signals ``SCR = (o_max − c_mean) / clutter``;
- (6.10)–(6.11) from a terrain description: ``clutter = (Σ_i k_i σ_i²)^(1/2)``, ``Σ k_i = 1``,
  the weights being how often each class occurs around the target.

Zero clutter (a uniform background) gives an infinite SCR for any contrast; a target with no
contrast at all has SCR 0.
"""

from __future__ import annotations

from typing import Any

from targetacq import _arrays

__all__ = ["signal_to_clutter_ratio", "terrain_clutter"]


def signal_to_clutter_ratio(target_signal: Any, background_mean: Any, clutter: Any) -> Any:
    """Signal-to-clutter ratio, Eqs. (3.14), (3.15) and (6.9) in Sonesson (2004).

    ``SCR = |target − background_mean| / clutter``. Pass the target's maximum for positive
    contrast (3.14) or its minimum for negative contrast (3.15).

    Parameters
    ----------
    target_signal : array_like
        g_0,max (or g_0,min), or o_max of Eq. (6.18), in any signal unit.
    background_mean : array_like
        g_mean or c_mean, same unit.
    clutter : array_like
        Clutter (3.12) or (6.10), same unit, >= 0.

    Returns
    -------
    array_like
        SCR >= 0; +inf where clutter is 0 and the contrast is not; 0 where the contrast is 0.
    """
    xp, (t, b, c) = _arrays.arrays(target_signal, background_mean, clutter)
    _arrays.require_nonnegative("clutter", c, xp)
    contrast = xp.abs(t - b)
    ratio = contrast / xp.where(c > 0, c, 1.0)
    out = xp.where(c > 0, ratio, xp.where(contrast > 0, xp.inf, 0.0 * contrast))
    return _arrays.result(xp.where(xp.isnan(c), c, out))


def terrain_clutter(weights: Any, variances: Any, axis: int = -1) -> Any:
    """Clutter from a terrain description, ``(Σ_i k_i σ_i²)^(1/2)``, Eqs. (6.10)–(6.11).

    Parameters
    ----------
    weights : array_like
        k_i, the fraction of the surroundings covered by each class, >= 0, summing to 1 along
        ``axis`` (Eq. (6.11)).
    variances : array_like
        σ_i² of each class's signal at the sensor's resolution [signal unit²], >= 0.
    axis : int
        The class axis.

    Returns
    -------
    array_like
        Clutter [signal unit].
    """
    xp, (k, v) = _arrays.arrays(weights, variances)
    _arrays.require_nonnegative("weights", k, xp)
    _arrays.require_nonnegative("variances", v, xp)
    total = xp.sum(k, axis=axis)
    if bool(xp.any(xp.abs(total - 1.0) > 1e-9)):
        raise ValueError("weights must sum to 1 over the classes (Eq. (6.11))")
    return _arrays.result(xp.sqrt(xp.sum(k * v, axis=axis)))
