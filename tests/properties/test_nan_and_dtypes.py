"""Input matrix over the kernels: NaN in gives NaN out at exactly those elements, infinities,
zeros and negatives give a limit or a clear error, and non-numeric dtypes are refused.

The kernels come from two places: the public functions of ``targetacq`` (and the kernel
modules' own), each with valid inputs below (a test fails when a public function has no
entry), and the registries (transforms, noise models, motion rules, semantics, critical
dimension methods, band exitance methods, resolution models), iterated so that a new entry is
tested without editing this file.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import targetacq as ta
from targetacq.acquisition import cues, transforms
from targetacq.acquisition import observed_detection as od
from targetacq.acquisition import path_noise as noise
from targetacq.acquisition import probabilities as acquisition
from targetacq.acquisition.criteria import CRITERIA
from targetacq.base import arrays as _arrays
from targetacq.base import constants
from targetacq.core.cases import RESOLUTION_MODELS, RangeCase, case_acquisition
from targetacq.physics import (
    atmosphere,
    clutter,
    detector_noise,
    geometry,
    named_atmospheres,
    optics,
    radiometry,
)

# --------------------------------------------------------------------------------------------
# The kernels and valid inputs: every float keyword is an array input of the kernel.
# --------------------------------------------------------------------------------------------

Kernel = tuple[Callable[..., Any], dict[str, Any]]


def _with_clutter(function: Callable[..., Any]) -> Callable[..., Any]:
    """``function``, with the fields of its :class:`targetacq.Clutter` record given as keywords
    (so that the matrix puts NaN into each of them as into any other input)."""

    def call(
        *,
        scr: Any = None,
        region: Any = None,
        hot_spot: Any = False,
        moving: Any = False,
        hot_spot_ratio: Any = None,
        hot_spot_size: Any = None,
        speed: Any = None,
        **kw: Any,
    ) -> Any:
        clutter = ta.Clutter(
            scr=scr,
            region=region,
            hot_spot=hot_spot,
            moving=moving,
            hot_spot_ratio=hot_spot_ratio,
            hot_spot_size=hot_spot_size,
            speed=speed,
        )
        return function(**kw, clutter=clutter)

    call.__name__ = function.__name__
    return call


KERNELS: dict[str, Kernel] = {
    "sky_reflected_exitance": (
        radiometry.sky_reflected_exitance,
        {"emissivity": 0.3, "temperature": 300.0, "sky_temperature": 240.0, "band": "lwir"},
    ),
    "contrast_transmittance": (
        atmosphere.contrast_transmittance,
        {"transmittance": 0.5, "sky_to_ground": 2.0},
    ),
    "path_radiance": (
        atmosphere.path_radiance,
        {"transmittance": 0.5, "air_temperature": 290.0, "band": "lwir"},
    ),
    "cue_weight": (cues.cue_weight, {"ratio": 2.0, "ratio50": 3.0}),
    "hot_spot_weight": (cues.hot_spot_weight, {"ratio": 5.0, "elements": 0.5, "ratio50": 3.0}),
    "motion_weight": (cues.motion_weight, {"rate": 0.7, "rate50": 1.0}),
    "probability graded cues": (
        _with_clutter(ta.probability),
        {
            "cycles": 0.8,
            "task": "detection",
            "scr": 0.5,
            "hot_spot_ratio": 5.0,
            "hot_spot_size": 0.3,
            "speed": 0.6,
        },
    ),
    "ttpf": (ta.ttpf, {"cycles": 1.2, "n50": 1.0}),
    "ttpf_inverse": (ta.ttpf_inverse, {"probability": 0.3, "n50": 1.0}),
    "c2nveo": (ta.c2nveo, {"cycles": 0.8, "n50": 1.0}),
    "c2nveo_inverse": (ta.c2nveo_inverse, {"probability": 0.3, "n50": 1.0}),
    "schmieder_weathersby": (ta.schmieder_weathersby, {"cycles": 1.2, "n50": 1.0, "scr": 0.2}),
    "schmieder_weathersby hot spot": (
        ta.schmieder_weathersby,
        {"cycles": 0.4, "n50": 1.0, "hot_spot": True},
    ),
    "schmieder_weathersby moving": (ta.schmieder_weathersby, {"cycles": 0.4, "moving": True}),
    "schmieder_weathersby_inverse": (
        ta.schmieder_weathersby_inverse,
        {"probability": 0.3, "n50": 1.0, "scr": 0.2},
    ),
    "observed_detection": (od.observed_detection, {"cycles": 0.8, "n50": 1.0, "scr": 2.0}),
    "observed_detection_inverse": (
        od.observed_detection_inverse,
        {"probability": 0.3, "n50": 1.0, "scr": 2.0},
    ),
    "clutter_n50": (transforms.clutter_n50, {"scr": 0.2}),
    "probability": (
        _with_clutter(ta.probability),
        {"cycles": 1.2, "task": "detection", "snr": 5.0, "scr": 0.3},
    ),
    "probability recognition": (
        _with_clutter(ta.probability),
        {"cycles": 4.0, "task": "recognition", "snr": 5.0},
    ),
    "probability hot spot": (
        _with_clutter(ta.probability),
        {"cycles": 0.4, "task": "detection", "snr": 5.0, "hot_spot": True},
    ),
    "probability moving": (
        _with_clutter(ta.probability),
        {"cycles": 0.4, "task": "detection", "snr": 5.0, "moving": True},
    ),
    "acquisition_probabilities": (
        _with_clutter(ta.acquisition_probabilities),
        {"cycles": 1.0, "snr": 5.0, "scr": 0.3},
    ),
    "acquisition_probabilities c2nveo": (
        _with_clutter(ta.acquisition_probabilities),
        {"cycles": 4.0, "snr": 5.0, "scr": 0.2, "transform": "c2nveo"},
    ),
    "effect_probability": (
        ta.effect_probability,
        {"detection": 0.9, "recognition": 0.5, "identification": 0.2},
    ),
    "effective_scr": (ta.effective_scr, {"scr": 2.0, "snr": 3.0}),
    "noise_n50_factor": (ta.noise_n50_factor, {"snr": 3.0}),
    "snr_ratio": (noise.snr_ratio, {"snr": 3.0}),
    "ratio_n50": (noise.ratio_n50, {"ratio": 3.0}),
    "transmittance": (ta.transmittance, {"extinction": 1e-3, "range": 1000.0}),
    "cloud_transmittance": (
        atmosphere.cloud_transmittance,
        {"extinction": 1e-3, "range": 1000.0, "cloud_extinction": 1e-2, "cloud_length": 50.0},
    ),
    "foliage_transmittance": (atmosphere.foliage_transmittance, {"depth": 3.0, "extinction": 0.1}),
    "extinction_from_visibility": (
        ta.extinction_from_visibility,
        {"visibility": 5000.0, "convention": "mor"},
    ),
    "visibility_from_extinction": (
        atmosphere.visibility_from_extinction,
        {"extinction": 1e-3, "convention": "mor"},
    ),
    "db_per_km_to_np_per_km": (atmosphere.db_per_km_to_np_per_km, {"value": 1.0}),
    "np_per_km_to_db_per_km": (atmosphere.np_per_km_to_db_per_km, {"value": 1.0}),
    "snr_from_transmittance": (ta.snr_from_transmittance, {"tau": 0.4}),
    "snr_from_optical_depth": (atmosphere.snr_from_optical_depth, {"depth": 0.4}),
    # Named atmospheres broadcast over range (the path's settings are scalars of the table).
    "named_band_transmittance": (
        named_atmospheres.named_band_transmittance,
        {"range": 5000.0, "band": "lwir", "atmosphere": "tropical", "aerosol": "rural"},
    ),
    "named_optical_depth": (
        named_atmospheres.named_optical_depth,
        {"range": 300.0, "band": "mwir", "atmosphere": "subarctic-winter", "aerosol": "fog"},
    ),
    "segmented_optical_depth": (
        atmosphere.segmented_optical_depth,
        {"range": 1000.0, "extinction": 1e-4},
    ),
    "spectral_exitance": (ta.spectral_exitance, {"wavelength": 10e-6, "temperature": 300.0}),
    "wien_spectral_exitance": (
        radiometry.wien_spectral_exitance,
        {"wavelength": 10e-6, "temperature": 300.0},
    ),
    "band_exitance": (ta.band_exitance, {"temperature": 300.0, "band": "lwir"}),
    "band_exitance hot": (ta.band_exitance, {"temperature": 3000.0, "band": "lwir"}),
    "grey_body_exitance": (
        radiometry.grey_body_exitance,
        {"emissivity": 0.9, "temperature": 300.0, "band": "lwir"},
    ),
    "band_exitance_derivative": (
        radiometry.band_exitance_derivative,
        {"temperature": 300.0, "band": "lwir"},
    ),
    "stefan_boltzmann_exitance": (radiometry.stefan_boltzmann_exitance, {"temperature": 300.0}),
    "peak_wavelength": (radiometry.peak_wavelength, {"temperature": 300.0}),
    "emissivity": (radiometry.emissivity, {"exitance": 50.0, "blackbody_exitance": 100.0}),
    "emissivity_from_reflectance": (
        radiometry.emissivity_from_reflectance,
        {"reflectance": 0.3, "transmittance": 0.1},
    ),
    "reflected_exitance": (
        radiometry.reflected_exitance,
        {"reflectance": 0.3, "irradiance": 100.0},
    ),
    "lambert_intensity": (radiometry.lambert_intensity, {"intensity": 3.0, "angle": 0.3}),
    "irradiance_at_sensor": (
        radiometry.irradiance_at_sensor,
        {"intensity": 3.0, "range": 100.0, "off_axis_angle": 0.2},
    ),
    "irradiance_at_sensor pinhole": (
        radiometry.irradiance_at_sensor,
        {
            "intensity": 3.0,
            "range": 100.0,
            "emission_angle": 0.1,
            "off_axis_angle": 0.2,
            "lens": False,
        },
    ),
    "target_signal": (
        radiometry.target_signal,
        {"emissivity": 0.9, "exitance": 100.0, "range": 100.0, "off_axis_angle": 0.1},
    ),
    "diurnal_temperature": (
        radiometry.diurnal_temperature,
        {"hour": 10.0, "mean": 290.0, "amplitude": 5.0, "peak_hour": 14.0},
    ),
    "quantisation_step": (radiometry.quantisation_step, {"bits": 8, "span": 2.0}),
    "netd_exitance": (
        detector_noise.netd_exitance,
        {"netd": 0.05, "band": "lwir", "reference_temperature": 300.0},
    ),
    "pixels_on_target": (
        detector_noise.pixels_on_target,
        {"area": 4.0, "range": 1000.0, "ifov": 1e-4},
    ),
    "pixel_gain": (detector_noise.pixel_gain, {"pixels": 4.0}),
    "sensor_snr": (
        detector_noise.sensor_snr,
        {"contrast": 1.0, "noise_equivalent": 0.05, "transmittance": 0.5, "pixels": 4.0},
    ),
    "signal_to_clutter_ratio": (
        ta.signal_to_clutter_ratio,
        {"target_signal": 10.0, "background_mean": 8.0, "clutter": 0.5},
    ),
    "temperature_spread_clutter": (
        clutter.temperature_spread_clutter,
        {"emissivity": 0.9, "temperature": 300.0, "temperature_std": 2.0, "band": "lwir"},
    ),
    "slant_range": (ta.slant_range, {"height": 100.0, "ground_distance": 1000.0}),
    "solid_angle": (ta.solid_angle, {"height": 100.0, "ground_distance": 1000.0, "area": 10.0}),
    "projected_extents": (
        ta.projected_extents,
        {"length": 6.0, "width": 3.0, "height": 2.5, "aspect": 0.5, "depression": 0.2},
    ),
    "critical_dimension": (
        ta.critical_dimension,
        {"length": 6.0, "width": 3.0, "height": 2.5, "aspect": 0.5, "depression": 0.2},
    ),
    "box_outline": (
        geometry.box_outline,
        {
            "x": 100.0,
            "y": 1000.0,
            "z": -10.0,
            "heading": 0.3,
            "length": 6.0,
            "width": 3.0,
            "height": 2.5,
        },
    ),
    "critical_dimension_seen": (
        geometry.critical_dimension_seen,
        {"horizontal": 1.2, "vertical": 2.5, "visible_fraction": 0.6},
    ),
    "critical_dimension_seen hidden": (
        geometry.critical_dimension_seen,
        {"horizontal": 6.0, "vertical": 2.5, "visible_fraction": 0.6},
    ),
    "pointing_direction": (geometry.pointing_direction, {"azimuth": 0.3, "depression": 0.1}),
    "ifov": (ta.ifov, {"pitch": 17e-6, "focal_length": 0.075}),
    "field_of_view": (ta.field_of_view, {"detector_size": 0.01, "focal_length": 0.075}),
    "ifov_from_field_of_view": (
        ta.ifov_from_field_of_view,
        {"field_of_view": 0.3, "pixels": 640.0},
    ),
    "ifov_from_field_of_view rectilinear": (
        ta.ifov_from_field_of_view,
        {"field_of_view": 0.3, "pixels": 640.0, "projection": "rectilinear"},
    ),
    "field_of_view_from_ifov": (optics.field_of_view_from_ifov, {"ifov": 1e-4, "pixels": 640.0}),
    "diffraction_angle": (ta.diffraction_angle, {"wavelength": 10e-6, "aperture": 0.05}),
    "diffraction_spot": (
        ta.diffraction_spot,
        {"wavelength": 10e-6, "aperture": 0.05, "focal_length": 0.1},
    ),
    "gaussian_psf": (ta.gaussian_psf, {"x": 1.0, "y": 0.5, "sigma_x": 1.0, "sigma_y": 2.0}),
    "blur_cycle_angle": (optics.blur_cycle_angle, {"blur_sigma": 1e-4}),
    "resolvable_cycle_angle": (ta.resolvable_cycle_angle, {"ifov": 1e-4}),
    "resolvable_cycle_angle optics": (
        ta.resolvable_cycle_angle,
        {"ifov": 1e-5, "wavelength": 10e-6, "aperture": 0.05, "blur_sigma": 8e-5},
    ),
    "cycles_on_target": (
        ta.cycles_on_target,
        {"critical_dimension": 2.3, "range": 1000.0, "ifov": 1e-4},
    ),
    "range_for_cycles": (
        ta.range_for_cycles,
        {"critical_dimension": 2.3, "cycles": 3.0, "ifov": 1e-4},
    ),
    "pixels_per_metre": (ta.pixels_per_metre, {"range": 1000.0, "ifov": 1e-4}),
    "range_for_pixel_density": (
        ta.range_for_pixel_density,
        {"pixel_density": 10.0, "ifov": 1e-4},
    ),
}

# Public names that are not elementwise kernels of floats, each tested elsewhere in this file
# or in its module's tests (registries, records, functions of tables or images).
NOT_KERNELS = {
    "BANDS",
    "CRITERIA",
    "NOISE_MODELS",
    "TASKS",
    "TRANSFORMS",
    "Acquisition",
    "Criterion",
    "RangeCase",  # a record of inputs: test_range_cases_keep_nan
    "Clutter",  # a record of inputs: the clutter rows of KERNELS below
    "Scene",  # a record of inputs: tests/run/test_scene.py
    "SceneAcquisition",
    "Simulation",
    "get_criterion",
    "example_path",  # a file name in, a path out: tests/base/test_examples_path.py
    "sweep",  # text options in, a Dataset out: NaN ranges are tested in test_studies
    "required_ifov",  # solvers (bisection): test_design.py::test_nan_in_nan_out
    "required_focal_length",
    "obscurant_extinction",  # names of Table 7.1
    "clutter_region",  # test_clutter_region_keeps_nan_as_no_region
    "transform",  # the registry below
    "inverse_transform",
    "fuse",  # test_fusion_keeps_nan_per_target
    "fuse_groups",  # test_fusion_keeps_nan_per_target
    "central_level_bounds",
    "image_clutter",  # images: tests/physics/test_clutter.py
    "terrain_clutter",  # weights summed over an axis: test_terrain_clutter_keeps_nan
    "dri_ranges",  # test_range_cases_keep_nan
    "path_transmittance",  # sums over an axis: test_path_transmittance_keeps_nan_per_path
    "scene_acquisition",  # scenario records: tests/run/test_scene.py
    "CriterionFit",  # a fit's result record: tests/acquisition/test_calibration.py
    "fit_criterion",  # a reduction over trials (NaN refused): test_calibration.py
    "register_criterion",  # the registry: test_calibration.py
    "unregister_criterion",
    "line_of_sight",  # a grid and positions (NaN: void or off the grid): test_line_of_sight.py
}

# (kernel, input) pairs on which no output depends at the base inputs, so NaN there need not
# come out: a flat region of the curve is not a missing value.
INDEPENDENT = {
    ("schmieder_weathersby moving", "cycles"),  # a moving target is always detected
    ("resolvable_cycle_angle optics", "ifov"),  # the optics limit is the coarser
    ("critical_dimension_seen", "vertical"),  # the horizontal side is the smaller...
    ("critical_dimension_seen", "visible_fraction"),
    ("critical_dimension_seen hidden", "horizontal"),  # ...or the visible height is
}


def _outputs(value: Any) -> list[np.ndarray]:
    if isinstance(value, ta.Acquisition):
        return [np.asarray(getattr(value, t)) for t in ("detection", "recognition", "effect")]
    if isinstance(value, tuple):
        return [np.asarray(v, dtype=float) for v in value]
    return [np.asarray(value, dtype=float)]


def _array_inputs(kwargs: dict[str, Any]) -> list[str]:
    return [k for k, v in kwargs.items() if isinstance(v, float)]


def _other(value: float) -> float:
    """Another valid value of an input (every base input is valid scaled by 0.9)."""
    return 0.9 * value if value else 0.1


MATRIX = [(name, arg) for name, (_, kw) in KERNELS.items() for arg in _array_inputs(kw)]


def test_every_public_function_is_in_the_matrix():
    covered = {f.__name__ for f, _ in KERNELS.values()}
    missing = sorted(set(ta.__all__) - covered - NOT_KERNELS)
    assert not missing, f"add these public functions to KERNELS or NOT_KERNELS: {missing}"


@pytest.mark.parametrize(("name", "arg"), MATRIX, ids=[f"{n}-{a}" for n, a in MATRIX])
def test_nan_in_gives_nan_out_at_exactly_that_element(name, arg):
    function, kwargs = KERNELS[name]
    base = _outputs(function(**kwargs))
    moved = _outputs(function(**{**kwargs, arg: _other(kwargs[arg])}))
    depends = [not np.allclose(m, b, rtol=1e-13, atol=0) for m, b in zip(moved, base, strict=True)]
    assert any(depends) != ((name, arg) in INDEPENDENT), f"no output of {name} moves with {arg}"
    values = np.array([kwargs[arg], np.nan, kwargs[arg]])
    for out, single, dependent in zip(
        _outputs(function(**{**kwargs, arg: values})), base, depends, strict=True
    ):
        out = np.broadcast_to(out, (3,))
        np.testing.assert_allclose(out[[0, 2]], [single, single], rtol=1e-13)
        if dependent:
            assert np.isnan(out[1]), f"{name}: NaN {arg} gave {out[1]}"
        else:
            assert np.isnan(out[1]) or out[1] == single


@pytest.mark.parametrize(("name", "arg"), MATRIX, ids=[f"{n}-{a}" for n, a in MATRIX])
def test_scalar_in_scalar_out_and_nd_arrays_elementwise(name, arg):
    function, kwargs = KERNELS[name]
    base = _outputs(function(**kwargs))
    assert all(b.ndim == 0 for b in base)
    grid = np.full((2, 1, 3), kwargs[arg])
    for out, single in zip(_outputs(function(**{**kwargs, arg: grid})), base, strict=True):
        assert out.shape in {(2, 1, 3), ()}  # () for an output that does not use the input
        np.testing.assert_allclose(out, np.broadcast_to(single, out.shape), rtol=1e-13)


# Where an infinite input has no limit the kernel can give, the outputs are NaN (unknown):
# an infinite line-of-sight component has no outline, two infinite signals no contrast, and
# Wien's approximation no value at an infinite temperature.
INFINITE_IS_UNKNOWN = {
    ("box_outline", "x"),
    ("box_outline", "y"),
    ("box_outline", "z"),
    ("wien_spectral_exitance", "temperature"),
}


@pytest.mark.parametrize(("name", "arg"), MATRIX, ids=[f"{n}-{a}" for n, a in MATRIX])
def test_infinite_zero_and_negative_give_a_number_or_a_named_error(name, arg):
    for bad in (math.inf, -math.inf, 0.0, -1.0):
        _number_or_named_error(name, arg, bad)


def _number_or_named_error(name: str, arg: str, bad: float) -> None:
    """Beside a valid element, ±inf, 0 or −1 either raises ``ValueError`` naming the input (for
    the whole batch, never a NumPy warning: pytest runs with -W error) or gives numbers (a
    limit, such as P = 1 for infinitely many cycles), never NaN from numbers."""
    function, kwargs = KERNELS[name]
    values = np.array([kwargs[arg], bad])
    try:
        outputs = _outputs(function(**{**kwargs, arg: values}))
    except ValueError as error:
        message = str(error)
    else:
        message = ""
    if message:
        assert arg.replace("_", " ") in message.replace("_", " ")
        assert "\n" not in message
        return
    if (name, arg) in INFINITE_IS_UNKNOWN and math.isinf(bad):
        return
    for out in outputs:
        assert not np.isnan(np.broadcast_to(out, (2,))).any(), f"{name}({arg}={bad}) gave NaN"


BAD_DTYPES = {
    "complex": np.array([1.0 + 2.0j]),
    "complex scalar": 3.0 + 0.0j,
    "text": np.array(["3.0"]),
    "text scalar": "3.0",
    "bytes": b"3.0",
    "datetime": np.array(["2024-01-01"], dtype="datetime64[s]"),
    "timedelta": np.timedelta64(3, "s"),
    "object": np.array([1.0, None]),
    "list with None": [1.0, None],
    "bool": np.array([True]),
    "bool scalar": True,
}


@pytest.mark.parametrize(("name", "arg"), MATRIX, ids=[f"{n}-{a}" for n, a in MATRIX])
def test_non_numeric_inputs_are_refused_naming_the_input(name, arg):
    function, kwargs = KERNELS[name]
    for value in BAD_DTYPES.values():
        with pytest.raises(TypeError, match=rf"^{arg} must be real numbers; got "):
            function(**{**kwargs, arg: value})


@pytest.mark.parametrize(("name", "arg"), MATRIX, ids=[f"{n}-{a}" for n, a in MATRIX])
def test_masked_arrays_are_refused_naming_the_input(name, arg):
    function, kwargs = KERNELS[name]
    masked = np.ma.masked_array([kwargs[arg], kwargs[arg]], mask=[False, True])
    with pytest.raises(TypeError, match=rf"^{arg} is a masked array.*filled\(numpy\.nan\)"):
        function(**{**kwargs, arg: masked})
    # The advice works: the masked element comes out NaN, the other as the plain value.
    for out, single in zip(
        _outputs(function(**{**kwargs, arg: masked.filled(np.nan)})),
        _outputs(function(**kwargs)),
        strict=True,
    ):
        out = np.broadcast_to(out, (2,))
        assert out[0] == pytest.approx(float(single), rel=1e-13)
        assert np.isnan(out[1]) or (name, arg) in INDEPENDENT or out[1] == out[0]


@pytest.mark.parametrize(("name", "arg"), MATRIX, ids=[f"{n}-{a}" for n, a in MATRIX])
def test_integers_and_float32_are_numbers(name, arg):
    function, kwargs = KERNELS[name]
    value = kwargs[arg]
    base = _outputs(function(**kwargs))
    single = _outputs(function(**{**kwargs, arg: np.float32(value)}))
    for out, expected in zip(single, base, strict=True):
        assert float(out) == pytest.approx(float(expected), rel=1e-5)
    if value == int(value):
        exact = _outputs(function(**{**kwargs, arg: np.array([int(value)])}))
        for out, expected in zip(exact, base, strict=True):
            assert float(np.reshape(out, -1)[0]) == pytest.approx(float(expected), rel=1e-13)


def _two_inputs() -> list[tuple[str, str, str]]:
    cases = []
    for name, (_, kwargs) in KERNELS.items():
        inputs = _array_inputs(kwargs)
        if len(inputs) >= 2:
            cases.append((name, inputs[0], inputs[1]))
    return cases


@pytest.mark.parametrize(("name", "first", "second"), _two_inputs())
def test_inputs_that_do_not_broadcast_are_named_with_their_shapes(name, first, second):
    function, kwargs = KERNELS[name]
    given = {**kwargs, first: np.full(3, kwargs[first]), second: np.full(2, kwargs[second])}
    with pytest.raises(ValueError, match=rf"{first} \(3,\).* and {second} \(2,\) do not broadcast"):
        function(**given)


# --------------------------------------------------------------------------------------------
# The registries
# --------------------------------------------------------------------------------------------

N_NAN = np.array([1.2, np.nan, 3.0])
P_NAN = np.array([0.3, np.nan, 0.6])


def _transform_cases() -> list[tuple[str, str]]:
    return [
        (name, task)
        for name, chosen in ta.TRANSFORMS.items()
        for task in chosen.tasks or ("detection", "recognition", "identification")
    ]


def _options(chosen: transforms.Transform) -> dict[str, Any]:
    return {"scr": np.array([2.0, 0.5, np.nan])} if "scr" in chosen.options else {}


def _nan_where(value: Any, mask: list[bool]) -> None:
    value = np.asarray(value, dtype=float)
    assert np.isnan(value).tolist() == mask, value


@pytest.mark.parametrize(("name", "task"), _transform_cases())
def test_every_transform_keeps_nan_in_cycles_n50_and_its_options(name, task):
    chosen = ta.TRANSFORMS[name]
    options = _options(chosen)
    expected = [False, True, "scr" in options]
    n50 = CRITERIA["johnson"].n50(task)
    _nan_where(chosen.forward(N_NAN, n50, task, **options), expected)
    _nan_where(chosen.inverse(P_NAN, n50, task, **options), expected)
    n50s = np.array([n50, np.nan, n50])
    _nan_where(chosen.forward(np.full(3, 2.0), n50s, task, **options), expected)
    _nan_where(chosen.inverse(np.full(3, 0.4), n50s, task, **options), expected)


@pytest.mark.parametrize("name", list(ta.NOISE_MODELS))
def test_every_noise_model_keeps_nan(name):
    factor = ta.noise_n50_factor(np.array([3.0, np.nan, math.inf, -math.inf]), name)
    assert np.isnan(factor).tolist() == [False, True, False, False]
    assert factor[2] == 1.0  # no noise at +inf
    assert factor[3] == (1.0 if name == "none" else math.inf)  # no signal at -inf


@pytest.mark.parametrize("rule", list(acquisition.MOTION_RULES))
@pytest.mark.parametrize("transform", ["ttpf", "c2nveo"])
def test_every_motion_rule_keeps_nan(rule, transform):
    chosen = ta.TRANSFORMS[transform]
    motion = acquisition.MOTION_RULES[rule]
    xp = _arrays.namespace()
    _nan_where(motion.detection(N_NAN, 1.0, chosen, {}, xp), [False, True, False])
    _nan_where(motion.cycles_needed(P_NAN, 1.0, chosen, {}), [False, True, False])


@pytest.mark.parametrize("name", list(acquisition.ACQUISITION_SEMANTICS))
@pytest.mark.parametrize("which", [0, 1, 2])
def test_every_semantics_keeps_nan_of_each_curve(name, which):
    curves = [np.array([0.9, 0.9]), np.array([0.5, 0.5]), np.array([0.2, 0.2])]
    curves[which] = np.array([curves[which][0], np.nan])
    events = acquisition.ACQUISITION_SEMANTICS[name].events(*curves, _arrays.namespace())
    for k, event in enumerate(events):
        # Every event from the NaN curve's on depends on it (nested: the caps; conditional:
        # the products); the ones before it do not.
        _nan_where(event, [False, k >= which])


@pytest.mark.parametrize("name", list(geometry.CRITICAL_DIMENSION_METHODS))
def test_every_critical_dimension_method_keeps_nan(name):
    method = geometry.CRITICAL_DIMENSION_METHODS[name]
    xp = _arrays.namespace()
    _nan_where(
        method(np.array([6.0, np.nan, 6.0]), np.array([2.5, 2.5, np.nan]), xp),
        [
            False,
            True,
            True,
        ],
    )


@pytest.mark.parametrize("method", list(radiometry.BAND_EXITANCE_METHODS))
@pytest.mark.parametrize("band", ["visible", "mwir", "lwir", (1e-6, 1e-3)])
def test_every_band_exitance_method_keeps_nan(method, band):
    exitance = ta.band_exitance(np.array([300.0, np.nan, 5000.0]), band, method)
    _nan_where(exitance, [False, True, False])


@pytest.mark.parametrize("name", list(RESOLUTION_MODELS))
def test_every_resolution_model_keeps_nan(name):
    from targetacq.physics.mrtd import MrtdCurve
    from targetacq.physics.ttp import TtpSystem

    extra = {
        "johnson": {},
        "mrtd": {"mrtd": MrtdCurve.example(), "contrast": 2.0},
        "ttp": {"ttp": TtpSystem(1e-4, 0.1, 1e-5, 0.05), "contrast": 2.0},
    }[name]
    case = RangeCase(2.3, 1e-4, **extra)
    assert case.resolution_model == name
    cycles = RESOLUTION_MODELS[name].cycles(case, np.array([1000.0, np.nan]), np.array([0.5, 0.5]))
    _nan_where(cycles, [False, True])
    cycles = RESOLUTION_MODELS[name].cycles(
        case, np.array([1000.0, 1000.0]), np.array([0.5, np.nan])
    )
    _nan_where(cycles, [False, name != "johnson"])  # MRTD and TTP see the contrast


# --------------------------------------------------------------------------------------------
# The chain: probability, acquisition, range cases, the core and the step API
# --------------------------------------------------------------------------------------------


def test_the_issues_example_gives_p_and_nan():
    p = ta.probability(np.array([3.0, 3.0]), "detection", snr=np.array([10.0, np.nan]))
    assert p[0] == pytest.approx(float(ta.probability(3.0, "detection", snr=10.0)), rel=1e-15)
    assert 0 < p[0] < 1 and np.isnan(p[1])


CLUTTER = [
    {},
    {"scr": np.array([3.0, 3.0, 0.1, np.nan])},
    {"region": "high"},
    {"hot_spot": True},
    {"moving": True},
    {"hot_spot": np.array([True, False, True, False])},
    {"moving": np.array([False, True, True, False]), "scr": 0.5},
]


@pytest.mark.parametrize("clutter", CLUTTER, ids=lambda c: ",".join(c) or "no clutter")
@pytest.mark.parametrize("noise_model", list(ta.NOISE_MODELS))
@pytest.mark.parametrize("motion", list(acquisition.MOTION_RULES))
@pytest.mark.parametrize("transform", ["ttpf", "c2nveo"])
def test_acquisition_keeps_nan_in_cycles_and_snr_through_every_branch(
    clutter, noise_model, motion, transform
):
    cycles = np.array([2.0, np.nan, 2.0, 0.6])
    snr = np.array([12.0, 5.0, np.nan, -3.0])
    found = ta.acquisition_probabilities(
        cycles,
        transform=transform,
        snr=snr,
        noise_model=noise_model,
        motion=motion,
        clutter=clutter,
    )
    scr_nan = bool(np.isnan(np.broadcast_to(clutter.get("scr", 1.0), (4,)))[3])
    moving = np.broadcast_to(clutter.get("moving", False), (4,))
    hot = np.broadcast_to(clutter.get("hot_spot", False), (4,))
    # A missing SCR counts where detection is read in clutter, not for a moving target or a
    # hot spot (their rules ignore the clutter); the nested semantics caps recognition and
    # identification by detection, so it reaches them too.
    nan = [False, True, True, scr_nan and not (moving[3] or hot[3])]
    for task in ("detection", "recognition", "identification"):
        values = getattr(found, task)
        assert np.isnan(values).tolist() == nan, (task, values)
        finite = values[~np.isnan(values)]
        assert ((finite >= 0) & (finite <= 1)).all()
    single = ta.probability(
        cycles,
        "detection",
        transform=transform,
        snr=snr,
        noise_model=noise_model,
        motion=motion,
        clutter=clutter,
    )
    assert np.isnan(single).tolist() == np.isnan(found.detection).tolist()


def test_no_signal_with_nan_cycles_stays_nan():
    p = ta.probability(np.array([np.nan, 2.0]), "detection", snr=-math.inf)
    assert np.isnan(p[0]) and p[1] == 0.0


def test_range_cases_keep_nan():
    extinction = np.array([1e-4, np.nan, 1e-4, 1e-4, 1e-4])
    foliage = np.array([0.8, 0.8, np.nan, 0.8, 0.8])
    scr = np.array([5.0, 5.0, 5.0, np.nan, 5.0])
    rng = np.array([1000.0, 1000.0, 1000.0, 1000.0, np.nan])
    found = case_acquisition(
        RangeCase(2.3, 1e-4, extinction=extinction, foliage=foliage, scr=scr), rng
    )
    # Nested semantics: a missing SCR reaches recognition through the cap P_rec <= P_det.
    for task in ("detection", "recognition", "identification"):
        assert np.isnan(getattr(found, task)).tolist() == [False, True, True, True, True]
    ranges = ta.dri_ranges(RangeCase(np.array([2.3, np.nan]), 1e-4))
    for task in ("detection", "recognition", "identification"):
        assert np.isnan(np.asarray(ranges[task])).tolist() == [False, True]


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("critical_dimension", math.inf),
        ("ifov", math.inf),
        ("extinction", math.inf),
        ("cycle", math.inf),
        ("blur_sigma", math.inf),
        ("target_area", math.inf),
        ("critical_dimension", np.array([2.3, math.inf])),
    ],
)
def test_range_case_refuses_infinities_naming_the_field(field, value):
    given = {"critical_dimension": 2.3, "ifov": 1e-4, field: value}
    if field == "target_area":
        given.update(contrast=2.0, noise_equivalent_contrast=0.05)
    with pytest.raises(ValueError, match=rf"^{field} must be finite; got inf"):
        RangeCase(**given)


def test_range_case_takes_no_clutter_as_infinite_scr_and_refuses_non_booleans():
    assert RangeCase(2.3, 1e-4, scr=math.inf).in_clutter
    with pytest.raises(TypeError, match=r"^moving must be True or False, got 'yes'$"):
        RangeCase(2.3, 1e-4, moving="yes")
    with pytest.raises(TypeError, match=r"^scr must be real numbers; got complex128"):
        RangeCase(2.3, 1e-4, scr=np.array([1 + 1j]))


def _simulation() -> ta.Simulation:
    from targetacq.scenario.schema import Background, Sensor, Target

    return ta.Simulation(
        [
            Sensor(name="wide", band="lwir", ifov=0.25e-3, position=(0.0, 0.0, 5.0)),
            Sensor(
                name="east",
                band="lwir",
                position=(0.0, 0.0, 5.0),
                hfov="20 deg",
                pixels=(640, 480),
                azimuth="90 deg",
                depression="0 deg",
            ),
        ],
        [
            Target(name=name, dimensions=(7.0, 2.5, 3.0), temperature=305.0, position=(0, 0, 0))
            for name in ("a", "b", "c")
        ],
        background=Background(temperature=295.0, clutter_std=1.0),
        atmosphere={"extinction": "0.3 /km"},
        seed=5,
    )


SENSORS = np.array([[0.0, 0.0, 5.0], [0.0, 0.0, 5.0]])
TARGETS = np.array([[1500.0, 0.0, 0.0], [1000.0, 100.0, 0.0], [0.0, 1200.0, 0.0]])


@pytest.mark.parametrize(
    ("which", "index", "nan_pairs"),
    [
        ("targets", (1, 0), [[False, True, False], [False, True, False]]),
        ("targets", (2, 2), [[False, False, True], [False, False, True]]),
        ("sensors", (1, 1), [[False, False, False], [True, True, True]]),
    ],
)
def test_step_api_gives_nan_for_the_pairs_of_a_nan_position_only(which, index, nan_pairs):
    sim = _simulation()
    plain = sim.probabilities(0.0, SENSORS, TARGETS)
    sensors, targets = SENSORS.copy(), TARGETS.copy()
    (targets if which == "targets" else sensors)[index] = np.nan
    found = sim.probabilities(0.0, sensors, targets)
    for task in ("detection", "recognition", "identification"):
        value, reference = getattr(found, task), getattr(plain, task)
        assert np.isnan(value).tolist() == nan_pairs
        np.testing.assert_array_equal(value[~np.isnan(value)], reference[~np.isnan(value)])
        fused = getattr(found, f"fused_{task}")
        assert np.isnan(fused).tolist() == np.isnan(value).any(axis=0).tolist()
    out = sim.step(0.0, 0.1, sensors, targets)  # the first step only starts the clock
    out = sim.step(0.1, 0.1, sensors, targets)
    assert np.isnan(out.detection).tolist() == nan_pairs
    assert not out.detected[np.isnan(out.detection)].any()


def test_step_api_gives_nan_for_a_nan_heading_where_the_target_is_in_view():
    sim = _simulation()
    found = sim.probabilities(0.0, SENSORS, TARGETS, np.array([0.1, np.nan, 0.2]))
    # Target c (north) is outside the east-looking sensor's view: 0 there whatever its heading
    # would be; everywhere else its probabilities are NaN.
    assert np.isnan(found.detection).tolist() == [[False, True, False], [False, True, False]]


@pytest.mark.parametrize(
    ("given", "error", "message"),
    [
        (
            {
                "target_positions": TARGETS * np.array([1, 1, 0])
                + [[np.inf, 0, 0], [0, 0, 0], [0, 0, 0]]
            },
            ValueError,
            r"^target_positions must be finite; got inf m",
        ),
        (
            {"sensor_positions": np.array([[0.0, -np.inf, 5.0], [0.0, 0.0, 5.0]])},
            ValueError,
            r"^sensor_positions must be finite; got -inf m",
        ),
        (
            {"target_headings": np.array([0.1, np.inf, 0.2])},
            ValueError,
            r"^target_headings must be in \[-6\.28319, 6\.28319\] rad; got inf rad$",
        ),
        (
            {"sensor_pointing": np.array([[np.nan, np.nan], [1.5, 2.0]])},
            ValueError,
            r"^sensor_pointing depression must be in \[-1\.5708, 1\.5708\] rad",
        ),
        (
            {"sensor_pointing": np.array([[np.nan, 0.1], [1.5, 0.0]])},
            ValueError,
            r"^sensor_pointing: give both the azimuth and the depression",
        ),
        (
            {"target_positions": TARGETS.astype(complex)},
            TypeError,
            r"^target_positions must be real numbers; got complex128",
        ),
        (
            {"target_positions": np.ma.masked_array(TARGETS, mask=TARGETS == 0)},
            TypeError,
            r"^target_positions is a masked array",
        ),
        ({"time": math.nan}, ValueError, r"^time must be a number; got NaN$"),
        ({"time": math.inf}, ValueError, r"^time must be finite; got inf"),
        ({"time": "3"}, TypeError, r"^time must be real numbers; got text"),
        ({"time": True}, TypeError, r"^time must be real numbers; got booleans"),
    ],
    ids=lambda v: v if isinstance(v, str) else None,
)
def test_step_api_refuses_infinite_and_non_numeric_inputs_naming_them(given, error, message):
    sim = _simulation()
    args = {"time": 0.0, "sensor_positions": SENSORS, "target_positions": TARGETS, **given}
    with pytest.raises(error, match=message):
        sim.probabilities(
            args["time"],
            args["sensor_positions"],
            args["target_positions"],
            args.get("target_headings"),
            args.get("sensor_pointing"),
        )
    with pytest.raises(error, match=message):
        sim.step(
            args["time"],
            0.1,
            args["sensor_positions"],
            args["target_positions"],
            args.get("target_headings"),
            args.get("sensor_pointing"),
        )


def test_step_api_refuses_a_non_numeric_or_infinite_dt():
    sim = _simulation()
    with pytest.raises(TypeError, match=r"^dt must be real numbers"):
        sim.step(0.0, "0.1", SENSORS, TARGETS)
    with pytest.raises(ValueError, match=r"^dt must be finite"):
        sim.step(0.0, math.inf, SENSORS, TARGETS)


def test_a_nan_pointing_row_keeps_the_sensors_own_pointing():
    sim = _simulation()
    own = sim.probabilities(0.0, SENSORS, TARGETS)
    kept = sim.probabilities(0.0, SENSORS, TARGETS, None, np.full((2, 2), np.nan))
    np.testing.assert_array_equal(kept.detection, own.detection)


# --------------------------------------------------------------------------------------------
# The rest: fusion, regions, terrain clutter, Table 7.2, messages
# --------------------------------------------------------------------------------------------


def test_fusion_keeps_nan_per_target():
    p = np.array([[0.5, np.nan, 0.2], [0.4, 0.3, np.nan]])
    fused = ta.fuse(p, axis=0)
    assert np.isnan(fused).tolist() == [False, True, True]
    assert fused[0] == pytest.approx(1 - 0.5 * 0.6)
    _, upper = ta.central_level_bounds(p, axis=0)
    assert np.isnan(upper).tolist() == [False, True, True] and upper[0] == 1.0
    with pytest.raises(TypeError, match=r"^probabilities must be real numbers"):
        ta.fuse(p.astype(complex))
    # Grouped (colour bands): NaN in any member is NaN for the group and for the fusion.
    grouped = ta.fuse_groups(np.vstack([p, [0.1, 0.2, 0.3]]), ["rgb", "rgb", "ir"])
    assert np.isnan(grouped).tolist() == [False, True, True]
    assert grouped[0] == pytest.approx(1 - 0.5 * 0.9)
    with pytest.raises(ValueError, match="groups must name the group of each of the 3"):
        ta.fuse_groups(np.vstack([p, p[:1]]), ["a", "b"])


def test_path_transmittance_keeps_nan_per_path():
    gamma = np.array([[1e-3, 2e-3], [np.nan, 2e-3], [1e-3, 2e-3]])
    tau = ta.path_transmittance(gamma, np.array([100.0, 50.0]))
    assert np.isnan(tau).tolist() == [False, True, False]
    assert tau[0] == pytest.approx(math.exp(-0.2), rel=1e-14) and tau[2] == tau[0]


def test_clutter_region_keeps_nan_as_no_region():
    assert ta.clutter_region(np.array([20.0, np.nan, 0.5, math.inf])).tolist() == [
        "low",
        "",
        "high",
        "low",
    ]
    with pytest.raises(TypeError, match=r"^scr must be real numbers"):
        ta.clutter_region("5")


def test_terrain_clutter_keeps_nan():
    weights = np.array([[0.5, 0.5], [0.5, 0.5]])
    variances = np.array([[4.0, 1.0], [np.nan, 1.0]])
    found = ta.terrain_clutter(weights, variances)
    assert found[0] == pytest.approx(math.sqrt(2.5)) and np.isnan(found[1])


@pytest.mark.parametrize(
    ("extinction", "term"),
    [
        (0.0, "very low"),
        (1e-4, "low"),
        (1e-3, "medium"),
        (5e-3, "high"),
        (1e300, "high"),
        (math.inf, "high"),
    ],
)
def test_table_7_2_covers_every_extinction_up_to_infinity(extinction, term):
    assert atmosphere.extinction_term(extinction)[0] == term


@pytest.mark.parametrize("bad", [math.nan, -1.0])
def test_table_7_2_refuses_nan_and_negative_extinctions(bad):
    with pytest.raises(ValueError, match=r"^extinction must be >= 0 Np/m"):
        atmosphere.extinction_term(bad)


def test_band_exitance_is_finite_for_any_finite_temperature():
    """Above about 1e77 K, T⁴ overflows: the Rayleigh–Jeans side gives the finite value,
    K T (c2/λ)³ / 3 per band edge to leading order, and +inf only at T = inf."""
    c2 = constants.SECOND_RADIATION_CONSTANT
    t = np.array([1e80, 1e300])
    lam1, lam2 = 8e-6, 12e-6
    leading = radiometry.BAND_CONSTANT * t * c2**3 * (lam1**-3 - lam2**-3) / 3.0
    np.testing.assert_allclose(ta.band_exitance(t, (lam1, lam2)), leading, rtol=1e-12)
    assert ta.band_exitance(math.inf, "lwir") == math.inf
    derivative = radiometry.band_exitance_derivative(np.array([1e80, 1e300, math.inf]), "lwir")
    limit = radiometry.BAND_CONSTANT * c2**3 * (lam1**-3 - lam2**-3) / 3.0
    np.testing.assert_allclose(derivative, limit, rtol=1e-12)


def test_schmieder_weathersby_without_clutter_speaks_the_users_words():
    with pytest.raises(ValueError, match="needs the clutter") as error:
        ta.schmieder_weathersby(1.0)
    message = str(error.value)
    assert "a clutter region (low, medium, high), a hot spot or a moving target" in message
    assert "=True" not in message and "hot_spot" not in message


def test_check_broadcast_names_every_input_with_a_shape():
    with pytest.raises(ValueError, match=r"^a \(3,\), b \(2,\) and d \(4, 1\) do not broadcast$"):
        _arrays.arrays(np.ones(3), np.ones(2), 1.0, np.ones((4, 1)), names=("a", "b", "c", "d"))


def test_arrays_in_other_namespaces_are_checked_too():
    xps = pytest.importorskip("array_api_strict")
    with pytest.raises(TypeError, match=r"^cycles must be real numbers; got .*complex"):
        ta.ttpf(xps.asarray([1 + 1j]), 1.0)
    with pytest.raises(TypeError, match=r"^cycles must be real numbers"):
        ta.ttpf(xps.asarray([True]), 1.0)
    found = ta.ttpf(xps.asarray([1, 2]), 1.0)  # integers become float64
    assert type(found).__module__.startswith("array_api_strict")
