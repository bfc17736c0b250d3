"""Gluing the free pieces: which pieces share points (inside a cell, across a face where a robot stands on a
vertex, at a corner where both do), the shared points, and the path components."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from mpa.freespace import _clip, _union_find
from mpa.planar.build import _Build
from mpa.planar.polygons import Coords, _area, _halfplanes, _meet, _portal_points, _portal_values


class _Glue(_Build):
    """The adjacency and path components of :class:`mpa.planar.PlanarFreeSpace`."""

    def _glue(self) -> None:
        tr = self.track
        tol = 10.0 * self.tol
        n = len(self.pieces)
        self.adjacent = [[] for _ in range(n)]
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
