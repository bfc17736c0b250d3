"""What the layout planners' searches share: the query they answer (:class:`SearchQuery`), the objective's cost of a
straight move, each robot's graph distance to its goal (the searches' lower bounds are built from it), and the robots'
speeds on each edge under speed limits.

Used by the exact any-angle search (:mod:`mpa.planners.graph.search`), the search under lane rules
(:mod:`mpa.planners.rules`) and the search with footprints (:mod:`mpa.planar.search`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from mpa.freespace import FreeSpace
    from mpa.geometry import GraphGeometry
    from mpa.graph_track import GraphTrack, Position

#: The ``"fastest"`` cost's first tie-break: ``1e-6`` of the summed time ``tA + tB`` (s) towards the less travel.
TIE_BREAK = 1e-6

#: The second tie-break: ``1e-9`` of the Euclidean time ``hypot(tA, tB)`` (s): one timing among equally fast ones.
TIE_BREAK_2 = 1e-9


@dataclass(frozen=True, slots=True)
class SearchQuery:
    """One checked query of the layout planners, built once by the entry points (:func:`mpa.planners.graph.plan_graph`,
    :func:`mpa.planar.plan_planar`) and passed to the searches and to the plan's assembly.

    Parameters
    ----------
    track : GraphTrack
        The layout (its one-way edges and speed limits are the lane rules).
    free_space : FreeSpace
        The free space of the robots on the track at the query's clearance (in the planar model: the one without the
        bodies, :attr:`mpa.planar.PlanarFreeSpace.base`); its clearances are the plan's.
    start, goal : (Position, Position)
        Robot A's and robot B's positions ``(edge, offset in metres)``, free.
    objective : {"fastest", "shortest"}
    speeds : (float, float)
        The robots' speed limits ``(vA, vB)`` (m/s, > 0).
    """

    track: GraphTrack
    free_space: FreeSpace
    start: tuple[Position, Position]
    goal: tuple[Position, Position]
    objective: str
    speeds: tuple[float, float]

    @property
    def va(self) -> float:
        """Robot A's speed limit (m/s)."""
        return self.speeds[0]

    @property
    def vb(self) -> float:
        """Robot B's speed limit (m/s)."""
        return self.speeds[1]


def move_cost(objective: str, ds: Any, dt: Any, va: Any, vb: Any) -> Any:
    """The cost of straight moves by ``ds``, ``dt`` metres (>= 0; scalars or arrays of one shape).

    Parameters
    ----------
    objective : {"fastest", "shortest"}
    ds, dt : float or ndarray
        Robot A's and robot B's travel (m), >= 0.
    va, vb : float or ndarray
        Their speeds (m/s), > 0 (the ``"shortest"`` cost ignores them).

    Returns
    -------
    float or ndarray
        ``"shortest"``: the length ``hypot(ds, dt)`` (m); ``"fastest"``: the time ``max(tA, tB)`` (s) with the
        tie-breaks ``TIE_BREAK * (tA + tB) + TIE_BREAK_2 * hypot(tA, tB)``, ``tA = ds / va``, ``tB = dt / vb``.
    """
    if objective == "shortest":
        return np.hypot(ds, dt) if isinstance(ds, np.ndarray) else math.hypot(ds, dt)
    ta, tb = ds / va, dt / vb
    if isinstance(ta, np.ndarray):
        return np.maximum(ta, tb) + TIE_BREAK * (ta + tb) + TIE_BREAK_2 * np.hypot(ta, tb)
    return max(ta, tb) + TIE_BREAK * (ta + tb) + TIE_BREAK_2 * math.hypot(ta, tb)


def cost_function(objective: str, va: float, vb: float) -> Callable[[float, float], float]:
    """The scalar :func:`move_cost` at fixed speeds as one fast function ``cost(ds, dt)`` of signed travels (m).

    Parameters
    ----------
    objective : {"fastest", "shortest"}
    va, vb : float
        The robots' speeds (m/s), > 0.

    Returns
    -------
    callable
        ``cost(ds, dt)``: :func:`move_cost` of ``|ds|``, ``|dt|`` (seconds or metres).
    """
    if objective == "shortest":
        return math.hypot

    def cost(ds: float, dt: float) -> float:
        ta, tb = abs(ds) / va, abs(dt) / vb
        return max(ta, tb) + TIE_BREAK * (ta + tb) + TIE_BREAK_2 * math.hypot(ta, tb)

    return cost


def cell_speeds(tr: GraphTrack, va: float, vb: float) -> tuple[list[float], list[float]]:
    """Per edge the speed (m/s) of robot A and of robot B on it: their limits ``va``, ``vb`` capped by the edge's
    speed limit (none: uncapped); two lists of length ``E``."""
    lim = [math.inf if v is None else float(v) for v in tr.speed_limits]
    return [min(va, x) for x in lim], [min(vb, x) for x in lim]


class GoalDistance:
    """One robot's graph distance (m) to its goal position, in closed form per edge.

    Off the goal's edge a position ``(e, y)`` is ``min(y + cp[e], cm[e] - y)`` from the goal (through the edge's tail
    or head); on it also ``|y - offset|`` straight along the edge; a vertex ``w`` is ``vd[w]`` from it.

    Parameters
    ----------
    g : GraphGeometry
        The layout's exact geometry (vertex distances ``dv``, shape ``(V, V)``).
    goal : Position
        ``(edge, offset in metres)``.
    """

    __slots__ = ("cm", "cp", "edge", "offset", "vd")

    def __init__(self, g: GraphGeometry, goal: Position) -> None:
        ge, gs = goal
        lg = g._L[ge]
        dv = g.dv
        tg, hg = g._t[ge], g._h[ge]
        self.edge, self.offset = ge, gs
        self.cp: list[float] = np.minimum(dv[g.tails, tg] + gs, dv[g.tails, hg] + lg - gs).tolist()
        self.cm: list[float] = (g.lengths + np.minimum(dv[g.heads, tg] + gs, dv[g.heads, hg] + lg - gs)).tolist()
        self.vd: list[float] = np.minimum(dv[:, tg] + gs, dv[:, hg] + lg - gs).tolist()

    def at(self, e: int, y: float) -> float:
        """The distance (m) from the position ``(e, y)`` to the goal."""
        d = min(y + self.cp[e], self.cm[e] - y)
        return min(d, abs(y - self.offset)) if e == self.edge else d

    def min_along(self, e: int, y0: float, y1: float, r: float) -> float:
        """``min over y in [y0, y1] of |y - r| + d((e, y), goal)`` (m): the least way from ``r`` to the goal through
        a point of ``[y0, y1]`` on edge ``e``.

        Off the goal's edge ``d = min(y + cp, cm - y)``, and ``min |y - r| + y = r + 2 max(0, y0 - r)``,
        ``min |y - r| - y = -r + 2 max(0, r - y1)``; on it ``|y - r| + |y - offset|`` is convex and least between
        ``r`` and the offset, so the clamp of ``r`` to ``[y0, y1]`` is a minimiser.
        """
        v = min(self.cp[e] + r + 2.0 * max(0.0, y0 - r), self.cm[e] - r + 2.0 * max(0.0, r - y1))
        if e == self.edge:
            y = min(max(r, y0), y1)
            v = min(v, abs(y - r) + abs(y - self.offset))
        return v
