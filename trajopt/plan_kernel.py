"""The graph planner's exact any-angle search (:class:`mpa.planners.graph.search.AnyAngleSearch`), compiled by numba.

:mod:`mpa` is numpy and scipy only, and its search runs in the interpreter: 12-22 µs per node, and the slow queries
of a large map take 20 000-40 000 nodes (docs/performance.md). This module is the same search as loops over arrays,
compiled by numba, and :func:`install` hands it to :func:`mpa.planners.graph.query.plan_graph`
(:func:`mpa.planners.graph.use_search`). It is the search node for node: the same nodes in the same order, the
same floating-point operations in the same order (Python's :func:`math.hypot` included, :func:`_py_hypot`), so the
plans are the same bit for bit; the tests check it on thousands of queries.

The free space's polygons, faces and points are named by integers and written into arrays as the search first
reaches them (:class:`_MeshArrays`, kept with the mesh across queries); the kernel (:func:`_run`) stops and asks
(:data:`NEED_PAGES`, :data:`NEED_MEMBERS`) when it needs a part not written yet, before it takes the node that needs
it from the queue, and resumes where it stopped. The passing bound's fronts of hinges are made in the kernel
(:func:`_front`) from the bound's segments, by the operations of :class:`~mpa.planners.graph.bounds.PassingBound`.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from mpa.planners.graph import bounds as graph_bounds
from mpa.planners.graph import search as graph_search
from mpa.planners.graph.base import TIE_BREAK, TIE_BREAK_2
from mpa.planners.graph.search import GOAL, START
from trajopt._numba import HAVE_NUMBA, kernel_mode, njit

__all__ = ["CompiledSearch", "install", "installed"]

# node kinds (column 0 of the node ints)
_POINT, _FACE, _INTERVAL = 0, 1, 2
# node ints: kind, key (a point's) or root key, root, last (a point's) or parent, polygon, ax, face, previous
# polygon, origin's polygon
_NI = 9
# node floats: g or g_root, r (or a point's frm), sig (or a point's to), a, y0, y1, lo, hi, previous a, origin
_NF = 13
# what the kernel returns
FOUND, STOPPED, NEED_PAGES, NEED_MEMBERS, EMPTY = 0, 1, 2, 3, 4
# the counters: nodes, heap entries, interval cells, pops this run, the goal's node, the request (kind, 3 ints),
# the fronts' rows and slots, the segments on an edge's rows and slots
_C = 13
_START_ID, _GOAL_ID = 0, 1
_BOUND_SAFETY = graph_bounds.BOUND_SAFETY
_NO_LIMIT = 2**62


# fmt: off
# (the kernels' long argument lists are kept a few to a line)

# ------------------------------------------------------------------------------------------- scalar helpers
@njit(cache=True)
def _split(a: float) -> tuple[float, float]:  # pragma: no cover - compiled
    c = 134217729.0 * a  # Veltkamp: 2**27 + 1
    hi = c - (c - a)
    return hi, a - hi


@njit(cache=True)
def _two_prod(x: float, y: float) -> tuple[float, float]:  # pragma: no cover - compiled
    z = x * y
    xh, xl = _split(x)
    yh, yl = _split(y)
    return z, ((xh * yh - z) + xh * yl + xl * yh) + xl * yl


@njit(cache=True)
def _py_hypot(x: float, y: float) -> float:  # pragma: no cover - compiled
    """Python's :func:`math.hypot` of two finite numbers, bit for bit (CPython's ``vector_norm``: lossless scaling,
    squaring and summation, then one differential correction); C's ``hypot`` differs from it in the last bit on
    about 0.2 % of arguments."""
    x, y = abs(x), abs(y)
    mx = x if x > y else y
    if mx == 0.0 or math.isinf(mx):
        return mx
    _, e = math.frexp(mx)
    if e < -1023:  # CPython rescales deep subnormals first; not met by the search (times and metres): C's hypot
        return math.hypot(x, y)
    scale = math.ldexp(1.0, -e)
    csum, frac1, frac2 = 1.0, 0.0, 0.0
    for v in (x, y):
        v *= scale
        phi, plo = _two_prod(v, v)
        s = csum + phi
        slo = (csum - s) + phi
        csum = s
        frac1 += plo
        frac2 += slo
    h = math.sqrt(csum - 1.0 + (frac1 + frac2))
    phi, plo = _two_prod(-h, h)
    s = csum + phi
    slo = (csum - s) + phi
    csum = s
    frac1 += plo
    frac2 += slo
    z = csum - 1.0 + (frac1 + frac2)
    h += z / (2.0 * h)
    return h / scale


@njit(cache=True)
def _hypot_many(xy: Any) -> Any:  # pragma: no cover - compiled
    """:func:`_py_hypot` of each row of ``xy`` (shape (N, 2)); shape (N,). For the tests."""
    out = np.empty(xy.shape[0])
    for i in range(xy.shape[0]):
        out[i] = _py_hypot(xy[i, 0], xy[i, 1])
    return out


@njit(cache=True)
def _cost(dx: float, dy: float, fastest: bool, va: float, vb: float) -> float:  # pragma: no cover - compiled
    """:func:`mpa.planners.search_common.cost_function`'s cost, the same operations."""
    if fastest:
        ta, tb = abs(dx) / va, abs(dy) / vb
        m = ta if ta >= tb else tb
        return m + TIE_BREAK * (ta + tb) + TIE_BREAK_2 * _py_hypot(ta, tb)
    return _py_hypot(dx, dy)


@njit(cache=True)
def _floor(x: float) -> int:  # pragma: no cover - compiled
    return math.floor(x)


# ------------------------------------------------------------------------------------------------- heap
@njit(cache=True)
def _less(hk: Any, hd: Any, i: int, j: int) -> bool:  # pragma: no cover - compiled
    if hk[i, 0] != hk[j, 0]:
        return hk[i, 0] < hk[j, 0]
    if hd[i] != hd[j]:
        return hd[i] < hd[j]
    return hk[i, 1] < hk[j, 1]


@njit(cache=True)
def _heap_push(hk: Any, hd: Any, c: Any, key: int, depth: float, nid: int) -> None:  # pragma: no cover - compiled
    i = c[1]
    c[1] += 1
    hk[i, 0], hk[i, 1], hd[i] = key, nid, depth
    while i > 0:
        p = (i - 1) >> 1
        if _less(hk, hd, i, p):
            hk[i, 0], hk[p, 0] = hk[p, 0], hk[i, 0]
            hk[i, 1], hk[p, 1] = hk[p, 1], hk[i, 1]
            hd[i], hd[p] = hd[p], hd[i]
            i = p
        else:
            break


@njit(cache=True)
def _heap_pop(hk: Any, hd: Any, c: Any) -> tuple[int, float, int]:  # pragma: no cover - compiled
    key, nid, depth = hk[0, 0], hk[0, 1], hd[0]
    n = c[1] - 1
    c[1] = n
    if n > 0:
        hk[0, 0], hk[0, 1], hd[0] = hk[n, 0], hk[n, 1], hd[n]
        i = 0
        while True:
            a = 2 * i + 1
            if a >= n:
                break
            b = a + 1
            m = b if b < n and _less(hk, hd, b, a) else a
            if _less(hk, hd, m, i):
                hk[i, 0], hk[m, 0] = hk[m, 0], hk[i, 0]
                hk[i, 1], hk[m, 1] = hk[m, 1], hk[i, 1]
                hd[i], hd[m] = hd[m], hd[i]
                i = m
            else:
                break
    return key, depth, nid


# ------------------------------------------------------------------------------------------------ nodes
@njit(cache=True)
def _lower_bound(pi: Any, p: int, s: float, t: float, gd: Any, gi: Any, par: Any) -> float:  # pragma: no cover
    """:meth:`AnyAngleSearch.lower_bound` at ``(s, t)`` in the polygon ``p``."""
    e = pi[p, 2]
    x, d = s + gd[0, e], gd[1, e] - s
    da = d if d < x else x
    if e == gi[2]:
        x = abs(s - par[7])
        da = x if x < da else da
    e = pi[p, 3]
    x, d = t + gd[2, e], gd[3, e] - t
    db = d if d < x else x
    if e == gi[3]:
        x = abs(t - par[8])
        db = x if x < db else db
    if gi[0]:
        ta, tb = abs(da) / par[2], abs(db) / par[3]
        return (tb if tb > ta else ta) + TIE_BREAK * (ta + tb) + TIE_BREAK_2 * _py_hypot(ta, tb)
    return _py_hypot(da, db)


@njit(cache=True)
def _push_point(
    ni: Any, nf: Any, pend: Any, hk: Any, hd: Any, c: Any, best: Any, pi: Any, gd: Any, gi: Any, par: Any,
    key: int, gval: float, root: int, last: int, p: int, f0: float, f1: float, t0: float, t1: float,
) -> None:  # pragma: no cover - compiled
    """:meth:`AnyAngleSearch.push_point` (``f0`` NaN: no ``frm``)."""
    is_goal = key == _GOAL_ID
    if gval < best[key] - (0.0 if is_goal else par[4]):
        best[key] = gval
        n = c[0]
        c[0] = n + 1
        ni[n, 0], ni[n, 1], ni[n, 2], ni[n, 3], ni[n, 4] = _POINT, key, root, last, p
        nf[n, 0], nf[n, 1], nf[n, 2], nf[n, 3], nf[n, 4] = gval, f0, f1, t0, t1
        f = gval if is_goal else gval + _lower_bound(pi, p, t0, t1, gd, gi, par)
        pend[n] = gi[1] != 0 and not is_goal
        _heap_push(hk, hd, c, _floor(f * par[5]), -gval, n)


@njit(cache=True)
def _min_along(
    cp: float, cm: float, on_edge: bool, off: float, y0: float, y1: float, r: float
) -> float:  # pragma: no cover - compiled
    """:meth:`GoalDistance.min_along` (``cp``, ``cm`` of the edge), the same operations."""
    u = y0 - r
    w = r - y1
    a = cp + r + 2.0 * (u if u > 0.0 else 0.0)
    b = cm - r + 2.0 * (w if w > 0.0 else 0.0)
    v = b if b < a else a
    if on_edge:
        y = r if r >= y0 else y0
        y = y1 if y1 < y else y
        x = abs(y - r) + abs(y - off)
        v = x if x < v else v
    return v


@njit(cache=True)
def _new_face_entry(
    ni: Any, nf: Any, pend: Any, hk: Any, hd: Any, c: Any, gd: Any, vd: Any, gi: Any, par: Any, fi: Any,
    root: int, root_key: int, g_root: float, r0: float, r1: float, s0: float, s1: float, ax: int, a: float,
    y0: float, y1: float, p: int, face: int, lo: float, hi: float, parent: int, op: int, o0: float, o1: float,
    inline: bool,
) -> None:  # pragma: no cover - compiled
    """A :class:`FaceEntry` queued: :meth:`AnyAngleSearch.push_face` (``inline`` False) or the inline push of
    :meth:`AnyAngleSearch.expand_interval` (True); their bounds are the same value by slightly different
    expressions, each kept as written."""
    n = c[0]
    c[0] = n + 1
    ni[n, 0], ni[n, 1], ni[n, 2], ni[n, 3], ni[n, 4] = _FACE, root_key, root, parent, p
    ni[n, 5], ni[n, 6], ni[n, 8] = ax, face, op
    nf[n, 0], nf[n, 1], nf[n, 2], nf[n, 3], nf[n, 4] = g_root, r0, r1, s0, s1
    nf[n, 5], nf[n, 6], nf[n, 7], nf[n, 8], nf[n, 9] = a, y0, y1, lo, hi
    nf[n, 11], nf[n, 12] = o0, o1
    pend[n] = gi[1] != 0
    w, e = fi[face, 1], fi[face, 2]
    fastest = gi[0] != 0
    va, vb = par[2], par[3]
    if not inline:
        if ax == 0:
            da = abs(r0 - a) + vd[0, w]
            db = _min_along(gd[2, e], gd[3, e], e == gi[3], par[8], y0, y1, r1)
        else:
            da = _min_along(gd[0, e], gd[1, e], e == gi[2], par[7], y0, y1, r0)
            db = abs(r1 - a) + vd[1, w]
        f = g_root + _cost(da, db, fastest, va, vb)
    else:
        if ax == 0:
            x_v, rr = abs(r0 - a) + vd[0, w], r1
            cp, cm, edge, off = gd[2, e], gd[3, e], gi[3], par[8]
        else:
            x_v, rr = abs(r1 - a) + vd[1, w], r0
            cp, cm, edge, off = gd[0, e], gd[1, e], gi[2], par[7]
        t0, t1 = y0 - rr, rr - y1
        lo_v = cp + rr + 2.0 * (t0 if t0 > 0.0 else 0.0)
        hi_v = cm - rr + 2.0 * (t1 if t1 > 0.0 else 0.0)
        x_e = hi_v if hi_v < lo_v else lo_v
        if e == edge:
            y = y0 if y0 > rr else rr
            y = y1 if y1 < y else y
            t0 = abs(y - rr) + abs(y - off)
            x_e = t0 if t0 < x_e else x_e
        if ax == 0:
            da, db = x_v, x_e
        else:
            da, db = x_e, x_v
        if fastest:
            ta, tb = abs(da) / va, abs(db) / vb
            f = g_root + ((tb if tb > ta else ta) + TIE_BREAK * (ta + tb) + TIE_BREAK_2 * _py_hypot(ta, tb))
        else:
            f = g_root + _py_hypot(da, db)
    _heap_push(hk, hd, c, _floor(f * par[5]), -g_root, n)


@njit(cache=True)
def _expand_point(
    ni: Any, nf: Any, pend: Any, hk: Any, hd: Any, c: Any, best: Any, pi: Any, si: Any, sf: Any, fi: Any,
    gd: Any, vd: Any, gi: Any, par: Any, goals_p: Any, goals_c: Any,
    nid: int, key: int, gval: float, mem_p: Any, mem_c: Any, m0: int, m1: int,
) -> None:  # pragma: no cover - compiled
    """:meth:`AnyAngleSearch.expand_point` over the members ``m0:m1`` of ``mem_p``, ``mem_c``."""
    fastest = gi[0] != 0
    va, vb, eps = par[2], par[3], par[1]
    for m in range(m0, m1):
        q = mem_p[m]
        rc0, rc1 = mem_c[m, 0], mem_c[m, 1]
        for j in range(goals_p.shape[0]):
            if goals_p[j] == q:
                pt0, pt1 = goals_c[j, 0], goals_c[j, 1]
                _push_point(
                    ni, nf, pend, hk, hd, c, best, pi, gd, gi, par,
                    _GOAL_ID, gval + _cost(pt0 - rc0, pt1 - rc1, fastest, va, vb), nid, -1, q, rc0, rc1, pt0, pt1,
                )
        for k in range(pi[q, 0], pi[q, 0] + pi[q, 1]):
            ax2, face2, a2, lo2, hi2 = si[k, 0], si[k, 1], sf[k, 0], sf[k, 1], sf[k, 2]
            on_line = (rc0 if ax2 == 0 else rc1) == a2
            for end in range(2 if hi2 > lo2 else 1):
                if end == 0:
                    k2, pt0, pt1 = si[k, 2], sf[k, 3], sf[k, 4]
                else:
                    k2, pt0, pt1 = si[k, 3], sf[k, 5], sf[k, 6]
                if pt0 == rc0 and pt1 == rc1:
                    continue
                _push_point(
                    ni, nf, pend, hk, hd, c, best, pi, gd, gi, par,
                    k2, gval + _cost(pt0 - rc0, pt1 - rc1, fastest, va, vb), nid, -1, q, rc0, rc1, pt0, pt1,
                )
            if on_line or hi2 - lo2 <= eps:
                continue
            _new_face_entry(
                ni, nf, pend, hk, hd, c, gd, vd, gi, par, fi,
                nid, key, gval, rc0, rc1, 1.0, 1.0, ax2, a2, lo2, hi2, q, face2, lo2, hi2, nid, q, rc0, rc1, False,
            )


@njit(cache=True)
def _expand_interval(
    ni: Any, nf: Any, pend: Any, hk: Any, hd: Any, c: Any, best: Any, pi: Any, si: Any, sf: Any, fi: Any,
    gd: Any, vd: Any, gi: Any, par: Any, goals_p: Any, goals_c: Any, nid: int,
) -> None:  # pragma: no cover - compiled
    """:meth:`AnyAngleSearch.expand_interval` of the interval node ``nid``."""
    ctol, eps, va, vb, again = par[0], par[1], par[2], par[3], par[4]
    fastest = gi[0] != 0
    rid, ax, pid, root_key = ni[nid, 2], ni[nid, 5], ni[nid, 4], ni[nid, 1]
    groot, rs, rt, sg0, sg1 = nf[nid, 0], nf[nid, 1], nf[nid, 2], nf[nid, 3], nf[nid, 4]
    a, y0, y1 = nf[nid, 5], nf[nid, 6], nf[nid, 7]
    if ax == 0:
        u00, u01, u10, u11 = a - rs, y0 - rt, a - rs, y1 - rt
    else:
        u00, u01, u10, u11 = y0 - rs, a - rt, y1 - rs, a - rt
    cr = u00 * u11 - u01 * u10
    if abs(cr) <= ctol:
        return
    sgn = 1.0 if cr > 0 else -1.0
    nsg = -sgn
    for j in range(goals_p.shape[0]):
        if goals_p[j] == pid:
            pt0, pt1 = goals_c[j, 0], goals_c[j, 1]
            dx, dy = pt0 - rs, pt1 - rt
            if sgn * (u00 * dy - u01 * dx) >= -ctol and nsg * (u10 * dy - u11 * dx) >= -ctol:
                _push_point(
                    ni, nf, pend, hk, hd, c, best, pi, gd, gi, par,
                    _GOAL_ID, groot + _cost(pt0 - rs, pt1 - rt, fastest, va, vb), rid, nid, pid, np.nan, np.nan,
                    pt0, pt1,
                )
    nctol = -ctol
    ca0_a, ca1_a = sgn * u00, nsg * u10
    m0_a, m1_a = -u00 * rt, -u10 * rt
    ca0_b, ca1_b = sgn * -u01, nsg * -u11
    m0_b, m1_b = u01 * rs, u11 * rs
    inf = math.inf
    for k in range(pi[pid, 0], pi[pid, 0] + pi[pid, 1]):
        ax2, face2, a2, lo2, hi2 = si[k, 0], si[k, 1], sf[k, 0], sf[k, 1], sf[k, 2]
        if ax2 == 0:
            if ax == 0 and a2 == a:
                continue
            if (rs - a2 if a2 == 0.0 else a2 - rs) <= eps:
                continue
            d_a = a2 - rs
            ca0, cb0 = ca0_a, sgn * (m0_a - u01 * d_a)
            ca1, cb1 = ca1_a, nsg * (m1_a - u11 * d_a)
        else:
            if ax == 1 and a2 == a:
                continue
            if (rt - a2 if a2 == 0.0 else a2 - rt) <= eps:
                continue
            d_a = a2 - rt
            ca0, cb0 = ca0_b, sgn * (u00 * d_a + m0_b)
            ca1, cb1 = ca1_b, nsg * (u10 * d_a + m1_b)
        yl, yh = lo2, hi2
        if ca0 > 0.0:
            v = (nctol - cb0) / ca0
            if v > yl:
                yl = v
        elif ca0 < 0.0:
            v = (nctol - cb0) / ca0
            if v < yh:
                yh = v
        elif cb0 < nctol:
            yl, yh = 1.0, 0.0
        if ca1 > 0.0:
            v = (nctol - cb1) / ca1
            if v > yl:
                yl = v
        elif ca1 < 0.0:
            v = (nctol - cb1) / ca1
            if v < yh:
                yh = v
        elif cb1 < nctol:
            yl, yh = 1.0, 0.0
        if yl > yh + eps:
            continue
        for end in range(2):
            if end == 0:
                if not yl <= lo2 + eps:
                    continue
                yl = lo2
                kk, p0, p1 = si[k, 2], sf[k, 3], sf[k, 4]
            else:
                if not yh >= hi2 - eps:
                    continue
                yh = hi2
                kk, p0, p1 = si[k, 3], sf[k, 5], sf[k, 6]
            dx, dy = p0 - rs, p1 - rt
            limit = best[kk] - again
            if fastest:
                ta, tb = abs(dx) / va, abs(dy) / vb
                m = tb if tb > ta else ta
                if groot + m < limit:
                    g2 = groot + (m + TIE_BREAK * (ta + tb) + TIE_BREAK_2 * _py_hypot(ta, tb))
                    if g2 < limit:
                        _push_point(
                            ni, nf, pend, hk, hd, c, best, pi, gd, gi, par,
                            kk, g2, rid, nid, pid, np.nan, np.nan, p0, p1,
                        )
            else:
                g2 = groot + _py_hypot(dx, dy)
                if g2 < limit:
                    _push_point(
                        ni, nf, pend, hk, hd, c, best, pi, gd, gi, par,
                        kk, g2, rid, nid, pid, np.nan, np.nan, p0, p1,
                    )
        if yh - yl <= eps:
            continue
        _new_face_entry(
            ni, nf, pend, hk, hd, c, gd, vd, gi, par, fi,
            rid, root_key, groot, rs, rt, sg0, sg1, ax2, a2, yl, yh, pid, face2, lo2, hi2, nid, ni[nid, 8],
            nf[nid, 11], nf[nid, 12], True,
        )
    _ = inf


@njit(cache=True)
def _uncovered(
    seen: Any, sk: Any, iv: Any, ivn: Any, c: Any, y0: float, y1: float, eps: float, out: Any
) -> int:  # pragma: no cover - compiled
    """:func:`mpa.planners.graph.search._uncovered`: the parts of ``[y0, y1]`` not recorded under ``sk`` into
    ``out`` (their number returned), the union recorded (a list of cells ``iv`` linked by ``ivn``)."""
    head = seen[sk]
    if ivn[head] < 0:  # one interval
        z0, z1 = iv[head, 0], iv[head, 1]
        if z1 >= y0 and z0 <= y1 and z0 <= y0 + eps and z1 >= y1 - eps:
            return 0
    n_out = 0
    cur = y0
    i = head
    while i >= 0:
        z0, z1 = iv[i, 0], iv[i, 1]
        i = ivn[i]
        if z1 < cur:
            continue
        if z0 > y1:
            break
        if z0 > cur + eps:
            out[n_out, 0], out[n_out, 1] = cur, z0
            n_out += 1
        cur = max(cur, z1)
    if cur < y1 - eps:
        out[n_out, 0], out[n_out, 1] = cur, y1
        n_out += 1
    if n_out:
        # sorted([*have, (y0, y1)]) merged: have is sorted and disjoint, insert (y0, y1) in order
        count = 0
        i = head
        while i >= 0:
            count += 1
            i = ivn[i]
        items = np.empty((count + 1, 2))
        i, j, placed = head, 0, False
        while i >= 0 or not placed:
            if not placed and (i < 0 or y0 < iv[i, 0] or (y0 == iv[i, 0] and y1 < iv[i, 1])):
                items[j, 0], items[j, 1] = y0, y1
                placed = True
            else:
                items[j, 0], items[j, 1] = iv[i, 0], iv[i, 1]
                i = ivn[i]
            j += 1
        prev = -1
        first = -1
        for j in range(count + 1):
            z0, z1 = items[j, 0], items[j, 1]
            if prev >= 0 and z0 <= iv[prev, 1]:
                iv[prev, 1] = max(iv[prev, 1], z1)
            else:
                cell = c[2]
                c[2] = cell + 1
                iv[cell, 0], iv[cell, 1], ivn[cell] = z0, z1, -1
                if prev >= 0:
                    ivn[prev] = cell
                else:
                    first = cell
                prev = cell
        seen[sk] = first
    return n_out


@njit(cache=True)
def _seen_key(
    rid: int, p2: int, ax: int, b: float, moved: float, k_kept: int, quantum: float
) -> Any:  # pragma: no cover - compiled
    """The key of :meth:`AnyAngleSearch.open_face`'s ``seen``: the side ``b`` (0 or the edge's length) as 0 / 1,
    Python's ``round`` (half to even) of the unfolded root's coordinates on the grid ``1 / quantum``."""
    km = int(np.rint(moved * quantum))
    if ax == 0:
        return (rid, p2, 0, 0 if b == 0.0 else 1, km, k_kept)
    return (rid, p2, 1, 0 if b == 0.0 else 1, k_kept, km)


@njit(cache=True)
def _page_open(pi: Any, goals_p: Any, p2: int) -> bool:  # pragma: no cover - compiled
    """:meth:`AnyAngleSearch.pages_to_open`'s test: not a dead end, or it holds the goal."""
    if pi[p2, 1] != 1:
        return True
    for j in range(goals_p.shape[0]):
        if goals_p[j] == p2:
            return True
    return False


@njit(cache=True)
def _open_needs(
    ni: Any, nf: Any, fi: Any, pg: Any, pgb: Any, pi: Any, si: Any, goals_p: Any, seen: Any, ivn: Any,
    par: Any, nid: int,
) -> tuple[int, int]:  # pragma: no cover - compiled
    """At most how many nodes and interval cells :func:`_open_face` of the face entry ``nid`` makes."""
    face, ax, pid, rid = ni[nid, 6], ni[nid, 5], ni[nid, 4], ni[nid, 2]
    a, quantum = nf[nid, 5], par[6]
    r_ax = nf[nid, 1] if ax == 0 else nf[nid, 2]
    kept = nf[nid, 2] if ax == 0 else nf[nid, 1]
    k_kept = int(np.rint(kept * quantum))
    n1 = 1.0 if a == 0.0 else -1.0
    across = r_ax - a
    nodes, cells = 0, 0
    for j in range(fi[face, 3], fi[face, 3] + fi[face, 4]):
        p2, b = pg[j], pgb[j]
        if not _page_open(pi, goals_p, p2) or (p2 == pid and b == a):
            continue
        sg = -n1 if b == 0.0 else n1
        sk = _seen_key(rid, p2, ax, b, b + sg * across, k_kept, quantum)
        count = 0
        if sk in seen:
            i = seen[sk]
            while i >= 0:
                count += 1
                i = ivn[i]
        cells += count + 2
        nodes += (count + 1) * (2 + goals_p.shape[0] + 3 * pi[p2, 1])
    return nodes, cells


@njit(cache=True)
def _open_face(
    ni: Any, nf: Any, pend: Any, hk: Any, hd: Any, c: Any, best: Any, pi: Any, si: Any, sf: Any, fi: Any,
    pg: Any, pgb: Any, gd: Any, vd: Any, gi: Any, par: Any, goals_p: Any, goals_c: Any, seen: Any, iv: Any,
    ivn: Any, parts: Any, nid: int,
) -> None:  # pragma: no cover - compiled
    """:meth:`AnyAngleSearch.open_face` of the face entry ``nid``."""
    face, ax, pid, rid, root_key = ni[nid, 6], ni[nid, 5], ni[nid, 4], ni[nid, 2], ni[nid, 1]
    g_root, r0, r1, sig0, sig1 = nf[nid, 0], nf[nid, 1], nf[nid, 2], nf[nid, 3], nf[nid, 4]
    a, y0, y1, lo, hi = nf[nid, 5], nf[nid, 6], nf[nid, 7], nf[nid, 8], nf[nid, 9]
    parent, op, o0, o1 = ni[nid, 3], ni[nid, 8], nf[nid, 11], nf[nid, 12]
    quantum, eps = par[6], par[1]
    n1 = 1.0 if a == 0.0 else -1.0
    across = (r0 if ax == 0 else r1) - a
    kept = r1 if ax == 0 else r0
    k_kept = int(np.rint(kept * quantum))
    for j in range(fi[face, 3], fi[face, 3] + fi[face, 4]):
        p2, b = pg[j], pgb[j]
        if not _page_open(pi, goals_p, p2):
            continue
        if p2 == pid and b == a:
            continue
        sg = -n1 if b == 0.0 else n1
        moved = b + sg * across
        if ax == 0:
            q0, q1, s0, s1 = moved, kept, sg * sig0, sig1
        else:
            q0, q1, s0, s1 = kept, moved, sig0, sg * sig1
        sk = _seen_key(rid, p2, ax, b, moved, k_kept, quantum)
        if sk not in seen:
            cell = c[2]
            c[2] = cell + 1
            iv[cell, 0], iv[cell, 1], ivn[cell] = y0, y1, -1
            seen[sk] = cell
            parts[0, 0], parts[0, 1] = y0, y1
            n_parts = 1
        else:
            n_parts = _uncovered(seen, sk, iv, ivn, c, y0, y1, eps, parts)
        for m in range(n_parts):
            z0, z1 = parts[m, 0], parts[m, 1]
            n = c[0]
            c[0] = n + 1
            ni[n, 0], ni[n, 1], ni[n, 2], ni[n, 3], ni[n, 4] = _INTERVAL, root_key, rid, parent, p2
            ni[n, 5], ni[n, 6], ni[n, 7], ni[n, 8] = ax, face, pid, op
            nf[n, 0], nf[n, 1], nf[n, 2], nf[n, 3], nf[n, 4] = g_root, q0, q1, s0, s1
            nf[n, 5], nf[n, 6], nf[n, 7], nf[n, 8], nf[n, 9] = b, z0, z1, lo, hi
            nf[n, 10], nf[n, 11], nf[n, 12] = a, o0, o1
            pend[n] = False
            _expand_interval(ni, nf, pend, hk, hd, c, best, pi, si, sf, fi, gd, vd, gi, par, goals_p, goals_c, n)


# ------------------------------------------------------------------------------------------- passing bound
@njit(cache=True)
def _least_front(fr: Any, frs: Any, slot: int, s1: float, s2: float, y: float) -> float:  # pragma: no cover
    """The least of ``max(c1 + s1 y, c2 + s2 y)`` over the front in ``slot`` (:meth:`PassingBound.least_through`)."""
    best = math.inf
    for i in range(frs[slot, 0], frs[slot, 0] + frs[slot, 1]):
        u = fr[i, 0] + s1 * y
        v = fr[i, 1] + s2 * y
        m = u if u >= v else v
        if m < best:
            best = m
    return best


@njit(cache=True)
def _to_stretch(dv: Any, bgi: Any, bd: Any, x: int, e: int, u0: float, u1: float) -> float:  # pragma: no cover
    """The distance from the vertex ``x`` to the stretch ``[u0, u1]`` of edge ``e`` (m), as the bound's numpy."""
    a = dv[x, bgi[0, e]] + u0
    b = dv[x, bgi[1, e]] + bd[1, e] - u1
    return b if b < a else a


@njit(cache=True)
def _front(
    c: Any, fronts: Any, fr: Any, frs: Any, dv: Any, bgi: Any, bd: Any, segi: Any, segf: Any, bpar: Any,
    ax: int, w: int, x: int,
) -> int:  # pragma: no cover - compiled
    """The slot of :meth:`PassingBound._front` ``(ax, w, x)``, made and kept when first asked for (the arrays hold
    room for one more front of every segment): the same hinges ``c1``, ``c2`` by the same operations, and the same
    least over them (a front of another order among equal ``c1`` has the same least)."""
    key = (ax, w, x)
    if key in fronts:
        return fronts[key]
    v_w = bpar[2] if ax == 0 else bpar[3]
    v_e = bpar[3] if ax == 0 else bpar[2]
    s1, s2 = TIE_BREAK / v_e, (1.0 + TIE_BREAK) / v_e
    n = segi.shape[1]
    c1 = np.empty(n)
    c2 = np.empty(n)
    least = math.inf
    for k in range(n):
        if ax == 0:
            dw = _to_stretch(dv, bgi, bd, w, segi[0, k], segf[0, k], segf[1, k])
            d = _to_stretch(dv, bgi, bd, x, segi[1, k], segf[2, k], segf[3, k])
        else:
            dw = _to_stretch(dv, bgi, bd, w, segi[1, k], segf[2, k], segf[3, k])
            d = _to_stretch(dv, bgi, bd, x, segi[0, k], segf[0, k], segf[1, k])
        a = dw / v_w
        c1[k] = (1.0 + TIE_BREAK) * a + segf[4, k] + s1 * d
        c2[k] = TIE_BREAK * a + segf[4, k] + s2 * d
        m = c1[k] if c1[k] >= c2[k] else c2[k]
        if m < least:
            least = m
    near = np.nonzero(c2 <= least)[0]
    order = near[np.argsort(c1[near])]
    j0 = c[9]
    j = j0
    low = math.inf
    for k in order:
        if j == j0 or c2[k] < low:
            fr[j, 0], fr[j, 1] = c1[k], c2[k]
            j += 1
        if c2[k] < low:
            low = c2[k]
    c[9] = j
    slot = c[10]
    c[10] = slot + 1
    frs[slot, 0], frs[slot, 1] = j0, j - j0
    fronts[key] = slot
    return slot


@njit(cache=True)
def _on_edge(
    c: Any, ons: Any, on: Any, onr: Any, dv: Any, bgi: Any, bd: Any, segi: Any, segf: Any, bpar: Any,
    ax: int, w: int, other: int,
) -> int:  # pragma: no cover - compiled
    """The slot of the segments on the face's own edge (:meth:`PassingBound._parts`): the vertex robot's time, ``W_k``
    and the stretch on the edge, made and kept when first asked for."""
    key = (ax, w, other)
    if key in ons:
        return ons[key]
    v_w = bpar[2] if ax == 0 else bpar[3]
    j0 = c[11]
    j = j0
    for k in range(segi.shape[1]):
        if ax == 0:
            if segi[1, k] != other:
                continue
            dw = _to_stretch(dv, bgi, bd, w, segi[0, k], segf[0, k], segf[1, k])
            z0, z1 = segf[2, k], segf[3, k]
        else:
            if segi[0, k] != other:
                continue
            dw = _to_stretch(dv, bgi, bd, w, segi[1, k], segf[2, k], segf[3, k])
            z0, z1 = segf[0, k], segf[1, k]
        on[j, 0], on[j, 1], on[j, 2], on[j, 3] = dw / v_w, segf[4, k], z0, z1
        j += 1
    c[11] = j
    slot = c[12]
    c[12] = slot + 1
    onr[slot, 0], onr[slot, 1] = j0, j - j0
    ons[key] = slot
    return slot


@njit(cache=True)
def _entry(
    c: Any, dv: Any, bgi: Any, bd: Any, segi: Any, segf: Any, bpar: Any, fronts: Any, fr: Any, frs: Any,
    ons: Any, on: Any, onr: Any, ax: int, w: int, other: int, y0: float, y1: float,
) -> float:  # pragma: no cover - compiled
    """:meth:`PassingBound.entry` of the face ``(ax, w, other)`` over ``[y0, y1]``. ``dv``: the layout's vertex
    distances; ``bgi``: tails, heads; ``bd``: the bound vertex's distances (row 0), the edges' lengths (row 1);
    ``segi``, ``segf``: the passing segments' edges ``e, f`` and ``u0, u1, v0, v1, W``; ``bpar``: sign, the bound at
    the start, vA, vB."""
    sign, va, vb = bpar[0], bpar[2], bpar[3]
    t_e, h_e = bgi[0, other], bgi[1, other]
    lo_e = bd[0, t_e]
    hi_e = bd[0, h_e]
    le = bd[1, other]
    a0, b0 = y0 + lo_e, le - y0 + hi_e
    ph0 = b0 if b0 < a0 else a0
    a1, b1 = y1 + lo_e, le - y1 + hi_e
    ph1 = b1 if b1 < a1 else a1
    peak = 0.5 * (le + hi_e - lo_e)
    if y0 < peak < y1:
        u, v = peak + lo_e, le - peak + hi_e
        third = v if v < u else u
    else:
        third = -math.inf
    top = ph0
    if ph1 > top:
        top = ph1
    if third > top:
        top = third
    lowest = ph1 if ph1 < ph0 else ph0
    if ax == 0:
        ok = sign * bd[0, w] <= (sign * lowest if sign > 0 else -top)
    else:
        ok = (sign * top if sign > 0 else -lowest) <= sign * bd[0, w]
    if not ok:
        return 0.0
    v_e = vb if ax == 0 else va
    s1, s2 = TIE_BREAK / v_e, (1.0 + TIE_BREAK) / v_e
    yh = le - y1
    bt = _least_front(fr, frs, _front(c, fronts, fr, frs, dv, bgi, bd, segi, segf, bpar, ax, w, t_e), s1, s2, y0)
    bh = _least_front(fr, frs, _front(c, fronts, fr, frs, dv, bgi, bd, segi, segf, bpar, ax, w, h_e), s1, s2, yh)
    best = bh if bh < bt else bt
    slot = _on_edge(c, ons, on, onr, dv, bgi, bd, segi, segf, bpar, ax, w, other)
    if onr[slot, 1]:
        inv = 1.0 / v_e
        for i in range(onr[slot, 0], onr[slot, 0] + onr[slot, 1]):
            a_k, w_k, z0, z1 = on[i, 0], on[i, 1], on[i, 2], on[i, 3]
            x = 0.0
            u = z0 - y1
            if u > x:
                x = u
            u = y0 - z1
            if u > x:
                x = u
            x = x * inv
            m = a_k if a_k >= x else x
            val = m + TIE_BREAK * (a_k + x) + w_k
            if val < best:
                best = val
    return best * (1.0 - _BOUND_SAFETY)


@njit(cache=True)
def _point_bound(
    c: Any, ti: Any, tf: Any, dv: Any, bgi: Any, bd: Any, segi: Any, segf: Any, bpar: Any, fronts: Any, fr: Any,
    frs: Any, ons: Any, on: Any, onr: Any, key: int,
) -> float:  # pragma: no cover - compiled
    """:meth:`PassingBound.point` of the point ``key`` (its face and coordinate in ``ti``, ``tf``)."""
    if key == _START_ID:
        return bpar[1]
    return _entry(c, dv, bgi, bd, segi, segf, bpar, fronts, fr, frs, ons, on, onr, ti[key, 2], ti[key, 3],
                  ti[key, 4], tf[key], tf[key])


@njit(cache=True)
def _grow(a: Any, need: int) -> Any:  # pragma: no cover - compiled
    """``a`` (2-D) with at least ``need`` rows, doubled."""
    if need <= a.shape[0]:
        return a
    n = a.shape[0]
    while n < need:
        n *= 2
    out = np.empty((n, a.shape[1]), a.dtype)
    out[: a.shape[0]] = a
    return out


@njit(cache=True)
def _grow1(a: Any, need: int) -> Any:  # pragma: no cover - compiled
    """``a`` (1-D) with at least ``need`` items, doubled."""
    if need <= a.shape[0]:
        return a
    n = a.shape[0]
    while n < need:
        n *= 2
    out = np.empty(n, a.dtype)
    out[: a.shape[0]] = a
    return out


# ---------------------------------------------------------------------------------------------------- run
@njit(cache=True)
def _run(
    ni: Any, nf: Any, pend: Any, hk: Any, hd: Any, c: Any, best: Any, iv: Any, ivn: Any, seen: Any,
    pi: Any, si: Any, sf: Any, fi: Any, pg: Any, pgb: Any, ti: Any, tf: Any, mp: Any, mc: Any,
    gd: Any, vd: Any, gi: Any, par: Any, goals_p: Any, goals_c: Any,
    dv: Any, bgi: Any, bd: Any, segi: Any, segf: Any, bpar: Any, fronts: Any, fr: Any, frs: Any, ons: Any,
    on: Any, onr: Any, budget: int, over: int,
) -> tuple[int, Any, Any, Any, Any, Any, Any, Any, Any, Any, Any, Any]:  # pragma: no cover - compiled
    """:meth:`AnyAngleSearch._run` from the queue as it stands (the start expanded by the caller's first call):
    :data:`FOUND` (the goal's node in ``c[4]``), :data:`STOPPED` (at ``budget`` pops of this run, -1: none, or a
    key above ``over``), :data:`EMPTY`, or a request (``c[5:9]``); with the node, heap and interval arrays, grown."""
    parts = np.empty((64, 2))
    bounded = gi[1] != 0
    while c[1] > 0:
        key0, depth, nid = _heap_pop(hk, hd, c)
        c[3] += 1
        if (budget >= 0 and c[3] > budget) or key0 > over:
            _heap_push(hk, hd, c, key0, depth, nid)
            return STOPPED, ni, nf, pend, hk, hd, iv, ivn, fr, frs, on, onr
        kind = ni[nid, 0]
        if kind == _POINT:
            if ni[nid, 1] == _GOAL_ID:
                c[4] = nid
                return FOUND, ni, nf, pend, hk, hd, iv, ivn, fr, frs, on, onr
            if nf[nid, 0] > best[ni[nid, 1]]:
                continue
        elif nf[nid, 0] > best[ni[nid, 1]]:
            continue
        if bounded and pend[nid]:
            n_seg = segi.shape[1]  # room for the fronts and segments on an edge a bound can make (two of each)
            fr = _grow(fr, c[9] + 4 * n_seg + 1)
            frs = _grow(frs, c[10] + 5)
            on = _grow(on, c[11] + 2 * n_seg + 1)
            onr = _grow(onr, c[12] + 3)
            if kind == _POINT:
                h = _point_bound(c, ti, tf, dv, bgi, bd, segi, segf, bpar, fronts, fr, frs, ons, on, onr, ni[nid, 1])
                key1 = _floor((nf[nid, 0] + h) * par[5])
            else:
                g_root, r0, r1, a = nf[nid, 0], nf[nid, 1], nf[nid, 2], nf[nid, 5]
                y0, y1 = nf[nid, 6], nf[nid, 7]
                h0 = _point_bound(c, ti, tf, dv, bgi, bd, segi, segf, bpar, fronts, fr, frs, ons, on, onr, ni[nid, 1])
                face = ni[nid, 6]
                h1 = _entry(c, dv, bgi, bd, segi, segf, bpar, fronts, fr, frs, ons, on, onr, fi[face, 0], fi[face, 1],
                            fi[face, 2], y0, y1)
                if ni[nid, 5] == 0:
                    u, v = y0 - r1, r1 - y1
                    x_a = abs(r0 - a)
                    x_b = 0.0
                    if u > x_b:
                        x_b = u
                    if v > x_b:
                        x_b = v
                else:
                    u, v = y0 - r0, r0 - y1
                    x_a = 0.0
                    if u > x_a:
                        x_a = u
                    if v > x_a:
                        x_a = v
                    x_b = abs(r1 - a)
                f0 = g_root + h0
                f1 = g_root + _cost(x_a, x_b, gi[0] != 0, par[2], par[3]) + h1
                key1 = _floor((f0 if f0 >= f1 else f1) * par[5])
            pend[nid] = False
            if key1 > key0:
                _heap_push(hk, hd, c, key1, depth, nid)
                continue
        if kind == _POINT:
            key = ni[nid, 1]
            if ti[key, 1] < 0:
                c[5], c[6] = NEED_MEMBERS, key
                _heap_push(hk, hd, c, key0, depth, nid)
                c[3] -= 1
                return NEED_MEMBERS, ni, nf, pend, hk, hd, iv, ivn, fr, frs, on, onr
            m0, m1 = ti[key, 0], ti[key, 0] + ti[key, 1]
            need = 0
            for m in range(m0, m1):
                need += 2 + goals_p.shape[0] + 3 * pi[mp[m], 1]
            ni = _grow(ni, c[0] + need)
            nf = _grow(nf, c[0] + need)
            pend = _grow1(pend, c[0] + need)
            hk = _grow(hk, c[1] + need)
            hd = _grow1(hd, c[1] + need)
            _expand_point(ni, nf, pend, hk, hd, c, best, pi, si, sf, fi, gd, vd, gi, par, goals_p, goals_c,
                          nid, key, nf[nid, 0], mp, mc, m0, m1)
        else:
            face = ni[nid, 6]
            if fi[face, 4] < 0:
                c[5], c[6] = NEED_PAGES, face
                _heap_push(hk, hd, c, key0, depth, nid)
                c[3] -= 1
                return NEED_PAGES, ni, nf, pend, hk, hd, iv, ivn, fr, frs, on, onr
            need, cells = _open_needs(ni, nf, fi, pg, pgb, pi, si, goals_p, seen, ivn, par, nid)
            ni = _grow(ni, c[0] + need)
            nf = _grow(nf, c[0] + need)
            pend = _grow1(pend, c[0] + need)
            hk = _grow(hk, c[1] + need)
            hd = _grow1(hd, c[1] + need)
            iv = _grow(iv, c[2] + cells)
            ivn = _grow1(ivn, c[2] + cells)
            if parts.shape[0] < cells:
                parts = np.empty((cells, 2))
            _open_face(ni, nf, pend, hk, hd, c, best, pi, si, sf, fi, pg, pgb, gd, vd, gi, par, goals_p, goals_c,
                       seen, iv, ivn, parts, nid)
    return EMPTY, ni, nf, pend, hk, hd, iv, ivn, fr, frs, on, onr


@njit(cache=True)
def _start(
    ni: Any, nf: Any, pend: Any, hk: Any, hd: Any, c: Any, best: Any, pi: Any, si: Any, sf: Any, fi: Any,
    gd: Any, vd: Any, gi: Any, par: Any, goals_p: Any, goals_c: Any, mem_p: Any, mem_c: Any,
) -> None:  # pragma: no cover - compiled
    """The start's node and its expansion (:meth:`AnyAngleSearch._run`'s first lines); the arrays hold enough."""
    best[_START_ID] = 0.0
    ni[0, 0], ni[0, 1], ni[0, 2], ni[0, 3], ni[0, 4] = _POINT, _START_ID, -1, -1, -1
    nf[0, 0], nf[0, 1], nf[0, 2], nf[0, 3], nf[0, 4] = 0.0, np.nan, np.nan, np.nan, np.nan
    pend[0] = False
    c[0] = 1
    _expand_point(ni, nf, pend, hk, hd, c, best, pi, si, sf, fi, gd, vd, gi, par, goals_p, goals_c,
                  0, _START_ID, 0.0, mem_p, mem_c, 0, mem_p.shape[0])


# fmt: on


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
            s0 = self.si.reserve(len(sides))
            self.sf.reserve(len(sides))
            for k, (ax, a, face, lo, hi, k_lo, p_lo, k_hi, p_hi) in enumerate(sides):
                self.si.a[s0 + k] = (ax, self.face_id(face), self.point_id(k_lo), self.point_id(k_hi))
                self.sf.a[s0 + k] = (a, lo, hi, p_lo[0], p_lo[1], p_hi[0], p_hi[1])
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


@njit(cache=True)
def _new_dicts() -> Any:  # pragma: no cover - compiled
    """The search's ``seen`` (six ints to a cell) and its fronts and segments on an edge (three ints to a slot):
    made and filled in compiled code (numba compiles a typed dict's operations from Python in every process)."""
    seen = {}
    fronts = {}
    ons = {}
    seen[(0, 0, 0, 0, 0, 0)] = 0
    fronts[(0, 0, 0)] = 0
    ons[(0, 0, 0)] = 0
    seen.pop((0, 0, 0, 0, 0, 0))
    fronts.pop((0, 0, 0))
    ons.pop((0, 0, 0))
    return seen, fronts, ons


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
        self.seen, self.fronts, self.ons = _new_dicts()
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
        n = self.m.ti.n
        if n > self.best.shape[0]:
            out = np.full(max(n, 2 * self.best.shape[0]), math.inf)
            out[: self.best.shape[0]] = self.best
            self.best = out

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
                self.fr, self.frs, self.on, self.onr,
            ) = _run(
                self.ni, self.nf, self.pend, self.hk, self.hd, c, self.best, self.iv, self.ivn, self.seen,
                m.pi.a, m.si.a, m.sf.a, m.fi.a, m.pg.a, m.pgb.a, m.ti.a, m.tf.a, m.mp.a, m.mc.a,
                self.gd, self.vd, self.gi, self.par, self.goals_p, self.goals_c,
                self.dv, self.bgi, self.bd, self.segi, self.segf, self.bpar, self.fronts, self.fr, self.frs,
                self.ons, self.on, self.onr, -1 if budget is None else budget, over,
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


def installed() -> bool:
    """Whether :func:`mpa.planners.graph.query.plan_graph` searches with :class:`CompiledSearch`."""
    from mpa.planners.graph import query

    return query.compiled_search() is CompiledSearch


def install() -> bool:
    """Hand :class:`CompiledSearch` to the graph planner (:func:`mpa.planners.graph.query.use_search`) in a process
    whose kernels are compiled (:func:`trajopt._numba.kernel_mode` ``"numba"``, numba installed); a no-op in the
    ``"numpy"`` mode (a single command, numba not imported). Returns :func:`installed`."""
    from mpa.planners.graph import query

    if kernel_mode() == "numba" and HAVE_NUMBA:
        query.use_search(CompiledSearch)
    return installed()
