"""Evaluation results written chunk by chunk: any number of triples in bounded memory.

:meth:`targetacq.run.model_chain.Results.write` holds the whole run in memory (the dataset, and for
the tables one row per sensor–target–time triple, about 250 B each: 2.6 GiB at 10⁷ triples).
:func:`write_chunks` evaluates a :class:`targetacq.run.model_chain.ModelChain` chunk by chunk
(:meth:`~targetacq.run.model_chain.ModelChain.evaluate_chunks`: every sensor, a block of targets, a
block of times) and writes each chunk as it comes, so the memory a run needs depends on the chunk's
size (:func:`chunk_sizes`), not on the run's.

The file holds what :meth:`~targetacq.run.model_chain.Results.write` writes for the same run: the
same columns or variables, dtypes, units and long names, and provenance (the chain's, updated with
``meta``), by the suffix of the path (:data:`targetacq.io.datasets.OUTPUT_FORMATS`):

``.parquet``
    one row group per chunk (:class:`pyarrow.parquet.ParquetWriter`); the schema (column types,
    units and long names, pandas' metadata, the provenance under the key ``targetacq``) is the
    one :meth:`~targetacq.run.model_chain.Results.write` gives, found from a one-row sample of the
    run.
``.csv``, ``.json``
    the rows appended chunk by chunk (the JSON's ``meta`` first, as in
    :meth:`~targetacq.run.model_chain.Results.write`).
``.nc``
    netCDF-4: the layout (coordinates, attributes, the sensor–target variables) written by
    xarray with ``time`` as the unlimited dimension, then every chunk written into its slice
    of each variable (``netCDF4``); variables chunked as the run is.
``.zarr``
    Zarr (format 2): the layout written by xarray, the arrays sized to the run, every chunk
    written into its slice (one Zarr chunk per chunk of the run), the metadata consolidated.

Read back with xarray, a .nc or .zarr result equals the in-memory one (its storage, chunked or
contiguous, differs). Every format is written atomically and with the user's umask
(:func:`targetacq.io.datasets.write_by_suffix`).

Row order
---------
The tables (.parquet, .csv, .json) hold their rows chunk by chunk: targets in blocks of
``targets_per_chunk``, each block's times in blocks of ``times_per_chunk``, and within a
chunk by sensor, target and time, as :meth:`~targetacq.run.model_chain.Results.to_dataframe` orders
them. A run of one chunk (every run of up to :data:`CHUNK_TRIPLES` triples, by default) has exactly
the rows of :meth:`~targetacq.run.model_chain.Results.to_dataframe`, in its order; any run's rows
sorted by sensor, target and time (in the scenario's order) are its rows.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from targetacq.base.arrays import Array
from targetacq.io.datasets import (
    Output,
    csv_head,
    json_head,
    netcdf_errors,
    output_file,
    parquet_schema,
    stored_dataset,
    write_by_suffix,
)
from targetacq.io.files import json_records
from targetacq.run.model_chain import ModelChain, Results

__all__ = ["CHUNK_TRIPLES", "chunk_sizes", "write_chunks"]

CHUNK_TRIPLES = 1 << 18
"""Sensor–target–time triples per chunk by default (262,144): about 100 MiB of working memory
for the evaluation and the conversion of a chunk, and one Parquet row group."""

_AXES = ("sensor", "target", "time")
_JSON_ROWS = 1 << 14  # rows per piece of JSON text (about 10 MB of text)

_Chunk = tuple[slice, np.ndarray, dict[str, np.ndarray]]  # as ModelChain.evaluate_chunks yields
_OnChunk = Callable[[slice, np.ndarray, dict[str, np.ndarray]], object]


def chunk_sizes(
    n_sensors: int, n_targets: int, n_times: int, triples: int = CHUNK_TRIPLES
) -> tuple[int, int]:
    """Targets and times per chunk for about ``triples`` triples a chunk (every sensor is in
    every chunk): all the times when the sensors × times fit, so that a block of targets is
    whole; then as many targets as fit, one at least.

    Parameters
    ----------
    n_sensors, n_targets, n_times : int
        The size of the run.
    triples : int
        Sensor–target–time triples per chunk, at most (unless the sensors alone are more).

    Returns
    -------
    targets_per_chunk, times_per_chunk : (int, int)

    Raises
    ------
    ValueError
        If ``triples`` is not >= 1.

    Examples
    --------
    >>> chunk_sizes(100, 10_000, 100)
    (26, 100)
    >>> chunk_sizes(2, 3, 13)
    (3, 13)
    >>> chunk_sizes(1000, 5, 10_000, triples=100_000)
    (1, 100)
    """
    if not triples >= 1:
        raise ValueError(f"triples must be >= 1; got {triples}")
    sensors = max(int(n_sensors), 1)
    times = max(1, min(int(n_times), triples // sensors))
    targets = max(1, min(int(n_targets), triples // (sensors * times)))
    return targets, times


@dataclass(frozen=True)
class _Run:
    """What every writer needs: the chunks to come and the run's layout."""

    chunks: Iterator[_Chunk]
    template: Any  # the in-memory dataset with no times: coordinates, pair variables, attrs
    output: Output  # the template and the provenance to write
    times: np.ndarray  # every time of the run [s]
    sample: Any  # the table of a one-row sample, as Results.to_dataframe gives it
    targets_per_chunk: int
    times_per_chunk: int
    on_chunk: _OnChunk | None

    def each(self) -> Iterator[tuple[slice, slice, np.ndarray, dict[str, np.ndarray]]]:
        """``(targets, time slice, times, arrays)`` per chunk, the time slice being the chunk's
        place in :attr:`times`; ``on_chunk`` is called once the writer is done with it."""
        previous, first = None, 0
        for targets, times, arrays in self.chunks:
            first = first + previous[1] if previous is not None and previous[0] == targets else 0
            previous = (targets, len(times))
            yield targets, slice(first, first + len(times)), times, arrays
            if self.on_chunk is not None:
                self.on_chunk(targets, times, arrays)

    def columns(
        self, targets: slice, times: np.ndarray, arrays: Mapping[str, Any]
    ) -> dict[str, np.ndarray]:
        """The chunk's table as 1-d arrays by column, rows by sensor, target and time; the
        sensor and target columns as indices into the names (of the whole run)."""
        n_sensors = self.template.sizes["sensor"]
        indices = {
            "sensor": np.arange(n_sensors),
            "target": np.arange(targets.start, targets.stop),
            "time": np.asarray(times),
        }
        shape = (n_sensors, len(indices["target"]), len(times))
        out: dict[str, np.ndarray] = {}
        for name in self.sample.columns:
            if name in indices:
                value, dims = indices[name], (name,)
            else:
                var = self.template[name]
                dims = var.dims
                value = arrays[name] if "time" in dims else var.isel(target=targets).values
            value = np.transpose(value, [dims.index(a) for a in _AXES if a in dims])
            value = value.reshape([value.shape[dims.index(a)] if a in dims else 1 for a in _AXES])
            out[name] = np.broadcast_to(value, shape).reshape(-1)
        return out

    def frame(self, targets: slice, times: np.ndarray, arrays: Mapping[str, Any]) -> Any:
        """The chunk's rows as :meth:`Results.to_dataframe` gives them."""
        import pandas as pd

        columns = self.columns(targets, times, arrays)
        for name in ("sensor", "target"):
            names = self.template[name].values.astype(object)
            columns[name] = names[columns[name]]
        frame = pd.DataFrame(columns)
        return frame.astype(self.sample.dtypes.to_dict())


def _chunk_dataset(
    template: Any, targets: slice, times: np.ndarray, arrays: Mapping[str, Any]
) -> Any:
    """The dataset :meth:`ModelChain.evaluate` gives for one chunk (without provenance)."""
    import xarray as xr

    coords = {
        "sensor": template["sensor"].variable,
        "target": template["target"].variable[targets],
        "time": xr.Variable("time", times, template["time"].attrs),
    }
    variables = {
        name: xr.Variable(var.dims, arrays[name], var.attrs)
        if "time" in var.dims
        else var.variable.isel(target=targets)
        for name, var in template.data_vars.items()
    }
    return xr.Dataset(variables, coords=coords)


def _run(
    chain: ModelChain,
    times: Any,
    meta: Mapping[str, Any] | None,
    targets_per_chunk: int | None,
    times_per_chunk: int | None,
    on_chunk: _OnChunk | None,
) -> _Run:
    t = chain._times(times)
    n_sensors, n_targets = len(chain.sensor_names), len(chain.target_names)
    default_targets, default_times = chunk_sizes(n_sensors, n_targets, t.size)
    per_target = default_targets if targets_per_chunk is None else targets_per_chunk
    per_time = default_times if times_per_chunk is None else times_per_chunk
    for name, value in (("targets_per_chunk", per_target), ("times_per_chunk", per_time)):
        if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
            raise ValueError(f"{name} must be an integer >= 1; got {value!r}")
    chunks = chain.evaluate_chunks(t, targets_per_chunk=per_target, times_per_chunk=per_time)
    # The first target at the first time, for every sensor: the arrays' names and dtypes, and
    # a table of the sample as Results.to_dataframe makes it (its columns and their dtypes).
    one = slice(0, min(1, n_targets))
    sample_arrays = chain.compute(t[:1], one)
    empty = {
        name: np.empty((*value.shape[:-2], n_targets, 0), value.dtype)
        for name, value in sample_arrays.items()
    }
    template = chain._dataset(empty, t[:0], slice(None))  # every target, no times
    sample = Results(_chunk_dataset(template, one, t[:1], sample_arrays)).to_dataframe()
    output = Output(template, {**template.attrs, **(meta or {})})
    return _Run(chunks, template, output, t, sample, per_target, per_time, on_chunk)


def write_chunks(
    chain: ModelChain,
    path: str | Path,
    times: Array = None,
    *,
    meta: Mapping[str, Any] | None = None,
    targets_per_chunk: int | None = None,
    times_per_chunk: int | None = None,
    on_chunk: _OnChunk | None = None,
) -> Path:
    """Evaluate ``chain`` chunk by chunk and write the results to ``path`` as they come.

    The file holds what ``chain.evaluate(times).write(path, meta)`` writes (see the module
    docstring for each format, and for the order of the rows), in memory bounded by the
    chunk's size.

    Parameters
    ----------
    chain : ModelChain
        The compiled scenario.
    path : path
        The output: .parquet, .csv, .json, .nc or .zarr
        (:data:`targetacq.io.datasets.OUTPUT_FORMATS`); checked before any work.
    times : array_like, optional
        The times [s] (default: the scenario's time grid).
    meta : mapping, optional
        Provenance to add to the chain's (e.g. the scenario file and its SHA-256).
    targets_per_chunk, times_per_chunk : int, optional
        The chunk's size (default: :func:`chunk_sizes`, about :data:`CHUNK_TRIPLES` triples).
    on_chunk : callable, optional
        Called as ``on_chunk(targets, times, arrays)`` after each chunk is written, with what
        :meth:`~targetacq.run.model_chain.ModelChain.evaluate_chunks` yields (progress, summaries).

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    ValueError
        If the suffix is not one of :data:`targetacq.io.datasets.OUTPUT_FORMATS`, a chunk size is
        not an integer >= 1, the times are not real numbers, or (``OutputError``) the file
        cannot be written: the message names the file and the reason. Nothing is left
        half-written.

    Examples
    --------
    >>> import tempfile, pyarrow.parquet as pq
    >>> from targetacq.scenario.schema import load_scenario
    >>> chain = ModelChain(load_scenario("examples/two_sensors_fused.toml"))
    >>> out = write_chunks(chain, f"{tempfile.mkdtemp()}/rows.parquet", targets_per_chunk=1)
    >>> pq.ParquetFile(out).metadata.num_row_groups, pq.read_table(out).num_rows  # 2 x 2 x 13
    (2, 52)
    >>> pq.read_table(out).schema.field("range").metadata[b"units"]
    b'm'
    """
    output_file(path)  # before work
    run = _run(chain, times, meta, targets_per_chunk, times_per_chunk, on_chunk)
    return write_by_suffix(path, lambda temporary, kind: _WRITERS[kind](run, temporary))


# -- the writers -------------------------------------------------------------------------------


def _write_parquet(run: _Run, path: Path) -> None:
    import pyarrow as pa
    import pyarrow.compute as pc
    import pyarrow.parquet as pq

    sample = pa.Table.from_pandas(run.sample, preserve_index=False)
    schema = parquet_schema(run.output, sample.schema)
    names = {
        name: pa.array(run.template[name].values.tolist(), type=schema.field(name).type)
        for name in ("sensor", "target")
    }
    writer = pq.ParquetWriter(path, schema)
    try:
        for targets, _, times, arrays in run.each():
            columns = run.columns(targets, times, arrays)
            table = pa.Table.from_arrays(
                [
                    pc.take(names[f.name], columns[f.name])
                    if f.name in names
                    else pa.array(columns[f.name], type=f.type)
                    for f in schema
                ],
                schema=schema,
            )
            writer.write_table(table)
    except BaseException:
        with contextlib.suppress(Exception):  # the first failure is the one to report
            writer.close()
        raise
    writer.close()


def _write_csv(run: _Run, path: Path) -> None:
    with open(path, "w", encoding="utf-8", newline="") as handle:
        handle.write(csv_head(run.output, run.sample.columns))
        first = True
        for targets, _, times, arrays in run.each():
            # One chunk at a time, the column names before the first.
            run.frame(targets, times, arrays).to_csv(handle, header=first, index=False)
            first = False
        if first:  # no rows: the header alone
            run.sample.iloc[:0].to_csv(handle, index=False)


def _write_json(run: _Run, path: Path) -> None:
    with open(path, "w", encoding="utf-8") as handle:
        handle.write(json_head(run.output, run.sample.columns) + "[\n")
        separator = ""
        for targets, _, times, arrays in run.each():
            frame = run.frame(targets, times, arrays)
            for start in range(0, len(frame), _JSON_ROWS):
                text = json_records(frame.iloc[start : start + _JSON_ROWS])
                handle.write(separator + text[2:-2])  # the rows, without "[\n" and "\n]"
                separator = ",\n"
        handle.write("\n]}\n")


def _layout(run: _Run, chunks: str) -> tuple[Any, dict[str, dict[str, Any]]]:
    """The stored dataset with no times, and each time variable's chunking encoding."""
    stored = stored_dataset(run.output)
    sizes = {
        "sensor": stored.sizes["sensor"],
        "target": run.targets_per_chunk,
        "time": run.times_per_chunk,
    }
    encoding = {
        name: {chunks: tuple(max(1, sizes[d]) for d in var.dims)}
        for name, var in stored.variables.items()
        if "time" in var.dims and name != "time"
    }
    encoding["time"] = {chunks: (max(1, run.times.size),)}
    return stored, encoding


def _stored(value: np.ndarray) -> np.ndarray:
    return value.astype("i1") if value.dtype == bool else value


def _write_netcdf(run: _Run, path: Path) -> None:
    import netCDF4

    stored, encoding = _layout(run, "chunksizes")
    with netcdf_errors(path):  # "NetCDF: HDF error" on a full disk: one line naming the file
        stored.to_netcdf(path, engine="netcdf4", unlimited_dims=["time"], encoding=encoding)
        with netCDF4.Dataset(path, "a") as nc:
            nc.set_auto_maskandscale(False)  # the values as they are, as xarray wrote them
            for name in encoding:
                # Whole chunks are written once each: no cache (HDF5 writes them through).
                nc[name].set_var_chunk_cache(size=0)
            nc["time"][:] = run.times
            for targets, times, _, arrays in run.each():
                for name, value in arrays.items():
                    index = (slice(None),) * (value.ndim - 2) + (targets, times)
                    nc[name][index] = _stored(value)


def _write_zarr(run: _Run, path: Path) -> None:
    import zarr

    stored, encoding = _layout(run, "chunks")
    stored.to_zarr(path, mode="w", zarr_format=2, consolidated=True, encoding=encoding)
    group = zarr.open_group(path, mode="r+", zarr_format=2, use_consolidated=False)
    arrays_of: dict[str, Any] = {}
    for name, var in stored.variables.items():
        if "time" in var.dims:
            array: Any = group[name]
            array.resize(tuple(run.times.size if d == "time" else n for d, n in var.sizes.items()))
            arrays_of[name] = array
    arrays_of["time"][:] = run.times
    for targets, times, _, arrays in run.each():
        for name, value in arrays.items():
            arrays_of[name][(slice(None),) * (value.ndim - 2) + (targets, times)] = _stored(value)
    zarr.consolidate_metadata(path, zarr_format=2)


_WRITERS: dict[str, Callable[[_Run, Path], None]] = {
    "csv": _write_csv,
    "json": _write_json,
    "parquet": _write_parquet,
    "nc": _write_netcdf,
    "zarr": _write_zarr,
}
