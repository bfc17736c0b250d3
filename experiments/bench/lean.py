"""The lean OMPL pipeline: what a careful user writes to get verified setpoints from OMPL.

:class:`LeanOmpl` builds its OMPL objects once (state space, ``SimpleSetup``, validity checker, motion validator,
``RRTConnect``, ``PathSimplifier``) and per query only clears the planner's tree and sets the start and goal:

1. ``RRTConnect`` (budget 1 s, a timed termination condition without OMPL's checking thread) in
   ``RealVectorStateSpace(2)`` of track coordinates on the lollipop (range = the space's extent, so that a step
   can pass the loop's seam) or ``SO2 × SO2`` on the circle;
2. an *exact geodesic* motion validator: between two states every robot moves along a shortest path of the track
   (through the seam when shorter), and the minimum separation of the joint move is computed exactly
   (:func:`~bench.geometry.joint_move_min_distance`); a Python validity callable ``d ≥ separation``;
3. simplification: ``reduceVertices`` (until it stops improving, at most 6 times) and ``collapseCloseVertices``
   (vertex-to-vertex shortcuts, each checked by the same validator; OMPL's partial shortcuts interpolate in
   coordinates, which is not the geodesic motion);
4. timing: rest to rest at every waypoint, one jerk-limited ruckig profile per straight segment (1-DoF, the
   segment's Euclidean length in the two robots' arc lengths, under the binding robot's limits: both robots in
   phase, on the segment);
5. setpoints at the rate and *dense verification* of them: the separation ``d ≥ D`` at every row, the
   displacement between rows within what ``vmax`` allows, the ends at the start and the goal.

Not included (ours does them; a lean user does not): the full gate of :func:`trajopt.verify.gate.verify_setpoints`
(route consistency, homotopy class of the rows, acceleration and jerk re-checked from the rows), the homotopy
word of the result, reproducible per-query seeding (the objects are built once, so a query's random stream
depends on what ran before it in the process: a δ-twin is therefore a *re-seeded* twin).
"""

from __future__ import annotations

import itertools
import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bench.geometry import joint_move_min_distance, leg_moves_circle, leg_moves_geodesic
from bench.ompl_tools import joint_state_space
from mpa.routes import RobotMove
from mpa.tracks import Circle, Lollipop, Track
from trajopt import Limits
from trajopt.timing import rest_to_rest_profile

__all__ = ["LeanOmpl", "LeanResult"]

FloatArray = NDArray[np.float64]


@dataclass
class LeanResult:
    """One query of the lean pipeline.

    Attributes
    ----------
    success : bool
        RRTConnect found an exact solution.
    verified : bool
        The setpoints passed the dense check.
    compute_time : float
        Query to verified setpoints (s).
    t, q : ndarray, shapes (M,) and (M, 2)
        Setpoint times (s) and track coordinates (empty on failure).
    makespan : float
        Motion time (s).
    min_separation : float
        Smallest separation at the rows (m).
    waypoints : int
    times : dict
        Seconds in ``solve``, ``simplify``, ``timing`` (profiles and setpoints), ``verify``.
    """

    success: bool
    verified: bool
    compute_time: float
    t: FloatArray = field(default_factory=lambda: np.zeros(0))
    q: FloatArray = field(default_factory=lambda: np.zeros((0, 2)))
    makespan: float = math.nan
    min_separation: float = math.nan
    waypoints: int = 0
    times: dict[str, float] = field(default_factory=dict)
    error: str = ""


def _positions(track: Track, moves: tuple[RobotMove, ...], x: FloatArray) -> FloatArray:
    """Track coordinates at arc lengths ``x`` (m, from the leg's start) along a robot's moves. Shape (N,)."""
    ell, c = (track.stick, track.loop) if isinstance(track, Lollipop) else (0.0, track.loop)  # type: ignore[attr-defined]
    out = np.empty_like(x)
    acc = 0.0
    done = np.zeros(len(x), dtype=bool)
    for k, m in enumerate(moves):
        L = abs(m.delta)
        sel = ~done & ((x <= acc + L) | (k == len(moves) - 1))
        u = np.clip(x[sel] - acc, 0.0, L)
        e = m.start + math.copysign(1.0, m.delta) * u
        out[sel] = e if m.edge == "stick" else ell + np.mod(e, c)
        done |= sel
        acc += L
    if isinstance(track, Lollipop):
        out = np.where(out >= ell + c - 1e-12, ell, out)
    else:
        out = np.where(out >= c - 1e-12, 0.0, out)
    return out


def _profile(length: float, v: float, a: float, j: float) -> tuple[FloatArray, ...]:
    """One rest-to-rest ruckig profile of ``length``: phase start times, p, v, a at them, jerks, duration."""
    prof = rest_to_rest_profile(length, v, a, j)
    return prof.t0, prof.p, prof.v, prof.a, prof.j, prof.duration


class LeanOmpl:
    """The lean OMPL pipeline (see the module docstring), objects built once.

    Parameters
    ----------
    track : Track
        A lollipop or a circle.
    clearance : float
        Required separation D checked at the setpoints (m).
    separation : float
        Separation the planner keeps (D plus the between-rows margin, m).
    limits : Limits
    rate : float
        Setpoint rate (Hz).
    budget : float
        RRTConnect's time budget (s).
    """

    def __init__(
        self, track: Track, clearance: float, separation: float, limits: Limits, rate: float, budget: float = 1.0
    ) -> None:
        from ompl import base as ob
        from ompl import geometric as og
        from ompl import util as ou

        ou.setLogLevel(ou.LOG_NONE)
        self.track, self.clearance, self.separation = track, float(clearance), float(separation)
        self.limits, self.rate, self.budget = limits, float(rate), float(budget)
        self.circle = isinstance(track, Circle)
        self._scale = track.loop / (2.0 * math.pi) if self.circle else 1.0  # type: ignore[attr-defined]
        dist, sep = track.distance_scalar, self.separation
        space = joint_state_space(ob, track.total_length, circle=self.circle)
        to_track, legs = self._to_track, self._legs

        def valid(state: Any) -> bool:
            a, b = to_track(state)
            return dist(a, b) >= sep

        class GeodesicMotionValidator(ob.MotionValidator):  # type: ignore[misc]
            def checkMotion(self, s1: Any, s2: Any, *_last: Any) -> bool:
                ma, mb = legs(to_track(s1), to_track(s2))
                return joint_move_min_distance(track, ma, mb) >= sep

        ss = og.SimpleSetup(space)
        ss.setStateValidityChecker(valid)
        si = ss.getSpaceInformation()
        self._validator = GeodesicMotionValidator(si)
        si.setMotionValidator(self._validator)
        planner = og.RRTConnect(si)
        if not self.circle:
            planner.setRange(space.getMaximumExtent())
        ss.setPlanner(planner)
        ss.setup()
        self._space, self._ss, self._si = space, ss, si
        self._simp = og.PathSimplifier(si)
        self._og, self._ob = og, ob

    def close(self) -> None:
        """Drop the OMPL objects (the motion validator holds Python callbacks: break the cycle)."""
        for name in ("_validator", "_simp", "_ss", "_si", "_space"):
            self.__dict__.pop(name, None)

    def _to_track(self, state: Any) -> tuple[float, float]:
        if self.circle:
            c = self.track.loop  # type: ignore[attr-defined]
            return (state[0].value * self._scale) % c, (state[1].value * self._scale) % c
        return state[0], state[1]

    def _set(self, state: Any, p: FloatArray) -> None:
        if self.circle:
            for r in (0, 1):
                state[r].value = (float(p[r]) / self._scale + math.pi) % (2.0 * math.pi) - math.pi
        else:
            state[0], state[1] = float(p[0]), float(p[1])

    def _legs(self, a: tuple[float, float], b: tuple[float, float]) -> tuple[tuple[RobotMove, ...], ...]:
        fn = leg_moves_circle if self.circle else leg_moves_geodesic
        return fn(self.track, a[0], b[0]), fn(self.track, a[1], b[1])

    def solve(self, start: ArrayLike, goal: ArrayLike) -> LeanResult:
        """Query to verified setpoints (see the module docstring)."""
        t0 = time.perf_counter()
        s, g = np.asarray(start, dtype=float), np.asarray(goal, dtype=float)
        ss = self._ss
        ss.clear()
        st, gl = self._space.allocState(), self._space.allocState()
        self._set(st, s)
        self._set(gl, g)
        ss.setStartAndGoalStates(st, gl)
        # a timed condition without a checking thread (OMPL's solve(t) starts one for t >= 1 s, and joining it
        # costs up to its 10 ms period: that was most of this pipeline's compute time, and the p95)
        ss.solve(self._ob.timedPlannerTerminationCondition(self.budget))
        t1 = time.perf_counter()
        if not ss.haveExactSolutionPath():
            return LeanResult(False, False, t1 - t0, error=f"no exact solution in {self.budget:g} s")
        path = self._og.PathGeometric(ss.getSolutionPath())
        more, k = self._simp.reduceVertices(path), 0
        while more and k < 5:
            more, k = self._simp.reduceVertices(path), k + 1
        self._simp.collapseCloseVertices(path)
        pts = [self._to_track(x) for x in path.getStates()]
        t2 = time.perf_counter()
        lim, dt = self.limits, 1.0 / self.rate
        ts, qs, t_acc = [], [], 0.0
        for p0, p1 in itertools.pairwise(pts):
            ma, mb = self._legs(p0, p1)
            la, lb = sum(abs(m.delta) for m in ma), sum(abs(m.delta) for m in mb)
            length = math.hypot(la, lb)
            if length <= 0.0:
                continue
            ua, ub = la / length, lb / length
            v, a, j = (
                min(x[r] / u for r, u in ((0, ua), (1, ub)) if u > 0) for x in (lim.v, lim.a, lim.j)
            )  # the binding robot's limits on the segment's length
            p_t0, pp, pv, pa, pj, dur = _profile(length, v, a, j)
            tt = np.arange(0.0, dur, dt)
            k_ph = np.clip(np.searchsorted(p_t0, tt, side="right") - 1, 0, 6)
            tau = tt - p_t0[k_ph]
            x = pp[k_ph] + pv[k_ph] * tau + 0.5 * pa[k_ph] * tau**2 + pj[k_ph] * tau**3 / 6.0
            x = np.clip(x, 0.0, length)
            ts.append(t_acc + tt)
            qs.append(np.stack([_positions(self.track, ma, x * ua), _positions(self.track, mb, x * ub)], axis=1))
            t_acc += dur
        ts.append(np.array([t_acc]))
        qs.append(np.array([pts[-1]], dtype=float))
        t_arr, q = np.concatenate(ts), np.vstack(qs)
        t3 = time.perf_counter()
        # dense verification of the setpoints
        tr = self.track
        d = tr.distance(q[:, 0], q[:, 1])
        step = tr.distance(q[1:], q[:-1]) if len(q) > 1 else np.zeros((0, 2))
        ok = bool(
            np.all(d >= self.clearance)
            and np.all(step <= np.asarray(lim.v) * dt * (1 + 1e-9) + 1e-12)
            and float(np.max(tr.distance(q[0], s))) <= 1e-9
            and float(np.max(tr.distance(q[-1], g))) <= 1e-9
        )
        t4 = time.perf_counter()
        return LeanResult(
            True,
            ok,
            t4 - t0,
            t_arr,
            q,
            t_acc,
            float(np.min(d)),
            len(pts),
            {"solve": t1 - t0, "simplify": t2 - t1, "timing": t3 - t2, "verify": t4 - t3},
            "" if ok else "dense check failed",
        )
