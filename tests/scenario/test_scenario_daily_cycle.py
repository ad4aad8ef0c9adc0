"""A temperature's daily cycle in a scenario (§6.5): ``[time] hour`` and ``temperature = {
mean, amplitude, peak_hour }``, validated, resolved at the hour in one place and evaluated by
every front-end (issue 24, "one evaluator").

Expected values come from the formula of
:func:`targetacq.physics.radiometry.diurnal_temperature`'s docstring, computed here with
:mod:`math` (``T = mean + amplitude · cos(2π (hour − peak)/24)``): a scenario with a cycle at an
hour must give the same numbers as the same scenario with that plain temperature. The
properties: a target is warmest at its peak hour, and two hours symmetric about the peak give
one temperature, hence one probability.
"""

from __future__ import annotations

import itertools
import math
import tomllib
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from targetacq import Simulation
from targetacq.core.evaluation import evaluate
from targetacq.run.model_chain import ModelChain
from targetacq.scenario.schema import (
    DailyCycle,
    Scenario,
    ScenarioError,
    held_temperature,
    load_scenario,
    parse_scenario,
)

TASKS = ("detection", "recognition", "identification")
MEAN, AMPLITUDE, PEAK = 296.0, 4.0, 15.0  # the target's cycle [K, K, h]
BACKGROUND = 291.0  # [K]: the target is warmer at every hour
RANGE = 3000.0  # [m]

SCENARIO = """
{time}
[[sensors]]
name = "ir"
type = "thermal"
band = "lwir"
pixels = [640, 512]
pitch = "17 um"
focal_length = "50 mm"
netd = "50 mK"
position = ["0 m", "0 m", "2 m"]
look_at = ["3 km", "0 m", "2 m"]

[[targets]]
name = "truck"
dimensions = ["7 m", "2.5 m", "3 m"]
temperature = {target}
emissivity = 1.0
position = ["3000 m", "0 m", "2 m"]

[background]
temperature = {background}
emissivity = 1.0
[atmosphere]
extinction = "0.2 /km"
"""

CYCLE = f'{{ mean = "{MEAN} K", amplitude = "{AMPLITUDE} K", peak_hour = {PEAK} }}'


def _formula(hour: float, mean: float, amplitude: float, peak: float = 14.0) -> float:
    """The docstring's formula, written here independently of the kernel."""
    return mean + amplitude * math.cos(2.0 * math.pi * (hour - peak) / 24.0)


def _text(hour: float | None, target: str = CYCLE, background: str = f'"{BACKGROUND} K"') -> str:
    time = "" if hour is None else f"[time]\nhour = {hour!r}\n"
    return SCENARIO.format(time=time, target=target, background=background)


def _scenario(folder: Path, text: str, name: str = "scenario.toml") -> Scenario:
    path = folder / name
    path.write_text(text)
    return load_scenario(path)


def _plain(folder: Path, hour: float) -> Scenario:
    """The same scene with the target's temperature at ``hour`` given plainly."""
    value = _formula(hour, MEAN, AMPLITUDE, PEAK)
    return _scenario(folder, _text(None, target=f'"{value!r} K"'), "plain.toml")


def _probabilities(scenario: Scenario, r: float = RANGE) -> Any:
    scene = ModelChain(scenario).compiled.scene
    sensors = np.array([[[0.0, 0.0, 2.0]]])
    targets = np.array([[[r, 0.0, 2.0]]])
    found, p = evaluate(scene, sensors, targets)
    assert bool(np.all(found.in_view))
    return scene, p


@pytest.mark.parametrize("hour", [0.0, 3.25, 6.5, 9.0, 15.0, 21.75, 23.999])
def test_the_target_at_the_hour_equals_the_plain_temperature(tmp_path: Path, hour: float):
    cycled = _scenario(tmp_path, _text(hour))
    expected = _formula(hour, MEAN, AMPLITUDE, PEAK)
    assert cycled.temperature(cycled.targets[0]) == pytest.approx(expected, rel=1e-12, abs=0)
    assert cycled.held().targets[0].temperature == pytest.approx(expected, rel=1e-12, abs=0)
    assert cycled.temperature(cycled.background) == BACKGROUND
    scene_a, a = _probabilities(cycled)
    scene_b, b = _probabilities(_plain(tmp_path, hour))
    np.testing.assert_allclose(scene_a.signature.contrast, scene_b.signature.contrast, rtol=1e-12)
    np.testing.assert_allclose(scene_a.signature.target, scene_b.signature.target, rtol=1e-12)
    for task in TASKS:
        np.testing.assert_allclose(getattr(a, task), getattr(b, task), rtol=1e-12, atol=1e-300)


@pytest.mark.parametrize("hour", [2.0, 15.0])
def test_the_step_api_takes_the_temperature_at_the_hour(tmp_path: Path, hour: float):
    positions = np.array([[0.0, 0.0, 2.0]]), np.array([[RANGE, 0.0, 2.0]])
    steps = []
    for scenario in (_scenario(tmp_path, _text(hour)), _plain(tmp_path, hour)):
        sim = Simulation.from_scenario(scenario, seed=1)
        steps.append(sim.step(0.0, 0.0, *positions))
    for name in ("fused_detection", "fused_recognition", "fused_identification"):
        np.testing.assert_allclose(
            getattr(steps[0], name), getattr(steps[1], name), rtol=1e-12, atol=1e-300
        )


def test_the_model_chain_holds_the_temperature_over_the_run(tmp_path: Path):
    # A run of minutes at 06:00: the temperature at every time is the one at the start.
    text = _text(6.0).replace("[time]\n", '[time]\nstart = "0 s"\nstop = "600 s"\nstep = "60 s"\n')
    results = ModelChain(_scenario(tmp_path, text)).evaluate().dataset
    for task in TASKS:
        values = results[task].values
        np.testing.assert_allclose(values, values[:1], rtol=0, atol=0)


def test_the_target_is_warmest_at_its_peak_hour(tmp_path: Path):
    hours = np.arange(0.0, 24.0, 0.5)
    signals = [
        float(_probabilities(_scenario(tmp_path, _text(float(h))))[0].signature.target[0, 0])
        for h in hours
    ]
    assert hours[int(np.argmax(signals))] == PEAK
    assert hours[int(np.argmin(signals))] == (PEAK + 12.0) % 24.0


def test_the_probability_follows_the_formula_over_the_day(tmp_path: Path):
    def p(hour: float) -> float:
        return float(_probabilities(_scenario(tmp_path, _text(hour)))[1].detection[0, 0, 0])

    # Two hours symmetric about the peak give one temperature, hence one probability.
    for offset in (1.5, 5.0, 9.0):
        np.testing.assert_allclose(p(PEAK - offset), p((PEAK + offset) % 24.0), rtol=1e-12)
    # The target warmer than the background at every hour: P falls as the cycle cools.
    day = [p((PEAK + d) % 24.0) for d in (0.0, 3.0, 6.0, 9.0, 12.0)]
    assert all(x > y for x, y in itertools.pairwise(day))
    # And it changes with the hour: the morning differs from the afternoon.
    assert p(6.0) != p(15.0)


def test_a_background_cycle_moves_the_contrast(tmp_path: Path):
    background = '{ mean = "291 K", amplitude = "3 K" }'  # peak_hour 14 by default
    hour = 9.5
    cycled = _scenario(tmp_path, _text(hour, target='"296 K"', background=background))
    value = _formula(hour, 291.0, 3.0)
    plain = _scenario(tmp_path, _text(None, '"296 K"', f'"{value!r} K"'), "plain.toml")
    assert cycled.temperature(cycled.background) == pytest.approx(value, rel=1e-12, abs=0)
    a, b = (ModelChain(s).compiled.scene.signature.contrast for s in (cycled, plain))
    np.testing.assert_allclose(a, b, rtol=1e-12)


def test_a_terrain_class_cycle_is_held_at_the_hour():
    classes = [
        {
            "name": "field",
            "temperature": {"mean": 288.0, "amplitude": 5.0, "peak_hour": 13.0},
            "temperature_std": 1.0,
            "resolution": 1.0,
        },
        {"name": "forest", "temperature": 285.0, "temperature_std": 1.0, "resolution": 1.0},
    ]
    scenario = Scenario.model_validate(
        {
            "sensors": [{"name": "ir", "band": "lwir", "ifov": 1e-4, "position": (0, 0, 10)}],
            "targets": [
                {
                    "name": "t",
                    "dimensions": (7, 2.5, 3),
                    "temperature": 300,
                    "position": (2000, 0, 0),
                }
            ],
            "background": {
                "temperature": 290,
                "terrain": {"map": "map.csv", "cell_size": 10, "classes": classes},
            },
            "time": {"hour": 19.0},
        }
    )
    held = scenario.held().background.terrain
    assert held is not None
    assert held.classes[0].temperature == pytest.approx(_formula(19.0, 288.0, 5.0, 13.0), 1e-12)
    assert held.classes[1].temperature == 285.0
    # A scenario without a cycle is its own held form; the plain numbers stay as they are.
    plain = scenario.model_copy(update={"background": scenario.held().background})
    assert plain.held() is plain


def test_a_cycle_round_trips_through_python():
    cycle = DailyCycle(mean="290 K", amplitude="6 K", peak_hour=3.0)
    assert (cycle.mean, cycle.amplitude, cycle.peak_hour) == (290.0, 6.0, 3.0)
    assert held_temperature(cycle, 3.0) == pytest.approx(296.0, rel=1e-12)
    assert held_temperature(301.5, None) == 301.5
    with pytest.raises(ValueError, match=r"\[time\] hour"):
        held_temperature(cycle, None)
    scenario = Scenario.model_validate(
        {
            "sensors": [{"name": "ir", "band": "lwir", "ifov": 1e-4, "position": (0, 0, 10)}],
            "targets": [
                {
                    "name": "t",
                    "dimensions": (7, 2.5, 3),
                    "temperature": cycle,
                    "position": (2000, 0, 0),
                }
            ],
            "background": {"temperature": 290},
            "time": {"hour": 9},
        }
    )
    assert Scenario.model_validate(scenario.model_dump()) == scenario


@pytest.mark.parametrize(
    ("time", "target", "where", "what"),
    [
        ("hour = 24", CYCLE, r"time\.hour", r"\[0, 24\)"),
        ("hour = -0.5", CYCLE, r"time\.hour", r"\[0, 24\)"),
        ("hour = nan", CYCLE, r"time\.hour", "finite"),
        ("hour = inf", CYCLE, r"time\.hour", "finite"),
        ('hour = "6 h"', CYCLE, r"time\.hour", "without quotes"),
        (
            "hour = 6",
            '{ mean = "290 K", amplitude = "290 K" }',
            r"targets\[0\]\.temperature",
            "amplitude must be smaller than mean",
        ),
        (
            "hour = 6",
            '{ mean = "290 K", amplitude = "-1 K" }',
            r"targets\[0\]\.temperature\.amplitude",
            r"\[0, 10000\] K",
        ),
        (
            "hour = 6",
            '{ mean = "290 K", amplitude = "1 K", peak_hour = 24 }',
            r"targets\[0\]\.temperature\.peak_hour",
            r"\[0, 24\)",
        ),
        (
            "hour = 6",
            '{ mean = "290 K", amplitude = "1 K", peak_hour = nan }',
            r"targets\[0\]\.temperature\.peak_hour",
            "finite",
        ),
        (
            "hour = 6",
            '{ mean = "290 K", amplitude = "1 K", peak = 14 }',
            r"targets\[0\]\.temperature\.peak",
            "unknown key 'peak' \\(did you mean 'peak_hour'",
        ),
        ("hour = 6", '{ mean = "290 K" }', r"targets\[0\]\.temperature\.amplitude", "missing"),
        (
            "hour = 6",
            '{ mean = 290, amplitude = "1 K" }',
            r"targets\[0\]\.temperature\.mean",
            "unit",
        ),
        ("minute = 6", '"300 K"', r"time\.minute", "unknown key 'minute'"),
        ("", CYCLE, r"targets\[0\]\.temperature", r"daily cycle needs .*\[time\] hour"),
    ],
)
def test_bad_inputs_are_located(time: str, target: str, where: str, what: str):
    text = SCENARIO.format(
        time=f"[time]\n{time}\n" if time else "", target=target, background='"291 K"'
    )
    with pytest.raises(ScenarioError, match=f"^daily.toml: {where}: .*{what}"):
        parse_scenario(tomllib.loads(text), "daily.toml")


def test_a_cycle_without_the_hour_names_both_in_python():
    with pytest.raises(ValueError, match=r"background\.temperature: a daily cycle .*\[time\] hour"):
        Scenario.model_validate(
            {
                "sensors": [{"name": "ir", "band": "lwir", "ifov": 1e-4, "position": (0, 0, 10)}],
                "targets": [
                    {
                        "name": "t",
                        "dimensions": (7, 2.5, 3),
                        "temperature": 300,
                        "position": (2000, 0, 0),
                    }
                ],
                "background": {"temperature": {"mean": 290, "amplitude": 2}},
            }
        )


def test_validate_and_evaluate_from_the_command_line(tmp_path: Path, cli: Any):
    path = tmp_path / "daily.toml"
    path.write_text(_text(6.5))
    code, out, err = cli("validate", str(path))
    assert code == 0 and "valid" in out and not err
    code, out, err = cli("evaluate", str(path), "--format", "json")
    assert code == 0, err
    plain = tmp_path / "plain.toml"
    plain.write_text(_text(None, target=f'"{_formula(6.5, MEAN, AMPLITUDE, PEAK)!r} K"'))
    code_b, out_b, err_b = cli("evaluate", str(plain), "--format", "json")
    assert code_b == 0, err_b
    assert out.replace(str(path), "") == out_b.replace(str(plain), "")
    path.write_text(_text(None))
    code, out, err = cli("validate", str(path))
    assert code == 2 and not out
    assert err.count("\n") >= 1 and "Traceback" not in err
    assert "targets[0].temperature: a daily cycle needs" in err and "[time] hour" in err
