"""Named targets: the critical dimension of a person, a vehicle, ... by name.

The range of a task scales with the target's critical dimension ``d`` (``N = d / (R · cycle)``,
§3.5 and Fig. 3.3 of Sonesson (2004)), but the thesis gives no target sizes. DRI statements of
thermal cameras use a few conventional targets; :data:`TARGETS` holds them, read from the
bundled table ``targets.csv`` (its header names the sources), so that ``--target person`` gives
the critical dimension of the usual convention.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

from targetacq.base.tables import load_table

__all__ = ["TARGETS", "Target", "get_target"]


@dataclass(frozen=True)
class Target:
    """A named target.

    Attributes
    ----------
    name : str
        Its name (``--target NAME``).
    critical_dimension : float
        Critical dimension [m], the ``d`` of ``N = d / (R · cycle)``.
    height, width : float
        The outline it stands for [m].
    description : str
        What it is.
    source : str
        Where the dimensions come from (the provenance header of ``targets.csv``).
    """

    name: str
    critical_dimension: float
    height: float
    width: float
    description: str
    source: str


@functools.cache
def _registry() -> Mapping[str, Target]:
    table = load_table("targets")
    return MappingProxyType(
        {
            name: Target(name, d, h, w, description, table.provenance)
            for name, d, h, w, description in zip(
                table.column("name"),
                table.numbers("critical_dimension_m"),
                table.numbers("height_m"),
                table.numbers("width_m"),
                table.column("description"),
                strict=True,
            )
        }
    )


TARGETS: Mapping[str, Target] = _registry()
"""The named targets, by name (read-only): ``person`` (0.75 m) and ``vehicle`` (2.3 m)."""


def get_target(name: str) -> Target:
    """The named target ``name``.

    Parameters
    ----------
    name : str
        A key of :data:`TARGETS`.

    Returns
    -------
    Target

    Raises
    ------
    ValueError
        If ``name`` is not a named target; the message lists the names.

    Examples
    --------
    >>> get_target("person").critical_dimension
    0.75
    >>> get_target("tank")
    Traceback (most recent call last):
    ...
    ValueError: target must be one of person, vehicle; got 'tank'
    """
    if name not in TARGETS:
        raise ValueError(f"target must be one of {', '.join(TARGETS)}; got {name!r}")
    return TARGETS[name]
