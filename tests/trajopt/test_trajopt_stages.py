"""The stages one by one: exact separation geometry, cells, C² blends, 1-DoF timing, gate."""

from __future__ import annotations

import dataclasses
import itertools
from typing import NamedTuple

import numpy as np
import pytest

from mpa import Circle, Interval, Lollipop, make_planner
from tests.helpers.common import random_plans
from trajopt import Limits, TrajectoryGenerator, verify_setpoints
from trajopt.path.planview import densify, route_geometry
from trajopt.timing import (
    blend_polyline,
    jerk_limited_scaling,
    min_time_rest_to_rest,
    spline_path,
    toppra_profile,
)

TRACKS = [Lollipop(1.0, 1.0), Lollipop(0.4, 1.5), Circle(1.0), Interval(1.0)]


@pytest.mark.parametrize("track", TRACKS, ids=repr)
def test_polyline_min_distance_is_exact(track) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(5)
    for p in random_plans(track, 0.02, 15, 1):
        geom = route_geometry(track, p.routes)
        lo = np.array([r.sigma_min for r in p.routes])
        hi = np.array([r.sigma_max for r in p.routes])
        for _ in range(5):
            pts = lo + rng.uniform(size=(3, 2)) * (hi - lo)
            exact = geom.polyline_min_distance(pts)
            dense = geom.distance(densify(pts, 2e-4)).min()
            assert exact <= dense + 1e-9, (pts, exact, dense)
            assert dense - exact <= 4e-4, (pts, exact, dense)


class _Cells(NamedTuple):
    points: np.ndarray
    boxes: np.ndarray
    rows: list  # type: ignore[type-arg]


def _plan_cells(geom, waypoints):  # type: ignore[no-untyped-def]
    """The plan's polyline cut at every route break, with the convex cell (box, half-planes) of every piece."""
    p = np.asarray(waypoints, dtype=float)
    pts = [p[0]]
    for a, b in itertools.pairwise(p):
        lam = [0.0, 1.0]
        for r in (0, 1):
            br = geom.routes[r].breaks
            if b[r] != a[r]:
                t = (br - a[r]) / (b[r] - a[r])
                lam.extend(t[(t > 0) & (t < 1)].tolist())
        for t in sorted(set(lam))[1:]:
            pts.append(a + t * (b - a))
    q = np.array(pts)
    q = q[np.concatenate([[True], np.max(np.abs(np.diff(q, axis=0)), axis=1) > 1e-10])]
    boxes, rows = [], []
    for k in range(len(q) - 1):
        (ia, ib), rr = geom.cell_rows(0.5 * (q[k] + q[k + 1]))
        boxes.append(geom.box(ia, ib))
        rows.append(rr)
    return _Cells(q, np.array(boxes), rows)


@pytest.mark.parametrize("track", TRACKS[:3], ids=repr)
def test_cells_imply_clearance(track) -> None:  # type: ignore[no-untyped-def]
    """Random points inside a plan piece's cell (box and half-planes) keep d >= D."""
    D = 0.05
    rng = np.random.default_rng(2)
    for p in random_plans(track, D, 10, 3):
        geom = route_geometry(track, p.routes)
        cells = _plan_cells(geom, p.waypoints_s)
        for k in range(len(cells.points) - 1):
            box, rows = cells.boxes[k], cells.rows[k]
            lo, hi = box[:, 0], box[:, 1]
            lo, hi = np.maximum(lo, [-5, -5]), np.minimum(hi, [5, 5])
            pts = lo + rng.uniform(size=(400, 2)) * (hi - lo)
            ok = np.ones(len(pts), bool)
            for ga, gb, h in rows:
                if np.isfinite(h):
                    ok &= ga * pts[:, 0] + gb * pts[:, 1] + h >= D
            d = geom.distance(pts[ok])
            assert np.all(d >= D - 1e-12)
            mid = 0.5 * (cells.points[k] + cells.points[k + 1])
            assert all(ga * mid[0] + gb * mid[1] + h >= D - 1e-9 for ga, gb, h in rows if np.isfinite(h))


def test_blend_is_c2_and_collision_checked() -> None:
    track = Lollipop(1.0, 1.0)
    p = make_planner(track, 0.05).plan((1.25, 1.75), (1.4, 1.9))
    geom = route_geometry(track, p.routes)
    corners = np.array([[0.0, 0.0], [0.3, 0.1], [0.35, 0.5]])
    path = blend_polyline(corners, geom.polyline_min_distance, 0.05)
    assert path.radii[1] > 0 and path.is_blend.sum() == 1
    for b in path.breaks[1:-1]:
        for order in (0, 1, 2):
            left = path(np.array([b]), order, piece=[np.searchsorted(path.breaks, b) - 1])
            right = path(np.array([b]), order, piece=[np.searchsorted(path.breaks, b)])
            np.testing.assert_allclose(left, right, atol=1e-9, err_msg=f"order {order} at s = {b}")
    np.testing.assert_allclose(path(np.array([0.0, path.length])), corners[[0, -1]], atol=1e-12)


def test_derivatives_in_one_pass_equal_each_order() -> None:
    # BlendedPath.derivatives (Horner, up to the path's degree) is what sampling uses; __call__ is the reference
    rng = np.random.default_rng(11)
    for k in range(300):
        pts = np.cumsum(rng.normal(size=(int(rng.integers(3, 8)), 2)), axis=0)
        path = [blend_polyline(pts), spline_path(pts), blend_polyline(pts[:2])][k % 3]
        s = rng.uniform(-0.1, path.length + 0.1, size=200)
        pieces = np.clip(np.searchsorted(path.breaks, s) - 1, 0, len(path.coef) - 1)
        for piece in (None, pieces):
            got = path.derivatives(s, piece)
            for order in range(4):
                ref = path(s, order, piece)
                scale = max(1.0, float(np.max(np.abs(ref))))
                assert np.max(np.abs(got[order] - ref)) <= 1e-12 * scale, (k, order, path.degree)


def test_unsafe_corner_is_passed_at_rest() -> None:
    corners = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    path = blend_polyline(corners, lambda pts: 0.0, 0.05)  # every blend "collides"
    assert path.radii[1] == 0 and path.stop.tolist() == [True, True, True]
    ts = jerk_limited_scaling(path, Limits(0.5, 1.0, 5.0))
    _, v, _, _ = ts.sample(np.array([0.0, ts.duration]))
    assert np.allclose(v, 0.0)
    one = min_time_rest_to_rest(1.0, 0.5, 1.0, 5.0)
    assert ts.duration == pytest.approx(2 * one, rel=1e-9)


def test_toppra_bounds_the_jerk_limited_time() -> None:
    track = Lollipop(1.0, 1.0)
    p = make_planner(track, 0.05).plan((0.3, 1.5), (1.2, 0.4))
    gen = TrajectoryGenerator(track)
    traj = gen.generate_from_plan(p)
    assert not traj.fallback
    path = blend_polyline(np.array([[0, 0], [0.5, 0.2], [0.9, 1.1]]), None)
    _, _, dur = toppra_profile(path, gen.limits)
    ts = jerk_limited_scaling(path, gen.limits)
    assert dur <= ts.duration


@pytest.fixture(scope="module")
def good():  # type: ignore[no-untyped-def]
    return TrajectoryGenerator(Lollipop(1.0, 1.0), clearance=0.05).generate((0.1, 0.6), (0.8, 0.3))


def _check(traj, **changes):  # type: ignore[no-untyped-def]
    columns = ("t", "track", "s", "v", "a", "j")
    arrays = {k: getattr(traj, k).copy() for k in columns}
    arrays.update(changes)
    p = traj.plan
    return verify_setpoints(
        p.track,
        p.routes,
        *(arrays[k] for k in columns),
        limits=traj.limits,
        clearance=traj.clearance,
        start=p.start,
        goal=p.goal,
        word=p.word,
        rate=traj.rate,
    )


def test_gate_accepts_good(good) -> None:  # type: ignore[no-untyped-def]
    rep = _check(good)
    assert rep.ok, rep.failures
    assert rep.min_separation_between >= good.clearance - 1e-9


def test_gate_rejects_tampering(good) -> None:  # type: ignore[no-untyped-def]
    j = good.j.copy()
    j[10, 0] = 1.01 * good.limits.j[0]
    assert any("|j|" in f for f in _check(good, j=j).failures)
    v = good.v.copy()
    v[-1, 1] = 1e-3
    assert any("not at rest" in f for f in _check(good, v=v).failures)
    tr = good.track.copy()
    tr[5, 0] += 0.01
    assert any("route.position" in f for f in _check(good, track=tr).failures)
    t = good.t.copy()
    t[3] += 1e-4
    assert any("time grid" in f for f in _check(good, t=t).failures)


def test_gate_rejects_collisions_and_other_classes() -> None:
    """A straight σ-line that cuts through the forbidden band, and a motion in another class, are refused."""
    track = Lollipop(1.0, 1.0)
    gen = TrajectoryGenerator(track, clearance=0.05)
    traj = gen.generate((1.25, 1.75), (1.75, 1.25))  # domain 2: ccw round S2
    p = traj.plan
    rng = np.arange(len(traj.t)) / max(len(traj.t) - 1, 1)
    # A stays, B goes straight the other way round: crosses A
    s = np.stack([np.zeros_like(rng), -p.routes[1].length * rng], axis=1)
    pos = np.stack([p.routes[0].position(s[:, 0]), p.routes[1].position(s[:, 1])], axis=1)
    rep = _check(traj, s=s, track=pos, v=np.zeros_like(s), a=np.zeros_like(s), j=np.zeros_like(s))
    assert not rep.ok
    assert any("separation" in f for f in rep.failures)
    assert any("goal" in f or "class" in f for f in rep.failures)


def test_trajectory_is_frozen(good) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(dataclasses.FrozenInstanceError):
        good.makespan = 0.0  # type: ignore[misc]


def test_toppra_bounds_the_hard_path_timing_from_below() -> None:
    """toppra (v/a limits, no jerk) is the time-optimal reference of the hard path's filtered timing."""
    from trajopt.timing import filtered_scaling, spline_path

    rng = np.random.default_rng(5)
    limits = Limits(0.5, 1.0, 5.0)
    for _ in range(20):
        nodes = np.cumsum(rng.uniform(-0.3, 0.3, (33, 2)), axis=0)
        path = spline_path(nodes)
        _, _, dur = toppra_profile(path, limits)
        filtered = filtered_scaling(path, limits)
        assert filtered.duration >= dur * (1 - 1e-3), (filtered.duration, dur)


def test_filtered_timing_of_a_path_shorter_than_its_plateaus() -> None:
    """τ·vmax beyond the path's length: the plateau speed is lowered (no stuck profile, no fallback).

    Soak query 10758 of seed 0 (lollipop 1.255/0.574, a/j = 2.27 s) used to fall back with "the timing is stuck".
    """
    from trajopt.timing import filtered_scaling, spline_path

    limits = Limits([1.9482514061192715], [4.886817299458834], [2.154572312142627])
    rng = np.random.default_rng(7)
    for _ in range(10):
        nodes = np.cumsum(rng.uniform(-0.05, 0.1, (33, 2)), axis=0)
        path = spline_path(nodes)
        sc = filtered_scaling(path, limits)
        t = np.linspace(0.0, sc.duration, 2001)
        q, v, a, j = sc.sample(t)
        assert np.isfinite(sc.duration) and sc.duration > 0
        assert np.allclose(q[-1], nodes[-1], atol=1e-9) and np.allclose(v[[0, -1]], 0.0, atol=1e-9)
        assert np.all(np.abs(v) <= limits.v + 1e-9) and np.all(np.abs(a) <= limits.a + 1e-9)
        assert np.all(np.abs(j) <= limits.j + 1e-6)
    track = Lollipop(1.2550156546350668, 0.5737858793370452)
    gen = TrajectoryGenerator(track, clearance=0.05940032929886244, limits=limits, rate=100.0)
    traj = gen.generate((0.36575297279437663, 0.49313140033489167), (1.7683246736261726, 0.5878900529500634))
    assert not traj.fallback, traj.fallback_reason
