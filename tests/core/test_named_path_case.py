"""A range case through a named atmosphere: its optical depth, not γR (issue 25)."""

import numpy as np
import pytest

from targetacq.core.cases import RangeCase, case_factors
from targetacq.core.ranges import case_ranges
from targetacq.physics import named_atmospheres as na

TROPICAL_LWIR = na.NamedBandPath(na.NamedPath("tropical", "rural", 23e3), "lwir")


def test_the_case_transmittance_is_the_named_band_transmittance():
    r = np.array([500.0, 5e3, 20e3])
    _, tau, snr = case_factors(RangeCase(2.3, 2e-4, path=TROPICAL_LWIR), r)
    expected = na.named_band_transmittance(r, "lwir", "tropical", "rural", 23e3)
    np.testing.assert_allclose(tau, expected, rtol=1e-12)
    assert np.all(np.isfinite(snr)) and np.all(np.diff(snr) < 0)


def test_a_named_path_attenuates_and_shortens_the_ranges():
    clear = case_ranges(RangeCase(2.3, 2e-4), 0.5)
    humid = case_ranges(RangeCase(2.3, 2e-4, path=TROPICAL_LWIR), 0.5)
    assert RangeCase(2.3, 2e-4, path=TROPICAL_LWIR).attenuates
    for task in clear:
        assert humid[task] < clear[task]


def test_a_path_and_an_extinction_are_one_too_many():
    with pytest.raises(ValueError, match="extinction or a path model"):
        RangeCase(2.3, 2e-4, extinction=1e-4, path=TROPICAL_LWIR)
    with pytest.raises(TypeError, match=r"path must have depth\(range, xp\)"):
        RangeCase(2.3, 2e-4, path="tropical")
