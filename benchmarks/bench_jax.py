"""The JAX engine against the numba and NumPy engines, on the same sensor–target–time triples.

The scene of bench_evaluate.py (``SENSORS`` LWIR sensors pointed by angles, ``TARGETS`` trucks,
clutter from a temperature spread, haze with noise) at ``TIMES`` times, evaluated by each engine
bound to it (:func:`targetacq.core.engines.bind`) as :class:`targetacq.run.model_chain.ModelChain`
calls it: ``factors`` then ``probabilities``, NumPy positions in, NumPy records out. The JAX
engine runs one jitted function from the positions to the probabilities per chunk and brings
the results to the host once (host transfers included in its time). One more line, ``jax
core``, times :func:`targetacq.core.evaluate` under ``jax.jit`` on arrays already on the
device, results left there: the device's own figure, without the transfers.

Everything runs on one thread: NumPy's (OMP_NUM_THREADS=1), XLA's
(``--xla_cpu_multi_thread_eigen=false intra_op_parallelism_threads=1``, set below before JAX is
imported) and numba's (the engine is serial). Each of ``RUNS`` runs takes the fastest of
``REPEATS`` calls, with the CPU time of that call beside its wall time. The first call of each
compiled engine (numba: its kernels, from the disk cache where they are there; JAX: tracing and
XLA compilation) is timed apart and not in the runs. One JSON line per engine with the median
and the range over the runs, triples (``pairs``) per second and the time over the numba
engine's, measured in this run; the last line compares them and says on which device JAX ran
(``jax.devices()[0]``: its platform and kind; ``gpu: false`` where it is a CPU).

Arguments: sensors targets times (default 100 160 64: about 10⁶ triples, in one chunk of the
JAX engine: 64 times, :data:`~targetacq.core.engines.jax_engine.BATCH_PER_CALL`; fewer times
are padded to 64).
"""

from __future__ import annotations

import json
import os
import statistics
import sys
import time
from collections.abc import Callable
from typing import Any

# One thread for XLA, like NumPy's elementwise ufuncs (must be set before JAX is imported).
os.environ.setdefault(
    "XLA_FLAGS", "--xla_cpu_multi_thread_eigen=false intra_op_parallelism_threads=1"
)
os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np

from _timing import REPEATS
from bench_evaluate import scenario
from targetacq import core
from targetacq.core.engines import ENGINES, bind

RUNS = 3


def _spread(values: list[float]) -> dict[str, float]:
    return {"median": statistics.median(values), "min": min(values), "max": max(values)}


def _fastest(function: Callable[[], object]) -> tuple[float, float]:
    """Wall and CPU time [s] of the fastest of ``REPEATS`` calls."""
    best = (np.inf, np.inf)
    for _ in range(REPEATS):
        wall, cpu = time.perf_counter(), time.process_time()
        function()
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        if wall < best[0]:
            best = (wall, cpu)
    return best


def _first_call(function: Callable[[], object]) -> float:
    start = time.perf_counter()
    function()
    return time.perf_counter() - start


def _engine_call(engine: Any, s: np.ndarray, t: np.ndarray, h: np.ndarray) -> Callable[[], Any]:
    def run() -> Any:
        found = engine.factors(s, t, h)
        return found, engine.probabilities(found)

    return run


def main() -> None:
    try:
        import jax
        import jax.numpy as jnp
    except ImportError:
        print("bench_jax: JAX is not installed (pip install 'targetacq[jax]'); skipped")
        return
    n_s, n_g, n_t = (int(a) for a in (sys.argv[1:] + ["100", "160", "64"][len(sys.argv) - 1 :]))
    chain = scenario(n_s, n_g, n_t)
    scene = chain.compiled.scene
    s, t, h = core.scenario_positions(chain.scenario, np.arange(float(n_t)))
    pairs = n_s * n_g * n_t

    calls: dict[str, Callable[[], Any]] = {"numpy": _engine_call(bind(scene, "numpy"), s, t, h)}
    compile_seconds: dict[str, float] = {}
    with_numba = ENGINES["numba"].available()
    if with_numba:
        start = time.perf_counter()
        numba_engine = bind(scene, "numba")
        calls["numba"] = _engine_call(numba_engine, s, t, h)
        compile_seconds["numba"] = time.perf_counter() - start + _first_call(calls["numba"])
    start = time.perf_counter()
    calls["jax"] = _engine_call(bind(scene, "jax"), s, t, h)
    compile_seconds["jax"] = time.perf_counter() - start + _first_call(calls["jax"])

    with jax.enable_x64(True):
        scene_jax = core.records.as_jax(scene)
        args = (scene_jax, jnp.asarray(s), jnp.asarray(t), jnp.asarray(h))
        jitted = jax.jit(core.evaluate)

        def jax_core() -> object:
            with jax.enable_x64(True):
                return jax.block_until_ready(jitted(*args))

        compile_seconds["jax core"] = _first_call(jax_core)

    # The same numbers (the tests check this to 1e-12).
    want = calls["numpy"]()[1].fused_detection
    difference = {
        name: float(np.nanmax(np.abs(np.asarray(calls[name]()[1].fused_detection) - want)))
        for name in calls
        if name != "numpy"
    }
    calls["jax core"] = jax_core

    wall: dict[str, list[float]] = {name: [] for name in calls}
    cpu: dict[str, list[float]] = {name: [] for name in calls}
    for _ in range(RUNS):
        for name, call in calls.items():
            w, c = _fastest(call)
            wall[name].append(w)
            cpu[name].append(c)
    device = jax.devices()[0]
    where = {
        "platform": device.platform,
        "device_kind": device.device_kind,
        "gpu": device.platform == "gpu",
    }
    common = {
        "sensors": n_s,
        "targets": n_g,
        "times": n_t,
        "pairs": pairs,
        "runs": RUNS,
        "repeats": REPEATS,
    }
    summary: dict[str, Any] = {"benchmark": "jax: engines compared", **common, "jax_device": where}
    for name in calls:
        line: dict[str, Any] = {
            "benchmark": f"jax: {name} engine, factors then probabilities"
            if name != "jax core"
            else "jax: jax.jit(core.evaluate) on device arrays, results left on the device",
            "engine": name,
            **common,
            "seconds": _spread(wall[name]),
            "cpu_seconds": _spread(cpu[name]),
            "pairs_per_second": pairs / statistics.median(wall[name]),
        }
        if name in compile_seconds:
            line["first_call_seconds"] = compile_seconds[name]
        if with_numba:
            line["time_over_numba"] = _spread(
                [a / b for a, b in zip(wall[name], wall["numba"], strict=True)]
            )
        line["time_over_numpy"] = _spread(
            [a / b for a, b in zip(wall[name], wall["numpy"], strict=True)]
        )
        if name.startswith("jax"):
            line["jax"] = jax.__version__
            line["device"] = where
        print(json.dumps(line))
    summary["max_abs_difference_fused_detection_vs_numpy"] = difference
    summary["numpy"] = np.__version__
    if not where["gpu"]:
        summary["note"] = "no GPU in this run: JAX ran on the CPU, one thread"
    text = ", ".join(
        f"{name} {statistics.median(wall[name]) * 1e3:.1f} ms "
        f"({pairs / statistics.median(wall[name]):.3g} pairs/s)"
        for name in calls
    )
    print(
        f"{pairs:,} triples on {device.platform} ({device.device_kind}): {text}; first calls "
        + ", ".join(f"{k} {v:.1f} s" for k, v in compile_seconds.items()),
        file=sys.stderr,
    )
    print(json.dumps(summary))


if __name__ == "__main__":
    main()
