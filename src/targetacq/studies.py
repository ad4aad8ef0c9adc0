"""Trade studies: DRI ranges (or probabilities at ranges) over the product of option lists.

:func:`sweep` takes the options of ``targetacq dri`` (:func:`targetacq.services.range_case.
range_setup`), any of which may be a list, and computes every combination by the code path of
a single ``dri`` run (``range_setup`` then :func:`targetacq.ranges.case_ranges` per
probability), so each number equals the one ``targetacq dri`` prints for that combination.
Large sweeps run on ``dask.distributed``, in blocks of points, each block computed by the same
pure function as the serial path: the results are identical.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from targetacq.services.options import (
    LIST_SEPARATORS,
    RANGE_CASE_OPTIONS,
    option_lists,
    option_product,
    split_list,
)
from targetacq.services.range_case import option_probabilities

__all__ = ["SERIAL_LIMIT", "sweep", "sweep_rows"]

SERIAL_LIMIT = 1000
"""A sweep of at most this many points runs serially unless a scheduler or workers are asked
for; a larger one runs on a Dask cluster."""

_DRI_TASKS = ("detection", "recognition", "identification")
_MAX_CHUNK = 250

_QUANTITIES = {
    # option → (kind for parse_quantity, CF units of its SI value)
    "pitch": ("length", "m"),
    "focal_length": ("length", "m"),
    "ifov": ("angle", "rad"),
    "hfov": ("angle", "rad"),
    "aperture": ("length", "m"),
    "wavelength": ("length", "m"),
    "blur": ("angle", "rad"),
    "critical_dimension": ("length", "m"),
    "target_temperature": ("temperature", "K"),
    "background_temperature": ("temperature", "K"),
    "clutter_std": ("temperature difference", "K"),
    "extinction": ("extinction", "m-1"),
    "visibility": ("length", "m"),
    "netd": ("temperature difference", "K"),
    "netd_temperature": ("temperature", "K"),
    "delta_t": ("temperature difference", "K"),
    "target_area": ("area", "m2"),
}
_SUFFIX = {"m": "m", "rad": "rad", "K": "k", "m-1": "per_m", "m2": "m2"}

_SPECS = {spec.name: spec for spec in RANGE_CASE_OPTIONS}


def _text_options(options: Mapping[str, Any]) -> dict[str, Any]:
    """Every range-case option (None where not given), Python lists joined into list text."""
    unknown = sorted(set(options) - set(_SPECS) - {"example"})
    if unknown:
        raise ValueError(
            f"unknown sweep option(s) {', '.join(unknown)}; choose from "
            f"{', '.join(sorted(_SPECS))}, example"
        )
    out: dict[str, Any] = dict.fromkeys(_SPECS)
    out["example"] = False
    for name, value in options.items():
        if isinstance(value, list | tuple | np.ndarray):
            items = list(value)
            if not items:
                raise ValueError(f"{name}: empty list of values")
            separator = LIST_SEPARATORS.get(name, ",") or ","
            texts = [str(item) for item in items]
            if any(separator in text for text in texts):
                raise ValueError(f"{name}: a value contains the list separator {separator!r}")
            value = separator.join(texts)
        out[name] = value
    return out


def _point(
    options: dict[str, Any], grid: np.ndarray | None, default_probability: str
) -> tuple[tuple[str, ...], np.ndarray]:
    """One point: its tasks and, per task, the ranges at each probability [m] (or, with
    ``grid``, the probabilities at each range); computed as ``targetacq dri`` computes them."""
    from targetacq.core.cases import case_acquisition
    from targetacq.ranges import case_ranges
    from targetacq.services.range_case import range_setup

    setup = range_setup(**options, default_probability=default_probability)
    if grid is not None:
        if not setup.criterion.gives_probabilities:
            raise ValueError(
                f"--criterion {setup.criterion.name} gives pixel-density thresholds, not "
                "probabilities at ranges"
            )
        found = case_acquisition(setup.case, grid)
        values = [np.broadcast_to(getattr(found, task), grid.shape) for task in _DRI_TASKS]
        return _DRI_TASKS, np.asarray(values, dtype=float)
    columns: list[dict[str, Any]] = []
    for p in setup.probabilities:
        columns.append(case_ranges(setup.case, p))  # as dri_report: one probability at a time
        if not setup.criterion.gives_probabilities:
            columns *= len(setup.probabilities)  # thresholds: the same at every probability
            break
    tasks = tuple(columns[0])
    return tasks, np.array([[float(c[task]) for c in columns] for task in tasks])


def _block(
    points: Sequence[dict[str, Any]], grid: np.ndarray | None, default_probability: str
) -> list[tuple[tuple[str, ...], np.ndarray]]:
    """A block of points, computed one by one (the unit of work of the serial and Dask paths)."""
    return [_point(dict(options), grid, default_probability) for options in points]


def sweep(
    options: Mapping[str, Any],
    *,
    ranges: Any = None,
    scheduler: Any = None,
    workers: int | None = None,
    chunk_size: int | None = None,
    progress: bool = False,
    default_probability: str = "0.5",
) -> Any:
    """DRI ranges, or probabilities at ranges, over the product of option lists.

    Parameters
    ----------
    options : mapping
        Options of :func:`targetacq.services.range_case.range_setup` (as typed on the command
        line: text with units, ``focal_length="75mm"``), any of which may be a list: a Python
        list or comma-separated text (``"35mm,50mm,75mm"``; ``n50`` sets are separated by
        ``;``). ``probability`` is the probabilities asked for (text or list); ``example=True``
        uses the bundled example camera and target.
    ranges : array_like, optional
        Slant ranges [m], > 0: give the probabilities of detection, recognition and
        identification (ordered, as ``ModelChain`` and ``plot curves``) at these ranges
        instead of the ranges at the probabilities.
    scheduler : str or distributed.Client or cluster, optional
        An existing Dask scheduler's address (``"tcp://host:8786"``), client or cluster.
    workers : int, optional
        Workers of a new local Dask cluster (one process, one thread each).
    chunk_size : int, optional
        Points per block of work (default: about four blocks per worker, at most 250 points).
    progress : bool
        Show a progress bar on standard error.
    default_probability : str
        The probability when ``probability`` is not given.

    Returns
    -------
    xarray.Dataset
        One dimension per option given a list (named after it, the values as given as its
        coordinate, and for a quantity its SI value as the coordinate ``<name>_<unit>``), then
        ``task`` and ``probability``: the variable ``range`` [m], NaN where the task never
        reaches the probability (or is not a task of that point's criterion); +inf where it is
        reached at any range. With ``ranges``: ``task`` and ``range``, the variable
        ``probability``. Every variable and coordinate has ``units`` (numbers) and
        ``long_name``; ``attrs`` hold the provenance (:func:`targetacq.datasets.provenance`).

    Raises
    ------
    ValueError
        For a list with an empty item or the same value twice, an unknown option, or any
        option ``targetacq dri`` refuses (naming it).
    ModuleNotFoundError
        If the sweep needs Dask and ``dask.distributed`` is not installed.

    Notes
    -----
    **Serial or Dask.** The sweep runs serially in this process when it has at most
    :data:`SERIAL_LIMIT` (1,000) points and neither ``scheduler`` nor ``workers`` is given;
    otherwise on Dask: on ``scheduler`` if given, else on a new local cluster of ``workers``
    processes (default: the machine's CPU count), closed afterwards. The grid is cut into
    blocks of ``chunk_size`` points, each computed by the same function as the serial path, so
    the numbers are identical.

    Examples
    --------
    >>> ds = sweep({"pitch": "12um", "focal_length": "35mm,50mm", "critical_dimension": "0.75m"})
    >>> dict(ds["range"].sizes)
    {'focal_length': 2, 'task': 4, 'probability': 1}
    >>> ds["focal_length"].values.tolist(), ds["range"].attrs["units"]
    (['35mm', '50mm'], 'm')
    >>> # Johnson detection, N50 = 1 cycle of 2 IFOV: 0.75 m / (2 × 12 µm / 50 mm) = 1,562.5 m
    >>> float(ds["range"].sel(focal_length="50mm", task="detection", probability=0.5))
    1562.5
    """
    import xarray as xr

    from targetacq.datasets import annotate, provenance

    text = _text_options(options)
    grid: np.ndarray | None = None
    if ranges is not None:
        if text["probability"] is not None:
            raise ValueError("give probability or ranges, not both (ranges gives probabilities)")
        grid = np.atleast_1d(np.asarray(ranges, dtype=float))
        if grid.ndim != 1 or not np.all(np.isfinite(grid)) or not np.all(grid > 0):
            raise ValueError("ranges must be a 1-D list of finite ranges [m] > 0")
        if len(np.unique(grid)) != grid.size:
            raise ValueError("ranges: a range appears twice")
    lists = option_lists(text)
    product = option_product(text)
    points = [full for _, full in product]
    probability_text = text["probability"] or default_probability
    split_list("--probability", probability_text)  # a coordinate: no empty or repeated value
    probabilities = option_probabilities(probability_text)
    # The first point checked here, before any cluster starts: most mistakes show at once.
    _point(dict(points[0]), grid, default_probability)
    blocks = _blocks(points, chunk_size, scheduler, workers)
    if scheduler is None and workers is None and len(points) <= SERIAL_LIMIT:
        results = _serial(blocks, grid, default_probability, progress)
    else:
        results = _distributed(blocks, grid, default_probability, scheduler, workers, progress)
    tasks: list[str] = []
    for point_tasks, _ in results:
        tasks += [t for t in point_tasks if t not in tasks]
    last = len(grid) if grid is not None else len(probabilities)
    values = np.full((len(results), len(tasks), last), np.nan)
    for i, (point_tasks, array) in enumerate(results):
        for j, task in enumerate(point_tasks):
            values[i, tasks.index(task)] = array[j]
    names = list(lists)
    shape = [len(lists[name]) for name in names]
    coords: dict[str, Any] = {name: np.asarray(lists[name]) for name in names}
    extra: dict[str, tuple[str | None, str]] = {}
    for name in names:
        spec = _SPECS[name]
        numeric = spec.kind is not str
        extra[name] = ("1" if numeric else None, f"{spec.flag} as given: {spec.help}")
        si = _si_values(name, lists[name])
        if si is not None:
            key, unit, array = si
            coords[key] = (name, array)
            extra[key] = (unit, f"{spec.flag} [{unit}]")
    # the probability coordinate is NaN for a pixel-density criterion (no probabilities)
    gives_p = any(_gives_probabilities(point) for point in points)
    if grid is None:
        coords["task"] = tasks
        coords["probability"] = probabilities if gives_p else [math.nan] * len(probabilities)
        dims = (*names, "task", "probability")
        data = {"range": (dims, values.reshape(*shape, len(tasks), last))}
        kind = "sweep"
    else:
        coords["task"] = tasks
        coords["range"] = grid
        dims = (*names, "task", "range")
        data = {"probability": (dims, values.reshape(*shape, len(tasks), last))}
        kind = "sweep_at"
    ds = xr.Dataset(data, coords=coords)
    annotate(ds, extra, kind=kind)
    ds.attrs.update(
        provenance(
            _model_choices(text),
            options={**text, **({"ranges_m": grid.tolist()} if grid is not None else {})},
            what="targetacq sweep: "
            + ("probabilities at ranges" if grid is not None else "ranges at probabilities"),
        )
    )
    return ds


def _gives_probabilities(options: Mapping[str, Any]) -> bool:
    from targetacq.criteria import get_criterion

    criterion = options.get("criterion")
    if options.get("n50") is not None or criterion is None:
        return True
    return bool(get_criterion(criterion).gives_probabilities)


def _model_choices(text: Mapping[str, Any]) -> dict[str, Any]:
    """The model choices of a sweep, defaults filled in as range_setup fills them."""
    return {
        "criterion": text["criterion"] or ("n50" if text["n50"] else "johnson"),
        "n50": text["n50"],
        "transform": text["transform"] or "ttpf",
        "semantics": text["semantics"] or "nested",
        "noise_model": text["noise_model"] or "variance-sum",
        "bound": text["bound"],
    }


def _si_values(name: str, values: list[Any]) -> tuple[str, str, np.ndarray] | None:
    """The SI values of a swept quantity option, or None when it is not one (or a value is
    not a quantity, e.g. ``--obscurant none``)."""
    if name not in _QUANTITIES:
        return None
    from targetacq.units import parse_quantity

    kind, unit = _QUANTITIES[name]
    try:
        array = np.array([parse_quantity(str(v), kind, _SPECS[name].flag) for v in values])
    except ValueError:
        return None
    return f"{name}_{_SUFFIX[unit]}", unit, array


def _cluster_size(scheduler: Any, workers: int | None) -> int:
    if workers is not None:
        return max(1, workers)
    return max(1, os.cpu_count() or 1) if scheduler is None else 4


def _blocks(
    points: list[dict[str, Any]], chunk_size: int | None, scheduler: Any, workers: int | None
) -> list[list[dict[str, Any]]]:
    if chunk_size is None:
        size = math.ceil(len(points) / (4 * _cluster_size(scheduler, workers)))
        chunk_size = min(_MAX_CHUNK, max(1, size))
    elif chunk_size < 1:
        raise ValueError(f"chunk_size must be >= 1; got {chunk_size}")
    if workers is not None and workers < 1:
        raise ValueError(f"workers must be >= 1; got {workers}")
    return [points[i : i + chunk_size] for i in range(0, len(points), chunk_size)]


def _bar(progress: bool, total: int) -> tuple[Any, Callable[[int], None]]:
    from rich.console import Console
    from rich.progress import Progress

    bar = Progress(transient=True, disable=not progress, console=Console(stderr=True))
    task = bar.add_task("sweeping", total=total)
    return bar, lambda n: bar.advance(task, n)


def _serial(
    blocks: list[list[dict[str, Any]]],
    grid: np.ndarray | None,
    default_probability: str,
    progress: bool,
) -> list[tuple[tuple[str, ...], np.ndarray]]:
    results: list[tuple[tuple[str, ...], np.ndarray]] = []
    bar, advance = _bar(progress, sum(len(b) for b in blocks))
    with bar:
        for block in blocks:
            results += _block(block, grid, default_probability)
            advance(len(block))
    return results


def _distributed(
    blocks: list[list[dict[str, Any]]],
    grid: np.ndarray | None,
    default_probability: str,
    scheduler: Any,
    workers: int | None,
    progress: bool,
) -> list[tuple[tuple[str, ...], np.ndarray]]:
    try:
        import distributed
    except ImportError as error:
        raise ModuleNotFoundError(
            "a sweep on Dask needs dask.distributed: pip install 'targetacq[sweep]'"
        ) from error
    import logging

    cluster = client = None
    try:
        if isinstance(scheduler, distributed.Client):
            client = scheduler
        elif scheduler is not None:
            client = distributed.Client(scheduler)  # an address or a cluster object
        else:
            cluster = distributed.LocalCluster(
                n_workers=_cluster_size(None, workers),
                threads_per_worker=1,
                processes=True,
                dashboard_address=None,
                silence_logs=logging.ERROR,
            )
            client = distributed.Client(cluster)
        futures = client.map(
            _block,
            blocks,
            grid=grid,
            default_probability=default_probability,
            pure=False,
        )
        bar, advance = _bar(progress, sum(len(b) for b in blocks))
        size = {future.key: len(block) for future, block in zip(futures, blocks, strict=True)}
        with bar:
            for future in distributed.as_completed(futures):
                advance(size[future.key])
        results: list[tuple[tuple[str, ...], np.ndarray]] = []
        for block in client.gather(futures):
            results += block
        return results
    finally:
        if client is not None and client is not scheduler:
            client.close()
        if cluster is not None:
            cluster.close()


def sweep_rows(dataset: Any) -> list[dict[str, Any]]:
    """The rows of a sweep, one per point, task and probability (or range): the swept options'
    values as given, then ``task``, ``probability`` and ``range_m`` (None where never reached),
    as ``targetacq dri --format json`` names them, and ``reached``.

    Examples
    --------
    >>> ds = sweep({"example": True, "focal_length": "50mm,75mm", "probability": "0.5"})
    >>> row = sweep_rows(ds)[0]
    >>> list(row), row["focal_length"], row["task"]
    (['focal_length', 'task', 'probability', 'range_m', 'reached'], '50mm', 'detection')
    """
    at_ranges = "probability" in dataset.data_vars
    variable = dataset["probability" if at_ranges else "range"]
    rows: list[dict[str, Any]] = []
    array = variable.values
    for index in np.ndindex(array.shape):
        row: dict[str, Any] = {}
        for dim, i in zip(variable.dims, index, strict=True):
            value = dataset[dim].values[i]
            row[dim if dim != "range" else "range_m"] = value.item()
        value = float(array[index])
        if at_ranges:
            row["probability"] = None if math.isnan(value) else value
        else:
            p = row["probability"]
            row["probability"] = None if isinstance(p, float) and math.isnan(p) else p
            row["range_m"] = None if math.isnan(value) else value
            row["reached"] = not math.isnan(value)
        rows.append(row)
    return rows
