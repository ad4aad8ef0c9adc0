"""The NumPy paths of the core and its kernels give the numbers of the generic computation.

The core's NumPy path computes the factors block by block and the probabilities of the pairs in
view only, with the noise as an amplitude ratio from the optical depth; the kernels have NumPy
paths with fewer temporaries and ``where`` guards. Each is checked against the generic
(whole-array, any-namespace) computation of the same formulas, which is the reference: exactly
where the operations are the same, to 1e-12 relative where the noise goes through the decibels.
"""

import copy
import dataclasses
import math
import pickle
import sys
from pathlib import Path

import array_api_strict as xps
import numpy as np
import pytest

import targetacq as ta
from targetacq import core
from targetacq.acquisition import path_noise as noise
from targetacq.acquisition import probabilities as acquisition
from targetacq.acquisition import transforms
from targetacq.core import active
from targetacq.core.records import derived
from targetacq.physics import atmosphere, geometry
from targetacq.scenario.schema import load_scenario, parse_scenario

ROOT = Path(__file__).parents[2]
GOLDEN = Path(__file__).parents[1] / "data" / "golden"
EVALUATE = sys.modules["targetacq.core.evaluation"]
FACTORS = (
    "range",
    "critical_dimension",
    "cycles",
    "optical_depth",
    "transmittance",
    "snr",
)
TASKS = ("detection", "recognition", "identification")
FUSED = tuple(f"fused_{task}" for task in TASKS)


def _sensor(i, **changes):
    sensor = {
        "name": f"s{i}",
        "band": ("lwir", "mwir", "8-12 um")[i % 3],
        "pixels": [640, 512],
        "pitch": "17 um",
        "focal_length": "35 mm",
        "position": ["0 m", "0 m", "1000 m"],
    }
    return {**sensor, **changes}


def _target(j, rng, **changes):
    target = {
        "name": f"t{j}",
        "dimensions": [f"{rng.uniform(1, 8):.2f} m", f"{rng.uniform(1, 4):.2f} m", "2 m"],
        "temperature": f"{rng.uniform(280, 330):.2f} K",
        "heading": f"{rng.uniform(0, 360):.1f} deg",
        "position": ["0 m", "0 m", "0 m"],
    }
    return {**target, **changes}


def _mixed_targets(rng, count=13):
    """Hot spots, moving targets, two criteria and hidden targets among ordinary ones."""
    return [
        _target(
            j,
            rng,
            **({"hot_spot": True} if j % 5 == 1 else {}),
            **({"moving": True} if j % 7 == 2 else {}),
            **({"criterion": "c2nveo"} if j % 4 == 3 else {}),
            **({"visible_fraction": 0.5} if j % 3 == 0 else {}),
        )
        for j in range(count)
    ]


SENSORS = [
    _sensor(0, azimuth="20 deg", depression="10 deg"),
    _sensor(1, look_at=["2 km", "1 km", "0 m"]),
    _sensor(2),  # pointed nowhere: sees every target
    _sensor(3, azimuth="200 deg", depression="-5 deg", netd="50 mK"),
    _sensor(4, azimuth="90 deg", depression="90 deg", netd="30 mK"),  # straight down
]
ANGLES_ONLY = [SENSORS[0], SENSORS[3], _sensor(5, azimuth="300 deg", depression="20 deg")]


def _variants():
    rng = np.random.default_rng(11)
    haze = {"obscurant": "haze"}
    return {
        "noise-clutter-segments-cloud": {
            "sensors": SENSORS,
            "targets": _mixed_targets(rng),
            "background": {"temperature": "293 K", "clutter_std": "2 K"},
            "atmosphere": {
                "obscurant": "haze",
                "segments": [{"length": "300 m", "extinction": "2 /km"}],
                "clouds": [
                    {"center": ["1 km", "500 m", "5 m"], "radius": "300 m", "extinction": "9 /km"}
                ],
            },
        },
        "scr-fog": {
            "sensors": SENSORS,
            "targets": _mixed_targets(rng),
            "background": {"temperature": "293 K", "scr": 0.2},
            "atmosphere": {"obscurant": "fog:low"},
        },
        "analogue-region-conditional": {
            "sensors": SENSORS,
            "targets": _mixed_targets(rng),
            "background": {"temperature": "293 K", "clutter": "high"},
            "atmosphere": {"extinction": "0.5 /km"},
            "model": {
                "noise_model": "clutter-analogue",
                "semantics": "conditional",
                "motion": "always",
            },
        },
        "noise-ignored": {
            "sensors": SENSORS,
            "targets": _mixed_targets(rng),
            "background": {"temperature": "293 K", "clutter_std": "5 K"},
            "atmosphere": haze,
            "model": {"noise_model": "none"},
        },
        "sensor-noise-only": {
            "sensors": SENSORS,
            "targets": _mixed_targets(rng),
            "background": {"temperature": "293 K", "clutter_std": "0.5 K"},
        },
        "c2nveo-angles": {
            "sensors": ANGLES_ONLY,
            "targets": [_target(j, rng) for j in range(7)],
            "background": {"temperature": "293 K"},
            "atmosphere": haze,
            "model": {"transform": "c2nveo", "bound": "optimistic"},
        },
    }


VARIANTS = _variants()


def _positions(scene, batch, rng, special):
    n_s, n_g = scene.shape
    sensors = rng.uniform(-3000.0, 3000.0, (n_s, *batch, 3))
    sensors[..., 2] = rng.uniform(0.0, 2000.0, (n_s, *batch))
    targets = rng.uniform(-3000.0, 3000.0, (n_g, *batch, 3))
    targets[..., 2] = 0.0
    # Some targets along a sensor's boresight, so that every pointed sensor sees some.
    (east, north, up), _ = EVALUATE.boresight(sensors, scene.sensors)
    forward = np.stack([east, north, up], axis=-1)
    forward /= np.linalg.norm(forward, axis=-1, keepdims=True)
    for j in range(3, n_g, 2):
        s = j % n_s
        reach = rng.uniform(500.0, 3000.0)
        targets[j] = sensors[s] + reach * forward[s] + rng.normal(0.0, 20.0, sensors[s].shape)
    if special:  # straight below a sensor, at a sensor, NaN target, NaN sensor
        targets[0] = sensors[0] * [1.0, 1.0, 0.0]
        targets[1] = sensors[1]
        targets[2, ..., 0] = np.nan
        sensors[2, ..., 1] = np.nan
    return sensors, targets


def _same_factors(got, want):
    for name in FACTORS:
        np.testing.assert_allclose(
            getattr(got, name), getattr(want, name), rtol=1e-12, atol=0, err_msg=name
        )
    np.testing.assert_array_equal(got.in_view, want.in_view)


def _same_probabilities(got, want):
    for name in TASKS + FUSED:
        np.testing.assert_allclose(
            getattr(got, name), getattr(want, name), rtol=1e-12, atol=1e-300, err_msg=name
        )


def _check_core(scene, sensors, targets, **given):
    found, probs = core.evaluate(scene, sensors, targets, **given)
    generic = EVALUATE._factors_generic(
        scene,
        sensors,
        targets,
        given.get("headings"),
        given.get("pointing"),
        given.get("scr"),
        np,
    )
    tasks = None
    if active.has_active(scene):  # radars and laser radars: their rows' own factors
        generic = active.active_factors(scene, generic, sensors, targets)
        tasks = active.active_probabilities(scene, generic, EVALUATE.task_probabilities)
    _same_factors(found, generic)
    # The probabilities of every pair computed generically, then masked by the field of view.
    expected = EVALUATE._probabilities_generic(scene, generic, tasks)
    if scene.sensors.groups:  # colour cameras: the best band of each
        expected = dataclasses.replace(
            expected,
            **{
                f"fused_{task}": ta.fuse_groups(getattr(expected, task), scene.sensors.groups)
                for task in ("detection", "recognition", "identification")
            },
        )
    _same_probabilities(probs, expected)
    # Factors made otherwise (here a copy): the noise through the decibels, the same numbers.
    _same_probabilities(core.probabilities(scene, dataclasses.replace(found)), probs)
    return found


@pytest.mark.parametrize("name", sorted(VARIANTS))
@pytest.mark.parametrize("batch", [(), (7,), (2, 3)])
def test_core_numpy_path_equals_the_generic_path(name, batch):
    scene = core.compile_scenario(parse_scenario(copy.deepcopy(VARIANTS[name]))).scene
    rng = np.random.default_rng(len(batch))
    sensors, targets = _positions(scene, batch, rng, special=True)
    n_s, n_g = scene.shape
    found = _check_core(scene, sensors, targets)
    assert found.in_view.any() and not found.in_view.all()
    _check_core(scene, sensors, targets, headings=rng.uniform(0.0, 6.0, (n_g, *batch)))
    pointing = np.array([[0.3, 0.2], [np.nan, np.nan]] + [[1.0, 0.5]] * (n_s - 2))
    _check_core(scene, sensors, targets, pointing=pointing)
    scr = rng.uniform(0.0, 20.0, (n_s, n_g, *batch))
    scr[0, 0] = 0.0
    _check_core(scene, sensors, targets, scr=scr)


@pytest.mark.parametrize(
    "path", sorted((ROOT / "examples").glob("*.toml")) + sorted(GOLDEN.glob("*.toml"))
)
def test_core_numpy_path_on_the_bundled_scenarios(path):
    scenario = load_scenario(path)
    compiled = core.compile_scenario(scenario)
    times = scenario.time.times()
    sensors, targets, headings = core.scenario_positions(scenario, times)
    scr = None
    if compiled.terrain is not None:
        found = core.factors(compiled.scene, sensors, targets, headings)
        scr = EVALUATE.footprint_scr(
            compiled.terrain,
            found.range,
            targets,
            compiled.scene.signature.target,
            compiled.scene.sensors.ifov,
        )
    _check_core(compiled.scene, sensors, targets, headings=headings, scr=scr)


def test_blocks_cover_the_grid_once_in_contiguous_pieces(monkeypatch):
    monkeypatch.setattr(EVALUATE, "_BLOCK", 12)
    for shape in [(5, 2, 3), (2, 7, 1), (2, 3, 30), (1, 1, 1), (3, 0, 4)]:
        seen = np.zeros(shape, dtype=int)
        for block in EVALUATE._blocks(*shape):
            part = seen[block]
            assert part.flags.c_contiguous
            assert part.size <= 12 or part.shape[0] == 1
            part += 1
        assert (seen == 1).all()


def test_small_blocks_give_the_same_numbers(monkeypatch):
    scene = core.compile_scenario(
        parse_scenario(copy.deepcopy(VARIANTS["noise-clutter-segments-cloud"]))
    ).scene
    sensors, targets = _positions(scene, (4,), np.random.default_rng(3), special=True)
    whole = core.evaluate(scene, sensors, targets)
    monkeypatch.setattr(EVALUATE, "_BLOCK", 7)
    monkeypatch.setattr(EVALUATE, "_PROBABILITY_BLOCK", 5)
    blocks = core.evaluate(scene, sensors, targets)
    for got, want in zip(blocks, whole, strict=True):
        for item in dataclasses.fields(want):
            np.testing.assert_array_equal(getattr(got, item.name), getattr(want, item.name))


def test_outputs_from_one_allocation_are_independent_arrays(monkeypatch):
    scene = core.compile_scenario(
        parse_scenario(copy.deepcopy(VARIANTS["noise-clutter-segments-cloud"]))
    ).scene
    sensors, targets = _positions(scene, (4,), np.random.default_rng(3), special=True)
    want_found, want = core.evaluate(scene, sensors, targets)
    monkeypatch.setattr(EVALUATE, "_SHARED_OUTPUTS", 1)  # every output carved from one block
    found = core.factors(scene, sensors, targets)
    first = core.probabilities(scene, found)
    second = core.probabilities(scene, found)  # the room is taken once: its own arrays now
    for got in (first, second):
        for item in dataclasses.fields(want):
            np.testing.assert_array_equal(getattr(got, item.name), getattr(want, item.name))
    for item in dataclasses.fields(want_found):
        np.testing.assert_array_equal(getattr(found, item.name), getattr(want_found, item.name))
    first.detection[...] = 2.0  # writing one output changes no other
    assert not np.any(second.detection == 2.0)
    assert not np.any(found.range == 2.0) and not np.any(first.recognition == 2.0)


@pytest.mark.parametrize("shape", [(100, 10, 30), (7, 3), (1, 5, 2)])
def test_fusion_over_the_pairs_in_view_is_the_fusion_of_every_pair_exactly(shape):
    rng = np.random.default_rng(shape[0])
    seen = rng.uniform(size=shape) < 0.3
    unknown = rng.uniform(size=shape) < 0.01
    p = np.where(seen, rng.uniform(0.0, 1.0, shape), 0.0)
    p[unknown] = np.nan
    picked = np.flatnonzero(seen & ~unknown)
    want = 1.0 - np.prod(1.0 - p, axis=0)
    np.testing.assert_array_equal(EVALUATE._fused_sparse(p, picked, unknown), want)


def test_factors_pickle_and_copy_as_their_fields(monkeypatch):
    scene = core.compile_scenario(parse_scenario(copy.deepcopy(VARIANTS["scr-fog"]))).scene
    sensors, targets = _positions(scene, (3,), np.random.default_rng(4), special=False)
    monkeypatch.setattr(EVALUATE, "_SHARED_OUTPUTS", 1)
    found = core.factors(scene, sensors, targets)
    want = core.probabilities(scene, found)
    for again in (pickle.loads(pickle.dumps(found)), copy.copy(found), copy.deepcopy(found)):
        assert set(vars(again)) == {item.name for item in dataclasses.fields(found)}
        got = core.probabilities(scene, again)  # through the decibels now: the same numbers
        for item in dataclasses.fields(want):
            np.testing.assert_allclose(
                getattr(got, item.name), getattr(want, item.name), rtol=1e-12, atol=1e-300
            )


def test_a_scene_derives_its_fixed_parts_once():
    scene = core.compile_scenario(parse_scenario(copy.deepcopy(VARIANTS["scr-fog"]))).scene
    calls = []

    def count(record):
        calls.append(record)
        return len(calls)

    assert derived(scene.targets, "count", count) == 1
    assert derived(scene.targets, "count", count) == 1
    assert calls == [scene.targets]
    # Not part of the record: equality, replace and the fields are those of the arrays.
    copied = dataclasses.replace(scene.targets)
    assert copied == scene.targets
    assert derived(copied, "count", count) == 2


# --------------------------------------------------------------------------------------------
# Kernels
# --------------------------------------------------------------------------------------------


def _outline_reference(x, y, z, heading, length, width, height):
    """The outline with the guards everywhere, written out (box_outline's formula)."""
    sin_h, cos_h = np.sin(heading), np.cos(heading)
    rho = np.sqrt(x * x + y * y)
    rng = np.sqrt(rho * rho + z * z)
    along = np.abs(x * sin_h + y * cos_h)
    across = np.abs(x * cos_h - y * sin_h)
    flat = rho == 0
    safe = np.where(flat, 1.0, rho)
    horizontal = (length * across + width * along) / safe
    vertical = (height * rho + (length * along + width * across) / safe * np.abs(z)) / np.where(
        rng > 0, rng, 1.0
    )
    horizontal = np.where(flat, length + 0.0 * flat, horizontal)
    vertical = np.where(flat, np.where(rng > 0, width + 0.0 * rng, height + 0.0 * rng), vertical)
    return rng, horizontal, vertical


@pytest.mark.parametrize("special", [False, True])
def test_outline_numpy_is_the_formula_exactly(special):
    rng = np.random.default_rng(4)
    x, y, z = (rng.normal(0.0, 1e3, (3, 4, 5)) for _ in range(3))
    if special:
        x[0, 0], y[0, 0] = 0.0, 0.0  # straight down
        x[1, 1], y[1, 1], z[1, 1] = 0.0, 0.0, 0.0  # at the sensor
        x[2, 2] = np.nan
    heading = rng.uniform(0.0, 6.0, (1, 4, 5))
    dims = [rng.uniform(1.0, 8.0, (4, 1)) for _ in range(3)]
    want = _outline_reference(x, y, z, heading, *dims)
    got = geometry.outline_numpy(x, y, z, np.sin(heading), np.cos(heading), *dims)
    for g, w in zip(got, want, strict=True):
        np.testing.assert_array_equal(g, w)
    public = geometry.box_outline(x, y, z, heading, *dims)
    for g, w in zip(public, want, strict=True):
        np.testing.assert_array_equal(g, w)


def test_field_of_view_numpy_is_the_formula_exactly():
    rng = np.random.default_rng(5)
    x, y, z = (rng.normal(0.0, 1e3, (3, 40, 2)) for _ in range(3))
    forward = [rng.normal(0.0, 1.0, (3, 1, 2)) for _ in range(3)]
    frame = geometry.sensor_frame(*forward, np)
    tan_h, tan_v = (
        np.array([0.3, 0.1, 1.0])[:, None, None],
        np.array([0.2, 0.1, 0.5])[:, None, None],
    )
    ahead, right, up = geometry.view_offsets(x, y, z, forward)
    want = (ahead > 0) & (np.abs(right) <= tan_h * ahead) & (np.abs(up) <= tan_v * ahead)
    got = geometry.within_numpy(x, y, z, frame, tan_h, tan_v)
    assert want.any() and not want.all()
    np.testing.assert_array_equal(got, want)


def test_snr_from_optical_depth_numpy_is_the_formula_exactly():
    depth = np.random.default_rng(6).uniform(1e-9, 60.0, 1000)
    want = 20.0 * (-depth / math.log(10.0) - np.log10(-np.expm1(-depth)))
    np.testing.assert_array_equal(atmosphere.snr_from_optical_depth(depth), want)


def test_ttpf_of_three_tasks_is_the_logistic_of_e_ln_x():
    n = np.concatenate([[0.0, np.nan, np.inf], np.random.default_rng(7).uniform(0, 30, 20000)])
    n50s = (1.0, 4.0, 6.4)
    e0, e1 = transforms.TTPF_E0, transforms.TTPF_E1
    with np.errstate(divide="ignore", invalid="ignore"):
        log_n = np.log(n)
    for got, n50 in zip(acquisition._ttpf_three_numpy(n, n50s), n50s, strict=True):
        # E · ln x with ln x = ln N − ln N50, each task as its own array.
        z = np.clip((log_n - np.log(n50)) * (n * (e1 / n50) + e0), -700.0, 700.0)
        want = np.where(n == 0, 0.0, 1.0 / (1.0 + np.exp(-z)))
        np.testing.assert_array_equal(got, want)
        np.testing.assert_allclose(got, ta.ttpf(n, n50), rtol=1e-13)


def test_clutter_transform_numpy_equals_the_generic_blend():
    rng = np.random.default_rng(8)
    n = np.concatenate([[0.0, 0.01, 2.8, 40.0, np.nan], rng.uniform(0.0, 8.0, 995)])
    for scr in (
        np.concatenate([[0.0, 0.1, 0.33, 1.0, 10.0, np.inf, np.nan], rng.uniform(0, 20, 993)]),
        rng.uniform(1.0, 30.0, 1000),  # above 1 only: two curves
        rng.uniform(0.0, 1.0, 1000),  # below 1 only
    ):
        got = transforms.sw_probability(n, 1.3, scr, None, np)
        want = ta.schmieder_weathersby(xps.asarray(n), 1.3, scr=xps.asarray(scr))
        np.testing.assert_allclose(got, np.asarray(want), rtol=1e-14, atol=0, equal_nan=True)
        np.testing.assert_array_equal(ta.schmieder_weathersby(n, 1.3, scr=scr), got)


def test_noise_factors_and_effective_scr_from_the_amplitude_ratio():
    snr = np.array([-7000.0, -40.0, -3.0, 0.0, 4.5, 20.0, 400.0, 7000.0, np.inf, -np.inf, np.nan])
    ratio = noise.noise_ratio(snr)
    # The amplitude ratio is 10^(-SNR/20): 1/SNR_lin.
    np.testing.assert_allclose(ratio[1:-3], 10.0 ** (-snr[1:-3] / 20.0), rtol=1e-15)
    for name, model in noise.NOISE_MODELS.items():
        got = model.ratio_factor(ratio, np)
        with np.errstate(over="ignore"):  # 10^(7000/20) in the decibels' path
            want = ta.noise_n50_factor(snr, name)
        np.testing.assert_allclose(got, want, rtol=1e-14, equal_nan=True, err_msg=name)
    scr = np.full(snr.shape, 3.0)
    got = noise.effective_scr_of_ratio(scr, ratio, np)
    with np.errstate(over="ignore"):
        want = ta.effective_scr(scr, snr)
    np.testing.assert_allclose(got, want, rtol=1e-14, equal_nan=True)
    assert got[-3] == 3.0  # exactly the SCR without noise


def test_path_noise_ratio_is_e_to_the_depth_minus_one():
    depth = np.random.default_rng(9).uniform(0.0, 30.0, 1000)
    snr = atmosphere.snr_from_optical_depth(depth)
    np.testing.assert_allclose(np.expm1(depth), noise.noise_ratio(snr), rtol=1e-13)


def test_in_view_path_passes_each_group_the_flags_of_all_its_targets():
    # task_probabilities passes a group's flags per target where they differ; the in-view path
    # passes the same flags (for the pairs in view), whichever pairs are in view.
    rng = np.random.default_rng(10)
    data = {
        "sensors": [_sensor(2)],
        "targets": [_target(0, rng, hot_spot=True), _target(1, rng, moving=True)],
        "background": {"temperature": "293 K", "clutter": "high"},
    }
    scene = core.compile_scenario(parse_scenario(data)).scene
    sensors = np.array([[0.0, 0.0, 100.0]])
    targets = np.array([[800.0, 0.0, 0.0], [900.0, 50.0, 0.0]])
    found, probs = core.evaluate(scene, sensors, targets)
    want = EVALUATE.task_probabilities(found.cycles, found.snr, found.scr, scene)
    for got, expected in zip(TASKS, want, strict=True):
        np.testing.assert_allclose(getattr(probs, got), expected, rtol=1e-14)
