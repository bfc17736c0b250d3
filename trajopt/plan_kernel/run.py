"""The compiled search's loop: :meth:`~mpa.planners.graph.search.AnyAngleSearch._run` over the node arrays, and the
start's expansion (:mod:`trajopt.plan_kernel`)."""

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
    NEED_MEMBERS,
    NEED_PAGES,
    STOPPED,
    _cost,
    _fit,
    _floor,
    _grow,
    _grow1,
    _heap_pop,
    _heap_push,
)
from trajopt.plan_kernel.bound import _entry, _point_bound
from trajopt.plan_kernel.expand import _expand_point, _open_face

# fmt: off
# (the kernels' long argument lists are kept a few to a line)

# ---------------------------------------------------------------------------------------------------- run
@njit(cache=True)
def _run(
    ni: Any, nf: Any, pend: Any, hk: Any, hd: Any, c: Any, best: Any, iv: Any, ivn: Any, seen_k: Any, seen_v: Any,
    pi: Any, si: Any, sf: Any, fi: Any, pg: Any, pgb: Any, ti: Any, tf: Any, mp: Any, mc: Any,
    gd: Any, vd: Any, gi: Any, par: Any, goals_p: Any, goals_c: Any,
    dv: Any, bgi: Any, bd: Any, segi: Any, segf: Any, bpar: Any, fk: Any, fv: Any, fr: Any, frs: Any, ok_: Any,
    ov: Any, on: Any, onr: Any, pbv: Any, fsl: Any, budget: int, over: int,
) -> tuple[Any, ...]:  # pragma: no cover - compiled
    """:meth:`AnyAngleSearch._run` from the queue as it stands (the start expanded by the caller's first call):
    :data:`FOUND` (the goal's node in ``c[4]``), :data:`STOPPED` (at ``budget`` pops of this run, -1: none, or a
    key above ``over``), :data:`EMPTY`, or a request (``c[5:9]``); with the node, heap and interval arrays, grown."""
    parts = np.empty((64, 2))
    items = np.empty((64, 2))
    bounded = gi[1] != 0
    while c[1] > 0:
        key0, depth, nid = _heap_pop(hk, hd, c)
        c[3] += 1
        if (budget >= 0 and c[3] > budget) or key0 > over:
            _heap_push(hk, hd, c, key0, depth, nid)
            return STOPPED, ni, nf, pend, hk, hd, iv, ivn, fr, frs, on, onr, seen_k, seen_v, fk, fv, ok_, ov
        kind = ni[nid, 0]
        if kind == _POINT:
            if ni[nid, 1] == _GOAL_ID:
                c[4] = nid
                return FOUND, ni, nf, pend, hk, hd, iv, ivn, fr, frs, on, onr, seen_k, seen_v, fk, fv, ok_, ov
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
            fk, fv = _fit(fk, fv, c[14] + 4)
            ok_, ov = _fit(ok_, ov, c[15] + 2)
            if kind == _POINT:
                h = _point_bound(c, ti, tf, dv, bgi, bd, segi, segf, bpar, fk, fv, fr, frs, ok_, ov, on, onr, pbv, fsl,
                                 ni[nid, 1])
                key1 = _floor((nf[nid, 0] + h) * par[5])
            else:
                g_root, r0, r1, a = nf[nid, 0], nf[nid, 1], nf[nid, 2], nf[nid, 5]
                y0, y1 = nf[nid, 6], nf[nid, 7]
                h0 = _point_bound(c, ti, tf, dv, bgi, bd, segi, segf, bpar, fk, fv, fr, frs, ok_, ov, on, onr, pbv, fsl,
                                  ni[nid, 1])
                face = ni[nid, 6]
                h1 = _entry(c, dv, bgi, bd, segi, segf, bpar, fk, fv, fr, frs, ok_, ov, on, onr, fi[face, 0],
                            fi[face, 1], fi[face, 2], y0, y1, fsl, face)
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
                return NEED_MEMBERS, ni, nf, pend, hk, hd, iv, ivn, fr, frs, on, onr, seen_k, seen_v, fk, fv, ok_, ov
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
                return NEED_PAGES, ni, nf, pend, hk, hd, iv, ivn, fr, frs, on, onr, seen_k, seen_v, fk, fv, ok_, ov
            seen_k, seen_v = _fit(seen_k, seen_v, c[13] + fi[face, 4])
            while True:
                need, cells = _open_face(
                    ni, nf, pend, hk, hd, c, best, pi, si, sf, fi, pg, pgb, gd, vd, gi, par, goals_p, goals_c,
                    seen_k, seen_v, iv, ivn, parts, items, nid,
                )
                if need == 0:
                    break
                ni = _grow(ni, c[0] + need)
                nf = _grow(nf, c[0] + need)
                pend = _grow1(pend, c[0] + need)
                hk = _grow(hk, c[1] + need)
                hd = _grow1(hd, c[1] + need)
                iv = _grow(iv, c[2] + cells)
                ivn = _grow1(ivn, c[2] + cells)
                parts = _grow(parts, cells)
                items = _grow(items, cells)
    return EMPTY, ni, nf, pend, hk, hd, iv, ivn, fr, frs, on, onr, seen_k, seen_v, fk, fv, ok_, ov


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
