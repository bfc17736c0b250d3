"""Trajectories with a requested tracking margin: :func:`generate_with_min_margin`.

:meth:`TrajectoryGenerator.generate(start, goal, min_margin=M) <trajopt.generator.TrajectoryGenerator.generate>`
(and ``mpa trajectory --min-margin M``) asks for a verified trajectory whose tracking margin
(:func:`trajopt.analysis.margins.margins`: how far either cart may be off its setpoint along its route, at every
instant,
with the separation still ``>= D``) is at least ``M`` metres.

Mechanism
    The tracking margin is ``(d_min − D) / 2`` (``d_min`` the closest approach of the continuous motion), so a
    motion that keeps the *effective clearance* ``D' = D + 2M`` at every instant has a tracking margin of at least
    ``M``. The pipeline already guarantees that for its own clearance (plan, smoothing, the gate at the rows and
    between them), so:

    1. **The ordinary trajectory** (clearance ``D``); if its tracking margin is ``>= M``, it is returned.
    2. **The effective clearance** ``D' = D + 2M`` (plus :data:`SLACK`): a verified trajectory for ``D'``,
       reported with the caller's clearance ``D`` (re-verified at ``D``) and its margins measured on it. If its
       margin falls short by rounding, ``D'`` is raised by :data:`SLACK` steps (at most :data:`RETRIES`).
    3. **None exists** (the layout's geometry or the start's and goal's own separations forbid ``D'``): the largest
       effective clearance with a motion is found by bisection on the planner alone (:data:`BISECTIONS` steps,
       the plan's existence is monotone in the clearance), a trajectory is made there and
       :class:`~mpa.errors.NoMotionError` names its tracking margin: the largest that can be had (to the
       bisection's resolution).

With ``delay_tolerance`` as well, every candidate is made by the delay-tolerance search
(:mod:`trajopt.analysis.delay`) at the effective clearance, so both requests hold. ``solver_stats["min_margin"]``
records
the request, the margin reached and the effective clearance.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from mpa._deprecation import deprecated_alias
from mpa.errors import InvalidInputError, NoMotionError, nonnegative_number
from trajopt.analysis.delay import _as_caller, rest_separation
from trajopt.export import Trajectory

if TYPE_CHECKING:
    from trajopt.generator import TrajectoryGenerator

__all__ = ["BISECTIONS", "RETRIES", "SLACK", "generate_with_min_margin", "largest_clearance", "validate_min_margin"]

#: Added to the effective clearance ``D + 2M`` (m): the margins are measured to about 1e-9 m.
SLACK = 1e-7
#: Further raises of the effective clearance by :data:`SLACK` · 10^k when the margin falls short by rounding.
RETRIES = 3
#: Bisection steps of :func:`largest_clearance`.
BISECTIONS = 30


def validate_min_margin(value: Any) -> float:
    """A requested tracking margin: a finite number of metres >= 0.

    Raises
    ------
    InvalidInputError
    """
    return nonnegative_number(value, "min_margin", "metres")


#: Deprecated name of :func:`validate_min_margin` (warns).
check_min_margin = deprecated_alias(validate_min_margin, "check_min_margin")


def _at_clearance(gen: TrajectoryGenerator, clearance: float) -> TrajectoryGenerator:
    """``gen`` at another clearance (its own class: this module does not import the generator, which calls it)."""
    return type(gen)(
        gen.track, clearance=clearance, limits=gen.limits, rate=gen.rate, optimize=gen.optimize, objective=gen.objective
    )


def _has_plan(gen: TrajectoryGenerator, start: Any, goal: Any, clearance: float) -> bool:
    """Whether the planner finds a motion at ``clearance`` (m) whose start and goal keep it."""
    try:
        _at_clearance(gen, clearance).plan(start, goal)
    except (NoMotionError, InvalidInputError):
        return False
    return True


def largest_clearance(gen: TrajectoryGenerator, start: Any, goal: Any, upto: float) -> float:
    """The largest effective clearance in ``[gen.clearance, upto]`` (m) with a plan from ``start`` to ``goal``
    (bisection, :data:`BISECTIONS` steps; capped by the start's and goal's own separations)."""
    lo = gen.clearance
    hi = min(upto, rest_separation(gen.track, start), rest_separation(gen.track, goal))
    if hi <= lo:
        return lo
    if _has_plan(gen, start, goal, hi):
        return hi
    for _ in range(BISECTIONS):
        mid = 0.5 * (lo + hi)
        if _has_plan(gen, start, goal, mid):
            lo = mid
        else:
            hi = mid
    return lo


def _candidate(gen: TrajectoryGenerator, start: Any, goal: Any, clearance: float, delay: float | None) -> Trajectory:
    """A verified trajectory for the effective ``clearance``, reported with ``gen``'s clearance."""
    raw = _at_clearance(gen, clearance).generate(start, goal, delay_tolerance=delay)
    out = _as_caller(raw, gen) if clearance != gen.clearance else raw
    if "delay_tolerance" in raw.solver_stats:
        out.solver_stats["delay_tolerance"] = raw.solver_stats["delay_tolerance"]
    return out


def generate_with_min_margin(
    gen: TrajectoryGenerator, start: Any, goal: Any, min_margin: float, delay_tolerance: float | None = None
) -> Trajectory:
    """A verified trajectory from ``start`` to ``goal`` whose tracking margin is at least ``min_margin`` (m).

    See the module docstring for the mechanism.

    Raises
    ------
    InvalidInputError
        Bad margin, start or goal.
    NoMotionError
        No motion exists, or none keeps ``min_margin`` (the message names the largest tracking margin that can
        be had).
    """
    M = validate_min_margin(min_margin)
    D = gen.clearance
    traj = _candidate(gen, start, goal, D, delay_tolerance)
    if traj.margins().tracking_margin >= M:
        return _record(traj, M, D)
    target = D + 2.0 * M + SLACK
    for k in range(RETRIES + 1):
        c = target + (SLACK * 10.0**k if k else 0.0)
        try:
            traj = _candidate(gen, start, goal, c, delay_tolerance)
        except (NoMotionError, InvalidInputError):
            break
        if traj.margins().tracking_margin >= M:
            return _record(traj, M, c)
    raise _no_margin_error(gen, start, goal, M, target, delay_tolerance)


def _record(traj: Trajectory, requested: float, clearance: float) -> Trajectory:
    traj.solver_stats["min_margin"] = {
        "requested": requested,
        "achieved": float(traj.margins().tracking_margin),
        "effective_clearance": clearance,
    }
    return traj


def _no_margin_error(
    gen: TrajectoryGenerator, start: Any, goal: Any, M: float, target: float, delay: float | None
) -> NoMotionError:
    """The error naming the largest tracking margin that can be had (a trajectory made at the largest clearance)."""
    c = largest_clearance(gen, start, goal, target)
    best = 0.0
    for shrink in (0.0, 1e-6, 1e-4, 1e-2):  # a plan right at the limit may not pass the gate at this rate
        cc = max(gen.clearance, c - shrink * max(1.0, c))
        try:
            best = float(_candidate(gen, start, goal, cc, delay).margins().tracking_margin)
            break
        except (NoMotionError, InvalidInputError):
            continue
    return NoMotionError(
        f"no motion keeps a tracking margin of {M:g} m (an effective clearance of {target:.6g} m): the largest "
        f"tracking margin that can be had is {best:.6g} m (effective clearance up to {c:.6g} m: the track's "
        "geometry and the start's and goal's separations allow no more)"
    )
