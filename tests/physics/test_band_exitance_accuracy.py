"""band_exitance to 1e-12 relative for any T >= 0, against an independent 45-digit reference.

The reference integrates Planck's law in closed form with Python's ``decimal`` at 45 significant
digits and the CODATA constants of :mod:`scipy.constants` (not ``targetacq.base.constants``):
``M = K T⁴ ∫_{x2}^{x1} t³/(e^t − 1) dt``, ``K = 2π k⁴/(h³c²)``, ``x = hc/(λkT)``, the integral
from one of two series, each summed until its terms fall below 1e-47 of the sum:

- ``x < 2``: ``∫_0^x t³/(e^t − 1) dt = Σ_k B_k x^{k+3}/(k! (k+3))`` with exact Bernoulli
  numbers (``fractions``);
- ``x >= 2``: ``∫_x^∞ t³/(e^t − 1) dt = Σ_n e^{−nx}(x³/n + 3x²/n² + 6x/n³ + 6/n⁴)``.

The reference is checked twice before it is used: the two series agree where both converge
(to 1e-40), and they agree with ``scipy.integrate.quad`` of Planck's law in wavelength, split
into pieces (to 1e-12). Where the true exitance is subnormal (below 2.2e-308) only an absolute
error of 1e-12 · 2.2e-308 is asked (double precision has no relative precision left there).
"""

from __future__ import annotations

import itertools
import math
from decimal import Decimal, localcontext
from fractions import Fraction

import numpy as np
import pytest
from scipy import constants, integrate

import targetacq as ta
from targetacq.physics.bands import band_limits

PRECISION = 45
TINY = 2.2250738585072014e-308  # smallest normal double
RTOL = 1e-12
C2 = constants.h * constants.c / constants.k  # [m K], only to place test temperatures


def _bernoulli(count: int) -> list[Fraction]:
    """B_0 … B_{count−1} (B_1 = −1/2), from Σ_{k<=m} C(m+1, k) B_k = 0."""
    numbers = [Fraction(1)]
    for m in range(1, count):
        numbers.append(-sum(math.comb(m + 1, k) * numbers[k] for k in range(m)) / (m + 1))
    return numbers


_SMALL_TERMS = [b / (math.factorial(k) * (k + 3)) for k, b in enumerate(_bernoulli(240))]


def _pi() -> Decimal:
    """π by Machin's formula, π/4 = 4 atan(1/5) − atan(1/239)."""

    def atan_inverse(n: int) -> Decimal:
        x = Decimal(1) / n
        term, total, k = x, x, 1
        while abs(term) > Decimal(10) ** -(PRECISION + 5):
            term *= -x * x
            k += 2
            total += term / k
        return total

    return 4 * (4 * atan_inverse(5) - atan_inverse(239))


def _partial_small(x: Decimal) -> Decimal:
    """∫_0^x t³/(e^t − 1) dt, Bernoulli series (|x| < 2π)."""
    if x == 0:
        return Decimal(0)
    total, power = Decimal(0), x**3
    for k, c in enumerate(_SMALL_TERMS):
        if c:
            term = Decimal(c.numerator) / Decimal(c.denominator) * power
            total += term
            if k > 6 and abs(term) <= abs(total) * Decimal(10) ** -(PRECISION + 2):
                return total
        power *= x
    raise AssertionError(f"the small-x series does not converge at x = {x}")


def _tail_large(x: Decimal) -> Decimal:
    """∫_x^∞ t³/(e^t − 1) dt, e^{−t}/(1 − e^{−t}) = Σ e^{−nt} integrated term by term."""
    decay = (-x).exp()
    power, total, n = Decimal(1), Decimal(0), 0
    while True:
        n += 1
        power *= decay
        term = power * (x**3 / n + 3 * x**2 / n**2 + 6 * x / n**3 + Decimal(6) / n**4)
        total += term
        if term <= total * Decimal(10) ** -(PRECISION + 2):
            return total


def _tail(x: Decimal) -> Decimal:
    return _tail_large(x) if x >= 2 else _pi() ** 4 / 15 - _partial_small(x)


def reference(t: float, low: float, high: float) -> float:
    """Band exitance [W/m²] between ``low`` and ``high`` [m] at ``t`` [K], 45 digits."""
    with localcontext() as context:
        context.prec = PRECISION
        context.Emin, context.Emax = -(10**9), 10**9
        if t == 0:
            return 0.0
        h, c, k = (Decimal(repr(v)) for v in (constants.h, constants.c, constants.k))
        temperature = Decimal(t)
        x_short = None if low == 0 else h * c / (k * Decimal(low) * temperature)  # None: inf
        x_long = Decimal(0) if math.isinf(high) else h * c / (k * Decimal(high) * temperature)
        if x_short is not None and x_short < 2:  # both small: no large constant cancels
            integral = _partial_small(x_short) - _partial_small(x_long)
        else:
            integral = _tail(x_long) - (Decimal(0) if x_short is None else _tail(x_short))
        value = 2 * _pi() * k**4 / (h**3 * c**2) * temperature**4 * integral
        return math.inf if value > Decimal("1.7976931348623157e308") else float(value)


def assert_close_to_reference(temperatures, low, high, values):
    temperatures = np.asarray(temperatures, dtype=float).reshape(-1)
    values = np.asarray(values, dtype=float).reshape(-1)
    for t, got in zip(temperatures, values, strict=True):
        want = reference(float(t), low, high)
        if want >= TINY or math.isinf(want):
            assert got == pytest.approx(want, rel=RTOL, abs=0), (t, low, high)
        else:
            assert abs(got - want) <= RTOL * TINY, (t, low, high, got, want)


BANDS = [
    "visible",
    "mwir",
    "lwir",
    (0.0, math.inf),
    (0.0, 10e-6),
    (10e-6, math.inf),
    (1e-6, 1e-3),
    (1e-7, 1e-6),
    (3e-6, 3.3e-6),
]


# ---------------------------------------------------------------------------------------------
# The reference itself.
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("x", ["0.25", "0.5", "1", "1.5", "2", "3", "4"])
def test_reference_series_agree_where_both_converge(x):
    with localcontext() as context:
        context.prec = PRECISION
        x = Decimal(x)
        small_x_form = _pi() ** 4 / 15 - _partial_small(x)
        assert abs(small_x_form / _tail_large(x) - 1) < Decimal("1e-40")


def _planck(lam, t):
    h, c, k = constants.h, constants.c, constants.k
    return 2 * math.pi * h * c**2 / lam**5 / math.expm1(h * c / (lam * k * t))


@pytest.mark.parametrize(
    ("t", "band"),
    [(300.0, "lwir"), (300.0, "mwir"), (5800.0, "visible"), (77.0, (1e-6, 1e-3)), (2e4, "lwir")],
)
def test_reference_agrees_with_quadrature_of_plancks_law(t, band):
    low, high = band_limits(band)
    edges = np.geomspace(low, high, 33)  # 32 pieces, each smooth and short
    pieces = [
        integrate.quad(_planck, a, b, args=(t,), epsabs=0, epsrel=1e-13, limit=200)[0]
        for a, b in itertools.pairwise(edges)
    ]
    assert math.fsum(pieces) == pytest.approx(reference(t, low, high), rel=1e-12)


def test_reference_full_spectrum_is_stefan_boltzmann():
    assert reference(300.0, 0.0, math.inf) == pytest.approx(
        constants.Stefan_Boltzmann * 300.0**4, rel=1e-15
    )


# ---------------------------------------------------------------------------------------------
# band_exitance against the reference.
# ---------------------------------------------------------------------------------------------


def test_tables_are_within_1e_15_of_the_reference():
    """The tables of Q on [0, 20) and S on [0, 2) (module docstring of radiometry): within one
    unit in the last place where the platform has an 80-bit long double, 1e-15 asked."""
    from targetacq.physics import radiometry

    q_table, s_table = radiometry._split_tables()
    rng = np.random.default_rng(11)
    with localcontext() as context:
        context.prec = PRECISION
        xs = np.concatenate([rng.uniform(0.0, 20.0, 300), np.arange(0, 1280, 7) / 64.0])
        got = radiometry._tabulated(q_table, xs * 64.0)
        for x, value in zip(xs, got, strict=True):
            want = _tail(Decimal(x)) if x > 0 else _pi() ** 4 / 15
            assert abs(Decimal(float(value)) / want - 1) < Decimal("1e-15"), x
        xs = np.concatenate([rng.uniform(0.0, 2.0, 200), np.arange(1, 128, 3) / 64.0])
        got = radiometry._tabulated(s_table, xs * 64.0)
        for x, value in zip(xs, got, strict=True):
            want = _partial_small(Decimal(x)) / Decimal(x) ** 3
            assert abs(Decimal(float(value)) / want - 1) < Decimal("1e-15"), x


@pytest.mark.parametrize("band", BANDS)
def test_relative_error_below_1e_12_from_1e_3_to_1e5_kelvin(band):
    low, high = band_limits(band)
    temperatures = np.geomspace(1e-3, 1e5, 241)
    assert_close_to_reference(temperatures, low, high, ta.band_exitance(temperatures, band))


def _switch_temperatures(low: float, high: float) -> np.ndarray:
    """Temperatures at which a band edge's x = c2/(λT) crosses the method's switches (2: small-
    and large-x sides, 20: end of the table of Q, 700: logarithms, table interval boundaries k/64
    and the large-x series' ⌈37.5/x⌉ steps), each with its neighbours one ulp away."""
    switches = [2.0, 20.0, 700.0, 708.4, 745.0, 1.0 / 64, 37 / 64, 1.5, 129 / 64, 7.5, 12.5]
    edges = [lam for lam in (low, high) if 0 < lam < math.inf]
    temperatures = []
    for lam in edges:
        for x in switches:
            t = C2 / (lam * x)
            temperatures += [math.nextafter(t, 0.0), t, math.nextafter(t, math.inf)]
    return np.array(temperatures)


@pytest.mark.parametrize("band", [b for b in BANDS if b != (0.0, math.inf)])
def test_relative_error_below_1e_12_where_the_method_switches(band):
    low, high = band_limits(band)
    temperatures = _switch_temperatures(low, high)
    assert_close_to_reference(temperatures, low, high, ta.band_exitance(temperatures, band))


@pytest.mark.parametrize("band", ["lwir", "visible", (0.0, math.inf), (1e-6, 1e-3)])
def test_huge_temperatures_stay_finite_and_accurate(band):
    low, high = band_limits(band)
    temperatures = np.array([1e6, 1e10, 1e40, 1e77, 1e80, 1e200, 1e300, 1.7e308])
    values = ta.band_exitance(temperatures, band)
    assert_close_to_reference(temperatures, low, high, values)  # inf where it overflows
    if band != (0.0, math.inf):  # σT⁴ overflows from about 1e79 K on; a band's value near 1e308
        assert np.all(np.isfinite(values[:-1]))


def test_extreme_bands_near_the_underflow_of_exp():
    """Where e^{−x} is subnormal but K T⁴ x³ e^{−x} is not (a very short band edge)."""
    low, high = 1e-30, 2e-30
    x = np.array([650.0, 700.0, 710.0, 750.0, 800.0, 900.0])
    temperatures = C2 / (high * x)
    values = ta.band_exitance(temperatures, (low, high))
    assert np.all(values > TINY)
    assert_close_to_reference(temperatures, low, high, values)


# ---------------------------------------------------------------------------------------------
# Zero, NaN, inf, negative; shapes.
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("band", BANDS)
def test_zero_nan_and_inf(band):
    assert ta.band_exitance(0.0, band) == 0.0
    assert math.isnan(ta.band_exitance(np.array([math.nan]), band)[0])  # a scalar NaN raises
    assert ta.band_exitance(math.inf, band) == math.inf
    values = ta.band_exitance(np.array([0.0, math.nan, 300.0, math.inf, 1e-3]), band)
    np.testing.assert_array_equal(np.isnan(values), [False, True, False, False, False])
    assert values[0] == 0.0 and values[3] == math.inf and values[4] >= 0.0


def test_tiny_temperatures_underflow_to_zero_without_warnings():
    with np.errstate(all="raise"):
        values = ta.band_exitance(np.array([1e-300, 5e-324, 1e-3, 1.0]), "visible")
    np.testing.assert_array_equal(values, 0.0)


@pytest.mark.parametrize("bad", [-1.0, -1e-300, -math.inf])
def test_negative_temperatures_are_refused(bad):
    with pytest.raises(ValueError, match="temperature must be >= 0"):
        ta.band_exitance(bad, "lwir")
    with pytest.raises(ValueError, match="temperature must be >= 0"):
        ta.band_exitance(np.array([300.0, bad]), "lwir")


def test_a_value_does_not_depend_on_its_neighbours():
    """Chunks of 8192 temperatures choose their method as a whole; each element's value is the
    same alone as among neighbours of any regime, NaN, zero or infinity."""
    rng = np.random.default_rng(3)
    temperatures = np.exp(rng.uniform(math.log(1e-3), math.log(1e6), 20_000))
    temperatures[rng.integers(0, temperatures.size, 300)] = math.nan
    temperatures[rng.integers(0, temperatures.size, 300)] = 0.0
    temperatures[rng.integers(0, temperatures.size, 300)] = math.inf
    for band in ("lwir", "visible", (1e-6, 1e-3)):
        together = ta.band_exitance(temperatures, band)
        alone = np.array([ta.band_exitance(np.array([t]), band)[0] for t in temperatures[::37]])
        np.testing.assert_array_equal(together[::37], alone)


def test_n_d_arrays_broadcast_and_keep_their_shape():
    temperatures = np.geomspace(50.0, 5000.0, 4 * 5 * 6).reshape(4, 5, 6)
    values = ta.band_exitance(temperatures, "mwir")
    assert values.shape == (4, 5, 6)
    np.testing.assert_array_equal(
        values.reshape(-1), ta.band_exitance(temperatures.reshape(-1), "mwir")
    )
    np.testing.assert_array_equal(
        ta.band_exitance(temperatures.T, "mwir"), values.T
    )  # a non-contiguous view
    assert ta.band_exitance(np.empty((0, 3)), "mwir").shape == (0, 3)
    scalar = ta.band_exitance(300.0, "lwir")
    assert isinstance(scalar, np.float64) and np.ndim(scalar) == 0
    np.testing.assert_array_equal(
        ta.band_exitance([250.0, 300.0], "lwir"), ta.band_exitance(np.array([250.0, 300.0]), "lwir")
    )


def test_other_namespaces_and_float32_take_the_series_and_agree():
    """array_api_strict arrays (and float32) go through the series, not the NumPy tables."""
    xps = pytest.importorskip("array_api_strict")
    temperatures = [0.0, 1.0, 77.0, 300.0, 3000.0, 1e5, math.nan]
    for band in ("visible", "mwir", "lwir", (0.0, math.inf)):
        strict = ta.band_exitance(xps.asarray(temperatures, dtype=xps.float64), band)
        assert type(strict).__module__.startswith("array_api_strict")
        np.testing.assert_allclose(
            np.asarray(strict), ta.band_exitance(np.array(temperatures), band), rtol=1e-13
        )
    single = ta.band_exitance(np.array([250.0, 300.0], dtype=np.float32), "lwir")
    np.testing.assert_allclose(single, ta.band_exitance(np.array([250.0, 300.0]), "lwir"), 1e-6)


def test_wien_method_against_its_closed_form():
    """Eq. (6.13): ``K T⁴ [e^{−x}(x³ + 3x² + 6x + 6)]`` between the edges, in 45 digits."""
    with localcontext() as context:
        context.prec = PRECISION
        h, c, k = (Decimal(repr(v)) for v in (constants.h, constants.c, constants.k))
        for t in (50.0, 300.0, 3000.0):

            def tail(lam, t=t):
                x = h * c / (k * Decimal(lam) * Decimal(t))
                return (-x).exp() * (((x + 3) * x + 6) * x + 6)

            want = 2 * _pi() * k**4 / (h**3 * c**2) * Decimal(t) ** 4 * (tail(12e-6) - tail(8e-6))
            got = ta.band_exitance(t, "lwir", method="wien")
            assert got == pytest.approx(float(want), rel=RTOL)


# ---------------------------------------------------------------------------------------------
# The numba version (optional: the ``fast`` extra).
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("band", BANDS)
def test_numba_version_agrees_with_numpy(band):
    pytest.importorskip("numba")
    from targetacq.core.engines.numba_radiometry import band_exitance_numba

    low, high = band_limits(band)
    temperatures = np.concatenate(
        [
            np.geomspace(1e-3, 1e5, 2001),
            _switch_temperatures(low, high),
            [0.0, math.nan, math.inf, 1e80, 1e300],
        ]
    )
    np.testing.assert_allclose(
        band_exitance_numba(temperatures, low, high),
        ta.band_exitance(temperatures, band),
        rtol=1e-12,
        atol=RTOL * TINY,
    )
    assert band_exitance_numba(300.0, low, high) == pytest.approx(
        ta.band_exitance(300.0, band), rel=1e-12
    )
    assert band_exitance_numba(temperatures.reshape(-1, 1)[:6], low, high).shape == (6, 1)
