"""Exact geometry of two robots on a metric graph: the one module of graph distance in this project.

A metric graph has ``V`` vertices (indices ``0..V-1``) and ``E`` edges ``i = (tail[i], head[i], length[i])``;
loops (``tail == head``) and parallel edges are allowed. A *position* is ``(edge, offset)``: the edge index and the
offset in metres from the edge's tail, ``0 <= offset <= length``.

Facts used everywhere (docs/graphs.md, "The free space, exactly"):

- ``DV`` is the all-pairs shortest vertex distance; a loop or the longer of two parallel edges never shortens it.
- For ``x = (e, s)`` and ``y = (f, t)``, ``d(x, y) = min(|s - t| if e == f, min over the four affine terms
  r_e(s, a) + DV[a, b] + r_f(t, b))`` with ``r_e(s, tail) = s`` and ``r_e(s, head) = L_e - s``. On a loop both terms
  exist, which covers going round it.
- In a *cell* ``e × f`` the distance is ``min`` over terms ``ca*s + cb*t + c0`` (``ca, cb ∈ {±1}``), plus ``|s - t|``
  when ``e == f``. Along a straight move ``(s0, t0) -> (s1, t1)`` inside one cell every term is affine in the move
  parameter, so the minimum of ``d`` sits at an end of the move, except that ``|s - t|`` reaches 0 when the robots
  cross on one edge. :meth:`GraphGeometry.segment_min` is therefore exact and costs a few flops.

The paper's tracks convert to graphs with ``as_graph_track()`` (see :mod:`mpa.graph_track`): an interval is one edge
``stick`` (free end ``F`` -> end ``E``), a circle one loop edge ``loop`` at ``P`` (counter-clockwise), a lollipop the
edges ``stick`` (free end ``F`` -> pole ``P``) and ``loop`` (``P`` -> ``P``, counter-clockwise). In *route
coordinates* (distance travelled along a route of directed edges, :class:`DirectedRoute`) the exact minimum
separation along a polyline is :meth:`GraphGeometry.route_min_distance`; smoothing and the verification gate of
``trajopt`` can use it instead of their own copies.
"""

from __future__ import annotations

import itertools
from bisect import bisect_right
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike

from mpa._arrays import FloatArray, IntArray
from mpa.errors import InvalidInputError

__all__ = ["DirectedRoute", "GraphGeometry", "RouteGeometry", "densify_polyline", "vertex_distance_matrix"]


def densify_polyline(pts: ArrayLike, step: float) -> FloatArray:
    """Points along a polyline with at most ``step`` between consecutive ones (max-norm), vectorized.

    Every leg ``p_k → p_{k+1}`` is cut into ``n_k = max(1, ⌈|p_{k+1} − p_k|_∞ / step⌉)`` equal parts; the result
    holds each leg's start and its ``n_k − 1`` inner points, then the last point.

    Parameters
    ----------
    pts : array_like, shape (K, D)
        The polyline's vertices.
    step : float
        Largest max-norm distance between consecutive output points (same unit as ``pts``, > 0).

    Returns
    -------
    ndarray, shape (M, D)
        ``M = Σ n_k + 1`` (a copy of ``pts`` when no leg is longer than ``step``).

    Examples
    --------
    >>> densify_polyline([[0.0, 0.0], [1.0, 0.5]], 0.5).tolist()
    [[0.0, 0.0], [0.5, 0.25], [1.0, 0.5]]
    """
    p = np.atleast_2d(np.asarray(pts, dtype=float))
    if len(p) < 2:
        return p.copy()
    leg = np.diff(p, axis=0)
    size = np.abs(leg)
    size = np.maximum(size[:, 0], size[:, 1]) if size.shape[1] == 2 else size.max(axis=1)  # (axis-1 max is slow)
    n = np.maximum(1, np.ceil(size / step).astype(np.int64))
    if int(n.max()) == 1:
        return p.copy()
    k = np.repeat(np.arange(len(leg)), n)
    first = np.repeat(np.cumsum(n) - n, n)
    frac = (np.arange(len(k)) - first) / n[k]
    return np.vstack([p[k] + frac[:, None] * leg[k], p[-1:]])


#: Largest vertex count for Floyd–Warshall in :func:`vertex_distance_matrix` (Dijkstra above it).
FLOYD_VERTICES = 300


def vertex_distance_matrix(n_vertices: int, tails: ArrayLike, heads: ArrayLike, lengths: ArrayLike) -> FloatArray:
    """All-pairs shortest distances between vertices.

    Up to :data:`FLOYD_VERTICES` vertices Floyd–Warshall (vectorized over one pivot at a time, ``O(V³)``), above
    it Dijkstra from every vertex (``scipy.sparse.csgraph``, ``O(V·E log V)``: 0.1 s instead of 1 s at 1 000
    edges). The two agree to rounding (``5.7e-14`` m at most on the benchmark's layouts and 200 random small
    graphs); the small layouts keep Floyd–Warshall's exact sums, so their plans do not change.

    Parameters
    ----------
    n_vertices : int
        ``V``.
    tails, heads : array_like of int, shape (E,)
        End vertices of each edge.
    lengths : array_like of float, shape (E,)
        Edge lengths (metres, >= 0).

    Returns
    -------
    ndarray, shape (V, V)
        ``DV[a, b]`` in metres, ``inf`` between graph components, 0 on the diagonal. Loops never change it and
        of parallel edges only the shortest counts.
    """
    t = np.asarray(tails, dtype=np.int64)
    h = np.asarray(heads, dtype=np.int64)
    w = np.asarray(lengths, dtype=float)
    keep = t != h
    t, h, w = t[keep], h[keep], w[keep]
    # the shortest of parallel edges, in both directions
    u = np.concatenate([t, h])
    v = np.concatenate([h, t])
    ww = np.concatenate([w, w])
    order = np.lexsort((ww, v, u))
    u, v, ww = u[order], v[order], ww[order]
    first = np.ones(len(u), dtype=bool)
    first[1:] = (u[1:] != u[:-1]) | (v[1:] != v[:-1])
    u, v, ww = u[first], v[first], ww[first]
    if n_vertices <= FLOYD_VERTICES or np.any(ww == 0.0):  # (a sparse matrix drops stored zeros)
        return _floyd(n_vertices, u, v, ww)
    from scipy.sparse import csr_matrix  # here: small layouts do without scipy's import (0.4 s)
    from scipy.sparse.csgraph import shortest_path

    graph = csr_matrix((ww, (u, v)), shape=(n_vertices, n_vertices))
    dv: FloatArray = shortest_path(graph, method="D", directed=True)
    np.fill_diagonal(dv, 0.0)
    return dv


def _floyd(n_vertices: int, u: IntArray, v: IntArray, w: FloatArray) -> FloatArray:
    """All-pairs shortest distances by Floyd–Warshall (one pivot at a time, vectorized); ``(u, v, w)`` directed."""
    dv = np.full((n_vertices, n_vertices), np.inf)
    np.fill_diagonal(dv, 0.0)
    np.minimum.at(dv, (u, v), w)
    for k in range(n_vertices):
        np.minimum(dv, dv[:, k, None] + dv[None, k, :], out=dv)
    return dv


@dataclass(frozen=True, eq=False)
class DirectedRoute:
    """A robot's route: a sequence of directed edges, with route coordinate = distance travelled along it.

    Piece ``i`` runs on edge ``edges[i]`` in direction ``dirs[i]`` (+1 along the edge's orientation, -1 against),
    entering at offset ``entry[i]`` and covering route coordinates ``[breaks[i], breaks[i+1]]``; on it the offset is
    ``entry[i] + dirs[i] * (r - breaks[i])``.

    Attributes
    ----------
    edges : ndarray of int, shape (M,)
    dirs : ndarray of int, shape (M,)
        +1 or -1.
    entry : ndarray of float, shape (M,)
        Offset where the piece starts (metres).
    breaks : ndarray of float, shape (M + 1,)
        Route coordinates of the piece boundaries, non-decreasing (metres). A plan's routes start at
        ``breaks[0] = 0`` (distance travelled); any origin works, e.g. a smoother's signed route coordinate σ.
        A polyline may move either way along the route coordinate: only the pieces' affine maps are used.
    """

    edges: IntArray
    dirs: IntArray
    entry: FloatArray
    breaks: FloatArray

    @classmethod
    def standing(cls, edge: int, offset: float) -> DirectedRoute:
        """The route of a robot that does not move (one piece of length 0)."""
        return cls(np.array([edge]), np.array([1]), np.array([float(offset)]), np.array([0.0, 0.0]))

    @classmethod
    def from_pieces(
        cls,
        edges: Sequence[int],
        dirs: Sequence[int],
        entry: Sequence[float],
        lengths: Sequence[float],
        origin: float = 0.0,
    ) -> DirectedRoute:
        """A route from its pieces' edges, directions (±1), entry offsets and lengths (metres), from ``origin``."""
        ln = np.asarray(lengths, dtype=float)
        if len(ln) == 0 or not (len(edges) == len(dirs) == len(entry) == len(ln)) or np.any(ln < 0):
            raise InvalidInputError("route pieces need one edge, direction, entry and length >= 0 each, at least one")
        d = np.asarray(dirs, dtype=np.int64)
        if not np.all(np.abs(d) == 1):
            raise InvalidInputError(f"route directions are {d.tolist()}, expected +1 or -1 each")
        breaks = float(origin) + np.concatenate([[0.0], np.cumsum(ln)])
        return cls(np.asarray(edges, dtype=np.int64), d, np.asarray(entry, dtype=float), breaks)

    @property
    def length(self) -> float:
        """Total route length (metres)."""
        return float(self.breaks[-1] - self.breaks[0])

    def piece_index(self, r: ArrayLike) -> IntArray:
        """Index of the piece holding route coordinate ``r`` (broadcast; ties go to the later piece)."""
        r = np.asarray(r, dtype=float)
        i = np.searchsorted(self.breaks, r, side="right") - 1
        return np.clip(i, 0, len(self.edges) - 1)

    def offsets_on(self, i: IntArray, r: FloatArray) -> FloatArray:
        """Offsets (m) at route coordinates ``r`` on the given pieces ``i`` (broadcast; no clamping)."""
        out: FloatArray = self.entry[i] + self.dirs[i] * (r - self.breaks[i])
        return out

    def positions(self, r: ArrayLike) -> tuple[IntArray, FloatArray]:
        """Positions ``(edge, offset)`` at route coordinates ``r`` (broadcast; clamped to the route)."""
        rr: FloatArray = np.clip(np.asarray(r, dtype=float), self.breaks[0], self.breaks[-1])
        i = self.piece_index(rr)
        return self.edges[i], self.offsets_on(i, rr)

    @cached_property
    def arrays(self) -> tuple[FloatArray, IntArray, IntArray, FloatArray]:
        """``breaks``, ``edges``, ``dirs``, ``entry`` as C-contiguous float/int64 arrays (built once)."""
        f = np.ascontiguousarray
        return (
            f(self.breaks, dtype=float),
            f(self.edges, dtype=np.int64),
            f(self.dirs, dtype=np.int64),
            f(self.entry, dtype=float),
        )

    @cached_property
    def pieces_list(self) -> tuple[list[float], list[int], list[int], list[float]]:
        """``breaks``, ``edges``, ``dirs``, ``entry`` as Python lists (for the scalar twins; built once)."""
        return self.breaks.tolist(), self.edges.tolist(), self.dirs.tolist(), self.entry.tolist()

    def piece_index_scalar(self, r: float) -> int:
        """:meth:`piece_index` of one route coordinate, in plain Python."""
        br = self.pieces_list[0]
        return min(max(bisect_right(br, r) - 1, 0), len(br) - 2)

    def position_scalar(self, r: float) -> tuple[int, float]:
        """:meth:`positions` of one route coordinate, in plain Python (the same clamping and piece choice)."""
        br, edges, dirs, entry = self.pieces_list
        r = min(max(r, br[0]), br[-1])
        i = self.piece_index_scalar(r)
        return edges[i], entry[i] + dirs[i] * (r - br[i])

    def to_list(self, names: Sequence[str] | None = None) -> list[dict[str, object]]:
        """JSON-friendly pieces ``{"edge", "dir", "entry", "from_s", "to_s"}``."""
        out: list[dict[str, object]] = []
        for i in range(len(self.edges)):
            e = int(self.edges[i])
            out.append(
                {
                    "edge": names[e] if names is not None else e,
                    "dir": int(self.dirs[i]),
                    "entry": float(self.entry[i]),
                    "from_s": float(self.breaks[i]),
                    "to_s": float(self.breaks[i + 1]),
                }
            )
        return out


class GraphGeometry:
    """Exact distances on one metric graph (built once; cheap to query).

    Parameters
    ----------
    n_vertices : int
        ``V``.
    tails, heads : array_like of int, shape (E,)
        Edge ends (vertex indices).
    lengths : array_like of float, shape (E,)
        Edge lengths (metres, > 0).

    Attributes
    ----------
    dv : ndarray, shape (V, V)
        All-pairs vertex distance (metres).
    """

    def __init__(self, n_vertices: int, tails: ArrayLike, heads: ArrayLike, lengths: ArrayLike) -> None:
        self.tails: IntArray = np.asarray(tails, dtype=np.int64)
        self.heads: IntArray = np.asarray(heads, dtype=np.int64)
        self.lengths: FloatArray = np.asarray(lengths, dtype=float)
        if not (self.tails.shape == self.heads.shape == self.lengths.shape) or self.tails.ndim != 1:
            raise InvalidInputError("tails, heads and lengths must be 1-D arrays of one length (E,)")
        self.n_vertices = int(n_vertices)
        self.n_edges = len(self.lengths)
        self.dv: FloatArray = vertex_distance_matrix(self.n_vertices, self.tails, self.heads, self.lengths)
        # python lists for the scalar fast path
        self._t = self.tails.tolist()
        self._h = self.heads.tolist()
        self._L = self.lengths.tolist()
        self._dv = self.dv.tolist()

    @cached_property
    def edges_at(self) -> tuple[list[list[int]], IntArray]:
        """Per vertex, the edges with an end there (in edge order, a loop once), and the vertices' degrees, shape
        (V,) (the edge ends there: a loop counts twice)."""
        at: list[list[int]] = [[] for _ in range(self.n_vertices)]
        for f, (t, h) in enumerate(zip(self._t, self._h)):
            at[t].append(f)
            if h != t:
                at[h].append(f)
        deg = np.bincount(np.concatenate([self.tails, self.heads]), minlength=self.n_vertices)
        return at, deg

    # ---------------------------------------------------------------------------------------- distance
    def distance(self, ea: ArrayLike, sa: ArrayLike, eb: ArrayLike, sb: ArrayLike) -> FloatArray:
        """Exact graph distance between positions ``(ea, sa)`` and ``(eb, sb)`` (broadcast, metres).

        Parameters
        ----------
        ea, eb : array_like of int
            Edge indices.
        sa, sb : array_like of float
            Offsets from the edges' tails (metres).

        Returns
        -------
        ndarray
            Broadcast shape of the inputs.
        """
        ea, sa, eb, sb = np.broadcast_arrays(
            np.asarray(ea, dtype=np.int64), np.asarray(sa, float), np.asarray(eb, dtype=np.int64), np.asarray(sb, float)
        )
        ta, ha, la = self.tails[ea], self.heads[ea], self.lengths[ea]
        tb, hb, lb = self.tails[eb], self.heads[eb], self.lengths[eb]
        dv = self.dv
        ra, qa = sa, la - sa
        rb, qb = sb, lb - sb
        d = np.minimum(
            np.minimum(ra + dv[ta, tb] + rb, ra + dv[ta, hb] + qb),
            np.minimum(qa + dv[ha, tb] + rb, qa + dv[ha, hb] + qb),
        )
        return np.where(ea == eb, np.minimum(d, np.abs(sa - sb)), d)

    def distance_scalar(self, ea: int, sa: float, eb: int, sb: float) -> float:
        """:meth:`distance` for one pair of positions, in plain Python (about 1 µs)."""
        dv = self._dv
        ta, ha, la = self._t[ea], self._h[ea], self._L[ea]
        tb, hb, lb = self._t[eb], self._h[eb], self._L[eb]
        qa, qb = la - sa, lb - sb
        d = min(sa + dv[ta][tb] + sb, sa + dv[ta][hb] + qb, qa + dv[ha][tb] + sb, qa + dv[ha][hb] + qb)
        if ea == eb:
            d = min(d, abs(sa - sb))
        return d

    # ------------------------------------------------------------------------------------------ cells
    def cell_terms(self, e: int, f: int) -> list[tuple[float, float, float]]:
        """The affine terms of the cell ``e × f``.

        Returns
        -------
        list of (ca, cb, c0)
            Four terms; in the cell, ``d(s, t) = min(ca*s + cb*t + c0 over the terms)``, and additionally
            ``min(..., |s - t|)`` when ``e == f`` (not included here). Terms through unreachable vertices have
            ``c0 = inf``.
        """
        dv = self._dv
        ta, ha, la = self._t[e], self._h[e], self._L[e]
        tb, hb, lb = self._t[f], self._h[f], self._L[f]
        return [
            (1.0, 1.0, dv[ta][tb]),
            (1.0, -1.0, dv[ta][hb] + lb),
            (-1.0, 1.0, la + dv[ha][tb]),
            (-1.0, -1.0, la + lb + dv[ha][hb]),
        ]

    def cell_terms_array(self, e: ArrayLike, f: ArrayLike) -> FloatArray:
        """Constant parts ``c0`` of the four terms for arrays of cells. Shape ``e.shape + (4,)``.

        The slopes ``(ca, cb)`` are ``(1, 1), (1, -1), (-1, 1), (-1, -1)`` in that order.
        """
        e, f = np.broadcast_arrays(np.asarray(e, dtype=np.int64), np.asarray(f, dtype=np.int64))
        ta, ha, la = self.tails[e], self.heads[e], self.lengths[e]
        tb, hb, lb = self.tails[f], self.heads[f], self.lengths[f]
        dv = self.dv
        return np.stack([dv[ta, tb], dv[ta, hb] + lb, la + dv[ha, tb], la + lb + dv[ha, hb]], axis=-1)

    def segment_min(self, e: ArrayLike, f: ArrayLike, p0: ArrayLike, p1: ArrayLike) -> FloatArray:
        """Exact minimum of ``d`` along straight moves ``p0 -> p1`` inside cells ``e × f`` (broadcast).

        Parameters
        ----------
        e, f : array_like of int
            Edge of robot A and of robot B (shape ``(...)``).
        p0, p1 : array_like of float, shape (..., 2)
            Ends of the moves in offsets ``(s, t)`` (metres); both must lie in the cell's box.

        Returns
        -------
        ndarray, shape (...)
            ``min over λ ∈ [0, 1] of d(p0 + λ (p1 - p0))`` (metres). Every term is affine in λ, so the minimum is
            at an end, except ``|s - t|`` on one edge, which is 0 when ``s - t`` changes sign.
        """
        p0 = np.asarray(p0, dtype=float)
        p1 = np.asarray(p1, dtype=float)
        e, f = np.broadcast_arrays(np.asarray(e, dtype=np.int64), np.asarray(f, dtype=np.int64))
        d0 = self.distance(e, p0[..., 0], f, p0[..., 1])
        d1 = self.distance(e, p1[..., 0], f, p1[..., 1])
        g0 = p0[..., 0] - p0[..., 1]
        g1 = p1[..., 0] - p1[..., 1]
        cross = (e == f) & (g0 * g1 <= 0.0)
        return np.where(cross, 0.0, np.minimum(d0, d1))

    def segment_min_scalar(self, e: int, f: int, s0: float, t0: float, s1: float, t1: float) -> float:
        """:meth:`segment_min` for one move, in plain Python."""
        if e == f and (s0 - t0) * (s1 - t1) <= 0.0:
            return 0.0
        return min(self.distance_scalar(e, s0, f, t0), self.distance_scalar(e, s1, f, t1))

    # ----------------------------------------------------------------------------------------- routes
    def route_min_distance(self, route_a: DirectedRoute, route_b: DirectedRoute, waypoints: ArrayLike) -> float:
        """Exact minimum separation along a polyline in route coordinates.

        Parameters
        ----------
        route_a, route_b : DirectedRoute
            The robots' routes.
        waypoints : array_like, shape (K, 2)
            Corners ``(r_A, r_B)`` of the polyline in route coordinates (metres), each within its route's length.

        Returns
        -------
        float
            ``min`` of the graph distance over the whole polyline (metres). Each segment is split where either robot
            changes piece; on each sub-segment both robots are on fixed edges with affine offsets, and
            :meth:`segment_min` is exact there.
        """
        w = np.asarray(waypoints, dtype=float)
        if w.ndim != 2 or w.shape[1] != 2 or len(w) < 1:
            raise InvalidInputError(f"waypoints have shape {w.shape}, expected (K, 2) with K >= 1")
        if len(w) == 1:
            ea, sa = route_a.positions(w[0, 0])
            eb, sb = route_b.positions(w[0, 1])
            return self.distance_scalar(int(ea), float(sa), int(eb), float(sb))
        if len(w) == 2:
            return self._segment_route_min(route_a, route_b, w[0].tolist(), w[1].tolist())
        lam_all = []
        for k in range(len(w) - 1):
            a, b = w[k], w[k + 1]
            lams = [0.0, 1.0]
            for j, route in ((0, route_a), (1, route_b)):
                lo, hi = min(a[j], b[j]), max(a[j], b[j])
                if hi > lo:
                    br = route.breaks[(route.breaks > lo) & (route.breaks < hi)]
                    lams.extend(((br - a[j]) / (b[j] - a[j])).tolist())
            lam = np.unique(np.asarray(lams))
            lam_all.append(np.stack([np.full(len(lam) - 1, k), lam[:-1], lam[1:]], axis=1))
        seg = np.concatenate(lam_all)
        seg_k = seg[:, 0].astype(np.int64)
        a, b = w[seg_k], w[seg_k + 1]
        q0 = a + seg[:, 1:2] * (b - a)
        q1 = a + seg[:, 2:3] * (b - a)
        mid = 0.5 * (q0 + q1)
        ia = route_a.piece_index(mid[:, 0])
        ib = route_b.piece_index(mid[:, 1])

        p0 = np.stack([route_a.offsets_on(ia, q0[:, 0]), route_b.offsets_on(ib, q0[:, 1])], axis=1)
        p1 = np.stack([route_a.offsets_on(ia, q1[:, 0]), route_b.offsets_on(ib, q1[:, 1])], axis=1)
        return float(np.min(self.segment_min(route_a.edges[ia], route_b.edges[ib], p0, p1)))

    def _segment_route_min(
        self, route_a: DirectedRoute, route_b: DirectedRoute, a: list[float], b: list[float]
    ) -> float:
        """:meth:`route_min_distance` of one segment ``a -> b`` in plain Python (the same cuts and cells)."""
        lams = [0.0, 1.0]
        for j, route in ((0, route_a), (1, route_b)):
            lo, hi = min(a[j], b[j]), max(a[j], b[j])
            if hi > lo:
                lams.extend((x - a[j]) / (b[j] - a[j]) for x in route.pieces_list[0] if lo < x < hi)
        lams = sorted(set(lams))
        (br_a, e_a, dir_a, en_a), (br_b, e_b, dir_b, en_b) = route_a.pieces_list, route_b.pieces_list
        da, db = b[0] - a[0], b[1] - a[1]
        best = np.inf
        for l0, l1 in itertools.pairwise(lams):
            qa0, qb0, qa1, qb1 = a[0] + l0 * da, a[1] + l0 * db, a[0] + l1 * da, a[1] + l1 * db
            ia, ib = route_a.piece_index_scalar(0.5 * (qa0 + qa1)), route_b.piece_index_scalar(0.5 * (qb0 + qb1))
            d = self.segment_min_scalar(
                e_a[ia],
                e_b[ib],
                en_a[ia] + dir_a[ia] * (qa0 - br_a[ia]),
                en_b[ib] + dir_b[ib] * (qb0 - br_b[ib]),
                en_a[ia] + dir_a[ia] * (qa1 - br_a[ia]),
                en_b[ib] + dir_b[ib] * (qb1 - br_b[ib]),
            )
            best = min(best, d)
        return float(best)


@dataclass(frozen=True, eq=False)
class RouteGeometry:
    """The separation of two robots on their routes as a function of route coordinates ``σ = (σ_A, σ_B)``.

    The plane of route coordinates is cut into *rectangles* at every break of either route (a robot changes
    edge); inside a rectangle each robot's offset is affine in its σ with slope ±1, so the graph distance is the
    minimum of the cell's affine terms (and ``|s - t|`` when both robots are on one edge): piecewise affine in σ.
    This is what trajectory smoothing (cells as half-planes), the verification gate (exact minimum along chords)
    and the benchmark's baselines use, for the paper's tracks (routes from :func:`mpa.routes.directed_route`) and
    for any track graph alike.

    Parameters
    ----------
    geometry : GraphGeometry
    routes : (DirectedRoute, DirectedRoute)
        Route of robot A and of robot B.
    """

    geometry: GraphGeometry
    routes: tuple[DirectedRoute, DirectedRoute]

    @property
    def breaks(self) -> tuple[FloatArray, FloatArray]:
        """Per robot, the route coordinates of its pieces' boundaries (metres)."""
        return self.routes[0].breaks, self.routes[1].breaks

    @property
    def junctions(self) -> tuple[FloatArray, FloatArray]:
        """Per robot, the interior boundaries (where it moves onto another edge or turns back)."""
        return self.routes[0].breaks[1:-1], self.routes[1].breaks[1:-1]

    def positions(self, sigma: ArrayLike) -> tuple[tuple[IntArray, FloatArray], tuple[IntArray, FloatArray]]:
        """``((edge_A, offset_A), (edge_B, offset_B))`` at route coordinates ``σ`` (shape (..., 2))."""
        s = np.asarray(sigma, dtype=float)
        return self.routes[0].positions(s[..., 0]), self.routes[1].positions(s[..., 1])

    def distance(self, sigma: ArrayLike) -> FloatArray:
        """Exact graph distance between the robots at route coordinates ``σ`` (shape (..., 2) -> (...); metres)."""
        (ea, oa), (eb, ob) = self.positions(sigma)
        return self.geometry.distance(ea, oa, eb, ob)

    def polyline_min_distance(self, pts: ArrayLike) -> float:
        """Exact minimum of the distance along the polyline through ``pts`` (shape (n, 2), route coordinates)."""
        p = np.atleast_2d(np.asarray(pts, dtype=float))
        if len(p) == 1:
            return float(self.distance(p)[0])
        return self.geometry.route_min_distance(self.routes[0], self.routes[1], p)

    def segment_min_distances(self, pts: ArrayLike) -> FloatArray:
        """Exact minimum of the distance along every chord of the polyline ``pts`` (shape (n, 2)). Shape (n-1,).

        :meth:`chord_min_distances` of the consecutive points. Continuous in the chord ends.
        """
        p = np.atleast_2d(np.asarray(pts, dtype=float))
        if len(p) < 2:
            return np.zeros(0)
        return self.chord_min_distances(p[:-1], p[1:])

    def chord_min_distances(self, a: ArrayLike, b: ArrayLike) -> FloatArray:
        """Exact minimum of the distance along every chord ``a[k] -> b[k]`` (each shape (n, 2), route coordinates).

        Every chord is cut where either robot changes route piece; on each sub-chord both robots stay on one edge
        with affine offsets and the minimum of ``d`` is at an end of the sub-chord (every term is affine there),
        or 0 where the robots cross on one edge (as :meth:`GraphGeometry.segment_min`). Vectorized over the chords
        and their sub-chords; continuous in the chord ends. Shape (n,).
        """
        a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        if a.ndim < 2 or b.ndim < 2:
            a, b = np.atleast_2d(a), np.atleast_2d(b)
        if len(a) < 1:
            return np.zeros(0)
        return self._chord_min(a, b)

    def _chord_min(self, a: FloatArray, b: FloatArray) -> FloatArray:
        """:meth:`chord_min_distances` of float arrays of shape (n, 2), ``n >= 1`` (no conversions)."""
        n = len(a)
        brk, rob, inner_a, inner_b, n_b = self._interior_breaks
        starts = None
        if len(brk):
            ar = a.take(rob, axis=1)
            d = b.take(rob, axis=1) - ar
            tt = (brk - ar) / np.where(d == 0.0, np.inf, d)  # a chord parallel to a break is not cut (tt = 0)
            cuts = ((tt > 0.0) & (tt < 1.0)).ravel().nonzero()[0]
            if len(cuts):  # sub-chords in order along every chord: [λ_i, λ_i+1] over its cuts
                k_all = np.concatenate([np.arange(n), cuts // len(brk)])
                l_all = np.concatenate([np.zeros(n), tt.take(cuts)])
                order = np.lexsort((l_all, k_all))
                k_all, l_all = k_all.take(order), l_all.take(order)
                first = np.empty(len(k_all), dtype=bool)
                first[0] = True
                np.not_equal(k_all[1:], k_all[:-1], out=first[1:])
                starts = first.nonzero()[0]
                aa = a.T.take(k_all, axis=1)
                q = np.empty((2, 2, len(k_all)))  # (end, robot, sub-chord): both ends of every sub-chord
                np.add(aa, l_all * (b.T.take(k_all, axis=1) - aa), out=q[0])  # (λ = 0: exactly a)
                q[1, :, :-1] = q[0, :, 1:]  # a sub-chord ends where the next one starts, the last of a chord at b
                q[1, :, starts[1:] - 1] = b[:-1]  # (advanced index first: shape (n − 1, 2))
                q[1, :, -1] = b[-1]
        if starts is None:
            q = np.empty((2, 2, n))
            q[0], q[1] = a.T, b.T
        mid = 0.5 * (q[0] + q[1])
        # the rectangle of every sub-chord: the route pieces at its middle (the later one at a break, as
        # piece_index); inside it every term of d is affine in σ (see _cell_terms); its ends are clamped to the
        # rectangle, as positions are to their pieces
        idx = inner_a.searchsorted(mid[0], "right") * n_b + inner_b.searchsorted(mid[1], "right")
        cell = self._cell_terms.take(idx, axis=1)  # (19, S)
        qc = np.minimum(np.maximum(q, cell[15:17]), cell[17:19])  # (2, 2, S)
        v = cell[0:5, None, :] * qc[:, 0] + cell[5:10, None, :] * qc[:, 1] + cell[10:15, None, :]  # (5, 2, S)
        # the fifth term is s − t on one edge (else +inf): d is 0 where it changes sign along the sub-chord, else
        # |s − t| at an end is a term: the minimum of |s − t| is max(min(g0, g1), −max(g0, g1), 0)
        g = v[4]
        gap = np.maximum(np.maximum(np.minimum(g[0], g[1]), -np.maximum(g[0], g[1])), 0.0)
        sub = np.minimum(np.minimum.reduce(v[:4].reshape(8, -1), axis=0), gap)
        if starts is not None:
            return np.asarray(np.minimum.reduceat(sub, starts))
        return np.asarray(sub)

    @cached_property
    def _interior_breaks(self) -> tuple[FloatArray, IntArray, FloatArray, FloatArray, int]:
        """The interior breaks of both routes (route coordinates, metres) and the robot of each (0 or 1); each
        route's interior breaks (``searchsorted(·, σ, "right")`` is the piece index); B's piece count."""
        ba, bb = self.routes[0].breaks[1:-1], self.routes[1].breaks[1:-1]
        robot = np.concatenate([np.zeros(len(ba), np.intp), np.ones(len(bb), np.intp)])
        return np.concatenate([ba, bb]), robot, ba, bb, len(self.routes[1].edges)

    @cached_property
    def _cell_terms(self) -> FloatArray:
        """Every rectangle's terms of ``d`` as affine functions ``gA·σ_A + gB·σ_B + h`` of route coordinates.

        Shape (19, Ma·Mb), column ``ia·Mb + ib`` for route pieces ``(ia, ib)``: ``gA`` (5), ``gB`` (5), ``h`` (5) of
        the four terms of :meth:`GraphGeometry.cell_terms` (``h = inf`` through unreachable vertices) and, fifth,
        of the signed gap ``s − t`` of the offsets where both robots are on one edge (there ``|s − t|`` is a term
        too; elsewhere ``0·σ + inf``); then the rectangle ``σ_A, σ_B`` from and ``σ_A, σ_B`` to.
        """
        ra, rb = self.routes
        oa = ra.entry - ra.dirs * ra.breaks[:-1]  # offset = o + dir·σ on each piece
        ob = rb.entry - rb.dirs * rb.breaks[:-1]
        da, db = ra.dirs.astype(float)[:, None, None], rb.dirs.astype(float)[None, :, None]
        c0 = self._cell_constants()  # (Ma, Mb, 4)
        ca, cb = np.array([1.0, 1.0, -1.0, -1.0]), np.array([1.0, -1.0, 1.0, -1.0])
        out = np.empty((*c0.shape[:2], 19))
        out[..., 0:4], out[..., 5:9] = ca * da, cb * db
        out[..., 10:14] = c0 + ca * oa[:, None, None] + cb * ob[None, :, None]
        same = ra.edges[:, None] == rb.edges[None, :]  # both robots on one edge: |s − t| is a term too
        out[..., 4], out[..., 9] = np.where(same, da[..., 0], 0.0), np.where(same, -db[..., 0], 0.0)
        out[..., 14] = np.where(same, oa[:, None] - ob[None, :], np.inf)
        out[..., 15], out[..., 17] = ra.breaks[:-1, None], ra.breaks[1:, None]
        out[..., 16], out[..., 18] = rb.breaks[None, :-1], rb.breaks[None, 1:]
        return np.ascontiguousarray(out.reshape(-1, 19).T)

    def _cell_constants(self) -> FloatArray:
        """:meth:`GraphGeometry.cell_terms_array` of every pair of route pieces, shape (Ma, Mb, 4) (the same
        values, gathered from the flat vertex distances)."""
        geo = self.geometry
        ea, eb = self.routes[0].edges, self.routes[1].edges
        nv = geo.dv.shape[1]
        dv = geo.dv.ravel()
        ta, ha = geo.tails.take(ea)[:, None] * nv, geo.heads.take(ea)[:, None] * nv
        tb, hb = geo.tails.take(eb)[None, :], geo.heads.take(eb)[None, :]
        la, lb = geo.lengths.take(ea)[:, None], geo.lengths.take(eb)[None, :]
        c0 = np.empty((len(ea), len(eb), 4))
        c0[..., 0] = dv.take(ta + tb)
        c0[..., 1] = dv.take(ta + hb) + lb
        c0[..., 2] = la + dv.take(ha + tb)
        c0[..., 3] = la + lb + dv.take(ha + hb)
        return c0

    def interval(self, robot: int, sigma: ArrayLike) -> IntArray:
        """Index of the route piece of ``robot`` that holds ``σ`` (the later one at a break)."""
        return self.routes[robot].piece_index(sigma)

    def box(self, ia: int, ib: int) -> FloatArray:
        """The rectangle ``[[σA_lo, σA_hi], [σB_lo, σB_hi]]`` of pieces ``(ia, ib)``."""
        ba, bb = self.breaks
        return np.array([[ba[ia], ba[ia + 1]], [bb[ib], bb[ib + 1]]])

    def cell_rows(self, mid: ArrayLike) -> tuple[tuple[int, int], list[tuple[float, float, float]]]:
        """The convex cell of the free set that contains the point ``mid`` (route coordinates).

        Returns
        -------
        (ia, ib) : tuple of int
            The rectangle (route piece of each robot).
        rows : list of (gA, gB, h)
            Half-planes ``gA·σ_A + gB·σ_B + h >= D`` whose intersection with the rectangle is the convex piece
            of ``{d >= D}`` holding ``mid`` (the cell's finite affine terms, and the side of ``s = t`` on one edge).
        """
        m = np.asarray(mid, dtype=float)
        ra, rb = self.routes
        ia, ib = int(ra.piece_index(m[0])), int(rb.piece_index(m[1]))
        ea, eb = int(ra.edges[ia]), int(rb.edges[ib])
        # offset = o0 + dr·σ on each piece
        da, db = float(ra.dirs[ia]), float(rb.dirs[ib])
        oa0, ob0 = float(ra.entry[ia] - da * ra.breaks[ia]), float(rb.entry[ib] - db * rb.breaks[ib])
        rows = [
            (ca * da, cb * db, c0 + ca * oa0 + cb * ob0)
            for ca, cb, c0 in self.geometry.cell_terms(ea, eb)
            if np.isfinite(c0)
        ]
        if ea == eb:
            sg = 1.0 if (oa0 + da * m[0]) - (ob0 + db * m[1]) >= 0 else -1.0
            rows.append((sg * da, -sg * db, sg * (oa0 - ob0)))
        return (ia, ib), rows
