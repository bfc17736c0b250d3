"""Stage 4, the independent verification gate.

:mod:`~trajopt.verify.gate` checks the rows (limits, separation at rows and between rows, words, rest and the
time grid) and says why a motion fails; :mod:`~trajopt.verify.kernels` and :mod:`~trajopt.verify.sampling` are its
compiled passes over the rows and over the plan; :mod:`~trajopt.verify.planar` checks the footprints in the plane;
:mod:`~trajopt.verify.rows` holds the rows as one :class:`~trajopt.verify.rows.Setpoints`.

The names of :mod:`~trajopt.verify.gate` (its ``__all__``) are importable from here too; they load on first use, so
importing :mod:`trajopt.verify.rows` does not load numba and the kernels.
"""

from __future__ import annotations

import importlib
from typing import Any


def __getattr__(name: str) -> Any:
    gate = importlib.import_module("trajopt.verify.gate")
    if name in gate.__all__:
        return getattr(gate, name)
    raise AttributeError(f"module 'trajopt.verify' has no attribute {name!r}")
