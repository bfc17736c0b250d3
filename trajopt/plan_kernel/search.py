"""The compiled search's Python side (:mod:`trajopt.plan_kernel`).

The mesh's parts as arrays (:class:`_MeshArrays`) and the search (:class:`CompiledSearch`).
"""

from __future__ import annotations

import math
import os
from typing import Any

import numpy as np

from mpa.planners.graph import bounds as graph_bounds
from mpa.planners.graph import search as graph_search
from mpa.planners.graph.search import GOAL, START
from trajopt._numba import HAVE_NUMBA, kernel_mode
from trajopt.plan_kernel.arith import (
    _C,
    _GOAL_ID,
    _NF,
    _NI,
    _NO_LIMIT,
    _START_ID,
    EMPTY,
    FOUND,
    NEED_MEMBERS,
    NEED_PAGES,
    STOPPED,
)
from trajopt.plan_kernel.run import _run, _start

__all__ = ["ENV", "CompiledSearch", "install", "installed", "warm"]


# ------------------------------------------------------------------------------------------- the Python side
class _Rows:
    """A growing array of rows (``n`` used of ``a``'s), doubled when full."""

    __slots__ = ("a", "n")

    def __init__(self, width: int, dtype: Any, cap: int = 256) -> None:
        self.a = np.empty((cap, width) if width else cap, dtype)
        self.n = 0

    def reserve(self, k: int) -> int:
        """Room for ``k`` more rows; the index of the first."""
        need = self.n + k
        if need > self.a.shape[0]:
            cap = self.a.shape[0]
            while cap < need:
                cap *= 2
            out = np.empty((cap, *self.a.shape[1:]), self.a.dtype)
            out[: self.n] = self.a[: self.n]
            self.a = out
        i = self.n
        self.n = need
        return i


class _MeshArrays:
    """The parts of a mesh (:class:`mpa.planners.graph.mesh._Mesh`) the kernel has reached, as arrays, kept with the
    mesh: polygons (``pi``: first side, sides, A's edge, B's edge), their sides that are faces (``si``: axis, face,
    the ends' points; ``sf``: side value, lo, hi, the ends' coordinates), faces (``fi``: axis, vertex, other edge,
    first page, pages or -1 before they are written), pages (``pg``, ``pgb``: polygon, side value), points (``ti``:
    first member, members or -1, the face and, in ``tf``, the coordinate of their passing bound, :meth:`point`) and
    the points' members (``mp``, ``mc``: polygon, coordinates). Points 0 and 1 are the start and the goal."""

    def __init__(self, mesh: Any) -> None:
        self.mesh = mesh
        self.poly: dict[Any, int] = {}
        self.poly_ids: list[Any] = []
        self.face: dict[Any, int] = {}
        self.point: dict[Any, int] = {START: _START_ID, GOAL: _GOAL_ID}
        self.keys: list[Any] = [START, GOAL]
        self.pi = _Rows(4, np.int64)
        self.si = _Rows(4, np.int64, 1024)
        self.sf = _Rows(7, np.float64, 1024)
        self.fi = _Rows(5, np.int64)
        self.pg = _Rows(0, np.int64)
        self.pgb = _Rows(0, np.float64)
        self.ti = _Rows(5, np.int64, 1024)
        self.tf = _Rows(0, np.float64, 1024)
        self.mp = _Rows(0, np.int64)
        self.mc = _Rows(2, np.float64)
        for _ in (START, GOAL):
            i = self.ti.reserve(1)
            self.tf.reserve(1)
            self.ti.a[i] = (0, 0, 0, 0, 0)
            self.tf.a[i] = 0.0

    def point_id(self, key: Any) -> int:
        i = self.point.get(key)
        if i is None:
            i = self.point[key] = self.ti.reserve(1)
            self.tf.reserve(1)
            self.keys.append(key)
            if key[0] == "F":
                _, ax, w, other, y = key
            else:  # a corner ("C", A's vertex, B's vertex): PassingBound.point's face through it
                _, w, w2 = key
                ax = 0
                other, y = self.mesh.inc[w2][0]
            self.ti.a[i] = (0, -1, ax, w, other)
            self.tf.a[i] = y
        return i

    def face_id(self, face: Any) -> int:
        i = self.face.get(face)
        if i is None:
            i = self.face[face] = self.fi.reserve(1)
            self.fi.a[i] = (face[0], face[1], face[2], 0, -1)
        return i

    def polygon(self, pid: Any) -> int:
        i = self.poly.get(pid)
        if i is None:
            sides = self.mesh.side_ends(pid)
            n = len(sides)
            s0 = self.si.reserve(n)
            self.sf.reserve(n)
            if n:
                face_id, point_id = self.face_id, self.point_id
                self.si.a[s0 : s0 + n] = [
                    (ax, face_id(face), point_id(k_lo), point_id(k_hi)) for ax, _, face, _, _, k_lo, _, k_hi, _ in sides
                ]
                self.sf.a[s0 : s0 + n] = [
                    (a, lo, hi, p_lo[0], p_lo[1], p_hi[0], p_hi[1]) for _, a, _, lo, hi, _, p_lo, _, p_hi in sides
                ]
            i = self.poly[pid] = self.pi.reserve(1)
            self.poly_ids.append(pid)
            self.pi.a[i] = (s0, len(sides), pid[0], pid[1])
        return i

    def pages(self, f: int) -> None:
        row = self.fi.a[f]
        pages = self.mesh.pages((int(row[0]), int(row[1]), int(row[2])))
        ids = [self.polygon(pid) for pid, _ in pages]
        j = self.pg.reserve(len(pages))
        self.pgb.reserve(len(pages))
        self.pg.a[j : j + len(pages)] = ids
        self.pgb.a[j : j + len(pages)] = [b for _, b in pages]
        self.fi.a[f, 3], self.fi.a[f, 4] = j, len(pages)

    def members(self, t: int, key: Any) -> None:
        members = self.mesh.members(key)
        ids = [self.polygon(pid) for pid, _ in members]
        j = self.mp.reserve(len(members))
        self.mc.reserve(len(members))
        self.mp.a[j : j + len(members)] = ids
        for k, (_, rc) in enumerate(members):
            self.mc.a[j + k] = rc
        self.ti.a[t, 0], self.ti.a[t, 1] = j, len(members)


def _mesh_arrays(mesh: Any) -> _MeshArrays:
    out = getattr(mesh, "_compiled_arrays", None)
    if out is None:
        out = mesh._compiled_arrays = _MeshArrays(mesh)
    return out


class CompiledSearch:
    """:class:`mpa.planners.graph.search.AnyAngleSearch` compiled: the same constructor, :meth:`run` and result.

    Parameters
    ----------
    mesh, query, bound
        As :class:`~mpa.planners.graph.search.AnyAngleSearch`'s.
    """

    def __init__(self, mesh: Any, query: Any, bound: Any = None) -> None:
        ref = graph_search.AnyAngleSearch(mesh, query, bound=bound)  # its constants and goal distances
        self.mesh, self.bound, self.start = mesh, bound, query.start
        self.m = m = _mesh_arrays(mesh)
        self.fq = ref.fq
        ga, gb = ref.to_goal
        self.gd = np.array([ga.cp, ga.cm, gb.cp, gb.cm], dtype=np.float64)
        self.vd = np.array([ga.vd, gb.vd], dtype=np.float64)
        self.gi = np.array([ref._fastest, bound is not None, ga.edge, gb.edge], dtype=np.int64)
        self.par = np.array([ref.ctol, ref.eps, ref._va, ref._vb, ref.again, ref.fq, ref.quantum, ga.offset, gb.offset])
        goals = [(m.polygon(pid), c) for pid, c in mesh.placements(*query.goal)]  # ref.goal_at's, in its order
        self.goals_p = np.array([p for p, _ in goals], dtype=np.int64)
        self.goals_c = np.array([c for _, c in goals], dtype=np.float64).reshape(-1, 2)
        self.start_members = mesh.placements(*query.start)
        self.ni = np.empty((1024, _NI), np.int64)
        self.nf = np.empty((1024, _NF), np.float64)
        self.pend = np.zeros(1024, np.bool_)
        self.hk = np.empty((1024, 2), np.int64)
        self.hd = np.empty(1024, np.float64)
        self.iv = np.empty((1024, 2), np.float64)
        self.ivn = np.empty(1024, np.int64)
        self.c = np.zeros(_C, np.int64)
        self.best = np.full(max(1024, m.ti.n), math.inf)
        self.pbv = np.full(self.best.shape[0], math.nan)  # the passing bound per point, NaN: not yet
        self.fsl = np.full((max(1024, m.fi.n), 3), -1, np.int64)  # per face: its fronts' and on-edge slots
        # hash tables (keys, values; -1: empty): interval cells seen, fronts' slots, on-edge slots
        self.seen_k, self.seen_v = np.zeros((1024, 6), np.int64), np.full(1024, -1, np.int64)
        self.fk, self.fv = np.zeros((256, 3), np.int64), np.full(256, -1, np.int64)
        self.ok_, self.ov = np.zeros((256, 3), np.int64), np.full(256, -1, np.int64)
        self.fr, self.frs = np.empty((256, 2)), np.empty((64, 2), np.int64)
        self.on, self.onr = np.empty((256, 4)), np.empty((64, 2), np.int64)
        g = mesh.g
        if bound is not None:
            n = max(g.n_vertices, g.n_edges)
            self.dv = np.ascontiguousarray(g.dv, dtype=np.float64)
            self.bd = np.zeros((2, n))
            self.bd[0, : g.n_vertices] = g.dv[bound.vertex]
            self.bd[1, : g.n_edges] = g.lengths
            self.bgi = np.array([g.tails, g.heads], dtype=np.int64)
            e_, u0, u1, f_, v0, v1, wk = bound._segs[:7]
            self.segi = np.array([e_, f_], dtype=np.int64).reshape(2, -1)
            self.segf = np.array([u0, u1, v0, v1, wk], dtype=np.float64).reshape(5, -1)
            self.bpar = np.array([bound._sign, bound.at_start, bound.va, bound.vb])
        else:
            self.dv, self.bd, self.bgi = np.zeros((1, 1)), np.zeros((2, 1)), np.zeros((2, 1), np.int64)
            self.segi, self.segf, self.bpar = np.zeros((2, 0), np.int64), np.zeros((5, 0)), np.zeros(4)
        self.started = False

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

    # -------------------------------------------------------------------------------------------- requests
    def _answer(self, status: int) -> None:
        m, c = self.m, self.c
        if status == NEED_PAGES:
            m.pages(int(c[6]))
        elif status == NEED_MEMBERS:
            t = int(c[6])
            m.members(t, m.keys[t])
        else:  # pragma: no cover - the kernel asks nothing else
            raise AssertionError(f"unknown request {status}")

    def _fit_best(self) -> None:
        """The per-point and per-face arrays as long as the points and faces written so far."""
        n = self.m.ti.n
        if n > self.best.shape[0]:
            size = max(n, 2 * self.best.shape[0])
            best, pbv = np.full(size, math.inf), np.full(size, math.nan)
            best[: self.best.shape[0]], pbv[: self.pbv.shape[0]] = self.best, self.pbv
            self.best, self.pbv = best, pbv
        n = self.m.fi.n
        if n > self.fsl.shape[0]:
            fsl = np.full((max(n, 2 * self.fsl.shape[0]), 3), -1, np.int64)
            fsl[: self.fsl.shape[0]] = self.fsl
            self.fsl = fsl

    # ------------------------------------------------------------------------------------------------- run
    def run(self, budget: int | None = None, limit: float | None = None) -> list[Any] | None:
        """:meth:`AnyAngleSearch.run`: the path's segments, or None at ``budget`` pops of this call or a queue key
        above ``limit`` (a later call resumes)."""
        m, c = self.m, self.c
        if not self.started:
            mem = [(m.polygon(pid), rc) for pid, rc in self.start_members]
            mem_p = np.array([p for p, _ in mem], dtype=np.int64)
            mem_c = np.array([rc for _, rc in mem], dtype=np.float64).reshape(-1, 2)
            need = 1 + sum(2 + len(self.goals_p) + 3 * int(m.pi.a[p, 1]) for p in mem_p)
            self._fit_best()
            if need > self.ni.shape[0]:
                size = 2 * need
                self.ni, self.nf = np.empty((size, _NI), np.int64), np.empty((size, _NF))
                self.pend, self.hk, self.hd = np.zeros(size, np.bool_), np.empty((size, 2), np.int64), np.empty(size)
            _start(
                self.ni,
                self.nf,
                self.pend,
                self.hk,
                self.hd,
                c,
                self.best,
                m.pi.a,
                m.si.a,
                m.sf.a,
                m.fi.a,
                self.gd,
                self.vd,
                self.gi,
                self.par,
                self.goals_p,
                self.goals_c,
                mem_p,
                mem_c,
            )
            self.started = True
        over = _NO_LIMIT if limit is None else math.floor(limit * self.fq)
        c[3] = 0
        while True:
            self._fit_best()
            (
                status, self.ni, self.nf, self.pend, self.hk, self.hd, self.iv, self.ivn,
                self.fr, self.frs, self.on, self.onr, self.seen_k, self.seen_v, self.fk, self.fv, self.ok_, self.ov,
            ) = _run(
                self.ni, self.nf, self.pend, self.hk, self.hd, c, self.best, self.iv, self.ivn, self.seen_k,
                self.seen_v,
                m.pi.a, m.si.a, m.sf.a, m.fi.a, m.pg.a, m.pgb.a, m.ti.a, m.tf.a, m.mp.a, m.mc.a,
                self.gd, self.vd, self.gi, self.par, self.goals_p, self.goals_c,
                self.dv, self.bgi, self.bd, self.segi, self.segf, self.bpar, self.fk, self.fv, self.fr, self.frs,
                self.ok_, self.ov, self.on, self.onr, self.pbv, self.fsl, -1 if budget is None else budget, over,
            )  # fmt: skip
            if status == FOUND:
                return self.segments(int(c[4]))
            if status == STOPPED:
                return None
            if status == EMPTY:
                from mpa.errors import PlanningError

                raise PlanningError(
                    "search ended without reaching the goal although it is in the start's component (a bug)"
                )
            self._answer(status)

    def segments(self, nid: int) -> list[Any]:
        """:meth:`AnyAngleSearch.segments`, read from the node arrays."""
        ni, nf, ids = self.ni, self.nf, self.m.poly_ids
        runs: list[list[Any]] = []
        while nid != 0:
            row_i, row_f = ni[nid].tolist(), nf[nid].tolist()
            last, root, pid = row_i[3], row_i[2], row_i[4]
            q = (row_f[3], row_f[4])
            if last < 0:
                runs.append([[ids[pid], (row_f[1], row_f[2]), q]])
                nid = root
                continue
            chain = []
            i = last
            while i != root:
                chain.append((ni[i].tolist(), nf[i].tolist()))
                i = chain[-1][0][3]
            chain.reverse()
            (ci, cf) = chain[0]
            q0, r0 = ids[ci[8]], (cf[11], cf[12])
            lk = chain[-1][1]
            rk, sk = (lk[1], lk[2]), (lk[3], lk[4])
            d0 = (sk[0] * (q[0] - rk[0]), sk[1] * (q[1] - rk[1]))
            segs: list[Any] = []
            prev_pid, prev_pt = q0, r0
            for it_i, it_f in chain:
                r, ax, a = (it_f[1], it_f[2]), it_i[5], it_f[5]
                di = (it_f[3] * d0[0], it_f[4] * d0[1])
                if di[ax] != 0.0:
                    lam = (a - r[ax]) / di[ax]
                    y = r[1 - ax] + lam * di[1 - ax]
                else:  # pragma: no cover - a crossing line is never parallel to its face
                    y = r[1 - ax]
                y = min(max(y, it_f[8]), it_f[9])
                exit_pt = (it_f[10], y) if ax == 0 else (y, it_f[10])
                entry = (a, y) if ax == 0 else (y, a)
                segs.append([prev_pid, prev_pt, exit_pt])
                prev_pid, prev_pt = ids[it_i[4]], entry
            segs.append([prev_pid, prev_pt, q])
            runs.append(segs)
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
    """Hand :class:`CompiledSearch` to the graph planner (:func:`mpa.planners.graph.query.use_search`).

    Only in a process whose kernels are compiled (:func:`trajopt._numba.kernel_mode` ``"numba"``, numba installed),
    and unless the environment variable :data:`ENV` is ``python``. The kernels are compiled on the first search after
    an install (about 45 s on a 2-core machine) and then loaded from numba's on-disk cache (about 1 s a process):
    :func:`warm` does it at a time of the caller's choosing.

    Returns
    -------
    bool
        :func:`installed`.
    """
    from mpa.planners.graph import query

    if kernel_mode() == "numba" and HAVE_NUMBA and os.environ.get(ENV, "compiled").strip().lower() != "python":
        query.use_search(CompiledSearch)
    return installed()


def warm() -> None:
    """Compile the kernels, or load them from the on-disk cache: one small search (a swap on a Y junction)."""
    from mpa.freespace import free_space
    from mpa.graph_track import GraphTrack
    from mpa.planners.graph.mesh import _mesh
    from mpa.planners.search_common import SearchQuery

    track = GraphTrack.from_layout({"edges": [["J", "a", 2.0], ["J", "b", 2.0], ["J", "c", 2.0]]})
    fs = free_space(track, 0.5)
    start, goal = ((0, 1.5), (1, 1.5)), ((1, 1.5), (0, 1.5))
    CompiledSearch(_mesh(fs), SearchQuery(track, fs, start, goal, "fastest", (1.0, 1.0))).run()
