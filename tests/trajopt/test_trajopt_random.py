"""Seeded random queries through the whole trajectory pipeline, re-checked independently of the library's gate.

The independent re-check (:func:`recheck`) resamples the continuous motion at a much finer rate and uses only
the track metric, ``mpa.path_word`` and plain comparisons: separation at every fine sample, limits, endpoints at
rest, the time grid, and the homotopy class against the plan's.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mpa import Circle, Lollipop, MPAError, path_word
from mpa.errors import InvalidInputError
from trajopt import Limits, Trajectory, TrajectoryGenerator
from trajopt.generator import separation_margin
from trajopt.testing import random_queries

#: Relative tolerance of the limit checks (the issue's 1e-6).
LIMIT_RTOL = 1e-6
#: Absolute tolerance of positions and rest (m, m/s, m/s²).
POS_TOL = 1e-9
#: Fine resampling factor of the independent re-check.
FINE = 8

# (track, clearance, number of queries): several sizes and clearances; hundreds of queries in all
CASES = [
    (Lollipop(1.0, 1.0), 0.05, 80),
    (Lollipop(1.0, 1.0), 0.2, 40),
    (Lollipop(0.4, 1.5), 0.1, 40),
    (Lollipop(2.0, 0.8), 0.02, 40),
    (Circle(1.0), 0.05, 60),
    (Circle(2.5), 0.3, 40),
]


def recheck(traj: Trajectory, start: np.ndarray, goal: np.ndarray) -> list[str]:
    """Independent checks of a returned trajectory; returns the failures (empty if fine)."""
    fails = []
    track, D = traj.plan.track, traj.clearance
    lim = traj.limits
    t, pos, s, v, a, j = traj.resample(traj.rate * FINE)
    d = track.distance(pos[:, 0], pos[:, 1])
    if len(s) > 1 and np.any(np.abs(np.diff(s, axis=0)) > lim.v / (traj.rate * FINE) * (1 + LIMIT_RTOL) + 1e-12):
        fails.append("route coordinate jumps between fine samples")
    if d.min() < D - 1e-12:
        fails.append(f"separation {d.min():.9g} < {D} at t = {t[np.argmin(d)]:.4f}")
    for name, x, m in (("v", v, lim.v), ("a", a, lim.a), ("j", j, lim.j)):
        peak = np.abs(x).max(axis=0)
        if np.any(peak > m * (1 + LIMIT_RTOL)):
            fails.append(f"|{name}| peak {peak} above {m}")
    for arr in (traj.t, t):
        step = np.diff(arr)
        if len(step) and np.ptp(step) > 1e-9:
            fails.append("time step not constant")
    if np.any(track.distance(traj.track[0], start) > POS_TOL) or np.any(track.distance(traj.track[-1], goal) > POS_TOL):
        fails.append("endpoints differ from the query")
    for row in (0, -1):
        if np.any(np.abs(traj.v[row]) > POS_TOL) or np.any(np.abs(traj.a[row]) > POS_TOL):
            fails.append(f"row {row} not at rest")
    if path_word(track, pos) != tuple(traj.plan.word):
        fails.append(f"class {path_word(track, pos)} != plan {traj.plan.word}")
    if traj.makespan < traj.motion_time - 1e-12 or traj.makespan - traj.motion_time > 1.0 / traj.rate + 1e-12:
        fails.append("makespan is not the motion time rounded up to the grid")
    return fails


@pytest.mark.parametrize(("track", "clearance", "n"), CASES, ids=lambda x: repr(x)[:40])
def test_random_queries_verified_and_rechecked(track, clearance, n) -> None:  # type: ignore[no-untyped-def]
    gen = TrajectoryGenerator(track, clearance=clearance, limits=Limits(0.5, 1.0, 5.0), rate=100.0)
    fallbacks, done = [], 0
    for i, (s, g) in enumerate(random_queries(track, clearance, n, seed=1234 + n)):
        try:
            traj = gen.generate(s, g)
        except MPAError as exc:
            # only "no motion" is acceptable (order change with D >= loop/2 on a lollipop)
            assert clearance >= getattr(track, "loop", np.inf) / 2, f"query {i} {s.tolist()} -> {g.tolist()}: {exc}"
            continue
        done += 1
        assert traj.verification["ok"], f"query {i} {s.tolist()} -> {g.tolist()}"
        assert traj.word == traj.plan.word
        fails = recheck(traj, s, g)
        assert not fails, f"query {i} {s.tolist()} -> {g.tolist()}: {fails}"
        if traj.fallback:
            fallbacks.append((i, s.tolist(), g.tolist(), traj.fallback_reason))
    print(f"{track}, D = {clearance}: {done} queries, {len(fallbacks)} fallbacks {fallbacks}")
    assert not fallbacks, fallbacks  # none expected at 100 Hz with these limits (was: at most 5 %)


@settings(max_examples=40, deadline=None, derandomize=True)
@given(
    st.tuples(*[st.floats(0.0, 1.999, allow_nan=False)] * 4),
    st.sampled_from([0.02, 0.05, 0.15]),
)
def test_hypothesis_lollipop(coords, clearance) -> None:  # type: ignore[no-untyped-def]
    track = Lollipop(1.0, 1.0)
    s, g = np.array(coords[:2]), np.array(coords[2:])
    if track.distance(*s) < clearance or track.distance(*g) < clearance:
        return
    gen = _GEN.setdefault(clearance, TrajectoryGenerator(track, clearance=clearance))
    try:
        traj = gen.generate(s, g)
    except InvalidInputError as exc:
        # robots at rest within the gate's between-rows margin of D (e.g. exactly D apart, a value Hypothesis draws
        # from the constants it finds in the code) cannot be verified at this rate: the documented error, only there
        near = min(track.distance(*s), track.distance(*g)) < clearance + separation_margin(gen.limits, gen.rate)
        assert near and ("lowest usable rate" in str(exc) or "apart" in str(exc)), (s, g, clearance, str(exc))
        return
    fails = recheck(traj, s, g)
    assert not fails, f"{s.tolist()} -> {g.tolist()}, D = {clearance}: {fails}"


_GEN: dict[float, TrajectoryGenerator] = {}


def test_fallback_is_verified_plan(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    """A failing optimiser yields the re-timed plan, marked and verified."""
    import trajopt.generator as genmod
    from mpa.errors import PlanningError

    def boom(*args, **kwargs):  # type: ignore[no-untyped-def]
        raise PlanningError("IPOPT failed: test")

    monkeypatch.setattr(genmod, "hard_path_scaling", boom)
    monkeypatch.setattr(genmod, "straight_scaling", boom)
    track = Lollipop(1.0, 1.0)
    traj = TrajectoryGenerator(track).generate((0.2, 0.5), (0.5, 0.2))
    assert traj.fallback and "IPOPT failed: test" in traj.fallback_reason
    assert traj.verification["ok"]
    assert not recheck(traj, np.array([0.2, 0.5]), np.array([0.5, 0.2]))


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(5))
def test_many_random_lollipops_slow(seed: int) -> None:
    rng = np.random.default_rng(seed)
    for _ in range(4):
        track = Lollipop(float(rng.uniform(0.3, 2.0)), float(rng.uniform(0.5, 2.0)))
        D = float(rng.uniform(0.005, 0.3)) * track.loop / 2
        gen = TrajectoryGenerator(track, clearance=D)
        for s, g in random_queries(track, D, 50, seed):
            traj = gen.generate(s, g)
            assert not recheck(traj, s, g), (track, D, s.tolist(), g.tolist())
