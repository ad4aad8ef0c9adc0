"""The JSON API of the web explorer (targetacq.web.api) and `targetacq serve`."""

import csv
import io
import itertools
import json
import math
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("fastapi")

with warnings.catch_warnings():
    # Starlette's test client announces its move to httpx2; the project tests with httpx.
    warnings.filterwarnings("ignore", message="Using `httpx` with `starlette.testclient`")
    from fastapi.testclient import TestClient

from targetacq import Simulation
from targetacq.acquisition.transforms import TRANSFORMS
from targetacq.run.model_chain import ModelChain
from targetacq.scenario.schema import load_scenario
from targetacq.sensors import SENSOR_TYPES
from targetacq.web.api import MAX_SESSIONS, create_app

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
FUSED = EXAMPLES / "two_sensors_fused.toml"


def _local(app, **options):
    """A test client whose requests are addressed to 127.0.0.1 (the app answers loopback names
    only, by default)."""
    return TestClient(app, base_url="http://127.0.0.1", **options)


@pytest.fixture(scope="module")
def client():
    # raise_server_exceptions: a handler that fails with a bug raises here, so any test below
    # that reached the 500 handler would fail rather than see a 500.
    with _local(create_app(max_body_bytes=200_000, max_elements=1_000)) as c:
        yield c


def _cli_dri(options):
    args = [sys.executable, "-m", "targetacq", "dri", "--format", "json"]
    for name, value in options.items():
        flag = "--" + name.replace("_", "-")
        args += [flag] if value is True else [flag, value]
    done = subprocess.run(args, capture_output=True, text=True, check=True)
    return json.loads(done.stdout)


@pytest.mark.parametrize(
    "options",
    [
        {"pitch": "17um", "focal_length": "50mm", "critical_dimension": "2.3m"},
        {"hfov": "12deg", "pixels": "640", "critical_dimension": "0.75m", "probability": "0.5,0.9"},
        {
            "pitch": "17um",
            "focal_length": "50mm",
            "critical_dimension": "2.3m",
            "probability": "0.5,0.8",
            "obscurant": "haze",
            "netd": "50mK",
            "delta_t": "2K",
            "band": "lwir",
        },
        {"example": True, "target": "person", "criterion": "johnson", "transform": "ttpf"},
    ],
)
def test_dri_is_what_the_cli_prints(client, options):
    response = client.post("/dri", json=options)
    assert response.status_code == 200, response.text
    assert response.headers["content-type"] == "application/json"
    assert response.json() == _cli_dri(options)


def test_dri_with_uncertainty_is_what_the_cli_prints(client):
    options = {
        "example": True,
        "netd": "50mK",
        "delta_t": "2K",
        "uncertainty": "200",
        "seed": "3",
        "netd_spread": "10%",
    }
    response = client.post("/dri", json=options)
    assert response.status_code == 200, response.text
    answer = response.json()
    assert answer == _cli_dri(options)
    row = answer["ranges"][0]
    assert row["range_p05_m"] < row["range_m"] < row["range_p95_m"]


@pytest.mark.parametrize(
    ("extra", "field", "message"),
    [
        ({"uncertainty": "5"}, "uncertainty", "--uncertainty must be a whole number"),
        ({"uncertainty": "200", "n50_spread": "0.25"}, "n50_spread", "--n50-spread"),
        ({"netd_spread": "10%"}, "netd_spread", "go with --uncertainty"),
        ({"uncertainty": "6000"}, "uncertainty", "at most 5000 samples over HTTP"),
    ],
)
def test_dri_uncertainty_errors_are_located(client, extra, field, message):
    (item,) = _problem(client.post("/dri", json={"example": True, **extra}))
    assert item["loc"] == ["body", field] and message in item["msg"]


def test_dri_takes_numbers_for_numeric_options(client):
    given = {"hfov": "12deg", "pixels": 640, "critical_dimension": "2.3m", "scr": 2.5}
    response = client.post("/dri", json=given)
    assert response.status_code == 200, response.text
    texts = {**given, "pixels": "640", "scr": "2.5"}
    assert response.json() == _cli_dri(texts)


def _problem(response, status=422):
    assert response.status_code == status, response.text
    detail = response.json()["detail"]
    assert isinstance(detail, list)
    assert detail
    assert all(set(item) >= {"loc", "msg"} for item in detail)
    return detail


def test_malformed_json_is_refused(client):
    response = client.post(
        "/dri", content=b'{"pitch": ', headers={"content-type": "application/json"}
    )
    (item,) = _problem(response)
    assert "malformed JSON" in item["msg"]
    (item,) = _problem(client.post("/dri", json=[1, 2]))
    assert item["loc"] == ["body"]


def test_a_value_without_its_unit_is_located(client):
    body = {"pitch": "17", "focal_length": "50mm", "critical_dimension": "2.3m"}
    (item,) = _problem(client.post("/dri", json=body))
    assert item["loc"] == ["body", "pitch"]
    assert "--pitch" in item["msg"]


def test_an_unknown_field_is_named_with_a_close_match(client):
    (item,) = _problem(client.post("/dri", json={"pitchh": "17um"}))
    assert item["loc"] == ["body", "pitchh"]
    assert "did you mean 'pitch'" in item["msg"]
    detail = _problem(client.post("/step", json=_step_body(sesion="x")))
    assert [item["loc"] for item in detail] == [["body", "sesion"]]
    assert "did you mean 'session'" in detail[0]["msg"]


def test_lists_a_file_and_a_boolean_text_are_refused_for_dri(client):
    base = {"focal_length": "50mm", "critical_dimension": "2.3m"}
    (item,) = _problem(client.post("/dri", json={**base, "pitch": "17um,12um"}))
    assert item["loc"] == ["body", "pitch"]
    assert "one value per option" in item["msg"]
    (item,) = _problem(client.post("/dri", json={**base, "pitch": "17um", "mrtd": "/etc/passwd"}))
    assert item["loc"] == ["body", "mrtd"]
    assert "files are not read over HTTP" in item["msg"]
    _problem(client.post("/dri", json={**base, "pitch": True}))


def test_a_huge_body_is_413_naming_the_limit(client):
    body = b'{"pitch": "' + b"x" * 300_000 + b'"}'
    response = client.post("/dri", content=body, headers={"content-type": "application/json"})
    (item,) = _problem(response, 413)
    assert "200,000 bytes" in item["msg"]


def test_a_body_streamed_past_the_limit_is_413():
    app = create_app(max_body_bytes=100)

    def chunks():
        for _ in range(10):
            yield b" " * 50

    with _local(app) as c:
        response = c.post("/dri", content=chunks(), headers={"content-type": "application/json"})
    assert response.status_code == 413


def _step_body(**extra):
    body = {
        "time": 0.0,
        "dt": 0.0,
        "sensor_positions": [[0.0, 0.0, 15.0], [0.0, 0.0, 15.0]],
        "target_positions": [[2000.0, 0.0, 0.0], [1800.0, 50.0, 0.0]],
    }
    return {**body, **extra}


def test_a_huge_array_in_step_is_refused_naming_the_field(client):
    body = _step_body(scenario=FUSED.read_text(), target_positions=[[1.0, 2.0, 0.0]] * 400)
    (item,) = _problem(client.post("/step", json=body))
    assert item["loc"] == ["body", "target_positions"]
    assert "1,000" in item["msg"]


def test_a_toml_syntax_error_is_refused(client):
    (item,) = _problem(client.post("/evaluate", json={"scenario": "name = \n[[["}))
    assert item["loc"] == ["body", "scenario"]
    assert "malformed TOML" in item["msg"]


def test_a_scenario_problem_is_located_in_the_scenario(client):
    text = FUSED.read_text().replace('temperature = "306 K"', 'temperature = "306"')
    detail = _problem(client.post("/evaluate", json={"scenario": text}))
    assert ["scenario", "targets[0].temperature"] in [item["loc"] for item in detail]
    assert all(not item["msg"].startswith("scenario:") for item in detail)


@pytest.mark.parametrize(
    ("table", "key"),
    [
        ('image = "/etc/passwd"', "image"),
        ('terrain = { map = "/etc/passwd", classes = [] }', "terrain"),
    ],
)
@pytest.mark.parametrize("path", ["/evaluate", "/report", "/step"])
def test_a_scenario_naming_a_file_is_refused(client, table, key, path):
    text = FUSED.read_text().replace('clutter = "medium"', table)
    body = _step_body(scenario=text) if path == "/step" else {"scenario": text}
    (item,) = _problem(client.post(path, json=body))
    assert item["loc"] == ["scenario", f"background.{key}"]
    assert "files are not read over HTTP" in item["msg"]


@pytest.mark.parametrize("path", ["/evaluate", "/report", "/step"])
def test_a_scenario_naming_an_elevation_model_is_refused(client, path):
    table = '\n[terrain]\nelevation = "/etc/passwd.npy"\nspacing = "1 m"\norigin = ["0 m", "0 m"]\n'
    text = FUSED.read_text() + table
    body = _step_body(scenario=text) if path == "/step" else {"scenario": text}
    (item,) = _problem(client.post(path, json=body))
    assert item["loc"] == ["scenario", "terrain.elevation"]
    assert "files are not read over HTTP" in item["msg"]


@pytest.mark.parametrize("path", ["/evaluate", "/report", "/step"])
def test_a_scenario_naming_an_mrtd_curve_is_refused(client, path):
    text = FUSED.read_text().replace('name = "thermal"', 'name = "thermal"\nmrtd = "/etc/passwd"')
    assert 'mrtd = "/etc/passwd"' in text
    body = _step_body(scenario=text) if path == "/step" else {"scenario": text}
    (item,) = _problem(client.post(path, json=body))
    assert item["loc"] == ["scenario", "sensors[1].mrtd"]
    assert "files are not read over HTTP" in item["msg"]


@pytest.mark.parametrize("path", ["/evaluate", "/step"])
def test_a_scenario_naming_a_signature_table_file_is_refused(client, path):
    text = FUSED.read_text().replace(
        'temperature = "306 K"', 'temperature = "306 K"\nsignature_table = "/etc/passwd"'
    )
    body = _step_body(scenario=text) if path == "/step" else {"scenario": text}
    (item,) = _problem(client.post(path, json=body))
    assert item["loc"] == ["scenario", "targets[0].signature_table"]
    assert "files are not read over HTTP" in item["msg"]


def test_a_signature_table_written_in_the_scenario_is_evaluated(client):
    # The truck 2 km east of the mast, seen head-on (heading west, 270 deg: 293.2 K in the
    # table, 0.2 K over the background) or from the rear (heading east, 90 deg: 316 K) by a
    # camera of 50 mK: the thermal camera's detection differs, the TV camera's (reflectance,
    # which the table does not change) does not.
    table = (
        'signature_table = { azimuth = ["0 deg", "180 deg"], elevation = ["0 deg"], '
        'temperature = [["293.2 K"], ["316 K"]] }'
    )
    text = (
        FUSED.read_text()
        .replace('temperature = "306 K"', table)
        .replace('aperture = "100 mm"', 'aperture = "100 mm"\nnetd = "50 mK"')
    )
    answers = []
    for heading in (1.5 * math.pi, 0.5 * math.pi):
        body = _step_body(scenario=text, target_headings=[heading, 0.0])
        response = client.post("/step", json=body)
        assert response.status_code == 200, response.text
        answers.append(np.array(response.json()["detection"]))
    front, rear = answers
    assert rear[1, 0] > front[1, 0]  # thermal: warmer from the rear
    assert rear[0, 0] == pytest.approx(front[0, 0], rel=1e-12)  # TV: the same


def test_an_unknown_session_is_404(client):
    (item,) = _problem(client.post("/step", json=_step_body(session="nope")), 404)
    assert "unknown session 'nope'" in item["msg"]


def test_a_step_without_session_or_scenario_is_refused(client):
    (item,) = _problem(client.post("/step", json=_step_body()))
    assert item["loc"] == ["body", "scenario"]


def test_a_step_with_wrong_shapes_is_422(client):
    body = _step_body(scenario=FUSED.read_text(), sensor_positions=[[0.0, 0.0]])
    _problem(client.post("/step", json=body))


def test_evaluate_json_is_the_model_chain(client):
    response = client.post("/evaluate", json={"scenario": FUSED.read_text()})
    assert response.status_code == 200, response.text
    got = response.json()
    ds = ModelChain(load_scenario(FUSED)).evaluate().dataset
    assert got["sensors"] == list(ds["sensor"].values)
    assert got["targets"] == list(ds["target"].values)
    np.testing.assert_array_equal(got["time_s"], ds["time"].values)
    np.testing.assert_array_equal(
        got["fused_detection"], ds["fused_detection"].transpose("target", "time").values
    )
    np.testing.assert_array_equal(
        got["detection"], ds["detection"].transpose("sensor", "target", "time").values
    )


def test_evaluate_csv_is_a_download(client):
    body = {"scenario": FUSED.read_text(), "format": "csv"}
    response = client.post("/evaluate", json=body)
    assert response.status_code == 200, response.text
    assert response.headers["content-disposition"] == "attachment; filename=results.csv"
    assert response.text.startswith("# units: ")  # units and provenance before the table
    table = "".join(line for line in response.text.splitlines(True) if not line.startswith("#"))
    rows = list(csv.DictReader(io.StringIO(table)))
    frame = ModelChain(load_scenario(FUSED)).evaluate().to_dataframe()
    assert len(rows) == len(frame)
    assert float(rows[-1]["fused_detection"]) == pytest.approx(frame["fused_detection"].iloc[-1])


def test_evaluate_parquet_is_a_download(client):
    pytest.importorskip("pyarrow")
    response = client.post("/evaluate", json={"scenario": FUSED.read_text(), "format": "parquet"})
    assert response.status_code == 200, response.text
    assert response.headers["content-disposition"] == "attachment; filename=results.parquet"
    assert response.content[:4] == b"PAR1"


def test_step_is_the_simulation_for_two_steps(client):
    text = FUSED.read_text()
    first = client.post("/step", json=_step_body(scenario=text, seed=3))
    assert first.status_code == 200, first.text
    session = first.json()["session"]
    moved = [[1500.0, 0.0, 0.0], [1800.0, 50.0, 0.0]]
    second = client.post(
        "/step", json=_step_body(session=session, time=5.0, dt=5.0, target_positions=moved)
    )
    assert second.status_code == 200, second.text
    sim = Simulation.from_scenario(FUSED, seed=3)
    body = _step_body()
    expected = [
        sim.step(0.0, 0.0, body["sensor_positions"], body["target_positions"]),
        sim.step(5.0, 5.0, body["sensor_positions"], moved),
    ]
    for response, result in zip((first, second), expected, strict=True):
        got = response.json()
        assert got["session"] == session
        assert got["sensors"] == list(sim.sensors)
        for name in ("detection", "identification", "fused_detection", "in_view"):
            np.testing.assert_array_equal(got[name], getattr(result, name))
        assert got["events"] == [
            {"sensor": e.sensor, "target": e.target, "task": e.task, "time": e.time, "kind": e.kind}
            for e in result.events
        ]
        assert got["warnings"] == []


def test_a_full_table_of_sessions_in_use_refuses_a_new_one_and_drops_none():
    """A client opening many sessions cannot evict the others': while every kept session has
    stepped within the idle time, a new one is 429 and the old ones go on."""
    with _local(create_app(max_sessions=2, session_idle_s=3600)) as c:
        text = FUSED.read_text()
        first = c.post("/step", json=_step_body(scenario=text)).json()["session"]
        assert c.post("/step", json=_step_body(scenario=text)).status_code == 200
        for _ in range(3):
            refused = c.post("/step", json=_step_body(scenario=text))
            assert refused.status_code == 429
            (problem,) = refused.json()["detail"]
            assert "at most 2 sessions" in problem["msg"] and "3600 s" in problem["msg"]
            assert 1 <= int(refused.headers["Retry-After"]) <= 3600
        body = _step_body(session=first, time=1.0, dt=1.0)
        assert c.post("/step", json=body).status_code == 200


def test_a_new_session_takes_the_place_of_the_least_recently_used_idle_one():
    with _local(create_app(max_sessions=2, session_idle_s=0)) as c:
        text = FUSED.read_text()
        a = c.post("/step", json=_step_body(scenario=text)).json()["session"]
        b = c.post("/step", json=_step_body(scenario=text)).json()["session"]
        assert c.post("/step", json=_step_body(session=a, time=1.0, dt=1.0)).status_code == 200
        assert c.post("/step", json=_step_body(scenario=text)).status_code == 200  # drops b
        assert c.post("/step", json=_step_body(session=a, time=2.0, dt=1.0)).status_code == 200
        gone = c.post("/step", json=_step_body(session=b, time=1.0, dt=1.0))
        assert gone.status_code == 404 and "idle" in gone.json()["detail"][0]["msg"]
    assert MAX_SESSIONS == 64


def test_registries_list_the_registries(client):
    got = client.get("/registries").json()
    assert [item["name"] for item in got["sensor_types"]] == list(SENSOR_TYPES)
    assert [item["name"] for item in got["transforms"]] == list(TRANSFORMS)
    assert got["transforms"][0]["source"] == next(iter(TRANSFORMS.values())).source
    assert {"sensor_types", "criteria", "noise_models", "bands", "obscurants", "bounds"} <= set(got)
    assert "person" in [item["name"] for item in got["targets"]]


def test_curves_of_one_case(client):
    body = {"pitch": "17um", "focal_length": "50mm", "critical_dimension": "2.3m"}
    got = client.post("/curves", json={**body, "max_range": "8km"}).json()
    assert len(got["range_m"]) == 200
    assert got["range_m"][-1] == pytest.approx(8000.0)
    p = np.asarray(got["detection"])
    assert p[0] > 0.99
    assert np.all(np.diff(p) <= 1e-12)
    dri = client.post("/dri", json={**body, "probability": "0.5"}).json()
    r50 = next(row["range_m"] for row in dri["ranges"] if row["task"] == "detection")
    assert np.interp(r50, got["range_m"], p) == pytest.approx(0.5, abs=0.01)
    auto = client.post("/curves", json=body).json()
    assert auto["detection"][-1] < 0.05
    (item,) = _problem(client.post("/curves", json={**body, "max_range": "8"}))
    assert item["loc"] == ["body", "max_range"]


def test_report_is_html(client):
    response = client.post("/report", json={"scenario": FUSED.read_text(), "probability": "0.5"})
    assert response.status_code == 200, response.text
    assert response.headers["content-type"].startswith("text/html")
    assert "TV and thermal on a mast, fused" in response.text
    (item,) = _problem(client.post("/report", json={"scenario": FUSED.read_text(), "x": 1}))
    assert item["loc"] == ["body", "x"]


def test_the_openapi_schema_lists_the_six_paths(client):
    paths = client.get("/openapi.json").json()["paths"]
    assert set(paths) == {"/registries", "/dri", "/curves", "/evaluate", "/report", "/step"}
    assert "pitch" in json.dumps(paths["/dri"]) or "DriRequest" in json.dumps(paths["/dri"])


def test_serve_help_and_loopback_default():
    from targetacq.cli.serve import DEFAULT_HOST, is_loopback

    assert DEFAULT_HOST == "127.0.0.1"
    done = subprocess.run(
        [sys.executable, "-m", "targetacq", "serve", "--help"],
        capture_output=True,
        text=True,
        check=True,
    )
    assert "--host" in done.stdout
    assert "127.0.0.1" in done.stdout
    assert is_loopback("::1")
    assert not is_loopback("0.0.0.0")


def test_serve_refuses_a_port_in_use_in_one_line():
    import socket

    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen(1)
        port = taken.getsockname()[1]
        done = subprocess.run(
            [sys.executable, "-m", "targetacq", "serve", "--port", str(port)],
            capture_output=True,
            text=True,
            timeout=30,
        )
    assert done.returncode == 2
    assert done.stderr.startswith("targetacq: error: cannot listen on 127.0.0.1:")
    assert done.stderr.count("\n") == 1


def test_serve_answers_on_its_port():
    import httpx

    process = subprocess.Popen(
        [sys.executable, "-m", "targetacq", "serve", "--port", "0"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert process.stdout is not None
        line = process.stdout.readline()
        assert line.startswith("targetacq explorer on http://127.0.0.1:")
        url = line.split()[3]
        for _ in range(100):
            try:
                response = httpx.get(url + "registries", timeout=5)
                break
            except httpx.TransportError:
                import time

                time.sleep(0.1)
        assert response.status_code == 200
    finally:
        process.terminate()
        process.communicate(timeout=30)


def test_a_bug_is_answered_500_in_json(monkeypatch):
    from targetacq.web import api

    def broken():
        raise RuntimeError("a bug")

    monkeypatch.setattr(api, "_registries", broken)
    with _local(create_app(), raise_server_exceptions=False) as c:
        response = c.get("/registries")
    assert response.status_code == 500
    assert response.json()["detail"][0]["msg"] == "internal error (RuntimeError)"


def test_importing_the_web_package_imports_no_web_framework():
    code = "import sys, targetacq.web; print('fastapi' in sys.modules)"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "False"


# --- after review: work limits, strict bodies, located errors ---------------------------------


def _fused_toml() -> str:
    return (EXAMPLES / "two_sensors_fused.toml").read_text(encoding="utf-8")


@pytest.mark.parametrize(
    "pitch", ["17 um**2**2**2**2**2**2", "17 " + "micro" * 10_000 + "meter"], ids=["tower", "long"]
)
def test_unit_text_that_would_take_pint_minutes_is_refused_at_once(client, pitch) -> None:
    import time

    began = time.perf_counter()
    answer = client.post(
        "/dri", json={"pitch": pitch, "focal_length": "50mm", "critical_dimension": "2m"}
    )
    assert answer.status_code == 422 and time.perf_counter() - began < 5.0
    (problem,) = answer.json()["detail"]
    assert problem["loc"][-1] == "pitch" and "unknown unit" in problem["msg"]
    assert len(problem["msg"]) < 300  # the input is not echoed whole


def test_a_small_file_asking_for_a_large_run_is_refused() -> None:
    text = _fused_toml().replace('stop = "60 s"', 'stop = "1000000 s"')
    assert 'stop = "1000000 s"' in text
    client = _local(create_app(max_evaluations=100_000))
    assert client.post("/evaluate", json={"scenario": _fused_toml()}).status_code == 200
    for path in ("/evaluate", "/report"):
        answer = client.post(path, json={"scenario": text})
        assert answer.status_code == 422, path
        (problem,) = answer.json()["detail"]
        assert problem["loc"] == ["scenario", "time.step"] and "limit" in problem["msg"]


def _with_targets(count):
    """The fused example with ``count`` more standing people (one pair per sensor row each)."""
    head, sep, tail = _fused_toml().partition("[background]")
    extra = "".join(
        f'[[targets]]\nname = "p{k}"\ndimensions = ["0.5 m", "0.5 m", "1.8 m"]\n'
        f'temperature = "304 K"\nreflectance = 0.1\n'
        f'position = ["{1000 + 10 * k} m", "0 m", "0 m"]\n\n'
        for k in range(count)
    )
    return head + extra + sep + tail


def test_report_work_is_estimated_and_refused_before_any_work(monkeypatch) -> None:
    """pairs × (curve ranges + times + simulated runs × steps) over max_report_work: a 422
    naming the limit, and the report never started."""
    import targetacq.reports.content as report_content

    def never(*args, **kwargs):
        raise AssertionError("the report was started")

    monkeypatch.setattr(report_content, "scenario_report", never)
    client = _local(create_app(max_report_work=1_000_000))
    answer = client.post("/report", json={"scenario": _with_targets(10)})  # 24 pairs
    assert answer.status_code == 422
    (problem,) = answer.json()["detail"]
    assert problem["loc"] == ["scenario", "targets"]
    assert "limit is 1,000,000" in problem["msg"] and "simulated runs" in problem["msg"]
    long_run = _fused_toml().replace('step = "5 s"', 'step = "0.1 s"')
    (problem,) = client.post("/report", json={"scenario": long_run}).json()["detail"]
    assert problem["loc"] == ["scenario", "time.step"] and "limit" in problem["msg"]


def test_an_evaluate_file_counts_its_rows_against_the_limit() -> None:
    """A 1 ms step: 240,004 evaluations, within a 500,000 limit as JSON; as a CSV file (each
    row four evaluations' work) refused before any work."""
    text = _fused_toml().replace('step = "5 s"', 'step = "1 ms"')
    client = _local(create_app(max_evaluations=500_000))
    for fmt in ("csv", "parquet"):
        answer = client.post("/evaluate", json={"scenario": text, "format": fmt})
        assert answer.status_code == 422, fmt
        (problem,) = answer.json()["detail"]
        assert problem["loc"] == ["scenario", "time.step"]
        assert "limit is 500,000" in problem["msg"] and "240,004 rows" in problem["msg"]
    small = _fused_toml().replace('step = "5 s"', 'step = "1 s"')
    assert client.post("/evaluate", json={"scenario": small, "format": "csv"}).status_code == 200


def test_the_default_limits_refuse_the_runs_that_took_minutes() -> None:
    client = _local(create_app())
    text = _fused_toml().replace('step = "5 s"', 'step = "1 ms"')
    assert client.post("/evaluate", json={"scenario": text, "format": "csv"}).status_code == 422
    assert client.post("/report", json={"scenario": _with_targets(3_000)}).status_code == 422


@pytest.mark.parametrize(
    ("change", "field"),
    [
        ({"sensor_positions": [[0, 0, 15], [0, 0]]}, "sensor_positions"),
        ({"time": "5"}, "time"),
        ({"seed": 2**129}, "seed"),
        ({"sensor_positions": [[True, 0, 15], [0, 0, 15]]}, "sensor_positions"),
    ],
    ids=["ragged", "text-time", "huge-seed", "boolean"],
)
def test_step_inputs_are_strict_and_located(client, change, field) -> None:
    body = {
        "scenario": _fused_toml(),
        "time": 0.0,
        "dt": 1.0,
        "sensor_positions": [[0, 0, 15], [0, 0, 15]],
        "target_positions": [[3000, 0, 0], [2000, 100, 0]],
        **change,
    }
    answer = client.post("/step", json=body)
    assert answer.status_code == 422
    assert any(field in map(str, p["loc"]) for p in answer.json()["detail"])


def test_nan_literals_are_refused(client) -> None:
    body = (
        '{"scenario": ' + json.dumps(_fused_toml()) + ', "time": 0, "dt": 1, '
        '"sensor_positions": [[NaN, 0, 15], [0, 0, 15]], "target_positions": [[3000, 0, 0], '
        "[2000, 100, 0]]}"
    )
    answer = client.post("/step", content=body, headers={"Content-Type": "application/json"})
    assert answer.status_code == 422


def test_framework_errors_have_the_same_shape(client) -> None:
    missing = client.get("/no-such-page")
    assert missing.status_code == 404 and isinstance(missing.json()["detail"], list)
    deep = client.post("/dri", content="[" * 100_000, headers={"Content-Type": "application/json"})
    assert deep.status_code == 422 and isinstance(deep.json()["detail"], list)


def test_curves_of_a_detection_only_transform_say_why_there_are_none(client) -> None:
    body = {
        "pitch": "17um",
        "focal_length": "50mm",
        "critical_dimension": "2.3m",
        "transform": "schmieder-weathersby",
        "scr": "2",
    }
    assert client.post("/dri", json=body).status_code == 200
    answer = client.post("/curves", json=body)
    assert answer.status_code == 200
    found = answer.json()
    assert found["detection"] is None and "detection in clutter only" in found["note"]


def test_too_many_probabilities_are_refused(client) -> None:
    body = {"example": True, "probability": ",".join(["0.5"] * 50)}
    answer = client.post("/dri", json=body)
    assert answer.status_code == 422 and answer.json()["detail"][0]["loc"][-1] == "probability"


def test_every_app_answers_loopback_names_only_unless_widened() -> None:
    """create_app on its own (no targetacq serve) checks the Host header too."""
    app = create_app()
    for base in ("http://127.0.0.1", "http://localhost:8050", "http://[::1]:8050"):
        assert TestClient(app, base_url=base).get("/registries").status_code == 200, base
    for base in ("http://rebound.example", "http://testserver", "http://127.0.0.1.evil.example"):
        answer = TestClient(app, base_url=base).get("/registries")
        assert answer.status_code == 400, base
        (problem,) = answer.json()["detail"]
        assert problem["loc"] == ["header", "host"] and "127.0.0.1" in problem["msg"]
    wide = create_app(trusted_hosts=["explorer.lan"])
    assert TestClient(wide, base_url="http://explorer.lan:80").get("/").status_code == 200
    assert TestClient(wide, base_url="http://127.0.0.1").get("/").status_code == 400
    anyone = create_app(trusted_hosts=None)
    assert TestClient(anyone, base_url="http://rebound.example").get("/").status_code == 200


@pytest.mark.parametrize(
    ("path", "body"),
    [
        ("/step", {"session": "s" * 500_000, "time": 1.0, "dt": 1.0}),
        ("/dri", {"pitch": "17um", "x" * 300_000: "1"}),
        ("/dri", {"pitch": "17um", "focal_length": "50mm", "target": "t" * 300_000}),
        ("/dri", {"pitch": "1" * 300_000 + " um", "focal_length": "50mm"}),
        ("/evaluate", {"scenario": 'name = "' + "n" * 300_000 + '"\n[time]\nstop = 5'}),
        ("/evaluate", {"scenario": "[time]\nstop = '" + "9" * 300_000 + " s'"}),
    ],
    ids=["session", "field", "target", "unit", "name", "time"],
)
def test_errors_quote_at_most_80_characters_of_a_value(path, body) -> None:
    with _local(create_app(max_body_bytes=2_000_000)) as c:
        if path == "/step":
            body = _step_body(**body)
        answer = c.post(path, json=body)
    assert 400 <= answer.status_code < 500, answer.text[:300]
    assert len(answer.content) < 3_000, answer.text[:300]
    for problem in answer.json()["detail"]:
        assert all(len(str(part)) < 120 for part in problem["loc"])


def test_a_loopback_server_answers_loopback_names_only() -> None:
    app = create_app(trusted_hosts=["127.0.0.1", "localhost"])
    assert TestClient(app, base_url="http://127.0.0.1").get("/registries").status_code == 200
    assert TestClient(app, base_url="http://rebound.example").get("/registries").status_code == 400


# --- /step: cumulative flags, event kinds, reset; warnings ------------------------------------

_FLAGS = ("detected", "recognised", "identified")


def _walk_steps(client, text, seed, steps, **first):
    """``steps`` steps of a session of ``text`` at 1 Hz, the targets driving towards the mast;
    the answers (the first starts the session)."""
    answers, session = [], None
    for k in range(steps):
        targets = [[3000.0 - 150.0 * k, 0.0, 0.0], [2500.0 - 100.0 * k, 50.0, 0.0]]
        body = _step_body(time=float(k), dt=1.0, target_positions=targets)
        body.update({"session": session} if session else {"scenario": text, "seed": seed, **first})
        response = client.post("/step", json=body)
        assert response.status_code == 200, response.text
        answers.append(response.json())
        session = answers[-1]["session"]
    return answers


def _same_steps(sim, answers):
    """Each answer against the simulation's own step on the same inputs."""
    for k, got in enumerate(answers):
        targets = [[3000.0 - 150.0 * k, 0.0, 0.0], [2500.0 - 100.0 * k, 50.0, 0.0]]
        result = sim.step(float(k), 1.0, _step_body()["sensor_positions"], targets)
        for flag in _FLAGS:
            np.testing.assert_array_equal(got[flag], getattr(result, flag))
            np.testing.assert_array_equal(got[f"fused_{flag}"], getattr(result, f"fused_{flag}"))
        assert [tuple(e.values()) for e in got["events"]] == [tuple(e) for e in result.events]


def test_step_answers_the_cumulative_flags_and_the_event_kinds(client):
    answers = _walk_steps(client, FUSED.read_text(), 4, 15)
    _same_steps(Simulation.from_scenario(FUSED, seed=4), answers)
    # The flags only ever turn on, and a "first" event turns its pair's flag on.
    for before, after in itertools.pairwise(answers):
        for flag in _FLAGS:
            assert np.all(np.asarray(after[flag]) >= np.asarray(before[flag]))
        for event in after["events"]:
            assert event["kind"] in ("first", "reacquired")
            s, t = after["sensors"].index(event["sensor"]), after["targets"].index(event["target"])
            flag = _FLAGS[("detection", "recognition", "identification").index(event["task"])]
            assert after[flag][s][t]
            if event["kind"] == "first":
                assert not before[flag][s][t]
    assert any(any(row) for row in answers[-1]["detected"])  # the walk detects something


def test_reset_restarts_a_session_as_a_new_one(client):
    text = FUSED.read_text()
    answers = _walk_steps(client, text, 4, 12)
    session = answers[-1]["session"]
    assert any(answers[-1]["fused_detected"])
    # reset with another seed and run: a first step (nothing acquired), then the steps of a new
    # session with that seed and run.
    reset = _step_body(session=session, reset=True, seed=9, run=2, time=0.0, dt=1.0)
    reset["target_positions"] = [[3000.0, 0.0, 0.0], [2500.0, 50.0, 0.0]]
    got = client.post("/step", json=reset).json()
    assert got["session"] == session and got["events"] == []
    assert not any(got["fused_detected"]) and not any(map(any, got["detected"]))
    later = [got]
    for k in range(1, 12):
        targets = [[3000.0 - 150.0 * k, 0.0, 0.0], [2500.0 - 100.0 * k, 50.0, 0.0]]
        body = _step_body(session=session, time=float(k), dt=1.0, target_positions=targets)
        later.append(client.post("/step", json=body).json())
    sim = Simulation.from_scenario(FUSED, seed=9)
    sim.reset(run=2)
    _same_steps(sim, later)
    fresh = _walk_steps(client, text, 9, 12, run=2)
    assert [a["events"] for a in fresh] == [a["events"] for a in later]


@pytest.mark.parametrize(
    ("change", "loc", "words"),
    [
        ({"reset": True, "scenario": "x"}, ["body", "reset"], "give its session"),
        ({"session": "SESSION", "seed": 3}, ["body", "seed"], "reset: true"),
        ({"session": "SESSION", "run": 1}, ["body", "run"], "reset: true"),
        ({"session": "SESSION", "reset": 1}, ["body", "reset"], "bool"),
        ({"scenario": "x", "run": 2**32}, ["body", "run"], "less than"),
    ],
    ids=["reset-without-session", "seed-without-reset", "run-without-reset", "reset-1", "run"],
)
def test_step_reset_seed_and_run_are_checked(client, change, loc, words):
    session = client.post("/step", json=_step_body(scenario=FUSED.read_text())).json()["session"]
    body = _step_body(**{k: session if v == "SESSION" else v for k, v in change.items()})
    (item,) = _problem(client.post("/step", json=body))
    assert item["loc"] == loc
    assert words in item["msg"]


def test_malformed_step_bodies_are_422_located(client):
    (item,) = _problem(
        client.post("/step", content=b'{"time": ', headers={"Content-Type": "application/json"})
    )
    assert item["loc"] == ["body"] and item["msg"].startswith("malformed JSON")
    (item,) = _problem(
        client.post("/step", content=b"", headers={"Content-Type": "application/json"})
    )
    assert item["loc"] == ["body"]
    detail = _problem(client.post("/step", json={"time": 0.0}))
    assert {"dt", "sensor_positions", "target_positions"} <= {p["loc"][-1] for p in detail}


def test_the_step_body_is_in_the_openapi_schema(client):
    step = client.get("/openapi.json").json()["paths"]["/step"]["post"]
    schema = step["requestBody"]["content"]["application/json"]["schema"]
    assert {"session", "scenario", "reset", "seed", "run", "sensor_positions"} <= set(
        schema["properties"]
    )


_SLIP = FUSED.read_text(encoding="utf-8").replace('pitch = "12 um"', 'pitch = "12 m"', 1)


def test_a_unit_slip_is_answered_in_warnings(client):
    assert FUSED.read_text(encoding="utf-8") != _SLIP
    expected = "sensors[1].pitch: 12 m is 1 mm or more; was it given in um?"
    got = client.post("/evaluate", json={"scenario": _SLIP}).json()
    assert [w.split(" (give")[0] for w in got["warnings"]] == [expected]
    assert client.post("/evaluate", json={"scenario": FUSED.read_text()}).json()["warnings"] == []
    first = client.post("/step", json=_step_body(scenario=_SLIP)).json()
    assert [w.split(" (give")[0] for w in first["warnings"]] == [expected]
    later = client.post("/step", json=_step_body(session=first["session"], time=1.0, dt=1.0))
    assert later.json()["warnings"] == []
    for path, body in (
        ("/report", {"scenario": _SLIP, "probability": "0.5"}),
        ("/evaluate", {"scenario": _SLIP, "format": "csv"}),
    ):
        response = client.post(path, json=body)
        assert response.status_code == 200, response.text
        listed = json.loads(response.headers["x-targetacq-warnings"])
        assert [w.split(" (give")[0] for w in listed] == [expected]
    plain = client.post("/report", json={"scenario": FUSED.read_text(), "probability": "0.5"})
    assert "x-targetacq-warnings" not in plain.headers


_CROSSING = """
[[sensors]]
name = "narrow"
band = "lwir"
pixels = [64, 64]
ifov = "0.5 mrad"
position = ["0 m", "0 m", "10 m"]
azimuth = "90 deg"
depression = "0.2 deg"

[[targets]]
name = "car"
dimensions = ["4 m", "2 m", "1.5 m"]
temperature = "305 K"
position = ["3 km", "0 m", "0 m"]

[background]
temperature = "295 K"
"""


def test_a_short_visit_in_a_step_is_answered_not_printed(client):
    # A 1.8 degree field of view at 3 km is 96 m wide; the car crosses it at 300 m/s, so it is
    # in view for about a third of a second of a 1 s step.
    found, session = [], None
    for k, north in enumerate((-300.0, 0.0, 300.0)):
        body = {
            "time": float(k),
            "dt": 1.0,
            "sensor_positions": [[0.0, 0.0, 10.0]],
            "target_positions": [[3000.0, north, 0.0]],
        }
        body.update({"session": session} if session else {"scenario": _CROSSING})
        response = client.post("/step", json=body)  # a warning raised here would be a 500
        assert response.status_code == 200, response.text
        session = response.json()["session"]
        found += response.json()["warnings"]
    assert len(found) == 1 and "less than one step of 1 s" in found[0]


_FIRST_CURVES = """
import sys, time, warnings
warnings.filterwarnings("ignore", message="Using `httpx` with `starlette.testclient`")
from fastapi.testclient import TestClient
from targetacq.web.api import create_app
body = {"pitch": "17um", "focal_length": "50mm", "critical_dimension": "2.3m"}
with TestClient(create_app(), base_url="http://127.0.0.1") as client:  # started: lifespan ran
    before = set(sys.modules)
    began = time.perf_counter()
    assert client.post("/curves", json=body).status_code == 200
    print(time.perf_counter() - began)
    print(sorted({name.split(".")[0] for name in set(sys.modules) - before}))
"""


def test_the_first_chart_after_start_imports_nothing() -> None:
    """The first /curves imported xarray, pandas and the solver (1.3 s idle, 4.5 s on a busy
    machine): the app now does it at start-up, before it answers."""
    done = subprocess.run(
        [sys.executable, "-c", _FIRST_CURVES], capture_output=True, text=True, check=True
    )
    seconds, imported = done.stdout.splitlines()
    assert imported == "[]", imported
    assert float(seconds) < 1.0


def test_evaluate_formats_are_the_writers_registry():
    """The choices of ``POST /evaluate``'s format come from the writers' registry: the arrays
    (json), or every format written as one file by the base install, with its media type."""
    from targetacq.io.datasets import (
        DIRECTORY_FORMATS,
        FORMAT_PACKAGES,
        MEDIA_TYPES,
        OUTPUT_FORMATS,
    )
    from targetacq.web.api import EvaluateRequest

    schema = EvaluateRequest.model_json_schema()["properties"]["format"]
    files = {f for f in OUTPUT_FORMATS if f not in DIRECTORY_FORMATS and f not in FORMAT_PACKAGES}
    assert set(schema["enum"]) == files | {"json"}
    assert files <= set(MEDIA_TYPES)
    assert {"csv", "parquet"} <= files  # the page's download buttons
