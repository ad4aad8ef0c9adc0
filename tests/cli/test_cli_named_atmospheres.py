"""Named atmospheres on the command line: `atmosphere`, and `dri` / `design` / `sweep` with
--atmosphere, --aerosol, --visibility for infrared bands (issue 25)."""

import json
import math

import pytest

from targetacq.physics import named_atmospheres as na

ISSUE_CASE = (
    "atmosphere",
    "--atmosphere",
    "tropical",
    "--aerosol",
    "rural",
    "--visibility",
    "23km",
    "--band",
    "8-12um",
    "--range",
    "5km",
)


def test_atmosphere_json_reports_band_transmittance_and_optical_depth(cli):
    code, out, err = cli(*ISSUE_CASE, "--format", "json")
    assert code == 0, err
    report = json.loads(out)
    (row,) = report["rows"]
    expected = float(na.named_band_transmittance(5e3, "lwir", "tropical", "rural", 23e3))
    assert row["transmittance"] == pytest.approx(expected, rel=1e-12)
    assert row["optical_depth"] == pytest.approx(-math.log(expected), rel=1e-12)
    assert report["path"]["model"] == "named"
    assert report["path"]["visibility_m"] == 23e3
    assert "LOWTRAN7" in report["path"]["source"]


def test_atmosphere_text_lists_each_range(cli):
    code, out, err = cli(*ISSUE_CASE[:-1], "1km,5km", "--path-altitude", "1km")
    assert code == 0, err
    assert "tropical atmosphere, rural aerosol, visibility 23 km" in out
    assert "horizontal path at 1000 m" in out
    assert "1,000" in out and "5,000" in out


def test_the_beer_lambert_path_reports_its_optical_depth_too(cli):
    code, out, _ = cli("atmosphere", "--range", "2km", "--extinction", "0.4/km", "--format", "json")
    assert code == 0
    assert json.loads(out)["rows"][0]["optical_depth"] == pytest.approx(0.8)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--atmosphere", "tropics"], "--atmosphere must be one of tropical, midlatitude-summer"),
        (["--aerosol", "smog"], "--aerosol must be one of none, rural, urban"),
        (
            ["--aerosol", "rural", "--visibility", "500m"],
            r"--visibility must be in \[2000, 50000\]",
        ),
        (["--aerosol", "fog", "--visibility", "5km"], r"--visibility must be in \[50, 1000\] m"),
        (["--aerosol", "none", "--visibility", "5km"], "--aerosol 'none' takes no visibility"),
        (["--atmosphere", "tropical", "--path-altitude", "9km"], r"--path-altitude must be in"),
        (["--atmosphere", "tropical", "--extinction", "1/km"], "--extinction do not go with"),
        (["--atmosphere", "tropical", "--visibility-convention", "mor"], "convention do not go"),
    ],
)
def test_bad_named_atmosphere_input_is_one_line_exit_2(cli, args, message):
    code, out, err = cli("atmosphere", "--range", "1km", "--band", "lwir", *args)
    assert code == 2 and not out
    assert err.count("\n") == 1 and err.startswith("targetacq: error: ")
    assert __import__("re").search(message, err), err


def test_a_named_atmosphere_needs_a_table_band(cli):
    code, _, err = cli("atmosphere", "--range", "1km", "--atmosphere", "tropical")
    assert code == 2 and "needs --band: visible, swir, mwir, lwir" in err
    code, _, err = cli(
        "atmosphere", "--range", "1km", "--atmosphere", "tropical", "--band", "3.5-4.5um"
    )
    assert code == 2 and "tabulated for the bands" in err


# --- range front-ends -----------------------------------------------------------------------

DRI = ("dri", "--pitch", "17um", "--focal-length", "75mm", "--critical-dimension", "2.3m")


def _ranges(out):
    return {row["task"]: row["range_m"] for row in json.loads(out)["ranges"]}


def test_dri_takes_a_named_atmosphere_for_an_infrared_band(cli):
    code, out, err = cli(*DRI, "--band", "lwir", "--atmosphere", "tropical", "--visibility", "23km",
                         "--format", "json")  # fmt: skip
    assert code == 0, err
    humid = _ranges(out)
    code, out, _ = cli(*DRI, "--band", "lwir", "--atmosphere", "subarctic-winter",
                       "--visibility", "23km", "--format", "json")  # fmt: skip
    dry = _ranges(out)
    code, out, _ = cli(*DRI, "--format", "json")
    clear = _ranges(out)
    for task in humid:  # water vapour shortens every range; dry air less so
        assert humid[task] < dry[task] < clear[task]
    assert (
        json.loads(cli(*DRI, "--band", "lwir", "--aerosol", "fog", "--format", "json")[1])["path"][
            "aerosol"
        ]
        == "fog"
    )


def test_dri_text_names_the_named_path(cli):
    code, out, err = cli(*DRI, "--band", "mwir", "--atmosphere", "midlatitude-summer")
    assert code == 0, err
    assert "path: midlatitude-summer atmosphere, rural aerosol, visibility 23 km" in out


def test_dri_refuses_mixing_named_and_beer_lambert(cli):
    code, _, err = cli(*DRI, "--band", "lwir", "--atmosphere", "tropical", "--obscurant", "haze")
    assert code == 2 and "--obscurant do not go with a named atmosphere" in err
    code, _, err = cli(*DRI, "--band", "lwir", "--visibility", "10km")
    assert code == 2 and "or a named atmosphere (--atmosphere, --aerosol)" in err


def test_design_and_sweep_take_a_named_atmosphere(cli):
    design = ("design", "--pitch", "17um", "--critical-dimension", "2.3m", "--range", "2km")
    code, out, err = cli(*design, "--band", "lwir", "--atmosphere", "tropical", "--format", "json")
    assert code == 0, err
    rows = json.loads(out)["rows"]
    clear = [r for r in rows if not r["weather"]]
    humid = [r for r in rows if r["weather"]]
    assert clear and humid
    assert all(h["focal_length_m"] > c["focal_length_m"] for h, c in zip(humid, clear, strict=True))
    code, out, err = cli(*("sweep", *DRI[1:]), "--band", "lwir", "--atmosphere",
                         "tropical,subarctic-winter", "--format", "json")  # fmt: skip
    assert code == 0, err
