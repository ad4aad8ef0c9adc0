"""Write the example images of the README's ``targetacq clutter`` commands.

The files are synthetic and reproducible: a smooth textured background made from a fixed
integer hash (no random generator whose stream could change between NumPy versions) with warm
targets added as soft-edged blobs.

- ``scene.png``: 640 × 512, 8-bit grey; targets in the boxes (x, y, width, height)
  412,118,20,20 and 228,470,24,24;
- ``frame16.tif``: 320 × 256, 16-bit thermal counts (deflate-compressed TIFF); targets in the
  boxes of ``targets.csv``.

Run ``python examples/make_clutter_examples.py [FOLDER]`` to write them again (into this file's
folder by default); then::

    targetacq clutter examples/scene.png --box 412,118,20,20 --box 228,470,24,24 \\
        --overlay cells.png
    targetacq clutter examples/frame16.tif --boxes examples/targets.csv \\
        --image-range 1km --range 3km
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

SCENE_SHAPE = (512, 640)
SCENE_BOXES = ((412, 118, 20, 20), (228, 470, 24, 24))
FRAME_SHAPE = (256, 320)
# name, (x, y, width, height) [pixels], the target's excess over its surroundings [counts]
FRAME_TARGETS = (
    ("vehicle", (60, 150, 28, 12), 900.0),
    ("person", (181, 120, 6, 14), 600.0),
    ("hot-spot", (262, 40, 8, 8), 1500.0),
)


def hash_noise(shape: tuple[int, int], seed: int) -> np.ndarray:
    """Noise uniform in [0, 1) from an integer hash of (row, column, seed): the same on every
    platform and NumPy version."""
    rows, cols = np.indices(shape, dtype=np.uint64)
    h = rows * np.uint64(0x9E3779B1) + cols * np.uint64(0x85EBCA77) + np.uint64(seed)
    mask = np.uint64(0xFFFFFFFF)
    h &= mask
    for multiplier in (0x7FEB352D, 0x846CA68B):  # a 32-bit integer mixer ("lowbias32")
        h ^= h >> np.uint64(16)
        h = (h * np.uint64(multiplier)) & mask
    h ^= h >> np.uint64(16)
    return h.astype(np.float64) / 2.0**32


def smooth(values: np.ndarray, width: int) -> np.ndarray:
    """A separable moving average over ``width`` pixels, edges wrapped."""
    kernel = np.ones(width) / width
    out = values
    for axis in (0, 1):
        pad = [(0, 0), (0, 0)]
        pad[axis] = (width, width)
        padded = np.pad(out, pad, mode="wrap")
        out = np.apply_along_axis(np.convolve, axis, padded, kernel, mode="same")
        out = out[width:-width, :] if axis == 0 else out[:, width:-width]
    return out


def texture(shape: tuple[int, int], seed: int) -> np.ndarray:
    """A background with structure at several scales, zero mean, unit standard deviation."""
    total = np.zeros(shape)
    for k, (width, weight) in enumerate(((41, 1.0), (15, 0.6), (5, 0.35))):
        layer = smooth(hash_noise(shape, seed + k), width)
        total += weight * (layer - layer.mean()) / layer.std()
    total += 0.25 * (hash_noise(shape, seed + 10) - 0.5)  # pixel noise
    return (total - total.mean()) / total.std()


def blob(shape: tuple[int, int], box: tuple[int, int, int, int]) -> np.ndarray:
    """1 inside an ellipse filling ``box`` (x, y, width, height), falling off smoothly to 0
    over about a pixel at its edge."""
    x, y, w, h = box
    rows, cols = np.indices(shape, dtype=np.float64)
    r = np.hypot((cols + 0.5 - (x + w / 2)) / (w / 2), (rows + 0.5 - (y + h / 2)) / (h / 2))
    edge = 2.0 / min(w, h)
    return np.clip((1.0 - r) / edge + 0.5, 0.0, 1.0)


def scene() -> np.ndarray:
    """The 8-bit scene: a textured background (mean 100, spread 12) darker towards the top,
    two warm targets."""
    values = 100.0 + 12.0 * texture(SCENE_SHAPE, seed=2004)
    values += np.linspace(-15.0, 15.0, SCENE_SHAPE[0])[:, None]  # a gradient, sky to ground
    for box, excess in zip(SCENE_BOXES, (60.0, 35.0), strict=True):
        values += excess * blob(SCENE_SHAPE, box)
    return np.clip(np.rint(values), 0, 255).astype(np.uint8)


def frame16() -> np.ndarray:
    """The 16-bit thermal frame: counts around 21,000 (spread 300), three warm targets."""
    values = 21000.0 + 300.0 * texture(FRAME_SHAPE, seed=4347)
    for _, box, excess in FRAME_TARGETS:
        values += excess * blob(FRAME_SHAPE, box)
    return np.clip(np.rint(values), 0, 65535).astype(np.uint16)


def targets_csv() -> str:
    """The boxes of ``frame16.tif`` as ``targetacq clutter --boxes`` reads them."""
    lines = [
        "# Targets in frame16.tif: x, y, width, height in pixels (other columns are ignored).",
        "name,x,y,width,height",
    ]
    lines += [f"{name},{x},{y},{w},{h}" for name, (x, y, w, h), _ in FRAME_TARGETS]
    return "\n".join(lines) + "\n"


def write(folder: Path) -> list[Path]:
    """Write ``scene.png``, ``frame16.tif`` and ``targets.csv`` into ``folder``."""
    from PIL import Image

    folder.mkdir(parents=True, exist_ok=True)
    paths = [folder / "scene.png", folder / "frame16.tif", folder / "targets.csv"]
    Image.fromarray(scene()).save(paths[0], format="PNG", optimize=True)
    Image.fromarray(frame16()).save(paths[1], format="TIFF", compression="tiff_adobe_deflate")
    paths[2].write_text(targets_csv(), encoding="utf-8")
    return paths


if __name__ == "__main__":
    for path in write(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parent):
        print(f"{path}: {path.stat().st_size:,} bytes")
