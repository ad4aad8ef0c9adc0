"""The design solver (targetacq.run.design) and `targetacq design`.

Expected values come from closed forms written out here (the TTPF inverted by a root finder,
the diffraction limit) or from a root finder run on ``case_ranges`` directly, never from the
solver itself.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from targetacq.cli import main
from targetacq.core.cases import RangeCase
from targetacq.core.ranges import case_ranges
from targetacq.run.design import (
    required_focal_length,
    required_ifov,
    required_pitch,
    unreachable_reason,
)

JOHNSON = {"detection": 1.0, "orientation": 1.4, "recognition": 4.0, "identification": 6.4}


def _ttpf_x(p: float) -> float:
    """N/N50 at which the TTPF (Eq. (3.1): E = 2.7 + 0.7 x) equals p, by a root finder."""

    def f(x: float) -> float:
        e = 2.7 + 0.7 * x
        return x**e / (1.0 + x**e) - p

    return brentq(f, 1e-6, 100.0, xtol=1e-15, rtol=1e-15)


def _closed_form_ifov(d: float, r: float, p: float, task: str) -> float:
    """IFOV = d / (2 · N50 · x(P) · R): one cycle is two pixels (Fig. 3.3)."""
    return d / (2.0 * JOHNSON[task] * _ttpf_x(p) * r)


def _bisected_ifov(d: float, r: float, p: float, task: str, **model) -> float:
    """The IFOV at which case_ranges gives range r, by a root finder in log IFOV."""

    def gap(log_ifov: float) -> float:
        case = RangeCase(d, math.exp(log_ifov), **model)
        return math.log(float(case_ranges(case, p)[task]) / r)

    geometric = _closed_form_ifov(d, r, p, task)
    lo, hi = math.log(geometric * 1e-3), math.log(geometric)
    return math.exp(brentq(gap, lo, hi, xtol=1e-12, rtol=1e-12))


def _run(capsys, *argv):
    with pytest.raises(SystemExit) as exit_info:
        main(list(argv))
    out, err = capsys.readouterr()
    return exit_info.value.code, out, err


CASE_128 = (
    "--task",
    "recognition",
    "--range",
    "1km",
    "--probability",
    "0.5",
    "--critical-dimension",
    "0.75m",
    "--pitch",
    "12um",
)


# --- the case: 12 µm, Johnson recognition at 50 %, 0.75 m at 1 km → 128 mm ----------


def test_128_mm_from_python():
    # 0.75 m / (2 · 4 cycles · 1000 m) = 93.75 µrad; 12 µm / 93.75 µrad = 128 mm.
    assert float(required_ifov(0.75, 1000.0, 0.5, "recognition")) == pytest.approx(
        93.75e-6, rel=1e-12
    )
    assert float(required_focal_length(12e-6, 0.75, 1000.0, 0.5)) == pytest.approx(0.128, rel=1e-12)
    assert float(required_pitch(0.128, 0.75, 1000.0, 0.5)) == pytest.approx(12e-6, rel=1e-12)


def test_128_mm_from_the_cli(capsys):
    code, out, err = _run(capsys, "design", *CASE_128)
    assert code == 0, err
    (row,) = [line for line in out.splitlines() if line.startswith("recognition")]
    assert row.split()[-2:] == ["128", "0.09375"]  # focal length [mm], IFOV [mrad]
    assert "focal length [mm]" in out


def test_json_keys_and_both_weathers(capsys):
    code, out, err = _run(capsys, "design", *CASE_128, "--extinction", "0.4/km", "--format", "json")
    assert code == 0, err
    rows = json.loads(out)["rows"]
    assert [row["weather"] for row in rows] == [None, "--extinction 0.4/km"]
    for row in rows:
        assert {"task", "probability", "range_m", "focal_length_m", "ifov_rad", "weather"} <= set(
            row
        )
        assert row["focal_length_m"] == pytest.approx(12e-6 / row["ifov_rad"], rel=1e-12)
    assert rows[0]["focal_length_m"] == pytest.approx(0.128, rel=1e-12)
    expected = _bisected_ifov(0.75, 1000.0, 0.5, "recognition", extinction=0.4e-3)
    assert rows[1]["ifov_rad"] == pytest.approx(expected, rel=1e-8)
    table = _run(capsys, "design", *CASE_128, "--extinction", "0.4/km")[1]
    assert len([line for line in table.splitlines() if line.startswith("recognition")]) == 2


def test_focal_length_gives_the_pitch_and_neither_gives_the_ifov(capsys):
    argv = ("design", "--task", "recognition", "--range", "1km", "--target", "person")
    code, out, err = _run(capsys, *argv, "--focal-length", "128mm", "--format", "csv")
    assert code == 0, err
    header, row = out.splitlines()
    values = dict(zip(header.split(","), row.split(","), strict=True))
    assert float(values["pitch_m"]) == pytest.approx(12e-6, rel=1e-12)
    code, out, err = _run(capsys, *argv, "--format", "json")
    assert code == 0, err
    (row,) = json.loads(out)["rows"]
    assert row["ifov_rad"] == pytest.approx(93.75e-6, rel=1e-12)
    assert "focal_length_m" not in row and "pitch_m" not in row


# --- the solver against closed forms and an independent root finder -------------------------


@pytest.mark.parametrize(
    ("d", "r", "p", "task"),
    [
        (0.75, 1000.0, 0.5, "recognition"),
        (2.3, 3000.0, 0.8, "detection"),
        (2.3, 500.0, 0.95, "identification"),
        (0.75, 250.0, 0.1, "orientation"),
    ],
)
def test_geometric_case_equals_the_closed_form(d, r, p, task):
    assert float(required_ifov(d, r, p, task)) == pytest.approx(
        _closed_form_ifov(d, r, p, task), rel=1e-10
    )


@pytest.mark.parametrize(
    "model",
    [
        {"extinction": 0.4e-3},
        {"extinction": 2e-3, "noise_model": "clutter-analogue"},
        {"extinction": 0.4e-3, "semantics": "conditional"},
        {"contrast": 2.0, "noise_equivalent_contrast": 0.5},
        {"extinction": 0.2e-3, "wavelength": 10e-6, "aperture": 0.1, "blur_sigma": 2e-5},
        {"scr": 1.0, "extinction": 0.1e-3},
    ],
    ids=["haze", "fog-clutter-analogue", "conditional", "netd", "diffraction-blur-haze", "clutter"],
)
@pytest.mark.parametrize("task", ["detection", "recognition"])
def test_noisy_cases_equal_a_root_finder_on_case_ranges(model, task):
    found = float(required_ifov(0.75, 800.0, 0.7, task, **model))
    assert found == pytest.approx(_bisected_ifov(0.75, 800.0, 0.7, task, **model), rel=1e-8)


def test_fixed_aperture_diffraction_closed_form():
    # cycle = max(2 IFOV, asin(1.22 λ / D)): below the needed cycle the sampling decides.
    d, r, lam = 0.75, 1000.0, 10e-6
    needed_cycle = d / (4.0 * r)  # recognition at P = 0.5: 4 cycles
    sharp = lam * 1.22 / math.sin(needed_cycle * 0.9)  # an aperture whose limit is finer
    assert float(required_ifov(d, r, 0.5, wavelength=lam, aperture=sharp)) == pytest.approx(
        needed_cycle / 2, rel=1e-10
    )
    blurred = lam * 1.22 / math.sin(needed_cycle * 1.1)  # coarser: no IFOV reaches it
    assert math.isnan(float(required_ifov(d, r, 0.5, wavelength=lam, aperture=blurred)))
    reason = unreachable_reason(d, r, 0.5, wavelength=lam, aperture=blurred)
    assert reason is not None and "optics limit" in reason


@pytest.mark.parametrize("f_number", [1.0, 2.5, 4.0])
def test_f_number_diffraction_closed_form(f_number):
    # Designing the focal length for a 12 µm pitch at F#: D = f / F# = p / (IFOV · F#), so the
    # diffraction angle asin(1.22 λ F# IFOV / p) scales with the IFOV; the cycle is the larger
    # of it and 2 IFOV, equal to the needed d / (N R).
    d, r, p, lam = 0.75, 1000.0, 12e-6, 10e-6
    needed_cycle = d / (4.0 * r)
    k = 1.22 * lam * f_number / p
    ifov = (
        needed_cycle / 2
        if math.asin(k * needed_cycle / 2) <= needed_cycle
        else (math.sin(needed_cycle) / k)
    )
    f = required_focal_length(p, d, r, 0.5, f_number=f_number, wavelength=lam)
    assert float(f) == pytest.approx(p / ifov, rel=1e-9)
    if f_number == 1.0:
        assert float(f) == pytest.approx(0.128, rel=1e-9)  # sampling-limited
    else:
        assert float(f) > 0.128  # diffraction-limited: a longer lens (larger aperture)


def test_pitch_for_a_focal_length_with_f_number():
    # A fixed lens (f = 100 mm, F/2, D = 50 mm): diffraction 1.22 · 10 µm / 50 mm = 0.244 mrad
    # is finer than the needed cycle 0.75 m / (4 · 700 m) = 0.268 mrad, so the pixel decides:
    # p = f · cycle / 2.
    needed_cycle = 0.75 / (4.0 * 700.0)
    pitch = required_pitch(0.1, 0.75, 700.0, 0.5, f_number=2.0, wavelength=10e-6)
    assert float(pitch) == pytest.approx(0.1 * needed_cycle / 2, rel=1e-9)


# --- round trip: dri with the designed focal length gives the asked range --------------------


@pytest.mark.parametrize(
    "extra",
    [
        (),
        ("--extinction", "0.4/km"),
        ("--band", "lwir", "--obscurant", "haze:high"),
        ("--extinction", "1/km", "--f-number", "2", "--wavelength", "10um", "--scr", "2"),
        ("--delta-t", "2K", "--netd", "0.5K"),
    ],
    ids=["clear", "haze", "obscurant", "diffraction-clutter", "netd"],
)
def test_round_trip_through_dri(capsys, extra):
    code, out, err = _run(capsys, "design", *CASE_128, *extra, "--format", "json")
    assert code == 0, err
    focal_length = json.loads(out)["rows"][-1]["focal_length_m"]  # with the weather if any
    code, out, err = _run(
        capsys,
        "dri",
        "--pitch",
        "12um",
        "--focal-length",
        f"{focal_length!r}m",
        "--critical-dimension",
        "0.75m",
        *extra,
        "--format",
        "json",
    )
    assert code == 0, err
    (row,) = [row for row in json.loads(out)["ranges"] if row["task"] == "recognition"]
    assert row["range_m"] == pytest.approx(1000.0, rel=1e-6)


# --- properties ------------------------------------------------------------------------------


def test_longer_range_or_higher_probability_needs_a_longer_lens():
    ranges = np.array([250.0, 500.0, 1000.0, 2000.0, 4000.0])
    for model in ({}, {"extinction": 0.5e-3}, {"contrast": 2.0, "noise_equivalent_contrast": 0.3}):
        f = required_focal_length(12e-6, 0.75, ranges, 0.5, **model)
        assert np.all(np.diff(f) > 0), model
        f = required_focal_length(
            12e-6, 0.75, 1000.0, np.array([0.1, 0.3, 0.5, 0.8, 0.95]), **model
        )
        assert np.all(np.diff(f) > 0), model


@pytest.mark.parametrize("gamma", [0.05e-3, 0.4e-3, 1e-3, 3e-3])
def test_weather_never_shortens_the_lens(gamma):
    clear = required_focal_length(12e-6, 0.75, 800.0, 0.5)
    assert float(required_focal_length(12e-6, 0.75, 800.0, 0.5, extinction=gamma)) >= float(clear)


def test_vectorised_over_range_and_probability_equals_elementwise():
    r = np.array([[400.0], [900.0]])
    p = np.array([0.3, 0.6, 0.9])
    grid = required_ifov(0.75, r, p, "recognition", extinction=0.4e-3)
    assert grid.shape == (2, 3)
    for i in range(2):
        for j in range(3):
            one = required_ifov(0.75, float(r[i, 0]), float(p[j]), extinction=0.4e-3)
            assert grid[i, j] == pytest.approx(float(one), rel=1e-12)


def test_nan_in_nan_out():
    out = required_ifov(0.75, np.array([1000.0, np.nan]), np.array([np.nan, 0.5]))
    assert np.isnan(out).all()
    assert math.isnan(float(required_ifov(0.75, math.nan, 0.5, extinction=0.4e-3)))
    ok = required_ifov(0.75, np.array([1000.0, np.nan]), 0.5, extinction=0.4e-3)
    assert np.isfinite(ok[0]) and np.isnan(ok[1])


def test_pixel_density_criterion_closed_form():
    # EN 62676-4 recognition: 125 pixels per metre at 50 m → IFOV = 1 / (125 · 50) rad.
    assert float(required_ifov(0.75, 50.0, task="recognition", criterion="en62676-4")) == (
        pytest.approx(1 / (125 * 50), rel=1e-12)
    )


# --- what no IFOV reaches, and bad input -----------------------------------------------------


def test_impossible_weather_is_nan_and_says_so():
    assert math.isnan(float(required_ifov(0.75, 1000.0, 0.5, extinction=20e-3)))
    reason = unreachable_reason(0.75, 1000.0, 0.5, extinction=20e-3)
    assert reason is not None and reason.startswith("the weather alone makes it impossible")


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"range": 0.0}, "range must be finite and > 0"),
        ({"range": -5.0}, "range must be finite and > 0"),
        ({"range": math.inf}, "range must be finite and > 0"),
        ({"probability": 1.0}, "probability must be in the open interval"),
        ({"task": "swim"}, "task must be one of"),
        ({"mrtd": object()}, "mrtd is not a model keyword"),
        ({"ifov": 1e-4}, "ifov is not a model keyword"),
        ({"extinction": -1.0}, "extinction"),
    ],
)
def test_bad_python_input_raises_value_error(kwargs, message):
    arguments = {"critical_dimension": 0.75, "range": 1000.0, "probability": 0.5}
    arguments.update(kwargs)
    with pytest.raises(ValueError, match=message):
        required_ifov(**arguments)


def test_bad_lens_input_raises_value_error():
    with pytest.raises(ValueError, match="pitch must be finite and > 0"):
        required_focal_length(0.0, 0.75, 1000.0)
    with pytest.raises(ValueError, match="give wavelength"):
        required_focal_length(12e-6, 0.75, 1000.0, f_number=1.0)
    with pytest.raises(ValueError, match="not both"):
        required_pitch(0.1, 0.75, 1000.0, f_number=1.0, wavelength=1e-5, aperture=0.1)


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (("--task", "swim"), "--task must be one of detection, orientation, recognition"),
        (("--probability", "1.5"), "--probability must be in the open interval (0, 1)"),
        (("--probability", "0"), "--probability must be in the open interval (0, 1)"),
        (("--extinction", "20/km"), "the weather alone makes it impossible"),
        (("--aperture", "5mm", "--wavelength", "10um"), "optics limit alone"),
        (("--focal-length", "50mm"), "not both"),
        (("--ifov", "0.1mrad"), "--ifov does not apply to design"),
        (("--hfov", "10deg", "--pixels", "640"), "--hfov does not apply to design"),
        (("--range", "-1km"), "--range"),
    ],
)
def test_bad_cli_input_is_one_line_exit_2(capsys, extra, message):
    argv = ["design", "--range", "1km", "--critical-dimension", "0.75m", "--pitch", "12um"]
    if extra[0] == "--range":
        argv = argv[:1] + argv[3:]
    code, out, err = _run(capsys, *argv, *extra)
    assert code == 2 and out == ""
    assert err.startswith("targetacq: error: ") and err.count("\n") == 1
    assert message in err


def test_help_has_an_example(capsys):
    code, out, _ = _run(capsys, "design", "--help")
    assert code == 0
    assert "Example: targetacq design" in out and "--target" in out
