"""Files that stay whole and unambiguous (second reliability round, items 1 and 2).

Item 1: every CSV is written with :mod:`csv`'s writer (RFC 4180 quoting), so edge names holding commas, quotes,
line breaks and any unicode read back exactly, with the same number of fields on every row. Item 2: an output
directory is replaced as a whole (:func:`trajopt.export.write_directory`): killed by ``SIGKILL``, ``SIGTERM`` or
``SIGINT`` at every stage (the test hook ``MPA_TEST_PAUSE_BETWEEN_FILES`` pauses after each), or out of disk
(``RLIMIT_FSIZE``), the directory holds the previous run's complete set byte for byte, or the new complete set.
"""

from __future__ import annotations

import csv
import io
import json
import os
import resource
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mpa import GraphTrack
from trajopt import TrajectoryGenerator
from trajopt.cli import main
from trajopt.export import GRAPH_CSV_COLUMNS, PAUSE_ENV, csv_field, csv_line, write_directory
from trajopt.testing import check_graph_setpoints

ROOT = Path(__file__).resolve().parents[2]
QUERY = ["--track", "lollipop", "--start", "0.2", "0.5", "--goal", "0.5", "0.2"]


def _layout(name: str) -> dict[str, object]:
    """The issue's reproducer with edge ``name`` as the siding the robots swap through."""
    return {"edges": [{"name": name, "from": "J", "to": "x", "length": 1}, ["J", "y", 2], ["J", "z", 2]]}


def _rows(path: Path) -> list[list[str]]:
    with path.open(encoding="utf-8", newline="") as fh:
        return list(csv.reader(fh))


def test_issue_reproducer_comma_in_an_edge_name_reads_back(tmp_path: Path) -> None:
    layout = tmp_path / "comma.json"
    layout.write_text('{"edges":[{"name":"s,0","from":"J","to":"x","length":1},["J","y",2],["J","z",2]]}')
    out = tmp_path / "o"
    argv = ["trajectory", "--graph", str(layout), "--start", "y", "z", "--goal", "z", "y", "--clearance", "0.5"]
    assert main([*argv, "--out", str(out)]) == 0
    rows = _rows(out / "setpoints.csv")
    assert {len(r) for r in rows} == {len(GRAPH_CSV_COLUMNS)}, {len(r) for r in rows}
    header = rows[0]
    edges = {r[header.index("a_edge")] for r in rows[1:]} | {r[header.index("b_edge")] for r in rows[1:]}
    assert "s,0" in edges and edges <= {"s,0", "e1", "e2"}, edges
    for r in rows[1:]:
        float(r[header.index("a_offset")])  # every offset a number, never a piece of a name


@pytest.mark.parametrize("name", ['s,"q"', "a\nb", "line\r\nbreak", "Gleis ü 3 ✓", ' lead,"', '"', "a,b,c,"])
def test_edge_names_with_commas_quotes_newlines_unicode_read_back(tmp_path: Path, name: str) -> None:
    track = GraphTrack.from_layout(_layout(name))
    traj = TrajectoryGenerator(track, clearance=0.5).generate(("y", "z"), ("z", "y"))
    path = tmp_path / "s.csv"
    traj.to_csv(path)
    rows = _rows(path)
    assert rows[0] == list(traj.columns)
    assert len(rows) == len(traj.t) + 1 and {len(r) for r in rows} == {len(traj.columns)}
    for k, col in enumerate("ab"):
        got = [r[rows[0].index(f"{col}_edge")] for r in rows[1:]]
        assert got == [traj.edge_names[e] for e in traj.edges[:, k]]
    assert any(r[1] == name or r[7] == name for r in rows[1:]), "the robots never used the named edge"
    # the independent checker, on the columns read back by name
    h = rows[0]
    col = {n: [r[i] for r in rows[1:]] for i, n in enumerate(h)}
    num = {n: np.array(v, dtype=float) for n, v in col.items() if not n.endswith("_edge")}
    index = {n: i for i, n in enumerate(track.edge_names)}
    edges = np.array([[index[a], index[b]] for a, b in zip(col["a_edge"], col["b_edge"], strict=True)])
    pair = {k: np.stack([num[f"a_{k}"], num[f"b_{k}"]], axis=1) for k in ("offset", "s", "v", "a", "j", "dir")}
    lim = traj.limits
    fails = check_graph_setpoints(
        track, num["time"], edges, pair["offset"], pair["s"], pair["v"], pair["a"], pair["j"],
        rate=traj.rate, clearance=traj.clearance, vmax=lim.v, amax=lim.a, jmax=lim.j,
        start=traj.plan.start, goal=traj.plan.goal, dirs=pair["dir"].astype(int),
    )  # fmt: skip
    assert not fails, fails


@settings(max_examples=200, deadline=None)
@given(st.lists(st.text(min_size=0, max_size=12), min_size=1, max_size=5))
def test_csv_line_and_field_round_trip(cells: list[str]) -> None:
    text = csv_line(cells)
    assert list(csv.reader(io.StringIO(text, newline=""))) == [cells], (cells, text)
    for c in cells:
        assert list(csv.reader(io.StringIO(csv_field(c) + "\n", newline=""))) == [[c]], (c, csv_field(c))


# --- one commit point per output directory -------------------------------------------------------------
def _snapshot(d: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(d.iterdir())} if d.exists() else {}


def _complete_new_set(d: Path, rate: float) -> bool:
    """Whether ``d`` holds one complete run at ``rate``: the summary's file list, the CSV at that rate."""
    s = json.loads((d / "summary.json").read_text())
    names = {p.name for p in d.iterdir()}
    if names != set(s["files"]) or s["rate"] != rate:
        return False
    rows = np.loadtxt(d / "setpoints.csv", delimiter=",", skiprows=1, usecols=(0,))
    return len(rows) == s["rows"] and abs(rows[1] - rows[0] - 1 / rate) < 1e-9


def _env(**extra: str) -> dict[str, str]:
    return {**os.environ, "PYTHONPATH": str(ROOT), **extra}


def _previous_run(out: Path) -> dict[str, bytes]:
    """A first run at 50 Hz with csv,pvt; its files byte for byte."""
    argv = [sys.executable, "-m", "trajopt.cli", "trajectory", *QUERY, "--rate", "50", "--format", "csv,pvt"]
    subprocess.run([*argv, "--out", str(out)], check=True, env=_env(), capture_output=True)
    snap = _snapshot(out)
    assert set(snap) == {"setpoints.csv", "pvt.csv", "summary.json"}
    return snap


STAGES = ("wrote setpoints.csv", "wrote summary.json", "commit", "committed")


@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM, signal.SIGINT], ids=["KILL", "TERM", "INT"])
def test_interrupted_at_every_stage_leaves_one_complete_set(tmp_path: Path, sig: int) -> None:
    out = tmp_path / "out"
    old = _previous_run(out)
    argv = [sys.executable, "-m", "trajopt.cli", "trajectory", *QUERY, "--rate", "100", "--out", str(out)]
    outcomes = []
    for stage in STAGES:
        env = _env(**{PAUSE_ENV: f"60@{stage}"})
        proc = subprocess.Popen(argv, env=env, stderr=subprocess.PIPE, stdout=subprocess.DEVNULL)
        assert proc.stderr is not None
        seen = []
        while True:
            line = proc.stderr.readline().decode()
            assert line, f"the run ended before stage {stage!r}: {seen}"
            seen.append(line.strip())
            if line.strip() == f"mpa-test-stage: {stage}":
                break
        proc.send_signal(sig)
        proc.wait(timeout=60)
        rest = proc.stderr.read().decode()
        proc.stderr.close()
        if sig == signal.SIGINT:
            assert proc.returncode == 130 and rest.strip() == "interrupted", (proc.returncode, rest)
        now = _snapshot(out)
        if now == old:
            outcomes.append("old")
        else:
            assert _complete_new_set(out, 100.0), (stage, sorted(now))
            outcomes.append("new")
            old = now  # the next interruption must keep this set
        hidden = [p.name for p in tmp_path.iterdir() if p.name != "out"]
        if sig == signal.SIGINT:  # cleaned up on the way out
            assert hidden == [], hidden
    print(sig, outcomes)
    assert outcomes[:3] == ["old", "old", "old"] and outcomes[3] == "new", outcomes
    # a dead writer's temporary directory is removed by the next write
    subprocess.run([*argv[:-2], "--out", str(out)], check=True, env=_env(), capture_output=True)
    assert [p.name for p in tmp_path.iterdir()] == ["out"]
    assert _complete_new_set(out, 100.0)


def _limit_file_size(limit: int) -> None:
    resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))


def test_full_disk_keeps_the_previous_set(tmp_path: Path) -> None:
    out = tmp_path / "out"
    old = _previous_run(out)
    argv = [sys.executable, "-m", "trajopt.cli", "trajectory", *QUERY, "--rate", "1000", "--out", str(out)]
    proc = subprocess.run(argv, env=_env(), capture_output=True, text=True, preexec_fn=lambda: _limit_file_size(65536))
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode == 2 and len(lines) == 1, proc.stderr
    assert lines[0] == f"error: --out: cannot write {str(out / 'setpoints.csv')!r}: File too large", lines
    assert _snapshot(out) == old
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def test_formats_not_asked_for_are_not_left_and_other_files_are_kept(tmp_path: Path) -> None:
    out = tmp_path / "out"
    write_directory(out, {"setpoints.csv": "a\n", "pvt.csv": "p\n", "summary.json": "{}\n"})
    (out / "notes.txt").write_text("mine")
    (out / "sub").mkdir()
    (out / "sub" / "x").write_text("x")
    write_directory(out, {"setpoints.csv": "b\n", "summary.json": "{}\n"})
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt", "setpoints.csv", "sub", "summary.json"]
    assert (out / "sub" / "x").read_text() == "x" and not (out / "pvt.csv").exists()
    assert (out / "setpoints.csv").read_text() == "b\n"
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def test_cli_after_csv_pvt_with_csv_only_drops_pvt(tmp_path: Path) -> None:
    out = tmp_path / "o"
    assert main(["trajectory", *QUERY, "--format", "csv,pvt", "--out", str(out)]) == 0
    assert (out / "pvt.csv").exists()
    assert main(["trajectory", *QUERY, "--rate", "50", "--out", str(out)]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["setpoints.csv", "summary.json"]
    assert _complete_new_set(out, 50.0)


def test_write_directory_through_a_symlink_keeps_the_link(tmp_path: Path) -> None:
    real = tmp_path / "real"
    write_directory(real, {"summary.json": "1\n"})
    link = tmp_path / "link"
    link.symlink_to(real)
    write_directory(link, {"summary.json": "2\n"})
    assert link.is_symlink() and (real / "summary.json").read_text() == "2\n"


def test_the_working_directory_is_written_in_place(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    write_directory(".", {"setpoints.csv": "a\n", "pvt.csv": "p\n", "summary.json": "{}\n"})
    (tmp_path / "mine.txt").write_text("keep")
    write_directory(".", {"setpoints.csv": "b\n", "summary.json": "{}\n"})
    assert Path("setpoints.csv").read_text() == "b\n"  # the working directory is still the directory
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mine.txt", "setpoints.csv", "summary.json"]
