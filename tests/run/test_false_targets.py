"""False targets (targetacq.run.false_targets): the area in view against closed forms and Monte
Carlo, Poisson counts per step (mean and dispersion), positions inside the field of view and
range, identical outcomes across batchings, sensor orders and targets, the step API, the
scenario checks and `targetacq simulate --false-detections`."""

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

from targetacq import Simulation, core
from targetacq.physics import geometry
from targetacq.run.false_targets import (
    FalseDetections,
    FalseTargetSampler,
    false_target_problems,
    false_target_rate,
    ground_area_in_view,
    ground_footprint,
    sample_false_detections,
)
from targetacq.run.model_chain import ModelChain
from targetacq.run.search import simulate
from targetacq.scenario.schema import FalseTargets, Scenario, ScenarioError, load_scenario

ROOT = Path(__file__).parents[2]
DOWN = math.pi / 2
SIGNIFICANCE = 1e-3  # of the statistical tests (fixed seeds: each result is deterministic)


def _sensor(name="cam", position=(0.0, 0.0, 1000.0), azimuth=0.0, depression=DOWN, **extra):
    sensor = {
        "name": name,
        "band": "lwir",
        "hfov": 0.4,
        "pixels": [640, 480],
        "projection": "rectilinear",
        "position": list(position),
        **extra,
    }
    if azimuth is not None:
        sensor |= {"azimuth": azimuth, "depression": depression}
    return sensor


_TRUCK = {
    "name": "truck",
    "dimensions": [7.0, 2.5, 3.0],
    "temperature": 305.0,
    "position": [300.0, 0.0, 0.0],
}


def _blind(name):
    """A sensor without a field of view (its resolution as an IFOV, no pixels)."""
    return {"name": name, "band": "lwir", "ifov": 1e-3, "position": [0.0, 0.0, 1000.0]}


def _scenario(sensors=None, table=None, targets=None, search_time=3.4):
    data = {
        "sensors": sensors or [_sensor()],
        "targets": targets or [_TRUCK],
        "background": {"temperature": 295.0},
        "model": {"search_time": search_time},
    }
    if table is not None:
        data["false_targets"] = table
    return Scenario.model_validate(data)


def _half(sensor):
    h, v = sensor.field_of_view
    return math.tan(h / 2), math.tan(v / 2)


def _counts(result, edges):
    """False detections per (run, step) of a simulation, shape (runs, steps)."""
    fd = result.false_detections
    step = np.searchsorted(edges, fd.time, side="left")  # t in (edges[k-1], edges[k]] -> k
    assert (step >= 1).all() and (step < edges.size).all()
    counts = np.zeros((result.times["detection"].shape[0], edges.size - 1), dtype=np.int64)
    np.add.at(counts, (fd.run, step - 1), 1)
    return counts


# --- the area in view ------------------------------------------------------------------------


@pytest.mark.parametrize("height", [10.0, 850.0, 3000.0])
@pytest.mark.parametrize("half", [(0.1, 0.05), (0.7, 0.3), (1.5, 1.2)])
def test_area_straight_down_is_the_rectangle(height, half):
    area = ground_area_in_view((120.0, -40.0, height), (0.0, 0.0, -1.0), half, 1e6)
    expected = (2 * height * half[0]) * (2 * height * half[1])
    assert area == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("azimuth_deg", [0.0, 33.0, 90.0, 211.0])
@pytest.mark.parametrize("hfov_deg", [2.0, 40.0, 150.0])
def test_area_of_a_level_sensor_on_the_ground_is_its_sector(azimuth_deg, hfov_deg):
    a = math.radians(azimuth_deg)
    forward = geometry.pointing_direction(a, 0.0)
    half = (math.tan(math.radians(hfov_deg) / 2), math.tan(math.radians(10.0)))
    area = ground_area_in_view((5.0, 7.0, 0.0), forward, half, 2500.0)
    assert area == pytest.approx(math.radians(hfov_deg) / (2 * math.pi) * math.pi * 2500.0**2)


def test_area_limited_by_the_range_is_the_disc():
    area = ground_area_in_view((0.0, 0.0, 100.0), (0.0, 0.0, -1.0), (50.0, 50.0), 300.0)
    assert area == pytest.approx(math.pi * 300.0**2, rel=1e-12)


def test_nothing_in_view_above_the_horizon_or_without_a_position():
    assert ground_area_in_view((0.0, 0.0, 100.0), (1.0, 0.0, 0.5), (0.1, 0.1), 5e3) == 0.0
    assert ground_area_in_view((np.nan, 0.0, 100.0), (0.0, 0.0, -1.0), (0.1, 0.1), 5e3) == 0.0
    with pytest.raises(ValueError, match="max_range must be > 0"):
        ground_area_in_view((0.0, 0.0, 100.0), (0.0, 0.0, -1.0), (0.1, 0.1), 0.0)


def test_area_agrees_with_monte_carlo_of_the_field_of_view_test():
    # Random geometries (tilted, cut by the range, partly above the horizon): the exact area
    # against the share of points of the square around the range that the geometry module's
    # own field-of-view test (not the footprint's) says are in view within the range.
    rng = np.random.default_rng(20240611)
    n = 200_000
    worst = 0.0
    for _ in range(40):
        position = (rng.normal(0, 100), rng.normal(0, 100), rng.uniform(0.0, 3000.0))
        forward = geometry.pointing_direction(rng.uniform(0, 2 * np.pi), rng.uniform(-0.2, DOWN))
        half = (math.tan(rng.uniform(0.02, 1.4)), math.tan(rng.uniform(0.02, 1.4)))
        radius = rng.uniform(200.0, 8000.0)
        dx, dy = rng.uniform(-radius, radius, (2, n))
        inside = geometry.within_field_of_view(dx, dy, np.full(n, -position[2]), forward, half) & (
            np.hypot(dx, dy) <= radius
        )
        share = inside.mean()
        se = math.sqrt(max(share * (1 - share), 1.0 / n) / n) * 4 * radius**2
        area = ground_area_in_view(position, forward, half, radius)
        worst = max(worst, abs(area - share * 4 * radius**2) / se)
    assert worst < 4.5  # about 40 normal deviates: the largest stays below 4.5 sigma


# --- the rate --------------------------------------------------------------------------------


def test_rate_is_linear_in_density_probability_and_area():
    base = false_target_rate(4e-6, 0.05, 2e6, 3.4)
    assert base == pytest.approx(4e-6 * 2e6 * 0.05 / 3.4)
    assert false_target_rate(8e-6, 0.05, 2e6, 3.4) == pytest.approx(2 * base)
    assert false_target_rate(4e-6, 0.15, 2e6, 3.4) == pytest.approx(3 * base)
    assert false_target_rate(4e-6, 0.05, 1e6, 3.4) == pytest.approx(base / 2)
    assert false_target_rate(0.0, 0.05, 2e6, 3.4) == 0.0
    with pytest.raises(ValueError, match="search_time"):
        false_target_rate(4e-6, 0.05, 2e6, 0.0)
    with pytest.raises(ValueError, match="probability"):
        false_target_rate(4e-6, 1.5, 2e6, 3.4)


def test_scenario_rates_scale_with_the_table():
    sc = _scenario(table={"density": 1e-5, "probability": 0.05, "max_range": 5000.0})
    scene = core.compile_scenario(sc).scene
    position = np.array([[0.0, 0.0, 1000.0]])

    def rate(**change):
        table = sc.false_targets.model_copy(update=change)
        (found,) = FalseTargetSampler(table, scene.sensors, 3.4, 0).footprints(position)
        return found[2]

    tan_h, tan_v = _half(sc.sensors[0])
    stated = 1e-5 * (2000 * tan_h) * (2000 * tan_v) * 0.05 / 3.4
    assert rate() == pytest.approx(stated, rel=1e-12)
    assert rate(density=3e-5) == pytest.approx(3 * stated, rel=1e-12)
    assert rate(probability=0.025) == pytest.approx(stated / 2, rel=1e-12)


# --- Poisson counts ----------------------------------------------------------------------------


@pytest.mark.parametrize(("mean", "runs"), [(1.5, 400), (0.2, 1000), (40.0, 100)])
def test_counts_per_step_are_poisson_with_the_stated_mean(mean, runs):
    # Straight down from 1 km: A = (2 h tan_h)(2 h tan_v) exactly; the density is chosen so
    # that a 1 s step has the stated mean density·A·p·dt/t_s.
    sc = _scenario()
    tan_h, tan_v = _half(sc.sensors[0])
    area = (2000.0 * tan_h) * (2000.0 * tan_v)
    density = mean * 3.4 / (area * 0.05 * 1.0)
    sc = sc.model_copy(
        update={"false_targets": FalseTargets(density=density, probability=0.05, max_range=5e3)}
    )
    duration, step = 25.0, 1.0
    result = simulate(ModelChain(sc), duration, step, runs=runs, seed=11)
    edges = np.arange(0.0, duration + step / 2, step)
    x = _counts(result, edges).ravel()
    n = x.size
    # The mean, within four standard errors.
    assert abs(x.mean() - mean) < 4 * math.sqrt(mean / n), (x.mean(), mean)
    # Index of dispersion: sum (x - mean)^2 / mean ~ chi^2(n - 1) for Poisson counts.
    dispersion = float(((x - x.mean()) ** 2).sum() / x.mean())
    p = stats.chi2.cdf(dispersion, n - 1)
    assert SIGNIFICANCE / 2 < p < 1 - SIGNIFICANCE / 2, (dispersion / (n - 1), p)
    # And the whole distribution: chi-square goodness of fit, tail classes merged (expected >= 5).
    k = np.arange(x.max() + 1)
    expected = stats.poisson.pmf(k, mean) * n
    expected[-1] += stats.poisson.sf(k[-1], mean) * n
    observed = np.bincount(x, minlength=k.size).astype(float)
    keep = np.flatnonzero(expected >= 5)
    lo, hi = keep[0], keep[-1]
    obs = np.r_[observed[: lo + 1].sum(), observed[lo + 1 : hi], observed[hi:].sum()]
    exp = np.r_[expected[: lo + 1].sum(), expected[lo + 1 : hi], expected[hi:].sum()]
    assert stats.chisquare(obs, exp).pvalue > SIGNIFICANCE


def test_positions_are_uniform_over_the_ground_in_view():
    sc = _scenario(table={"density": 2e-3, "probability": 0.05, "max_range": 5000.0})
    result = simulate(ModelChain(sc), 20.0, 1.0, runs=20, seed=5)
    fd = result.false_detections
    assert len(fd) > 1000
    tan_h, tan_v = _half(sc.sensors[0])
    # Straight down, right is east and up is north: a rectangle 2 h tan_h by 2 h tan_v.
    east = fd.position[:, 0] / (1000.0 * tan_h)
    north = fd.position[:, 1] / (1000.0 * tan_v)
    for values in (east, north):
        assert stats.kstest(values, stats.uniform(-1, 2).cdf).pvalue > SIGNIFICANCE
    # Times uniform within their steps.
    fraction = fd.time - np.floor(fd.time - 1e-12)
    assert stats.kstest(fraction, stats.uniform(0, 1).cdf).pvalue > SIGNIFICANCE


# --- inside the field of view ------------------------------------------------------------------


def _uav(density=2e-4, **extra):
    sc = load_scenario(ROOT / "examples" / "uav_haze.toml")
    table = FalseTargets(density=density, probability=0.05, max_range=5000.0, **extra)
    return sc.model_copy(update={"false_targets": table})


def test_every_false_detection_is_in_view_within_range_on_the_ground():
    sc = _uav()
    duration, step = 30.0, 1.0
    result = simulate(ModelChain(sc), duration, step, runs=5, seed=3)
    fd = result.false_detections
    assert len(fd) > 500
    edges = sc.time.start + np.arange(0.0, duration + step / 2, step)
    k = np.searchsorted(edges, fd.time, side="left")
    assert ((edges[k - 1] < fd.time) & (fd.time <= edges[k])).all()
    # The sensor where it is at the end of each step, pointed by its azimuth and depression.
    sensor = sc.sensors[0]
    positions = core.scenario_positions(sc, edges)[0][0][k]
    forward = geometry.pointing_direction(sensor.azimuth, sensor.depression)
    sight = fd.position - positions
    assert geometry.within_field_of_view(*sight.T, forward, _half(sensor)).all()
    assert (np.hypot(sight[:, 0], sight[:, 1]) <= 5000.0 * (1 + 1e-12)).all()
    assert (fd.position[:, 2] == 0.0).all()
    assert set(fd.sensor.tolist()) == {"uav-lwir"}
    # Sorted by run, then time.
    assert (np.diff(fd.run) >= 0).all()
    same = np.diff(fd.run) == 0
    assert (np.diff(fd.time)[same] >= 0).all()


def test_step_api_draws_inside_the_pointing_given_per_step():
    # A sensor with pixels but no pointing of its own reports nothing until a step points it.
    sc = _scenario(
        sensors=[_sensor("free", azimuth=None), _blind("ifov-only")],
        table={"density": 1e-3, "probability": 0.1, "max_range": 3000.0},
    )
    sim = Simulation.from_scenario(sc, seed=9)
    sensors = np.array([[0.0, 0.0, 500.0], [0.0, 0.0, 500.0]])
    target = np.array([[300.0, 0.0, 0.0]])
    first = sim.step(0.0, 0.0, sensors, target)
    assert len(first.false_detections) == 0  # the first step only starts the clock
    assert len(sim.step(1.0, 1.0, sensors, target).false_detections) == 0  # not pointed
    pointing = np.array([[0.7, 0.5], [0.0, 0.6]])  # the ifov-only one has no field of view
    seen = 0
    for k in range(2, 12):
        out = sim.step(float(k), 1.0, sensors, target, sensor_pointing=pointing)
        fd = out.false_detections
        seen += len(fd)
        assert set(fd.sensor.tolist()) <= {"free"}
        assert ((k - 1 < fd.time) & (fd.time <= k)).all() and (np.diff(fd.time) >= 0).all()
        forward = geometry.pointing_direction(*pointing[0])
        sight = fd.position - sensors[0]
        assert geometry.within_field_of_view(*sight.T, forward, _half(sc.sensors[0])).all()
        assert (np.hypot(sight[:, 0], sight[:, 1]) <= 3000.0 * (1 + 1e-12)).all()
    assert seen > 40  # about 9 a step


def test_no_table_no_false_detections():
    sc = _scenario()
    sim = Simulation.from_scenario(sc, seed=1)
    for k in range(5):
        out = sim.step(float(k), 1.0, np.array([[0.0, 0.0, 1000.0]]), np.array([[0.0, 0, 0]]))
        assert len(out.false_detections) == 0
    assert len(simulate(ModelChain(sc), 10.0, 1.0, runs=3).false_detections) == 0


# --- reproducible whatever the batching, order and targets ------------------------------------


def test_identical_across_batchings_and_the_step_api():
    sc = _uav()
    chain = ModelChain(sc)
    duration, step, runs = 20.0, 1.0, 9
    one = simulate(chain, duration, step, runs=runs, seed=21, batch=1).false_detections
    seven = simulate(chain, duration, step, runs=runs, seed=21, batch=7).false_detections
    assert len(one) > 100
    for name in ("run", "sensor", "time", "position"):
        np.testing.assert_array_equal(getattr(one, name), getattr(seven, name))
    times = sc.time.start + np.arange(0.0, duration + step / 2, step)
    sensor_pos, target_pos, headings = core.scenario_positions(sc, times)
    sim = Simulation.from_scenario(sc, seed=21)
    for run in (0, 4, 8):
        sim.reset(run=run)
        stepped = []
        for k, t in enumerate(times):
            dt = t - times[k - 1] if k else 0.0
            out = sim.step(t, dt, sensor_pos[:, k], target_pos[:, k], headings[:, k])
            stepped += list(out.false_detections)
        assert stepped == [d for d in one if d.run == run]
        assert all(d.run == run for d in stepped)
    other = simulate(chain, duration, step, runs=runs, seed=22, batch=7).false_detections
    assert len(other) != len(one) or not np.array_equal(other.time, one.time)


def test_the_order_of_sensors_and_the_targets_do_not_change_them():
    table = {"density": 1e-4, "probability": 0.05, "max_range": 4000.0}
    a = _sensor("a", position=(0.0, 0.0, 800.0), azimuth=0.3, depression=0.6)
    b = _sensor("b", position=(500.0, 0.0, 300.0), azimuth=2.0, depression=0.3)
    c = _blind("c")
    truck = _TRUCK
    jeep = {**truck, "name": "jeep", "position": [-200.0, 900.0, 0.0]}

    def frame(sensors, targets):
        sc = _scenario(sensors=sensors, table=table, targets=targets)
        fd = simulate(ModelChain(sc), 15.0, 0.5, runs=4, seed=8, batch=3).false_detections
        return fd.frame().sort_values(["sensor", "run", "time"]).reset_index(drop=True)

    reference = frame([a, b, c], [truck])
    assert set(reference["sensor"]) == {"a", "b"}  # c has no field of view
    for sensors, targets in (([b, c, a], [truck]), ([c, a, b], [jeep, truck]), ([b, a], [jeep])):
        got = frame(sensors, targets)
        assert got.equals(reference)


def test_sample_false_detections_is_counter_based():
    fp = ground_footprint((0.0, 0.0, 1000.0), (0.0, 0.0, -1.0), (0.3, 0.2), 5000.0)
    together = sample_false_detections(fp, 3.0, 4.0, 5.0, seed=2, sensor="ir", step=4, runs=[0, 3])
    alone = sample_false_detections(fp, 3.0, 4.0, 5.0, seed=2, sensor="ir", step=4, runs=3)
    mine = together.run == 3
    np.testing.assert_array_equal(together.time[mine], alone.time)
    np.testing.assert_array_equal(together.position[mine], alone.position)
    other = sample_false_detections(fp, 3.0, 4.0, 5.0, seed=2, sensor="tv", step=4, runs=3)
    assert not np.array_equal(other.time, alone.time)
    assert len(sample_false_detections(fp, 0.0, 4.0, 5.0, seed=2, sensor="ir", step=4)) == 0
    assert len(FalseDetections.empty()) == 0


def test_the_bands_of_one_group_report_once_under_its_name():
    # Two rows of one group (a colour camera's bands): false targets once, as the group, the
    # same as a single sensor of that name.
    sc = _scenario(sensors=[_sensor("cam"), _sensor("other")])
    sensors = core.compile_scenario(sc).scene.sensors
    grouped = dataclasses.replace(sensors, names=("cam:red", "cam:green"), groups=("cam", "cam"))
    table = FalseTargets(density=5e-4, probability=0.05, max_range=5000.0)
    sampler = FalseTargetSampler(table, grouped, 3.4, seed=4)
    assert sampler.groups == ("cam",)
    positions = np.array([[0.0, 0.0, 1000.0], [0.0, 0.0, 1000.0]])
    got = sampler.sample(3, 2.0, 3.0, [0, 1, 2], positions)
    assert len(got) > 0 and set(got.sensor.tolist()) == {"cam"}
    single = core.compile_scenario(_scenario(sensors=[_sensor("cam")])).scene.sensors
    alone = FalseTargetSampler(table, single, 3.4, seed=4).sample(
        3, 2.0, 3.0, [0, 1, 2], positions[:1]
    )
    np.testing.assert_array_equal(got.position, alone.position)


# --- the scenario's checks ---------------------------------------------------------------------


def test_false_target_problems_are_located():
    sc = _scenario(sensors=[_sensor("pointed"), _sensor("free", azimuth=None), _blind("x")])

    def problems(names):
        table = FalseTargets(density=1e-6, probability=0.1, max_range=1e3, sensors=names)
        return false_target_problems(sc.model_copy(update={"false_targets": table}))

    assert problems(None) == [] and problems(["pointed"]) == []
    assert false_target_problems(sc) == []
    (unknown,) = problems(["nope"])
    assert unknown.startswith("false_targets.sensors[0]: unknown sensor 'nope'")
    assert "pointed, free, x" in unknown
    (free,) = problems(["pointed", "free"])
    assert free.startswith("false_targets.sensors[1]: sensor 'free' is not pointed")
    (blind,) = problems(["x"])
    assert blind.startswith("false_targets.sensors[0]: sensor 'x' has no field of view")
    (twice,) = problems(["pointed", "pointed"])
    assert twice == "false_targets.sensors[1]: 'pointed' is listed twice"
    no_view = sc.model_copy(update={"sensors": [sc.sensors[2]]})
    table = FalseTargets(density=1e-6, probability=0.1, max_range=1e3)
    (none,) = false_target_problems(no_view.model_copy(update={"false_targets": table}))
    assert none.startswith("false_targets: no sensor has a field of view")


def test_an_empty_false_target_sensor_list_is_refused_not_silently_empty():
    # sensors = [] named no sensor: the table was accepted and no false target ever drawn.
    sc = _scenario()
    table = FalseTargets(density=1e-6, probability=0.1, max_range=1e3, sensors=[])
    (empty,) = false_target_problems(sc.model_copy(update={"false_targets": table}))
    assert empty.startswith("false_targets.sensors: an empty list names no sensor")
    with pytest.raises(ValueError, match=r"false_targets\.sensors: an empty list"):
        _scenario(table={"density": 1e-6, "probability": 0.1, "max_range": 1e3, "sensors": []})
    sensors = core.compile_scenario(sc).scene.sensors
    with pytest.raises(ValueError, match=r"^false_targets\.sensors: an empty list"):
        FalseTargetSampler(table, sensors, 3.4, seed=0)


def test_simulation_refuses_an_unknown_false_target_sensor():
    table = {"density": 1e-6, "probability": 0.1, "max_range": 1e3, "sensors": ["nope"]}
    with pytest.raises(ScenarioError, match=r"false_targets\.sensors\[0\]: unknown sensor 'nope'"):
        Simulation(
            [_sensor()],
            [{"name": "t", "dimensions": [1.0, 1.0, 1.0], "temperature": 300.0}],
            background={"temperature": 290.0},
            false_targets=table,
        )


# --- targetacq simulate --false-detections ---------------------------------------------------


def test_cli_writes_the_false_detections(cli, tmp_path):
    text = (ROOT / "examples" / "uav_haze.toml").read_text()
    table = '\n[false_targets]\ndensity = "50 /km^2"\nprobability = 0.05\nmax_range = "5 km"\n'
    scenario = tmp_path / "scene.toml"
    scenario.write_text(text + table)
    common = ["simulate", str(scenario), "--duration", "10s", "--step", "1s", "--runs", "3"]
    written = {}
    for suffix in ("csv", "json", "parquet"):
        path = tmp_path / f"false.{suffix}"
        code, out, err = cli(*common, "--seed", "5", "--false-detections", str(path))
        assert code == 0, err
        assert "false detections: " in out and str(path) in out
        written[suffix] = path
    import pandas as pd

    reference = simulate(ModelChain(load_scenario(scenario)), 10.0, 1.0, runs=3, seed=5)
    expected = reference.false_detections.frame()
    assert len(expected) > 20
    got = pd.read_csv(written["csv"], comment="#")
    assert list(got.columns) == ["run", "sensor", "time", "x", "y", "z"]
    pd.testing.assert_frame_equal(got, expected, check_exact=False, rtol=1e-12)
    pd.testing.assert_frame_equal(pd.read_parquet(written["parquet"]), expected)
    document = json.loads(written["json"].read_text())
    assert document["meta"]["variables"]["x"]["units"] == "m"
    assert document["meta"]["false_targets"]["max_range"] == 5000.0
    assert document["meta"]["seed"] == 5 and len(document["rows"]) == len(expected)
    # Without the table, or onto the summary's own file: one line, exit status 2.
    plain = ROOT / "examples" / "uav_haze.toml"
    code, _, err = cli("simulate", str(plain), "--false-detections", str(tmp_path / "a.csv"))
    assert code == 2 and "has no [false_targets] table" in err
    same = str(tmp_path / "same.csv")
    code, _, err = cli(*common, "--out", same, "--false-detections", same)
    assert code == 2 and "name the same file" in err
