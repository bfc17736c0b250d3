"""The acceleration a motion is timed with, chosen per query: the fastest verified motion over a few caps.

A trajectory declares the limits it was timed with (:attr:`trajopt.result.Trajectory.limits_used`, each at most
the one asked for); the gate checks its rows against them and bounds the motion between rows with them, so a
lower acceleration cap is a valid answer to the limits asked for. The plan keeps the between-rows margin of the
cap (:func:`trajopt.verify.gate.separation_margin`, about ``amax·Δt²/4`` per robot beyond the clearance). The motion
time as a function of the cap is least at an interior optimum: below it a higher cap shortens the starts and
stops (about ``vmax/amax`` each), above it the wider margin lengthens the path more than the acceleration saves
(measured on the Y junction: about ``2·vmax·rate``). :func:`faster_caps` evaluates, besides the cap of
:attr:`~trajopt.generator.TrajectoryGenerator.motion_limits`:

- the **reached cap** (layouts, blended motions): each robot's largest ``|a|`` of the first motion's rows plus
  ``jmax·Δt/2`` (the most its jerk adds between rows), when that lowers the margin;
- the **grid**: the caps ``2^(k/2)`` m/s² (a fixed grid, the same for every query and every limit asked for) below
  the motion limits' ``amax``, in descending order until :data:`PATIENCE` caps in a row are not faster, when a
  robot's ``amax`` is above
  :data:`SEARCH_FROM` ``· vmax · rate`` (below it the margin, ``amax·Δt²/4``, is a small fraction of the distance
  a start covers in a row, and the acceleration's saving dominates), then :data:`REFINE_STEPS` golden-section
  steps (in ``log cap``) between the neighbours of the fastest cap found.

Each candidate is planned for its margin (layouts) and timed with its cap; the candidates are compared by their
motion times before the rows are sampled (a probing generator raises :class:`MotionTime` there), and the fastest
one below the first motion's time is made, verified by the gate and returned if it passes optimised (else the
next one). Straight motions (a lower cap times the same line slower) and motions with footprints (the
plane's margin is that of the limits asked for) take neither. Because the grid does not depend on the limits asked
for, a looser ``amax`` evaluates the same grid caps as a tighter one (and more); the refinement brings the
chosen cap near the optimum of its bracket, so a tighter ``amax`` between grid points is rarely faster (measured
in docs/reliability.md, "the makespan when a limit is loosened").
"""

from __future__ import annotations

import copy
import time
from dataclasses import replace
from typing import Any

import numpy as np

from mpa.errors import MPAError
from mpa.planners.graph import GraphPlan
from mpa.plans import Plan
from trajopt.path.planning import GraphPlanner
from trajopt.result import Source, Trajectory

__all__ = [
    "GRID_RATIO",
    "MAX_GRID_STEPS",
    "PATIENCE",
    "REFINE_STEPS",
    "SEARCH_FROM",
    "MotionTime",
    "faster_caps",
    "grid_caps_below",
]

#: Ratio of consecutive caps of the grid ``2^(k/2)`` m/s².
GRID_RATIO = float(np.sqrt(2.0))
#: The grid is searched when a robot's ``amax`` (of the motion limits) exceeds ``SEARCH_FROM · vmax · rate``.
SEARCH_FROM = 0.5
#: At most this many grid caps are evaluated per query (the descent stops earlier at the first slower motion).
MAX_GRID_STEPS = 12
#: The descent over the grid stops after this many caps in a row that are not faster (the plan's route may change
#: with the margin, so the motion time is not unimodal in the cap: one slower cap may hide faster ones below).
PATIENCE = 2
#: Golden-section steps between the neighbours of the fastest grid cap.
REFINE_STEPS = 4
#: The golden section's inner fraction, ``(3 − √5)/2``.
GOLDEN = (3.0 - np.sqrt(5.0)) / 2.0


def grid_caps_below(top: float) -> list[float]:
    """The grid caps ``2^(k/2)`` (m/s²) strictly below ``top``, descending (at most :data:`MAX_GRID_STEPS`).

    Parameters
    ----------
    top : float
        The highest acceleration (m/s²) of the motion limits.

    Returns
    -------
    list of float
    """
    if not np.isfinite(top) or top <= 0.0:
        return []
    k = int(np.ceil(2.0 * np.log2(top)))
    while 2.0 ** (k / 2.0) >= top:
        k -= 1
    return [2.0 ** ((k - i) / 2.0) for i in range(MAX_GRID_STEPS)]


class MotionTime(BaseException):  # a signal, not an error: no `except Exception` may swallow it
    """Raised by a probing generator where it would sample and verify a motion: the motion's time and whether it
    is the optimised motion (not the re-timed plan)."""

    def __init__(self, duration: float, optimized: bool) -> None:
        super().__init__(duration, optimized)
        self.duration = float(duration)
        self.optimized = optimized


def _trial(gen: Any, plan: Plan | GraphPlan, cap: np.ndarray) -> tuple[Any, Plan | GraphPlan]:
    """A copy of ``gen`` with accelerations capped at ``cap`` (m/s², shape (2,)) and its plan of the query (a
    layout's plan is made for the cap's margin). Raises what the planner raises."""
    trial = copy.copy(gen)
    trial._cap = (float(cap[0]), float(cap[1]))
    if isinstance(plan, GraphPlan) and isinstance(gen.planner, GraphPlanner):
        trial.planner = replace(gen.planner, margin=trial.separation_margin())
        plan = trial.planner.plan(plan.start, plan.goal)
    return trial, plan


def _predicted(gen: Any, plan: Plan | GraphPlan, cap: np.ndarray) -> float:
    """The optimised motion's time (s) with accelerations capped at ``cap``, before its rows are sampled and
    verified; ``inf`` when the pipeline does not reach an optimised motion."""
    try:
        trial, plan = _trial(gen, plan, cap)
        trial._probe = True
        trial._generate(plan, None)
    except MotionTime as probe:
        return probe.duration if probe.optimized else np.inf
    except MPAError:
        return np.inf
    return np.inf  # pragma: no cover - a probing generator always raises


def _capped(gen: Any, plan: Plan | GraphPlan, cap: np.ndarray, t0: float) -> Trajectory | None:
    """The verified motion of ``plan`` timed with accelerations capped at ``cap`` (m/s², shape (2,)), planned for
    the margin of the cap on a layout; ``None`` when none is verified optimised."""
    try:
        trial, plan = _trial(gen, plan, cap)
        out: Trajectory = trial._generate(plan, {"plan": time.perf_counter() - t0})
    except MPAError:  # no motion or none verified for this cap: the others stand
        return None
    return out if out.source is Source.OPTIMIZED else None


def faster_caps(gen: Any, plan: Plan | GraphPlan, first: Trajectory) -> Trajectory:
    """The fastest verified motion of ``plan`` over the reached cap and the grid caps (see the module docstring).

    The caps are compared by their optimised motions' times before sampling (:class:`MotionTime`); the fastest
    one below ``first``'s time is then made and verified, and the next one tried if it fails the gate.

    Parameters
    ----------
    gen : TrajectoryGenerator
        The generator ``first`` was made by (no cap of its own).
    plan : Plan or GraphPlan
        The plan ``first`` was made from (by ``gen``'s planner).
    first : Trajectory
        The verified motion of ``plan`` timed with ``gen.motion_limits``.

    Returns
    -------
    Trajectory
        ``first`` or a faster motion; ``solver_stats["reached_pass"]`` (the reached cap won: the caps in m/s², the
        margin in m, ``first``'s motion time in s) or ``solver_stats["cap_search"]`` (a grid cap won: the caps, the
        margin, ``first``'s motion time, and the ``[cap, motion time]`` pairs evaluated, ``inf`` for none).
    """
    if (
        gen.footprint is not None
        or gen._cap is not None
        or gen._probe
        or gen._gate_asked
        or first.source is not Source.OPTIMIZED
        or first.solver_stats.get("path") not in ("blend", "hard", "switch")
    ):
        return first
    t0 = time.perf_counter()
    limits = gen.motion_limits
    a = np.asarray(limits.a, dtype=float)
    cands: list[tuple[float, str, np.ndarray]] = []  # (predicted motion time, kind, cap)
    if first.solver_stats.get("path") == "blend" and isinstance(plan, GraphPlan):
        reached = np.minimum(a, np.max(np.abs(first.a), axis=0) + np.asarray(limits.j, dtype=float) / (2.0 * gen.rate))
        if np.any(reached < a):
            cands.append((_predicted(gen, plan, reached), "reached_pass", reached))
    tried: list[list[float]] = []
    v = np.asarray(limits.v, dtype=float)
    if np.any(a > SEARCH_FROM * v * gen.rate):
        top = float(np.max(a))
        points = [(top, first.motion_time)]  # descending caps and their motion times
        worse = 0  # grid caps in a row that were not faster than the fastest before them
        for x in grid_caps_below(top):
            t_x = _predicted(gen, plan, np.minimum(a, x))
            tried.append([x, t_x])
            worse = worse + 1 if t_x >= min(t for _, t in points) else 0
            points.append((x, t_x))
            if worse >= PATIENCE:
                break
        tried += _refine(gen, plan, a, points)
        cands += [(t, "cap_search", np.minimum(a, x)) for x, t in tried]
    for t_c, kind, cap in sorted(cands, key=lambda c: c[0]):
        if not t_c < first.motion_time:
            break
        best = _capped(gen, plan, cap, t0)
        if best is None or best.motion_time > first.motion_time:
            continue
        best.timings["total"] = best.timings.get("total", 0.0) + first.timings.get("total", 0.0)
        info: dict[str, Any] = {
            "amax": [float(x) for x in best.limits_used.a],
            "margin": _margin(gen, cap),
            "first_motion_time": first.motion_time,
        }
        if kind == "cap_search":
            info["tried"] = tried
        best.solver_stats[kind] = info
        return best
    return first


def _refine(gen: Any, plan: Plan | GraphPlan, a: np.ndarray, points: list[tuple[float, float]]) -> list[list[float]]:
    """Golden-section steps (in ``log cap``, :data:`REFINE_STEPS` of them) between the neighbours of the fastest
    cap of ``points`` (descending caps and their motion times); the ``[cap, motion time]`` pairs evaluated."""
    caps = [x for x, _ in points]
    times = [t for _, t in points]
    i = int(np.argmin(times))
    out: list[list[float]] = []
    if len(points) < 2 or not np.isfinite(times[i]):
        return out
    hi = np.log(caps[max(i - 1, 0)])
    lo = np.log(caps[min(i + 1, len(caps) - 1)])
    mid, t_mid = np.log(caps[i]), times[i]
    for _ in range(REFINE_STEPS):
        if hi - mid >= mid - lo:  # probe the wider side
            x = mid + GOLDEN * (hi - mid)
        else:
            x = mid - GOLDEN * (mid - lo)
        if not (lo < x < hi) or hi - lo < 1e-6:
            break
        t_x = _predicted(gen, plan, np.minimum(a, np.exp(x)))
        out.append([float(np.exp(x)), t_x])
        if t_x < t_mid:
            lo, hi = (mid, hi) if x > mid else (lo, mid)
            mid, t_mid = x, t_x
        else:
            lo, hi = (lo, x) if x > mid else (x, hi)
    return out


def _margin(gen: Any, cap: np.ndarray) -> float:
    """The between-rows margin (m) a plan keeps for accelerations capped at ``cap`` (m/s², shape (2,))."""
    trial = copy.copy(gen)
    trial._cap = (float(cap[0]), float(cap[1]))
    return float(trial.separation_margin())
