"""What the layout searches share (:mod:`mpa.planners.search_common`) and the graph search's typed nodes.

The goal distance is checked against the exact geometry and a brute-force minimum, the scalar cost against the
array cost, on seeded random layouts (failing cases printed).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mpa.freespace import free_space
from mpa.planners.graph import mesh as gmesh
from mpa.planners.graph.search import GOAL, START, AnyAngleSearch, FaceEntry, IntervalNode, PointNode
from mpa.planners.search_common import (
    TIE_BREAK,
    TIE_BREAK_2,
    GoalDistance,
    SearchQuery,
    cell_speeds,
    cost_function,
    least_through_face,
    move_cost,
)
from tests.helpers.graph_helpers import random_face_case, random_layout, random_position


@pytest.mark.parametrize("seed", range(20))
def test_goal_distance_is_the_exact_graph_distance(seed: int) -> None:
    rng = np.random.default_rng(seed)
    tr = random_layout(rng)
    geo = tr.geometry
    goal = random_position(tr, rng)
    dist = GoalDistance(geo, goal)
    for _ in range(40):
        e, y = random_position(tr, rng)
        exact = geo.distance_scalar(e, y, goal[0], goal[1])
        assert dist.at(e, y) == pytest.approx(exact, abs=1e-12), (seed, goal, (e, y))
    for e in range(tr.n_edges):  # each vertex as an edge's tail and head
        for w, y in ((int(geo._t[e]), 0.0), (int(geo._h[e]), float(tr.lengths[e]))):
            exact = geo.distance_scalar(e, y, goal[0], goal[1])
            assert dist.vd[w] == pytest.approx(exact, abs=1e-12), (seed, goal, w)


GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0


def _through(case: tuple[Any, ...], y: Any) -> Any:
    """The straight move's cost from the root to ``y`` (a float or an array) plus the cost of the goal distances from
    there, written plainly with :func:`move_cost` (the face entry's bound is the least of it over the part)."""
    ax, x_seg, x_rest, r, _, _, cp, cm, on_edge, off, fastest, va, vb = case
    y = np.asarray(y, dtype=float)
    d = np.minimum(y + cp, cm - y)
    if on_edge:
        d = np.minimum(d, np.abs(y - off))
    objective = "fastest" if fastest else "shortest"
    seg, rest = np.full(y.shape, x_seg), np.full(y.shape, x_rest)
    if ax == 0:
        return move_cost(objective, seg, np.abs(y - r), va, vb) + move_cost(objective, rest, d, va, vb)
    return move_cost(objective, np.abs(y - r), seg, va, vb) + move_cost(objective, d, rest, va, vb)


def _through_at(case: tuple[Any, ...], y: float) -> float:
    """:func:`_through` at one point, in scalars (:func:`cost_function`)."""
    ax, x_seg, x_rest, r, _, _, cp, cm, on_edge, off, fastest, va, vb = case
    d = min(y + cp, cm - y, abs(y - off) if on_edge else math.inf)
    cost = cost_function("fastest" if fastest else "shortest", va, vb)
    return cost(x_seg, y - r) + cost(x_rest, d) if ax == 0 else cost(y - r, x_seg) + cost(d, x_rest)


@pytest.mark.parametrize("seed", range(10))
def test_least_through_a_face_is_the_least_over_the_part(seed: int) -> None:
    """On 3 000 seeded cases the face entry's bound is at most the cost through every one of 1 001 points of the part
    and through a refined minimum (golden section around the best of them): a lower bound; and within
    ``2e-12`` relative of that minimum: exact at the search's grid (``1e-12`` of the start's bound; the straightness
    term alone is ``1e-9``). It is at least the former bound, the cost of the robots' whole ways (subadditivity)."""
    rng = np.random.default_rng(9100 + seed)
    worst = 0.0
    for i in range(300):
        case = random_face_case(rng)
        ax, x_seg, x_rest, r, y0, y1, cp, cm, on_edge, off, fastest, va, vb = case
        got = least_through_face(*case)
        ys = np.concatenate([np.linspace(y0, y1, 1001), [min(max(r, y0), y1), min(max(off, y0), y1)]])
        vals = _through(case, ys)  # the 1 001 points, and the straight move's and the goal's kinks
        j = int(np.argmin(vals))
        best = float(vals[j])
        if y1 > y0 and math.isfinite(best) and j < 1001:
            lo, hi = float(ys[max(0, j - 1)]), float(ys[min(1000, j + 1)])
            for _ in range(90):  # golden section: the bracket shrinks to 1e-19 of itself
                m1, m2 = hi - GOLDEN * (hi - lo), lo + GOLDEN * (hi - lo)
                if _through_at(case, m1) <= _through_at(case, m2):
                    hi = m2
                else:
                    lo = m1
            best = min(best, _through_at(case, lo), _through_at(case, hi))
        ctx = (seed, i, case, got, best)
        assert got <= best, ctx  # a lower bound: never above a motion through the part
        if not math.isfinite(best):
            assert not math.isfinite(got), ctx
            continue
        assert got >= best * (1.0 - 2e-12) - 1e-15, ctx  # and the least, at the grid's resolution
        worst = max(worst, (best - got) / max(best, 1e-300))
        # the former bound: the cost of the two robots' whole ways through the part's nearest points
        dist = np.abs(ys - r) + np.minimum(np.minimum(ys + cp, cm - ys), np.abs(ys - off) if on_edge else math.inf)
        whole = float(dist.min())
        cost = cost_function("fastest" if fastest else "shortest", va, vb)
        former = cost(x_seg + x_rest, whole) if ax == 0 else cost(whole, x_seg + x_rest)
        assert got >= former * (1.0 - 1e-12), ctx
    print("largest relative gap to the refined minimum:", worst)


@settings(max_examples=200, deadline=None)
@given(
    ds=st.floats(-50.0, 50.0),
    dt=st.floats(-50.0, 50.0),
    va=st.floats(1e-3, 1e3),
    vb=st.floats(1e-3, 1e3),
    objective=st.sampled_from(["fastest", "shortest"]),
)
def test_scalar_cost_equals_the_array_cost(ds: float, dt: float, va: float, vb: float, objective: str) -> None:
    cost = cost_function(objective, va, vb)
    scalar = cost(ds, dt)
    array = move_cost(objective, np.array([abs(ds)]), np.array([abs(dt)]), va, vb)[0]
    assert scalar == move_cost(objective, abs(ds), abs(dt), va, vb)
    assert scalar == pytest.approx(float(array), rel=1e-15, abs=0.0)
    if objective == "fastest":
        ta, tb = abs(ds) / va, abs(dt) / vb
        assert max(ta, tb) <= scalar <= (max(ta, tb) + (TIE_BREAK + TIE_BREAK_2) * (ta + tb)) * (1.0 + 1e-15)
    else:
        assert scalar == math.hypot(ds, dt)


def test_cell_speeds_cap_the_robots_at_the_edges_limits() -> None:
    from mpa.graph_track import GraphTrack

    tr = GraphTrack.from_layout(
        {"edges": [{"name": "a", "from": "X", "to": "Y", "length": 1.0, "speed_limit": 0.4}, ["Y", "Z", 2.0]]}
    )
    spa, spb = cell_speeds(tr, 1.0, 0.3)
    assert spa == [0.4, 1.0]
    assert spb == [0.3, 0.3]


@pytest.mark.parametrize("seed", range(6))
def test_the_search_nodes_are_typed_and_read_back_to_the_path(seed: int) -> None:
    rng = np.random.default_rng(300 + seed)
    tr = random_layout(rng)
    fs = free_space(tr, 0.2)
    while True:
        s = (random_position(tr, rng), random_position(tr, rng))
        g = (random_position(tr, rng), random_position(tr, rng))
        if fs.is_free(*s) and fs.is_free(*g) and fs.component_of(*s) == fs.component_of(*g) is not None:
            break
    search = AnyAngleSearch(gmesh._mesh(fs), SearchQuery(tr, fs, s, g, "fastest", (1.0, 0.5)))
    segs = search.run()
    assert segs is not None
    kinds = {type(nd) for nd in search.nodes}
    assert kinds <= {PointNode, FaceEntry, IntervalNode}, kinds
    assert search.nodes[0].key == START  # type: ignore[union-attr]
    goals = [nd for nd in search.nodes if isinstance(nd, PointNode) and nd.key is GOAL]
    assert goals, (seed, s, g)
    # the path's cost is the goal's cost in the search, and the bound at the start never exceeds it
    cost = search.cost
    total = sum(cost(b[0] - a[0], b[1] - a[1]) for _, a, b in segs)
    assert total == pytest.approx(search.best[GOAL], rel=1e-9, abs=1e-12), (seed, s, g)
    start_pid, start_c = search.mesh.placements(*s)[0]
    assert search.lower_bound(start_pid, start_c) <= search.best[GOAL] * (1 + 1e-12) + 1e-12, (seed, s, g)


@pytest.mark.parametrize("seed", range(4))
def test_the_search_query_is_frozen_and_its_plan_carries_it(seed: int) -> None:
    """A :class:`SearchQuery` cannot change after it is built (frozen, slotted), and the plan assembled from the
    search of a query carries its track, start, goal, objective, speeds and the free space's clearances."""
    from mpa.planners.graph.assemble import _assemble

    rng = np.random.default_rng(900 + seed)
    tr = random_layout(rng)
    fs = free_space(tr, 0.15)
    while True:
        s = (random_position(tr, rng), random_position(tr, rng))
        g = (random_position(tr, rng), random_position(tr, rng))
        if fs.is_free(*s) and fs.is_free(*g) and fs.component_of(*s) == fs.component_of(*g) is not None:
            break
    speeds = (float(rng.uniform(0.3, 2.0)), float(rng.uniform(0.3, 2.0)))
    objective = "fastest" if seed % 2 else "shortest"
    query = SearchQuery(tr, fs, s, g, objective, speeds)
    assert (query.va, query.vb) == speeds
    assert not hasattr(query, "__dict__")
    with pytest.raises(dataclasses.FrozenInstanceError):
        query.start = g  # type: ignore[misc]
    segs = AnyAngleSearch(gmesh._mesh(fs), query).run()
    assert segs is not None
    plan = _assemble(query, segs)
    got = (plan.track, plan.start, plan.goal, plan.objective, plan.speeds, plan.clearance, plan.clearance_used)
    assert got == (tr, s, g, objective, speeds, fs.clearance, fs.clearance_used), (seed, s, g)
    assert plan.min_distance() >= fs.clearance_used - 1e-9, (seed, s, g)
