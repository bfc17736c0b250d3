"""Skeletons: the 1-dimensional deformation retracts of the configuration spaces (paper §5.2, §6.1).

Conventions: docs/conventions.md, "The lollipop skeleton".

- Circle: the *antipodal circle* ``A = {(a, b) : b = a + c/2 mod c}``, a graph with two vertices
  (B at 0 and B at h) and two edges ``Aa`` (B's angle in [0, h]) and ``Ab`` (in [h, c]); b₁ = 1.
- Lollipop: the set of *generalized antipodal* states ``S = {(a, b) : d(a, b) = h}``, the chain
  ``I1 — S1 — S2 — S3 — I2`` with vertices e1, v1, v2, v3, v4, e2 (b₁ = 3, computed from the graph).
  Each circle ``S_j`` has two arcs, ``S_ja`` (circle parameter φ in [0, h]) and ``S_jb`` (φ in [h, c]),
  oriented counter-clockwise: φ increases when the robot on the loop moves ccw. The parameter is
  B's loop angle on S1, A's loop angle on S2 and S3.
- Interval: one point per component (the robots at the two ends), b₀ = 2, b₁ = 0.

For a lollipop with ``ℓ < h`` the set ``{d = h}`` is not a retract: the skeleton is then defined
through the homeomorphism ``ψ`` that shrinks the loop to circumference ``2ℓ`` (stick unchanged), i.e. in the
*model lollipop* ``(ℓ, 2ℓ)``; all skeleton coordinates (and arc lengths) are model coordinates.
Shrinking the loop never increases a distance, so plans keep ``d ≥ min(d_start, d_goal, ℓ)``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa._arrays import FloatArray
from mpa.errors import InvalidInputError, PlanningError
from mpa.graph import Edge, MetricGraph
from mpa.routes import RobotMove
from mpa.tracks import Circle, Interval, Lollipop, Track

__all__ = [
    "CircleSkeleton",
    "IntervalSkeleton",
    "LollipopSkeleton",
    "Skeleton",
    "SkeletonPoint",
    "lollipop_point_index",
    "skeleton_of",
]

#: Tolerance (model metres) for snapping skeleton points to vertices.
VERTEX_TOL = 1e-9


@dataclass(frozen=True)
class SkeletonPoint:
    """A point of a skeleton graph: edge name and arc length ``t`` from the edge's tail (model metres)."""

    edge: str
    t: float


@dataclass(frozen=True)
class Skeleton:
    """Base class: a skeleton graph inside the configuration space of a track."""

    track: Track
    graph: MetricGraph = field(init=False)

    @property
    def betti(self) -> tuple[int, int]:
        """``(b0, b1)`` computed from the graph."""
        return self.graph.betti()

    def vertex_at(self, pt: SkeletonPoint) -> str | None:
        """The vertex ``pt`` sits on, or None."""
        e = self.graph.edge(pt.edge)
        if pt.t <= VERTEX_TOL:
            return str(e.tail)
        if pt.t >= e.length - VERTEX_TOL:
            return str(e.head)
        return None


# ---------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class IntervalSkeleton(Skeleton):
    """Two points: ``A<B`` = (0, ℓ) and ``B<A`` = (ℓ, 0), one per component of the configuration space."""

    def __post_init__(self) -> None:
        if not isinstance(self.track, Interval):
            raise InvalidInputError(f"track is {self.track!r}, expected an Interval")
        object.__setattr__(self, "graph", MetricGraph(("A<B", "B<A"), ()))


# ---------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class CircleSkeleton(Skeleton):
    """The antipodal circle, parametrized by B's position φ = b ∈ [0, c) (A at b + h)."""

    def __post_init__(self) -> None:
        if not isinstance(self.track, Circle):
            raise InvalidInputError(f"track is {self.track!r}, expected a Circle")
        h = self.track.half
        object.__setattr__(
            self, "graph", MetricGraph(("B0", "Bh"), (Edge("Aa", "B0", "Bh", h), Edge("Ab", "Bh", "B0", h)))
        )

    @property
    def circumference(self) -> float:
        """Length of the antipodal circle measured by either robot's travel."""
        track = self.track
        assert isinstance(track, Circle), "checked in __post_init__"
        return track.loop

    def point_of_phi(self, phi: float) -> SkeletonPoint:
        """Skeleton point with circle parameter ``φ`` (B's position)."""
        c = self.circumference
        h = 0.5 * c
        phi = (phi) % c
        return SkeletonPoint("Aa", phi) if phi < h else SkeletonPoint("Ab", phi - h)

    def phi_of_point(self, pt: SkeletonPoint) -> float:
        """Circle parameter of a skeleton point."""
        return pt.t if pt.edge == "Aa" else 0.5 * self.circumference + pt.t

    def points_of_states(self, states: ArrayLike) -> tuple[NDArray[np.int64], FloatArray]:
        """Vectorized: edge index (0 = Aa, 1 = Ab) and t for states on the skeleton. Shape (N,) each."""
        st = np.atleast_2d(np.asarray(states, dtype=float))
        c = self.circumference
        phi = np.mod(st[:, 1], c)
        h = 0.5 * c
        return (phi >= h).astype(np.int64), np.where(phi >= h, phi - h, phi)

    def state(self, pt: SkeletonPoint) -> FloatArray:
        """Configuration (a, b) of a skeleton point."""
        c = self.circumference
        phi = self.phi_of_point(pt)
        return np.array([np.mod(phi + 0.5 * c, c), np.mod(phi, c)])

    def edge_moves(self, edge: str, t0: float, t1: float) -> tuple[RobotMove, RobotMove]:
        """Robot moves while the state runs along ``edge`` from ``t0`` to ``t1``: both robots move alike."""
        c = self.circumference
        phi0 = self.phi_of_point(SkeletonPoint(edge, t0))
        return (
            RobotMove("loop", ((phi0 + 0.5 * c) % (c)), t1 - t0),
            RobotMove("loop", ((phi0) % (c)), t1 - t0),
        )


# ---------------------------------------------------------------------------------------------------
#: (edge, tail, head) of the lollipop skeleton; circle arcs are oriented counter-clockwise.
_LOLLIPOP_EDGES = (
    ("I1", "e1", "v1"),
    ("S1a", "v1", "v2"),
    ("S1b", "v2", "v1"),
    ("S2a", "v2", "v3"),
    ("S2b", "v3", "v2"),
    ("S3a", "v4", "v3"),
    ("S3b", "v3", "v4"),
    ("I2", "e2", "v4"),
)
#: Left and right vertex of each circle of the chain, and their circle parameters φ.
CIRCLE_ENDS = {1: (("v1", 0.0), ("v2", 1.0)), 2: (("v2", 0.0), ("v3", 1.0)), 3: (("v3", 1.0), ("v4", 0.0))}
#: Blocks of the chain: 0 = I1, 1..3 = S1..S3, 4 = I2.
EDGE_BLOCK = {"I1": 0, "S1a": 1, "S1b": 1, "S2a": 2, "S2b": 2, "S3a": 3, "S3b": 3, "I2": 4}
VERTEX_BLOCKS = {"e1": (0,), "v1": (0, 1), "v2": (1, 2), "v3": (2, 3), "v4": (3, 4), "e2": (4,)}


@dataclass(frozen=True)
class LollipopSkeleton(Skeleton):
    """The chain I1 — S1 — S2 — S3 — I2 of generalized antipodal states (model coordinates).

    Attributes
    ----------
    model : Lollipop
        The model lollipop ``(ℓ, max(c, ...))``: the track itself when ``ℓ ≥ c/2``, else ``(ℓ, 2ℓ)``.
    kappa : float
        Loop scale ``c_model / c`` of the homeomorphism ψ (1 when ``ℓ ≥ c/2``).
    """

    model: Lollipop = field(init=False)
    kappa: float = field(init=False)

    def __post_init__(self) -> None:
        tr = self.track
        if not isinstance(tr, Lollipop):
            raise InvalidInputError(f"track is {tr!r}, expected a Lollipop")
        if tr.stick >= tr.half:
            model, kappa = tr, 1.0
        else:
            model, kappa = Lollipop(tr.stick, 2.0 * tr.stick), 2.0 * tr.stick / tr.loop
        object.__setattr__(self, "model", model)
        object.__setattr__(self, "kappa", kappa)
        h, ell = model.half, model.stick
        lengths = {"I1": ell - h, "I2": ell - h}
        edges = tuple(Edge(n, t, hd, lengths.get(n, h)) for n, t, hd in _LOLLIPOP_EDGES)
        object.__setattr__(self, "graph", MetricGraph(("e1", "v1", "v2", "v3", "v4", "e2"), edges))

    # --- the homeomorphism ψ ------------------------------------------------------------------
    def to_model(self, p: ArrayLike) -> FloatArray:
        """ψ: track coordinates of the real lollipop to the model lollipop."""
        p = np.asarray(p, dtype=float)
        ell = self.model.stick
        return np.where(p <= ell, p, ell + (p - ell) * self.kappa)

    def from_model(self, p: ArrayLike) -> FloatArray:
        """ψ⁻¹."""
        p = np.asarray(p, dtype=float)
        ell = self.model.stick
        return np.where(p <= ell, p, ell + (p - ell) / self.kappa)

    def move_from_model(self, mv: RobotMove) -> RobotMove:
        """A robot move of the model lollipop as a move of the real one."""
        if mv.edge == "loop" and self.kappa != 1.0:
            return RobotMove("loop", mv.start / self.kappa, mv.delta / self.kappa)
        return mv

    # --- coordinates --------------------------------------------------------------------------
    @property
    def half(self) -> float:
        """Model half loop h (the arc length of every circle arc)."""
        return 0.5 * self.model.loop

    def circle_phi(self, pt: SkeletonPoint) -> float:
        """Circle parameter φ ∈ [0, c) of a point on a circle arc."""
        return pt.t + (self.half if pt.edge.endswith("b") else 0.0)

    def circle_point(self, j: int, phi: float) -> SkeletonPoint:
        """Point of circle ``S_j`` with parameter ``φ`` (taken mod c)."""
        c = 2.0 * self.half
        phi = (phi) % c
        if phi >= c - VERTEX_TOL:
            phi = 0.0
        return SkeletonPoint(f"S{j}a", phi) if phi < self.half else SkeletonPoint(f"S{j}b", phi - self.half)

    def model_state(self, pt: SkeletonPoint) -> FloatArray:
        """Model configuration (a, b) of a skeleton point."""
        st = self._model_state_raw(pt)
        ell, c = self.model.stick, 2.0 * self.half
        return np.where(st >= ell + c - VERTEX_TOL, ell, st)

    def _model_state_raw(self, pt: SkeletonPoint) -> FloatArray:
        h, ell = self.half, self.model.stick
        e, t = pt.edge, pt.t
        if e == "I1":
            return np.array([t, t + h])
        if e == "I2":
            return np.array([t + h, t])
        if e.startswith("S1"):
            phi = self.circle_phi(pt)
            w = min(phi, 2 * h - phi)
            return np.array([ell - (h - w), ell + phi])
        if e.startswith("S2"):
            phi = self.circle_phi(pt)
            return np.array([ell + phi, ell + ((phi + h) % (2 * h))])
        phi = self.circle_phi(pt)  # S3
        w = min(phi, 2 * h - phi)
        return np.array([ell + phi, ell - (h - w)])

    def state(self, pt: SkeletonPoint) -> FloatArray:
        """Configuration (a, b) of a skeleton point on the real track."""
        return self.from_model(self.model_state(pt))

    def point_of_model_state(self, a: float, b: float) -> SkeletonPoint:
        """Skeleton point of a model state on S (``d = h`` up to rounding)."""
        h, ell = self.half, self.model.stick
        a_stick, b_stick = a <= ell + VERTEX_TOL, b <= ell + VERTEX_TOL
        if a_stick and b_stick:
            if b > a:
                return SkeletonPoint("I1", min(max(a, 0.0), ell - h))
            return SkeletonPoint("I2", min(max(b, 0.0), ell - h))
        if a_stick:
            return self.circle_point(1, b - ell)
        if b_stick:
            return self.circle_point(3, a - ell)
        return self.circle_point(2, a - ell)

    def points_of_model_states(self, states: ArrayLike) -> tuple[NDArray[np.int64], FloatArray]:
        """Vectorized :meth:`point_of_model_state`: edge index into ``graph.edges`` and ``t``. Shape (N,).

        One state in plain Python: :func:`lollipop_point_index`.
        """
        st = np.atleast_2d(np.asarray(states, dtype=float))
        a, b = st[:, 0], st[:, 1]
        h, ell = self.half, self.model.stick
        c = 2 * h
        a_stick, b_stick = a <= ell + VERTEX_TOL, b <= ell + VERTEX_TOL
        both = a_stick & b_stick
        b_ahead = b > a
        # both on the stick: I1 (B ahead) or I2, at the rear robot's depth
        edge_i = np.where(b_ahead, 0, 7)
        t_i = np.clip(np.where(b_ahead, a, b), 0.0, ell - h)
        # else circle S_j (j = 1: A on the stick, 3: B on the stick, 2: both on the loop) at the loop robot's φ
        a_only = a_stick & ~b_stick
        j = np.where(a_only, 1, np.where(b_stick, 3, 2))
        phi = np.mod(np.where(a_only, b, a) - ell, c)
        phi = np.where(phi >= c - VERTEX_TOL, 0.0, phi)
        is_b = phi >= h
        edge = np.where(both, edge_i, np.where(is_b, 2 * j, 2 * j - 1)).astype(np.int64)
        t = np.where(both, t_i, np.where(is_b, phi - h, phi))
        return edge, t

    def blocks_of(self, pt: SkeletonPoint) -> tuple[int, ...]:
        """Chain blocks containing the point (two for a junction vertex)."""
        v = self.vertex_at(pt)
        return VERTEX_BLOCKS[v] if v is not None else (EDGE_BLOCK[pt.edge],)

    def edge_moves(self, edge: str, t0: float, t1: float) -> tuple[RobotMove, RobotMove]:
        """Model robot moves while the state runs along ``edge`` from ``t0`` to ``t1``.

        On every edge both robots move at the same speed: I1/I2 slide along the stick, on S1 (S3) B (A) runs on
        the loop while the other robot runs along the stick, on S2 both run round the loop.
        """
        h, ell = self.half, self.model.stick
        dt = t1 - t0
        if edge == "I1":
            return RobotMove("stick", t0, dt), RobotMove("stick", t0 + h, dt)
        if edge == "I2":
            return RobotMove("stick", t0 + h, dt), RobotMove("stick", t0, dt)
        j, arc = int(edge[1]), edge[2]
        phi0 = t0 + (h if arc == "b" else 0.0)
        # on arc a the loop robot moves away from P as φ grows (w = φ); on arc b towards P (w = c − φ)
        stick_sign = 1.0 if arc == "a" else -1.0
        if j == 1:
            return RobotMove("stick", ell - h + min(phi0, 2 * h - phi0), stick_sign * dt), RobotMove(
                "loop", ((phi0) % (2 * h)), dt
            )
        if j == 3:
            return RobotMove("loop", ((phi0) % (2 * h)), dt), RobotMove(
                "stick", ell - h + min(phi0, 2 * h - phi0), stick_sign * dt
            )
        return RobotMove("loop", ((phi0) % (2 * h)), dt), RobotMove("loop", ((phi0 + h) % (2 * h)), dt)


def lollipop_point_index(h: float, ell: float, a: float, b: float) -> tuple[int, float]:
    """Edge index (into :class:`LollipopSkeleton`'s graph) and ``t`` of a model state on the skeleton.

    Scalar twin of :meth:`LollipopSkeleton.points_of_model_states` (the same cases, the same operations), in
    plain Python on floats only, so that it can also be compiled (:mod:`trajopt.verify.kernels`).

    Parameters
    ----------
    h, ell : float
        The model's half loop and stick (model metres).
    a, b : float
        Model track coordinates of A and B, on the skeleton (``d = h`` up to rounding).
    """
    c = 2 * h
    a_stick, b_stick = a <= ell + VERTEX_TOL, b <= ell + VERTEX_TOL
    if a_stick and b_stick:  # I1 (B ahead) or I2, at the rear robot's depth
        if b > a:
            return 0, min(max(a, 0.0), ell - h)
        return 7, min(max(b, 0.0), ell - h)
    # circle S_j (j = 1: A on the stick, 3: B on the stick, 2: both on the loop) at the loop robot's φ
    a_only = a_stick and not b_stick
    j = 1 if a_only else (3 if b_stick else 2)
    phi = ((b if a_only else a) - ell) % c
    if phi >= c - VERTEX_TOL:
        phi = 0.0
    if phi >= h:
        return 2 * j, phi - h
    return 2 * j - 1, phi


@lru_cache(maxsize=64)
def skeleton_of(track: Track) -> Skeleton:
    """The skeleton of the configuration space of two robots on ``track`` (cached per track)."""
    if isinstance(track, Interval):
        return IntervalSkeleton(track)
    if isinstance(track, Circle):
        return CircleSkeleton(track)
    if isinstance(track, Lollipop):
        return LollipopSkeleton(track)
    raise PlanningError(f"no skeleton for track {track!r}")
