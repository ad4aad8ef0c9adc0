"""What the package ships: the examples the README uses are the package's, reproducible, and
listed in the package data (the slow build-install-run check is ``.ci/package``)."""

from __future__ import annotations

import filecmp
import fnmatch
import importlib.util
import tomllib
from pathlib import Path
from types import ModuleType

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
PACKAGE = ROOT / "src" / "targetacq"
GENERATOR = EXAMPLES / "make_clutter_examples.py"


def _files(folder: Path) -> list[str]:
    return sorted(
        str(p.relative_to(folder))
        for p in folder.rglob("*")
        if p.is_file() and "__pycache__" not in p.parts
    )


def _generator() -> ModuleType:
    spec = importlib.util.spec_from_file_location("make_clutter_examples", GENERATOR)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_repository_examples_are_the_package_examples() -> None:
    """``examples/`` (the README's paths) and ``targetacq/examples`` (the wheel's) hold the same
    files with the same contents."""
    ours, shipped = _files(EXAMPLES), _files(PACKAGE / "examples")
    assert ours == shipped
    _, mismatch, errors = filecmp.cmpfiles(EXAMPLES, PACKAGE / "examples", ours, shallow=False)
    assert not mismatch and not errors, (mismatch, errors)


def test_every_example_and_data_file_is_package_data() -> None:
    """Each non-Python file under examples/ and data/ matches a [tool.setuptools.package-data]
    pattern (Python files ship as modules of the namespace package ``targetacq.examples``)."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    patterns = config["tool"]["setuptools"]["package-data"]["targetacq"]
    files = [f"examples/{f}" for f in _files(EXAMPLES)] + [
        f"data/{f}" for f in _files(PACKAGE / "data")
    ]
    missing = [
        f
        for f in files
        if not f.endswith(".py") and not any(fnmatch.fnmatch(f, p) for p in patterns)
    ]
    assert not missing, f"not in [tool.setuptools.package-data]: {missing}"
    assert "py.typed" in patterns


def test_the_clutter_examples_are_reproduced_by_their_generator(tmp_path: Path) -> None:
    from targetacq.io.images import read_image

    written = _generator().write(tmp_path)
    assert [p.name for p in written] == ["scene.png", "frame16.tif", "targets.csv"]
    for path in written:
        committed = EXAMPLES / path.name
        if path.suffix == ".csv":
            assert path.read_text() == committed.read_text()
            continue
        ours, theirs = read_image(path), read_image(committed)
        assert ours.dtype == theirs.dtype and ours.shape == theirs.shape
        # The same pixels (a last-bit difference in floating point may move one by a count).
        difference = np.abs(ours.astype(np.int64) - theirs.astype(np.int64))
        assert difference.max() <= 1 and np.count_nonzero(difference) <= 10


def test_the_clutter_examples_are_what_the_readme_says() -> None:
    """scene.png: 8-bit 640 × 512, the README's two --box targets warmer than their
    surroundings; frame16.tif: 16-bit, with targets.csv's boxes inside it; both small."""
    from targetacq.io.images import read_image
    from targetacq.physics.clutter import image_clutter

    scene = read_image(EXAMPLES / "scene.png")
    assert scene.dtype == np.uint8 and scene.shape == (512, 640)
    boxes = [(412, 118, 20, 20), (228, 470, 24, 24)]
    result = image_clutter(scene, boxes)
    assert np.all(np.asarray(result.scr_positive) > 2.0), result.scr_positive

    frame = read_image(EXAMPLES / "frame16.tif")
    assert frame.dtype == np.uint16 and int(frame.max()) > 255
    rows = [
        line.split(",")
        for line in (EXAMPLES / "targets.csv").read_text().splitlines()
        if line and not line.startswith("#")
    ]
    header, values = rows[0], [[int(v) for v in row[1:]] for row in rows[1:]]
    assert header == ["name", "x", "y", "width", "height"] and len(values) == 3
    for x, y, w, h in values:
        assert min(x, y) >= 0 and x + w <= frame.shape[1] and y + h <= frame.shape[0]
    assert np.all(np.asarray(image_clutter(frame, values).scr_positive) > 2.0)
    for name in ("scene.png", "frame16.tif"):
        assert (EXAMPLES / name).stat().st_size < 300_000, name
