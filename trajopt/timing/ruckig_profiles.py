"""Jerk-limited profiles with ruckig.

The path parameter ``s`` is one degree of freedom, so a 1-DoF ruckig profile of ``s(t)`` can never leave the path.
Each piece gets its own 1-DoF limits (:func:`~trajopt.timing.limits.piece_limits`). Boundary states are
``(s_b, ṡ_b, 0)``; a forward-backward pass lowers the ``ṡ_b`` until every piece is long enough to change speed
within its limits, then one ruckig call per piece (state to state in one DoF, no waypoints needed) times it
(:func:`jerk_limited_scaling`). :func:`rest_to_rest_profile` and :func:`min_time_rest_to_rest` are the 1-DoF
rest-to-rest profile and its minimum time (a lower bound, for tests and benchmarks).
"""

from __future__ import annotations

import time
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from mpa._arrays import FloatArray
from mpa.errors import PlanningError
from trajopt.timing.curves import (
    BlendedPath,
)
from trajopt.timing.limits import Limits, PieceLimits, piece_limits
from trajopt.timing.scaling import TimeScaling


def _dmin(v0: float, v1: float, a: float, j: float) -> float:
    """Shortest distance to change speed from ``v0`` to ``v1`` (both ≥ 0) at zero acceleration at both ends."""
    dv = abs(v1 - v0)
    t = 2.0 * np.sqrt(dv / j) if dv <= a * a / j else dv / a + a / j
    return 0.5 * (v0 + v1) * t


def _reach(v0: float, ds: float, cap: float, a: float, j: float) -> float:
    """Highest speed ``≤ cap`` reachable from ``v0`` within ``ds`` (a = 0 at both ends)."""
    if _dmin(v0, cap, a, j) <= ds:
        return cap
    lo, hi = min(v0, cap), cap
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if _dmin(v0, mid, a, j) <= ds:
            lo = mid
        else:
            hi = mid
    return lo


def jerk_limited_scaling(
    path: BlendedPath,
    limits: Limits,
    speed_caps: FloatArray | None = None,
    safety: float = 1.0 - 1e-9,
) -> TimeScaling:
    """Time the path with one 1-DoF ruckig profile per piece (see module docstring).

    Parameters
    ----------
    path : BlendedPath
    limits : Limits
    speed_caps : ndarray, shape (P+1,), optional
        Upper bounds of ``ṡ`` at the piece boundaries (e.g. toppra's profile).
    safety : float
        Factor applied to the joint limits.

    Returns
    -------
    TimeScaling

    Raises
    ------
    PlanningError
        If ruckig reports an error.
    """
    t_start = time.perf_counter()
    P = len(path.coef)
    lens = np.diff(path.breaks)
    if path.length <= 0:
        return TimeScaling(path, np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0), 0.0, np.zeros(P + 1))
    pl = piece_limits(path, limits, safety)
    vb = _boundary_speeds(path, pl, lens, speed_caps)
    t0s, ps, vs, as_, js, pcs, t_acc = _ruckig_phases(path, pl, lens, vb)
    stats = {"pieces": P, "blends": int(np.sum(path.is_blend)), "jerk_time": time.perf_counter() - t_start}
    return TimeScaling(
        path,
        np.array(t0s),
        np.array(ps),
        np.array(vs),
        np.array(as_),
        np.array(js),
        float(t_acc),
        vb,
        np.array(pcs, dtype=np.intp),
        stats,
    )


def _boundary_speeds(path: BlendedPath, pl: PieceLimits, lens: FloatArray, speed_caps: ArrayLike | None) -> FloatArray:
    """Speeds at the piece boundaries (shape (P + 1,)): the pieces' speed limits and the caps, 0 at stops, then
    lowered by a forward and a backward pass to what a jerk-limited piece can reach."""
    P = len(lens)
    vb = np.full(P + 1, np.inf)
    vb[1:] = np.minimum(vb[1:], pl.v)
    vb[:-1] = np.minimum(vb[:-1], pl.v)
    vb[path.stop] = 0.0
    if speed_caps is not None:
        vb = np.minimum(vb, np.asarray(speed_caps, dtype=float))
    vb = np.maximum(vb, 0.0)
    for k in range(P):  # forward
        vb[k + 1] = min(vb[k + 1], _reach(vb[k], lens[k] * (1 - 1e-9), vb[k + 1], pl.a[k], pl.j[k]))
    for k in range(P - 1, -1, -1):  # backward
        vb[k] = min(vb[k], _reach(vb[k + 1], lens[k] * (1 - 1e-9), vb[k], pl.a[k], pl.j[k]))
    return vb


def _ruckig_phases(
    path: BlendedPath, pl: PieceLimits, lens: FloatArray, vb: FloatArray
) -> tuple[list[float], list[float], list[float], list[float], list[float], list[int], float]:
    """One 1-DoF ruckig profile per piece between the boundary speeds ``vb``: the phases of constant jerk (start
    times, ``s, ṡ, s̈``, jerks, piece index) and the total duration.

    Raises
    ------
    PlanningError
        ruckig fails or needs a brake profile on a piece.
    """
    from ruckig import InputParameter, Result, Ruckig, Trajectory

    otg = Ruckig(1)
    inp = InputParameter(1)
    traj = Trajectory(1)
    t0s: list[float] = []
    ps: list[float] = []
    vs: list[float] = []
    as_: list[float] = []
    js: list[float] = []
    pcs: list[int] = []
    t_acc = 0.0
    for k in range(len(lens)):
        if lens[k] <= 0:
            continue
        inp.current_position = [float(path.breaks[k])]
        inp.current_velocity = [float(vb[k])]
        inp.current_acceleration = [0.0]
        inp.target_position = [float(path.breaks[k + 1])]
        inp.target_velocity = [float(vb[k + 1])]
        inp.target_acceleration = [0.0]
        inp.max_velocity = [float(pl.v[k])]
        inp.max_acceleration = [float(pl.a[k])]
        inp.max_jerk = [float(pl.j[k])]
        res = otg.calculate(inp, traj)
        if res not in (Result.Working, Result.Finished):
            raise PlanningError(f"ruckig failed on piece {k}: {res}")
        prof = traj.profiles[0][0]
        if prof.brake.duration > 0 or prof.accel.duration > 0:
            raise PlanningError(f"ruckig used a brake profile on piece {k}")
        tp = np.asarray(prof.t, dtype=float)
        for i in range(7):
            if tp[i] <= 0:
                continue
            t0s.append(t_acc)
            ps.append(prof.p[i])
            vs.append(prof.v[i])
            as_.append(prof.a[i])
            js.append(prof.j[i])
            pcs.append(k)
            t_acc += tp[i]
    return t0s, ps, vs, as_, js, pcs, t_acc


class RestToRest(NamedTuple):
    """A 1-DoF jerk-limited profile from rest at 0 to rest at ``length``: ruckig's seven phases.

    ``dt`` (shape (7,)) the phase durations (some may be 0), ``t0`` their start times, ``p, v, a`` the state at
    each phase start and ``j`` the phase's constant jerk (each shape (7,)); ``duration`` the sum of ``dt``.
    """

    dt: FloatArray
    t0: FloatArray
    p: FloatArray
    v: FloatArray
    a: FloatArray
    j: FloatArray
    duration: float


def rest_to_rest_profile(length: float, v: float, a: float, j: float) -> RestToRest:
    """The time-optimal jerk-limited 1-DoF profile over ``length`` (m) from rest to rest (ruckig; ``length > 0``).

    Raises
    ------
    PlanningError
        ruckig reports a failure.
    """
    from ruckig import InputParameter, Result, Ruckig, Trajectory

    otg, inp, traj = Ruckig(1), InputParameter(1), Trajectory(1)
    inp.current_position, inp.target_position = [0.0], [float(length)]
    inp.current_velocity = inp.target_velocity = [0.0]
    inp.current_acceleration = inp.target_acceleration = [0.0]
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = [float(v)], [float(a)], [float(j)]
    res = otg.calculate(inp, traj)
    if res not in (Result.Working, Result.Finished):
        raise PlanningError(f"ruckig failed on a rest-to-rest move of {length!r} m: {res}")
    prof = traj.profiles[0][0]
    dt = np.asarray(prof.t, dtype=float)
    t0 = np.concatenate([[0.0], np.cumsum(dt)])[:-1]
    p, vv, aa = (np.asarray(x[:7], dtype=float) for x in (prof.p, prof.v, prof.a))
    return RestToRest(dt, t0, p, vv, aa, np.asarray(prof.j, dtype=float), float(dt.sum()))


def min_time_rest_to_rest(distance: float, v: float, a: float, j: float) -> float:
    """Jerk-limited minimum time (s) to travel ``distance`` from rest to rest in one DoF (ruckig)."""
    if distance <= 0:
        return 0.0
    return rest_to_rest_profile(distance, v, a, j).duration


def reachable_speed(length: float, amax: np.ndarray, jmax: np.ndarray) -> np.ndarray:
    """Peak speed (m/s) of a time-optimal jerk-limited rest-to-rest profile over ``length`` (m), without a speed limit.

    Parameters
    ----------
    length : float
        The travel (m, > 0).
    amax, jmax : ndarray, shape (2,)
        Acceleration (m/s²) and jerk (m/s³) limits per robot.

    Returns
    -------
    ndarray, shape (2,)
        ``amax²/jmax`` when the profile never reaches ``amax`` (``amax³ ≥ jmax²·length/2``), else the root of
        ``v²/amax + v·amax/jmax = length`` (each half covers ``v/2·(v/amax + amax/jmax)``).
    """
    a = np.asarray(amax, dtype=float)
    j = np.asarray(jmax, dtype=float)
    r = a * a / j
    with np.errstate(over="ignore", invalid="ignore"):
        plateau = 0.5 * (np.sqrt(r * r + 4.0 * a * length) - r)
        return np.where(a * a * a >= j * j * length / 2.0, r, plateau)
