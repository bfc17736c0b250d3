"""The goals' order in a corridor (``mpa.planners.graph.corridor``): the corridors, the classes' goal distances, and
the planner that searches per class.

The lemma behind it: robots in a corridor keep their order, so the last robot to come in is the one whose goal is
nearer the end it comes through. Checked here on the motions themselves: the optimal motion of every query the classes
apply to (found by the search without them) is in one of the classes, and that class's bound is below the motion's
remaining cost at every one of its waypoints; the planner with the classes finds motions of the same cost.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import mpa.planners.graph.query as graph_query
from mpa.freespace import FreeSpace, free_space
from mpa.graph_track import GraphTrack, Position
from mpa.planners.graph import plan_graph
from mpa.planners.graph.corridor import Corridor, approach_distances, corridor_of
from mpa.planners.graph.mesh import _mesh
from mpa.planners.graph.search import AnyAngleSearch
from mpa.planners.search_common import GoalDistance, SearchQuery, cost_function
from tests.helpers.graph_helpers import random_layout

ROOT = Path(__file__).resolve().parents[2]
TOL = 1e-9


def _track(edges: list[list[object]]) -> GraphTrack:
    return GraphTrack.from_layout({"edges": edges})


def _example(name: str) -> GraphTrack:
    return GraphTrack.from_layout(json.loads((ROOT / "examples" / "tracks" / f"{name}.json").read_text()))


def _subdivided(rng: np.random.Generator) -> GraphTrack:
    """A random layout (:func:`random_layout`) with some edges cut in two or three: vertices of degree 2, corridors."""
    base = random_layout(rng)
    names = {i: n for n, i in base._vertex_index.items()}
    edges: list[list[object]] = []
    for k in range(base.n_edges):
        t, h = names[int(base.tails[k])], names[int(base.heads[k])]
        length = float(base.lengths[k])
        parts = int(rng.integers(1, 4))
        chain = [t] + [f"m{k}_{i}" for i in range(1, parts)] + [h]
        cuts = np.sort(rng.uniform(0.2, 0.8, parts - 1)) if parts > 1 else np.array([])
        pts = np.concatenate([[0.0], cuts, [1.0]]) * length
        for i in range(parts):
            edges.append([chain[i], chain[i + 1], round(float(pts[i + 1] - pts[i]), 4) + 0.05])
    return _track(edges)


def _at(c: Corridor, x: float) -> Position:
    """The position at coordinate ``x`` of the corridor."""
    i = max(j for j in range(len(c.edges)) if c.starts[j] <= x)
    i = min(i, len(c.edges) - 1)
    y = x - c.starts[i]
    length = (c.starts[i + 1] if i + 1 < len(c.edges) else c.length) - c.starts[i]
    y = min(max(y, 0.0), length)
    return c.edges[i], (y if c.dirs[i] > 0 else length - y)


def _outside_at(track: GraphTrack, c: Corridor, w: int, rng: np.random.Generator) -> Position | None:
    """A random position on an edge at vertex ``w`` that is not the corridor's, None when there is none."""
    g = track.geometry
    es = [e for e in range(track.n_edges) if e not in c.edges and w in (g.tails[e], g.heads[e])]
    if not es:
        return None
    e = es[int(rng.integers(len(es)))]
    return e, float(rng.uniform(0, track.lengths[e]))


def _corridor_queries(
    track: GraphTrack, fs: FreeSpace, rng: np.random.Generator, n: int
) -> list[tuple[tuple[Position, Position], tuple[Position, Position], Corridor]]:
    """Up to ``n`` free queries whose goals lie in one corridor and to which the classes apply."""
    g = track.geometry
    out = []
    for _ in range(40 * n):
        if len(out) >= n:
            break
        c = corridor_of(g, int(rng.integers(track.n_edges)))
        if c is None or not (c.u_port or c.v_port):
            continue
        gl = (_at(c, float(rng.uniform(0, c.length))), _at(c, float(rng.uniform(0, c.length))))
        if rng.random() < 0.7 and c.u_port and c.v_port:  # each robot beyond the other's end: they must pass
            near = [_outside_at(track, c, w, rng) for w in (c.v, c.u)]
            if near[0] is None or near[1] is None:
                continue
            xu = [c.coordinate(gl[0], 1e-9), c.coordinate(gl[1], 1e-9)]
            if xu[0] is None or xu[1] is None:
                continue
            s = (near[0], near[1]) if xu[0] < xu[1] else (near[1], near[0])
        else:
            if rng.random() < 0.3:  # one robot starts inside
                s0 = _at(c, float(rng.uniform(0, c.length)))
            else:
                e = int(rng.integers(track.n_edges))
                s0 = (e, float(rng.uniform(0, track.lengths[e])))
            e = int(rng.integers(track.n_edges))
            s = (s0, (e, float(rng.uniform(0, track.lengths[e])))) if rng.random() < 0.5 else (
                (e, float(rng.uniform(0, track.lengths[e]))), s0)  # fmt: skip
        if not (fs.is_free(*s) and fs.is_free(*gl)):
            continue
        comp = fs.component_of(*s)
        if comp is None or comp != fs.component_of(*gl):
            continue
        if approach_distances(g, s, gl, _mesh(fs).eps) is None:
            continue
        c = corridor_of(g, gl[0][0])  # oriented as approach_distances orients it
        assert c is not None
        out.append((s, gl, c))
    return out


# ------------------------------------------------------------------------------------------------ corridors
def test_corridors_are_the_chains_of_degree_two_vertices_with_their_ports() -> None:
    # J has degree 3 (x, p, q), K degree 3 (q, r, s); the chain J-p-a-b-K is the corridor (p, a, b reversed in part)
    t = _track(
        [["x", "J", 1.0], ["a", "J", 2.0], ["a", "b", 1.5], ["K", "b", 0.5], ["J", "K", 4.0], ["K", "r", 1.0],
         ["r", "dead", 2.0], ["L", "L", 3.0], ["L", "K", 1.0]]
    )  # fmt: skip
    g = t.geometry
    names = {i: n for n, i in t._vertex_index.items()}
    c = corridor_of(g, 2)  # a-b
    assert c is not None
    assert set(c.edges) == {1, 2, 3} and math.isclose(c.length, 4.0)
    assert {names[c.u], names[c.v]} == {"J", "K"} and c.u_port and c.v_port
    # coordinates run from u to v through the edges in order, whatever their own directions
    for e, d, s0 in zip(c.edges, c.dirs, c.starts):
        first = g.tails[e] if d > 0 else g.heads[e]
        assert math.isclose(g.dv[c.u, first], s0) or c.u == c.v, (e, d, s0)
    # a spur to a dead end: one port
    c = corridor_of(g, 6)
    assert c is not None and set(c.edges) == {5, 6} and (c.u_port != c.v_port)
    # a loop at L (L has degree 3: its loop's two ends and L-K)
    c = corridor_of(g, 7)
    assert c is not None and c.edges == (7,) and c.u == c.v and c.u_port and c.v_port
    # the incidences the corridors are walked on: a loop is listed once and counts two ends
    at, deg = g.edges_at
    ix = t._vertex_index
    assert at[ix["L"]] == [7, 8] and deg[ix["L"]] == 3 and deg[ix["K"]] == 4 and deg[ix["dead"]] == 1
    assert sum(deg) == 2 * t.n_edges
    # a circle of degree-2 vertices has no ends
    assert corridor_of(_track([["a", "b", 1.0], ["b", "a", 2.0]]).geometry, 0) is None
    assert corridor_of(_track([["a", "a", 2.0]]).geometry, 0) is None


def test_positions_on_a_port_are_outside_and_coordinates_run_along() -> None:
    t = _track([["x", "J", 1.0], ["y", "J", 1.0], ["J", "a", 2.0], ["b", "a", 1.0], ["b", "K", 1.0],
                ["K", "z", 1.0], ["K", "w", 1.0]])  # fmt: skip
    c = corridor_of(t.geometry, 3)
    assert c is not None and set(c.edges) == {2, 3, 4}
    jk = {i: n for n, i in t._vertex_index.items()}[c.u] == "J"
    x_on = c.coordinate((3, 0.25), 1e-9)  # edge b->a, 0.25 from b
    assert x_on is not None and math.isclose(x_on, 2.75 if jk else 1.25)
    assert c.coordinate((2, 0.0), 1e-9) is None  # on J
    assert c.coordinate((4, 1.0), 1e-9) is None  # on K
    assert c.coordinate((0, 0.5), 1e-9) is None  # another edge


# ---------------------------------------------------------------------------------------- the goal distances
@pytest.mark.parametrize("seed", range(4))
def test_a_class_distance_is_the_way_in_through_its_end(seed: int) -> None:
    """Outside the corridor ``d(p, end) + x``; inside also the corridor's own way; never below the graph distance."""
    rng = np.random.default_rng(800 + seed)
    checks = 0
    for _ in range(60):
        track = _subdivided(rng)
        g = track.geometry
        fs = free_space(track, float(rng.uniform(0.02, 0.3)))
        for s, gl, c in _corridor_queries(track, fs, rng, 2):
            pairs = approach_distances(g, s, gl, 1e-9)
            assert pairs
            xg = [c.coordinate(gl[0], 1e-9), c.coordinate(gl[1], 1e-9)]
            assert xg[0] is not None and xg[1] is not None
            first = 0 if xg[0] < xg[1] else 1
            k = 0
            for end, port, robot, x in ((c.u, c.u_port, first, xg[first]), (c.v, c.v_port, 1 - first, None)):
                if not port:
                    continue
                dist = pairs[k][robot]
                other = pairs[k][1 - robot]
                k += 1
                xr = x if x is not None else c.length - xg[robot]  # type: ignore[operator]
                own = GoalDistance(g, gl[robot])
                for _ in range(20):
                    e = int(rng.integers(track.n_edges))
                    y = float(rng.uniform(0, track.lengths[e]))
                    to_end = min(y + g.dv[g.tails[e], end], track.lengths[e] - y + g.dv[g.heads[e], end])
                    want = to_end + xr
                    xp = c.coordinate((e, y), 1e-9)
                    if xp is not None:
                        want = min(want, abs(xp - xg[robot]))  # type: ignore[operator]
                    got = dist.at(e, y)
                    assert math.isclose(got, want, rel_tol=1e-12, abs_tol=1e-12), (e, y, got, want, c)
                    assert got >= own.at(e, y) - 1e-12, (e, y)
                    assert other.at(e, y) == GoalDistance(g, gl[1 - robot]).at(e, y)
                    checks += 1
            assert k == len(pairs)
    assert checks >= 400, checks


def test_the_classes_do_not_apply_where_the_lemma_says_nothing() -> None:
    t = _track([["x", "J", 1.0], ["y", "J", 1.0], ["J", "a", 2.0], ["b", "a", 2.0], ["b", "K", 2.0],
                ["K", "z", 1.0], ["K", "w", 1.0]])  # fmt: skip
    g = t.geometry
    c = corridor_of(g, 3)
    assert c is not None
    goals = (_at(c, 2.0), _at(c, 4.5))  # A nearer u, B nearer v
    outside = ((0, 0.5), (6, 0.5))
    assert approach_distances(g, outside, goals, 1e-9) is not None
    assert approach_distances(g, (_at(c, 1.0), _at(c, 3.0)), goals, 1e-9) is None  # inside, in the goals' order
    assert approach_distances(g, (_at(c, 3.0), _at(c, 1.0)), goals, 1e-9) is not None  # inside, the other order
    assert approach_distances(g, outside, ((0, 0.5), goals[1]), 1e-9) is None  # one goal outside
    assert approach_distances(g, outside, ((2, 0.0), goals[1]), 1e-9) is None  # one goal on a port
    assert approach_distances(g, outside, ((2, 1e-12), goals[1]), 1e-9) is None  # within the tolerance of it


# --------------------------------------------------------------------------------------------- the planner
def _class_of(segs: list[list[object]], c: Corridor) -> tuple[int, str] | None:
    """Which robot comes into the corridor last in the motion ``segs`` and through which end (``"u"`` or ``"v"``),
    sampled finely along each segment; None when both are inside all along."""
    xa: list[float | None] = []
    xb: list[float | None] = []
    for pid, p, q in segs:
        for lam in np.linspace(0.0, 1.0, 200):
            xa.append(c.coordinate((pid[0], p[0] + lam * (q[0] - p[0])), 1e-9))  # type: ignore[index]
            xb.append(c.coordinate((pid[1], p[1] + lam * (q[1] - p[1])), 1e-9))  # type: ignore[index]
    out = [k for k in range(len(xa)) if xa[k] is None or xb[k] is None]
    if not out:
        return None
    k = out[-1] + 1
    assert k < len(xa), "the goals are inside the corridor"
    robot = 0 if xa[k - 1] is None else 1
    x = (xa if robot == 0 else xb)[k]
    assert x is not None
    return robot, ("u" if x < c.length / 2 else "v")


def _travel(plan: object, speeds: tuple[float, float]) -> float:
    """The robots' summed travel times along a plan's waypoints (s)."""
    w = np.diff(plan.waypoints, axis=0)  # type: ignore[attr-defined]
    return float(np.sum(np.abs(w[:, 0]) / speeds[0] + np.abs(w[:, 1]) / speeds[1]))


def _remaining_costs(segs: list[list[object]], cost: object) -> list[float]:
    c = [cost(abs(q[0] - p[0]), abs(q[1] - p[1])) for _, p, q in segs]  # type: ignore[index, operator]
    out = [0.0]
    for x in reversed(c):
        out.append(out[-1] + x)
    return out[::-1]


@pytest.mark.parametrize("source", ["random", "examples"])
def test_the_best_class_is_the_optimum_and_each_motion_is_in_a_class_below_its_bound(
    source: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    rng = np.random.default_rng(42 if source == "random" else 43)
    tracks: list[tuple[GraphTrack, float]] = []
    if source == "random":
        for _ in range(18):
            tracks.append((_subdivided(rng), float(rng.uniform(0.02, 0.4))))
    else:
        for name in ("y_junction", "passing_loop", "two_sidings", "theta", "rail_yard", "warehouse", "lollipop"):
            track = _example(name)
            med = float(np.median(track.lengths))
            tracks += [(track, 0.1 * med), (track, 0.4 * med)]
    cases = gained = 0
    for track, d in tracks:
        fs = free_space(track, d)
        mesh = _mesh(fs)
        for s, gl, c in _corridor_queries(track, fs, rng, 4):
            speeds = (1.0, 1.0) if rng.random() < 0.6 else (float(rng.uniform(0.4, 1.5)), float(rng.uniform(0.4, 1.5)))
            for objective in ("fastest", "shortest"):
                query = SearchQuery(track, fs, s, gl, objective, speeds)
                cost = cost_function(objective, *speeds)
                plain = AnyAngleSearch(mesh, query).run()
                assert plain is not None
                opt = graph_query._path_cost(plain, objective, *speeds)
                # every class's best is no dearer than its bound's promise, and the least of them is the optimum
                pairs = approach_distances(track.geometry, s, gl, mesh.eps)
                assert pairs
                found = []
                for pair in pairs:
                    segs = AnyAngleSearch(mesh, query, to_goal=pair).run()
                    assert segs is not None
                    found.append(graph_query._path_cost(segs, objective, *speeds))
                assert min(found) <= opt * (1 + 1e-11) + 1e-12, (s, gl, d, objective, found, opt)
                assert min(found) >= opt * (1 - 1e-11) - 1e-12, (s, gl, d, objective, found, opt)
                # the optimal motion's class, and its bound along it
                plan = plan_graph(track, s, gl, d, objective, speeds)
                which = _class_of(plain, c)
                assert which is not None, (s, gl)
                robot, end = which
                xg = [c.coordinate(gl[0], 1e-9), c.coordinate(gl[1], 1e-9)]
                first = 0 if xg[0] < xg[1] else 1  # type: ignore[operator]
                assert (robot, end) in ((first, "u"), (1 - first, "v")), (s, gl, which)
                k = 0 if end == "u" or not c.u_port else 1
                ga, gb = pairs[k]
                rest = _remaining_costs(plain, cost)
                for i, (pid, p, _) in enumerate(plain):
                    pa, pb = (pid[0], p[0]), (pid[1], p[1])  # type: ignore[index]
                    h = cost(ga.at(*pa), gb.at(*pb))
                    assert h <= rest[i] * (1 + 1e-11) + 1e-12, (s, gl, d, objective, i, h, rest[i])
                cases += 1
                # the planner with the classes: the same cost as without
                if graph_query._corridor_classes(mesh, query) is not None:
                    gained += 1
                    monkeypatch.setattr(graph_query, "CORRIDOR_CLASSES", False)
                    without = plan_graph(track, s, gl, d, objective, speeds)
                    monkeypatch.setattr(graph_query, "CORRIDOR_CLASSES", True)
                    if objective == "shortest":
                        assert math.isclose(plan.length, without.length, rel_tol=1e-10, abs_tol=1e-12), (s, gl, d)
                    else:  # equally fast and equally long travels (the corners re-solved may differ)
                        assert math.isclose(plan.makespan, without.makespan, rel_tol=1e-10, abs_tol=1e-12), (s, gl, d)
                        assert math.isclose(_travel(plan, speeds), _travel(without, speeds), rel_tol=1e-10), (s, gl, d)
                    assert plan.min_distance() >= fs.clearance_used - 1e-9
    assert cases >= 60, cases
    assert gained >= 10, gained
