"""Re-planning from a moving state on a layout (:class:`mpa.GraphTrack`): :func:`replan_graph`.

The same four steps and guarantees as on the paper's tracks (:mod:`trajopt.replan`), on the routes of a
:class:`~mpa.planners.graph.GraphPlan`:

1. **Brake** both carts on their current routes from their state ``(s, ṡ, s̈)`` at ``at_time``
   (:func:`trajopt.replan.brake_profile`: ruckig, jerk-limited, phase-synchronised when the state allows). The
   braking rows are checked against the clearance (exact graph distance, at the rows and between them with the
   gate's bound); if braking would bring the carts closer than D, or past the end of a route, the re-plan is
   refused with :class:`~mpa.errors.NoMotionError` (re-plan at another time).
2. **New motion** from the rest positions to the goal: :meth:`TrajectoryGenerator.generate` (the complete graph
   planner, blending, timing, gate). Goals are positions ``(edge, offset)``, ``"EDGE:OFFSET"`` or vertex names.
3. **Splice.** Each cart's route is the stretch of its old route from the current state to the rest point
   followed by the new route, as one :class:`~mpa.geometry.DirectedRoute` whose coordinate is the distance
   travelled from the state at ``at_time`` (0 there). The braking profile starts exactly at the old state, so
   position, velocity and acceleration are continuous at the splice (to rounding) and the jerk is limited; the
   new motion starts at rest where the braking ends.
4. **Gate** (:func:`trajopt.verify.gate.verify_graph_setpoints`) on the spliced rows: every check except "first row at
   rest" (the first row is the moving state by construction).

The result's plan is the new :class:`GraphPlan` re-stated for the spliced motion (start: the positions at
``at_time``; routes and corners in the spliced route coordinates).
"""

from __future__ import annotations

import dataclasses
import time
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from mpa._arrays import FloatArray
from mpa.errors import NoMotionError, PlanningError
from mpa.geometry import DirectedRoute, RouteGeometry
from mpa.graph_track import as_graph_track
from mpa.planners.graph import GraphPlan
from trajopt.export import Trajectory, time_grid, verified_rows
from trajopt.path.braking import Brake, _Splice, _spliced_sampler, _validate_at_time, brake_profile
from trajopt.path.planview import plan_view
from trajopt.verify.gate import SEPARATION_TOL, VerificationError, VerificationReport
from trajopt.verify.rows import Setpoints

if TYPE_CHECKING:
    from trajopt.generator import TrajectoryGenerator

__all__ = ["replan_graph"]

#: Route coordinates (m) within which a braking stop counts as on the route's end.
END_TOL = 1e-9


def replan_graph(generator: TrajectoryGenerator, trajectory: Trajectory, at_time: float, goal: Any) -> Trajectory:
    """A verified trajectory on a layout from both carts' state at ``at_time`` of ``trajectory`` to rest at ``goal``.

    Parameters
    ----------
    generator : TrajectoryGenerator
        Built for the trajectory's layout (its clearance, limits and rate are used).
    trajectory : Trajectory
        The motion being executed (a layout's: its plan is a :class:`GraphPlan`).
    at_time : float
        Time of ``trajectory`` (s), in ``[0, makespan]``.
    goal : pair
        New goal of A and B: positions ``(edge, offset)``, ``"EDGE:OFFSET"`` or vertex names.

    Returns
    -------
    Trajectory
        Time 0 is ``at_time``; ``solver_stats["replan"]`` records the splice (braking time and distance, phase
        synchronisation, the rest positions, the new plan's cell word).

    Raises
    ------
    InvalidInputError
        ``at_time`` not in ``[0, makespan]``; a bad goal (unknown edge or vertex, offset off the edge, closer than
        the clearance); another layout than the generator's.
    NoMotionError
        Braking from that state would break the clearance or run past a route's end, or no motion reaches the goal.
    PlanningError
        The spliced rows fail the gate (never observed).
    """
    from mpa.errors import InvalidInputError

    t_start = time.perf_counter()
    at = _validate_at_time(at_time, trajectory)
    old = trajectory.plan
    if not isinstance(old, GraphPlan):  # the spliced plan is a GraphPlan (cells and offsets of its segments)
        raise InvalidInputError("the trajectory is on a paper track, expected one on a layout (use trajopt.replan)")
    if generator.track != old.layout:
        raise InvalidInputError(f"the generator's track {generator.track!r} is not the trajectory's layout")
    routes_old = old.layout_routes
    s_now, v_now, a_now, _ = trajectory.sampler(np.array([min(at, trajectory.motion_time)]))
    s0, v0, a0 = s_now[0], v_now[0], a_now[0]
    if at >= trajectory.motion_time:
        v0, a0 = np.zeros(2), np.zeros(2)
        s0 = np.asarray(trajectory.s[-1], dtype=float)
    # 1. brake on the current routes
    brake = brake_profile(s0, v0, a0, generator.limits)
    _check_brake(generator, routes_old, brake, s0, at)
    p_cur = tuple(_position(routes_old[r], float(s0[r])) for r in (0, 1))
    p_rest = tuple(_position(routes_old[r], float(brake.stop[r])) for r in (0, 1))
    # 2. the new motion from rest
    new = generator.for_asked_gate().generate(p_rest, goal)  # the splice is checked with the limits asked for
    plan = new.plan
    assert isinstance(plan, GraphPlan)  # the generator's track is the trajectory's layout
    # 3. one route per cart through the brake and the new motion
    splice = _splice(routes_old, s0, brake, plan)
    sampler = _spliced_sampler(brake, new, s0, splice)
    motion_time = brake.duration + new.motion_time
    t = time_grid(motion_time, generator.rate)
    s, v, a, j = sampler(t)
    spliced = _spliced_plan(plan, p_cur, splice, brake)
    # 4. the gate (the first row is the moving state by construction, not at rest)
    rep = _gate(generator, spliced, t, (s, v, a, j))
    stats = dict(new.solver_stats)
    names = plan.track
    stats["replan"] = {
        "at_time": at,
        "brake_duration": brake.duration,
        "brake_distance": np.abs(brake.stop - s0).tolist(),
        "phase_synchronized": brake.phase_synchronized,
        "orientation": [int(x) for x in splice.brake_sign],
        "rest": [names.position_name(*p) for p in p_rest],
        "new_plan_word": list(plan.word),
    }
    timings = dict(new.timings)
    timings["replan_total"] = time.perf_counter() - t_start
    view = plan_view(spliced)
    tr = view.track_coordinates(s)
    return Trajectory(
        **verified_rows(t, tr, (s, v, a, j), rep),
        limits=generator.limits,
        clearance=generator.clearance,
        rate=generator.rate,
        motion_time=motion_time,
        domain=0,
        word=tuple(plan.word),
        source=new.source,
        fallback_reason=new.fallback_reason,
        solver_stats=stats,
        timings=timings,
        plan=spliced,
        sampler=sampler,
    )


def _position(route: DirectedRoute, r: float) -> tuple[int, float]:
    e, o = route.position_scalar(r)
    return int(e), float(o)


def _check_brake(
    generator: TrajectoryGenerator, routes: tuple[DirectedRoute, DirectedRoute], brake: Brake, s0: FloatArray, at: float
) -> None:
    """Refuse (NoMotionError) a braking that leaves a route or comes closer than the clearance."""
    for r in (0, 1):
        lo, hi = float(routes[r].breaks[0]), float(routes[r].breaks[-1])
        if not lo - END_TOL <= float(brake.stop[r]) <= hi + END_TOL:
            raise NoMotionError(
                f"braking from the state at t = {at:g} s would carry robot {'AB'[r]} past the end of its route "
                f"(stop at {float(brake.stop[r]):.6g} m, route [{lo:.6g}, {hi:.6g}] m); re-plan at another time"
            )
    if brake.duration == 0:
        return
    rate = max(generator.rate, 1000.0)
    tb = np.append(np.arange(0.0, brake.duration, 1.0 / rate), brake.duration)
    sb, _, _, _ = brake.sample(tb)
    geom = plan_view_routes(generator, routes)
    worst = float(np.min(geom.segment_min_distances(sb)))
    if worst < generator.clearance - SEPARATION_TOL:
        raise NoMotionError(
            f"braking from the state at t = {at:g} s on the current routes would bring the carts to "
            f"{worst:.6g} m < D = {generator.clearance:g}; re-plan at another time"
        )


def plan_view_routes(generator: TrajectoryGenerator, routes: tuple[DirectedRoute, DirectedRoute]) -> RouteGeometry:
    """The exact geometry (:class:`mpa.geometry.RouteGeometry`) of ``routes`` on the generator's layout."""
    return RouteGeometry(as_graph_track(generator.track).geometry, routes)


def _stretch(route: DirectedRoute, a: float, b: float) -> tuple[list[int], list[int], list[float], list[float]]:
    """The pieces of ``route`` between route coordinates ``a`` and ``b`` (either order), travelled from ``a`` to
    ``b``: edges, directions, entry offsets and lengths."""
    edges: list[int] = []
    dirs: list[int] = []
    entry: list[float] = []
    lengths: list[float] = []
    if abs(b - a) <= 0.0:
        return edges, dirs, entry, lengths
    lo, hi = min(a, b), max(a, b)
    br = route.breaks
    idx = [i for i in range(len(route.edges)) if br[i + 1] > lo and br[i] < hi]
    forward = b > a
    for i in idx if forward else idx[::-1]:
        x0, x1 = max(float(br[i]), lo), min(float(br[i + 1]), hi)
        d = int(route.dirs[i])
        at_start = x0 if forward else x1
        edges.append(int(route.edges[i]))
        dirs.append(d if forward else -d)
        entry.append(float(route.entry[i] + d * (at_start - br[i])))
        lengths.append(x1 - x0)
    return edges, dirs, entry, lengths


def _splice(routes_old: tuple[DirectedRoute, DirectedRoute], s0: FloatArray, brake: Brake, plan: GraphPlan) -> _Splice:
    """Per cart one route: the braking stretch of the old route, then the new route (coordinate 0 at ``s0``)."""
    routes: list[DirectedRoute] = []
    sign: list[float] = []
    corners: list[FloatArray] = []
    for r, rn in enumerate(plan.layout_routes):
        a, b = float(s0[r]), float(brake.stop[r])
        e, d, en, ln = _stretch(routes_old[r], a, b)
        for k, length in enumerate(np.diff(rn.breaks).tolist()):
            ek, dk, xk = int(rn.edges[k]), int(rn.dirs[k]), float(rn.entry[k])
            if e and e[-1] == ek and d[-1] == dk and abs(en[-1] + d[-1] * ln[-1] - xk) <= END_TOL:
                ln[-1] += length  # the new route carries on along the braking piece: one piece
                continue
            e.append(ek)
            d.append(dk)
            en.append(xk)
            ln.append(length)
        routes.append(DirectedRoute.from_pieces(e, d, en, ln))
        sign.append(1.0 if b >= a else -1.0)
        rest = abs(b - a)
        corners.append(np.concatenate([[0.0, rest], rest + np.asarray(plan.route_waypoints[:, r], dtype=float)]))
    return _Splice((routes[0], routes[1]), np.array(sign), np.ones(2), (corners[0], corners[1]))  # type: ignore[arg-type]


def _spliced_plan(plan: GraphPlan, p_cur: Any, splice: _Splice, brake: Brake) -> GraphPlan:
    """The new plan re-stated for the spliced motion: the state at ``at_time`` as its first corner (when the carts
    brake), then the new plan's corners shifted by the braking distance, on the spliced routes."""
    corners = np.stack(splice.corners, axis=1)  # rows: state, rest, then the new plan's corners (rest again first)
    cells, offsets = plan.segment_cells, np.asarray(plan.segment_offsets, dtype=float)
    times = np.asarray(plan._times, dtype=float)
    if brake.duration > 0 and np.any(corners[1] > 0):
        waypoints = np.vstack([corners[:1], corners[2:]])
        rest_off = offsets[0, 0] if len(offsets) else np.array([plan.start[0][1], plan.start[1][1]])
        first = np.stack([np.array([p_cur[0][1], p_cur[1][1]], dtype=float), rest_off])[None]
        offsets = np.concatenate([first, offsets]) if len(offsets) else first
        cells = (plan.corner_cells[0], *cells)
        times = np.concatenate([[0.0], brake.duration + times])
    else:
        waypoints = corners[2:]
    return dataclasses.replace(
        plan,
        start=((int(p_cur[0][0]), float(p_cur[0][1])), (int(p_cur[1][0]), float(p_cur[1][1]))),
        route_a=cast(DirectedRoute, splice.routes[0]),
        route_b=cast(DirectedRoute, splice.routes[1]),
        waypoints=waypoints,
        segment_offsets=offsets,
        segment_cells=cells,
        makespan=float(brake.duration + plan.makespan),
        _times=times,
    )


def _gate(
    generator: TrajectoryGenerator,
    plan: GraphPlan,
    t: FloatArray,
    svaj: tuple[FloatArray, FloatArray, FloatArray, FloatArray],
) -> VerificationReport:
    """The gate on the spliced rows; the first row is the moving state by construction ("not at rest" excused).

    Raises
    ------
    PlanningError
        Any other failure of the gate.
    """
    rep = plan_view(plan).verify(
        Setpoints(t, *svaj), limits=generator.limits, clearance=generator.clearance, rate=generator.rate
    )
    fails = tuple(f for f in rep.failures if not f.startswith("first row is not at rest"))
    if fails:
        raise PlanningError(f"the re-planned motion fails the gate: {'; '.join(fails)}") from VerificationError(rep)
    return dataclasses.replace(rep, ok=True, failures=())
