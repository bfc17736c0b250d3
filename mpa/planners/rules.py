"""The complete planner on layouts with lane rules: one-way edges and speed limits (used by :func:`plan_graph`).

**Rules.** An edge ``e`` marked one-way may be driven from its tail to its head only: while robot A is on ``e`` its
offset ``s`` never decreases (it may stand still), and likewise robot B's offset ``t``. An edge with a speed limit
``v_e`` caps the speed of a robot on it: robot A moves at most ``min(vA, v_e)``.

**Reachability in one polygon.** In a free polygon of the cell ``e × f`` (convex) the moves allowed from a point
``r`` are the straight moves into the *forward cone* ``C(r) = {q : q_s >= r_s if e is one-way, q_t >= r_t if f is
one-way}`` (a quadrant, a half-plane or the plane): a monotone path between two points of a convex polygon exists
iff the straight one is monotone, and ``q ∈ C(r)`` implies ``C(q) ⊆ C(r)``. On a face (a side where one robot
stands on a vertex) the allowed part ``face ∩ C(r)`` is an interval whose ends are face ends or the projections
``y = r_s`` / ``y = r_t`` of ``r``.

**Search.** A* over points: the start, and on every face reached from a point ``r`` the two ends of
``face ∩ C(r)``; a point's key names it independently of the polygon (a corner, or a face and an offset), and it is
expanded in every polygon holding it. The goal is reached from a point whose polygon holds it and whose cone contains
it. Each coordinate is a face end, the start's, or a coordinate carried over from an earlier point while the same
robot stays on the same edge, so the set of points is finite and the search ends. The bound is each robot's graph
distance to its goal at its top speed (admissible: the rules only forbid and slow down).

**Complete.** Let a motion respecting every one-way edge cross faces ``x1, x2, ...``. By induction the search holds,
on the face of ``x_k``, the lower end ``y_k`` of ``face ∩ C(y_{k-1})``, which contains ``x_k`` (cones only shrink
along a monotone motion): ``y_k`` is no later than ``x_k`` in the one-way coordinate along the face (if any) and
equal in the other, so ``C(y_k) ⊇ C(x_k)`` in every polygon glued along that face. The goal lies in ``C(x_last)``,
hence in ``C(y_last)``: a motion is found whenever one exists.

**Cost.** A straight move ``(Δs, Δt)`` in the cell ``e × f`` takes ``max(|Δs| / min(vA, v_e), |Δt| / min(vB, v_f))``
seconds (``"fastest"``, with the tie-breaks of :mod:`mpa.planners.graph`) or its length (``"shortest"``). The path
found bends only at the points above; it is then improved by sliding each face crossing along its face (coordinate
descent, every rule kept, :func:`_smooth`), and replaced by the exact optimum without the rules (also smoothed) when
that one keeps the one-way rule and costs less. The result is exact in its time at the speed limits but not proven
optimal. Its distance from the optimum is bounded per plan: the plan records as ``lower_bound`` the larger of the
optimum of the same query without the rules (:func:`mpa.planners.graph.plan_graph`'s exact search at the speeds
``(vA, vB)``) and, for ``"fastest"``, each robot's least time alone under the rules (:func:`single_robot_time`:
its own fastest route with the speed limits and one-way lanes); no motion under the rules can beat either.
"""

from __future__ import annotations

import dataclasses
import heapq
import math
from typing import TYPE_CHECKING, Any

import numpy as np

from mpa.errors import NoMotionError, PlanningError
from mpa.freespace import PolygonId
from mpa.graph_track import GraphTrack, Position
from mpa.planners.search_common import GoalDistance, SearchQuery, cell_speeds, move_cost

if TYPE_CHECKING:
    from mpa.planners.graph.mesh import _Mesh
    from mpa.planners.graph.result import GraphPlan

__all__ = ["plan_with_rules", "single_robot_time"]

Coords = tuple[float, float]


def single_robot_time(tr: GraphTrack, start: Position, goal: Position, speed: float) -> float:
    """The least time (s) one robot alone needs from ``start`` to ``goal`` under the track's rules.

    Dijkstra (scipy's) over the vertices, an edge ``e`` costing ``length / min(speed, v_e)`` and usable only from
    ``from`` to ``to`` when one-way; a move along the start's edge straight to the goal counts when both are on it.
    ``inf`` when the one-way lanes leave no way. Both robots of a plan must make their own journeys, so the larger of
    the two times bounds the ``fastest`` makespan from below, speed limits included.

    Parameters
    ----------
    tr : GraphTrack
    start, goal : Position
        ``(edge index, offset in metres)``.
    speed : float
        The robot's speed limit (m/s), > 0.
    """
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import dijkstra

    spd = [min(speed, math.inf if v is None else v) for v in tr.speed_limits]
    tails, heads, lengths = tr.tails, tr.heads, tr.lengths
    n = tr.graph.n_vertices
    # the arcs between the vertices (the faster of parallel ones) and from a source, node n, to the start's ends
    arcs: dict[tuple[int, int], float] = {}

    def arc(u: int, w: int, t: float) -> None:
        if t < arcs.get((u, w), math.inf):
            arcs[(u, w)] = t

    for e in range(tr.n_edges):
        t_e = float(lengths[e]) / spd[e]
        arc(int(tails[e]), int(heads[e]), t_e)
        if not tr.oneway[e]:
            arc(int(heads[e]), int(tails[e]), t_e)

    def ends(pos: Position, leaving: bool) -> list[tuple[int, float]]:
        """(vertex, time) from ``pos`` to its edge's ends (``leaving``) or from the ends to ``pos``."""
        e, x = pos
        head = (int(heads[e]), (float(lengths[e]) - x) / spd[e])
        tail = (int(tails[e]), x / spd[e])
        # against a one-way lane only from or to the vertex the position is at (no motion on the lane)
        if leaving:  # towards the head is forward
            return [head] + ([tail] if not tr.oneway[e] or tail[1] == 0.0 else [])
        return [tail] + ([head] if not tr.oneway[e] or head[1] == 0.0 else [])

    best = math.inf
    (es, xs), (eg, xg) = start, goal
    if es == eg and (not tr.oneway[es] or xg >= xs):
        best = abs(xg - xs) / spd[es]
    for v, t_v in ends(start, True):
        arc(n, v, t_v)
    (rows, cols), times = zip(*arcs.keys()), list(arcs.values())
    graph = csr_matrix((times, (rows, cols)), shape=(n + 1, n + 1))  # explicit zeros stay arcs
    dist = dijkstra(graph, directed=True, indices=n)
    for v, t_v in ends(goal, False):
        best = min(best, float(dist[v]) + t_v)
    return best


def _cost_function(query: SearchQuery) -> Any:
    """``cost(polygon, p, q)`` of the straight move ``p -> q`` in the polygon's cell: :func:`move_cost` at the cell's
    speeds (:func:`cell_speeds`), seconds (``"fastest"``) or metres (``"shortest"``)."""
    spa, spb = cell_speeds(query.track, query.va, query.vb)
    objective = query.objective

    def cost(pid: PolygonId, p: Coords, q: Coords) -> float:
        return float(move_cost(objective, abs(q[0] - p[0]), abs(q[1] - p[1]), spa[pid[0]], spb[pid[1]]))

    return cost


def _search(mesh: _Mesh, query: SearchQuery) -> list[list[Any]] | None:
    """Segments ``[polygon, from, to]`` (cell offsets) of the cheapest path through the candidate points of ``mesh``
    (the query's free space as the search sees it), or None when the goal cannot be reached under the one-way rule."""
    start, goal, objective, (va, vb) = query.start, query.goal, query.objective, query.speeds
    oneway = query.track.oneway
    cost = _cost_function(query)
    to_a, to_b = GoalDistance(mesh.g, goal[0]), GoalDistance(mesh.g, goal[1])

    def bound(pid: PolygonId, p: Coords) -> float:
        """Admissible: each robot's graph distance to its goal at its top speed (lanes two-way, no limits)."""
        return float(move_cost(objective, to_a.at(pid[0], p[0]), to_b.at(pid[1], p[1]), va, vb))

    def allowed(pid: PolygonId, p: Coords, q: Coords) -> bool:
        return (not oneway[pid[0]] or q[0] >= p[0]) and (not oneway[pid[1]] or q[1] >= p[1])

    goal_at: dict[PolygonId, list[Coords]] = {}
    for pid, c in mesh.placements(*goal):
        goal_at.setdefault(pid, []).append(c)
    best: dict[Any, float] = {("S",): 0.0}
    back: dict[Any, tuple[Any, PolygonId, Coords, Coords]] = {}
    members: dict[Any, list[tuple[PolygonId, Coords]]] = {("S",): mesh.placements(*start)}
    heap: list[tuple[float, int, Any]] = [(0.0, 0, ("S",))]
    done: set[Any] = set()
    counter = 1

    def push(key: Any, gval: float, src: Any, pid: PolygonId, p: Coords, q: Coords) -> None:
        nonlocal counter
        if gval < best.get(key, math.inf):
            best[key] = gval
            back[key] = (src, pid, p, q)
            heapq.heappush(heap, (gval + (0.0 if key == ("G",) else bound(pid, q)), counter, key))
            counter += 1

    while heap:
        _, _, key = heapq.heappop(heap)
        gval = best[key]
        if key in done:
            continue
        done.add(key)
        if key == ("G",):
            break
        mem = members.get(key)
        if mem is None:
            mem = mesh.members(key)
        for pid, rc in mem:
            for pt in goal_at.get(pid, ()):
                if allowed(pid, rc, pt):
                    push(("G",), gval + cost(pid, rc, pt), key, pid, rc, pt)
            e, f, _ = pid
            for ax, a, face, lo, hi in mesh.sides(pid):
                # the face's fixed coordinate must be reachable; its other coordinate y within [lo, hi]
                if ax == 0:
                    if oneway[e] and a < rc[0]:
                        continue
                    ylo, yhi = (max(lo, rc[1]) if oneway[f] else lo), hi
                else:
                    if oneway[f] and a < rc[1]:
                        continue
                    ylo, yhi = (max(lo, rc[0]) if oneway[e] else lo), hi
                if ylo > yhi:
                    continue
                for y in (ylo, yhi) if yhi > ylo else (ylo,):
                    pt = (a, y) if ax == 0 else (y, a)
                    if pt == rc:
                        continue
                    k2 = mesh.point_key(face, y)
                    if k2 in done:
                        continue
                    push(k2, gval + cost(pid, rc, pt), key, pid, rc, pt)
    if ("G",) not in done:
        return None
    segs: list[list[Any]] = []
    key = ("G",)
    while key != ("S",):
        src, pid, p, q = back[key]
        segs.append([pid, p, q])
        key = src
    segs.reverse()
    return segs


def allowed_path(tr: GraphTrack, seg: list[Any]) -> bool:
    """Whether a straight segment ``[polygon, from, to]`` keeps the one-way rule in its cell."""
    (e, f, _), p, q = seg
    return (not tr.oneway[e] or q[0] >= p[0]) and (not tr.oneway[f] or q[1] >= p[1])


def _vertex_of(g: Any, e: int, x: float) -> int | None:
    return int(g._t[e]) if x == 0.0 else (int(g._h[e]) if x == g._L[e] else None)


def _relabel_standing(mesh: _Mesh, segs: list[list[Any]]) -> None:
    """A robot standing on a vertex during a segment belongs to every edge there: name it on the edge it uses in the
    neighbouring segment, so that the junction becomes a face point (one robot changes edges) that may slide."""
    g = mesh.g
    index = mesh.fs._index
    relabelled: set[tuple[int, int]] = set()
    changed = True
    while changed:
        changed = False
        for k in range(len(segs) - 1):
            for i, j in ((k, k + 1), (k + 1, k)):
                pid, p, q = segs[i]
                other = segs[j][0]
                for r in (0, 1):
                    if p[r] != q[r] or pid[r] == other[r] or (i, r) in relabelled:
                        continue
                    w = _vertex_of(g, pid[r], p[r])
                    e2 = other[r]
                    x2 = 0.0 if g._t[e2] == w else (float(g._L[e2]) if g._h[e2] == w else None)
                    if w is None or x2 is None:
                        continue
                    ea, eb = (e2, pid[1]) if r == 0 else (pid[0], e2)
                    p2 = (x2, p[1]) if r == 0 else (p[0], x2)
                    q2 = (x2, q[1]) if r == 0 else (q[0], x2)
                    if ea == eb and (p2[0] - p2[1]) * (q2[0] - q2[1]) <= 0:
                        continue
                    new = (ea, eb, 0 if ea != eb or p2[0] > p2[1] else 1)
                    if new in index:
                        relabelled.add((i, r))
                        segs[i] = [new, p2, q2]
                        pid, p, q = segs[i]
                        changed = True


def _smooth(
    mesh: _Mesh,
    tr: GraphTrack,
    segs: list[list[Any]],
    seg_cost: Any,
    sweeps: int = 60,
) -> list[list[Any]]:
    """Slide the path's face crossings along their faces to lower its cost, keeping every rule.

    A junction of two segments where exactly one robot changes frames (it stands on a vertex: a face point) may move
    along the face's free interval ``[lo, hi]``, and, when the other robot's edge is one-way, between the other
    robot's offsets at the neighbouring corners (monotone). Each segment stays in its convex polygon (its ends on the
    polygon's sides), so the path stays free. Coordinate descent: each junction in turn at the minimum of the two
    segments' costs (convex in its position; ternary search), sweeps until nothing improves by ``1e-12``.
    """
    g = mesh.g
    segs = [[x[0], tuple(x[1]), tuple(x[2])] for x in segs]
    _relabel_standing(mesh, segs)
    movable = []
    for k in range(len(segs) - 1):
        (p1, _, q1), (p2, q2, _) = segs[k], segs[k + 1]
        for ax in (0, 1):
            o = 1 - ax
            if p1[o] != p2[o] or q1[o] != q2[o]:
                continue  # the other robot must stay on its edge, at one offset, through the junction
            e1, e2 = p1[ax], p2[ax]
            end1 = g._t[e1] if q1[ax] == 0.0 else (g._h[e1] if q1[ax] == g._L[e1] else None)
            end2 = g._t[e2] if q2[ax] == 0.0 else (g._h[e2] if q2[ax] == g._L[e2] else None)
            if end1 is None or end2 is None or end1 != end2:
                continue
            w, f = int(end1), int(p1[o])
            if not mesh.ok[w][f]:
                continue
            movable.append((k, ax, mesh.lo[w][f], mesh.hi[w][f]))
            break
    if not movable:
        return segs
    oneway = tr.oneway

    def total(k: int) -> float:
        return seg_cost(segs[k][0], segs[k][1], segs[k][2]) + seg_cost(segs[k + 1][0], segs[k + 1][1], segs[k + 1][2])

    def place(k: int, ax: int, y: float) -> None:
        o = 1 - ax
        q1, q2 = list(segs[k][2]), list(segs[k + 1][1])
        q1[o] = q2[o] = y
        segs[k][2], segs[k + 1][1] = tuple(q1), tuple(q2)

    for _ in range(sweeps):
        gain = 0.0
        for k, ax, lo, hi in movable:
            o = 1 - ax
            lo_k, hi_k = lo, hi
            if oneway[segs[k][0][o]]:
                lo_k = max(lo_k, segs[k][1][o])
                hi_k = min(hi_k, segs[k + 1][2][o])
            y0 = segs[k][2][o]
            if hi_k <= lo_k:
                continue
            before = total(k)
            a, b = lo_k, hi_k
            for _ in range(80):
                m1, m2 = a + (b - a) / 3.0, b - (b - a) / 3.0
                place(k, ax, m1)
                c1 = total(k)
                place(k, ax, m2)
                c2 = total(k)
                if c1 <= c2:
                    b = m2
                else:
                    a = m1
            y = 0.5 * (a + b)
            place(k, ax, y)
            after = total(k)
            if after < before:
                gain += before - after
            else:
                place(k, ax, y0)
        if gain <= 1e-12:
            break
    return segs


def plan_with_rules(query: SearchQuery) -> Any:
    """A :class:`~mpa.planners.graph.GraphPlan` under the track's one-way edges and speed limits (see the module).

    ``query.start`` and ``query.goal`` are validated positions in one path component of ``query.free_space`` (without
    the rules).

    Raises
    ------
    NoMotionError
        Only the one-way rule can make the query impossible here; the message says so.
    """
    from mpa.planners.graph.assemble import _assemble, _merge_same_polygon
    from mpa.planners.graph.mesh import _mesh
    from mpa.planners.graph.search import AnyAngleSearch

    tr, start, goal, objective, (va, vb) = query.track, query.start, query.goal, query.objective, query.speeds
    mesh = _mesh(query.free_space)
    segs = _search(mesh, query)
    if segs is None:
        names = ", ".join(tr.position_name(*p) for p in start)
        gnames = ", ".join(tr.position_name(*p) for p in goal)
        one = [tr.edge_names[i] for i, ow in enumerate(tr.oneway) if ow]
        listed = ", ".join(one[:8]) + (" ..." if len(one) > 8 else "")
        raise NoMotionError(
            f"the one-way lanes forbid it: start ({names}) and goal ({gnames}) are connected when every lane may be "
            f"driven both ways, but no motion drives the one-way lanes ({listed}) only from 'from' to 'to'"
        )
    seg_cost = _cost_function(query)

    def smoothed(path: list[list[Any]]) -> list[list[Any]]:
        path = _merge_same_polygon([x for x in path if x[1] != x[2]])
        return _merge_same_polygon([x for x in _smooth(mesh, tr, path, seg_cost) if x[1] != x[2]])

    def path_cost(path: list[list[Any]]) -> float:
        return sum(seg_cost(x[0], x[1], x[2]) for x in path)

    raw = AnyAngleSearch(mesh, query).run()
    if raw is None:  # pragma: no cover - the component check guarantees a path without the rules
        raise PlanningError("the search without the rules found no path although it exists")
    raw = _merge_same_polygon([x for x in raw if x[1] != x[2]])
    free = _assemble(query, raw)
    bound = free.makespan if objective == "fastest" else free.length
    if objective == "fastest":  # each robot's own journey under the limits bounds the makespan too
        bound = max(bound, single_robot_time(tr, start[0], goal[0], va), single_robot_time(tr, start[1], goal[1], vb))
    candidates = [smoothed(segs)]
    if all(allowed_path(tr, x) for x in raw):  # the optimum without the rules keeps the one-way rule: start there
        candidates.append(smoothed(raw))
    segs = min(candidates, key=path_cost)
    plan = _assemble(query, segs)
    return dataclasses.replace(timed_at_limits(plan), lower_bound=bound)


def timed_at_limits(plan: GraphPlan) -> GraphPlan:
    """The plan (a :class:`~mpa.planners.graph.GraphPlan`) with its waypoint times and makespan at the cells' speeds:
    each straight move takes ``max(|Δs| / min(vA, v_e), |Δt| / min(vB, v_f))`` seconds (``vA, vB`` the plan's
    ``speeds``, ``v_e`` the speed limit of edge ``e`` of its track, if any)."""
    spa, spb = cell_speeds(plan.track, plan.speeds[0], plan.speeds[1])
    offs = plan.segment_offsets
    d = np.abs(offs[:, 1] - offs[:, 0]) if len(offs) else np.zeros((0, 2))
    sa = np.array([spa[c[0]] for c in plan.segment_cells], dtype=float)
    sb = np.array([spb[c[1]] for c in plan.segment_cells], dtype=float)
    seg_t = np.maximum(d[:, 0] / sa, d[:, 1] / sb) if len(offs) else np.zeros(0)
    times = np.concatenate([[0.0], np.cumsum(seg_t)])
    return dataclasses.replace(plan, makespan=float(times[-1]), _times=times)
