"""Sampling and simulation over time: reproducibility, step-size independence, nested events."""

import math

import numpy as np
import pytest
from scipy import stats

from targetacq.base.sampling import philox4x32, stream_key, uniforms
from targetacq.run.model_chain import ModelChain
from targetacq.run.search import search_probability, simulate
from targetacq.scenario.schema import parse_scenario


@pytest.mark.parametrize(
    ("counter", "key", "expected"),
    [  # Random123 kat_vectors, philox4x32 10 (counter[4] key[2] -> output[4])
        ((0, 0, 0, 0), (0, 0), (0x6627E8D5, 0xE169C58D, 0xBC57AC4C, 0x9B00DBD8)),
        ((0xFFFFFFFF,) * 4, (0xFFFFFFFF,) * 2, (0x408F276D, 0x41C83B0E, 0xA20BC7C6, 0x6D5451FD)),
        (
            (0x243F6A88, 0x85A308D3, 0x13198A2E, 0x03707344),
            (0xA4093822, 0x299F31D0),
            (0xD16CFE09, 0x94FDCCEB, 0x5001E420, 0x24126EA1),
        ),
    ],
)
def test_philox_known_answers(counter, key, expected):
    assert tuple(int(w) for w in philox4x32(counter, key)) == expected


def test_uniforms_are_uniform_and_counter_based():
    key = stream_key(7, "sensor", "target")
    u = uniforms(key, np.arange(100_000), 3, purpose=1)
    assert np.all((u > 0) & (u < 1))
    assert stats.kstest(u, "uniform").pvalue > 1e-3
    # The same counter gives the same number, computed alone or in a batch.
    assert uniforms(key, 12_345, 3, purpose=1) == u[12_345]
    assert stream_key(7, "a", "b") != stream_key(7, "b", "a")
    assert stream_key(7, "a", "b") != stream_key(8, "a", "b")


def _scene(waypoints=None, sensors=None, extra_target=None, distance="1.2 km"):
    target = {"name": "truck", "dimensions": ["7 m", "2.5 m", "3 m"], "temperature": "305 K"}
    if waypoints is None:
        target["position"] = [distance, "0 m", "0 m"]
    else:
        target["waypoints"] = waypoints
    targets = [target] + ([extra_target] if extra_target else [])
    return parse_scenario(
        {
            "sensors": sensors
            or [
                {
                    "name": "ir",
                    "band": "lwir",
                    "ifov": "0.25 mrad",
                    "position": ["0 m", "0 m", "5 m"],
                }
            ],
            "targets": targets,
            "background": {"temperature": "295 K"},
        }
    )


def test_search_model_closed_form():
    assert search_probability(3.4, 1.0) == pytest.approx(1 - math.exp(-1))
    assert search_probability(0.0, 0.8) == 0.0
    assert search_probability(1e6, 0.8) == pytest.approx(0.8)


def test_constant_p_infinity_matches_the_search_model_at_any_step():
    chain = ModelChain(_scene(distance="5 km"))
    p_inf = float(chain.compute([0.0])["detection"][0, 0, 0])
    assert 0.3 < p_inf < 0.95
    n = 4000
    for step in (0.05, 0.5):
        t = simulate(chain, 30.0, step, runs=n, seed=11).fused["detection"][:, 0]
        grid = np.linspace(0.0, 30.0, 61)
        ecdf = np.array([(t <= x).mean() for x in grid])
        # Dvoretzky–Kiefer–Wolfowitz: sup |ECDF − F| <= ε with probability 1 − α, α = 0.001.
        epsilon = math.sqrt(math.log(2 / 0.001) / (2 * n))
        assert np.max(np.abs(ecdf - search_probability(grid, p_inf))) < epsilon


def test_step_size_independence_for_a_moving_target():
    # The truck drives away, so P∞ falls with time; 2,000 runs at 0.05 s and 0.5 s steps.
    waypoints = [
        {"time": "0 s", "position": ["600 m", "0 m", "0 m"]},
        {"time": "60 s", "position": ["3 km", "0 m", "0 m"]},
    ]
    chain = ModelChain(_scene(waypoints))
    fine = simulate(chain, 60.0, 0.05, runs=2000, seed=3).fused["detection"][:, 0]
    coarse = simulate(chain, 60.0, 0.5, runs=2000, seed=4).fused["detection"][:, 0]
    # Two-sample Kolmogorov–Smirnov on the first-detection times (never = +inf, kept: the
    # defective part of the distribution must agree too). Threshold: p > 0.001.
    assert stats.ks_2samp(np.minimum(fine, 1e9), np.minimum(coarse, 1e9)).pvalue > 0.001
    # Both agree with the hazard integrated on a fine grid (within DKW, α = 0.001).
    t = np.linspace(0.0, 60.0, 6001)
    p = chain.compute(t)["detection"][0, 0]
    # P(T <= t) = E_u[1 − exp(−∫ 1{u < P(s)} P(s)/3.4 ds)], over u uniform: by quadrature in u.
    u = (np.arange(2000) + 0.5) / 2000
    rate = np.where(u[:, None] < p[None, :], p[None, :] / 3.4, 0.0)
    hazard = np.concatenate(
        [np.zeros((u.size, 1)), np.cumsum(rate[:, :-1] * np.diff(t), axis=1)], axis=1
    )
    model = (1 - np.exp(-hazard)).mean(axis=0)
    epsilon = math.sqrt(math.log(2 / 0.001) / (2 * 2000))
    for sample in (fine, coarse):
        ecdf = np.searchsorted(np.sort(sample), t, side="right") / sample.size
        assert np.max(np.abs(ecdf - model)) < epsilon + 0.01  # + the step's discretisation


def test_same_seed_any_batch_and_sensor_order_gives_identical_outcomes():
    sensors = [
        {"name": "a", "band": "lwir", "ifov": "0.25 mrad", "position": ["0 m", "0 m", "5 m"]},
        {"name": "b", "band": "mwir", "ifov": "0.2 mrad", "position": ["0 m", "50 m", "5 m"]},
    ]
    one = simulate(ModelChain(_scene(sensors=sensors)), 20.0, 0.1, runs=300, seed=5, batch=300)
    other = simulate(
        ModelChain(_scene(sensors=sensors[::-1])), 20.0, 0.1, runs=300, seed=5, batch=7
    )
    for task in ("detection", "recognition", "identification"):
        np.testing.assert_array_equal(one.fused[task], other.fused[task])
        np.testing.assert_array_equal(one.times[task][:, 0], other.times[task][:, 1])
    different = simulate(ModelChain(_scene(sensors=sensors)), 20.0, 0.1, runs=300, seed=6)
    assert not np.array_equal(one.fused["detection"], different.fused["detection"])


def test_nested_events_and_marginal_frequencies():
    chain = ModelChain(_scene())
    p = {
        task: float(chain.compute([0.0])[task][0, 0, 0])
        for task in ("detection", "recognition", "identification")
    }
    n, duration = 4000, 400.0  # long enough for the search clock: P(t) = P∞(1 − 3e-13)
    result = simulate(chain, duration, 1.0, runs=n, seed=9)
    det, rec, ide = (
        result.fused[task][:, 0] for task in ("detection", "recognition", "identification")
    )
    assert np.all(rec >= det)
    assert np.all(ide >= rec)
    assert not np.any(np.isfinite(ide) & ~np.isfinite(rec))
    assert not np.any(np.isfinite(rec) & ~np.isfinite(det))
    for sample, task in ((det, "detection"), (rec, "recognition"), (ide, "identification")):
        expected = p[task] * (1 - math.exp(-duration * p["detection"] / 3.4))
        sigma = math.sqrt(expected * (1 - expected) / n)
        assert abs(np.isfinite(sample).mean() - expected) < 4 * sigma + 1e-12


def test_leaving_the_view_resets_and_bad_arguments():
    sensors = [
        {
            "name": "ir",
            "band": "lwir",
            "pixels": [640, 480],
            "ifov": "0.25 mrad",
            "position": ["0 m", "0 m", "5 m"],
            "azimuth": "90 deg",
            "depression": "0 deg",
        }
    ]
    waypoints = [
        {"time": "0 s", "position": ["1 km", "-1 km", "0 m"]},
        {"time": "20 s", "position": ["1 km", "1 km", "0 m"]},
    ]
    chain = ModelChain(_scene(waypoints, sensors))
    result = simulate(chain, 20.0, 0.1, runs=500, seed=1)
    grid = np.arange(0.0, 20.0, 0.1)
    in_view = chain.compute(grid)["in_view"][0, 0]
    first, last = grid[in_view].min(), grid[in_view].max()
    detected = result.fused["detection"][:, 0]
    assert np.isfinite(detected).any()
    # Entering (leaving) the view, the target is taken to be in view for the half of the step
    # next to its first (last) in-view step time.
    seen = detected[np.isfinite(detected)]
    assert np.all((seen >= first - 0.05 - 1e-9) & (seen <= last + 0.05 + 1e-9))
    for kwargs, match in (({"runs": 0}, "runs"), ({"step": -1.0}, "step"), ({"seed": -1}, "seed")):
        args = {"duration": 10.0, "step": 0.1, "runs": 1, "seed": 0, **kwargs}
        with pytest.raises(ValueError, match=match):
            simulate(chain, **args)


def test_summary_quantiles_over_all_runs():
    chain = ModelChain(_scene(distance="5 km"))
    result = simulate(chain, 5.0, 0.5, runs=200, seed=2)
    summary = result.summary().set_index("task")
    det = result.fused["detection"][:, 0]
    assert summary.loc["detection", "fraction"] == pytest.approx(np.isfinite(det).mean())
    # The median is the 100th smallest of 200 times; +inf (never) when fewer than half got there.
    assert summary.loc["detection", "t50_s"] == np.sort(det)[99]
    rare = summary.loc["identification"]
    assert rare["fraction"] < 0.5  # at 5 km identification is rare
    assert rare["t50_s"] == np.inf


@pytest.mark.parametrize(
    ("start", "end"),
    [
        ((0.2, 0.1, 0.05), (0.9, 0.6, 0.3)),
        ((0.9, 0.7, 0.4), (0.3, 0.2, 0.0)),
        ((0.5,) * 3, (0.5,) * 3),
    ],
)
def test_within_step_law_matches_quadrature(start, end):
    # One step of 3 s with each probability linear from `start` to `end`: the sampled detection
    # times and recognition frequency against quadrature of the model (not the closed forms).
    from targetacq.run.search import SearchState, Streams

    n, dt, t_s = 20_000, 3.0, 3.4
    state = SearchState(Streams(4, ["s"], ["g"]), np.arange(n), t_s)
    state.advance(10.0, np.array(start, dtype=float).reshape(3, 1), np.array([True]))
    state.advance(10.0 + dt, np.array(end, dtype=float).reshape(3, 1), np.array([True]))
    detected = state.first[0, :, 0] - 10.0
    recognised = state.first[1, :, 0] - 10.0
    assert np.all(recognised[np.isfinite(recognised)] >= detected[np.isfinite(recognised)])
    s = np.linspace(0.0, dt, 3001)
    p_det = start[0] + (end[0] - start[0]) * s / dt
    u = (np.arange(1000) + 0.5) / 1000
    rate = np.where(u[:, None] < p_det[None, :], p_det[None, :] / t_s, 0.0)
    hazard = np.concatenate(
        [np.zeros((u.size, 1)), np.cumsum((rate[:, 1:] + rate[:, :-1]) / 2 * np.diff(s), axis=1)],
        axis=1,
    )
    model = (1 - np.exp(-hazard)).mean(axis=0)
    ecdf = np.searchsorted(np.sort(detected), s, side="right") / n
    epsilon = math.sqrt(math.log(2 / 0.001) / (2 * n))  # DKW, α = 0.001
    assert np.max(np.abs(ecdf - model)) < epsilon
    # Recognised by the end: detected, and u below P_rec at some moment at or after detection.
    p_rec = start[1] + (end[1] - start[1]) * s / dt
    survive = np.exp(-hazard)  # (u, s): not yet detected by s
    density = -np.diff(survive, axis=1)  # detection within each sub-interval
    later = np.maximum.accumulate(p_rec[::-1])[::-1][1:]  # max P_rec from there to the end
    expected = (density * (u[:, None] < later[None, :])).sum(axis=1).mean()
    sigma = math.sqrt(expected * (1 - expected) / n)
    assert abs(np.isfinite(recognised).mean() - expected) < 4 * sigma + 1e-3
