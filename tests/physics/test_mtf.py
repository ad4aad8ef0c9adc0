"""The MTF components against closed forms computed independently, and their properties."""

from __future__ import annotations

import math

import array_api_strict as xps
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from targetacq.physics import mtf as m

# One sample of parameters per component, scaled so that f = 1000 cycles/rad is mid-band.
PARAMETERS = {
    "diffraction": {"wavelength": 10e-6, "aperture": 0.02},
    "detector": {"ifov": 3.4e-4},
    "sampling": {"pitch": 3.4e-4},
    "blur": {"blur_sigma": 2e-4},
    "jitter": {"jitter": 1.5e-4},
    "motion": {"smear": 4e-4},
    "turbulence": {"range": 3000.0, "wavelength": 4e-6, "cn2": 1e-13, "aperture": 0.1},
}


def test_every_component_has_sample_parameters():
    assert set(PARAMETERS) == set(m.MTF_COMPONENTS)


def _pupil_overlap(nu: float, n: int = 2001) -> float:
    """The overlap of two unit-diameter disks shifted by ν, over one disk's area, by counting
    the points of a grid (the incoherent OTF of a circular pupil is its autocorrelation)."""
    x = np.linspace(-0.5, 0.5, n)
    xx, yy = np.meshgrid(x, x)
    inside = xx**2 + yy**2 <= 0.25
    shifted = (xx - nu) ** 2 + yy**2 <= 0.25
    return float(np.sum(inside & shifted) / np.sum(inside))


@pytest.mark.parametrize("nu", [0.1, 0.25, 0.5, 0.75, 0.9])
def test_diffraction_mtf_is_the_pupil_autocorrelation(nu):
    wavelength, aperture = 10e-6, 0.05
    got = m.diffraction_mtf(nu * aperture / wavelength, wavelength, aperture)
    assert got == pytest.approx(_pupil_overlap(nu), abs=2e-3)


def test_diffraction_mtf_closed_form_points():
    # ν = 1/2: (2/π)(π/3 − (1/2)(√3/2)) = 2/3 − √3/(2π); 0 at and beyond the cut-off D/λ.
    cutoff = 0.05 / 10e-6
    assert m.diffraction_mtf(0.5 * cutoff, 10e-6, 0.05) == pytest.approx(
        2 / 3 - math.sqrt(3) / (2 * math.pi), rel=1e-13
    )
    np.testing.assert_array_equal(m.diffraction_mtf(np.array([1.0, 3.0]) * cutoff, 1e-5, 0.05), 0)


@pytest.mark.parametrize("name", sorted(PARAMETERS))
def test_each_component_is_one_at_zero_and_at_most_one(name):
    component = m.MTF_COMPONENTS[name]
    args = [PARAMETERS[name][p] for p in component.parameters]
    assert component.kernel(0.0, *args) == pytest.approx(1.0, abs=1e-15)
    f = np.linspace(0.0, 2e4, 2001)
    values = component.kernel(f, *args)
    assert np.all(values <= 1.0 + 1e-15)
    assert np.all(values >= 0.0)
    assert values[200] < 1.0  # 2000 cycles/rad: each component does attenuate


@given(
    f=st.floats(0.0, 1e5),
    width=st.floats(1e-6, 1e-2),
)
def test_sinc_components_bounded(f, width):
    for kernel in (m.detector_mtf, m.sampling_mtf, m.motion_mtf):
        value = kernel(f, width)
        assert 0.0 <= value <= 1.0


def test_motion_mtf_zero_at_one_over_smear_and_jitter_closed_form():
    assert m.motion_mtf(1.0 / 4e-4, 4e-4) == pytest.approx(0.0, abs=1e-15)
    assert m.motion_mtf(123.0, 0.0) == 1.0
    sigma = 1e-4
    f = 1.0 / (math.pi * math.sqrt(2.0) * sigma)
    assert m.jitter_mtf(f, sigma) == pytest.approx(math.exp(-1.0), rel=1e-14)


def test_fried_parameter_scaling_and_definition():
    # r0 ∝ λ^(6/5) L^(−3/5) Cn2^(−3/5); the spherical wave's is (8/3)^(3/5) the plane wave's.
    base = m.fried_parameter(1000.0, 1e-5, 1e-14)
    assert m.fried_parameter(2000.0, 1e-5, 1e-14) == pytest.approx(base * 2**-0.6, rel=1e-12)
    assert m.fried_parameter(1000.0, 2e-5, 1e-14) == pytest.approx(base * 2**1.2, rel=1e-12)
    plane = m.fried_parameter(1000.0, 1e-5, 1e-14, wave="plane")
    assert base / plane == pytest.approx((8 / 3) ** 0.6, rel=1e-12)
    k = 2 * math.pi / 1e-5
    assert plane == pytest.approx((0.423 * k**2 * 1e-14 * 1000.0) ** -0.6, rel=1e-12)
    assert m.fried_parameter(0.0, 1e-5, 1e-14) == math.inf
    assert m.fried_parameter(1000.0, 1e-5, 0.0) == math.inf


def test_turbulence_short_exposure_above_long_and_monotone_in_cn2():
    f = np.linspace(0.0, 2e4, 101)
    args = (3000.0, 4e-6)
    long_ = m.turbulence_mtf(f, *args, 1e-13, 0.1)
    short = m.turbulence_mtf(f, *args, 1e-13, 0.1, exposure="short")
    assert np.all(short >= long_)
    assert np.any(short > long_)
    stronger = m.turbulence_mtf(f, *args, 1e-12, 0.1)
    assert np.all(stronger <= long_)
    assert np.all(m.turbulence_mtf(f, *args, 0.0, 0.1) == 1.0)


def test_system_mtf_is_the_product_of_the_components():
    f = np.array([0.0, 400.0, 1000.0, 2500.0])
    product = np.ones_like(f)
    for name, params in PARAMETERS.items():
        component = m.MTF_COMPONENTS[name]
        product = product * component.kernel(f, *[params[p] for p in component.parameters])
    np.testing.assert_allclose(m.system_mtf(f, PARAMETERS), product, rtol=1e-14)
    np.testing.assert_array_equal(m.system_mtf(f, {}), np.ones(4))


def test_system_mtf_refuses_unknown_names():
    with pytest.raises(ValueError, match="unknown MTF component 'optics'"):
        m.system_mtf(1.0, {"optics": {}})
    with pytest.raises(ValueError, match="missing aperture"):
        m.system_mtf(1.0, {"diffraction": {"wavelength": 1e-5}})
    with pytest.raises(ValueError, match="unknown focus"):
        m.system_mtf(1.0, {"detector": {"ifov": 1e-4, "focus": 1}})
    with pytest.raises(ValueError, match="exposure must be one of long, short"):
        m.turbulence_mtf(1.0, 1.0, 1e-5, 1e-14, 0.1, exposure="medium")


def test_inputs_checked_and_nan_kept():
    with pytest.raises(ValueError, match="jitter must be >= 0 rad"):
        m.jitter_mtf(1.0, -1.0)
    with pytest.raises(ValueError, match="cn2 must be >= 0"):
        m.turbulence_mtf(1.0, 1.0, 1e-5, -1e-14, 0.1)
    assert np.isnan(m.motion_mtf(float("nan"), 1e-4))
    assert np.isnan(m.turbulence_mtf(1000.0, float("nan"), 1e-5, 1e-14, 0.1))


def test_array_api_strict():
    f = xps.asarray([0.0, 500.0, 1500.0])
    got = m.system_mtf(f, {name: dict(p) for name, p in PARAMETERS.items()})
    assert isinstance(got, type(f))
    expected = m.system_mtf(np.asarray([0.0, 500.0, 1500.0]), PARAMETERS)
    np.testing.assert_allclose(np.asarray(got), expected, rtol=1e-13)
