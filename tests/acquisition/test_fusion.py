"""Sensor-level fusion (8.4) and central-level bounds (8.5)."""

import itertools

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import targetacq as ta


def test_two_sensors():
    # 1 - (1 - 0.5)(1 - 0.4) = 0.7, Eq. (8.4).
    assert ta.fuse([0.5, 0.4]) == pytest.approx(0.7)


def test_fuse_along_any_axis():
    p = np.array([[0.5, 0.2], [0.4, 0.1]])
    np.testing.assert_allclose(ta.fuse(p, axis=0), [0.7, 0.28])
    np.testing.assert_allclose(ta.fuse(p, axis=-1), [0.6, 0.46])


@given(st.lists(st.floats(0, 1), min_size=1, max_size=6))
def test_fusion_is_symmetric_and_at_least_its_largest_input(ps):
    fused = ta.fuse(np.array(ps))
    assert fused >= max(ps) - 1e-15
    assert fused <= 1.0
    for perm in itertools.islice(itertools.permutations(ps), 6):
        assert ta.fuse(np.array(perm)) == pytest.approx(fused, abs=1e-15)


def test_central_level_bounds():
    lower, upper = ta.central_level_bounds([0.5, 0.4])
    assert lower == pytest.approx(0.7) and upper == 1.0


def test_bad_fusion_input():
    with pytest.raises(ValueError, match=r"probabilities must be in \[0, 1\]"):
        ta.fuse([0.5, 1.2])
    with pytest.raises(ValueError, match="at least one axis"):
        ta.fuse(0.5)


def test_nan_propagates():
    out = ta.fuse(np.array([[0.5, np.nan], [0.5, 0.5]]))
    assert np.isnan(out[0]) and out[1] == pytest.approx(0.75)
