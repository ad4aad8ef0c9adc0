"""Write the golden numbers of ModelChain.evaluate for the golden scenarios.

First written at commit 2d5239a (the version before the array core), from the repository
root: ``python tests/data/golden/generate.py``. The golden test compares every later version
with these files; regenerate them only for a deliberate change of the model, and say so in the
commit and here.

Regenerated (deliberate model changes of the physical-fidelity issue): the noise law
``variance-sum`` (quadrature), the Schmieder–Weathersby transform continuous in the SCR,
detection in clutter capped by the uncluttered value, moving targets detected as in low
clutter (not always), hot spots under noise read at the noisy N; then the datasheet field-of-view
convention (``hfov`` over pixels is IFOV = hfov / pixels by default, features.toml). Then
features.npz alone, for a bug fix: a hot spot evaluated beside a moving target of the same
criterion lost its hot-spot curve (target ``hot``'s detection and fused detection only; see
tests/properties/test_target_independence.py).

Added, not regenerated: colour_camera, radar_surveillance, laser_radar and
fused_tv_thermal_radar (the chapter 9 sensors), first written when those examples were; they
pin the numbers against later change, while tests/sensors/test_colour.py and
tests/sensors/test_active_sensors.py check them against the published equations. Rewritten once
before their first release: laser_radar.npz for a wider field of view in the example (the crate
was never in view), fused_tv_thermal_radar.npz for the SCR of imagers without clutter in a
scene with a radar, reported as +inf (no clutter measure) instead of NaN.

Added, not regenerated: swir_mast_haze (the SWIR example of the sensor-type protocol), first
written when the example was, with the loop above for that file alone; tests/sensors/test_swir.py
checks its physics (the emitted part against a quadrature of Planck's law, the reflected part
against r·E).
"""

from pathlib import Path

import numpy as np

from targetacq.run.model_chain import ModelChain
from targetacq.scenario.schema import load_scenario

HERE = Path(__file__).parent
ROOT = HERE.parents[2]
SCENARIOS = sorted((ROOT / "examples").glob("*.toml")) + sorted(HERE.glob("*.toml"))

for path in SCENARIOS:
    ds = ModelChain(load_scenario(path)).evaluate().dataset
    arrays = {name: np.asarray(ds[name].values) for name in ds.data_vars}
    arrays["time"] = ds["time"].values
    np.savez_compressed(HERE / f"{path.stem}.npz", **arrays)
    print(path.stem, sorted(arrays))
