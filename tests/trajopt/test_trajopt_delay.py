"""``delay_tolerance=``: trajectories that tolerate a requested delay of either cart, checked by shifting them."""

from __future__ import annotations

import numpy as np
import pytest

from mpa import Interval, Lollipop
from mpa.errors import InvalidInputError, NoMotionError
from trajopt import TrajectoryGenerator, generate_trajectory
from trajopt.analysis.delay import validate_delay_tolerance

CHECK_RATE = 20_000.0  # Hz of the independent dense check
TOL = 1e-9


def shifted_min(traj, robot, delay):  # type: ignore[no-untyped-def]
    """Smallest separation (dense samples) with one robot's whole motion delayed by ``delay`` seconds."""
    t = np.arange(int((traj.motion_time + delay) * CHECK_RATE) + 2) / CHECK_RATE
    sa = traj.sampler(np.clip(t - (delay if robot == 0 else 0.0), 0.0, traj.motion_time))[0][:, 0]
    sb = traj.sampler(np.clip(t - (delay if robot == 1 else 0.0), 0.0, traj.motion_time))[0][:, 1]
    r = traj.plan.routes
    return float(np.min(traj.plan.track.distance(r[0].position(sa), r[1].position(sb))))


@pytest.fixture(scope="module")
def gen() -> TrajectoryGenerator:
    return TrajectoryGenerator(Lollipop(1.0, 1.0), clearance=0.05)


QUERY = ((0.3, 1.2), (1.6, 0.4))  # A climbs into the loop as B leaves it: 0.35 ms of delay tolerance as planned


def test_ordinary_motion_tolerates_little(gen) -> None:  # type: ignore[no-untyped-def]
    traj = gen.generate(*QUERY)
    tau = traj.margins().delay_tolerance
    assert tau < 0.01
    assert shifted_min(traj, 0, 0.05) < traj.clearance - 1e-4  # a 50 ms delay of A really breaks D


@pytest.mark.parametrize("T", [0.05, 0.2])
def test_requested_tolerance_holds_when_shifted(gen, T) -> None:  # type: ignore[no-untyped-def]
    traj = gen.generate(*QUERY, delay_tolerance=T)
    st = traj.solver_stats["delay_tolerance"]
    assert st["requested"] == T and st["achieved"] >= T
    assert st["effective_clearance"] > 0.05  # reached by the larger clearance, not by luck
    assert traj.clearance == 0.05 and traj.verification["ok"]
    assert traj.limits == gen.limits
    assert traj.margins().delay_tolerance >= T
    assert traj.word == gen.generate(*QUERY).word  # same homotopy class here
    for robot in (0, 1):
        for frac in (0.25, 0.5, 1.0):
            assert shifted_min(traj, robot, frac * T) >= 0.05 - TOL
    assert traj.summary()["solver"]["delay_tolerance"]["achieved"] >= T


def test_already_tolerant_motion_is_returned_unchanged(gen) -> None:  # type: ignore[no-untyped-def]
    plain = gen.generate((0.1, 0.6), (0.8, 0.3))
    traj = gen.generate((0.1, 0.6), (0.8, 0.3), delay_tolerance=0.2)
    np.testing.assert_array_equal(traj.s, plain.s)
    assert traj.solver_stats["delay_tolerance"]["effective_clearance"] == 0.05
    assert len(traj.solver_stats["delay_tolerance"]["tried"]) == 1


def test_generate_trajectory_keyword() -> None:
    traj = generate_trajectory(Lollipop(1.0, 1.0), *QUERY, delay_tolerance=0.05)
    assert traj.margins().delay_tolerance >= 0.05


def test_impossible_tolerance_says_the_best_value() -> None:
    # B leads A along an interval, 6 cm apart at the start: the clearance cannot grow beyond ~6 cm, and
    # slowing down by at most 4x cannot reach 5 s
    gen = TrajectoryGenerator(Interval(1.0), clearance=0.05)
    with pytest.raises(NoMotionError, match=r"tolerates a delay of 5 s.*best found tolerates (\d|\.)+ s"):
        gen.generate((0.0, 0.06), (0.5, 0.56), delay_tolerance=5.0)


@pytest.mark.parametrize("bad", [-0.1, float("nan"), float("inf"), "x", None])
def test_bad_tolerance(bad) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(InvalidInputError, match="delay tolerance"):
        validate_delay_tolerance(bad)


def test_bad_tolerance_in_api(gen) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(InvalidInputError, match="delay tolerance"):
        gen.generate(*QUERY, delay_tolerance=-1.0)
