"""The aspect kernels: where a sensor sees a target from, and a signature table read there."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.interpolate import RegularGridInterpolator

from targetacq.physics.aspect import AspectTable, interpolate_aspect, observer_aspect

NODES_AZ = np.radians([0.0, 45.0, 120.0, 200.0, 300.0])
NODES_EL = np.radians([-10.0, 0.0, 30.0, 80.0])
VALUES = 290.0 + np.arange(20, dtype=float).reshape(5, 4) ** 1.3


@pytest.mark.parametrize(
    ("offset", "heading", "azimuth"),
    [
        ((0.0, -100.0), 0.0, 0.0),  # sensor north of a target heading north: head-on
        ((-100.0, 0.0), 0.0, 90.0),  # sensor east: its right side
        ((0.0, 100.0), 0.0, 180.0),  # sensor south: its rear
        ((100.0, 0.0), 0.0, 270.0),  # sensor west: its left side
        ((-100.0, 0.0), math.pi / 2, 0.0),  # heading east, sensor east: head-on
        ((0.0, -100.0), math.pi / 2, 270.0),  # heading east, sensor north: its left side
    ],
)
def test_observer_azimuth_follows_the_stated_convention(offset, heading, azimuth):
    x, y = offset  # target minus sensor
    found, elevation = observer_aspect(x, y, 0.0, heading)
    assert math.degrees(float(found)) == pytest.approx(azimuth, abs=1e-9)
    assert float(elevation) == 0.0


def test_observer_elevation_is_the_angle_above_the_targets_plane():
    # A sensor 1 km up at 1.732 km ground distance: 30 deg above.
    _, elevation = observer_aspect(0.0, -math.sqrt(3.0) * 1000.0, -1000.0, 0.0)
    assert math.degrees(float(elevation)) == pytest.approx(30.0, abs=1e-12)
    _, below = observer_aspect(0.0, -1000.0, 1000.0, 0.0)
    assert math.degrees(float(below)) == pytest.approx(-45.0, abs=1e-12)


def test_observer_aspect_is_nan_for_nan_positions_and_in_one_turn():
    az, el = observer_aspect(
        np.array([np.nan, -1e-300, 5.0]), np.array([1.0, 1.0, -1e-12]), 0.0, 0.0
    )
    assert np.isnan(az[0]) and np.isnan(el[0])
    assert np.all((az[1:] >= 0.0) & (az[1:] < 2 * math.pi))


def _periodic_reference(az, el):
    """scipy's linear grid interpolation on the table extended by one node across the wrap."""
    extended_az = np.concatenate(
        [NODES_AZ[-1:] - 2 * math.pi, NODES_AZ, NODES_AZ[:1] + 2 * math.pi]
    )
    extended = np.concatenate([VALUES[-1:], VALUES, VALUES[:1]])
    reference = RegularGridInterpolator((extended_az, NODES_EL), extended)
    clipped = np.clip(el, NODES_EL[0], NODES_EL[-1])
    return reference(np.stack([np.remainder(az, 2 * math.pi), clipped], axis=-1))


@settings(max_examples=60, deadline=None)
@given(
    st.floats(-20.0, 20.0, allow_nan=False),
    st.floats(-math.pi / 2, math.pi / 2, allow_nan=False),
)
def test_interpolation_equals_scipys_linear_grid_interpolation(az, el):
    found = interpolate_aspect(NODES_AZ, NODES_EL, VALUES, np.array([az]), np.array([el]))
    assert found[0] == pytest.approx(
        _periodic_reference(np.array([az]), np.array([el]))[0], rel=1e-12
    )


def test_interpolation_is_exact_at_the_nodes_and_holds_beyond_the_elevations():
    az, el = np.meshgrid(NODES_AZ, NODES_EL, indexing="ij")
    np.testing.assert_allclose(
        interpolate_aspect(NODES_AZ, NODES_EL, VALUES, az, el), VALUES, rtol=1e-14
    )
    above = interpolate_aspect(NODES_AZ, NODES_EL, VALUES, NODES_AZ, np.full(5, math.pi / 2))
    np.testing.assert_allclose(above, VALUES[:, -1], rtol=1e-14)


def test_interpolation_wraps_between_the_last_and_the_first_azimuth():
    # Halfway between 300 deg and 360 deg (= 0 deg): the mean of the two rows.
    found = interpolate_aspect(NODES_AZ, NODES_EL, VALUES, np.radians([330.0, -30.0]), np.zeros(2))
    expected = 0.5 * (VALUES[-1, 1] + VALUES[0, 1])
    np.testing.assert_allclose(found, [expected, expected], rtol=1e-12)


def test_interpolation_with_leading_table_axes_takes_each_pairs_own_table():
    tables = np.stack([VALUES, 2 * VALUES, VALUES + 7.0]).reshape(3, 1, 5, 4)
    az = np.radians(np.array([[[10.0, 250.0]], [[10.0, 250.0]], [[10.0, 250.0]]]))
    el = np.zeros_like(az)
    found = interpolate_aspect(NODES_AZ, NODES_EL, tables, az, el)
    base = _periodic_reference(az[0, 0], el[0, 0])
    np.testing.assert_allclose(found[:, 0], [base, 2 * base, base + 7.0], rtol=1e-12)


def test_interpolation_of_one_node_is_constant_and_nan_stays_nan():
    one = interpolate_aspect([0.0], [0.0], [[305.0]], np.array([0.3, 4.0, np.nan]), np.zeros(3))
    assert one[:2].tolist() == [305.0, 305.0] and np.isnan(one[2])
    found = interpolate_aspect(
        NODES_AZ, NODES_EL, VALUES, np.array([0.1, 0.1]), np.array([np.nan, 0.2])
    )
    assert np.isnan(found[0]) and np.isfinite(found[1])


def test_interpolation_refuses_a_table_of_the_wrong_shape():
    with pytest.raises(ValueError, match=r"values must end in the table's axes \(5, 4\)"):
        interpolate_aspect(NODES_AZ, NODES_EL, VALUES.T, 0.0, 0.0)


def test_interpolation_runs_under_jax_jit_and_array_api_strict():
    jax = pytest.importorskip("jax")
    jax.config.update("jax_enable_x64", True)
    az, el = np.radians([17.0, 333.0]), np.radians([5.0, 60.0])
    expected = _periodic_reference(az, el)
    jitted = jax.jit(interpolate_aspect)(NODES_AZ, NODES_EL, VALUES, az, el)
    np.testing.assert_allclose(np.asarray(jitted), expected, rtol=1e-12)
    xps = pytest.importorskip("array_api_strict")
    found = interpolate_aspect(*(xps.asarray(v) for v in (NODES_AZ, NODES_EL, VALUES, az, el)))
    np.testing.assert_allclose(np.asarray(found), expected, rtol=1e-12)


def test_table_from_csv_with_states_and_its_errors(tmp_path):
    path = tmp_path / "tank.csv"
    path.write_text(
        "# illustrative\nstate,azimuth,elevation,temperature\n"
        "engine-on,0,0,300\nengine-on,180,0,330\nengine-off,0,0,299\nengine-off,180,0,301\n"
    )
    on = AspectTable.from_csv(path, "engine-on")
    assert on.values == ((300.0,), (330.0,)) and on.azimuth == (0.0, math.pi)
    assert AspectTable.from_csv(path, "engine-off").values == ((299.0,), (301.0,))
    with pytest.raises(ValueError, match="choose a state, one of engine-off, engine-on"):
        AspectTable.from_csv(path)
    path.write_text("azimuth,elevation,temperature\n0,0,300\n90,0,301\n0,10,300\n")
    with pytest.raises(ValueError, match=r"full grid.*azimuth 90 deg, elevation 10 deg is missing"):
        AspectTable.from_csv(path)
    path.write_text("azimuth,elevation,radiance\n0,0,300\n")
    with pytest.raises(ValueError, match="header must name the columns azimuth, elevation"):
        AspectTable.from_csv(path)
    path.write_text("azimuth,elevation,temperature\n0,0,warm\n")
    with pytest.raises(ValueError, match="line 2: azimuth, elevation and temperature must be"):
        AspectTable.from_csv(path)


@pytest.mark.parametrize(
    ("azimuth", "elevation", "values", "message"),
    [
        ((0.0, 0.0), (0.0,), ((1.0,), (2.0,)), "azimuth: values must be strictly ascending"),
        ((2 * math.pi,), (0.0,), ((1.0,),), r"azimuth: values must lie in \[0, 360\) deg"),
        ((0.0,), (2.0,), ((1.0,),), r"elevation: values must lie in \[-90, 90\] deg"),
        ((0.0,), (0.0,), ((float("nan"),),), "values must be finite"),
        ((0.0,), (0.0,), ((0.0,),), "temperatures must be > 0 K"),
        ((0.0, 1.0), (0.0,), ((1.0,),), "grid of 2 azimuths × 1 elevations"),
    ],
)
def test_table_refuses_what_is_not_a_grid_of_signatures(azimuth, elevation, values, message):
    with pytest.raises(ValueError, match=message):
        AspectTable(azimuth, elevation, values)


def test_a_csv_azimuth_outside_one_turn_is_refused_not_wrapped(tmp_path):
    path = tmp_path / "t.csv"
    path.write_text("azimuth,elevation,temperature\n0,0,300\n400,0,310\n")
    with pytest.raises(ValueError, match=r"azimuths must lie in \[0, 360\) deg"):
        AspectTable.from_csv(path)
