"""The web explorer's server: how long ``targetacq serve`` takes to answer, and how long one
``POST /dri`` takes once it does. Goals: start in under 3 s, ``/dri`` in under 50 ms.

Start-up: ``python -m targetacq serve --port P`` in a fresh process, timed from launch until
``GET /registries`` answers (polled every 10 ms), ``REPEATS`` times. ``/dri``: one warm-up
request, then ``REQUESTS`` requests of a thermal camera (pitch, focal length, critical dimension,
haze, NETD and the target's contrast) over one HTTP connection; median and spread. The last line
printed is one JSON object.

Arguments: repeats (default 3), requests (default 50).
"""

from __future__ import annotations

import http.client
import json
import socket
import statistics
import subprocess
import sys
import time

REPEATS = int(sys.argv[1]) if len(sys.argv) > 1 else 3
REQUESTS = int(sys.argv[2]) if len(sys.argv) > 2 else 50
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
            }
        )
    )


if __name__ == "__main__":
    main()
