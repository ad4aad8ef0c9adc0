"""ModelChain.evaluate equals the numbers of the version before the array core (commit 2d5239a).

The golden files were written by ``tests/data/golden/generate.py`` at that commit, for every
bundled example and four scenarios that exercise the rest of the chain (segments, a cloud,
c2nveo with a bound, a user N50 triple, hidden targets, hot spots, moving targets, clutter
regions, an SCR, visibility, the "none" noise model, TV, image and terrain clutter).

They hold the thesis's SNR law (Eq. (7.7) + the sensor's own in variance), which is the
``sonesson`` law since the ``contrast`` law became the default (issue 25): the scenarios are
evaluated under it, so the files pin that law to the earlier numbers.
"""

from pathlib import Path

import numpy as np
import pytest

from targetacq.run.model_chain import ModelChain
from targetacq.scenario.schema import load_scenario

ROOT = Path(__file__).parents[2]
GOLDEN = Path(__file__).parents[1] / "data" / "golden"
SCENARIOS = sorted((ROOT / "examples").glob("*.toml")) + sorted(GOLDEN.glob("*.toml"))


@pytest.mark.parametrize("path", SCENARIOS, ids=lambda p: p.stem)
def test_evaluate_equals_the_previous_version(path):
    expected = np.load(GOLDEN / f"{path.stem}.npz")
    scenario = load_scenario(path)
    scenario = scenario.model_copy(
        update={"model": scenario.model.model_copy(update={"snr_law": "sonesson"})}
    )
    ds = ModelChain(scenario).evaluate().dataset
    np.testing.assert_array_equal(ds["time"].values, expected["time"])
    for name in expected.files:
        if name == "time":
            continue
        got = np.asarray(ds[name].values)
        want = expected[name]
        assert got.shape == want.shape, name
        if want.dtype == bool:
            np.testing.assert_array_equal(got, want, err_msg=name)
        else:
            np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-15, err_msg=name)
