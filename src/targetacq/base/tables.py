"""Literature tables shipped as CSV files in ``targetacq/data``.

Each file starts with ``#`` lines naming its source (publication, table, page) and any inference
or erratum; :func:`load_table` keeps that header as :attr:`Table.provenance` so it can be shown
next to results. Tables are read once and cached; they are small.
"""

from __future__ import annotations

import csv
import functools
import io
import math
from dataclasses import dataclass
from importlib import resources

__all__ = ["Table", "available_tables", "load_table"]


@dataclass(frozen=True)
class Table:
    """A literature table: its provenance header and its rows as text.

    Attributes
    ----------
    name : str
        File stem in ``targetacq/data``.
    provenance : str
        The ``#`` header of the file without the ``#`` marks: source, table, page, notes.
    columns : tuple of str
        Column names.
    rows : tuple of tuple of str
        Cell text, row by row; an empty cell means "not given" in the source.
    """

    name: str
    provenance: str
    columns: tuple[str, ...]
    rows: tuple[tuple[str, ...], ...]

    def column(self, name: str) -> tuple[str, ...]:
        """Cell text of one column, top to bottom."""
        if name not in self.columns:
            raise KeyError(f"table {self.name!r} has no column {name!r}; columns: {self.columns}")
        index = self.columns.index(name)
        return tuple(row[index] for row in self.rows)

    def keyed_ranges(
        self, keys: tuple[str, ...], low: str, high: str, scale: float = 1.0
    ) -> dict[tuple[str, ...], tuple[float, float]]:
        """Cells printed as ranges "low-high", by the text of the key columns, times ``scale``.

        An empty cell (not given in the source) becomes NaN.
        """
        key_columns = [self.column(k) for k in keys]
        return {
            tuple(parts): (lo * scale, hi * scale)
            for *parts, lo, hi in zip(
                *key_columns, self.numbers(low), self.numbers(high), strict=True
            )
        }

    def numbers(self, name: str) -> tuple[float, ...]:
        """One column as floats; an empty cell ("not given" in the source) becomes NaN."""
        return tuple(float(cell) if cell.strip() else math.nan for cell in self.column(name))


def available_tables() -> tuple[str, ...]:
    """Names of the bundled tables."""
    files = resources.files("targetacq").joinpath("data").iterdir()
    return tuple(sorted(f.name[:-4] for f in files if f.name.endswith(".csv")))


@functools.cache
def load_table(name: str) -> Table:
    """Read a bundled table by name (file stem), cached.

    Raises
    ------
    KeyError
        If no such table exists; the message lists the valid names.
    """
    if name not in available_tables():
        raise KeyError(f"no table {name!r}; available: {', '.join(available_tables())}")
    text = resources.files("targetacq").joinpath("data").joinpath(f"{name}.csv").read_text("utf-8")
    header = [line[1:].strip() for line in text.splitlines() if line.startswith("#")]
    body = "\n".join(line for line in text.splitlines() if line and not line.startswith("#"))
    reader = list(csv.reader(io.StringIO(body)))
    columns = tuple(reader[0])
    rows = tuple(tuple(row) for row in reader[1:])
    for row in rows:
        if len(row) != len(columns):
            raise ValueError(f"table {name!r}: row {row} does not match columns {columns}")
    return Table(name=name, provenance="\n".join(header), columns=columns, rows=rows)
