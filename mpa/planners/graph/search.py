"""The exact any-angle A* over roots and intervals of faces (docs/graphs.md, "The search in detail").

:class:`AnyAngleSearch` holds one query's search; its nodes are :class:`PointNode` (a root: the start, a face end or
corner, or the goal), :class:`FaceEntry` (a face seen from a root, queued; its pages are opened when it is taken) and
:class:`IntervalNode` (the part of a face seen straight from a root, unfolded into one of its pages).
"""

from __future__ import annotations

import gc
import heapq
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from mpa.errors import PlanningError
from mpa.freespace import PolygonId
from mpa.planners.graph.base import F_GRID, TIE_BREAK, TIE_BREAK_2, Coords, FaceKey, Key, Segment
from mpa.planners.graph.mesh import _Mesh
from mpa.planners.search_common import GoalDistance, SearchQuery, cost_function, least_through_face

if TYPE_CHECKING:
    from mpa.planners.graph.bounds import PassingBound

#: The keys of the start's and the goal's point nodes.
START: Key = ("S",)
GOAL: Key = ("G",)

#: A root reached again is queued (and expanded) again only when its cost falls by more than this many steps of the
#: queue's grid (``F_GRID`` of the start's bound): a smaller gain cannot change the order of the queue's buckets, and
#: on plateaus of equally fast motions it made the search expand the same roots up to ten times over (the "fastest"
#: cost's second tie-break, 1e-9 of the Euclidean time, differs between the ways to a root by less than the grid);
#: 0: every gain. The goal is always kept at its least cost.
AGAIN_GRID_STEPS = 1.0


def _uncovered(
    seen: dict[Key, list[tuple[float, float]]], key: Key, y0: float, y1: float, eps: float
) -> list[tuple[float, float]]:
    """The parts of ``[y0, y1]`` not yet covered by the intervals recorded under ``key``; records the union."""
    have = seen.get(key)
    if have is None:
        seen[key] = [(y0, y1)]
        return [(y0, y1)]
    if len(have) == 1:  # the common case: one interval recorded, covering [y0, y1] (what the loop below finds)
        z0, z1 = have[0]
        if z1 >= y0 and z0 <= y1 and z0 <= y0 + eps and z1 >= y1 - eps:
            return []
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


@dataclass(slots=True)
class PointNode:
    """A root reached at cost ``g``: the start (``key`` :data:`START`), a face end or corner (``key`` from
    :meth:`_Mesh.point_key`) or the goal (:data:`GOAL`).

    It is reached by a straight run from the point node ``root`` (-1: none, the start): inside the polygon
    ``polygon`` from ``frm`` to ``to`` (offsets in the polygon's cell, metres) when ``last`` is -1, else through
    faces, the run's last face crossed in the interval node ``last``, ending at ``to`` in ``polygon``.
    """

    key: Key
    g: float
    root: int
    last: int
    polygon: PolygonId | None
    frm: Coords | None
    to: Coords | None


@dataclass(slots=True)
class _Sight:
    """The part ``[y0, y1]`` of a face seen straight from a root: the point node ``root`` (key ``root_key``, reached
    at ``g_root``), at ``r`` in the frame of the polygon ``polygon``, unfolded with the signs ``sig`` per axis; the
    face is ``polygon``'s side ``ax = a`` (``ax`` 0: robot A on a vertex)."""

    root: int
    root_key: Key
    g_root: float
    r: Coords
    sig: Coords
    ax: int
    a: float
    y0: float
    y1: float
    polygon: PolygonId


@dataclass(slots=True)
class FaceEntry(_Sight):
    """A face seen from a root, queued once for all its pages: the line leaves ``polygon`` through its side
    ``face``, free over ``[lo, hi]``; ``parent``: the node the line came through (the interval node before, or the
    root), ``origin``: the root's polygon and coordinates."""

    face: FaceKey
    lo: float
    hi: float
    parent: int
    origin: tuple[PolygonId, Coords]


@dataclass(slots=True)
class IntervalNode(_Sight):
    """A face seen from a root, in one page: ``polygon`` entered through its side ``ax = a`` from the polygon
    ``prev_polygon`` (its side ``ax = prev_a``); ``lo``, ``hi``, ``parent`` and ``origin`` as in
    :class:`FaceEntry`."""

    prev_polygon: PolygonId
    prev_a: float
    lo: float
    hi: float
    parent: int
    origin: tuple[PolygonId, Coords]


Node = PointNode | FaceEntry | IntervalNode


Crossing = tuple[PolygonId, Coords, tuple[float, float], int, float, float, float, float]


def fold_run(q0: PolygonId, r0: Coords, q: Coords, crossings: list[Crossing]) -> list[Segment]:
    """The straight segments of a run through faces, read back from its interval nodes (for
    :meth:`AnyAngleSearch.segments` and the compiled search's).

    Parameters
    ----------
    q0 : PolygonId
        The polygon the run leaves its root in.
    r0 : (float, float)
        The root, in ``q0``'s offsets (metres).
    q : (float, float)
        Where the run ends, in the last polygon's offsets (metres).
    crossings : list of (polygon, r, sig, ax, a, lo, hi, prev_a)
        Per interval node from the root on: the polygon it enters, its root ``r`` and signs ``sig`` in that
        polygon's offsets, the face's axis ``ax`` and offset ``a`` there, the interval ``[lo, hi]`` on the face and
        the face's offset ``prev_a`` in the polygon before.

    Returns
    -------
    list of [PolygonId, (s, t), (s, t)]
        One segment per polygon of the run, the straight line from the root to ``q`` clamped into each face.
    """
    rk, sk = crossings[-1][1], crossings[-1][2]
    d0 = (sk[0] * (q[0] - rk[0]), sk[1] * (q[1] - rk[1]))
    segs: list[Segment] = []
    prev_pid, prev_pt = q0, r0
    for polygon, r, sig, ax, a, lo, hi, prev_a in crossings:
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
        prev_pid, prev_pt = polygon, entry
    segs.append([prev_pid, prev_pt, q])
    return segs


class AnyAngleSearch:
    """The exact shortest path (for the objective's cost) of one query in the free space.

    An any-angle A* over *roots* (start, face ends and corners, where a taut path can bend) and *intervals* (the part
    of a face seen straight from a root through the faces crossed so far, unfolded across faces). The queue's order
    is the lower bound (:meth:`lower_bound`, :meth:`face_lower_bound`) plus the cost so far (:meth:`queue_key`).

    Parameters
    ----------
    mesh : _Mesh
        The free space as the search sees it.
    query : SearchQuery
        The start, the goal, the objective and the robots' speeds.
    bound : PassingBound, optional
        The passing bound of this query (:mod:`mpa.planners.graph.bounds`): a node's bound is then the larger of the
        robots' distances' and the passing bound at its point (at its root, for a face entry).
    to_goal : (GoalDistance, GoalDistance), optional
        The robots' distances to their goals that the bound is made of (default: their graph distances). A class of
        motions whose last entry into a corridor is known (:mod:`mpa.planners.graph.corridor`) has larger ones; the
        search then returns a motion no dearer than the best of that class.
    """

    def __init__(
        self,
        mesh: _Mesh,
        query: SearchQuery,
        bound: PassingBound | None = None,
        to_goal: tuple[GoalDistance, GoalDistance] | None = None,
    ) -> None:
        start, goal = query.start, query.goal
        self.mesh = mesh
        self.bound = bound
        self.start = start
        self.eps = mesh.eps
        self.ctol = 1e-12 * mesh.scale * mesh.scale
        self.cost = cost_function(query.objective, query.va, query.vb)
        self.to_goal = (GoalDistance(mesh.g, goal[0]), GoalDistance(mesh.g, goal[1])) if to_goal is None else to_goal
        self._vd_a, self._vd_b = self.to_goal[0].vd, self.to_goal[1].vd
        self.goal_at: dict[PolygonId, list[Coords]] = {}
        for pid, c in mesh.placements(*goal):
            self.goal_at.setdefault(pid, []).append(c)
        self.nodes: list[Node] = []
        # interval nodes by (root, page, side, root position in the page's frame): routes of equal lengths (a
        # lattice's Manhattan ties) unfold to the same node; keep one
        self.seen: dict[Key, list[tuple[float, float]]] = {}
        self.quantum = 1.0 / (1e-9 * mesh.scale)
        self.best: dict[Key, float] = {}
        self.heap: list[tuple[int, float, int]] = []
        # nodes queued by their own bound whose passing bound is taken into their key when they are first taken from
        # the queue (:meth:`_passing_key`): most queued nodes are never taken
        self.pending: set[int] = set()
        (sa_e, sa_s), (sb_e, sb_s) = start
        self.fq = 1.0 / (F_GRID * max(1e-3, self.cost(self.to_goal[0].at(sa_e, sa_s), self.to_goal[1].at(sb_e, sb_s))))
        self.again = AGAIN_GRID_STEPS / self.fq
        # the hot paths compute the objective's cost inline, with the floating-point operations of cost_function
        self._fastest = query.objective != "shortest"
        self._va, self._vb = query.va, query.vb
        ga, gb = self.to_goal
        self._goal_terms = (ga.cp, ga.cm, ga.edge, ga.offset, gb.cp, gb.cm, gb.edge, gb.offset)
        self._through = ((gb.cp, gb.cm, gb.edge, gb.offset), (ga.cp, ga.cm, ga.edge, ga.offset))
        # per face, its pages a straight line can go on into (dead ends dropped unless they hold the goal)
        self._open_pages: dict[FaceKey, list[tuple[PolygonId, float]]] = {}
        # what expand_interval reads on every call, in one tuple (nothing in it refers back to the search)
        self._hot = (
            self.ctol, self.eps, self.goal_at, self._fastest, self._va, self._vb, math.hypot, self.best.get,
            self.again, bound, self.nodes, self.heap, self.fq, heapq.heappush, math.floor, self._vd_a, self._vd_b,
            self._through, mesh._side_ends, self.pending.add, least_through_face,
        )  # fmt: skip

    # ------------------------------------------------------------------------------------------- the lower bound
    def lower_bound(self, pid: PolygonId, pt: Coords) -> float:
        """A lower bound of the cost from the configuration at ``pt`` (offsets in the cell ``pid``) to the goal: the
        cost of the robots' graph distances to their goals (each move costs at least what it takes off them).

        The cost of :meth:`GoalDistance.at` of both robots, computed inline with the same floating-point operations
        (``min(x, y)`` as ``y if y < x else x``, the objective's cost as :func:`cost_function`'s)."""
        cp_a, cm_a, edge_a, off_a, cp_b, cm_b, edge_b, off_b = self._goal_terms
        e, y = pid[0], pt[0]
        x, d = y + cp_a[e], cm_a[e] - y
        da = d if d < x else x
        if e == edge_a:
            x = abs(y - off_a)
            da = x if x < da else da
        e, y = pid[1], pt[1]
        x, d = y + cp_b[e], cm_b[e] - y
        db = d if d < x else x
        if e == edge_b:
            x = abs(y - off_b)
            db = x if x < db else db
        if self._fastest:
            ta, tb = abs(da) / self._va, abs(db) / self._vb
            return (tb if tb > ta else ta) + TIE_BREAK * (ta + tb) + TIE_BREAK_2 * math.hypot(ta, tb)
        return math.hypot(da, db)

    def face_lower_bound(self, r: Coords, ax: int, a: float, face: FaceKey, y0: float, y1: float) -> float:
        """A lower bound of the cost from the root at ``r`` through the part ``[y0, y1]`` of ``face`` (the side
        ``ax = a`` of the root's polygon) to the goal: the least over the part's points of the straight move's cost
        to the point plus the cost of the robots' distances to their goals from there
        (:func:`~mpa.planners.search_common.least_through_face`; every motion through the entry goes straight from
        the root to a point of the part). :meth:`expand_interval` computes it inline, with the same operations."""
        w, e = face[1], face[2]
        cp, cm, edge, off = self._through[ax]
        if ax == 0:
            x_v, x_w, rr = abs(r[0] - a), self._vd_a[w], r[1]
        else:
            x_v, x_w, rr = abs(r[1] - a), self._vd_b[w], r[0]
        return least_through_face(
            ax, x_v, x_w, rr, y0, y1, cp[e], cm[e], e == edge, off, self._fastest, self._va, self._vb
        )

    def queue_key(self, f: float, depth: float, nid: int) -> tuple[int, float, int]:
        """The search's order (:meth:`expand_interval` queues face entries with this expression inline): the bound
        ``f`` on a grid of ``F_GRID`` of the start's bound (so that near-equal bounds count as ties), then deeper first
        (larger cost from the start of the root, ``depth``): on the plateaus of equally fast motions (a robot with
        slack may take any of many routes) the search dives to the goal instead of widening; the plan is optimal up to
        that grid."""
        return (math.floor(f * self.fq), -depth, nid)

    # ---------------------------------------------------------------------------------------------- the queue
    def push_point(
        self, key: Key, gval: float, root: int, last: int, pid: PolygonId, frm: Coords | None, pt: Coords
    ) -> None:
        """Queue the point ``key`` (at ``pt`` in ``pid``) reached at cost ``gval`` (a :class:`PointNode` with these
        fields) if more cheaply than before; the goal (``key`` :data:`GOAL`) with its cost as its bound."""
        best = self.best
        if gval < best.get(key, math.inf) - (0.0 if key is GOAL else self.again):
            best[key] = gval
            nodes = self.nodes
            nodes.append(PointNode(key, gval, root, last, pid, frm, pt))
            f = gval if key is GOAL else gval + self.lower_bound(pid, pt)
            if self.bound is not None and key is not GOAL:
                self.pending.add(len(nodes) - 1)  # its passing bound when taken (_passing_key)
            heapq.heappush(self.heap, self.queue_key(f, gval, len(nodes) - 1))

    def push_face(self, entry: FaceEntry) -> None:
        """Queue the part ``[y0, y1]`` of a face seen from a root, once for all the face's other pages: the bound is
        the same for each (the robot on the vertex is as far from its goal, and the other robot's edge is the
        face's), so the pages are opened only when the entry is taken from the queue (:meth:`open_face`)."""
        nodes = self.nodes
        nodes.append(entry)
        g_root = entry.g_root
        f = g_root + self.face_lower_bound(entry.r, entry.ax, entry.a, entry.face, entry.y0, entry.y1)
        if self.bound is not None:
            self.pending.add(len(nodes) - 1)  # its passing bound when taken (_passing_key)
        heapq.heappush(self.heap, self.queue_key(f, g_root, len(nodes) - 1))

    def _passing_key(self, nd: PointNode | FaceEntry, key0: int) -> int:
        """The queue key of a node queued with ``key0`` from its own bound, with the passing bound taken in: the key
        it would have had if the larger of the two had been computed when it was queued (``floor`` is monotone, so the
        key of the larger bound is the larger key). A point's bound is the passing bound at the point; a face entry's
        the passing bound at its root and through the face's part ``[y0, y1]``."""
        bound = self.bound
        assert bound is not None
        fq = self.fq
        if type(nd) is PointNode:
            return max(key0, math.floor((nd.g + bound.point(nd.key)) * fq))
        assert type(nd) is FaceEntry
        g_root, r, a, y0, y1 = nd.g_root, nd.r, nd.a, nd.y0, nd.y1
        x_a, x_b = (
            (abs(r[0] - a), max(0.0, y0 - r[1], r[1] - y1))
            if nd.ax == 0
            else (max(0.0, y0 - r[0], r[0] - y1), abs(r[1] - a))
        )
        f = max(
            g_root + bound.point(nd.root_key),
            g_root + self.cost(x_a, x_b) + bound.entry(nd.face, y0, y1),
        )
        return max(key0, math.floor(f * fq))

    # ----------------------------------------------------------------------------------------------- expansion
    def pages_to_open(self, face: FaceKey) -> list[tuple[PolygonId, float]]:
        """The pages of ``face`` (:meth:`_Mesh.pages`, in order) a straight line can go on into: a dead end (a polygon
        of one face) only when it holds the goal; made once per face and search."""
        out = self._open_pages.get(face)
        if out is None:
            mesh, goal_at = self.mesh, self.goal_at
            out = self._open_pages[face] = [
                (pid2, b) for pid2, b in mesh.pages(face) if len(mesh.sides(pid2)) != 1 or pid2 in goal_at
            ]
        return out

    def open_face(self, entry: FaceEntry) -> None:
        """The interval nodes of a queued face entry in each other page (the root unfolded), expanded at once."""
        r, sig, ax, a, pid = entry.r, entry.sig, entry.ax, entry.a, entry.polygon
        pages = self._open_pages.get(entry.face)
        if pages is None:
            pages = self.pages_to_open(entry.face)
        rid, y0, y1, quantum, seen = entry.root, entry.y0, entry.y1, self.quantum, self.seen
        nodes, expand = self.nodes, self.expand_interval
        root_key, g_root, lo, hi, parent, origin = (
            entry.root_key,
            entry.g_root,
            entry.lo,
            entry.hi,
            entry.parent,
            entry.origin,
        )
        n1 = 1.0 if a == 0.0 else -1.0
        # the unfolded root moves along the face's axis only: the other coordinate and its rounding are the entry's
        across = r[ax] - a
        kept = r[1 - ax]
        k_kept = round(kept * quantum)
        for pid2, b in pages:
            if pid2 == pid and b == a:
                continue
            sg = -n1 if b == 0.0 else n1  # -n1 * n2, n2 the page's side normal
            moved = b + sg * across
            if ax == 0:
                r2 = (moved, kept)
                sig2 = (sg * sig[0], sig[1])
                sk = (rid, pid2, 0, b, round(moved * quantum), k_kept)
            else:
                r2 = (kept, moved)
                sig2 = (sig[0], sg * sig[1])
                sk = (rid, pid2, 1, b, k_kept, round(moved * quantum))
            if sk not in seen:  # nothing seen so before: the whole part
                seen[sk] = [(y0, y1)]
                parts: list[tuple[float, float]] | tuple[tuple[float, float]] = ((y0, y1),)
            else:
                parts = _uncovered(seen, sk, y0, y1, self.eps)  # the parts not seen so before
            for z0, z1 in parts:
                node = IntervalNode(
                    rid, root_key, g_root, r2, sig2, ax, b, z0, z1, pid2, pid, a, lo, hi, parent, origin
                )
                nodes.append(node)
                expand(len(nodes) - 1, node)

    def expand_point(self, nid: int, key: Key, gval: float, members: list[tuple[PolygonId, Coords]]) -> None:
        """Straight runs from the root ``nid`` (at cost ``gval``) in each polygon holding it: to the goal, to every
        face end, and into every face it does not lie on."""
        mesh, cost, eps = self.mesh, self.cost, self.eps
        push_point, push_face = self.push_point, self.push_face
        for q, rc in members:
            for pt in self.goal_at.get(q, ()):
                push_point(GOAL, gval + cost(pt[0] - rc[0], pt[1] - rc[1]), nid, -1, q, rc, pt)
            for ax2, a2, face2, lo2, hi2 in mesh.sides(q):
                on_line = rc[ax2] == a2
                for y in (lo2, hi2) if hi2 > lo2 else (lo2,):
                    pt = (a2, y) if ax2 == 0 else (y, a2)
                    if pt == rc:
                        continue
                    k2 = mesh.point_key(face2, y)
                    push_point(k2, gval + cost(pt[0] - rc[0], pt[1] - rc[1]), nid, -1, q, rc, pt)
                if on_line or hi2 - lo2 <= eps:
                    continue
                push_face(
                    FaceEntry(nid, key, gval, rc, (1.0, 1.0), ax2, a2, lo2, hi2, q, face2, lo2, hi2, nid, (q, rc))
                )

    def expand_interval(self, nid: int, nd: IntervalNode) -> None:
        """The interval node ``nid``: the goal and the face ends it sees in its polygon, and the parts of the
        polygon's other faces it sees (queued as face entries).

        The cone from the root through ``[y0, y1]`` is ``sgn * cross(u0, q - r) >= -ctol`` and
        ``-sgn * cross(u1, q - r) >= -ctol``; on a side ``ax2 = a2`` each is ``ca * y + cb >= -ctol`` in the side's
        coordinate ``y``, which clips the side's ``[lo, hi]``. The face ends' costs are the objective's, inline."""
        (
            ctol, eps, goal_at, fastest, va, vb, hypot, best_get, again, bound, nodes, heap, fq, heappush, floor,
            vd_a, vd_b, through, side_ends, pending_add, least_face,
        ) = self._hot  # fmt: skip
        rid, r, ax, a, y0, y1, pid, groot = nd.root, nd.r, nd.ax, nd.a, nd.y0, nd.y1, nd.polygon, nd.g_root
        rs, rt = r
        if ax == 0:
            u00, u01, u10, u11 = a - rs, y0 - rt, a - rs, y1 - rt
        else:
            u00, u01, u10, u11 = y0 - rs, a - rt, y1 - rs, a - rt
        cr = u00 * u11 - u01 * u10
        if abs(cr) <= ctol:
            return
        sgn = 1.0 if cr > 0 else -1.0
        nsg = -sgn
        goals = goal_at.get(pid)
        if goals is not None:
            for pt in goals:
                dx, dy = pt[0] - rs, pt[1] - rt
                if sgn * (u00 * dy - u01 * dx) >= -ctol and nsg * (u10 * dy - u11 * dx) >= -ctol:  # in the cone
                    self.push_point(GOAL, groot + self.cost(pt[0] - rs, pt[1] - rt), rid, nid, pid, None, pt)
        # the cone's conditions on a side ax2 = a2 (q = (a2, y) or (y, a2)), the parts that do not depend on a2
        nctol = -ctol
        ca0_a, ca1_a = sgn * u00, nsg * u10  # ax2 = 0: cross(u, q - r) = u_s (y - rt) - u_t (a2 - rs)
        m0_a, m1_a = -u00 * rt, -u10 * rt
        ca0_b, ca1_b = sgn * -u01, nsg * -u11  # ax2 = 1: u_s (a2 - rt) - u_t (y - rs)
        m0_b, m1_b = u01 * rs, u11 * rs
        inf = math.inf
        sides = side_ends.get(pid)
        if sides is None:
            sides = self.mesh.side_ends(pid)
        for ax2, a2, face2, lo2, hi2, k_lo, p_lo, k_hi, p_hi in sides:
            if ax2 == 0:
                if ax == 0 and a2 == a:
                    continue
                if (rs - a2 if a2 == 0.0 else a2 - rs) <= eps:
                    continue  # a straight line leaves through this side only if its root lies on the side's inner side
                d_a = a2 - rs
                ca0, cb0 = ca0_a, sgn * (m0_a - u01 * d_a)
                ca1, cb1 = ca1_a, nsg * (m1_a - u11 * d_a)
            else:
                if ax == 1 and a2 == a:
                    continue
                if (rt - a2 if a2 == 0.0 else a2 - rt) <= eps:
                    continue
                d_a = a2 - rt
                ca0, cb0 = ca0_b, sgn * (u00 * d_a + m0_b)
                ca1, cb1 = ca1_b, nsg * (u10 * d_a + m1_b)
            yl, yh = lo2, hi2  # the two conditions unrolled: a loop over them made the search 5 % slower
            if ca0 > 0.0:
                v = (nctol - cb0) / ca0
                if v > yl:
                    yl = v
            elif ca0 < 0.0:
                v = (nctol - cb0) / ca0
                if v < yh:
                    yh = v
            elif cb0 < nctol:
                yl, yh = 1.0, 0.0
            if ca1 > 0.0:
                v = (nctol - cb1) / ca1
                if v > yl:
                    yl = v
            elif ca1 < 0.0:
                v = (nctol - cb1) / ca1
                if v < yh:
                    yh = v
            elif cb1 < nctol:
                yl, yh = 1.0, 0.0
            if yl > yh + eps:
                continue
            if yl <= lo2 + eps:
                yl = lo2
                dx, dy, limit = p_lo[0] - rs, p_lo[1] - rt, best_get(k_lo, inf) - again
                if fastest:
                    ta, tb = abs(dx) / va, abs(dy) / vb
                    m = tb if tb > ta else ta
                    if groot + m < limit:  # else the cost, at least groot + m, is not below the limit
                        g2 = groot + (m + TIE_BREAK * (ta + tb) + TIE_BREAK_2 * hypot(ta, tb))
                        if g2 < limit:
                            self.push_point(k_lo, g2, rid, nid, pid, None, p_lo)
                elif (g2 := groot + hypot(dx, dy)) < limit:
                    self.push_point(k_lo, g2, rid, nid, pid, None, p_lo)
            if yh >= hi2 - eps:
                yh = hi2
                dx, dy, limit = p_hi[0] - rs, p_hi[1] - rt, best_get(k_hi, inf) - again
                if fastest:
                    ta, tb = abs(dx) / va, abs(dy) / vb
                    m = tb if tb > ta else ta
                    if groot + m < limit:  # else the cost, at least groot + m, is not below the limit
                        g2 = groot + (m + TIE_BREAK * (ta + tb) + TIE_BREAK_2 * hypot(ta, tb))
                        if g2 < limit:
                            self.push_point(k_hi, g2, rid, nid, pid, None, p_hi)
                elif (g2 := groot + hypot(dx, dy)) < limit:
                    self.push_point(k_hi, g2, rid, nid, pid, None, p_hi)
            if yh - yl <= eps:
                continue
            entry = FaceEntry(rid, nd.root_key, groot, r, nd.sig, ax2, a2, yl, yh, pid, face2, lo2, hi2, nid, nd.origin)
            # push_face inline: face_lower_bound and queue_key, the same operations; the passing bound when taken
            nodes.append(entry)
            if bound is not None:
                pending_add(len(nodes) - 1)
            w, e = face2[1], face2[2]
            cp, cm, edge, off = through[ax2]
            if ax2 == 0:
                x_v, x_w, rr = abs(rs - a2), vd_a[w], rt
            else:
                x_v, x_w, rr = abs(rt - a2), vd_b[w], rs
            f = groot + least_face(ax2, x_v, x_w, rr, yl, yh, cp[e], cm[e], e == edge, off, fastest, va, vb)
            heappush(heap, (floor(f * fq), -groot, len(nodes) - 1))

    # --------------------------------------------------------------------------------------------------- run
    def run(self, budget: int | None = None, limit: float | None = None) -> list[Segment] | None:
        """The path's straight segments start to goal (:meth:`segments`); with ``budget``: None after that many
        expansions (a later call resumes the search where it stopped); with ``limit``: None when the queue's least
        bound exceeds ``limit`` (the objective's cost) before the goal is taken.

        The search makes tens of thousands of small objects and no reference cycles: Python's cyclic garbage
        collector, which would traverse all of them again and again (a quarter of the time of a long search), is
        paused while it runs (:func:`gc.disable`) and enabled again after, if it was.

        Raises
        ------
        PlanningError
            The goal was not reached although the caller found it in the start's component (a bug).
        """
        collecting = gc.isenabled()
        gc.disable()
        try:
            return self._run(budget, limit)
        finally:
            if collecting:
                gc.enable()

    def _run(self, budget: int | None, limit: float | None) -> list[Segment] | None:
        start_members = self.mesh.placements(*self.start)
        if not self.nodes:
            self.best[START] = 0.0
            self.nodes.append(PointNode(START, 0.0, -1, -1, None, None, None))
            self.expand_point(0, START, 0.0, start_members)
        nodes, best, heap, pending = self.nodes, self.best, self.heap, self.pending
        found = -1
        expanded = 0
        over = math.inf if limit is None else math.floor(limit * self.fq)
        while heap:
            key0, depth, nid = heapq.heappop(heap)
            expanded += 1
            if (budget is not None and expanded > budget) or key0 > over:
                heapq.heappush(heap, (key0, depth, nid))  # not taken: run() resumes with it
                return None
            nd = nodes[nid]
            if type(nd) is PointNode:
                if nd.key is GOAL:
                    found = nid
                    break
                if nd.g > best[nd.key]:
                    continue  # reached more cheaply since (a root reached again more cheaply is expanded again)
            else:
                assert type(nd) is FaceEntry
                if nd.g_root > best[nd.root_key]:
                    continue  # its root was reached more cheaply since
            if pending and nid in pending:  # queued by its own bound: now with the passing bound too
                pending.discard(nid)
                key1 = self._passing_key(nd, key0)
                if key1 > key0:
                    heapq.heappush(heap, (key1, depth, nid))
                    continue
            if type(nd) is PointNode:
                self.expand_point(nid, nd.key, nd.g, self.mesh.members(nd.key))
            else:
                assert type(nd) is FaceEntry
                self.open_face(nd)
        if found < 0:
            raise PlanningError(
                "search ended without reaching the goal although it is in the start's component (a bug)"
            )
        return self.segments(found, start_members)

    def segments(self, nid: int, start_members: list[tuple[PolygonId, Coords]]) -> list[Segment]:
        """The path's straight segments ``[polygon, from, to]`` (offsets in the polygon's cell, metres), start to
        goal, read back from the point node ``nid``: a run through faces is folded back from its interval nodes."""
        nodes = self.nodes
        runs: list[list[Segment]] = []
        while nid != 0:
            nd = nodes[nid]
            assert type(nd) is PointNode
            if nd.last < 0:
                runs.append([[nd.polygon, nd.frm, nd.to]])
                nid = nd.root
                continue
            rid, q = nd.root, nd.to
            assert q is not None
            chain: list[IntervalNode] = []
            i = nd.last
            while i != rid:
                it = nodes[i]
                assert type(it) is IntervalNode
                chain.append(it)
                i = it.parent
            chain.reverse()
            q0, r0 = chain[0].origin
            crossings = [(it.polygon, it.r, it.sig, it.ax, it.a, it.lo, it.hi, it.prev_a) for it in chain]
            runs.append(fold_run(q0, r0, q, crossings))
            nid = rid
        out: list[Segment] = []
        for run in reversed(runs):
            out.extend(run)
        if not out:
            pid, c = start_members[0]
            out.append([pid, c, c])
        return out
