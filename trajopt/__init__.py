"""trajopt: optimisation-based, jerk-limited trajectories on the plans of :mod:`mpa`, exported as setpoints.

The pipeline has one module per stage: :mod:`trajopt.path.fastpath` (a query whose straight route-coordinate motion
keeps the clearance: one phase-synchronised ruckig profile), :mod:`trajopt.path.corridor` (the hard path: a strictly
convex QP in a corridor fixed by the plan, continuous in the query), :mod:`trajopt.path.planview` (every
:class:`mpa.MotionPlan` in one route geometry, :class:`mpa.geometry.RouteGeometry`),
:mod:`trajopt.timing` (C² paths and their jerk-limited timing),
:mod:`trajopt.verify.gate` (the independent gate, on rows given as one :class:`~trajopt.verify.rows.Setpoints`),
:mod:`trajopt.result` (the :class:`Trajectory` result),
:mod:`trajopt.io` (atomic writes, CSV, JSON summary) and :mod:`trajopt.generator` (the pipeline with its
fallback); :mod:`trajopt.analysis.stability` measures continuity. The
drawings (:mod:`trajopt.viz`) and the command line (:mod:`trajopt.cli`, one module per subcommand) sit on top; the
pipeline imports neither, and nothing else in :mod:`trajopt` imports matplotlib.

Conventions: arrays are ``(N, 2)`` with robot A in column 0 and B in column 1, time is ``t``, SI units (m, s),
limits are per robot on the route coordinate ``s`` (signed distance along the robot's own route).

Names are imported on first use (PEP 562), so ``import trajopt.cli`` does not load the pipeline, CasADi, toppra
or ruckig before a command needs them.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from trajopt import _aliases

if TYPE_CHECKING:  # pragma: no cover
    from trajopt.generator import GraphPlanner, TrajectoryGenerator, generate_trajectory
    from trajopt.io.csvfile import CSV_COLUMNS, GRAPH_CSV_COLUMNS, XY_COLUMNS
    from trajopt.result import Source, Trajectory
    from trajopt.timing import Limits
    from trajopt.verify.gate import VerificationError, VerificationReport, verify_graph_setpoints, verify_setpoints
    from trajopt.verify.rows import Setpoints

_aliases.install()

_WHERE = {
    "CSV_COLUMNS": "trajopt.io.csvfile",
    "GRAPH_CSV_COLUMNS": "trajopt.io.csvfile",
    "XY_COLUMNS": "trajopt.io.csvfile",
    "GraphPlanner": "trajopt.generator",
    "verify_graph_setpoints": "trajopt.verify.gate",
    "Setpoints": "trajopt.verify.rows",
    "Source": "trajopt.result",
    "Trajectory": "trajopt.result",
    "TrajectoryGenerator": "trajopt.generator",
    "generate_trajectory": "trajopt.generator",
    "Limits": "trajopt.timing",
    "VerificationError": "trajopt.verify.gate",
    "VerificationReport": "trajopt.verify.gate",
    "verify_setpoints": "trajopt.verify.gate",
}

__all__ = [
    "CSV_COLUMNS",
    "GRAPH_CSV_COLUMNS",
    "XY_COLUMNS",
    "GraphPlanner",
    "Limits",
    "Setpoints",
    "Source",
    "Trajectory",
    "TrajectoryGenerator",
    "VerificationError",
    "VerificationReport",
    "generate_trajectory",
    "verify_graph_setpoints",
    "verify_setpoints",
]


def __getattr__(name: str) -> Any:
    if name in _WHERE:
        value = getattr(importlib.import_module(_WHERE[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'trajopt' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted([*globals(), *__all__])
