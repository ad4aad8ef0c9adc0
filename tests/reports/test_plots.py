"""Figures are real images with the plotted data in them (colours read back), not pixel hashes."""

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from matplotlib import colors
from matplotlib.backends.backend_agg import FigureCanvasAgg
from PIL import Image

from targetacq.acquisition.fusion import fuse
from targetacq.core.ranges import range_performance
from targetacq.reports import plots
from targetacq.run.model_chain import ModelChain
from targetacq.run.search import simulate
from targetacq.scenario.schema import load_scenario

EXAMPLES = Path(__file__).parents[2] / "examples"


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
        assert image.size == (800, 560)  # 8 x 5.6 in at 100 dpi (two legend rows below)
    for colour in plots.TASK_COLOURS.values():
        assert _colour_pixels(out, colour) > 300, colour  # a drawn curve, not a legend swatch


def test_transforms_png_has_tables_and_ttpf(tmp_path):
    out = plots.save_figure(plots.plot_transforms("johnson"), tmp_path / "t.png")
    with Image.open(out) as image:
        assert image.size == (1100, 540)
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


@pytest.fixture(scope="module")
def fused_chain():
    return ModelChain(load_scenario(EXAMPLES / "two_sensors_fused.toml"))


def _lines(ax):
    return {line.get_label(): np.asarray(line.get_ydata(), dtype=float) for line in ax.lines}


def test_timeline_fused_curve_is_fuse_of_the_drawn_sensor_curves(fused_chain):
    dataset = fused_chain.evaluate().dataset
    fig = plots.plot_timeline(dataset, title="fused")
    sensors = list(dataset["sensor"].values)
    assert sensors == ["tv", "thermal"]
    axes = [ax for ax in fig.axes if ax.get_visible()]
    assert [ax.get_title(loc="left") for ax in axes] == ["truck", "soldier"]
    checked = 0
    for ax in axes:
        drawn = _lines(ax)
        for task in plots.TASK_COLOURS:
            per_sensor = np.stack([drawn[f"{task} — {s}"] for s in sensors])
            np.testing.assert_allclose(drawn[f"{task} — fused"], fuse(per_sensor, axis=0))
            checked += 1
    assert checked == 6
    # Not trivially equal: fusing helps somewhere (the truck's detection by two sensors).
    truck = _lines(axes[0])
    assert np.max(truck["detection — fused"] - truck["detection — tv"]) > 0.01


def test_timeline_of_one_sensor_has_no_fused_curve():
    chain = ModelChain(load_scenario(EXAMPLES / "uav_haze.toml"))
    fig = plots.plot_timeline(chain.evaluate().dataset)
    labels = {line.get_label() for ax in fig.axes for line in ax.lines}
    assert not any("fused" in label for label in labels)
    assert "fused" not in fig.get_suptitle()


def test_first_times_cdf_ends_at_the_share_of_runs_that_got_there(fused_chain):
    result = simulate(fused_chain, duration=60.0, step=0.5, runs=200, seed=3)
    fig = plots.plot_first_times(result)
    summary = result.summary().set_index(["target", "task"])
    axes = [ax for ax in fig.axes if ax.get_visible()]
    assert len(axes) == 2
    for ax, target in zip(axes, result.targets, strict=True):
        drawn = _lines(ax)
        for task in plots.TASK_COLOURS:
            curve = drawn[task]
            assert np.all(np.diff(curve) >= 0)  # a CDF
            assert curve[-1] == pytest.approx(summary.loc[(target, task), "fraction"])
    assert summary["fraction"].max() > 0.5  # something was acquired


def _overlaps(a, b):
    return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1


def _legends_off_the_data(fig):
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    legends = list(fig.legends) + [ax.get_legend() for ax in fig.axes if ax.get_legend()]
    assert legends
    for legend in legends:
        box = legend.get_window_extent(renderer)
        for ax in fig.axes:
            if ax.get_visible():
                assert not _overlaps(box, ax.get_window_extent(renderer)), ax.get_title()
    return len(legends)


def test_legends_are_outside_every_axes(performance, fused_chain):
    dataset = fused_chain.evaluate().dataset
    result = simulate(fused_chain, duration=60.0, step=1.0, runs=20, seed=1)
    figures = [
        plots.plot_range_performance(performance),
        plots.plot_transforms("johnson"),
        plots.plot_atmosphere("mwir", 5e3),
        plots.plot_timeline(dataset),
        plots.plot_first_times(result),
    ]
    assert [_legends_off_the_data(fig) for fig in figures] == [1, 2, 1, 1, 1]


def test_several_cases_get_distinct_line_styles(performance):
    fig = plots.plot_range_performance(performance, labels={"clear": "A", "haze": "B"})
    ax = fig.axes[0]
    styles = {
        line.get_label(): line.get_linestyle() for line in ax.lines if line.get_label()[0] != "_"
    }
    assert styles["detection — A"] != styles["detection — B"]
    texts = [t.get_text() for t in fig.legends[0].get_texts()]
    assert {"A", "B", "detection", "DRI range"} <= set(texts)
