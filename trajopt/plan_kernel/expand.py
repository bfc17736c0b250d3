"""The compiled search's nodes (:mod:`trajopt.plan_kernel`): the ``push_point``, ``push_face``, ``expand_point``,
``expand_interval`` and ``open_face`` of :class:`~mpa.planners.graph.search.AnyAngleSearch` over the node arrays."""

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
    _put,
    _py_hypot,
    _slot,
)

# fmt: off
# (the kernels' long argument lists are kept a few to a line)

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


@njit(cache=True)
def _uncovered(
    seen_k: Any, seen_v: Any, sk: Any, head: int, iv: Any, ivn: Any, c: Any, y0: float, y1: float, eps: float, out: Any,
    items: Any,
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
def _open_face(
    ni: Any, nf: Any, pend: Any, hk: Any, hd: Any, c: Any, best: Any, pi: Any, si: Any, sf: Any, fi: Any,
    pg: Any, pgb: Any, gd: Any, vd: Any, gi: Any, par: Any, goals_p: Any, goals_c: Any, seen_k: Any,
    seen_v: Any, iv: Any, ivn: Any, parts: Any, items: Any, nid: int,
) -> tuple[int, int]:  # pragma: no cover - compiled
    """:meth:`AnyAngleSearch.open_face` of the face entry ``nid``.

    First the pages' records in the table ``seen_k``, ``seen_v`` (room for a key per page) are looked up; when the
    arrays cannot hold what it may make (nodes and heap entries, interval cells, the rows of ``parts`` and ``items``),
    it returns those numbers and changes nothing; ``(0, 0)`` when done."""
    face, ax, pid, rid, root_key = ni[nid, 6], ni[nid, 5], ni[nid, 4], ni[nid, 2], ni[nid, 1]
    g_root, r0, r1, sig0, sig1 = nf[nid, 0], nf[nid, 1], nf[nid, 2], nf[nid, 3], nf[nid, 4]
    a, y0, y1, lo, hi = nf[nid, 5], nf[nid, 6], nf[nid, 7], nf[nid, 8], nf[nid, 9]
    parent, op, o0, o1 = ni[nid, 3], ni[nid, 8], nf[nid, 11], nf[nid, 12]
    quantum, eps = par[6], par[1]
    n1 = 1.0 if a == 0.0 else -1.0
    across = (r0 if ax == 0 else r1) - a
    kept = r1 if ax == 0 else r0
    k_kept = int(np.rint(kept * quantum))
    j0, n_pages = fi[face, 3], fi[face, 4]
    heads = np.full(n_pages, -2, np.int64)  # -2: page not opened, -1: nothing seen so before
    nodes, cells, rows = 0, 0, 0
    for jj in range(n_pages):
        p2, b = pg[j0 + jj], pgb[j0 + jj]
        if not _page_open(pi, goals_p, p2) or (p2 == pid and b == a):
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
        nodes += (count + 1) * (2 + goals_p.shape[0] + 3 * pi[p2, 1])
    if (
        c[0] + nodes > ni.shape[0] or c[1] + nodes > hk.shape[0] or c[2] + cells > iv.shape[0]
        or rows > parts.shape[0] or rows > items.shape[0]
    ):
        return max(nodes, 1), max(cells, rows)
    for jj in range(n_pages):
        head = heads[jj]
        if head == -2:
            continue
        p2, b = pg[j0 + jj], pgb[j0 + jj]
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
            ni[n, 5], ni[n, 6], ni[n, 7], ni[n, 8] = ax, face, pid, op
            nf[n, 0], nf[n, 1], nf[n, 2], nf[n, 3], nf[n, 4] = g_root, q0, q1, s0, s1
            nf[n, 5], nf[n, 6], nf[n, 7], nf[n, 8], nf[n, 9] = b, z0, z1, lo, hi
            nf[n, 10], nf[n, 11], nf[n, 12] = a, o0, o1
            pend[n] = False
            _expand_interval(ni, nf, pend, hk, hd, c, best, pi, si, sf, fi, gd, vd, gi, par, goals_p, goals_c, n)
    return 0, 0
