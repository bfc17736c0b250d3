"""Clearances the paper does not cover (lollipop, D > min(ℓ, h)): order rule, clearance kept, continuity."""

from __future__ import annotations

import numpy as np
import pytest

from mpa import Circle, Interval, InvalidInputError, Lollipop, NoMotionError, make_planner, path_word, plan
from tests.helpers.common import EXACT, path_gap, random_states

CASES = [
    (Lollipop(1.0, 1.0), 0.7, "retreat"),
    (Lollipop(2.0, 1.0), 1.2, "retreat"),
    (Lollipop(0.2, 1.0), 0.6, "retreat"),  # D > ℓ too: the front robot keeps to an arc of the loop
    (Lollipop(0.2, 1.0), 0.3, "loop"),
    (Lollipop(0.4, 1.0), 0.45, "loop"),
    (Lollipop(1.0, 1.0), 0.5, "paper"),  # D = h, ℓ ≥ h: the paper's plan keeps d >= h
    (Lollipop(0.3, 1.0), 0.1, "paper"),  # conjugated planner, D <= ℓ
]


@pytest.mark.parametrize(("track", "D", "regime"), CASES, ids=lambda v: repr(v))
def test_clearance_is_kept_and_order_rule_holds(track, D, regime) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(21)
    planner = make_planner(track, D)
    s_all, g_all = random_states(track, 800, rng, D), random_states(track, 800, rng, D)
    solved = 0
    for i in range(len(s_all)):
        s, g = s_all[i], g_all[i]
        os_, og = planner.cspace.order(s), planner.cspace.order(g)
        if D >= track.half and os_ * og < 0:
            with pytest.raises(NoMotionError, match="must change order"):
                planner.plan(s, g)
            continue
        p = planner.plan(s, g)
        solved += 1
        assert p.regime == regime
        x = p.sample(max(2000, p.samples_needed(0.0005)))
        d = track.distance(x[:, 0], x[:, 1])
        assert d.min() >= D - EXACT, (i, s.tolist(), g.tolist(), d.min())
        assert track.distance(x[-1, 0], g[0]) + track.distance(x[-1, 1], g[1]) < EXACT
        assert path_word(track, x) == p.word
    assert solved > 100


@pytest.mark.parametrize(("track", "D", "regime"), CASES[:5], ids=lambda v: repr(v))
def test_extra_regimes_are_continuous_on_their_domains(track, D, regime) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(22)
    planner = make_planner(track, D)
    L = np.nextafter(track.total_length, 0)
    s_all, g_all = random_states(track, 600, rng, D + 1e-3), random_states(track, 600, rng, D + 1e-3)
    for i in range(len(s_all)):
        try:
            p = planner.plan(s_all[i], g_all[i])
            q = planner.plan(
                np.clip(s_all[i] + 1e-6 * rng.uniform(-1, 1, 2), 0, L),
                np.clip(g_all[i] + 1e-6 * rng.uniform(-1, 1, 2), 0, L),
            )
        except NoMotionError:
            continue
        if p.domain == q.domain:
            assert path_gap(track, p, q) <= 20e-6, (i, s_all[i].tolist(), g_all[i].tolist())


def test_interval_order_and_messages() -> None:
    with pytest.raises(NoMotionError, match="can never change order"):
        plan(Interval(1.0), (0.1, 0.5), (0.6, 0.2))
    with pytest.raises(InvalidInputError, match="robots coincide"):
        plan(Interval(1.0), (0.3, 0.3), (0.6, 0.9))
    with pytest.raises(InvalidInputError, match=r"expected at least the clearance 0\.2"):
        plan(Interval(1.0), (0.3, 0.4), (0.6, 0.9), clearance=0.2)
    with pytest.raises(InvalidInputError, match=r"clearance is -1\.0"):
        plan(Interval(1.0), (0.3, 0.4), (0.6, 0.9), clearance=-1.0)
    with pytest.raises(InvalidInputError, match="clearance is nan"):
        plan(Circle(1.0), (0.3, 0.4), (0.6, 0.9), clearance=float("nan"))
    with pytest.raises(InvalidInputError, match=r"neighbourhood is 0\.7"):
        make_planner(Circle(1.0), neighbourhood=0.7)
    with pytest.raises(InvalidInputError, match="start is"):
        plan(Circle(1.0), (0.3, 0.4, 0.5), (0.6, 0.9))


def test_circle_clearance_above_half_loop_is_rejected_at_the_states() -> None:
    with pytest.raises(InvalidInputError, match=r"expected at least the clearance 0\.6"):
        plan(Circle(1.0), (0.0, 0.5), (0.1, 0.6), clearance=0.6)


def test_lollipop_order_change_with_large_clearance_says_why() -> None:
    with pytest.raises(NoMotionError, match=r"clearance 0.5 >= loop/2 = 0.5"):
        plan(Lollipop(1.0, 1.0), (0.1, 0.6), (0.8, 0.3), clearance=0.5)
    p = plan(Lollipop(1.0, 1.0), (0.1, 0.6), (0.8, 0.3), clearance=0.49)
    assert p.domain == 1 and p.min_distance() >= 0.49
