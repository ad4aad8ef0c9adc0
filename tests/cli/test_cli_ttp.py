"""``--resolution-model`` on the CLI: the TTP metric's ranges, its options and its errors."""

from __future__ import annotations

import json
import math
import warnings

import pytest

from targetacq.cli import main
from targetacq.physics.ttp import TtpSystem, ttp_cycles

CAMERA = [
    "--pitch", "17um", "--focal-length", "100mm", "--f-number", "1", "--wavelength", "10um",
    "--critical-dimension", "2.3m", "--netd", "50mK", "--delta-t", "2K",
]  # fmt: skip


def _dri(capsys, *extra):
    with pytest.raises(SystemExit) as exit_:
        main(["dri", *CAMERA, "--resolution-model", "ttp", "--format", "json", *extra])
    out = capsys.readouterr()
    assert exit_.value.code in (0, None), out.err
    return json.loads(out.out)


def test_dri_ttp_identification_range_is_where_v_reaches_v50(capsys):
    report = _dri(capsys, "--jitter", "0.03mrad")
    assert report["resolution_model"] == "ttp"
    assert report["criterion"] == "ttp-vehicles" and report["transform"] == "ttp"
    assert report["target"]["ttp"]["netd_k"] == pytest.approx(0.05)
    (ident,) = [row for row in report["ranges"] if row["task"] == "identification"]
    system = TtpSystem(ifov=17e-6 / 0.1, aperture=0.1, wavelength=10e-6, netd=0.05, jitter=3e-5)
    lo, hi = 100.0, 1e5  # independent bisection of V(R) = V50 on the physics kernel
    for _ in range(80):
        mid = math.sqrt(lo * hi)
        lo, hi = (
            (mid, hi) if ttp_cycles(mid, 2.3, 2.0, 1.0, system) > ident["threshold"] else (lo, mid)
        )
    assert ident["range_m"] == pytest.approx(lo, rel=1e-6)


def test_turbulence_shortens_the_cli_range(capsys):
    clear = _dri(capsys)["ranges"][-1]["range_m"]
    turbulent = _dri(capsys, "--cn2", "1e-13m^(-2/3)")["ranges"][-1]["range_m"]
    assert turbulent < clear


@pytest.mark.parametrize(
    ("args", "wanted"),
    [
        (["--jitter", "0.1mrad"], "--jitter is used by --resolution-model ttp"),
        (["--resolution-model", "mrtd"], "--resolution-model mrtd needs an MRTD curve"),
        (["--resolution-model", "tpp"], "--resolution-model"),
        (["--resolution-model", "ttp", "--cn2", "-1e-14m^(-2/3)"], "--cn2 must be >= 0"),
    ],
)
def test_errors_are_one_line_exit_2(capsys, args, wanted):
    with pytest.raises(SystemExit) as exit_:
        main(["dri", *CAMERA, *args])
    err = capsys.readouterr().err
    assert exit_.value.code == 2
    assert wanted in err and "Traceback" not in err


def test_geometric_is_still_accepted(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["dri", *CAMERA, "--resolution-model", "geometric", "--format", "json"])
    assert exit_.value.code in (0, None)
    assert json.loads(capsys.readouterr().out)["resolution_model"] == "johnson"


def test_the_web_dri_takes_the_resolution_model(capsys):
    pytest.importorskip("fastapi")
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="Using `httpx` with `starlette.testclient`")
        from fastapi.testclient import TestClient

    from targetacq.web.api import create_app

    options = dict(zip([a[2:].replace("-", "_") for a in CAMERA[::2]], CAMERA[1::2], strict=True))
    options |= {"resolution_model": "ttp", "jitter": "0.03mrad"}
    with TestClient(create_app(), base_url="http://127.0.0.1") as client:
        response = client.post("/dri", json=options)
    assert response.status_code == 200, response.text
    assert response.json() == _dri(capsys, "--jitter", "0.03mrad")


def test_design_finds_the_lens_that_dri_ranged(capsys):
    ident = _dri(capsys)["ranges"][-1]
    camera = [a for a in CAMERA if a not in ("--focal-length", "100mm")]
    with pytest.raises(SystemExit) as exit_:
        main(["design", *camera, "--resolution-model", "ttp", "--task", "identification",
              "--range", f"{ident['range_m']!r}m", "--format", "json"])  # fmt: skip
    out = capsys.readouterr()
    assert exit_.value.code in (0, None), out.err
    (row,) = json.loads(out.out)["rows"]
    assert row["focal_length_m"] == pytest.approx(0.1, rel=1e-6)
