"""Exact geometry of the baselines' motions: joint straight moves, joint paths, single-route segments.

A baseline planner (OMPL, grid search) returns a *joint path*: waypoints in track coordinates and, between two
waypoints, a *leg* in which each robot runs through a short list of :class:`~mpa.routes.RobotMove` (one straight
move per edge of the track, the robots progressing proportionally: both route coordinates are affine in the
leg's parameter). Two facts make every check here exact:

- On one leg piece where each robot stays on one edge, the graph distance between the robots is piecewise affine
  in the parameter, with breakpoints where the robots meet on the stick, where the loop coordinate difference of
  two loop robots is a multiple of ``c/2``, or where a loop robot's angle from P is a multiple of ``c/2``
  (:func:`single_edge_min_distance`). Its minimum over the piece is at one of those points or at an end.
- A robot whose moves stay on one geodesic line of the track's universal cover (it may turn back along it) has
  one :class:`~mpa.routes.Route`. A joint path is cut where a robot would branch off its line (it steps into a
  side branch and comes back: it must stop there), and every piece becomes a polyline in route coordinates σ
  (:func:`split_routes`), which ``trajopt``'s time parametrization and verification gate accept unchanged.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from mpa.errors import PlanningError
from mpa.routes import Lift, RobotMove, Route, lift_moves
from mpa.tracks import Circle, Lollipop, Track

__all__ = [
    "JointPath",
    "RouteSegment",
    "edge_position",
    "joint_move_min_distance",
    "leg_moves_circle",
    "leg_moves_geodesic",
    "leg_moves_track_coordinates",
    "single_edge_min_distance",
    "single_edge_min_distance_vec",
    "split_routes",
]

FloatArray = NDArray[np.float64]
Leg = tuple[tuple[RobotMove, ...], tuple[RobotMove, ...]]
#: Tolerance (metres) of the line test in the universal cover.
GEODESIC_TOL = 1e-9


def _loop_data(track: Track) -> tuple[float, float]:
    """``(ℓ, c)``: the track coordinate of P (0 for the circle) and the loop length."""
    if isinstance(track, Lollipop):
        return track.stick, track.loop
    if isinstance(track, Circle):
        return 0.0, track.loop
    raise PlanningError(f"the benchmark supports lollipop and circle tracks, not {type(track).__name__}")


def edge_position(track: Track, edge: str, x: float) -> float:
    """Track coordinate of edge-local coordinate ``x`` (stick: ``p``; loop: unwrapped angle ``θ`` from P)."""
    if edge == "stick":
        return x
    ell, c = _loop_data(track)
    th = x % c
    if th >= c - 1e-12:
        th = 0.0
    return ell + th


def _multiples_in(lo: float, hi: float, step: float) -> range:
    return range(math.ceil(lo / step - 1e-12), math.floor(hi / step + 1e-12) + 1)


def single_edge_min_distance(track: Track, a: RobotMove, b: RobotMove) -> float:
    """Exact minimum of the graph distance while A and B each run one straight move on one edge.

    Both robots progress proportionally (parameter ``t ∈ [0, 1]``: ``x = start + t·delta``).

    Parameters
    ----------
    track : Track
        A lollipop or a circle.
    a, b : RobotMove
        The moves of A and B (``edge`` "stick" with ``x = p`` or "loop" with ``x = θ`` unwrapped).

    Returns
    -------
    float
        The minimum distance (metres).
    """
    ts = [0.0, 1.0]
    if a.edge == "stick" and b.edge == "stick":
        w0, dw = a.start - b.start, a.delta - b.delta
        if dw != 0.0:
            t = -w0 / dw
            if 0.0 < t < 1.0:
                ts.append(t)
    else:
        half = 0.5 * _loop_data(track)[1]
        if a.edge == "loop" and b.edge == "loop":
            w0, dw = a.start - b.start, a.delta - b.delta
        elif a.edge == "loop":
            w0, dw = a.start, a.delta
        else:
            w0, dw = b.start, b.delta
        if dw != 0.0:
            for k in _multiples_in(min(w0, w0 + dw), max(w0, w0 + dw), half):
                t = (k * half - w0) / dw
                if 0.0 < t < 1.0:
                    ts.append(t)
    best = math.inf
    for t in ts:
        pa = edge_position(track, a.edge, a.start + t * a.delta)
        pb = edge_position(track, b.edge, b.start + t * b.delta)
        best = min(best, track.distance_scalar(pa, pb))
    return best


def single_edge_min_distance_vec(
    track: Track,
    a_loop: NDArray[np.bool_],
    a0: FloatArray,
    da: FloatArray,
    b_loop: NDArray[np.bool_],
    b0: FloatArray,
    db: FloatArray,
) -> FloatArray:
    """Vectorized :func:`single_edge_min_distance` for many short moves (each ``|delta| < c/4``).

    Parameters
    ----------
    track : Track
    a_loop, b_loop : ndarray of bool, shape (E,)
        Whether each robot's move runs on the loop (else on the stick).
    a0, da, b0, db : ndarray, shape (E,)
        Edge-local start coordinates and signed lengths.

    Returns
    -------
    ndarray, shape (E,)
    """
    ell, c = _loop_data(track)
    half = 0.5 * c

    def pos(is_loop: NDArray[np.bool_], x: FloatArray) -> FloatArray:
        th = np.mod(x, c)
        th = np.where(th >= c - 1e-12, 0.0, th)
        return np.where(is_loop, ell + th, x)

    def dist(t: FloatArray) -> FloatArray:
        return track.distance(pos(a_loop, a0 + t * da), pos(b_loop, b0 + t * db))

    best = np.minimum(dist(np.zeros_like(a0)), dist(np.ones_like(a0)))
    ss = ~a_loop & ~b_loop
    both = ss | (a_loop & b_loop)
    w0 = np.where(both, a0 - b0, np.where(a_loop, a0, b0))
    dw = np.where(both, da - db, np.where(a_loop, da, db))
    with np.errstate(divide="ignore", invalid="ignore"):
        k0 = np.ceil(np.minimum(w0, w0 + dw) / half - 1e-12)
        cands = [np.where(ss, -w0 / dw, np.nan)]  # stick-stick: where the robots meet
        cands += [np.where(ss, np.nan, ((k0 + e) * half - w0) / dw) for e in (0.0, 1.0)]
    for t in cands:
        ok = np.isfinite(t) & (t > 0.0) & (t < 1.0)
        if np.any(ok):
            best = np.where(ok, np.minimum(best, dist(np.where(ok, t, 0.0))), best)
    return best


def joint_move_min_distance(track: Track, moves_a: Sequence[RobotMove], moves_b: Sequence[RobotMove]) -> float:
    """Exact minimum distance along a leg in which each robot runs through consecutive single-edge moves.

    The robots progress proportionally to their own travel. The leg is cut where either robot changes edge and
    :func:`single_edge_min_distance` is applied to every piece.
    """
    pieces = []
    for mv in (moves_a, moves_b):
        total = sum(abs(m.delta) for m in mv)
        cuts = [0.0]
        acc = 0.0
        for m in mv:
            acc += abs(m.delta)
            cuts.append(acc / total if total > 0 else 1.0)
        pieces.append((mv, cuts))
    ts = sorted({0.0, 1.0, *pieces[0][1][1:-1], *pieces[1][1][1:-1]})
    best = math.inf
    for t0, t1 in itertools.pairwise(ts):
        if t1 - t0 <= 0.0:
            continue
        sub = []
        for mv, cuts in pieces:
            tm = 0.5 * (t0 + t1)
            k = 0
            while k < len(mv) - 1 and cuts[k + 1] <= tm:
                k += 1
            m = mv[k]
            span = cuts[k + 1] - cuts[k]
            if span <= 0.0:
                sub.append(RobotMove(m.edge, m.start + m.delta, 0.0))
                continue
            f0, f1 = (t0 - cuts[k]) / span, (t1 - cuts[k]) / span
            sub.append(RobotMove(m.edge, m.start + f0 * m.delta, (f1 - f0) * m.delta))
        best = min(best, single_edge_min_distance(track, sub[0], sub[1]))
    return best


# ---------------------------------------------------------------------------------------------------
def _stay(track: Track, p: float) -> RobotMove:
    ell, _c = _loop_data(track)
    if isinstance(track, Lollipop) and p <= ell:
        return RobotMove("stick", p, 0.0)
    return RobotMove("loop", p - ell, 0.0)


def leg_moves_track_coordinates(track: Track, p0: float, p1: float) -> tuple[RobotMove, ...]:
    """A robot's moves when its *track coordinate* goes linearly from ``p0`` to ``p1`` (lollipop).

    On the lollipop this is the motion a planner in a real vector space of track coordinates makes: across P
    between the stick and the loop, but never through the loop's seam at ``ℓ + c`` (it goes round instead).
    """
    if not isinstance(track, Lollipop):
        raise PlanningError("track-coordinate interpolation is the lollipop's; use leg_moves_circle on a circle")
    ell = track.stick
    if p0 == p1:
        return (_stay(track, p0),)
    if p0 <= ell and p1 <= ell:
        return (RobotMove("stick", p0, p1 - p0),)
    if p0 >= ell and p1 >= ell:
        return (RobotMove("loop", p0 - ell, p1 - p0),)
    if p0 < ell:
        return RobotMove("stick", p0, ell - p0), RobotMove("loop", 0.0, p1 - ell)
    return RobotMove("loop", p0 - ell, ell - p0), RobotMove("stick", ell, p1 - ell)


def leg_moves_geodesic(track: Track, p0: float, p1: float) -> tuple[RobotMove, ...]:
    """A robot's moves along a shortest path of the lollipop from ``p0`` to ``p1`` (through the seam if shorter).

    Ties (antipodal points on the loop) go counter-clockwise.
    """
    if not isinstance(track, Lollipop):
        return leg_moves_circle(track, p0, p1)
    ell, c = track.stick, track.loop
    if p0 == p1:
        return (_stay(track, p0),)
    if p0 <= ell and p1 <= ell:
        return (RobotMove("stick", p0, p1 - p0),)

    def arc(th0: float, th1: float) -> float:
        d = (th1 - th0) % c
        return d - c if d > 0.5 * c else d

    if p0 >= ell and p1 >= ell:
        return (RobotMove("loop", p0 - ell, arc(p0 - ell, p1 - ell)),)
    if p0 < ell:
        return RobotMove("stick", p0, ell - p0), RobotMove("loop", 0.0, arc(0.0, p1 - ell))
    return RobotMove("loop", p0 - ell, arc(p0 - ell, 0.0)), RobotMove("stick", ell, p1 - ell)


def leg_moves_circle(track: Track, p0: float, p1: float) -> tuple[RobotMove, ...]:
    """A robot's move on the circle along the shorter arc from ``p0`` to ``p1`` (OMPL's SO(2) interpolation)."""
    c = _loop_data(track)[1]
    d = (p1 - p0) % c
    if d > 0.5 * c:
        d -= c
    return (RobotMove("loop", p0, d),)


# ---------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class JointPath:
    """Waypoints of both robots and, between consecutive waypoints, each robot's single-edge moves.

    Attributes
    ----------
    track : Track
    states : ndarray, shape (K, 2)
        Waypoints (track coordinates of A and B).
    legs : tuple of (tuple of RobotMove, tuple of RobotMove)
        ``K − 1`` legs: the moves of A and of B from waypoint k to k + 1 (proportional progress).
    """

    track: Track
    states: FloatArray
    legs: tuple[Leg, ...]

    @classmethod
    def from_states(cls, track: Track, states: FloatArray, geodesic: bool = False) -> JointPath:
        """Legs by the interpolation of the planner's state space: track coordinates (lollipop) or SO(2)
        (circle); with ``geodesic`` every robot takes a shortest path of the track instead."""
        st = np.asarray(states, dtype=float)
        if isinstance(track, Circle):
            fn = leg_moves_circle
        else:
            fn = leg_moves_geodesic if geodesic else leg_moves_track_coordinates
        legs = tuple(
            (fn(track, float(st[k, 0]), float(st[k + 1, 0])), fn(track, float(st[k, 1]), float(st[k + 1, 1])))
            for k in range(len(st) - 1)
        )
        return cls(track, st, legs)

    def min_distance(self) -> float:
        """Exact minimum separation along the whole path (metres)."""
        if not self.legs:
            return float(self.track.distance(self.states[0, 0], self.states[0, 1]))
        return min(joint_move_min_distance(self.track, ma, mb) for ma, mb in self.legs)

    def leg_min_distances(self) -> FloatArray:
        """Exact minimum separation of every leg. Shape (K − 1,)."""
        return np.array([joint_move_min_distance(self.track, ma, mb) for ma, mb in self.legs])


@dataclass(frozen=True)
class RouteSegment:
    """A piece of a joint path along which each robot stays on one geodesic line of the cover (one route).

    Inside a segment a robot may turn back along its line (its route coordinate is then not monotone); it
    cannot branch off it. The segment is a polyline in the plane of route coordinates σ.

    Attributes
    ----------
    routes : tuple of Route
        Route of A and of B on this piece.
    nodes : ndarray, shape (M, 2)
        Waypoints in route coordinates σ (consecutive duplicates removed; ``M ≥ 2``).
    states : ndarray, shape (M, 2)
        The same waypoints in track coordinates.
    """

    routes: tuple[Route, Route]
    nodes: FloatArray
    states: FloatArray


class _LineHull:
    """The part of the lollipop's universal cover a robot has visited, while it is still a segment of a line.

    The cover is the line of unrolled loop coordinates ``U`` with a copy ``k`` of the stick hanging at every
    ``U = k·c``. The visited set is a segment of one geodesic line iff every stick copy entered below its
    junction hangs at an end of the visited ``U``-range (at most one per end).
    """

    def __init__(self, track: Track) -> None:
        self.c = track.loop if isinstance(track, Lollipop) else 0.0
        self.lollipop = isinstance(track, Lollipop)
        self.lo = math.inf
        self.hi = -math.inf
        self.sticks: dict[int, float] = {}

    def add(self, lift: Lift) -> bool:
        """Add a visited point (the motion to it runs along one edge); False if the set stops being a line."""
        if not self.lollipop:
            return True
        if lift.kind == "stick" and lift.v > GEODESIC_TOL:
            self.sticks[lift.k] = max(self.sticks.get(lift.k, 0.0), lift.v)
            u = None
        else:
            u = lift.k * self.c if lift.kind == "stick" else lift.v
        if u is not None:
            self.lo, self.hi = min(self.lo, u), max(self.hi, u)
        if len(self.sticks) > 2:
            return False
        if self.lo > self.hi:  # only ever on one stick
            return len(self.sticks) <= 1
        ends = []
        for k in self.sticks:
            j = k * self.c
            tol = GEODESIC_TOL * max(1.0, abs(j))
            if abs(j - self.lo) <= tol:
                ends.append(0)
            elif abs(j - self.hi) <= tol:
                ends.append(1)
            else:
                return False
        if len(ends) == 2 and (ends[0] == ends[1] or self.hi - self.lo <= GEODESIC_TOL):
            return False
        return True


def _robot_lifts(track: Track, path: JointPath, r: int) -> tuple[list[Lift], list[int]]:
    """All lifts of robot ``r`` (one per move end) and the lift index of every waypoint."""
    flat: list[RobotMove] = []
    wp = [0]
    for leg in path.legs:
        flat.extend(leg[r])
        wp.append(len(flat))
    return lift_moves(track, flat, float(path.states[0, r])), wp


def split_routes(path: JointPath) -> list[RouteSegment]:
    """Cut a joint path into :class:`RouteSegment` pieces where a robot would leave its geodesic line.

    That only happens on the lollipop, when a robot steps into a branch and comes back (e.g. down the stick
    and back up onto the loop on the other side of P): it must stop at the turning point, and both robots stop
    there. Never on the circle. Greedy: a segment grows waypoint by waypoint while both robots' visited sets
    stay segments of lines (:class:`_LineHull`).

    Returns
    -------
    list of RouteSegment
        Empty if the path does not move.
    """
    track = path.track
    data = [_robot_lifts(track, path, r) for r in (0, 1)]
    n_wp = len(path.states)
    cuts = [0]

    def fresh(k: int) -> list[_LineHull]:
        hulls = [_LineHull(track), _LineHull(track)]
        for r in (0, 1):
            lifts, wp = data[r]
            hulls[r].add(lifts[wp[k]])
        return hulls

    hulls = fresh(0)
    for k in range(n_wp - 1):
        ok = all(hulls[r].add(data[r][0][i + 1]) for r in (0, 1) for i in range(data[r][1][k], data[r][1][k + 1]))
        if not ok:
            cuts.append(k)
            hulls = fresh(k)
            for r in (0, 1):
                lifts, wp = data[r]
                for i in range(wp[k], wp[k + 1]):
                    hulls[r].add(lifts[i + 1])
    cuts.append(n_wp - 1)
    segments = []
    for s0, s1 in itertools.pairwise(cuts):
        if s1 <= s0:
            continue
        routes = []
        sig = []
        for r in (0, 1):
            lifts, wp = data[r]
            route, sigma = Route.through(track, lifts[wp[s0] : wp[s1] + 1])
            routes.append(route)
            sig.append(np.asarray(sigma)[np.array(wp[s0 : s1 + 1]) - wp[s0]])
        nodes = np.stack(sig, axis=1)
        states = path.states[s0 : s1 + 1]
        keep = np.concatenate([[True], np.max(np.abs(np.diff(nodes, axis=0)), axis=1) > 1e-12])
        if keep.sum() < 2:
            continue
        idx = np.flatnonzero(keep)
        idx[-1] = len(nodes) - 1
        segments.append(RouteSegment((routes[0], routes[1]), nodes[idx], states[idx]))
    return segments
