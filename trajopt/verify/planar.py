"""The gate's check in the plane: the robots' bodies (footprints) stay apart at every row and between rows.

Next to the along-track clearance (:mod:`trajopt.verify.gate`) a trajectory with a footprint passes this check before it
leaves the library. It reads only the rows (edges, offsets, speeds), the layout's drawing
(:class:`mpa.footprint.Drawing`) and the footprints; it shares no code with the planner (:mod:`mpa.planar`).

**At rows.** Each body is placed at the row's point with its piece's heading (a row exactly on a corner or vertex:
every heading there). The gap is a lower bound of the Euclidean distance between the bodies, exact for two discs and
for a disc and a rectangle; for two rectangles the largest separation of their projections on the four edge
normals (exact when the closest features are an edge and a vertex or two parallel edges, never above the distance).

**Between rows.** Along its track a robot travels at most ``∫ min(|v_i| + A·τ, |v_{i+1}| + A·(Δt − τ)) dτ`` between
rows ``i`` and ``i + 1`` (speeds at the rows, acceleration limit A); a point of its body moves at most that distance
times the drawing's scale (drawn metres per metre of offset), plus, where the robot passes a corner, the rotation:
``reach · |turn|`` (``reach`` the largest distance of a body point from its centre: half the diagonal of a rectangle;
a disc does not move by turning; the turn of a centrally symmetric body is taken modulo pi, at most pi/2).
If ``m`` bounds both bodies' motion, the gap anywhere between the rows is at least
``(gap_i + gap_{i+1} − m) / 2``. Where a rectangle turns between two rows, its sweep lies in the disc of its reach
about its centre (moved by its travel), which gives a second bound: the centres' distance minus both reaches and both
travels; the larger of the two counts. The check asks a bound ``>= 0`` of every interval (tolerance 1e-9 m).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa._arrays import FloatArray
from mpa.footprint import Disc, Drawing, Footprint, Footprints, drawing_of
from mpa.graph_track import GraphTrack

__all__ = ["PLANE_TOL", "PlaneReport", "plane_margin", "row_gaps", "verify_plane"]

#: Tolerance (metres) of the plane checks.
PLANE_TOL = 1e-9


@dataclass(frozen=True)
class PlaneReport:
    """Outcome of :func:`verify_plane`.

    Attributes
    ----------
    ok : bool
    failures : tuple of str
    min_gap_plane : float
        Smallest gap between the bodies at the rows (metres).
    min_gap_between : float
        Lower bound of the gap between rows (metres).
    gaps : ndarray, shape (N,)
        The gap at every row (metres).
    """

    ok: bool
    failures: tuple[str, ...]
    min_gap_plane: float
    min_gap_between: float
    gaps: FloatArray

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary (without the per-row gaps)."""
        return {
            "ok": self.ok,
            "failures": list(self.failures),
            "min_gap_plane": self.min_gap_plane,
            "min_gap_between": self.min_gap_between,
        }


def _local(fp: Footprint, d: FloatArray, h: FloatArray) -> FloatArray:
    """Distance from points ``d`` (relative to a rectangle's centre) to the rectangle of heading ``h``."""
    c, s = np.cos(h), np.sin(h)
    x = np.abs(c * d[:, 0] + s * d[:, 1]) - fp.half_length
    y = np.abs(-s * d[:, 0] + c * d[:, 1]) - fp.half_width
    return np.hypot(np.maximum(x, 0.0), np.maximum(y, 0.0)) + np.minimum(np.maximum(x, y), 0.0)


def _rect_axes_gap(
    fa: Footprint, pa: FloatArray, ha: FloatArray, fb: Footprint, pb: FloatArray, hb: FloatArray
) -> FloatArray:
    """Largest separation of two rectangles' projections on their four edge normals (per row)."""
    d = pb - pa
    best = np.full(len(d), -np.inf)
    for h_axis in (ha, ha + 0.5 * math.pi, hb, hb + 0.5 * math.pi):
        ux, uy = np.cos(h_axis), np.sin(h_axis)
        centre = np.abs(d[:, 0] * ux + d[:, 1] * uy)
        ra = fa.half_length * np.abs(np.cos(h_axis - ha)) + fa.half_width * np.abs(np.sin(h_axis - ha))
        rb = fb.half_length * np.abs(np.cos(h_axis - hb)) + fb.half_width * np.abs(np.sin(h_axis - hb))
        best = np.maximum(best, centre - ra - rb)
    return best


def pair_gaps(fps: Footprints, pa: FloatArray, ha: FloatArray, pb: FloatArray, hb: FloatArray) -> FloatArray:
    """Lower bounds of the distance between the bodies, per row (negative: overlapping). Shape (N,)."""
    fa, fb = fps.a, fps.b
    if isinstance(fa, Disc) and isinstance(fb, Disc):
        return np.hypot(*(pb - pa).T) - fa.radius - fb.radius
    if isinstance(fa, Disc):
        return _local(fb, pa - pb, hb) - fa.radius
    if isinstance(fb, Disc):
        return _local(fa, pb - pa, ha) - fb.radius
    return _rect_axes_gap(fa, pa, ha, fb, pb, hb)


def row_gaps(track: GraphTrack, fps: Footprints, edges: ArrayLike, offsets: ArrayLike) -> FloatArray:
    """The gap between the bodies at every row (metres, every heading at a corner). Shape (N,)."""
    d = drawing_of(track)
    E = np.asarray(edges, dtype=np.int64)
    OFF = np.asarray(offsets, dtype=float)
    pa, ha = d.pose(E[:, 0], OFF[:, 0])
    pb, hb = d.pose(E[:, 1], OFF[:, 1])
    gaps = pair_gaps(fps, pa, ha, pb, hb)
    rows = np.nonzero(_at_corner(d, E, OFF))[0]
    if len(rows):
        # every pair of headings at the corner rows, in one call (the headings looked up once per position)
        memo: dict[tuple[int, float], list[float]] = {}

        def heads(e: int, o: float) -> list[float]:
            key = (e, o)
            if key not in memo:
                memo[key] = d.corner_headings(e, o)
            return memo[key]

        ks: list[int] = []
        hs_a: list[float] = []
        hs_b: list[float] = []
        for k in rows.tolist():
            la = heads(int(E[k, 0]), float(OFF[k, 0]))
            lb = heads(int(E[k, 1]), float(OFF[k, 1]))
            for hha in la:
                ks.extend([k] * len(lb))
                hs_a.extend([hha] * len(lb))
                hs_b.extend(lb)
        if ks:
            kk = np.array(ks, dtype=np.int64)
            g = pair_gaps(fps, pa[kk], np.array(hs_a), pb[kk], np.array(hs_b))
            np.minimum.at(gaps, kk, g)
    return gaps


def _at_corner(d: Drawing, E: NDArray[np.int64], OFF: FloatArray, tol: float = 1e-9) -> NDArray[np.bool_]:
    out = np.zeros(len(E), dtype=bool)
    for r in (0, 1):
        p = d.piece_at(E[:, r], OFF[:, r])
        out |= (np.abs(OFF[:, r] - d.piece_s0[p]) <= tol) | (np.abs(OFF[:, r] - d.piece_s1[p]) <= tol)
    return out


def _travel(v0: FloatArray, v1: FloatArray, amax: float, dt: float) -> FloatArray:
    """Largest distance travelled in ``dt`` from speed |v0| to |v1| with |acceleration| <= amax (per interval)."""
    u, w = np.abs(v0), np.abs(v1)
    if amax <= 0:
        return np.maximum(u, w) * dt
    ts = np.clip((w - u + amax * dt) / (2.0 * amax), 0.0, dt)
    return u * ts + 0.5 * amax * ts**2 + w * (dt - ts) + 0.5 * amax * (dt - ts) ** 2


def _motion(
    d: Drawing,
    fp: Footprint,
    e: NDArray[np.int64],
    o: FloatArray,
    v: FloatArray,
    amax: float,
    dt: float,
    where: tuple[NDArray[np.int64], NDArray[np.bool_]] | None = None,
) -> FloatArray:
    """Bound of how far any point of one body moves between consecutive rows (metres). Shape (N - 1,).

    ``where``: the rows' pieces and whether each row is on a corner (:func:`_pieces`), when already known."""
    travel = _travel(v[:-1], v[1:], amax, dt)
    scale = float(np.max(np.hypot(*d.piece_dir.T)))
    move = travel * scale
    p, at = where if where is not None else _pieces(d, e, o)
    h = d.piece_heading[p]
    turned = (p[:-1] != p[1:]) | at[:-1] | at[1:]
    if np.any(turned) and not isinstance(fp, Disc):
        shortest = float(np.min(d.piece_s1 - d.piece_s0))
        dh = _axis_turn(h[1:] - h[:-1])
        # passing a vertex, the headings of every piece there bound the turn; more than one corner: pi each
        many = travel >= shortest
        turn = np.where(
            many, 0.5 * math.pi * (1.0 + travel / max(shortest, 1e-12)), np.maximum(dh, _vertex_turn(d, e, o, at))
        )
        move = move + np.where(turned, fp.reach * turn, 0.0)
    return move


def _point_gap(fp: Footprint, d: FloatArray, h: FloatArray) -> FloatArray:
    """Distance from points ``d`` (relative to the body's centre) to a body of heading ``h`` (0 inside)."""
    if isinstance(fp, Disc):
        return np.maximum(np.hypot(*d.T) - fp.radius, 0.0)
    return np.maximum(_local(fp, d, h), 0.0)


def _turning_one(
    d: Drawing,
    fp: Footprint,
    e: NDArray[np.int64],
    o: FloatArray,
    where: tuple[NDArray[np.int64], NDArray[np.bool_]] | None = None,
) -> NDArray[np.bool_]:
    """Per interval: whether this robot's rectangle turns (its piece's orientation changes, or a row on a corner)."""
    if isinstance(fp, Disc):
        return np.zeros(len(e) - 1, dtype=bool)
    p, at = where if where is not None else _pieces(d, e, o)
    h = d.piece_heading[p]
    return np.asarray((_axis_turn(h[1:] - h[:-1]) > 1e-12) | at[:-1] | at[1:])


def _turning(d: Drawing, fps: Footprints, E: NDArray[np.int64], OFF: FloatArray) -> NDArray[np.bool_]:
    """Per interval: whether a rectangle body turns (its piece's orientation changes, or a row is on a corner)."""
    out = np.zeros(len(E) - 1, dtype=bool)
    for r, fp in enumerate((fps.a, fps.b)):
        if isinstance(fp, Disc):
            continue
        p = d.piece_at(E[:, r], OFF[:, r])
        h = d.piece_heading[p]
        at = _at_corner_1(d, E[:, r], OFF[:, r])
        out |= (_axis_turn(h[1:] - h[:-1]) > 1e-12) | at[:-1] | at[1:]
    return out


def _at_corner_1(d: Drawing, e: NDArray[np.int64], o: FloatArray, tol: float = 1e-9) -> NDArray[np.bool_]:
    return _pieces(d, e, o, tol)[1]


def _pieces(
    d: Drawing, e: NDArray[np.int64], o: FloatArray, tol: float = 1e-9
) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    """The drawing piece of every row of one robot and whether the row is on a corner (within ``tol`` metres of
    its piece's start or end). Shapes (N,), (N,)."""
    p = d.piece_at(e, o)
    return p, (np.abs(o - d.piece_s0[p]) <= tol) | (np.abs(o - d.piece_s1[p]) <= tol)


def _axis_turn(dh: Any) -> Any:
    """Rotation (radians, in [0, pi/2]) between two headings of a centrally symmetric body (orientation mod pi)."""
    x = np.mod(np.abs(dh), math.pi)
    return np.minimum(x, math.pi - x)


def _vertex_turn(d: Drawing, e: NDArray[np.int64], o: FloatArray, at: NDArray[np.bool_] | None = None) -> FloatArray:
    """Per interval: the largest turn between the headings of any two pieces at a corner touched by its rows
    (``at``: whether each row is on a corner, when already known)."""
    out = np.zeros(len(e) - 1)
    if at is None:
        at = _at_corner_1(d, e, o)
    for k in np.nonzero(at)[0]:
        hs = d.corner_headings(int(e[k]), float(o[k]))
        if len(hs) < 2:
            continue
        arr = np.array(hs)
        turn = float(np.max(_axis_turn(arr[:, None] - arr[None, :])))
        if k > 0:
            out[k - 1] = max(out[k - 1], turn)
        if k < len(out):
            out[k] = max(out[k], turn)
    return out


def plane_margin(fps: Footprints, vmax: ArrayLike, amax: ArrayLike, rate: float, scale: float = 1.0) -> float:
    """Gap (metres) the planner keeps between the bodies so that the between-rows bound holds at ``rate``.

    At full speed both bodies move at most ``Σ (v·Δt + a·Δt²/4)·scale`` between rows; the gap at both rows must
    cover it (half each), plus 1e-9 m.
    """
    dt = 1.0 / float(rate)
    v = np.broadcast_to(np.asarray(vmax, dtype=float), (2,))
    a = np.broadcast_to(np.asarray(amax, dtype=float), (2,))
    return float(0.5 * np.sum(v * dt + a * dt * dt / 4.0) * scale + 1e-9)


def verify_plane(
    track: GraphTrack,
    fps: Footprints,
    edges: ArrayLike,
    offsets: ArrayLike,
    v: ArrayLike,
    *,
    amax: ArrayLike,
    rate: float,
) -> PlaneReport:
    """Check that the bodies stay apart at every row and between rows (see the module docstring).

    Parameters
    ----------
    track : GraphTrack
        A layout with coordinates.
    fps : Footprints
    edges, offsets : array_like, shape (N, 2)
        Rows' positions (edge index, metres from the edge's tail).
    v : array_like, shape (N, 2)
        Speeds at the rows (m/s; the sign is ignored).
    amax : float or (float, float)
        Acceleration limits (m/s²).
    rate : float
        Row rate (Hz).

    Returns
    -------
    PlaneReport
        Never raises for a failed check.
    """
    d = drawing_of(track)
    E = np.asarray(edges, dtype=np.int64)
    OFF = np.asarray(offsets, dtype=float)
    V = np.asarray(v, dtype=float)
    acc = np.broadcast_to(np.asarray(amax, dtype=float), (2,))
    gaps = row_gaps(track, fps, E, OFF)
    fails: list[str] = []
    k = int(np.argmin(gaps))
    if gaps[k] < -PLANE_TOL:
        fails.append(f"row {k}: the bodies overlap in the plane (gap {float(gaps[k]):.6g} m)")
    if len(gaps) > 1:
        dt = 1.0 / float(rate)
        wa, wb = _pieces(d, E[:, 0], OFF[:, 0]), _pieces(d, E[:, 1], OFF[:, 1])
        ma = _motion(d, fps.a, E[:, 0], OFF[:, 0], V[:, 0], float(acc[0]), dt, wa)
        mb = _motion(d, fps.b, E[:, 1], OFF[:, 1], V[:, 1], float(acc[1]), dt, wb)
        between = 0.5 * (gaps[:-1] + gaps[1:] - (ma + mb))
        # where a rectangle turns between two rows its sweep lies in the disc of its reach about its centre
        turn_a = _turning_one(d, fps.a, E[:, 0], OFF[:, 0], wa)
        turn_b = _turning_one(d, fps.b, E[:, 1], OFF[:, 1], wb)
        turn = turn_a | turn_b
        if np.any(turn):
            pa, ha = d.pose(E[:, 0], OFF[:, 0])
            pb, hb = d.pose(E[:, 1], OFF[:, 1])
            scale = float(np.max(np.hypot(*d.piece_dir.T)))
            ta = _travel(V[:-1, 0], V[1:, 0], float(acc[0]), dt) * scale
            tb = _travel(V[:-1, 1], V[1:, 1], float(acc[1]), dt) * scale
            both = np.hypot(*(pa[:-1] - pb[:-1]).T) - fps.a.reach - fps.b.reach - ta - tb
            # one body turns: the disc of its reach against the other body as it is (which moves at most m)
            only_a = _point_gap(fps.b, pa[:-1] - pb[:-1], hb[:-1]) - fps.a.reach - ta - mb
            only_b = _point_gap(fps.a, pb[:-1] - pa[:-1], ha[:-1]) - fps.b.reach - tb - ma
            one = np.where(turn_a, np.maximum(only_a, both), np.maximum(only_b, both))
            disc_lb = np.where(turn_a & turn_b, both, one)
            between = np.where(turn, np.maximum(between, disc_lb), between)
        i = int(np.argmin(between))
        bmin = float(between[i])
        if bmin < -PLANE_TOL:
            fails.append(f"rows {i}-{i + 1}: the bodies may overlap in the plane between rows (bound {bmin:.6g} m)")
    else:
        bmin = float(gaps[0])
    return PlaneReport(not fails, tuple(fails), float(gaps.min()), bmin, gaps)
