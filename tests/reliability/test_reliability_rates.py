"""Every export verified at its own rate (reliability issue, item 1).

``Trajectory.at_rate``/``resample``/``to_csv(rate=...)`` and the command line's ``--rate`` pass the gate at that
rate, re-time the plan when the resampled motion does not, and otherwise name the lowest usable rate; the
rows are re-checked by the independent checker :mod:`trajopt.testing`.
"""

from __future__ import annotations

import contextlib
import io
import re

import numpy as np
import pytest

from mpa import Circle, Interval, InvalidInputError, Lollipop, NoMotionError, Track, plan
from trajopt import Limits, TrajectoryGenerator, generate_trajectory
from trajopt.cli import main
from trajopt.export import CSV_COLUMNS
from trajopt.testing import check_setpoints, check_trajectory

RATES = (1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 250.0, 1000.0)
LOWEST = re.compile(r"the lowest usable rate is ([0-9.e+]+) Hz")


def _queries(track: Track, clearance: float, n: int, seed: int) -> list[tuple[np.ndarray, np.ndarray]]:
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        s, g = rng.uniform(0, track.total_length, 2), rng.uniform(0, track.total_length, 2)
        if track.distance(*s) >= clearance + 1e-3 and track.distance(*g) >= clearance + 1e-3:
            out.append((s, g))
    return out


CASES = [
    (Lollipop(1.0, 1.0), 0.05, Limits(0.5, 1.0, 5.0)),
    (Lollipop(0.4, 1.5), 0.1, Limits(1.5, 4.0, 40.0)),
    (Circle(1.0), 0.05, Limits(0.5, 1.0, 5.0)),
    (Circle(2.5), 0.3, Limits(2.0, 5.0, 50.0)),
    (Interval(1.75), 0.0, Limits(1.43, 1.41, 14.1)),
]


@pytest.mark.parametrize(("track", "clearance", "limits"), CASES, ids=lambda x: repr(x)[:30])
def test_every_rate_verified_or_lowest_rate_named(track: Track, clearance: float, limits: Limits) -> None:
    gen = TrajectoryGenerator(track, clearance=clearance, limits=limits)
    stats = {"resampled": 0, "retimed": 0, "too_low": 0}
    done = 0
    for s, g in _queries(track, clearance, 6, seed=42):
        try:
            traj = gen.generate(s, g)
        except NoMotionError:
            continue
        done += 1
        for r in RATES:
            try:
                t2 = traj.at_rate(r)
            except InvalidInputError as exc:
                m = LOWEST.search(str(exc))
                assert m, str(exc)
                best = float(m.group(1))
                assert best > r
                stats["too_low"] += 1
                t2 = traj.at_rate(best)  # the rate it names works
                r = best
            assert t2.rate == r and t2.verification["ok"]
            assert not check_trajectory(t2, s, g, fine=2), (s.tolist(), g.tolist(), r, check_trajectory(t2, s, g))
            stats["retimed" if "retimed_for_rate" in t2.solver_stats else "resampled"] += 1
            # resample() and csv_text() give the same verified rows
            rows = t2.resample(None)
            assert np.array_equal(rows[0], traj.resample(r)[0])
    assert done >= 3
    print(track, stats)


def test_resample_rejected_by_gate_is_retimed(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    """Force the resampled rows to fail the gate: the export is then the re-timed plan, verified."""
    traj = generate_trajectory(Lollipop(1.0, 1.0), (0.2, 0.5), (0.5, 0.2))
    import trajopt.path.planview as ex  # Trajectory.at_rate verifies through PlanView.verify
    from trajopt.verify.gate import VerificationReport

    real = ex.verify_setpoints
    calls = {"n": 0}

    def first_fails(*a, **k):  # type: ignore[no-untyped-def]
        calls["n"] += 1
        if calls["n"] == 1:
            return VerificationReport(False, ("forced failure",), 0.0, 0.0, {}, ())
        return real(*a, **k)

    monkeypatch.setattr(ex, "verify_setpoints", first_fails)
    t2 = traj.at_rate(20.0)
    assert "forced failure" in t2.solver_stats["retimed_for_rate"]
    assert t2.rate == 20.0 and t2.verification["ok"]
    assert not check_trajectory(t2)


def test_to_csv_at_rate_writes_only_verified_rows(tmp_path) -> None:  # type: ignore[no-untyped-def]
    track = Lollipop(1.0, 1.0)
    traj = generate_trajectory(track, (0.2, 0.5), (0.5, 0.2), vmax=2.0, amax=5.0, jmax=50.0)
    for r in (2.0, 5.0, 10.0, 20.0):
        path = tmp_path / f"r{r:g}.csv"
        try:
            traj.to_csv(path, rate=r)
        except InvalidInputError as exc:
            assert LOWEST.search(str(exc)) and not path.exists()
            continue
        data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2, usecols=range(11))
        assert path.read_text().splitlines()[0] == ",".join(CSV_COLUMNS)
        lim = traj.limits
        fails = check_setpoints(
            track,
            data[:, 0],
            data[:, [1, 6]],
            data[:, [2, 7]],
            data[:, [3, 8]],
            data[:, [4, 9]],
            data[:, [5, 10]],
            rate=r,
            clearance=traj.clearance,
            vmax=lim.v,
            amax=lim.a,
            jmax=lim.j,
            start=(0.2, 0.5),
            goal=(0.5, 0.2),
        )
        # the CSV keeps 12 significant digits: only round-off at the 1e-12 level may differ from the arrays
        assert not [f for f in fails if "row at" not in f and "not at rest" not in f], (r, fails)


def run(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def test_issue_interval_case_at_20_hz(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """`--rate 20` on this interval query used to exit 2 with "may drop to -inf"."""
    argv = "trajectory --track interval --stick 1.75140224151655 --start 0.345339 0.32789 --goal 1.04454 0.989143"
    argv += " --clearance 0 --vmax 1.4309025807182407 --amax 1.4108620188787198 --jmax 14.08945308031903 --rate 20"
    code, _out, err = run([*argv.split(), "--out", str(tmp_path / "o")])
    assert code == 0, err
    assert (tmp_path / "o" / "setpoints.csv").exists()


def test_rate_too_low_names_the_lowest_usable_rate(tmp_path) -> None:  # type: ignore[no-untyped-def]
    base = ["trajectory", "--track", "lollipop", "--start", "0.2", "0.5", "--goal", "0.5", "0.2"]
    code, _out, err = run([*base, "--rate", "0.2", "--out", str(tmp_path / "a")])
    assert code == 2 and err.startswith("error: rate is 0.2 Hz, too low") and len(err.strip().splitlines()) == 1
    assert "-inf" not in err
    m = LOWEST.search(err)
    assert m, err
    assert not (tmp_path / "a").exists()
    code, _out, err = run([*base, "--rate", m.group(1), "--out", str(tmp_path / "b")])
    assert code == 0, err


def test_robots_exactly_the_clearance_apart() -> None:
    """0.25 - 0.2 < 0.05 in floating point: accepted within CLEARANCE_TOL, printed with enough digits."""
    track = Lollipop(1.0, 1.0)
    p = plan(track, (0.2, 0.25), (0.5, 0.2), clearance=0.05)
    assert p.min_distance() >= 0.05 - 1e-12
    with pytest.raises(InvalidInputError, match=r"distance 0\.04999999 m|distance 0\.0499999"):
        plan(track, (0.2, 0.24999999), (0.5, 0.2), clearance=0.05)
    # a trajectory must leave the start at rest exactly at D: the gate needs a fine enough grid, and says so
    gen = TrajectoryGenerator(track, clearance=0.05)
    with pytest.raises(InvalidInputError) as info:
        gen.generate((0.2, 0.25), (0.5, 0.2))
    m = LOWEST.search(str(info.value))
    assert m, str(info.value)
    traj = TrajectoryGenerator(track, clearance=0.05, rate=float(m.group(1))).generate((0.2, 0.25), (0.5, 0.2))
    assert traj.verification["ok"] and not check_trajectory(traj, fine=2)
