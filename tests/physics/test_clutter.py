"""Clutter in images (3.12)–(3.15): summed-area cells against direct computation, known answers,
a real photograph; terrain clutter (6.10)–(6.11); signature features (2.6)–(2.12)."""

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import targetacq as ta
from targetacq.io.images import read_image, save_clutter_overlay
from targetacq.physics.clutter import gray, image_clutter
from targetacq.physics.features import target_features
from targetacq.physics.terrain import TerrainClass, TerrainMap

DATA = Path(__file__).parents[1] / "data"


def direct_clutter(image, box, cell_factor=2.0):
    """Independent per-cell computation with masks: same cell layout, np.var per cell."""
    img = np.asarray(image, dtype=float)
    height, width = img.shape
    x, y, w, h = box
    side = max(1, int(np.round(cell_factor * min(w, h))))
    cx0 = int(np.floor(x + w / 2 - side / 2))
    cy0 = int(np.floor(y + h / 2 - side / 2))
    target = np.zeros(img.shape, dtype=bool)
    target[y : y + h, x : x + w] = True
    variances, background = [], []
    for j in (-1, 0, 1):
        for i in (-1, 0, 1):
            cell = np.zeros(img.shape, dtype=bool)
            x0, y0 = cx0 + i * side, cy0 + j * side
            ys = slice(min(max(y0, 0), height), min(max(y0 + side, 0), height))
            xs = slice(min(max(x0, 0), width), min(max(x0 + side, 0), width))
            cell[ys, xs] = True
            pixels = img[cell & ~target]
            if pixels.size >= 2:
                variances.append(pixels.var())
                background.append(pixels)
    if not variances:  # no cell with two background pixels
        return np.nan, np.nan, np.nan
    clutter = np.sqrt(np.mean(variances))
    g_mean = np.concatenate(background).mean()
    g = img[target]
    return clutter, abs(g.max() - g_mean) / clutter, abs(g.min() - g_mean) / clutter


@settings(max_examples=40, deadline=None)
@given(
    st.integers(0, 2**32 - 1),
    st.integers(8, 60),
    st.integers(8, 60),
    st.sampled_from([np.uint8, np.uint16, np.float32, np.float64]),
    st.floats(0.5, 3.0),
)
def test_summed_area_tables_equal_direct_cells(seed, height, width, dtype, cell_factor):
    rng = np.random.default_rng(seed)
    image = (rng.uniform(0, 250, (height, width))).astype(dtype)
    boxes = []
    for _ in range(5):
        w, h = rng.integers(1, width // 2 + 1), rng.integers(1, height // 2 + 1)
        boxes.append(
            (
                int(rng.integers(0, width - w + 1)),
                int(rng.integers(0, height - h + 1)),
                int(w),
                int(h),
            )
        )
    boxes.append((0, 0, 3, 2))  # touching two edges
    boxes.append((width - 4, height - 5, 4, 5))  # touching the other two
    direct = [direct_clutter(image, box, cell_factor) for box in boxes]
    # No cell with two background pixels (a thin box in small cells): refused, the box named.
    empty = [k for k, (clutter, _, _) in enumerate(direct) if np.isnan(clutter)]
    if empty:
        with pytest.raises(ValueError, match=rf"^box {empty[0]} .* leaves no background"):
            image_clutter(image, boxes, cell_factor)
    kept = [k for k in range(len(boxes)) if k not in empty]
    result = image_clutter(image, [boxes[k] for k in kept], cell_factor)
    for i, k in enumerate(kept):
        clutter, pos, neg = direct[k]
        assert result.clutter[i] == pytest.approx(clutter, rel=1e-9, nan_ok=True)
        assert result.scr_positive[i] == pytest.approx(pos, rel=1e-9, nan_ok=True)
        assert result.scr_negative[i] == pytest.approx(neg, rel=1e-9, nan_ok=True)


def test_uniform_background_has_zero_clutter_and_infinite_scr():
    image = np.full((200, 300), 1234, dtype=np.uint16)
    image[90:110, 140:160] = 1500
    result = image_clutter(image, [(140, 90, 20, 20)])
    assert result.clutter[0] == 0.0
    assert result.scr_positive[0] == np.inf
    assert not np.isnan(result.scr[0])
    assert result.region[0] == "low"


@pytest.mark.parametrize("sigma", [3.0, 20.0])
def test_gaussian_noise_background_gives_its_sigma(sigma):
    rng = np.random.default_rng(4)
    image = rng.normal(100.0, sigma, (1000, 1000))
    result = image_clutter(image, [(490, 490, 20, 20)])
    # 9 cells of 40 x 40 (the centre one less the target): ~13,000 samples, so the RMS of the
    # cell standard deviations is within a few tenths of a percent of sigma (5 % is very safe).
    assert result.clutter[0] == pytest.approx(sigma, rel=0.05)


def test_checkerboard_background_gives_its_sigma():
    # A ±a checkerboard has standard deviation a in every even-sided cell.
    a = 5.0
    yy, xx = np.mgrid[0:120, 0:120]
    image = 50.0 + a * np.where((xx + yy) % 2 == 0, 1.0, -1.0)
    result = image_clutter(image, [(54, 54, 12, 12)])
    assert result.clutter[0] == pytest.approx(a, rel=1e-3)


def test_real_photograph_sky_target_beats_vegetation_target():
    # tests/data/README: CC0 photograph; tower top against the sky vs tripod foot in the grass.
    image = read_image(DATA / "camera.png")
    assert image.shape == (512, 512)
    result = image_clutter(image, [(412, 118, 20, 20), (228, 470, 24, 24)])
    sky, grass = result.scr
    assert sky > grass
    assert result.clutter[0] < result.clutter[1]


def test_thousands_of_boxes_match_one_at_a_time():
    rng = np.random.default_rng(0)
    image = rng.normal(0.0, 1.0, (256, 256))
    boxes = np.column_stack(
        [
            rng.integers(0, 240, 500),
            rng.integers(0, 240, 500),
            rng.integers(1, 16, 500),
            rng.integers(1, 16, 500),
        ]
    )
    together = image_clutter(image, boxes)
    for k in (0, 123, 499):
        alone = image_clutter(image, boxes[k])
        assert together.clutter[k] == pytest.approx(alone.clutter[0], rel=1e-12)


@pytest.mark.parametrize(
    ("boxes", "match"),
    [
        ([(95, 10, 10, 10)], "box 0 .* leaves the 100 x 50 image"),
        ([(-1, 0, 5, 5)], "leaves"),
        ([(10, 10, 0, 5)], "zero or negative size"),
        ([(10, 10, 2.5, 5)], "whole numbers"),
        ([(1, 2, 3)], r"rows of \(x, y, width, height\)"),
    ],
)
def test_bad_boxes(boxes, match):
    with pytest.raises(ValueError, match=match):
        image_clutter(np.zeros((50, 100)), boxes)


def test_colour_image_needs_a_channel():
    rgb = np.zeros((10, 10, 3), dtype=np.uint8)
    rgb[..., 1] = 100
    with pytest.raises(ValueError, match="image must be 2-D"):
        image_clutter(rgb, [(1, 1, 2, 2)])
    with pytest.raises(ValueError, match="needs a channel"):
        gray(rgb)
    assert gray(rgb, "green")[0, 0] == 100
    assert gray(rgb, "luminance")[0, 0] == pytest.approx(58.7)


def test_sixteen_bit_tiff_and_png_round_trip(tmp_path):
    from PIL import Image

    values = (np.arange(64 * 64, dtype=np.uint16).reshape(64, 64) * 15) + 1000
    for name in ("frame.tif", "frame.png"):
        Image.fromarray(values).save(tmp_path / name)
        back = read_image(tmp_path / name)
        assert back.dtype.itemsize >= 2
        np.testing.assert_array_equal(back.astype(np.int64), values.astype(np.int64))


def test_unreadable_files(tmp_path):
    bad = tmp_path / "bad.png"
    bad.write_text("not an image")
    with pytest.raises(ValueError, match="cannot read"):
        read_image(bad)
    with pytest.raises(ValueError, match="no image file"):
        read_image(tmp_path / "missing.png")


def test_overlay_draws_cells_and_targets(tmp_path):
    from PIL import Image

    image = read_image(DATA / "camera.png")
    boxes = [(412, 118, 20, 20)]
    out = save_clutter_overlay(image, image_clutter(image, boxes), boxes, tmp_path / "o.png")
    pixels = np.asarray(Image.open(out).convert("RGB")).astype(int)
    assert pixels.shape == (512, 512, 3)
    assert np.sum(np.all(pixels == (255, 0, 0), axis=-1)) > 50  # target outline
    assert np.sum(np.all(pixels == (255, 220, 0), axis=-1)) > 200  # cell outlines


# --- terrain -------------------------------------------------------------------------------------


def test_terrain_clutter_eq_6_10_and_weights_eq_6_11():
    classes = [TerrainClass("grass", 10.0, 4.0, 0.5), TerrainClass("forest", 8.0, 16.0, 0.5)]
    grid = np.array([[0, 0, 1, 1], [0, 0, 1, 1]])
    terrain = TerrainMap(classes, grid, cell_size=10.0)
    k = terrain.weights([20.0, 10.0, 22.5], [10.0, 10.0, 10.0], 10.0)
    np.testing.assert_allclose(k, [[0.5, 0.5], [1.0, 0.0], [0.25, 0.75]])  # fractional overlap
    np.testing.assert_allclose(k.sum(axis=-1), 1.0)
    clutter, mean = terrain.clutter(20.0, 10.0, 10.0, footprint=0.5)
    assert clutter == pytest.approx(np.sqrt(0.5 * 4.0 + 0.5 * 16.0))  # (6.10)
    assert mean == pytest.approx(9.0)
    assert ta.terrain_clutter([0.5, 0.5], [4.0, 16.0]) == pytest.approx(clutter)


def test_terrain_variance_falls_as_resolution_coarsens():
    terrain = TerrainMap([TerrainClass("grass", 1.0, 9.0, 0.5)], np.zeros((4, 4), int), 10.0)
    fine, _ = terrain.clutter(20.0, 20.0, 10.0, footprint=0.25)
    coarse, _ = terrain.clutter(20.0, 20.0, 10.0, footprint=2.0)
    assert fine == pytest.approx(3.0)  # finer than the reference: no new variance
    assert coarse == pytest.approx(3.0 * 0.5 / 2.0)  # σ · r0 / g


def test_terrain_weights_move_continuously():
    classes = [TerrainClass("a", 0.0, 1.0, 1.0), TerrainClass("b", 1.0, 1.0, 1.0)]
    terrain = TerrainMap(classes, np.array([[0, 1]]), cell_size=1.0)
    x = np.linspace(0.6, 1.4, 81)
    k_b = terrain.weights(x, 0.5, 0.4)[:, 1]
    assert np.all(np.diff(k_b) >= -1e-15)
    assert np.max(np.abs(np.diff(k_b))) < 0.03


# --- features ------------------------------------------------------------------------------------


def test_features_of_a_bright_rectangle_on_a_flat_background():
    image = np.full((100, 100), 10.0)
    image[40:50, 30:60] = 50.0  # 30 wide, 10 high
    f = target_features(image, (30, 40, 30, 10))
    assert f.aspect == pytest.approx(10 / 30)  # (2.6)
    assert f.std_over_mean == pytest.approx(0.0)  # (2.7)
    assert f.mean_intensity == pytest.approx(50.0)  # (2.11)
    assert f.area == 300
    assert f.perimeter == 80
    assert f.compactness == pytest.approx(4 * np.pi * 300 / 80**2)  # (2.8), Z = 1/(4π)
    assert f.contrast == pytest.approx(40.0 / np.sqrt(1e-12))  # (2.12): no spread at all
    assert 0 < f.edge_strength <= 1  # (2.9): the rim is an edge, the flat inside is not
    # (2.10): inside an axis-aligned rectangle the nearest background pixel is straight across
    # the nearest side, so the distance is the smallest of the four axis distances.
    rows, cols = np.mgrid[0:10, 0:30]
    distances = np.minimum.reduce([rows + 1, 10 - rows, cols + 1, 30 - cols])
    assert f.form_factor == pytest.approx(300 / np.mean(distances) ** 2, rel=1e-12)


def test_features_with_a_mask_and_bad_input():
    image = np.random.default_rng(2).normal(0, 1, (64, 64))
    disc = (np.hypot(*np.mgrid[-10:11, -10:11]) <= 10).astype(bool)
    f = target_features(image, (20, 20, 21, 21), mask=disc)
    assert f.area == int(disc.sum())
    with pytest.raises(ValueError, match="mask must have the box's shape"):
        target_features(image, (20, 20, 21, 21), mask=disc[:-1])
    with pytest.raises(ValueError, match="edge_detector must be one of sobel"):
        target_features(image, (20, 20, 5, 5), edge_detector="canny")


@pytest.mark.parametrize(
    ("shape", "box"),
    [
        ((1, 1), (0, 0, 1, 1)),  # a 1 x 1 image
        ((40, 60), (0, 0, 60, 40)),  # a box covering the whole image
    ],
)
def test_a_box_without_background_is_refused_not_nan(shape, box, tmp_path, capsys):
    # The clutter of Eq. (3.12) is measured on background pixels around the box: with none,
    # the clutter, SCR and P(detection) were NaN, and `targetacq clutter` exited 0.
    image = np.random.default_rng(1).uniform(0, 200, shape).astype(np.uint8)
    x, y, w, h = box
    expected = rf"^box 0 \({x}, {y}, {w}, {h}\) leaves no background in the {shape[1]} x "
    with pytest.raises(ValueError, match=expected):
        image_clutter(image, [box])
    with pytest.raises(ValueError, match=expected):
        target_features(image, box)
    path = tmp_path / "small.png"
    from PIL import Image

    Image.fromarray(image).save(path)
    from targetacq.cli import main

    with pytest.raises(SystemExit) as done:
        main(["clutter", str(path), "--box", ",".join(map(str, box))])
    err = capsys.readouterr().err
    assert done.value.code == 2 and err.count("\n") == 1
    assert err.startswith(f"targetacq: error: box 0 ({x}, {y}, {w}, {h}) leaves no background")
