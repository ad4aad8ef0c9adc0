"""The orchestration object: a scenario evaluated for all sensors × targets × times at once.

:class:`ModelChain` compiles the scenario once into the array core's records
(:func:`targetacq.core.compile_scenario`) and runs named, swappable steps over them, like
pvlib's ``ModelChain``; it holds no physics of its own (every formula is in a topic module, wired
by :mod:`targetacq.core.evaluation`). The steps, in order:

``positions``
    where the sensors and targets are at the times, and the targets' headings
    (:func:`targetacq.core.scenario_positions`);
``factors``
    line of sight, range, critical dimension, cycles, field of view, the path's optical depth,
    transmittance and SNR, and the SCR (:func:`targetacq.core.factors`); with a ``[terrain]``
    elevation model each pair's visible fraction over the relief at each time, a target the
    terrain hides out of view (:func:`targetacq.core.terrain_view.terrain_view`, as the step
    API);
``clutter``
    the SCR of a terrain map at each sensor's footprint, where the scenario has one
    (:func:`targetacq.core.evaluation.footprint_scr`);
``probabilities``
    ordered probabilities of detection, recognition and identification, and their sensor-level
    fusion (:func:`targetacq.core.probabilities`).

Replace a step by name: ``ModelChain(scenario, steps={"clutter": my_clutter})``, where
``my_clutter(chain, scene, factors, target_positions, targets)`` returns the factors to use
(``scene`` holds the chosen ``targets`` only).

:meth:`ModelChain.evaluate_chunks` yields the results chunk by chunk (targets × times), so a run
over 10⁸ triples or more stays in bounded memory.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from targetacq import core
from targetacq.base import arrays as _arrays
from targetacq.base.limits import BYTES_PER_EVALUATION, check_size
from targetacq.base.registry import lookup
from targetacq.core import engines, ttp_rows
from targetacq.core.cases import RangeCase
from targetacq.core.evaluation import footprint_scr
from targetacq.core.terrain_view import hide, terrain_view
from targetacq.io.datasets import OUTPUT_FORMATS, Output, annotate, provenance, write_output
from targetacq.physics.named_atmospheres import TabulatedPath
from targetacq.scenario.schema import Scenario
from targetacq.sensors import get_sensor_type

__all__ = ["OUTPUT_FORMATS", "STEPS", "ModelChain", "Results", "evaluate"]

_TASKS = ("detection", "recognition", "identification")


@dataclass(frozen=True)
class Results:
    """Evaluation results.

    Attributes
    ----------
    dataset : xarray.Dataset
        Dims ``(sensor, target, time)`` for the per-sensor variables (range [m],
        critical_dimension [m], cycles, in_view, transmittance, snr [dB], detection,
        recognition, identification); ``(sensor, target)`` for contrast and scr;
        ``(target, time)`` for the fused probabilities ``fused_<task>``. Every variable and
        coordinate has CF ``units`` (but the text names) and ``long_name``; ``attrs`` hold the
        provenance (:func:`targetacq.io.datasets.provenance`): package version, model choices and
        ``scenario_sha256``, the SHA-256 of the scenario as validated (its canonical JSON).
    """

    dataset: Any

    def to_dataframe(self) -> Any:
        """One row per sensor–target–time, with the pair's contrast and SCR and the target's
        fused probabilities at that time."""
        ds = self.dataset
        per_triple = [
            name for name in ds.data_vars if ds[name].dims == ("sensor", "target", "time")
        ]
        frame = ds[per_triple].to_dataframe().reset_index()
        pairs = ds[[n for n in ds.data_vars if ds[n].dims == ("sensor", "target")]]
        pairs = pairs.to_dataframe().reset_index()
        fused = ds[[f"fused_{t}" for t in _TASKS]].to_dataframe().reset_index()
        return frame.merge(pairs, on=["sensor", "target"]).merge(fused, on=["target", "time"])

    def write(self, path: str | Path, meta: Mapping[str, Any] | None = None) -> Path:
        """Write the results by suffix (:data:`targetacq.io.datasets.OUTPUT_FORMATS`): the
        dataset as netCDF (.nc) or Zarr (.zarr), or the table of :meth:`to_dataframe` as CSV,
        JSON (``{"meta": ..., "rows": [...]}``) or Parquet; atomically, so a failed write leaves
        nothing half-written, with the user's umask.

        Units, long names and provenance (the dataset's ``attrs``, updated with ``meta``) go in
        every format; in CSV as ``#`` lines before the table
        (:func:`targetacq.io.datasets.csv_head`). JSON is strict: NaN is ``null``, ±inf
        the strings ``"inf"`` and ``"-inf"`` (:func:`targetacq.io.files.json_records`).

        Raises
        ------
        ValueError
            If the suffix is not one of .csv, .json, .parquet, .nc or .zarr, or
            (``OutputError``) the file cannot be written: the message names the file and the
            reason.
        """
        output = Output(
            self.dataset, {**self.dataset.attrs, **(meta or {})}, table=self.to_dataframe
        )
        return write_output(output, path)


def _positions(
    chain: ModelChain, times: np.ndarray, targets: slice
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return core.scenario_positions(chain.scenario, times, targets)


def _factors(
    chain: ModelChain,
    scene: core.SceneArrays,
    positions: tuple[np.ndarray, np.ndarray, np.ndarray],
) -> core.Factors:
    sensor_pos, target_pos, heading = positions
    elevation = chain.compiled.elevation
    if elevation is None:
        return chain.bound(scene).factors(sensor_pos, target_pos, heading)
    # Lines of sight over the [terrain] relief: every (sensor, target, time) in one call.
    view = terrain_view(
        elevation,
        chain.compiled.earth_radius_factor,
        sensor_pos,
        target_pos,
        np.asarray(scene.targets.dimensions, dtype=float)[:, 2],
        scene.targets.visible_fraction,
    )
    found = chain.bound(scene).factors(
        sensor_pos, target_pos, heading, visible_fraction=view.visible_fraction
    )
    return hide(found, view.hidden)


def _clutter(
    chain: ModelChain,
    scene: core.SceneArrays,
    found: core.Factors,
    target_positions: np.ndarray,
    targets: slice,
) -> core.Factors:
    terrain = chain.compiled.terrain
    if terrain is None:
        return found
    scr = footprint_scr(
        dataclasses.replace(terrain, window=terrain.window[targets]),
        found.range,
        target_positions,
        scene.signature.target,
        np.asarray(scene.sensors.ifov),
    )
    return dataclasses.replace(found, scr=scr)


def _probabilities(
    chain: ModelChain, scene: core.SceneArrays, found: core.Factors
) -> core.Probabilities:
    return chain.bound(scene).probabilities(found)


STEPS: Mapping[str, Callable[..., Any]] = {
    "positions": _positions,
    "factors": _factors,
    "clutter": _clutter,
    "probabilities": _probabilities,
}
"""The default steps of :class:`ModelChain`, in order (see the module docstring)."""


def _subset(scene: core.SceneArrays, targets: slice) -> core.SceneArrays:
    """The scene restricted to a slice of the targets."""
    t, sig = scene.targets, scene.signature
    return dataclasses.replace(
        scene,
        targets=core.TargetArrays(
            dimensions=t.dimensions[targets],
            visible_fraction=t.visible_fraction[targets],
            heading=t.heading[targets],
            n50=t.n50[targets],
            names=t.names[targets],
            hot_spot=t.hot_spot[targets],
            moving=t.moving[targets],
            foliage=None if t.foliage is None else t.foliage[targets],
            hot_spot_ratio=None if t.hot_spot_ratio is None else t.hot_spot_ratio[targets],
            hot_spot_size=None if t.hot_spot_size is None else t.hot_spot_size[targets],
            graded_motion=t.graded_motion[targets],
        ),
        signature=dataclasses.replace(
            sig,
            contrast=sig.contrast[:, targets],
            target=sig.target[:, targets],
            scr=None if sig.scr is None else sig.scr[:, targets],
        ),
    )


class ModelChain:
    """A scenario compiled for evaluation, with named, swappable steps.

    Parameters
    ----------
    scenario : Scenario
        A validated scenario (:func:`targetacq.scenario.schema.load_scenario`).
    steps : mapping of str to callable, optional
        Steps to replace, by name (:data:`STEPS`).
    engine : str
        The compute engine of the ``factors`` and ``probabilities`` steps
        (:data:`targetacq.core.engines.ENGINES`: ``numpy``, the default and reference, ``numba``,
        ``jax`` or ``auto``); the results are the same to about 1e-15 relative (JAX: 1e-12).

    Raises
    ------
    ValueError
        An unknown step or engine, an engine not installed, or one that cannot evaluate the
        scenario's model choices.

    Examples
    --------
    >>> from targetacq.scenario.schema import load_scenario
    >>> chain = ModelChain(load_scenario("examples/uav_haze.toml"), engine="numpy")
    >>> chain.engine.name
    'numpy'
    """

    def __init__(
        self,
        scenario: Scenario,
        steps: Mapping[str, Callable[..., Any]] | None = None,
        engine: str = "numpy",
    ) -> None:
        if not isinstance(scenario, Scenario):
            raise TypeError(
                f"scenario must be a Scenario (read a file with targetacq.load_scenario); got "
                f"{type(scenario).__name__}"
            )
        self.scenario = scenario
        self.steps = dict(STEPS)
        for name, step in (steps or {}).items():
            lookup(STEPS, name, "step")
            self.steps[name] = step
        self.engine = engines.get_engine(engine)
        self.compiled = core.compile_scenario(scenario)
        scene = self.compiled.scene
        self._bound: tuple[core.SceneArrays, engines.BoundEngine] = (
            scene,
            self.engine.bind(scene),
        )
        self.sensor_names = list(scene.sensors.names)
        self.target_names = list(scene.targets.names)
        self.criteria = np.array(self.compiled.criteria, dtype=object)
        self.contrast = scene.signature.contrast
        self.scr = scene.signature.scr
        self._scr_per_position = self.compiled.terrain is not None or core.has_active(scene)

    def bound(self, scene: core.SceneArrays) -> engines.BoundEngine:
        """The chain's engine bound to ``scene`` (the whole scene, or a chunk's targets); the
        last one is kept, so the steps of one chunk bind once."""
        kept = self._bound
        if kept[0] is not scene:
            kept = (scene, self.engine.bind(scene))
            self._bound = kept
        return kept[1]

    def _times(self, times: Any) -> np.ndarray:
        """The evaluation times [s]: the scenario's grid, or the caller's as a 1-d float array.

        Real numbers only (text, complex numbers and dates are refused by name); a NaN time
        gives NaN results at that time, an infinite one is an error.
        """
        if times is None:
            return np.asarray(self.scenario.time.times())
        _, (t,) = _arrays.arrays(times, names=("times",))
        t = np.atleast_1d(np.asarray(t, dtype=float))
        if t.ndim != 1:
            raise ValueError(f"times must be a 1-d array of seconds; got shape {t.shape}")
        _arrays.require_finite("times", t, np, "s")
        return t

    def compute(self, times: Any, targets: slice | None = None) -> dict[str, np.ndarray]:
        """All variables for every sensor, the chosen targets and the times, as arrays."""
        t = self._times(times)
        chosen = slice(None) if targets is None else targets
        scene = self.compiled.scene
        if targets is not None:
            scene = _subset(scene, targets)
        positions = self.steps["positions"](self, t, chosen)
        found = self.steps["factors"](self, scene, positions)
        if any(scene.targets.graded_motion):  # graded motion: the scripted paths' velocities
            found = dataclasses.replace(
                found,
                crossing_speed=core.crossing_speeds(
                    positions[0], positions[1], core.scenario_velocities(self.scenario, t, chosen)
                ),
            )
        found = self.steps["clutter"](self, scene, found, positions[1], chosen)
        p = self.steps["probabilities"](self, scene, found)
        out = {
            # The SCR per position: a terrain map's, or a radar's (its cell grows with range).
            **({"scr": found.scr} if self._scr_per_position else {}),
            "range": found.range,
            "critical_dimension": found.critical_dimension,
            "cycles": found.cycles,
            "in_view": found.in_view,
            "transmittance": found.transmittance,
            "snr": found.snr,
        }
        for task in _TASKS:
            out[task] = getattr(p, task)
        for task in _TASKS:
            out[f"fused_{task}"] = getattr(p, f"fused_{task}")
        return out

    # -- results -------------------------------------------------------------------------------

    def _dataset(self, arrays: dict[str, np.ndarray], times: np.ndarray, targets: slice) -> Any:
        import xarray as xr

        names = self.target_names[targets]
        coords = {"sensor": self.sensor_names, "target": names, "time": times}
        variables: dict[str, Any] = {}
        for name, value in arrays.items():
            if name.startswith("fused_"):
                variables[name] = (("target", "time"), value)
            else:
                variables[name] = (("sensor", "target", "time"), value)
        variables["contrast"] = (("sensor", "target"), self.contrast[:, targets])
        if "scr" not in arrays:
            scr = np.full(self.contrast.shape, np.inf) if self.scr is None else self.scr
            variables["scr"] = (("sensor", "target"), scr[:, targets])
        ds = xr.Dataset(variables, coords=coords)
        annotate(ds, kind="model")
        ds.attrs.update(self.provenance())
        return ds

    def provenance(self) -> dict[str, Any]:
        """The provenance of this chain's results: version, model choices (the steps replaced
        too) and the SHA-256 of the scenario's canonical JSON."""
        import hashlib

        choices = dataclasses.asdict(self.compiled.scene.choices)
        choices["criteria"] = dict(
            zip(self.target_names, (c.name for c in self.compiled.criteria), strict=True)
        )
        choices["engine"] = self._bound[1].engine
        choices["steps_replaced"] = sorted(n for n, f in self.steps.items() if f is not STEPS[n])
        meta = provenance(choices, what=f"targetacq evaluate: {self.scenario.name or 'scenario'}")
        text = self.scenario.model_dump_json()
        meta["scenario_sha256"] = hashlib.sha256(text.encode()).hexdigest()
        return meta

    def range_cases(self, time: float | None = None) -> dict[str, RangeCase]:
        """Every sensor–target pair as a :class:`targetacq.core.cases.RangeCase`, for
        :func:`targetacq.core.ranges.range_performance`, built from the compiled scenario.

        The critical dimension is the target's outline seen from the sensor at ``time``
        (default: the scenario's start); the resolution is the sensor type's cycle and IFOV; the
        path is the base extinction of each sensor's band where the scenario has an atmosphere
        (segments and local clouds depend on where the target stands, so they are left out of
        range curves); the clutter (SCR or region), criterion, transform, noise model, motion
        rule and semantics are the scenario's, and so is a sensor's own noise (its
        noise-equivalent exitance against the pair's exitance contrast), with the pixels on
        target counted over the critical dimension squared (the fewest a target of that critical
        dimension covers: the range curves do not follow the outline's other side). A sensor
        with an MRTD curve gives MRTD-limited cases: its curve, with the contrast and the NETD
        as temperature differences (over the band's ``∂M_bb/∂T`` at ``netd_temperature``, as
        the core has them: :mod:`targetacq.core.mrtd_rows`). Under the ``ttp`` resolution model
        the thermal sensors give TTP cases: their system, the contrast as a ΔT, the outline's
        area at ``time`` and no separate SNR (as the core has them:
        :mod:`targetacq.core.ttp_rows`). A target's graded hot spot, its speed across each line
        of sight at ``time`` (graded motion) and the background's sky-to-ground ratio (TV and
        colour rows with their own noise) are the cases' too. Imaging
        sensors only. A scenario's ranges in ``targetacq dri`` and its report (command
        line and web) do not use these cases: they come from the core for every sensor type
        (:func:`targetacq.core.pair_ranges.pair_performance`), with the outline seen from each
        range and the path where the target would stand.

        Examples
        --------
        >>> from targetacq.scenario.schema import load_scenario
        >>> chain = ModelChain(load_scenario("examples/two_sensors_fused.toml"))
        >>> sorted(chain.range_cases())[0]
        'thermal → soldier'
        """
        t = self.scenario.time.start if time is None else float(time)
        seen = self.compute([t])["critical_dimension"][..., 0]
        scene = self.compiled.scene
        sensors, targets, choices = scene.sensors, scene.targets, scene.choices
        noise: list[list[dict[str, Any]]] = [
            [
                {
                    "contrast": float(scene.signature.contrast[s, g]),
                    "noise_equivalent_contrast": float(sensors.noise_equivalent[s]),
                    **(
                        {"path_contrast": float(sensors.path_contrast[s])}
                        if sensors.path_contrast is not None and sensors.path_contrast[s] > 0
                        else {}
                    ),
                }
                if sensors.noise_equivalent[s] > 0
                else {}
                for g in range(len(targets.names))
            ]
            for s in range(len(sensors.names))
        ]
        signature = scene.signature
        rows = signature.rows_with_clutter(len(sensors.names), signature.scr is not None)
        clutter = [signature.scr[s] if given else None for s, given in enumerate(rows)]
        limited = sensors.mrtd
        if limited is not None:  # MRTD-limited rows: the curve, with the contrast as a ΔT [K]
            for k, s in enumerate(limited.rows):
                slope = float(limited.exitance_slope[k])
                netd = float(sensors.noise_equivalent[s]) / slope
                noise[s] = [
                    {
                        "contrast": float(scene.signature.contrast[s, g]) / slope,
                        "mrtd": limited.curves[k],
                        # The default: the curve holds the noise, no SNR on top (as the core).
                        "noise_model": choices.noise_model if choices.snr_on_mrtd else None,
                        **({"noise_equivalent_contrast": netd} if netd > 0 else {}),
                    }
                    for g in range(len(targets.names))
                ]
        if sensors.ttp is not None:  # TTP rows: the system, the contrast as a ΔT, the area
            s_pos, t_pos, headings = core.scenario_positions(self.scenario, [t])
            area = ttp_rows.outline_area(scene, s_pos, t_pos, headings)[..., 0]
            for k, s in enumerate(sensors.ttp.rows):
                slope = float(sensors.ttp.exitance_slope[k])
                noise[s] = [
                    {
                        "contrast": float(scene.signature.contrast[s, g]) / slope,
                        "ttp": sensors.ttp.systems[k],
                        "target_area": float(area[s, g]),
                        "noise_model": "none",  # the NETD and τ are in the metric (as the core)
                    }
                    for g in range(len(targets.names))
                ]
        graded = self._graded_cases(t)
        cases: dict[str, RangeCase] = {}
        for s, sensor in enumerate(sensors.names):
            if get_sensor_type(sensors.types[s]).kind != "imaging":
                continue  # radars, laser radars: targetacq.core.pair_ranges
            row_clutter = clutter[s]
            for g, target in enumerate(targets.names):
                cases[f"{sensor} → {target}"] = RangeCase(
                    float(seen[s, g]),
                    float(sensors.ifov[s]),
                    cycle=None
                    if "mrtd" in noise[s][g] or "ttp" in noise[s][g]
                    else float(sensors.cycle[s]),
                    criterion=self.compiled.criteria[g],
                    transform=choices.transform,
                    options=dict(choices.options),
                    extinction=float(sensors.extinction[s])
                    if scene.path.attenuates and scene.path.named_depths is None
                    else None,
                    path=None
                    if scene.path.named_depths is None
                    else TabulatedPath(
                        scene.path.named_ranges,
                        tuple(float(v) for v in scene.path.named_depths[s]),
                    ),
                    foliage=None if targets.foliage is None else float(targets.foliage[g]),
                    scr=None if row_clutter is None else float(row_clutter[g]),
                    region=choices.region,
                    hot_spot=targets.hot_spot[g],
                    moving=targets.moving[g],
                    **(
                        {}
                        if "noise_model" in noise[s][g] or "mrtd" in noise[s][g]
                        else {"noise_model": choices.noise_model}
                    ),
                    motion=choices.motion,
                    semantics=choices.semantics,
                    # σ_path unknown: the core forms the SNR by the thesis's law too.
                    snr_law=choices.snr_law if sensors.path_contrast is not None else "sonesson",
                    **noise[s][g],
                    **graded[s][g],
                )
        return cases

    def _graded_cases(self, time: float) -> list[list[dict[str, Any]]]:
        """Each pair's graded cues as :class:`RangeCase` fields: a target's hot spot, its speed
        across the sensor's line of sight at ``time`` (graded motion) and the background's
        sky-to-ground ratio for a TV or colour row with its own noise."""
        scene = self.compiled.scene
        n_s, n_g = scene.shape
        out: list[list[dict[str, Any]]] = [[{} for _ in range(n_g)] for _ in range(n_s)]
        crossing = None
        if any(scene.targets.graded_motion):
            s_pos, t_pos, _ = core.scenario_positions(self.scenario, [time])
            velocities = core.scenario_velocities(self.scenario, [time])
            crossing = np.asarray(core.crossing_speeds(s_pos, t_pos, velocities))[..., 0]
        k = scene.sensors.sky_to_ground
        for g, target in enumerate(self.scenario.targets):
            for s in range(n_s):
                given = out[s][g]
                if target.hot_spot_ratio is not None:
                    given["hot_spot_ratio"] = target.hot_spot_ratio
                    given["hot_spot_size"] = target.hot_spot_size
                if crossing is not None and target.graded_motion:
                    given["target_speed"] = float(crossing[s, g])
                airlight = get_sensor_type(scene.sensors.types[s]).airlight
                if k is not None and airlight and scene.sensors.noise_equivalent[s] > 0:
                    given["sky_to_ground"] = float(k[s])
        return out

    def evaluate(self, times: Any = None) -> Results:
        """Evaluate every sensor × target × time (default: the scenario's time grid), held in
        memory.

        Raises
        ------
        ValueError
            If the run would not fit in memory: evaluate it chunk by chunk instead
            (:meth:`evaluate_chunks`, :func:`targetacq.run.streaming.write_chunks`).
        """
        t = self._times(times)
        n_s, n_g = len(self.sensor_names), len(self.target_names)
        check_size(
            t.size * n_s * n_g,
            BYTES_PER_EVALUATION,
            f"evaluating {t.size} times x {n_s} sensor(s) x {n_g} target(s) in memory",
            "evaluate chunk by chunk: ModelChain.evaluate_chunks, "
            "targetacq.run.streaming.write_chunks, or targetacq evaluate --out FILE",
        )
        whole = slice(None)
        return Results(self._dataset(self.compute(t, whole), t, whole))

    def evaluate_chunks(
        self, times: Any = None, targets_per_chunk: int = 256, times_per_chunk: int = 64
    ) -> Iterator[tuple[slice, np.ndarray, dict[str, np.ndarray]]]:
        """Evaluate in chunks of targets × times, for runs too large to hold at once.

        Yields
        ------
        targets, times, arrays
            The target slice, the chunk's times and the arrays of :meth:`compute`.
        """
        if targets_per_chunk < 1 or times_per_chunk < 1:
            raise ValueError("chunk sizes must be >= 1")
        t = self._times(times)
        for start in range(0, len(self.target_names), targets_per_chunk):
            chosen = slice(start, min(start + targets_per_chunk, len(self.target_names)))
            for first in range(0, t.size, times_per_chunk):
                part = t[first : first + times_per_chunk]
                yield chosen, part, self.compute(part, chosen)


def evaluate(scenario: Scenario, times: Any = None) -> Results:
    """Evaluate a scenario (:class:`ModelChain` in one call)."""
    return ModelChain(scenario).evaluate(times)
