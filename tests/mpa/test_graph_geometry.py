"""Exact graph distance and the exact minimum along straight moves (mpa.geometry)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mpa.geometry import DirectedRoute, GraphGeometry
from mpa.graph_track import GraphTrack
from tests.helpers.graph_helpers import EXACT, brute_distance, random_layout, random_position


@pytest.mark.parametrize("seed", range(40))
def test_distance_matches_brute_force_and_is_a_metric(seed: int) -> None:
    rng = np.random.default_rng(seed)
    track = random_layout(rng)
    g = track.geometry
    pts = [random_position(track, rng) for _ in range(6)]
    for a in pts:
        for b in pts:
            d = g.distance_scalar(a[0], a[1], b[0], b[1])
            assert d == pytest.approx(brute_distance(track, a, b), abs=EXACT), (seed, a, b)
            assert d == pytest.approx(g.distance_scalar(b[0], b[1], a[0], a[1]), abs=EXACT)
            assert float(g.distance(a[0], a[1], b[0], b[1])) == pytest.approx(d, abs=1e-12)
            for c in pts:
                dac = g.distance_scalar(a[0], a[1], c[0], c[1])
                dcb = g.distance_scalar(c[0], c[1], b[0], b[1])
                assert d <= dac + dcb + EXACT, (seed, a, b, c)


def test_vectorized_distance_shapes() -> None:
    track = GraphTrack.from_layout({"edges": [["F", "P", 1.0], ["P", "P", 1.0]]})
    g = track.geometry
    e = np.array([[0, 1], [1, 1]])
    s = np.array([[0.2, 0.1], [0.9, 0.5]])
    d = g.distance(e, s, 1, 0.5)
    assert d.shape == (2, 2)
    assert d[0, 0] == pytest.approx(0.8 + 0.5)
    assert d[1, 0] == pytest.approx(0.4)
    assert d[1, 1] == pytest.approx(0.0)


def test_loops_and_long_parallel_edges_never_shorten_dv() -> None:
    track = GraphTrack.from_layout({"edges": [["a", "b", 2.0], ["a", "b", 5.0], ["a", "a", 0.5], ["b", "c", 1.0]]})
    dv = track.geometry.dv
    assert dv[0, 1] == 2.0 and dv[0, 0] == 0.0 and dv[0, 2] == 3.0


def test_cell_terms_reproduce_distance() -> None:
    rng = np.random.default_rng(7)
    for _ in range(20):
        track = random_layout(rng)
        g = track.geometry
        e, f = (int(x) for x in rng.integers(0, track.n_edges, 2))
        s = rng.uniform(0, track.lengths[e], 50)
        t = rng.uniform(0, track.lengths[f], 50)
        terms = g.cell_terms(e, f)
        d = np.min([ca * s + cb * t + c0 for ca, cb, c0 in terms], axis=0)
        if e == f:
            d = np.minimum(d, np.abs(s - t))
        np.testing.assert_allclose(d, g.distance(e, s, f, t), atol=EXACT)


@pytest.mark.parametrize("seed", range(30))
def test_segment_min_is_exact(seed: int) -> None:
    """Never above dense sampling, and within the sampling error (2 · step length) of it."""
    rng = np.random.default_rng(100 + seed)
    track = random_layout(rng)
    g = track.geometry
    lam = np.linspace(0.0, 1.0, 2001)
    for _ in range(20):
        e, f = (int(x) for x in rng.integers(0, track.n_edges, 2))
        if rng.random() < 0.3:
            f = e
        p0 = np.array([rng.uniform(0, track.lengths[e]), rng.uniform(0, track.lengths[f])])
        p1 = np.array([rng.uniform(0, track.lengths[e]), rng.uniform(0, track.lengths[f])])
        exact = float(g.segment_min(e, f, p0, p1))
        pts = p0 + lam[:, None] * (p1 - p0)
        sampled = float(np.min(g.distance(e, pts[:, 0], f, pts[:, 1])))
        bound = 2.0 * np.abs(p1 - p0).max() / (len(lam) - 1)
        assert exact <= sampled + 1e-12, (seed, e, f, p0, p1)
        assert exact >= sampled - bound - EXACT, (seed, e, f, p0, p1)
        assert g.segment_min_scalar(e, f, *p0, *p1) == pytest.approx(exact, abs=1e-12)


def test_route_min_distance_splits_at_edge_changes() -> None:
    # lollipop: A runs from the free end up the stick and round the loop; B stands on the loop opposite P
    track = GraphTrack.from_layout({"edges": [["F", "P", 1.0], ["P", "P", 2.0]]})
    g = track.geometry
    ra = DirectedRoute(np.array([0, 1]), np.array([1, 1]), np.array([0.0, 0.0]), np.array([0.0, 1.0, 1.8]))
    rb = DirectedRoute.standing(1, 1.0)
    w = np.array([[0.0, 0.0], [1.8, 0.0]])
    exact = g.route_min_distance(ra, rb, w)
    r = np.linspace(0, 1.8, 3601)
    ea, sa = ra.positions(r)
    sampled = np.min(g.distance(ea, sa, 1, 1.0))
    assert exact == pytest.approx(0.2, abs=1e-12)
    assert exact <= sampled + 1e-12


def test_geometry_rejects_mismatched_arrays() -> None:
    from mpa.errors import InvalidInputError

    with pytest.raises(InvalidInputError, match="1-D arrays"):
        GraphGeometry(2, [0], [1, 0], [1.0])


def test_route_with_origin_and_backward_moves() -> None:
    """A smoother's signed route coordinate: origin -1, polyline moving back and forth across a vertex."""
    track = GraphTrack.from_layout({"edges": [["F", "P", 1.0], ["P", "P", 2.0]]})
    g = track.geometry
    ra = DirectedRoute.from_pieces([0, 1], [1, 1], [0.0, 0.0], [1.0, 2.0], origin=-1.0)
    rb = DirectedRoute.from_pieces([1], [-1], [2.0], [2.0])
    w = np.array([[-0.5, 0.0], [1.5, 0.5], [0.2, 1.9], [-1.0, 0.3]])
    exact = g.route_min_distance(ra, rb, w)
    lam = np.linspace(0, 1, 4001)[:, None]
    pts = np.concatenate([w[k] + lam * (w[k + 1] - w[k]) for k in range(len(w) - 1)])
    (ea, sa), (eb, sb) = ra.positions(pts[:, 0]), rb.positions(pts[:, 1])
    sampled = float(np.min(g.distance(ea, sa, eb, sb)))
    assert exact <= sampled + 1e-12
    assert exact >= sampled - 2 * 2.0 / 4000 - 1e-12
    assert ra.length == 3.0 and ra.positions(-1.0)[1] == 0.0


@settings(max_examples=300, deadline=None)
@given(
    pts=st.lists(
        st.tuples(st.floats(-50, 50, allow_nan=False), st.floats(-50, 50, allow_nan=False)), min_size=1, max_size=12
    ),
    step=st.floats(1e-3, 20.0),
)
def test_densify_polyline_keeps_the_vertices_and_the_step(pts: list[tuple[float, float]], step: float) -> None:
    from mpa.geometry import densify_polyline

    p = np.array(pts, dtype=float)
    out = densify_polyline(p, step)
    assert out.shape[1] == 2 and np.array_equal(out[0], p[0]) and np.array_equal(out[-1], p[-1])
    if len(p) > 1:
        gaps = np.max(np.abs(np.diff(out, axis=0)), axis=1)
        assert np.all(gaps <= step * (1 + 1e-9) + 1e-12), float(gaps.max())
        # every vertex of the polyline is a point of the output, in order, and the legs' points lie on the legs
        n = np.maximum(1, np.ceil(np.max(np.abs(np.diff(p, axis=0)), axis=1) / step).astype(int))
        assert len(out) == int(n.sum()) + 1
        starts = np.concatenate([[0], np.cumsum(n)])
        np.testing.assert_array_equal(out[starts[:-1]], p[:-1])


def test_directed_routes_and_graph_forms_are_built_once() -> None:
    from mpa import Lollipop, make_planner
    from mpa.routes import directed_route

    track = Lollipop(1.0, 1.0)
    assert track.as_graph_track() is track.as_graph_track()
    plan = make_planner(track, 0.05).plan((0.2, 0.5), (0.5, 0.2))
    for route in plan.routes:
        assert directed_route(route) is directed_route(route)


def test_scalar_route_positions_equal_the_vectorized_ones() -> None:
    # the gate's few cut points and the fast path's one-segment minimum use the plain-Python twins
    from mpa import Circle, Lollipop, make_planner
    from mpa.routes import directed_route

    rng = np.random.default_rng(12)
    for track in (Lollipop(1.0, 1.0), Lollipop(0.3, 1.2), Circle(1.0)):
        for _ in range(20):
            plan = make_planner(track, 0.0).plan(rng.uniform(0, track.total_length, 2), (0.05, 0.5))
            for route in map(directed_route, plan.routes):
                r = np.concatenate([rng.uniform(route.breaks[0] - 0.1, route.breaks[-1] + 0.1, 100), route.breaks])
                edges, offsets = route.positions(r)
                idx = route.piece_index(r)
                for k, x in enumerate(r.tolist()):
                    assert route.position_scalar(x) == (edges[k], offsets[k])
                    assert route.piece_index_scalar(x) == idx[k]
