"""The free pieces: each sub-cell (a drawing piece of A's edge x one of B's) of the along-track free polygons cut
by the obstacle of the two bodies, a convex polygon of offsets."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from mpa.footprint import Disc
from mpa.freespace import _clip, _dedupe
from mpa.planar.corners import _Corners
from mpa.planar.polygons import Coords, _area, _halfplanes, _hull, _Piece


class _Build(_Corners):
    """The free pieces of :class:`mpa.planar.PlanarFreeSpace` (its :attr:`pieces`)."""

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
