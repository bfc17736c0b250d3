"""Free space of two robots with bodies in the plane, exactly, and the complete planner in it.

**The model.** Robot A at offset ``s`` on a straight piece of the drawing (:class:`mpa.footprint.Drawing`) stands at
``p(s) = p0 + s·u`` (affine), robot B at ``q(t)`` likewise; each body is its footprint oriented along its piece. The
bodies overlap iff ``q(t) - p(s)`` lies in the interior of ``Q = K_A ⊕ (−K_B)`` (the Minkowski difference of the
placed bodies: a convex polygon, an octagon at most for two rectangles). The preimage of a convex set under the
affine map ``(s, t) ↦ q(t) − p(s)`` is convex: in each *sub-cell* (a piece of A's edge × a piece of B's edge) the
*obstacle* ``O`` is a convex polygon given by at most ``|Q|`` half-planes (a strip when the pieces are parallel, e.g.
``|s − t| < (L_A + L_B)/2`` on one straight piece). Discs use the polygon of :data:`mpa.footprint.DISC_SIDES` sides
circumscribed about the disc of the summed radius, one side normal to A's piece (exact across parallel tracks,
at most 0.48 % of the summed radius conservative elsewhere). Bodies that touch (distance 0, within 1e-9 m) count as
apart.

**Free pieces.** The free part of a sub-cell is the along-track free polygon of :mod:`mpa.freespace` (the clearance D
in graph distance, unchanged) minus the interior of ``O``: with ``O = {g_1 <= 0, ..., g_m <= 0}`` it is the union of
the closed convex pieces ``{g_k >= 0, g_j <= 0 for j < k}`` (cut along the obstacle's supporting lines).

**Corners.** A robot's body takes the orientation of the piece it is on. A configuration where a robot stands on a
corner (a polyline corner or a vertex) belongs to the sub-cells of every piece there; the planner moves from one to
the other only through configurations free in both (the two pieces touch there), so at the instant the body turns
it is clear of the other body in both orientations. The turn itself is instantaneous in this model: the gate
(:mod:`trajopt.planar_gate`) bounds the sweep of a real turn between rows.

**Gluing and completeness.** Two free pieces are adjacent when they share a point: inside one cell (they touch
along a cut, across a polyline corner, or at a point), or across a face (a robot on a vertex, the pieces of the
cells of two edges at that vertex meeting in an interval or a point of the other robot's offsets), or at a corner
(both robots on vertices). Path components are the connected components of this adjacency (union-find): two
configurations are joined by a motion in the model iff their pieces are in one component, and the planner then finds
one (**complete**; a shortest path through the pieces' shared points, straight inside each convex piece). The path
is not the optimum of the objective (it bends only at the pieces' shared points: the ends and middle of each shared
segment), but it is free by construction.
"""

from __future__ import annotations

import bisect
import heapq
import itertools
import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np
from numpy.typing import NDArray

from mpa.errors import InvalidInputError, NoMotionError, PlanningError
from mpa.footprint import Disc, Drawing, Footprint, Footprints, body_gap, drawing_of, footprints
from mpa.freespace import FreeSpace, _clip, _dedupe, _union_find, free_space
from mpa.graph_track import GraphTrack, Position, as_graph_track

__all__ = ["PlanarFreeSpace", "bodies_gap", "corner_sweep", "plan_planar", "planar_free_space", "start_refusal"]

FloatArray = NDArray[np.float64]
Coords = tuple[float, float]
TOUCH = 1e-9  # times max(1, total length): bodies this close count as apart
_EMPTY, _FULL = 0, 1


def _area(p: list[Coords]) -> float:
    n = len(p)
    if n < 3:
        return 0.0
    return 0.5 * sum(p[i][0] * p[(i + 1) % n][1] - p[(i + 1) % n][0] * p[i][1] for i in range(n))


def _halfplanes(poly: list[Coords], slack: float) -> list[tuple[float, float, float]]:
    """Half-planes ``a*s + b*t >= c`` of a counter-clockwise convex polygon, loosened by ``slack`` metres."""
    out = []
    n = len(poly)
    for i in range(n):
        (x0, y0), (x1, y1) = poly[i], poly[(i + 1) % n]
        a, b = -(y1 - y0), x1 - x0
        nrm = math.hypot(a, b)
        if nrm <= 0.0:
            continue
        out.append((a / nrm, b / nrm, (a * x0 + b * y0) / nrm - slack))
    return out


def _hull(pts: FloatArray) -> FloatArray:
    """Convex hull, counter-clockwise (monotone chain)."""
    p = sorted(map(tuple, np.round(pts, 15)))
    if len(p) <= 2:
        return np.array(p)

    def cross(o: Any, a: Any, b: Any) -> float:
        return float((a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]))

    lower: list[Any] = []
    for q in p:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], q) <= 0:
            lower.pop()
        lower.append(q)
    upper: list[Any] = []
    for q in reversed(p):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], q) <= 0:
            upper.pop()
        upper.append(q)
    return np.array(lower[:-1] + upper[:-1])


def _inside(poly: FloatArray, s: float, t: float, tol: float) -> bool:
    n = len(poly)
    if n == 1:
        return abs(poly[0, 0] - s) <= tol and abs(poly[0, 1] - t) <= tol
    if n == 2 or abs(_area([tuple(x) for x in poly])) <= tol * tol:
        # degenerate: distance to the segment hull
        best = math.inf
        for i in range(n):
            a, b = poly[i], poly[(i + 1) % n]
            ab = b - a
            den = float(ab @ ab)
            lam = 0.0 if den <= 0 else min(1.0, max(0.0, float((np.array([s, t]) - a) @ ab) / den))
            best = min(best, math.hypot(a[0] + lam * ab[0] - s, a[1] + lam * ab[1] - t))
        return best <= tol
    for a, b, c in _halfplanes([tuple(x) for x in poly], tol):
        if a * s + b * t < c:
            return False
    return True


def _meet(p: FloatArray, q: FloatArray, tol: float) -> list[Coords] | None:
    """Points of the intersection of two closed convex polygons (within ``tol``), None if they do not meet."""
    small, big = (p, q) if abs(_area([tuple(x) for x in p])) <= abs(_area([tuple(x) for x in q])) else (q, p)
    if len(big) >= 3 and abs(_area([tuple(x) for x in big])) > tol * tol:
        out: list[Coords] = [tuple(x) for x in small]
        for a, b, c in _halfplanes([tuple(x) for x in big], tol):
            out = _clip(out, a, b, c)
            if not out:
                return None
        return out
    # both degenerate: a vertex of one close to the other
    for v in small:
        if _inside(big, float(v[0]), float(v[1]), tol):
            return [(float(v[0]), float(v[1]))]
    for v in big:
        if _inside(small, float(v[0]), float(v[1]), tol):
            return [(float(v[0]), float(v[1]))]
    return None


@dataclass(frozen=True)
class _Piece:
    cell: tuple[int, int, int]  # (edge A, edge B, along-track piece k)
    sub: tuple[int, int]  # (drawing piece of A, drawing piece of B)
    poly: FloatArray  # (n, 2) offsets (s, t), counter-clockwise


class PlanarFreeSpace:
    """Free configuration space of two robots with footprints in the plane and the along-track clearance D.

    Parameters
    ----------
    track : GraphTrack or paper track or layout
        Needs coordinates for every vertex (the drawing, :class:`mpa.footprint.Drawing`).
    clearance : float
        D (metres, >= 0), the along-track clearance as in :class:`mpa.freespace.FreeSpace`.
    footprint : Footprints or anything :func:`mpa.footprint.footprints` accepts

    Attributes
    ----------
    base : FreeSpace
        The along-track free space.
    pieces : list
        Closed convex free pieces (cell, sub-cell, polygon in offsets).
    component : ndarray of int, shape (len(pieces),)
        Path component of each piece.
    n_components : int
    """

    def __init__(self, track: object, clearance: float, footprint: object) -> None:
        fps = footprints(footprint)
        if fps is None:
            raise InvalidInputError("footprint is None, expected a footprint for the planar free space")
        self.track: GraphTrack = as_graph_track(track)
        self.footprints = fps
        self.drawing = drawing_of(self.track)
        self.base: FreeSpace = free_space(self.track, clearance)
        self.clearance = self.base.clearance
        self.tol = TOUCH * max(1.0, self.track.total_length)
        self._build()
        self._glue()

    # ------------------------------------------------------------------------------------------ build
    def _obstacle(self, pa: int, pb: int) -> list[tuple[float, float, float]] | None:
        """Half-planes ``a*s + b*t <= c`` whose intersection is the open obstacle of sub-cell (pa, pb), or None."""
        d = self.drawing
        fa, fb = self.footprints.a, self.footprints.b
        ha, hb = float(d.piece_heading[pa]), float(d.piece_heading[pb])
        ca, sa = math.cos(ha), math.sin(ha)
        cb, sb = math.cos(hb), math.sin(hb)
        ka = fa.corners() @ np.array([[ca, sa], [-sa, ca]])
        kb = fb.corners() @ np.array([[cb, sb], [-sb, cb]])
        if isinstance(fa, Disc) and isinstance(fb, Disc):
            r = fa.radius + fb.radius
            q = Disc(r).corners() @ np.array([[ca, sa], [-sa, ca]])
        else:
            q = _hull((ka[:, None, :] - kb[None, :, :]).reshape(-1, 2))
        # overlap iff q(t) - p(s) ∈ int Q; q(t) - p(s) = d0 + t*ub - s*ua
        ua, ub = d.piece_dir[pa], d.piece_dir[pb]
        d0 = (d.piece_p0[pb] - d.piece_s0[pb] * ub) - (d.piece_p0[pa] - d.piece_s0[pa] * ua)
        out = []
        for a_, b_, c_ in _halfplanes([tuple(x) for x in q], 0.0):
            # Q: a_*x + b_*y >= c_ (inside); written as n·x <= h with n = -(a_, b_), h = -c_
            nx, ny, h = -a_, -b_, -c_
            cs = -(nx * ua[0] + ny * ua[1])
            ct = nx * ub[0] + ny * ub[1]
            rhs = h - (nx * d0[0] + ny * d0[1]) - self.tol
            out.append((cs, ct, rhs))
        return out

    def _turns(self, p: int, q: int) -> bool:
        """Whether a body passing from drawing piece ``p`` to ``q`` turns (orientation modulo pi; remembered)."""
        memo: dict[tuple[int, int], bool] = self.__dict__.setdefault("_turn_memo", {})
        key = (p, q)
        out = memo.get(key)
        if out is None:
            d = self.drawing
            x = abs(float(d.piece_heading[p] - d.piece_heading[q])) % math.pi
            out = memo[key] = min(x, math.pi - x) > 1e-12
        return out

    def _reach_halfplanes(self, ax: int, pb: int) -> list[tuple[float, float, float]]:
        """Half-planes ``a*x + b*y >= c`` of ``K = B ⊕ disc(reach)``: the other robot's body on piece ``pb`` (at
        the origin) grown by the reach of robot ``ax`` (cached per ``(ax, pb)``: it does not depend on where the
        turning robot stands)."""
        memo: dict[tuple[int, int], list[tuple[float, float, float]]] = self.__dict__.setdefault("_reach_hp", {})
        key = (ax, pb)
        hp = memo.get(key)
        if hp is None:
            fp = self.footprints.a if ax == 0 else self.footprints.b
            other = self.footprints.b if ax == 0 else self.footprints.a
            hb = float(self.drawing.piece_heading[pb])
            cb, sb = math.cos(hb), math.sin(hb)
            kb = other.corners() @ np.array([[cb, sb], [-sb, cb]])
            disc = Disc(fp.reach).corners()
            k = _hull((kb[:, None, :] + disc[None, :, :]).reshape(-1, 2))
            hp = memo[key] = _halfplanes([tuple(x) for x in k], 0.0)
        return hp

    def _turn_block(self, ax: int, turner: int, side: float, pb: int) -> tuple[float, float] | None:
        """Open interval of the other robot's offsets on piece ``pb`` where its body comes closer than the reach of
        robot ``ax`` to that robot's centre at offset ``side`` of piece ``turner`` (a turning body's sweep lies in
        that disc), None if it never does (cached per arguments)."""
        memo: dict[tuple[int, int, float, int], tuple[float, float] | None] = self.__dict__.setdefault("_blocks", {})
        key = (ax, turner, side, pb)
        if key in memo:
            return memo[key]
        d = self.drawing
        centre = d.piece_p0[turner] + (side - d.piece_s0[turner]) * d.piece_dir[turner]
        # overlap iff centre - q(t) in int K; q(t) = q0 + t*u
        u = d.piece_dir[pb]
        q0 = d.piece_p0[pb] - d.piece_s0[pb] * u
        lo, hi = -math.inf, math.inf
        out: tuple[float, float] | None = None
        for a_, b_, c_ in self._reach_halfplanes(ax, pb):
            # a·(centre - q0 - t u) > c + tol
            alpha = -(a_ * u[0] + b_ * u[1])
            beta = a_ * (centre[0] - q0[0]) + b_ * (centre[1] - q0[1]) - c_ - self.tol
            if abs(alpha) <= 1e-15:
                if beta <= 0.0:
                    break
                continue
            r = -beta / alpha
            if alpha > 0:
                lo = max(lo, r)
            else:
                hi = min(hi, r)
        else:
            out = (lo, hi) if lo < hi else None
        memo[key] = out
        return out

    def _turn_filter(self, ax: int, side: float, turner_piece: int, other_piece: int, ys: list[float]) -> list[float]:
        """The portal values ``ys`` (the other robot's offsets) kept where the turning robot's sweep is clear."""
        fp = self.footprints.a if ax == 0 else self.footprints.b
        if isinstance(fp, Disc):
            return ys
        blk = self._turn_block(ax, turner_piece, side, other_piece)
        if blk is None or not ys:
            return ys
        y0, y1 = min(ys), max(ys)
        parts = [(y0, min(y1, blk[0])), (max(y0, blk[1]), y1)]
        out: list[float] = []
        for a0, a1 in parts:
            if a1 >= a0:
                out.extend(_portal_values(a0, a1))
        return out

    def _near_pairs(self) -> NDArray[np.bool_]:
        d = self.drawing
        e0 = d.piece_p0
        e1 = d.piece_p0 + (d.piece_s1 - d.piece_s0)[:, None] * d.piece_dir
        lo = np.minimum(e0, e1)
        hi = np.maximum(e0, e1)
        reach = self.footprints.a.reach + self.footprints.b.reach + 1e-6
        gap_x = np.maximum(lo[:, None, 0] - hi[None, :, 0], lo[None, :, 0] - hi[:, None, 0])
        gap_y = np.maximum(lo[:, None, 1] - hi[None, :, 1], lo[None, :, 1] - hi[:, None, 1])
        return (gap_x < reach) & (gap_y < reach)

    def _build(self) -> None:
        base = self.base
        d = self.drawing
        near = self._near_pairs()
        pieces: list[_Piece] = []
        eps = 1e-12 * max(1.0, float(self.track.lengths.max()))
        ps0, ps1 = d.piece_s0.tolist(), d.piece_s1.tolist()
        for pid in base.polygon_ids:
            e, f, k = pid
            bpoly: list[Coords] = [tuple(x) for x in base.vertices(pid).tolist()]
            bs = [x[0] for x in bpoly]
            lo_s, hi_s = min(bs), max(bs)
            for pa in d.edge_pieces[e]:
                s0, s1 = ps0[pa], ps1[pa]
                # the clip to the drawing piece, skipped where it keeps or drops every vertex (the same result)
                if hi_s < s0 or lo_s > s1:
                    continue
                ra = bpoly if s0 <= lo_s and hi_s <= s1 else _clip(_clip(bpoly, 1.0, 0.0, s0), -1.0, 0.0, -s1)
                if not ra:
                    continue
                ts = [x[1] for x in ra]
                lo_t, hi_t = min(ts), max(ts)
                for pb in d.edge_pieces[f]:
                    t0, t1 = ps0[pb], ps1[pb]
                    if hi_t < t0 or lo_t > t1:
                        continue
                    rb = ra if t0 <= lo_t and hi_t <= t1 else _clip(_clip(ra, 0.0, 1.0, t0), 0.0, -1.0, -t1)
                    r = _dedupe(rb, eps)
                    if not r:
                        continue
                    cell = (e, f, k)
                    sub = (int(pa), int(pb))
                    if not near[pa, pb]:
                        pieces.append(_Piece(cell, sub, np.asarray(r, dtype=float)))
                        continue
                    hp = self._obstacle(int(pa), int(pb)) or []
                    ha = np.array([h[0] for h in hp], dtype=float)
                    hb = np.array([h[1] for h in hp], dtype=float)
                    hc = np.array([h[2] for h in hp], dtype=float)
                    inner = r
                    for a_, b_, c_ in hp:
                        inner = _clip(inner, -a_, -b_, -c_)
                        if not inner:
                            break
                    degenerate = abs(_area(r)) <= eps * eps
                    if not inner or (not degenerate and (_area(inner) <= eps * eps or len(_dedupe(inner, eps)) < 3)):
                        pieces.append(_Piece(cell, sub, np.asarray(r, dtype=float)))
                        continue
                    rv = np.asarray(r, dtype=float)
                    fr = ha[:, None] * rv[None, :, 0] + hb[:, None] * rv[None, :, 1] - hc[:, None]
                    keeps_all, keeps_none = np.all(fr >= 0.0, axis=1), np.all(fr < 0.0, axis=1)
                    for i, (a_, b_, c_) in enumerate(hp):
                        if abs(a_) + abs(b_) <= 1e-15 or keeps_none[i]:
                            continue  # (outside no vertex of r: the clip is empty)
                        q = r if keeps_all[i] else _clip(r, a_, b_, c_)
                        for a2, b2, c2 in hp[:i]:
                            if not q:
                                break
                            q = _clip(q, -a2, -b2, -c2)
                        q = _dedupe(q, eps)
                        if q:
                            pieces.append(_Piece(cell, sub, np.asarray(q, dtype=float)))
        self.pieces = pieces

    def _glue(self) -> None:
        tr = self.track
        tol = 10.0 * self.tol
        n = len(self.pieces)
        self.adjacent: list[list[tuple[int, list[Coords], list[Coords]]]] = [[] for _ in range(n)]
        joined: tuple[list[int], list[int]] = ([], [])  # the linked pairs, for the components

        cell2 = [p.cell[:2] for p in self.pieces]

        self._box(0) if n else None  # the sub-cells' boxes, built once
        boxes = self.__dict__.get("_boxes", [])

        def link(i: int, j: int, pi: list[Coords], pj: list[Coords]) -> None:
            # the shared points clamped into their boxes (:meth:`_clamp_box`, inlined)
            s0, s1, t0, t1 = boxes[i]
            same = cell2[i] == cell2[j]
            if same:
                u0, u1, v0, v1 = boxes[j]
                s0, s1, t0, t1 = max(s0, u0), min(s1, u1), max(t0, v0), min(t1, v1)
                if s0 > s1:
                    s0 = s1 = 0.5 * (s0 + s1)
                if t0 > t1:
                    t0 = t1 = 0.5 * (t0 + t1)
            pi = [(min(max(c[0], s0), s1), min(max(c[1], t0), t1)) for c in pi]
            if same:
                pj = pi
            else:
                s0, s1, t0, t1 = boxes[j]
                pj = [(min(max(c[0], s0), s1), min(max(c[1], t0), t1)) for c in pj]
            self.adjacent[i].append((j, pi, pj))
            self.adjacent[j].append((i, pj, pi))
            joined[0].append(i)
            joined[1].append(j)

        lo = np.array([p.poly.min(axis=0) for p in self.pieces]).reshape(-1, 2)
        hi = np.array([p.poly.max(axis=0) for p in self.pieces]).reshape(-1, 2)
        by_cell: dict[tuple[int, int], list[int]] = {}
        for i, p in enumerate(self.pieces):
            by_cell.setdefault((p.cell[0], p.cell[1]), []).append(i)
        for idx in by_cell.values():
            if len(idx) < 2:
                continue
            ix = np.array(idx)
            l_, h_ = lo[ix], hi[ix]
            ok = np.all(l_[:, None, :] <= h_[None, :, :] + tol, axis=-1) & np.all(
                l_[None, :, :] <= h_[:, None, :] + tol, axis=-1
            )
            for x, y in zip(*np.nonzero(np.triu(ok, 1))):
                i, j = idx[int(x)], idx[int(y)]
                m = self._meet(i, j, tol)
                if m:
                    pts = self._turn_points(i, j, _portal_points(m))
                    if pts:
                        link(i, j, pts, pts)
        # faces: a robot on a vertex; key (axis, vertex, other edge) -> (piece, side value, lo, hi)
        faces: dict[tuple[Any, ...], list[tuple[int, float, float, float]]] = {}
        lengths = tr.lengths
        ls, tails, heads = lengths.tolist(), tr.tails.tolist(), tr.heads.tolist()
        # every piece's vertices at once: owner piece, and per (axis, end of the edge) which pieces have vertices
        # on that side and the range of the other robot's offsets there
        verts = np.concatenate([p.poly for p in self.pieces]) if n else np.zeros((0, 2))
        owner = np.repeat(np.arange(n), [len(p.poly) for p in self.pieces])
        cells = np.array(cell2, dtype=np.int64).reshape(-1, 2)
        near_end: dict[tuple[int, int], NDArray[np.bool_]] = {}
        ext: dict[tuple[int, int], tuple[list[bool], list[float], list[float]]] = {}
        for ax in (0, 1):
            far = lengths[cells[owner, ax]]
            for end in (0, 1):
                on = np.abs(verts[:, ax] - (far if end else 0.0)) <= tol
                near_end[ax, end] = on
                lo_y, hi_y = np.full(n, math.inf), np.full(n, -math.inf)
                np.minimum.at(lo_y, owner[on], verts[on, 1 - ax])
                np.maximum.at(hi_y, owner[on], verts[on, 1 - ax])
                has = np.bincount(owner[on], minlength=n) > 0
                ext[ax, end] = (has.tolist(), lo_y.tolist(), hi_y.tolist())
        for i in range(n):
            e, f = cell2[i]
            for ax, edge, other in ((0, e, f), (1, f, e)):
                for end in (0, 1):
                    has_l, lo_l, hi_l = ext[ax, end]
                    if not has_l[i]:
                        continue
                    side, w = (ls[edge], heads[edge]) if end else (0.0, tails[edge])
                    faces.setdefault((ax, w, other), []).append((i, side, lo_l[i], hi_l[i]))
        for (ax, _, _), items in faces.items():
            items.sort(key=lambda x: x[2])
            for x, (i, si, li, hi_) in enumerate(items):
                for j, sj, lj, hj in items[x + 1 :]:
                    if lj > hi_ + tol:
                        break
                    if self.pieces[i].cell[:2] == self.pieces[j].cell[:2] and si == sj:
                        continue  # same cell, same side: glued inside the cell already
                    a0, a1 = max(li, lj), min(hi_, hj)
                    if a0 > a1:
                        a0 = a1 = 0.5 * (a0 + a1)
                    ys = _portal_values(a0, a1)
                    sub_i, sub_j = self.pieces[i].sub, self.pieces[j].sub
                    if self._turns(sub_i[ax], sub_j[ax]):
                        ys = self._turn_filter(ax, si, sub_i[ax], sub_i[1 - ax], ys)
                        if ys and sub_i[1 - ax] != sub_j[1 - ax]:
                            ys = self._turn_filter(ax, sj, sub_j[ax], sub_j[1 - ax], ys)
                    if not ys:
                        continue
                    pi = [(si, y) if ax == 0 else (y, si) for y in ys]
                    pj = [(sj, y) if ax == 0 else (y, sj) for y in ys]
                    link(i, j, pi, pj)
        # corners: both robots on vertices
        corners: dict[tuple[int, int], list[tuple[int, Coords]]] = {}
        at_corner = {
            (ea, eb): (np.bincount(owner[near_end[0, ea] & near_end[1, eb]], minlength=n) > 0).tolist()
            for ea in (0, 1)
            for eb in (0, 1)
        }
        for i in range(n):
            e, f = cell2[i]
            for ea, (sa, wa) in enumerate(((0.0, tails[e]), (ls[e], heads[e]))):
                for eb, (sb, wb) in enumerate(((0.0, tails[f]), (ls[f], heads[f]))):
                    if at_corner[ea, eb][i]:
                        corners.setdefault((wa, wb), []).append((i, (sa, sb)))
        for citems in corners.values():
            for x, (i, ci) in enumerate(citems):
                for j, cj in citems[x + 1 :]:
                    if self.pieces[i].cell[:2] != self.pieces[j].cell[:2] and self._corner_clear(i, j, ci):
                        link(i, j, [ci], [cj])
        roots = _union_find(n, *joined)
        labels: dict[int, int] = {}
        self.component = np.array([labels.setdefault(r, len(labels)) for r in roots], dtype=np.int64)
        self.n_components = len(labels)

    def _meet(self, i: int, j: int, tol: float) -> list[Coords] | None:
        """:func:`_meet` of pieces ``i`` and ``j``, with each piece's area and half-planes computed once."""
        cache = self.__dict__.setdefault("_meet_cache", {})
        data = []
        for k in (i, j):
            c = cache.get(k)
            if c is None:
                pts = [tuple(x) for x in self.pieces[k].poly]
                c = cache[k] = (pts, abs(_area(pts)), None)
            data.append(c)
        ai, aj = data[0][1], data[1][1]
        small, big = (i, j) if ai <= aj else (j, i)
        pts_b, area_b, hp_b = cache[big]
        if len(pts_b) >= 3 and area_b > tol * tol:
            if hp_b is None:
                hp_b = _halfplanes(pts_b, tol)
                cache[big] = (pts_b, area_b, hp_b)
            out: list[Coords] = cache[small][0]
            for a, b, c_ in hp_b:
                out = _clip(out, a, b, c_)
                if not out:
                    return None
            return out
        return _meet(self.pieces[i].poly, self.pieces[j].poly, tol)

    def _box(self, i: int) -> tuple[float, float, float, float]:
        """The sub-cell of piece ``i``: ``(s0, s1, t0, t1)`` offsets (metres) of its two drawing pieces."""
        boxes = self.__dict__.get("_boxes")
        if boxes is None:
            d = self.drawing
            s0, s1 = d.piece_s0.tolist(), d.piece_s1.tolist()
            boxes = self._boxes = [(s0[a], s1[a], s0[b], s1[b]) for a, b in (p.sub for p in self.pieces)]
        return boxes[i]

    def _clamp_box(self, i: int, j: int) -> tuple[float, float, float, float]:
        """The box ``(s0, s1, t0, t1)`` a shared point of pieces ``i`` and ``j`` is moved into, exactly: piece
        ``i``'s sub-cell (and ``j``'s, in the same cell), so that no point of a path lies on another drawing piece
        than the one its sub-cell says (tolerances never flip an orientation)."""
        s0, s1, t0, t1 = self._box(i)
        if self.pieces[i].cell[:2] == self.pieces[j].cell[:2]:
            u0, u1, v0, v1 = self._box(j)
            s0, s1, t0, t1 = max(s0, u0), min(s1, u1), max(t0, v0), min(t1, v1)
            if s0 > s1:
                s0 = s1 = 0.5 * (s0 + s1)
            if t0 > t1:
                t0 = t1 = 0.5 * (t0 + t1)
        return s0, s1, t0, t1

    def _corner_offsets(self) -> list[dict[float, float]]:
        """Per edge: offsets where a body turns (polyline corners, ends at a vertex with several orientations)."""
        co = getattr(self, "_co", None)
        if co is None:
            d = self.drawing
            tr = self.track
            co = []
            for e in range(tr.n_edges):
                out: dict[float, float] = {}
                pcs = d.edge_pieces[e]
                for p, q in itertools.pairwise(pcs):
                    if self._turns(int(p), int(q)):
                        out[float(d.piece_s1[p])] = 1.0
                for off in (0.0, float(tr.lengths[e])):
                    hs = d.corner_headings(e, off)
                    if any(self._turns_h(hs[0], h) for h in hs[1:]):
                        out[off] = 1.0
                co.append(out)
            self._co = co
        return co

    @staticmethod
    def _turns_h(h1: float, h2: float) -> bool:
        x = abs(h1 - h2) % math.pi
        return min(x, math.pi - x) > 1e-12

    def still_on_corner(self, i: int, c0: Coords, c1: Coords) -> list[tuple[int, float]]:
        """The robots (axis ``0`` A, ``1`` B) that a straight move ``c0 -> c1`` in piece ``i`` keeps on a corner of
        the drawing where the body turns, with that corner's offset: both ends within ``10 * tol`` of it (shared
        points computed two ways may differ in the last digits)."""
        e, f, _ = self.pieces[i].cell
        co = self._corner_lists()
        tol = 10.0 * self.tol
        out = []
        for ax, edge in ((0, e), (1, f)):
            x = c0[ax]
            if abs(c1[ax] - x) > tol:
                continue
            arr = co[edge]
            k = bisect.bisect_left(arr, x)
            for j in (k - 1, k):
                if 0 <= j < len(arr) and abs(arr[j] - x) <= tol and abs(arr[j] - c1[ax]) <= tol:
                    out.append((ax, arr[j]))
                    break
        return out

    def _corner_lists(self) -> list[list[float]]:
        """Per edge the sorted offsets of :meth:`_corner_offsets`."""
        ca = self.__dict__.get("_ca")
        if ca is None:
            ca = self._ca = [sorted(d) for d in self._corner_offsets()]
        return ca

    def segment_ok(self, i: int, c0: Coords, c1: Coords) -> bool:
        """Whether a straight move inside piece ``i`` is clear also where a robot stands still on a corner: there
        it may have either orientation, so its reach disc must stay clear of the other body (memoised)."""
        memo: dict[tuple[int, Coords, Coords], bool] = self.__dict__.setdefault("_seg_ok", {})
        key = (i, c0, c1)
        ok = memo.get(key)
        if ok is None:
            ok = memo[key] = self._segment_ok(i, c0, c1)
        return ok

    def _segment_ok(self, i: int, c0: Coords, c1: Coords) -> bool:
        sub = self.pieces[i].sub
        for ax, corner in self.still_on_corner(i, c0, c1):
            fp = self.footprints.a if ax == 0 else self.footprints.b
            if isinstance(fp, Disc):
                continue
            blk = self._turn_block(ax, sub[ax], corner, sub[1 - ax])
            if blk is None:
                continue
            y0, y1 = sorted((c0[1 - ax], c1[1 - ax]))
            if y1 > blk[0] and y0 < blk[1]:
                return False
        return True

    def _turn_points(self, i: int, j: int, pts: list[Coords]) -> list[Coords]:
        """Shared points of two pieces of one cell, kept where a robot that turns between them sweeps clear."""
        si, sj = self.pieces[i].sub, self.pieces[j].sub
        out = pts
        for ax in (0, 1):
            if si[ax] != sj[ax] and self._turns(si[ax], sj[ax]):
                if si[1 - ax] != sj[1 - ax] and self._turns(si[1 - ax], sj[1 - ax]):
                    return [c for c in out if self._corner_clear(i, j, c)]
                side = out[0][ax] if out else 0.0
                ys = self._turn_filter(ax, side, si[ax], si[1 - ax], [c[1 - ax] for c in out])
                out = [(side, y) if ax == 0 else (y, side) for y in ys]
        return out

    def _corner_clear(self, i: int, j: int, c: Coords) -> bool:
        """Both robots on corners: the discs of their reach (a turning body's sweep) apart, where they turn."""
        si, sj = self.pieces[i].sub, self.pieces[j].sub
        fa, fb = self.footprints.a, self.footprints.b
        ta = self._turns(si[0], sj[0]) and not isinstance(fa, Disc)
        tb = self._turns(si[1], sj[1]) and not isinstance(fb, Disc)
        if not (ta or tb):
            return True
        d = self.drawing
        pa = d.piece_p0[si[0]] + (c[0] - d.piece_s0[si[0]]) * d.piece_dir[si[0]]
        pb = d.piece_p0[si[1]] + (c[1] - d.piece_s0[si[1]]) * d.piece_dir[si[1]]
        return float(np.hypot(*(pa - pb))) >= fa.reach + fb.reach - self.tol

    # ---------------------------------------------------------------------------------------- queries
    def moves(self) -> list[list[tuple[Coords, tuple[int, Coords]]]]:
        """Per piece its shared points with the glued pieces, flattened: ``(point in this piece, (neighbour, the
        point in the neighbour's offsets))`` in the order of :attr:`adjacent` (built once; a repeated move relaxes
        nothing the first one did not and is kept once)."""
        mv = self.__dict__.get("_moves")
        if mv is None:
            mv = self._moves = [
                list(dict.fromkeys((pi, (j, pj)) for j, pts_i, pts_j in row for pi, pj in zip(pts_i, pts_j)))
                for row in self.adjacent
            ]
        return mv

    def search_graph(self, objective: str, spa: list[float], spb: list[float]) -> _Moves:
        """The moves between shared points as a sparse graph (:class:`_Moves`), built once per objective and the
        robots' speeds per edge (m/s)."""
        memo: dict[tuple[Any, ...], _Moves] = self.__dict__.setdefault("_graphs", {})
        key = (objective, tuple(spa), tuple(spb))
        g = memo.get(key)
        if g is None:
            g = memo[key] = _Moves(self, objective, spa, spb)
        return g

    def detour(self, i: int, c0: Coords, c1: Coords) -> Coords | None:
        """A point of piece ``i`` off the corner line of a move ``c0 -> c1`` that keeps one robot still on a corner
        where :meth:`segment_ok` refuses it (the other body passes its turning disc).

        The piece is convex and the corner line is one of its sides (the sub-cell's edge), so the point
        ``w = m + λ (z - m)`` between the move's middle ``m`` and the mean ``z`` of the piece's vertices lies in the
        piece, off that line for ``λ > 0``: ``c0 -> w -> c1`` moves the robot a little into its piece and back, its
        body at the piece's orientation, and it stands on the corner only at ``c0`` and ``c1``. ``λ = 1/2``, smaller
        where the other robot's edge is one-way (its offset then stays between the ends). None when the piece has
        no interior, the still robot's edge is one-way (it could not come back) or either move is refused too.
        """
        still = self.still_on_corner(i, c0, c1)
        if len(still) != 1:  # both still: no move; none: nothing to go round
            return None
        ax = still[0][0]
        poly = self.pieces[i].poly
        tol = 10.0 * self.tol
        if len(poly) < 3 or abs(_area([tuple(x) for x in poly])) <= tol * tol:
            return None
        edges = self.pieces[i].cell[:2]
        if self.track.oneway[edges[ax]]:
            return None
        z = poly.mean(axis=0)
        m = (0.5 * (c0[0] + c1[0]), 0.5 * (c0[1] + c1[1]))
        lam = 0.5
        o = 1 - ax
        dz = abs(float(z[o]) - m[o])
        if self.track.oneway[edges[o]] and dz > 0.0:
            lam = min(lam, 0.25 * abs(c1[o] - c0[o]) / dz)
        w = (m[0] + lam * (float(z[0]) - m[0]), m[1] + lam * (float(z[1]) - m[1]))
        if self.still_on_corner(i, c0, w) or not (self.segment_ok(i, c0, w) and self.segment_ok(i, w, c1)):
            return None
        return w

    def names(self, pos: Position) -> list[Position]:
        """All ``(edge, offset)`` names of a position (several on a vertex)."""
        tr = self.track
        e, s = pos
        w = tr.vertex_at(e, s)
        if w is None:
            return [pos]
        out = []
        for f in range(tr.n_edges):
            if tr.tails[f] == w:
                out.append((f, 0.0))
            if tr.heads[f] == w:
                out.append((f, float(tr.lengths[f])))
        return out

    def placements(self, pa: Position, pb: Position) -> list[tuple[int, Coords]]:
        """The free pieces holding the configuration, with its offsets in each (empty if it is not free; the last
        few configurations asked remembered: a query asks for its start and goal several times)."""
        memo: dict[tuple[Position, Position], list[tuple[int, Coords]]] = self.__dict__.setdefault("_placed", {})
        key = ((int(pa[0]), float(pa[1])), (int(pb[0]), float(pb[1])))
        out = memo.get(key)
        if out is None:
            out = []
            for ea, sa in self.names(pa):
                for eb, sb in self.names(pb):
                    for i in self._inside_cell((ea, eb), sa, sb):
                        out.append((i, (sa, sb)))
            if len(memo) >= 64:
                memo.clear()
            memo[key] = out
        return list(out)

    def _inside_cell(self, cell: tuple[int, int], s: float, t: float) -> list[int]:
        """The pieces of ``cell`` (in :meth:`_by_cell` order) holding ``(s, t)``: :func:`_inside` with tolerance
        ``10 * tol``, the half-planes of every piece of the cell tested at once (the same expression)."""
        memo = self.__dict__.setdefault("_cell_tests", {})
        tol = 10.0 * self.tol
        data = memo.get(cell)
        if data is None:
            idx = self._by_cell().get(cell, [])
            rows: list[tuple[float, float, float]] = []
            owner: list[int] = []
            degenerate = []
            for k, i in enumerate(idx):
                poly = self.pieces[i].poly
                pts = [tuple(x) for x in poly]
                if len(poly) <= 2 or abs(_area(pts)) <= tol * tol:
                    degenerate.append(k)
                    continue
                hp = _halfplanes(pts, tol)
                rows.extend(hp)
                owner.extend([k] * len(hp))
            arr = np.array(rows, dtype=float).reshape(-1, 3)
            data = memo[cell] = (idx, arr[:, 0], arr[:, 1], arr[:, 2], np.array(owner, dtype=np.int64), degenerate)
        idx, a, b, c, own, degenerate = data
        if not idx:
            return []
        outside = np.bincount(own[a * s + b * t < c], minlength=len(idx)) > 0
        for k in degenerate:
            outside[k] = not _inside(self.pieces[idx[k]].poly, s, t, tol)
        return [idx[k] for k in np.flatnonzero(~outside).tolist()]

    def cells(self) -> list[tuple[int, int]]:
        """Per piece its cell's two edges ``(edge of A, edge of B)`` (built once)."""
        cl = self.__dict__.get("_cells")
        if cl is None:
            cl = self._cells = [(p.cell[0], p.cell[1]) for p in self.pieces]
        return cl

    def _by_cell(self) -> dict[tuple[int, int], list[int]]:
        bc = getattr(self, "_bc", None)
        if bc is None:
            bc = {}
            for i, p in enumerate(self.pieces):
                bc.setdefault((p.cell[0], p.cell[1]), []).append(i)
            self._bc = bc
        return bc

    def component_of(self, pos_a: object, pos_b: object) -> int | None:
        """Path component of a configuration (None if the bodies overlap or the robots are closer than D)."""
        a = self.track.position(pos_a, "position of robot A")
        b = self.track.position(pos_b, "position of robot B")
        pl = self.placements(a, b)
        return None if not pl else int(self.component[pl[0][0]])

    def is_free(self, pos_a: Position, pos_b: Position) -> bool:
        """Whether the configuration is free in the planar model: the robots keep the clearance along the track and
        it lies in a free piece (the bodies apart in the plane, every orientation at a corner)."""
        if not self.base.is_free(pos_a, pos_b):
            return False
        return not start_refusal(self.track, self, "", pos_a, pos_b)

    def can_swap(self, pos_a: object | None = None, pos_b: object | None = None) -> bool:
        """Whether the robots can exchange places (two positions: these; none: some free configuration)."""
        if pos_a is None and pos_b is None:
            for i, p in enumerate(self.pieces):
                e, f, _ = p.cell
                s, t = p.poly.mean(axis=0)
                other = self.placements((f, float(t)), (e, float(s)))
                if any(self.component[j] == self.component[i] for j, _ in other):
                    return True
            return False
        if pos_a is None or pos_b is None:
            raise InvalidInputError("can_swap takes two positions or none")
        a = self.track.position(pos_a, "position of robot A")
        b = self.track.position(pos_b, "position of robot B")
        c1 = self.component_of(a, b)
        why = start_refusal(self.track, self, "configuration", a, b) if c1 is not None else ""
        if c1 is None or why:
            raise InvalidInputError(
                why
                or f"configuration {pos_a!r}, {pos_b!r} has the bodies overlapping or the robots closer than the "
                f"clearance {self.clearance:g}"
            )
        if start_refusal(self.track, self, "configuration", b, a):
            return False
        return c1 == self.component_of(b, a)


def _portal_values(a0: float, a1: float) -> list[float]:
    if a1 - a0 <= 1e-12:
        return [0.5 * (a0 + a1)]
    return [a0, 0.5 * (a0 + a1), a1]


def _portal_points(m: list[Coords]) -> list[Coords]:
    """The shared points of a glued pair: its one point, or the two points of ``m`` farthest apart (the first such
    pair in row-major order: the ends of a shared segment) with their middle between them."""
    n = len(m)
    if n == 1:
        return [(float(m[0][0]), float(m[0][1]))]
    arr = np.asarray(m, dtype=float)
    dist = np.hypot(arr[:, None, 0] - arr[None, :, 0], arr[:, None, 1] - arr[None, :, 1])
    bi, bj = divmod(int(np.argmax(dist)), n)  # the first largest in row-major order
    a = (float(m[bi][0]), float(m[bi][1]))
    b = (float(m[bj][0]), float(m[bj][1]))
    # the exact middle of the two ends (not the mean of m, whose near-duplicate points move it off the middle):
    # the one-way search reads an end, middle, end triple as the whole segment (_parts)
    return [a, (0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])), b]


def bodies_gap(track: GraphTrack, fps: Footprints, pos_a: Position, pos_b: Position) -> float:
    """Smallest exact distance (metres) between the two bodies over every orientation they may have there
    (one inside a piece; every piece's at a corner or vertex)."""
    d = drawing_of(track)
    xy_a, _ = d.pose(pos_a[0], pos_a[1])
    xy_b, _ = d.pose(pos_b[0], pos_b[1])
    best = math.inf
    for ha in d.corner_headings(pos_a[0], pos_a[1]):
        for hb in d.corner_headings(pos_b[0], pos_b[1]):
            best = min(best, body_gap(fps.a, xy_a, ha, fps.b, xy_b, hb))
    return best


def _turning_at(d: Drawing, pos: Position, tol: float) -> list[float] | None:
    """The headings at a position where a body standing there turns (a corner or vertex whose pieces' orientations
    differ modulo pi, within ``tol`` metres), None elsewhere."""
    hs = d.corner_headings(pos[0], pos[1], tol)
    if any(PlanarFreeSpace._turns_h(hs[0], h) for h in hs[1:]):
        return hs
    return None


def _point_to_body(fp: Footprint, centre: FloatArray, point: FloatArray, heading: float) -> float:
    """Distance (metres) from ``point`` to a body centred at ``centre`` with ``heading`` (0 inside)."""
    dx, dy = float(point[0] - centre[0]), float(point[1] - centre[1])
    if isinstance(fp, Disc):
        return max(math.hypot(dx, dy) - fp.radius, 0.0)
    c, s = math.cos(heading), math.sin(heading)
    x = abs(c * dx + s * dy) - fp.half_length
    y = abs(-s * dx + c * dy) - fp.half_width
    return math.hypot(max(x, 0.0), max(y, 0.0))


def corner_sweep(
    track: GraphTrack, fps: Footprints, pos_a: Position, pos_b: Position, tol: float = 1e-9
) -> tuple[int, float]:
    """How far a rectangle standing on a corner sweeps into the other body (the model's rule for a body at rest
    on a corner).

    A rectangle on a corner or vertex where the drawing turns takes every orientation of the pieces there, and
    turning between them it sweeps the disc of its reach (half its diagonal) about the corner; the rule keeps that
    disc clear of the other body (in every orientation the other body may have; the other's disc too when it also
    turns there). Discs do not turn.

    Parameters
    ----------
    track : GraphTrack
        A layout with coordinates.
    fps : Footprints
    pos_a, pos_b : (int, float)
        The robots' positions ``(edge, offset)`` (metres).
    tol : float
        A position within ``tol`` metres of a corner stands on it (the gate's 1e-9 m; the planner's start and goal
        check uses ten times its touching tolerance, so that it is never more lenient than the gate).

    Returns
    -------
    (int, float)
        The robot (0 A, 1 B) whose sweep reaches deepest into the other body and the depth (metres; <= 0: clear,
        ``(-1, -inf)`` when neither robot turns where it stands).
    """
    d = drawing_of(track)
    pos = (pos_a, pos_b)
    body = (fps.a, fps.b)
    xy = [d.pose(p[0], p[1])[0] for p in pos]
    turning = [None if isinstance(body[r], Disc) else _turning_at(d, pos[r], tol) for r in (0, 1)]
    best: tuple[int, float] = (-1, -math.inf)
    for r in (0, 1):
        if turning[r] is None:
            continue
        o = 1 - r
        if turning[o] is not None:
            free = float(np.hypot(*(xy[r] - xy[o]))) - body[o].reach
        else:
            heads = d.corner_headings(pos[o][0], pos[o][1], tol)
            free = min(_point_to_body(body[o], xy[o], xy[r], h) for h in heads)
        depth = body[r].reach - free
        if depth > best[1]:
            best = (r, depth)
    return best


def start_refusal(track: GraphTrack, space: PlanarFreeSpace, what: str, pa: Position, pb: Position) -> str:
    """Why a start or goal (``what``) is not a configuration of the planar model ("" if it is): the bodies overlap
    in the plane in some orientation they may have there, or a rectangle on a corner sweeps into the other body
    (:func:`corner_sweep`). Robots closer than the clearance along the track are the caller's check."""
    names = (track.position_name(*pa), track.position_name(*pb))
    if not space.placements(pa, pb):
        gap = bodies_gap(track, space.footprints, pa, pb)
        closest = "they overlap" if gap <= 0.0 else f"{gap:.3g} m apart, inside the planner's disc polygon"
        return (
            f"{what} has the bodies ({space.footprints.spec()}) overlapping in the plane at robot A {names[0]}, "
            f"robot B {names[1]} ({closest} in some orientation they take there), expected them apart"
        )
    r, depth = corner_sweep(track, space.footprints, pa, pb, 10.0 * space.tol)
    if depth > space.tol:
        fp = space.footprints.a if r == 0 else space.footprints.b
        who, other = ("A", "B") if r == 0 else ("B", "A")
        return (
            f"{what} has robot {who} ({fp.spec()}) on a corner at {names[r]}, where its body takes every "
            f"orientation of the pieces there: the disc of its half-diagonal ({fp.reach:.3g} m) about that point "
            f"overlaps robot {other}'s body at {names[1 - r]} by {depth:.3g} m, expected it clear"
        )
    return ""


@lru_cache(maxsize=16)
def _cached(track: GraphTrack, clearance: float, fps: Footprints) -> PlanarFreeSpace:
    return PlanarFreeSpace(track, clearance, fps)


def planar_free_space(track: object, clearance: float, footprint: object) -> PlanarFreeSpace:
    """The :class:`PlanarFreeSpace` of ``(track, clearance, footprint)``, built once and cached."""
    fps = footprints(footprint)
    if fps is None:
        raise InvalidInputError("footprint is None, expected a footprint for the planar free space")
    tr = as_graph_track(track)
    if isinstance(clearance, bool) or not isinstance(clearance, (int, float, np.integer, np.floating)):
        raise InvalidInputError(f"clearance is {clearance!r}, expected a finite number >= 0 (metres)")
    return _cached(tr, float(clearance), fps)


# ------------------------------------------------------------------------------------------------ search
def _cell_speeds(tr: GraphTrack, va: float, vb: float) -> tuple[list[float], list[float]]:
    """Per edge the speed of robot A and of robot B on it (m/s): their limit capped by the edge's speed limit."""
    lim = [math.inf if v is None else float(v) for v in tr.speed_limits]
    return [min(va, x) for x in lim], [min(vb, x) for x in lim]


def _forward(tr: GraphTrack, cell: tuple[int, int, int], p: Coords, q: Coords) -> bool:
    """Whether the straight move ``p -> q`` in ``cell`` keeps the one-way rule (no robot backs along a one-way
    edge; standing still is allowed)."""
    return (not tr.oneway[cell[0]] or q[0] >= p[0]) and (not tr.oneway[cell[1]] or q[1] >= p[1])


def _move_cost(objective: str, ds: Any, dt: Any, va: Any, vb: Any) -> Any:
    """Cost of straight moves by ``ds``, ``dt`` metres (scalars or arrays): the length, or the time at speeds
    ``va``, ``vb`` with two tie-breaks (the summed and the Euclidean time, 1e-6 and 1e-9 of it)."""
    if objective == "shortest":
        return np.hypot(ds, dt) if isinstance(ds, np.ndarray) else math.hypot(ds, dt)
    ta, tb = ds / va, dt / vb
    if isinstance(ta, np.ndarray):
        return np.maximum(ta, tb) + 1e-6 * (ta + tb) + 1e-9 * np.hypot(ta, tb)
    return max(ta, tb) + 1e-6 * (ta + tb) + 1e-9 * math.hypot(ta, tb)


def _from_ends(tr: GraphTrack, pos: Position) -> tuple[FloatArray, FloatArray]:
    """Per edge the graph distance (metres) from its tail and from its head to the position ``pos``, shape
    ``(E,)`` each: a position ``(e, x)`` is ``min(x + tail[e], (L_e - x) + head[e])`` from it (and ``|x - offset|``
    on ``pos``'s own edge)."""
    geo = tr.geometry
    g, gs = pos
    back = float(geo.lengths[g]) - gs
    tg, hg = int(geo.tails[g]), int(geo.heads[g])
    dv = geo.dv
    tail = np.minimum(dv[geo.tails, tg] + gs, dv[geo.tails, hg] + back)
    head = np.minimum(dv[geo.heads, tg] + gs, dv[geo.heads, hg] + back)
    return tail, head


class _Moves:
    """The moves between the pieces' shared points as one sparse graph (built once per objective and speeds).

    A node is a piece with a shared point where a motion enters it (:meth:`PlanarFreeSpace.moves`: the point in
    that piece's offsets); its arcs are the straight moves inside the piece to each of its shared points, landing
    in the neighbour, at the move's cost (:func:`_move_cost`). Moves that back along a one-way edge are left out;
    a move that would keep a rectangle still on a corner while the other body passes its turning disc goes by
    :meth:`PlanarFreeSpace.detour` (or is left out when there is none). ``arc_to``, ``arc_via`` give each arc's end
    point in the piece's offsets and its detour point (NaN: straight).
    """

    SLOTS = 1024  # the most arcs the source may have (the start's moves in all its pieces)

    def __init__(self, space: PlanarFreeSpace, objective: str, spa: list[float], spb: list[float]) -> None:
        mv = space.moves()
        pieces = space.pieces
        node: dict[tuple[int, Coords], int] = {}
        for row in mv:
            for _, nk in row:
                if nk not in node:
                    node[nk] = len(node)
        n = len(node)
        self.n = n
        self.node_piece = np.array([k[0] for k in node], dtype=np.int64)
        self.node_xy = np.array([k[1] for k in node], dtype=float).reshape(-1, 2)
        # the moves flattened, grouped by piece
        counts = np.array([len(r) for r in mv], dtype=np.int64)
        m_start = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
        m_xy = np.array([pi for r in mv for pi, _ in r], dtype=float).reshape(-1, 2)
        m_to = np.array([node[nk] for r in mv for _, nk in r], dtype=np.int64)
        # arcs: every node times every move of its piece
        per = counts[self.node_piece]
        rows = np.repeat(np.arange(n, dtype=np.int64), per)
        first = np.repeat(np.cumsum(per) - per, per)
        mi = np.arange(int(per.sum()), dtype=np.int64) - first + np.repeat(m_start[self.node_piece], per)
        src = self.node_xy[rows]
        dst = m_xy[mi]
        cols = m_to[mi]
        piece = self.node_piece[rows]
        cells = np.array([p.cell[:2] for p in pieces], dtype=np.int64).reshape(-1, 2)
        ea, eb = cells[piece, 0], cells[piece, 1]
        va = np.asarray(spa, dtype=float)[ea]
        vb = np.asarray(spb, dtype=float)[eb]
        w = _move_cost(objective, np.abs(dst[:, 0] - src[:, 0]), np.abs(dst[:, 1] - src[:, 1]), va, vb)
        keep = np.ones(len(w), dtype=bool)
        ow = np.asarray(space.track.oneway, dtype=bool)
        if ow.any():
            keep &= (~ow[ea] | (dst[:, 0] >= src[:, 0])) & (~ow[eb] | (dst[:, 1] >= src[:, 1]))
        via = np.full((len(w), 2), np.nan)
        if not (isinstance(space.footprints.a, Disc) and isinstance(space.footprints.b, Disc)):
            near = 10.0 * space.tol
            still = keep & ((np.abs(dst[:, 0] - src[:, 0]) <= near) | (np.abs(dst[:, 1] - src[:, 1]) <= near))
            for k in np.flatnonzero(still).tolist():
                i, c0, c1 = int(piece[k]), (float(src[k, 0]), float(src[k, 1])), (float(dst[k, 0]), float(dst[k, 1]))
                if space.segment_ok(i, c0, c1):
                    continue
                wp = space.detour(i, c0, c1)
                if wp is None:
                    keep[k] = False
                    continue
                cell = pieces[i].cell
                w[k] = _move_cost(objective, abs(wp[0] - c0[0]), abs(wp[1] - c0[1]), spa[cell[0]], spb[cell[1]])
                w[k] += _move_cost(objective, abs(c1[0] - wp[0]), abs(c1[1] - wp[1]), spa[cell[0]], spb[cell[1]])
                via[k] = wp
        rows, cols, w, dst, via = rows[keep], cols[keep], w[keep], dst[keep], via[keep]
        # rows already in order; zero costs kept as arcs (the smallest positive float); two arcs between the same
        # nodes are both kept (the search takes the cheaper, and so does the path read back)
        self.indptr = np.concatenate([[0], np.cumsum(np.bincount(rows, minlength=n))]).astype(np.int32)
        self.indices = cols.astype(np.int32)
        self.weights = np.maximum(w, 5e-324)
        self.arc_to = dst
        self.arc_via = via
        self.widen(self.SLOTS)
        self.by_piece: dict[int, NDArray[np.int64]] = {}
        order_p = np.argsort(self.node_piece, kind="stable")
        bounds = np.searchsorted(self.node_piece[order_p], np.arange(len(pieces) + 1))
        for i in range(len(pieces)):
            if bounds[i + 1] > bounds[i]:
                self.by_piece[i] = order_p[bounds[i] : bounds[i + 1]]
        self.node_of = node
        self.node_edges = cells[self.node_piece].T.copy()  # (2, n): robot A's and robot B's edge at each node
        self.node_room = space.track.lengths[self.node_edges] - self.node_xy.T  # (2, n): metres to the edges' heads

    def lower(
        self, tr: GraphTrack, pos: tuple[Position, Position], speeds: tuple[float, float], objective: str
    ) -> FloatArray:
        """A lower bound of the cost between every node and the configuration ``pos``, shape ``(n,)``: the cost
        (:func:`_move_cost` at the robots' own limits ``speeds``, m/s) of the robots' graph distances to it, shrunk by
        1e-9 of itself (rounding). Every move costs at least the cost of what it changes the two distances (the
        cost is a monotone norm of the two travels, and the edges' speed limits only make a move dearer), so a path
        between a node and ``pos`` in either direction costs at least this."""
        d = []
        for r in (0, 1):
            g, gs = pos[r]
            from_tail, from_head = _from_ends(tr, pos[r])
            e, x = self.node_edges[r], self.node_xy[:, r]
            dr = np.minimum(x + from_tail[e], self.node_room[r] + from_head[e])
            same = e == g
            dr[same] = np.minimum(dr[same], np.abs(x[same] - gs))
            d.append(dr)
        return _move_cost(objective, d[0], d[1], speeds[0], speeds[1]) * (1.0 - 1e-9)

    LANDMARKS = 6  # nodes whose distances to and from every node bound the cost of a query (:meth:`landmarks`)

    def landmarks(self) -> tuple[FloatArray, FloatArray]:
        """Costs from and to a few *landmark* nodes (built once): ``(out, back)``, shape ``(LANDMARKS, n)`` each,
        ``out[l, u]`` the least cost from landmark ``l`` to node ``u``, ``back[l, u]`` from ``u`` to ``l`` (inf:
        not reached). Landmarks are picked farthest first (each the node farthest from those before it). By the
        triangle inequality a path from ``u`` to ``v`` costs at least ``out[l, v] - out[l, u]`` and
        ``back[l, u] - back[l, v]``: bounds that see the detours a motion must make (one body stepping aside)."""
        lm = self.__dict__.get("_landmarks")
        if lm is None:
            from scipy.sparse import csr_matrix
            from scipy.sparse.csgraph import dijkstra

            n = self.n
            g = csr_matrix((self.weights, self.indices, self.indptr), shape=(n, n))
            gt = g.T.tocsr()
            out, back = [], []
            near = np.full(n, np.inf)
            node = 0
            for _ in range(min(self.LANDMARKS, n)):
                d = dijkstra(g, directed=True, indices=node)
                out.append(d)
                back.append(dijkstra(gt, directed=True, indices=node))
                near = np.minimum(near, d)
                far = np.where(np.isfinite(near), near, -1.0)
                if far.max() <= 0.0:
                    break
                node = int(np.argmax(far))
            lm = self._landmarks = (np.array(out).reshape(-1, n), np.array(back).reshape(-1, n))
        return lm

    def widen(self, slots: int) -> None:
        """The graph with the source, node ``n``: its row has ``slots`` arcs, rewritten per query (unused arcs
        loop to the source itself)."""
        from scipy.sparse import csr_matrix

        self.SLOTS = slots
        m, n = len(self.weights), self.n
        self.graph = csr_matrix(
            (
                np.concatenate([self.weights, np.ones(slots)]),
                np.concatenate([self.indices, np.full(slots, n, dtype=np.int32)]),
                np.concatenate([self.indptr, [m + slots]]).astype(np.int32),
            ),
            shape=(n + 1, n + 1),
        )


def _search(
    space: PlanarFreeSpace,
    start: tuple[Position, Position],
    goal: tuple[Position, Position],
    objective: str,
    va: float,
    vb: float,
) -> list[list[Any]] | None:
    """The cheapest path over the pieces' shared points: its straight segments ``[cell, from, to]``.

    Every move keeps the one-way rule and costs its time at the cell's speeds (the edges' speed limits), or its
    length; a move that would keep a rectangle still on a corner while the other body passes its turning disc
    goes by a point inside the piece (:meth:`PlanarFreeSpace.detour`). A* with the robots' own distances to the
    goal as the bound; when it expands more than a few per cent of the nodes (a motion that must go round), the
    same graph is searched by scipy's Dijkstra (:class:`_Moves`, compiled), which finds a path of the same cost.
    None when no path through the shared points keeps the one-way rule (:func:`_search_sets` decides).
    """
    tr = space.track
    spa, spb = _cell_speeds(tr, va, vb)
    rules = any(tr.oneway)

    def cost(cell: tuple[int, int, int], p: Coords, q: Coords) -> float:
        return float(_move_cost(objective, abs(q[0] - p[0]), abs(q[1] - p[1]), spa[cell[0]], spb[cell[1]]))

    pieces = space.pieces
    bodies_turn = not (isinstance(space.footprints.a, Disc) and isinstance(space.footprints.b, Disc))

    def move(i: int, c: Coords, q: Coords) -> tuple[float, Coords | None] | None:
        """The cost of the move ``c -> q`` inside piece ``i`` and its detour point, None if it is not allowed."""
        cell = pieces[i].cell
        if rules and not _forward(tr, cell, c, q):
            return None
        if not bodies_turn or space.segment_ok(i, c, q):
            return cost(cell, c, q), None
        w = space.detour(i, c, q)
        if w is None:
            return None
        return cost(cell, c, w) + cost(cell, w, q), w

    s_pl = space.placements(*start)
    g_pl = space.placements(*goal)
    found = _astar(space, s_pl, g_pl, goal, objective, va, vb, spa, spb, move, budget=40)
    if found is None:
        (ea, sa), (eb, sb) = start
        (fa, ta), (fb, tb) = goal
        da = tr.geometry.distance_scalar(ea, sa, fa, ta)
        db = tr.geometry.distance_scalar(eb, sb, fb, tb)
        lower = math.hypot(da, db) if objective == "shortest" else max(da / va, db / vb)
        found = _dijkstra(space, (start, goal), (s_pl, g_pl), objective, (va, vb), (spa, spb), move, lower)
    if found is None:
        return None
    return [[pieces[i].cell, a, b] for i, a, b in found]


def _astar(
    space: PlanarFreeSpace,
    s_pl: list[tuple[int, Coords]],
    g_pl: list[tuple[int, Coords]],
    goal: tuple[Position, Position],
    objective: str,
    va: float,
    vb: float,
    spa: list[float],
    spb: list[float],
    move: Any,
    budget: int,
) -> list[tuple[int, Coords, Coords]] | None:
    """A* over the shared points; the moves ``(piece, from, to)``, or None when it expands more than ``budget``
    nodes or the goal is not reached."""
    tr = space.track
    rules = any(tr.oneway)
    (ga_e, ga_s), (gb_e, gb_s) = goal
    pieces = space.pieces
    shortest = objective == "shortest"
    hcache: dict[tuple[int, Coords], float] = {}
    # per edge the robots' distances from its tail and head to their goal positions (metres), per robot
    (ta_l, ha_l), (tb_l, hb_l) = (tuple(x.tolist() for x in _from_ends(tr, goal[r])) for r in (0, 1))
    lens = tr.lengths.tolist()
    cells = space.cells()
    slack = 1.0 - 1e-12

    def bound(i: int, c: Coords) -> float:
        """The cost of the robots' own distances to the goal (:func:`_move_cost`, inlined): each move costs at least
        what it takes off each of them."""
        key = (i, c)
        h = hcache.get(key)
        if h is None:
            e, f = cells[i]
            x, y = c
            da = min(x + ta_l[e], (lens[e] - x) + ha_l[e])
            if e == ga_e:
                da = min(da, abs(x - ga_s))
            db = min(y + tb_l[f], (lens[f] - y) + hb_l[f])
            if f == gb_e:
                db = min(db, abs(y - gb_s))
            if shortest:
                h = math.hypot(da, db) * slack
            else:
                ta, tb = da / va, db / vb
                h = (max(ta, tb) + 1e-6 * (ta + tb) + 1e-9 * math.hypot(ta, tb)) * slack
            hcache[key] = h
        return h

    bodies_turn = not (isinstance(space.footprints.a, Disc) and isinstance(space.footprints.b, Disc))
    near = 10.0 * space.tol  # a robot this close to standing still may stand on a corner (segment_ok decides)
    flat = space.moves()
    goal_in: dict[int, list[Coords]] = {}
    for i, c in g_pl:
        goal_in.setdefault(i, []).append(c)
    # a node: (piece, coords in that piece); entering a neighbour through a shared point switches piece
    best: dict[tuple[int, Coords], float] = {}
    prev: dict[tuple[int, Coords], tuple[Any, ...] | None] = {}
    heap: list[tuple[float, int, tuple[int, Coords]]] = []
    counter = 0
    for i, c in s_pl:
        key = (i, c)
        best[key] = 0.0
        prev[key] = None
        heap.append((bound(i, c), counter, key))
        counter += 1
    heapq.heapify(heap)
    done: set[tuple[int, Coords]] = set()
    found: tuple[int, Coords] | None = None
    while heap:
        _, _, key = heapq.heappop(heap)
        if key in done:
            continue
        if len(done) >= budget:
            return None
        g = best[key]
        done.add(key)
        if key[0] < 0:
            found = key
            break
        i, c = key
        cell = pieces[i].cell
        # to the goal inside this piece
        for gc in goal_in.get(i, ()):
            mv = move(i, c, gc)
            if mv is None:
                continue
            gk = (-1 - i, gc)
            ng = g + mv[0]
            if ng < best.get(gk, math.inf):
                best[gk] = ng
                prev[gk] = (key, i, c, gc, mv[1])
                heapq.heappush(heap, (ng, counter, gk))  # the goal's bound is 0
                counter += 1
        # the moves to the shared points (cost inlined: the same expression as _move_cost)
        c0, c1 = c
        va_i, vb_i = spa[cell[0]], spb[cell[1]]
        for pi, nk in flat[i]:
            if rules and not _forward(tr, cell, c, pi):
                continue
            ds, dt = abs(pi[0] - c0), abs(pi[1] - c1)
            if shortest:
                ng = g + math.hypot(ds, dt)
            else:
                ta, tb = ds / va_i, dt / vb_i
                ng = g + (max(ta, tb) + 1e-6 * (ta + tb) + 1e-9 * math.hypot(ta, tb))
            if ng >= best.get(nk, math.inf) - 1e-15:
                continue
            via = None
            # a move that keeps a robot still may turn its body on a corner (discs never need the check)
            if bodies_turn and (abs(pi[0] - c0) <= near or abs(pi[1] - c1) <= near) and not space.segment_ok(i, c, pi):
                mv = move(i, c, pi)
                if mv is None:
                    continue
                ng, via = g + mv[0], mv[1]
                if ng >= best.get(nk, math.inf) - 1e-15:
                    continue
            best[nk] = ng
            prev[nk] = (key, i, c, pi, via)
            heapq.heappush(heap, (ng + bound(nk[0], nk[1]), counter, nk))
            counter += 1
    if found is None:
        return None
    segs: list[tuple[int, Coords, Coords]] = []
    key_: tuple[int, Coords] | None = found
    while key_ is not None:
        pv = prev[key_]
        if pv is None:
            break
        pkey, i, a, b, via = pv
        if via is not None:
            segs += [(i, via, b), (i, a, via)]
        elif a != b:
            segs.append((i, a, b))
        key_ = pkey
    return _in_order(segs, s_pl)


def _in_order(
    segs: list[tuple[int, Coords, Coords]], s_pl: list[tuple[int, Coords]]
) -> list[tuple[int, Coords, Coords]]:
    """The moves read back from the goal, in order from the start (a move that stays at the start when none)."""
    segs.reverse()
    if not segs:
        i, c = s_pl[0]
        segs.append((i, c, c))
    return segs


#: Node counts of the regions the planar search tries after the first (:func:`_dijkstra`).
_REGIONS = (2_000, 6_000, 18_000)


def _dijkstra(
    space: PlanarFreeSpace,
    ends: tuple[tuple[Position, Position], tuple[Position, Position]],
    places: tuple[list[tuple[int, Coords]], list[tuple[int, Coords]]],
    objective: str,
    speeds: tuple[float, float],
    cell_speeds: tuple[list[float], list[float]],
    move: Any,
    lower: float,
) -> list[tuple[int, Coords, Coords]] | None:
    """Dijkstra (scipy, compiled) over :class:`_Moves` from a source node joined to the start's moves; the moves
    ``(piece, from, to)`` of a cheapest path, or None when the goal is not reached.

    ``ends``: start and goal configurations, ``places``: their placements, ``speeds``: the robots' limits (m/s),
    ``cell_speeds``: per edge, ``lower``: a lower bound of the cost (the cost of the robots' own distances). First
    in growing *regions*: the nodes whose bounds from the start and to the goal (:meth:`_Moves.lower`) sum to at
    most ``ub``; every node of a path that costs at most ``ub`` lies in that region, so a goal reached there at a cost
    within ``ub`` is reached at its least cost over the whole graph. Then, when no region reaches it, the whole
    graph.
    """
    from scipy.sparse.csgraph import dijkstra

    s_pl, g_pl = places
    spa, spb = cell_speeds
    G = space.search_graph(objective, spa, spb)
    flat = space.moves()
    n = G.n
    # the source's arcs: from the start in each of its pieces to that piece's shared points
    first: dict[int, tuple[float, int, Coords, Coords, Coords | None]] = {}
    direct: list[tuple[float, int, Coords, Coords, Coords | None]] = []
    goal_in: dict[int, list[Coords]] = {}
    for i, c in g_pl:
        goal_in.setdefault(i, []).append(c)
    for i, c in s_pl:
        for pi, nk in flat[i]:
            mv = move(i, c, pi)
            if mv is None:
                continue
            k = G.node_of[nk]
            if k not in first or mv[0] < first[k][0]:
                first[k] = (mv[0], i, c, pi, mv[1])
        for gc in goal_in.get(i, ()):
            mv = move(i, c, gc)
            if mv is not None:
                direct.append((mv[0], i, c, gc, mv[1]))
    fk = np.array(sorted(first), dtype=np.int64)
    fw = np.maximum(np.array([first[int(k)][0] for k in fk], dtype=float), 5e-324)

    def arrival(dist: FloatArray) -> tuple[float, int, int, Coords, Coords, Coords | None] | None:
        """The cheapest arrival at the goal: cost, node (-1: from the start), piece, its point, goal point, detour."""
        best: tuple[float, int, int, Coords, Coords, Coords | None] | None = None
        for cost, i, c, gc, via in direct:
            if best is None or cost < best[0]:
                best = (cost, -1, i, c, gc, via)
        for i, gcs in goal_in.items():
            nodes = G.by_piece.get(i)
            if nodes is None:
                continue
            reached = nodes[np.isfinite(dist[nodes])]
            for k in reached.tolist():
                xy = (float(G.node_xy[k, 0]), float(G.node_xy[k, 1]))
                for gc in gcs:
                    if best is not None and dist[k] >= best[0]:
                        break
                    mv = move(i, xy, gc)
                    if mv is not None and (best is None or dist[k] + mv[0] < best[0]):
                        best = (float(dist[k] + mv[0]), k, i, xy, gc, mv[1])
        return best

    tr = space.track
    from_start, to_goal = G.lower(tr, ends[0], speeds, objective), G.lower(tr, ends[1], speeds, objective)
    # the landmarks' bounds (Goldberg and Harrelson's ALT): to the goal out[l, T] - out[l, u] with out[l, T]
    # through the goal pieces' nodes and a straight last move (never dearer than the move taken), from the start
    # back[l, S] - back[l, u] with back[l, S] through the source's arcs; 1e-9 of the larger term kept for rounding
    out, back = G.landmarks()
    to_t = np.full(len(out), np.inf)
    for i, gcs in goal_in.items():
        nodes = G.by_piece.get(i)
        if nodes is None:
            continue
        e, f = space.cells()[i]
        for gc in gcs:
            last = _move_cost(
                objective,
                np.abs(G.node_xy[nodes, 0] - gc[0]),
                np.abs(G.node_xy[nodes, 1] - gc[1]),
                spa[e],
                spb[f],
            )
            to_t = np.minimum(to_t, np.min(out[:, nodes] + last, axis=1))
    from_s = np.min(back[:, fk] + fw, axis=1) if len(fk) else np.full(len(back), np.inf)
    with np.errstate(invalid="ignore"):
        for l_ in range(len(out)):
            to_goal = np.fmax(to_goal, to_t[l_] - out[l_] - 1e-9 * to_t[l_])
            from_start = np.fmax(from_start, from_s[l_] - back[l_] - 1e-9 * from_s[l_])
    through = from_start + to_goal
    if len(fk):
        lower = max(lower, float(np.min(fw + to_goal[fk])))
    # the bounds: just above the lower bound (most queries), then the sums that take in about 2 000, 6 000 and
    # 18 000 nodes (each region about three times the last), then the whole graph
    finite = through[np.isfinite(through)]
    ubs = [lower * (1.0 + 1e-3) + 1e-9 * (1.0 + lower)]
    for size in _REGIONS:
        if size < len(finite):
            ub = float(np.partition(finite, size)[size])
            if ub > ubs[-1]:
                ubs.append(ub)
    best = None
    for ub in ubs:
        dist, pred = _region_search(G, through <= ub, fk, fw)
        best = arrival(dist)
        if best is not None and best[0] <= ub:
            break
    else:
        if len(first) > G.SLOTS:  # a start with more shared points than the source's row holds: a larger row
            G.widen(len(first))
        graph = G.graph
        ks = np.full(G.SLOTS, n, dtype=np.int32)
        ws = np.ones(G.SLOTS)
        ks[: len(first)] = fk
        ws[: len(first)] = fw
        graph.indices[-G.SLOTS :] = ks
        graph.data[-G.SLOTS :] = ws
        dist, pred = dijkstra(graph, directed=True, indices=n, return_predecessors=True)
        best = arrival(dist)
    if best is None:
        return None
    _, k, i, c_last, gc, via = best
    segs: list[tuple[int, Coords, Coords]] = []

    def add(piece: int, a: Coords, b: Coords, w: Coords | None) -> None:
        if w is not None:
            segs.extend([(piece, w, b), (piece, a, w)])
        elif a != b:
            segs.append((piece, a, b))

    add(i, c_last, gc, via)
    while k >= 0:
        p = int(pred[k])
        if p == n:  # the source: the first move, from the start
            _, i0, c0, to, w0 = first[k]
            add(i0, c0, to, w0)
            break
        lo, hi = int(G.indptr[p]), int(G.indptr[p + 1])
        arcs = lo + np.flatnonzero(G.indices[lo:hi] == k)
        a = int(arcs[np.argmin(G.weights[arcs])])
        w = G.arc_via[a]
        add(
            int(G.node_piece[p]),
            (float(G.node_xy[p, 0]), float(G.node_xy[p, 1])),
            (float(G.arc_to[a, 0]), float(G.arc_to[a, 1])),
            None if np.isnan(w[0]) else (float(w[0]), float(w[1])),
        )
        k = p
    return _in_order(segs, s_pl)


def _region_search(
    G: _Moves, region: NDArray[np.bool_], fk: NDArray[np.int64], fw: FloatArray
) -> tuple[FloatArray, NDArray[np.int64]]:
    """Dijkstra (scipy) over the nodes of ``region`` (shape ``(n,)``) only, from a source joined to the nodes ``fk``
    at costs ``fw``: the costs of all ``n`` nodes (inf outside the region or not reached) and their predecessors
    (``n``: the source; negative: none), in the whole graph's numbering."""
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import dijkstra

    n = G.n
    r = np.flatnonzero(region)
    m = len(r)
    dist = np.full(n, np.inf)
    pred = np.full(n, -9999, dtype=np.int64)
    if m == 0:
        return dist, pred
    new = np.full(n, -1, dtype=np.int64)
    new[r] = np.arange(m)
    lo = G.indptr[r].astype(np.int64)
    cnt = G.indptr[r + 1].astype(np.int64) - lo
    stop = np.cumsum(cnt)
    idx = np.repeat(lo - (stop - cnt), cnt) + np.arange(int(stop[-1]))
    cols = new[G.indices[idx]]
    keep = cols >= 0
    per_row = np.bincount(np.repeat(np.arange(m), cnt)[keep], minlength=m)
    fc = new[fk]
    fin = fc >= 0
    data = np.concatenate([G.weights[idx[keep]], fw[fin]])
    indices = np.concatenate([cols[keep], fc[fin]]).astype(np.int32)
    indptr = np.concatenate([[0], np.cumsum(per_row), [len(data)]]).astype(np.int32)
    sub = csr_matrix((data, indices, indptr), shape=(m + 1, m + 1))
    d, p = dijkstra(sub, directed=True, indices=m, return_predecessors=True)
    dist[r] = d[:m]
    ok = p[:m] >= 0
    pred[r[ok]] = np.append(r, n)[p[:m][ok]]
    return dist, pred


def _parts(pi: list[Coords], pj: list[Coords]) -> list[tuple[Coords, Coords, Coords, Coords]]:
    """The shared sets of a glued pair of pieces, as segments ``(p0, p1, q0, q1)`` (``p`` in the first piece's
    offsets, ``q`` in the second's; one parameter ``λ`` maps ``p0 + λ(p1 - p0)`` to ``q0 + λ(q1 - q0)``; a point has
    ``p0 == p1``). The shared points come as the two ends and the middle of each segment, or a single point."""
    out: list[tuple[Coords, Coords, Coords, Coords]] = []
    k, n = 0, len(pi)
    while k < n:
        if k + 2 < n:
            a, m, b = pi[k], pi[k + 1], pi[k + 2]
            span = max(abs(b[0] - a[0]), abs(b[1] - a[1]))
            mid = (0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]))
            if span > 0.0 and max(abs(m[0] - mid[0]), abs(m[1] - mid[1])) <= 1e-9 * max(1.0, span):
                out.append((a, b, pj[k], pj[k + 2]))
                k += 3
                continue
        out.append((pi[k], pi[k], pj[k], pj[k]))
        k += 1
    return out


def _cone(ow: tuple[bool, bool], ends: tuple[Coords, Coords]) -> list[tuple[float, float, float]]:
    """Half-planes ``a*s + b*t >= c`` of ``S ⊕ K``: the configurations a monotone move reaches from the segment
    ``S`` (its two ends) when ``K`` is the forward cone of the one-way axes ``ow`` (a quadrant, a half-plane, or the
    plane: no half-plane)."""
    p, q = ends
    out = []
    if ow[0]:
        out.append((1.0, 0.0, min(p[0], q[0])))
    if ow[1]:
        out.append((0.0, 1.0, min(p[1], q[1])))
    ds, dt = q[0] - p[0], q[1] - p[1]
    if ow[0] and ow[1] and ds * dt < 0.0:  # a falling segment: nothing below its line is reached
        a, b = abs(dt), abs(ds)
        nrm = math.hypot(a, b)
        out.append((a / nrm, b / nrm, (a * p[0] + b * p[1]) / nrm))
    return out


def _lam_range(p0: Coords, p1: Coords, hp: list[tuple[float, float, float]], tol: float) -> tuple[float, float] | None:
    """The parameters ``λ ∈ [0, 1]`` where ``p0 + λ(p1 - p0)`` satisfies every half-plane: exactly when some do,
    else within ``tol`` (a segment that only touches the half-planes, where rounding decides)."""
    exact = _lam_range_tol(p0, p1, hp, 0.0)
    return exact if exact is not None else _lam_range_tol(p0, p1, hp, tol)


def _lam_range_tol(
    p0: Coords, p1: Coords, hp: list[tuple[float, float, float]], tol: float
) -> tuple[float, float] | None:
    lo, hi = 0.0, 1.0
    for a, b, c in hp:
        f0 = a * p0[0] + b * p0[1] - c + tol
        df = a * (p1[0] - p0[0]) + b * (p1[1] - p0[1])
        if abs(df) <= 1e-15:
            if f0 < 0.0:
                return None
            continue
        r = -f0 / df
        if df > 0:
            lo = max(lo, r)
        else:
            hi = min(hi, r)
    return (lo, hi) if lo <= hi else None


def _at(p0: Coords, p1: Coords, lam: float) -> Coords:
    return (p0[0] + lam * (p1[0] - p0[0]), p0[1] + lam * (p1[1] - p0[1]))


def _search_sets(
    space: PlanarFreeSpace,
    start: tuple[Position, Position],
    goal: tuple[Position, Position],
    budget: int = 400_000,
) -> list[list[Any]] | None:
    """A motion that keeps the one-way rule, or None when none exists in the model (complete).

    **Reach.** In a convex free piece the moves allowed from a point ``r`` are the straight moves to the points of
    its forward cone ``C(r)`` (the one-way coordinates do not decrease); from a segment ``S`` they reach
    ``R(S) = piece ∩ (S ⊕ K)``: the piece cut by ``s >= min_S s`` and ``t >= min_S t`` on one-way axes and, when both
    axes are one-way and ``S`` falls, by ``S``'s line (:func:`_cone`). A state is a piece with the segment ``S``
    where the motion may enter it; its successors are the shared segments with the glued pieces cut to ``R(S)``
    (again segments: a convex set meets a segment in a segment), and the goal is reached when it lies in ``R(S)``.

    **Complete.** Every motion under the rule passes through a sequence of pieces and shared sets; by induction
    its crossing points lie in the successive states' segments (a monotone move from a point of ``S`` stays in
    ``R(S)``), so the search reaches the goal whenever such a motion exists. A state whose segment lies in the reach
    of a state already expanded in the same piece adds nothing (``S' ⊆ R(S)`` implies ``R(S') ⊆ R(S)``) and is
    skipped, which also ends the search.

    **Path.** Back from the goal: in each state the point of its segment from which the next point is forward
    (closest to it), a straight move inside the piece. ``budget`` bounds the expanded states.
    """
    from collections import deque

    tr = space.track
    pieces = space.pieces
    tol = 10.0 * space.tol
    dom = 100.0 * tol  # a state within this of an expanded one's reach adds nothing (rounding never loops)
    ow_of = [(bool(tr.oneway[p.cell[0]]), bool(tr.oneway[p.cell[1]])) for p in pieces]
    goal_in: dict[int, list[Coords]] = {}
    for i, c in space.placements(*goal):
        goal_in.setdefault(i, []).append(c)
    # a state: (piece, ends of S, parent state, (p0, p1, q0, q1, lo, hi) of the shared segment it came through)
    states: list[tuple[int, tuple[Coords, Coords], int, Any]] = []
    todo: deque[int] = deque()
    for i, c in space.placements(*start):
        states.append((i, (c, c), -1, None))
        todo.append(len(states) - 1)
    expanded: dict[int, list[list[tuple[float, float, float]]]] = {}
    parts_memo: dict[int, list[tuple[int, list[tuple[Coords, Coords, Coords, Coords]]]]] = {}
    found: tuple[int, Coords] | None = None
    steps = 0
    seen_pinned: set[tuple[int, tuple[Coords, Coords]]] = set()
    while todo and found is None:
        sid = todo.popleft()
        i, ends, _, _ = states[sid]
        done = expanded.setdefault(i, [])
        if any(all(a * x[0] + b * x[1] >= c - dom for x in ends for a, b, c in hp) for hp in done):
            continue
        pins = _pins(space, i, ends, ow_of[i])
        if pins:  # a smaller reach: never used to drop other states, and each such state expanded once
            if (i, ends) in seen_pinned:
                continue
            seen_pinned.add((i, ends))
        steps += 1
        if steps > budget:
            raise PlanningError(f"the one-way search expanded more than {budget} states without deciding")
        hp = _cone(ow_of[i], ends)
        if not pins:
            done.append(hp)
        for gc in goal_in.get(i, ()):
            if all(a * gc[0] + b * gc[1] >= c - tol for a, b, c in hp) and _pinned_ok(pins, gc, ends, tol):
                found = (sid, gc)
                break
        if found is not None:
            break
        if i not in parts_memo:
            parts_memo[i] = [(j, _parts(pi, pj)) for j, pi, pj in space.adjacent[i]]
        for j, parts in parts_memo[i]:
            for p0, p1, q0, q1 in parts:
                rng = _lam_range(p0, p1, hp, tol)
                if rng is None:
                    continue
                for lo, hi in _pinned_ranges(pins, p0, p1, rng, ends, tol):
                    x = (_at(q0, q1, lo), _at(q0, q1, hi))
                    if any(
                        all(a * y[0] + b * y[1] >= c - dom for y in x for a, b, c in h2) for h2 in expanded.get(j, ())
                    ):
                        continue
                    states.append((j, x, sid, (p0, p1, q0, q1, lo, hi)))
                    todo.append(len(states) - 1)
    if found is None:
        return None
    sid, y = found
    segs: list[list[Any]] = []
    lam = 0.0
    while True:
        i, ends, parent, via = states[sid]
        cell = pieces[i].cell
        ow = ow_of[i]
        if via is None:
            xp = ends[0]
        else:
            p0, p1, q0, q1, lo, hi = via
            # the parameters in [lo, hi] whose point is behind y on the one-way axes (and, where a robot is pinned
            # to a corner, on y's side of its turning block), then the closest to y
            hp = [(-1.0, 0.0, -y[0])] if ow[0] else []
            hp += [(0.0, -1.0, -y[1])] if ow[1] else []
            for ax, corner, b0, b1 in _pins(space, i, (_at(q0, q1, lo), _at(q0, q1, hi)), ow):
                if abs(y[ax] - corner) <= tol:
                    o = 1 - ax
                    if y[o] <= b0:
                        hp.append((-1.0, 0.0, -b0) if o == 0 else (0.0, -1.0, -b0))
                    elif y[o] >= b1:
                        hp.append((1.0, 0.0, b1) if o == 0 else (0.0, 1.0, b1))
            a0, a1 = _at(q0, q1, lo), _at(q0, q1, hi)
            rng = _lam_range(a0, a1, hp, tol)
            u0, u1 = rng if rng is not None else (0.0, 1.0)
            d = (a1[0] - a0[0], a1[1] - a0[1])
            den = d[0] * d[0] + d[1] * d[1]
            mu = 0.0 if den <= 0.0 else ((y[0] - a0[0]) * d[0] + (y[1] - a0[1]) * d[1]) / den
            mu = min(max(mu, u0), u1)
            # the closest point first; where its move would hold a robot on a corner through the other's block,
            # a point of the allowed range off that corner (the middle, then the ends)
            cands = [mu, 0.5 * (u0 + u1), u0, u1]
        chosen: tuple[Coords, Coords | None] | None = None
        for m_ in cands if via is not None else [0.0]:
            if via is not None:
                lam = lo + m_ * (hi - lo)
                xp = _at(q0, q1, lam)
            # a move within the tolerances of a shared point: never backwards on a one-way axis
            xp = (min(xp[0], y[0]) if ow[0] else xp[0], min(xp[1], y[1]) if ow[1] else xp[1])
            if xp == y or space.segment_ok(i, xp, y):
                chosen = (xp, None)
                break
            w = space.detour(i, xp, y)  # a robot kept still on a corner: by a point inside the piece
            if w is not None:
                chosen = (xp, w)
                break
        if chosen is None:
            raise PlanningError(
                "the one-way search found a motion whose move turns a body on a corner into the other one"
            )
        xp, w = chosen
        if xp != y:
            segs += [[cell, xp, y]] if w is None else [[cell, w, y], [cell, xp, w]]  # reversed below
        if via is None:
            break
        y = _at(via[0], via[1], lam)
        sid = parent
    segs.reverse()
    return segs


def _pins(
    space: PlanarFreeSpace, i: int, ends: tuple[Coords, Coords], ow: tuple[bool, bool]
) -> list[tuple[int, float, float, float]]:
    """The robots a state of the one-way search holds on a corner: ``(axis, corner offset, block start, block
    end)`` where its segment ``S`` lies on the corner's line, the robot is a rectangle that cannot step off the
    line and back (its edge is one-way, or the piece has no interior) and the other body passes its turning disc
    over the open interval ``(block start, block end)`` of the other robot's offsets. From ``S`` the points of that
    line are then reached only on the side of the block where ``S`` reaches it."""
    out = []
    sub = space.pieces[i].sub
    flat = None
    for ax, corner in space.still_on_corner(i, ends[0], ends[1]):
        fp = space.footprints.a if ax == 0 else space.footprints.b
        if isinstance(fp, Disc):
            continue
        if not ow[ax]:
            if flat is None:
                poly = space.pieces[i].poly
                t = 10.0 * space.tol
                flat = len(poly) < 3 or abs(_area([tuple(x) for x in poly])) <= t * t
            if not flat:
                continue  # it may step into the piece and back (PlanarFreeSpace.detour)
        blk = space._turn_block(ax, sub[ax], corner, sub[1 - ax])
        if blk is not None:
            out.append((ax, corner, blk[0], blk[1]))
    return out


def _pinned_ok(pins: list[tuple[int, float, float, float]], y: Coords, ends: tuple[Coords, Coords], tol: float) -> bool:
    """Whether the point ``y`` is reached from the segment ``ends`` with the robots in ``pins`` held on their
    corners (a point off a pinned line is reached by moving that robot, which :func:`_cone` decides)."""
    for ax, corner, b0, b1 in pins:
        if abs(y[ax] - corner) > tol:
            continue
        o = 1 - ax
        lo, hi = min(ends[0][o], ends[1][o]), max(ends[0][o], ends[1][o])
        if not ((lo <= b0 and y[o] <= b0) or (hi >= b1 and y[o] >= b1) or lo <= y[o] <= hi):
            return False
    return True


def _pinned_ranges(
    pins: list[tuple[int, float, float, float]],
    p0: Coords,
    p1: Coords,
    rng: tuple[float, float],
    ends: tuple[Coords, Coords],
    tol: float,
) -> list[tuple[float, float]]:
    """The parameter range ``rng`` of the shared segment ``p0 -> p1`` cut to the points reached with the robots in
    ``pins`` held on their corners: on a pinned line, the parts on the reached sides of the block (and ``S``'s own
    points); an end of a segment that only touches the line is dropped when it is not reached."""
    out = [rng]
    for ax, corner, b0, b1 in pins:
        o = 1 - ax
        on0, on1 = abs(p0[ax] - corner) <= tol, abs(p1[ax] - corner) <= tol
        nxt: list[tuple[float, float]] = []
        for lo, hi in out:
            if on0 and on1:  # along the line: the other robot's offsets allowed there, as parameters
                lo_s, hi_s = min(ends[0][o], ends[1][o]), max(ends[0][o], ends[1][o])
                allowed = [(lo_s, hi_s)]
                if lo_s <= b0:
                    allowed.append((-math.inf, b0))
                if hi_s >= b1:
                    allowed.append((b1, math.inf))
                d = p1[o] - p0[o]
                for y0, y1 in allowed:
                    if abs(d) <= 1e-15:
                        if y0 - tol <= p0[o] <= y1 + tol:
                            nxt.append((lo, hi))
                        continue
                    l0, l1 = sorted(((y0 - p0[o]) / d, (y1 - p0[o]) / d))
                    a, b = max(lo, l0), min(hi, l1)
                    if a <= b:
                        nxt.append((a, b))
            elif on0 or on1:  # touches the line at one end: that end only if reached
                end = p0 if on0 else p1
                if _pinned_ok([(ax, corner, b0, b1)], end, ends, tol):
                    nxt.append((lo, hi))
                else:
                    cut = 1e-9
                    a, b = (max(lo, cut), hi) if on0 else (lo, min(hi, 1.0 - cut))
                    if a <= b:
                        nxt.append((a, b))
            else:
                nxt.append((lo, hi))
        out = nxt
    return out


def _why_not(space: PlanarFreeSpace) -> str:
    """Where the layout is too narrow for the bodies: the closest two pieces of the drawing that do not meet."""
    tr = space.track
    d = space.drawing
    fps = space.footprints
    best = (math.inf, -1, -1)
    n = len(d.piece_edge)
    ends = [(d.piece_p0[p], d.piece_p0[p] + (d.piece_s1[p] - d.piece_s0[p]) * d.piece_dir[p]) for p in range(n)]
    tol = 1e-9 * max(1.0, tr.total_length)
    for p in range(n):
        for q in range(p + 1, n):
            (a0, a1), (b0, b1) = ends[p], ends[q]
            if min(float(np.hypot(*(x - y))) for x in (a0, a1) for y in (b0, b1)) <= tol:
                continue  # pieces that meet (a corner or a switch)
            dist = _seg_seg(a0, a1, b0, b1)
            if dist < best[0]:
                best = (dist, int(d.piece_edge[p]), int(d.piece_edge[q]))
    need = fps.across()
    what = "radii summed" if isinstance(fps.a, Disc) and isinstance(fps.b, Disc) else "half-widths summed"
    if best[1] >= 0 and best[0] < need:
        return (
            f"the bodies ({fps.spec()}) cannot pass each other in the plane: edges {tr.edge_names[best[1]]!r} and "
            f"{tr.edge_names[best[2]]!r} run {best[0]:.4g} m apart in the drawing; bodies that need {need:.4g} m "
            f"side by side ({what}) cannot pass there"
        )
    return (
        f"the bodies ({fps.spec()}) block each other in the plane near the switches: start and goal are in "
        "different components of the free space with footprints, although they are connected along the track"
    )


def _seg_seg(a0: FloatArray, a1: FloatArray, b0: FloatArray, b1: FloatArray) -> float:
    def pt(p: FloatArray, s0: FloatArray, s1: FloatArray) -> float:
        ab = s1 - s0
        den = float(ab @ ab)
        lam = 0.0 if den <= 0 else min(1.0, max(0.0, float((p - s0) @ ab) / den))
        return float(np.hypot(*(s0 + lam * ab - p)))

    def orient(p: FloatArray, q: FloatArray, r: FloatArray) -> float:
        return float((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]))

    o1, o2 = orient(a0, a1, b0), orient(a0, a1, b1)
    o3, o4 = orient(b0, b1, a0), orient(b0, b1, a1)
    if o1 * o2 < 0 and o3 * o4 < 0:
        return 0.0
    return min(pt(a0, b0, b1), pt(a1, b0, b1), pt(b0, a0, a1), pt(b1, a0, a1))


def plan_planar(
    track: GraphTrack,
    start: tuple[Position, Position],
    goal: tuple[Position, Position],
    clearance: float,
    objective: str,
    speeds: tuple[float, float],
    footprint: Footprints,
) -> Any:
    """Plan in the planar model (called by :func:`mpa.planners.graph.plan_graph` with ``footprint=``).

    Returns
    -------
    GraphPlan

    Raises
    ------
    InvalidInputError
        Bodies overlapping at start or goal (the message gives the gap), a layout without coordinates.
    NoMotionError
        Start and goal in different components; the message names the narrow place.
    """
    from mpa.planners.graph import _assemble, _why_no_motion

    space = planar_free_space(track, clearance, footprint)
    for what, (pa, pb) in (("start", start), ("goal", goal)):
        why = start_refusal(track, space, what, pa, pb)
        if why:
            raise InvalidInputError(why)
    ca, cb = space.component_of(*start), space.component_of(*goal)
    if ca is None or ca != cb:
        bca, bcb = space.base.component_of(*start), space.base.component_of(*goal)
        if bca is None or bca != bcb:
            raise NoMotionError(_why_no_motion(track, space.base, start, goal))
        raise NoMotionError(_why_not(space))
    by_sets = None
    if any(track.oneway):  # decide first (complete, and cheaper than exhausting the shared points)
        by_sets = _search_sets(space, start, goal)
        if by_sets is None:
            raise NoMotionError(_why_one_way(space, start, goal))
    found = _search(space, start, goal, objective, speeds[0], speeds[1]) or by_sets
    if found is None:  # pragma: no cover - start and goal were checked to share a component
        raise PlanningError("the search ended without reaching the goal although start and goal share a component")
    segs = [x for x in found if x[1] != x[2]]
    plan = _assemble(track, space.base, start, goal, objective, speeds, segs)
    if not track.has_rules:
        return plan
    from mpa.planners.rules import timed_at_limits

    return timed_at_limits(plan, track, speeds)  # the time at the edges' speed limits


def _why_one_way(space: PlanarFreeSpace, start: tuple[Position, Position], goal: tuple[Position, Position]) -> str:
    """The reason when only the one-way rule forbids the motion (start and goal share a component)."""
    tr = space.track
    names = ", ".join(tr.position_name(*p) for p in start)
    gnames = ", ".join(tr.position_name(*p) for p in goal)
    one = [tr.edge_names[i] for i, ow in enumerate(tr.oneway) if ow]
    listed = ", ".join(one[:8]) + (" ..." if len(one) > 8 else "")
    return (
        f"the one-way lanes forbid it: start ({names}) and goal ({gnames}) are connected with the bodies "
        f"({space.footprints.spec()}) apart when every lane may be driven both ways, but no such motion drives the "
        f"one-way lanes ({listed}) only from 'from' to 'to'"
    )
