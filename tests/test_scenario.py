"""Scenario files: the examples load, and bad files give one clear located message."""

import copy
from pathlib import Path

import pytest

from targetacq.scenario import ScenarioError, load_scenario, parse_scenario

EXAMPLES = Path(__file__).parents[1] / "examples"

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
    assert message.startswith("scene.toml: sensors[0].pitch: missing unit")


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
    with pytest.raises(ScenarioError, match="no such scenario file"):
        load_scenario(tmp_path / "missing.toml")
