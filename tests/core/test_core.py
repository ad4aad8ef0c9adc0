"""The array core's kernels, each on its own, and the core's purity and batch independence."""

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy import integrate

import targetacq as ta
from targetacq import core
from targetacq.physics import atmosphere, clutter, geometry, radiometry
from targetacq.scenario.schema import Sensor, load_scenario
from targetacq.sensors import SENSOR_TYPES, get_sensor_type

EXAMPLES = Path(__file__).parents[2] / "examples"

finite = st.floats(-5e3, 5e3, allow_nan=False)


@given(finite, finite, st.floats(-2e3, 2e3), st.floats(0, 2 * math.pi))
def test_box_outline_equals_the_projection_through_angles(x, y, z, heading):
    rho = math.hypot(x, y)
    if rho < 1e-3:
        return
    aspect = math.atan2(x, y) - heading  # line of sight against the long axis
    depression = math.atan2(abs(z), rho)
    h, v = ta.projected_extents(7.0, 2.5, 3.0, aspect, depression)
    rng, horizontal, vertical = geometry.box_outline(x, y, z, heading, 7.0, 2.5, 3.0)
    assert rng == pytest.approx(math.sqrt(x * x + y * y + z * z), rel=1e-12)
    assert horizontal == pytest.approx(h, rel=1e-9, abs=1e-9)
    assert vertical == pytest.approx(v, rel=1e-9, abs=1e-9)


def test_box_outline_straight_down_is_the_top_and_nan_stays_nan():
    rng, h, v = geometry.box_outline(0.0, 0.0, -100.0, 0.3, 7.0, 2.5, 3.0)
    assert (float(rng), float(h), float(v)) == (100.0, 7.0, 2.5)
    rng, h, v = geometry.box_outline(np.array([np.nan, 1.0]), 0.0, 0.0, 0.0, 7.0, 2.5, 3.0)
    assert np.isnan(rng[0]) and np.isnan(h[0]) and np.isnan(v[0])
    assert np.isfinite(rng[1])


def test_critical_dimension_seen_hides_part_of_the_height():
    assert geometry.critical_dimension_seen(6.0, 2.5) == 2.5
    assert geometry.critical_dimension_seen(6.0, 2.5, 0.4) == pytest.approx(1.0)
    assert geometry.critical_dimension_seen(1.0, 2.5, 0.6) == 1.0


@given(st.floats(-math.pi, math.pi), st.floats(-1.5, 1.5))
def test_pointing_direction_is_a_unit_vector_at_the_angles(azimuth, depression):
    e, n, u = geometry.pointing_direction(azimuth, depression)
    assert e * e + n * n + u * u == pytest.approx(1.0, rel=1e-12)
    assert math.asin(-u) == pytest.approx(depression, abs=1e-9)
    if abs(depression) < 1.5:
        assert math.atan2(e, n) == pytest.approx(azimuth, abs=1e-9)


@given(st.floats(-math.pi, math.pi), st.floats(-1.4, 1.4), finite, finite, finite)
def test_view_offsets_are_an_orthonormal_frame(azimuth, depression, x, y, z):
    forward = geometry.pointing_direction(azimuth, depression)
    ahead, right, up = geometry.view_offsets(x, y, z, forward)
    # Orthonormal: the length is kept, the boresight is "ahead" and "right" is horizontal.
    assert ahead**2 + right**2 + up**2 == pytest.approx(x * x + y * y + z * z, rel=1e-9, abs=1e-6)
    a, r, u = geometry.view_offsets(*forward, forward)
    assert (a, r, u) == pytest.approx((1.0, 0.0, 0.0), abs=1e-12)
    _, _, up_of_zenith = geometry.view_offsets(0.0, 0.0, 1.0, forward)
    assert up_of_zenith == pytest.approx(math.cos(depression), abs=1e-12)


def test_segmented_optical_depth_is_the_integral_of_the_extinction_along_the_path():
    lengths, gammas, base = [300.0, 200.0, 50.0], [2e-3, 5e-4, 0.0], 1e-4

    def gamma(s):
        start = 0.0
        for length, g in zip(lengths, gammas):
            if start <= s < start + length:
                return g
            start += length
        return base

    for r in (0.0, 150.0, 420.0, 530.0, 3000.0):
        expected = integrate.quad(gamma, 0.0, r, points=[300, 500, 550], limit=200)[0]
        got = atmosphere.segmented_optical_depth(r, base, lengths, gammas)
        assert got == pytest.approx(expected, rel=1e-10, abs=1e-14)


def test_sphere_chord_length_against_sampling():
    start, end, center, radius = np.zeros(3), np.array([100.0, 20.0, 0.0]), [50, 5, 3], 12.0
    s = np.linspace(0, 1, 2_000_001)
    points = start + s[:, None] * (end - start)
    inside = np.linalg.norm(points - center, axis=1) < radius
    expected = inside.mean() * np.linalg.norm(end - start)
    assert atmosphere.sphere_chord_length(start, end, center, radius) == pytest.approx(
        expected, rel=1e-4
    )
    assert atmosphere.sphere_chord_length(start, [10.0, 0, 0], center, radius) == 0.0


def test_temperature_spread_clutter_is_the_linearised_exitance_spread():
    # A central difference of the band exitance: independent of the analytic derivative.
    t, spread, eps, h = 295.0, 2.0, 0.9, 1e-3
    slope = (ta.band_exitance(t + h, "lwir") - ta.band_exitance(t - h, "lwir")) / (2 * h)
    got = clutter.temperature_spread_clutter(eps, t, spread, "lwir")
    assert got == pytest.approx(eps * slope * spread, rel=1e-7)
    with pytest.raises(ValueError, match="temperature_std must be >= 0"):
        clutter.temperature_spread_clutter(eps, t, -1.0, "lwir")


def test_grey_body_exitance_and_its_checks():
    assert radiometry.grey_body_exitance(1.0, 300.0, (1e-9, 1.0)) == pytest.approx(
        5.670374419e-8 * 300.0**4, rel=1e-6
    )
    with pytest.raises(ValueError, match="emissivity must be in"):
        radiometry.grey_body_exitance(1.2, 300.0, "lwir")


def test_extinction_for_band_reads_table_7_1_per_band():
    # Table 7.1 haze, high end: 0.4 Np/km in 8-12 um.
    assert atmosphere.extinction_for_band("lwir", obscurant="haze:high") == pytest.approx(4e-4)
    assert atmosphere.extinction_for_band("lwir") == 0.0
    assert atmosphere.extinction_for_band(
        "visible", visibility=3912.0, convention="koschmieder"
    ) == pytest.approx(1e-3, rel=1e-3)
    with pytest.raises(ValueError, match="give one of"):
        atmosphere.extinction_for_band("lwir", extinction=1e-4, obscurant="haze")


def test_sensor_types_come_from_the_registry():
    assert set(SENSOR_TYPES) == {"thermal", "tv", "colour", "swir", "radar", "laser_radar"}
    for kind in SENSOR_TYPES.values():
        assert get_sensor_type(kind.name) is kind
    with pytest.raises(ValueError, match="did you mean 'thermal'"):
        get_sensor_type("thermel")
    with pytest.raises(ValueError, match="unknown sensor type 'sonar'"):
        Sensor(name="s", type="sonar", band="lwir", ifov=1e-4, position=[0.0, 0.0, 0.0])


def _scene():
    return core.compile_scenario(load_scenario(EXAMPLES / "two_sensors_fused.toml"))


def test_core_does_not_write_into_its_inputs_and_broadcasts_batches():
    compiled = _scene()
    scenario = load_scenario(EXAMPLES / "two_sensors_fused.toml")
    s_pos, t_pos, heading = core.scenario_positions(scenario, np.arange(0.0, 60.0, 5.0))
    copies = [a.copy() for a in (s_pos, t_pos, heading)]
    _, p = core.evaluate(compiled.scene, s_pos, t_pos, heading)
    for a, b in zip(copies, (s_pos, t_pos, heading)):
        np.testing.assert_array_equal(a, b)
    assert p.detection.shape == (2, 2, 12) and p.fused_detection.shape == (2, 12)
    # One time at a time (no batch axis) gives the same numbers as the batch.
    for k in (0, 5, 11):
        _, single = core.evaluate(compiled.scene, s_pos[:, k], t_pos[:, k], heading[:, k])
        np.testing.assert_allclose(single.detection, p.detection[..., k], rtol=1e-14)
        np.testing.assert_allclose(single.fused_identification, p.fused_identification[..., k])


def test_nan_position_gives_nan_for_its_pairs_only():
    compiled = _scene()
    s_pos = np.array([[0.0, 0.0, 15.0], [0.0, 0.0, 15.0]])
    t_pos = np.array([[2000.0, 0.0, 0.0], [np.nan, 0.0, 0.0]])
    _, p = core.evaluate(compiled.scene, s_pos, t_pos)
    assert np.all(np.isnan(p.detection[:, 1])) and np.isnan(p.fused_detection[1])
    assert np.all(np.isfinite(p.detection[:, 0])) and p.fused_detection[0] > 0


def test_pointing_replaces_the_sensors_own():
    compiled = _scene()
    s_pos = np.array([[0.0, 0.0, 15.0], [0.0, 0.0, 15.0]])
    t_pos = np.array([[2000.0, 0.0, 0.0], [0.0, 2000.0, 0.0]])
    found, _ = core.evaluate(compiled.scene, s_pos, t_pos)
    assert found.in_view[:, 0].all() and not found.in_view[:, 1].any()  # look_at east
    north = np.array([[0.0, 0.0], [np.nan, np.nan]])  # the TV turns north; thermal keeps its own
    found, _ = core.evaluate(compiled.scene, s_pos, t_pos, pointing=north)
    assert found.in_view.tolist() == [[False, True], [True, False]]


def test_noise_factor_of_nan_is_nan():
    from targetacq.acquisition.path_noise import noise_n50_factor, ratio_n50

    got = ratio_n50(np.array([np.nan, 0.0]))  # in an array NaN passes the check, as NaN
    assert np.isnan(got[0]) and got[1] == np.inf
    got = noise_n50_factor(np.array([np.nan, np.inf, -np.inf]))
    assert np.isnan(got[0]) and got[1] == 1.0 and got[2] == np.inf
