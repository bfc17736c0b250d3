"""The exact any-angle A* over roots and intervals of faces (docs/graphs.md, "The search in detail")."""

from __future__ import annotations

import heapq
import math
from typing import TYPE_CHECKING, Any

import numpy as np

from mpa.errors import PlanningError
from mpa.freespace import PolygonId
from mpa.graph_track import Position
from mpa.planners.graph.assemble import _unwind
from mpa.planners.graph.base import F_GRID, TIE_BREAK, TIE_BREAK_2, Coords, FaceKey, Key
from mpa.planners.graph.mesh import _Mesh

if TYPE_CHECKING:
    from mpa.planners.graph.bounds import PassingBound


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
    bound: PassingBound | None = None,
) -> list[list[Any]] | None:
    """Exact shortest path (for the objective's cost) in the free space: an any-angle A* over *roots* (start, face
    ends and corners, where a taut path can bend) and *intervals* (the part of a face seen straight from a root
    through the faces crossed so far, unfolded across faces). With ``budget``: None after that many expansions. With
    ``bound`` (:class:`~mpa.planners.graph.bounds.PassingBound` of this query): a node's bound is the larger of the
    robots' distances' and the passing bound at its point (at its root, for a face entry)."""
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
            if bound is not None:
                f = max(f, gval + bound.point(key))
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
        f = groot + comb(xa, xb)
        if bound is not None:
            x_a, x_b = (
                (abs(r[0] - a), max(0.0, y0 - r[1], r[1] - y1))
                if ax == 0
                else (max(0.0, y0 - r[0], r[0] - y1), abs(r[1] - a))
            )
            f = max(f, groot + bound.point(rkey), groot + comb(x_a, x_b) + bound.entry(face, y0, y1))
        nodes.append([3, rid, rkey, groot, r, sig, ax, a, y0, y1, pid, face, lo, hi, parent, origin])
        heapq.heappush(heap, queue_key(f, groot, len(nodes) - 1))

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
