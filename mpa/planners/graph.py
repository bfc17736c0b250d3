"""A complete planner for two robots on any graph track: shortest or fastest paths in the exact free space.

Entry point :func:`plan_graph` (also :func:`mpa.plan` with ``planner="graph"`` or on a graph track).

**Search.** The free space ``{d >= D}`` is a union of convex polygons glued along faces (:mod:`mpa.freespace`).
The planner runs A* on a visibility graph whose nodes are the polygons' corners, the two ends of every shared face
and :data:`FACE_POINTS` evenly spaced points inside it, plus start and goal. Inside one convex polygon every pair of
its points is visible, so each polygon contributes all pairs of its nodes, and each straight segment inside one
polygon is free. Polygons sharing a face share its nodes, so the graph is connected exactly where the free space is:
the search finds a path whenever one exists (**complete**), and :func:`plan_graph` raises
:class:`~mpa.errors.NoMotionError` otherwise, naming the reason.

**Costs.** A straight move ``(Δs, Δt)`` costs ``hypot(Δs, Δt)`` (metres) for ``"shortest"`` and
``max(|Δs|/vA, |Δt|/vB)`` (seconds, a weighted L∞ length) for ``"fastest"``, ties broken towards the Euclidean
shortest (``+ 1e-6 · hypot / max(v)``). A*'s heuristic ``hypot(dA, dB)`` resp. ``max(dA/vA, dB/vB)`` (graph
distances of each robot to its goal) is consistent.

**Straightening.** The search's path bends at face nodes; the polygon sequence it found is then pulled taut: each
face crossing slides along its face to the closed-form optimum given its neighbours (Gauss–Seidel, on the length
``hypot(Δs/vA, Δt/vB)`` — speeds scaled for ``"fastest"``, so that the taut path is also of least weighted-L∞
time in its corridor — smoothed with ``ε → 0`` so that it does not stall on zero-length pieces). Where the path
passes a corner (both robots on vertices, both changing edges) the robots may instead pass their vertices one after
the other (both orders tried). Consecutive segments in one polygon are merged.

**What is and is not guaranteed.** Completeness and the clearance (exact, up to the membership tolerance
``1e-12 · max(1, total length)`` of :mod:`mpa.freespace`) are guaranteed. Optimality is not proven: the corridor is
chosen by the discretized search and then straightened. Checked: on seeded random layouts the ``"fastest"`` time is
never above the best 8-neighbour grid path's (0.05 m grid) and ``"shortest"`` never longer; on lollipops it is never
slower than the paper planner's plan.

**Routes.** Each robot's route is a sequence of directed edges (a new piece at every edge change and every
reversal); its route coordinate is the distance travelled, and the plan is a polyline in route coordinates
(straight on each segment).
"""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass, field
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from mpa.errors import InvalidInputError, NoMotionError, PlanningError
from mpa.freespace import FreeSpace, PolygonId, free_space
from mpa.geometry import DirectedRoute
from mpa.graph_track import GraphTrack, Position, as_graph_track

__all__ = ["OBJECTIVES", "GraphPlan", "plan_graph"]

FloatArray = NDArray[np.float64]
OBJECTIVES = ("fastest", "shortest")
TIE_BREAK = 1e-6
FACE_POINTS = 3  # interior nodes per face (besides its two ends), so that the search sees crossings inside faces
Key = tuple[Any, ...]
Coords = tuple[float, float]


@dataclass(frozen=True, eq=False)
class GraphPlan:
    """A collision-free motion of two robots on a graph track (frozen; plain numpy arrays).

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

    def sample(self, n: int) -> tuple[FloatArray, FloatArray]:
        """``n`` points evenly in ``u``: returns ``(u, route coordinates)`` with shapes (n,) and (n, 2)."""
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 2:
            raise InvalidInputError(f"number of samples is {n!r}, expected an integer >= 2")
        u = np.linspace(0.0, 1.0, int(n))
        return u, self.path_s(u)

    def min_distance(self) -> float:
        """Exact minimum graph distance between the robots along the whole path (metres)."""
        return self.track.geometry.route_min_distance(self.route_a, self.route_b, self.waypoints)

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
        }


# ------------------------------------------------------------------------------------------------ search
class _Search:
    """The visibility graph of one free space, built lazily per polygon."""

    def __init__(self, fs: FreeSpace, face_points: int = FACE_POINTS) -> None:
        self.fs = fs
        self.face_points = face_points
        g = fs.geometry
        self.g = g
        self.inc: list[list[tuple[int, float]]] = [[] for _ in range(g.n_vertices)]
        for e in range(g.n_edges):
            self.inc[g._t[e]].append((e, 0.0))
            self.inc[g._h[e]].append((e, g._L[e]))
        self.lo = fs.faces.lo.tolist()
        self.hi = fs.faces.hi.tolist()
        self.ok = fs.faces.ok.tolist()
        self.side_eps = 1e-12 * max(1.0, float(g.lengths.max()))
        self._nodes: dict[PolygonId, list[tuple[Key, Coords]]] = {}
        self._members: dict[Key, list[tuple[PolygonId, Coords]]] = {}

    def face_value(self, w: int, f: int, j: int) -> float:
        """Offset of face node ``j`` of face (vertex w, edge f): 0 the low end, 1 the high end, 2.. interior."""
        lo, hi = self.lo[w][f], self.hi[w][f]
        if j == 0:
            return lo
        if j == 1:
            return hi
        return lo + (hi - lo) * (j - 1) / (self.face_points + 1)

    def endpoints(self, w: int, f: int) -> list[tuple[int, float]]:
        lo, hi = self.lo[w][f], self.hi[w][f]
        if lo >= hi:
            return [(0, lo)]
        return [(j, self.face_value(w, f, j)) for j in range(self.face_points + 2)]

    def face_key(self, role: str, w: int, other: int, j: int, x: float) -> Key:
        g = self.g
        if x == 0.0:
            w2 = g._t[other]
        elif x == g._L[other]:
            w2 = g._h[other]
        else:
            return (role, w, other, j)
        return ("C", w, w2) if role == "A" else ("C", w2, w)

    def nodes(self, pid: PolygonId) -> list[tuple[Key, Coords]]:
        out = self._nodes.get(pid)
        if out is not None:
            return out
        fs, eps = self.fs, self.side_eps
        e, f, k = pid
        found: dict[tuple[Key, Coords], None] = {}
        a_sides = [(s, w) for s, w in fs._sides_a(e, f, k) if self.ok[w][f]]
        b_sides = [(t, w) for t, w in fs._sides_b(e, f, k) if self.ok[w][e]]
        for s, w in a_sides:
            for j, t in self.endpoints(w, f):
                found[(self.face_key("A", w, f, j, t), (s, t))] = None
        for t, w in b_sides:
            for j, s in self.endpoints(w, e):
                found[(self.face_key("B", w, e, j, s), (s, t))] = None
        for idx, (s, t) in enumerate(fs.vertices(pid).tolist()):
            if any(abs(s - s0) <= eps for s0, _ in a_sides) or any(abs(t - t0) <= eps for t0, _ in b_sides):
                continue
            found[(("P", pid, idx), (s, t))] = None
        out = list(found)
        self._nodes[pid] = out
        return out

    def members(self, key: Key) -> list[tuple[PolygonId, Coords]]:
        out = self._members.get(key)
        if out is not None:
            return out
        index = self.fs._index
        out = []
        kind = key[0]
        if kind == "P":
            pid = key[1]
            out = [(pid, tuple(self.fs.vertices(pid)[key[2]].tolist()))]
        elif kind == "A":
            _, w, f, j = key
            t = self.face_value(w, f, j)
            for e, s in self.inc[w]:
                pid = (e, f, 0 if e != f else (1 if s == 0.0 else 0))
                if pid in index:
                    out.append((pid, (s, t)))
        elif kind == "B":
            _, w, e, j = key
            s = self.face_value(w, e, j)
            for f, t in self.inc[w]:
                pid = (e, f, 0 if e != f else (0 if t == 0.0 else 1))
                if pid in index:
                    out.append((pid, (s, t)))
        elif kind == "C":
            _, w, w2 = key
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


def _cost_fn(objective: str, va: float, vb: float) -> Any:
    if objective == "shortest":
        return lambda ds, dt: math.hypot(ds, dt)
    tb = TIE_BREAK / max(va, vb)
    return lambda ds, dt: max(abs(ds) / va, abs(dt) / vb) + tb * math.hypot(ds, dt)


def _astar(
    srch: _Search, start: tuple[Position, Position], goal: tuple[Position, Position], cost: Any, heur: Any
) -> list[tuple[PolygonId, Coords, Coords]]:
    s_members = srch.placements(*start)
    g_members = srch.placements(*goal)
    goal_at: dict[PolygonId, list[Coords]] = {}
    for pid, c in g_members:
        goal_at.setdefault(pid, []).append(c)
    srch._members[("S",)] = s_members
    geo = srch.g
    (gea, gsa), (geb, gsb) = goal

    hcache: dict[Key, float] = {}

    def h(key: Key, pid: PolygonId, c: Coords) -> float:
        v = hcache.get(key)
        if v is None:
            da = geo.distance_scalar(pid[0], c[0], gea, gsa)
            db = geo.distance_scalar(pid[1], c[1], geb, gsb)
            v = hcache[key] = heur(da, db)
        return v

    best: dict[Key, float] = {("S",): 0.0}
    parent: dict[Key, tuple[Key, PolygonId, Coords, Coords]] = {}
    heap: list[tuple[float, float, int, Key]] = [(0.0, 0.0, 0, ("S",))]
    closed: set[Key] = set()
    counter = 1
    goal_key: Key = ("G",)
    while heap:
        _, gk, _, key = heapq.heappop(heap)
        if key in closed:
            continue
        closed.add(key)
        if key == goal_key:
            break
        for pid, c in srch.members(key):
            targets = list(srch.nodes(pid))
            targets.extend((goal_key, cg) for cg in goal_at.get(pid, ()))
            for k2, c2 in targets:
                if k2 in closed:
                    continue
                ng = gk + cost(c2[0] - c[0], c2[1] - c[1])
                if ng < best.get(k2, math.inf):
                    best[k2] = ng
                    parent[k2] = (key, pid, c, c2)
                    hk = 0.0 if k2 == goal_key else h(k2, pid, c2)
                    heapq.heappush(heap, (ng + hk, ng, counter, k2))
                    counter += 1
    if goal_key not in parent:
        raise PlanningError("search ended without reaching the goal although it is in the start's component (a bug)")
    segs = []
    key = goal_key
    while key != ("S",):
        prev, pid, c, c2 = parent[key]
        segs.append((pid, c, c2))
        key = prev
    return segs[::-1]


def _face_of_crossing(
    srch: _Search, a1: Coords, b0: Coords, p1: PolygonId, p2: PolygonId
) -> tuple[str, int, int] | None:
    """The face a path crosses between polygons ``p1`` and ``p2`` at ``a1`` (in p1) = ``b0`` (in p2), if any."""
    g = srch.g
    w1 = g._t[p1[0]] if a1[0] == 0.0 else g._h[p1[0]] if a1[0] == g._L[p1[0]] else None
    w2 = g._t[p2[0]] if b0[0] == 0.0 else g._h[p2[0]] if b0[0] == g._L[p2[0]] else None
    if w1 is not None and w1 == w2 and p1[1] == p2[1] and a1[1] == b0[1] and srch.ok[w1][p1[1]]:
        return ("A", w1, p1[1])
    v1 = g._t[p1[1]] if a1[1] == 0.0 else g._h[p1[1]] if a1[1] == g._L[p1[1]] else None
    v2 = g._t[p2[1]] if b0[1] == 0.0 else g._h[p2[1]] if b0[1] == g._L[p2[1]] else None
    if v1 is not None and v1 == v2 and p1[0] == p2[0] and a1[0] == b0[0] and srch.ok[v1][p1[0]]:
        return ("B", v1, p1[0])
    return None


def _straighten(
    srch: _Search, segs: list[list[Any]], wa: float, wb: float, eps: float, tol: float, sweeps: int = 400
) -> None:
    """Slide face crossings along their faces (in place) to shorten ``sum sqrt((wa Δs)² + (wb Δt)² + eps²)``.

    Each crossing's optimum given its neighbours is closed-form (the straight line through the face, unfolded),
    clamped to the face's interval; Gauss–Seidel sweeps until no crossing moves more than ``tol``.
    """
    faces = [None] + [
        _face_of_crossing(srch, segs[j - 1][2], segs[j][1], segs[j - 1][0], segs[j][0]) for j in range(1, len(segs))
    ]
    e2 = eps * eps
    for _ in range(sweeps):
        moved = 0.0
        for j in range(1, len(segs)):
            face = faces[j]
            if face is None:
                continue
            role, w, other = face
            lo, hi = srch.lo[w][other], srch.hi[w][other]
            a0, a1 = segs[j - 1][1], segs[j - 1][2]
            b0, b1 = segs[j][1], segs[j][2]
            if role == "A":  # A on the vertex: t varies
                u = math.sqrt((wa * (a1[0] - a0[0])) ** 2 + e2)
                v = math.sqrt((wa * (b1[0] - b0[0])) ** 2 + e2)
                y0, y1, old = a0[1], b1[1], a1[1]
            else:  # B on the vertex: s varies
                u = math.sqrt((wb * (a1[1] - a0[1])) ** 2 + e2)
                v = math.sqrt((wb * (b1[1] - b0[1])) ** 2 + e2)
                y0, y1, old = a0[0], b1[0], a1[0]
            if u + v <= 0.0:
                continue
            x = min(max(y0 + (y1 - y0) * u / (u + v), lo), hi)
            if x == old:
                continue
            moved = max(moved, abs(x - old))
            if role == "A":
                segs[j - 1][2] = (a1[0], x)
                segs[j][1] = (b0[0], x)
            else:
                segs[j - 1][2] = (x, a1[1])
                segs[j][1] = (x, b0[1])
        if moved <= tol:
            break


def _total(segs: list[list[Any]], cost: Any) -> float:
    return sum(cost(b[0] - a[0], b[1] - a[1]) for _, a, b in segs)


def _taut(srch: _Search, segs: list[list[Any]], wa: float, wb: float, scale: float) -> None:
    """Straighten (in place) for the length ``hypot(wa Δs, wb Δt)``, smoothed as ``sqrt(... + ε²)`` with ε -> 0
    so that coordinate descent does not stall where a segment has zero length."""
    for eps in (1e-2 * scale, 1e-4 * scale, 1e-6 * scale, 0.0):
        _straighten(srch, segs, wa, wb, eps, 1e-3 * eps if eps > 0 else 1e-12 * scale)


def _split_corners(srch: _Search, segs: list[list[Any]], wa: float, wb: float, scale: float) -> list[list[Any]]:
    """Where the path passes a corner (both robots on vertices) changing both edges, let the robots pass their
    vertices at different times: insert the middle cell (A's new edge × B's old edge, or the other order) and keep
    the order whose straightened path is cheaper."""
    g, fs = srch.g, srch.fs
    _taut(srch, segs, wa, wb, scale)

    def cost(ds: float, dt: float) -> float:
        return math.hypot(ds * wa, dt * wb)

    j = 1
    while j < len(segs):
        p1, _, a1 = segs[j - 1]
        p2, b0, _ = segs[j]
        at_a = a1[0] in (0.0, g._L[p1[0]]) and b0[0] in (0.0, g._L[p2[0]])
        at_b = a1[1] in (0.0, g._L[p1[1]]) and b0[1] in (0.0, g._L[p2[1]])
        if not (at_a and at_b and p1[0] != p2[0] and p1[1] != p2[1]):
            j += 1
            continue
        best, best_cost = segs, _total(segs, cost)
        inserted = False
        for mid in (((p2[0], b0[0]), (p1[1], a1[1])), ((p1[0], a1[0]), (p2[1], b0[1]))):
            pid = fs.polygon_of(*mid)
            if pid is None:
                continue
            c = (mid[0][1], mid[1][1])
            trial = [list(x) for x in segs[:j]] + [[pid, c, c]] + [list(x) for x in segs[j:]]
            _taut(srch, trial, wa, wb, scale)
            tc = _total(trial, cost)
            if tc < best_cost - 1e-12 * max(1.0, best_cost):
                best, best_cost, inserted = trial, tc, True
        segs = best
        j += 2 if inserted else 1
    return segs


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
    return (
        f"the clearance {fs.clearance:g} m does not fit {where}: start ({names}) and goal ({gnames}) are in "
        f"different components of the free space; they are connected only for clearances up to about {lo:.6g} m"
    )


# ------------------------------------------------------------------------------------------------- API
def _speeds(speeds: object) -> tuple[float, float]:
    try:
        va, vb = cast("tuple[object, object]", speeds)
    except (TypeError, ValueError):
        raise InvalidInputError(f"speeds is {speeds!r}, expected two positive numbers (vA, vB) in m/s") from None
    out = []
    for name, v in (("speed of robot A", va), ("speed of robot B", vb)):
        if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
            raise InvalidInputError(f"{name} is {v!r}, expected a positive number (m/s)")
        if not math.isfinite(float(v)) or float(v) <= 0:
            raise InvalidInputError(f"{name} is {v!r}, expected a finite number > 0 (m/s)")
        out.append(float(v))
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

    Returns
    -------
    GraphPlan

    Raises
    ------
    InvalidInputError
        Bad track, position, clearance, objective or speeds; robots closer than D at start or goal.
    NoMotionError
        Start and goal are in different path components of the free space; the message says why (different
        components, order on a path-like layout, clearance too large for the only siding or loop).

    Examples
    --------
    >>> t = GraphTrack.from_layout({"edges": [["J", "a", 1.0], ["J", "b", 2.0], ["J", "c", 2.0]]})
    >>> p = plan_graph(t, ("b", "c"), ("c", "b"), clearance=0.5)
    >>> round(p.min_distance(), 6) >= 0.5
    True
    """
    tr = as_graph_track(track)
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
    ca, cb = fs.component_of(*s), fs.component_of(*gl)
    if ca is None or ca != cb:
        raise NoMotionError(_why_no_motion(tr, fs, s, gl))
    cost = _cost_fn(objective, va, vb)
    if objective == "shortest":

        def heur(da: float, db: float) -> float:
            return math.hypot(da, db)

    else:
        tb = TIE_BREAK / max(va, vb)

        def heur(da: float, db: float) -> float:
            return max(da / va, db / vb) + tb * math.hypot(da, db)

    srch = _Search(fs)
    segs = [list(x) for x in _astar(srch, s, gl, cost, heur)]
    # Straighten with the Euclidean length in coordinates scaled by the speeds (s/vA, t/vB): strictly convex, so
    # coordinate descent does not stall, and in a corridor its taut path is also shortest for the weighted L∞ time.
    wa, wb = (1.0, 1.0) if objective == "shortest" else (1.0 / va, 1.0 / vb)
    scale = max(1.0, float(tr.lengths.max())) * max(wa, wb)
    segs = _split_corners(srch, segs, wa, wb, scale)
    segs = _merge_same_polygon([x for x in segs if x[1] != x[2]])
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
