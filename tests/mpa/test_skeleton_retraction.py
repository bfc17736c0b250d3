"""Skeletons and the deformation H: Betti numbers computed, H₁ lands on S, fixes S, distance monotone, continuity."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, note, settings
from hypothesis import strategies as st

from mpa import Circle, Interval, Lollipop, retract, skeleton_of
from mpa.skeleton import SkeletonPoint
from mpa.topology import rules_needed, topological_complexity
from tests.helpers.common import CIRCLES, EXACT, LOLLIPOPS, random_states

LOOPED = [*LOLLIPOPS, *CIRCLES]


@pytest.mark.parametrize("track", LOLLIPOPS, ids=repr)
def test_lollipop_skeleton_is_a_chain_with_three_cycles(track) -> None:  # type: ignore[no-untyped-def]
    sk = skeleton_of(track)
    assert sk.betti == (1, 3)
    assert {e.name for e in sk.graph.edges} == {"I1", "S1a", "S1b", "S2a", "S2b", "S3a", "S3b", "I2"}
    h = sk.model.half
    for j in (1, 2, 3):  # every circle has length c (model units) measured by either robot's travel
        assert sk.graph.edge(f"S{j}a").length + sk.graph.edge(f"S{j}b").length == pytest.approx(2 * h)


@pytest.mark.parametrize("track", [t for t in LOLLIPOPS if t.stick >= t.half], ids=repr)
def test_skeleton_points_are_generalized_antipodal(track) -> None:  # type: ignore[no-untyped-def]
    sk = skeleton_of(track)
    for e in sk.graph.edges:
        for t in np.linspace(0, e.length, 11):
            a, b = sk.state(SkeletonPoint(e.name, float(t)))
            assert track.distance(a, b) == pytest.approx(track.half, abs=EXACT), (e.name, t)
            back = sk.point_of_model_state(*sk.to_model([a, b]))
            assert np.allclose(sk.state(back), [a, b], atol=EXACT), (e.name, t, back)


def test_topological_complexity_from_computed_skeletons() -> None:
    assert skeleton_of(Interval(1.0)).betti == (2, 0)
    assert skeleton_of(Circle(1.0)).betti == (1, 1)
    assert topological_complexity(Interval(1.0)) == (1, 1)
    assert topological_complexity(Circle(2.0)) == (2,)
    assert topological_complexity(Lollipop(1.0, 1.0)) == (3,)
    assert topological_complexity(Lollipop(0.2, 1.0)) == (3,)
    assert [rules_needed(t) for t in (Interval(1.0), Circle(1.0), Lollipop())] == [1, 2, 3]


@pytest.mark.parametrize("track", LOOPED, ids=repr)
def test_retraction_lands_on_and_fixes_the_skeleton(track) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(11)
    x = random_states(track, 5000, rng, min_gap=1e-4)
    y = retract(track, x, 1.0)
    sk = skeleton_of(track)
    to_model = getattr(sk, "to_model", lambda p: p)
    model = getattr(sk, "model", track)
    d_model = model.distance(*to_model(y).T)
    assert np.max(np.abs(d_model - model.half)) < EXACT
    z = retract(track, y, 1.0)
    assert np.max(track.distance(z[:, 0], y[:, 0]) + track.distance(z[:, 1], y[:, 1])) < EXACT
    for t in (0.3, 0.7):  # H fixes S pointwise at every time, and traces are fibres of H₁
        assert np.max(track.distance(retract(track, y, t)[:, 0], y[:, 0])) < EXACT
        mid = retract(track, x, t)
        assert np.max(track.distance(retract(track, mid, 1.0)[:, 1], y[:, 1])) < 10 * EXACT


@pytest.mark.parametrize("track", LOOPED, ids=repr)
def test_distance_changes_monotonically_along_every_trace(track) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(12)
    x = random_states(track, 3000, rng, min_gap=1e-4)
    ts = np.linspace(0, 1, 21)
    d = np.array([track.distance(*retract(track, x, t).T) for t in ts])  # (21, N)
    steps = np.diff(d, axis=0)
    inc = steps >= -EXACT
    dec = steps <= EXACT
    monotone = np.all(inc, axis=0) | np.all(dec, axis=0)
    bad = np.flatnonzero(~monotone)
    assert len(bad) == 0, f"non-monotone distance along traces of {x[bad[:3]]}"
    if not isinstance(track, Lollipop) or track.stick >= track.half:  # distance linear in t, towards h
        want = d[0] + ts[:, None] * (track.half - d[0])
        assert np.max(np.abs(d - want)) < 1e-9


def test_trace_info_says_which_robot_moves_and_the_speed_ratio() -> None:
    from mpa.retraction import trace_info

    L = Lollipop(1.0, 1.0)
    far = trace_info(L, (0.1, 0.9))  # farther than h on the stick: the robot nearer the free end moves, B waits
    assert far.moving == "A" and far.speed_ratio == float("inf") and far.distance == pytest.approx((0.8, 0.5))
    assert far.text.startswith("A moves 0.3 m towards P while B waits")
    through_p = trace_info(L, (0.9, 1.2))  # x = 0.1, w = 0.2: radial scaling about P, speed ratio x : w
    assert through_p.moving == "both" and through_p.speed_ratio == pytest.approx(0.5)
    on_loop = trace_info(L, (1.1, 1.3))  # short arc avoids P: both move towards P along the long arc
    assert on_loop.moving == "both" and on_loop.speed_ratio == pytest.approx(0.1 / 0.7)
    assert trace_info(Circle(1.0), (0.1, 0.3)).moving == "A"  # the paper: A moves away from B, B waits
    assert trace_info(L, (0.1, 0.6)).moving == "none"


@settings(max_examples=3000, deadline=None)
@given(st.sampled_from(LOOPED), st.floats(0, 1), st.floats(0, 1), st.floats(-1, 1), st.floats(-1, 1))
def test_retraction_is_continuous(track, u, v, du, dv) -> None:  # type: ignore[no-untyped-def]
    L = np.nextafter(track.total_length, 0)
    x = np.array([u * L, v * L])
    if track.distance(*x) < 0.05:
        return
    delta = 1e-7
    x2 = np.clip(x + delta * np.array([du, dv]), 0, L)
    y1, y2 = retract(track, np.array([x, x2]), 1.0)
    gap = max(track.distance(y1[0], y2[0]), track.distance(y1[1], y2[1]))
    note(f"x = {x.tolist()}, x2 = {x2.tolist()}, H1 = {y1.tolist()} / {y2.tolist()}")
    # Lipschitz bound of H₁: the radial scalings have slope <= h/d; the loop scale κ of a short-stick lollipop
    # shrinks distances in the model by κ at most; two coordinates each.
    kappa = getattr(skeleton_of(track), "kappa", 1.0)
    bound = 4.0 * max(1.0, track.half / (kappa * track.distance(*x))) * delta
    assert gap <= bound


@pytest.mark.parametrize("track", [*LOOPED, Interval(1.0)], ids=repr)
def test_scalar_twins_agree_with_the_vectorized_versions(track) -> None:  # type: ignore[no-untyped-def]
    """The planner's scalar fast paths (distance, traces of H) equal the vectorized ones they shadow."""
    from mpa.retraction import lollipop_trace, lollipop_trace_scalar

    rng = np.random.default_rng(31)
    x = random_states(track, 3000, rng, min_gap=1e-4)
    vec = track.distance(x[:, 0], x[:, 1])
    assert max(abs(track.distance_scalar(float(a), float(b)) - d) for (a, b), d in zip(x, vec)) < EXACT
    if isinstance(track, Lollipop):
        sk = skeleton_of(track)
        m = sk.to_model(x)
        want = lollipop_trace(sk.model, m)
        got = np.array([lollipop_trace_scalar(sk.model.stick, sk.model.loop, a, b) for a, b in m])
        assert np.max(np.abs(got - want)) < EXACT


@pytest.mark.parametrize("track", [Lollipop(1.0, 1.0), Lollipop(0.6, 1.2), Lollipop(2.0, 0.5)], ids=repr)
def test_trace_on_vertices_and_every_case_matches_the_scalar_twin(track) -> None:  # type: ignore[no-untyped-def]
    # the vectorized trace computes every case branch-free: on P, the free end and the loop's seam as well
    from mpa.retraction import lollipop_trace, lollipop_trace_scalar

    rng = np.random.default_rng(32)
    sk = skeleton_of(track)
    ell, c = sk.model.stick, sk.model.loop
    m = rng.uniform(0.0, ell + c, (4000, 2))
    m[:300, 0], m[300:600, 1], m[600:700, 0], m[700:800, 1] = ell, ell, 0.0, ell + c * (1 - 1e-16)
    m = m[sk.model.distance(m[:, 0], m[:, 1]) > 1e-6]
    with np.errstate(all="raise"):
        want = lollipop_trace(sk.model, m)
    got = np.array([lollipop_trace_scalar(ell, c, a, b) for a, b in m.tolist()])
    assert np.max(np.abs(got - want)) < EXACT
