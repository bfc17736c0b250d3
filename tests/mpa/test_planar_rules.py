"""Footprints in the plane under lane rules: one-way lanes and speed limits with bodies apart, the command line
with Open-RMF maps and ``--fleet``, and completeness of the one-way search against a directed grid search."""

from __future__ import annotations

import csv
import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

import mpa
from mpa import Disc, GraphTrack, NoMotionError, Rectangle
from tests.helpers.planar_checker import overlap_depth
from tests.helpers.planar_grid import grid_nodes, grid_queries
from tests.mpa.test_footprints import drawn_of, fp_tuple, passing_loop, plan_depth
from trajopt import generate_trajectory
from trajopt.cli.main import main
from trajopt.testing import random_rules

DATA = Path(__file__).resolve().parents[1] / "data" / "openrmf"
FLEET = DATA / "office_tinyRobot_config.yaml"  # footprint 0.3 m, vicinity 0.5 m, limits 0.5 m/s, 0.75 m/s²


def _y(oneway_short: bool, limit_right: float | None = None) -> GraphTrack:
    """A Y junction drawn in metres: branches short (1 m, up), left (2 m) and right (3 m) from J."""
    edges: list[dict[str, Any]] = [
        {"name": "b_short", "from": "J", "to": "short", "oneway": oneway_short},
        {"name": "b_left", "from": "left", "to": "J"},
        {"name": "b_right", "from": "J", "to": "right"},
    ]
    if limit_right is not None:
        edges[2]["speed_limit"] = limit_right
    verts = {"J": [0.0, 0.0], "short": [0.0, 1.5], "left": [-2.0, 0.0], "right": [3.0, 0.0]}
    return GraphTrack.from_layout({"vertices": verts, "edges": edges})


def _monotone(plan: Any) -> None:
    """No segment of the plan backs along a one-way edge."""
    tr = plan.track
    for (e, f, _), o in zip(plan.segment_cells, plan.segment_offsets):
        assert not tr.oneway[e] or o[1, 0] >= o[0, 0] - 1e-12, (tr.edge_names[e], o)
        assert not tr.oneway[f] or o[1, 1] >= o[0, 1] - 1e-12, (tr.edge_names[f], o)


def _cli(capsys: pytest.CaptureFixture[str], *args: object) -> tuple[int, str, str]:
    rc = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return rc, out, err


# ---------------------------------------------------------------------------------------------- planner
@pytest.mark.parametrize("fp", [Disc(0.2), Rectangle(0.5, 0.3)])
def test_one_way_branch_forbids_the_swap_with_bodies_and_says_so(fp: Disc | Rectangle) -> None:
    two_way = mpa.plan(_y(False), ("left", "right"), ("right", "left"), 0.5, footprint=fp)
    assert plan_depth(two_way.track, two_way, fp_tuple(fp), fp_tuple(fp), 600) <= 1e-6
    with pytest.raises(NoMotionError, match=r"one-way lanes forbid it.*b_short"):
        mpa.plan(_y(True), ("left", "right"), ("right", "left"), 0.5, footprint=fp)


def test_one_way_branch_entered_forwards_with_bodies() -> None:
    """A parks in the one-way branch (forwards) while B passes J behind it; the reverse query is impossible."""
    tr = _y(True)
    p = mpa.plan(tr, ("left", "b_right:1"), ("short", "b_right:2.5"), 0.5, footprint=Disc(0.3))
    _monotone(p)
    assert plan_depth(tr, p, (0.3,), (0.3,), 600) <= 1e-6
    with pytest.raises(NoMotionError, match="one-way"):
        mpa.plan(tr, ("short", "b_right:2.5"), ("left", "b_right:1"), 0.5, footprint=Disc(0.3))


def test_the_search_over_shared_segments_keeps_the_rule_and_decides() -> None:
    """The complete search over shared segments (the fallback of the search over shared points) finds a motion
    that keeps the one-way rule where one exists, and none out of the one-way branch."""
    from mpa.planar import _search, _search_sets, planar_free_space
    from mpa.planners.search_common import SearchQuery

    tr = _y(True)
    space = planar_free_space(tr, 0.5, Disc(0.2))
    s = (tr.position("left"), tr.position("b_right:1"))
    g = (tr.position("b_right:1.5"), tr.position("short"))
    by_points = _search(space, SearchQuery(tr, space.base, s, g, "fastest", (1.0, 1.0)))
    by_sets = _search_sets(space, s, g)
    assert by_points is not None and by_sets is not None
    for cell, p, q in by_sets:
        assert not tr.oneway[cell[0]] or q[0] >= p[0]
        assert not tr.oneway[cell[1]] or q[1] >= p[1]
    assert by_sets[0][1] == (0.0, 1.0) and by_sets[-1][2] == (1.5, 1.5)  # start and goal in offsets
    assert _search_sets(space, (s[1], s[0]), (g[1], g[0])) is not None
    assert _search_sets(space, g, s) is None  # back out of the one-way branch: impossible


def test_speed_limits_with_bodies_time_the_plan_and_cap_the_rows() -> None:
    tr = _y(True, limit_right=0.3)
    p = mpa.plan(tr, ("left", "b_right:1"), ("short", "right"), 0.5, speeds=(1.0, 1.0), footprint=Disc(0.3))
    free = mpa.plan(_y(True), ("left", "b_right:1"), ("short", "right"), 0.5, speeds=(1.0, 1.0), footprint=Disc(0.3))
    assert p.makespan >= 2.0 / 0.3 - 1e-9  # B drives 2 m of the limited branch
    assert p.makespan > free.makespan
    traj = generate_trajectory(tr, ("left", "b_right:1"), ("short", "right"), clearance=0.5, footprint=Disc(0.3))
    assert traj.verification["ok"] and not traj.fallback, traj.fallback_reason
    rows = list(csv.DictReader(traj.csv_text().splitlines()))
    names = list(tr.edge_names)
    for r in rows:
        for robot in "ab":
            e = names.index(r[f"{robot}_edge"])
            lim = tr.speed_limits[e]
            assert lim is None or abs(float(r[f"{robot}_v"])) <= lim * (1 + 1e-6), r
            if tr.oneway[e]:
                assert int(r[f"{robot}_dir"]) >= 0, r


# ------------------------------------------------------------------------------------------ command line
def _building_y(oneway: bool) -> dict[str, Any]:
    params = {"graph_idx": [2, 0], "speed_limit": [3, 0.0], "orientation": [1, ""]}
    vertices = [[0, 0, 0, "J"], [0, 1.5, 0, "short"], [-2, 0, 0, "left"], [3, 0, 0, "right"]]
    lanes = [
        [0, 1, {**params, "bidirectional": [4, not oneway]}],
        [2, 0, {**params, "bidirectional": [4, True]}],
        [0, 3, {**params, "bidirectional": [4, True]}],
    ]
    level = {"vertices": vertices, "lanes": lanes}
    return {"name": "y", "coordinate_system": "cartesian_meters", "levels": {"L1": level}}


@pytest.mark.parametrize("oneway", [True, False])
def test_cli_swap_with_the_fleet_footprint_one_way_exit_3_two_way_verified(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], oneway: bool
) -> None:
    path = tmp_path / "y.building.yaml"
    path.write_text(yaml.safe_dump(_building_y(oneway)), encoding="utf-8")
    out = tmp_path / "out"
    query = ["--start", "left", "right", "--goal", "right", "left", "--clearance", "0.5", "--fleet", FLEET]
    rc, _, err = _cli(capsys, "trajectory", "--graph", path, *query, "--out", out)
    if oneway:
        assert rc == 3, err
        assert err.startswith("no motion: ") and err.count("\n") == 1 and "one-way" in err, err
        assert not out.exists() or list(out.iterdir()) == []
        return
    assert rc == 0, err
    summary = json.loads((out / "summary.json").read_text())
    assert "0.3" in json.dumps(summary["footprint"]) and summary["min_gap_plane"] >= 0.0
    assert summary["min_separation"] >= 0.5 - 1e-9 and not summary["fallback"]


def test_cli_office_map_with_one_way_lanes_and_the_fleet(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The Open-RMF office map with two lanes made one-way (one on the swap's route), the fleet's disc of 0.3 m:
    a verified motion that drives the one-way lane forwards only, checked row by row and by the independent
    checker."""
    raw = yaml.safe_load((DATA / "office.building.yaml").read_text(encoding="utf-8"))
    lanes = raw["levels"]["L1"]["lanes"]
    for k in (0, 14):
        lanes[k][2]["bidirectional"] = [4, False]
    path = tmp_path / "office.building.yaml"
    path.write_text(yaml.safe_dump(raw), encoding="utf-8")
    out = tmp_path / "out"
    query = ["--start", "pantry", "patrol_A1", "--goal", "patrol_A1", "pantry", "--clearance", "0.5"]
    rc, _, err = _cli(capsys, "trajectory", "--graph", path, *query, "--fleet", FLEET, "--out", out)
    assert rc == 0, err
    summary = json.loads((out / "summary.json").read_text())
    assert "0.3" in json.dumps(summary["footprint"]) and summary["verification"]["ok"] is True
    tr = GraphTrack.from_file(path)
    assert tr.oneway[0] and tr.oneway[14]
    names = list(tr.edge_names)
    rows = list(csv.DictReader((out / "setpoints.csv").read_text().splitlines()))
    used = set()
    for r in rows:
        for robot in "ab":
            e = names.index(r[f"{robot}_edge"])
            assert abs(float(r[f"{robot}_v"])) <= 0.5 * (1 + 1e-6), r  # the fleet's limit
            if tr.oneway[e]:
                used.add(e)
                assert int(r[f"{robot}_dir"]) >= 0, r
    assert 14 in used  # the one-way lane is on the route, driven forwards
    dr = drawn_of(tr)
    worst = max(
        overlap_depth(dr, (0.3,), (names.index(r["a_edge"]), float(r["a_offset"])), (0.3,),
                      (names.index(r["b_edge"]), float(r["b_offset"])))
        for r in rows
    )  # fmt: skip
    assert worst <= 1e-6


# ------------------------------------------------------------------------------- completeness (grid)
def _directed_grid(tr: GraphTrack, radius: float, clearance: float, step: float) -> tuple[list[Any], Any]:
    """Grid nodes along every edge (vertices shared), the forward moves between neighbours (only from tail to head
    on a one-way edge), and the configurations kept: discs at least ``step + 0.02`` m apart in the plane and the
    robots at least ``clearance + step`` apart along the track. One robot moves one step at a time, so every grid
    path is a motion of the model that keeps the one-way rule."""
    dr = drawn_of(tr)
    nodes, nxt = grid_nodes(tr, step, oneway=True)
    c = np.array([dr.point(*q) for q in nodes])
    plane = np.hypot(c[:, None, 0] - c[None, :, 0], c[:, None, 1] - c[None, :, 1]) - 2.0 * radius
    geo = tr.geometry
    along = np.array([[geo.distance_scalar(*p, *q) for q in nodes] for p in nodes])
    free = (plane >= step + 0.02) & (along >= clearance + step)
    return nodes, (nxt, free)


def _random_ruled_layout(rng: np.random.Generator) -> GraphTrack:
    """A main line with a siding close beside it (``passing_loop``), some edges one-way, some speed-limited."""
    layout = passing_loop(float(rng.uniform(0.5, 1.5)), float(rng.uniform(0.5, 2.0)), float(rng.uniform(25, 50)))
    return random_rules(layout, rng, oneway=0.45, limited=0.2, speed=0.4)


@pytest.mark.parametrize("seed", range(6))
def test_complete_under_one_way_rules_with_bodies_against_a_grid(seed: int) -> None:
    """Whenever the directed grid finds a motion, the planner finds one, and every plan keeps the rule and the
    bodies apart (independent checker)."""
    rng = np.random.default_rng(1000 + seed)
    tr = _random_ruled_layout(rng)
    radius = float(rng.choice([0.2, 0.3, 0.45]))
    clearance = float(rng.choice([0.0, 0.5]))
    step = 0.2
    nodes, (nxt, free) = _directed_grid(tr, radius, clearance, step)
    met = 0
    for grid, start, goal in grid_queries(rng, nodes, nxt, free, 12):
        try:
            plan = mpa.plan(tr, start, goal, clearance, footprint=Disc(radius))
        except NoMotionError as exc:
            assert not grid, (
                f"seed {seed}: the grid finds a motion, the planner says {exc}; {tr.to_dict()} {start} {goal}"
            )
            continue
        met += grid
        _monotone(plan)
        assert plan.min_distance() >= clearance - 1e-9
        assert plan_depth(tr, plan, (radius,), (radius,), 300) <= 1e-6, (seed, start, goal)
    assert met >= 1, f"seed {seed}: no query the grid could solve"


# ------------------------------------------------------------------------------------ no fallback
EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tracks"


@pytest.mark.parametrize(
    ("layout", "start", "goal", "clearance", "spec"),
    [
        ("rail_yard.json", ("W", "E"), ("E", "W"), 2.5, "2.0x0.8"),
        ("rail_yard.json", ("W", "D"), ("D", "W"), 2.5, "0.3"),
        ("passing_loop.json", ("W", "E"), ("E", "W"), 0.5, "2x0.8"),
        ("passing_loop.json", ("W", "E"), ("E", "W"), 0.5, "0.3"),
        ("y_junction.json", ("short", "right"), ("right", "short"), 0.5, "0.3"),
    ],
)
def test_example_swaps_with_footprints_verify_without_fallback(
    layout: str, start: tuple[str, str], goal: tuple[str, str], clearance: float, spec: str
) -> None:
    """The blend keeps the plane margin along the whole path (the gate's bound between its samples, turns at
    corners included), and the plan keeps it beyond the planner's touching tolerance: the optimized motion passes."""
    tr = GraphTrack.from_json(EXAMPLES / layout)
    traj = generate_trajectory(tr, start, goal, clearance=clearance, footprint=spec)
    assert traj.verification["ok"]
    assert not traj.fallback, traj.fallback_reason
    assert traj.summary()["min_gap_plane"] >= 0.0
