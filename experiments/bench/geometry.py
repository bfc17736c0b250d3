"""Exact geometry of the baselines' motions: joint straight moves, joint paths, single-route segments.

A baseline planner (OMPL, grid search) returns a *joint path*: waypoints in track coordinates and, between two
waypoints, a *leg* in which each robot runs through a short list of :class:`~mpa.routes.RobotMove` (one straight
move per edge of the track, the robots progressing proportionally: both route coordinates are affine in the
leg's parameter). Two facts make every check here exact:

- On one leg piece where each robot stays on one edge, the graph distance between the robots is the minimum of
  affine functions of the parameter (and of ``|s - t|`` on one edge), so its minimum is at an end or 0 where the
  robots meet. The legs are written as routes on the track's graph form (:func:`move_route`) and measured by
  :mod:`mpa.geometry`, the project's one module of graph distance (:func:`joint_move_min_distance`).
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
from mpa.geometry import DirectedRoute, GraphGeometry, RouteGeometry
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
    "move_route",
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


def _edges(track: Track) -> tuple[GraphGeometry, int, int]:
    """The graph form's metric and the indices of its ``stick`` and ``loop`` edges (-1 where there is none)."""
    g = track.as_graph_track()
    names = g.edge_names
    return g.geometry, names.index("stick") if "stick" in names else -1, names.index("loop") if "loop" in names else -1


def move_route(track: Track, moves: Sequence[RobotMove]) -> DirectedRoute:
    """The moves of one robot as a :class:`~mpa.geometry.DirectedRoute` on ``track.as_graph_track()``.

    Route coordinate = travel along the moves; a loop move is cut where its unwrapped angle passes a multiple of
    ``c`` (the robot passes P), so that every piece lies on one edge with an affine offset.
    """
    _geo, stick, loop = _edges(track)
    c = _loop_data(track)[1] if loop >= 0 else 0.0
    edges: list[int] = []
    dirs: list[int] = []
    entry: list[float] = []
    lengths: list[float] = []
    for m in moves:
        sign = 1 if m.delta >= 0 else -1
        if m.edge == "stick":
            edges.append(stick)
            dirs.append(sign)
            entry.append(float(m.start))
            lengths.append(abs(float(m.delta)))
            continue
        u0, u1 = float(m.start), float(m.start + m.delta)
        lo, hi = min(u0, u1), max(u0, u1)
        cuts = [k * c for k in range(math.floor(lo / c) + 1, math.ceil(hi / c))]
        pts = [u0, *(cuts if sign > 0 else cuts[::-1]), u1]
        for a, b in itertools.pairwise(pts):
            k = math.floor(0.5 * (a + b) / c)
            edges.append(loop)
            dirs.append(sign)
            entry.append(a - k * c)
            lengths.append(abs(b - a))
    return DirectedRoute.from_pieces(edges, dirs, entry, lengths)


def single_edge_min_distance(track: Track, a: RobotMove, b: RobotMove) -> float:
    """Exact minimum of the graph distance while A and B each run one straight move on one edge.

    Both robots progress proportionally (parameter ``t ∈ [0, 1]``: ``x = start + t·delta``). Computed by
    :mod:`mpa.geometry` on the track's graph form (:func:`joint_move_min_distance`).

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
    return joint_move_min_distance(track, (a,), (b,))


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

    Each move passes P at most once; the moves are cut there and :meth:`mpa.geometry.GraphGeometry.segment_min`
    (exact) is applied to the pieces.

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
    geo, stick, loop = _edges(track)
    c = _loop_data(track)[1]
    n = len(a0)
    moves = [(np.asarray(a_loop, bool), np.asarray(a0, float), np.asarray(da, float))]
    moves.append((np.asarray(b_loop, bool), np.asarray(b0, float), np.asarray(db, float)))
    cuts = [np.zeros(n), np.ones(n)]
    for is_loop, x0, dx in moves:
        lo = np.minimum(x0, x0 + dx)
        k = np.floor(lo / c) + 1.0
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (k * c - x0) / dx
        cuts.append(np.where(is_loop & np.isfinite(t) & (t > 0.0) & (t < 1.0), t, 1.0))
    ts = np.sort(np.stack(cuts, axis=1), axis=1)  # (n, 4)
    t0, t1 = ts[:, :-1].ravel(), ts[:, 1:].ravel()
    row = np.repeat(np.arange(n), 3)
    keep = t1 > t0  # the cuts hold 0 and 1: every row keeps at least one piece
    t0, t1, row = t0[keep], t1[keep], row[keep]
    ends = []
    for is_loop, x0, dx in moves:
        lp, x, d = is_loop[row], x0[row], dx[row]
        m = np.floor((x + 0.5 * (t0 + t1) * d) / c)
        shift = np.where(lp, m * c, 0.0)
        ends.append((np.where(lp, loop, stick), x + t0 * d - shift, x + t1 * d - shift))
    (ea, a_s, a_e), (eb, b_s, b_e) = ends
    sub = geo.segment_min(ea, eb, np.stack([a_s, b_s], axis=-1), np.stack([a_e, b_e], axis=-1))
    best = np.full(n, np.inf)
    np.minimum.at(best, row, sub)
    return best


def joint_move_min_distance(track: Track, moves_a: Sequence[RobotMove], moves_b: Sequence[RobotMove]) -> float:
    """Exact minimum distance along a leg in which each robot runs through consecutive single-edge moves.

    The robots progress proportionally to their own travel: the leg is the straight line from ``(0, 0)`` to the
    two travels in route coordinates of :func:`move_route`, whose exact minimum is
    :meth:`mpa.geometry.RouteGeometry.polyline_min_distance`.
    """
    geo = _edges(track)[0]
    ra, rb = move_route(track, moves_a), move_route(track, moves_b)
    return RouteGeometry(geo, (ra, rb)).polyline_min_distance(np.array([[0.0, 0.0], [ra.length, rb.length]]))


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
