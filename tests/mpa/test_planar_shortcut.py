"""The independent motion in the planar model (:func:`mpa.planar.shortcut.independent_motion`): when it answers, its
plan is free (the independent checker), costs the robots' own bound and never more than the search's path; a
rectangle passing a corner where its sweep would reach the other body makes it decline; and the search it skips
still finds the least cost of the whole graph on the queries it would have answered."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

import mpa
from mpa import Disc, GraphTrack, Rectangle
from mpa.planar import plan as planar_plan
from mpa.planar import plan_planar, planar_free_space
from mpa.planar.shortcut import _covered, independent_motion
from tests.helpers.planar_checker import depth_many
from tests.mpa.test_footprints import DEPTH_TOL, drawn_of, fp_tuple, random_layout
from tests.mpa.test_planar_search import CASES, _queries
from tests.mpa.test_planar_search import test_regions_find_the_least_cost_of_the_whole_graph as _regions_vs_whole

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tracks"
SPEEDS = (1.0, 0.7)


def _no_shortcut(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(planar_plan, "independent_motion", lambda *a, **k: None)


def _cost(plan: Any, objective: str) -> float:
    return float(plan.makespan if objective == "fastest" else plan.length)


def _bound(tr: GraphTrack, start: Any, goal: Any, objective: str) -> float:
    da = tr.geometry.distance_scalar(*start[0], *goal[0])
    db = tr.geometry.distance_scalar(*start[1], *goal[1])
    return float(np.hypot(da, db)) if objective == "shortest" else max(da / SPEEDS[0], db / SPEEDS[1])


def _cases() -> list[tuple[GraphTrack, Disc | Rectangle, float]]:
    rng = np.random.default_rng(3)
    out: list[tuple[GraphTrack, Disc | Rectangle, float]] = [
        (GraphTrack.from_file(EXAMPLES / "passing_loop.json"), Rectangle(2.0, 1.0), 1.5),
        (GraphTrack.from_file(EXAMPLES / "rail_yard.json"), Rectangle(2.0, 0.8), 2.5),
        (GraphTrack.from_file(EXAMPLES / "y_junction.json"), Disc(0.45), 0.5),
    ]
    for fp in (Disc(0.3), Rectangle(1.2, 0.5)):
        out.append((GraphTrack.from_layout(random_layout(rng)), fp, 0.5))
    return out


@pytest.mark.parametrize("objective", ["fastest", "shortest"])
def test_independent_motion_is_free_at_the_bound_and_never_dearer_than_the_search(
    objective: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    answered = declined = 0
    u = np.linspace(0.0, 1.0, 600)
    for tr, fp, clearance in _cases():
        space = planar_free_space(tr, clearance, fp)
        dr = drawn_of(tr)
        for q in _queries(tr, 11, 25):
            start, goal = (q[0], q[1]), (q[2], q[3])
            try:
                plan = plan_planar(tr, start, goal, clearance, objective, SPEEDS, mpa.footprint.footprints(fp))
            except (mpa.InvalidInputError, mpa.NoMotionError):
                continue
            if independent_motion(space, start, goal) is None:
                declined += 1
                continue
            answered += 1
            bound = _bound(tr, start, goal, objective)
            got = _cost(plan, objective)
            # the fastest cost carries tie-break terms of 1e-6 of the summed times
            assert bound * (1 - 1e-9) <= got <= bound * (1 + 3e-6) + 1e-12, (tr.edge_names, fp, q, got, bound)
            with monkeypatch.context() as m:
                _no_shortcut(m)
                searched = plan_planar(tr, start, goal, clearance, objective, SPEEDS, mpa.footprint.footprints(fp))
            assert got <= _cost(searched, objective) * (1 + 1e-9) + 1e-12, (tr.edge_names, fp, q)
            (ea, oa), (eb, ob) = plan.positions(u)
            depth = depth_many(dr, fp_tuple(fp), fp_tuple(fp), ea, oa, eb, ob, along=True)
            i = int(np.argmax(depth))
            assert depth[i] <= DEPTH_TOL, (tr.to_dict(), q, fp, clearance, float(depth[i]), i)
            assert plan.min_distance() >= clearance - 1e-9
    print(f"independent motion: {answered} answered, {declined} left to the search")
    assert answered >= 20 and declined >= 10, (answered, declined)


def _corner_layout() -> GraphTrack:
    """An L-shaped track (a 90° polyline corner at (10, 0)) and a short straight track beside the corner's outside."""
    return GraphTrack.from_layout(
        {
            "vertices": {"P": [0, 0], "Q": [10, 10], "R": [10.6, -0.8], "S": [14.6, -0.8]},
            "edges": [
                {"name": "L", "from": "P", "to": "Q", "points": [[10, 0]], "length": 20.0},
                {"name": "M", "from": "R", "to": "S"},
            ],
        }
    )


def test_a_rectangle_turning_into_the_other_body_is_left_to_the_search() -> None:
    """Robot A (2 x 0.8 m, reach 1.077 m) turns at the corner; robot B (a disc of 0.1 m) is never hit by A's body in
    either orientation, but 0.1 m along its track it is 1.063 m from the corner: inside A's sweep. The straight
    motion passes the corner when B is there (declined, though every segment lies in the free pieces); 2 m along
    it is 1.55 m away (answered). The search's plan keeps the sweep clear and takes no longer than A's 10 m."""
    tr = _corner_layout()
    fps = (Rectangle(2.0, 0.8), Disc(0.1))
    space = planar_free_space(tr, 0.0, fps)
    blocked = ((0, 5.0), (1, 0.0)), ((0, 15.0), (1, 0.2))
    clear = ((0, 5.0), (1, 2.0)), ((0, 15.0), (1, 2.2))
    assert independent_motion(space, *clear) == [[(0, 1, 0), (5.0, 2.0), (15.0, 2.2)]]
    assert _covered(space, (0, 1, 0), (5.0, 0.0), (15.0, 0.2))
    assert independent_motion(space, *blocked) is None
    plan = mpa.plan(tr, *blocked, 0.0, footprint=fps)
    assert plan.makespan == pytest.approx(10.0, rel=1e-5)
    u = np.linspace(0.0, 1.0, 4001)
    (_, oa), (_, ob) = plan.positions(u)
    at_corner = np.argmin(np.abs(oa - 10.0))
    xy = np.array([10.6 + ob[at_corner], -0.8])
    assert np.hypot(*(xy - [10.0, 0.0])) >= np.hypot(1.0, 0.4) + 0.1 - 1e-3


@pytest.mark.parametrize(("path", "spec", "clearance"), CASES, ids=lambda x: getattr(x, "stem", None))
@pytest.mark.parametrize("objective", ["fastest", "shortest"])
def test_the_search_alone_finds_the_least_cost_of_the_whole_graph(
    path: Path, spec: str, clearance: float, objective: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """With the independent motion switched off, the search's regions give the whole graph's least cost also on
    the queries the independent motion answers (the comparison of ``tests/mpa/test_planar_search.py``)."""
    _no_shortcut(monkeypatch)
    _regions_vs_whole(path, spec, clearance, objective, monkeypatch)
