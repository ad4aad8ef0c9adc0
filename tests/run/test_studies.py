"""Trade studies: `targetacq sweep`, `dri` with lists and `targetacq.run.studies.sweep`.

Every number of a sweep must equal that of a single `targetacq dri` run with the same values,
serially and on Dask; the clear-path numbers are also checked against the closed forms.
"""

import contextlib
import itertools
import json
import math
import os
import re
import socket
import sys
import time

import numpy as np
import pytest

from targetacq.run import studies
from targetacq.run.studies import local_cluster, sweep, sweep_rows

FOCAL = ["35mm", "50mm", "75mm"]
TARGETS = {"person": "0.75m", "vehicle": "2.3m"}
WEATHERS = ["none", "fog:low"]
PROBABILITIES = ["0.5", "0.9"]
JOHNSON_N50 = {"detection": 1.0, "orientation": 1.4, "recognition": 4.0, "identification": 6.4}


def _single_dri_runs(cli, size="--critical-dimension", sizes=("0.75m", "2.3m")):
    """(focal, size, weather, task, probability) → range_m, from 24 single `dri` runs."""
    expected = {}
    for focal, dim, weather, p in itertools.product(FOCAL, sizes, WEATHERS, PROBABILITIES):
        code, out, err = cli(
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


def test_sweep_equals_24_single_dri_runs_serially(cli, capsys):
    expected = _single_dri_runs(cli)
    code, out, err = cli(
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


def test_sweep_of_named_targets_equals_single_dri_runs(cli, capsys):
    expected = _single_dri_runs(cli, "--target", tuple(TARGETS))
    code, out, err = cli("sweep", *SWEEP_ARGS, "--target", "person,vehicle", "--format", "json")
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


def test_sweep_on_a_local_dask_cluster_equals_single_dri_runs(cli):
    pytest.importorskip("distributed")
    expected = _single_dri_runs(cli)
    with local_cluster(2, processes=False) as cluster:
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


def test_sweep_cli_on_two_worker_processes_equals_serial(cli):
    args = ["sweep", "--example", "--focal-length", "35mm,50mm,75mm", "--obscurant", "none,fog:low"]
    args += ["--band", "lwir", "--format", "csv"]
    code, serial, err = cli(*args)
    assert code == 0, err
    code, on_dask, err = cli(*args, "--workers", "2", "--chunk-size", "2", "--no-progress")
    assert code == 0, err
    assert on_dask == serial
    assert serial.splitlines()[0] == "focal_length,obscurant,task,probability,range_m,reached"


def test_json_keys_are_dri_keys_plus_one_per_swept_option(cli):
    code, out, _ = cli(
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
    dri_keys = set(json.loads(cli("dri", "--example", "--format", "json")[1])["ranges"][0])
    assert {"task", "probability", "range_m", "reached"} <= dri_keys


def test_dri_with_lists_prints_the_sweep(cli):
    for fmt in ("json", "csv", "table"):
        args = ["--example", "--focal-length", "50mm,75mm", "--format", fmt]
        code, from_dri, err = cli("dri", *args)
        assert code == 0, err
        code, from_sweep, _ = cli("sweep", *args)
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
def test_bad_lists_fail_with_one_line(cli, args, message):
    for command in ("sweep", "dri"):
        if command == "dri" and args[0] == "--probability":
            continue  # dri itself takes a list of probabilities
        code, out, err = cli(command, "--example", "--band", "lwir", *args)
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


def test_figure_is_a_png(cli, tmp_path):
    out = tmp_path / "ranges.png"
    code, _, err = cli("sweep", "--example", "--focal-length", "35mm,50mm", "--figure", str(out))
    assert code == 0, err
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_missing_dask_is_one_line_naming_the_extra(cli, monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed fails
    code, _, err = cli("sweep", "--example", "--focal-length", "35mm,50mm", "--workers", "1")
    assert code == 2 and "pip install 'targetacq[sweep]'" in err and err.count("\n") == 1


def test_small_sweeps_run_serially_without_dask(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)
    ds = sweep({"example": True, "focal_length": "35mm,50mm", "scr": "1,2,3"})
    assert ds["range"].shape[:2] == (2, 3) and not math.isnan(float(ds["range"].max()))


def test_sweep_cli_on_an_existing_scheduler_by_address(cli):
    pytest.importorskip("distributed")
    args = ["sweep", "--example", "--focal-length", "35mm,50mm,75mm", "--scr", "1,2"]
    code, serial, err = cli(*args, "--format", "csv")
    assert code == 0, err
    with local_cluster(2, processes=False) as cluster:
        address = cluster.scheduler_address
        code, on_dask, err = cli(*args, "--format", "csv", "--scheduler", address)
    assert code == 0, err
    assert on_dask == serial


# -- Dask: no fixed port, workers capped at the CPUs, a lost scheduler, the size up front ------

QUICK_SWEEP = ["sweep", "--example", "--focal-length", "35mm,50mm", "--scr", "1,2"]


@contextlib.contextmanager
def _port_taken(port):
    """``port`` held by a listening socket (a notebook's Dask dashboard), or by whoever holds
    it already."""
    with socket.socket() as held:
        with contextlib.suppress(OSError):  # taken already: the condition holds as well
            held.bind(("", port))
            held.listen()
        yield


def test_the_dask_paths_run_with_port_8787_taken(cli):
    # Dask's default dashboard port: its scheduler took it (and warned when it could not) even
    # with the dashboard off, so `make test` failed (2 failed, 2 errors) and a user's
    # `sweep --workers` printed a warning.
    pytest.importorskip("distributed")
    code, serial, err = cli(*QUICK_SWEEP, "--format", "csv")
    assert code == 0, err
    with _port_taken(8787):
        code, on_dask, err = cli(*QUICK_SWEEP, "--format", "csv", "--workers", "1")
        assert (code, err) == (0, ""), err
        with local_cluster(1, processes=False) as cluster:
            ds = sweep({"example": True, "focal_length": "35mm,50mm"}, scheduler=cluster)
    assert on_dask == serial
    assert ds["range"].sizes["focal_length"] == 2


def test_workers_beyond_the_cpus_are_capped_with_a_one_line_note(cli, monkeypatch):
    pytest.importorskip("distributed")
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0}, raising=False)
    monkeypatch.setattr(os, "cpu_count", lambda: 1)
    started = []
    real = studies.local_cluster

    def in_threads(workers=None, **kwargs):
        cluster = real(workers, processes=False)
        started.append(len(cluster.workers))
        return cluster

    monkeypatch.setattr(studies, "local_cluster", in_threads)
    code, _, err = cli(*QUICK_SWEEP, "--format", "csv", "--workers", "64")
    assert code == 0, err
    assert err == (
        "targetacq: warning: workers 64 is more than the CPUs this process may use (1): using 1\n"
    )
    assert started == [1]
    with pytest.warns(UserWarning, match=r"\(1\): using 1$"):
        assert studies.cluster_workers(64) == 1


def test_a_sweep_beyond_the_point_limit_is_refused_before_any_work(cli, monkeypatch):
    # A 9-million-point sweep failed after 178 s; 1,001 x 1,000 points is refused at once.
    monkeypatch.setattr(studies, "option_product", lambda *a: pytest.fail("work started"))
    focal = ",".join(f"{v}mm" for v in range(10, 1011))
    scr = ",".join(str(v) for v in range(1, 1001))
    code, _, err = cli("sweep", "--example", "--focal-length", focal, "--scr", scr)
    assert code == 2
    assert err == (
        "targetacq: error: the sweep of 1,001,000 points (1,001 --focal-length x 1,000 --scr) "
        "is more than the limit of 1,000,000 points (targetacq.run.studies.MAX_SWEEP_POINTS); "
        "sweep fewer values, or split the study\n"
    )
    with pytest.raises(ValueError, match=r"1,000,000 points"):
        sweep({"example": True, "focal_length": focal, "scr": scr})


def test_a_sweep_beyond_the_memory_is_refused_with_its_estimate(cli, monkeypatch):
    monkeypatch.setattr("targetacq.base.limits.available_memory", lambda: 10_000)
    monkeypatch.setattr(studies, "option_product", lambda *a: pytest.fail("work started"))
    code, _, err = cli(*QUICK_SWEEP, "--probability", "0.5,0.9")
    assert code == 2 and err.count("\n") == 1, err
    # 4 points x 2,048 B + 4 points x 4 tasks x 2 probabilities x 1,024 B = 40,960 B
    assert "the sweep of 4 points (2 --focal-length x 2 --scr) at 8 values each needs " in err
    assert "about 4.1e+04 bytes" in err
    assert studies.sweep_bytes(4, 32) == 40_960


_LOSE = {}


def _block_losing_the_scheduler(points, grid, default_probability):
    """The sweep's block of work; the second one closes the scheduler under the sweep."""
    _LOSE["calls"] += 1
    if _LOSE["calls"] == 2:
        _LOSE["cluster"].loop.add_callback(_LOSE["cluster"].scheduler.close)
        time.sleep(0.5)
    return _LOSE["block"](points, grid, default_probability)


def test_losing_the_scheduler_mid_sweep_is_one_line(cli, monkeypatch):
    # An 85-line FutureCancelledError traceback with exit status 1 before.
    dask = pytest.importorskip("dask")
    pytest.importorskip("distributed")
    _LOSE.update(calls=0, block=studies._block)
    monkeypatch.setattr(studies, "_block", _block_losing_the_scheduler)
    args = ["--focal-length", "35mm,50mm,75mm,100mm", "--scr", "1,2,3", "--chunk-size", "2"]
    with (
        dask.config.set({"distributed.comm.timeouts.connect": "2s"}),  # the client's reconnect
        local_cluster(1, processes=False) as cluster,
    ):
        _LOSE["cluster"] = cluster
        address = cluster.scheduler_address
        code, _, err = cli("sweep", "--example", *args, "--scheduler", address)
    assert code == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert err.startswith(f"targetacq: error: the Dask scheduler {address} was lost during the ")
    assert "scheduler-connection-lost" in err and "re-run the sweep" in err


# -- blocks: the points of a block stacked into arrays, the numbers of each point alone -------

MRTD_CSV = os.path.join(
    os.path.dirname(__file__), "..", "..", "src", "targetacq", "data", "example_mrtd.csv"
)


def _points(**options):
    """The points of a sweep of ``options`` (every option of ``dri``, None where not given)."""
    from targetacq.run.option_table import option_product

    return [full for _, full in option_product(studies._text_options(options))]


def _mixed_points():
    """Points of many groups: clear and fog, two cycles criteria, sensor noise and clutter,
    conditional semantics, an MRTD curve and a pixel-density criterion, interleaved."""
    focal = ["35mm", "50mm", "75mm"]
    groups = [
        _points(
            pitch="12um",
            focal_length=focal,
            critical_dimension=["0.75m", "2.3m"],
            band="lwir",
            obscurant=["none", "fog:low", "haze:high"],
            criterion=["johnson", "c2nveo"],
        ),
        _points(
            example=True,
            netd=["30mK", "50mK"],
            delta_t=["0.5K", "2K"],
            extinction=["0.2/km", "3/km"],
            scr=["1", "5"],
        ),
        _points(
            ifov=["0.2mrad", "0.34mrad"],
            critical_dimension="2.3m",
            mrtd=MRTD_CSV,
            delta_t=["70mK", "2K"],
            extinction=["0.5/km", "1e300/km"],
            semantics=["nested", "conditional"],
        ),
        _points(pitch="12um", focal_length=focal, criterion="en62676-4", probability=None),
        _points(
            hfov=["10deg", "24deg"],
            pixels=["640", "1280"],
            projection=["angular", "rectilinear"],
            critical_dimension="2.3m",
        ),
        _points(
            pitch="12um",
            focal_length=focal,
            pixels="640",
            criterion="en62676-4",
            pixel_density=["plane", "arc"],
            probability=None,
        ),
        _points(
            pitch="17um",
            focal_length=focal,
            f_number=["1", "1.4"],
            wavelength="10um",
            critical_dimension="2.3m",
        ),
    ]
    mixed = [p for chunk in itertools.zip_longest(*groups) for p in chunk if p is not None]
    assert len(mixed) == 36 + 16 + 16 + 3 + 8 + 6 + 6
    return mixed


def _assert_same(got, expected):
    """Equal to 1e-12 relative, NaN where NaN and inf where inf."""
    assert got.shape == expected.shape
    np.testing.assert_array_equal(np.isnan(got), np.isnan(expected))
    np.testing.assert_array_equal(np.isinf(got), np.isinf(expected))
    finite = np.isfinite(expected)
    np.testing.assert_allclose(got[finite], expected[finite], rtol=1e-12, atol=0)


def test_a_block_of_mixed_points_equals_each_point_alone():
    points = _mixed_points()
    alone = [studies._point(dict(p), None, "0.5,0.9") for p in points]
    assert any(np.isnan(values).any() for _, values in alone)  # some never reached
    for block in (points, points[::-1]):  # in any order: each point's own numbers
        found = studies._block(block, None, "0.5,0.9")
        expected = alone if block is points else alone[::-1]
        assert len(found) == len(block)
        for (tasks, values), (want_tasks, want) in zip(found, expected, strict=True):
            assert tasks == want_tasks
            _assert_same(values, want)
    assert {tasks for tasks, _ in alone} >= {
        ("detection", "orientation", "recognition", "identification"),
        ("detection", "recognition", "identification"),
        ("monitoring", "detection", "observation", "recognition", "identification", "inspection"),
    }


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"focal_length": ["50mm", "-3mm", "75mm"]}, "--focal-length must be > 0"),
        ({"critical_dimension": ["2.3m", "nanm"]}, "--critical-dimension"),
        # 1e-320 m over 1e9 m underflows to an IFOV of 0: the kernel's check, on the arrays
        ({"pitch": ["12um", "1e-320m"], "focal_length": "1e9m"}, "--pitch 1e-320m over"),
        ({"pitch": ["12um", "1e9m"], "focal_length": ["1mm", "2mm"]}, "--pitch 1e9m over"),
        (
            {"hfov": ["10deg", "190deg"], "pixels": "640", "pitch": None, "focal_length": None},
            "--hfov must be in",
        ),
        ({"noise_model": "variance-sum", "obscurant": ["fog:low", "none"]}, "--noise-model"),
    ],
)
def test_a_bad_value_in_a_block_is_the_error_of_its_point_alone(options, message):
    """A bad value among good ones: the block raises the ValueError of that point computed
    alone (naming the option and the value), whichever group it falls in."""
    from targetacq.run.range_options import range_setup

    chosen = {"pitch": "12um", "focal_length": "50mm", "critical_dimension": "2.3m"}
    chosen |= {"band": "lwir"} | options
    points = _points(**{k: v for k, v in chosen.items() if v is not None})
    errors = []
    for point in points:
        try:
            range_setup(point, "0.5")
        except ValueError as error:
            errors.append(str(error))
    assert len(errors) >= 1 and message in errors[0]
    with pytest.raises(ValueError, match=re.escape(message)) as raised:
        studies._block(points, None, "0.5")
    assert str(raised.value) == errors[0]


def test_a_block_at_ranges_equals_each_point_alone():
    points = [p for p in _mixed_points() if p["criterion"] != "en62676-4"]
    grid = np.array([100.0, 700.0, 2500.0, 9000.0])
    found = studies._block(points, grid, "0.5")
    for options, (tasks, values) in zip(points, found, strict=True):
        want_tasks, want = studies._point(dict(options), grid, "0.5")
        assert tasks == want_tasks
        _assert_same(values, want)


def test_a_group_of_points_is_one_solve_per_probability(monkeypatch):
    calls = []
    real = studies.case_ranges

    def counted(case, probability):
        calls.append(np.shape(case.ifov))
        return real(case, probability)

    monkeypatch.setattr(studies, "case_ranges", counted)
    points = _points(
        pitch="12um",
        focal_length=FOCAL,
        critical_dimension=["0.75m", "2.3m"],
        band="lwir",
        obscurant=["none", "fog:low"],
    )
    studies._block(points, None, "0.5,0.9")
    # two groups (clear, fog) of 6 points each, two probabilities: four solves of 6 points
    assert calls == [(6,)] * 4


def test_blocks_are_large_on_dask_and_every_250_points_serially():
    points = [{}] * 100_000
    on = "tcp://scheduler:8786"  # workers as given (a local cluster has at most one per CPU)
    sizes = [len(b) for b in studies._blocks(points, None, on, 4, serial=False)]
    assert sizes == [6250] * 16  # four blocks per worker
    sizes = [len(b) for b in studies._blocks(points * 10, None, on, 4, serial=False)]
    assert sizes == [10_000] * 100  # at most 10,000 points a block
    assert [len(b) for b in studies._blocks(points[:1001], None, on, 16, serial=False)] == (
        [100] * 10 + [1]
    )  # at least 100
    assert [len(b) for b in studies._blocks(points[:600], None, None, None, serial=True)] == (
        [250, 250, 100]
    )
    assert [len(b) for b in studies._blocks(points[:5], 2, None, None, serial=True)] == [2, 2, 1]
