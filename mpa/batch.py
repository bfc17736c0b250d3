"""Many queries at once: :func:`plan_many` gives the domain and the homotopy word of every query.

The answers are the ones :func:`mpa.plan` gives query by query: input checks, the preliminary step's end
points and the domain tests run on whole arrays with numpy. On a lollipop, the main step's discrete choices
(which branch, which comparisons hold) are evaluated on whole arrays and packed into one key per query; one
query per distinct key (a few hundred at most) runs the planner's own main-step code, and its domain and word
are shared by every query with that key. Queries within ``_MARGIN`` of a decision border (a vertex, an
ε-neighbourhood's edge, an antipode) are answered one by one by the same code. Full :class:`~mpa.plans.Plan`
objects are built on demand by :meth:`BatchPlans.plan`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa.errors import InvalidInputError, NoMotionError
from mpa.planners import make_planner
from mpa.planners.base import DEFAULT_NEIGHBOURHOOD, Planner, circle_pieces, pieces_word
from mpa.planners.circle import CirclePlanner
from mpa.planners.interval import IntervalPlanner
from mpa.planners.lollipop import LollipopPlanner, _drop_zero_edges, _wrap_model
from mpa.plans import Plan
from mpa.retraction import lollipop_trace, lollipop_trace_scalar
from mpa.skeleton import CircleSkeleton, skeleton_of
from mpa.tracks import Circle, Lollipop, Track

__all__ = ["BatchPlans", "plan_many"]


@dataclass(frozen=True)
class BatchPlans:
    """Domains and words of many queries on one track.

    Attributes
    ----------
    planner : Planner
        The planner (built once) that answers :meth:`plan`.
    starts, goals : ndarray, shape (N, 2)
        The queries, normalized (track coordinates, metres).
    domain : ndarray of int, shape (N,)
        Domain of continuity of every query (the numbering of docs/conventions.md), equal to ``plan(...).domain``.
    word : tuple of tuple of str
        Reduced skeleton word of every query, equal to ``plan(...).word``.
    """

    planner: Planner
    starts: NDArray[np.float64]
    goals: NDArray[np.float64]
    domain: NDArray[np.int64]
    word: tuple[tuple[str, ...], ...]
    _cache: dict[int, Plan] = field(default_factory=dict, repr=False, compare=False)

    def __len__(self) -> int:
        return len(self.domain)

    def plan(self, i: int) -> Plan:
        """The full :class:`~mpa.plans.Plan` of query ``i`` (built on first use, then kept)."""
        k = int(i)
        if not -len(self) <= k < len(self):
            raise InvalidInputError(f"query index is {i!r}, expected 0 <= i < {len(self)}")
        k %= len(self)
        if k not in self._cache:
            self._cache[k] = self.planner.plan(self.starts[k], self.goals[k])
        return self._cache[k]


def _as_states(name: str, value: ArrayLike) -> NDArray[np.float64]:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise InvalidInputError(f"{name} is not an array of numbers, expected shape (N, 2)") from None
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise InvalidInputError(f"{name} has shape {arr.shape}, expected (N, 2)")
    return arr


def _validate_states(planner: Planner, name: str, st: NDArray[np.float64]) -> NDArray[np.float64]:
    """The vectorised twin of :meth:`mpa.cspace.ConfigurationSpace.validate_state` (raises for the first bad row)."""
    tr = planner.track
    bad = ~np.all(np.isfinite(st), axis=1)
    out = np.stack([tr.normalize(st[:, 0]), tr.normalize(st[:, 1])], axis=1)
    if not bad.any():
        bad = ~np.all(tr._valid_mask(out), axis=1)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        planner.cspace.validate_state(st[i], f"{name}[{i}]")  # raises with the scalar message
        raise InvalidInputError(f"{name}[{i}] is {st[i].tolist()}, expected track coordinates")  # pragma: no cover
    d = tr.distance(out[:, 0], out[:, 1])
    low = (d <= 0.0) | (d < planner.clearance)
    if low.any():
        i = int(np.flatnonzero(low)[0])
        planner.cspace.validate_state(st[i], f"{name}[{i}]")
    return out


def plan_many(
    track: Track,
    starts: ArrayLike,
    goals: ArrayLike,
    clearance: float = 0.0,
    neighbourhood: float = DEFAULT_NEIGHBOURHOOD,
) -> BatchPlans:
    """Domains and words of many queries, equal to :func:`mpa.plan` query by query.

    Parameters
    ----------
    track : Track
    starts, goals : array_like, shape (N, 2)
        Track coordinates of robots A and B.
    clearance : float
        Required clearance D >= 0 (metres).
    neighbourhood : float
        Neighbourhood size of the domains, as a fraction of half the loop.

    Returns
    -------
    BatchPlans

    Raises
    ------
    InvalidInputError
        Bad arrays, or a bad query (the message names its index).
    NoMotionError
        A query has no collision-free motion (the message names its index).

    Examples
    --------
    >>> from mpa import Lollipop, plan_many
    >>> b = plan_many(Lollipop(1.0, 1.0), [(0.1, 0.6), (1.25, 1.75)], [(0.8, 0.3), (1.75, 1.25)])
    >>> b.domain.tolist(), b.word[0] == b.plan(0).word
    ([1, 2], True)
    """
    planner = make_planner(track, clearance, neighbourhood)
    s = _as_states("starts", starts)
    g = _as_states("goals", goals)
    if s.shape != g.shape:
        raise InvalidInputError(f"starts has shape {s.shape} and goals {g.shape}, expected equal shapes")
    s = _validate_states(planner, "starts", s)
    g = _validate_states(planner, "goals", g)
    n = len(s)
    if isinstance(planner, IntervalPlanner):
        flip = (s[:, 0] < s[:, 1]) != (g[:, 0] < g[:, 1])
        if flip.any():
            i = int(np.flatnonzero(flip)[0])
            try:
                planner.cspace.validate_query(s[i], g[i])
            except NoMotionError as exc:
                raise NoMotionError(f"query {i}: {exc}") from None
        return BatchPlans(planner, s, g, np.ones(n, dtype=np.int64), ((),) * n)
    if isinstance(planner, CirclePlanner):
        return _circle(planner, s, g)
    assert isinstance(planner, LollipopPlanner) and isinstance(track, Lollipop)
    if planner.clearance > track.half or planner.clearance > track.stick:
        return _one_by_one(planner, s, g)
    return _lollipop(planner, s, g)


def _one_by_one(planner: Planner, s: NDArray[np.float64], g: NDArray[np.float64]) -> BatchPlans:
    plans = {}
    for i in range(len(s)):
        try:
            plans[i] = planner.plan(s[i], g[i])
        except NoMotionError as exc:
            raise NoMotionError(f"query {i}: {exc}") from None
    dom = np.array([p.domain for p in plans.values()], dtype=np.int64)
    return BatchPlans(planner, s, g, dom, tuple(p.word for p in plans.values()), plans)


def _circle(planner: CirclePlanner, s: NDArray[np.float64], g: NDArray[np.float64]) -> BatchPlans:
    tr = planner.track
    assert isinstance(tr, Circle)
    sk = skeleton_of(tr)
    assert isinstance(sk, CircleSkeleton)
    c, h = tr.loop, tr.half
    eps = planner.neighbourhood * h
    b_i, b_f = s[:, 1], g[:, 1]
    dccw = (b_f - b_i) % c
    dccw = np.where(dccw >= c - 1e-15, 0.0, dccw)
    one = np.abs(dccw - h) < eps
    delta = np.where(one, dccw, np.where(dccw <= h, dccw, dccw - c))
    words = tuple(
        pieces_word(sk.graph, circle_pieces(float(b), float(d), h, lambda a: "Aa" if a == 0 else "Ab"))
        for b, d in zip(b_i.tolist(), delta.tolist())
    )
    return BatchPlans(planner, s, g, np.where(one, 1, 2).astype(np.int64), words)


def _lollipop_one(planner: LollipopPlanner, sa: float, sb: float, ga: float, gb: float) -> tuple[int, tuple[str, ...]]:
    """Domain and word of one query by the planner's own code (preliminary step, main step, word)."""
    sk = planner.skeleton
    ell, c_model, kappa = sk.model.stick, sk.model.loop, sk.kappa
    pts = []
    for a, b in ((sa, sb), (ga, gb)):
        ma = a if a <= ell else ell + (a - ell) * kappa
        mb = b if b <= ell else ell + (b - ell) * kappa
        da, db = lollipop_trace_scalar(ell, c_model, ma, mb)
        pts.append(sk.point_of_model_state(*_wrap_model(ell, c_model, ma, ma + da, mb, mb + db)))
    d, pieces = planner.route_in_skeleton(pts[0], pts[1])
    return d, pieces_word(sk.graph, _drop_zero_edges(sk, pieces))


#: Margin (metres, model units) within which a query counts as near a decision of the main step (a vertex, an
#: ε-neighbourhood's border, an antipode, the half-loop): such queries are answered one by one.
_MARGIN = 1e-7
#: Extended-vertex component (I1 = 0, v2 = 1, v3 = 2, I2 = 3) at φ = 0 and φ = h of circle j = 1, 2, 3.
_COMP0 = np.array([0, 0, 1, 3])
_COMPH = np.array([0, 1, 2, 2])


def _skeleton_points(
    planner: LollipopPlanner, st: NDArray[np.float64]
) -> tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.bool_]]:
    """The preliminary step on whole arrays: edge index, arc length, and a flag for points near a vertex."""
    sk = planner.skeleton
    ell, c_model, kappa = sk.model.stick, sk.model.loop, sk.kappa
    m = np.where(st <= ell, st, ell + (st - ell) * kappa)
    end = m + lollipop_trace(sk.model, m)
    on_loop = m > ell
    wrapped = ell + np.mod(end - ell, c_model)
    end = np.where(on_loop, np.where(wrapped >= ell + c_model - 1e-12, ell, wrapped), end)
    edge, t = sk.points_of_model_states(end)
    length = np.where((edge == 0) | (edge == 7), ell - sk.half, sk.half)
    near = np.any(np.abs(end - ell) < _MARGIN, axis=1) | (t < _MARGIN) | (t > length - _MARGIN)
    return edge, t, near


def _lollipop(planner: LollipopPlanner, s: NDArray[np.float64], g: NDArray[np.float64]) -> BatchPlans:
    """Vectorised main step: every query gets a key of the discrete choices the planner makes for it.

    Away from the decision borders (by more than ``_MARGIN``), the planner's domain and its sequence of skeleton
    pieces (edges and directions, hence the word) are functions of: the edges of the two skeleton points, and the
    branch and the comparisons that ``route_in_skeleton`` evaluates (nearest extended vertex and whether it is
    within ε; for a common circle, ``|Δccw − h| < ε`` and ``Δccw ≤ h``; across blocks, each own-circle run's
    ambiguity and direction). One query per key is answered by the planner's own code and its answer shared;
    queries within ``_MARGIN`` of any border are answered one by one.
    """
    key, bad = _decision_keys(planner, s, g)
    dom, words = _answer_per_key(planner, np.hstack([s, g]), key, bad)
    return BatchPlans(planner, s, g, dom, tuple(words.tolist()))


def _decision_keys(
    planner: LollipopPlanner, s: NDArray[np.float64], g: NDArray[np.float64]
) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    """Per query (starts ``s``, goals ``g``, shape (N, 2)) the key of the planner's discrete choices, and whether
    the query lies within ``_MARGIN`` of a decision border (its key is then not trusted)."""
    sk = planner.skeleton
    h = sk.half
    c, eps, mg = 2.0 * h, planner.neighbourhood * h, _MARGIN
    n = len(s)
    ex, tx, bad_x = _skeleton_points(planner, s)
    ey, ty, bad_y = _skeleton_points(planner, g)
    bad = bad_x | bad_y
    if sk.graph.edge("I1").length <= mg:  # zero-length sticks in the model: I1/I2 points are vertices
        bad |= (ex == 0) | (ex == 7) | (ey == 0) | (ey == 7)
    circ_x, blk_x, phi_x = _circle_block_phi(ex, tx, h)
    circ_y, blk_y, phi_y = _circle_block_phi(ey, ty, h)
    cx, nx, close_x = _nearest_extended_vertex(ex, circ_x, phi_x, h, eps)
    cy, ny, close_y = _nearest_extended_vertex(ey, circ_y, phi_y, h, eps)
    bad |= close_x | close_y
    key = np.zeros(n, dtype=np.int64)
    # branch 1: both near an extended vertex
    b1 = nx & ny
    same = ex == ey
    bad |= b1 & same & (np.abs(ty - tx) < mg)
    key = np.where(b1, cx * 8 + cy * 2 + (same & (ty > tx)), key)
    # branch 2: a common circle
    b2 = ~b1 & (blk_x == blk_y) & (circ_x > 0)
    dccw = np.mod(phi_y - phi_x, c)
    off = np.abs(dccw - h)
    bad |= b2 & ((np.abs(off - eps) < mg) | (off < mg) | (dccw < mg) | (dccw > c - mg))
    key = np.where(b2, 256 + (off < eps) * 2 + (dccw <= h), key)
    # branch 3: different blocks; own-circle runs to the exit vertex and from the entry vertex
    b3 = ~b1 & ~b2
    right = blk_x < blk_y
    flags, bad_runs = _own_circle_runs(b3, right, ((circ_x, phi_x), (circ_y, phi_y)), h, eps)
    bad |= bad_runs
    bad |= b3 & (blk_x == blk_y)  # not reached: both on one stick are both near an extended vertex
    key = np.where(b3, 512 + flags * 2 + right, key)
    key = ((key * 3 + np.where(b1, 0, np.where(b2, 1, 2))) * 8 + ex) * 8 + ey
    return key, bad


def _circle_block_phi(
    e: NDArray[np.int64], t: NDArray[np.float64], h: float
) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]]:
    """Of skeleton points (edge ``e``, arc length ``t``): circle index (0 on I1/I2), chain block, circle
    parameter φ."""
    circ = np.where((e == 0) | (e == 7), 0, (e + 1) // 2)
    blk = np.where(e == 7, 4, circ)
    phi = t + np.where(e % 2 == 0, h, 0.0)
    return circ, blk, phi


def _nearest_extended_vertex(
    e: NDArray[np.int64], circ: NDArray[np.int64], phi: NDArray[np.float64], h: float, eps: float
) -> tuple[Any, Any, Any]:
    """The nearest extended-vertex component of each point, whether it is within ε, and whether the point is
    within ``_MARGIN`` of either decision."""
    c, mg = 2.0 * h, _MARGIN
    d0 = np.minimum(phi, c - phi)
    dh = np.abs(phi - h)
    on_i = (e == 0) | (e == 7)
    comp = np.where(on_i, np.where(e == 0, 0, 3), np.where(d0 <= dh, _COMP0[circ], _COMPH[circ]))
    dist = np.where(on_i, 0.0, np.minimum(d0, dh))
    close = ~on_i & ((np.abs(d0 - dh) < mg) | (np.abs(dist - eps) < mg))
    return comp, dist < eps, close


def _own_circle_runs(
    b3: NDArray[np.bool_],
    right: NDArray[np.bool_],
    points: tuple[tuple[NDArray[np.int64], NDArray[np.float64]], tuple[NDArray[np.int64], NDArray[np.float64]]],
    h: float,
    eps: float,
) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    """Branch 3 (different blocks): for the start's run to its exit vertex and the goal's from its entry vertex
    (``points``: circle index and φ of each), the ambiguity and direction flags, and the queries near a border."""
    c, mg = 2.0 * h, _MARGIN
    n = len(b3)
    flags = np.zeros(n, dtype=np.int64)
    bad = np.zeros(n, dtype=bool)
    for k, ((circ, phi), exit_) in enumerate(zip(points, (True, False))):
        # vertex φ: CIRCLE_ENDS gives (left, right) = (0, h) for S1 and S2, (h, 0) for S3
        use_right = right if exit_ else ~right
        left_phi = np.where(circ == 3, h, 0.0)
        vphi = np.where(use_right, h - left_phi, left_phi)
        dist = np.mod(phi - (vphi + h), c)
        dist = np.minimum(dist, c - dist)
        amb = dist < eps
        run = np.mod(vphi - phi, c) if exit_ else np.mod(phi - vphi, c)
        ccw = amb | (run <= h)
        on_c = b3 & (circ > 0)
        bad |= on_c & ((np.abs(dist - eps) < mg) | (np.abs(run - h) < mg) | (run < mg) | (run > c - mg))
        flags |= np.where(on_c, (amb * 2 + ccw) << (2 * k), 0)
    return flags, bad


def _answer_per_key(
    planner: LollipopPlanner, q: NDArray[np.float64], key: NDArray[np.int64], bad: NDArray[np.bool_]
) -> tuple[NDArray[np.int64], NDArray[Any]]:
    """Domain and word per query (``q``: start and goal, shape (N, 4)): the planner answers one query per key and
    its answer is shared; the ``bad`` queries are answered one by one."""
    n = len(q)
    dom = np.empty(n, dtype=np.int64)
    words = np.empty(n, dtype=object)
    ok = np.flatnonzero(~bad)
    if len(ok):
        uniq, first, inv = np.unique(key[ok], return_index=True, return_inverse=True)
        table_d = np.empty(len(uniq), dtype=np.int64)
        table_w = np.empty(len(uniq), dtype=object)
        for k, i in enumerate(ok[first].tolist()):
            table_d[k], table_w[k] = _lollipop_one(planner, *q[i].tolist())
        dom[ok] = table_d[inv]
        words[ok] = table_w[inv]
    for i in np.flatnonzero(bad).tolist():
        dom[i], words[i] = _lollipop_one(planner, *q[i].tolist())
    return dom, words
