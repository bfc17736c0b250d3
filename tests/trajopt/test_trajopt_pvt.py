"""PVT tables: rows on the grid, Hermite reconstruction checked independently, failing intervals named."""

from __future__ import annotations

import csv
import dataclasses
import os

import numpy as np
import pytest

from mpa import InvalidInputError, Lollipop, MPAError
from trajopt import generate_trajectory
from trajopt.io.pvt import (
    PVT_COLUMNS,
    check_pvt,
    hermite_eval,
    largest_pvt_interval,
    pvt_rows,
    pvt_table,
    smallest_pvt_stretch,
    write_pvt,
)

LIMIT_RTOL = 1e-6
DENSE = 20_000  # samples per second of the independent check
L = Lollipop(1.0, 1.0)


@pytest.fixture(scope="module")
def canon():  # type: ignore[no-untyped-def]
    """Default limits: the jerk-limited phases last 0.2 s, so a 0.1 s grid reproduces the motion's peaks."""
    return generate_trajectory(L, (0.1, 0.6), (0.8, 0.3))


@pytest.fixture(scope="module")
def tight():  # type: ignore[no-untyped-def]
    """vmax 0.4, amax 0.8, jmax 3: phases of 0.267 s, off any round grid."""
    return generate_trajectory(L, (0.2, 0.5), (0.5, 0.2), vmax=0.4, amax=0.8, jmax=3.0)


def reconstruction(traj, tab):  # type: ignore[no-untyped-def]
    """Dense samples of the reconstruction: separation, and per-piece peaks of v, a, j (independent of pvt.py)."""
    n = int(tab.t[-1] * DENSE) + 2
    tg = np.linspace(0.0, tab.t[-1], n)
    s, v, _, _ = hermite_eval(tab.t, tab.s, tab.v, tg)
    r = traj.plan.routes
    d = traj.plan.track.distance(r[0].position(s[:, 0]), r[1].position(s[:, 1]))
    # a and j inside each piece by finite differences of v sampled strictly inside the piece
    apk, jpk = np.zeros(2), np.zeros(2)
    for k in range(len(tab.t) - 1):
        tt = np.linspace(tab.t[k], tab.t[k + 1], 41)[1:-1]
        _, vv, aa, jj = hermite_eval(tab.t, tab.s, tab.v, tt)
        fd_a = np.diff(vv, axis=0) / np.diff(tt)[:, None]
        fd_j = np.diff(aa, axis=0) / np.diff(tt)[:, None]
        np.testing.assert_allclose(fd_j, np.broadcast_to(jj[0], fd_j.shape), rtol=1e-5, atol=1e-6, err_msg=f"{k}")
        apk = np.maximum(apk, np.max(np.abs(aa), axis=0))
        apk = np.maximum(apk, np.max(np.abs(fd_a), axis=0) - 1e-6)
        jpk = np.maximum(jpk, np.abs(jj[0]))
    return d, np.max(np.abs(v), axis=0), apk, jpk


def test_rows_on_the_grid(canon) -> None:  # type: ignore[no-untyped-def]
    tab = pvt_table(canon, 0.1)
    assert tab.stretch == 1.0
    steps = np.diff(tab.t)
    np.testing.assert_allclose(tab.t[:-1], 0.1 * np.arange(len(tab.t) - 1), atol=1e-12)
    assert tab.t[-1] == canon.motion_time
    assert np.all(steps >= 0.1 / 100) and np.all(steps <= 0.1 * 1.01 + 1e-12)
    np.testing.assert_array_equal(tab.s[0], [0.0, 0.0])
    np.testing.assert_array_equal(tab.s[-1], canon.s[-1])
    np.testing.assert_array_equal(tab.v[[0, -1]], np.zeros((2, 2)))
    s, v, _, _ = canon.sampler(tab.t[1:-1])
    np.testing.assert_allclose(tab.s[1:-1], s, atol=1e-12)
    np.testing.assert_allclose(tab.v[1:-1], v, atol=1e-12)


def test_reconstruction_interpolates_c1(canon) -> None:  # type: ignore[no-untyped-def]
    tab = pvt_rows(canon, 0.1)
    s, v, _, _ = hermite_eval(tab.t, tab.s, tab.v, tab.t)
    np.testing.assert_allclose(s, tab.s, atol=1e-12)
    np.testing.assert_allclose(v[:-1], tab.v[:-1], atol=1e-12)
    eps = 1e-9
    sl, vl, _, _ = hermite_eval(tab.t, tab.s, tab.v, tab.t[1:-1] - eps)
    np.testing.assert_allclose(sl, tab.s[1:-1], atol=1e-8)
    np.testing.assert_allclose(vl, tab.v[1:-1], atol=1e-7)
    # at rest before and after
    s0, v0, a0, _ = hermite_eval(tab.t, tab.s, tab.v, np.array([-1.0, tab.t[-1] + 1.0]))
    np.testing.assert_array_equal(s0, tab.s[[0, -1]])
    assert not np.any(v0) and not np.any(a0)


@pytest.mark.parametrize("interval", [0.1, 0.05, 1.0])
def test_accepted_tables_keep_clearance_and_limits(canon, interval) -> None:  # type: ignore[no-untyped-def]
    tab = pvt_table(canon, interval)
    d, vpk, apk, jpk = reconstruction(canon, tab)
    assert d.min() >= canon.clearance - 1e-9, d.min()
    lim = canon.limits
    assert np.all(vpk <= lim.v * (1 + LIMIT_RTOL)), vpk
    assert np.all(apk <= lim.a * (1 + LIMIT_RTOL)), apk
    assert np.all(jpk <= lim.j * (1 + LIMIT_RTOL)), jpk


def test_failing_interval_names_the_largest_that_works(canon, tmp_path) -> None:  # type: ignore[no-untyped-def]
    chk = check_pvt(canon, 0.5)
    assert not chk.ok
    # the failure is real: the reconstruction's velocity exceeds vmax somewhere
    _, vpk, _, _ = reconstruction(canon, pvt_rows(canon, 0.5))
    assert np.any(vpk > canon.limits.v * (1 + LIMIT_RTOL))
    with pytest.raises(InvalidInputError, match=r"PVT interval 0\.5 s.*largest interval that works is 0\.2 s"):
        write_pvt(canon, tmp_path / "pvt.csv", 0.5)
    assert list(tmp_path.iterdir()) == []
    assert largest_pvt_interval(canon, 0.5) == 0.2
    # 0.2 s passes, the round intervals between it and 0.5 s do not
    assert check_pvt(canon, 0.2).ok and not check_pvt(canon, 0.25).ok and not check_pvt(canon, 0.4).ok


def test_off_grid_motion_gets_fitted_row_velocities(tight, tmp_path) -> None:  # type: ignore[no-untyped-def]
    """Phases off the grid: the cubics through exact samples overshoot amax; the fitted velocities keep it."""
    exact = pvt_rows(tight, 0.1, fit=False)
    _, _, apk, _ = reconstruction(tight, exact)
    assert np.any(apk > tight.limits.a * (1 + LIMIT_RTOL)), apk  # the overshoot of exact samples is real
    assert exact.velocity_change == 0.0
    tab = write_pvt(tight, tmp_path / "pvt.csv", "auto")
    assert tab.interval == 0.1 and tab.stretch == 1.0
    assert 0.0 < tab.velocity_change < 0.01, tab.velocity_change
    d, vpk, apk, jpk = reconstruction(tight, tab)
    lim = tight.limits
    assert d.min() >= tight.clearance - 1e-9
    assert np.all(vpk <= lim.v * (1 + LIMIT_RTOL)) and np.all(apk <= lim.a * (1 + LIMIT_RTOL)), (vpk, apk)
    assert np.all(jpk <= lim.j * (1 + LIMIT_RTOL)), jpk
    # positions at the rows are the motion's; velocities moved by at most velocity_change
    np.testing.assert_array_equal(tab.t, exact.t)
    np.testing.assert_array_equal(tab.s, exact.s)
    assert np.max(np.abs(tab.v - exact.v)) == tab.velocity_change
    assert tab.v[0].tolist() == [0.0, 0.0] and tab.v[-1].tolist() == [0.0, 0.0]


def test_stretch_samples_the_same_path(canon, tmp_path) -> None:  # type: ignore[no-untyped-def]
    """An interval no fit rescues (0.5 s) works with the motion slowed: the rows sample s(t/k)."""
    with pytest.raises(InvalidInputError, match=r"0\.5 s works with the motion slowed"):
        pvt_table(canon, 0.5)
    k = smallest_pvt_stretch(canon, 0.5)
    assert k is not None and 1.0 < k <= 1.1
    tab = write_pvt(canon, tmp_path / "pvt.csv", 0.5, max_stretch=1.1)
    assert tab.stretch == k
    assert tab.t[-1] == pytest.approx(k * canon.motion_time, rel=1e-12)
    d, vpk, apk, jpk = reconstruction(canon, tab)
    lim = canon.limits
    assert d.min() >= canon.clearance - 1e-9
    assert np.all(vpk <= lim.v * (1 + LIMIT_RTOL)) and np.all(apk <= lim.a * (1 + LIMIT_RTOL))
    assert np.all(jpk <= lim.j * (1 + LIMIT_RTOL))
    s, v, _, _ = canon.sampler(tab.t[1:-1] / k)
    np.testing.assert_allclose(tab.s[1:-1], s, atol=1e-12)
    np.testing.assert_allclose(tab.v[1:-1], v / k, atol=tab.velocity_change + 1e-12)


@pytest.mark.parametrize("seed", range(4))
def test_auto_interval_on_random_queries_and_limits(seed) -> None:  # type: ignore[no-untyped-def]
    """Seeded queries with limits drawn off any round grid: auto finds an interval and its cubics keep
    clearance and limits (independent dense check)."""
    rng = np.random.default_rng(seed)
    for _ in range(20):
        st, gl = rng.uniform(0.0, 2.0, 2), rng.uniform(0.0, 2.0, 2)
        try:
            traj = generate_trajectory(
                L, tuple(st), tuple(gl), vmax=rng.uniform(0.2, 0.8), amax=rng.uniform(0.3, 1.5), jmax=rng.uniform(1, 8)
            )
        except MPAError:  # a query with no motion: draw another
            continue
        break
    else:
        pytest.fail(f"seed {seed}: no query with a motion")
    tab = pvt_table(traj, "auto")
    d, vpk, apk, jpk = reconstruction(traj, tab)
    lim = traj.limits
    info = (seed, st, gl, lim, tab.interval, tab.velocity_change)
    assert d.min() >= traj.clearance - 1e-9, info
    assert np.all(vpk <= lim.v * (1 + LIMIT_RTOL)) and np.all(apk <= lim.a * (1 + LIMIT_RTOL)), (info, vpk, apk)
    assert np.all(jpk <= lim.j * (1 + LIMIT_RTOL)), (info, jpk)


def test_separation_cut_by_the_cubic_is_caught() -> None:
    """Queries whose reconstruction passes closer than the motion itself (measured: by 1 mm at 1 s), D just below
    the motion's minimum."""
    cases = 0
    for st, gl, dlt in (((0.38, 1.86), (1.1, 0.36), 1.0), ((0.04, 0.62), (1.88, 1.08), 0.5)):
        traj = generate_trajectory(L, st, gl, clearance=0.1)
        tab = pvt_rows(traj, dlt)
        tg = np.linspace(0.0, traj.motion_time, 200_001)
        r, track = traj.plan.routes, traj.plan.track
        s_true = traj.sampler(tg)[0]
        true_min = float(np.min(track.distance(r[0].position(s_true[:, 0]), r[1].position(s_true[:, 1]))))
        d_rec, _, _, _ = reconstruction(traj, tab)
        if d_rec.min() > true_min - 5e-7:
            continue
        cases += 1
        strict = dataclasses.replace(traj, clearance=true_min - 2e-7)
        chk = check_pvt(strict, dlt, 1.0)
        assert any("separation" in f for f in chk.failures), chk.failures
        if d_rec.min() < traj.clearance:  # the cubic cuts below the real D: the trajectory's own check fails too
            assert any("separation" in f for f in check_pvt(traj, dlt).failures)
    assert cases >= 1


@pytest.mark.parametrize("bad", [0, -0.1, float("nan"), float("inf"), "x", 1e-4])
def test_bad_interval(canon, tmp_path, bad) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(InvalidInputError, match="PVT interval"):
        write_pvt(canon, tmp_path / "p.csv", bad)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("bad", [0.5, float("nan"), "y"])
def test_bad_stretch(canon, bad) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(InvalidInputError, match="stretch"):
        pvt_table(canon, 0.1, max_stretch=bad)


def test_file_round_trip(canon, tmp_path) -> None:  # type: ignore[no-untyped-def]
    path = tmp_path / "pvt.csv"
    tab = write_pvt(canon, path, 0.1)
    assert sorted(os.listdir(tmp_path)) == ["pvt.csv"]
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    assert tuple(rows[0]) == PVT_COLUMNS
    data = np.array(rows[1:], dtype=float)
    assert data.shape == (len(tab.t), 5)
    np.testing.assert_array_equal(data[:, 0], tab.t)
    np.testing.assert_allclose(data[:, [1, 3]], tab.s, rtol=1e-11, atol=1e-12)
    np.testing.assert_allclose(data[:, [2, 4]], tab.v, rtol=1e-11, atol=1e-12)
    assert data[-1, 0] == canon.motion_time


def test_pvt_of_a_replan_starts_moving() -> None:
    """A re-planned motion starts moving: its first PVT row keeps the velocity, and the check accepts it."""
    from trajopt import TrajectoryGenerator
    from trajopt.io.pvt import hermite_eval

    gen = TrajectoryGenerator(Lollipop(1.0, 1.0), clearance=0.05)
    new = gen.replan(gen.generate((0.2, 0.5), (0.5, 0.2)), 1.3, (0.7, 0.35))
    assert np.all(np.abs(new.v[0]) > 0.1)
    tab = pvt_table(new, 0.1)
    np.testing.assert_array_equal(tab.v[0], new.v[0])
    assert tab.s[0].tolist() == [0.0, 0.0] and tab.v[-1].tolist() == [0.0, 0.0]
    tq = np.linspace(0.0, tab.t[-1], 20_001)
    _s, v, _a, _j = hermite_eval(tab.t, tab.s, tab.v, tq)
    assert float(np.max(np.abs(v))) <= 0.5 * (1 + 1e-6)
