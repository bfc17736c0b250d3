"""Measuring the stability of the whole pipeline: seeded perturbation pairs inside a domain and trajectory gaps.

A *perturbation pair* is a query ``(start, goal)`` and the query moved by ``δ`` (Euclidean norm of the move of the
four coordinates, metres) in a random direction, both valid and in the same domain of continuity. The *gap* of two
trajectories is the sup over the normalised time ``τ ∈ [0, 1]`` of the larger robot's graph distance between
their positions at ``τ·T`` (each at its own motion time ``T``); the makespan gap is ``|T₁ − T₂|``. A pipeline that
is continuous in the query has gaps that shrink with ``δ`` (``gap/δ`` bounded).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from mpa.errors import MPAError
from mpa.planners import Planner
from mpa.tracks import Interval
from trajopt.export import Trajectory

__all__ = ["PerturbationPairs", "perturbation_pairs", "route_coordinate_gap", "trajectory_gap"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class PerturbationPairs:
    """Queries and their perturbed twins, all in one domain.

    Attributes
    ----------
    starts, goals : ndarray, shape (N, 2)
        The queries (track coordinates).
    directions : ndarray, shape (N, 4)
        Unit directions of the perturbation of ``(start, goal)``.
    domain : int
    """

    starts: FloatArray
    goals: FloatArray
    directions: FloatArray
    domain: int

    def perturbed(self, delta: float) -> tuple[FloatArray, FloatArray]:
        """Start and goal moved by ``delta`` (metres) along :attr:`directions`. Shapes (N, 2)."""
        return self.starts + delta * self.directions[:, :2], self.goals + delta * self.directions[:, 2:]


def _inside(planner: Planner, s: FloatArray, g: FloatArray, domain: int) -> bool:
    tr = planner.track
    hi = tr.total_length
    for p in (s, g):
        if np.any(p < 0) or np.any(p > hi) or (not isinstance(tr, Interval) and np.any(p >= hi)):
            return False
        if float(tr.distance(p[0], p[1])) < planner.clearance:
            return False
    try:
        return planner.plan(s, g).domain == domain
    except MPAError:
        return False


def perturbation_pairs(
    planner: Planner,
    domain: int,
    n: int,
    rng: np.random.Generator,
    max_delta: float = 1e-3,
    margin: float = 1e-6,
    max_tries: int = 200_000,
) -> PerturbationPairs:
    """``n`` seeded queries of ``domain`` whose moves by every ``δ ≤ max_delta`` stay valid and in the domain.

    The move is checked at ``max_delta`` and at ``max_delta·1e-4`` (a domain boundary between them is rare);
    queries whose robots are closer than ``clearance + margin + 2·max_delta`` at the start or goal are skipped.

    Raises
    ------
    MPAError
        If fewer than ``n`` queries were found within ``max_tries`` draws.
    """
    tr = planner.track
    hi = np.nextafter(tr.total_length, 0.0)
    s_l: list[FloatArray] = []
    g_l: list[FloatArray] = []
    d_l: list[FloatArray] = []
    tries = 0
    need = planner.clearance + margin + 2 * max_delta
    while len(s_l) < n:
        tries += 1
        if tries > max_tries:
            raise MPAError(f"found only {len(s_l)} of {n} pairs in domain {domain} after {max_tries} draws")
        s, g = rng.uniform(0.0, hi, 2), rng.uniform(0.0, hi, 2)
        if isinstance(tr, Interval) and np.sign(s[1] - s[0]) != np.sign(g[1] - g[0]):
            g = g[::-1]
        if float(tr.distance(s[0], s[1])) < need or float(tr.distance(g[0], g[1])) < need:
            continue
        try:
            if planner.plan(s, g).domain != domain:
                continue
        except MPAError:
            continue
        d = rng.normal(size=4)
        d /= np.linalg.norm(d)
        if not all(_inside(planner, s + f * d[:2], g + f * d[2:], domain) for f in (max_delta, max_delta * 1e-4)):
            continue
        s_l.append(s)
        g_l.append(g)
        d_l.append(d)
    return PerturbationPairs(np.array(s_l), np.array(g_l), np.array(d_l), domain)


def trajectory_gap(a: Trajectory, b: Trajectory, samples: int = 1001) -> tuple[float, float]:
    """Sup over normalised time of the larger robot's graph distance, and the motion-time gap (m, s)."""
    tau = np.linspace(0.0, 1.0, samples)
    pos = []
    for tr in (a, b):
        s = tr.sampler(tau * tr.motion_time)[0] if tr.motion_time > 0 else np.tile(tr.s[0], (samples, 1))
        routes = tr.plan.routes  # type: ignore[union-attr]  # paper plans (the stability measure)
        pos.append(np.stack([routes[0].position(s[:, 0]), routes[1].position(s[:, 1])], axis=1))
    track: Any = a.plan.track
    gap = max(float(np.max(track.distance(pos[0][:, r], pos[1][:, r]))) for r in (0, 1))
    return gap, abs(a.motion_time - b.motion_time)


def route_coordinate_gap(a: Trajectory, b: Trajectory, samples: int = 1001) -> tuple[float, float]:
    """Sup over normalised time of the change of the exported route coordinates and of their speeds.

    The exported ``*_s`` and ``*_v`` columns (CSV, ROS positions, PVT rows) of two trajectories compared at the same
    normalised time ``τ·T`` (each at its own motion time ``T``), the larger robot's change: ``(m, m/s)``. Unlike
    :func:`trajectory_gap` (positions on the track) it also sees a flip of a route's orientation, which moves no
    cart but the columns a controller is fed.
    """
    tau = np.linspace(0.0, 1.0, samples)
    cols = []
    for tr in (a, b):
        if tr.motion_time > 0:
            s, v = tr.sampler(tau * tr.motion_time)[:2]
        else:
            s, v = np.tile(tr.s[0], (samples, 1)), np.zeros((samples, 2))
        cols.append((np.asarray(s, dtype=float), np.asarray(v, dtype=float)))
    ds = float(np.max(np.abs(cols[0][0] - cols[1][0])))
    dv = float(np.max(np.abs(cols[0][1] - cols[1][1])))
    return ds, dv
