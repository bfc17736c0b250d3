"""Exceptions raised by :mod:`mpa` (and re-used by :mod:`trajopt`).

The hierarchy keeps the caller's mistakes apart from answers and from numerical trouble:

- :class:`MPAError` -- base class of everything raised on purpose by this project.
- :class:`InvalidInputError` -- the caller passed something out of range (also a :class:`ValueError`).
- :class:`NoMotionError` -- the query is well formed but no collision-free motion exists; the message says why.
- :class:`PlanningError` -- an internal step could not be completed (a bug or an unsupported corner case).

:func:`positive_number` and :func:`nonnegative_number` read a number the caller gave, raising
:class:`InvalidInputError` with the message the conventions ask for (the quantity, its value, what was expected).
"""

from __future__ import annotations

import math
from typing import Any

__all__ = [
    "InvalidInputError",
    "MPAError",
    "NoMotionError",
    "PlanningError",
    "nonnegative_number",
    "positive_number",
]


class MPAError(Exception):
    """Base class of the errors raised by this project.

    The message is one line (a value's multi-line ``repr``, e.g. of an array, is joined with spaces), so that
    the command line can print it as one ``error:`` line.
    """

    def __str__(self) -> str:
        text = super().__str__()
        return " ".join(text.split()) if "\n" in text else text


class InvalidInputError(MPAError, ValueError):
    """A quantity given by the caller is not valid (names the quantity, its value and what was expected)."""


class NoMotionError(MPAError):
    """No collision-free motion between the requested start and goal exists (the message says why)."""


class PlanningError(MPAError):
    """A planning step failed although the input was valid."""


def _number(value: Any, name: str, expected: str) -> float:
    try:
        return float(value)
    except (TypeError, ValueError, OverflowError):
        raise InvalidInputError(f"{name} is {value!r}, expected {expected}") from None


def positive_number(value: Any, name: str, unit: str) -> float:
    """``value`` as a float > 0 and finite.

    Parameters
    ----------
    value : object
        What the caller gave.
    name : str
        The quantity, as the message names it (e.g. ``"rate"``, ``"stick length"``).
    unit : str
        Its unit in words (e.g. ``"metres"``, ``"Hz"``).

    Raises
    ------
    InvalidInputError
        ``"{name} is {value!r}, expected a positive finite number ({unit})"``.
    """
    expected = f"a positive finite number ({unit})"
    v = _number(value, name, expected)
    if not math.isfinite(v) or v <= 0:
        raise InvalidInputError(f"{name} is {v!r}, expected {expected}")
    return v


def nonnegative_number(value: Any, name: str, unit: str) -> float:
    """``value`` as a float >= 0 and finite, else :class:`InvalidInputError`: ``"{name} is {value!r}, expected a
    number of {unit} >= 0"`` (not a number) or ``"... a finite number of {unit} >= 0"`` (negative, infinite or NaN).
    ``unit`` in words, plural (``"metres"``, ``"seconds"``); see :func:`positive_number`."""
    v = _number(value, name, f"a number of {unit} >= 0")
    if not math.isfinite(v) or v < 0.0:
        raise InvalidInputError(f"{name} is {value!r}, expected a finite number of {unit} >= 0")
    return v
