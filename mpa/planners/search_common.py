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


#: The least cost through a face (:func:`least_through_face`) is scaled by ``1 - FACE_SAFETY``: its minimiser is
#: computed in floating point, and the bound must not exceed a motion's cost by rounding (the searches order their
#: queues on a grid of ``1e-12`` of the start's bound).
FACE_SAFETY = 1e-13


def _through_face(
    ax: int, x_seg: float, x_rest: float, r: float, y: float, cp: float, cm: float, on_edge: bool, off: float,
    fastest: bool, va: float, vb: float,
) -> float:  # fmt: skip
    """The cost of the straight move from a root to the point ``y`` of a face plus the cost of the robots' graph
    distances from there to their goals (:func:`least_through_face`'s arguments)."""
    q1 = abs(y - r)
    x, d = y + cp, cm - y
    q2 = d if d < x else x
    if on_edge:
        x = abs(y - off)
        q2 = x if x < q2 else q2
    if ax == 0:
        a1, b1, a2, b2 = x_seg, q1, x_rest, q2
    else:
        a1, b1, a2, b2 = q1, x_seg, q2, x_rest
    if fastest:
        ta, tb = a1 / va, b1 / vb
        c = (tb if tb > ta else ta) + TIE_BREAK * (ta + tb) + TIE_BREAK_2 * math.hypot(ta, tb)
        ta, tb = a2 / va, b2 / vb
        return c + ((tb if tb > ta else ta) + TIE_BREAK * (ta + tb) + TIE_BREAK_2 * math.hypot(ta, tb))
    return math.hypot(a1, b1) + math.hypot(a2, b2)


def least_through_face(
    ax: int, x_seg: float, x_rest: float, r: float, y0: float, y1: float, cp: float, cm: float, on_edge: bool,
    off: float, fastest: bool, va: float, vb: float,
) -> float:  # fmt: skip
    """A lower bound of the cost to the goal of a motion that goes straight from a root through a part of a face:
    the least over ``y`` in ``[y0, y1]`` of the straight move's cost to the face's point ``y`` plus the cost of the
    robots' graph distances from there to their goals (the bound of the any-angle search's face entries).

    One robot (robot A when ``ax`` is 0) reaches the face's vertex after ``x_seg`` metres and is then ``x_rest``
    from its goal; the other goes straight from ``r`` to ``y`` on the face's edge, and is then ``min(y + cp, cm - y)``
    from its goal (also ``|y - off|`` when the edge holds its goal, ``on_edge``; :class:`GoalDistance`'s terms).

    **Exact.** The edge robot's distance to its goal is the least of affine pieces (``y + cp``, ``cm - y``) or, on
    its goal's edge, also ``|y - off|``; the cost is the least over the pieces of the cost with that piece, ``F_j``,
    and ``F_j`` evaluated where the piece is not the least is above the cost there, so the least of the cost is the
    least of the ``F_j``'s minima, found by evaluating the cost itself at their minimisers. Between its convex kinks
    (``y = r``; ``y = off``; where one of the two ``max`` terms starts to count, ``"fastest"``) the piecewise-linear
    part of ``F_j`` (the ``max`` terms and the ``TIE_BREAK`` sum) is affine and its ``hypot`` terms are convex, so
    ``F_j`` is convex there. Its least is at an end of such a stretch unless the affine part is flat: its slope is
    otherwise at least ``2 TIE_BREAK / v`` per metre in size, the ``hypot`` terms' at most ``2 TIE_BREAK_2 / v``.
    Where it is flat, the edge robot's two travels have opposite slopes and sum to a constant ``Q``, and the
    ``hypot`` terms are least where the two robots' travels are in proportion: the first part's ``Q x_seg / (x_seg +
    x_rest)``. The value is the least of the cost at ``y0``, ``y1`` and those points inside; the ``"shortest"``
    cost (``hypot`` only) is the same case without the ``max`` terms. It is at least the search's former bound, the
    cost of the two robots' whole ways (``max`` and ``hypot`` are subadditive), and often far above it: a line on
    which the robot with the longer way lags is charged for the time it loses.

    Parameters
    ----------
    ax : {0, 1}
        0: robot A is on the face's vertex, robot B on its edge; 1: the other way round.
    x_seg, x_rest : float
        The vertex robot's straight travel to the vertex, and its graph distance from there to its goal (m).
    r : float
        The edge robot's coordinate on the edge (unfolded; may lie outside it) at the root (m).
    y0, y1 : float
        The part of the face (m, ``y0 <= y1``).
    cp, cm, on_edge, off : float, float, bool, float
        The edge robot's distance to its goal on this edge (:class:`GoalDistance`: ``cp[e]``, ``cm[e]``, whether
        ``e`` is its goal's edge, the goal's offset).
    fastest : bool
        The ``"fastest"`` cost (s; ``va``, ``vb`` the speeds, m/s), else ``"shortest"`` (m).

    Returns
    -------
    float
        The least, scaled by ``1 - FACE_SAFETY``.
    """
    best = _through_face(ax, x_seg, x_rest, r, y0, cp, cm, on_edge, off, fastest, va, vb)
    if y1 > y0:
        v = _through_face(ax, x_seg, x_rest, r, y1, cp, cm, on_edge, off, fastest, va, vb)
        if v < best:
            best = v
        s = x_seg + x_rest
        k = x_seg / s if s > 0.0 else 0.0
        cands = [r, r + (cm - r) * k, r - (cp + r) * k]
        p = q = 0.0
        if fastest:
            vv, ve = (va, vb) if ax == 0 else (vb, va)
            p, q = x_seg / vv * ve, x_rest / vv * ve
            cands += [r - p, r + p, q - cp, cm - q]
        if on_edge:
            cands += [off, r + (off - r) * k]
            if fastest:
                cands += [off - q, off + q]
        for y in cands:
            if y0 < y < y1:
                v = _through_face(ax, x_seg, x_rest, r, y, cp, cm, on_edge, off, fastest, va, vb)
                if v < best:
                    best = v
    return best * (1.0 - FACE_SAFETY)


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
