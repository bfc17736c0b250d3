"""Many queries at once: :func:`plan_many` gives the domain and the homotopy word of every query.

The answers are the ones :func:`mpa.plan` gives query by query (the same arithmetic): input checks, the
preliminary step's end points and the domain tests run on whole arrays with numpy; the skeleton word of a
lollipop query runs the planner's own main-step code per query, without assembling the routes of a full
:class:`~mpa.plan.Plan` (which :meth:`BatchPlans.plan` builds on demand).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa.errors import InvalidInputError, NoMotionError
from mpa.plan import Plan
from mpa.planners import make_planner
from mpa.planners.base import DEFAULT_NEIGHBOURHOOD, Planner, circle_pieces, pieces_word
from mpa.planners.circle import CirclePlanner
from mpa.planners.interval import IntervalPlanner
from mpa.planners.lollipop import LollipopPlanner, _drop_zero_edges, _wrap_model
from mpa.retraction import lollipop_trace_scalar
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
        Domain of continuity of every query (SPEC §4 numbering), equal to ``plan(...).domain``.
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
        """The full :class:`~mpa.plan.Plan` of query ``i`` (built on first use, then kept)."""
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
    except (TypeError, ValueError):
        raise InvalidInputError(f"{name} is not an array of numbers, expected shape (N, 2)") from None
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise InvalidInputError(f"{name} has shape {arr.shape}, expected (N, 2)")
    return arr


def _check(planner: Planner, name: str, st: NDArray[np.float64]) -> NDArray[np.float64]:
    """The vectorised twin of :meth:`mpa.cspace.ConfigurationSpace.check_state` (raises for the first bad row)."""
    tr = planner.track
    bad = ~np.all(np.isfinite(st), axis=1)
    out = np.stack([tr.normalize(st[:, 0]), tr.normalize(st[:, 1])], axis=1)
    if not bad.any():
        bad = ~np.all(tr._valid_mask(out), axis=1)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        planner.cspace.check_state(st[i], f"{name}[{i}]")  # raises with the scalar message
        raise InvalidInputError(f"{name}[{i}] is {st[i].tolist()}, expected track coordinates")  # pragma: no cover
    d = tr.distance(out[:, 0], out[:, 1])
    low = (d <= 0.0) | (d < planner.clearance)
    if low.any():
        i = int(np.flatnonzero(low)[0])
        planner.cspace.check_state(st[i], f"{name}[{i}]")
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
    s = _check(planner, "starts", s)
    g = _check(planner, "goals", g)
    n = len(s)
    if isinstance(planner, IntervalPlanner):
        flip = (s[:, 0] < s[:, 1]) != (g[:, 0] < g[:, 1])
        if flip.any():
            i = int(np.flatnonzero(flip)[0])
            try:
                planner.cspace.check_query(s[i], g[i])
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


def _lollipop(planner: LollipopPlanner, s: NDArray[np.float64], g: NDArray[np.float64]) -> BatchPlans:
    sk = planner.skeleton
    ell, c_model, kappa = sk.model.stick, sk.model.loop, sk.kappa
    dom = np.empty(len(s), dtype=np.int64)
    words: list[tuple[str, ...]] = []
    route, point, graph = planner.route_in_skeleton, sk.point_of_model_state, sk.graph
    for i, (sa, sb, ga, gb) in enumerate(np.hstack([s, g]).tolist()):
        pts = []
        for a, b in ((sa, sb), (ga, gb)):
            ma = a if a <= ell else ell + (a - ell) * kappa
            mb = b if b <= ell else ell + (b - ell) * kappa
            da, db = lollipop_trace_scalar(ell, c_model, ma, mb)
            pts.append(point(*_wrap_model(ell, c_model, ma, ma + da, mb, mb + db)))
        d, pieces = route(pts[0], pts[1])
        dom[i] = d
        words.append(pieces_word(graph, _drop_zero_edges(sk, pieces)))
    return BatchPlans(planner, s, g, dom, tuple(words))
