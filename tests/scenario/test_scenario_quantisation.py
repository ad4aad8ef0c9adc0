"""A sensor's digitiser step in a scenario (§6.8): validated, compiled into the core and
evaluated by every front-end (issue 24, "one evaluator").

A pair whose contrast is below its sensor's step has every probability 0; one just above it has
the numbers of the same scenario without a step, and of the analyst's
:func:`targetacq.scene_acquisition` with ``quantisation_step``. The contrasts are computed here
from the band exitances (:func:`targetacq.physics.radiometry.grey_body_exitance`), the step of bits
over a span as ``span / (2^bits − 1)``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from targetacq import Simulation
from targetacq.core.cases import RangeCase
from targetacq.core.engines import bind
from targetacq.core.evaluation import evaluate
from targetacq.core.pair_ranges import pair_performance
from targetacq.physics import radiometry
from targetacq.run.model_chain import ModelChain
from targetacq.run.scene import Scene, scene_acquisition
from targetacq.scenario.schema import ScenarioError, load_scenario

TASKS = ("detection", "recognition", "identification")
LWIR = (8e-6, 12e-6)  # the "lwir" band [m]
GAMMA = 0.4e-3  # extinction [Np/m]
SENSOR_Z = 2.0
IFOV = 17e-6 / 50e-3
T_BACKGROUND = 293.0
T_TARGETS = {"warm": 296.0, "faint": 293.2}  # [K], emissivity 1


def _contrast(name: str) -> float:
    """Exitance contrast of a target against the background in the lwir band [W/m²]."""
    target = radiometry.grey_body_exitance(1.0, T_TARGETS[name], LWIR)
    return float(target - radiometry.grey_body_exitance(1.0, T_BACKGROUND, LWIR))


SENSOR = """
[[sensors]]
name = "{name}"
type = "thermal"
band = "lwir"
pixels = [640, 512]
pitch = "17 um"
focal_length = "50 mm"
position = ["0 m", "0 m", "2 m"]
look_at = ["3 km", "0 m", "2 m"]
{extra}
"""

TARGET = """
[[targets]]
name = "{name}"
dimensions = ["7 m", "2.5 m", "3 m"]
temperature = "{temperature} K"
emissivity = 1.0
position = ["3 km", "0 m", "2 m"]
"""

REST = f"""
[background]
temperature = "{T_BACKGROUND} K"
emissivity = 1.0

[atmosphere]
extinction = "{GAMMA} /m"
"""


def _text(sensors: dict[str, str]) -> str:
    return (
        "".join(SENSOR.format(name=n, extra=e) for n, e in sensors.items())
        + "".join(TARGET.format(name=n, temperature=t) for n, t in T_TARGETS.items())
        + REST
    )


def _load(folder: Path, text: str, name: str = "scenario.toml") -> ModelChain:
    path = folder / name
    path.write_text(text)
    return ModelChain(load_scenario(path))


def _positions(ranges: np.ndarray, n_s: int) -> tuple[np.ndarray, np.ndarray]:
    n = ranges.size
    sensors = np.broadcast_to(np.array([0.0, 0.0, SENSOR_Z]), (n_s, n, 3)).copy()
    one = np.stack([ranges, np.zeros(n), np.full(n, SENSOR_Z)], axis=-1)
    return sensors, np.broadcast_to(one, (len(T_TARGETS), n, 3)).copy()


def _step(value: float) -> str:
    return f'quantisation_step = "{value!r} W/m^2"'


# Between the two contrasts, just above the faint one's: "faint" is lost, "warm" is seen.
BETWEEN = _contrast("faint") * (1.0 + 1e-6)
JUST_BELOW = _contrast("faint") * (1.0 - 1e-6)


@pytest.fixture
def chain(tmp_path: Path) -> ModelChain:
    return _load(
        tmp_path,
        _text(
            {
                "coarse": _step(BETWEEN),
                "fine": _step(JUST_BELOW),
                "plain": "",
                "adc": f'adc_bits = 8\nadc_span = "{BETWEEN * 255.0!r} W/m^2"',
            }
        ),
    )


def test_steps_compile_into_the_sensors(chain: ModelChain, tmp_path: Path) -> None:
    steps = chain.compiled.scene.sensors.quantisation_step
    np.testing.assert_allclose(steps, [BETWEEN, JUST_BELOW, 0.0, BETWEEN], rtol=1e-12)
    np.testing.assert_allclose(
        chain.compiled.scene.signature.contrast[0],
        [_contrast("warm"), _contrast("faint")],
        rtol=1e-9,
    )
    plain = _load(tmp_path, _text({"plain": ""}), "plain.toml")
    assert plain.compiled.scene.sensors.quantisation_step is None


@pytest.mark.parametrize("r", [200.0, 1500.0, 4000.0])
def test_a_contrast_below_the_step_is_not_seen(chain: ModelChain, r: float) -> None:
    found, p = evaluate(chain.compiled.scene, *_positions(np.array([r]), 4))
    assert bool(np.all(found.in_view))
    for task in TASKS:
        values = getattr(p, task)[:, :, 0]
        # The plain sensor's numbers, wherever the contrast is at or above the step.
        plain = values[2]
        assert np.all(plain > 0.0)
        np.testing.assert_array_equal(values[1], plain)  # step just below both contrasts
        for row in (0, 3):  # step between them (given, and 8 bits over 255 steps)
            assert values[row, 0] == plain[0]
            assert values[row, 1] == 0.0
        # Fused (8.4): the rows that see the faint target, again.
        fused = getattr(p, f"fused_{task}")[:, 0]
        np.testing.assert_allclose(fused[1], 1.0 - (1.0 - plain[1]) ** 2, rtol=1e-12)


def test_the_core_equals_scene_acquisition_with_a_step(chain: ModelChain) -> None:
    r = 1500.0
    _, p = evaluate(chain.compiled.scene, *_positions(np.array([r]), 4))
    case = RangeCase(3.0, IFOV, cycle=2.0 * IFOV, extinction=GAMMA)
    for g, name in enumerate(T_TARGETS):
        scene = Scene("lwir", T_TARGETS[name], T_BACKGROUND)
        for row, step in ((0, BETWEEN), (1, JUST_BELOW)):
            expected = scene_acquisition(r, case, scene, quantisation_step=step)
            for task in TASKS:
                np.testing.assert_allclose(
                    getattr(p, task)[row, g, 0], getattr(expected, task), rtol=1e-9, atol=0.0
                )


def test_nan_geometry_stays_nan(chain: ModelChain) -> None:
    sensors, targets = _positions(np.array([1500.0]), 4)
    targets[1] = np.nan
    _, p = evaluate(chain.compiled.scene, sensors, targets)
    assert np.all(np.isnan(p.detection[:, 1]))
    assert not np.isnan(p.detection[:, 0]).any()


def test_the_step_api_and_model_chain_see_the_step(chain: ModelChain) -> None:
    scene = chain.compiled.scene
    sensors, targets = _positions(np.array([3000.0]), 4)
    _, want = evaluate(scene, sensors, targets)
    _, tasks, fused = bind(scene, "numpy").step(sensors[:, 0], targets[:, 0])
    for k, task in enumerate(TASKS):
        np.testing.assert_allclose(tasks[k], getattr(want, task)[:, :, 0], rtol=1e-12)
        np.testing.assert_allclose(fused[k], getattr(want, f"fused_{task}")[:, 0], rtol=1e-12)
    assert np.all(tasks[:, [0, 3], 1] == 0.0)
    step = Simulation.from_scenario(chain.scenario, seed=3).step(
        0.0, 0.0, sensors[:, 0], targets[:, 0]
    )
    np.testing.assert_allclose(step.fused_detection, want.fused_detection[:, 0], rtol=1e-12)
    # The scenario's targets stand 3 km east, where evaluate() put them.
    results = chain.evaluate([0.0]).dataset
    for task in TASKS:
        np.testing.assert_allclose(
            results[task].values[..., 0], getattr(want, task)[:, :, 0], rtol=1e-12
        )


def test_dri_has_no_range_below_the_step(chain: ModelChain) -> None:
    dri = pair_performance(chain, [0, 2], [0.5]).dri
    lost = dri[dri["case"] == "coarse → faint"]
    seen = dri[dri["case"] == "plain → faint"]
    assert not lost["reached"].any()
    assert seen["reached"].all()


def test_jax_engine_gives_the_same_numbers(chain: ModelChain) -> None:
    pytest.importorskip("jax")
    scene = chain.compiled.scene
    sensors, targets = _positions(np.array([300.0, 1500.0, 6000.0]), 4)
    numpy_engine, jax_engine = bind(scene, "numpy"), bind(scene, "jax")
    want = numpy_engine.probabilities(numpy_engine.factors(sensors, targets))
    got = jax_engine.probabilities(jax_engine.factors(sensors, targets))
    for task in (*TASKS, *(f"fused_{t}" for t in TASKS)):
        np.testing.assert_allclose(
            np.asarray(getattr(got, task)), getattr(want, task), rtol=1e-10, atol=1e-13
        )
    _, tasks, _ = jax_engine.step(sensors[:, 1], targets[:, 1])
    np.testing.assert_allclose(
        np.asarray(tasks), [getattr(want, t)[:, :, 1] for t in TASKS], rtol=1e-10, atol=1e-13
    )


def test_numba_refuses_and_auto_falls_back(chain: ModelChain) -> None:
    pytest.importorskip("numba")
    scene = chain.compiled.scene
    with pytest.raises(ValueError, match="quantisation"):
        bind(scene, "numba")
    assert bind(scene, "auto").engine == "numpy"


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        ('quantisation_step = "-1 W/m^2"', "quantisation_step must be >= 0"),
        ("quantisation_step = 0.01", "quantisation_step"),  # no unit
        ('quantisation_step = "nan W/m^2"', "quantisation_step"),
        ('quantisation_step = "1 K"', "quantisation_step"),
        ("adc_bits = 12", "adc_bits and adc_span go together"),
        ('adc_span = "1 W/m^2"', "adc_bits and adc_span go together"),
        ('adc_bits = 0\nadc_span = "1 W/m^2"', "adc_bits"),
        ('adc_bits = 12.5\nadc_span = "1 W/m^2"', "adc_bits"),
        ('adc_bits = 12\nadc_span = "0 W/m^2"', "adc_span must be > 0"),
        ('adc_bits = 12\nadc_span = "1 W/m^2"\nquantisation_step = "1 W/m^2"', "not both"),
    ],
)
def test_bad_steps_are_refused(tmp_path: Path, extra: str, message: str) -> None:
    with pytest.raises(ScenarioError, match=r"sensors\[0\]") as error:
        _load(tmp_path, _text({"ir": extra}))
    assert message in str(error.value)


def test_a_radar_takes_no_step(tmp_path: Path) -> None:
    radar = """
[[sensors]]
name = "rad"
type = "radar"
position = ["0 m", "0 m", "2 m"]
quantisation_step = "1 W/m^2"
radar = { power = "1 kW", gain = "30 dB", frequency = "10 GHz", pulse_length = "0.1 us", beamwidth = "1 deg" }
"""  # noqa: E501
    with pytest.raises(ScenarioError) as error:
        _load(tmp_path, _text({"ir": ""}) + radar)
    assert any(
        "quantisation_step: a digitiser's step is compared with an imaging sensor's contrast; "
        "a radar has none" in problem
        for problem in error.value.problems
    )
