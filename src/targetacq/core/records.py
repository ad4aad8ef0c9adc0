"""Typed records of arrays: what the core computes from.

Every quantity is an SI float array; names carry no unit suffixes. The records are frozen
dataclasses. Their array fields are the *data* of a JAX pytree and their other fields (names,
flags, model choices) the static *metadata*, so a compiled scene can be passed through
``jax.jit``, ``vmap`` and ``grad`` (:func:`register_pytrees`; JAX is never imported unless it is
used). Nothing here holds physics: :mod:`targetacq.core.compile` fills the records from a
scenario and :mod:`targetacq.core.evaluation` computes from them.

JAX (``pip install 'targetacq[jax]'``)::

    import jax, jax.numpy as jnp
    jax.config.update("jax_enable_x64", True)  # float64, as NumPy: equal to about 1e-12
    scene = as_jax(compile_scenario(load_scenario(path)))  # registers the pytrees too
    p = jax.jit(evaluate)(scene, jnp.asarray(sensors), jnp.asarray(targets))[1]

:func:`to_namespace` converts a record to any other array namespace.

Shapes: ``n_s`` sensors, ``n_g`` targets, ``n_seg`` path segments, ``n_c`` local clouds.
"""

from __future__ import annotations

import dataclasses
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, TypeVar

import numpy as np

from targetacq.base.arrays import Array

_R = TypeVar("_R")
_V = TypeVar("_V")

__all__ = [
    "LaserArrays",
    "ModelChoices",
    "MrtdArrays",
    "PathArrays",
    "RadarArrays",
    "SceneArrays",
    "SensorArrays",
    "SignatureArrays",
    "TargetArrays",
    "TtpArrays",
    "as_jax",
    "derived",
    "pytree_record",
    "register_pytrees",
    "take_targets",
    "to_namespace",
]


_RECORDS: list[type] = []  # the records that are JAX pytrees (pytree_record)


def derived(record: Any, key: str, compute: Callable[[Any], _V]) -> _V:
    """A value derived from a record's fields, computed once per record and kept on it.

    The records are frozen and their arrays are read, never written, so what depends on them
    alone (a grouping of the targets' criteria, the sensors' fixed pointing) need not be
    computed again on every call. The value lives on the record itself, outside its fields: it
    is no part of its equality, of its pytree, nor of a copy made by ``dataclasses.replace``
    (which computes it afresh), and it goes when the record goes.

    Parameters
    ----------
    record : a record of this module
    key : str
        What is derived (one value per key).
    compute : callable
        ``compute(record) -> value``.
    """
    cache = record.__dict__.get("_derived")
    if cache is None:
        cache = {}
        object.__setattr__(record, "_derived", cache)
    if key not in cache:
        cache[key] = compute(record)
    return cache[key]


def _static(default: Any = dataclasses.MISSING) -> Any:
    if default is dataclasses.MISSING:
        return field(metadata={"static": True})
    return field(default=default, metadata={"static": True})


_REGISTERED: set[type] = set()  # records already known to JAX (registration is once per process)


def _register(record: type) -> None:
    import jax

    if record in _REGISTERED:
        return
    fields = dataclasses.fields(record)
    data = [f.name for f in fields if not f.metadata.get("static")]
    meta = [f.name for f in fields if f.metadata.get("static")]
    jax.tree_util.register_dataclass(record, data_fields=data, meta_fields=meta)
    _REGISTERED.add(record)


def pytree_record(cls: type[_R]) -> type[_R]:
    """Class decorator: a frozen dataclass of the core whose non-static fields are pytree data.

    The class joins the records that :func:`register_pytrees` registers (at once, where JAX is
    already imported). Fields marked ``metadata={"static": True}`` are the pytree's metadata.
    """
    _RECORDS.append(cls)
    if "jax" in sys.modules:  # JAX already in use: the record works under jit at once
        _register(cls)
    return cls


@pytree_record
@dataclass(frozen=True)
class SensorArrays:
    """The sensors.

    Attributes
    ----------
    cycle : array (n_s,)
        Angle of one resolvable cycle [rad] (the resolution model of the sensor's type).
    ifov : array (n_s,)
        Pixel IFOV [rad] (the footprint on terrain clutter).
    half_tangents : array (n_s, 2)
        tan(FOV_h / 2), tan(FOV_v / 2); NaN where the sensor has no field of view.
    look_at : array (n_s, 3)
        A point the sensor is pointed at [m]; NaN where it is pointed by angles or not at all.
    pointing : array (n_s, 2)
        Azimuth (from north, clockwise) and depression (below the horizon) [rad]; NaN where
        not pointed by angles.
    extinction : array (n_s,)
        Extinction of the path in the sensor's band outside the segments [Np/m].
    segment_extinction : array (n_s, n_seg)
        Extinction of each segment in the sensor's band [Np/m].
    noise_equivalent : array (n_s,)
        Signal difference equal to the sensor's own noise [W/m²]; 0 where none is given
        (:mod:`targetacq.physics.detector_noise`).
    names : tuple of str
    types : tuple of str
        Sensor types (:data:`targetacq.sensors.SENSOR_TYPES`).
    pointed : tuple of bool
        Whether the scenario points each sensor (look_at or angles); unpointed sensors see every
        target.
    has_noise : bool
        Whether any sensor has noise of its own (static, so the noise-free path stays exactly
        as it was when none has).
    groups : tuple of str
        The scenario sensor each row belongs to: its own name, or, for a band of a colour
        camera, the camera's name. Rows of one group see the scene through the same optics: the
        sensor-level fusion takes the best of them
        (:func:`targetacq.acquisition.fusion.fuse_groups`) and the step API draws their outcomes
        from the same random stream. Empty: every row is its own
        group.
    mrtd : MrtdArrays or None
        The rows whose resolution is MRTD-limited (thermal sensors with an ``mrtd`` curve);
        None where no sensor has one.
    quantisation_step : array (n_s,) or None
        The smallest contrast each row's digitiser resolves [W/m²] (§6.8,
        :func:`targetacq.physics.radiometry.quantisation_step`): a pair whose contrast at the scene
        (:attr:`SignatureArrays.contrast`) is below it has every probability 0. 0 where a row
        has none; None where no row has one.
    path_contrast : array (n_s,) or None
        ``σ_path`` of the ``contrast`` SNR law [W/m²] (:class:`ModelChoices`): each row's
        reference contrast (:attr:`targetacq.sensors.SensorType.path_contrast`); None: unknown,
        the SNR is then formed by the ``sonesson`` law.
    ttp : TtpArrays or None
        The rows whose resolution is the TTP metric (thermal sensors under ``[model]
        resolution_model = "ttp"``); None where there are none.
    sky_to_ground : array (n_s,) or None
        The sky-to-ground ratio K [1] of the background each row's own noise sees its contrast
        against: a reflective (TV, colour) row's path airlight leaves ``τ / (τ + (1 − τ) K)`` of
        the contrast (:func:`targetacq.physics.atmosphere.contrast_transmittance`); 1 for the
        other rows (``τ``); None where the scene gives none.
    """

    cycle: Any
    ifov: Any
    half_tangents: Any
    look_at: Any
    pointing: Any
    extinction: Any
    segment_extinction: Any
    noise_equivalent: Any
    names: tuple[str, ...] = _static()
    types: tuple[str, ...] = _static()
    pointed: tuple[bool, ...] = _static()
    has_noise: bool = _static(False)
    groups: tuple[str, ...] = _static(())
    mrtd: MrtdArrays | None = None
    quantisation_step: Any = None
    path_contrast: Any = None
    ttp: TtpArrays | None = None
    sky_to_ground: Any = None

    @property
    def group_names(self) -> tuple[str, ...]:
        """The group of every row: :attr:`groups`, or the row's own name where it is empty."""
        return self.groups or self.names


@pytree_record
@dataclass(frozen=True)
class MrtdArrays:
    """The sensor rows whose resolution is MRTD-limited (:mod:`targetacq.physics.mrtd`), one entry
    each.

    The cycles on target of these rows are ``f*(τ ΔT) · d / R``
    (:func:`targetacq.physics.mrtd.mrtd_cycles`) instead of the geometric ``d / (R · cycle)``, with
    ΔT the pair's exitance contrast turned into the blackbody temperature difference that gives it
    at the reference temperature.

    Attributes
    ----------
    exitance_slope : array (n_m,)
        ``∂M_bb,band/∂T`` of each row's band at its reference temperature (the sensor's
        ``netd_temperature``) [W/(m²·K)]: the contrast [W/m²] over it is ΔT [K].
    rows : tuple of int
        The rows among the scene's sensors.
    curves : tuple of targetacq.physics.mrtd.MrtdCurve
        Each row's curve (static: the kernel's tables are constants under ``jax.jit``).
    """

    exitance_slope: Any
    rows: tuple[int, ...] = _static()
    curves: tuple[Any, ...] = _static()


@pytree_record
@dataclass(frozen=True)
class TtpArrays:
    """The sensor rows whose resolution is the TTP metric (:mod:`targetacq.physics.ttp`), one
    entry each (:mod:`targetacq.core.ttp_rows`).

    The cycles on target of these rows are the TTP metric's ``V``
    (:func:`targetacq.physics.ttp.ttp_cycles`) at the pair's range, ΔT and transmittance instead
    of the geometric ``d / (R · cycle)``, with ΔT the pair's exitance contrast over the slope
    ``∂M_bb,band/∂T`` at the reference temperature (as :class:`MrtdArrays`).

    Attributes
    ----------
    exitance_slope : array (n_t,)
        ``∂M_bb,band/∂T`` of each row's band at its sensor's ``netd_temperature`` [W/(m²·K)].
    rows : tuple of int
        The rows among the scene's sensors.
    systems : tuple of targetacq.physics.ttp.TtpSystem
        Each row's imager, display and observer (static: constants under ``jax.jit``).
    """

    exitance_slope: Any
    rows: tuple[int, ...] = _static()
    systems: tuple[Any, ...] = _static()


@pytree_record
@dataclass(frozen=True)
class TargetArrays:
    """The targets.

    Attributes
    ----------
    dimensions : array (n_g, 3)
        Box length, width, height [m].
    visible_fraction : array (n_g,)
        Fraction of the height in view, in (0, 1].
    heading : array (n_g,)
        Direction of the long axis where no heading is given per step [rad].
    n50 : array (n_g, 3)
        Cycles for P = 0.5 of detection, recognition, identification.
    names : tuple of str
    hot_spot, moving : tuple of bool
    foliage : array (n_g,) or None
        Transmittance ``τ_f`` of foliage in front of each target, in [0, 1] [1] (§6.8): it
        multiplies the path's transmittance, so the pair's optical depth gains ``−ln τ_f`` (an
        imaging sensor's path; τ_f = 0 hides the target: P = 0). 1 where a target has none;
        None where no target has any. Where it is given the path adds noise
        (:attr:`PathArrays.attenuates` must then be True, as the compiled scenario has it).
    hot_spot_ratio : array (n_g,) or None
        A graded hot spot's own signal-to-clutter ratio [1], >= 0
        (:func:`targetacq.acquisition.cues.hot_spot_weight`); 0 where a target has none (weight
        0: detection exactly as without); None where no target has one.
    hot_spot_size : array (n_g,) or None
        The hot spot's linear size [m], > 0: smaller than a resolution element it is diluted;
        NaN where a target gives none (no dilution); None where no target gives one.
    graded_motion : tuple of bool
        Which targets have a motion cue graded by their angular speed across the line of sight
        (:func:`targetacq.acquisition.cues.motion_weight`, from the pairs'
        :attr:`targetacq.core.Factors.crossing_speed`); empty: none.
    """

    dimensions: Any
    visible_fraction: Any
    heading: Any
    n50: Any
    names: tuple[str, ...] = _static()
    hot_spot: tuple[bool, ...] = _static()
    moving: tuple[bool, ...] = _static()
    foliage: Any = None
    hot_spot_ratio: Any = None
    hot_spot_size: Any = None
    graded_motion: tuple[bool, ...] = _static(())

    @property
    def graded(self) -> bool:
        """Whether a graded hot spot or a graded motion cue acts on any target."""
        return self.hot_spot_ratio is not None or any(self.graded_motion)


@pytree_record
@dataclass(frozen=True)
class PathArrays:
    """The path between sensors and targets, besides each band's base extinction.

    Attributes
    ----------
    segment_length : array (n_seg,)
        Lengths of the segments laid from each sensor outward [m].
    cloud_center : array (n_c, 3)
        [m].
    cloud_radius : array (n_c,)
        [m].
    cloud_extinction : array (n_c,)
        [Np/m].
    attenuates : bool
        Whether the path has an atmosphere at all, or foliage in front of a target (neither:
        no path noise).
    named_ranges : tuple of float
        The ranges [m] of a named atmosphere's table (:mod:`targetacq.physics.named_atmospheres`),
        static; empty: no named atmosphere (the path is Beer–Lambert in each band's extinction).
    named_depths : array (n_s, n_k) or None
        Each sensor row's band-mean optical depth at ``named_ranges`` (0 for a radar), which
        :func:`targetacq.physics.named_atmospheres.tabulated_depth` interpolates per pair; it
        adds to the segments' and clouds' depths.
    """

    segment_length: Any
    cloud_center: Any
    cloud_radius: Any
    cloud_extinction: Any
    attenuates: bool = _static(False)
    named_ranges: tuple[float, ...] = _static(())
    named_depths: Any = None


@pytree_record
@dataclass(frozen=True)
class AspectArrays:
    """Signatures that depend on the aspect (:mod:`targetacq.physics.aspect`): each pair's
    contrast tabulated over where the sensor sees the target from.

    Every target's table is on one grid of the scene (the union of the tables' nodes, on which
    each table's bilinear interpolant is exact); a target without a table has its one contrast
    at every node.

    Attributes
    ----------
    azimuth : array (n_az,)
        The grid's azimuths [rad], ascending in [0, 2π), from the target's heading clockwise.
    elevation : array (n_el,)
        The grid's elevations [rad], ascending.
    contrast : array (n_s, n_g, n_az, n_el)
        ``|target − background|`` signal at the scene [W/m²] at each node.
    clutter : array (n_s, n_g) or None
        The clutter spread [W/m²] whose ratio to the contrast is the SCR (a background's
        ``clutter_std``); None where the SCR does not follow the contrast (a given SCR, an
        image's, none).
    """

    azimuth: Any
    elevation: Any
    contrast: Any
    clutter: Any = None


@pytree_record
@dataclass(frozen=True)
class SignatureArrays:
    """What each sensor sees of each target, independent of where they are.

    Attributes
    ----------
    contrast : array (n_s, n_g)
        ``|target − background|`` signal at the scene [W/m²].
    target : array (n_s, n_g)
        Target signal [W/m²] (a radar's row: the radar cross-section [m²]; a laser radar's:
        the reflectance at its wavelength).
    scr : array (n_s, n_g) or None
        Signal-to-clutter ratio where the clutter does not depend on the positions; None where
        the scenario gives no clutter measure (or a terrain map, evaluated per position).
        With :attr:`aspect`, ``contrast`` and ``scr`` are those the pair's aspect replaces.
    clutter_rows : tuple of bool
        Which sensor rows have a clutter measure (the SCR, a terrain map), where that differs
        from row to row (a scene with radars or laser radars); empty: every row has one exactly
        when ``scr`` is given (or an SCR is passed per position).
    aspect : AspectArrays or None
        Contrasts (and SCRs) over the aspect, for scenes whose targets have signature tables;
        the core reads each pair's at its aspect.
    """

    contrast: Any
    target: Any
    scr: Any = None
    clutter_rows: tuple[bool, ...] = _static(())
    aspect: AspectArrays | None = None

    def rows_with_clutter(self, n_rows: int, given: bool) -> tuple[bool, ...]:
        """Whether each of ``n_rows`` rows has a clutter measure: :attr:`clutter_rows`, or
        ``given`` (an SCR at hand) for every row where that is empty."""
        return self.clutter_rows or (given,) * n_rows


@pytree_record
@dataclass(frozen=True)
class RadarArrays:
    """The radars of a scene (:mod:`targetacq.sensors.radar`), one row per radar.

    Attributes
    ----------
    constant : array (n_r,)
        ``K`` of the radar equation ``SNR = K σ τ² / R⁴`` [m²]
        (:func:`targetacq.physics.radar_equation.radar_constant`).
    beamwidth : array (n_r,)
        Azimuth beamwidth [rad], Eq. (9.1).
    pulse_length : array (n_r,)
        [s], Eq. (9.2).
    extinction : array (n_r,)
        One-way power extinction of the rain at the radar's frequency [Np/m].
    sigma0 : array (n_r,)
        The ground's backscatter coefficient σ⁰ [m²/m²].
    false_alarm : array (n_r,)
        P_fa of the detector.
    pulses : array (n_r,)
        Pulses integrated.
    cells50 : array (n_r, 2)
        Cells on target for P = 0.5 of recognition and identification.
    rows : tuple of int
        The radars' rows among the scene's sensors.
    detectors : tuple of str
        Each radar's P_d model (:data:`targetacq.physics.radar_equation.RADAR_DETECTION_MODELS`).
    """

    constant: Any
    beamwidth: Any
    pulse_length: Any
    extinction: Any
    sigma0: Any
    false_alarm: Any
    pulses: Any
    cells50: Any
    rows: tuple[int, ...] = _static()
    detectors: tuple[str, ...] = _static()


@pytree_record
@dataclass(frozen=True)
class LaserArrays:
    """The laser radars of a scene (:mod:`targetacq.sensors.laser_radar`), one row each.

    Attributes
    ----------
    power : array (n_l,)
        Transmitted power [W].
    aperture_area : array (n_l,)
        Receiver area [m²].
    efficiency : array (n_l,)
        Of the optics and detector [1].
    nep : array (n_l,)
        Noise-equivalent power [W]; 0: no receiver noise.
    rows : tuple of int
        The laser radars' rows among the scene's sensors.
    """

    power: Any
    aperture_area: Any
    efficiency: Any
    nep: Any
    rows: tuple[int, ...] = _static()


@dataclass(frozen=True)
class ModelChoices:
    """The model's named choices (static: they select code, not numbers).

    Attributes
    ----------
    transform : str
        :data:`targetacq.acquisition.transforms.TRANSFORMS`.
    options : tuple of (str, object)
        The transform's options.
    noise_model : str
        :data:`targetacq.acquisition.path_noise.NOISE_MODELS`.
    region : str or None
        A Table 3.5 clutter region for every pair.
    search_time : float
        t_s of the search model [s].
    motion : str
        :data:`targetacq.acquisition.probabilities.MOTION_RULES`.
    semantics : str
        :data:`targetacq.acquisition.probabilities.ACQUISITION_SEMANTICS`.
    snr_law : str
        :data:`targetacq.acquisition.path_noise.SNR_LAWS` (default ``contrast``).
    snr_on_mrtd : bool
        Whether the SNR acts on the MRTD-limited rows too (a noise model named by the user); by
        default not: their curve already holds the sensor's noise and the path (``τ · ΔT``).
    """

    transform: str = "ttpf"
    options: tuple[tuple[str, Any], ...] = ()
    noise_model: str = "variance-sum"
    region: str | None = None
    search_time: float = 3.4
    motion: str = "low-clutter"
    semantics: str = "nested"
    snr_law: str = "contrast"
    snr_on_mrtd: bool = False


@pytree_record
@dataclass(frozen=True)
class SceneArrays:
    """Everything the core needs besides positions, pointing and headings."""

    sensors: SensorArrays
    targets: TargetArrays
    path: PathArrays
    signature: SignatureArrays
    choices: ModelChoices = field(default_factory=ModelChoices, metadata={"static": True})
    radar: RadarArrays | None = None
    laser: LaserArrays | None = None

    @property
    def shape(self) -> tuple[int, int]:
        """(n_sensors, n_targets)."""
        return len(self.sensors.names), len(self.targets.names)


def _target_index(index: Any, count: int) -> np.ndarray:
    """``index`` as an int64 NumPy array (M,) of targets in [0, count), else ``ValueError``."""
    valid = f"integers in [0, {count - 1}]" if count else "none (the scene has no targets)"
    given = np.asarray(index)
    if given.ndim != 1:
        raise ValueError(
            f"targets: the index must be an array of shape (M,) of {valid}; got shape {given.shape}"
        )
    if given.size == 0:
        return np.zeros(0, dtype=np.int64)
    if given.dtype.kind not in "iu":
        raise ValueError(f"targets: the index must hold {valid}; got {given.dtype} values")
    low, high = int(given.min()), int(given.max())
    if low < 0 or high >= count:
        bad = low if low < 0 else high
        raise ValueError(
            f"targets: index {bad} is outside the scene's {count} targets; valid: {valid}"
        )
    return given.astype(np.int64, copy=False)


def _take(value: Any, index: np.ndarray, axis: int) -> Any:
    """``value`` taken at ``index`` along ``axis`` (NumPy fancy indexing, else ``xp.take``)."""
    if value is None:
        return None
    if isinstance(value, np.ndarray):
        return np.take(value, index, axis=axis)
    import array_api_compat

    xp = array_api_compat.array_namespace(value)
    return xp.take(value, xp.asarray(index), axis=axis)


def take_targets(scene: SceneArrays, index: Array) -> SceneArrays:
    """The scene whose targets are ``scene.targets[index]``, in that order.

    Every per-target array is taken along its target axis: the targets' fields (dimensions,
    visible fraction, heading, N50s, names, hot-spot and moving flags, foliage, graded cues)
    and the signature's ``contrast``, ``target`` and ``scr`` (axis 1 of their ``(n_s, n_g)``).
    The sensors, the path, the model choices and the radar and laser-radar rows are per sensor
    and are kept. Evaluating
    the subset at ``target_positions[index]`` gives the whole scene's numbers at
    ``[:, index]``: nothing in the core depends on the other targets.

    Parameters
    ----------
    scene : SceneArrays
        NumPy arrays, or any array namespace with ``take`` (JAX).
    index : array_like of int, shape (M,)
        Indices of the scene's targets in ``[0, n_g − 1]``; repeats and any order allowed (a
        target taken twice appears twice, with its name twice); M = 0 gives a scene with no
        targets.

    Returns
    -------
    SceneArrays

    Raises
    ------
    ValueError
        ``index`` not a one-dimensional array of integers, or an index outside ``[0, n_g − 1]``
        (the message names ``targets`` and the valid range).

    Examples
    --------
    >>> import numpy as np
    >>> from targetacq.core import take_targets
    >>> from targetacq.core.records import SceneArrays, SensorArrays, TargetArrays
    >>> from targetacq.core.records import PathArrays, SignatureArrays
    >>> targets = TargetArrays(
    ...     dimensions=np.array([[7.0, 2.5, 3.0], [4.0, 2.0, 2.0]]),
    ...     visible_fraction=np.array([1.0, 0.5]), heading=np.zeros(2),
    ...     n50=np.ones((2, 3)), names=("truck", "jeep"), hot_spot=(False, True),
    ...     moving=(False, False))
    >>> sensors = SensorArrays(np.ones(1), np.ones(1), np.ones((1, 2)), np.ones((1, 3)),
    ...     np.ones((1, 2)), np.zeros(1), np.zeros((1, 0)), np.zeros(1), names=("ir",),
    ...     types=("thermal",), pointed=(False,))
    >>> path = PathArrays(np.zeros(0), np.zeros((0, 3)), np.zeros(0), np.zeros(0))
    >>> scene = SceneArrays(sensors, targets, path,
    ...     SignatureArrays(contrast=np.array([[1.0, 2.0]]), target=np.array([[3.0, 4.0]])))
    >>> subset = take_targets(scene, [1, 1, 0])
    >>> subset.targets.names, subset.targets.hot_spot
    (('jeep', 'jeep', 'truck'), (True, True, False))
    >>> subset.signature.contrast.tolist()
    [[2.0, 2.0, 1.0]]
    """
    if not isinstance(scene, SceneArrays):
        raise TypeError(f"take_targets takes a SceneArrays, got {type(scene).__name__}")
    chosen = _target_index(index, scene.shape[1])
    picked = chosen.tolist()
    t, sig = scene.targets, scene.signature
    targets = dataclasses.replace(
        t,
        dimensions=_take(t.dimensions, chosen, 0),
        visible_fraction=_take(t.visible_fraction, chosen, 0),
        heading=_take(t.heading, chosen, 0),
        n50=_take(t.n50, chosen, 0),
        names=tuple(t.names[k] for k in picked),
        hot_spot=tuple(t.hot_spot[k] for k in picked),
        moving=tuple(t.moving[k] for k in picked),
        foliage=_take(t.foliage, chosen, 0),
        hot_spot_ratio=_take(t.hot_spot_ratio, chosen, 0),
        hot_spot_size=_take(t.hot_spot_size, chosen, 0),
        graded_motion=tuple(t.graded_motion[k] for k in picked) if t.graded_motion else (),
    )
    signature = dataclasses.replace(
        sig,
        contrast=_take(sig.contrast, chosen, 1),
        target=_take(sig.target, chosen, 1),
        scr=_take(sig.scr, chosen, 1),
        aspect=None
        if sig.aspect is None
        else dataclasses.replace(
            sig.aspect,
            contrast=_take(sig.aspect.contrast, chosen, 1),
            clutter=_take(sig.aspect.clutter, chosen, 1),
        ),
    )
    return dataclasses.replace(scene, targets=targets, signature=signature)


def register_pytrees() -> None:
    """Register the records as JAX pytrees (idempotent; imports JAX).

    Needed before a record is passed to ``jax.jit``, ``vmap`` or ``grad``. It is done at import
    where JAX was imported before targetacq, and by :func:`as_jax`; otherwise call it once.
    """
    for record in _RECORDS:
        _register(record)


def _convert(value: Any, xp: Any) -> Any:
    if value is None:
        return None
    if type(value) in _RECORDS:
        return to_namespace(value, xp)
    return xp.asarray(value)


def to_namespace(record: _R, xp: Any) -> _R:
    """The record with every array field an array of namespace ``xp`` (``xp.asarray``).

    Nested records are converted too; static fields (names, flags, model choices) and None
    fields are kept as they are. Values are not checked again: they were checked when the
    scenario was compiled.

    Parameters
    ----------
    record : SceneArrays or any record of this module
    xp : module
        An array namespace, e.g. ``jax.numpy``. ``jax.numpy`` keeps float64 only with
        ``jax.config.update("jax_enable_x64", True)`` (:func:`as_jax`).

    Returns
    -------
    record
        A new record of the same type.
    """
    if type(record) not in _RECORDS:
        raise TypeError(f"to_namespace takes a record of targetacq.core, got {type(record)!r}")
    changes = {
        f.name: _convert(getattr(record, f.name), xp)
        for f in dataclasses.fields(record)  # type: ignore[arg-type]
        if not f.metadata.get("static")
    }
    return dataclasses.replace(record, **changes)  # type: ignore[type-var]


def as_jax(scene: Any) -> SceneArrays:
    """A scene with JAX arrays, ready for ``jax.jit``, ``vmap`` and ``grad`` of the core.

    Registers the records as pytrees (:func:`register_pytrees`) and converts every array field
    with ``jax.numpy.asarray``, to concrete arrays even inside ``jax.jit`` (so the scene can be
    made once, lazily, and kept).

    Precision: the NumPy core computes in float64. JAX does so only with
    ``jax.config.update("jax_enable_x64", True)`` (set before the arrays are made); the jitted
    core then equals the NumPy one to about 1e-12 relative. Without it JAX computes in float32:
    the probabilities stay in [0, 1] and finite, but agree with NumPy to about 1e-5 only.

    Parameters
    ----------
    scene : SceneArrays or targetacq.core.CompiledScenario
        A compiled scenario's ``scene``, or the compiled scenario itself. A scenario with a
        terrain map raises ``ValueError``: the terrain's SCR is looked up per position on the
        host (:func:`targetacq.core.evaluation.footprint_scr`), with NumPy only.

    Returns
    -------
    SceneArrays
    """
    import jax
    import jax.numpy as jnp

    register_pytrees()
    if not isinstance(scene, SceneArrays):
        if getattr(scene, "terrain", None) is not None:
            raise ValueError(
                "a scenario with a terrain map (background.terrain) is evaluated with NumPy "
                "only: its clutter is looked up in the map per position on the host; use the "
                "NumPy core (ModelChain) for it, or give the SCR (background.scr or clutter_std)"
            )
        scene = getattr(scene, "scene", scene)
    if not isinstance(scene, SceneArrays):
        raise TypeError(f"as_jax takes a SceneArrays or a CompiledScenario, got {type(scene)!r}")
    # Concrete arrays even when called while a function is traced (the first call of a jitted
    # function that makes the scene then): a scene kept for later calls must hold no tracer.
    with jax.ensure_compile_time_eval():
        return to_namespace(scene, jnp)
