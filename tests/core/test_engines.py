"""The compute engines agree: numba and JAX give the NumPy engine's numbers.

The NumPy engine (the array core, :mod:`targetacq.core.evaluation`) is the reference. The numba
engine mirrors its arithmetic element by element, so the two must agree to 1e-12 relative on
every probability (with an absolute floor of 1e-15: a fused ``1 − Π(1 − p)`` of tiny ``p`` is
only known to a few units of 1e-16 in either engine) and exactly on the field of view. Checked
over the bundled examples and over scenarios drawn by Hypothesis that exercise every choice
the numba engine compiles (transforms, noise models, motion rules, semantics, clutter as a
region, an SCR or a temperature spread, hot spots, moving targets, segments, clouds, sensor
noise, pointing by angles, at a point or not at all).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from targetacq import Simulation
from targetacq.core.engines import ENGINES, bind, engine_names, get_engine
from targetacq.run.model_chain import ModelChain
from targetacq.scenario.schema import load_scenario, parse_scenario

numba = pytest.importorskip("numba")

EXAMPLES = sorted((Path(__file__).parents[2] / "examples").glob("*.toml"))
# The numba engine compiles the imaging sensors; radars and laser radars are NumPy and JAX.
ACTIVE = {"radar_surveillance", "laser_radar", "fused_tv_thermal_radar"}
IMAGING = [p for p in EXAMPLES if p.stem not in ACTIVE]
PER_TRIPLE = ("range", "critical_dimension", "cycles", "transmittance", "snr")
PROBABILITIES = (
    "detection",
    "recognition",
    "identification",
    "fused_detection",
    "fused_recognition",
    "fused_identification",
)


def assert_agree(ours: dict[str, np.ndarray], reference: dict[str, np.ndarray]) -> None:
    """Probabilities to 1e-12 relative (1e-15 absolute), the field of view exactly, the other
    factors to 1e-12 relative, NaN and ±inf in the same places."""
    np.testing.assert_array_equal(ours["in_view"], reference["in_view"])
    for name in PROBABILITIES:
        np.testing.assert_allclose(
            ours[name], reference[name], rtol=1e-12, atol=1e-15, err_msg=name
        )
    for name in PER_TRIPLE:
        np.testing.assert_allclose(ours[name], reference[name], rtol=1e-12, atol=0, err_msg=name)


# -- the registry ------------------------------------------------------------------------------


def test_registry_names_and_errors() -> None:
    assert engine_names() == tuple(ENGINES)
    assert {"numpy", "numba", "jax", "auto"} <= set(ENGINES)
    with pytest.raises(ValueError, match="numpy"):  # the valid names are listed
        get_engine("numbaa")


def test_unavailable_engine_names_its_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "numba" else real(name, *a)
    )
    with pytest.raises(ValueError, match=r"targetacq\[fast\]"):
        get_engine("numba")


def test_numba_refuses_a_choice_it_does_not_compile() -> None:
    chain = ModelChain(load_scenario(EXAMPLES[0]))
    scene = chain.compiled.scene
    odd = dataclasses.replace(scene, choices=dataclasses.replace(scene.choices, transform="mine"))
    with pytest.raises(ValueError, match="engine='numpy'"):
        bind(odd, "numba")


def test_model_chain_rejects_unknown_engine() -> None:
    with pytest.raises(ValueError, match="engine"):
        ModelChain(load_scenario(EXAMPLES[0]), engine="gpu")


# -- bundled examples --------------------------------------------------------------------------


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
@pytest.mark.parametrize("engine", ["numba", "jax", "auto"])
def test_engines_agree_on_bundled_examples(path: Path, engine: str) -> None:
    if not ENGINES[engine].available():
        pytest.skip(f"{engine} is not installed")
    scenario = load_scenario(path)
    times = np.asarray(scenario.time.times())
    reference = ModelChain(scenario).compute(times)
    if engine == "numba" and path.stem in ACTIVE:
        with pytest.raises(ValueError, match="radars and laser radars run on engine='numpy'"):
            ModelChain(scenario, engine=engine)
        return
    chain = ModelChain(scenario, engine=engine)
    assert_agree(chain.compute(times), reference)
    resolved = "numba" if path.stem not in ACTIVE else "numpy"  # auto falls back to NumPy
    assert chain.provenance()["model"]["engine"] == (resolved if engine == "auto" else engine)


@pytest.mark.parametrize("path", IMAGING, ids=[p.stem for p in IMAGING])
def test_simulation_steps_agree(path: Path) -> None:
    """The step API with the numba engine: the same probabilities and the same events (sensor,
    target, task; their times to 1e-12)."""
    scenario = load_scenario(path)
    ours = Simulation.from_scenario(scenario, seed=5, engine="numba")
    reference = Simulation.from_scenario(scenario, seed=5)
    assert ours.engine == "numba" and reference.engine == "numpy"
    from targetacq import core

    times = np.asarray(scenario.time.times())
    sensors, targets, headings = core.scenario_positions(scenario, times, slice(None))
    previous = times[0]
    for k, t in enumerate(times):
        a = ours.step(t, t - previous, sensors[:, k], targets[:, k], headings[:, k])
        b = reference.step(t, t - previous, sensors[:, k], targets[:, k], headings[:, k])
        previous = t
        np.testing.assert_array_equal(a.in_view, b.in_view)
        for name in PROBABILITIES:
            np.testing.assert_allclose(
                getattr(a, name), getattr(b, name), rtol=1e-12, atol=1e-15, err_msg=name
            )
        # The same events; their times come from the probabilities, so to the same precision.
        assert [e[:3] for e in a.events] == [e[:3] for e in b.events]
        np.testing.assert_allclose(
            [e.time for e in a.events], [e.time for e in b.events], rtol=1e-12
        )


def test_chunks_equal_one_evaluation() -> None:
    """The numba engine bound per chunk of targets gives the whole evaluation's numbers."""
    scenario = load_scenario(EXAMPLES[-1])
    chain = ModelChain(scenario, engine="numba")
    times = np.asarray(scenario.time.times())
    whole = chain.compute(times)
    for chosen, part, arrays in chain.evaluate_chunks(
        times, targets_per_chunk=1, times_per_chunk=3
    ):
        first = int(np.searchsorted(times, part[0]))
        span = slice(first, first + part.size)
        np.testing.assert_array_equal(arrays["detection"], whole["detection"][:, chosen, span])


# -- scenarios drawn by Hypothesis -------------------------------------------------------------


def _metres(value: float) -> str:
    return f"{value:.3f} m"


@st.composite
def scenarios(draw: st.DrawFn) -> dict:
    n_sensors = draw(st.integers(1, 3))
    n_targets = draw(st.integers(1, 4))
    coordinate = st.floats(-4000.0, 4000.0)
    sensors = []
    for i in range(n_sensors):
        sensor = {
            "name": f"s{i}",
            "type": "thermal",
            "band": draw(st.sampled_from(["lwir", "mwir"])),
            "pixels": [640, 480],
            "pitch": f"{draw(st.sampled_from([12, 15, 17]))} um",
            "focal_length": f"{draw(st.floats(10.0, 300.0)):.2f} mm",
            "position": [
                _metres(draw(coordinate)),
                _metres(draw(coordinate)),
                _metres(draw(st.floats(2.0, 3000.0))),
            ],
        }
        pointing = draw(st.sampled_from(["none", "angles", "look_at"]))
        if pointing == "angles":
            sensor["azimuth"] = f"{draw(st.floats(0.0, 359.0)):.2f} deg"
            sensor["depression"] = f"{draw(st.floats(-10.0, 89.0)):.2f} deg"
        elif pointing == "look_at":
            sensor["look_at"] = [_metres(draw(coordinate)), _metres(draw(coordinate)), "0 m"]
        if draw(st.booleans()):
            sensor["netd"] = f"{draw(st.floats(10.0, 200.0)):.1f} mK"
        sensors.append(sensor)
    targets = [
        {
            "name": f"t{j}",
            "dimensions": [
                _metres(draw(st.floats(0.5, 10.0))),
                _metres(draw(st.floats(0.5, 5.0))),
                _metres(draw(st.floats(0.5, 4.0))),
            ],
            "heading": f"{draw(st.floats(0.0, 359.0)):.1f} deg",
            "temperature": f"{draw(st.floats(280.0, 330.0)):.2f} K",
            "position": [_metres(draw(coordinate)), _metres(draw(coordinate)), "0 m"],
            "criterion": draw(st.sampled_from(["johnson", "johnson-truck", "johnson-jeep"])),
            "hot_spot": draw(st.booleans()),
            "moving": draw(st.booleans()),
        }
        for j in range(n_targets)
    ]
    background: dict = {"temperature": f"{draw(st.floats(270.0, 320.0)):.2f} K"}
    clutter = draw(st.sampled_from(["none", "region", "scr", "clutter_std"]))
    if clutter == "region":
        background["clutter"] = draw(st.sampled_from(["low", "medium", "high"]))
    elif clutter == "scr":
        background["scr"] = draw(st.floats(0.0, 30.0))
    elif clutter == "clutter_std":
        background["clutter_std"] = f"{draw(st.floats(0.1, 8.0)):.2f} K"
    document: dict = {
        "sensors": sensors,
        "targets": targets,
        "background": background,
        # A short batch (targets in rows by their model) or a long one (a row per pair).
        "time": {"start": "0 s", "stop": f"{draw(st.sampled_from([2, 9]))} s", "step": "1 s"},
    }
    path = draw(st.sampled_from(["none", "haze", "extinction", "segments"]))
    if path == "haze":
        document["atmosphere"] = {"obscurant": "haze:high"}
    elif path in ("extinction", "segments"):
        atmosphere: dict = {"extinction": f"{draw(st.floats(0.0, 2.0)):.3f} /km"}
        if path == "segments":
            atmosphere["segments"] = [
                {"length": _metres(draw(st.floats(0.0, 3000.0))), "extinction": "1.5 /km"}
                for _ in range(draw(st.integers(1, 2)))
            ]
            atmosphere["clouds"] = [
                {
                    "center": [_metres(draw(coordinate)), _metres(draw(coordinate)), "50 m"],
                    "radius": _metres(draw(st.floats(50.0, 3000.0))),
                    "extinction": "3 /km",
                }
            ]
        document["atmosphere"] = atmosphere
    transform = draw(st.sampled_from(["ttpf", "c2nveo"]))
    model = {
        "transform": transform,
        "noise_model": draw(st.sampled_from(["variance-sum", "clutter-analogue", "none"])),
        "motion": draw(st.sampled_from(["low-clutter", "always"])),
        "semantics": draw(st.sampled_from(["nested", "conditional"])),
    }
    if transform == "c2nveo":
        model["bound"] = draw(st.sampled_from(["optimistic", "nominal", "pessimistic"]))
    document["model"] = model
    return document


@settings(
    max_examples=60,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.too_slow],
)
@given(document=scenarios())
def test_numba_agrees_on_drawn_scenarios(document: dict) -> None:
    scenario = parse_scenario(document)
    times = np.asarray(scenario.time.times())
    assert_agree(
        ModelChain(scenario, engine="numba").compute(times), ModelChain(scenario).compute(times)
    )


# -- the vectorisable exponential and logarithm ------------------------------------------------


def test_simd_exp_log_match_numpy() -> None:
    """A few units in the last place against NumPy over the whole double range, and the special
    values as NumPy has them."""
    from numba import njit

    from targetacq.core.engines import _simd

    @njit(error_model="numpy")
    def apply(kind: int, values: np.ndarray) -> np.ndarray:
        out = np.empty_like(values)
        for k in range(values.size):
            v = values[k]
            out[k] = (
                _simd.exp(v)
                if kind == 0
                else _simd.log(v)
                if kind == 1
                else _simd.expm1(v)
                if kind == 2
                else _simd.log10(v)
            )
        return out

    rng = np.random.default_rng(11)
    wide = rng.uniform(-745.0, 709.0, 200_000)
    positive = np.exp(rng.uniform(-744.0, 709.0, 200_000))
    small = rng.uniform(-1.0, 1.0, 50_000) * 10.0 ** rng.uniform(-300.0, 0.5, 50_000)
    with np.errstate(all="ignore"):
        for kind, values, reference in (
            (0, wide, np.exp),
            (1, positive, np.log),
            (2, small, np.expm1),
            (3, positive, np.log10),
        ):
            expected = reference(values)
            normal = np.abs(expected) > 2.3e-308
            got = apply(kind, values)
            np.testing.assert_allclose(got[normal], expected[normal], rtol=1e-15, atol=0)
        specials = np.array([0.0, -0.0, np.nan, np.inf, -np.inf, -1.0, 5e-324, 1e-310, 709.9])
        for kind, reference in ((0, np.exp), (1, np.log), (2, np.expm1), (3, np.log10)):
            np.testing.assert_allclose(
                apply(kind, specials), reference(specials), rtol=1e-13, atol=0, equal_nan=True
            )


# -- the command line --------------------------------------------------------------------------


def _cli(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    from targetacq.cli import main

    with pytest.raises(SystemExit) as done:
        main(list(args))
    out, err = capsys.readouterr()
    return int(done.value.code or 0), out, err


def test_cli_evaluate_engine_gives_the_same_peaks(capsys: pytest.CaptureFixture[str]) -> None:
    import json

    path = str(EXAMPLES[-1])
    runs = {}
    for engine in ("numpy", "numba"):
        code, out, _ = _cli(capsys, "evaluate", path, "--format", "json", "--engine", engine)
        assert code == 0
        runs[engine] = json.loads(out)
    for ours, reference in zip(runs["numba"]["targets"], runs["numpy"]["targets"], strict=True):
        assert ours.keys() == reference.keys()
        for key, value in reference.items():
            if isinstance(value, float):
                assert ours[key] == pytest.approx(value, rel=1e-12, abs=1e-15), key
            else:
                assert ours[key] == value, key


def test_cli_unknown_engine_is_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = _cli(capsys, "evaluate", "--engine", "gpu")
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and "numba" in err and "Traceback" not in err


# -- edges found in review ---------------------------------------------------------------------


def _region_scene() -> tuple[ModelChain, np.ndarray, np.ndarray]:
    document = {
        "sensors": [
            {
                "name": "ir",
                "type": "thermal",
                "band": "lwir",
                "pixels": [640, 480],
                "pitch": "17 um",
                "focal_length": "100 mm",
                "position": ["0 m", "0 m", "10 m"],
            }
        ],
        "targets": [
            {
                "name": "truck",
                "dimensions": ["7 m", "2.5 m", "3 m"],
                "temperature": "305 K",
                "position": ["1 km", "0 m", "0 m"],
            },
            {
                "name": "jeep",
                "dimensions": ["3.4 m", "1.6 m", "1.8 m"],
                "temperature": "303 K",
                "position": ["2 km", "0 m", "0 m"],
            },
        ],
        "background": {"temperature": "300 K", "clutter": "high"},
        "time": {"start": "0 s", "stop": "3 s", "step": "1 s"},
    }
    chain = ModelChain(parse_scenario(document))
    sensors = np.tile(np.array([0.0, 0.0, 10.0]), (1, 4, 1))
    targets = np.stack([np.linspace(500.0, 3000.0, 4)[:, None] * [1.0, 0.0, 0.0]] * 2)
    return chain, sensors, targets


def test_an_scr_given_wins_over_the_region() -> None:
    """``factors(scr=...)`` replaces the scene's clutter, its region too, in both engines."""
    chain, sensors, targets = _region_scene()
    scene = chain.compiled.scene
    results = []
    for engine in ("numpy", "numba"):
        bound = bind(scene, engine)
        found = bound.factors(sensors, targets, scr=np.full((1, 2, 4), 30.0))
        results.append(bound.probabilities(found))
    for name in PROBABILITIES:
        np.testing.assert_allclose(
            getattr(results[1], name), getattr(results[0], name), rtol=1e-12, atol=1e-15
        )


def test_hand_made_factors_broadcast_as_with_numpy() -> None:
    chain, sensors, targets = _region_scene()
    scene = chain.compiled.scene
    reference = bind(scene, "numpy")
    found = dataclasses.replace(reference.factors(sensors, targets), in_view=True)
    expected = reference.probabilities(found)
    got = bind(scene, "numba").probabilities(found)
    for name in PROBABILITIES:
        np.testing.assert_allclose(getattr(got, name), getattr(expected, name), rtol=1e-12)


def test_wrong_counts_and_bad_options_are_value_errors() -> None:
    chain, sensors, targets = _region_scene()
    scene = chain.compiled.scene
    bound = bind(scene, "numba")
    with pytest.raises(ValueError, match=r"target_positions must have shape \(2, \.\.\., 3\)"):
        bound.factors(sensors, targets[:1])
    with pytest.raises(ValueError, match="sensor_positions"):
        bound.factors(sensors[..., :2], targets)
    odd = dataclasses.replace(
        scene,
        choices=dataclasses.replace(scene.choices, transform="c2nveo", options=(("bound", "x"),)),
    )
    with pytest.raises(ValueError, match="bound must be one of"):
        bind(odd, "numba")


def test_an_empty_target_subset_gives_empty_results() -> None:
    chain, _, _ = _region_scene()
    numba_chain = ModelChain(chain.scenario, engine="numba")
    got = numba_chain.compute(np.arange(3.0), slice(1, 1))
    expected = chain.compute(np.arange(3.0), slice(1, 1))
    for name in ("detection", "fused_detection"):
        assert got[name].shape == expected[name].shape


def test_auto_is_numba_for_chains_and_steps_where_it_can() -> None:
    scenario = load_scenario(EXAMPLES[-1])
    assert Simulation.from_scenario(scenario, engine="auto").engine == "numba"
    assert ModelChain(scenario, engine="auto").provenance()["model"]["engine"] == "numba"
    radar = load_scenario(next(p for p in EXAMPLES if p.stem == "radar_surveillance"))
    assert Simulation.from_scenario(radar, engine="auto").engine == "numpy"


# -- one time (the step API's batches): the pair kernels ---------------------------------------


def step_scene(n_sensors: int, n_targets: int) -> tuple[object, np.ndarray, np.ndarray]:
    """The scene of ``benchmarks/bench_step.py``: thermal cameras pointed down at random
    azimuths over targets near their boresights, haze, clutter from a temperature spread; a
    sensor with its own noise and one pointed at a point, so that every path of the kernels
    runs."""
    from targetacq.scenario.schema import Atmosphere, Background, Sensor, Target

    rng = np.random.default_rng(1)
    azimuths = rng.uniform(0.0, 2 * np.pi, n_sensors)
    sensors = [
        Sensor(
            name=f"s{i}",
            band="lwir",
            pixels=(640, 512),
            pitch=17e-6,
            focal_length=35e-3,
            position=(0.0, 0.0, 0.0),
            azimuth=float(az),
            depression=float(np.radians(30.0)),
            netd=0.05 if i % 2 else None,
        )
        for i, az in enumerate(azimuths)
    ]
    targets = [
        Target(
            name=f"t{j}",
            dimensions=(7.0, 2.5, 3.0),
            temperature=float(temp),
            heading=float(h),
            position=(0.0, 0.0, 0.0),
            hot_spot=j % 3 == 1,
            moving=j % 4 == 2,
        )
        for j, (temp, h) in enumerate(
            zip(rng.uniform(295, 315, n_targets), rng.uniform(0, 2 * np.pi, n_targets), strict=True)
        )
    ]
    sim = Simulation(
        sensors,
        targets,
        background=Background(temperature=293.0, clutter_std=2.0),
        atmosphere=Atmosphere(obscurant="haze"),
        seed=1,
    )
    sensor_pos = np.column_stack(
        [
            rng.uniform(-5e3, 5e3, n_sensors),
            rng.uniform(-5e3, 5e3, n_sensors),
            rng.uniform(1e3, 3e3, n_sensors),
        ]
    )
    which = np.arange(n_targets) % n_sensors
    reach = sensor_pos[which, 2] / np.tan(np.radians(30.0))
    target_pos = np.column_stack(
        [
            sensor_pos[which, 0]
            + reach * np.sin(azimuths[which])
            + rng.uniform(-150, 150, n_targets),
            sensor_pos[which, 1]
            + reach * np.cos(azimuths[which])
            + rng.uniform(-150, 150, n_targets),
            np.zeros(n_targets),
        ]
    )
    return sim.compiled.scene, sensor_pos, target_pos


def _fields(found: object, p: object) -> dict[str, np.ndarray]:
    out = {name: np.asarray(getattr(found, name)) for name in ("in_view", *PER_TRIPLE)}
    out.update({name: np.asarray(getattr(p, name)) for name in PROBABILITIES})
    return out


@pytest.mark.parametrize("size", [(1, 1), (1, 6), (20, 500)], ids=["1x1", "1x6", "20x500"])
@pytest.mark.parametrize("engine", ["numba", "jax"])
def test_engines_agree_on_one_time(engine: str, size: tuple[int, int]) -> None:
    """Positions of one time, (n_s, 3) and (n_g, 3), at the step benchmark's sizes: factors,
    probabilities and the one-call step, with the targets' own inputs and with every per-call
    input (headings, pointing, visible fraction, moving flags)."""
    if not ENGINES[engine].available():
        pytest.skip(f"{engine} is not installed")
    scene, sensors, targets = step_scene(*size)
    n_s, n_g = size
    reference, ours = bind(scene, "numpy"), bind(scene, engine)
    rng = np.random.default_rng(3)
    pointing = np.column_stack([rng.uniform(0, 2 * np.pi, n_s), np.full(n_s, 0.5)])
    pointing[::2] = np.nan  # those keep their own
    calls = [
        {},
        {
            "headings": rng.uniform(0, 2 * np.pi, n_g),
            "pointing": pointing,
            "visible_fraction": rng.uniform(0.2, 1.0, (n_s, n_g)),
            "moving": rng.uniform(size=n_g) < 0.5,
        },
    ]
    for call in calls:
        found_args = {k: v for k, v in call.items() if k != "moving"}
        expected_f = reference.factors(sensors, targets, **found_args)
        expected = _fields(expected_f, reference.probabilities(expected_f, call.get("moving")))
        found = ours.factors(sensors, targets, **found_args)
        got = _fields(found, ours.probabilities(found, call.get("moving")))
        np.testing.assert_array_equal(got["in_view"], expected["in_view"])
        for name in (*PER_TRIPLE, *PROBABILITIES):
            np.testing.assert_allclose(
                got[name], expected[name], rtol=1e-12, atol=1e-15, err_msg=name
            )
        in_view, p, fused = ours.step(sensors, targets, **call)
        np.testing.assert_array_equal(in_view, expected["in_view"])
        for k in range(3):
            np.testing.assert_allclose(
                p[k], expected[PROBABILITIES[k]], rtol=1e-12, atol=1e-15, err_msg="step"
            )
            np.testing.assert_allclose(
                fused[k], expected[PROBABILITIES[3 + k]], rtol=1e-12, atol=1e-15, err_msg="step"
            )
    assert expected["in_view"].any()  # the comparison sees pairs in view


@settings(
    max_examples=40,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.too_slow],
)
@given(document=scenarios(), when=st.floats(0.0, 1.0))
def test_numba_agrees_on_one_time_of_drawn_scenarios(document: dict, when: float) -> None:
    """The pair kernels on every choice they compile (the drawn scenarios above), at one
    time: factors, probabilities and the one-call step."""
    from targetacq import core

    scenario = parse_scenario(document)
    times = np.asarray(scenario.time.times())
    t = times[int(when * (times.size - 1))]
    sensors, targets, headings = core.scenario_positions(scenario, [t])
    sensors, targets, headings = sensors[:, 0], targets[:, 0], headings[:, 0]
    scene = core.compile_scenario(scenario).scene
    reference, ours = bind(scene, "numpy"), bind(scene, "numba")
    expected_f = reference.factors(sensors, targets, headings)
    expected_p = reference.probabilities(expected_f)
    found = ours.factors(sensors, targets, headings)
    assert_agree(_fields(found, ours.probabilities(found)), _fields(expected_f, expected_p))
    in_view, p, fused = ours.step(sensors, targets, headings)
    np.testing.assert_array_equal(in_view, expected_f.in_view)
    for k in range(3):
        np.testing.assert_allclose(
            p[k], getattr(expected_p, PROBABILITIES[k]), rtol=1e-12, atol=1e-15
        )
        np.testing.assert_allclose(
            fused[k], getattr(expected_p, PROBABILITIES[3 + k]), rtol=1e-12, atol=1e-15
        )


def _read_only(value: np.ndarray, dtype: type = float) -> np.ndarray:
    """The same values as a read-only, strided (not contiguous) view."""
    doubled = np.repeat(np.asarray(value, dtype=dtype)[..., None], 2, axis=-1)
    view = doubled[..., 0]
    view.flags.writeable = False
    return view


def test_numba_kernels_keep_one_signature_whatever_the_arrays() -> None:
    """Each kernel is compiled for its one signature when the module is imported, and the engine
    hands it read-only and strided arrays (a frozen scenario's, a broadcast's, a slice) as that
    signature's types: the same numbers as with writable contiguous ones, and no second
    specialisation (each would be a compilation of tens of seconds)."""
    from targetacq.core.engines import numba_kernels, numba_pairs

    kernels = (
        numba_kernels._factors_kernel,
        numba_kernels._probabilities_kernel,
        numba_pairs._pair_factors,
        numba_pairs._pair_probabilities,
        numba_pairs._pair_step,
    )
    scene, sensors, targets = step_scene(2, 5)
    ours = bind(scene, "numba")
    batch_s = np.repeat(np.asarray(sensors)[:, None, :], 8, axis=1)  # eight times: one pass
    batch_t = np.repeat(np.asarray(targets)[:, None, :], 8, axis=1)
    for s_pos, t_pos in ((sensors, targets), (batch_s, batch_t)):
        writable = _fields(found := ours.factors(s_pos, t_pos), ours.probabilities(found))
        frozen = ours.factors(_read_only(s_pos), _read_only(t_pos))
        frozen = dataclasses.replace(
            frozen, **{name: _read_only(getattr(frozen, name)) for name in PER_TRIPLE}
        )
        read_only = _fields(frozen, ours.probabilities(frozen))
        for name, value in writable.items():
            np.testing.assert_array_equal(read_only[name], value, err_msg=name)
    moving = np.arange(5) % 2 == 0
    expected = ours.step(sensors, targets, moving=moving)
    got = ours.step(_read_only(sensors), _read_only(targets), moving=_read_only(moving, bool))
    for ours_k, expected_k in zip(got, expected, strict=True):
        np.testing.assert_array_equal(ours_k, expected_k)
    assert [len(kernel.signatures) for kernel in kernels] == [1] * len(kernels)
