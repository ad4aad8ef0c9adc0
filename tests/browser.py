"""Headless Chromium for the tests that render a page (Debian's browser, installed by .ci/run)."""

import shutil
import subprocess

import numpy as np
from PIL import Image

from targetacq.io.html_report import HEADLESS_CHROMIUM_FLAGS

BROWSER = shutil.which("chromium") or shutil.which("chromium-browser")

DETECTION_BLUE = np.array([0x1F, 0x77, 0xB4])  # the detection curves' colour in the figures


def screenshot(page, tmp_path, height):
    """Render ``page`` (a file) 1200 px wide and ``height`` px high; the RGB pixels as ints."""
    shot = tmp_path / "shot.png"
    subprocess.run(
        [
            BROWSER,
            *HEADLESS_CHROMIUM_FLAGS,
            f"--user-data-dir={tmp_path / 'profile'}",
            f"--window-size=1200,{height}",
            f"--screenshot={shot}",
            page.as_uri(),
        ],
        check=True,
        capture_output=True,
        timeout=120,
    )
    image = np.asarray(Image.open(shot).convert("RGB")).astype(int)
    assert image.shape[:2] == (height, 1200)
    return image


def shows_figures(image):
    """Not blank: text and rules drawn, and the detection curves of the figures on screen."""
    dark = np.mean(image.sum(axis=-1) < 600) > 0.01
    blue = np.sum(np.all(np.abs(image - DETECTION_BLUE) < 20, axis=-1)) > 200
    return bool(dark and blue)
