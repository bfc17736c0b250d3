"""Stability end to end: inside a domain the executed trajectory moves continuously with (start, goal).

Seeded perturbation pairs (:mod:`trajopt.analysis.stability`): a query and the query moved by δ in a random direction,
both
in the same domain. The gap (sup over normalised time of the robots' graph distance, and the motion-time change)
must be at most :data:`GAP_AT_1E7` for δ = 1e-7 and ``gap/δ`` must not grow as δ shrinks from 1e-5 to 1e-7 (a
jump would make it grow like 1/δ; the measured local Lipschitz constants reach about 100 in domain 2).
CI runs 30 pairs per domain; the 1 000 of the issue are in the ``slow`` test.
"""

from __future__ import annotations

import numpy as np
import pytest

from mpa import Circle, Interval, Lollipop, MPAError, Track
from trajopt import TrajectoryGenerator
from trajopt.analysis.stability import perturbation_pairs, trajectory_gap

#: The issue's goal: sup gap at δ = 1e-7 (metres, and seconds for the motion time).
GAP_AT_1E7 = 1e-4
#: ``gap/δ`` at δ = 1e-7 may exceed the one at 1e-5 by at most this factor: a jump would make it grow 100-fold
#: over two decades; a continuous, piecewise-affine dependence keeps it flat (a kink in between may change it).
RATIO_GROWTH = 10.0
DELTAS = (1e-3, 1e-5, 1e-6, 1e-7)
#: Largest distance (m) of the hard path from the straight line just past the fast/hard switch (measured ≤ 6e-4).
LINE_AT_SWITCH = 2e-3

CASES: list[tuple[Track, int]] = [
    (Lollipop(1.0, 1.0), 1),
    (Lollipop(1.0, 1.0), 2),
    (Lollipop(1.0, 1.0), 3),
    (Circle(1.0), 1),
    (Circle(1.0), 2),
    (Interval(1.0), 1),
]
_GENS: dict[str, TrajectoryGenerator] = {}


def _gen(track: Track) -> TrajectoryGenerator:
    key = repr(track)
    if key not in _GENS:
        _GENS[key] = TrajectoryGenerator(track, clearance=0.05)
    return _GENS[key]


def _check_pairs(track: Track, domain: int, n: int, seed: int, hard_only: bool = False) -> dict[str, int]:
    gen = _gen(track)
    rng = np.random.default_rng(seed)
    pp = perturbation_pairs(gen.planner, domain, 40 * n if hard_only else n, rng)
    moved = {d: pp.perturbed(d) for d in DELTAS}
    counts = {"pairs": 0, "hard": 0}
    for i in range(len(pp.starts)):
        base = gen.generate(pp.starts[i], pp.goals[i])
        if hard_only and base.solver_stats.get("path") != "hard":
            continue
        case = f"{track} domain {domain}: {pp.starts[i].tolist()} -> {pp.goals[i].tolist()}"
        assert not base.fallback, f"{case}: {base.fallback_reason}"
        assert base.domain == domain
        ratios = {}
        for d in DELTAS:
            s2, g2 = moved[d]
            other = gen.generate(s2[i], g2[i])
            assert not other.fallback, f"{case}, δ = {d}: {other.fallback_reason}"
            gap, dt = trajectory_gap(base, other)
            ratios[d] = max(gap, dt) / d
            if d == 1e-7:
                assert gap <= GAP_AT_1E7 and dt <= GAP_AT_1E7, f"{case}: gap {gap:.3g} m, {dt:.3g} s at δ = 1e-7"
        assert ratios[1e-7] <= RATIO_GROWTH * max(ratios[1e-5], 1.0), f"{case}: gap/δ {ratios}"
        counts["pairs"] += 1
        counts["hard"] += base.solver_stats.get("path") == "hard"
        if counts["pairs"] >= n:
            break
    return counts


@pytest.mark.parametrize(("track", "domain"), CASES, ids=[f"{t!r}-{d}" for t, d in CASES])
def test_perturbation_pairs(track: Track, domain: int) -> None:
    counts = _check_pairs(track, domain, 30, seed=domain)
    assert counts["pairs"] == 30


@pytest.mark.parametrize("domain", [1, 2, 3])
def test_perturbation_pairs_hard_path(domain: int) -> None:
    """Pairs whose query goes through the corridor QP (its straight line collides or has another class)."""
    counts = _check_pairs(Lollipop(1.0, 1.0), domain, 10, seed=100 + domain, hard_only=True)
    assert counts["pairs"] == 10 and counts["hard"] == 10


def test_issue_query_is_stable() -> None:
    """The issue's query: a 1e-7 m move used to move the trajectory by 6.8 cm; now by about the move itself."""
    gen = _gen(Lollipop(1.0, 1.0))
    s = np.array([0.08626294125818701, 0.6907495920087285])
    g = np.array([1.0648068767904069, 0.564806876790407])
    s_to = np.array([0.08631406808922695, 0.6907437010607501])
    g_to = np.array([1.064817055985661, 0.5647533948117762])
    base = gen.generate(s, g)
    assert not base.fallback and base.solver_stats["path"] == "hard"
    for frac in (1e-1, 1e-3, 1e-5):
        other = gen.generate(s + frac * (s_to - s), g + frac * (g_to - g))
        step = frac * float(np.max(np.abs(np.concatenate([s_to - s, g_to - g]))))
        gap, dt = trajectory_gap(base, other)
        assert gap <= 10 * step and dt <= 10 * step, (frac, gap, dt, step)


@pytest.mark.slow
@pytest.mark.parametrize(("track", "domain"), CASES, ids=[f"{t!r}-{d}" for t, d in CASES])
def test_perturbation_pairs_slow(track: Track, domain: int) -> None:
    """The issue's 1 000 seeded pairs per domain and track."""
    counts = _check_pairs(track, domain, 1000, seed=1000 + domain)
    assert counts["pairs"] == 1000


def _switch_queries(n: int, seed: int) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Queries on both sides of the fast/hard switch: the straight line's clearance crosses the required one."""
    from trajopt.generator import separation_margin
    from trajopt.path.fastpath import straight_line_clearance
    from trajopt.path.planview import route_geometry

    gen = _gen(Lollipop(1.0, 1.0))
    sep = gen.clearance + separation_margin(gen.limits, gen.rate)
    rng = np.random.default_rng(seed)

    def line(s: np.ndarray, g: np.ndarray) -> tuple[float, int]:
        p = gen.plan(s, g)
        return straight_line_clearance(p, route_geometry(p.track, p.routes)), p.domain

    out = []
    while len(out) < n:
        s, g0, g1 = (rng.uniform(0.0, 1.999, 2) for _ in range(3))
        try:
            (c0, d0), (c1, d1) = line(s, g0), line(s, g1)
        except MPAError:
            continue
        if d0 != d1 or not (c0 >= sep > c1 > 0):
            continue
        lo, hi = 0.0, 1.0
        ok = True
        for _ in range(60):
            m = 0.5 * (lo + hi)
            try:
                c, d = line(s, g0 + m * (g1 - g0))
            except MPAError:
                ok = False
                break
            if d != d0:
                ok = False
                break
            lo, hi = (m, hi) if c >= sep else (lo, m)
        if ok:
            out.append((s, g0 + lo * (g1 - g0), g0 + hi * (g1 - g0)))
    return out


def test_hard_path_converges_to_the_line_at_the_switch() -> None:
    """Just past the switch the hard path is near the straight line, and the trajectory is continuous across it.

    The re-centred corridor converges to the line (the QP returns the line exactly once the corridor contains it;
    near the contact point the balls shrink, so a finite number of re-centrings leaves up to
    :data:`LINE_AT_SWITCH`). On the line's side the switch bands (:mod:`trajopt.path.switch`) start from that same
    corridor path, so the two sides agree: gap at most 1e-4 m and motion-time change at most 1e-3 s.
    """
    gen = _gen(Lollipop(1.0, 1.0))
    for s, g_fast, g_hard in _switch_queries(4, seed=5):
        fast, hard = gen.generate(s, g_fast), gen.generate(s, g_hard)
        assert fast.solver_stats["path"] == "switch" and hard.solver_stats["path"] == "hard"
        assert not fast.fallback and not hard.fallback
        ends = np.asarray(hard.plan.waypoints_s)[[0, -1]]
        q = hard.sampler(np.linspace(0.0, hard.motion_time, 501))[0]
        u = (ends[1] - ends[0]) / np.linalg.norm(ends[1] - ends[0])
        off = np.abs((q - ends[0]) @ np.array([-u[1], u[0]]))
        assert float(np.max(off)) <= LINE_AT_SWITCH, (s.tolist(), g_hard.tolist(), float(np.max(off)))
        gap, dt = trajectory_gap(fast, hard)
        assert gap <= 1e-4 and dt <= 1e-3, (s.tolist(), g_fast.tolist(), g_hard.tolist(), gap, dt)
