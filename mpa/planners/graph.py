"""A complete planner for two robots on any graph track: shortest or fastest paths in the exact free space.

Entry point :func:`plan_graph` (also :func:`mpa.plan` with ``planner="graph"`` or on a graph track). An any-angle
A* over roots (face ends, corners) and intervals of faces in the free polygons of :mod:`mpa.freespace`, complete
and optimal for the objective; each robot's independent fastest motion is tried first, and the corners of a
searched ``fastest`` plan are re-solved by :mod:`mpa.planners.corners`. The search, its costs and tie-breaks, why
it is optimal and what is guaranteed: docs/graphs.md, "The search in detail".
"""

from __future__ import annotations

import bisect
import heapq
import itertools
import math
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from mpa.errors import InvalidInputError, NoMotionError, PlanningError
from mpa.footprint import footprints
from mpa.freespace import FreeSpace, PolygonId, check_size, free_space
from mpa.geometry import DirectedRoute
from mpa.graph_track import GraphTrack, Position, as_graph_track
from mpa.plans import sample_parameter

__all__ = ["OBJECTIVES", "GraphPlan", "plan_graph"]

FloatArray = NDArray[np.float64]
OBJECTIVES = ("fastest", "shortest")
TIE_BREAK = 1e-6
#: Supported speeds (m/s) of the graph planner, and their largest ratio.
SPEED_RANGE = (1e-6, 1e6)
SPEED_RATIO = 1e8
TIE_BREAK_2 = 1e-9  # then towards the straightest (Euclidean in time units): one timing among equally fast ones
F_GRID = 1e-12  # relative resolution of the search's order (see _search)
Key = tuple[Any, ...]
Coords = tuple[float, float]


@dataclass(frozen=True, eq=False)
class GraphPlan:
    """A collision-free motion of two robots on a graph track (frozen; plain numpy arrays).

    A :class:`mpa.plans.MotionPlan` (``layout`` is :attr:`track`, ``layout_start``/``layout_goal`` are
    :attr:`start`/:attr:`goal`, ``layout_routes`` is ``(route_a, route_b)``, ``route_waypoints`` is
    :attr:`waypoints`, ``domain`` is None).

    Attributes
    ----------
    track : GraphTrack
    start, goal : tuple of two (edge index, offset)
        Robot A first (metres from the edge's tail).
    clearance : float
        D asked for (metres); ``clearance_used`` is what the free space was built with (D = 0: a tiny D > 0).
    objective : str
        ``"fastest"`` or ``"shortest"``.
    speeds : tuple of float
        ``(vA, vB)`` in m/s for the makespan estimate and ``"fastest"``.
    segment_cells : tuple of PolygonId, length K - 1
        Free polygon ``(e, f, k)`` holding each straight segment.
    segment_offsets : ndarray, shape (K - 1, 2, 2)
        Segment ends in the cell's offsets: ``[i, 0] = (s, t)`` at its start, ``[i, 1]`` at its end (metres).
    waypoints : ndarray, shape (K, 2)
        Corners in route coordinates ``(r_A, r_B)`` (metres travelled along each robot's route).
    route_a, route_b : DirectedRoute
        The robots' routes (edges, directions ±1, entry offsets, route-coordinate breakpoints).
    word : tuple of str
        The cells the path crosses (``"eA×eB"``), consecutive repeats merged and immediate returns ``x y x -> x``
        cancelled: a label of the path's class (not a complete homotopy invariant).
    makespan : float
        Estimate (seconds): ``sum of max(|Δs|/vA, |Δt|/vB)`` over the segments (speed limits only).
    length : float
        Euclidean length in the plane of offsets (metres).
    lower_bound : float or None
        On a track with lane rules (:mod:`mpa.planners.rules`): a lower bound of the optimum under them, the optimum
        of the query without the rules (seconds for ``"fastest"``, metres for ``"shortest"``) and, for
        ``"fastest"``, at least each robot's least time alone under the rules; None otherwise.
    """

    track: GraphTrack
    start: tuple[Position, Position]
    goal: tuple[Position, Position]
    clearance: float
    clearance_used: float
    objective: str
    speeds: tuple[float, float]
    segment_cells: tuple[PolygonId, ...]
    segment_offsets: FloatArray
    waypoints: FloatArray
    route_a: DirectedRoute
    route_b: DirectedRoute
    word: tuple[str, ...]
    makespan: float
    length: float
    _times: FloatArray = field(repr=False, default_factory=lambda: np.zeros(1))
    lower_bound: float | None = None

    @property
    def n_corners(self) -> int:
        """K, the number of corners."""
        return len(self.waypoints)

    @property
    def corner_offsets(self) -> FloatArray:
        """Corners in cell offsets, shape (K, 2): segment starts, then the last segment's end (metres)."""
        if len(self.segment_offsets) == 0:
            return np.array([[self.start[0][1], self.start[1][1]]])
        return np.vstack([self.segment_offsets[:, 0], self.segment_offsets[-1:, 1]])

    @property
    def corner_cells(self) -> tuple[PolygonId, ...]:
        """Cell of each corner (the cell of the segment leaving it; the last corner: of the segment entering it)."""
        if not self.segment_cells:
            (ea, sa), (eb, sb) = self.start
            return ((ea, eb, 0 if ea != eb or sa > sb else 1),)
        return (*self.segment_cells, self.segment_cells[-1])

    def path_s(self, u: Any) -> FloatArray:
        """Route coordinates at path parameter ``u ∈ [0, 1]`` (proportional to the time estimate). Shape (..., 2)."""
        u = np.clip(np.asarray(u, dtype=float), 0.0, 1.0)
        w = self.waypoints
        if len(w) == 1 or self._times[-1] <= 0:
            return np.broadcast_to(w[0], (*u.shape, 2)).copy()
        tau = u * self._times[-1]
        return np.stack([np.interp(tau, self._times, w[:, 0]), np.interp(tau, self._times, w[:, 1])], axis=-1)

    def positions(self, u: Any) -> tuple[tuple[NDArray[np.int64], FloatArray], tuple[NDArray[np.int64], FloatArray]]:
        """Per robot ``(edge index, offset)`` arrays at path parameter ``u``."""
        r = self.path_s(u)
        return self.route_a.positions(r[..., 0]), self.route_b.positions(r[..., 1])

    def sample_s(self, n: int) -> tuple[FloatArray, FloatArray]:
        """``n >= 2`` values of ``u`` evenly in [0, 1] and :meth:`path_s` there: shapes (n,) and (n, 2)."""
        u = sample_parameter(n)
        return u, self.path_s(u)

    def sample(self, n: int) -> tuple[FloatArray, FloatArray]:
        """The same as :meth:`sample_s` (``(u, route coordinates)``; the class's own name)."""
        return self.sample_s(n)

    def min_distance(self) -> float:
        """Exact minimum graph distance between the robots along the whole path (metres)."""
        return self.track.geometry.route_min_distance(self.route_a, self.route_b, self.waypoints)

    # ------------------------------------------------------------------ the MotionPlan interface
    @property
    def layout(self) -> GraphTrack:
        """The track (:attr:`track`)."""
        return self.track

    @property
    def layout_start(self) -> tuple[Position, Position]:
        """:attr:`start`."""
        return self.start

    @property
    def layout_goal(self) -> tuple[Position, Position]:
        """:attr:`goal`."""
        return self.goal

    @property
    def layout_routes(self) -> tuple[DirectedRoute, DirectedRoute]:
        """``(route_a, route_b)``."""
        return self.route_a, self.route_b

    @property
    def route_waypoints(self) -> FloatArray:
        """Corners in route coordinates, shape (K, 2) (metres): :attr:`waypoints`."""
        return self.waypoints

    @property
    def domain(self) -> None:
        """None: the graph planner has no domains of continuity."""
        return None

    def to_dict(self) -> dict[str, Any]:
        """JSON-friendly summary (positions by canonical name, routes by edge name)."""
        tr = self.track
        names = list(tr.edge_names)
        return {
            "track": "graph",
            "start": [tr.position_name(*p) for p in self.start],
            "goal": [tr.position_name(*p) for p in self.goal],
            "clearance": self.clearance,
            "clearance_used": self.clearance_used,
            "objective": self.objective,
            "speeds": list(self.speeds),
            "makespan": self.makespan,
            "length": self.length,
            "word": list(self.word),
            "waypoints": self.waypoints.tolist(),
            "segments": [
                {"cell": [names[c[0]], names[c[1]], c[2]], "from": o[0].tolist(), "to": o[1].tolist()}
                for c, o in zip(self.segment_cells, self.segment_offsets)
            ],
            "routes": {"a": self.route_a.to_list(names), "b": self.route_b.to_list(names)},
            **({} if self.lower_bound is None else {"lower_bound": self.lower_bound}),
        }


# ------------------------------------------------------------------------------------------------ search
FaceKey = tuple[int, int, int]  # (axis fixed: 0 = robot A on a vertex, 1 = robot B on a vertex), vertex, other edge
Side = tuple[int, float, FaceKey, float, float]  # (axis, side value, face, lo, hi)


class _Mesh:
    """What the search needs of one free space, built lazily and kept with it: per polygon its sides that are faces,
    per face its *pages* (the polygons glued along it, each with its side value), per face end the polygons holding it.
    """

    def __init__(self, fs: FreeSpace) -> None:
        self.fs = fs
        g = fs.geometry
        self.g = g
        self.inc: list[list[tuple[int, float]]] = [[] for _ in range(g.n_vertices)]
        for e in range(g.n_edges):
            self.inc[g._t[e]].append((e, 0.0))
            self.inc[g._h[e]].append((e, g._L[e]))
        self.lo = fs.faces.lo.tolist()
        self.hi = fs.faces.hi.tolist()
        self.ok = fs.faces.ok.tolist()
        self.scale = max(1.0, float(g.lengths.max()))
        self.eps = 1e-12 * self.scale
        self._sides: dict[PolygonId, list[Side]] = {}
        self._pages: dict[FaceKey, list[tuple[PolygonId, float]]] = {}
        self._members: dict[Key, list[tuple[PolygonId, Coords]]] = {}

    def sides(self, pid: PolygonId) -> list[Side]:
        out = self._sides.get(pid)
        if out is None:
            e, f, k = pid
            out = []
            for s, w in self.fs._sides_a(e, f, k):
                if self.ok[w][f]:
                    out.append((0, s, (0, w, f), self.lo[w][f], self.hi[w][f]))
            for t, w in self.fs._sides_b(e, f, k):
                if self.ok[w][e]:
                    out.append((1, t, (1, w, e), self.lo[w][e], self.hi[w][e]))
            self._sides[pid] = out
        return out

    def pages(self, face: FaceKey) -> list[tuple[PolygonId, float]]:
        out = self._pages.get(face)
        if out is None:
            ax, w, other = face
            index = self.fs._index
            out = []
            for e2, x in self.inc[w]:
                if ax == 0:
                    pid = (e2, other, 0 if e2 != other else (1 if x == 0.0 else 0))
                else:
                    pid = (other, e2, 0 if e2 != other else (0 if x == 0.0 else 1))
                if pid in index:
                    out.append((pid, x))
            self._pages[face] = out
        return out

    def point_key(self, face: FaceKey, y: float) -> Key:
        """Canonical name of the point at coordinate ``y`` along a face (a corner when ``y`` is an end of the edge)."""
        ax, w, other = face
        g = self.g
        if y == 0.0:
            w2 = g._t[other]
        elif y == g._L[other]:
            w2 = g._h[other]
        else:
            return ("F", ax, w, other, y)
        return ("C", w, w2) if ax == 0 else ("C", w2, w)

    def members(self, key: Key) -> list[tuple[PolygonId, Coords]]:
        """The polygons holding a face end or corner, with its coordinates in each."""
        out = self._members.get(key)
        if out is not None:
            return out
        out = []
        if key[0] == "F":
            _, ax, w, other, y = key
            for pid, x in self.pages((ax, w, other)):
                out.append((pid, (x, y) if ax == 0 else (y, x)))
        else:
            _, w, w2 = key
            index = self.fs._index
            for e, s in self.inc[w]:
                for f, t in self.inc[w2]:
                    if e == f and s == t:
                        continue
                    pid = (e, f, 0 if e != f or s > t else 1)
                    if pid in index:
                        out.append((pid, (s, t)))
        self._members[key] = out
        return out

    def names(self, pos: Position) -> list[tuple[int, float]]:
        """All (edge, offset) names of a position (several at a vertex)."""
        e, s = pos
        if s == 0.0:
            return list(self.inc[self.g._t[e]])
        if s == self.g._L[e]:
            return list(self.inc[self.g._h[e]])
        return [pos]

    def placements(self, pa: Position, pb: Position) -> list[tuple[PolygonId, Coords]]:
        out = []
        for ea, sa in self.names(pa):
            for eb, sb in self.names(pb):
                pid = self.fs.polygon_of((ea, sa), (eb, sb))
                if pid is not None:
                    out.append((pid, (sa, sb)))
        return out


def _mesh(fs: FreeSpace) -> _Mesh:
    m = getattr(fs, "_plan_mesh", None)
    if m is None:
        m = _Mesh(fs)
        fs._plan_mesh = m  # type: ignore[attr-defined]
    return cast("_Mesh", m)


# ------------------------------------------------------------------------------------- independent motion
Piece = tuple[int, float, float]  # (edge, offset from, offset to): one robot's move along one edge


#: Per robot, at most this many of its equally short routes are tried by :func:`_independent_motion` (half of them
#: in the order of the edges' numbers, half in the reverse order: on a lattice the two extremes, e.g. "along the
#: aisle first" and "across first"); 1: only a robot's unique shortest route (the benchmark's comparison).
TIED_ROUTES = 4


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


def _uncovered(
    seen: dict[Key, list[tuple[float, float]]], key: Key, y0: float, y1: float, eps: float
) -> list[tuple[float, float]]:
    """The parts of ``[y0, y1]`` not yet covered by the intervals recorded under ``key``; records the union."""
    have = seen.get(key)
    if have is None:
        seen[key] = [(y0, y1)]
        return [(y0, y1)]
    out = []
    cur = y0
    for z0, z1 in have:
        if z1 < cur:
            continue
        if z0 > y1:
            break
        if z0 > cur + eps:
            out.append((cur, z0))
        cur = max(cur, z1)
    if cur < y1 - eps:
        out.append((cur, y1))
    if out:
        merged: list[tuple[float, float]] = []
        for z0, z1 in sorted([*have, (y0, y1)]):
            if merged and z0 <= merged[-1][1]:
                merged[-1] = (merged[-1][0], max(merged[-1][1], z1))
            else:
                merged.append((z0, z1))
        seen[key] = merged
    return out


def _goal_terms(g: Any, goal: Position) -> tuple[list[float], list[float], list[float]]:
    """Per edge ``(cp, cm)`` with ``d((e, x), goal) = min(x + cp[e], cm[e] - x)`` off the goal's edge; per vertex its
    distance to the goal."""
    ge, gs = goal
    lg = g._L[ge]
    dv = g.dv
    tg, hg = g._t[ge], g._h[ge]
    cp = np.minimum(dv[g.tails, tg] + gs, dv[g.tails, hg] + lg - gs)
    cm = g.lengths + np.minimum(dv[g.heads, tg] + gs, dv[g.heads, hg] + lg - gs)
    vd = np.minimum(dv[:, tg] + gs, dv[:, hg] + lg - gs)
    return cp.tolist(), cm.tolist(), vd.tolist()


def _search(
    mesh: _Mesh,
    start: tuple[Position, Position],
    goal: tuple[Position, Position],
    objective: str,
    va: float,
    vb: float,
    budget: int | None = None,
) -> list[list[Any]] | None:
    """Exact shortest path (for the objective's cost) in the free space: an any-angle A* over *roots* (start, face
    ends and corners, where a taut path can bend) and *intervals* (the part of a face seen straight from a root
    through the faces crossed so far, unfolded across faces). With ``budget``: None after that many expansions."""
    g = mesh.g
    eps = mesh.eps
    ctol = 1e-12 * mesh.scale * mesh.scale
    if objective == "shortest":

        def cost(ds: float, dt: float) -> float:
            return math.hypot(ds, dt)

        def comb(xa: float, xb: float) -> float:
            return math.hypot(xa, xb)

    else:

        def cost(ds: float, dt: float) -> float:
            ta, tb_ = abs(ds) / va, abs(dt) / vb
            return max(ta, tb_) + TIE_BREAK * (ta + tb_) + TIE_BREAK_2 * math.hypot(ta, tb_)

        def comb(xa: float, xb: float) -> float:
            ta, tb_ = xa / va, xb / vb
            return max(ta, tb_) + TIE_BREAK * (ta + tb_) + TIE_BREAK_2 * math.hypot(ta, tb_)

    (gea, gsa), (geb, gsb) = goal
    cpa, cma, vda = _goal_terms(g, goal[0])
    cpb, cmb, vdb = _goal_terms(g, goal[1])

    def dist_a(e: int, y: float) -> float:
        d = min(y + cpa[e], cma[e] - y)
        return min(d, abs(y - gsa)) if e == gea else d

    def dist_b(e: int, y: float) -> float:
        d = min(y + cpb[e], cmb[e] - y)
        return min(d, abs(y - gsb)) if e == geb else d

    def min_along(e: int, y0: float, y1: float, r: float, robot: int) -> float:
        """``min over y in [y0, y1] of |y - r| + d_robot((e, y), goal)``: ``d = min(y + cp, cm - y)`` off the goal's
        edge, and ``min |y - r| + y = r + 2 max(0, y0 - r)``, ``min |y - r| - y = -r + 2 max(0, r - y1)``."""
        if robot == 0:
            cp, cm, ge, gs = cpa[e], cma[e], gea, gsa
        else:
            cp, cm, ge, gs = cpb[e], cmb[e], geb, gsb
        v = min(cp + r + 2.0 * max(0.0, y0 - r), cm - r + 2.0 * max(0.0, r - y1))
        if e == ge:  # |y - r| + |y - gs| is convex, least between r and gs: the clamp of r is a minimiser
            y = min(max(r, y0), y1)
            v = min(v, abs(y - r) + abs(y - gs))
        return v

    def queue_key(f: float, depth: float, nid: int) -> tuple[int, float, int]:
        """The search's order, in one place: the bound ``f`` on a grid of ``F_GRID`` of the start's bound (so that
        near-equal bounds count as ties), then deeper first (larger cost from the start of the root, ``depth``): on
        the plateaus of equally fast motions (a robot with slack may take any of many routes) the search dives to the
        goal instead of widening; the plan is optimal up to that grid."""
        return (math.floor(f * fq), -depth, nid)

    goal_at: dict[PolygonId, list[Coords]] = {}
    for pid, c in mesh.placements(*goal):
        goal_at.setdefault(pid, []).append(c)

    # node records
    #   point:    [0, key, g, seg]             seg = (kind, ...) the straight run that ends here
    #   interval: [1, root id, root key, g_root, r, sig, ax, a, y0, y1, pid, prev pid, prev a, lo, hi, parent, origin]
    #   face entry (queued, opens the intervals into its pages):
    #             [3, root id, root key, g_root, r, sig, ax, a, y0, y1, prev pid, face, lo, hi, parent, origin]
    #   goal:     [2, None, g, seg]
    nodes: list[list[Any]] = []
    # interval nodes by (root, page, side, root position in the page's frame): routes of equal lengths (a lattice's
    # Manhattan ties) unfold to the same node; keep one
    seen: dict[Key, list[tuple[float, float]]] = {}
    quantum = 1.0 / (1e-9 * mesh.scale)
    best: dict[Key, float] = {}
    heap: list[tuple[int, float, int]] = []

    def push_point(key: Key, gval: float, pid: PolygonId, pt: Coords, seg: tuple[Any, ...]) -> None:
        if gval < best.get(key, math.inf):
            best[key] = gval
            nodes.append([0, key, gval, seg])
            f = gval + comb(dist_a(pid[0], pt[0]), dist_b(pid[1], pt[1]))
            heapq.heappush(heap, queue_key(f, gval, len(nodes) - 1))

    def push_goal(gval: float, seg: tuple[Any, ...]) -> None:
        if gval < best.get(("G",), math.inf):
            best[("G",)] = gval
            nodes.append([2, ("G",), gval, seg])
            heapq.heappush(heap, queue_key(gval, gval, len(nodes) - 1))

    def push_intervals(
        rid: int,
        rkey: Key,
        groot: float,
        r: Coords,
        sig: Coords,
        pid: PolygonId,
        ax: int,
        a: float,
        face: FaceKey,
        y0: float,
        y1: float,
        lo: float,
        hi: float,
        parent: int,
        origin: tuple[PolygonId, Coords],
    ) -> None:
        """Queue the part [y0, y1] of face ``face`` (side ``ax = a`` of ``pid``) seen from the root, once for all the
        face's other pages: the bound is the same for each (the robot on the vertex is as far from its goal, and the
        other robot's edge is the face's), so the pages are opened only when the entry is taken from the queue."""
        w = face[1]
        if ax == 0:
            xa = abs(r[0] - a) + vda[w]
            xb = min_along(face[2], y0, y1, r[1], 1)
        else:
            xb = abs(r[1] - a) + vdb[w]
            xa = min_along(face[2], y0, y1, r[0], 0)
        nodes.append([3, rid, rkey, groot, r, sig, ax, a, y0, y1, pid, face, lo, hi, parent, origin])
        heapq.heappush(heap, queue_key(groot + comb(xa, xb), groot, len(nodes) - 1))

    def open_face(nd: list[Any]) -> None:
        """Interval nodes of a queued face entry into each other page (unfolding the root), expanded at once."""
        _, rid, rkey, groot, r, sig, ax, a, y0, y1, pid, face, lo, hi, parent, origin = nd
        n1 = 1.0 if a == 0.0 else -1.0
        for pid2, b in mesh.pages(face):
            if pid2 == pid and b == a:
                continue
            if len(mesh.sides(pid2)) == 1 and pid2 not in goal_at:
                continue  # a dead end: a straight line entering it cannot leave
            sg = n1 if b == 0.0 else -n1  # -n1 * n2
            sg = -sg
            if ax == 0:
                r2 = (b + sg * (r[0] - a), r[1])
                sig2 = (sg * sig[0], sig[1])
            else:
                r2 = (r[0], b + sg * (r[1] - a))
                sig2 = (sig[0], sg * sig[1])
            sk = (rid, pid2, ax, b, round(r2[0] * quantum), round(r2[1] * quantum))
            for z0, z1 in _uncovered(seen, sk, y0, y1, eps):  # parts not seen the same way from this root before
                nodes.append([1, rid, rkey, groot, r2, sig2, ax, b, z0, z1, pid2, pid, a, lo, hi, parent, origin])
                expand_interval(len(nodes) - 1, nodes[-1])

    def expand_point(nid: int, key: Key, gval: float, members: list[tuple[PolygonId, Coords]]) -> None:
        for q, rc in members:
            for pt in goal_at.get(q, ()):
                push_goal(gval + cost(pt[0] - rc[0], pt[1] - rc[1]), ("direct", nid, q, rc, pt))
            for ax2, a2, face2, lo2, hi2 in mesh.sides(q):
                on_line = rc[ax2] == a2
                for y in (lo2, hi2) if hi2 > lo2 else (lo2,):
                    pt = (a2, y) if ax2 == 0 else (y, a2)
                    if pt == rc:
                        continue
                    k2 = mesh.point_key(face2, y)
                    push_point(k2, gval + cost(pt[0] - rc[0], pt[1] - rc[1]), q, pt, ("direct", nid, q, rc, pt))
                if on_line or hi2 - lo2 <= eps:
                    continue
                push_intervals(nid, key, gval, rc, (1.0, 1.0), q, ax2, a2, face2, lo2, hi2, lo2, hi2, nid, (q, rc))

    def expand_interval(nid: int, nd: list[Any]) -> None:
        _, rid, rkey, groot, r, sig, ax, a, y0, y1, pid, _, _, _, _, _, origin = nd
        rs, rt = r
        if ax == 0:
            u0 = (a - rs, y0 - rt)
            u1 = (a - rs, y1 - rt)
        else:
            u0 = (y0 - rs, a - rt)
            u1 = (y1 - rs, a - rt)
        cr = u0[0] * u1[1] - u0[1] * u1[0]
        if abs(cr) <= ctol:
            return
        sgn = 1.0 if cr > 0 else -1.0

        def inside(q: Coords) -> bool:
            dx, dy = q[0] - rs, q[1] - rt
            c0 = sgn * (u0[0] * dy - u0[1] * dx)
            c1 = -sgn * (u1[0] * dy - u1[1] * dx)
            return c0 >= -ctol and c1 >= -ctol

        for pt in goal_at.get(pid, ()):
            if inside(pt):
                push_goal(groot + cost(pt[0] - rs, pt[1] - rt), ("chain", rid, nid, pid, pt))
        for ax2, a2, face2, lo2, hi2 in mesh.sides(pid):
            if ax2 == ax and a2 == a:
                continue
            if (r[ax2] - a2 if a2 == 0.0 else a2 - r[ax2]) <= eps:
                continue  # a straight line leaves through this side only if its root lies on the side's inner side
            yl, yh = lo2, hi2
            # conditions c(y) = A*y + B >= -ctol for both cone edges
            for u, sg in ((u0, sgn), (u1, -sgn)):
                if ax2 == 0:  # q = (a2, y): cross(u, q - r) = u_s (y - rt) - u_t (a2 - rs)
                    ca, cb = u[0], -u[0] * rt - u[1] * (a2 - rs)
                else:  # q = (y, a2): u_s (a2 - rt) - u_t (y - rs)
                    ca, cb = -u[1], u[0] * (a2 - rt) + u[1] * rs
                ca, cb = sg * ca, sg * cb
                if ca > 0.0:
                    yl = max(yl, (-ctol - cb) / ca)
                elif ca < 0.0:
                    yh = min(yh, (-ctol - cb) / ca)
                elif cb < -ctol:
                    yl, yh = 1.0, 0.0
            if yl > yh + eps:
                continue
            if yl <= lo2 + eps:
                yl = lo2
                pt = (a2, lo2) if ax2 == 0 else (lo2, a2)
                k2 = mesh.point_key(face2, lo2)
                push_point(k2, groot + cost(pt[0] - rs, pt[1] - rt), pid, pt, ("chain", rid, nid, pid, pt))
            if yh >= hi2 - eps:
                yh = hi2
                pt = (a2, hi2) if ax2 == 0 else (hi2, a2)
                k2 = mesh.point_key(face2, hi2)
                push_point(k2, groot + cost(pt[0] - rs, pt[1] - rt), pid, pt, ("chain", rid, nid, pid, pt))
            if yh - yl <= eps:
                continue
            push_intervals(rid, rkey, groot, r, sig, pid, ax2, a2, face2, yl, yh, lo2, hi2, nid, origin)

    # the queue's order: f on a grid of F_GRID of the start's bound (so that near-equal bounds count as ties), then
    # deeper first (larger g): on the plateaus of equally fast motions (a robot with slack may take any of many
    # routes) the search dives to the goal instead of widening; the plan is optimal up to that grid
    (sa_e, sa_s), (sb_e, sb_s) = start
    fq = 1.0 / (F_GRID * max(1e-3, comb(dist_a(sa_e, sa_s), dist_b(sb_e, sb_s))))
    start_members = mesh.placements(*start)
    best[("S",)] = 0.0
    nodes.append([0, ("S",), 0.0, None])
    expand_point(0, ("S",), 0.0, start_members)
    found = -1
    expanded = 0
    while heap:
        _, _, nid = heapq.heappop(heap)
        expanded += 1
        if budget is not None and expanded > budget:
            return None
        nd = nodes[nid]
        kind = nd[0]
        if kind == 2:
            found = nid
            break
        if kind == 0:
            key = nd[1]
            if nd[2] > best[key]:
                continue  # reached more cheaply since (a root reached again more cheaply is expanded again)
            expand_point(nid, key, nd[2], mesh.members(key))
        else:
            if nd[3] > best[nd[2]]:
                continue  # its root was reached more cheaply since
            open_face(nd)
    if found < 0:
        raise PlanningError("search ended without reaching the goal although it is in the start's component (a bug)")
    return _unwind(mesh, nodes, found, start_members)


def _unwind(mesh: _Mesh, nodes: list[list[Any]], nid: int, start_members: Any) -> list[list[Any]]:
    """The path's straight segments ``[polygon, from, to]`` (offsets in the polygon's cell), start to goal."""
    runs: list[list[list[Any]]] = []
    while nid != 0:
        seg = nodes[nid][3]
        if seg[0] == "direct":
            _, rid, q, rc, pt = seg
            runs.append([[q, rc, pt]])
            nid = rid
            continue
        _, rid, last, pid, q = seg
        chain = []
        i = last
        while i != rid:
            chain.append(nodes[i])
            i = nodes[i][15]
        chain.reverse()
        q0, r0 = chain[0][16]
        rk, sk = chain[-1][4], chain[-1][5]
        d0 = (sk[0] * (q[0] - rk[0]), sk[1] * (q[1] - rk[1]))
        segs: list[list[Any]] = []
        prev_pid, prev_pt = q0, r0
        for nd in chain:
            r, sig, ax, a, pid_i, prev_a, lo, hi = nd[4], nd[5], nd[6], nd[7], nd[10], nd[12], nd[13], nd[14]
            di = (sig[0] * d0[0], sig[1] * d0[1])
            if di[ax] != 0.0:
                lam = (a - r[ax]) / di[ax]
                y = r[1 - ax] + lam * di[1 - ax]
            else:  # pragma: no cover - a crossing line is never parallel to its face
                y = r[1 - ax]
            y = min(max(y, lo), hi)
            exit_pt = (prev_a, y) if ax == 0 else (y, prev_a)
            entry = (a, y) if ax == 0 else (y, a)
            segs.append([prev_pid, prev_pt, exit_pt])
            prev_pid, prev_pt = pid_i, entry
        segs.append([prev_pid, prev_pt, q])
        runs.append(segs)
        nid = rid
    out: list[list[Any]] = []
    for run in reversed(runs):
        out.extend(run)
    if not out:
        pid, c = start_members[0]
        out.append([pid, c, c])
    return out


def _merge_same_polygon(segs: list[list[Any]]) -> list[list[Any]]:
    """Join consecutive segments inside one convex polygon into one straight segment (never longer, still free)."""
    out: list[list[Any]] = []
    for x in segs:
        if out and out[-1][0] == x[0] and out[-1][2] == x[1]:
            out[-1] = [x[0], out[-1][1], x[2]]
            if out[-1][1] == out[-1][2]:
                out.pop()
        else:
            out.append(list(x))
    return out


def _route(moves: list[tuple[int, float, float]], start: Position) -> tuple[DirectedRoute, list[float]]:
    """A robot's route from its per-segment moves ``(edge, from, to)``; also the route coordinate at each corner."""
    edges: list[int] = []
    dirs: list[int] = []
    entry: list[float] = []
    lengths: list[float] = []
    exit_off: float | None = None
    at = [0.0]
    for e, a, b in moves:
        ds = b - a
        if ds != 0.0:
            d = 1 if ds > 0 else -1
            if edges and edges[-1] == e and dirs[-1] == d and exit_off == a:
                lengths[-1] += abs(ds)
            else:
                edges.append(e)
                dirs.append(d)
                entry.append(a)
                lengths.append(abs(ds))
            exit_off = b
        at.append(at[-1] + abs(ds))
    if not edges:
        return DirectedRoute.standing(*start), at
    breaks = np.concatenate([[0.0], np.cumsum(lengths)])
    return DirectedRoute(np.array(edges), np.array(dirs), np.array(entry), breaks), at


def _word(track: GraphTrack, cells: list[PolygonId]) -> tuple[str, ...]:
    names = track.edge_names
    out: list[str] = []
    for e, f, k in cells:
        label = f"{names[e]}×{names[f]}" + (f"/{k}" if e == f else "")
        if out and out[-1] == label:
            continue
        if len(out) >= 2 and out[-2] == label:
            out.pop()
            continue
        out.append(label)
    return tuple(out)


# ------------------------------------------------------------------------------------------ diagnosis
def _path_like(track: GraphTrack) -> bool:
    _, b1 = track.graph.betti()
    degrees = [track.degree(v) for v in range(track.graph.n_vertices)]
    return b1 == 0 and max(degrees) <= 2


def _why_no_motion(track: GraphTrack, fs: FreeSpace, start: tuple[Position, ...], goal: tuple[Position, ...]) -> str:
    g = track.geometry
    for robot, s, t in (("A", start[0], goal[0]), ("B", start[1], goal[1])):
        if not math.isfinite(g.distance_scalar(s[0], s[1], t[0], t[1])):
            return f"robot {robot}'s goal is on another part of the track, not connected to its start"
    names = f"{track.position_name(*start[0])}, {track.position_name(*start[1])}"
    gnames = f"{track.position_name(*goal[0])}, {track.position_name(*goal[1])}"
    if _path_like(track):
        return (
            f"the robots' order cannot change on a path-like layout (no vertex of degree >= 3 and no cycle): "
            f"start ({names}) and goal ({gnames}) have them in different orders"
        )
    tiny = FreeSpace(track, 0.0)
    if tiny.component_of(*start) != tiny.component_of(*goal):
        return (
            f"start ({names}) and goal ({gnames}) are in different components of the free space, even for a "
            "vanishing clearance"
        )
    lo, hi = 0.0, fs.clearance
    iters = 30 if track.n_edges <= 40 else 10
    for _ in range(iters):
        mid = 0.5 * (lo + hi)
        trial = FreeSpace(track, mid)
        ca, cb = trial.component_of(*start), trial.component_of(*goal)
        if ca is not None and ca == cb:
            lo = mid
        else:
            hi = mid
    _, b1 = track.graph.betti()
    branch = sum(track.degree(v) >= 3 for v in range(track.graph.n_vertices))
    where = "the layout"
    if b1 == 1 and branch <= 1:
        where = "the only loop"
    elif b1 == 0 and branch == 1:
        where = "the only siding"
    digits = next((k for k in range(6, 18) if f"{lo:.{k}g}" != f"{fs.clearance:.{k}g}"), 17)
    return (
        f"the clearance {fs.clearance!r} m does not fit {where}: start ({names}) and goal ({gnames}) are in "
        f"different components of the free space; they are connected only for clearances up to about "
        f"{lo:.{digits}g} m"
    )


# ------------------------------------------------------------------------------------------------- API
def _fits_float(x: int) -> bool:
    try:
        float(x)
    except OverflowError:
        return False
    return True


def _speeds(speeds: object) -> tuple[float, float]:
    try:
        va, vb = cast("tuple[object, object]", speeds)
    except (TypeError, ValueError, OverflowError):
        raise InvalidInputError(f"speeds is {speeds!r}, expected two positive numbers (vA, vB) in m/s") from None
    out = []
    for name, v in (("speed of robot A", va), ("speed of robot B", vb)):
        if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
            raise InvalidInputError(f"{name} is {v!r}, expected a positive number (m/s)")
        if isinstance(v, int) and not _fits_float(v):
            raise InvalidInputError(
                f"{name} is an integer of {len(str(abs(v)))} digits, expected a finite number > 0 (m/s)"
            )
        if not math.isfinite(float(v)) or float(v) <= 0:
            raise InvalidInputError(f"{name} is {v!r}, expected a finite number > 0 (m/s)")
        if not SPEED_RANGE[0] <= float(v) <= SPEED_RANGE[1]:
            raise InvalidInputError(
                f"{name} is {v!r}, expected a number in [{SPEED_RANGE[0]:g}, {SPEED_RANGE[1]:g}] m/s (the planner "
                "works in times Δs/v, which overflow or lose all precision outside it)"
            )
        out.append(float(v))
    if max(out) / min(out) > SPEED_RATIO:
        raise InvalidInputError(
            f"speeds are {out[0]!r} and {out[1]!r} m/s, expected a ratio of at most {SPEED_RATIO:g} (the slower "
            "robot's times would swamp the faster one's)"
        )
    return out[0], out[1]


def _pair(track: GraphTrack, value: object, what: str) -> tuple[Position, Position]:
    if isinstance(value, str) or not isinstance(value, (tuple, list)) or len(value) != 2:
        raise InvalidInputError(f"{what} is {value!r}, expected two positions (robot A, robot B)")
    return (
        track.position(value[0], f"{what} of robot A"),
        track.position(value[1], f"{what} of robot B"),
    )


def plan_graph(
    track: object,
    start: object,
    goal: object,
    clearance: float = 0.0,
    objective: str = "fastest",
    speeds: object = (1.0, 1.0),
    footprint: object = None,
) -> GraphPlan:
    """Plan a collision-free motion of two robots on a graph track (complete: finds one whenever one exists).

    Parameters
    ----------
    track : GraphTrack, paper track, layout dict or path to a JSON layout
    start, goal : pair of positions
        ``(robot A, robot B)``; a position is ``(edge, offset)``, ``"EDGE:OFFSET"`` or a vertex name.
    clearance : float
        D (metres, >= 0): the graph distance between the robots stays >= D (D = 0: a tiny positive clearance, see
        :mod:`mpa.freespace`).
    objective : {"fastest", "shortest"}
        Minimum time for the speed limits (weighted L∞), or minimum Euclidean length in offsets.
    speeds : (float, float)
        Speed limits ``(vA, vB)`` (m/s, > 0).
    footprint : None, mpa.Disc, mpa.Rectangle, pair or spec string
        The robots' bodies in the plane (:mod:`mpa.footprint`); the motion then also keeps the bodies apart in the
        layout's drawing (:mod:`mpa.planar`: complete in that model; the path bends only at the free pieces' shared
        points, so it is not the optimum of ``objective``). Needs vertex coordinates.

    Returns
    -------
    GraphPlan

    Raises
    ------
    InvalidInputError
        Bad track, position, clearance, objective or speeds; robots closer than D at start or goal.
    NoMotionError
        Start and goal are in different path components of the free space; the message says why (different
        components, order on a path-like layout, clearance too large for the only siding or loop, the one-way
        lanes). On a track with one-way edges or speed limits the planner of :mod:`mpa.planners.rules` answers
        (complete under the one-way rule; time exact at the edges' speed limits).

    Examples
    --------
    >>> t = GraphTrack.from_layout({"edges": [["J", "a", 1.0], ["J", "b", 2.0], ["J", "c", 2.0]]})
    >>> p = plan_graph(t, ("b", "c"), ("c", "b"), clearance=0.5)
    >>> round(p.min_distance(), 6) >= 0.5
    True
    """
    tr = as_graph_track(track)
    check_size(tr)  # before the distances and the free space are built
    if objective not in OBJECTIVES:
        raise InvalidInputError(f"objective is {objective!r}, expected one of {list(OBJECTIVES)}")
    va, vb = _speeds(speeds)
    s = _pair(tr, start, "start")
    gl = _pair(tr, goal, "goal")
    fs = free_space(tr, clearance)
    geo = tr.geometry
    for what, (pa, pb) in (("start", s), ("goal", gl)):
        if not fs.is_free(pa, pb):
            d = geo.distance_scalar(pa[0], pa[1], pb[0], pb[1])
            raise InvalidInputError(
                f"{what} has the robots {d:.12g} m apart, expected at least the clearance {fs.clearance_used:.12g} m"
            )
    fps = footprints(footprint)
    if fps is not None:
        from mpa.planar.plan import plan_planar

        return cast("GraphPlan", plan_planar(tr, s, gl, clearance, objective, (va, vb), fps))
    ca, cb = fs.component_of(*s), fs.component_of(*gl)
    if ca is None or ca != cb:
        raise NoMotionError(_why_no_motion(tr, fs, s, gl))
    if tr.has_rules:  # one-way edges or speed limits: the planner of mpa.planners.rules
        from mpa.planners.rules import plan_with_rules

        return cast("GraphPlan", plan_with_rules(tr, fs, s, gl, objective, (va, vb)))
    mesh = _mesh(fs)
    quick = _independent_motion(mesh, s, gl)
    if quick is not None:
        return _assemble(tr, fs, s, gl, objective, (va, vb), quick)
    segs = _search(mesh, s, gl, objective, va, vb)
    if segs is None:  # pragma: no cover - no budget given
        raise PlanningError("search gave up")
    segs = _merge_same_polygon([x for x in segs if x[1] != x[2]])
    if objective == "fastest":  # one motion among the equally fast ones of the chain, continuous in the query
        from mpa.planners.corners import resolve_corners

        segs = [x for x in resolve_corners(fs, segs, (va, vb)) if x[1] != x[2]]
    return _assemble(tr, fs, s, gl, objective, (va, vb), segs)


def _assemble(
    tr: GraphTrack,
    fs: FreeSpace,
    start: tuple[Position, Position],
    goal: tuple[Position, Position],
    objective: str,
    speeds: tuple[float, float],
    segs: list[list[Any]],
) -> GraphPlan:
    va, vb = speeds
    cells = [tuple(x[0]) for x in segs]
    offs = np.array([[x[1], x[2]] for x in segs], dtype=float).reshape(-1, 2, 2)
    route_a, at_a = _route([(c[0], o[0, 0], o[1, 0]) for c, o in zip(cells, offs)], start[0])
    route_b, at_b = _route([(c[1], o[0, 1], o[1, 1]) for c, o in zip(cells, offs)], start[1])
    waypoints = np.stack([at_a, at_b], axis=1)
    d = np.abs(offs[:, 1] - offs[:, 0]) if len(offs) else np.zeros((0, 2))
    seg_t = np.maximum(d[:, 0] / va, d[:, 1] / vb)
    times = np.concatenate([[0.0], np.cumsum(seg_t)])
    return GraphPlan(
        track=tr,
        start=start,
        goal=goal,
        clearance=fs.clearance,
        clearance_used=fs.clearance_used,
        objective=objective,
        speeds=speeds,
        segment_cells=tuple(cells),
        segment_offsets=offs,
        waypoints=waypoints,
        route_a=route_a,
        route_b=route_b,
        word=_word(tr, cells),
        makespan=float(times[-1]),
        length=float(np.hypot(d[:, 0], d[:, 1]).sum()),
        _times=times,
    )
