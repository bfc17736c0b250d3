"""Trajectories that tolerate a given delay of either cart: :func:`generate_with_delay_tolerance`.

:meth:`TrajectoryGenerator.generate(start, goal, delay_tolerance=T) <trajopt.generator.TrajectoryGenerator.generate>`
(and ``mpa trajectory --delay-tolerance T``) asks for a verified trajectory whose delay tolerance
(:func:`trajopt.analysis.margins.margins`: how late either cart may run, its whole motion shifted in time, with the
separation still ``>= D``) is at least ``T`` seconds.

Mechanism
    1. **The ordinary trajectory** (clearance ``D``); if its delay tolerance is ``>= T``, it is returned.
    2. **A larger effective clearance** ``D' > D`` for the planner and the optimiser: the motion then keeps
       ``D'`` at every instant, and delaying a cart by ``δ`` moves it by at most ``vmax·δ`` along its route, so
       its separation stays ``>= D' − vmax·δ`` (triangle inequality): the delay tolerance is at least
       ``(D' − D)/max(vmax)``. ``D'`` is tried at ``D + max(vmax)·T·f`` for ``f`` in :data:`CLEARANCE_STEPS`
       (``f = 1`` guarantees ``T`` by this bound whenever the query is feasible with ``D'``), capped below the
       start's and goal's own separations (the carts rest there; the planner rejects a start closer than its
       clearance). A smaller ``D'`` often suffices (the bound is loose), and it costs less time.
    3. **Slowing down**: the best candidate so far (largest tolerance ``τ_b > 0``) re-generated with the limits
       scaled to ``vmax/k, amax/k², jmax/k³`` (the same path ``k`` times slower, so its delay tolerance scales by
       about ``k``), ``k = 1.05·T/τ_b`` if ``k <=`` :data:`MAX_SLOWDOWN`.

    Every candidate is an ordinary verified trajectory (gate at ``D'``, which implies ``D``; limits at most the
    caller's). It is reported with the caller's clearance ``D`` and limits, re-verified at ``D``, and its
    margins are measured exactly (:func:`trajopt.analysis.margins.margins`) on that final object; the first candidate
    with ``delay_tolerance >= T`` is returned, with ``solver_stats["delay_tolerance"]`` recording the request,
    the value reached, the effective clearance, the slowdown and every candidate tried. If none reaches ``T``,
    :class:`~mpa.errors.NoMotionError` states the best value found.

On a layout (:class:`mpa.GraphTrack`) the same stages run with the complete graph planner (its objective kept)
and the exact graph distance; start and goal are positions.

Cost: one margins computation per candidate (0.4–2 s each), at most 5 candidates.
"""

from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from mpa._deprecation import deprecated_alias
from mpa.errors import InvalidInputError, MPAError, NoMotionError, nonnegative_number
from mpa.graph_track import GraphTrack
from mpa.tracks import Track
from trajopt.export import Trajectory
from trajopt.path.planview import plan_view
from trajopt.timing import Limits
from trajopt.verify.gate import separation_margin

if TYPE_CHECKING:
    from trajopt.generator import TrajectoryGenerator

__all__ = [
    "CLEARANCE_STEPS",
    "MAX_SLOWDOWN",
    "generate_with_delay_tolerance",
    "rest_separation",
    "validate_delay_tolerance",
]

#: Fractions f of ``max(vmax)·T`` added to the clearance, in order (f = 1 guarantees T when feasible).
CLEARANCE_STEPS = (0.25, 0.5, 1.0)
#: Largest slowdown factor tried (stage 3).
MAX_SLOWDOWN = 4.0


def validate_delay_tolerance(value: Any) -> float:
    """A requested delay tolerance: a finite number of seconds >= 0.

    Raises
    ------
    InvalidInputError
    """
    return nonnegative_number(value, "delay tolerance", "seconds")


#: Deprecated name of :func:`validate_delay_tolerance` (warns).
check_delay_tolerance = deprecated_alias(validate_delay_tolerance, "check_delay_tolerance")


def _as_caller(traj: Trajectory, gen: TrajectoryGenerator) -> Trajectory:
    """``traj`` (made with a larger clearance or lower limits) reported with ``gen``'s clearance and limits,
    re-verified at them (a gate pass at D' and lower limits implies one at D and the caller's limits)."""
    rep = plan_view(traj.plan).verify(
        traj.rows(),
        limits=gen.limits,
        clearance=gen.clearance,
        rate=traj.rate,
        limits_used=traj.limits_used,
    )
    if not rep.ok:  # pragma: no cover - implied by the gate at D' and lower limits
        raise MPAError(f"a delay-tolerance candidate fails the gate at D = {gen.clearance:g}: {rep.failures}")
    inner = traj.retimer

    def retimer(rate: float) -> Trajectory:
        assert inner is not None
        return _as_caller(inner(rate), gen.at_rate(rate))

    return dataclasses.replace(
        traj,
        clearance=gen.clearance,
        limits=gen.limits,
        verification=rep.to_dict(),
        solver_stats=dict(traj.solver_stats),
        retimer=retimer if inner is not None else None,
    )


def _feasible_cap(gen: TrajectoryGenerator, start: ArrayLike, goal: ArrayLike) -> float:
    """The largest effective clearance the carts' rest states allow (a little below their separations)."""
    d = min(rest_separation(gen.track, start), rest_separation(gen.track, goal))
    return d - 2.0 * separation_margin(gen.limits, gen.rate) - 1e-6


def rest_separation(track: Track | GraphTrack, pair: Any) -> float:
    """Graph distance (m) between the carts at ``pair``: track coordinates on a paper track, positions
    (``(edge, offset)``, ``"EDGE:OFFSET"`` or vertex names) on a layout.

    Raises
    ------
    InvalidInputError
        A position off the track.
    """
    if isinstance(track, GraphTrack):
        (ea, oa), (eb, ob) = (track.position(x, f"robot {r}") for x, r in zip(pair, "AB"))
        return float(track.geometry.distance_scalar(ea, oa, eb, ob))
    p = np.asarray(pair, dtype=float)
    return float(track.distance_scalar(float(p[0]), float(p[1])))


def generate_with_delay_tolerance(
    gen: TrajectoryGenerator, start: ArrayLike, goal: ArrayLike, tolerance: float
) -> Trajectory:
    """A verified trajectory from ``start`` to ``goal`` whose delay tolerance is at least ``tolerance`` (s).

    See the module docstring for the mechanism.

    Raises
    ------
    InvalidInputError
        Bad tolerance, start or goal.
    NoMotionError
        No motion exists, or no candidate reaches ``tolerance`` (the message states the best value found).
    """
    T = validate_delay_tolerance(tolerance)
    search = _CandidateSearch(gen, start, goal, T)
    out = search.attempt(gen.clearance, 1.0)
    if out is not None:
        return out
    cap = _feasible_cap(gen, start, goal)
    out = _try_larger_clearances(search, cap)
    if out is None:
        out = _try_slowing_down(search)
    if out is not None:
        return out
    raise _no_candidate_error(search, cap)


class _CandidateSearch:
    """The candidates tried for one request (``tried``, JSON-ready records) and the best one so far.

    ``best`` is ``(delay tolerance, trajectory, effective clearance, slowdown)``.
    """

    def __init__(self, gen: TrajectoryGenerator, start: ArrayLike, goal: ArrayLike, tolerance: float) -> None:
        self.gen, self.start, self.goal, self.T = gen, start, goal, tolerance
        self.tried: list[dict[str, Any]] = []
        self.best: tuple[float, Trajectory | None, float, float] = (-1.0, None, gen.clearance, 1.0)

    def attempt(self, clearance: float, slowdown: float) -> Trajectory | None:
        """The candidate at this effective clearance and slowdown if it reaches the tolerance, else None.

        The ordinary query (caller's clearance, no slowdown) raises when it has no motion; other candidates
        record the failure and return None.
        """
        gen, D, T = self.gen, self.gen.clearance, self.T
        limits = gen.limits
        rec: dict[str, Any] = {"clearance": clearance, "slowdown": slowdown}
        self.tried.append(rec)
        if slowdown != 1.0:
            k = slowdown
            try:
                limits = Limits(gen.limits.v / k, gen.limits.a / k**2, gen.limits.j / k**3)
            except InvalidInputError as exc:  # slowed below the supported range of the limits
                rec["failed"] = str(exc)
                return None
        try:
            if clearance == D and slowdown == 1.0:
                raw = gen.generate(self.start, self.goal)
            else:
                g2 = type(gen)(gen.track, clearance=clearance, limits=limits, rate=gen.rate, objective=gen.objective)
                raw = g2.generate(self.start, self.goal)
        except (NoMotionError, InvalidInputError) as exc:
            if clearance == D and slowdown == 1.0:
                raise
            rec["failed"] = " ".join(str(exc).split())
            return None
        traj = _as_caller(raw, gen) if (clearance != D or slowdown != 1.0) else raw
        tau = float(traj.margins().delay_tolerance)
        rec["delay_tolerance"] = None if math.isinf(tau) else tau
        rec["makespan"] = traj.makespan
        if tau > self.best[0]:
            self.best = (tau, traj, clearance, slowdown)
        if tau >= T:
            traj.solver_stats["delay_tolerance"] = {
                "requested": T,
                "achieved": None if math.isinf(tau) else tau,
                "effective_clearance": clearance,
                "slowdown": slowdown,
                "tried": self.tried,
            }
            return traj
        return None


def _try_larger_clearances(search: _CandidateSearch, cap: float) -> Trajectory | None:
    """Stage 2: effective clearances ``D + max(vmax)·T·f`` for ``f`` in :data:`CLEARANCE_STEPS`, up to ``cap``."""
    D = search.gen.clearance
    vmax = float(np.max(search.gen.limits.v))
    for f in CLEARANCE_STEPS:
        c = D + vmax * search.T * f
        if c > cap:
            if cap > D and all(r["clearance"] != cap for r in search.tried):
                return search.attempt(cap, 1.0)
            return None
        out = search.attempt(c, 1.0)
        if out is not None:
            return out
    return None


def _try_slowing_down(search: _CandidateSearch) -> Trajectory | None:
    """Stage 3: the best candidate's clearance with the limits scaled down by ``k = 1.05·T/τ_b`` (if ``k <=``
    :data:`MAX_SLOWDOWN`)."""
    tau_b, _, c_b, _ = search.best
    if 0.0 < tau_b < search.T:
        k = 1.05 * search.T / tau_b
        if k <= MAX_SLOWDOWN:
            return search.attempt(c_b, float(f"{k:.3g}"))
    return None


def _no_candidate_error(search: _CandidateSearch, cap: float) -> NoMotionError:
    """The error stating the best delay tolerance found and what was tried."""
    tried, D = search.tried, search.gen.clearance
    tau_b, _, c_b, k_b = search.best
    how = [f"clearance up to {max(r['clearance'] for r in tried):.4g} m"]
    if any(r["slowdown"] != 1.0 for r in tried):
        how.append(f"slowed down by up to {max(r['slowdown'] for r in tried):g}x")
    return NoMotionError(
        f"no trajectory found that tolerates a delay of {search.T:g} s of either cart: the best found tolerates "
        f"{max(tau_b, 0.0):.4g} s (effective clearance {c_b:.4g} m, slowdown {k_b:g}); tried "
        f"{len(tried)} candidates ({', '.join(how)}; the start and goal separations cap the clearance at "
        f"{max(cap, D):.4g} m)"
    )
