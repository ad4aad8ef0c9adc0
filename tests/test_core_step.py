"""The core's per-step inputs: target subsets by index, a visible fraction and moving flags per
call, and the bound engines' one-call step.

Expected values come from independent routes: a subset is checked against the whole scene's
columns, a visible fraction per call against a scene compiled with it
(``dataclasses.replace`` of its targets), moving flags against a scene whose targets move, and
the step method against ``factors`` then ``probabilities``.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from targetacq import core
from targetacq.engines import ENGINES, bind
from targetacq.scenario import load_scenario

EXAMPLES = sorted((Path(__file__).parent.parent / "examples").glob("*.toml"))
ENGINE_NAMES = ("numpy", "numba", "jax")
FACTORS = (
    "range",
    "critical_dimension",
    "cycles",
    "in_view",
    "optical_depth",
    "transmittance",
    "snr",
    "scr",
)
PROBABILITIES = ("detection", "recognition", "identification")
FUSED = ("fused_detection", "fused_recognition", "fused_identification")
NUMBA_REFUSES = "radars and laser radars run on engine='numpy'"


def _needs(engine: str) -> None:
    """Skip only where the engine's package is missing (both are installed here)."""
    if not ENGINES[engine].available():
        pytest.skip(f"{engine} is not installed")


def _example(path: Path) -> tuple[core.SceneArrays, np.ndarray, np.ndarray, np.ndarray]:
    scenario = load_scenario(path)
    compiled = core.compile_scenario(scenario)
    times = np.asarray(scenario.time.times())
    sensors, targets, headings = core.scenario_positions(scenario, times)
    return compiled.scene, sensors, targets, headings


def _bind(scene: core.SceneArrays, engine: str) -> object | None:
    """The engine bound to ``scene``; None where the numba engine refuses it, having checked
    that it says why in its own words."""
    _needs(engine)
    if engine == "numba" and core.has_active(scene):
        with pytest.raises(ValueError, match=NUMBA_REFUSES):
            bind(scene, engine)
        return None
    return bind(scene, engine)


def _close(got: object, expected: object, what: str) -> None:
    if expected is None:
        assert got is None, what
        return
    got_a, expected_a = np.asarray(got), np.asarray(expected)
    if expected_a.dtype == bool:
        np.testing.assert_array_equal(got_a, expected_a, err_msg=what)
    else:
        np.testing.assert_allclose(got_a, expected_a, rtol=1e-12, atol=1e-15, err_msg=what)


# -- target subsets by index -------------------------------------------------------------------


def _subset_index(n_g: int) -> np.ndarray:
    """Repeats, reversed order and every target at least once."""
    return np.array([n_g - 1, 0, 0, *range(n_g), n_g // 2, n_g - 1], dtype=np.int64)


@pytest.mark.parametrize("engine", ENGINE_NAMES)
@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_a_subset_equals_the_whole_scenes_columns(path: Path, engine: str) -> None:
    scene, sensors, targets, headings = _example(path)
    whole = _bind(scene, engine)
    if whole is None:
        return
    index = _subset_index(scene.shape[1])
    subset = core.take_targets(scene, index)
    assert subset.targets.names == tuple(scene.targets.names[k] for k in index)
    part = bind(subset, engine)
    found_all = whole.factors(sensors, targets, headings)
    found = part.factors(sensors, targets[index], headings[index])
    for name in FACTORS:
        reference = getattr(found_all, name)
        if reference is not None and np.ndim(reference) >= 2:
            reference = np.broadcast_to(reference, found_all.range.shape)[:, index]
            got = np.broadcast_to(getattr(found, name), found.range.shape)
        else:
            got = getattr(found, name)
        _close(got, reference, name)
    p_all, p = whole.probabilities(found_all), part.probabilities(found)
    for name in PROBABILITIES:
        _close(getattr(p, name), getattr(p_all, name)[:, index], name)
    for name in FUSED:  # over the sensors: each target's own
        _close(getattr(p, name), getattr(p_all, name)[index], name)


def test_a_subset_takes_every_per_target_array() -> None:
    scene, *_ = _example(EXAMPLES[0])
    n_g = scene.shape[1]
    index = np.array([n_g - 1, 0, n_g - 1])
    subset = core.take_targets(scene, index)
    t, sig = scene.targets, scene.signature
    for name in ("dimensions", "visible_fraction", "heading", "n50"):
        np.testing.assert_array_equal(getattr(subset.targets, name), getattr(t, name)[index])
    for name in ("names", "hot_spot", "moving"):
        assert getattr(subset.targets, name) == tuple(getattr(t, name)[k] for k in index)
    for name in ("contrast", "target"):
        np.testing.assert_array_equal(getattr(subset.signature, name), getattr(sig, name)[:, index])
    assert subset.sensors is scene.sensors and subset.path is scene.path
    assert subset.shape == (scene.shape[0], 3)
    empty = core.take_targets(scene, np.zeros(0, dtype=int))
    assert empty.shape == (scene.shape[0], 0)


def test_a_subset_of_a_jax_scene_stays_jax() -> None:
    _needs("jax")
    import jax

    from targetacq.core.records import as_jax

    scene, *_ = _example(EXAMPLES[0])
    with jax.enable_x64(True):
        subset = core.take_targets(as_jax(scene), [0, 0])
        assert isinstance(subset.targets.dimensions, jax.Array)
        np.testing.assert_array_equal(
            np.asarray(subset.signature.contrast), scene.signature.contrast[:, [0, 0]]
        )


@pytest.mark.parametrize(
    "index",
    [[0, 99], [-1], [0.0, 1.0], [[0, 1]], [True, False], 0, ["a"]],
    ids=["too-large", "negative", "floats", "2-d", "bools", "scalar", "text"],
)
def test_a_bad_index_names_targets_and_the_valid_range(index: object) -> None:
    scene, *_ = _example(EXAMPLES[0])
    n_g = scene.shape[1]
    with pytest.raises(ValueError, match=rf"targets.*\[0, {n_g - 1}\]"):
        core.take_targets(scene, index)
