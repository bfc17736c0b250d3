"""Plans of two robots: the interface every plan satisfies (:class:`MotionPlan`) and the paper planner's result
:class:`Plan` (frozen, plain numpy arrays).

:class:`MotionPlan` names what the paper's planner (:class:`Plan`) and the complete graph planner
(:class:`~mpa.planners.graph.GraphPlan`) both say of a motion, with one meaning: the layout the robots move on (a
paper track through :meth:`~mpa.tracks.Track.as_graph_track`), start and goal as positions on it, each robot's
route as a sequence of directed edges (:class:`~mpa.geometry.DirectedRoute`), the path as a polyline in route
coordinates, the class of the path as a word, the domain, the clearance and the exact minimum distance
(docs/conventions.md, "Plans").
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike

from mpa._arrays import FloatArray, IntArray
from mpa.errors import InvalidInputError
from mpa.geometry import DirectedRoute
from mpa.graph_track import GraphTrack, Position
from mpa.routes import RobotMove, Route, directed_route, lift_moves, lift_position
from mpa.skeleton import Skeleton
from mpa.tracks import Track

__all__ = ["JointMove", "MotionPlan", "Plan", "PlanStep", "build_plan", "sample_parameter"]

#: Per robot ``(edge indices, offsets)`` on the layout: what :meth:`MotionPlan.positions` returns.
LayoutPositions = tuple[tuple[IntArray, FloatArray], tuple[IntArray, FloatArray]]
JointMove = tuple[RobotMove, RobotMove]
STEP_NAMES = ("preliminary", "main", "final")


@runtime_checkable
class MotionPlan(Protocol):
    """A collision-free motion of two robots (A first) on a layout, as every planner's plan describes it.

    Satisfied by :class:`Plan` (the paper's planner on an interval, circle or lollipop) and
    :class:`~mpa.planners.graph.GraphPlan` (the complete planner on any layout, also with lane rules or
    footprints). A paper track is the layout :meth:`~mpa.tracks.Track.as_graph_track` (edges ``stick`` and
    ``loop``). The path is a polyline in *route coordinates* ``σ = (σ_A, σ_B)`` (metres along each robot's route,
    shape (2,)); between corners both robots move at constant speeds along their routes.

    Attributes
    ----------
    layout : GraphTrack
        The track the robots move on (a paper track's graph form).
    layout_start, layout_goal : tuple of two (edge index, offset)
        Start and goal of robot A and robot B as positions on ``layout`` (offset in metres from the edge's tail).
    layout_routes : (DirectedRoute, DirectedRoute)
        Each robot's route on ``layout``: the directed edges it travels in order, with the route coordinate of
        every piece boundary (``breaks``; a paper plan's routes keep its σ, a graph plan's start at 0).
    route_waypoints : ndarray, shape (K, 2)
        Corners of the path in route coordinates (metres); the first is the start, the last the goal.
    word : tuple of str
        The path's class as a word: the reduced edge word in the skeleton graph for a paper plan (a homotopy
        invariant, :mod:`mpa.homotopy`), the cells crossed for a graph plan (a label of the class).
    domain : int or None
        Domain of continuity of the paper's planner (docs/conventions.md, "Domains of continuity"); None for the
        graph planner, whose plans are optimal rather than continuous on domains.
    clearance : float
        The clearance D the query asked for (metres).
    """

    @property
    def layout(self) -> GraphTrack: ...

    @property
    def layout_start(self) -> tuple[Position, Position]: ...

    @property
    def layout_goal(self) -> tuple[Position, Position]: ...

    @property
    def layout_routes(self) -> tuple[DirectedRoute, DirectedRoute]: ...

    @property
    def route_waypoints(self) -> FloatArray: ...

    @property
    def word(self) -> tuple[str, ...]: ...

    @property
    def domain(self) -> int | None: ...

    @property
    def clearance(self) -> float: ...

    def path_s(self, u: ArrayLike) -> FloatArray:
        """Route coordinates at path parameter ``u ∈ [0, 1]`` (clipped; metres). Shape ``u.shape + (2,)``."""
        ...

    def positions(self, u: ArrayLike) -> LayoutPositions:
        """Per robot ``(edge indices, offsets)`` on :attr:`layout` at path parameter ``u`` (each of ``u``'s shape)."""
        ...

    def sample_s(self, n: int) -> tuple[FloatArray, FloatArray]:
        """``n >= 2`` values of ``u`` evenly in [0, 1] and the route coordinates there: shapes (n,) and (n, 2)."""
        ...

    def min_distance(self) -> float:
        """Exact minimum graph distance between the robots along the whole path (metres)."""
        ...


def sample_parameter(n: object) -> FloatArray:
    """``n`` values of the path parameter evenly in [0, 1] (shape (n,)); ``n`` must be an integer >= 2.

    Raises
    ------
    InvalidInputError
        ``n`` is not an integer >= 2.
    """
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 2:
        raise InvalidInputError(f"number of samples is {n!r}, expected an integer >= 2")
    return np.linspace(0.0, 1.0, int(n))


@dataclass(frozen=True)
class PlanStep:
    """One of the three steps of the algorithm.

    Attributes
    ----------
    name : str
        ``"preliminary"``, ``"main"`` or ``"final"``.
    description : str
        The instruction in the paper's words.
    u_start, u_end : float
        The part of the path parameter ``u ∈ [0, 1]`` the step occupies (equal if the step is empty).
    waypoints : ndarray, shape (K, 2)
        Corner states of the step (track coordinates, first = where the step starts).
    """

    name: str
    description: str
    u_start: float
    u_end: float
    waypoints: FloatArray


@dataclass(frozen=True)
class Plan:
    """A motion plan α: [0, 1] → C² for two robots, as produced by the paper's algorithm.

    Between consecutive corners every robot moves at constant speed along its route, so the path is the polyline
    ``waypoints_s`` in route coordinates, parametrized by ``u`` proportionally to the larger of the two robots'
    travel (``knots``).

    A :class:`MotionPlan` (``layout``, ``layout_start``, ``layout_goal``, ``layout_routes``, ``route_waypoints``,
    ``path_s``, ``positions``, ``sample_s``, ``word``, ``domain``, ``clearance``, exact ``min_distance()``).
    Its own names speak in the paper's track coordinates: ``start``, ``goal``, ``waypoints``, :meth:`path` and
    :meth:`sample` (states, not ``(u, σ)``), ``routes`` (:class:`~mpa.routes.Route` in the track's cover).

    Attributes
    ----------
    track : Track
    start, goal : ndarray, shape (2,)
        Track coordinates of (A, B).
    clearance : float
        The clearance the query was checked against (metres).
    domain : int
        Domain of continuity (numbering of docs/conventions.md, "Domains of continuity").
    rule : str
        The instruction of the domain, in words.
    steps : tuple of PlanStep
        Preliminary, main and final step.
    knots : ndarray, shape (K,)
        Path parameter of every corner, from 0 to 1.
    waypoints : ndarray, shape (K, 2)
        Corner states in track coordinates.
    waypoints_s : ndarray, shape (K, 2)
        Corner states in route coordinates σ (metres along each robot's route).
    routes : tuple of Route
        Route of A and of B.
    skeleton : Skeleton
        The skeleton of the configuration space.
    skeleton_start, skeleton_goal : ndarray, shape (2,)
        ``x_i' = H₁(start)`` and ``x_f' = H₁(goal)``.
    word : tuple of str
        Reduced edge word of ``H₁∘α`` in the skeleton graph (the path's homotopy class).
    travel : ndarray, shape (2,)
        Distance travelled by A and by B (metres).
    regime : str
        ``"paper"`` (the paper's algorithm), or for a lollipop whose clearance forbids generalized antipodal
        states: ``"retreat"`` (D > h) or ``"loop"`` (ℓ < D ≤ h); see :mod:`mpa.planners`.
    length : float
        Length of the path in the max-norm of route coordinates (metres): ``u`` is proportional to it, so
        equally spaced samples are at most ``length / (n − 1)`` apart for each robot.
    """

    track: Track
    start: FloatArray
    goal: FloatArray
    clearance: float
    domain: int
    rule: str
    steps: tuple[PlanStep, ...]
    knots: FloatArray
    waypoints: FloatArray
    waypoints_s: FloatArray
    routes: tuple[Route, Route]
    skeleton: Skeleton
    skeleton_start: FloatArray
    skeleton_goal: FloatArray
    word: tuple[str, ...]
    travel: FloatArray = field(default_factory=lambda: np.zeros(2))
    length: float = 0.0
    regime: str = "paper"

    def path_s(self, u: ArrayLike) -> FloatArray:
        """Route coordinates α_σ(u) (vectorized). Shape ``u.shape + (2,)``."""
        uu: FloatArray = np.clip(np.asarray(u, dtype=float), 0.0, 1.0)
        if self.knots[-1] <= 0.0:
            return np.broadcast_to(self.waypoints_s[0], (*uu.shape, 2)).copy()
        sa = np.interp(uu, self.knots, self.waypoints_s[:, 0])
        sb = np.interp(uu, self.knots, self.waypoints_s[:, 1])
        return np.stack([sa, sb], axis=-1)

    def path(self, u: ArrayLike) -> FloatArray:
        """The path α(u) in track coordinates (vectorized). Shape ``u.shape + (2,)``.

        ``path(0)`` is the start and ``path(1)`` the goal exactly (the routes reproduce them to a few ulps; the
        ends are then set bit for bit).
        """
        uu = np.asarray(u, dtype=float)
        s = self.path_s(uu)
        out = np.stack([self.routes[0].position(s[..., 0]), self.routes[1].position(s[..., 1])], axis=-1)
        out[uu <= 0.0] = self.start
        out[uu >= 1.0] = self.goal
        return out

    def sample(self, n: int = 400) -> FloatArray:
        """α at ``n`` equally spaced values of u in [0, 1] in track coordinates (first = start, last = goal,
        exactly). Shape (n, 2). The plan's own sampling; :meth:`sample_s` is the one of :class:`MotionPlan`."""
        out = self.path(np.linspace(0.0, 1.0, max(int(n), 2)))
        out[0], out[-1] = self.start, self.goal
        return out

    def samples_needed(self, fraction: float = 0.01) -> int:
        """Number of equally spaced samples so that consecutive points are at most ``fraction`` of the track's
        total length apart for each robot."""
        step = fraction * self.track.total_length
        return int(np.ceil(self.length / step)) + 1

    def min_distance(self, n: int | None = None) -> float:
        """Smallest graph distance between the robots along the path (metres).

        Exact by default (:class:`MotionPlan`): the polyline ``waypoints_s`` on :attr:`layout_routes`, cut where
        either robot changes edge, minimised exactly on every piece
        (:meth:`mpa.geometry.GraphGeometry.route_min_distance`). With ``n``: the minimum over :meth:`sample`
        ``(n)`` in track coordinates instead (at most the exact value plus one sample step of travel).
        """
        if n is not None:
            st = self.sample(n)
            return float(np.min(self.track.distance(st[:, 0], st[:, 1])))
        ra, rb = self.layout_routes
        return self.layout.geometry.route_min_distance(ra, rb, self.waypoints_s)

    # ------------------------------------------------------------------ the MotionPlan interface
    @property
    def layout(self) -> GraphTrack:
        """The track's graph form (:meth:`mpa.tracks.Track.as_graph_track`; edges ``stick`` and/or ``loop``)."""
        return self.track.as_graph_track()

    @property
    def layout_start(self) -> tuple[Position, Position]:
        """The start as positions ``((edge, offset) of A, (edge, offset) of B)`` on :attr:`layout`."""
        return _layout_pair(self.track, self.start)

    @property
    def layout_goal(self) -> tuple[Position, Position]:
        """The goal as positions ``((edge, offset) of A, (edge, offset) of B)`` on :attr:`layout`."""
        return _layout_pair(self.track, self.goal)

    @property
    def layout_routes(self) -> tuple[DirectedRoute, DirectedRoute]:
        """The routes of A and B as directed edges on :attr:`layout` (:func:`mpa.routes.directed_route`; route
        coordinates σ kept)."""
        return directed_route(self.routes[0]), directed_route(self.routes[1])

    @property
    def route_waypoints(self) -> FloatArray:
        """Corners in route coordinates σ, shape (K, 2) (metres): :attr:`waypoints_s`."""
        return self.waypoints_s

    def positions(self, u: ArrayLike) -> LayoutPositions:
        """Per robot ``(edge indices, offsets)`` on :attr:`layout` at path parameter ``u`` (each of ``u``'s shape)."""
        s = self.path_s(u)
        ra, rb = self.layout_routes
        return ra.positions(s[..., 0]), rb.positions(s[..., 1])

    def sample_s(self, n: int) -> tuple[FloatArray, FloatArray]:
        """``n >= 2`` values of ``u`` evenly in [0, 1] and :meth:`path_s` there: shapes (n,) and (n, 2).

        (:meth:`sample` gives the states in track coordinates instead.)
        """
        u = sample_parameter(n)
        return u, self.path_s(u)

    def to_dict(self, samples: int = 400) -> dict[str, object]:
        """A JSON-ready description of the plan, with the path sampled at ``samples`` equally spaced u."""
        return {
            "track": self.track.to_dict(),
            "start": self.start.tolist(),
            "goal": self.goal.tolist(),
            "clearance": self.clearance,
            "domain": self.domain,
            "regime": self.regime,
            "rule": self.rule,
            "skeleton_start": self.skeleton_start.tolist(),
            "skeleton_goal": self.skeleton_goal.tolist(),
            "word": list(self.word),
            "steps": [
                {
                    "name": s.name,
                    "description": s.description,
                    "u": [s.u_start, s.u_end],
                    "waypoints": s.waypoints.tolist(),
                }
                for s in self.steps
            ],
            "knots": self.knots.tolist(),
            "waypoints": self.waypoints.tolist(),
            "waypoints_s": self.waypoints_s.tolist(),
            "route_lengths": [self.routes[0].length, self.routes[1].length],
            "travel": self.travel.tolist(),
            "length": self.length,
            "path": self.sample(samples).tolist(),
        }


def _layout_pair(track: Track, q: FloatArray) -> tuple[Position, Position]:
    """Track coordinates ``q`` (shape (2,)) as positions ``((edge, offset), (edge, offset))`` on the graph form."""
    e, o = track.to_graph_position(np.asarray(q, dtype=float))
    return (int(e[0]), float(o[0])), (int(e[1]), float(o[1]))


def build_plan(
    track: Track,
    start: FloatArray,
    goal: FloatArray,
    clearance: float,
    domain: int,
    rule: str,
    steps: Sequence[tuple[str, Sequence[JointMove]]],
    skeleton: Skeleton,
    skeleton_start: FloatArray,
    skeleton_goal: FloatArray,
    word: tuple[str, ...] | None,
    regime: str = "paper",
) -> Plan:
    """Assemble a :class:`Plan` from the three steps given as joint moves (real track coordinates)."""
    moves_a, moves_b, step_ranges = _moving_moves(steps)
    lifts_a = lift_moves(track, moves_a, float(start[0]))
    lifts_b = lift_moves(track, moves_b, float(start[1]))
    route_a, sig_a = Route.through(track, lifts_a)
    route_b, sig_b = Route.through(track, lifts_b)
    sa, sb = sig_a.tolist(), sig_b.tolist()
    knots_l, (trav_a, trav_b), total = _knots_and_travel(sa, sb)
    pos_l = [[lift_position(track, la), lift_position(track, lb)] for la, lb in zip(lifts_a, lifts_b)]
    pos_l[0], pos_l[-1] = [float(start[0]), float(start[1])], [float(goal[0]), float(goal[1])]
    pos = np.array(pos_l)
    ws = np.array([sa, sb]).T.copy()
    knots = np.array(knots_l)
    travel = np.array([trav_a, trav_b])
    plan_steps = []
    for (desc, _), name, (i0, i1) in zip(steps, STEP_NAMES, step_ranges):
        plan_steps.append(PlanStep(name, desc, knots_l[i0], knots_l[i1], pos[i0 : i1 + 1]))
    result = Plan(
        track=track,
        start=np.asarray(start, dtype=float),
        goal=np.asarray(goal, dtype=float),
        clearance=clearance,
        domain=domain,
        rule=rule,
        steps=tuple(plan_steps),
        knots=knots,
        waypoints=pos,
        waypoints_s=ws,
        routes=(route_a, route_b),
        skeleton=skeleton,
        skeleton_start=np.asarray(skeleton_start, dtype=float),
        skeleton_goal=np.asarray(skeleton_goal, dtype=float),
        word=() if word is None else word,
        travel=travel,
        length=float(total),
        regime=regime,
    )
    if word is None:  # read the class off the sampled path (regimes whose main step is not a skeleton path)
        from mpa.homotopy import path_word

        n = max(2001, result.samples_needed(0.0005))
        return replace(result, word=path_word(track, result.sample(n)))
    return result


def _moving_moves(
    steps: Sequence[tuple[str, Sequence[JointMove]]],
) -> tuple[list[RobotMove], list[RobotMove], list[tuple[int, int]]]:
    """Each robot's moves of all steps in order, joint moves where neither robot moves dropped, and the range of
    move indices ``[first, end)`` of every step."""
    moves_a: list[RobotMove] = []
    moves_b: list[RobotMove] = []
    step_ranges: list[tuple[int, int]] = []
    for _desc, jm in steps:
        first = len(moves_a)
        for ma, mb in jm:
            if abs(ma.delta) <= 1e-15 and abs(mb.delta) <= 1e-15:
                continue
            moves_a.append(ma)
            moves_b.append(mb)
        step_ranges.append((first, len(moves_a)))
    return moves_a, moves_b, step_ranges


def _knots_and_travel(sa: list[float], sb: list[float]) -> tuple[list[float], tuple[float, float], float]:
    """From the corners' route coordinates of A and B: the knots ``u`` of the corners (path length by the larger
    of the two moves, normalised to [0, 1]), each robot's travel and the total length (metres)."""
    cum_l = [0.0]
    trav_a = trav_b = 0.0
    for i in range(1, len(sa)):
        da, db = abs(sa[i] - sa[i - 1]), abs(sb[i] - sb[i - 1])
        trav_a += da
        trav_b += db
        cum_l.append(cum_l[-1] + (da if da > db else db))
    total = cum_l[-1]
    knots_l = [c / total for c in cum_l] if total > 0 else [0.0] * len(cum_l)
    return knots_l, (trav_a, trav_b), total
