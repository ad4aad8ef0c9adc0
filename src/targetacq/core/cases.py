"""Range cases: one sensor, one target and one path, evaluated at slant ranges.

A :class:`RangeCase` is the typed record that every range front-end describes: the range
solver (:func:`targetacq.core.ranges.dri_ranges`), the range-performance curves
(:func:`targetacq.core.ranges.range_performance`), :func:`targetacq.scene_acquisition`, the CLI's
``dri``, ``plot`` and ``report`` commands of the analyst's options (a scenario's ranges come from
the core: :mod:`targetacq.core.pair_ranges`) and
:meth:`targetacq.run.model_chain.ModelChain.range_cases`. Its inputs are checked once, when it is
made. :func:`case_acquisition` is the one place where a case becomes cycles on target,
transmittance, SNR and the ordered probabilities at ranges (:func:`case_probability` gives one
task's own curve, for the range solver). It is the array core along a line of ranges:

1. factors: the core's own function for an imaging pair
   (:func:`targetacq.core.pair_factors.imager_factors`, the one the scenario core calls after
   its geometry): ``N = d / (R · cycle)`` (§3.5, Fig. 3.3 and Eqs. (5.2), (5.3) in Sonesson
   (2004)), ``τ = exp(−γR)`` times the foliage's transmittance (Eq. (7.3), §6.8) and the SNR of
   Eqs. (7.5)–(7.7) with the sensor's own noise; an MRTD curve or a TTP system gives the
   cycles instead (:data:`RESOLUTION_MODELS`);
2. probabilities: the transform with the noise model and, for detection in clutter, the
   Schmieder–Weathersby transform, ordered ``P_id <= P_rec <= P_det``
   (:func:`targetacq.acquisition.probabilities.acquisition_probabilities`, §3.5–3.9), the kernel
   under the scenario core's probabilities too; under the ``contrast`` SNR law with the sensor's
   noise, times the probability that the target is seen above the noise
   (:func:`targetacq.acquisition.path_noise.seen_probability`).

Without ``extinction`` and ``foliage`` the path adds no noise (the SNR is +inf and the noise
model is not applied). Where the resolution model already holds the noise and the path (MRTD:
the curve is the sensor's noise-limited threshold, met by the apparent ``τ · ΔT``; TTP), the
default noise handling (``noise_model=None``) applies no SNR, so τ is counted once; a noise model
given by name is applied as given.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np

from targetacq.acquisition import transforms as _transforms
from targetacq.acquisition.criteria import Criterion, get_criterion
from targetacq.acquisition.path_noise import get_noise_model, get_snr_law, seen_probability
from targetacq.acquisition.probabilities import (
    Acquisition,
    Clutter,
    acquisition_probabilities,
    get_motion_rule,
    get_semantics,
    probability,
)
from targetacq.base import arrays as _arrays
from targetacq.base.arrays import Array
from targetacq.base.registry import lookup
from targetacq.core.pair_factors import SensorNoise, imager_factors
from targetacq.physics import optics
from targetacq.physics.ttp import TtpSystem, ttp_cycles

__all__ = [
    "NOISE_INSIDE_RESOLUTION",
    "RESOLUTION_MODELS",
    "RESOLUTION_MODEL_ALIASES",
    "CaseAcquisition",
    "RangeCase",
    "RangePerformance",
    "ResolutionModel",
    "case_acquisition",
    "case_factors",
    "case_probability",
    "get_resolution_model",
]


@dataclass(frozen=True)
class RangeCase:
    """One sensor, one target and one path, for probabilities and ranges against range.

    Array fields broadcast with each other and with the ranges they are evaluated at. The
    inputs are checked when the case is made (``ValueError`` naming the field and its valid
    range, ``TypeError`` for a value that is not real numbers); ``criterion`` is then always a
    :class:`targetacq.acquisition.criteria.Criterion`. Every quantity must be finite except ``scr``,
    whose +inf means no clutter; an array field may hold NaN (a missing value), which gives NaN
    probabilities at those elements only.

    Attributes
    ----------
    critical_dimension : array_like
        Critical dimension of the target as seen [m], > 0.
    ifov : array_like
        Pixel IFOV [rad], > 0.
    wavelength, aperture : array_like, optional
        Wavelength and aperture diameter [m] of the diffraction limit, Eq. (5.3); both or
        neither.
    blur_sigma : array_like, optional
        Angular standard deviation of a Gaussian optics blur [rad], >= 0, Eq. (5.2).
    cycle : array_like, optional
        The angle of one resolvable cycle [rad], > 0, where it is known already (e.g. from a
        scenario's sensor type); instead of the optics limits above.
    criterion : str, Criterion or mapping
        Criteria set (name, object, or task → N50 mapping).
    transform : str
        A name from :data:`targetacq.acquisition.transforms.TRANSFORMS`.
    options : mapping
        The transform's options (e.g. ``{"bound": "pessimistic"}`` for c2nveo).
    extinction : array_like, optional
        γ of the path [Np/m], >= 0; None for no atmosphere (and no path noise).
    foliage : array_like, optional
        Transmittance of foliage in front of the target, in [0, 1] (§6.8); None for none.
    scr : array_like, optional
        Signal-to-clutter ratio [1], >= 0 (acts on detection, §3.8).
    region : {"low", "medium", "high"}, optional
        Table 3.5 clutter region, instead of ``scr``.
    hot_spot, moving : bool
        Switches: the full hot-spot and motion cues (§3.9, §1.3; see
        :func:`targetacq.acquisition.transforms.schmieder_weathersby`).
    hot_spot_ratio : array_like, optional
        A graded hot spot: its own signal-to-clutter ratio [1], >= 0 (its peak contrast over the
        background's clutter and noise), whose weight blends the low-clutter curve into
        detection (:func:`targetacq.acquisition.cues.hot_spot_weight`).
    hot_spot_size : array_like, optional
        The hot spot's linear size [m], >= 0, with ``hot_spot_ratio``: smaller than a resolution
        element, its contrast is diluted (so the cue fades with range); None for no dilution.
    target_speed : array_like, optional
        A graded motion cue: the target's speed across the line of sight [m/s], >= 0; it crosses
        ``v / (R · IFOV)`` pixels per second, whose weight blends the motion rule into
        detection (:func:`targetacq.acquisition.cues.motion_weight`).
        See :func:`targetacq.acquisition.transforms.schmieder_weathersby`.
    noise_model : str, NoiseModel, callable or None
        How the noise moves the transforms (:mod:`targetacq.acquisition.path_noise`). None (the
        default): ``variance-sum``, except where the resolution model already holds the noise
        and the path (MRTD, TTP), where no SNR is applied (:attr:`applies_snr`).
    snr_law : str
        How a known contrast and sensor noise form the SNR
        (:data:`targetacq.acquisition.path_noise.SNR_LAWS`): ``contrast`` (default; the path
        radiance's noise and a detection threshold) or ``sonesson`` (Eq. (7.7) + the sensor's).
    path_contrast : array_like
        ``σ_path`` of the ``contrast`` law, > 0, in the unit of ``contrast``: the reference
        target's contrast whose SNR is Eq. (7.7) (default 1: 1 K for a ΔT in kelvin, a contrast
        ratio of 1 for a TV camera's contrast).
    contrast : array_like, optional
        Target–background contrast at the scene, in the unit of ``noise_equivalent_contrast``
        (a thermal sensor: ΔT [K]); with ``noise_equivalent_contrast``, the sensor's own noise
        (:mod:`targetacq.physics.detector_noise`).
    noise_equivalent_contrast : array_like, optional
        The sensor's noise-equivalent contrast, >= 0 (a thermal sensor: its NETD [K]).
    target_area : array_like, optional
        Area of the target's outline as seen [m²], > 0, for the pixels on target of the
        sensor's SNR; default the critical dimension squared (the fewest pixels a target of that
        critical dimension can cover).
    mrtd : MrtdCurve, optional
        The sensor's MRTD curve (:class:`targetacq.physics.mrtd.MrtdCurve`): the cycles on target
        are then MRTD-limited (:data:`RESOLUTION_MODELS` "mrtd"), with ``contrast`` the target's ΔT
        [K].
    ttp : TtpSystem, optional
        The imager, display and observer of the TTP metric
        (:class:`targetacq.physics.ttp.TtpSystem`): the cycles on target are then the TTP
        metric's V (:data:`RESOLUTION_MODELS` "ttp"), with ``contrast`` the target's ΔT [K] and
        the characteristic dimension ``sqrt(target_area)`` (or the critical dimension). Its V
        goes with V50s, not Johnson's N50s: a criterion and transform left at their defaults
        (``johnson``, ``ttpf``) become ``ttp-vehicles`` and ``ttp``.
    motion : str
        How a moving target is detected (:data:`targetacq.acquisition.probabilities.MOTION_RULES`).
    semantics : str
        What the three probabilities mean
        (:data:`targetacq.acquisition.probabilities.ACQUISITION_SEMANTICS`).
    sky_to_ground : array_like, optional
        A reflective (TV) band's sky-to-ground ratio K = L_horizon / L_background [1], >= 0, with
        ``noise_equivalent_contrast``: the path's airlight leaves the contrast
        ``C τ / (τ + (1 − τ) K)`` (Duntley's law,
        :func:`targetacq.physics.atmosphere.contrast_transmittance`); None for ``C τ`` (K = 1).
    path : optional
        The path's optical depth by a path model other than Beer–Lambert
        (:data:`targetacq.physics.named_atmospheres.PATH_MODELS`): an object with
        ``depth(range, xp)``, e.g. a :class:`targetacq.physics.named_atmospheres.NamedBandPath`
        (a named atmosphere in the sensor's band), used instead of ``extinction · range``.

    Examples
    --------
    >>> case = RangeCase(2.3, 2e-4, extinction=0.4e-3, scr=5.0)
    >>> case.criterion.name, case.attenuates
    ('johnson', True)
    >>> RangeCase(2.3, -2e-4)
    Traceback (most recent call last):
    ...
    ValueError: ifov must be > 0 rad, got -0.0002
    """

    critical_dimension: Any
    ifov: Any
    wavelength: Any = None
    aperture: Any = None
    blur_sigma: Any = None
    cycle: Any = None
    criterion: str | Criterion | Mapping[str, float] = "johnson"
    transform: str = "ttpf"
    options: Mapping[str, Any] = field(default_factory=dict)
    extinction: Any = None
    foliage: Any = None
    scr: Any = None
    region: str | None = None
    hot_spot: bool = False
    moving: bool = False
    noise_model: Any = None
    contrast: Any = None
    noise_equivalent_contrast: Any = None
    target_area: Any = None
    mrtd: Any = None
    ttp: Any = None
    motion: str = "low-clutter"
    semantics: str = "nested"
    sky_to_ground: Any = None
    hot_spot_ratio: Any = None
    hot_spot_size: Any = None
    target_speed: Any = None
    path: Any = None
    snr_law: str = "contrast"
    path_contrast: Any = 1.0

    def __post_init__(self) -> None:
        xp, (d, i) = _arrays.arrays(
            self.critical_dimension, self.ifov, names=("critical_dimension", "ifov")
        )
        _arrays.require_positive("critical_dimension", d, xp, "m")
        _arrays.require_positive("ifov", i, xp, "rad")
        _arrays.require_finite("critical_dimension", d, xp, "m")
        _arrays.require_finite("ifov", i, xp, "rad")
        _arrays.require_flag("hot_spot", self.hot_spot, arrays=False)
        _arrays.require_flag("moving", self.moving, arrays=False)
        self._check_resolution()
        if self.ttp is not None:
            self._check_ttp()
        crit = get_criterion(self.criterion)
        object.__setattr__(self, "criterion", crit)
        object.__setattr__(self, "options", dict(self.options))
        if self.extinction is not None:
            gamma = _arrays.as_float(self.extinction, xp, "extinction")
            _arrays.require_nonnegative("extinction", gamma, xp, "Np/m")
            _arrays.require_finite("extinction", gamma, xp, "Np/m")
        if self.path is not None:
            if self.extinction is not None:
                raise ValueError("give the path's extinction or a path model (path), not both")
            if not callable(getattr(self.path, "depth", None)):
                raise TypeError(f"path must have depth(range, xp); got {type(self.path).__name__}")
        if self.foliage is not None:
            tau = _arrays.as_float(self.foliage, xp, "foliage")
            _arrays.require_unit_interval("foliage", tau, xp)
        _transforms.check_clutter(self.scr, self.region, xp)
        for name, unit in (("hot_spot_ratio", ""), ("hot_spot_size", "m"), ("target_speed", "m/s")):
            if getattr(self, name) is not None:
                value = _arrays.as_float(getattr(self, name), xp, name)
                _arrays.require_nonnegative(name, value, xp, unit)
                _arrays.require_finite(name, value, xp, unit)
        self.clutter.check_cues(xp)
        if self.noise_model is not None:
            get_noise_model(self.noise_model)
        get_snr_law(self.snr_law)
        xp, (sigma,) = _arrays.arrays(self.path_contrast, names=("path_contrast",))
        _arrays.require_positive("path_contrast", sigma, xp)
        _arrays.require_finite("path_contrast", sigma, xp)
        get_motion_rule(self.motion)
        get_semantics(self.semantics)
        self._check_sensor_noise()
        if crit.gives_probabilities:
            self._check_transform(crit)
        else:
            self._check_thresholds(crit)

    def _check_resolution(self) -> None:
        optics_given = [
            name
            for name in ("wavelength", "aperture", "blur_sigma")
            if getattr(self, name) is not None
        ]
        if self.cycle is not None:
            if optics_given:
                raise ValueError(
                    f"give the cycle or the optics limits ({', '.join(optics_given)}), not both"
                )
            xp, (cycle,) = _arrays.arrays(self.cycle, names=("cycle",))
            _arrays.require_positive("cycle", cycle, xp, "rad")
            _arrays.require_finite("cycle", cycle, xp, "rad")
            return
        if (self.wavelength is None) != (self.aperture is None):
            raise ValueError(
                "give both wavelength and aperture for the diffraction limit, or neither"
            )
        for name in ("wavelength", "aperture"):
            if getattr(self, name) is not None:
                xp, (value,) = _arrays.arrays(getattr(self, name))
                _arrays.require_positive(name, value, xp, "m")
                _arrays.require_finite(name, value, xp, "m")
        if self.blur_sigma is not None:
            xp, (sigma,) = _arrays.arrays(self.blur_sigma, names=("blur_sigma",))
            _arrays.require_nonnegative("blur_sigma", sigma, xp, "rad")
            _arrays.require_finite("blur_sigma", sigma, xp, "rad")

    def _check_ttp(self) -> None:
        if not isinstance(self.ttp, TtpSystem):
            raise ValueError(f"ttp must be a TtpSystem, got {type(self.ttp).__name__}")
        if self.mrtd is not None:
            raise ValueError("give an MRTD curve or a TTP system (ttp), not both")
        if self.cycle is not None:
            raise ValueError("give the cycle or a TTP system (ttp), not both")
        if self.contrast is None:
            raise ValueError("the TTP resolution model needs the target's contrast ΔT [K]")
        if self.criterion == "johnson":
            object.__setattr__(self, "criterion", "ttp-vehicles")
        if self.transform == "ttpf":
            object.__setattr__(self, "transform", "ttp")

    def _check_sensor_noise(self) -> None:
        if self.noise_equivalent_contrast is not None and self.contrast is None:
            raise ValueError(
                "the sensor's noise (noise_equivalent_contrast, e.g. a NETD) needs the target's "
                "contrast (e.g. delta_t)"
            )
        if self.mrtd is not None:
            from targetacq.physics.mrtd import MrtdCurve

            if not isinstance(self.mrtd, MrtdCurve):
                raise ValueError(f"mrtd must be an MrtdCurve, got {type(self.mrtd).__name__}")
            if self.contrast is None:
                raise ValueError("the MRTD resolution model needs the target's contrast ΔT [K]")
            if self.cycle is not None:
                raise ValueError("give the cycle or an MRTD curve, not both")
        elif self.contrast is not None and self.noise_equivalent_contrast is None and not self.ttp:
            raise ValueError(
                "the target's contrast is used with the sensor's noise (e.g. a NETD), an MRTD "
                "curve or a TTP system; give one of them"
            )
        if self.contrast is not None:
            xp, (c,) = _arrays.arrays(self.contrast, names=("contrast",))
            _arrays.require_finite("contrast", c, xp)
        if self.noise_equivalent_contrast is not None:
            xp, (nec,) = _arrays.arrays(
                self.noise_equivalent_contrast, names=("noise_equivalent_contrast",)
            )
            _arrays.require_finite("noise_equivalent_contrast", nec, xp)
            _arrays.require_nonnegative("noise_equivalent_contrast", nec, xp)
        if self.sky_to_ground is not None:
            if self.noise_equivalent_contrast is None:
                raise ValueError(
                    "sky_to_ground reduces the contrast against the sensor's noise; give "
                    "noise_equivalent_contrast (e.g. a TV camera's NEC) and contrast"
                )
            xp, (k,) = _arrays.arrays(self.sky_to_ground, names=("sky_to_ground",))
            _arrays.require_nonnegative("sky_to_ground", k, xp)
            _arrays.require_finite("sky_to_ground", k, xp)
        if self.target_area is not None:
            xp, (a,) = _arrays.arrays(self.target_area, names=("target_area",))
            _arrays.require_positive("target_area", a, xp, "m²")
            _arrays.require_finite("target_area", a, xp, "m²")

    def _check_transform(self, crit: Criterion) -> None:
        chosen = _transforms.get_transform(self.transform)
        tasks = [t for t in crit.tasks if chosen.tasks is None or t in chosen.tasks]
        if not tasks:
            raise ValueError(
                f"transform {chosen.name!r} covers none of criterion {crit.name!r}'s tasks "
                f"({', '.join(crit.tasks)})"
            )
        chosen.check(tasks[0], self.options)

    def _check_thresholds(self, crit: Criterion) -> None:
        given = {
            **self.options,
            "scr": self.scr,
            "region": self.region,
            "hot_spot": self.hot_spot,
            "moving": self.moving,
            "hot_spot_ratio": self.hot_spot_ratio,
            "target_speed": self.target_speed,
            "extinction": self.extinction,
            "path": self.path,
            "foliage": self.foliage,
            "contrast": self.contrast,
            "noise_equivalent_contrast": self.noise_equivalent_contrast,
        }
        extras = [name for name, value in given.items() if value is not None and value is not False]
        extras = [name for name in extras if name != "extinction" or bool(self.extinction)]
        if extras:
            raise ValueError(
                f"criterion {crit.name!r} gives pixel-density thresholds; {', '.join(extras)} "
                "do not apply"
            )

    @property
    def attenuates(self) -> bool:
        """Whether the path attenuates (an extinction, a path model or foliage is given),
        adding noise."""
        return self.extinction is not None or self.path is not None or self.foliage is not None

    @property
    def noisy(self) -> bool:
        """Whether any noise acts: the path's (it attenuates) or the sensor's own."""
        return self.attenuates or self.noise_equivalent_contrast is not None

    @property
    def applies_snr(self) -> bool:
        """Whether the SNR acts on the probabilities: noise acts (:attr:`noisy`), and either a
        noise model is given or the resolution model does not already hold the noise (MRTD,
        TTP: their threshold is the sensor's noise-limited one, met by the apparent contrast)."""
        inside = self.resolution_model in NOISE_INSIDE_RESOLUTION
        return self.noisy and (self.noise_model is not None or not inside)

    @property
    def applied_noise_model(self) -> Any:
        """The noise model that acts: the one given, else ``variance-sum`` where
        :attr:`applies_snr` and ``none`` where not."""
        if self.noise_model is not None:
            return self.noise_model
        return "variance-sum" if self.applies_snr else "none"

    @property
    def seen_threshold(self) -> float | None:
        """k of the probability that the target is seen above the noise
        (:func:`targetacq.acquisition.path_noise.seen_probability`): the SNR law's, where the SNR
        acts and the sensor's noise is known; else None (no threshold)."""
        if not self.applies_snr or self.noise_equivalent_contrast is None:
            return None
        return get_snr_law(self.snr_law).threshold

    @property
    def resolution_model(self) -> str:
        """The name of the resolution model in :data:`RESOLUTION_MODELS`."""
        if self.mrtd is not None:
            return "mrtd"
        return "johnson" if self.ttp is None else "ttp"

    @property
    def characteristic_dimension(self) -> Any:
        """The TTP metric's target size ``sqrt(target_area)`` [m], or the critical dimension
        where no area is given."""
        return self.critical_dimension if self.target_area is None else self.target_area**0.5

    @property
    def in_clutter(self) -> bool:
        """Whether detection comes from the Schmieder–Weathersby transform (§3.8)."""
        return (
            self.scr is not None
            or self.region is not None
            or self.hot_spot
            or self.moving
            or self.graded
        )

    @property
    def graded(self) -> bool:
        """Whether a graded hot-spot or motion cue acts (``hot_spot_ratio``, ``target_speed``)."""
        return self.hot_spot_ratio is not None or self.target_speed is not None

    @property
    def clutter(self) -> Clutter:
        """``scr``, ``region``, the hot spot and the motion, as a
        :class:`targetacq.acquisition.probabilities.Clutter` (sizes and speeds over the critical
        dimension, as the cycles count them)."""
        d = self.critical_dimension
        return Clutter(
            scr=self.scr,
            region=self.region,
            hot_spot=self.hot_spot,
            moving=self.moving,
            hot_spot_ratio=self.hot_spot_ratio,
            hot_spot_size=None if self.hot_spot_size is None else self.hot_spot_size / d,
            speed=None if self.target_speed is None else self.target_speed / d,
        )

    def resolution(self) -> dict[str, Any]:
        """Keyword arguments of :func:`targetacq.physics.optics.cycles_on_target` and
        :func:`targetacq.physics.optics.range_for_cycles` for this case's resolution.

        A given ``cycle`` is passed as the IFOV of a sensor sampling at it, ``cycle / 2``
        (one cycle is two pixel rows, Fig. 3.3), with no optics limit.
        """
        if self.cycle is not None:
            return {"ifov": self.cycle / 2.0}
        return {
            "ifov": self.ifov,
            "wavelength": self.wavelength,
            "aperture": self.aperture,
            "blur_sigma": self.blur_sigma,
        }

    @property
    def cycle_angle(self) -> Any:
        """The angle of one resolvable cycle [rad]: ``cycle``, or the coarser of the sampling
        and the optics limits (:func:`targetacq.physics.optics.resolvable_cycle_angle`)."""
        if self.cycle is not None:
            return self.cycle
        return optics.resolvable_cycle_angle(
            self.ifov,
            wavelength=self.wavelength,
            aperture=self.aperture,
            blur_sigma=self.blur_sigma,
        )


@dataclass(frozen=True)
class RangePerformance:
    """Range-performance curves and DRI ranges for one or several cases.

    Attributes
    ----------
    curves : xarray.Dataset
        Dims ``(case, range)``; variables ``detection``, ``recognition``, ``identification``
        (ordered probabilities), ``cycles`` [cycles], ``transmittance`` and ``snr`` [dB]; the
        ``range`` coordinate in metres.
    dri : pandas.DataFrame
        One row per case, task and probability: ``range_m`` (NaN where never reached) and
        ``reached``.
    cases : Mapping[str, RangeCase]
        Each case, as a :class:`RangeCase` (mappings given are converted).
    """

    curves: Any
    dri: Any
    cases: Mapping[str, RangeCase]


@dataclass(frozen=True)
class CaseAcquisition(Acquisition):
    """A case at ranges: the probabilities (as
    :class:`targetacq.acquisition.probabilities.Acquisition`, ordered) and the factors behind them,
    each of the broadcast shape of case and ranges.

    Attributes
    ----------
    cycles : array_like
        N [cycles].
    transmittance : array_like
        τ of the path, foliage included [1].
    snr : array_like
        Total SNR [dB]: the path's of Eq. (7.7) and the sensor's own, added in variance
        (+inf where neither is given).
    """

    cycles: Any
    transmittance: Any
    snr: Any


@dataclass(frozen=True)
class ResolutionModel:
    """How a case's sensor resolves its target: ``cycles(case, range, transmittance) -> N``.

    ``includes_noise``: whether the model's cycles already account for the sensor's noise and
    the path's transmittance on the contrast (MRTD, TTP), so that a separate SNR noise model
    would count them twice.
    """

    name: str
    cycles: Callable[[RangeCase, Any, Any], Any]
    source: str
    includes_noise: bool = False


def _geometric_cycles(case: RangeCase, range: Any, transmittance: Any) -> Any:
    return optics.cycles_on_target(case.critical_dimension, range, **case.resolution())


def _mrtd_cycles(case: RangeCase, range: Any, transmittance: Any) -> Any:
    from targetacq.physics.mrtd import mrtd_cycles

    return mrtd_cycles(range, case.critical_dimension, case.contrast, transmittance, case.mrtd)


def _ttp_cycles(case: RangeCase, range: Any, transmittance: Any) -> Any:
    return ttp_cycles(range, case.characteristic_dimension, case.contrast, transmittance, case.ttp)


RESOLUTION_MODELS: Mapping[str, ResolutionModel] = MappingProxyType(
    {
        "johnson": ResolutionModel(
            "johnson",
            _geometric_cycles,
            "Johnson's pixel model: N = d / (R · cycle), one cycle two pixels or the optics "
            "limit (Sonesson 2004 §3.5, Fig. 3.3, Eqs. (5.2), (5.3))",
        ),
        "mrtd": ResolutionModel(
            "mrtd",
            _mrtd_cycles,
            "MRTD-limited, STANAG 4347 style: N = f*(R) · d / R with MRTD(f*) = τ(R) ΔT "
            "(:func:`targetacq.physics.mrtd.mrtd_cycles`)",
            includes_noise=True,
        ),
        "ttp": ResolutionModel(
            "ttp",
            _ttp_cycles,
            "targeting task performance metric: V = d / R · ∫ sqrt(C / CTF_sys) dξ, contrast "
            "and system MTF with noise (Vollmerhausen, Jacobs & Driggers, Opt. Eng. 43(11) "
            "2004; :func:`targetacq.physics.ttp.ttp_cycles`)",
            includes_noise=True,
        ),
    }
)
"""Resolution models of a range case, by name (read-only): ``johnson`` is the default,
``mrtd`` applies where the case has an MRTD curve and ``ttp`` where it has a TTP system."""

RESOLUTION_MODEL_ALIASES: Mapping[str, str] = MappingProxyType({"geometric": "johnson"})
"""Former names of resolution models, still accepted by :func:`get_resolution_model`."""


def get_resolution_model(name: str) -> ResolutionModel:
    """A resolution model by name (or a former name, ``geometric`` for ``johnson``).

    Raises
    ------
    ValueError
        For an unknown name, listing the valid ones.

    Examples
    --------
    >>> get_resolution_model("geometric").name
    'johnson'
    """
    return lookup(RESOLUTION_MODELS, RESOLUTION_MODEL_ALIASES.get(name, name), "resolution model")


NOISE_INSIDE_RESOLUTION = frozenset(
    name for name, model in RESOLUTION_MODELS.items() if model.includes_noise
)
"""Resolution models whose threshold already holds the sensor's noise and the path's
transmittance (the MRTD curve met by ``τ · ΔT``; the TTP metric's noise-raised contrast threshold):
with the default noise handling no SNR is applied on top (:attr:`RangeCase.applies_snr`)."""


def case_factors(case: RangeCase, range: Array) -> tuple[Any, Any, Any]:
    """Cycles on target, transmittance and SNR of a case at ranges.

    The array core's factors of an imaging pair (:func:`targetacq.core.pair_factors.imager_factors`)
    along the line of ranges: ``N = d / (R · cycle)`` with the case's cycle angle (§3.5,
    Eqs. (5.2), (5.3) in Sonesson (2004)), the optical depth ``γR − ln τ_foliage`` (Eq. (7.3),
    §6.8), so ``τ = exp(−γR) · τ_foliage``, and the SNR of Eqs. (7.5)–(7.7) added in variance to
    the sensor's own (:func:`targetacq.physics.detector_noise.sensor_snr`, with the pixels the
    target's area covers at the sensor's IFOV). An MRTD curve or a TTP system then gives the
    cycles instead (:data:`RESOLUTION_MODELS`).

    Parameters
    ----------
    case : RangeCase
    range : array_like
        Slant range [m], > 0.

    Returns
    -------
    cycles, transmittance, snr : array_like
        [cycles], [1], [dB].

    Examples
    --------
    >>> n, tau, snr = case_factors(RangeCase(2.3, 2e-4, extinction=1e-3), 1150.0)
    >>> round(float(n), 12), round(float(tau), 6), round(float(snr), 3)
    (5.0, 0.316637, -6.682)
    """
    xp, (r,) = _arrays.arrays(range, names=("range",))
    _arrays.require_positive("range", r, xp, "m")
    depth = 0.0 if case.extinction is None else case.extinction * r
    if case.path is not None:  # a path model's optical depth, not Beer-Lambert in range
        depth = case.path.depth(r, xp)
    if case.foliage is not None:  # τ_f more in front of the target: −ln τ_f of depth (§6.8)
        with np.errstate(divide="ignore"):
            depth = depth - xp.log(_arrays.as_float(case.foliage, xp))
    noise = None
    if case.noise_equivalent_contrast is not None:
        noise = SensorNoise(
            contrast=case.contrast,
            noise_equivalent=case.noise_equivalent_contrast,
            ifov=case.resolution()["ifov"],
            area=case.critical_dimension**2 if case.target_area is None else case.target_area,
            sky_to_ground=case.sky_to_ground,
            path_contrast=case.path_contrast,
            law=case.snr_law,
        )
    cycles, tau, snr = imager_factors(r, case.critical_dimension, case.cycle_angle, depth, noise)
    if case.resolution_model != "johnson":
        cycles = RESOLUTION_MODELS[case.resolution_model].cycles(case, r, tau)
    return cycles, tau, snr


def case_acquisition(case: RangeCase, range: Array) -> CaseAcquisition:
    """Cycles, transmittance, SNR and the ordered probabilities of a case at ranges.

    The factors of :func:`case_factors` and the probabilities of
    :func:`targetacq.acquisition.probabilities.acquisition_probabilities` (detection in clutter from
    Table 3.5, §3.8; ``P_id <= P_rec <= P_det``), with the SNR applied through the case's noise
    model where the path attenuates.

    Parameters
    ----------
    case : RangeCase
        Its transform must cover detection, recognition and identification.
    range : array_like
        Slant range [m], > 0.

    Returns
    -------
    CaseAcquisition

    Examples
    --------
    >>> found = case_acquisition(RangeCase(2.3, 2e-4), 1150.0)  # N = 5 cycles
    >>> round(float(found.cycles), 12), round(float(found.detection), 4)
    (5.0, 1.0)
    >>> round(float(found.recognition), 4)  # TTPF at N/N50 = 5/4, Eq. (3.2)
    0.6895
    """
    cycles, tau, snr = case_factors(case, range)
    acq = acquisition_probabilities(
        cycles,
        case.criterion,
        case.transform,
        snr=snr if case.applies_snr else None,
        noise_model=case.applied_noise_model,
        motion=case.motion,
        semantics=case.semantics,
        clutter=case.clutter,
        **case.options,
    )
    seen = _seen(case, snr)
    return CaseAcquisition(
        detection=acq.detection * seen,
        recognition=acq.recognition * seen,
        identification=acq.identification * seen,
        semantics=acq.semantics,
        cycles=cycles,
        transmittance=tau,
        snr=snr,
    )


def case_probability(case: RangeCase, range: Array, task: str) -> Any:
    """Probability of one task of a case at ranges: the task's own (marginal) curve.

    :func:`targetacq.acquisition.probabilities.probability` at the factors of :func:`case_factors`;
    for any task of the criterion that the transform covers (e.g. orientation, or detection alone
    with the Schmieder–Weathersby transform). :func:`case_acquisition` gives the ordered three.

    Parameters
    ----------
    case : RangeCase
    range : array_like
        Slant range [m], > 0.
    task : str
        A task of the case's criterion.

    Returns
    -------
    array_like
        P in [0, 1].

    Examples
    --------
    >>> round(float(case_probability(RangeCase(2.3, 2e-4), 1150.0, "recognition")), 4)
    0.6895
    """
    cycles, _, snr = case_factors(case, range)
    p = probability(
        cycles,
        task,
        case.criterion,
        case.transform,
        snr=snr if case.applies_snr else None,
        noise_model=case.applied_noise_model,
        motion=case.motion,
        clutter=case.clutter,
        **case.options,
    )
    return p * _seen(case, snr)


def _seen(case: RangeCase, snr: Any) -> Any:
    """The probability that the case's target is seen above the noise (1 without a threshold)."""
    k = case.seen_threshold
    if k is None:
        return 1.0
    xp, (nec,) = _arrays.arrays(case.noise_equivalent_contrast)
    return seen_probability(snr, xp.where(nec > 0, k, -xp.inf))  # NEC 0: no noise of its own
