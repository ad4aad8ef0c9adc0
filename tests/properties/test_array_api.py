"""The core kernels run under array_api_strict and agree with NumPy."""

import array_api_strict as xps
import numpy as np
import pytest

import targetacq as ta
from targetacq.acquisition.criteria import CRITERIA
from targetacq.acquisition.cues import hot_spot_weight, motion_weight
from targetacq.physics.atmosphere import contrast_transmittance

N = [0.0, 0.3, 0.9, 1.0, 2.5, 7.0, 40.0, float("nan")]
P = [0.02, 0.3, 0.5, 0.8, 0.95, float("nan")]


def _strict(values):
    return xps.asarray(values, dtype=xps.float64)


def _same(strict_result, numpy_result):
    assert type(strict_result).__module__.startswith("array_api_strict")
    np.testing.assert_allclose(np.asarray(strict_result), numpy_result, rtol=1e-14, equal_nan=True)


@pytest.mark.parametrize(
    ("kernel", "inputs"),
    [
        (lambda n: ta.ttpf(n, 4.0), N),
        (
            lambda n: ta.c2nveo(
                n, CRITERIA["c2nveo"].n50("recognition"), "recognition", "pessimistic"
            ),
            N,
        ),
        (lambda n: ta.schmieder_weathersby(n, scr=0.5), N),
        (lambda n: ta.schmieder_weathersby(n, region="medium"), N),
        (lambda p: ta.ttpf_inverse(p, 4.0), P),
        (lambda p: ta.c2nveo_inverse(p, 1.0, "detection", "optimistic"), P),
        (lambda p: ta.schmieder_weathersby_inverse(p, region="high"), P),
        (lambda r: ta.cycles_on_target(2.3, r, 2e-4), [100.0, 1000.0, float("nan")]),
        (
            lambda r: ta.cycles_on_target(
                2.3, r, 2e-5, wavelength=1e-5, aperture=0.1, blur_sigma=1e-5
            ),
            [100.0, 1000.0],
        ),
        (lambda p: ta.ifov(p, 0.075), [12e-6, 17e-6]),
        (lambda h: ta.slant_range(h, 1000.0), [0.0, 300.0]),
        (lambda n: ta.range_for_cycles(2.3, n, 1e-4), [0.5, 1.0, 4.0]),
        (lambda t: contrast_transmittance(t, 3.0), [0.0, 0.02, 0.5, 1.0, float("nan")]),
        (lambda x: hot_spot_weight(x, 0.5), [0.0, 1.0, 3.0, 10.0, 1e300, float("nan")]),
        (lambda x: motion_weight(x), [0.0, 0.3, 1.0, 3.2, float("nan")]),
    ],
)
def test_kernel_under_array_api_strict(kernel, inputs):
    _same(kernel(_strict(inputs)), kernel(np.asarray(inputs)))


def test_fusion_under_array_api_strict():
    p = [[0.5, 0.2], [0.4, 0.1]]
    _same(ta.fuse(_strict(p), axis=0), ta.fuse(np.asarray(p), axis=0))


def test_acquisition_under_array_api_strict():
    n = [0.0, 1.0, 4.0, 9.0]
    strict = ta.acquisition_probabilities(
        _strict(n), clutter=ta.Clutter(scr=_strict([20.0, 5.0, 0.5, 0.5]))
    )
    plain = ta.acquisition_probabilities(
        np.asarray(n), clutter=ta.Clutter(scr=np.asarray([20.0, 5.0, 0.5, 0.5]))
    )
    for task in ("detection", "recognition", "identification", "effect"):
        _same(getattr(strict, task), getattr(plain, task))
