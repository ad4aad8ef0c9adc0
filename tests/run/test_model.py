"""ModelChain: the pipeline adds nothing of its own; results, chunks and files."""

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import targetacq as ta
from targetacq.physics import geometry
from targetacq.physics.radiometry import band_exitance_derivative, material_emissivity
from targetacq.run.model_chain import ModelChain, evaluate
from targetacq.scenario.schema import load_scenario, parse_scenario

EXAMPLES = Path(__file__).parents[2] / "examples"


def test_uav_example_agrees_with_the_functions_called_by_hand():
    scenario = load_scenario(EXAMPLES / "uav_haze.toml")
    ds = evaluate(scenario).dataset
    sensor = scenario.sensors[0]
    gamma = ta.obscurant_extinction("haze", "lwir", "high")
    eps_b = material_emissivity("vegetation", "lwir")
    m_b = eps_b * ta.band_exitance(295.0, "lwir")
    clutter = eps_b * band_exitance_derivative(295.0, "lwir") * 2.0
    checked = 0
    for g, target in enumerate(scenario.targets):
        m_t = material_emissivity("olive-paint", "lwir") * ta.band_exitance(
            target.temperature, "lwir"
        )
        scr = abs(m_t - m_b) / clutter
        assert float(ds["scr"][0, g]) == pytest.approx(scr, rel=1e-12)
        for k, t in enumerate(ds["time"].values):
            s_pos = geometry.positions_at(
                [t], [w.time for w in sensor.waypoints], [w.position for w in sensor.waypoints]
            )[0]
            if target.waypoints is None:
                g_pos = np.array(target.position)
                heading = target.heading
            else:
                wt = [w.time for w in target.waypoints]
                wp = [w.position for w in target.waypoints]
                g_pos = geometry.positions_at([t], wt, wp)[0]
                heading = math.atan2(wp[1][0] - wp[0][0], wp[1][1] - wp[0][1])
            los = g_pos - s_pos
            rng = float(np.linalg.norm(los))
            aspect = math.atan2(los[0], los[1]) - heading
            depression = abs(math.atan2(los[2], math.hypot(los[0], los[1])))
            h, v = ta.projected_extents(*target.dimensions, aspect, depression)
            d = min(h, v)
            n = ta.cycles_on_target(d, rng, sensor.pixel_ifov, wavelength=10e-6, aperture=0.035)
            snr = ta.snr_from_transmittance(ta.transmittance(gamma, rng))
            acq = ta.acquisition_probabilities(
                n, target.criterion, clutter=ta.Clutter(scr=scr, moving=target.moving), snr=snr
            )
            assert float(ds["range"][0, g, k]) == pytest.approx(rng, rel=1e-12)
            assert float(ds["cycles"][0, g, k]) == pytest.approx(n, rel=1e-12)
            assert float(ds["snr"][0, g, k]) == pytest.approx(snr, rel=1e-9, abs=1e-9)
            if bool(ds["in_view"][0, g, k]):
                checked += 1
                for task in ("detection", "recognition", "identification"):
                    assert float(ds[task][0, g, k]) == pytest.approx(
                        getattr(acq, task), rel=1e-12, abs=1e-15
                    )
            else:
                assert float(ds["detection"][0, g, k]) == 0.0
    assert checked >= 5


def test_fusion_of_two_sensors_is_eq_8_4():
    ds = evaluate(load_scenario(EXAMPLES / "two_sensors_fused.toml")).dataset
    for task in ("detection", "recognition", "identification"):
        expected = 1 - (1 - ds[task].sel(sensor="tv")) * (1 - ds[task].sel(sensor="thermal"))
        np.testing.assert_allclose(ds[f"fused_{task}"], expected, rtol=1e-12, atol=1e-15)


def test_tv_sensor_contrast_is_reflected_light():
    scenario = load_scenario(EXAMPLES / "two_sensors_fused.toml")
    chain = ModelChain(scenario)
    assert chain.contrast[0, 0] == pytest.approx(abs(0.075 - 0.1) * 500.0)


def _one_target(position, **sensor):
    return parse_scenario(
        {
            "sensors": [
                {
                    "name": "s",
                    "band": "lwir",
                    "pixels": [640, 480],
                    "ifov": "0.2 mrad",
                    "position": ["0 m", "0 m", "2 m"],
                    **sensor,
                }
            ],
            "targets": [
                {
                    "name": "t",
                    "dimensions": ["6 m", "3 m", "2.5 m"],
                    "temperature": "300 K",
                    "position": position,
                }
            ],
            "background": {"temperature": "290 K"},
        }
    )


def test_outside_the_field_of_view_probability_is_zero():
    ahead = _one_target(["0 m", "1 km", "0 m"], azimuth="0 deg", depression="0 deg")
    behind = _one_target(["0 m", "-1 km", "0 m"], azimuth="0 deg", depression="0 deg")
    aside = _one_target(["1 km", "1 km", "0 m"], azimuth="0 deg", depression="0 deg")
    assert float(evaluate(ahead).dataset["detection"][0, 0, 0]) > 0.9
    for scenario in (behind, aside):
        ds = evaluate(scenario).dataset
        assert not bool(ds["in_view"][0, 0, 0])
        assert float(ds["detection"][0, 0, 0]) == 0.0


def test_viewing_geometry_sets_the_critical_dimension():
    # Broadside at eye level: the 2.5 m height; from straight above: the 3 m width.
    side = evaluate(_one_target(["0 m", "1 km", "2 m"])).dataset
    top = evaluate(_one_target(["0 m", "0 m", "-1 km"])).dataset  # sensor 1 km above
    assert float(side["critical_dimension"][0, 0, 0]) == pytest.approx(2.5, rel=1e-6)
    assert float(top["critical_dimension"][0, 0, 0]) == pytest.approx(3.0, rel=1e-6)


def test_chunks_equal_the_whole_and_tables_round_trip(tmp_path):
    chain = ModelChain(load_scenario(EXAMPLES / "two_sensors_fused.toml"))
    whole = chain.evaluate().dataset
    for targets, times, arrays in chain.evaluate_chunks(targets_per_chunk=1, times_per_chunk=5):
        part = whole.isel(target=targets).sel(time=times)
        np.testing.assert_array_equal(arrays["detection"], part["detection"].values)
        np.testing.assert_array_equal(
            arrays["fused_identification"], part["fused_identification"].values
        )
    results = chain.evaluate()
    frame = results.to_dataframe()
    assert len(frame) == 2 * 2 * 13
    for suffix, read in (
        (".csv", lambda path: pd.read_csv(path, comment="#")),  # units and provenance first
        (".json", lambda path: pd.DataFrame(json.loads(path.read_text())["rows"])),
        (".parquet", pd.read_parquet),
    ):
        out = results.write(tmp_path / f"results{suffix}")
        back = read(out)
        assert len(back) == len(frame)
        np.testing.assert_allclose(back["detection"], frame["detection"], rtol=1e-12)


def test_bad_output_leaves_nothing(tmp_path):
    results = evaluate(load_scenario(EXAMPLES / "ground_observer_aircraft.toml"))
    with pytest.raises(ValueError, match=r"must end in \.csv, \.json, \.parquet, \.nc or \.zarr"):
        results.write(tmp_path / "results.xlsx")
    with pytest.raises(ValueError, match="does not exist"):
        results.write(tmp_path / "missing" / "results.csv")
    assert list(tmp_path.iterdir()) == []


def _clutter_scene(background, boxes=None):
    targets = [
        {
            "name": "a",
            "dimensions": ["6 m", "3 m", "2.5 m"],
            "temperature": "305 K",
            "position": ["1 km", "0 m", "0 m"],
        },
        {
            "name": "b",
            "dimensions": ["6 m", "3 m", "2.5 m"],
            "temperature": "300 K",
            "position": ["2 km", "15 m", "0 m"],
        },
    ]
    if boxes:
        for target, box in zip(targets, boxes):
            target["image_box"] = box
    return parse_scenario(
        {
            "sensors": [
                {
                    "name": "s",
                    "band": "lwir",
                    "ifov": "0.2 mrad",
                    "position": ["0 m", "0 m", "10 m"],
                }
            ],
            "targets": targets,
            "background": {"temperature": "295 K", **background},
        }
    )


def test_scr_measured_in_a_background_image():
    from targetacq.io.images import read_image
    from targetacq.physics.clutter import image_clutter

    image = str(Path(__file__).parents[1] / "data" / "camera.png")
    boxes = [(412, 118, 20, 20), (228, 470, 24, 24)]
    ds = evaluate(_clutter_scene({"image": image}, boxes)).dataset
    expected = image_clutter(read_image(image), boxes).scr
    np.testing.assert_allclose(ds["scr"].values[0], expected)
    with pytest.raises(ValueError, match="needs an image_box for every target"):
        _clutter_scene({"image": image}, [boxes[0], None])


def test_terrain_clutter_per_triple(tmp_path):
    grid = tmp_path / "map.csv"
    np.savetxt(grid, np.array([[0, 0, 1, 1]] * 4), fmt="%d", delimiter=",")
    terrain = {
        "map": str(grid),
        "cell_size": "1 km",
        "origin": ["0 m", "-2 km"],
        "classes": [
            {
                "name": "grass",
                "temperature": "293 K",
                "temperature_std": "1 K",
                "resolution": "0.1 m",
            },
            {
                "name": "forest",
                "temperature": "290 K",
                "temperature_std": "3 K",
                "resolution": "0.5 m",
            },
        ],
    }
    chain = ModelChain(_clutter_scene({"terrain": terrain}))
    ds = chain.evaluate().dataset
    # Target a (x = 1 km, window 15 m) stands in grass; b (x = 2 km) on the class boundary.
    m_t = ta.band_exitance(305.0, "lwir")
    grass_mean = ta.band_exitance(293.0, "lwir")
    grass_sigma = band_exitance_derivative(293.0, "lwir") * 1.0
    footprint = float(ds["range"][0, 0, 0]) * 2e-4
    sigma = grass_sigma * min(1.0, 0.1 / footprint)
    assert float(ds["scr"][0, 0, 0]) == pytest.approx(abs(m_t - grass_mean) / sigma, rel=1e-9)
    m_b = ta.band_exitance(300.0, "lwir")
    forest_mean = ta.band_exitance(290.0, "lwir")
    forest_sigma = band_exitance_derivative(290.0, "lwir") * 3.0
    foot_b = float(ds["range"][0, 1, 0]) * 2e-4
    var = (
        0.5 * (grass_sigma * min(1, 0.1 / foot_b)) ** 2
        + 0.5 * (forest_sigma * min(1, 0.5 / foot_b)) ** 2
    )
    mean = 0.5 * (grass_mean + forest_mean)
    assert float(ds["scr"][0, 1, 0]) == pytest.approx(abs(m_b - mean) / math.sqrt(var), rel=1e-9)
    assert "scr" in chain.evaluate().to_dataframe().columns


def test_terrain_chunks_equal_the_whole():
    path = Path(__file__).parents[1] / "data" / "golden" / "terrain.toml"
    chain = ModelChain(load_scenario(path))
    whole = chain.evaluate().dataset
    for targets, times, arrays in chain.evaluate_chunks(targets_per_chunk=1, times_per_chunk=2):
        part = whole.isel(target=targets).sel(time=times)
        np.testing.assert_array_equal(arrays["scr"], part["scr"].values)
        np.testing.assert_array_equal(arrays["detection"], part["detection"].values)


def test_range_cases_carry_the_sensor_noise_and_the_model_choices():
    from targetacq.scenario.schema import Scenario

    base = load_scenario(EXAMPLES / "uav_haze.toml")
    data = base.model_dump(mode="python", exclude_none=True)
    data["sensors"][0]["netd"] = 0.05
    data["model"]["semantics"] = "conditional"
    cases = ModelChain(Scenario.model_validate(data)).range_cases()
    case = next(iter(cases.values()))
    assert case.semantics == "conditional"
    assert case.noise_equivalent_contrast > 0 and case.contrast > 0
    assert next(iter(ModelChain(base).range_cases().values())).contrast is None
