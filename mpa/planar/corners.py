"""Bodies at the drawing's corners: where a body turns, the sweep of a turning rectangle (the disc of its reach),
the moves that keep a robot on a corner, and the check of a start or goal (:func:`start_refusal`)."""

from __future__ import annotations

import bisect
import itertools
import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from mpa.footprint import Disc, Drawing, Footprint, Footprints, body_gap, drawing_of
from mpa.freespace import FreeSpace
from mpa.graph_track import GraphTrack, Position
from mpa.planar.polygons import Coords, FloatArray, _area, _halfplanes, _hull, _Piece, _portal_values

if TYPE_CHECKING:
    from mpa.planar.space import PlanarFreeSpace


class _SpaceBase:
    """The attributes the parts of :class:`mpa.planar.PlanarFreeSpace` share (set by its constructor)."""

    track: GraphTrack
    footprints: Footprints
    drawing: Drawing
    base: FreeSpace
    clearance: float
    tol: float
    pieces: list[_Piece]
    adjacent: list[list[tuple[int, list[Coords], list[Coords]]]]
    component: NDArray[np.int64]
    n_components: int


class _Corners(_SpaceBase):
    """Where bodies turn: the drawing's corners, a turning body's sweep (the disc of its reach) and the moves that
    keep a robot on a corner (:class:`mpa.planar.PlanarFreeSpace`)."""

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

    @staticmethod
    def _turns_h(h1: float, h2: float) -> bool:
        x = abs(h1 - h2) % math.pi
        return min(x, math.pi - x) > 1e-12

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

    def _corner_lists(self) -> list[list[float]]:
        """Per edge the sorted offsets of :meth:`_corner_offsets`."""
        ca = self.__dict__.get("_ca")
        if ca is None:
            ca = self._ca = [sorted(d) for d in self._corner_offsets()]
        return ca

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
    if any(_Corners._turns_h(hs[0], h) for h in hs[1:]):
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
