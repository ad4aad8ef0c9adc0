"""Range cases (core/cases.py): the record's checks, the one evaluation of a case at ranges, and
the front-ends that build cases (dri_ranges, range_performance, ModelChain.range_cases)."""

import math
from pathlib import Path

import numpy as np
import pytest

import targetacq as ta
from targetacq.acquisition.criteria import Criterion
from targetacq.core.cases import (
    CaseAcquisition,
    RangeCase,
    case_acquisition,
    case_factors,
    case_probability,
)
from targetacq.core.ranges import as_range_case, case_ranges, range_performance
from targetacq.run.model_chain import ModelChain
from targetacq.scenario.schema import load_scenario

EXAMPLES = Path(__file__).parents[2] / "examples"


def _ttpf(x):
    """TTPF by hand: P = x^E / (1 + x^E), E = 2.7 + 0.7 x, x = N / N50 (NVESD)."""
    e = 2.7 + 0.7 * x
    return x**e / (1 + x**e)


# --- the record ----------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"critical_dimension": 0.0}, r"critical_dimension must be > 0 m"),
        ({"ifov": -1e-4}, r"ifov must be > 0 rad"),
        ({"cycle": 0.0}, r"cycle must be > 0 rad"),
        ({"cycle": 4e-4, "blur_sigma": 1e-5}, r"give the cycle or the optics limits \(blur_sigma"),
        ({"wavelength": 10e-6}, "both wavelength and aperture"),
        ({"wavelength": 10e-6, "aperture": -0.1}, r"aperture must be > 0 m"),
        ({"blur_sigma": -1e-5}, r"blur_sigma must be >= 0 rad"),
        ({"extinction": -1e-3}, r"extinction must be >= 0 Np/m"),
        ({"foliage": 1.2}, r"foliage must be in \[0, 1\]"),
        ({"scr": -1.0}, "scr must be >= 0"),
        ({"region": "dense"}, "region must be one of low, medium, high"),
        ({"scr": 2.0, "region": "low"}, "either scr or region"),
        ({"criterion": "jonson"}, "unknown criterion"),
        ({"transform": "tpf"}, "unknown transform"),
        ({"options": {"bound": "nominal"}}, r"transform 'ttpf' takes no option\(s\) bound"),
        (
            {"transform": "schmieder-weathersby", "criterion": {"recognition": 4.0}},
            "covers none of criterion",
        ),
        ({"noise_model": "loud"}, "unknown noise model"),
        ({"criterion": "en62676-4", "scr": 3.0}, "scr do not apply"),
    ],
)
def test_bad_case_names_the_field_and_its_range(kwargs, match):
    given = {"critical_dimension": 2.3, "ifov": 2e-4, **kwargs}
    with pytest.raises(ValueError, match=match):
        RangeCase(**given)


def test_case_resolves_its_criterion_and_copies_its_options():
    options = {"bound": "pessimistic"}
    case = RangeCase(2.3, 2e-4, criterion="johnson", transform="c2nveo", options=options)
    assert isinstance(case.criterion, Criterion) and case.criterion.name == "johnson"
    options["bound"] = "optimistic"
    assert case.options == {"bound": "pessimistic"}
    assert not case.attenuates and not case.in_clutter
    assert RangeCase(2.3, 2e-4, foliage=0.5).attenuates
    assert RangeCase(2.3, 2e-4, moving=True).in_clutter


def test_cycle_angle_is_the_coarser_limit():
    # Diffraction at 10 µm through 20 mm: asin(1.22 · 10e-6 / 0.02) = 0.61 mrad > 2 · 0.2 mrad.
    diffraction = math.asin(1.22 * 10e-6 / 0.02)
    assert RangeCase(2.3, 2e-4, wavelength=10e-6, aperture=0.02).cycle_angle == pytest.approx(
        diffraction, rel=1e-12
    )
    assert RangeCase(2.3, 2e-4).cycle_angle == pytest.approx(4e-4, rel=1e-15)
    assert RangeCase(2.3, 2e-4, cycle=5e-4).cycle_angle == 5e-4


# --- the evaluation ------------------------------------------------------------------------------


def test_case_equals_the_formulas_by_hand():
    r = np.array([400.0, 1500.0, 6000.0])
    d, ifov, gamma, foliage = 2.3, 2e-4, 0.6e-3, 0.8
    case = RangeCase(d, ifov, extinction=gamma, foliage=foliage, scr=4.0)
    got = case_acquisition(case, r)
    assert isinstance(got, CaseAcquisition)
    n = d / (r * 2 * ifov)  # Fig. 3.3: one cycle is two pixels
    tau = np.exp(-gamma * r) * foliage  # Eq. (7.3), foliage in series
    snr = 20 * np.log10(tau / (1 - tau))  # Eq. (7.7)
    np.testing.assert_allclose(got.cycles, n, rtol=1e-14)
    np.testing.assert_allclose(got.transmittance, tau, rtol=1e-14)
    np.testing.assert_allclose(got.snr, snr, rtol=1e-12)
    acq = ta.acquisition_probabilities(n, clutter=ta.Clutter(scr=4.0), snr=snr)
    for task in ("detection", "recognition", "identification"):
        np.testing.assert_allclose(getattr(got, task), getattr(acq, task), rtol=1e-12)


def test_clear_case_is_the_ttpf_by_hand():
    r = np.array([300.0, 900.0, 2500.0, 7000.0])
    got = case_acquisition(RangeCase(2.3, 2e-4), r)
    x = 2.3 / (r * 4e-4)
    np.testing.assert_allclose(got.detection, _ttpf(x / 1.0), rtol=1e-12)
    np.testing.assert_allclose(got.recognition, _ttpf(x / 4.0), rtol=1e-12)
    np.testing.assert_allclose(got.identification, _ttpf(x / 6.4), rtol=1e-12)
    assert np.all(np.isinf(got.snr)) and np.all(got.transmittance == 1.0)


def test_given_cycle_sets_the_cycles():
    r = np.array([500.0, 2000.0])
    got = case_factors(RangeCase(2.3, 2e-4, cycle=7e-4), r)[0]
    np.testing.assert_allclose(got, 2.3 / (r * 7e-4), rtol=1e-15)


def test_zero_extinction_adds_no_noise():
    r = np.linspace(100.0, 9000.0, 40)
    clear = case_acquisition(RangeCase(2.3, 2e-4), r)
    zero = case_acquisition(RangeCase(2.3, 2e-4, extinction=0.0), r)
    for task in ("detection", "recognition", "identification"):
        np.testing.assert_array_equal(getattr(zero, task), getattr(clear, task))


def test_case_probability_is_the_marginal_curve():
    r = np.array([700.0, 1800.0])
    case = RangeCase(2.3, 2e-4, extinction=1e-3)
    n, _, snr = case_factors(case, r)
    for task in ("detection", "orientation", "recognition", "identification"):
        np.testing.assert_allclose(
            case_probability(case, r, task), ta.probability(n, task, snr=snr), rtol=1e-15
        )


def test_detection_alone_with_schmieder_weathersby():
    case = RangeCase(2.3, 2e-4, transform="schmieder-weathersby", region="high")
    # Table 3.5, high clutter: P = 0.5 at 2.5 cycles, so at R = d / (2.5 · 2 IFOV).
    r50 = 2.3 / (2.5 * 4e-4)
    assert case_probability(case, r50, "detection") == pytest.approx(0.5, abs=1e-12)
    with pytest.raises(ValueError, match="covers detection only"):
        case_acquisition(case, r50)


# --- the range solver on cases -------------------------------------------------------------------


def test_ranges_of_a_case_are_where_its_curves_cross():
    case = RangeCase(2.3, 2e-4, extinction=0.8e-3, foliage=0.9, scr=3.0, noise_model="variance-sum")
    found = case_ranges(case, 0.7, tolerance=1e-9)
    for task in ("detection", "recognition", "identification"):
        r = found[task]
        assert getattr(case_acquisition(case, r), task) >= 0.7 - 1e-12
        assert getattr(case_acquisition(case, r * (1 + 2e-9)), task) < 0.7


def test_dri_ranges_of_a_mapping_is_case_ranges_of_its_case():
    kwargs = {"extinction": 1e-3, "scr": 2.0, "wavelength": 10e-6, "aperture": 0.03}
    by_args = ta.dri_ranges({"critical_dimension": 2.3, "ifov": 2e-4, **kwargs}, 0.6)
    by_case = case_ranges(RangeCase(2.3, 2e-4, **kwargs), 0.6)
    assert by_args == by_case


def test_pixel_density_case_ranges():
    found = case_ranges(RangeCase(2.3, 2e-4, criterion="en62676-4"))
    assert found["identification"] == pytest.approx(1 / (250 * 2e-4))  # 250 px/m


def test_tolerance_out_of_range():
    with pytest.raises(ValueError, match=r"tolerance must be in \(0, 0.01\)"):
        case_ranges(RangeCase(2.3, 2e-4), 0.5, tolerance=0.1)


# --- range_performance takes cases ---------------------------------------------------------------


def test_range_performance_of_cases_equals_that_of_mappings():
    grid = np.linspace(50.0, 6000.0, 60)
    mapping = {"critical_dimension": 2.3, "ifov": 2e-4, "extinction": 0.4e-3, "scr": 3.0}
    as_dict = range_performance(grid, {"haze": mapping}, [0.5, 0.9])
    as_case = range_performance(grid, {"haze": RangeCase(**mapping)}, [0.5, 0.9])
    assert as_case.curves.identical(as_dict.curves)
    assert as_case.dri.equals(as_dict.dri)
    assert isinstance(as_dict.cases["haze"], RangeCase)
    direct = case_acquisition(RangeCase(**mapping), grid)
    np.testing.assert_array_equal(as_case.curves["detection"].sel(case="haze"), direct.detection)


def test_as_range_case_keeps_cases_and_names_bad_keys():
    case = RangeCase(2.3, 2e-4)
    assert as_range_case("a", case) is case
    with pytest.raises(ValueError, match=r"'hotspot' \(did you mean 'hot_spot'\?\)"):
        as_range_case("a", {"critical_dimension": 2.3, "ifov": 2e-4, "hotspot": True})


def test_old_case_probabilities_still_answer():
    n, tau, _, acq = ta.core.ranges.case_probabilities(
        np.array([1000.0]), {"critical_dimension": 2.3, "ifov": 2e-4, "extinction": 1e-3}
    )
    assert n[0] == pytest.approx(2.3 / (1000.0 * 4e-4))
    assert tau[0] == pytest.approx(math.exp(-1.0))
    assert acq.detection[0] < _ttpf(n[0])  # the haze's noise lowers it


# --- ModelChain.range_cases ----------------------------------------------------------------------


def test_scenario_range_cases_come_from_the_compiled_scenario():
    chain = ModelChain(load_scenario(EXAMPLES / "two_sensors_fused.toml"))
    cases = chain.range_cases()
    assert set(cases) == {"tv → truck", "tv → soldier", "thermal → truck", "thermal → soldier"}
    thermal = cases["thermal → soldier"]
    # 12 µm / 100 mm pixels, diffraction of 100 mm at the LWIR centre (10 µm): sampling-limited.
    assert thermal.ifov == pytest.approx(12e-6 / 0.1, rel=1e-12)
    assert thermal.cycle_angle == pytest.approx(max(2 * 12e-6 / 0.1, math.asin(1.22e-4)))
    # Table 7.1, haze in the LWIR band, nominal (the geometric mean of the cell), in Np/m.
    assert thermal.extinction == pytest.approx(ta.obscurant_extinction("haze", "lwir"))
    assert thermal.region == "medium" and thermal.scr is None
    assert thermal.criterion.name == "johnson-soldier-standing"
    assert cases["tv → truck"].criterion.name == "johnson"


def test_scenario_range_case_at_the_pair_range_is_the_chain():
    # Without segments or clouds, a pair's range case at the pair's own range gives the
    # probabilities of the chain at that time (at 40 s every pair is in view).
    chain = ModelChain(load_scenario(EXAMPLES / "two_sensors_fused.toml"))
    ds = chain.evaluate([40.0]).dataset
    for label, case in chain.range_cases(40.0).items():
        sensor, target = label.split(" → ")
        pair = ds.sel(sensor=sensor, target=target, time=40.0)
        assert bool(pair["in_view"])
        got = case_acquisition(case, float(pair["range"]))
        for task in ("detection", "recognition", "identification"):
            assert getattr(got, task) == pytest.approx(float(pair[task]), rel=1e-9, abs=1e-15)
