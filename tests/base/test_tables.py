"""The bundled literature tables reproduce Sonesson (2004) at the printed values."""

import math

import pytest

from targetacq.base.tables import available_tables, load_table

# Table 3.1, Sonesson (2004) p. 18: target → (detection, orientation, recognition, identification)
TABLE_3_1 = {
    "Truck": (0.90, 1.25, 4.5, 8.0),
    "M-48 tank": (0.75, 1.2, 3.5, 7.0),
    "Stalin tank": (0.75, 1.2, 3.3, 6.0),
    "Centurion tank": (0.75, 1.2, 3.5, 6.0),
    "Half-track": (1.0, 1.5, 4.0, 5.0),
    "Jeep": (1.2, 1.5, 4.5, 5.5),
    "Command car": (1.2, 1.5, 4.5, 5.5),
    "Soldier (standing)": (1.5, 1.8, 3.8, 8.0),
    "105 howitzer": (1.0, 1.5, 4.8, 6.0),
}
TASKS = ("detection", "orientation", "recognition", "identification")


def test_every_table_has_a_provenance_header_naming_its_source():
    for name in available_tables():
        provenance = load_table(name).provenance
        assert provenance, name
        assert "Sonesson (2004)" in provenance or "Source" in provenance or "source" in provenance


def test_table_3_1_johnson_cycles():
    table = load_table("johnson_cycles")
    labels = table.column("label")
    assert set(labels) == set(TABLE_3_1)
    for i, label in enumerate(labels):
        assert tuple(table.numbers(task)[i] for task in TASKS) == TABLE_3_1[label]


def test_table_3_1_average_row_and_table_3_2():
    table = load_table("johnson_average")
    assert table.column("task") == TASKS
    assert table.numbers("cycles") == (1.0, 1.4, 4.0, 6.4)  # Tables 3.1 and 3.2
    assert table.numbers("spread_table_3_1") == (0.25, 0.35, 0.8, 1.5)  # Table 3.1 "±"
    assert table.numbers("spread_table_3_2") == (0.25, 0.35, 1.00, 1.60)  # Table 3.2 "±25 %"
    assert table.numbers("ratio_to_detection") == (1.0, 1.4, 4.0, 6.4)  # Table 3.2


def test_table_3_1_average_row_is_near_the_mean_of_the_rows():
    # A second transcription check, through the bundled file: the printed average row agrees
    # with the mean of the nine rows within 0.1 cycles (identification is the loosest: the
    # rows' mean is 6.33 against the printed 6.4).
    table = load_table("johnson_cycles")
    for task, average in zip(TASKS, (1.0, 1.4, 4.0, 6.4)):
        column = table.numbers(task)
        assert abs(sum(column) / len(column) - average) <= 0.1


def test_table_3_3_c2nveo():
    t = load_table("c2nveo")
    assert t.numbers("probability") == (1.00, 0.95, 0.80, 0.50, 0.30, 0.10, 0.02)
    assert t.numbers("detection_low") == (1.5, 1, 0.75, 0.5, 0.375, 0.25, 0.125)
    assert t.numbers("detection_high") == (3, 2, 1.5, 1, 0.75, 0.5, 0.25)
    assert t.numbers("recognition_low") == (9, 6, 4.5, 3, 2.25, 1.5, 0.75)
    assert t.numbers("recognition_high") == (12, 12, 6, 4, 3, 2, 1)  # "6-12" kept as printed
    assert t.numbers("identification_low") == (18, 12, 9, 6, 4.5, 3, 1.5)
    assert t.numbers("identification_high") == (24, 16, 12, 8, 6, 4, 2)


def test_table_3_4_observed_detection():
    t = load_table("schmieder_weathersby_observed")
    assert t.numbers("scr") == (0.33, 1.2, 5.8, 39)
    rows = {
        0.33: (math.nan, 0.00, 0.00, 0.32, 0.67, 0.77, 0.84),
        1.2: (math.nan, 0.04, 0.46, 0.96, 0.98, 1.0, 1.0),
        5.8: (math.nan, 0.38, 0.87, 0.95, 1.0, 1.0, 1.0),
        39: (0.93, 0.96, 1.0, 1.0, math.nan, math.nan, math.nan),
    }
    columns = [c for c in t.columns if c.startswith("n_")]
    assert [float(c[2:]) for c in columns] == [0.25, 0.5, 1.0, 2.0, 3.0, 4.0, 6.0]
    for i, scr in enumerate(t.numbers("scr")):
        got = tuple(t.numbers(c)[i] for c in columns)
        assert got == pytest.approx(rows[scr], nan_ok=True)


def test_table_3_5_schmieder_weathersby():
    t = load_table("schmieder_weathersby")
    assert t.numbers("probability") == (1.00, 0.95, 0.90, 0.80, 0.50, 0.30, 0.10, 0.02, 0.00)
    assert t.numbers("low") == (1.7, 1.0, 0.9, 0.75, 0.5, 0.3, 0.15, 0.05, 0.0)
    assert t.numbers("medium") == (2.8, 1.9, 1.7, 1.3, 1.0, 0.75, 0.35, 0.1, 0.0)
    high = t.numbers("high")
    assert math.isnan(high[0]) and math.isnan(high[1])  # "-": never reached
    assert high[2:] == (7.0, 5.0, 2.5, 2.0, 1.4, 1.0, 0.0)


def test_unknown_table_lists_the_valid_names():
    with pytest.raises(KeyError, match=r"available: .*c2nveo"):
        load_table("nope")
