"""The entry point :func:`plan_graph`: the query read and checked, then the shortcut or the search.

When no motion exists, :func:`~mpa.planners.graph.reasons._why_no_motion` says why.
"""

from __future__ import annotations

import gc
import math
from typing import cast

import numpy as np

from mpa.errors import InvalidInputError, NoMotionError, PlanningError
from mpa.footprint import footprints
from mpa.freespace import FreeSpace, free_space, validate_size
from mpa.graph_track import GraphTrack, Position, as_graph_track
from mpa.planners.graph.assemble import _assemble, _merge_same_polygon
from mpa.planners.graph.base import OBJECTIVES, SPEED_RANGE, SPEED_RATIO, TIE_BREAK
from mpa.planners.graph.bounds import PassingBound, passing_bound, separating_vertices
from mpa.planners.graph.corridor import approach_distances
from mpa.planners.graph.mesh import _Mesh, _mesh
from mpa.planners.graph.reasons import _why_no_motion
from mpa.planners.graph.result import GraphPlan
from mpa.planners.graph.search import AnyAngleSearch
from mpa.planners.graph.shortcut import _independent_motion
from mpa.planners.search_common import GoalDistance, SearchQuery, cost_function

#: The reference search: a benchmark that replaces the module's ``AnyAngleSearch`` gets its own, not the installed one.
_REFERENCE = AnyAngleSearch

#: Queue pops after which a "fastest" search starts again with the passing bound (:mod:`mpa.planners.graph.bounds`;
#: a query that no vertex separates, where the bound is 0, is searched once without it); None: never. Building the
#: bound takes a few ms (its segments' geometry is kept per vertex with the free space, their goal costs are relaxed),
#: and a search whose bound keeps only the segments near the optimum is cheap per node, so searches that negotiate get
#: it early. Measured (docs/performance.md): after 300 pops against 2 000 (5 000 above 120 edges) with whole segments.
PASSING_BOUND_AFTER: int | None = 300

#: Edges above which the passing bound waits ``PASSING_BOUND_AFTER_LARGE`` pops (at least ``PASSING_BOUND_AFTER``).
PASSING_BOUND_EDGES = 120

PASSING_BOUND_AFTER_LARGE = 300

#: The passing bound is used when at the start it exceeds the robots' own bound (with the travel tie-break) by more
#: than this fraction of it. Its gain on a swap is seconds; where the robots' own motions already take the least time,
#: the bound still knows that one robot must step aside (its travel: 1e-9 to 1e-8 of the bound on the airport map's
#: slowest plateaus), and the search ordered by it takes 0.5-10x fewer nodes there (docs/performance.md).
BOUND_GAIN = 1e-9

#: When the passing bound knows no more than the robots' own bound at the start (``BOUND_GAIN``), the search that
#: took ``PASSING_BOUND_AFTER`` pops goes on where it stopped (``AnyAngleSearch.run`` resumes) instead of starting
#: again without a bound (False: the earlier scheme, the same search twice). With a gain it starts again with the
#: bound: resumed with the bound (the queued nodes re-keyed), the swaps of the airport map took 1.2-1.5x longer.
RESUME_WITHOUT_GAIN = True

#: The bounded search keeps first only the passing segments through which a motion can cost at most ``(1 + slack)``
#: times the bound at the start (:meth:`PassingBound.restrict`) and stops when the queue's least bound exceeds that
#: (below it the search is the one with every segment, node for node); then again with the next slack, and last with
#: every segment. Empty: every segment at once. The first, 1e-8, is the tie-breaks' scale: a query whose motion takes
#: the bound's time (a plateau) is answered with the few segments that allow it.
LIMIT_SLACKS: tuple[float, ...] = (1e-8, 0.02, 0.1, 0.3)

#: The first limit also admits the travel tie-break of this many clearances (``LIMIT_STEP_ASIDE * TIE_BREAK * D /
#: min(vA, vB)`` s, :func:`_limits`). A robot that steps aside into a branch travels at least D into it and D back;
#: the passing lemma sees the robots at one moment, ``D / 2`` on either side of the branch, so it counts D of that
#: travel and the optimum lies about one more ``TIE_BREAK * D`` above it: measured 1.0-1.5 (at most 2.15) of it on 44
#: of the 89 bounded queries of ``bench_plan_tails.py``. With the first limit at ``1e-8`` of the bound alone, every
#: query whose bound is under about 110 D / v searched up to that limit and then again (docs/performance.md).
LIMIT_STEP_ASIDE = 2.5

#: The second limit is at least the bound at the start plus this many clearances of time (``LIMIT_WAIT * D /
#: min(vA, vB)`` s, :func:`_limits`): where the bound misses that one robot must wait for the other to be D clear, or
#: go D round it, the optimum lies ``D / v`` above it (measured: exactly D / v on 5 of the 14 bounded queries of
#: ``bench_plan_tails.py`` whose optimum lies more than the tie-breaks' scale above the bound, less on 6 more), which
#: on the hotel maps (D / v of 13 % of the bound) is above the second and third slacks.
LIMIT_WAIT = 1.05


#: A query whose goals lie in one corridor in an order that its start does not have (``mpa.planners.graph.corridor``)
#: is searched once per class of motions (which robot comes into the corridor last, and through which end) when the
#: classes' least bound at the start exceeds the robots' own by more than ``BOUND_GAIN`` of it; False: one search.
#: Measured (docs/performance.md): the airport map's slowest query at seed 2 (a robot must follow the other into the
#: corridor of both goals, 14.6 m round) 1.47 s -> 0.21 s.
CORRIDOR_CLASSES = True


#: The search :func:`plan_graph` runs in place of :class:`AnyAngleSearch` (:func:`use_search`), None: that one.
_COMPILED: type | None = None


def use_search(cls: type | None) -> None:
    """Search with ``cls`` in place of :class:`~mpa.planners.graph.search.AnyAngleSearch` (None: that one again).

    ``cls`` takes the same arguments, has the same ``run`` and returns the same segments, node for node, and has a
    static method ``supports(query, bound)`` that says whether it does so under the planner's current settings
    (where it does not, :class:`AnyAngleSearch` answers). :mod:`mpa` stays numpy and scipy only: the compiled search
    of :mod:`trajopt.plan_kernel` installs itself with this (:func:`trajopt.plan_kernel.install`)."""
    global _COMPILED
    _COMPILED = cls


def compiled_search() -> type | None:
    """The search installed by :func:`use_search`, None when there is none."""
    return _COMPILED


def _new_search(
    mesh: _Mesh,
    query: SearchQuery,
    bound: PassingBound | None = None,
    to_goal: tuple[GoalDistance, GoalDistance] | None = None,
) -> AnyAngleSearch:
    """The installed search where it supports the query (:func:`use_search`), else :class:`AnyAngleSearch`; with
    ``to_goal`` (a class of motions' goal distances, :mod:`mpa.planners.graph.corridor`) when given."""
    cls = _COMPILED
    kw = {} if to_goal is None else {"to_goal": to_goal}
    if cls is not None and AnyAngleSearch is _REFERENCE and cls.supports(query, bound):  # type: ignore[attr-defined]
        return cast("AnyAngleSearch", cls(mesh, query, bound=bound, **kw))
    return AnyAngleSearch(mesh, query, bound=bound, **kw)


# ------------------------------------------------------------------------------------------------- API
def _fits_float(x: int) -> bool:
    try:
        float(x)
    except OverflowError:
        return False
    return True


def _speeds(speeds: object) -> tuple[float, float]:
    try:
        va, vb = cast("tuple[object, object]", speeds)
    except (TypeError, ValueError, OverflowError):
        raise InvalidInputError(f"speeds is {speeds!r}, expected two positive numbers (vA, vB) in m/s") from None
    out = []
    for name, v in (("speed of robot A", va), ("speed of robot B", vb)):
        if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
            raise InvalidInputError(f"{name} is {v!r}, expected a positive number (m/s)")
        if isinstance(v, int) and not _fits_float(v):
            raise InvalidInputError(
                f"{name} is an integer of {len(str(abs(v)))} digits, expected a finite number > 0 (m/s)"
            )
        if not math.isfinite(float(v)) or float(v) <= 0:
            raise InvalidInputError(f"{name} is {v!r}, expected a finite number > 0 (m/s)")
        if not SPEED_RANGE[0] <= float(v) <= SPEED_RANGE[1]:
            raise InvalidInputError(
                f"{name} is {v!r}, expected a number in [{SPEED_RANGE[0]:g}, {SPEED_RANGE[1]:g}] m/s (the planner "
                "works in times Δs/v, which overflow or lose all precision outside it)"
            )
        out.append(float(v))
    if max(out) / min(out) > SPEED_RATIO:
        raise InvalidInputError(
            f"speeds are {out[0]!r} and {out[1]!r} m/s, expected a ratio of at most {SPEED_RATIO:g} (the slower "
            "robot's times would swamp the faster one's)"
        )
    return out[0], out[1]


def _pair(track: GraphTrack, value: object, what: str) -> tuple[Position, Position]:
    if isinstance(value, str) or not isinstance(value, (tuple, list)) or len(value) != 2:
        raise InvalidInputError(f"{what} is {value!r}, expected two positions (robot A, robot B)")
    return (
        track.position(value[0], f"{what} of robot A"),
        track.position(value[1], f"{what} of robot B"),
    )


def plan_graph(
    track: object,
    start: object,
    goal: object,
    clearance: float = 0.0,
    objective: str = "fastest",
    speeds: object = (1.0, 1.0),
    footprint: object = None,
) -> GraphPlan:
    """Plan a collision-free motion of two robots on a graph track (complete: finds one whenever one exists).

    Parameters
    ----------
    track : GraphTrack, paper track, layout dict or path to a JSON layout
    start, goal : pair of positions
        ``(robot A, robot B)``; a position is ``(edge, offset)``, ``"EDGE:OFFSET"`` or a vertex name.
    clearance : float
        D (metres, >= 0): the graph distance between the robots stays >= D (D = 0: a tiny positive clearance, see
        :mod:`mpa.freespace`).
    objective : {"fastest", "shortest"}
        Minimum time for the speed limits (weighted L∞), or minimum Euclidean length in offsets.
    speeds : (float, float)
        Speed limits ``(vA, vB)`` (m/s, > 0).
    footprint : None, mpa.Disc, mpa.Rectangle, pair or spec string
        The robots' bodies in the plane (:mod:`mpa.footprint`); the motion then also keeps the bodies apart in the
        layout's drawing (:mod:`mpa.planar`: complete in that model; the robots' own shortest routes at once when
        they are free there, an optimum of ``objective``, else a path that bends only at the free pieces' shared
        points, not the optimum). Needs vertex coordinates.

    Returns
    -------
    GraphPlan

    Raises
    ------
    InvalidInputError
        Bad track, position, clearance, objective or speeds; robots closer than D at start or goal.
    NoMotionError
        Start and goal are in different path components of the free space; the message says why (different
        components, order on a path-like layout, clearance too large for the only siding or loop, the one-way
        lanes). On a track with one-way edges or speed limits the planner of :mod:`mpa.planners.rules` answers
        (complete under the one-way rule; time exact at the edges' speed limits).

    Examples
    --------
    >>> t = GraphTrack.from_layout({"edges": [["J", "a", 1.0], ["J", "b", 2.0], ["J", "c", 2.0]]})
    >>> p = plan_graph(t, ("b", "c"), ("c", "b"), clearance=0.5)
    >>> round(p.min_distance(), 6) >= 0.5
    True
    """
    tr = as_graph_track(track)
    validate_size(tr)  # before the distances and the free space are built
    if objective not in OBJECTIVES:
        raise InvalidInputError(f"objective is {objective!r}, expected one of {list(OBJECTIVES)}")
    va, vb = _speeds(speeds)
    s = _pair(tr, start, "start")
    gl = _pair(tr, goal, "goal")
    fs = free_space(tr, clearance)
    geo = tr.geometry
    for what, (pa, pb) in (("start", s), ("goal", gl)):
        if not fs.is_free(pa, pb):
            d = geo.distance_scalar(pa[0], pa[1], pb[0], pb[1])
            raise InvalidInputError(
                f"{what} has the robots {d:.12g} m apart, expected at least the clearance {fs.clearance_used:.12g} m"
            )
    fps = footprints(footprint)
    if fps is not None:
        from mpa.planar.plan import plan_planar

        return cast("GraphPlan", plan_planar(tr, s, gl, clearance, objective, (va, vb), fps))
    ca, cb = fs.component_of(*s), fs.component_of(*gl)
    if ca is None or ca != cb:
        raise NoMotionError(_why_no_motion(tr, fs, s, gl))
    query = SearchQuery(tr, fs, s, gl, objective, (va, vb))
    if tr.has_rules:  # one-way edges or speed limits: the planner of mpa.planners.rules
        from mpa.planners.rules import plan_with_rules

        return cast("GraphPlan", plan_with_rules(query))
    collecting = gc.isenabled()
    gc.disable()  # the search's tens of thousands of nodes are freed with it, before the collector is back
    try:
        return _plan_in(query, fs, s, gl)
    finally:
        if collecting:
            gc.enable()


def _limits(at_start: float, clearance: float, va: float, vb: float) -> list[float | None]:
    """The limits of the bounded searches (s), rising, then None (every segment): ``(1 + slack)`` times the bound at
    the start for each of :data:`LIMIT_SLACKS`, the first raised by :data:`LIMIT_STEP_ASIDE` clearances of travel
    tie-break, the second to at least :data:`LIMIT_WAIT` clearances of time (``clearance`` in metres, speeds in
    m/s); a limit not above the one before is left out."""
    out: list[float | None] = []
    last = -math.inf
    per_d = clearance / min(va, vb)  # s: the slower robot's time for one clearance
    for i, slack in enumerate(LIMIT_SLACKS):
        limit = at_start * (1.0 + slack)
        if i == 0:
            limit += LIMIT_STEP_ASIDE * TIE_BREAK * per_d
        elif i == 1:
            limit = max(limit, at_start + LIMIT_WAIT * per_d)
        if limit > last:
            out.append(limit)
            last = limit
    out.append(None)
    return out


def _plan_in(
    query: SearchQuery, fs: FreeSpace, s: tuple[Position, Position], gl: tuple[Position, Position]
) -> GraphPlan:
    """The motion of a checked query whose start and goal share a component of the free space: the shortcut, else
    the search (with the passing bound when it negotiates), the corners re-solved, the plan assembled.

    Called with Python's cyclic garbage collector paused (:func:`plan_graph`): the search makes tens of thousands of
    small objects and no reference cycles, and they are all freed (by their reference counts) when this returns, so
    the collector never traverses them; with the collector running, its first pass after the search traversed every
    one of them (about 8 % of the plan time of the searched queries measured in docs/performance.md)."""
    objective = query.objective
    va, vb = query.va, query.vb
    mesh = _mesh(fs)
    quick = _independent_motion(mesh, s, gl)
    if quick is not None:
        return _assemble(query, quick)
    classes = _corridor_classes(mesh, query) if CORRIDOR_CLASSES else None
    if classes is None:
        segs = _search(mesh, query, s, gl)
    else:  # the best of each class of motions, each class searched only below the best found so far
        segs, best = None, math.inf
        for at_start, to_goal in classes:
            if at_start > best:
                break
            got = _search(mesh, query, s, gl, to_goal, cap=None if segs is None else best)
            if got is not None and (c := _path_cost(got, objective, va, vb)) < best:
                segs, best = got, c
    if segs is None:  # pragma: no cover - no budget given
        raise PlanningError("search gave up")
    segs = _merge_same_polygon([x for x in segs if x[1] != x[2]])
    if objective == "fastest":  # one motion among the equally fast ones of the chain, continuous in the query
        from mpa.planners.corners import resolve_corners

        segs = [x for x in resolve_corners(fs, segs, (va, vb)) if x[1] != x[2]]
    return _assemble(query, segs)


def _path_cost(segs: list[list[object]], objective: str, va: float, vb: float) -> float:
    """The objective's cost of a path's segments ``[polygon, (s, t) from, (s, t) to]`` (s or m), summed in order."""
    cost = cost_function(objective, va, vb)
    return sum((cost(abs(q[0] - p[0]), abs(q[1] - p[1])) for _, p, q in segs), 0.0)  # type: ignore[index]


def _corridor_classes(mesh: _Mesh, query: SearchQuery) -> list[tuple[float, tuple[GoalDistance, GoalDistance]]] | None:
    """The classes of motions of :mod:`mpa.planners.graph.corridor` with their bounds at the start (the objective's
    cost of their goal distances), least first; None where they do not apply or gain nothing at the start (at most
    ``BOUND_GAIN`` of the robots' own bound)."""
    s, gl = query.start, query.goal
    pairs = approach_distances(mesh.g, s, gl, mesh.eps)
    if not pairs:
        return None
    cost = cost_function(query.objective, query.va, query.vb)
    geo = mesh.g
    own = cost(geo.distance_scalar(*s[0], *gl[0]), geo.distance_scalar(*s[1], *gl[1]))
    out = sorted(
        ((cost(ga.at(*s[0]), gb.at(*s[1])), i, (ga, gb)) for i, (ga, gb) in enumerate(pairs)), key=lambda x: x[:2]
    )
    if out[0][0] <= own * (1.0 + BOUND_GAIN):
        return None
    return [(h, p) for h, _, p in out]


def _search(
    mesh: _Mesh,
    query: SearchQuery,
    s: tuple[Position, Position],
    gl: tuple[Position, Position],
    to_goal: tuple[GoalDistance, GoalDistance] | None = None,
    cap: float | None = None,
) -> list[list[object]] | None:
    """The search's path (segments) for the query: first without the passing bound, then, on a long negotiation,
    with it when it knows more, within the limits of :func:`_limits`. ``to_goal``: a class's goal distances
    (:func:`_corridor_classes`); ``cap``: only a motion of cost up to it is of use (None when there is none)."""
    tr, objective = query.track, query.objective
    va, vb = query.va, query.vb
    fs = query.free_space
    after = PASSING_BOUND_AFTER if objective == "fastest" and separating_vertices(mesh, s, gl) else None
    if after is not None and tr.n_edges > PASSING_BOUND_EDGES:
        after = max(after, PASSING_BOUND_AFTER_LARGE)
    search = _new_search(mesh, query, to_goal=to_goal)
    segs = search.run(after, limit=cap)
    if segs is None and after is not None:  # a long negotiation: again with the bound that knows the robots must pass
        if to_goal is None:
            geo = tr.geometry
            ta, tb = geo.distance_scalar(*s[0], *gl[0]) / va, geo.distance_scalar(*s[1], *gl[1]) / vb
        else:
            ta, tb = to_goal[0].at(*s[0]) / va, to_goal[1].at(*s[1]) / vb
        own = max(ta, tb) + TIE_BREAK * (ta + tb)
        bound = passing_bound(mesh, s, gl, va, vb, floor=own * (1.0 + BOUND_GAIN))
        if bound is not None and LIMIT_SLACKS:  # first only the segments a near-optimal motion can use
            for limit in _limits(bound.at_start, fs.clearance_used, va, vb):
                last = cap is not None and (limit is None or limit >= cap)
                if last:
                    limit = cap
                bound.restrict(math.inf if limit is None else limit)
                search = _new_search(mesh, query, bound, to_goal)
                segs = search.run(limit=limit)
                if segs is not None or last:
                    break
        else:
            if bound is not None or not RESUME_WITHOUT_GAIN:
                search = _new_search(mesh, query, bound, to_goal)
            segs = search.run(limit=cap)  # with no gain from the bound: the same search resumed, not started again
    return segs
