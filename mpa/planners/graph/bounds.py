"""A lower bound on the cost to the goal that knows the robots must pass each other: distances in the faces' graph.

The search's own bound at a configuration is each robot's exact distance to its goal alone, combined by the
objective's cost (``max(dA/vA, dB/vB)`` plus the tie-break terms, or ``hypot(dA, dB)``). It ignores the other robot,
so on a swap or a crossing (one robot must step aside at a branch while the other passes) every configuration whose
two distances are small enough looks promising and the search expands them all before the goal.

:class:`FaceBound` relaxes the free space instead of the other robot. Every path of the free space that goes from one
free polygon to another crosses a *face* (one robot on a vertex, the other on an edge, in the free interval
``[lo, hi]`` of its offsets) or a *corner* (both on vertices). The faces' graph has one node per face and per free
corner; inside each free polygon its sides (faces) are joined by the objective's cost of the least displacement
between them (two axis-parallel segments: per robot the gap between its two ranges), and a corner is joined to the
faces it lies on at cost 0. A path of the free space crosses a chain of faces and corners, and its piece inside a
polygon costs at least the least displacement between the two sides it joins (the cost is a norm of the
displacement), so the Dijkstra distance ``H(F)`` from the goal in this graph is at most the cost of every path from
a point of ``F`` to the goal: an admissible bound. Unlike the robots' distances alone it cannot leave out the
side-step: a robot that gives way must reach a branch's face while the other robot's faces on the shared corridor
are blocked by the clearance.

The graph's shape and the displacements are built once per free space (:func:`face_graph`, cached with it); a query
weighs them with its speeds and objective and runs one Dijkstra (``scipy.sparse.csgraph``) from the goal.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import cast

import numpy as np
from numpy.typing import NDArray

from mpa.freespace import FreeSpace, PolygonId
from mpa.graph_track import Position
from mpa.planners.graph.base import TIE_BREAK, TIE_BREAK_2, FaceKey, FloatArray, Key
from mpa.planners.graph.mesh import _Mesh

__all__ = ["BOUND_SAFETY", "UNREACHABLE", "FaceBound", "FaceGraph", "face_graph"]

#: The face bound is scaled by ``1 - BOUND_SAFETY`` so that rounding in the Dijkstra sums never lifts it above a
#: motion's cost (the search's order is on a grid of ``F_GRID = 1e-12`` of the start's bound).
BOUND_SAFETY = 1e-10

#: A bound standing for "the goal cannot be reached from here" (finite, so that the search's queue key stays an int).
UNREACHABLE = 1e200


@dataclass(frozen=True)
class FaceGraph:
    """The faces' graph of one free space, without weights (they depend on the query's speeds and objective).

    Attributes
    ----------
    node_of : dict
        Compact node number of each face ``(axis, vertex, other edge)`` and corner ``("C", vertex A, vertex B)``.
    n_nodes : int
        Faces and corners; node ``n_nodes`` is the goal's (added per query).
    indptr, indices : ndarray of int, shapes (n_nodes + 1,) and (M,)
        The joins in compressed rows (both directions of each; a pair of faces joined in several polygons keeps
        every join, and Dijkstra takes the cheapest).
    ds, dt : ndarray of float, shape (M,)
        Least displacement of robot A and of robot B along each join (metres; 0 for a corner's joins).
    """

    node_of: dict[Key, int]
    n_nodes: int
    indptr: NDArray[np.int64]
    indices: NDArray[np.int64]
    ds: FloatArray
    dt: FloatArray


def _gap(lo0: FloatArray, hi0: FloatArray, lo1: FloatArray, hi1: FloatArray) -> FloatArray:
    """Distance between the intervals ``[lo0, hi0]`` and ``[lo1, hi1]`` (0 when they meet), elementwise."""
    return np.maximum(0.0, np.maximum(lo0 - hi1, lo1 - hi0))


def _build(fs: FreeSpace) -> FaceGraph:
    g = fs.geometry
    n_e, n_v = g.n_edges, g.n_vertices
    pe, pf, pk = fs._pe, fs._pf, fs._pk
    lengths, tails, heads = g.lengths, g.tails, g.heads
    lo, hi, ok = fs.faces.lo, fs.faces.hi, fs.faces.ok
    same = pe == pf
    n_a = n_v * n_e  # raw numbers: A's faces w * E + f, then B's faces n_a + e * V + w, then corners
    n_f = 2 * n_a
    # the polygons' sides as in FreeSpace._components: A on the tail / head of e, B on the tail / head of f;
    # per side (robot on the vertex, active, raw face number, fixed coordinate, free range of the other robot)
    zero = np.zeros(len(pe))
    sides = []
    for w, val, use in ((tails[pe], zero, ~same | (pk == 1)), (heads[pe], lengths[pe], ~same | (pk == 0))):
        sides.append((0, use & ok[w, pf], w * n_e + pf, val, lo[w, pf], hi[w, pf]))
    for w, val, use in ((tails[pf], zero, ~same | (pk == 0)), (heads[pf], lengths[pf], ~same | (pk == 1))):
        sides.append((1, use & ok[w, pe], n_a + pe * n_v + w, val, lo[w, pe], hi[w, pe]))
    rows, cols, dss, dts = [], [], [], []
    for i in range(4):
        for j in range(i + 1, 4):
            ax_i, act_i, id_i, v_i, lo_i, hi_i = sides[i]
            ax_j, act_j, id_j, v_j, lo_j, hi_j = sides[j]
            m = act_i & act_j
            if ax_i == ax_j:  # two sides of one robot: it crosses the cell, the other closes the ranges' gap
                fixed = np.abs(v_i[m] - v_j[m])
                free = _gap(lo_i[m], hi_i[m], lo_j[m], hi_j[m])
                ds, dt = (fixed, free) if ax_i == 0 else (free, fixed)
            else:  # side i is A's (s = v_i, t in [lo_i, hi_i]), side j is B's (t = v_j, s in [lo_j, hi_j])
                ds = _gap(v_i[m], v_i[m], lo_j[m], hi_j[m])
                dt = _gap(v_j[m], v_j[m], lo_i[m], hi_i[m])
            rows.append(id_i[m])
            cols.append(id_j[m])
            dss.append(ds)
            dts.append(dt)
    # a free corner on the faces holding it (cost 0): A's face (w, f) holds corner (w, tail f) when its range starts
    # at 0 and (w, head f) when it ends at L_f; B's face (w, e) holds (tail e, w) and (head e, w) the same way
    w_o, x_o = np.nonzero(ok)
    for at_end, end in ((lo[w_o, x_o] == 0.0, tails[x_o]), (hi[w_o, x_o] == lengths[x_o], heads[x_o])):
        for face, corner in ((w_o * n_e + x_o, n_f + w_o * n_v + end), (n_a + x_o * n_v + w_o, n_f + end * n_v + w_o)):
            rows.append(face[at_end])
            cols.append(corner[at_end])
            dss.append(np.zeros(int(at_end.sum())))
            dts.append(dss[-1])
    r = np.concatenate(rows).astype(np.int64)
    c = np.concatenate(cols).astype(np.int64)
    ds = np.concatenate(dss)
    dt = np.concatenate(dts)
    used, inv = np.unique(np.concatenate([r, c]), return_inverse=True)
    n = len(used)
    src = np.concatenate([inv[: len(r)], inv[len(r) :]])
    dst = np.concatenate([inv[len(r) :], inv[: len(r)]])
    order = np.argsort(src, kind="stable")
    indptr = np.zeros(n + 2, dtype=np.int64)  # the goal's row (n) is empty here; its joins are appended per query
    np.cumsum(np.bincount(src, minlength=n + 1), out=indptr[1:])
    node_of: dict[Key, int] = {}
    for k, raw in enumerate(used.tolist()):
        if raw < n_a:
            node_of[(0, raw // n_e, raw % n_e)] = k
        elif raw < n_f:
            x = raw - n_a
            node_of[(1, x % n_v, x // n_v)] = k
        else:
            x = raw - n_f
            node_of[("C", x // n_v, x % n_v)] = k
    return FaceGraph(
        node_of=node_of,
        n_nodes=n,
        indptr=indptr,
        indices=dst[order].astype(np.int64),
        ds=np.concatenate([ds, ds])[order],
        dt=np.concatenate([dt, dt])[order],
    )


def face_graph(fs: FreeSpace) -> FaceGraph:
    """The faces' graph of a free space, built on first use and kept with it."""
    fg = getattr(fs, "_face_graph", None)
    if fg is None:
        fg = _build(fs)
        fs._face_graph = fg  # type: ignore[attr-defined]
    return cast("FaceGraph", fg)


def _dist(y: float, lo: float, hi: float) -> float:
    """Distance from ``y`` to the interval ``[lo, hi]`` (metres)."""
    return lo - y if y < lo else (y - hi if y > hi else 0.0)


def _side_cost(
    comb: Callable[[float, float], float], ax: int, a: float, lo: float, hi: float, s: float, t: float
) -> float:
    """The cost of the least displacement from ``(s, t)`` to the side ``ax = a`` whose other coordinate is in
    ``[lo, hi]``."""
    if ax == 0:
        return comb(abs(s - a), _dist(t, lo, hi))
    return comb(_dist(s, lo, hi), abs(t - a))


class FaceBound:
    """The faces' graph distances to one query's goal, and the bounds the search asks for.

    Parameters
    ----------
    mesh : _Mesh
        The free space as the search sees it.
    goal : (Position, Position)
        The goal ``(robot A, robot B)``.
    objective : {"fastest", "shortest"}
        The search's cost: ``max(tA, tB)`` plus the tie-break terms (``tX = |dX| / vX``, s), or ``hypot(dA, dB)`` (m).
    va, vb : float
        The speed limits (m/s).

    Attributes
    ----------
    h : ndarray of float, shape (n_nodes,)
        ``H`` per face and corner node (the search's cost units); :data:`UNREACHABLE` where the goal is not reached.
    """

    def __init__(self, mesh: _Mesh, goal: tuple[Position, Position], objective: str, va: float, vb: float) -> None:
        from scipy.sparse import csr_matrix
        from scipy.sparse.csgraph import dijkstra

        self.mesh = mesh
        if objective == "shortest":

            def comb(xa: float, xb: float) -> float:
                return math.hypot(xa, xb)

        else:

            def comb(xa: float, xb: float) -> float:
                ta, tb_ = xa / va, xb / vb
                return max(ta, tb_) + TIE_BREAK * (ta + tb_) + TIE_BREAK_2 * math.hypot(ta, tb_)

        self.comb = comb
        fg = face_graph(mesh.fs)
        self.node_of = fg.node_of
        self.goal_at: dict[PolygonId, list[tuple[float, float]]] = {}
        for pid, c in mesh.placements(*goal):
            self.goal_at.setdefault(pid, []).append(c)
        if objective == "shortest":
            w = np.hypot(fg.ds, fg.dt)
        else:
            ta, tb = fg.ds / va, fg.dt / vb
            w = np.maximum(ta, tb) + TIE_BREAK * (ta + tb) + TIE_BREAK_2 * np.hypot(ta, tb)
        g_cols, g_w = [], []
        for pid, pts in self.goal_at.items():
            for pt in pts:
                for ax, a, face, lo, hi in mesh.sides(pid):
                    node = fg.node_of.get(face)
                    if node is not None:
                        g_cols.append(node)
                        g_w.append(_side_cost(comb, ax, a, lo, hi, pt[0], pt[1]))
        n = fg.n_nodes + 1
        indptr = fg.indptr.copy()
        indptr[-1] += len(g_cols)
        # explicit zeros are edges of weight 0 for csgraph, and of repeated entries Dijkstra takes the cheapest
        graph = csr_matrix(
            (
                np.concatenate([w, np.asarray(g_w, dtype=float)]),
                np.concatenate([fg.indices, np.asarray(g_cols, dtype=np.int64)]),
                indptr,
            ),
            shape=(n, n),
        )
        dist = dijkstra(graph, directed=True, indices=fg.n_nodes)[: fg.n_nodes]
        self.h = np.where(np.isfinite(dist), dist * (1.0 - BOUND_SAFETY), UNREACHABLE)
        self._h = self.h.tolist()
        self._points: dict[Key, float] = {}

    def face(self, face: FaceKey) -> float:
        """``H`` of a face (the search's cost units)."""
        node = self.node_of.get(face)
        return UNREACHABLE if node is None else self._h[node]

    def point(self, key: Key) -> float:
        """A lower bound on the cost from the point named ``key`` (a face end or corner of the search) to the goal:
        the least over the polygons holding it of the way to the goal inside the polygon or through one of its
        sides."""
        out = self._points.get(key)
        if out is None:
            out = UNREACHABLE
            comb = self.comb
            for pid, (s, t) in self.mesh.members(key):
                for pt in self.goal_at.get(pid, ()):
                    out = min(out, comb(abs(pt[0] - s), abs(pt[1] - t)))
                for ax, a, face, lo, hi in self.mesh.sides(pid):
                    hf = self.face(face)
                    if hf >= out:
                        continue
                    out = min(out, _side_cost(comb, ax, a, lo, hi, s, t) * (1.0 - BOUND_SAFETY) + hf)
            self._points[key] = out
        return out

    def interval(self, face: FaceKey, ax: int, a: float, r: tuple[float, float], y0: float, y1: float) -> float:
        """A lower bound on the cost from the root ``r`` (in the page's frame) through the part ``[y0, y1]`` of the
        face ``face`` (side ``ax = a``) to the goal."""
        return _side_cost(self.comb, ax, a, y0, y1, r[0], r[1]) * (1.0 - BOUND_SAFETY) + self.face(face)
