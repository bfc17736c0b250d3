"""One-way lanes and speed limits: the complete planner under the rules, the setpoints, the gate, the command line."""

from __future__ import annotations

import csv
import json
import math
from collections import deque
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

import mpa
from mpa.graph_track import GraphTrack
from trajopt import generate_trajectory
from trajopt.cli.main import main
from trajopt.verify.gate import lane_rule_failures

H = 0.25  # grid step of the oracle (m)


def _y(oneway_short: bool = False, limit_right: float | None = None) -> GraphTrack:
    """A Y junction: branches short (1 m), left (2 m), right (3 m) from J."""
    edges: list[dict[str, Any]] = [
        {"name": "b_short", "from": "J", "to": "short", "length": 1.0},
        {"name": "b_left", "from": "left", "to": "J", "length": 2.0},
        {"name": "b_right", "from": "J", "to": "right", "length": 3.0},
    ]
    if oneway_short:
        edges[0]["oneway"] = True
    if limit_right is not None:
        edges[2]["speed_limit"] = limit_right
    verts = {"J": [0.0, 0.0], "short": [0.0, 1.0], "left": [-2.0, 0.0], "right": [3.0, 0.0]}
    return GraphTrack.from_layout({"vertices": verts, "edges": edges})


def _segments_monotone(plan: Any) -> None:
    tr = plan.track
    for (e, f, _), o in zip(plan.segment_cells, plan.segment_offsets):
        if tr.oneway[e]:
            assert o[1, 0] >= o[0, 0], (tr.edge_names[e], o)
        if tr.oneway[f]:
            assert o[1, 1] >= o[0, 1], (tr.edge_names[f], o)
    for route in (plan.route_a, plan.route_b):
        for e, d, lo, hi in zip(route.edges, route.dirs, route.breaks[:-1], route.breaks[1:]):
            if hi > lo and tr.oneway[int(e)]:
                assert d == 1, (tr.edge_names[int(e)], route)


# ----------------------------------------------------------------------------------------------- planner
def test_one_way_branch_forbids_the_swap_and_says_so() -> None:
    two_way = mpa.plan(_y(), ("left", "right"), ("right", "left"), 0.5)
    assert two_way.min_distance() >= 0.5 - 1e-9
    with pytest.raises(mpa.NoMotionError, match=r"one-way lanes forbid it.*b_short"):
        mpa.plan(_y(oneway_short=True), ("left", "right"), ("right", "left"), 0.5)
    # a clearance the siding cannot hold is not the one-way rule's fault
    with pytest.raises(mpa.NoMotionError, match="does not fit") as info:
        mpa.plan(_y(oneway_short=True), ("left", "right"), ("right", "left"), 1.5)
    assert "one-way" not in str(info.value)


def test_one_way_plans_are_monotone_and_robots_may_stand_on_one_way_edges() -> None:
    tr = _y(oneway_short=True)
    # A into the one-way branch and stays; B passes J behind it
    plan = mpa.plan(tr, ("left", "right"), ("b_short:0.8", "left"), 0.5)
    _segments_monotone(plan)
    assert plan.min_distance() >= 0.5 - 1e-9
    assert plan.lower_bound is not None and plan.makespan >= plan.lower_bound - 1e-9


def test_fastest_takes_the_longer_lane_without_a_limit() -> None:
    """Two lanes from P to Q: 2 m limited to 0.25 m/s (8 s), or 4 m at full speed (4 s)."""
    layout = {
        "edges": [
            {"name": "slow", "from": "P", "to": "Q", "length": 2.0, "speed_limit": 0.25},
            {"name": "fast", "from": "P", "to": "Q", "length": 4.0},
            {"name": "park", "from": "Q", "to": "R", "length": 6.0},
        ]
    }
    tr = GraphTrack.from_layout(layout)
    fastest = mpa.plan(tr, ("P", "R"), ("Q", "R"), 0.5)
    assert [tr.edge_names[int(e)] for e in fastest.route_a.edges] == ["fast"]
    assert fastest.makespan == pytest.approx(4.0, rel=1e-5)
    # the optimum without the limit is 2 s; A alone under the limit needs 4 s: the plan is optimal
    assert fastest.lower_bound == pytest.approx(4.0, rel=1e-5)
    shortest = mpa.plan(tr, ("P", "R"), ("Q", "R"), 0.5, objective="shortest")
    assert [tr.edge_names[int(e)] for e in shortest.route_a.edges] == ["slow"]
    assert shortest.makespan == pytest.approx(8.0, rel=1e-9)  # its time at the limit


def test_single_robot_time_under_limits_and_one_way_lanes() -> None:
    """A ring P -> Q -> R -> P with one one-way lane and a slow lane, and a spur."""
    from mpa.planners.rules import single_robot_time

    layout = {
        "edges": [
            {"name": "pq", "from": "P", "to": "Q", "length": 2.0, "oneway": True},
            {"name": "qr", "from": "Q", "to": "R", "length": 3.0, "speed_limit": 0.5},
            {"name": "rp", "from": "R", "to": "P", "length": 4.0},
            {"name": "spur", "from": "R", "to": "S", "length": 1.0},
        ]
    }
    tr = GraphTrack.from_layout(layout)
    pos = tr.position
    # forward on the one-way lane: 1.5 m at 1 m/s
    assert single_robot_time(tr, pos("pq:0.25"), pos("pq:1.75"), 1.0) == pytest.approx(1.5)
    # backwards on it is forbidden: round the ring, 0.25 + 6 (qr at 0.5 m/s) + 4 + 0.25... the other way
    # pq:1.75 -> Q (0.25 s) -> R (6 s) -> P (4 s) -> pq:0.25 (0.25 s)
    assert single_robot_time(tr, pos("pq:1.75"), pos("pq:0.25"), 1.0) == pytest.approx(10.5)
    # Q to S: through R via qr (6 s + 1 s) beats Q -> ... (pq is one-way, no way back to P from Q)
    assert single_robot_time(tr, pos("Q"), pos("S"), 1.0) == pytest.approx(7.0)
    # a slower robot: the limit binds no more than its own speed
    assert single_robot_time(tr, pos("Q"), pos("S"), 0.25) == pytest.approx(16.0)
    # on a two-way lane either way
    assert single_robot_time(tr, pos("rp:3"), pos("rp:1"), 1.0) == pytest.approx(2.0)
    # a bound: every plan on this layout takes at least each robot's own time
    plan = mpa.plan(tr, ("Q", "S"), ("S", "P"), 0.3)
    own = max(single_robot_time(tr, pos("Q"), pos("S"), 1.0), single_robot_time(tr, pos("S"), pos("P"), 1.0))
    assert plan.lower_bound is not None and plan.lower_bound >= own - 1e-12
    assert plan.makespan >= plan.lower_bound - 1e-9, (plan.makespan, plan.lower_bound)


def _random_track(rng: np.random.Generator) -> GraphTrack:
    n_v = int(rng.integers(3, 6))
    edges: list[dict[str, Any]] = []
    for v in range(1, n_v):  # a random tree, then extra edges (cycles, parallel edges)
        edges.append({"from": f"v{int(rng.integers(0, v))}", "to": f"v{v}"})
    for _ in range(int(rng.integers(0, 3))):
        u, w = rng.integers(0, n_v, size=2)
        if u != w:
            edges.append({"from": f"v{u}", "to": f"v{w}"})
    for i, e in enumerate(edges):
        e["name"] = f"e{i}"
        e["length"] = H * int(rng.integers(3, 12))
        if rng.random() < 0.4:
            e["oneway"] = True
        if rng.random() < 0.3:
            e["speed_limit"] = float(rng.choice([0.3, 0.6]))
    return GraphTrack.from_layout({"edges": edges})


def _grid_points(tr: GraphTrack) -> list[tuple[int, float]]:
    pts = [tr.vertex_position(v) for v in range(tr.graph.n_vertices)]
    for e in range(tr.n_edges):
        n = round(tr.lengths[e] / H)
        pts += [(e, k * H) for k in range(1, n)]
    return pts


def _grid_reachable(tr: GraphTrack, start: Any, goal: Any, clearance: float) -> bool:
    """A search on the grid of step H: one robot moves one step at a time (forward only on one-way edges), the
    robots at least ``clearance + H`` apart at every grid configuration (so every grid path is a motion with the
    clearance: the distance is 1-Lipschitz in each robot's position)."""
    pts = _grid_points(tr)
    geo = tr.geometry

    def key(p: tuple[int, float]) -> tuple[int, float]:
        w = tr.vertex_at(p[0], p[1])
        return tr.vertex_position(w) if w is not None else (p[0], round(p[1] / H) * H)

    nbrs: dict[tuple[int, float], list[tuple[int, float]]] = {key(p): [] for p in pts}
    for e in range(tr.n_edges):
        n = round(tr.lengths[e] / H)
        for k in range(n):
            a, b = key((e, k * H)), key((e, (k + 1) * H if k + 1 < n else float(tr.lengths[e])))
            nbrs[a].append(b)
            if not tr.oneway[e]:
                nbrs[b].append(a)

    def free(a: tuple[int, float], b: tuple[int, float]) -> bool:
        return geo.distance_scalar(a[0], a[1], b[0], b[1]) >= clearance + H - 1e-9

    s, g = (key(start[0]), key(start[1])), (key(goal[0]), key(goal[1]))
    seen = {s}
    todo = deque([s])
    while todo:
        a, b = todo.popleft()
        if (a, b) == g:
            return True
        for nxt in [(x, b) for x in nbrs[a]] + [(a, y) for y in nbrs[b]]:
            if nxt not in seen and free(*nxt):
                seen.add(nxt)
                todo.append(nxt)
    return False


@settings(max_examples=80, deadline=None, derandomize=True)
@given(st.integers(0, 2**31 - 1))
def test_complete_under_one_way_rules_against_a_grid_oracle(seed: int) -> None:
    rng = np.random.default_rng(seed)
    tr = _random_track(rng)
    clearance = float(rng.choice([0.25, 0.5, 0.75]))
    pts = _grid_points(tr)
    geo = tr.geometry
    for _ in range(4):
        i, j, k, m = rng.integers(0, len(pts), size=4)
        start, goal = (pts[i], pts[j]), (pts[k], pts[m])
        if min(geo.distance_scalar(*start[0], *start[1]), geo.distance_scalar(*goal[0], *goal[1])) < clearance + H:
            continue
        reachable = _grid_reachable(tr, start, goal, clearance)
        try:
            plan = mpa.plan(tr, start, goal, clearance)
        except mpa.NoMotionError as exc:
            assert not reachable, f"seed {seed}: the grid finds a motion, the planner says {exc}; {tr.to_dict()}"
            continue
        _segments_monotone(plan)
        assert plan.min_distance() >= clearance - 1e-9, f"seed {seed}"
        if tr.has_rules:
            assert plan.lower_bound is not None and plan.makespan >= plan.lower_bound * (1 - 1e-9), f"seed {seed}"


# ----------------------------------------------------------------------------------------- trajectories
def test_trajectory_keeps_speed_limits_and_one_way_on_every_row() -> None:
    tr = _y(oneway_short=True, limit_right=0.3)
    traj = generate_trajectory(tr, ("left", "right"), ("b_right:1", "short"), clearance=0.5)
    assert traj.verification["ok"]
    rows = list(csv.DictReader(traj.csv_text().splitlines()))
    names = list(tr.edge_names)
    for r in rows:
        for robot in "ab":
            e = names.index(r[f"{robot}_edge"])
            v = abs(float(r[f"{robot}_v"]))
            limit = tr.speed_limits[e]
            assert limit is None or v <= limit * (1 + 1e-6), r
            if tr.oneway[e]:
                assert int(r[f"{robot}_dir"]) >= 0, r


def test_gate_rejects_driving_a_one_way_edge_backwards_and_speeding() -> None:
    two_way = _y()
    traj = generate_trajectory(two_way, ("left", "right"), ("right", "left"), clearance=0.5)
    routes = traj.plan.route_a, traj.plan.route_b
    s = np.stack([traj.s[:, 0], traj.s[:, 1]], axis=1) if traj.s.ndim == 2 else traj.s
    v = traj.v
    assert lane_rule_failures(routes, s, v, two_way.oneway, two_way.speed_limits) == []
    # B drives b_right from right to J: against the edge; A drives b_left backwards from J? no: from left to J
    fails = lane_rule_failures(routes, s, v, (False, False, True), None)
    assert len(fails) == 1 and "robot B drives the one-way edge 2 against its direction" in fails[0]
    fails = lane_rule_failures(routes, s, v, None, (None, 0.2, None))
    assert fails and all("over its speed limit 0.2" in f for f in fails)


# ------------------------------------------------------------------------------------------ command line
def _building_with_y(oneway: bool) -> dict[str, Any]:
    params = {"graph_idx": [2, 0], "speed_limit": [3, 0.0], "orientation": [1, ""]}
    vertices = [[0, 0, 0, "J"], [0, 1, 0, "short"], [-2, 0, 0, "left"], [3, 0, 0, "right"]]
    lanes = [
        [0, 1, {**params, "bidirectional": [4, not oneway]}],
        [2, 0, {**params, "bidirectional": [4, True]}],
        [0, 3, {**params, "bidirectional": [4, True]}],
    ]
    return {
        "name": "y",
        "coordinate_system": "cartesian_meters",
        "levels": {"L1": {"vertices": vertices, "lanes": lanes}},
    }


@pytest.mark.parametrize("oneway", [True, False])
def test_cli_swap_on_a_hand_made_map_one_way_exit_3_two_way_verified(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], oneway: bool
) -> None:
    path = tmp_path / "y.building.yaml"
    path.write_text(yaml.safe_dump(_building_with_y(oneway)), encoding="utf-8")
    out = tmp_path / "out"
    query = ["--start", "left", "right", "--goal", "right", "left", "--clearance", "0.5"]
    rc = main(["trajectory", "--graph", str(path), *query, "--out", str(out)])
    _, err = capsys.readouterr()
    if oneway:
        assert rc == 3
        assert err.startswith("no motion: ") and err.count("\n") == 1 and "one-way" in err
        assert not out.exists() or list(out.iterdir()) == []
        return
    assert rc == 0, err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["min_separation"] >= 0.5 - 1e-9
    rows = list(csv.DictReader((out / "setpoints.csv").read_text().splitlines()))
    assert (rows[0]["a_edge"], rows[-1]["b_edge"]) != ("", "")
    assert math.isclose(float(rows[-1]["time"]), summary["makespan"], abs_tol=0.011)


def test_plan_prints_the_bound_with_the_speed_limits(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    """`mpa plan` on the Y with a slow branch: B alone needs 8 s, so the bound is 8 s and the plan is optimal."""
    import json

    from trajopt.cli import main

    layout = {
        "edges": [
            {"name": "b_short", "from": "J", "to": "short", "length": 1.0, "oneway": True},
            {"name": "b_left", "from": "left", "to": "J", "length": 2.0},
            {"name": "b_right", "from": "J", "to": "right", "length": 3.0, "speed_limit": 0.5},
        ]
    }
    path = tmp_path / "y.json"
    path.write_text(json.dumps(layout))
    argv = ["plan", "--graph", str(path), "--start", "left", "right", "--goal", "short", "left", "--clearance", "0.5"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "makespan   8 s" in out, out
    assert "no motion under them beats 8 s (this plan at most 0 s above the optimum)" in out, out
