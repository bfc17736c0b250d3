"""A lower bound on the time to the goal that knows the robots must pass each other (the "fastest" objective).

The search's own bound at a configuration ``(a, b)`` is each robot's exact distance to its goal alone, combined by
the objective's cost (``max(dA/vA, dB/vB)`` plus the tie-break terms). It ignores the other robot, so on a swap or a
crossing (one robot must step aside at a branch while the other passes) every configuration whose two distances are
small enough looks promising, and the search expands all of them before it reaches the goal.

**The passing lemma.** Let ``φ = d(x, ·)`` be the graph distance from a vertex ``x``. Along any motion from
``(a, b)`` to the goal ``(a1, b1)`` the difference ``φ(A) - φ(B)`` is continuous; when it has one sign at the start
(or is 0) and the other, strictly, at the goal, it is 0 at some moment: the robots are then at a *passing
configuration* ``m = (p, q)``, at equal distance from ``x`` and at least the clearance apart (on a corridor two such
points exist only where it branches: one robot has stepped aside into a branch or a loop the other passes). The
motion's cost is at least ``c(a, b → p, q) + c(p, q → a1, b1)``, and each part at least the objective's cost of the
robots' graph distances. So

    h(a, b) = min over passing configurations m of  comb(d(a, p), d(b, q)) + W(m),   W(m) = comb(d(p, a1), d(q, b1))

is a lower bound on the cost to the goal, for every configuration on the start's side of ``φ(A) = φ(B)``.

**Computed exactly per cell, relaxed per node.** In a cell ``e × f`` (A on edge e at offset u, B on f at v) the
distance ``φ`` is a tent on each edge, so ``φ(p) = φ(q)`` is at most four straight pieces ``v = ±u + β``, and the
clearance keeps an interval of each (the cell's four distance terms and, on one edge, ``|u - v|``, are affine in u
along the piece). These *passing segments* ``k`` are built once per query (numpy over all cells); ``W_k``, the least
``W`` along segment ``k``, is exact: along a segment every distance is a minimum of affine functions of u and the cost
is a maximum of two of them plus a linear term, so its least value is at one of the finitely many points where two of
these affine functions cross, or at an end. At a search node the bound is
``min_k comb(d(a, P_k), d(b, Q_k)) + W_k`` (``P_k``, ``Q_k``: the segment's stretches of e and f), which relaxes the
coupling of p and q along the segment and is therefore still a lower bound. The tie-break term in ``hypot`` is left
out (it is >= 0), so the bound never exceeds the search's cost of a motion. Of the vertices at the ends of the
start's and the goal's edges that separate them, the two clearest are tried and the one whose bound at the start is
largest is used.

**Pieces, relaxed goal costs, limits.** The segments are cut in pieces of at most ``PIECE_LENGTH`` times the longest
edge (:mod:`mpa.planners.graph.passing`, which builds them and keeps them per vertex with the free space), which bounds
what the relaxation loses at a node; ``W_k`` is by default relaxed the same way (each robot from the nearest point of
its stretch, ``W_EXACT``). :meth:`PassingBound.restrict` keeps only the segments through which a motion from the
start can cost at most a limit; exact for a search stopped at that limit (the method's docstring).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from mpa._arrays import FloatArray
from mpa.graph_track import Position
from mpa.planners.graph.base import TIE_BREAK, TIE_BREAK_2, FaceKey, Key
from mpa.planners.graph.mesh import _Mesh
from mpa.planners.graph.passing import _build_passing_geometry, passing_geometry

__all__ = ["BOUND_SAFETY", "PassingBound", "fastest_cost", "passing_bound", "separating_vertices"]

#: The bound is scaled by ``1 - BOUND_SAFETY`` so that rounding never lifts it above a motion's cost (the search's
#: order is on a grid of ``F_GRID = 1e-12`` of the start's bound).
BOUND_SAFETY = 1e-13

#: Separating vertices tried per query (the clearest first); the bound of the one largest at the start is kept.
VERTICES_TRIED = 2

#: Above this many edges the passing segments are built for each query, and only in the cells ``e × f`` through
#: which a motion from the start to the goal can cost at most the bound's *reach* (each robot from its start to the
#: nearest point of its edge and from there to its goal, combined by the cost; :meth:`PassingBound._segments`):
#: 0.2-10 % of a 1 000-edge layout's cells. At and below it every segment of ``d(x, ·)`` is built once and kept
#: with the free space (:func:`mpa.planners.graph.passing.passing_geometry`).
REACH_EDGES = 300

#: The first reach: ``(1 + FIRST_REACH)`` times the robots' own bound; :meth:`PassingBound.restrict` extends it
#: when a search needs segments beyond it.
FIRST_REACH = 0.5

#: Segments whose exact least cost is computed at once (module docstring).
EXACT_CHUNK = 32

#: A face end's or a corner's bound from the fronts of hinges of a face through it (:meth:`PassingBound.point`);
#: False: from every segment (:meth:`PassingBound.at`), the earlier way (the benchmark's comparison).
POINTS_FROM_FRONTS = True

#: Segments on a face's own edge evaluated in a Python loop up to this many, in one numpy pass above.
ON_EDGE_LOOP = 16

#: ``W_k``, the least cost from segment k to the goal: exact along the segment (True), or relaxed like the bound at a
#: node (False: each robot from the nearest point of its stretch; a lower bound, within a piece of the exact value).
W_EXACT = False


def _vertex_dist(mesh: _Mesh, pos: Position) -> FloatArray:
    """Graph distance from a position to every vertex (metres), shape (V,)."""
    g = mesh.g
    e, s = pos
    return np.minimum(s + g.dv[g._t[e]], g._L[e] - s + g.dv[g._h[e]])


def _pieces(
    e: np.ndarray, vd: FloatArray, pos: Position, lengths: FloatArray, tails: np.ndarray, heads: np.ndarray
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """``u -> d((e, u), pos)`` per row: ``min(u + c_t, -u + c_h)``, and on the position's own edge also
    ``|sigma u + kappa|`` (``sigma = 1, kappa = -offset``). Returns ``sl, cs`` of shape (N, 4) (the affine pieces; the
    last two, ``±(u - offset)``, copies of the first off the position's edge) and ``sigma, kappa`` of shape (N,)
    (``kappa`` NaN off the position's edge)."""
    le = lengths[e]
    c_t = vd[tails[e]]
    c_h = le + vd[heads[e]]
    same = e == pos[0]
    one = np.ones(len(e))
    sl = np.stack([one, -one, one, np.where(same, -1.0, 1.0)], axis=1)
    cs = np.stack([c_t, c_h, np.where(same, -pos[1], c_t), np.where(same, pos[1], c_t)], axis=1)
    return sl, cs, one, np.where(same, -pos[1], np.nan)


def _eval(sl: FloatArray, cs: FloatArray, sigma: FloatArray, kappa: FloatArray, u: FloatArray) -> FloatArray:
    """The distance at candidate points ``u`` of shape (N, C): ``min(sl0 u + cs0, sl1 u + cs1, |sigma u + kappa|)``
    (the last only where ``kappa`` is a number). Shape (N, C)."""
    d = np.minimum(sl[:, 0:1] * u + cs[:, 0:1], sl[:, 1:2] * u + cs[:, 1:2])
    on = ~np.isnan(kappa)
    if on.any():
        d[on] = np.minimum(d[on], np.abs(sigma[on, None] * u[on] + kappa[on, None]))
    return d


def _crossings(s1: FloatArray, c1: FloatArray, s2: FloatArray, c2: FloatArray) -> FloatArray:
    """Where ``s1[:, i] u + c1[:, i] = s2[:, j] u + c2[:, j]`` for all pairs ``i, j``; NaN where parallel. (N, I*J)."""
    ds = s1[:, :, None] - s2[:, None, :]
    dc = c2[:, None, :] - c1[:, :, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        u = np.where(ds != 0.0, dc / np.where(ds != 0.0, ds, 1.0), np.nan)
    return u.reshape(len(s1), -1)


def _hinges(a: FloatArray, d: FloatArray, w: FloatArray, s1: float, s2: float) -> list[tuple[float, float]]:
    """The lower envelope of the segments' costs through one end of a face's edge, as a front of hinges.

    Segment k costs ``max(a_k, x) + TIE_BREAK (a_k + x) + w_k`` when the edge's robot needs ``x = (y + d_k) / v``
    seconds to it (``y``: its travel to the edge's end, ``d_k``: from there to the segment, m; ``a_k``: the vertex
    robot's time, s): ``max(c1_k + s1 y, c2_k + s2 y)`` with ``c1_k = (1 + TIE_BREAK) a_k + w_k + s1 d_k``, ``c2_k =
    TIE_BREAK a_k + w_k + s2 d_k`` and the slopes ``s1 = TIE_BREAK / v``, ``s2 = (1 + TIE_BREAK) / v`` common to
    all. A hinge no lower in both ``c1`` and ``c2`` than another is never the least, so only the front is kept
    (sorted by ``c1``, ``c2`` falling): the least over it equals the least over all segments.

    Returns
    -------
    list of (float, float)
        The front's ``(c1, c2)`` (s), by ``c1`` rising; not empty when ``a`` is not (a few: at most 7 on the
        airport map's 2 352 segments).
    """
    c1 = (1.0 + TIE_BREAK) * a + w + s1 * d
    c2 = TIE_BREAK * a + w + s2 * d
    # a hinge whose c2 exceeds the least value at y = 0, max(c1_j, c2_j), lies above hinge j for every y >= 0
    near = c2 <= np.min(np.maximum(c1, c2))
    c1, c2 = c1[near], c2[near]
    order = np.argsort(c1)
    c1, c2 = c1[order], c2[order]
    keep = np.ones(len(c1), dtype=bool)
    if len(c1) > 1:
        keep[1:] = c2[1:] < np.minimum.accumulate(c2)[:-1]
    return list(zip(c1[keep].tolist(), c2[keep].tolist()))


def fastest_cost(segs: list[list[Any]], va: float, vb: float) -> float:
    """The search's "fastest" cost of a motion's segments ``[polygon, (s, t) from, (s, t) to]`` (offsets in metres;
    seconds): ``max(tA, tB)`` plus the tie-break terms, summed."""
    total = 0.0
    for _, p, q in segs:
        ta, tb = abs(q[0] - p[0]) / va, abs(q[1] - p[1]) / vb
        total += max(ta, tb) + TIE_BREAK * (ta + tb) + TIE_BREAK_2 * math.hypot(ta, tb)
    return total


Pieces = tuple[FloatArray, FloatArray, FloatArray, FloatArray]


def _in_u(p: Pieces, al: FloatArray, be: FloatArray) -> Pieces:
    """Robot B's distance pieces in v turned into pieces in u along ``v = al u + be``."""
    sl, cs, sigma, kappa = p
    return sl * al[:, None], sl * be[:, None] + cs, sigma * al, sigma * be + kappa


def _least(u0: FloatArray, u1: FloatArray, terms: list[tuple[Pieces, Pieces]], va: float, vb: float) -> FloatArray:
    """The least over ``u in [u0, u1]`` of ``sum over terms of max(tA, tB) + TIE_BREAK (tA + tB)`` per row (s),
    ``tA = dA(u) / va``, ``tB = dB(u) / vb``: exact, every distance being a minimum of affine pieces (or an absolute
    value), so the sum is affine between the points where two pieces of one distance, or ``tA`` and ``tB``, cross."""
    cand = [u0[:, None], u1[:, None]]
    for pa, pb in terms:
        for sl, cs, _, _ in (pa, pb):
            cand.append(_crossings(sl, cs, sl, cs))
        cand.append(_crossings(pa[0] / va, pa[1] / va, pb[0] / vb, pb[1] / vb))
    u = np.concatenate(cand, axis=1)
    u = np.clip(np.where(np.isnan(u), u0[:, None], u), u0[:, None], u1[:, None])
    total = np.zeros(u.shape)
    for pa, pb in terms:
        ta = _eval(*pa, u) / va
        tb = _eval(*pb, u) / vb
        total += np.maximum(ta, tb) + TIE_BREAK * (ta + tb)
    return np.min(total, axis=1)


def _relaxed(
    g: Any,
    e: np.ndarray,
    u0: FloatArray,
    u1: FloatArray,
    f: np.ndarray,
    v0: FloatArray,
    v1: FloatArray,
    pa: Position,
    pb: Position,
    vda: FloatArray,
    vdb: FloatArray,
    va: float,
    vb: float,
) -> FloatArray:
    """``comb(d(a, P_k), d(b, Q_k))`` per segment (s): robot A at ``pa`` to the nearest point of its stretch ``P_k =
    [u0, u1]`` of edge ``e``, robot B at ``pb`` to ``Q_k = [v0, v1]`` of ``f`` (``vda``, ``vdb``: their vertex
    distances), each alone: a lower bound of the cost of reaching the segment together. Shape (K,)."""
    lengths, tails, heads = g.lengths, g.tails, g.heads
    da = np.minimum(vda[tails[e]] + u0, vda[heads[e]] + lengths[e] - u1)
    on = e == pa[0]
    if on.any():
        da[on] = np.minimum(da[on], np.maximum(0.0, np.maximum(u0[on] - pa[1], pa[1] - u1[on])))
    db = np.minimum(vdb[tails[f]] + v0, vdb[heads[f]] + lengths[f] - v1)
    on = f == pb[0]
    if on.any():
        db[on] = np.minimum(db[on], np.maximum(0.0, np.maximum(v0[on] - pb[1], pb[1] - v1[on])))
    ta, tb = da / va, db / vb
    return np.maximum(ta, tb) + TIE_BREAK * (ta + tb)


def separating_vertices(
    mesh: _Mesh,
    start: tuple[Position, Position],
    goal: tuple[Position, Position],
    vd: list[FloatArray] | None = None,
) -> list[int]:
    """The vertices ``x`` at the ends of the query's four edges for which ``φ(A) - φ(B)``, ``φ = d(x, ·)``, changes
    sign strictly between start and goal (the passing lemma applies), the clearest first (the larger of the two
    differences' smaller size); ``vd``: the four positions' vertex distances, when already at hand."""
    g = mesh.g
    if vd is None:
        vd = [_vertex_dist(mesh, p) for p in (*start, *goal)]
    ends = {int(g._t[p[0]]) for p in (*start, *goal)} | {int(g._h[p[0]]) for p in (*start, *goal)}
    out = []
    for x in sorted(ends):
        s0, s1 = float(vd[0][x] - vd[1][x]), float(vd[2][x] - vd[3][x])
        if s0 * s1 < 0.0:
            out.append((-min(abs(s0), abs(s1)), x))
    return [x for _, x in sorted(out)]


class PassingBound:
    """The passing lemma's lower bound for one query (module docstring), built from its free space.

    Parameters
    ----------
    mesh : _Mesh
        The free space as the search sees it.
    start, goal : (Position, Position)
        The query ``(robot A, robot B)``.
    va, vb : float
        The speed limits (m/s); the bound is in seconds, the search's "fastest" cost.
    floor : float, optional
        A value (s) at or below which the bound is of no use to the caller (the robots' own bound): the least at the
        start stops as soon as it is known not to exceed it (default: never).

    Attributes
    ----------
    vertex : int or None
        The vertex ``x`` of ``φ = d(x, ·)``; None when no vertex at the ends of the query's edges separates the start
        from the goal (the bound is then 0).
    n_segments : int
        Passing segments kept.
    at_start : float
        The bound at the start (s); when it does not exceed ``floor``, some value between it and ``floor``.
    """

    #: Whether the bound at a search node is the exact least cost through the segments (True) or the relaxed one.
    exact_points = False

    def __init__(
        self,
        mesh: _Mesh,
        start: tuple[Position, Position],
        goal: tuple[Position, Position],
        va: float,
        vb: float,
        floor: float = -math.inf,
    ) -> None:
        self.mesh = mesh
        self.start = start
        self.va, self.vb = va, vb
        g = mesh.g
        self._dv = g.dv
        self.vertex: int | None = None
        self.at_start = 0.0
        self.n_segments = 0
        self._cache: dict[Key, float] = {}
        self._face_parts: dict[FaceKey, tuple[Any, ...]] = {}
        self._entries: dict[tuple[FaceKey, float, float], float] = {}
        self._times: dict[tuple[int, int], FloatArray] = {}
        self._fronts: dict[tuple[int, int, int], list[tuple[float, float]]] = {}
        vd = [_vertex_dist(mesh, p) for p in (*start, *goal)]
        self._vd = vd
        self._goal_vd = vd[2:]
        self._goal = goal
        self._reach = math.inf
        first = math.inf
        if g.n_edges > REACH_EDGES:
            ta = g.distance_scalar(*start[0], *goal[0]) / va
            tb = g.distance_scalar(*start[1], *goal[1]) / vb
            first = (max(ta, tb) + TIE_BREAK * (ta + tb)) * (1.0 + FIRST_REACH)
        best: tuple[float, int, tuple[Any, ...], FloatArray, float] | None = None
        for x in separating_vertices(mesh, start, goal, vd)[:VERTICES_TRIED]:
            for reach in (first, math.inf) if math.isfinite(first) else (math.inf,):
                segs = self._segments(x, goal, reach)
                if segs is None:
                    continue
                from_start = self._relaxed_from_start(segs)
                h0 = self._value(segs, start[0], start[1], vd[0], vd[1], True, from_start, floor)
                if h0 <= reach:  # exact: a segment of the cells beyond the reach costs more than the reach
                    break
            else:
                continue
            if best is None or h0 > best[0]:
                best = (h0, x, segs, from_start, reach)
        if best is not None:
            self.at_start, self.vertex, self._segs, self._from_start, self._reach = best
            self._all_segs = self._segs
            self._sign = 1.0 if float(vd[2][best[1]] - vd[3][best[1]]) > 0.0 else -1.0
            self.n_segments = len(self._segs[0])

    def restrict(self, limit: float) -> None:
        """Keep only the segments through which a motion from the start can cost at most ``limit`` (s): those whose
        relaxed cost from the start ``comb(d(a0, P_k), d(b0, Q_k)) + W_k`` is at most ``limit``.

        Exact for every search node whose bound is at most ``limit`` minus its cost from the start: the search's cost
        obeys the triangle inequality, so ``g(n) + b_k(n) >= b_k(start)`` for every node ``n`` and segment ``k``, and a
        segment dropped here is never the least at such a node. A search with a limit at least the optimum
        therefore finds the optimum; one whose motion costs more than ``limit`` proves nothing, and the caller
        searches again with a limit no smaller than that motion's cost (:func:`mpa.planners.graph.query.plan_graph`).
        """
        if self.vertex is None:
            return
        if limit * (1.0 + 1e-9) > self._reach:  # beyond the cells built: build those up to the new limit
            reach = limit * (1.0 + 1e-6) if math.isfinite(limit) else math.inf
            segs = self._segments(self.vertex, self._goal, reach)
            assert segs is not None  # the cells within the former reach are among them
            self._from_start = self._relaxed_from_start(segs)
            self._all_segs, self._reach = segs, reach
        keep = self._from_start <= limit * (1.0 + 1e-9)
        self._segs = tuple(a[keep] for a in self._all_segs)
        self.n_segments = int(keep.sum())
        self._cache = {("S",): self._cache[("S",)]} if ("S",) in self._cache else {}
        self._face_parts.clear()
        self._entries.clear()
        self._times.clear()
        self._fronts.clear()

    # ------------------------------------------------------------------------------------------ segments
    def _segments(self, x: int, goal: tuple[Position, Position], reach: float = math.inf) -> tuple[Any, ...] | None:
        """The passing segments of ``φ = d(x, ·)`` and their least goal cost ``W_k``: arrays ``(e, u0, u1, f, v0,
        v1, W, alpha, beta)`` over the segments, None when there are none.

        ``reach`` (s): only the segments of the cells ``e × f`` whose least cost of a motion from the start through
        them to the goal, each robot to the nearest point of its edge (``comb(d(a0, e), d(b0, f)) + comb(d(e, a1),
        d(f, b1))``, a lower bound of the relaxed cost of each of their segments) is at most ``reach``; every
        segment (kept with the free space) when infinite."""
        if math.isfinite(reach):
            geom = self._geometry_within(x, reach)
        else:
            geom = passing_geometry(self.mesh, x)
        if geom is None:
            return None
        e, u0, u1, f, al, be = geom
        g = self.mesh.g
        v_a, v_b = al * u0 + be, al * u1 + be
        v0, v1 = np.minimum(v_a, v_b), np.maximum(v_a, v_b)
        if W_EXACT:
            w = _least(u0, u1, [self._goal_pieces(e, f, al, be)], self.va, self.vb)
        else:  # each robot to the nearest point of its stretch: a lower bound of the least along the segment
            gva, gvb = self._goal_vd
            w = _relaxed(g, e, u0, u1, f, v0, v1, goal[0], goal[1], gva, gvb, self.va, self.vb)
        return e, u0, u1, f, v0, v1, w, al, be

    def _relaxed_from_start(self, segs: tuple[Any, ...]) -> FloatArray:
        """Each segment's relaxed least cost of a motion from the start through it to the goal (s), shape (K,):
        ``comb(d(a0, P_k), d(b0, Q_k)) + W_k``."""
        e, u0, u1, f, v0, v1, w = segs[:7]
        (pa, pb), vd = self.start, self._vd
        return _relaxed(self.mesh.g, e, u0, u1, f, v0, v1, pa, pb, vd[0], vd[1], self.va, self.vb) + w

    def _geometry_within(self, x: int, reach: float) -> tuple[Any, ...] | None:
        """The passing geometry of ``d(x, ·)`` in the cells within ``reach`` of the query (:meth:`_segments`), built
        for it (not kept)."""
        g = self.mesh.g
        start, goal, vd = self.start, self._goal, self._vd
        tails, heads = g.tails, g.heads

        def edge_time(vdx: FloatArray, pos: Position, v: float) -> FloatArray:
            d = np.minimum(vdx[tails], vdx[heads])
            d[pos[0]] = 0.0  # the position is on its own edge
            return d / v

        ta0, ta1 = edge_time(vd[0], start[0], self.va), edge_time(vd[2], goal[0], self.va)
        tb0, tb1 = edge_time(vd[1], start[1], self.vb), edge_time(vd[3], goal[1], self.vb)
        top = reach * (1.0 + 1e-9)
        rows = np.nonzero(ta0 + ta1 <= top)[0]  # the cost is at least each robot's own time through its edge
        cols = np.nonzero(tb0 + tb1 <= top)[0]
        if not len(rows) or not len(cols):
            return None

        def within(ee: np.ndarray, ff: np.ndarray) -> np.ndarray:
            a0, b0, a1, b1 = ta0[ee], tb0[ff], ta1[ee], tb1[ff]
            lb = np.maximum(a0, b0) + TIE_BREAK * (a0 + b0) + np.maximum(a1, b1) + TIE_BREAK * (a1 + b1)
            return lb <= top

        return _build_passing_geometry(self.mesh, x, rows=rows, cols=cols, cell_ok=within)

    def _goal_pieces(self, e: np.ndarray, f: np.ndarray, al: FloatArray, be: FloatArray) -> tuple[Pieces, Pieces]:
        """The robots' distances to their goals as affine pieces in ``u`` along segments ``(e, f, alpha, beta)``."""
        g = self.mesh.g
        goal = self._goal
        goal_a = _pieces(e, self._goal_vd[0], goal[0], g.lengths, g.tails, g.heads)
        goal_b = _in_u(_pieces(f, self._goal_vd[1], goal[1], g.lengths, g.tails, g.heads), al, be)
        return goal_a, goal_b

    # ------------------------------------------------------------------------------------------ the bound
    def _value(
        self,
        segs: tuple[Any, ...],
        pa: Position,
        pb: Position,
        vda: FloatArray,
        vdb: FloatArray,
        exact: bool,
        relaxed: FloatArray | None = None,
        floor: float = -math.inf,
    ) -> float:
        """``min_k`` over the segments of the least cost through segment k (s): first the relaxed value of each
        (``comb(d(a, P_k), d(b, Q_k)) + W_k``, a lower bound of the exact one), then the exact least of
        ``comb(d(a, p), d(b, q)) + comb(d(p, a1), d(q, b1))`` along the segments in the order of their relaxed
        values, until the next relaxed value is no smaller than the best exact one (``relaxed``: those values, when at
        hand), or until the best exact one is at most ``floor`` (then a value between the least and ``floor``)."""
        e, u0, u1, f, v0, v1, w, al, be = segs
        g = self.mesh.g
        lengths, tails, heads = g.lengths, g.tails, g.heads
        if relaxed is None:
            relaxed = _relaxed(g, e, u0, u1, f, v0, v1, pa, pb, vda, vdb, self.va, self.vb) + w
        if not exact:
            return float(relaxed.min()) * (1.0 - BOUND_SAFETY)
        best = math.inf
        # the few smallest relaxed values first (a partition, not a sort of every segment), then every segment whose
        # relaxed value is still below the best exact one, in rising order, until the next is no smaller
        first = np.argpartition(relaxed, EXACT_CHUNK)[:EXACT_CHUNK] if len(relaxed) > EXACT_CHUNK else None
        for pass_ in (0, 1):
            if pass_ == 0:
                if first is None:
                    continue
                cand = first
            else:
                cand = np.nonzero(relaxed < best)[0] if math.isfinite(best) else np.arange(len(relaxed))
            cand = cand[np.argsort(relaxed[cand], kind="stable")]
            for i in range(0, len(cand), EXACT_CHUNK):
                idx = cand[i : i + EXACT_CHUNK]
                if relaxed[idx[0]] >= best:
                    break
                here_a = _pieces(e[idx], vda, pa, lengths, tails, heads)
                here_b = _in_u(_pieces(f[idx], vdb, pb, lengths, tails, heads), al[idx], be[idx])
                least = _least(
                    u0[idx],
                    u1[idx],
                    [(here_a, here_b), self._goal_pieces(e[idx], f[idx], al[idx], be[idx])],
                    self.va,
                    self.vb,
                )
                best = min(best, float(least.min()))
                if best * (1.0 - BOUND_SAFETY) <= floor:  # the least is no larger: no use to the caller
                    return best * (1.0 - BOUND_SAFETY)
        return best * (1.0 - BOUND_SAFETY)

    def at(self, pa: Position, pb: Position) -> float:
        """The bound at the configuration ``(pa, pb)`` (s); 0 on the goal's side of ``φ(A) = φ(B)``."""
        if self.vertex is None:
            return 0.0
        x = self.vertex
        vda, vdb = _vertex_dist(self.mesh, pa), _vertex_dist(self.mesh, pb)
        if (vda[x] - vdb[x]) * self._sign > 0.0:
            return 0.0
        return self._value(self._segs, pa, pb, vda, vdb, self.exact_points)

    def point(self, key: Key) -> float:
        """The bound at the search's point named ``key`` (the start ``("S",)``, a face end or a corner), cached.

        A face end or a corner has one robot on a vertex, so its relaxed bound is :meth:`entry` of the face through
        it over the one point ``y`` (the same value as :meth:`at`, from the face's fronts of hinges in a few scalar
        steps instead of a pass over every segment)."""
        out = self._cache.get(key)
        if out is None:
            if key == ("S",) or not POINTS_FROM_FRONTS:
                if key == ("S",):  # the exact least through the segments, found when the bound was built
                    out = self.at_start
                else:
                    (e, f, _), (s, t) = self.mesh.members(key)[0]
                    out = self.at((e, s), (f, t))
            elif key[0] == "F":  # a face end: one robot on the face's vertex, the other at y on its edge
                _, ax, w, other, y = key
                out = self.entry((ax, w, other), y, y)
            else:  # a corner ("C", A's vertex, B's vertex): B at an end of one of its edges
                _, w, w2 = key
                e2, y = self.mesh.inc[w2][0]
                out = self.entry((0, w, e2), y, y)
            self._cache[key] = out
        return out

    def entry(self, face: FaceKey, y0: float, y1: float) -> float:
        """A lower bound on the cost to the goal from any configuration of the part ``[y0, y1]`` of ``face`` (one
        robot on the face's vertex, the other on its edge), relaxed per segment: ``min_k comb(d(w, P_k), d(I, Q_k))
        + W_k`` with robots exchanged as the face says; 0 when part of the face lies on the goal's side."""
        if self.vertex is None:
            return 0.0
        key = (face, y0, y1)
        out = self._entries.get(key)
        if out is None:
            out = self._entries[key] = self._entry(face, y0, y1)
        return out

    def _entry(self, face: FaceKey, y0: float, y1: float) -> float:
        ax, w, other = face
        g = self.mesh.g
        x = self.vertex
        dvx = self._dv[x]
        # φ along the edge is a tent: least at an end, largest at its peak when inside
        lo_e = float(dvx[g._t[other]])
        hi_e = float(dvx[g._h[other]])
        le = g._L[other]
        ph0 = min(y0 + lo_e, le - y0 + hi_e)
        ph1 = min(y1 + lo_e, le - y1 + hi_e)
        peak = 0.5 * (le + hi_e - lo_e)
        top = max(ph0, ph1, min(peak + lo_e, le - peak + hi_e) if y0 < peak < y1 else -math.inf)
        # configurations (robot on the vertex, robot on the edge): start side when sign * (φ(A) - φ(B)) <= 0
        if ax == 0:  # A on w: sign (φ(w) - φ(y)) <= 0 for every y
            ok = self._sign * float(dvx[w]) <= (self._sign * min(ph0, ph1) if self._sign > 0 else -top)
        else:  # B on w: sign (φ(y) - φ(w)) <= 0 for every y
            ok = (self._sign * top if self._sign > 0 else -min(ph0, ph1)) <= self._sign * float(dvx[w])
        if not ok:
            return 0.0
        return self.least_through(face, y0, y1) * (1.0 - BOUND_SAFETY)

    def least_through(self, face: FaceKey, y0: float, y1: float) -> float:
        """``min_k comb(d(w, P_k), d(I, Q_k)) + W_k`` over the passing segments k (s), ``I = [y0, y1]`` on the face's
        edge, from the fronts of hinges through the edge's two ends (:func:`_hinges`) and the segments on the edge
        itself; equal to :meth:`least_through_all` (up to rounding), in a few scalar steps."""
        parts = self._face_parts.get(face)
        if parts is None:
            parts = self._face_parts[face] = self._parts(face)
        front_t, front_h, on = parts
        s1, s2 = self._slopes(face[0])
        # the edge's robot travels y0 to the edge's tail, le - y1 to its head
        yh = self.mesh.g._L[face[2]] - y1
        best = min(
            min(max(c1 + s1 * y0, c2 + s2 * y0) for c1, c2 in front_t),
            min(max(c1 + s1 * yh, c2 + s2 * yh) for c1, c2 in front_h),
        )
        if on is not None:  # segments on the face's own edge: straight along it to their stretch
            inv = 1.0 / (self.vb if face[0] == 0 else self.va)
            if isinstance(on, list):
                for a_k, w_k, z0, z1 in on:
                    x = max(0.0, z0 - y1, y0 - z1) * inv  # the edge robot's time to the stretch (s)
                    best = min(best, max(a_k, x) + TIE_BREAK * (a_k + x) + w_k)
            else:  # many: one numpy pass, the same operations per segment
                a_k, w_k, z0, z1 = on
                x = np.maximum(np.maximum(0.0, z0 - y1), y0 - z1) * inv
                best = min(best, float(np.min(np.maximum(a_k, x) + TIE_BREAK * (a_k + x) + w_k)))
        return best

    def least_through_all(self, face: FaceKey, y0: float, y1: float) -> float:
        """:meth:`least_through` evaluated over every passing segment at once (numpy; s): the reference the fronts
        are checked against, tens of µs a call on a 139-edge map."""
        ax, w, other = face
        g = self.mesh.g
        e_, u0, u1, f_, v0, v1, wk = self._segs[:7]
        eb, ub0, ub1 = (f_, v0, v1) if ax == 0 else (e_, u0, u1)
        dv, le = self._dv, g._L[other]
        d_t = np.minimum(dv[g._t[other], g.tails[eb]] + ub0, dv[g._t[other], g.heads[eb]] + g.lengths[eb] - ub1)
        d_h = np.minimum(dv[g._h[other], g.tails[eb]] + ub0, dv[g._h[other], g.heads[eb]] + g.lengths[eb] - ub1)
        di = np.minimum(y0 + d_t, le - y1 + d_h)
        on = eb == other
        di[on] = np.minimum(di[on], np.maximum(0.0, np.maximum(ub0[on] - y1, y0 - ub1[on])))
        t_w = self._vertex_times(ax, w)
        t_i = di / (self.vb if ax == 0 else self.va)
        return float(np.min(np.maximum(t_w, t_i) + TIE_BREAK * (t_w + t_i) + wk))

    def _slopes(self, ax: int) -> tuple[float, float]:
        """The hinges' two slopes per metre of the edge robot's travel (s/m): ``TIE_BREAK / v`` and ``(1 +
        TIE_BREAK) / v``, ``v`` the speed of the robot on the face's edge (robot B when ``ax`` is 0)."""
        v = self.vb if ax == 0 else self.va
        return TIE_BREAK / v, (1.0 + TIE_BREAK) / v

    def _parts(self, face: FaceKey) -> tuple[Any, ...]:
        """What :meth:`entry` needs of a face: the fronts of hinges through its edge's tail and head
        (:meth:`_front`), and the segments on the face's own edge (the vertex robot's time, ``W_k``, their stretch
        there), None when there are none."""
        ax, w, other = face
        g = self.mesh.g
        e_, u0, u1, f_, v0, v1, wk = self._segs[:7]
        eb, ub0, ub1 = (f_, v0, v1) if ax == 0 else (e_, u0, u1)
        a = self._vertex_times(ax, w)
        on = eb == other
        n_on = int(on.sum())
        on_part: Any = None
        if n_on > ON_EDGE_LOOP:
            on_part = (a[on], wk[on], ub0[on], ub1[on])
        elif n_on:
            on_part = list(zip(a[on].tolist(), wk[on].tolist(), ub0[on].tolist(), ub1[on].tolist()))
        return self._front(ax, w, int(g._t[other])), self._front(ax, w, int(g._h[other])), on_part

    def _vertex_times(self, ax: int, w: int) -> FloatArray:
        """The time (s) of the robot on the vertex ``w`` (robot A when ``ax`` is 0) to each segment's stretch of its
        edge, shape (K,), cached per vertex."""
        out = self._times.get((ax, w))
        if out is None:
            g = self.mesh.g
            e_, u0, u1, f_, v0, v1 = self._segs[:6]
            ea, ua0, ua1 = (e_, u0, u1) if ax == 0 else (f_, v0, v1)
            dv = self._dv
            dw = np.minimum(dv[w, g.tails[ea]] + ua0, dv[w, g.heads[ea]] + g.lengths[ea] - ua1)
            out = self._times[(ax, w)] = dw / (self.va if ax == 0 else self.vb)
        return out

    def _front(self, ax: int, w: int, x: int) -> list[tuple[float, float]]:
        """The front of hinges (:func:`_hinges`) of one robot on the vertex ``w`` (robot A when ``ax`` is 0) and the
        other at the vertex ``x`` (an end of its edge), cached: a face's bound depends on its edge only through the
        edge's ends and, for segments on that edge, their stretch."""
        out = self._fronts.get((ax, w, x))
        if out is None:
            g = self.mesh.g
            e_, u0, u1, f_, v0, v1, wk = self._segs[:7]
            eb, ub0, ub1 = (f_, v0, v1) if ax == 0 else (e_, u0, u1)
            dv = self._dv
            d = np.minimum(dv[x, g.tails[eb]] + ub0, dv[x, g.heads[eb]] + g.lengths[eb] - ub1)
            s1, s2 = self._slopes(ax)
            out = self._fronts[(ax, w, x)] = _hinges(self._vertex_times(ax, w), d, wk, s1, s2)
        return out


def passing_bound(
    mesh: _Mesh,
    start: tuple[Position, Position],
    goal: tuple[Position, Position],
    va: float,
    vb: float,
    floor: float = -math.inf,
) -> PassingBound | None:
    """The :class:`PassingBound` of a query, or None when no vertex separates its start from its goal or its value
    at the start does not exceed ``floor`` (s; the search's own bound there, for one: the passing bound is then
    known to gain nothing without its exact least at the start, the larger part of its cost)."""
    b = PassingBound(mesh, start, goal, va, vb, floor)
    return None if b.vertex is None or b.at_start <= floor else b
