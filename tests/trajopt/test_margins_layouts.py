"""Delay tolerance and ``min_margin`` / ``--min-margin`` on layouts and on the paper's tracks."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from mpa import GraphTrack, InvalidInputError, Lollipop, NoMotionError
from tests.helpers.cli import run_main as _run
from trajopt import TrajectoryGenerator
from trajopt.analysis.min_margin import largest_clearance

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tracks"
Y = str(EXAMPLES / "y_junction.json")  # branches b_short 1, b_left 2, b_right 3 at J: a swap needs D <= 1


@pytest.fixture(scope="module")
def y_track() -> GraphTrack:
    return GraphTrack.from_json(Y)


@pytest.mark.parametrize("margin", [0.0, 0.05, 0.2])
def test_min_margin_on_a_layout(y_track, margin) -> None:  # type: ignore[no-untyped-def]
    gen = TrajectoryGenerator(y_track, clearance=0.5)
    traj = gen.generate(("left", "right"), ("right", "left"), min_margin=margin)
    m = traj.margins()
    assert m.tracking_margin >= margin and traj.verification["ok"] and traj.clearance == 0.5
    assert traj.solver_stats["min_margin"]["requested"] == margin
    # the margin is what it says: the closest approach of the continuous motion keeps D + 2M
    t = np.linspace(0.0, traj.motion_time, 8001)
    s, *_ = traj.sampler(t)
    (ea, oa), (eb, ob) = traj.plan.route_a.positions(s[:, 0]), traj.plan.route_b.positions(s[:, 1])
    assert float(np.min(y_track.geometry.distance(ea, oa, eb, ob))) >= 0.5 + 2 * margin - 1e-9


def test_min_margin_too_large_names_the_largest(y_track) -> None:  # type: ignore[no-untyped-def]
    gen = TrajectoryGenerator(y_track, clearance=0.9)
    with pytest.raises(NoMotionError, match=r"largest tracking margin that can be had is 0\.04\d* m") as exc:
        gen.generate(("left", "right"), ("right", "left"), min_margin=0.1)
    best = float(str(exc.value).split("can be had is ")[1].split(" m")[0])
    # and that margin can indeed be had (to the bisection's resolution)
    traj = gen.generate(("left", "right"), ("right", "left"), min_margin=best * 0.999)
    assert traj.margins().tracking_margin >= best * 0.999
    assert largest_clearance(gen, ("left", "right"), ("right", "left"), 2.0) == pytest.approx(1.0, abs=1e-6)


def test_min_margin_on_a_paper_track() -> None:
    gen = TrajectoryGenerator(Lollipop(1.0, 1.0), clearance=0.05)
    traj = gen.generate((0.2, 0.5), (0.5, 0.2), min_margin=0.05)
    assert traj.margins().tracking_margin >= 0.05 and traj.domain in (1, 2, 3)
    with pytest.raises(NoMotionError, match="largest tracking margin"):
        gen.generate((0.2, 0.5), (0.5, 0.2), min_margin=0.3)  # the start's separation is 0.3
    for bad in (-1.0, float("nan"), "x"):
        with pytest.raises(InvalidInputError, match="min_margin"):
            gen.generate((0.2, 0.5), (0.5, 0.2), min_margin=bad)  # type: ignore[arg-type]


def test_delay_tolerance_on_a_layout(y_track) -> None:  # type: ignore[no-untyped-def]
    gen = TrajectoryGenerator(y_track, clearance=0.5)
    traj = gen.generate(("left", "right"), ("right", "left"), delay_tolerance=0.3)
    assert traj.margins().delay_tolerance >= 0.3 and traj.verification["ok"]
    assert traj.solver_stats["delay_tolerance"]["requested"] == 0.3
    with pytest.raises(NoMotionError, match="best found tolerates"):
        TrajectoryGenerator(y_track, clearance=0.99).generate(("left", "right"), ("right", "left"), delay_tolerance=5)


def test_cli_min_margin_and_delay_tolerance_on_a_layout(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    q = ["trajectory", "--graph", Y, "--start", "left", "right", "--goal", "right", "left"]
    out = tmp_path / "m"
    rc, text, err = _run([*q, "--clearance", "0.5", "--min-margin", "0.1", "--out", str(out)], capsys)
    assert rc == 0, err
    js = json.loads((out / "summary.json").read_text())
    assert js["margins"]["tracking_margin"] >= 0.1 and js["recipe"]["min_margin"] == 0.1
    assert "margin      asked 0.1 m" in text
    # the run can be re-planned: the recipe rebuilds the same motion
    rc, _, err = _run(
        ["replan", "--from", str(out), "--at", "3", "--goal", "b_left:1", "right", "--out", str(tmp_path / "r")], capsys
    )
    assert rc == 0, err
    out2 = tmp_path / "d"
    rc, text, err = _run([*q, "--clearance", "0.5", "--delay-tolerance", "0.2", "--out", str(out2)], capsys)
    assert rc == 0, err
    assert json.loads((out2 / "summary.json").read_text())["margins"]["delay_tolerance"] >= 0.2
    bad = tmp_path / "bad"
    rc, _, err = _run([*q, "--clearance", "0.95", "--min-margin", "0.1", "--out", str(bad)], capsys)
    assert rc == 3 and err.startswith("no motion: ") and err.count("\n") == 1 and not bad.exists()
    assert "largest tracking margin that can be had is" in err
    rc, _, err = _run([*q, "--min-margin", "-1", "--out", str(bad)], capsys)
    assert rc == 2 and err.startswith("error: --min-margin is -1") and not bad.exists()


def test_cli_min_margin_on_a_paper_track_replans(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out, again = tmp_path / "p", tmp_path / "r"
    q = ["trajectory", "--track", "lollipop", "--start", "0.2", "0.5", "--goal", "0.5", "0.2", "--min-margin", "0.05"]
    rc, _, err = _run([*q, "--out", str(out)], capsys)
    assert rc == 0, err
    js = json.loads((out / "summary.json").read_text())
    assert js["recipe"]["min_margin"] == 0.05 and js["margins"]["tracking_margin"] >= 0.05
    rc, _, err = _run(["replan", "--from", str(out), "--at", "1", "--goal", "0.6", "0.1", "--out", str(again)], capsys)
    assert rc == 0, err  # the recipe (with its margin) rebuilds the same rows
    assert json.loads((again / "summary.json").read_text())["recipe"]["min_margin"] == 0.05
