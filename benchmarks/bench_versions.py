"""This version against an earlier one, in one run: bench_evaluate.py on both, alternating.

The earlier version is checked out with ``git worktree`` into a temporary folder and imported
from there (``PYTHONPATH``), the benchmark script being this checkout's. The runs alternate
(earlier, this, earlier, this, ...) so both see the same machine load; the spread over the
repeats is printed with the medians. The last line printed is one JSON object.

Arguments: REV (default 2d5239a, the version before the array core), then sensors targets steps
for bench_evaluate.py (default 100 1000 100), then repeats (default 3).
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).parent
ROOT = HERE.parent


def run(src: Path, size: list[str]) -> float:
    env = {**os.environ, "PYTHONPATH": str(src), "OMP_NUM_THREADS": "1"}
    out = subprocess.run(
        [sys.executable, str(HERE / "bench_evaluate.py"), *size, "numpy"],
        capture_output=True,
        text=True,
        env=env,
        check=True,
    ).stdout
    return float(json.loads(out.strip().splitlines()[-1])["triples_per_second"])


def main() -> None:
    args = sys.argv[1:]
    rev = args[0] if args else "2d5239a"
    size = args[1:4] if len(args) >= 4 else ["100", "1000", "100"]
    repeats = int(args[4]) if len(args) >= 5 else 3
    with tempfile.TemporaryDirectory() as folder:
        earlier = Path(folder) / "earlier"
        subprocess.run(
            ["git", "-C", str(ROOT), "worktree", "add", "--detach", str(earlier), rev],
            check=True,
            capture_output=True,
        )
        try:
            rates: dict[str, list[float]] = {"earlier": [], "this": []}
            for _ in range(repeats):
                rates["earlier"].append(run(earlier / "src", size))
                rates["this"].append(run(ROOT / "src", size))
        finally:
            subprocess.run(
                ["git", "-C", str(ROOT), "worktree", "remove", "--force", str(earlier)],
                check=True,
                capture_output=True,
            )
    medians = {k: statistics.median(v) for k, v in rates.items()}
    result = {
        "benchmark": "versions: bench_evaluate.py, this version against an earlier one",
        "earlier": rev,
        "size": [int(s) for s in size],
        "earlier_triples_per_second": rates["earlier"],
        "this_triples_per_second": rates["this"],
        "speedup_median": medians["this"] / medians["earlier"],
        "speedup_range": [
            min(rates["this"]) / max(rates["earlier"]),
            max(rates["this"]) / min(rates["earlier"]),
        ],
    }
    print(
        f"earlier {medians['earlier'] / 1e6:.2f} M triples/s, this {medians['this'] / 1e6:.2f} "
        f"M triples/s: {result['speedup_median']:.2f}x (median of {repeats})"
    )
    print(json.dumps(result))


if __name__ == "__main__":
    main()
