"""Tracks: the interval, the circle and the lollipop as metric graphs.

Conventions: docs/conventions.md, "Tracks and track coordinates".

A position on a track is one float, the *track coordinate* ``p`` (metres):

========  =====================  ===============================================================
track     parameters             coordinate
========  =====================  ===============================================================
interval  ``stick`` = ℓ          ``p ∈ [0, ℓ]``
circle    ``loop`` = c           ``p ∈ [0, c)``, counter-clockwise
lollipop  ``stick`` ℓ, ``loop`` c  ``p ∈ [0, ℓ]`` on the stick from the free end (0) to the pole P (ℓ);
                                 ``p ∈ (ℓ, ℓ + c)`` on the loop, ``θ = p − ℓ`` ccw from P
========  =====================  ===============================================================

Every distance is the exact graph distance (length of the shortest path along the track),
vectorized over numpy arrays.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import TYPE_CHECKING, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa._arrays import FloatArray
from mpa.errors import InvalidInputError, positive_number
from mpa.graph import Edge, MetricGraph

if TYPE_CHECKING:
    from mpa.graph_track import GraphTrack

__all__ = ["Circle", "Interval", "Lollipop", "Track", "make_track"]

#: Positions this close to the end of a half-open coordinate range are wrapped (metres).
WRAP_TOL = 1e-12


class Track:
    """A track: a compact metric graph with a one-float coordinate (see module docstring).

    An abstract base (not an ``abc.ABC``: ``isinstance`` checks on the hot path of the planner stay cheap).
    """

    kind: str
    #: Whether the track contains a cycle (the only place where the robots can change order).
    has_loop: ClassVar[bool]
    _total_length: float

    def __post_init__(self) -> None:
        """Check the lengths the track is made of (its dataclass fields: ``stick``, ``loop``), each > 0 and finite."""
        lengths = [f.name for f in fields(self)]  # type: ignore[arg-type]
        for name in lengths:
            object.__setattr__(self, name, positive_number(getattr(self, name), f"{name} length", "metres"))
        object.__setattr__(self, "_total_length", float(sum(getattr(self, name) for name in lengths)))

    @property
    def total_length(self) -> float:
        """Total length of the track (metres): the sum of its lengths."""
        return self._total_length

    def distance(self, p: ArrayLike, q: ArrayLike) -> FloatArray:
        """Graph distance between positions ``p`` and ``q`` (broadcast, metres)."""
        raise NotImplementedError

    def normalize(self, p: ArrayLike) -> FloatArray:
        """Map coordinates on the loop into the canonical half-open range (no validation)."""
        raise NotImplementedError

    def _valid_mask(self, p: FloatArray) -> NDArray[np.bool_]:
        """Which normalized coordinates lie on the track."""
        raise NotImplementedError

    def _range_text(self) -> str:
        """Human description of the valid coordinate range."""
        raise NotImplementedError

    def embed(self, p: ArrayLike) -> FloatArray:
        """Planar embedding for plotting. Shape ``p.shape + (2,)`` (metres)."""
        raise NotImplementedError

    def as_graph(self) -> MetricGraph:
        """The track as a generic :class:`~mpa.graph.MetricGraph` (vertices, edges with lengths)."""
        raise NotImplementedError

    def to_dict(self) -> dict[str, object]:
        """Parameters as a JSON-ready dict: ``{"track": kind}`` and the lengths (``stick``, ``loop``) in metres."""
        return {"track": self.kind, **{f.name: getattr(self, f.name) for f in fields(self)}}  # type: ignore[arg-type]

    def validate(self, p: ArrayLike, name: str = "position") -> FloatArray:
        """Check that ``p`` holds finite coordinates on the track and return them normalized.

        Parameters
        ----------
        p : array_like
            Track coordinates (any shape).
        name : str
            What the coordinates are, for the error message (e.g. ``"start of robot A"``).

        Returns
        -------
        ndarray
            The normalized coordinates, same shape.

        Raises
        ------
        InvalidInputError
            If a value is not finite or lies outside the track's coordinate range.
        """
        if isinstance(p, (float, int, np.floating, np.integer)) and not isinstance(p, bool):
            v = float(p)
            lo, hi, closed = self._bounds()
            if lo <= v < hi or (closed and v == hi):
                if hi - WRAP_TOL * max(1.0, hi) <= v < hi and not closed:
                    return self.normalize(v)
                return np.asarray(v)
        try:
            arr = np.asarray(p, dtype=float)
        except (TypeError, ValueError, OverflowError):
            raise InvalidInputError(f"{name} is {p!r}, expected a number in {self._range_text()}") from None
        bad = ~np.isfinite(arr)
        if np.any(bad):
            raise InvalidInputError(
                f"{name} is {float(arr[bad].flat[0])!r}, expected a finite number in {self._range_text()}"
            )
        out = self.normalize(arr)
        ok = self._valid_mask(out)
        if not np.all(ok):
            v = float(arr[~ok].flat[0])
            raise InvalidInputError(f"{name} is {v!r}, expected a track coordinate in {self._range_text()}")
        return out

    def on_loop(self, p: ArrayLike) -> NDArray[np.bool_]:
        """Whether positions lie on the loop (the pole P of a lollipop counts as both)."""
        return np.zeros(np.shape(p), dtype=bool)

    def _bounds(self) -> tuple[float, float, bool]:
        """(low, high, high end included) of the coordinate range."""
        return 0.0, self.total_length, False

    def distance_scalar(self, p: float, q: float) -> float:
        """Graph distance of two scalar positions (pure Python twin of :meth:`distance`)."""
        return float(self.distance(p, q))

    def interpolate(self, p: ArrayLike, q: ArrayLike, f: ArrayLike) -> FloatArray:
        """Points a fraction ``f`` of the way along a shortest path from ``p`` to ``q`` (broadcast).

        Used to refine densely sampled motions: between two close samples the shortest path is the motion.
        """
        raise NotImplementedError

    def as_graph_track(self) -> GraphTrack:
        """This track as a :class:`~mpa.graph_track.GraphTrack` with edges ``stick`` and/or ``loop``.

        Interval: ``stick`` (F -> E); circle: ``loop`` (P -> P, ccw); lollipop: ``stick`` (free end F -> pole P) and
        ``loop`` (P -> P, ccw). Offsets: ``p`` on the stick, ``p - stick`` on a lollipop's loop, ``p`` on a circle.
        """
        cached = self.__dict__.get("_graph_track")
        if cached is None:  # built once per track (tracks are immutable)
            from mpa.graph_track import paper_track_as_graph

            cached = paper_track_as_graph(self)
            object.__setattr__(self, "_graph_track", cached)
        return cached

    def to_graph_position(self, p: ArrayLike) -> tuple[NDArray[np.int64], FloatArray]:
        """Track coordinates -> ``(edge index, offset)`` on :meth:`as_graph_track` (vectorized)."""
        from mpa.graph_track import paper_to_graph_position

        return paper_to_graph_position(self, p)

    def from_graph_position(self, edge: ArrayLike, offset: ArrayLike) -> FloatArray:
        """``(edge index, offset)`` on :meth:`as_graph_track` -> track coordinates (vectorized)."""
        from mpa.graph_track import paper_from_graph_position

        return paper_from_graph_position(self, edge, offset)


def _shortest_loop_step(p: FloatArray, q: FloatArray, c: float) -> FloatArray:
    """Signed shortest displacement (m) from loop coordinate ``p`` to ``q`` on a loop of circumference ``c``,
    in ``(−c/2, c/2]`` (positive: counter-clockwise)."""
    d = np.mod(q - p, c)
    return np.where(d > 0.5 * c, d - c, d)


def _snap_near_end(p: ArrayLike, end: float, to: float) -> FloatArray:
    """A copy of coordinates ``p`` with those just below ``end`` (within :data:`WRAP_TOL`, relative) set to ``to``,
    the same point of the loop."""
    out = np.asarray(p, dtype=float).copy()
    near_end = (out >= end - WRAP_TOL * max(1.0, end)) & (out < end)
    out[near_end] = to
    return out


@dataclass(frozen=True)
class Interval(Track):
    """The interval track ``[0, stick]``.

    Parameters
    ----------
    stick : float
        Length ℓ (metres, > 0).
    """

    stick: float = 1.0
    kind = "interval"
    has_loop = False

    def distance(self, p: ArrayLike, q: ArrayLike) -> FloatArray:
        return np.abs(np.asarray(q, dtype=float) - np.asarray(p, dtype=float))

    def distance_scalar(self, p: float, q: float) -> float:
        return abs(q - p)

    def _bounds(self) -> tuple[float, float, bool]:
        return 0.0, self.stick, True

    def interpolate(self, p: ArrayLike, q: ArrayLike, f: ArrayLike) -> FloatArray:
        p, q, f = (np.asarray(v, dtype=float) for v in (p, q, f))
        return p + f * (q - p)

    def normalize(self, p: ArrayLike) -> FloatArray:
        return np.asarray(p, dtype=float).copy()

    def _valid_mask(self, p: FloatArray) -> NDArray[np.bool_]:
        return (p >= 0.0) & (p <= self.stick)

    def _range_text(self) -> str:
        return f"[0, {self.stick:g}]"

    def embed(self, p: ArrayLike) -> FloatArray:
        p = np.asarray(p, dtype=float)
        return np.stack([p, np.zeros_like(p)], axis=-1)

    def as_graph(self) -> MetricGraph:
        return MetricGraph(("F", "E"), (Edge("stick", "F", "E", self.stick),))


@dataclass(frozen=True)
class Circle(Track):
    """The circle track of circumference ``loop``, coordinate ``[0, loop)`` counter-clockwise.

    Parameters
    ----------
    loop : float
        Circumference c (metres, > 0).
    """

    loop: float = 1.0
    kind = "circle"
    has_loop = True

    @property
    def half(self) -> float:
        """Half the circumference, ``h = c/2``: the antipodal distance."""
        return 0.5 * self.loop

    def distance(self, p: ArrayLike, q: ArrayLike) -> FloatArray:
        c = self.loop
        diff = np.mod(np.asarray(q, dtype=float) - np.asarray(p, dtype=float), c)
        return np.minimum(diff, c - diff)

    def distance_scalar(self, p: float, q: float) -> float:
        diff = (q - p) % self.loop
        return min(diff, self.loop - diff)

    def interpolate(self, p: ArrayLike, q: ArrayLike, f: ArrayLike) -> FloatArray:
        p, q, f = (np.asarray(v, dtype=float) for v in (p, q, f))
        c = self.loop
        return np.mod(p + f * _shortest_loop_step(p, q, c), c)

    def normalize(self, p: ArrayLike) -> FloatArray:
        return _snap_near_end(p, self.loop, 0.0)

    def _valid_mask(self, p: FloatArray) -> NDArray[np.bool_]:
        return (p >= 0.0) & (p < self.loop)

    def _range_text(self) -> str:
        return f"[0, {self.loop:g})"

    def on_loop(self, p: ArrayLike) -> NDArray[np.bool_]:
        return np.ones(np.shape(p), dtype=bool)

    def embed(self, p: ArrayLike) -> FloatArray:
        p = np.asarray(p, dtype=float)
        r = self.loop / (2 * np.pi)
        ang = 2 * np.pi * p / self.loop
        return np.stack([r * np.cos(ang), r * np.sin(ang)], axis=-1)

    def as_graph(self) -> MetricGraph:
        return MetricGraph(("P",), (Edge("loop", "P", "P", self.loop),))


@dataclass(frozen=True)
class Lollipop(Track):
    """The lollipop track: a stick of length ``stick`` from the free end F to the pole P, and a loop at P.

    Parameters
    ----------
    stick : float
        Stick length ℓ (metres, > 0).
    loop : float
        Loop circumference c (metres, > 0).
    """

    stick: float = 1.0
    loop: float = 1.0
    kind = "lollipop"
    has_loop = True

    @property
    def half(self) -> float:
        """Half the loop, ``h = c/2`` (the paper's "half unit")."""
        return 0.5 * self.loop

    def theta(self, p: ArrayLike) -> FloatArray:
        """Loop angle ``θ = p − ℓ`` in ``[0, c)`` for positions on the loop (0 at P); NaN on the open stick."""
        p = np.asarray(p, dtype=float)
        return np.where(p >= self.stick, p - self.stick, np.nan)

    def distance(self, p: ArrayLike, q: ArrayLike) -> FloatArray:
        ell, c = self.stick, self.loop
        p, q = np.broadcast_arrays(np.asarray(p, dtype=float), np.asarray(q, dtype=float))
        # depth below P along the stick (0 on the loop) and loop-distance to P (0 on the stick)
        xp = np.maximum(ell - p, 0.0)
        xq = np.maximum(ell - q, 0.0)
        tp = np.maximum(p - ell, 0.0)
        tq = np.maximum(q - ell, 0.0)
        wp = np.minimum(tp, c - tp)
        wq = np.minimum(tq, c - tq)
        diff = np.abs(tp - tq)
        both_loop = np.minimum(diff, c - diff)
        return np.where(
            (p <= ell) & (q <= ell),
            np.abs(p - q),
            np.where((p >= ell) & (q >= ell), both_loop, xp + xq + wp + wq),
        )

    def distance_scalar(self, p: float, q: float) -> float:
        ell, c = self.stick, self.loop
        if p <= ell and q <= ell:
            return abs(p - q)
        if p >= ell and q >= ell:
            diff = abs(p - q)
            return min(diff, c - diff)
        if p > q:
            p, q = q, p
        w = q - ell
        return (ell - p) + min(w, c - w)

    def interpolate(self, p: ArrayLike, q: ArrayLike, f: ArrayLike) -> FloatArray:
        p, q, f = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (p, q, f)))
        ell, c = self.stick, self.loop
        out = np.empty(p.shape)
        ps, qs = p <= ell, q <= ell
        m = ps & qs
        out[m] = p[m] + f[m] * (q[m] - p[m])
        m = ~ps & ~qs
        th = np.mod(p[m] - ell + f[m] * _shortest_loop_step(p[m], q[m], c), c)
        out[m] = ell + th
        m = ps != qs  # through P: stick part, then loop part
        if np.any(m):
            pm, qm, fm = p[m], q[m], f[m]
            stick_pt = np.where(pm <= ell, pm, qm)
            loop_pt = np.where(pm <= ell, qm, pm)
            x = ell - stick_pt
            th = loop_pt - ell
            w = np.minimum(th, c - th)
            side = np.where(th <= 0.5 * c, 1.0, -1.0)
            total = x + w
            along = np.where(pm <= ell, fm, 1.0 - fm) * total  # distance travelled from the stick end
            on_stick = along <= x
            out[m] = np.where(on_stick, stick_pt + along, ell + np.mod(side * (along - x), c))
        return out

    def normalize(self, p: ArrayLike) -> FloatArray:
        return _snap_near_end(p, self.stick + self.loop, self.stick)

    def _valid_mask(self, p: FloatArray) -> NDArray[np.bool_]:
        return (p >= 0.0) & (p < self.stick + self.loop)

    def _range_text(self) -> str:
        ell, end = self.stick, self.stick + self.loop
        return f"[0, {end:g}) (stick [0, {ell:g}], loop ({ell:g}, {end:g}))"

    def on_loop(self, p: ArrayLike) -> NDArray[np.bool_]:
        return np.asarray(p, dtype=float) >= self.stick

    def embed(self, p: ArrayLike) -> FloatArray:
        """Stick along the negative x axis ending at P = (0, 0); loop a circle to the right of P, ccw."""
        p = np.asarray(p, dtype=float)
        ell, c = self.stick, self.loop
        r = c / (2 * np.pi)
        ang = 2 * np.pi * np.maximum(p - ell, 0.0) / c
        loop_xy = np.stack([r - r * np.cos(ang), -r * np.sin(ang)], axis=-1)  # ccw about the centre (r, 0)
        stick_xy = np.stack([p - ell, np.zeros_like(p)], axis=-1)
        return np.where((p <= ell)[..., None], stick_xy, loop_xy)

    def as_graph(self) -> MetricGraph:
        return MetricGraph(("F", "P"), (Edge("stick", "F", "P", self.stick), Edge("loop", "P", "P", self.loop)))


def make_track(kind: str, stick: float | None = None, loop: float | None = None) -> Track:
    """Build a track by name with the paper's defaults (ℓ = c = 1).

    Parameters
    ----------
    kind : {"interval", "circle", "lollipop"}
    stick, loop : float, optional
        Lengths in metres; a parameter the track does not have is rejected.

    Returns
    -------
    Track
    """
    if not isinstance(kind, str):
        raise InvalidInputError(f"track is {kind!r}, expected one of 'interval', 'circle', 'lollipop'")
    if kind == "interval":
        if loop is not None:
            raise InvalidInputError(f"loop is {loop!r}, but an interval track has no loop (give --stick only)")
        return Interval(1.0 if stick is None else stick)
    if kind == "circle":
        if stick is not None:
            raise InvalidInputError(f"stick is {stick!r}, but a circle track has no stick (give --loop only)")
        return Circle(1.0 if loop is None else loop)
    if kind == "lollipop":
        return Lollipop(1.0 if stick is None else stick, 1.0 if loop is None else loop)
    raise InvalidInputError(f"track is {kind!r}, expected one of 'interval', 'circle', 'lollipop'")
