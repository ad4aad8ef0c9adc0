"""``targetacq dri SCENARIO``: every sensor type's ranges through the core (issue 24, item 1).

Expected values come from the property that a DRI range is where the core, evaluated with the
target moved to that range along its start bearing, gives the asked probability; and from the
definition of what the line of ranges leaves out (false targets) or takes in (a terrain map).
"""

from __future__ import annotations

import dataclasses
import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from targetacq.cli import main
from targetacq.core.compile import scenario_positions
from targetacq.core.evaluation import evaluate, factors, footprint_scr, probabilities
from targetacq.run.model_chain import ModelChain
from targetacq.scenario.schema import load_scenario

GOLDEN = Path(__file__).parents[1] / "data" / "golden"
BEARING = math.radians(60.0)  # from north, clockwise
HEIGHT = 2.0  # sensors and target at one height [m]

POINTED = f"""
[[sensors]]
name = "ir"
type = "thermal"
band = "lwir"
pixels = [640, 512]
pitch = "17 um"
focal_length = "50 mm"
position = ["0 m", "0 m", "{HEIGHT} m"]
azimuth = "60 deg"
depression = "0 deg"

[[sensors]]
name = "tv"
type = "tv"
pixels = [1920, 1080]
hfov = "4 deg"
nec = 0.01
position = ["0 m", "0 m", "{HEIGHT} m"]
azimuth = "60 deg"
depression = "0 deg"

[[targets]]
name = "truck"
dimensions = ["7 m", "2.5 m", "3 m"]
temperature = "300 K"
reflectance = 0.2
position = ["{3e3 * math.sin(BEARING)} m", "{3e3 * math.cos(BEARING)} m", "{HEIGHT} m"]

[background]
temperature = "299 K"
reflectance = 0.1
irradiance = "300 W/m^2"

[atmosphere]
extinction = "0.3 /km"
"""

FALSE_TARGETS = '\n[false_targets]\ndensity = "50 /km^2"\nprobability = 0.05\nmax_range = "5 km"\n'


def _dri(capsys: pytest.CaptureFixture[str], path: Path, probability: str) -> list[dict]:
    with pytest.raises(SystemExit) as done:
        main(["dri", str(path), "--probability", probability, "--format", "json"])
    out, err = capsys.readouterr()
    assert done.value.code == 0, err
    return json.loads(out)["ranges"]


def _along(chain: ModelChain, sensor: int, target: int, slant: float) -> np.ndarray:
    """The target's position at ``slant`` from the sensor along its start bearing, its height
    kept (computed here from the scenario's start positions)."""
    s_pos, t_pos, _ = scenario_positions(chain.scenario, [chain.scenario.time.start])
    s, g = s_pos[sensor, 0], t_pos[target, 0]
    east, north = g[0] - s[0], g[1] - s[1]
    flat = math.hypot(east, north)
    ground = math.sqrt(slant**2 - (g[2] - s[2]) ** 2)
    return np.array([s[0] + east / flat * ground, s[1] + north / flat * ground, g[2]])


def _positions(chain: ModelChain, sensor: int, target: int, slant: float):
    """Sensors at their start positions and every target at its start, but ``target`` moved to
    ``slant`` from ``sensor``: ``(n_s, 1, 3)``, ``(n_g, 1, 3)``."""
    s_pos, t_pos, _ = scenario_positions(chain.scenario, [chain.scenario.time.start])
    t_pos = np.array(t_pos)
    t_pos[target, 0] = _along(chain, sensor, target, slant)
    return np.ascontiguousarray(s_pos), t_pos


def test_dri_of_a_pointed_scenario_gives_the_asked_probability(capsys, tmp_path):
    """A geometric thermal sensor and a TV sensor pointed by azimuth and depression: at each
    DRI range the CLI prints, evaluate (the scene's own pointing, the target moved there along
    its bearing, so in view) gives the asked probability."""
    path = tmp_path / "pointed.toml"
    path.write_text(POINTED)
    chain = ModelChain(load_scenario(path))
    scene = chain.compiled.scene
    rows = {name: k for k, name in enumerate(scene.sensors.names)}
    checked = set()
    for entry in _dri(capsys, path, "0.5,0.9"):
        assert entry["range_m"] is not None, entry
        sensor = rows[entry["pair"].split(" → ")[0]]
        found, p = evaluate(scene, *_positions(chain, sensor, 0, entry["range_m"]))
        assert bool(found.in_view[sensor, 0, 0])
        got = float(getattr(p, entry["task"])[sensor, 0, 0])
        assert abs(got - entry["probability"]) < 1e-6, (entry, got)
        checked.add(sensor)
    assert checked == {0, 1}


def test_false_targets_do_not_enter_the_ranges(capsys, tmp_path):
    """A [false_targets] table is a simulation's false detections, not a pair's probability:
    the ranges are those of the same scenario without it."""
    without, with_ = tmp_path / "without.toml", tmp_path / "with.toml"
    without.write_text(POINTED)
    with_.write_text(POINTED + FALSE_TARGETS)
    assert load_scenario(with_).false_targets is not None
    assert _dri(capsys, with_, "0.5") == _dri(capsys, without, "0.5")


def test_a_terrain_map_is_used_around_the_target_where_it_stands(capsys, tmp_path):
    """With a terrain map, the SCR at each DRI range is the map's window at the target's start
    position seen at that range's footprint (footprint_scr): with it, the core gives the asked
    probability at the range, and with the scene's SCR without the map it would not."""
    # The golden terrain scenario with targets of little contrast: an SCR that matters.
    shutil.copy(GOLDEN / "map.csv", tmp_path / "map.csv")
    text = (GOLDEN / "terrain.toml").read_text()
    path = tmp_path / "terrain.toml"
    path.write_text(text.replace('"305 K"', '"292 K"').replace('"300 K"', '"292 K"'))
    chain = ModelChain(load_scenario(path))
    scene, terrain = chain.compiled.scene, chain.compiled.terrain
    assert terrain is not None
    sensors = {name: k for k, name in enumerate(scene.sensors.names)}
    targets = {name: k for k, name in enumerate(scene.targets.names)}
    moved = 0
    for entry in _dri(capsys, path, "0.5"):
        if entry["range_m"] is None:
            continue
        name_s, name_g = entry["pair"].split(" → ")
        s, g = sensors[name_s], targets[name_g]
        s_pos, t_pos = _positions(chain, s, g, entry["range_m"])
        _, start, heading = scenario_positions(chain.scenario, [chain.scenario.time.start])
        found = factors(scene, s_pos, t_pos, heading)  # a moving target's heading at the start
        scr = footprint_scr(
            terrain, found.range, start, scene.signature.target, np.asarray(scene.sensors.ifov)
        )
        on_map = probabilities(scene, dataclasses.replace(found, scr=scr))
        got = float(getattr(on_map, entry["task"])[s, g, 0])
        assert abs(got - entry["probability"]) < 1e-6, (entry, got)
        plain = float(getattr(probabilities(scene, found), entry["task"])[s, g, 0])
        moved += abs(plain - entry["probability"]) > 1e-3
    assert moved >= 3, moved


NEAR_AND_FAR = f"""
[[sensors]]
name = "wide"
type = "tv"
pixels = [640, 480]
hfov = "90 deg"
position = ["0 m", "0 m", "{HEIGHT} m"]

[[sensors]]
name = "tele"
type = "thermal"
band = "lwir"
pixels = [640, 512]
pitch = "12 um"
focal_length = "500 mm"
position = ["0 m", "0 m", "{HEIGHT} m"]

[[targets]]
name = "soldier"
criterion = "johnson-soldier-standing"
dimensions = ["0.5 m", "0.5 m", "1.8 m"]
temperature = "304 K"
reflectance = 0.3
position = ["{3e3 * math.sin(BEARING)} m", "{3e3 * math.cos(BEARING)} m", "{HEIGHT} m"]

[background]
temperature = "293 K"
reflectance = 0.1
irradiance = "300 W/m^2"

[atmosphere]
extinction = "0.01 /km"
"""


def _table(performance) -> dict[tuple[str, str, float], float]:
    return {
        (r["case"], r["task"], r["probability"]): r["range_m"]
        for r in performance.dri.to_dict("records")
    }


def test_a_dri_range_shorter_than_the_curves_first_range_is_found(tmp_path):
    """The curves' grid starts at r_max / 600; a wide TV camera's ranges below it are still
    found (not "not reached"), and equal the analyst's range solve of the same level pair (the
    outline is the same from every range of a level line), an independent bisection."""
    from targetacq.core.pair_ranges import pair_performance
    from targetacq.core.ranges import case_ranges

    path = tmp_path / "near_far.toml"
    path.write_text(NEAR_AND_FAR)
    chain = ModelChain(load_scenario(path))
    r_max = 30e3  # first range of the curves: 50 m
    table = _table(pair_performance(chain, [0, 1], [0.5, 0.9], max_range=r_max))
    case = chain.range_cases()["wide → soldier"]
    below = 0
    for p in (0.5, 0.9):
        expected = case_ranges(case, p)
        for task in ("detection", "recognition", "identification"):
            got = table[("wide → soldier", task, p)]
            assert got == pytest.approx(float(expected[task]), rel=1e-6), (task, p)
            below += got < r_max / 600
    assert below >= 2  # the test reaches below the grid


def test_dri_ranges_do_not_depend_on_how_far_the_curves_go(tmp_path):
    """--max-range sets the curves' axis only: ranges beyond it are still found (were the
    axis's end, "reached"), and the table is the same for any axis."""
    from targetacq.core.pair_ranges import pair_performance

    path = tmp_path / "near_far.toml"
    path.write_text(NEAR_AND_FAR)
    chain = ModelChain(load_scenario(path))
    short = _table(pair_performance(chain, [0, 1], [0.5], max_range=500.0))
    long = _table(pair_performance(chain, [0, 1], [0.5], max_range=40e3))
    assert short.keys() == long.keys()
    for key, value in long.items():
        assert short[key] == pytest.approx(value, rel=1e-9, nan_ok=True), key
    assert max(v for v in long.values() if math.isfinite(v)) > 5e3


def test_an_aircraft_above_the_first_probe_range_warns_nothing():
    """A target higher above the sensor than the first automatic probe (1 km) has no place on
    the line there (NaN): no RuntimeWarning (all-NaN max), and the grid goes on out."""
    from targetacq.core.pair_ranges import pair_performance

    example = Path(__file__).resolve().parents[2] / "examples" / "ground_observer_aircraft.toml"
    chain = ModelChain(load_scenario(example))
    performance = pair_performance(chain, [0], [0.5])  # -W error: a warning fails
    assert float(performance.curves["range"][-1]) > 1e3


def test_curves_a_quarter_beyond_the_farthest_dri_range_search_the_ranges_once(
    tmp_path, monkeypatch
):
    """``beyond_dri``: the table is that of the automatic axis (one search), the curves end at
    1.25 times its farthest finite range, and the core runs as often as for the automatic axis
    alone (the curve pass on the new axis replaces the old one; no second search)."""
    from targetacq.core import pair_ranges

    path = tmp_path / "near_far.toml"
    path.write_text(NEAR_AND_FAR)
    chain = ModelChain(load_scenario(path))
    calls = []
    original = pair_ranges._Pairs.probabilities

    def counted(self, row, slant):
        calls.append(row)
        return original(self, row, slant)

    monkeypatch.setattr(pair_ranges._Pairs, "probabilities", counted)
    plain = pair_ranges.pair_performance(chain, [0, 1], [0.5, 0.9])
    plain_calls = len(calls)
    calls.clear()
    drawn = pair_ranges.pair_performance(chain, [0, 1], [0.5, 0.9], beyond_dri=1.25)
    assert _table(drawn) == pytest.approx(_table(plain), nan_ok=True)
    farthest = max(v for v in _table(plain).values() if 0 < v < math.inf)
    assert float(drawn.curves["range"][-1]) == pytest.approx(1.25 * farthest, rel=1e-12)
    assert len(calls) == plain_calls  # the curve pass on the new axis replaces the old one
