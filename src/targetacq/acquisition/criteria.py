"""Criteria sets: the resolution each observation task needs.

A criteria set maps tasks to thresholds. Most sets give ``N50``, the cycles (line pairs) across
the target's critical dimension at which a task succeeds with probability 0.5 (Johnson's
criteria; Sonesson 2004 §3.5: "the measure of the 50 % probability"). The EN 62676-4 set instead
gives pixel densities on the target, which are pass/fail thresholds for ranges, not the 50 %
points of a probability curve.

The registry :data:`CRITERIA` is built from the bundled tables and is the single source of truth
for names, tasks and values (the CLI's choices and the docs come from it):

- ``johnson``: Table 3.2 averages, 1.0 / 1.4 / 4.0 / 6.4 cycles;
- ``johnson-<target>``: one set per row of Table 3.1 (truck, m48-tank, ..., 105-howitzer);
- ``c2nveo``: the 50 % row of Table 3.3, geometric mean of each printed cell;
- ``schmieder-weathersby``: detection only, the medium-clutter 50 % point of Table 3.5;
- ``pixels-1.5-6-12``, ``pixels-2-8-12.8``, ``stanag-i2``, ``en62676-4``: see
  ``data/criteria_sets.csv`` for their sources;
- ``ttp-vehicles``: V50s of the TTP metric (TTP cycles, not Johnson cycles) for tactical
  vehicles, ``data/ttp_v50.csv``; for the ``ttp`` resolution model and transform.

Criteria of one's own join the registry with :func:`register_criterion` (e.g. one fitted to
trial data, :func:`targetacq.acquisition.calibration.fit_criterion`): from then on, in that
process, its name is a criterion like the bundled ones, for the Python API, a scenario's
``[model] criterion`` and the command line's ``--criterion``. The bundled sets cannot be
replaced; :func:`unregister_criterion` takes a registered one out again.
"""

from __future__ import annotations

import functools
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Literal

from targetacq.base.registry import lookup
from targetacq.base.tables import load_table

__all__ = [
    "BUNDLED_CRITERIA",
    "CRITERIA",
    "TASKS",
    "Criterion",
    "get_criterion",
    "register_criterion",
    "unregister_criterion",
]

TASKS: tuple[str, ...] = ("detection", "orientation", "recognition", "identification")
"""The observation tasks of Johnson's criteria, in order of increasing difficulty."""


@dataclass(frozen=True)
class Criterion:
    """A named criteria set.

    Attributes
    ----------
    name : str
        Registry name.
    thresholds : Mapping[str, float]
        Task → threshold: N50 [cycles] for ``kind="cycles"``, pixel density [pixels/m] for
        ``kind="pixel-density"``.
    kind : {"cycles", "pixel-density"}
        What the thresholds are.
    source : str
        Where the numbers come from.

    Examples
    --------
    >>> import targetacq as ta
    >>> mine = ta.Criterion("mine", {"detection": 0.75, "recognition": 3.0})
    >>> mine.n50("recognition")
    3.0
    >>> ta.CRITERIA["en62676-4"].gives_probabilities  # pixel densities: ranges only
    False
    """

    name: str
    thresholds: Mapping[str, float]
    kind: Literal["cycles", "pixel-density"] = "cycles"
    source: str = ""
    tasks: tuple[str, ...] = field(init=False)

    def __post_init__(self) -> None:
        if self.kind not in ("cycles", "pixel-density"):
            raise ValueError(f"kind must be 'cycles' or 'pixel-density', got {self.kind!r}")
        if not self.thresholds:
            raise ValueError(f"criterion {self.name!r} has no thresholds")
        for task, value in self.thresholds.items():
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(
                    f"criterion {self.name!r}: threshold for {task!r} must be a finite number "
                    f"> 0, got {value!r}"
                )
        object.__setattr__(self, "thresholds", MappingProxyType(dict(self.thresholds)))
        object.__setattr__(self, "tasks", tuple(self.thresholds))

    @property
    def gives_probabilities(self) -> bool:
        """Whether the thresholds are 50 % points that a transform turns into probabilities."""
        return self.kind == "cycles"

    def n50(self, task: str) -> float:
        """N50 [cycles] for a task.

        Raises
        ------
        ValueError
            If the set has no such task, or if it is a pixel-density set (thresholds only).
        """
        if not self.gives_probabilities:
            raise ValueError(
                f"criterion {self.name!r} gives pixel-density thresholds, not probabilities: "
                "use it for ranges (dri_ranges), or choose a cycles criterion"
            )
        return self.threshold(task)

    def threshold(self, task: str) -> float:
        """The threshold for a task, in the set's own unit (see :attr:`kind`)."""
        if task not in self.thresholds:
            raise ValueError(
                f"criterion {self.name!r} has no task {task!r}; its tasks: {', '.join(self.tasks)}"
            )
        return float(self.thresholds[task])


def _johnson() -> dict[str, Criterion]:
    average = load_table("johnson_average")
    sets = {
        "johnson": Criterion(
            "johnson",
            dict(zip(average.column("task"), average.numbers("cycles"), strict=True)),
            source="Sonesson (2004) Table 3.2 (Johnson 1958 averages)",
        )
    }
    per_class = load_table("johnson_cycles")
    for i, slug in enumerate(per_class.column("target")):
        name = f"johnson-{slug}"
        label = per_class.column("label")[i]
        values = {task: per_class.numbers(task)[i] for task in TASKS}
        sets[name] = Criterion(name, values, source=f"Sonesson (2004) Table 3.1, {label}")
    return sets


def _c2nveo() -> Criterion:
    table = load_table("c2nveo")
    row = [float(p) for p in table.column("probability")].index(0.5)
    values = {
        task: math.sqrt(table.numbers(f"{task}_low")[row] * table.numbers(f"{task}_high")[row])
        for task in ("detection", "recognition", "identification")
    }
    return Criterion(
        "c2nveo", values, source="Sonesson (2004) Table 3.3, 50 % row, geometric mean of each cell"
    )


def _schmieder_weathersby() -> Criterion:
    table = load_table("schmieder_weathersby")
    row = [float(p) for p in table.column("probability")].index(0.5)
    return Criterion(
        "schmieder-weathersby",
        {"detection": table.numbers("medium")[row]},
        source="Sonesson (2004) Table 3.5, medium clutter, 50 % row",
    )


def _other_sets() -> dict[str, Criterion]:
    table = load_table("criteria_sets")
    grouped: dict[str, tuple[str, dict[str, float]]] = {}
    for name, kind, task, value in table.rows:
        grouped.setdefault(name, (kind, {}))[1][task] = float(value)
    return {
        name: Criterion(
            name,
            values,
            kind="pixel-density" if kind == "pixel-density" else "cycles",
            source="targetacq/data/criteria_sets.csv",
        )
        for name, (kind, values) in grouped.items()
    }


def _ttp_vehicles() -> Criterion:
    table = load_table("ttp_v50")
    return Criterion(
        "ttp-vehicles",
        dict(zip(table.column("task"), table.numbers("v50"), strict=True)),
        source="targetacq/data/ttp_v50.csv: V50s of the TTP metric for tactical vehicles "
        "(Vollmerhausen, Jacobs & Driggers, Opt. Eng. 43(11) 2004); use with the ttp resolution "
        "model and transform",
    )


@functools.cache
def _sets() -> dict[str, Criterion]:
    """The registry's own dict: the bundled sets, then those registered at run time."""
    sets = _johnson()
    sets["c2nveo"] = _c2nveo()
    sets["schmieder-weathersby"] = _schmieder_weathersby()
    sets.update(_other_sets())
    sets["ttp-vehicles"] = _ttp_vehicles()
    return sets


def _registry() -> Mapping[str, Criterion]:
    return MappingProxyType(_sets())


CRITERIA: Mapping[str, Criterion] = _registry()
"""All named criteria sets, by name (read-only; :func:`register_criterion` adds to it)."""

BUNDLED_CRITERIA: frozenset[str] = frozenset(CRITERIA)
"""The names of the bundled sets, which :func:`register_criterion` never replaces."""

_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]{0,63}$")


def register_criterion(criterion: Criterion, *, replace: bool = False) -> Criterion:
    """Add a criterion to :data:`CRITERIA` under its name, for the rest of this process.

    From then on the name is a criterion like the bundled ones: ``get_criterion(name)``, the
    ``criterion=`` of the probability functions, a scenario's ``[model] criterion`` (which needs
    N50s for detection, recognition and identification) and the command line's ``--criterion``
    run in this process (:func:`targetacq.cli.main`) take it.

    Parameters
    ----------
    criterion : Criterion
        Its ``name``: letters, digits, ``.``, ``_`` and ``-``, at most 64 characters, starting
        with a letter or digit.
    replace : bool
        Replace a criterion registered before under that name (never a bundled one).

    Returns
    -------
    Criterion
        ``criterion``.

    Raises
    ------
    ValueError
        A bundled name, a name registered before (without ``replace``), or a name that is not
        of the form above.

    Examples
    --------
    >>> import targetacq as ta
    >>> from targetacq.acquisition.criteria import register_criterion, unregister_criterion
    >>> mine = ta.Criterion("my-trials", {"detection": 0.9, "recognition": 3.1,
    ...                                   "identification": 6.0})
    >>> _ = register_criterion(mine)
    >>> ta.get_criterion("my-trials").n50("recognition")
    3.1
    >>> unregister_criterion("my-trials")
    >>> "my-trials" in ta.CRITERIA
    False
    """
    if not isinstance(criterion, Criterion):
        raise TypeError(f"criterion must be a Criterion, got {type(criterion).__name__}")
    name = criterion.name
    if not _NAME.match(name):
        raise ValueError(
            f"criterion name must be letters, digits, '.', '_' or '-' (at most 64, starting with "
            f"a letter or digit); got {name!r}"
        )
    if name in BUNDLED_CRITERIA:
        raise ValueError(f"criterion {name!r} is a bundled set and cannot be replaced")
    if name in CRITERIA and not replace:
        raise ValueError(
            f"criterion {name!r} is registered already; pass replace=True to replace it"
        )
    _sets()[name] = criterion
    return criterion


def unregister_criterion(name: str) -> None:
    """Take a criterion added by :func:`register_criterion` out of :data:`CRITERIA`.

    Raises
    ------
    ValueError
        A bundled name, or a name not registered.
    """
    if name in BUNDLED_CRITERIA:
        raise ValueError(f"criterion {name!r} is a bundled set and cannot be removed")
    if name not in CRITERIA:
        raise ValueError(f"no registered criterion {name!r}")
    del _sets()[name]


def get_criterion(criterion: str | Criterion | Mapping[str, float]) -> Criterion:
    """Resolve a criterion given by name, as a :class:`Criterion`, or as a task → N50 mapping.

    Parameters
    ----------
    criterion : str, Criterion or mapping
        A name from :data:`CRITERIA`; a :class:`Criterion`; or a user-defined mapping of tasks
        (from :data:`TASKS`) to N50 [cycles], e.g. ``{"detection": 1, "recognition": 4}``.

    Raises
    ------
    ValueError
        Unknown name (the message lists the valid ones), unknown task, or a threshold that is
        not a finite number > 0.

    Examples
    --------
    Johnson's averages (Table 3.2), a row of Table 3.1, and a set of one's own:

    >>> import targetacq as ta
    >>> dict(ta.get_criterion("johnson").thresholds)
    {'detection': 1.0, 'orientation': 1.4, 'recognition': 4.0, 'identification': 6.4}
    >>> ta.get_criterion("johnson-truck").n50("identification")
    8.0
    >>> ta.get_criterion({"detection": 0.75, "recognition": 3.0}).tasks
    ('detection', 'recognition')
    """
    if isinstance(criterion, Criterion):
        return criterion
    if isinstance(criterion, str):
        return lookup(CRITERIA, criterion, "criterion")
    if isinstance(criterion, Mapping):
        unknown = [task for task in criterion if task not in TASKS]
        if unknown:
            raise ValueError(
                f"criterion mapping has unknown task(s) {unknown}; valid tasks: {', '.join(TASKS)}"
            )
        return Criterion("user-defined", dict(criterion), source="user-defined")
    raise TypeError(
        f"criterion must be a name, a Criterion or a task → N50 mapping, got {type(criterion)}"
    )
