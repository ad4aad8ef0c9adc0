"""A named atmosphere in a scenario: ``[atmosphere] model, aerosol, visibility, altitude``,
validated, compiled into the core as each band's table of optical depth against range, and
evaluated like the range case through the same path (issue 25).

Expected values come from the physics kernel (:func:`named_band_transmittance`, the table read
for the band) and from the range-case chain with the same path (:class:`RangeCase` ``path=``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from targetacq.core.cases import RangeCase, case_acquisition
from targetacq.core.engines import bind
from targetacq.core.evaluation import evaluate
from targetacq.physics import named_atmospheres as na
from targetacq.run.model_chain import ModelChain
from targetacq.scenario.schema import load_scenario

IFOV = 17e-6 / 50e-3
SCENARIO = """
[[sensors]]
name = "ir"
type = "thermal"
band = "{band}"
pixels = [640, 512]
pitch = "17 um"
focal_length = "50 mm"
position = ["0 m", "0 m", "2 m"]
look_at = ["3 km", "0 m", "2 m"]

[[targets]]
name = "truck"
dimensions = ["7 m", "2.5 m", "3 m"]
temperature = "300 K"
emissivity = 1.0
position = ["3 km", "0 m", "2 m"]

[background]
temperature = "293 K"
emissivity = 1.0

[atmosphere]
{atmosphere}
"""


def _chain(folder: Path, atmosphere: str, band: str = "lwir") -> ModelChain:
    path = folder / "scenario.toml"
    path.write_text(SCENARIO.format(atmosphere=atmosphere, band=band))
    return ModelChain(load_scenario(path))


def _positions(r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    n = r.size
    sensors = np.broadcast_to(np.array([0.0, 0.0, 2.0]), (1, n, 3)).copy()
    targets = np.stack([r, np.zeros(n), np.full(n, 2.0)], axis=-1)[None]
    return sensors, targets


@pytest.mark.parametrize("band", ["lwir", "mwir"])
def test_evaluate_transmittance_is_the_named_band_transmittance(tmp_path: Path, band: str):
    text = 'model = "tropical"\naerosol = "rural"\nvisibility = "23 km"\naltitude = "500 m"'
    scene = _chain(tmp_path, text, band).compiled.scene
    assert scene.path.attenuates and scene.path.named_depths.shape == (1, 15)
    r = np.array([300.0, 2500.0, 5000.0, 12e3])
    found, p = evaluate(scene, *_positions(r))
    expected = na.named_band_transmittance(r, band, "tropical", "rural", 23e3, 500.0)
    np.testing.assert_allclose(found.transmittance[0, 0], expected, rtol=1e-12)
    path = na.NamedBandPath(na.NamedPath("tropical", "rural", 23e3, 500.0), band)
    for k, rk in enumerate(r):
        case = RangeCase(3.0, IFOV, cycle=2.0 * IFOV, path=path)
        acquired = case_acquisition(case, rk)
        np.testing.assert_allclose(found.snr[0, 0, k], acquired.snr, rtol=1e-9)
        np.testing.assert_allclose(p.detection[0, 0, k], acquired.detection, rtol=1e-9)


def test_the_scenario_ranges_see_the_named_path(tmp_path: Path):
    humid = _chain(tmp_path, 'model = "tropical"').range_cases()
    dry = _chain(tmp_path, 'model = "subarctic-winter"').range_cases()
    (case_humid,), (case_dry,) = humid.values(), dry.values()
    assert case_humid.path is not None and case_humid.extinction is None
    tau_humid = case_acquisition(case_humid, 5e3).transmittance
    tau_dry = case_acquisition(case_dry, 5e3).transmittance
    assert tau_humid < tau_dry


def test_numba_refuses_a_named_atmosphere_and_auto_runs_numpy(tmp_path: Path):
    scene = _chain(tmp_path, 'model = "us-standard"\naerosol = "maritime"').compiled.scene
    pytest.importorskip("numba")
    with pytest.raises(ValueError, match="named atmosphere"):
        bind(scene, "numba")


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ('model = "tropics"', "unknown atmosphere model 'tropics'"),
        ('aerosol = "smog"', "unknown aerosol 'smog'"),
        ('model = "tropical"\nextinction = "0.2 /km"', "extinction do not go with a named"),
        ('model = "tropical"\nvisibility = "500 m"', r"visibility must be in \[2000, 50000\]"),
        ('aerosol = "fog"\nvisibility = "5 km"', r"visibility must be in \[50, 1000\] m"),
        ('altitude = "1 km"', "altitude goes with a named atmosphere"),
        ('model = "tropical"\naltitude = "8 km"', r"altitude must be in \[0, 5000\] m"),
    ],
)
def test_bad_named_atmospheres_are_located_errors(tmp_path: Path, text: str, message: str):
    with pytest.raises(Exception, match=message):
        _chain(tmp_path, text)


def test_a_band_outside_the_table_names_the_sensor(tmp_path: Path):
    with pytest.raises(ValueError, match="sensor 'ir': named atmospheres are tabulated"):
        _chain(tmp_path, 'model = "tropical"', band="3.5-4.5um")
