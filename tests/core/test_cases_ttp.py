"""The TTP resolution model of a range case: its cycles, its ranges and its registry entry."""

from __future__ import annotations

import math

import numpy as np
import pytest

from targetacq.acquisition.criteria import CRITERIA
from targetacq.core.cases import (
    RESOLUTION_MODELS,
    RangeCase,
    case_acquisition,
    case_factors,
    get_resolution_model,
)
from targetacq.core.ranges import dri_ranges
from targetacq.physics.mrtd import MrtdCurve
from targetacq.physics.ttp import TtpSystem, ttp_cycles

SYSTEM = TtpSystem(ifov=1.7e-4, aperture=0.1, wavelength=10e-6, netd=0.05)


def test_registry_names_and_noise_flags():
    assert list(RESOLUTION_MODELS) == ["johnson", "mrtd", "ttp"]
    assert get_resolution_model("geometric") is RESOLUTION_MODELS["johnson"]
    assert [m.includes_noise for m in RESOLUTION_MODELS.values()] == [False, True, True]
    with pytest.raises(ValueError, match="resolution model"):
        get_resolution_model("ttpp")


def test_a_case_with_a_ttp_system_uses_the_ttp_criterion_and_transform():
    case = RangeCase(2.3, 1.7e-4, ttp=SYSTEM, contrast=2.0)
    assert case.resolution_model == "ttp"
    assert case.criterion.name == "ttp-vehicles" and case.transform == "ttp"
    chosen = RangeCase(2.3, 1.7e-4, ttp=SYSTEM, contrast=2.0, criterion={"identification": 18.0})
    assert chosen.criterion.n50("identification") == 18.0


def test_case_factors_are_the_ttp_kernel_through_the_path():
    case = RangeCase(2.3, 1.7e-4, ttp=SYSTEM, contrast=2.0, extinction=0.3e-3, target_area=6.0)
    r = np.array([500.0, 2000.0])
    cycles, tau, _ = case_factors(case, r)
    np.testing.assert_allclose(tau, np.exp(-0.3e-3 * r), rtol=1e-14)
    expected = ttp_cycles(r, math.sqrt(6.0), 2.0, np.exp(-0.3e-3 * r), SYSTEM)
    np.testing.assert_allclose(cycles, expected, rtol=1e-12)


def test_identification_range_is_where_v_reaches_v50():
    case = RangeCase(2.3, 1.7e-4, ttp=SYSTEM, contrast=2.0)
    v50 = CRITERIA["ttp-vehicles"].n50("identification")
    lo, hi = 100.0, 1e5  # an independent bisection of V(R) = V50 on the physics kernel
    for _ in range(80):
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if ttp_cycles(mid, 2.3, 2.0, 1.0, SYSTEM) > v50 else (lo, mid)
    got = dri_ranges(case)["identification"]
    assert got == pytest.approx(lo, rel=1e-6)
    assert case_acquisition(case, got).identification == pytest.approx(0.5, abs=1e-6)


def test_ttp_case_checks():
    with pytest.raises(ValueError, match="needs the target's contrast"):
        RangeCase(2.3, 1.7e-4, ttp=SYSTEM)
    with pytest.raises(ValueError, match="not both"):
        RangeCase(2.3, 1.7e-4, ttp=SYSTEM, contrast=2.0, mrtd=MrtdCurve.example())
    with pytest.raises(ValueError, match="ttp must be a TtpSystem"):
        RangeCase(2.3, 1.7e-4, ttp={"ifov": 1e-4}, contrast=2.0)
