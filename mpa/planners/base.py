"""Shared parts of the paper's planners: the rules in words, the :class:`Planner` base class and path pieces.

Every planner follows the paper's three steps: the *preliminary step* ``H(x_i, ·)`` moves the start onto the
skeleton, the *main step* moves inside the skeleton by the rule of the query's domain, the *final step* is
``H(x_f, ·)`` reversed. Domain numbering: docs/conventions.md.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from mpa.cspace import ConfigurationSpace
from mpa.errors import InvalidInputError, PlanningError
from mpa.graph import MetricGraph
from mpa.homotopy import word_from_samples
from mpa.plans import JointMove, Plan
from mpa.routes import RobotMove
from mpa.tracks import Track

__all__ = [
    "DEFAULT_NEIGHBOURHOOD",
    "FINAL",
    "PRELIM",
    "RULES",
    "Planner",
    "circle_distance",
    "circle_pieces",
    "pieces_word",
    "reverse_moves",
]

RULES = {
    ("interval", 1): "same order: straight translation of both robots",
    ("circle", 1): "B's initial and final positions are antipodal: both robots move counterclockwise until B arrives",
    ("circle", 2): "otherwise: both robots move the same way along B's shortest path until B arrives",
    ("lollipop", 1): (
        "generalized vertex position: shortest path in the skeleton, counterclockwise across every circle "
        "(same order: slide along the stick; reverse order: go round the loop)"
    ),
    ("lollipop", 2): (
        "generalized swapped states: counterclockwise in the circle S_j where start and goal (or the start or goal "
        "and the vertex where the path leaves or enters S_j) are antipodal"
    ),
    ("lollipop", 3): "all other pairs: shortest path in the skeleton, counterclockwise whenever crossing a circle",
}
PRELIM = {
    "interval": "none: the robots move straight to their goals",
    "circle": "robot A moves away from robot B until it is antipodal to B; B waits",
    "lollipop": (
        "if farther apart than half the loop, the robot nearer the free end moves towards the other, which waits; "
        "otherwise both move apart (staying on the loop if on it) until generalized antipodal"
    ),
}
FINAL = {
    "interval": "none",
    "circle": (
        "robot A moves along its shortest path to its goal; B waits (the preliminary trace of the goal, reversed)"
    ),
    "lollipop": "both robots move to their goals along the reversed preliminary trace of the goal",
}

DEFAULT_NEIGHBOURHOOD = 0.1


def reverse_moves(moves: JointMove) -> JointMove:
    """The joint move run backwards: each robot from its end back to its start."""
    a, b = moves
    return RobotMove(a.edge, a.start + a.delta, -a.delta), RobotMove(b.edge, b.start + b.delta, -b.delta)


def circle_distance(a: float, b: float, c: float) -> float:
    d = abs((a - b) % c)
    return min(d, c - d)


@dataclass(frozen=True)
class Planner:
    """Base class: a planner built once for a track and a clearance, re-used for many queries.

    Parameters
    ----------
    track : Track
    clearance : float
        Required clearance D (metres); start and goal must respect it.
    neighbourhood : float
        Size ε of the domains' neighbourhoods as a fraction of half the loop (0 < neighbourhood < 0.5).
    """

    track: Track
    clearance: float = 0.0
    neighbourhood: float = DEFAULT_NEIGHBOURHOOD
    cspace: ConfigurationSpace = field(init=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "cspace", ConfigurationSpace(self.track, self.clearance))
        object.__setattr__(self, "clearance", self.cspace.clearance)
        try:
            nb = float(self.neighbourhood)
        except (TypeError, ValueError, OverflowError):
            nb = float("nan")
        if not np.isfinite(nb) or not 0.0 < nb < 0.5:
            raise InvalidInputError(f"neighbourhood is {self.neighbourhood!r}, expected a number in (0, 0.5)")

    def plan(self, start: ArrayLike, goal: ArrayLike) -> Plan:  # pragma: no cover - abstract
        """Plan a motion from ``start`` to ``goal`` (each ``(a, b)`` in track coordinates)."""
        raise NotImplementedError

    def domain(self, start: ArrayLike, goal: ArrayLike) -> int:
        """Domain of continuity of a query (same numbering as :attr:`Plan.domain`)."""
        return self.plan(start, goal).domain


def circle_pieces(
    phi0: float, delta: float, h: float, edge_name: Callable[[int], str]
) -> list[tuple[str, float, float]]:
    """Split the run of a circle parameter from ``φ0`` by ``delta`` into pieces on the arcs [0, h] and [h, 2h].

    ``edge_name(arc)`` names the skeleton edge of arc 0 ([0, h]) and arc 1 ([h, 2h]); each piece is
    ``(edge, t_from, t_to)`` with arc lengths along that edge.
    """
    c = 2.0 * h
    out: list[tuple[str, float, float]] = []
    phi = (phi0) % c
    if phi >= c - 1e-12:
        phi = 0.0
    rem = float(delta)
    direction = 1.0 if rem > 0 else -1.0
    guard = 0
    while abs(rem) > 1e-13:
        guard += 1
        if guard > 64:
            raise PlanningError("circle run did not terminate")
        arc = 0 if phi < h else 1
        base = arc * h
        t = phi - base
        if direction > 0:
            step = min(h - t, rem)
            out.append((edge_name(arc), t, t + step))
        else:
            if t <= 1e-13:  # at the arc's tail: continue on the previous arc from its head
                arc = 1 - arc
                base = arc * h
                t = h
            step = min(t, -rem)
            out.append((edge_name(arc), t, t - step))
        phi = (base + out[-1][2]) % c
        rem -= direction * step
    return out


def pieces_word(graph: MetricGraph, pieces: Sequence[tuple[str, float, float]]) -> tuple[str, ...]:
    """The reduced skeleton word (:func:`~mpa.homotopy.word_from_samples`) of a run given as edge pieces."""
    index = {e.name: i for i, e in enumerate(graph.edges)}
    edges, ts = [], []
    for e, t0, t1 in pieces:
        edges += [index[e], index[e]]
        ts += [t0, t1]
    return word_from_samples(graph, edges, ts)
