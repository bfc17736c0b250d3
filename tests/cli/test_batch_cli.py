"""``mpa batch``: every query of a CSV planned and verified, one result row each, locally and on Dask."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from mpa.graph_track import GraphTrack
from trajopt import GRAPH_CSV_COLUMNS
from trajopt.cli.batch import RESULT_COLUMNS, read_queries, run_batch
from trajopt.cli.common import TRAJECTORY_DEFAULTS
from trajopt.cli.main import main

ROOT = Path(__file__).resolve().parents[2]
Y = ROOT / "examples" / "tracks" / "y_junction.json"
CLEARANCE = 0.3

# (query, expected status): a swap through the junction, a plain move, a bad position, robots too close,
# an order swap on a dead-end branch pair that is solvable, and a query that needs the order changed on a line.
QUERIES = [
    (("b_short:0.8", "b_left:0.8", "b_left:0.8", "b_short:0.8"), "ok"),
    (("b_short:0.8", "b_left:0.8", "b_short:0.5", "b_left:1.5"), "ok"),
    (("b_nowhere:0.1", "b_left:0.8", "b_short:0.5", "b_left:1.5"), "bad input"),
    (("b_short:0.8", "b_short:0.7", "b_short:0.5", "b_left:1.5"), "bad input"),
    (("b_short:0.1", "b_left:0.8", "b_short:0.5", "b_left:9"), "bad input"),
]


def _args(qfile: Path, out: Path, *extra: str) -> list[str]:
    return [
        "batch",
        "--graph",
        str(Y),
        "--queries",
        str(qfile),
        "--out",
        str(out),
        "--clearance",
        str(CLEARANCE),
        *extra,
    ]


def _write_queries(path: Path, queries: list[tuple[tuple[str, ...], str]]) -> Path:
    with path.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["a_start", "b_start", "a_goal", "b_goal", "note"])
        for q, _ in queries:
            w.writerow([*q, "extra column ignored"])
    return path


def _results(out: Path) -> list[dict[str, str]]:
    with (out / "results.csv").open(newline="") as f:
        reader = csv.DictReader(f)
        assert tuple(reader.fieldnames or ()) == RESULT_COLUMNS
        return list(reader)


def _check_setpoints(track: GraphTrack, path: Path, query: tuple[str, ...]) -> None:
    """The file's header, its first and last rows at the query's start and goal, and the clearance on every row."""
    with path.open(newline="") as f:
        rows = list(csv.DictReader(f))
        header = list(rows[0])
    assert header[: len(GRAPH_CSV_COLUMNS)] == list(GRAPH_CSV_COLUMNS)
    names = track.edge_names
    for row, (a, b) in ((rows[0], query[:2]), (rows[-1], query[2:])):
        for r, want in zip("ab", (a, b)):
            e, off = track.position(want)
            assert row[f"{r}_edge"] == names[e], (path, row, want)
            assert float(row[f"{r}_offset"]) == pytest.approx(off, abs=1e-6), (path, row, want)
    idx = {n: i for i, n in enumerate(names)}
    ea = np.array([idx[r["a_edge"]] for r in rows])
    eb = np.array([idx[r["b_edge"]] for r in rows])
    sa = np.array([float(r["a_offset"]) for r in rows])
    sb = np.array([float(r["b_offset"]) for r in rows])
    d = track.geometry.distance(ea, sa, eb, sb)
    assert float(d.min()) >= CLEARANCE - 1e-6, (path, float(d.min()))


def _check(out: Path, queries: list[tuple[tuple[str, ...], str]], setpoints: bool) -> list[dict[str, str]]:
    track = GraphTrack.from_json(Y)
    res = _results(out)
    assert [int(r["row"]) for r in res] == list(range(len(queries)))
    for r, (q, status) in zip(res, queries):
        assert (r["a_start"], r["b_start"], r["a_goal"], r["b_goal"]) == q
        assert r["status"] == status, r
        assert float(r["compute_time"]) >= 0.0
        if status == "ok":
            assert r["message"] == ""
            assert float(r["makespan"]) > 0.0
            assert float(r["min_separation"]) >= CLEARANCE - 1e-9
            assert r["route_a"] or r["route_b"]
            for piece in (r["route_a"] + " " + r["route_b"]).split():
                assert piece[:-1] in track.edge_names and piece[-1] in "+-", piece
            sp = out / r["row"] / "setpoints.csv"
            assert sp.is_file() == setpoints
            if setpoints:
                _check_setpoints(track, sp, q)
        else:
            assert r["message"], r
            assert r["makespan"] == ""
            assert not (out / r["row"]).exists()
    return res


def test_batch_in_process_writes_one_row_per_query_and_the_setpoints(tmp_path: Path, capsys) -> None:
    qfile = _write_queries(tmp_path / "q.csv", QUERIES)
    out = tmp_path / "out"
    code = main(_args(qfile, out, "--workers", "1", "--setpoints"))
    captured = capsys.readouterr()
    assert code == 0, captured.err
    res = _check(out, QUERIES, setpoints=True)
    assert "b_nowhere" in res[2]["message"] and "a_start of row 2" in res[2]["message"]
    assert "9" in res[4]["message"] and "b_goal of row 4" in res[4]["message"]
    assert "5 queries" in captured.out.replace("queries     5", "5 queries")
    assert captured.err == ""  # no progress bar off a terminal


def test_batch_no_motion_is_a_result_row(tmp_path: Path) -> None:
    line = ROOT / "examples" / "tracks" / "interval.json"
    queries = [
        (("stick:0.1", "stick:0.6", "stick:0.6", "stick:0.1"), "no motion"),
        (("stick:0.1", "stick:0.6", "stick:0.3", "stick:0.9"), "ok"),
    ]
    qfile = _write_queries(tmp_path / "q.csv", queries)
    track = GraphTrack.from_json(line)
    res = run_batch(track, read_queries(qfile), tmp_path / "out", clearance=CLEARANCE, workers=1)
    assert [r["status"] for r in res] == ["no motion", "ok"]
    assert "order" in str(res[0]["message"]).lower() or res[0]["message"], res[0]
    assert _results(tmp_path / "out")[0]["status"] == "no motion"


@pytest.mark.parametrize(
    ("content", "expected"),
    [
        ("a_start,b_start,a_goal\nJ,left,short\n", "missing b_goal"),
        ("", "empty"),
    ],
)
def test_batch_bad_queries_file_is_exit_2_and_writes_nothing(tmp_path: Path, capsys, content, expected) -> None:
    qfile = tmp_path / "q.csv"
    qfile.write_text(content)
    out = tmp_path / "out"
    code = main(["batch", "--graph", str(Y), "--queries", str(qfile), "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and err.startswith("error: ") and expected in err, err
    assert not out.exists()


def test_batch_missing_queries_file_and_bad_workers(tmp_path: Path, capsys) -> None:
    out = tmp_path / "out"
    assert main(["batch", "--graph", str(Y), "--queries", str(tmp_path / "nope.csv"), "--out", str(out)]) == 2
    assert "does not exist" in capsys.readouterr().err
    qfile = _write_queries(tmp_path / "q.csv", QUERIES[:1])
    assert main(["batch", "--graph", str(Y), "--queries", str(qfile), "--out", str(out), "--workers", "0"]) == 2
    assert "--workers is 0" in capsys.readouterr().err
    assert not (out / "results.csv").exists()


def test_batch_on_local_processes_matches_in_process(tmp_path: Path) -> None:
    queries = QUERIES[:3]
    qfile = _write_queries(tmp_path / "q.csv", queries)
    track = GraphTrack.from_json(Y)
    one = run_batch(track, read_queries(qfile), tmp_path / "one", clearance=CLEARANCE, workers=1)
    two = run_batch(track, read_queries(qfile), tmp_path / "two", clearance=CLEARANCE, workers=2, setpoints=True)
    _check(tmp_path / "two", queries, setpoints=True)
    for r1, r2 in zip(one, two):
        assert (r1["status"], r1["makespan"], r1["route_a"], r1["route_b"]) == (
            r2["status"],
            r2["makespan"],
            r2["route_a"],
            r2["route_b"],
        )


def test_batch_on_a_dask_local_cluster(tmp_path: Path) -> None:
    distributed = pytest.importorskip("dask.distributed")
    qfile = _write_queries(tmp_path / "q.csv", QUERIES)
    out = tmp_path / "out"
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=1, processes=False, protocol="tcp://", dashboard_address=":0"
    ) as cluster:
        code = main(_args(qfile, out, "--dask", cluster.scheduler_address, "--setpoints"))
    assert code == 0
    _check(out, QUERIES, setpoints=True)


def test_batch_unreachable_dask_scheduler_is_exit_2(tmp_path: Path, capsys, monkeypatch) -> None:
    pytest.importorskip("dask.distributed")
    import trajopt.cli.batch as batch_cli

    monkeypatch.setattr(batch_cli, "DASK_TIMEOUT", 1.0)  # nothing listens on port 9: waiting longer changes nothing
    qfile = _write_queries(tmp_path / "q.csv", QUERIES[:1])
    out = tmp_path / "out"
    code = main(["batch", "--graph", str(Y), "--queries", str(qfile), "--out", str(out), "--dask", "tcp://127.0.0.1:9"])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("error: --dask is 'tcp://127.0.0.1:9'"), err
    assert not (out / "results.csv").exists()


def test_batch_rows_equal_single_runs_on_seeded_random_layouts(tmp_path: Path) -> None:
    """Each row is what TrajectoryGenerator.generate gives for that query alone (status, makespan, routes)."""
    from mpa.errors import InvalidInputError, NoMotionError
    from tests.helpers.graph_helpers import random_layout, random_position
    from trajopt.generator import TrajectoryGenerator
    from trajopt.timing import Limits

    rng = np.random.default_rng(25)
    seen: list[str] = []
    for k in range(3):
        track = random_layout(rng)
        names = track.edge_names
        queries = []
        for _ in range(4):
            ps = [random_position(track, rng) for _ in range(4)]
            queries.append(
                {c: f"{names[e]}:{o:.6f}" for c, (e, o) in zip(("a_start", "b_start", "a_goal", "b_goal"), ps)}
            )
        res = run_batch(track, queries, tmp_path / f"out{k}", clearance=CLEARANCE, workers=1)
        d = TRAJECTORY_DEFAULTS
        gen = TrajectoryGenerator(
            track, clearance=CLEARANCE, limits=Limits(d["vmax"], d["amax"], d["jmax"]), rate=d["rate"]
        )
        seen += [str(r["status"]) for r in res]
        for q, r in zip(queries, res):
            start = (track.position(q["a_start"]), track.position(q["b_start"]))
            goal = (track.position(q["a_goal"]), track.position(q["b_goal"]))
            try:
                traj = gen.generate(start, goal)
            except NoMotionError:
                assert r["status"] == "no motion", (k, q, r)
                continue
            except InvalidInputError:
                assert r["status"] == "bad input", (k, q, r)
                continue
            assert r["status"] == "ok", (k, q, r)
            assert r["makespan"] == pytest.approx(traj.makespan, abs=1e-9), (k, q, r)
    assert seen.count("ok") >= 3, seen  # the check is not vacuous


def test_progress_bar_counts_every_query(tmp_path: Path, capsys) -> None:
    qfile = _write_queries(tmp_path / "q.csv", QUERIES[2:])
    run_batch(
        GraphTrack.from_json(Y), read_queries(qfile), tmp_path / "out", clearance=CLEARANCE, workers=1, progress=True
    )
    err = capsys.readouterr().err
    assert "3/3" in err, err


def test_batch_with_footprints_in_the_plane(tmp_path: Path, capsys) -> None:
    """``--footprint``: discs of radius 0.55 m pass on the passing loop's siding (1.2 m apart), 0.65 m do not."""
    loop = ROOT / "examples" / "tracks" / "passing_loop.json"
    qfile = _write_queries(tmp_path / "q.csv", [(("W", "E", "E", "W"), "")])
    for radius, status in (("0.55", "ok"), ("0.65", "no motion")):
        out = tmp_path / radius
        args = ["batch", "--graph", str(loop), "--queries", str(qfile), "--out", str(out), "--clearance", "1.5"]
        code = main([*args, "--footprint", radius, "--workers", "1"])
        assert code == 0, capsys.readouterr().err
        (row,) = _results(out)
        assert row["status"] == status, row
    bad = tmp_path / "bad"
    args = ["batch", "--graph", str(loop), "--queries", str(qfile), "--out", str(bad), "--footprint", "2x"]
    code = main(args)
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("error: ") and err.count("\n") == 1 and not bad.exists()
