"""A camera entered as its datasheet gives it: pitch, focal length and pixels (issue: what an
analyst hits first, item 5)."""

from __future__ import annotations

import json
import math

import pytest

from targetacq.cli import main

CASE = ["--critical-dimension", "0.75m", "--band", "lwir", "--format", "json"]


def test_pitch_focal_length_and_pixels_are_accepted_and_give_the_field_of_view(cli):
    code, out, err = cli(
        "dri", "--pitch", "12um", "--focal-length", "100mm", "--pixels", "640", *CASE
    )
    assert code == 0, err
    report = json.loads(out)
    # Eq. (5.1): FOV = 2 atan(n p / (2 f)), 640 × 12 µm behind 100 mm.
    assert report["sensor"]["hfov_rad"] == pytest.approx(2 * math.atan(640 * 12e-6 / 0.2), 1e-12)
    assert report["sensor"]["pixels"] == 640
    # The IFOV is the pitch over the focal length: the same ranges as --ifov 0.12 mrad.
    assert report["sensor"]["ifov_rad"] == pytest.approx(12e-6 / 0.1, 1e-12)
    code, alone, _ = cli("dri", "--ifov", "0.12mrad", *CASE)
    assert code == 0
    assert [r["range_m"] for r in json.loads(alone)["ranges"]] == pytest.approx(
        [r["range_m"] for r in report["ranges"]], rel=1e-12
    )


def test_the_text_output_prints_the_field_of_view(cli):
    code, out, err = cli("dri", "--pitch", "12um", "--focal-length", "100mm", "--pixels", "640",
        "--critical-dimension", "0.75m", "--band", "lwir",
    )  # fmt: skip
    assert code == 0, err
    degrees = math.degrees(2 * math.atan(640 * 12e-6 / 0.2))
    assert f"field of view {degrees:.4g}° × 640 pixels" in out


def test_pixels_without_a_lens_or_a_field_of_view_is_refused(cli):
    code, _, err = cli("dri", "--pixels", "640", "--ifov", "0.1mrad", *CASE)
    assert code == 2
    assert "resolution one way" in err and len(err.strip().splitlines()) == 1


def test_design_with_pixels_gives_each_design_its_field_of_view(capsys):
    with pytest.raises(SystemExit) as done:
        main(["design", "--task", "recognition", "--range", "1km", "--target", "person",
              "--pitch", "12um", "--pixels", "640", "--band", "lwir",
              "--format", "json"])  # fmt: skip
    out, err = capsys.readouterr()
    assert done.value.code == 0, err
    report = json.loads(out)
    (row,) = report["rows"]
    # The field of view of the designed lens, Eq. (5.1): 2 atan(640 · 12 µm / (2 f)).
    expected = 2 * math.atan(640 * 12e-6 / (2 * row["focal_length_m"]))
    assert row["hfov_rad"] == pytest.approx(expected, rel=1e-12)
    assert report["pixels"] == 640
    with pytest.raises(SystemExit):
        main(["design", "--task", "recognition", "--range", "1km", "--target", "person",
              "--pitch", "12um", "--pixels", "640", "--band", "lwir"])  # fmt: skip
    out, _ = capsys.readouterr()
    assert "FOV [deg]" in out and f"{math.degrees(expected):.4g}" in out


@pytest.mark.parametrize(
    "sensor",
    [
        ["--hfov", "10deg", "--pixels", "640"],
        ["--pitch", "12um", "--focal-length", "100mm", "--pixels", "640"],
    ],
    ids=["hfov", "datasheet"],
)
def test_the_report_of_a_camera_with_pixels_shows_its_field_of_view(sensor, tmp_path, capsys):
    out = tmp_path / "r.html"
    with pytest.raises(SystemExit) as done:
        main(["report", *sensor, "--critical-dimension", "0.75m", "--band", "lwir",
              "--out", str(out)])  # fmt: skip
    assert done.value.code == 0, capsys.readouterr().err
    fov = 10.0 if "--hfov" in sensor else math.degrees(2 * math.atan(640 * 12e-6 / 0.2))
    assert f"HFOV {fov:.4g}° over 640 pixels" in out.read_text()


def _report(tmp_path, *args):
    out = tmp_path / "r.html"
    with pytest.raises(SystemExit) as done:
        main(["report", *args, "--out", str(out)])
    assert done.value.code == 0
    return out.read_text()


PERSON = [
    *("--pitch", "12um", "--focal-length", "100mm", "--pixels", "640", "--target", "person"),
    *("--band", "lwir", "--target-temperature", "305K", "--background-temperature", "295K"),
]


def test_the_range_chart_covers_the_answers_and_marks_the_requirement(tmp_path, capsys):
    import re

    with pytest.raises(SystemExit):
        main(["dri", *PERSON, "--probability", "0.5,0.8,0.95", "--format", "json"])
    rows = json.loads(capsys.readouterr().out)["ranges"]
    farthest = max(r["range_m"] for r in rows if r["reached"] and math.isfinite(r["range_m"]))
    page = _report(tmp_path, *PERSON, "--requirement", "1km,0.8")
    stops = [float(v) for v in re.findall(r"The curves stop at ([0-9.]+) km", page)]
    # The whole chart: every DRI range on it, its end within 30 % beyond the farthest (not the
    # range where every probability has faded, tens of kilometres out).
    assert farthest / 1e3 < stops[0] <= 1.3 * farthest / 1e3
    # The chart zoomed on the requirement: out to twice its range.
    assert stops[1] == pytest.approx(2.0)
    assert "Range performance near the requirement" in page
    assert "the requirement, P ≥ 0.8 at 1,000 m" in page


def test_the_requirement_is_drawn_on_the_chart():
    from targetacq.core.cases import RangeCase
    from targetacq.core.ranges import range_performance
    from targetacq.reports.plots import plot_range_performance

    perf = range_performance([500.0, 5000.0], {"c": RangeCase(2.3, 2e-4)}, [0.5])
    ax = plot_range_performance(perf, requirement=(1500.0, 0.8)).axes[0]
    vertical = [line for line in ax.get_lines() if list(line.get_xdata()) == [1.5, 1.5]]
    stars = [line for line in ax.get_lines() if line.get_marker() == "*"]
    assert vertical and [(s.get_xdata()[0], s.get_ydata()[0]) for s in stars] == [(1.5, 0.8)]


@pytest.mark.parametrize("bad", ["1km,1.5", "0m", "1km,0.8,3", "fast"])
def test_a_bad_requirement_is_one_line(bad, tmp_path, capsys):
    with pytest.raises(SystemExit) as done:
        main(["report", *PERSON, "--requirement", bad, "--out", str(tmp_path / "r.html")])
    err = capsys.readouterr().err
    assert done.value.code == 2 and "--requirement" in err and len(err.strip().splitlines()) == 1


def test_cases_that_differ_get_a_column_each(tmp_path):
    page = _report(tmp_path, "--example", "--critical-dimension", "0.75m,2.3m,5m")
    header = "<th>critical dimension 0.75 m</th><th>critical dimension 2.3 m</th><th>critical"
    assert header in page
    assert "<td>0.75 m (smallest side seen, §3.2)</td><td>2.3 m (smallest side seen" in page
    # No cell strings several cases' values together.
    assert "critical dimension 0.75 m:" not in page and "; critical dimension 2.3 m" not in page
    lenses = _report(
        tmp_path, "--pitch", "12um", "--focal-length", "50mm,100mm,150mm",
        "--critical-dimension", "2.3m",
    )  # fmt: skip
    # In a section where some items differ, the shared ones span the case columns.
    assert "<td>pixel pitch</td><td colspan='3'>12 µm</td>" in lenses


def test_light_fog_for_a_thermal_camera_is_not_described_as_clear_to_hazy(capsys):
    """fog:low in the LWIR (0.4 Np/km) is light fog; Table 7.2's visual range for 0.4 Np/km
    ("6 - 30 km, clear to hazy") describes the visible band and is not printed for the LWIR."""
    with pytest.raises(SystemExit):
        main(["dri", "--example", "--obscurant", "fog:low", "--band", "lwir"])
    out = capsys.readouterr().out
    assert "light fog" in out and "clear to hazy" not in out
    with pytest.raises(SystemExit):
        main(["dri", "--example", "--obscurant", "fog:low", "--band", "lwir", "--format", "json"])
    path = json.loads(capsys.readouterr().out)["path"]
    assert path["visual_range"] is None and "light fog" in path["description"]
    with pytest.raises(SystemExit):
        main(["dri", "--pitch", "5um", "--focal-length", "50mm", "--critical-dimension", "2.3m",
              "--obscurant", "haze:high", "--band", "visible"])  # fmt: skip
    out = capsys.readouterr().out
    assert "dense haze" in out and "visual range < 2 km, foggy" in out  # Table 7.2 at 2 Np/km


def test_the_obscurant_option_says_what_its_levels_mean(capsys):
    with pytest.raises(SystemExit):
        main(["dri", "--help"])
    help_text = " ".join(capsys.readouterr().out.split())
    assert "low = light" in help_text.replace("│ ", "").replace(" │", "")


ZERO_CONTRAST = [
    *("--pitch", "17um", "--focal-length", "75mm", "--critical-dimension", "2.3m"),
    *("--band", "lwir", "--target-temperature", "295K", "--background-temperature", "295K"),
]


def test_a_zero_contrast_answered_geometrically_warns(cli):
    code, out, err = cli("dri", *ZERO_CONTRAST)
    assert code == 0 and out
    warning = [line for line in err.splitlines() if "warning" in line]
    assert len(warning) == 1 and "geometric ones" in warning[0] and "--netd" in warning[0]
    code, _, err = cli("dri", *ZERO_CONTRAST, "--netd", "50mK")
    assert code == 0 and "warning" not in err  # with the noise, contrast counts: no warning


def test_pixel_density_criteria_need_no_critical_dimension(cli):
    code, out, err = cli(
        "dri", "--pitch", "3um", "--focal-length", "8mm", "--criterion", "en62676-4",
        "--format", "json",
    )  # fmt: skip
    assert code == 0, err
    report = json.loads(out)
    assert report["target"]["critical_dimension_m"] is None
    ifov = 3e-6 / 8e-3
    # EN 62676-4:2015, identification at 250 pixels per metre: R = 1 / (250 · IFOV).
    row = next(r for r in report["ranges"] if r["task"] == "identification")
    assert row["range_m"] == pytest.approx(1.0 / (250.0 * ifov), rel=1e-9)


def test_the_2025_edition_levels_are_there():
    from targetacq.acquisition.criteria import CRITERIA

    levels = CRITERIA["iec62676-4-2025"]
    # IEC/EN 62676-4:2025 as tabulated by JVSG (2026): O/O/D 20/40/80, P/C/V/S 125/250/500/1500.
    assert levels.thresholds == {
        "overview": 20.0, "outline": 40.0, "discern": 80.0, "perceive": 125.0,
        "characterise": 250.0, "validate": 500.0, "scrutinise": 1500.0,
    }  # fmt: skip
    assert not levels.gives_probabilities


def test_provenance_names_the_scenario_file_without_the_local_folders(tmp_path, capsys):
    import shutil
    from pathlib import Path

    folder = tmp_path / "private" / "project"
    folder.mkdir(parents=True)
    scenario = folder / "mine.toml"
    shutil.copy(Path(__file__).parents[2] / "examples" / "uav_haze.toml", scenario)
    out = tmp_path / "e.json"
    with pytest.raises(SystemExit) as done:
        main(["evaluate", str(scenario), "--out", str(out)])
    assert done.value.code == 0, capsys.readouterr().err
    text = out.read_text()
    assert json.loads(text)["meta"]["scenario_file"] == "mine.toml"
    assert "private" not in text and str(tmp_path) not in text


def test_simulate_prints_one_number_format_per_column(capsys):
    import re

    with pytest.raises(SystemExit) as done:
        main(["simulate", "examples/two_sensors_fused.toml", "--runs", "50", "--seed", "1"])
    assert done.value.code == 0
    lines = capsys.readouterr().out.splitlines()
    rows = [line.split() for line in lines if "tion " in line and not line.startswith("target")]
    assert len(rows) == 6
    for column in (3, 4, 5):  # t10, t50, t90: every finite time with the same decimals
        decimals = {
            len(v.split(".")[1]) for row in rows if re.fullmatch(r"[0-9.]+", v := row[column])
        }
        assert len(decimals) <= 1, (column, decimals)
    assert any(re.fullmatch(r"[0-9]+\.[0-9]+", row[3]) for row in rows)


def test_sweep_with_out_writes_the_rows_to_the_file_not_to_stdout(tmp_path, capsys):
    out = tmp_path / "s.csv"
    with pytest.raises(SystemExit) as done:
        main(["sweep", "--example", "--focal-length", "50mm,75mm,100mm", "--out", str(out)])
    assert done.value.code == 0
    printed = capsys.readouterr().out.splitlines()
    # 3 focal lengths × the criterion's tasks × 1 probability, said in one line.
    rows = [line for line in out.read_text().splitlines() if not line.startswith("#")][1:]
    assert printed == [f"{len(rows)} points (focal_length × task × probability)", f"wrote {out}"]


def test_csv_outputs_carry_units_and_provenance(tmp_path, capsys):
    import pandas as pd

    out = tmp_path / "e.csv"
    with pytest.raises(SystemExit) as done:
        main(["evaluate", "examples/uav_haze.toml", "--out", str(out)])
    assert done.value.code == 0, capsys.readouterr().err
    first, second, *_ = out.read_text().splitlines()
    assert first.startswith("# units: sensor, target, time [s], range [m]") and "snr [dB]" in first
    meta = json.loads(second.removeprefix("# provenance: "))
    assert meta["software"] == "targetacq" and meta["scenario_file"] == "uav_haze.toml"
    frame = pd.read_csv(out, comment="#")
    assert list(frame.columns[:4]) == ["sensor", "target", "time", "range"]
