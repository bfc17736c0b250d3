"""The result of the motion planner: a :class:`Plan` (frozen, plain numpy arrays)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa.routes import RobotMove, Route, lift_moves, lift_position
from mpa.skeleton import Skeleton
from mpa.tracks import Track

__all__ = ["JointMove", "Plan", "PlanStep", "build_plan"]

FloatArray = NDArray[np.float64]
JointMove = tuple[RobotMove, RobotMove]
STEP_NAMES = ("preliminary", "main", "final")


@dataclass(frozen=True)
class PlanStep:
    """One of the three steps of the algorithm.

    Attributes
    ----------
    name : str
        ``"preliminary"``, ``"main"`` or ``"final"``.
    description : str
        The instruction in the paper's words.
    u_start, u_end : float
        The part of the path parameter ``u ∈ [0, 1]`` the step occupies (equal if the step is empty).
    waypoints : ndarray, shape (K, 2)
        Corner states of the step (track coordinates, first = where the step starts).
    """

    name: str
    description: str
    u_start: float
    u_end: float
    waypoints: FloatArray


@dataclass(frozen=True)
class Plan:
    """A motion plan α: [0, 1] → C² for two robots, as produced by the paper's algorithm.

    Between consecutive corners every robot moves at constant speed along its route, so the path is the polyline
    ``waypoints_s`` in route coordinates, parametrized by ``u`` proportionally to the larger of the two robots'
    travel (``knots``).

    Attributes
    ----------
    track : Track
    start, goal : ndarray, shape (2,)
        Track coordinates of (A, B).
    clearance : float
        The clearance the query was checked against (metres).
    domain : int
        Domain of continuity (numbering of docs/conventions.md, "Domains of continuity").
    rule : str
        The instruction of the domain, in words.
    steps : tuple of PlanStep
        Preliminary, main and final step.
    knots : ndarray, shape (K,)
        Path parameter of every corner, from 0 to 1.
    waypoints : ndarray, shape (K, 2)
        Corner states in track coordinates.
    waypoints_s : ndarray, shape (K, 2)
        Corner states in route coordinates σ (metres along each robot's route).
    routes : tuple of Route
        Route of A and of B.
    skeleton : Skeleton
        The skeleton of the configuration space.
    skeleton_start, skeleton_goal : ndarray, shape (2,)
        ``x_i' = H₁(start)`` and ``x_f' = H₁(goal)``.
    word : tuple of str
        Reduced edge word of ``H₁∘α`` in the skeleton graph (the path's homotopy class).
    travel : ndarray, shape (2,)
        Distance travelled by A and by B (metres).
    regime : str
        ``"paper"`` (the paper's algorithm), or for a lollipop whose clearance forbids generalized antipodal
        states: ``"retreat"`` (D > h) or ``"loop"`` (ℓ < D ≤ h); see :mod:`mpa.planners`.
    length : float
        Length of the path in the max-norm of route coordinates (metres): ``u`` is proportional to it, so
        equally spaced samples are at most ``length / (n − 1)`` apart for each robot.
    """

    track: Track
    start: FloatArray
    goal: FloatArray
    clearance: float
    domain: int
    rule: str
    steps: tuple[PlanStep, ...]
    knots: FloatArray
    waypoints: FloatArray
    waypoints_s: FloatArray
    routes: tuple[Route, Route]
    skeleton: Skeleton
    skeleton_start: FloatArray
    skeleton_goal: FloatArray
    word: tuple[str, ...]
    travel: FloatArray = field(default_factory=lambda: np.zeros(2))
    length: float = 0.0
    regime: str = "paper"

    def path_s(self, u: ArrayLike) -> FloatArray:
        """Route coordinates α_σ(u) (vectorized). Shape ``u.shape + (2,)``."""
        uu: FloatArray = np.clip(np.asarray(u, dtype=float), 0.0, 1.0)
        if self.knots[-1] <= 0.0:
            return np.broadcast_to(self.waypoints_s[0], (*uu.shape, 2)).copy()
        sa = np.interp(uu, self.knots, self.waypoints_s[:, 0])
        sb = np.interp(uu, self.knots, self.waypoints_s[:, 1])
        return np.stack([sa, sb], axis=-1)

    def path(self, u: ArrayLike) -> FloatArray:
        """The path α(u) in track coordinates (vectorized). Shape ``u.shape + (2,)``.

        ``path(0)`` is the start and ``path(1)`` the goal exactly (the routes reproduce them to a few ulps; the
        ends are then set bit for bit).
        """
        uu = np.asarray(u, dtype=float)
        s = self.path_s(uu)
        out = np.stack([self.routes[0].position(s[..., 0]), self.routes[1].position(s[..., 1])], axis=-1)
        out[uu <= 0.0] = self.start
        out[uu >= 1.0] = self.goal
        return out

    def sample(self, n: int = 400) -> FloatArray:
        """α at ``n`` equally spaced values of u in [0, 1] (first = start, last = goal, exactly). Shape (n, 2)."""
        out = self.path(np.linspace(0.0, 1.0, max(int(n), 2)))
        out[0], out[-1] = self.start, self.goal
        return out

    def samples_needed(self, fraction: float = 0.01) -> int:
        """Number of equally spaced samples so that consecutive points are at most ``fraction`` of the track's
        total length apart for each robot."""
        step = fraction * self.track.total_length
        return int(np.ceil(self.length / step)) + 1

    def min_distance(self, n: int = 20001) -> float:
        """Smallest distance between the robots along the path, on ``n`` samples (metres)."""
        st = self.sample(n)
        return float(np.min(self.track.distance(st[:, 0], st[:, 1])))

    def to_dict(self, samples: int = 400) -> dict[str, object]:
        """A JSON-ready description of the plan, with the path sampled at ``samples`` equally spaced u."""
        return {
            "track": self.track.to_dict(),
            "start": self.start.tolist(),
            "goal": self.goal.tolist(),
            "clearance": self.clearance,
            "domain": self.domain,
            "regime": self.regime,
            "rule": self.rule,
            "skeleton_start": self.skeleton_start.tolist(),
            "skeleton_goal": self.skeleton_goal.tolist(),
            "word": list(self.word),
            "steps": [
                {
                    "name": s.name,
                    "description": s.description,
                    "u": [s.u_start, s.u_end],
                    "waypoints": s.waypoints.tolist(),
                }
                for s in self.steps
            ],
            "knots": self.knots.tolist(),
            "waypoints": self.waypoints.tolist(),
            "waypoints_s": self.waypoints_s.tolist(),
            "route_lengths": [self.routes[0].length, self.routes[1].length],
            "travel": self.travel.tolist(),
            "length": self.length,
            "path": self.sample(samples).tolist(),
        }


def build_plan(
    track: Track,
    start: FloatArray,
    goal: FloatArray,
    clearance: float,
    domain: int,
    rule: str,
    steps: Sequence[tuple[str, Sequence[JointMove]]],
    skeleton: Skeleton,
    skeleton_start: FloatArray,
    skeleton_goal: FloatArray,
    word: tuple[str, ...] | None,
    regime: str = "paper",
) -> Plan:
    """Assemble a :class:`Plan` from the three steps given as joint moves (real track coordinates)."""
    moves_a, moves_b, step_ranges = _moving_moves(steps)
    lifts_a = lift_moves(track, moves_a, float(start[0]))
    lifts_b = lift_moves(track, moves_b, float(start[1]))
    route_a, sig_a = Route.through(track, lifts_a)
    route_b, sig_b = Route.through(track, lifts_b)
    sa, sb = sig_a.tolist(), sig_b.tolist()
    knots_l, (trav_a, trav_b), total = _knots_and_travel(sa, sb)
    pos_l = [[lift_position(track, la), lift_position(track, lb)] for la, lb in zip(lifts_a, lifts_b)]
    pos_l[0], pos_l[-1] = [float(start[0]), float(start[1])], [float(goal[0]), float(goal[1])]
    pos = np.array(pos_l)
    ws = np.array([sa, sb]).T.copy()
    knots = np.array(knots_l)
    travel = np.array([trav_a, trav_b])
    plan_steps = []
    for (desc, _), name, (i0, i1) in zip(steps, STEP_NAMES, step_ranges):
        plan_steps.append(PlanStep(name, desc, knots_l[i0], knots_l[i1], pos[i0 : i1 + 1]))
    result = Plan(
        track=track,
        start=np.asarray(start, dtype=float),
        goal=np.asarray(goal, dtype=float),
        clearance=clearance,
        domain=domain,
        rule=rule,
        steps=tuple(plan_steps),
        knots=knots,
        waypoints=pos,
        waypoints_s=ws,
        routes=(route_a, route_b),
        skeleton=skeleton,
        skeleton_start=np.asarray(skeleton_start, dtype=float),
        skeleton_goal=np.asarray(skeleton_goal, dtype=float),
        word=() if word is None else word,
        travel=travel,
        length=float(total),
        regime=regime,
    )
    if word is None:  # read the class off the sampled path (regimes whose main step is not a skeleton path)
        from mpa.homotopy import path_word

        n = max(2001, result.samples_needed(0.0005))
        return replace(result, word=path_word(track, result.sample(n)))
    return result


def _moving_moves(
    steps: Sequence[tuple[str, Sequence[JointMove]]],
) -> tuple[list[RobotMove], list[RobotMove], list[tuple[int, int]]]:
    """Each robot's moves of all steps in order, joint moves where neither robot moves dropped, and the range of
    move indices ``[first, end)`` of every step."""
    moves_a: list[RobotMove] = []
    moves_b: list[RobotMove] = []
    step_ranges: list[tuple[int, int]] = []
    for _desc, jm in steps:
        first = len(moves_a)
        for ma, mb in jm:
            if abs(ma.delta) <= 1e-15 and abs(mb.delta) <= 1e-15:
                continue
            moves_a.append(ma)
            moves_b.append(mb)
        step_ranges.append((first, len(moves_a)))
    return moves_a, moves_b, step_ranges


def _knots_and_travel(sa: list[float], sb: list[float]) -> tuple[list[float], tuple[float, float], float]:
    """From the corners' route coordinates of A and B: the knots ``u`` of the corners (path length by the larger
    of the two moves, normalised to [0, 1]), each robot's travel and the total length (metres)."""
    cum_l = [0.0]
    trav_a = trav_b = 0.0
    for i in range(1, len(sa)):
        da, db = abs(sa[i] - sa[i - 1]), abs(sb[i] - sb[i - 1])
        trav_a += da
        trav_b += db
        cum_l.append(cum_l[-1] + (da if da > db else db))
    total = cum_l[-1]
    knots_l = [c / total for c in cum_l] if total > 0 else [0.0] * len(cum_l)
    return knots_l, (trav_a, trav_b), total
