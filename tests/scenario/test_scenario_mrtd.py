"""A thermal sensor's MRTD curve in a scenario: validated, compiled into the core, evaluated,
simulated, and its DRI ranges (issue 24).

Expected values come from the range-case chain (:class:`targetacq.core.cases.RangeCase` with an
MRTD curve and :func:`targetacq.core.cases.case_acquisition`, the CLI's tested ``--mrtd``
path) with the target's ΔT computed here from the band exitances, and from the property that a
DRI range is where the core gives the asked probability.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

from targetacq import Simulation
from targetacq.core.cases import RangeCase, case_acquisition
from targetacq.core.compile import check_runnable
from targetacq.core.engines import bind
from targetacq.core.evaluation import evaluate
from targetacq.core.pair_ranges import pair_performance
from targetacq.physics import radiometry
from targetacq.physics.mrtd import MrtdCurve
from targetacq.run.model_chain import ModelChain
from targetacq.run.search import simulate
from targetacq.scenario.schema import ScenarioError, load_scenario

TASKS = ("detection", "recognition", "identification")
LWIR = (8e-6, 12e-6)  # the "lwir" band [m]
T_TARGET, T_BACKGROUND = 293.1, 293.0  # [K], both emissivity 1
GAMMA = 0.4e-3  # extinction [Np/m]
SENSOR_Z = 2.0  # sensor and target at one height: the critical dimension is the height, 3 m

SENSOR = """
[[sensors]]
name = "{name}"
type = "{type}"
band = "lwir"
pixels = [640, 512]
pitch = "17 um"
focal_length = "50 mm"
position = ["0 m", "0 m", "2 m"]
look_at = ["3 km", "0 m", "2 m"]
{extra}
"""

REST = f"""
[[targets]]
name = "truck"
dimensions = ["7 m", "2.5 m", "3 m"]
temperature = "{T_TARGET} K"
emissivity = 1.0
position = ["3 km", "0 m", "2 m"]

[background]
temperature = "{T_BACKGROUND} K"
emissivity = 1.0

[atmosphere]
extinction = "{GAMMA * 1e3} /km"
"""


def _curve_file(folder: Path) -> Path:
    path = folder / "curves" / "bench.csv"
    path.parent.mkdir()
    source = resources.files("targetacq").joinpath("data").joinpath("example_mrtd.csv")
    with resources.as_file(source) as file:
        shutil.copy(file, path)
    return path


def _write(folder: Path, sensors: list[tuple[str, str, str]]) -> Path:
    text = "".join(SENSOR.format(name=n, type=t, extra=e) for n, t, e in sensors) + REST
    path = folder / "scenario.toml"
    path.write_text(text)
    return path


@pytest.fixture
def scenario_path(tmp_path: Path) -> Path:
    _curve_file(tmp_path)
    return _write(
        tmp_path,
        [
            ("ir", "thermal", 'mrtd = "curves/bench.csv"'),
            ("ir-netd", "thermal", 'mrtd = "curves/bench.csv"\nnetd = "50 mK"'),
            ("geometric", "thermal", ""),
        ],
    )


def _delta_t() -> float:
    """The blackbody ΔT at 300 K (the default netd_temperature) of the band-exitance contrast."""
    contrast = radiometry.grey_body_exitance(1.0, T_TARGET, LWIR) - radiometry.grey_body_exitance(
        1.0, T_BACKGROUND, LWIR
    )
    return float(contrast / radiometry.band_exitance_derivative(300.0, LWIR))


def _positions(ranges: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Three sensors at the origin and the target at ``ranges`` east, one batch column each."""
    n = ranges.size
    sensors = np.broadcast_to(np.array([0.0, 0.0, SENSOR_Z]), (3, n, 3)).copy()
    targets = np.stack([ranges, np.zeros(n), np.full(n, SENSOR_Z)], axis=-1)[None]
    return sensors, targets


def test_scenario_with_mrtd_validates_and_compiles(scenario_path: Path) -> None:
    scenario = load_scenario(scenario_path)
    assert Path(scenario.sensors[0].mrtd).is_absolute()  # taken from the file's folder
    assert check_runnable(scenario) == []
    limited = ModelChain(scenario).compiled.scene.sensors.mrtd
    assert limited is not None
    assert limited.rows == (0, 1)
    assert limited.curves[0] == MrtdCurve.example()


@pytest.mark.parametrize("r", [300.0, 800.0, 3000.0, 6000.0])
def test_evaluate_equals_the_range_case_chain(scenario_path: Path, r: float) -> None:
    chain = ModelChain(load_scenario(scenario_path))
    found, p = evaluate(chain.compiled.scene, *_positions(np.array([r])))
    assert bool(np.all(found.in_view))
    curve = MrtdCurve.example()
    base = {"extinction": GAMMA, "contrast": _delta_t(), "mrtd": curve}
    ifov = 17e-6 / 50e-3
    cases = [
        RangeCase(3.0, ifov, **base),
        # The sensor's noise sees the outline's area, 7 m × 3 m (the long side across the line
        # of sight).
        RangeCase(3.0, ifov, noise_equivalent_contrast=0.05, target_area=21.0, **base),
        RangeCase(3.0, ifov, cycle=2.0 * ifov, extinction=GAMMA),
    ]
    for row, case in enumerate(cases):
        expected = case_acquisition(case, r)
        np.testing.assert_allclose(found.cycles[row, 0, 0], expected.cycles, rtol=1e-9)
        for task in TASKS:
            np.testing.assert_allclose(
                getattr(p, task)[row, 0, 0], getattr(expected, task), rtol=1e-9, atol=1e-300
            )
    # Near, τΔT is above the curve's last MRTD: the cut-off's cycles; far, the ΔT limits.
    at_cutoff = curve.cutoff * 3.0 / r
    if np.exp(-GAMMA * r) * _delta_t() >= curve.mrtd[-1]:
        assert found.cycles[0, 0, 0] == pytest.approx(at_cutoff, rel=1e-12)
    else:
        assert 0.0 < found.cycles[0, 0, 0] < at_cutoff * (1.0 - 1e-6)
    assert found.cycles[0, 0, 0] < found.cycles[2, 0, 0]


def test_range_cases_carry_the_curve(scenario_path: Path) -> None:
    cases = ModelChain(load_scenario(scenario_path)).range_cases()
    assert cases["ir → truck"].resolution_model == "mrtd"
    assert cases["ir → truck"].contrast == pytest.approx(_delta_t(), rel=1e-9)
    assert cases["ir-netd → truck"].noise_equivalent_contrast == pytest.approx(0.05, rel=1e-12)
    assert cases["geometric → truck"].resolution_model == "johnson"


def test_jax_engine_gives_the_same_numbers(scenario_path: Path) -> None:
    pytest.importorskip("jax")
    scene = ModelChain(load_scenario(scenario_path)).compiled.scene
    sensors, targets = _positions(np.array([300.0, 800.0, 3000.0, 6000.0]))
    numpy_engine, jax_engine = bind(scene, "numpy"), bind(scene, "jax")
    want = numpy_engine.probabilities(numpy_engine.factors(sensors, targets))
    got_factors = jax_engine.factors(sensors, targets)
    got = jax_engine.probabilities(got_factors)
    for task in TASKS:
        np.testing.assert_allclose(
            np.asarray(getattr(got, task)), getattr(want, task), rtol=1e-10, atol=1e-13
        )
    # One time through the step API's core, jitted too.
    in_view, tasks, _ = jax_engine.step(sensors[:, 1], targets[:, 1])
    assert bool(np.all(in_view))
    np.testing.assert_allclose(
        np.asarray(tasks)[:, :, 0], [getattr(want, t)[:, 0, 1] for t in TASKS], rtol=1e-10
    )


def test_numba_refuses_and_auto_falls_back(scenario_path: Path) -> None:
    pytest.importorskip("numba")
    scene = ModelChain(load_scenario(scenario_path)).compiled.scene
    with pytest.raises(ValueError, match="MRTD-limited sensors"):
        bind(scene, "numba")
    assert bind(scene, "auto").engine == "numpy"


def test_step_and_simulate_use_the_curve(scenario_path: Path) -> None:
    scenario = load_scenario(scenario_path)
    chain = ModelChain(scenario, engine="auto")
    sensors, targets = _positions(np.array([6000.0]))
    _, want = evaluate(chain.compiled.scene, sensors, targets)
    bound = bind(chain.compiled.scene, "auto")
    in_view, tasks, _ = bound.step(sensors[:, 0], targets[:, 0])
    assert bool(np.all(in_view))
    for k, task in enumerate(TASKS):
        np.testing.assert_allclose(tasks[k][:, 0], getattr(want, task)[:, 0, 0], rtol=1e-12)
    result = simulate(chain, duration=10.0, step=1.0, runs=3, seed=1)
    assert result is not None


def test_missing_curve_file_is_located(tmp_path: Path) -> None:
    path = _write(tmp_path, [("ir", "thermal", 'mrtd = "nowhere.csv"')])
    scenario = load_scenario(path)
    problems = check_runnable(scenario)
    assert len(problems) == 1
    assert problems[0].startswith("sensors[0].mrtd: ")
    assert "nowhere.csv" in problems[0]
    with pytest.raises(ValueError, match=r"sensors\[0\]\.mrtd: "):
        ModelChain(scenario)


def test_bad_curve_file_is_located(tmp_path: Path) -> None:
    (tmp_path / "bad.csv").write_text("frequency,mrtd\n0.5,0.05\n0.4,0.1\n")
    scenario = load_scenario(_write(tmp_path, [("ir", "thermal", 'mrtd = "bad.csv"')]))
    (problem,) = check_runnable(scenario)
    assert problem.startswith("sensors[0].mrtd: ")
    assert "line 3" in problem and "ascending" in problem


def test_mrtd_of_a_tv_sensor_is_refused(tmp_path: Path) -> None:
    _curve_file(tmp_path)
    path = tmp_path / "tv.toml"
    path.write_text(
        SENSOR.format(name="tv", type="tv", extra='mrtd = "curves/bench.csv"').replace(
            'band = "lwir"\n', ""
        )
        + """
[[targets]]
name = "truck"
dimensions = ["7 m", "2.5 m", "3 m"]
reflectance = 0.075
position = ["3 km", "0 m", "2 m"]

[background]
reflectance = 0.1
irradiance = "500 W/m^2"
"""
    )
    with pytest.raises(ScenarioError, match=r"sensors\[0\]\.mrtd: an MRTD curve is a thermal"):
        load_scenario(path)


@pytest.mark.parametrize("row", [0, 2])  # MRTD-limited, geometric
def test_dri_range_gives_the_asked_probability(scenario_path: Path, row: int) -> None:
    chain = ModelChain(load_scenario(scenario_path))
    probabilities = (0.5, 0.9)
    dri = pair_performance(chain, [row], probabilities).dri
    scene = chain.compiled.scene
    checked = 0
    for entry in dri.itertuples():
        if not entry.reached:
            continue
        # The target moved to that range along the line of sight, the sensor pointed at it.
        found, p = evaluate(scene, *_positions(np.array([entry.range_m])))
        assert bool(found.in_view[row, 0, 0])
        got = float(getattr(p, entry.task)[row, 0, 0])
        assert abs(got - entry.probability) < 1e-6, (entry.task, entry.probability, got)
        checked += 1
    assert checked >= 4


def test_dri_of_the_scenario_on_the_command_line(scenario_path: Path) -> None:
    """``targetacq dri SCENARIO``: every pair's range, evaluated by the core with the target
    moved there in view, gives the asked probability (and the MRTD pair's ranges are not the
    geometric ones)."""
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "targetacq",
            "dri",
            str(scenario_path),
            "--probability",
            "0.5,0.9",
            "--format",
            "json",
        ],
        capture_output=True,
        text=True,
        check=True,
    )
    rows = {"ir → truck": 0, "ir-netd → truck": 1, "geometric → truck": 2}
    scene = ModelChain(load_scenario(scenario_path)).compiled.scene
    ranges = json.loads(run.stdout)["ranges"]
    assert {r["probability"] for r in ranges} == {0.5, 0.9}
    for entry in ranges:  # every pair, the NETD's too: its pixels the outline, as evaluate's
        found, p = evaluate(scene, *_positions(np.array([entry["range_m"]])))
        row = rows[entry["pair"]]
        assert bool(found.in_view[row, 0, 0])
        got = float(getattr(p, entry["task"])[row, 0, 0])
        assert abs(got - entry["probability"]) < 1e-6, (entry, got)
    by_pair = {(r["pair"], r["task"], r["probability"]): r["range_m"] for r in ranges}
    mrtd = by_pair[("ir → truck", "recognition", 0.5)]
    geometric = by_pair[("geometric → truck", "recognition", 0.5)]
    assert abs(mrtd - geometric) > 0.05 * geometric


def test_the_step_api_takes_the_scenario_file(scenario_path: Path) -> None:
    """Simulation.from_scenario(path, engine="auto"): the probabilities of a step are the core's
    with the curve (the file found from the scenario's folder)."""
    simulation = Simulation.from_scenario(scenario_path, engine="auto")
    sensors, targets = _positions(np.array([6000.0]))
    scene = ModelChain(load_scenario(scenario_path)).compiled.scene
    found, want = evaluate(scene, sensors, targets)
    simulation.step(0.0, 0.0, sensors[:, 0], targets[:, 0])
    got = simulation.step(1.0, 1.0, sensors[:, 0], targets[:, 0])
    for task in TASKS:
        np.testing.assert_allclose(
            getattr(got, task)[:, 0], getattr(want, task)[:, 0, 0], rtol=1e-12
        )
    assert found.cycles[0, 0, 0] < found.cycles[2, 0, 0]  # the MRTD row resolves less
