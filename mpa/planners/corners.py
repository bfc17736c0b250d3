"""The corners of a searched plan re-solved by a continuous rule: one motion among the equally fast ones.

The any-angle search of :mod:`mpa.planners.graph` returns a chain of straight segments through free convex polygons,
one cell per segment. Along such a chain the optimum is often a *plateau*: a robot with time to spare may wait a
little earlier or a little later, and every such timing is equally fast. Which of them the search returns depends on
the order of its queue, so a query moved by a hair may return a corner moved by metres. :func:`resolve_corners`
replaces the search's corners by the unique minimiser of a strictly convex function over the plateau of the plan's
own chain of cells, so the corners move continuously with the query while the routes, the cells and the makespan
stay the search's.

**The chain.** Segment ``i`` runs in cell ``c_i = (e_i, f_i, k_i)`` from ``P_i`` to ``Q_i`` (offsets ``(s, t)`` in
metres). At the corner between segments ``i - 1`` and ``i`` a robot whose edge changes (or whose offset is read
differently in the two cells) stands on a vertex: its coordinate is fixed. A robot on the same edge at the same
offset in both cells is *free*: one variable ``x`` shared by ``Q_{i-1}`` and ``P_i``. The start and the goal are
fixed. Each robot's motion on a segment keeps the direction of its route there (``σ Δ >= 0``; a robot that stands
on an edge for the whole stay keeps standing), so ``|Δ| = σ Δ`` is linear and the routes (edges and directions)
cannot change.

**The rule.** With ``T_i`` the duration of segment ``i`` (at least ``σ_A ΔA_i / vA`` and ``σ_B ΔB_i / vB``):

1. the makespan ``sum T_i`` is at most the search's, ``M (1 + RESOLVE_TOL)``;
2. the travel in time units ``sum (|ΔA_i| / vA + |ΔB_i| / vB)`` is at most the search's, ``W (1 + RESOLVE_TOL)``;
3. every corner lies in both polygons it joins (the clearance's affine terms, the edges' ends, the piece of a cell
   of one edge), so every segment lies in its convex polygon;

and among those motions the one of least ``sum (ΔA_i / vA)² + (ΔB_i / vB)² + T_i²`` (squared segment lengths and
durations, seconds²; solved with durations in metres at the faster speed, :func:`_unit_speeds`, so that the
corners do not depend on the speeds' common scale). The function is strictly convex in the free corners and the
durations and the feasible set is a polyhedron that moves continuously with the query, so the minimiser is unique
and continuous in the query. It is a least-distance programme, solved exactly (a finite active-set method) by
Lawson and Hanson's reduction to non-negative least squares (:func:`scipy.optimize.nnls`'s routine, loaded without
the rest of :mod:`scipy.optimize`: :func:`mpa._nnls.nnls`): with ``R`` from the QR
factorisation of the map from the free corners to the scaled segment moves, ``min |y|`` subject to ``G y >= h`` is
``y = -r[:n] / r[n]`` for the residual ``r = E u - (0, ..., 0, 1)`` of the non-negative least squares problem with
``E = [Gᵀ; hᵀ]``. Each iteration of that solve costs in proportion to the rows of ``G``, so the rows that others
imply are left out (:data:`DROP_IMPLIED_ROWS`, :func:`_monotone_variables`): the feasible set is the same; and the
solve starts from the rows tight at the chain's own corners and the durations' rows, adding the rows its minimiser
breaks (:data:`ACTIVE_SET_SEED`, :func:`_least_distance`): the same minimiser. Each chain's programme is built by
:func:`_programme` (a :class:`Programme`), or by a compiled builder of the same arrays installed with
:func:`use_programme` (:mod:`trajopt.plan_kernel` installs one with its compiled search).

**Checks.** The free coordinates are clamped into the face intervals of :mod:`mpa.freespace` (as the search clamps
its crossings), and the result is kept only if every segment keeps the clearance (exact per cell,
:meth:`~mpa.geometry.GraphGeometry.segment_min_scalar`), every corner lies in its edges, each robot's directions
are kept and the makespan and travel are within :data:`CHECK_TOL` of the search's (the solve aims at half of
:data:`RESOLVE_TOL`; the check allows its rounding); otherwise the search's corners are returned unchanged.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from typing import Any, NamedTuple, cast

import numpy as np

from mpa._arrays import FloatArray
from mpa._nnls import nnls
from mpa.freespace import FreeSpace, PolygonId
from mpa.planners.corner_chains import _widened, _widenings

__all__ = ["CHECK_TOL", "RESOLVE_TOL", "Programme", "compiled_programme", "resolve_corners", "use_programme"]

#: Relative tolerance of the re-solve: makespan and travel at most ``(1 + RESOLVE_TOL)`` times the search's.
RESOLVE_TOL = 1e-12
#: Relative tolerance of the check on the re-solved makespan and travel. The programme aims at ``RESOLVE_TOL / 2``
#: above the search's; the solve's rounding can overshoot ``RESOLVE_TOL`` (measured: 1.3e-12 to 2.2e-12 on the
#: airport map's chains of about 90 unknowns, 1.4e-12 on the 1 000-edge warehouse grid's of 185), and a check at
#: ``RESOLVE_TOL`` then refused a chain's corners by rounding alone: another chain, or the search's corners, was taken,
#: and the plan could jump between queries a hair apart. The check allows a hundred times the aim.
CHECK_TOL = 100.0 * RESOLVE_TOL
_SLOPES = ((1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0))
#: Leave out of the programme the rows that other rows imply (the boxes of coordinates held between two fixed values
#: by their direction rows, ``T_i >= 0`` where a moving robot's rows bound ``T_i``): the same feasible set and
#: minimiser with 40 % fewer rows, which the non-negative least squares solve pays for on every iteration (2-3x
#: faster on the building maps' and 1 000-edge layouts' long chains). False: every row, as a check.
DROP_IMPLIED_ROWS = True
#: Solve each chain's programme first with the rows that hold at its own corners with equality and the rows of the
#: durations, adding the rows its minimiser breaks until it breaks none (:func:`_least_distance`): the same
#: minimiser from about half the rows, in one solve on nearly every chain. False: every row, as a check.
ACTIVE_SET_SEED = True
#: A row is in the first solve when it holds at the chain's own corners with at most this slack (metres, seconds).
SEED_SLACK = 1e-9
#: Solves of :func:`_least_distance` from its first rows before it solves with every row.
SEED_ROUNDS = 6
#: A first solve whose minimiser breaks its own rows by more than this (relative to the largest right-hand side) has
#: lost its accuracy (a nearly infeasible subset): :func:`_least_distance` solves with every row instead.
SEED_LOST = 1e-6


class Programme(NamedTuple):
    """The least-distance programme of one chain (:func:`_programme`): ``G z >= h`` over ``z = [x; T]`` (``nv`` free
    coordinates in metres, then ``n`` durations in metres at the faster speed) and the objective
    ``|dmat x + dcon|² + |T|²``.

    ``free[j][r]`` is the variable of robot ``r``'s coordinate at corner ``j`` (between segments ``j - 1`` and ``j``,
    ``j`` in ``0 .. n``) or -1 where it is fixed; ``sig[r][i]`` the sign robot ``r``'s move keeps on segment ``i``;
    ``vix[i][end][r]`` and ``cst[i][end][r]`` the variable (or -1) and the constant (the search's value where fixed,
    else 0) of robot ``r``'s coordinate at the start (``end`` 0) or end (1) of segment ``i``; ``x_own`` the free
    coordinates at the chain's own corners; ``var_robot``, ``var_edge`` each variable's robot and edge; ``travel_row``
    the row of the travel."""

    nv: int
    free: list[list[int]]
    sig: tuple[list[int], list[int]]
    vix: list[list[list[int]]]
    cst: list[list[list[float]]]
    x_own: FloatArray  # (nv,)
    var_robot: list[int]
    var_edge: list[int]
    gmat: FloatArray  # (m, nv + n)
    h: FloatArray  # (m,)
    dmat: FloatArray  # (2n, nv)
    dcon: FloatArray  # (2n,)
    travel_row: int


#: The builder of :class:`Programme` that :func:`_solve_chain` calls in place of :func:`_programme`
#: (:func:`use_programme`), None: that one.
_PROGRAMME: Callable[..., Programme | None] | None = None


def use_programme(build: Callable[..., Programme | None] | None) -> None:
    """Build each chain's programme with ``build`` in place of :func:`_programme` (None: that one again).

    ``build`` takes :func:`_programme`'s arguments and returns the same :class:`Programme`, bit for bit. :mod:`mpa`
    stays numpy and scipy only: the compiled builder of :mod:`trajopt.plan_kernel` installs itself with this
    (:func:`trajopt.plan_kernel.install`)."""
    global _PROGRAMME
    _PROGRAMME = build


def compiled_programme() -> Callable[..., Programme | None] | None:
    """The builder installed by :func:`use_programme`, None when there is none."""
    return _PROGRAMME


def _terms(
    fs: FreeSpace, e: int, f: int, terms_of: dict[tuple[int, int], list[tuple[float, float, float]]]
) -> list[tuple[float, float, float]]:
    """:func:`_binding_terms` of the cell ``e × f``, kept in ``terms_of`` (one dict per plan)."""
    terms = terms_of.get((e, f))
    if terms is None:
        terms = terms_of[(e, f)] = _binding_terms(fs, e, f)
    return terms


def _directions(cells: list[Any], d: FloatArray, free: list[list[int]], robot: int) -> list[int]:
    """Per segment the sign each robot's move must keep: its own sign, or for a standing stay the sign of the
    previous (else the next) move on the same stay on one edge, or 0 (the robot stands there throughout).

    ``d`` has shape (n, 2), the search's moves; ``free[j][robot] >= 0`` when the robot's coordinate at corner ``j``
    (between segments ``j - 1`` and ``j``) is a free variable, i.e. the robot stays on its edge across the corner.
    """
    n = len(cells)
    sig = [(x > 0.0) - (x < 0.0) for x in d[:, robot].tolist()]
    out = list(sig)
    i = 0
    while i < n:  # stays: maximal runs of segments joined by free corners of this robot
        j = i
        while j + 1 < n and free[j + 1][robot] >= 0:
            j += 1
        last = 0
        pending: list[int] = []
        for k in range(i, j + 1):
            if sig[k] != 0:
                for p in pending:
                    out[p] = sig[k]
                pending = []
                last = sig[k]
            elif last != 0:
                out[k] = last
            else:
                pending.append(k)
        i = j + 1
    return out


def _monotone_variables(free: list[list[int]], sig: tuple[list[int], list[int]], nv: int, n: int) -> list[bool]:
    """Per free variable whether its edge's box ``0 <= x <= L`` is implied by the direction rows.

    A robot's *stay* is a maximal run of segments joined by its free corners; the coordinates at the stay's two ends
    are fixed (the search's, on the edge). Where every move of the stay keeps one sign (or stands), the rows
    ``σ Δ >= 0`` hold each free coordinate of the stay between those two fixed values, so its box rows are redundant
    and left out of the programme (the feasible set, hence the minimiser, is the same). ``free[j][r]`` is the
    variable of robot ``r`` at corner ``j`` (between segments ``j - 1`` and ``j``) or -1 where fixed.
    """
    boxed = [False] * nv
    for r in (0, 1):
        i = 0
        while i < n:
            j = i
            while j + 1 < n and free[j + 1][r] >= 0:
                j += 1
            signs = {sig[r][k] for k in range(i, j + 1)} - {0}
            if len(signs) <= 1:
                for k in range(i + 1, j + 1):
                    boxed[free[k][r]] = True
            i = j + 1
    return boxed


def _programme(
    fs: FreeSpace,
    cells: list[PolygonId],
    p0: FloatArray,
    p1: FloatArray,
    speeds: tuple[float, float],
    m_search: float,
    w_search: float,
    terms_of: dict[tuple[int, int], list[tuple[float, float, float]]],
) -> Programme | None:
    """The least-distance programme of the rule in the chain of cells ``cells`` whose segments run from ``p0`` to
    ``p1`` (shape (n, 2), offsets in metres; speeds scaled by :func:`_unit_speeds`); None when no corner is free.

    The unknowns ``z = [x; T]`` are the free coordinates (metres) and the segments' durations (metres at the faster
    speed); :class:`Programme` holds the rows ``G z >= h``, the objective's map (``|dmat x + dcon|² + |T|²``) and
    which coordinate is which variable. ``terms_of`` keeps :func:`_binding_terms` per cell between the chains of one
    plan. :func:`use_programme` installs a compiled builder of the same arrays, bit for bit."""
    n = len(cells)
    va, vb = speeds
    g = fs.geometry
    lengths = g._L
    # free variables at the interior corners j = 1 .. n-1 (between segment j-1 and j)
    free: list[list[int]] = [[-1, -1] for _ in range(n + 1)]
    values: list[float] = []
    var_robot: list[int] = []
    var_edge: list[int] = []
    for j in range(1, n):
        for r in (0, 1):
            if cells[j - 1][r] == cells[j][r] and p1[j - 1, r] == p0[j, r]:
                free[j][r] = len(values)
                values.append(float(p0[j, r]))
                var_robot.append(r)
                var_edge.append(int(cells[j][r]))
    nv = len(values)
    if nv == 0:
        return None
    d = p1 - p0
    sig_a = _directions(cells, d, free, 0)
    sig_b = _directions(cells, d, free, 1)
    sig = (sig_a, sig_b)
    vel = (va, vb)
    # a robot standing on a segment keeps one coordinate at both its corners: one variable, or none at a fixed end
    parent = list(range(nv))
    pinned = [False] * nv

    def find(v: int) -> int:
        while parent[v] != v:
            parent[v] = parent[parent[v]]
            v = parent[v]
        return v

    for i in range(n):
        for r in (0, 1):
            if sig[r][i] != 0:
                continue
            v0 = free[i][r] if i > 0 else -1
            v1 = free[i + 1][r] if i + 1 < n else -1
            if v0 >= 0 and v1 >= 0:
                a0, a1 = find(v0), find(v1)
                pinned[a1] = pinned[a1] or pinned[a0]
                parent[a0] = a1
            elif v0 >= 0 or v1 >= 0:
                pinned[find(max(v0, v1))] = True
    renumber: dict[int, int] = {}
    kept: list[int] = []
    for v in range(nv):
        root = find(v)
        if pinned[root]:
            continue
        if root not in renumber:
            renumber[root] = len(kept)
            kept.append(root)
    for j in range(1, n):
        for r in (0, 1):
            v = free[j][r]
            if v >= 0:
                root = find(v)
                free[j][r] = -1 if pinned[root] else renumber[root]
    x_own = np.array([values[v] for v in kept], dtype=float)  # the free coordinates at the chain's own corners
    var_robot = [var_robot[v] for v in kept]
    var_edge = [var_edge[v] for v in kept]
    nv = len(kept)
    if nv == 0:
        return None
    boxed = _monotone_variables(free, sig, nv, n) if DROP_IMPLIED_ROWS else [False] * nv

    # every coordinate as a variable (index, or -1) plus a constant (the search's value when fixed)
    p0l, p1l = p0.tolist(), p1.tolist()
    vix = [[[-1, -1], [-1, -1]] for _ in range(n)]
    cst = [[[0.0, 0.0], [0.0, 0.0]] for _ in range(n)]
    for i in range(n):
        for r in (0, 1):
            v0 = free[i][r] if i > 0 else -1
            v1 = free[i + 1][r] if i + 1 < n else -1
            vix[i][0][r], vix[i][1][r] = v0, v1
            cst[i][0][r] = 0.0 if v0 >= 0 else p0l[i][r]
            cst[i][1][r] = 0.0 if v1 >= 0 else p1l[i][r]

    # constraints G [x; T] >= h over nv + n unknowns, as (column, value) entries per row
    nz = nv + n
    rows_g: list[list[tuple[int, float]]] = []
    rhs: list[float] = []
    # the objective's linear map: scaled moves Δ/v of every segment and robot, (2n, nv) and constant (2n,)
    dmat = np.zeros((2 * n, nv))
    dcon = [0.0] * (2 * n)
    travel: dict[int, float] = {}
    travel_const = 0.0
    fixed_t = [0.0] * n
    timed = [False] * n  # T_i bounded below by a moving robot's σ Δ / v >= 0
    for i in range(n):
        for r in (0, 1):
            v0, v1 = vix[i][0][r], vix[i][1][r]
            iv = 1.0 / vel[r]
            k = 2 * i + r
            dk = (cst[i][1][r] - cst[i][0][r]) * iv
            dcon[k] = dk
            s = sig[r][i]
            if v0 < 0 and v1 < 0:  # both ends fixed: the move is the search's
                fixed_t[i] = max(fixed_t[i], abs(dk))
                travel_const += s * dk
                continue
            ents = []
            if v1 >= 0:
                dmat[k, v1] += iv
                ents.append((v1, iv))
            if v0 >= 0:
                dmat[k, v0] -= iv
                ents.append((v0, -iv))
            if s == 0:  # stands: both ends are one variable (Δ = 0 identically)
                continue
            rows_g.append([(c, s * x) for c, x in ents])  # σ Δ >= 0
            rhs.append(-s * dk)
            rows_g.append([(c, -s * x) for c, x in ents] + [(nv + i, 1.0)])  # T_i - σ Δ / v >= 0
            rhs.append(s * dk)
            timed[i] = True
            for c, x in ents:
                travel[c] = travel.get(c, 0.0) - s * x
            travel_const += s * dk
    for i in range(n):  # T_i >= the fixed moves' durations (and >= 0, implied by a moving robot's two rows)
        if DROP_IMPLIED_ROWS and fixed_t[i] == 0.0 and timed[i]:
            continue
        rows_g.append([(nv + i, 1.0)])
        rhs.append(fixed_t[i])
    rows_g.append([(nv + i, -1.0) for i in range(n)])  # makespan
    rhs.append(-m_search * (1.0 + 0.5 * RESOLVE_TOL))
    travel_row = len(rows_g)
    rows_g.append(list(travel.items()))  # travel: sum σ Δ / v
    rhs.append(travel_const - w_search * (1.0 + 0.5 * RESOLVE_TOL))
    # corners in their polygons: the clearance's affine terms, the edges' ends, the piece of a one-edge cell
    dmin = fs._dmin
    margin = 0.5 * fs.tol  # rounding of the solve stays on the free side of the membership test
    pts = (p0l, p1l)
    for v in range(nv):  # box of the free coordinate (implied where its stay is monotone)
        if boxed[v]:
            continue
        rows_g.append([(v, 1.0)])
        rhs.append(0.0)
        rows_g.append([(v, -1.0)])
        rhs.append(-float(lengths[var_edge[v]]))
    for i in range(n):
        e, f, kk = cells[i]
        terms = _terms(fs, e, f, terms_of)
        for end in (0, 1):
            va_, vb_ = vix[i][end]
            if va_ < 0 and vb_ < 0:
                continue
            ca_, cb_ = cst[i][end]
            ps, pt_ = pts[end][i]
            for sa, sb, c0 in terms:
                ents = []  # sa * s + sb * t + c0 >= dmin (+ margin, where the search's corner allows it)
                if va_ >= 0:
                    ents.append((va_, sa))
                if vb_ >= 0:
                    ents.append((vb_, sb))
                rows_g.append(ents)
                here = max(dmin, sa * ps + sb * pt_ + c0)
                rhs.append(min(dmin + margin, here) - c0 - sa * ca_ - sb * cb_)
            if e == f:
                sg = 1.0 if kk == 0 else -1.0  # piece 0: s - t >= dmin; piece 1: t - s >= dmin
                ents = []
                if va_ >= 0:
                    ents.append((va_, sg))
                if vb_ >= 0:
                    ents.append((vb_, -sg))
                rows_g.append(ents)
                here = max(dmin, sg * (ps - pt_))
                rhs.append(min(dmin + margin, here) - sg * (ca_ - cb_))
    # G from its entries, summed in their order where a row holds a column twice (bincount adds in array order)
    counts = [len(ents) for ents in rows_g]
    entries = np.array(list(itertools.chain.from_iterable(rows_g)), dtype=float).reshape(-1, 2)
    flat = np.repeat(np.arange(len(rows_g)) * nz, counts) + entries[:, 0].astype(np.int64)
    gmat = np.bincount(flat, weights=entries[:, 1], minlength=len(rows_g) * nz).astype(float, copy=False)
    gmat = gmat.reshape(len(rows_g), nz)
    h = np.array(rhs)
    return Programme(nv, free, sig, vix, cst, x_own, var_robot, var_edge, gmat, h, dmat, np.array(dcon), travel_row)


def _solve_chain(
    fs: FreeSpace,
    segs: list[list[Any]],
    speeds: tuple[float, float],
    m_search: float,
    w_search: float,
    floor: float,
    terms_of: dict[tuple[int, int], list[tuple[float, float, float]]] | None = None,
) -> tuple[float, list[list[Any]]] | None:
    """The rule's minimiser in the chain of cells of ``segs`` (segments as in :func:`resolve_corners`; a segment may
    have length zero), with its objective value (s²); None when the chain has no free corner, no motion within the
    tolerance of the search's makespan ``m_search`` and travel ``w_search`` (s), or a check fails. ``terms_of``
    keeps :func:`_binding_terms` per cell between the chains of one plan."""
    n = len(segs)
    va, vb = speeds
    g = fs.geometry
    lengths = g._L
    cells = [tuple(x[0]) for x in segs]
    p0 = np.array([x[1] for x in segs], dtype=float)  # (n, 2)
    p1 = np.array([x[2] for x in segs], dtype=float)
    if terms_of is None:
        terms_of = {}
    build = _PROGRAMME if _PROGRAMME is not None else _programme
    prog = build(fs, cells, p0, p1, speeds, m_search, w_search, terms_of)
    if prog is None:
        return None
    nv, free, sig, vix, cst, x_own, var_robot, var_edge, gmat, h, dmat, dcon_a, travel_row = prog
    d = p1 - p0
    var_corners: list[list[int]] = [[] for _ in range(nv)]
    for j in range(1, n):  # each variable's corners in order (a corner once per robot holding it)
        for r in (0, 1):
            if free[j][r] >= 0:
                var_corners[free[j][r]].append(j)

    def coord(i: int, end: int, r: int) -> tuple[int, float]:
        """Variable index (or -1) and constant of robot r's coordinate at segment i's start (0) or end (1)."""
        return vix[i][end][r], cst[i][end][r]

    # objective 1/2 |dmat x + dcon|² + 1/2 |T|²: with dmat = Q R, w = R x + Qᵀ dcon, min 1/2 |(w, T)|²; R and Qᵀ dcon
    # from the triangular factor of [dmat, dcon] (Q itself is not formed: half the time at 180 × 90)
    raug = cast("FloatArray", np.linalg.qr(np.column_stack([dmat, dcon_a]), mode="r"))
    rm = raug[:nv, :nv]
    diag = np.abs(np.diag(rm))
    if diag.min() <= 1e-12 * diag.max():  # pragma: no cover - full rank
        return None
    rinv = np.linalg.inv(rm)
    shift = raug[:nv, nv]  # Qᵀ dcon; x = R⁻¹ (w - shift)
    gx = gmat[:, :nv] @ rinv
    g2 = np.hstack([gx, gmat[:, nv:]])
    h2 = h + gx @ shift
    # least distance: min |y| s.t. g2 y >= h2 (None: infeasible, a widened chain without a motion as fast as the
    # search's), first from the rows tight at the chain's own corners and the durations' rows
    seed = None
    if ACTIVE_SET_SEED:
        z_own = np.concatenate([x_own, np.maximum(np.abs(d[:, 0]) / va, np.abs(d[:, 1]) / vb)])
        seed = (gmat @ z_own - h <= SEED_SLACK) | (gmat[:, nv:] != 0.0).any(axis=1)
        seed[travel_row] = True
    y = _least_distance(g2, h2, seed)
    if y is None:
        return None
    x = rinv @ (y[:nv] - shift)
    # clamp into the edges and the faces (the other robot on its vertex), as the search clamps its crossings
    lo_f, hi_f = fs.faces.lo, fs.faces.hi
    for v in range(nv):
        r, e = var_robot[v], var_edge[v]
        xv = min(max(float(x[v]), 0.0), float(lengths[e]))
        for j in var_corners[v]:
            for cell, pt in ((cells[j - 1], p1[j - 1]), (cells[j], p0[j])):
                other = 1 - r
                if free[j][other] < 0:  # the other robot stands on a vertex there
                    oe, oo = cell[other], float(pt[other])
                    w = g._t[oe] if oo == 0.0 else (g._h[oe] if oo == lengths[oe] else -1)
                    if w >= 0:
                        xv = min(max(xv, float(lo_f[w, e])), float(hi_f[w, e]))
        x[v] = xv
    out: list[list[Any]] = []
    for i in range(n):
        a = [0.0, 0.0]
        b = [0.0, 0.0]
        for r in (0, 1):
            v0, c0 = coord(i, 0, r)
            v1, c1 = coord(i, 1, r)
            a[r] = float(x[v0]) if v0 >= 0 else c0
            b[r] = float(x[v1]) if v1 >= 0 else c1
        out.append([segs[i][0], (a[0], a[1]), (b[0], b[1])])
    if not _valid(fs, out, sig, speeds, m_search, w_search, floor):
        return None
    value = 0.0
    for _, a, b in out:
        ta, tb = (b[0] - a[0]) / va, (b[1] - a[1]) / vb
        value += ta * ta + tb * tb + max(abs(ta), abs(tb)) ** 2
    return value, out


def _least_distance(g: FloatArray, h: FloatArray, seed: np.ndarray | None) -> FloatArray | None:
    """The least-distance programme ``min |y|`` subject to ``g y >= h``, solved exactly (Lawson and Hanson's reduction
    to non-negative least squares, ch. 23), from a subset of its rows.

    The programme of the rows of ``seed`` alone is solved first. When its minimiser keeps every other row too, it is
    the whole programme's (it is feasible there, and more rows cannot lower the minimum); otherwise the rows it breaks
    are added and it is solved again, and after :data:`SEED_ROUNDS` solves with every row. A subset of the rows
    without a feasible point proves the whole programme infeasible; a minimiser that breaks the subset's own rows
    (by more than :data:`SEED_LOST`: the reduction's division by a residual near 0, a subset nearly infeasible) is
    not trusted, and every row is solved. Fewer rows also round less (measured on a chain of 185 unknowns of the
    1 000-edge warehouse grid: every row's minimiser breaks rows by 2.2e-9, the subset's by 6.9e-12).

    Parameters
    ----------
    g : ndarray, shape (m, k)
    h : ndarray, shape (m,)
    seed : ndarray of bool, shape (m,), or None
        The rows of the first solve; None: every row.

    Returns
    -------
    ndarray, shape (k,), or None
        The minimiser; None when the rows have no feasible point (or the iteration limit is reached with every row).
    """
    m, k = g.shape
    f_vec = np.zeros(k + 1)
    f_vec[-1] = 1.0
    rows = np.ones(m, dtype=bool) if seed is None else seed  # never changed in place
    for solves in itertools.count(1):
        idx = np.flatnonzero(rows)
        y: FloatArray = np.zeros(k)  # the minimiser of no rows
        if len(idx):
            e_mat = np.vstack([g[idx].T, h[idx][None, :]])
            try:
                u, _ = nnls(e_mat, f_vec, maxiter=50 * e_mat.shape[1])
            except RuntimeError:  # the iteration limit: with every row, else give up
                if len(idx) == m:
                    return None
                rows = np.ones(m, dtype=bool)
                continue
            res = e_mat @ u - f_vec
            if abs(res[-1]) <= 1e-12:  # infeasible: these rows already are
                return None
            y = -res[:-1] / res[-1]
        if len(idx) == m:
            return y
        gy = g @ y
        if np.any(gy[idx] < h[idx] - SEED_LOST * (1.0 + float(np.max(np.abs(h[idx]), initial=0.0)))):
            rows = np.ones(m, dtype=bool)  # the subset's solve lost its accuracy (nearly infeasible): every row
            continue
        broken = ~rows & (gy < h)
        if not broken.any():
            return y
        rows = rows | broken if solves < SEED_ROUNDS else np.ones(m, dtype=bool)
    raise AssertionError("unreachable")  # pragma: no cover


def _binding_terms(fs: FreeSpace, e: int, f: int) -> list[tuple[float, float, float]]:
    """The affine terms ``(sa, sb, c0)`` of the cell ``e × f`` (:meth:`~mpa.geometry.GraphGeometry.cell_terms`)
    that can bind in it: reachable (``c0`` finite) and below the clearance somewhere on the cell's box."""
    g = fs.geometry
    dmin = fs._dmin
    le, lf = float(g._L[e]), float(g._L[f])
    return [
        (sa, sb, c0)
        for sa, sb, c0 in g.cell_terms(e, f)
        if math.isfinite(c0) and c0 + min(0.0, sa * le) + min(0.0, sb * lf) < dmin
    ]


#: At most this many grid corners of a chain are widened (2 ** MAX_WIDEN chains solved at most).
MAX_WIDEN = 3


def resolve_corners(
    fs: FreeSpace,
    segs: list[list[Any]],
    speeds: tuple[float, float],
) -> list[list[Any]]:
    """The corners of a searched ``fastest`` plan re-solved by the continuous rule of this module.

    Parameters
    ----------
    fs : FreeSpace
        The free space the plan was searched in.
    segs : list of [PolygonId, (s, t), (s, t)]
        The search's segments, start to goal: cell, start and end in the cell's offsets (metres), consecutive
        segments meeting at the same configuration, no segment of length zero.
    speeds : (float, float)
        ``(vA, vB)`` in m/s.

    Returns
    -------
    list of [PolygonId, (s, t), (s, t)]
        The re-solved segments (segments of length zero included), or ``segs`` itself when the plan has no free
        corner or no chain passes the checks.
    """
    n = len(segs)
    if n < 2:
        return segs
    va, vb = _unit_speeds(speeds)
    speeds = (va, vb)
    g = fs.geometry
    d = np.array([np.subtract(x[2], x[1]) for x in segs], dtype=float)
    m_search = float(np.sum(np.maximum(np.abs(d[:, 0]) / va, np.abs(d[:, 1]) / vb)))
    w_search = float(np.sum(np.abs(d[:, 0]) / va + np.abs(d[:, 1]) / vb))
    floor = min(fs._dmin, min(g.segment_min_scalar(c[0], c[1], *a, *b) for c, a, b in segs))
    places = _widenings(fs, segs)[:MAX_WIDEN]
    best: tuple[float, list[list[Any]]] | None = None
    routes = _routes(segs)
    terms_of: dict[tuple[int, int], list[tuple[float, float, float]]] = {}
    for choice in itertools.product(*places):
        chain = _widened(fs, segs, list(choice))
        if chain is None:
            continue
        got = _solve_chain(fs, chain, speeds, m_search, w_search, floor, terms_of)
        if got is not None and (best is None or got[0] < best[0] * (1.0 - 1e-12)) and _routes(got[1]) == routes:
            best = got
    return segs if best is None else best[1]


def _unit_speeds(speeds: tuple[float, float]) -> tuple[float, float]:
    """The speeds divided by the faster one: ``(vA / v, vB / v)`` with ``v = max(vA, vB)`` (m/s in, unitless out).

    The rule is solved with durations in metres at the faster speed (``v·T``) instead of seconds: the plateau, the
    minimiser and the checks are the same for ``(vA, vB)`` and ``(k·vA, k·vB)`` (every term of the rule scales by
    ``1/k`` or ``1/k²``), so the corners do not depend on the common scale of the speeds, and the least-distance
    programme keeps the conditioning of speeds near 1 m/s: the durations' rows and the clearance's rows of ``G``
    are of one size. Solved in seconds, speeds of a few mm/s (durations thousands of times the lengths) leave the
    solve's rounding above :data:`RESOLVE_TOL` of the makespan (measured: 1.2e-11 on the Y junction at 1.75 mm/s),
    so the check refuses the rule's corners for some clearances and keeps them for others a micrometre away, and
    the plan jumps between the search's corners and the rule's.
    """
    va, vb = float(speeds[0]), float(speeds[1])
    top = max(va, vb)
    return va / top, vb / top


def _routes(segs: list[list[Any]]) -> tuple[tuple[tuple[int, int], ...], ...]:
    """Each robot's route as ``(edge, direction)`` pairs in order (moves of length zero left out, repeats merged)."""
    out = []
    for r in (0, 1):
        route: list[tuple[int, int]] = []
        for cell, a, b in segs:
            dr = b[r] - a[r]
            if dr != 0.0:
                key = (int(cell[r]), 1 if dr > 0 else -1)
                if not route or route[-1] != key:
                    route.append(key)
        out.append(tuple(route))
    return tuple(out)


def _valid(
    fs: FreeSpace,
    segs: list[list[Any]],
    sig: tuple[list[int], list[int]],
    speeds: tuple[float, float],
    m_search: float,
    w_search: float,
    floor: float,
) -> bool:
    """Whether re-solved segments keep the clearance (at least ``floor`` m: the membership test's bound, or the
    search's own least distance when its rounding is below it), their directions, the makespan and the travel."""
    g = fs.geometry
    va, vb = speeds
    tol = CHECK_TOL  # the solve aims at half of RESOLVE_TOL: its rounding stays inside
    m = w = 0.0
    for i, (pid, a, b) in enumerate(segs):
        e, f, _ = pid
        le, lf = g._L[e], g._L[f]
        if not (0.0 <= a[0] <= le and 0.0 <= b[0] <= le and 0.0 <= a[1] <= lf and 0.0 <= b[1] <= lf):
            return False
        for r in (0, 1):
            dr = b[r] - a[r]
            if dr * sig[r][i] < 0.0 or (sig[r][i] == 0 and dr != 0.0):
                return False
        if g.segment_min_scalar(e, f, a[0], a[1], b[0], b[1]) < floor:
            return False
        ta, tb = abs(b[0] - a[0]) / va, abs(b[1] - a[1]) / vb
        m += max(ta, tb)
        w += ta + tb
    return m <= m_search * (1.0 + tol) and w <= w_search * (1.0 + tol)
