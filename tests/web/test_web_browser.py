"""The explorer page in a real browser: the app served by uvicorn, driven by Playwright.

Runs Debian's Chromium headless (installed by .ci/run); skipped where no Chromium is found.
"""

import csv
import io
import json
import shutil
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

BROWSER = shutil.which("chromium") or shutil.which("chromium-browser")
if BROWSER is None:
    pytest.skip("no Chromium (chromium, chromium-browser) on the PATH", allow_module_level=True)

import uvicorn  # noqa: E402
from playwright.sync_api import sync_playwright  # noqa: E402

from targetacq.scenario.schema import load_scenario  # noqa: E402
from targetacq.web.api import create_app  # noqa: E402

ROOT = Path(__file__).parents[2]
SCENARIO = ROOT / "examples" / "two_sensors_fused.toml"
SCREENSHOT = ROOT / "build" / "web-explorer.png"
WAIT_MS = 30_000

DETECTION_AT_HALF = 'tr[data-task="detection"] td[data-probability="0.5"]'


@pytest.fixture(scope="module")
def base_url():
    """The real app on a free port (uvicorn picks it), stopped after the module's tests."""
    config = uvicorn.Config(create_app(), host="127.0.0.1", port=0, log_level="warning")
    server = uvicorn.Server(config)
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    deadline = time.monotonic() + 30
    while not server.started:
        if not thread.is_alive() or time.monotonic() > deadline:
            server.should_exit = True
            thread.join(10)
            pytest.fail("the explorer app did not start")
        time.sleep(0.05)
    port = server.servers[0].sockets[0].getsockname()[1]
    try:
        yield f"http://127.0.0.1:{port}"
    finally:
        server.should_exit = True
        thread.join(30)


@pytest.fixture
def page(base_url):
    """A fresh page of headless Chromium on the explorer; fails the test on any script error."""
    script_errors = []
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=BROWSER, headless=True, args=["--no-sandbox"])
        try:
            page = browser.new_page(viewport={"width": 1280, "height": 900})
            page.on("pageerror", lambda error: script_errors.append(str(error)))
            page.goto(f"{base_url}/")
            yield page
        finally:
            browser.close()
    assert script_errors == []


def cli_detection_range(focal_length):
    """The detection range at P = 0.5 that `targetacq dri --format json` prints."""
    args = ["--pitch", "17um", "--focal-length", focal_length, "--critical-dimension", "2.3m"]
    done = subprocess.run(
        [sys.executable, "-m", "targetacq", "dri", *args, "--format", "json"],
        capture_output=True,
        text=True,
        check=True,
        timeout=120,
    )
    ranges = json.loads(done.stdout)["ranges"]
    (row,) = [r for r in ranges if r["task"] == "detection" and r["probability"] == 0.5]
    return row["range_m"]


def shown_detection_range(page):
    return float(page.get_attribute(DETECTION_AT_HALF, "data-range-m"))


def wait_for_range(page, *, near=None, away_from=None):
    """Wait until the table's detection range at P = 0.5 is ``near`` a value (or leaves one)."""
    page.wait_for_function(
        """([selector, near, away]) => {
            const cell = document.querySelector(selector);
            if (!cell || !cell.dataset.rangeM) return false;
            const value = Number(cell.dataset.rangeM);
            if (near !== null && Math.abs(value - near) > 1e-9 * Math.abs(near)) return false;
            return away === null || value !== away;
        }""",
        arg=[DETECTION_AT_HALF, near, away_from],
        timeout=WAIT_MS,
    )


def curve_cases(page):
    return set(page.eval_on_selector_all("path.curve", "paths => paths.map(p => p.dataset.case)"))


def test_explorer_page(page):
    at_50mm = cli_detection_range("50mm")
    at_100mm = cli_detection_range("100mm")
    assert at_100mm != pytest.approx(at_50mm, rel=1e-6)

    # The form, filled as the CLI's options; the table follows it.
    page.wait_for_selector("#band option:nth-child(2)", state="attached", timeout=WAIT_MS)
    page.fill("#pitch", "17um")
    page.fill("#focal_length", "50mm")
    page.fill("#critical_dimension", "2.3m")
    page.fill("#probability", "0.5,0.8")
    wait_for_range(page, near=at_50mm)
    assert page.locator("#dri-table tbody tr").count() >= 3
    assert page.get_attribute('label[for="focal_length"]', "for") == "focal_length"

    page.fill("#focal_length", "100mm")
    wait_for_range(page, away_from=shown_detection_range(page))
    shown = shown_detection_range(page)
    assert shown == pytest.approx(at_100mm, rel=1e-9)
    assert shown != pytest.approx(at_50mm, rel=1e-6)
    labels = page.eval_on_selector_all("#curves .axis-label", "ts => ts.map(t => t.textContent)")
    assert labels == ["slant range [km]", "P"]
    assert curve_cases(page) == {"live"}

    # A frozen configuration beside the live one.
    page.click("#add-comparison")
    page.fill("#focal_length", "75mm")
    wait_for_range(page, away_from=at_100mm)
    assert len(curve_cases(page)) == 2
    assert page.locator("#legend li[data-case]").count() == 2
    page.click("#clear-comparison")
    assert curve_cases(page) == {"live"}

    # A value without its unit: the message beside the field, gone once fixed.
    pitch_error = ".error[data-for=pitch]"
    page.fill("#pitch", "17")
    page.wait_for_function(
        f"document.querySelector('{pitch_error}').textContent.trim() !== ''", timeout=WAIT_MS
    )
    page.fill("#pitch", "17um")
    page.wait_for_function(
        f"document.querySelector('{pitch_error}').textContent.trim() === ''", timeout=WAIT_MS
    )

    # A scenario: one fused-detection path per target, and the downloads offered.
    names = [target.name for target in load_scenario(SCENARIO).targets]
    page.set_input_files("#scenario-file", str(SCENARIO))
    page.wait_for_function(
        "n => document.querySelectorAll('path.timeline').length === n",
        arg=len(names),
        timeout=WAIT_MS,
    )
    shown_targets = page.eval_on_selector_all(
        "path.timeline", "paths => paths.map(p => p.dataset.target)"
    )
    assert sorted(shown_targets) == sorted(names)
    assert page.locator("#scenario-errors li").count() == 0
    assert page.locator("#scenario-warnings li").count() == 0
    assert page.is_enabled("#download-csv")

    SCREENSHOT.parent.mkdir(exist_ok=True)
    page.screenshot(path=str(SCREENSHOT), full_page=True)
    assert SCREENSHOT.stat().st_size > 10_000


def wait_for_case(page, **options):
    """Wait until the table and curves show a case with these options (``None``: left out)."""
    page.wait_for_function(
        """expected => {
            const shown = document.getElementById("results").dataset.shown;
            if (!shown) return false;
            const options = JSON.parse(shown);
            const same = ([key, value]) => (options[key] ?? null) === value;
            return Object.entries(expected).every(same);
        }""",
        arg=options,
        timeout=WAIT_MS,
    )


def field_errors(page):
    """The messages beside the form's fields that are not empty."""
    return page.eval_on_selector_all(
        "#case-form .error",
        "spans => spans.map(s => s.textContent.trim()).filter(Boolean)",
    )


def wait_for_registries(page):
    page.wait_for_selector("#transform option:nth-child(2)", state="attached", timeout=WAIT_MS)


def test_detection_only_transform_keeps_the_table(page):
    """A transform for detection alone: the table shows, the curves lack what it cannot give."""
    wait_for_registries(page)
    page.select_option("#transform", "schmieder-weathersby")
    page.fill("#scr", "2")
    wait_for_case(page, transform="schmieder-weathersby", scr="2")
    assert page.locator('#dri-table tr[data-task="detection"]').count() >= 1
    assert shown_detection_range(page) > 0
    assert "stale" not in (page.get_attribute("#results", "class") or "")
    assert field_errors(page) == []
    live = page.eval_on_selector_all(
        'path.curve[data-case="live"]', "paths => paths.map(p => p.dataset.task)"
    )
    assert set(live) <= {"detection"}
    if not live:  # no curves for this case (null tasks or a 422): the reason is shown
        assert page.text_content("#status").strip().startswith("No curves: ")


def test_visibility_with_its_convention(page):
    wait_for_registries(page)
    options = page.eval_on_selector_all(
        "#visibility_convention option", "os => os.map(o => o.value)"
    )
    assert {"koschmieder", "mor"} <= set(options)
    page.select_option("#visibility_convention", "koschmieder")
    page.fill("#visibility", "10km")
    wait_for_case(page, visibility="10km", visibility_convention="koschmieder")
    assert page.text_content(".error[data-for=visibility]").strip() == ""
    assert field_errors(page) == []
    assert page.text_content("#status").strip() == ""
    assert shown_detection_range(page) > 0

    # Back to none: the convention is not sent at all.
    page.fill("#visibility", "")
    page.select_option("#visibility_convention", "")
    wait_for_case(page, visibility=None, visibility_convention=None)
    assert field_errors(page) == []


def registries(page):
    return page.evaluate("fetch('/registries').then(r => r.json())")


def test_named_target_disables_the_critical_dimension(page):
    page.wait_for_selector("#target option:nth-child(2)", state="attached", timeout=WAIT_MS)
    name = page.eval_on_selector("#target option:nth-child(2)", "o => o.value")
    assert page.input_value("#critical_dimension") == "2.3m"
    page.select_option("#target", name)
    assert page.is_disabled("#critical_dimension")
    (listed,) = [t for t in registries(page)["targets"] if t["name"] == name]
    assert page.input_value("#critical_dimension") == f"{listed['critical_dimension_m']:g}m"
    wait_for_case(page, target=name, critical_dimension=None)
    assert field_errors(page) == []
    assert page.text_content("#status").strip() == ""
    assert shown_detection_range(page) > 0

    # Back to none: the field is enabled and given its value again.
    page.select_option("#target", "")
    assert page.is_enabled("#critical_dimension")
    assert page.input_value("#critical_dimension") == "2.3m"
    wait_for_case(page, target=None, critical_dimension="2.3m")
    assert field_errors(page) == []


def test_a_unit_slip_in_a_scenario_is_shown_as_a_warning(page, tmp_path):
    text = SCENARIO.read_text(encoding="utf-8")
    slip = tmp_path / "slip.toml"
    slip.write_text(text.replace('pitch = "12 um"', 'pitch = "12 m"', 1), encoding="utf-8")
    assert slip.read_text(encoding="utf-8") != text
    page.set_input_files("#scenario-file", str(slip))
    page.wait_for_function(
        "() => document.querySelectorAll('#scenario-warnings li').length === 1", timeout=WAIT_MS
    )
    shown = page.locator("#scenario-warnings li").inner_text()
    assert shown.startswith("warning: sensors[1].pitch: 12 m is 1 mm or more")
    # The scenario still runs: its timeline is drawn, and the downloads offered.
    page.wait_for_function("() => document.querySelectorAll('path.timeline').length > 0")
    assert page.is_enabled("#download-csv")
    page.set_input_files("#scenario-file", str(SCENARIO))
    page.wait_for_function(
        "() => document.querySelectorAll('#scenario-warnings li').length === 0", timeout=WAIT_MS
    )


def test_the_disabled_box_shows_the_persons_critical_dimension(page):
    """The box shows the 0.75 m used for `person` (from /registries), not the 2.3 m typed."""
    wait_for_registries(page)
    (person,) = [t for t in registries(page)["targets"] if t["name"] == "person"]
    assert person["critical_dimension_m"] == 0.75
    page.select_option("#target", "person")
    assert page.is_disabled("#critical_dimension")
    assert page.input_value("#critical_dimension") == "0.75m"
    wait_for_case(page, target="person", critical_dimension=None)
    page.select_option("#target", "vehicle")
    assert page.input_value("#critical_dimension") == "2.3m"
    page.select_option("#target", "")
    assert page.is_enabled("#critical_dimension")
    wait_for_case(page, target=None, critical_dimension="2.3m")


def table_cells(page):
    """Every cell of the DRI table: (task, probability, range [m] as the page holds it)."""
    return page.eval_on_selector_all(
        "#dri-table td",
        "tds => tds.map(td => [td.parentElement.dataset.task, td.dataset.probability,"
        " td.dataset.rangeM])",
    )


def fill_a_case(page):
    wait_for_registries(page)
    page.fill("#pitch", "17um")
    page.fill("#focal_length", "75mm")
    page.fill("#probability", "0.5,0.9")
    page.select_option("#band", "lwir")
    page.select_option("#obscurant", "haze")
    wait_for_case(page, focal_length="75mm", probability="0.5,0.9", obscurant="haze", band="lwir")


def test_a_shared_url_restores_the_form_and_its_table(page):
    fill_a_case(page)
    shared = page.url
    assert "focal_length=75mm" in shared and "obscurant=haze" in shared and "band=lwir" in shared
    shown = json.loads(page.get_attribute("#results", "data-shown"))
    cells = table_cells(page)
    assert len(cells) >= 6 and all(range_m for _, _, range_m in cells)

    other = page.context.browser.new_page()
    other.goto(shared)
    wait_for_case(other, **shown)
    assert json.loads(other.get_attribute("#results", "data-shown")) == shown
    for name, value in [("#focal_length", "75mm"), ("#obscurant", "haze"), ("#band", "lwir")]:
        assert other.input_value(name) == value
    assert table_cells(other) == cells
    assert other.url == shared

    # A shared named target: the box shows its dimension, and the case is the same.
    page.select_option("#target", "person")
    wait_for_case(page, target="person", critical_dimension=None)
    third = page.context.browser.new_page()
    third.goto(page.url)
    wait_for_case(third, target="person", critical_dimension=None, focal_length="75mm")
    assert third.is_disabled("#critical_dimension")
    assert third.input_value("#critical_dimension") == "0.75m"
    assert table_cells(third) == table_cells(page)


def downloaded(page, button):
    with page.expect_download(timeout=WAIT_MS) as info:
        page.click(button)
    return info.value.suggested_filename, Path(info.value.path()).read_text(encoding="utf-8")


def test_the_forms_case_downloads_as_the_table_and_the_curves(page):
    fill_a_case(page)
    cells = {(task, p): float(r) for task, p, r in table_cells(page)}

    name, text = downloaded(page, "#download-dri-csv")
    assert name == "dri.csv"
    rows = list(csv.DictReader(io.StringIO(text)))
    assert {(r["task"], str(float(r["probability"]))): float(r["range_m"]) for r in rows} == {
        (task, str(float(p))): r for (task, p), r in cells.items()
    }

    name, text = downloaded(page, "#download-dri-json")
    assert name == "dri.json"
    report = json.loads(text)
    got = {(r["task"], r["probability"]): r["range_m"] for r in report["ranges"]}
    assert got == {(task, float(p)): r for (task, p), r in cells.items()}

    name, text = downloaded(page, "#download-curves-csv")
    assert name == "curves.csv"
    rows = list(csv.DictReader(io.StringIO(text)))
    assert len(rows) == 200 and list(rows[0]) == [
        "range_m",
        "p_detection",
        "p_recognition",
        "p_identification",
    ]
    ranges = [float(r["range_m"]) for r in rows]
    assert ranges == sorted(ranges) and all(0 <= float(r["p_detection"]) <= 1 for r in rows)

    name, text = downloaded(page, "#download-curves-svg")
    assert name == "curves.svg" and text.startswith("<svg")
    assert 'class="curve"' in text and "slant range [km]" in text
