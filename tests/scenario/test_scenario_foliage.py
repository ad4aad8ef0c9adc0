"""Foliage in front of a target in a scenario (§6.8): validated, compiled into the core and
evaluated by every front-end (issue 24, "one evaluator").

Expected values come from the range-case chain (:class:`targetacq.core.cases.RangeCase` with
``foliage``, :func:`targetacq.core.cases.case_acquisition`: ``τ = exp(−γR) · τ_f``) and from an
independent identity: foliage of transmittance ``τ_f`` at range ``R`` is the same path as no
foliage and an extinction raised by ``−ln(τ_f) / R``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from targetacq import Simulation
from targetacq.core import take_targets
from targetacq.core.cases import RangeCase, case_acquisition
from targetacq.core.engines import bind
from targetacq.core.evaluation import evaluate
from targetacq.core.pair_ranges import pair_performance
from targetacq.run.model_chain import ModelChain
from targetacq.scenario.schema import ScenarioError, load_scenario

TASKS = ("detection", "recognition", "identification")
GAMMA = 0.4e-3  # extinction [Np/m]
SENSOR_Z = 2.0  # sensors and targets at one height: the critical dimension is the height, 3 m
IFOV = 17e-6 / 50e-3  # pitch / focal length [rad]
FOLIAGE = {"truck": 0.6, "jeep": None, "hidden": 0.0}

SENSORS = """
[[sensors]]
name = "ir"
type = "thermal"
band = "lwir"
pixels = [640, 512]
pitch = "17 um"
focal_length = "50 mm"
position = ["0 m", "0 m", "2 m"]
look_at = ["3 km", "0 m", "2 m"]

[[sensors]]
name = "ir-netd"
type = "thermal"
band = "lwir"
pixels = [640, 512]
pitch = "17 um"
focal_length = "50 mm"
netd = "50 mK"
position = ["0 m", "0 m", "2 m"]
look_at = ["3 km", "0 m", "2 m"]
"""

TARGET = """
[[targets]]
name = "{name}"
dimensions = ["7 m", "2.5 m", "3 m"]
temperature = "293.5 K"
emissivity = 1.0
position = ["{x} m", "0 m", "2 m"]
{extra}
"""

BACKGROUND = """
[background]
temperature = "293 K"
emissivity = 1.0
"""
RADAR_BACKGROUND = 'sigma0 = "-20 dB"\n'


def _text(foliage: dict[str, float | None], extinction: float | None = GAMMA, x: float = 3000.0):
    targets = "".join(
        TARGET.format(name=name, x=x, extra="" if f is None else f"foliage = {f!r}")
        for name, f in foliage.items()
    )
    atmosphere = "" if extinction is None else f'[atmosphere]\nextinction = "{extinction} /m"\n'
    return SENSORS + targets + BACKGROUND + atmosphere


def _load(folder: Path, text: str, name: str = "scenario.toml") -> ModelChain:
    path = folder / name
    path.write_text(text)
    return ModelChain(load_scenario(path))


def _positions(ranges: np.ndarray, n_g: int) -> tuple[np.ndarray, np.ndarray]:
    """Two sensors at the origin and every target at ``ranges`` east, one batch column each."""
    n = ranges.size
    sensors = np.broadcast_to(np.array([0.0, 0.0, SENSOR_Z]), (2, n, 3)).copy()
    one = np.stack([ranges, np.zeros(n), np.full(n, SENSOR_Z)], axis=-1)
    return sensors, np.broadcast_to(one, (n_g, n, 3)).copy()


def _cases(chain: ModelChain, g: int, extinction: float | None) -> list[RangeCase]:
    """The two sensors' range cases of target ``g``: geometric, and with the NETD's noise (its
    pixels the outline's area, 7 m × 3 m, the long side across the line of sight)."""
    scene = chain.compiled.scene
    foliage = FOLIAGE[scene.targets.names[g]]
    base = {"extinction": extinction, "foliage": foliage, "cycle": 2.0 * IFOV}
    return [
        RangeCase(3.0, IFOV, **base),
        RangeCase(
            3.0,
            IFOV,
            contrast=float(scene.signature.contrast[1, g]),
            noise_equivalent_contrast=float(scene.sensors.noise_equivalent[1]),
            # σ_path of the contrast SNR law in the contrast's unit, W/m² (1 K · ∂M/∂T).
            path_contrast=float(scene.sensors.path_contrast[1]),
            target_area=21.0,
            **base,
        ),
    ]


@pytest.fixture
def chain(tmp_path: Path) -> ModelChain:
    return _load(tmp_path, _text(FOLIAGE))


def test_foliage_compiles_into_the_targets(chain: ModelChain) -> None:
    scene = chain.compiled.scene
    assert scene.targets.foliage.tolist() == [0.6, 1.0, 0.0]
    assert scene.path.attenuates
    assert take_targets(scene, [2, 0]).targets.foliage.tolist() == [0.0, 0.6]


def test_no_foliage_leaves_the_scene_as_it_was(tmp_path: Path) -> None:
    scene = _load(tmp_path, _text({"jeep": None}, extinction=None)).compiled.scene
    assert scene.targets.foliage is None
    assert not scene.path.attenuates  # no atmosphere, no foliage: no path noise


@pytest.mark.parametrize("r", [300.0, 1500.0, 3000.0, 8000.0])
@pytest.mark.parametrize("extinction", [GAMMA, None])
def test_evaluate_equals_the_range_case_chain(
    tmp_path: Path, r: float, extinction: float | None
) -> None:
    chain = _load(tmp_path, _text(FOLIAGE, extinction))
    scene = chain.compiled.scene
    found, p = evaluate(scene, *_positions(np.array([r]), 3))
    assert bool(np.all(found.in_view))
    for g in range(3):
        for row, case in enumerate(_cases(chain, g, extinction)):
            expected = case_acquisition(case, r)
            np.testing.assert_allclose(
                found.transmittance[row, g, 0], expected.transmittance, rtol=1e-12
            )
            np.testing.assert_allclose(found.snr[row, g, 0], expected.snr, rtol=1e-9)
            for task in TASKS:
                np.testing.assert_allclose(
                    getattr(p, task)[row, g, 0], getattr(expected, task), rtol=1e-9, atol=1e-300
                )


@pytest.mark.parametrize("r", [700.0, 2500.0])
def test_foliage_is_extinction_raised_by_its_depth_over_the_range(tmp_path: Path, r: float):
    tau_f = 0.6
    with_foliage = _load(tmp_path, _text({"truck": tau_f}), "a.toml").compiled.scene
    raised = GAMMA - math.log(tau_f) / r
    thicker = _load(tmp_path, _text({"truck": None}, raised), "b.toml").compiled.scene
    positions = _positions(np.array([r]), 1)
    found_a, a = evaluate(with_foliage, *positions)
    found_b, b = evaluate(thicker, *positions)
    np.testing.assert_allclose(found_a.transmittance, math.exp(-GAMMA * r) * tau_f, rtol=1e-12)
    np.testing.assert_allclose(found_a.optical_depth, found_b.optical_depth, rtol=1e-12)
    for task in TASKS:
        np.testing.assert_allclose(getattr(a, task), getattr(b, task), rtol=1e-10, atol=1e-300)
        assert np.all(getattr(a, task) < 1.0)


def test_zero_foliage_hides_the_target_without_nan(chain: ModelChain) -> None:
    scene = chain.compiled.scene
    sensors, targets = _positions(np.array([50.0, 300.0, 3000.0]), 3)
    found, p = evaluate(scene, sensors, targets)
    assert np.all(found.transmittance[:, 2] == 0.0)
    for task in TASKS:
        values = getattr(p, task)
        assert not np.isnan(values).any()
        assert np.all(values[:, 2] == 0.0)
        assert np.all(values[:, 1] > 0.0)  # the jeep, no foliage, is seen
    in_view, tasks, fused = bind(scene, "numpy").step(sensors[:, 0], targets[:, 0])
    assert bool(np.all(in_view))
    assert np.all(tasks[:, :, 2] == 0.0) and np.all(fused[:, 2] == 0.0)


def test_the_step_api_sees_foliage(chain: ModelChain) -> None:
    scene = chain.compiled.scene
    sensors, targets = _positions(np.array([1500.0]), 3)
    _, want = evaluate(scene, sensors, targets)
    # The lean NumPy step computes the chain of the pairs it needs only: the same numbers.
    _, tasks, _ = bind(scene, "numpy").step(sensors[:, 0], targets[:, 0])
    for k, task in enumerate(TASKS):
        np.testing.assert_allclose(tasks[k], getattr(want, task)[:, :, 0], rtol=1e-12)
    sim = Simulation.from_scenario(chain.scenario, seed=1)
    step = sim.step(0.0, 0.0, sensors[:, 0], targets[:, 0])
    expected = 1.0 - np.prod(1.0 - want.detection[:, :, 0], axis=0)
    np.testing.assert_allclose(step.fused_detection, expected, rtol=1e-12)
    assert step.fused_detection[2] == 0.0


def test_model_chain_evaluate_and_range_cases_see_foliage(chain: ModelChain) -> None:
    # The scenario's targets stand 3 km east of the sensors, at their height.
    results = chain.evaluate([0.0]).dataset
    cases = chain.range_cases()
    for g, target in enumerate(("truck", "jeep", "hidden")):
        assert cases[f"ir → {target}"].foliage == {None: 1.0}.get(FOLIAGE[target], FOLIAGE[target])
        expected = case_acquisition(_cases(chain, g, GAMMA)[0], 3000.0)
        for task in TASKS:
            np.testing.assert_allclose(
                results[task].values[0, g, 0], getattr(expected, task), rtol=1e-9, atol=1e-300
            )


def test_dri_ranges_shrink_behind_foliage(tmp_path: Path) -> None:
    chain = _load(tmp_path, _text({"truck": 0.3, "jeep": None}, x=2000.0))
    dri = pair_performance(chain, [0, 1], [0.5]).dri
    for sensor in ("ir", "ir-netd"):
        for task in TASKS:

            def at(target: str, task: str = task, sensor: str = sensor) -> float:
                row = dri[(dri["case"] == f"{sensor} → {target}") & (dri["task"] == task)]
                return float(row["range_m"].iloc[0])

            # NaN: never reached (the contrast law's foliage, emitting as 1 − τ_f, can hide it).
            truck = at("truck")
            assert math.isnan(truck) or truck < at("jeep")


def test_jax_engine_gives_the_same_numbers(chain: ModelChain) -> None:
    pytest.importorskip("jax")
    scene = chain.compiled.scene
    sensors, targets = _positions(np.array([300.0, 1500.0, 6000.0]), 3)
    numpy_engine, jax_engine = bind(scene, "numpy"), bind(scene, "jax")
    want = numpy_engine.probabilities(numpy_engine.factors(sensors, targets))
    got = jax_engine.probabilities(jax_engine.factors(sensors, targets))
    for task in TASKS:
        np.testing.assert_allclose(
            np.asarray(getattr(got, task)), getattr(want, task), rtol=1e-10, atol=1e-13
        )
    in_view, tasks, _ = jax_engine.step(sensors[:, 1], targets[:, 1])
    assert bool(np.all(in_view))
    np.testing.assert_allclose(
        np.asarray(tasks), [getattr(want, t)[:, :, 1] for t in TASKS], rtol=1e-10, atol=1e-13
    )


def test_numba_refuses_and_auto_falls_back(chain: ModelChain) -> None:
    pytest.importorskip("numba")
    scene = chain.compiled.scene
    with pytest.raises(ValueError, match="foliage"):
        bind(scene, "numba")
    assert bind(scene, "auto").engine == "numpy"


@pytest.mark.parametrize("value", ["1.5", "-0.1", "nan", "inf", '"0.5"', "true"])
def test_bad_foliage_is_refused(tmp_path: Path, value: str) -> None:
    text = _text({"truck": None}).replace(
        'position = ["3000.0 m"', f'foliage = {value}\nposition = ["3000.0 m"'
    )
    assert "foliage = " in text
    with pytest.raises(ScenarioError, match=r"targets\[0\]\.foliage"):
        _load(tmp_path, text)


def test_foliage_with_a_radar_is_refused(tmp_path: Path) -> None:
    radar = """
[[sensors]]
name = "rad"
type = "radar"
position = ["0 m", "0 m", "2 m"]
radar = { power = "1 kW", gain = "30 dB", frequency = "10 GHz", pulse_length = "0.1 us", beamwidth = "1 deg" }
"""  # noqa: E501
    text = _text({"truck": 0.5, "jeep": None}).replace(BACKGROUND, BACKGROUND + RADAR_BACKGROUND)
    text += radar
    text = text.replace("emissivity = 1.0\nposition", 'emissivity = 1.0\nrcs = "10 m^2"\nposition')
    with pytest.raises(ScenarioError) as error:
        _load(tmp_path, text)
    (problem,) = error.value.problems
    assert "targets[0].foliage" in problem
    assert "'truck'" in problem and "'rad', a radar" in problem
