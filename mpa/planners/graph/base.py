"""The graph planner's constants and the small types its modules share (keys, coordinates, faces, route pieces)."""

from __future__ import annotations

from typing import Any

from mpa.planners.search_common import TIE_BREAK as TIE_BREAK
from mpa.planners.search_common import TIE_BREAK_2 as TIE_BREAK_2

OBJECTIVES = ("fastest", "shortest")


#: Supported speeds (m/s) of the graph planner, and their largest ratio.
SPEED_RANGE = (1e-6, 1e6)


SPEED_RATIO = 1e8


F_GRID = 1e-12  # relative resolution of the search's order (see AnyAngleSearch.queue_key)


Key = tuple[Any, ...]


Coords = tuple[float, float]


#: A straight segment of a path: ``[polygon, from, to]``, the cell's polygon and the ends' offsets in it (m).
Segment = list[Any]


# ------------------------------------------------------------------------------------------------ search
FaceKey = tuple[int, int, int]  # (axis fixed: 0 = robot A on a vertex, 1 = robot B on a vertex), vertex, other edge


Side = tuple[int, float, FaceKey, float, float]  # (axis, side value, face, lo, hi)


# ------------------------------------------------------------------------------------- independent motion
Piece = tuple[int, float, float]  # (edge, offset from, offset to): one robot's move along one edge


#: Per robot, at most this many of its equally short routes are tried by :func:`_independent_motion` (half of them
#: in the order of the edges' numbers, half in the reverse order: on a lattice the two extremes, e.g. "along the
#: aisle first" and "across first"); 1: only a robot's unique shortest route (the benchmark's comparison).
TIED_ROUTES = 4
