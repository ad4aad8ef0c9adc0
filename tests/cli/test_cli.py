"""The `targetacq` command through its entry point."""

import itertools
import json
import math
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest


def test_dri_json_gives_range_m_per_task(cli):
    code, out, _ = cli(
        "dri",
        "--pitch",
        "17um",
        "--focal-length",
        "75mm",
        "--critical-dimension",
        "2.3m",
        "--format",
        "json",
    )
    assert code == 0
    report = json.loads(out)
    ranges = {row["task"]: row["range_m"] for row in report["ranges"]}
    ifov = 17e-6 / 75e-3
    assert ranges["detection"] == pytest.approx(2.3 / (1.0 * 2 * ifov))
    assert ranges["identification"] == pytest.approx(2.3 / (6.4 * 2 * ifov))


@pytest.mark.parametrize(
    "sensor",
    [
        ["--pitch", "17um", "--focal-length", "75mm"],
        ["--ifov", "0.22666667mrad"],
        [
            "--hfov",
            f"{math.degrees(2 * math.atan(640 * 17e-6 / 0.15)):.10f}deg",
            "--pixels",
            "640",
            "--projection",
            "rectilinear",
        ],
        ["--hfov", f"{math.degrees(640 * 17e-6 / 75e-3):.10f}deg", "--pixels", "640"],
    ],
)
def test_three_ways_to_give_the_sensor_agree(cli, sensor):
    code, out, _ = cli("dri", *sensor, "--critical-dimension", "2.3m", "--format", "json")
    assert code == 0
    assert json.loads(out)["ranges"][0]["range_m"] == pytest.approx(5073.53, rel=1e-6)


def test_datasheet_hfov_is_the_mean_angle_per_pixel(cli):
    # IFOV = 1.7453 rad / 640 = 2.727 mrad; detection at N = 0.75 cycles, 2 pixels a cycle:
    # R = 2.3 m / (0.75 · 2 · 2.727e-3) = 562.2 m.
    args = ["--hfov", "100deg", "--pixels", "640", "--n50", "0.75,3,6"]
    code, out, _ = cli("dri", *args, "--critical-dimension", "2.3m", "--format", "json")
    assert code == 0
    report = json.loads(out)
    ifov = math.radians(100) / 640
    assert report["sensor"]["ifov_rad"] == pytest.approx(ifov, rel=1e-15)
    assert report["ranges"][0]["range_m"] == pytest.approx(2.3 / (0.75 * 2 * ifov), rel=1e-9)
    assert round(report["ranges"][0]["range_m"]) == 562
    code, out, _ = cli("dri", *args, "--critical-dimension", "2.3m")
    assert "field of view 100° × 640 pixels (angular)" in out and "IFOV 2.727 mrad" in out


def test_f_number_gives_the_aperture(cli):
    base = ["dri", "--pitch", "12um", "--focal-length", "100mm", "--wavelength", "10um"]
    code, out, _ = cli(*base, "--f-number", "2", "--critical-dimension", "2.3m", "--format", "json")
    assert code == 0
    assert json.loads(out)["sensor"]["aperture_m"] == pytest.approx(0.05, rel=1e-15)
    code, _, err = cli(
        *base, "--f-number", "2", "--aperture", "50mm", "--critical-dimension", "2.3m"
    )
    assert code == 2 and "--aperture or --f-number" in err


def test_table_and_csv_formats(cli):
    code, out, _ = cli("dri", "--example")
    assert code == 0
    assert "detection" in out and "identification" in out and "range [m]" in out
    code, out, _ = cli("dri", "--example", "--format", "csv", "--probability", "0.5,0.8")
    lines = out.strip().splitlines()
    assert lines[0] == "task,probability,threshold,threshold_unit,range_m,reached"
    assert len(lines) == 1 + 2 * 4


def test_user_n50_and_transforms(cli):
    code, out, _ = cli(
        "dri",
        "--ifov",
        "0.2mrad",
        "--critical-dimension",
        "2m",
        "--n50",
        "1,4,8",
        "--format",
        "json",
    )
    assert code == 0
    ranges = {row["task"]: row["range_m"] for row in json.loads(out)["ranges"]}
    assert ranges["identification"] == pytest.approx(2 / (8 * 4e-4))
    code, out, _ = cli(
        "dri",
        "--ifov",
        "0.2mrad",
        "--critical-dimension",
        "2m",
        "--transform",
        "schmieder-weathersby",
        "--clutter",
        "high",
        "--probability",
        "0.95",
    )
    assert code == 0 and "not reached" in out


def test_en62676_4_ranges(cli):
    code, out, _ = cli(
        "dri",
        "--ifov",
        "0.2mrad",
        "--critical-dimension",
        "2m",
        "--criterion",
        "en62676-4",
        "--format",
        "json",
    )
    assert code == 0
    ranges = {row["task"]: row["range_m"] for row in json.loads(out)["ranges"]}
    assert ranges["identification"] == pytest.approx(1 / (250 * 2e-4))


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (
            ["--pitch", "17", "--focal-length", "75mm", "--critical-dimension", "2.3m"],
            "needs a unit",
        ),
        (["--pitch", "17um", "--focal-length", "75mm", "--critical-dimension", "-2m"], "> 0"),
        (["--pitch", "17um", "--critical-dimension", "2m"], "go together"),
        (
            ["--ifov", "0.2mrad", "--critical-dimension", "2m", "--criterion", "johnsen"],
            "--criterion must be one of",
        ),
        (
            ["--ifov", "0.2mrad", "--critical-dimension", "2m", "--transform", "x"],
            "--transform must be one of",
        ),
        (
            ["--ifov", "0.2mrad", "--critical-dimension", "2m", "--probability", "1.5"],
            "open interval",
        ),
        (
            ["--ifov", "0.2mrad", "--critical-dimension", "2m", "--format", "xml"],
            "--format must be one of",
        ),
        (["--ifov", "0.2mrad", "--critical-dimension", "2m", "--n50", "1,4"], "three numbers"),
        (
            [
                "--ifov",
                "0.2mrad",
                "--critical-dimension",
                "2m",
                "--bound",
                "best",
                "--transform",
                "c2nveo",
            ],
            "bound",
        ),
        (["--ifov", "0.2mrad"], "--critical-dimension is required"),
        (["--nope"], "No such option"),
    ],
)
def test_bad_input_is_one_line_on_stderr_and_exit_2(cli, args, match):
    code, out, err = cli("dri", *args)
    assert code == 2
    assert out == ""
    assert err.count("\n") == 1 and err.startswith("targetacq: error:")
    assert "Traceback" not in err
    assert re.search(match, err), err


def test_installed_entry_point_runs():
    exe = str(Path(sys.executable).with_name("targetacq"))
    if not Path(exe).exists():
        exe = shutil.which("targetacq") or exe
    done = subprocess.run([exe, "dri", "--example"], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    assert "identification" in done.stdout
    bad = subprocess.run([exe, "dri", "--pitch", "x"], capture_output=True, text=True, check=False)
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1


# --- signal and atmosphere options ---------------------------------------------------------------

# An LWIR target 10 K above its background, whose temperature spread is 2 K.
THERMAL = [
    "--band",
    "lwir",
    "--target-temperature",
    "305K",
    "--background-temperature",
    "295K",
    "--clutter-std",
    "2K",
]


def test_dri_with_temperatures_clutter_and_obscurant(cli):
    code, out, _ = cli(
        "dri",
        "--example",
        *THERMAL,
        "--obscurant",
        "haze:high",
        "--format",
        "json",
    )
    assert code == 0
    report = json.loads(out)
    assert report["path"]["extinction_np_per_km"] == pytest.approx(0.4)  # Table 7.1 haze, lwir
    assert report["path"]["term"] == "low"  # Table 7.2
    assert report["target"]["scr"] > 1
    ranges = {row["task"]: row["range_m"] for row in report["ranges"]}
    plain = json.loads(cli("dri", "--example", "--format", "json")[1])
    plain_ranges = {row["task"]: row["range_m"] for row in plain["ranges"]}
    assert ranges["detection"] < plain_ranges["detection"]


def test_dri_extinction_units_and_visibility(cli):
    a = json.loads(cli("dri", "--example", "--extinction", "0.2303/km", "--format", "json")[1])
    b = json.loads(cli("dri", "--example", "--extinction", "1dB/km", "--format", "json")[1])
    assert a["ranges"][0]["range_m"] == pytest.approx(b["ranges"][0]["range_m"], rel=1e-3)
    code, out, _ = cli(
        "dri",
        "--example",
        "--visibility",
        "5km",
        "--visibility-convention",
        "koschmieder",
        "--format",
        "json",
    )
    assert code == 0
    assert json.loads(out)["path"]["extinction_np_per_km"] == pytest.approx(3.912 / 5, abs=1e-3)


def test_atmosphere_command(cli):
    code, out, _ = cli(
        "atmosphere",
        "--range",
        "0m,1km",
        "--extinction",
        "0.693147/km",
        "--format",
        "json",
    )
    assert code == 0
    rows = json.loads(out)["rows"]
    assert rows[0]["transmittance"] == 1.0 and rows[0]["snr_db"] == "inf"  # τ(0) = 1, SNR +inf
    assert rows[1]["transmittance"] == pytest.approx(0.5, rel=1e-6)
    assert rows[1]["snr_db"] == pytest.approx(0.0, abs=1e-4)  # τ = 0.5 → 0 dB
    code, out, _ = cli("atmosphere", "--range", "2km", "--obscurant", "fog", "--band", "lwir")
    # The LWIR's fog, in words; Table 7.2's visual ranges are the visible band's, not printed.
    assert code == 0 and "moderate fog" in out and "foggy" not in out and "< 2 km" not in out


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (
            ["dri", "--example", "--obscurant", "smoke", "--band", "lwir"],
            "--obscurant must be one of",
        ),
        (["dri", "--example", "--obscurant", "fog"], "needs --band"),
        (["dri", "--example", "--visibility", "5km"], "needs --visibility-convention"),
        (
            ["dri", "--example", "--visibility", "5km", "--visibility-convention", "x"],
            "convention must be one of",
        ),
        (["dri", "--example", "--extinction", "-0.4/km"], "must be >= 0"),
        (["dri", "--example", "--extinction", "0.4"], "needs a unit"),
        (["dri", "--example", "--band", "12-8um"], "0 <= λ1 < λ2"),
        (["dri", "--example", "--band", "swir"], "--band must be one of"),
        (
            [
                "dri",
                "--example",
                "--band",
                "lwir",
                "--target-temperature",
                "-5K",
                "--background-temperature",
                "290K",
            ],
            r"--target-temperature must be in \(0, 10000\] K",
        ),
        (
            [
                "dri",
                "--example",
                "--band",
                "lwir",
                "--target-temperature",
                "300K",
                "--background-temperature",
                "290K",
                "--emissivity",
                "2",
            ],
            r"--emissivity must be in \[0, 1\]",
        ),
        (["dri", "--example", "--clutter-std", "2K"], "needs --target-temperature"),
        (
            ["dri", "--example", "--noise-model", "x", "--extinction", "1/km"],
            "--noise-model must be one of",
        ),
        (["atmosphere", "--range", "1km"], "give the path's extinction"),
        (["atmosphere", "--range", "-1km", "--extinction", "1/km"], "must be >= 0"),
    ],
)
def test_bad_signal_and_atmosphere_input(cli, args, match):
    code, _, err = cli(*args)
    assert code == 2
    assert err.count("\n") == 1
    assert re.search(match, err), err


# --- plots and report ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    "args",
    [
        ["plot", "curves", "--example", "--band", "lwir", "--obscurant", "haze"],
        ["plot", "transforms", "--criterion", "johnson-truck"],
        ["plot", "atmosphere", "--band", "mwir", "--max-range", "5km"],
    ],
)
def test_plot_writes_a_png(cli, tmp_path, args):
    out = tmp_path / "figure.png"
    code, text, _ = cli(*args, "--out", str(out))
    assert code == 0
    assert out.stat().st_size > 10_000
    assert str(out) in text


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (["plot", "bars", "--out", "x.png"], "plot kind must be one of curves, transforms"),
        (["plot", "curves", "--example", "--out", "/no/such/folder/x.png"], "does not exist"),
        (["plot", "curves", "--example", "--out", "x.gif"], r"\.png or \.svg"),
        (["plot", "transforms", "--pitch", "17um", "--out", "x.png"], "does not use --pitch"),
        (
            ["plot", "curves", "--example", "--probability", "1.2", "--out", "x.png"],
            "open interval",
        ),
        (["report", "--example", "--out", "/no/such/folder/r.html"], "does not exist"),
        (
            ["report", "--example", "--criterion", "en62676-4", "--out", "r.html"],
            "needs a criterion",
        ),
    ],
)
def test_bad_plot_and_report_input(cli, tmp_path, monkeypatch, args, match):
    monkeypatch.chdir(tmp_path)
    code, _, err = cli(*args)
    assert code == 2
    assert err.count("\n") == 1
    assert re.search(match, err), err


# --- clutter --------------------------------------------------------------------------------------

CAMERA = str(Path(__file__).parents[1] / "data" / "camera.png")


def test_clutter_command_json_and_overlay(cli, tmp_path):
    boxes = tmp_path / "boxes.csv"
    boxes.write_text("x,y,width,height\n228,470,24,24\n")
    overlay = tmp_path / "overlay.png"
    code, out, _ = cli(
        "clutter",
        CAMERA,
        "--box",
        "412,118,20,20",
        "--boxes",
        str(boxes),
        "--overlay",
        str(overlay),
        "--format",
        "json",
    )
    assert code == 0
    targets = json.loads(out)["targets"]
    assert [t["box"] for t in targets] == ["412,118,20,20", "228,470,24,24"]
    assert targets[0]["scr_negative"] > targets[1]["scr_negative"]
    assert targets[0]["cycles"] == 10.0  # box's smaller side / 2 pixels per cycle
    assert 0 <= targets[0]["p_detection"] <= 1
    assert overlay.stat().st_size > 1000


def test_clutter_probability_at_another_range(cli):
    near = json.loads(cli("clutter", CAMERA, "--box", "228,470,24,24", "--format", "json")[1])
    far = json.loads(
        cli(
            "clutter",
            CAMERA,
            "--box",
            "228,470,24,24",
            "--image-range",
            "1km",
            "--range",
            "12km",
            "--format",
            "json",
        )[1]
    )
    assert far["targets"][0]["cycles"] == pytest.approx(1.0)
    assert far["targets"][0]["p_detection"] < near["targets"][0]["p_detection"]


@pytest.mark.parametrize(
    ("args", "match"),
    [
        ([CAMERA, "--box", "600,1,2,2"], "leaves the 512 x 512 image"),
        ([CAMERA, "--box", "1,1,0,2"], "zero or negative size"),
        ([CAMERA, "--box", "1,1,2"], "x,y,width,height"),
        ([CAMERA], "at least one target"),
        (["/no/such.png", "--box", "1,1,2,2"], "no image file"),
        ([__file__, "--box", "1,1,2,2"], "cannot read"),
        ([CAMERA, "--box", "1,1,2,2", "--overlay", "/no/dir/o.png"], "does not exist"),
        ([CAMERA, "--box", "1,1,2,2", "--range", "3km"], "go together"),
    ],
)
def test_bad_clutter_input(cli, args, match):
    code, _, err = cli("clutter", *args)
    assert code == 2
    assert err.count("\n") == 1
    assert re.search(match, err), err


def test_colour_image_needs_channel_on_cli(cli, tmp_path):
    from PIL import Image

    rgb = tmp_path / "rgb.png"
    Image.fromarray(np.zeros((20, 20, 3), dtype=np.uint8)).save(rgb)
    code, _, err = cli("clutter", str(rgb), "--box", "5,5,4,4")
    assert code == 2
    assert "needs a channel" in err
    code, out, _ = cli("clutter", str(rgb), "--box", "5,5,4,4", "--channel", "luminance")
    assert "low" in out or "high" in out
    assert code == 0


# --- scenarios ---------------------------------------------------------------------------------

EXAMPLES = Path(__file__).parents[2] / "examples"


def test_evaluate_bundled_example_and_out(cli, tmp_path):
    code, out, _ = cli("evaluate")
    assert code == 0
    assert "UAV over vehicles in haze" in out
    assert "truck" in out and "jeep" in out
    target = tmp_path / "results.parquet"
    code, out, _ = cli("evaluate", str(EXAMPLES / "two_sensors_fused.toml"), "--out", str(target))
    assert code == 0
    import pandas as pd

    assert len(pd.read_parquet(target)) == 2 * 2 * 13


def test_simulate_and_validate(cli):
    code, out, _ = cli(
        "simulate",
        str(EXAMPLES / "two_sensors_fused.toml"),
        "--duration",
        "30s",
        "--step",
        "0.5s",
        "--seed",
        "7",
        "--runs",
        "200",
        "--format",
        "json",
    )
    assert code == 0
    rows = json.loads(out)["targets"]
    assert {r["task"] for r in rows} == {"detection", "recognition", "identification"}
    again = json.loads(
        cli(
            "simulate",
            str(EXAMPLES / "two_sensors_fused.toml"),
            "--duration",
            "30s",
            "--step",
            "0.5s",
            "--seed",
            "7",
            "--runs",
            "200",
            "--format",
            "json",
        )[1]
    )
    assert again["targets"] == rows
    code, out, _ = cli("validate", str(EXAMPLES / "uav_haze.toml"))
    assert code == 0 and "valid" in out


_SENSOR = '[[sensors]]\nname = "a"\nband = "lwir"\nposition = ["0 m","0 m","1 m"]\n'
_TARGET = '[[targets]]\nname = "t"\ndimensions = ["1 m","1 m","1 m"]\ntemperature = "300 K"\n'
_REST = 'position = ["1 km","0 m","0 m"]\n[background]\ntemperature = "290 K"\n'


@pytest.mark.parametrize(
    ("content", "match"),
    [
        ("[[sensors]\n", "malformed TOML"),
        (_SENSOR + "ifov = 0.2\n" + _TARGET + _REST, r"sensors\[0\]\.ifov: missing unit"),
        (
            _SENSOR + 'ifov = "0.2 mrad"\n' + _TARGET + "emisivity = 0.5\n" + _REST,
            r"targets\[0\]\.emisivity: unknown key 'emisivity' \(did you mean 'emissivity'\?\)",
        ),
        (
            _SENSOR + 'ifov = "0.2 mrad"\n' + _TARGET + "emissivity = 2\n" + _REST,
            r"targets\[0\]\.emissivity",
        ),
        (_SENSOR + 'ifov = "-0.2 mrad"\n' + _TARGET + _REST, "ifov must be > 0"),
    ],
)
def test_bad_scenario_files(cli, tmp_path, content, match):
    scenario = tmp_path / "scene.toml"
    scenario.write_text(content)
    out_file = tmp_path / "results.csv"
    for command in (
        ["validate", str(scenario)],
        ["evaluate", str(scenario), "--out", str(out_file)],
    ):
        code, out, err = cli(*command)
        assert code == 2
        assert out == ""
        assert err.count("\n") == 1
        assert re.search(match, err), err
    assert not out_file.exists()  # nothing half-written


def test_dri_scr_from_a_temperature_spread(cli):
    # SCR = |M(305 K) − M(295 K)| / (dM/dT · 2 K) in the LWIR band, Eq. (6.9), with dM/dT by a
    # central difference of the band exitance.
    from targetacq.physics.radiometry import band_exitance

    code, out, _ = cli(
        "dri",
        "--example",
        *THERMAL,
        "--format",
        "json",
    )
    assert code == 0
    target = json.loads(out)["target"]
    contrast = band_exitance(305.0, "lwir") - band_exitance(295.0, "lwir")
    slope = (band_exitance(295.001, "lwir") - band_exitance(294.999, "lwir")) / 0.002
    assert target["contrast_w_per_m2"] == pytest.approx(contrast, rel=1e-12)
    assert target["clutter_w_per_m2"] == pytest.approx(slope * 2.0, rel=1e-6)
    assert target["scr"] == pytest.approx(contrast / (slope * 2.0), rel=1e-6)


def _bench_curve(path):
    """The example bench curve read with the csv module: (cycles/rad, K) rows."""
    import csv

    lines = [line for line in path.read_text().splitlines() if not line.startswith("#")]
    rows = list(csv.DictReader(lines))
    return [(float(r["frequency"]) * 1e3, float(r["mrtd"])) for r in rows]


def _resolved_frequency(curve, delta_t):
    # ln MRTD linear in f between the points (the documented law); delta_t inside the table.
    for (f0, m0), (f1, m1) in itertools.pairwise(curve):
        if m0 <= delta_t <= m1:
            return f0 + (f1 - f0) * math.log(delta_t / m0) / math.log(m1 / m0)
    raise AssertionError("delta_t outside the tabulated MRTDs")


def test_mrtd_range_equals_an_independent_bisection(cli):
    """dri --mrtd: the range where N(R) = f*(τ(R)·ΔT)·d/R reaches N50 (P = 0.5 with TTPF),
    solved here by bisection on the bench CSV itself, to 0.1 %."""
    from pathlib import Path

    csv_path = Path(__file__).parents[2] / "src/targetacq/data/example_mrtd.csv"
    curve = _bench_curve(csv_path)
    d, delta_t, gamma, n50 = 2.3, 0.07, 1e-3, 1.0

    def cycles(r):
        return _resolved_frequency(curve, delta_t * math.exp(-gamma * r)) * d / r

    lo, hi = 200.0, 3000.0  # N(lo) > N50 > N(hi), τ·ΔT inside the table
    assert cycles(lo) > n50 > cycles(hi)
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if cycles(mid) >= n50 else (lo, mid)
    args = ["dri", "--ifov", "0.34mrad", "--critical-dimension", "2.3m", "--mrtd", str(csv_path)]
    args += ["--delta-t", "70mK", "--extinction", "1/km", "--noise-model", "none"]
    code, out, _ = cli(*args, "--format", "json")
    assert code == 0
    report = json.loads(out)
    assert report["resolution_model"] == "mrtd"
    assert report["ranges"][0]["range_m"] == pytest.approx(lo, rel=1e-3)


def test_zero_contrast_is_never_detected_with_a_netd(cli):
    code, out, _ = cli("dri", "--example", "--netd", "50mK", "--delta-t", "0K")
    assert code == 0 and out.count("not reached") == 4


def test_sensor_noise_needs_a_contrast(cli):
    code, _, err = cli("dri", "--example", "--netd", "50mK")
    assert code == 2 and "--delta-t" in err and "Traceback" not in err
    code, _, err = cli("dri", "--example", "--mrtd", "/no/such.csv", "--delta-t", "2K")
    assert code == 2 and "--mrtd" in err and "no such file" in err


def test_conditional_semantics_shortens_recognition(cli):
    ranges = {}
    for semantics in ("nested", "conditional"):
        code, out, _ = cli("dri", "--example", "--semantics", semantics, "--format", "json")
        assert code == 0
        ranges[semantics] = {r["task"]: r["range_m"] for r in json.loads(out)["ranges"]}
    assert ranges["conditional"]["detection"] == ranges["nested"]["detection"]
    assert ranges["conditional"]["recognition"] < ranges["nested"]["recognition"]


# --- plausibility warnings (targetacq.scenario.plausibility)
# ----------------------------------------------

_EXAMPLES = Path(__file__).resolve().parents[2] / "src" / "targetacq" / "examples"


@pytest.mark.parametrize(
    "command",
    [
        ["validate"],
        ["evaluate"],
        ["simulate", "--runs", "5", "--duration", "20s", "--step", "5s"],
        ["dri"],
        ["report", "--out", "{tmp}/report.html"],
    ],
    ids=lambda command: command[0],
)
def test_a_unit_slip_in_a_file_is_one_warning_line_and_exit_0(cli, tmp_path, command):
    text = (_EXAMPLES / "uav_haze.toml").read_text(encoding="utf-8")
    assert 'focal_length = "35 mm"' in text
    path = tmp_path / "slip.toml"
    path.write_text(text.replace('focal_length = "35 mm"', 'focal_length = "35 m"'))
    name, *options = (part.replace("{tmp}", str(tmp_path)) for part in command)
    code, out, err = cli(name, str(path), *options)
    assert code == 0
    assert out
    assert err.splitlines() == [
        f"targetacq: warning: {path}: sensors[0].focal_length: 35 m is 5 m or more; was it "
        'given in mm? (give "35 mm" or 0.035)'
    ]


def test_the_bundled_example_gives_no_warning(cli):
    code, _, err = cli("validate", str(_EXAMPLES / "uav_haze.toml"))
    assert (code, err) == (0, "")
