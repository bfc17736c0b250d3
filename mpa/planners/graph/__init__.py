"""A complete planner for two robots on any graph track: shortest or fastest paths in the exact free space.

Entry point :func:`plan_graph` (also :func:`mpa.plan` with ``planner="graph"`` or on a graph track). An any-angle
A* over roots (face ends, corners) and intervals of faces in the free polygons of :mod:`mpa.freespace`, complete
and optimal for the objective; each robot's independent fastest motion is tried first, and the corners of a
searched ``fastest`` plan are re-solved by :mod:`mpa.planners.corners`. The search, its costs and tie-breaks, why
it is optimal and what is guaranteed: docs/graphs.md, "The search in detail".
"""

from __future__ import annotations

from mpa._arrays import FloatArray  # noqa: F401
from mpa.planners.graph.assemble import _assemble, _merge_same_polygon, _route, _word  # noqa: F401
from mpa.planners.graph.base import (  # noqa: F401
    F_GRID,
    OBJECTIVES,
    SPEED_RANGE,
    SPEED_RATIO,
    TIE_BREAK,
    TIE_BREAK_2,
    TIED_ROUTES,
    Coords,
    FaceKey,
    Key,
    Piece,
    Segment,
    Side,
)
from mpa.planners.graph.mesh import _Mesh, _mesh  # noqa: F401
from mpa.planners.graph.query import _fits_float, _pair, _speeds, plan_graph  # noqa: F401
from mpa.planners.graph.reasons import _path_like, _why_no_motion  # noqa: F401
from mpa.planners.graph.result import GraphPlan
from mpa.planners.graph.search import AnyAngleSearch, _uncovered  # noqa: F401
from mpa.planners.graph.shortcut import _fastest_alone, _independent_motion, _shortest_routes, _straight_motion  # noqa: F401

__all__ = ["OBJECTIVES", "GraphPlan", "plan_graph"]
