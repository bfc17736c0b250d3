"""The compiled search's Python side (:mod:`trajopt.plan_kernel`).

The layout and its free space as arrays (:func:`_layout_arrays`, kept with the mesh) and the search
(:class:`CompiledSearch`).
"""

from __future__ import annotations

import math
import os
from typing import Any

import numpy as np

from mpa.planners import corners as graph_corners
from mpa.planners.graph import bounds as graph_bounds
from mpa.planners.graph import search as graph_search
from trajopt._numba import HAVE_NUMBA, kernel_mode
from trajopt.plan_kernel.arith import (
    _C,
    _NF,
    _NI,
    _NO_LIMIT,
    FOUND,
    STOPPED,
)
from trajopt.plan_kernel.run import _point_nodes, _room, _room_poly, _run, _start

__all__ = ["ENV", "CompiledSearch", "install", "installed", "warm"]


# ------------------------------------------------------------------------------------------- the Python side
def _layout_arrays(mesh: Any) -> tuple[Any, ...]:
    """``M`` (:mod:`trajopt.plan_kernel.expand`) of a mesh, made once and kept with it: the edges' ends and lengths,
    each vertex's edge ends in the order of :attr:`_Mesh.inc`, the faces' arrays (views, ``[edge, vertex]``) and per
    cell a bit per free piece."""
    out = getattr(mesh, "_kernel_layout", None)
    if out is None:
        fs, g = mesh.fs, mesh.g
        n_e, n_v = g.n_edges, g.n_vertices
        inc_ptr = np.zeros(n_v + 1, np.int64)
        inc_e, inc_x = [], []
        for w in range(n_v):
            for e, x in mesh.inc[w]:
                inc_e.append(e)
                inc_x.append(x)
            inc_ptr[w + 1] = len(inc_e)
        pieces = np.zeros((n_e, n_e), np.int8)
        for k in (0, 1):
            sel = fs._pk == k
            pieces[fs._pe[sel], fs._pf[sel]] |= np.int8(1 << k)
        faces = fs.faces
        out = mesh._kernel_layout = (
            np.ascontiguousarray(g.tails, dtype=np.int64),
            np.ascontiguousarray(g.heads, dtype=np.int64),
            np.ascontiguousarray(g.lengths, dtype=np.float64),
            inc_ptr,
            np.array(inc_e, dtype=np.int64),
            np.array(inc_x, dtype=np.float64),
            np.ascontiguousarray(faces.ok.T),
            np.ascontiguousarray(faces.lo.T, dtype=np.float64),
            np.ascontiguousarray(faces.hi.T, dtype=np.float64),
            pieces,
        )
    return out


#: The most bytes of node arrays (:attr:`CompiledSearch.N`, every row written before it is read) that a process
#: keeps, once a search is dropped, for its next search to start with (0: none kept). A search that grows its arrays
#: to hundreds of thousands of rows (the plateaus of docs/performance.md, about 220 bytes a node) otherwise pays, at
#: each doubling, for fresh pages from the kernel, the copy, and the pages returned: measured as a third of the
#: plan time of scaling 150/0's slowest query. Larger arrays are freed as before.
SPARE_BYTES = 256 * 2**20

#: The node arrays kept (at most one set: the largest under :data:`SPARE_BYTES`).
_spare: list[tuple[Any, ...]] = []


def _node_arrays() -> tuple[Any, ...]:
    """A new search's node arrays ``(ni, nf, pend, hk, hd)`` (``N`` of :mod:`trajopt.plan_kernel.expand` without the
    counters): those of a dropped search when a process keeps them (:data:`SPARE_BYTES`), else 1 024 rows each."""
    try:
        return _spare.pop()
    except IndexError:
        size = 1024
        return (
            np.empty((size, _NI), np.int64),
            np.empty((size, _NF), np.float64),
            np.zeros(size, np.bool_),
            np.empty((size, 2), np.int64),
            np.empty(size, np.float64),
        )


def _keep_spare(arrays: tuple[Any, ...]) -> None:
    """Keep a dropped search's node arrays for the next search when they are within :data:`SPARE_BYTES` and larger
    than those kept already."""
    size = sum(a.nbytes for a in arrays)
    if size > SPARE_BYTES or (_spare and sum(a.nbytes for a in _spare[0]) >= size):
        return
    _spare[:] = [arrays]


class _Tables:
    """The points and polygons the kernel has named on one mesh, shared by its searches and kept with it: the points'
    hash table (``pk``, ``pv``), keys (``pt``) and coordinates (``pty``); the polygon table ``C``
    (:func:`trajopt.plan_kernel.expand._poly`); the counters ``c[16:21]`` (points, point keys, polygons, polygon keys,
    sides). Points 0 and 1 are the start and the goal. Only ever appended to, so a search that resumes after another
    ran reads them as that one left them."""

    def __init__(self) -> None:
        n = 8192
        self.pk, self.pv = np.zeros((2 * n, 5), np.int64), np.full(2 * n, -1, np.int64)
        self.pt, self.pty = np.zeros((n, 5), np.int64), np.zeros(n)
        self.C = (
            np.zeros((2048, 1), np.int64),
            np.full(2048, -1, np.int64),
            np.empty((1024, 2), np.int64),
            np.empty((4096, 5), np.int64),
            np.empty((4096, 3)),
        )
        self.counts = np.array([2, 0, 0, 0, 0], np.int64)


def _tables(mesh: Any) -> _Tables:
    out = getattr(mesh, "_kernel_tables", None)
    if out is None:
        out = mesh._kernel_tables = _Tables()
    return out


def _polygon_int(pid: Any, n_e: int) -> int:
    e, f, k = pid
    return (int(e) * n_e + int(f)) * 2 + int(k)


class CompiledSearch:
    """:class:`mpa.planners.graph.search.AnyAngleSearch` compiled: the same constructor, :meth:`run` and result.

    Parameters
    ----------
    mesh, query, bound, to_goal
        As :class:`~mpa.planners.graph.search.AnyAngleSearch`'s.
    """

    def __init__(self, mesh: Any, query: Any, bound: Any = None, to_goal: Any = None) -> None:
        ref = graph_search.AnyAngleSearch(mesh, query, bound=bound, to_goal=to_goal)  # its constants, goal distances
        self.M = _layout_arrays(mesh)
        self.n_e = n_e = mesh.g.n_edges
        self.fq = ref.fq
        ga, gb = ref.to_goal
        goals = [(_polygon_int(pid, n_e), c) for pid, c in mesh.placements(*query.goal)]  # ref.goal_at's order
        self.G = (
            np.array([ga.cp, ga.cm, gb.cp, gb.cm], dtype=np.float64),
            np.array([ga.vd, gb.vd], dtype=np.float64),
            np.array([ref._fastest, bound is not None, ga.edge, gb.edge], dtype=np.int64),
            np.array([ref.ctol, ref.eps, ref._va, ref._vb, ref.again, ref.fq, ref.quantum, ga.offset, gb.offset]),
            np.array([p for p, _ in goals], dtype=np.int64),
            np.array([c for _, c in goals], dtype=np.float64).reshape(-1, 2),
        )
        self.start_members = mesh.placements(*query.start)
        c = np.zeros(_C, np.int64)
        self.N = (*_node_arrays(), c)
        self.tables = _tables(mesh)
        self.best = np.full(self.tables.pt.shape[0], math.inf)  # per point of the tables: least cost, bound
        self.pbv = np.full(self.tables.pt.shape[0], math.nan)
        self.S = (
            np.zeros((1024, 6), np.int64),
            np.full(1024, -1, np.int64),
            np.empty((1024, 2)),
            np.empty(1024, np.int64),
        )
        self.BS = (
            np.zeros((256, 3), np.int64),
            np.full(256, -1, np.int64),
            np.empty((256, 2)),
            np.empty((64, 2), np.int64),
            np.zeros((256, 3), np.int64),
            np.full(256, -1, np.int64),
            np.empty((256, 4)),
            np.empty((64, 2), np.int64),
        )
        g = mesh.g
        if bound is not None:
            n = max(g.n_vertices, g.n_edges)
            bd = np.zeros((2, n))
            bd[0, : g.n_vertices] = g.dv[bound.vertex]
            bd[1, : g.n_edges] = g.lengths
            e_, u0, u1, f_, v0, v1, wk = bound._segs[:7]
            self.B = (
                np.ascontiguousarray(g.dv, dtype=np.float64),
                np.array([g.tails, g.heads], dtype=np.int64),
                bd,
                np.array([e_, f_], dtype=np.int64).reshape(2, -1),
                np.array([u0, u1, v0, v1, wk], dtype=np.float64).reshape(5, -1),
                np.array([bound._sign, bound.at_start, bound.va, bound.vb]),
            )
        else:
            self.B = (
                np.zeros((1, 1)), np.zeros((2, 1), np.int64), np.zeros((2, 1)), np.zeros((2, 0), np.int64),
                np.zeros((5, 0)), np.zeros(4),
            )  # fmt: skip
        self.started = False

    def __del__(self) -> None:
        # the node arrays are this search's alone (the kernel writes every row before it reads it; no view of them
        # leaves the search), so the next search may start with them
        N = getattr(self, "N", None)
        if N is not None and _keep_spare is not None:  # None: the module torn down at exit
            _keep_spare(N[:5])

    def _tables_in(self) -> tuple[Any, Any]:
        """``P`` and ``C`` for the kernel: the mesh's tables (points and polygons, shared by its searches), this
        search's least costs and point bounds as long as the points' arrays, the counters in ``c[16:21]``."""
        t, c = self.tables, self.N[5]
        n = t.pt.shape[0]
        if self.best.shape[0] < n:
            best, pbv = np.full(n, math.inf), np.full(n, math.nan)
            best[: self.best.shape[0]], pbv[: self.pbv.shape[0]] = self.best, self.pbv
            self.best, self.pbv = best, pbv
        c[16:21] = t.counts
        return (t.pk, t.pv, t.pt, t.pty, self.best, self.pbv), t.C

    def _tables_out(self, P: Any, C: Any) -> None:
        t = self.tables
        t.pk, t.pv, t.pt, t.pty = P[0], P[1], P[2], P[3]
        self.best, self.pbv = P[4], P[5]
        t.C = C
        t.counts = self.N[5][16:21].copy()

    @staticmethod
    def supports(query: Any, bound: Any) -> bool:
        """Whether this search is the reference's node for node under the planner's current settings (the benchmark
        changes some of them for its "before" arms; the reference then answers)."""
        pb = graph_bounds.PassingBound
        return bound is None or (
            type(bound) is pb
            and graph_bounds.POINTS_FROM_FRONTS
            and not pb.exact_points
            and pb.least_through is _LEAST_THROUGH
            and bound.vertex is not None
        )

    # ------------------------------------------------------------------------------------------------- run
    def run(self, budget: int | None = None, limit: float | None = None) -> list[Any] | None:
        """:meth:`AnyAngleSearch.run`: the path's segments, or None at ``budget`` pops of this call or a queue key
        above ``limit`` (a later call resumes)."""
        c = self.N[5]
        if not self.started:
            mem_p = np.array([_polygon_int(pid, self.n_e) for pid, _ in self.start_members], dtype=np.int64)
            mem_c = np.array([rc for _, rc in self.start_members], dtype=np.float64).reshape(-1, 2)
            P, C = self._tables_in()  # room as the kernel makes it before an expansion (run._room, run._room_poly)
            C, P = _room_poly(C, P, c, len(mem_p))
            self.N, P = _room(self.N, P, 1 + _point_nodes(len(mem_p), len(self.G[4])), 0)
            _start(self.N, P, C, self.M, self.G, mem_p, mem_c)
            self._tables_out(P, C)
            self.started = True
        over = _NO_LIMIT if limit is None else math.floor(limit * self.fq)
        c[3] = 0
        P, C = self._tables_in()
        status, self.N, P, C, self.S, self.BS = _run(
            self.N, P, C, self.S, self.B, self.BS, self.M, self.G, -1 if budget is None else budget, over
        )
        self._tables_out(P, C)
        if status == FOUND:
            return self.segments(int(c[4]))
        if status == STOPPED:
            return None
        from mpa.errors import PlanningError

        raise PlanningError("search ended without reaching the goal although it is in the start's component (a bug)")

    def segments(self, nid: int) -> list[Any]:
        """:meth:`AnyAngleSearch.segments`, read from the node arrays."""
        ni, nf = self.N[0], self.N[1]
        n_e = self.n_e

        def ids(p: int) -> tuple[int, int, int]:
            return ((p // 2) // n_e, (p // 2) % n_e, p % 2)

        runs: list[list[Any]] = []
        while nid != 0:
            row_i, row_f = ni[nid].tolist(), nf[nid].tolist()
            last, root, pid = row_i[3], row_i[2], row_i[4]
            q = (row_f[3], row_f[4])
            if last < 0:
                runs.append([[ids(pid), (row_f[1], row_f[2]), q]])
                nid = root
                continue
            chain = []
            i = last
            while i != root:
                chain.append((ni[i].tolist(), nf[i].tolist()))
                i = chain[-1][0][3]
            chain.reverse()
            ci, cf = chain[0]
            crossings = [
                (ids(it_i[4]), (it_f[1], it_f[2]), (it_f[3], it_f[4]), it_i[5], it_f[5], it_f[8], it_f[9], it_f[10])
                for it_i, it_f in chain
            ]
            runs.append(graph_search.fold_run(ids(ci[8]), (cf[11], cf[12]), q, crossings))
            nid = root
        out: list[Any] = []
        for run in reversed(runs):
            out.extend(run)
        if not out:
            pid, c = self.start_members[0]
            out.append([pid, c, c])
        return out


_LEAST_THROUGH = graph_bounds.PassingBound.least_through


#: The environment variable that chooses the graph planner's search in :func:`install`: ``compiled`` (the default)
#: or ``python`` (:class:`~mpa.planners.graph.search.AnyAngleSearch` stays; the test suite sets it, but for the tests
#: of this package, so that one process compiles the kernels, not every worker).
ENV = "TRAJOPT_SEARCH"


def installed() -> bool:
    """Whether :func:`mpa.planners.graph.query.plan_graph` searches with :class:`CompiledSearch`."""
    from mpa.planners.graph import query

    return query.compiled_search() is CompiledSearch


def install() -> bool:
    """Hand :class:`CompiledSearch` to the graph planner (:func:`mpa.planners.graph.query.use_search`), and the
    compiled builder of the corners' programme to :mod:`mpa.planners.corners`
    (:func:`~trajopt.plan_kernel.corners.build_programme`, :func:`mpa.planners.corners.use_programme`).

    Only in a process whose kernels are compiled (:func:`trajopt._numba.kernel_mode` ``"numba"``, numba installed),
    and unless the environment variable :data:`ENV` is ``python``. The kernels are compiled on the first search after
    an install (55–75 s on a 2-core machine, the corners' builder included) and then loaded from numba's on-disk
    cache (about 1 s a process): :func:`warm` does it at a time of the caller's choosing.

    Returns
    -------
    bool
        :func:`installed`.
    """
    from mpa.planners.graph import query

    if kernel_mode() == "numba" and HAVE_NUMBA and os.environ.get(ENV, "compiled").strip().lower() != "python":
        from trajopt.plan_kernel.corners import build_programme

        query.use_search(CompiledSearch)
        graph_corners.use_programme(build_programme)
    return installed()


def warm() -> None:
    """Compile the kernels, or load them from the on-disk cache: one small search (a swap on a Y junction) and the
    corners' programme builder (:func:`trajopt.plan_kernel.corners.warm`)."""
    from mpa.freespace import free_space
    from mpa.graph_track import GraphTrack
    from mpa.planners.graph.mesh import _mesh
    from mpa.planners.search_common import SearchQuery
    from trajopt.plan_kernel.corners import warm as corners_warm

    track = GraphTrack.from_layout({"edges": [["J", "a", 2.0], ["J", "b", 2.0], ["J", "c", 2.0]]})
    fs = free_space(track, 0.5)
    start, goal = ((0, 1.5), (1, 1.5)), ((1, 1.5), (0, 1.5))
    CompiledSearch(_mesh(fs), SearchQuery(track, fs, start, goal, "fastest", (1.0, 1.0))).run()
    corners_warm()
