"""The measuring tools of :mod:`trajopt.analysis.stability`: the bisection to the fast/hard switch and the layout
δ-twins."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from mpa import Lollipop
from mpa.graph_track import GraphTrack
from trajopt import TrajectoryGenerator
from trajopt.analysis.stability import layout_queries, layout_twins, switch_points

ROOT = Path(__file__).resolve().parents[2]


def test_switch_points_bracket_the_switch() -> None:
    """Every switch point found has the line's side (within the switch bands: path ``"switch"``) on one side and the
    hard path on the other, 1e-9 m apart, and the trajectory barely moves across it (gap <= 1e-4 m, 1e-3 s)."""
    gen = TrajectoryGenerator(Lollipop(1.0, 1.0), clearance=0.15)
    pts = switch_points(gen, 150, np.random.default_rng(3))
    assert pts, "no switch point in 150 draws"
    for p in pts:
        assert p.paths == ("switch", "hard"), p
        assert 0.0 < p.width <= 1e-9
        assert np.array_equal(p.fast_start, p.hard_start)
        assert 0.0 <= p.gap <= 1e-4 and 0.0 <= p.time_gap <= 1e-3, p


def test_layout_twins_on_theta() -> None:
    """Theta: queries for every clearance that fits, twins at three δ; with unchanged routes the plans move by about
    δ (theta measured 0 same-route moves above 1e-3 m at δ = 1e-5 and 1e-7)."""
    track = GraphTrack.from_json(ROOT / "examples" / "tracks" / "theta.json")
    med = float(np.median(track.lengths))
    qs = layout_queries(track, 8, np.random.default_rng(1), (0.05 * med, 0.2 * med, 0.5 * med, 10.0 * med))
    assert 0 < len(qs) < 8  # the last clearance fits nowhere: its queries are left out
    twins = layout_twins(track, qs, (1e-5, 1e-7), np.random.default_rng(2))
    assert twins
    for t in twins:
        assert t.makespan_gap <= 10 * t.delta + 1e-9, t
        if not t.route_changed:
            assert t.gap <= 1e-3, t


def test_layout_twins_flag_swaps_and_the_circle_changes_routes_only_on_them() -> None:
    """``LayoutTwin.swap`` marks exactly the twins of swap queries (every fourth of :func:`layout_queries`). On the
    circle layout a swap's two motions (both robots one way round or the other) are equally fast, so its twins may
    change routes; every other query has one fastest motion there, and its twins keep their routes."""
    track = GraphTrack.from_json(ROOT / "examples" / "tracks" / "circle.json")
    qs = layout_queries(track, 24, np.random.default_rng(5), (0.05, 0.2))
    twins = layout_twins(track, qs, (1e-7,), np.random.default_rng(6))
    assert len(twins) >= 20
    for t in twins:
        _, st, gl = qs[t.query]
        assert t.swap == (gl == (st[1], st[0])), t
        if t.route_changed:
            assert t.swap, (qs[t.query], t)
    assert any(t.swap for t in twins) and any(not t.swap for t in twins)
