"""Streamed output of a large scenario: 100 sensors × 10,000 targets × 100 time steps (10⁸
sensor–target–time triples) evaluated chunk by chunk and written to Parquet as it comes
(:func:`targetacq.run.streaming.write_chunks`), in bounded memory.

Prints the triples, the seconds, the triples per second, the peak resident memory and the size
of the file; the last line printed is one JSON object. Arguments: sensors targets steps
[file] (defaults 100 10000 100, and a temporary .parquet file, removed afterwards; the suffix
of a file given picks the format: .parquet, .csv, .json, .nc or .zarr).

The scenario (bench_evaluate.py's) is built with a one-step time grid and evaluated at the
times 0, 1, ..., steps - 1 s given explicitly: its targets and sensors stand still, so the work
is that of a grid of ``steps`` times, but the compiler's memory check (which sizes an
evaluation of the scenario's own grid held whole in memory) does not refuse a run that streams.
"""

from __future__ import annotations

import json
import resource
import shutil
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from bench_evaluate import scenario
from targetacq.run.streaming import chunk_sizes, write_chunks


def _size(path: Path) -> int:
    if path.is_dir():
        return sum(p.stat().st_size for p in path.rglob("*") if p.is_file())
    return path.stat().st_size


def main() -> None:
    counts = (sys.argv[1:4] + ["100", "10000", "100"][len(sys.argv[1:4]) :])[:3]
    n_s, n_g, n_t = (int(a) for a in counts)
    folder = None
    if len(sys.argv) > 4:
        out = Path(sys.argv[4])
    else:
        folder = Path(tempfile.mkdtemp(prefix="bench_write-"))
        out = folder / "rows.parquet"
    start = time.perf_counter()
    chain = scenario(n_s, n_g, 1)
    times = np.arange(n_t, dtype=float)
    setup = time.perf_counter() - start
    triples = n_s * n_g * n_t
    per_target, per_time = chunk_sizes(n_s, n_g, n_t)
    try:
        start = time.perf_counter()
        write_chunks(chain, out, times)
        elapsed = time.perf_counter() - start
        size = _size(out)
    finally:
        if folder is not None:
            shutil.rmtree(folder, ignore_errors=True)
    rss_mib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    rate = triples / elapsed
    result = {
        "benchmark": "write: streaming.write_chunks, full pipeline to " + out.suffix,
        "sensors": n_s,
        "targets": n_g,
        "steps": n_t,
        "triples": triples,
        "targets_per_chunk": per_target,
        "times_per_chunk": per_time,
        "seconds": elapsed,
        "setup_seconds": setup,
        "triples_per_second": rate,
        "peak_memory_mib": rss_mib,
        "file_mib": size / 2**20,
    }
    print(
        f"{triples:.3g} triples to {out.suffix} in {elapsed:.1f} s: {rate / 1e6:.2f} M triples/s, "
        f"peak memory {rss_mib:.0f} MiB, file {size / 2**20:.0f} MiB"
    )
    print(json.dumps(result))


if __name__ == "__main__":
    main()
