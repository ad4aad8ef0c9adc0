"""Figures are real images with the plotted data in them (colours read back), not pixel hashes."""

import xml.etree.ElementTree as ET

import numpy as np
import pytest
from matplotlib import colors
from PIL import Image

from targetacq import plots
from targetacq.ranges import range_performance


def _colour_pixels(path, hex_colour, tolerance=12):
    image = np.asarray(Image.open(path).convert("RGB")).astype(int)
    target = np.array(colors.to_rgb(hex_colour)) * 255
    return int(np.sum(np.all(np.abs(image - target) <= tolerance, axis=-1)))


@pytest.fixture(scope="module")
def performance():
    grid = np.linspace(20.0, 8000.0, 300)
    cases = {
        "clear": {"critical_dimension": 2.3, "ifov": 2.27e-4},
        "haze": {"critical_dimension": 2.3, "ifov": 2.27e-4, "extinction": 0.4e-3, "scr": 3.0},
    }
    return range_performance(grid, cases)


def test_curves_png_has_every_task_colour(tmp_path, performance):
    out = plots.save_figure(
        plots.plot_range_performance(performance, title="test"), tmp_path / "c.png"
    )
    with Image.open(out) as image:
        assert image.format == "PNG"
        assert image.size == (800, 500)  # 8 x 5 in at 100 dpi
    for colour in plots.TASK_COLOURS.values():
        assert _colour_pixels(out, colour) > 300, colour  # a drawn curve, not a legend swatch


def test_transforms_png_has_tables_and_ttpf(tmp_path):
    out = plots.save_figure(plots.plot_transforms("johnson"), tmp_path / "t.png")
    with Image.open(out) as image:
        assert image.size == (1100, 460)
    for colour in (*plots.TASK_COLOURS.values(), *plots.REGION_COLOURS.values()):
        assert _colour_pixels(out, colour) > 300, colour


def test_atmosphere_png(tmp_path):
    out = plots.save_figure(plots.plot_atmosphere("lwir", 5e3), tmp_path / "a.png")
    assert _colour_pixels(out, "#1f77b4") > 300


def test_svg_is_valid_and_has_curves(tmp_path, performance):
    out = plots.save_figure(plots.plot_range_performance(performance), tmp_path / "c.svg")
    root = ET.parse(out).getroot()
    assert root.tag.endswith("svg")
    paths = [e for e in root.iter() if e.tag.endswith("path")]
    assert len(paths) > 20


@pytest.mark.parametrize(
    ("name", "match"),
    [("missing/x.png", "does not exist"), ("x.jpg", r"must end in \.png or \.svg")],
)
def test_bad_output_paths(tmp_path, name, match):
    with pytest.raises(ValueError, match=match):
        plots.save_figure(plots.plot_transforms(), tmp_path / name)


def test_range_performance_data_agrees_with_its_dri_table(performance):
    curves, dri = performance.curves, performance.dri
    assert curves.sizes == {"case": 2, "range": 300}
    for _, row in dri[dri["reached"]].iterrows():
        p = np.interp(row["range_m"], curves["range"], curves[row["task"]].sel(case=row["case"]))
        # Linear interpolation on the 27 m grid: within a few percent of p (jumps excepted).
        assert p >= row["probability"] - 0.05 or row["case"] == "haze"


def test_bad_case_keys_say_what_was_meant():
    with pytest.raises(ValueError, match="'extintion' \\(did you mean 'extinction'\\?\\)"):
        range_performance(
            [100.0, 200.0], {"x": {"critical_dimension": 2.3, "ifov": 1e-4, "extintion": 1e-3}}
        )
    with pytest.raises(ValueError, match="needs 'ifov'"):
        range_performance([100.0, 200.0], {"x": {"critical_dimension": 2.3}})
    with pytest.raises(ValueError, match=r"open interval \(0, 1\)"):
        range_performance(
            [100.0, 200.0], {"x": {"critical_dimension": 2.3, "ifov": 1e-4}}, [0.5, 1.0]
        )
