"""Trade studies: DRI ranges (or probabilities at ranges) over the product of option lists.

:func:`sweep` takes the options of ``targetacq dri`` (:func:`targetacq.run.range_options.
range_setup`), any of which may be a list, and computes every combination as a single ``dri``
run computes it (``range_setup`` then :func:`targetacq.core.ranges.case_ranges` per probability), so
each number equals the one ``targetacq dri`` prints for that combination. The points are
computed in blocks: each point's options are read and checked on their own, then the points
that differ only in numbers are stacked into arrays, made into one case and solved together
(one bisection for thousands of points). Large sweeps run on ``dask.distributed``, a block per
task, each block computed by the same pure function as the serial path: the results are
identical.

Limits, checked before any work: at most :data:`MAX_SWEEP_POINTS` points, and the sweep's
estimated memory (:func:`sweep_bytes`: points × outputs × bytes) within what this machine has;
a local cluster has at most one worker per CPU (:func:`cluster_workers`) and never takes a fixed
port (:func:`local_cluster`: Dask's dashboard, port 8787 by default, is off). A cluster lost
during the sweep (its scheduler, or a worker that died) is :class:`ClusterLostError`, one line.
"""

from __future__ import annotations

import contextlib
import logging
import math
import os
import warnings
from collections.abc import Callable, Hashable, Iterator, Mapping, Sequence
from typing import Any

import numpy as np

from targetacq.acquisition.criteria import Criterion
from targetacq.base.arrays import Array
from targetacq.base.limits import check_size
from targetacq.core.cases import case_acquisition
from targetacq.core.ranges import case_ranges
from targetacq.run.option_table import (
    LIST_SEPARATORS,
    RANGE_CASE_OPTIONS,
    option_lists,
    option_product,
    split_list,
)
from targetacq.run.range_options import (
    RangeReading,
    RangeSetup,
    option_probabilities,
    range_case,
    range_setup,
    read_range_options,
    stack_readings,
)

__all__ = [
    "BYTES_PER_SWEEP_POINT",
    "BYTES_PER_SWEEP_VALUE",
    "MAX_SWEEP_POINTS",
    "SERIAL_LIMIT",
    "ClusterLostError",
    "cluster_workers",
    "local_cluster",
    "sweep",
    "sweep_bytes",
    "sweep_rows",
]

SERIAL_LIMIT = 1000
"""A sweep of at most this many points runs serially unless a scheduler or workers are asked
for; a larger one runs on a Dask cluster."""

MAX_SWEEP_POINTS = 1_000_000
"""Most points (combinations of the listed values) one sweep computes: at 0.15 to 1 ms a point
(reading a point's options, and its share of a block's solve), minutes on one core. A larger
study is several sweeps."""

BYTES_PER_SWEEP_POINT = 2048
"""Memory [bytes] one point of a sweep takes until the sweep returns: its options (about 430 B
measured), its place in a block of work and its result."""

BYTES_PER_SWEEP_VALUE = 1024
"""Memory [bytes] one output value (a point's task at one probability or range) takes: the
dataset's float, and its row of the table the command line prints or writes (about 700 B)."""


class ClusterLostError(ConnectionError):
    """The Dask cluster of a sweep was lost before the sweep finished: its scheduler (the
    connection to it) or a worker that died. Nothing of the sweep is returned."""


_DRI_TASKS = ("detection", "recognition", "identification")
_SERIAL_CHUNK = 250
"""Points per block of a serial sweep (so its progress bar moves every 250 points)."""
_MIN_CHUNK = 100
_MAX_CHUNK = 10_000
"""Points per block on Dask: about four blocks per worker, at least :data:`_MIN_CHUNK` (a
block's solve costs a fixed number of array passes, cheap per point only for many points) and
at most :data:`_MAX_CHUNK` (a block's memory, about 20 MB at most)."""

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


def _setup(options: Mapping[str, Any], default_probability: str) -> RangeSetup:
    """One point's range setup: its options read as ``targetacq dri`` reads them."""
    return range_setup(options, default_probability)


def _check_grid(criterion: Criterion, grid: np.ndarray | None) -> None:
    """Refuse probabilities at ranges for a criterion that gives no probabilities."""
    if grid is not None and not criterion.gives_probabilities:
        raise ValueError(
            f"--criterion {criterion.name} gives pixel-density thresholds, not "
            "probabilities at ranges"
        )


def _point(
    options: dict[str, Any], grid: np.ndarray | None, default_probability: str
) -> tuple[tuple[str, ...], np.ndarray]:
    """One point on its own: its tasks and, per task, the ranges at each probability [m] (or,
    with ``grid``, the probabilities at each range), as ``targetacq dri`` computes them.

    The reference of :func:`_block`, which computes many points at once to the same numbers
    (the tests and ``benchmarks/bench_sweep.py`` compare the two)."""
    setup = _setup(options, default_probability)
    _check_grid(setup.criterion, grid)
    if grid is not None:
        found = case_acquisition(setup.case, grid)
        values = [np.broadcast_to(getattr(found, task), grid.shape) for task in _DRI_TASKS]
        return _DRI_TASKS, np.asarray(values, dtype=float)
    columns: list[dict[str, Any]] = []
    for p in setup.probabilities:
        columns.append(case_ranges(setup.case, p))
        if not setup.criterion.gives_probabilities:
            columns *= len(setup.probabilities)  # thresholds: the same at every probability
            break
    tasks = tuple(columns[0])
    return tasks, np.array([[float(c[task]) for c in columns] for task in tasks])


def _block(
    points: Sequence[dict[str, Any]], grid: np.ndarray | None, default_probability: str
) -> list[tuple[tuple[str, ...], np.ndarray]]:
    """A block of points (the unit of work of the serial and Dask paths), as :func:`_point`
    computes each.

    Each point's options are read and checked on their own, as ``targetacq dri`` reads them
    (:func:`targetacq.run.range_options.read_range_options`: SI numbers and choices); the
    points that agree on everything but the numbers form a group, whose numbers are stacked
    into arrays (:func:`targetacq.run.range_options.stack_readings`) and made into one case
    of 1-D arrays (:func:`targetacq.run.range_options.range_case`: the optics kernels and the
    case's checks once per group), solved by one call of :func:`targetacq.core.ranges.case_ranges`
    per probability (or one of :func:`targetacq.core.cases.case_acquisition` on a points ×
    ranges grid). The bisection of ``case_ranges`` narrows every element's bracket by the same
    factor at each step, so the stacked solve stops at the step where each point alone stops:
    the same numbers."""
    readings = [read_range_options(options, default_probability) for options in points]
    groups: dict[Hashable, list[int]] = {}
    seen: dict[int, Hashable] = {}
    for i, reading in enumerate(readings):
        _check_grid(reading.settings["criterion"], grid)
        groups.setdefault(_group_key(reading, seen), []).append(i)
    results: list[tuple[tuple[str, ...], np.ndarray]] = [((), np.empty(0))] * len(readings)
    for members in groups.values():
        tasks, values = _group_values([readings[i] for i in members], grid)
        for k, i in enumerate(members):
            results[i] = (tasks, values[k])
    return results


def _group_key(reading: RangeReading, seen: dict[int, Hashable]) -> Hashable:
    """What the points of one stacked case share: their probabilities, which numbers are given,
    and every setting (criterion, transform, noise model...); ``seen`` keeps the
    :func:`_hashable` of each object met in the block (by its identity: the readings hold
    them), e.g. a named criterion, the same object at every point."""
    settings = tuple(
        value
        if value is None or type(value) is str
        else seen.get(id(value)) or seen.setdefault(id(value), _hashable(value))
        for value in reading.settings.values()
    )
    given = (tuple(reading.numbers), tuple(reading.texts), tuple(reading.settings))
    return (tuple(reading.probabilities), given, settings)


def _hashable(value: Any) -> Hashable:
    """A value that compares equal where the setting does: criteria by their thresholds,
    mappings by their items, anything unhashable by its identity."""
    if value is None or type(value) in (str, bool):
        return value
    if isinstance(value, Criterion):
        return ("criterion", value.name, value.kind, tuple(value.thresholds.items()))
    if isinstance(value, Mapping):
        return ("mapping", tuple(sorted((k, _hashable(v)) for k, v in value.items())))
    try:
        hash(value)
    except TypeError:
        return ("object", id(value))
    return value


def _group_values(
    readings: Sequence[RangeReading], grid: np.ndarray | None
) -> tuple[tuple[str, ...], np.ndarray]:
    """The tasks and values of a group of points (:func:`_block`), stacked into one case:
    ``(points, tasks, probabilities)`` (or ``(points, tasks, ranges)`` with ``grid``)."""
    first = readings[0]
    n = len(readings)
    case, _ = range_case(stack_readings(readings, (n, 1) if grid is not None else (n,)))
    if grid is not None:
        found = case_acquisition(case, grid)
        values = [np.broadcast_to(getattr(found, task), (n, grid.size)) for task in _DRI_TASKS]
        return _DRI_TASKS, np.stack(values, axis=1).astype(float)
    columns: list[dict[str, Any]] = []
    gives_probabilities = first.settings["criterion"].gives_probabilities
    for p in first.probabilities:
        columns.append(case_ranges(case, p))
        if not gives_probabilities:
            columns *= len(first.probabilities)  # thresholds: the same at every probability
            break
    tasks = tuple(columns[0])
    per_task = [
        np.stack([np.broadcast_to(np.asarray(c[task], dtype=float), (n,)) for c in columns], -1)
        for task in tasks
    ]
    return tasks, np.stack(per_task, axis=1)


def sweep(
    options: Mapping[str, Any],
    *,
    ranges: Array = None,
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
        Options of :func:`targetacq.run.range_options.range_setup` (as typed on the command
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
        Points per block of work (default: serially 250; on Dask about four blocks per worker,
        from 100 to 10,000 points).
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
        ``long_name``; ``attrs`` hold the provenance (:func:`targetacq.io.datasets.provenance`).

    Raises
    ------
    ValueError
        For a list with an empty item or the same value twice, an unknown option, or any
        option ``targetacq dri`` refuses (naming it); for a sweep of more than
        :data:`MAX_SWEEP_POINTS` points, or whose estimated memory (:func:`sweep_bytes`)
        exceeds what this machine has available (both before any work).
    ModuleNotFoundError
        If the sweep needs Dask and ``dask.distributed`` is not installed.
    ClusterLostError
        If the Dask scheduler, or a worker, is lost before the sweep finishes.

    Warns
    -----
    UserWarning
        Where ``workers`` is more than this machine's CPUs: the local cluster has one worker
        per CPU (:func:`cluster_workers`).

    Notes
    -----
    **Serial or Dask.** The sweep runs serially in this process when it has at most
    :data:`SERIAL_LIMIT` (1,000) points and neither ``scheduler`` nor ``workers`` is given;
    otherwise on Dask: on ``scheduler`` if given, else on a new local cluster
    (:func:`local_cluster`) of ``workers`` processes, at most one per CPU (default: the CPUs
    this process may use), closed afterwards.

    **Blocks.** The grid is cut into blocks of ``chunk_size`` points, a Dask task each, each
    computed by the same function as the serial path, so the numbers are identical. In a block
    every point's options are read and checked as ``targetacq dri`` reads them, into SI numbers
    and choices; the points that agree on everything but the numbers (the same criterion,
    transform, noise model, semantics, MRTD curve, the same options given...) are stacked into
    arrays and made into one case (the optics kernels and the case's checks run once on the
    arrays), solved by one call of
    :func:`targetacq.core.ranges.case_ranges` per probability (or one of
    :func:`targetacq.core.cases.case_acquisition` with ``ranges``). Each point's numbers equal
    those of the point computed alone: the bisection narrows every point's bracket by the same
    factor at each step, and stops at the same step.

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

    from targetacq.io.datasets import annotate, provenance

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
    probability_text = text["probability"] or default_probability
    split_list("--probability", probability_text)  # a coordinate: no empty or repeated value
    probabilities = option_probabilities(probability_text)
    # The size, before the points are made (a product of lists can be millions of points).
    per_point = len(_DRI_TASKS) + 1 if grid is None else len(_DRI_TASKS)  # + orientation
    _check_sweep_size(lists, per_point * (len(grid) if grid is not None else len(probabilities)))
    product = option_product(text)
    points = [full for _, full in product]
    # The first point's options checked here, before any work or cluster starts: most mistakes
    # show at once.
    _check_grid(_setup(points[0], default_probability).criterion, grid)
    serial = scheduler is None and workers is None and len(points) <= SERIAL_LIMIT
    blocks = _blocks(points, chunk_size, scheduler, workers, serial)
    if serial:
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
    from targetacq.acquisition.criteria import get_criterion

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
    from targetacq.base.units import parse_quantity

    kind, unit = _QUANTITIES[name]
    try:
        array = np.array([parse_quantity(str(v), kind, _SPECS[name].flag) for v in values])
    except ValueError:
        return None
    return f"{name}_{_SUFFIX[unit]}", unit, array


def sweep_bytes(points: int, values: int) -> int:
    """Estimated memory [bytes] of a sweep of ``points`` points and ``values`` output values
    (points × tasks × probabilities or ranges): :data:`BYTES_PER_SWEEP_POINT` per point and
    :data:`BYTES_PER_SWEEP_VALUE` per value.

    Examples
    --------
    >>> sweep_bytes(1000, 4000)  # 1,000 points, 4 tasks at one probability
    6144000
    """
    return points * BYTES_PER_SWEEP_POINT + values * BYTES_PER_SWEEP_VALUE


def _check_sweep_size(lists: Mapping[str, Sequence[Any]], per_point: int) -> None:
    """Refuse, before any work, a sweep of more than :data:`MAX_SWEEP_POINTS` points or one
    whose estimated memory (:func:`sweep_bytes`) this machine does not have."""
    points = math.prod(len(values) for values in lists.values())
    shape = " x ".join(f"{len(values):,} {_SPECS[name].flag}" for name, values in lists.items())
    what = f"the sweep of {points:,} points ({shape})" if lists else "the sweep"
    if points > MAX_SWEEP_POINTS:
        raise ValueError(
            f"{what} is more than the limit of {MAX_SWEEP_POINTS:,} points "
            "(targetacq.run.studies.MAX_SWEEP_POINTS); sweep fewer values, or split the study"
        )
    check_size(
        sweep_bytes(points, points * per_point),
        1,
        f"{what} at {per_point} values each",
        "sweep fewer values, or split the study",
    )


def _cpus() -> int:
    """CPUs this process may run on (its affinity where the system says, else the count)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def cluster_workers(workers: int | None = None) -> int:
    """Workers of a new local cluster: ``workers`` (default: one per CPU), at most one per CPU
    this process may use; more would only share the CPUs and add processes' memory.

    Warns
    -----
    UserWarning
        Where ``workers`` is more than the CPUs, saying so and how many are used.

    Raises
    ------
    ValueError
        If ``workers`` is not an integer >= 1.

    Examples
    --------
    >>> cluster_workers(1)
    1
    """
    cpus = _cpus()
    if workers is None:
        return cpus
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ValueError(f"workers must be an integer >= 1; got {workers!r}")
    if workers > cpus:
        warnings.warn(
            f"workers {workers} is more than the CPUs this process may use ({cpus}): using {cpus}",
            UserWarning,
            stacklevel=3,
        )
        return cpus
    return workers


def local_cluster(workers: int | None = None, *, processes: bool = True) -> Any:
    """A new local Dask cluster that takes no fixed port: ``workers`` workers
    (:func:`cluster_workers`), one thread each.

    Dask's dashboard (port 8787 by default) is off, and the scheduler's HTTP server, which Dask
    starts even then and would put on port 8787, listens on a free port of this machine only:
    a notebook's dashboard, or another cluster, on 8787 changes nothing.

    Parameters
    ----------
    workers : int, optional
        Workers (default: one per CPU); more than the CPUs are capped, with a warning.
    processes : bool
        Workers in processes (the sweep's default) or in threads of this process.

    Returns
    -------
    distributed.LocalCluster
        Close it (or use it as a context manager).

    Raises
    ------
    ModuleNotFoundError
        If ``dask.distributed`` is not installed, naming the extra.
    """
    try:
        import distributed
    except ImportError as error:
        raise ModuleNotFoundError(
            "a sweep on Dask needs dask.distributed: pip install 'targetacq[sweep]'"
        ) from error
    return distributed.LocalCluster(
        n_workers=cluster_workers(workers),
        threads_per_worker=1,
        processes=processes,
        dashboard_address=None,
        # dashboard_address=None still starts the scheduler's HTTP server on port 8787 (and
        # warns when it is taken): a free port of this machine instead.
        scheduler_kwargs={"dashboard": False, "dashboard_address": "127.0.0.1:0"},
        silence_logs=logging.ERROR,
    )


def _cluster_size(scheduler: Any, workers: int | None) -> int:
    if scheduler is None:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # said once, when the cluster starts
            return cluster_workers(workers)
    return max(1, workers) if workers is not None else 4


def _blocks(
    points: list[dict[str, Any]],
    chunk_size: int | None,
    scheduler: Any,
    workers: int | None,
    serial: bool,
) -> list[list[dict[str, Any]]]:
    if chunk_size is None:
        if serial:
            chunk_size = _SERIAL_CHUNK
        else:
            size = math.ceil(len(points) / (4 * _cluster_size(scheduler, workers)))
            chunk_size = min(_MAX_CHUNK, max(_MIN_CHUNK, size))
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

    cluster = client = None
    total = sum(len(b) for b in blocks)
    done = 0
    try:
        if isinstance(scheduler, distributed.Client):
            client = scheduler
        elif scheduler is not None:
            client = distributed.Client(scheduler)  # an address or a cluster object
        else:
            cluster = local_cluster(workers)
            client = distributed.Client(cluster)
        with _lost_cluster(client, lambda: done, total), _client_logs_quiet():
            futures = client.map(
                _block,
                blocks,
                grid=grid,
                default_probability=default_probability,
                pure=False,
            )
            bar, advance = _bar(progress, total)
            size = {future.key: len(block) for future, block in zip(futures, blocks, strict=True)}
            with bar:
                for future in distributed.as_completed(futures):
                    if future.status == "finished":  # not cancelled, as on a lost scheduler
                        advance(size[future.key])
                        done += size[future.key]
            results: list[tuple[tuple[str, ...], np.ndarray]] = []
            for block in client.gather(futures):
                results += block
        return results
    finally:
        with _client_logs_quiet():
            if client is not None and client is not scheduler:
                client.close()
            if cluster is not None:
                cluster.close()


@contextlib.contextmanager
def _lost_cluster(client: Any, done: Callable[[], int], total: int) -> Iterator[None]:
    """The cluster's failures as :class:`ClusterLostError`, one line saying what was lost and how
    far the sweep got; the sweep's own errors (a ValueError of a point) pass unchanged."""
    from concurrent.futures import CancelledError

    from distributed.comm import CommClosedError
    from distributed.scheduler import KilledWorker

    try:
        yield
    except (CancelledError, CommClosedError, ConnectionError, TimeoutError) as error:
        address = getattr(getattr(client, "scheduler", None), "address", None)
        where = f" {address}" if address else ""
        # A cancelled future says why ("scheduler-connection-lost"); the rest, their message.
        reason = getattr(error, "reason", None) or " ".join(str(error).split())
        raise ClusterLostError(
            f"the Dask scheduler{where} was lost during the sweep ({done():,} of {total:,} "
            f"points done; {reason or type(error).__name__}): re-run the sweep"
        ) from None
    except KilledWorker:
        raise ClusterLostError(
            f"Dask workers died computing a block of the sweep ({done():,} of {total:,} points "
            "done), more often than Dask retries it: out of memory, or killed"
        ) from None


@contextlib.contextmanager
def _client_logs_quiet() -> Iterator[None]:
    """The Dask client's log lines (e.g. "Failed to reconnect to scheduler") kept off standard
    error while a sweep runs: :class:`ClusterLostError` says it in one line."""
    logger = logging.getLogger("distributed.client")
    level = logger.level
    logger.setLevel(logging.CRITICAL)
    try:
        yield
    finally:
        logger.setLevel(level)


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
