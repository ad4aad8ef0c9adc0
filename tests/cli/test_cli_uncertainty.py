"""``targetacq dri --uncertainty``: 5–95 % bands in JSON, CSV and the table; one-line errors."""

from __future__ import annotations

import json

import pytest

CAMERA = ["--ifov", "0.2mrad", "--critical-dimension", "2.3m"]  # detection at P=0.5: 5,750 m
HAZE = [*CAMERA, "--extinction", "0.4/km", "--netd", "50mK", "--delta-t", "2K"]


def _json(cli, *args):
    code, out, err = cli("dri", *args, "--format", "json")
    assert code in (0, None), err
    return json.loads(out)


def test_json_rows_carry_a_band_that_contains_the_nominal_range(cli):
    report = _json(cli, *HAZE, "--uncertainty", "200", "--extinction-spread", "20%",
                   "--netd-spread", "10%", "--probability", "0.5,0.8")  # fmt: skip
    assert report["uncertainty"]["samples"] == 200
    assert report["uncertainty"]["spreads"] == {
        "n50": 0.25, "observer": 0.0, "netd": 0.1, "extinction": 0.2,
    }  # fmt: skip
    assert len(report["ranges"]) == 8
    for row in report["ranges"]:
        assert row["range_p05_m"] < row["range_m"] < row["range_p95_m"], row


def test_closed_form_band_and_nominal(cli):
    report = _json(cli, *CAMERA, "--uncertainty", "400")
    (det,) = [row for row in report["ranges"] if row["task"] == "detection"]
    assert det["range_m"] == pytest.approx(5750.0)  # d / (N50 · 2 IFOV), Johnson's N50 = 1
    # R0 · exp(∓1.645 σ), σ = sqrt(ln 1.0625): about 3,830 m and 8,620 m
    assert det["range_p05_m"] == pytest.approx(3834.0, rel=0.06)
    assert det["range_p95_m"] == pytest.approx(8622.0, rel=0.06)


def test_same_seed_same_output_other_seed_other_band(cli):
    first = _json(cli, *CAMERA, "--uncertainty", "100", "--seed", "4")
    again = _json(cli, *CAMERA, "--uncertainty", "100", "--seed", "4")
    other = _json(cli, *CAMERA, "--uncertainty", "100", "--seed", "5")
    assert first == again
    assert first["ranges"][0]["range_p95_m"] != other["ranges"][0]["range_p95_m"]


def test_table_and_csv_show_the_band(cli):
    code, out, _ = cli("dri", *CAMERA, "--uncertainty", "100")
    assert code in (0, None)
    assert "5 % [m]" in out and "95 % [m]" in out and "100 samples (seed 0)" in out
    code, out, _ = cli("dri", *CAMERA, "--uncertainty", "100", "--format", "csv")
    assert "range_p05_m" in out.splitlines()[0] and "range_p95_m" in out.splitlines()[0]


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--uncertainty", "5"], "--uncertainty must be a whole number of samples in [20, 100000]"),
        (["--uncertainty", "abc"], "--uncertainty must be a whole number"),
        (["--uncertainty", "100", "--netd-spread", "nan%"], "--netd-spread must be a percentage"),
        (["--uncertainty", "100", "--n50-spread", "0.25"], "--n50-spread must be a percentage"),
        (["--uncertainty", "100", "--observer-spread", "150%"], "from 0% to 100%"),
        (["--uncertainty", "100", "--seed", "-1"], "--seed must be an integer"),
        (["--seed", "3"], "--seed go with --uncertainty"),
        (["--extinction-spread", "20%"], "--extinction-spread go with --uncertainty"),
        (["--uncertainty", "100", "--netd-spread", "10%"], "--netd-spread) needs"),
        (["--uncertainty", "100", "--extinction-spread", "10%"], "--extinction-spread) needs"),
        (["--uncertainty", "100", "--scr", "2,3"], "not a scenario file or lists"),
    ],
)
def test_errors_are_one_line_on_stderr_exit_2(cli, args, words):
    code, out, err = cli("dri", *CAMERA, *args)
    assert code == 2
    assert out == ""
    assert len(err.strip().splitlines()) == 1 and words in err, err


def test_scenario_file_is_refused(cli):
    code, _, err = cli("dri", "examples/two_sensors_fused.toml", "--uncertainty", "100")
    assert code == 2 and "not a scenario file or lists" in err
