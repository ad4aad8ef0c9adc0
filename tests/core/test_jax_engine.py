"""The JAX engine (``engine="jax"``): one jitted call from positions to probabilities, fixed
chunk shapes (one compilation per bound scene, whatever the number of times) and one transfer
to the host per call.

The reference numbers are the NumPy engine's; the compilations are counted by the engine's own
trace counter (:func:`targetacq.core.engines.jax_engine.compilations`), which the Python body
of the jitted function increments only when JAX traces it, after ``jax.clear_caches()``.
"""

import dataclasses
from pathlib import Path

import numpy as np
import pytest

jax = pytest.importorskip("jax")

from targetacq import core  # noqa: E402
from targetacq.core.engines import bind, jax_engine  # noqa: E402
from targetacq.run.model_chain import ModelChain  # noqa: E402
from targetacq.scenario.schema import load_scenario  # noqa: E402

ROOT = Path(__file__).parents[2]
GOLDEN = Path(__file__).parents[1] / "data" / "golden"
PROBABILITIES = tuple(f.name for f in dataclasses.fields(core.Probabilities))
PER_TRIPLE = ("range", "critical_dimension", "cycles", "optical_depth", "transmittance", "snr")


def _scene(name="two_sensors_fused"):
    scenario = load_scenario(ROOT / "examples" / f"{name}.toml")
    return scenario, core.compile_scenario(scenario).scene


def _positions(scenario, count):
    """Positions and headings at ``count`` times spread over the scenario's run."""
    times = np.linspace(scenario.time.start, scenario.time.stop, count)
    return core.scenario_positions(scenario, times)


def _assert_equal(found, p, want_found, want):
    np.testing.assert_array_equal(
        np.broadcast_to(found.in_view, want_found.range.shape),
        np.broadcast_to(want_found.in_view, want_found.range.shape),
    )
    for name in PER_TRIPLE:
        got, expected = getattr(found, name), getattr(want_found, name)
        assert np.shape(got) == np.shape(expected), name
        np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-15, err_msg=name)
    for name in PROBABILITIES:
        got, expected = getattr(p, name), getattr(want, name)
        assert np.shape(got) == np.shape(expected), name
        np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-15, err_msg=name)


def test_chunk_length():
    assert jax_engine.chunk_length(4, 1) == 1  # one time: no padding
    assert jax_engine.chunk_length(4, 2) == jax_engine.BATCH_PER_CALL
    many = jax_engine.TRIPLES_PER_CALL // 10
    assert jax_engine.chunk_length(many, 500) == 10  # the triples per call bound the chunk
    assert jax_engine.chunk_length(10 * jax_engine.TRIPLES_PER_CALL, 500) == 2


def test_one_compilation_for_every_batch_size():
    """Calls of 3, 17 and 64 times (one chunk) and of 200 (four chunks, the last padded) run
    one compiled shape: the function is traced once. Each call equals the NumPy engine."""
    scenario, scene = _scene()
    ours, reference = bind(scene, "jax"), bind(scene, "numpy")
    jax.clear_caches()
    before = jax_engine.compilations()["evaluate"]
    for count in (3, 17, 64, 200):
        s, t, h = _positions(scenario, count)
        found = ours.factors(s, t, h)
        p = ours.probabilities(found)
        want_found = reference.factors(s, t, h)
        _assert_equal(found, p, want_found, reference.probabilities(want_found))
    assert jax_engine.compilations()["evaluate"] - before == 1


def test_padded_chunks_keep_nan_and_batch_axes():
    """A NaN position inside the last (padded) chunk gives NaN there only; two batch axes
    and none at all come back in the NumPy engine's shapes."""
    scenario, scene = _scene()
    ours = bind(scene, "jax")
    s, t, h = _positions(scenario, 130)
    t = t.copy()
    t[0, 129] = np.nan
    for args in (
        (s, t, h),
        (s.reshape(s.shape[0], 10, 13, 3), t.reshape(t.shape[0], 10, 13, 3), h.reshape(-1, 10, 13)),
        (s[:, 5], t[:, 5], h[:, 5]),
    ):
        found, p = ours.evaluate(*args)
        want_found, want = core.evaluate(scene, *args)
        _assert_equal(found, p, want_found, want)
    found, p = ours.evaluate(s, t, h)
    assert np.isnan(p.detection[:, 0, 129]).all()
    assert np.isfinite(p.detection[:, 0, 128]).all()


def test_factors_then_probabilities_transfer_once(monkeypatch):
    """factors() computes the probabilities in the same jitted call and brings both to the
    host in one ``jax.device_get``; probabilities() of those factors transfers nothing more.
    Factors changed on the host (here the SCR) go through the probabilities alone."""
    scenario, scene = _scene()
    ours, reference = bind(scene, "jax"), bind(scene, "numpy")
    s, t, h = _positions(scenario, 150)  # three chunks
    ours.factors(s, t, h)  # compiled here, outside the count
    calls = []
    real = jax.device_get

    def counting(value):
        calls.append(1)
        return real(value)

    monkeypatch.setattr(jax, "device_get", counting)
    found = ours.factors(s, t, h)
    p = ours.probabilities(found)
    assert len(calls) == 1
    want_found = reference.factors(s, t, h)
    _assert_equal(found, p, want_found, reference.probabilities(want_found))
    moving = np.array([True] * scene.shape[1])
    np.testing.assert_allclose(
        ours.probabilities(found, moving).detection,
        reference.probabilities(want_found, moving).detection,
        rtol=1e-12,
        atol=1e-15,
    )
    assert len(calls) == 2
    changed = dataclasses.replace(found, scr=np.full(found.range.shape, 2.0))
    want = reference.probabilities(dataclasses.replace(want_found, scr=changed.scr))
    got = ours.probabilities(changed)
    for name in PROBABILITIES:
        np.testing.assert_allclose(
            getattr(got, name), getattr(want, name), rtol=1e-12, atol=1e-15, err_msg=name
        )
    assert not np.allclose(got.detection, p.detection, equal_nan=True)  # the SCR mattered


def test_chunks_of_targets_compile_once():
    """evaluate_chunks binds the engine to each chunk of targets; chunks of one target each and
    of three times each (the last padded) run one compilation, with the whole run's numbers."""
    scenario = load_scenario(ROOT / "examples" / "two_sensors_fused.toml")
    assert len(scenario.targets) > 1
    chain = ModelChain(scenario, engine="jax")
    times = np.linspace(scenario.time.start, scenario.time.stop, 11)
    whole = ModelChain(scenario).compute(times)
    jax.clear_caches()
    before = jax_engine.compilations()["evaluate"]
    for chosen, part, arrays in chain.evaluate_chunks(
        times, targets_per_chunk=1, times_per_chunk=3
    ):
        first = int(np.searchsorted(times, part[0]))
        span = slice(first, first + part.size)
        for name in ("detection", "snr", "range"):
            np.testing.assert_allclose(
                arrays[name], whole[name][:, chosen, span], rtol=1e-12, atol=1e-15, err_msg=name
            )
    assert jax_engine.compilations()["evaluate"] - before == 1


def test_terrain_map_scenarios_run_on_the_jax_engine():
    """A terrain map's SCR is looked up on the host between the factors and the
    probabilities (ModelChain's clutter step); the JAX engine gives the NumPy numbers."""
    scenario = load_scenario(GOLDEN / "terrain.toml")
    times = np.asarray(scenario.time.times())
    want = ModelChain(scenario).compute(times)
    got = ModelChain(scenario, engine="jax").compute(times)
    assert set(got) == set(want)
    for name, value in want.items():
        np.testing.assert_allclose(
            np.asarray(got[name], dtype=float),
            np.asarray(value, dtype=float),
            rtol=1e-12,
            atol=1e-15,
            err_msg=name,
        )


def test_positions_of_the_wrong_shape_are_refused():
    _, scene = _scene()
    ours = bind(scene, "jax")
    with pytest.raises(ValueError, match="sensor_positions must have shape"):
        ours.factors(np.zeros((scene.shape[0] + 1, 3)), np.zeros((scene.shape[1], 3)))
