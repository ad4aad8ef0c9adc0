"""The HTML report: content, self-containment, and rendering in a real headless browser."""

import base64
import io
import re
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from browser import BROWSER, screenshot, shows_figures
from targetacq.cli import main
from targetacq.core.cases import RangeCase
from targetacq.reports.content import performance_and_note

EXAMPLES = Path(__file__).parents[2] / "examples"

# 2 targets × 2 weathers: four cases in one report.
MULTI_ARGS = [
    "report",
    "--pitch",
    "12um",
    "--focal-length",
    "50mm",
    "--critical-dimension",
    "0.75m,2.3m",
    "--band",
    "lwir",
    "--obscurant",
    "haze:high,fog:low",
]
MULTI_LABELS = [
    "critical dimension 0.75 m, haze:high",
    "critical dimension 0.75 m, fog:low",
    "critical dimension 2.3 m, haze:high",
    "critical dimension 2.3 m, fog:low",
]


def _run(args, capsys=None):
    with pytest.raises(SystemExit) as done:
        main(args)
    return done.value.code


def _headings(page):
    return [re.sub(r"<.*?>", "", h) for h in re.findall(r"<h[12]>(.*?)</h[12]>", page)]


def _images(page):
    """The embedded figures, decoded."""
    found = re.findall(r"<img alt='[^']*' src='data:image/png;base64,([^']+)'>", page)
    return [
        np.asarray(Image.open(io.BytesIO(base64.b64decode(src))).convert("RGB")) for src in found
    ]


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
    scenario = str(Path(__file__).parents[2] / "examples" / "two_sensors_fused.toml")
    with pytest.raises(SystemExit) as done:
        main(["report", scenario, "--out", str(out)])
    assert done.value.code == 0
    page = out.read_text()
    for case in ("tv → truck", "thermal → soldier"):
        assert case in page
    assert "Table 7.1 haze" in page
    # Both bands in use (the TV's visible, the thermal camera's LWIR), the timeline (fused: two
    # sensors) and the simulated first times.
    headings = _headings(page)
    for heading in (
        "Atmosphere, visible band",
        "Atmosphere, lwir band",
        "Timeline",
        "Simulated first times",
    ):
        assert heading in headings
    assert page.count("data:image/png;base64,") == 6
    assert "HFOV × VFOV" in page and "critical dimension" in page
    assert "seed 0" in page
    assert "errata and assumptions: see the targetacq user guide" in page
    assert "A Probabilistic Approach to Conceptual Sensor Modeling" in page
    assert "https://www.diva-portal.org/smash/get/diva2:20633/FULLTEXT01.pdf" in page


@pytest.fixture(scope="module")
def multi_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("multi") / "report.html"
    assert _run([*MULTI_ARGS, "--out", str(out)]) == 0
    return out


def test_several_cases_in_one_report(multi_report):
    page = multi_report.read_text()
    table = page[page.index("<h2>DRI ranges [m]</h2>") :]
    table = table[: table.index("</table>")]
    for label in MULTI_LABELS:
        # One row per task and case in the one DRI table.
        assert (
            len(
                re.findall(
                    rf"<td>{re.escape(label)}</td><td>(detection|recognition|identification)</td>",
                    table,
                )
            )
            == 3
        )
    headings = _headings(page)
    # What differs between the cases is a column each (no "Cases" section stringing them).
    assert headings[1] == "Sensor" and "Cases" not in headings
    assert headings[-3:] == ["Range performance", "Transforms", "Atmosphere, lwir band"]
    assert "field of view" in page
    # Each case's critical dimension is printed, in its own column.
    for size in ("0.75 m", "2.3 m"):
        assert f"<td>{size} (smallest side seen" in page
    images = _images(page)
    assert len(images) == 3
    for image in images:  # every figure drawn: dark text and coloured curves on white
        assert np.mean(image.sum(axis=-1) < 300) > 0.002
        assert np.mean(image.std(axis=-1) > 40) > 0.002


def test_scenario_report_takes_probabilities(tmp_path):
    out = tmp_path / "r.html"
    args = ["report", str(EXAMPLES / "uav_haze.toml"), "--probability", "0.5,0.9"]
    assert _run([*args, "--max-range", "2km", "--title", "UAV", "--out", str(out)]) == 0
    page = out.read_text()
    header = re.search(r"<tr><th>case</th><th>task</th>(.*?)</tr>", page).group(1)
    assert header == "<th>50%</th><th>90%</th>"
    assert "<h1>UAV</h1>" in page
    assert "stop at 2 km (--max-range 2km)" in page  # P(detection) is still high at 2 km


def test_scenario_report_refuses_sensor_options(tmp_path, capsys):
    args = ["report", str(EXAMPLES / "uav_haze.toml"), "--pitch", "12um"]
    assert _run([*args, "--out", str(tmp_path / "r.html")]) == 2
    err = capsys.readouterr().err
    assert "--pitch" in err and "--probability, --max-range and --title" in err


def test_curves_cover_every_dri_range_and_stop_a_quarter_beyond_the_farthest():
    """The default axis shows every answer of the table (the DRI ranges) without squeezing
    them into its first few per cent: it ends 25 % beyond the farthest one."""
    cases = {
        "clear": RangeCase(2.3, 2e-4),
        "haze": RangeCase(2.3, 2e-4, extinction=0.4e-3, scr=3.0),
        "person": RangeCase(0.75, 2.4e-4, extinction=1e-3),
    }
    performance, note = performance_and_note(cases, None, [0.5, 0.9])
    dri = performance.dri
    farthest = float(dri["range_m"][dri["reached"] & np.isfinite(dri["range_m"])].max())
    end = float(performance.curves["range"][-1])
    assert end == pytest.approx(1.25 * farthest, rel=1e-9)
    assert "a quarter beyond the farthest DRI range" in note
    _, note = performance_and_note(cases, "2km", [0.5])
    assert "stop at 2 km (--max-range 2km)" in note and "P(detection)" in note


def test_curves_of_a_case_that_reaches_no_probability_go_on_until_every_task_is_below_2_percent():
    # In high clutter (SCR 0.2) detection never reaches 0.99 (Table 3.5): no finite answer.
    cases = {"clutter": RangeCase(2.3, 2e-4, scr=0.2)}
    performance, note = performance_and_note(cases, None, [0.99])
    assert not performance.dri["reached"].any()
    last = performance.curves.isel(range=-1)
    for task in ("detection", "recognition", "identification"):
        assert float(last[task].max()) < 0.02, task
    assert "below 2%" in note


@pytest.mark.skipif(BROWSER is None, reason="no Chromium installed (.ci/run installs Debian's)")
def test_several_cases_render_in_headless_chromium(multi_report, tmp_path):
    image = screenshot(multi_report, tmp_path, 5200)
    assert shows_figures(image)


@pytest.mark.skipif(BROWSER is None, reason="no Chromium installed (.ci/run installs Debian's)")
def test_pdf_report_has_the_sections_and_figures_of_the_html(multi_report, tmp_path):
    from pypdf import PdfReader

    pdf = tmp_path / "report.pdf"
    assert _run([*MULTI_ARGS, "--out", str(pdf)]) == 0
    assert pdf.read_bytes().startswith(b"%PDF")
    reader = PdfReader(pdf)
    text = re.sub(r"\s+", " ", " ".join(page.extract_text() for page in reader.pages))
    headings = _headings(multi_report.read_text())
    assert len(headings) == 9  # title, 4 sections, the DRI table, 3 figures (no "Cases")
    position = 0
    for heading in headings:  # every heading, in the HTML's order
        found = text.find(heading.replace("&amp;", "&"), position)
        assert found >= 0, heading
        position = found
    images = [image for page in reader.pages for image in page.images]
    assert len(images) == len(_images(multi_report.read_text()))


def test_pdf_without_a_browser_says_what_to_install(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("TARGETACQ_BROWSER", str(tmp_path / "no-such-browser"))
    out = tmp_path / "report.pdf"
    assert _run([*MULTI_ARGS, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0
    assert "chromium package" in err
    assert not out.exists()
