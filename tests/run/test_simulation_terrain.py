"""The ``[terrain]`` elevation model in scenarios and the step API: lines of sight over the relief
set each pair's visible fraction (targetacq.physics.line_of_sight), a hidden target is out of
view, and false targets fall only on ground in sight."""

import importlib.util
import math

import numpy as np
import pytest

from targetacq import Simulation
from targetacq.core.compile import check_runnable, compile_scenario
from targetacq.scenario.schema import ScenarioError, load_scenario, parse_scenario

SENSOR = {"name": "ir", "band": "lwir", "ifov": 0.25e-3, "position": [0.0, 0.0, 10.0]}
BACKGROUND = {"temperature": 295.0}
FLAT = 1e12  # an Earth-radius factor that makes the Earth flat to 1e-8 m over these tracks


def targets(count=2, height=4.0, **extra):
    return [
        {
            "name": f"t{k}",
            "dimensions": [7.0, 2.5, height],
            "temperature": 305.0,
            "position": [0.0, 0.0, 0.0],
            **extra,
        }
        for k in range(count)
    ]


@pytest.fixture
def ridge(tmp_path):
    """Flat ground at 0 m, 4 km east by 1 km north (10 m posts, origin (-500, -500)), with a
    20 m ridge from 1000 m to 1020 m east."""
    grid = np.zeros((101, 401))
    grid[:, 150:153] = 20.0
    path = tmp_path / "dem.npy"
    np.save(path, grid)
    return {"elevation": str(path), "spacing": 10.0, "origin": (-500.0, -500.0)}


@pytest.fixture
def plateau(tmp_path):
    """A 6 m plateau from 400 m to 500 m east: seen from 10 m up at the origin, a 4 m target
    at 1000 m east shows its upper half (10 - 4 * 1000 / 500 = 2 m is hidden)."""
    grid = np.zeros((101, 401))
    grid[:, 90:101] = 6.0
    path = tmp_path / "plateau.npy"
    np.save(path, grid)
    return {
        "elevation": str(path),
        "spacing": 10.0,
        "origin": (-500.0, -500.0),
        "earth_radius_factor": FLAT,
    }


NO_NUMBA = importlib.util.find_spec("numba") is None
ENGINES = [
    "numpy",
    pytest.param("numba", marks=pytest.mark.skipif(NO_NUMBA, reason="numba is not installed")),
]


@pytest.mark.parametrize("engine", ENGINES)
def test_a_target_behind_the_ridge_is_out_of_view_and_one_in_front_unchanged(ridge, engine):
    sim = Simulation([SENSOR], targets(), background=BACKGROUND, terrain=ridge, engine=engine)
    bare = Simulation([SENSOR], targets(), background=BACKGROUND, engine=engine)
    sensors = np.array([[0.0, 0.0, 10.0]])
    where = np.array([[800.0, 0.0, 0.0], [1500.0, 0.0, 0.0]])  # in front, behind
    out, ref = sim.step(0.0, 0.1, sensors, where), bare.step(0.0, 0.1, sensors, where)
    assert ref.detection[0, 1] > 0.9 and ref.in_view[0, 1]  # without terrain: seen
    assert out.in_view.tolist() == [[True, False]]
    for task in ("detection", "recognition", "identification"):
        assert getattr(out, task)[0, 1] == 0.0
        assert getattr(out, task)[0, 0] == getattr(ref, task)[0, 0]
        assert getattr(out, f"fused_{task}")[1] == 0.0
    p = sim.probabilities(0.0, sensors, where)
    assert p.detection[0, 1] == 0.0 and p.detection[0, 0] == ref.detection[0, 0]
    # A query of target 0 behind the ridge and target 1 in front.
    q = sim.probabilities_at(0.0, sensors, where[::-1], np.array([0, 1]))
    assert q.detection[0].tolist() == [0.0, ref.detection[0, 0]]
    # Stepping on: the hidden one is never detected, the other is.
    for k in range(1, 600):
        out = sim.step(0.1 * k, 0.1, sensors, where)
    assert out.detected.tolist() == [[True, False]]


@pytest.mark.parametrize("own", [None, 0.3, 0.8])
def test_partial_masking_is_the_closed_form_fraction(plateau, own):
    extra = {} if own is None else {"visible_fraction": own}
    sim = Simulation([SENSOR], targets(1, **extra), background=BACKGROUND, terrain=plateau)
    bare = Simulation([SENSOR], targets(1), background=BACKGROUND)
    sensors, where = np.array([[0.0, 0.0, 10.0]]), np.array([[1000.0, 0.0, 0.0]])
    # The terrain leaves 1/2; an occlusion of the target's own hides from the bottom too: the
    # pair sees the smaller fraction.
    fraction = 0.5 if own is None else min(own, 0.5)
    expected = bare.step(0.0, 0.1, sensors, where, visible_fraction=np.array([fraction]))
    got = sim.step(0.0, 0.1, sensors, where)
    assert got.detection[0, 0] == pytest.approx(expected.detection[0, 0], rel=1e-7)
    assert got.identification[0, 0] == pytest.approx(expected.identification[0, 0], rel=1e-7)
    bare.reset()
    assert got.identification[0, 0] < bare.step(0.0, 0.1, sensors, where).identification[0, 0]
    # One given to the step replaces the target's own, and meets the terrain's likewise.
    sim.reset()
    bare.reset()
    given = sim.step(0.0, 0.1, sensors, where, visible_fraction=np.array([0.35]))
    wanted = bare.step(0.0, 0.1, sensors, where, visible_fraction=np.array([0.35]))
    assert given.identification[0, 0] == pytest.approx(wanted.identification[0, 0], rel=1e-7)


def test_off_the_grid_gives_nan(ridge):
    sim = Simulation([SENSOR], targets(), background=BACKGROUND, terrain=ridge)
    out = sim.step(
        0.0, 0.1, np.array([[0.0, 0.0, 10.0]]), np.array([[800.0, 0.0, 0.0], [9000.0, 0.0, 0.0]])
    )
    assert out.detection[0, 0] > 0 and math.isnan(out.detection[0, 1])


def test_jax_positions_are_refused_with_terrain(ridge):
    jnp = pytest.importorskip("jax.numpy")
    sim = Simulation([SENSOR], targets(), background=BACKGROUND, terrain=ridge)
    with pytest.raises(ValueError, match=r"\[terrain\]"):
        sim.probabilities(0.0, jnp.zeros((1, 3)), jnp.ones((2, 3)))


def test_a_scenario_file_with_terrain(tmp_path):
    grid = np.zeros((101, 401))
    grid[:, 150:153] = 20.0
    np.save(tmp_path / "dem.npy", grid)
    (tmp_path / "scene.toml").write_text(
        """
[[sensors]]
name = "ir"
band = "lwir"
ifov = "0.25 mrad"
position = ["0 m", "0 m", "10 m"]

[[targets]]
name = "front"
dimensions = ["7 m", "2.5 m", "4 m"]
temperature = "305 K"
position = ["800 m", "0 m", "0 m"]

[[targets]]
name = "behind"
dimensions = ["7 m", "2.5 m", "4 m"]
temperature = "305 K"
position = ["1500 m", "0 m", "0 m"]

[background]
temperature = "295 K"

[terrain]
elevation = "dem.npy"
spacing = "10 m"
origin = ["-500 m", "-500 m"]
"""
    )
    scenario = load_scenario(tmp_path / "scene.toml")
    assert scenario.terrain.elevation == str(tmp_path / "dem.npy")  # from the file's folder
    assert scenario.terrain.earth_radius_factor == pytest.approx(4 / 3)
    compiled = compile_scenario(scenario)
    assert compiled.elevation.spacing == 10.0 and compiled.elevation.origin == (-500.0, -500.0)
    sim = Simulation.from_scenario(scenario)
    out = sim.step(
        0.0, 0.1, np.array([[0.0, 0.0, 10.0]]), np.array([[800.0, 0, 0], [1500.0, 0, 0]])
    )
    assert out.in_view.tolist() == [[True, False]]
    missing = scenario.model_copy(
        update={
            "terrain": scenario.terrain.model_copy(update={"elevation": str(tmp_path / "no.npy")})
        }
    )
    problems = check_runnable(missing)
    assert len(problems) == 1 and problems[0].startswith("terrain.elevation: ")
    assert "no such elevation file" in problems[0]


def _parse(terrain):
    data = {
        "sensors": [{**SENSOR, "ifov": "0.25 mrad", "position": ["0 m", "0 m", "10 m"]}],
        "targets": [
            {
                "name": "t",
                "dimensions": ["7 m", "2.5 m", "4 m"],
                "temperature": "305 K",
                "position": ["1 km", "0 m", "0 m"],
            }
        ],
        "background": {"temperature": "295 K"},
        "terrain": terrain,
    }
    return parse_scenario(data, "scene.toml")


@pytest.mark.parametrize(
    ("terrain", "message"),
    [
        (
            {"elevation": "dem.npy"},
            "terrain.spacing: a .npy elevation grid needs its spacing",
        ),
        (
            {"elevation": "dem.npy", "spacing": "10 m"},
            "terrain.origin: a .npy elevation grid needs its origin",
        ),
        (
            {"elevation": "dem.csv"},
            "terrain.elevation: an elevation model is a .npy grid",
        ),
        ({"elevation": "dem.tif", "spacing": "0 m"}, "terrain.spacing: must be > 0 m"),
        ({"elevation": "dem.tif", "spacing": "10"}, "terrain.spacing: "),
        (
            {"elevation": "dem.tif", "earth_radius_factor": -1},
            "terrain.earth_radius_factor: must be > 0",
        ),
        (
            {"elevation": "dem.tif", "spaceing": "10 m"},
            "terrain.spaceing: unknown key 'spaceing' (did you mean 'spacing'?)",
        ),
        ({"spacing": "10 m"}, "terrain.elevation: required key missing"),
    ],
)
def test_scenario_errors_are_located(terrain, message):
    with pytest.raises(ScenarioError) as caught:
        _parse(terrain)
    problems = caught.value.problems
    assert any(p.startswith(f"scene.toml: {message}") for p in problems), problems


def test_a_geotiff_needs_no_spacing_in_the_file():
    scenario = _parse({"elevation": "dem.tif"})
    assert scenario.terrain.spacing is None and scenario.terrain.origin is None


def test_false_targets_fall_only_on_ground_in_sight(ridge):
    camera = {
        "name": "cam",
        "band": "lwir",
        "hfov": 0.4,
        "pixels": [640, 480],
        "projection": "rectilinear",
        "position": [0.0, 0.0, 30.0],
        "azimuth": math.pi / 2,
        "depression": 0.02,
    }
    table = {"density": 2e-4, "probability": 0.5, "max_range": 2900.0}
    kinds = {}
    for name, terrain in (("flat", None), ("ridge", ridge)):
        sim = Simulation(
            [camera],
            targets(1),
            background=BACKGROUND,
            false_targets=table,
            terrain=terrain,
            seed=3,
        )
        sensors, where = np.array([[0.0, 0.0, 30.0]]), np.array([[500.0, 0.0, 0.0]])
        found = [sim.step(0.5 * k, 0.5, sensors, where).false_detections for k in range(40)]
        kinds[name] = np.concatenate([f.position for f in found])
    flat, masked = kinds["flat"], kinds["ridge"]
    assert (flat[:, 0] > 1100).sum() > 20 and (flat[:, 0] < 1000).sum() > 20
    # Behind the 20 m ridge at 1000 m (seen from 30 m up) nothing; in front as many as before
    # (the same draws, kept where in sight).
    assert len(masked) > 20 and masked[:, 0].max() <= 1020.0
    front = flat[flat[:, 0] < 1000]
    assert np.array_equal(masked[masked[:, 0] < 1000][:, :2], front[:, :2])
    on_ridge = (masked[:, 0] >= 1000) & (masked[:, 0] <= 1020)
    assert np.all(masked[~on_ridge, 2] == 0.0) and np.all(masked[on_ridge, 2] > 0.0)
