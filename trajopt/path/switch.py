"""Continuity across the fast/hard switch: the hard path turned into the fast path over a band of line margins.

The fast path (:mod:`trajopt.path.fastpath`: the straight route-coordinate line, one ruckig profile) is taken when the
line keeps the separation ``sep``; the hard path (:mod:`trajopt.path.corridor`: the corridor QP's nodes, their cubic
B-spline, :func:`trajopt.timing.filtered_scaling`) otherwise. The two differ at the switch (where the line's
clearance equals ``sep``): the corridor's nodes do not reach the line in a fixed number of re-centrings (they stay
millimetres to centimetres off it, and the curved path is timed slower), and on a short line the filtered timing
is slower than the single ruckig profile. Both motions are continuous in the query on their own side, so the jump
is removed by moving from one to the other continuously in the line's margin ``m = clearance(line) − sep`` over
two bands of width ``b`` (:func:`switch_band`):

1. ``0 ≤ m < b`` (geometry): the nodes ``(1 − λ)·N + λ·L``, ``λ = m/b``, between the corridor's nodes ``N`` and
   the evenly spaced nodes ``L`` of the line (the same count); their spline, timed by ``filtered_scaling``. At
   ``m = 0`` it is the hard path; at ``λ = 1`` the line itself (evenly spaced collinear nodes give the line at unit
   speed). The blended nodes' spans are checked exactly (:func:`trajopt.path.corridor.hull_clearance` of every four
   consecutive nodes keeps ``sep``), as the corridor's are.
2. ``b ≤ m < 2b`` (timing): the line, timed by the power-mean blend of the two time laws
   (:func:`blended_time_law`) with weight ``w = m/b − 1``: the filtered timing at ``w = 0``, ruckig's profile at
   ``w = 1``. The geometric path is the same (the line), so the motion stays free; the blend keeps every limit.

Beyond ``2b`` the fast path is untouched, so its speed is kept far from the switch.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from mpa.errors import PlanningError
from mpa.geometry import RouteGeometry
from mpa.graph_track import GraphTrack
from mpa.plans import MotionPlan
from mpa.tracks import Track
from trajopt.path.corridor import CorridorProblem, corridor_nodes, hull_clearance
from trajopt.path.planview import plan_view
from trajopt.timing import Limits, TimeScaling, filtered_scaling, spline_path

__all__ = ["SWITCH_BAND", "blended_time_law", "near_switch_scaling", "switch_band"]


#: Width of each of the two bands of line margins, as a share of the track's total length.
SWITCH_BAND = 0.005


def switch_band(track: Track | GraphTrack) -> float:
    """Width ``b`` (metres) of each band of line margins over which the hard path turns into the fast path.

    :data:`SWITCH_BAND` times the track's total length (0.01 m on the paper's lollipop 1/1).
    """
    return SWITCH_BAND * float(track.total_length)


def blended_time_law(first: TimeScaling, second: TimeScaling, w: float) -> TimeScaling:
    """The time law ``(1 − w)·s₁(t·T₁/T) + w·s₂(t·T₂/T)`` of one path, timed by ``first`` and ``second``.

    ``T₁``, ``T₂`` are the two durations (s) and ``T = max_k ((1 − w)·T₁ᵏ + w·T₂ᵏ)^(1/k)`` over ``k = 1, 2, 3``
    (power means): the k-th derivative of the blend is at most ``lim_k·((1 − w)·T₁ᵏ + w·T₂ᵏ)/Tᵏ ≤ lim_k``, so
    on a straight path (where each robot's speed, acceleration and jerk are fixed multiples of ``ṡ, s̈, s⃛``) the
    blend keeps every limit both keep. ``T`` moves continuously from ``T₁`` (``w = 0``) to ``T₂`` (``w = 1``).

    Parameters
    ----------
    first, second : TimeScaling
        Rest-to-rest time laws of the same path (the same parameter ``s``, ``0 ≤ s ≤`` the path's length).
    w : float
        Weight of ``second``, in ``[0, 1]``.

    Returns
    -------
    TimeScaling
        Of ``first.path``; phases of constant jerk at the union of both laws' (rescaled) phase starts.
    """
    w = float(min(max(w, 0.0), 1.0))
    t1, t2 = first.duration, second.duration
    if t1 <= 0.0 or t2 <= 0.0:
        return first if w < 1.0 else second
    big = max(((1.0 - w) * t1**k + w * t2**k) ** (1.0 / k) for k in (1, 2, 3))
    f1, f2 = t1 / big, t2 / big  # time factors: law k is evaluated at t·f_k
    t0 = np.concatenate([first.t0 / f1, second.t0 / f2])
    t0 = np.unique(np.minimum(t0, big))
    t0 = t0[t0 < big]
    ends = np.concatenate([t0[1:], [big]])
    mid = 0.5 * (t0 + ends)
    p1, v1, a1, _ = first.param(t0 * f1)
    p2, v2, a2, _ = second.param(t0 * f2)
    j1 = first.param(mid * f1)[3]
    j2 = second.param(mid * f2)[3]
    p = (1.0 - w) * p1 + w * p2
    v = (1.0 - w) * f1 * v1 + w * f2 * v2
    a = (1.0 - w) * f1**2 * a1 + w * f2**2 * a2
    j = (1.0 - w) * f1**3 * j1 + w * f2**3 * j2
    stats = dict(first.stats)
    stats.update(time_law_weight=w)
    return TimeScaling(
        first.path,
        t0,
        p,
        v,
        a,
        j,
        float(big),
        np.zeros(len(first.path.coef) + 1),
        np.zeros(0, dtype=np.intp),
        stats,
    )


def near_switch_scaling(
    plan: MotionPlan,
    geom: RouteGeometry,
    separation: float,
    limits: Limits,
    problem: CorridorProblem,
    margin: float,
    band: float,
    fast: TimeScaling,
    timings: dict[str, Any] | None = None,
) -> tuple[TimeScaling, dict[str, Any]]:
    """The timing of a query whose straight line keeps the separation by a margin ``0 ≤ margin < 2·band``.

    See the module docstring: the corridor's nodes blended towards the line (first band), then the line's two
    time laws blended (second band).

    Parameters
    ----------
    plan : Plan
        A paper plan.
    geom : RouteGeometry
        Of the plan's routes.
    separation : float
        ``sep``: the clearance plus the gate's margin (metres).
    limits : Limits
    problem : CorridorProblem
        The generator's corridor QP.
    margin : float
        The line's clearance minus ``sep`` (metres, ``>= 0``).
    band : float
        :func:`switch_band` of the track (metres, ``> 0``).
    fast : TimeScaling
        :func:`trajopt.path.fastpath.straight_scaling` of the plan (ruckig's profile on the line).
    timings : dict, optional
        Filled with the stage times (s).

    Returns
    -------
    scaling : TimeScaling
    stats : dict
        ``switch_weight`` (``margin / (2·band)``, in ``[0, 1)``) and, in the first band, the corridor's stats.

    Raises
    ------
    PlanningError
        A blended node polygon leaves the separation (the caller takes the hard path), or a solver failed.
    """
    timings = timings if timings is not None else {}
    t0 = time.perf_counter()
    view = plan_view(plan)
    ends = view.waypoints[[0, -1]]
    n = problem.n
    u = np.linspace(0.0, 1.0, n + 1)[:, None]
    line = ends[0] + u * (ends[1] - ends[0])
    line[0], line[-1] = ends[0], ends[-1]
    x = margin / band
    stats: dict[str, Any] = {"switch_weight": 0.5 * x}
    if x < 1.0:
        res = corridor_nodes(plan, geom, separation, problem)
        stats.update(res.stats)
        nodes = (1.0 - x) * res.nodes + x * line
        nodes[0], nodes[-1] = ends[0], ends[-1]
        worst = float(np.min(hull_clearance(geom, nodes)))
        if worst < separation:
            raise PlanningError(
                f"the nodes blended towards the line come {worst!r} m close, below the separation {separation!r} m"
            )
        timings["smooth"] = time.perf_counter() - t0
        scaling = filtered_scaling(spline_path(nodes), limits)
    else:
        scaling = blended_time_law(filtered_scaling(spline_path(line), limits), fast, x - 1.0)
    timings["jerk"] = time.perf_counter() - t0
    stats.update(scaling.stats)
    return scaling, stats
