"""Throughput of the core per sensor type: the same 20 sensors × 1000 targets × 50 time steps
(10⁶ triples) evaluated through ``ModelChain.compute`` with thermal imagers, colour cameras
(three bands: three rows each), radars and laser radars.

Thermal scenes take the core's NumPy path; a scene with radars or laser radars takes the
generic array path with the active sensors' rows (``targetacq.core.active``), so the ratio to
the thermal line measures what the active rows cost. One JSON line per type: ``type``,
``rows`` (sensor rows of the core), ``triples`` (scenario sensors × targets × times),
``triples_per_second`` and ``vs_thermal``.
"""

from __future__ import annotations

import json

import numpy as np

from _timing import best_of
from targetacq.run.model_chain import ModelChain
from targetacq.scenario.schema import parse_scenario

N_SENSORS, N_TARGETS, N_STEPS = 20, 1000, 50


def _sensor(kind: str, i: int, x: float, y: float) -> dict:
    base = {"name": f"s{i}", "position": [f"{x:.1f} m", f"{y:.1f} m", "20 m"]}
    if kind == "thermal":
        return {**base, "type": "thermal", "band": "lwir", "ifov": "0.1 mrad", "netd": "50 mK"}
    if kind == "colour":
        bands = ["red", "green", "blue"]
        return {**base, "type": "colour", "bands": bands, "ifov": "0.05 mrad", "nec": 0.01}
    if kind == "radar":
        radar = {
            "power": "1 kW",
            "gain": "30 dB",
            "frequency": "10 GHz",
            "pulse_length": "0.1 us",
            "beamwidth": "1 deg",
        }
        return {**base, "type": "radar", "radar": radar}
    laser = {"power": "1 kW", "aperture": "50 mm", "timing": "1 ns", "nep": "10 nW"}
    return {**base, "type": "laser_radar", "band": "1.5-1.6 um", "ifov": "0.2 mrad", "laser": laser}


def chain(kind: str) -> ModelChain:
    rng = np.random.default_rng(3)
    xy = rng.uniform(-5e3, 5e3, (N_SENSORS + N_TARGETS, 2))
    colours = {"red": 0.2, "green": 0.15, "blue": 0.1}
    document = {
        "sensors": [_sensor(kind, i, *xy[i]) for i in range(N_SENSORS)],
        "targets": [
            {
                "name": f"t{j}",
                "dimensions": ["7 m", "2.5 m", "3 m"],
                "temperature": "305 K",
                "reflectance": colours if kind == "colour" else 0.2,
                "rcs": "10 m^2",
                "position": [f"{x:.1f} m", f"{y:.1f} m", "0 m"],
            }
            for j, (x, y) in enumerate(xy[N_SENSORS:])
        ],
        "background": {
            "temperature": "300 K",
            "reflectance": 0.1,
            "irradiance": "300 W/m^2",
            "sigma0": "-30 dB",
            "relief_std": "0.3 m",
        },
        "atmosphere": {"extinction": "0.2 /km", "rain_rate": "2 mm/h"}
        if kind == "radar"
        else {"extinction": "0.2 /km"},
        "time": {"start": "0 s", "stop": f"{N_STEPS - 1} s", "step": "1 s"},
    }
    return ModelChain(parse_scenario(document))


def main() -> None:
    times = np.arange(N_STEPS, dtype=float)
    triples = N_SENSORS * N_TARGETS * N_STEPS
    thermal = None
    for kind in ("thermal", "colour", "radar", "laser_radar"):
        model = chain(kind)
        seconds = best_of(lambda model=model: model.compute(times), repeats=3)
        rate = triples / seconds
        thermal = thermal or rate
        print(
            json.dumps(
                {
                    "type": kind,
                    "rows": len(model.sensor_names),
                    "triples": triples,
                    "triples_per_second": round(rate),
                    "vs_thermal": round(rate / thermal, 3),
                }
            )
        )


if __name__ == "__main__":
    main()
