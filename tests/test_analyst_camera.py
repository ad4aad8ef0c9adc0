"""A camera entered as its datasheet gives it: pitch, focal length and pixels (issue: what an
analyst hits first, item 5)."""

from __future__ import annotations

import json
import math

import pytest

from targetacq.cli import main

CASE = ["--critical-dimension", "0.75m", "--band", "lwir", "--format", "json"]


def _dri(capsys, *args):
    with pytest.raises(SystemExit) as done:
        main(["dri", *args])
    out, err = capsys.readouterr()
    return done.value.code, out, err


def test_pitch_focal_length_and_pixels_are_accepted_and_give_the_field_of_view(capsys):
    code, out, err = _dri(
        capsys, "--pitch", "12um", "--focal-length", "100mm", "--pixels", "640", *CASE
    )
    assert code == 0, err
    report = json.loads(out)
    # Eq. (5.1): FOV = 2 atan(n p / (2 f)), 640 × 12 µm behind 100 mm.
    assert report["sensor"]["hfov_rad"] == pytest.approx(2 * math.atan(640 * 12e-6 / 0.2), 1e-12)
    assert report["sensor"]["pixels"] == 640
    # The IFOV is the pitch over the focal length: the same ranges as --ifov 0.12 mrad.
    assert report["sensor"]["ifov_rad"] == pytest.approx(12e-6 / 0.1, 1e-12)
    code, alone, _ = _dri(capsys, "--ifov", "0.12mrad", *CASE)
    assert code == 0
    assert [r["range_m"] for r in json.loads(alone)["ranges"]] == pytest.approx(
        [r["range_m"] for r in report["ranges"]], rel=1e-12
    )


def test_the_text_output_prints_the_field_of_view(capsys):
    code, out, err = _dri(
        capsys, "--pitch", "12um", "--focal-length", "100mm", "--pixels", "640",
        "--critical-dimension", "0.75m", "--band", "lwir",
    )  # fmt: skip
    assert code == 0, err
    degrees = math.degrees(2 * math.atan(640 * 12e-6 / 0.2))
    assert f"field of view {degrees:.4g}° × 640 pixels" in out


def test_pixels_without_a_lens_or_a_field_of_view_is_refused(capsys):
    code, _, err = _dri(capsys, "--pixels", "640", "--ifov", "0.1mrad", *CASE)
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
