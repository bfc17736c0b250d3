"""CSV / JSON export: pinned columns, constant step, endpoints at rest, limits at every row, atomic writes."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from mpa import Circle, Lollipop
from trajopt import CSV_COLUMNS, Limits, TrajectoryGenerator, generate_trajectory

LIMIT_RTOL = 1e-6
POS_TOL = 1e-9
HEADER = "time,a_track,a_s,a_v,a_a,a_j,b_track,b_s,b_v,b_a,b_j"


@pytest.fixture(scope="module")
def traj():  # type: ignore[no-untyped-def]
    return generate_trajectory(Lollipop(1.0, 1.0), (0.2, 0.5), (0.5, 0.2), vmax=0.4, amax=0.8, jmax=3.0)


def read_csv(path):  # type: ignore[no-untyped-def]
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    # the numeric columns (the paper tracks' CSV ends with the edge/offset/dir columns, whose edges are names)
    return rows[0], np.array([r[:11] for r in rows[1:]], dtype=float)


@pytest.mark.parametrize("rate", [None, 37.0, 250.0, 1000.0])
def test_csv_rows_keep_every_limit(traj, tmp_path, rate) -> None:  # type: ignore[no-untyped-def]
    path = tmp_path / "sp.csv"
    traj.to_csv(path, rate=rate)
    header, data = read_csv(path)
    assert ",".join(header).startswith(HEADER)
    assert tuple(header) == CSV_COLUMNS
    hz = traj.rate if rate is None else rate
    t = data[:, 0]
    np.testing.assert_allclose(t, np.arange(len(t)) / hz, atol=1e-9)
    assert t[-1] >= traj.motion_time - 1e-12 and t[-1] - traj.motion_time < 1.0 / hz + 1e-9
    lim = traj.limits
    for r, off in ((0, 1), (1, 6)):
        for k, name, m in ((2, "v", lim.v[r]), (3, "a", lim.a[r]), (4, "j", lim.j[r])):
            col = np.abs(data[:, off + k])
            bad = np.flatnonzero(col > m * (1 + LIMIT_RTOL))
            assert len(bad) == 0, f"robot {'AB'[r]} |{name}| rows {bad[:5]}: {col[bad[:5]]} > {m}"
        # first and last rows: start and goal, at rest
        for row in (0, -1):
            assert abs(data[row, off + 2]) <= POS_TOL and abs(data[row, off + 3]) <= POS_TOL
    np.testing.assert_allclose(data[0, [1, 6]], traj.plan.start, atol=POS_TOL)
    np.testing.assert_allclose(data[-1, [1, 6]], traj.plan.goal, atol=POS_TOL)
    # *_s is continuous (route coordinate), *_track wraps round the loop
    assert np.max(np.abs(np.diff(data[:, [2, 7]], axis=0))) <= lim.v.max() / hz * (1 + 1e-6) + 1e-9
    assert list(tmp_path.iterdir()) == [path]  # no temporary file left behind


def test_csv_default_rate_matches_arrays(traj, tmp_path) -> None:  # type: ignore[no-untyped-def]
    traj.to_csv(tmp_path / "a.csv")
    _, data = read_csv(tmp_path / "a.csv")
    assert data.shape == (len(traj.t), 11) and len(CSV_COLUMNS) == 17
    np.testing.assert_allclose(data[:, 2], traj.s[:, 0], atol=1e-9)
    np.testing.assert_allclose(data[:, 9], traj.a[:, 1], atol=1e-9)
    assert traj.makespan == pytest.approx(traj.t[-1])


def test_json_summary(traj, tmp_path) -> None:  # type: ignore[no-untyped-def]
    traj.to_json(tmp_path / "s.json")
    js = json.loads((tmp_path / "s.json").read_text())
    for key in (
        "makespan",
        "min_separation",
        "domain",
        "fallback",
        "fallback_reason",
        "limits",
        "clearance",
        "rate",
        "word",
        "solver",
        "timings",
    ):
        assert key in js, key
    assert isinstance(js["fallback"], bool) and isinstance(js["domain"], int)
    assert js["makespan"] == pytest.approx(traj.makespan)
    assert js["min_separation"] >= js["clearance"]
    assert js["limits"]["vmax"] == [0.4, 0.4]


def test_trajectory_shapes_and_units(traj) -> None:  # type: ignore[no-untyped-def]
    n = len(traj.t)
    for name in ("track", "s", "v", "a", "j"):
        assert getattr(traj, name).shape == (n, 2), name
    assert traj.min_separation >= traj.clearance


def test_stationary_query_and_circle_rate(tmp_path) -> None:  # type: ignore[no-untyped-def]
    traj = TrajectoryGenerator(Circle(1.0), clearance=0.1, limits=Limits(0.3, 0.5, 2.0), rate=50).generate(
        (0.1, 0.6), (0.1, 0.6)
    )
    assert traj.makespan == 0.0 and len(traj.t) == 1 and traj.verification["ok"]
    traj.to_csv(tmp_path / "x.csv", rate=10)
    _, data = read_csv(tmp_path / "x.csv")
    assert data.shape == (1, 11)


def test_per_robot_limits() -> None:
    traj = generate_trajectory(Lollipop(1.0, 1.0), (0.1, 0.6), (0.8, 0.3), vmax=(0.5, 0.2), amax=(1.0, 0.4))
    assert np.abs(traj.v[:, 1]).max() <= 0.2 * (1 + LIMIT_RTOL)
    assert np.abs(traj.a[:, 1]).max() <= 0.4 * (1 + LIMIT_RTOL)
    assert traj.verification["ok"]
