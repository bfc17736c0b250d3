"""The first region of the planar search (:meth:`mpa.planar.search._Moves.near`): exactly the nodes whose bounds
from the start and to the goal sum to at most ``ub``, although it computes those bounds only in the pieces whose
offset ranges could hold such a node."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from mpa.graph_track import GraphTrack
from mpa.planar import planar_free_space
from mpa.planar.search import _cell_speeds
from mpa.planners.search_common import SearchQuery
from tests.mpa.test_planar_search import _queries

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tracks"


@pytest.mark.parametrize(
    ("name", "spec", "clearance"),
    [
        ("circle", "0.05", 0.2),
        ("figure_eight", "0.5", 1.0),
        ("two_sidings", "1.5x0.8", 1.0),
        ("y_junction", "0.45", 0.5),
    ],
)
@pytest.mark.parametrize("objective", ["fastest", "shortest"])
def test_near_is_the_region_of_every_node(name: str, spec: str, clearance: float, objective: str) -> None:
    tr = GraphTrack.from_file(EXAMPLES / f"{name}.json")
    space = planar_free_space(tr, clearance, spec)
    speeds = (1.0, 0.7)
    G = space.search_graph(objective, *_cell_speeds(tr, *speeds))
    sizes = []
    for q in _queries(tr, 5, 15):
        query = SearchQuery(tr, space.base, (q[0], q[1]), (q[2], q[3]), objective, speeds)
        through = G.lower(query, query.start) + G.lower(query, query.goal)
        least = float(np.min(through))
        for factor in (1.0, 1.001, 1.2, 2.0, 10.0):
            ub = least * factor
            region = G.near(query, ub)
            want = through <= ub
            bad = np.flatnonzero(region != want)
            assert not len(bad), (name, q, factor, bad[:5], through[bad[:5]], ub)
            sizes.append(int(region.sum()))
    assert min(sizes) >= 1 and max(sizes) > 10 * min(sizes), sizes
