"""The orchestration object: a scenario evaluated for all sensors × targets × times at once.

:class:`ModelChain` wires the topic modules together, like pvlib's ``ModelChain``; it holds no
physics of its own (DESIGN.md §2). For each sensor–target–time triple:

1. geometry: positions on their paths, line of sight, slant range, aspect and depression
   (:mod:`targetacq.geometry`); the critical dimension is the smaller side of the target box as
   seen, the vertical side shrunk by the visible fraction (a partly hidden target, §3.10);
   a target outside the sensor's field of view has probability 0;
2. optics: cycles on target ``N = d / (R · cycle)`` (:mod:`targetacq.optics`);
3. radiometry and clutter: the contrast and SCR of each sensor–target pair
   (:mod:`targetacq.radiometry`, :mod:`targetacq.clutter`);
4. atmosphere: optical depth of the path (segments, local clouds), transmittance, SNR
   (:mod:`targetacq.atmosphere`);
5. transforms: ordered probabilities of detection, recognition and identification
   (:func:`targetacq.acquisition_probabilities`), then sensor-level fusion over the sensors (8.4).

:meth:`ModelChain.evaluate_chunks` yields the results chunk by chunk (targets × times), so a run
over 10⁸ triples or more stays in bounded memory.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from targetacq import atmosphere, geometry, optics, radiometry
from targetacq.acquisition import acquisition_probabilities
from targetacq.clutter import signal_to_clutter_ratio
from targetacq.criteria import get_criterion
from targetacq.fusion import fuse
from targetacq.outputs import output_path, write_atomically
from targetacq.scenario import Scenario

__all__ = ["ModelChain", "Results", "evaluate"]

_TASKS = ("detection", "recognition", "identification")
OUTPUT_FORMATS = ("csv", "json", "parquet")


@dataclass(frozen=True)
class Results:
    """Evaluation results.

    Attributes
    ----------
    dataset : xarray.Dataset
        Dims ``(sensor, target, time)`` for the per-sensor variables (range [m],
        critical_dimension [m], cycles, in_view, transmittance, snr [dB], detection,
        recognition, identification); ``(sensor, target)`` for contrast and scr;
        ``(target, time)`` for the fused probabilities ``fused_<task>``.
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

    def write(self, path: str | Path) -> Path:
        """Write the table as CSV, JSON (records) or Parquet, by suffix; atomically, so a failed
        write leaves nothing half-written."""
        out, kind = output_path(path, OUTPUT_FORMATS, "output")
        frame = self.to_dataframe()
        writers = {
            "csv": lambda p: frame.to_csv(p, index=False),
            "json": lambda p: frame.to_json(p, orient="records", indent=1, double_precision=15),
            "parquet": lambda p: frame.to_parquet(p, index=False),
        }
        return write_atomically(out, writers[kind])


def _waypoints(item: Any) -> tuple[list[float], list[tuple[float, float, float]]]:
    return [w.time for w in item.waypoints], [w.position for w in item.waypoints]


def _path_arrays(items: list[Any], times: np.ndarray) -> np.ndarray:
    """(n, n_t, 3) positions of sensors or targets at the times."""
    out = np.empty((len(items), times.size, 3))
    for k, item in enumerate(items):
        if item.waypoints is None:
            out[k] = np.asarray(item.position)
        else:
            out[k] = geometry.positions_at(times, *_waypoints(item))
    return out


class ModelChain:
    """A scenario prepared for evaluation.

    Parameters
    ----------
    scenario : Scenario
        A validated scenario (:func:`targetacq.scenario.load_scenario`).
    """

    def __init__(self, scenario: Scenario) -> None:
        self.scenario = scenario
        sensors, targets = scenario.sensors, scenario.targets
        self.sensor_names = [s.name for s in sensors]
        self.target_names = [t.name for t in targets]
        self.cycle = np.array(
            [
                float(
                    optics.resolvable_cycle_angle(
                        s.pixel_ifov,
                        wavelength=sum(s.limits) / 2 if s.aperture is not None else None,
                        aperture=s.aperture,
                    )
                )
                for s in sensors
            ]
        )
        self.ifov = np.array([s.pixel_ifov for s in sensors])
        self.contrast, self.scr = self._contrast_and_scr()
        self._terrain_data = self._terrain()
        self.extinction = np.array([self._extinction(s) for s in sensors])
        segments = scenario.atmosphere.segments
        self.segment_lengths = np.array([seg.length for seg in segments])
        self.segment_extinction = np.array(
            [[self._segment_extinction(seg, s) for seg in segments] for s in sensors]
        ).reshape(len(sensors), len(segments))
        model = scenario.model
        self.criteria = [
            get_criterion(
                t.criterion
                if t.criterion is not None
                else (
                    dict(zip(_TASKS, model.n50, strict=True))
                    if model.n50 is not None
                    else model.criterion
                )
            )
            for t in targets
        ]
        self.options = {} if model.bound is None else {"bound": model.bound}

    # -- per pair ------------------------------------------------------------------------------

    def _emissivity(self, thing: Any, band: tuple[float, float]) -> float:
        if thing.emissivity is not None:
            return float(thing.emissivity)
        if thing.material is not None:
            return radiometry.material_emissivity(thing.material, band)
        return 1.0

    def _contrast_and_scr(self) -> tuple[np.ndarray, np.ndarray | None]:
        sc = self.scenario
        bg = sc.background
        contrast = np.empty((len(sc.sensors), len(sc.targets)))
        target_exitance = np.empty_like(contrast)
        self.target_exitance = target_exitance
        clutter = np.full(contrast.shape, np.nan)
        for i, s in enumerate(sc.sensors):
            band = s.limits
            if s.type == "tv":
                assert bg.irradiance is not None
                assert bg.reflectance is not None
                m_b = bg.reflectance * bg.irradiance
                m_t = np.array([t.reflectance for t in sc.targets], dtype=float) * bg.irradiance
            else:
                eps_b = self._emissivity(bg, band)
                m_b = eps_b * float(radiometry.band_exitance(bg.temperature, band))
                eps_t = np.array([self._emissivity(t, band) for t in sc.targets])
                temperatures = np.array([t.temperature for t in sc.targets], dtype=float)
                m_t = eps_t * np.asarray(radiometry.band_exitance(temperatures, band))
                if bg.clutter_std is not None:
                    slope = float(radiometry.band_exitance_derivative(bg.temperature, band))
                    clutter[i] = eps_b * slope * bg.clutter_std
            contrast[i] = np.abs(m_t - m_b)
            target_exitance[i] = m_t
        if bg.scr is not None:
            return contrast, np.full(contrast.shape, bg.scr)
        if bg.image is not None:
            return contrast, np.broadcast_to(self._image_scr(), contrast.shape).copy()
        if bg.clutter_std is not None:
            return contrast, np.asarray(signal_to_clutter_ratio(contrast, 0.0, clutter))
        return contrast, None

    def _image_scr(self) -> np.ndarray:
        """SCR of each target measured in the background image (Eqs. (3.12)–(3.15))."""
        from targetacq.clutter import gray, image_clutter
        from targetacq.images import read_image

        bg = self.scenario.background
        assert bg.image is not None
        pixels = gray(read_image(bg.image), bg.channel)
        boxes = [t.image_box for t in self.scenario.targets]
        return np.asarray(image_clutter(pixels, boxes).scr)

    def _terrain(self) -> tuple[Any, np.ndarray, np.ndarray, np.ndarray] | None:
        """The terrain map and, per sensor and class, intensity, variance and resolution."""
        from targetacq.terrain import TerrainClass, TerrainMap

        bg = self.scenario.background
        if bg.terrain is None:
            return None
        spec = bg.terrain
        try:
            grid = np.loadtxt(spec.map, delimiter=",", dtype=np.int64, ndmin=2)
        except (OSError, ValueError) as error:
            raise ValueError(f"background.terrain.map: cannot read {spec.map!r}: {error}") from None
        classes = [TerrainClass(c.name, 0.0, 0.0, c.resolution) for c in spec.classes]
        terrain = TerrainMap(classes, grid, spec.cell_size, spec.origin)
        intensity = np.empty((len(self.sensor_names), len(spec.classes)))
        variance = np.empty_like(intensity)
        for s, sensor in enumerate(self.scenario.sensors):
            eps = self._emissivity(bg, sensor.limits)
            temps = np.array([c.temperature for c in spec.classes])
            spread = np.array([c.temperature_std for c in spec.classes])
            intensity[s] = eps * np.asarray(radiometry.band_exitance(temps, sensor.limits))
            slope = np.asarray(radiometry.band_exitance_derivative(temps, sensor.limits))
            variance[s] = (eps * slope * spread) ** 2
        resolution = np.array([c.resolution for c in spec.classes])
        return terrain, intensity, variance, resolution

    def _terrain_scr(
        self, rng: np.ndarray, target_pos: np.ndarray, targets: slice, m_target: np.ndarray
    ) -> np.ndarray:
        """(n_s, n_g, n_t) SCR from the terrain map at the sensors' footprints (6.10), (6.9)."""
        from targetacq.terrain import resolution_variance

        assert self._terrain_data is not None
        terrain, intensity, variance, resolution = self._terrain_data
        items = self.scenario.targets[targets]
        # Window: the 3 x 3 cells of twice the target's minimum dimension (Fig. 3.6).
        window = np.array([6.0 * min(t.dimensions) for t in items]).reshape(-1, 1)
        k = terrain.weights(target_pos[..., 0], target_pos[..., 1], window)  # (n_g, n_t, K)
        footprint = rng * self.ifov.reshape(-1, 1, 1)  # (n_s, n_g, n_t)
        seen = resolution_variance(
            variance[:, None, None, :], resolution, footprint[..., None]
        )  # (n_s, n_g, n_t, K)
        clutter = np.sqrt(np.sum(k[None] * seen, axis=-1))
        mean = np.sum(k[None] * intensity[:, None, None, :], axis=-1)
        return np.asarray(signal_to_clutter_ratio(m_target[..., None], mean, clutter))

    def _extinction(self, sensor: Any) -> float:
        atm = self.scenario.atmosphere
        if atm.extinction is not None:
            return atm.extinction
        if atm.obscurant is not None:
            name, _, level = atm.obscurant.partition(":")
            return atmosphere.obscurant_extinction(name, sensor.limits, level or "nominal")
        if atm.visibility is not None:
            return float(
                atmosphere.extinction_from_visibility(atm.visibility, atm.visibility_convention)
            )
        return 0.0

    def _segment_extinction(self, segment: Any, sensor: Any) -> float:
        if segment.extinction is not None:
            return float(segment.extinction)
        name, _, level = segment.obscurant.partition(":")
        return atmosphere.obscurant_extinction(name, sensor.limits, level or "nominal")

    # -- per triple ----------------------------------------------------------------------------

    def _positions(self, times: np.ndarray, targets: slice) -> tuple[np.ndarray, ...]:
        sc = self.scenario
        sensor_pos = _path_arrays(sc.sensors, times)
        chosen = sc.targets[targets]
        target_pos = _path_arrays(chosen, times)
        heading = np.empty((len(chosen), times.size))
        for k, t in enumerate(chosen):
            if t.waypoints is None:
                heading[k] = t.heading
            else:
                heading[k] = geometry.heading_along(times, *_waypoints(t), t.heading)
        return sensor_pos, target_pos, heading

    def _in_view(self, los: np.ndarray, sensor_pos: np.ndarray) -> np.ndarray:
        """(n_s, n_g, n_t) field-of-view test, all pointed sensors at once."""
        forward = self._forward(sensor_pos)
        pointed = [k for k, f in enumerate(forward) if f is not None]
        in_view = np.ones(los.shape[:-1], dtype=bool)
        if pointed:
            directions = np.stack([f for f in forward if f is not None])[:, None]  # (p, 1, n_t, 3)
            fov = np.array([self.scenario.sensors[k].field_of_view for k in pointed])
            halves = np.tan(fov / 2.0).reshape(len(pointed), 2, 1, 1)
            in_view[pointed] = geometry.in_field_of_view(
                los[pointed], directions, (halves[:, 0], halves[:, 1])
            )
        return in_view

    def _forward(self, sensor_pos: np.ndarray) -> list[np.ndarray | None]:
        out: list[np.ndarray | None] = []
        for k, s in enumerate(self.scenario.sensors):
            if s.look_at is not None:
                out.append(np.asarray(s.look_at) - sensor_pos[k])
            elif s.azimuth is not None and s.depression is not None:
                ce = math.cos(s.depression)
                direction = [
                    ce * math.sin(s.azimuth),
                    ce * math.cos(s.azimuth),
                    -math.sin(s.depression),
                ]
                out.append(np.broadcast_to(direction, sensor_pos[k].shape))
            else:
                out.append(None)
        return out

    def _optical_depth(
        self, rng: np.ndarray, sensor_pos: np.ndarray, target_pos: np.ndarray
    ) -> np.ndarray:
        n_s = len(self.sensor_names)
        gamma = self.extinction.reshape(n_s, 1, 1)
        depth = gamma * rng
        start = 0.0
        for j, length in enumerate(self.segment_lengths):
            inside = np.clip(rng - start, 0.0, length)
            depth = depth + (self.segment_extinction[:, j].reshape(n_s, 1, 1) - gamma) * inside
            start += length
        for cloud in self.scenario.atmosphere.clouds:
            chord = atmosphere.sphere_chord_length(
                sensor_pos[:, None], target_pos[None], cloud.center, cloud.radius
            )
            depth = depth + cloud.extinction * chord
        return depth

    def compute(self, times: Any, targets: slice | None = None) -> dict[str, np.ndarray]:
        """All variables for every sensor, the chosen targets and the times, as arrays."""
        sc = self.scenario
        t = np.atleast_1d(np.asarray(times, dtype=float))
        chosen = slice(None) if targets is None else targets
        sensor_pos, target_pos, heading = self._positions(t, chosen)
        # (n_s, n_g, n_t, 3), each component contiguous in memory (fast elementwise work).
        los = np.moveaxis(
            np.stack([target_pos[None, ..., k] - sensor_pos[:, None, :, k] for k in range(3)]),
            0,
            -1,
        )
        items = sc.targets[chosen]
        dims = np.array([t_.dimensions for t_ in items]).reshape(1, -1, 1, 3)
        rng, horizontal, vertical = geometry.box_extents_seen(
            los, heading[None], dims[..., 0], dims[..., 1], dims[..., 2]
        )
        visible = np.array([t_.visible_fraction for t_ in items]).reshape(1, -1, 1)
        critical = np.minimum(horizontal, vertical * visible)
        with np.errstate(divide="ignore"):
            cycles = critical / (np.maximum(rng, 1e-9) * self.cycle.reshape(-1, 1, 1))
        in_view = self._in_view(los, sensor_pos)
        depth = self._optical_depth(rng, sensor_pos, target_pos)
        tau = np.exp(-depth)
        snr = np.asarray(atmosphere.snr_from_optical_depth(depth))
        noise = snr if sc.atmosphere.present else None
        probabilities = {task: np.zeros(rng.shape) for task in _TASKS}
        bg = sc.background
        scr = None if self.scr is None else self.scr[:, chosen][..., None]
        if self._terrain_data is not None:
            scr = self._terrain_scr(rng, target_pos, chosen, self.target_exitance[:, chosen])
        groups: dict[tuple[Any, bool, bool], list[int]] = {}
        for g, (target, crit) in enumerate(zip(items, self.criteria[chosen], strict=True)):
            groups.setdefault((crit.name, target.hot_spot, target.moving), []).append(g)
        for (_, hot_spot, moving), members in groups.items():
            idx = np.array(members)
            acq = acquisition_probabilities(
                cycles[:, idx],
                self.criteria[chosen][members[0]],
                sc.model.transform,
                scr=None if scr is None else scr[:, idx],
                region=bg.clutter,
                hot_spot=hot_spot,
                moving=moving,
                snr=None if noise is None else noise[:, idx],
                noise_model=sc.model.noise_model,
                **self.options,
            )
            for task in _TASKS:
                probabilities[task][:, idx] = np.where(in_view[:, idx], getattr(acq, task), 0.0)
        out = {
            **({} if self._terrain_data is None else {"scr": scr}),
            "range": rng,
            "critical_dimension": critical,
            "cycles": cycles,
            "in_view": in_view,
            "transmittance": tau,
            "snr": snr,
            **probabilities,
        }
        for task in _TASKS:
            out[f"fused_{task}"] = np.asarray(fuse(probabilities[task], axis=0))
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
        units = {
            "range": "m",
            "critical_dimension": "m",
            "snr": "dB",
            "time": "s",
            "contrast": "W/m2",
            "cycles": "cycles",
        }
        for name, unit in units.items():
            ds[name].attrs["units"] = unit
        return ds

    def range_cases(self, time: float | None = None) -> dict[str, dict[str, Any]]:
        """Every sensor–target pair as a case of :func:`targetacq.ranges.range_performance`.

        The critical dimension is the target's outline seen from the sensor at ``time``
        (default: the scenario's start); the path is the base extinction of each sensor's band
        (segments and local clouds depend on where the target stands, so they are left out of
        range curves); the clutter, criterion and transform are the scenario's.
        """
        t = self.scenario.time.start if time is None else float(time)
        seen = self.compute([t])["critical_dimension"][..., 0]
        atm = self.scenario.atmosphere
        present = (
            atm.extinction is not None or atm.obscurant is not None or atm.visibility is not None
        )
        cases: dict[str, dict[str, Any]] = {}
        for s, sensor in enumerate(self.scenario.sensors):
            for g, target in enumerate(self.scenario.targets):
                case: dict[str, Any] = {
                    "critical_dimension": float(seen[s, g]),
                    "ifov": sensor.pixel_ifov,
                    "criterion": self.criteria[g],
                    "transform": self.scenario.model.transform,
                    "noise_model": self.scenario.model.noise_model,
                    "hot_spot": target.hot_spot,
                    "moving": target.moving,
                    "options": dict(self.options),
                }
                if present:
                    case["extinction"] = float(self.extinction[s])
                if sensor.aperture is not None:
                    case["aperture"] = sensor.aperture
                    case["wavelength"] = sum(sensor.limits) / 2
                if self.scr is not None:
                    case["scr"] = float(self.scr[s, g])
                elif self.scenario.background.clutter is not None:
                    case["region"] = self.scenario.background.clutter
                cases[f"{sensor.name} → {target.name}"] = case
        return cases

    def evaluate(self, times: Any = None) -> Results:
        """Evaluate every sensor × target × time (default: the scenario's time grid)."""
        t = self.scenario.time.times() if times is None else np.atleast_1d(np.asarray(times, float))
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
        t = self.scenario.time.times() if times is None else np.atleast_1d(np.asarray(times, float))
        for start in range(0, len(self.target_names), targets_per_chunk):
            chosen = slice(start, min(start + targets_per_chunk, len(self.target_names)))
            for first in range(0, t.size, times_per_chunk):
                part = t[first : first + times_per_chunk]
                yield chosen, part, self.compute(part, chosen)


def evaluate(scenario: Scenario, times: Any = None) -> Results:
    """Evaluate a scenario (:class:`ModelChain` in one call)."""
    return ModelChain(scenario).evaluate(times)
