"""The design solver with the TTP resolution model: it inverts the DRI range."""

from __future__ import annotations

import pytest

from targetacq.core.cases import RangeCase
from targetacq.core.ranges import dri_ranges
from targetacq.physics.ttp import TtpSystem
from targetacq.run import design

PITCH, FOCAL, F_NUMBER = 17e-6, 0.1, 1.0
MODEL = {
    "ttp": TtpSystem(1e-3, FOCAL / F_NUMBER, 10e-6, 0.05, jitter=2e-5),
    "contrast": 2.0,
    "wavelength": 10e-6,  # with f_number: the aperture of the Johnson limit and the TTP system
}


@pytest.fixture(scope="module")
def distance():
    system = TtpSystem(PITCH / FOCAL, FOCAL / F_NUMBER, 10e-6, 0.05, jitter=2e-5)
    return float(dri_ranges(RangeCase(2.3, PITCH / FOCAL, ttp=system, contrast=2.0))["recognition"])


def test_design_recovers_the_camera_that_gives_the_range(distance):
    args = (2.3, distance, 0.5, "recognition")
    assert design.required_focal_length(PITCH, *args, f_number=F_NUMBER, **MODEL) == pytest.approx(
        FOCAL, rel=1e-6
    )
    assert design.required_pitch(FOCAL, *args, f_number=F_NUMBER, **MODEL) == pytest.approx(
        PITCH, rel=1e-6
    )
    assert design.required_ifov(*args, aperture=FOCAL / F_NUMBER, **MODEL) == pytest.approx(
        PITCH / FOCAL, rel=1e-6
    )


def test_a_farther_range_needs_a_longer_lens(distance):
    near = design.required_focal_length(
        PITCH, 2.3, distance, 0.5, "recognition", f_number=1.0, **MODEL
    )
    far = design.required_focal_length(
        PITCH, 2.3, 2 * distance, 0.5, "recognition", f_number=1.0, **MODEL
    )
    assert far > near
