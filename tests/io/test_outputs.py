"""Output files and standard output: every write failure is one line naming the path and the
reason (exit status 2, no traceback), nothing is left half-written or behind (SIGTERM and
SIGKILL included), new files get the umask's mode, a link is written through, JSON is strict.

The command runs through its real entry point (``python -m targetacq``) in subprocesses, started
together so that the suite stays fast; failures that need no real process run in-process."""

import errno
import json
import os
import signal
import stat
import subprocess
import sys
import time
import warnings
from importlib import resources
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr

import targetacq.cli.scenarios as scenarios_command
from child_process import file_size_limited
from targetacq.cli import main
from targetacq.io.files import (
    OutputError,
    json_records,
    json_text,
    json_value,
    output_path,
    write_atomically,
)
from targetacq.run.model_chain import Results

COMMAND = [sys.executable, "-m", "targetacq"]
EXAMPLE = str(resources.files("targetacq") / "examples" / "uav_haze.toml")
CAMERA = str(Path(__file__).parents[1] / "data" / "camera.png")
TEMPORARY_MARK = ".targetacq-tmp-"

# Every command that writes a file, with the name of its output (the suffix gives the format).
WRITERS = {
    "evaluate-csv": (["evaluate", EXAMPLE, "--out"], "rows.csv"),
    "evaluate-parquet": (["evaluate", EXAMPLE, "--out"], "rows.parquet"),
    "plot": (["plot", "transforms", "--criterion", "johnson-truck", "--out"], "figure.png"),
    "report": (["report", EXAMPLE, "--out"], "report.html"),
    "clutter-overlay": (["clutter", CAMERA, "--box", "228,470,24,24", "--overlay"], "o.png"),
    "validation": (["validation", "--out"], "validation.html"),
}

FILE_SIZE_LIMIT = 1024  # bytes: every writer's output is larger


def strict_json(text):
    """Parse ``text`` as strict JSON: the literals NaN, Infinity and -Infinity are refused."""

    def refuse(constant):
        raise AssertionError(f"not JSON: {constant}")

    return json.loads(text, parse_constant=refuse)


def start(args, folder, *, file_size_limit=None, stdout=subprocess.PIPE):
    """Start ``python -m targetacq ARGS`` in ``folder``, under a file-size limit [bytes] if
    given."""
    command = [*COMMAND, *args]
    if file_size_limit is not None:
        command = file_size_limited(command, file_size_limit)
    return subprocess.Popen(command, cwd=folder, stdout=stdout, stderr=subprocess.PIPE, text=True)


def finish(process):
    out, err = process.communicate(timeout=300)
    return process.returncode, out, err


def assert_one_error_line(code, err, *fragments):
    assert code == 2, err
    assert "Traceback" not in err and "Exception ignored" not in err, err
    lines = err.splitlines()
    assert len(lines) == 1 and err.endswith("\n"), err
    assert lines[0].startswith("targetacq: error: "), err
    for fragment in fragments:
        assert fragment in lines[0], err


def leftovers(*folders):
    return [p for folder in folders for p in Path(folder).iterdir() if TEMPORARY_MARK in p.name]


# --- write failures, through the real entry point -------------------------------------------


@pytest.fixture(scope="module")
def failed_runs(tmp_path_factory):
    """Every command that writes, each made to fail in a real process, all started at once:
    a file-size limit per writer, plus a folder as --out, a read-only folder, and standard
    output to /dev/full or a closed pipe."""
    root = tmp_path_factory.mktemp("failures")
    processes = {}
    for name, (args, file_name) in WRITERS.items():
        folder = root / name
        folder.mkdir()
        processes[name] = (
            start([*args, file_name], folder, file_size_limit=FILE_SIZE_LIMIT),
            folder,
        )
    taken = root / "folder-as-out"
    (taken / "rows.csv").mkdir(parents=True)
    processes["folder-as-out"] = (start(["evaluate", EXAMPLE, "--out", "rows.csv"], taken), taken)
    # The kernel lets root write into a read-only folder; sysfs refuses new files even to root.
    read_only = root / "read-only"
    read_only.mkdir(mode=0o555)
    folder = Path("/sys") if os.geteuid() == 0 else read_only
    processes["read-only"] = (start(["evaluate", EXAMPLE, "--out", "rows.csv"], folder), folder)
    with open("/dev/full", "w") as full:
        for name, args in {
            "stdout-full-dri": ["dri", "--example"],
            "stdout-full-evaluate": ["evaluate", EXAMPLE, "--format", "json"],
        }.items():
            folder = root / name
            folder.mkdir()
            processes[name] = (start(args, folder, stdout=full), folder)
    done = {name: (*finish(process), folder) for name, (process, folder) in processes.items()}
    read_only.chmod(0o755)
    return done


@pytest.mark.parametrize("writer", sorted(WRITERS))
def test_a_file_size_limit_is_one_line_naming_the_file_and_nothing_is_left(failed_runs, writer):
    code, _, err, folder = failed_runs[writer]
    file_name = WRITERS[writer][1]
    assert_one_error_line(code, err, f"cannot write '{file_name}'", "File too large")
    assert list(folder.iterdir()) == []  # no partial file, no temporary file


def test_a_folder_as_output_is_refused_before_any_work(failed_runs):
    code, out, err, _ = failed_runs["folder-as-out"]
    assert_one_error_line(code, err, "cannot write 'rows.csv': it is a folder")
    assert out == ""


def test_a_read_only_folder_is_one_line_naming_the_file(failed_runs):
    code, _, err, folder = failed_runs["read-only"]
    assert_one_error_line(code, err, "cannot write 'rows.csv'")
    assert "not writable" in err or "Permission denied" in err
    assert not (folder / "rows.csv").exists() and leftovers(folder) == []


@pytest.mark.parametrize("command", ["dri", "evaluate"])
def test_standard_output_on_a_full_device_is_one_line(failed_runs, command):
    code, _, err, _ = failed_runs[f"stdout-full-{command}"]
    assert_one_error_line(code, err, "cannot write standard output: No space left on device")


def test_a_closed_pipe_ends_quietly(tmp_path):
    process = start(["dri", "--example"], tmp_path)
    process.stdout.close()  # the reader is gone before the command writes anything
    err = process.stderr.read()
    process.wait(timeout=300)
    process.stderr.close()
    assert process.returncode == 1 and err == ""


@pytest.mark.parametrize("name", sorted(WRITERS))
def test_a_folder_as_output_is_one_line_for_every_writer(cli, tmp_path, name):
    args, file_name = WRITERS[name]
    (tmp_path / file_name).mkdir()
    code, _, err = cli(*args, str(tmp_path / file_name))
    assert_one_error_line(code, err, f"cannot write '{tmp_path / file_name}': it is a folder")


def test_a_full_file_system_is_one_line_and_removes_the_temporary_file(cli, tmp_path, monkeypatch):
    def full(self, target, **options):
        if isinstance(target, (str, Path)):
            Path(target).write_text("partial")
        else:  # a handle the units and provenance were written to first
            target.write("partial")
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(pd.DataFrame, "to_csv", full)
    code, _, err = cli("evaluate", EXAMPLE, "--out", str(tmp_path / "rows.csv"))
    assert_one_error_line(
        code, err, f"cannot write '{tmp_path / 'rows.csv'}': No space left on device"
    )
    assert list(tmp_path.iterdir()) == []


# --- temporary files: SIGTERM and SIGKILL during a write ------------------------------------


def _big_scenario(folder):
    """The bundled example at a 4 ms step: about 90,000 rows, an 18 MB CSV, a write of a
    second or so, long enough to be caught in the middle."""
    text = Path(EXAMPLE).read_text(encoding="utf-8").replace('step = "10 s"', 'step = "4 ms"')
    assert 'step = "4 ms"' in text
    path = folder / "big.toml"
    path.write_text(text, encoding="utf-8")
    return path


def _caught_writing(folder, kill_signal):
    """Start `evaluate --out big.csv`, send ``kill_signal`` once its temporary file exists."""
    process = start(["evaluate", str(_big_scenario(folder)), "--out", "big.csv"], folder)
    deadline = time.monotonic() + 240
    while not leftovers(folder):
        assert process.poll() is None, process.communicate()
        assert time.monotonic() < deadline, "no temporary file appeared"
        time.sleep(0.002)
    process.send_signal(kill_signal)
    return finish(process)


def test_sigterm_during_a_write_removes_the_temporary_file(tmp_path):
    code, _, err = _caught_writing(tmp_path, signal.SIGTERM)
    assert code == 128 + signal.SIGTERM, err
    assert "Traceback" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["big.toml"]


def test_a_temporary_file_left_by_sigkill_is_removed_by_the_next_write(tmp_path):
    code, _, _ = _caught_writing(tmp_path, signal.SIGKILL)
    assert code == -signal.SIGKILL
    assert len(leftovers(tmp_path)) == 1 and not (tmp_path / "big.csv").exists()
    write_atomically(tmp_path / "big.csv", lambda p: p.write_text("next run"))
    assert leftovers(tmp_path) == []
    assert (tmp_path / "big.csv").read_text() == "next run"


def _temporary_name(target, pid):
    """A temporary file name of ``target`` for the process ``pid``, as this machine names it."""
    seen = []
    write_atomically(target, lambda p: seen.append(p.name) or p.write_text(""))
    own = seen[0]
    return own.replace(f"-{os.getpid()}-", f"-{pid}-", 1)


def test_only_the_temporaries_of_finished_processes_are_removed(tmp_path):
    target = tmp_path / "rows.csv"
    finished_pid = subprocess.Popen([sys.executable, "-c", "pass"])
    finished_pid.wait()
    dead = tmp_path / _temporary_name(target, finished_pid.pid)
    alive = tmp_path / _temporary_name(target, os.getpid())  # a running process
    other_target = tmp_path / _temporary_name(tmp_path / "other.csv", finished_pid.pid)
    other_machine = tmp_path / dead.name.replace(TEMPORARY_MARK, TEMPORARY_MARK + "f", 1)
    for path in (dead, alive, other_target, other_machine):
        path.write_text("left over")
    write_atomically(target, lambda p: p.write_text("new"))
    assert not dead.exists()
    assert alive.exists() and other_target.exists() and other_machine.exists()


def test_a_failed_write_leaves_nothing_and_names_the_file(tmp_path):
    target = tmp_path / "rows.csv"
    target.write_text("old")

    def fails(path):
        path.write_text("half")
        raise OSError(errno.EIO, os.strerror(errno.EIO))

    with pytest.raises(OutputError, match=r"^cannot write '.*rows\.csv': Input/output error$"):
        write_atomically(target, fails)
    assert target.read_text() == "old" and leftovers(tmp_path) == []

    def interrupted(path):
        path.write_text("half")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        write_atomically(target, interrupted)
    assert target.read_text() == "old" and leftovers(tmp_path) == []


def test_a_very_long_file_name_still_gets_a_temporary_file(tmp_path):
    target = tmp_path / ("x" * 250 + ".csv")  # 254 bytes: the longest names a folder takes
    write_atomically(target, lambda p: p.write_text("long"))
    assert target.read_text() == "long" and leftovers(tmp_path) == []


# --- modes and links -------------------------------------------------------------------------


@pytest.mark.parametrize(("umask", "mode"), [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
def test_a_new_file_gets_the_mode_of_the_umask(tmp_path, umask, mode):
    previous = os.umask(umask)
    try:
        write_atomically(tmp_path / "new.csv", lambda p: p.write_text("x"))
        _results().write(tmp_path / "new.parquet")
    finally:
        os.umask(previous)
    assert stat.S_IMODE((tmp_path / "new.csv").stat().st_mode) == mode
    assert stat.S_IMODE((tmp_path / "new.parquet").stat().st_mode) == mode


def test_a_replaced_file_keeps_its_mode(tmp_path):
    target = tmp_path / "old.csv"
    target.write_text("old")
    target.chmod(0o640)
    previous = os.umask(0o077)
    try:
        write_atomically(target, lambda p: p.write_text("new"))
    finally:
        os.umask(previous)
    assert target.read_text() == "new" and stat.S_IMODE(target.stat().st_mode) == 0o640


def test_a_link_is_written_through(tmp_path):
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    real = elsewhere / "real.csv"
    real.write_text("old")
    real.chmod(0o604)
    link = tmp_path / "link.csv"
    link.symlink_to(real)
    seen = []
    write_atomically(link, lambda p: seen.append(p.parent) or p.write_text("new"))
    assert link.is_symlink() and os.readlink(link) == str(real)
    assert real.read_text() == "new" and stat.S_IMODE(real.stat().st_mode) == 0o604
    assert seen == [elsewhere]  # the temporary file sat next to the target: an atomic rename
    assert leftovers(tmp_path, elsewhere) == []


def test_a_link_to_a_missing_file_creates_the_file(tmp_path):
    link = tmp_path / "link.csv"
    link.symlink_to(tmp_path / "target.csv")
    output_path(link, ("csv",), "output")
    write_atomically(link, lambda p: p.write_text("new"))
    assert link.is_symlink() and (tmp_path / "target.csv").read_text() == "new"


def test_a_link_to_something_not_a_regular_file_is_refused(tmp_path):
    pipe = tmp_path / "pipe"
    os.mkfifo(pipe)
    link = tmp_path / "out.csv"
    link.symlink_to(pipe)
    with pytest.raises(OutputError, match="not a regular file"):
        output_path(link, ("csv",), "output")
    with pytest.raises(OutputError, match="not a regular file"):
        write_atomically(link, lambda p: p.write_text("new"))
    assert stat.S_ISFIFO(pipe.stat().st_mode) and leftovers(tmp_path) == []


# --- strict JSON ---------------------------------------------------------------------------------


def test_json_spells_infinities_as_strings_and_nan_as_null():
    document = {
        "values": [1.5, np.inf, -np.inf, np.nan, np.float32(np.inf), np.float32(0.25)],
        "array": np.array([[np.nan, 2.0]]),
        "count": np.int64(3),
        "flag": np.bool_(True),
        "nested": ({"t50_s": float("inf")},),
    }
    parsed = strict_json(json_text(document))
    assert parsed == {
        "values": [1.5, "inf", "-inf", None, "inf", 0.25],
        "array": [[None, 2.0]],
        "count": 3,
        "flag": True,
        "nested": [{"t50_s": "inf"}],
    }
    assert json_value(float("-inf")) == "-inf" and json_value(float("nan")) is None


def _results():
    """A small Results with +inf, -inf and NaN where the model gives them: an SNR of +inf dB
    (no attenuation), -inf dB (none transmitted) and a NaN probability (undefined)."""
    sensor, target, time_ = ["s"], ["a", "b"], [0.0, 1.0]
    triple = ("sensor", "target", "time")
    snr = np.array([[[np.inf, 3.0], [-np.inf, np.nan]]])
    detection = np.array([[[0.5, np.nan], [0.0, 1.0]]])
    return Results(
        xr.Dataset(
            {
                "snr": (triple, snr),
                "detection": (triple, detection),
                "in_view": (triple, np.array([[[True, False], [True, True]]])),
                "scr": (("sensor", "target"), np.array([[np.inf, 2.0]])),
                **{
                    f"fused_{task}": (("target", "time"), np.array([[0.5, np.nan], [0.0, 1.0]]))
                    for task in ("detection", "recognition", "identification")
                },
            },
            coords={"sensor": sensor, "target": target, "time": time_},
        )
    )


def test_results_json_is_strict_and_tells_infinity_from_nan(tmp_path):
    _results().write(tmp_path / "rows.json")
    rows = strict_json((tmp_path / "rows.json").read_text(encoding="utf-8"))["rows"]
    by_key = {(row["target"], row["time"]): row for row in rows}
    assert [by_key[k]["snr"] for k in [("a", 0.0), ("a", 1.0), ("b", 0.0), ("b", 1.0)]] == [
        "inf",
        3.0,
        "-inf",
        None,
    ]
    assert by_key[("a", 1.0)]["detection"] is None and by_key[("a", 0.0)]["detection"] == 0.5
    assert by_key[("a", 0.0)]["scr"] == "inf" and by_key[("b", 1.0)]["scr"] == 2.0
    assert by_key[("a", 0.0)]["in_view"] is True and by_key[("a", 1.0)]["in_view"] is False


def test_json_records_keep_finite_columns_as_numbers():
    frame = pd.DataFrame({"x": [0.1, 1e300], "y": [np.inf, 2.5], "name": ["p", "q"]})
    assert strict_json(json_records(frame)) == [
        {"x": 0.1, "y": "inf", "name": "p"},
        {"x": 1e300, "y": 2.5, "name": "q"},
    ]


def test_evaluate_and_simulate_json_are_strict(cli):
    code, out, err = cli("evaluate", EXAMPLE, "--format", "json")
    assert code == 0, err
    targets = strict_json(out)["targets"]
    assert {row["target"] for row in targets} == {"truck", "tank", "jeep"}
    # The truck's detection probability peaks at 0.06: in 20 runs of 10 s, not every run
    # detects it, so its 90th-percentile first time is "never" (+inf).
    code, out, err = cli(
        "simulate", EXAMPLE, "--runs", "20", "--duration", "10s", "--format", "json"
    )
    assert code == 0, err
    rows = strict_json(out)["targets"]
    truck = next(r for r in rows if r["target"] == "truck" and r["task"] == "detection")
    assert truck["fraction"] < 1 and truck["t90_s"] == "inf"


def test_dri_and_atmosphere_json_are_strict(cli):
    code, out, err = cli("dri", "--example", "--format", "json")
    assert code == 0, err
    assert {row["task"] for row in strict_json(out)["ranges"]} >= {"detection"}
    # At range 0 nothing is attenuated (τ = 1): the SNR of Eq. (7.7) is +inf dB, not missing.
    code, out, err = cli(
        "atmosphere", "--extinction", "1/km", "--range", "0m,10km", "--format", "json"
    )
    assert code == 0, err
    rows = strict_json(out)["rows"]
    assert rows[0]["transmittance"] == 1.0 and rows[0]["snr_db"] == "inf"
    assert isinstance(rows[1]["snr_db"], float)


# --- the command line's handling of failures and warnings -----------------------------------


def _load_then(monkeypatch, action):
    real = scenarios_command.load_scenario

    def load(path):
        action()
        return real(path)

    monkeypatch.setattr(scenarios_command, "load_scenario", load)


def test_warnings_of_a_succeeding_command_are_printed_once_after_its_output(cli, monkeypatch):
    def warn():
        for _ in range(3):
            warnings.warn("the terrain map is coarse", UserWarning, stacklevel=1)
        warnings.warn("overflow encountered in exp", RuntimeWarning, stacklevel=1)

    _load_then(monkeypatch, warn)
    code, out, err = cli("validate", EXAMPLE)
    assert code == 0 and "valid" in out
    assert err == "targetacq: warning: the terrain map is coarse\n"


def test_a_failing_command_prints_only_its_error_line(cli, monkeypatch):
    def warn_then_fail():
        warnings.warn("divide by zero encountered", RuntimeWarning, stacklevel=1)
        warnings.warn("the terrain map is coarse", UserWarning, stacklevel=1)
        raise ValueError("time.step must be > 0")

    _load_then(monkeypatch, warn_then_fail)
    code, out, err = cli("validate", EXAMPLE)
    assert err == "targetacq: error: time.step must be > 0\n" and code == 2 and out == ""


@pytest.mark.parametrize(
    ("error", "message"),
    [
        (MemoryError("cannot allocate 894 GiB"), "not enough memory for this run: cannot"),
        (MemoryError(), "not enough memory for this run: an allocation failed"),
        (RecursionError("maximum recursion depth exceeded"), "input too deeply nested"),
        (KeyError("sensors"), "'sensors'"),
        (TypeError("pitch must be a number"), "pitch must be a number"),
        (FileNotFoundError(errno.ENOENT, "No such file or directory", "map.csv"), "map.csv: No"),
    ],
)
def test_failures_the_user_can_fix_are_one_line(cli, monkeypatch, error, message):
    def fail():
        raise error

    _load_then(monkeypatch, fail)
    code, _, err = cli("validate", EXAMPLE)
    assert_one_error_line(code, err, message)


def test_a_bug_keeps_its_traceback(capsys, monkeypatch):
    def bug():
        raise ZeroDivisionError("a bug")

    _load_then(monkeypatch, bug)
    with pytest.raises(ZeroDivisionError):
        main(["validate", EXAMPLE])


def test_main_restores_the_signal_handlers(cli):
    before = signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGXFSZ)
    code, _, _ = cli("validate", EXAMPLE)
    assert code == 0
    assert (signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGXFSZ)) == before


# --- start-up: the click command built once, heavy libraries imported by the commands -------


def test_the_click_command_is_built_once_and_keeps_no_state_between_calls(cli):
    from targetacq.cli import _click_command

    assert _click_command() is _click_command()
    code, out, _ = cli("dri", "--example", "--format", "json")
    assert code == 0 and json.loads(out)
    code, out, _ = cli("dri", "--example")
    assert code == 0 and not out.startswith("{") and "task" in out
    code, _, err = cli("dri", "--example", "--no-such-option")
    assert code == 2 and err.startswith("targetacq: error:") and err.count("\n") == 1
    code, out, _ = cli("dri", "--example", "--format", "csv")
    assert code == 0 and not out.startswith("{")


def test_the_cli_starts_without_matplotlib_pandas_or_the_validation_page():
    heavy = (
        "matplotlib",
        "pandas",
        "targetacq.reports.plots",
        "targetacq.io.html_report",
        "targetacq.validation",
    )
    code = f"import sys, targetacq.cli; print([m for m in {heavy!r} if m in sys.modules])"
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout
    assert out.strip() == "[]"


def test_the_plot_kinds_of_the_help_text_are_those_of_the_plots_module():
    from targetacq.cli.figures import PLOT_KIND_NAMES
    from targetacq.reports.plots import PLOT_KINDS

    assert tuple(PLOT_KINDS) == PLOT_KIND_NAMES
