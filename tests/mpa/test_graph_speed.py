"""The graph planner's shortcuts are exact: the independent motion, the polygon index, the components, the distances.

Each shortcut is checked against the code it replaces on seeded random layouts and queries (failing cases printed).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import mpa.freespace as fsmod
import mpa.geometry as geomod
from mpa.errors import NoMotionError
from mpa.freespace import FreeSpace, free_space
from mpa.graph_track import GraphTrack
from mpa.planners import graph as gp
from mpa.planners.graph import shortcut as gp_shortcut
from mpa.planners.search_common import SearchQuery
from tests.helpers.graph_helpers import EXACT, random_layout, random_position

ROOT = Path(__file__).resolve().parents[2]
LAYOUTS = ["y_junction", "theta", "two_sidings", "passing_loop", "figure_eight", "warehouse"]


def _query(track: GraphTrack, fs: FreeSpace, start, goal) -> SearchQuery:  # type: ignore[no-untyped-def]
    """The query ``start`` -> ``goal`` for the fastest motion at unit speeds."""
    return SearchQuery(track, fs, start, goal, "fastest", (1.0, 1.0))


def _search_plan(track: GraphTrack, fs: FreeSpace, start, goal) -> gp.GraphPlan:  # type: ignore[no-untyped-def]
    """The plan of the full search (no shortcut), as ``plan_graph`` assembles it."""
    query = _query(track, fs, start, goal)
    segs = gp.AnyAngleSearch(gp._mesh(fs), query).run()
    assert segs is not None
    segs = gp._merge_same_polygon([x for x in segs if x[1] != x[2]])
    return gp._assemble(query, segs)


@pytest.mark.parametrize("name", LAYOUTS)
def test_the_independent_motion_is_the_search_s_answer(name: str) -> None:
    track = GraphTrack.from_json(ROOT / "examples" / "tracks" / f"{name}.json")
    rng = np.random.default_rng(25)
    med = float(np.median(track.lengths))
    used = searched = 0
    for q in range(8 if name == "warehouse" else 24):
        d = [0.05, 0.2, 0.5][q % 3] * med
        start = (random_position(track, rng), random_position(track, rng))
        goal = (random_position(track, rng), random_position(track, rng))
        if q % 4 == 3:  # a swap: the robots must negotiate, the search answers
            goal = (start[1], start[0])
        fs = free_space(track, d)
        if not (fs.is_free(*start) and fs.is_free(*goal)):
            continue
        try:
            plan = gp.plan_graph(track, start, goal, d)
        except NoMotionError:
            continue
        quick = gp._independent_motion(gp._mesh(fs), start, goal)
        took = quick is not None
        if took:  # kept the clearance cell by cell: so along the whole motion (an independent exact check)
            motion = gp._assemble(_query(track, fs, start, goal), quick)  # type: ignore[arg-type]
            assert motion.min_distance() >= fs._dmin - 1e-12, f"{name} D={d!r} start={start!r} goal={goal!r}"
        used += took
        searched += not took
        ref = _search_plan(track, fs, start, goal)
        case = f"{name} D={d!r} start={start!r} goal={goal!r}"
        assert math.isclose(plan.makespan, ref.makespan, rel_tol=1e-9, abs_tol=1e-12), case
        assert plan.min_distance() >= fs._dmin - 1e-12, case
        mesh = gp._mesh(fs)
        unique = all(gp._fastest_alone(mesh, p, q, 1e-9 * mesh.scale) is not None for p, q in zip(start, goal))
        if took and unique:  # the only motion of the bound's cost: the same routes as the search's
            assert plan.route_a.edges.tolist() == ref.route_a.edges.tolist(), case
            assert plan.route_b.edges.tolist() == ref.route_b.edges.tolist(), case
        if took:  # the bound at the start: no motion is faster (with tied routes, one of the optimal motions)
            lb = max(plan.route_a.length, plan.route_b.length)
            assert math.isclose(plan.makespan, lb, rel_tol=1e-12, abs_tol=1e-12), case
    assert used > 0 and searched > 0, (used, searched)


def test_a_robot_with_two_equally_short_routes_is_left_to_the_search() -> None:
    # a loop of 4 m through J: from the loop's middle both ways back to J are 2 m
    track = GraphTrack.from_layout({"edges": [["J", "J", 4.0], ["J", "x", 3.0]]})
    mesh = gp._mesh(free_space(track, 0.5))
    assert gp._fastest_alone(mesh, (0, 2.0), (1, 1.0), 1e-9) is None
    moves = gp._fastest_alone(mesh, (0, 1.5), (1, 1.0), 1e-9)
    assert moves == [(0, 1.5, 0.0), (1, 0.0, 1.0)]


def test_the_independent_motion_is_refused_when_the_robots_meet() -> None:
    # a swap on a Y junction: the straight motion drives the robots through each other, the search answers
    track = GraphTrack.from_layout({"edges": [["J", "a", 2.0], ["J", "b", 2.0], ["J", "c", 2.0]]})
    fs = free_space(track, 0.5)
    start, goal = ((0, 1.5), (1, 1.5)), ((1, 1.5), (0, 1.5))
    assert gp._independent_motion(gp._mesh(fs), start, goal) is None
    plan = gp.plan_graph(track, start, goal, 0.5)
    assert plan.min_distance() >= 0.5 - EXACT and plan.makespan > 3.0 + 1e-9


def test_polygon_index_and_components_match_a_dictionary_and_a_union_find(monkeypatch: pytest.MonkeyPatch) -> None:
    rng = np.random.default_rng(7)
    for _ in range(30):
        track = random_layout(rng)
        d = float(rng.uniform(0.0, 1.5))
        small = FreeSpace(track, d)
        monkeypatch.setattr(fsmod, "SMALL_POLYGONS", 0)  # label jumping in numpy
        middle = FreeSpace(track, d)
        monkeypatch.setattr(fsmod, "SCIPY_POLYGONS", 0)  # the scipy path
        monkeypatch.setattr(fsmod, "INDEX_DICT_POLYGONS", 0)  # the nested lists
        large = FreeSpace(track, d)
        monkeypatch.undo()
        assert small.polygon_ids == large.polygon_ids
        assert np.array_equal(small.polygon_component, large.polygon_component), (track.to_dict(), d)
        assert np.array_equal(small.polygon_component, middle.polygon_component), (track.to_dict(), d)
        ref = {pid: i for i, pid in enumerate(small.polygon_ids)}
        n_e = track.n_edges
        assert dict(small._index) == ref and isinstance(large._index, fsmod._PolygonIndex)
        index = large._index
        for e in range(n_e):
            for f in range(n_e):
                for k in (0, 1):
                    assert ((e, f, k) in index) == ((e, f, k) in ref)
                    assert index.get((e, f, k)) == ref.get((e, f, k))
        assert (n_e, 0, 0) not in index and (0, -1, 0) not in index
        assert len(index) == len(ref)
        # components: the swap's image of every component is a component
        for c in range(small.n_components):
            assert 0 <= small.swap_component(c) < small.n_components


def test_dijkstra_and_floyd_warshall_agree(monkeypatch: pytest.MonkeyPatch) -> None:
    rng = np.random.default_rng(11)
    for _ in range(40):
        track = random_layout(rng, n_edges=int(rng.integers(3, 12)))
        g = track.geometry
        floyd = geomod.vertex_distance_matrix(g.n_vertices, g.tails, g.heads, g.lengths)
        monkeypatch.setattr(geomod, "FLOYD_VERTICES", 0)
        dijkstra = geomod.vertex_distance_matrix(g.n_vertices, g.tails, g.heads, g.lengths)
        monkeypatch.undo()
        assert np.array_equal(np.isinf(floyd), np.isinf(dijkstra))
        fin = np.isfinite(floyd)
        assert np.allclose(floyd[fin], dijkstra[fin], rtol=0, atol=1e-12), track.to_dict()
    # an edge of length 0 joins two vertices into one point (both methods)
    monkeypatch.setattr(geomod, "FLOYD_VERTICES", 0)
    dv = geomod.vertex_distance_matrix(3, [0, 1, 2], [1, 2, 2], [0.0, 2.0, 1.0])
    assert dv.tolist() == [[0.0, 0.0, 2.0], [0.0, 0.0, 2.0], [2.0, 2.0, 0.0]]


def test_equally_short_routes_are_tried_until_a_pair_keeps_the_clearance() -> None:
    # a square loop of 2 m sides: each robot crosses to the opposite corner by either of two 4 m routes; the pair
    # going round the same way meets head-on, the pair going opposite ways stays 4 m apart
    track = GraphTrack.from_layout(
        {"edges": [["NW", "NE", 2.0], ["NE", "SE", 2.0], ["SE", "SW", 2.0], ["SW", "NW", 2.0]]}
    )
    fs = free_space(track, 1.0)
    mesh = gp._mesh(fs)
    start, goal = (track.position("NW"), track.position("SE")), (track.position("SE"), track.position("NW"))
    assert len(gp._shortest_routes(mesh, start[0], goal[0], 1e-9, 4)) == 2
    assert gp._fastest_alone(mesh, start[0], goal[0], 1e-9) is None
    assert gp._independent_motion(mesh, start, goal) is not None
    with pytest.MonkeyPatch.context() as mp:  # unique routes only: the tie is left to the search
        mp.setattr(gp_shortcut, "TIED_ROUTES", 1)  # where the shortcut reads it
        assert gp._independent_motion(mesh, start, goal) is None
    plan = gp.plan_graph(track, start, goal, 1.0)
    ref = _search_plan(track, fs, start, goal)
    assert math.isclose(plan.makespan, 4.0, rel_tol=1e-12) and math.isclose(ref.makespan, 4.0, rel_tol=1e-9)
    assert plan.min_distance() >= 1.0 - EXACT
    assert set(plan.route_a.edges.tolist()) != set(plan.route_b.edges.tolist())  # round the loop opposite ways


def test_tied_routes_shortcut_matches_the_search_on_random_layouts() -> None:
    """Every query the shortcut answers has the search's makespan and keeps the clearance (seeded random layouts,
    lattices with ties included)."""
    rng = np.random.default_rng(2025)
    warehouse = GraphTrack.from_json(ROOT / "examples" / "tracks" / "warehouse.json")
    tracks = [random_layout(rng) for _ in range(12)] + [warehouse, warehouse]
    took = tied = 0
    for track in tracks:
        d = float(rng.uniform(0.05, 1.0))
        fs = free_space(track, d)
        mesh = gp._mesh(fs)
        for _ in range(10):
            start = (random_position(track, rng), random_position(track, rng))
            goal = (random_position(track, rng), random_position(track, rng))
            if not (fs.is_free(*start) and fs.is_free(*goal)) or fs.component_of(*start) != fs.component_of(*goal):
                continue
            quick = gp._independent_motion(mesh, start, goal)
            if quick is None:
                continue
            took += 1
            tied += any(gp._fastest_alone(mesh, p, q, 1e-9 * mesh.scale) is None for p, q in zip(start, goal))
            case = f"{track.to_dict()} D={d!r} start={start!r} goal={goal!r}"
            plan = gp._assemble(_query(track, fs, start, goal), quick)  # type: ignore[arg-type]
            ref = _search_plan(track, fs, start, goal)
            assert math.isclose(plan.makespan, ref.makespan, rel_tol=1e-9, abs_tol=1e-12), case
            assert plan.min_distance() >= fs._dmin - 1e-12, case
    assert took >= 20 and tied >= 3, (took, tied)


def test_label_jumping_finds_the_union_finds_components() -> None:
    """Seeded random graphs (isolated nodes, loops, repeated edges, long chains): the same partition, each label the
    least node of its component."""
    rng = np.random.default_rng(11)
    for case in range(300):
        n = int(rng.integers(1, 400))
        m = int(rng.integers(0, 2 * n))
        rows = rng.integers(0, n, m)
        cols = rng.integers(0, n, m)
        if case % 5 == 0:  # a long chain in a random order: many rounds of hooking
            perm = rng.permutation(n)
            rows, cols = np.concatenate([rows, perm[:-1]]), np.concatenate([cols, perm[1:]])
        got = fsmod._label_components(n, rows.astype(np.int64), cols.astype(np.int64))
        ref = np.asarray(fsmod._union_find(n, rows.tolist(), cols.tolist()))
        least = {}
        for i, r in enumerate(ref.tolist()):
            least.setdefault(r, i)
        assert got.tolist() == [least[r] for r in ref.tolist()], (case, n, m)
