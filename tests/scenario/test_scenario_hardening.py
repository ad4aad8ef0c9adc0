"""Bad scenarios never crash and never lie: domains, strict types, contradictions, files named by
the scenario, run sizes, seeds and the file parser, through the Python API and the CLI."""

import copy
import json
import math
import os
import re
import shutil
import tomllib
from pathlib import Path

import numpy as np
import pytest

from targetacq.base import limits
from targetacq.base.sampling import stream_key
from targetacq.core.compile import check_runnable, compile_scenario
from targetacq.run.model_chain import ModelChain
from targetacq.run.search import simulate
from targetacq.scenario.plausibility import PlausibilityWarning
from targetacq.scenario.schema import (
    Scenario,
    ScenarioError,
    Sensor,
    Target,
    TimeGrid,
    load_scenario,
    parse_scenario,
)

EXAMPLES = Path(__file__).parents[2] / "examples"
GOLDEN = Path(__file__).parents[1] / "data" / "golden"

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


def _problems(change):
    """The located problems of BASE after ``change(data)``, without the source prefix."""
    data = copy.deepcopy(BASE)
    change(data)
    with pytest.raises(ScenarioError) as info:
        parse_scenario(data, "scene.toml")
    assert all(p.startswith("scene.toml: ") for p in info.value.problems)
    return [p.removeprefix("scene.toml: ") for p in info.value.problems]


def _set(table, key, value, index=0):
    def change(data):
        where = data[table][index] if isinstance(data[table], list) else data[table]
        where[key] = value

    return change


def _refused(cli, *args):
    """Run the CLI; it must exit 2 with only error lines on stderr and nothing on stdout."""
    code, out, err = cli(*args)
    assert code == 2, (out, err)
    assert out == ""
    lines = err.splitlines()
    assert lines and all(line.startswith("targetacq: error: ") for line in lines), err
    assert "Traceback" not in err
    return lines


# -- physical domains and finite numbers ---------------------------------------------------------


@pytest.mark.parametrize(
    ("change", "location", "match"),
    [
        (_set("sensors", "pitch", "1e400 um"), "sensors[0].pitch", "finite"),
        (_set("targets", "temperature", "-5 K"), "targets[0].temperature", r"\(0, 10000\] K"),
        (_set("targets", "temperature", "0 K"), "targets[0].temperature", r"\(0, 10000\] K"),
        (_set("targets", "temperature", "1e5 K"), "targets[0].temperature", "got 100000 K"),
        (_set("background", "temperature", "-300 degC"), "background.temperature", "got -26"),
        (_set("sensors", "netd_temperature", "-1 K"), "sensors[0].netd_temperature", "10000"),
        (_set("sensors", "netd", "-50 mK"), "sensors[0].netd", r"\[0, 10000\] K"),
        (_set("background", "clutter_std", "1e6 K"), "background.clutter_std", "10000"),
        (_set("targets", "heading", "400 deg"), "targets[0].heading", r"\[-360, 360\] deg"),
    ],
)
def test_quantities_outside_their_domain_are_located(change, location, match):
    problems = _problems(change)
    assert len(problems) == 1
    assert problems[0].startswith(f"{location}: ")
    assert re.search(match, problems[0]), problems[0]


def test_angles_of_pointing_within_their_range():
    def pointing(azimuth, depression):
        def change(data):
            sensor = data["sensors"][0]
            sensor.pop("look_at")
            sensor.update(azimuth=azimuth, depression=depression)

        return change

    (message,) = _problems(pointing("0 deg", "720 deg"))
    assert message == "sensors[0].depression: depression must be in [-90, 90] deg; got 720 deg"
    (message,) = _problems(pointing("361 deg", "10 deg"))
    assert message.startswith("sensors[0].azimuth: azimuth must be in [-360, 360] deg")
    edge = copy.deepcopy(BASE)
    pointing("-360 deg", "-90 deg")(edge)
    scenario = parse_scenario(edge)
    assert scenario.sensors[0].depression == pytest.approx(-math.pi / 2)


def test_the_temperature_domain_is_the_one_of_limits():
    at_edge = Target(name="t", dimensions=(1, 1, 1), position=(0, 0, 0), temperature=1e4)
    assert at_edge.temperature == limits.MAX_TEMPERATURE
    with pytest.raises(ValueError, match="temperature"):
        Target(name="t", dimensions=(1, 1, 1), position=(0, 0, 0), temperature=1e4 * (1 + 1e-12))


@pytest.mark.parametrize("bad", [math.inf, -math.inf, math.nan])
@pytest.mark.parametrize(
    ("model", "field", "valid"),
    [
        (
            Sensor,
            "pitch",
            {"name": "s", "band": "lwir", "focal_length": 0.1, "position": (0, 0, 0)},
        ),
        (Sensor, "f_number", {"name": "s", "band": "lwir", "pitch": 1e-5, "focal_length": 0.1}),
        (Target, "temperature", {"name": "t", "dimensions": (1, 1, 1), "position": (0, 0, 0)}),
        (Target, "emissivity", {"name": "t", "dimensions": (1, 1, 1), "position": (0, 0, 0)}),
        (Target, "visible_fraction", {"name": "t", "dimensions": (1, 1, 1), "position": (0, 0, 0)}),
        (Target, "heading", {"name": "t", "dimensions": (1, 1, 1), "position": (0, 0, 0)}),
    ],
)
def test_python_si_numbers_must_be_finite(model, field, valid, bad):
    fields = {"position": (0, 0, 0), **valid, field: bad}
    with pytest.raises(ValueError, match=field) as info:
        model(**fields)
    assert info.value.errors()[0]["loc"][0] == field


# -- lengths and coordinates within ±limits.MAX_LENGTH ---------------------------------------------


def _put(path, value):
    """A change setting ``value`` at a path of keys and indices in a scenario dictionary."""

    def change(data):
        where = data
        for key in path[:-1]:
            where = where.setdefault(key, {}) if isinstance(key, str) else where[key]
        where[path[-1]] = value

    return change


CLOUD = {"center": ["1 km", "0 m", "0 m"], "radius": "5 m", "extinction": "1 /km"}


@pytest.mark.parametrize(
    ("change", "expected"),
    [
        (
            _put(["sensors", 0, "position", 1], "-6.56e193 m"),
            "sensors[0].position: coordinates must be within ±1e+09 m; got -6.56e+193 m",
        ),
        (
            _put(["sensors", 0, "look_at", 2], "-1.5e9 m"),
            "sensors[0].look_at: coordinates must be within ±1e+09 m; got -1.5e+09 m",
        ),
        (
            _put(["targets", 0, "position"], "0 0 2e6 km"),
            "targets[0].position: coordinates must be within ±1e+09 m; got 2e+09 m",
        ),
        (
            _put(["targets", 0, "dimensions", 0], "1e12 m"),
            "targets[0].dimensions[0]: dimensions must be within ±1e+09 m; got 1e+12 m",
        ),
        (
            _put(["sensors", 0, "focal_length"], "1e10 m"),
            "sensors[0].focal_length: focal_length must be within ±1e+09 m; got 1e+10 m",
        ),
        (
            _put(["atmosphere", "segments"], [{"length": "1e10 km", "extinction": "1 /km"}]),
            "atmosphere.segments[0].length: length must be within ±1e+09 m; got 1e+13 m",
        ),
        (
            _put(["atmosphere", "clouds"], [{**CLOUD, "center": ["1e10 m", "0 m", "0 m"]}]),
            "atmosphere.clouds[0].center: coordinates must be within ±1e+09 m; got 1e+10 m",
        ),
        (
            _put(["atmosphere", "clouds"], [{**CLOUD, "radius": "2e9 m"}]),
            "atmosphere.clouds[0].radius: radius must be within ±1e+09 m; got 2e+09 m",
        ),
    ],
)
def test_lengths_and_coordinates_beyond_a_million_kilometres_are_refused(change, expected):
    assert _problems(change) == [expected]


def test_lengths_and_coordinates_at_the_limit_are_accepted():
    data = copy.deepcopy(BASE)
    data["targets"][0]["position"] = ["1e6 km", "-1e9 m", "0 m"]
    data["sensors"][0]["look_at"] = ["1e6 km", "-1e9 m", "0 m"]
    data["targets"][0]["dimensions"] = ["1e9 m", "2.5 m", "3 m"]
    # Accepted, and warned: no target is a million kilometres long.
    with pytest.warns(
        PlausibilityWarning, match=r"targets\[0\]\.dimensions\[0\]: 1e\+09 m is 500 m"
    ):
        parse_scenario(data)


@pytest.mark.parametrize(
    ("name", "path", "value", "expected"),
    [
        # Found by a fuzzer: the geometry's rho * rho overflowed, validate said valid and
        # evaluate gave probability 0.
        (
            "uav_haze.toml",
            ["sensors", 0, "waypoints", 1, "position", 1],
            "-6.5642221016625684e+193 m",
            "sensors[0].waypoints[1].position: coordinates must be within ±1e+09 m; "
            "got -6.56e+193 m",
        ),
        (
            "two_sensors_fused.toml",
            ["sensors", 1, "look_at", 1],
            "2.7418797852402033e+178 m",
            "sensors[1].look_at: coordinates must be within ±1e+09 m; got 2.74e+178 m",
        ),
        (
            "ground_observer_aircraft.toml",
            ["sensors", 0, "position", 2],
            "4.282954151089434e+284 m",
            "sensors[0].position: coordinates must be within ±1e+09 m; got 4.28e+284 m",
        ),
    ],
)
def test_huge_coordinates_in_the_examples_are_refused(cli, tmp_path, name, path, value, expected):
    text = (EXAMPLES / name).read_text(encoding="utf-8")
    data = tomllib.loads(text)
    _put(path, value)(data)
    assert "e+" in value and value.replace(" m", "") not in text
    scene = tmp_path / name
    scene.write_text(_toml(data), encoding="utf-8")
    with pytest.raises(ScenarioError) as info:
        load_scenario(scene)
    assert info.value.problems == (f"{scene}: {expected}",)
    (line,) = _refused(cli, "validate", str(scene))
    assert line == f"targetacq: error: {scene}: {expected}"


def _toml(data, prefix=""):
    """A scenario dictionary as TOML (strings, numbers, flags, lists and tables only)."""

    def value(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return json.dumps(v)
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        if isinstance(v, dict):
            return "{" + ", ".join(f"{k} = {value(x)}" for k, x in v.items()) + "}"
        return repr(v)

    lines = []
    tables = []
    for key, item in data.items():
        if isinstance(item, dict):
            tables.append((key, item))
        elif isinstance(item, list) and item and all(isinstance(x, dict) for x in item):
            tables.extend((key, [x]) for x in item)
        else:
            lines.append(f"{key} = {value(item)}")
    for key, item in tables:
        name = f"{prefix}{key}"
        if isinstance(item, list):
            lines += ["", f"[[{name}]]", _toml(item[0], name + ".")]
        else:
            lines += ["", f"[{name}]", _toml(item, name + ".")]
    return "\n".join(lines)


# -- projection and pixel counts -------------------------------------------------------------------


def test_projection_with_a_pitch_or_an_ifov_is_refused_as_the_cli_refuses_it():
    problems = _problems(_set("sensors", "projection", "rectilinear"))
    assert problems == ["sensors[0]: projection applies to hfov and pixels"]

    def with_ifov(data):
        sensor = data["sensors"][0]
        del sensor["pitch"], sensor["focal_length"]
        sensor.update(ifov="0.2 mrad", projection="angular")

    assert _problems(with_ifov) == ["sensors[0]: projection applies to hfov and pixels"]


def test_projection_with_hfov_round_trips_and_defaults_to_angular():
    def sensor(**given):
        return Sensor(
            name="ir", band="lwir", hfov="12 deg", pixels=[640, 512], position="0 0 1 m", **given
        )

    plain, rectilinear = sensor(), sensor(projection="rectilinear")
    assert plain.projection is None and plain.fov_projection == "angular"
    assert sensor(projection="angular").pixel_ifov == plain.pixel_ifov
    assert rectilinear.pixel_ifov > plain.pixel_ifov
    for each in (plain, rectilinear):
        assert Sensor.model_validate(each.model_dump()) == each
    with pytest.raises(ValueError, match="projection"):
        sensor(projection="fisheye")


@pytest.mark.parametrize(
    ("change", "expected"),
    [
        (
            _set("sensors", "pixels", [2**64, 512]),
            "sensors[0].pixels[0]: pixels must be a whole number in [1, 1.1e+12]; got a number "
            "of 20 digits",
        ),
        (
            _set("sensors", "pixels", [640, 2**40 + 1]),
            "sensors[0].pixels[1]: pixels must be a whole number in [1, 1.1e+12]; got "
            "1099511627777",
        ),
    ],
)
def test_pixel_counts_beyond_the_element_limit_are_refused(change, expected):
    assert _problems(change) == [expected]


def test_image_box_entries_beyond_the_element_limit_are_refused():
    data = copy.deepcopy(BASE)
    data["background"] = {"temperature": "295 K", "image": "camera.png"}
    data["targets"][0]["image_box"] = [0, 2**64, 3, 4]
    with pytest.raises(ScenarioError) as info:
        parse_scenario(data, "scene.toml")
    assert info.value.problems == (
        "scene.toml: targets[0].image_box[1]: image_box must be a whole number in [0, 1.1e+12]; "
        "got a number of 20 digits",
    )
    data["targets"][0]["image_box"] = [0, 0, 2**40, 2**40]
    parse_scenario(data)  # as large as any result may be; the image is checked when compiled


# -- strict types ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("change", "expected"),
    [
        (
            _set("targets", "moving", "yes"),
            'targets[0].moving: moving must be true or false (without quotes); got "yes"',
        ),
        (
            _set("targets", "hot_spot", 1),
            "targets[0].hot_spot: hot_spot must be true or false (without quotes); got 1",
        ),
        (
            _set("sensors", "pixels", ["640", 512]),
            'sensors[0].pixels[0]: pixels must hold whole numbers; got "640"',
        ),
        (
            _set("sensors", "pixels", [640.0, 512]),
            "sensors[0].pixels[0]: pixels must hold whole numbers; got 640.0",
        ),
        (_set("sensors", "pixels", [0, 512]), "sensors[0].pixels[0]: must be > 0; got 0"),
        (
            _set("targets", "emissivity", "0.9"),
            'targets[0].emissivity: emissivity must be a number (without quotes); got "0.9"',
        ),
        (_set("targets", "emissivity", True), "targets[0].emissivity: emissivity must be a number"),
        (_set("sensors", "name", ""), 'sensors[0].name: name must be a non-empty text; got ""'),
        (_set("targets", "name", "  "), "targets[0].name: name must be a non-empty text"),
        (_set("targets", "name", 5), "targets[0].name: name must be a non-empty text; got 5"),
        (_set("sensors", "band", 8), "sensors[0].band: must be text in quotes; got 8"),
        (_set("background", "clutter", "mid"), "background.clutter: must be 'low', 'medium' or"),
        (_set("targets", "dimensions", ["1 m", "1 m"]), "targets[0].dimensions[2]: missing item"),
    ],
)
def test_strict_types_in_the_files_words(change, expected):
    problems = _problems(change)
    assert problems[0].startswith(expected), problems
    assert not any("=True" in p or "Input should" in p for p in problems)


def test_whole_numbers_for_image_boxes():
    data = copy.deepcopy(BASE)
    data["background"] = {"temperature": "295 K", "image": "camera.png"}
    data["targets"][0]["image_box"] = [1, 2, 3.5, 4]
    with pytest.raises(ScenarioError, match=r"targets\[0\]\.image_box\[2\]: .*whole numbers"):
        parse_scenario(data)
    data["targets"][0]["image_box"] = [-1, 2, 3, 4]
    with pytest.raises(ScenarioError, match=r"targets\[0\]: image_box is \[x, y, width, height\]"):
        parse_scenario(data)


# -- contradictions and combinations evaluate rejects ----------------------------------------------


def _without_look_at(data):
    data["sensors"][0].pop("look_at")


@pytest.mark.parametrize(
    ("change", "match"),
    [
        (
            lambda d: d["background"].update(emissivity=0.9, material="vegetation"),
            r"^background: give emissivity or material, not both",
        ),
        (
            _set("sensors", "look_at", ["0 m", "0 m", "10 m"]),
            r"^sensors\[0\]: look_at is the sensor's own position",
        ),
        (
            lambda d: (
                d["sensors"][0].update(
                    position=None,
                    waypoints=[
                        {"time": "0 s", "position": ["0 m", "0 m", "10 m"]},
                        {"time": "10 s", "position": ["4 km", "0 m", "10 m"]},
                    ],
                    look_at=["2 km", "0 m", "10 m"],  # half-way along its own path
                )
                or d["sensors"][0].pop("position")
            ),
            r"^sensors\[0\]: look_at .*cannot look at itself",
        ),
        (
            _set("targets", "criterion", "en62676-4"),
            r"^targets\[0\]\.criterion: criterion 'en62676-4' gives pixel-density thresholds",
        ),
        (
            _set("targets", "criterion", "schmieder-weathersby"),
            r"^targets\[0\]\.criterion: .*has no N50 for recognition, identification",
        ),
        (
            lambda d: d.update(model={"criterion": "en62676-4"}),
            r"^model: criterion 'en62676-4' gives pixel-density thresholds",
        ),
        (
            lambda d: d.update(model={"transform": "schmieder-weathersby"}),
            r"^model\.transform: .*detection in clutter only.*give the clutter in \[background\]",
        ),
        (
            lambda d: d.update(model={"transform": "schmieder-weathersby-observed"}),
            r"^model\.transform: .*detection in clutter only",
        ),
        (
            lambda d: d.update(model={"bound": "pessimistic"}),
            r'^model: bound is an option of transform = "c2nveo"',
        ),
        (
            lambda d: d.update(model={"n50": [8, 4, 1]}),
            r"^model: n50 = \[detection, recognition, identification\] must not decrease",
        ),
        (
            _set("background", "channel", "red"),
            r"^background: channel picks the channel of background.image",
        ),
        (
            _set("targets", "image_box", [0, 0, 4, 4]),
            r"^targets\[0\]\.image_box: an image_box is a box in background.image",
        ),
        (
            lambda d: d.update(atmosphere={"visibility_convention": "mor"}),
            r"^atmosphere: visibility_convention goes with visibility",
        ),
        (
            _set("sensors", "aperture", "5 um"),  # below 1.22 wavelengths in the LWIR
            r"^sensors\[0\]: aperture must be at least 1\.22 × wavelength",
        ),
        (
            lambda d: d["background"].update(irradiance="-1 W/m^2"),
            r"^background: irradiance must be >= 0",
        ),
        (
            lambda d: (
                d["sensors"][0].update(
                    pitch=None, focal_length=None, hfov="170 deg", pixels=[100, 200]
                )
                or [d["sensors"][0].pop(k) for k in ("pitch", "focal_length")]
            ),
            r"field of view must be < 180 degrees",
        ),
    ],
)
def test_contradictions_are_refused(change, match):
    problems = _problems(change)
    assert any(re.search(match, p) for p in problems), problems
    assert not any("=True" in p or "hot_spot=" in p for p in problems)


def test_combinations_that_run_are_kept():
    data = copy.deepcopy(BASE)
    data["model"] = {"criterion": "en62676-4", "n50": [1, 4, 6.4]}  # the N50s replace it
    data["targets"][0]["criterion"] = "johnson-truck"
    data["model"]["transform"] = "ttpf"
    scenario = parse_scenario(data)
    ds = ModelChain(scenario).evaluate().dataset
    assert 0.0 <= float(ds["fused_detection"].max()) <= 1.0
    data["model"] = {"transform": "c2nveo", "bound": "pessimistic", "n50": [1, 1, 1]}
    assert parse_scenario(data).model.bound == "pessimistic"


def test_every_problem_is_reported_and_located():
    def change(data):
        data["sensors"][0]["pitch"] = 17  # no unit
        data["targets"][0]["moving"] = "yes"
        data["time"] = {"step": "-1 s"}
        data["atmosphere"] = {"extinction": "1e400 /km"}

    problems = _problems(change)
    assert [p.split(":")[0] for p in problems] == [
        "sensors[0].pitch",
        "targets[0].moving",
        "atmosphere.extinction",
        "time",
    ]
    data = copy.deepcopy(BASE)
    change(data)
    with pytest.raises(ScenarioError) as info:
        parse_scenario(data, "scene.toml")
    assert str(info.value) == info.value.problems[0] + " (and 3 more problems)"


def test_problems_across_tables_are_all_listed():
    def change(data):
        data["targets"].append({**data["targets"][0], "name": "jeep"})
        for target in data["targets"]:
            target.pop("temperature")
        data["background"].pop("temperature")

    assert _problems(change) == [
        "background.temperature: missing: background.temperature is needed for thermal sensors",
        "targets[0].temperature: thermal sensors need a temperature (or a signature_table) "
        "for every target",
        "targets[1].temperature: thermal sensors need a temperature (or a signature_table) "
        "for every target",
    ]


def test_the_cli_prints_every_problem_with_its_file(cli, tmp_path):
    scene = tmp_path / "scene.toml"
    scene.write_text(
        '[[sensors]]\nname = ""\nband = "lwir"\nifov = "0.2 mrad"\n'
        'position = ["0 m", "0 m", "1 m"]\n'
        '[[targets]]\nname = "t"\ndimensions = ["1 m", "1 m", "1 m"]\ntemperature = "-5 K"\n'
        'moving = "yes"\nposition = ["1 km", "0 m", "0 m"]\n'
        '[background]\ntemperature = "290 K"\n'
    )
    lines = _refused(cli, "validate", str(scene))
    assert lines == [
        f'targetacq: error: {scene}: sensors[0].name: name must be a non-empty text; got ""',
        f"targetacq: error: {scene}: targets[0].temperature: temperature must be in "
        "(0, 10000] K; got -5 K",
        f"targetacq: error: {scene}: targets[0].moving: moving must be true or false "
        '(without quotes); got "yes"',
    ]
    (line,) = _refused(cli, "evaluate", str(scene))
    assert line == lines[0] + " (and 2 more problems)"


# -- files the scenario names: validate finds what evaluate would ---------------------------------


def _image_scene(tmp_path, image="camera.png", boxes=((412, 118, 20, 20), (228, 470, 24, 24))):
    text = (GOLDEN / "image.toml").read_text().replace('"../camera.png"', f'"{image}"')
    for old, new in zip(((412, 118, 20, 20), (228, 470, 24, 24)), boxes, strict=True):
        text = text.replace(str(list(old)), str(list(new)))
    shutil.copy(GOLDEN.parent / "camera.png", tmp_path / "camera.png")
    scene = tmp_path / "image.toml"
    scene.write_text(text)
    return scene


def _terrain_scene(tmp_path, rows):
    (tmp_path / "map.csv").write_text(rows)
    scene = tmp_path / "terrain.toml"
    shutil.copy(GOLDEN / "terrain.toml", scene)
    return scene


def _agree(cli, scene, *expected):
    """validate lists every expected problem (in order), evaluate stops on the first: both
    located in the scenario file."""
    lines = _refused(cli, "validate", str(scene))
    assert len(lines) == len(expected), lines
    for line, pattern in zip(lines, expected, strict=True):
        assert re.search(f"^targetacq: error: {re.escape(str(scene))}: {pattern}", line), line
    (first,) = _refused(cli, "evaluate", str(scene))
    assert first.startswith(lines[0])
    assert check_runnable(load_scenario(scene))  # the same check from Python


def test_the_bundled_files_are_runnable(tmp_path):
    for scene in (_image_scene(tmp_path), GOLDEN / "terrain.toml", *EXAMPLES.glob("*.toml")):
        assert check_runnable(load_scenario(scene)) == []


def test_missing_and_unreadable_images(cli, tmp_path):
    _agree(cli, _image_scene(tmp_path, "none.png"), r"background\.image: no image file .*none")
    (tmp_path / "text.png").write_text("not an image")
    _agree(cli, _image_scene(tmp_path, "text.png"), r"background\.image: cannot read .*text")
    (tmp_path / "folder.png").mkdir()
    _agree(cli, _image_scene(tmp_path, "folder.png"), r"background\.image: .*is a directory")


def test_boxes_outside_the_image_are_each_located(cli, tmp_path):
    scene = _image_scene(tmp_path, boxes=((600, 118, 20, 20), (228, 470, 24, 400)))
    _agree(
        cli,
        scene,
        r"targets\[0\]\.image_box: box \(600, 118, 20, 20\) leaves the 512 x 512 image",
        r"targets\[1\]\.image_box: box \(228, 470, 24, 400\) leaves the 512 x 512 image",
    )


def test_a_colour_image_needs_a_channel(cli, tmp_path):
    from PIL import Image

    scene = _image_scene(tmp_path)
    Image.new("RGB", (512, 512), (10, 200, 30)).save(tmp_path / "camera.png")
    _agree(cli, scene, r"background\.channel: a colour image needs a channel")


@pytest.mark.parametrize(
    ("rows", "match"),
    [
        ("0,0,1,1\n0,5,1,1\n", r"class index 5 at row 2, column 2 names none of the 2 classes"),
        ("0,0,1,1\n0,-1,1,1\n", r"class index -1 at row 2, column 2"),
        ("0,0.5,1,1\n", r"not a CSV map of whole class indices"),
        ("0,0,1\n0,1\n", r"not a CSV map of whole class indices"),
        ("", r"the terrain map is empty"),
        (" \n\n", r"the terrain map is empty"),
    ],
)
def test_bad_terrain_maps(cli, tmp_path, rows, match):
    _agree(cli, _terrain_scene(tmp_path, rows), r"background\.terrain\.map: .*" + match)


def test_utf8_bom_in_a_terrain_map_and_a_scenario(tmp_path):
    plain = (GOLDEN / "map.csv").read_text()
    scene = _terrain_scene(tmp_path, plain)
    reference = ModelChain(load_scenario(scene)).evaluate().dataset
    (tmp_path / "map.csv").write_bytes(b"\xef\xbb\xbf" + plain.encode())
    scene.write_bytes(b"\xef\xbb\xbf" + scene.read_bytes())
    with_bom = ModelChain(load_scenario(scene)).evaluate().dataset
    np.testing.assert_array_equal(with_bom["scr"].values, reference["scr"].values)
    np.testing.assert_array_equal(with_bom["fused_detection"], reference["fused_detection"])


def test_evaluate_errors_from_python_are_located(tmp_path):
    scenario = load_scenario(_image_scene(tmp_path, "none.png"))
    with pytest.raises(ScenarioError, match=r"^background\.image: no image file") as info:
        ModelChain(scenario)
    assert info.value.in_file("x.toml").problems == (f"x.toml: {info.value.problems[0]}",)


# -- sizes -------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("start", "stop", "step", "count"),
    [(0.0, 0.0, 1.0, 1), (0.0, 120.0, 10.0, 13), (5.0, 6.0, 0.25, 5), (0.0, 0.3, 0.1, 4)],
)
def test_time_grid_counts_without_building(start, stop, step, count):
    grid = TimeGrid(start=start, stop=stop, step=step)
    assert grid.count == count
    assert grid.times().size == count


def test_a_time_grid_too_large_is_refused_before_allocating(cli, tmp_path):
    grid = TimeGrid(start=0.0, stop=600.0, step=1e-9)
    assert grid.count == 600e9 + 1
    with pytest.raises(ValueError, match=r"use a longer time\.step or a shorter span"):
        grid.times()
    assert TimeGrid(start=-1e308, stop=1e308, step=1e-300).count == math.inf
    scene = tmp_path / "scene.toml"
    scene.write_text(
        (EXAMPLES / "uav_haze.toml").read_text().replace('step = "10 s"', 'step = "1 ns"')
    )
    (line,) = _refused(cli, "validate", str(scene))
    assert re.search(
        r"time\.step: evaluating 1\.2e\+11 times .* x 1 sensor\(s\) x 3 target\(s\) needs about "
        r".* use a longer time\.step",
        line,
    ), line
    (again,) = _refused(cli, "evaluate", str(scene))
    assert again == line


def test_simulate_refuses_sizes_and_seeds_clearly(cli, capsys, monkeypatch):
    scene = str(EXAMPLES / "two_sensors_fused.toml")
    (line,) = _refused(cli, "simulate", scene, "--duration", "1e9s", "--step", "0.1s")
    assert "use fewer --runs, a longer --step or a shorter --duration" in line
    monkeypatch.setattr(limits, "available_memory", lambda: 2**30)
    (line,) = _refused(cli, "simulate", scene, "--runs", "1000000000")
    assert re.search(r"1000000000 runs x 4 pair\(s\) needs about .* use fewer --runs", line)
    monkeypatch.undo()
    for seed in (str(2**128), "-1", str(10**60)):
        (line,) = _refused(cli, "simulate", scene, "--seed", seed, "--runs", "2")
        assert line == (
            f"targetacq: error: --seed must be an integer in [0, 2**128 - 1]; got {seed}"
        )
    code, _, _ = cli("simulate", scene, "--seed", str(2**128 - 1), "--runs", "2")
    assert code == 0


def test_simulate_and_stream_keys_from_python(monkeypatch):
    chain = ModelChain(load_scenario(EXAMPLES / "two_sensors_fused.toml"))
    with pytest.raises(ValueError, match=r"seed must be an integer in \[0, 2\*\*128 - 1\]"):
        simulate(chain, 10.0, 1.0, runs=2, seed=2**128)
    monkeypatch.setattr(limits, "available_memory", lambda: 2**30)
    with pytest.raises(ValueError, match="use fewer runs, a longer step or a shorter duration"):
        simulate(chain, 10.0, 1.0, runs=10**9)
    with pytest.raises(ValueError, match="use fewer runs"):
        simulate(chain, 1e300, 1e-300)
    assert stream_key(2**128 - 1, "a") != stream_key(0, "a")
    for seed in (2**128, -1, 1.0, True):
        with pytest.raises(ValueError, match="seed must be an integer"):
            stream_key(seed, "a")
    assert simulate(chain, 2.0, 1.0, runs=2, seed=np.uint64(3)).fused["detection"].shape == (2, 2)


# -- the scenario file itself ---------------------------------------------------------------------


def test_utf8_bom_in_a_scenario_file(tmp_path):
    text = (EXAMPLES / "uav_haze.toml").read_bytes()
    scene = tmp_path / "bom.toml"
    scene.write_bytes(b"\xef\xbb\xbf" + text)
    assert load_scenario(scene) == load_scenario(EXAMPLES / "uav_haze.toml")


def test_oversized_scenario_file(cli, tmp_path):
    scene = tmp_path / "big.toml"
    text = (EXAMPLES / "uav_haze.toml").read_text()
    scene.write_text(text + "#" * (limits.MAX_INPUT_BYTES + 2_300_000 - len(text)) + "\n")
    (line,) = _refused(cli, "validate", str(scene))
    assert line == (f"targetacq: error: {scene}: scenario files are limited to 10 MB; got 12.3 MB")


def test_deeply_nested_toml(cli, tmp_path):
    scene = tmp_path / "deep.toml"
    scene.write_text("a = " + "[" * 5000 + "]" * 5000 + "\n")
    (line,) = _refused(cli, "validate", str(scene))
    assert line == f"targetacq: error: {scene}: malformed TOML: nested too deeply"
    with pytest.raises(ScenarioError, match="nested too deeply"):
        load_scenario(scene)


def test_directories_devices_and_fifos(cli, tmp_path):
    (line,) = _refused(cli, "validate", str(tmp_path))
    assert line.endswith(f"{tmp_path}: is a directory, not a scenario file")
    (line,) = _refused(cli, "validate", "/dev/null")
    assert line.endswith(
        "/dev/null: not a regular file (a device, a fifo or a socket), so not a scenario file"
    )
    fifo = tmp_path / "fifo.toml"
    os.mkfifo(fifo)  # opening it would block: it must be refused without being opened
    (line,) = _refused(cli, "evaluate", str(fifo))
    assert "not a regular file" in line
    (line,) = _refused(cli, "validate", str(tmp_path / "none.toml"))
    assert line.endswith(
        "no scenario file " + repr(str(tmp_path / "none.toml")) + " (no such file)"
    )


def test_unreadable_scenario_file(cli, tmp_path, monkeypatch):
    scene = tmp_path / "scene.toml"
    shutil.copy(EXAMPLES / "uav_haze.toml", scene)
    # As the operating system answers for a file without read permission (root reads anyway).
    monkeypatch.setattr(os, "access", lambda path, mode: False)
    (line,) = _refused(cli, "validate", str(scene))
    assert line == f"targetacq: error: {scene}: cannot read the scenario file: permission denied"


def test_not_utf8(cli, tmp_path):
    scene = tmp_path / "latin1.toml"
    scene.write_bytes('name = "café"\n'.encode("latin-1"))
    (line,) = _refused(cli, "validate", str(scene))
    assert line == (
        f"targetacq: error: {scene}: not UTF-8 text (byte 12 is 0xe9), so not a scenario file"
    )


def test_round_trip_still_holds_with_the_strict_types():
    for path in EXAMPLES.glob("*.toml"):
        scenario = load_scenario(path)
        assert Scenario.model_validate(scenario.model_dump()) == scenario
        assert compile_scenario(scenario).scene.targets.names


def test_a_target_at_the_sensor_on_a_terrain_map_runs(tmp_path):
    # Range 0: the pixel footprint is 0, the limit of a fine one (the classes' own variance).
    from targetacq.physics.terrain import resolution_variance

    assert float(resolution_variance(4.0, 0.5, 0.0)) == 4.0
    assert float(resolution_variance(4.0, 0.5, 1e-12)) == 4.0
    assert float(resolution_variance(4.0, 0.5, 2.0)) == pytest.approx(4.0 * 0.25**2)
    text = (GOLDEN / "terrain.toml").read_text()
    text = text.replace('position = ["1 km", "0 m", "0 m"]', 'position = ["0 m", "0 m", "10 m"]')
    scene = tmp_path / "terrain.toml"
    scene.write_text(text)
    shutil.copy(GOLDEN / "map.csv", tmp_path / "map.csv")
    ds = ModelChain(load_scenario(scene)).evaluate().dataset
    p = ds["detection"].values
    assert np.all((p >= 0) & (p <= 1))
