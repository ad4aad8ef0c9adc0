"""SWIR imagers (``type = "swir"``): the signal, the band, the path, and every front-end.

Expected values: the emitted part by numerical quadrature of Planck's law (CODATA constants,
Sonesson 2004 Eq. (6.2)), the reflected part by its closed form ``r · E`` (§6.2), the path by
Beer–Lambert (7.3) with Table 7.1's haze cells interpolated by hand, and properties (more
contrast, a higher P; a band outside 0.9–2.5 µm refused).
"""

import copy
import itertools
import json
import math
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy import integrate

from targetacq import Simulation, core
from targetacq.run.model_chain import ModelChain
from targetacq.scenario.schema import ScenarioError, load_scenario, parse_scenario
from targetacq.sensors import SENSOR_TYPES, swir

EXAMPLE = Path(__file__).parents[2] / "examples" / "swir_mast_haze.toml"
DOCUMENT = tomllib.loads(EXAMPLE.read_text(encoding="utf-8"))

H, C, K = 6.62607015e-34, 299792458.0, 1.380649e-23  # CODATA 2018, exact


def planck_band(temperature: float, low: float, high: float) -> float:
    """∫ M_λ dλ over [low, high] [W/m²] by adaptive quadrature of Eq. (6.2)."""

    def m(lam: float) -> float:
        x = H * C / (lam * K * temperature)
        return 0.0 if x > 700 else 2 * math.pi * H * C**2 / lam**5 / math.expm1(x)

    value, _ = integrate.quad(m, low, high, epsabs=0.0, epsrel=1e-11, limit=200)
    return value


def _document(**changes) -> dict:
    """The bundled example with changes: ``target``/``background``/``sensor``/``atmosphere``
    dicts merged into the first target, the background, the sensor or the atmosphere."""
    doc = copy.deepcopy(DOCUMENT)
    for key, where in (
        ("target", doc["targets"][0]),
        ("background", doc["background"]),
        ("sensor", doc["sensors"][0]),
    ):
        for name, value in changes.get(key, {}).items():
            if value is None:
                where.pop(name, None)
            else:
                where[name] = value
    if "atmosphere" in changes:
        doc["atmosphere"] = changes["atmosphere"]
    return doc


# -- the signal ----------------------------------------------------------------------------------


@pytest.mark.parametrize("temperature", [250.0, 300.0, 700.0, 1500.0])
@pytest.mark.parametrize("band", [(0.9e-6, 2.5e-6), (1.0e-6, 1.7e-6), (2.0e-6, 2.5e-6)])
def test_the_emitted_part_is_planck_over_the_band_times_one_minus_r(temperature, band):
    r, irradiance = 0.3, 200.0
    emitted = swir.exitance(r, irradiance, temperature, band) - swir.exitance(
        r, 0.0, temperature, band
    )
    assert emitted == pytest.approx(r * irradiance, rel=1e-12)  # adding E adds r·E only
    assert swir.exitance(r, 0.0, temperature, band) == pytest.approx(
        (1 - r) * planck_band(temperature, *band), rel=1e-7
    )


def test_the_reflected_part_is_r_times_e_in_its_closed_form():
    band = (0.9e-6, 2.5e-6)
    r = np.array([0.0, 0.1, 0.5, 1.0])
    cold = swir.exitance(r, 300.0, 3.0, band)  # 3 K: no emission in the short-wave IR
    np.testing.assert_allclose(cold, r * 300.0, rtol=1e-12, atol=1e-300)
    assert swir.exitance(1.0, 0.0, 2000.0, band) == 0.0  # a perfect reflector emits nothing


def test_the_scenario_signature_is_reflected_plus_emitted_with_the_file_s_values():
    scenario = load_scenario(EXAMPLE)
    sensor = scenario.sensors[0]
    seen = SENSOR_TYPES["swir"].signature(sensor, scenario.background, scenario.targets)
    band = (1.0e-6, 1.7e-6)  # band = "1-1.7 um"
    assert sensor.limits == pytest.approx(band)
    target = 0.1 * 150.0 + 0.9 * planck_band(306.0, *band)
    background = 0.35 * 150.0 + 0.65 * planck_band(295.0, *band)
    assert float(seen.target[0]) == pytest.approx(target, rel=1e-7)
    assert seen.background == pytest.approx(background, rel=1e-7)
    # The camera's noise: nec x the background's signal, as for a TV camera.
    assert SENSOR_TYPES["swir"].noise_equivalent(sensor, seen) == pytest.approx(0.01 * background)


def test_more_reflectance_contrast_gives_a_higher_probability():
    detection = []
    for r in (0.1, 0.34, 0.345, 0.349):  # against a background of 0.35
        ds = ModelChain(parse_scenario(_document(target={"reflectance": r}))).evaluate().dataset
        detection.append(ds["detection"].values.ravel())
    for more, less in itertools.pairwise(detection):
        assert np.all(more >= less - 1e-12)
    assert np.any(detection[0] > detection[-1] + 0.01)


def test_a_hot_target_is_seen_by_its_emission_alone():
    # Same reflectance as the background: no reflected contrast; at 700 K the emission makes one.
    cool = _document(target={"reflectance": 0.35, "temperature": "295 K"})
    hot = _document(target={"reflectance": 0.35, "temperature": "700 K"})
    p = [ModelChain(parse_scenario(d)).evaluate().dataset["detection"].values for d in (cool, hot)]
    assert float(p[0].max()) == 0.0 and float(p[1].max()) > 0.01
    # Under the thesis's SNR law the haze's noise ignores the contrast, and the emission's
    # contrast is seen at P > 0.5 on the way; the default contrast law weighs it (ratio 0.33 of
    # the background's exitance) against the haze's path radiance, which mostly hides it.
    for d in (cool, hot):
        d["model"] = {**d.get("model", {}), "snr_law": "sonesson"}
    p = [ModelChain(parse_scenario(d)).evaluate().dataset["detection"].values for d in (cool, hot)]
    assert float(p[1].max()) > float(p[0].max()) + 0.5


# -- the band and the scenario's checks -----------------------------------------------------------


def test_a_swir_sensor_without_a_band_takes_0_9_to_2_5_um():
    scenario = parse_scenario(_document(sensor={"band": None}))
    assert scenario.sensors[0].limits == pytest.approx((0.9e-6, 2.5e-6))


@pytest.mark.parametrize("band", ["0.8-1.7 um", "mwir", "1-3 um", "visible"])
def test_a_band_outside_0_9_to_2_5_um_is_refused_naming_the_key_and_range(band):
    expected = r"sensors\[0\].*band of a swir sensor must lie within 0\.9-2\.5 um; got "
    with pytest.raises(ScenarioError, match=expected):
        parse_scenario(_document(sensor={"band": band}))


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"target": {"temperature": None}}, r"targets\[0\].temperature: SWIR sensors need"),
        ({"target": {"reflectance": None}}, r"targets\[0\].reflectance: SWIR sensors need"),
        ({"background": {"irradiance": None}}, "background.irradiance: required with SWIR"),
        ({"background": {"temperature": None}}, "background.temperature: required with SWIR"),
        (
            {"atmosphere": {"visibility": "10 km", "visibility_convention": "mor"}},
            "atmosphere.visibility: gives the visible-band extinction; with SWIR sensors",
        ),
        ({"sensor": {"nec": None, "netd": "50 mK"}}, "netd is the noise-equivalent temperature"),
        (
            {"background": {"clutter": None, "clutter_std": "2 K"}},
            "background.clutter_std: a temperature spread; for SWIR sensors",
        ),
    ],
)
def test_what_a_swir_scenario_lacks_is_located(changes, message):
    with pytest.raises(ScenarioError, match=message):
        parse_scenario(_document(**changes))


def test_the_path_is_the_atmosphere_model_in_the_sensor_s_band():
    ds = ModelChain(load_scenario(EXAMPLE)).evaluate().dataset
    # Haze, 1-1.7 um (centre 1.35 um): Table 7.1's visible (0.2-2.0 Np/km, at 0.55 um) and
    # mid-wave (0.02-1.0 Np/km, at 4 um) cell ends interpolated log-log, the geometric mean.
    w = math.log(1.35 / 0.55) / math.log(4.0 / 0.55)
    low, high = 0.2 * (0.02 / 0.2) ** w, 2.0 * (1.0 / 2.0) ** w
    gamma = math.sqrt(low * high) / 1e3  # Np/m
    rng = ds["range"].values.ravel()
    np.testing.assert_allclose(ds["transmittance"].values.ravel(), np.exp(-gamma * rng), rtol=1e-9)


# -- every front-end ---------------------------------------------------------------------------


def test_validate_evaluate_and_simulate_take_the_example(cli, tmp_path):
    code, out, _ = cli("validate", str(EXAMPLE))
    assert code == 0 and "valid" in out
    code, _, _ = cli("evaluate", str(EXAMPLE), "--out", str(tmp_path / "e.csv"))
    assert code == 0 and "mast-swir" in (tmp_path / "e.csv").read_text()
    code, out, _ = cli(
        "simulate", str(EXAMPLE), "--runs", "20", "--duration", "600 s", "--step", "5 s"
    )
    assert code == 0 and "truck" in out


def test_dri_of_the_scenario_gives_ordered_ranges(cli):
    code, out, _ = cli("dri", str(EXAMPLE), "--format", "json")
    assert code == 0
    text = json.dumps(json.loads(out))
    ranges = [float(v) for v in _numbers(json.loads(out), "range_m")]
    assert "mast-swir" in text and len(ranges) == 3
    assert all(math.isfinite(r) and r > 0 for r in ranges)
    assert ranges[0] > ranges[1] > ranges[2]  # detection, recognition, identification


def _numbers(value, key):
    if isinstance(value, dict):
        for k, v in value.items():
            if k == key and isinstance(v, int | float):
                yield v
            else:
                yield from _numbers(v, key)
    elif isinstance(value, list):
        for v in value:
            yield from _numbers(v, key)


def test_report_of_the_scenario(cli, tmp_path):
    out = tmp_path / "swir.html"
    code, _, _ = cli("report", str(EXAMPLE), "--out", str(out))
    assert code == 0 and "mast-swir" in out.read_text(encoding="utf-8")


def test_the_step_api_steps_a_swir_sensor_as_the_model_chain_evaluates_it():
    scenario = load_scenario(EXAMPLE)
    times = np.asarray(scenario.time.times())
    sensors, targets, headings = core.scenario_positions(scenario, times)
    whole = ModelChain(scenario).evaluate().dataset["detection"].values.ravel()
    sim = Simulation.from_scenario(scenario, seed=1)
    previous = times[0]
    for k, t in enumerate(times):
        out = sim.step(t, t - previous, sensors[:, k], targets[:, k], headings[:, k])
        previous = t
        assert float(np.ravel(out.detection)[0]) == pytest.approx(whole[k], rel=1e-9)


def test_the_web_explorer_evaluates_a_swir_scenario():
    pytest.importorskip("fastapi")
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="Using `httpx` with `starlette.testclient`")
        from fastapi.testclient import TestClient

    from targetacq.web.api import create_app

    with TestClient(create_app(), base_url="http://127.0.0.1") as client:
        got = client.post("/evaluate", json={"scenario": EXAMPLE.read_text()})
        assert got.status_code == 200, got.text
        ds = ModelChain(load_scenario(EXAMPLE)).evaluate().dataset
        assert got.json()["sensors"] == ["mast-swir"]
        np.testing.assert_allclose(
            got.json()["detection"], ds["detection"].transpose("sensor", "target", "time").values
        )
        names = [item["name"] for item in client.get("/registries").json()["sensor_types"]]
        assert "swir" in names


def test_the_environment_runs_swir_cameras():
    gymnasium = pytest.importorskip("gymnasium")
    from gymnasium.utils.env_checker import check_env

    from targetacq.envs import SensorPointingEnv
    from targetacq.envs.pointing import CAMERA_TYPES

    assert "swir" in CAMERA_TYPES
    env = gymnasium.make(
        "targetacq/SensorPointing-v0", targets=3, duration=60.0, camera_type="swir"
    )
    check_env(env.unwrapped, skip_render_check=True)
    env = SensorPointingEnv(targets=4, duration=120.0, camera_type="swir")
    env.reset(seed=2)
    assert env._sim is not None and env.unwrapped.camera_type == "swir"
    total, done = 0.0, False
    while not done:
        _, reward, terminated, truncated, _ = env.step(env.greedy_action())
        total += reward
        done = terminated or truncated
    assert total > 0  # the cameras acquire something over the flight
    with pytest.raises(ValueError, match="camera_type must be one of thermal, tv, swir"):
        SensorPointingEnv(camera_type="radar")
