"""The verification gate's pass over the rows in numpy, for one-shot processes: numba is never imported.

:func:`check_rows` and :func:`between_rows` take the arguments of the compiled kernels of
:mod:`trajopt.verify.kernels` and return the same results, bit for bit (tested on the pipeline's own arguments,
perturbed ones and hypothesis's): the same floating-point operations in the same order (``+ − × /``, ``abs``,
comparisons), on many rows at once instead of one row at a time.

- Python's ``min``/``max`` of two floats (``b if b < a else a``, which keeps ``a`` when ``b`` is NaN and the first
  of two equal zeros) are :func:`_pmin` and :func:`_pmax`; the graph distance's four terms, which are never NaN
  nor ``−0.0``, take :func:`numpy.minimum` (:func:`_dists`).
- The route positions are ``np.searchsorted(breaks, r, side="right")``, the graph distance has the terms of
  :meth:`mpa.geometry.GraphGeometry.distance` in their order, and the chords that no junction cuts take the cell's
  exact minimum where the robots could meet, all vectorised. The chords that a junction cuts (a robot passes a
  junction between two rows: a few per edge of a route) are done one at a time by the kernel's scalar code
  (:func:`_cut_chord_min`).
- The rows' "first row wins" choices (the minimum's row, the peaks' rows, with the kernels' ``k == 0`` start) are
  the kernels' running minimum and maximum, carried from block to block (:func:`_running_min`,
  :func:`_running_max`).
- The rows go in blocks of :data:`_BLOCK`: temporaries of a whole grid were fresh memory on every call.

A command-line process verifies one trajectory: a few milliseconds of numpy cost less than importing numba and
loading its compiled kernels (about half a second); the per-process switch of :mod:`trajopt._numba` picks these
twins there. This module imports numpy, math and :mod:`mpa`'s array types only (not the kernels' module, which
imports numba).

Contract (as the kernels'): the routes' ``breaks`` are non-decreasing (:class:`mpa.geometry.DirectedRoute`), the
graph's arrays are those of :class:`mpa.geometry.GraphGeometry` (``dv`` finite or ``+inf``), the limits and the
row step are finite and positive, ``ends`` holds valid positions, and there is at least one row. :func:`check_rows`
takes any rows (non-finite values and edge indices out of range are reported in ``RES["bad"]``, as by the kernel);
:func:`between_rows` takes finite ones.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from mpa._arrays import FloatArray, IntArray
from trajopt.verify.elementwise import BLOCK as _BLOCK
from trajopt.verify.elementwise import pmax as _pmax
from trajopt.verify.elementwise import pmin as _pmin
from trajopt.verify.results import NRES as _NRES
from trajopt.verify.results import RES

__all__ = ["RES", "between_rows", "check_rows"]

#: A graph as the kernels take it: ``tails, heads, lengths, dv`` (:class:`mpa.geometry.GraphGeometry`).
Graph = tuple[IntArray, IntArray, FloatArray, FloatArray]
#: A route as the kernels take it: ``breaks, edges, dirs, entry`` (:class:`mpa.geometry.DirectedRoute`).
Route = tuple[FloatArray, IntArray, IntArray, FloatArray]


# ------------------------------------------------------------------------------------------ elementwise
def _clamp(x: FloatArray, low: float, high: float) -> FloatArray:
    """``min(max(x, low), high)`` elementwise, as the kernels clamp to a route (shape of ``x``)."""
    return _pmin(_pmax(x, low), high)


def _pieces(breaks: FloatArray, r: FloatArray) -> NDArray[np.intp]:
    """The route piece of each coordinate ``r`` (m, shape (K,)): ``min(max(searchsorted(breaks, r, "right") − 1,
    0), M − 1)``, the kernels' ``_piece``. ``breaks`` (shape (M+1,)) non-decreasing."""
    i = np.searchsorted(breaks, r, side="right") - 1
    return np.minimum(np.maximum(i, 0), len(breaks) - 2)


def _positions(route: Route, r: FloatArray) -> tuple[IntArray, FloatArray]:
    """``(edge, offset)`` (offset in m) at route coordinates ``r`` (m, shape (K,)), clamped to the route: the
    kernels' ``_position`` (:meth:`mpa.geometry.DirectedRoute.positions`)."""
    breaks, edges, dirs, entry = route
    rc = _clamp(r, breaks[0], breaks[-1])
    i = _pieces(breaks, rc)
    return edges[i], entry[i] + dirs[i] * (rc - breaks[i])


def _dists(graph: Graph, ea: IntArray, sa: FloatArray, eb: IntArray, sb: FloatArray) -> FloatArray:
    """Graph distance (m) between ``(ea, sa)`` and ``(eb, sb)`` elementwise (shape (K,)):
    :meth:`mpa.geometry.GraphGeometry.distance` with the kernels' ``_dist``'s terms in their order.

    The minima are :func:`numpy.minimum`, which equals Python's ``min`` here: no term is NaN (the offsets are
    finite, the lengths finite, ``dv`` finite or ``+inf``) and none is ``−0.0`` (``dv ≥ +0.0``, ``la − sa`` and
    ``|sa − sb|`` are ``+0.0`` when zero), so equal terms are the same bits.
    """
    tails, heads, lengths, dv = graph
    nv = dv.shape[1]
    flat = dv.reshape(-1)
    ta, ha, la = tails[ea] * nv, heads[ea] * nv, lengths[ea]
    tb, hb, lb = tails[eb], heads[eb], lengths[eb]
    qa, qb = la - sa, lb - sb
    d = np.minimum(
        np.minimum(sa + flat[ta + tb] + sb, sa + flat[ta + hb] + qb),
        np.minimum(qa + flat[ha + tb] + sb, qa + flat[ha + hb] + qb),
    )
    same = np.flatnonzero(ea == eb)
    if len(same):
        d[same] = np.minimum(d[same], np.abs(sa[same] - sb[same]))
    return d


def _running_min(cur: float, row: int, x: FloatArray, lo: int) -> tuple[float, int]:
    """The kernels' running minimum ``(cur, row)`` carried over ``x`` (shape (K,), rows ``lo, lo+1, …``): replaced
    where ``x[k] < cur``, so the row is the first occurrence of the minimum (NaN never replaces, nor is replaced)."""
    below = np.flatnonzero(x < cur)
    if len(below) == 0:
        return cur, row
    k = int(below[np.argmin(x[below])])  # argmin: the first of equal minima; no NaN is below anything
    return float(x[k]), lo + k


def _running_max(cur: float, row: int, x: FloatArray, lo: int) -> tuple[float, int]:
    """The kernels' running maximum ``(cur, row)`` carried over ``x``: replaced where ``x[k] > cur``."""
    above = np.flatnonzero(x > cur)
    if len(above) == 0:
        return cur, row
    k = int(above[np.argmax(x[above])])
    return float(x[k]), lo + k


def _blocks(n: int) -> list[tuple[int, int]]:
    """``[(lo, hi), …]``: the rows ``0 … n−1`` in blocks of :data:`_BLOCK`."""
    return [(lo, min(lo + _BLOCK, n)) for lo in range(0, n, _BLOCK)]


# ------------------------------------------------------------------------------------------ scalar twins
# The kernels' scalar functions as plain Python on Python floats (the same IEEE operations), for the rare chords a
# junction cuts and the endpoint distances. A route is given as lists (:func:`_route_lists`), the graph as its
# arrays, read one element at a time (``item``).
#: A route as lists ``breaks, edges, dirs, entry``.
RouteLists = tuple[list[float], list[int], list[int], list[float]]


def _route_lists(route: Route) -> RouteLists:
    """A route's arrays as lists (shapes (M+1,), (M,), (M,), (M,))."""
    breaks, edges, dirs, entry = route
    return breaks.tolist(), edges.tolist(), dirs.tolist(), entry.tolist()


def _bisect_right(x: list[float], v: float) -> int:
    """The number of entries of the sorted ``x`` that are ``<= v`` (the kernels' ``_bisect_right``)."""
    lo, hi = 0, len(x)
    while lo < hi:
        mid = (lo + hi) // 2
        if v < x[mid]:
            hi = mid
        else:
            lo = mid + 1
    return lo


def _piece(breaks: list[float], r: float) -> int:
    """``clip(searchsorted(breaks, r, "right") − 1, 0, M − 1)`` (the kernels' ``_piece``)."""
    return min(max(_bisect_right(breaks, r) - 1, 0), len(breaks) - 2)


def _position(route: RouteLists, r: float) -> tuple[int, float]:
    """``(edge, offset)`` at route coordinate ``r`` (m), clamped to the route (the kernels' ``_position``)."""
    breaks, edges, dirs, entry = route
    r = min(max(r, breaks[0]), breaks[-1])
    i = _piece(breaks, r)
    return edges[i], entry[i] + dirs[i] * (r - breaks[i])


def _dist(graph: Graph, ea: int, sa: float, eb: int, sb: float) -> float:
    """Graph distance (m) of one pair of positions (the kernels' ``_dist``: the same terms in the same order)."""
    tails, heads, lengths, dv = graph
    ta, ha, la = tails.item(ea), heads.item(ea), lengths.item(ea)
    tb, hb, lb = tails.item(eb), heads.item(eb), lengths.item(eb)
    qa, qb = la - sa, lb - sb
    d = min(
        min(sa + dv.item(ta, tb) + sb, sa + dv.item(ta, hb) + qb),
        min(qa + dv.item(ha, tb) + sb, qa + dv.item(ha, hb) + qb),
    )
    if ea == eb:
        d = min(d, abs(sa - sb))
    return d


def _excluded(p0a: float, p0b: float, p1a: float, p1b: float, d0: float, d1: float) -> bool:
    """Whether the robots cannot meet along the chord ``p0 → p1``: ``d0 + d1 > (|ΔsA| + |ΔsB|)(1 + 1e-9) + 1e-12``
    (the distance is 1-Lipschitz in each route coordinate; the margin absorbs rounding of a head-on meeting)."""
    return d0 + d1 > (abs(p1a - p0a) + abs(p1b - p0b)) * (1.0 + 1e-9) + 1e-12


def _cell_min(graph: Graph, ra: RouteLists, rb: RouteLists, p0a: float, p0b: float, p1a: float, p1b: float) -> float:
    """Exact minimum (m) of the distance along a chord ``p0 → p1`` on which each robot stays on one edge: at an
    end, or 0 where the robots meet on one edge (the kernels' ``_cell_min``)."""
    (ba, ea_, da, na), (bb, eb_, db, nb) = ra, rb
    ia = _piece(ba, min(max(0.5 * (p0a + p1a), ba[0]), ba[-1]))
    ib = _piece(bb, min(max(0.5 * (p0b + p1b), bb[0]), bb[-1]))
    e, f = ea_[ia], eb_[ib]
    s0 = na[ia] + da[ia] * (min(max(p0a, ba[0]), ba[-1]) - ba[ia])
    s1 = na[ia] + da[ia] * (min(max(p1a, ba[0]), ba[-1]) - ba[ia])
    t0 = nb[ib] + db[ib] * (min(max(p0b, bb[0]), bb[-1]) - bb[ib])
    t1 = nb[ib] + db[ib] * (min(max(p1b, bb[0]), bb[-1]) - bb[ib])
    if e == f and (s0 - t0) * (s1 - t1) <= 0.0:  # the robots meet on one edge
        return 0.0
    return min(_dist(graph, e, s0, f, t0), _dist(graph, e, s1, f, t1))


def _cut_chord_min(
    graph: Graph, ra: RouteLists, rb: RouteLists, a0: float, a1: float, b0: float, b1: float, d0: float, d1: float
) -> float:
    """Exact minimum (m) of the distance along the chord ``(a0, a1) → (b0, b1)`` that a robot's junction cuts: cut
    at the parameters ``(x − a)/(b − a)`` of the junctions ``x`` strictly inside it, each piece by
    :func:`_cell_min` unless :func:`_excluded` (the kernels' ``_cut_chord_min``). ``d0``, ``d1``: the distance at
    the chord's ends."""
    cuts: list[float] = []
    for br, a, b in ((ra[0], a0, b0), (rb[0], a1, b1)):
        low, high = min(a, b), max(a, b)
        for x in br[1:-1]:
            if low < x < high:
                cuts.append((x - a) / (b - a))
    cuts.sort()
    m = len(cuts)
    da, db = b0 - a0, b1 - a1
    chord = math.inf
    t0, p0a, p0b, dd0 = 0.0, a0, a1, d0
    for q in range(m + 1):
        t1 = cuts[q] if q < m else 1.0
        if t1 == 1.0:  # the piece ends at the chord's end itself
            p1a, p1b, dd1 = b0, b1, d1
        else:
            p1a, p1b = a0 + t1 * da, a1 + t1 * db
            ea, oa = _position(ra, p1a)
            eb, ob = _position(rb, p1b)
            dd1 = _dist(graph, ea, oa, eb, ob)
        if t0 == 0.0:  # the piece starts at the chord's start itself
            p0a, p0b, dd0 = a0, a1, d0
        chord = min(chord, dd0, dd1)
        if not _excluded(p0a, p0b, p1a, p1b, dd0, dd1):
            chord = min(chord, _cell_min(graph, ra, rb, p0a, p0b, p1a, p1b))
        t0, p0a, p0b, dd0 = t1, p1a, p1b, dd1
    return chord


# ------------------------------------------------------------------------------------------ the rows
def _crosses(breaks: FloatArray, s: FloatArray) -> NDArray[np.bool_]:
    """Whether a junction of the route (an interior break) lies strictly inside each chord between consecutive
    coordinates ``s`` (m, shape (K,), finite); shape (K−1,). Only where the count of interior breaks at or below
    the row changes can one lie inside; there the breaks below the chord's higher end outnumber those at or below
    its lower end (``breaks`` non-decreasing)."""
    inner = breaks[1:-1]
    upto = np.searchsorted(inner, s, side="right")
    cross = upto[1:] != upto[:-1]
    k = np.flatnonzero(cross)
    if len(k):
        low, high = np.minimum(s[k], s[k + 1]), np.maximum(s[k], s[k + 1])
        cross[k] = np.searchsorted(inner, high, side="left") > np.searchsorted(inner, low, side="right")
    return cross


def _cell_mins(
    graph: Graph, ra: Route, rb: Route, p0a: FloatArray, p0b: FloatArray, p1a: FloatArray, p1b: FloatArray
) -> FloatArray:
    """:func:`_cell_min` of many chords ``p0 → p1`` (route coordinates in m, each shape (K,)) at once."""
    ba, ea_, da, na = ra
    bb, eb_, db, nb = rb
    ia = _pieces(ba, _clamp(0.5 * (p0a + p1a), ba[0], ba[-1]))
    ib = _pieces(bb, _clamp(0.5 * (p0b + p1b), bb[0], bb[-1]))
    e, f = ea_[ia], eb_[ib]
    sa, oa, xa = da[ia], na[ia], ba[ia]
    sb, ob, xb = db[ib], nb[ib], bb[ib]
    s0 = oa + sa * (_clamp(p0a, ba[0], ba[-1]) - xa)
    s1 = oa + sa * (_clamp(p1a, ba[0], ba[-1]) - xa)
    t0 = ob + sb * (_clamp(p0b, bb[0], bb[-1]) - xb)
    t1 = ob + sb * (_clamp(p1b, bb[0], bb[-1]) - xb)
    meet = (e == f) & ((s0 - t0) * (s1 - t1) <= 0.0)
    return np.where(meet, 0.0, _pmin(_dists(graph, e, s0, f, t0), _dists(graph, e, s1, f, t1)))


def _between(
    graph: Graph,
    ra: Route,
    rb: Route,
    S: FloatArray,
    A: FloatArray,
    d_route: FloatArray,
    dt: float,
    amax: FloatArray,
    jmax: FloatArray,
    out: FloatArray,
) -> None:
    """Lower bound (m) of the distance between consecutive rows into ``out`` (shape (N−1,)), the kernels'
    ``_between``: the chord's minimum (its ends' distances ``d_route``, shape (N,); the cell's exact minimum where
    the robots could meet; cut chords one at a time) minus ``Σ_r a_int·Δt²/8``,
    ``a_int = min(amax, max(|a_k|, |a_k+1|) + jmax·Δt/2)``."""
    if len(S) < 2:
        return
    a0, a1, b0, b1 = S[:-1, 0], S[:-1, 1], S[1:, 0], S[1:, 1]
    d0, d1 = d_route[:-1], d_route[1:]
    chord = _pmin(d0, d1)
    cut = _crosses(ra[0], S[:, 0]) | _crosses(rb[0], S[:, 1])
    near = ~(d0 + d1 > (np.abs(b0 - a0) + np.abs(b1 - a1)) * (1.0 + 1e-9) + 1e-12) & ~cut
    k = np.flatnonzero(near)
    if len(k):
        chord[k] = _pmin(chord[k], _cell_mins(graph, ra, rb, a0[k], a1[k], b0[k], b1[k]))
    cuts = np.flatnonzero(cut)
    if len(cuts):
        la, lb = _route_lists(ra), _route_lists(rb)
        ends = zip(*(x[cuts].tolist() for x in (a0, a1, b0, b1, d0, d1)), strict=True)
        chord[cuts] = [_cut_chord_min(graph, la, lb, *e) for e in ends]
    dev = 0.0 + _pmin(amax[0], _pmax(np.abs(A[:-1, 0]), np.abs(A[1:, 0])) + jmax[0] * dt / 2)
    dev = dev + _pmin(amax[1], _pmax(np.abs(A[:-1, 1]), np.abs(A[1:, 1])) + jmax[1] * dt / 2)
    out[:] = chord - dev * (dt * dt / 8.0)


def _route_distances(
    graph: Graph, ra: Route, rb: Route, S: FloatArray
) -> tuple[IntArray, FloatArray, IntArray, FloatArray, FloatArray]:
    """The rows' route positions ``(ea, oa, eb, ob)`` and the distance between them (m); each shape (N,)."""
    ea, oa = _positions(ra, S[:, 0])
    eb, ob = _positions(rb, S[:, 1])
    return ea, oa, eb, ob, _dists(graph, ea, oa, eb, ob)


def between_rows(
    graph: Graph,
    ra: Route,
    rb: Route,
    S: FloatArray,
    A: FloatArray,
    dt: float,
    amax: FloatArray,
    jmax: FloatArray,
) -> FloatArray:
    """Lower bound of the graph distance between consecutive rows (m). Shape (N−1,).

    The same numbers as :func:`trajopt.verify.kernels.between_rows`.

    Parameters
    ----------
    graph : tuple of ndarray
        ``(tails, heads, lengths, dv)`` (:class:`mpa.geometry.GraphGeometry`): shapes (E,), (E,), (E,) in m,
        (V, V) in m.
    ra, rb : tuple of ndarray
        Each robot's route ``(breaks, edges, dirs, entry)`` (:class:`mpa.geometry.DirectedRoute`): shapes (M+1,)
        in m, (M,), (M,), (M,) in m.
    S, A : ndarray, shape (N, 2)
        Route coordinates (m) and accelerations (m/s²) at the rows.
    dt : float
        Row step (s).
    amax, jmax : ndarray, shape (2,)
        Acceleration (m/s²) and jerk (m/s³) limits of A and B.

    Returns
    -------
    ndarray, shape (N−1,)
    """
    out = np.empty(max(len(S) - 1, 0))
    with np.errstate(all="ignore"):
        for lo, hi in _blocks(len(out)):  # the chords lo … hi−1: the rows lo … hi
            d_route = _route_distances(graph, ra, rb, S[lo : hi + 1])[-1]
            _between(graph, ra, rb, S[lo : hi + 1], A[lo : hi + 1], d_route, dt, amax, jmax, out[lo:hi])
    return out


def _bad(tt: FloatArray, E: IntArray, ne: int, arrays: tuple[FloatArray, ...]) -> float:
    """``RES["bad"]``: 1.0 for a non-finite time or value (first), 2.0 for an edge index outside ``[0, ne)``."""
    if not bool(np.isfinite(tt).all()) or not all(bool(np.isfinite(x).all()) for x in arrays):
        return 1.0
    if len(E) and (int(E.min()) < 0 or int(E.max()) >= ne):
        return 2.0
    return 0.0


def check_rows(
    graph: Graph,
    ra: Route,
    rb: Route,
    tt: FloatArray,
    E: IntArray,
    OFF: FloatArray,
    S: FloatArray,
    V: FloatArray,
    A: FloatArray,
    J: FloatArray,
    lims: FloatArray,
    dt: float,
    time_tol: float,
    ends: FloatArray,
    between: FloatArray,
) -> FloatArray:
    """Every row check of the gate at once; returns the numbers of :data:`RES` and fills ``between``.

    The same numbers as :func:`trajopt.verify.kernels.check_rows` (and ``between`` the same): the rows' distance
    and its first minimum, each row's distance from its route position and the first row of the largest, the
    peaks of ``|v|, |a|, |j|`` and their first rows, the time grid, the ends and rest, the bound between rows.

    Parameters
    ----------
    graph, ra, rb : tuple of ndarray
        The graph and the routes of A and B, as :func:`between_rows` takes them.
    tt : ndarray, shape (N,)
        Times (s), N ≥ 1.
    E, OFF : ndarray, shape (N, 2)
        Rows' positions (edge index, offset in m) of A and B.
    S, V, A, J : ndarray, shape (N, 2)
        Route coordinates (m) and their derivatives (m/s, m/s², m/s³).
    lims : ndarray, shape (6,)
        ``vA, vB, aA, aB, jA, jB`` limits.
    dt : float
        Row step (s).
    time_tol : float
        Tolerance of the time grid (s), scaled by ``max(1, N·dt)``.
    ends : ndarray, shape (8,)
        ``(edge, offset)`` of A and B at the start, then at the goal.
    between : ndarray, shape (N−1,)
        Filled with the lower bound of the distance between rows (m), when the input is sound.

    Returns
    -------
    ndarray, shape (len(RES),)
    """
    res = np.zeros(_NRES)
    n, ne = len(tt), len(graph[2])
    res[0] = _bad(tt, E, ne, (OFF, S, V, A, J))
    if res[0] != 0.0:
        return res
    grid_ok = abs(tt[0]) <= time_tol
    gtol = time_tol * max(1.0, n * dt)
    dmin, dk = math.inf, 0
    top = [0.0] * 8  # the largest distance from the route position of A, B; |v|, |a|, |j| of A, B
    top_k = [0] * 8
    with np.errstate(all="ignore"):
        for lo, hi in _blocks(n):
            end = min(hi + 1, n)  # the block's rows and the next one, the far end of the block's last chord
            if bool((np.abs(tt[lo:hi] - dt * np.arange(lo, hi)) > gtol).any()):
                grid_ok = False
            ea, oa, eb, ob, d_route = _route_distances(graph, ra, rb, S[lo:end])
            Eb, Ob = E[lo:hi], OFF[lo:hi]
            dmin, dk = _running_min(dmin, dk, _dists(graph, Eb[:, 0], Ob[:, 0], Eb[:, 1], Ob[:, 1]), lo)
            m = hi - lo
            values = (
                _dists(graph, ea[:m], oa[:m], Eb[:, 0], Ob[:, 0]),
                _dists(graph, eb[:m], ob[:m], Eb[:, 1], Ob[:, 1]),
                *(np.abs(X[lo:hi, r]) for X in (V, A, J) for r in (0, 1)),
            )
            for i, x in enumerate(values):  # the first row counts whatever its value (the kernels' ``k == 0``)
                cur = float(x[0]) if lo == 0 else top[i]
                top[i], top_k[i] = _running_max(cur, top_k[i], x, lo)
            _between(graph, ra, rb, S[lo:end], A[lo:end], d_route, dt, lims[2:4], lims[4:6], between[lo : end - 1])
        # the first row of the least bound, from row 0 (with one row: the rows' minimum, row 0)
        bmin, bk = _running_min(float(between[0]), 0, between, 0) if n > 1 else (dmin, 0)
    res[1] = 1.0 if grid_ok else 0.0
    res[2], res[3], res[4], res[5] = dmin, dk, bmin, bk
    res[6], res[7], res[8], res[9] = top[0], top_k[0], top[1], top_k[1]
    res[10:16], res[16:22] = top[2:], top_k[2:]
    for row, slot in ((0, 26), (n - 1, 27)):
        v0, v1, a0, a1 = (abs(float(x)) for x in (V[row, 0], V[row, 1], A[row, 0], A[row, 1]))
        res[slot] = max(max(v0, v1), max(a0, a1))
    for r in range(2):
        res[22 + r] = _dist(graph, int(E[0, r]), float(OFF[0, r]), int(ends[2 * r]), float(ends[2 * r + 1]))
        goal = int(ends[4 + 2 * r]), float(ends[5 + 2 * r])
        res[24 + r] = _dist(graph, int(E[n - 1, r]), float(OFF[n - 1, r]), *goal)
    return res
