"""The verification gate's pass over the rows, compiled (numba), in one call per grid.

:func:`trajopt.verify.gate.verify_graph_setpoints` checks a few hundred rows per trajectory; written with numpy it
took about 150 array calls, and their fixed cost (not the arithmetic) was most of the gate's time. Here the same
checks run as one loop over the rows: the route positions of the route coordinates, the exact graph distance
(:meth:`mpa.geometry.GraphGeometry.distance`, the same formula and the same order of operations), the rows'
consistency with their routes, the endpoints, the limits, and the exact minimum of the distance along each chord
between consecutive rows, cut where a robot changes edge (:meth:`mpa.geometry.GraphGeometry.segment_min`). The
messages are written by :mod:`trajopt.verify.gate` from the few numbers returned here.

Without numba (:mod:`trajopt._numba`) the same functions run as plain Python: the same results, about a hundred
times slower.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from mpa._arrays import FloatArray, IntArray
from mpa.retraction import lollipop_trace_scalar
from mpa.routes import affine_position
from mpa.skeleton import lollipop_point_index
from trajopt._numba import njit, numpy_twins
from trajopt.verify.results import NRES as _NRES
from trajopt.verify.results import RES

__all__ = [
    "RES",
    "between_rows",
    "check_rows",
    "circle_skeleton_points",
    "dense_polyline",
    "lollipop_skeleton_points",
    "needs_densify",
    "track_positions",
    "word_samples",
]

#: A graph as the kernels take it: ``tails, heads, lengths, dv`` (:class:`mpa.geometry.GraphGeometry`).
Graph = tuple[IntArray, IntArray, FloatArray, FloatArray]
#: A route as the kernels take it: ``breaks, edges, dirs, entry`` (:class:`mpa.geometry.DirectedRoute`).
Route = tuple[FloatArray, IntArray, IntArray, FloatArray]


@njit(cache=True)
def _bisect_right(x: FloatArray, v: float) -> int:
    """``searchsorted(x, v, side="right")``: the number of entries of the sorted ``x`` that are ``<= v``."""
    lo, hi = 0, len(x)
    while lo < hi:
        mid = (lo + hi) // 2
        if v < x[mid]:
            hi = mid
        else:
            lo = mid + 1
    return lo


@njit(cache=True)
def _piece(breaks: FloatArray, r: float) -> int:
    """``clip(searchsorted(breaks, r, "right") − 1, 0, M − 1)`` (:meth:`DirectedRoute.piece_index`)."""
    return min(max(_bisect_right(breaks, r) - 1, 0), len(breaks) - 2)


@njit(cache=True)
def _position(breaks: FloatArray, edges: IntArray, dirs: IntArray, entry: FloatArray, r: float) -> tuple[int, float]:
    """``(edge, offset)`` at route coordinate ``r`` (:meth:`DirectedRoute.positions`: clamped to the route)."""
    r = min(max(r, breaks[0]), breaks[-1])
    i = _piece(breaks, r)
    return edges[i], entry[i] + dirs[i] * (r - breaks[i])


@njit(cache=True)
def _dist(
    tails: IntArray, heads: IntArray, lengths: FloatArray, dv: FloatArray, ea: int, sa: float, eb: int, sb: float
) -> float:
    """:meth:`mpa.geometry.GraphGeometry.distance` of one pair (the same terms in the same order)."""
    ta, ha, la = tails[ea], heads[ea], lengths[ea]
    tb, hb, lb = tails[eb], heads[eb], lengths[eb]
    qa, qb = la - sa, lb - sb
    d = min(min(sa + dv[ta, tb] + sb, sa + dv[ta, hb] + qb), min(qa + dv[ha, tb] + sb, qa + dv[ha, hb] + qb))
    if ea == eb:
        d = min(d, abs(sa - sb))
    return d


@njit(cache=True)
def _cell_min(graph: Graph, ra: Route, rb: Route, p0a: float, p0b: float, p1a: float, p1b: float) -> float:
    """Exact minimum of the distance along a chord ``p0 → p1`` on which each robot stays on one edge.

    On such a chord both offsets are affine, so the distance is the minimum of the cell's affine terms (and
    ``|s − t|`` on one edge): its minimum is at an end, or 0 where the robots meet on one edge
    (:meth:`mpa.geometry.GraphGeometry.segment_min`).
    """
    tails, heads, lengths, dv = graph
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
    return min(_dist(tails, heads, lengths, dv, e, s0, f, t0), _dist(tails, heads, lengths, dv, e, s1, f, t1))


@njit(cache=True)
def _excluded(p0a: float, p0b: float, p1a: float, p1b: float, d0: float, d1: float) -> bool:
    """Whether the robots cannot meet along the chord ``p0 → p1``: ``d0 + d1 > |ΔsA| + |ΔsB|``.

    The distance is 1-Lipschitz in each route coordinate. With a margin of 1e-9 relative and 1e-12 m: robots
    heading straight at each other and meeting have ``d0 + d1`` equal to the span, which rounding can tip
    either way.
    """
    return d0 + d1 > (abs(p1a - p0a) + abs(p1b - p0b)) * (1.0 + 1e-9) + 1e-12


@njit(cache=True)
def _crosses(breaks: FloatArray, a: float, b: float) -> bool:
    """Whether a junction of the route (an interior break) lies strictly between ``a`` and ``b``."""
    low, high = min(a, b), max(a, b)
    for q in range(1, len(breaks) - 1):
        if low < breaks[q] < high:
            return True
    return False


@njit(cache=True)
def _cut_chord_min(
    graph: Graph, ra: Route, rb: Route, a0: float, a1: float, b0: float, b1: float, d0: float, d1: float
) -> float:
    """Exact minimum of the distance along the chord ``(a0, a1) → (b0, b1)`` that a robot's junction cuts.

    The chord is cut at the parameters ``(x − a)/(b − a)`` of the junctions ``x`` strictly inside it; on each
    piece both robots stay on one edge (:func:`_cell_min`). ``d0``, ``d1``: the distance at the chord's ends.
    """
    tails, heads, lengths, dv = graph
    (ba, ea_, da_, na), (bb, eb_, db_, nb) = ra, rb
    cuts = np.empty(len(ba) + len(bb))
    m = 0
    for br, a, b in ((ba, a0, b0), (bb, a1, b1)):
        low, high = min(a, b), max(a, b)
        for q in range(1, len(br) - 1):
            if low < br[q] < high:
                cuts[m] = (br[q] - a) / (b - a)
                m += 1
    cuts = np.sort(cuts[:m])
    da, db = b0 - a0, b1 - a1
    chord = np.inf
    t0, p0a, p0b, dd0 = 0.0, a0, a1, d0
    for q in range(m + 1):
        t1 = cuts[q] if q < m else 1.0
        if t1 == 1.0:  # the piece ends at the chord's end itself
            p1a, p1b, dd1 = b0, b1, d1
        else:
            p1a, p1b = a0 + t1 * da, a1 + t1 * db
            ea, oa = _position(ba, ea_, da_, na, p1a)
            eb, ob = _position(bb, eb_, db_, nb, p1b)
            dd1 = _dist(tails, heads, lengths, dv, ea, oa, eb, ob)
        if t0 == 0.0:  # the piece starts at the chord's start itself
            p0a, p0b, dd0 = a0, a1, d0
        chord = min(chord, dd0, dd1)
        if not _excluded(p0a, p0b, p1a, p1b, dd0, dd1):
            chord = min(chord, _cell_min(graph, ra, rb, p0a, p0b, p1a, p1b))
        t0, p0a, p0b, dd0 = t1, p1a, p1b, dd1
    return chord


@njit(cache=True)
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
    """Lower bound of the distance between consecutive rows into ``out`` (shape (N−1,)).

    The chord between two rows is cut where a robot passes a junction of its route (:func:`_cut_chord_min`);
    on a chord without a cut, the distance at its ends (``d_route``: at the rows' route positions) unless the
    robots could meet on it (:func:`_excluded`), then the cell's exact minimum (:func:`_cell_min`). Minus the
    bound of how far both robots leave the chord: per robot ``a_int·Δt²/8`` with
    ``a_int = min(amax, max(|a_k|, |a_k+1|) + jmax·Δt/2)``. (The rare cases are separate functions: a call
    that passes arrays costs more than the common case's arithmetic.)
    """
    ba, bb = ra[0], rb[0]
    for k in range(len(S) - 1):
        a0, a1, b0, b1 = S[k, 0], S[k, 1], S[k + 1, 0], S[k + 1, 1]
        d0, d1 = d_route[k], d_route[k + 1]
        if _crosses(ba, a0, b0) or _crosses(bb, a1, b1):
            chord = _cut_chord_min(graph, ra, rb, a0, a1, b0, b1, d0, d1)
        else:
            chord = min(d0, d1)
            if not _excluded(a0, a1, b0, b1, d0, d1):
                chord = min(chord, _cell_min(graph, ra, rb, a0, a1, b0, b1))
        dev = 0.0
        for r in range(2):
            dev += min(amax[r], max(abs(A[k, r]), abs(A[k + 1, r])) + jmax[r] * dt / 2)
        out[k] = chord - dev * (dt * dt / 8.0)


@njit(cache=True)
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

    ``ra``, ``rb``: each robot's route as ``(breaks, edges, dirs, entry)`` (:class:`mpa.geometry.DirectedRoute`);
    ``graph``: ``(tails, heads, lengths, dv)`` (:class:`mpa.geometry.GraphGeometry`); ``S``, ``A``
    (shape (N, 2)): route coordinates (m) and accelerations (m/s²) at the rows; ``dt``: row step (s).
    """
    tails, heads, lengths, dv = graph
    (ba, ea_, da_, na), (bb, eb_, db_, nb) = ra, rb
    n = len(S)
    d_route = np.empty(n)
    for k in range(n):
        ea, oa = _position(ba, ea_, da_, na, S[k, 0])
        eb, ob = _position(bb, eb_, db_, nb, S[k, 1])
        d_route[k] = _dist(tails, heads, lengths, dv, ea, oa, eb, ob)
    out = np.empty(max(n - 1, 0))
    _between(graph, ra, rb, S, A, d_route, dt, amax, jmax, out)
    return out


@njit(cache=True)
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
    """Every row check of the gate in one pass; returns the numbers of :data:`RES` and fills ``between``.

    Parameters
    ----------
    tt : shape (N,)
        Times (s).
    E, OFF : shape (N, 2)
        Rows' positions (edge index, offset in m) of A and B.
    S, V, A, J : shape (N, 2)
        Route coordinates (m) and their derivatives.
    lims : shape (6,)
        ``vA, vB, aA, aB, jA, jB`` limits.
    ends : shape (8,)
        ``(edge, offset)`` of A and B at the start, then at the goal.
    between : shape (N−1,)
        Filled with the lower bound of the distance between rows (m), when the input is sound.
    """
    tails, heads, lengths, dv = graph
    (ba, ea_, da_, na), (bb, eb_, db_, nb) = ra, rb
    res = np.zeros(_NRES)
    n, ne = len(tt), len(lengths)
    for k in range(n):
        if not math.isfinite(tt[k]):
            res[0] = 1.0
        for r in range(2):
            if not (
                math.isfinite(OFF[k, r])
                and math.isfinite(S[k, r])
                and math.isfinite(V[k, r])
                and math.isfinite(A[k, r])
                and math.isfinite(J[k, r])
            ):
                res[0] = 1.0
    if res[0] != 0.0:
        return res
    for k in range(n):
        for r in range(2):
            if E[k, r] < 0 or E[k, r] >= ne:
                res[0] = 2.0
                return res
    grid_ok = abs(tt[0]) <= time_tol
    gtol = time_tol * max(1.0, n * dt)
    for k in range(n):
        if abs(tt[k] - dt * k) > gtol:
            grid_ok = False
    res[1] = 1.0 if grid_ok else 0.0
    d_route = np.empty(n)
    dmin, dk = np.inf, 0
    err = np.zeros(2)
    err_k = np.zeros(2)
    peak = np.zeros(6)
    peak_k = np.zeros(6)
    for k in range(n):
        ea, oa = _position(ba, ea_, da_, na, S[k, 0])
        eb, ob = _position(bb, eb_, db_, nb, S[k, 1])
        d = _dist(tails, heads, lengths, dv, E[k, 0], OFF[k, 0], E[k, 1], OFF[k, 1])
        if d < dmin:
            dmin, dk = d, k
        e0 = _dist(tails, heads, lengths, dv, ea, oa, E[k, 0], OFF[k, 0])
        e1 = _dist(tails, heads, lengths, dv, eb, ob, E[k, 1], OFF[k, 1])
        if e0 > err[0] or k == 0:
            err[0], err_k[0] = e0, k
        if e1 > err[1] or k == 0:
            err[1], err_k[1] = e1, k
        d_route[k] = _dist(tails, heads, lengths, dv, ea, oa, eb, ob)
        for r in range(2):
            for q in range(3):
                x = abs(V[k, r]) if q == 0 else (abs(A[k, r]) if q == 1 else abs(J[k, r]))
                if x > peak[2 * q + r] or k == 0:
                    peak[2 * q + r], peak_k[2 * q + r] = x, k
    res[2], res[3] = dmin, dk
    _between(graph, ra, rb, S, A, d_route, dt, lims[2:4], lims[4:6], between)
    bmin, bk = dmin, 0
    for k in range(n - 1):
        if k == 0 or between[k] < bmin:
            bmin, bk = between[k], k
    res[4], res[5] = bmin, bk
    res[6], res[7], res[8], res[9] = err[0], err_k[0], err[1], err_k[1]
    for i in range(6):
        res[10 + i] = peak[i]
        res[16 + i] = peak_k[i]
    for row, slot in ((0, 26), (n - 1, 27)):
        res[slot] = max(max(abs(V[row, 0]), abs(V[row, 1])), max(abs(A[row, 0]), abs(A[row, 1])))
    for r in range(2):
        res[22 + r] = _dist(tails, heads, lengths, dv, E[0, r], OFF[0, r], int(ends[2 * r]), ends[2 * r + 1])
        res[24 + r] = _dist(
            tails, heads, lengths, dv, E[n - 1, r], OFF[n - 1, r], int(ends[4 + 2 * r]), ends[5 + 2 * r]
        )
    return res


# ------------------------------------------------------------------------------------------ skeleton words
#: mpa's scalar twins, compiled here (mpa itself is numpy only): the trace of H on a model lollipop and the
#: skeleton point of a model state.
_trace = njit(cache=True)(lollipop_trace_scalar)
_point_index = njit(cache=True)(lollipop_point_index)


@njit(cache=True)
def lollipop_skeleton_points(
    P: FloatArray, ell: float, c_model: float, kappa: float, degenerate: bool, edge: IntArray, t: FloatArray
) -> None:
    """``H₁`` of each state on a lollipop: skeleton edge index and ``t`` into ``edge``, ``t`` (shape (N,)).

    The same steps as :func:`mpa.homotopy.skeleton_points` (ψ to the model, the trace of
    :func:`mpa.retraction.lollipop_trace_scalar` at ``t = 1``, ψ⁻¹ as :func:`mpa.retraction.retract` returns, ψ
    again, :func:`mpa.skeleton.lollipop_point_index`), one state at a time.

    Parameters
    ----------
    P : shape (N, 2)
        Track coordinates of A and B (collision-free).
    ell, c_model, kappa : float
        The stick, the model's loop and the loop scale ψ (:class:`mpa.skeleton.LollipopSkeleton`).
    degenerate : bool
        ``ℓ = h``: I1 and I2 are single points, taken as the vertices ``S1a(0)`` and ``S3a(0)``.
    """
    h = 0.5 * c_model
    for k in range(len(P)):
        a, b = P[k, 0], P[k, 1]
        ma = a if a <= ell else ell + (a - ell) * kappa
        mb = b if b <= ell else ell + (b - ell) * kappa
        da, db = _trace(ell, c_model, ma, mb)
        na, nb = ma + 1.0 * da, mb + 1.0 * db
        if ma > ell:
            na = ell + (na - ell) % c_model
        if mb > ell:
            nb = ell + (nb - ell) % c_model
        ra = na if na <= ell else ell + (na - ell) / kappa  # retract returns track coordinates ...
        rb = nb if nb <= ell else ell + (nb - ell) / kappa
        ra = ra if ra <= ell else ell + (ra - ell) * kappa  # ... which skeleton_points takes to the model
        rb = rb if rb <= ell else ell + (rb - ell) * kappa
        e, tk = _point_index(h, ell, ra, rb)
        if degenerate and (e == 0 or e == 7):
            e, tk = (1 if e == 0 else 5), 0.0
        edge[k], t[k] = e, tk


@njit(cache=True)
def circle_skeleton_points(P: FloatArray, c: float, edge: IntArray, t: FloatArray) -> None:
    """``H₁`` of each state on a circle into ``edge`` (0 = Aa, 1 = Ab), ``t`` (shape (N,)).

    A moves until antipodal and B waits (:func:`mpa.retraction.circle_trace`), so the skeleton point is B's
    position φ (:meth:`mpa.skeleton.CircleSkeleton.points_of_states`).
    """
    h = 0.5 * c
    for k in range(len(P)):
        phi = (P[k, 1] + 1.0 * 0.0) % c % c  # as retract (B's displacement 0, mod c), then points_of_states
        if phi >= h:
            edge[k], t[k] = 1, phi - h
        else:
            edge[k], t[k] = 0, phi


@njit(cache=True)
def word_samples(edge: IntArray, adjacent: NDArray[np.bool_]) -> tuple[IntArray, bool]:
    """The samples that matter for the word (the first, the last, and both sides of every edge change;
    :func:`mpa.homotopy.word_from_points`), and whether two consecutive samples lie on skeleton edges without a
    common vertex (``adjacent[e, f]`` False: the sampling is too coarse there)."""
    n = len(edge)
    keep = np.empty(n, dtype=np.int64)
    m = 0
    jump = False
    for k in range(n):
        change_next = k + 1 < n and edge[k + 1] != edge[k]
        if k == 0 or k == n - 1 or change_next or edge[k] != edge[k - 1]:
            keep[m] = k
            m += 1
        if change_next and not adjacent[edge[k], edge[k + 1]]:
            jump = True
    return keep[:m], jump


@njit(cache=True)
def needs_densify(S: FloatArray, step: float) -> bool:
    """Whether some leg of the polyline ``S`` (shape (N, 2)) is longer than ``step`` in the max-norm
    (:func:`mpa.geometry.densify_polyline` would cut it)."""
    for k in range(len(S) - 1):
        size = max(abs(S[k + 1, 0] - S[k, 0]), abs(S[k + 1, 1] - S[k, 1]))
        if math.ceil(size / step) > 1:
            return True
    return False


_route_position = njit(cache=True)(affine_position)


@njit(cache=True)
def dense_polyline(S: FloatArray, step: float) -> FloatArray:
    """The polyline of route coordinates ``S`` (shape (N, 2)) refined to ``step`` (m): the points of
    :func:`mpa.geometry.densify_polyline` (every leg cut into ``max(1, ⌈|leg|_∞ / step⌉)`` equal parts).
    Shape (M, 2)."""
    n = len(S)
    counts = np.ones(max(n - 1, 0), dtype=np.int64)
    total = 1
    for k in range(n - 1):
        size = max(abs(S[k + 1, 0] - S[k, 0]), abs(S[k + 1, 1] - S[k, 1]))
        counts[k] = max(1, math.ceil(size / step))
        total += counts[k]
    out = np.empty((total, 2))
    m = 0
    for k in range(n - 1):
        nk = counts[k]
        la, lb = S[k + 1, 0] - S[k, 0], S[k + 1, 1] - S[k, 1]
        for q in range(nk):
            frac = q / nk
            out[m, 0] = S[k, 0] + frac * la
            out[m, 1] = S[k, 1] + frac * lb
            m += 1
    out[m, 0] = S[n - 1, 0]
    out[m, 1] = S[n - 1, 1]
    return out


@njit(cache=True)
def track_positions(
    S: FloatArray,
    breaks_a: FloatArray,
    A_a: FloatArray,
    B_a: FloatArray,
    line_a: NDArray[np.bool_],
    breaks_b: FloatArray,
    A_b: FloatArray,
    B_b: FloatArray,
    line_b: NDArray[np.bool_],
    interval: bool,
    stick: float,
    loop: float,
    out: FloatArray,
) -> None:
    """Track coordinates of route coordinates ``S`` (shape (N, 2)) into ``out`` (shape (N, 2)):
    :meth:`mpa.routes.Route.position` of each robot's route, given as :meth:`mpa.routes.Route.affine_form`
    (:func:`mpa.routes.affine_position`, compiled). The gate's word check and the pipeline's rows
    (:meth:`trajopt.path.planview.PlanView.track_coordinates`) both read positions through it."""
    for r in range(len(S)):
        out[r, 0] = _route_position(breaks_a, A_a, B_a, line_a, interval, stick, loop, S[r, 0])
        out[r, 1] = _route_position(breaks_b, A_b, B_b, line_b, interval, stick, loop, S[r, 1])


if numpy_twins():  # a process that runs without numba (trajopt._numba): the kernels' numpy twins
    import trajopt.verify.kernels_numpy as kernels_numpy
    import trajopt.verify.paper_numpy as paper_numpy

    between_rows = kernels_numpy.between_rows
    check_rows = kernels_numpy.check_rows
    circle_skeleton_points = paper_numpy.circle_skeleton_points
    dense_polyline = paper_numpy.dense_polyline
    lollipop_skeleton_points = paper_numpy.lollipop_skeleton_points
    needs_densify = paper_numpy.needs_densify
    track_positions = paper_numpy.track_positions
    word_samples = paper_numpy.word_samples
