"""One view of a plan for the pipeline: paper plans and graph plans in the same route geometry.

The pipeline (fast path, corridor, fallback, gate, export) works in *route coordinates* ``σ = (σ_A, σ_B)`` on the
exact geometry of :class:`mpa.geometry.RouteGeometry`, for every :class:`mpa.MotionPlan`: its layout
(``plan.layout``; a paper track's graph form, edges ``stick`` and ``loop``), its routes (``plan.layout_routes``)
and its corners (``plan.route_waypoints``). :func:`plan_view` builds the view once per plan (cached on it).

What differs for the paper's plans (:class:`mpa.Plan`) is small and lives here: the track coordinates (the rows'
``*_track`` columns), the skeleton word (the fast path's line must keep the plan's homotopy class, the gate checks
it) and so the gate (:func:`~trajopt.verify.gate.verify_setpoints` in track coordinates,
:func:`~trajopt.verify.gate.verify_graph_setpoints` in positions).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import cast

import numpy as np
from numpy.typing import ArrayLike

from mpa._arrays import FloatArray, IntArray
from mpa.geometry import DirectedRoute, RouteGeometry, densify_polyline
from mpa.graph_track import GraphTrack
from mpa.homotopy import path_word
from mpa.plans import MotionPlan, Plan
from mpa.routes import Route, directed_route
from mpa.tracks import Track
from trajopt.timing import Limits
from trajopt.verify.gate import VerificationReport, verify_graph_setpoints, verify_setpoints
from trajopt.verify.kernels import track_positions
from trajopt.verify.rows import Setpoints, rows_of

__all__ = ["REST_SPEED", "PlanView", "densify", "plan_view", "route_geometry"]

Pair = tuple[tuple[int, float], tuple[int, float]]
#: Speeds (m/s) at or below which a robot counts as at rest (its ``*_dir`` is 0).
REST_SPEED = 1e-9


def densify(pts: ArrayLike, step: float) -> FloatArray:
    """Points along a polyline (shape (n, 2)) with at most ``step`` between consecutive ones (max-norm).

    :func:`mpa.geometry.densify_polyline`.
    """
    return densify_polyline(pts, step)


@dataclass(frozen=True, eq=False)
class PlanView:
    """A plan as the pipeline sees it (build with :func:`plan_view`).

    Attributes
    ----------
    plan : MotionPlan
    graph : GraphTrack
        The plan's layout (a paper track's graph form).
    routes : (DirectedRoute, DirectedRoute)
        The robots' routes; route coordinates as in the plan (σ for paper plans, distance travelled for graph plans).
    geom : RouteGeometry
        Exact separation in route coordinates.
    waypoints : ndarray, shape (K, 2)
        The plan's polyline in route coordinates (metres).
    is_graph : bool
        The plan is not one of the paper's (:class:`mpa.Plan`): no track coordinates, no skeleton word.
    """

    plan: MotionPlan
    graph: GraphTrack
    routes: tuple[DirectedRoute, DirectedRoute]
    geom: RouteGeometry
    waypoints: FloatArray
    is_graph: bool

    @property
    def paper(self) -> Plan:
        """The plan as the paper's :class:`mpa.Plan` (only when not :attr:`is_graph`)."""
        return cast(Plan, self.plan)

    @property
    def lower(self) -> FloatArray:
        """Smallest route coordinate of each robot (metres). Shape (2,)."""
        if not self.is_graph:  # the paper route's own σ range (its directed route's first break, exactly)
            return np.array([self.paper.routes[0].sigma_min, self.paper.routes[1].sigma_min], dtype=float)
        return np.array([self.routes[0].breaks[0], self.routes[1].breaks[0]])

    @property
    def upper(self) -> FloatArray:
        """Largest route coordinate of each robot (metres). Shape (2,)."""
        if not self.is_graph:  # the paper route's own σ range (not the sum of its pieces' lengths)
            return np.array([self.paper.routes[0].sigma_max, self.paper.routes[1].sigma_max], dtype=float)
        return np.array([self.routes[0].breaks[-1], self.routes[1].breaks[-1]])

    def path_s(self, u: ArrayLike) -> FloatArray:
        """The plan's path in route coordinates at parameter ``u ∈ [0, 1]``. Shape (..., 2)."""
        return np.asarray(self.plan.path_s(u), dtype=float)

    # ------------------------------------------------------------------------------------ positions
    def positions(self, s: ArrayLike, v: ArrayLike | None = None) -> tuple[IntArray, FloatArray]:
        """Edge indices and offsets of both robots at route coordinates ``s`` (shape (N, 2)).

        At a route break (a robot on a vertex between two pieces) the piece the robot moves into is taken: the
        later one when it moves forward or rests, the earlier one when its velocity ``v`` is negative.

        Returns
        -------
        edges : ndarray of int, shape (N, 2)
        offsets : ndarray, shape (N, 2)
            Metres from each edge's tail, within ``[0, length]``.
        """
        S = np.atleast_2d(np.asarray(s, dtype=float))
        V = np.zeros_like(S) if v is None else np.atleast_2d(np.asarray(v, dtype=float))
        edges = np.empty(S.shape, dtype=np.int64)
        offs = np.empty(S.shape)
        for r, route in enumerate(self.routes):
            x, i = _route_piece(route, S[:, r], V[:, r])
            edges[:, r] = route.edges[i]
            lengths = self.graph.lengths[route.edges[i]]
            offs[:, r] = np.clip(route.offsets_on(i, x), 0.0, lengths)
        return edges, offs

    def graph_rows(self, s: FloatArray, v: FloatArray) -> tuple[IntArray, FloatArray, IntArray, FloatArray]:
        """Everything the rows of a graph plan's motion say about positions, from one search of the route breaks.

        The results of :meth:`positions` ``(s, v)``, :meth:`directions` ``(s, v)`` and :meth:`track_coordinates`
        ``(s)`` (the offsets on the piece taken when the robot moves forward or rests), element for element the
        same numbers as those three calls give.

        Parameters
        ----------
        s, v : ndarray, shape (N, 2)
            Route coordinates (m) and velocities (m/s) of both robots at the rows.

        Returns
        -------
        edges : ndarray of int, shape (N, 2)
        offsets : ndarray, shape (N, 2)
            Metres from each edge's tail (:meth:`positions`).
        directions : ndarray of int, shape (N, 2)
            +1, -1 or 0 (:meth:`directions`).
        track : ndarray, shape (N, 2)
            :meth:`track_coordinates` of ``s`` (m).
        """
        S = np.atleast_2d(np.asarray(s, dtype=float))
        V = np.atleast_2d(np.asarray(v, dtype=float))
        edges = np.empty(S.shape, dtype=np.int64)
        offs = np.empty(S.shape)
        dirs = np.empty(S.shape, dtype=np.int64)
        track = np.empty(S.shape)
        for r, route in enumerate(self.routes):
            x, i, forward = _route_pieces(route, S[:, r], V[:, r])
            edges[:, r] = route.edges[i]
            offs[:, r] = np.clip(route.offsets_on(i, x), 0.0, self.graph.lengths[route.edges[i]])
            sign = np.where(V[:, r] > REST_SPEED, 1, np.where(V[:, r] < -REST_SPEED, -1, 0))
            dirs[:, r] = sign * route.dirs[i]
            track[:, r] = offs[:, r]
            other = np.flatnonzero(forward != i)  # moving backwards onto a break: the forward piece's offset
            if len(other):
                k = forward[other]
                track[other, r] = np.clip(route.offsets_on(k, x[other]), 0.0, self.graph.lengths[route.edges[k]])
        return edges, offs, dirs, track

    def directions(self, s: ArrayLike, v: ArrayLike) -> IntArray:
        """Direction of travel on the current edge: +1 along its orientation, -1 against, 0 at rest. Shape (N, 2)."""
        S = np.atleast_2d(np.asarray(s, dtype=float))
        V = np.atleast_2d(np.asarray(v, dtype=float))
        out = np.zeros(S.shape, dtype=np.int64)
        for r, route in enumerate(self.routes):
            _x, i = _route_piece(route, S[:, r], V[:, r])
            sign = np.where(V[:, r] > REST_SPEED, 1, np.where(V[:, r] < -REST_SPEED, -1, 0))
            out[:, r] = sign * route.dirs[i]
        return out

    def track_coordinates(self, s: ArrayLike) -> FloatArray:
        """Track coordinates of a paper plan at route coordinates ``s`` (graph plan: the offsets). Shape (N, 2)."""
        S = np.atleast_2d(np.asarray(s, dtype=float))
        if self.is_graph:
            return self.positions(S)[1]
        (br_a, A_a, B_a, line_a, interval, stick, loop), (br_b, A_b, B_b, line_b, *_) = (
            r.affine_form() for r in self.paper.routes
        )
        out = np.empty(S.shape)
        track_positions(
            np.ascontiguousarray(S), br_a, A_a, B_a, line_a, br_b, A_b, B_b, line_b, interval, stick, loop, out
        )
        return out

    def endpoints(self) -> tuple[Pair, Pair]:
        """Start and goal as positions ``((edge, offset) of A, (edge, offset) of B)``."""
        return self.plan.layout_start, self.plan.layout_goal

    def separation(self, which: str) -> float:
        """Graph distance between the robots at the ``"start"`` or the ``"goal"`` (metres)."""
        st, gl = self.endpoints()
        (ea, oa), (eb, ob) = st if which == "start" else gl
        return float(self.graph.geometry.distance_scalar(ea, oa, eb, ob))

    # ------------------------------------------------------------------------------ class and gate
    def keeps_class(self, pts: ArrayLike) -> bool:
        """Whether the polyline ``pts`` (route coordinates) has the plan's homotopy class.

        Paper plans: the reduced skeleton word of the densified polyline equals the plan's word. Graph plans:
        always True (any motion along the plan's routes is a motion of the query; the gate checks the clearance).
        """
        if self.is_graph:
            return True
        track = self.paper.track
        dense = densify(pts, 0.004 * track.total_length)
        return tuple(path_word(track, self.track_coordinates(dense))) == tuple(self.plan.word)

    def verify(
        self,
        rows: Setpoints | ArrayLike,
        *arrays: ArrayLike,
        limits: Limits,
        clearance: float,
        rate: float,
        track_pos: ArrayLike | None = None,
        limits_used: Limits | None = None,
        positions: tuple[IntArray, FloatArray] | None = None,
    ) -> VerificationReport:
        """The independent gate on rows of this plan's motion (see :mod:`trajopt.verify.gate`).

        ``limits``: the limits asked for; ``limits_used``: the limits the motion declares it was timed with (the
        rows and the bound between rows are checked with them, and each against ``limits``; default ``limits``).

        ``rows``: a :class:`~trajopt.verify.rows.Setpoints` (``t, s, v, a, j``), or positionally the arrays
        ``t, s, v, a, j``. Paper plans: the rows' track coordinates are ``rows.track`` (or ``track_pos``, shape
        (N, 2)) when given, else :meth:`track_coordinates` of ``s``; graph plans: ``positions`` (edges and offsets,
        shape (N, 2) each) when given (as :meth:`graph_rows` computes them), else :meth:`positions` of ``s`` and
        ``v``. The gate checks the positions against the routes either way (the rows' distance to their route
        positions).
        """
        rows = rows_of(rows, arrays, ("t", "s", "v", "a", "j"))
        if track_pos is not None:
            rows = replace(rows, track=np.asarray(track_pos))
        if not self.is_graph:  # the paper's gate: track coordinates and the skeleton word too
            plan = self.paper
            if rows.track is None:
                rows = replace(rows, track=self.track_coordinates(rows.s))
            return verify_setpoints(
                plan.track,
                plan.routes,
                rows,
                limits=limits,
                clearance=clearance,
                start=plan.start,
                goal=plan.goal,
                word=plan.word,
                rate=rate,
                limits_used=limits_used,
            )
        edges, offs = self.positions(rows.s, rows.v) if positions is None else positions
        return verify_graph_setpoints(
            self.graph.geometry,
            self.routes,
            replace(rows, edges=edges, offsets=offs),
            limits=limits,
            clearance=clearance,
            start=self.plan.layout_start,
            goal=self.plan.layout_goal,
            rate=rate,
            limits_used=limits_used,
            oneway=self.graph.oneway if self.graph.has_rules else None,
            speed_limits=self.graph.speed_limits if self.graph.has_rules else None,
        )

    def route_lists(self, s: ArrayLike | None = None) -> dict[str, list[dict[str, object]]]:
        """Per robot (``"a"``, ``"b"``) its route: edges by name with the direction travelled (JSON-ready).

        Each piece is ``{"edge", "dir", "entry", "from_s", "to_s"}`` (:meth:`mpa.geometry.DirectedRoute.to_list`).
        With ``s`` (route coordinates of a motion, shape (N, 2)) only the pieces the motion travels are listed,
        cut to the travelled range (a paper route spans its whole line in the track's cover); a robot that does not
        move gets the one piece it stands on, of length 0.
        """
        names = list(self.graph.edge_names)
        out: dict[str, list[dict[str, object]]] = {}
        for r, key in enumerate("ab"):
            pieces = self.routes[r].to_list(names)
            if s is not None:
                col = np.asarray(s, dtype=float)[:, r]
                lo, hi = float(np.min(col)), float(np.max(col))
                keep = []
                for p in pieces:
                    a, b = max(float(p["from_s"]), lo), min(float(p["to_s"]), hi)  # type: ignore[arg-type]
                    if b > a or (lo == hi and float(p["from_s"]) <= lo <= float(p["to_s"])):  # type: ignore[arg-type]
                        q = dict(p)
                        q["entry"] = float(p["entry"]) + int(p["dir"]) * (a - float(p["from_s"]))  # type: ignore[arg-type, call-overload]
                        q["from_s"], q["to_s"] = a, max(a, b)
                        keep.append(q)
                        if lo == hi:
                            break
                pieces = keep
            out[key] = pieces
        return out


def route_geometry(track: Track, routes: tuple[Route, Route]) -> RouteGeometry:
    """The :class:`mpa.geometry.RouteGeometry` of two paper-track routes (:class:`mpa.routes.Route`) on ``track``.

    Route coordinates stay the routes' σ; the metric is the track's graph form (:meth:`Track.as_graph_track`).
    """
    return RouteGeometry(track.as_graph_track().geometry, (directed_route(routes[0]), directed_route(routes[1])))


def _route_piece(route: DirectedRoute, s: FloatArray, v: FloatArray) -> tuple[FloatArray, IntArray]:
    """Route coordinates ``s`` (shape (N,)) clipped to the route, and the index of the route's piece (edge) each
    is on: at a junction the piece being entered (the one before when moving backwards, ``v < -REST_SPEED``)."""
    x, i, _ = _route_pieces(route, s, v)
    return x, i


def _route_pieces(route: DirectedRoute, s: FloatArray, v: FloatArray) -> tuple[FloatArray, IntArray, IntArray]:
    """:func:`_route_piece` and the piece each ``s`` is on when the robot moves forward or rests (the later one at a
    junction), from one clip and two searches. Shapes (N,)."""
    br = route.breaks
    x = np.clip(s, br[0], br[-1])
    right = np.searchsorted(br, x, side="right") - 1
    back = np.flatnonzero(v < -REST_SPEED)  # moving backwards: the piece before a junction (searched only there)
    piece = right.copy()
    if len(back):
        piece[back] = np.searchsorted(br, x[back], side="left") - 1
    last = len(route.edges) - 1
    return x, np.clip(piece, 0, last), np.clip(right, 0, last)


def plan_view(plan: MotionPlan) -> PlanView:
    """The :class:`PlanView` of a plan (:class:`mpa.MotionPlan`: a paper :class:`~mpa.plans.Plan`, a
    :class:`~mpa.planners.graph.GraphPlan`).

    Built once per plan (cached on the plan object).
    """
    cached = plan.__dict__.get("_trajopt_view")
    if cached is not None:
        return cast(PlanView, cached)
    graph = plan.layout
    routes = plan.layout_routes
    waypoints = np.asarray(plan.route_waypoints, dtype=float)
    # The paper's plans carry more than the interface: track coordinates and the skeleton word the gate checks.
    is_graph = not isinstance(plan, Plan)
    view = PlanView(plan, graph, routes, RouteGeometry(graph.geometry, routes), waypoints, is_graph)
    object.__setattr__(plan, "_trajopt_view", view)
    return view
