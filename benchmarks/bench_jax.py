"""The core jitted by JAX against the NumPy core, on the same sensor–target pairs, one step.

The scene of bench_evaluate.py (``SENSORS`` LWIR sensors pointed by angles, ``TARGETS`` trucks,
clutter from a temperature spread, haze with noise), evaluated at one time:
:func:`targetacq.core.evaluate` on NumPy arrays, and the same function under ``jax.jit`` on the
scene's JAX arrays (float64). Both compute every factor and probability of every pair.

The roofline is the time NumPy needs to read the per-pair input (the SCR, n_s × n_g) and write
the per-pair float outputs (range, critical dimension, cycles, optical depth, transmittance,
SNR and three probabilities: nine fresh arrays), one add each (as in bench_core.py). Everything
runs on one thread (XLA's too, set below before JAX is imported); each of ``RUNS`` runs takes the
best of ``REPEATS`` calls. One JSON line per backend is printed, with the median and the range
over the runs; the last line compares them. The jit compilation is timed once, apart.

Arguments: sensors targets (default 100 10000).
"""

from __future__ import annotations

import json
import os
import statistics
import sys
import time

# One thread for XLA, like NumPy's elementwise ufuncs (must be set before JAX is imported).
os.environ.setdefault(
    "XLA_FLAGS", "--xla_cpu_multi_thread_eigen=false intra_op_parallelism_threads=1"
)

import numpy as np

from _timing import REPEATS, best_of, roofline
from bench_evaluate import scenario
from targetacq import core

RUNS = 3
OUTPUTS = 9  # per-pair float arrays written (module docstring)


def _spread(values: list[float]) -> dict[str, float]:
    return {"median": statistics.median(values), "min": min(values), "max": max(values)}


def main() -> None:
    try:
        import jax
        import jax.numpy as jnp
    except ImportError:
        print("bench_jax: JAX is not installed (pip install 'targetacq[jax]'); skipped")
        return
    jax.config.update("jax_enable_x64", True)
    n_s, n_g = (int(a) for a in (sys.argv[1:] + ["100", "10000"][len(sys.argv) - 1 :]))
    chain = scenario(n_s, n_g, 1)
    scene = chain.compiled.scene
    s, t, h = core.scenario_positions(chain.scenario, [0.0])
    s, t, h = s[:, 0], t[:, 0], h[:, 0]
    pairs = n_s * n_g

    def numpy_core() -> object:
        return core.evaluate(scene, s, t, h)

    scene_jax = core.records.as_jax(scene)
    args = (scene_jax, jnp.asarray(s), jnp.asarray(t), jnp.asarray(h))
    jitted = jax.jit(core.evaluate)
    start = time.perf_counter()
    jax.block_until_ready(jitted(*args))
    compile_seconds = time.perf_counter() - start

    def jax_core() -> object:
        return jax.block_until_ready(jitted(*args))

    # The same numbers (the tests check this to 1e-12 on every bundled scenario).
    want, got = numpy_core()[1].fused_detection, np.asarray(jax_core()[1].fused_detection)
    difference = float(np.nanmax(np.abs(got - want))) if want.size else 0.0

    scr = np.ascontiguousarray(np.broadcast_to(scene.signature.scr, (n_s, n_g)))
    roof = roofline([scr], outputs=OUTPUTS)
    times: dict[str, list[float]] = {"numpy": [], "jax": [], "roofline": []}
    for _ in range(RUNS):
        times["numpy"].append(best_of(numpy_core))
        times["jax"].append(best_of(jax_core))
        times["roofline"].append(best_of(roof))
    roof_median = statistics.median(times["roofline"])
    common = {"sensors": n_s, "targets": n_g, "pairs": pairs, "runs": RUNS, "repeats": REPEATS}
    for name in ("numpy", "jax"):
        seconds = _spread(times[name])
        line = {
            "benchmark": f"jax: core.evaluate, {'jax.jit, float64' if name == 'jax' else name}",
            **common,
            "seconds": seconds,
            "pairs_per_second": pairs / seconds["median"],
            "roofline_ratio": _spread([v / roof_median for v in times[name]]),
        }
        if name == "jax":
            line["compile_seconds"] = compile_seconds
            line["jax"] = jax.__version__
            line["device"] = str(jax.devices()[0])
        print(json.dumps(line))
    jax_over_numpy = [a / b for a, b in zip(times["jax"], times["numpy"], strict=True)]
    summary = {
        "benchmark": "jax: jitted core against the NumPy core",
        **common,
        "roofline_seconds": _spread(times["roofline"]),
        "jax_over_numpy_time": _spread(jax_over_numpy),
        "max_abs_difference_fused_detection": difference,
        "numpy": np.__version__,
    }
    print(
        f"{pairs:,} pairs, one step: NumPy {statistics.median(times['numpy']) * 1e3:.1f} ms, "
        f"jitted JAX {statistics.median(times['jax']) * 1e3:.1f} ms "
        f"({statistics.median(jax_over_numpy):.2f} x NumPy's time), roofline "
        f"{roof_median * 1e3:.1f} ms; compile {compile_seconds:.1f} s",
        file=sys.stderr,
    )
    print(json.dumps(summary))


if __name__ == "__main__":
    main()
