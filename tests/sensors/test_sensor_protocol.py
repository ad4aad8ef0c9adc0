"""The sensor-type protocol: the scenario's per-type rules come from :data:`SENSOR_TYPES`.

Each rule is checked for every registered type, so a type added to the registry is checked
without a test of its own: its table, its band (required, default, limits) and its noise key.
"""

import tomllib
from pathlib import Path

import pytest

from targetacq.scenario.schema import Sensor
from targetacq.sensors import NOISE_KEYS, SENSOR_TYPES, get_sensor_type

EXAMPLES = Path(__file__).parents[2] / "examples"


def _sensors_by_type() -> dict[str, dict]:
    """The first sensor of each type in the bundled examples, as its file gives it."""
    found: dict[str, dict] = {}
    for path in sorted(EXAMPLES.glob("*.toml")):
        for sensor in tomllib.loads(path.read_text(encoding="utf-8")).get("sensors", []):
            found.setdefault(sensor.get("type", "thermal"), sensor)
    return found


SENSORS = _sensors_by_type()
IMAGING = [n for n, t in SENSOR_TYPES.items() if t.kind != "radar"]


def _sensor(name: str, **update) -> Sensor:
    raw = {k: v for k, v in SENSORS[name].items() if k not in ("netd", "nec", "netd_temperature")}
    raw.update(update)
    return Sensor.model_validate({k: v for k, v in raw.items() if v is not None})


def test_every_registered_type_has_a_bundled_example():
    assert set(SENSORS) == set(SENSOR_TYPES)


@pytest.mark.parametrize("name", list(SENSOR_TYPES))
def test_a_type_s_table_is_required_for_it_and_refused_for_the_others(name):
    kind = get_sensor_type(name)
    for other in SENSOR_TYPES.values():
        if other.table is None or other is kind:
            continue
        with pytest.raises(ValueError, match=f'{other.table} belongs to a type = "{other.name}"'):
            _sensor(name, **{other.table: SENSORS[other.name][other.table]})
    if kind.table is not None:
        with pytest.raises(ValueError, match=f'a type = "{name}" sensor needs its {kind.table}'):
            _sensor(name, **{kind.table: None})


@pytest.mark.parametrize("name", IMAGING)
def test_a_type_s_band_is_required_or_defaults(name):
    kind = get_sensor_type(name)
    if kind.band_required:
        with pytest.raises(ValueError, match=f"a {name} sensor needs its band"):
            _sensor(name, band=None)
    else:
        assert _sensor(name, band=None).limits == kind.default_band
        low, high = kind.band_within or kind.default_band
        assert low <= kind.default_band[0] < kind.default_band[1] <= high


BOUNDED = [name for name in IMAGING if get_sensor_type(name).band_within is not None]


def test_some_type_bounds_its_band():
    assert "swir" in BOUNDED  # the test below runs on at least one type


@pytest.mark.parametrize("name", BOUNDED)
def test_a_band_outside_the_type_s_limits_is_refused_naming_them(name):
    within = get_sensor_type(name).band_within
    inside = f"{within[0] * 1e6:g}-{within[1] * 1e6:g} um"
    assert _sensor(name, band=inside).limits == pytest.approx(within)
    beyond = f"{within[0] * 1e6:g}-{within[1] * 1.2e6:g} um"
    with pytest.raises(ValueError, match=f"band of a {name} sensor must lie within {inside}"):
        _sensor(name, band=beyond)


@pytest.mark.parametrize("name", IMAGING)
def test_a_type_takes_its_own_noise_key_only(name):
    kind = get_sensor_type(name)
    values = {"netd": "50 mK", "nec": 0.01}
    assert set(values) == set(NOISE_KEYS)
    for key, value in values.items():
        if key == kind.noise_key:
            assert getattr(_sensor(name, **{key: value}), key) is not None
            continue
        owners = [t for t in SENSOR_TYPES.values() if t.noise_key == key]
        expected = (
            kind.noise_elsewhere
            if kind.noise_key is None
            else f"{key} is the {NOISE_KEYS[key]} of a type = .*{owners[0].name}.* sensor; "
            f"a {name} sensor takes {kind.noise_key}"
        )
        with pytest.raises(ValueError, match=expected):
            _sensor(name, **{key: value})
