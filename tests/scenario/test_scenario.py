"""Scenario files: the examples load, and bad files give one clear located message."""

import copy
import math
from pathlib import Path

import numpy as np
import pint
import pytest
from pydantic import ValidationError

from targetacq.scenario.schema import (
    Scenario,
    ScenarioError,
    Sensor,
    Target,
    load_scenario,
    parse_scenario,
)

EXAMPLES = Path(__file__).parents[2] / "examples"

BASE = {
    "sensors": [
        {
            "name": "ir",
            "band": "lwir",
            "pixels": [640, 512],
            "pitch": "17 um",
            "focal_length": "75 mm",
            "position": ["0 m", "0 m", "10 m"],
            "look_at": ["2 km", "0 m", "0 m"],
        }
    ],
    "targets": [
        {
            "name": "truck",
            "dimensions": ["7 m", "2.5 m", "3 m"],
            "temperature": "305 K",
            "position": ["2 km", "0 m", "0 m"],
        }
    ],
    "background": {"temperature": "295 K", "clutter": "medium"},
}


@pytest.mark.parametrize("name", ["uav_haze", "ground_observer_aircraft", "two_sensors_fused"])
def test_examples_load(name):
    scenario = load_scenario(EXAMPLES / f"{name}.toml")
    assert scenario.sensors and scenario.targets


def test_units_become_si():
    s = parse_scenario(BASE)
    assert s.sensors[0].pitch == pytest.approx(17e-6)
    assert s.sensors[0].position == (0.0, 0.0, 10.0)
    assert s.targets[0].temperature == 305.0
    assert s.sensors[0].pixel_ifov == pytest.approx(17e-6 / 75e-3)


def _error(mutate):
    data = copy.deepcopy(BASE)
    mutate(data)
    with pytest.raises(ScenarioError) as info:
        parse_scenario(data, "scene.toml")
    message = str(info.value)
    assert "\n" not in message
    return message


def test_missing_unit_is_located():
    message = _error(lambda d: d["sensors"][0].__setitem__("pitch", 17))
    assert message.startswith("scene.toml: sensors[0].pitch: missing unit: got 17; ")
    assert "length" in message and "17 um" in message  # which unit to add
    message = _error(lambda d: d["targets"][0].__setitem__("position", ["2 km", 0, "0 m"]))
    assert message.startswith("scene.toml: targets[0].position: missing unit: got 0; ")
    message = _error(lambda d: d["targets"][0].__setitem__("temperature", 305))
    assert message.startswith("scene.toml: targets[0].temperature: missing unit: got 305; ")
    assert "305 K, 22 degC" in message


def test_file_with_bare_number_is_refused(tmp_path):
    text = (EXAMPLES / "uav_haze.toml").read_text(encoding="utf-8")
    assert 'pitch = "17 um"' in text
    path = tmp_path / "bare.toml"
    path.write_text(text.replace('pitch = "17 um"', "pitch = 17e-6"), encoding="utf-8")
    with pytest.raises(ScenarioError, match=r"bare.toml: sensors\[0\]\.pitch: missing unit"):
        load_scenario(path)


def test_unknown_key_says_what_was_meant():
    message = _error(lambda d: d["sensors"][0].__setitem__("focal_lenght", "75 mm"))
    assert (
        "sensors[0].focal_lenght: unknown key 'focal_lenght' (did you mean 'focal_length'?)"
        in message
    )
    message = _error(lambda d: d.__setitem__("atmosphre", {}))
    assert "unknown key 'atmosphre' (did you mean 'atmosphere'?)" in message


def test_negative_and_out_of_range_values():
    assert "pitch must be > 0" in _error(lambda d: d["sensors"][0].__setitem__("pitch", "-17 um"))
    assert "targets[0].emissivity" in _error(lambda d: d["targets"][0].__setitem__("emissivity", 2))
    message = _error(
        lambda d: d.__setitem__(
            "atmosphere", {"segments": [{"length": "-1 km", "extinction": "1/km"}]}
        )
    )
    assert "atmosphere.segments[0]: length must be >= 0" in message
    assert "step must be > 0" in _error(lambda d: d.__setitem__("time", {"step": "-1 s"}))


def test_wrong_unit_kind_and_bad_names():
    assert "is not a length" in _error(lambda d: d["sensors"][0].__setitem__("pitch", "17 K"))
    message = _error(lambda d: d.__setitem__("model", {"criterion": "jonson"}))
    assert "did you mean 'johnson'" in message
    assert "need a temperature" in _error(lambda d: d["targets"][0].pop("temperature"))
    assert "sensor names must be unique" in _error(
        lambda d: d["sensors"].append(copy.deepcopy(d["sensors"][0]))
    )


def test_malformed_and_missing_files(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[[sensors]\nname = 'x'\n")
    with pytest.raises(ScenarioError, match=r"bad.toml: malformed TOML: .*line 1"):
        load_scenario(bad)
    with pytest.raises(ScenarioError, match=r"no scenario file .*no such file"):
        load_scenario(tmp_path / "missing.toml")


ureg = pint.UnitRegistry()

SENSOR = {"name": "ir", "band": "lwir", "pixels": (640, 512), "position": (0.0, 0.0, 10.0)}


def test_python_accepts_si_floats_and_quantities():
    from_floats = Sensor(**SENSOR, pitch=17e-6, focal_length=0.075)
    from_quantities = Sensor(
        **{**SENSOR, "position": [0 * ureg.m, 0 * ureg.m, 1 * ureg.dam]},
        pitch=17 * ureg.um,
        focal_length=7.5 * ureg.cm,
    )
    from_text = Sensor(**SENSOR, pitch="17 um", focal_length="75 mm")
    assert from_floats.pitch == 17e-6 and from_floats.focal_length == 0.075
    assert from_quantities.pitch == pytest.approx(17e-6, rel=1e-15)
    assert from_quantities.focal_length == pytest.approx(0.075, rel=1e-15)
    assert from_quantities.position == (0.0, 0.0, 10.0)
    assert from_text.pitch == pytest.approx(17e-6, rel=1e-15)


def test_python_positions_and_temperatures():
    target = Target(
        name="t",
        dimensions=(7.0, 2.5 * ureg.m, "3 m"),
        temperature=ureg.Quantity(31.85, "degC"),  # 305 K
        position=ureg.Quantity(np.array([2.0, 0.5, 0.0]), "km"),
    )
    assert target.dimensions == (7.0, 2.5, 3.0)
    assert target.temperature == pytest.approx(305.0, rel=1e-12)
    assert target.position == (2000.0, 500.0, 0.0)
    from_array = Target(name="t", dimensions=(1, 1, 1), position=np.array([1.0, 2.0, 3.0]))
    assert from_array.position == (1.0, 2.0, 3.0)
    from_text = Target(name="t", dimensions=(1, 1, 1), position="1 2 3 km")
    assert from_text.position == (1000.0, 2000.0, 3000.0)


@pytest.mark.parametrize(
    ("field", "value", "match"),
    [
        ("pitch", 17 * ureg.K, r"pitch: 17 kelvin is not a length: expected dimension \[length\]"),
        ("focal_length", 75 * ureg.s, r"focal_length: .* is not a length"),
        ("pitch", math.nan, "pitch must be (finite|a number)[,;] got (nan|NaN)"),
        ("pitch", math.inf, "pitch must be finite[,;] got inf"),
        ("position", (0.0, math.nan, 10.0), "position must be (finite|a number)[,;] got (nan|NaN)"),
        ("position", (0.0, 0.0, 1 * ureg.K), r"position: 1 kelvin is not a length"),
        ("position", (0.0, 0.0), "position: a position needs three coordinates x, y, z; got 2"),
        ("look_at", 5.0, r"look_at: a position is \[x, y, z\]"),
    ],
)
def test_python_errors_name_the_field(field, value, match):
    fields = {**SENSOR, "pitch": 17e-6, "focal_length": 0.075, field: value}
    with pytest.raises(ValidationError, match=match) as info:
        Sensor(**fields)
    assert info.value.errors()[0]["loc"][0] == field
    assert isinstance(info.value, ValueError)


def test_python_angle_quantity_and_non_finite_fraction():
    waypoints = [
        {"time": 0.0, "position": (0, 0, 10)},
        {"time": 1 * ureg.min, "position": (600, 0, 10)},
    ]
    fields = {**SENSOR, "position": None, "waypoints": waypoints}
    sensor = Sensor(**fields, hfov=ureg.Quantity(12, "deg"))
    assert sensor.hfov == pytest.approx(math.pi / 15, rel=1e-15)
    assert sensor.waypoints is not None and sensor.waypoints[1].time == 60.0
    with pytest.raises(ValidationError, match="emissivity"):
        Target(name="t", dimensions=(1, 1, 1), position=(0, 0, 0), emissivity=math.nan)


def test_quantity_of_wrong_dimension_in_a_file_dict():
    message = _error(lambda d: d["sensors"][0].__setitem__("pitch", 17 * ureg.K))
    assert message == (
        "scene.toml: sensors[0].pitch: 17 kelvin is not a length: expected dimension [length] "
        "(meter, e.g. 17 um, 75 mm, 2.5 km), got [temperature]"
    )


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.toml")), ids=lambda p: p.stem)
@pytest.mark.parametrize("mode", ["python", "json"])
def test_examples_round_trip_through_model_dump(path, mode):
    scenario = load_scenario(path)
    again = Scenario.model_validate(scenario.model_dump(mode=mode))
    assert again == scenario
    assert again.model_dump() == scenario.model_dump()


def test_scenario_from_quantities_round_trips_and_equals_the_file_form():
    built = Scenario(
        sensors=[
            Sensor(
                name="ir",
                band="lwir",
                pixels=(640, 512),
                pitch=17 * ureg.um,
                focal_length=75 * ureg.mm,
                position=[0 * ureg.m, 0 * ureg.m, 10 * ureg.m],
                look_at=[2 * ureg.km, 0 * ureg.m, 0 * ureg.m],
            )
        ],
        targets=[
            Target(
                name="truck",
                dimensions=(7 * ureg.m, 2.5 * ureg.m, 3 * ureg.m),
                temperature=305 * ureg.K,
                position=[2 * ureg.km, 0 * ureg.m, 0 * ureg.m],
            )
        ],
        background={"temperature": 295 * ureg.K, "clutter": "medium"},
    )
    assert built == parse_scenario(BASE)
    for mode in ("python", "json"):
        assert Scenario.model_validate(built.model_dump(mode=mode)) == built
    # The dump holds bare SI floats: a file-strict parse of it must refuse them.
    with pytest.raises(ScenarioError, match="missing unit"):
        parse_scenario(built.model_dump())


def test_duplicate_names_are_listed_once_each():
    data = copy.deepcopy(BASE)
    target = data["targets"][0]
    data["targets"] = [{**target, "name": name} for name in ["b", "a", "c", "b", "a", "b", "d"]]
    with pytest.raises(ScenarioError, match=r"target names must be unique; repeated: a, b$"):
        parse_scenario(data)
