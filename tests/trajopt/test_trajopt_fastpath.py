"""The fast path: a free straight route-coordinate motion is one phase-synchronised ruckig profile, then the gate."""

from __future__ import annotations

import numpy as np
import pytest

from mpa import Circle, Lollipop
from trajopt import TrajectoryGenerator
from trajopt.path.fastpath import straight_line_clearance
from trajopt.path.planview import route_geometry
from trajopt.timing import min_time_rest_to_rest


def test_free_straight_line_takes_the_fast_path() -> None:
    gen = TrajectoryGenerator(Lollipop(1.0, 1.0), clearance=0.05)
    traj = gen.generate((0.1, 0.6), (0.3, 0.8))  # both slide 0.2 along the stick
    assert traj.solver_stats["path"] == "fast" and not traj.fallback and traj.verification["ok"]
    ends = np.asarray(traj.plan.waypoints_s)[[0, -1]]
    u = (ends[1] - ends[0]) / np.linalg.norm(ends[1] - ends[0])
    q = traj.sampler(np.linspace(0.0, traj.motion_time, 401))[0]
    assert float(np.max(np.abs((q - ends[0]) @ np.array([-u[1], u[0]])))) <= 1e-12  # stays on the line
    lim = gen.limits
    best = max(min_time_rest_to_rest(abs(float(ends[1, r] - ends[0, r])), lim.v[r], lim.a[r], lim.j[r]) for r in (0, 1))
    np.testing.assert_allclose(traj.motion_time, best, rtol=1e-9)  # time-optimal for the slower robot


def test_blocked_or_other_class_takes_the_hard_path() -> None:
    gen = TrajectoryGenerator(Lollipop(1.0, 1.0), clearance=0.05)
    # the query: the straight route-coordinate motion comes closer than the clearance
    traj = gen.generate((0.08626294125818701, 0.6907495920087285), (1.0648068767904069, 0.564806876790407))
    assert traj.solver_stats["path"] == "hard" and not traj.fallback
    p = traj.plan
    assert straight_line_clearance(p, route_geometry(p.track, p.routes)) < gen.clearance


def test_most_random_queries_take_the_fast_path() -> None:
    rng = np.random.default_rng(4)
    for track, share in ((Lollipop(1.0, 1.0), 0.7), (Circle(1.0), 0.9)):
        gen = TrajectoryGenerator(track, clearance=0.05)
        paths = []
        while len(paths) < 40:
            s, g = rng.uniform(0.0, track.total_length * 0.9999, (2, 2))
            if track.distance(*s) < 0.05 or track.distance(*g) < 0.05:
                continue
            traj = gen.generate(s, g)
            assert not traj.fallback
            paths.append(traj.solver_stats["path"])
        assert paths.count("fast") >= share * len(paths), (track, paths.count("fast"))


def test_a_free_line_of_another_class_takes_the_hard_path(monkeypatch: pytest.MonkeyPatch) -> None:
    # The gate decides the line's homotopy class (the fast path does not check it in advance). Make the gate's class
    # check fail once, on the fast path's rows: the generator must take the hard path, not fall back or raise.
    import trajopt.verify.gate as verify

    gen = TrajectoryGenerator(Lollipop(1.0, 1.0), clearance=0.05)
    real = verify._word_check
    calls: list[int] = []

    def once_wrong(track, routes, S, word, *rest):  # type: ignore[no-untyped-def]
        calls.append(len(S))
        w, fails = real(track, routes, S, word, *rest)
        return (w, [*fails, "homotopy class (test) differs from the plan's"]) if len(calls) == 1 else (w, fails)

    monkeypatch.setattr(verify, "_word_check", once_wrong)
    traj = gen.generate((0.1, 0.6), (0.3, 0.8))  # a free line (see the first test)
    assert len(calls) == 2
    assert traj.solver_stats["path"] == "hard" and traj.solver_stats["line_other_class"]
    assert not traj.fallback and traj.verification["ok"]


def test_other_gate_failures_on_the_fast_path_fall_back(monkeypatch: pytest.MonkeyPatch) -> None:
    import trajopt.verify.gate as verify

    gen = TrajectoryGenerator(Lollipop(1.0, 1.0), clearance=0.05)
    real = verify._limit_check
    calls: list[int] = []

    def once_over(res, lims):  # type: ignore[no-untyped-def]
        calls.append(1)
        peak, fails = real(res, lims)
        return (peak, [*fails, "row 0: |v| of robot A is 9, limit 0.5"]) if len(calls) == 1 else (peak, fails)

    monkeypatch.setattr(verify, "_limit_check", once_over)
    traj = gen.generate((0.1, 0.6), (0.3, 0.8))
    assert traj.fallback and "|v| of robot A" in traj.fallback_reason and traj.verification["ok"]


def test_line_path_is_blend_polyline_of_the_two_ends() -> None:
    from trajopt.path.fastpath import _line_path
    from trajopt.timing import blend_polyline

    rng = np.random.default_rng(8)
    for k in range(3000):
        ends = rng.normal(size=(2, 2)) * 10 ** rng.uniform(-6, 2)
        got, want = _line_path(ends), blend_polyline(ends)
        for name in ("breaks", "coef", "is_blend", "stop", "corners", "radii", "bounds"):
            assert np.array_equal(getattr(got, name), getattr(want, name)), (k, name, ends)
