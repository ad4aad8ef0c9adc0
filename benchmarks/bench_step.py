"""One step of the step API (:class:`targetacq.Simulation`): CPU time per step and per core
evaluation, this version against a previous one, in one run.

A scenario built in Python (thermal cameras pointed down at random azimuths over targets at
random places, haze, clutter from a temperature spread) is stepped at 10 Hz while the targets
drive. Each timed ``Simulation.step(time, dt, sensor_positions, target_positions)`` is followed
by the core alone on the same positions: the engine bound to the scene
(``targetacq.core.engines.bind``), ``factors`` then ``probabilities`` (the evaluation a step makes),
and, where the version has it, the bound engine's one-call ``step``. CPU time is
``time.process_time`` (one process, one thread: what the step costs the core it runs on), wall
time ``time.perf_counter``; each figure is the median over the steps of a run.

Sizes (sensors × targets, default 1×1, 1×6 — one camera, six targets — and 20×500) and
engines (default numpy and numba) are measured in runs (default 3); each run measures the
previous version (default ``dd51896``, the version before the one-call step) and then this
one, each engine in a process of its own, so both see the same machine load. The previous
version is checked out with ``git worktree add --detach`` into a temporary folder and imported
from there (``PYTHONPATH``); the measuring script is this one. One JSON line per engine and
size: the medians of the runs' medians, the previous version's, their ratio, and the spread
(minimum, median, maximum over the runs).

Usage::

    python benchmarks/bench_step.py [SIZE ...] [--engines numpy,numba] [--runs 3]
                                    [--previous REV | --no-previous]

``SIZE`` is ``NxM``, e.g. ``1x1 20x500``. ``--measure ENGINE SIZE ...`` is the worker: it
measures in this process and prints one JSON line per size.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from _timing import REPEATS
from targetacq import Simulation
from targetacq.core import engines
from targetacq.scenario.schema import Atmosphere, Background, Sensor, Target

HERE = Path(__file__).parent
ROOT = HERE.parent
SIZES = ((1, 1), (1, 6), (20, 500))
RATE = 10.0  # steps per second
PREVIOUS = "dd51896"
WARM_UP = 3  # steps not timed: the first compile (numba) and start the clock and the episodes


def build(
    n_sensors: int, n_targets: int, engine: str = "numpy"
) -> tuple[Simulation, np.ndarray, np.ndarray, np.ndarray]:
    """The simulation, sensor positions (n_s, 3), target positions (n_g, 3) and velocities."""
    rng = np.random.default_rng(1)
    sensors = [
        Sensor(
            name=f"s{i}",
            band="lwir",
            pixels=(640, 512),
            pitch=17e-6,
            focal_length=35e-3,
            position=(0.0, 0.0, 0.0),
            azimuth=float(az),
            depression=float(np.radians(30.0)),
        )
        for i, az in enumerate(rng.uniform(0.0, 2 * np.pi, n_sensors))
    ]
    targets = [
        Target(
            name=f"t{j}",
            dimensions=(7.0, 2.5, 3.0),
            temperature=float(temp),
            heading=float(h),
            position=(0.0, 0.0, 0.0),
        )
        for j, (temp, h) in enumerate(
            zip(rng.uniform(295, 315, n_targets), rng.uniform(0, 2 * np.pi, n_targets), strict=True)
        )
    ]
    sim = Simulation(
        sensors,
        targets,
        background=Background(temperature=293.0, clutter_std=2.0),
        atmosphere=Atmosphere(obscurant="haze"),
        seed=1,
        engine=engine,
    )
    sensor_pos = np.column_stack(
        [
            rng.uniform(-5e3, 5e3, n_sensors),
            rng.uniform(-5e3, 5e3, n_sensors),
            rng.uniform(1e3, 3e3, n_sensors),
        ]
    )
    # Each target on the ground near the boresight of one sensor (round robin), so that every
    # sensor has targets in view.
    which = np.arange(n_targets) % n_sensors
    azimuth = np.array([s.azimuth for s in sensors])[which]
    reach = sensor_pos[which, 2] / np.tan(np.radians(30.0))
    target_pos = np.column_stack(
        [
            sensor_pos[which, 0] + reach * np.sin(azimuth) + rng.uniform(-150, 150, n_targets),
            sensor_pos[which, 1] + reach * np.cos(azimuth) + rng.uniform(-150, 150, n_targets),
            np.zeros(n_targets),
        ]
    )
    velocity = np.column_stack(
        [rng.uniform(-15, 15, n_targets), rng.uniform(-15, 15, n_targets), np.zeros(n_targets)]
    )
    return sim, sensor_pos, target_pos, velocity


def _clocked(function: object, *args: object) -> tuple[float, float, object]:
    """CPU and wall time of one call [s], and its result."""
    wall, cpu = time.perf_counter(), time.process_time()
    out = function(*args)
    return time.process_time() - cpu, time.perf_counter() - wall, out


def measure(n_sensors: int, n_targets: int, engine: str) -> dict[str, object]:
    """Medians over the steps of one run, in this process's version of targetacq."""
    sim, sensor_pos, target_pos, velocity = build(n_sensors, n_targets, engine)
    pairs = n_sensors * n_targets
    steps = 60 if pairs > 1000 else 40 * REPEATS
    dt = 1.0 / RATE
    bound = engines.bind(sim.compiled.scene, engine)
    lean = getattr(bound, "step", None)  # the one-call step, where this version has it
    times: dict[str, list[float]] = {
        k: [] for k in ("step_cpu", "step_wall", "core_cpu", "core_wall", "lean_cpu")
    }
    events, in_view = 0, 0.0
    for k in range(steps + WARM_UP):
        t = k * dt
        positions = target_pos + velocity * t
        step_cpu, step_wall, out = _clocked(sim.step, t, dt, sensor_pos, positions)
        core_cpu, core_wall, _ = _clocked(
            lambda p=positions: bound.probabilities(bound.factors(sensor_pos, p))
        )
        lean_cpu = _clocked(lean, sensor_pos, positions)[0] if lean is not None else None
        if k < WARM_UP:
            continue
        times["step_cpu"].append(step_cpu)
        times["step_wall"].append(step_wall)
        times["core_cpu"].append(core_cpu)
        times["core_wall"].append(core_wall)
        if lean_cpu is not None:
            times["lean_cpu"].append(lean_cpu)
        events += len(out.events)
        in_view = float(np.mean(out.in_view))
    medians = {k: (statistics.median(v) if v else None) for k, v in times.items()}
    return {
        "engine": engine,
        "bound_engine": bound.engine,
        "sensors": n_sensors,
        "targets": n_targets,
        "steps_timed": steps,
        **medians,
        "events_per_step": events / steps,
        "in_view_fraction": in_view,
    }


def _worker(engine: str, sizes: list[tuple[int, int]]) -> None:
    for n_s, n_g in sizes:
        print(json.dumps(measure(n_s, n_g, engine)), flush=True)


def _run(src: Path, engine: str, sizes: list[tuple[int, int]]) -> list[dict[str, object]]:
    """The worker in a process of its own, importing targetacq from ``src``."""
    env = {**os.environ, "PYTHONPATH": str(src), "OMP_NUM_THREADS": "1"}
    args = [f"{n_s}x{n_g}" for n_s, n_g in sizes]
    done = subprocess.run(
        [sys.executable, str(Path(__file__).resolve()), "--measure", engine, *args],
        capture_output=True,
        text=True,
        env=env,
        check=False,
    )
    if done.returncode != 0:
        raise RuntimeError(f"the worker for {engine} at {src} failed:\n{done.stderr}")
    return [json.loads(line) for line in done.stdout.splitlines() if line.startswith("{")]


def _spread(values: list[float | None]) -> list[float] | None:
    known = [v for v in values if v is not None]
    if not known:
        return None
    return [min(known), statistics.median(known), max(known)]


def _median(values: list[float | None]) -> float | None:
    spread = _spread(values)
    return None if spread is None else spread[1]


def _report(
    engine: str,
    size: tuple[int, int],
    this: list[dict[str, object]],
    previous: list[dict[str, object]],
    rev: str | None,
) -> dict[str, object]:
    def runs(records: list[dict[str, object]], key: str) -> list[float | None]:
        return [r[key] for r in records]

    step_cpu = _median(runs(this, "step_cpu"))
    core_cpu = _median(runs(this, "core_cpu"))
    before_step = _median(runs(previous, "step_cpu")) if previous else None
    before_core = _median(runs(previous, "core_cpu")) if previous else None
    return {
        "benchmark": "step: Simulation.step and the core per step, CPU time, against a previous "
        "version",
        "engine": engine,
        "bound_engine": this[0]["bound_engine"],
        "sensors": size[0],
        "targets": size[1],
        "runs": len(this),
        "steps_timed": this[0]["steps_timed"],
        "step_cpu_median_s": step_cpu,
        "step_wall_median_s": _median(runs(this, "step_wall")),
        "core_cpu_median_s": core_cpu,
        "core_wall_median_s": _median(runs(this, "core_wall")),
        "core_step_cpu_median_s": _median(runs(this, "lean_cpu")),
        "previous": rev,
        "previous_step_cpu_median_s": before_step,
        "previous_step_wall_median_s": _median(runs(previous, "step_wall")) if previous else None,
        "previous_core_cpu_median_s": before_core,
        "ratio_to_previous": None if not before_step else step_cpu / before_step,
        "core_ratio_to_previous": None if not before_core else core_cpu / before_core,
        "spread": {
            "step_cpu_s": _spread(runs(this, "step_cpu")),
            "core_cpu_s": _spread(runs(this, "core_cpu")),
            "core_step_cpu_s": _spread(runs(this, "lean_cpu")),
            "previous_step_cpu_s": _spread(runs(previous, "step_cpu")) if previous else None,
            "previous_core_cpu_s": _spread(runs(previous, "core_cpu")) if previous else None,
        },
        "events_per_step": this[0]["events_per_step"],
        "in_view_fraction": this[0]["in_view_fraction"],
    }


def main() -> None:
    args = sys.argv[1:]
    if args and args[0] == "--measure":
        _worker(args[1], [tuple(int(v) for v in a.split("x")) for a in args[2:]])
        return
    chosen = [e for e in ("numpy", "numba") if engines.ENGINES[e].available()]
    runs, rev = 3, PREVIOUS
    for flag in ("--engines", "--runs", "--previous"):
        if flag in args:
            at = args.index(flag)
            value = args[at + 1]
            del args[at : at + 2]
            if flag == "--engines":
                chosen = value.split(",")
            elif flag == "--runs":
                runs = int(value)
            else:
                rev = value
    previous_wanted = "--no-previous" not in args
    args = [a for a in args if a != "--no-previous"]
    sizes: list[tuple[int, int]] = [tuple(int(v) for v in a.split("x")) for a in args] or list(
        SIZES
    )
    results: dict[tuple[str, str], list[list[dict[str, object]]]] = {}
    with tempfile.TemporaryDirectory() as folder:
        earlier = Path(folder) / "previous"
        if previous_wanted:
            subprocess.run(
                ["git", "-C", str(ROOT), "worktree", "add", "--detach", str(earlier), rev],
                check=True,
                capture_output=True,
            )
        try:
            for _ in range(runs):  # alternating: previous, this, for each engine
                for engine in chosen:
                    versions = (
                        (("previous", earlier), ("this", ROOT))
                        if previous_wanted
                        else (("this", ROOT),)
                    )
                    for label, where in versions:
                        results.setdefault((label, engine), []).append(
                            _run(where / "src", engine, sizes)
                        )
        finally:
            if previous_wanted:
                subprocess.run(
                    ["git", "-C", str(ROOT), "worktree", "remove", "--force", str(earlier)],
                    check=True,
                    capture_output=True,
                )
    for engine in chosen:
        for k, size in enumerate(sizes):
            this = [run[k] for run in results[("this", engine)]]
            before = [run[k] for run in results.get(("previous", engine), [])]
            print(json.dumps(_report(engine, size, this, before, rev if before else None)))


if __name__ == "__main__":
    main()
