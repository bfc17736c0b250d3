"""Continuity across the fast/hard switch (:mod:`trajopt.path.switch`): shrinking-δ twins across the switch points that
:func:`trajopt.analysis.stability.switch_points` finds and across both edges of the bands of line margins, and the
time-law
blend's limits."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mpa import Lollipop, MPAError
from tests.trajopt.test_stability_reproducers import _gen
from trajopt import Limits, TrajectoryGenerator
from trajopt.analysis.stability import switch_points, trajectory_gap
from trajopt.generator import separation_margin
from trajopt.path.fastpath import _line_path, straight_line_clearance
from trajopt.path.switch import blended_time_law, switch_band
from trajopt.timing import TimeScaling, filtered_scaling, rest_to_rest_profile, spline_path

DELTAS = (1e-3, 1e-5, 1e-7, 1e-9)


def _shrinking_gaps(gen: TrajectoryGenerator, s: Any, g_left: Any, g_right: Any) -> list[tuple[float, float, float]]:
    """Gaps ``(δ, gap, Δt)`` between the goals ``mid ∓ δ·e`` around the midpoint of a bracket, ``e`` along it."""
    mid = 0.5 * (np.asarray(g_left) + np.asarray(g_right))
    e = np.asarray(g_right) - np.asarray(g_left)
    e = e / max(float(np.linalg.norm(e)), 1e-300)
    out = []
    for d in DELTAS:
        one, two = gen.generate(s, mid - d * e), gen.generate(s, mid + d * e)
        assert (one.domain, one.word) == (two.domain, two.word)
        gap, dt = trajectory_gap(one, two)
        out.append((d, gap, dt))
    return out


@pytest.mark.parametrize(
    ("track", "clearance"),
    [
        (Lollipop(1.0, 1.0), 0.05),
        (Lollipop(1.0, 1.0), 0.15),
        pytest.param(Lollipop(1.3, 0.9), 0.15, marks=pytest.mark.slow),
        pytest.param(Lollipop(1.3, 0.9), 0.05, marks=pytest.mark.slow),
    ],
)
def test_switch_points_shrinking_delta(track: Lollipop, clearance: float) -> None:
    """Seeded switch points (bisected to 1e-9 m): the gap across each is at most 1e-4 m and 1e-3 s, and twins
    δ = 1e-3 … 1e-9 m either side of it differ by at most ``max(200·δ, 1e-8)`` m (motion time: the same bound, s)."""
    gen = _gen(track, clearance)
    pts = switch_points(gen, 300, np.random.default_rng(5))
    assert len(pts) >= 1
    for p in pts[:4]:
        goals = f"{p.fast_goal.tolist()} / {p.hard_goal.tolist()}"
        case = f"{track} D={clearance}: start {p.fast_start.tolist()}, goals {goals}"
        assert p.gap <= 1e-4 and p.time_gap <= 1e-3, (case, p.gap, p.time_gap, p.paths)
        try:
            gaps = _shrinking_gaps(gen, p.fast_start, p.fast_goal, p.hard_goal)
        except AssertionError:
            continue  # a domain boundary within 1e-3 m of the switch
        for d, gap, dt in gaps:
            assert gap <= max(200 * d, 1e-8) and dt <= max(200 * d, 1e-8), (case, d, gap, dt)


def _bisect_margin(gen: TrajectoryGenerator, s: Any, g0: Any, g1: Any, level: float) -> tuple[Any, Any] | None:
    """Goals either side of the line margin ``level`` (bracket 1e-10 m), or None if the word changes on the way."""
    sep = gen.clearance + separation_margin(gen.limits, gen.rate)

    def m(g: Any) -> tuple[float, Any]:
        p = gen.plan(s, g)
        return straight_line_clearance(p) - sep, (p.domain, tuple(p.word))

    (m0, k0), (m1, k1) = m(g0), m(g1)
    if k0 != k1 or (m0 >= level) == (m1 >= level):
        return None
    lo, hi = (np.asarray(g0), np.asarray(g1)) if m0 < level else (np.asarray(g1), np.asarray(g0))
    for _ in range(80):
        if float(np.max(np.abs(hi - lo))) <= 1e-10:
            return lo, hi
        mid = 0.5 * (lo + hi)
        mm, k = m(mid)
        if k != k0:
            return None
        lo, hi = (mid, hi) if mm < level else (lo, mid)
    return lo, hi


@pytest.mark.parametrize("edge", [1.0, 2.0])
def test_band_edges_are_continuous(edge: float) -> None:
    """Where the line's margin crosses the edges of the bands (``b``: nodes on the line, timing switches to the
    time-law blend; ``2b``: the blend ends in the bare fast path), twins 1e-10 m apart differ by at most 1e-6 m and
    1e-6 s."""
    track = Lollipop(1.0, 1.0)
    gen = _gen(track, 0.05)
    level = edge * switch_band(track)
    rng = np.random.default_rng(8)
    hi = np.nextafter(track.total_length, 0.0)
    found = 0
    for _ in range(3000):
        s, g0 = rng.uniform(0.0, hi, 2), rng.uniform(0.0, hi, 2)
        g1 = np.clip(g0 + rng.normal(scale=0.1, size=2), 0.0, hi)
        try:
            br = _bisect_margin(gen, s, g0, g1, level)
            if br is None:
                continue
            one, two = gen.generate(s, br[0]), gen.generate(s, br[1])
        except MPAError:
            continue
        gap, dt = trajectory_gap(one, two)
        case = (s.tolist(), br[0].tolist(), br[1].tolist(), one.solver_stats["path"], two.solver_stats["path"])
        assert gap <= 1e-6 and dt <= 1e-6, (case, gap, dt)
        found += 1
        if found >= 3:
            break
    assert found >= 3, found


@settings(max_examples=60, deadline=None, derandomize=True)
@given(length=st.floats(1e-3, 3.0), w=st.floats(0.0, 1.0), angle=st.floats(0.0, 2 * np.pi))
def test_blended_time_law_keeps_the_limits(length: float, w: float, angle: float) -> None:
    """The power-mean blend of the filtered timing and ruckig's profile of one line keeps every robot's speed,
    acceleration and jerk limit (sampled densely), ends at rest at the line's end, and its duration lies between
    the two."""
    limits = Limits(0.5, 1.0, 5.0)
    d = length * np.array([np.cos(angle), np.sin(angle)])
    nodes = np.linspace([0.0, 0.0], d, 33)
    first = filtered_scaling(spline_path(nodes), limits)
    u = np.abs(d) / length
    lim = [min(x / ur for x, ur in zip(q.tolist(), u.tolist()) if ur > 1e-12) for q in (limits.v, limits.a, limits.j)]
    prof = rest_to_rest_profile(length, *lim)
    keep = prof.dt > 0
    second = TimeScaling(
        _line_path(np.stack([np.zeros(2), d])),
        prof.t0[keep],
        prof.p[keep],
        prof.v[keep],
        prof.a[keep],
        prof.j[keep],
        prof.duration,
        np.zeros(2),
    )
    mix = blended_time_law(first, second, w)
    lo, hi = sorted((first.duration, second.duration))
    assert lo - 1e-12 <= mix.duration <= hi + 1e-12
    t = np.linspace(0.0, mix.duration, 4001)
    s, v, a, j = mix.sample(t)
    tol = 1e-6
    for got, cap, name in ((v, limits.v, "v"), (a, limits.a, "a"), (j, limits.j, "j")):
        excess = float(np.max(np.abs(got) - cap * (1 + tol)))
        assert excess <= 0.0, (name, length, w, angle, excess)
    assert np.allclose(s[-1], d, atol=1e-9) and np.allclose(v[-1], 0.0, atol=1e-9)


def test_queries_in_the_bands_take_the_switch_path() -> None:
    """Seeded random queries (lollipop 1/1, clearance 0.15): every one whose line keeps the separation by less than
    two bands takes the switch path (its blended nodes keep the separation: none goes to the hard path or the
    fallback), and every one beyond them the bare fast path."""
    track = Lollipop(1.0, 1.0)
    gen = _gen(track, 0.15)
    sep = gen.clearance + separation_margin(gen.limits, gen.rate)
    band = switch_band(track)
    rng = np.random.default_rng(3)
    hi = np.nextafter(track.total_length, 0.0)
    seen = 0
    for _ in range(400):
        s, g = rng.uniform(0.0, hi, 2), rng.uniform(0.0, hi, 2)
        try:
            tr = gen.generate(s, g)
        except MPAError:
            continue
        st = tr.solver_stats
        m = st["line_clearance"] - sep if "line_clearance" in st else float("nan")
        case = (s.tolist(), g.tolist(), m, st.get("path"))
        assert not tr.fallback and "switch_failed" not in st, case
        if 0.0 <= m < 2 * band:
            assert st["path"] == "switch", case
            seen += 1
        elif m >= 2 * band:
            assert st["path"] == "fast", case
    assert seen >= 5, seen
