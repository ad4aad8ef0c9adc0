"""The `validate`, `evaluate` and `simulate` commands: scenario files."""

from __future__ import annotations

import math
import os
import sys
from importlib import resources
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer
import typer.main

from targetacq.base.limits import check_seed
from targetacq.base.units import parse_quantity
from targetacq.cli import (
    DEFAULT_EXAMPLE,
    FORMATS,
    FormatOption,
    _one_line,
    _render_rows,
    app,
)
from targetacq.cli.params import complete_names
from targetacq.core.compile import check_runnable
from targetacq.core.engines import ENGINES, get_engine
from targetacq.io.datasets import output_file, sha256_file
from targetacq.run.model_chain import ModelChain
from targetacq.run.range_options import option_choice
from targetacq.run.search import check_simulation_size
from targetacq.run.search import simulate as simulate_runs
from targetacq.scenario.schema import Scenario, ScenarioError, load_scenario


def _scenario_path(scenario: str | None) -> tuple[Scenario, str]:
    """The scenario and its file's name (the bundled example without one)."""
    if scenario is not None:
        return load_scenario(scenario), scenario
    default = resources.files("targetacq").joinpath("examples").joinpath(DEFAULT_EXAMPLE)
    with resources.as_file(default) as path:
        return load_scenario(path), str(path)


def _file_name(source: str) -> str:
    """The scenario file as provenance records it: its name, not where it lies on this machine
    (an output sent to a colleague must not carry the local folders); its SHA-256 beside it
    identifies the content."""
    return Path(source).name


def _chain(scenario: Scenario, source: str, engine: str = "numpy") -> ModelChain:
    """The scenario compiled, its problems (files, sizes) located in its file."""
    try:
        return ModelChain(scenario, engine=engine)
    except ScenarioError as error:
        raise error.in_file(source) from None


EngineOption = Annotated[
    str,
    typer.Option(
        help="Compute engine: numpy (the reference), numba (pip install 'targetacq[fast]'), "
        "jax, or auto (numba where installed); the same numbers to 1e-12.",
        autocompletion=complete_names(ENGINES, separator=None),
    ),
]

ScenarioArgument = Annotated[
    str | None,
    typer.Argument(metavar="SCENARIO", help="Scenario TOML file (default: the bundled example)."),
]


@app.command()
def validate(scenario: Annotated[str, typer.Argument(metavar="SCENARIO")]) -> None:
    """Check a scenario file without running it: every check `evaluate` makes (the files it
    names, image boxes, terrain classes, the run's size). Every problem is one line on stderr
    (exit status 2).

    Example: targetacq validate examples/two_sensors_fused.toml
    """
    try:
        loaded = load_scenario(scenario)
        problems = [f"{scenario}: {problem}" for problem in check_runnable(loaded)]
    except ScenarioError as error:
        problems = list(error.problems)
    if problems:
        for problem in problems:
            sys.stderr.write(f"targetacq: error: {_one_line(problem)}\n")
        raise typer.Exit(2)
    grid = loaded.time
    last = grid.start + grid.step * (grid.count - 1)
    typer.echo(
        f"{scenario}: valid — {len(loaded.sensors)} sensor(s), {len(loaded.targets)} target(s), "
        f"{grid.count:.0f} time(s) from {grid.start:g} s to {last:g} s"
    )


@app.command()
def evaluate(
    scenario: ScenarioArgument = None,
    out: Annotated[
        str | None,
        typer.Option(
            help="Write every sensor-target-time row: .csv, .json, .parquet, .nc (netCDF) or "
            ".zarr (units and provenance in each; in CSV as # lines first), chunk by chunk as "
            "it is evaluated."
        ),
    ] = None,
    output_format: FormatOption = "table",
    engine: EngineOption = "numpy",
) -> None:
    """Evaluate all sensors x targets x times of a scenario; print the peak fused
    probabilities per target (and write the full table with --out).

    The run is evaluated and written chunk by chunk (a block of targets and times at a time;
    a progress bar on stderr when it is a terminal), so its memory does not grow with its size.

    Example: targetacq evaluate examples/two_sensors_fused.toml --out results.nc
    """
    from targetacq.run.streaming import chunk_sizes, write_chunks

    option_choice(output_format, FORMATS, "--format")
    if out is not None:
        output_file(out, "--out")  # before work
    get_engine(engine)  # before work: an unknown or missing engine is one line
    loaded, source = _scenario_path(scenario)
    chain = _chain(loaded, source, engine)
    n_sensors, n_targets = len(chain.sensor_names), len(chain.target_names)
    times = np.asarray(loaded.time.times())
    peaks = _Peaks(n_targets)
    from rich.progress import Progress

    with Progress(
        transient=True, disable=not sys.stderr.isatty(), console=_stderr_console()
    ) as bar:
        task = bar.add_task("evaluating", total=n_sensors * n_targets * times.size)

        def done(targets: slice, at: np.ndarray, arrays: dict[str, np.ndarray]) -> None:
            peaks.add(targets, at, arrays)
            bar.advance(task, n_sensors * (targets.stop - targets.start) * at.size)

        if out is not None:
            meta = {
                "scenario_file": _file_name(source),
                "scenario_file_sha256": sha256_file(source),
            }
            write_chunks(chain, out, times, meta=meta, on_chunk=done)
        else:
            per_target, per_time = chunk_sizes(n_sensors, n_targets, times.size)
            for chunk in chain.evaluate_chunks(times, per_target, per_time):
                done(*chunk)
    rows = []
    for g, target in enumerate(chain.target_names):
        row: dict[str, Any] = {"target": str(target)}
        for name in _TASKS:
            row[f"peak_{name}"] = float(peaks.value[name][g])
            row[f"at_{name}_s"] = float(peaks.at[name][g])
        row["in_view_steps"] = int(peaks.in_view_steps[g])
        rows.append(row)
    if output_format == "table":
        lines = [
            f"{loaded.name or 'scenario'}: {len(loaded.sensors)} sensor(s), "
            f"{len(loaded.targets)} target(s), {times.size} time(s); peak fused "
            "probability over time (and when)",
            "",
            f"{'target':<16}{'detection':>18}{'recognition':>18}{'identification':>18}"
            f"{'in view':>9}",
        ]
        for row in rows:
            cells = "".join(f"{row[f'peak_{k}']:>9.3f} @{row[f'at_{k}_s']:>6.0f} s" for k in _TASKS)
            lines.append(f"{row['target']:<16}{cells}{row['in_view_steps']:>9}")
        if out is not None:
            lines += ["", f"wrote {out}"]
        typer.echo("\n".join(lines))
    else:
        typer.echo(_render_rows(rows, output_format), nl=False)


_TASKS = ("detection", "recognition", "identification")


class _Peaks:
    """Per target, the peak of each fused probability over time and its time, and the steps
    with the target in some sensor's view, gathered chunk by chunk (chunks of a block of
    targets come in time order).

    The peak is the one ``np.argmax`` finds over the whole series: the first maximum, or the
    first NaN where there is one (a NaN wins, as in ``np.argmax``).
    """

    def __init__(self, n_targets: int) -> None:
        self.value = {task: np.full(n_targets, np.nan) for task in _TASKS}
        self.at = {task: np.full(n_targets, np.nan) for task in _TASKS}
        self.in_view_steps = np.zeros(n_targets, dtype=np.int64)
        self._seen = np.zeros(n_targets, dtype=bool)

    def add(self, targets: slice, times: np.ndarray, arrays: dict[str, np.ndarray]) -> None:
        if times.size == 0:
            return
        seen = self._seen[targets]
        for task in _TASKS:
            series = arrays[f"fused_{task}"]  # (targets, times)
            best = np.argmax(series, axis=-1)
            value = np.take_along_axis(series, best[:, None], axis=-1)[:, 0]
            current = self.value[task][targets]
            later = ~np.isnan(current) & (np.isnan(value) | (value > current))
            take = ~seen | later
            self.value[task][targets] = np.where(take, value, current)
            self.at[task][targets] = np.where(take, times[best], self.at[task][targets])
        self._seen[targets] = True
        self.in_view_steps[targets] += arrays["in_view"].any(axis=0).sum(axis=-1)


@app.command()
def simulate(
    scenario: Annotated[str, typer.Argument(metavar="SCENARIO")],
    duration: Annotated[str, typer.Option(help="Simulated time, e.g. 60s.")] = "60 s",
    step: Annotated[str, typer.Option(help="Time step, e.g. 0.1s.")] = "0.1 s",
    seed: Annotated[
        int, typer.Option(help="Seed in [0, 2**128 - 1]; same seed, same outcomes.")
    ] = 0,
    runs: Annotated[int, typer.Option(help="Independent runs.")] = 1000,
    output_format: FormatOption = "table",
    out: Annotated[
        str | None,
        typer.Option(
            help="Write the summary per target and task: .csv, .json, .parquet; .nc or .zarr "
            "also hold every run's first times (units and provenance, with the seed, in all but "
            "CSV)."
        ),
    ] = None,
    engine: EngineOption = "numpy",
    false_detections: Annotated[
        str | None,
        typer.Option(
            "--false-detections",
            help="Write every run's false detections (the scenario's [false_targets] table: "
            "clutter declared a target), one row each, ordered by run and time: run, sensor, "
            "time [s], x, y, z [m] (east, north, up: on the ground, z = 0), ready to feed a "
            "tracker: .csv, .json, .parquet, .nc or .zarr (units and provenance in each; in CSV as "
            "# lines first).",
        ),
    ] = None,
) -> None:
    """Random acquisition over time (field-of-view search model): per target, the fraction of
    runs with a detection / recognition / identification and the distribution of its first time.
    With a false_targets table the runs also have false detections (clutter declared a target,
    inside each sensor's field of view): counted in the table, written by --false-detections.

    Example: targetacq simulate examples/two_sensors_fused.toml --runs 200 --out sim.parquet
    """
    option_choice(output_format, FORMATS, "--format")
    if out is not None:
        output_file(out, "--out")  # before work
    if false_detections is not None:
        output_file(false_detections, "--false-detections")
        if out is not None and os.path.realpath(out) == os.path.realpath(false_detections):
            raise ValueError("--false-detections and --out name the same file; give two")
    t_total = parse_quantity(duration, "time", "--duration")
    dt = parse_quantity(step, "time", "--step")
    if not t_total > 0 or not dt > 0:
        raise ValueError("--duration and --step must be > 0")
    if runs < 1:
        raise ValueError(f"--runs must be >= 1; got {runs}")
    check_seed(seed, "--seed")
    get_engine(engine)
    loaded = load_scenario(scenario)
    if false_detections is not None and loaded.false_targets is None:
        raise ValueError(
            f"--false-detections: {scenario} has no [false_targets] table (density, "
            "probability, max_range), so there are no false detections to write"
        )
    check_simulation_size(
        t_total,
        dt,
        runs,
        len(loaded.sensors) * len(loaded.targets),
        "use fewer --runs, a longer --step or a shorter --duration",
    )
    chain = _chain(loaded, scenario, engine)
    from rich.progress import Progress

    with Progress(
        transient=True, disable=not sys.stderr.isatty(), console=_stderr_console()
    ) as bar:
        task = bar.add_task("simulating", total=runs)
        result = simulate_runs(
            chain,
            t_total,
            dt,
            runs=runs,
            seed=seed,
            progress=lambda n: bar.advance(task, n),
        )
    summary = result.summary()
    if out is not None:
        _write_simulation(out, chain, result, summary, scenario, seed, dt)
    if false_detections is not None:
        _write_false_detections(false_detections, chain, result, scenario, seed, dt)
    if output_format == "table":
        lines = [
            f"{runs} runs, {t_total:g} s in steps of {dt:g} s, seed {seed}; first times over "
            "runs (sensor-level fusion); inf: not reached by that share of runs",
            "",
            f"{'target':<16}{'task':<16}{'fraction':>9}{'t10 [s]':>9}{'t50 [s]':>9}{'t90 [s]':>9}",
        ]
        # One format per column: times to a tenth of the step's resolution (a step of 0.1 s,
        # two decimals), so that a column's numbers line up and compare by eye.
        decimals = min(4, max(0, math.ceil(-math.log10(dt)) + 1))
        for _, row in summary.iterrows():
            times = "".join(f"{row[k]:>9.{decimals}f}" for k in ("t10_s", "t50_s", "t90_s"))
            lines.append(f"{row['target']:<16}{row['task']:<16}{row['fraction']:>9.3f}{times}")
        if loaded.false_targets is not None:
            count = len(result.false_detections)
            lines += [
                "",
                f"false detections: {count} in {runs} runs ({count / runs:.3g} per run)"
                + ("" if false_detections is not None else "; --false-detections FILE writes them"),
            ]
        written = [path for path in (out, false_detections) if path is not None]
        if written:
            lines += ["", f"wrote {', '.join(written)}"]
        typer.echo("\n".join(lines))
    else:
        rows = [dict(r) for r in summary.to_dict(orient="records")]
        typer.echo(_render_rows(rows, output_format), nl=False)


def _write_simulation(
    out: str, chain: ModelChain, result: Any, summary: Any, source: str, seed: int, step: float
) -> None:
    """The summary (and, for .nc/.zarr, every run's fused first times) with provenance."""
    import xarray as xr

    from targetacq.io.datasets import Output, annotate, write_output

    tasks = list(result.fused)
    by = summary.set_index(["target", "task"])
    ds = xr.Dataset.from_dataframe(by).reindex(target=result.targets, task=tasks)
    first = np.stack([result.fused[task] for task in tasks], axis=-1)  # run, target, task
    ds["first_time"] = (("run", "target", "task"), first)
    ds = ds.assign_coords(run=np.arange(first.shape[0]))
    annotate(ds)
    meta = chain.provenance()
    meta.update(
        title=f"targetacq simulate: {chain.scenario.name or 'scenario'}",
        seed=int(seed),
        runs=int(first.shape[0]),
        duration_s=float(result.duration),
        step_s=float(step),
        scenario_file=_file_name(source),
        scenario_file_sha256=sha256_file(source),
    )
    write_output(Output(ds, meta, table=lambda: summary), out)


_FALSE_COLUMNS: dict[str, tuple[str | None, str]] = {
    "run": ("1", "index of the simulated run"),
    "sensor": (None, "sensor that declared a target where there was none"),
    "time": ("s", "time of the false detection (the scenario's clock)"),
    "x": ("m", "east coordinate of the false detection"),
    "y": ("m", "north coordinate of the false detection"),
    "z": ("m", "up coordinate of the false detection (0: on the ground)"),
}


def _write_false_detections(
    path: str, chain: ModelChain, result: Any, source: str, seed: int, step: float
) -> None:
    """Every run's false detections, one row each (run, sensor, time, x, y, z), with units and
    provenance (the [false_targets] table among it)."""
    import xarray as xr

    from targetacq.io.datasets import Output, annotate, write_output

    frame = result.false_detections.frame()
    ds = xr.Dataset({name: ("false_detection", frame[name].to_numpy()) for name in _FALSE_COLUMNS})
    annotate(ds, _FALSE_COLUMNS)
    table = chain.scenario.false_targets
    meta = chain.provenance()
    meta.update(
        title=f"targetacq simulate: false detections, {chain.scenario.name or 'scenario'}",
        seed=int(seed),
        runs=int(result.times["detection"].shape[0]),
        duration_s=float(result.duration),
        step_s=float(step),
        false_targets=None if table is None else table.model_dump(),
        scenario_file=_file_name(source),
        scenario_file_sha256=sha256_file(source),
    )
    write_output(Output(ds, meta, table=lambda: frame), path)


def _stderr_console() -> Any:
    from rich.console import Console

    return Console(stderr=True)
