"""The compiled search's nodes (:mod:`trajopt.plan_kernel`): the ``push_point``, ``push_face``, ``expand_point``,
``expand_interval`` and ``open_face`` of :class:`~mpa.planners.graph.search.AnyAngleSearch` over the node arrays,
and the free space's polygons, sides, pages and points as :class:`~mpa.planners.graph.mesh._Mesh` names them, read
from the free space's arrays.

The arguments come in tuples: ``N = (ni, nf, pend, hk, hd, c)`` the nodes, the queue and the counters; ``P = (pk,
pv, pt, pty, best)`` the points (a hash table of their keys, their keys and coordinates, the least cost found);
``M = (tails, heads, lengths, inc_ptr, inc_e, inc_x, face_ok, face_lo, face_hi, pieces)`` the layout and its free
space (the faces' arrays indexed ``[edge, vertex]``);
``G = (gd, vd, gi, par, goals_p, goals_c)`` the query. A polygon ``(e, f, k)`` is the integer ``(e E + f) 2 + k``.
A point's key is ``(1, ax, w, other, end)`` for a face end (``end`` 0 at the face's ``lo``, 1 at its ``hi``) and
``(2, wA, wB, 0, 0)`` for a corner (:meth:`~mpa.planners.graph.mesh._Mesh.point_key`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from mpa.planners.graph.base import TIE_BREAK, TIE_BREAK_2
from trajopt._numba import njit
from trajopt.plan_kernel.arith import (
    _FACE,
    _GOAL_ID,
    _INTERVAL,
    _POINT,
    _cost,
    _floor,
    _heap_push,
    _least_through_face,
    _put,
    _py_hypot,
    _slot,
)

# fmt: off
# (the kernels' long argument lists are kept a few to a line)

# --------------------------------------------------------------------------------------------- the mesh
@njit(cache=True, no_alloc=True)
def _exists(M: Any, e: int, f: int, k: int) -> bool:  # pragma: no cover - compiled
    """Whether ``(e, f, k)`` is a free polygon (``pieces``: per cell a bit per piece)."""
    return (M[9][e, f] >> k) & 1 == 1


@njit(cache=True, no_alloc=True)
def _side(M: Any, p: int, j: int) -> tuple[bool, int, int, int, float, float, float]:  # pragma: no cover
    """The ``j``-th (0-3) of the sides :meth:`_Mesh.sides` may list for the polygon ``p``, in its order (robot A on a
    vertex first): ``(valid, ax, w, other, a, lo, hi)``."""
    tails, heads, lengths, ok, lo, hi = M[0], M[1], M[2], M[6], M[7], M[8]
    n_e = lengths.shape[0]
    k = p % 2
    e = (p // 2) // n_e
    f = (p // 2) % n_e
    if j < 2:  # FreeSpace._sides_a
        ax, other, edge, first = 0, f, e, j == 0
        if e == f and first != (k == 1):
            return False, 0, 0, 0, 0.0, 0.0, 0.0
    else:  # FreeSpace._sides_b
        ax, other, edge, first = 1, e, f, j == 2
        if e == f and first != (k == 0):
            return False, 0, 0, 0, 0.0, 0.0, 0.0
    w = tails[edge] if first else heads[edge]
    a = 0.0 if first else lengths[edge]
    if not ok[other, w]:
        return False, 0, 0, 0, 0.0, 0.0, 0.0
    return True, ax, w, other, a, lo[other, w], hi[other, w]


@njit(cache=True, no_alloc=True)
def _page(M: Any, ax: int, other: int, e2: int, x: float) -> int:  # pragma: no cover - compiled
    """The page of the face ``(ax, w, other)`` through the edge ``e2`` at ``w`` (its offset ``x`` there): the polygon
    :meth:`_Mesh.pages` lists, -1 when it is not free."""
    n_e = M[2].shape[0]
    if ax == 0:
        e, f, k = e2, other, 0 if e2 != other else (1 if x == 0.0 else 0)
    else:
        e, f, k = other, e2, 0 if e2 != other else (0 if x == 0.0 else 1)
    if not _exists(M, e, f, k):
        return -1
    return (e * n_e + f) * 2 + k


@njit(cache=True, no_alloc=True)
def _end_key(M: Any, ax: int, w: int, other: int, y: float, lo: float) -> Any:  # pragma: no cover - compiled
    """The key of :meth:`_Mesh.point_key` of the point ``y`` (the face's ``lo`` or ``hi``) on the face."""
    if y == 0.0:
        w2 = M[0][other]
    elif y == M[2][other]:
        w2 = M[1][other]
    else:
        return (1, ax, w, other, 0 if y == lo else 1)
    if ax == 0:
        return (2, w, w2, 0, 0)
    return (2, w2, w, 0, 0)


@njit(cache=True, no_alloc=True)
def _point(P: Any, c: Any, key: Any, y: float) -> int:  # pragma: no cover - compiled
    """The point named ``key`` (at ``y`` on its face, for a face end), made when first named (the arrays hold
    room)."""
    pk, pv, pt, pty = P[0], P[1], P[2], P[3]
    i = pv[_slot(pk, pv, key)]
    if i >= 0:
        return i
    i = c[16]
    c[16] = i + 1
    for j in range(5):
        pt[i, j] = key[j]
    pty[i] = y
    _put(pk, pv, c, 17, key, i)
    return i


@njit(cache=True, no_alloc=True)
def _poly(C: Any, P: Any, M: Any, c: Any, p: int) -> int:  # pragma: no cover - compiled
    """The row of the polygon ``p`` in the polygon table ``C = (keys, rows, first side and sides, side ints, side
    floats)``: its sides that are faces as :meth:`_Mesh.side_ends` lists them (axis, vertex, other edge, the ends'
    points; side value, lo, hi), written when first asked for (the arrays hold room)."""
    ck, cv, ps, si, sf = C
    i = cv[_slot(ck, cv, (p,))]
    if i >= 0:
        return i
    i = c[18]
    c[18] = i + 1
    r0 = c[20]
    n = 0
    for j in range(4):
        valid, ax, w, other, a, lo, hi = _side(M, p, j)
        if not valid:
            continue
        r = r0 + n
        si[r, 0], si[r, 1], si[r, 2] = ax, w, other
        si[r, 3] = _point(P, c, _end_key(M, ax, w, other, lo, lo), lo)
        si[r, 4] = _point(P, c, _end_key(M, ax, w, other, hi, lo), hi)
        sf[r, 0], sf[r, 1], sf[r, 2] = a, lo, hi
        n += 1
    c[20] = r0 + n
    ps[i, 0], ps[i, 1] = r0, n
    _put(ck, cv, c, 19, (p,), i)
    return i


@njit(cache=True, no_alloc=True)
def _members(M: Any, P: Any, key: int, mp: Any, mc: Any) -> int:  # pragma: no cover - compiled
    """:meth:`_Mesh.members` of the point ``key`` into ``mp`` (polygons), ``mc`` (its coordinates in each); their
    number."""
    pt, pty = P[2], P[3]
    inc_ptr, inc_e, inc_x = M[3], M[4], M[5]
    n_e = M[2].shape[0]
    n = 0
    if pt[key, 0] == 1:  # a face end: the face's pages
        ax, w, other, y = pt[key, 1], pt[key, 2], pt[key, 3], pty[key]
        for i in range(inc_ptr[w], inc_ptr[w + 1]):
            p = _page(M, ax, other, inc_e[i], inc_x[i])
            if p >= 0:
                mp[n] = p
                if ax == 0:
                    mc[n, 0], mc[n, 1] = inc_x[i], y
                else:
                    mc[n, 0], mc[n, 1] = y, inc_x[i]
                n += 1
        return n
    wa, wb = pt[key, 1], pt[key, 2]
    for i in range(inc_ptr[wa], inc_ptr[wa + 1]):
        e, s = inc_e[i], inc_x[i]
        for j in range(inc_ptr[wb], inc_ptr[wb + 1]):
            f, t = inc_e[j], inc_x[j]
            if e == f and s == t:
                continue
            k = 0 if e != f or s > t else 1
            if _exists(M, e, f, k):
                mp[n] = (e * n_e + f) * 2 + k
                mc[n, 0], mc[n, 1] = s, t
                n += 1
    return n


# ------------------------------------------------------------------------------------------------ nodes
@njit(cache=True, no_alloc=True)
def _lower_bound(M: Any, G: Any, p: int, s: float, t: float) -> float:  # pragma: no cover - compiled
    """:meth:`AnyAngleSearch.lower_bound` at ``(s, t)`` in the polygon ``p``."""
    gd, gi, par = G[0], G[2], G[3]
    n_e = M[2].shape[0]
    e = (p // 2) // n_e
    x, d = s + gd[0, e], gd[1, e] - s
    da = d if d < x else x
    if e == gi[2]:
        x = abs(s - par[7])
        da = x if x < da else da
    e = (p // 2) % n_e
    x, d = t + gd[2, e], gd[3, e] - t
    db = d if d < x else x
    if e == gi[3]:
        x = abs(t - par[8])
        db = x if x < db else db
    if gi[0]:
        ta, tb = abs(da) / par[2], abs(db) / par[3]
        return (tb if tb > ta else ta) + TIE_BREAK * (ta + tb) + TIE_BREAK_2 * _py_hypot(ta, tb)
    return _py_hypot(da, db)


@njit(cache=True, no_alloc=True)
def _push_point(
    N: Any, P: Any, M: Any, G: Any, key: int, gval: float, root: int, last: int, p: int, f0: float, f1: float,
    t0: float, t1: float,
) -> None:  # pragma: no cover - compiled
    """:meth:`AnyAngleSearch.push_point` (``f0`` NaN: no ``frm``)."""
    ni, nf, pend, hk, hd, c = N
    best, par = P[4], G[3]
    is_goal = key == _GOAL_ID
    if gval < best[key] - (0.0 if is_goal else par[4]):
        best[key] = gval
        n = c[0]
        c[0] = n + 1
        ni[n, 0], ni[n, 1], ni[n, 2], ni[n, 3], ni[n, 4] = _POINT, key, root, last, p
        nf[n, 0], nf[n, 1], nf[n, 2], nf[n, 3], nf[n, 4] = gval, f0, f1, t0, t1
        f = gval if is_goal else gval + _lower_bound(M, G, p, t0, t1)
        pend[n] = G[2][1] != 0 and not is_goal
        _heap_push(hk, hd, c, _floor(f * par[5]), -gval, n)


@njit(cache=True, no_alloc=True)
def _new_face_entry(
    N: Any, G: Any, root: int, root_key: int, g_root: float, r0: float, r1: float, s0: float, s1: float,
    ax: int, w: int, e: int, a: float, y0: float, y1: float, p: int, lo: float, hi: float, parent: int, op: int,
    o0: float, o1: float,
) -> None:  # pragma: no cover - compiled
    """A :class:`FaceEntry` of the face ``(ax, w, e)`` queued: :meth:`AnyAngleSearch.push_face`, and the inline push
    of :meth:`AnyAngleSearch.expand_interval` (the bound :meth:`AnyAngleSearch.face_lower_bound`)."""
    ni, nf, pend, hk, hd, c = N
    gd, vd, gi, par = G[0], G[1], G[2], G[3]
    n = c[0]
    c[0] = n + 1
    ni[n, 0], ni[n, 1], ni[n, 2], ni[n, 3], ni[n, 4] = _FACE, root_key, root, parent, p
    ni[n, 5], ni[n, 6], ni[n, 8], ni[n, 9] = ax, w, op, e
    nf[n, 0], nf[n, 1], nf[n, 2], nf[n, 3], nf[n, 4] = g_root, r0, r1, s0, s1
    nf[n, 5], nf[n, 6], nf[n, 7], nf[n, 8], nf[n, 9] = a, y0, y1, lo, hi
    nf[n, 11], nf[n, 12] = o0, o1
    pend[n] = gi[1] != 0
    fastest = gi[0] != 0
    if ax == 0:
        x_v, x_w, rr = abs(r0 - a), vd[0, w], r1
        cp, cm, edge, off = gd[2, e], gd[3, e], gi[3], par[8]
    else:
        x_v, x_w, rr = abs(r1 - a), vd[1, w], r0
        cp, cm, edge, off = gd[0, e], gd[1, e], gi[2], par[7]
    f = g_root + _least_through_face(ax, x_v, x_w, rr, y0, y1, cp, cm, e == edge, off, fastest, par[2], par[3])
    _heap_push(hk, hd, c, _floor(f * par[5]), -g_root, n)


@njit(cache=True, no_alloc=True)
def _expand_point(
    N: Any, P: Any, C: Any, M: Any, G: Any, nid: int, key: int, gval: float, mem_p: Any, mem_c: Any, n_mem: int,
) -> None:  # pragma: no cover - compiled
    """:meth:`AnyAngleSearch.expand_point` over the members ``mem_p[:n_mem]``, ``mem_c[:n_mem]`` (the polygon table
    has room for them)."""
    ps, si, sf = C[2], C[3], C[4]
    gi, par, goals_p, goals_c = G[2], G[3], G[4], G[5]
    fastest = gi[0] != 0
    va, vb, eps = par[2], par[3], par[1]
    for m in range(n_mem):
        q = mem_p[m]
        rc0, rc1 = mem_c[m, 0], mem_c[m, 1]
        for j in range(goals_p.shape[0]):
            if goals_p[j] == q:
                pt0, pt1 = goals_c[j, 0], goals_c[j, 1]
                _push_point(N, P, M, G, _GOAL_ID, gval + _cost(pt0 - rc0, pt1 - rc1, fastest, va, vb), nid, -1, q,
                            rc0, rc1, pt0, pt1)
        row = _poly(C, P, M, N[5], q)
        for r in range(ps[row, 0], ps[row, 0] + ps[row, 1]):
            ax2, w2, other2, a2, lo2, hi2 = si[r, 0], si[r, 1], si[r, 2], sf[r, 0], sf[r, 1], sf[r, 2]
            on_line = (rc0 if ax2 == 0 else rc1) == a2
            for end in range(2 if hi2 > lo2 else 1):
                y = lo2 if end == 0 else hi2
                if ax2 == 0:
                    pt0, pt1 = a2, y
                else:
                    pt0, pt1 = y, a2
                if pt0 == rc0 and pt1 == rc1:
                    continue
                _push_point(N, P, M, G, si[r, 3 + end], gval + _cost(pt0 - rc0, pt1 - rc1, fastest, va, vb), nid,
                            -1, q, rc0, rc1, pt0, pt1)
            if on_line or hi2 - lo2 <= eps:
                continue
            _new_face_entry(N, G, nid, key, gval, rc0, rc1, 1.0, 1.0, ax2, w2, other2, a2, lo2, hi2, q, lo2, hi2, nid,
                            q, rc0, rc1)


@njit(cache=True, no_alloc=True)
def _expand_interval(N: Any, P: Any, C: Any, M: Any, G: Any, nid: int) -> None:  # pragma: no cover - compiled
    """:meth:`AnyAngleSearch.expand_interval` of the interval node ``nid`` (its polygon's row in ``ni[nid, 10]``)."""
    ni, nf = N[0], N[1]
    best = P[4]
    ps, si, sf = C[2], C[3], C[4]
    gi, par, goals_p, goals_c = G[2], G[3], G[4], G[5]
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
                _push_point(N, P, M, G, _GOAL_ID, groot + _cost(pt0 - rs, pt1 - rt, fastest, va, vb), rid, nid, pid,
                            np.nan, np.nan, pt0, pt1)
    nctol = -ctol
    ca0_a, ca1_a = sgn * u00, nsg * u10
    m0_a, m1_a = -u00 * rt, -u10 * rt
    ca0_b, ca1_b = sgn * -u01, nsg * -u11
    m0_b, m1_b = u01 * rs, u11 * rs
    row = ni[nid, 10]
    for r in range(ps[row, 0], ps[row, 0] + ps[row, 1]):
        ax2, w2, other2, a2, lo2, hi2 = si[r, 0], si[r, 1], si[r, 2], sf[r, 0], sf[r, 1], sf[r, 2]
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
                y = lo2
            else:
                if not yh >= hi2 - eps:
                    continue
                yh = hi2
                y = hi2
            if ax2 == 0:
                p0, p1 = a2, y
            else:
                p0, p1 = y, a2
            kk = si[r, 3 + end]
            dx, dy = p0 - rs, p1 - rt
            limit = best[kk] - again
            if fastest:
                ta, tb = abs(dx) / va, abs(dy) / vb
                m = tb if tb > ta else ta
                if groot + m < limit:
                    g2 = groot + (m + TIE_BREAK * (ta + tb) + TIE_BREAK_2 * _py_hypot(ta, tb))
                    if g2 < limit:
                        _push_point(N, P, M, G, kk, g2, rid, nid, pid, np.nan, np.nan, p0, p1)
            else:
                g2 = groot + _py_hypot(dx, dy)
                if g2 < limit:
                    _push_point(N, P, M, G, kk, g2, rid, nid, pid, np.nan, np.nan, p0, p1)
        if yh - yl <= eps:
            continue
        _new_face_entry(N, G, rid, root_key, groot, rs, rt, sg0, sg1, ax2, w2, other2, a2, yl, yh, pid, lo2, hi2,
                        nid, ni[nid, 8], nf[nid, 11], nf[nid, 12])


# ------------------------------------------------------------------------------------------------ faces
@njit(cache=True, no_alloc=True)
def _uncovered(
    seen_k: Any, seen_v: Any, sk: Any, head: int, iv: Any, ivn: Any, c: Any, y0: float, y1: float, eps: float,
    out: Any, items: Any,
) -> int:  # pragma: no cover - compiled
    """:func:`mpa.planners.graph.search._uncovered`: the parts of ``[y0, y1]`` not recorded under ``sk`` (its list of
    cells ``iv`` linked by ``ivn`` starts at ``head``) into ``out``, their number returned; the union recorded
    (``items``: room for the merge)."""
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
        for k in range(j):
            z0, z1 = items[k, 0], items[k, 1]
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
        _put(seen_k, seen_v, c, 13, sk, first)
    return n_out


@njit(cache=True, no_alloc=True)
def _seen_key(
    rid: int, p2: int, ax: int, b: float, moved: float, k_kept: int, quantum: float
) -> Any:  # pragma: no cover - compiled
    """The key of :meth:`AnyAngleSearch.open_face`'s ``seen``: the side ``b`` (0 or the edge's length) as 0 / 1,
    Python's ``round`` (half to even) of the unfolded root's coordinates on the grid ``1 / quantum``."""
    km = int(np.rint(moved * quantum))
    if ax == 0:
        return (rid, p2, 0, 0 if b == 0.0 else 1, km, k_kept)
    return (rid, p2, 1, 0 if b == 0.0 else 1, k_kept, km)


@njit(cache=True, no_alloc=True)
def _page_open(C: Any, goals_p: Any, p2: int, row: int) -> bool:  # pragma: no cover - compiled
    """:meth:`AnyAngleSearch.pages_to_open`'s test of the polygon ``p2`` (its row ``row``): not a dead end, or it holds
    the goal."""
    if C[2][row, 1] != 1:
        return True
    for j in range(goals_p.shape[0]):
        if goals_p[j] == p2:
            return True
    return False


@njit(cache=True, no_alloc=True)
def _open_face(
    N: Any, P: Any, C: Any, M: Any, G: Any, seen_k: Any, seen_v: Any, iv: Any, ivn: Any, parts: Any, items: Any,
    nid: int, pages_buf: Any,
) -> tuple[int, int]:  # pragma: no cover - compiled
    """:meth:`AnyAngleSearch.open_face` of the face entry ``nid``.

    First the pages' records in the table ``seen_k``, ``seen_v`` (room for a key per page) are looked up; when the
    arrays cannot hold what it may make (nodes and heap entries, interval cells and the rows of ``parts`` and
    ``items``), it returns those numbers and changes nothing but the polygon table (room for every page: the
    caller's); ``(0, 0)`` when done. ``pages_buf`` (3, at least the vertices' largest degree) is scratch for the
    pages' records (allocated once per run, not per face entry)."""
    ni, nf, pend, hk, c = N[0], N[1], N[2], N[3], N[5]
    inc_ptr, inc_e, inc_x = M[3], M[4], M[5]
    goals_p, par = G[4], G[3]
    ax, w, other, pid, rid, root_key = ni[nid, 5], ni[nid, 6], ni[nid, 9], ni[nid, 4], ni[nid, 2], ni[nid, 1]
    g_root, r0, r1, sig0, sig1 = nf[nid, 0], nf[nid, 1], nf[nid, 2], nf[nid, 3], nf[nid, 4]
    a, y0, y1, lo, hi = nf[nid, 5], nf[nid, 6], nf[nid, 7], nf[nid, 8], nf[nid, 9]
    parent, op, o0, o1 = ni[nid, 3], ni[nid, 8], nf[nid, 11], nf[nid, 12]
    quantum, eps = par[6], par[1]
    n1 = 1.0 if a == 0.0 else -1.0
    across = (r0 if ax == 0 else r1) - a
    kept = r1 if ax == 0 else r0
    k_kept = int(np.rint(kept * quantum))
    i0, n_inc = inc_ptr[w], inc_ptr[w + 1] - inc_ptr[w]
    heads, pages, prow = pages_buf[0], pages_buf[1], pages_buf[2]
    heads[:n_inc] = -2  # -2: not a page opened, -1: nothing seen so before
    nodes, cells, rows = 0, 0, 0
    for jj in range(n_inc):
        b = inc_x[i0 + jj]
        p2 = _page(M, ax, other, inc_e[i0 + jj], b)
        pages[jj] = p2
        if p2 < 0:
            continue
        prow[jj] = row2 = _poly(C, P, M, c, p2)
        if not _page_open(C, goals_p, p2, row2) or (p2 == pid and b == a):
            continue
        sk = _seen_key(rid, p2, ax, b, b + (-n1 if b == 0.0 else n1) * across, k_kept, quantum)
        head = seen_v[_slot(seen_k, seen_v, sk)]
        heads[jj] = head
        count = 0
        i = head
        while i >= 0:
            count += 1
            i = ivn[i]
        cells += count + 2
        rows = max(rows, count + 2)
        nodes += (count + 1) * (2 + goals_p.shape[0] + 3 * C[2][row2, 1])
    if (
        c[0] + nodes > ni.shape[0] or c[1] + nodes > hk.shape[0] or c[2] + cells > iv.shape[0]
        or rows > parts.shape[0] or rows > items.shape[0]
    ):
        return max(nodes, 1), max(cells, rows)
    for jj in range(n_inc):
        head = heads[jj]
        if head == -2:
            continue
        p2, b = pages[jj], inc_x[i0 + jj]
        sg = -n1 if b == 0.0 else n1
        moved = b + sg * across
        if ax == 0:
            q0, q1, s0, s1 = moved, kept, sg * sig0, sig1
        else:
            q0, q1, s0, s1 = kept, moved, sig0, sg * sig1
        sk = _seen_key(rid, p2, ax, b, moved, k_kept, quantum)
        if head < 0:
            cell = c[2]
            c[2] = cell + 1
            iv[cell, 0], iv[cell, 1], ivn[cell] = y0, y1, -1
            _put(seen_k, seen_v, c, 13, sk, cell)
            parts[0, 0], parts[0, 1] = y0, y1
            n_parts = 1
        else:
            n_parts = _uncovered(seen_k, seen_v, sk, head, iv, ivn, c, y0, y1, eps, parts, items)
        for m in range(n_parts):
            z0, z1 = parts[m, 0], parts[m, 1]
            n = c[0]
            c[0] = n + 1
            ni[n, 0], ni[n, 1], ni[n, 2], ni[n, 3], ni[n, 4] = _INTERVAL, root_key, rid, parent, p2
            ni[n, 5], ni[n, 6], ni[n, 7], ni[n, 8], ni[n, 9], ni[n, 10] = ax, w, pid, op, other, prow[jj]
            nf[n, 0], nf[n, 1], nf[n, 2], nf[n, 3], nf[n, 4] = g_root, q0, q1, s0, s1
            nf[n, 5], nf[n, 6], nf[n, 7], nf[n, 8], nf[n, 9] = b, z0, z1, lo, hi
            nf[n, 10], nf[n, 11], nf[n, 12] = a, o0, o1
            pend[n] = False
            _expand_interval(N, P, C, M, G, n)
    return 0, 0
