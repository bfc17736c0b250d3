"""Smoke run of the plan-level graph benchmark (experiments/benchmark.py --track ...) and checks of its baselines."""

from __future__ import annotations

import itertools
import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest

import mpa
from mpa.errors import NoMotionError
from mpa.graph_track import GraphTrack

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "experiments"))

import benchmark  # noqa: E402
from bench import graph_runner as gr  # noqa: E402
from bench.graph_baselines import Geodesics, GraphGrid, GraphOmpl, leg_min_distance, ours_trajectory  # noqa: E402

Y = GraphTrack.from_layout({"edges": [["J", "s", 1.0], ["J", "l", 2.0], ["J", "r", 3.0]]})


def test_cli_smoke(tmp_path: Path) -> None:
    rc = benchmark.main(
        [
            "--track",
            "y_junction,theta",
            "--queries",
            "4",
            "--ompl-time",
            "0.05",
            "--out",
            str(tmp_path),
            "--no-progress",
        ]
    )
    assert rc == 0
    data = json.loads((tmp_path / "graphs.json").read_text())
    recs = data["layouts"]
    assert {r["method"] for r in recs} == {"ours", "grid", "ompl"}
    assert {r["layout"] for r in recs} == {"y_junction", "theta"}
    for r in recs:
        if r["method"] == "ours" and r["solved"]:
            assert r["min_distance"] >= r["clearance"] * (1 - 1e-9)  # exactness
            assert r["ratio_to_grid"] <= 1.02  # the target (median within 2 % of the grid), per query here
        if r["method"] == "grid" and r["solved"]:
            ours = next(
                x for x in recs if x["method"] == "ours" and x["layout"] == r["layout"] and x["query"] == r["query"]
            )
            assert ours["solved"]  # completeness cross-check
    assert all(r["ours"] == r["expect"] and r["grid"] == r["expect"] for r in data["oracle"])
    assert data["completeness"] and not any(r["grid"] and not r["ours"] for r in data["completeness"])
    assert all(r["ratio"] <= 1.01 for r in data["price"] if "ratio" in r)
    assert len(data["scaling"]) == 4 * 3
    md = (tmp_path / "graphs.md").read_text()
    for head in ("Layouts", "Y-junction", "Completeness", "Paper tracks", "Scaling"):
        assert head in md


def test_cli_errors(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert benchmark.main(["--track", "no_such_layout", "--out", str(tmp_path)]) == 2
    assert capsys.readouterr().err.startswith("error:")
    assert benchmark.main(["--track", "theta", "--graph-parts", "nope", "--out", str(tmp_path)]) == 2
    assert not (tmp_path / "graphs.json").exists()


def test_grid_is_exact_and_matches_ours_on_y_swap() -> None:
    D = 0.9
    grid = GraphGrid(Y, D, 0.05)
    st, gl = ((1, 2.0), (2, 3.0)), ((2, 3.0), (1, 2.0))
    res = grid.solve(st, gl)
    assert res.solved and res.path is not None
    assert min(leg_min_distance(Y, a, b) for a, b in res.path.legs) >= D - 1e-12
    p = mpa.plan(Y, st, gl, D, planner="graph", objective="fastest")
    assert p.makespan <= res.makespan + 1e-9
    # the grid path starts and ends at the query
    ea, sa, eb, sb = res.path.positions(np.array([0.0, 1.0]))
    assert (int(ea[0]), sa[0], int(eb[0]), sb[0]) == (1, 2.0, 2, 3.0)
    assert (int(ea[1]), sa[1], int(eb[1]), sb[1]) == (2, 3.0, 1, 2.0)


def test_grid_and_ours_refuse_swap_above_threshold() -> None:
    D = 1.0 + 1e-6
    st, gl = ((1, 2.0), (2, 3.0)), ((2, 3.0), (1, 2.0))
    assert not GraphGrid(Y, D, 0.05).solve(st, gl).solved
    with pytest.raises(NoMotionError):
        mpa.plan(Y, st, gl, D, planner="graph")


def test_geodesics_are_shortest() -> None:
    _, track = gr.load_layout("passing_loop")
    geo = Geodesics(track)
    rng = np.random.default_rng(3)
    for _ in range(50):
        a, b = gr._sample_pos(track, rng), gr._sample_pos(track, rng)
        pieces = geo.path(*a, *b)
        length = sum(abs(p[2] - p[1]) for p in pieces)
        assert math.isclose(length, track.geometry.distance_scalar(*a, *b), rel_tol=1e-12, abs_tol=1e-12)
        assert pieces[0][0] == a[0] or pieces[0][1] in (0.0, track.lengths[pieces[0][0]])
        # consecutive pieces join at one vertex
        for p, q in itertools.pairwise(pieces):
            end = track.tails[p[0]] if p[2] == 0.0 else track.heads[p[0]]
            start = track.tails[q[0]] if q[1] == 0.0 else track.heads[q[0]]
            assert end == start


def test_ompl_path_is_exact_and_ends_at_query() -> None:
    _, track = gr.load_layout("theta")
    D = 0.5
    om = GraphOmpl(track, D, budget=0.5)
    st, gl = ((0, 0.5), (2, 2.5)), ((2, 2.5), (0, 0.5))
    res = om.solve(st, gl, seed=3)
    assert res.solved and res.path is not None
    assert min(leg_min_distance(track, a, b) for a, b in res.path.legs) >= D - 1e-12
    ea, sa, eb, sb = res.path.positions(np.array([0.0, 1.0]))
    g = track.geometry
    assert g.distance_scalar(int(ea[0]), sa[0], *st[0]) < 1e-12 and g.distance_scalar(int(eb[0]), sb[0], *st[1]) < 1e-12
    assert g.distance_scalar(int(ea[1]), sa[1], *gl[0]) < 1e-12 and g.distance_scalar(int(eb[1]), sb[1], *gl[1]) < 1e-12


def test_scaling_layouts_have_the_asked_edge_count() -> None:
    for n in (10, 30, 100, 150):
        t = gr.grid_layout(n, seed=n)
        assert t.n_edges == n
        assert t.graph.betti()[0] == 1  # connected


def test_trajectory_hook_gives_verified_setpoints() -> None:
    res = ours_trajectory(Y, {"start": ((1, 2.0), (2, 3.0)), "goal": ((2, 3.0), (1, 2.0)), "clearance": 0.5})
    assert res["verified"] and not res["fallback"] and res["makespan"] > 0 and res["rows"] > 2, res
    no = ours_trajectory(Y, {"start": ((1, 2.0), (2, 3.0)), "goal": ((2, 3.0), (1, 2.0)), "clearance": 1.5})
    assert not no["verified"] and no["error"].startswith("NoMotionError"), no
    md = gr.trajectories_markdown([{"layout": "Y", "method": "ours", "makespan": 5.0, "trajectory": res}])
    assert "| Y | 1 | 1/1 | 0 |" in md, md
