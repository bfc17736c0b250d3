"""The compiled search's loop: :meth:`~mpa.planners.graph.search.AnyAngleSearch._run` over the node arrays, and the
start's expansion (:mod:`trajopt.plan_kernel`).

The state comes in tuples (:mod:`trajopt.plan_kernel.expand` names ``N``, ``P``, ``M`` and ``G``): ``S = (seen_k,
seen_v, iv, ivn)`` the intervals seen per root, page and side; ``B = (dv, bgi, bd, segi, segf, bpar)`` the passing
bound (:func:`trajopt.plan_kernel.bound._entry`) and ``BS = (fk, fv, fr, frs, ok_, ov, on, onr)`` its fronts and
segments on an edge made so far. The arrays that grow are returned.

Only :func:`_run` and the functions that grow arrays allocate; every node function it calls (the expansions, the
bounds, the tables) is compiled ``no_alloc`` (:func:`trajopt._numba.njit`: without numba's reference counts, which
cost a call twice the arrays of the tuples it is handed) and works in the arrays ``_run`` holds, its scratch
included (a point's members, the pages of a face, the hinges of a front).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from trajopt._numba import njit
from trajopt.plan_kernel.arith import (
    _GOAL_ID,
    _POINT,
    _START_ID,
    EMPTY,
    FOUND,
    STOPPED,
    _cost,
    _crowded,
    _fit,
    _floor,
    _grow,
    _grow1,
    _heap_pop,
    _heap_push,
    _short,
)
from trajopt.plan_kernel.bound import _entry, _point_bound
from trajopt.plan_kernel.expand import _expand_point, _members, _open_face

# fmt: off
# (the kernels' long argument lists are kept a few to a line)


@njit(cache=True)
def _grow_fill(a: Any, need: int, value: float) -> Any:  # pragma: no cover - compiled
    """``a`` (1-D) with at least ``need`` items, doubled, the new ones ``value``."""
    if not _short(a, need):
        return a
    n = a.shape[0]
    while n < need:
        n *= 2
    out = np.full(n, value, a.dtype)
    out[: a.shape[0]] = a
    return out


@njit(cache=True)
def _room(N: Any, P: Any, nodes: int, points: int) -> tuple[Any, Any]:  # pragma: no cover - compiled
    """``N`` and ``P`` with room for ``nodes`` more nodes and heap entries and ``points`` more points."""
    ni, nf, pend, hk, hd, c = N
    pk, pv, pt, pty, best, pbv = P
    ni = _grow(ni, c[0] + nodes)
    nf = _grow(nf, c[0] + nodes)
    pend = _grow1(pend, c[0] + nodes)
    hk = _grow(hk, c[1] + nodes)
    hd = _grow1(hd, c[1] + nodes)
    pt = _grow(pt, c[16] + points)
    pty = _grow1(pty, c[16] + points)
    best = _grow_fill(best, c[16] + points, np.inf)
    pbv = _grow_fill(pbv, c[16] + points, np.nan)
    pk, pv = _fit(pk, pv, c[17] + points)
    return (ni, nf, pend, hk, hd, c), (pk, pv, pt, pty, best, pbv)


@njit(cache=True)
def _room_poly(C: Any, P: Any, c: Any, polys: int) -> tuple[Any, Any]:  # pragma: no cover - compiled
    """``C`` and ``P`` with room for ``polys`` more polygons (four sides and eight points each)."""
    ck, cv, ps, si, sf = C
    ck, cv = _fit(ck, cv, c[19] + polys)
    ps = _grow(ps, c[18] + polys)
    si = _grow(si, c[20] + 4 * polys)
    sf = _grow(sf, c[20] + 4 * polys)
    pk, pv, pt, pty, best, pbv = P
    pt = _grow(pt, c[16] + 8 * polys)
    pty = _grow1(pty, c[16] + 8 * polys)
    best = _grow_fill(best, c[16] + 8 * polys, np.inf)
    pbv = _grow_fill(pbv, c[16] + 8 * polys, np.nan)
    pk, pv = _fit(pk, pv, c[17] + 8 * polys)
    return (ck, cv, ps, si, sf), (pk, pv, pt, pty, best, pbv)


@njit(cache=True, no_alloc=True)
def _poly_short(C: Any, P: Any, c: Any, polys: int) -> bool:  # pragma: no cover - compiled
    """Whether :func:`_room_poly` would grow anything for ``polys`` more polygons (it is called only then: a call
    that returns every array as it was still rebuilds the tuples)."""
    pts = c[16] + 8 * polys
    return (
        _crowded(C[0], c[19] + polys)
        or _short(C[2], c[18] + polys)
        or _short(C[3], c[20] + 4 * polys)
        or _short(C[4], c[20] + 4 * polys)
        or _short(P[2], pts)
        or _short(P[3], pts)
        or _short(P[4], pts)
        or _short(P[5], pts)
        or _crowded(P[0], c[17] + 8 * polys)
    )


@njit(cache=True)
def _run(
    N: Any, P: Any, C: Any, S: Any, B: Any, BS: Any, M: Any, G: Any, budget: int, over: int,
) -> tuple[int, Any, Any, Any, Any, Any]:  # pragma: no cover - compiled
    """:meth:`AnyAngleSearch._run` from the queue as it stands (the start expanded by :func:`_start`):
    :data:`FOUND` (the goal's node in ``c[4]``), :data:`STOPPED` (at ``budget`` pops of this run, -1: none, or a
    key above ``over``) or :data:`EMPTY`; with ``N``, ``P``, ``C``, ``S`` and ``BS``, grown."""
    ni, nf, pend, hk, hd, c = N
    seen_k, seen_v, iv, ivn = S
    dv, bgi, bd, segi, segf, bpar = B
    fk, fv, fr, frs, ok_, ov, on, onr = BS
    gi, par, goals_p = G[2], G[3], G[4]
    inc_ptr = M[3]
    parts = np.empty((64, 2))
    items = np.empty((64, 2))
    deg_max = max(1, int(np.max(inc_ptr[1:] - inc_ptr[:-1])))
    pages_buf = np.empty((3, deg_max), np.int64)  # _open_face's scratch
    mp = np.empty(deg_max * deg_max, np.int64)  # a point's members (polygons, coordinates): _members's scratch
    mc = np.empty((deg_max * deg_max, 2))
    best, pbv = P[4], P[5]  # taken again whenever P is grown
    bounded = gi[1] != 0
    status = EMPTY
    while c[1] > 0:
        key0, depth, nid = _heap_pop(hk, hd, c)
        c[3] += 1
        if (budget >= 0 and c[3] > budget) or key0 > over:
            _heap_push(hk, hd, c, key0, depth, nid)
            status = STOPPED
            break
        kind = ni[nid, 0]
        if kind == _POINT:
            if ni[nid, 1] == _GOAL_ID:
                c[4] = nid
                status = FOUND
                break
            if nf[nid, 0] > best[ni[nid, 1]]:
                continue
        elif nf[nid, 0] > best[ni[nid, 1]]:
            continue
        if bounded and pend[nid]:
            # room for what a pop's two bounds can make: four fronts of at most n_seg rows (the last one's hinges
            # written after its rows) and two edges' segments
            n_seg = segi.shape[1]
            if (
                _short(fr, c[9] + 5 * n_seg + 1)
                or _short(frs, c[10] + 5)
                or _short(on, c[11] + 2 * n_seg + 1)
                or _short(onr, c[12] + 3)
                or _crowded(fk, c[14] + 4)
                or _crowded(ok_, c[15] + 2)
            ):
                fr = _grow(fr, c[9] + 5 * n_seg + 1)
                frs = _grow(frs, c[10] + 5)
                on = _grow(on, c[11] + 2 * n_seg + 1)
                onr = _grow(onr, c[12] + 3)
                fk, fv = _fit(fk, fv, c[14] + 4)
                ok_, ov = _fit(ok_, ov, c[15] + 2)
            if kind == _POINT:
                h = _point_bound(c, P, M, dv, bgi, bd, segi, segf, bpar, fk, fv, fr, frs, ok_, ov, on, onr, pbv,
                                 ni[nid, 1])
                key1 = _floor((nf[nid, 0] + h) * par[5])
            else:
                g_root, r0, r1, a = nf[nid, 0], nf[nid, 1], nf[nid, 2], nf[nid, 5]
                y0, y1 = nf[nid, 6], nf[nid, 7]
                h0 = _point_bound(c, P, M, dv, bgi, bd, segi, segf, bpar, fk, fv, fr, frs, ok_, ov, on, onr, pbv,
                                  ni[nid, 1])
                h1 = _entry(c, dv, bgi, bd, segi, segf, bpar, fk, fv, fr, frs, ok_, ov, on, onr, ni[nid, 5],
                            ni[nid, 6], ni[nid, 9], y0, y1)
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
            n_mem = _members(M, P, key, mp, mc)
            C, P = _room_poly(C, P, c, n_mem)
            N, P = _room((ni, nf, pend, hk, hd, c), P, n_mem * (2 + goals_p.shape[0] + 12), 0)
            ni, nf, pend, hk, hd = N[0], N[1], N[2], N[3], N[4]
            best, pbv = P[4], P[5]
            _expand_point(N, P, C, M, G, nid, key, nf[nid, 0], mp, mc, n_mem)
        else:
            deg = inc_ptr[ni[nid, 6] + 1] - inc_ptr[ni[nid, 6]]
            if _crowded(seen_k, c[13] + deg):
                seen_k, seen_v = _fit(seen_k, seen_v, c[13] + deg)
            if _poly_short(C, P, c, deg):
                C, P = _room_poly(C, P, c, deg)
                best, pbv = P[4], P[5]
            N = (ni, nf, pend, hk, hd, c)
            while True:
                need, cells = _open_face(N, P, C, M, G, seen_k, seen_v, iv, ivn, parts, items, nid, pages_buf)
                if need == 0:
                    break
                N, P = _room(N, P, need, 0)
                ni, nf, pend, hk, hd = N[0], N[1], N[2], N[3], N[4]
                best, pbv = P[4], P[5]
                iv = _grow(iv, c[2] + cells)
                ivn = _grow1(ivn, c[2] + cells)
                parts = _grow(parts, cells)
                items = _grow(items, cells)
    return (
        status, (ni, nf, pend, hk, hd, c), P, C, (seen_k, seen_v, iv, ivn), (fk, fv, fr, frs, ok_, ov, on, onr),
    )


@njit(cache=True, no_alloc=True)
def _start(
    N: Any, P: Any, C: Any, M: Any, G: Any, mem_p: Any, mem_c: Any,
) -> None:  # pragma: no cover - compiled
    """The start's node and its expansion (:meth:`AnyAngleSearch._run`'s first lines); the arrays hold enough."""
    ni, nf, pend, c = N[0], N[1], N[2], N[5]
    P[4][_START_ID] = 0.0
    ni[0, 0], ni[0, 1], ni[0, 2], ni[0, 3], ni[0, 4] = _POINT, _START_ID, -1, -1, -1
    nf[0, 0], nf[0, 1], nf[0, 2], nf[0, 3], nf[0, 4] = 0.0, np.nan, np.nan, np.nan, np.nan
    pend[0] = False
    c[0] = 1
    _expand_point(N, P, C, M, G, 0, _START_ID, 0.0, mem_p, mem_c, mem_p.shape[0])
