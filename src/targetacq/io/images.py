"""Reading images (PNG, TIFF, 8- and 16-bit) and drawing what the clutter measure measured."""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Any

import numpy as np

from targetacq.base.arrays import Array
from targetacq.io.files import output_path, write_atomically

__all__ = ["read_image", "save_clutter_overlay"]


def read_image(path: str | Path) -> np.ndarray:
    """Pixels of an image file as an array: (H, W) for one channel, (H, W, 3|4) for colour.

    8-bit and 16-bit PNG and TIFF keep their integer values (thermal counts included).

    Raises
    ------
    ValueError
        If the file does not exist, is not a regular readable file
        (:func:`targetacq.base.inputs.input_file`), is not an image Pillow can read, or has more
        pixels than Pillow's decompression-bomb guard allows.
    """
    from PIL import Image, UnidentifiedImageError

    from targetacq.base.inputs import input_file

    # No size limit: Pillow's decompression-bomb guard bounds the pixels.
    source = input_file(path, "image file", limit=None)
    try:
        with warnings.catch_warnings():
            # Pillow warns of a possible decompression bomb before refusing one outright: one
            # clear error instead of a warning printed ahead of it.
            warnings.simplefilter("error", Image.DecompressionBombWarning)
            with Image.open(source) as opened:
                opened.load()
                if opened.mode in ("P", "LA", "PA"):
                    pixels = np.asarray(opened.convert("RGBA" if "A" in opened.mode else "RGB"))
                else:
                    pixels = np.asarray(opened)
    except (Image.DecompressionBombWarning, Image.DecompressionBombError) as error:
        raise ValueError(f"{source}: too many pixels to read safely: {error}") from None
    except (UnidentifiedImageError, OSError) as error:
        raise ValueError(f"cannot read {str(source)!r} as an image: {error}") from None
    if pixels.dtype == bool:
        pixels = pixels.astype(np.uint8)
    return pixels


def save_clutter_overlay(image: Array, result: Any, boxes: Array, path: str | Path) -> Path:
    """Write the image in grey with the clutter cells (yellow) and the targets (red) drawn.

    Parameters
    ----------
    image : array_like
        The 2-D image the clutter was measured on.
    result : targetacq.physics.clutter.ImageClutter
        Its result (the cells).
    boxes : array_like
        The (x, y, width, height) boxes.
    path : str or Path
        A .png file in an existing folder.
    """
    from PIL import Image, ImageDraw

    out, _ = output_path(path, ("png",), "the overlay file")
    values = np.asarray(image, dtype=np.float64)
    low, high = np.nanpercentile(values, [0.5, 99.5])
    scale = 255.0 / (high - low) if high > low else 0.0
    grey = np.clip((values - low) * scale, 0, 255).astype(np.uint8)
    canvas = Image.fromarray(grey).convert("RGB")
    draw = ImageDraw.Draw(canvas)
    for cells, used in zip(result.cells, result.cell_pixels, strict=True):
        for (x0, y0, x1, y1), n in zip(cells, used, strict=True):
            if n > 0:
                draw.rectangle([int(x0), int(y0), int(x1) - 1, int(y1) - 1], outline=(255, 220, 0))
    for k, (x, y, w, h) in enumerate(np.asarray(boxes, dtype=int).reshape(-1, 4)):
        draw.rectangle([x, y, x + w - 1, y + h - 1], outline=(255, 0, 0), width=2)
        draw.text((x, max(0, y - 11)), str(k), fill=(255, 0, 0))
    return write_atomically(out, lambda p: canvas.save(p, format="PNG"))
