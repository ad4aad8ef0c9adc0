"""Outputs people can trust later: units, long names and provenance in every format; umask."""

import contextlib
import hashlib
import json
import os
import stat
from pathlib import Path

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest
import xarray as xr

import targetacq
from targetacq.cli import main
from targetacq.io.datasets import OUTPUT_FORMATS, Output, annotate, provenance, write_output
from targetacq.run.model_chain import ModelChain
from targetacq.run.studies import sweep
from targetacq.scenario.schema import load_scenario

EXAMPLES = Path(__file__).parents[2] / "examples"
SCENARIO = EXAMPLES / "two_sensors_fused.toml"
SWEEP = ["sweep", "--example", "--focal-length", "35mm,50mm", "--scr", "1,2"]


def run(capsys, *args):
    with pytest.raises(SystemExit) as done:
        main([str(a) for a in args])
    out, err = capsys.readouterr()
    return done.value.code, out, err


@contextlib.contextmanager
def umask(mask):
    old = os.umask(mask)
    try:
        yield
    finally:
        os.umask(old)


def _open(path):
    if path.suffix == ".zarr":
        return xr.open_zarr(path).load()
    return xr.load_dataset(path, engine="netcdf4")


def _file_sha256(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def _check_described(ds):
    """Every variable and coordinate has a long_name; every numeric one has units."""
    for name in ds.variables:
        attrs = ds[name].attrs
        assert attrs.get("long_name"), name
        if ds[name].dtype.kind in "fiub":
            assert "units" in attrs, name


@pytest.mark.parametrize("suffix", sorted(OUTPUT_FORMATS))
def test_sweep_round_trips_with_units_and_provenance(capsys, tmp_path, suffix):
    out = tmp_path / f"sweep.{suffix}"
    code, _, err = run(capsys, *SWEEP, "--out", out)
    assert code == 0, err
    expected = sweep({"example": True, "focal_length": "35mm,50mm", "scr": "1,2"})
    values = expected["range"].values.reshape(-1)
    if suffix in ("nc", "zarr"):
        ds = _open(out)
        _check_described(ds)
        assert ds["range"].attrs["units"] == "m"
        assert ds["focal_length_m"].attrs["units"] == "m"
        np.testing.assert_array_equal(ds["range"].values, expected["range"].values)
        assert ds.attrs["version"] == targetacq.__version__
        assert ds.attrs["options_sha256"] == expected.attrs["options_sha256"]
        assert json.loads(ds.attrs["model"])["criterion"] == "johnson"
        return
    if suffix == "csv":
        frame = pd.read_csv(out, comment="#")
        assert list(frame.columns) == [
            "focal_length",
            "scr",
            "task",
            "probability",
            "range_m",
            "reached",
        ]
        # Units and provenance in "#" lines before the table (a CSV has no attributes).
        head = [line for line in out.read_text().splitlines() if line.startswith("#")]
        assert head[0].startswith("# units: focal_length, ") and "range_m [m]" in head[0]
        assert json.loads(head[1].removeprefix("# provenance: "))["software"] == "targetacq"
    elif suffix == "parquet":
        table = pq.read_table(out)
        meta = json.loads(table.schema.metadata[b"targetacq"])
        assert meta["version"] == targetacq.__version__ and meta["options_sha256"]
        assert table.schema.field("range_m").metadata[b"units"] == b"m"
        assert table.schema.field("probability").metadata[b"units"] == b"1"
        frame = table.to_pandas()
    else:
        document = json.loads(out.read_text())
        meta = document["meta"]
        assert meta["version"] == targetacq.__version__ and meta["software"] == "targetacq"
        assert meta["variables"]["range_m"]["units"] == "m"
        assert meta["variables"]["task"]["long_name"]
        frame = pd.DataFrame(document["rows"])
    np.testing.assert_array_equal(frame["range_m"].to_numpy(dtype=float), values)


@pytest.mark.parametrize("suffix", sorted(OUTPUT_FORMATS))
def test_evaluate_out_has_units_and_the_scenario_hash(capsys, tmp_path, suffix):
    out = tmp_path / f"results.{suffix}"
    code, _, err = run(capsys, "evaluate", SCENARIO, "--out", out)
    assert code == 0, err
    expected = ModelChain(load_scenario(SCENARIO)).evaluate().to_dataframe()
    file_hash = _file_sha256(SCENARIO)
    if suffix in ("nc", "zarr"):
        ds = _open(out)
        _check_described(ds)
        assert ds["range"].attrs["units"] == "m" and ds["snr"].attrs["units"] == "dB"
        assert ds["time"].attrs["units"] == "s"
        assert ds.attrs["scenario_file_sha256"] == file_hash
        assert json.loads(ds.attrs["model"])["transform"] == "ttpf"
        np.testing.assert_array_equal(
            ds["detection"].values.reshape(-1),
            expected.set_index(["sensor", "target", "time"])["detection"].to_numpy(),
        )
        return
    if suffix == "parquet":
        table = pq.read_table(out)
        assert json.loads(table.schema.metadata[b"targetacq"])["scenario_file_sha256"] == file_hash
        assert table.schema.field("range").metadata[b"units"] == b"m"
        frame = table.to_pandas()
    elif suffix == "json":
        document = json.loads(out.read_text())
        assert document["meta"]["scenario_file_sha256"] == file_hash
        assert document["meta"]["variables"]["snr"]["units"] == "dB"
        frame = pd.DataFrame(document["rows"])
    else:
        frame = pd.read_csv(out, comment="#")
    assert len(frame) == len(expected)
    np.testing.assert_allclose(frame["detection"], expected["detection"], rtol=1e-12)


@pytest.mark.parametrize("suffix", ["nc", "json", "parquet", "csv"])
def test_simulate_out_records_the_seed(capsys, tmp_path, suffix):
    out = tmp_path / f"sim.{suffix}"
    args = ["simulate", SCENARIO, "--runs", "30", "--duration", "20s", "--seed", "7"]
    code, stdout, err = run(capsys, *args, "--format", "json", "--out", out)
    assert code == 0, err
    printed = pd.DataFrame(json.loads(stdout)["targets"])
    if suffix == "nc":
        ds = _open(out)
        _check_described(ds)
        assert ds.attrs["seed"] == 7 and ds.attrs["runs"] == 30
        assert ds["first_time"].dims == ("run", "target", "task")
        assert ds["first_time"].attrs["units"] == "s"
        fraction = np.isfinite(ds["first_time"].values).mean(axis=0)
        np.testing.assert_allclose(
            fraction.reshape(-1), ds["fraction"].values.reshape(-1), rtol=1e-12
        )
        return
    if suffix == "json":
        document = json.loads(out.read_text())
        assert document["meta"]["seed"] == 7
        assert document["meta"]["scenario_file_sha256"] == _file_sha256(SCENARIO)
        frame = pd.DataFrame(document["rows"])
    elif suffix == "parquet":
        table = pq.read_table(out)
        assert json.loads(table.schema.metadata[b"targetacq"])["seed"] == 7
        frame = table.to_pandas()
    else:
        frame = pd.read_csv(out, comment="#")
    np.testing.assert_allclose(frame["fraction"], printed["fraction"], rtol=1e-12)


def test_outputs_are_0644_under_umask_022(capsys, tmp_path):
    with umask(0o022):
        for suffix in sorted(OUTPUT_FORMATS):
            commands = {
                "sweep": [*SWEEP, "--out"],
                "evaluate": ["evaluate", SCENARIO, "--out"],
                "simulate": ["simulate", SCENARIO, "--runs", "5", "--duration", "5s", "--out"],
            }
            for name, args in commands.items():
                out = tmp_path / f"{name}.{suffix}"
                code, _, err = run(capsys, *args, out)
                assert code == 0, err
                if out.is_dir():
                    assert stat.S_IMODE(out.stat().st_mode) == 0o755
                    files = [p for p in out.rglob("*") if p.is_file()]
                    assert files
                    assert {stat.S_IMODE(p.stat().st_mode) for p in files} == {0o644}
                else:
                    assert stat.S_IMODE(out.stat().st_mode) == 0o644, out
        figure = tmp_path / "sweep.png"
        assert run(capsys, *SWEEP, "--figure", figure)[0] == 0
        assert stat.S_IMODE(figure.stat().st_mode) == 0o644
    assert not [p for p in tmp_path.iterdir() if "targetacq-tmp" in p.name]


def test_zarr_store_is_replaced_whole_and_a_folder_is_refused(capsys, tmp_path):
    out = tmp_path / "s.zarr"
    assert run(capsys, *SWEEP, "--out", out)[0] == 0
    assert (
        run(capsys, "sweep", "--example", "--focal-length", "20mm,25mm,30mm", "--out", out)[0] == 0
    )
    assert list(_open(out)["focal_length"].values) == ["20mm", "25mm", "30mm"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.zarr"]  # nothing left aside
    other = tmp_path / "photos.zarr"
    other.mkdir()
    (other / "keep.jpg").write_bytes(b"x")
    code, _, err = run(capsys, *SWEEP, "--out", other)
    assert code == 2 and "not a Zarr store" in err and (other / "keep.jpg").exists()
    code, _, err = run(capsys, *SWEEP, "--out", tmp_path / "s.xlsx")
    assert code == 2 and ".nc" in err and ".zarr" in err


def test_model_results_describe_every_variable():
    results = ModelChain(load_scenario(SCENARIO)).evaluate()
    _check_described(results.dataset)
    assert results.dataset["contrast"].attrs["units"] == "W m-2"
    meta = results.dataset.attrs
    assert meta["version"] == targetacq.__version__ and len(meta["scenario_sha256"]) == 64
    assert set(meta["model"]["criteria"]) == set(results.dataset["target"].values.tolist())


def test_annotate_refuses_an_unknown_variable():
    with pytest.raises(ValueError, match="'mystery'"):
        annotate(xr.Dataset({"mystery": ("x", [1.0])}, coords={"x": [0.0]}))


def test_a_seed_beyond_int64_is_kept_exactly_in_netcdf(tmp_path):
    seed = 2**128 - 1
    ds = annotate(xr.Dataset({"snr": ("time", [1.0])}, coords={"time": [0.0]}))
    out = write_output(Output(ds, provenance({}, seed=seed)), tmp_path / "big.nc")
    assert json.loads(_open(out).attrs["seed"]) == seed


# -- a full disk and a missing [sweep] extra: one line, exit 2, nothing left behind ----------

WRITES = {
    "evaluate": ["evaluate", SCENARIO, "--out"],  # chunk by chunk (targetacq.run.streaming)
    "sweep": [*SWEEP, "--out"],  # whole (targetacq.io.datasets.write_output)
}


def _disk_fills(monkeypatch, error):
    """Every netCDF write puts a few bytes in its file, then fails with ``error``, the disk
    reported full."""
    import shutil

    def to_netcdf(self, path=None, *args, **kwargs):
        Path(path).write_bytes(b"\x89HDF\r\n\x1a\n" + bytes(100))  # a partial file
        raise error

    monkeypatch.setattr(xr.Dataset, "to_netcdf", to_netcdf)
    usage = shutil.disk_usage("/")
    monkeypatch.setattr(
        "targetacq.io.datasets.shutil.disk_usage", lambda path: usage._replace(free=0)
    )


@pytest.mark.parametrize("command", list(WRITES))
def test_netcdf_on_a_full_disk_is_one_line_and_leaves_nothing(
    capsys, tmp_path, monkeypatch, command
):
    # netCDF4 reports ENOSPC as RuntimeError("NetCDF: HDF error"): a 51-85-line traceback
    # with exit status 1 before.
    _disk_fills(monkeypatch, RuntimeError("NetCDF: HDF error"))
    out = tmp_path / "e.nc"
    code, _, err = run(capsys, *WRITES[command], out)
    assert code == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert err.startswith(f"targetacq: error: cannot write {str(out)!r}: No space left on device")
    assert "NetCDF: HDF error" in err
    assert list(tmp_path.iterdir()) == [], "a partial or temporary file is left behind"


def test_netcdf_write_errors_that_are_not_the_library_s_are_not_hidden(tmp_path, monkeypatch):
    _disk_fills(monkeypatch, RuntimeError("a bug elsewhere"))
    ds = annotate(xr.Dataset({"snr": ("time", [3.0])}, coords={"time": [0.0]}))
    with pytest.raises(RuntimeError, match="a bug elsewhere"):
        write_output(Output(ds, provenance({})), tmp_path / "r.nc")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(("suffix", "package"), [("nc", "netCDF4"), ("zarr", "zarr")])
@pytest.mark.parametrize("command", list(WRITES))
def test_nc_or_zarr_without_the_sweep_extra_is_one_line_before_any_work(
    capsys, tmp_path, monkeypatch, command, suffix, package
):
    # A base install has neither: a 47-64-line ModuleNotFoundError traceback before, after the
    # whole run. Now refused before any work, naming the extra.
    monkeypatch.setitem(__import__("sys").modules, package, None)  # its import fails
    monkeypatch.setattr(ModelChain, "__init__", lambda *a, **k: pytest.fail("work started"))
    monkeypatch.setattr("targetacq.run.studies.sweep", lambda *a, **k: pytest.fail("work started"))
    out = tmp_path / f"e.{suffix}"
    code, _, err = run(capsys, *WRITES[command], out)
    assert code == 2, err
    assert err == (
        f"targetacq: error: --out {str(out)!r}: a .{suffix} file needs the {package} package, "
        "which is not installed: pip install 'targetacq[sweep]'\n"
    )
    assert list(tmp_path.iterdir()) == []


def test_write_output_without_netcdf4_names_the_extra(tmp_path, monkeypatch):
    monkeypatch.setitem(__import__("sys").modules, "netCDF4", None)
    ds = annotate(xr.Dataset({"snr": ("time", [3.0])}, coords={"time": [0.0]}))
    with pytest.raises(ValueError, match=r"netCDF4 package.*pip install 'targetacq\[sweep\]'"):
        write_output(Output(ds, provenance({})), tmp_path / "r.nc")
    assert list(tmp_path.iterdir()) == []
