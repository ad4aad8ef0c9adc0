"""The HTML report: content, self-containment, and rendering in a real headless browser."""

import re
from html.parser import HTMLParser
from pathlib import Path

import pytest

from browser import BROWSER, screenshot, shows_figures
from targetacq.cli import main

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
    image = screenshot(report_file, tmp_path, 2400)
    assert shows_figures(image)


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
