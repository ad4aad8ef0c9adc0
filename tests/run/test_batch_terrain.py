"""The ``[terrain]`` elevation model in the batch runs: ``ModelChain``, ``targetacq evaluate`` and
``targetacq simulate`` trace every (sensor, target, time) line of sight, as the step API does."""

import json

import numpy as np
import pytest

from targetacq import Simulation
from targetacq.core import scenario_positions
from targetacq.run.model_chain import ModelChain
from targetacq.run.search import simulate
from targetacq.scenario.schema import load_scenario

TASKS = ("detection", "recognition", "identification")

SCENE = """
name = "ridge"

[[sensors]]
name = "ir"
band = "lwir"
ifov = "0.25 mrad"
position = ["0 m", "0 m", "10 m"]

[[targets]]
name = "front"
dimensions = ["7 m", "2.5 m", "4 m"]
temperature = "305 K"
position = ["800 m", "-200 m", "0 m"]

[[targets]]
name = "behind"
dimensions = ["7 m", "2.5 m", "4 m"]
temperature = "305 K"
position = ["1500 m", "-200 m", "0 m"]

[[targets]]
name = "partial"
dimensions = ["7 m", "2.5 m", "4 m"]
temperature = "305 K"
visible_fraction = 0.9
position = ["1000 m", "300 m", "0 m"]

[[targets]]
name = "crossing"
dimensions = ["7 m", "2.5 m", "4 m"]
temperature = "305 K"
waypoints = [
    {time = "0 s", position = ["600 m", "-200 m", "0 m"]},
    {time = "10 s", position = ["1600 m", "-200 m", "0 m"]},
]

[background]
temperature = "295 K"

[time]
start = "0 s"
stop = "10 s"
step = "1 s"
"""

TERRAIN = """
[terrain]
elevation = "dem.npy"
spacing = "10 m"
origin = ["-500 m", "-500 m"]
"""


@pytest.fixture
def scenes(tmp_path):
    """The scene with and without terrain: 10 m posts from (-500, -500), 4 km east by 1 km north;
    south of y = 0 a 20 m ridge from 1000 m to 1020 m east, north of y = 100 m a 6 m plateau
    from 400 m to 500 m east (which hides the lower part of the 'partial' target)."""
    grid = np.zeros((101, 401))
    grid[:50, 150:153] = 20.0
    grid[60:, 90:101] = 6.0
    np.save(tmp_path / "dem.npy", grid)
    (tmp_path / "terrain.toml").write_text(SCENE + TERRAIN)
    (tmp_path / "bare.toml").write_text(SCENE)
    return tmp_path / "terrain.toml", tmp_path / "bare.toml"


def test_model_chain_hides_targets_behind_the_ridge(scenes):
    ds = ModelChain(load_scenario(scenes[0])).evaluate().dataset
    ref = ModelChain(load_scenario(scenes[1])).evaluate().dataset
    names = list(ds.target.values)
    front, behind, partial, crossing = (names.index(n) for n in names)
    assert bool(ref.in_view[0, behind].all()) and float(ref.detection[0, behind, 0]) > 0.5
    for task in TASKS:
        got, want = ds[task].values[0], ref[task].values[0]
        assert np.all(got[behind] == 0.0) and np.all(ds[f"fused_{task}"].values[behind] == 0.0)
        np.testing.assert_array_equal(got[front], want[front])  # in front: unchanged
    assert not ds.in_view.values[0, behind].any() and ds.in_view.values[0, front].all()
    # The plateau hides the lower part of 'partial': fewer cycles than without terrain.
    assert np.all(ds.cycles.values[0, partial] < ref.cycles.values[0, partial])
    assert np.all(ds.identification.values[0, partial] > 0.0)
    # The crossing target: seen before the ridge (x < 1000 m until 4 s), hidden after it.
    seen = ds.in_view.values[0, crossing]
    x = 600.0 + 100.0 * ds.time.values
    assert seen[x < 990].all() and not seen[x > 1100].any()
    p = ds.detection.values[0, crossing]
    assert np.all(p[x > 1100] == 0.0) and np.all(p[x < 990] > 0.0)


def test_batch_equals_the_step_api_at_the_same_times(scenes):
    scenario = load_scenario(scenes[0])
    ds = ModelChain(scenario).evaluate().dataset
    sim = Simulation.from_scenario(scenario)
    sensors = np.array([[0.0, 0.0, 10.0]])
    for k, t in enumerate(ds.time.values):
        x = 600.0 + 100.0 * min(t, 10.0)  # the crossing target's waypoints, by hand
        where = np.array(
            [[800.0, -200.0, 0.0], [1500.0, -200.0, 0.0], [1000.0, 300.0, 0.0], [x, -200.0, 0.0]]
        )
        # The headings the scenario gives (a moving target faces along its path).
        headings = scenario_positions(scenario, [float(t)])[2][:, 0]
        step = sim.probabilities(float(t), sensors, where, headings)
        for task in TASKS:
            np.testing.assert_allclose(
                ds[task].values[..., k], getattr(step, task), rtol=1e-12, atol=0.0
            )
            np.testing.assert_allclose(
                ds[f"fused_{task}"].values[:, k], getattr(step, f"fused_{task}"), rtol=1e-12
            )


def test_chunks_give_the_whole_run(scenes):
    chain = ModelChain(load_scenario(scenes[0]))
    every = np.arange(11.0)
    whole = chain.compute(every)
    for targets, times, arrays in chain.evaluate_chunks(targets_per_chunk=3, times_per_chunk=4):
        first = int(np.searchsorted(every, times[0]))
        part = slice(first, first + times.size)
        for name in ("detection", "in_view"):
            np.testing.assert_array_equal(arrays[name], whole[name][:, targets, part])


def test_cli_evaluate_and_simulate(scenes, cli, tmp_path):
    out = tmp_path / "results.json"
    code, _, err = cli("evaluate", str(scenes[0]), "--out", str(out))
    assert code == 0, err
    rows = json.loads(out.read_text())["rows"]
    behind = [r for r in rows if r["target"] == "behind"]
    front = [r for r in rows if r["target"] == "front"]
    assert behind and all(r["detection"] == 0.0 and not r["in_view"] for r in behind)
    assert all(r["detection"] > 0.5 for r in front)
    code, out, err = cli(
        "simulate", str(scenes[0]), "--duration", "60s", "--step", "0.5s", "--runs", "20",
        "--seed", "1", "--format", "json",
    )  # fmt: skip
    assert code == 0, err
    fractions = {
        (row["target"], row["task"]): row["fraction"] for row in json.loads(out)["targets"]
    }
    assert fractions["behind", "detection"] == 0.0 and fractions["front", "detection"] == 1.0
    result = simulate(ModelChain(load_scenario(scenes[0])), 60.0, 0.5, runs=20, seed=1)
    names = result.targets
    detected = np.isfinite(result.fused["detection"])
    assert not detected[:, names.index("behind")].any()
    assert detected[:, names.index("front")].all()


def test_a_scenarios_dri_says_it_does_not_trace_the_terrain(scenes, cli):
    code, out, err = cli("dri", str(scenes[0]), "--format", "json")
    assert code == 0, err
    assert "do not trace the scenario's [terrain] line of sight" in json.loads(out)["note"]
    code, out, err = cli("dri", str(scenes[0]))
    assert code == 0 and "do not trace" in out
    code, out, err = cli("dri", str(scenes[1]), "--format", "json")
    assert code == 0 and "note" not in json.loads(out)


def test_a_scripted_target_off_the_elevation_model_is_a_located_problem(scenes, cli):
    moved = 'position = ["9 km", "-200 m", "0 m"]'
    text = scenes[0].read_text().replace('position = ["1500 m", "-200 m", "0 m"]', moved, 1)
    assert moved in text
    scenes[0].write_text(text)
    code, _, err = cli("validate", str(scenes[0]))
    assert code == 2 and "is off the elevation model" in err
