"""Robot routes in unwrapped coordinates (the universal cover of the track).

The universal cover ``T`` of a track is a tree: for the circle the real line (the loop unrolled), for the
lollipop the real line with a copy of the stick hanging at every lift ``P_k = k·c`` of the pole, for the
interval the interval itself. A point of ``T`` is a :class:`Lift`: ``("line", k=0, v=U)`` with the unrolled
loop coordinate ``U`` (for the interval ``U = p``), or ``("stick", k, v=x)`` on the k-th copy of the stick at
depth ``x`` below ``P_k`` (``x = ℓ − p``).

Every robot of a plan moves along a single geodesic line of ``T``: its :class:`Route`. The route coordinate
``σ`` (metres) is the signed distance along that line from the robot's start (``σ = 0``), continuous through P
and round the loop. Its sign is fixed by the robot's farthest excursion: the corner of the plan farthest from the
start along the line has ``σ > 0`` (usually the goal). It never depends on the sign of a displacement that can
vanish inside a domain (a robot that leaves and comes back to almost its start keeps its orientation), so the
exported route coordinates move continuously with the query. Trajectory optimisation works in these coordinates.
"""

from __future__ import annotations

import functools
import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa._arrays import FloatArray
from mpa.errors import InvalidInputError, PlanningError
from mpa.geometry import DirectedRoute
from mpa.tracks import Circle, Interval, Lollipop, Track

__all__ = ["Lift", "RobotMove", "Route", "affine_position", "directed_route", "lift_moves", "lift_position"]

#: Tolerance (metres) for deciding that a lifted point sits on a junction.
LIFT_TOL = 1e-9


class _PieceArrays(NamedTuple):
    """A route's pieces as arrays (one entry per piece; ``ends``: the ``r`` where each piece but the last ends)."""

    ends: FloatArray
    is_stick: NDArray[np.bool_]
    k: NDArray[np.int64]
    v0: FloatArray
    v1: FloatArray
    r0: FloatArray
    span: FloatArray


class Lift(NamedTuple):
    """A point of the universal cover: ``kind`` "line" (v = U) or "stick" (copy ``k``, v = depth x >= 0)."""

    kind: str
    k: int
    v: float


class RobotMove(NamedTuple):
    """One robot's motion during one elementary step, along a single edge of the track.

    ``edge`` is "stick" (``p`` goes linearly from ``start`` to ``start + delta``; also the interval) or
    "loop" (``θ`` goes linearly from ``start`` by the signed, unwrapped ``delta``; ccw positive).
    """

    edge: str
    start: float
    delta: float

    @staticmethod
    def stay(track: Track, p: float) -> RobotMove:
        """A robot that does not move (at track coordinate ``p``)."""
        if isinstance(track, Lollipop) and p > track.stick:
            return RobotMove("loop", p - track.stick, 0.0)
        if isinstance(track, Circle):
            return RobotMove("loop", p, 0.0)
        return RobotMove("stick", p, 0.0)


def lift_position(track: Track, lift: Lift) -> float:
    """Track coordinate of a point of the universal cover."""
    if isinstance(track, Interval):
        return lift.v
    if isinstance(track, Circle):
        return lift.v % track.loop
    if not isinstance(track, Lollipop):
        raise InvalidInputError(f"track is {track!r}, expected a Lollipop")
    if lift.kind == "stick":
        return track.stick - lift.v
    th = lift.v % track.loop
    if th > track.loop - LIFT_TOL:
        th = 0.0
    return track.stick + th


def lift_moves(track: Track, moves: Sequence[RobotMove], start: float) -> list[Lift]:
    """Lift a robot's sequence of moves to the universal cover.

    Parameters
    ----------
    track : Track
    moves : sequence of RobotMove
        Consecutive moves of one robot; each must start where the previous one ended.
    start : float
        The robot's start (track coordinate).

    Returns
    -------
    list of Lift
        ``len(moves) + 1`` lifted points: the start and the end of every move.
    """
    ell = track.stick if isinstance(track, Lollipop) else 0.0
    if isinstance(track, Lollipop):
        cur = Lift("stick", 0, ell - start) if start <= ell else Lift("line", 0, start - ell)
    else:
        cur = Lift("line", 0, float(start))
    out = [cur]
    c = getattr(track, "loop", 0.0)
    for mv in moves:
        if isinstance(track, Lollipop):
            if mv.edge == "stick":
                if cur.kind == "line":
                    k = round(cur.v / c)
                    if abs(cur.v - k * c) > 1e-7 * max(1.0, c):
                        raise PlanningError(f"robot leaves the loop onto the stick away from P (U = {cur.v})")
                    cur = Lift("stick", k, 0.0)
                x_end = ell - (mv.start + mv.delta)
                if abs((ell - cur.v) - mv.start) > 1e-7 * max(1.0, ell):
                    raise PlanningError(f"stick move starts at {mv.start}, robot is at {ell - cur.v}")
                cur = Lift("stick", cur.k, max(x_end, 0.0))
            else:
                if cur.kind == "stick":
                    if cur.v > 1e-7 * max(1.0, ell):
                        raise PlanningError(f"robot enters the loop from the stick away from P (x = {cur.v})")
                    cur = Lift("line", 0, cur.k * c)
                cur = Lift("line", 0, cur.v + _loop_gap(cur.v, mv.start, c) + mv.delta)
        elif isinstance(track, Circle):
            cur = Lift("line", 0, cur.v + _loop_gap(cur.v, mv.start, c) + mv.delta)
        else:
            if abs(cur.v - mv.start) > 1e-7 * max(1.0, track.total_length):
                raise PlanningError(f"move starts at {mv.start}, robot is at {cur.v}")
            cur = Lift("line", 0, mv.start + mv.delta)
        out.append(cur)
    return out


def _loop_gap(u: float, theta: float, c: float) -> float:
    """Signed shortest step from the unrolled loop coordinate ``u`` to the loop coordinate ``theta``.

    Moves are chained by their absolute ends (the start of a move may differ from the previous end by rounding),
    so that the last corner is exactly where the last move ends, with no drift along the chain.

    Raises
    ------
    PlanningError
        If the gap exceeds 1e-7 (relative): the moves are not consecutive.
    """
    gap = (theta - u) % c
    if gap > 0.5 * c:
        gap -= c
    if abs(gap) > 1e-7 * max(1.0, c):
        raise PlanningError(f"loop move starts at θ = {theta}, robot is at θ = {u % c}")
    return gap


@dataclass(frozen=True)
class Route:
    """A geodesic line of the universal cover, parametrized by the route coordinate ``σ`` (metres).

    The line is stored as consecutive pieces in the order of increasing ``r`` (arc length from the
    line's first end); ``σ = direction · (r − r_start)``.

    Attributes
    ----------
    track : Track
    pieces : tuple of (kind, k, v_from, v_to, r_from, r_to)
        Each piece is a straight part of one edge of the cover; ``v`` varies linearly with ``r``.
    r_start : float
        ``r`` of the robot's start.
    direction : int
        +1 or -1.
    sigma_min, sigma_max : float
        The extent of the line in route coordinates (sticks extended to the free end, the loop by one turn).
    length : float
        Distance of the goal from the start along the route (``|σ|`` of the goal; the goal's ``σ`` is negative
        when the robot's farthest excursion is on the other side of its start).
    goal_sigma : float
        ``σ`` of the goal (metres; ``±length``).
    """

    track: Track
    pieces: tuple[tuple[str, int, float, float, float, float], ...]
    r_start: float
    direction: int
    sigma_min: float
    sigma_max: float
    length: float
    goal_sigma: float = 0.0

    # -------------------------------------------------------------------------------------------
    @classmethod
    def through(cls, track: Track, lifts: Sequence[Lift], goal_index: int = -1) -> tuple[Route, FloatArray]:
        """The route through a robot's lifted corner points, and the corners' route coordinates.

        Parameters
        ----------
        track : Track
        lifts : sequence of Lift
            The robot's corner points (start first).
        goal_index : int
            Which point is the goal (``length`` is its distance from the start).

        Returns
        -------
        route : Route
        sigma : ndarray, shape (len(lifts),)
            Route coordinate of every corner.

        Raises
        ------
        PlanningError
            If the points do not lie on one geodesic line of the cover (never happens for the paper's plans).
        """
        tol = 1e-7 * max(1.0, track.total_length)
        ends = {0, goal_index % len(lifts)}
        pts = _at_junctions_on_the_line(track, lifts, ends, tol)
        if isinstance(track, Lollipop):
            pieces, r = _lollipop_line(track, pts, ends, tol)
        else:
            pieces, r = _unrolled_line(track, pts)
        return cls._oriented(track, pieces, r, goal_index)

    @classmethod
    def _oriented(
        cls,
        track: Track,
        pieces: tuple[tuple[str, int, float, float, float, float], ...],
        r: FloatArray,
        goal_index: int,
    ) -> tuple[Route, FloatArray]:
        """The route through corner points at line arc lengths ``r``, oriented by :func:`_direction`."""
        rs = [float(v) for v in r]
        r_start = rs[0]
        diffs = [v - r_start for v in rs]
        goal = diffs[goal_index]
        direction = _direction(diffs)
        r_lo, r_hi = pieces[0][4], pieces[-1][5]
        s_a, s_b = direction * (r_lo - r_start), direction * (r_hi - r_start)
        sigma = np.array(diffs) * direction
        route = cls(track, tuple(pieces), r_start, direction, min(s_a, s_b), max(s_a, s_b), abs(goal), direction * goal)
        return route, sigma

    @functools.cached_property
    def _piece_arrays(self) -> _PieceArrays:
        """Per-piece arrays for :meth:`lift_at` (built on first use, cached on the instance)."""
        pcs = self.pieces
        ra = np.array([pc[4] for pc in pcs])
        rb = np.array([pc[5] for pc in pcs])
        return _PieceArrays(
            ends=np.array([pc[5] for pc in pcs[:-1]]),
            is_stick=np.array([pc[0] == "stick" for pc in pcs]),
            k=np.array([pc[1] for pc in pcs], dtype=np.int64),
            v0=np.array([pc[2] for pc in pcs]),
            v1=np.array([pc[3] for pc in pcs]),
            r0=ra,
            span=np.where(rb > ra, rb - ra, 1.0),
        )

    def lift_at(self, sigma: ArrayLike) -> tuple[NDArray[np.bool_], NDArray[np.int64], FloatArray]:
        """Lifted points at route coordinates ``σ``: (is_stick, copy index k, v). Same shape as ``σ``."""
        s = np.asarray(sigma, dtype=float)
        r = self.r_start + self.direction * s
        pa = self._piece_arrays
        idx = np.searchsorted(pa.ends, r, side="left")
        frac = (r - pa.r0[idx]) / pa.span[idx]
        v = pa.v0[idx] + frac * (pa.v1[idx] - pa.v0[idx])
        is_stick = pa.is_stick[idx]
        if isinstance(self.track, (Lollipop, Interval)):
            lim = self.track.stick
            v = np.where(is_stick, np.clip(v, 0.0, lim), v)
            if isinstance(self.track, Interval):
                v = np.clip(v, 0.0, lim)
        return is_stick, pa.k[idx], v

    def _affine(self) -> tuple[FloatArray, FloatArray, FloatArray, NDArray[np.bool_]]:
        """Per piece, in order of increasing σ: breakpoints, and ``A + B·σ`` = depth-or-track value."""
        return self._affine_form

    @functools.cached_property
    def _affine_form(self) -> tuple[FloatArray, FloatArray, FloatArray, NDArray[np.bool_]]:
        """:meth:`_affine`, computed on first use and cached on the instance."""
        tr = self.track
        ell = tr.stick if isinstance(tr, Lollipop) else 0.0
        rows = []
        for kind, _k, v0, v1, ra, rb in self.pieces:
            span = rb - ra if rb > ra else 1.0
            beta = self.direction * (v1 - v0) / span
            alpha = v0 + (self.r_start - ra) * (v1 - v0) / span
            s_a, s_b = self.direction * (ra - self.r_start), self.direction * (rb - self.r_start)
            if kind == "stick" and isinstance(tr, Lollipop):
                rows.append((min(s_a, s_b), ell - alpha, -beta, False))
            else:
                rows.append((min(s_a, s_b), alpha, beta, True))
        rows.sort(key=lambda r: r[0])
        out = (
            np.array([r[0] for r in rows[1:]], dtype=float),
            np.array([r[1] for r in rows], dtype=float),
            np.array([r[2] for r in rows], dtype=float),
            np.array([r[3] for r in rows], dtype=bool),
        )
        return out

    def affine_form(self) -> tuple[FloatArray, FloatArray, FloatArray, NDArray[np.bool_], bool, float, float]:
        """The route as :func:`affine_position` takes it: ``breaks, A, B, is_line, interval, stick, loop``
        (C-contiguous float and bool arrays, built once; plain Python ``bool`` and ``float``)."""
        tr = self.track
        breaks, A, B, is_line = self._affine()
        stick = float(tr.stick) if isinstance(tr, (Interval, Lollipop)) else 0.0
        loop = float(tr.loop) if isinstance(tr, (Circle, Lollipop)) else 1.0
        return breaks, A, B, is_line, isinstance(tr, Interval), stick, loop

    def position(self, sigma: ArrayLike) -> FloatArray:
        """Track coordinate at route coordinate ``σ`` (vectorized; metres). One in plain Python:
        :func:`affine_position` of :meth:`affine_form`."""
        s = np.asarray(sigma, dtype=float)
        breaks, A, B, is_line = self._affine()
        tr = self.track
        if len(A) == 1:
            val = A[0] + B[0] * s
            line = bool(is_line[0])
            if isinstance(tr, Interval) or (isinstance(tr, Lollipop) and not line):
                return np.clip(val, 0.0, tr.stick)
            if not isinstance(tr, (Circle, Lollipop)):
                raise InvalidInputError(f"track is {tr!r}, expected an Interval, Circle or Lollipop")
            th = np.mod(val, tr.loop)
            th = np.where(th >= tr.loop - 1e-12, 0.0, th)
            return tr.stick + th if isinstance(tr, Lollipop) else th
        idx = np.searchsorted(breaks, s, side="left")
        val = A[idx] + B[idx] * s
        if not isinstance(tr, Lollipop):
            raise InvalidInputError(f"track is {tr!r}, expected a Lollipop")
        c = tr.loop
        th = np.mod(val, c)
        th = np.where(th >= c - 1e-12, 0.0, th)
        return np.where(is_line[idx], tr.stick + th, np.clip(val, 0.0, tr.stick))

    def junctions(self) -> FloatArray:
        """Route coordinates where the route passes the pole P (empty for the circle and the interval)."""
        if not isinstance(self.track, Lollipop):
            return np.zeros(0)
        c = self.track.loop
        rs: list[float] = []
        for kind, _k, v0, v1, ra, _rb in self.pieces:
            if kind == "line":
                lo, hi = min(v0, v1), max(v0, v1)
                m = np.arange(np.ceil(lo / c - 1e-12), np.floor(hi / c + 1e-12) + 1)
                rs.extend(ra + (m * c - v0) * np.sign(v1 - v0 if v1 != v0 else 1.0))
        s = self.direction * (np.array(sorted(set(np.round(rs, 12)))) - self.r_start)
        return np.sort(s[(s >= self.sigma_min - 1e-12) & (s <= self.sigma_max + 1e-12)])


_Piece = tuple[str, int, float, float, float, float]  # (kind, k, v_from, v_to, r_from, r_to), see Route


def _direction(diffs: Sequence[float]) -> int:
    """Orientation (+1 or -1) of a route from its corners' arc lengths relative to the start (metres, along ``r``).

    The corner farthest from the start gets ``σ > 0`` (the first of equally far ones): a continuous rule
    except where two corners on opposite sides are exactly equally far, a set of measure zero (the goal's own
    displacement, which may vanish, decides only when it is the farthest). A robot that does not move: +1.
    """
    best = 0.0
    for d in diffs:
        if abs(d) > abs(best):
            best = d
    return -1 if best < 0 else 1


def _at_junctions_on_the_line(track: Track, lifts: Sequence[Lift], ends: set[int], tol: float) -> list[Lift]:
    """The lifts with every stick point at depth 0 (within ``tol``) moved onto the line (the junction ``P_k``); the
    start and the goal (indices ``ends``) only when exactly at P: a robot a hair below P keeps its own position."""
    c = getattr(track, "loop", 0.0)
    pts = []
    for i, lf in enumerate(lifts):
        if lf.kind == "stick" and (lf.v <= 0.0 if i in ends else lf.v <= tol):
            pts.append(Lift("line", 0, lf.k * c))
        else:
            pts.append(lf)
    return pts


def _unrolled_line(track: Track, pts: Sequence[Lift]) -> tuple[tuple[_Piece, ...], FloatArray]:
    """The circle's line (the points' span and one turn each way) or the interval; ``r`` of every point."""
    c = getattr(track, "loop", 0.0)
    line_vals = [p.v for p in pts if p.kind == "line"] + [p.k * c for p in pts if p.kind == "stick"]
    lo, hi = min(line_vals), max(line_vals)
    if isinstance(track, Interval):
        ext_lo, ext_hi = 0.0, track.stick
    else:
        ext_lo, ext_hi = lo - c, hi + c
    pieces = (("line", 0, ext_lo, ext_hi, 0.0, ext_hi - ext_lo),)
    return pieces, np.array([p.v - ext_lo for p in pts])


def _lollipop_line(
    track: Lollipop, pts: Sequence[Lift], ends: set[int], tol: float
) -> tuple[tuple[_Piece, ...], FloatArray]:
    """The geodesic line of the lollipop's cover through the points: one copy of the stick alone, or the unrolled
    loop with at most one stick copy hanging at each end; ``r`` of every point.

    Raises
    ------
    PlanningError
        The points visit more than two stick copies, or branch off the line at a lift of P.
    """
    c, ell = track.loop, track.stick
    sticks = sorted({p.k for p in pts if p.kind == "stick"})
    line_vals = [p.v for p in pts if p.kind == "line"] + [k * c for k in sticks]
    lo, hi = min(line_vals), max(line_vals)
    if len(sticks) > 2:
        raise PlanningError(f"robot visits {len(sticks)} copies of the stick: not a geodesic route")
    only_stick = (
        all(p.kind == "stick" or abs(p.v - sticks[0] * c) <= (0.0 if i in ends else tol) for i, p in enumerate(pts))
        if sticks
        else False
    )
    if only_stick and len(sticks) == 1:
        k = sticks[0]
        stick_piece: tuple[_Piece, ...] = (("stick", k, ell, 0.0, 0.0, ell),)  # free end up to P_k: r = ℓ − x
        return stick_piece, np.array([ell - (p.v if p.kind == "stick" else 0.0) for p in pts])
    # a stick hangs at the low (high) end of the line if no point of the line lies below (above) its P_k; the
    # start and the goal count exactly, other corners within ``tol``
    line_pts = [(p.v, 0.0 if i in ends else tol) for i, p in enumerate(pts) if p.kind == "line"]
    low_stick = [k for k in sticks if abs(k * c - lo) <= tol and all(v >= k * c - t for v, t in line_pts)]
    high_stick = [
        k for k in sticks if abs(k * c - hi) <= tol and k not in low_stick and all(v <= k * c + t for v, t in line_pts)
    ]
    if len(low_stick) + len(high_stick) != len(sticks):
        raise PlanningError("robot's path branches off its route at a lift of P: not a geodesic route")
    parts: list[_Piece] = []
    r0 = 0.0
    if low_stick:
        parts.append(("stick", low_stick[0], ell, 0.0, 0.0, ell))
        r0 = ell
        line_lo = lo
    else:
        line_lo = lo - c
    line_hi = hi if high_stick else hi + c
    parts.append(("line", 0, line_lo, line_hi, r0, r0 + line_hi - line_lo))
    r1 = r0 + line_hi - line_lo
    if high_stick:
        parts.append(("stick", high_stick[0], 0.0, ell, r1, r1 + ell))
    r_list = []
    for p in pts:
        if p.kind == "stick":
            r_list.append(ell - p.v if p.k in low_stick else r1 + p.v)
        else:
            r_list.append(r0 + p.v - line_lo)
    return tuple(parts), np.array(r_list)


def directed_route(route: Route) -> DirectedRoute:
    """A paper track's route as a :class:`~mpa.geometry.DirectedRoute` on :meth:`Track.as_graph_track`.

    The route coordinate is kept (``breaks`` run from ``sigma_min`` to ``sigma_max``); the unrolled loop is cut
    into one piece per turn, so every piece lies on one edge (``stick`` or ``loop``) with its offset affine in σ.

    Parameters
    ----------
    route : Route

    Returns
    -------
    DirectedRoute
        Built once per route (cached on it: a route is immutable).
    """
    cached = route.__dict__.get("_directed_route")
    if cached is not None:
        return cached
    out = _directed_route(route)
    object.__setattr__(route, "_directed_route", out)
    return out


def _directed_route(route: Route) -> DirectedRoute:
    tr = route.track
    breaks, alpha, beta, is_line = route._affine()
    lo = np.concatenate([[route.sigma_min], breaks])
    hi = np.concatenate([breaks, [route.sigma_max]])
    names = ("stick", "loop") if isinstance(tr, Lollipop) else (("loop",) if isinstance(tr, Circle) else ("stick",))
    stick_edge, loop_edge = 0, len(names) - 1
    c = getattr(tr, "loop", 0.0)
    edges: list[int] = []
    dirs: list[int] = []
    entry: list[float] = []
    lengths: list[float] = []

    def piece(edge: int, s0: float, s1: float, a: float, b: float, shift: float) -> None:
        edges.append(edge)
        dirs.append(1 if b >= 0 else -1)
        entry.append(a + b * s0 - shift)
        lengths.append(s1 - s0)

    s_min, s_max = route.sigma_min, route.sigma_max
    for s0, s1, a, b, line in zip(lo.tolist(), hi.tolist(), alpha.tolist(), beta.tolist(), is_line.tolist()):
        s0, s1 = max(s0, s_min), min(s1, s_max)
        if s1 < s0:
            continue
        if not line or isinstance(tr, Interval):
            piece(stick_edge, s0, s1, a, b, 0.0)
            continue
        # the unrolled loop coordinate U = a + b·σ: one piece per turn, cut where U is a multiple of c
        u0, u1 = a + b * s0, a + b * s1
        cuts = [k * c for k in range(math.floor(min(u0, u1) / c) + 1, math.ceil(max(u0, u1) / c))]
        ss = sorted({s0, s1, *(min(max((x - a) / b, s0), s1) for x in cuts)})
        for p0, p1 in itertools.pairwise(ss):
            m = math.floor((a + b * 0.5 * (p0 + p1)) / c)
            piece(loop_edge, p0, p1, a, b, m * c)
        if len(ss) == 1:  # a piece of length 0
            piece(loop_edge, s0, s1, a, b, math.floor((a + b * s0) / c) * c)
    # valid by construction (s1 >= s0, directions ±1): DirectedRoute.from_pieces without its checks
    breaks = float(s_min) + np.concatenate([[0.0], np.cumsum(np.asarray(lengths, dtype=float))])
    return DirectedRoute(
        np.asarray(edges, dtype=np.int64), np.asarray(dirs, dtype=np.int64), np.asarray(entry, dtype=float), breaks
    )


def affine_position(
    breaks: FloatArray,
    A: FloatArray,
    B: FloatArray,
    is_line: NDArray[np.bool_],
    interval: bool,
    stick: float,
    loop: float,
    sigma: float,
) -> float:
    """Scalar twin of :meth:`Route.position`: the track coordinate at route coordinate ``sigma`` (metres).

    The same cases and operations on one float, in plain Python, so that it can also be compiled
    (:mod:`trajopt.verify.sampling`). The arguments are :meth:`Route.affine_form` (``stick = 0`` on a circle).
    """
    if len(A) == 1:
        idx = 0
    else:  # searchsorted(breaks, sigma, side="left")
        lo, hi = 0, len(breaks)
        while lo < hi:
            mid = (lo + hi) // 2
            if breaks[mid] < sigma:
                lo = mid + 1
            else:
                hi = mid
        idx = lo
    val = A[idx] + B[idx] * sigma
    if interval or not is_line[idx]:
        return min(max(val, 0.0), stick)
    th = val % loop
    if th >= loop - 1e-12:
        th = 0.0
    return stick + th
