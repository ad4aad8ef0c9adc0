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
from targetacq.core.engines import ENGINES, bind
from targetacq.scenario.schema import load_scenario

EXAMPLES = sorted((Path(__file__).parents[2] / "examples").glob("*.toml"))
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


# -- a visible fraction and moving flags per call ----------------------------------------------

# The JAX engine compiles per shape and per argument given: two examples keep it short (an
# imager's and a laser radar's, whose relief SCR follows the visible fraction).
JAX_EXAMPLES = {"uav_haze", "laser_radar"}


def _engines_for(path: Path) -> list[str]:
    return [e for e in ENGINE_NAMES if e != "jax" or path.stem in JAX_EXAMPLES]


def _results(
    bound: object,
    sensors: np.ndarray,
    targets: np.ndarray,
    headings: np.ndarray,
    visible: object = None,
    moving: object = None,
) -> dict[str, object]:
    found = bound.factors(sensors, targets, headings, visible_fraction=visible)
    p = bound.probabilities(found, moving=moving)
    out = {name: getattr(found, name) for name in FACTORS}
    out.update({name: getattr(p, name) for name in PROBABILITIES + FUSED})
    return out


def _same(got: dict[str, object], expected: dict[str, object], exact: bool = False) -> None:
    for name, value in expected.items():
        if value is None:
            assert got[name] is None, name
        elif exact:
            np.testing.assert_array_equal(np.asarray(got[name]), np.asarray(value), err_msg=name)
        else:
            _close(got[name], value, name)


def _fractions(n_g: int) -> np.ndarray:
    return np.linspace(0.3, 0.9, n_g)


def _flip(scene: core.SceneArrays) -> np.ndarray:
    return ~np.asarray(scene.targets.moving, dtype=bool)


def _with_targets(scene: core.SceneArrays, **changes: object) -> core.SceneArrays:
    return dataclasses.replace(scene, targets=dataclasses.replace(scene.targets, **changes))


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_the_scenes_own_values_change_nothing(path: Path) -> None:
    scene, sensors, targets, headings = _example(path)
    own_visible = np.array(scene.targets.visible_fraction)
    own_moving = np.array(scene.targets.moving, dtype=bool)
    for engine in _engines_for(path):
        bound = _bind(scene, engine)
        if bound is None:
            continue
        reference = _results(bound, sensors, targets, headings)
        # Exact on NumPy and numba; JAX compiles the call with the flags given as another XLA
        # graph (the probabilities again from the factors on the device), whose fusion may
        # round differently in the last bit.
        _same(
            _results(bound, sensors, targets, headings, own_visible, own_moving),
            reference,
            exact=engine != "jax",
        )


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_a_visible_fraction_per_call_is_a_scene_compiled_with_it(path: Path) -> None:
    """Per target: a whole new scenario compiled with the fractions (laser radars' relief SCR
    included); per sensor and target, and per time: the rows and columns of scenes with
    ``dataclasses.replace`` of their targets."""
    scenario = load_scenario(path)
    scene, sensors, targets, headings = _example(path)
    n_s, n_g = scene.shape
    fractions = _fractions(n_g)
    recompiled = scenario.model_copy(
        update={
            "targets": [
                t.model_copy(update={"visible_fraction": float(v)})
                for t, v in zip(scenario.targets, fractions, strict=True)
            ]
        }
    )
    other = core.compile_scenario(recompiled).scene
    numpy_reference = None
    for engine in _engines_for(path):
        bound = _bind(scene, engine)
        if bound is None:
            continue
        got = _results(bound, sensors, targets, headings, fractions)
        expected = _results(bind(other, engine), sensors, targets, headings)
        _same(got, expected)
        if numpy_reference is None:
            numpy_reference = got
        else:  # the engines agree
            _same(got, numpy_reference)
    if core.has_active(scene):
        return
    # Per pair (n_s, n_g): row s is the scene whose targets have the fractions of row s.
    per_pair = np.linspace(0.2, 1.0, n_s * n_g).reshape(n_s, n_g)
    for engine in ("numpy", "numba"):
        bound = bind(scene, engine)
        found = bound.factors(sensors, targets, headings, visible_fraction=per_pair)
        for s in range(n_s):
            row = bind(_with_targets(scene, visible_fraction=per_pair[s]), engine)
            expected = row.factors(sensors, targets, headings)
            for name in ("critical_dimension", "cycles", "snr"):
                _close(getattr(found, name)[s], getattr(expected, name)[s], name)
            _close(
                bound.probabilities(found).detection[s],
                row.probabilities(expected).detection[s],
                "detection",
            )
    # Per time (1, n_g, n_t): time k is the scene with the fractions of time k.
    n_t = targets.shape[1]
    per_time = np.linspace(0.25, 1.0, n_g * n_t).reshape(1, n_g, n_t)
    found = bind(scene, "numpy").factors(sensors, targets, headings, visible_fraction=per_time)
    for k in (0, n_t - 1):
        expected = bind(_with_targets(scene, visible_fraction=per_time[0, :, k]), "numpy").factors(
            sensors, targets, headings
        )
        _close(found.cycles[..., k], expected.cycles[..., k], "cycles")


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_moving_per_call_is_a_scene_whose_targets_move(path: Path) -> None:
    scene, sensors, targets, headings = _example(path)
    moving = _flip(scene)
    other = _with_targets(scene, moving=tuple(bool(m) for m in moving))
    numpy_reference = None
    for engine in _engines_for(path):
        bound = _bind(scene, engine)
        if bound is None:
            continue
        got = _results(bound, sensors, targets, headings, moving=moving)
        _same(got, _results(bind(other, engine), sensors, targets, headings))
        if numpy_reference is None:
            numpy_reference = got
        else:
            _same(got, numpy_reference)


def test_moving_flags_change_detection() -> None:
    """The comparison above can fail: moving targets are detected otherwise (uav_haze)."""
    scene, sensors, targets, headings = _example(EXAMPLES[-1])
    for engine in ("numpy", "numba", "jax"):
        bound = bind(scene, engine)
        found = bound.factors(sensors, targets, headings)
        still = bound.probabilities(found, moving=np.zeros(scene.shape[1], dtype=bool))
        moving = bound.probabilities(found, moving=np.ones(scene.shape[1], dtype=bool))
        assert not np.allclose(still.detection, moving.detection, equal_nan=True), engine


@pytest.mark.parametrize("engine", ENGINE_NAMES)
def test_a_nan_visible_fraction_gives_nan_for_its_pairs(engine: str) -> None:
    _needs(engine)
    scene, sensors, targets, headings = _example(EXAMPLES[-1])
    n_g = scene.shape[1]
    visible = np.full(n_g, 0.7)
    visible[0] = np.nan
    bound = bind(scene, engine)
    found = bound.factors(sensors, targets, headings, visible_fraction=visible)
    p = bound.probabilities(found)
    assert np.isnan(p.detection[:, 0]).all() and np.isnan(p.fused_detection[0]).all()
    assert not np.isnan(found.range[:, 0]).any()  # the geometry is known, the target is not
    reference = bind(_with_targets(scene, visible_fraction=np.full(n_g, 0.7)), engine)
    expected = reference.probabilities(reference.factors(sensors, targets, headings))
    _close(p.detection[:, 1:], expected.detection[:, 1:], "detection")


@pytest.mark.parametrize("engine", ENGINE_NAMES)
@pytest.mark.parametrize(
    ("visible", "match"),
    [
        (0.0, r"visible_fraction must be in \(0, 1\]"),
        (1.5, r"visible_fraction must be in \(0, 1\]"),
        (-np.inf, r"visible_fraction must be in \(0, 1\]"),
        ("wrong-length", r"visible_fraction must have shape \(3,\)"),
        ("wrong-axes", r"visible_fraction must have shape \(3,\)"),
    ],
)
def test_a_bad_visible_fraction_names_it(engine: str, visible: object, match: str) -> None:
    _needs(engine)
    scene, sensors, targets, headings = _example(EXAMPLES[-1])
    n_s, n_g = scene.shape
    assert n_g == 3  # uav_haze
    if visible == "wrong-length":
        value = np.full(n_g + 1, 0.5)
    elif visible == "wrong-axes":
        value = np.full((n_s, n_g, targets.shape[1] + 1), 0.5)
    else:
        value = np.full(n_g, visible)
        value[0] = 0.5
    with pytest.raises(ValueError, match=match):
        bind(scene, engine).factors(sensors, targets, headings, visible_fraction=value)


@pytest.mark.parametrize("engine", ENGINE_NAMES)
@pytest.mark.parametrize(
    "moving", [np.zeros(4, dtype=bool), np.zeros((1, 3), dtype=bool), np.array([0, 1, 1])]
)
def test_bad_moving_flags_name_moving(engine: str, moving: np.ndarray) -> None:
    _needs(engine)
    scene, sensors, targets, headings = _example(EXAMPLES[-1])
    bound = bind(scene, engine)
    found = bound.factors(sensors, targets, headings)
    with pytest.raises(ValueError, match="moving must"):
        bound.probabilities(found, moving=moving)
    with pytest.raises(ValueError, match="moving must"):
        core.evaluate(scene, sensors, targets, headings, moving=moving)


# -- one time in one call: BoundEngine.step ----------------------------------------------------


def _one_time_calls(scene: core.SceneArrays, headings: np.ndarray) -> list[dict[str, object]]:
    """No per-call input, then every one of them (pointing NaN for half the sensors)."""
    n_s, n_g = scene.shape
    rng = np.random.default_rng(7)
    pointing = np.column_stack([rng.uniform(0, 2 * np.pi, n_s), rng.uniform(0.0, 0.6, n_s)])
    pointing[::2] = np.nan
    visible = rng.uniform(0.2, 1.0, (n_s, n_g))
    visible[0, 0] = np.nan  # NaN for that pair, whatever its field of view
    scr = None if scene.signature.scr is None else rng.uniform(0.5, 20.0, (n_s, n_g))
    return [
        {},
        {
            "headings": headings + 0.3,
            "pointing": pointing,
            "visible_fraction": visible,
            "moving": rng.uniform(size=n_g) < 0.5,
            "scr": scr,
        },
    ]


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_step_is_factors_then_probabilities(path: Path) -> None:
    """``bound.step`` of one time: ``in_view`` exactly and the probabilities and their fusion
    to 1e-12 of ``factors`` then ``probabilities`` of the same engine, and of the NumPy
    engine's."""
    scene, sensors, targets, headings = _example(path)
    n_t = targets.shape[1]
    for engine in _engines_for(path):
        bound = _bind(scene, engine)
        if bound is None:
            continue
        numpy_bound = bind(scene, "numpy")
        for k in sorted({0, n_t // 2, n_t - 1}):
            s_pos, t_pos = sensors[:, k], targets[:, k]
            for call in _one_time_calls(scene, headings[:, k]):
                call = {**call, "headings": call.get("headings", headings[:, k])}
                moving = call.pop("moving", None)
                for reference in (bound, numpy_bound):
                    found = reference.factors(s_pos, t_pos, **call)
                    p = reference.probabilities(found, moving)
                    in_view, tasks, fused = bound.step(s_pos, t_pos, moving=moving, **call)
                    np.testing.assert_array_equal(in_view, found.in_view)
                    for j, name in enumerate(PROBABILITIES):
                        _close(tasks[j], getattr(p, name), f"{engine} {name}")
                        _close(fused[j], getattr(p, FUSED[j]), f"{engine} {FUSED[j]}")
                    assert in_view.shape == scene.shape and tasks.shape == (3, *scene.shape)
                if call.get("visible_fraction") is not None:
                    assert np.isnan(tasks[:, 0, 0]).all()


@pytest.mark.parametrize("engine", ENGINE_NAMES)
def test_step_refuses_what_is_not_one_time_and_infinite_positions(engine: str) -> None:
    _needs(engine)
    scene, sensors, targets, _ = _example(EXAMPLES[-1])
    bound = bind(scene, engine)
    with pytest.raises(ValueError, match=r"\(1, 3\)"):
        bound.step(sensors, targets)  # a batch of times
    s_pos, t_pos = sensors[:, 0].copy(), targets[:, 0].copy()
    bad = s_pos.copy()
    bad[0, 1] = np.inf
    with pytest.raises(ValueError, match="sensor_positions must be finite"):
        bound.step(bad, t_pos)
    bad = t_pos.copy()
    bad[-1, 2] = -np.inf
    with pytest.raises(ValueError, match="target_positions must be finite"):
        bound.step(s_pos, bad)
    with pytest.raises(ValueError, match="target_positions must be finite"):
        bound.factors(s_pos, bad)


@pytest.mark.parametrize("engine", ENGINE_NAMES)
def test_a_nan_position_gives_nan_for_its_pairs_in_a_step(engine: str) -> None:
    _needs(engine)
    scene, sensors, targets, _ = _example(EXAMPLES[-1])
    s_pos, t_pos = sensors[:, 0].copy(), targets[:, 0].copy()
    t_pos[1, 0] = np.nan
    in_view, tasks, fused = bind(scene, engine).step(s_pos, t_pos)
    assert not in_view[:, 1].any()
    assert np.isnan(tasks[:, :, 1]).all() and np.isnan(fused[:, 1]).all()
    assert not np.isnan(tasks[:, :, 0]).any()


@pytest.mark.parametrize("engine", ENGINE_NAMES)
def test_a_scalar_visible_fraction_is_every_targets(engine: str) -> None:
    _needs(engine)
    scene, sensors, targets, headings = _example(EXAMPLES[-1])
    bound = bind(scene, engine)
    got = _results(bound, sensors, targets, headings, 0.6)
    _same(got, _results(bound, sensors, targets, headings, np.full(scene.shape[1], 0.6)))
