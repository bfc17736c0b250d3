"""The fast path: a query whose straight motion in route coordinates keeps the separation, timed by one profile.

If the segment from the start to the goal in route coordinates (both robots along their routes, proportionally)
keeps the separation (exact check, :meth:`mpa.geometry.RouteGeometry.polyline_min_distance`), it is timed
directly by one time-synchronised jerk-limited ruckig profile for both robots (one 1-DoF profile of the line's
length under the binding robot's limits: both robots in phase, on the line), with no QP and no toppra. The line
must also have the plan's homotopy class (paper plans; on a graph plan any motion along the plan's routes
qualifies): the generator leaves that to the gate, which checks the class of the rows (they lie on the line) and
sends a line of another class to the hard path (:meth:`trajopt.TrajectoryGenerator.generate`);
:func:`straight_line_clearance` checks both at once.
The line and the phase-synchronised profile move continuously with the query. Where the line keeps the separation
by less than two bands (:func:`trajopt.path.switch.switch_band`), :mod:`trajopt.path.switch` turns the hard path
(:mod:`trajopt.path.corridor`) into this one, so the motion is continuous across the switch.
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np

from mpa._arrays import FloatArray
from mpa.errors import MPAError
from mpa.geometry import RouteGeometry
from mpa.plans import MotionPlan
from trajopt.path.planview import plan_view
from trajopt.timing import BlendedPath, Limits, TimeScaling, blend_polyline, rest_to_rest_profile

__all__ = ["straight_line_clearance", "straight_scaling"]


def straight_line_clearance(plan: MotionPlan, geom: RouteGeometry | None = None) -> float:
    """Exact minimum separation along the straight route-coordinate motion from start to goal (metres).

    Parameters
    ----------
    plan : Plan or GraphPlan
    geom : RouteGeometry, optional
        The plan's route geometry (default: :func:`trajopt.path.planview.plan_view`'s).

    Returns
    -------
    float
        ``-inf`` if the line's homotopy class is not the plan's (it then never qualifies; paper plans only).
    """
    view = plan_view(plan)
    geom = view.geom if geom is None else geom
    line = view.waypoints[[0, -1]]
    d = geom.polyline_min_distance(line)
    if d <= 0.0:
        return d
    try:
        same = view.keeps_class(line)
    except MPAError:
        return float("-inf")
    return d if same else float("-inf")


def straight_scaling(plan: MotionPlan, limits: Limits) -> TimeScaling:
    """One jerk-limited ruckig profile from start to goal (rest to rest) along the straight line.

    The line is parametrized by its Euclidean length ``s`` in route coordinates, unit direction ``u``; robot r
    moves by ``u_r·s``, so its limits bound ``s`` by ``v_r/|u_r|`` (and likewise ``a``, ``j``). One 1-DoF
    profile of ``s`` under the smallest of those bounds is the time-optimal phase-synchronised motion of both
    robots (it is what ruckig's ``Synchronization.Phase`` gives when that exists, and exists for any limits).

    Returns
    -------
    TimeScaling
        Of a one-piece :class:`~trajopt.timing.BlendedPath` (``s`` = Euclidean length in route coordinates).

    Raises
    ------
    PlanningError
        ruckig fails (never expected for rest-to-rest).
    """
    t_start = time.perf_counter()
    ends = plan_view(plan).waypoints[[0, -1]]
    path = _line_path(ends)
    length = path.length
    if length <= 0:
        return TimeScaling(path, np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0), 0.0, np.zeros(2))
    u = (np.abs(ends[1] - ends[0]) / length).tolist()
    v_s, a_s, j_s = (  # the binding robot's limit along the line (plain floats: the same divisions as numpy's)
        min(x / ur for x, ur in zip(lim.tolist(), u) if ur > 0) for lim in (limits.v, limits.a, limits.j)
    )
    prof = rest_to_rest_profile(length, v_s, a_s, j_s)
    keep = prof.dt > 0
    t0, p, v, a, j = prof.t0[keep], prof.p, prof.v, prof.a, prof.j
    stats: dict[str, Any] = {"pieces": 1, "blends": 0, "jerk_time": time.perf_counter() - t_start}
    return TimeScaling(
        path,
        t0,
        p[keep],
        v[keep],
        a[keep],
        j[keep],
        prof.duration,
        np.zeros(2),
        np.zeros(int(np.sum(keep)), dtype=np.intp),
        stats,
    )


def _line_path(ends: FloatArray) -> BlendedPath:
    """``blend_polyline(ends)`` of a two-point polyline (one straight piece), built directly."""
    seg = ends[1] - ends[0]
    x, y = float(seg[0]), float(seg[1])
    length = math.sqrt(x * x + y * y)  # as np.linalg.norm (bit for bit)
    if length <= 1e-12:  # no straight piece: blend_polyline's single point (start == goal), or its error
        return blend_polyline(ends[:1] if length == 0.0 else ends)
    u = seg / length
    coef = np.zeros((1, 6, 2))
    coef[0, 0], coef[0, 1] = ends[0], u
    return BlendedPath(
        breaks=np.array([0.0, length]),
        coef=coef,
        is_blend=np.zeros(1, dtype=bool),
        stop=np.ones(2, dtype=bool),
        corners=ends,
        radii=np.zeros(2),
        bounds=np.stack([np.abs(u), np.zeros(2), np.zeros(2)])[None],
    )
