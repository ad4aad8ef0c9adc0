"""Start-up cost of the ``targetacq`` command: ``targetacq --help`` and ``targetacq dri
--example`` in fresh processes, and one in-process call of ``targetacq.cli.main``.

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
import statistics
import subprocess
import sys
import time

from _timing import best_of

REPEATS = int(sys.argv[1]) if len(sys.argv) > 1 else 5

COMMANDS = {"help": ["--help"], "dri_example": ["dri", "--example"]}


def process_times(args: list[str]) -> list[float]:
    """Wall times [s] of ``targetacq ARGS`` in a new interpreter, ``REPEATS`` runs."""
    command = [sys.executable, "-m", "targetacq", *args]
    subprocess.run(command, capture_output=True, check=True)  # warm the file cache
    times = []
    for _ in range(REPEATS):
        start = time.perf_counter()
        subprocess.run(command, capture_output=True, check=True)
        times.append(time.perf_counter() - start)
    return times


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
    for name, args in COMMANDS.items():
        times = process_times(args)
        median = statistics.median(times)
        result[f"{name}_seconds"] = times
        result[f"{name}_median_seconds"] = median
        print(
            f"targetacq {' '.join(args)}: median {median:.3f} s "
            f"(min {min(times):.3f}, max {max(times):.3f}; {REPEATS} runs)"
        )
    call = in_process_call()
    result["in_process_dri_example_seconds"] = call
    print(f"main(['dri', '--example']) in-process: {call * 1e3:.1f} ms (best of several)")
    print(json.dumps(result))


if __name__ == "__main__":
    main()
