"""The corners' programme compiled: :func:`mpa.planners.corners._programme` as loops over arrays (numba).

:func:`mpa.planners.corners._solve_chain` builds, for each chain of cells of a searched plan, the least-distance
programme of the corners' rule (:class:`mpa.planners.corners.Programme`): which corners are free, the directions the
robots keep, and the rows ``G z >= h``. In the interpreter that takes about 1.5 ms for a chain of 45 segments, as much
as its solve, and a plan solves up to eight chains. :func:`build_programme` is the same construction compiled: the
same arrays bit for bit (the same floating-point operations in the same order; ``G``'s entries added into zeros in the
order :func:`numpy.bincount` adds them), so the corners, and the plans, are the same.
:func:`trajopt.plan_kernel.install` hands it to :mod:`mpa.planners.corners`
(:func:`~mpa.planners.corners.use_programme`).
"""

from __future__ import annotations

import itertools
from typing import Any

import numpy as np

from mpa.planners import corners as graph_corners
from trajopt._numba import njit

__all__ = ["build_programme", "warm"]


@njit(cache=True)
def _directions(cells: Any, d: Any, free: Any, robot: int) -> Any:  # pragma: no cover - compiled
    """:func:`mpa.planners.corners._directions`: per segment the sign the robot's move keeps, shape (n,)."""
    n = cells.shape[0]
    sig = np.zeros(n, np.int64)
    for i in range(n):
        x = d[i, robot]
        sig[i] = (1 if x > 0.0 else 0) - (1 if x < 0.0 else 0)
    out = sig.copy()
    pending = np.empty(n, np.int64)
    i = 0
    while i < n:
        j = i
        while j + 1 < n and free[j + 1, robot] >= 0:
            j += 1
        last = 0
        npend = 0
        for k in range(i, j + 1):
            if sig[k] != 0:
                for q in range(npend):
                    out[pending[q]] = sig[k]
                npend = 0
                last = sig[k]
            elif last != 0:
                out[k] = last
            else:
                pending[npend] = k
                npend += 1
        i = j + 1
    return out


@njit(cache=True)
def _find(parent: Any, v: int) -> int:  # pragma: no cover - compiled
    """The root of ``v``'s set in the forest ``parent``, halving the path (``find`` of
    :func:`mpa.planners.corners._programme`)."""
    while parent[v] != v:
        parent[v] = parent[parent[v]]
        v = parent[v]
    return v


@njit(cache=True)
def _programme_arrays(
    cells: Any,
    p0: Any,
    p1: Any,
    va: float,
    vb: float,
    lengths: Any,
    tptr: Any,
    terms: Any,
    dmin: float,
    margin: float,
    m_rhs: float,
    w_scaled: float,
    drop: bool,
) -> Any:  # pragma: no cover - compiled
    """The arrays of :func:`mpa.planners.corners._programme` (module docstring); ``nv = 0`` when no corner is free.

    ``cells`` (n, 3) int, ``p0``, ``p1`` (n, 2) the segments' ends, ``lengths`` (E,) the edges' lengths, the binding
    terms of segment ``i``'s cell the rows ``tptr[i] .. tptr[i + 1]`` of ``terms`` (k, 3); ``m_rhs`` the makespan
    row's right-hand side, ``w_scaled`` the search's travel times ``1 + RESOLVE_TOL / 2``; ``drop``
    :data:`~mpa.planners.corners.DROP_IMPLIED_ROWS`."""
    n = cells.shape[0]
    free = np.full((n + 1, 2), -1, np.int64)
    values = np.empty(2 * n)
    var_robot0 = np.empty(2 * n, np.int64)
    var_edge0 = np.empty(2 * n, np.int64)
    nv = 0
    for j in range(1, n):
        for r in range(2):
            if cells[j - 1, r] == cells[j, r] and p1[j - 1, r] == p0[j, r]:
                free[j, r] = nv
                values[nv] = p0[j, r]
                var_robot0[nv] = r
                var_edge0[nv] = cells[j, r]
                nv += 1
    empty_f = np.zeros((0, 0))
    empty_i = np.zeros(0, np.int64)
    sig = np.zeros((2, n), np.int64)
    vix = np.full((n, 2, 2), -1, np.int64)
    cst = np.zeros((n, 2, 2))
    if nv == 0:
        return 0, free, sig, vix, cst, np.zeros(0), empty_i, empty_i, empty_f, np.zeros(0), 0, empty_f, np.zeros(0), -1
    d = p1 - p0
    sig[0] = _directions(cells, d, free, 0)
    sig[1] = _directions(cells, d, free, 1)
    # a robot standing on a segment keeps one coordinate at both its corners: one variable, or none at a fixed end
    parent = np.arange(nv)
    pinned = np.zeros(nv, np.bool_)
    for i in range(n):
        for r in range(2):
            if sig[r, i] != 0:
                continue
            v0 = free[i, r] if i > 0 else -1
            v1 = free[i + 1, r] if i + 1 < n else -1
            if v0 >= 0 and v1 >= 0:
                a0 = _find(parent, v0)
                a1 = _find(parent, v1)
                pinned[a1] = pinned[a1] or pinned[a0]
                parent[a0] = a1
            elif v0 >= 0 or v1 >= 0:
                pinned[_find(parent, max(v0, v1))] = True
    renumber = np.full(nv, -1, np.int64)
    kept = np.empty(nv, np.int64)
    nk = 0
    for v in range(nv):
        root = _find(parent, v)
        if pinned[root]:
            continue
        if renumber[root] < 0:
            renumber[root] = nk
            kept[nk] = root
            nk += 1
    for j in range(1, n):
        for r in range(2):
            v = free[j, r]
            if v >= 0:
                root = _find(parent, v)
                free[j, r] = -1 if pinned[root] else renumber[root]
    x_own = np.empty(nk)
    var_robot = np.empty(nk, np.int64)
    var_edge = np.empty(nk, np.int64)
    for q in range(nk):
        x_own[q] = values[kept[q]]
        var_robot[q] = var_robot0[kept[q]]
        var_edge[q] = var_edge0[kept[q]]
    nv = nk
    if nv == 0:
        return 0, free, sig, vix, cst, np.zeros(0), empty_i, empty_i, empty_f, np.zeros(0), 0, empty_f, np.zeros(0), -1
    # the boxes that the direction rows imply (mpa.planners.corners._monotone_variables)
    boxed = np.zeros(nv, np.bool_)
    if drop:
        for r in range(2):
            i = 0
            while i < n:
                j = i
                while j + 1 < n and free[j + 1, r] >= 0:
                    j += 1
                pos = False
                neg = False
                for k in range(i, j + 1):
                    if sig[r, k] > 0:
                        pos = True
                    elif sig[r, k] < 0:
                        neg = True
                if not (pos and neg):
                    for k in range(i + 1, j + 1):
                        boxed[free[k, r]] = True
                i = j + 1
    for i in range(n):
        for r in range(2):
            v0 = free[i, r] if i > 0 else -1
            v1 = free[i + 1, r] if i + 1 < n else -1
            vix[i, 0, r] = v0
            vix[i, 1, r] = v1
            cst[i, 0, r] = 0.0 if v0 >= 0 else p0[i, r]
            cst[i, 1, r] = 0.0 if v1 >= 0 else p1[i, r]
    nz = nv + n
    rows = 4 * n + n + 2 + 2 * nv + 2 * (tptr[n] - tptr[0] + n)
    gmat = np.zeros((rows, nz))
    h = np.zeros(rows)
    m = 0
    dmat = np.zeros((2 * n, nv))
    dcon = np.zeros(2 * n)
    travel = np.zeros(nv)
    travel_const = 0.0
    fixed_t = np.zeros(n)
    timed = np.zeros(n, np.bool_)
    for i in range(n):
        for r in range(2):
            v0 = vix[i, 0, r]
            v1 = vix[i, 1, r]
            iv = 1.0 / (va if r == 0 else vb)
            k = 2 * i + r
            dk = (cst[i, 1, r] - cst[i, 0, r]) * iv
            dcon[k] = dk
            s = sig[r, i]
            if v0 < 0 and v1 < 0:  # both ends fixed
                a = abs(dk)
                if a > fixed_t[i]:
                    fixed_t[i] = a
                travel_const += s * dk
                continue
            if v1 >= 0:
                dmat[k, v1] += iv
            if v0 >= 0:
                dmat[k, v0] -= iv
            if s == 0:
                continue
            # σ Δ >= 0, then T_i - σ Δ / v >= 0 (the entries in the order of mpa's rows: v1, then v0)
            if v1 >= 0:
                gmat[m, v1] += s * iv
            if v0 >= 0:
                gmat[m, v0] += s * -iv
            h[m] = -s * dk
            m += 1
            if v1 >= 0:
                gmat[m, v1] += -s * iv
            if v0 >= 0:
                gmat[m, v0] += -s * -iv
            gmat[m, nv + i] += 1.0
            h[m] = s * dk
            m += 1
            timed[i] = True
            if v1 >= 0:
                travel[v1] = travel[v1] - s * iv
            if v0 >= 0:
                travel[v0] = travel[v0] - s * -iv
            travel_const += s * dk
    for i in range(n):
        if drop and fixed_t[i] == 0.0 and timed[i]:
            continue
        gmat[m, nv + i] += 1.0
        h[m] = fixed_t[i]
        m += 1
    for i in range(n):
        gmat[m, nv + i] += -1.0
    h[m] = m_rhs
    m += 1
    travel_row = m
    for c in range(nv):
        gmat[m, c] += travel[c]
    h[m] = travel_const - w_scaled
    m += 1
    for v in range(nv):
        if boxed[v]:
            continue
        gmat[m, v] += 1.0
        h[m] = 0.0
        m += 1
        gmat[m, v] += -1.0
        h[m] = -lengths[var_edge[v]]
        m += 1
    for i in range(n):
        e = cells[i, 0]
        f = cells[i, 1]
        kk = cells[i, 2]
        for end in range(2):
            va_ = vix[i, end, 0]
            vb_ = vix[i, end, 1]
            if va_ < 0 and vb_ < 0:
                continue
            ca_ = cst[i, end, 0]
            cb_ = cst[i, end, 1]
            ps = p0[i, 0] if end == 0 else p1[i, 0]
            pt_ = p0[i, 1] if end == 0 else p1[i, 1]
            for t in range(tptr[i], tptr[i + 1]):
                sa = terms[t, 0]
                sb = terms[t, 1]
                c0 = terms[t, 2]
                if va_ >= 0:
                    gmat[m, va_] += sa
                if vb_ >= 0:
                    gmat[m, vb_] += sb
                x = sa * ps + sb * pt_ + c0
                here = x if x > dmin else dmin
                top = dmin + margin
                h[m] = (here if here < top else top) - c0 - sa * ca_ - sb * cb_
                m += 1
            if e == f:
                sg = 1.0 if kk == 0 else -1.0
                if va_ >= 0:
                    gmat[m, va_] += sg
                if vb_ >= 0:
                    gmat[m, vb_] += -sg
                x = sg * (ps - pt_)
                here = x if x > dmin else dmin
                top = dmin + margin
                h[m] = (here if here < top else top) - sg * (ca_ - cb_)
                m += 1
    return nv, free, sig, vix, cst, x_own, var_robot, var_edge, gmat, h, m, dmat, dcon, travel_row


def build_programme(
    fs: Any,
    cells: list[Any],
    p0: Any,
    p1: Any,
    speeds: tuple[float, float],
    m_search: float,
    w_search: float,
    terms_of: dict[tuple[int, int], list[tuple[float, float, float]]],
) -> graph_corners.Programme | None:
    """:func:`mpa.planners.corners._programme` compiled: the same :class:`~mpa.planners.corners.Programme`, bit for
    bit (module docstring); the same arguments."""
    n = len(cells)
    terms_cells = [graph_corners._terms(fs, int(c[0]), int(c[1]), terms_of) for c in cells]
    tptr = np.zeros(n + 1, np.int64)
    np.cumsum([len(t) for t in terms_cells], out=tptr[1:])
    terms = np.array(list(itertools.chain.from_iterable(terms_cells)), dtype=np.float64).reshape(-1, 3)
    lengths = fs.geometry.lengths
    tol = 1.0 + 0.5 * graph_corners.RESOLVE_TOL
    out = _programme_arrays(
        np.array(cells, dtype=np.int64).reshape(n, 3), p0, p1, float(speeds[0]), float(speeds[1]),
        np.ascontiguousarray(lengths, dtype=np.float64), tptr, terms, float(fs._dmin), 0.5 * fs.tol,
        -m_search * tol, w_search * tol, bool(graph_corners.DROP_IMPLIED_ROWS),
    )  # fmt: skip
    nv, free, sig, vix, cst, x_own, var_robot, var_edge, gmat, h, m, dmat, dcon, travel_row = out
    if nv == 0:
        return None
    sig_l = sig.tolist()
    return graph_corners.Programme(
        int(nv), free.tolist(), (sig_l[0], sig_l[1]), vix.tolist(), cst.tolist(), x_own, var_robot.tolist(),
        var_edge.tolist(), gmat[:m], h[:m], dmat, dcon, int(travel_row),
    )  # fmt: skip


def warm() -> None:
    """Compile :func:`_programme_arrays`, or load it from numba's on-disk cache: the programme of a chain of two
    segments on a Y junction (:func:`trajopt.plan_kernel.warm` calls it after the search's kernels; called alone, it
    lets another process compile the search meanwhile)."""
    from mpa.freespace import free_space
    from mpa.graph_track import GraphTrack

    track = GraphTrack.from_layout({"edges": [["J", "a", 2.0], ["J", "b", 2.0], ["J", "c", 2.0]]})
    fs = free_space(track, 0.5)
    p0 = np.array([[1.5, 1.5], [1.0, 1.2]])
    p1 = np.array([[1.0, 1.2], [0.5, 1.0]])
    build_programme(fs, [(0, 1, 0), (0, 1, 0)], p0, p1, (1.0, 1.0), 2.0, 2.0, {})
