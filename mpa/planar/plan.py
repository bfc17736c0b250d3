"""Planning in the planar model (:func:`plan_planar`, called by the graph planner with ``footprint=``) and the
reason when the bodies cannot pass (:func:`_why_not`)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from mpa.errors import InvalidInputError, NoMotionError, PlanningError
from mpa.footprint import Disc, Footprints
from mpa.graph_track import GraphTrack, Position
from mpa.planar.corners import start_refusal
from mpa.planar.oneway import _search_sets, _why_one_way
from mpa.planar.polygons import FloatArray
from mpa.planar.search import _search
from mpa.planar.shortcut import independent_motion
from mpa.planar.space import PlanarFreeSpace, planar_free_space
from mpa.planners.search_common import SearchQuery


def _why_not(space: PlanarFreeSpace) -> str:
    """Where the layout is too narrow for the bodies: the closest two pieces of the drawing that do not meet."""
    tr = space.track
    d = space.drawing
    fps = space.footprints
    best = (math.inf, -1, -1)
    n = len(d.piece_edge)
    ends = [(d.piece_p0[p], d.piece_p0[p] + (d.piece_s1[p] - d.piece_s0[p]) * d.piece_dir[p]) for p in range(n)]
    tol = 1e-9 * max(1.0, tr.total_length)
    for p in range(n):
        for q in range(p + 1, n):
            (a0, a1), (b0, b1) = ends[p], ends[q]
            if min(float(np.hypot(*(x - y))) for x in (a0, a1) for y in (b0, b1)) <= tol:
                continue  # pieces that meet (a corner or a switch)
            dist = _seg_seg(a0, a1, b0, b1)
            if dist < best[0]:
                best = (dist, int(d.piece_edge[p]), int(d.piece_edge[q]))
    need = fps.across()
    what = "radii summed" if isinstance(fps.a, Disc) and isinstance(fps.b, Disc) else "half-widths summed"
    if best[1] >= 0 and best[0] < need:
        return (
            f"the bodies ({fps.spec()}) cannot pass each other in the plane: edges {tr.edge_names[best[1]]!r} and "
            f"{tr.edge_names[best[2]]!r} run {best[0]:.4g} m apart in the drawing; bodies that need {need:.4g} m "
            f"side by side ({what}) cannot pass there"
        )
    return (
        f"the bodies ({fps.spec()}) block each other in the plane near the switches: start and goal are in "
        "different components of the free space with footprints, although they are connected along the track"
    )


def _seg_seg(a0: FloatArray, a1: FloatArray, b0: FloatArray, b1: FloatArray) -> float:
    def pt(p: FloatArray, s0: FloatArray, s1: FloatArray) -> float:
        ab = s1 - s0
        den = float(ab @ ab)
        lam = 0.0 if den <= 0 else min(1.0, max(0.0, float((p - s0) @ ab) / den))
        return float(np.hypot(*(s0 + lam * ab - p)))

    def orient(p: FloatArray, q: FloatArray, r: FloatArray) -> float:
        return float((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]))

    o1, o2 = orient(a0, a1, b0), orient(a0, a1, b1)
    o3, o4 = orient(b0, b1, a0), orient(b0, b1, a1)
    if o1 * o2 < 0 and o3 * o4 < 0:
        return 0.0
    return min(pt(a0, b0, b1), pt(a1, b0, b1), pt(b0, a0, a1), pt(b1, a0, a1))


def plan_planar(
    track: GraphTrack,
    start: tuple[Position, Position],
    goal: tuple[Position, Position],
    clearance: float,
    objective: str,
    speeds: tuple[float, float],
    footprint: Footprints,
) -> Any:
    """Plan in the planar model (called by :func:`mpa.planners.graph.plan_graph` with ``footprint=``).

    Parameters
    ----------
    track : GraphTrack
        A layout with vertex coordinates.
    start, goal : (Position, Position)
        Robot A's and robot B's positions ``(edge, offset in metres)``.
    clearance : float
        D (metres, >= 0): the graph distance the robots keep, as in :func:`~mpa.planners.graph.plan_graph`.
    objective : {"fastest", "shortest"}
    speeds : (float, float)
        The robots' speed limits ``(vA, vB)`` (m/s, > 0).
    footprint : Footprints
        The robots' bodies in the plane (:func:`mpa.footprint.footprints`).

    Returns
    -------
    GraphPlan
        The motion, its bodies apart in the plane; timed at the edges' speed limits on a track with lane rules.

    Raises
    ------
    InvalidInputError
        Bodies overlapping at start or goal (the message gives the gap), a layout without coordinates.
    NoMotionError
        Start and goal in different components; the message names the narrow place.
    """
    from mpa.planners.graph.assemble import _assemble
    from mpa.planners.graph.reasons import _why_no_motion

    space = planar_free_space(track, clearance, footprint)
    for what, (pa, pb) in (("start", start), ("goal", goal)):
        why = start_refusal(track, space, what, pa, pb)
        if why:
            raise InvalidInputError(why)
    ca, cb = space.component_of(*start), space.component_of(*goal)
    if ca is None or ca != cb:
        bca, bcb = space.base.component_of(*start), space.base.component_of(*goal)
        if bca is None or bca != bcb:
            raise NoMotionError(_why_no_motion(track, space.base, start, goal))
        raise NoMotionError(_why_not(space))
    by_sets = None
    if any(track.oneway):  # decide first (complete, and cheaper than exhausting the shared points)
        by_sets = _search_sets(space, start, goal)
        if by_sets is None:
            raise NoMotionError(_why_one_way(space, start, goal))
    # the robots' own shortest routes at once when they are free (an optimum, no search), else the search
    query = SearchQuery(track, space.base, start, goal, objective, speeds)
    found = independent_motion(space, start, goal) or _search(space, query) or by_sets
    if found is None:  # pragma: no cover - start and goal were checked to share a component
        raise PlanningError("the search ended without reaching the goal although start and goal share a component")
    segs = [x for x in found if x[1] != x[2]]
    plan = _assemble(query, segs)
    if not track.has_rules:
        return plan
    from mpa.planners.rules import timed_at_limits

    return timed_at_limits(plan)  # the time at the edges' speed limits
