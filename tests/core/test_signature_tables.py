"""Signature tables over the aspect in scenarios, the core and the step API.

The expected numbers come from scenes without tables whose target has, as its one temperature,
the table's value at the pair's aspect worked out by hand (the aspect from the stated
convention, the value by linear interpolation between two nodes): the table must change
nothing but the temperature each sensor sees.
"""

from __future__ import annotations

import math
import textwrap

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from targetacq import Simulation, core
from targetacq.core.engines import for_steps, get_engine
from targetacq.scenario.schema import (
    Background,
    ScenarioError,
    Sensor,
    Target,
    load_scenario,
    parse_scenario,
)

SENSOR = Sensor(name="ir", band="lwir", ifov=0.25e-3, position=(0.0, 0.0, 5.0), netd=0.05)
BACKGROUND = Background(temperature=295.0, clutter_std=2.0)
# Front 295.3 K, right and left sides 296 K, rear 298 K, at one elevation.
TABLE = {
    "azimuth": ["0 deg", "90 deg", "180 deg", "270 deg"],
    "elevation": ["0 deg"],
    "temperature": [["295.3 K"], ["296 K"], ["298 K"], ["296 K"]],
}
SENSOR_AT = np.array([[0.0, 2500.0, 5.0]])  # 2.5 km north of the target
TARGET_AT = np.array([[0.0, 0.0, 0.0]])


def _scene(table=None, temperature=None, sensor=SENSOR, background=BACKGROUND):
    target = Target(
        name="truck",
        dimensions=(7.0, 2.5, 3.0),
        temperature=temperature,
        signature_table=table,
        position=(0.0, 0.0, 0.0),
    )
    return Simulation([sensor], [target], background=background, seed=1).compiled.scene


def _by_hand(heading_deg: float) -> float:
    """The table's temperature seen from the north by a target heading ``heading_deg``: the
    observer's azimuth is −heading (mod 360); linear between the two nodes around it."""
    azimuth = (-heading_deg) % 360.0
    nodes = [0.0, 90.0, 180.0, 270.0, 360.0]
    values = [295.3, 296.0, 298.0, 296.0, 295.3]
    i = int(azimuth // 90.0)
    u = (azimuth - nodes[i]) / 90.0
    return (1 - u) * values[i] + u * values[i + 1]


def _evaluate(scene, heading_deg):
    return core.evaluate(scene, SENSOR_AT, TARGET_AT, np.array([math.radians(heading_deg)]))


@pytest.mark.parametrize("heading", [0.0, 90.0, 180.0, 270.0])
def test_at_the_nodes_each_heading_sees_the_tables_temperature(heading):
    found, p = _evaluate(_scene(TABLE), heading)
    ref_found, ref = _evaluate(_scene(temperature=_by_hand(heading)), heading)
    for name in ("snr", "scr", "cycles"):
        np.testing.assert_allclose(getattr(found, name), getattr(ref_found, name), rtol=1e-9)
    for task in ("detection", "recognition", "identification"):
        np.testing.assert_allclose(getattr(p, task), getattr(ref, task), rtol=1e-9, atol=1e-15)


@pytest.mark.parametrize("heading", [30.0, 135.0, 250.0, 315.0])
def test_between_the_nodes_the_signal_is_linear_in_the_aspect(heading):
    # The SCR is the contrast over a fixed clutter: linear between the two nodes' SCRs (each
    # from a scene of the node's one temperature), with the azimuth's fraction between them.
    azimuth = (-heading) % 360.0
    low, high = 90.0 * (azimuth // 90.0), 90.0 * (azimuth // 90.0) + 90.0
    u = (azimuth - low) / 90.0
    node_scr = [
        _evaluate(_scene(temperature=_by_hand(-a)), heading)[0].scr[0, 0] for a in (low, high)
    ]
    found, _ = _evaluate(_scene(TABLE), heading)
    assert found.scr[0, 0] == pytest.approx((1 - u) * node_scr[0] + u * node_scr[1], rel=1e-12)
    # Interpolating the signal rather than the temperature: within 0.1 % of the SNR of the
    # temperature interpolated by hand (Planck's curvature over the nodes' 0.7-2 K).
    ref_found, _ = _evaluate(_scene(temperature=_by_hand(heading)), heading)
    assert found.snr[0, 0] == pytest.approx(ref_found.snr[0, 0], rel=1e-3)


def test_detection_rises_where_the_table_is_warmer():
    front = float(_evaluate(_scene(TABLE), 0.0)[1].detection[0, 0])  # seen head-on: 295.3 K
    rear = float(_evaluate(_scene(TABLE), 180.0)[1].detection[0, 0])  # its rear: 298 K
    assert rear > front + 0.1


@settings(max_examples=25, deadline=None)
@given(
    st.floats(0.0, 2 * math.pi),
    st.floats(-3000.0, 3000.0),
    st.floats(-3000.0, 3000.0),
    st.floats(1.0, 800.0),
    st.floats(290.0, 320.0),
)
def test_a_uniform_table_gives_todays_answer(heading, east, north, up, temperature):
    uniform = {"azimuth": ["0 deg"], "elevation": ["0 deg"], "temperature": [[temperature]]}
    sensors = np.array([[east, north, up]])
    headings = np.array([heading])
    with_table = core.evaluate(_scene(uniform), sensors, TARGET_AT, headings)[1]
    today = core.evaluate(_scene(temperature=temperature), sensors, TARGET_AT, headings)[1]
    for task in ("detection", "recognition", "identification"):
        np.testing.assert_allclose(
            getattr(with_table, task), getattr(today, task), rtol=1e-12, atol=1e-300
        )


def test_elevation_axis_and_batches_of_positions():
    # Warmer seen from above (an engine deck): 296 K level, 300 K from 60 deg up.
    table = {
        "azimuth": ["0 deg"],
        "elevation": ["0 deg", "60 deg"],
        "contrast": [["1 K", "5 K"]],
    }
    scene = _scene(table)
    # One sensor, a batch of heights over the same ground distance of 1 km: level, 60 deg up
    # (the nodes), 79 deg (held at the last node) and 30 deg (halfway between the nodes).
    angles = np.radians([0.0, 60.0, 79.0, 30.0])
    sensors = np.stack([np.zeros(4), np.full(4, 1000.0), 1000.0 * np.tan(angles)], axis=-1)[None]
    targets = np.zeros((1, 4, 3))
    found = core.factors(scene, sensors, targets)
    scr = []
    for k, expected in enumerate([296.0, 300.0, 300.0]):
        alone = core.factors(_scene(temperature=expected), sensors[:, k], targets[:, k])
        np.testing.assert_allclose(found.snr[0, 0, k], alone.snr[0, 0], rtol=1e-9)
        np.testing.assert_allclose(found.scr[0, 0, k], alone.scr[0, 0], rtol=1e-9)
        scr.append(alone.scr[0, 0])
    assert found.scr[0, 0, 3] == pytest.approx(0.5 * (scr[0] + scr[1]), rel=1e-12)


def test_the_numba_engine_refuses_and_auto_takes_numpy():
    scene = _scene(TABLE)
    pytest.importorskip("numba")
    from targetacq.core.engines.numba_engine import supported

    assert "signature tables" in supported(scene)
    assert get_engine("auto").bind(scene).engine == "numpy"
    assert for_steps("auto") is not None


def test_jax_gives_the_numpy_numbers():
    jax = pytest.importorskip("jax")
    jax.config.update("jax_enable_x64", True)
    from targetacq.core.records import as_jax

    scene = _scene(TABLE)
    headings = np.radians([10.0, 200.0])
    sensors = np.array([[[0.0, 2500.0, 5.0], [0.0, 2500.0, 5.0]]])
    targets = np.zeros((1, 2, 3))
    expected = core.evaluate(scene, sensors, targets, headings[None])[1].detection
    run = jax.jit(lambda s, t, h: core.evaluate(as_jax(scene), s, t, h)[1].detection)
    np.testing.assert_allclose(
        np.asarray(run(sensors, targets, headings[None])), expected, rtol=1e-12
    )


def test_the_step_api_follows_the_heading_each_step():
    def detection(heading):
        sim = Simulation(
            [SENSOR],
            [{"name": "truck", "dimensions": (7.0, 2.5, 3.0), "signature_table": TABLE}],
            background=BACKGROUND,
            seed=4,
            engine="auto",
        )
        out = None
        for k in range(31):
            out = sim.step(float(k), 1.0, SENSOR_AT, TARGET_AT, np.array([math.radians(heading)]))
        return out.detection[0, 0]

    assert detection(180.0) > detection(0.0) + 0.1


def test_scenario_files_take_a_table_file_with_states_and_a_written_one(tmp_path):
    (tmp_path / "tank.csv").write_text(
        "# illustrative\nstate,azimuth,elevation,temperature\n"
        "on,0,0,300\non,180,0,320\noff,0,0,296\noff,180,0,297\n"
    )
    text = textwrap.dedent(
        """
        [[sensors]]
        name = "ir"
        band = "lwir"
        ifov = "0.25 mrad"
        position = ["0 m", "0 m", "5 m"]
        [[targets]]
        name = "tank"
        dimensions = ["7 m", "3.5 m", "2.5 m"]
        position = ["2 km", "0 m", "0 m"]
        signature_table = "tank.csv"
        signature_state = "on"
        [[targets]]
        name = "truck"
        dimensions = ["7 m", "2.5 m", "3 m"]
        position = ["2 km", "50 m", "0 m"]
        signature_table = {azimuth = ["0 deg"], elevation = ["0 deg"], contrast = [["4 K"]]}
        [background]
        temperature = "295 K"
        """
    )
    path = tmp_path / "scene.toml"
    path.write_text(text)
    scenario = load_scenario(path)
    assert scenario.targets[0].aspect_table().values == ((300.0,), (320.0,))
    scene = Simulation.from_scenario(scenario).compiled.scene
    assert scene.signature.aspect.contrast.shape == (1, 2, 2, 1)
    # The truck's one contrast of 4 K: its temperature 299 K stands for it where one is needed.
    truck = Simulation.from_scenario(scenario).scenario.targets[1]
    assert truck.temperature is None and truck.aspect_table().quantity == "contrast"
    path.write_text(text.replace('signature_state = "on"', 'signature_state = "idle"'))
    with pytest.raises(ScenarioError, match=r"targets\[0\]\.signature_table: .*choose a state"):
        Simulation.from_scenario(load_scenario(path))


@pytest.mark.parametrize(
    ("table", "message"),
    [
        (
            {"azimuth": ["0 deg"], "elevation": ["0 deg"]},
            "give temperature or contrast",
        ),
        (
            {
                "azimuth": ["90 deg", "0 deg"],
                "elevation": ["0 deg"],
                "temperature": [["300 K"], ["301 K"]],
            },
            "azimuth: values must be strictly ascending",
        ),
        (
            {"azimuth": ["0 deg"], "elevation": ["0 deg"], "temperature": [["300 K", "301 K"]]},
            "grid of 1 azimuths × 1 elevations",
        ),
    ],
)
def test_a_bad_written_table_is_located(table, message):
    data = {
        "sensors": [
            {"name": "ir", "band": "lwir", "ifov": "0.25 mrad", "position": ["0 m", "0 m", "5 m"]}
        ],
        "targets": [
            {
                "name": "t",
                "dimensions": ["7 m", "2 m", "2 m"],
                "position": ["1 km", "0 m", "0 m"],
                "signature_table": table,
            }
        ],
        "background": {"temperature": "295 K"},
    }
    with pytest.raises(ScenarioError) as raised:
        parse_scenario(data, "scene.toml")
    problems = [p for p in raised.value.problems if "signature_table" in p]
    assert problems, raised.value.problems
    # Located at the key the user wrote (not at pydantic's name of the union's branch).
    assert problems[0].startswith("scene.toml: targets[0].signature_table")
    assert ".table" not in problems[0] and "signature table written" not in problems[0]
    assert message in problems[0]


def test_a_table_on_a_digitisers_step_is_refused_and_a_state_needs_a_file():
    sensor = Sensor(
        name="ir", band="lwir", ifov=0.25e-3, position=(0.0, 0.0, 5.0), quantisation_step=1e-4
    )
    with pytest.raises(ScenarioError, match=r"not with sensors\[0\]\.quantisation_step"):
        _scene(TABLE, sensor=sensor)
    with pytest.raises(ValueError, match="signature_state picks a state of a signature table file"):
        Target(
            name="t",
            dimensions=(1.0, 1.0, 1.0),
            position=(0.0, 0.0, 0.0),
            temperature=300.0,
            signature_state="on",
        )
