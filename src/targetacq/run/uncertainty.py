"""Uncertainty bands: a Monte Carlo over stated input distributions, as one array pass.

A DRI range is one number, but its inputs are not known exactly: Johnson's N50s carry the spread
printed beside them (Sonesson 2004, Table 3.1's "Average" row, 1.0 ± 0.25 … 6.4 ± 1.5 cycles,
and Table 3.2's "±25 %" row), observers differ, a NETD is a datasheet's typical value and an
extinction a weather class. :func:`uncertainty_ranges` and :func:`uncertainty_curves` draw ``M``
samples of those inputs and give the 5 %, 50 % and 95 % points of the ranges and of the
range-performance curves over them.

**One evaluator, one pass.** The samples are not a loop over the solver: they are one
:class:`targetacq.core.cases.RangeCase` whose inputs are arrays of shape ``(M, 1)``, and the
core evaluates it along the line of ranges as it evaluates any case
(:func:`targetacq.core.ranges.case_ranges`: the closed form, or its vectorised bisection, all
samples and probabilities at once; :func:`targetacq.core.cases.case_acquisition` for the
curves).

**The N50 draws.** The model reads a task's cycles only through ``N / N50`` (§3.5: every
transform of Tables 3.2–3.5 is a curve in ``N / N50``, and the noise models multiply the N50s
by a factor, which is dividing N by it). So an N50 ``f`` times the table's is the same as a
target whose critical dimension is ``d / f`` (``N = d / (R · cycle)``, and the MRTD and TTP
cycles are proportional to the target's size too): a sample's case carries ``d / f``, with the
outline's area kept (``target_area``) so that the sensor's noise still sees the real target.
The ranges stay those of the real target: ``R = d / (N_p · cycle)`` is a range in metres. One
factor per sample multiplies every task's N50 (a target class, or an observer, is harder or
easier for every task alike), so the ordering of the tasks holds in every sample.

**Distributions.** Every input is drawn lognormal with its median at the nominal value and the
stated spread ``s`` as its relative standard deviation: ``x = x0 · exp(σ z)``, ``z`` standard
normal, ``σ = sqrt(ln(1 + s²))``. Lognormal, not a normal truncated at 0, because every input is
a positive scale (N50, NETD, extinction), its printed ± is relative (Table 3.2: "±25 %"), and a
normal of 25 % would need truncation that shifts its mean and median off the table's value. The
median at the nominal value has a consequence the tests hold: a range is monotone in each input,
so with ``k`` inputs drawn independently at least ``2^-k`` of the samples lie on either side of
the nominal range; for ``k <= 4`` (> 5 %) the 5–95 % band contains it.

**Reproducible.** The draws are Philox4x32 counters (:mod:`targetacq.base.sampling`): sample
``i`` of input ``j`` is a pure function of the seed, ``i`` and ``j``, so the first 100 samples of
a run of 500 are the 100 samples of a run of 100, on every machine.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.special import ndtri

from targetacq.acquisition.criteria import get_criterion
from targetacq.base.arrays import Array
from targetacq.base.limits import check_seed
from targetacq.base.sampling import stream_key, uniforms
from targetacq.base.tables import load_table
from targetacq.core import ranges
from targetacq.core.cases import RangeCase, case_acquisition
from targetacq.run.range_options import RangeSetup, dri_report

__all__ = [
    "BAND",
    "MAX_SAMPLES",
    "MIN_SAMPLES",
    "SPREAD_LIMITS",
    "TABLE_N50_SPREAD",
    "Uncertainty",
    "lognormal_factors",
    "observer_factor",
    "parse_spread",
    "read_uncertainty",
    "uncertainty_curves",
    "uncertainty_ranges",
    "uncertainty_report",
]

BAND = (0.05, 0.95)
"""The quantiles of a band: 5 % and 95 %."""

MIN_SAMPLES, MAX_SAMPLES = 20, 100_000
"""The fewest samples that place a 5 % point (one in twenty) and the most a run may draw."""

SPREAD_LIMITS = (0.0, 1.0)
"""A spread's valid range: a relative standard deviation from 0 to 1 (0–100 %)."""


def _table_spread() -> float:
    """Table 3.2's "±25 %" row over the average N50s (johnson_average.csv): one relative spread
    for every task."""
    table = load_table("johnson_average")
    relative = {
        s / n
        for s, n in zip(table.numbers("spread_table_3_2"), table.numbers("cycles"), strict=True)
    }
    (spread,) = {round(r, 12) for r in relative}
    return spread


TABLE_N50_SPREAD: float = _table_spread()
"""The N50's relative spread of Sonesson (2004) Table 3.2, "±25 %" (0.25), for every task: the
default of :attr:`Uncertainty.n50_spread`. (Table 3.1's Average row prints 25, 25, 20 and 23 %
for detection, orientation, recognition and identification; one factor per sample moves every
task's N50 alike, so the table's one figure is used.)"""

# Counter purposes of the draws (the third Philox counter word): one stream per input.
_N50, _OBSERVER, _NETD, _EXTINCTION = 1, 2, 3, 4


def parse_spread(text: str, option: str) -> float:
    """A spread given as a percentage (``"25%"``) as a fraction (0.25), checked in
    :data:`SPREAD_LIMITS`.

    Raises
    ------
    ValueError
        Naming ``option``: not a percentage (the unit is explicit: ``%``), NaN, or outside
        0–100 %.

    Examples
    --------
    >>> parse_spread("25%", "--n50-spread")
    0.25
    >>> parse_spread("0.25", "--n50-spread")
    Traceback (most recent call last):
    ...
    ValueError: --n50-spread must be a percentage from 0% to 100%, e.g. 25%; got '0.25'
    """
    stripped = text.strip()
    message = f"{option} must be a percentage from 0% to 100%, e.g. 25%; got {text!r}"
    if not stripped.endswith("%"):
        raise ValueError(message)
    try:
        value = float(stripped[:-1]) / 100.0
    except ValueError:
        raise ValueError(message) from None
    return _check_spread(option, value, message)


def _check_spread(name: str, value: Any, message: str | None = None) -> float:
    low, high = SPREAD_LIMITS
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(
            message or f"{name} must be a number in [{low:g}, {high:g}]; got {value!r}"
        )
    if not (math.isfinite(value) and low <= value <= high):
        raise ValueError(
            message
            or f"{name} must be a relative spread in [{low:g}, {high:g}] (0–100 %); got {value!r}"
        )
    return float(value)


@dataclass(frozen=True)
class Uncertainty:
    """The Monte Carlo's size, seed and the spread of each input.

    Every spread is a relative standard deviation [1] in [0, 1] of a lognormal with its median
    at the nominal value (module docstring); 0 leaves that input at its value.

    Attributes
    ----------
    samples : int
        Samples drawn, in [:data:`MIN_SAMPLES`, :data:`MAX_SAMPLES`].
    seed : int
        Seed of the counter-based streams, in [0, 2**128 - 1].
    n50_spread : float
        The N50s' spread; default Table 3.2's ±25 % (:data:`TABLE_N50_SPREAD`).
    observer_spread : float
        An observer's own spread of the N50s, drawn apart from ``n50_spread`` (default 0: the
        thesis states none).
    netd_spread : float
        The sensor's noise-equivalent contrast (NETD) spread (default 0; needs the sensor's
        noise in the case).
    extinction_spread : float
        The path's extinction spread (default 0; needs a Beer–Lambert extinction in the case).

    Examples
    --------
    >>> Uncertainty(500, seed=1).n50_spread
    0.25
    >>> Uncertainty(500, netd_spread=float("nan"))
    Traceback (most recent call last):
    ...
    ValueError: netd_spread must be a relative spread in [0, 1] (0–100 %); got nan
    """

    samples: int = 500
    seed: int = 0
    n50_spread: float = TABLE_N50_SPREAD
    observer_spread: float = 0.0
    netd_spread: float = 0.0
    extinction_spread: float = 0.0

    def __post_init__(self) -> None:
        m = self.samples
        if isinstance(m, bool) or not isinstance(m, int) or not MIN_SAMPLES <= m <= MAX_SAMPLES:
            raise ValueError(
                f"samples must be a whole number in [{MIN_SAMPLES}, {MAX_SAMPLES}]; got {m!r}"
            )
        check_seed(self.seed)
        for name in ("n50_spread", "observer_spread", "netd_spread", "extinction_spread"):
            object.__setattr__(self, name, _check_spread(name, getattr(self, name)))

    def applicable_to(self, case: RangeCase) -> Uncertainty:
        """This run with the spreads of inputs that ``case`` lacks set to 0: the NETD's
        without a sensor noise-equivalent contrast (or with the TTP model), the extinction's
        without a Beer–Lambert extinction. For cases side by side (a report over a clear and a
        hazy path), where a spread applies to those that have the input.

        Examples
        --------
        >>> Uncertainty(100, extinction_spread=0.2).applicable_to(RangeCase(2.3, 2e-4))
        ... # doctest: +ELLIPSIS
        Uncertainty(samples=100, seed=0, n50_spread=0.25, ..., extinction_spread=0.0)
        """
        changes: dict[str, Any] = {}
        if case.noise_equivalent_contrast is None or case.ttp is not None:
            changes["netd_spread"] = 0.0
        if case.extinction is None:
            changes["extinction_spread"] = 0.0
        return dataclasses.replace(self, **changes)

    def check_cases(self, cases: Any) -> None:
        """Refuse a spread that none of ``cases`` (range cases side by side) has the input of:
        a stated spread is applied to some case, or it is an error, never silently dropped.

        Raises
        ------
        ValueError
            Naming the option (``--netd-spread``, ``--extinction-spread``) and what it needs.

        Examples
        --------
        >>> try:
        ...     Uncertainty(100, netd_spread=0.1).check_cases([RangeCase(2.3, 2e-4)])
        ... except ValueError as error:
        ...     print(str(error)[:46])
        --netd-spread needs the sensor's noise-equival
        """
        cases = list(cases)
        needs = {
            "netd_spread": "the sensor's noise-equivalent contrast (--netd or --nec) without the "
            "TTP model",
            "extinction_spread": "a Beer–Lambert extinction (--extinction, --visibility or "
            "--obscurant)",
        }
        for name, what in needs.items():
            if getattr(self, name) and not any(
                getattr(self.applicable_to(case), name) for case in cases
            ):
                flag = "--" + name.replace("_", "-")
                raise ValueError(f"{flag} needs {what} in at least one case; set it to 0%")

    def description(self) -> dict[str, Any]:
        """The run as a JSON-ready record: samples, seed, band and each input's distribution."""
        return {
            "samples": self.samples,
            "seed": self.seed,
            "band": list(BAND),
            "distribution": "lognormal, median at the nominal value, relative standard deviation",
            "spreads": {
                "n50": self.n50_spread,
                "observer": self.observer_spread,
                "netd": self.netd_spread,
                "extinction": self.extinction_spread,
            },
        }


def lognormal_factors(spread: float, seed: int, purpose: int, samples: int) -> np.ndarray:
    """``samples`` lognormal factors of median 1 and relative standard deviation ``spread``.

    ``exp(σ z)`` with ``σ = sqrt(ln(1 + s²))`` (so that the factor's standard deviation over its
    mean is ``s``) and ``z = Φ⁻¹(u)``, ``u`` the Philox uniform of counter (0, i, purpose) under
    the seed's key (:func:`targetacq.base.sampling.uniforms`): sample ``i`` depends on the seed,
    ``i`` and ``purpose`` only.

    Parameters
    ----------
    spread : float
        Relative standard deviation [1], in [0, 1].
    seed : int
    purpose : int
        Which input (a small integer, one stream each).
    samples : int

    Returns
    -------
    numpy.ndarray
        Shape ``(samples,)``, > 0; all ones for a spread of 0.

    Examples
    --------
    >>> f = lognormal_factors(0.25, 0, 1, 20000)
    >>> round(float(np.median(f)), 2), round(float(f.std() / f.mean()), 2)
    (1.0, 0.25)
    """
    spread = _check_spread("spread", spread)
    sigma = math.sqrt(math.log1p(spread * spread))
    u = uniforms(stream_key(seed, "uncertainty"), 0, np.arange(samples), purpose)
    return np.exp(sigma * ndtri(u))


def observer_factor(spread: float, seed: int, run: int) -> float:
    """The N50 factor of run ``run``'s observer: sample ``run`` of the observer's stream of
    :func:`lognormal_factors` (so run ``r`` of a simulation has the observer of sample ``r`` of
    a DRI Monte Carlo with the same seed and spread).

    Parameters
    ----------
    spread : float
        Relative standard deviation [1], in [0, 1].
    seed : int
    run : int
        In [0, 2**32).

    Returns
    -------
    float
        > 0; 1.0 for a spread of 0.

    Examples
    --------
    >>> f = lognormal_factors(0.2, 5, 2, 4)
    >>> observer_factor(0.2, 5, 3) == float(f[3])
    True
    """
    spread = _check_spread("observer_spread", spread)
    if not spread:
        return 1.0
    sigma = math.sqrt(math.log1p(spread * spread))
    u = uniforms(stream_key(seed, "uncertainty"), 0, np.asarray([run]), _OBSERVER)
    return float(np.exp(sigma * ndtri(u))[0])


def _sampled_case(case: RangeCase, uncertainty: Uncertainty) -> RangeCase:
    """The case with its inputs as arrays ``(M, 1)`` of samples (module docstring)."""
    u = uncertainty
    criterion = get_criterion(case.criterion)
    if not criterion.gives_probabilities:
        raise ValueError(
            f"uncertainty bands need a criterion with probabilities (N50s), not {criterion.name!r}"
        )
    if np.ndim(case.critical_dimension) or np.ndim(case.ifov):
        raise ValueError("uncertainty bands take one case of scalar inputs, not a sweep")
    m = u.samples

    def draw(spread: float, purpose: int) -> np.ndarray:
        return lognormal_factors(spread, u.seed, purpose, m)[:, None]

    changes: dict[str, Any] = {}
    n50 = draw(u.n50_spread, _N50) * draw(u.observer_spread, _OBSERVER)
    d = case.critical_dimension
    changes["critical_dimension"] = d / n50
    if case.ttp is not None:  # its characteristic dimension sqrt(area) scales with d
        area = d * d if case.target_area is None else case.target_area
        changes["target_area"] = area / (n50 * n50)
    elif case.noise_equivalent_contrast is not None:  # the sensor's noise sees the real outline
        changes["target_area"] = d * d if case.target_area is None else case.target_area
    if u.netd_spread:
        if case.noise_equivalent_contrast is None or case.ttp is not None:
            raise ValueError(
                "netd_spread (--netd-spread) needs the sensor's noise-equivalent contrast "
                "(--netd or --nec) without the TTP model; set it to 0%"
            )
        changes["noise_equivalent_contrast"] = case.noise_equivalent_contrast * draw(
            u.netd_spread, _NETD
        )
    if u.extinction_spread:
        if case.extinction is None:
            raise ValueError(
                "extinction_spread (--extinction-spread) needs a Beer–Lambert extinction "
                "(--extinction, --visibility or --obscurant), not a clear path or a named "
                "atmosphere; set it to 0%"
            )
        changes["extinction"] = case.extinction * draw(u.extinction_spread, _EXTINCTION)
    return dataclasses.replace(case, **changes)


def _quantiles(values: np.ndarray) -> np.ndarray:
    """(3, …): the 5 %, 50 % and 95 % points over axis 0, order statistics (no interpolation,
    so +inf stays +inf); NaN (never reached) counts as the shortest range and comes back NaN."""
    never = np.isnan(values)
    points = np.quantile(
        np.where(never, -np.inf, values), [BAND[0], 0.5, BAND[1]], axis=0, method="inverted_cdf"
    )
    return np.where(points == -np.inf, np.nan, points)


def uncertainty_ranges(
    case: RangeCase, probabilities: Array, uncertainty: Uncertainty, tolerance: float = 1e-9
) -> dict[str, dict[str, np.ndarray]]:
    """The DRI ranges of a case over the samples: nominal, 5 %, median and 95 % points.

    One call of :func:`targetacq.core.ranges.case_ranges` for the nominal case and one for the
    sampled case (inputs of shape ``(M, 1)``, every sample and probability in one vectorised
    solve).

    Parameters
    ----------
    case : RangeCase
        Scalar inputs; a criterion with probabilities.
    probabilities : array_like
        1-D, in (0, 1).
    uncertainty : Uncertainty
    tolerance : float
        Relative range tolerance of the solver.

    Returns
    -------
    dict
        Task → ``{"nominal", "p05", "p50", "p95"}``, each an array [m] of shape
        ``(n_probabilities,)`` (NaN: never reached; +inf: any range), and ``"samples"``,
        ``(M, n_probabilities)``.

    Examples
    --------
    >>> found = uncertainty_ranges(RangeCase(2.3, 2e-4), [0.5], Uncertainty(200))
    >>> det = found["detection"]
    >>> round(float(det["nominal"][0]), 6)  # R = d / (N50 · 2 IFOV)
    5750.0
    >>> bool(det["p05"][0] < 5750.0 < det["p95"][0])
    True
    """
    probs = np.asarray(probabilities, dtype=float).reshape(-1)
    nominal = ranges.case_ranges(case, probs, tolerance)
    sampled = ranges.case_ranges(_sampled_case(case, uncertainty), probs, tolerance)
    out = {}
    for task, value in nominal.items():
        samples = np.broadcast_to(sampled[task], (uncertainty.samples, probs.size))
        p05, p50, p95 = _quantiles(np.asarray(samples, dtype=float))
        out[task] = {
            "nominal": np.broadcast_to(value, probs.shape).astype(float),
            "p05": p05,
            "p50": p50,
            "p95": p95,
            "samples": samples,
        }
    return out


def uncertainty_curves(
    case: RangeCase, range: Array, uncertainty: Uncertainty
) -> dict[str, np.ndarray]:
    """The range-performance curves' 5 %, 50 % and 95 % points over the samples.

    One :func:`targetacq.core.cases.case_acquisition` of the sampled case on the grid
    (``(M, n)`` probabilities in one pass).

    Parameters
    ----------
    case : RangeCase
    range : array_like
        1-D grid of slant ranges [m], > 0.
    uncertainty : Uncertainty

    Returns
    -------
    dict
        ``"<task>_p05"``, ``"<task>_p50"``, ``"<task>_p95"`` for detection, recognition and
        identification, each of the grid's shape.

    Examples
    --------
    >>> bands = uncertainty_curves(RangeCase(2.3, 2e-4), [1000.0, 5750.0], Uncertainty(200))
    >>> bool(bands["detection_p05"][1] < 0.5 < bands["detection_p95"][1])
    True
    """
    grid = np.asarray(range, dtype=float).reshape(-1)
    found = case_acquisition(_sampled_case(case, uncertainty), grid)
    out = {}
    for task in ("detection", "recognition", "identification"):
        values = np.broadcast_to(getattr(found, task), (uncertainty.samples, grid.size))
        p05, p50, p95 = np.quantile(values, [BAND[0], 0.5, BAND[1]], axis=0)
        out[f"{task}_p05"], out[f"{task}_p50"], out[f"{task}_p95"] = p05, p50, p95
    return out


_SPREAD_OPTIONS = ("n50_spread", "observer_spread", "netd_spread", "extinction_spread")


def read_uncertainty(options: Mapping[str, str | None]) -> Uncertainty | None:
    """The Monte Carlo of the options as typed (the names of
    :data:`targetacq.run.option_table.UNCERTAINTY_OPTIONS`, text or None), or None without
    ``uncertainty``.

    Raises
    ------
    ValueError
        Naming the option (``--uncertainty``, ``--seed``, ``--n50-spread`` …) and its valid
        range; a knob given without ``--uncertainty``.

    Examples
    --------
    >>> read_uncertainty({"uncertainty": "500", "netd_spread": "10%"}).netd_spread
    0.1
    >>> read_uncertainty({"uncertainty": None, "seed": None}) is None
    True
    >>> read_uncertainty({"uncertainty": "5"})
    Traceback (most recent call last):
    ...
    ValueError: --uncertainty must be a whole number of samples in [20, 100000]; got '5'
    """
    given = {name: value for name, value in options.items() if value is not None}
    if "uncertainty" not in given:
        if given:
            flags = ", ".join("--" + name.replace("_", "-") for name in given)
            raise ValueError(f"{flags} go with --uncertainty (the number of samples)")
        return None
    text = str(given.pop("uncertainty")).strip()
    if not (text.isdigit() and MIN_SAMPLES <= int(text) <= MAX_SAMPLES):
        raise ValueError(
            f"--uncertainty must be a whole number of samples in [{MIN_SAMPLES}, {MAX_SAMPLES}]; "
            f"got {text!r}"
        )
    values: dict[str, Any] = {"samples": int(text)}
    if "seed" in given:
        seed = str(given.pop("seed")).strip()
        if not seed.isdigit():
            raise ValueError(f"--seed must be an integer in [0, 2**128 - 1]; got {seed!r}")
        values["seed"] = check_seed(int(seed), "--seed")
    for name in _SPREAD_OPTIONS:
        if name in given:
            values[name] = parse_spread(str(given.pop(name)), "--" + name.replace("_", "-"))
    if given:
        raise ValueError(f"unknown uncertainty option(s): {', '.join(given)}")
    return Uncertainty(**values)


def uncertainty_report(setup: RangeSetup, uncertainty: Uncertainty) -> dict[str, Any]:
    """The DRI report of a range setup (:func:`targetacq.run.range_options.dri_report`) with
    each row's band: ``range_p05_m``, ``range_p50_m`` and ``range_p95_m`` (None: never reached
    at that point), and the run's description under ``"uncertainty"``.

    Examples
    --------
    >>> from targetacq.run.range_options import range_setup
    >>> setup = range_setup({"ifov": "0.2mrad", "critical_dimension": "2.3m"})
    >>> row = uncertainty_report(setup, Uncertainty(100))["ranges"][0]
    >>> row["task"], round(row["range_m"], 6), row["range_p05_m"] < 5750.0 < row["range_p95_m"]
    ('detection', 5750.0, True)
    """
    report = dri_report(setup)
    found = uncertainty_ranges(setup.case, setup.probabilities, uncertainty)
    index = {p: k for k, p in enumerate(setup.probabilities)}
    for row in report["ranges"]:
        band = found[row["task"]]
        k = index[row["probability"]]
        for point in ("p05", "p50", "p95"):
            value = float(band[point][k])
            row[f"range_{point}_m"] = None if math.isnan(value) else value
    report["uncertainty"] = uncertainty.description()
    return report
