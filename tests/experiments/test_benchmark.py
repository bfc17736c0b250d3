"""Smoke runs of experiments/benchmark.py (in process and on a local Dask cluster) and checks of its geometry."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

from mpa import Circle, Lollipop
from mpa.routes import RobotMove

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "experiments"))

from bench.geometry import (  # noqa: E402
    JointPath,
    edge_position,
    joint_move_min_distance,
    single_edge_min_distance_vec,
    split_routes,
)

#: Fields every record must have (issue 5).
FIELDS = (
    "method",
    "query",
    "success",
    "compute_time",
    "makespan",
    "min_separation",
    "discontinuity",
    "track",
    "domain",
    "lower_bound",
    "makespan_ratio",
    "word",
    "verified",
)
TINY = ["--grid", "0.05", "--ompl-time", "0.05", "--no-progress"]


def _check_records(records: list[dict], methods: set[str]) -> None:
    assert {r["method"] for r in records} == methods
    for r in records:
        missing = [f for f in FIELDS if f not in r]
        assert not missing, f"record {r['method']} {r['query']} lacks {missing}"
        assert r["compute_time"] > 0
        if r["verified"]:
            assert r["success"] and r["makespan"] > 0 and r["makespan_ratio"] >= 1 - 1e-9
            assert r["min_separation"] >= 0.05 - 1e-9, (r["method"], r["query"], r["min_separation"])
    for r in records:
        if r["method"] == "ours":
            assert r["verified"], f"ours failed on query {r['query']}: {r['error']}"
            assert r["discontinuity"] is not None and r["discontinuity"] < 0.05


def test_smoke_run_writes_files_and_fields(tmp_path: Path) -> None:
    pytest.importorskip("ompl")
    import benchmark

    out = tmp_path / "run"
    rc = benchmark.main(
        ["--queries", "3,2", "--track", "lollipop,circle", "--workers", "1", "--seed", "3", "--out", str(out), *TINY]
    )
    assert rc == 0
    for name in ("results.json", "results.md", "run.json", "makespan.png", "compute_time.png", "discontinuity.png"):
        assert (out / name).is_file(), name
    for png in out.glob("*.png"):
        assert png.stat().st_size < 200_000, png
    records = json.loads((out / "results.json").read_text())
    assert len(records) == 3 * 6 + 2 * 5  # ompl_geo is lollipop-only
    _check_records(
        [r for r in records if r["track"] == "lollipop"],
        {"ours", "raw_plan", "ompl_rest", "ompl_bspline", "ompl_geo", "grid"},
    )
    _check_records(
        [r for r in records if r["track"] == "circle"], {"ours", "raw_plan", "ompl_rest", "ompl_bspline", "grid"}
    )
    md = (out / "results.md").read_text()
    assert "## lollipop" in md and "## circle" in md and "Per domain of our plan" in md
    # seeded and reproducible: the same command gives the same results (times aside)
    out2 = tmp_path / "again"
    benchmark.main(
        [
            "--queries",
            "3",
            "--track",
            "lollipop",
            "--workers",
            "1",
            "--seed",
            "3",
            "--methods",
            "ours,grid,ompl_rest",
            "--out",
            str(out2),
            *TINY,
        ]
    )
    again = {(r["method"], r["query"]): r for r in json.loads((out2 / "results.json").read_text())}
    for r in records:
        key = (r["method"], r["query"])
        if r["track"] == "lollipop" and key in again:
            assert again[key]["makespan"] == r["makespan"] and again[key]["word"] == r["word"], key


def test_dask_local_cluster(tmp_path: Path) -> None:
    pytest.importorskip("ompl")
    distributed = pytest.importorskip("dask.distributed")
    import benchmark

    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:
        rc = benchmark.main(
            [
                "--queries",
                "2",
                "--track",
                "circle",
                "--methods",
                "ours,ompl_rest,grid",
                "--dask",
                cluster.scheduler_address,
                "--out",
                str(tmp_path),
                *TINY,
            ]
        )
    assert rc == 0
    records = json.loads((tmp_path / "results.json").read_text())
    _check_records(records, {"ours", "ompl_rest", "grid"})
    assert sorted({r["query"] for r in records}) == [0, 1]


@pytest.mark.parametrize(
    "args",
    [["--track", "interval"], ["--methods", "rrt"], ["--queries", "0"], ["--clearance", "-1"], ["--queries", "2,3"]],
)
def test_bad_arguments_exit_2(tmp_path: Path, args: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    import benchmark

    assert benchmark.main(["--out", str(tmp_path / "x"), *args]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error:") and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "x").exists()


# --- geometry ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("track", [Lollipop(1.0, 1.0), Lollipop(0.4, 1.5), Circle(1.0)], ids=repr)
def test_exact_leg_minimum_is_a_lower_bound_and_tight(track) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(0)
    t = np.linspace(0.0, 1.0, 4001)
    for case in range(300):
        moves = []
        for _ in range(2):
            if isinstance(track, Lollipop) and rng.random() < 0.5:
                p0 = rng.uniform(0, track.stick)
                moves.append(RobotMove("stick", p0, rng.uniform(-p0, track.stick - p0)))
            else:
                moves.append(RobotMove("loop", rng.uniform(0, track.loop), rng.uniform(-0.3, 0.3) * track.loop))
        a, b = moves
        exact = joint_move_min_distance(track, (a,), (b,))
        pa = np.array([edge_position(track, a.edge, a.start + x * a.delta) for x in t])
        pb = np.array([edge_position(track, b.edge, b.start + x * b.delta) for x in t])
        dense = float(track.distance(pa, pb).min())
        assert exact <= dense + 1e-12, (case, a, b)
        assert dense - exact <= 2 * (abs(a.delta) + abs(b.delta)) / 4000, (case, a, b)
        if abs(a.delta) < track.loop / 4 and abs(b.delta) < track.loop / 4:
            vec = single_edge_min_distance_vec(
                track,
                np.array([a.edge == "loop"]),
                np.array([a.start]),
                np.array([a.delta]),
                np.array([b.edge == "loop"]),
                np.array([b.start]),
                np.array([b.delta]),
            )
            assert abs(vec[0] - exact) < 1e-12, (case, a, b)


def test_split_routes_cuts_only_where_a_robot_branches() -> None:
    track = Lollipop(1.0, 1.0)
    # A: stick → loop → back down the stick (one line: no cut); B: loop, then P, then onto the loop's other side
    # after a detour down the stick (a branch at P: cut there)
    states = np.array([[0.2, 1.6], [1.3, 1.9], [0.5, 1.95], [0.4, 0.9], [0.35, 1.1]])
    path = JointPath.from_states(track, states, geodesic=True)
    segs = split_routes(path)
    assert len(segs) == 2
    for seg in segs:
        for r in (0, 1):
            got = seg.routes[r].position(seg.nodes[:, r])
            assert np.allclose(track.distance(got, seg.states[:, r]), 0.0, atol=1e-9)
    assert split_routes(JointPath.from_states(Circle(1.0), np.array([[0.1, 0.6], [0.3, 0.9], [0.95, 0.4]])))
