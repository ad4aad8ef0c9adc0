"""The array core under JAX: ``jit`` equals NumPy, ``grad`` equals central differences, ``vmap``.

The reference numbers are the NumPy core's (the golden test pins those to the version before the
core); the reference derivatives are central finite differences of the NumPy core, independent
of JAX's differentiation. Float64 (``jax_enable_x64``) is needed for agreement to 1e-12.
"""

import dataclasses
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

jax = pytest.importorskip("jax")
jnp = pytest.importorskip("jax.numpy")
jax.config.update("jax_enable_x64", True)

from targetacq import core  # noqa: E402
from targetacq.core import records  # noqa: E402
from targetacq.core.evaluation import footprint_scr  # noqa: E402
from targetacq.scenario.schema import load_scenario, parse_scenario  # noqa: E402

ROOT = Path(__file__).parents[2]
GOLDEN = Path(__file__).parents[1] / "data" / "golden"
SCENARIOS = sorted((ROOT / "examples").glob("*.toml")) + sorted(GOLDEN.glob("*.toml"))
NUMPY_ONLY = {"terrain"}  # terrain maps: the SCR is looked up per position on the host
FACTORS = ("range", "critical_dimension", "cycles", "optical_depth", "transmittance", "snr", "scr")
PROBABILITIES = tuple(f.name for f in dataclasses.fields(core.Probabilities))


def _compiled(path):
    scenario = load_scenario(path)
    return scenario, core.compile_scenario(scenario)


def _step(scenario, time):
    """Positions and headings of a scenario at one time: (n_s, 3), (n_g, 3), (n_g,)."""
    s, t, h = core.scenario_positions(scenario, [time])
    return s[:, 0], t[:, 0], h[:, 0]


def _central_difference(function, point, step):
    """Central differences of a scalar function of an array, element by element."""
    out = np.zeros_like(point)
    for index in np.ndindex(point.shape):
        up, down = point.copy(), point.copy()
        up[index] += step
        down[index] -= step
        out[index] = (function(up) - function(down)) / (2.0 * step)
    return out


def _boresight_angles(scene, sensor_positions):
    """Azimuth and depression of each sensor's own pointing (look_at turned into angles)."""
    sensors = scene.sensors
    angles = np.array(sensors.pointing, dtype=float)
    for k in range(angles.shape[0]):
        if np.isfinite(sensors.look_at[k, 0]):
            d = sensors.look_at[k] - sensor_positions[k]
            angles[k] = np.arctan2(d[0], d[1]), np.arctan2(-d[2], np.hypot(d[0], d[1]))
    return angles


@pytest.mark.parametrize(
    "path", [p for p in SCENARIOS if p.stem not in NUMPY_ONLY], ids=lambda p: p.stem
)
def test_jit_equals_numpy_on_every_bundled_scenario(path):
    scenario, compiled = _compiled(path)
    s, t, h = core.scenario_positions(scenario, scenario.time.times())
    want_factors, want = core.evaluate(compiled.scene, s, t, h)
    scene = records.as_jax(compiled)
    got_factors, got = jax.jit(core.evaluate)(scene, jnp.asarray(s), jnp.asarray(t), jnp.asarray(h))
    for name in FACTORS:
        expected = getattr(want_factors, name)
        if expected is None:
            assert getattr(got_factors, name) is None, name
            continue
        np.testing.assert_allclose(
            np.asarray(getattr(got_factors, name)), expected, rtol=1e-12, atol=0, err_msg=name
        )
    np.testing.assert_array_equal(np.asarray(got_factors.in_view), want_factors.in_view)
    for name in PROBABILITIES:
        value = getattr(got, name)
        assert value.dtype == jnp.float64, name
        # atol: the fusion 1 − Π(1 − p) of probabilities of 1e-5 carries ~1e-16 absolute
        # rounding, beyond 1e-12 relative (the contrast SNR law makes such small ones).
        np.testing.assert_allclose(
            np.asarray(value), getattr(want, name), rtol=1e-12, atol=1e-15, err_msg=name
        )


def test_terrain_scenarios_are_numpy_only():
    scenario, compiled = _compiled(GOLDEN / "terrain.toml")
    with pytest.raises(ValueError, match="terrain map"):
        records.as_jax(compiled)
    s, t, _ = _step(scenario, 0.0)
    rng = np.linalg.norm(t[None] - s[:, None], axis=-1)
    args = (rng, t, compiled.scene.signature.target, np.asarray(compiled.scene.sensors.ifov))
    np.asarray(footprint_scr(compiled.terrain, *args))  # NumPy: fine
    with pytest.raises(ValueError, match="NumPy only"):
        footprint_scr(compiled.terrain, jnp.asarray(rng), *args[1:])


def test_as_jax_and_to_namespace():
    _, compiled = _compiled(ROOT / "examples" / "uav_haze.toml")
    scene = records.as_jax(compiled.scene)
    assert isinstance(scene.sensors.cycle, jax.Array)
    assert scene.sensors.names == compiled.scene.sensors.names
    assert scene.choices == compiled.scene.choices
    np.testing.assert_array_equal(np.asarray(scene.targets.n50), compiled.scene.targets.n50)
    leaves = jax.tree_util.tree_leaves(scene)
    assert leaves and all(isinstance(leaf, jax.Array) for leaf in leaves)
    kept = []

    @jax.jit
    def traced(x):  # made while tracing, kept for later: must hold concrete arrays
        kept.append(records.as_jax(compiled))
        return x

    traced(1.0)
    assert not any(isinstance(leaf, jax.core.Tracer) for leaf in jax.tree_util.tree_leaves(kept))
    back = records.to_namespace(scene, np)
    assert isinstance(back.sensors.cycle, np.ndarray)
    with pytest.raises(TypeError, match="record"):
        records.to_namespace(compiled, jnp)


def test_records_register_on_demand_when_targetacq_is_imported_first():
    code = (
        "import sys\n"
        "from targetacq import core\n"
        "from targetacq.core import records\n"
        "from targetacq.scenario.schema import load_scenario\n"
        "assert 'jax' not in sys.modules\n"
        "import jax, jax.numpy as jnp\n"
        "jax.config.update('jax_enable_x64', True)\n"
        f"sc = load_scenario({str(ROOT / 'examples' / 'uav_haze.toml')!r})\n"
        "scene = records.as_jax(core.compile_scenario(sc))\n"
        "s, t, h = core.scenario_positions(sc, [60.0])\n"
        "found, p = jax.jit(core.evaluate)(scene, jnp.asarray(s), jnp.asarray(t), jnp.asarray(h))\n"
        "print(float(p.fused_detection[0, 0]))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    scenario, compiled = _compiled(ROOT / "examples" / "uav_haze.toml")
    s, t, h = core.scenario_positions(scenario, [60.0])
    want = core.evaluate(compiled.scene, s, t, h)[1].fused_detection[0, 0]
    assert float(out.stdout) == pytest.approx(want, rel=1e-12)


# Points where the model is smooth: the target inside the field of view of a sensor that sees it
# (away from the edge), P strictly between 0 and 1, no line of sight along a target's axes (the
# outline's |sin a|, |cos a| kinks), away from the table curves' printed points.
GRADIENT_CASES = [
    ("uav_haze", 60.0, 0),  # one sensor pointed by angles, SCR from clutter_std, haze noise
    ("uav_haze", 60.0, 1),
    ("two_sensors_fused", 25.0, 1),  # TV and thermal fused, look_at, medium clutter
    ("two_sensors_fused", 25.0, 0),  # the same, in the TV's field of view only
    ("features", 14.0, 1),  # segments, a cloud, hot spot, c2nveo, an unpointed sensor
]


def _case(name):
    path = ROOT / "examples" / f"{name}.toml"
    return _compiled(path if path.exists() else GOLDEN / f"{name}.toml")


@pytest.mark.parametrize(("name", "time", "target"), GRADIENT_CASES)
def test_grad_of_fused_detection_equals_central_differences(name, time, target):
    scenario, compiled = _case(name)
    s, t, h = _step(scenario, time)
    _, p = core.evaluate(compiled.scene, s, t, h)
    assert 0.02 < p.fused_detection[target] < 0.98
    scene = records.as_jax(compiled)

    def fused(sensor_positions):
        return core.evaluate(scene, sensor_positions, jnp.asarray(t), jnp.asarray(h))[
            1
        ].fused_detection[target]

    got = np.asarray(jax.jit(jax.grad(fused))(jnp.asarray(s)))
    want = _central_difference(
        lambda sp: core.evaluate(compiled.scene, sp, t, h)[1].fused_detection[target], s, 1e-3
    )
    assert np.all(np.isfinite(got))
    assert np.max(np.abs(want)) > 1e-6  # the test means something
    np.testing.assert_allclose(got, want, rtol=1e-6, atol=1e-6 * np.max(np.abs(want)))


@pytest.mark.parametrize(("name", "time", "target"), GRADIENT_CASES[:3])
def test_grad_with_respect_to_pointing_inside_the_field_of_view(name, time, target):
    # Pointing decides only whether a target is in view (a step), so inside the field of view
    # the probability does not change with it: the gradient is finite and zero, as are the
    # central differences.
    scenario, compiled = _case(name)
    s, t, h = _step(scenario, time)
    angles = _boresight_angles(compiled.scene, s)
    found, p = core.evaluate(compiled.scene, s, t, h, angles)
    assert found.in_view[:, target].all()
    own = core.evaluate(compiled.scene, s, t, h)[1].fused_detection
    np.testing.assert_allclose(p.fused_detection, own, rtol=1e-12)
    scene = records.as_jax(compiled)

    def fused(sensor_positions, pointing):
        return core.evaluate(scene, sensor_positions, jnp.asarray(t), jnp.asarray(h), pointing)[
            1
        ].fused_detection[target]

    by_position, by_pointing = jax.jit(jax.grad(fused, argnums=(0, 1)))(
        jnp.asarray(s), jnp.asarray(angles)
    )
    want = _central_difference(
        lambda a: core.evaluate(compiled.scene, s, t, h, a)[1].fused_detection[target],
        angles,
        1e-6,
    )
    assert np.all(np.isfinite(np.asarray(by_position)))
    np.testing.assert_allclose(np.asarray(by_pointing), want, atol=1e-12)


def _uav(**changes):
    """One downward-looking LWIR sensor and a truck in its field of view, as a dict scenario."""
    scenario = {
        "sensors": [
            {
                "name": "uav",
                "type": "thermal",
                "band": "lwir",
                "pixels": [640, 512],
                "pitch": "17 um",
                "focal_length": "35 mm",
                "aperture": "35 mm",
                "position": ["0 m", "0 m", "1500 m"],
                "azimuth": "20 deg",
                "depression": "60 deg",
            }
        ],
        "targets": [
            {
                "name": "truck",
                "dimensions": ["7 m", "2.5 m", "3 m"],
                "heading": "10 deg",
                "temperature": "305 K",
                "position": ["300 m", "800 m", "0 m"],
            }
        ],
        "background": {"temperature": "295 K", "clutter_std": "2 K"},
        "atmosphere": {"obscurant": "haze"},
    }
    for key, value in changes.items():
        if key in ("position", "look_at", "azimuth", "depression"):
            sensor = scenario["sensors"][0]
            if key == "look_at":
                sensor.pop("azimuth")
                sensor.pop("depression")
            sensor[key] = value
        elif key == "target":
            scenario["targets"][0]["position"] = value
        else:
            scenario[key] = value
    return parse_scenario(scenario)


NAN_SAFE_CASES = {
    # sqrt(b² − c) of the chord is masked where the line of sight misses the cloud
    "a cloud off the line of sight": {
        "atmosphere": {
            "obscurant": "haze",
            "clouds": [
                {"center": ["-2 km", "-2 km", "10 m"], "radius": "50 m", "extinction": "20 /km"}
            ],
        }
    },
    # optical depth 0: SNR = +inf, where 10^(SNR/20) has an infinite slope
    "an atmosphere of zero extinction": {"atmosphere": {"extinction": "0 /km"}},
    # the sensor frame's horizontal part of the boresight is 0
    "a sensor looking straight down": {
        "look_at": ["0 m", "0 m", "0 m"],
        "target": ["150 m", "100 m", "0 m"],
        "position": ["0 m", "0 m", "4000 m"],
    },
}


@pytest.mark.parametrize("changes", NAN_SAFE_CASES.values(), ids=NAN_SAFE_CASES.keys())
def test_gradients_are_not_poisoned_by_masked_branches(changes):
    compiled = core.compile_scenario(_uav(**changes))
    s, t, h = _step(_uav(**changes), 0.0)
    found, p = core.evaluate(compiled.scene, s, t, h)
    assert found.in_view.all()
    assert 0.02 < p.fused_detection[0] < 0.98
    scene = records.as_jax(compiled)

    def fused(sensor_positions):
        return core.evaluate(scene, sensor_positions, jnp.asarray(t), jnp.asarray(h))[
            1
        ].fused_detection[0]

    got = np.asarray(jax.jit(jax.grad(fused))(jnp.asarray(s)))
    want = _central_difference(
        lambda sp: core.evaluate(compiled.scene, sp, t, h)[1].fused_detection[0], s, 1e-3
    )
    assert np.all(np.isfinite(got)), got
    np.testing.assert_allclose(got, want, rtol=1e-6, atol=1e-6 * np.max(np.abs(want)))


def test_vmap_over_a_batch_of_sensor_positions():
    scenario, compiled = _compiled(ROOT / "examples" / "two_sensors_fused.toml")
    s, t, h = _step(scenario, 25.0)
    offsets = np.random.default_rng(7).normal(0.0, 50.0, (16, 1, 3))
    batch = s[None] + offsets  # (16, n_s, 3)
    scene = records.as_jax(compiled)

    def fused(sensor_positions):
        return core.evaluate(scene, sensor_positions, jnp.asarray(t), jnp.asarray(h))[1]

    got = jax.jit(jax.vmap(fused))(jnp.asarray(batch))
    # NumPy's own batch axis: positions (n_s, 16, 3) and (n_g, 16, 3), results (..., 16).
    _, want = core.evaluate(
        compiled.scene,
        np.moveaxis(batch, 0, 1),
        np.repeat(t[:, None], 16, axis=1),
        np.repeat(h[:, None], 16, axis=1),
    )
    for name in PROBABILITIES:
        np.testing.assert_allclose(
            np.moveaxis(np.asarray(getattr(got, name)), 0, -1),
            getattr(want, name),
            rtol=1e-12,
            atol=0,
            err_msg=name,
        )


def test_without_x64_jax_computes_in_float32_close_to_numpy():
    # A fresh process: x64 is a global setting. Warnings are errors there too.
    code = (
        "import warnings\n"
        "warnings.simplefilter('error')\n"
        "import jax, jax.numpy as jnp, numpy as np\n"
        "from targetacq import core\n"
        "from targetacq.core import records\n"
        "from targetacq.scenario.schema import load_scenario\n"
        f"sc = load_scenario({str(GOLDEN / 'features.toml')!r})\n"
        "compiled = core.compile_scenario(sc)\n"
        "s, t, h = core.scenario_positions(sc, sc.time.times())\n"
        "_, want = core.evaluate(compiled.scene, s, t, h)\n"
        "scene = records.as_jax(compiled)\n"
        "_, got = jax.jit(core.evaluate)(scene, jnp.asarray(s), jnp.asarray(t), jnp.asarray(h))\n"
        "assert got.detection.dtype == jnp.float32, got.detection.dtype\n"
        "for name in ('detection', 'recognition', 'identification', 'fused_detection'):\n"
        "    np.testing.assert_allclose(np.asarray(getattr(got, name)), getattr(want, name),\n"
        "                               atol=1e-5, err_msg=name)\n"
        "def fused(sp):\n"
        "    args = (jnp.asarray(t[:, 0]), jnp.asarray(h[:, 0]))\n"
        "    return core.evaluate(scene, sp, *args)[1].fused_detection[1]\n"
        "g = jax.jit(jax.grad(fused))(jnp.asarray(s[:, 0]))\n"
        "assert np.isfinite(np.asarray(g)).all() and np.abs(np.asarray(g)).max() > 0\n"
        "print('ok')\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "ok"


def test_simulation_probabilities_under_jit_and_grad():
    from targetacq.run.simulation import Simulation

    sim = Simulation.from_scenario(ROOT / "examples" / "uav_haze.toml")
    s, t, h = _step(sim.scenario, 60.0)
    pointing = np.array([[np.pi / 2, np.pi / 6]])  # the scenario's own: east, 30° down
    want = sim.probabilities(60.0, s, t, h, pointing)
    got = jax.jit(sim.probabilities)(
        60.0, jnp.asarray(s), jnp.asarray(t), jnp.asarray(h), jnp.asarray(pointing)
    )
    for name in PROBABILITIES:
        value = getattr(got, name)
        assert isinstance(value, jax.Array), name
        np.testing.assert_allclose(
            np.asarray(value), getattr(want, name), rtol=1e-12, atol=0, err_msg=name
        )

    def fused(sensor_positions):
        return sim.probabilities(
            60.0, sensor_positions, jnp.asarray(t), jnp.asarray(h)
        ).fused_detection[1]

    by_position = np.asarray(jax.jit(jax.grad(fused))(jnp.asarray(s)))
    expected = _central_difference(
        lambda sp: sim.probabilities(60.0, sp, t, h).fused_detection[1], s, 1e-3
    )
    assert np.max(np.abs(expected)) > 1e-6
    np.testing.assert_allclose(
        by_position, expected, rtol=1e-6, atol=1e-6 * np.max(np.abs(expected))
    )
    assert sim.time is None  # pure: no step was taken
