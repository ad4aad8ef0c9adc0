"""A target's probabilities do not depend on which other targets are evaluated with it.

The core groups targets that share a criterion and evaluates a group's hot-spot and moving flags
together; whatever the grouping, each target must get the numbers it gets alone. A regression
test: a hot spot evaluated beside a moving target of the same criterion once lost its hot-spot
curve (the moving rule's value, NaN for targets that do not move, masked it).
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from targetacq.run.model_chain import ModelChain
from targetacq.scenario.schema import parse_scenario

TARGETS = {
    "hot": {"hot_spot": True},
    "moving": {"moving": True},
    "both": {"hot_spot": True, "moving": True},
    "plain": {},
}


def _document(names: tuple[str, ...], clutter: dict, motion: str) -> dict:
    return {
        "sensors": [
            {
                "name": "ir",
                "type": "thermal",
                "band": "lwir",
                "pixels": [640, 480],
                "pitch": "17 um",
                "focal_length": "50 mm",
                "position": ["0 m", "0 m", "10 m"],
            }
        ],
        "targets": [
            {
                "name": name,
                "dimensions": ["5 m", "2 m", "2 m"],
                "temperature": "310 K",
                "position": ["3000 m", "0 m", "0 m"],  # the same place: only the flags differ
                **TARGETS[name],
            }
            for name in names
        ],
        "background": {"temperature": "300 K", **clutter},
        "model": {"motion": motion},
        "time": {"start": "0 s", "stop": "0 s", "step": "1 s"},
    }


@pytest.mark.parametrize("clutter", [{}, {"clutter": "high"}, {"scr": 0.5}], ids=str)
@pytest.mark.parametrize("motion", ["low-clutter", "always"])
def test_each_target_as_alone(clutter: dict, motion: str) -> None:
    alone = {
        name: ModelChain(parse_scenario(_document((name,), clutter, motion))).compute([0.0])
        for name in TARGETS
    }
    for names in itertools.permutations(TARGETS, 2):
        together = ModelChain(parse_scenario(_document(names, clutter, motion))).compute([0.0])
        for g, name in enumerate(names):
            for task in ("detection", "recognition", "identification"):
                np.testing.assert_allclose(
                    together[task][:, g], alone[name][task][:, 0], rtol=1e-12, err_msg=str(names)
                )


def test_a_hot_spot_beside_a_moving_target_keeps_its_curve() -> None:
    """In high clutter a hot spot is detected on the low-clutter curve (§3.9), far above the
    high-clutter curve that applies to a plain target at the same range."""
    names = ("hot", "moving", "plain")
    p = ModelChain(parse_scenario(_document(names, {"clutter": "high"}, "low-clutter"))).compute(
        [0.0]
    )["detection"][0, :, 0]
    assert p[0] > 10 * p[2]
