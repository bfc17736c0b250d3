"""Re-planning from a moving state: splice continuous in p, v, a; verified; stable under 1 mm goal moves."""

from __future__ import annotations

import numpy as np
import pytest

from mpa import Interval, InvalidInputError, Lollipop, NoMotionError
from mpa.homotopy import path_word
from tests.helpers.scripts import is_png, run_script
from trajopt import TrajectoryGenerator
from trajopt.testing import travel_curve

SPLICE_TOL = 1e-9
LIMIT_RTOL = 1e-6
CHECK_RATE = 20_000.0
L = Lollipop(1.0, 1.0)


@pytest.fixture(scope="module")
def gen():  # type: ignore[no-untyped-def]
    return TrajectoryGenerator(L, clearance=0.05)


@pytest.fixture(scope="module")
def swap(gen):  # type: ignore[no-untyped-def]
    return gen.generate((0.2, 0.5), (0.5, 0.2))


def dense_check(traj):  # type: ignore[no-untyped-def]
    """Independent re-check of the continuous motion at 20 kHz: limits, clearance, goal at rest."""
    t = np.linspace(0.0, traj.motion_time, int(traj.motion_time * CHECK_RATE) + 2)
    s, v, a, j = traj.sampler(t)
    lim = traj.limits
    for name, x, m in (("v", v, lim.v), ("a", a, lim.a), ("j", j, lim.j)):
        peak = np.max(np.abs(x), axis=0)
        assert np.all(peak <= m * (1 + LIMIT_RTOL)), (name, peak)
    r = traj.plan.routes
    d = traj.plan.track.distance(r[0].position(s[:, 0]), r[1].position(s[:, 1]))
    assert d.min() >= traj.clearance - 1e-9, d.min()
    # s, v, a continuous: no jump larger than what the limits allow in one step
    h = t[1] - t[0]
    assert np.max(np.abs(np.diff(s, axis=0))) <= lim.v.max() * h * (1 + 1e-6) + 1e-12
    assert np.max(np.abs(np.diff(v, axis=0))) <= lim.a.max() * h * (1 + 1e-6) + 1e-12
    assert np.max(np.abs(np.diff(a, axis=0))) <= lim.j.max() * h * (1 + 1e-6) + 1e-12
    np.testing.assert_allclose(traj.track[-1], traj.plan.goal, atol=1e-9)
    assert np.max(np.abs(v[-1])) <= 1e-12 and np.max(np.abs(a[-1])) <= 1e-12
    assert np.all(traj.v[-1] == 0) or np.max(np.abs(traj.v[-1])) <= 1e-12


@pytest.mark.parametrize("at", [0.0, 0.37, 1.3, 2.0, 3.1, 4.55, 5.0])
def test_splice_is_continuous_and_verified(gen, swap, at) -> None:  # type: ignore[no-untyped-def]
    goal = (0.52, 0.18)
    new = gen.replan(swap, at, goal)
    assert new.verification["ok"]
    s_old, v_old, a_old, _ = swap.sampler(np.array([at]))
    s_new, v_new, a_new, _ = new.sampler(np.array([0.0]))
    o = np.array(new.solver_stats["replan"]["orientation"], dtype=float)
    assert set(o.tolist()) <= {-1.0, 1.0}
    p_old = np.array([swap.plan.routes[r].position(s_old[0, r]) for r in (0, 1)])
    p_new = np.array([new.plan.routes[r].position(s_new[0, r]) for r in (0, 1)])
    assert np.max(L.distance(p_old, p_new)) <= SPLICE_TOL
    np.testing.assert_allclose(new.track[0], p_old, atol=SPLICE_TOL)
    np.testing.assert_allclose(v_new[0], o * v_old[0], atol=SPLICE_TOL)
    np.testing.assert_allclose(a_new[0], o * a_old[0], atol=SPLICE_TOL)
    assert s_new[0].tolist() == [0.0, 0.0]
    # the position along the route follows the old motion for a moment (same direction of travel)
    eps = 1e-4
    s_old2 = swap.sampler(np.array([at + eps]))[0][0]
    s_new2 = new.sampler(np.array([eps]))[0][0]
    p2_old = np.array([swap.plan.routes[r].position(s_old2[r]) for r in (0, 1)])
    p2_new = np.array([new.plan.routes[r].position(s_new2[r]) for r in (0, 1)])
    assert np.max(L.distance(p2_old, p2_new)) <= 1e-9 + 2 * swap.limits.j.max() * eps**3
    # the braking ends at rest and the new motion starts there: continuous too
    tb = new.solver_stats["replan"]["brake_duration"]
    if tb > 0:
        left = new.sampler(np.array([tb - 1e-9]))
        right = new.sampler(np.array([tb]))
        for k in range(3):
            np.testing.assert_allclose(left[k], right[k], atol=1e-8)
    dense_check(new)


@pytest.mark.parametrize("at", [1.6, 3.6])
def test_a_stop_next_to_the_pole_is_moved_onto_it(gen, swap, at) -> None:  # type: ignore[no-untyped-def]
    """The swap slows down towards corners at P: the time-optimal stop lands within 1e-9 m of P, where the planner
    fails; the brake then ends exactly on P."""
    new = gen.replan(swap, at, (0.52, 0.2))
    dense_check(new)
    tb = new.solver_stats["replan"]["brake_duration"]
    rest = new.sampler(np.array([tb]))[0][0]
    p = np.array([new.plan.routes[r].position(rest[r]) for r in (0, 1)])
    near = L.distance(p, np.ones(2))
    assert np.all((near == 0.0) | (near > 1e-6)), p


def test_replan_at_the_end_and_at_rest(gen, swap) -> None:  # type: ignore[no-untyped-def]
    new = gen.replan(swap, swap.makespan, (0.45, 0.2))
    assert new.solver_stats["replan"]["brake_duration"] == 0.0
    np.testing.assert_allclose(new.track[0], swap.plan.goal, atol=1e-12)
    dense_check(new)
    same = gen.replan(swap, 0.0, swap.plan.goal)
    assert same.word == swap.word


@pytest.mark.parametrize(
    ("at", "goal", "err", "match"),
    [
        (-0.1, (0.5, 0.2), InvalidInputError, "at_time"),
        (1e3, (0.5, 0.2), InvalidInputError, "at_time"),
        (float("nan"), (0.5, 0.2), InvalidInputError, "at_time"),
        ("soon", (0.5, 0.2), InvalidInputError, "at_time"),
        (1.0, (5.0, 0.2), InvalidInputError, "goal of robot A is 5.0"),
        (1.0, (0.5, 0.52), InvalidInputError, "clearance"),
    ],
)
def test_bad_input(gen, swap, at, goal, err, match) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(err, match=match):
        gen.replan(swap, at, goal)


def test_no_motion_on_an_interval() -> None:
    gen = TrajectoryGenerator(Interval(1.0), clearance=0.05)
    traj = gen.generate((0.1, 0.5), (0.3, 0.9))
    with pytest.raises(NoMotionError):
        gen.replan(traj, 0.5, (0.9, 0.3))  # the order cannot change


@pytest.mark.parametrize(("start", "goal"), [((0.2, 0.5), (0.5, 0.2)), ((1.25, 1.75), (1.75, 1.25))])
def test_replanning_every_tenth_with_millimetre_goal_moves_is_stable(gen, start, goal) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(14)
    cur, g = gen.generate(start, goal), np.array(goal, dtype=float)
    for k in range(25):
        move = rng.uniform(-1e-3, 1e-3, 2)
        new = gen.replan(cur, 0.1, g + move)
        rem, nw = travel_curve(cur, 0.1), travel_curve(new, 0.0)
        assert path_word(L, nw) == path_word(L, rem), k  # the class never changes
        jump = max(L.distance(rem[:, 0], nw[:, 0]).max(), L.distance(rem[:, 1], nw[:, 1]).max())
        assert jump <= 10 * np.abs(move).max(), (k, jump, move)
        cur, g = new, g + move


def test_figure_script_smoke(tmp_path) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "r.png"
    res = run_script("experiments/replan_figure.py", "--out", str(out), "--dpi", "40")
    assert res.returncode == 0, res.stderr
    assert is_png(out, 5000)


def test_stability_script_smoke() -> None:
    res = run_script("experiments/replan_stability.py", "--replans", "2")
    assert res.returncode == 0, res.stderr
    lines = res.stdout.strip().splitlines()
    ours = [ln for ln in lines if not ln.startswith("    OMPL")]
    ompl = [ln for ln in lines if ln.startswith("    OMPL re-seeded: ")]
    assert len(ours) == 4 and all("2 re-plans, class changes 0" in ln for ln in ours), res.stdout
    assert len(ompl) == 4 and all("re-plans" in ln for ln in ompl), res.stdout


def test_brake_past_p_onto_another_branch_is_no_motion_with_its_reason() -> None:
    """A cart that would brake past P and come back onto a third branch: no single-route motion (exit 3, not 4)."""
    gen = TrajectoryGenerator(Lollipop(1.0, 1.0), clearance=0.05)
    traj = gen.generate((0.36588664935143744, 1.9260382802485345), (1.601834073217218, 0.9625209931505372))
    with pytest.raises(NoMotionError, match="brake past P and come back onto another branch"):
        gen.replan(traj, 2.0832849834925895, (1.627068128359271, 1.2056978104822327))
