"""The fast path: a query whose straight motion in route coordinates keeps the separation, timed by one profile.

If the segment from the start to the goal in route coordinates (both robots along their routes, proportionally)
keeps the separation (exact check, :meth:`~trajopt.smoothing.RouteGeometry.polyline_min_distance`) and has the
plan's homotopy class, it is timed directly by one time-synchronised jerk-limited ruckig profile for both robots
(``Synchronization.Phase``, which keeps the straight line between two rest states), with no QP and no toppra.
The line and the phase-synchronised profile move continuously with the query. On the other side of the switch,
the hard path (:mod:`trajopt.corridor`) converges to the same line; its timing costs ``a/j`` more (its filter).
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from mpa.errors import MPAError, PlanningError
from mpa.plan import Plan
from trajopt.smoothing import RouteGeometry, polyline_word
from trajopt.timing import BlendedPath, Limits, TimeScaling, blend_polyline

__all__ = ["straight_line_clearance", "straight_scaling"]


def straight_line_clearance(plan: Plan, geom: RouteGeometry) -> float:
    """Exact minimum separation along the straight route-coordinate motion from start to goal (metres).

    Returns ``-inf`` if the line's homotopy class is not the plan's (it then never qualifies).
    """
    line = np.asarray(plan.waypoints_s)[[0, -1]]
    d = geom.polyline_min_distance(line)
    if d <= 0.0:
        return d
    try:
        word = polyline_word(geom, line)
    except MPAError:
        return float("-inf")
    return d if word == tuple(plan.word) else float("-inf")


def straight_scaling(plan: Plan, limits: Limits) -> TimeScaling:
    """One phase-synchronised ruckig profile from start to goal (rest to rest) along the straight line.

    Returns
    -------
    TimeScaling
        Of a one-piece :class:`~trajopt.timing.BlendedPath` (``s`` = Euclidean length in route coordinates).

    Raises
    ------
    PlanningError
        ruckig fails or does not keep the line (never expected for rest-to-rest).
    """
    from ruckig import InputParameter, Result, Ruckig, Synchronization, Trajectory

    t_start = time.perf_counter()
    ends = np.asarray(plan.waypoints_s, dtype=float)[[0, -1]]
    path: BlendedPath = blend_polyline(ends)
    length = path.length
    if length <= 0:
        return TimeScaling(path, np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0), 0.0, np.zeros(2))
    otg, inp, traj = Ruckig(2), InputParameter(2), Trajectory(2)
    inp.current_position = ends[0].tolist()
    inp.target_position = ends[1].tolist()
    inp.current_velocity = inp.target_velocity = [0.0, 0.0]
    inp.current_acceleration = inp.target_acceleration = [0.0, 0.0]
    inp.max_velocity = limits.v.tolist()
    inp.max_acceleration = limits.a.tolist()
    inp.max_jerk = limits.j.tolist()
    inp.synchronization = Synchronization.Phase
    res = otg.calculate(inp, traj)
    if res not in (Result.Working, Result.Finished):
        raise PlanningError(f"ruckig failed on the straight line: {res}")
    u = (ends[1] - ends[0]) / length
    r = int(np.argmax(np.abs(u)))
    prof = traj.profiles[0][r]
    other = traj.profiles[0][1 - r]
    tp = np.asarray(prof.t, dtype=float)
    if abs(u[1 - r]) > 0 and not np.allclose(np.asarray(other.t), tp, rtol=1e-9, atol=1e-12):
        raise PlanningError("ruckig's profile is not phase-synchronised")
    keep = tp > 0
    t0 = np.concatenate([[0.0], np.cumsum(tp)])[:-1][keep]
    scale = 1.0 / u[r]
    p = (np.asarray(prof.p[:7]) - ends[0, r]) * scale
    v = np.asarray(prof.v[:7]) * scale
    a = np.asarray(prof.a[:7]) * scale
    j = np.asarray(prof.j) * scale
    stats: dict[str, Any] = {"pieces": 1, "blends": 0, "jerk_time": time.perf_counter() - t_start}
    return TimeScaling(
        path,
        t0,
        p[keep],
        v[keep],
        a[keep],
        j[keep],
        float(np.sum(tp)),
        np.zeros(2),
        np.zeros(int(np.sum(keep)), dtype=np.intp),
        stats,
    )
