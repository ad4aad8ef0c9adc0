"""``targetacq calibrate``: a task's N50 (and exponent) fitted to a CSV file of trials.

Expected values come from a brute-force grid of the log-likelihood written out here (the TTPF
with its own exponent, ``P = x^E / (1 + x^E)``, ``x = N/N50``, ``E = 2.7 + 0.7 x``) and from the
geometry ``N = d / (2 IFOV R)`` worked by hand, never from the command's own output.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy import stats

from targetacq.cli import main

CYCLES = [2, 2, 3, 3, 3, 4, 4, 4, 5, 5, 5, 6, 6, 7]
SEEN = [0, 0, 0, 1, 0, 0, 1, 1, 1, 0, 1, 1, 1, 1]


def run(capsys, *args):
    with pytest.raises(SystemExit) as exit_:
        main(["calibrate", *args])
    out, err = capsys.readouterr()
    return exit_.value.code, out, err


def write(tmp_path, name, header, rows):
    path = tmp_path / name
    path.write_text("# trials\n" + header + "\n" + "\n".join(rows) + "\n", encoding="utf-8")
    return str(path)


def grid_fit(cycles, seen):
    """N50 and its 90 % interval with the TTPF's own exponent, on a fine grid."""
    n50 = np.linspace(1.0, 10.0, 90001)[:, None]
    x = np.asarray(cycles, dtype=float) / n50
    z = (2.7 + 0.7 * x) * np.log(x)
    ll = np.sum(np.asarray(seen) * z - np.logaddexp(0.0, z), axis=1)
    inside = n50[ll >= ll.max() - 0.5 * stats.chi2.ppf(0.9, 1), 0]
    return n50[np.argmax(ll), 0], (inside.min(), inside.max()), ll.max()


@pytest.fixture
def cycles_file(tmp_path):
    return write(
        tmp_path,
        "cycles.csv",
        "observer,cycles,outcome",
        [f"a,{n},{y}" for n, y in zip(CYCLES, SEEN, strict=True)],
    )


def test_json_gives_the_grid_maximum_and_interval(capsys, cycles_file):
    code, out, err = run(capsys, cycles_file, "--task", "recognition", "--fixed-exponent",
                         "--format", "json")  # fmt: skip
    assert (code, err) == (0, "")
    report = json.loads(out)
    n50, interval, top = grid_fit(CYCLES, SEEN)
    assert report["n50"] == pytest.approx(n50, abs=2e-4)
    assert report["n50_interval"] == pytest.approx(list(interval), abs=2e-4)
    assert report["log_likelihood"] == pytest.approx(top, abs=1e-6)
    assert (report["trials"], report["successes"]) == (len(SEEN), sum(SEEN))
    assert report["exponent"] == pytest.approx(3.4) and report["exponent_fitted"] is False
    assert report["thresholds"]["identification"] == 6.4  # Johnson's, the default base
    assert report["n50_option"] == f"1,{report['n50']:.4g},6.4"


def test_the_table_names_the_fit_and_how_to_use_it(capsys, cycles_file):
    code, out, err = run(capsys, cycles_file, "--task", "recognition")
    assert (code, err) == (0, "")
    lines = out.splitlines()
    assert lines[0] == "task recognition, transform ttpf, 14 trials (8 successes)"
    assert "90 % intervals by profile likelihood" in lines[1]
    assert any(line.startswith("N50 [cycles]") for line in lines)
    assert any(line.startswith("E50 [1]") and "fixed" not in line for line in lines)
    assert any(line.startswith("log-likelihood") for line in lines)
    # The exponent fitted: its N50 goes with that exponent, not the transform's own.
    assert lines[-1].startswith("to use N50 in evaluations") and "--fixed-exponent" in lines[-1]
    code, out, err = run(capsys, cycles_file, "--task", "recognition", "--fixed-exponent")
    assert (code, err) == (0, "")
    assert out.splitlines()[-1].startswith("use it: --n50 1,")


def test_ranges_become_cycles_by_the_sensor_geometry(capsys, tmp_path, cycles_file):
    # A 2.3 m target and a 0.25 mrad IFOV: N = 2.3 / (2 · 0.25e-3 · R), so R = 4600 m / N.
    ranges = [f"{4600.0 / n / 1000.0!r} km" for n in CYCLES]
    range_file = write(
        tmp_path,
        "ranges.csv",
        "range,outcome",
        [f"{r},{y}" for r, y in zip(ranges, SEEN, strict=True)],
    )
    common = ("--task", "recognition", "--fixed-exponent", "--format", "json")
    code, out, err = run(capsys, range_file, *common, "--critical-dimension", "2.3m",
                         "--ifov", "0.25mrad")  # fmt: skip
    assert (code, err) == (0, "")
    from_ranges = json.loads(out)
    assert from_ranges["input"] == "range"
    n50, interval, _ = grid_fit(CYCLES, SEEN)
    assert from_ranges["n50"] == pytest.approx(n50, abs=2e-4)
    assert from_ranges["n50_interval"] == pytest.approx(list(interval), abs=2e-4)
    # The IFOV from pitch and focal length: 25 um / 100 mm = 0.25 mrad, the same cycles.
    code, out, err = run(capsys, range_file, *common, "--critical-dimension", "2.3m",
                         "--pitch", "25um", "--focal-length", "100mm")  # fmt: skip
    assert (code, err) == (0, "")
    assert json.loads(out)["n50"] == pytest.approx(from_ranges["n50"], rel=1e-9)


def test_csv_is_one_row_with_the_interval_ends(capsys, cycles_file):
    code, out, err = run(capsys, cycles_file, "--task", "recognition", "--format", "csv",
                         "--base", "none")  # fmt: skip
    assert (code, err) == (0, "")
    header, row = out.splitlines()
    values = dict(zip(header.split(","), row.split(","), strict=True))
    assert float(values["n50_low"]) < float(values["n50"]) < float(values["n50_high"])
    assert values["n50_option"] == ""  # recognition alone: no D,R,I triple


@pytest.mark.parametrize(
    ("header", "rows", "args", "wanted"),
    [
        ("cycles,result", ["2,0"], [], "the header needs outcome"),
        ("cycles,range,outcome", ["2,1 km,0"], [], "one of cycles or range"),
        ("cycles,outcome", ["2,maybe"], [], "column 'outcome'"),
        ("cycles,outcome", ["two,1"], [], "column 'cycles'"),
        ("cycles,outcome", ["2,1,3"], [], "3 cells"),
        ("cycles,outcome", [], [], "no trials"),
        ("cycles,outcome", ["2,1", "3,1", "4,1"], [], "fix no N50"),
        ("cycles,outcome", ["2,0", "3,0", "4,1", "5,1"], [], "separated by the cycles"),
        ("cycles,outcome", ["2,0", "4,1"], ["--critical-dimension", "2m"], "this file gives"),
        ("range,outcome", ["1 km,0", "2 km,1"], ["--ifov", "1mrad"], "--critical-dimension"),
        ("range,outcome", ["1 km,0"], ["--critical-dimension", "2m"], "the sensor"),
        ("range,outcome", ["1000,0"], ["--critical-dimension", "2m", "--ifov", "1mrad"], "line 3"),
        ("cycles,outcome", ["2,0", "4,1"], ["--transform", "ttpff"], "--transform"),
        ("cycles,outcome", ["2,0", "4,1"], ["--base", "nobody"], "--base"),
        ("cycles,outcome", ["2,0", "4,1"], ["--confidence", "1.5"], "confidence"),
        ("cycles,outcome", ["2,0", "4,1"], ["--format", "xml"], "--format"),
    ],
)
def test_errors_are_one_line_and_exit_2(capsys, tmp_path, header, rows, args, wanted):
    path = write(tmp_path, "trials.csv", header, rows)
    code, out, err = run(capsys, path, "--task", "recognition", *args)
    assert code == 2 and out == ""
    assert err.startswith("targetacq: error: ") and err.count("\n") == 1
    assert wanted in err


def test_a_missing_file_is_one_line(capsys, tmp_path):
    code, _, err = run(capsys, str(tmp_path / "none.csv"), "--task", "recognition")
    assert code == 2 and "no trials file" in err and err.count("\n") == 1


def test_a_registered_fit_is_a_criterion_of_the_commands_run_in_that_process(capsys):
    import targetacq as ta

    fit = ta.fit_criterion(
        CYCLES, SEEN, "recognition", fit_exponent=False, name="cli-calibration-test"
    )
    try:
        with pytest.raises(SystemExit) as exit_:
            main(["dri", "--example", "--criterion", "cli-calibration-test", "--format", "json"])
        out, err = capsys.readouterr()
        assert exit_.value.code in (0, None), err
        report = json.loads(out)
        thresholds = {row["task"]: row["threshold"] for row in report["ranges"]}
        assert thresholds["recognition"] == pytest.approx(fit.n50, rel=1e-12)
        assert thresholds["identification"] == 6.4  # Johnson's, the base
    finally:
        ta.unregister_criterion("cli-calibration-test")


def test_schmieder_weathersby_takes_its_clutter_region(capsys, cycles_file):
    # Detection in medium clutter (Table 3.5), N50 alone: the grid maximum of the likelihood of
    # the printed curve stretched to each N50 (P held in [1e-15, 1 - 1e-15], as documented).
    import targetacq as ta

    code, out, err = run(capsys, cycles_file, "--task", "detection", "--transform",
                         "schmieder-weathersby", "--region", "medium", "--base", "none",
                         "--format", "json")  # fmt: skip
    assert (code, err) == (0, "")
    report = json.loads(out)
    assert report["exponent_fitted"] is False and report["exponent"] is None
    n50 = np.linspace(1.0, 6.0, 5001)
    p = ta.schmieder_weathersby(np.asarray(CYCLES, float), n50[:, None], region="medium")
    p = np.clip(p, 1e-15, 1 - 1e-15)
    ll = np.sum(np.where(np.asarray(SEEN) == 1, np.log(p), np.log1p(-p)), axis=1)
    assert report["n50"] == pytest.approx(n50[np.argmax(ll)], abs=2e-3)
    code, out, err = run(capsys, cycles_file, "--task", "detection", "--region", "low")
    assert code == 2 and "takes no option(s) region" in err
