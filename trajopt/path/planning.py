"""What the trajectory pipeline asks of the planners: the layout planner with the pipeline's margins
(:class:`GraphPlanner`), each robot's speed limit along its route, and a plan's waypoints in route coordinates."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from mpa.errors import InvalidInputError, NoMotionError
from mpa.footprint import Footprints
from mpa.graph_track import GraphTrack
from mpa.planners.graph import GraphPlan, plan_graph
from mpa.plans import MotionPlan, Plan
from trajopt.explain import _decimal_at_most, _RejectedError, explain_rejection, explain_threshold  # noqa: F401
from trajopt.path.planview import plan_view
from trajopt.timing import Limits

__all__ = ["GraphPlanner", "route_speed_limits", "view_waypoints"]


@dataclass(frozen=True, eq=False)
class GraphPlanner:
    """The complete graph planner on one layout, in the generator's planner interface (``plan(start, goal)``).

    Plans with objective ``"fastest"`` for the speed limits, for the clearance plus ``margin`` (the gate's
    between-rows margin at the generator's rate); if no motion keeps that, for the bare clearance (or raises the
    planner's :class:`~mpa.errors.InvalidInputError` / :class:`~mpa.errors.NoMotionError` for it).

    Parameters
    ----------
    track : GraphTrack
    clearance : float
        D (m, >= 0).
    speeds : (float, float)
        Speed limits of A and B (m/s).
    margin : float
        Extra separation asked of the plan (m, >= 0).
    objective : {"fastest", "shortest"}
        The graph planner's objective (:func:`mpa.planners.graph.plan_graph`).
    """

    track: GraphTrack
    clearance: float
    speeds: tuple[float, float]
    margin: float = 0.0
    objective: str = "fastest"
    footprint: Footprints | None = None
    plane_margin: float = 0.0

    def __post_init__(self) -> None:
        c = self.clearance
        number = isinstance(c, (int, float, np.integer, np.floating)) and not isinstance(c, bool)
        if not number or not np.isfinite(c) or c < 0:
            raise InvalidInputError(f"clearance is {c!r}, expected a finite number >= 0 (metres)")
        object.__setattr__(self, "clearance", float(c))

    def plan(self, start: Any, goal: Any) -> GraphPlan:
        """A :class:`~mpa.planners.graph.GraphPlan` from ``start`` to ``goal`` (pairs of positions, robot A first).

        Raises
        ------
        InvalidInputError
            Unknown edge or vertex, offset outside the edge, robots closer than the clearance at start or goal.
        NoMotionError
            No collision-free motion exists (the message says why).
        """
        fp = self.footprint
        if fp is not None and self.plane_margin > 0:  # the bodies grown by the gate's between-rows margin first
            # plus the planner's touching tolerance (bodies that close count as apart there, not at the gate)
            from mpa.planar import TOUCH as PLANAR_TOUCH

            grow = 0.5 * self.plane_margin + PLANAR_TOUCH * max(1.0, float(self.track.total_length))
            try:
                return plan_graph(
                    self.track,
                    start,
                    goal,
                    self.clearance + self.margin,
                    self.objective,
                    self.speeds,
                    fp.inflated(grow),
                )
            except (InvalidInputError, NoMotionError):
                pass  # the bare footprint decides (and names the error)
        if self.margin > 0:
            try:
                return plan_graph(
                    self.track, start, goal, self.clearance + self.margin, self.objective, self.speeds, fp
                )
            except (InvalidInputError, NoMotionError):
                pass  # the bare clearance decides (and names the error)
        return plan_graph(self.track, start, goal, self.clearance, self.objective, self.speeds, fp)


def route_speed_limits(plan: MotionPlan, limits: Limits) -> Limits:
    """``limits`` with each robot's speed capped by the lowest speed limit of the edges its route travels.

    The setpoints then keep every lane's limit on every row (checked by the gate); on a route whose edges have
    different limits the robot drives its whole route at the lowest one (conservative, not time-optimal). Returns
    ``limits`` itself when no edge of the routes has a limit.
    """
    layout = plan.layout
    if not layout.has_rules:
        return limits
    caps = []
    for route, v in zip(plan.layout_routes, limits.vmax):
        lengths = np.diff(route.breaks)
        lims = [layout.speed_limits[int(e)] for e, ln in zip(route.edges, lengths) if ln > 0]
        caps.append(min([v, *[x for x in lims if x is not None]]))
    if tuple(caps) == tuple(limits.vmax):
        return limits
    return dataclasses.replace(limits, vmax=tuple(caps))


def view_waypoints(plan: Plan | GraphPlan) -> np.ndarray:
    """The plan's polyline in route coordinates (shape (K, 2))."""
    return plan_view(plan).waypoints


def _dedupe(pts: ArrayLike) -> np.ndarray:
    p = np.atleast_2d(np.asarray(pts, dtype=float))
    keep = np.concatenate([[True], np.linalg.norm(np.diff(p, axis=0), axis=1) > 1e-12])
    out = p[keep]
    out[-1] = p[-1]
    return out
