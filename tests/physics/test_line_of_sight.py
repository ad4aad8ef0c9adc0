"""Line of sight over terrain (targetacq.physics.line_of_sight): ridges with closed-form answers,
the Earth's curvature with standard refraction against the smooth-Earth hidden height, the input
matrix, and the numba loops against the NumPy ones."""

import importlib.util
import math

import numpy as np
import pytest

import targetacq as ta
from targetacq.physics.line_of_sight import (
    EARTH_RADIUS,
    STANDARD_K,
    ElevationModel,
    line_of_sight,
    read_elevation,
)

HAS_NUMBA = importlib.util.find_spec("numba") is not None
NO_NUMBA = pytest.mark.skipif(not HAS_NUMBA, reason="numba (the fast extra) is not installed")
METHODS = ["numpy", pytest.param("numba", marks=NO_NUMBA)]
SPACING = 10.0


def plateau(height, first, last, rows=61, cols=201):
    """Flat ground at 0 with a north-south plateau of ``height`` on columns first..last."""
    grid = np.zeros((rows, cols))
    grid[:, first : last + 1] = height
    return grid


@pytest.mark.parametrize("method", METHODS)
def test_a_ridge_hides_a_target_behind_it_and_not_one_in_front(method):
    grid = plateau(20.0, 99, 101)  # a 20 m ridge 1 km east of the observer
    observer = [0.0, 300.0, 2.0]
    behind, front = [1800.0, 300.0, 0.0], [800.0, 300.0, 0.0]
    for k in (STANDARD_K, math.inf):
        seen = line_of_sight(
            grid, SPACING, (0.0, 0.0), observer, [behind, front], 4.0, k=k, method=method
        )
        assert seen.tolist() == [0.0, 1.0]


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("direction", [(1, 0), (-1, 0), (1, 0.5), (1, -0.3), (-1, 0.25)])
def test_partial_masking_by_a_plateau_is_the_closed_form(method, direction):
    # A 6 m plateau from 400 m to 500 m along the track; observer 10 m up, a 4 m target at
    # 1000 m. The highest sight line grazes the plateau's far edge (slope (6 - 10)/500): at the
    # target it passes 10 - 4 * 1000/500 = 2 m, so (4 - 2)/4 = 1/2 of the target is seen,
    # whatever the track's direction (the plateau spans the track's columns 40 to 50).
    grid = plateau(6.0, 140, 150, rows=201, cols=301)
    du, dv = direction
    x0 = 1000.0 if du > 0 else 2000.0
    observer = [x0, 400.0, 10.0]
    target = [x0 + 1000.0 * du, 400.0 + 1000.0 * dv, 0.0]
    if du < 0:
        grid = plateau(6.0, 150, 160, rows=201, cols=301)
    seen = line_of_sight(
        grid, SPACING, (0.0, 0.0), observer, target, 4.0, k=math.inf, method=method
    )
    assert seen == pytest.approx(0.5, abs=1e-12)


@pytest.mark.parametrize("method", METHODS)
def test_partial_masking_with_the_earth_bulge(method):
    # The same plateau at 30 km scale (spacing 100 m): in the chord frame the plateau's far
    # edge at b rises by the bulge b (D - b) / (2 k R_e) (ITU-R P.452), and the sight line over
    # it reaches z_o + (D/b) (H + b (D - b)/(2a) - z_o) at the target.
    grid = plateau(40.0, 100, 120, rows=3, cols=301)
    zo, h, b, d = 60.0, 50.0, 12_000.0, 30_000.0
    a = STANDARD_K * EARTH_RADIUS
    hidden = zo + (d / b) * (40.0 + b * (d - b) / (2 * a) - zo)
    expected = (h - hidden) / h
    assert 0.05 < expected < 0.95  # partial, and the bulge matters:
    assert abs(expected - (h - (zo + (d / b) * (40.0 - zo))) / h) > 0.05
    seen = line_of_sight(
        grid, 100.0, (0.0, 0.0), [0.0, 100.0, zo], [d, 100.0, 0.0], h, method=method
    )
    assert seen == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("method", METHODS)
def test_curvature_drop_at_25_km_is_the_smooth_earth_hidden_height(method):
    # Flat terrain at 0, an observer 10 m up: the smooth Earth of radius a = (4/3) R_e hides
    # (D - sqrt(2 a z_o))^2 / (2a) of a target at D beyond the horizon sqrt(2 a z_o) (13.0 km).
    a = STANDARD_K * EARTH_RADIUS
    zo, h, d = 10.0, 10.0, 25_000.0
    horizon = math.sqrt(2 * a * zo)
    hidden = (d - horizon) ** 2 / (2 * a)
    assert 8.0 < hidden < 9.0
    grid = np.zeros((2, 301))
    seen = line_of_sight(grid, 100.0, (0.0, 0.0), [0.0, 0.0, zo], [d, 100.0, 0.0], h, method=method)
    assert seen == pytest.approx((h - hidden) / h, rel=1e-4)
    # Before the horizon, all of it; a flat Earth hides nothing.
    near = line_of_sight(
        grid, 100.0, (0.0, 0.0), [0.0, 0.0, zo], [12_000.0, 0.0, 0.0], h, method=method
    )
    flat = line_of_sight(
        grid, 100.0, (0.0, 0.0), [0.0, 0.0, zo], [d, 0.0, 0.0], h, k=math.inf, method=method
    )
    assert (near, flat) == (1.0, 1.0)


@pytest.mark.parametrize("method", METHODS)
def test_nan_voids_and_positions_off_the_grid(method):
    grid = plateau(20.0, 99, 101)
    grid[0, :] = np.nan  # a void along the southern edge
    observer = np.array([0.0, 300.0, 2.0])
    targets = np.array(
        [
            [800.0, 300.0, 0.0],  # in front: 1
            [800.0, 300.0, np.nan],  # NaN base
            [np.nan, 300.0, 0.0],
            [800.0, 0.0, 0.0],  # the track crosses the void: unknown
            [2001.0, 300.0, 0.0],  # off the grid (east edge at 2000 m)
            [800.0, -0.5, 0.0],
        ]
    )
    heights = np.array([4.0, 4.0, 4.0, 4.0, 4.0, 4.0])
    seen = line_of_sight(grid, SPACING, (0.0, 0.0), observer, targets, heights, method=method)
    assert seen[0] == 1.0 and np.isnan(seen[1:]).all()
    assert np.isnan(
        line_of_sight(grid, SPACING, (0.0, 0.0), observer, targets[0], np.nan, method=method)
    )
    assert np.isnan(
        line_of_sight(grid, SPACING, (0.0, 0.0), [-5.0, 300.0, 2.0], targets[0], 4.0, method=method)
    )
    # On the edges exactly: inside.
    corner = line_of_sight(
        grid, SPACING, (0.0, 0.0), [0.0, 600.0, 100.0], [2000.0, 600.0, 0.0], 4.0, method=method
    )
    assert corner == 1.0


def test_the_input_matrix_is_refused_by_name():
    grid = np.zeros((5, 5))
    ok = ([0.0, 0.0, 1.0], [10.0, 10.0, 0.0], 2.0)
    for bad, match in (
        ((grid, 0.0, (0.0, 0.0)), "spacing"),
        ((grid, np.inf, (0.0, 0.0)), "spacing"),
        ((grid, 1.0, (np.nan, 0.0)), "origin"),
        ((grid, 1.0, (0.0,)), "origin"),
        ((np.zeros(5), 1.0, (0.0, 0.0)), "elevation"),
        ((np.zeros((1, 5)), 1.0, (0.0, 0.0)), "elevation"),
        ((np.full((5, 5), np.inf), 1.0, (0.0, 0.0)), "elevation"),
    ):
        with pytest.raises(ValueError, match=match):
            line_of_sight(*bad, *ok)
    args = (grid, 10.0, (0.0, 0.0))
    with pytest.raises(ValueError, match="observers"):
        line_of_sight(*args, [0.0, 0.0], ok[1], 2.0)
    with pytest.raises(ValueError, match="targets"):
        line_of_sight(*args, ok[0], [[np.inf, 0.0, 0.0]], 2.0)
    with pytest.raises(ValueError, match="target_heights"):
        line_of_sight(*args, ok[0], ok[1], 0.0)
    with pytest.raises(ValueError, match="target_heights"):
        line_of_sight(*args, ok[0], ok[1], -1.0)
    with pytest.raises(ValueError, match="broadcast"):
        line_of_sight(*args, np.zeros((2, 3)), np.zeros((3, 3)), 2.0)
    with pytest.raises(ValueError, match="k "):
        line_of_sight(*args, *ok, k=0.0)
    with pytest.raises(ValueError, match="method"):
        line_of_sight(*args, *ok, method="fortran")


def test_pairs_broadcast_and_the_public_export():
    grid = plateau(20.0, 99, 101)
    observers = np.array([[0.0, 300.0, 2.0], [1900.0, 300.0, 2.0]])[:, None, :]
    targets = np.array([[800.0, 300.0, 0.0], [1800.0, 300.0, 0.0], [1200.0, 300.0, 0.0]])[None]
    seen = ta.line_of_sight(grid, SPACING, (0.0, 0.0), observers, targets, 4.0)
    # Each observer sees its own side of the ridge (at 1 km) and not the other's.
    assert seen.tolist() == [[1.0, 0.0, 0.0], [0.0, 1.0, 1.0]]
    model = ElevationModel(grid, SPACING, (0.0, 0.0))
    assert np.array_equal(ta.line_of_sight(model, None, None, observers, targets, 4.0), seen)


def test_coincident_observer_and_target_see_each_other():
    grid = np.zeros((3, 3))
    assert line_of_sight(grid, 1.0, (0.0, 0.0), [1.0, 1.0, 5.0], [1.0, 1.0, 0.0], 1.0) == 1.0


def test_height_at_is_bilinear_with_row_zero_south():
    model = ElevationModel([[0.0, 10.0], [20.0, 30.0]], 100.0, (500.0, 1000.0))
    # Row 0 is the southern edge: the north-west post (row 1, column 0) holds 20 m.
    assert model.height_at(500.0, 1100.0) == 20.0

    assert model.height_at(525.0, 1050.0) == pytest.approx(
        (0.75 * 0 + 0.25 * 10) * 0.5 + (0.75 * 20 + 0.25 * 30) * 0.5
    )
    assert np.isnan(model.height_at(499.0, 1050.0))
    assert model.extent == (500.0, 600.0, 1000.0, 1100.0)


@NO_NUMBA
def test_numba_and_numpy_give_the_same_numbers():
    rng = np.random.default_rng(5)
    n = 96
    x = np.arange(n)
    grid = 30 * np.sin(x / 9.0)[None, :] * np.cos(x / 13.0)[:, None] + rng.normal(0, 2, (n, n))
    count = 3000
    observers = np.column_stack(
        [rng.uniform(-20, 970, count), rng.uniform(0, 950, count), rng.uniform(0, 60, count)]
    )
    targets = np.column_stack(
        [rng.uniform(0, 960, count), rng.uniform(-20, 970, count), rng.uniform(-30, 30, count)]
    )
    heights = rng.uniform(0.5, 10, count)
    heights[::97] = np.nan
    for k in (STANDARD_K, math.inf, 0.01):  # 0.01: a strong bulge, to exercise the term
        a = line_of_sight(grid, 10.0, (0.0, 0.0), observers, targets, heights, k=k, method="numpy")
        b = line_of_sight(grid, 10.0, (0.0, 0.0), observers, targets, heights, k=k, method="numba")
        assert np.array_equal(a, b, equal_nan=True)
        assert 0.1 < np.mean(a == 0) < 0.9 and np.mean((a > 0) & (a < 1)) > 0.01
    # High ground (3 km up, the same relief): the numba loops' skipped chunks stay skipped.
    up = np.array([0.0, 0.0, 3000.0])
    lifted = (observers + up, targets + up)
    a = line_of_sight(grid + 3000.0, 10.0, (0.0, 0.0), *lifted, heights, method="numpy")
    b = line_of_sight(grid + 3000.0, 10.0, (0.0, 0.0), *lifted, heights, method="numba")
    assert np.array_equal(a, b, equal_nan=True)
    grid[40:44, 40:44] = np.nan  # voids: no early stop, NaN where a track crosses one
    a = line_of_sight(grid, 10.0, (0.0, 0.0), observers, targets, heights, method="numpy")
    b = line_of_sight(grid, 10.0, (0.0, 0.0), observers, targets, heights, method="numba")
    assert np.array_equal(a, b, equal_nan=True)


def test_read_elevation_from_npy(tmp_path):
    grid = np.arange(12.0).reshape(3, 4)
    path = tmp_path / "dem.npy"
    np.save(path, grid)
    model = read_elevation(path, 30.0, (100.0, 200.0))
    assert np.array_equal(model.elevation, grid) and model.spacing == 30.0
    assert model.origin == (100.0, 200.0)
    with pytest.raises(ValueError, match="spacing"):
        read_elevation(path)
    with pytest.raises(ValueError, match="no such"):
        read_elevation(tmp_path / "missing.npy", 1.0, (0.0, 0.0))
    with pytest.raises(ValueError, match=r"\.npy grid or a GeoTIFF"):
        read_elevation(tmp_path / "dem.csv", 1.0, (0.0, 0.0))
    (tmp_path / "bad.npy").write_text("not numpy")
    with pytest.raises(ValueError, match=r"bad\.npy"):
        read_elevation(tmp_path / "bad.npy", 1.0, (0.0, 0.0))
    np.save(tmp_path / "one.npy", np.zeros(4))
    with pytest.raises(ValueError, match=r"one\.npy: elevation must be a 2-D grid"):
        read_elevation(tmp_path / "one.npy", 1.0, (0.0, 0.0))


def test_read_elevation_from_geotiff(tmp_path):
    tifffile = pytest.importorskip(
        "tifffile", reason="tifffile (the terrain extra) is not installed"
    )
    # A 3 x 4 north-up raster of 30 m pixels whose upper-left corner is at (1000, 5000):
    # PixelIsArea, so the south-west pixel's centre is (1015, 5000 - 90 + 15).
    grid = np.arange(12.0).reshape(3, 4)
    path = tmp_path / "dem.tif"
    tifffile.imwrite(
        path,
        grid.astype(np.float32),
        extratags=[
            (33550, "d", 3, (30.0, 30.0, 0.0), True),
            (33922, "d", 6, (0.0, 0.0, 0.0, 1000.0, 5000.0, 0.0), True),
        ],
    )
    model = read_elevation(path)
    assert model.spacing == 30.0 and model.origin == (1015.0, 4925.0)
    assert np.array_equal(model.elevation, grid[::-1])  # row 0 south
    # The north-west pixel's centre (1015, 4985) holds the raster's first value.
    assert model.height_at(1015.0, 4985.0) == 0.0
