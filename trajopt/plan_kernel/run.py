"""The compiled search's loop: :meth:`~mpa.planners.graph.search.AnyAngleSearch._run` over the node arrays, and the
start's expansion (:mod:`trajopt.plan_kernel`).

The state comes in tuples (:mod:`trajopt.plan_kernel.expand` names ``N``, ``P``, ``M`` and ``G``): ``S = (seen_k,
seen_v, iv, ivn)`` the intervals seen per root, page and side; ``B = (dv, bgi, bd, segi, segf, bpar)`` the passing
bound (:func:`trajopt.plan_kernel.bound._entry`) and ``BS = (fk, fv, fr, frs, ok_, ov, on, onr)`` its fronts and
segments on an edge made so far. The arrays that grow are returned.

Only :func:`_run` and the functions that grow arrays allocate. The pops run in :func:`_pops`, and every node
function it calls (the expansions, the bounds, the tables), compiled ``no_alloc`` (:func:`trajopt._numba.njit`:
without numba's reference counts, which cost a call twice the arrays of the tuples it is handed, and a loop whose
arrays may be replaced every one of them at every turn); they work in the arrays ``_run`` holds, its scratch
included (a point's members, the pages of a face, the hinges of a front). ``_pops`` stops where a table is too small
for the pop in hand; ``_run`` grows it and calls it again.
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


@njit(cache=True, no_alloc=True)
def _room_needs(c: Any, nodes: int, points: int) -> tuple[int, int, int, int]:  # pragma: no cover - compiled
    """The rows of the node arrays, of the heap and of the points' arrays, and the keys of the points' table, that
    ``nodes`` more nodes and heap entries and ``points`` more points need."""
    return c[0] + nodes, c[1] + nodes, c[16] + points, c[17] + points


@njit(cache=True)
def _room(N: Any, P: Any, nodes: int, points: int) -> tuple[Any, Any]:  # pragma: no cover - compiled
    """``N`` and ``P`` with room for ``nodes`` more nodes and heap entries and ``points`` more points."""
    ni, nf, pend, hk, hd, c = N
    pk, pv, pt, pty, best, pbv = P
    n_node, n_heap, n_pt, n_pk = _room_needs(c, nodes, points)
    ni = _grow(ni, n_node)
    nf = _grow(nf, n_node)
    pend = _grow1(pend, n_node)
    hk = _grow(hk, n_heap)
    hd = _grow1(hd, n_heap)
    pt = _grow(pt, n_pt)
    pty = _grow1(pty, n_pt)
    best = _grow_fill(best, n_pt, np.inf)
    pbv = _grow_fill(pbv, n_pt, np.nan)
    pk, pv = _fit(pk, pv, n_pk)
    return (ni, nf, pend, hk, hd, c), (pk, pv, pt, pty, best, pbv)


@njit(cache=True, no_alloc=True)
def _point_nodes(n_mem: int, n_goals: int) -> int:  # pragma: no cover - compiled
    """The nodes (and heap entries) that the expansion of a point with ``n_mem`` members can make, the query's
    goal having ``n_goals`` placements (:func:`trajopt.plan_kernel.expand._expand_point`)."""
    return n_mem * (2 + n_goals + 12)


@njit(cache=True, no_alloc=True)
def _poly_needs(c: Any, polys: int) -> tuple[int, int, int, int, int]:  # pragma: no cover - compiled
    """The keys of the polygons' table, the rows of the polygons and of their sides, the rows of the points' arrays
    and the keys of their table that ``polys`` more polygons need (four sides and eight points each)."""
    return c[19] + polys, c[18] + polys, c[20] + 4 * polys, c[16] + 8 * polys, c[17] + 8 * polys


@njit(cache=True)
def _room_poly(C: Any, P: Any, c: Any, polys: int) -> tuple[Any, Any]:  # pragma: no cover - compiled
    """``C`` and ``P`` with room for ``polys`` more polygons (four sides and eight points each)."""
    ck, cv, ps, si, sf = C
    n_ck, n_ps, n_si, n_pt, n_pk = _poly_needs(c, polys)
    ck, cv = _fit(ck, cv, n_ck)
    ps = _grow(ps, n_ps)
    si = _grow(si, n_si)
    sf = _grow(sf, n_si)
    pk, pv, pt, pty, best, pbv = P
    pt = _grow(pt, n_pt)
    pty = _grow1(pty, n_pt)
    best = _grow_fill(best, n_pt, np.inf)
    pbv = _grow_fill(pbv, n_pt, np.nan)
    pk, pv = _fit(pk, pv, n_pk)
    return (ck, cv, ps, si, sf), (pk, pv, pt, pty, best, pbv)


@njit(cache=True, no_alloc=True)
def _poly_short(C: Any, P: Any, c: Any, polys: int) -> bool:  # pragma: no cover - compiled
    """Whether :func:`_room_poly` would grow anything for ``polys`` more polygons (it is called only then: a call
    that returns every array as it was still rebuilds the tuples)."""
    n_ck, n_ps, n_si, n_pt, n_pk = _poly_needs(c, polys)
    return (
        _crowded(C[0], n_ck)
        or _short(C[2], n_ps)
        or _short(C[3], n_si)
        or _short(C[4], n_si)
        or _short(P[2], n_pt)
        or _short(P[3], n_pt)
        or _short(P[4], n_pt)
        or _short(P[5], n_pt)
        or _crowded(P[0], n_pk)
    )


# what stops _pops before a status: a table to grow before the pop in hand goes on
_GROW_BOUND, _GROW_POINT, _GROW_FACE = 5, 6, 7


@njit(cache=True, no_alloc=True)
def _room_short(N: Any, P: Any, nodes: int, points: int) -> bool:  # pragma: no cover - compiled
    """Whether :func:`_room` would grow anything for ``nodes`` more nodes and ``points`` more points."""
    n_node, n_heap, n_pt, n_pk = _room_needs(N[5], nodes, points)
    return (
        _short(N[0], n_node)
        or _short(N[1], n_node)
        or _short(N[2], n_node)
        or _short(N[3], n_heap)
        or _short(N[4], n_heap)
        or _short(P[2], n_pt)
        or _short(P[3], n_pt)
        or _short(P[4], n_pt)
        or _short(P[5], n_pt)
        or _crowded(P[0], n_pk)
    )


@njit(cache=True, no_alloc=True)
def _bound_needs(c: Any, n_seg: int) -> tuple[int, int, int, int, int, int]:  # pragma: no cover - compiled
    """The rows of ``fr``, ``frs``, ``on``, ``onr`` and the keys of ``fk``, ``ok_`` that what a pop's two bounds can
    make needs: four fronts of at most ``n_seg`` rows (the last one's hinges written after its rows) and two edges'
    segments."""
    return c[9] + 5 * n_seg + 1, c[10] + 5, c[11] + 2 * n_seg + 1, c[12] + 3, c[14] + 4, c[15] + 2


@njit(cache=True, no_alloc=True)
def _bound_short(c: Any, BS: Any, n_seg: int) -> bool:  # pragma: no cover - compiled
    """Whether the bound's tables lack room for what a pop's two bounds can make (:func:`_bound_needs`)."""
    n_fr, n_frs, n_on, n_onr, n_fk, n_ok = _bound_needs(c, n_seg)
    return (
        _short(BS[2], n_fr)
        or _short(BS[3], n_frs)
        or _short(BS[6], n_on)
        or _short(BS[7], n_onr)
        or _crowded(BS[0], n_fk)
        or _crowded(BS[4], n_ok)
    )


@njit(cache=True, no_alloc=True)
def _pops(
    N: Any, P: Any, C: Any, S: Any, B: Any, BS: Any, M: Any, G: Any, budget: int, over: int, parts: Any, items: Any,
    pages_buf: Any, mp: Any, mc: Any, held: Any, held_depth: Any,
) -> int:  # pragma: no cover - compiled
    """The queue's pops in the tables as they are, until a status (:data:`FOUND`, :data:`STOPPED`, :data:`EMPTY`) or
    a table too small for the pop in hand: :data:`_GROW_BOUND` (the bound's), :data:`_GROW_POINT` (a point's
    expansion: ``held[3]`` members), :data:`_GROW_FACE` (a face entry's: ``held[3]`` nodes, ``held[4]`` cells). The
    pop is kept in ``held`` (its node and key; ``held[0]`` -1: none) and ``held_depth`` (its depth) and goes on in
    the call after :func:`_run` grew the table. The loop allocates nothing, so it counts no references: a loop whose
    arrays may be replaced (grown) counts every one of them at every turn."""
    ni, nf, pend, hk, hd, c = N
    seen_k, seen_v, iv, ivn = S
    dv, bgi, bd, segi, segf, bpar = B
    fk, fv, fr, frs, ok_, ov, on, onr = BS
    gi, par, goals_p = G[2], G[3], G[4]
    inc_ptr = M[3]
    best, pbv = P[4], P[5]
    bounded = gi[1] != 0
    n_seg = segi.shape[1]
    while True:
        if held[0] >= 0:  # the pop in hand, its table grown
            nid, key0, depth = held[0], held[1], held_depth[0]
            held[0] = -1
        else:
            if c[1] <= 0:
                return EMPTY
            key0, depth, nid = _heap_pop(hk, hd, c)
            c[3] += 1
            if (budget >= 0 and c[3] > budget) or key0 > over:
                _heap_push(hk, hd, c, key0, depth, nid)
                return STOPPED
        kind = ni[nid, 0]
        if kind == _POINT:
            if ni[nid, 1] == _GOAL_ID:
                c[4] = nid
                return FOUND
            if nf[nid, 0] > best[ni[nid, 1]]:
                continue
        elif nf[nid, 0] > best[ni[nid, 1]]:
            continue
        if bounded and pend[nid]:
            if _bound_short(c, BS, n_seg):
                held[0], held[1], held_depth[0] = nid, key0, depth
                return _GROW_BOUND
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
            if _poly_short(C, P, c, n_mem) or _room_short(N, P, _point_nodes(n_mem, goals_p.shape[0]), 0):
                held[0], held[1], held_depth[0], held[3] = nid, key0, depth, n_mem
                return _GROW_POINT
            _expand_point(N, P, C, M, G, nid, key, nf[nid, 0], mp, mc, n_mem)
        else:
            deg = inc_ptr[ni[nid, 6] + 1] - inc_ptr[ni[nid, 6]]
            if _crowded(seen_k, c[13] + deg) or _poly_short(C, P, c, deg):
                held[0], held[1], held_depth[0], held[3], held[4] = nid, key0, depth, 0, 0
                return _GROW_FACE
            need, cells = _open_face(N, P, C, M, G, seen_k, seen_v, iv, ivn, parts, items, nid, pages_buf)
            if need != 0:
                held[0], held[1], held_depth[0], held[3], held[4] = nid, key0, depth, need, cells
                return _GROW_FACE


@njit(cache=True)
def _run(
    N: Any, P: Any, C: Any, S: Any, B: Any, BS: Any, M: Any, G: Any, budget: int, over: int,
) -> tuple[int, Any, Any, Any, Any, Any]:  # pragma: no cover - compiled
    """:meth:`AnyAngleSearch._run` from the queue as it stands (the start expanded by :func:`_start`):
    :data:`FOUND` (the goal's node in ``c[4]``), :data:`STOPPED` (at ``budget`` pops of this run, -1: none, or a
    key above ``over``) or :data:`EMPTY`; with ``N``, ``P``, ``C``, ``S`` and ``BS``, grown. The pops are
    :func:`_pops`'s; this grows the table it stops for and calls it again."""
    c = N[5]
    inc_ptr = M[3]
    segi = B[3]
    goals_p = G[4]
    parts = np.empty((64, 2))
    items = np.empty((64, 2))
    deg_max = max(1, int(np.max(inc_ptr[1:] - inc_ptr[:-1])))
    pages_buf = np.empty((3, deg_max), np.int64)  # _open_face's scratch
    mp = np.empty(deg_max * deg_max, np.int64)  # a point's members (polygons, coordinates): _members's scratch
    mc = np.empty((deg_max * deg_max, 2))
    held = np.full(5, -1, np.int64)  # the pop in hand: node, key, -, what it needs
    held_depth = np.zeros(1)  # and its depth
    while True:
        status = _pops(N, P, C, S, B, BS, M, G, budget, over, parts, items, pages_buf, mp, mc, held, held_depth)
        if status == _GROW_BOUND:
            n_fr, n_frs, n_on, n_onr, n_fk, n_ok = _bound_needs(c, segi.shape[1])
            fk, fv, fr, frs, ok_, ov, on, onr = BS
            fk, fv = _fit(fk, fv, n_fk)
            ok_, ov = _fit(ok_, ov, n_ok)
            BS = (fk, fv, _grow(fr, n_fr), _grow(frs, n_frs), ok_, ov, _grow(on, n_on), _grow(onr, n_onr))
        elif status == _GROW_POINT:
            n_mem = held[3]
            C, P = _room_poly(C, P, c, n_mem)
            N, P = _room(N, P, _point_nodes(n_mem, goals_p.shape[0]), 0)
        elif status == _GROW_FACE:
            nid = held[0]
            deg = inc_ptr[N[0][nid, 6] + 1] - inc_ptr[N[0][nid, 6]]
            seen_k, seen_v, iv, ivn = S
            seen_k, seen_v = _fit(seen_k, seen_v, c[13] + deg)
            C, P = _room_poly(C, P, c, deg)
            need, cells = held[3], held[4]
            if need != 0:
                N, P = _room(N, P, need, 0)
                iv = _grow(iv, c[2] + cells)
                ivn = _grow1(ivn, c[2] + cells)
                parts = _grow(parts, cells)
                items = _grow(items, cells)
            S = (seen_k, seen_v, iv, ivn)
        else:
            return status, N, P, C, S, BS
    return EMPTY, N, P, C, S, BS  # not reached


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
