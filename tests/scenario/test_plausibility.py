"""Plausibility warnings (targetacq.scenario.plausibility): each row of the table warns at its limit
and not just inside it, located and with its fix; plausible scenes give none; the warning is emitted
once per validation, by files, Python records and the step API alike."""

from __future__ import annotations

import copy
import math
import re
import tomllib
import warnings
from pathlib import Path
from typing import Any

import pytest

from targetacq import Simulation
from targetacq.base.units import DIMENSIONS, parse_quantity
from targetacq.scenario.plausibility import (
    PLAUSIBLE_RANGES,
    PlausibilityWarning,
    PlausibleRange,
    collected,
    plausibility_warnings,
)
from targetacq.scenario.schema import Scenario, load_scenario, parse_scenario

EXAMPLES = Path(__file__).resolve().parents[2] / "src" / "targetacq" / "examples"


def _example(name: str) -> dict[str, Any]:
    return tomllib.loads((EXAMPLES / name).read_text(encoding="utf-8"))


def _documents() -> dict[str, dict[str, Any]]:
    """Plausible scenario files (the bundled examples, some with a table added) that between
    them hold every location of the table."""
    uav = _example("uav_haze.toml")
    uav["sensors"][0].update(netd="50 mK", netd_temperature="300 K")
    uav["model"]["search_time"] = "3.4 s"
    uav["atmosphere"]["clouds"] = [
        {"center": ["1 km", "0 m", "0 m"], "radius": "20 m", "extinction": "5 /km"}
    ]
    ifov = _example("uav_haze.toml")
    for key in ("pitch", "focal_length", "aperture"):
        del ifov["sensors"][0][key]
    ifov["sensors"][0]["ifov"] = "0.5 mrad"
    terrain = _example("uav_haze.toml")
    del terrain["background"]["clutter_std"]
    terrain["background"]["terrain"] = {
        "map": "map.csv",  # read when compiled, not when validated
        "cell_size": "10 m",
        "classes": [
            {
                "name": "grass",
                "temperature": "295 K",
                "temperature_std": "2 K",
                "resolution": "1 m",
            }
        ],
    }
    daily = copy.deepcopy(terrain)  # daily cycles (§6.5): their means are checked
    daily["time"]["hour"] = 9.0
    daily["targets"][0]["temperature"] = {"mean": "300 K", "amplitude": "5 K"}
    daily["background"]["temperature"] = {"mean": "295 K", "amplitude": "3 K"}
    daily["background"]["terrain"]["classes"][0]["temperature"] = {
        "mean": "295 K",
        "amplitude": "4 K",
        "peak_hour": 13,
    }
    ground = _example("ground_observer_aircraft.toml")
    ground["atmosphere"]["segments"] = [{"length": "200 m", "extinction": "2 /km"}]
    dry_radar = _example("radar_surveillance.toml")
    del dry_radar["atmosphere"]  # rain needs a radar at 1-1000 GHz
    return {
        "uav": uav,
        "ifov": ifov,
        "terrain": terrain,
        "daily": daily,
        "ground": ground,
        "radar": dry_radar,
        "rain": _example("radar_surveillance.toml"),
        "laser": _example("laser_radar.toml"),
        "fused": _example("two_sensors_fused.toml"),
        "colour": _example("colour_camera.toml"),
    }


# The document that holds each location (a location added to the table needs one here).
HOME = {
    "sensors[].focal_length": "uav",
    "sensors[].pitch": "uav",
    "sensors[].aperture": "uav",
    "sensors[].laser.aperture": "laser",
    "sensors[].ifov": "ifov",
    "sensors[].band": "uav",
    "sensors[].netd": "uav",
    "targets[].temperature": "uav",
    "background.temperature": "uav",
    "background.terrain.classes[].temperature": "terrain",
    "sensors[].netd_temperature": "uav",
    "targets[].temperature.mean": "daily",
    "background.temperature.mean": "daily",
    "background.terrain.classes[].temperature.mean": "daily",
    "background.clutter_std": "uav",
    "background.terrain.classes[].temperature_std": "terrain",
    "sensors[].position[2]": "fused",
    "sensors[].waypoints[].position[2]": "uav",
    "sensors[].look_at[2]": "fused",
    "targets[].position[2]": "uav",
    "targets[].waypoints[].position[2]": "uav",
    "targets[].dimensions[0]": "uav",
    "targets[].dimensions[1]": "uav",
    "targets[].dimensions[2]": "uav",
    "atmosphere.extinction": "ground",
    "atmosphere.segments[].extinction": "ground",
    "atmosphere.clouds[].extinction": "uav",
    "atmosphere.visibility": "colour",
    "atmosphere.rain_rate": "rain",
    "model.search_time": "uav",
    "sensors[].radar.power": "radar",
    "sensors[].radar.frequency": "radar",
    "sensors[].radar.pulse_length": "radar",
    "sensors[].laser.timing": "laser",
    "false_targets.max_range": "laser",
    "false_targets.density": "laser",
}

CASES = [(row, location) for row in PLAUSIBLE_RANGES for location in row.locations]


def _set(document: dict[str, Any], location: str, text: str) -> str:
    """Put ``text`` at ``location`` of a scenario document (the first item of each ``[]`` list
    that holds the rest); the location with its indices."""
    parts = location.split(".")

    def put(item: Any, k: int, shown: str) -> str | None:
        name, _, index = parts[k].partition("[")
        if not isinstance(item, dict) or name not in item:
            return None
        shown = f"{shown}.{name}" if shown else name
        if not index:
            if k == len(parts) - 1:
                item[name] = text
                return shown
            return put(item[name], k + 1, shown)
        if index == "]":
            for j, element in enumerate(item[name]):
                found = put(element, k + 1, f"{shown}[{j}]") if k < len(parts) - 1 else None
                if found is not None:
                    return found
            return None
        j = int(index.rstrip("]"))
        if isinstance(item[name], str):  # a position as one text: "0 0 1.5 km"
            *numbers, unit = item[name].split()
            item[name] = [f"{n} {unit}" for n in numbers]
        item[name][j] = text
        return f"{shown}[{j}]"

    where = put(document, 0, "")
    assert where is not None, f"{location} is not in the document"
    return where


def _text(row: PlausibleRange, value: float) -> str:
    """``value`` [SI] as a file writes it at ``row``'s location."""
    if row.read is not None:  # a band: its upper limit, the lower half of it below
        return f"{value / 2!r}-{value!r} m"
    return f"{value!r} {row.unit}"


def _warned(document: dict[str, Any]) -> list[str]:
    with collected() as found:
        parse_scenario(document, source="file.toml")
    return found


def test_the_documents_are_plausible():
    for name, document in _documents().items():
        assert _warned(document) == [], name


def test_every_location_of_the_table_has_a_document():
    assert sorted(HOME) == sorted({location for _, location in CASES})


@pytest.mark.parametrize(("row", "location"), CASES, ids=[f"{r.side}:{loc}" for r, loc in CASES])
def test_each_row_warns_at_its_limit_and_not_just_inside(row, location):
    limit = parse_quantity(row.limit, row.kind, "limit")
    inside = limit * (1 - 1e-9) if row.side == "above" else limit * (1 + 1e-9)
    document = _documents()[HOME[location]]
    where = _set(document, location, _text(row, inside))
    assert _warned(copy.deepcopy(document)) == []
    where = _set(document, location, _text(row, limit))
    found = _warned(document)
    shown = where.replace("limits", "band")
    assert len(found) == 1, found
    assert found[0].startswith(f"file.toml: {shown}: {limit:g} {row.unit} is {row.limit} or ")
    assert row.question in found[0]


def test_the_table_is_consistent():
    for row in PLAUSIBLE_RANGES:
        assert row.kind in DIMENSIONS
        # Values are shown in the SI unit of the kind, as a file would write them.
        assert parse_quantity(f"1 {row.unit}", row.kind, "unit") == 1.0
        assert row.side in ("above", "below")
        assert row.reason and row.question.endswith("?")
        if row.meant is not None:  # the fix is a quantity of the same kind
            parse_quantity(f"1 {row.meant}", row.kind, "meant")
        # Every slip moves the value by a large factor, across the limit.
        for location in row.locations:
            assert re.fullmatch(r"[a-z_]+(\[\d*\])?(\.[a-z_]+(\[\d*\])?)*", location), location


# Independent checks of messages and limits: the cases of the brief and datasheet values.
@pytest.mark.parametrize(
    ("change", "expected"),
    [
        (
            {"focal_length": 100},
            "sensors[0].focal_length: 100 m is 5 m or more; was it given in mm? "
            '(give "100 mm" or 0.1)',
        ),
        (
            {"pitch": 17},
            'sensors[0].pitch: 17 m is 1 mm or more; was it given in um? (give "17 um" or 1.7e-05)',
        ),
        (
            {"netd": 50},
            'sensors[0].netd: 50 K is 5 K or more; was it given in mK? (give "50 mK" or 0.05)',
        ),
        (
            {"position": (0.0, 0.0, 1.5e6)},
            "sensors[0].position[2]: 1.5e+06 m is 100 km or more; was it given in km for m? "
            '(give "1500 m" or 1500)',
        ),
    ],
)
def test_python_slips_are_warned_with_their_fix(change, expected):
    camera = {"name": "ir", "band": "lwir", "pitch": 17e-6, "focal_length": 0.1}
    camera.update({"position": (0.0, 0.0, 10.0), **change})
    with pytest.warns(PlausibilityWarning) as record:
        Scenario.model_validate(
            {
                "sensors": [camera],
                "targets": [
                    {
                        "name": "truck",
                        "dimensions": (7, 2.5, 3),
                        "temperature": 305.0,
                        "position": (2000.0, 0.0, 0.0),
                    }
                ],
                "background": {"temperature": 295.0},
            }
        )
    assert [str(w.message) for w in record] == [expected]


def test_a_temperature_in_degrees_celsius_is_warned():
    with pytest.warns(
        PlausibilityWarning,
        match=r"targets\[0\]\.temperature: 25 K is 150 K or "
        r'less; was it given in degC\? \(give "25 degC" or 298\.15\)',
    ):
        Scenario.model_validate(
            {
                "sensors": [
                    {"name": "ir", "band": "lwir", "ifov": 2.5e-4, "position": (0.0, 0.0, 10.0)}
                ],
                "targets": [
                    {
                        "name": "t",
                        "dimensions": (7, 2.5, 3),
                        "temperature": 25.0,
                        "position": (2000.0, 0.0, 0.0),
                    }
                ],
                "background": {"temperature": 295.0},
            }
        )


def test_a_file_with_a_unit_slip_warns_once_located_in_the_file(tmp_path):
    document = _example("uav_haze.toml")
    document["sensors"][0]["focal_length"] = "100 m"
    from toml_text import toml_dumps

    path = tmp_path / "slip.toml"
    path.write_text(toml_dumps(document), encoding="utf-8")
    with pytest.warns(PlausibilityWarning) as record:
        load_scenario(path)
    assert [str(w.message) for w in record] == [
        f"{path}: sensors[0].focal_length: 100 m is 5 m or more; was it given in mm? "
        '(give "100 mm" or 0.1)'
    ]


def test_an_aperture_from_the_f_number_is_not_warned_twice():
    camera = {
        "name": "ir",
        "band": "lwir",
        "pitch": 17e-6,
        "focal_length": 100.0,
        "f_number": 1.2,
        "position": (0.0, 0.0, 10.0),
    }
    with collected() as found:
        Scenario.model_validate(
            {
                "sensors": [camera],
                "targets": [
                    {
                        "name": "t",
                        "dimensions": (7, 2.5, 3),
                        "temperature": 305.0,
                        "position": (2000.0, 0.0, 0.0),
                    }
                ],
                "background": {"temperature": 295.0},
            }
        )
    assert [m.split(":")[0] for m in found] == ["sensors[0].focal_length"]


def test_bundled_examples_and_a_datasheet_camera_give_none():
    for path in sorted(EXAMPLES.glob("*.toml")):
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # any warning fails
            scenario = load_scenario(path)
        assert plausibility_warnings(scenario) == [], path.name


def test_the_step_api_warns():
    sensor = {"name": "ir", "band": "lwir", "pitch": 17e-6, "focal_length": 100.0}
    target = {"name": "t", "dimensions": (7.0, 2.5, 3.0), "temperature": 305.0}
    with pytest.warns(PlausibilityWarning, match=r"sensors\[0\]\.focal_length: 100 m"):
        Simulation([sensor], [target], background={"temperature": 295.0})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        Simulation([{**sensor, "focal_length": 0.1}], [target], background={"temperature": 295.0})


def test_collected_gathers_per_thread():
    import threading

    results: dict[int, list[str]] = {}

    def worker(k: int) -> None:
        sensor = {
            "name": "ir",
            "band": "lwir",
            "pitch": 17e-6,
            "focal_length": 10.0 + k,
            "position": (0.0, 0.0, 10.0),
        }
        with collected() as found:
            for _ in range(20):
                Scenario.model_validate(
                    {
                        "sensors": [sensor],
                        "targets": [
                            {
                                "name": "t",
                                "dimensions": (7, 2.5, 3),
                                "temperature": 305.0,
                                "position": (2000.0, 0.0, 0.0),
                            }
                        ],
                        "background": {"temperature": 295.0},
                    }
                )
        results[k] = found

    threads = [threading.Thread(target=worker, args=(k,)) for k in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    for k, found in results.items():
        assert len(found) == 20
        assert all(f": {10 + k:g} m is 5 m" in m for m in found)


def test_limits_are_beyond_real_values():
    """Datasheet and published values stay inside every limit (sources in each line)."""
    inside = {
        # The longest lens of a long-range surveillance camera, 2.5 m (e.g. 2500 mm zooms).
        "sensors[].focal_length": 2.5,
        "sensors[].pitch": 50e-6,  # large early FPA pixels
        "sensors[].netd": 1.0,  # cheap thermopile arrays
        "targets[].temperature": 184.0,  # Vostok station's record low, -89.2 degC
        "targets[].dimensions[0]": 458.0,  # Seawise Giant's length
        "sensors[].radar.power": 15.4e6,  # Cobra Dane's peak power
        "atmosphere.extinction": 20e-3,  # Table 7.1's densest fog, 20 /km
    }
    for location, value in inside.items():
        for row in PLAUSIBLE_RANGES:
            if location in row.locations:
                assert not row.beyond(value), (location, row.limit)
    assert math.isclose(parse_quantity("3600 mm/h", "speed", "x"), 1e-3)
