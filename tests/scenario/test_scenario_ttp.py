"""The TTP resolution model in a scenario: validated, compiled into the core, evaluated, stepped
(issue 25, item 1).

Expected values come from the range-case chain (:class:`targetacq.core.cases.RangeCase` with a
:class:`targetacq.physics.ttp.TtpSystem` and :func:`targetacq.core.cases.case_acquisition`, the
CLI's ``--resolution-model ttp`` path), with the target's ΔT computed here from the band
exitances, the outline's area from the box seen broadside at eye level (length × height) and the
transmittance from the extinction; and from properties (a hotter target has a larger V).
"""

from __future__ import annotations

import copy
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from targetacq import Simulation
from targetacq.core.cases import RangeCase, case_acquisition
from targetacq.core.compile import check_runnable, compile_scenario
from targetacq.core.engines import bind
from targetacq.core.evaluation import evaluate, evaluate_step
from targetacq.physics import radiometry
from targetacq.physics.ttp import TtpSystem
from targetacq.run.model_chain import ModelChain
from targetacq.scenario.schema import ScenarioError, load_scenario, parse_scenario

TASKS = ("detection", "recognition", "identification")
LWIR = (8e-6, 12e-6)  # the "lwir" band [m]
T_BACKGROUND = 295.0  # [K]; targets and background of emissivity 1
TEMPERATURES = (296.0, 305.0)  # [K]: a cool and a hot truck
GAMMA = 0.2e-3  # extinction [Np/m]
IFOV = 17e-6 / 75e-3  # [rad]
APERTURE = 75e-3 / 1.5  # [m]
CN2 = 1e-14  # [m^(-2/3)]

TEXT = f"""
[[sensors]]
name = "ir"
band = "lwir"
pixels = [640, 512]
pitch = "17 um"
focal_length = "75 mm"
f_number = 1.5
netd = "50 mK"
jitter = "0.02 mrad"
smear = "0.01 mrad"
frame_rate = "60 Hz"
scene_contrast = "4 K"
position = ["0 m", "0 m", "2 m"]
look_at = ["3 km", "0 m", "2 m"]

[[targets]]
name = "cool"
dimensions = ["7 m", "2.5 m", "3 m"]
temperature = "{TEMPERATURES[0]} K"
emissivity = 1.0
position = ["3 km", "0 m", "2 m"]

[[targets]]
name = "hot"
dimensions = ["7 m", "2.5 m", "3 m"]
temperature = "{TEMPERATURES[1]} K"
emissivity = 1.0
position = ["3 km", "0 m", "2 m"]

[background]
temperature = "{T_BACKGROUND} K"
emissivity = 1.0

[atmosphere]
extinction = "{GAMMA * 1e3} /km"
cn2 = "{CN2} m^(-2/3)"

[model]
resolution_model = "ttp"
"""


@pytest.fixture
def scenario_path(tmp_path: Path) -> Path:
    path = tmp_path / "ttp.toml"
    path.write_text(TEXT)
    return path


def _delta_t(temperature: float) -> float:
    """The blackbody ΔT at 300 K (the default netd_temperature) of the band-exitance contrast."""
    contrast = radiometry.grey_body_exitance(1.0, temperature, LWIR) - (
        radiometry.grey_body_exitance(1.0, T_BACKGROUND, LWIR)
    )
    return float(contrast / radiometry.band_exitance_derivative(300.0, LWIR))


def _system() -> TtpSystem:
    return TtpSystem(
        ifov=IFOV,
        aperture=APERTURE,
        wavelength=0.5 * (LWIR[0] + LWIR[1]),  # the band centre
        netd=0.05,
        jitter=2e-5,
        smear=1e-5,
        frame_rate=60.0,
        scene_contrast=4.0,
        cn2=CN2,
    )


def _positions(r: float) -> tuple[np.ndarray, np.ndarray]:
    """The sensor at the origin, both targets ``r`` east at its height (broadside: the heading
    is north, so the outline is the length by the height, 7 m × 3 m)."""
    sensors = np.array([[[0.0, 0.0, 2.0]]])
    targets = np.array([[[r, 0.0, 2.0]], [[r, 0.0, 2.0]]])
    return sensors, targets


def test_ttp_scenario_defaults_and_round_trip(scenario_path: Path) -> None:
    scenario = load_scenario(scenario_path)
    assert scenario.model.criterion == "ttp-vehicles"
    assert scenario.model.transform == "ttp"
    assert scenario.sensors[0].jitter == pytest.approx(2e-5)
    assert check_runnable(scenario) == []
    assert (
        type(scenario)
        .model_validate(
            scenario.model_dump(exclude={"sensors"})
            | {"sensors": [scenario.sensors[0].model_dump(exclude={"f_number"})]}
        )
        .model
        == scenario.model
    )
    ttp = compile_scenario(scenario).scene.sensors.ttp
    assert ttp is not None and ttp.rows == (0,)
    assert ttp.systems[0] == _system()


@pytest.mark.parametrize("r", [500.0, 2000.0, 6000.0])
def test_pair_equals_the_range_case(scenario_path: Path, r: float) -> None:
    scene = compile_scenario(load_scenario(scenario_path)).scene
    found, p = evaluate(scene, *_positions(r))
    assert bool(np.all(found.in_view))
    for g, temperature in enumerate(TEMPERATURES):
        case = RangeCase(
            3.0,
            IFOV,
            contrast=_delta_t(temperature),
            target_area=7.0 * 3.0,
            ttp=_system(),
            extinction=GAMMA,
            noise_model="none",  # the TTP metric holds the NETD and τ: no SNR on top
        )
        assert case.criterion.name == "ttp-vehicles"
        expected = case_acquisition(case, r)
        np.testing.assert_allclose(found.transmittance[0, g, 0], np.exp(-GAMMA * r), rtol=1e-12)
        np.testing.assert_allclose(found.cycles[0, g, 0], expected.cycles, rtol=1e-9)
        for task in TASKS:
            np.testing.assert_allclose(
                getattr(p, task)[0, g, 0], getattr(expected, task), rtol=1e-9, atol=1e-300
            )
    assert found.cycles[0, 1, 0] > found.cycles[0, 0, 0]  # the hotter target: a larger V
    assert p.recognition[0, 1, 0] >= p.recognition[0, 0, 0]


def test_ttp_differs_from_johnson(scenario_path: Path) -> None:
    text = scenario_path.read_text().replace('resolution_model = "ttp"', "")
    for name in ("jitter", "smear", "frame_rate", "scene_contrast"):
        text = "\n".join(line for line in text.splitlines() if not line.startswith(name))
    text = text.replace('cn2 = "1e-14 m^(-2/3)"', "")
    scenario_path.write_text(text)
    scene = compile_scenario(load_scenario(scenario_path)).scene
    assert scene.sensors.ttp is None
    found, _ = evaluate(scene, *_positions(2000.0))
    assert found.cycles[0, 0, 0] == pytest.approx(found.cycles[0, 1, 0])  # ΔT does not matter


def _data(**model: Any) -> dict[str, Any]:
    return {
        "sensors": [
            {
                "name": "ir",
                "band": "lwir",
                "ifov": IFOV,
                "aperture": APERTURE,
                "netd": 0.05,
                "position": [0, 0, 2],
            },
        ],
        "targets": [
            {"name": "t", "dimensions": [7, 2.5, 3], "temperature": 300.0, "position": [1000, 0, 2]}
        ],
        "background": {"temperature": 295.0},
        "model": {"resolution_model": "ttp", **model},
    }


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda d: d["model"].update(criterion="johnson"), "Johnson's N50s"),
        (lambda d: d["targets"][0].update(criterion="johnson"), r"targets\[0\].criterion"),
        (lambda d: d["sensors"][0].pop("aperture"), r"sensors\[0\].aperture: .*f_number"),
        (
            lambda d: d["sensors"].append(
                {
                    "name": "radar",
                    "type": "radar",
                    "position": [0, 0, 5],
                    "radar": {
                        "power": "1 kW",
                        "gain": "30 dB",
                        "frequency": "10 GHz",
                        "pulse_length": "1 us",
                        "beamwidth": "2 deg",
                    },
                }
            ),
            r"sensors\[1\].type: .*radar sensor cannot use it",
        ),
        (
            lambda d: (d["model"].pop("resolution_model"), d["sensors"][0].update(jitter="1 mrad")),
            r"sensors\[0\].jitter: is read by resolution_model = \"ttp\"",
        ),
    ],
)
def test_what_cannot_work_is_refused_located(change: Any, message: str) -> None:
    data = copy.deepcopy(_data())
    change(data)
    with pytest.raises(ScenarioError) as info:
        parse_scenario(data, "s.toml", strict_units=False)
    assert any(re.search(message, problem) for problem in info.value.problems), info.value.problems


def test_unknown_resolution_model_is_located_when_compiled() -> None:
    scenario = parse_scenario(
        _data() | {"model": {"resolution_model": "tpp"}}, "s.toml", strict_units=False
    )
    assert any(
        p.startswith("model.resolution_model: ") and "ttp" in p for p in check_runnable(scenario)
    )


def test_user_v50s_are_kept() -> None:
    scenario = parse_scenario(_data(n50=[3.0, 12.0, 24.0]), "s.toml", strict_units=False)
    assert scenario.model.n50 == (3.0, 12.0, 24.0)
    assert scenario.model.transform == "ttp"


def test_step_paths_equal_evaluate(scenario_path: Path) -> None:
    scene = compile_scenario(load_scenario(scenario_path)).scene
    sensors, targets = _positions(2500.0)
    _, want = evaluate(scene, sensors, targets)
    in_view, tasks, _ = evaluate_step(scene, sensors[:, 0], targets[:, 0])
    assert bool(np.all(in_view))
    for k, task in enumerate(TASKS):
        np.testing.assert_allclose(tasks[k], getattr(want, task)[:, :, 0], rtol=1e-12)
    # The step API: Simulation.from_scenario steps through the same core.
    sim = Simulation.from_scenario(scenario_path, seed=1, engine="auto")
    result = sim.step(0.0, 0.0, sensors[:, 0], targets[:, 0])
    for task in TASKS:
        np.testing.assert_allclose(getattr(result, task), getattr(want, task)[:, :, 0], rtol=1e-12)
    assert result.recognition[0, 1] > result.recognition[0, 0] > 0.0


def test_numba_refuses_and_auto_falls_back(scenario_path: Path) -> None:
    pytest.importorskip("numba")
    scene = compile_scenario(load_scenario(scenario_path)).scene
    with pytest.raises(ValueError, match="TTP resolution model"):
        bind(scene, "numba")
    assert bind(scene, "auto").engine == "numpy"


def test_jax_engine_gives_the_same_numbers(scenario_path: Path) -> None:
    pytest.importorskip("jax")
    scene = compile_scenario(load_scenario(scenario_path)).scene
    sensors = np.zeros((1, 3, 3)) + np.array([0.0, 0.0, 2.0])
    ranges = np.array([500.0, 2000.0, 6000.0])
    one = np.stack([ranges, np.zeros(3), np.full(3, 2.0)], axis=-1)
    targets = np.stack([one, one])
    numpy_engine, jax_engine = bind(scene, "numpy"), bind(scene, "jax")
    want_found = numpy_engine.factors(sensors, targets)
    want = numpy_engine.probabilities(want_found)
    got_found = jax_engine.factors(sensors, targets)
    got = jax_engine.probabilities(got_found)
    np.testing.assert_allclose(np.asarray(got_found.cycles), want_found.cycles, rtol=1e-10)
    for task in TASKS:
        np.testing.assert_allclose(
            np.asarray(getattr(got, task)), getattr(want, task), rtol=1e-10, atol=1e-13
        )


def test_range_cases_carry_the_ttp_system(scenario_path: Path) -> None:
    chain = ModelChain(load_scenario(scenario_path))
    cases = chain.range_cases()
    for g, name in enumerate(("cool", "hot")):
        case = cases[f"ir → {name}"]
        assert case.resolution_model == "ttp"
        assert case.ttp == _system()
        assert case.contrast == pytest.approx(_delta_t(TEMPERATURES[g]), rel=1e-9)
        assert case.target_area == pytest.approx(21.0, rel=1e-9)  # 7 m × 3 m broadside
        # At the scenario's own geometry (3 km), the core's cycles and P are the case's.
        found, p = evaluate(chain.compiled.scene, *_positions(3000.0))
        expected = case_acquisition(case, 3000.0)
        np.testing.assert_allclose(found.cycles[0, g, 0], expected.cycles, rtol=1e-9)
        np.testing.assert_allclose(p.recognition[0, g, 0], expected.recognition, rtol=1e-9)
