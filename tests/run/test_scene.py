"""scene_acquisition: physics to probabilities adds nothing of its own."""

import math

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

import targetacq as ta
from targetacq.physics import radiometry
from targetacq.run.scene import scene_signature


def test_scene_equals_the_chain_of_lower_level_functions():
    r = np.array([500.0, 2000.0, 5000.0])
    d, ifov, gamma = 2.3, 2.27e-4, 0.3e-3
    got = ta.scene_acquisition(
        r,
        ta.RangeCase(d, ifov, extinction=gamma),
        ta.Scene(
            "lwir", 305.0, 295.0, target_emissivity=0.9, background_emissivity=0.8, clutter_std=2.0
        ),
    )
    n = ta.cycles_on_target(d, r, ifov)
    m_t = 0.9 * ta.band_exitance(305.0, "lwir")
    m_b = 0.8 * ta.band_exitance(295.0, "lwir")
    clutter = 0.8 * radiometry.band_exitance_derivative(295.0, "lwir") * 2.0  # ε_b dM/dT σ_T
    scr = ta.signal_to_clutter_ratio(m_t, m_b, clutter)
    snr = ta.snr_from_transmittance(ta.transmittance(gamma, r))
    acq = ta.acquisition_probabilities(n, clutter=ta.Clutter(scr=scr), snr=snr)
    np.testing.assert_allclose(got.cycles, n)
    np.testing.assert_allclose(got.contrast, abs(m_t - m_b))
    np.testing.assert_allclose(got.scr, scr)
    np.testing.assert_allclose(got.snr, snr)
    for task in ("detection", "recognition", "identification", "effect"):
        np.testing.assert_allclose(getattr(got, task), getattr(acq, task))


def test_clutter_std_is_a_temperature_spread_in_kelvin():
    # The exitance spread of a ±σ_T spread of the background temperature, by a central difference
    # of the band exitance (independent of band_exitance_derivative): ε_b · ΔM/ΔT · σ_T.
    eps_b, t_b, sigma_t, h = 0.85, 290.0, 1.5, 1e-3
    slope = (ta.band_exitance(t_b + h, "mwir") - ta.band_exitance(t_b - h, "mwir")) / (2 * h)
    contrast = abs(ta.band_exitance(300.0, "mwir") - eps_b * ta.band_exitance(t_b, "mwir"))
    case = ta.RangeCase(2.3, 2e-4)
    scene = ("mwir", 300.0, t_b)
    got = ta.scene_acquisition(
        1000.0, case, ta.Scene(*scene, background_emissivity=eps_b, clutter_std=sigma_t)
    )
    assert got.scr == pytest.approx(contrast / (eps_b * slope * sigma_t), rel=1e-6)
    # The same clutter given in W/m² gives the same SCR.
    spread = eps_b * slope * sigma_t
    same = ta.scene_acquisition(
        1000.0,
        case,
        ta.Scene(*scene, background_emissivity=eps_b, clutter_exitance_std=spread),
    )
    assert same.scr == pytest.approx(got.scr, rel=1e-6)


def test_scene_signature_by_hand():
    seen = scene_signature(
        "lwir", 305.0, 295.0, target_emissivity=0.9, background_emissivity=0.95, clutter_std=2.0
    )
    m_t = 0.9 * ta.band_exitance(305.0, "lwir")
    m_b = 0.95 * ta.band_exitance(295.0, "lwir")
    clutter = 0.95 * radiometry.band_exitance_derivative(295.0, "lwir") * 2.0
    assert seen.target == pytest.approx(m_t, rel=1e-15)
    assert seen.background == pytest.approx(m_b, rel=1e-15)
    assert seen.contrast == pytest.approx(abs(m_t - m_b), rel=1e-15)
    assert seen.clutter == pytest.approx(clutter, rel=1e-15)
    assert seen.scr == pytest.approx(abs(m_t - m_b) / clutter, rel=1e-15)
    plain = scene_signature("lwir", 305.0, 295.0)
    assert plain.clutter is None and plain.scr is None


def test_no_atmosphere_no_clutter_is_exactly_the_core_model():
    r = np.linspace(100.0, 8000.0, 50)
    got = ta.scene_acquisition(r, ta.RangeCase(2.3, 2e-4), ta.Scene("mwir", 310.0, 290.0))
    core = ta.acquisition_probabilities(ta.cycles_on_target(2.3, r, 2e-4))
    for task in ("detection", "recognition", "identification"):
        np.testing.assert_array_equal(getattr(got, task), getattr(core, task))


@given(st.floats(100, 2e4), st.floats(0, 5e-3), st.floats(0, 5e-3), st.floats(0.1, 20))
# A subnormal extinction: an SNR of thousands of dB, whose amplitude overflows to +inf (no noise)
# without a warning (found by Hypothesis once the SNR came from the optical depth).
@example(r=100.0, g1=0.0, g2=5e-324, clutter=1.0)
def test_non_increasing_in_extinction(r, g1, g2, clutter):
    low, high = sorted((g1, g2))
    a = ta.scene_acquisition(
        r,
        ta.RangeCase(2.3, 2e-4, extinction=low),
        ta.Scene("lwir", 300.0, 295.0, clutter_std=clutter),
    )
    b = ta.scene_acquisition(
        r,
        ta.RangeCase(2.3, 2e-4, extinction=high),
        ta.Scene("lwir", 300.0, 295.0, clutter_std=clutter),
    )
    for task in ("detection", "recognition", "identification"):
        assert getattr(b, task) <= getattr(a, task) + 1e-15


@given(st.floats(100, 2e4), st.floats(100, 2e4), st.floats(0, 3e-3), st.floats(0.1, 20))
def test_non_increasing_in_range(r1, r2, gamma, clutter):
    near, far = sorted((r1, r2))
    a = ta.scene_acquisition(
        near,
        ta.RangeCase(2.3, 2e-4, extinction=gamma),
        ta.Scene("lwir", 300.0, 295.0, clutter_std=clutter),
    )
    b = ta.scene_acquisition(
        far,
        ta.RangeCase(2.3, 2e-4, extinction=gamma),
        ta.Scene("lwir", 300.0, 295.0, clutter_std=clutter),
    )
    for task in ("detection", "recognition", "identification"):
        assert getattr(b, task) <= getattr(a, task) + 1e-15


def test_broadcasting_over_all_inputs():
    got = ta.scene_acquisition(
        np.array([1000.0, 2000.0])[:, None, None],
        ta.RangeCase(2.3, 2e-4, extinction=0.2e-3),
        ta.Scene(
            "lwir",
            np.array([300.0, 310.0])[None, :, None],
            295.0,
            clutter_std=np.array([0.5, 5.0, 50.0]),
        ),
    )
    for name in (
        "cycles",
        "contrast",
        "scr",
        "snr",
        "transmittance",
        "detection",
        "identification",
    ):
        assert np.shape(getattr(got, name)) == (2, 2, 3)


def test_visible_band_uses_reflected_light():
    e_sun = 500.0
    got = ta.scene_acquisition(
        1000.0,
        ta.RangeCase(2.3, 1e-4),
        ta.Scene(
            "visible",
            0.0,
            0.0,
            target_exitance=radiometry.reflected_exitance(0.75, e_sun),
            background_exitance=radiometry.reflected_exitance(0.1, e_sun),
            clutter_exitance_std=20.0,
        ),
    )
    assert got.contrast == pytest.approx(0.65 * e_sun)
    assert got.scr == pytest.approx(0.65 * e_sun / 20.0)


def test_contrast_below_quantisation_is_invisible():
    step = radiometry.quantisation_step(8, 255.0)  # 1 W/m² per level
    faint = ta.scene_acquisition(
        500.0, ta.RangeCase(2.3, 2e-4), ta.Scene("lwir", 300.1, 300.0), quantisation_step=step
    )
    assert faint.contrast < 1.0
    assert faint.detection == 0.0
    clear = ta.scene_acquisition(
        500.0, ta.RangeCase(2.3, 2e-4), ta.Scene("lwir", 310.0, 300.0), quantisation_step=step
    )
    assert clear.detection > 0.9


@pytest.mark.parametrize(
    ("case", "scene", "match"),
    [
        ({}, {"target_emissivity": 2.0}, r"target_emissivity must be in \[0, 1\]"),
        ({"extinction": -1e-3}, {}, "extinction must be >= 0"),
        ({"scr": 3.0}, {"clutter_std": 1.0}, "at most one of"),
        ({"region": "low"}, {"clutter_std": 1.0}, "at most one of"),
        ({}, {"clutter_std": 1.0, "clutter_exitance_std": 1.0}, "at most one of"),
        ({}, {"clutter_std": -1.0}, r"clutter_std must be >= 0 K"),
        ({}, {"clutter_exitance_std": -1.0}, "clutter_exitance_std must be >= 0"),
        ({"foliage": 1.5}, {}, r"foliage must be in \[0, 1\]"),
        ({}, {"background_exitance": 10.0, "clutter_std": 1.0}, "give clutter_exitance_std"),
        ({"contrast": 2.0, "noise_equivalent_contrast": 0.1}, {}, "the scene gives the contrast"),
        ({"target_area": 4.0}, {}, "target_area is used with the sensor's noise"),
    ],
)
def test_bad_scene_input(case, scene, match):
    with pytest.raises(ValueError, match=match):
        ta.scene_acquisition(
            1000.0, ta.RangeCase(2.3, 2e-4, **case), ta.Scene("lwir", 300.0, 290.0, **scene)
        )


def test_negative_temperature_is_an_error():
    with pytest.raises(ValueError, match=r"target_temperature must be in \[0, 10000\] K"):
        ta.scene_acquisition(1000.0, ta.RangeCase(2.3, 2e-4), ta.Scene("lwir", -3.0, 290.0))
    with pytest.raises(ValueError, match="background_temperature"):  # overflow, not a bad SCR
        ta.scene_acquisition(
            1000.0, ta.RangeCase(2.3, 2e-4), ta.Scene("lwir", 300.0, 1e300, clutter_std=2.0)
        )
    assert math.isfinite(
        ta.scene_acquisition(1000.0, ta.RangeCase(2.3, 2e-4), ta.Scene("lwir", 0.0, 290.0)).contrast
    )


def test_zero_contrast_with_a_netd_is_never_detected():
    # The case: a target at the background's temperature. Without the sensor's noise
    # the thesis's model detects it (only the atmosphere's noise, none here); with a NETD the
    # sensor's SNR is 0 and nothing is detected, at any range.
    ranges = np.geomspace(10.0, 1e5, 50)
    quiet = ta.scene_acquisition(ranges, ta.RangeCase(2.3, 2e-4), ta.Scene("lwir", 295.0, 295.0))
    noisy = ta.scene_acquisition(
        ranges, ta.RangeCase(2.3, 2e-4), ta.Scene("lwir", 295.0, 295.0), netd=0.05
    )
    assert quiet.detection[0] > 0.9
    assert np.all(noisy.detection < 0.01)


@pytest.mark.parametrize(
    ("case", "scene", "extra"),
    [
        ({}, {}, {}),  # no noise, no clutter: the contrast entered no factor (P = 0.99999 before)
        ({}, {}, {"quantisation_step": 0.1}),
        ({"scr": 5.0}, {}, {}),
        ({}, {}, {"netd": 0.05}),  # these two gave NaN probabilities already (not a NaN SNR or SCR)
        ({}, {"clutter_std": 2.0}, {}),
    ],
)
@pytest.mark.parametrize(
    "nan", [{"target_temperature": [305.0, np.nan]}, {"target_emissivity": [0.9, np.nan]}]
)
def test_a_nan_signature_gives_nan_out_without_noise_or_clutter(case, scene, extra, nan):
    range_case = ta.RangeCase(2.3, 2e-4, **case)
    base = {"band": "lwir", "target_temperature": 305.0, "background_temperature": 295.0, **scene}
    batch = ta.Scene(**{**base, **{k: np.array(v) for k, v in nan.items()}})
    found = ta.scene_acquisition(1000.0, range_case, batch, **extra)
    alone = ta.scene_acquisition(
        1000.0, range_case, ta.Scene(**{**base, **{k: v[0] for k, v in nan.items()}}), **extra
    )
    for name in ("detection", "recognition", "identification", "contrast", "snr", "scr"):
        values = getattr(found, name)
        assert np.isnan(values[1]), f"{name}: {values[1]} where the input is NaN"
        # the known row as computed alone (to rounding: a batch may round differently)
        np.testing.assert_allclose(values[0], getattr(alone, name), rtol=1e-14, err_msg=name)
