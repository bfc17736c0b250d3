"""Re-planning from a moving state: :func:`replan` (and :meth:`TrajectoryGenerator.replan`).

Given a verified trajectory, a time ``at_time`` of it and a new goal, the result is a verified trajectory that
starts at both carts' state at ``at_time`` — position, velocity and acceleration along their routes — and ends
at rest at the new goal. Its time 0 is ``at_time`` of the old one.

1. **Brake** on the current routes: one 2-DoF ruckig call in the velocity interface (target velocity and
   acceleration 0) from the state ``(σ, σ̇, σ̈)`` of both carts, with the generator's limits and
   ``Synchronization.Phase``. When the two carts' velocity and acceleration are collinear in the σ-plane (always
   on a straight piece of the optimized path, and at rest) phase synchronization keeps the braking motion on that
   straight line, i.e. on the old path; otherwise ruckig falls back to time synchronization and the braking
   curve leaves the old path slightly. A cart whose stop would fall within 1e-6 m of the pole P is brought to
   rest exactly on P instead (ruckig's position interface; the planner handles starts at P but not a hair
   beside it). The braking part is checked on its own (separation at the rows and
   between them, the gate's bound); if it would bring the carts closer than D the re-plan is refused with
   :class:`~mpa.errors.NoMotionError` (re-plan at another time).
2. **New motion** from the rest state to the goal: :meth:`TrajectoryGenerator.generate` (plan, smoothing,
   timing, gate). The goal is validated there (off the track, too close: :class:`~mpa.errors.InvalidInputError`;
   no motion: :class:`~mpa.errors.NoMotionError`).
3. **Splice.** Each cart's braking segment and new route are joined into one route (a geodesic line of the
   universal cover, :meth:`mpa.routes.Route.through` on the lifted corners, the new route moved by the deck
   transformation that puts its start on the rest point), so the result has the usual route coordinates
   (σ = 0 at the state at ``at_time``; σ may run opposite to the old route's, the sign is reported in
   ``solver_stats["replan"]["orientation"]``). At the splice the braking profile starts exactly at the old state,
   so position, velocity and acceleration are continuous (to rounding, 1e-12) and the jerk is limited; the
   braking ends at rest, where the new motion starts at rest. If a cart would come back through P onto a third
   branch (its path is then no single route) :class:`~mpa.errors.NoMotionError` says so (a limit of the
   one-route-coordinate setpoint format, not a failure: the command line answers exit 3, re-plan at another time).
4. **Gate** on the spliced rows, with every check of :func:`~trajopt.verify.gate.verify_setpoints` except "first row
   at rest" (the first row is the moving state by construction); the homotopy class checked is the reduced
   word of the braking rows followed by the new plan's path (``mpa.path_word``).
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, cast

import numpy as np
from numpy.typing import ArrayLike

from mpa._arrays import FloatArray
from mpa.errors import InvalidInputError, NoMotionError, PlanningError
from mpa.homotopy import path_word
from mpa.plans import Plan, PlanStep
from mpa.routes import Lift, Route
from mpa.tracks import Circle, Lollipop, Track
from trajopt.export import Trajectory, time_grid, verified_rows
from trajopt.path.braking import Brake, _Splice, _spliced_sampler, _validate_at_time, brake_profile
from trajopt.verify.gate import (
    SEPARATION_TOL,
    VerificationError,
    VerificationReport,
    between_rows_separation,
    verify_setpoints,
)
from trajopt.verify.rows import Setpoints

if TYPE_CHECKING:
    from trajopt.generator import TrajectoryGenerator

__all__ = ["Brake", "brake_profile", "replan"]


#: A stop closer than this to the pole P (m) is moved onto P (the planner treats nearer starts as P).
SNAP = 1e-6


def _snap_to_pole(routes: Sequence[Route], stop: FloatArray) -> FloatArray | None:
    """Stops within :data:`SNAP` of a junction of their route moved onto it (None if none is)."""
    out = np.array(stop, dtype=float)
    moved = False
    for r in (0, 1):
        junc = routes[r].junctions()
        if len(junc):
            k = int(np.argmin(np.abs(junc - out[r])))
            if 0.0 < abs(junc[k] - out[r]) <= SNAP:
                out[r] = float(junc[k])
                moved = True
    return out if moved else None


def _lift(route: Route, sigma: float) -> Lift:
    is_stick, k, v = route.lift_at(np.array([sigma]))
    return Lift("stick" if bool(is_stick[0]) else "line", int(k[0]), float(v[0]))


def _normal(track: Track, lf: Lift) -> Lift:
    c = getattr(track, "loop", 0.0)
    if lf.kind == "stick" and lf.v <= 1e-9 * max(1.0, track.total_length):
        return Lift("line", 0, lf.k * c)
    return lf


def _deck(track: Track, frm: Lift, to: Lift) -> int:
    """The deck transformation (shift by m turns) that maps ``frm`` onto ``to`` (same track point)."""
    if not isinstance(track, (Lollipop, Circle)):
        return 0
    c = track.loop
    f, g = _normal(track, frm), _normal(track, to)
    if f.kind == "line" and g.kind == "line":
        return round((g.v - f.v) / c)
    if f.kind == "stick" and g.kind == "stick":
        return g.k - f.k
    raise PlanningError(f"cannot match the new route's start {frm} with the rest point {to}")


def _shift(track: Track, lf: Lift, m: int) -> Lift:
    if m == 0 or not isinstance(track, (Lollipop, Circle)):
        return lf
    if lf.kind == "stick":
        return Lift("stick", lf.k + m, lf.v)
    return Lift("line", 0, lf.v + m * track.loop)


def replan(generator: TrajectoryGenerator, trajectory: Trajectory, at_time: float, goal: ArrayLike) -> Trajectory:
    """A verified trajectory from both carts' state at ``at_time`` of ``trajectory`` to rest at ``goal``.

    Parameters
    ----------
    generator : TrajectoryGenerator
        Built for the trajectory's track (its clearance, limits and rate are used).
    trajectory : Trajectory
        The motion being executed.
    at_time : float
        Time of ``trajectory`` (s), in ``[0, makespan]``.
    goal : array_like, shape (2,)
        New goal (track coordinates of A and B); on a layout positions ``(edge, offset)``, ``"EDGE:OFFSET"`` or
        vertex names (:func:`trajopt.replan_graph.replan_graph`).

    Returns
    -------
    Trajectory
        Time 0 is ``at_time``; ``solver_stats["replan"]`` records the splice (braking time and distance, the
        orientation of the new route coordinates relative to the old ones, phase synchronization).

    Raises
    ------
    InvalidInputError
        ``at_time`` not in ``[0, makespan]``; bad goal; another track than the generator's.
    NoMotionError
        Braking from that state would break the clearance, or no motion reaches the goal.
    PlanningError
        A cart's path would branch at P (no single route), or the spliced rows fail the gate (never observed).
    """
    # The paper's re-planning is its own: the spliced rows keep track coordinates and the gate checks the skeleton
    # word of the braking rows and the new plan; every other plan is re-planned on its layout.
    if not isinstance(trajectory.plan, Plan):
        from trajopt.replan_graph import replan_graph

        return replan_graph(generator, trajectory, at_time, goal)
    t_start = time.perf_counter()
    at = _validate_at_time(at_time, trajectory)
    old = _paper_plan_for(generator, trajectory)
    track = old.track
    s0, v0, a0, p_cur = _state_at(trajectory, old, at)
    # 1. brake on the current routes
    brake, brake_pos, p_rest = _brake_on_current_routes(generator, old.routes, s0, v0, a0, at, p_cur)
    # 2. the new motion from rest
    new = generator.for_asked_gate().generate(p_rest, goal)  # the splice is checked with the limits asked for
    plan = new.plan
    assert isinstance(plan, Plan)  # the generator's track is the trajectory's paper track
    # 3. one route per cart through the brake and the new motion
    splice = _splice_routes(track, old.routes, s0, brake, new)
    sampler = _spliced_sampler(brake, new, s0, splice)
    motion_time = brake.duration + new.motion_time
    t = time_grid(motion_time, generator.rate)
    s, v, a, j = sampler(t)
    routes_c = splice.routes
    tr = np.stack([routes_c[0].position(s[:, 0]), routes_c[1].position(s[:, 1])], axis=1)
    goal_pos = np.asarray(plan.goal, dtype=float)
    tr[0], tr[-1] = p_cur, goal_pos
    # 4. the gate: the class of the braking rows followed by the new plan's path (the new motion is in its plan's
    # class); the first row is the moving state by construction, not at rest
    word = path_word(track, np.vstack([brake_pos, plan.sample(max(plan.samples_needed(0.002), 2))]))
    rep = _gate_from_moving_state(generator, routes_c, t, tr, (s, v, a, j), word)
    stats = dict(new.solver_stats)
    stats["replan"] = _splice_record(at, brake, s0, splice, plan)
    timings = dict(new.timings)
    timings["replan_total"] = time.perf_counter() - t_start
    return Trajectory(
        **verified_rows(t, tr, (s, v, a, j), rep),
        limits=generator.limits,
        clearance=generator.clearance,
        rate=generator.rate,
        motion_time=motion_time,
        domain=plan.domain,
        word=tuple(word),
        source=new.source,
        fallback_reason=new.fallback_reason,
        solver_stats=stats,
        timings=timings,
        plan=_spliced_plan(plan, p_cur, goal_pos, splice, word),
        sampler=sampler,
    )


def _paper_plan_for(generator: TrajectoryGenerator, trajectory: Trajectory) -> Plan:
    """The trajectory's plan, checked to be on a paper track and on the generator's (InvalidInputError otherwise)."""
    old = trajectory.plan
    if not isinstance(old, Plan):  # a GraphPlan
        raise InvalidInputError("replan is implemented for the paper's tracks, not for a GraphTrack layout")
    if generator.track != old.track:
        raise InvalidInputError(f"the generator's track {generator.track!r} is not the trajectory's {old.track!r}")
    return old


def _state_at(trajectory: Trajectory, old: Plan, at: float) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Both carts' route coordinates, velocities, accelerations (shape (2,) each) and track coordinates at ``at``.

    After the motion's end the carts rest at the goal.
    """
    s0, v0, a0, _ = trajectory.sampler(np.array([min(at, trajectory.motion_time)]))
    s0, v0, a0 = s0[0], v0[0], a0[0]
    p_cur = np.array([float(old.routes[r].position(s0[r])) for r in (0, 1)])
    if at >= trajectory.motion_time:
        p_cur = np.asarray(old.goal, dtype=float).copy()
    return s0, v0, a0, p_cur


def _splice_record(at: float, brake: Brake, s0: FloatArray, splice: _Splice, plan: Plan) -> dict[str, Any]:
    """``solver_stats["replan"]``: braking time and distance, orientation of the new route coordinates, the new
    plan's word (JSON-ready)."""
    return {
        "at_time": at,
        "brake_duration": brake.duration,
        "brake_distance": np.abs(brake.stop - s0).tolist(),
        "phase_synchronized": brake.phase_synchronized,
        "orientation": [int(splice.brake_sign[0]), int(splice.brake_sign[1])],
        "new_plan_word": list(plan.word),
    }


def _gate_from_moving_state(
    generator: TrajectoryGenerator,
    routes: Sequence[Route],
    t: FloatArray,
    tr: FloatArray,
    svaj: tuple[FloatArray, FloatArray, FloatArray, FloatArray],
    word: tuple[str, ...],
) -> VerificationReport:
    """The gate on the spliced rows (times ``t``, track positions ``tr``, route coordinates and derivatives
    ``svaj``); the first row is the moving state by construction, so only "not at rest" is excused there.

    Raises
    ------
    PlanningError
        Any other failure of the gate.
    """
    s, v, a, j = svaj
    rep = verify_setpoints(
        cast(Track, generator.track),  # replan runs on the paper's tracks only
        routes,
        Setpoints(t, s, v, a, j, track=tr),
        limits=generator.limits,
        clearance=generator.clearance,
        start=tr[0],
        goal=tr[-1],
        word=word,
        rate=generator.rate,
    )
    fails = tuple(f for f in rep.failures if not f.startswith("first row is not at rest"))
    if fails:
        raise PlanningError(f"the re-planned motion fails the gate: {'; '.join(fails)}") from VerificationError(rep)
    return dataclasses.replace(rep, ok=True, failures=())


def _brake_on_current_routes(
    generator: TrajectoryGenerator,
    routes: Sequence[Route],
    s0: FloatArray,
    v0: FloatArray,
    a0: FloatArray,
    at: float,
    p_cur: FloatArray,
) -> tuple[Brake, FloatArray, FloatArray]:
    """Brake both carts on their current routes (onto P if they would stop just short of it), checking the
    clearance on the rows and between them.

    Returns the brake, the braking rows' track positions (shape (K, 2)) and the rest point (track coordinates).

    Raises
    ------
    NoMotionError
        Braking would bring the carts closer than the clearance.
    """
    track, limits, D = cast(Track, generator.track), generator.limits, generator.clearance
    brake = brake_profile(s0, v0, a0, limits)
    snapped = _snap_to_pole(routes, brake.stop)
    if snapped is not None:
        brake = brake_profile(s0, v0, a0, limits, snapped)
    if brake.duration == 0:
        return brake, p_cur[None, :], p_cur.copy()
    dt = 1.0 / generator.rate
    tb = np.append(np.arange(0.0, brake.duration, dt), brake.duration)
    sb, _, ab, _ = brake.sample(tb)
    pos = np.stack([routes[0].position(sb[:, 0]), routes[1].position(sb[:, 1])], axis=1)
    d = track.distance(pos[:, 0], pos[:, 1])
    between = between_rows_separation(track, routes, sb[:-1], ab[:-1], dt, limits) if len(tb) > 2 else d
    worst = float(min(np.min(d), np.min(between) if len(between) else np.inf))
    if worst < D - SEPARATION_TOL:
        raise NoMotionError(
            f"braking from the state at t = {at:g} s on the current routes would bring the carts to "
            f"{worst:.6g} m < D = {D:g}; re-plan at another time"
        )
    p_rest = np.array([float(routes[r].position(brake.stop[r])) for r in (0, 1)])
    return brake, pos, p_rest


def _splice_routes(track: Track, routes_old: Sequence[Route], s0: FloatArray, brake: Brake, new: Trajectory) -> _Splice:
    """One route per cart through its current state, its rest point and the new motion (shifted onto the same
    sheet of the universal cover as the rest point).

    Raises
    ------
    PlanningError
        A cart would brake past P and come back onto another branch (no single route).
    """
    plan = cast(Plan, new.plan)
    routes_c: list[Route] = []
    orient: list[int] = []
    brake_sign: list[int] = []
    corners_c: list[FloatArray] = []
    for r in (0, 1):
        ro, rn = routes_old[r], plan.routes[r]
        lf_cur, lf_rest = _lift(ro, float(s0[r])), _lift(ro, float(brake.stop[r]))
        m = _deck(track, _lift(rn, 0.0), lf_rest)
        ext = [float(np.min(new.s[:, r])), float(np.max(new.s[:, r]))]
        new_pts = [*plan.waypoints_s[:, r].tolist(), *ext, float(new.s[-1, r])]
        lifts = [lf_cur, lf_rest, *(_shift(track, _lift(rn, x), m) for x in new_pts)]
        try:
            rc, sig = Route.through(track, lifts, goal_index=-1)
        except PlanningError as exc:
            raise NoMotionError(
                f"robot {'AB'[r]} would brake past P and come back onto another branch: its motion is not a "
                f"single route, which setpoints along one route coordinate cannot express ({exc}); re-plan at "
                "another time"
            ) from exc
        # orientation of the old route coordinate and of the new one in the combined route
        sb_sign = 1
        if abs(brake.stop[r] - s0[r]) > 1e-12:
            sb_sign = 1 if (sig[1] - sig[0]) * (brake.stop[r] - s0[r]) > 0 else -1
        on = 1
        g = float(new.s[-1, r])
        if abs(g) > 1e-12:
            on = 1 if (sig[-1] - sig[1]) * g > 0 else -1
        routes_c.append(rc)
        brake_sign.append(sb_sign)
        orient.append(on)
        corners_c.append(np.array([sig[0], sig[1], *(sig[1] + on * np.asarray(plan.waypoints_s[:, r]))]))
    return _Splice(
        (routes_c[0], routes_c[1]),
        np.array(brake_sign, dtype=float),
        np.array(orient, dtype=float),
        (corners_c[0], corners_c[1]),
    )


def _spliced_plan(plan: Plan, p_cur: FloatArray, goal_pos: FloatArray, splice: _Splice, word: tuple[str, ...]) -> Plan:
    """The new plan re-stated for the spliced motion: one step from the moving state, the combined routes."""
    routes_c = splice.routes
    corners = np.stack(splice.corners, axis=1)
    waypoints = np.stack([routes_c[0].position(corners[:, 0]), routes_c[1].position(corners[:, 1])], axis=1)
    waypoints[0], waypoints[-1] = p_cur, goal_pos
    seg = np.max(np.abs(np.diff(corners, axis=0)), axis=1)
    length = float(np.sum(seg))
    knots = np.concatenate([[0.0], np.cumsum(seg)]) / length if length > 0 else np.zeros(len(corners))
    step = PlanStep("replan", "brake on the current routes, then the new plan", 0.0, 1.0, waypoints)
    return dataclasses.replace(
        plan,
        start=p_cur,
        rule="re-plan from a moving state: brake on the current routes, then " + plan.rule,
        steps=(step,),
        knots=knots,
        waypoints=waypoints,
        waypoints_s=corners,
        routes=routes_c,
        word=word,
        travel=np.sum(np.abs(np.diff(corners, axis=0)), axis=0),
        length=length,
    )
