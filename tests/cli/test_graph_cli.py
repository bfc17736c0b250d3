"""``mpa plan --graph`` / ``--planner graph`` and ``mpa topology --clearance`` on the example layouts."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from mpa import GraphTrack, InvalidInputError, Lollipop, NoMotionError, plan
from mpa.planners.graph import GraphPlan
from trajopt.cli import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tracks"
Y = str(EXAMPLES / "y_junction.json")  # branches b_short 1, b_left 2, b_right 3 at J


def _json_out(argv: list[str], capsys: pytest.CaptureFixture[str]) -> dict:  # type: ignore[type-arg]
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


def test_plan_dispatch_paper_and_graph() -> None:
    track = Lollipop(1.0, 1.0)
    p = plan(track, (0.2, 0.5), (0.5, 0.2), clearance=0.05)
    assert p.domain in (1, 2, 3)
    g = plan(track, (0.2, 0.5), (0.5, 0.2), clearance=0.05, planner="graph")
    assert isinstance(g, GraphPlan)
    assert g.min_distance() >= 0.05 - 1e-9
    # the graph planner's fastest plan is never slower than the paper's plan at the same speeds (1 m/s, no acceleration)
    paper_time = float(np.sum(np.max(np.abs(np.diff(p.waypoints_s, axis=0)), axis=1)))
    assert g.makespan <= paper_time + 1e-9
    gt = GraphTrack.from_json(Y)
    assert isinstance(plan(gt, ("left", "right"), ("right", "left"), clearance=1.0), GraphPlan)
    with pytest.raises(NoMotionError, match="clearance"):
        plan(gt, ("left", "right"), ("right", "left"), clearance=1.01)
    with pytest.raises(InvalidInputError, match="planner is 'paper'"):
        plan(gt, ("left", "right"), ("right", "left"), planner="paper")
    with pytest.raises(InvalidInputError, match="objective is 'quick'"):
        plan(track, (0.2, 0.5), (0.5, 0.2), objective="quick")
    with pytest.raises(InvalidInputError, match="planner is 'ompl'"):
        plan(track, (0.2, 0.5), (0.5, 0.2), planner="ompl")


@pytest.mark.parametrize("objective", ["fastest", "shortest"])
def test_cli_plan_graph_json(objective: str, capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["plan", "--graph", Y, "--start", "left", "right", "--goal", "right", "left", "--clearance", "0.5"]
    out = _json_out([*argv, "--objective", objective, "--json"], capsys)
    assert out["planner"] == "graph" and out["objective"] == objective
    assert out["start"] == ["left", "right"] and out["goal"] == ["right", "left"]
    assert len(out["path"]) >= 200 and out["min_distance"] >= 0.5 - 1e-9
    gt = GraphTrack.from_json(Y)
    first, last = out["path"][0], out["path"][-1]
    for (edge, off), want in zip(first + last, ["left", "right", "right", "left"]):
        assert gt.position_name(gt.edge_index(edge), off) == want
    # consecutive samples are close: the path is continuous in the layout
    s = np.asarray(out["path_s"])
    assert np.max(np.abs(np.diff(s, axis=0))) <= 0.05 * gt.total_length
    assert {p["edge"] for p in out["routes"]["a"]} >= {"b_left", "b_right"}


def test_cli_plan_graph_text_and_paper_track(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["plan", "--graph", Y, "--start", "left", "right", "--goal", "right", "left", "--clearance", "1"]) == 0
    text = capsys.readouterr().out
    assert "route A" in text and "b_short" in text
    out = _json_out(
        [
            "plan",
            "--track",
            "lollipop",
            "--start",
            "0.2",
            "0.5",
            "--goal",
            "0.5",
            "0.2",
            "--planner",
            "graph",
            "--json",
        ],
        capsys,
    )
    assert out["planner"] == "graph" and out["start"] == ["stick:0.2", "stick:0.5"]
    out = _json_out(["plan", "--track", "lollipop", "--start", "0.2", "0.5", "--goal", "0.5", "0.2", "--json"], capsys)
    assert out["domain"] in (1, 2, 3)


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["--graph", Y, "--start", "nowhere", "right", "--goal", "right", "left"], "--start of robot A"),
        (["--graph", Y, "--start", "b_left:9", "right", "--goal", "right", "left"], "offset"),
        (["--graph", Y, "--track", "lollipop", "--start", "left", "right", "--goal", "right", "left"], "both"),
        (["--start", "0.1", "0.2", "--goal", "0.2", "0.3"], "no track"),
        (["--track", "lollipop", "--start", "x", "0.2", "--goal", "0.2", "0.3"], "--start has 'x'"),
        (["--graph", "/nonexistent.json", "--start", "a", "b", "--goal", "b", "a"], "nonexistent"),
        (["--graph", Y, "--planner", "paper", "--start", "left", "right", "--goal", "right", "left"], "paper"),
    ],
)
def test_cli_plan_graph_bad_input(argv: list[str], needle: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["plan", *argv]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error:") and needle in err[0], err


def test_cli_topology_clearance_y_junction(capsys: pytest.CaptureFixture[str]) -> None:
    # two robots can exchange places on a Y junction iff the clearance fits the shortest branch (b1 = 1 m)
    for d, swap in [(0.5, True), (1.0, True), (1.01, False), (2.5, False)]:
        out = _json_out(["topology", "--graph", Y, "--clearance", str(d), "--json"], capsys)
        assert out["can_swap"] is swap, d
        assert out["clearance"] == d and out["free_components"] >= 1
        assert out["betti"] == [1, 1, 0]
    assert main(["topology", "--graph", Y, "--clearance", "1"]) == 0
    assert "can exchange places: yes" in capsys.readouterr().out
    assert main(["topology", "--graph", Y, "--clearance", "-1"]) == 2
    assert capsys.readouterr().err.startswith("error:")


def test_cli_topology_reads_every_example_layout(capsys: pytest.CaptureFixture[str]) -> None:
    for f in sorted(EXAMPLES.glob("*.json")):
        if f.stem == "warehouse":
            continue  # 77 edges: the full homology takes seconds; its free space is covered in test_graph_track
        out = _json_out(["topology", "--graph", str(f), "--clearance", "0.01", "--json"], capsys)
        assert out["free_components"] == out["betti"][0], f.name
