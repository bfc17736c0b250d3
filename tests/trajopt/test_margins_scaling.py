"""The delay search's branch and bound agrees with the direct search over every row, and its cost does not
follow the length of the motion."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mpa import Circle, Lollipop
from mpa.errors import MPAError
from mpa.graph_track import GraphTrack
from tests.helpers.graph_helpers import random_layout, random_position
from trajopt import generate_trajectory
from trajopt.analysis.margins import DELAY_PRECISION, DELAY_STEP, DENSE_RATE, MAX_DELAY_STEPS, _Motion
from trajopt.generator import TrajectoryGenerator
from trajopt.timing import Limits
from trajopt.verify.gate import SEPARATION_TOL, between_rows_separation


def _window_max(x: np.ndarray, w: int) -> np.ndarray:
    p, m = 1, x
    while 2 * p <= w:
        m = np.maximum(m[:-p], m[p:])
        p *= 2
    n = len(x) - w + 1
    return np.maximum(m[:n], m[w - p : w - p + n])


def reference_delay_limit(m: _Motion, robot: int) -> tuple[float, bool]:
    """The direct search: every row of ``[0, T + δ + h]`` bounded at every step (the definition)."""
    traj = m.traj
    D = traj.clearance - SEPARATION_TOL
    if m.T <= 0.0 or float(m.vpeak[robot]) <= 0.0:
        return math.inf, True
    dt = 1.0 / DENSE_RATE
    amax = float(traj.limits.a[robot])
    delta, h, steps = 0.0, DELAY_STEP, 0
    while delta <= m.T:
        steps += 1
        if steps > MAX_DELAY_STEPS:
            return delta, False
        delay = np.zeros(2)
        delay[robot] = delta
        t = np.arange(int(np.ceil((m.T + delta + h) * DENSE_RATE)) + 2) / DENSE_RATE
        s, a = m.states(t, delay)
        speed = np.abs(traj.sampler(t - delta)[1][:, robot])
        lb = between_rows_separation(m.track, m.routes, s, a, dt, traj.limits)
        k = int(np.ceil(h * DENSE_RATE))
        win = _window_max(np.concatenate([np.zeros(k), speed]), k + 2)
        u0, u1 = t[:-1] - delta - h, t[1:] - delta
        moving = (u1 > 0.0) & (u0 < m.T)
        bound = lb - h * np.where(moving, win + amax * dt / 2.0, 0.0)
        if float(np.min(bound)) >= D:
            delta += h
            h = min(2.0 * h, max(DELAY_STEP, m.T))
        elif h <= DELAY_PRECISION:
            return delta, True
        else:
            h /= 2.0
    return math.inf, True


def _cases() -> list:  # type: ignore[type-arg]
    L = Lollipop(1.0, 1.0)
    out = [
        generate_trajectory(L, (0.2, 0.5), (0.5, 0.2)),
        generate_trajectory(L, (0.1, 0.6), (0.8, 0.3)),
        generate_trajectory(Circle(1.0), (0.3, 0.6), (0.25, 0.1)),
    ]
    rng = np.random.default_rng(2025)
    while len(out) < 9:
        track = random_layout(rng)
        gen = TrajectoryGenerator(track, clearance=0.3, limits=Limits(0.5, 1.0, 4.0), rate=100.0)
        try:
            out.append(
                gen.generate(
                    tuple(random_position(track, rng) for _ in "ab"), tuple(random_position(track, rng) for _ in "ab")
                )
            )
        except MPAError:  # a random query without a motion, or robots too close: draw another
            continue
    return out


CASES = _cases()


@pytest.mark.parametrize("i", range(len(CASES)))
def test_branch_and_bound_equals_the_direct_search(i: int) -> None:
    traj = CASES[i]
    m = _Motion(traj)
    for robot in (0, 1):
        got, ref = m.delay_limit(robot), reference_delay_limit(_Motion(traj), robot)
        assert got[1] == ref[1], (i, robot, got, ref)
        if math.isinf(ref[0]) or math.isinf(got[0]):
            assert got[0] == ref[0], (i, robot, got, ref)
        else:
            # both are lower bounds of the true tolerance to the search's resolution
            assert abs(got[0] - ref[0]) <= 4 * DELAY_PRECISION, (i, robot, got, ref)


def test_cost_does_not_follow_the_length_of_the_motion() -> None:
    """A five-minute motion of carts far apart: the search bounds a few hundred blocks per step, not 300 000 rows."""
    track = GraphTrack.from_layout({"edges": [["a0", "a1", 60.0], ["b0", "b1", 60.0], ["a1", "b1", 40.0]]})
    gen = TrajectoryGenerator(track, clearance=0.5, limits=Limits(0.2, 0.5, 1.0), rate=10.0)
    traj = gen.generate((track.position("a0"), track.position("b0")), (track.position("a1"), track.position("b1")))
    assert traj.motion_time > 250.0
    m = _Motion(traj)
    calls: list[int] = []
    real = m.states

    def counting(t, delay):  # type: ignore[no-untyped-def]
        calls.append(int(np.size(t)))
        return real(t, delay)

    m.states = counting  # type: ignore[method-assign]
    tau, resolved = m.delay_limit(0)
    assert resolved and math.isinf(tau)
    rows = int(traj.motion_time * DENSE_RATE)
    # steps double while the delay keeps the clearance, up to the motion's time: a few dozen, not one a second
    assert m.steps < 40, m.steps
    assert sum(calls) < rows, (sum(calls), rows, m.steps)  # fewer states in all than one direct step's rows


def reference_exact_min(m: _Motion) -> tuple[float, float]:
    """The minimum of the full 1 kHz grid refined as :meth:`_Motion.exact_min` refines its rows near contact."""
    delay = np.zeros(2)
    return m.refine_min(m.grid(delay), delay)


@pytest.mark.parametrize("i", range(len(CASES)))
def test_minimum_on_the_rows_near_contact_equals_the_full_grid(i: int) -> None:
    m = _Motion(CASES[i])
    got, ref = m.exact_min(np.zeros(2)), reference_exact_min(m)
    assert got[0] == pytest.approx(ref[0], abs=1e-12), (i, got, ref)


@pytest.mark.parametrize("i", range(len(CASES)))
def test_states_on_two_clocks_are_two_samplings(i: int) -> None:
    # one sampler call for both clocks' times gives the numbers of one call per clock, bit for bit
    traj = CASES[i]
    m = _Motion(traj)
    rng = np.random.default_rng(i)
    for _ in range(20):
        t = np.sort(rng.uniform(-1.0, traj.motion_time + 2.0, int(rng.integers(1, 60))))
        delay = rng.choice([0.0, 1e-9, rng.uniform(0.0, 3.0)], 2)
        s, a = m.states(t, delay)
        s0, _, a0, _ = traj.sampler(t - delay[0])
        s1, _, a1, _ = traj.sampler(t - delay[1])
        assert np.array_equal(s, np.column_stack([s0[:, 0], s1[:, 1]])), (i, t, delay)
        assert np.array_equal(a, np.column_stack([a0[:, 0], a1[:, 1]])), (i, t, delay)
