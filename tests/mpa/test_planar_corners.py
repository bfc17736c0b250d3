"""A rectangle held on a corner of the drawing: the planner in the plane never moves the other body through its
turning disc while it stands there, goes round by a point inside the piece where it may (two-way edge), and under
one-way lanes the complete search reaches the corner's line only on the side of that disc it can (reproduced cases
that raised ``PlanningError`` before); the drawing's piece lookup; completeness against a grid search on random
layouts with coordinates, for discs and rectangles."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import mpa
from mpa import Disc, GraphTrack, InvalidInputError, Rectangle
from mpa.footprint import drawing_of
from tests.helpers.planar_checker import depth_many
from tests.mpa.test_footprints import DEPTH_TOL, _grid_connected, drawn_of, fp_tuple, grid_and_planner, random_layout

# (x of SE, the siding's two points, its length, one-way per edge, query, rectangle) from a seeded hunt
CASES = [
    (
        11.132501615199319,
        [[5.2718232056605085, 1.4751336532465338], [9.86067840953881, 1.4751336532465338]],
        8.484264584878987,
        [False, False, True, True],
        [(0, 0.0), (2, 3.0154245213786606), (3, 3.0609895331140904), (2, 7.713717854994598)],
        (2.5530710459569157, 1.1564833145024553),
    ),
    (
        8.834013416037088,
        [[4.973468717022749, 0.6620521876953991], [7.860544699014339, 0.6620521876953991]],
        5.241607308820079,
        [False, False, True, True],
        # A starts 0.3 m into 'main': at SW itself its body overlaps B in the orientation of 'west' and 'main'
        # (a start on a vertex takes every orientation there; tests/test_planar_vertex_start.py)
        [(1, 0.3), (0, 2.0583570525992587), (0, 0.31419821261844083), (0, 3.8365748444234673)],
        (2.1590832776246143, 0.4133165891054602),
    ),
]


def _layout(se: float, pts: list[list[float]], length: float, oneway: list[bool]) -> dict[str, Any]:
    names = ("west", "main", "siding", "east")
    ends = (("W", "SW"), ("SW", "SE"), ("SW", "SE"), ("SE", "E"))
    edges: list[dict[str, Any]] = [
        {"name": n, "from": a, "to": b, "oneway": o} for n, (a, b), o in zip(names, ends, oneway)
    ]
    edges[2].update(points=pts, length=length)
    return {"vertices": {"W": [0.0, 0.0], "SW": [4.0, 0.0], "SE": [se, 0.0], "E": [se + 4.0, 0.0]}, "edges": edges}


@pytest.mark.parametrize("case", range(len(CASES)))
def test_one_way_search_holds_a_rectangle_on_a_corner_only_where_it_may(case: int) -> None:
    se, pts, length, oneway, q, (lg, wd) = CASES[case]
    tr = GraphTrack.from_layout(_layout(se, pts, length, oneway))
    fp = Rectangle(lg, wd)
    for clearance in (0.0, 0.5):
        p = mpa.plan(tr, (q[0], q[1]), (q[2], q[3]), clearance=clearance, footprint=fp)
        times = p._times
        u = np.linspace(0.0, 1.0, 2001)
        wp = times / times[-1] if times[-1] > 0 else np.zeros(1)
        uu = np.clip(np.union1d(u, np.concatenate([wp - 1e-9, wp, wp + 1e-9])), 0.0, 1.0)
        (ea, oa), (eb, ob) = p.positions(uu)
        depth = depth_many(drawn_of(tr), fp_tuple(fp), fp_tuple(fp), ea, oa, eb, ob, along=True)
        # the motion, not its ends: a query's start or goal on a vertex is checked in every orientation there
        # (the checker cannot tell which edge the robot stands on), so the samples still at them are left out
        rows = np.stack([ea, oa, eb, ob], axis=1)
        moving = ~np.all(rows == rows[0], axis=1) & ~np.all(rows == rows[-1], axis=1) & (np.abs(uu - 0.5) < 0.5 - 1e-6)
        assert moving.sum() > 1000
        assert float(depth[moving].max()) <= DEPTH_TOL, (case, clearance, float(depth[moving].max()))
        for e, o in ((ea, oa), (eb, ob)):  # the one-way lanes driven forward only
            same = e[1:] == e[:-1]
            back = same & np.asarray(tr.oneway)[e[1:]] & (o[1:] < o[:-1] - 1e-9)
            assert not back.any(), (case, clearance)


def test_piece_at_is_the_piece_holding_the_offset_exactly() -> None:
    rng = np.random.default_rng(3)
    for seed in range(4):
        tr = GraphTrack.from_layout(random_layout(np.random.default_rng(seed)))
        d = drawing_of(tr)
        n = 3000
        p = rng.integers(0, len(d.piece_edge), n)
        e = d.piece_edge[p]
        o = rng.uniform(-0.1, 1.1, n) * tr.lengths[e]
        o[:1000] = d.piece_s0[p[:1000]]  # exactly on a piece's start, and one float either side
        o[1000:1500] = np.nextafter(d.piece_s0[p[1000:1500]], -np.inf)
        o[1500:2000] = np.nextafter(d.piece_s1[p[1500:2000]], np.inf)
        want = np.empty(n, dtype=np.int64)
        for k in range(n):
            pcs = d.edge_pieces[int(e[k])]
            i = int(np.searchsorted(d.piece_s0[pcs], o[k], side="right")) - 1
            want[k] = pcs[min(max(i, 0), len(pcs) - 1)]
        assert np.array_equal(d.piece_at(e, o), want)


@pytest.mark.parametrize("seed", [0, 1, 3])
def test_complete_against_grid_on_random_layouts(seed: int) -> None:
    """On random sidings (coordinates in metres), a disc and a rectangle each: whenever the grid search finds a
    motion (bodies kept a grid step plus 2 cm apart, a turning rectangle as the disc of its reach), the planner
    finds one; and it finds none only with a reason (NoMotionError)."""
    rng = np.random.default_rng(100 + seed)
    tr = GraphTrack.from_layout(random_layout(rng))
    found = 0
    for fp in (
        Disc(float(rng.uniform(0.25, 0.6))),
        Rectangle(float(rng.uniform(0.8, 2.5)), float(rng.uniform(0.3, 1.2))),
    ):
        for start, goal in ((("W", "E"), ("E", "W")), (("west:1", "east:3"), ("east:3", "west:1"))):
            try:
                grid, planned = grid_and_planner(tr, fp, start, goal)
            except InvalidInputError:  # the bodies overlap at start or goal: the grid has no such node either
                assert not _grid_connected(tr, fp, start, goal, 0.1)
                continue
            assert planned or not grid, (tr.to_dict(), fp, start, goal)
            found += grid
    assert found >= 1  # the grid found a motion at least once: the cross-check was exercised
