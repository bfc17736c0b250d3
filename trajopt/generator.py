"""The pipeline: plan → fast path or corridor → timing → verify → :class:`~trajopt.export.Trajectory`.

:class:`TrajectoryGenerator` is built once per track, clearance, limits and rate (it keeps the planner and the
corridor QP) and answers many queries; :func:`generate_trajectory` is the one-shot call. Tracks: the paper's
(:class:`~mpa.tracks.Interval`, ``Circle``, ``Lollipop``; the paper's planner) and any layout
(:class:`mpa.GraphTrack`; the complete graph planner, :func:`mpa.planners.graph.plan_graph`). Both run through
the same geometry (:class:`mpa.geometry.RouteGeometry`, via :func:`trajopt.path.planview.plan_view`).
If any optimisation stage fails or its setpoints fail the gate (:func:`trajopt.verify.gate.verify_setpoints`, on a
layout :func:`trajopt.verify.gate.verify_graph_setpoints`), the plan itself is re-timed (every straight step rest to
rest along the plan's polyline, which is collision-free by construction), marked as the fallback with the reason,
and verified too. Nothing unverified is returned.

On a layout the graph planner is asked for the clearance plus :func:`separation_margin` (so that the plan's own
polyline, re-timed, passes the gate's between-rows bound); only if no such motion exists is the plan for the bare
clearance used (it then passes the gate only at a higher rate, which the error names).
"""

from __future__ import annotations

import copy
import time
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from mpa import defaults
from mpa.errors import InvalidInputError, MPAError, PlanningError
from mpa.footprint import drawing_of, footprints
from mpa.geometry import RouteGeometry
from mpa.graph_track import GraphTrack
from mpa.planners import Planner, make_planner
from mpa.planners.factory import OBJECTIVES
from mpa.planners.graph import GraphPlan
from mpa.plans import Plan
from mpa.tracks import Track
from trajopt.explain import RATE_LADDER, _decimal_at_most, _ladder, _RejectedError, explain_rejection, explain_threshold  # noqa: F401
from trajopt.export import Source, Trajectory, time_grid, validate_rate, verified_rows
from trajopt.path.corridor import CORRIDOR_SEGMENTS, CorridorProblem, hard_path_scaling
from trajopt.path.fastpath import straight_scaling
from trajopt.path.planning import GraphPlanner, _dedupe, route_speed_limits, view_waypoints
from trajopt.path.planview import densify, plan_view
from trajopt.path.switch import near_switch_scaling, switch_band
from trajopt.timing import Limits, TimeScaling, blend_polyline, jerk_limited_scaling, reachable_speed
from trajopt.verify.gate import VerificationError, VerificationReport, class_failures_only, separation_margin
from trajopt.verify.rows import Setpoints

__all__ = [
    "RATE_LADDER",
    "GraphPlanner",
    "TrajectoryGenerator",
    "generate_trajectory",
    "reachable_speed",
    "separation_margin",
]


#: Factor of :attr:`TrajectoryGenerator.motion_limits`: accelerations above ``LIMIT_CAP·vmax·rate`` and jerks above
#: ``LIMIT_CAP·amax·rate`` are not used.
LIMIT_CAP = 10.0


@dataclass
class TrajectoryGenerator:
    """Verified jerk-limited trajectories for many queries on one track.

    Parameters
    ----------
    track : Track or GraphTrack
        One of the paper's tracks (the paper's planner; queries in track coordinates) or a layout (the complete
        graph planner; queries as pairs of positions ``(edge, offset)``, ``"EDGE:OFFSET"`` or vertex names).
    clearance : float
        Required separation D (m, graph distance).
    limits : Limits
        Per-robot limits of the route coordinate.
    rate : float
        Setpoint rate (Hz).
    optimize : bool
        False skips the optimisation and always returns the re-timed plan (the benchmark's baseline).
    objective : {"fastest", "shortest"}
        On a layout, the graph planner's objective (default ``"fastest"``: minimum time at the speed limits).
        A paper track planned by the graph planner is its layout form, ``track.as_graph_track()``.
    footprint : None, mpa.Disc, mpa.Rectangle, pair or spec string
        The robots' bodies in the plane (layouts with coordinates): the plan keeps them apart in the drawing
        (:mod:`mpa.planar`) and the gate checks it at and between rows (:mod:`trajopt.verify.planar`).

    Raises
    ------
    InvalidInputError
        Bad clearance or rate (limits are checked by :class:`~trajopt.timing.Limits`).

    Examples
    --------
    >>> from mpa import Lollipop
    >>> gen = TrajectoryGenerator(Lollipop(1.0, 1.0), clearance=0.05)
    >>> traj = gen.generate((0.2, 0.5), (0.5, 0.2))
    >>> bool(traj.verification["ok"]), traj.word == traj.plan.word
    (True, True)
    """

    track: Track | GraphTrack
    clearance: float = defaults.CLEARANCE
    limits: Limits = field(default_factory=Limits)
    rate: float = defaults.RATE
    optimize: bool = True
    objective: str = "fastest"
    footprint: Any = None
    planner: Planner | GraphPlanner = field(init=False, repr=False)
    _corridor: CorridorProblem | None = field(default=None, init=False, repr=False)
    #: Per-robot cap (m/s²) on the motion's acceleration, below :attr:`limits` (:mod:`trajopt.caps`).
    _cap: tuple[float, float] | None = field(default=None, init=False, repr=False)
    #: When true, the motion time is reported (:class:`trajopt.caps.MotionTime`) before the rows are sampled.
    _probe: bool = field(default=False, init=False, repr=False)
    #: When true, the plan keeps the margin of the gate's bound with :attr:`limits` (:meth:`for_asked_gate`).
    _gate_asked: bool = field(default=False, init=False, repr=False)

    def __post_init__(self) -> None:
        if not isinstance(self.limits, Limits):
            raise InvalidInputError(f"limits is {self.limits!r}, expected a trajopt.Limits")
        self.rate = validate_rate(self.rate)
        if self.objective not in OBJECTIVES:
            raise InvalidInputError(f"objective is {self.objective!r}, expected one of {', '.join(OBJECTIVES)}")
        self.footprint = footprints(self.footprint)
        if self.footprint is not None and not isinstance(self.track, GraphTrack):
            raise InvalidInputError(
                f"footprint is {self.footprint.spec()!r} on {self.track!r}, expected a layout (GraphTrack): pass "
                "track.as_graph_track() and positions on it"
            )
        self.planner = self._make_planner()
        self.clearance = self.planner.clearance

    @property
    def travel_bound(self) -> float:
        """Bound (m) on a robot's travel in one motion, known before planning: twice the track's total length.

        A robot's route passes the track's pieces at most about once (measured: at most 1.21 times the total
        length on the lollipop, where a route can take the stick, the loop and part of the stick again; at most
        0.76 times on the example layouts), so twice the total length leaves room. It caps the limits the motion
        is timed with (:attr:`motion_limits`).
        """
        return 2.0 * float(self.track.total_length)

    @property
    def motion_limits(self) -> Limits:
        """The limits the motion is timed with: :attr:`limits`, lowered (per robot) to what a motion can use.

        With ``L`` = :attr:`travel_bound` (m) and ``CAP`` = :data:`LIMIT_CAP`:

        - accelerations above ``a_L = (jmax²·L/2)^(1/3)``, ``CAP·vmax·rate`` or ``sqrt(vmax·jmax)`` are lowered to
          the least of them;
        - speeds above ``v_L``, the peak speed of a time-optimal jerk-limited rest-to-rest profile over ``L`` with
          that acceleration, are lowered to ``v_L``;
        - jerks above ``CAP·amax·rate`` (the lowered ``amax``) are lowered to that;
        - in the motions :mod:`trajopt.caps` tries, accelerations are also lowered to a cap (what the first motion
          reached, or a value of a fixed grid).

        A time-optimal jerk-limited rest-to-rest profile over a travel ``L`` never accelerates beyond ``a_L``
        (with jerk alone it covers ``L = 2·jmax·T³`` in ``4T`` and peaks at ``jmax·T``) nor beyond
        ``sqrt(vmax·jmax)`` (the speed limit is reached before), and never runs faster than ``v_L``; so those
        caps cost nothing. They keep the timing filters away from plateaus of ``amax/jmax`` seconds (amax 1e4 with
        jmax 5 gave a 4 097 s motion) and keep the between-rows margin (:func:`separation_margin`, about
        ``amax·Δt²/4``) at what the motion can use, so a loosened ``amax`` does not make the straight motion fail
        its margin and take a slower detour.

        A higher acceleration than ``CAP·vmax·rate`` reaches the speed limit in less than a tenth of a row, so it
        cannot shorten the motion by more than a row per start or stop; it would only widen the margin. The
        trajectory declares these limits (:attr:`Trajectory.limits_used <trajopt.result.Trajectory.limits_used>`,
        each at most the one asked for); the gate checks the rows and bounds the motion between rows with them,
        and checks them against :attr:`limits`.

        Returns
        -------
        Limits
            ``vmax`` (m/s), ``amax`` (m/s²), ``jmax`` (m/s³), each a pair (robot A, robot B); :attr:`limits`
            itself when nothing is lowered.
        """
        v, a, j = self.limits.v, self.limits.a, self.limits.j
        length = self.travel_bound
        with np.errstate(over="ignore"):  # a huge rate: no cap (inf), the memory budget refuses it later
            a_eff = np.minimum(np.minimum(a, LIMIT_CAP * v * self.rate), np.sqrt(v * j))
            a_eff = np.minimum(a_eff, np.cbrt(j * j * length / 2.0))
            if self._cap is not None:
                a_eff = np.minimum(a_eff, self._cap)
            v_eff = np.minimum(v, reachable_speed(length, a_eff, j))
            j_eff = np.minimum(j, LIMIT_CAP * a_eff * self.rate)
        if np.array_equal(v_eff, v) and np.array_equal(a_eff, a) and np.array_equal(j_eff, j):
            return self.limits
        capped = object.__new__(Limits)  # lower than valid limits, so valid (not checked against the range again)
        for name, x in (("vmax", v_eff), ("amax", a_eff), ("jmax", j_eff)):
            object.__setattr__(capped, name, (float(x[0]), float(x[1])))
        return capped

    def separation_margin(self) -> float:
        """The between-rows margin (m) the plan keeps beyond the clearance: :func:`separation_margin` of the motion's
        limits (:attr:`motion_limits`) at :attr:`rate`, for the gate's bound with those limits (the trajectory
        declares them, :attr:`Trajectory.limits_used <trajopt.result.Trajectory.limits_used>`)."""
        return separation_margin(self.motion_limits, self.rate, self.limits if self._gate_asked else None)

    def for_asked_gate(self) -> TrajectoryGenerator:
        """This generator with motions that also pass the gate with the limits asked for.

        Its plans keep the margin of the gate's between-rows bound with :attr:`limits`
        (``separation_margin(motion_limits, rate, gate=limits)``: ``min(amax, a + jmax·Δt/2)`` per robot, more than
        the ``a`` the motion is timed with) and no lower acceleration cap is searched. The re-planners use it:
        a spliced motion brakes with the limits asked for, so the gate checks it with them.
        """
        gen = copy.copy(self)
        gen._gate_asked = True
        if isinstance(self.planner, GraphPlanner):
            gen.planner = replace(self.planner, margin=gen.separation_margin())
        return gen

    @property
    def is_graph(self) -> bool:
        """Whether the track is a layout (:class:`mpa.GraphTrack`) rather than one of the paper's tracks."""
        return isinstance(self.track, GraphTrack)

    def _make_planner(self) -> Planner | GraphPlanner:
        if isinstance(self.track, GraphTrack):
            speeds = (float(self.limits.v[0]), float(self.limits.v[1]))
            return GraphPlanner(
                self.track,
                self.clearance,
                speeds,
                self.separation_margin(),
                objective=self.objective,
                footprint=self.footprint,
                plane_margin=self._plane_margin(self.rate),
            )
        return make_planner(self.track, self.clearance)

    def _plane_margin(self, rate: float) -> float:
        if self.footprint is None or not isinstance(self.track, GraphTrack):
            return 0.0
        from trajopt.verify.planar import plane_margin

        d = drawing_of(self.track)
        scale = float(np.max(np.hypot(*d.piece_dir.T)))
        return plane_margin(self.footprint, self.limits.v, self.limits.a, rate, scale)

    # ---------------------------------------------------------------------------------------------
    def plan(self, start: Any, goal: Any) -> Plan | GraphPlan:
        """The plan of a query (validates it; see :meth:`mpa.planners.Planner.plan` and :class:`GraphPlanner`)."""
        return self.planner.plan(start, goal)

    def generate(
        self, start: Any, goal: Any, *, delay_tolerance: float | None = None, min_margin: float | None = None
    ) -> Trajectory:
        """A verified trajectory from ``start`` to ``goal`` (robot A first).

        On a paper track ``start`` and ``goal`` are track coordinates; on a layout pairs of positions
        ``(edge, offset)``, ``"EDGE:OFFSET"`` or vertex names.

        With ``delay_tolerance`` (s), one whose delay tolerance (:meth:`Trajectory.margins`) is at least that
        (:func:`trajopt.analysis.delay.generate_with_delay_tolerance`: a larger effective clearance, then slower).
        With ``min_margin`` (m), one whose tracking margin is at least that
        (:func:`trajopt.analysis.min_margin.generate_with_min_margin`: the effective clearance ``D + 2·min_margin``).

        Raises
        ------
        InvalidInputError
            Bad start or goal (off the track, closer than the clearance), bad ``delay_tolerance`` or
            ``min_margin``.
        NoMotionError
            No collision-free motion exists (e.g. the order must change and ``D ≥ loop/2``), or none found
            with the requested delay tolerance (the message states the best value found) or tracking margin
            (the message names the largest that can be had).
        PlanningError
            Even the re-timed plan fails verification (never expected).
        """
        if min_margin is not None:
            from trajopt.analysis.min_margin import generate_with_min_margin

            return generate_with_min_margin(self, start, goal, min_margin, delay_tolerance)
        if delay_tolerance is not None:
            from trajopt.analysis.delay import generate_with_delay_tolerance

            return generate_with_delay_tolerance(self, start, goal, delay_tolerance)
        t0 = time.perf_counter()
        plan = self.plan(start, goal)
        timings: dict[str, Any] = {"plan": time.perf_counter() - t0}
        return self.generate_from_plan(plan, timings)

    def generate_from_plan(self, plan: Plan | GraphPlan, timings: dict[str, Any] | None = None) -> Trajectory:
        """Like :meth:`generate` for an existing plan (from this generator's planner).

        Raises
        ------
        InvalidInputError
            The rate is too low for this motion (the message names the lowest usable rate), or the start or
            goal is so close to the clearance that no setpoints at this rate can be verified.
        PlanningError
            Not even the re-timed plan passes verification (never expected).
        """
        try:
            first = self._generate(plan, timings)
        except _RejectedError as exc:
            why = explain_rejection(self, plan) or explain_threshold(self, plan)
            if why:
                raise InvalidInputError(why) from None
            raise PlanningError(str(exc)) from exc
        return self._faster_caps(plan, first)

    def _faster_caps(self, plan: Plan | GraphPlan, first: Trajectory) -> Trajectory:
        """The fastest verified motion of ``plan`` over the acceleration caps :func:`trajopt.caps.faster_caps`
        tries below :attr:`motion_limits` (``first`` is the motion timed with :attr:`motion_limits`)."""
        from trajopt.caps import faster_caps

        return faster_caps(self, plan, first)

    def at_rate(self, rate: float) -> TrajectoryGenerator:
        """The same generator at another setpoint rate (Hz; the planner is shared)."""
        gen = TrajectoryGenerator.__new__(TrajectoryGenerator)
        gen.track, gen.clearance, gen.limits, gen.optimize, gen.objective, gen.planner = (
            self.track,
            self.clearance,
            self.limits,
            self.optimize,
            self.objective,
            self.planner,
        )
        gen.footprint = self.footprint
        gen.rate = validate_rate(rate)
        gen._corridor = self._corridor
        gen._cap = None  # what a motion reaches between rows depends on the rate
        gen._gate_asked = self._gate_asked
        if isinstance(self.planner, GraphPlanner):  # the plan's margin depends on the rate
            pl = self.planner
            gen.planner = GraphPlanner(
                pl.track,
                pl.clearance,
                pl.speeds,
                gen.separation_margin(),
                objective=pl.objective,
                footprint=self.footprint,
                plane_margin=self._plane_margin(gen.rate),
            )
        return gen

    def _attempt(self, plan: Plan | GraphPlan) -> Trajectory:
        """:meth:`_generate` at this generator's rate (a graph plan is made again for this rate's margin)."""
        if isinstance(self.planner, GraphPlanner):  # its plans keep a margin that depends on the rate
            plan = self.planner.plan(plan.layout_start, plan.layout_goal)
        return self._generate(plan, None)

    def lowest_rate(self, plan: Plan | GraphPlan, upto: float = 20_000.0) -> float | None:
        """The lowest rate of :data:`RATE_LADDER` above :attr:`rate` at which ``plan`` gives verified setpoints.

        Exponential then bisection search over the ladder (passing is assumed monotone in the rate, as the
        gate's between-rows bound shrinks with the step); ``None`` if even ``upto`` Hz fails.
        """
        ladder = [r for r in _ladder(self.rate, upto) if r > self.rate]

        def ok(r: float) -> bool:
            try:
                self.at_rate(r)._attempt(plan)
            except (_RejectedError, MPAError):
                return False
            return True

        lo, step, hi = -1, 1, None
        i = 0
        while i < len(ladder):
            if ok(ladder[i]):
                hi = i
                break
            lo, i, step = i, i + step, step * 2
        if hi is None:
            if lo == len(ladder) - 1 or not ok(ladder[-1]):
                return None
            hi = len(ladder) - 1
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if ok(ladder[mid]):
                hi = mid
            else:
                lo = mid
        return ladder[hi]

    def _generate(self, plan: Plan | GraphPlan, timings: dict[str, Any] | None = None) -> Trajectory:
        capped = route_speed_limits(plan, self.limits)
        if capped is not self.limits:  # lanes with speed limits: each robot at most its route's lowest limit
            gen = copy.copy(self)
            gen.limits = capped
            return gen._generate(plan, timings)
        timings = dict(timings or {})
        t_all = time.perf_counter()
        view = plan_view(plan)
        geom = view.geom
        stats: dict[str, Any] = {}
        reason = ""
        if self.optimize:
            try:
                traj = self._optimized(plan, geom, timings, stats)
                timings["total"] = timings.get("plan", 0.0) + time.perf_counter() - t_all
                return traj
            except VerificationError as exc:
                reason = str(exc)
            except MPAError as exc:
                reason = f"{type(exc).__name__}: {exc}"
            except RuntimeError as exc:  # CasADi and ruckig raise RuntimeError on internal failures
                reason = f"solver error: {exc}"
            except Exception as exc:  # numerical trouble of any kind in an optional stage: fall back, say why
                reason = f"optimisation failed ({type(exc).__name__}: {exc})"
        else:
            reason = "optimisation disabled"
        t1 = time.perf_counter()
        try:
            path = blend_polyline(_dedupe(view.waypoints))
            scaling = jerk_limited_scaling(path, self.motion_limits)
        except (MPAError, RuntimeError, ArithmeticError, ValueError) as exc:
            raise _RejectedError(f"the re-timed plan cannot be computed ({exc}); after: {reason}") from exc
        timings["fallback_jerk"] = time.perf_counter() - t1
        stats["fallback_pieces"] = len(path.coef)
        try:
            traj = self._finish(plan, scaling, Source.PLAN, reason, stats, timings)
        except VerificationError as exc:
            raise _RejectedError(f"the re-timed plan fails verification ({exc}); after: {reason}") from exc
        timings["total"] = timings.get("plan", 0.0) + time.perf_counter() - t_all
        return traj

    def replan(self, trajectory: Trajectory, at_time: float, goal: ArrayLike) -> Trajectory:
        """A verified trajectory from both robots' state at ``at_time`` of ``trajectory`` to rest at ``goal``
        (see :func:`trajopt.replan.replan`; on a layout :func:`trajopt.replan_graph.replan_graph`, goals as
        positions ``(edge, offset)``, ``"EDGE:OFFSET"`` or vertex names).

        Raises
        ------
        InvalidInputError
            ``at_time`` outside ``[0, makespan]``, a bad goal, a trajectory of another track.
        NoMotionError
            Braking would break the clearance, or no motion reaches the goal.
        """
        from trajopt.replan import replan

        return replan(self, trajectory, at_time, goal)

    # ---------------------------------------------------------------------------------------------
    def _optimized(
        self, plan: Plan | GraphPlan, geom: RouteGeometry, timings: dict[str, Any], stats: dict[str, Any]
    ) -> Trajectory:
        sep = self.clearance + self.separation_margin()
        t0 = time.perf_counter()
        view = plan_view(plan)
        # start == goal: a motion of zero length (one row at rest); the straight "line" is a single point
        line = float("inf") if plan.length <= 0 else geom.polyline_min_distance(view.waypoints[[0, -1]])
        plane = self.footprint is not None and plan.length > 0
        if plane:
            line = min(line, sep + self._plane_chord_slack(view, view.waypoints[[0, -1]]))
        # the switch bands (paper plans without bodies in the plane: the corridor keeps the graph distance only)
        band = 0.0 if view.is_graph or plane else switch_band(self.track)
        if line >= sep or plan.length <= 0:  # the fast path: one phase-synchronised profile along the straight line
            scaling = straight_scaling(plan, self.motion_limits)
            timings["jerk"] = time.perf_counter() - t0
            stats.update(scaling.stats, path="fast", line_clearance=line)
            timed: TimeScaling | None = scaling
            if plan.length > 0 and line < sep + 2.0 * band:  # near the switch: the hard path turned into this one
                try:
                    timed, st = near_switch_scaling(
                        plan,
                        geom,
                        sep,
                        self.motion_limits,
                        self._corridor_problem(),
                        line - sep,
                        band,
                        scaling,
                        timings,
                    )
                    stats.clear()
                    stats.update(st, path="switch", line_clearance=line)
                except PlanningError as exc:  # the blended nodes leave the separation: the hard path
                    stats.clear()
                    stats["switch_failed"] = str(exc)
                    timed = None
            try:
                if timed is not None:
                    return self._finish(plan, timed, Source.OPTIMIZED, "", stats, timings)
            except VerificationError as exc:
                # The line keeps the separation but the gate finds another homotopy class than the plan's (the
                # rows lie on the line: the line's class): not a motion of this plan, so the hard path. Never seen
                # on 10 000 random queries of the benchmark's tracks; any other failure falls back to the re-timed plan.
                if view.is_graph or not class_failures_only(exc.report):
                    raise
                stats.clear()
                stats["line_other_class"] = True
        if not view.is_graph:  # the paper's plan: the corridor QP keeps its skeleton class (the gate checks it)
            scaling, st = hard_path_scaling(
                view.paper, geom, sep, self.motion_limits, self._corridor_problem(), timings
            )
            stats.update(st, path="hard", line_clearance=line)
        else:
            # A graph plan is taut: it touches the clearance (plus the margin) at its corners, so the corridor has
            # no room there (its samples cut the corners; measured: no graph query passed). Instead the plan's
            # corners are blended where a collision-checked blend keeps the separation, else passed at rest.
            t1 = time.perf_counter()

            def chord_min(pts: np.ndarray) -> float:
                d = float(np.min(geom.segment_min_distances(pts)))
                if self.footprint is not None:
                    d = min(d, sep + self._plane_chord_slack(view, pts))
                return d

            path = blend_polyline(_dedupe(view_waypoints(plan)), chord_min, sep)
            scaling = jerk_limited_scaling(path, self.motion_limits)
            timings["blend"] = time.perf_counter() - t1
            stats.update(scaling.stats, path="blend", line_clearance=line, blends=int(np.sum(path.radii > 0)))
        return self._finish(plan, scaling, Source.OPTIMIZED, "", stats, timings)

    def _corridor_problem(self) -> CorridorProblem:
        """The corridor QP of this generator's speed limits (built at its first use)."""
        if self._corridor is None:
            self._corridor = CorridorProblem(CORRIDOR_SEGMENTS, self.limits.v)
        return self._corridor

    def _plane_chord_slack(self, view: Any, pts: np.ndarray) -> float:
        """How far the bodies stay beyond the plane margin along a polyline in route coordinates (negative: closer;
        the gate decides exactly).

        The polyline is sampled every 1 cm and the samples go through the gate's plane check as if they were rows
        one second apart at speeds no lower than each step (no acceleration): the gap at the samples and the gate's
        bound between them, a rectangle's turn at a corner included, so the blend keeps the plane margin along the
        whole path and not only at its samples.
        """
        from trajopt.verify.planar import verify_plane

        assert self.footprint is not None
        dense = densify(pts, 0.01)
        e, o = view.positions(dense)
        speed = np.zeros_like(dense)
        if len(dense) > 1:
            step = np.abs(np.diff(dense, axis=0))
            speed[:-1] = step
            speed[1:] = np.maximum(speed[1:], step)
        rep = verify_plane(view.graph, self.footprint, e, o, speed, amax=0.0, rate=1.0)
        return min(rep.min_gap_plane, rep.min_gap_between) - 0.5 * self._plane_margin(self.rate)

    def _finish(
        self,
        plan: Plan | GraphPlan,
        scaling: TimeScaling,
        source: Source,
        reason: str,
        stats: dict[str, Any],
        timings: dict[str, Any],
    ) -> Trajectory:
        if self._probe:  # the caps' search compares motion times; the chosen motion is made and verified after
            from trajopt.caps import MotionTime

            raise MotionTime(scaling.duration, source is Source.OPTIMIZED)
        t0 = time.perf_counter()
        t = time_grid(scaling.duration, self.rate)
        s, v, a, j = scaling.sample(t)
        view = plan_view(plan)
        rows_pos = None  # a graph plan's edges, offsets and directions: one search of the route breaks for all
        if view.is_graph:
            e, o, d, tr = view.graph_rows(s, v)
            rows_pos = (e, o, d)
        else:
            tr = view.track_coordinates(s)
        timings["sample"] = time.perf_counter() - t0
        t1 = time.perf_counter()
        used = self.motion_limits  # the limits the motion is timed with, declared with the rows
        rep: VerificationReport = view.verify(
            Setpoints(t, s, v, a, j, track=None if view.is_graph else tr),  # the rows' coordinates, as exported
            limits=self.limits,
            clearance=self.clearance,
            rate=self.rate,
            limits_used=used,
            positions=None if rows_pos is None else rows_pos[:2],
        )
        timings["verify" if source is Source.OPTIMIZED else "fallback_verify"] = time.perf_counter() - t1
        if not rep.ok:
            raise VerificationError(rep)
        plane = None
        if self.footprint is not None:
            from trajopt.verify.planar import verify_plane

            e, o = (rows_pos[0], rows_pos[1]) if rows_pos is not None else view.positions(s, v)
            t2 = time.perf_counter()
            prep = verify_plane(view.graph, self.footprint, e, o, v, amax=self.limits.a, rate=self.rate)
            timings["verify_plane"] = time.perf_counter() - t2
            if not prep.ok:
                raise VerificationError(replace(rep, ok=False, failures=rep.failures + prep.failures))
            plane = prep.to_dict()
        traj = Trajectory(
            **verified_rows(t, tr, (s, v, a, j), rep),
            limits=self.limits,
            clearance=self.clearance,
            rate=self.rate,
            motion_time=scaling.duration,
            domain=plan.domain or 0,  # the trajectory's domain is 0 on a layout (an int in summary.json)
            word=tuple(plan.word),
            source=source,
            fallback_reason=reason,
            solver_stats=dict(stats),
            timings=timings,
            plan=plan,
            sampler=scaling.sample,
            retimer=self._retimer(plan),
            footprint=self.footprint,
            plane=plane,
            limits_used=used,
        )
        if rows_pos is not None:
            traj.cache_positions(*rows_pos)  # the rows' positions as the gate checked them, not searched again
        return traj

    def _retimer(self, plan: Plan | GraphPlan) -> Any:
        """``rate -> Trajectory``: the query again at another rate (a graph plan is made for that rate's margin)."""
        if isinstance(self.planner, GraphPlanner):  # its plans keep a margin that depends on the rate
            return lambda r: self.at_rate(r).generate(plan.layout_start, plan.layout_goal)
        return lambda r: self.at_rate(r).generate_from_plan(plan)


def generate_trajectory(
    track: Track | GraphTrack,
    start: Any,
    goal: Any,
    *,
    clearance: float = defaults.CLEARANCE,
    vmax: Any = defaults.VMAX,
    amax: Any = defaults.AMAX,
    jmax: Any = defaults.JMAX,
    rate: float = defaults.RATE,
    delay_tolerance: float | None = None,
    min_margin: float | None = None,
    footprint: Any = None,
) -> Trajectory:
    """One call from a query to a verified jerk-limited :class:`~trajopt.export.Trajectory`.

    Parameters
    ----------
    track : Track or GraphTrack
    start, goal : pair
        Robots A and B: track coordinates (m) on a paper track; on a layout positions ``(edge, offset)``,
        ``"EDGE:OFFSET"`` or vertex names.
    clearance : float
        Required separation D (m, graph distance).
    vmax, amax, jmax : float or (float, float)
        Per-robot limits (m/s, m/s², m/s³).
    rate : float
        Setpoint rate (Hz).
    delay_tolerance : float, optional
        Ask for a delay tolerance of at least this (s; see :mod:`trajopt.analysis.delay`).
    min_margin : float, optional
        Ask for a tracking margin of at least this (m; see :mod:`trajopt.analysis.min_margin`).
    footprint : None, mpa.Disc, mpa.Rectangle, pair or spec string
        The robots' bodies in the plane (layouts with coordinates; see :class:`TrajectoryGenerator`).

    Returns
    -------
    Trajectory

    Raises
    ------
    InvalidInputError
        Bad limits, rate, clearance, start, goal, delay tolerance or margin.
    NoMotionError
        No collision-free motion exists (or none with the requested delay tolerance or tracking margin).
    PlanningError
        Not even the re-timed plan passes verification.

    Examples
    --------
    >>> from mpa import Lollipop
    >>> traj = generate_trajectory(Lollipop(1.0, 1.0), (0.1, 0.6), (0.8, 0.3))
    >>> traj.t.shape[0] == traj.s.shape[0], traj.fallback
    (True, False)
    """
    gen = TrajectoryGenerator(
        track, clearance=clearance, limits=Limits(vmax, amax, jmax), rate=rate, footprint=footprint
    )
    return gen.generate(start, goal, delay_tolerance=delay_tolerance, min_margin=min_margin)
