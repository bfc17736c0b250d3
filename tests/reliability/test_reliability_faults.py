"""Fault injection (reliability issue, item 4): every solver failure gives a verified fallback with a reason;
a killed writer never leaves a partial file; two writers never interleave their files."""

from __future__ import annotations

import dataclasses
import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

import trajopt.generator as genmod
import trajopt.path.corridor as corridor
import trajopt.timing as timing
from mpa import Lollipop, PlanningError
from trajopt import TrajectoryGenerator
from trajopt.testing import check_trajectory

ROOT = Path(__file__).resolve().parents[2]
TRACK = Lollipop(1.0, 1.0)
#: Queries whose straight route-coordinate motion is blocked: they take the hard path (corridor QP, timing filter).
HARD = [((0.1, 0.6), (1.5, 0.3)), ((0.17, 0.47), (1.6, 1.16)), ((0.06, 1.41), (0.75, 0.18))]
#: Queries taken by the fast path (one ruckig profile along the straight line).
FAST = [((0.2, 0.5), (0.5, 0.2)), ((0.9, 1.7), (0.3, 1.2)), ((0.1, 0.3), (0.6, 0.9))]
QUERIES = HARD


def test_the_queries_take_the_paths_they_are_meant_to() -> None:
    gen = TrajectoryGenerator(TRACK, clearance=0.05)
    for queries, path in ((HARD, "hard"), (FAST, "fast")):
        for s, g in queries:
            traj = gen.generate(s, g)
            assert traj.solver_stats.get("path") == path and not traj.fallback, (s, g, traj.solver_stats)


def _all_fall_back(match: str, queries: list = HARD) -> None:  # type: ignore[type-arg]
    gen = TrajectoryGenerator(TRACK, clearance=0.05)
    for s, g in queries:
        traj = gen.generate(s, g)
        assert traj.fallback, (s, g)
        assert match in traj.fallback_reason, traj.fallback_reason
        assert traj.verification["ok"]
        assert not check_trajectory(traj, s, g), check_trajectory(traj, s, g)


def test_qp_solver_raises(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    def boom(self, *a, **k):  # type: ignore[no-untyped-def]
        raise RuntimeError("Error in Function::call for 'corridor32' [DaqpInterface] at .../casadi: Invalid_Number")

    monkeypatch.setattr(corridor.CorridorProblem, "solve", boom)
    _all_fall_back("solver error: Error in Function::call")


def test_qp_solver_reports_failure(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    real = corridor.CorridorProblem.solve

    def failed(self, *a, **k):  # type: ignore[no-untyped-def]
        nodes, stats = real(self, *a, **k)
        stats.update(qp_success=False, qp_status="INFEASIBLE")
        return nodes, stats

    monkeypatch.setattr(corridor.CorridorProblem, "solve", failed)
    _all_fall_back("corridor QP failed: INFEASIBLE")


@pytest.mark.parametrize("garbage", ["nan", "random", "huge", "reversed"])
def test_qp_solver_returns_garbage(monkeypatch, garbage) -> None:  # type: ignore[no-untyped-def]
    real = corridor.CorridorProblem.solve
    rng = np.random.default_rng(0)

    def bad(self, *a, **k):  # type: ignore[no-untyped-def]
        nodes, stats = real(self, *a, **k)
        if garbage == "nan":
            nodes[1:-1] = np.nan
        elif garbage == "random":
            nodes[1:-1] = rng.uniform(-3, 3, nodes[1:-1].shape)
        elif garbage == "huge":
            nodes[1:-1] = 1e300
        else:
            nodes[1:-1] = nodes[-2:0:-1]
        return nodes, stats

    monkeypatch.setattr(corridor.CorridorProblem, "solve", bad)
    gen = TrajectoryGenerator(TRACK, clearance=0.05)
    for s, g in QUERIES:
        traj = gen.generate(s, g)
        # garbage must never reach the output: either caught (fallback with a reason) or harmless and verified
        assert traj.verification["ok"]
        assert not check_trajectory(traj, s, g)
        if traj.fallback:
            assert traj.fallback_reason


def test_timing_returns_none(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    monkeypatch.setattr(timing, "filtered_scaling", lambda *a, **k: None)
    _all_fall_back("optimisation failed (AttributeError")


def test_timing_raises(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    def boom(*a, **k):  # type: ignore[no-untyped-def]
        raise ValueError("timing: infeasible instance")

    monkeypatch.setattr(timing, "filtered_scaling", boom)
    _all_fall_back("timing: infeasible instance")


def test_timing_returns_a_motion_off_the_path(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    real = timing.filtered_scaling

    def stretched(*a, **k):  # type: ignore[no-untyped-def]
        sc = real(*a, **k)
        return dataclasses.replace(sc, j=sc.j * 3.0)  # jerk over the limit and positions off the profile

    monkeypatch.setattr(timing, "filtered_scaling", stretched)
    _all_fall_back("verification failed: row")  # the gate names the rows whose jerk (and acceleration) is over


def test_fast_path_raises(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    def boom(*a, **k):  # type: ignore[no-untyped-def]
        raise RuntimeError("[ruckig] error in step 2 in dof 0")

    monkeypatch.setattr(genmod, "straight_scaling", boom)
    _all_fall_back("solver error: [ruckig] error in step 2", FAST)


class _FlakyRuckig:
    """``ruckig.Ruckig`` whose first instance raises in ``calculate`` (the optimised stage's)."""

    made = 0

    def __init__(self, *a):  # type: ignore[no-untyped-def]
        _FlakyRuckig.made += 1
        self.broken = _FlakyRuckig.made == 1
        self.real = _REAL_RUCKIG(*a)

    def calculate(self, *a):  # type: ignore[no-untyped-def]
        if self.broken:
            raise RuntimeError("[ruckig] error in step 2 in dof 0")
        return self.real.calculate(*a)


import ruckig as _ruckig  # noqa: E402

_REAL_RUCKIG = _ruckig.Ruckig


def test_ruckig_raises_in_the_optimised_stage(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    gen = TrajectoryGenerator(TRACK, clearance=0.05)
    for s, g in FAST:  # the fast path's profile is the first ruckig call; the fallback's the second
        _FlakyRuckig.made = 0
        monkeypatch.setattr(_ruckig, "Ruckig", _FlakyRuckig)
        traj = gen.generate(s, g)
        monkeypatch.setattr(_ruckig, "Ruckig", _REAL_RUCKIG)
        assert traj.fallback and "ruckig" in traj.fallback_reason, traj.fallback_reason
        assert traj.verification["ok"] and not check_trajectory(traj, s, g)


def test_ruckig_always_fails_is_a_planning_error(monkeypatch, tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    class Broken(_FlakyRuckig):
        def calculate(self, *a):  # type: ignore[no-untyped-def]
            raise RuntimeError("[ruckig] broken")

    monkeypatch.setattr(_ruckig, "Ruckig", Broken)
    with pytest.raises(PlanningError, match="ruckig"):
        TrajectoryGenerator(TRACK, clearance=0.05).generate((0.2, 0.5), (0.5, 0.2))
    from trajopt.cli import main

    out = tmp_path / "o"
    code = main(
        ["trajectory", "--track", "lollipop", "--start", "0.2", "0.5", "--goal", "0.5", "0.2", "--out", str(out)]
    )
    err = capsys.readouterr().err
    assert code == 4 and err.startswith("internal error:") and len(err.strip().splitlines()) == 1, err
    assert not out.exists()


# --- files ----------------------------------------------------------------------------------------------
WRITER = textwrap.dedent(
    """
    import sys
    from trajopt.export import atomic_write_bytes
    target, size = sys.argv[1], int(sys.argv[2])
    block = b"0123456789abcdef" * (size // 16)
    print("ready", flush=True)
    while True:
        atomic_write_bytes(target, block)
    """
)


def test_kill_9_during_a_large_write_never_leaves_a_partial_file(tmp_path) -> None:  # type: ignore[no-untyped-def]
    target = tmp_path / "setpoints.csv"
    size = 64 * 2**20
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    for attempt in range(3):
        proc = subprocess.Popen([sys.executable, "-c", WRITER, str(target), str(size)], stdout=subprocess.PIPE, env=env)
        assert proc.stdout is not None and proc.stdout.readline().strip() == b"ready"
        deadline = time.time() + 30
        while not list(tmp_path.glob(".setpoints.csv.*.tmp")) and time.time() < deadline:
            time.sleep(0.001)  # wait until a write is under way
        time.sleep(0.01 * attempt)
        proc.send_signal(signal.SIGKILL)
        proc.wait()
        proc.stdout.close()
        if target.exists():  # a complete earlier write, never a partial one
            assert target.stat().st_size == size
            with open(target, "rb") as fh:
                head = fh.read(16)
            assert head == b"0123456789abcdef"
    leftovers = list(tmp_path.glob(".setpoints.csv.*.tmp"))
    # the next write removes the dead writer's temporary files
    from trajopt.export import atomic_write_text

    atomic_write_text(target, "time\n")
    assert target.read_text() == "time\n"
    assert not list(tmp_path.glob(".setpoints.csv.*.tmp")), leftovers


MULTI = textwrap.dedent(
    """
    import sys, time
    import trajopt.cli.trajectory as ct
    out, tag, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
    real = ct.atomic_write_text
    def slow(path, text):
        real(path, text)
        time.sleep(0.01)  # widen the window between the files of one run
    ct.atomic_write_text = slow
    for i in range(n):
        files = {"setpoints.csv": f"{tag} {i}\\n" * 1000, "summary.json": f'{{"tag": "{tag}", "i": {i}}}'}
        ct.write_outputs(out, files)
    """
)
READER = textwrap.dedent(
    """
    import json, sys, time
    from pathlib import Path
    from trajopt.cli.trajectory import output_lock
    out, seconds = Path(sys.argv[1]), float(sys.argv[2])
    bad = 0
    end = time.time() + seconds
    checks = 0
    while time.time() < end:
        if (out / "summary.json").exists():
            with output_lock(out):
                s = json.loads((out / "summary.json").read_text())
                lines = set((out / "setpoints.csv").read_text().splitlines())
            checks += 1
            if lines != {f"{s['tag']} {s['i']}"}:
                bad += 1
        time.sleep(0.002)
    print(checks, bad)
    """
)


def test_two_processes_writing_one_directory_never_interleave(tmp_path) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "shared"
    out.mkdir()
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    writers = [
        subprocess.Popen([sys.executable, "-c", MULTI, str(out), tag, "40"], env=env) for tag in ("alpha", "beta")
    ]
    reader = subprocess.Popen([sys.executable, "-c", READER, str(out), "3"], env=env, stdout=subprocess.PIPE)
    for w in writers:
        assert w.wait(timeout=120) == 0
    stdout, _ = reader.communicate(timeout=120)
    checks, bad = map(int, stdout.split())
    assert checks > 0 and bad == 0, (checks, bad)
    s = json.loads((out / "summary.json").read_text())
    assert set((out / "setpoints.csv").read_text().splitlines()) == {f"{s['tag']} {s['i']}"}
    assert sorted(p.name for p in out.iterdir()) == ["setpoints.csv", "summary.json"]
