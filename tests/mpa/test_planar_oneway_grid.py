"""Completeness of the one-way search with rectangles against a directed grid search in the plane model.

The grid: both robots' positions sampled every 0.2 m along every edge (vertices shared), one robot one step at a
time, forward only on one-way edges, the rectangles kept ``step + 0.02`` m apart (a rectangle on a corner where the
drawing turns counts as the disc of its half-diagonal), so every grid path is a motion of the model. A seeded hunt
over siding layouts (``tests/mpa/test_planar_corners.py``'s family, random one-way edges) found the planner answering
"no motion" where the grid moved: a shared segment of two pieces across the siding's polyline corner was read by the
one-way search as three single points, because its middle point was the mean of the meeting points (1.3e-8 m off the
ends' middle), so a robot held still on a one-way edge could not cross there.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import mpa
from mpa import Disc, GraphTrack, NoMotionError, Rectangle
from tests.helpers.planar_grid import grid_nodes, grid_queries, plane_free
from tests.mpa.test_footprints import fp_tuple, plan_depth
from tests.mpa.test_planar_corners import _layout
from tests.mpa.test_planar_rules import _monotone


def _siding(rng: np.random.Generator) -> tuple[GraphTrack, Rectangle]:
    se = float(rng.uniform(8, 12))
    h = float(rng.uniform(0.5, 1.6))
    x0, x1 = 4.0 + float(rng.uniform(0.8, 1.5)), se - float(rng.uniform(0.8, 1.5))
    length = math.hypot(x0 - 4.0, h) + (x1 - x0) + math.hypot(se - x1, h)
    oneway = [bool(rng.random() < 0.5) for _ in range(4)]
    tr = GraphTrack.from_layout(_layout(se, [[x0, h], [x1, h]], length, oneway))
    return tr, Rectangle(float(rng.uniform(0.8, 2.6)), float(rng.uniform(0.2, min(1.2, 0.95 * h + 0.3))))


# seed 232 of the hunt: every edge one-way; A drives west -> siding -> east past B, which creeps forward on 'main'
HUNTED = (
    {
        "vertices": {
            "W": [0.0, 0.0],
            "SW": [4.0, 0.0],
            "SE": [10.318222152674185, 0.0],
            "E": [14.318222152674185, 0.0],
        },
        "edges": [
            {"name": "west", "from": "W", "to": "SW", "length": 4.0, "oneway": True},
            {"name": "main", "from": "SW", "to": "SE", "length": 6.318222152674185, "oneway": True},
            {
                "name": "siding",
                "from": "SW",
                "to": "SE",
                "length": 7.437415285351091,
                "points": [[5.185941834571988, 1.2347706914048548], [9.329400713836819, 1.2347706914048548]],
                "oneway": True,
            },
            {"name": "east", "from": "SE", "to": "E", "length": 4.0, "oneway": True},
        ],
    },
    Rectangle(1.7375781619853732, 0.3992147358439024),
    ((0, 3.4), (1, 3.5539999608792288)),
    ((3, 0.6), (1, 3.9488888454213655)),
)


@pytest.mark.parametrize("fp", [HUNTED[1], Disc(0.3)])
def test_hunted_one_way_query_crosses_the_polyline_corner(fp: Disc | Rectangle) -> None:
    layout, _, start, goal = HUNTED
    tr = GraphTrack.from_layout(layout)
    plan = mpa.plan(tr, start, goal, 0.0, footprint=fp)
    _monotone(plan)
    assert plan_depth(tr, plan, fp_tuple(fp), fp_tuple(fp), 600) <= 1e-6
    # B held still on its one-way lane while A passes the siding's corner
    mpa.plan(tr, start, ((2, 2.5), start[1]), 0.0, footprint=fp)


@pytest.mark.parametrize("seed", [79, 183, 232])
def test_one_way_rectangles_complete_against_a_directed_grid(seed: int) -> None:
    """Whenever the directed grid finds a motion the planner finds one (and it keeps the rule and the bodies apart);
    both answers counted so that the check was exercised."""
    rng = np.random.default_rng(seed)
    tr, fp = _siding(rng)
    nodes, nxt = grid_nodes(tr, 0.2, oneway=True)
    free = plane_free(tr, nodes, fp, 0.2)
    met = refused = 0
    for grid, start, goal in grid_queries(rng, nodes, nxt, free, 15):
        try:
            plan = mpa.plan(tr, start, goal, 0.0, footprint=fp)
        except NoMotionError as exc:
            assert not grid, f"seed {seed}: the grid moves, the planner says {exc}; {tr.to_dict()} {fp} {start} {goal}"
            refused += 1
            continue
        met += grid
        _monotone(plan)
        assert plan_depth(tr, plan, fp_tuple(fp), fp_tuple(fp), 300) <= 1e-6, (seed, start, goal)
    assert met >= 1 and refused >= 1, (seed, met, refused)
