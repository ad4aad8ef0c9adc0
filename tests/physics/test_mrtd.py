"""MRTD-limited resolution: the parametric MRTD against its formula worked by hand, the MTFs
against closed forms, the tabulated law and its inverse against an independent bisection, the
resolved cycles against hand arithmetic, the bench-file reader's errors, and properties."""

import csv
import math
from importlib import resources

import array_api_strict as xps
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from targetacq.base.tables import load_table
from targetacq.physics import mrtd as m

# A small curve whose law is easy to follow by hand: [cycles/rad], [K].
SMALL = m.MrtdCurve(frequency=(500.0, 1000.0, 1500.0), mrtd=(0.05, 0.1, 0.4))

# The example camera of the bundled file: 17 µm / 50 mm, 50 mm f/1.0, NETD 50 mK, 10 µm.
CAMERA = {"netd": 0.05, "ifov": 17e-6 / 50e-3, "aperture": 0.05, "wavelength": 10e-6}


# --------------------------------------------------------------------------------------------
# The parametric MRTD, worked by hand from the printed formula
#   MRTD(f) = (π²/(4√14)) · SNR_th · NETD · f / MTF_sys(f) · sqrt(αβ / (t_e · F_R · Δf_R τ_d))


def test_parametric_mrtd_at_1_cycle_per_mrad_by_hand():
    # f = 1000 cycles/rad, IFOV 3.4e-4 rad, D = 0.05 m, λ = 10 µm, NETD 0.05 K, no blur,
    # F_R = 30 Hz, t_e = 0.1 s, SNR_th = 2.5, Δf_R τ_d = 0.5.
    mtf_detector = abs(math.sin(math.pi * 1000 * 3.4e-4) / (math.pi * 1000 * 3.4e-4))
    nu = 1000 * 10e-6 / 0.05  # 0.2
    mtf_optics = 2 / math.pi * (math.acos(0.2) - 0.2 * math.sqrt(1 - 0.2**2))
    assert nu == pytest.approx(0.2)
    expected = (
        math.pi**2
        / (4 * math.sqrt(14))
        * 2.5
        * 0.05
        * 1000
        / (mtf_detector * mtf_optics)
        * math.sqrt(3.4e-4 * 3.4e-4 / (0.1 * 30 * 0.5))
    )
    assert expected == pytest.approx(0.03734, abs=5e-6)  # worked on paper: 0.0373 K
    assert m.parametric_mrtd(1000.0, **CAMERA) == pytest.approx(expected, rel=1e-12)


def test_parametric_mrtd_near_nyquist_by_hand():
    # f = 1400 cycles/rad, just below the Nyquist frequency 1/(2 · 3.4e-4) = 1470.6 cycles/rad.
    mtf_detector = abs(math.sin(math.pi * 1400 * 3.4e-4) / (math.pi * 1400 * 3.4e-4))
    mtf_optics = 2 / math.pi * (math.acos(0.28) - 0.28 * math.sqrt(1 - 0.28**2))
    expected = (
        math.pi**2
        / (4 * math.sqrt(14))
        * 2.5
        * 0.05
        * 1400
        / (mtf_detector * mtf_optics)
        * math.sqrt(3.4e-4 * 3.4e-4 / (0.1 * 30 * 0.5))
    )
    assert expected == pytest.approx(0.0741, abs=5e-5)
    assert m.parametric_mrtd(1400.0, **CAMERA) == pytest.approx(expected, rel=1e-12)


def test_parametric_mrtd_every_parameter_by_hand():
    # f = 2000 cycles/rad, IFOV 2e-4 rad, D = 0.1 m, λ = 4 µm, NETD 0.02 K, blur σ = 1e-4 rad,
    # F_R = 60 Hz, t_e = 0.2 s, SNR_th = 2.25, Δf_R τ_d = 1.
    mtf_detector = abs(math.sin(math.pi * 2000 * 2e-4) / (math.pi * 2000 * 2e-4))
    mtf_optics = 2 / math.pi * (math.acos(0.08) - 0.08 * math.sqrt(1 - 0.08**2))
    mtf_blur = math.exp(-2 * math.pi**2 * 1e-4**2 * 2000**2)
    expected = (
        math.pi**2
        / (4 * math.sqrt(14))
        * 2.25
        * 0.02
        * 2000
        / (mtf_detector * mtf_optics * mtf_blur)
        * math.sqrt(2e-4 * 2e-4 / (0.2 * 60 * 1.0))
    )
    got = m.parametric_mrtd(
        2000.0,
        netd=0.02,
        ifov=2e-4,
        aperture=0.1,
        wavelength=4e-6,
        blur_sigma=1e-4,
        frame_rate=60.0,
        eye_integration_time=0.2,
        snr_threshold=2.25,
        noise_bandwidth_dwell=1.0,
    )
    assert got == pytest.approx(expected, rel=1e-12)


def test_the_constant_is_the_bar_signal_over_the_bar_noise():
    # (π²/8) for the fundamental averaged over a bar, 2f for 1/W, 1/sqrt(2 · 7) for the 7:1 bar
    # and the white-noise average over a dwell: (π²/8) · 2 / √14 = π²/(4√14) ≈ 0.6594.
    assert (math.pi**2 / 8) * 2 / math.sqrt(2 * 7) == pytest.approx(m.MRTD_CONSTANT, rel=1e-15)
    assert abs(m.MRTD_CONSTANT - 0.6594) < 1e-4


def test_parametric_mrtd_edges():
    f = np.array([0.0, 1.0 / CAMERA["ifov"], 5000.0, 6000.0, np.nan])
    got = m.parametric_mrtd(f, **CAMERA)
    assert got[0] == 0.0
    assert np.isinf(got[1:4]).all()  # at/after the detector's first zero, 1/IFOV
    assert np.isnan(got[4])
    assert np.isnan(m.parametric_mrtd(1000.0, **{**CAMERA, "netd": float("nan")}))
    # Diffraction-limited: D/λ below 1/IFOV is the first zero.
    assert np.isinf(m.parametric_mrtd(1000.0, netd=0.05, ifov=1e-5, aperture=0.01, wavelength=1e-5))
    with pytest.raises(ValueError, match="netd must be > 0 K"):
        m.parametric_mrtd(1000.0, **{**CAMERA, "netd": 0.0})
    with pytest.raises(ValueError, match="frame_rate must be > 0 Hz"):
        m.parametric_mrtd(1000.0, **CAMERA, frame_rate=-1.0)


def test_parametric_mrtd_increases_with_frequency():
    f = np.linspace(10.0, 2900.0, 300)
    assert np.all(np.diff(m.parametric_mrtd(f, **CAMERA)) > 0)


# --------------------------------------------------------------------------------------------
# MTFs against closed forms


def test_diffraction_mtf_closed_form_values():
    cutoff = 0.05 / 10e-6  # D/λ [cycles/rad]
    assert m.diffraction_mtf(0.0, 10e-6, 0.05) == pytest.approx(1.0, abs=1e-15)
    # MTF = 1/2 at ν ≈ 0.404 (the half-modulation point of a circular pupil).
    assert m.diffraction_mtf(0.404 * cutoff, 10e-6, 0.05) == pytest.approx(0.5, abs=5e-4)
    # ν = 1/2: (2/π)(π/3 − (1/2)(√3/2)) = 2/3 − √3/(2π).
    expected = 2 / 3 - math.sqrt(3) / (2 * math.pi)
    assert m.diffraction_mtf(0.5 * cutoff, 10e-6, 0.05) == pytest.approx(expected, rel=1e-13)
    got = m.diffraction_mtf(np.array([cutoff, 2 * cutoff, np.inf]), 10e-6, 0.05)
    np.testing.assert_array_equal(got, [0.0, 0.0, 0.0])


def test_detector_mtf_zero_at_one_over_ifov_and_two_over_pi_at_nyquist():
    ifov = 3.4e-4
    assert m.detector_mtf(0.0, ifov) == 1.0
    assert m.detector_mtf(1.0 / ifov, ifov) == pytest.approx(0.0, abs=1e-15)
    assert m.detector_mtf(0.5 / ifov, ifov) == pytest.approx(2 / math.pi, rel=1e-14)
    assert m.detector_mtf(1.5 / ifov, ifov) == pytest.approx(2 / (3 * math.pi), rel=1e-13)


def test_blur_mtf_is_one_over_e_at_sigma_f_one_over_pi_root_two():
    sigma = 2e-4
    f = 1 / (math.pi * math.sqrt(2)) / sigma
    assert m.blur_mtf(f, sigma) == pytest.approx(math.exp(-1), rel=1e-14)
    assert m.blur_mtf(123.0, 0.0) == 1.0


def test_system_mtf_is_the_product():
    f = np.array([0.0, 400.0, 1000.0, 2500.0])
    product = m.diffraction_mtf(f, 10e-6, 0.05) * m.detector_mtf(f, 3.4e-4) * m.blur_mtf(f, 5e-5)
    got = m.system_mtf(f, ifov=3.4e-4, aperture=0.05, wavelength=10e-6, blur_sigma=5e-5)
    np.testing.assert_allclose(got, product, rtol=1e-15)


def test_mtf_inputs_are_checked():
    with pytest.raises(ValueError, match="frequency must be >= 0 cycles/rad"):
        m.detector_mtf(-1.0, 1e-4)
    with pytest.raises(ValueError, match="ifov must be > 0 rad"):
        m.detector_mtf(1.0, 0.0)
    with pytest.raises(ValueError, match="wavelength must be > 0 m"):
        m.diffraction_mtf(1.0, -1e-6, 0.05)
    with pytest.raises(ValueError, match="blur_sigma must be >= 0 rad"):
        m.blur_mtf(1.0, -1.0)
    assert np.isnan(m.detector_mtf(float("nan"), 1e-4))
    assert np.isnan(m.diffraction_mtf(float("nan"), 1e-5, 0.05))


# --------------------------------------------------------------------------------------------
# The tabulated law and its inverse, against an independent implementation


def _bundled_rows():
    path = resources.files("targetacq").joinpath("data").joinpath("example_mrtd.csv")
    lines = [line for line in path.read_text("utf-8").splitlines() if not line.startswith("#")]
    rows = list(csv.DictReader(lines))
    return [float(r["frequency"]) * 1000.0 for r in rows], [float(r["mrtd"]) for r in rows]


def _law_by_hand(f, table_f, table_m):
    """The documented law, in plain Python: linear below, log-linear between, inf above."""
    if f > table_f[-1]:
        return math.inf
    if f <= table_f[0]:
        return table_m[0] * f / table_f[0]
    for f0, f1, m0, m1 in zip(table_f, table_f[1:], table_m, table_m[1:]):
        if f0 <= f <= f1:
            return m0 * (m1 / m0) ** ((f - f0) / (f1 - f0))
    raise AssertionError("unreachable")


def _bisect_resolved(delta_t, table_f, table_m):
    """Largest f in [0, cut-off] with MRTD(f) <= ΔT, by 200 bisections of the law by hand."""
    lo, hi = 0.0, table_f[-1]
    if _law_by_hand(hi, table_f, table_m) <= delta_t:
        return hi
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if _law_by_hand(mid, table_f, table_m) <= delta_t:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def test_mrtd_law_at_and_between_the_points():
    # At the points: the table; at a midpoint the geometric mean; below, ∝ f; above, inf.
    got = m.mrtd([500.0, 1000.0, 1500.0, 750.0, 1250.0, 100.0, 0.0, 1500.1, np.inf], SMALL)
    expected = [0.05, 0.1, 0.4, math.sqrt(0.05 * 0.1), 0.2, 0.01, 0.0, math.inf, math.inf]
    np.testing.assert_allclose(got, expected, rtol=1e-14)


def test_mrtd_law_matches_the_law_by_hand_on_the_bundled_curve():
    table_f, table_m = _bundled_rows()
    curve = m.MrtdCurve.example()
    f = np.linspace(0.0, 1450.0, 59)
    expected = [_law_by_hand(x, table_f, table_m) for x in f]
    np.testing.assert_allclose(m.mrtd(f, curve), expected, rtol=1e-12)


def test_resolved_frequency_equals_an_independent_bisection():
    table_f, table_m = _bundled_rows()
    curve = m.MrtdCurve.example()
    delta_t = [1e-4, 0.001, 0.00235259, 0.004, 0.01, 0.0373367, 0.05, 0.07, 0.0741183, 0.5, 20.0]
    got = m.resolved_frequency(delta_t, curve)
    expected = [_bisect_resolved(dt, table_f, table_m) for dt in delta_t]
    np.testing.assert_allclose(got, expected, rtol=1e-10, atol=1e-9)


def test_resolved_frequency_by_hand_on_the_small_curve():
    # 0.025 K: 500 · 0.025/0.05 = 250. 0.2 K: 1000 + 500 · ln(0.2/0.1)/ln(0.4/0.1) = 1250.
    got = m.resolved_frequency([0.025, 0.05, 0.2, 0.4, 1.0], SMALL)
    np.testing.assert_allclose(got, [250.0, 500.0, 1250.0, 1500.0, 1500.0], rtol=1e-14)


def test_resolved_frequency_on_a_flat_part_is_its_largest_frequency():
    curve = m.MrtdCurve(frequency=(100.0, 200.0, 300.0, 400.0), mrtd=(0.1, 0.2, 0.2, 0.5))
    assert m.resolved_frequency(0.2, curve) == pytest.approx(300.0, rel=1e-14)
    assert m.resolved_frequency(0.19999999, curve) < 200.0
    assert m.resolved_frequency(0.3, curve) == pytest.approx(
        300.0 + 100.0 * math.log(1.5) / math.log(2.5), rel=1e-14
    )


def test_resolved_frequency_special_values():
    got = m.resolved_frequency([np.nan, np.inf, -np.inf, -1.0, 0.0], SMALL)
    np.testing.assert_array_equal(got, [np.nan, 1500.0, 0.0, 0.0, 0.0])
    assert np.isnan(m.resolved_frequency(float("nan"), SMALL))


@given(st.floats(min_value=1e-6, max_value=0.399999))
def test_mrtd_of_the_resolved_frequency_is_the_temperature_difference(delta_t):
    f = m.resolved_frequency(delta_t, SMALL)
    assert m.mrtd(f, SMALL) == pytest.approx(delta_t, rel=1e-12)


@given(st.floats(min_value=1e-3, max_value=1500.0))
def test_resolved_frequency_of_the_mrtd_is_the_frequency(f):
    assert m.resolved_frequency(m.mrtd(f, SMALL), SMALL) == pytest.approx(f, rel=1e-12)


# --------------------------------------------------------------------------------------------
# Resolved cycles N(R) = f*(τ ΔT) · Dc / R


def test_mrtd_cycles_by_hand():
    # R = 2000 m, Dc = 2.3 m, ΔT = 2 K.
    # τ = 0.05: τΔT = 0.1 K -> f* = 1000 cycles/rad -> N = 1000 · 2.3 / 2000 = 1.15.
    assert m.mrtd_cycles(2000.0, 2.3, 2.0, 0.05, SMALL) == pytest.approx(1.15, rel=1e-14)
    # τ = 0.1: τΔT = 0.2 K -> f* = 1250 -> N = 1250 · 2.3 / 2000 = 1.4375.
    assert m.mrtd_cycles(2000.0, 2.3, 2.0, 0.1, SMALL) == pytest.approx(1.4375, rel=1e-14)
    # τ = 0.01: τΔT = 0.02 K -> f* = 500 · 0.02 / 0.05 = 200 -> N = 200 · 2.3 / 2000 = 0.23.
    assert m.mrtd_cycles(2000.0, 2.3, 2.0, 0.01, SMALL) == pytest.approx(0.23, rel=1e-14)
    # τ = 1: 2 K is above the last MRTD -> the cut-off 1500 -> N = 1.725; a cold target alike.
    assert m.mrtd_cycles(2000.0, 2.3, 2.0, 1.0, SMALL) == pytest.approx(1.725, rel=1e-14)
    assert m.mrtd_cycles(2000.0, 2.3, -2.0, 1.0, SMALL) == pytest.approx(1.725, rel=1e-14)
    assert m.mrtd_cycles(2000.0, 2.3, 0.0, 1.0, SMALL) == 0.0


def test_mrtd_cycles_broadcasts_n_d():
    r = np.array([[500.0], [1000.0], [4000.0]])
    dt = np.array([0.0, 0.5, 1.0, 4.0])
    got = m.mrtd_cycles(r, 2.3, dt, 0.1, SMALL)
    assert got.shape == (3, 4)
    for i, ri in enumerate(r[:, 0]):
        for j, dtj in enumerate(dt):
            f_star = m.resolved_frequency(0.1 * dtj, SMALL)
            assert got[i, j] == pytest.approx(f_star * 2.3 / ri, rel=1e-14)
    assert isinstance(m.mrtd_cycles(1000.0, 2.3, 2.0, 0.5, SMALL), np.floating)


def test_mrtd_cycles_nan_and_inf():
    got = m.mrtd_cycles(
        np.array([np.nan, 1000.0, 1000.0, 1000.0, np.inf]),
        2.3,
        np.array([2.0, np.nan, 2.0, np.inf, 2.0]),
        np.array([0.5, 0.5, np.nan, 0.5, 0.5]),
        SMALL,
    )
    np.testing.assert_array_equal(got[:3], [np.nan, np.nan, np.nan])
    assert got[3] == pytest.approx(1500.0 * 2.3 / 1000.0)
    assert got[4] == 0.0
    assert np.isnan(m.mrtd_cycles(float("nan"), 2.3, 2.0, 0.5, SMALL))  # a scalar NaN too


def test_mrtd_cycles_rejects_bad_inputs_naming_them():
    with pytest.raises(ValueError, match=r"range must be > 0 m, got -5"):
        m.mrtd_cycles(-5.0, 2.3, 2.0, 0.5, SMALL)
    with pytest.raises(ValueError, match=r"range must be > 0 m, got 0"):
        m.mrtd_cycles(np.array([100.0, 0.0, np.nan]), 2.3, 2.0, 0.5, SMALL)
    with pytest.raises(ValueError, match="critical_dimension must be > 0 m"):
        m.mrtd_cycles(100.0, 0.0, 2.0, 0.5, SMALL)
    with pytest.raises(ValueError, match=r"transmittance must be in \[0, 1\], got 1.5"):
        m.mrtd_cycles(100.0, 2.3, 2.0, 1.5, SMALL)
    with pytest.raises(ValueError, match="frequency must be >= 0 cycles/rad"):
        m.mrtd(-1.0, SMALL)
    with pytest.raises(TypeError, match="curve must be an MrtdCurve"):
        m.mrtd_cycles(100.0, 2.3, 2.0, 0.5, [(500.0, 0.05), (1000.0, 0.1)])


@given(
    r1=st.floats(min_value=1.0, max_value=5e4),
    r2=st.floats(min_value=1.0, max_value=5e4),
    gamma=st.floats(min_value=0.0, max_value=2e-3),
    delta_t=st.floats(min_value=0.0, max_value=10.0),
)
def test_cycles_do_not_increase_with_range(r1, r2, gamma, delta_t):
    near, far = min(r1, r2), max(r1, r2)
    curve = m.MrtdCurve.example()
    n_near = m.mrtd_cycles(near, 2.3, delta_t, math.exp(-gamma * near), curve)
    n_far = m.mrtd_cycles(far, 2.3, delta_t, math.exp(-gamma * far), curve)
    assert n_far <= n_near * (1 + 1e-12)


@given(
    dt1=st.floats(min_value=-10.0, max_value=10.0),
    dt2=st.floats(min_value=-10.0, max_value=10.0),
    tau=st.floats(min_value=0.0, max_value=1.0),
)
def test_cycles_do_not_decrease_with_the_temperature_difference(dt1, dt2, tau):
    small, large = sorted((abs(dt1), abs(dt2)))
    curve = m.MrtdCurve.example()
    assert m.mrtd_cycles(1500.0, 2.3, small, tau, curve) <= m.mrtd_cycles(
        1500.0, 2.3, large, tau, curve
    ) * (1 + 1e-12)


def test_cycles_are_continuous_in_range_across_the_cut_off():
    # With τ = exp(−γR), τΔT crosses the last MRTD at R* = ln(ΔT / M_n) / γ.
    curve = m.MrtdCurve.example()
    gamma, delta_t = 1e-3, 2.0
    r_star = math.log(delta_t / curve.mrtd[-1]) / gamma
    r = np.array([r_star * (1 - 1e-9), r_star, r_star * (1 + 1e-9)])
    n = m.mrtd_cycles(r, 2.3, delta_t, np.exp(-gamma * r), curve)
    np.testing.assert_allclose(n, n[1], rtol=1e-6)


# --------------------------------------------------------------------------------------------
# MrtdCurve and the bench file


def test_curve_validation_names_the_column_and_row():
    with pytest.raises(ValueError, match="'frequency' must be strictly ascending: row 3"):
        m.MrtdCurve(frequency=(1.0, 2.0, 2.0), mrtd=(0.1, 0.2, 0.3))
    with pytest.raises(ValueError, match="'mrtd' must be non-decreasing in frequency: row 2"):
        m.MrtdCurve(frequency=(1.0, 2.0), mrtd=(0.2, 0.1))
    with pytest.raises(ValueError, match=r"'mrtd' must be finite and > 0 K, row 1 is -0\.1"):
        m.MrtdCurve(frequency=(1.0, 2.0), mrtd=(-0.1, 0.1))
    with pytest.raises(ValueError, match="'frequency' must be finite and > 0 cycles/rad, row 2"):
        m.MrtdCurve(frequency=(1.0, math.nan), mrtd=(0.1, 0.2))
    with pytest.raises(ValueError, match="at least 2 rows"):
        m.MrtdCurve(frequency=(1.0,), mrtd=(0.1,))
    with pytest.raises(ValueError, match="same length"):
        m.MrtdCurve(frequency=(1.0, 2.0), mrtd=(0.1,))


def test_from_csv_converts_cycles_per_mrad_and_keeps_the_comments(tmp_path):
    path = tmp_path / "bench.csv"
    path.write_text(
        "# Bench: camera X, 2024-05-01\n"
        "\n"
        "Frequency , MRTD, observer\n"
        "0.25, 0.04, A\n"
        "# a comment between rows\n"
        "0.5,0.06,A\n"
        "1.0,0.2,B\n"
    )
    curve = m.MrtdCurve.from_csv(path)
    assert curve.frequency == (250.0, 500.0, 1000.0)
    assert curve.mrtd == (0.04, 0.06, 0.2)
    assert "Bench: camera X" in curve.provenance
    assert str(path) in curve.provenance


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("frequency,temp\n0.5,0.1\n1,0.2\n", r"line 1: missing column 'mrtd' \[K\]"),
        ("# c\nmrtd\n0.1\n0.2\n", r"line 2: missing column 'frequency' \[cycles/mrad\]"),
        ("frequency,mrtd\n0.5,0.1\n1.0,abc\n", r"line 3: column 'mrtd': 'abc' is not a number"),
        ("frequency,mrtd\n0.5,0.1\n0.4,0.2\n", r"line 3: column 'frequency' must be strictly"),
        ("frequency,mrtd\n0.5,0.1\n0.5,0.2\n", r"line 3: .* not above 0.5 on line 2"),
        ("frequency,mrtd\n0.5,-0.1\n1.0,0.2\n", r"line 2: column 'mrtd' must be a finite number"),
        ("frequency,mrtd\n-0.5,0.1\n1.0,0.2\n", r"line 2: column 'frequency' must be a finite"),
        ("frequency,mrtd\n0.5,0.3\n1.0,0.2\n", r"line 3: column 'mrtd' must be non-decreasing"),
        ("frequency,mrtd\n0.5,0.1\n1.0,0.2,7\n", r"line 3: 3 cells, but the header on line 1"),
        ("frequency,mrtd\n0.5,0.1\n", r"needs at least 2 data rows .*found 1"),
        ("# only comments\n", r"no header line"),
        ("frequency,mrtd\n0.5,nan\n1.0,0.2\n", r"line 2: column 'mrtd' must be a finite number"),
    ],
)
def test_from_csv_errors_name_the_file_and_line(tmp_path, text, message):
    path = tmp_path / "bench.csv"
    path.write_text(text)
    with pytest.raises(ValueError, match=message) as info:
        m.MrtdCurve.from_csv(path)
    assert str(path) in str(info.value)


def test_from_parametric_samples_the_formula():
    f = [300.0, 900.0, 1400.0]
    curve = m.MrtdCurve.from_parametric(f, **CAMERA)
    assert curve.frequency == tuple(f)
    np.testing.assert_allclose(curve.mrtd, m.parametric_mrtd(np.array(f), **CAMERA), rtol=0)
    assert "netd=0.05" in curve.provenance
    with pytest.raises(ValueError, match="first zero of the system MTF"):
        m.MrtdCurve.from_parametric([1000.0, 3000.0], **CAMERA)


def test_bundled_example_is_the_formula_for_the_stated_camera():
    curve = m.MrtdCurve.example()
    assert 8 <= len(curve.frequency) <= 15
    assert curve.cutoff < 1 / (2 * CAMERA["ifov"])  # below the Nyquist frequency
    regenerated = m.parametric_mrtd(np.asarray(curve.frequency), **CAMERA)
    np.testing.assert_allclose(curve.mrtd, regenerated, rtol=6e-6)  # printed to 6 digits
    provenance = load_table("example_mrtd").provenance
    assert "NOT a measurement" in provenance
    for stated in ("640 x 512", "17 um", "50 mm f/1.0", "NETD 50 mK", "10 um", "Source"):
        assert stated in provenance


# --------------------------------------------------------------------------------------------
# Other array namespaces


def test_kernels_under_array_api_strict():
    r = [100.0, 1000.0, 3000.0, float("nan")]
    strict = m.mrtd_cycles(xps.asarray(r, dtype=xps.float64), 2.3, 2.0, 0.3, SMALL)
    assert type(strict).__module__.startswith("array_api_strict")
    np.testing.assert_allclose(
        np.asarray(strict), m.mrtd_cycles(np.asarray(r), 2.3, 2.0, 0.3, SMALL), equal_nan=True
    )
    f = [0.0, 250.0, 1000.0, 1600.0]
    np.testing.assert_allclose(
        np.asarray(m.mrtd(xps.asarray(f, dtype=xps.float64), SMALL)), m.mrtd(np.asarray(f), SMALL)
    )
    strict_mrtd = m.parametric_mrtd(xps.asarray(f, dtype=xps.float64), **CAMERA)
    np.testing.assert_allclose(np.asarray(strict_mrtd), m.parametric_mrtd(np.asarray(f), **CAMERA))


def test_mrtd_cycles_under_jax_jit():
    jax = pytest.importorskip("jax")
    jax.config.update("jax_enable_x64", True)
    jnp = pytest.importorskip("jax.numpy")
    curve = m.MrtdCurve.example()
    r = np.array([300.0, 2000.0, 8000.0])

    def cycles(r):
        return m.mrtd_cycles(r, 2.3, 2.0, jnp.exp(-2e-4 * r), curve)

    got = jax.jit(cycles)(jnp.asarray(r))
    expected = m.mrtd_cycles(r, 2.3, 2.0, np.exp(-2e-4 * r), curve)
    np.testing.assert_allclose(np.asarray(got), expected, rtol=1e-12)
