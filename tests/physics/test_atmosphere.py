"""Atmosphere: Beer–Lambert (7.1)–(7.4), Tables 7.1–7.2, segments, SNR (7.5)–(7.7)."""

import math

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

import targetacq as ta
from targetacq.physics import atmosphere
from targetacq.physics.bands import band_limits

# Table 7.1, Sonesson (2004) p. 42, Np/km: (obscurant, band) → (low, high).
TABLE_7_1 = {
    ("gases", "visible"): (0.02, 0.02),
    ("gases", "mwir"): (0.25, 0.73),
    ("gases", "lwir"): (0.03, 0.8),
    ("haze", "visible"): (0.2, 2.0),
    ("haze", "mwir"): (0.02, 1.0),
    ("haze", "lwir"): (0.02, 0.4),
    ("fog", "visible"): (2.0, 20),
    ("fog", "mwir"): (1.0, 20),
    ("fog", "lwir"): (0.4, 20),
    ("rain", "visible"): (0.3, 1.6),
    ("rain", "mwir"): (0.3, 1.6),
    ("rain", "lwir"): (0.3, 1.6),
    ("snow", "visible"): (2.0, 12),
    ("snow", "mwir"): (2.0, 12),
    ("snow", "lwir"): (2.0, 12),
    ("dust", "visible"): (0.2, 4.0),
    ("dust", "mwir"): (0.2, 4.0),
    ("dust", "lwir"): (0.2, 4.0),
}


def test_table_7_1():
    for (obscurant, band), (low, high) in TABLE_7_1.items():
        assert atmosphere.obscurant_extinction(obscurant, band, "low") == pytest.approx(low / 1000)
        assert atmosphere.obscurant_extinction(obscurant, band, "high") == pytest.approx(
            high / 1000
        )
        nominal = atmosphere.obscurant_extinction(obscurant, band)
        assert nominal == pytest.approx(math.sqrt(low * high) / 1000)


def test_a_band_inside_a_table_band_reads_its_cell():
    for (obscurant, band), (low, high) in TABLE_7_1.items():
        lo, hi = band_limits(band)
        inside = (lo + 0.25 * (hi - lo), hi - 0.25 * (hi - lo))
        assert atmosphere.obscurant_extinction(obscurant, inside, "low") == pytest.approx(low / 1e3)
        assert atmosphere.obscurant_extinction(obscurant, inside, "high") == pytest.approx(
            high / 1e3
        )


def test_a_short_wave_band_interpolates_log_log_between_visible_and_mid_wave():
    # By hand: the SWIR band 0.9-2.5 um has its centre at 1.7 um; the visible cell stands at
    # 0.55 um, the mid-wave one at 4 um; each cell end is interpolated in log(gamma) against
    # log(wavelength).
    w = math.log(1.7 / 0.55) / math.log(4.0 / 0.55)
    for obscurant in atmosphere.OBSCURANTS:
        vis, mid = TABLE_7_1[obscurant, "visible"], TABLE_7_1[obscurant, "mwir"]
        for k, level in enumerate(("low", "high")):
            expected = vis[k] ** (1 - w) * mid[k] ** w / 1e3
            got = atmosphere.obscurant_extinction(obscurant, (0.9e-6, 2.5e-6), level)
            assert got == pytest.approx(expected, rel=1e-12)
            assert min(vis[k], mid[k]) / 1e3 <= got <= max(vis[k], mid[k]) / 1e3


@given(st.floats(0.7, 2.9), st.floats(0.01, 1.0))
def test_interpolated_haze_falls_with_wavelength(centre_um, shift_um):
    # Table 7.1's haze cells fall from the visible to the mid-wave IR: so must the interpolation.
    def haze(c):
        return atmosphere.obscurant_extinction("haze", ((c - 0.05) * 1e-6, (c + 0.05) * 1e-6))

    assume(centre_um + shift_um <= 2.9)
    assert haze(centre_um + shift_um) <= haze(centre_um)


def test_a_band_across_the_water_vapour_absorption_is_refused():
    with pytest.raises(ValueError, match=r"Table 7.1 gives the bands .* got 5-8 um"):
        atmosphere.obscurant_extinction("haze", (5e-6, 8e-6))
    with pytest.raises(ValueError, match="got 10-14 um"):  # beyond the long-wave band
        atmosphere.obscurant_extinction("haze", (10e-6, 14e-6))


@pytest.mark.parametrize(
    ("np_per_km", "term", "visual"),
    [  # Table 7.2
        (0.05, "very low", "> 30 km, very clear"),
        (0.3, "low", "6 - 30 km, clear to hazy"),
        (1.0, "medium", "2 - 6 km, hazy"),
        (5.0, "high", "< 2 km, foggy"),
        (0.1, "low", "6 - 30 km, clear to hazy"),
    ],
)
def test_table_7_2_terms(np_per_km, term, visual):
    assert atmosphere.extinction_term(np_per_km / 1000) == (term, visual)


def test_beer_lambert():
    assert ta.transmittance(0.4e-3, 0.0) == 1.0  # τ(0) = 1
    assert ta.transmittance(0.4e-3, 2500.0) == pytest.approx(math.exp(-1.0))  # (7.3)


@given(st.lists(st.tuples(st.floats(0, 1e-2), st.floats(0, 1e4)), min_size=1, max_size=6))
def test_path_through_segments_is_the_product(segments):
    gammas = np.array([g for g, _ in segments])
    lengths = np.array([r for _, r in segments])
    product = np.prod([ta.transmittance(g, r) for g, r in segments])
    assert atmosphere.path_transmittance(gammas, lengths) == pytest.approx(
        product, rel=1e-12, abs=1e-300
    )


def test_local_cloud_over_part_of_the_path():
    tau = atmosphere.cloud_transmittance(0.2e-3, 3000.0, 5e-3, 50.0)
    assert tau == pytest.approx(math.exp(-0.2e-3 * 3000) * math.exp(-5e-3 * 50))
    # A cloud longer than the path covers only the path.
    assert atmosphere.cloud_transmittance(0.0, 10.0, 1e-2, 100.0) == pytest.approx(math.exp(-0.1))


def test_band_mean_transmittance_eq_7_4():
    lam = np.linspace(8e-6, 12e-6, 4001)
    flat = np.full_like(lam, 0.3e-3)
    assert atmosphere.band_transmittance(flat, lam, 2000.0) == pytest.approx(
        ta.transmittance(0.3e-3, 2000.0)
    )
    # γ linear in λ from a to b: the mean of exp(−γR) is (e^{−aR} − e^{−bR}) / ((b − a) R).
    a, b, r = 0.1e-3, 0.9e-3, 3000.0
    linear = a + (b - a) * (lam - lam[0]) / (lam[-1] - lam[0])
    exact = (math.exp(-a * r) - math.exp(-b * r)) / ((b - a) * r)
    assert atmosphere.band_transmittance(linear, lam, r) == pytest.approx(exact, rel=1e-6)


def test_snr_from_transmittance_eqs_7_6_7_7():
    assert ta.snr_from_transmittance(0.5) == pytest.approx(0.0, abs=1e-14)
    assert ta.snr_from_transmittance(1.0) == math.inf
    assert ta.snr_from_transmittance(0.0) == -math.inf
    gamma, r = 0.3e-3, 1500.0
    tau = ta.transmittance(gamma, r)
    assert ta.snr_from_transmittance(tau) == pytest.approx(
        -20 * math.log10(math.exp(gamma * r) - 1)
    )


def test_db_per_km_erratum():
    # 1 dB/km = 0.2303 Np/km (erratum to §7.4's "Np/km = 0.23 dB/km", see the user guide).
    assert atmosphere.db_per_km_to_np_per_km(1.0) == pytest.approx(0.2303, abs=5e-5)
    assert atmosphere.np_per_km_to_db_per_km(1.0) == pytest.approx(4.343, abs=5e-4)
    assert atmosphere.np_per_km_to_db_per_km(
        atmosphere.db_per_km_to_np_per_km(7.0)
    ) == pytest.approx(7.0)


def test_visibility_conventions():
    assert ta.extinction_from_visibility(10e3, convention="koschmieder") == pytest.approx(
        3.912e-4, abs=5e-8
    )
    assert ta.extinction_from_visibility(10e3, convention="mor") == pytest.approx(
        2.996e-4, abs=5e-8
    )
    assert atmosphere.visibility_from_extinction(3.912e-4, "koschmieder") == pytest.approx(
        10e3, rel=1e-4
    )
    with pytest.raises(ValueError, match="needs its convention"):
        ta.extinction_from_visibility(10e3)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: ta.transmittance(-1e-3, 100.0), "extinction must be >= 0"),
        (lambda: ta.transmittance(1e-3, -100.0), "range must be >= 0"),
        (lambda: atmosphere.obscurant_extinction("smoke", "lwir"), "unknown obscurant 'smoke'"),
        (lambda: atmosphere.obscurant_extinction("fog", "swir"), "unknown band"),
        (lambda: atmosphere.obscurant_extinction("fog", "lwir", "max"), "level must be one of"),
        (lambda: ta.extinction_from_visibility(1e3, convention="wmo"), "convention must be one of"),
        (lambda: ta.snr_from_transmittance(1.5), r"tau must be in \[0, 1\]"),
        (lambda: atmosphere.extinction_term(-1.0), "extinction must be >= 0"),
    ],
)
def test_bad_atmosphere_input(call, match):
    with pytest.raises(ValueError, match=match):
        call()


@given(st.floats(0.0, 50.0))
def test_snr_from_optical_depth_equals_snr_from_transmittance(depth):
    # Where 1 − τ is well conditioned (d > 1e-6: 1 − τ keeps 10 digits); below that the
    # transmittance form loses digits to cancellation and the depth form is the accurate one.
    assume(depth > 1e-6)
    tau = math.exp(-depth)
    assert atmosphere.snr_from_optical_depth(depth) == pytest.approx(
        ta.snr_from_transmittance(tau), rel=1e-9, abs=1e-9
    )
    assert atmosphere.snr_from_optical_depth(0.0) == math.inf
    assert atmosphere.snr_from_optical_depth(math.inf) == -math.inf


def test_snr_from_a_tiny_optical_depth():
    # −20 log10(e^d − 1) = −20 log10(d (1 + d/2 + ...)) → 240 dB at d = 1e-12.
    d = 1e-12
    assert atmosphere.snr_from_optical_depth(d) == pytest.approx(
        -20 * math.log10(d + d * d / 2), rel=1e-12
    )


def test_foliage_is_a_transmittance_that_lowers_the_probabilities():
    assert atmosphere.foliage_transmittance(0.0, 0.5) == 1.0
    assert atmosphere.foliage_transmittance(4.0, 0.25) == pytest.approx(math.exp(-1.0))
    open_field = ta.scene_acquisition(
        1500.0, ta.RangeCase(2.3, 2e-4, extinction=1e-4), ta.Scene("lwir", 305.0, 295.0)
    )
    in_forest = ta.scene_acquisition(
        1500.0,
        ta.RangeCase(
            2.3, 2e-4, extinction=1e-4, foliage=atmosphere.foliage_transmittance(4.0, 0.25)
        ),
        ta.Scene("lwir", 305.0, 295.0),
    )
    assert in_forest.transmittance == pytest.approx(open_field.transmittance * math.exp(-1.0))
    assert in_forest.detection < open_field.detection
    with pytest.raises(ValueError, match="depth must be >= 0"):
        atmosphere.foliage_transmittance(-1.0, 0.1)
