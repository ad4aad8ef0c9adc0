"""An elevation model in the environments (``scenario_overrides={"terrain": ...}``): targets on
the ground, lines of sight from the platform over the relief, a hidden target out of view."""

import math

import numpy as np
import pytest

gymnasium = pytest.importorskip("gymnasium")

from targetacq.envs import AcquisitionEnv, AcquisitionVectorEnv, SensorPointingEnv  # noqa: E402
from targetacq.envs.acquisition import (  # noqa: E402
    CAMERA_FEATURES,
    PLATFORM_FEATURES,
    TARGET_FEATURES,
)
from targetacq.physics.line_of_sight import ElevationModel, line_of_sight  # noqa: E402

NEAR = {"altitude": 400.0, "half_width": 800.0, "speed": 10.0}
T = 6


def _blocks(obs, n_targets=T):
    start = PLATFORM_FEATURES + CAMERA_FEATURES
    return obs[..., start : start + TARGET_FEATURES * n_targets].reshape(
        *obs.shape[:-1], n_targets, TARGET_FEATURES
    )


@pytest.fixture
def wall(tmp_path):
    """10 m posts over [-1000, 1000] m east and north: ground rising 2 m per 100 m eastward, and a
    390 m wall from 600 m to 580 m west of the origin, which hides, from the platform 400 m up
    and west of it, every target east of it."""
    east = -1000.0 + 10.0 * np.arange(201)
    grid = np.tile(0.02 * (east + 1000.0), (201, 1))
    grid[:, 40:43] = 390.0
    path = tmp_path / "wall.npy"
    np.save(path, grid)
    spec = {"elevation": str(path), "spacing": "10 m", "origin": ["-1000 m", "-1000 m"]}
    return spec, ElevationModel(grid, 10.0, (-1000.0, -1000.0))


def _scene(spec, **atmosphere):
    overrides = {"terrain": spec, **({"atmosphere": atmosphere} if atmosphere else {})}
    return {**NEAR, "scenario_overrides": overrides}


def test_targets_stand_on_the_ground_and_the_wall_hides_them(wall):
    spec, model = wall
    env = AcquisitionEnv(targets=T, duration=15.0, scene=_scene(spec))
    obs, _ = env.reset(seed=4)
    e = env._core  # the targets' true positions
    targets = e.targets[0]
    off_wall = (targets[:, 0] < -610.0) | (targets[:, 0] > -570.0)
    assert off_wall.sum() >= T - 1
    slope = 0.02 * (targets[off_wall, 0] + 1000.0)  # the ground's own formula
    np.testing.assert_allclose(targets[off_wall, 2], slope, rtol=1e-12)
    np.testing.assert_array_equal(targets[:, 2], model.height_at(targets[:, 0], targets[:, 1]))
    behind = targets[:, 0] > -570.0
    assert behind.any()
    # An independent trace over the grid: the wall hides whatever stands east of it.
    platform = np.array([-NEAR["half_width"], 0.0, NEAR["altitude"]])
    seen = line_of_sight(model, None, None, platform, targets, 2.5)
    assert np.all(seen[behind] == 0.0)
    for _ in range(15):
        blocks = _blocks(obs)
        assert np.all(blocks[behind, 12] == 0.0)  # in view: never
        assert np.all(blocks[behind, 7:10] == 0.0)  # prospects: none
        assert np.all(blocks[behind, 4:7] == 0.0)  # never detected
        # Point the camera at the first target behind the wall: still nothing.
        obs, *_ = env.step(int(np.flatnonzero(behind)[0]))
    assert np.all(_blocks(obs)[behind, 4] == 0.0)


def test_flat_ground_at_zero_gives_the_numbers_without_terrain(tmp_path):
    np.save(tmp_path / "flat.npy", np.zeros((201, 201)))
    spec = {"elevation": str(tmp_path / "flat.npy"), "spacing": 10.0, "origin": [-1000, -1000]}
    with_terrain = AcquisitionVectorEnv(2, targets=4, duration=8.0, scene=_scene(spec))
    without = AcquisitionVectorEnv(2, targets=4, duration=8.0, scene=NEAR)
    a, _ = with_terrain.reset(seed=2)
    b, _ = without.reset(seed=2)
    np.testing.assert_array_equal(a, b)
    for k in range(8):
        a, ra, *_ = with_terrain.step(np.full(2, k % 4))
        b, rb, *_ = without.step(np.full(2, k % 4))
        np.testing.assert_array_equal(a, b)
        np.testing.assert_array_equal(ra, rb)


@pytest.mark.parametrize("cloud", [False, True])
def test_vector_env_i_is_the_single_env_with_terrain(wall, cloud):
    spec, _ = wall
    atmosphere = (
        {"clouds": [{"center": (-700.0, 0.0, 300.0), "radius": 200.0, "extinction": 0.01}]}
        if cloud
        else {}
    )
    scene = _scene(spec, **atmosphere)
    n, seed = 3, 7
    vec = AcquisitionVectorEnv(n, chunk=2, targets=T, duration=6.0, scene=scene)
    obs, _ = vec.reset(seed=seed)
    trace = [obs]
    for k in range(6):
        trace.append(vec.step(np.full(n, k % T))[0])
    for i in range(n):
        single = AcquisitionEnv(targets=T, duration=6.0, scene=scene)
        obs, _ = single.reset(seed=seed + i)
        np.testing.assert_array_equal(trace[0][i], obs)
        for k in range(6):
            obs, *_ = single.step(k % T)
            np.testing.assert_array_equal(trace[k + 1][i], obs)
    assert (_blocks(np.stack(trace))[..., 12] == 0).any()  # the wall hid something


def test_the_prospects_are_the_step_apis_with_terrain(wall):
    spec, _ = wall
    scene = _scene(spec)
    env = AcquisitionEnv(targets=T, duration=6.0, scene=scene)
    obs, _ = env.reset(seed=9)
    legacy = SensorPointingEnv(targets=T, duration=6.0, **scene)
    legacy.reset(seed=9)  # the same draws; its Simulation traces the lines of sight itself
    assert legacy._sim.compiled.elevation is not None
    np.testing.assert_array_equal(legacy._targets, env._core.targets[0])
    platform = np.array([[-NEAR["half_width"], 0.0, NEAR["altitude"]]])
    for j in range(T):
        offset = legacy._targets[j] - platform[0]
        pointing = np.array(
            [[math.atan2(offset[0], offset[1]), math.atan2(-offset[2], math.hypot(*offset[:2]))]]
        )
        p = legacy._sim.probabilities(0.0, platform, legacy._targets, sensor_pointing=pointing)
        block = _blocks(obs)[j]
        expected = [p.detection[0, j], p.recognition[0, j], p.identification[0, j]]
        np.testing.assert_allclose(block[7:10], expected, rtol=1e-5, atol=1e-7)


def test_terrain_options_are_checked(wall, tmp_path):
    spec, _ = wall
    # The platform's start off the grid is refused too (by the scenario's own check, first).
    off = r"scenario_overrides: (terrain.elevation: the grid|sensor.position: .* is off the elev)"
    with pytest.raises(ValueError, match=off):
        AcquisitionEnv(scene={**_scene(spec), "half_width": 2000.0})
    with pytest.raises(ValueError, match=r"altitude \(300 m, above the elevation model's datum"):
        AcquisitionEnv(scene={**_scene(spec), "altitude": 300.0})
    with pytest.raises(ValueError, match=r"scenario_overrides: terrain.spacing"):
        SensorPointingEnv(scenario_overrides={"terrain": {"elevation": spec["elevation"]}})
