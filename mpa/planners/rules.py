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

**Search.** Dijkstra over points: the start, and on every face reached from a point ``r`` the two ends of
``face ∩ C(r)`` and the point of it nearest to ``r`` along the face; a point's key names it independently of the
polygon (a corner, or a face and an offset), and it is expanded in every polygon holding it. The goal is reached
from a point whose polygon holds it and whose cone contains it. Each coordinate is a face end, the start's, or a
coordinate carried over from an earlier point while the same robot stays on the same edge, so the set of points is
finite and the search ends.

**Complete.** Let a motion respecting every one-way edge cross faces ``x1, x2, ...``. By induction the search holds,
on the face of ``x_k``, the lower end ``y_k`` of ``face ∩ C(y_{k-1})``, which contains ``x_k`` (cones only shrink
along a monotone motion): ``y_k`` is no later than ``x_k`` in the one-way coordinate along the face (if any) and
equal in the other, so ``C(y_k) ⊇ C(x_k)`` in every polygon glued along that face. The goal lies in ``C(x_last)``,
hence in ``C(y_last)``: a motion is found whenever one exists.

**Cost.** A straight move ``(Δs, Δt)`` in the cell ``e × f`` takes ``max(|Δs| / min(vA, v_e), |Δt| / min(vB, v_f))``
seconds (``"fastest"``, exact for the path found, with the tie-breaks of :mod:`mpa.planners.graph`) or its length
(``"shortest"``). The path found is the cheapest through the points above; it is not the optimum over all paths (an
optimal path may bend elsewhere on a face). Its distance from the optimum is bounded per plan: the plan records as
``lower_bound`` the optimum of the same query without the rules (:func:`mpa.planners.graph.plan_graph`'s exact
search, at the speeds ``(vA, vB)``), which no motion under the rules can beat.
"""

from __future__ import annotations

import dataclasses
import heapq
import math
from typing import Any

import numpy as np

from mpa.errors import NoMotionError, PlanningError
from mpa.freespace import FreeSpace, PolygonId
from mpa.graph_track import GraphTrack, Position

__all__ = ["plan_with_rules"]

Coords = tuple[float, float]


def _cell_speeds(tr: GraphTrack, va: float, vb: float) -> tuple[list[float], list[float]]:
    """Per edge the speed of robot A and of robot B on it (m/s): their limit capped by the edge's."""
    lim = [math.inf if v is None else v for v in tr.speed_limits]
    return [min(va, x) for x in lim], [min(vb, x) for x in lim]


def _search(
    mesh: Any,
    tr: GraphTrack,
    start: tuple[Position, Position],
    goal: tuple[Position, Position],
    objective: str,
    va: float,
    vb: float,
) -> list[list[Any]] | None:
    """Segments ``[polygon, from, to]`` (cell offsets) of the cheapest path through the candidate points, or None
    when the goal cannot be reached under the one-way rule."""
    from mpa.planners.graph import TIE_BREAK, TIE_BREAK_2

    oneway = tr.oneway
    spa, spb = _cell_speeds(tr, va, vb)

    def cost(pid: PolygonId, p: Coords, q: Coords) -> float:
        ds, dt = q[0] - p[0], q[1] - p[1]
        if objective == "shortest":
            return math.hypot(ds, dt)
        ta, tb = abs(ds) / spa[pid[0]], abs(dt) / spb[pid[1]]
        return max(ta, tb) + TIE_BREAK * (ta + tb) + TIE_BREAK_2 * math.hypot(ta, tb)

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
            heapq.heappush(heap, (gval, counter, key))
            counter += 1

    while heap:
        gval, _, key = heapq.heappop(heap)
        if key in done or gval > best[key]:
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
                    ylo, yhi, near = (max(lo, rc[1]) if oneway[f] else lo), hi, rc[1]
                else:
                    if oneway[f] and a < rc[1]:
                        continue
                    ylo, yhi, near = (max(lo, rc[0]) if oneway[e] else lo), hi, rc[0]
                if ylo > yhi:
                    continue
                for y in {ylo, yhi, min(max(near, ylo), yhi)}:
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


def plan_with_rules(
    tr: GraphTrack,
    fs: FreeSpace,
    start: tuple[Position, Position],
    goal: tuple[Position, Position],
    objective: str,
    speeds: tuple[float, float],
) -> Any:
    """A :class:`~mpa.planners.graph.GraphPlan` under the track's one-way edges and speed limits (see the module).

    ``start`` and ``goal`` are validated positions in one path component of ``fs`` (without the rules).

    Raises
    ------
    NoMotionError
        Only the one-way rule can make the query impossible here; the message says so.
    """
    from mpa.planners.graph import _assemble, _merge_same_polygon, _mesh
    from mpa.planners.graph import _search as exact_search

    va, vb = speeds
    mesh = _mesh(fs)
    segs = _search(mesh, tr, start, goal, objective, va, vb)
    if segs is None:
        names = ", ".join(tr.position_name(*p) for p in start)
        gnames = ", ".join(tr.position_name(*p) for p in goal)
        one = [tr.edge_names[i] for i, ow in enumerate(tr.oneway) if ow]
        listed = ", ".join(one[:8]) + (" ..." if len(one) > 8 else "")
        raise NoMotionError(
            f"the one-way lanes forbid it: start ({names}) and goal ({gnames}) are connected when every lane may be "
            f"driven both ways, but no motion drives the one-way lanes ({listed}) only from 'from' to 'to'"
        )
    segs = _merge_same_polygon([x for x in segs if x[1] != x[2]])
    plan = _assemble(tr, fs, start, goal, objective, speeds, segs)
    spa, spb = _cell_speeds(tr, va, vb)
    offs = plan.segment_offsets
    d = np.abs(offs[:, 1] - offs[:, 0]) if len(offs) else np.zeros((0, 2))
    sa = np.array([spa[c[0]] for c in plan.segment_cells], dtype=float)
    sb = np.array([spb[c[1]] for c in plan.segment_cells], dtype=float)
    seg_t = np.maximum(d[:, 0] / sa, d[:, 1] / sb) if len(offs) else np.zeros(0)
    times = np.concatenate([[0.0], np.cumsum(seg_t)])
    bound = None
    raw = exact_search(mesh, start, goal, objective, va, vb)
    if raw is not None:
        raw = _merge_same_polygon([x for x in raw if x[1] != x[2]])
        free = _assemble(tr, fs, start, goal, objective, speeds, raw)
        bound = free.makespan if objective == "fastest" else free.length
    if bound is None:  # pragma: no cover - the component check guarantees a path without the rules
        raise PlanningError("the search without the rules found no path although it exists")
    return dataclasses.replace(plan, makespan=float(times[-1]), _times=times, lower_bound=bound)
