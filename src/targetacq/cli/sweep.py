"""The `sweep` command: DRI ranges over the product of option lists (a trade study)."""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Annotated, Any

import typer

from targetacq.cli import FORMATS, FormatOption, _csv, app
from targetacq.cli.options import range_case_options
from targetacq.io.files import json_text, output_path, write_atomically
from targetacq.run.range_options import option_choice, option_quantity

# xarray, dask and matplotlib are imported by the command when it runs, not when the CLI starts.


@app.command()
@range_case_options
def sweep(
    case_options: dict[str, Any],
    output_format: FormatOption = "table",
    out: Annotated[
        str | None,
        typer.Option(
            help="Write the sweep: .nc (netCDF), .zarr, .csv, .parquet or .json (units and "
            "provenance in each; in CSV as # lines first)."
        ),
    ] = None,
    figure: Annotated[
        str | None,
        typer.Option(help="Draw the ranges against the first swept option: a .png file."),
    ] = None,
    range_: Annotated[
        str | None,
        typer.Option(
            "--range",
            help="Give the probabilities at these ranges instead, e.g. 500m,1km,2km.",
        ),
    ] = None,
    workers: Annotated[
        int | None,
        typer.Option(
            help="Workers of a local Dask cluster, at most one per CPU (default: serial up "
            "to 1,000 points, else one per CPU)."
        ),
    ] = None,
    scheduler: Annotated[
        str | None,
        typer.Option(help="Address of an existing Dask scheduler, e.g. tcp://host:8786."),
    ] = None,
    chunk_size: Annotated[
        int | None,
        typer.Option(
            help="Points per block of work, solved together as arrays (default: 250 serially; "
            "on Dask about four blocks per worker, 100 to 10,000 points)."
        ),
    ] = None,
    progress: Annotated[
        bool | None,
        typer.Option(
            "--progress/--no-progress",
            help="Progress bar on stderr (default: when stderr is a terminal).",
        ),
    ] = None,
) -> None:
    """Ranges (or probabilities at ranges) over every combination of the options given as
    comma-separated lists: a trade study. Each number equals that of a single `targetacq dri`
    run with those values. Large sweeps run on Dask.

    Example: targetacq sweep --pitch 12um --focal-length 35mm,50mm,75mm
    --critical-dimension 0.75m,2.3m --band lwir --obscurant none,fog:low --probability 0.5,0.9
    """
    from targetacq.io.datasets import output_file

    option_choice(output_format, FORMATS, "--format")
    if out is not None:
        output_file(out, "--out")
    if figure is not None:
        output_path(figure, ("png",), "--figure")
    if workers is not None and workers < 1:
        raise ValueError(f"--workers must be >= 1; got {workers}")
    if chunk_size is not None and chunk_size < 1:
        raise ValueError(f"--chunk-size must be >= 1; got {chunk_size}")
    grid = None
    if range_ is not None:
        grid = [option_quantity(part, "length", "--range") for part in range_.split(",")]
    ds = run_sweep(
        case_options,
        ranges=grid,
        scheduler=scheduler,
        workers=workers,
        chunk_size=chunk_size,
        progress=sys.stderr.isatty() if progress is None else progress,
    )
    if out is not None:
        write_sweep(ds, out)
    if figure is not None:
        write_figure(ds, figure)
    written = "".join(f"wrote {name}\n" for name in (out, figure) if name is not None)
    if out is not None:
        # The rows are in the file: stdout says what was written, not every row again.
        points = math.prod(ds.sizes[d] for d in ds.dims)
        typer.echo(f"{points:,} points ({' × '.join(map(str, ds.dims))})\n{written}", nl=False)
        return
    text = render_sweep(ds, output_format)
    if output_format == "table" and written:
        text += "\n" + written
    typer.echo(text, nl=False)


def run_sweep(case_options: dict[str, Any], **kwargs: Any) -> Any:
    """:func:`targetacq.run.studies.sweep` with a missing Dask reported as a one-line error."""
    from targetacq.run.studies import sweep as sweep_

    try:
        return sweep_(case_options, **kwargs)
    except ModuleNotFoundError as error:
        raise ValueError(str(error)) from None


def _output(ds: Any) -> Any:
    import pandas as pd

    from targetacq.io.datasets import Output
    from targetacq.run.studies import sweep_rows

    at_ranges = "probability" in ds.data_vars
    columns = {}
    if not at_ranges:
        columns["range_m"] = {"units": "m", "long_name": ds["range"].attrs["long_name"]}
    else:
        columns["range_m"] = {"units": "m", "long_name": "slant range"}
    return Output(
        ds,
        dict(ds.attrs),
        table=lambda: pd.DataFrame(sweep_rows(ds)),
        columns=columns,
    )


def write_sweep(ds: Any, out: str) -> Path:
    """Write a sweep by the suffix of ``out`` (:data:`targetacq.io.datasets.OUTPUT_FORMATS`)."""
    from targetacq.io.datasets import write_output

    return write_output(_output(ds), out)


def render_sweep(ds: Any, output_format: str) -> str:
    """A sweep as a table, JSON (``{"meta": ..., "ranges": [rows]}``) or CSV text."""
    from targetacq.run.studies import sweep_rows

    rows = sweep_rows(ds)
    if output_format == "json":
        return json_text({"meta": dict(ds.attrs), "ranges": rows}) + "\n"
    if output_format == "csv":
        return _csv(rows)
    at_ranges = "probability" in ds.data_vars
    keys = list(rows[0])
    value_key = "probability" if at_ranges else "range_m"
    shown = [k for k in keys if k not in ("reached", value_key)]
    widths = {k: max(len(k), *(len(_cell(row[k])) for row in rows)) for k in shown}
    title = "P" if at_ranges else "range [m]"
    header = "  ".join(f"{k:<{widths[k]}}" for k in shown) + f"  {title:>12}"
    lines = [header, "-" * len(header)]
    for row in rows:
        value = row[value_key]
        if at_ranges:
            text = "-" if value is None else f"{value:.4f}"
        elif value is None:
            text = "not reached"
        elif math.isinf(value):
            text = "any"
        else:
            text = f"{value:,.0f}"
        lines.append("  ".join(f"{_cell(row[k]):<{widths[k]}}" for k in shown) + f"  {text:>12}")
    return "\n".join(lines) + "\n"


def _cell(value: Any) -> str:
    if value is None:
        return "-"
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


def write_figure(ds: Any, path: str) -> Path:
    """Ranges against the first swept option (or, at ranges, probabilities against range): one
    panel per task, one line per combination of the other swept options and probabilities (the
    same colour in every panel), the legend below the panels; a PNG written atomically."""
    import numpy as np
    from matplotlib.figure import Figure

    at_ranges = "probability" in ds.data_vars
    variable = ds["probability" if at_ranges else "range"]
    swept = [d for d in variable.dims if d not in ("task", "probability", "range")]
    x_dim = "range" if at_ranges else (swept[0] if swept else "probability")
    others = [d for d in variable.dims if d not in (x_dim, "task")]
    si = [name for name in ds.coords if ds[name].dims == (x_dim,) and name != x_dim]
    x_values = ds[si[0]].values if si else ds[x_dim].values
    numeric = np.issubdtype(np.asarray(x_values).dtype, np.number)
    positions = np.asarray(x_values, dtype=float) if numeric else np.arange(len(x_values))
    tasks = [str(t) for t in ds["task"].values]
    columns = 2 if len(tasks) > 1 else 1
    rows = math.ceil(len(tasks) / columns)
    stacked = variable.transpose("task", *others, x_dim)
    combinations = list(np.ndindex(*stacked.shape[1:-1]))
    fig = Figure(
        figsize=(9.0, 3.2 * rows + 0.25 * math.ceil(len(combinations) / 2) + 0.8),
        dpi=100,
        layout="constrained",
    )
    axes = fig.subplots(rows, columns, squeeze=False, sharex=True)
    handles = []
    for k, task in enumerate(tasks):
        ax = axes[k // columns][k % columns]
        for c, index in enumerate(combinations):
            (line,) = ax.plot(
                positions, stacked.values[(k, *index)], marker="o", markersize=3, color=f"C{c % 10}"
            )
            if k == 0:
                label = ", ".join(
                    f"{dim} {_cell(ds[dim].values[i].item())}"
                    for dim, i in zip(others, index, strict=True)
                )
                line.set_label(label or task)
                handles.append(line)
        ax.set_title(task)
        ax.grid(True, alpha=0.3)
        ax.set_ylabel("P" if at_ranges else "range [m]")
        if x_dim != "range" and (not numeric or len(x_values) <= 12):
            ax.set_xticks(positions, [_cell(v) for v in ds[x_dim].values.tolist()])
        if k // columns == rows - 1 or k + columns >= len(tasks):
            ax.set_xlabel("range [m]" if at_ranges else x_dim.replace("_", " "))
    for k in range(len(tasks), rows * columns):
        axes[k // columns][k % columns].set_visible(False)
    fig.suptitle(str(ds.attrs.get("title", "targetacq sweep")))
    if len(handles) > 1:
        fig.legend(handles=handles, loc="outside lower center", ncol=2, fontsize="small")
    out, _ = output_path(path, ("png",), "--figure")
    return write_atomically(out, lambda p: fig.savefig(p, format="png"))
