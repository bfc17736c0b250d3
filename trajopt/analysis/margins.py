"""How much tracking error and delay a verified motion survives: :func:`margins`.

Both margins are computed on the continuous motion (:attr:`Trajectory.sampler`), with the exact graph metric of
the track, on a dense time grid of :data:`DENSE_RATE` Hz plus the gate's rigorous between-rows bound
(:func:`trajopt.verify.gate.between_rows_separation`: chord minimum minus the deviation ``a_int·Δt²/8``).

Tracking margin ``r`` (m)
    The largest ``r`` such that both carts, each anywhere within ``r`` of its setpoint *along its own route*, at
    every instant, keep the separation ``>= D``. Moving a point by ``x`` along a route moves it by at most ``x``
    in the graph metric, so by the triangle inequality two points displaced by ``<= r`` each are at least
    ``d − 2r`` apart; the bound is attained by displacing both toward each other along the shortest path
    (each cart's route runs both ways along its edge, so it can). Hence

        ``tracking_margin = (d_min − D) / 2``,   ``d_min = min over t of d(A(t), B(t))``.

    ``d_min`` is the minimum of the continuous motion, by branch and bound: grid steps whose lower bound is below
    the best value found are cut into 8 and bounded again (four levels), so ``d_min`` is exact to
    :data:`MIN_PRECISION` (1e-9 m) wherever the bound allows it, and an upper bound of the true minimum
    (it is a sampled value) within the gate's slack (``Σ amax·(Δt/8⁴)²/8``) of it. Where more than
    :data:`MAX_REFINE_STEPS` steps would have to be cut at one level (carts moving in step at their closest for
    a long time, e.g. a 4 600 s motion), ``d_min`` is the smallest lower bound of those steps instead: below the
    true minimum by at most that level's slack, so the tracking margin is never overstated.

Delay tolerance ``τ`` (s)
    The largest ``τ`` such that delaying either cart's whole motion by any ``δ ∈ [0, τ]`` (the other on time,
    each cart at rest at its start before and at its goal after its own motion) keeps the separation ``>= D``
    (to the gate's tolerance :data:`~trajopt.verify.gate.SEPARATION_TOL`). With ``F(δ) = min_t d(A(t − δ), B(t))``
    (A delayed; likewise B), ``τ_A = sup{τ : F ≥ D on [0, τ]}`` is found by interval stepping on ``δ`` with a
    rigorous bound: over ``[δ, δ + h]`` the delayed cart's position at time ``t`` changes by at most
    ``h·V(t)``, with ``V(t)`` its peak speed over the times ``[t − δ − h, t − δ]`` of its own motion (largest
    sampled ``|v|`` plus ``amax·Δt/2``), or 0 where it rests throughout; so
    ``F ≥ min_k [lb_k(δ) − h·V_k]`` (``lb_k`` the between-rows bound of grid step k). An interval that passes is
    accepted (and ``h`` doubled, up to the motion's time ``T``; the first step is :data:`DELAY_STEP`); one that
    fails is halved, down to :data:`DELAY_PRECISION`, where ``τ`` is set. So ``τ`` is a lower bound of the true
    value, short of it by at most ``DELAY_PRECISION`` plus the bound's slack (``≈ Σ amax·Δt²/8``, 2.5e-7 m at
    1 kHz, divided by the rate at which ``F`` falls). Delaying a cart by more than its whole motion changes
    nothing more (it waits at its start during the other's motion, then moves while the other rests at its
    goal): if the stepping passes the cart's own motion time, ``τ`` is infinite.
    ``delay_tolerance = min(τ_A, τ_B)``. Where ``F`` stays within the bound's slack of ``D`` over a long range
    of delays (a grazing contact) the steps shrink; the search stops after :data:`MAX_DELAY_STEPS` steps and
    reports the delay reached (a lower bound) with ``delay_resolved = False``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from mpa._arrays import FloatArray
from trajopt.path.planview import plan_view
from trajopt.verify.gate import SEPARATION_TOL, between_rows_separation

if TYPE_CHECKING:  # the result type calls margins() (Trajectory.margins): a type here, no import at run time
    from trajopt.result import Trajectory

__all__ = [
    "DELAY_PRECISION",
    "DENSE_RATE",
    "Margins",
    "delay_tolerance",
    "margins",
    "min_separation",
    "tracking_margin",
]

#: Rate of the dense grid (Hz).
DENSE_RATE = 1000.0
#: Largest number of rows of a dense grid: longer motions get a lower dense rate (a bounded cost).
MAX_DENSE_ROWS = 20_000
#: Most grid steps :meth:`_Motion.exact_min` cuts at one level (a bounded cost; beyond it the result is a lower bound).
MAX_REFINE_STEPS = 20_000
#: Precision of the minimum separation (m).
MIN_PRECISION = 1e-9
#: Resolution of the delay tolerance (s).
DELAY_PRECISION = 1e-6
#: First δ step of the delay search (s); a step that keeps the clearance doubles the next, up to the motion's time
#: (delays far from a contact cost a few steps, not one a second).
DELAY_STEP = 1.0
#: Cap on the rows the delay search of one cart samples (a bounded cost for long motions; the value reached is
#: returned, a lower bound, as at :data:`MAX_DELAY_STEPS`).
MAX_DELAY_ROWS = 4_000_000
#: Cap on the steps of the delay search (the value reached is returned: a lower bound).
MAX_DELAY_STEPS = 400


@dataclass(frozen=True)
class Margins:
    """Tracking and delay margins of a motion (see the module docstring).

    Attributes
    ----------
    tracking_margin : float
        m, ``(d_min − D)/2``.
    min_separation : float
        ``d_min``: the smallest separation of the continuous motion (m).
    min_separation_time : float
        When it occurs (s).
    delay_tolerance : float
        s, ``min(delay_a, delay_b)``; ``math.inf`` if neither delay can break the separation.
    delay_a, delay_b : float
        The largest delay of robot A (of B) alone that keeps the separation (s; may be ``math.inf``).
    delay_resolved : bool
        False if a delay search stopped at :data:`MAX_DELAY_STEPS` (the separation stays within the bound's
        slack of D over a long range of delays): the values are then lower bounds.
    """

    tracking_margin: float
    min_separation: float
    min_separation_time: float
    delay_tolerance: float
    delay_a: float
    delay_b: float
    delay_resolved: bool = True

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: an infinite delay is written as None with ``"delay_unbounded": true``."""

        def fin(x: float) -> float | None:
            return None if math.isinf(x) else float(x)

        return {
            "tracking_margin": float(self.tracking_margin),
            "min_separation": float(self.min_separation),
            "min_separation_time": float(self.min_separation_time),
            "delay_tolerance": fin(self.delay_tolerance),
            "delay_unbounded": math.isinf(self.delay_tolerance),
            "delay_a": fin(self.delay_a),
            "delay_b": fin(self.delay_b),
            "delay_resolved": self.delay_resolved,
            "units": {"tracking_margin": "m", "min_separation": "m", "delay_tolerance": "s"},
        }


class _Motion:
    """Both carts' positions with optional delays, and the separation on grids."""

    def __init__(self, trajectory: Trajectory) -> None:
        self.traj = trajectory
        plan: Any = trajectory.plan
        view = plan_view(plan)
        if view.is_graph:  # the graph metric and the directed routes (the gate's bound takes both forms)
            self.track: Any = view.graph.geometry
            self.routes: Any = view.routes
        else:
            self.track = plan.track
            self.routes = plan.routes
        self.graph = view.is_graph
        self.T = float(trajectory.motion_time)
        # the dense grid's rate: DENSE_RATE, lowered for long motions so that a grid has at most MAX_DENSE_ROWS
        # rows (the bounds stay lower bounds at any step, only looser): a bounded cost per search step
        self.rate = min(DENSE_RATE, MAX_DENSE_ROWS / max(self.T, 1e-9))
        _, v, _, _ = trajectory.sampler(np.linspace(0.0, self.T, max(2, int(self.T * self.rate) + 1)))
        lim = trajectory.limits
        self.vpeak = np.minimum(np.max(np.abs(v), axis=0) + lim.a / self.rate, lim.v)
        self.sampled = 0  # rows sampled by :meth:`states` (the delay search's budget, MAX_DELAY_ROWS)

    def states(self, t: FloatArray, delay: FloatArray) -> tuple[FloatArray, FloatArray]:
        self.sampled += len(t)
        if delay[1] == delay[0]:  # both carts on the same clock: one sampling gives both columns
            s0, _, a0, _ = self.traj.sampler(t - delay[0])
            return s0, a0
        # each cart on its own clock: both clocks' times in one call (the sampler works row by row, so the numbers
        # are those of two calls; a call has a fixed cost, the larger with the kernels' numpy twins)
        n = len(t)
        s, _, a, _ = self.traj.sampler(np.concatenate([t - delay[0], t - delay[1]]))
        return np.column_stack([s[:n, 0], s[n:, 1]]), np.column_stack([a[:n, 0], a[n:, 1]])

    def dist(self, s: FloatArray) -> FloatArray:
        r = self.routes
        if self.graph:
            (ea, oa), (eb, ob) = r[0].positions(s[:, 0]), r[1].positions(s[:, 1])
            return self.track.distance(ea, oa, eb, ob)
        return self.track.distance(r[0].position(s[:, 0]), r[1].position(s[:, 1]))

    def grid(self, delay: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Times, separations at the rows, between-rows lower bounds for a motion with delays (s)."""
        end = self.T + float(np.max(delay))
        n = int(np.ceil(end * self.rate - 1e-9)) + 1
        t = np.arange(max(n, 2)) / self.rate
        s, a = self.states(t, delay)
        d = self.dist(s)
        lb = between_rows_separation(self.track, self.routes, s, a, 1.0 / self.rate, self.traj.limits_used)
        return t, d, lb

    def _near_rows(self, delay: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """:meth:`grid` restricted to the rows that can hold the minimum: rows, separations, between-rows bounds.

        Blocks of ``w`` rows from ``t_0`` whose bound ``d(t_0) − (V_A + V_B)·w·Δt`` is above the smallest
        separation sampled so far cannot hold the minimum (each cart moves at most its peak speed ``V`` times the
        time) and are dropped; the others are cut into 8, down to blocks of 8 steps, whose rows are returned with
        the bounds between them (``inf`` across the gaps between blocks). Every row dropped has a separation
        above the returned minimum, so the minimum and the rows to refine are those of the full grid.
        """
        end = self.T + float(np.max(delay))
        n_rows = max(int(np.ceil(end * self.rate - 1e-9)) + 1, 2)
        dt = 1.0 / self.rate
        v = float(np.sum(self.vpeak))
        w = 8
        while w * 8 < n_rows:
            w *= 8
        starts = np.arange(0, n_rows - 1, w, dtype=np.int64)
        best = math.inf
        while w > 8:
            s, _ = self.states(starts / self.rate, delay)
            d = self.dist(s)
            best = min(best, float(np.min(d)))
            starts = starts[d - v * w * dt <= best]
            w //= 8
            starts = (starts[:, None] + w * np.arange(8)[None, :]).ravel()
            starts = starts[starts < n_rows - 1]
        k = np.minimum(starts[:, None] + np.arange(9)[None, :], n_rows - 1).ravel()
        t = k / self.rate
        s, a = self.states(t, delay)
        d = self.dist(s)
        lb = between_rows_separation(self.track, self.routes, s, a, dt, self.traj.limits_used)
        lb = np.append(lb, np.inf).reshape(-1, 9)
        lb[:, 8] = np.inf  # no step across the gap to the next block
        return t, d, lb.ravel()[:-1]

    def exact_min(self, delay: FloatArray) -> tuple[float, float]:
        """Minimum separation of the continuous motion (m) and its time (s), to :data:`MIN_PRECISION`.

        Branch and bound: grid steps whose lower bound (the gate's between-rows bound) is below the best
        separation found minus :data:`MIN_PRECISION` are cut into 8 and bounded again, down to steps of
        ``Δt/8⁴``. When more than :data:`MAX_REFINE_STEPS` steps are left to cut (the carts moving in step at
        the minimum for a long time), the smallest of their lower bounds is returned instead, with its step's
        time: below the true minimum by at most the between-rows slack of that level (conservative).
        """
        return self.refine_min(self._near_rows(delay), delay)

    def refine_min(self, rows: tuple[FloatArray, FloatArray, FloatArray], delay: FloatArray) -> tuple[float, float]:
        """The branch and bound of :meth:`exact_min` from the rows ``(t, d, lb)`` of :meth:`grid` (or of the rows
        near contact): minimum separation (m) and its time (s)."""
        t, d, lb = rows
        k = int(np.argmin(d))
        best, t_best = float(d[k]), float(t[k])
        keep = lb < best - MIN_PRECISION
        lo, bound = t[:-1][keep], lb[keep]
        w = 1.0 / self.rate
        u = np.arange(9) / 8.0
        for _ in range(4):
            if len(lo) == 0:
                break
            if len(lo) > MAX_REFINE_STEPS:
                m0 = int(np.argmin(bound))
                return min(best, float(bound[m0])), float(lo[m0])
            tt = lo[:, None] + w * u[None, :]
            s, a = self.states(tt.ravel(), delay)
            dd = self.dist(s).reshape(tt.shape)
            m = np.unravel_index(int(np.argmin(dd)), dd.shape)
            if dd[m] < best:
                best, t_best = float(dd[m]), float(tt[m])
            w /= 8.0
            sub = between_rows_separation(self.track, self.routes, s, a, w, self.traj.limits_used)
            sub = np.append(sub, np.inf).reshape(tt.shape)[:, :8]  # drop the pairs across candidates
            keep = sub < best - MIN_PRECISION
            lo, bound = tt[:, :8][keep], sub[keep]
        return best, t_best

    def delay_limit(self, robot: int) -> tuple[float, bool]:
        """τ of one robot (see the module docstring), and whether the search resolved it (not capped)."""
        D = self.traj.clearance - SEPARATION_TOL
        if self.T <= 0.0 or float(self.vpeak[robot]) <= 0.0:
            return math.inf, True
        delta, h = 0.0, DELAY_STEP
        self.steps = 0
        first = self.sampled
        while delta <= self.T:
            self.steps += 1
            if self.steps > MAX_DELAY_STEPS or self.sampled - first > MAX_DELAY_ROWS:
                return delta, False
            if self._delay_interval_holds(robot, delta, h, D):
                delta += h
                h = min(2.0 * h, max(DELAY_STEP, self.T))
            elif h <= DELAY_PRECISION:
                return delta, True
            else:
                h /= 2.0
        return math.inf, True

    def _own_speed_max(self, robot: int) -> list[FloatArray]:
        """Sparse table of the cart's sampled speed on its own grid ``j/the dense rate``: level q holds
        ``max(|v_j| … |v_{j+2^q−1}|)`` (built once per robot, levels added as needed)."""
        cache = self.__dict__.setdefault("_speed_tables", {})
        if robot not in cache:
            n = int(np.ceil(self.T * self.rate - 1e-9)) + 1
            u = np.minimum(np.arange(n) / self.rate, self.T)
            cache[robot] = [np.abs(self.traj.sampler(u)[1][:, robot])]
        table: list[FloatArray] = cache[robot]
        return table

    def _peak_speed(self, robot: int, u0: FloatArray, u1: FloatArray) -> FloatArray:
        """An upper bound of the cart's speed over its own times ``[u0, u1]`` (m/s; 0 where it rests throughout).

        The largest sampled ``|v|`` on the own grid steps that cover the range, plus ``amax·Δt/2`` (between two
        samples ``|v|`` exceeds the larger by at most that).
        """
        dt = 1.0 / self.rate
        table = self._own_speed_max(robot)
        n = len(table[0])
        j0 = np.clip(np.floor(u0 / dt).astype(np.int64), 0, n - 1)
        j1 = np.clip(np.ceil(u1 / dt).astype(np.int64), 0, n - 1)
        width = j1 - j0 + 1
        q = int(np.floor(np.log2(max(int(width.max()), 1))))
        while len(table) <= q:
            p = 1 << (len(table) - 1)
            prev = table[-1]
            table.append(np.maximum(prev[:-p], prev[p:]) if len(prev) > p else prev[:0])
        lev = np.floor(np.log2(np.maximum(width, 1))).astype(np.int64)
        out = np.empty(len(u0))
        for level in np.unique(lev):
            sel = lev == level
            t_l = table[int(level)]
            p = 1 << int(level)
            out[sel] = np.maximum(t_l[j0[sel]], t_l[j1[sel] - p + 1])
        moving = (u1 > 0.0) & (u0 < self.T)
        amax = float(self.traj.limits.a[robot])
        return np.where(moving, np.minimum(out + amax * dt / 2.0, float(self.traj.limits.v[robot])), 0.0)

    def _delay_interval_holds(self, robot: int, delta: float, h: float, D: float) -> bool:
        """Whether ``F(δ') >= D`` for every delay ``δ' ∈ [δ, δ + h]`` of ``robot`` (a rigorous bound).

        Branch and bound over the rows ``t_k = k/self.rate`` up to ``T + δ + h``: a block of ``w`` rows from
        ``t_0`` is cleared when ``d(t_0) − V_r·(w·Δt + h) − V_o·w·Δt >= D`` (each cart moves at most its peak
        speed ``V`` times the time; the graph metric is 1-Lipschitz along a route), else cut into 8 blocks;
        blocks of 8 rows are decided by the gate's between-rows bound minus ``h·V_k`` (``V_k`` the delayed
        cart's peak speed over the own times of step k and the delays), as in the module docstring. The cost
        follows the rows near a contact, not the length of the motion.
        """
        dt = 1.0 / self.rate
        other = 1 - robot
        delay = np.zeros(2)
        delay[robot] = delta
        n_rows = int(np.ceil((self.T + delta + h) * self.rate)) + 2
        vr, vo = float(self.vpeak[robot]), float(self.vpeak[other])
        w = 8
        while w * 8 < n_rows:
            w *= 8
        starts = np.arange(0, n_rows - 1, w, dtype=np.int64)
        while w > 8:
            t0 = starts / self.rate
            s, _ = self.states(t0, delay)
            lower = self.dist(s) - vr * (w * dt + h) - vo * w * dt
            starts = starts[lower < D]
            if len(starts) == 0:
                return True
            w //= 8
            starts = (starts[:, None] + w * np.arange(8)[None, :]).ravel()
            starts = starts[starts < n_rows - 1]
        # blocks of 8 steps (9 rows): the between-rows bound, the pairs across blocks dropped
        k = (starts[:, None] + np.arange(9)[None, :]).ravel()
        t = k / self.rate
        s, a = self.states(t, delay)
        lb = between_rows_separation(self.track, self.routes, s, a, dt, self.traj.limits_used)
        lb = np.append(lb, np.inf).reshape(-1, 9)[:, :8].ravel()
        tk = (starts[:, None] + np.arange(8)[None, :]).ravel() / self.rate
        speed = self._peak_speed(robot, tk - delta - h, tk + dt - delta)
        return bool(np.min(lb - h * speed) >= D)


def min_separation(trajectory: Trajectory) -> tuple[float, float]:
    """The smallest separation of the continuous motion (m) and when it occurs (s)."""
    return _Motion(trajectory).exact_min(np.zeros(2))


def tracking_margin(trajectory: Trajectory) -> float:
    """``(d_min − D)/2`` (m): how far each cart may be from its setpoint along its route (module docstring)."""
    d, _ = min_separation(trajectory)
    return (d - trajectory.clearance) / 2.0


def delay_tolerance(trajectory: Trajectory) -> tuple[float, float, float]:
    """``(τ, τ_A, τ_B)`` (s): how late either cart may run with its whole motion (module docstring)."""
    m = _Motion(trajectory)
    (ta, _), (tb, _) = m.delay_limit(0), m.delay_limit(1)
    return min(ta, tb), ta, tb


def margins(trajectory: Trajectory) -> Margins:
    """Tracking margin and delay tolerance of a verified trajectory.

    Examples
    --------
    >>> from mpa import Lollipop
    >>> from trajopt import generate_trajectory
    >>> m = margins(generate_trajectory(Lollipop(1.0, 1.0), (0.2, 0.5), (0.5, 0.2)))
    >>> round(m.tracking_margin, 6), m.delay_tolerance > 0
    (0.125, True)
    """
    m = _Motion(trajectory)
    d, td = m.exact_min(np.zeros(2))
    (ta, ra), (tb, rb) = m.delay_limit(0), m.delay_limit(1)
    return Margins((d - trajectory.clearance) / 2.0, d, td, min(ta, tb), ta, tb, ra and rb)
