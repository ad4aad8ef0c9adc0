"""The TTP section of the validation page."""

from __future__ import annotations

import csv
from importlib import resources

from targetacq.validation._ttp import ttp_section


def test_the_v50_rows_are_the_bundled_table_and_all_checks_agree():
    text = resources.files("targetacq").joinpath("data", "ttp_v50.csv").read_text("utf-8")
    rows = list(csv.DictReader(line for line in text.splitlines() if not line.startswith("#")))
    section = ttp_section()
    v50 = {c.item.split(",")[1].split("(")[0].strip(): c for c in section.checks[:3]}
    assert {row["task"]: float(row["v50"]) for row in rows} == {
        task: check.published for task, check in v50.items()
    }
    assert all(check.within for check in section.checks)
    assert "not" in section.notes and "worked example" in section.notes


def test_the_figure_draws():
    figure = ttp_section().figure
    assert figure is not None
    assert len(figure().axes) == 2
