"""The HTML report: content, self-containment, and rendering in a real headless browser."""

import re
import shutil
import subprocess
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from targetacq.cli import main

BROWSER = shutil.which("chromium") or shutil.which("chromium-browser")
REPORT_ARGS = [
    "report",
    "--example",
    "--band",
    "lwir",
    "--target-temperature",
    "305K",
    "--background-temperature",
    "295K",
    "--clutter-std",
    "2K",
    "--obscurant",
    "haze:high",
]


@pytest.fixture(scope="module")
def report_file(tmp_path_factory):
    out = tmp_path_factory.mktemp("report") / "report.html"
    with pytest.raises(SystemExit) as done:
        main([*REPORT_ARGS, "--out", str(out)])
    assert done.value.code == 0
    return out


class _Collector(HTMLParser):
    def __init__(self):
        super().__init__()
        self.images, self.links = [], []

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag == "img":
            self.images.append(attrs.get("src", ""))
        if tag in ("link", "script") and (attrs.get("href") or attrs.get("src")):
            self.links.append(attrs)


def test_report_content(report_file):
    page = report_file.read_text()
    for needle in (
        "50%",
        "80%",
        "95%",
        "detection",
        "identification",
        "Table 7.1",
        "Table 3.2",
        "NVESD",
        "variance-sum",
        "critical dimension",
    ):
        assert needle in page, needle
    parser = _Collector()
    parser.feed(page)
    assert len(parser.images) == 3  # curves, transforms, atmosphere
    assert all(src.startswith("data:image/png;base64,") for src in parser.images)
    assert parser.links == []  # self-contained: no external style sheets or scripts
    # The DRI row for detection has three ranges in metres.
    row = re.search(r"<td>detection</td>(.*?)</tr>", page).group(1)
    assert len(re.findall(r'class="num">[\d,]+<', row)) == 3


@pytest.mark.skipif(BROWSER is None, reason="no Chromium installed (.ci/run installs Debian's)")
def test_report_renders_in_headless_chromium(report_file, tmp_path):
    shot = tmp_path / "shot.png"
    subprocess.run(
        [
            BROWSER,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            f"--user-data-dir={tmp_path / 'profile'}",
            "--window-size=1200,2400",
            f"--screenshot={shot}",
            report_file.as_uri(),
        ],
        check=True,
        capture_output=True,
        timeout=120,
    )
    image = np.asarray(Image.open(shot).convert("RGB")).astype(int)
    assert image.shape[:2] == (2400, 1200)
    # The page is not blank: text and the embedded figures' curves are drawn.
    assert np.mean(image.sum(axis=-1) < 600) > 0.01
    detection_blue = np.array([0x1F, 0x77, 0xB4])
    assert np.sum(np.all(np.abs(image - detection_blue) < 20, axis=-1)) > 200


def test_report_of_a_scenario(tmp_path):
    out = tmp_path / "scenario.html"
    scenario = str(Path(__file__).parents[1] / "examples" / "two_sensors_fused.toml")
    with pytest.raises(SystemExit) as done:
        main(["report", scenario, "--out", str(out)])
    assert done.value.code == 0
    page = out.read_text()
    for case in ("tv → truck", "thermal → soldier"):
        assert case in page
    assert "Table 7.1 haze" in page
    assert page.count("data:image/png;base64,") == 3
