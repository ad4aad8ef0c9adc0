"""The report's 5–95 % bands: in the range performance, the figure and the HTML page."""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.collections import PolyCollection

from targetacq.core.cases import RangeCase
from targetacq.core.ranges import range_performance
from targetacq.reports.content import uncertainty_section, with_uncertainty
from targetacq.reports.plots import plot_range_performance
from targetacq.run.uncertainty import Uncertainty

HAZE = RangeCase(2.3, 2e-4, extinction=0.4e-3)
GRID = np.linspace(50.0, 6000.0, 40)


@pytest.fixture(scope="module")
def banded():
    perf = range_performance(GRID, {"haze": HAZE, "clear": RangeCase(2.3, 2e-4)}, [0.5, 0.8])
    return perf, with_uncertainty(perf, Uncertainty(100, extinction_spread=0.2))


def test_bands_contain_the_nominal_curves_and_ranges(banded):
    nominal, perf = banded
    for task in ("detection", "recognition", "identification"):
        curve = perf.curves[task].values
        assert np.all(perf.curves[f"{task}_p05"].values <= curve + 1e-12)
        assert np.all(curve <= perf.curves[f"{task}_p95"].values + 1e-12)
    dri = perf.dri
    assert len(dri) == len(nominal.dri)  # the same rows, with the band's columns
    assert np.all(dri["range_p05_m"] < dri["range_m"])
    assert np.all(dri["range_m"] < dri["range_p95_m"])
    assert np.all(dri["range_p05_m"] <= dri["range_p50_m"])


def test_range_figure_shades_one_band_per_curve(banded):
    nominal, perf = banded
    shaded = [c for c in plot_range_performance(perf).axes[0].collections
              if isinstance(c, PolyCollection)]  # fmt: skip
    plain = [c for c in plot_range_performance(nominal).axes[0].collections
             if isinstance(c, PolyCollection)]  # fmt: skip
    assert len(shaded) == 6 and not plain  # 2 cases × 3 tasks


def test_section_states_the_distributions():
    section = uncertainty_section(Uncertainty(300, seed=2, netd_spread=0.1))
    assert section["samples"] == "300 (seed 2)"
    assert "lognormal" in section["distributions"] and "NETD 10 %" in section["distributions"]


def test_report_command_writes_the_bands(cli, tmp_path):
    out = tmp_path / "r.html"
    code, _, err = cli(
        "report", "--ifov", "0.2mrad", "--critical-dimension", "2.3m", "--extinction", "0.4/km",
        "--uncertainty", "100", "--extinction-spread", "20%", "--out", str(out),
    )  # fmt: skip
    assert code in (0, None), err
    page = out.read_text()
    assert "Uncertainty (Monte Carlo)" in page and "Shaded: the 5–95 % band over 100" in page


def test_report_of_a_scenario_refuses_uncertainty(cli, tmp_path):
    code, _, err = cli("report", "examples/two_sensors_fused.toml", "--uncertainty", "100",
                       "--out", str(tmp_path / "r.html"))  # fmt: skip
    assert code == 2 and len(err.strip().splitlines()) == 1 and "not a scenario" in err


def test_the_reports_range_axis_reaches_the_bands_95_percent_points():
    from targetacq.cli.figures import _range_case_report

    options = {"ifov": "0.2 mrad", "critical_dimension": "2.3 m", "extinction": "0.4/km"}
    spread = Uncertainty(100, n50_spread=0.4)
    _, perf, *_ = _range_case_report(options, None, None, uncertainty=spread)
    farthest = np.nanmax(perf.dri["range_p95_m"].to_numpy())
    assert perf.curves["range"].values[-1] >= farthest


def test_a_report_refuses_a_spread_that_no_case_has(cli, tmp_path):
    out = tmp_path / "r.html"
    code, _, err = cli(
        "report", "--example", "--critical-dimension", "0.75m,2.3m", "--uncertainty", "50",
        "--netd-spread", "10%", "--out", str(out),
    )  # fmt: skip
    assert code == 2 and "--netd-spread needs" in err and not out.exists()
