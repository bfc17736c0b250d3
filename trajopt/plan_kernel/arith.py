"""The compiled search's scalar arithmetic, queue, growing arrays and hash tables (:mod:`trajopt.plan_kernel`).

Python's :func:`math.hypot` bit for bit (:func:`_py_hypot`), the objective's cost by the operations of
:func:`mpa.planners.search_common.cost_function`, a binary heap of ``(key, depth, node)`` rows, arrays grown by
doubling, and open-addressing hash tables of integer keys (faster than numba's typed dicts, and nothing of them is
compiled when the interpreter touches them).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from mpa.planners.graph import bounds as graph_bounds
from mpa.planners.graph.base import TIE_BREAK, TIE_BREAK_2
from mpa.planners.search_common import FACE_SAFETY
from trajopt._numba import njit

# node kinds (column 0 of the node ints)
_POINT, _FACE, _INTERVAL = 0, 1, 2
# node ints: kind, key (a point's) or root key, root, last (a point's) or parent, polygon, ax, the face's vertex,
# previous polygon, origin's polygon, the face's other edge, the polygon's row in the polygon table
_NI = 11
# node floats: g or g_root, r (or a point's frm), sig (or a point's to), a, y0, y1, lo, hi, previous a, origin
_NF = 13
# what the kernel returns
FOUND, STOPPED, EMPTY = 0, 1, 4
# the counters: nodes, heap entries, interval cells, pops this run, the goal's node, (unused: 5-8), the fronts' rows
# and slots, the segments on an edge's rows and slots, the keys in the tables of seen, fronts and segments on an
# edge, the points and the keys in the points' table, the polygons, the keys in their table and their sides
_C = 21
_START_ID, _GOAL_ID = 0, 1
_BOUND_SAFETY = graph_bounds.BOUND_SAFETY
_NO_LIMIT = 2**62


# fmt: off
# (the kernels' long argument lists are kept a few to a line)

# ------------------------------------------------------------------------------------------- scalar helpers
@njit(cache=True, no_alloc=True)
def _split(a: float) -> tuple[float, float]:  # pragma: no cover - compiled
    c = 134217729.0 * a  # Veltkamp: 2**27 + 1
    hi = c - (c - a)
    return hi, a - hi


@njit(cache=True, no_alloc=True)
def _two_prod(x: float, y: float) -> tuple[float, float]:  # pragma: no cover - compiled
    z = x * y
    xh, xl = _split(x)
    yh, yl = _split(y)
    return z, ((xh * yh - z) + xh * yl + xl * yh) + xl * yl


@njit(cache=True, no_alloc=True)
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


@njit(cache=True, no_alloc=True)
def _cost(dx: float, dy: float, fastest: bool, va: float, vb: float) -> float:  # pragma: no cover - compiled
    """:func:`mpa.planners.search_common.cost_function`'s cost, the same operations."""
    if fastest:
        ta, tb = abs(dx) / va, abs(dy) / vb
        m = ta if ta >= tb else tb
        return m + TIE_BREAK * (ta + tb) + TIE_BREAK_2 * _py_hypot(ta, tb)
    return _py_hypot(dx, dy)


@njit(cache=True, no_alloc=True)
def _through_face(
    ax: int, x_seg: float, x_rest: float, r: float, y: float, cp: float, cm: float, on_edge: bool, off: float,
    fastest: bool, va: float, vb: float,
) -> float:  # pragma: no cover - compiled
    """:func:`mpa.planners.search_common._through_face`, the same operations."""
    q1 = abs(y - r)
    x, d = y + cp, cm - y
    q2 = d if d < x else x
    if on_edge:
        x = abs(y - off)
        q2 = x if x < q2 else q2
    if ax == 0:
        a1, b1, a2, b2 = x_seg, q1, x_rest, q2
    else:
        a1, b1, a2, b2 = q1, x_seg, q2, x_rest
    if fastest:
        ta, tb = a1 / va, b1 / vb
        c = (tb if tb > ta else ta) + TIE_BREAK * (ta + tb) + TIE_BREAK_2 * _py_hypot(ta, tb)
        ta, tb = a2 / va, b2 / vb
        return c + ((tb if tb > ta else ta) + TIE_BREAK * (ta + tb) + TIE_BREAK_2 * _py_hypot(ta, tb))
    return _py_hypot(a1, b1) + _py_hypot(a2, b2)


@njit(cache=True, no_alloc=True)
def _least_through_face(
    ax: int, x_seg: float, x_rest: float, r: float, y0: float, y1: float, cp: float, cm: float, on_edge: bool,
    off: float, fastest: bool, va: float, vb: float,
) -> float:  # pragma: no cover - compiled
    """:func:`mpa.planners.search_common.least_through_face`, the same operations (its candidate points in another
    order: the least of the same values)."""
    best = _through_face(ax, x_seg, x_rest, r, y0, cp, cm, on_edge, off, fastest, va, vb)
    if y1 > y0:
        v = _through_face(ax, x_seg, x_rest, r, y1, cp, cm, on_edge, off, fastest, va, vb)
        if v < best:
            best = v
        s = x_seg + x_rest
        k = x_seg / s if s > 0.0 else 0.0
        p = 0.0
        q = 0.0
        if fastest:
            vv = va if ax == 0 else vb
            ve = vb if ax == 0 else va
            p = x_seg / vv * ve
            q = x_rest / vv * ve
        n = 3
        if fastest:
            n += 4
        if on_edge:
            n += 4 if fastest else 2
        for i in range(n):
            if i == 0:
                y = r
            elif i == 1:
                y = r + (cm - r) * k
            elif i == 2:
                y = r - (cp + r) * k
            elif fastest and i < 7:
                if i == 3:
                    y = r - p
                elif i == 4:
                    y = r + p
                elif i == 5:
                    y = q - cp
                else:
                    y = cm - q
            else:
                j = i - (7 if fastest else 3)
                if j == 0:
                    y = off
                elif j == 1:
                    y = r + (off - r) * k
                elif j == 2:
                    y = off - q
                else:
                    y = off + q
            if y0 < y < y1:
                v = _through_face(ax, x_seg, x_rest, r, y, cp, cm, on_edge, off, fastest, va, vb)
                if v < best:
                    best = v
    return best * (1.0 - FACE_SAFETY)


@njit(cache=True, no_alloc=True)
def _floor(x: float) -> int:  # pragma: no cover - compiled
    return math.floor(x)


# ------------------------------------------------------------------------------------------------- heap
@njit(cache=True, no_alloc=True)
def _less(hk: Any, hd: Any, i: int, j: int) -> bool:  # pragma: no cover - compiled
    if hk[i, 0] != hk[j, 0]:
        return hk[i, 0] < hk[j, 0]
    if hd[i] != hd[j]:
        return hd[i] < hd[j]
    return hk[i, 1] < hk[j, 1]


@njit(cache=True, no_alloc=True)
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


@njit(cache=True, no_alloc=True)
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


@njit(cache=True, no_alloc=True)
def _short(a: Any, need: int) -> bool:  # pragma: no cover - compiled
    """Whether ``a`` has fewer than ``need`` rows (:func:`_grow` would grow it)."""
    return need > a.shape[0]


@njit(cache=True)
def _grow(a: Any, need: int) -> Any:  # pragma: no cover - compiled
    """``a`` (2-D) with at least ``need`` rows, doubled."""
    if not _short(a, need):
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
    if not _short(a, need):
        return a
    n = a.shape[0]
    while n < need:
        n *= 2
    out = np.empty(n, a.dtype)
    out[: a.shape[0]] = a
    return out


# ------------------------------------------------------------------------------------------ hash tables
@njit(cache=True, no_alloc=True)
def _slot(keys: Any, vals: Any, k: Any) -> int:  # pragma: no cover - compiled
    """The row of ``keys`` holding the key ``k`` (a tuple of ints), or the empty row (``vals`` -1) where it goes:
    open addressing, linear probing, the table at most half full (:func:`_fit`)."""
    h = 1469598103934665603
    for x in k:
        h = (h ^ x) * 1099511628211
    mask = keys.shape[0] - 1
    i = (h ^ (h >> 29)) & mask
    w = keys.shape[1]
    while vals[i] >= 0:
        same = True
        for j in range(w):
            if keys[i, j] != k[j]:
                same = False
                break
        if same:
            return i
        i = (i + 1) & mask
    return i


@njit(cache=True, no_alloc=True)
def _put(keys: Any, vals: Any, c: Any, count: int, k: Any, v: int) -> None:  # pragma: no cover - compiled
    """``table[k] = v`` (``v`` >= 0); ``c[count]`` counts the keys."""
    i = _slot(keys, vals, k)
    if vals[i] < 0:
        c[count] += 1
        for j in range(keys.shape[1]):
            keys[i, j] = k[j]
    vals[i] = v


@njit(cache=True, no_alloc=True)
def _crowded(keys: Any, n: int) -> bool:  # pragma: no cover - compiled
    """Whether ``n`` keys would fill the table ``keys`` more than half (:func:`_fit` would rebuild it)."""
    return 2 * n > keys.shape[0]


@njit(cache=True)
def _fit(keys: Any, vals: Any, n: int) -> tuple[Any, Any]:  # pragma: no cover - compiled
    """The table with room for ``n`` keys at most half full: itself, or rebuilt twice (or more) as large."""
    if not _crowded(keys, n):
        return keys, vals
    cap = keys.shape[0]
    while 2 * n > cap:
        cap *= 2
    k2 = np.zeros((cap, keys.shape[1]), np.int64)
    v2 = np.full(cap, -1, np.int64)
    for i in range(keys.shape[0]):
        if vals[i] >= 0:
            j = _slot(k2, v2, keys[i])
            k2[j] = keys[i]
            v2[j] = vals[i]
    return k2, v2
