"""The TTP metric: its pieces against independent computations, and its physical properties."""

from __future__ import annotations

import dataclasses
import math

import array_api_strict as xps
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate

from targetacq.acquisition.criteria import CRITERIA
from targetacq.acquisition.transforms import ttp_transform, ttp_transform_inverse
from targetacq.physics import ttp as t
from targetacq.physics.mtf import system_mtf

# A 640 × 512, 17 µm LWIR camera behind a 100 mm f/1.0 lens, NETD 50 mK.
CAMERA = t.TtpSystem(ifov=17e-6 / 0.1, aperture=0.1, wavelength=10e-6, netd=0.05)
TARGET = 2.3  # characteristic dimension sqrt(A) [m]


def _range_for(v50: float, system: t.TtpSystem, delta_t: float = 2.0) -> float:
    """The range at which V = V50 (P = 0.5), by bisection on the public kernel."""
    lo, hi = 10.0, 1e5
    for _ in range(60):
        mid = math.sqrt(lo * hi)
        if t.ttp_cycles(mid, TARGET, delta_t, 1.0, system) > v50:
            lo = mid
        else:
            hi = mid
    return math.sqrt(lo * hi)


# --------------------------------------------------------------------------------------------
# Pieces


def test_eye_ctf_is_barten_simplified_formula_written_out():
    # Written out independently in cycles/degree, L = 50 cd/m², w = 10°, u = 1, 4, 16.
    def barten(u, lum=50.0, w=10.0):
        a = 540 * (1 + 0.7 / lum) ** -0.2 / (1 + 12 / (w * (1 + u / 3) ** 2))
        b = 0.3 * (1 + 100 / lum) ** 0.15
        return 1 / (a * u * math.exp(-b * u) * math.sqrt(1 + 0.06 * math.exp(b * u)))

    for u in (1.0, 4.0, 16.0):
        got = t.eye_ctf(u * 180 / math.pi, 50.0, math.radians(10.0))
        assert got == pytest.approx(barten(u), rel=1e-12)


def test_eye_ctf_shape_brighter_display_lowers_threshold():
    u = np.array([0.5, 1, 2, 3, 4, 6, 10, 20, 40]) * 180 / math.pi
    ctf = t.eye_ctf(u)
    assert int(np.argmin(ctf)) in (2, 3, 4, 5)  # lowest at 2–6 cycles/degree (band-pass)
    assert 1e-3 < ctf.min() < 1e-2
    assert np.all(t.eye_ctf(u, 100.0) < t.eye_ctf(u, 1.0))
    assert t.eye_ctf(0.0) == math.inf


def test_noise_factor_properties():
    f = np.linspace(0.0, 5000.0, 11)
    assert np.all(t.noise_factor(f, 0.0, 1.7e-4, 30.0, 5.0) == 1.0)
    quiet = t.noise_factor(f, 0.05, 1.7e-4, 30.0, 5.0)
    noisy = t.noise_factor(f, 0.2, 1.7e-4, 30.0, 5.0)
    faster = t.noise_factor(f, 0.2, 1.7e-4, 120.0, 5.0)
    assert np.all(noisy[1:] > quiet[1:]) and np.all(faster[1:] < noisy[1:])
    # the variance term grows linearly with frequency (Q_H = κ ξ) and with NETD²
    excess = noisy**2 - 1
    np.testing.assert_allclose(excess[2:] / excess[1], f[2:] / f[1], rtol=1e-12)
    np.testing.assert_allclose(excess, 16 * (quiet**2 - 1), rtol=1e-12)


def test_apparent_contrast():
    assert t.apparent_contrast(-2.0, 0.5, 5.0) == pytest.approx(0.1)
    assert t.apparent_contrast(40.0, 1.0, 5.0) == 1.0  # clipped: a display's modulation <= 1
    with pytest.raises(ValueError, match="transmittance must be in"):
        t.apparent_contrast(1.0, 1.5, 5.0)


def test_system_ctf_is_eye_over_mtf_times_noise():
    f = np.array([300.0, 1000.0, 3000.0])
    r = 2000.0
    system = dataclasses.replace(CAMERA, jitter=5e-5, cn2=1e-14)
    mtf = system_mtf(
        f,
        {
            "diffraction": {"wavelength": 10e-6, "aperture": 0.1},
            "detector": {"ifov": 1.7e-4},
            "sampling": {"pitch": 1.7e-4},
            "jitter": {"jitter": 5e-5},
            "turbulence": {"range": r, "wavelength": 10e-6, "cn2": 1e-14, "aperture": 0.1},
        },
    )
    eye = t.eye_ctf(f / system.magnification)
    noise = t.noise_factor(f, 0.05, 1.7e-4, 30.0, t.DEFAULT_SCENE_CONTRAST)
    np.testing.assert_allclose(t.system_ctf(f, r, system), eye / mtf * noise, rtol=1e-12)


def test_ttp_value_equals_adaptive_quadrature_of_the_definition():
    # Φ = ∫ sqrt(C / CTF_sys) over C > CTF_sys, by scipy's adaptive quadrature on the public CTF.
    for delta_t, r in ((2.0, 1000.0), (0.1, 3000.0), (0.02, 500.0)):
        c = t.apparent_contrast(delta_t, 1.0, t.DEFAULT_SCENE_CONTRAST)

        def integrand(f, c=c, r=r):
            ctf = t.system_ctf(f, r, CAMERA)
            return math.sqrt(c / ctf) if c > ctf else 0.0

        cutoff = float(CAMERA.cutoff)
        expected, _ = integrate.quad(integrand, 0.0, cutoff, limit=400, points=[cutoff * 0.9])
        got = t.ttp_value(r, delta_t, 1.0, CAMERA)
        assert got == pytest.approx(expected, rel=2e-3)


def test_cycles_are_dimension_over_range_times_ttp():
    phi = t.ttp_value(1500.0, 1.0, 0.8, CAMERA)
    assert t.ttp_cycles(1500.0, TARGET, 1.0, 0.8, CAMERA) == pytest.approx(TARGET / 1500 * phi)


def test_a_target_below_the_eye_threshold_is_not_resolved():
    # 1 mK against a 5 K scene contrast: C = 1e-4, below the eye's lowest threshold (~2e-3).
    assert t.ttp_cycles(np.array([10.0, 100.0, 1000.0]), TARGET, 1e-3, 1.0, CAMERA).max() == 0


def test_nan_and_array_api_strict():
    got = t.ttp_cycles(np.array([500.0, np.nan, 2000.0]), TARGET, 2.0, 1.0, CAMERA)
    assert np.isnan(got).tolist() == [False, True, False]
    strict = t.ttp_cycles(xps.asarray([500.0, 2000.0]), TARGET, 2.0, 1.0, CAMERA)
    np.testing.assert_allclose(np.asarray(strict), got[[0, 2]], rtol=1e-12)


def test_broadcasts_over_ranges_and_system_arrays():
    system = dataclasses.replace(CAMERA, jitter=np.array([[0.0], [1e-4]]))
    got = t.ttp_cycles(np.array([500.0, 1000.0, 2000.0]), TARGET, 2.0, 1.0, system)
    assert got.shape == (2, 3)
    one = t.ttp_cycles(1000.0, TARGET, 2.0, 1.0, dataclasses.replace(CAMERA, jitter=1e-4))
    assert got[1, 1] == pytest.approx(one, rel=1e-12)


def test_system_record_checks():
    with pytest.raises(ValueError, match="fill_factor must be in"):
        dataclasses.replace(CAMERA, fill_factor=1.5)
    with pytest.raises(ValueError, match="exposure must be one of"):
        dataclasses.replace(CAMERA, exposure="medium")
    with pytest.raises(ValueError, match="aperture must be > 0 m"):
        dataclasses.replace(CAMERA, aperture=0.0)


# --------------------------------------------------------------------------------------------
# Properties: the range moves the right way.

V50_ID = CRITERIA["ttp-vehicles"].n50("identification")


def test_larger_f_number_shortens_the_range():
    # The same 100 mm focal length at f/1, f/2, f/4: the aperture shrinks, diffraction grows.
    ranges = [_range_for(V50_ID, dataclasses.replace(CAMERA, aperture=0.1 / n)) for n in (1, 2, 4)]
    assert ranges[0] > ranges[1] > ranges[2]


def test_larger_jitter_shortens_the_range():
    ranges = [_range_for(V50_ID, dataclasses.replace(CAMERA, jitter=j)) for j in (0, 5e-5, 2e-4)]
    assert ranges[0] > ranges[1] > ranges[2]


def test_stronger_turbulence_shortens_the_range():
    ranges = [_range_for(V50_ID, dataclasses.replace(CAMERA, cn2=c)) for c in (0, 1e-14, 1e-13)]
    assert ranges[0] > ranges[1] > ranges[2]


def test_more_noise_and_more_smear_shorten_the_range():
    low_contrast = 0.1
    quiet = _range_for(V50_ID, CAMERA, low_contrast)
    noisy = _range_for(V50_ID, dataclasses.replace(CAMERA, netd=0.3), low_contrast)
    assert noisy < quiet
    assert _range_for(V50_ID, dataclasses.replace(CAMERA, smear=3e-4)) < _range_for(V50_ID, CAMERA)


@settings(max_examples=30, deadline=None)
@given(
    low=st.floats(1e-3, 20.0),
    factor=st.floats(1.01, 10.0),
    r=st.floats(100.0, 10_000.0),
    tau=st.floats(0.05, 1.0),
)
def test_v_does_not_decrease_with_contrast(low, factor, r, tau):
    v_low = t.ttp_cycles(r, TARGET, low, tau, CAMERA)
    v_high = t.ttp_cycles(r, TARGET, low * factor, tau, CAMERA)
    assert v_high >= v_low
    if v_low > 0 and low * factor * tau / (2 * t.DEFAULT_SCENE_CONTRAST) < 1:
        assert v_high > v_low


@given(v=st.floats(0.0, 1e3), dv=st.floats(1e-3, 10.0), v50=st.floats(0.5, 50.0))
def test_ttpf_in_unit_interval_and_monotone(v, dv, v50):
    p, q = ttp_transform(v, v50), ttp_transform(v + dv, v50)
    assert 0.0 <= p <= q <= 1.0


def test_ttpf_inverse_round_trip_and_its_exponent():
    p = np.array([0.01, 0.2, 0.5, 0.8, 0.99])
    np.testing.assert_allclose(ttp_transform(ttp_transform_inverse(p, 20.8), 20.8), p, rtol=1e-12)
    # E = 1.51 + 0.24 x written out: at x = 3, P = 3^2.23 / (1 + 3^2.23).
    assert ttp_transform(3 * 20.8, 20.8) == pytest.approx(3**2.23 / (1 + 3**2.23), rel=1e-14)


def test_jax_jit_and_grad():
    jax = pytest.importorskip("jax")
    jnp = pytest.importorskip("jax.numpy")
    jax.config.update("jax_enable_x64", True)
    system = dataclasses.replace(CAMERA, cn2=1e-14, jitter=1e-5)
    r = np.array([1000.0, 2000.0])
    got = jax.jit(lambda rr: t.ttp_cycles(rr, TARGET, 2.0, 1.0, system))(jnp.asarray(r))
    np.testing.assert_allclose(
        np.asarray(got), t.ttp_cycles(r, TARGET, 2.0, 1.0, system), rtol=1e-12
    )
    slope = jax.grad(lambda dt: t.ttp_cycles(1000.0, TARGET, dt, 1.0, system))(0.5)
    step = 1e-4
    central = (
        t.ttp_cycles(1000.0, TARGET, 0.5 + step, 1.0, system)
        - t.ttp_cycles(1000.0, TARGET, 0.5 - step, 1.0, system)
    ) / (2 * step)
    assert float(slope) == pytest.approx(central, rel=1e-6)
