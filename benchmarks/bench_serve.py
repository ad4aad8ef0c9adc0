"""The web explorer's server: how long ``targetacq serve`` takes to answer, how long one
``POST /dri`` takes once it does, and what ``POST /step`` adds to the in-process step.
Goals: start in under 3 s, ``/dri`` in under 50 ms, ``/step`` within 1.5x the in-process
``Simulation.step`` plus the transport.

Start-up: ``python -m targetacq serve --port P`` in a fresh process, timed from launch until
``GET /registries`` answers (polled every 10 ms), ``REPEATS`` times. ``/dri``: one warm-up
request, then ``REQUESTS`` requests of a thermal camera (pitch, focal length, critical dimension,
haze, NETD and the target's contrast) over one HTTP connection; median and spread.

``/step``: the bundled one-camera example (``uav_haze.toml``: 1 camera x 3 targets, its scripted
positions) and a generated 20 cameras x 500 targets (the layout of ``bench_step.py``), stepped at
10 Hz ``STEPS`` times each way, medians of:

- ``in_process``: ``Simulation.step`` on NumPy arrays (what a Python caller pays);
- ``step``: ``POST /step`` of the same positions (a session of the same seed), and ``empty``:
  ``POST /empty`` of ``{}`` answering ``{}`` on the same application (its middleware and
  routing: the transport);

each of the three timed one after the other at every step (so that a busy machine slows them
alike), through FastAPI's ``TestClient`` (in this process, no socket, its event loop kept) and
over real HTTP (uvicorn in another process on a free port, one keep-alive ``httpx``
connection). ``ratio`` is the ``step`` median over the ``in_process`` median plus the ``empty``
median; the aim is <= 1.5. The last line printed is one JSON object.

Arguments: repeats (default 3), requests (default 50), steps (default 200).
"""

from __future__ import annotations

import contextlib
import http.client
import json
import socket
import statistics
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np


def _argument(index: int, default: int) -> int:
    """The command line's argument ``index`` (the defaults where uvicorn imports this module)."""
    return int(sys.argv[index]) if __name__ == "__main__" and len(sys.argv) > index else default


REPEATS = _argument(1, 3)
REQUESTS = _argument(2, 50)
STEPS = _argument(3, 200)
RATE = 10.0  # steps per second
EXAMPLE = Path(__file__).resolve().parents[1] / "src" / "targetacq" / "examples" / "uav_haze.toml"
BODY = json.dumps(
    {
        "pitch": "17um",
        "focal_length": "75mm",
        "critical_dimension": "2.3m",
        "obscurant": "haze",
        "band": "lwir",
        "netd": "50mK",
        "delta_t": "2K",
        "probability": "0.5,0.8,0.95",
    }
)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def answering(port: int) -> bool:
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=1)
    try:
        connection.request("GET", "/registries")
        return connection.getresponse().status == 200
    except OSError:
        return False
    finally:
        connection.close()


def start(port: int) -> tuple[subprocess.Popen[bytes], float]:
    began = time.perf_counter()
    server = subprocess.Popen(
        [sys.executable, "-m", "targetacq", "serve", "--port", str(port)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    while not answering(port):
        if server.poll() is not None or time.perf_counter() - began > 30:
            server.kill()
            raise RuntimeError("targetacq serve did not answer within 30 s")
        time.sleep(0.01)
    return server, time.perf_counter() - began


def dri_times(port: int) -> list[float]:
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
    headers = {"Content-Type": "application/json"}
    times = []
    try:
        for k in range(REQUESTS + 1):
            began = time.perf_counter()
            connection.request("POST", "/dri", BODY, headers)
            response = connection.getresponse()
            response.read()
            if response.status != 200:
                raise RuntimeError(f"/dri answered {response.status}")
            if k:  # the first request warms the caches
                times.append(time.perf_counter() - began)
    finally:
        connection.close()
    return times


# --- /step ----------------------------------------------------------------------------------


def bench_app() -> Any:
    """The explorer's application with ``POST /empty`` (``{}`` in, ``{}`` out): the transport
    measured through the same middleware and routing (``uvicorn --factory``)."""
    from starlette.responses import Response

    from targetacq.web import create_app

    app = create_app(max_body_bytes=10_000_000)

    async def empty(request: Any) -> Response:
        await request.body()
        return Response(b"{}", media_type="application/json")

    app.router.add_route("/empty", empty, methods=["POST"])
    return app


def _generated(n_sensors: int, n_targets: int) -> tuple[str, np.ndarray, np.ndarray, np.ndarray]:
    """A TOML scenario of ``bench_step.py``'s layout, its sensor and target positions [m] and
    the targets' velocities [m/s]."""
    rng = np.random.default_rng(1)
    azimuths = rng.uniform(0.0, 360.0, n_sensors)
    lines = ['name = "bench"', "[background]", 'temperature = "293 K"', 'clutter_std = "2 K"']
    lines += ["[atmosphere]", 'obscurant = "haze"']
    for i, az in enumerate(azimuths):
        lines += [
            "[[sensors]]",
            f'name = "s{i}"',
            'band = "lwir"',
            "pixels = [640, 512]",
            'pitch = "17 um"',
            'focal_length = "35 mm"',
            'position = ["0 m", "0 m", "0 m"]',
            f'azimuth = "{az:.6f} deg"',
            'depression = "30 deg"',
        ]
    temperatures = rng.uniform(295, 315, n_targets)
    headings = rng.uniform(0, 360, n_targets)
    for j in range(n_targets):
        lines += [
            "[[targets]]",
            f'name = "t{j}"',
            'dimensions = ["7 m", "2.5 m", "3 m"]',
            f'temperature = "{temperatures[j]:.4f} K"',
            f'heading = "{headings[j]:.4f} deg"',
            'position = ["0 m", "0 m", "0 m"]',
        ]
    sensor_pos = np.column_stack(
        [
            rng.uniform(-5e3, 5e3, n_sensors),
            rng.uniform(-5e3, 5e3, n_sensors),
            rng.uniform(1e3, 3e3, n_sensors),
        ]
    )
    which = np.arange(n_targets) % n_sensors
    azimuth = np.radians(azimuths)[which]
    reach = sensor_pos[which, 2] / np.tan(np.radians(30.0))
    target_pos = np.column_stack(
        [
            sensor_pos[which, 0] + reach * np.sin(azimuth) + rng.uniform(-150, 150, n_targets),
            sensor_pos[which, 1] + reach * np.cos(azimuth) + rng.uniform(-150, 150, n_targets),
            np.zeros(n_targets),
        ]
    )
    velocity = np.column_stack(
        [rng.uniform(-15, 15, n_targets), rng.uniform(-15, 15, n_targets), np.zeros(n_targets)]
    )
    return "\n".join(lines) + "\n", sensor_pos, target_pos, velocity


def _cases() -> list[tuple[str, str, list[tuple[np.ndarray, np.ndarray]]]]:
    """(label, scenario text, positions (sensors, targets) per step) of each size."""
    from targetacq.core import scenario_positions
    from targetacq.scenario.schema import load_scenario

    times = np.arange(STEPS + 2) / RATE
    text = EXAMPLE.read_text(encoding="utf-8")
    sensors, targets, _ = scenario_positions(load_scenario(EXAMPLE), times)
    example = [(sensors[:, k], targets[:, k]) for k in range(times.size)]
    generated, s_pos, t_pos, velocity = _generated(20, 500)
    moving = [(s_pos, t_pos + velocity * t) for t in times]
    return [("uav_haze.toml (1 x 3)", text, example), ("generated (20 x 500)", generated, moving)]


def _body(k: int, positions: tuple[np.ndarray, np.ndarray], **extra: Any) -> bytes:
    sensors, targets = positions
    document = {
        "time": k / RATE,
        "dt": 1 / RATE,
        "sensor_positions": sensors.tolist(),
        "target_positions": targets.tolist(),
        **extra,
    }
    return json.dumps(document).encode()


def _over(post: Any, text: str, steps: list[tuple[np.ndarray, np.ndarray]]) -> dict[str, Any]:
    """``/step`` and ``/empty`` through ``post(path, body bytes) -> answer bytes``, each
    request beside the same step in process (so that a busy machine slows all three alike)."""
    import tomllib

    from targetacq import Simulation
    from targetacq.scenario.schema import parse_scenario

    sim = Simulation.from_scenario(parse_scenario(tomllib.loads(text)))
    sim.step(0.0, 1 / RATE, *steps[0])
    first = json.loads(post("/step", _body(0, steps[0], scenario=text)))
    session = first["session"]
    in_process, step_times, empty_times, sizes = [], [], [], []
    for k in range(1, len(steps)):
        sensors, targets = steps[k]
        began = time.perf_counter()
        sim.step(k / RATE, 1 / RATE, sensors, targets)
        in_process.append(time.perf_counter() - began)
        body = _body(k, steps[k], session=session)
        began = time.perf_counter()
        answer = post("/step", body)
        step_times.append(time.perf_counter() - began)
        began = time.perf_counter()
        post("/empty", b"{}")
        empty_times.append(time.perf_counter() - began)
        sizes.append((len(body), len(answer)))
    return {
        "in_process": statistics.median(in_process),
        "step": statistics.median(step_times),
        "empty": statistics.median(empty_times),
        "request_bytes": sizes[-1][0],
        "answer_bytes": sizes[-1][1],
    }


@contextlib.contextmanager
def _testclient_post() -> Iterator[Any]:
    """``post`` through FastAPI's ``TestClient`` (its event loop kept between requests)."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # Starlette's note on its test client's transport
        from fastapi.testclient import TestClient

    headers = {"Content-Type": "application/json"}
    with TestClient(bench_app()) as client:

        def post(path: str, body: bytes) -> bytes:
            response = client.post(path, content=body, headers=headers)
            if response.status_code != 200:
                raise RuntimeError(f"{path} answered {response.status_code}: {response.text}")
            return response.content

        yield post


def _http_server() -> tuple[subprocess.Popen[bytes], int]:
    port = free_port()
    server = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "uvicorn",
            "--factory",
            "bench_serve:bench_app",
            "--app-dir",
            str(Path(__file__).parent),
            "--port",
            str(port),
            "--log-level",
            "warning",
        ],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    began = time.perf_counter()
    while not answering(port):
        if server.poll() is not None or time.perf_counter() - began > 30:
            server.kill()
            raise RuntimeError("uvicorn did not answer within 30 s")
        time.sleep(0.01)
    return server, port


def _row(label: str, steps: int, testclient: dict[str, Any], http: dict[str, Any]) -> dict:
    def ms(seconds: float) -> float:
        return round(1e3 * seconds, 3)

    def ratio(over: dict[str, Any]) -> float:
        return round(over["step"] / (over["in_process"] + over["empty"]), 2)

    return {
        "case": label,
        "steps": steps,
        "testclient": {
            "in_process_ms": ms(testclient["in_process"]),
            "step_ms": ms(testclient["step"]),
            "empty_ms": ms(testclient["empty"]),
            "ratio": ratio(testclient),
        },
        "http": {
            "in_process_ms": ms(http["in_process"]),
            "step_ms": ms(http["step"]),
            "empty_ms": ms(http["empty"]),
            "ratio": ratio(http),
        },
        "request_bytes": testclient["request_bytes"],
        "answer_bytes": testclient["answer_bytes"],
        "ratio_goal": 1.5,
    }


def step_times() -> list[dict[str, Any]]:
    """The ``/step`` measurements of each size (see the module docstring)."""
    import httpx

    cases = _cases()
    server, port = _http_server()
    rows = []
    try:
        with (
            _testclient_post() as testclient,
            httpx.Client(base_url=f"http://127.0.0.1:{port}", timeout=60) as client,
        ):
            headers = {"Content-Type": "application/json"}

            def http_post(path: str, body: bytes) -> bytes:
                response = client.post(path, content=body, headers=headers)
                if response.status_code != 200:
                    raise RuntimeError(f"{path} answered {response.status_code}")
                return response.content

            for label, text, steps in cases:
                tc = _over(testclient, text, steps)
                over_http = _over(http_post, text, steps)
                rows.append(_row(label, len(steps) - 1, tc, over_http))
    finally:
        server.terminate()
        server.wait(timeout=10)
    return rows


def main() -> None:
    starts, requests = [], []
    for _ in range(REPEATS):
        port = free_port()
        server, seconds = start(port)
        try:
            starts.append(seconds)
            requests += dri_times(port)
        finally:
            server.terminate()
            server.wait(timeout=10)
    print(
        json.dumps(
            {
                "start_s_median": round(statistics.median(starts), 3),
                "start_s_range": [round(min(starts), 3), round(max(starts), 3)],
                "start_goal_s": 3.0,
                "dri_ms_median": round(1e3 * statistics.median(requests), 2),
                "dri_ms_range": [round(1e3 * min(requests), 2), round(1e3 * max(requests), 2)],
                "dri_goal_ms": 50.0,
                "requests": len(requests),
                "step": step_times(),
            }
        )
    )


if __name__ == "__main__":
    main()
