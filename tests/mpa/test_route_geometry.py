"""The route-coordinate geometry of :mod:`mpa.geometry` on the paper's tracks and on layouts.

Paper plans' routes convert to directed routes on ``as_graph_track()`` (:func:`mpa.routes.directed_route`); the
distance, the exact minimum along polylines and the convex cells must agree with the track metric and with dense
sampling.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from mpa import Circle, Interval, Lollipop, NoMotionError, Track, plan
from mpa.geometry import RouteGeometry
from mpa.routes import directed_route

TRACKS = [Lollipop(1.0, 1.0), Lollipop(0.3, 1.2), Lollipop(2.0, 0.6), Circle(1.7), Interval(2.0)]


def _plans(track: Track, n: int, seed: int) -> list:  # type: ignore[type-arg]
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        s, g = rng.uniform(0, track.total_length, 2), rng.uniform(0, track.total_length, 2)
        if isinstance(track, Interval):
            s, g = np.sort(s), np.sort(g)
        try:
            out.append(plan(track, s, g, 0.0))
        except NoMotionError:
            continue
    return out


def _sigma_box(p) -> tuple[np.ndarray, np.ndarray]:  # type: ignore[no-untyped-def]
    """The route-coordinate box ``(lo, hi)`` of a plan's two routes (shapes (2,))."""
    ra, rb = p.routes
    return np.array([ra.sigma_min, rb.sigma_min]), np.array([ra.sigma_max, rb.sigma_max])


def _geometry(track: Track, p) -> RouteGeometry:  # type: ignore[no-untyped-def]
    routes = (directed_route(p.routes[0]), directed_route(p.routes[1]))
    return RouteGeometry(track.as_graph_track().geometry, routes)


@pytest.mark.parametrize("track", TRACKS, ids=repr)
def test_directed_routes_follow_the_paper_routes(track: Track) -> None:
    for i, p in enumerate(_plans(track, 60, 1)):
        for r in p.routes:
            sig = np.linspace(r.sigma_min, r.sigma_max, 401)
            e, o = directed_route(r).positions(sig)
            gap = track.distance(track.from_graph_position(e, o), r.position(sig))
            assert np.max(gap) <= 1e-9, (i, p.start, p.goal, float(np.max(gap)))


@pytest.mark.parametrize("track", TRACKS, ids=repr)
def test_distance_and_polyline_minimum_are_exact(track: Track) -> None:
    rng = np.random.default_rng(2)
    for i, p in enumerate(_plans(track, 40, 3)):
        geom, (ra, rb), (lo, hi) = _geometry(track, p), p.routes, _sigma_box(p)
        sig = lo + rng.uniform(size=(200, 2)) * (hi - lo)
        want = track.distance(ra.position(sig[:, 0]), rb.position(sig[:, 1]))
        np.testing.assert_allclose(geom.distance(sig), want, atol=1e-9, err_msg=f"plan {i}: {p.start} -> {p.goal}")
        pts = lo + rng.uniform(size=(4, 2)) * (hi - lo)
        exact = geom.polyline_min_distance(pts)
        dense = np.concatenate([np.linspace(a, b, 4001) for a, b in itertools.pairwise(pts)])
        sampled = float(np.min(geom.distance(dense)))
        step = float(np.max(np.abs(np.diff(dense, axis=0)).sum(axis=1)))
        assert exact <= sampled + 1e-9 and exact >= sampled - step, (i, exact, sampled)
        # the plan's own polyline: the exact minimum is at most the plan's sampled minimum (20 001 samples)
        exact = geom.polyline_min_distance(p.waypoints_s)
        travel = float(np.abs(np.diff(p.waypoints_s, axis=0)).sum())
        assert p.min_distance() - 2 * travel / 20000 - 1e-9 <= exact <= p.min_distance() + 1e-9, (i, exact)


@pytest.mark.parametrize("track", TRACKS, ids=repr)
def test_cell_rows_bound_the_distance_and_are_exact_on_their_side(track: Track) -> None:
    rng = np.random.default_rng(4)
    for i, p in enumerate(_plans(track, 30, 5)):
        geom = _geometry(track, p)
        for u in rng.uniform(size=5):
            mid = p.path_s(u)
            (ia, ib), rows = geom.cell_rows(mid)
            box = geom.box(ia, ib)
            q = box[:, 0] + rng.uniform(size=(100, 2)) * (box[:, 1] - box[:, 0])
            g = np.array([[ga, gb] for ga, gb, _ in rows])
            h = np.array([c for _, _, c in rows])
            vals = q @ g.T + h
            d = geom.distance(q)
            # min over the rows never exceeds the distance: rows >= D imply d >= D (the cell is sound)
            assert np.all(vals.min(axis=1) <= d + 1e-9), (i, u)
            # at mid itself the rows are exact
            dm = float(geom.distance(mid))
            assert min(gA * mid[0] + gB * mid[1] + c for gA, gB, c in rows) == pytest.approx(dm, abs=1e-9)


@pytest.mark.parametrize("track", TRACKS, ids=repr)
def test_chord_minimum_is_exact_on_independent_chords(track: Track) -> None:
    rng = np.random.default_rng(6)
    for i, p in enumerate(_plans(track, 30, 7)):
        geom, (lo, hi) = _geometry(track, p), _sigma_box(p)
        a = lo + rng.uniform(size=(25, 2)) * (hi - lo)
        b = lo + rng.uniform(size=(25, 2)) * (hi - lo)
        b[0] = a[0]  # a chord of length 0
        a[1, 0] = geom.routes[0].breaks[len(geom.routes[0].breaks) // 2]  # an end on a break
        exact = geom.chord_min_distances(a, b)
        lam = np.linspace(0.0, 1.0, 2001)[None, :, None]
        dense = a[:, None, :] + lam * (b - a)[:, None, :]
        sampled = np.min(geom.distance(dense), axis=1)
        step = np.abs(b - a).sum(axis=1) / 2000
        assert np.all(exact <= sampled + 1e-9), (i, exact - sampled)
        assert np.all(exact >= sampled - step - 1e-9), (i, exact - sampled)
        # the polyline version is the chord version on consecutive points
        np.testing.assert_array_equal(geom.segment_min_distances(a), geom.chord_min_distances(a[:-1], a[1:]))
