"""Robots' bodies in the plane: footprints, the drawing of a layout, poses and the exact gap between two bodies.

A *footprint* is a robot's body, centred on its position on the track:

- :class:`Disc` ``(radius)``: a disc (the Open-RMF convention);
- :class:`Rectangle` ``(length, width)``: ``length`` along the track's tangent, ``width`` across.

:class:`Footprints` holds one footprint per robot (``a``, ``b``); :func:`footprints` turns a footprint, a pair, a
:class:`Footprints` or a spec string into one, and :func:`parse_footprint` reads the command line's spec: ``R``
(a disc of radius R metres), ``LxW`` (a rectangle, e.g. ``2.0x0.8``), one spec for both robots or ``SPEC_A,SPEC_B``.

**The drawing.** A layout with vertex coordinates (metres) is drawn with each edge a straight segment between its
ends or along its ``points`` polyline. A robot at offset ``o`` on an edge of length ``L`` stands at the point at the
fraction ``o / L`` of the drawn polyline's length (arc length in proportion), with *heading* the direction of the
polyline's piece there (radians, ``atan2(dy, dx)``, along the edge's orientation ``from -> to``). :class:`Drawing`
splits every edge into its straight *pieces*: on a piece the point is affine in the offset.

**Corners.** Where the heading changes (a polyline corner, or a vertex between edges) the body's orientation jumps in
this model; a robot standing exactly on the corner has *every* orientation of the pieces that meet there (the union
of those bodies), and the planner and the gate keep the bodies apart in each of them (:mod:`mpa.planar`).

**Gap.** :func:`body_gap` is the exact Euclidean distance between two bodies (0 when they touch or overlap): discs
exactly, rectangles as polygons (separating-axis distance of convex polygons).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa._arrays import FloatArray
from mpa.errors import InvalidInputError
from mpa.graph_track import GraphTrack, as_graph_track

__all__ = [
    "DISC_SIDES",
    "Disc",
    "Drawing",
    "Footprint",
    "Footprints",
    "Rectangle",
    "body_gap",
    "body_polygon",
    "drawing_of",
    "footprints",
    "parse_footprint",
]


#: Sides of the polygon circumscribed about a disc (or a sum of discs) in the planner's free space: the polygon
#: reaches at most ``R / cos(pi / DISC_SIDES) - R`` (0.48 % of R) beyond the disc of radius R, and exactly R across
#: robot A's track (one side is normal to it), so thresholds across parallel tracks are exact.
DISC_SIDES = 32


def _positive(value: object, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InvalidInputError(f"{what} is {value!r}, expected a finite number > 0 (metres)")
    v = float(value)
    if not math.isfinite(v) or v <= 0.0:
        raise InvalidInputError(f"{what} is {value!r}, expected a finite number > 0 (metres)")
    return v


@dataclass(frozen=True)
class Disc:
    """A disc footprint of ``radius`` metres (> 0), centred on the robot's position."""

    radius: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", _positive(self.radius, "footprint radius"))

    @property
    def half_length(self) -> float:
        """Reach along the track from the centre (metres)."""
        return self.radius

    @property
    def half_width(self) -> float:
        """Reach across the track from the centre (metres)."""
        return self.radius

    @property
    def reach(self) -> float:
        """Largest distance of a point of the body from its centre (metres)."""
        return self.radius

    def spec(self) -> str:
        """The command line's spec of this footprint (``R``)."""
        return f"{self.radius:g}"

    def corners(self) -> FloatArray:
        """Body-frame polygon (x along the track, y across) circumscribed about the disc, shape (DISC_SIDES, 2)."""
        n = DISC_SIDES
        ang = (np.arange(n) + 0.5) * (2.0 * math.pi / n) - 0.5 * math.pi
        rr = self.radius / math.cos(math.pi / n)
        return np.stack([rr * np.cos(ang), rr * np.sin(ang)], axis=1)


@dataclass(frozen=True)
class Rectangle:
    """A rectangular footprint: ``length`` along the track's tangent, ``width`` across (metres, > 0)."""

    length: float
    width: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "length", _positive(self.length, "footprint length"))
        object.__setattr__(self, "width", _positive(self.width, "footprint width"))

    @property
    def half_length(self) -> float:
        """Reach along the track from the centre (metres)."""
        return 0.5 * self.length

    @property
    def half_width(self) -> float:
        """Reach across the track from the centre (metres)."""
        return 0.5 * self.width

    @property
    def reach(self) -> float:
        """Largest distance of a point of the body from its centre: half the diagonal (metres)."""
        return 0.5 * math.hypot(self.length, self.width)

    def spec(self) -> str:
        """The command line's spec of this footprint (``LxW``)."""
        return f"{self.length:g}x{self.width:g}"

    def corners(self) -> FloatArray:
        """Body-frame corners (x along the track, y across), counter-clockwise, shape (4, 2)."""
        hx, hy = 0.5 * self.length, 0.5 * self.width
        return np.array([[-hx, -hy], [hx, -hy], [hx, hy], [-hx, hy]])


Footprint = Disc | Rectangle


@dataclass(frozen=True)
class Footprints:
    """The footprints of robot A (``a``) and robot B (``b``)."""

    a: Footprint
    b: Footprint

    def spec(self) -> str:
        """The command line's spec: one footprint when both are equal, else ``SPEC_A,SPEC_B``."""
        return self.a.spec() if self.a == self.b else f"{self.a.spec()},{self.b.spec()}"

    def inflated(self, margin: float) -> Footprints:
        """Both bodies grown by ``margin`` metres on every side (discs: radius; rectangles: length and width)."""
        if margin <= 0.0:
            return self
        return Footprints(_grow(self.a, margin), _grow(self.b, margin))

    def across(self) -> float:
        """How far apart (metres) the centres must be across two parallel tracks: the half-widths summed."""
        return self.a.half_width + self.b.half_width

    def to_dict(self) -> dict[str, object]:
        """JSON form: ``{"spec", "a", "b"}`` with each body ``{"shape": "disc", "radius"}`` or rectangle."""
        return {"spec": self.spec(), "a": _body_dict(self.a), "b": _body_dict(self.b)}


def _grow(fp: Footprint, m: float) -> Footprint:
    if isinstance(fp, Disc):
        return Disc(fp.radius + m)
    return Rectangle(fp.length + 2.0 * m, fp.width + 2.0 * m)


def _body_dict(fp: Footprint) -> dict[str, object]:
    if isinstance(fp, Disc):
        return {"shape": "disc", "radius": fp.radius}
    return {"shape": "rectangle", "length": fp.length, "width": fp.width}


def _parse_one(text: str, whole: str) -> Footprint:
    t = text.strip().lower()
    expected = "expected R (disc radius, metres) or LxW (rectangle length x width, metres), e.g. 0.5 or 2.0x0.8"
    parts = t.split("x")
    if not t or len(parts) > 2 or any(not p.strip() for p in parts):
        raise InvalidInputError(f"footprint is {whole!r}, {expected}")
    vals = []
    for p in parts:
        try:
            v = float(p)
        except ValueError:
            raise InvalidInputError(f"footprint is {whole!r}, {expected}") from None
        if not math.isfinite(v) or v <= 0.0:
            raise InvalidInputError(f"footprint is {whole!r}: {p.strip()!r} is not a finite number > 0; {expected}")
        vals.append(v)
    return Disc(vals[0]) if len(vals) == 1 else Rectangle(vals[0], vals[1])


def parse_footprint(spec: str) -> Footprints:
    """Read a footprint spec: ``R``, ``LxW``, or ``SPEC_A,SPEC_B`` (one per robot).

    Raises
    ------
    InvalidInputError
        A malformed spec, or a size that is not a finite number > 0 (the message names the spec).

    Examples
    --------
    >>> parse_footprint("0.3")
    Footprints(a=Disc(radius=0.3), b=Disc(radius=0.3))
    >>> parse_footprint("2x0.8,0.4").b
    Disc(radius=0.4)
    """
    if not isinstance(spec, str):
        raise InvalidInputError(f"footprint is {spec!r}, expected a spec string such as '0.5' or '2.0x0.8'")
    parts = spec.split(",")
    if len(parts) > 2:
        raise InvalidInputError(f"footprint is {spec!r}, expected one spec for both robots or SPEC_A,SPEC_B")
    a = _parse_one(parts[0], spec)
    b = _parse_one(parts[1], spec) if len(parts) == 2 else a
    return Footprints(a, b)


def footprints(value: object) -> Footprints | None:
    """Normalise ``footprint=``: None, a :class:`Disc` or :class:`Rectangle` (both robots), a pair ``(A, B)``,
    a :class:`Footprints` or a spec string (:func:`parse_footprint`).

    Raises
    ------
    InvalidInputError
        Anything else.
    """
    if value is None or isinstance(value, Footprints):
        return value
    if isinstance(value, (Disc, Rectangle)):
        return Footprints(value, value)
    if isinstance(value, str):
        return parse_footprint(value)
    if isinstance(value, (tuple, list)) and len(value) == 2 and all(isinstance(v, (Disc, Rectangle)) for v in value):
        return Footprints(value[0], value[1])
    raise InvalidInputError(
        f"footprint is {value!r}, expected mpa.Disc(r), mpa.Rectangle(length, width), a pair of them (robot A, "
        "robot B) or a spec string such as '0.5' or '2.0x0.8'"
    )


# ------------------------------------------------------------------------------------------------ drawing
@dataclass(frozen=True, eq=False)
class Drawing:
    """The straight pieces of a layout's drawing.

    Attributes
    ----------
    track : GraphTrack
    piece_edge : ndarray of int, shape (P,)
        The edge of each piece.
    piece_s0, piece_s1 : ndarray, shape (P,)
        The offsets (metres) where the piece starts and ends on its edge.
    piece_p0 : ndarray, shape (P, 2)
        The drawn point at ``piece_s0`` (metres).
    piece_dir : ndarray, shape (P, 2)
        Drawn displacement per metre of offset: unit tangent times the drawing's scale on that edge.
    piece_heading : ndarray, shape (P,)
        Heading of the piece (radians).
    edge_pieces : list of ndarray of int
        Per edge its pieces in order of offset.
    """

    track: GraphTrack
    piece_edge: NDArray[np.int64]
    piece_s0: FloatArray
    piece_s1: FloatArray
    piece_p0: FloatArray
    piece_dir: FloatArray
    piece_heading: FloatArray
    edge_pieces: tuple[NDArray[np.int64], ...]

    @cached_property
    def edge_breaks(self) -> tuple[FloatArray, ...]:
        """Per edge the offsets of its pieces' starts (for lookup)."""
        return tuple(self.piece_s0[p] for p in self.edge_pieces)

    @cached_property
    def _lookup(self) -> tuple[FloatArray, FloatArray, NDArray[np.int64], NDArray[np.int64]]:
        """For :meth:`piece_at`: each edge's base on one line (edges 1 m apart), the pieces' starts on that line,
        and each edge's first and last piece."""
        lengths = np.asarray(self.track.lengths, dtype=float)
        base = np.concatenate([[0.0], np.cumsum(lengths + 1.0)[:-1]])
        keys = base[self.piece_edge] + self.piece_s0
        first = np.array([int(p[0]) for p in self.edge_pieces], dtype=np.int64)
        last = np.array([int(p[-1]) for p in self.edge_pieces], dtype=np.int64)
        return base, keys, first, last

    def piece_at(self, edge: ArrayLike, offset: ArrayLike) -> NDArray[np.int64]:
        """The piece holding each position (at a corner: the piece that starts there; at the edge's end: the last).

        One search over all edges' pieces at once (each edge's offsets shifted onto one line), then corrected by
        comparing the offset with the pieces' own starts, so the answer is the piece whose ``[s0, s1)`` holds the
        offset exactly (clamped to the edge's first and last piece).
        """
        e, o = np.broadcast_arrays(np.asarray(edge, dtype=np.int64), np.asarray(offset, dtype=float))
        base, keys, first, last = self._lookup
        lo, hi = first[e], last[e]
        k = np.clip(np.searchsorted(keys, base[e] + o, side="right") - 1, lo, hi)
        s0 = self.piece_s0
        for _ in range(2):  # rounding on the shared line moves the index by one piece at most, each way
            k = k - ((k > lo) & (o < s0[k]))
            k = k + ((k < hi) & (o >= s0[np.minimum(k + 1, hi)]))
        return np.asarray(k, dtype=np.int64)

    def pose(self, edge: ArrayLike, offset: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Drawn point ``(..., 2)`` (metres) and heading ``(...)`` (radians) of positions."""
        e, o = np.broadcast_arrays(np.asarray(edge, dtype=np.int64), np.asarray(offset, dtype=float))
        p = self.piece_at(e, o)
        xy = self.piece_p0[p] + (o - self.piece_s0[p])[..., None] * self.piece_dir[p]
        return xy, self.piece_heading[p]

    def corner_headings(self, edge: int, offset: float, tol: float = 1e-9) -> list[float]:
        """All headings a body at this position may have: one inside a piece, every piece's at a corner or vertex."""
        tr = self.track
        w = tr.vertex_at(edge, offset) if (offset <= tol or offset >= tr.lengths[edge] - tol) else None
        out: list[float] = []
        if w is not None:
            for f in range(tr.n_edges):
                pcs = self.edge_pieces[f]
                if tr.tails[f] == w:
                    out.append(float(self.piece_heading[pcs[0]]))
                if tr.heads[f] == w:
                    out.append(float(self.piece_heading[pcs[-1]]))
            return out
        for p in self.edge_pieces[edge]:
            if self.piece_s0[p] - tol <= offset <= self.piece_s1[p] + tol:
                out.append(float(self.piece_heading[p]))
        return out


def _build_drawing(tr: GraphTrack) -> Drawing:
    edge_l: list[int] = []
    s0: list[float] = []
    s1: list[float] = []
    p0: list[NDArray[np.float64]] = []
    dr: list[NDArray[np.float64]] = []
    hd: list[float] = []
    per_edge: list[NDArray[np.int64]] = []
    for e in range(tr.n_edges):
        a, b = tr.coords[tr.tails[e]], tr.coords[tr.heads[e]]
        if a is None or b is None:
            raise InvalidInputError(
                f"edge {tr.edge_names[e]!r} has an end without coordinates, expected [x, y] for both ends: a "
                "footprint needs the layout drawn in metres"
            )
        pts = np.array([a, *tr.points[e], b], dtype=float)
        seg = np.hypot(*np.diff(pts, axis=0).T)
        total = float(seg.sum())
        length = float(tr.lengths[e])
        if total <= 0.0:
            raise InvalidInputError(
                f"edge {tr.edge_names[e]!r} is drawn with length 0, expected a drawing with a direction at every "
                "point (a footprint needs each edge drawn as a segment or polyline)"
            )
        cum = np.concatenate([[0.0], np.cumsum(seg)]) / total * length
        first = len(edge_l)
        for i in range(len(seg)):
            if seg[i] <= 1e-12 * max(1.0, total):
                continue
            u = (pts[i + 1] - pts[i]) / seg[i]
            edge_l.append(e)
            s0.append(cum[i])
            s1.append(cum[i + 1])
            p0.append(pts[i])
            dr.append(u * (total / length))
            hd.append(math.atan2(u[1], u[0]))
        per_edge.append(np.arange(first, len(edge_l), dtype=np.int64))
    return Drawing(
        tr,
        np.array(edge_l, dtype=np.int64),
        np.array(s0, dtype=float),
        np.array(s1, dtype=float),
        np.array(p0, dtype=float).reshape(-1, 2),
        np.array(dr, dtype=float).reshape(-1, 2),
        np.array(hd, dtype=float),
        tuple(per_edge),
    )


_DRAWINGS: dict[int, tuple[GraphTrack, Drawing]] = {}


def drawing_of(track: object) -> Drawing:
    """The :class:`Drawing` of a track (cached per track).

    Raises
    ------
    InvalidInputError
        A vertex without coordinates, or an edge drawn with length 0.
    """
    tr = as_graph_track(track)
    hit = _DRAWINGS.get(id(tr))
    if hit is not None and hit[0] is tr:
        return hit[1]
    d = _build_drawing(tr)
    if len(_DRAWINGS) > 32:
        _DRAWINGS.clear()
    _DRAWINGS[id(tr)] = (tr, d)
    return d


# ------------------------------------------------------------------------------------------------ bodies
def _rot(heading: float) -> FloatArray:
    c, s = math.cos(heading), math.sin(heading)
    return np.array([[c, -s], [s, c]])


def body_polygon(fp: Footprint, xy: ArrayLike, heading: float) -> FloatArray:
    """Corners of a rectangle (or the polygon circumscribed about a disc) placed at ``xy`` with ``heading``."""
    return np.asarray(xy, dtype=float) + fp.corners() @ _rot(heading).T


def _seg_point_dist(p: FloatArray, a: FloatArray, b: FloatArray) -> float:
    ab = b - a
    den = float(ab @ ab)
    lam = 0.0 if den <= 0.0 else min(1.0, max(0.0, float((p - a) @ ab) / den))
    return float(np.hypot(*(a + lam * ab - p)))


def _point_in_convex(p: FloatArray, poly: FloatArray) -> bool:
    n = len(poly)
    sign = 0.0
    for i in range(n):
        a, b = poly[i], poly[(i + 1) % n]
        c = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
        if c != 0.0:
            if sign == 0.0:
                sign = c
            elif (c > 0) != (sign > 0):
                return False
    return True


def _poly_poly_dist(p: FloatArray, q: FloatArray) -> float:
    """Distance between two convex polygons (0 if they overlap)."""
    if _convex_overlap(p, q):
        return 0.0
    best = math.inf
    for P, Q in ((p, q), (q, p)):
        for v in P:
            for i in range(len(Q)):
                best = min(best, _seg_point_dist(v, Q[i], Q[(i + 1) % len(Q)]))
    return best


def _convex_overlap(p: FloatArray, q: FloatArray) -> bool:
    """Separating-axis test of two convex polygons (touching counts as overlapping)."""
    for P in (p, q):
        d = np.roll(P, -1, axis=0) - P
        normals = np.stack([d[:, 1], -d[:, 0]], axis=1)
        pa = p @ normals.T
        qa = q @ normals.T
        if np.any((pa.max(axis=0) < qa.min(axis=0)) | (qa.max(axis=0) < pa.min(axis=0))):
            return False
    return True


def body_gap(
    fa: Footprint, xy_a: ArrayLike, heading_a: float, fb: Footprint, xy_b: ArrayLike, heading_b: float
) -> float:
    """Exact distance (metres) between two placed bodies; 0 when they touch or overlap.

    Discs are exact discs here (not the planner's circumscribed polygon).
    """
    pa = np.asarray(xy_a, dtype=float)
    pb = np.asarray(xy_b, dtype=float)
    if isinstance(fa, Disc) and isinstance(fb, Disc):
        return max(0.0, float(np.hypot(*(pa - pb))) - fa.radius - fb.radius)
    if isinstance(fa, Disc) or isinstance(fb, Disc):
        disc, centre, rect, rxy, rh = (
            (fa, pa, fb, pb, heading_b) if isinstance(fa, Disc) else (fb, pb, fa, pa, heading_a)
        )
        assert isinstance(disc, Disc) and isinstance(rect, Rectangle)
        poly = body_polygon(rect, rxy, rh)
        if _point_in_convex(centre, poly):
            return 0.0
        d = min(_seg_point_dist(centre, poly[i], poly[(i + 1) % 4]) for i in range(4))
        return max(0.0, d - disc.radius)
    assert isinstance(fa, Rectangle) and isinstance(fb, Rectangle)
    return _poly_poly_dist(body_polygon(fa, pa, heading_a), body_polygon(fb, pb, heading_b))
