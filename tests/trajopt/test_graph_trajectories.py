"""Verified jerk-limited trajectories on layouts (issue 10, items 5 and 6): generator, files, command line.

Every trajectory is checked by the independent checker (:func:`trajopt.testing.check_graph_setpoints`, its own
Dijkstra metric) on the exported CSV itself: graph distance between the robots at every row, limits, endpoints at
rest, ``s`` consistent with ``v`` and ``a``, offsets within their edges, edge changes only at shared vertices,
``*_dir`` = the sign of the offset change, and the summary's routes.
"""

from __future__ import annotations

import csv
import io
import itertools
import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mpa import GraphTrack, Lollipop, MPAError, NoMotionError
from mpa.errors import InvalidInputError
from tests.helpers.cli import run_main as _run
from tests.helpers.graph_helpers import random_layout, random_position
from trajopt import Limits, TrajectoryGenerator, generate_trajectory
from trajopt.export import CSV_COLUMNS, GRAPH_CSV_COLUMNS, XY_COLUMNS
from trajopt.testing import GraphMetric, check_graph_setpoints, check_trajectory, requirements

ROOT = Path(__file__).resolve().parents[2]
LAYOUTS = sorted((ROOT / "examples" / "tracks").glob("*.json"))
HEADER = "time,a_edge,a_offset,a_s,a_v,a_a,a_j,b_edge,b_offset,b_s,b_v,b_a,b_j"
Y = ROOT / "examples" / "tracks" / "y_junction.json"


def _parse(text: str) -> tuple[list[str], dict[str, np.ndarray]]:
    rows = list(csv.reader(io.StringIO(text)))
    header = rows[0]
    cols: dict[str, np.ndarray] = {}
    for i, name in enumerate(header):
        raw = [r[i] for r in rows[1:]]
        cols[name] = np.array(raw, dtype=object) if name.endswith("_edge") else np.array(raw, dtype=float)
    return header, cols


def _pairs(c: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The CSV's per-robot columns (``a_K``, ``b_K``) as pairs: shape (N, 2) per quantity K."""
    return {k: np.stack([c[f"a_{k}"], c[f"b_{k}"]], axis=1) for k in ("offset", "s", "v", "a", "j", "dir")}


def _row_failures(  # type: ignore[no-untyped-def]
    traj, track: Any, t: np.ndarray, edges: np.ndarray, pair: dict[str, np.ndarray], ends: Any, metric: Any, **kw: Any
) -> list[str]:
    """The independent checker's failures of rows read from a CSV of ``traj`` (positions on ``track``, the query
    ``ends``); ``kw`` overrides :func:`trajopt.testing.requirements` (e.g. the rate read from the file)."""
    rows = [pair[k] for k in ("offset", "s", "v", "a", "j")]
    need = requirements(traj) | kw
    return check_graph_setpoints(
        track, t, edges, *rows, start=ends[0], goal=ends[1], dirs=pair["dir"].astype(int), metric=metric, **need
    )


def _check_csv(traj, text: str, metric: GraphMetric | None = None) -> list[str]:  # type: ignore[no-untyped-def]
    """Check the graph CSV ``text`` of ``traj`` with the independent checker; returns the failures."""
    plan = traj.plan
    track = plan.track
    header, c = _parse(text)
    fails = []
    want = GRAPH_CSV_COLUMNS + (XY_COLUMNS if track.has_coordinates else ())
    if tuple(header) != want or not ",".join(header).startswith(HEADER):
        fails.append(f"header {header}")
    index = {n: i for i, n in enumerate(track.edge_names)}
    edges = np.stack([[index[x] for x in c["a_edge"]], [index[x] for x in c["b_edge"]]], axis=1)
    pair = _pairs(c)
    rate = 1.0 / (c["time"][1] - c["time"][0]) if len(c["time"]) > 1 else traj.rate
    fails += _row_failures(traj, track, c["time"], edges, pair, (plan.start, plan.goal), metric, rate=round(rate, 6))
    if track.has_coordinates:
        xy = np.stack([np.stack([c["a_x"], c["a_y"]], 1), np.stack([c["b_x"], c["b_y"]], 1)], axis=1)
        for r in (0, 1):
            want_xy = track.embed(edges[:, r], pair["offset"][:, r])
            if np.max(np.abs(xy[:, r] - want_xy)) > 1e-9 * max(1.0, float(np.max(np.abs(want_xy)))):
                fails.append(f"x/y of robot {'AB'[r]} are not the offsets' points on the drawn edges")
    return fails


def _check_routes(traj) -> list[str]:  # type: ignore[no-untyped-def]
    """The summary's routes: consecutive pieces meet at a shared vertex and the rows lie on them."""
    plan = traj.plan
    track = plan.track
    routes = traj.routes()
    fails = []
    for r, key in enumerate("ab"):
        pieces = routes[key]
        if not pieces:
            fails.append(f"robot {key}: empty route")
            continue
        for p in pieces:
            if p["edge"] not in track.edge_names or p["dir"] not in (1, -1) or p["to_s"] < p["from_s"]:
                fails.append(f"robot {key}: bad piece {p}")
        for p, q in itertools.pairwise(pieces):
            e0, e1 = track.edge_index(p["edge"]), track.edge_index(q["edge"])
            exit_off = p["entry"] + p["dir"] * (p["to_s"] - p["from_s"])
            gap = track.geometry.distance_scalar(e0, exit_off, e1, q["entry"])
            if gap > 1e-9 or abs(p["to_s"] - q["from_s"]) > 1e-12:
                fails.append(f"robot {key}: pieces {p} and {q} do not meet")
        s = traj.s[:, r]
        if s.min() < pieces[0]["from_s"] - 1e-12 or s.max() > pieces[-1]["to_s"] + 1e-12:
            fails.append(f"robot {key}: rows leave the route's range")
    return fails


def _random_queries(track: GraphTrack, gen: TrajectoryGenerator, n: int, seed: int):  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(seed)
    out, tries = [], 0
    while len(out) < n and tries < 40 * n:
        tries += 1
        q = (random_position(track, rng), random_position(track, rng))
        g = (random_position(track, rng), random_position(track, rng))
        try:
            out.append(gen.generate(q, g))
        except (NoMotionError, InvalidInputError):
            continue
    return out


# ------------------------------------------------------------------------------------------ layouts
@pytest.mark.parametrize("path", LAYOUTS, ids=lambda p: p.stem)
def test_random_queries_on_every_example_layout_are_verified(path: Path) -> None:
    track = GraphTrack.from_json(path)
    gen = TrajectoryGenerator(track, clearance=0.1)
    metric = GraphMetric(track)
    trajs = _random_queries(track, gen, 4, seed=11)
    assert len(trajs) == 4
    for traj in trajs:
        assert traj.verification["ok"] and traj.is_graph
        text = traj.csv_text()
        assert not _check_csv(traj, text, metric), _check_csv(traj, text, metric)
        assert not check_trajectory(traj, fine=4)
        assert not _check_routes(traj)
        rows = text.strip().splitlines()
        assert len(rows) == len(traj.t) + 1


@pytest.mark.slow
@pytest.mark.parametrize("path", LAYOUTS, ids=lambda p: p.stem)
@pytest.mark.parametrize("clearance", [0.05, 0.3])
def test_many_random_queries_on_every_example_layout(path: Path, clearance: float) -> None:
    track = GraphTrack.from_json(path)
    gen = TrajectoryGenerator(track, clearance=clearance, limits=Limits((0.5, 0.3), (1.0, 0.6), (5.0, 3.0)))
    metric = GraphMetric(track)
    for traj in _random_queries(track, gen, 25, seed=3):
        assert not _check_csv(traj, traj.csv_text(), metric)
        assert not _check_csv(traj, traj.csv_text(rate=37.0), metric)
        assert not check_trajectory(traj) and not _check_routes(traj)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**31 - 1), clearance=st.sampled_from([0.0, 0.05, 0.2]))
def test_random_small_graphs(seed: int, clearance: float) -> None:
    rng = np.random.default_rng(seed)
    track = random_layout(rng)
    gen = TrajectoryGenerator(track, clearance=clearance, rate=50.0)
    for traj in _random_queries(track, gen, 1, seed):
        assert traj.verification["ok"]
        assert not _check_csv(traj, traj.csv_text())
        assert not check_trajectory(traj, fine=4) and not _check_routes(traj)


def test_every_export_rate_is_verified_at_that_rate() -> None:
    track = GraphTrack.from_json(Y)
    traj = TrajectoryGenerator(track, clearance=0.3).generate(("left", "right"), ("right", "left"))
    metric = GraphMetric(track)
    for rate in (7.0, 25.0, 250.0):
        try:
            at = traj.at_rate(rate)
        except InvalidInputError as exc:  # too low for this motion: the message names the lowest usable rate
            assert "lowest usable rate" in str(exc)
            continue
        assert at.rate == rate and at.verification["ok"]
        assert not _check_csv(at, at.csv_text(), metric)
        assert not _check_csv(traj, traj.csv_text(rate=rate), metric)


def test_swap_on_the_y_junction_passes_the_switches_along_the_routes() -> None:
    track = GraphTrack.from_json(Y)
    traj = generate_trajectory(track, ("left", "right"), ("right", "left"), clearance=0.3)
    routes = traj.summary()["routes"]
    # A waits in the short branch while B passes: its route goes into b_short and back out
    assert [p["edge"] for p in routes["a"]][:3] == ["b_left", "b_short", "b_short"]
    assert [p["dir"] for p in routes["a"]][1:3] == [1, -1]
    edges_b = {p["edge"] for p in routes["b"]}
    assert "b_short" not in edges_b
    assert traj.summary()["start"] == ["left", "right"] and traj.summary()["goal"] == ["right", "left"]
    assert traj.min_separation >= 0.3 - 1e-9
    prose = traj.description()["A"]
    assert "along b_short to b_short:" in prose and "back along b_short to J" in prose


def test_positions_as_names_tuples_and_text_agree() -> None:
    track = GraphTrack.from_json(Y)
    gen = TrajectoryGenerator(track, clearance=0.2)
    a = gen.generate(("b_left:1.5", "right"), ("b_right:2", "left"))
    b = gen.generate((("b_left", 1.5), (2, 3.0)), ((2, 2.0), ("b_left", 2.0)))
    np.testing.assert_array_equal(a.s, b.s)
    assert a.csv_text() == b.csv_text()


def test_no_motion_and_bad_input_are_raised_as_by_the_planner() -> None:
    track = GraphTrack.from_json(Y)
    with pytest.raises(NoMotionError, match="siding"):
        TrajectoryGenerator(track, clearance=1.5).generate(("left", "right"), ("right", "left"))
    gen = TrajectoryGenerator(track, clearance=0.3)
    with pytest.raises(InvalidInputError, match="b_left"):
        gen.generate(("b_left:9", "right"), ("right", "left"))
    with pytest.raises(InvalidInputError, match="apart"):
        gen.generate(("J", "b_short:0.1"), ("right", "left"))
    with pytest.raises(InvalidInputError, match="clearance"):
        TrajectoryGenerator(track, clearance=-1.0)
    with pytest.raises(InvalidInputError, match="goal"):  # re-planning on a layout validates the goal as generate
        gen.replan(gen.generate(("left", "right"), ("short", "left")), 1.0, ("b_left:9", "right"))


def test_start_at_the_clearance_is_explained_not_unverified() -> None:
    """Robots exactly D apart at rest cannot pass the gate's between-rows bound: a clear error, never bad rows."""
    track = GraphTrack.from_layout({"edges": [["a", "b", 2.0]]})
    gen = TrajectoryGenerator(track, clearance=0.5)
    with pytest.raises(InvalidInputError, match=r"lowest usable rate|start"):
        gen.generate((("e0", 0.2), ("e0", 0.7)), (("e0", 0.5), ("e0", 1.5)))


def test_stationary_query_gives_one_row_at_rest() -> None:
    track = GraphTrack.from_json(Y)
    traj = TrajectoryGenerator(track, clearance=0.2).generate(("left", "right"), ("left", "right"))
    assert len(traj.t) == 1 and traj.makespan == 0.0
    _header, c = _parse(traj.csv_text())
    assert c["a_dir"].tolist() == [0.0] and c["b_dir"].tolist() == [0.0]
    routes = traj.summary()["routes"]
    assert len(routes["a"]) == 1 and routes["a"][0]["from_s"] == routes["a"][0]["to_s"]


def test_layout_without_coordinates_has_no_xy_columns() -> None:
    track = GraphTrack.from_layout({"edges": [["J", "a", 1.0], ["J", "b", 2.0], ["J", "c", 2.0]]})
    traj = TrajectoryGenerator(track, clearance=0.3).generate(("b", "c"), ("c", "b"))
    assert traj.columns == GRAPH_CSV_COLUMNS
    assert traj.csv_text().splitlines()[0] == ",".join(GRAPH_CSV_COLUMNS)
    assert not _check_csv(traj, traj.csv_text())
    assert "x" not in traj.summary()["units"]


def test_margins_use_the_graph_distance() -> None:
    track = GraphTrack.from_json(Y)
    traj = TrajectoryGenerator(track, clearance=0.2).generate(("b_left:1.5", "right"), ("b_left:0.5", "b_right:2.5"))
    m = traj.margins()
    metric = GraphMetric(track)
    dense = np.linspace(0.0, traj.motion_time, 4001)
    s, *_ = traj.sampler(dense)
    (ea, oa), (eb, ob) = traj.plan.route_a.positions(s[:, 0]), traj.plan.route_b.positions(s[:, 1])
    sampled = float(np.min(metric(ea, oa, eb, ob)))
    assert m.min_separation <= sampled + 1e-9 and m.min_separation >= traj.clearance - 1e-9
    assert m.tracking_margin == pytest.approx((m.min_separation - traj.clearance) / 2)


def test_ros_and_pvt_exports_use_the_route_coordinates() -> None:
    import yaml

    from trajopt.io.pvt import check_pvt, pvt_table
    from trajopt.io.ros import ros2_yaml_text
    from trajopt.replan import replan

    track = GraphTrack.from_json(Y)
    gen = TrajectoryGenerator(track, clearance=0.3)
    traj = gen.generate(("b_left:1.5", "right"), ("b_right:2", "left"))
    msg = yaml.safe_load(ros2_yaml_text(traj))
    pos = np.array([p["positions"] for p in msg["points"]])
    np.testing.assert_allclose(pos, traj.s, rtol=0, atol=1e-12)
    tab = pvt_table(traj, 0.1, max_stretch=2.0)
    chk = check_pvt(traj, 0.1, tab.stretch)
    assert chk.ok and chk.report.ok  # the gate in positions on the layout, on the PVT check's dense grid
    np.testing.assert_allclose(tab.s[[0, -1]], traj.s[[0, -1]], atol=1e-9)
    again = replan(
        gen, traj, 0.5, ("left", "right")
    )  # re-planning works on layouts (tests/trajopt/test_replan_layouts.py)
    assert again.verification["ok"] and again.is_graph


# ------------------------------------------------------------------------------------- paper tracks
@pytest.mark.parametrize(
    "query", [((0.2, 0.5), (0.5, 0.2)), ((0.1, 0.6), (1.5, 0.3)), ((0.9, 1.7), (0.3, 1.2)), ((1.2, 1.9), (1.9, 1.2))]
)
def test_paper_csv_gains_consistent_edge_offset_dir_columns(query) -> None:  # type: ignore[no-untyped-def]
    track = Lollipop(1.0, 1.0)
    traj = TrajectoryGenerator(track, clearance=0.05).generate(*query)
    header, c = _parse(traj.csv_text())
    # conventions: Command line and files (the header continues after b_j)
    assert tuple(header) == CSV_COLUMNS and ",".join(header[11:]) == "a_edge,a_offset,a_dir,b_edge,b_offset,b_dir"
    g = track.as_graph_track()
    assert set(c["a_edge"]) | set(c["b_edge"]) <= {"stick", "loop"} == set(g.edge_names)
    for x in "ab":
        edge, off, p = c[f"{x}_edge"], c[f"{x}_offset"], c[f"{x}_track"]
        on_loop = edge == "loop"
        # the offset is the track coordinate on the stick, and on the loop the coordinate past P (modulo the loop)
        assert np.all(np.abs(np.where(on_loop, (off + 1.0) % 1.0 - (p - 1.0) % 1.0, off - p)) < 1e-9)
        ln = np.where(on_loop, 1.0, 1.0)
        assert np.all(off >= -1e-12) and np.all(off <= ln + 1e-12)
        # continuous: consecutive rows are at most vmax/rate apart in the graph metric, no jump at P
        e = np.where(on_loop, 1, 0)
        step = g.geometry.distance(e[:-1], off[:-1], e[1:], off[1:])
        assert np.max(step) <= traj.limits.v.max() / traj.rate * (1 + 1e-6) + 1e-9
        # on the loop the offset moves continuously modulo the loop length (a wrap at P, never a jump)
        same = on_loop[:-1] & on_loop[1:]
        d_off = np.diff(off)[same]
        assert np.all(np.abs((d_off + 0.5) % 1.0 - 0.5) <= traj.limits.v.max() / traj.rate + 1e-9)
    metric = GraphMetric(g)
    idx = {"stick": 0, "loop": 1}
    edges = np.stack([[idx[v] for v in c["a_edge"]], [idx[v] for v in c["b_edge"]]], axis=1)
    ends = [tuple((int(e), float(o)) for e, o in zip(*track.to_graph_position(np.asarray(q, float)))) for q in query]
    fails = _row_failures(traj, g, c["time"], edges, _pairs(c), ends, metric)
    assert not fails, fails
    routes = traj.summary()["routes"]
    assert {p["edge"] for r in "ab" for p in routes[r]} <= {"stick", "loop"}


def test_paper_summary_routes_cover_the_travelled_range() -> None:
    traj = generate_trajectory(Lollipop(1.0, 1.0), (0.2, 0.5), (0.5, 0.2), clearance=0.05)
    routes = traj.summary()["routes"]
    assert [p["edge"] for p in routes["a"]] == ["stick", "loop", "stick"]
    assert [p["dir"] for p in routes["a"]] == [1, 1, -1]
    for r, key in enumerate("ab"):
        assert routes[key][0]["from_s"] == pytest.approx(traj.s[:, r].min())
        assert routes[key][-1]["to_s"] == pytest.approx(traj.s[:, r].max())


# --------------------------------------------------------------------------------------- command line
def test_cli_trajectory_graph_writes_verified_files(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "o"
    args = ["trajectory", "--graph", str(Y), "--start", "left", "right", "--goal", "right", "left"]
    code, stdout, err = _run([*args, "--clearance", "0.3", "--rate", "50", "--out", str(out)], capsys)
    assert code == 0, err
    assert "route A" in stdout and err == ""
    assert sorted(p.name for p in out.iterdir()) == ["setpoints.csv", "summary.json"]
    js = json.loads((out / "summary.json").read_text())
    assert js["columns"] == list(GRAPH_CSV_COLUMNS + XY_COLUMNS) and js["rate"] == 50
    assert js["routes"]["a"][0] == {"edge": "b_left", "dir": -1, "entry": 2.0, "from_s": 0.0, "to_s": 2.0}
    assert js["verification"]["ok"] and js["start"] == ["left", "right"]
    text = (out / "setpoints.csv").read_text()
    assert text.splitlines()[0] == ",".join(GRAPH_CSV_COLUMNS + XY_COLUMNS)
    track = GraphTrack.from_json(Y)
    traj = TrajectoryGenerator(track, clearance=0.3, rate=50).generate(("left", "right"), ("right", "left"))
    assert text == traj.csv_text()
    assert not _check_csv(traj, text)


@pytest.mark.parametrize(
    ("extra", "code", "prefix"),
    [
        (["--start", "left", "right", "--goal", "right", "left", "--clearance", "1.5"], 3, "no motion:"),
        (["--start", "nowhere", "right", "--goal", "right", "left"], 2, "error:"),
        (["--start", "b_left:7", "right", "--goal", "right", "left"], 2, "error:"),
        (["--start", "b_left:x", "right", "--goal", "right", "left"], 2, "error:"),
        (["--start", "J", "b_short:0.05", "--goal", "right", "left"], 2, "error:"),
        (["--start", "left", "right", "--goal", "right", "left", "--clearance", "-1"], 2, "error:"),
        (["--start", "left", "right", "--goal", "right", "left", "--track", "lollipop"], 2, "error:"),
    ],
)
def test_cli_graph_exit_codes(tmp_path, capsys, extra, code, prefix) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "o"
    got, _stdout, err = _run(["trajectory", "--graph", str(Y), *extra, "--out", str(out)], capsys)
    assert got == code and err.startswith(prefix) and len(err.strip().splitlines()) == 1, (got, err)
    assert not out.exists()


def test_cli_graph_formats_and_paper_only_options(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    base = ["trajectory", "--graph", str(Y), "--start", "left", "right", "--goal", "right", "left"]
    base += ["--clearance", "0.5"]
    out = tmp_path / "o"
    code, stdout, err = _run([*base, "--format", "csv,ros2-yaml,pvt", "--pvt-stretch", "2", "--out", str(out)], capsys)
    assert code == 0, err
    assert sorted(p.name for p in out.iterdir()) == ["pvt.csv", "setpoints.csv", "summary.json", "trajectory.yaml"]
    js = json.loads((out / "summary.json").read_text())
    assert js["recipe"]["start"] == ["left", "right"]
    # a swap is an exact tie between "A waits in the short branch" and "B does": exactly one robot uses it, and
    # the printout describes that robot's detour
    short = [r for r in ("a", "b") if any(p["edge"] == "b_short" for p in js["routes"][r])]
    assert len(short) == 1, js["routes"]
    other = "B" if short == ["a"] else "A"
    start_edge = {"A": "b_left", "B": "b_right"}[other]
    goal_edge = {"A": "b_right", "B": "b_left"}[other]
    assert f"{other}           back along {start_edge} to J, along {goal_edge} to " in stdout, stdout
    bad = tmp_path / "bad"
    code, _, err = _run(["replan", "--from", str(out), "--at", "1", "--goal", "0.1", "0.5", "--out", str(bad)], capsys)
    assert code == 2 and "--goal of robot A is '0.1'" in err and not bad.exists()  # a layout run takes positions


def test_cli_bad_layout_file(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    bad = tmp_path / "bad.json"
    bad.write_text('{"edges": []}')
    out = tmp_path / "o"
    args = ["trajectory", "--graph", str(bad), "--start", "a", "b", "--goal", "b", "a", "--out", str(out)]
    code, _, err = _run(args, capsys)
    assert code == 2 and err.startswith("error:") and not out.exists()


def test_cli_animate_graph(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "anim"
    args = ["animate", "--graph", str(Y), "--start", "left", "right", "--goal", "right", "left"]
    code, stdout, err = _run(
        [*args, "--clearance", "0.3", "--max-frames", "6", "--dpi", "30", "--out", str(out)], capsys
    )
    assert code == 0, err
    gif = out / "animation.gif"
    assert gif.is_file() and gif.read_bytes()[:6] in (b"GIF89a", b"GIF87a")
    assert stdout.strip() == str(gif)
    code, _, err = _run([*args, "--clearance", "1.5", "--out", str(tmp_path / "none")], capsys)
    assert code == 3 and err.startswith("no motion:") and not (tmp_path / "none").exists()


def test_unverified_output_never_leaves(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    """If every candidate fails the gate, the generator raises instead of returning rows."""
    import trajopt.path.planview as pv
    from trajopt.verify.gate import VerificationReport

    def reject(self, *a, **k):  # type: ignore[no-untyped-def]
        return VerificationReport(False, ("forced",), 0.0, 0.0, {}, ())

    monkeypatch.setattr(pv.PlanView, "verify", reject)
    track = GraphTrack.from_json(Y)
    with pytest.raises(MPAError):
        TrajectoryGenerator(track, clearance=0.3).generate(("left", "right"), ("right", "left"))


def test_a_clearance_that_fits_exactly_says_so_and_the_suggested_one_works() -> None:
    """D equal to the short branch: the swap exists with no slack, so no finite grid of setpoints can be verified
    at 100 Hz; the error says why and which clearance works, and that clearance gives verified setpoints."""
    import re

    from mpa import GraphTrack, InvalidInputError
    from trajopt import TrajectoryGenerator

    track = GraphTrack.from_json(ROOT / "examples" / "tracks" / "y_junction.json")
    with pytest.raises(InvalidInputError, match="lower the clearance to about") as info:
        TrajectoryGenerator(track, clearance=1.0).generate(("left", "right"), ("right", "left"))
    suggested = float(re.search(r"lower the clearance to about ([0-9.]+) m", str(info.value)).group(1))
    assert 0.999 < suggested < 1.0
    traj = TrajectoryGenerator(track, clearance=suggested).generate(("left", "right"), ("right", "left"))
    assert traj.verification["ok"] and traj.min_separation >= suggested - 1e-9
