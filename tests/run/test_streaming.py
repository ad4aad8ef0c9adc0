"""Streamed results (targetacq.run.streaming): the file holds what Results.write writes for the same
run, in every format, whatever the chunks; rows come chunk by chunk; atomic, umask; the
command line's evaluate streams and its summary is the whole run's."""

import contextlib
import json
import os
import stat
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest
import xarray as xr
from hypothesis import given
from hypothesis import strategies as st

from targetacq.cli import main
from targetacq.cli.scenarios import _Peaks
from targetacq.io.datasets import OUTPUT_FORMATS
from targetacq.run import streaming
from targetacq.run.model_chain import ModelChain
from targetacq.run.streaming import CHUNK_TRIPLES, chunk_sizes, write_chunks
from targetacq.scenario.schema import load_scenario

ROOT = Path(__file__).parents[2]
SCENARIOS = [
    *sorted((ROOT / "examples").glob("*.toml")),
    ROOT / "tests" / "data" / "golden" / "terrain.toml",  # SCR per triple (a terrain map)
]
IDS = [p.stem for p in SCENARIOS]
FORMATS = sorted(OUTPUT_FORMATS)
KEY = ["sensor", "target", "time"]
META = {"scenario_file": "scene.toml", "note": ["a", 1]}
SMALL: dict[str, Any] = {"targets_per_chunk": 1, "times_per_chunk": 3}  # times split


@pytest.fixture(scope="module", params=SCENARIOS, ids=IDS)
def chain(request):
    return ModelChain(load_scenario(request.param))


def _written(chain, tmp_path, suffix, **chunks):
    """The in-memory write and the streamed write of the same run."""
    whole = chain.evaluate().write(tmp_path / f"whole.{suffix}", META)
    streamed = write_chunks(chain, tmp_path / f"streamed.{suffix}", meta=META, **chunks)
    return whole, streamed


def _without_created(meta):
    assert meta.pop("created")  # a timestamp: the two writes are made at different times
    return meta


def _open(path):
    ds = xr.open_zarr(path).load() if path.suffix == ".zarr" else xr.load_dataset(path)
    _without_created(ds.attrs)
    return ds


def _in_run_order(frame, chain):
    """Rows sorted by sensor, target and time in the scenario's order."""
    order = frame.assign(
        _s=frame["sensor"].map({n: i for i, n in enumerate(chain.sensor_names)}),
        _g=frame["target"].map({n: i for i, n in enumerate(chain.target_names)}),
    )
    order = order.sort_values(["_s", "_g", "time"], kind="stable")
    return order.drop(columns=["_s", "_g"]).reset_index(drop=True)


def _chunk_order(chain, **chunks):
    """(sensor, target, time) of every row in the documented order: chunk by chunk, and
    within a chunk by sensor, target and time; built from evaluate_chunks' chunks."""
    rows = []
    for targets, times, _ in chain.evaluate_chunks(**chunks):
        for sensor in chain.sensor_names:
            for target in chain.target_names[targets]:
                rows += [(sensor, target, float(t)) for t in times]
    return rows


# --- the same content as Results.write ------------------------------------------------------


@pytest.mark.parametrize("chunks", [{}, SMALL], ids=["default", "small"])
def test_parquet_equals_the_in_memory_write(chain, tmp_path, chunks):
    whole, streamed = _written(chain, tmp_path, "parquet", **chunks)
    a, b = pq.read_table(whole), pq.read_table(streamed)
    assert b.schema.equals(a.schema, check_metadata=False)
    for field in a.schema:  # units and long names
        assert b.schema.field(field.name).metadata == field.metadata, field.name
    assert b.schema.metadata[b"pandas"] == a.schema.metadata[b"pandas"]
    meta = _without_created(json.loads(b.schema.metadata[b"targetacq"]))
    assert meta == _without_created(json.loads(a.schema.metadata[b"targetacq"]))
    assert meta["scenario_file"] == "scene.toml" and meta["scenario_sha256"]
    expected, got = a.to_pandas(), b.to_pandas()
    if not chunks:  # one chunk: the very same rows in the same order
        assert chain.evaluate().dataset["detection"].size <= CHUNK_TRIPLES
        pd.testing.assert_frame_equal(got, expected)
    else:
        assert list(got[KEY].itertuples(index=False, name=None)) == _chunk_order(chain, **chunks)
        pd.testing.assert_frame_equal(_in_run_order(got, chain), _in_run_order(expected, chain))
    n_chunks = sum(1 for _ in chain.evaluate_chunks(**chunks)) if chunks else 1
    assert pq.ParquetFile(streamed).metadata.num_row_groups == n_chunks


@pytest.mark.parametrize("chunks", [{}, SMALL], ids=["default", "small"])
def test_csv_equals_the_in_memory_write(chain, tmp_path, chunks):
    whole, streamed = _written(chain, tmp_path, "csv", **chunks)
    a, b = whole.read_text(), streamed.read_text()
    # Units and provenance first ("#" lines): the same but for the moment each was created.
    a_head, b_head = ([x for x in t.splitlines() if x.startswith("#")] for t in (a, b))
    assert a_head[0] == b_head[0] and a_head[0].startswith("# units: sensor, target, time [s]")
    provenance = [json.loads(h[1].removeprefix("# provenance: ")) for h in (a_head, b_head)]
    assert _without_created(provenance[0]) == _without_created(provenance[1])
    a, b = ("\n".join(x for x in t.splitlines() if not x.startswith("#")) for t in (a, b))
    if not chunks:
        assert b == a  # byte for byte
        return
    header, *rows = b.splitlines()
    assert header == a.splitlines()[0]
    assert sorted(rows) == sorted(a.splitlines()[1:])
    got = pd.read_csv(streamed, comment="#")
    assert list(got[KEY].itertuples(index=False, name=None)) == _chunk_order(chain, **chunks)


@pytest.mark.parametrize("chunks", [{}, SMALL], ids=["default", "small"])
def test_json_equals_the_in_memory_write(chain, tmp_path, chunks, monkeypatch):
    monkeypatch.setattr(streaming, "_JSON_ROWS", 7)  # each chunk's rows in several pieces
    whole, streamed = _written(chain, tmp_path, "json", **chunks)
    a, b = json.loads(whole.read_text()), json.loads(streamed.read_text())
    assert _without_created(b["meta"]) == _without_created(a["meta"])
    assert b["meta"]["variables"]["snr"]["units"] == "dB"
    if not chunks:
        assert b["rows"] == a["rows"]
        created = (json.loads(p.read_text())["meta"]["created"] for p in (streamed, whole))
        text = streamed.read_text().replace(*created)
        assert text == whole.read_text()  # byte for byte but the time of writing
        return
    rows = [(r["sensor"], r["target"], r["time"]) for r in b["rows"]]
    assert rows == _chunk_order(chain, **chunks)
    position = {(r["sensor"], r["target"], r["time"]): i for i, r in enumerate(a["rows"])}
    in_run_order = sorted(b["rows"], key=lambda r: position[r["sensor"], r["target"], r["time"]])
    assert in_run_order == a["rows"]


@pytest.mark.parametrize("suffix", ["nc", "zarr"])
@pytest.mark.parametrize("chunks", [{}, SMALL], ids=["default", "small"])
def test_netcdf_and_zarr_equal_the_in_memory_write(chain, tmp_path, suffix, chunks):
    whole, streamed = _written(chain, tmp_path, suffix, **chunks)
    expected, got = _open(whole), _open(streamed)
    xr.testing.assert_identical(got, expected)  # values, dtypes, attributes, provenance
    for name in expected.variables:
        assert got[name].dtype == expected[name].dtype, name
    assert got.attrs["scenario_file"] == "scene.toml"
    assert json.loads(got.attrs["note"]) == ["a", 1]


def test_times_given_equal_the_in_memory_write_at_those_times(tmp_path):
    chain = ModelChain(load_scenario(SCENARIOS[0]))
    times = [7.5, float("nan"), 0.0, 3.0]  # any order; a NaN time gives NaN results
    for suffix in FORMATS:
        whole = chain.evaluate(times).write(tmp_path / f"whole.{suffix}")
        streamed = write_chunks(chain, tmp_path / f"streamed.{suffix}", times, times_per_chunk=3)
        if suffix in ("nc", "zarr"):
            xr.testing.assert_identical(_open(streamed), _open(whole))
        elif suffix == "parquet":
            got, expected = pd.read_parquet(streamed), pd.read_parquet(whole)
            assert len(got) == len(expected) == chain.evaluate(times).dataset["range"].size
            pd.testing.assert_frame_equal(
                got.sort_values(KEY).reset_index(drop=True),
                expected.sort_values(KEY).reset_index(drop=True),
            )


# --- chunks, progress, failures --------------------------------------------------------------


def test_on_chunk_sees_every_triple_once(tmp_path):
    chain = ModelChain(load_scenario(ROOT / "examples" / "two_sensors_fused.toml"))
    seen = []

    def on_chunk(targets, times, arrays):
        seen.append((targets, tuple(times), arrays["detection"].shape))

    write_chunks(chain, tmp_path / "r.parquet", on_chunk=on_chunk, **SMALL)
    expected = [
        (targets, tuple(times), arrays["detection"].shape)
        for targets, times, arrays in chain.evaluate_chunks(**SMALL)
    ]
    assert seen == expected
    n_times = len(chain.scenario.time.times())
    assert sum(int(np.prod(shape)) for *_, shape in seen) == 2 * 2 * n_times


@pytest.mark.parametrize("suffix", FORMATS)
def test_a_failure_midway_leaves_the_previous_file_and_no_temporary(tmp_path, suffix):
    chain = ModelChain(load_scenario(ROOT / "examples" / "two_sensors_fused.toml"))
    out = write_chunks(chain, tmp_path / f"r.{suffix}")
    before = sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*"))
    calls = []

    def fail_on_the_second(*_):
        calls.append(1)
        if len(calls) == 2:
            raise ValueError("stopped")

    with pytest.raises(ValueError, match="stopped"):
        write_chunks(chain, out, on_chunk=fail_on_the_second, **SMALL)
    assert sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*")) == before
    assert not [p for p in tmp_path.iterdir() if "targetacq-tmp" in p.name]


def test_bad_sizes_and_suffixes_are_refused_before_any_work(tmp_path):
    chain = ModelChain(load_scenario(ROOT / "examples" / "two_sensors_fused.toml"))
    bad_sizes: list[Any] = [0, -1, 2.5, True]
    for bad in bad_sizes:
        with pytest.raises(ValueError, match="targets_per_chunk must be an integer >= 1"):
            write_chunks(chain, tmp_path / "r.csv", targets_per_chunk=bad)
        with pytest.raises(ValueError, match="times_per_chunk must be an integer >= 1"):
            write_chunks(chain, tmp_path / "r.csv", times_per_chunk=bad)
    with pytest.raises(ValueError, match=r"must end in .*\.parquet.*\.zarr"):
        write_chunks(chain, tmp_path / "r.xlsx")
    with pytest.raises(ValueError, match="does not exist"):
        write_chunks(chain, tmp_path / "no" / "r.csv")
    assert list(tmp_path.iterdir()) == []


@contextlib.contextmanager
def _umask(mask):
    old = os.umask(mask)
    try:
        yield
    finally:
        os.umask(old)


def test_files_are_0644_and_folders_0755_under_umask_022(tmp_path):
    chain = ModelChain(load_scenario(ROOT / "examples" / "two_sensors_fused.toml"))
    with _umask(0o022):
        for suffix in FORMATS:
            out = write_chunks(chain, tmp_path / f"r.{suffix}", **SMALL)
            if out.is_dir():
                assert stat.S_IMODE(out.stat().st_mode) == 0o755
                files = [p for p in out.rglob("*") if p.is_file()]
                assert files and {stat.S_IMODE(p.stat().st_mode) for p in files} == {0o644}
            else:
                assert stat.S_IMODE(out.stat().st_mode) == 0o644


@given(st.integers(1, 10**4), st.integers(1, 10**5), st.integers(1, 10**5), st.integers(1, 10**7))
def test_chunk_sizes_stay_within_the_budget(n_sensors, n_targets, n_times, triples):
    per_target, per_time = chunk_sizes(n_sensors, n_targets, n_times, triples)
    assert 1 <= per_target <= n_targets and 1 <= per_time <= n_times
    assert n_sensors * per_target * per_time <= max(triples, n_sensors)
    if n_sensors * n_times <= triples:  # all times in a chunk: a block of targets is whole
        assert per_time == n_times
        assert per_target == min(n_targets, triples // (n_sensors * n_times))


def test_chunk_sizes_refuse_an_empty_budget():
    with pytest.raises(ValueError, match="triples must be >= 1; got 0"):
        chunk_sizes(1, 1, 1, 0)


# --- the command line -----------------------------------------------------------------------


def _run(capsys, *args):
    with pytest.raises(SystemExit) as done:
        main([str(a) for a in args])
    out, err = capsys.readouterr()
    return done.value.code, out, err


@given(
    st.lists(st.one_of(st.floats(0, 1), st.just(float("nan"))), min_size=1, max_size=12).flatmap(
        lambda s: st.tuples(st.just(s), st.integers(1, len(s)))
    )
)
def test_peaks_gathered_by_chunk_are_those_of_argmax_over_the_whole_series(series_and_chunk):
    series, per_time = series_and_chunk
    values = np.array([series, series[::-1]])  # two targets, (target, time)
    times = np.arange(values.shape[1]) * 10.0
    peaks = _Peaks(2)
    for first in range(0, values.shape[1], per_time):
        part = values[:, first : first + per_time]
        arrays = {f"fused_{t}": part for t in ("detection", "recognition", "identification")}
        arrays["in_view"] = np.ones((1, *part.shape), dtype=bool)
        peaks.add(slice(0, 2), times[first : first + per_time], arrays)
    for g in range(2):
        best = int(np.argmax(values[g]))
        np.testing.assert_array_equal(peaks.value["detection"][g], values[g, best])
        assert peaks.at["recognition"][g] == times[best]
    assert list(peaks.in_view_steps) == [len(series)] * 2


@pytest.mark.parametrize("scenario", SCENARIOS, ids=IDS)
def test_evaluate_summary_is_the_whole_runs(capsys, tmp_path, scenario):
    out_file = tmp_path / "r.parquet"
    code, out, err = _run(capsys, "evaluate", scenario, "--format", "json", "--out", out_file)
    assert code == 0, err
    rows = next(iter(json.loads(out).values()))
    ds = ModelChain(load_scenario(scenario)).evaluate().dataset
    assert [row["target"] for row in rows] == list(ds["target"].values)
    for g, row in enumerate(rows):
        for task in ("detection", "recognition", "identification"):
            series = ds[f"fused_{task}"].values[g]
            best = int(np.argmax(series))
            assert row[f"peak_{task}"] == float(series[best])
            assert row[f"at_{task}_s"] == float(ds["time"].values[best])
        assert row["in_view_steps"] == int(ds["in_view"].values[:, g].any(axis=0).sum())


def test_evaluate_out_streams_the_in_memory_content(capsys, tmp_path):
    scenario = ROOT / "examples" / "uav_haze.toml"
    out = tmp_path / "r.parquet"
    code, _, err = _run(capsys, "evaluate", scenario, "--out", out)
    assert code == 0 and err == ""  # no progress bar where stderr is not a terminal
    expected = ModelChain(load_scenario(scenario)).evaluate().to_dataframe()
    table = pq.read_table(out)
    meta = json.loads(table.schema.metadata[b"targetacq"])
    # The file's name, not the folders it lies in on this machine.
    assert meta["scenario_file"] == scenario.name and len(meta["scenario_file_sha256"]) == 64
    pd.testing.assert_frame_equal(table.to_pandas(), expected)


def test_a_run_too_large_for_memory_streams_but_is_not_held(monkeypatch, tmp_path):
    """A run larger than memory compiles and streams chunk by chunk; held whole it is refused
    with advice to stream (the machine's memory made small for the test)."""
    from targetacq.base import limits
    from targetacq.run.model_chain import ModelChain
    from targetacq.run.streaming import write_chunks
    from targetacq.scenario.schema import load_scenario

    scenario = load_scenario(ROOT / "examples" / "uav_haze.toml")
    # One target's times fit; all three targets' do not.
    monkeypatch.setattr(limits, "available_memory", lambda: 2 * 13 * 1024)
    chain = ModelChain(scenario)
    with pytest.raises(ValueError, match="evaluate chunk by chunk"):
        chain.evaluate()
    out = write_chunks(chain, tmp_path / "run.csv", targets_per_chunk=1)
    assert out.exists()
