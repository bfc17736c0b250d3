"""One plan interface: the paper planner's ``Plan`` and the graph planner's ``GraphPlan`` are both ``MotionPlan``s
with the same names and meanings (property tests on the paper's tracks)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import mpa
from mpa import MotionPlan, MPAError, Plan
from mpa.planners.graph import GraphPlan
from tests.helpers.common import ALL_TRACKS, EXACT

#: Samples of the independent dense check of the minimum distance.
DENSE = 4001


def _queries() -> st.SearchStrategy[tuple[int, tuple[float, float, float, float], float]]:
    fractions = st.tuples(*(st.floats(0.0, 0.999, allow_nan=False) for _ in range(4)))
    return st.tuples(st.integers(0, len(ALL_TRACKS) - 1), fractions, st.sampled_from([0.0, 0.02, 0.1, 0.3]))


def _plans(k: int, fr: tuple[float, ...], share: float) -> tuple[mpa.Track, Plan, GraphPlan]:
    """The paper plan and the graph plan of one query (rejected by hypothesis when either refuses it)."""
    track = ALL_TRACKS[k]
    L = track.total_length
    start, goal = (fr[0] * L, fr[1] * L), (fr[2] * L, fr[3] * L)
    clearance = share * L / 2
    try:
        paper = mpa.plan(track, start, goal, clearance, planner="paper")
        graph = mpa.plan(track, start, goal, clearance, planner="graph")
    except MPAError:
        assume(False)
        raise
    assert isinstance(paper, Plan) and isinstance(graph, GraphPlan)
    return track, paper, graph


def _same_point(track: mpa.Track, p: tuple[int, float], q: tuple[int, float]) -> float:
    """Graph distance between two positions on the track's graph form, through the track's own coordinates."""
    a = track.from_graph_position(np.array([p[0]]), np.array([p[1]]))
    b = track.from_graph_position(np.array([q[0]]), np.array([q[1]]))
    return float(track.distance(a, b)[0])


def _check_interface(track: mpa.Track, plan: MotionPlan) -> None:
    assert isinstance(plan, MotionPlan)
    assert plan.layout is track.as_graph_track()
    w = plan.route_waypoints
    assert w.ndim == 2 and w.shape[1] == 2 and len(w) >= 1
    np.testing.assert_allclose(plan.path_s(0.0), w[0], atol=EXACT)
    np.testing.assert_allclose(plan.path_s(1.0), w[-1], atol=EXACT)
    # the routes' coordinates start and end at the query
    for r in (0, 1):
        route = plan.layout_routes[r]
        for sigma, want in ((w[0, r], plan.layout_start[r]), (w[-1, r], plan.layout_goal[r])):
            e, o = route.positions(sigma)
            assert _same_point(track, (int(e), float(o)), want) <= EXACT, (r, sigma, want, route)
    # sampling: one convention
    u, s = plan.sample_s(257)
    assert u.shape == (257,) and s.shape == (257, 2) and u[0] == 0.0 and u[-1] == 1.0
    np.testing.assert_array_equal(s, plan.path_s(u))
    # positions on the layout agree with the track's coordinates and its distance
    (ea, oa), (eb, ob) = plan.positions(u)
    pa, pb = track.from_graph_position(ea, oa), track.from_graph_position(eb, ob)
    np.testing.assert_allclose(
        plan.layout.geometry.distance(ea, oa, eb, ob), track.distance(pa, pb), atol=EXACT, rtol=0
    )
    assert isinstance(plan.word, tuple) and all(isinstance(x, str) for x in plan.word)
    # the exact minimum: above the clearance, and the minimum of a dense independent sample within its resolution
    dmin = plan.min_distance()
    assert dmin >= plan.clearance - EXACT, (dmin, plan.clearance)
    ud, sd = plan.sample_s(DENSE)
    (ea, oa), (eb, ob) = plan.positions(ud)
    dense = track.distance(track.from_graph_position(ea, oa), track.from_graph_position(eb, ob))
    step = float(np.max(np.abs(np.diff(sd, axis=0)).sum(axis=1)))
    assert dmin <= float(dense.min()) + EXACT, (dmin, float(dense.min()))
    assert float(dense.min()) <= dmin + step + EXACT, (dmin, float(dense.min()), step)


@settings(max_examples=250, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.filter_too_much])
@given(_queries())
def test_paper_and_graph_plans_are_motion_plans(query) -> None:  # type: ignore[no-untyped-def]
    track, paper, graph = _plans(*query)
    for plan in (paper, graph):
        _check_interface(track, plan)
    assert paper.domain in (1, 2, 3) and graph.domain is None
    # the same query: the same layout, start and goal
    assert paper.layout is graph.layout
    for r in (0, 1):
        assert _same_point(track, paper.layout_start[r], graph.layout_start[r]) <= EXACT
        assert _same_point(track, paper.layout_goal[r], graph.layout_goal[r]) <= EXACT


@settings(max_examples=250, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.filter_too_much])
@given(_queries())
def test_paper_plan_positions_are_its_track_coordinates(query) -> None:  # type: ignore[no-untyped-def]
    track, paper, _ = _plans(*query)
    u = np.linspace(0.0, 1.0, 513)
    (ea, oa), (eb, ob) = paper.positions(u)
    states = paper.path(u)
    gap_a = track.distance(track.from_graph_position(ea, oa), states[:, 0])
    gap_b = track.distance(track.from_graph_position(eb, ob), states[:, 1])
    assert float(max(gap_a.max(), gap_b.max())) <= EXACT
    # the exact minimum never exceeds the old sampled one, and is within its resolution
    sampled = paper.min_distance(20001)
    assert paper.min_distance() <= sampled + EXACT
    assert sampled - paper.min_distance() <= 2 * paper.length / 20000 + EXACT


def test_sample_s_rejects_bad_counts() -> None:
    track = ALL_TRACKS[0]
    for plan in (
        mpa.plan(track, (0.1, 0.6), (0.8, 0.3), planner="paper"),
        mpa.plan(track, (0.1, 0.6), (0.8, 0.3), planner="graph"),
    ):
        for n in (1, 0, 2.5, True, "3"):
            with pytest.raises(mpa.InvalidInputError, match="number of samples"):
                plan.sample_s(n)  # type: ignore[arg-type]
