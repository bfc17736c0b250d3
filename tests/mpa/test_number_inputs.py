"""The numbers the caller gives: one reader per kind, each message naming the quantity, the value and what was
expected (conventions: Errors and exit status)."""

from __future__ import annotations

import math

import pytest

from mpa import Lollipop
from mpa.errors import InvalidInputError, nonnegative_number, positive_number
from trajopt.analysis.delay import validate_delay_tolerance
from trajopt.analysis.min_margin import validate_min_margin
from trajopt.grid import validate_rate


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: Lollipop(stick=-1.0), "stick length is -1.0, expected a positive finite number (metres)"),
        (lambda: Lollipop(loop="x"), "loop length is 'x', expected a positive finite number (metres)"),
        (lambda: validate_rate(0), "rate is 0.0, expected a positive finite number (Hz)"),
        (lambda: validate_rate(None, "--rate"), "--rate is None, expected a positive finite number (Hz)"),
        (lambda: validate_min_margin(-0.5), "min_margin is -0.5, expected a finite number of metres >= 0"),
        (lambda: validate_min_margin([1]), "min_margin is [1], expected a number of metres >= 0"),
        (
            lambda: validate_delay_tolerance(math.inf),
            "delay tolerance is inf, expected a finite number of seconds >= 0",
        ),
        (lambda: validate_delay_tolerance("soon"), "delay tolerance is 'soon', expected a number of seconds >= 0"),
        # a Python int too large for a float is bad input too, not an OverflowError
        (lambda: validate_min_margin(10**400), "min_margin is 1000"),
    ],
)
def test_bad_numbers_name_the_quantity_the_value_and_what_was_expected(call, message: str) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(InvalidInputError) as info:
        call()
    assert str(info.value).startswith(message), str(info.value)


@pytest.mark.parametrize("value", [0.0, 1e-300, 2.5, "3", 7])
def test_good_numbers_come_back_as_floats(value: object) -> None:
    assert nonnegative_number(value, "x", "metres") == float(value)  # type: ignore[arg-type]
    if float(value) > 0:  # type: ignore[arg-type]
        assert positive_number(value, "x", "Hz") == float(value)  # type: ignore[arg-type]
    else:
        with pytest.raises(InvalidInputError, match=r"^x is 0.0, expected a positive finite number \(Hz\)$"):
            positive_number(value, "x", "Hz")
    for check in (positive_number, nonnegative_number):  # NaN is neither
        with pytest.raises(InvalidInputError, match="expected a"):
            check(float("nan"), "x", "metres")
