"""Stage 4, the independent verification gate.

:mod:`~trajopt.verify.gate` checks the rows (limits, separation at rows and between rows, words, rest and the
time grid) and says why a motion fails; :mod:`~trajopt.verify.kernels` and :mod:`~trajopt.verify.sampling` are its
compiled passes over the rows and over the plan; :mod:`~trajopt.verify.planar` checks the footprints in the plane;
:mod:`~trajopt.verify.rows` holds the rows as one :class:`~trajopt.verify.rows.Setpoints`.

The names of :mod:`~trajopt.verify.gate` are importable from here; they load on first use, so importing
:mod:`trajopt.verify.rows` does not compile the kernels.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    from trajopt.verify.gate import (
        CLASS_FAILURE_PREFIXES,
        LIMIT_RTOL,
        POSITION_TOL,
        SEPARATION_TOL,
        Setpoints,
        VerificationError,
        VerificationReport,
        between_rows_separation,
        class_failures_only,
        declared_limit_failures,
        lane_rule_failures,
        separation_margin,
        skeleton_word,
        verify_graph_setpoints,
        verify_setpoints,
    )

__all__ = [
    "CLASS_FAILURE_PREFIXES",
    "LIMIT_RTOL",
    "POSITION_TOL",
    "SEPARATION_TOL",
    "Setpoints",
    "VerificationError",
    "VerificationReport",
    "between_rows_separation",
    "class_failures_only",
    "declared_limit_failures",
    "lane_rule_failures",
    "separation_margin",
    "skeleton_word",
    "verify_graph_setpoints",
    "verify_setpoints",
]


def __getattr__(name: str) -> Any:
    if name in __all__:
        return getattr(importlib.import_module("trajopt.verify.gate"), name)
    raise AttributeError(f"module 'trajopt.verify' has no attribute {name!r}")
