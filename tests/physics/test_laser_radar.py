"""Laser radar kernels: worked numbers computed here from the constants written out, the
properties the module docstring states, an input matrix, and JAX under ``jit``."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from targetacq.physics import atmosphere, laser_radar_equation
from targetacq.physics.laser_radar_equation import (
    cross_range_resolution,
    laser_snr,
    range_cells_on_target,
    range_resolution,
    received_power,
    relief_scr,
    relief_seen,
    two_way_optical_depth,
)

C = 299_792_458.0  # m/s, exact by the SI definition of the metre
INF = math.inf
positive = st.floats(1e-3, 1e3)


def test_range_and_cross_range_resolution():
    assert range_resolution(1e-9) == pytest.approx(C * 1e-9 / 2, rel=1e-15)
    assert range_resolution(10e-9) == pytest.approx(1.49896229, rel=1e-15)
    assert range_resolution(INF) == INF
    np.testing.assert_allclose(range_resolution([2e-9, 4e-9]), [C * 1e-9, 2 * C * 1e-9])
    assert cross_range_resolution(2000.0, 0.1e-3) == pytest.approx(0.2, rel=1e-15)
    assert cross_range_resolution(0.0, 1e-3) == 0.0
    assert cross_range_resolution(INF, 1e-3) == INF


def test_relief_and_range_cells():
    assert relief_seen(2.5, 0.8) == pytest.approx(2.0)
    assert relief_seen(2.5, 0.0) == 0.0
    assert range_cells_on_target(2.0, 0.25) == 8.0
    assert range_cells_on_target(2.0, INF) == 0.0
    # The two chain: a 3 m target 60 % visible, 1 ns timing: 1.8 / (C · 0.5e-9) cells.
    cells = range_cells_on_target(relief_seen(3.0, 0.6), range_resolution(1e-9))
    assert cells == pytest.approx(1.8 / (C * 0.5e-9), rel=1e-14)


def test_relief_scr_values_and_limits():
    # Clutter alone, quantisation alone (std Δr/√12), both in variance.
    assert relief_scr(2.0, 0.5, 0.0) == pytest.approx(4.0, rel=1e-15)
    assert relief_scr(2.0, 0.0, 0.5 * math.sqrt(12.0)) == pytest.approx(4.0, rel=1e-15)
    assert relief_scr(2.0, 0.3, 1.2) == pytest.approx(2.0 / math.sqrt(0.09 + 0.12), rel=1e-15)
    assert relief_scr(2.0, 0.0, 0.0) == INF  # no clutter
    assert relief_scr(0.0, 0.0, 0.0) == 0.0  # no relief
    assert relief_scr(0.0, 0.4, 0.1) == 0.0
    assert relief_scr(2.0, INF, 0.1) == 0.0
    assert relief_scr(2.0, 0.1, INF) == 0.0
    # Huge but finite spreads neither overflow nor underflow the ratio.
    assert relief_scr(1e200, 1e200, 0.0) == pytest.approx(1.0)
    assert relief_scr(1e-200, 1e-200, 0.0) == pytest.approx(1.0)


@given(positive, positive, positive, st.floats(1.01, 10.0))
def test_relief_scr_is_linear_in_relief_and_decreasing_in_clutter(h, s, dr, k):
    base = relief_scr(h, s, dr)
    assert relief_scr(k * h, s, dr) == pytest.approx(k * base, rel=1e-13)
    assert relief_scr(h, k * s, dr) < base
    assert relief_scr(h, s, k * dr) < base


def _worked_example():
    # P_t 10 kW, ρ 0.1, D 10 cm, τ = exp(-0.2) one way, η 0.5, R 1 km. A_r / π = D² / 4, so
    # P_r = P_t ρ τ² η D² / (4 R²), written out: 1e4 · 0.1 · exp(-0.4) · 0.5 · 0.01 / 4e6.
    expected = 1e4 * 0.1 * math.exp(-0.4) * 0.5 * 0.01 / 4e6
    got = received_power(1000.0, 1e4, 0.1, math.pi * 0.05**2, math.exp(-0.2), 0.5)
    return got, expected


def test_received_power_worked_example():
    got, expected = _worked_example()
    assert got == pytest.approx(expected, rel=1e-14)
    assert got == pytest.approx(8.37900e-7, rel=1e-5)


@given(positive, st.floats(1.0, 1e5), st.floats(1.01, 100.0), st.floats(0.01, 1.0))
def test_received_power_scaling(power, rng, k, tau):
    base = received_power(rng, power, 0.3, 0.01, tau, 0.8)
    assert received_power(k * rng, power, 0.3, 0.01, tau, 0.8) == pytest.approx(
        base / k**2, rel=1e-13
    )
    assert received_power(rng, power, 0.3, 0.01, tau / k, 0.8) == pytest.approx(
        base / k**2, rel=1e-13
    )
    assert received_power(rng, k * power, 0.3, 0.01, tau, 0.8) == pytest.approx(k * base, rel=1e-13)
    assert received_power(rng, power, 0.3, k * 0.01, tau, 0.8) == pytest.approx(k * base, rel=1e-13)


def test_received_power_limits():
    assert received_power(INF, 1.0, 0.5, 0.01, 1.0) == 0.0
    assert received_power(1e200, 1.0, 0.5, 0.01, 1.0) == 0.0
    assert received_power(1e-200, 1.0, 0.5, 0.01, 1.0) == INF
    assert received_power(1e-200, 0.0, 0.5, 0.01, 1.0) == 0.0  # no 0 / 0
    assert received_power(100.0, 1.0, 0.5, 0.01, 0.0) == 0.0
    assert received_power(100.0, 1.0, 0.0, 0.01, 1.0) == 0.0
    # Default efficiency 1: a Lambertian white target, clear air: A / (π R²) of the power.
    assert received_power(10.0, 1.0, 1.0, math.pi, 1.0) == pytest.approx(0.01, rel=1e-15)


def test_laser_snr_is_an_amplitude_ratio():
    assert laser_snr(1e-6, 1e-8) == pytest.approx(40.0, rel=1e-15)
    assert laser_snr(1e-8, 1e-8) == 0.0
    # Currents i = ℜ P: the electrical power ratio (i_s / i_n)² in 10 log10 dB is the same.
    responsivity, p, nep = 0.9, 3e-7, 2e-8
    electrical = (responsivity * p) ** 2 / (responsivity * nep) ** 2
    assert laser_snr(p, nep) == pytest.approx(10 * math.log10(electrical), rel=1e-14)
    assert laser_snr(0.0, 1e-8) == -INF
    assert laser_snr(1e-9, 0.0) == INF
    assert laser_snr(0.0, 0.0) == INF  # no receiver noise: the noise-free model
    assert laser_snr(INF, 1e-8) == INF
    assert laser_snr(1e-9, INF) == -INF
    assert np.isnan(laser_snr(INF, INF))


def test_snr_decreases_with_range_through_the_atmosphere():
    ranges = np.linspace(100.0, 20e3, 200)
    tau = np.exp(-0.2e-3 * ranges)  # one way, 0.2 Np/km
    snr = laser_snr(received_power(ranges, 1e4, 0.2, 0.01, tau, 0.6), 1e-9)
    assert np.all(np.diff(snr) < 0)
    atmos = atmosphere.snr_from_optical_depth(two_way_optical_depth(0.2e-3 * ranges))
    assert np.all(np.diff(atmos) < 0)


def test_two_way_optical_depth_is_the_square_of_the_transmittance():
    assert two_way_optical_depth(0.3) == pytest.approx(0.6)
    assert two_way_optical_depth(0.0) == 0.0
    assert two_way_optical_depth(INF) == INF
    for d in (0.05, math.log(2.0), 2.0):
        tau = math.exp(-d)
        assert atmosphere.snr_from_optical_depth(two_way_optical_depth(d)) == pytest.approx(
            atmosphere.snr_from_transmittance(tau * tau), rel=1e-12
        )


# Each kernel with valid arguments; the input matrix below swaps one argument at a time.
KERNELS = {
    "range_resolution": (range_resolution, {"timing": 1e-9}),
    "cross_range_resolution": (
        cross_range_resolution,
        {"range": 1000.0, "detector_ifov": 1e-4},
    ),
    "relief_seen": (relief_seen, {"height": 2.5, "visible_fraction": 0.8}),
    "range_cells_on_target": (range_cells_on_target, {"relief": 2.0, "range_resolution": 0.3}),
    "relief_scr": (
        relief_scr,
        {"target_relief": 2.0, "background_relief_std": 0.3, "range_resolution": 0.5},
    ),
    "received_power": (
        received_power,
        {
            "range": 1000.0,
            "power": 1e4,
            "reflectance": 0.1,
            "aperture_area": 0.01,
            "transmittance": 0.8,
            "efficiency": 0.5,
        },
    ),
    "laser_snr": (laser_snr, {"received_power": 1e-7, "noise_equivalent_power": 1e-9}),
    "two_way_optical_depth": (two_way_optical_depth, {"optical_depth": 0.3}),
}
ARGUMENTS = [(k, name) for k, (_, args) in KERNELS.items() for name in args]
# Arguments that must be > 0 (0 refused), and those whose +inf is refused.
ZERO_REFUSED = {
    ("range_resolution", "timing"),
    ("cross_range_resolution", "detector_ifov"),
    ("range_cells_on_target", "range_resolution"),
    ("received_power", "range"),
}
FINITE_ONLY = {"detector_ifov", "height", "relief", "target_relief", "power", "aperture_area"}
UNIT_INTERVAL = {"visible_fraction", "reflectance", "transmittance", "efficiency"}


def _call(kernel, changes):
    function, args = KERNELS[kernel]
    return function(**{**args, **changes})


@pytest.mark.parametrize(("kernel", "name"), ARGUMENTS)
def test_negative_and_scalar_nan_are_refused_naming_the_input(kernel, name):
    with pytest.raises(ValueError, match=name):
        _call(kernel, {name: -1.0})
    with pytest.raises(ValueError, match=name):
        _call(kernel, {name: math.nan})
    with pytest.raises(TypeError, match=name):
        _call(kernel, {name: True})


@pytest.mark.parametrize(("kernel", "name"), ARGUMENTS)
def test_zero_and_infinity_give_the_documented_result(kernel, name):
    if (kernel, name) in ZERO_REFUSED:
        with pytest.raises(ValueError, match=name):
            _call(kernel, {name: 0.0})
    else:
        assert not np.isnan(_call(kernel, {name: 0.0}))
    if name in FINITE_ONLY or name in UNIT_INTERVAL:
        with pytest.raises(ValueError, match=name):
            _call(kernel, {name: INF})
    else:
        assert not np.isnan(_call(kernel, {name: INF}))


@pytest.mark.parametrize(("kernel", "name"), ARGUMENTS)
def test_nan_in_an_array_is_nan_out_there_only(kernel, name):
    value = KERNELS[kernel][1][name]
    out = np.asarray(_call(kernel, {name: np.array([value, math.nan, value])}))
    assert out.shape == (3,)
    assert np.isnan(out[1]) and not np.isnan(out[[0, 2]]).any()
    assert out[0] == out[2] == _call(kernel, {})


@pytest.mark.parametrize("kernel", [k for k, (_, args) in KERNELS.items() if len(args) > 1])
def test_broadcasting_n_d_and_shapes_that_do_not_broadcast(kernel):
    function, args = KERNELS[kernel]
    names = list(args)
    rng = np.random.default_rng(3)
    shapes = [(2, 1, 3), (4, 1), (3,), (1,), (1, 1, 1), ()]
    batch = {
        n: args[n] * rng.uniform(0.5, 1.0, shapes[k]) if shapes[k] else args[n]
        for k, n in enumerate(names)
    }
    out = np.asarray(function(**batch))
    full = np.broadcast_shapes(*(np.shape(v) for v in batch.values()))
    assert out.shape == full
    index = (1, 2, 0)[-len(full) :] if full else ()
    scalars = {n: float(np.broadcast_to(v, full)[index]) for n, v in batch.items()}
    assert out[index] == pytest.approx(function(**scalars), rel=1e-15)
    with pytest.raises(ValueError, match=f"{names[0]} .* and {names[1]} .* do not broadcast"):
        function(**{**args, names[0]: np.ones(3), names[1]: np.ones(2)})


def test_quantities_are_taken_in_si():
    pint = pytest.importorskip("pint")
    ureg = pint.UnitRegistry()
    got = received_power(
        1 * ureg.km, 10 * ureg.kW, 0.1, 100 * ureg.cm**2, 0.8, 0.5
    )  # 100 cm² = 0.01 m²
    assert got == pytest.approx(received_power(1000.0, 1e4, 0.1, 0.01, 0.8, 0.5), rel=1e-14)
    assert range_resolution(1 * ureg.ns) == pytest.approx(C * 0.5e-9, rel=1e-15)


def test_jax_jit_equals_numpy():
    jax = pytest.importorskip("jax")
    jnp = pytest.importorskip("jax.numpy")
    jax.config.update("jax_enable_x64", True)
    rng = np.random.default_rng(11)
    for kernel, (function, args) in KERNELS.items():
        batch = {n: v * rng.uniform(0.5, 1.0, (5,)) for n, v in args.items()}
        want = np.asarray(function(**batch))
        got = jax.jit(function)(**{n: jnp.asarray(v) for n, v in batch.items()})
        assert isinstance(got, jax.Array), kernel
        np.testing.assert_allclose(np.asarray(got), want, rtol=1e-12, atol=0, err_msg=kernel)
    # The limits under jit too: no clutter, no receiver noise, no range.
    edges = jax.jit(relief_scr)(jnp.asarray([2.0, 0.0]), jnp.zeros(2), jnp.zeros(2))
    np.testing.assert_array_equal(np.asarray(edges), [INF, 0.0])
    assert float(jax.jit(laser_snr)(jnp.asarray(1e-9), jnp.asarray(0.0))) == INF


def test_module_exports():
    assert sorted(laser_radar_equation.__all__) == sorted(KERNELS)
