"""Braking from a moving state and splicing a new motion onto it: the pieces re-planning shares on the paper's
tracks (:mod:`trajopt.replan`) and on layouts (:mod:`trajopt.replan_graph`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from mpa._arrays import FloatArray
from mpa.errors import InvalidInputError, PlanningError
from mpa.routes import Route
from trajopt.result import Trajectory

_REST = 1e-12


@dataclasses.dataclass(frozen=True)
class Brake:
    """Piecewise-constant-jerk braking of both carts. Phase tables per cart: ``t0, p, v, a, j`` (Q,);
    ``last``: the duration of each cart's last phase (s), after which the cart rests at ``stop``."""

    t0: tuple[FloatArray, FloatArray]
    p: tuple[FloatArray, FloatArray]
    v: tuple[FloatArray, FloatArray]
    a: tuple[FloatArray, FloatArray]
    j: tuple[FloatArray, FloatArray]
    duration: float
    start: FloatArray
    stop: FloatArray
    phase_synchronized: bool
    last: tuple[float, float] = (0.0, 0.0)

    def sample(self, t: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """``σ, σ̇, σ̈, σ⃛`` (each shape ``t.shape + (2,)``); held at rest at ``stop`` after the end."""
        tt = np.asarray(t, dtype=float)
        out = [np.zeros((*tt.shape, 2)) for _ in range(4)]
        for r in (0, 1):
            t0 = self.t0[r]
            if len(t0) == 0:
                out[0][..., r] = self.stop[r]
                continue
            k = np.clip(np.searchsorted(t0, tt, side="right") - 1, 0, len(t0) - 1)
            tau = np.clip(tt - t0[k], 0.0, None)
            j = self.j[r][k]
            a = self.a[r][k] + j * tau
            v = self.v[r][k] + self.a[r][k] * tau + 0.5 * j * tau**2
            s = self.p[r][k] + self.v[r][k] * tau + 0.5 * self.a[r][k] * tau**2 + j * tau**3 / 6.0
            end = t0[-1] + self.last[r]
            after = tt >= end
            out[0][..., r] = np.where(after, self.stop[r], s)
            out[1][..., r] = np.where(after, 0.0, v)
            out[2][..., r] = np.where(after, 0.0, a)
            out[3][..., r] = np.where(after, 0.0, j)
        return out[0], out[1], out[2], out[3]


def brake_profile(s: ArrayLike, v: ArrayLike, a: ArrayLike, limits: Any, target: ArrayLike | None = None) -> Brake:
    """Jerk-limited braking of both carts from ``(σ, σ̇, σ̈)`` (each shape (2,)) to rest (ruckig, see above).

    ``target`` (shape (2,), optional): stop exactly there (ruckig's position interface) instead of where the
    time-optimal stop ends (velocity interface).

    Raises
    ------
    PlanningError
        ruckig fails or needs a pre-brake (the state violates the limits).
    """
    from ruckig import ControlInterface, InputParameter, Result, Ruckig, Synchronization
    from ruckig import Trajectory as RTrajectory

    s0, v0, a0 = (np.asarray(x, dtype=float) for x in (s, v, a))
    if np.all(np.abs(v0) <= _REST) and np.all(np.abs(a0) <= _REST):
        z = (np.zeros(0), np.zeros(0))
        return Brake(z, z, z, z, z, 0.0, s0.copy(), s0.copy(), True, last=(0.0, 0.0))
    otg, inp, tr = Ruckig(2), InputParameter(2), RTrajectory(2)
    if target is None:
        inp.control_interface = ControlInterface.Velocity
    else:
        inp.target_position = np.asarray(target, dtype=float).tolist()
    collinear = abs(v0[0] * a0[1] - v0[1] * a0[0]) <= 1e-12 * max(1.0, float(np.abs(v0).max() * np.abs(a0).max()))
    inp.synchronization = Synchronization.Phase if collinear else Synchronization.Time
    inp.current_position = s0.tolist()
    inp.current_velocity = v0.tolist()
    inp.current_acceleration = a0.tolist()
    inp.target_velocity = [0.0, 0.0]
    inp.target_acceleration = [0.0, 0.0]
    # the limits, or the current state's own value when the verified motion sits on the limit (within the
    # gate's tolerance): ruckig would otherwise add a pre-brake
    safety = 1.0 - 1e-9
    inp.max_velocity = np.maximum(limits.v * safety, np.abs(v0) * (1 + 1e-12)).tolist()
    inp.max_acceleration = np.maximum(limits.a * safety, np.abs(a0) * (1 + 1e-12)).tolist()
    inp.max_jerk = (limits.j * safety).tolist()
    res = otg.calculate(inp, tr)
    if res not in (Result.Working, Result.Finished):
        raise PlanningError(f"ruckig failed to brake from v = {v0.tolist()}, a = {a0.tolist()}: {res}")
    t0s, ps, vs, as_, js, lasts, stop = [], [], [], [], [], [], []
    for r in (0, 1):
        prof = tr.profiles[0][r]
        if prof.brake.duration > 0 or prof.accel.duration > 0:
            raise PlanningError(f"ruckig needed a pre-brake for robot {'AB'[r]} (state beyond the limits)")
        tp = np.asarray(prof.t, dtype=float)
        keep = tp > 0
        starts = np.concatenate([[0.0], np.cumsum(tp)[:-1]])
        t0s.append(starts[keep])
        ps.append(np.asarray(prof.p[:7], dtype=float)[keep])
        vs.append(np.asarray(prof.v[:7], dtype=float)[keep])
        as_.append(np.asarray(prof.a[:7], dtype=float)[keep])
        js.append(np.asarray(prof.j, dtype=float)[keep])
        lasts.append(float(tp[keep][-1]) if keep.any() else 0.0)
        stop.append(float(prof.p[7]))
    return Brake(
        (t0s[0], t0s[1]),
        (ps[0], ps[1]),
        (vs[0], vs[1]),
        (as_[0], as_[1]),
        (js[0], js[1]),
        float(tr.duration),
        s0.copy(),
        np.array(stop),
        collinear,
        last=(lasts[0], lasts[1]),
    )


def _validate_at_time(at_time: float, trajectory: Trajectory) -> float:
    """``at_time`` as seconds in ``[0, makespan]`` (InvalidInputError otherwise)."""
    try:
        at = float(at_time)
    except (TypeError, ValueError, OverflowError):
        raise InvalidInputError(f"at_time is {at_time!r}, expected a number of seconds") from None
    if not math.isfinite(at) or at < 0.0 or at > trajectory.makespan + 1e-12:
        raise InvalidInputError(f"at_time is {at!r} s, expected a time in [0, {trajectory.makespan:g}] s")
    return at


class _Splice(NamedTuple):
    """Per cart: the combined route through the brake and the new motion, the orientation (+1 or -1) of the old
    route coordinate and of the new plan's within it, and the corners' combined route coordinates."""

    routes: tuple[Route, Route]
    brake_sign: FloatArray
    new_sign: FloatArray
    corners: tuple[FloatArray, FloatArray]


def _spliced_sampler(
    brake: Brake, new: Trajectory, s0: FloatArray, splice: _Splice
) -> Callable[[ArrayLike], tuple[FloatArray, FloatArray, FloatArray, FloatArray]]:
    """``σ, σ̇, σ̈, σ⃛`` of the spliced motion in the combined route coordinates: the brake, then the new motion."""
    sig_rest = np.array([splice.corners[r][1] for r in (0, 1)])
    bsign, nsign = splice.brake_sign, splice.new_sign

    def sampler(t: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        tt = np.asarray(t, dtype=float)
        bs, bv, ba, bj = brake.sample(tt)
        ns, nv, na, nj = new.sampler(tt - brake.duration)
        first = (tt < brake.duration)[..., None]
        s = np.where(first, bsign * (bs - s0), sig_rest + nsign * ns)
        v = np.where(first, bsign * bv, nsign * nv)
        a = np.where(first, bsign * ba, nsign * na)
        j = np.where(first, bsign * bj, nsign * nj)
        return s, v, a, j

    return sampler
