"""Named targets: the registry, its table, and ``--target`` in range_setup and the CLI."""

from __future__ import annotations

import json

import pytest

from targetacq.base.tables import load_table
from targetacq.cli import main
from targetacq.physics.targets import TARGETS, get_target
from targetacq.run.option_table import RANGE_CASE_OPTIONS


def _run(capsys, *argv):
    with pytest.raises(SystemExit) as exit_info:
        main(list(argv))
    out, err = capsys.readouterr()
    return exit_info.value.code, out, err


def test_registry_holds_the_conventional_targets():
    # Hikvision / FLIR thermal-camera convention: person 1.8 m x 0.5 m, critical dimension
    # 0.75 m; NATO standard target 2.3 m x 2.3 m.
    person, vehicle = get_target("person"), get_target("vehicle")
    assert (person.critical_dimension, person.height, person.width) == (0.75, 1.8, 0.5)
    assert (vehicle.critical_dimension, vehicle.height, vehicle.width) == (2.3, 2.3, 2.3)
    for target in TARGETS.values():
        assert "Sources" in target.source and target.description


def test_table_has_provenance_and_every_row_in_the_registry():
    table = load_table("targets")
    assert "Hikvision" in table.provenance and "NATO" in table.provenance
    assert set(table.column("name")) == set(TARGETS)


def test_registry_is_read_only_and_unknown_name_lists_the_names():
    with pytest.raises(TypeError):
        TARGETS["tank"] = TARGETS["person"]  # type: ignore[index]
    with pytest.raises(ValueError, match="person, vehicle"):
        get_target("tank")


def test_option_help_lists_the_registry_names():
    (spec,) = [s for s in RANGE_CASE_OPTIONS if s.name == "target"]
    assert all(name in spec.help for name in TARGETS)


def _dri_json(capsys, *argv):
    code, out, err = _run(capsys, "dri", "--format", "json", *argv)
    assert code == 0, err
    return json.loads(out)


def test_target_sets_the_critical_dimension(capsys):
    report = _dri_json(capsys, "--target", "person", "--pitch", "12um", "--focal-length", "128mm")
    assert report["target"]["critical_dimension_m"] == 0.75
    # Closed form: R = d / (N50 · 2 · IFOV) = 0.75 / (4 · 2 · 12e-6 / 0.128) = 1000 m.
    (rec,) = [row for row in report["ranges"] if row["task"] == "recognition"]
    assert rec["range_m"] == pytest.approx(1000.0, rel=1e-12)
    same = _dri_json(
        capsys, "--critical-dimension", "0.75m", "--pitch", "12um", "--focal-length", "128mm"
    )
    assert same["ranges"] == report["ranges"]


def test_example_keeps_its_target_unless_target_is_given(capsys):
    own = _dri_json(capsys, "--example")
    assert own["target"]["critical_dimension_m"] == 2.3
    person = _dri_json(capsys, "--example", "--target", "person")
    assert person["target"]["critical_dimension_m"] == 0.75
    assert person["sensor"] == own["sensor"]


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--target", "tank"], "--target must be one of person, vehicle"),
        (["--target", "person", "--critical-dimension", "1m"], "not both"),
    ],
)
def test_bad_target_is_one_line_exit_2(capsys, argv, message):
    code, out, err = _run(capsys, "dri", "--ifov", "0.1mrad", *argv)
    assert code == 2 and out == ""
    assert err.startswith("targetacq: error: ") and message in err
    assert err.count("\n") == 1
