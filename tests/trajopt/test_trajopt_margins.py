"""Tracking margin and delay tolerance, checked by actually perturbing and shifting the motion."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from mpa import Circle, Lollipop
from tests.helpers.scripts import is_png, run_script
from trajopt import generate_trajectory
from trajopt.analysis.margins import margins, min_separation

CHECK_RATE = 20_000.0  # Hz of the independent dense checks
L = Lollipop(1.0, 1.0)
QUERIES = [
    (L, (0.2, 0.5), (0.5, 0.2)),  # swap through the loop
    (L, (0.1, 0.6), (0.8, 0.3)),  # domain 1
    (L, (1.25, 1.75), (1.75, 1.25)),  # domain 2
    (Circle(1.0), (0.3, 0.6), (0.25, 0.1)),
]


@pytest.fixture(scope="module", params=range(len(QUERIES)), ids=["swap", "dom1", "dom2", "circle"])
def case(request):  # type: ignore[no-untyped-def]
    track, st, gl = QUERIES[request.param]
    traj = generate_trajectory(track, st, gl)
    return traj, margins(traj)


def separations(traj, sa, sb):  # type: ignore[no-untyped-def]
    r = traj.plan.routes
    return traj.plan.track.distance(r[0].position(sa), r[1].position(sb))


def shifted_min(traj, robot, delay):  # type: ignore[no-untyped-def]
    """Smallest separation (dense samples) with one robot's motion delayed by ``delay`` seconds."""
    t = np.arange(int((traj.motion_time + delay) * CHECK_RATE) + 2) / CHECK_RATE
    sa = traj.sampler(t - (delay if robot == 0 else 0.0))[0][:, 0]
    sb = traj.sampler(t - (delay if robot == 1 else 0.0))[0][:, 1]
    return float(np.min(separations(traj, sa, sb)))


def test_min_separation_is_the_continuous_minimum(case) -> None:  # type: ignore[no-untyped-def]
    traj, m = case
    t = np.linspace(0.0, traj.motion_time, int(traj.motion_time * CHECK_RATE) + 1)
    s = traj.sampler(t)[0]
    dense = float(np.min(separations(traj, s[:, 0], s[:, 1])))
    assert m.min_separation <= dense + 1e-12
    assert m.min_separation >= dense - 1e-9  # dense sampling cannot miss more than the motion allows
    assert m.min_separation <= traj.min_separation + 1e-12
    assert m.min_separation >= traj.verification["min_separation_between"] - 1e-12
    s_star = traj.sampler(np.array([m.min_separation_time]))[0]
    assert float(separations(traj, s_star[:, 0], s_star[:, 1])[0]) == pytest.approx(m.min_separation, abs=1e-12)
    assert m.tracking_margin == pytest.approx((m.min_separation - traj.clearance) / 2, abs=1e-15)
    assert min_separation(traj)[0] == m.min_separation


def test_tracking_margin_by_perturbing(case) -> None:  # type: ignore[no-untyped-def]
    traj, m = case
    r, D = m.tracking_margin, traj.clearance
    assert r > 0
    t = np.linspace(0.0, traj.motion_time, int(traj.motion_time * 2000) + 1)
    s = traj.sampler(t)[0]
    # every cart within r(1 − 1e-3) of its setpoint, worst case of the four directions, at every instant: ≥ D
    x = r * (1 - 1e-3)
    worst = min(
        float(np.min(separations(traj, s[:, 0] + ea * x, s[:, 1] + eb * x))) for ea in (-1, 1) for eb in (-1, 1)
    )
    assert worst >= D - 1e-12, worst
    rng = np.random.default_rng(14)
    rand = rng.uniform(-x, x, size=s.shape)
    assert float(np.min(separations(traj, s[:, 0] + rand[:, 0], s[:, 1] + rand[:, 1]))) >= D - 1e-12
    # r(1 + 1e-2) toward each other at the closest instant breaks the clearance
    s_star = traj.sampler(np.array([m.min_separation_time]))[0][0]
    y = r * (1 + 1e-2)
    toward = min(
        float(separations(traj, np.array([s_star[0] + ea * y]), np.array([s_star[1] + eb * y]))[0])
        for ea in (-1, 1)
        for eb in (-1, 1)
    )
    assert toward < D, (toward, D)


def test_delay_tolerance_by_shifting(case) -> None:  # type: ignore[no-untyped-def]
    traj, m = case
    D = traj.clearance
    assert m.delay_resolved
    assert m.delay_tolerance == min(m.delay_a, m.delay_b)
    for robot, tau in ((0, m.delay_a), (1, m.delay_b)):
        if math.isinf(tau):
            for delay in (0.3, 0.5 * traj.motion_time, traj.motion_time, 2.0 * traj.motion_time):
                assert shifted_min(traj, robot, delay) >= D - 1e-9, (robot, delay)
            continue
        assert tau > 0
        for frac in (0.1, 0.5, 0.9, 1 - 1e-3):
            got = shifted_min(traj, robot, tau * frac)
            assert got >= D - 1e-9, (robot, frac, got)
        assert shifted_min(traj, robot, tau * (1 + 1e-2)) < D, robot


def test_some_delay_is_finite_and_some_infinite() -> None:
    """The canonical swap has a finite delay tolerance (B may be late by 0.5 s); a domain-2 lollipop query none."""
    swap = margins(generate_trajectory(L, (0.2, 0.5), (0.5, 0.2)))
    assert 0.4 < swap.delay_tolerance < 0.6
    free = margins(generate_trajectory(L, (0.8, 1.3), (0.7, 1.8)))
    assert math.isinf(free.delay_tolerance)
    d = free.to_dict()
    assert d["delay_tolerance"] is None and d["delay_unbounded"] is True
    json.dumps(d, allow_nan=False)
    assert json.loads(json.dumps(swap.to_dict(), allow_nan=False))["delay_tolerance"] == swap.delay_tolerance


def test_summary_reports_margins(tmp_path) -> None:  # type: ignore[no-untyped-def]
    traj = generate_trajectory(L, (0.2, 0.5), (0.5, 0.2))
    traj.to_json(tmp_path / "s.json")
    got = json.loads((tmp_path / "s.json").read_text())["margins"]
    m = traj.margins()
    assert traj.margins() is m  # computed once
    assert got["tracking_margin"] == m.tracking_margin and got["delay_tolerance"] == m.delay_tolerance


def test_figure_script_smoke(tmp_path) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "m.png"
    res = run_script("experiments/margins_figure.py", "--out", str(out), "--dpi", "40", "--points", "5")
    assert res.returncode == 0, res.stderr
    assert is_png(out, 5000)


@pytest.mark.parametrize("delay", [(0.0, 0.0), (0.37, 0.0), (0.0, 1.25), (0.5, 0.5)])
def test_states_with_equal_delays_sample_once_and_say_the_same(delay) -> None:  # type: ignore[no-untyped-def]
    from trajopt.analysis.margins import _Motion

    traj = generate_trajectory(Lollipop(1.0, 1.0), (0.2, 0.5), (0.5, 0.2))
    motion = _Motion(traj)
    t = np.linspace(-0.5, traj.motion_time + 2.0, 997)
    d = np.array(delay)
    s, a = motion.states(t, d)
    s0, _, a0, _ = traj.sampler(t - d[0])
    s1, _, a1, _ = traj.sampler(t - d[1])
    np.testing.assert_array_equal(s, np.column_stack([s0[:, 0], s1[:, 1]]))
    np.testing.assert_array_equal(a, np.column_stack([a0[:, 0], a1[:, 1]]))
    assert s.shape == a.shape == (len(t), 2)
