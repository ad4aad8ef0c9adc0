"""Trade studies: `targetacq sweep`, `dri` with lists and `targetacq.studies.sweep`.

Every number of a sweep must equal that of a single `targetacq dri` run with the same values,
serially and on Dask; the clear-path numbers are also checked against the closed forms.
"""

import itertools
import json
import math
import sys

import numpy as np
import pytest

from targetacq.cli import main
from targetacq.studies import sweep, sweep_rows

FOCAL = ["35mm", "50mm", "75mm"]
TARGETS = {"person": "0.75m", "vehicle": "2.3m"}
WEATHERS = ["none", "fog:low"]
PROBABILITIES = ["0.5", "0.9"]
JOHNSON_N50 = {"detection": 1.0, "orientation": 1.4, "recognition": 4.0, "identification": 6.4}


def run(capsys, *args):
    with pytest.raises(SystemExit) as done:
        main(list(args))
    out, err = capsys.readouterr()
    return done.value.code, out, err


def _single_dri_runs(capsys, size="--critical-dimension", sizes=("0.75m", "2.3m")):
    """(focal, size, weather, task, probability) → range_m, from 24 single `dri` runs."""
    expected = {}
    for focal, dim, weather, p in itertools.product(FOCAL, sizes, WEATHERS, PROBABILITIES):
        code, out, err = run(
            capsys,
            "dri",
            "--pitch",
            "12um",
            "--focal-length",
            focal,
            size,
            dim,
            "--band",
            "lwir",
            "--obscurant",
            weather,
            "--probability",
            p,
            "--format",
            "json",
        )
        assert code == 0, err
        for row in json.loads(out)["ranges"]:
            expected[focal, dim, weather, row["task"], row["probability"]] = row["range_m"]
    assert len(expected) == 24 * 4
    return expected


SWEEP_ARGS = [
    "--pitch",
    "12um",
    "--focal-length",
    ",".join(FOCAL),
    "--band",
    "lwir",
    "--obscurant",
    ",".join(WEATHERS),
    "--probability",
    ",".join(PROBABILITIES),
]


def test_sweep_equals_24_single_dri_runs_serially(capsys):
    expected = _single_dri_runs(capsys)
    code, out, err = run(
        capsys,
        "sweep",
        *SWEEP_ARGS,
        "--critical-dimension",
        ",".join(TARGETS.values()),
        "--format",
        "json",
    )
    assert code == 0, err
    rows = json.loads(out)["ranges"]
    got = {
        (
            r["focal_length"],
            r["critical_dimension"],
            r["obscurant"],
            r["task"],
            r["probability"],
        ): r["range_m"]
        for r in rows
    }
    assert got == expected  # exactly: the same code path
    # the fog shortens every range; the clear path is the closed form d / (N50 · 2 pitch / f)
    for focal, dim, task in itertools.product(FOCAL, TARGETS.values(), JOHNSON_N50):
        clear = expected[focal, dim, "none", task, 0.5]
        cycle = 2 * 12e-6 / (float(focal[:-2]) * 1e-3)
        assert clear == pytest.approx(float(dim[:-1]) / (JOHNSON_N50[task] * cycle), rel=1e-12)
        assert expected[focal, dim, "fog:low", task, 0.5] < clear


def test_sweep_of_named_targets_equals_single_dri_runs(capsys):
    expected = _single_dri_runs(capsys, "--target", tuple(TARGETS))
    code, out, err = run(
        capsys, "sweep", *SWEEP_ARGS, "--target", "person,vehicle", "--format", "json"
    )
    assert code == 0, err
    got = {
        (r["focal_length"], r["target"], r["obscurant"], r["task"], r["probability"]): r["range_m"]
        for r in json.loads(out)["ranges"]
    }
    assert got == expected


def _options():
    return {
        "pitch": "12um",
        "focal_length": FOCAL,  # a Python list
        "critical_dimension": ",".join(TARGETS.values()),  # or comma text, as on the CLI
        "band": "lwir",
        "obscurant": WEATHERS,
        "probability": [0.5, 0.9],
    }


def test_sweep_on_a_local_dask_cluster_equals_single_dri_runs(capsys):
    distributed = pytest.importorskip("distributed")
    expected = _single_dri_runs(capsys)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
    ) as cluster:
        ds = sweep(_options(), scheduler=cluster, chunk_size=5)
    assert ds["range"].dims == (
        "focal_length",
        "critical_dimension",
        "obscurant",
        "task",
        "probability",
    )
    for focal, dim, weather, task, p in expected:
        value = float(
            ds["range"].sel(
                focal_length=focal,
                critical_dimension=dim,
                obscurant=weather,
                task=task,
                probability=p,
            )
        )
        assert value == expected[focal, dim, weather, task, p]
    serial = sweep(_options())
    np.testing.assert_array_equal(serial["range"].values, ds["range"].values)


def test_sweep_cli_on_two_worker_processes_equals_serial(capsys):
    args = ["sweep", "--example", "--focal-length", "35mm,50mm,75mm", "--obscurant", "none,fog:low"]
    args += ["--band", "lwir", "--format", "csv"]
    code, serial, err = run(capsys, *args)
    assert code == 0, err
    code, on_dask, err = run(capsys, *args, "--workers", "2", "--chunk-size", "2", "--no-progress")
    assert code == 0, err
    assert on_dask == serial
    assert serial.splitlines()[0] == "focal_length,obscurant,task,probability,range_m,reached"


def test_json_keys_are_dri_keys_plus_one_per_swept_option(capsys):
    code, out, _ = run(
        capsys,
        "sweep",
        "--example",
        "--focal-length",
        "50mm,75mm",
        "--scr",
        "1,2",
        "--format",
        "json",
    )
    assert code == 0
    document = json.loads(out)
    row = document["ranges"][0]
    assert list(row) == ["focal_length", "scr", "task", "probability", "range_m", "reached"]
    assert row["scr"] == 1.0 and row["focal_length"] == "50mm"
    assert len(document["ranges"]) == 2 * 2 * 4
    assert document["meta"]["version"] and len(document["meta"]["options_sha256"]) == 64
    dri_keys = set(json.loads(run(capsys, "dri", "--example", "--format", "json")[1])["ranges"][0])
    assert {"task", "probability", "range_m", "reached"} <= dri_keys


def test_dri_with_lists_prints_the_sweep(capsys):
    for fmt in ("json", "csv", "table"):
        args = ["--example", "--focal-length", "50mm,75mm", "--format", fmt]
        code, from_dri, err = run(capsys, "dri", *args)
        assert code == 0, err
        code, from_sweep, _ = run(capsys, "sweep", *args)
        if fmt == "json":  # the provenance's time of creation may differ by a second
            assert json.loads(from_dri)["ranges"] == json.loads(from_sweep)["ranges"]
        else:
            assert from_dri == from_sweep
    assert "50mm" in from_dri and "identification" in from_dri


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--focal-length", "35mm,,50mm"], "--focal-length: empty item"),
        (["--focal-length", "35mm,35mm"], "--focal-length: a value appears twice"),
        (["--focal-length", "35mm,"], "--focal-length: empty item"),
        (["--probability", "0.5,0.5"], "--probability: a value appears twice"),
        (["--obscurant", "none,smog"], "--obscurant must be one of"),
        (["--scr", "1,x"], "--scr must be a number"),
    ],
)
def test_bad_lists_fail_with_one_line(capsys, args, message):
    for command in ("sweep", "dri"):
        if command == "dri" and args[0] == "--probability":
            continue  # dri itself takes a list of probabilities
        code, out, err = run(capsys, command, "--example", "--band", "lwir", *args)
        assert code == 2 and out == ""
        assert err.count("\n") == 1 and err.startswith("targetacq: error: ") and message in err


def test_python_lists_are_checked_like_comma_text():
    with pytest.raises(ValueError, match="--focal-length: a value appears twice"):
        sweep({"example": True, "focal_length": ["50mm", "50mm"]})
    with pytest.raises(ValueError, match="focal_length: empty list"):
        sweep({"example": True, "focal_length": []})
    with pytest.raises(ValueError, match="unknown sweep option"):
        sweep({"example": True, "focal": ["50mm", "75mm"]})


def test_probabilities_at_ranges_follow_the_ttpf_closed_form():
    ranges = [250.0, 500.0, 1000.0, 2000.0]
    ds = sweep(
        {"pitch": "12um", "focal_length": ["35mm", "75mm"], "critical_dimension": "2.3m"},
        ranges=ranges,
    )
    assert ds["probability"].dims == ("focal_length", "task", "range")
    for focal in ("35mm", "75mm"):
        cycle = 2 * 12e-6 / (float(focal[:-2]) * 1e-3)
        for task in ("detection", "recognition", "identification"):
            for r in ranges:
                x = 2.3 / (r * cycle) / JOHNSON_N50[task]
                e = 2.7 + 0.7 * x  # TTPF, Eq. (3.2)
                p = x**e / (1 + x**e)
                got = float(ds["probability"].sel(focal_length=focal, task=task, range=r))
                assert got == pytest.approx(p, rel=1e-12)
    assert ds["range"].attrs["units"] == "m"


def test_never_reached_is_nan_and_null(capsys):
    ds = sweep({"example": True, "extinction": ["0.1/km", "1e300/km"]})
    opaque = ds["range"].sel(extinction="1e300/km").values
    assert np.isnan(opaque).all() and np.isfinite(ds["range"].sel(extinction="0.1/km")).all()
    rows = [r for r in sweep_rows(ds) if r["extinction"] == "1e300/km"]
    assert all(r["range_m"] is None and r["reached"] is False for r in rows)
    np.testing.assert_allclose(ds["extinction_per_m"].values, [1e-4, 1e297])


def test_figure_is_a_png(capsys, tmp_path):
    out = tmp_path / "ranges.png"
    code, _, err = run(
        capsys, "sweep", "--example", "--focal-length", "35mm,50mm", "--figure", str(out)
    )
    assert code == 0, err
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_missing_dask_is_one_line_naming_the_extra(capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed fails
    code, _, err = run(
        capsys, "sweep", "--example", "--focal-length", "35mm,50mm", "--workers", "1"
    )
    assert code == 2 and "pip install 'targetacq[sweep]'" in err and err.count("\n") == 1


def test_small_sweeps_run_serially_without_dask(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)
    ds = sweep({"example": True, "focal_length": "35mm,50mm", "scr": "1,2,3"})
    assert ds["range"].shape[:2] == (2, 3) and not math.isnan(float(ds["range"].max()))


def test_sweep_cli_on_an_existing_scheduler_by_address(capsys):
    distributed = pytest.importorskip("distributed")
    args = ["sweep", "--example", "--focal-length", "35mm,50mm,75mm", "--scr", "1,2"]
    code, serial, err = run(capsys, *args, "--format", "csv")
    assert code == 0, err
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
    ) as cluster:
        address = cluster.scheduler_address
        code, on_dask, err = run(capsys, *args, "--format", "csv", "--scheduler", address)
    assert code == 0, err
    assert on_dask == serial
