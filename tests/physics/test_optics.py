"""Optics: IFOV, FOV (5.1), diffraction (5.3–5.4), blur (5.2), cycles on target (Fig. 3.3)."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy import integrate

import targetacq as ta
from targetacq.physics import optics


def test_ifov_is_pitch_over_focal_length():
    assert ta.ifov(17e-6, 75e-3) == pytest.approx(2.2666666e-4, rel=1e-7)


def test_field_of_view_eq_5_1():
    a, f = 640 * 17e-6, 50e-3
    assert ta.field_of_view(a, f) == pytest.approx(2 * math.atan(a / (2 * f)))


def test_ifov_from_field_of_view_inverts_eq_5_1():
    pitch, f, n = 17e-6, 50e-3, 640
    fov = ta.field_of_view(n * pitch, f)
    got = ta.ifov_from_field_of_view(fov, n, projection="rectilinear")
    assert got == pytest.approx(pitch / f, rel=1e-12)


def test_datasheet_ifov_is_the_mean_angle_per_pixel():
    # A 100° lens over 640 pixels: 1.7453 rad / 640 = 2.727 mrad (the datasheet convention).
    assert ta.ifov_from_field_of_view(math.radians(100), 640) == pytest.approx(
        1.7453292519943295 / 640, rel=1e-15
    )
    with pytest.raises(ValueError, match="unknown projection 'fisheye'"):
        ta.ifov_from_field_of_view(1.0, 640, projection="fisheye")


@pytest.mark.parametrize("projection", ["angular", "rectilinear"])
def test_field_of_view_from_ifov_inverts(projection):
    from targetacq.physics.optics import field_of_view_from_ifov

    ifov = ta.ifov_from_field_of_view(1.2, 640, projection=projection)
    assert field_of_view_from_ifov(ifov, 640, projection) == pytest.approx(1.2, rel=1e-14)


def test_fig_3_3_a_target_two_and_a_half_pixel_rows_high_is_1_25_cycles():
    ifov, rng = 0.1e-3, 2000.0
    height = 2.5 * ifov * rng  # 2.5 pixel rows
    assert ta.cycles_on_target(height, rng, ifov) == pytest.approx(1.25)


def test_diffraction_check_value_0_1_m_at_1_km():
    # Sonesson (2004) §5.5, Eq. (5.3): D = 122 mm, λ = 10 µm -> 1e-4 rad -> 0.1 m at 1000 m.
    angle = ta.diffraction_angle(10e-6, 0.122)
    assert angle == pytest.approx(1e-4, rel=1e-6)
    assert angle * 1000.0 == pytest.approx(0.1, rel=1e-6)
    assert ta.diffraction_spot(10e-6, 0.122, 0.2) == pytest.approx(0.2 * 1e-4)  # Eq. (5.4)


def test_cycle_is_the_larger_of_sampling_and_diffraction():
    # Coarse pixels: sampling-limited, one cycle = 2 IFOV (the erratum's "usual" case).
    assert ta.resolvable_cycle_angle(1e-4, wavelength=10e-6, aperture=0.122) == pytest.approx(2e-4)
    # Fine pixels behind a small lens: diffraction-limited, one cycle = 1.22 λ / D.
    assert ta.resolvable_cycle_angle(1e-5, wavelength=10e-6, aperture=0.122) == pytest.approx(
        1e-4, rel=1e-6
    )
    n_sampling = ta.cycles_on_target(2.3, 1000.0, 1e-5)
    n_optics = ta.cycles_on_target(2.3, 1000.0, 1e-5, wavelength=10e-6, aperture=0.122)
    assert n_optics == pytest.approx(2.3 / 1000.0 / 1e-4, rel=1e-6)
    assert n_optics < n_sampling


def _circular_aperture_mtf_by_quadrature(nu):
    """Overlap area of two unit-diameter discs offset by nu, over the disc area (independent)."""
    r = 0.5

    def chord(x):
        return 2 * math.sqrt(max(r * r - x * x, 0.0))

    # Overlap of discs centred at 0 and nu, integrated along x across the lens-shaped region.
    area, _ = integrate.quad(
        lambda x: min(chord(x), chord(x - nu)), nu - r, r, epsabs=1e-13, epsrel=1e-12
    )
    return area / (math.pi * r * r)


def test_blur_cycle_has_the_modulation_the_diffraction_rule_accepts():
    threshold = _circular_aperture_mtf_by_quadrature(1 / 1.22)
    assert pytest.approx(threshold, rel=1e-8) == optics.DIFFRACTION_THRESHOLD_MODULATION
    sigma = 3e-5
    cycle = ta.resolvable_cycle_angle(1e-7, blur_sigma=sigma)
    # The Gaussian PSF's MTF at one cycle per `cycle` equals the threshold.
    mtf = math.exp(-2 * math.pi**2 * sigma**2 / cycle**2)
    assert mtf == pytest.approx(threshold, rel=1e-9)


def test_optical_blurs_add_in_quadrature():
    diff = ta.diffraction_angle(4e-6, 0.05)
    blur = optics.BLUR_CYCLE_PER_SIGMA * 5e-5
    got = ta.resolvable_cycle_angle(1e-6, wavelength=4e-6, aperture=0.05, blur_sigma=5e-5)
    assert got == pytest.approx(math.hypot(diff, blur))


def test_gaussian_psf_is_separable_per_erratum():
    x, y, sx, sy = 1.0, 2.0, 0.5, 3.0
    assert ta.gaussian_psf(x, y, sx, sy) == pytest.approx(
        math.exp(-(x**2) / (2 * sx**2)) * math.exp(-(y**2) / (2 * sy**2))
    )


@given(st.floats(0.1, 20), st.floats(10, 1e5), st.floats(1e-6, 1e-2))
def test_range_for_cycles_inverts_cycles_on_target(d, rng, ifov):
    n = ta.cycles_on_target(d, rng, ifov)
    assert ta.range_for_cycles(d, n, ifov) == pytest.approx(rng, rel=1e-12)


def test_cycles_fall_with_range():
    n = ta.cycles_on_target(2.3, np.array([100.0, 1000.0, 10000.0]), 1e-4)
    assert np.all(np.diff(n) < 0)


def test_pixel_density_and_its_range():
    assert ta.pixels_per_metre(100.0, 1e-3) == pytest.approx(10.0)
    assert ta.range_for_pixel_density(250.0, 2e-4) == pytest.approx(20.0)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: ta.ifov(0.0, 0.05), "pitch must be > 0"),
        (lambda: ta.ifov(17e-6, -0.05), "focal_length must be > 0"),
        (lambda: ta.cycles_on_target(2.3, 0.0, 1e-4), "range must be > 0"),
        (lambda: ta.cycles_on_target(-2.3, 10.0, 1e-4), "critical_dimension must be > 0"),
        (lambda: ta.cycles_on_target(2.3, math.nan, 1e-4), "range .*NaN"),
        (lambda: ta.cycles_on_target(2.3, 10.0, 1e-4, wavelength=1e-5), "both wavelength"),
        (lambda: ta.diffraction_angle(1e-3, 1e-3), "aperture must be at least"),
        (lambda: ta.ifov_from_field_of_view(4.0, 640), "field_of_view must be < π"),
    ],
)
def test_bad_optics_input(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_nan_in_an_array_propagates_and_does_not_raise():
    n = ta.cycles_on_target(2.3, np.array([1000.0, math.nan]), 1e-4)
    assert math.isnan(n[1]) and n[0] == pytest.approx(11.5)
