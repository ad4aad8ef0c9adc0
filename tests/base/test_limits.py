"""The limits every front-end checks (targetacq.base.limits): boundaries, in and just out."""

from __future__ import annotations

import doctest
import math

import pytest

from targetacq.base import inputs, limits
from targetacq.base.limits import (
    MAX_ELEMENTS,
    MAX_LENGTH,
    MAX_SEED,
    MAX_TEMPERATURE,
    check_count,
    check_finite,
    check_length,
    check_range,
    check_seed,
    check_size,
    check_temperature,
    check_temperature_difference,
)

NOT_FINITE = [math.nan, math.inf, -math.inf]


def test_the_limits_hold_the_values_the_messages_quote():
    assert MAX_TEMPERATURE == 1e4
    assert MAX_LENGTH == 1e9
    assert limits.MAX_INPUT_BYTES == 10 * 1000**2
    assert limits.BYTES_PER_EVALUATION == 1024
    assert f"{MAX_ELEMENTS:.4g}" == "1.1e+12"
    # Squares and products of the largest lengths stay far from overflow.
    assert math.isfinite(MAX_LENGTH**3 * 1e100)


# -- temperatures ---------------------------------------------------------------------------------


def test_temperature_accepts_its_whole_domain():
    assert check_temperature("T", MAX_TEMPERATURE) == MAX_TEMPERATURE
    assert check_temperature("T", 5e-324) == 5e-324  # the smallest positive double
    assert check_temperature("T", 300) == 300.0


@pytest.mark.parametrize(
    ("value", "got"),
    [
        (math.nextafter(MAX_TEMPERATURE, math.inf), "got 10000 K"),
        (0.0, "got 0 K"),
        (-0.0, "got -0 K"),
        (-5.0, "got -5 K"),
    ],
)
def test_temperature_outside_its_domain_is_refused(value, got):
    with pytest.raises(ValueError, match="--target-temperature") as info:
        check_temperature("--target-temperature", value)
    assert str(info.value) == f"--target-temperature must be in (0, 10000] K; {got}"


@pytest.mark.parametrize("value", NOT_FINITE)
def test_temperature_not_finite_is_refused(value):
    with pytest.raises(ValueError, match=r"^temperature must be (a number|finite)"):
        check_temperature("temperature", value)


def test_temperature_difference_is_unsigned_unless_asked():
    assert check_temperature_difference("netd", 0.0) == 0.0
    assert check_temperature_difference("netd", MAX_TEMPERATURE) == MAX_TEMPERATURE
    with pytest.raises(ValueError, match=r"^netd must be in \[0, 10000\] K; got -0.05 K$"):
        check_temperature_difference("netd", -0.05)
    with pytest.raises(ValueError, match=r"^netd must be in \[0, 10000\] K; got 10000 K$"):
        check_temperature_difference("netd", math.nextafter(MAX_TEMPERATURE, math.inf))
    assert check_temperature_difference("dT", -MAX_TEMPERATURE, signed=True) == -MAX_TEMPERATURE
    with pytest.raises(ValueError, match=r"^dT must be in \[-10000, 10000\] K; got -1e\+06 K$"):
        check_temperature_difference("dT", -1e6, signed=True)
    for value in NOT_FINITE:
        with pytest.raises(ValueError, match=r"^dT must be"):
            check_temperature_difference("dT", value, signed=True)


# -- lengths and counts ---------------------------------------------------------------------------


def test_length_accepts_up_to_a_million_kilometres_either_way():
    for value in (MAX_LENGTH, -MAX_LENGTH, 0.0, 1.7e-5):
        assert check_length("x", value) == value


@pytest.mark.parametrize("value", [math.nextafter(MAX_LENGTH, math.inf), -2e9, 6.56e193])
def test_length_beyond_the_limit_is_refused(value):
    with pytest.raises(ValueError, match=r"^--pitch must be within ±1e\+09 m; got "):
        check_length("--pitch", value)
    with pytest.raises(ValueError, match=r"^position: coordinates must be within ±1e\+09 m"):
        check_length("position", value, "coordinates")


@pytest.mark.parametrize("value", NOT_FINITE)
def test_length_not_finite_is_refused(value):
    with pytest.raises(ValueError, match=r"^x must be (a number|finite)"):
        check_length("x", value)


def test_count_bounds():
    assert check_count("n", 1) == 1
    assert check_count("n", MAX_ELEMENTS) == MAX_ELEMENTS
    assert check_count("i", 0, low=0) == 0
    with pytest.raises(ValueError, match=r"^n must be a whole number in \[1, 1.1e\+12\]; got 0$"):
        check_count("n", 0)
    with pytest.raises(ValueError, match=r"got 1099511627777$"):
        check_count("n", MAX_ELEMENTS + 1)
    with pytest.raises(ValueError, match=r"got a number of 20 digits$"):
        check_count("n", 2**64)
    with pytest.raises(ValueError, match=r"got a number of 20 digits$"):
        check_count("n", -(2**64))


# -- finite numbers, ranges, seeds ----------------------------------------------------------------


def test_finite_and_range():
    assert check_finite("a", "2.5") == 2.5
    with pytest.raises(ValueError, match=r"^a must be a number; got NaN$"):
        check_finite("a", math.nan)
    with pytest.raises(
        ValueError, match=r"^a must be finite; got -inf \(an overflowing number\?\)"
    ):
        check_finite("a", -math.inf)
    assert check_range("r", 1.0, 0.0, 1.0) == 1.0
    assert check_range("r", 0.0, 0.0, 1.0) == 0.0
    with pytest.raises(ValueError, match=r"^r must be in \[0, 1\]; got 1$"):
        check_range("r", math.nextafter(1.0, 2.0), 0.0, 1.0)


def test_seed_bounds_and_types():
    assert check_seed(0) == 0
    assert check_seed(MAX_SEED) == MAX_SEED
    for bad in (True, False, -1, MAX_SEED + 1, 1.0, "1", None):
        with pytest.raises(ValueError, match=r"^seed must be an integer in \[0, 2\*\*128 - 1\]"):
            check_seed(bad)
    with pytest.raises(ValueError, match=r"^--seed must be"):
        check_seed(True, "--seed")


# -- sizes ----------------------------------------------------------------------------------------


def test_size_against_the_memory_available(monkeypatch):
    monkeypatch.setattr(limits, "available_memory", lambda: 1000 * 2**30 // 1000)  # 1 GiB
    check_size(2**30 // 8, 8, "exactly the memory", "no advice")
    with pytest.raises(ValueError, match="one element more") as info:
        check_size(2**30 // 8 + 1, 8, "one element more", "use fewer")
    assert str(info.value) == (
        "one element more needs about 1.07e+09 bytes (1 GiB); this machine has 1 GiB "
        "available: use fewer"
    )


def test_size_beyond_the_element_limit_or_overflowing_is_refused_whatever_the_memory(
    monkeypatch,
):
    monkeypatch.setattr(limits, "available_memory", lambda: 2**80)
    check_size(MAX_ELEMENTS, 1, "at the limit", "")
    with pytest.raises(ValueError, match=r"^just over needs"):
        check_size(MAX_ELEMENTS + 1, 1, "just over", "")
    with pytest.raises(ValueError, match=r"^overflowing needs about inf bytes"):
        check_size(1e200, 1e200, "overflowing", "")
    with pytest.raises(ValueError, match=r"^nan needs"):
        check_size(math.nan, 8, "nan", "")


def test_available_memory_is_a_positive_number_of_bytes():
    assert limits.available_memory() > 0


@pytest.mark.parametrize("module", [limits, inputs])
def test_docstring_examples_run(module):
    failures, tried = doctest.testmod(module, optionflags=doctest.ELLIPSIS)
    assert tried > 0 and failures == 0
