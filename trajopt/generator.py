"""The pipeline: plan → smooth → time-parametrize → jerk-limit → verify → :class:`~trajopt.export.Trajectory`.

:class:`TrajectoryGenerator` is built once per track, clearance, limits and rate (it keeps the planner; the
NLPs are cached per size class) and answers many queries; :func:`generate_trajectory` is the one-shot call.
If any optimisation stage fails or its setpoints fail the gate (:func:`trajopt.verify.verify_setpoints`), the
plan itself is re-timed (every straight step rest to rest along the plan's polyline, which is collision-free by
construction), marked as the fallback with the reason, and verified too. Nothing unverified is returned.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from mpa import defaults
from mpa.errors import InvalidInputError, MPAError, PlanningError
from mpa.plan import Plan
from mpa.planners import Planner, make_planner
from mpa.tracks import Track
from trajopt.corridor import CORRIDOR_SEGMENTS, CorridorProblem, hard_path_scaling
from trajopt.export import Source, Trajectory, check_rate, time_grid
from trajopt.fastpath import straight_line_clearance, straight_scaling
from trajopt.smoothing import RouteGeometry
from trajopt.timing import Limits, TimeScaling, blend_polyline, jerk_limited_scaling
from trajopt.verify import VerificationError, VerificationReport, verify_setpoints

__all__ = ["RATE_LADDER", "TrajectoryGenerator", "generate_trajectory", "separation_margin"]


def separation_margin(limits: Limits, rate: float) -> float:
    """Extra separation (m) the geometric path keeps so that the gate's between-rows bound holds.

    The gate allows the motion to deviate from the chord between rows by ``Σ amax·Δt²/8``; the path keeps
    twice that (the chord loses it once, the bound once more) plus 1e-9 m.
    """
    dt = 1.0 / rate
    return 2.0 * float(np.sum(limits.a)) * dt * dt / 8.0 + 1e-9


@dataclass
class TrajectoryGenerator:
    """Verified jerk-limited trajectories for many queries on one track.

    Parameters
    ----------
    track : Track
    clearance : float
        Required separation D (m, graph distance).
    limits : Limits
        Per-robot limits of the route coordinate.
    rate : float
        Setpoint rate (Hz).
    optimize : bool
        False skips the optimisation and always returns the re-timed plan (the benchmark's baseline).

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

    track: Track
    clearance: float = defaults.CLEARANCE
    limits: Limits = field(default_factory=Limits)
    rate: float = defaults.RATE
    optimize: bool = True
    planner: Planner = field(init=False, repr=False)
    _corridor: CorridorProblem | None = field(default=None, init=False, repr=False)

    def __post_init__(self) -> None:
        if not isinstance(self.limits, Limits):
            raise InvalidInputError(f"limits is {self.limits!r}, expected a trajopt.Limits")
        self.rate = check_rate(self.rate)
        self.planner = make_planner(self.track, self.clearance)
        self.clearance = self.planner.clearance

    # ---------------------------------------------------------------------------------------------
    def plan(self, start: ArrayLike, goal: ArrayLike) -> Plan:
        """The topological plan of a query (validates it; see :meth:`mpa.planners.Planner.plan`)."""
        return self.planner.plan(start, goal)

    def generate(self, start: ArrayLike, goal: ArrayLike, *, delay_tolerance: float | None = None) -> Trajectory:
        """A verified trajectory from ``start`` to ``goal`` (track coordinates of A and B).

        With ``delay_tolerance`` (s), one whose delay tolerance (:meth:`Trajectory.margins`) is at least that
        (:func:`trajopt.delay.generate_with_delay_tolerance`: a larger effective clearance, then slower).

        Raises
        ------
        InvalidInputError
            Bad start or goal (off the track, closer than the clearance), bad ``delay_tolerance``.
        NoMotionError
            No collision-free motion exists (e.g. the order must change and ``D ≥ loop/2``), or none found
            with the requested delay tolerance (the message states the best value found).
        PlanningError
            Even the re-timed plan fails verification (never expected).
        """
        if delay_tolerance is not None:
            from trajopt.delay import generate_with_delay_tolerance

            return generate_with_delay_tolerance(self, start, goal, delay_tolerance)
        t0 = time.perf_counter()
        plan = self.plan(start, goal)
        timings: dict[str, Any] = {"plan": time.perf_counter() - t0}
        return self.generate_from_plan(plan, timings)

    def generate_from_plan(self, plan: Plan, timings: dict[str, Any] | None = None) -> Trajectory:
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
            return self._generate(plan, timings)
        except _RejectedError as exc:
            why = self._explain_rejection(plan)
            if why:
                raise InvalidInputError(why) from None
            raise PlanningError(str(exc)) from exc

    def at_rate(self, rate: float) -> TrajectoryGenerator:
        """The same generator at another setpoint rate (Hz; the planner is shared)."""
        gen = TrajectoryGenerator.__new__(TrajectoryGenerator)
        gen.track, gen.clearance, gen.limits, gen.optimize, gen.planner = (
            self.track,
            self.clearance,
            self.limits,
            self.optimize,
            self.planner,
        )
        gen.rate = check_rate(rate)
        return gen

    def lowest_rate(self, plan: Plan, upto: float = 20_000.0) -> float | None:
        """The lowest rate of :data:`RATE_LADDER` above :attr:`rate` at which ``plan`` gives verified setpoints.

        Exponential then bisection search over the ladder (passing is assumed monotone in the rate, as the
        gate's between-rows bound shrinks with the step); ``None`` if even ``upto`` Hz fails.
        """
        ladder = [r for r in _ladder(self.rate, upto) if r > self.rate]

        def ok(r: float) -> bool:
            try:
                self.at_rate(r)._generate(plan, None)
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

    def _explain_rejection(self, plan: Plan) -> str:
        """Why every candidate of ``plan`` fails the gate at this rate, if the caller can fix it ("" if not)."""
        best = self.lowest_rate(plan)
        if best is not None:
            return (
                f"rate is {self.rate!r} Hz, too low for this motion: between rows the robots could come closer "
                f"than the clearance {self.clearance!r} m; the lowest usable rate is {best:g} Hz"
            )
        margin = separation_margin(self.limits, self.rate)
        for name, st in (("start", plan.start), ("goal", plan.goal)):
            d = float(plan.track.distance_scalar(float(st[0]), float(st[1])))
            if d < self.clearance + margin:
                return (
                    f"{name} ({float(st[0])!r}, {float(st[1])!r}) has the robots {d!r} apart, expected more than "
                    f"the clearance {self.clearance!r} plus {margin:.3g} m: the gate cannot verify setpoints that "
                    f"leave robots at rest exactly at the clearance (at {self.rate:g} Hz); lower the clearance "
                    f"or move the {name} apart"
                )
        return ""

    def _generate(self, plan: Plan, timings: dict[str, Any] | None = None) -> Trajectory:
        timings = dict(timings or {})
        t_all = time.perf_counter()
        geom = RouteGeometry(plan.track, plan.routes)
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
            path = blend_polyline(_dedupe(plan.waypoints_s))
            scaling = jerk_limited_scaling(path, self.limits)
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
        (see :func:`trajopt.replan.replan`)."""
        from trajopt.replan import replan

        return replan(self, trajectory, at_time, goal)

    # ---------------------------------------------------------------------------------------------
    def _optimized(self, plan: Plan, geom: RouteGeometry, timings: dict[str, Any], stats: dict[str, Any]) -> Trajectory:
        sep = self.clearance + separation_margin(self.limits, self.rate)
        t0 = time.perf_counter()
        line = straight_line_clearance(plan, geom)
        if line >= sep or plan.length <= 0:  # the fast path: one phase-synchronised profile along the straight line
            scaling = straight_scaling(plan, self.limits)
            timings["jerk"] = time.perf_counter() - t0
            stats.update(scaling.stats, path="fast", line_clearance=line)
        else:
            if self._corridor is None:
                self._corridor = CorridorProblem(CORRIDOR_SEGMENTS, self.limits.v)
            scaling, st = hard_path_scaling(plan, geom, sep, self.limits, self._corridor, timings)
            stats.update(st, path="hard", line_clearance=line)
        return self._finish(plan, scaling, Source.OPTIMIZED, "", stats, timings)

    def _finish(
        self,
        plan: Plan,
        scaling: TimeScaling,
        source: Source,
        reason: str,
        stats: dict[str, Any],
        timings: dict[str, Any],
    ) -> Trajectory:
        t0 = time.perf_counter()
        t = time_grid(scaling.duration, self.rate)
        s, v, a, j = scaling.sample(t)
        routes = plan.routes
        tr = np.stack([routes[0].position(s[:, 0]), routes[1].position(s[:, 1])], axis=1)
        timings["sample"] = time.perf_counter() - t0
        t1 = time.perf_counter()
        rep: VerificationReport = verify_setpoints(
            plan.track,
            routes,
            t,
            tr,
            s,
            v,
            a,
            j,
            limits=self.limits,
            clearance=self.clearance,
            start=plan.start,
            goal=plan.goal,
            word=plan.word,
            rate=self.rate,
        )
        timings["verify" if source is Source.OPTIMIZED else "fallback_verify"] = time.perf_counter() - t1
        if not rep.ok:
            raise VerificationError(rep)
        return Trajectory(
            t=t,
            track=tr,
            s=s,
            v=v,
            a=a,
            j=j,
            limits=self.limits,
            clearance=self.clearance,
            rate=self.rate,
            makespan=float(t[-1]),
            motion_time=scaling.duration,
            min_separation=rep.min_separation,
            domain=plan.domain,
            word=tuple(plan.word),
            source=source,
            fallback_reason=reason,
            solver_stats=dict(stats),
            timings=timings,
            verification=rep.to_dict(),
            plan=plan,
            sampler=scaling.sample,
            retimer=lambda r: self.at_rate(r).generate_from_plan(plan),
        )


class _RejectedError(PlanningError):
    """Neither the optimised motion nor the re-timed plan passes the gate (the caller may be told why)."""


def _ladder(lo: float, hi: float) -> list[float]:
    """Round rates (Hz) from below ``lo`` up to ``hi``: 1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 8 per decade."""
    out: list[float] = []
    e = int(np.floor(np.log10(max(lo, 1e-3))))
    while True:
        for m in RATE_LADDER:
            r = float(f"{m * 10.0**e:.6g}")
            if r > hi:
                return out
            out.append(r)
        e += 1


#: Mantissas of the round rates tried when a rate is too low (see :meth:`TrajectoryGenerator.lowest_rate`).
RATE_LADDER = (1.0, 1.2, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0)


def _dedupe(pts: ArrayLike) -> np.ndarray:
    p = np.atleast_2d(np.asarray(pts, dtype=float))
    keep = np.concatenate([[True], np.linalg.norm(np.diff(p, axis=0), axis=1) > 1e-12])
    out = p[keep]
    out[-1] = p[-1]
    return out


def generate_trajectory(
    track: Track,
    start: ArrayLike,
    goal: ArrayLike,
    *,
    clearance: float = defaults.CLEARANCE,
    vmax: Any = defaults.VMAX,
    amax: Any = defaults.AMAX,
    jmax: Any = defaults.JMAX,
    rate: float = defaults.RATE,
    delay_tolerance: float | None = None,
) -> Trajectory:
    """One call from a query to a verified jerk-limited :class:`~trajopt.export.Trajectory`.

    Parameters
    ----------
    track : Track
    start, goal : array_like, shape (2,)
        Track coordinates of robots A and B (m).
    clearance : float
        Required separation D (m, graph distance).
    vmax, amax, jmax : float or (float, float)
        Per-robot limits (m/s, m/s², m/s³).
    rate : float
        Setpoint rate (Hz).
    delay_tolerance : float, optional
        Ask for a delay tolerance of at least this (s; see :mod:`trajopt.delay`).

    Returns
    -------
    Trajectory

    Raises
    ------
    InvalidInputError
        Bad limits, rate, clearance, start, goal or delay tolerance.
    NoMotionError
        No collision-free motion exists (or none with the requested delay tolerance).
    PlanningError
        Not even the re-timed plan passes verification.

    Examples
    --------
    >>> from mpa import Lollipop
    >>> traj = generate_trajectory(Lollipop(1.0, 1.0), (0.1, 0.6), (0.8, 0.3))
    >>> traj.t.shape[0] == traj.s.shape[0], traj.fallback
    (True, False)
    """
    gen = TrajectoryGenerator(track, clearance=clearance, limits=Limits(vmax, amax, jmax), rate=rate)
    return gen.generate(start, goal, delay_tolerance=delay_tolerance)
