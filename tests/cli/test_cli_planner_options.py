"""``mpa trajectory --planner paper|graph --objective fastest|shortest`` on the paper's tracks and on layouts."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from mpa import Lollipop
from tests.helpers.cli import run_main as _run
from trajopt import GRAPH_CSV_COLUMNS, TrajectoryGenerator
from trajopt.cli import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tracks"
Y = str(EXAMPLES / "y_junction.json")
QUERY = ["--track", "lollipop", "--stick", "1.3", "--loop", "0.9", "--start", "0.35", "1.75", "--goal", "1.75", "0.35"]


@pytest.mark.parametrize("objective", ["fastest", "shortest"])
def test_trajectory_graph_planner_on_a_paper_track(
    objective: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / objective
    rc, text, err = _run(
        ["trajectory", *QUERY, "--planner", "graph", "--objective", objective, "--out", str(out)], capsys
    )
    assert rc == 0, err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["verification"]["ok"] is True
    assert summary["min_separation"] >= 0.05 - 1e-9
    # written as on the track's graph form: edges stick and loop, positions by name
    with open(out / "setpoints.csv") as f:
        header = next(csv.reader(f))
    assert tuple(header[: len(GRAPH_CSV_COLUMNS)]) == GRAPH_CSV_COLUMNS
    assert {e["edge"] for r in "ab" for e in summary["routes"][r]} <= {"stick", "loop"}
    assert summary["recipe"]["start"] == ["stick:0.35", "loop:0.45"]
    assert "route A" in text


def test_graph_fastest_is_no_slower_than_shortest_on_the_paper_track() -> None:
    g = Lollipop(1.3, 0.9).as_graph_track()
    start, goal = (("stick", 0.35), ("loop", 0.45)), (("loop", 0.45), ("stick", 0.35))
    fast = TrajectoryGenerator(g, clearance=0.05, objective="fastest").plan(start, goal)
    short = TrajectoryGenerator(g, clearance=0.05, objective="shortest").plan(start, goal)
    assert fast.objective == "fastest" and short.objective == "shortest"
    assert fast.makespan <= short.makespan + 1e-9
    assert short.route_a.length + short.route_b.length <= fast.route_a.length + fast.route_b.length + 1e-9


def test_planner_options_errors(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "x"
    argv = ["trajectory", "--graph", Y, "--start", "left", "right", "--goal", "right", "left", "--planner", "paper"]
    rc, _, err = _run([*argv, "--out", str(out)], capsys)
    assert rc == 2 and err.startswith("error: --planner is 'paper' with --graph") and err.count("\n") == 1
    assert not out.exists()
    with pytest.raises(SystemExit) as exc:  # a usage error (argparse): status 2, one line
        main(["trajectory", *QUERY, "--objective", "quick", "--out", str(out)])
    assert exc.value.code == 2 and "--objective" in capsys.readouterr().err
    with pytest.raises(ValueError, match="objective is 'quick'"):
        TrajectoryGenerator(Lollipop(1.0, 1.0), objective="quick")


def test_paper_planner_is_the_default_on_paper_tracks(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "p"
    rc, text, err = _run(["trajectory", *QUERY, "--planner", "paper", "--out", str(out)], capsys)
    assert rc == 0, err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["domain"] in (1, 2, 3) and summary["recipe"]["start"] == [0.35, 1.75]
    assert text.startswith("domain")
