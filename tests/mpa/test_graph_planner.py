"""The complete graph planner: completeness against a grid search, oracles, plans on the paper's lollipop."""

from __future__ import annotations

import heapq
import itertools
import math
from collections import deque
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mpa import Lollipop
from mpa.errors import InvalidInputError, NoMotionError
from mpa.freespace import free_space
from mpa.graph_track import GraphTrack
from mpa.planners.graph import OBJECTIVES, plan_graph
from tests.helpers.graph_helpers import random_free_query, random_layout

COUNTS = {"cases": 0, "grid_found": 0, "planned": 0}


def _grid(track: GraphTrack, h: float):
    """Grid positions: canonical keys, their (edge, offset) names and robot-level neighbours."""
    names: dict[object, list[tuple[int, float]]] = {}
    nbrs: dict[object, set[object]] = {}

    def key(e: int, i: int, n: int) -> object:
        if i == 0:
            return ("v", int(track.tails[e]))
        if i == n:
            return ("v", int(track.heads[e]))
        return ("p", e, i)

    for e in range(track.n_edges):
        n = max(1, int(np.ceil(track.lengths[e] / h)))
        length = float(track.lengths[e])

        def off(i: int, n: int = n, length: float = length) -> float:
            return length if i == n else length * i / n

        for i in range(n + 1):
            k = key(e, i, n)
            names.setdefault(k, []).append((e, off(i)))
            for j in (i - 1, i + 1):
                if 0 <= j <= n:
                    nbrs.setdefault(k, set()).add((key(e, j, n), e, off(i), off(j)))
    return names, nbrs


def _grid_steps(g: Any, names: dict, nbrs: dict, ka: object, kb: object, D: float) -> Iterator[tuple]:
    """The grid's moves from ``(ka, kb)``: one robot or both one step (``nbrs``), each kept when its straight segment
    keeps >= D (exact, ``g.segment_min_scalar``). Yields ``(na, nb, Δs_a, Δs_b)``: the new keys and each robot's
    travel along its edge (m)."""
    moves_a = [(ka, names[ka][0][0], names[ka][0][1], names[ka][0][1]), *sorted(nbrs[ka], key=str)]
    moves_b = [(kb, names[kb][0][0], names[kb][0][1], names[kb][0][1]), *sorted(nbrs[kb], key=str)]
    for (na, ea, sa0, sa1), (nb, eb, sb0, sb1) in itertools.product(moves_a, moves_b):
        if na == ka and nb == kb:
            continue
        if na == ka:  # A stays: use a name of its position on any edge
            ea, sa0 = names[ka][0]
            sa1 = sa0
        if nb == kb:
            eb, sb0 = names[kb][0]
            sb1 = sb0
        if g.segment_min_scalar(ea, eb, sa0, sb0, sa1, sb1) < D:
            continue
        yield na, nb, sa1 - sa0, sb1 - sb0


def _grid_reachable(track: GraphTrack, D: float, h: float, start: tuple[object, object]) -> set[tuple[object, object]]:
    """BFS over grid states at least D + h apart with 8-neighbour moves whose straight segment keeps >= D."""
    g = track.geometry
    names, nbrs = _grid(track, h)

    def dist(ka: object, kb: object) -> float:
        (ea, sa), (eb, sb) = names[ka][0], names[kb][0]
        return g.distance_scalar(ea, sa, eb, sb)

    seen = {start}
    queue = deque([start])
    while queue:
        ka, kb = queue.popleft()
        for na, nb, _, _ in _grid_steps(g, names, nbrs, ka, kb, D):
            if (na, nb) in seen or dist(na, nb) < D + h:
                continue
            seen.add((na, nb))
            queue.append((na, nb))
    return seen


@pytest.mark.parametrize("seed", range(60))
def test_complete_whenever_a_grid_search_finds_a_path(seed: int) -> None:
    rng = np.random.default_rng(5000 + seed)
    track = random_layout(rng)
    D = float(rng.choice([0.0, rng.uniform(0.05, 0.8)]))
    h = 0.1
    names, _ = _grid(track, h)
    keys = sorted(names, key=str)
    g = track.geometry

    def d(ka: object, kb: object) -> float:
        (ea, sa), (eb, sb) = names[ka][0], names[kb][0]
        return g.distance_scalar(ea, sa, eb, sb)

    pairs = [(a, b) for a, b in itertools.product(keys, keys) if d(a, b) >= D + h]
    if not pairs:
        pytest.skip("no grid state at this clearance")
    start = pairs[int(rng.integers(len(pairs)))]
    reach = _grid_reachable(track, D, h, start)
    goals = [pairs[int(i)] for i in rng.integers(0, len(pairs), 8)] + [(start[1], start[0])]
    for goal in goals:
        COUNTS["cases"] += 1
        s = (names[start[0]][0], names[start[1]][0])
        t = (names[goal[0]][0], names[goal[1]][0])
        try:
            p = plan_graph(track, s, t, D)
        except NoMotionError as exc:
            assert goal not in reach, (seed, D, s, t, str(exc), track.to_dict())
            continue
        COUNTS["planned"] += 1
        COUNTS["grid_found"] += goal in reach
        assert p.min_distance() >= p.clearance_used - 1e-9, (seed, D, s, t, p.min_distance())
        ra, rb = p.route_a.positions(p.waypoints[-1, 0]), p.route_b.positions(p.waypoints[-1, 1])
        assert g.distance_scalar(int(ra[0]), float(ra[1]), t[0][0], t[0][1]) < 1e-9
        assert g.distance_scalar(int(rb[0]), float(rb[1]), t[1][0], t[1][1]) < 1e-9


def _grid_cost(track: GraphTrack, D: float, h: float, start: tuple, goal: tuple, cost: Callable) -> float | None:
    """Minimum ``sum cost(Δs, Δt)`` over grid paths (8-neighbour moves keeping >= D), None if unreachable."""
    g = track.geometry
    names, nbrs = _grid(track, h)
    best = {start: 0.0}
    heap = [(0.0, 0, start)]
    n = 1
    while heap:
        c, _, (ka, kb) = heapq.heappop(heap)
        if (ka, kb) == goal:
            return c
        if c > best[(ka, kb)]:
            continue
        for na, nb, da, db in _grid_steps(g, names, nbrs, ka, kb, D):
            nc = c + cost(da, db)
            if nc < best.get((na, nb), np.inf):
                best[(na, nb)] = nc
                heapq.heappush(heap, (nc, n, (na, nb)))
                n += 1
    return None


@pytest.mark.parametrize("seed", range(12))
def test_fastest_is_never_slower_than_the_grid_optimum(seed: int) -> None:
    """Every grid path is a free path, so the planner's time must not exceed the grid's best time."""
    rng = np.random.default_rng(9000 + seed)
    track = random_layout(rng)
    D = float(rng.uniform(0.05, 0.5))
    va, vb = (1.0, 1.0) if seed % 2 else (1.0, 0.6)
    h = 0.05
    names, _ = _grid(track, h)
    keys = sorted(names, key=str)
    for _ in range(3):
        a, b, c, d = (keys[int(i)] for i in rng.integers(0, len(keys), 4))
        s, t = (names[a][0], names[b][0]), (names[c][0], names[d][0])
        try:
            p = plan_graph(track, s, t, D, objective="fastest", speeds=(va, vb))
        except (NoMotionError, InvalidInputError):
            continue
        gt = _grid_cost(track, D, h, (a, b), (c, d), lambda x, y: max(abs(x) / va, abs(y) / vb))
        if gt is None:
            continue
        COUNTS["optimality"] = COUNTS.get("optimality", 0) + 1
        assert p.makespan <= gt + 1e-9, (seed, D, s, t, p.makespan, gt)
        q = plan_graph(track, s, t, D, objective="shortest", speeds=(va, vb))
        gl = _grid_cost(track, D, h, (a, b), (c, d), math.hypot)
        assert gl is not None and q.length <= gl + 1e-9, (seed, D, s, t, q.length, gl)
        assert q.min_distance() >= q.clearance_used - 1e-9


@pytest.mark.parametrize(("b1", "b2", "b3"), [(1.0, 2.0, 3.0), (0.6, 1.0, 1.0)])
def test_y_junction_plans_swap_iff_clearance_fits(b1: float, b2: float, b3: float) -> None:
    y = GraphTrack.from_layout({"edges": [["J", "x1", b1], ["J", "x2", b2], ["J", "x3", b3]]})
    for D in (0.5 * b1, b1):
        p = plan_graph(y, ("x2", "x3"), ("x3", "x2"), D)
        assert p.min_distance() >= D - 1e-9
        assert any(e == 0 for e in [*p.route_a.edges.tolist(), *p.route_b.edges.tolist()])
    with pytest.raises(NoMotionError, match=r"only siding.*up to about 0?\.?\d"):
        plan_graph(y, ("x2", "x3"), ("x3", "x2"), b1 * 1.01)


def test_path_like_layout_names_the_reason() -> None:
    path = GraphTrack.from_layout({"edges": [["a", "b", 1.0], ["b", "c", 2.0]]})
    with pytest.raises(NoMotionError, match="order cannot change on a path-like layout"):
        plan_graph(path, ("e0:0.2", "e1:1.5"), ("e1:1.5", "e0:0.2"), 0.1)
    p = plan_graph(path, ("e0:0.2", "e1:1.5"), ("e1:0.5", "c"), 0.1)
    assert p.min_distance() >= 0.1 - 1e-9


def test_cycle_loop_reason_and_plan() -> None:
    cyc = GraphTrack.from_layout({"edges": [["P", "P", 2.0]]})
    p = plan_graph(cyc, ("e0:0", "e0:1"), ("e0:1", "e0:0"), 1.0)
    assert p.min_distance() >= 1.0 - 1e-9
    ring_with_stub = GraphTrack.from_layout({"edges": [["P", "P", 2.0], ["P", "S", 3.0]]})
    with pytest.raises(NoMotionError, match="only loop"):
        plan_graph(ring_with_stub, ("S", "e1:1"), ("e1:1", "S"), 1.2)


def test_paper_lollipop_swaps_and_fastest_is_fast() -> None:
    lol = Lollipop(1.0, 1.0)
    t = lol.as_graph_track()
    rng = np.random.default_rng(3)
    for _ in range(30):
        p0 = rng.uniform(0, 2, 2)
        if lol.distance_scalar(*p0) < 0.1:
            continue
        ea, sa = lol.to_graph_position(p0)
        start = ((int(ea[0]), float(sa[0])), (int(ea[1]), float(sa[1])))
        goal = (start[1], start[0])
        fast = plan_graph(t, start, goal, 0.05, objective="fastest", speeds=(1.0, 1.0))
        short = plan_graph(t, start, goal, 0.05, objective="shortest", speeds=(1.0, 1.0))
        assert fast.min_distance() >= 0.05 - 1e-9 and short.min_distance() >= 0.05 - 1e-9
        # lower bound: each robot must travel at least the graph distance between its start and goal
        lb = lol.distance_scalar(*p0)
        assert fast.makespan >= lb - 1e-9
        assert fast.makespan <= short.makespan + 1e-6
        assert short.length <= fast.length + 1e-6


def test_plan_api_shapes_and_dict() -> None:
    t = Lollipop(1.0, 1.0).as_graph_track()
    p = plan_graph(t, ("stick:0.2", "loop:0.5"), ("loop:0.5", "stick:0.2"), 0.05)
    u, s = p.sample(11)
    assert u.shape == (11,) and s.shape == (11, 2)
    np.testing.assert_allclose(p.path_s(0.0), p.waypoints[0])
    np.testing.assert_allclose(p.path_s(1.0), p.waypoints[-1])
    (ea, sa), (eb, sb) = p.positions(np.array([0.0, 1.0]))
    assert (int(ea[0]), float(sa[0])) == (0, 0.2)
    assert p.corner_offsets.shape == (p.n_corners, 2) and len(p.corner_cells) == p.n_corners
    d = p.to_dict()
    assert d["start"] == ["stick:0.2", "loop:0.5"] and d["routes"]["a"][0]["edge"] == "stick"
    # dense sampling never beats the exact minimum
    _, r = p.sample(2001)
    (ea, sa), (eb, sb) = p.route_a.positions(r[:, 0]), p.route_b.positions(r[:, 1])
    assert p.min_distance() <= float(np.min(t.geometry.distance(ea, sa, eb, sb))) + 1e-12


def test_standing_still_is_a_plan() -> None:
    t = Lollipop(1.0, 1.0).as_graph_track()
    p = plan_graph(t, ("stick:0.2", "loop:0.5"), ("stick:0.2", "loop:0.5"), 0.05)
    assert p.makespan == 0.0 and p.n_corners == 1


@settings(max_examples=40, deadline=None)
@given(
    st.integers(0, 2**31 - 1),
    st.floats(0.0, 0.8),
    st.sampled_from(OBJECTIVES),
    st.floats(0.2, 3.0),
    st.floats(0.2, 3.0),
)
def test_random_graphs_plans_keep_clearance_and_reach_the_goal(
    seed: int, D: float, objective: str, va: float, vb: float
) -> None:
    rng = np.random.default_rng(seed)
    track = random_layout(rng)
    fs = free_space(track, D)
    g = track.geometry
    query = random_free_query(track, fs, rng)
    if query is None:
        return
    s, t = query
    try:
        p = plan_graph(track, s, t, D, objective=objective, speeds=(va, vb))
    except NoMotionError:
        assert fs.component_of(*s) != fs.component_of(*t)
        return
    assert p.min_distance() >= p.clearance_used - 1e-9
    da = g.distance_scalar(s[0][0], s[0][1], t[0][0], t[0][1])
    db = g.distance_scalar(s[1][0], s[1][1], t[1][0], t[1][1])
    assert p.makespan >= max(da / va, db / vb) - 1e-9
    assert p.length >= math.hypot(da, db) - 1e-9
    (ea, sa), (eb, sb) = p.positions(1.0)
    assert g.distance_scalar(int(ea), float(sa), t[0][0], t[0][1]) <= 1e-9
    assert g.distance_scalar(int(eb), float(sb), t[1][0], t[1][1]) <= 1e-9


@pytest.mark.parametrize(("stick", "loop"), [(1.0, 1.0), (2.0, 3.0), (100.0, 300.0)])
def test_fastest_on_lollipops_is_never_slower_than_the_paper_plan(stick: float, loop: float) -> None:
    """The paper's plan is a free path, so its speed-limited time bounds ours (both as max(|Δs|, |Δt|) at v = 1)."""
    import mpa

    lol = Lollipop(stick, loop)
    t = lol.as_graph_track()
    D = 0.05 * min(stick, loop)
    rng = np.random.default_rng(11)
    checked = 0
    for k in range(40):
        st_ = rng.uniform(0, stick + loop, 2)
        go = st_[::-1].copy() if k % 2 else rng.uniform(0, stick + loop, 2)
        if min(lol.distance_scalar(*st_), lol.distance_scalar(*go)) < D + 1e-6:
            continue
        paper = mpa.plan(lol, tuple(st_), tuple(go), clearance=D)
        paper_time = float(np.sum(np.max(np.abs(np.diff(paper.waypoints_s, axis=0)), axis=1)))
        ea, oa = lol.to_graph_position(st_)
        eb, ob = lol.to_graph_position(go)
        ours = plan_graph(
            t,
            ((int(ea[0]), float(oa[0])), (int(ea[1]), float(oa[1]))),
            ((int(eb[0]), float(ob[0])), (int(eb[1]), float(ob[1]))),
            D,
        )
        assert ours.makespan <= paper_time * (1 + 1e-9) + 1e-12, (stick, loop, st_, go, ours.makespan, paper_time)
        assert ours.min_distance() >= ours.clearance_used - 1e-9
        checked += 1
    assert checked >= 20


def test_completeness_cases_were_exercised() -> None:
    """The seeded completeness cases above ran, planned and met the grid (skipped when they were deselected)."""
    if COUNTS["cases"] == 0:
        pytest.skip("the completeness tests did not run in this session (deselected)")
    assert COUNTS["planned"] > 0 and COUNTS["grid_found"] > 0, COUNTS


def test_disconnected_layout_and_isolated_vertex() -> None:
    two = GraphTrack.from_layout({"edges": [["a", "b", 2.0], ["c", "c", 3.0]]})
    with pytest.raises(NoMotionError, match="robot A's goal is on another part of the track"):
        plan_graph(two, ("e0:0.5", "e1:1"), ("e1:0.5", "e1:2"), 0.1)
    p = plan_graph(two, ("e0:0.5", "e1:1"), ("e0:1.5", "e1:2.5"), 0.1)
    assert p.min_distance() == float("inf") or p.min_distance() >= 0.1
    iso = GraphTrack.from_layout({"vertices": {"a": [0, 0], "b": [1, 0], "z": [5, 5]}, "edges": [["a", "b"]]})
    with pytest.raises(InvalidInputError, match="vertex 'z' has no edge"):
        iso.position("z")
