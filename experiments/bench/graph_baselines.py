"""Baselines on any track graph: an exact-edge grid search and an OMPL pipeline, at the plan level.

Both work on a :class:`mpa.GraphTrack` with clearance ``D`` and speed limits ``(vA, vB)``, use the one module of
exact geometry (:class:`mpa.geometry.GraphGeometry`: graph distance and ``segment_min``) and return a
:class:`GraphPath`: a polyline of joint positions whose every leg keeps ``>= D`` exactly, timed at the speed limits
(each leg takes ``max(LA/vA, LB/vB)``, ``L`` the distance a robot travels on it; both robots move at constant speed
along a leg, so a leg is straight in the robots' route coordinates, like the segments of
:class:`mpa.planners.graph.GraphPlan`).

Grid (:class:`GraphGrid`). Each robot's positions are discretised along every edge with step ``<= h`` (an edge of
length ``L`` gets ``ceil(L/h)`` equal pieces; vertices are shared nodes, so a robot on a vertex may step onto any
incident edge). Joint states are node pairs at least ``D`` apart (exact graph distance). A move takes one robot or
both to a neighbouring node; it is kept only if the straight move keeps ``>= D`` exactly (``segment_min`` in the cell
of the two edges used). Cost ``max(|Δs|/vA, |Δt|/vB)``: time with speed limits. The joint graph is built once per
(layout, ``D``, ``h``), vectorised with numpy; a query adds its start (joined to the up to four grid states around it
by straight moves inside its cell) and reads the goal off the up to four grid states around it; Dijkstra is
:func:`scipy.sparse.csgraph.dijkstra` (scipy comes with toppra) from the start over the whole joint graph. The
result is the optimum *of the grid*, an upper bound of the true optimum that converges as ``h -> 0`` (for
``vA == vB``; with unequal speeds king moves do not represent every direction at its L∞ cost).

OMPL (:class:`GraphOmpl`, ``ompl`` 2.x Python bindings). What a careful user writes for a graph without writing a
new state space in C++: a ``RealVectorStateSpace(2)`` whose coordinates are each robot's *global arc coordinate*
``x ∈ [0, total length]`` (the edges laid end to end in layout order; ``x`` maps to ``(edge, offset)``). A straight
line in these coordinates means nothing on a graph, so the motion between two states is defined by the user: each
robot moves along a shortest path *of the graph* (its geodesic) from its first to its second position, both at
constant speed in one leg; a Python :class:`ompl.base.MotionValidator` checks that leg exactly (split where a robot
changes edge, ``segment_min`` on every piece) and a Python validity checker checks ``d >= D``. ``RRTConnect`` with a
time budget per query and range = the space's maximum extent (its new states are then OMPL's random samples; with
the default range 0.2 × extent a new state is a meaningless point on the coordinate line); then OMPL's
``PathSimplifier.reduceVertices`` and ``collapseCloseVertices`` (they only call the motion validator).
``partialShortcutPath``, ``shortcutPath`` and ``smoothBSpline`` interpolate states in the coordinates and are not
used (their new states would join by geodesics that the simplifier did not check in the same way). OMPL's own
``RealVectorStateSpace`` distance (Euclidean in arc coordinates) guides its nearest neighbours; a graph-aware
distance would need a C++ state space. Seeded per query with :func:`ompl.util.RNG.setSeed`.
"""

from __future__ import annotations

import itertools
import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from bench.ompl_tools import joint_state_space, simplify_vertices
from mpa.graph_track import GraphTrack

__all__ = ["Geodesics", "GraphGrid", "GraphOmpl", "GraphPath", "GridGraphResult", "OmplGraphResult"]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
#: A robot's piece of a leg: (edge, offset at the start, offset at the end).
Piece = tuple[int, float, float]


# ------------------------------------------------------------------------------------------------ paths
@dataclass(frozen=True)
class GraphPath:
    """A joint path on a graph: legs of simultaneous constant-speed motion, each robot along given pieces.

    Attributes
    ----------
    legs : list of (pieces A, pieces B)
        Each robot's pieces ``(edge, offset0, offset1)`` of one leg (consecutive pieces join at vertices).
    durations : ndarray, shape (L,)
        Time of each leg at the speed limits (s): ``max(LA/vA, LB/vB)``.
    """

    legs: list[tuple[list[Piece], list[Piece]]]
    durations: FloatArray

    @property
    def makespan(self) -> float:
        """Total time at the speed limits (s)."""
        return float(self.durations.sum())

    def positions(self, u: FloatArray) -> tuple[IntArray, FloatArray, IntArray, FloatArray]:
        """Positions ``(eA, sA, eB, sB)`` at normalised times ``u ∈ [0, 1]`` (arrays of the shape of ``u``)."""
        u = np.clip(np.asarray(u, dtype=float), 0.0, 1.0)
        T = self.makespan
        cum = np.concatenate([[0.0], np.cumsum(self.durations)])
        out = [
            np.zeros(u.shape, dtype=np.int64),
            np.zeros(u.shape),
            np.zeros(u.shape, dtype=np.int64),
            np.zeros(u.shape),
        ]
        for idx in np.ndindex(u.shape):
            tau = u[idx] * T
            k = int(np.clip(np.searchsorted(cum, tau, side="right") - 1, 0, len(self.legs) - 1)) if self.legs else 0
            lam = (tau - cum[k]) / self.durations[k] if self.legs and self.durations[k] > 0 else 1.0
            lam = min(max(lam, 0.0), 1.0)
            for r in (0, 1):
                e, s = _at(self.legs[k][r], lam)
                out[2 * r][idx] = e
                out[2 * r + 1][idx] = s
        return out[0], out[1], out[2], out[3]

    def cells(self, n: int = 2001) -> list[tuple[int, int, int]]:
        """Cells ``(eA, eB, k)`` along the path sampled at ``n`` normalised times (``k`` orders robots on one edge)."""
        ea, sa, eb, sb = self.positions(np.linspace(0.0, 1.0, n))
        return [(int(a), int(b), 0 if a != b or x > y else 1) for a, x, b, y in zip(ea, sa, eb, sb)]


def _at(pieces: list[Piece], lam: float) -> tuple[int, float]:
    """Position at fraction ``lam`` of a robot's leg (constant speed along its pieces)."""
    lens = [abs(p[2] - p[1]) for p in pieces]
    total = sum(lens)
    if total <= 0.0:
        return pieces[-1][0], pieces[-1][2]
    r = lam * total
    for i, ((e, a, b), ln) in enumerate(zip(pieces, lens)):
        if r <= ln or i == len(pieces) - 1:
            f = min(r / ln, 1.0) if ln > 0 else 1.0
            return e, a + f * (b - a)
        r -= ln
    return pieces[-1][0], pieces[-1][2]


def leg_min_distance(track: GraphTrack, pa: list[Piece], pb: list[Piece]) -> float:
    """Exact minimum graph distance along a leg (both robots at constant speed along their pieces; metres)."""
    g = track.geometry
    la = [abs(p[2] - p[1]) for p in pa]
    lb = [abs(p[2] - p[1]) for p in pb]
    ta, tb = sum(la), sum(lb)
    ca = np.concatenate([[0.0], np.cumsum(la)]) / ta if ta > 0 else np.array([0.0, 1.0])
    cb = np.concatenate([[0.0], np.cumsum(lb)]) / tb if tb > 0 else np.array([0.0, 1.0])
    if ta <= 0:
        pa, ca = [pa[-1]], np.array([0.0, 1.0])
    if tb <= 0:
        pb, cb = [pb[-1]], np.array([0.0, 1.0])
    lams = np.unique(np.concatenate([ca, cb]))
    best = math.inf
    for l0, l1 in itertools.pairwise(lams):
        if l1 <= l0:
            continue
        m = 0.5 * (l0 + l1)
        i = min(int(np.searchsorted(ca, m, side="right")) - 1, len(pa) - 1)
        j = min(int(np.searchsorted(cb, m, side="right")) - 1, len(pb) - 1)
        ea, a0, a1 = pa[i]
        eb, b0, b1 = pb[j]

        def off(p0: float, p1: float, c: FloatArray, k: int, lam: float) -> float:
            w = c[k + 1] - c[k]
            return p0 + (p1 - p0) * ((lam - c[k]) / w if w > 0 else 0.0)

        d = g.segment_min_scalar(
            ea, eb, off(a0, a1, ca, i, l0), off(b0, b1, cb, j, l0), off(a0, a1, ca, i, l1), off(b0, b1, cb, j, l1)
        )
        best = min(best, float(d))
    return best


# -------------------------------------------------------------------------------------------- geodesics
class Geodesics:
    """Shortest paths of one robot on a graph track, as pieces ``(edge, offset0, offset1)``."""

    def __init__(self, track: GraphTrack) -> None:
        self.track = track
        g = track.geometry
        self.g = g
        V = g.n_vertices
        dv = g._dv
        tol = 1e-12 * max(1.0, float(track.total_length))
        # next edge from u towards b: (edge, entry offset, exit offset, next vertex)
        self.next: list[list[tuple[int, float, float, int] | None]] = [[None] * V for _ in range(V)]
        inc: list[list[tuple[int, float, float, int]]] = [[] for _ in range(V)]
        for e in range(g.n_edges):
            u, w, L = g._t[e], g._h[e], g._L[e]
            if u == w:
                continue
            inc[u].append((e, 0.0, L, w))
            inc[w].append((e, L, 0.0, u))
        for u in range(V):
            for b in range(V):
                if u == b or not math.isfinite(dv[u][b]):
                    continue
                for e, o0, o1, w in inc[u]:
                    if abs(abs(o1 - o0) + dv[w][b] - dv[u][b]) <= tol:
                        self.next[u][b] = (e, o0, o1, w)
                        break

    def vertex_path(self, a: int, b: int) -> list[Piece]:
        """Pieces of a shortest path from vertex ``a`` to vertex ``b``."""
        out: list[Piece] = []
        u = a
        while u != b:
            nx = self.next[u][b]
            assert nx is not None, "vertices in different components"
            out.append((nx[0], nx[1], nx[2]))
            u = nx[3]
        return out

    def path(self, e: int, s: float, f: int, t: float) -> list[Piece]:
        """Pieces of a shortest path from ``(e, s)`` to ``(f, t)`` (one piece of length 0 if they coincide)."""
        g = self.g
        dv = g._dv
        best = (abs(s - t), None, None) if e == f else (math.inf, None, None)
        ends_e = ((g._t[e], 0.0), (g._h[e], g._L[e]))
        ends_f = ((g._t[f], 0.0), (g._h[f], g._L[f]))
        for a, oa in ends_e:
            for b, ob in ends_f:
                c = abs(s - oa) + dv[a][b] + abs(t - ob)
                if c < best[0] - 1e-15:
                    best = (c, (a, oa), (b, ob))
        if best[1] is None:
            return [(e, s, t)]
        (a, oa), (b, ob) = best[1], best[2]  # type: ignore[misc]
        out: list[Piece] = []
        if oa != s:
            out.append((e, s, oa))
        out += self.vertex_path(a, b)
        if ob != t:
            out.append((f, ob, t))
        return out or [(e, s, s)]


def _length(pieces: list[Piece]) -> float:
    return sum(abs(p[2] - p[1]) for p in pieces)


# --------------------------------------------------------------------------------------------------- grid
@dataclass
class GridGraphResult:
    """Outcome of one grid query: ``solved``, ``path`` (or None), ``makespan`` (s), ``compute_time`` (s)."""

    solved: bool
    path: GraphPath | None
    makespan: float
    compute_time: float
    stats: dict[str, Any] = field(default_factory=dict)


class GraphGrid:
    """Exact-edge grid search on a graph layout's configuration space (see the module docstring).

    Parameters
    ----------
    track : GraphTrack
    clearance : float
        D (metres): states and moves keep the graph distance ``>= D`` (up to ``1e-12 · max(1, total length)``).
    h : float
        Largest grid step along an edge (metres).
    speeds : (float, float)
        Speed limits (m/s).
    """

    def __init__(self, track: GraphTrack, clearance: float, h: float, speeds: tuple[float, float] = (1.0, 1.0)):
        import scipy.sparse as sp

        t0 = time.perf_counter()
        self.track = track
        self.D = float(clearance)
        self.h = float(h)
        self.speeds = (float(speeds[0]), float(speeds[1]))
        g = track.geometry
        self.tol = 1e-12 * max(1.0, float(track.total_length))
        V, E = g.n_vertices, g.n_edges
        node_e: list[int] = []
        node_s: list[float] = []
        for v in range(V):  # canonical position of a vertex: its lowest-indexed incident edge
            for e in range(E):
                if g._t[e] == v:
                    node_e.append(e), node_s.append(0.0)
                    break
                if g._h[e] == v:
                    node_e.append(e), node_s.append(g._L[e])
                    break
        self.edge_nodes: list[list[int]] = []  # node ids along each edge, tail to head
        self._steps: dict[tuple[int, int], Piece] = {}
        self.edge_offs: list[FloatArray] = []
        step_src, step_dst, step_e, step_o0, step_o1 = [], [], [], [], []
        for e in range(E):
            L = g._L[e]
            n = max(1, math.ceil(L / self.h - 1e-9))
            offs = np.linspace(0.0, L, n + 1)
            ids = [g._t[e]]
            for k in range(1, n):
                ids.append(len(node_e))
                node_e.append(e)
                node_s.append(float(offs[k]))
            ids.append(g._h[e])
            self.edge_nodes.append(ids)
            self.edge_offs.append(offs)
            for k in range(n):
                for a, b in ((k, k + 1), (k + 1, k)):
                    step_src.append(ids[a]), step_dst.append(ids[b]), step_e.append(e)
                    step_o0.append(offs[a]), step_o1.append(offs[b])
                    self._steps.setdefault((ids[a], ids[b]), (e, float(offs[a]), float(offs[b])))
        self.node_e = np.array(node_e, dtype=np.int64)
        self.node_s = np.array(node_s, dtype=float)
        N = self.N = len(node_e)
        src, dst = np.array(step_src), np.array(step_dst)
        se, so0, so1 = np.array(step_e), np.array(step_o0), np.array(step_o1)
        # free states (N, N)
        dist = g.distance(self.node_e[:, None], self.node_s[:, None], self.node_e[None, :], self.node_s[None, :])
        self.free = dist >= self.D - self.tol
        va, vb = self.speeds
        rows, cols, costs = [], [], []
        M = len(src)
        # A steps, B stays; B steps, A stays; both step (chunked over A's steps)
        stay_e, stay_s = self.node_e, self.node_s
        for robot in (0, 1):
            for c0 in range(0, M, 256):
                k = np.arange(c0, min(M, c0 + 256))[:, None]
                j = np.arange(N)[None, :]
                k, j = np.broadcast_arrays(k, j)
                if robot == 0:
                    ia0, ia1, ib0, ib1 = src[k], dst[k], j, j
                    ea, eb = se[k], stay_e[j]
                    p0 = np.stack([so0[k], stay_s[j]], -1)
                    p1 = np.stack([so1[k], stay_s[j]], -1)
                    cost = np.abs(so1[k] - so0[k]) / va
                else:
                    ia0, ia1, ib0, ib1 = j, j, src[k], dst[k]
                    ea, eb = stay_e[j], se[k]
                    p0 = np.stack([stay_s[j], so0[k]], -1)
                    p1 = np.stack([stay_s[j], so1[k]], -1)
                    cost = np.abs(so1[k] - so0[k]) / vb
                ok = self.free[ia0, ib0] & self.free[ia1, ib1]
                if not ok.any():
                    continue
                m = g.segment_min(ea[ok], eb[ok], p0[ok], p1[ok]) >= self.D - self.tol
                rows.append((ia0[ok] * N + ib0[ok])[m])
                cols.append((ia1[ok] * N + ib1[ok])[m])
                costs.append(cost[ok][m])
        for c0 in range(0, M, 256):
            ka = np.arange(c0, min(M, c0 + 256))[:, None]
            kb = np.arange(M)[None, :]
            ka, kb = np.broadcast_arrays(ka, kb)
            ok = self.free[src[ka], src[kb]] & self.free[dst[ka], dst[kb]]
            if not ok.any():
                continue
            ka, kb = ka[ok], kb[ok]
            p0 = np.stack([so0[ka], so0[kb]], -1)
            p1 = np.stack([so1[ka], so1[kb]], -1)
            m = g.segment_min(se[ka], se[kb], p0, p1) >= self.D - self.tol
            ka, kb = ka[m], kb[m]
            rows.append(src[ka] * N + src[kb])
            cols.append(dst[ka] * N + dst[kb])
            costs.append(np.maximum(np.abs(so1[ka] - so0[ka]) / va, np.abs(so1[kb] - so0[kb]) / vb))
        r = np.concatenate(rows) if rows else np.zeros(0, dtype=np.int64)
        c = np.concatenate(cols) if cols else np.zeros(0, dtype=np.int64)
        w = np.concatenate(costs) if costs else np.zeros(0)
        S = N * N
        # one extra row/column (index S) for a query's start, filled per query
        self.adj = sp.csr_matrix((w + 1e-12, (r, c)), shape=(S + 1, S + 1))
        self.adj.sort_indices()
        self.n_states = int(self.free.sum())
        self.n_moves = len(w)
        self.build_time = time.perf_counter() - t0

    def _brackets(self, e: int, s: float) -> list[tuple[int, float]]:
        """Grid nodes of edge ``e`` around offset ``s``: ``(node, offset on e)`` (one if ``s`` is a node)."""
        offs = self.edge_offs[e]
        ids = self.edge_nodes[e]
        k = int(np.clip(np.searchsorted(offs, s, side="right") - 1, 0, len(offs) - 2))
        if abs(s - offs[k]) <= 1e-12 * max(1.0, offs[-1]):
            return [(ids[k], float(offs[k]))]
        if abs(s - offs[k + 1]) <= 1e-12 * max(1.0, offs[-1]):
            return [(ids[k + 1], float(offs[k + 1]))]
        return [(ids[k], float(offs[k])), (ids[k + 1], float(offs[k + 1]))]

    def _attach(self, pa: tuple[int, float], pb: tuple[int, float]) -> list[tuple[int, float, float, float]]:
        """Grid states joined to the configuration by a free straight move: ``(state, cost, offset A, offset B)``."""
        g = self.track.geometry
        va, vb = self.speeds
        out = []
        for na, oa in self._brackets(*pa):
            for nb, ob in self._brackets(*pb):
                if not self.free[na, nb]:
                    continue
                if g.segment_min_scalar(pa[0], pb[0], pa[1], pb[1], oa, ob) >= self.D - self.tol:
                    out.append((na * self.N + nb, max(abs(oa - pa[1]) / va, abs(ob - pb[1]) / vb), oa, ob))
        return out

    def solve(self, start: tuple[tuple[int, float], tuple[int, float]], goal: Any) -> GridGraphResult:
        """Fastest grid path from ``start`` to ``goal`` (pairs of positions ``(edge, offset)``, robot A first)."""
        import scipy.sparse as sp
        from scipy.sparse.csgraph import dijkstra

        t0 = time.perf_counter()
        S = self.N * self.N
        src = self._attach(*start)
        dst = self._attach(*goal)
        if not src or not dst:
            return GridGraphResult(False, None, math.inf, time.perf_counter() - t0, {"reason": "not attached"})
        a = self.adj
        ptr = a.indptr.copy()
        ptr[-1] = ptr[-2] + len(src)
        row_cols = np.array([s[0] for s in src], dtype=a.indices.dtype)
        order = np.argsort(row_cols)
        adj = sp.csr_matrix(
            (
                np.concatenate([a.data, np.array([s[1] + 1e-12 for s in src])[order]]),
                np.concatenate([a.indices, row_cols[order]]),
                ptr,
            ),
            shape=a.shape,
        )
        dist, pred = dijkstra(adj, directed=True, indices=S, return_predecessors=True)
        best, bi = math.inf, -1
        for i, (st, c, _, _) in enumerate(dst):
            if dist[st] + c < best:
                best, bi = float(dist[st] + c), i
        if bi < 0 or not math.isfinite(best):
            return GridGraphResult(False, None, math.inf, time.perf_counter() - t0, {})
        chain = [dst[bi][0]]
        while pred[chain[-1]] != S and pred[chain[-1]] >= 0:
            chain.append(int(pred[chain[-1]]))
        chain.reverse()
        path = self._path(start, goal, chain, src, dst[bi])
        return GridGraphResult(True, path, path.makespan, time.perf_counter() - t0, {"grid_states": len(chain)})

    def _node_pos(self, n: int) -> tuple[int, float]:
        return int(self.node_e[n]), float(self.node_s[n])

    def _path(self, start: Any, goal: Any, chain: list[int], src: list[Any], dst: Any) -> GraphPath:
        N = self.N
        first = next(x for x in src if x[0] == chain[0])
        legs: list[tuple[list[Piece], list[Piece]]] = []
        (ea, sa), (eb, sb) = start
        legs.append(([(ea, sa, first[2])], [(eb, sb, first[3])]))
        for s0, s1 in itertools.pairwise(chain):
            pieces = []
            for n0, n1 in ((s0 // N, s1 // N), (s0 % N, s1 % N)):
                pieces.append([self._step(n0, n1)])
            legs.append((pieces[0], pieces[1]))
        (ga, ta), (gb, tb) = goal
        legs.append(([(ga, dst[2], ta)], [(gb, dst[3], tb)]))
        va, vb = self.speeds
        dur = np.array([max(_length(a) / va, _length(b) / vb) for a, b in legs])
        return GraphPath(legs, dur)

    def _step(self, n0: int, n1: int) -> Piece:
        """The piece of a grid step of one robot from node ``n0`` to ``n1`` (or a stay)."""
        if n0 == n1:
            e, s = self._node_pos(n0)
            return (e, s, s)
        return self._steps[(n0, n1)]


# --------------------------------------------------------------------------------------------------- OMPL
@dataclass
class OmplGraphResult:
    """Outcome of one OMPL query: ``solved`` (exact solution in the budget), ``path``, ``makespan`` (s), times."""

    solved: bool
    path: GraphPath | None
    makespan: float
    compute_time: float
    stats: dict[str, Any] = field(default_factory=dict)


class GraphOmpl:
    """RRTConnect over global arc coordinates with geodesic motions checked exactly (see the module docstring).

    Parameters
    ----------
    track : GraphTrack
    clearance : float
        D (metres).
    budget : float
        RRTConnect time budget per query (s).
    speeds : (float, float)
        Speed limits (m/s) for the makespan.
    """

    def __init__(
        self, track: GraphTrack, clearance: float, budget: float = 1.0, speeds: tuple[float, float] = (1.0, 1.0)
    ):
        from ompl import util as ou

        ou.setLogLevel(ou.LOG_NONE)
        self.track = track
        self.D = float(clearance)
        self.tol = 1e-12 * max(1.0, float(track.total_length))
        self.budget = float(budget)
        self.speeds = (float(speeds[0]), float(speeds[1]))
        self.geo = Geodesics(track)
        L = track.lengths
        self.cum = np.concatenate([[0.0], np.cumsum(L)])
        self._cum = self.cum.tolist()
        self._L = L.tolist()
        self.total = float(self.cum[-1])
        self._special: tuple[dict[float, tuple[int, float]], dict[float, tuple[int, float]]] = ({}, {})

    def to_pos(self, x: float, r: int = 0) -> tuple[int, float]:
        """Position ``(edge, offset)`` of robot ``r`` at global arc coordinate ``x``.

        The start's and goal's coordinates map back to exactly the given positions (an arc coordinate at the
        junction of two consecutive edges is ambiguous: the head of one edge, the tail of the next)."""
        sp = self._special[r].get(x)
        if sp is not None:
            return sp
        e = min(max(int(np.searchsorted(self.cum, x, side="right")) - 1, 0), len(self._L) - 1)
        return e, min(max(x - self._cum[e], 0.0), self._L[e])

    def to_x(self, p: tuple[int, float]) -> float:
        """Global arc coordinate of position ``p``."""
        return self._cum[p[0]] + p[1]

    def leg(self, a: tuple[float, float], b: tuple[float, float]) -> tuple[list[Piece], list[Piece]]:
        """Geodesic leg between two states given in arc coordinates."""
        out = []
        for r in (0, 1):
            e, s = self.to_pos(a[r], r)
            f, t = self.to_pos(b[r], r)
            out.append(self.geo.path(e, s, f, t))
        return out[0], out[1]

    def solve(self, start: Any, goal: Any, seed: int) -> OmplGraphResult:
        """Plan one query (positions ``(edge, offset)``, robot A first; ``seed`` >= 1)."""
        from ompl import base as ob
        from ompl import geometric as og
        from ompl import util as ou

        t0 = time.perf_counter()
        ou.RNG.setSeed(int(seed))
        self._special = (
            {self.to_x(start[0]): tuple(start[0]), self.to_x(goal[0]): tuple(goal[0])},
            {self.to_x(start[1]): tuple(start[1]), self.to_x(goal[1]): tuple(goal[1])},
        )
        track, D, tol = self.track, self.D, self.tol
        dist = track.geometry.distance_scalar
        to_pos, leg = self.to_pos, self.leg
        counts = {"states": 0, "motions": 0}
        space = joint_state_space(ob, self.total)
        ss = og.SimpleSetup(space)

        def valid(state: Any) -> bool:
            counts["states"] += 1
            ea, sa = to_pos(state[0], 0)
            eb, sb = to_pos(state[1], 1)
            return bool(dist(ea, sa, eb, sb) >= D - tol)

        class GeodesicMotionValidator(ob.MotionValidator):  # type: ignore[misc]
            def checkMotion(self, s1: Any, s2: Any, *_last: Any) -> bool:
                counts["motions"] += 1
                pa, pb = leg((s1[0], s1[1]), (s2[0], s2[1]))
                return bool(leg_min_distance(track, pa, pb) >= D - tol)

        ss.setStateValidityChecker(valid)
        si = ss.getSpaceInformation()
        validator = GeodesicMotionValidator(si)
        si.setMotionValidator(validator)
        st, gl = space.allocState(), space.allocState()
        st[0], st[1] = self.to_x(start[0]), self.to_x(start[1])
        gl[0], gl[1] = self.to_x(goal[0]), self.to_x(goal[1])
        ss.setStartAndGoalStates(st, gl)
        planner = og.RRTConnect(si)
        planner.setRange(space.getMaximumExtent())
        ss.setPlanner(planner)
        status = ss.solve(self.budget)
        stats: dict[str, Any] = {"status": str(status)}
        if not ss.haveExactSolutionPath():
            stats.update(counts)
            del validator, ss, si
            return OmplGraphResult(False, None, math.inf, time.perf_counter() - t0, stats)
        path = og.PathGeometric(ss.getSolutionPath())
        stats["rrt_states"] = path.getStateCount()
        simp = og.PathSimplifier(si)
        simplify_vertices(simp, path)
        xs = [(s[0], s[1]) for s in path.getStates()]
        compute = time.perf_counter() - t0
        stats.update(counts)
        stats["waypoints"] = len(xs)
        del validator, ss, si
        legs = [leg(a, b) for a, b in itertools.pairwise(xs)]
        va, vb = self.speeds
        dur = np.array([max(_length(a) / va, _length(b) / vb) for a, b in legs])
        gp = GraphPath(legs, dur)
        return OmplGraphResult(True, gp, gp.makespan, compute, stats)


_GENERATORS: dict[tuple[int, float, tuple[float, float]], Any] = {}


def ours_trajectory(track: GraphTrack, query: dict[str, Any]) -> dict[str, Any]:
    """Verified jerk-limited setpoints for one query on a graph track, timed (``trajopt``'s pipeline on graph plans).

    One :class:`trajopt.TrajectoryGenerator` per (track, clearance, speeds) is built once and re-used (its plan
    cache and solvers, as a user would); the limits are the query's speeds with a = 1 m/s² and j = 5 m/s³ per robot,
    100 Hz. The time includes planning, timing and the verification gate.

    Parameters
    ----------
    track : GraphTrack
    query : dict
        ``{"start": ((eA, sA), (eB, sB)), "goal": ..., "clearance": D, "speeds": (vA, vB)}``.

    Returns
    -------
    dict
        ``verified`` (bool), ``compute_time`` (s), ``makespan`` (s), ``fallback`` (bool), ``path`` (fast/blend/...),
        ``rows``; or ``{"verified": False, "error": ...}`` when the pipeline raises.
    """
    from trajopt import Limits, TrajectoryGenerator

    speeds = tuple(float(v) for v in query.get("speeds", (1.0, 1.0)))
    key = (id(track), float(query["clearance"]), speeds)
    gen = _GENERATORS.get(key)
    if gen is None:
        gen = TrajectoryGenerator(track, clearance=float(query["clearance"]), limits=Limits(list(speeds), 1.0, 5.0))
        _GENERATORS.clear()  # one layout and clearance at a time
        _GENERATORS[key] = gen
    start = tuple(tuple(p) for p in query["start"])
    goal = tuple(tuple(p) for p in query["goal"])
    t0 = time.perf_counter()
    try:
        traj = gen.generate(start, goal)
    except Exception as exc:  # recorded, the benchmark goes on
        return {"verified": False, "error": f"{type(exc).__name__}: {exc}", "compute_time": time.perf_counter() - t0}
    return {
        "verified": bool(traj.verification["ok"]),
        "compute_time": time.perf_counter() - t0,
        "makespan": float(traj.makespan),
        "fallback": bool(traj.fallback),
        "path": str(traj.solver_stats.get("path", "")),
        "rows": len(traj.t),
    }
