"""Colour cameras (§9.4.2): one TV model per band, merged as one look (the best band).

Expected values come from the TV camera of the same scene, computed independently through the
``tv`` sensor type, and from the merging rule's own properties (identical bands give the single
band; a band the target does not differ in adds nothing; independent cameras still fuse by
Eq. (8.4)).
"""

from __future__ import annotations

import copy
import itertools

import numpy as np
import pytest

from targetacq import Simulation, fuse
from targetacq.run.model_chain import ModelChain
from targetacq.scenario.schema import ScenarioError, parse_scenario

TIMES = np.array([0.0, 30.0, 60.0])
CAMERA = {
    "pixels": [1920, 1080],
    "hfov": "6 deg",
    "nec": 0.02,
    "position": ["0 m", "0 m", "10 m"],
}


def _document(sensors: list[dict], reflectance: object, background: object) -> dict:
    return {
        "sensors": sensors,
        "targets": [
            {
                "name": "vehicle",
                "dimensions": ["6 m", "2.5 m", "2.5 m"],
                "reflectance": reflectance,
                "waypoints": [
                    {"time": "0 s", "position": ["9 km", "0 m", "0 m"]},
                    {"time": "60 s", "position": ["2 km", "100 m", "0 m"]},
                ],
            }
        ],
        "background": {"reflectance": background, "irradiance": "400 W/m^2", "clutter": "medium"},
        "atmosphere": {"visibility": "15 km", "visibility_convention": "koschmieder"},
        "time": {"start": "0 s", "stop": "60 s", "step": "30 s"},
    }


def _tv(name: str = "tv") -> dict:
    return {"name": name, "type": "tv", **CAMERA}


def _colour(bands: list[str]) -> dict:
    return {"name": "rgb", "type": "colour", "bands": bands, **CAMERA}


def _run(document: dict) -> _Found:
    chain = ModelChain(parse_scenario(copy.deepcopy(document)))
    return _Found(chain.compute(TIMES))


class _Found:
    def __init__(self, out: dict) -> None:
        self.__dict__.update(out)


def test_three_identical_bands_are_the_single_band() -> None:
    single = _run(_document([_tv()], 0.2, 0.1))
    colour = _run(
        _document(
            [_colour(["red", "green", "blue"])],
            {"red": 0.2, "green": 0.2, "blue": 0.2},
            {"red": 0.1, "green": 0.1, "blue": 0.1},
        )
    )
    assert colour.detection.shape == (3, 1, TIMES.size)  # a row per band
    p_single = single.detection
    assert np.any((p_single > 0.01) & (p_single < 0.99))  # the comparison is not trivial
    for task in ("detection", "recognition", "identification"):
        for band in range(3):
            np.testing.assert_allclose(
                getattr(colour, task)[band], getattr(single, task)[0], rtol=1e-12, atol=1e-15
            )
        np.testing.assert_allclose(
            getattr(colour, "fused_" + task),
            getattr(single, "fused_" + task),
            rtol=1e-12,
            atol=1e-15,
        )
    # The independent-sensor rule would have reported 1 − (1 − p)³.
    p = single.fused_detection
    middle = (p > 0.01) & (p < 0.99)
    assert np.all(colour.fused_detection[middle] < (1 - (1 - p) ** 3)[middle] - 1e-3)


def test_a_target_different_in_one_band_is_found_through_that_band() -> None:
    colour = _run(
        _document(
            [_colour(["red", "green", "blue"])],
            {"red": 0.25, "green": 0.1, "blue": 0.1},
            0.1,  # one background reflectance for every band
        )
    )
    red_alone = _run(_document([_tv()], 0.25, 0.1))
    green, blue = colour.detection[1], colour.detection[2]
    assert np.all(green == 0.0) and np.all(blue == 0.0)  # no contrast, noise: nothing seen
    np.testing.assert_allclose(colour.detection[0], red_alone.detection[0], rtol=1e-12)
    np.testing.assert_allclose(colour.fused_detection, red_alone.fused_detection, rtol=1e-12)
    assert float(colour.fused_detection.max()) > 0.05


def test_a_colour_camera_and_another_sensor_fuse_as_independent() -> None:
    thermal = {"name": "ir", "type": "thermal", "band": "lwir", "ifov": "0.1 mrad"}
    thermal["position"] = CAMERA["position"]
    document = _document([_colour(["red", "green"]), thermal], {"red": 0.3, "green": 0.15}, 0.1)
    document["targets"][0]["temperature"] = "305 K"
    document["background"]["temperature"] = "300 K"
    document["atmosphere"] = {"extinction": "0.2 /km"}
    found = _run(document)
    best = np.maximum(found.detection[0], found.detection[1])
    np.testing.assert_allclose(
        found.fused_detection, fuse(np.stack([best, found.detection[2]]), axis=0), rtol=1e-12
    )


def test_colour_bands_step_together() -> None:
    """Over time the bands of one camera are one look: three identical bands give the events
    of one band (the same draws), never three chances."""
    bands = ["red", "green", "blue"]
    colour = _document([_colour(bands)], dict.fromkeys(bands, 0.2), dict.fromkeys(bands, 0.1))
    single = _document([_tv("rgb")], 0.2, 0.1)
    runs = []
    for document, rows in ((colour, 3), (single, 1)):
        # The draws are under test, not the noise: the thesis's SNR law, under which this
        # contrast through the haze is seen on the way in (the default contrast law hides it).
        document["model"] = {**document.get("model", {}), "snr_law": "sonesson"}
        sim = Simulation.from_scenario(parse_scenario(copy.deepcopy(document)), seed=11)
        assert len(sim.sensors) == rows
        found = []
        target = np.array([[9000.0, 0.0, 0.0]])
        for step, time in enumerate(np.arange(0.0, 200.0, 5.0)):
            target = target - [[150.0, 0.0, 0.0]] if step else target
            out = sim.step(time, 5.0, np.tile([[0.0, 0.0, 10.0]], (rows, 1)), target)
            found += [(e.task, e.time) for e in out.events]
        runs.append(sorted(set(found)))
    assert runs[0] == runs[1]
    assert runs[1]  # something happened


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda d: d["targets"][0].update(reflectance={"red": 0.2}), "band 'green'"),
        (lambda d: d["background"].pop("reflectance"), "background.reflectance"),
        (lambda d: d["sensors"][0].pop("bands"), "needs its bands"),
        (lambda d: d["sensors"][0].update(type="tv"), "bands belongs to"),
    ],
)
def test_colour_scenarios_are_checked(change, message) -> None:
    document = _document(
        [_colour(["red", "green"])], {"red": 0.2, "green": 0.3}, {"red": 0.1, "green": 0.1}
    )
    change(document)
    with pytest.raises(ScenarioError, match=message):
        parse_scenario(document)


@pytest.mark.parametrize(
    ("change", "where"),
    [
        (lambda d: d["targets"][0]["reflectance"].update(uv=0.3), "targets[0].reflectance.uv"),
        (lambda d: d["background"]["reflectance"].update(uv=0.1), "background.reflectance.uv"),
        (
            lambda d: d["background"].update(
                irradiance={"red": "1 W/m^2", "green": "1 W/m^2", "Red": "2 W/m^2"}
            ),
            "background.irradiance.Red",
        ),
    ],
)
def test_a_band_no_colour_camera_has_is_refused_not_ignored(change, where) -> None:
    # A value for band "uv" (or a typo) was accepted and silently unused.
    document = _document(
        [_colour(["red", "green"])], {"red": 0.2, "green": 0.3}, {"red": 0.1, "green": 0.1}
    )
    change(document)
    with pytest.raises(ScenarioError) as error:
        parse_scenario(document)
    (problem,) = error.value.problems
    band = where.rsplit(".", 1)[1]
    assert problem == (
        f"scenario: {where}: {band!r} is not a band of the colour cameras (bands: red, green)"
    )


def test_a_tv_camera_refuses_a_table_of_bands() -> None:
    with pytest.raises(ScenarioError, match="a table of bands is for colour cameras"):
        parse_scenario(_document([_tv()], {"red": 0.2}, 0.1))


def test_detection_rises_with_a_band_contrast() -> None:
    """A property: more contrast in one band (the others matched) never lowers detection."""
    peaks = []
    for red in (0.11, 0.13, 0.16, 0.2, 0.3):
        found = _run(
            _document(
                [_colour(["red", "green"])],
                {"red": red, "green": 0.1},
                {"red": 0.1, "green": 0.1},
            )
        )
        peaks.append(found.fused_detection)
    for lower, higher in itertools.pairwise(peaks):
        assert np.all(higher >= lower) and np.any(higher > lower)


def test_a_colour_camera_needs_its_noise_and_light_in_every_band() -> None:
    document = _document([_colour(["red", "green"])], {"red": 0.1, "green": 0.1}, 0.1)
    document["sensors"][0].pop("nec")
    with pytest.raises(ScenarioError, match=r"sensors\[0\].nec"):
        parse_scenario(document)
    document = _document([_colour(["red", "green"])], {"red": 0.1, "green": 0.1}, 0.1)
    document["background"]["irradiance"] = {"red": "0 W/m^2", "green": "300 W/m^2"}
    with pytest.raises(ScenarioError, match="band 'red' has no background light"):
        parse_scenario(document)


@pytest.mark.parametrize(
    ("reflectance", "message"),
    [
        ({"red": 0.2, "green": 1.5}, r"reflectance.green must be in \[0, 1\]; got 1.5"),
        ({"red": 0.2, "green": "0.3"}, r"reflectance.green must be a number \(without quotes\)"),
        ({}, "a table of bands needs at least one band"),
    ],
)
def test_band_tables_say_which_band_is_wrong(reflectance: dict, message: str) -> None:
    with pytest.raises(ScenarioError) as error:
        parse_scenario(_document([_colour(["red", "green"])], reflectance, 0.1))
    assert len(error.value.problems) == 1 and "function-" not in str(error.value)
    assert error.value.problems[0].startswith("scenario: targets[0].reflectance")
    assert __import__("re").search(message, error.value.problems[0])


def test_the_bands_of_a_camera_take_one_position() -> None:
    bands = ["red", "green"]
    document = _document([_colour(bands)], dict.fromkeys(bands, 0.2), dict.fromkeys(bands, 0.1))
    sim = Simulation.from_scenario(parse_scenario(document), seed=1)
    target = np.array([[3000.0, 0.0, 0.0]])
    with pytest.raises(ValueError, match="rows of colour camera 'rgb'"):
        sim.step(0.0, 1.0, np.array([[0.0, 0.0, 10.0], [0.0, 50.0, 10.0]]), target)
    sim.step(0.0, 1.0, np.array([[0.0, 0.0, 10.0], [0.0, 0.0, 10.0]]), target)


def test_a_colour_camera_beside_a_radar() -> None:
    """A mixed scene: the colour rows are those of the camera alone, the fusion takes the
    best band and the radar as independent."""
    bands = ["red", "green"]
    colour = _document([_colour(bands)], {"red": 0.25, "green": 0.1}, 0.1)
    mixed = copy.deepcopy(colour)
    mixed["sensors"].append(
        {
            "name": "radar",
            "type": "radar",
            "position": ["0 m", "0 m", "10 m"],
            "radar": {
                "power": "1 kW",
                "gain": "30 dB",
                "frequency": "10 GHz",
                "pulse_length": "0.1 us",
                "beamwidth": "1 deg",
            },
        }
    )
    mixed["targets"][0]["rcs"] = "10 m^2"
    mixed["background"]["sigma0"] = "-30 dB"
    alone, both = _run(colour), _run(mixed)
    # To rounding: a scene with a radar takes the core's generic path, the camera alone the
    # NumPy one (equal to about 1e-14, tests/core/test_numpy_paths.py).
    np.testing.assert_allclose(both.detection[:2], alone.detection, rtol=1e-12, atol=1e-16)
    best = np.maximum(both.detection[0], both.detection[1])
    np.testing.assert_allclose(
        both.fused_detection, fuse(np.stack([best, both.detection[2]]), axis=0), rtol=1e-12
    )
