"""Geometry: slant range, solid angle (3.5), critical dimension seen by the sensor."""

import math

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

import targetacq as ta


def test_slant_range_is_the_hypotenuse():
    assert ta.slant_range(300.0, 400.0) == pytest.approx(500.0)
    np.testing.assert_allclose(ta.slant_range([0.0, 3.0], [5.0, 4.0]), [5.0, 5.0])


def test_solid_angle_eq_3_5_as_printed():
    h, r, a = 1000.0, 2000.0, 10.0
    expected = h * a / (math.pi * (h**2 + r**2) ** 1.5)  # Eq. (3.5), Sonesson (2004)
    assert ta.solid_angle(h, r, a) == pytest.approx(expected, rel=1e-14)


def _box_outline(length, width, height, aspect, depression):
    """Independent check: project the 8 corners with rotation matrices and take the extents."""
    corners = np.array(
        [[x, y, z] for x in (0, length) for y in (0, width) for z in (0, height)], dtype=float
    )
    # Line of sight in the target frame (x along the length, z up), looking down.
    ca, sa, ce, se = math.cos(aspect), math.sin(aspect), math.cos(depression), math.sin(depression)
    los = np.array([ce * ca, ce * sa, -se])
    horizontal_axis = np.array([-sa, ca, 0.0])
    vertical_axis = np.cross(horizontal_axis, los)
    u = corners @ horizontal_axis
    v = corners @ vertical_axis
    return u.max() - u.min(), v.max() - v.min()


@given(
    st.floats(0.1, 10),
    st.floats(0.1, 10),
    st.floats(0.1, 10),
    st.floats(-math.pi, math.pi),
    st.floats(0, math.pi / 2),
)
def test_projected_extents_match_projected_corners(length, width, height, aspect, depression):
    h, v = ta.projected_extents(length, width, height, aspect, depression)
    eh, ev = _box_outline(length, width, height, aspect, depression)
    assert h == pytest.approx(eh, rel=1e-9, abs=1e-12)
    assert v == pytest.approx(ev, rel=1e-9, abs=1e-12)


def test_critical_dimension_is_the_smallest_side_seen():
    # Broadside, level view of a 6.5 x 3.4 x 2.3 m vehicle: the 2.3 m height (§3.2, Fig. 3.3).
    assert ta.critical_dimension(6.5, 3.4, 2.3) == pytest.approx(2.3)
    # Head-on, level: min(width, height).
    assert ta.critical_dimension(6.5, 3.4, 2.3, aspect=0.0) == pytest.approx(2.3)
    # Straight down from above, broadside: the width.
    assert ta.critical_dimension(6.5, 3.4, 2.3, depression=math.pi / 2) == pytest.approx(3.4)
    assert ta.critical_dimension(6.5, 3.4, 2.3, method="geometric-mean") == pytest.approx(
        math.sqrt(6.5 * 2.3)
    )


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: ta.slant_range(-1.0, 10.0), "height must be >= 0"),
        (lambda: ta.slant_range(math.nan, 10.0), "height .* NaN"),
        (lambda: ta.critical_dimension(1, 1, 1, method="area"), "minimum, geometric-mean"),
        (lambda: ta.critical_dimension(1, 1, 1, depression=2.0), "depression"),
        (lambda: ta.critical_dimension(-1, 1, 1), "length must be >= 0"),
    ],
)
def test_bad_geometry_input(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_nan_in_an_array_propagates():
    out = ta.slant_range([1.0, math.nan], [1.0, 1.0])
    assert math.isnan(out[1]) and out[0] == pytest.approx(math.sqrt(2))


@given(
    st.floats(0.1, 10),
    st.floats(0.1, 10),
    st.floats(0.1, 10),
    st.floats(-5e3, 5e3),
    st.floats(-5e3, 5e3),
    st.floats(-3e3, 3e3),
    st.floats(-7, 7),
)
def test_box_extents_from_vectors_equal_the_angle_form(length, width, height, x, y, z, heading):
    from targetacq.physics.geometry import box_extents_seen

    rng, h, v = box_extents_seen([x, y, z], heading, length, width, height)
    assume(math.hypot(x, y) > 1e-6)
    aspect = math.atan2(x, y) - heading
    depression = abs(math.atan2(z, math.hypot(x, y)))
    eh, ev = ta.projected_extents(length, width, height, aspect, depression)
    assert rng == pytest.approx(math.sqrt(x * x + y * y + z * z))
    assert h == pytest.approx(eh, rel=1e-9, abs=1e-12)
    assert v == pytest.approx(ev, rel=1e-9, abs=1e-12)


def test_box_seen_from_straight_above_is_its_top():
    from targetacq.physics.geometry import box_extents_seen

    _, h, v = box_extents_seen([0.0, 0.0, -100.0], 0.3, 6.0, 3.0, 2.0)
    assert sorted((h, v)) == [3.0, 6.0]
