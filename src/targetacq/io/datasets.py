"""Result datasets people can trust later: units, names and provenance, and one set of writers.

Every result targetacq writes (a sweep, a scenario's evaluation, a simulation's summary) is an
:class:`Output`: an xarray Dataset whose variables and coordinates carry CF-style ``units`` and
``long_name`` attributes (:func:`annotate`), the rows of its table, and a provenance record
(:func:`provenance`): the package version, the model choices, the seed where there is one, and a
SHA-256 of the scenario file or of the options that made it.

:data:`OUTPUT_FORMATS` maps a file suffix to its writer, for every ``--out`` of the command line:

``.nc``
    netCDF-4 (``netCDF4``): units and long names as variable attributes, provenance as global
    attributes (nested values as JSON text).
``.zarr``
    a Zarr (format 2) folder, attributes as for netCDF; written to a temporary folder next to
    the target and renamed (:func:`targetacq.io.files.write_directory_atomically`).
``.parquet``
    the table; units and long names in each column's field metadata, provenance in the schema
    metadata under the key ``targetacq`` (JSON).
``.json``
    ``{"meta": {...provenance, "variables": {column: {units, long_name}}}, "rows": [...]}``,
    strict JSON (:func:`targetacq.io.files.json_records`).
``.csv``
    the plain table, one header line and one line per row: no metadata. Provenance and units
    are in the other formats.

Every file is written atomically and with the user's umask (mode 0644 under umask 022).

Failures are one line naming the file (:class:`targetacq.io.files.OutputError`, a
``ValueError``): a .nc or .zarr output without its package (the ``[sweep]`` extra,
:data:`FORMAT_PACKAGES`) is refused before any work (:func:`output_file`), and the netCDF
library's ``RuntimeError`` on a failed write ("NetCDF: HDF error", e.g. on a full disk) is
reported as the failure to write the file it is; nothing half-written is left behind.
"""

from __future__ import annotations

import contextlib
import datetime
import errno
import hashlib
import importlib
import json
import os
import shutil
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from targetacq.io.files import (
    json_records,
    json_text,
    output_path,
    write_atomically,
    write_directory_atomically,
)

__all__ = [
    "DIRECTORY_FORMATS",
    "DOWNLOAD_FORMATS",
    "FORMAT_PACKAGES",
    "MEDIA_TYPES",
    "OUTPUT_FORMATS",
    "Output",
    "annotate",
    "json_head",
    "netcdf_errors",
    "options_sha256",
    "output_file",
    "parquet_schema",
    "provenance",
    "sha256_file",
    "stored_dataset",
    "write_by_suffix",
    "write_output",
]

ATTRIBUTES: dict[str, tuple[str | None, str]] = {
    # ModelChain results
    "sensor": (None, "sensor name"),
    "target": (None, "target name"),
    "time": ("s", "time since the scenario's start"),
    "critical_dimension": ("m", "critical dimension of the target as seen from the sensor"),
    "cycles": (
        "1",
        "resolvable cycles across the critical dimension (radars: resolution cells across it)",
    ),
    "in_view": ("1", "target in the sensor's field of view and line of sight (boolean)"),
    "transmittance": ("1", "atmospheric transmittance of the path"),
    "snr": (
        "dB",
        "signal-to-noise ratio: of the path (Eq. 7.7) and the sensor's own noise; radars: the "
        "radar equation's (10 log10 of the power ratio); laser radars: the two-way path's and "
        "the receiver's",
    ),
    "detection": ("1", "probability of detection"),
    "recognition": ("1", "probability of recognition"),
    "identification": ("1", "probability of identification"),
    "fused_detection": ("1", "sensor-level fused probability of detection"),
    "fused_recognition": ("1", "sensor-level fused probability of recognition"),
    "fused_identification": ("1", "sensor-level fused probability of identification"),
    "contrast": (
        "W m-2",
        "target-background exitance contrast in the sensor's band (radars: the target's radar "
        "cross-section in m2; laser radars: its reflectance)",
    ),
    "scr": (
        "1",
        "signal-to-clutter ratio (+inf: no clutter measure; radars: the power ratio "
        "sigma / (sigma0 A); laser radars: height over 3-D relief)",
    ),
    # sweeps
    "task": (None, "acquisition task"),
    "probability": ("1", "probability of the task"),
    # simulations
    "run": ("1", "index of the simulated run"),
    "runs": ("1", "number of simulated runs"),
    "first_time": ("s", "first time of the task over all sensors (inf: never within the run)"),
    "fraction": ("1", "fraction of runs in which the task happened"),
    "t10_s": ("s", "10th percentile over runs of the first time of the task"),
    "t50_s": ("s", "median over runs of the first time of the task"),
    "t90_s": ("s", "90th percentile over runs of the first time of the task"),
    "mean_s": ("s", "mean over runs of the first time of the task"),
}
"""Variable or coordinate name → (CF units, long name); units None for text (no units)."""

_RANGE = {
    "model": ("m", "slant range from the sensor to the target"),
    "sweep": ("m", "range at which the task reaches the probability (NaN: never reached)"),
    "sweep_at": ("m", "slant range"),
}


@dataclass(frozen=True)
class Output:
    """A result ready to write.

    Attributes
    ----------
    dataset : xarray.Dataset
        Annotated (:func:`annotate`): every variable and coordinate has ``long_name``, and
        ``units`` unless it is text.
    meta : dict
        Provenance (:func:`provenance`), JSON-serialisable.
    table : callable, optional
        Returns the rows as a pandas DataFrame for .csv, .parquet and .json (default: the
        dataset's ``to_dataframe().reset_index()``).
    columns : mapping, optional
        Units and long name of the table's columns that are not variables of the dataset.
    """

    dataset: Any
    meta: dict[str, Any]
    table: Callable[[], Any] | None = field(default=None)
    columns: Mapping[str, Mapping[str, str]] = field(default_factory=dict)

    def frame(self) -> Any:
        if self.table is not None:
            return self.table()
        return self.dataset.to_dataframe().reset_index()

    def variables(self, columns: Any) -> dict[str, dict[str, str]]:
        """Units and long name of each column that the dataset describes."""
        out: dict[str, dict[str, str]] = {}
        for name in columns:
            if name in self.columns:
                out[str(name)] = dict(self.columns[name])
            elif name in self.dataset.variables:
                attrs = self.dataset[name].attrs
                out[str(name)] = {k: str(attrs[k]) for k in ("units", "long_name") if k in attrs}
        return out


def annotate(
    dataset: Any, extra: Mapping[str, tuple[str | None, str]] | None = None, *, kind: str = ""
) -> Any:
    """Set ``units`` and ``long_name`` on every variable and coordinate of ``dataset`` (in place).

    Parameters
    ----------
    dataset : xarray.Dataset
    extra : mapping, optional
        Name → (units or None for text, long name), before the built-in table.
    kind : {"model", "sweep", "sweep_at"}
        Which meaning ``range`` has.

    Returns
    -------
    xarray.Dataset
        ``dataset``.

    Raises
    ------
    ValueError
        If a variable or coordinate has no known units and long name.

    Examples
    --------
    >>> import xarray as xr
    >>> ds = annotate(xr.Dataset({"snr": ("time", [3.0])}, coords={"time": [0.0]}))
    >>> ds["snr"].attrs["units"], ds["time"].attrs["units"]
    ('dB', 's')
    """
    table = {**ATTRIBUTES, **({"range": _RANGE[kind]} if kind in _RANGE else {}), **(extra or {})}
    for name in dataset.variables:
        if name not in table:
            raise ValueError(f"no units and long_name known for the variable {name!r}")
        units, long_name = table[str(name)]
        attrs = dataset[name].attrs
        attrs["long_name"] = long_name
        if units is not None:
            attrs["units"] = units
    return dataset


def sha256_file(path: str | Path) -> str:
    """SHA-256 of a file's bytes, as hex.

    Examples
    --------
    >>> import tempfile, os
    >>> with tempfile.NamedTemporaryFile(delete=False) as f:
    ...     _ = f.write(b"abc")
    >>> sha256_file(f.name)[:16]
    'ba7816bf8f01cfea'
    >>> os.unlink(f.name)
    """
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def options_sha256(options: Mapping[str, Any]) -> str:
    """SHA-256 of options as canonical JSON (keys sorted, no spaces; None values left out).

    Examples
    --------
    >>> options_sha256({"pitch": "12um", "blur": None}) == options_sha256({"pitch": "12um"})
    True
    """
    given = {str(k): v for k, v in options.items() if v is not None and v is not False}
    text = json.dumps(given, sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha256(text.encode()).hexdigest()


def provenance(
    model: Mapping[str, Any],
    *,
    seed: int | None = None,
    scenario: str | Path | None = None,
    options: Mapping[str, Any] | None = None,
    what: str = "",
) -> dict[str, Any]:
    """The provenance of a result: package, version, model choices, seed, and a hash.

    Parameters
    ----------
    model : mapping
        The model choices (criterion, transform, noise model, semantics, ...).
    seed : int, optional
        The random seed, for a simulation.
    scenario : path, optional
        The scenario file: its SHA-256 is recorded as ``scenario_sha256``.
    options : mapping, optional
        The options of a sweep: recorded, and their SHA-256 as ``options_sha256``.
    what : str
        A title for the result.

    Examples
    --------
    >>> meta = provenance({"criterion": "johnson"}, seed=7)
    >>> meta["software"], meta["seed"], meta["model"]
    ('targetacq', 7, {'criterion': 'johnson'})
    """
    from targetacq import __version__

    meta: dict[str, Any] = {
        "title": what,
        "software": "targetacq",
        "version": __version__,
        "created": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
        "model": dict(model),
        "references": "Sonesson (2004), LiTH-ISY-EX-3428, Linköping University",
    }
    if seed is not None:
        meta["seed"] = int(seed)
    if scenario is not None:
        meta["scenario"] = str(scenario)
        meta["scenario_sha256"] = sha256_file(scenario)
    if options is not None:
        meta["options"] = {str(k): v for k, v in options.items() if v is not None}
        meta["options_sha256"] = options_sha256(options)
    return meta


def _global_attributes(meta: Mapping[str, Any]) -> dict[str, Any]:
    """Provenance as netCDF/Zarr global attributes: text and numbers; the rest as JSON text."""
    out: dict[str, Any] = {}
    for key, value in meta.items():
        in_int64 = isinstance(value, int) and -(2**63) <= value < 2**63  # a seed may not be
        if (in_int64 and not isinstance(value, bool)) or isinstance(value, str | float):
            out[key] = value
        else:
            out[key] = json.dumps(value, sort_keys=True, default=str)
    return out


def stored_dataset(output: Output) -> Any:
    """The dataset as the .nc and .zarr writers store it: a shallow copy of ``output.dataset``
    with the provenance as global attributes (``Conventions`` first; nested values as JSON
    text) and every boolean variable as ``int8`` (netCDF has no booleans), attributes kept.

    Examples
    --------
    >>> import xarray as xr
    >>> ds = annotate(xr.Dataset({"in_view": ("time", [True])}, coords={"time": [0.0]}))
    >>> stored = stored_dataset(Output(ds, {"model": {"criterion": "johnson"}}))
    >>> stored["in_view"].dtype, stored.attrs["model"], stored["in_view"].attrs["units"]
    (dtype('int8'), '{"criterion": "johnson"}', '1')
    """
    ds = output.dataset.copy()
    ds.attrs = {"Conventions": "CF-1.10", **_global_attributes(output.meta)}
    for name in ds.variables:
        if ds[name].dtype == bool:
            ds[name] = ds[name].astype("i1")
            ds[name].attrs.update(output.dataset[name].attrs)
    return ds


def parquet_schema(output: Output, schema: Any) -> Any:
    """The Parquet schema of ``output``'s table: ``schema`` (pyarrow, e.g. of
    ``pyarrow.Table.from_pandas(output.frame())``) with each column's units and long name as
    field metadata and the provenance as JSON under the schema metadata key ``targetacq``
    (the schema's other metadata, pandas' own, kept).

    Examples
    --------
    >>> import json, pyarrow as pa, xarray as xr
    >>> ds = annotate(xr.Dataset({"snr": ("time", [3.0])}, coords={"time": [0.0]}))
    >>> schema = parquet_schema(Output(ds, {"version": "0"}), pa.schema([("snr", pa.float64())]))
    >>> schema.field("snr").metadata[b"units"], json.loads(schema.metadata[b"targetacq"])
    (b'dB', {'version': '0'})
    """
    import pyarrow as pa

    described = output.variables(schema.names)
    fields = [
        f.with_metadata({k.encode(): v.encode() for k, v in described.get(f.name, {}).items()})
        for f in schema
    ]
    meta = {**(schema.metadata or {}), b"targetacq": json_text(output.meta, None).encode()}
    return pa.schema(fields, metadata=meta)


def json_head(output: Output, columns: Any) -> str:
    """The start of a .json result, up to its rows: ``{"meta": {...}, "rows": `` with the
    provenance and the units and long name of ``columns``; the rows (a JSON list,
    :func:`targetacq.io.files.json_records`) and ``}`` and a newline follow.

    Examples
    --------
    >>> import xarray as xr
    >>> ds = annotate(xr.Dataset({"snr": ("time", [3.0])}, coords={"time": [0.0]}))
    >>> document = json.loads(json_head(Output(ds, {"version": "0"}), ["snr"]) + "[]}")
    >>> document["meta"]["version"], document["meta"]["variables"]["snr"]["units"]
    ('0', 'dB')
    """
    meta = {**output.meta, "variables": output.variables(columns)}
    return '{"meta": ' + json_text(meta, 1) + ',\n"rows": '


def csv_head(output: Output, columns: Any) -> str:
    """The comment lines that open a .csv result: the units of every column and the provenance,
    each line starting with ``#`` (read the table with ``pandas.read_csv(path, comment="#")``).

    A CSV file has no place for attributes; these lines carry what the other formats keep in
    theirs, so that a file sent to a colleague says what its numbers are and where they came
    from.

    Examples
    --------
    >>> import xarray as xr
    >>> ds = annotate(xr.Dataset({"snr": ("time", [3.0])}, coords={"time": [0.0]}))
    >>> print(csv_head(Output(ds, {"version": "0"}), ["time", "snr"]), end="")
    # units: time [s], snr [dB]
    # provenance: {"version": "0"}
    """
    described = output.variables(columns)
    units = ", ".join(
        f"{name} [{described[name]['units']}]" if "units" in described.get(name, {}) else name
        for name in columns
    )
    meta = json.dumps(output.meta, ensure_ascii=False, separators=(", ", ": "), default=str)
    return f"# units: {units}\n# provenance: {meta}\n"


_LOW_SPACE = 1 << 20  # bytes free on the file system below which a failed write is "disk full"


@contextlib.contextmanager
def netcdf_errors(path: Path) -> Iterator[None]:
    """The netCDF library's ``RuntimeError`` while writing ``path`` as an ``OSError``, which
    :func:`targetacq.io.files.write_atomically` reports in one line naming the file (and
    removes the temporary file).

    netCDF4 raises ``RuntimeError("NetCDF: HDF error")`` where the system said "No space left
    on device" or "File too large"; the reason given says which, where it can tell.

    Examples
    --------
    >>> import tempfile
    >>> with netcdf_errors(Path(tempfile.mkdtemp()) / "x.nc"):
    ...     raise RuntimeError("NetCDF: HDF error")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    OSError: [Errno 5] NetCDF: HDF error (the netCDF library could not write the file...)
    """
    try:
        yield
    except RuntimeError as error:
        if not any(word in str(error) for word in ("NetCDF", "HDF")):
            raise  # not the library's report of a failed write
        raise OSError(*_netcdf_reason(error, path)) from error


def _netcdf_reason(error: RuntimeError, path: Path) -> tuple[int, str]:
    """(errno, reason) for a failed netCDF write: the file system's state where it explains
    the library's message."""
    message = str(error) or "the netCDF library failed"
    with contextlib.suppress(OSError):
        if shutil.disk_usage(path.parent).free < _LOW_SPACE:
            return errno.ENOSPC, f"{os.strerror(errno.ENOSPC)} ({message})"
    with contextlib.suppress(ImportError, OSError, ValueError):
        import resource

        soft, _ = resource.getrlimit(resource.RLIMIT_FSIZE)
        if soft != resource.RLIM_INFINITY:
            return errno.EFBIG, (
                f"{os.strerror(errno.EFBIG)} (a file-size limit of {soft} bytes is set; {message})"
            )
    return errno.EIO, (
        f"{message} (the netCDF library could not write the file: a full disk, a file-size "
        "limit or a failing device gives this)"
    )


def _write_netcdf(output: Output, path: Path) -> None:
    with netcdf_errors(path):
        stored_dataset(output).to_netcdf(path, engine="netcdf4")


def _write_zarr(output: Output, path: Path) -> None:
    stored_dataset(output).to_zarr(path, mode="w", zarr_format=2, consolidated=True)


def _write_csv(output: Output, path: Path) -> None:
    frame = output.frame()
    with open(path, "w", encoding="utf-8", newline="") as handle:
        handle.write(csv_head(output, frame.columns))
        frame.to_csv(handle, index=False)


def _write_parquet(output: Output, path: Path) -> None:
    import pyarrow as pa
    import pyarrow.parquet as pq

    table = pa.Table.from_pandas(output.frame(), preserve_index=False)
    schema = parquet_schema(output, table.schema)
    pq.write_table(table.cast(schema).replace_schema_metadata(schema.metadata), path)


def _write_json(output: Output, path: Path) -> None:
    frame = output.frame()
    text = json_head(output, frame.columns) + json_records(frame) + "}\n"
    path.write_text(text, encoding="utf-8")


OUTPUT_FORMATS: dict[str, Callable[[Output, Path], None]] = {
    "csv": _write_csv,
    "json": _write_json,
    "parquet": _write_parquet,
    "nc": _write_netcdf,
    "zarr": _write_zarr,
}
"""File suffix (without the dot) → writer ``(output, path)``; see the module docstring."""

DIRECTORY_FORMATS = ("zarr",)
"""The formats written as a folder."""

FORMAT_PACKAGES: dict[str, tuple[str, ...]] = {"nc": ("netCDF4",), "zarr": ("zarr",)}
"""Format → the packages its writer needs beyond the base install (the ``[sweep]`` extra)."""

MEDIA_TYPES: dict[str, str] = {
    "csv": "text/csv",
    "json": "application/json",
    "parquet": "application/vnd.apache.parquet",
    "nc": "application/x-netcdf",
}
"""Format → the media type of the one file its writer writes (every format but a folder's)."""

DOWNLOAD_FORMATS: tuple[str, ...] = tuple(
    name for name in OUTPUT_FORMATS if name not in DIRECTORY_FORMATS and name not in FORMAT_PACKAGES
)
"""The formats of :data:`OUTPUT_FORMATS` written as one file by the base install: those an
HTTP answer can carry (the web API's ``/evaluate`` downloads)."""

_EXTRA = "sweep"


def output_file(path: str | Path, what: str = "output") -> tuple[Path, str]:
    """Check an output before any work: its suffix is one of :data:`OUTPUT_FORMATS`
    (:func:`targetacq.io.files.output_path`: a writable place, not a folder unless a Zarr
    store) and the packages its format needs (:data:`FORMAT_PACKAGES`) are installed.

    Parameters
    ----------
    path : path
        The output file.
    what : str
        The input's name for messages (e.g. ``"--out"``).

    Returns
    -------
    path, format : (Path, str)

    Raises
    ------
    ValueError
        Naming ``what`` or the file: a suffix that is not one of the formats, a place that
        cannot be written (:class:`targetacq.io.files.OutputError`), or a format whose package
        is missing, with the command that installs it.

    Examples
    --------
    >>> import tempfile
    >>> output_file(f"{tempfile.mkdtemp()}/r.csv", "--out")[1]
    'csv'
    """
    out, kind = output_path(path, OUTPUT_FORMATS, what, directories=DIRECTORY_FORMATS)
    for package in FORMAT_PACKAGES.get(kind, ()):
        try:
            importlib.import_module(package)
        except ImportError:
            raise ValueError(
                f"{what} {str(out)!r}: a .{kind} file needs the {package} package, which is not "
                f"installed: pip install 'targetacq[{_EXTRA}]'"
            ) from None
    return out, kind


def write_by_suffix(path: str | Path, write: Callable[[Path, str], object]) -> Path:
    """Check ``path`` (:func:`targetacq.io.files.output_path`, before any work), then call
    ``write(temporary, format)`` and rename the temporary file onto ``path``, or the temporary
    folder for :data:`DIRECTORY_FORMATS` (:func:`targetacq.io.files.write_atomically`,
    :func:`targetacq.io.files.write_directory_atomically`).

    Parameters
    ----------
    path : path
        The output, ending in one of the suffixes of :data:`OUTPUT_FORMATS`.
    write : callable
        ``write(temporary_path, format)``, the format being the suffix without its dot.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    ValueError
        If the suffix is not one of :data:`OUTPUT_FORMATS`, or (``OutputError``) the file
        cannot be written (its format's package missing included, :func:`output_file`): the
        message names the file and the reason.

    Examples
    --------
    >>> import tempfile
    >>> out = write_by_suffix(f"{tempfile.mkdtemp()}/r.csv", lambda p, kind: p.write_text(kind))
    >>> out.read_text()
    'csv'
    """
    out, kind = output_file(path)
    if kind in DIRECTORY_FORMATS:
        return write_directory_atomically(out, lambda p: write(p, kind))
    return write_atomically(out, lambda p: write(p, kind))


def write_output(output: Output, path: str | Path) -> Path:
    """Write ``output`` by the suffix of ``path`` (:data:`OUTPUT_FORMATS`), atomically.

    Raises
    ------
    ValueError
        If the suffix is not one of :data:`OUTPUT_FORMATS`, or (``OutputError``) the file
        cannot be written: the message names the file and the reason.

    Examples
    --------
    >>> import json, tempfile, xarray as xr
    >>> ds = annotate(xr.Dataset({"snr": ("time", [3.0])}, coords={"time": [0.0]}))
    >>> result = Output(ds, provenance({"noise_model": "variance-sum"}))
    >>> out = write_output(result, f"{tempfile.mkdtemp()}/r.json")
    >>> document = json.loads(out.read_text())
    >>> document["meta"]["variables"]["snr"]["units"], document["rows"]
    ('dB', [{'time': 0.0, 'snr': 3.0}])
    """
    return write_by_suffix(path, lambda p, kind: OUTPUT_FORMATS[kind](output, p))
