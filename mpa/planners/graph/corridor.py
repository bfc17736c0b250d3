"""The goals' order in a corridor: which robot must come in last, and from which end.

A *corridor* is a maximal chain of edges joined at vertices of degree 2 (:func:`corridor_of`); its *ports* are its end
vertices of degree 3 or more (an end of degree 1, a dead end, belongs to the corridor and lets nobody in). Two robots
in a corridor keep their order along it (to pass, they would have to meet). So when both goals lie inside one
corridor, say robot R1's goal nearer the end ``u`` and R2's nearer ``v``, every motion ends with both robots in the
corridor in that order, and the last time one of them comes in, it is R1 through ``u`` or R2 through ``v`` (the other
is inside already; or both were inside from the start in that order and never left: the search's own case, not this
module's). Hence two *classes* of motions, and every motion from a start that does not have both robots inside in the
goals' order is in one of them:

- class ``u``: R1's last entry is through ``u``; from any configuration on such a motion R1 still travels at least
  ``d(r1, u) + x1`` (``x1``: its goal's distance from ``u`` along the corridor), or, once inside for good, the
  corridor's distance to its goal;
- class ``v``: the same for R2 through ``v``.

:func:`approach_distances` writes each class's lower bound as a :class:`~mpa.planners.search_common.GoalDistance`
(the tables the searches read), so the search of a class is the search of :mod:`mpa.planners.graph.search` with
other goal distances: an A* whose bound is admissible along every motion of its class, so it returns a motion no
dearer than the best of that class (the usual argument: a node of that motion stays queued with a key at most its
cost). The cheaper of the two classes' motions is optimal over all motions. The bound is not consistent (it jumps up
where a robot leaves the corridor by the wrong end); the search expands a root again when it is reached more cheaply.

See docs/graphs.md ("The goals' order in a corridor").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mpa.geometry import GraphGeometry
from mpa.graph_track import Position
from mpa.planners.search_common import GoalDistance


@dataclass(frozen=True)
class Corridor:
    """A maximal chain of edges joined at vertices of degree 2.

    Attributes
    ----------
    edges : tuple of int
        The chain's edges, from the end ``u`` to the end ``v``.
    dirs : tuple of int
        +1 where the edge runs from ``u`` towards ``v`` (tail first), -1 otherwise.
    starts : tuple of float
        Each edge's first point's coordinate along the chain (m, from ``u``).
    length : float
        The chain's length (m).
    u, v : int
        The end vertices (equal for a chain that leaves a vertex and comes back to it).
    u_port, v_port : bool
        Whether the end is a port (degree >= 3; a dead end, degree 1, is not).
    """

    edges: tuple[int, ...]
    dirs: tuple[int, ...]
    starts: tuple[float, ...]
    length: float
    u: int
    v: int
    u_port: bool
    v_port: bool

    def coordinate(self, pos: Position, tol: float) -> float | None:
        """The position's distance from ``u`` along the chain (m), None when it is not inside the corridor: on another
        edge, or on a port (within ``tol`` metres of it)."""
        e, y = pos
        try:
            i = self.edges.index(e)
        except ValueError:
            return None
        x = self.starts[i] + (y if self.dirs[i] > 0 else self._len(i) - y)
        if (self.u_port and x <= tol) or (self.v_port and x >= self.length - tol):
            return None
        return x

    def _len(self, i: int) -> float:
        nxt = self.starts[i + 1] if i + 1 < len(self.starts) else self.length
        return nxt - self.starts[i]


def corridor_of(g: GraphGeometry, edge: int) -> Corridor | None:
    """The corridor holding ``edge``, None when the chain closes into a cycle of degree-2 vertices (a circle: there
    the robots' order is cyclic and no end lets a robot in)."""
    at, deg = g.edges_at
    t, h = g._t, g._h

    def walk(e: int, w: int) -> tuple[list[tuple[int, int]], int] | None:
        # from edge e's end w outwards while w has degree 2: [(edge, +1 if it is left by its tail)], the end vertex
        out: list[tuple[int, int]] = []
        while deg[w] == 2:
            nxt = [(f, 1 if t[f] == w else -1) for f in at[w] if f != e]
            if not nxt:  # e is a loop at w: w's two ends are both e's
                return None
            f, d = nxt[0]
            if f == edge:
                return None
            out.append((f, d))
            e, w = f, (h[f] if d > 0 else t[f])
        return out, w

    fwd = walk(edge, h[edge])
    back = walk(edge, t[edge])
    if fwd is None or back is None:
        return None
    (after, v), (before, u) = fwd, back
    chain = [(f, -d) for f, d in reversed(before)] + [(edge, 1)] + after
    L = g._L
    starts, x = [], 0.0
    for f, _ in chain:
        starts.append(x)
        x += L[f]
    return Corridor(
        tuple(f for f, _ in chain), tuple(d for _, d in chain), tuple(starts), x, int(u), int(v),
        bool(deg[u] >= 3), bool(deg[v] >= 3),
    )  # fmt: skip


def _through(g: GraphGeometry, x: float, end: int, inside: np.ndarray, cx: np.ndarray) -> GoalDistance:
    """The distance of :class:`GoalDistance`'s form to the goal at coordinate ``x`` of ``c`` for a robot whose last
    entry is through the end vertex ``end`` (``x`` and ``cx``, the corridor's vertices' coordinates, measured from that
    end): outside the corridor ``d(., end) + x``; inside it also the corridor's own way, ``|cx - x|``."""
    vd = g.dv[:, end] + x
    vd[inside] = np.minimum(vd[inside], np.abs(cx[inside] - x))
    out = GoalDistance.__new__(GoalDistance)
    out.vd = vd.tolist()
    out.cp = vd[g.tails].tolist()
    out.cm = (g.lengths + vd[g.heads]).tolist()
    return out


def approach_distances(
    g: GraphGeometry, start: tuple[Position, Position], goal: tuple[Position, Position], tol: float
) -> list[tuple[GoalDistance, GoalDistance]] | None:
    """The goal distances of the two classes of motions when both goals lie inside one corridor (module doc): a list
    of one or two pairs ``(robot A's, robot B's)``, each with one robot's distance through its end of the corridor
    and the other's own (:class:`GoalDistance`); None when the goals are not in one corridor, or the start has both
    robots inside it in the goals' order (every motion may then stay inside: the search's own case).

    Parameters
    ----------
    g : GraphGeometry
    start, goal : (Position, Position)
        Robot A's and robot B's positions ``(edge, offset in metres)``.
    tol : float
        Positions within ``tol`` metres of a port are on the port, outside the corridor.
    """
    c = corridor_of(g, goal[0][0])
    if c is None or not (c.u_port or c.v_port):
        return None
    xa, xb = c.coordinate(goal[0], tol), c.coordinate(goal[1], tol)
    if xa is None or xb is None:
        return None
    xg = (xa, xb)
    first = 0 if xa < xb else 1  # R1: the robot whose goal is nearer u
    sa, sb = c.coordinate(start[0], tol), c.coordinate(start[1], tol)
    if sa is not None and sb is not None and ((sa < sb) if first == 0 else (sb < sa)):
        return None
    # the corridor's vertices other than its ports, with their coordinates
    inside = np.zeros(g.n_vertices, dtype=bool)
    cx = np.zeros(g.n_vertices)
    for e, d, s0 in zip(c.edges, c.dirs, c.starts):
        a, b = (g._t[e], g._h[e]) if d > 0 else (g._h[e], g._t[e])
        for w, x in ((a, s0), (b, s0 + g._L[e])):
            if not ((c.u_port and w == c.u) or (c.v_port and w == c.v)):
                inside[w], cx[w] = True, x
    out: list[tuple[GoalDistance, GoalDistance]] = []
    second = 1 - first
    for end, port, robot, x, along in (
        (c.u, c.u_port, first, xg[first], cx),
        (c.v, c.v_port, second, c.length - xg[second], c.length - cx),
    ):
        if not port:
            continue
        gd = _through(g, x, end, inside, along)
        gd.edge, gd.offset = goal[robot]
        own = GoalDistance(g, goal[1 - robot])
        out.append((gd, own) if robot == 0 else (own, gd))
    return out
