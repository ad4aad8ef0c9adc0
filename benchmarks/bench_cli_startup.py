"""Start-up cost of the ``targetacq`` command: ``targetacq --help``, ``--version``,
``examples list`` and ``dri --example`` in fresh processes, and one in-process call of
``targetacq.cli.main``. The goal for ``--help`` is under 0.5 s: it imports no command module
(nor NumPy or SciPy), only typer and rich.

Each command runs ``REPEATS`` times in a new interpreter (``python -m targetacq``, the console
script's entry point), after one untimed run that warms the file cache; the median and the
spread (smallest, largest) of the wall times are printed. The in-process figure is the best of
several calls of ``main(["dri", "--example"])`` once the package is imported: what a test pays
per call. The last line printed is one JSON object.

Arguments: repeats (default 5).
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import resource
import statistics
import subprocess
import sys
import time

from _timing import best_of

REPEATS = int(sys.argv[1]) if len(sys.argv) > 1 else 5

COMMANDS = {
    "help": ["--help"],
    "version": ["--version"],
    "examples_list": ["examples", "list"],
    "dri_example": ["dri", "--example"],
}


def process_times(args: list[str]) -> tuple[list[float], list[float]]:
    """Wall times and CPU times (user + system) [s] of ``targetacq ARGS`` in a new interpreter,
    ``REPEATS`` runs. The CPU time is what the command costs on an idle machine; the wall time
    grows with the machine's load (printed as ``load_average_1min``)."""
    command = [sys.executable, "-m", "targetacq", *args]
    subprocess.run(command, capture_output=True, check=True)  # warm the file cache
    walls, cpus = [], []
    for _ in range(REPEATS):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        subprocess.run(command, capture_output=True, check=True)
        walls.append(time.perf_counter() - start)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpus.append(after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
    return walls, cpus


def in_process_call() -> float:
    """Best wall time [s] of one ``main(["dri", "--example"])`` call, the package imported."""
    from targetacq.cli import main

    def call() -> None:
        with contextlib.redirect_stdout(io.StringIO()), contextlib.suppress(SystemExit):
            main(["dri", "--example"])

    call()
    return best_of(call)


def main() -> None:
    result: dict[str, object] = {"benchmark": "cli: start-up", "repeats": REPEATS}
    result["load_average_1min"] = os.getloadavg()[0] if hasattr(os, "getloadavg") else None
    for name, args in COMMANDS.items():
        times, cpus = process_times(args)
        median = statistics.median(times)
        result[f"{name}_seconds"] = times
        result[f"{name}_median_seconds"] = median
        result[f"{name}_cpu_seconds"] = cpus
        print(
            f"targetacq {' '.join(args)}: median {median:.3f} s "
            f"(min {min(times):.3f}, max {max(times):.3f}; {REPEATS} runs); CPU median "
            f"{statistics.median(cpus):.3f} s (min {min(cpus):.3f}, max {max(cpus):.3f})"
        )
    call = in_process_call()
    result["in_process_dri_example_seconds"] = call
    print(f"main(['dri', '--example']) in-process: {call * 1e3:.1f} ms (best of several)")
    print(json.dumps(result))


if __name__ == "__main__":
    main()
