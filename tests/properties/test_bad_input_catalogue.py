"""The bad-input catalogue: every front-end refuses bad input with one clear, located line.

Each case is one row of a table: an id, the class of bad input it stands for, what is run (a
command line, a Python call, or a bundled scenario file with one field broken) and what must
happen. Over the command line the promise is: exit status 2, exactly one line on stderr (for
``validate``: one line per problem, at least one) starting ``targetacq: error:``, naming the
input the user gave (the option, the key, the file), no traceback and no warning printed before
it. Over Python: a ``ValueError`` or ``TypeError`` (a scenario's ``ScenarioError`` is a
``ValueError``) whose message is one line naming the input. A scenario file must be refused by
``validate`` (one or more located lines naming the file and the key) and by ``evaluate`` (one
line naming the key): whatever ``validate`` accepts, ``evaluate`` runs.

A few cases are inputs that must be *accepted* (a byte-order mark, a symlink at ``--out``, the
umask's file mode) or that must give NaN exactly where a NaN went in and finite values elsewhere
("nan-in-nan-out"). They have classes of their own.

``python tests/bad_input_catalogue.py`` prints the number of cases by class.
"""

from __future__ import annotations

import contextlib
import copy
import dataclasses
import datetime
import json
import math
import os
import re
import signal
import stat
import subprocess
import sys
import tomllib
import warnings
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from child_process import file_size_limited
from toml_text import Raw, toml_dumps

HERE = Path(__file__).parents[1]
DATA = HERE / "data"
CAMERA = DATA / "camera.png"
GOLDEN = DATA / "golden"
EXAMPLES = HERE.parent / "src" / "targetacq" / "examples"
UAV = EXAMPLES / "uav_haze.toml"
FUSED = EXAMPLES / "two_sensors_fused.toml"
AIRCRAFT = EXAMPLES / "ground_observer_aircraft.toml"
RADAR = EXAMPLES / "radar_surveillance.toml"
COLOUR = EXAMPLES / "colour_camera.toml"
LASER = EXAMPLES / "laser_radar.toml"

PREFIX = "targetacq: error:"
IS_ROOT = hasattr(os, "geteuid") and os.geteuid() == 0

# The sensor and target of most `dri` cases: a valid command line to break one option of.
SENSOR = ["--pitch", "17um", "--focal-length", "75mm", "--critical-dimension", "2.3m"]
THERMAL = [*SENSOR, "--band", "lwir", "--target-temperature", "305K"]
THERMAL += ["--background-temperature", "295K"]
CAM = "{camera}"
QUICK = ["--runs", "2", "--duration", "1s", "--step", "0.5s"]  # a fast `simulate`

Names = Sequence[str | tuple[str, ...]]


# -- the table ------------------------------------------------------------------------------


@dataclass(frozen=True)
class Case:
    """One row: ``kind`` says how ``what`` is run (cli, scenario, api, process, accepted)."""

    id: str
    cls: str
    kind: str
    what: Any
    names: Names = ()
    setup: Callable[[Path], None] | None = None
    base: Path = UAV
    evaluate: bool = True
    extra: dict[str, Any] = field(default_factory=dict)


CASES: list[Case] = []


def cli(
    id: str, cls: str, argv: list[str], names: Names = (), setup: Callable | None = None
) -> None:
    CASES.append(Case(id, cls, "cli", argv, names, setup))


def scenario(
    id: str,
    cls: str,
    patch: Callable[[dict, Path], Any],
    names: Names = (),
    base: Path = UAV,
    evaluate: bool = True,
) -> None:
    CASES.append(Case(id, cls, "scenario", patch, names, base=base, evaluate=evaluate))


def api(id: str, cls: str, call: Callable[[Path], Any], names: Names = ()) -> None:
    CASES.append(Case(id, cls, "api", call, names))


def process(id: str, cls: str, check: Callable[[Path], None]) -> None:
    CASES.append(Case(id, cls, "process", check))


def accepted(id: str, cls: str, check: Callable[[Path, Any], None]) -> None:
    CASES.append(Case(id, cls, "accepted", check))


# -- TOML out (the standard library only reads it) ------------------------------------------


def read_base(base: Path) -> dict[str, Any]:
    """A scenario file as a dictionary, its image and terrain map made absolute paths."""
    document = tomllib.loads(base.read_text(encoding="utf-8"))
    background = document.get("background", {})
    if "image" in background:
        background["image"] = str((base.parent / background["image"]).resolve())
    if "terrain" in background:
        terrain = background["terrain"]
        terrain["map"] = str((base.parent / terrain["map"]).resolve())
    return document


# -- scenario patches -----------------------------------------------------------------------


def _steps(path: str) -> list[str | int]:
    steps: list[str | int] = []
    for part in re.findall(r"[^.\[\]]+|\[\d+\]", path):
        steps.append(int(part[1:-1]) if part.startswith("[") else part)
    return steps


def _parent(document: dict, path: str) -> tuple[Any, str | int]:
    *head, last = _steps(path)
    node: Any = document
    for step in head:
        if isinstance(step, str) and step not in node:
            node[step] = {}
        node = node[step]
    return node, last


def put(path: str, value: Any) -> Callable[[dict, Path], None]:
    """Set ``path`` (e.g. ``sensors[0].pitch``) to ``value``."""

    def patch(document: dict, tmp: Path) -> None:
        node, last = _parent(document, path)
        node[last] = value(tmp) if callable(value) else value

    return patch


def drop(path: str) -> Callable[[dict, Path], None]:
    """Delete ``path``."""

    def patch(document: dict, tmp: Path) -> None:
        node, last = _parent(document, path)
        del node[last]

    return patch


def both(*patches: Callable[[dict, Path], None]) -> Callable[[dict, Path], None]:
    def patch(document: dict, tmp: Path) -> None:
        for one in patches:
            one(document, tmp)

    return patch


def copy_of(path: str, index: int) -> Callable[[dict, Path], None]:
    """Append a copy of ``path[index]`` (a duplicate entry)."""

    def patch(document: dict, tmp: Path) -> None:
        node, last = _parent(document, path)
        node[last].append(copy.deepcopy(node[last][index]))

    return patch


def file_in(name: str, content: bytes | str = b"") -> Callable[[Path], str]:
    """A file made in the test's folder, as a path for a scenario value."""

    def make(tmp: Path) -> str:
        target = tmp / name
        data = content.encode() if isinstance(content, str) else content
        target.write_bytes(data)
        return str(target)

    return make


def folder_in(name: str) -> Callable[[Path], str]:
    def make(tmp: Path) -> str:
        (tmp / name).mkdir(exist_ok=True)
        return str(tmp / name)

    return make


# -- running a command in-process -----------------------------------------------------------


class Hang(BaseException):
    """A command that ran past its time (not caught by the CLI's handlers)."""


@contextlib.contextmanager
def watchdog(seconds: int) -> Any:
    def expire(signum: int, frame: Any) -> None:
        raise Hang(f"still running after {seconds} s")

    previous = signal.signal(signal.SIGALRM, expire)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def run_cli(capsys: Any, argv: list[str], seconds: int = 10) -> tuple[Any, str, str, list[str]]:
    """Run ``targetacq argv`` through its entry point: (exit code, stdout, stderr, warnings).

    Anything but ``SystemExit`` escaping the entry point is a traceback for the user: the test
    fails with it. Warnings are recorded, not raised: the real command prints them on stderr.
    """
    from targetacq.cli import main

    capsys.readouterr()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            with watchdog(seconds):
                main(list(argv))
        except SystemExit as done:
            code = done.code
        except Hang as hang:
            out, err = capsys.readouterr()
            pytest.fail(f"targetacq {' '.join(argv)}: {hang} (stderr {err[-300:]!r})")
        except BaseException as error:  # a traceback for the user
            out, err = capsys.readouterr()
            pytest.fail(
                f"targetacq {' '.join(argv)}: traceback {type(error).__name__}: "
                f"{str(error)[:300]} (stderr {err[-300:]!r})"
            )
        else:
            code = 0
    out, err = capsys.readouterr()
    return code, out, err, [f"{w.category.__name__}: {w.message}" for w in caught]


def _normal(text: str) -> str:
    return text.lower().replace("_", "-")


def names_found(line: str, names: Names) -> list[str]:
    """The names (or groups of alternatives) that ``line`` does not contain."""
    missing = []
    for name in names:
        options = (name,) if isinstance(name, str) else name
        if not any(_normal(option) in _normal(line) for option in options):
            missing.append(" or ".join(repr(o) for o in options))
    return missing


def check_error(
    argv: list[str], result: tuple[Any, str, str, list[str]], names: Names, many: bool = False
) -> None:
    """Exit 2, one line (``many``: one or more) on stderr, each ``targetacq: error: ...``,
    one of them naming every name; no traceback, no warning."""
    code, _, err, caught = result
    command = "targetacq " + " ".join(argv)
    lines = err.splitlines()
    assert "Traceback" not in err, f"{command}: traceback on stderr: {err[-500:]}"
    assert not caught, f"{command}: warnings printed before the error: {caught} then {err!r}"
    assert code == 2, f"{command}: exit status {code}, not 2 (stderr {err[-300:]!r})"
    if many:
        assert lines, f"{command}: nothing on stderr"
    else:
        assert len(lines) == 1, f"{command}: {len(lines)} lines on stderr, not one: {err!r}"
    for line in lines:
        assert line.startswith(PREFIX), f"{command}: {line!r} does not start with {PREFIX!r}"
    if names:
        misses = [names_found(line, names) for line in lines]
        assert any(not m for m in misses), (
            f"{command}: no line names {', '.join(min(misses, key=len))}: {err!r}"
        )


def substitute(argv: list[str], tmp: Path) -> list[str]:
    values = {"{tmp}": str(tmp), "{camera}": str(CAMERA), "{uav}": str(UAV)}
    out = []
    for arg in argv:
        for key, value in values.items():
            arg = arg.replace(key, value)
        out.append(arg)
    return out


# -- helpers making files -------------------------------------------------------------------


def write(name: str, content: bytes | str) -> Callable[[Path], None]:
    def setup(tmp: Path) -> None:
        (tmp / name).parent.mkdir(parents=True, exist_ok=True)
        data = content.encode() if isinstance(content, str) else content
        (tmp / name).write_bytes(data)

    return setup


def mkdir(name: str, mode: int | None = None) -> Callable[[Path], None]:
    def setup(tmp: Path) -> None:
        (tmp / name).mkdir(parents=True, exist_ok=True)
        if mode is not None:
            (tmp / name).chmod(mode)

    return setup


def unreadable(name: str, content: str) -> Callable[[Path], None]:
    def setup(tmp: Path) -> None:
        (tmp / name).write_text(content)
        (tmp / name).chmod(0)

    return setup


def nested_toml(depth: int) -> str:
    return "x = " + "[" * depth + "]" * depth + "\n"


def big_toml() -> str:
    head = UAV.read_text(encoding="utf-8")
    return head + "# padding\n" + ("#" + "x" * 99 + "\n") * 110_000  # 11 MB of comments


MRTD_CSV = "frequency,mrtd\n0.5,0.01\n1,0.02\n2,0.05\n4,0.2\n8,1.0\n"
BOXES_CSV = "x,y,width,height\n412,118,20,20\n228,470,24,24\n"

# ===========================================================================================
# The command line
# ===========================================================================================

D = "dri"

# -- non-finite: NaN, inf and numbers that overflow to infinity -----------------------------
cli("dri-pitch-1e400", "non-finite", [D, *SENSOR, "--pitch", "1e400um"], ["pitch"])
cli("dri-pitch-nan", "non-finite", [D, *SENSOR, "--pitch", "nan um"], ["pitch"])
cli("dri-focal-length-1e400", "non-finite", [D, *SENSOR, "--focal-length", "1e400mm"], ["focal"])
cli(
    "dri-critical-dimension-inf",
    "non-finite",
    [D, *SENSOR[:4], "--critical-dimension", "inf m"],
    ["critical"],
)
cli(
    "dri-critical-dimension-nan",
    "non-finite",
    [D, *SENSOR[:4], "--critical-dimension", "nan m"],
    ["critical"],
)
cli(
    "dri-ifov-nan",
    "non-finite",
    [D, "--ifov", "nan mrad", "--critical-dimension", "2.3m"],
    ["ifov"],
)
cli(
    "dri-ifov-1e400",
    "non-finite",
    [D, "--ifov", "1e400mrad", "--critical-dimension", "2.3m"],
    ["ifov"],
)
cli(
    "dri-hfov-1e400",
    "non-finite",
    [D, "--hfov", "1e400deg", "--pixels", "640", "--critical-dimension", "2.3m"],
    ["hfov"],
)
cli("dri-extinction-1e400", "non-finite", [D, *SENSOR, "--extinction", "1e400/km"], ["extinction"])
cli("dri-extinction-nan", "non-finite", [D, *SENSOR, "--extinction", "nan/km"], ["extinction"])
cli("dri-scr-nan", "non-finite", [D, *SENSOR, "--scr", "nan"], ["scr"])
cli("dri-scr-inf", "non-finite", [D, *SENSOR, "--scr", "inf"], ["scr"])
cli("dri-emissivity-nan", "non-finite", [D, *THERMAL, "--emissivity", "nan"], ["emissivity"])
cli(
    "dri-f-number-inf",
    "non-finite",
    [D, *SENSOR, "--f-number", "inf", "--wavelength", "10um"],
    ["f-number"],
)
cli("dri-probability-nan", "non-finite", [D, *SENSOR, "--probability", "nan"], ["probability"])
cli("dri-probability-inf", "non-finite", [D, *SENSOR, "--probability", "0.5,inf"], ["probability"])
cli("dri-n50-inf", "non-finite", [D, *SENSOR, "--n50", "1,4,inf"], ["n50"])
cli(
    "dri-target-temperature-1e400",
    "non-finite",
    [D, *THERMAL, "--target-temperature", "1e400K"],
    ["target-temperature"],
)
cli(
    "dri-background-temperature-nan",
    "non-finite",
    [D, *THERMAL, "--background-temperature", "nan K"],
    ["background-temperature"],
)
cli("dri-blur-1e400", "non-finite", [D, *SENSOR, "--blur", "1e400mrad"], ["blur"])
cli(
    "dri-wavelength-1e400",
    "non-finite",
    [D, *SENSOR, "--wavelength", "1e400um", "--aperture", "75mm"],
    ["wavelength"],
)
cli(
    "dri-aperture-nan",
    "non-finite",
    [D, *SENSOR, "--wavelength", "10um", "--aperture", "nan mm"],
    ["aperture"],
)
cli(
    "dri-visibility-1e400",
    "non-finite",
    [D, *SENSOR, "--band", "visible", "--visibility", "1e400km", "--visibility-convention", "mor"],
    ["visibility"],
)
cli(
    "dri-netd-1e400",
    "non-finite",
    [D, *SENSOR, "--band", "lwir", "--netd", "1e400mK", "--delta-t", "2K"],
    ["netd"],
)
cli(
    "dri-delta-t-nan",
    "non-finite",
    [D, *SENSOR, "--band", "lwir", "--netd", "50mK", "--delta-t", "nan K"],
    ["delta-t"],
)
cli("dri-nec-inf", "non-finite", [D, *SENSOR, "--nec", "inf", "--contrast", "0.3"], ["nec"])
cli(
    "dri-contrast-nan",
    "non-finite",
    [D, *SENSOR, "--nec", "0.01", "--contrast", "nan"],
    ["contrast"],
)
cli(
    "dri-clutter-std-1e400", "non-finite", [D, *THERMAL, "--clutter-std", "1e400K"], ["clutter-std"]
)
cli(
    "dri-target-area-1e400",
    "non-finite",
    [
        D,
        *SENSOR,
        "--band",
        "lwir",
        "--netd",
        "50mK",
        "--delta-t",
        "2K",
        "--target-area",
        "1e400m^2",
    ],
    ["target-area"],
)
cli(
    "atmosphere-range-1e400",
    "non-finite",
    ["atmosphere", "--range", "1e400km", "--extinction", "0.4/km"],
    ["range"],
)
cli(
    "atmosphere-range-nan",
    "non-finite",
    ["atmosphere", "--range", "1km,nan km", "--extinction", "0.4/km"],
    ["range"],
)
cli(
    "atmosphere-extinction-1e400",
    "non-finite",
    ["atmosphere", "--range", "1km", "--extinction", "1e400/km"],
    ["extinction"],
)
cli(
    "atmosphere-visibility-inf",
    "non-finite",
    [
        "atmosphere",
        "--range",
        "1km",
        "--band",
        "visible",
        "--visibility",
        "inf km",
        "--visibility-convention",
        "mor",
    ],
    ["visibility"],
)
cli("clutter-box-1e400", "non-finite", ["clutter", CAM, "--box", "1e400,0,10,10"], ["box"])
cli("clutter-box-nan", "non-finite", ["clutter", CAM, "--box", "nan,0,10,10"], ["box"])
cli(
    "clutter-cycles-nan",
    "non-finite",
    ["clutter", CAM, "--box", "412,118,20,20", "--cycles", "nan"],
    ["cycles"],
)
cli(
    "clutter-cell-factor-inf",
    "non-finite",
    ["clutter", CAM, "--box", "412,118,20,20", "--cell-factor", "inf"],
    ["cell-factor"],
)
cli(
    "clutter-image-range-1e400",
    "non-finite",
    ["clutter", CAM, "--box", "412,118,20,20", "--image-range", "1e400km", "--range", "1km"],
    ["image-range"],
)
cli(
    "plot-curves-max-range-1e400",
    "non-finite",
    ["plot", "curves", "--out", "{tmp}/c.png", *SENSOR, "--max-range", "1e400km"],
    ["max-range"],
)
cli(
    "plot-atmosphere-max-range-nan",
    "non-finite",
    ["plot", "atmosphere", "--out", "{tmp}/a.png", "--max-range", "nan km"],
    ["max-range"],
)
cli(
    "simulate-duration-1e400",
    "non-finite",
    ["simulate", "{uav}", "--runs", "2", "--duration", "1e400s"],
    ["duration"],
)
cli(
    "simulate-step-nan",
    "non-finite",
    ["simulate", "{uav}", "--runs", "2", "--duration", "1s", "--step", "nan s"],
    ["step"],
)

# -- out of the physical domain -------------------------------------------------------------
cli("dri-pitch-negative", "out-of-domain", [D, *SENSOR, "--pitch", "-17um"], ["pitch"])
cli("dri-focal-length-zero", "out-of-domain", [D, *SENSOR, "--focal-length", "0mm"], ["focal"])
cli(
    "dri-critical-dimension-negative",
    "out-of-domain",
    [D, *SENSOR[:4], "--critical-dimension", "-2.3m"],
    ["critical"],
)
cli(
    "dri-ifov-negative",
    "out-of-domain",
    [D, "--ifov", "-0.2mrad", "--critical-dimension", "2.3m"],
    ["ifov"],
)
cli(
    "dri-hfov-720deg",
    "out-of-domain",
    [D, "--hfov", "720deg", "--pixels", "640", "--critical-dimension", "2.3m"],
    ["hfov"],
)
cli(
    "dri-hfov-zero",
    "out-of-domain",
    [D, "--hfov", "0deg", "--pixels", "640", "--critical-dimension", "2.3m"],
    ["hfov"],
)
cli(
    "dri-pixels-zero",
    "out-of-domain",
    [D, "--hfov", "12deg", "--pixels", "0", "--critical-dimension", "2.3m"],
    ["pixels"],
)
cli(
    "dri-pixels-negative",
    "out-of-domain",
    [D, "--hfov", "12deg", "--pixels", "-640", "--critical-dimension", "2.3m"],
    ["pixels"],
)
cli("dri-probability-zero", "out-of-domain", [D, *SENSOR, "--probability", "0"], ["probability"])
cli("dri-probability-one", "out-of-domain", [D, *SENSOR, "--probability", "1"], ["probability"])
cli(
    "dri-probability-1.5",
    "out-of-domain",
    [D, *SENSOR, "--probability", "0.5,1.5"],
    ["probability"],
)
cli(
    "dri-probability-negative",
    "out-of-domain",
    [D, *SENSOR, "--probability", "-0.2"],
    ["probability"],
)
cli("dri-emissivity-1.5", "out-of-domain", [D, *THERMAL, "--emissivity", "1.5"], ["emissivity"])
cli(
    "dri-background-emissivity-negative",
    "out-of-domain",
    [D, *THERMAL, "--background-emissivity", "-0.1"],
    ["background-emissivity"],
)
cli(
    "dri-target-temperature-minus-5K",
    "out-of-domain",
    [D, *THERMAL, "--target-temperature", "-5K"],
    ["target-temperature"],
)
cli(
    "dri-background-temperature-0K",
    "out-of-domain",
    [D, *THERMAL, "--background-temperature", "0K"],
    ["background-temperature"],
)
cli(
    "dri-target-temperature-1e300K",
    "out-of-domain",
    [D, *THERMAL, "--target-temperature", "1e300K"],
    ["target-temperature"],
)
cli(
    "dri-target-temperature-minus-300degC",
    "out-of-domain",
    [D, *THERMAL, "--target-temperature", "-300degC"],
    ["target-temperature"],
)
cli("dri-scr-negative", "out-of-domain", [D, *SENSOR, "--scr", "-1"], ["scr"])
cli(
    "dri-extinction-negative",
    "out-of-domain",
    [D, *SENSOR, "--extinction", "-0.4/km"],
    ["extinction"],
)
cli(
    "dri-visibility-negative",
    "out-of-domain",
    [D, *SENSOR, "--band", "visible", "--visibility", "-1km", "--visibility-convention", "mor"],
    ["visibility"],
)
cli(
    "dri-f-number-zero",
    "out-of-domain",
    [D, *SENSOR, "--f-number", "0", "--wavelength", "10um"],
    ["f-number"],
)
cli(
    "dri-netd-negative",
    "out-of-domain",
    [D, *SENSOR, "--band", "lwir", "--netd", "-50mK", "--delta-t", "2K"],
    ["netd"],
)
cli(
    "dri-netd-temperature-negative",
    "out-of-domain",
    [D, *THERMAL, "--netd", "50mK", "--netd-temperature", "-300K"],
    ["netd-temperature"],
)
cli(
    "dri-nec-negative",
    "out-of-domain",
    [D, *SENSOR, "--nec", "-0.01", "--contrast", "0.3"],
    ["nec"],
)
cli("dri-blur-negative", "out-of-domain", [D, *SENSOR, "--blur", "-0.05mrad"], ["blur"])
cli(
    "dri-wavelength-negative",
    "out-of-domain",
    [D, *SENSOR, "--wavelength", "-10um", "--aperture", "75mm"],
    ["wavelength"],
)
cli("dri-n50-zero", "out-of-domain", [D, *SENSOR, "--n50", "0,4,6.4"], ["n50"])
cli("dri-n50-negative", "out-of-domain", [D, *SENSOR, "--n50", "-1,4,6.4"], ["n50"])
cli(
    "dri-target-area-negative",
    "out-of-domain",
    [D, *SENSOR, "--band", "lwir", "--netd", "50mK", "--delta-t", "2K", "--target-area", "-1m^2"],
    ["target-area"],
)
cli(
    "dri-clutter-std-negative",
    "out-of-domain",
    [D, *THERMAL, "--clutter-std", "-2K"],
    ["clutter-std"],
)
cli(
    "atmosphere-range-negative",
    "out-of-domain",
    ["atmosphere", "--range", "-1km", "--extinction", "0.4/km"],
    ["range"],
)
cli("clutter-box-negative-width", "out-of-domain", ["clutter", CAM, "--box", "0,0,-10,10"], ["box"])
cli("clutter-box-zero-size", "out-of-domain", ["clutter", CAM, "--box", "10,10,0,0"], ["box"])
cli(
    "clutter-box-outside-image",
    "out-of-domain",
    ["clutter", CAM, "--box", "600,600,20,20"],
    ["box"],
)
cli(
    "clutter-cell-factor-zero",
    "out-of-domain",
    ["clutter", CAM, "--box", "412,118,20,20", "--cell-factor", "0"],
    ["cell-factor"],
)
cli(
    "clutter-cycles-negative",
    "out-of-domain",
    ["clutter", CAM, "--box", "412,118,20,20", "--cycles", "-1"],
    ["cycles"],
)
cli(
    "simulate-duration-negative",
    "out-of-domain",
    ["simulate", "{uav}", "--runs", "2", "--duration", "-60s"],
    ["duration"],
)
cli(
    "simulate-step-zero",
    "out-of-domain",
    ["simulate", "{uav}", "--runs", "2", "--duration", "1s", "--step", "0s"],
    ["step"],
)
cli("simulate-runs-zero", "out-of-domain", ["simulate", "{uav}", "--runs", "0"], ["runs"])
cli(
    "simulate-seed-negative",
    "out-of-domain",
    ["simulate", "{uav}", *QUICK, "--seed", "-1"],
    ["seed"],
)
cli(
    "plot-curves-max-range-negative",
    "out-of-domain",
    ["plot", "curves", "--out", "{tmp}/c.png", *SENSOR, "--max-range", "-8km"],
    ["max-range"],
)
cli(
    "plot-atmosphere-max-range-zero",
    "out-of-domain",
    ["plot", "atmosphere", "--out", "{tmp}/a.png", "--max-range", "0km"],
    ["max-range"],
)

# -- wrong types ----------------------------------------------------------------------------
cli(
    "dri-pixels-fraction",
    "wrong-type",
    [D, "--hfov", "12deg", "--pixels", "640.5", "--critical-dimension", "2.3m"],
    ["pixels"],
)
cli(
    "dri-pixels-word",
    "wrong-type",
    [D, "--hfov", "12deg", "--pixels", "many", "--critical-dimension", "2.3m"],
    ["pixels"],
)
cli("dri-scr-word", "wrong-type", [D, *SENSOR, "--scr", "high"], ["scr"])
cli("dri-emissivity-yes", "wrong-type", [D, *THERMAL, "--emissivity", "yes"], ["emissivity"])
cli("dri-f-number-word", "wrong-type", [D, *SENSOR, "--f-number", "two"], ["f-number"])
cli("dri-probability-word", "wrong-type", [D, *SENSOR, "--probability", "half"], ["probability"])
cli(
    "dri-probability-with-unit", "wrong-type", [D, *SENSOR, "--probability", "50%"], ["probability"]
)
cli("dri-n50-words", "wrong-type", [D, *SENSOR, "--n50", "a,b,c"], ["n50"])
cli("dri-pitch-complex", "wrong-type", [D, *SENSOR, "--pitch", "(1+2j)um"], ["pitch"])
cli(
    "atmosphere-range-word",
    "wrong-type",
    ["atmosphere", "--range", "far", "--extinction", "0.4/km"],
    ["range"],
)
cli("simulate-runs-float", "wrong-type", ["simulate", "{uav}", "--runs", "1e3"], ["runs"])
cli("simulate-seed-word", "wrong-type", ["simulate", "{uav}", *QUICK, "--seed", "abc"], ["seed"])
cli("clutter-box-words", "wrong-type", ["clutter", CAM, "--box", "a,b,c,d"], ["box"])
cli("clutter-box-three-numbers", "wrong-type", ["clutter", CAM, "--box", "1,2,3"], ["box"])
cli(
    "clutter-cycles-word",
    "wrong-type",
    ["clutter", CAM, "--box", "412,118,20,20", "--cycles", "lots"],
    ["cycles"],
)

# -- contradictory or meaningless combinations ----------------------------------------------
cli("dri-n50-decreasing", "contradictory", [D, *SENSOR, "--n50", "8,4,1"], ["n50"])
cli("dri-n50-two-values", "contradictory", [D, *SENSOR, "--n50", "1,4"], ["n50"])
cli(
    "dri-probability-with-threshold-criterion",
    "contradictory",
    [
        D,
        "--hfov",
        "12deg",
        "--pixels",
        "640",
        "--critical-dimension",
        "2.3m",
        "--criterion",
        "en62676-4",
        "--probability",
        "0.8",
    ],
    ["probability"],
)
cli(
    "dri-criterion-and-n50",
    "contradictory",
    [D, *SENSOR, "--criterion", "johnson-truck", "--n50", "1,4,6.4"],
    ["n50"],
)
cli(
    "dri-pitch-without-focal-length",
    "contradictory",
    [D, "--pitch", "17um", "--critical-dimension", "2.3m"],
    ["focal-length"],
)
cli("dri-two-sensor-resolutions", "contradictory", [D, *SENSOR, "--ifov", "0.2mrad"], ["ifov"])
cli(
    "dri-aperture-and-f-number",
    "contradictory",
    [D, *SENSOR, "--aperture", "75mm", "--f-number", "1", "--wavelength", "10um"],
    ["f-number"],
)
cli(
    "dri-extinction-and-obscurant",
    "contradictory",
    [D, *SENSOR, "--band", "lwir", "--extinction", "0.4/km", "--obscurant", "haze"],
    ["obscurant"],
)
cli(
    "dri-scr-and-clutter",
    "contradictory",
    [D, *SENSOR, "--scr", "5", "--clutter", "low"],
    ["clutter"],
)
cli(
    "dri-schmieder-weathersby-without-clutter",
    "contradictory",
    [D, *SENSOR, "--transform", "schmieder-weathersby"],
    [("scr", "clutter")],
)
cli("dri-obscurant-without-band", "contradictory", [D, *SENSOR, "--obscurant", "haze"], ["band"])
cli(
    "dri-convention-without-visibility",
    "contradictory",
    [D, *SENSOR, "--visibility-convention", "mor"],
    ["visibility"],
)
cli(
    "dri-nec-and-netd",
    "contradictory",
    [
        D,
        *SENSOR,
        "--band",
        "lwir",
        "--nec",
        "0.01",
        "--contrast",
        "0.3",
        "--netd",
        "50mK",
        "--delta-t",
        "2K",
    ],
    ["nec"],
)
cli("dri-delta-t-alone", "contradictory", [D, *SENSOR, "--delta-t", "2K"], ["delta-t"])
cli(
    "dri-projection-with-pitch",
    "contradictory",
    [D, *SENSOR, "--projection", "rectilinear"],
    ["projection"],
)
cli("dri-bound-with-ttpf", "contradictory", [D, *SENSOR, "--bound", "optimistic"], ["bound"])
cli(
    "dri-target-temperature-alone",
    "contradictory",
    [D, *SENSOR, "--band", "lwir", "--target-temperature", "305K"],
    ["background-temperature"],
)
cli(
    "clutter-cycles-and-ranges",
    "contradictory",
    [
        "clutter",
        CAM,
        "--box",
        "412,118,20,20",
        "--cycles",
        "3",
        "--image-range",
        "1km",
        "--range",
        "2km",
    ],
    ["cycles"],
)
cli(
    "clutter-image-range-alone",
    "contradictory",
    ["clutter", CAM, "--box", "412,118,20,20", "--image-range", "1km"],
    ["range"],
)
cli(
    "plot-transforms-with-band",
    "contradictory",
    ["plot", "transforms", "--out", "{tmp}/t.png", "--band", "lwir"],
    ["band"],
)
cli(
    "report-scenario-with-sensor-options",
    "contradictory",
    ["report", "--out", "{tmp}/r.html", "{uav}", "--pitch", "17um"],
    ["pitch"],
)

# -- unknown options, choices and units -----------------------------------------------------
cli("unknown-command", "unknown", ["frobnicate"], ["frobnicate"])
cli("dri-unknown-option", "unknown", [D, *SENSOR, "--bogus", "1"], ["bogus"])
cli("dri-criterion-typo", "unknown", [D, *SENSOR, "--criterion", "jonson"], ["criterion"])
cli("dri-transform-unknown", "unknown", [D, *SENSOR, "--transform", "ttpff"], ["transform"])
cli("dri-band-unknown", "unknown", [D, *THERMAL[:-4], "--band", "uv", *THERMAL[-4:]], ["band"])
cli(
    "dri-band-reversed",
    "unknown",
    [D, *SENSOR, "--band", "12-8um", "--obscurant", "haze"],
    ["band"],
)
cli(
    "dri-obscurant-unknown",
    "unknown",
    [D, *SENSOR, "--band", "lwir", "--obscurant", "smog"],
    ["obscurant"],
)
cli(
    "dri-obscurant-level-unknown",
    "unknown",
    [D, *SENSOR, "--band", "lwir", "--obscurant", "haze:extreme"],
    [("level", "extreme")],
)
cli("dri-noise-model-unknown", "unknown", [D, *SENSOR, "--noise-model", "loud"], ["noise"])
cli("dri-semantics-unknown", "unknown", [D, *SENSOR, "--semantics", "fuzzy"], ["semantics"])
cli("dri-format-unknown", "unknown", [D, *SENSOR, "--format", "xml"], ["format"])
cli(
    "dri-projection-unknown",
    "unknown",
    [
        D,
        "--hfov",
        "12deg",
        "--pixels",
        "640",
        "--critical-dimension",
        "2.3m",
        "--projection",
        "fisheye",
    ],
    ["projection"],
)
cli(
    "dri-pixel-density-unknown",
    "unknown",
    [
        D,
        "--hfov",
        "12deg",
        "--pixels",
        "640",
        "--critical-dimension",
        "2.3m",
        "--criterion",
        "en62676-4",
        "--pixel-density",
        "sphere",
    ],
    ["pixel-density"],
)
cli(
    "dri-visibility-convention-unknown",
    "unknown",
    [D, *SENSOR, "--band", "visible", "--visibility", "5km", "--visibility-convention", "foo"],
    ["convention"],
)
cli(
    "dri-bound-unknown",
    "unknown",
    [D, *SENSOR, "--transform", "c2nveo", "--bound", "median"],
    ["bound"],
)
cli("dri-clutter-unknown", "unknown", [D, *SENSOR, "--clutter", "extreme"], ["clutter"])
cli("dri-pitch-unknown-unit", "unknown", [D, *SENSOR, "--pitch", "17parsnips"], ["pitch"])
cli("dri-pitch-wrong-dimension", "unknown", [D, *SENSOR, "--pitch", "17kg"], ["pitch"])
cli("dri-focal-length-seconds", "unknown", [D, *SENSOR, "--focal-length", "75s"], ["focal"])
cli("dri-extinction-length", "unknown", [D, *SENSOR, "--extinction", "0.4km"], ["extinction"])
cli(
    "dri-target-temperature-metres",
    "unknown",
    [D, *THERMAL, "--target-temperature", "305m"],
    ["target-temperature"],
)
cli(
    "atmosphere-format-unknown",
    "unknown",
    ["atmosphere", "--range", "1km", "--extinction", "0.4/km", "--format", "yaml"],
    ["format"],
)
cli(
    "clutter-channel-unknown",
    "unknown",
    ["clutter", CAM, "--box", "412,118,20,20", "--channel", "alpha"],
    ["channel"],
)
cli(
    "clutter-criterion-unknown",
    "unknown",
    ["clutter", CAM, "--box", "412,118,20,20", "--criterion", "bogus"],
    ["criterion"],
)
cli(
    "clutter-format-unknown",
    "unknown",
    ["clutter", CAM, "--box", "412,118,20,20", "--format", "html"],
    ["format"],
)
cli("plot-kind-unknown", "unknown", ["plot", "pie", "--out", "{tmp}/p.png"], ["pie"])
cli("plot-out-suffix", "unknown", ["plot", "transforms", "--out", "{tmp}/p.gif"], ["p.gif"])
cli(
    "plot-level-unknown",
    "unknown",
    ["plot", "atmosphere", "--out", "{tmp}/a.png", "--level", "extreme"],
    ["level"],
)
cli("report-out-suffix", "unknown", ["report", "--out", "{tmp}/r.docx", *SENSOR], ["r.docx"])
cli("evaluate-out-suffix", "unknown", ["evaluate", "--out", "{tmp}/x.xlsx"], ["x.xlsx"])
cli("evaluate-format-unknown", "unknown", ["evaluate", "--format", "yaml"], ["format"])
cli(
    "simulate-format-unknown",
    "unknown",
    ["simulate", "{uav}", *QUICK, "--format", "yaml"],
    ["format"],
)
cli(
    "simulate-duration-metres",
    "unknown",
    ["simulate", "{uav}", "--runs", "2", "--duration", "60m"],
    ["duration"],
)
cli("validation-out-suffix", "unknown", ["validation", "--out", "{tmp}/v.txt"], ["v.txt"])

# -- the obvious: empty, missing, no unit ---------------------------------------------------
cli("dri-no-sensor", "obvious", [D, "--critical-dimension", "2.3m"], [])
cli("dri-no-target", "obvious", [D, "--pitch", "17um", "--focal-length", "75mm"], ["critical"])
cli("dri-pitch-empty", "obvious", [D, *SENSOR, "--pitch", ""], ["pitch"])
cli("dri-pitch-no-unit", "obvious", [D, *SENSOR, "--pitch", "17"], ["pitch"])
cli(
    "dri-critical-dimension-no-unit",
    "obvious",
    [D, *SENSOR[:4], "--critical-dimension", "2.3"],
    ["critical"],
)
cli("dri-probability-empty", "obvious", [D, *SENSOR, "--probability", ""], ["probability"])
cli("dri-n50-empty", "obvious", [D, *SENSOR, "--n50", ""], ["n50"])
cli("dri-band-empty", "obvious", [D, *SENSOR, "--band", "", "--obscurant", "haze"], ["band"])
cli("dri-criterion-empty", "obvious", [D, *SENSOR, "--criterion", ""], ["criterion"])
cli("dri-option-without-value", "obvious", [D, *SENSOR, "--pitch"], ["pitch"])
cli("atmosphere-no-range", "obvious", ["atmosphere", "--extinction", "0.4/km"], ["range"])
cli(
    "atmosphere-range-empty",
    "obvious",
    ["atmosphere", "--range", "", "--extinction", "0.4/km"],
    ["range"],
)
cli("atmosphere-no-path", "obvious", ["atmosphere", "--range", "1km"], ["extinction"])
cli("validate-no-argument", "obvious", ["validate"], ["scenario"])
cli("clutter-no-box", "obvious", ["clutter", CAM], ["box"])
cli("clutter-no-image", "obvious", ["clutter", "--box", "1,2,3,4"], ["image"])
cli("plot-no-out", "obvious", ["plot", "transforms"], ["out"])
cli("simulate-no-scenario", "obvious", ["simulate"], ["scenario"])
cli("simulate-step-empty", "obvious", ["simulate", "{uav}", "--runs", "2", "--step", ""], ["step"])
cli(
    "simulate-duration-no-unit",
    "obvious",
    ["simulate", "{uav}", "--runs", "2", "--duration", "60"],
    ["duration"],
)

# -- files: missing, unreadable, a folder, a device, too large, too deep, not text ----------
cli("validate-missing-file", "file", ["validate", "{tmp}/missing.toml"], ["missing.toml"])
cli(
    "validate-directory",
    "file",
    ["validate", "{tmp}/folder.toml"],
    ["folder.toml", ("director", "folder")],
    setup=mkdir("folder.toml"),
)
cli("validate-dev-null", "file", ["validate", "/dev/null"], ["/dev/null", ("device", "not a")])
if not IS_ROOT:
    cli(
        "validate-unreadable",
        "file",
        ["validate", "{tmp}/secret.toml"],
        ["secret.toml"],
        setup=unreadable("secret.toml", UAV.read_text()),
    )
cli(
    "validate-binary",
    "file",
    ["validate", "{tmp}/binary.toml"],
    ["binary.toml"],
    setup=write("binary.toml", bytes(range(256)) * 4),
)
cli(
    "validate-oversized",
    "file",
    ["validate", "{tmp}/big.toml"],
    ["big.toml", ("large", "big", "size", "mb")],
    setup=lambda tmp: write("big.toml", big_toml())(tmp),
)
cli(
    "validate-deeply-nested",
    "file",
    ["validate", "{tmp}/deep.toml"],
    ["deep.toml", ("nest", "deep")],
    setup=write("deep.toml", nested_toml(5000)),
)
cli(
    "validate-deep-tables",
    "file",
    ["validate", "{tmp}/tables.toml"],
    ["tables.toml"],
    setup=write("tables.toml", "x = " + "{a = " * 3000 + "1" + "}" * 3000 + "\n"),
)
cli(
    "validate-malformed",
    "file",
    ["validate", "{tmp}/bad.toml"],
    ["bad.toml", "line"],
    setup=write("bad.toml", "name = 'x'\n[time\nstop = '1 s'\n"),
)
cli(
    "validate-duplicate-key",
    "file",
    ["validate", "{tmp}/dup.toml"],
    ["dup.toml"],
    setup=write("dup.toml", "name = 'a'\nname = 'b'\n"),
)
cli(
    "validate-empty-file",
    "file",
    ["validate", "{tmp}/empty.toml"],
    ["empty.toml", "sensors"],
    setup=write("empty.toml", ""),
)
cli("validate-png-as-scenario", "file", ["validate", CAM], ["camera.png"])
cli("evaluate-missing-file", "file", ["evaluate", "{tmp}/missing.toml"], ["missing.toml"])
cli("evaluate-directory", "file", ["evaluate", "{tmp}"], [("director", "folder")])
cli("simulate-missing-file", "file", ["simulate", "{tmp}/missing.toml", *QUICK], ["missing.toml"])
cli(
    "report-missing-scenario",
    "file",
    ["report", "--out", "{tmp}/r.html", "{tmp}/missing.toml"],
    ["missing.toml"],
)
cli(
    "dri-mrtd-missing",
    "file",
    [D, *SENSOR, "--band", "lwir", "--delta-t", "2K", "--mrtd", "{tmp}/missing.csv"],
    ["missing.csv"],
)
cli(
    "dri-mrtd-directory",
    "file",
    [D, *SENSOR, "--band", "lwir", "--delta-t", "2K", "--mrtd", "{tmp}"],
    ["mrtd"],
)
cli(
    "dri-mrtd-malformed",
    "file",
    [D, *SENSOR, "--band", "lwir", "--delta-t", "2K", "--mrtd", "{tmp}/m.csv"],
    ["m.csv"],
    setup=write("m.csv", "frequency,mrtd\n0.5,cold\n1,0.02\n"),
)
cli(
    "dri-mrtd-nan",
    "file",
    [D, *SENSOR, "--band", "lwir", "--delta-t", "2K", "--mrtd", "{tmp}/m.csv"],
    ["m.csv"],
    setup=write("m.csv", "frequency,mrtd\n0.5,nan\n1,0.02\n2,0.05\n"),
)
cli(
    "clutter-missing-image",
    "file",
    ["clutter", "{tmp}/missing.png", "--box", "1,2,3,4"],
    ["missing.png"],
)
cli(
    "clutter-directory-image",
    "file",
    ["clutter", "{tmp}/pictures", "--box", "1,2,3,4"],
    ["pictures"],
    setup=mkdir("pictures"),
)
cli(
    "clutter-text-as-image",
    "file",
    ["clutter", "{tmp}/note.png", "--box", "1,2,3,4"],
    ["note.png"],
    setup=write("note.png", "not an image\n"),
)
cli(
    "clutter-truncated-png",
    "file",
    ["clutter", "{tmp}/cut.png", "--box", "1,2,3,4"],
    ["cut.png"],
    setup=write("cut.png", CAMERA.read_bytes()[:2000]),
)
cli(
    "clutter-boxes-missing",
    "file",
    ["clutter", CAM, "--boxes", "{tmp}/missing.csv"],
    ["missing.csv"],
)
cli("clutter-boxes-directory", "file", ["clutter", CAM, "--boxes", "{tmp}"], ["boxes"])
cli(
    "clutter-boxes-wrong-columns",
    "file",
    ["clutter", CAM, "--boxes", "{tmp}/b.csv"],
    ["b.csv"],
    setup=write("b.csv", "a,b,c\n1,2,3\n"),
)
cli(
    "clutter-boxes-words",
    "file",
    ["clutter", CAM, "--boxes", "{tmp}/b.csv"],
    ["b.csv"],
    setup=write("b.csv", "x,y,width,height\n1,2,three,4\n"),
)
cli(
    "clutter-boxes-binary",
    "file",
    ["clutter", CAM, "--boxes", "{tmp}/b.csv"],
    ["b.csv"],
    setup=write("b.csv", bytes(range(256)) * 4),
)

# -- sizes that cannot fit ------------------------------------------------------------------
cli("simulate-runs-1e9", "size", ["simulate", "{uav}", "--runs", "1000000000"], ["runs"])
cli("simulate-runs-overflowing", "size", ["simulate", "{uav}", "--runs", str(10**30)], ["runs"])
cli(
    "simulate-duration-1e9s",
    "size",
    ["simulate", "{uav}", "--runs", "2", "--duration", "1e9s"],
    [("duration", "step")],
)
cli(
    "simulate-step-1ns",
    "size",
    ["simulate", "{uav}", "--runs", "2", "--step", "1ns"],
    [("duration", "step")],
)
cli(
    "simulate-seed-2-to-128", "size", ["simulate", "{uav}", *QUICK, "--seed", str(2**128)], ["seed"]
)
cli("simulate-seed-huge", "size", ["simulate", "{uav}", *QUICK, "--seed", str(10**60)], ["seed"])
cli(
    "dri-pixels-overflowing",
    "size",
    [D, "--hfov", "12deg", "--pixels", str(2**64), "--critical-dimension", "2.3m"],
    ["pixels"],
)

# -- output failures ------------------------------------------------------------------------
cli(
    "evaluate-out-directory",
    "output",
    ["evaluate", "--out", "{tmp}/d.csv"],
    ["d.csv"],
    setup=mkdir("d.csv"),
)
cli("evaluate-out-missing-folder", "output", ["evaluate", "--out", "{tmp}/no/x.csv"], ["x.csv"])
cli(
    "evaluate-out-proc",
    "output",
    ["evaluate", "--out", "/proc/targetacq-test.csv"],
    ["targetacq-test.csv"],
)
cli(
    "evaluate-out-json-directory",
    "output",
    ["evaluate", "--out", "{tmp}/d.json"],
    ["d.json"],
    setup=mkdir("d.json"),
)
cli(
    "evaluate-out-parquet-directory",
    "output",
    ["evaluate", "--out", "{tmp}/d.parquet"],
    ["d.parquet"],
    setup=mkdir("d.parquet"),
)
cli(
    "plot-out-directory",
    "output",
    ["plot", "transforms", "--out", "{tmp}/d.png"],
    ["d.png"],
    setup=mkdir("d.png"),
)
cli(
    "plot-out-proc",
    "output",
    ["plot", "transforms", "--out", "/proc/targetacq-test.svg"],
    ["targetacq-test.svg"],
)
cli(
    "report-out-directory",
    "output",
    ["report", "--out", "{tmp}/d.html", *SENSOR],
    ["d.html"],
    setup=mkdir("d.html"),
)
cli(
    "report-out-proc",
    "output",
    ["report", "--out", "/proc/targetacq-test.html", *SENSOR],
    ["targetacq-test.html"],
)
cli(
    "clutter-overlay-directory",
    "output",
    ["clutter", CAM, "--box", "412,118,20,20", "--overlay", "{tmp}/d.png"],
    ["d.png"],
    setup=mkdir("d.png"),
)
cli(
    "clutter-overlay-suffix",
    "output",
    ["clutter", CAM, "--box", "412,118,20,20", "--overlay", "{tmp}/o.jpg"],
    ["o.jpg"],
)
cli(
    "clutter-overlay-proc",
    "output",
    ["clutter", CAM, "--box", "412,118,20,20", "--overlay", "/proc/targetacq-test.png"],
    ["targetacq-test.png"],
)
cli(
    "validation-out-directory",
    "output",
    ["validation", "--out", "{tmp}/d.html"],
    ["d.html"],
    setup=mkdir("d.html"),
)
if not IS_ROOT:
    cli(
        "evaluate-out-read-only-folder",
        "output",
        ["evaluate", "--out", "{tmp}/ro/x.csv"],
        ["x.csv"],
        setup=mkdir("ro", 0o555),
    )
    cli(
        "plot-out-read-only-folder",
        "output",
        ["plot", "transforms", "--out", "{tmp}/ro/x.png"],
        ["x.png"],
        setup=mkdir("ro", 0o555),
    )
    cli(
        "report-out-read-only-folder",
        "output",
        ["report", "--out", "{tmp}/ro/x.html", *SENSOR],
        ["x.html"],
        setup=mkdir("ro", 0o555),
    )


# -- issue 28: what an analyst hits first --------------------------------------------------


def _png(name: str, shape: tuple[int, int]) -> Callable[[Path], None]:
    def setup(tmp: Path) -> None:
        from PIL import Image

        Image.fromarray(np.full(shape, 100, dtype=np.uint8)).save(tmp / name)

    return setup


# An image clutter measure needs background pixels around the box: NaN and exit 0 before.
cli(
    "clutter-1x1-image",
    "out-of-domain",
    ["clutter", "{tmp}/one.png", "--box", "0,0,1,1"],
    ["box", "background"],
    setup=_png("one.png", (1, 1)),
)
cli(
    "clutter-box-whole-image",
    "out-of-domain",
    ["clutter", CAM, "--box", "0,0,512,512"],
    ["box", "background"],
)
# A sweep beyond the points limit, refused before any work (a 9-million-point sweep failed
# after 178 s before).
cli(
    "sweep-1001x1000-points",
    "size",
    [
        "sweep",
        "--example",
        "--focal-length",
        ",".join(f"{v}mm" for v in range(10, 1011)),
        "--scr",
        ",".join(str(v) for v in range(1, 1001)),
    ],
    ["1,001,000 points", "1,000,000"],
)


@pytest.mark.parametrize("case", [c for c in CASES if c.kind == "cli"], ids=lambda c: c.id)
def test_command_line(case: Case, tmp_path: Path, capsys: Any) -> None:
    if case.setup is not None:
        case.setup(tmp_path)
    argv = substitute(case.what, tmp_path)
    check_error(argv, run_cli(capsys, argv), case.names, many=argv[0] == "validate")
    leftovers = [p.name for p in tmp_path.iterdir() if p.name.startswith(".")]
    assert not leftovers, f"temporary files left behind: {leftovers}"


# ===========================================================================================
# Scenario files: one field of a bundled example broken; `validate` and `evaluate` refuse it
# ===========================================================================================

S = scenario
ONE_M = ["0 m", "0 m", "0 m"]

# -- non-finite ------------------------------------------------------------------------------
S("pitch-1e400", "non-finite", put("sensors[0].pitch", "1e400 um"), ["pitch"])
S("pitch-nan", "non-finite", put("sensors[0].pitch", "nan um"), ["pitch"])
S("focal-length-inf", "non-finite", put("sensors[0].focal_length", "inf mm"), ["focal_length"])
S("temperature-1e400", "non-finite", put("targets[0].temperature", "1e400 K"), ["temperature"])
S("dimension-1e400", "non-finite", put("targets[0].dimensions[0]", "1e400 m"), ["dimensions"])
S("position-nan", "non-finite", put("targets[0].position[0]", "nan m"), ["position"])
S("waypoint-inf", "non-finite", put("sensors[0].waypoints[0].position[2]", "inf km"), ["position"])
S("waypoint-time-nan", "non-finite", put("targets[2].waypoints[1].time", "nan s"), ["time"])
S(
    "extinction-1e400",
    "non-finite",
    both(drop("atmosphere.obscurant"), put("atmosphere.extinction", "1e400 /km")),
    ["extinction"],
)
S("clutter-std-1e400", "non-finite", put("background.clutter_std", "1e400 K"), ["clutter_std"])
S("azimuth-nan", "non-finite", put("sensors[0].azimuth", "nan deg"), ["azimuth"])
S("search-time-1e400", "non-finite", put("model.search_time", "1e400 s"), ["search_time"])
S(
    "emissivity-toml-nan",
    "non-finite",
    put("targets[1].emissivity", Raw("nan")),
    ["emissivity"],
    base=FUSED,
)
S(
    "emissivity-toml-1e400",
    "non-finite",
    put("targets[1].emissivity", Raw("1e400")),
    ["emissivity"],
    base=FUSED,
)
S(
    "reflectance-toml-inf",
    "non-finite",
    put("targets[0].reflectance", Raw("inf")),
    ["reflectance"],
    base=FUSED,
)
S(
    "irradiance-1e400",
    "non-finite",
    put("background.irradiance", "1e400 W/m^2"),
    ["irradiance"],
    base=FUSED,
)
S(
    "background-temperature-nan",
    "non-finite",
    put("background.temperature", "nan K"),
    ["temperature"],
)

# -- out of domain ---------------------------------------------------------------------------
S("depression-720deg", "out-of-domain", put("sensors[0].depression", "720 deg"), ["depression"])
S("azimuth-1000deg", "out-of-domain", put("sensors[0].azimuth", "1000 deg"), ["azimuth"])
S("heading-minus-400deg", "out-of-domain", put("targets[1].heading", "-400 deg"), ["heading"])
S("temperature-minus-5K", "out-of-domain", put("targets[0].temperature", "-5 K"), ["temperature"])
S("temperature-1e300K", "out-of-domain", put("targets[0].temperature", "1e300 K"), ["temperature"])
S(
    "background-temperature-0K",
    "out-of-domain",
    put("background.temperature", "0 K"),
    ["temperature"],
)
S("dimension-negative", "out-of-domain", put("targets[0].dimensions[1]", "-2.5 m"), ["dimensions"])
S("pitch-negative", "out-of-domain", put("sensors[0].pitch", "-17 um"), ["pitch"])
S("pixels-zero", "out-of-domain", put("sensors[0].pixels", [0, 512]), ["pixels"])
S("clutter-std-negative", "out-of-domain", put("background.clutter_std", "-2 K"), ["clutter_std"])
S("emissivity-1.5", "out-of-domain", put("targets[1].emissivity", 1.5), ["emissivity"], base=FUSED)
S(
    "reflectance-negative",
    "out-of-domain",
    put("targets[0].reflectance", -0.1),
    ["reflectance"],
    base=FUSED,
)
S(
    "visible-fraction-zero",
    "out-of-domain",
    put("targets[0].visible_fraction", 0.0),
    ["visible_fraction"],
)
S("search-time-zero", "out-of-domain", put("model.search_time", "0 s"), ["search_time"])
S("step-negative", "out-of-domain", put("time.step", "-1 s"), ["step"])
S("stop-before-start", "out-of-domain", put("time.stop", "-10 s"), ["stop"])
S("netd-negative", "out-of-domain", put("sensors[0].netd", "-50 mK"), ["netd"])
S(
    "netd-temperature-negative",
    "out-of-domain",
    put("sensors[0].netd_temperature", "-300 K"),
    ["netd_temperature"],
)
S(
    "hfov-200deg",
    "out-of-domain",
    both(
        drop("sensors[0].pitch"),
        drop("sensors[0].focal_length"),
        drop("sensors[0].aperture"),
        put("sensors[0].hfov", "200 deg"),
    ),
    ["hfov"],
)
S(
    "f-number-zero",
    "out-of-domain",
    both(drop("sensors[0].aperture"), put("sensors[0].f_number", 0)),
    ["f_number"],
)
S(
    "extinction-negative",
    "out-of-domain",
    both(drop("atmosphere.obscurant"), put("atmosphere.extinction", "-0.1 /km")),
    ["extinction"],
)
S("n50-zero", "out-of-domain", put("model.n50", [0, 4, 6.4]), ["n50"])
S(
    "cloud-radius-negative",
    "out-of-domain",
    put("atmosphere.clouds", [{"center": ONE_M, "radius": "-5 m", "extinction": "1 /km"}]),
    ["radius"],
)
S(
    "segment-length-negative",
    "out-of-domain",
    put("atmosphere.segments", [{"length": "-1 km", "extinction": "1 /km"}]),
    ["length"],
)

# -- wrong types ----------------------------------------------------------------------------
S("moving-yes", "wrong-type", put("targets[2].moving", "yes"), ["moving"])
S(
    "hot-spot-string-true",
    "wrong-type",
    put("targets[0].hot_spot", "true"),
    ["hot_spot"],
    base=AIRCRAFT,
)
S("hot-spot-one", "wrong-type", put("targets[0].hot_spot", 1), ["hot_spot"], base=AIRCRAFT)
S("pixels-strings", "wrong-type", put("sensors[0].pixels", ["640", 512]), ["pixels"])
S("pixels-fraction", "wrong-type", put("sensors[0].pixels", [640.5, 512]), ["pixels"])
S(
    "emissivity-string",
    "wrong-type",
    put("targets[1].emissivity", "0.9"),
    ["emissivity"],
    base=FUSED,
)
S("n50-strings", "wrong-type", put("model.n50", ["1", "4", "6.4"]), ["n50"])
S("name-number", "wrong-type", put("name", 5), ["name"])
S("sensors-string", "wrong-type", put("sensors", "camera"), ["sensors"])
S("dimensions-string", "wrong-type", put("targets[0].dimensions", "7 m"), ["dimensions"])
S("time-number", "wrong-type", put("time", 5), ["time"])
S("background-list", "wrong-type", put("background", []), ["background"])
S("band-number", "wrong-type", put("sensors[0].band", 10), ["band"])
S("criterion-list", "wrong-type", put("model.criterion", ["johnson"]), ["criterion"])
S("position-bool", "wrong-type", put("sensors[0].position", True), ["position"], base=FUSED)
S("waypoints-table", "wrong-type", put("targets[2].waypoints", {"time": "0 s"}), ["waypoints"])
S("start-datetime", "wrong-type", put("time.start", Raw("1979-05-27T07:32:00Z")), ["start"])
S("pitch-table", "wrong-type", put("sensors[0].pitch", {"value": 17, "unit": "um"}), ["pitch"])
S(
    "image-box-words",
    "wrong-type",
    put("targets[0].image_box", ["a", 1, 2, 3]),
    ["image_box"],
    base=GOLDEN / "image.toml",
)

# -- contradictory or meaningless -----------------------------------------------------------
S(
    "emissivity-and-material",
    "contradictory",
    put("targets[1].material", "olive-paint"),
    [("material", "emissivity")],
    base=FUSED,
)
S(
    "look-at-equals-position",
    "contradictory",
    put("sensors[0].look_at", ["0 m", "0 m", "15 m"]),
    ["look_at"],
    base=FUSED,
)
S(
    "schmieder-weathersby-without-clutter",
    "contradictory",
    both(drop("background.clutter_std"), put("model.transform", "schmieder-weathersby")),
    [("clutter", "scr")],
)
S(
    "threshold-criterion-on-target",
    "contradictory",
    put("targets[0].criterion", "en62676-4"),
    ["criterion"],
)
S(
    "threshold-criterion-in-model",
    "contradictory",
    put("model.criterion", "en62676-4"),
    ["criterion"],
)
S("n50-decreasing", "contradictory", put("model.n50", [8, 4, 1]), ["n50"])
S("two-resolutions", "contradictory", put("sensors[0].ifov", "0.2 mrad"), ["ifov"])
S(
    "look-at-and-azimuth",
    "contradictory",
    put("sensors[0].look_at", ["1 km", "0 m", "0 m"]),
    ["look_at"],
)
S(
    "position-and-waypoints",
    "contradictory",
    put("sensors[0].position", ONE_M),
    [("position", "waypoints")],
)
S(
    "neither-position-nor-waypoints",
    "contradictory",
    drop("targets[0].position"),
    [("position", "waypoints")],
)
S(
    "waypoints-decreasing-times",
    "contradictory",
    put("targets[2].waypoints[1].time", "-5 s"),
    ["waypoints"],
)
S("clutter-and-clutter-std", "contradictory", put("background.clutter", "low"), ["clutter"])
S(
    "extinction-and-obscurant",
    "contradictory",
    put("atmosphere.extinction", "0.1 /km"),
    [("extinction", "obscurant")],
)
S(
    "visibility-without-convention",
    "contradictory",
    both(drop("atmosphere.obscurant"), put("atmosphere.visibility", "5 km")),
    ["visibility"],
)
S("netd-on-tv-sensor", "contradictory", put("sensors[0].netd", "50 mK"), ["netd"], base=FUSED)
S("thermal-without-band", "contradictory", drop("sensors[0].band"), ["band"])
S("duplicate-sensor", "contradictory", copy_of("sensors", 0), ["sensor", "uav-lwir"])
S("duplicate-target", "contradictory", copy_of("targets", 1), ["target", "tank"])
S("bound-with-ttpf", "contradictory", put("model.bound", "optimistic"), ["bound"])
S(
    "projection-with-pitch",
    "contradictory",
    put("sensors[0].projection", "rectilinear"),
    ["projection"],
)
S(
    "image-without-boxes",
    "contradictory",
    both(drop("background.clutter_std"), put("background.image", str(CAMERA))),
    ["image_box"],
)
S("azimuth-without-depression", "contradictory", drop("sensors[0].depression"), ["depression"])

# -- unknown keys, choices and units --------------------------------------------------------
S(
    "unknown-key-typo",
    "unknown",
    both(drop("sensors[0].pitch"), put("sensors[0].pitchh", "17 um")),
    ["pitchh"],
)
S("unknown-top-level-table", "unknown", put("sensor", {"name": "x"}), ["sensor"])
S("criterion-typo", "unknown", put("model.criterion", "jonson"), ["criterion"])
S("transform-unknown", "unknown", put("model.transform", "magic"), ["transform"])
S("band-unknown", "unknown", put("sensors[0].band", "uv"), ["band"])
S("sensor-type-unknown", "unknown", put("sensors[0].type", "radar"), ["type"])
S("obscurant-unknown", "unknown", put("atmosphere.obscurant", "smog"), ["obscurant"])
S("obscurant-level-unknown", "unknown", put("atmosphere.obscurant", "haze:extreme"), ["obscurant"])
S("material-unknown", "unknown", put("background.material", "plastic"), ["material"])
S(
    "clutter-region-unknown",
    "unknown",
    both(drop("background.clutter_std"), put("background.clutter", "extreme")),
    ["clutter"],
)
S("unit-unknown", "unknown", put("sensors[0].pitch", "17 parsnips"), ["pitch"])
S("unit-wrong-dimension", "unknown", put("sensors[0].pitch", "17 kg"), ["pitch"])
S("temperature-in-metres", "unknown", put("targets[0].temperature", "305 m"), ["temperature"])
S("step-in-metres", "unknown", put("time.step", "10 m"), ["step"])
S("noise-model-unknown", "unknown", put("model.noise_model", "loud"), ["noise"])
S("semantics-unknown", "unknown", put("model.semantics", "fuzzy"), ["semantics"])
S("motion-unknown", "unknown", put("model.motion", "teleport"), ["motion"])
S("fusion-unknown", "unknown", put("model.fusion", "decision-level"), ["fusion"])
S(
    "channel-unknown",
    "unknown",
    put("background.channel", "alpha"),
    ["channel"],
    base=GOLDEN / "image.toml",
)

# -- the obvious ----------------------------------------------------------------------------
S("pitch-empty", "obvious", put("sensors[0].pitch", ""), ["pitch"])
S("temperature-empty", "obvious", put("targets[0].temperature", ""), ["temperature"])
S("pitch-no-unit", "obvious", put("sensors[0].pitch", "17"), ["pitch"])
S("pitch-bare-number", "obvious", put("sensors[0].pitch", 17), ["pitch"])
S("no-sensors", "obvious", put("sensors", []), ["sensors"])
S("no-targets", "obvious", put("targets", []), ["targets"])
S("sensors-missing", "obvious", drop("sensors"), ["sensors"])
S("dimensions-missing", "obvious", drop("targets[0].dimensions"), ["dimensions"])
S("sensor-name-missing", "obvious", drop("sensors[0].name"), ["name"])
S("two-dimensions", "obvious", put("targets[0].dimensions", ["7 m", "2.5 m"]), ["dimensions"])
S(
    "position-two-coordinates",
    "obvious",
    put("targets[0].position", ["1 km", "100 m"]),
    ["position"],
)
S(
    "one-waypoint",
    "obvious",
    put("targets[2].waypoints", [{"time": "0 s", "position": ONE_M}]),
    ["waypoints"],
)
S("step-zero", "obvious", put("time.step", "0 s"), ["step"])

# -- files a scenario names: image and terrain map ------------------------------------------
IMAGE = GOLDEN / "image.toml"
TERRAIN = GOLDEN / "terrain.toml"
S(
    "image-missing",
    "referenced-file",
    put("background.image", lambda t: str(t / "missing.png")),
    ["missing.png"],
    base=IMAGE,
)
S(
    "image-directory",
    "referenced-file",
    put("background.image", folder_in("pictures")),
    ["pictures"],
    base=IMAGE,
)
S(
    "image-not-an-image",
    "referenced-file",
    put("background.image", file_in("note.png", "not an image\n")),
    ["note.png"],
    base=IMAGE,
)
S(
    "image-truncated",
    "referenced-file",
    put("background.image", file_in("cut.png", CAMERA.read_bytes()[:2000])),
    ["cut.png"],
    base=IMAGE,
)
S(
    "image-box-outside",
    "referenced-file",
    put("targets[0].image_box", [600, 600, 20, 20]),
    ["image_box"],
    base=IMAGE,
)
S(
    "image-box-zero-width",
    "referenced-file",
    put("targets[1].image_box", [10, 10, 0, 10]),
    ["image_box"],
    base=IMAGE,
)
S(
    "image-box-negative",
    "referenced-file",
    put("targets[0].image_box", [-30, 10, 20, 20]),
    ["image_box"],
    base=IMAGE,
)
S(
    "terrain-map-missing",
    "referenced-file",
    put("background.terrain.map", lambda t: str(t / "missing.csv")),
    ["missing.csv"],
    base=TERRAIN,
)
S(
    "terrain-map-directory",
    "referenced-file",
    put("background.terrain.map", folder_in("maps")),
    ["maps"],
    base=TERRAIN,
)
S(
    "terrain-map-class-out-of-range",
    "referenced-file",
    put("background.terrain.map", file_in("map.csv", "0,0,1,5\n0,0,1,1\n")),
    [("map.csv", "terrain.map")],
    base=TERRAIN,
)
S(
    "terrain-map-words",
    "referenced-file",
    put("background.terrain.map", file_in("map.csv", "0,grass,1\n0,0,1\n")),
    ["map.csv"],
    base=TERRAIN,
)
S(
    "terrain-map-empty",
    "referenced-file",
    put("background.terrain.map", file_in("map.csv", "")),
    ["map.csv"],
    base=TERRAIN,
)
S(
    "terrain-map-ragged",
    "referenced-file",
    put("background.terrain.map", file_in("map.csv", "0,0,1\n0,1\n")),
    ["map.csv"],
    base=TERRAIN,
)
S(
    "terrain-class-temperature-negative",
    "referenced-file",
    put("background.terrain.classes[0].temperature", "-5 K"),
    ["temperature"],
    base=TERRAIN,
)

# -- sizes ----------------------------------------------------------------------------------
S("step-1ns", "size", put("time.step", "1 ns"), ["step"])
S("stop-1e400s", "size", put("time.stop", "1e400 s"), ["stop"])
S("stop-1e15s", "size", put("time.stop", "1e15 s"), [("step", "stop")])
S("pixels-overflowing", "size", put("sensors[0].pixels", [2**64, 512]), ["pixels"])

# -- decibels beyond double precision (10 ** (dB / 10) overflowed: OverflowError, exit 1) ----
S(
    "radar-gain-4000dB",
    "non-finite",
    put("sensors[0].radar.gain", "4000 dB"),
    ["gain", "3000 dB"],
    base=RADAR,
)
# -- silently accepted before ----------------------------------------------------------------
S(
    "colour-reflectance-band-uv",
    "unknown",
    put("targets[0].reflectance.uv", 0.3),
    ["reflectance", "uv"],
    base=COLOUR,
)
S(
    "colour-irradiance-band-nir",
    "unknown",
    put(
        "background.irradiance",
        {"red": "5 W/m^2", "green": "5 W/m^2", "blue": "5 W/m^2", "nir": "9 W/m^2"},
    ),
    ["irradiance.nir"],
    base=COLOUR,
)
S(
    "false-targets-sensors-empty",
    "obvious",
    put("false_targets.sensors", []),
    ["false_targets.sensors", "empty"],
    base=LASER,
)
# -- an image box with no background around it (NaN probabilities, exit 0 before) ----------
S(
    "image-box-whole-image",
    "referenced-file",
    put("targets[0].image_box", [0, 0, 512, 512]),
    ["image_box", "background"],
    base=IMAGE,
)


@pytest.mark.parametrize("case", [c for c in CASES if c.kind == "scenario"], ids=lambda c: c.id)
def test_scenario_file(case: Case, tmp_path: Path, capsys: Any) -> None:
    document = read_base(case.base)
    case.what(document, tmp_path)
    path = tmp_path / "case.toml"
    path.write_text(toml_dumps(document), encoding="utf-8")
    argv = ["validate", str(path)]
    check_error(argv, run_cli(capsys, argv), [*case.names, "case.toml"], many=True)
    if case.evaluate:
        argv = ["evaluate", str(path)]
        check_error(argv, run_cli(capsys, argv), case.names)


# ===========================================================================================
# Python: functions and records
# ===========================================================================================


def _ta(module: str = "") -> Any:
    """The package, or one of its modules by its path under ``targetacq``."""
    import importlib

    return importlib.import_module(f"targetacq.{module}" if module else "targetacq")


def _scenario_dict(base: Path = UAV) -> dict[str, Any]:
    return read_base(base)


def _chain(base: Path = UAV) -> Any:
    from targetacq.run.model_chain import ModelChain
    from targetacq.scenario.schema import load_scenario

    return ModelChain(load_scenario(base))


def _sim(seed: Any = 0) -> Any:
    from targetacq.scenario.schema import Background, Sensor, Target

    return _ta().Simulation(
        [Sensor(name="ir", band="lwir", ifov=0.25e-3, position=(0.0, 0.0, 5.0))],
        [
            Target(name="a", dimensions=(7.0, 2.5, 3.0), temperature=305.0, position=ZERO),
            Target(name="b", dimensions=(7.0, 2.5, 3.0), temperature=305.0, position=ZERO),
        ],
        background=Background(temperature=295.0),
        seed=seed,
    )


ZERO = (0.0, 0.0, 0.0)
SENSOR_POSITIONS = np.array([[0.0, 0.0, 5.0]])
TARGET_POSITIONS = np.array([[2000.0, 0.0, 0.0], [1500.0, 100.0, 0.0]])


def _sensor(**change: Any) -> Any:
    from targetacq.scenario.schema import Sensor

    fields = {"name": "s", "band": "lwir", "pitch": 17e-6, "focal_length": 0.035}
    fields.update(pixels=(640, 512), position=(0.0, 0.0, 10.0), azimuth=0.0, depression=0.1)
    fields.update(change)
    return Sensor(**{k: v for k, v in fields.items() if v is not None})


def _target(**change: Any) -> Any:
    from targetacq.scenario.schema import Target

    fields = {"name": "t", "dimensions": (7.0, 2.5, 3.0), "position": (0.0, 1000.0, 0.0)}
    fields.update(temperature=305.0)
    fields.update(change)
    return Target(**{k: v for k, v in fields.items() if v is not None})


def prob(*args: Any, **kwargs: Any) -> Callable[[Path], Any]:
    """``probability``, the clutter's fields given as keywords going into its record."""
    clutter = {k: kwargs.pop(k) for k in ("scr", "region", "hot_spot", "moving") if k in kwargs}
    return lambda tmp: _ta().probability(*args, clutter=clutter or None, **kwargs)


def ranges(*args: Any, probability: Any = 0.5, **kwargs: Any) -> Callable[[Path], Any]:
    return lambda tmp: _ta().dri_ranges(_ta().RangeCase(*args, **kwargs), probability)


def rcase(*args: Any, **kwargs: Any) -> Callable[[Path], Any]:
    def call(tmp: Path) -> Any:
        from targetacq.core.cases import RangeCase

        return RangeCase(*args, **kwargs)

    return call


SCENE = {"range": 1000.0, "critical_dimension": 2.3, "ifov": 2e-4, "band": "lwir"}
SCENE |= {"target_temperature": 305.0, "background_temperature": 295.0}
_SCENE_KEYWORDS = ("range", "netd", "netd_temperature", "quantisation_step")


def _scene_acquisition(values: dict[str, Any]) -> Any:
    """``scene_acquisition`` of :data:`SCENE` changed by ``values``, each in its place: the
    fields of a ``Scene`` in the scene, the function's own keywords, the rest in the case."""
    ta = _ta()
    scene_fields = {f.name for f in dataclasses.fields(ta.Scene)}
    given = {**SCENE, **values}
    own = {k: v for k, v in given.items() if k in _SCENE_KEYWORDS}
    scene = ta.Scene(**{k: v for k, v in given.items() if k in scene_fields})
    rest = {k: v for k, v in given.items() if k not in scene_fields and k not in own}
    return ta.scene_acquisition(own.pop("range"), ta.RangeCase(**rest), scene, **own)


def scene(**change: Any) -> Callable[[Path], Any]:
    return lambda tmp: _scene_acquisition(change)


NAN = float("nan")
INF = float("inf")
DATES = np.array(["2020-01-01"], dtype="datetime64[D]")

# -- probability ----------------------------------------------------------------------------
api("probability-cycles-complex", "wrong-type", prob(np.array([3 + 1j]), "detection"), ["cycles"])
api(
    "probability-cycles-complex-zero-imag",
    "wrong-type",
    prob(np.array([3 + 0j]), "detection"),
    ["cycles"],
)
api("probability-cycles-strings", "wrong-type", prob(np.array(["3"]), "detection"), ["cycles"])
api("probability-cycles-string", "wrong-type", prob("3", "detection"), ["cycles"])
api("probability-cycles-datetime", "wrong-type", prob(DATES, "detection"), ["cycles"])
api("probability-cycles-object", "wrong-type", prob(np.array([3.0, None]), "detection"), ["cycles"])
api(
    "probability-snr-complex", "wrong-type", prob(3.0, "detection", snr=np.array([1 + 2j])), ["snr"]
)
api("probability-scr-string", "wrong-type", prob(3.0, "detection", scr="high"), ["scr"])
api("probability-moving-yes", "wrong-type", prob(3.0, "detection", moving="yes"), ["moving"])
api("probability-hot-spot-no", "wrong-type", prob(3.0, "detection", hot_spot="no"), ["hot_spot"])
api("probability-cycles-negative", "out-of-domain", prob(-1.0, "detection"), ["cycles"])
api("probability-scr-negative", "out-of-domain", prob(3.0, "detection", scr=-1.0), ["scr"])
api(
    "probability-n50-negative",
    "out-of-domain",
    prob(3.0, "detection", criterion={"detection": -1.0}),
    ["detection"],
)
api("probability-task-unknown", "unknown", prob(3.0, "sighting"), ["sighting"])
api("probability-criterion-typo", "unknown", prob(3.0, "detection", criterion="jonson"), ["jonson"])
api(
    "probability-transform-unknown", "unknown", prob(3.0, "detection", transform="magic"), ["magic"]
)
api(
    "probability-noise-model-unknown",
    "unknown",
    prob(3.0, "detection", snr=10.0, noise_model="loud"),
    ["loud"],
)
api("probability-unknown-option", "unknown", prob(3.0, "detection", bogus=1), ["bogus"])
api("probability-region-unknown", "unknown", prob(3.0, "detection", region="extreme"), ["region"])
api(
    "probability-broadcast",
    "contradictory",
    prob(np.ones(2), "detection", snr=np.ones(3)),
    ["snr", "cycles"],
)
api(
    "probability-threshold-criterion",
    "contradictory",
    prob(3.0, "recognition", criterion="en62676-4"),
    ["criterion"],
)
api(
    "probability-schmieder-weathersby-without-clutter",
    "contradictory",
    prob(3.0, "detection", transform="schmieder-weathersby"),
    [("scr", "region")],
)
api(
    "probability-scr-and-region",
    "contradictory",
    prob(3.0, "detection", scr=5.0, region="low"),
    [("scr", "region")],
)

# -- dri_ranges and RangeCase ---------------------------------------------------------------
api(
    "dri-ranges-probability-1.5",
    "out-of-domain",
    ranges(2.3, 2e-4, probability=1.5),
    ["probability"],
)
api(
    "dri-ranges-probability-zero",
    "out-of-domain",
    ranges(2.3, 2e-4, probability=0.0),
    ["probability"],
)
api(
    "dri-ranges-critical-dimension-negative",
    "out-of-domain",
    ranges(-2.3, 2e-4),
    ["critical_dimension"],
)
api("dri-ranges-ifov-negative", "out-of-domain", ranges(2.3, -2e-4), ["ifov"])
api("dri-ranges-ifov-zero", "out-of-domain", ranges(2.3, 0.0), ["ifov"])
api(
    "dri-ranges-extinction-negative",
    "out-of-domain",
    ranges(2.3, 2e-4, extinction=-1e-3),
    ["extinction"],
)
api("dri-ranges-ifov-inf", "non-finite", ranges(2.3, INF), ["ifov"])
api("dri-ranges-critical-dimension-inf", "non-finite", ranges(INF, 2e-4), ["critical_dimension"])
api("dri-ranges-extinction-inf", "non-finite", ranges(2.3, 2e-4, extinction=INF), ["extinction"])
api("dri-ranges-ifov-complex", "wrong-type", ranges(2.3, np.array([1e-4 + 1j])), ["ifov"])
api(
    "dri-ranges-critical-dimension-string",
    "wrong-type",
    ranges("2.3 m", 2e-4),
    ["critical_dimension"],
)
api(
    "dri-ranges-critical-dimension-strings",
    "wrong-type",
    ranges(np.array(["2.3"]), 2e-4),
    ["critical_dimension"],
)
api("dri-ranges-ifov-datetime", "wrong-type", ranges(2.3, DATES), ["ifov"])
api(
    "dri-ranges-wavelength-without-aperture",
    "contradictory",
    ranges(2.3, 2e-4, wavelength=10e-6),
    ["aperture"],
)
api(
    "dri-ranges-schmieder-weathersby-without-clutter",
    "contradictory",
    ranges(2.3, 2e-4, transform="schmieder-weathersby"),
    [("scr", "region")],
)
api("dri-ranges-criterion-unknown", "unknown", ranges(2.3, 2e-4, criterion="jonson"), ["jonson"])
api(
    "range-case-scr-and-region",
    "contradictory",
    rcase(2.3, 2e-4, scr=5.0, region="low"),
    [("scr", "region")],
)
api("range-case-foliage-1.5", "out-of-domain", rcase(2.3, 2e-4, foliage=1.5), ["foliage"])
api("range-case-blur-negative", "out-of-domain", rcase(2.3, 2e-4, blur_sigma=-1.0), ["blur_sigma"])
api("range-case-cycle-zero", "out-of-domain", rcase(2.3, 2e-4, cycle=0.0), ["cycle"])
api("range-case-motion-unknown", "unknown", rcase(2.3, 2e-4, motion="teleport"), ["motion"])
api("range-case-semantics-unknown", "unknown", rcase(2.3, 2e-4, semantics="fuzzy"), ["semantics"])
api(
    "range-case-noise-negative",
    "out-of-domain",
    rcase(2.3, 2e-4, contrast=2.0, noise_equivalent_contrast=-1.0),
    ["noise_equivalent_contrast"],
)
api(
    "range-case-critical-dimension-datetime",
    "wrong-type",
    rcase(DATES, 2e-4),
    ["critical_dimension"],
)
api(
    "range-case-target-area-zero",
    "out-of-domain",
    rcase(2.3, 2e-4, target_area=0.0, contrast=2.0, noise_equivalent_contrast=0.05),
    ["target_area"],
)

# -- scene_acquisition ----------------------------------------------------------------------
api(
    "scene-target-temperature-minus-5K",
    "out-of-domain",
    scene(target_temperature=-5.0),
    ["target_temperature"],
)
api(
    "scene-target-temperature-1e300K",
    "out-of-domain",
    scene(target_temperature=1e300),
    ["target_temperature"],
)
api(
    "scene-background-temperature-inf",
    "non-finite",
    scene(background_temperature=INF),
    ["background_temperature"],
)
api("scene-emissivity-1.5", "out-of-domain", scene(target_emissivity=1.5), ["target_emissivity"])
api("scene-band-unknown", "unknown", scene(band="uv"), ["band"])
api("scene-range-negative", "out-of-domain", scene(range=-1000.0), ["range"])
api("scene-foliage-2", "out-of-domain", scene(foliage=2.0), ["foliage"])
api("scene-extinction-negative", "out-of-domain", scene(extinction=-1e-3), ["extinction"])
api("scene-clutter-std-negative", "out-of-domain", scene(clutter_std=-2.0), ["clutter_std"])
api(
    "scene-scr-and-clutter-std",
    "contradictory",
    scene(scr=5.0, clutter_std=2.0),
    [("scr", "clutter")],
)
api("scene-clutter-region-unknown", "unknown", scene(region="extreme"), ["region"])
api(
    "scene-temperature-complex",
    "wrong-type",
    scene(target_temperature=np.array([300 + 1j])),
    ["target_temperature"],
)
api("scene-netd-negative", "out-of-domain", scene(netd=-0.05), ["netd"])
api("scene-range-strings", "wrong-type", scene(range=np.array(["1 km"])), ["range"])

# -- ModelChain -----------------------------------------------------------------------------
api("chain-times-inf", "non-finite", lambda tmp: _chain().evaluate([0.0, INF]), ["time"])
api("chain-times-strings", "wrong-type", lambda tmp: _chain().evaluate(["0 s"]), ["time"])
api(
    "chain-times-complex", "wrong-type", lambda tmp: _chain().evaluate(np.array([1 + 1j])), ["time"]
)
api("chain-times-datetime", "wrong-type", lambda tmp: _chain().evaluate(DATES), ["time"])
api(
    "chain-step-unknown",
    "unknown",
    lambda tmp: _ta("run.model_chain").ModelChain(_chain().scenario, steps={"bogus": print}),
    ["bogus"],
)
api(
    "chain-of-a-path",
    "wrong-type",
    lambda tmp: _ta("run.model_chain").ModelChain(str(UAV)),
    ["scenario"],
)
api(
    "chain-chunks-zero",
    "out-of-domain",
    lambda tmp: next(_chain().evaluate_chunks(targets_per_chunk=0)),
    ["chunk"],
)


def _chain_of(**time: Any) -> Callable[[Path], Any]:
    def call(tmp: Path) -> Any:
        from targetacq.run.model_chain import ModelChain
        from targetacq.scenario.schema import parse_scenario

        document = _scenario_dict()
        document["time"].update(time)
        return ModelChain(parse_scenario(document)).evaluate()

    return call


api("chain-step-1ns", "size", _chain_of(step="1 ns"), ["step"])
api("chain-stop-1e15s", "size", _chain_of(stop="1e15 s", step="1 s"), [("step", "stop")])

# -- Simulation and the step API ------------------------------------------------------------
api("simulation-seed-negative", "out-of-domain", lambda tmp: _sim(seed=-1), ["seed"])
api("simulation-seed-2-to-128", "size", lambda tmp: _sim(seed=2**128), ["seed"])
api("simulation-seed-float", "wrong-type", lambda tmp: _sim(seed=1.5), ["seed"])
api("simulation-seed-string", "wrong-type", lambda tmp: _sim(seed="7"), ["seed"])
api(
    "simulation-sensor-type-unknown",
    "unknown",
    lambda tmp: _ta().Simulation(
        [{"name": "r", "type": "radar", "ifov": 1e-4}],
        [{"name": "t", "dimensions": [7.0, 2.5, 3.0]}],
    ),
    ["type"],
)
api(
    "simulation-step-time-nan",
    "non-finite",
    lambda tmp: _sim().step(NAN, 0.1, SENSOR_POSITIONS, TARGET_POSITIONS),
    ["time"],
)
api(
    "simulation-step-dt-negative",
    "out-of-domain",
    lambda tmp: _sim().step(0.0, -1.0, SENSOR_POSITIONS, TARGET_POSITIONS),
    ["dt"],
)


def _step_back(tmp: Path) -> Any:
    sim = _sim()
    sim.step(1.0, 0.1, SENSOR_POSITIONS, TARGET_POSITIONS)
    return sim.step(0.5, 0.1, SENSOR_POSITIONS, TARGET_POSITIONS)


api("simulation-step-back-in-time", "out-of-domain", _step_back, ["time"])
api(
    "simulation-positions-wrong-shape",
    "wrong-type",
    lambda tmp: _sim().probabilities(0.0, np.zeros((2, 3)), TARGET_POSITIONS),
    ["sensor_positions"],
)
api(
    "simulation-positions-complex",
    "wrong-type",
    lambda tmp: _sim().probabilities(0.0, SENSOR_POSITIONS + 1j, TARGET_POSITIONS),
    ["sensor_positions"],
)
api(
    "simulation-positions-strings",
    "wrong-type",
    lambda tmp: _sim().probabilities(0.0, SENSOR_POSITIONS, np.array([["1 km", "0", "0"]] * 2)),
    ["target_positions"],
)
api(
    "simulation-time-inf",
    "non-finite",
    lambda tmp: _sim().probabilities(INF, SENSOR_POSITIONS, TARGET_POSITIONS),
    ["time"],
)
api("simulation-reset-seed-negative", "out-of-domain", lambda tmp: _sim().reset(seed=-5), ["seed"])
api(
    "simulation-from-missing-file",
    "file",
    lambda tmp: _ta().Simulation.from_scenario(tmp / "missing.toml"),
    ["missing.toml"],
)

# -- load_scenario, parse_scenario and the records ------------------------------------------


def _load(path: Callable[[Path], Path | str]) -> Callable[[Path], Any]:
    def call(tmp: Path) -> Any:
        from targetacq.scenario.schema import load_scenario

        return load_scenario(path(tmp))

    return call


def _parse(*patches: Callable[[dict, Path], None], data: Any = None) -> Callable[[Path], Any]:
    def call(tmp: Path) -> Any:
        from targetacq.scenario.schema import parse_scenario

        document = _scenario_dict() if data is None else data
        for patch in patches:
            patch(document, tmp)
        return parse_scenario(document)

    return call


def _bom_free_nested(tmp: Path) -> Path:
    (tmp / "deep.toml").write_text(nested_toml(5000))
    return tmp / "deep.toml"


api("load-missing", "file", _load(lambda t: t / "missing.toml"), ["missing.toml"])
api("load-directory", "file", _load(lambda t: t), [("director", "folder")])
api("load-dev-null", "file", _load(lambda t: "/dev/null"), [("device", "not a")])
api("load-deeply-nested", "file", _load(_bom_free_nested), ["deep.toml", ("nest", "deep")])
api("parse-empty", "obvious", _parse(data={}), ["sensors"])
api("parse-not-a-table", "wrong-type", _parse(data=[1, 2]), ["scenario"])
api("parse-pitch-1e400", "non-finite", _parse(put("sensors[0].pitch", "1e400 um")), ["pitch"])
api("parse-moving-yes", "wrong-type", _parse(put("targets[2].moving", "yes")), ["moving"])
api(
    "parse-depression-720",
    "out-of-domain",
    _parse(put("sensors[0].depression", "720 deg")),
    ["depression"],
)
api("record-sensor-pitch-inf", "non-finite", lambda tmp: _sensor(pitch=INF), ["pitch"])
api("record-sensor-pitch-complex", "wrong-type", lambda tmp: _sensor(pitch=1e-5 + 1j), ["pitch"])
api(
    "record-sensor-depression-720",
    "out-of-domain",
    lambda tmp: _sensor(depression=math.radians(720)),
    ["depression"],
)
api(
    "record-sensor-azimuth-10-turns",
    "out-of-domain",
    lambda tmp: _sensor(azimuth=20 * math.pi),
    ["azimuth"],
)
api(
    "record-sensor-look-at-position",
    "contradictory",
    lambda tmp: _sensor(azimuth=None, depression=None, look_at=(0.0, 0.0, 10.0)),
    ["look_at"],
)
api(
    "record-sensor-pixels-fraction",
    "wrong-type",
    lambda tmp: _sensor(pixels=(640.5, 512)),
    ["pixels"],
)
api(
    "record-target-temperature-minus-5",
    "out-of-domain",
    lambda tmp: _target(temperature=-5.0),
    ["temperature"],
)
api(
    "record-target-temperature-1e300",
    "out-of-domain",
    lambda tmp: _target(temperature=1e300),
    ["temperature"],
)
api("record-target-moving-yes", "wrong-type", lambda tmp: _target(moving="yes"), ["moving"])
api(
    "record-target-emissivity-and-material",
    "contradictory",
    lambda tmp: _target(emissivity=0.9, material="olive-paint"),
    [("emissivity", "material")],
)
api("record-target-heading-1000", "out-of-domain", lambda tmp: _target(heading=1000.0), ["heading"])
api(
    "record-target-dimensions-datetime",
    "wrong-type",
    lambda tmp: _target(dimensions=(datetime.datetime(2020, 1, 1), 2.5, 3.0)),
    ["dimensions"],
)
api(
    "record-background-temperature-negative",
    "out-of-domain",
    lambda tmp: _ta("scenario.schema").Background(temperature=-5.0),
    ["temperature"],
)
api(
    "record-scenario-no-sensors",
    "obvious",
    lambda tmp: _ta("scenario.schema").Scenario(sensors=[], targets=[_target()]),
    ["sensors"],
)


# -- issue 28 ---------------------------------------------------------------------------


def _radar_gain(tmp: Path) -> Any:
    from targetacq.scenario.schema import parse_scenario

    document = read_base(RADAR)
    document["sensors"][0]["radar"]["gain"] = "4000 dB"  # OverflowError before
    return parse_scenario(document)


def _sweep_of(**options: Any) -> Callable[[Path], Any]:
    def call(tmp: Path) -> Any:
        from targetacq.run.studies import sweep

        with watchdog(10):  # refused before any work, or this fails (not hours later)
            return sweep({"example": True, **options})

    return call


api("parse-radar-gain-4000dB", "non-finite", _radar_gain, ["radar.gain", "3000 dB"])
api(
    "studies-sweep-1001x1000-points",
    "size",
    _sweep_of(
        focal_length=[f"{v}mm" for v in range(10, 1011)], scr=[str(v) for v in range(1, 1001)]
    ),
    ["1,000,000 points"],
)
api(
    "image-clutter-1x1-image",
    "out-of-domain",
    lambda tmp: _ta().image_clutter(np.ones((1, 1)), [(0, 0, 1, 1)]),
    ["box 0", "background"],
)
api(
    "image-clutter-box-whole-image",
    "out-of-domain",
    lambda tmp: _ta().image_clutter(np.ones((30, 40)), [(0, 0, 40, 30)]),
    ["box 0", "background"],
)


@pytest.mark.parametrize("case", [c for c in CASES if c.kind == "api"], ids=lambda c: c.id)
def test_python(case: Case, tmp_path: Path) -> None:
    with pytest.raises((ValueError, TypeError)) as raised:
        case.what(tmp_path)
    error = raised.value
    message = str(error)
    if not case.id.startswith("record-"):
        # Records built directly are pydantic models: their ValidationError is a ValueError
        # naming the field (over several lines). Everything else says it in one line.
        assert type(error).__module__.split(".")[0] != "pydantic_core", (
            f"a pydantic ValidationError leaks: {message!r}"
        )
        assert message and "\n" not in message.strip(), f"not one line: {message!r}"
    missing = names_found(message, case.names)
    assert not missing, f"{type(error).__name__}({message!r}) does not name {', '.join(missing)}"


# ===========================================================================================
# Process-level behaviour: stdout to /dev/full, file size limits, SIGTERM, umask
# ===========================================================================================

TARGETACQ = [sys.executable, "-c", "from targetacq.cli import main; main()"]


def _run(argv: list[str], timeout: float = 120, **kwargs: Any) -> subprocess.CompletedProcess:
    return subprocess.run(
        [*TARGETACQ, *argv], capture_output=True, text=True, timeout=timeout, check=False, **kwargs
    )


def _one_line(done: Any, names: Names, argv: list[str]) -> None:
    check_error(argv, (done.returncode, done.stdout, done.stderr, []), names)


def _to_dev_full(argv: list[str]) -> Callable[[Path], None]:
    def check(tmp: Path) -> None:
        with open("/dev/full", "w") as full:
            done = subprocess.run(
                [*TARGETACQ, *argv],
                stdout=full,
                stderr=subprocess.PIPE,
                text=True,
                timeout=120,
                check=False,
            )
        _one_line(done, [("stdout", "standard output")], argv)

    return check


def _file_size_limit(argv: list[str], name: str) -> Callable[[Path], None]:
    def check(tmp: Path) -> None:
        full = [a.replace("{tmp}", str(tmp)) for a in argv]
        done = subprocess.run(
            file_size_limited([*TARGETACQ, *full], 2000),
            capture_output=True,
            text=True,
            timeout=120,
            check=False,
        )
        _one_line(done, [name], full)
        assert sorted(p.name for p in tmp.iterdir()) == [], "a partial or temporary file is left"

    return check


def _sigterm(tmp: Path) -> None:
    """SIGTERM during `evaluate --out big.csv` leaves no temporary file and no partial file."""
    import time

    document = read_base(UAV)
    document["time"] = {"start": "0 s", "stop": "6000 s", "step": "1 s"}
    scenario_file = tmp / "big.toml"
    scenario_file.write_text(toml_dumps(document))
    folder = tmp / "out"
    folder.mkdir()
    out = folder / "big.csv"
    child = subprocess.Popen(
        [*TARGETACQ, "evaluate", str(scenario_file), "--out", str(out)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    deadline = time.monotonic() + 30
    try:
        # Wait for the temporary file (or 30 s, for a writer that shows none), then stop it.
        while child.poll() is None and time.monotonic() < deadline and not any(folder.iterdir()):
            time.sleep(0.002)
        child.send_signal(signal.SIGTERM)
        child.wait(timeout=30)
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
    left = sorted(p.name for p in folder.iterdir())
    assert left in ([], ["big.csv"]), f"SIGTERM left {left}"
    if left:  # finished before the signal: the whole file
        assert out.read_text().count("\n") > 1000


process("dri-stdout-dev-full", "output", _to_dev_full(["dri", "--example"]))
process("evaluate-stdout-dev-full", "output", _to_dev_full(["evaluate"]))
process(
    "evaluate-out-file-size-limit",
    "output",
    _file_size_limit(["evaluate", "--out", "{tmp}/x.csv"], "x.csv"),
)
process("evaluate-sigterm-no-temporary-file", "output", _sigterm)


def _without(packages: Sequence[str], argv: list[str], names: Names) -> Callable[[Path], None]:
    """``targetacq argv`` where importing each of ``packages`` fails (a base install)."""

    def check(tmp: Path) -> None:
        hide = "; ".join(f"sys.modules[{p!r}] = None" for p in packages)
        code = f"import sys; {hide}; from targetacq.cli import main; main()"
        full = [a.replace("{tmp}", str(tmp)) for a in argv]
        done = subprocess.run(
            [sys.executable, "-c", code, *full],
            capture_output=True,
            text=True,
            timeout=120,
            check=False,
        )
        _one_line(done, names, full)
        assert sorted(p.name for p in tmp.iterdir()) == [], "a file is left"

    return check


SWEEP_ARGS = ["sweep", "--example", "--focal-length", "35mm,50mm"]
# A write that fails part-way (netCDF4 says "NetCDF: HDF error", as on a full disk): a
# RuntimeError traceback with exit status 1 before.
process(
    "evaluate-out-nc-file-size-limit",
    "output",
    _file_size_limit(["evaluate", "--out", "{tmp}/x.nc"], "x.nc"),
)
process(
    "sweep-out-nc-file-size-limit",
    "output",
    _file_size_limit([*SWEEP_ARGS, "--out", "{tmp}/x.nc"], "x.nc"),
)
# .nc and .zarr without the [sweep] extra: a ModuleNotFoundError traceback after the work.
for _command, _argv in (("evaluate", ["evaluate"]), ("sweep", SWEEP_ARGS)):
    for _suffix, _package in (("nc", "netCDF4"), ("zarr", "zarr")):
        process(
            f"{_command}-out-{_suffix}-without-the-sweep-extra",
            "output",
            _without(
                [_package], [*_argv, "--out", f"{{tmp}}/x.{_suffix}"], [f"x.{_suffix}", "[sweep]"]
            ),
        )


@pytest.mark.parametrize("case", [c for c in CASES if c.kind == "process"], ids=lambda c: c.id)
def test_process(case: Case, tmp_path: Path) -> None:
    case.what(tmp_path)


# ===========================================================================================
# Accepted: inputs that must work, and NaN in → NaN out
# ===========================================================================================

BOM = "\ufeff"


def _ok(capsys: Any, argv: list[str]) -> str:
    code, out, err, caught = run_cli(capsys, argv)
    assert code == 0, f"targetacq {' '.join(argv)}: exit {code}: {err!r}"
    assert not caught, f"warnings: {caught}"
    return out


def _bom_toml(tmp: Path, capsys: Any) -> None:
    path = tmp / "bom.toml"
    path.write_text(BOM + UAV.read_text(encoding="utf-8"), encoding="utf-8")
    _ok(capsys, ["validate", str(path)])


def _bom_boxes(tmp: Path, capsys: Any) -> None:
    path = tmp / "boxes.csv"
    path.write_text(BOM + BOXES_CSV, encoding="utf-8")
    out = _ok(capsys, ["clutter", str(CAMERA), "--boxes", str(path), "--format", "json"])
    assert len(json.loads(out)["targets"]) == 2


def _bom_terrain(tmp: Path, capsys: Any) -> None:
    document = read_base(GOLDEN / "terrain.toml")
    grid = tmp / "map.csv"
    grid.write_text(BOM + (GOLDEN / "map.csv").read_text(), encoding="utf-8")
    document["background"]["terrain"]["map"] = str(grid)
    path = tmp / "terrain.toml"
    path.write_text(toml_dumps(document))
    _ok(capsys, ["validate", str(path)])
    _ok(capsys, ["evaluate", str(path)])


def _bom_mrtd(tmp: Path, capsys: Any) -> None:
    path = tmp / "mrtd.csv"
    path.write_text(BOM + MRTD_CSV, encoding="utf-8")
    _ok(capsys, [D, *SENSOR, "--band", "lwir", "--delta-t", "2K", "--mrtd", str(path)])


def _symlink_out(tmp: Path, capsys: Any) -> None:
    real = tmp / "real.csv"
    real.write_text("old\n")
    link = tmp / "link.csv"
    link.symlink_to(real)
    _ok(capsys, ["evaluate", "--out", str(link)])
    assert link.is_symlink(), "the symlink at --out was replaced"
    assert real.read_text().startswith("sensor") or real.read_text().count("\n") > 3
    assert sorted(p.name for p in tmp.iterdir()) == ["link.csv", "real.csv"]


@contextlib.contextmanager
def _umask(mask: int) -> Any:
    previous = os.umask(mask)
    try:
        yield
    finally:
        os.umask(previous)


def _mode(argv: list[str], name: str, mask: int, existing: int | None = None) -> Any:
    def check(tmp: Path, capsys: Any) -> None:
        out = tmp / name
        if existing is not None:
            out.write_text("old\n")
            out.chmod(existing)
        with _umask(mask):
            _ok(capsys, [a.replace("{out}", str(out)) for a in argv])
        mode = stat.S_IMODE(out.stat().st_mode)
        expected = existing if existing is not None else 0o666 & ~mask
        assert mode == expected, f"{name}: mode {mode:o}, expected {expected:o}"

    return check


def _nan_at(values: Any, where: Any) -> None:
    values = np.asarray(values, dtype=float)
    nan = np.isnan(values)
    assert np.array_equal(nan, np.broadcast_to(where, values.shape)), (
        f"NaN expected exactly at {np.argwhere(where).tolist()}; got {values.tolist()}"
    )


def _nan_probability(kwarg: str) -> Callable[[Path, Any], None]:
    def check(tmp: Path, capsys: Any) -> None:
        value = {"snr": np.array([10.0, NAN]), "scr": np.array([5.0, NAN])}[kwarg]
        given = {"clutter": {"scr": value}} if kwarg == "scr" else {kwarg: value}
        p = _ta().probability(np.array([3.0, 3.0]), "detection", **given)
        _nan_at(p, [False, True])

    return check


def _nan_cycles(tmp: Path, capsys: Any) -> None:
    for transform in ("ttpf", "c2nveo"):
        p = _ta().probability(np.array([3.0, NAN, 1.0]), "recognition", transform=transform)
        _nan_at(p, [False, True, False])


def _nan_scene(name: str) -> Callable[[Path, Any], None]:
    def check(tmp: Path, capsys: Any) -> None:
        base = {"extinction": 1e-4, "foliage": 1.0}[name]
        values = {name: np.array([base, NAN, base])}
        got = _scene_acquisition(values)
        for task in ("detection", "recognition", "identification"):
            _nan_at(getattr(got, task), [False, True, False])

    return check


def _nan_ranges(tmp: Path, capsys: Any) -> None:
    got = _ta().dri_ranges(_ta().RangeCase(np.array([2.3, NAN]), 2e-4, extinction=4e-4))
    for task in ("detection", "recognition", "identification"):
        _nan_at(got[task], [False, True])


def _nan_chain_time(tmp: Path, capsys: Any) -> None:
    ds = _chain().evaluate([0.0, NAN, 60.0]).dataset
    for task in ("detection", "recognition", "identification"):
        _nan_at(ds[task].values, np.array([False, True, False]))
        _nan_at(ds[f"fused_{task}"].values, np.array([False, True, False]))


def _nan_simulation_row(tmp: Path, capsys: Any) -> None:
    positions = TARGET_POSITIONS.copy()
    positions[1] = NAN
    p = _sim().probabilities(0.0, SENSOR_POSITIONS, positions)
    _nan_at(p.detection, np.array([[False, True]]))
    _nan_at(p.fused_detection, np.array([False, True]))


def _nan_step(tmp: Path, capsys: Any) -> None:
    positions = TARGET_POSITIONS.copy()
    positions[1] = NAN
    out = _sim().step(0.0, 0.1, SENSOR_POSITIONS, positions)
    _nan_at(out.detection, np.array([[False, True]]))


def _masked(tmp: Path, capsys: Any) -> None:
    cycles = np.ma.masked_array([3.0, 3.0], mask=[False, True])
    try:
        p = _ta().probability(cycles, "detection")
    except (ValueError, TypeError) as error:  # refused clearly
        refused = str(error)
    else:
        assert np.ma.isMaskedArray(p), f"the mask is lost: {p!r}"
        assert np.array_equal(np.ma.getmaskarray(p), [False, True])
        return
    assert "\n" not in refused and "cycles" in refused, refused


def _evaluate_json_nan(tmp: Path, capsys: Any) -> None:
    """A NaN in the results is null in --out x.json, and the file is strict JSON."""
    out = tmp / "x.json"
    _ok(capsys, ["evaluate", "--out", str(out)])
    text = out.read_text()
    json.loads(text, parse_constant=lambda c: pytest.fail(f"{c} in {out.name}: not JSON"))


def _evaluate_json_inf(tmp: Path, capsys: Any) -> None:
    """+inf in --out x.json (the SCR where no clutter is measured) is "inf", not null (NaN)."""
    out = tmp / "x.json"
    _ok(capsys, ["evaluate", str(FUSED), "--out", str(out)])
    document = json.loads(out.read_text(), parse_constant=lambda c: pytest.fail(f"{c}: not JSON"))
    scr = [row["scr"] for row in document["rows"]]  # {"meta": provenance, "rows": [...]}
    assert scr and all(v == "inf" for v in scr), f"+inf written as {sorted(set(map(str, scr)))}"


def _dri_json_strict(tmp: Path, capsys: Any) -> None:
    """`dri --format json` is strict JSON even where a range is unbounded."""
    out = _ok(capsys, [D, *SENSOR, "--format", "json", "--probability", "0.001,0.5"])
    json.loads(out, parse_constant=lambda c: pytest.fail(f"{c} in dri's JSON: not JSON"))


accepted("bom-in-scenario-toml", "accepted", _bom_toml)
accepted("bom-in-boxes-csv", "accepted", _bom_boxes)
accepted("bom-in-terrain-map-csv", "accepted", _bom_terrain)
accepted("bom-in-mrtd-csv", "accepted", _bom_mrtd)
accepted("symlink-at-out-written-through", "accepted", _symlink_out)
accepted(
    "umask-022-evaluate-csv-0644", "accepted", _mode(["evaluate", "--out", "{out}"], "x.csv", 0o022)
)
accepted(
    "umask-027-evaluate-json-0640",
    "accepted",
    _mode(["evaluate", "--out", "{out}"], "x.json", 0o027),
)
accepted(
    "umask-022-plot-png-0644",
    "accepted",
    _mode(["plot", "transforms", "--out", "{out}"], "x.png", 0o022),
)
accepted(
    "umask-022-report-html-0644",
    "accepted",
    _mode(["report", "--out", "{out}", *SENSOR], "x.html", 0o022),
)
accepted(
    "existing-0644-file-keeps-its-mode",
    "accepted",
    _mode(["evaluate", "--out", "{out}"], "x.csv", 0o077, existing=0o644),
)
accepted("evaluate-json-strict", "accepted", _evaluate_json_nan)
accepted("dri-json-strict", "accepted", _dri_json_strict)
accepted("evaluate-json-inf-is-not-null", "accepted", _evaluate_json_inf)
accepted("nan-snr-gives-nan", "nan-in-nan-out", _nan_probability("snr"))
accepted("nan-scr-gives-nan", "nan-in-nan-out", _nan_probability("scr"))
accepted("nan-cycles-gives-nan", "nan-in-nan-out", _nan_cycles)
accepted("nan-extinction-gives-nan", "nan-in-nan-out", _nan_scene("extinction"))
accepted("nan-foliage-gives-nan", "nan-in-nan-out", _nan_scene("foliage"))
accepted("nan-critical-dimension-range-nan", "nan-in-nan-out", _nan_ranges)
accepted("nan-time-in-evaluate", "nan-in-nan-out", _nan_chain_time)
accepted("nan-target-row-in-probabilities", "nan-in-nan-out", _nan_simulation_row)
accepted("nan-target-row-in-step", "nan-in-nan-out", _nan_step)
accepted("masked-array-keeps-mask", "nan-in-nan-out", _masked)


def _nan_target_temperature(tmp: Path, capsys: Any) -> None:
    """No noise, no clutter: the contrast entered no factor (P = 0.99999 for a NaN before)."""
    got = _scene_acquisition({"target_temperature": np.array([305.0, NAN])})
    for task in ("detection", "recognition", "identification"):
        _nan_at(getattr(got, task), [False, True])


def _laser_nep_zero(tmp: Path, capsys: Any) -> None:
    """nep = 0 W is documented (no receiver noise): accepted, and said in one warning line."""
    document = read_base(LASER)
    document["sensors"][0]["laser"]["nep"] = "0 W"
    path = tmp / "ideal.toml"
    path.write_text(toml_dumps(document), encoding="utf-8")
    code, _, err, caught = run_cli(capsys, ["validate", str(path)])
    assert code == 0 and not caught, err
    assert err.startswith("targetacq: warning: sensors[0].laser.nep = 0 W: a receiver without")
    assert err.count("\n") == 1, err


accepted("nan-target-temperature-without-noise", "nan-in-nan-out", _nan_target_temperature)
accepted("laser-nep-0-W-said", "accepted", _laser_nep_zero)


@pytest.mark.parametrize("case", [c for c in CASES if c.kind == "accepted"], ids=lambda c: c.id)
def test_accepted(case: Case, tmp_path: Path, capsys: Any) -> None:
    case.what(tmp_path, capsys)


# -- the web API: the scenario's refusals are 4xx, never 500 ---------------------------------


def test_web_evaluate_refuses_decibels_beyond_the_range_with_422() -> None:
    """``radar.gain = "4000 dB"`` raised OverflowError inside validation: an HTTP 500."""
    pytest.importorskip("fastapi")
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="Using `httpx` with `starlette.testclient`")
        from fastapi.testclient import TestClient
    from targetacq.web.api import create_app

    text = RADAR.read_text(encoding="utf-8").replace('gain = "32 dB"', 'gain = "4000 dB"')
    assert '"4000 dB"' in text
    with TestClient(
        create_app(max_body_bytes=200_000, max_elements=1_000), base_url="http://127.0.0.1"
    ) as client:
        answer = client.post("/evaluate", json={"scenario": text})
    assert answer.status_code == 422, answer.text
    items = answer.json()["detail"]
    assert any("gain" in str(i["loc"]) and "3000 dB" in i["msg"] for i in items), items


# -- the table itself -----------------------------------------------------------------------

_ids = Counter(c.id for c in CASES)
assert not [i for i, n in _ids.items() if n > 1], [i for i, n in _ids.items() if n > 1]


def test_catalogue_size() -> None:
    assert len(CASES) >= 150


def counts_by_class() -> dict[str, int]:
    return dict(sorted(Counter(c.cls for c in CASES).items()))


if __name__ == "__main__":
    for name, count in counts_by_class().items():
        print(f"{name:<16}{count:>5}")
    print(f"{'total':<16}{len(CASES):>5}")
