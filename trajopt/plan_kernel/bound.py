"""The passing bound in the compiled search: :class:`~mpa.planners.graph.bounds.PassingBound`'s ``point`` and
``entry``, its fronts of hinges made from the bound's segments by the same operations (:mod:`trajopt.plan_kernel`).
"""

from __future__ import annotations

import math
from typing import Any

from mpa.planners.graph.base import TIE_BREAK
from trajopt._numba import njit
from trajopt.plan_kernel.arith import _BOUND_SAFETY, _START_ID, _put, _slot

# fmt: off
# (the kernels' long argument lists are kept a few to a line)

# ------------------------------------------------------------------------------------------- passing bound
@njit(cache=True, no_alloc=True)
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


@njit(cache=True, no_alloc=True)
def _to_stretch(dv: Any, bgi: Any, bd: Any, x: int, e: int, u0: float, u1: float) -> float:  # pragma: no cover
    """The distance from the vertex ``x`` to the stretch ``[u0, u1]`` of edge ``e`` (m), as the bound's numpy."""
    a = dv[x, bgi[0, e]] + u0
    b = dv[x, bgi[1, e]] + bd[1, e] - u1
    return b if b < a else a


@njit(cache=True, no_alloc=True)
def _front(
    c: Any, fk: Any, fv: Any, fr: Any, frs: Any, dv: Any, bgi: Any, bd: Any, segi: Any, segf: Any, bpar: Any,
    ax: int, w: int, x: int,
) -> int:  # pragma: no cover - compiled
    """The slot of :meth:`PassingBound._front` ``(ax, w, x)``, made and kept when first asked for: the same hinges
    ``c1``, ``c2`` by the same operations, and the same least over them (a front of another order among equal ``c1``
    has the same least). The arrays hold room for two fronts of every segment: the hinges are written after the
    front's own rows, those near the least sorted there by ``c1`` (insertion sort: no array is allocated), and the
    front written from them."""
    key = (ax, w, x)
    known = fv[_slot(fk, fv, key)]
    if known >= 0:
        return known
    v_w = bpar[2] if ax == 0 else bpar[3]
    v_e = bpar[3] if ax == 0 else bpar[2]
    s1, s2 = TIE_BREAK / v_e, (1.0 + TIE_BREAK) / v_e
    n = segi.shape[1]
    j0 = c[9]
    h0 = j0 + n  # the hinges' rows
    least = math.inf
    for k in range(n):
        if ax == 0:
            dw = _to_stretch(dv, bgi, bd, w, segi[0, k], segf[0, k], segf[1, k])
            d = _to_stretch(dv, bgi, bd, x, segi[1, k], segf[2, k], segf[3, k])
        else:
            dw = _to_stretch(dv, bgi, bd, w, segi[1, k], segf[2, k], segf[3, k])
            d = _to_stretch(dv, bgi, bd, x, segi[0, k], segf[0, k], segf[1, k])
        a = dw / v_w
        c1 = (1.0 + TIE_BREAK) * a + segf[4, k] + s1 * d
        c2 = TIE_BREAK * a + segf[4, k] + s2 * d
        fr[h0 + k, 0], fr[h0 + k, 1] = c1, c2
        m = c1 if c1 >= c2 else c2
        if m < least:
            least = m
    m = 0  # the hinges near the least, in order of c1
    for k in range(n):
        c1, c2 = fr[h0 + k, 0], fr[h0 + k, 1]
        if c2 <= least:
            i = h0 + m
            while i > h0 and fr[i - 1, 0] > c1:
                fr[i, 0], fr[i, 1] = fr[i - 1, 0], fr[i - 1, 1]
                i -= 1
            fr[i, 0], fr[i, 1] = c1, c2
            m += 1
    j = j0
    low = math.inf
    for i in range(h0, h0 + m):
        c1, c2 = fr[i, 0], fr[i, 1]
        if j == j0 or c2 < low:
            fr[j, 0], fr[j, 1] = c1, c2
            j += 1
        if c2 < low:
            low = c2
    c[9] = j
    slot = c[10]
    c[10] = slot + 1
    frs[slot, 0], frs[slot, 1] = j0, j - j0
    _put(fk, fv, c, 14, key, slot)
    return slot


@njit(cache=True, no_alloc=True)
def _on_edge(
    c: Any, ok_: Any, ov: Any, on: Any, onr: Any, dv: Any, bgi: Any, bd: Any, segi: Any, segf: Any, bpar: Any,
    ax: int, w: int, other: int,
) -> int:  # pragma: no cover - compiled
    """The slot of the segments on the face's own edge (:meth:`PassingBound._parts`): the vertex robot's time, ``W_k``
    and the stretch on the edge, made and kept when first asked for."""
    key = (ax, w, other)
    known = ov[_slot(ok_, ov, key)]
    if known >= 0:
        return known
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
    _put(ok_, ov, c, 15, key, slot)
    return slot


@njit(cache=True, no_alloc=True)
def _entry(
    c: Any, dv: Any, bgi: Any, bd: Any, segi: Any, segf: Any, bpar: Any, fk: Any, fv: Any, fr: Any, frs: Any,
    ok_: Any, ov: Any, on: Any, onr: Any, ax: int, w: int, other: int, y0: float, y1: float,
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
    st = _front(c, fk, fv, fr, frs, dv, bgi, bd, segi, segf, bpar, ax, w, t_e)
    sh = _front(c, fk, fv, fr, frs, dv, bgi, bd, segi, segf, bpar, ax, w, h_e)
    slot = _on_edge(c, ok_, ov, on, onr, dv, bgi, bd, segi, segf, bpar, ax, w, other)
    bt = _least_front(fr, frs, st, s1, s2, y0)
    bh = _least_front(fr, frs, sh, s1, s2, yh)
    best = bh if bh < bt else bt
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


@njit(cache=True, no_alloc=True)
def _point_bound(
    c: Any, P: Any, M: Any, dv: Any, bgi: Any, bd: Any, segi: Any, segf: Any, bpar: Any, fk: Any, fv: Any, fr: Any,
    frs: Any, ok_: Any, ov: Any, on: Any, onr: Any, pbv: Any, key: int,
) -> float:  # pragma: no cover - compiled
    """:meth:`PassingBound.point` of the point ``key``, kept in ``pbv`` (NaN: not yet): a face end's is the bound
    through its face over its one coordinate, a corner's through the face of robot B's vertex's first edge."""
    if key == _START_ID:
        return bpar[1]
    out = pbv[key]
    if math.isnan(out):
        pt, pty = P[2], P[3]
        if pt[key, 0] == 1:
            ax, w, other, y = pt[key, 1], pt[key, 2], pt[key, 3], pty[key]
        else:
            wb = pt[key, 2]
            ax, w, other, y = 0, pt[key, 1], M[4][M[3][wb]], M[5][M[3][wb]]
        out = pbv[key] = _entry(c, dv, bgi, bd, segi, segf, bpar, fk, fv, fr, frs, ok_, ov, on, onr, ax, w, other,
                                y, y)
    return out
