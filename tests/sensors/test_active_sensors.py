"""Radars and laser radars through the scenario, the core, the step API and the report.

Expected values are written out here from the published equations, independently of the
kernels: the radar equation (K σ τ² / R⁴ with K = P G² λ² τ_p / ((4π)³ k T₀ F L)), the
resolution cells of Eqs. (9.1)-(9.2), the σ⁰ clutter of the cell, Swerling I
(P_d = P_fa^(1/(1+SINR))) and the TTPF; for the laser radar the 3-D clutter measure, the
Lambertian range equation and Eq. (7.7) over the two-way path. The rest are properties:
probabilities fall with range and rain, and rise with the radar cross-section.
"""

from __future__ import annotations

import copy
import itertools
import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from targetacq import Simulation, core
from targetacq.run.model_chain import ModelChain
from targetacq.scenario.schema import ScenarioError, load_scenario, parse_scenario

EXAMPLES = Path(__file__).parents[2] / "examples"
K_BOLTZMANN = 1.380649e-23  # J/K, exact (SI 2019)
C = 299_792_458.0  # m/s, exact
HEIGHT = 12.0


def _radar_document(rcs: str = "10 m^2", rain: str | None = None, **radar: str) -> dict:
    spec = {
        "power": "2 kW",
        "gain": "30 dB",
        "frequency": "10 GHz",
        "pulse_length": "0.2 us",
        "beamwidth": "1.5 deg",
        "noise_figure": "3 dB",
        "losses": "5 dB",
        "false_alarm": 1e-6,
        **radar,
    }
    document = {
        "sensors": [
            {
                "name": "radar",
                "type": "radar",
                "position": ["0 m", "0 m", f"{HEIGHT} m"],
                "radar": spec,
            }
        ],
        "targets": [
            {
                "name": "truck",
                "dimensions": ["7 m", "2.5 m", "3 m"],
                "rcs": rcs,
                "position": ["5 km", "0 m", "0 m"],
            }
        ],
        "background": {"sigma0": "-30 dB"},
        "time": {"start": "0 s", "stop": "0 s", "step": "1 s"},
    }
    if rain is not None:
        document["atmosphere"] = {"rain_rate": rain}
    return document


def _along(chain: ModelChain, ranges: np.ndarray):
    """Factors and probabilities with the target at ground ranges east of the sensor."""
    scene = chain.compiled.scene
    n = ranges.size
    sensors = np.broadcast_to([[[0.0, 0.0, HEIGHT]]], (1, n, 3)).copy()
    targets = np.stack([ranges, np.zeros(n), np.zeros(n)], axis=-1)[None]
    return core.evaluate(scene, sensors, targets)


def test_radar_factors_and_probabilities_from_the_published_equations() -> None:
    chain = ModelChain(parse_scenario(_radar_document()))
    ground = np.array([800.0, 3000.0, 9000.0, 25000.0])
    found, p = _along(chain, ground)
    slant = np.hypot(ground, HEIGHT)
    wavelength = C / 10e9
    gain, noise_figure, losses, sigma0 = 10**3.0, 10**0.3, 10**0.5, 10**-3.0
    constant = (
        2e3 * gain**2 * wavelength**2 * 0.2e-6 / ((4 * math.pi) ** 3 * K_BOLTZMANN * 290.0)
    ) / (noise_figure * losses)
    snr = constant * 10.0 / slant**4
    nadir = np.arctan2(ground, HEIGHT)  # from straight down, at the radar
    along = 2 * slant * math.sin(math.radians(1.5) / 2)  # Eq. (9.1)
    across = C * 0.2e-6 / (2 * np.sin(nadir))  # Eq. (9.2)
    scr = 10.0 / (sigma0 * along * across)
    cells = found.critical_dimension[0, 0] / np.sqrt(along * across)
    np.testing.assert_allclose(found.snr[0, 0], 10 * np.log10(snr), rtol=1e-12)
    np.testing.assert_allclose(found.scr[0, 0], scr, rtol=1e-12)
    np.testing.assert_allclose(found.cycles[0, 0], cells, rtol=1e-12)
    sinr = 1.0 / (1.0 / snr + 1.0 / scr)
    detection = 1e-6 ** (1.0 / (1.0 + sinr))  # Swerling I, one pulse
    np.testing.assert_allclose(p.detection[0, 0], detection, rtol=1e-12)
    x = cells / 8.0  # recognition: 8 cells for P = 0.5 (the project's criteria)
    ttpf = x ** (2.7 + 0.7 * x) / (1 + x ** (2.7 + 0.7 * x))
    np.testing.assert_allclose(p.recognition[0, 0], detection * ttpf, rtol=1e-12)
    assert np.all(p.identification <= p.recognition) and np.all(p.recognition <= p.detection)
    np.testing.assert_allclose(p.fused_detection[0], p.detection[0, 0], rtol=1e-12, atol=1e-16)


def test_radar_probabilities_fall_with_range_and_rain_and_rise_with_rcs() -> None:
    ground = np.geomspace(500.0, 60e3, 200)
    dry = _along(ModelChain(parse_scenario(_radar_document())), ground)[1].detection[0, 0]
    assert np.all(np.diff(dry) <= 0) and dry[0] > 0.5 and dry[-1] < 1e-3
    wet = [
        _along(ModelChain(parse_scenario(_radar_document(rain=rain))), ground)[1].detection[0, 0]
        for rain in ("1 mm/h", "10 mm/h", "50 mm/h")
    ]
    for lighter, heavier in zip([dry, *wet], wet, strict=False):
        assert np.all(heavier <= lighter) and np.any(heavier < lighter)
    rcs = [
        _along(ModelChain(parse_scenario(_radar_document(rcs=v))), ground)[1].detection[0, 0]
        for v in ("1 m^2", "10 m^2", "100 m^2")
    ]
    for small, large in itertools.pairwise(rcs):
        assert np.all(large >= small) and np.any(large > small)


def test_far_targets_go_to_the_false_alarm_probability() -> None:
    """Nothing is detected at any range: as the SNR vanishes P_d falls to P_fa (Swerling I)."""
    p = _along(ModelChain(parse_scenario(_radar_document())), np.array([1e6]))[1]
    assert float(p.detection[0, 0, 0]) == pytest.approx(1e-6, rel=1e-3)


def test_radar_scenarios_are_checked() -> None:
    document = _radar_document()
    document["targets"][0].pop("rcs")
    document["background"].pop("sigma0")
    with pytest.raises(ScenarioError) as error:
        parse_scenario(document)
    assert any("targets[0].rcs" in problem for problem in error.value.problems)
    assert any("background.sigma0" in problem for problem in error.value.problems)
    for change, message in [
        ({"pitch": "17 um"}, "pitch is an imaging sensor's"),
        ({"radar": None}, "needs its radar"),
    ]:
        bad = copy.deepcopy(_radar_document())
        bad["sensors"][0].update(change)
        if change.get("radar", 1) is None:
            bad["sensors"][0].pop("radar")
        with pytest.raises(ScenarioError, match=message):
            parse_scenario(bad)
    bad = _radar_document(pulses=4)  # type: ignore[arg-type]
    bad["sensors"][0]["radar"]["pulses"] = 4
    with pytest.raises(ScenarioError, match="for one pulse"):
        parse_scenario(bad)


def _laser_document(relief: str = "0.3 m") -> dict:
    return {
        "sensors": [
            {
                "name": "ladar",
                "type": "laser_radar",
                "band": "1.5-1.6 um",
                "ifov": "0.2 mrad",
                "position": ["0 m", "0 m", f"{HEIGHT} m"],
                "laser": {
                    "power": "1 kW",
                    "aperture": "50 mm",
                    "timing": "2 ns",
                    "nep": "10 nW",
                    "efficiency": 0.5,
                },
            }
        ],
        "targets": [
            {
                "name": "truck",
                "dimensions": ["7 m", "2.5 m", "3 m"],
                "reflectance": 0.25,
                "position": ["2 km", "0 m", "0 m"],
            }
        ],
        "background": {"relief_std": relief},
        "atmosphere": {"extinction": "0.3 /km"},
        "time": {"start": "0 s", "stop": "0 s", "step": "1 s"},
    }


def test_laser_radar_factors_from_the_published_equations() -> None:
    chain = ModelChain(parse_scenario(_laser_document()))
    ground = np.array([500.0, 2000.0, 6000.0])
    found, p = _along(chain, ground)
    slant = np.hypot(ground, HEIGHT)
    tau = np.exp(-0.3e-3 * slant)
    received = 1e3 * 0.25 * tau**2 * (math.pi * 0.05**2 / 4) * 0.5 / (math.pi * slant**2)
    receiver = (received / 10e-9) ** 2  # an amplitude ratio, squared: power
    path = (tau**2 / (1 - tau**2)) ** 2  # Eq. (7.7) over the two-way path
    expected_snr = 10 * np.log10(1.0 / (1.0 / receiver + 1.0 / path))
    np.testing.assert_allclose(found.snr[0, 0], expected_snr, rtol=1e-12)
    relief = 3.0 / math.sqrt(0.3**2 + (C * 2e-9 / 2) ** 2 / 12)  # height over 3-D clutter
    np.testing.assert_allclose(found.scr[0, 0], relief, rtol=1e-12)
    np.testing.assert_allclose(found.transmittance[0, 0], tau, rtol=1e-12)
    assert np.all(np.diff(p.detection[0, 0]) < 0)


def test_laser_radar_clutter_lowers_detection() -> None:
    """Where the resolution is coarse and the noise small, the 3-D clutter decides."""
    ground = np.array([1000.0, 1500.0, 2500.0])
    found = {}
    # SCR 30 against 0.6: the clutter acts where the SCR is below about 1 (Table 3.5).
    for relief in ("0.05 m", "5 m"):
        document = _laser_document(relief)
        document["sensors"][0].update(ifov="1 mrad")
        document["sensors"][0]["laser"]["nep"] = "0 W"
        document.pop("atmosphere")  # no noise: at low SNR the noise, not the clutter, decides
        with pytest.warns(UserWarning, match="a receiver without noise"):
            scenario = parse_scenario(document)
        found[relief] = _along(ModelChain(scenario), ground)[1].detection[0, 0]
    assert np.all(found["5 m"] < found["0.05 m"])


@pytest.mark.parametrize("name", ["radar_surveillance", "laser_radar", "fused_tv_thermal_radar"])
def test_examples_step_through_the_step_api(name: str) -> None:
    scenario = load_scenario(EXAMPLES / f"{name}.toml")
    chain = ModelChain(scenario)
    sim = Simulation.from_scenario(scenario, seed=3)
    times = np.asarray(scenario.time.times())
    sensors, targets, headings = core.scenario_positions(scenario, times)
    whole = chain.compute(times)
    events: list = []
    # The examples are made so that something is found: P_d of the radar's truck peaks near 0.8,
    # so a run finds it with that probability; among five runs one does (all miss: 6e-4).
    for run in range(5):
        sim.reset(run=run)
        previous = times[0]
        for k, t in enumerate(times):
            out = sim.step(t, t - previous, sensors[:, k], targets[:, k], headings[:, k])
            previous = t
            np.testing.assert_allclose(out.detection, whole["detection"][..., k], rtol=1e-12)
            events += list(out.events)
        if events:
            break
    assert events
    nan = sim.probabilities(times[0], sensors[:, 0], np.full_like(targets[:, 0], np.nan))
    assert np.all(np.isnan(nan.detection))


def test_the_report_has_core_ranges_for_active_sensors(tmp_path: Path) -> None:
    from targetacq.core.pair_ranges import pair_performance

    chain = ModelChain(load_scenario(EXAMPLES / "fused_tv_thermal_radar.toml"))
    performance = pair_performance(chain, [2], [0.5])
    detection = performance.dri.set_index("task").loc["detection"]
    r = float(detection["range_m"])
    assert detection["reached"] and 500.0 < r < 50e3
    # The range is where the core's own curve crosses 0.5 (bisection against the curve).
    curve = performance.curves.sel(case="radar → truck")["detection"]
    assert float(curve.interp(range=r * 0.98)) > 0.5 > float(curve.interp(range=r * 1.02))


def test_core_ranges_agree_with_the_range_solver_for_an_imager() -> None:
    """The core's bisection and the range cases' solver are independent computations of one
    thing for an imager seen level (the critical dimension does not change with range; no
    sensor noise, whose pixels on target the range cases count over the critical dimension
    squared and the core over the outline seen)."""
    from targetacq.core.pair_ranges import pair_performance
    from targetacq.core.ranges import range_performance

    document = {
        "sensors": [
            {
                "name": "ir",
                "type": "thermal",
                "band": "lwir",
                "ifov": "0.1 mrad",
                "position": ["0 m", "0 m", "1.5 m"],
            }
        ],
        "targets": [
            {
                "name": "box",
                "dimensions": ["3 m", "3 m", "3 m"],
                "temperature": "304 K",
                "position": ["4 km", "0 m", "1.5 m"],
                "visible_fraction": 0.5,
            }
        ],
        "background": {"temperature": "300 K"},
        "atmosphere": {"extinction": "0.2 /km"},
        "time": {"start": "0 s", "stop": "0 s", "step": "1 s"},
    }
    chain = ModelChain(parse_scenario(document))
    ours = pair_performance(chain, [0], [0.5, 0.8], max_range=40e3).dri
    theirs = range_performance([1e3, 2e3], chain.range_cases(), [0.5, 0.8]).dri
    np.testing.assert_allclose(ours["range_m"], theirs["range_m"], rtol=1e-6)


def test_dri_and_report_of_a_scenario_on_the_command_line(tmp_path: Path) -> None:
    import json
    import subprocess
    import sys

    path = str(EXAMPLES / "radar_surveillance.toml")
    run = subprocess.run(
        [sys.executable, "-m", "targetacq", "dri", path, "--format", "json"],
        capture_output=True,
        text=True,
        check=True,
    )
    ranges = {(r["pair"], r["task"]): r["range_m"] for r in json.loads(run.stdout)["ranges"]}
    assert ranges[("gsr → truck", "detection")] > 1000.0
    assert ranges[("gsr → truck", "recognition")] is None  # a cell is far larger than a truck
    bad = subprocess.run(
        [sys.executable, "-m", "targetacq", "dri", path, "--pitch", "17um"],
        capture_output=True,
        text=True,
    )
    assert bad.returncode == 2 and len(bad.stderr.strip().splitlines()) == 1
    out = tmp_path / "radar.html"
    subprocess.run(
        [sys.executable, "-m", "targetacq", "report", path, "--out", str(out)],
        capture_output=True,
        check=True,
    )
    page = out.read_text()
    assert "gsr → truck" in page and "radar, 10 GHz" in page


@pytest.mark.parametrize(
    ("document", "message"),
    [
        (_radar_document(rcs="-10 m^2"), r"targets\[0\]: rcs must be >= 0"),
        (_radar_document(rain="2 mm/h", frequency="500 MHz"), r"sensors\[0\].radar.frequency"),
        (  # a band Table 7.1 cannot be read for (the 5-8 um water-vapour absorption)
            {
                **_laser_document(),
                "sensors": [{**_laser_document()["sensors"][0], "band": "6-6.1 um"}],
                "atmosphere": {"obscurant": "haze"},
            },
            r"atmosphere.obscurant: Table 7.1 gives the bands .* got 6-6.1 um",
        ),
        (
            {
                **_laser_document(),
                "atmosphere": {"visibility": "10 km", "visibility_convention": "mor"},
            },
            "atmosphere.visibility",
        ),
    ],
    ids=["negative-rcs", "rain-below-1-GHz", "laser-obscurant", "laser-visibility"],
)
def test_active_sensor_mistakes_are_located(document: dict, message: str) -> None:
    with pytest.raises(ScenarioError, match=message):
        parse_scenario(document)


def test_a_laser_nep_of_0_w_is_the_documented_noiseless_receiver_and_said() -> None:
    # nep = "0 W" was accepted without a word. 0 is documented (Laser, LaserArrays.nep,
    # laser_snr: "0: no receiver noise") and the project's own clutter study uses it, so it
    # stays accepted; typed in a scenario it is now said, naming the input.
    document = _laser_document()
    document["sensors"][0]["laser"]["nep"] = "0 W"
    with pytest.warns(UserWarning, match="laser.nep") as caught:
        quiet = parse_scenario(copy.deepcopy(document))
    (warning,) = caught
    assert str(warning.message).startswith(
        "sensors[0].laser.nep = 0 W: a receiver without noise, so the laser radar 'ladar' sees "
        "only its path's noise"
    )
    # What it means: the receiver adds nothing, so the SNR is the two-way path's alone.
    ground = np.array([500.0, 2000.0])
    found, _ = _along(ModelChain(quiet), ground)
    tau = np.exp(-0.3e-3 * np.hypot(ground, HEIGHT))
    path = (tau**2 / (1 - tau**2)) ** 2  # Eq. (7.7) over the two-way path, as a power ratio
    np.testing.assert_allclose(found.snr[0, 0], 10 * np.log10(path), rtol=1e-12)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a receiver's NEP given: nothing to say
        parse_scenario(_laser_document())


def test_the_laser_radar_noise_is_its_receiver() -> None:
    document = _laser_document()
    document["sensors"][0]["netd"] = "50 mK"
    with pytest.raises(ScenarioError, match=r"laser\.nep"):
        parse_scenario(document)


def test_a_radar_beside_imagers_changes_nothing_of_theirs() -> None:
    """Adding a radar (and rain, which only a radar feels) leaves every imager's numbers as
    they were: the rows are computed by kind, not mixed."""
    scenario = load_scenario(EXAMPLES / "fused_tv_thermal_radar.toml")
    times = np.asarray(scenario.time.times())
    whole = ModelChain(scenario).compute(times)
    imagers = scenario.model_copy(
        update={
            "sensors": scenario.sensors[:2],
            "atmosphere": scenario.atmosphere.model_copy(update={"rain_rate": None}),
        }
    )
    alone = ModelChain(imagers).compute(times)
    for name in ("detection", "recognition", "identification", "snr", "cycles"):
        # To rounding: with a radar the core takes its generic path (tests/core/test_numpy_paths.py)
        np.testing.assert_allclose(
            whole[name][:2], alone[name], rtol=1e-12, atol=1e-16, err_msg=name
        )


def test_the_jax_engine_says_marcum_is_numpy_only() -> None:
    pytest.importorskip("jax")
    document = _radar_document(detector="marcum")
    document["sensors"][0]["radar"]["detector"] = "marcum"
    scenario = parse_scenario(document)
    with pytest.raises(ValueError, match="'radar': detector 'marcum' runs on NumPy only"):
        ModelChain(scenario, engine="jax")
    assert ModelChain(scenario).compute([0.0])["detection"].shape == (1, 1, 1)
