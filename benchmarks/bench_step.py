"""One step of the step API (:class:`targetacq.Simulation`) against the array core alone.

A scenario built in Python (thermal cameras pointed down at random azimuths over targets at
random places, haze, clutter from a temperature spread) is stepped at 10 Hz while the targets
drive; the median wall time of one ``Simulation.step`` is compared with the median of
:func:`targetacq.core.evaluate` on the same pairs (the kernel a step calls once). Sizes
(sensors × targets): 1 × 1, 20 × 500 and 100 × 10,000, with each available compute engine
(``targetacq.engines``: numpy, numba). One JSON line per engine and size (``engine``,
``sensors``, ``targets``, ``median_step_s``, ...); arguments pick other sizes, e.g.
``bench_step.py 1x1 20x500``, and ``--engines numpy`` the engines.
"""

from __future__ import annotations

import json
import statistics
import sys
import time

import numpy as np

from _timing import REPEATS
from targetacq import Simulation, core
from targetacq.scenario import Atmosphere, Background, Sensor, Target

SIZES = ((1, 1), (20, 500), (100, 10_000))
RATE = 10.0  # steps per second


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


def measure(n_sensors: int, n_targets: int, engine: str = "numpy") -> dict[str, object]:
    start = time.perf_counter()
    sim, sensor_pos, target_pos, velocity = build(n_sensors, n_targets, engine)
    setup = time.perf_counter() - start
    repeats = 5 if n_sensors * n_targets > 100_000 else 20 * REPEATS
    dt = 1.0 / RATE
    scene = sim.compiled.scene
    step_times, core_times, events = [], [], 0
    # The first two steps start the clock and the episodes; then each timed step is followed by
    # the core alone on the same positions, so that a busy machine slows both alike.
    for k in range(repeats + 3):
        t = k * dt
        positions = target_pos + velocity * t
        start = time.perf_counter()
        out = sim.step(t, dt, sensor_pos, positions)
        elapsed = time.perf_counter() - start
        if k < 3:  # the first steps compile (numba) and start the clock and the episodes
            continue
        step_times.append(elapsed)
        events += len(out.events)
        start = time.perf_counter()
        core.evaluate(scene, sensor_pos, positions)
        core_times.append(time.perf_counter() - start)
    step_median, core_median = statistics.median(step_times), statistics.median(core_times)
    return {
        "benchmark": "step: Simulation.step against core.evaluate",
        "engine": engine,
        "sensors": n_sensors,
        "targets": n_targets,
        "pairs": n_sensors * n_targets,
        "steps_timed": repeats,
        "median_step_s": step_median,
        "core_median_s": core_median,
        "ratio_to_core": step_median / core_median,
        "step_overhead_s": statistics.median(
            a - b for a, b in zip(step_times, core_times, strict=True)
        ),
        "events_per_step": events / repeats,
        "in_view_fraction": float(np.mean(out.in_view)),
        "setup_seconds": setup,
    }


def main() -> None:
    from targetacq.engines import ENGINES

    args = sys.argv[1:]
    engines = [e for e in ("numpy", "numba") if ENGINES[e].available()]
    if "--engines" in args:
        at = args.index("--engines")
        engines = args[at + 1].split(",")
        del args[at : at + 2]
    sizes = [tuple(int(v) for v in a.split("x")) for a in args] or list(SIZES)
    for n_s, n_g in sizes:
        for engine in engines:
            print(json.dumps(measure(n_s, n_g, engine)), flush=True)


if __name__ == "__main__":
    main()
