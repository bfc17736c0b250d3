"""The planners: ev∘s = id, continuity in u, collision-freeness, continuity of every rule on its domain,
jumps across every domain boundary, exactly TC rules, canonical cases, homotopy words."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, note, settings
from hypothesis import strategies as st

from mpa import Circle, Interval, Lollipop, make_planner, path_word, plan
from mpa.topology import rules_needed
from tests.helpers.common import (
    ALL_TRACKS,
    CIRCLES,
    CONTINUITY_DELTA,
    EXACT,
    LIPSCHITZ_K,
    LOLLIPOPS,
    MIN_GAP,
    path_gap,
    random_states,
    same_order_goals,
)

LOOPED = [*LOLLIPOPS, *CIRCLES]


def _queries(track, n: int, seed: int, min_gap: float = 1e-3):  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(seed)
    s = random_states(track, n, rng, min_gap)
    g = same_order_goals(track, s, random_states(track, n, rng, min_gap))
    return s, g


@pytest.mark.parametrize("track", ALL_TRACKS, ids=repr)
def test_paths_start_and_end_exactly_and_are_continuous_in_u(track) -> None:  # type: ignore[no-untyped-def]
    planner = make_planner(track)
    s, g = _queries(track, 1500, seed=1)
    for i in range(len(s)):
        p = planner.plan(s[i], g[i])
        n = max(400, p.samples_needed(0.005))
        x = p.sample(n)
        assert track.distance(x[0, 0], s[i, 0]) + track.distance(x[0, 1], s[i, 1]) < EXACT, (i, s[i], g[i])
        assert track.distance(x[-1, 0], g[i, 0]) + track.distance(x[-1, 1], g[i, 1]) < EXACT, (i, s[i], g[i])
        # equally spaced u: consecutive samples at most max-travel/(n-1) apart for each robot
        step = max(track.distance(x[:-1, 0], x[1:, 0]).max(), track.distance(x[:-1, 1], x[1:, 1]).max())
        assert step <= p.length / (n - 1) + EXACT
        assert p.length >= np.max(p.travel) - EXACT, (i, s[i], g[i], step)


@pytest.mark.parametrize("track", ALL_TRACKS, ids=repr)
def test_plans_never_come_closer_than_start_goal_or_half_loop(track) -> None:  # type: ignore[no-untyped-def]
    planner = make_planner(track)
    s, g = _queries(track, 1500, seed=2)
    floor = min(track.half, getattr(track, "stick", np.inf)) if not isinstance(track, Interval) else np.inf
    for i in range(len(s)):
        p = planner.plan(s[i], g[i])
        n = max(2000, p.samples_needed(0.001))
        x = p.sample(n)
        d = track.distance(x[:, 0], x[:, 1])
        # the distance is 1-Lipschitz in each robot's position: bound it between samples too
        step = p.length / (n - 1)
        lower = min(d.min(), ((d[:-1] + d[1:]) / 2 - step).min())
        bound = min(track.distance(*s[i]), track.distance(*g[i]), floor)
        assert lower >= bound - 2 * step - EXACT, (i, s[i].tolist(), g[i].tolist(), d.min(), bound)
        assert d.min() >= bound - EXACT, (i, s[i].tolist(), g[i].tolist(), d.min(), bound)


@pytest.mark.parametrize("track", ALL_TRACKS, ids=repr)
def test_exactly_tc_rules_over_ten_thousand_queries(track) -> None:  # type: ignore[no-untyped-def]
    planner = make_planner(track)
    s, g = _queries(track, 10_000, seed=3)
    domains = {planner.plan(s[i], g[i]).domain for i in range(len(s))}
    assert domains == set(range(1, rules_needed(track) + 1)), domains


@settings(max_examples=2500, deadline=None)
@given(
    st.sampled_from(ALL_TRACKS),
    st.lists(st.floats(0, 1), min_size=4, max_size=4),
    st.lists(st.floats(-1, 1), min_size=4, max_size=4),
)
def test_every_rule_is_continuous_on_its_domain(track, u, du) -> None:  # type: ignore[no-untyped-def]
    """Perturbing start and goal by δ inside one domain moves the path by at most K·δ (sup norm over u)."""
    L = np.nextafter(track.total_length, 0)
    s, g = np.array(u[:2]) * L, np.array(u[2:]) * L
    if min(track.distance(*s), track.distance(*g)) < MIN_GAP:
        return
    if isinstance(track, Interval) and np.sign(s[1] - s[0]) != np.sign(g[1] - g[0]):
        g = g[::-1].copy()
    s2 = np.clip(s + CONTINUITY_DELTA * np.array(du[:2]), 0, L)
    g2 = np.clip(g + CONTINUITY_DELTA * np.array(du[2:]), 0, L)
    p, q = plan(track, s, g), plan(track, s2, g2)
    if p.domain != q.domain:
        return  # the perturbation crossed a domain boundary: no continuity is claimed there
    gap = path_gap(track, p, q)
    note(f"{track!r}: {s.tolist()} -> {g.tolist()} vs {s2.tolist()} -> {g2.tolist()}, domain {p.domain}, gap {gap}")
    assert gap <= LIPSCHITZ_K * CONTINUITY_DELTA


@pytest.mark.parametrize("track", LOOPED, ids=repr)
def test_rule_continuity_seeded_sweep(track) -> None:  # type: ignore[no-untyped-def]
    """The same property over 2000 seeded queries per track; reports the largest ratio per domain."""
    rng = np.random.default_rng(4)
    planner = make_planner(track)
    s, g = _queries(track, 2000, seed=5, min_gap=MIN_GAP)
    worst: dict[int, float] = {}
    L = np.nextafter(track.total_length, 0)
    for i in range(len(s)):
        s2 = np.clip(s[i] + CONTINUITY_DELTA * rng.uniform(-1, 1, 2), 0, L)
        g2 = np.clip(g[i] + CONTINUITY_DELTA * rng.uniform(-1, 1, 2), 0, L)
        p, q = planner.plan(s[i], g[i]), planner.plan(s2, g2)
        if p.domain == q.domain:
            r = path_gap(track, p, q) / CONTINUITY_DELTA
            worst[p.domain] = max(worst.get(p.domain, 0.0), r)
            assert r <= LIPSCHITZ_K, (i, s[i].tolist(), g[i].tolist(), s2.tolist(), g2.tolist(), p.domain, r)
    assert set(worst) == set(range(1, rules_needed(track) + 1))


# ------------------------------------------------------------------------------------------------------
# every domain boundary is a real discontinuity: nearby queries on its two sides, paths a finite jump apart
ETA = 1e-7


def test_circle_boundary_between_domains_1_and_2_is_a_jump() -> None:
    for c in (1.0, 1.7):
        C = Circle(c)
        h, eps = C.half, 0.1 * C.half
        start = (0.3 * c, 0.3 * c + h)  # already antipodal: no preliminary step
        b_in = np.mod(start[1] + h + eps - ETA, c)  # B's ccw offset h + ε − η: domain 1 (ccw)
        b_out = np.mod(start[1] + h + eps + ETA, c)  # h + ε + η: domain 2 (shortest = clockwise)
        p = plan(C, start, (np.mod(b_in + h, c), b_in))
        q = plan(C, start, (np.mod(b_out + h, c), b_out))
        assert (p.domain, q.domain) == (1, 2)
        assert path_gap(C, p, q) > 0.5 * h


@pytest.mark.parametrize("track", [Lollipop(1.0, 1.0), Lollipop(2.0, 1.3)], ids=repr)
def test_lollipop_boundaries_are_jumps(track) -> None:  # type: ignore[no-untyped-def]
    sk = make_planner(track).skeleton  # type: ignore[attr-defined]
    h = track.half
    eps = 0.1 * h
    from mpa.skeleton import SkeletonPoint

    def st_(edge: str, t: float) -> np.ndarray:
        return sk.state(SkeletonPoint(edge, t))

    # 2 | 3: same circle S2, ccw offset h + ε ∓ η
    x = st_("S2a", 0.5 * h)
    p = plan(track, x, st_("S2b", 0.5 * h + eps - ETA))
    q = plan(track, x, st_("S2b", 0.5 * h + eps + ETA))
    assert (p.domain, q.domain) == (2, 3)
    assert path_gap(track, p, q) > 0.5 * h
    # 1 | 3: start on I1, goal on S1b at distance ε ∓ η from v2
    x = st_("I1", 0.5 * (track.stick - h))
    p = plan(track, x, st_("S1b", eps - ETA))
    q = plan(track, x, st_("S1b", eps + ETA))
    assert (p.domain, q.domain) == (1, 3)
    assert path_gap(track, p, q) > 0.5 * h
    # 1 | 2: antipodal pair on S2 at distance ε ∓ η from its vertices
    p = plan(track, st_("S2a", eps - ETA), st_("S2b", eps - ETA))
    q = plan(track, st_("S2a", eps + ETA), st_("S2b", eps + ETA))
    assert (p.domain, q.domain) == (1, 2)
    assert path_gap(track, p, q) > eps
    # 2 | 3 across the generalized kind: goal in the middle of S3, start near the far vertex v2 of S2
    y = st_("S3a", 0.5 * h)
    p = plan(track, st_("S2b", h - eps + ETA), y)
    q = plan(track, st_("S2b", h - eps - ETA), y)
    assert (p.domain, q.domain) == (2, 3)
    assert path_gap(track, p, q) > 0.5 * h


# ------------------------------------------------------------------------------------------------------
def _scaled(track: Lollipop, a: float, b: float) -> float:
    """Map the paper's coordinates (ℓ = c = 1) to a lollipop of other lengths (stick and loop scaled apart)."""
    return a * track.stick if a <= 1 else track.stick + (a - 1) * track.loop


CANONICAL = [
    ((0.1, 0.6), (0.3, 0.8), 1),
    ((0.1, 0.6), (0.8, 0.3), 1),
    ((1.25, 1.75), (1.75, 1.25), 2),
    ((0.8, 1.3), (0.7, 1.8), 2),
    ((1.25, 1.75), (1.4, 1.9), 3),
]


@pytest.mark.parametrize(("start", "goal", "domain"), CANONICAL)
def test_canonical_lollipop_cases(start, goal, domain) -> None:  # type: ignore[no-untyped-def]
    p = plan(Lollipop(1.0, 1.0), start, goal)
    assert p.domain == domain
    assert np.allclose(p.skeleton_start, start) and np.allclose(p.skeleton_goal, goal)  # already on S
    assert p.steps[0].u_end == 0.0 and p.steps[2].u_start == 1.0  # empty preliminary and final steps


@pytest.mark.parametrize(("stick", "loop"), [(2.0, 1.0), (3.0, 3.0), (4.0, 2.0)])
@pytest.mark.parametrize(("start", "goal", "domain"), CANONICAL)
def test_canonical_cases_on_other_lollipops(stick, loop, start, goal, domain) -> None:  # type: ignore[no-untyped-def]
    """The same configurations drawn on other lollipops (stick ≥ loop/2): positions on the stick measured from
    P keep their distance to P, loop angles scale with the loop."""
    tr = Lollipop(stick, loop)

    def conv(p: float) -> float:
        return stick - (1.0 - p) * loop if p <= 1 else stick + (p - 1.0) * loop

    s = (conv(start[0]), conv(start[1]))
    g = (conv(goal[0]), conv(goal[1]))
    assert plan(tr, s, g).domain == domain


def test_canonical_circle_cases() -> None:
    assert plan(Circle(1.0), (0.3, 0.6), (0.25, 0.1)).domain == 1
    assert plan(Circle(1.0), (0.1, 0.6), (0.3, 0.8)).domain == 2
    for c in (2.0, 0.7):
        assert plan(Circle(c), (0.3 * c, 0.6 * c), (0.25 * c, 0.1 * c)).domain == 1
        assert plan(Circle(c), (0.1 * c, 0.6 * c), (0.3 * c, 0.8 * c)).domain == 2


def test_domain_1_reverse_order_goes_round_the_loop_ccw() -> None:
    p = plan(Lollipop(1.0, 1.0), (0.1, 0.6), (0.8, 0.3))
    assert p.word == ("+I1", "+S1a", "+S2a", "+S3b", "-I2")
    assert p.routes[0].length == pytest.approx(2.1) and p.routes[1].length == pytest.approx(2.1)
    back = plan(Lollipop(1.0, 1.0), (0.8, 0.3), (0.1, 0.6))
    assert back.word == ("+I2", "+S3a", "+S2b", "+S1b", "-I1")  # also ccw round the loop


# ------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("track", [*LOOPED], ids=repr)
def test_words_of_sampled_paths_match_the_plans(track) -> None:  # type: ignore[no-untyped-def]
    planner = make_planner(track)
    s, g = _queries(track, 600, seed=6)
    for i in range(len(s)):
        p = planner.plan(s[i], g[i])
        x = p.sample(p.samples_needed(0.002))
        assert path_word(track, x) == p.word, (i, s[i].tolist(), g[i].tolist(), p.word)
        w = np.stack([p.routes[0].position(p.waypoints_s[:, 0]), p.routes[1].position(p.waypoints_s[:, 1])], -1)
        assert np.max(track.distance(w[:, 0], p.waypoints[:, 0]) + track.distance(w[:, 1], p.waypoints[:, 1])) < 1e-9


def test_interval_plan_is_a_straight_translation() -> None:
    p = plan(Interval(2.0), (0.1, 0.5), (1.2, 1.9))
    assert p.domain == 1 and p.word == ()
    u = np.linspace(0, 1, 11)
    assert np.allclose(p.path(u), (1 - u)[:, None] * [0.1, 0.5] + u[:, None] * [1.2, 1.9])


def test_word_keeps_a_partial_remainder_after_returning_through_a_vertex() -> None:
    """A full traversal of S1b, a sample exactly on the vertex v1 (an I1 point), then part of S1b back: the class
    is the partial +S1b, not the empty word (found by the benchmark on the raw-plan fallback)."""
    from mpa.homotopy import word_from_samples

    sk = make_planner(Lollipop()).skeleton  # type: ignore[attr-defined]
    idx = {e.name: i for i, e in enumerate(sk.graph.edges)}
    edges = [idx["S2b"], idx["S2b"], idx["S1b"], idx["S1b"], idx["I1"], idx["S1b"]]
    assert word_from_samples(sk.graph, edges, [0.3, 0.5, 0.0, 0.5, 0.5, 0.475]) == ("+S2b", "+S1b")
    assert word_from_samples(sk.graph, edges, [0.3, 0.5, 0.0, 0.5, 0.5, 0.5]) == ("+S2b", "+S1b")
    # a path that never leaves S1b (up to v1 and back): its net run along the edge
    assert word_from_samples(sk.graph, [idx["S1b"], idx["I1"], idx["S1b"]], [0.4, 0.5, 0.45]) == ("+S1b",)
    assert word_from_samples(sk.graph, [idx["S1b"], idx["I1"], idx["S1b"]], [0.4, 0.5, 0.4]) == ()


def test_raw_plan_fallback_verifies_where_it_stops_on_a_vertex() -> None:
    from trajopt import TrajectoryGenerator

    s, g = (0.18955335672233398, 0.009798829977151202), (0.6458416073279567, 1.981489436482444)
    traj = TrajectoryGenerator(Lollipop(1.0, 1.0), clearance=0.05, optimize=False).generate(s, g)
    assert traj.word == ("+I2", "+S3a", "+S2b", "+S1b") == traj.plan.word
