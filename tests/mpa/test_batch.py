"""mpa.plan_many: the domain and word of every query equal what mpa.plan gives one by one."""

from __future__ import annotations

import numpy as np
import pytest

from mpa import BatchPlans, Circle, Interval, InvalidInputError, Lollipop, NoMotionError, Track, make_planner, plan_many
from tests.helpers.common import random_states, same_order_goals

TRACKS: list[tuple[Track, float]] = [
    (Lollipop(1.0, 1.0), 0.0),
    (Lollipop(1.0, 1.0), 0.05),
    (Lollipop(0.3, 1.0), 0.0),
    (Lollipop(1.0, 1.0), 0.7),  # clearance above half the loop: the retreat regime, one by one
    (Circle(1.0), 0.0),
    (Interval(1.0), 0.05),
]


def _queries(track: Track, clearance: float, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    gap = max(clearance, 1e-6)
    s, g = random_states(track, n, rng, gap), random_states(track, n, rng, gap)
    g = same_order_goals(track, s, g)
    if isinstance(track, Lollipop) and clearance >= track.half:  # keep the order (no motion otherwise)
        pl = make_planner(track, clearance)
        keep = np.array([pl.cspace.order(a) * pl.cspace.order(b) >= 0 for a, b in zip(s, g)])
        s, g = s[keep], g[keep]
    return s, g


def _assert_same(track: Track, clearance: float, n: int, seed: int, every: int = 1) -> None:
    s, g = _queries(track, clearance, n, seed)
    b = plan_many(track, s, g, clearance=clearance)
    assert isinstance(b, BatchPlans) and len(b) == len(s)
    assert b.domain.shape == (len(s),) and b.domain.dtype.kind == "i"
    pl = make_planner(track, clearance)
    for i in range(0, len(s), every):
        p = pl.plan(s[i], g[i])
        assert (int(b.domain[i]), b.word[i]) == (p.domain, p.word), (i, s[i].tolist(), g[i].tolist())


@pytest.mark.parametrize(("track", "clearance"), TRACKS, ids=[f"{t!r}-{d}" for t, d in TRACKS])
def test_plan_many_equals_plan(track: Track, clearance: float) -> None:
    n = 2000 if clearance < 0.5 else 200
    _assert_same(track, clearance, n, seed=7)


def test_plan_many_ten_thousand_lollipop_queries() -> None:
    _assert_same(Lollipop(1.0, 1.0), 0.0, 10_000, seed=11)


@pytest.mark.slow
def test_plan_many_hundred_thousand_lollipop_queries_slow() -> None:
    _assert_same(Lollipop(1.0, 1.0), 0.0, 100_000, seed=12)


def test_full_plan_of_one_query() -> None:
    track = Lollipop(1.0, 1.0)
    b = plan_many(track, [(0.1, 0.6), (1.25, 1.75)], [(0.8, 0.3), (1.75, 1.25)])
    p = b.plan(1)
    assert p.domain == 2 and p.word == b.word[1]
    assert b.plan(-1) is p
    np.testing.assert_allclose(p.start, [1.25, 1.75])
    with pytest.raises(InvalidInputError, match="query index"):
        b.plan(2)


def test_plan_many_rejects_bad_input() -> None:
    track = Lollipop(1.0, 1.0)
    with pytest.raises(InvalidInputError, match=r"expected \(N, 2\)"):
        plan_many(track, [0.1, 0.6], [0.8, 0.3])
    with pytest.raises(InvalidInputError, match=r"starts\[1\]"):
        plan_many(track, [(0.1, 0.6), (5.0, 0.6)], [(0.8, 0.3), (0.8, 0.3)])
    with pytest.raises(InvalidInputError, match=r"goals\[0\].*clearance"):
        plan_many(track, [(0.1, 0.6)], [(0.8, 0.81)], clearance=0.05)
    with pytest.raises(NoMotionError, match="query 0"):
        plan_many(Interval(1.0), [(0.1, 0.6)], [(0.6, 0.1)])


@pytest.mark.parametrize(
    ("track", "clearance"), [(Lollipop(1.0, 1.0), 0.0), (Lollipop(0.3, 1.2), 0.0), (Lollipop(1.3, 0.9), 0.05)]
)
def test_plan_many_near_decision_borders(track: Lollipop, clearance: float) -> None:
    """Queries on and within hairs of the main step's borders (P, the free end, antipodes, ε-edges) agree."""
    rng = np.random.default_rng(3)
    ell, c = track.stick, track.loop
    h, e = c / 2, 0.1 * c / 2
    special = np.array([0, ell, ell + h, ell + c / 4, ell + e, ell + h - e, ell + h + e, ell + c - e, ell - h, h, e])
    special = special[(special >= 0) & (special < track.total_length)]
    n = 1500
    noise = rng.choice([0.0, 1e-12, -1e-12, 1e-8, -1e-8, 1e-6, 1e-3], size=(2, n, 2))
    s, g = (np.clip(special[rng.integers(len(special), size=(n, 2))] + z, 0, track.total_length - 1e-9) for z in noise)
    keep = (track.distance(s[:, 0], s[:, 1]) >= max(clearance, 1e-9)) & (
        track.distance(g[:, 0], g[:, 1]) >= max(clearance, 1e-9)
    )
    s, g = s[keep], g[keep]
    assert len(s) > 1000
    b = plan_many(track, s, g, clearance=clearance)
    pl = make_planner(track, clearance)
    for i in range(len(s)):
        p = pl.plan(s[i], g[i])
        assert (int(b.domain[i]), b.word[i]) == (p.domain, p.word), (i, s[i].tolist(), g[i].tolist())
