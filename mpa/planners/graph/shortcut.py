"""The independent motion: both robots drive their fastest routes at once, checked exactly, before any search."""

from __future__ import annotations

import bisect
import itertools
import math
from collections.abc import Iterator
from typing import Any

from mpa.graph_track import Position
from mpa.planners.graph.base import TIED_ROUTES, Piece
from mpa.planners.graph.mesh import _Mesh


def _shortest_routes(mesh: _Mesh, pos: Position, goal: Position, tol: float, limit: int) -> list[list[Piece]]:
    """Up to ``limit`` of a robot's shortest routes from ``pos`` to ``goal`` on the graph, as moves along edges.

    Every route returned is within ``tol`` metres of the graph distance. The routes are the first ``ceil(limit/2)``
    of a depth-first walk over the edges of shortest paths taking the vertex's edges in their order at the vertex,
    then the first of the same walk in the reverse order (duplicates dropped): a deterministic choice. A robot
    already at its goal gets one standing piece. An empty list when the goal cannot be reached.
    """
    g = mesh.g
    dv = g._dv

    def ends(p: Position, leaving: bool) -> list[tuple[int, float, list[Piece]]]:
        """(vertex, distance, the move between p and the vertex) for each way between p and the vertices."""
        e, s = p
        le = g._L[e]
        if s == 0.0:
            return [(g._t[e], 0.0, [])]
        if s == le:
            return [(g._h[e], 0.0, [])]
        if leaving:
            return [(g._t[e], s, [(e, s, 0.0)]), (g._h[e], le - s, [(e, s, le)])]
        return [(g._t[e], s, [(e, 0.0, s)]), (g._h[e], le - s, [(e, le, s)])]

    options: list[tuple[float, int, int, list[Piece], list[Piece]]] = []
    (e0, s0), (e1, s1) = pos, goal
    if e0 == e1 and 0.0 < s0 < g._L[e0] and 0.0 < s1 < g._L[e0]:
        options.append((abs(s1 - s0), -1, -1, [(e0, s0, s1)] if s0 != s1 else [], []))
    for a, ca, pa in ends(pos, True):
        for b, cb, pb in ends(goal, False):
            d = ca + dv[a][b] + cb
            if math.isfinite(d):
                options.append((d, a, b, pa, pb))
    if not options:
        return []
    options.sort(key=lambda o: o[0])
    best = options[0][0]
    options = [o for o in options if o[0] - best <= tol]

    def walks(a: int, b: int, forward: bool, want: int) -> list[list[Piece]]:
        """Up to ``want`` routes from vertex ``a`` to ``b`` along edges of shortest paths (depth first, no
        recursion: a route may cross hundreds of vertices)."""
        out: list[list[Piece]] = []
        path: list[Piece] = []
        on_path = {a}

        def nexts(x: int) -> Iterator[tuple[Piece, int]]:
            inc = mesh.inc[x] if forward else mesh.inc[x][::-1]
            for e, x_off in inc:
                if g._t[e] == g._h[e]:
                    continue
                y = g._h[e] if x_off == 0.0 else g._t[e]
                if g._L[e] + dv[y][b] <= dv[x][b] + tol:
                    yield (e, x_off, g._L[e] - x_off), y

        if a == b:
            return [[]]
        stack = [nexts(a)]
        while stack and len(out) < want:
            for piece, y in stack[-1]:
                if y in on_path:
                    continue
                if y == b:
                    out.append([*path, piece])
                    break
                path.append(piece)
                on_path.add(y)
                stack.append(nexts(y))
                break
            else:
                stack.pop()
                if path:
                    e, x_off, _ = path.pop()
                    on_path.discard(g._h[e] if x_off == 0.0 else g._t[e])
        return out

    routes: list[list[Piece]] = []
    for forward, want in ((True, (limit + 1) // 2), (False, limit)):
        for _, a, b, pa, pb in options:
            if len(routes) >= want:
                break
            middles: list[list[Piece]] = [[]] if a < 0 else walks(a, b, forward, want - len(routes))
            for mid in middles:
                r = [*pa, *mid, *pb] or [(e0, s0, s0)]
                if r not in routes:
                    routes.append(r)
                if len(routes) >= want:
                    break
    return routes


def _fastest_alone(mesh: _Mesh, pos: Position, goal: Position, tol: float) -> list[Piece] | None:
    """A robot's unique shortest route from ``pos`` to ``goal`` on the graph, as moves along edges (metres).

    Returns None when another route is within ``tol`` metres of the shortest one. A robot already at its goal gets
    one standing piece.
    """
    routes = _shortest_routes(mesh, pos, goal, tol, 2)
    return routes[0] if len(routes) == 1 else None


def _independent_motion(
    mesh: _Mesh, start: tuple[Position, Position], goal: tuple[Position, Position]
) -> list[list[Any]] | None:
    """The two robots' individually fastest motions, both starting at once, as straight segments in cells.

    Each robot follows one of its shortest routes at its own pace: a straight line in route coordinates from
    ``(0, 0)`` to ``(dA, dB)``, cut where either robot changes edge. Its cost is the search's bound at the start
    (``max(dA/vA, dB/vB)`` plus the tie-break terms, resp. ``hypot(dA, dB)``), which no motion undercuts; so when it
    keeps the clearance it is an optimal answer, and when both shortest routes are unique (no other route within
    ``1e-9 · max(1, longest edge)`` metres) it is the only motion of that cost, the search's answer. With equally
    short routes (a lattice's ties) up to :data:`TIED_ROUTES` of each robot's are tried, pairs in the order of
    :func:`_shortest_routes` (A's first route with each of B's, then A's second, ...), and the first pair that keeps
    the clearance is the answer. Returns the segments ``[polygon, (s, t) from, (s, t) to]`` (offsets in metres), or
    None when no pair tried keeps the clearance (a segment leaves the free polygons or the robots come closer than
    the clearance on a segment: exact minimum per cell, :meth:`~mpa.geometry.GraphGeometry.segment_min_scalar`).
    """
    tol = 1e-9 * mesh.scale
    routes_a = _shortest_routes(mesh, start[0], goal[0], tol, max(2, TIED_ROUTES))
    routes_b = _shortest_routes(mesh, start[1], goal[1], tol, max(2, TIED_ROUTES))
    if TIED_ROUTES <= 1 and (len(routes_a) > 1 or len(routes_b) > 1):
        return None
    for ra in routes_a:
        for rb in routes_b:
            segs = _straight_motion(mesh, ra, rb)
            if segs is not None:
                return segs
    return None


def _straight_motion(mesh: _Mesh, ra: list[Piece], rb: list[Piece]) -> list[list[Any]] | None:
    """The straight line in route coordinates along routes ``ra`` and ``rb`` as segments in cells, None when it
    leaves the free polygons or brings the robots closer than the clearance (see :func:`_independent_motion`)."""
    cum_a = [0.0]
    for _, x0, x1 in ra:
        cum_a.append(cum_a[-1] + abs(x1 - x0))
    cum_b = [0.0]
    for _, x0, x1 in rb:
        cum_b.append(cum_b[-1] + abs(x1 - x0))
    da, db = cum_a[-1], cum_b[-1]
    if da <= 0.0 and db <= 0.0:
        return None
    lams = {0.0, 1.0}
    if da > 0.0:
        lams.update(c / da for c in cum_a[1:-1])
    if db > 0.0:
        lams.update(c / db for c in cum_b[1:-1])
    cuts = sorted(x for x in lams if 0.0 <= x <= 1.0)

    def at(route: list[Piece], cum: list[float], total: float, lam0: float, lam1: float) -> tuple[int, float, float]:
        """The robot's edge and its offsets at ``lam0`` and ``lam1`` (both within one piece)."""
        if total <= 0.0:
            e, x, _ = route[0]
            return e, x, x
        mid = 0.5 * (lam0 + lam1) * total
        i = min(max(bisect.bisect_right(cum, mid) - 1, 0), len(route) - 1)
        e, x0, x1 = route[i]
        length = cum[i + 1] - cum[i]

        def off(lam: float) -> float:
            r = lam * total - cum[i]
            if length <= 0.0 or r <= 0.0:
                return x0
            if r >= length:
                return x1
            return x0 + (x1 - x0) * (r / length)

        return e, off(lam0), off(lam1)

    segs: list[list[Any]] = []
    index = mesh.fs._index
    for lam0, lam1 in itertools.pairwise(cuts):
        if lam1 <= lam0:
            continue
        ea, sa0, sa1 = at(ra, cum_a, da, lam0, lam1)
        eb, sb0, sb1 = at(rb, cum_b, db, lam0, lam1)
        pid = (ea, eb, 0 if ea != eb or sa0 + sa1 > sb0 + sb1 else 1)
        if pid not in index:
            return None
        if (sa0, sb0) != (sa1, sb1):
            if mesh.g.segment_min_scalar(ea, eb, sa0, sb0, sa1, sb1) < mesh.fs._dmin:
                return None  # the robots come closer than the clearance: they must negotiate
            segs.append([pid, (sa0, sb0), (sa1, sb1)])
    return segs or None
