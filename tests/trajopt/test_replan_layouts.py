"""Re-planning from a moving state on layouts: API (splice, gate, stability under goal jitter) and ``mpa replan``."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from mpa import GraphTrack, InvalidInputError, NoMotionError
from tests.helpers.cli import run_main as _run
from trajopt import TrajectoryGenerator
from trajopt.path.planview import plan_view
from trajopt.testing import check_graph_trajectory

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tracks"
Y = str(EXAMPLES / "y_junction.json")


@pytest.fixture(scope="module")
def y_gen() -> TrajectoryGenerator:
    return TrajectoryGenerator(GraphTrack.from_json(Y), clearance=0.5)


@pytest.fixture(scope="module")
def swap(y_gen):  # type: ignore[no-untyped-def]
    return y_gen.generate(("left", "right"), ("right", "left"))


def _positions(traj, t):  # type: ignore[no-untyped-def]
    """Edge indices and offsets of both carts at times ``t`` of ``traj``'s continuous motion."""
    s, v, _, _ = traj.sampler(np.asarray(t, dtype=float))
    return plan_view(traj.plan).positions(s, v)


@pytest.mark.parametrize("frac", [0.0, 0.1, 0.33, 0.6, 0.85, 1.0])
def test_splice_is_continuous_and_verified(y_gen, swap, frac) -> None:  # type: ignore[no-untyped-def]
    at = round(frac * swap.makespan, 2)
    new = y_gen.replan(swap, at, ("b_left:1.0", "b_right:2.0"))
    assert new.verification["ok"] and new.min_separation >= 0.5 - 1e-9
    _, v0, a0, _ = swap.sampler(np.array([min(at, swap.motion_time)]))
    moving = at < swap.motion_time
    # p, v, a continuous at the splice (to rounding)
    np.testing.assert_allclose(new.v[0], v0[0] if moving else 0.0, atol=1e-9)
    np.testing.assert_allclose(new.a[0], a0[0] if moving else 0.0, atol=1e-9)
    (e_old, o_old), (e_new, o_new) = _positions(swap, [at]), (new.edges[:1], new.offsets[:1])
    g = y_gen.track.geometry
    for r in (0, 1):
        d = g.distance(e_old[:, r], o_old[:, r], e_new[:, r], o_new[:, r])
        assert float(d[0]) <= 1e-9, (r, d)
    # the goal at rest, the limits kept
    names = [y_gen.track.position_name(int(e), float(o)) for e, o in zip(new.edges[-1], new.offsets[-1])]
    assert names == ["b_left:1", "b_right:2"]
    assert np.all(new.v[-1] == 0) and np.all(np.abs(new.j) <= y_gen.limits.j * (1 + 1e-6))
    assert new.solver_stats["replan"]["at_time"] == at
    # the jerk-limited profile passes the project's independent checker of exported rows, too
    fails = check_graph_trajectory(new)
    assert [f for f in fails if not (moving and "first row" in f and "rest" in f)] == [], fails


def test_bad_input_and_no_motion(y_gen, swap) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(InvalidInputError, match="at_time"):
        y_gen.replan(swap, swap.makespan + 1, ("left", "right"))
    with pytest.raises(InvalidInputError, match="edge"):
        y_gen.replan(swap, 1.0, ("nowhere:1", "right"))
    with pytest.raises(InvalidInputError, match="clearance"):
        y_gen.replan(swap, 1.0, ("b_left:1.0", "b_left:1.2"))
    line = TrajectoryGenerator(GraphTrack.from_json(str(EXAMPLES / "interval.json")), clearance=0.1)
    first = line.generate(("stick:0.1", "stick:0.5"), ("stick:0.3", "stick:0.8"))
    with pytest.raises(NoMotionError):  # an order change on a line
        line.replan(first, 0.5, ("stick:0.8", "stick:0.3"))


def _route_class(traj, t0: float, n: int = 600):  # type: ignore[no-untyped-def]
    """The remaining path from ``t0``: per cart the edges it visits in order (consecutive repeats merged), and
    ``n`` positions equally spaced in route travel."""
    t = np.append(np.arange(t0, traj.motion_time, 1 / 2000.0), traj.motion_time)
    s, v, _, _ = traj.sampler(t)
    c = np.concatenate([[0.0], np.cumsum(np.max(np.abs(np.diff(s, axis=0)), axis=1))])
    u = np.linspace(0.0, c[-1], n)
    idx = np.clip(np.searchsorted(c, u, side="right") - 1, 0, len(c) - 1)
    e, o = plan_view(traj.plan).positions(s[idx], v[idx])
    word = []
    for r in (0, 1):
        seq = [int(x) for x in e[:, r]]
        word.append(tuple(x for k, x in enumerate(seq) if k == 0 or seq[k - 1] != x))
    return tuple(word), e, o


@pytest.mark.parametrize(
    ("layout", "start", "goal", "clearance"),
    [
        (Y, ("left", "right"), ("right", "left"), 0.5),
        (str(EXAMPLES / "two_sidings.json"), ("north_end", "south_end"), ("south_end", "north_end"), 0.05),
    ],
)
def test_replanning_every_tenth_with_millimetre_goal_moves_is_stable(layout, start, goal, clearance) -> None:  # type: ignore[no-untyped-def]
    """As experiments/replan_stability.py: re-plan at 0.1 s with the goal moved by up to 1 mm; the class (edges
    visited) never changes and the path moves by at most 10x the goal's move."""
    track = GraphTrack.from_json(layout)
    gen = TrajectoryGenerator(track, clearance=clearance)
    cur = gen.generate(start, goal)
    pos = [track.position(x) for x in goal]
    g = np.array([p[1] for p in pos])
    rng = np.random.default_rng(24)
    for k in range(15):
        if cur.motion_time <= 0.1:
            break
        move = rng.uniform(-1e-3, 1e-3, 2)
        # moved inwards from a vertex at an edge end: offsets stay on the edge
        lengths = np.array([track.lengths[p[0]] for p in pos])
        target = np.clip(g + move, 0.0, lengths)
        new = gen.replan(cur, 0.1, [(int(p[0]), float(x)) for p, x in zip(pos, target)])
        w_old, e_old, o_old = _route_class(cur, 0.1)
        w_new, e_new, o_new = _route_class(new, 0.0)
        assert w_new == w_old, (k, w_old, w_new)
        gap = max(
            float(np.max(track.geometry.distance(e_old[:, r], o_old[:, r], e_new[:, r], o_new[:, r]))) for r in (0, 1)
        )
        assert gap <= 10 * max(float(np.max(np.abs(target - g))), 1e-9) + 1e-6, (k, gap, move)
        cur, g = new, target


def test_cli_replan_on_a_layout_chain(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    r1, r2, r3 = tmp_path / "r1", tmp_path / "r2", tmp_path / "r3"
    argv = ["trajectory", "--graph", Y, "--start", "left", "right", "--goal", "right", "left", "--clearance", "0.5"]
    assert _run([*argv, "--out", str(r1)], capsys)[0] == 0
    rc, out, err = _run(
        ["replan", "--from", str(r1), "--at", "9.5", "--goal", "b_left:1", "right", "--out", str(r2)], capsys
    )
    assert rc == 0, err
    assert out.startswith("replan      at 9.5 s")
    js = json.loads((r2 / "summary.json").read_text())
    assert js["recipe"]["replans"] == [{"at": 9.5, "goal": ["b_left:1", "right"]}]
    assert js["verification"]["ok"] and js["goal"] == ["b_left:1", "right"]
    # a re-plan of a re-plan: the chain is rebuilt from the recipe and checked against setpoints.csv
    rc, out, err = _run(["replan", "--from", str(r2), "--at", "1", "--goal", "short", "J", "--out", str(r3)], capsys)
    assert rc == 0, err
    assert json.loads((r3 / "summary.json").read_text())["goal"] == ["short", "J"]


def test_cli_replan_checks_the_run_kind_before_the_goal(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    r1, bad = tmp_path / "r1", tmp_path / "bad"
    argv = ["trajectory", "--graph", Y, "--start", "left", "right", "--goal", "right", "left", "--clearance", "0.5"]
    assert _run([*argv, "--out", str(r1)], capsys)[0] == 0
    rc, _, err = _run(["replan", "--from", str(r1), "--at", "1", "--goal", "1", "2", "--out", str(bad)], capsys)
    assert rc == 2 and err.startswith("error: --goal of robot A is '1'") and err.count("\n") == 1
    rc, _, err = _run(
        ["replan", "--from", str(r1), "--at", "1", "--goal", "b_left:1", "b_left:1.2", "--out", str(bad)], capsys
    )
    assert rc == 2 and "clearance" in err and err.count("\n") == 1
    assert not bad.exists()
    # a paper run still takes track coordinates
    p1 = tmp_path / "p1"
    q = ["trajectory", "--track", "lollipop", "--start", "0.2", "0.5", "--goal", "0.5", "0.2", "--out", str(p1)]
    assert _run(q, capsys)[0] == 0
    rc, _, err = _run(["replan", "--from", str(p1), "--at", "1", "--goal", "short", "J", "--out", str(bad)], capsys)
    assert rc == 2 and "expected a track coordinate" in err
    # edited setpoints are refused
    text = (r1 / "setpoints.csv").read_text().splitlines()
    cells = text[5].split(",")
    cells[3] = str(float(cells[3]) + 1e-3)
    text[5] = ",".join(cells)
    (r1 / "setpoints.csv").write_text("\n".join(text) + "\n")
    rc, _, err = _run(["replan", "--from", str(r1), "--at", "1", "--goal", "left", "right", "--out", str(bad)], capsys)
    assert rc == 2 and "do not belong together" in err


def test_cli_replan_of_a_graph_planner_run_on_a_paper_track(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    r1, r2 = tmp_path / "r1", tmp_path / "r2"
    q = ["trajectory", "--track", "lollipop", "--stick", "1.3", "--loop", "0.9", "--start", "0.35", "1.75"]
    q += ["--goal", "1.75", "0.35", "--planner", "graph", "--objective", "shortest", "--out", str(r1)]
    assert _run(q, capsys)[0] == 0
    rc, _, err = _run(
        ["replan", "--from", str(r1), "--at", "2", "--goal", "stick:0.2", "loop:0.5", "--out", str(r2)], capsys
    )
    assert rc == 0, err
    js = json.loads((r2 / "summary.json").read_text())
    assert js["recipe"]["objective"] == "shortest" and js["goal"] == ["stick:0.2", "loop:0.5"]
