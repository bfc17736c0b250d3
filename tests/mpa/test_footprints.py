"""Footprints in the plane: specs, bad input, exact swap thresholds, an independent overlap check of plans and
trajectories, completeness against a grid search, the gate's plane check and the exported fields."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import mpa
from mpa import Disc, GraphTrack, InvalidInputError, NoMotionError, Rectangle
from mpa.footprint import Footprints, parse_footprint
from mpa.planar import planar_free_space
from tests.helpers.planar_checker import overlap_depth
from tests.helpers.planar_grid import drawn_of, grid_nodes, plane_free
from trajopt.cli.main import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tracks"
DEPTH_TOL = 1e-6


def passing_loop(h: float, straight: float, angle_deg: float = 30.0) -> dict[str, Any]:
    """A main line with a siding that leaves at ``angle_deg`` and runs ``straight`` metres at lateral offset h."""
    run = h / math.tan(math.radians(angle_deg))
    sw, se = 4.0, 4.0 + 2.0 * run + straight
    pts = [[sw + run, h], [sw + run + straight, h]]
    diag = math.hypot(run, h)
    return {
        "vertices": {"W": [0.0, 0.0], "SW": [sw, 0.0], "SE": [se, 0.0], "E": [se + 4.0, 0.0]},
        "edges": [
            {"name": "west", "from": "W", "to": "SW"},
            {"name": "main", "from": "SW", "to": "SE"},
            {"name": "siding", "from": "SW", "to": "SE", "points": pts, "length": 2.0 * diag + straight},
            {"name": "east", "from": "SE", "to": "E"},
        ],
    }


def fp_tuple(fp: Disc | Rectangle) -> tuple[float, ...]:
    return (fp.radius,) if isinstance(fp, Disc) else (fp.length, fp.width)


def plan_depth(track: GraphTrack, plan: Any, fa: tuple[float, ...], fb: tuple[float, ...], n: int = 1500) -> float:
    """Deepest overlap along a plan (positions sampled densely, corners included)."""
    dr = drawn_of(track)
    u = np.linspace(0.0, 1.0, n)
    (ea, oa), (eb, ob) = plan.positions(u)
    worst = 0.0
    for a, b, c, d in zip(ea, oa, eb, ob):
        worst = max(worst, overlap_depth(dr, fa, (int(a), float(b)), fb, (int(c), float(d))))
    return worst


# ------------------------------------------------------------------------------------------------ specs
def test_parse_specs() -> None:
    assert parse_footprint("0.3") == Footprints(Disc(0.3), Disc(0.3))
    assert parse_footprint("2.0x0.8") == Footprints(Rectangle(2.0, 0.8), Rectangle(2.0, 0.8))
    assert parse_footprint("2X0.8, 0.4") == Footprints(Rectangle(2.0, 0.8), Disc(0.4))
    assert parse_footprint("1x0.5,2x1").spec() == "1x0.5,2x1"
    assert mpa.footprint.footprints((Disc(0.2), Rectangle(1, 0.5))) == Footprints(Disc(0.2), Rectangle(1, 0.5))


@pytest.mark.parametrize("spec", ["2x", "x1", "-1", "0", "nan", "inf", "1x0", "1x-2", "a", "", "1,2,3", "1x2x3", "1,"])
def test_bad_specs(spec: str) -> None:
    with pytest.raises(InvalidInputError, match="footprint"):
        parse_footprint(spec)


@pytest.mark.parametrize("bad", [-1.0, 0.0, float("nan"), "0.3", True])
def test_bad_disc(bad: Any) -> None:
    with pytest.raises(InvalidInputError, match="radius"):
        Disc(bad)


def test_cli_bad_spec_exit_2_nothing_written(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "out"
    loop = str(EXAMPLES / "passing_loop.json")
    for spec in ("2x", "-1", "nan", "0"):
        argv = ["trajectory", "--graph", loop, "--start", "W", "E", "--goal", "E", "W", f"--footprint={spec}"]
        assert main([*argv, "--out", str(out)]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and err[0].startswith("error: footprint is"), err
        assert not out.exists()


def test_no_coordinates(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    layout = {"edges": [["J", "a", 2.0], ["J", "b", 2.0], ["J", "c", 2.0]]}
    tr = GraphTrack.from_layout(layout)
    with pytest.raises(InvalidInputError, match="coordinates"):
        mpa.plan(tr, ("a", "b"), ("b", "a"), footprint=Disc(0.1))
    path = tmp_path / "y.json"
    path.write_text(json.dumps(layout))
    out = tmp_path / "out"
    argv = ["trajectory", "--graph", str(path), "--start", "a", "b", "--goal", "b", "a", "--footprint", "0.1"]
    assert main([*argv, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error:") and "coordinates" in err[0]
    assert not out.exists()
    assert main(["topology", "--graph", str(path), "--clearance", "0.5", "--footprint", "0.1"]) == 2


def test_bodies_overlap_at_start_or_goal(capsys: pytest.CaptureFixture[str]) -> None:
    tr = GraphTrack.from_layout(passing_loop(1.2, 4.0))
    with pytest.raises(InvalidInputError, match="start has the bodies"):
        mpa.plan(tr, ("west:1", "west:2"), ("E", "W"), footprint=Rectangle(2.0, 0.5))
    with pytest.raises(InvalidInputError, match="goal has the bodies"):
        mpa.plan(tr, ("W", "E"), ("main:3", "siding:3.2"), footprint=Disc(0.7))
    loop = str(EXAMPLES / "passing_loop.json")
    argv = ["plan", "--graph", loop, "--start", "west:1", "west:2", "--goal", "E", "W", "--footprint", "2x0.5"]
    assert main(argv) == 2
    assert capsys.readouterr().err.startswith("error: start has the bodies")


# ------------------------------------------------------------------------------------------ thresholds
@pytest.mark.parametrize("h", [0.8, 1.2, 2.0])
@pytest.mark.parametrize("length", [0.6, 1.5, 3.0])
def test_swap_thresholds(h: float, length: float) -> None:
    """Swap iff rectangle width <= h, iff disc radius <= h/2 (on both sides of the threshold, and on it)."""
    tr = GraphTrack.from_layout(passing_loop(h, straight=length + 1.0))
    q = (("W", "E"), ("E", "W"))
    for width, ok in ((h - 0.05, True), (h, True), (h + 0.05, False)):
        fp = Rectangle(length, width)
        assert planar_free_space(tr, 0.0, fp).can_swap("W", "E") is ok, (h, length, width)
        if ok:
            p = mpa.plan(tr, *q, footprint=fp)
            assert plan_depth(tr, p, fp_tuple(fp), fp_tuple(fp), 200) <= DEPTH_TOL
        else:
            with pytest.raises(NoMotionError, match="cannot pass"):
                mpa.plan(tr, *q, footprint=fp)
    for radius, ok in (((h - 0.05) / 2, True), (h / 2, True), ((h + 0.05) / 2, False)):
        fp_d = Disc(radius)
        assert planar_free_space(tr, 0.0, fp_d).can_swap("W", "E") is ok, (h, radius)


def test_threshold_mixed_pair_and_reason() -> None:
    tr = GraphTrack.from_layout(passing_loop(1.2, 4.0))
    # half-widths summed: 0.35 + 0.8 = 1.15 <= 1.2 passes; 0.35 + 0.9 = 1.25 does not
    assert planar_free_space(tr, 0.0, (Rectangle(2.0, 0.7), Disc(0.8))).can_swap("W", "E")
    with pytest.raises(NoMotionError) as exc:
        mpa.plan(tr, ("W", "E"), ("E", "W"), footprint=(Rectangle(2.0, 0.7), Disc(0.9)))
    msg = str(exc.value)
    assert "'main'" in msg and "'siding'" in msg and "1.2 m apart" in msg and "1.25 m" in msg


# ---------------------------------------------------------------------------------- independent check
def random_layout(rng: np.random.Generator) -> dict[str, Any]:
    """A main line with one or two sidings at random offsets and switch angles (drawn in metres)."""
    layout = passing_loop(float(rng.uniform(0.6, 2.0)), float(rng.uniform(1.0, 5.0)), float(rng.uniform(12, 60)))
    if rng.random() < 0.5:  # a stub siding off the east end, close to the line
        e = layout["vertices"]["E"]
        layout["vertices"]["X"] = [e[0] - 3.0, float(rng.uniform(0.5, 1.5))]
        layout["edges"].append({"name": "stub", "from": "E", "to": "X"})
    return layout


def _random_position(tr: GraphTrack, rng: np.random.Generator) -> tuple[int, float]:
    e = int(rng.integers(tr.n_edges))
    return e, float(rng.uniform(0.0, tr.lengths[e]))


def _random_fp(rng: np.random.Generator) -> Disc | Rectangle:
    if rng.random() < 0.5:
        return Disc(float(rng.uniform(0.1, 0.7)))
    return Rectangle(float(rng.uniform(0.3, 2.5)), float(rng.uniform(0.2, 1.4)))


def _layouts(seed: int) -> list[GraphTrack]:
    rng = np.random.default_rng(seed)
    out = [GraphTrack.from_json(EXAMPLES / "passing_loop.json")]
    out += [GraphTrack.from_layout(random_layout(rng)) for _ in range(3)]
    return out


def _plan_queries(n: int, seed: int) -> tuple[int, int]:
    rng = np.random.default_rng(seed)
    tracks = _layouts(seed)
    planned = refused = 0
    for _ in range(n):
        tr = tracks[int(rng.integers(len(tracks)))]
        fa, fb = _random_fp(rng), _random_fp(rng) if rng.random() < 0.3 else None
        fps = (fa, fb) if fb is not None else fa
        start = (_random_position(tr, rng), _random_position(tr, rng))
        goal = (_random_position(tr, rng), _random_position(tr, rng))
        try:
            p = mpa.plan(tr, start, goal, clearance=float(rng.uniform(0.0, 1.0)), footprint=fps)
        except (InvalidInputError, NoMotionError):
            refused += 1
            continue
        planned += 1
        depth = plan_depth(tr, p, fp_tuple(fa), fp_tuple(fb or fa), 300)
        assert depth <= DEPTH_TOL, (tr.to_dict(), start, goal, fps, depth)
    return planned, refused


def test_plans_never_overlap_independent_check() -> None:
    planned, _ = _plan_queries(40, seed=7)
    assert planned >= 8


@pytest.mark.slow
def test_plans_never_overlap_independent_check_many() -> None:
    planned, _ = _plan_queries(1000, seed=11)
    assert planned >= 200


def _trajectory_queries(n: int, seed: int) -> int:
    from trajopt import generate_trajectory

    rng = np.random.default_rng(seed)
    tracks = _layouts(seed)
    done = 0
    for _ in range(n):
        tr = tracks[int(rng.integers(len(tracks)))]
        fp = _random_fp(rng)
        start = (_random_position(tr, rng), _random_position(tr, rng))
        goal = (_random_position(tr, rng), _random_position(tr, rng))
        try:
            traj = generate_trajectory(tr, start, goal, clearance=0.3, footprint=fp)
        except (InvalidInputError, NoMotionError):
            continue
        done += 1
        dr = drawn_of(tr)
        plan: Any = traj.plan
        # rows and 4 instants between consecutive rows, from the continuous motion
        t = np.union1d(traj.t, (traj.t[:-1, None] + np.linspace(0.2, 0.8, 4)[None, :] / traj.rate).ravel())
        s, _, _, _ = traj.sampler(np.minimum(t, traj.motion_time))
        ea, oa = plan.route_a.positions(s[:, 0])
        eb, ob = plan.route_b.positions(s[:, 1])
        f = fp_tuple(fp)
        worst = max(
            overlap_depth(dr, f, (int(a), float(b)), f, (int(c), float(d))) for a, b, c, d in zip(ea, oa, eb, ob)
        )
        assert worst <= DEPTH_TOL, (tr.to_dict(), start, goal, fp, worst)
        sm = traj.summary()
        assert sm["min_gap_plane"] >= 0.0 and sm["footprint"]["spec"] == Footprints(fp, fp).spec()
        assert "a_heading" in traj.columns
    return done


def test_trajectories_never_overlap_independent_check() -> None:
    assert _trajectory_queries(4, seed=3) >= 1


@pytest.mark.slow
def test_trajectories_never_overlap_independent_check_many() -> None:
    assert _trajectory_queries(40, seed=5) >= 10


# -------------------------------------------------------------------------------- completeness (grid)
def _grid_connected(tr: GraphTrack, fp: Disc | Rectangle, start: Any, goal: Any, step: float) -> bool:
    """Breadth-first search on a grid of both robots' sampled positions (one or both move one step), kept only where
    the bodies stay at least ``step + 0.02`` m apart (so every grid move is a motion of the model: a step moves a
    body at most ``step``). A rectangle on a corner where the drawing turns counts as the disc of its half-diagonal
    (it may turn there)."""
    nodes, adj = grid_nodes(tr, step, oneway=False)
    free = plane_free(tr, nodes, fp, step)
    geo = tr.geometry

    def nearest(pos: Any) -> int:
        e, o = tr.position(pos)
        return min(range(len(nodes)), key=lambda i: geo.distance_scalar(e, o, *nodes[i]))

    s = (nearest(start[0]), nearest(start[1]))
    goal_node = (nearest(goal[0]), nearest(goal[1]))
    if not free[s] or not free[goal_node]:
        return False
    seen = {s}
    todo = [s]
    while todo:
        i, j = todo.pop()
        for a in [i, *adj[i]]:
            for b in [j, *adj[j]]:
                if (a, b) not in seen and free[a, b]:
                    seen.add((a, b))
                    todo.append((a, b))
    return goal_node in seen


def grid_and_planner(tr: GraphTrack, fp: Disc | Rectangle, start: Any, goal: Any) -> tuple[bool, bool]:
    """Whether the grid search (step 0.1 m) finds a motion, and whether the planner plans one (False on
    NoMotionError; bad input propagates)."""
    grid = _grid_connected(tr, fp, start, goal, 0.1)
    try:
        mpa.plan(tr, start, goal, footprint=fp)
    except NoMotionError:
        return grid, False
    return grid, True


@pytest.mark.parametrize(
    "fp", [Disc(0.4), Disc(0.5), Disc(0.7), Rectangle(1.5, 0.9), Rectangle(1.0, 1.0), Rectangle(2.0, 1.3)]
)
def test_complete_against_grid(fp: Disc | Rectangle) -> None:
    """Whenever the grid finds a motion (with margins), the planner finds one."""
    tr = GraphTrack.from_layout(passing_loop(1.2, 2.5, 35.0))
    agree = 0
    for start, goal in ((("W", "E"), ("E", "W")), (("west:1", "east:3"), ("east:3", "west:1"))):
        grid, planned = grid_and_planner(tr, fp, start, goal)
        if grid:
            assert planned, (fp, start, goal)
        agree += grid == planned
    assert agree >= 1


# ------------------------------------------------------------------------------------------- the gate
def test_gate_rejects_larger_bodies_and_exports() -> None:
    from trajopt import generate_trajectory
    from trajopt.verify.planar import verify_plane

    tr = GraphTrack.from_json(EXAMPLES / "passing_loop.json")
    traj = generate_trajectory(tr, ("W", "E"), ("E", "W"), clearance=1.5, footprint=Rectangle(2.0, 1.0))
    assert traj.plane is not None and traj.plane["ok"]
    e, o = traj.edges, traj.offsets
    ok = verify_plane(tr, parse_footprint("2x1"), e, o, traj.v, amax=traj.limits.a, rate=traj.rate)
    assert ok.ok and ok.min_gap_plane >= 0
    bad = verify_plane(tr, parse_footprint("2x1.3"), e, o, traj.v, amax=traj.limits.a, rate=traj.rate)
    assert not bad.ok and "overlap" in bad.failures[0]
    sm = traj.summary()
    assert sm["footprint"] == {
        "spec": "2x1",
        "a": {"shape": "rectangle", "length": 2.0, "width": 1.0},
        "b": {"shape": "rectangle", "length": 2.0, "width": 1.0},
    }
    assert sm["min_gap_plane"] == pytest.approx(ok.min_gap_plane)
    assert sm["tracking_margin_plane"] == pytest.approx(sm["min_gap_plane"] / 2)
    header = traj.csv_text().splitlines()[0].split(",")
    assert header[-6:] == ["a_x", "a_y", "b_x", "b_y", "a_heading", "b_heading"]
    h = traj.headings()
    assert np.all(np.abs(h) <= math.pi)
    # on the siding's rising piece the heading is its direction
    on_siding = (traj.edges[:, 0] == tr.edge_index("siding")) & (traj.offsets[:, 0] < 1.0)
    assert np.allclose(h[on_siding, 0], math.atan2(1.2, 1.0))


def test_cli_topology_and_trajectory(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    loop = str(EXAMPLES / "passing_loop.json")
    assert main(["topology", "--graph", loop, "--clearance", "1.5", "--footprint", "0.6", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["can_swap"] is True
    assert main(["topology", "--graph", loop, "--clearance", "1.5", "--footprint", "0.65", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["can_swap"] is False
    out = tmp_path / "o"
    argv = ["trajectory", "--graph", loop, "--start", "W", "E", "--goal", "E", "W", "--clearance", "1.5"]
    assert main([*argv, "--footprint", "1.25", "--out", str(out)]) == 3
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("no motion:") and "1.2 m apart" in err[0], err
    assert not out.exists()
    assert main([*argv, "--footprint", "2x1", "--out", str(out)]) == 0
    sm = json.loads((out / "summary.json").read_text())
    assert sm["footprint"]["spec"] == "2x1" and sm["min_gap_plane"] >= 0
    rows = (out / "setpoints.csv").read_text().splitlines()
    assert rows[0].endswith("a_heading,b_heading")


def test_is_free_rejects_bodies_that_overlap_in_the_plane() -> None:
    """Side by side on the passing loop (siding 1.2 m from the main line): discs of 0.8 m overlap, of 0.5 m do not;
    the along-track distance is large in both cases, so only the plane decides."""
    tr = GraphTrack.from_json(EXAMPLES / "passing_loop.json")
    main, siding = tr.position("main:2"), tr.position("siding:2.5621")
    assert not planar_free_space(tr, 0.0, Disc(0.8)).is_free(main, siding)
    assert planar_free_space(tr, 0.0, Disc(0.5)).is_free(main, siding)
    assert planar_free_space(tr, 0.0, Disc(0.8)).is_free(tr.position("W"), tr.position("E"))
