"""The graph planner's result: :class:`GraphPlan`, a :class:`~mpa.plans.MotionPlan`."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from mpa._arrays import FloatArray
from mpa.freespace import PolygonId
from mpa.geometry import DirectedRoute
from mpa.graph_track import GraphTrack, Position
from mpa.plans import sample_parameter


@dataclass(frozen=True, eq=False)
class GraphPlan:
    """A collision-free motion of two robots on a graph track (frozen; plain numpy arrays).

    A :class:`mpa.plans.MotionPlan` (``layout`` is :attr:`track`, ``layout_start``/``layout_goal`` are
    :attr:`start`/:attr:`goal`, ``layout_routes`` is ``(route_a, route_b)``, ``route_waypoints`` is
    :attr:`waypoints`, ``domain`` is None).

    Attributes
    ----------
    track : GraphTrack
    start, goal : tuple of two (edge index, offset)
        Robot A first (metres from the edge's tail).
    clearance : float
        D asked for (metres); ``clearance_used`` is what the free space was built with (D = 0: a tiny D > 0).
    objective : str
        ``"fastest"`` or ``"shortest"``.
    speeds : tuple of float
        ``(vA, vB)`` in m/s for the makespan estimate and ``"fastest"``.
    segment_cells : tuple of PolygonId, length K - 1
        Free polygon ``(e, f, k)`` holding each straight segment.
    segment_offsets : ndarray, shape (K - 1, 2, 2)
        Segment ends in the cell's offsets: ``[i, 0] = (s, t)`` at its start, ``[i, 1]`` at its end (metres).
    waypoints : ndarray, shape (K, 2)
        Corners in route coordinates ``(r_A, r_B)`` (metres travelled along each robot's route).
    route_a, route_b : DirectedRoute
        The robots' routes (edges, directions ±1, entry offsets, route-coordinate breakpoints).
    word : tuple of str
        The cells the path crosses (``"eA×eB"``), consecutive repeats merged and immediate returns ``x y x -> x``
        cancelled: a label of the path's class (not a complete homotopy invariant).
    makespan : float
        Estimate (seconds): ``sum of max(|Δs|/vA, |Δt|/vB)`` over the segments (speed limits only).
    length : float
        Euclidean length in the plane of offsets (metres).
    lower_bound : float or None
        On a track with lane rules (:mod:`mpa.planners.rules`): a lower bound of the optimum under them, the optimum
        of the query without the rules (seconds for ``"fastest"``, metres for ``"shortest"``) and, for
        ``"fastest"``, at least each robot's least time alone under the rules; None otherwise.
    """

    track: GraphTrack
    start: tuple[Position, Position]
    goal: tuple[Position, Position]
    clearance: float
    clearance_used: float
    objective: str
    speeds: tuple[float, float]
    segment_cells: tuple[PolygonId, ...]
    segment_offsets: FloatArray
    waypoints: FloatArray
    route_a: DirectedRoute
    route_b: DirectedRoute
    word: tuple[str, ...]
    makespan: float
    length: float
    _times: FloatArray = field(repr=False, default_factory=lambda: np.zeros(1))
    lower_bound: float | None = None

    @property
    def n_corners(self) -> int:
        """K, the number of corners."""
        return len(self.waypoints)

    @property
    def corner_offsets(self) -> FloatArray:
        """Corners in cell offsets, shape (K, 2): segment starts, then the last segment's end (metres)."""
        if len(self.segment_offsets) == 0:
            return np.array([[self.start[0][1], self.start[1][1]]])
        return np.vstack([self.segment_offsets[:, 0], self.segment_offsets[-1:, 1]])

    @property
    def corner_cells(self) -> tuple[PolygonId, ...]:
        """Cell of each corner (the cell of the segment leaving it; the last corner: of the segment entering it)."""
        if not self.segment_cells:
            (ea, sa), (eb, sb) = self.start
            return ((ea, eb, 0 if ea != eb or sa > sb else 1),)
        return (*self.segment_cells, self.segment_cells[-1])

    def path_s(self, u: Any) -> FloatArray:
        """Route coordinates at path parameter ``u ∈ [0, 1]`` (proportional to the time estimate). Shape (..., 2)."""
        u = np.clip(np.asarray(u, dtype=float), 0.0, 1.0)
        w = self.waypoints
        if len(w) == 1 or self._times[-1] <= 0:
            return np.broadcast_to(w[0], (*u.shape, 2)).copy()
        tau = u * self._times[-1]
        return np.stack([np.interp(tau, self._times, w[:, 0]), np.interp(tau, self._times, w[:, 1])], axis=-1)

    def positions(self, u: Any) -> tuple[tuple[NDArray[np.int64], FloatArray], tuple[NDArray[np.int64], FloatArray]]:
        """Per robot ``(edge index, offset)`` arrays at path parameter ``u``."""
        r = self.path_s(u)
        return self.route_a.positions(r[..., 0]), self.route_b.positions(r[..., 1])

    def sample_s(self, n: int) -> tuple[FloatArray, FloatArray]:
        """``n >= 2`` values of ``u`` evenly in [0, 1] and :meth:`path_s` there: shapes (n,) and (n, 2)."""
        u = sample_parameter(n)
        return u, self.path_s(u)

    def sample(self, n: int) -> tuple[FloatArray, FloatArray]:
        """The same as :meth:`sample_s` (``(u, route coordinates)``; the class's own name)."""
        return self.sample_s(n)

    def min_distance(self) -> float:
        """Exact minimum graph distance between the robots along the whole path (metres)."""
        return self.track.geometry.route_min_distance(self.route_a, self.route_b, self.waypoints)

    # ------------------------------------------------------------------ the MotionPlan interface
    @property
    def layout(self) -> GraphTrack:
        """The track (:attr:`track`)."""
        return self.track

    @property
    def layout_start(self) -> tuple[Position, Position]:
        """:attr:`start`."""
        return self.start

    @property
    def layout_goal(self) -> tuple[Position, Position]:
        """:attr:`goal`."""
        return self.goal

    @property
    def layout_routes(self) -> tuple[DirectedRoute, DirectedRoute]:
        """``(route_a, route_b)``."""
        return self.route_a, self.route_b

    @property
    def route_waypoints(self) -> FloatArray:
        """Corners in route coordinates, shape (K, 2) (metres): :attr:`waypoints`."""
        return self.waypoints

    @property
    def domain(self) -> None:
        """None: the graph planner has no domains of continuity."""
        return None

    def to_dict(self) -> dict[str, Any]:
        """JSON-friendly summary (positions by canonical name, routes by edge name)."""
        tr = self.track
        names = list(tr.edge_names)
        return {
            "track": "graph",
            "start": [tr.position_name(*p) for p in self.start],
            "goal": [tr.position_name(*p) for p in self.goal],
            "clearance": self.clearance,
            "clearance_used": self.clearance_used,
            "objective": self.objective,
            "speeds": list(self.speeds),
            "makespan": self.makespan,
            "length": self.length,
            "word": list(self.word),
            "waypoints": self.waypoints.tolist(),
            "segments": [
                {"cell": [names[c[0]], names[c[1]], c[2]], "from": o[0].tolist(), "to": o[1].tolist()}
                for c, o in zip(self.segment_cells, self.segment_offsets)
            ],
            "routes": {"a": self.route_a.to_list(names), "b": self.route_b.to_list(names)},
            **({} if self.lower_bound is None else {"lower_bound": self.lower_bound}),
        }
