"""Bad input to `dri`, `atmosphere`, `plot`, `report` and `clutter`: one located line, exit 2.

Every case goes through the command's entry point and asserts the user's contract: exit status
2, exactly one line on stderr, starting ``targetacq: error:``, naming the option (or file) at
fault, and no traceback. Valid edge cases (zero range, zero extinction, a byte-order mark) run
without a warning and print strict JSON.
"""

import contextlib
import io
import json
import math
import warnings
from pathlib import Path

import pytest

from targetacq.base.inputs import read_input_text
from targetacq.base.limits import MAX_INPUT_BYTES
from targetacq.cli import app
from targetacq.physics.mrtd import MrtdCurve

SENSOR = ["--pitch", "17um", "--focal-length", "75mm", "--critical-dimension", "2.3m"]
FIELD_OF_VIEW = ["--hfov", "12deg", "--pixels", "640", "--critical-dimension", "2m"]
THERMAL = ["--band", "lwir", "--target-temperature", "300K", "--background-temperature", "290K"]
CAMERA = str(Path(__file__).parents[1] / "data" / "camera.png")  # a 512 x 512 grayscale image
EXAMPLE_MRTD = str(Path(__file__).parents[2] / "src/targetacq/data/example_mrtd.csv")


def assert_refused(cli, args, *named):
    """The command exits 2 with one stderr line naming each of ``named``, no traceback."""
    code, out, err = cli(*args)
    assert code == 2, (args, out, err)
    assert err.startswith("targetacq: error: "), err
    assert err.count("\n") == 1 and err.endswith("\n"), err
    assert "Traceback" not in err
    for name in named:
        assert name in err, (name, err)
    return err


# --- dri: each option finite and in its domain ---------------------------------------------------

OVERFLOW = "(the number overflows)"

DRI_DOMAIN = [
    # the issue's own examples
    (["--pitch", "1e400um", "--focal-length", "75mm", "--critical-dimension", "2m"], "--pitch"),
    ([*SENSOR, "--extinction", "1e400/km"], "--extinction"),
    (["--pitch", "17um", "--focal-length", "1e400mm", "--critical-dimension", "2m"], "--focal"),
    (["--pitch", "17um", "--focal-length", "75mm", "--critical-dimension", "1e999m"], "--critical"),
    # NaN and infinity spelled out
    (["--pitch", "nan um", "--focal-length", "75mm", "--critical-dimension", "2m"], "--pitch"),
    (["--pitch", "inf um", "--focal-length", "75mm", "--critical-dimension", "2m"], "--pitch"),
    ([*SENSOR[:4], "--critical-dimension", "-inf m"], "--critical-dimension"),
    # lengths > 0
    (["--pitch", "-17um", "--focal-length", "75mm", "--critical-dimension", "2m"], "--pitch"),
    (["--pitch", "0um", "--focal-length", "75mm", "--critical-dimension", "2m"], "--pitch"),
    (["--pitch", "17um", "--focal-length", "0mm", "--critical-dimension", "2m"], "--focal-length"),
    ([*SENSOR[:4], "--critical-dimension", "0m"], "--critical-dimension"),
    ([*SENSOR, "--aperture", "-1mm", "--wavelength", "10um"], "--aperture"),
    ([*SENSOR, "--aperture", "50mm", "--wavelength", "0um"], "--wavelength"),
    ([*SENSOR, "--aperture", "1e400mm", "--wavelength", "10um"], "--aperture"),
    # lengths within ±1e9 m (limits.MAX_LENGTH)
    (["--pitch", "1e12m", "--focal-length", "75mm", "--critical-dimension", "2m"], "--pitch"),
    (["--pitch", "17um", "--focal-length", "1e300m", "--critical-dimension", "2m"], "±1e+09 m"),
    ([*SENSOR[:4], "--critical-dimension", "1000001km"], "--critical-dimension"),
    ([*SENSOR, "--aperture", "1e10m", "--wavelength", "10um"], "--aperture"),
    ([*SENSOR, "--aperture", "50mm", "--wavelength", "2e9m"], "--wavelength"),
    # the IFOV that pitch over focal length gives underflows to zero
    (["--pitch", "1e-320m", "--focal-length", "1e9m", "--critical-dimension", "2m"], "IFOV"),
    # angles
    (["--ifov", "0mrad", "--critical-dimension", "2m"], "--ifov"),
    (["--ifov", "200deg", "--critical-dimension", "2m"], "--ifov"),
    (["--ifov", "1e400mrad", "--critical-dimension", "2m"], "--ifov"),
    (["--hfov", "180deg", "--pixels", "640", "--critical-dimension", "2m"], "--hfov"),
    (["--hfov", "720deg", "--pixels", "640", "--critical-dimension", "2m"], "--hfov"),
    (["--hfov", "-12deg", "--pixels", "640", "--critical-dimension", "2m"], "--hfov"),
    (["--hfov", "0deg", "--pixels", "640", "--critical-dimension", "2m"], "--hfov"),
    ([*SENSOR, "--blur", "-1mrad"], "--blur"),
    ([*SENSOR, "--blur", "400deg"], "--blur"),
    # pixels: whole and positive, not beyond any array
    (["--hfov", "12deg", "--pixels", "0", "--critical-dimension", "2m"], "--pixels"),
    (["--hfov", "12deg", "--pixels", "-640", "--critical-dimension", "2m"], "--pixels"),
    (["--hfov", "12deg", "--pixels", "1" + "0" * 30, "--critical-dimension", "2m"], "--pixels"),
    (["--hfov", "12deg", "--pixels", "1" + "0" * 400, "--critical-dimension", "2m"], "--pixels"),
    (["--hfov", "12deg", "--pixels", "640.5", "--critical-dimension", "2m"], "--pixels"),
    # plain numbers
    ([*SENSOR, "--f-number", "0", "--wavelength", "10um"], "--f-number"),
    ([*SENSOR, "--f-number", "inf", "--wavelength", "10um"], "--f-number"),
    ([*SENSOR, "--f-number", "nan", "--wavelength", "10um"], "--f-number"),
    ([*SENSOR, "--scr", "-1"], "--scr"),
    ([*SENSOR, "--scr", "inf"], "--scr"),
    ([*SENSOR, "--scr", "nan"], "--scr"),
    ([*SENSOR, "--nec", "-0.01", "--contrast", "0.3"], "--nec"),
    ([*SENSOR, "--nec", "inf", "--contrast", "0.3"], "--nec"),
    ([*SENSOR, "--nec", "0.01", "--contrast", "nan"], "--contrast"),
    ([*SENSOR, "--nec", "0.01", "--contrast", "-inf"], "--contrast"),
    ([*SENSOR, *THERMAL, "--emissivity", "1.5"], "--emissivity"),
    ([*SENSOR, *THERMAL, "--emissivity", "nan"], "--emissivity"),
    ([*SENSOR, *THERMAL, "--background-emissivity", "-0.1"], "--background-emissivity"),
    # temperatures in (0, 10000] K and differences at most 10000 K
    ([*SENSOR, *THERMAL[:3], "-5K", *THERMAL[4:]], "--target-temperature"),
    ([*SENSOR, *THERMAL[:3], "0K", *THERMAL[4:]], "--target-temperature"),
    ([*SENSOR, *THERMAL[:3], "1e300K", *THERMAL[4:]], "--target-temperature"),
    ([*SENSOR, *THERMAL[:5], "1e5K"], "--background-temperature"),
    ([*SENSOR, *THERMAL[:5], "-300degC"], "--background-temperature"),
    ([*SENSOR, *THERMAL, "--clutter-std", "-2K"], "--clutter-std"),
    ([*SENSOR, *THERMAL, "--clutter-std", "1e9K"], "--clutter-std"),
    ([*SENSOR, "--netd", "-50mK", "--delta-t", "2K"], "--netd"),
    ([*SENSOR, "--netd", "1e400mK", "--delta-t", "2K"], "--netd"),
    ([*SENSOR, "--netd", "50mK", "--delta-t", "1e9K"], "--delta-t"),
    ([*SENSOR, "--netd", "50mK", "--delta-t", "nan K"], "--delta-t"),
    ([*SENSOR, *THERMAL, "--netd", "50mK", "--netd-temperature", "0K"], "--netd-temperature"),
    ([*SENSOR, *THERMAL, "--netd", "50mK", "--netd-temperature", "1e6K"], "--netd-temperature"),
    # path
    ([*SENSOR, "--extinction", "-0.4/km"], "--extinction"),
    ([*SENSOR, "--extinction", "inf/km"], "--extinction"),
    ([*SENSOR, "--extinction", "1e400dB/km"], "--extinction"),
    (
        [*SENSOR, "--band", "visible", "--visibility", "0km", "--visibility-convention", "mor"],
        "--v",
    ),
    (
        [*SENSOR, "--band", "visible", "--visibility", "1e400km", "--visibility-convention", "mor"],
        "--visibility",
    ),
    ([*SENSOR, "--band", "8-" + "1" * 400 + "um", *THERMAL[2:]], "--band"),
    ([*SENSOR, "--band", "12-8um", *THERMAL[2:]], "--band"),
    ([*SENSOR, "--band", "8-8um", *THERMAL[2:]], "--band"),
    ([*SENSOR, "--netd", "50mK", "--delta-t", "2K", "--target-area", "0m^2"], "--target-area"),
    ([*SENSOR, "--netd", "50mK", "--delta-t", "2K", "--target-area", "1e400m^2"], "--target-area"),
    # probabilities in (0, 1)
    ([*SENSOR, "--probability", "0"], "--probability"),
    ([*SENSOR, "--probability", "1"], "--probability"),
    ([*SENSOR, "--probability", "nan"], "--probability"),
    ([*SENSOR, "--probability", "inf"], "--probability"),
    ([*SENSOR, "--probability", "0.5,"], "--probability"),
    ([*SENSOR, "--probability", "half"], "--probability"),
    # N50s: finite, positive, increasing
    ([*SENSOR, "--n50", "8,4,1"], "--n50 must increase"),
    ([*SENSOR, "--n50", "1,4,4"], "--n50 must increase"),
    ([*SENSOR, "--n50", "1,1,1"], "--n50 must increase"),
    ([*SENSOR, "--n50", "0,4,6"], "--n50"),
    ([*SENSOR, "--n50", "-1,4,6"], "--n50"),
    ([*SENSOR, "--n50", "1,inf,6"], "--n50"),
    ([*SENSOR, "--n50", "nan,4,6"], "--n50"),
    ([*SENSOR, "--n50", "1,4"], "--n50"),
    # choices
    ([*SENSOR, "--criterion", "jonson"], "--criterion"),
    ([*SENSOR, "--transform", "nope"], "--transform"),
    ([*SENSOR, "--semantics", "nope"], "--semantics"),
    ([*SENSOR, "--bound", "upper"], "--bound"),
    ([*SENSOR, "--clutter", "extreme"], "--clutter"),
    ([*SENSOR, "--format", "xml"], "--format"),
    ([*SENSOR, "--extinction", "1/km", "--noise-model", "rss"], "--noise-model"),
    (
        ["--hfov", "12deg", "--pixels", "640", "--critical-dimension", "2m", "--projection", "x"],
        "--p",
    ),
]


@pytest.mark.parametrize(("args", "named"), DRI_DOMAIN)
def test_dri_refuses_values_outside_their_domain(cli, args, named):
    assert_refused(cli, ["dri", *args], named)


def test_an_overflowing_option_says_so(cli):
    err = assert_refused(cli, ["dri", "--pitch", "1e400um", *SENSOR[2:]], "--pitch")
    assert err == f"targetacq: error: --pitch must be finite; got '1e400um' {OVERFLOW}\n"


def test_decreasing_n50_is_refused_with_the_rule(cli):
    err = assert_refused(cli, ["dri", *SENSOR, "--n50", "8,4,1"], "--n50")
    assert err == (
        "targetacq: error: --n50 must increase: detection < recognition < identification; "
        "got 8, 4, 1\n"
    )


# --- dri: contradictory or unused combinations -------------------------------------------------

DRI_COMBINATIONS = [
    # the sensor's resolution one way
    ([*SENSOR, "--ifov", "0.2mrad"], ["--pitch", "--ifov"]),
    ([*SENSOR, "--hfov", "12deg", "--pixels", "640"], ["--pitch", "--hfov"]),
    (["--ifov", "0.2mrad", "--hfov", "12deg", "--critical-dimension", "2m"], ["--ifov"]),
    (["--pitch", "17um", "--critical-dimension", "2m"], ["--pitch", "--focal-length"]),
    (["--focal-length", "75mm", "--critical-dimension", "2m"], ["--pitch", "--focal-length"]),
    (["--hfov", "12deg", "--critical-dimension", "2m"], ["--hfov", "--pixels"]),
    (["--pixels", "640", "--critical-dimension", "2m"], ["--hfov", "--pixels"]),
    (["--critical-dimension", "2m"], ["--pitch"]),
    (["--pitch", "17um", "--focal-length", "75mm"], ["--critical-dimension"]),
    ([*SENSOR, "--projection", "rectilinear"], ["--projection", "--hfov"]),
    ([*SENSOR, "--pixel-density", "arc"], ["--pixel-density"]),
    # optics
    ([*SENSOR, "--aperture", "50mm"], ["--aperture", "--wavelength"]),
    ([*SENSOR, "--wavelength", "10um"], ["--aperture", "--wavelength"]),
    ([*SENSOR, "--f-number", "1.2"], ["--f-number", "--wavelength"]),
    ([*SENSOR, "--f-number", "1.2", "--aperture", "50mm", "--wavelength", "10um"], ["--f-number"]),
    (["--ifov", "0.2mrad", "--critical-dimension", "2m", "--f-number", "1"], ["--focal-length"]),
    # criterion
    ([*SENSOR, "--criterion", "johnson-truck", "--n50", "1,4,6"], ["--criterion", "--n50"]),
    ([*SENSOR, "--criterion", "en62676-4", "--probability", "0.8"], ["en62676-4", "--probability"]),
    ([*SENSOR, "--criterion", "en62676-4", "--transform", "ttpf"], ["en62676-4", "--transform"]),
    ([*SENSOR, "--criterion", "en62676-4", "--semantics", "nested"], ["--semantics"]),
    (
        [*FIELD_OF_VIEW, "--criterion", "en62676-4", "--projection", "rectilinear"],
        ["--projection"],
    ),
    # clutter and temperatures
    ([*SENSOR, "--scr", "3", "--clutter", "low"], ["--scr", "--clutter"]),
    ([*SENSOR, *THERMAL, "--scr", "3", "--clutter-std", "2K"], ["--scr", "--clutter-std"]),
    ([*SENSOR, "--band", "lwir", "--target-temperature", "300K"], ["--background-temperature"]),
    ([*SENSOR, "--clutter-std", "2K"], ["--clutter-std", "--target-temperature"]),
    ([*SENSOR, *THERMAL[2:]], ["--band"]),
    ([*SENSOR, "--emissivity", "0.9"], ["--emissivity", "--target-temperature"]),
    ([*SENSOR, "--background-emissivity", "0.9"], ["--background-emissivity"]),
    # the path
    ([*SENSOR, "--extinction", "1/km", "--band", "lwir", "--obscurant", "fog"], ["--extinction"]),
    ([*SENSOR, "--obscurant", "fog"], ["--obscurant", "--band"]),
    ([*SENSOR, "--band", "lwir", "--obscurant", "smog"], ["--obscurant"]),
    ([*SENSOR, "--band", "lwir", "--obscurant", "fog:extreme"], ["--obscurant level"]),
    ([*SENSOR, "--visibility", "5km"], ["--visibility-convention"]),
    ([*SENSOR, "--visibility-convention", "mor"], ["--visibility"]),
    (
        [*SENSOR, "--band", "lwir", "--visibility", "5km", "--visibility-convention", "mor"],
        ["--visibility", "--band"],
    ),
    ([*SENSOR, "--noise-model", "none"], ["--noise-model"]),
    # the sensor's noise
    ([*SENSOR, "--nec", "0.01"], ["--nec", "--contrast"]),
    ([*SENSOR, "--contrast", "0.3"], ["--nec", "--contrast"]),
    ([*SENSOR, "--nec", "0.01", "--contrast", "0.3", "--netd", "50mK"], ["--nec", "--netd"]),
    ([*SENSOR, "--netd", "50mK"], ["--delta-t"]),
    ([*SENSOR, "--delta-t", "2K"], ["--delta-t", "--netd"]),
    ([*SENSOR, "--netd-temperature", "290K"], ["--netd-temperature", "--netd"]),
    ([*SENSOR, "--netd", "50mK", "--delta-t", "2K", "--netd-temperature", "290K"], ["--delta-t"]),
    ([*SENSOR, *THERMAL, "--netd", "50mK", "--delta-t", "2K"], ["--delta-t", "--target-temp"]),
    ([*SENSOR, "--target-area", "4m^2"], ["--target-area", "--netd"]),
    ([*SENSOR, "--mrtd", EXAMPLE_MRTD], ["--delta-t"]),
]


@pytest.mark.parametrize(("args", "named"), DRI_COMBINATIONS)
def test_dri_refuses_contradictory_or_unused_options(cli, args, named):
    assert_refused(cli, ["dri", *args], *named)


# --- CSV inputs: --mrtd and --boxes ------------------------------------------------------------

BENCH = "frequency,mrtd\n0.5,0.05\n1.0,0.12\n1.4,0.4\n"


@pytest.mark.parametrize(
    ("text", "named"),
    [
        ("frequency,mrtd\n0.5,0.05\n1.0,inf\n", ["line 3", "'mrtd'", "inf"]),
        ("frequency,mrtd\n0.5,0.05\nnan,0.1\n", ["line 3", "'frequency'"]),
        ("frequency,mrtd\n0.5,0.05\n1e400,0.1\n", ["line 3", "'frequency'"]),
        ("frequency,mrtd\n0.5,0.05\n1.0,abc\n", ["line 3", "'mrtd'", "'abc'"]),
        ("# bench\n\nfrequency,mrtd\n0.5,0.05\n1.0\n", ["line 5"]),
        ("freq,mrtd\n0.5,0.05\n1.0,0.1\n", ["line 1", "'frequency'"]),
    ],
)
def test_mrtd_csv_errors_name_the_file_line_and_column(cli, tmp_path, text, named):
    path = tmp_path / "bench.csv"
    path.write_text(text, encoding="utf-8")
    args = ["dri", *SENSOR, "--mrtd", str(path), "--delta-t", "2K"]
    assert_refused(cli, args, "--mrtd", str(path), *named)


def _unreadable_paths(tmp_path):
    big = tmp_path / "big.csv"
    with big.open("wb") as handle:  # sparse: the size is what is refused, nothing is written
        handle.truncate(MAX_INPUT_BYTES + 1)
    binary = tmp_path / "binary.csv"
    binary.write_bytes(b"x,y,width,height\n\xff\xfe\x00\n")
    return {
        "missing": (tmp_path / "none.csv", "no such file"),
        "folder": (tmp_path, "is a directory"),
        "device": (Path("/dev/null"), "not a regular file"),
        "too large": (big, "limited to 10 MB"),
        "not UTF-8": (binary, "not UTF-8 text (byte 18 is 0xff)"),
    }


@pytest.mark.parametrize("kind", ["missing", "folder", "device", "too large", "not UTF-8"])
@pytest.mark.parametrize("option", ["--mrtd", "--boxes"])
def test_unreadable_csv_files_are_one_line_naming_option_and_file(cli, tmp_path, kind, option):
    path, why = _unreadable_paths(tmp_path)[kind]
    if option == "--mrtd":
        args = ["dri", *SENSOR, "--mrtd", str(path), "--delta-t", "2K"]
    else:
        args = ["clutter", CAMERA, "--boxes", str(path)]
    assert_refused(cli, args, option, str(path), why)


def test_mrtd_csv_with_a_byte_order_mark_reads_as_without(tmp_path):
    plain, marked = tmp_path / "plain.csv", tmp_path / "marked.csv"
    plain.write_text(BENCH, encoding="utf-8")
    marked.write_text(BENCH, encoding="utf-8-sig")
    assert marked.read_bytes().startswith(b"\xef\xbb\xbf")
    curve = MrtdCurve.from_csv(marked)
    assert curve == MrtdCurve.from_csv(plain)
    assert curve.frequency == (500.0, 1000.0, 1400.0)  # cycles/mrad × 1000


@pytest.mark.parametrize(
    ("text", "named"),
    [
        ("x,y,width,height\n10,10,8,8\n20,20,nan,8\n", ["line 3", "'width'", "'nan'"]),
        ("x,y,width,height\n10,10,8,8\n20,inf,8,8\n", ["line 3", "'y'", "'inf'"]),
        ("x,y,width,height\n1e400,10,8,8\n", ["line 2", "'x'"]),
        ("# targets\n\nx,y,width,height\n10,10,8,abc\n", ["line 4", "'height'", "'abc'"]),
        ("x,y,width,height\n10,10,8\n", ["line 2", "3 cells"]),
        ("x,y,width,height\n10,10,8,8,9\n", ["line 2", "5 cells"]),
        ("x,y,w,h\n10,10,8,8\n", ["line 1", "missing column width, height"]),
        ("x,y,width,height\n", ["no box"]),
        ("", ["no box"]),
    ],
)
def test_boxes_csv_errors_name_the_file_line_and_column(cli, tmp_path, text, named):
    path = tmp_path / "targets.csv"
    path.write_text(text, encoding="utf-8")
    assert_refused(cli, ["clutter", CAMERA, "--boxes", str(path)], "--boxes", *named)


def test_boxes_csv_with_a_byte_order_mark_gives_the_same_table(cli, tmp_path):
    text = "X,Y,Width,Height,label\n412,118,20,20,truck\n228,470,24,24,car\n"
    outputs = []
    for encoding in ("utf-8", "utf-8-sig"):
        path = tmp_path / f"{encoding}.csv"
        path.write_text(text, encoding=encoding)
        code, out, err = cli("clutter", CAMERA, "--boxes", str(path), "--format", "csv")
        assert code == 0, err
        outputs.append(out)
    assert outputs[0] == outputs[1]
    assert outputs[0].count("\n") == 3  # a header and the two boxes


CLUTTER_OPTIONS = [
    (["--box", "nan,10,8,8"], ["--box"]),
    (["--box", "10,10,inf,8"], ["--box"]),
    (["--box", "10,10,8"], ["--box"]),
    (["--box", "10,10,8,8", "--cycles", "inf"], ["--cycles"]),
    (["--box", "10,10,8,8", "--cycles", "-1"], ["--cycles"]),
    (["--box", "10,10,8,8", "--cycles", "nan"], ["--cycles"]),
    (["--box", "10,10,8,8", "--cell-factor", "0"], ["--cell-factor"]),
    (["--box", "10,10,8,8", "--cell-factor", "nan"], ["--cell-factor"]),
    (["--box", "10,10,8,8", "--cell-factor", "inf"], ["--cell-factor"]),
    (["--box", "10,10,8,8", "--image-range", "0km", "--range", "1km"], ["--image-range"]),
    (["--box", "10,10,8,8", "--image-range", "1km", "--range", "-1km"], ["--range"]),
    (["--box", "10,10,8,8", "--image-range", "1e400km", "--range", "1km"], ["--image-range"]),
    (["--box", "10,10,8,8", "--image-range", "1km", "--range", "1e12m"], ["--range"]),
    (["--box", "10,10,8,8", "--image-range", "1km"], ["--image-range", "--range"]),
    (["--box", "10,10,8,8", "--cycles", "3", "--image-range", "1km", "--range", "2km"], ["--c"]),
    (["--box", "10,10,8,8", "--criterion", "en62676-4"], ["--criterion"]),
    (["--box", "10,10,8,8", "--criterion", "jonson"], ["--criterion"]),
    (["--box", "10,10,8,8", "--channel", "purple"], ["--channel"]),
    (["--box", "10,10,8,8", "--channel", "red"], ["--channel", "grayscale"]),
    (["--box", "10,10,8,8", "--format", "xml"], ["--format"]),
    ([], ["--box"]),
]


@pytest.mark.parametrize(("args", "named"), CLUTTER_OPTIONS)
def test_clutter_refuses_bad_options(cli, args, named):
    assert_refused(cli, ["clutter", CAMERA, *args], *named)


# --- atmosphere, plot, report ------------------------------------------------------------------

ATMOSPHERE = [
    (["--range", "1e400km", "--extinction", "1/km"], "--range"),
    (["--range", "1km,nan km", "--extinction", "1/km"], "--range"),
    (["--range", "-1km", "--extinction", "1/km"], "--range"),
    (["--range", "1km,1e300m", "--extinction", "1/km"], "±1e+09 m"),
    (["--range", "1km", "--visibility", "2e6km", "--visibility-convention", "mor"], "--visibility"),
    (["--range", "1km,", "--extinction", "1/km"], "--range"),
    (["--range", "1km", "--extinction", "1e400/km"], "--extinction"),
    (["--range", "1km", "--extinction", "-1/km"], "--extinction"),
    (["--range", "1km", "--band", "lwir", "--obscurant", "fog:x"], "--obscurant"),
    (["--range", "1km", "--visibility", "-5km", "--visibility-convention", "mor"], "--visibility"),
    (["--range", "1km", "--extinction", "1/km", "--format", "yaml"], "--format"),
    (["--range", "1km"], "--extinction"),
]


@pytest.mark.parametrize(("args", "named"), ATMOSPHERE)
def test_atmosphere_refuses_bad_options(cli, args, named):
    assert_refused(cli, ["atmosphere", *args], named)


FIGURES = [
    (["plot", "curves", "--example", "--pitch", "1e400um"], ["--pitch"]),
    (["plot", "curves", "--example", "--max-range", "0km"], ["--max-range"]),
    (["plot", "curves", "--example", "--max-range", "1e400km"], ["--max-range"]),
    (["plot", "curves", "--example", "--n50", "8,4,1"], ["--n50"]),
    (["plot", "curves", "--example", "--criterion", "en62676-4"], ["en62676-4"]),
    (["plot", "curves", "--example", "--format", "json"], ["--format"]),
    (["plot", "curves", "--example", "--level", "high"], ["--level"]),
    (["plot", "transforms", "--n50", "8,4,1"], ["--n50 must increase"]),
    (["plot", "transforms", "--max-range", "5km"], ["--max-range"]),
    (["plot", "atmosphere", "--max-range", "-1km"], ["--max-range"]),
    (["plot", "atmosphere", "--max-range", "nan km"], ["--max-range"]),
    (["plot", "atmosphere", "--level", "extreme"], ["--level"]),
    (["plot", "atmosphere", "--band", "12-8um"], ["--band"]),
    (["report", "--example", "--extinction", "1e400/km"], ["--extinction"]),
    (["report", "--example", "--probability", "0.5,1.5"], ["--probability"]),
    (["report", "--example", "--max-range", "0m"], ["--max-range"]),
    (["report", "--example", "--format", "csv"], ["--format"]),
    (["report", "--example", "--emissivity", "0.5"], ["--emissivity"]),
]


@pytest.mark.parametrize(("args", "named"), FIGURES)
def test_plot_and_report_refuse_bad_options_before_drawing(cli, tmp_path, args, named):
    out = tmp_path / ("figure.png" if args[0] == "plot" else "report.html")
    assert_refused(cli, [*args, "--out", str(out)], *named)
    assert not out.exists()


# --- valid edge cases: strict JSON, no warning --------------------------------------------------


def _strict_json(text):
    def refuse(constant):
        raise AssertionError(f"{constant} is not JSON")

    return json.loads(text, parse_constant=refuse)


def _run_app_warnings_as_errors(args):
    """stdout of the command, run without the entry point's warning handling."""
    out = io.StringIO()
    with warnings.catch_warnings(), contextlib.redirect_stdout(out):
        warnings.simplefilter("error")
        app(args=args, prog_name="targetacq", standalone_mode=False)
    return out.getvalue()


VALID_EDGES = [
    ["dri", "--example", "--extinction", "0/km"],
    ["dri", "--example", "--extinction", "1e300/km"],  # opaque: nothing is ever reached
    ["dri", "--example", "--netd", "50mK", "--delta-t", "0K"],
    ["dri", "--example", "--netd", "0mK", "--delta-t", "2K"],
    ["dri", "--example", "--nec", "0", "--contrast", "0"],
    ["dri", "--example", "--scr", "0"],
    ["dri", "--example", "--blur", "0mrad"],
    ["dri", "--example", *THERMAL, "--clutter-std", "0K", "--emissivity", "0"],
    ["dri", "--example", *THERMAL[:3], "10000K", "--background-temperature", "0.001K"],
    ["dri", "--example", *THERMAL, "--netd", "50mK", "--netd-temperature", "250K"],
    ["dri", "--example", "--probability", "1e-300,0.999999999"],
    ["dri", "--example", "--criterion", "en62676-4"],
    ["dri", "--ifov", "179deg", "--critical-dimension", "1000km"],
    ["dri", "--pitch", "1e9m", "--focal-length", "1e9m", "--critical-dimension", "1e9m"],
    ["atmosphere", "--range", "0m,1km,1e9m", "--extinction", "0/km"],
    ["atmosphere", "--range", "0m,1km", "--extinction", "1e300/km"],
]


@pytest.mark.parametrize("args", VALID_EDGES)
def test_valid_edge_cases_print_strict_json_without_warnings(args):
    document = _strict_json(_run_app_warnings_as_errors([*args, "--format", "json"]))
    assert document


def test_atmosphere_spells_an_infinite_snr_as_inf_not_null():
    # τ(0) = 1 gives SNR = 20 log10(τ / (1 − τ)) = +inf dB, Eq. (7.7); at τ = 1/2 it is 0 dB.
    text = _run_app_warnings_as_errors(
        ["atmosphere", "--range", "0m,1km", "--extinction", f"{math.log(2)}/km", "--format", "json"]
    )
    rows = _strict_json(text)["rows"]
    assert rows[0]["transmittance"] == 1.0 and rows[0]["snr_db"] == "inf"
    assert rows[1]["snr_db"] == pytest.approx(0.0, abs=1e-9)


def test_an_opaque_path_reaches_no_range_and_says_null():
    text = _run_app_warnings_as_errors(
        ["dri", "--example", "--extinction", "1e300/km", "--format", "json"]
    )
    rows = _strict_json(text)["ranges"]
    assert rows and all(r["range_m"] is None and r["reached"] is False for r in rows)


def test_options_given_the_default_value_explicitly_are_accepted(cli):
    # --emissivity 1 with temperatures, --transform ttpf with a cycles criterion: same result.
    plain = cli("dri", "--example", *THERMAL, "--format", "json")
    defaults = ["--emissivity", "1", "--transform", "ttpf", "--semantics", "nested"]
    explicit = cli("dri", "--example", *THERMAL, *defaults, "--probability", "0.5",
                   "--format", "json")  # fmt: skip
    assert plain[0] == explicit[0] == 0
    assert _strict_json(plain[1]) == _strict_json(explicit[1])


# --- the boundary functions ---------------------------------------------------------------------


def test_read_input_text_strips_a_byte_order_mark_only_at_the_start(tmp_path):
    path = tmp_path / "t.csv"
    path.write_bytes(b"\xef\xbb\xbfa,b\n1,\xef\xbb\xbf2\n")
    assert read_input_text(path, "test file") == "a,b\n1,\ufeff2\n"


def test_read_input_text_accepts_a_file_of_exactly_the_limit(tmp_path):
    path = tmp_path / "limit.csv"
    path.write_bytes(b"a" * MAX_INPUT_BYTES)
    assert len(read_input_text(path, "test file")) == MAX_INPUT_BYTES
