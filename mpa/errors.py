"""Exceptions raised by :mod:`mpa` (and re-used by :mod:`trajopt`).

The hierarchy keeps the caller's mistakes apart from answers and from numerical trouble:

- :class:`MPAError` -- base class of everything raised on purpose by this project.
- :class:`InvalidInputError` -- the caller passed something out of range (also a :class:`ValueError`).
- :class:`NoMotionError` -- the query is well formed but no collision-free motion exists; the message says why.
- :class:`PlanningError` -- an internal step could not be completed (a bug or an unsupported corner case).
"""

from __future__ import annotations

__all__ = ["InvalidInputError", "MPAError", "NoMotionError", "PlanningError"]


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
