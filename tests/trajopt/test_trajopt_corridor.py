"""The corridor QP of the hard path: the known-active-set solve is DAQP's solution, the hull clearance is the
minimum over all chords of every window."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from mpa import Lollipop
from tests.helpers.common import random_plans
from trajopt import Limits
from trajopt.generator import separation_margin
from trajopt.path.corridor import (
    CORRIDOR_ITERATIONS,
    CORRIDOR_SEGMENTS,
    CorridorProblem,
    corridor_radii,
    hull_clearance,
)
from trajopt.path.planview import plan_view

TRACKS = [Lollipop(1.0, 1.0), Lollipop(1.5, 0.8)]
LIMITS = Limits(0.5, 1.0, 5.0)
SEP = 0.05 + separation_margin(LIMITS, 100.0)


def _samples(view, n):  # type: ignore[no-untyped-def]
    c = view.path_s(np.linspace(0.0, 1.0, n + 1))
    c[0], c[-1] = view.waypoints[0], view.waypoints[-1]
    return c


@pytest.fixture(scope="module")
def problem() -> CorridorProblem:
    return CorridorProblem(CORRIDOR_SEGMENTS, LIMITS.v)


@pytest.mark.parametrize("track", TRACKS, ids=repr)
def test_known_active_set_gives_daqps_solution(track, problem) -> None:  # type: ignore[no-untyped-def]
    verified = 0
    for p in random_plans(track, 0.05, 25, 1):
        view = plan_view(p)
        centers = _samples(view, problem.n)
        active = None
        for _ in range(CORRIDOR_ITERATIONS):
            free = corridor_radii(view.geom, centers, SEP)
            warm, st = problem.solve(centers, free, view.lower, view.upper, active)
            cold, st0 = problem.solve(centers, free, view.lower, view.upper)
            assert st["qp_success"] and st0["qp_status"] != "KKT_VERIFIED"
            np.testing.assert_allclose(warm, cold, rtol=0.0, atol=1e-9)
            verified += st["qp_status"] == "KKT_VERIFIED"
            active = st["active"]
            centers = np.clip(warm, view.lower, view.upper)
    assert verified > 0  # the shortcut is exercised


def test_a_wrong_active_set_falls_back_to_daqp(problem) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(2)
    nrows = 2 * problem.nx
    for p in random_plans(TRACKS[0], 0.05, 10, 3):
        view = plan_view(p)
        centers = _samples(view, problem.n)
        free = corridor_radii(view.geom, centers, SEP)
        cold, _ = problem.solve(centers, free, view.lower, view.upper)
        guesses = [
            (np.arange(nrows // 2), np.ones(nrows // 2)),  # every ball row at its upper side
            (np.array([0, 0]), np.array([1.0, 1.0])),  # a repeated row: singular
            (np.sort(rng.choice(nrows, 5, replace=False)), rng.choice([-1.0, 1.0], 5)),
        ]
        for k, guess in enumerate(guesses):
            warm, st = problem.solve(centers, free, view.lower, view.upper, guess)
            np.testing.assert_allclose(warm, cold, rtol=0.0, atol=1e-9)
            if k == 1:  # singular: DAQP solved it (the other guesses may be repaired, then verified)
                assert st["qp_status"] != "KKT_VERIFIED"
            assert st["qp_success"]


@pytest.mark.parametrize("track", TRACKS, ids=repr)
def test_hull_clearance_is_the_minimum_over_all_chords_of_each_window(track) -> None:  # type: ignore[no-untyped-def]
    for p in random_plans(track, 0.05, 15, 4):
        view = plan_view(p)
        centers = _samples(view, CORRIDOR_SEGMENTS)
        got = hull_clearance(view.geom, centers, 4)
        want = [
            min(
                float(view.geom.polyline_min_distance(centers[[w + i, w + j]]))
                for i, j in itertools.combinations(range(4), 2)
            )
            for w in range(len(centers) - 3)
        ]
        np.testing.assert_allclose(got, want, rtol=0.0, atol=1e-12)


def test_window_extremes_match_brute_force() -> None:
    from trajopt.timing import _window_extreme, _window_min

    rng = np.random.default_rng(5)
    for _ in range(30):
        P = int(rng.integers(1, 40))
        breaks = np.concatenate([[0.0], np.cumsum(rng.uniform(0.01, 0.2, P))])
        values = rng.uniform(0.1, 2.0, (2, P))
        mid = rng.uniform(-0.1, breaks[-1] + 0.1, 50)
        reach = float(rng.uniform(0.0, 0.5))
        got = _window_min(values, breaks, mid - reach, mid + reach)
        inside = (breaks[1:][None, :] >= (mid - reach)[:, None]) & (breaks[:-1][None, :] <= (mid + reach)[:, None])
        for k in range(2):
            want = np.min(np.where(inside, values[k][None, :], np.inf), axis=1)
            edge = np.all(~inside, axis=1)  # a window beyond the path: the nearest piece's value (clamped index)
            np.testing.assert_array_equal(got[k][~edge], want[~edge])
        np.testing.assert_array_equal(_window_min(values[0], breaks, mid - reach, mid + reach), got[0])
        grid = np.sort(rng.uniform(0.0, 1.0, int(rng.integers(2, 300))))
        f = rng.uniform(-1.0, 1.0, len(grid))
        r = float(rng.uniform(0.0, 0.3))
        for fn in (np.minimum, np.maximum):
            ends = fn(np.interp(grid - r, grid, f), np.interp(grid + r, grid, f))
            near = np.abs(grid[None, :] - grid[:, None]) <= r
            red = np.min if fn is np.minimum else np.max
            want = fn(red(np.where(near, f[None, :], np.inf if fn is np.minimum else -np.inf), axis=1), ends)
            np.testing.assert_array_equal(_window_extreme(grid, f, r, fn), want)


@pytest.mark.parametrize("track", TRACKS, ids=repr)
def test_corridor_radii_follow_their_definition(track) -> None:  # type: ignore[no-untyped-def]
    # the radius of a node: the minimum over the windows (spline spans) that contain it of max(E - sep, 0)
    rng = np.random.default_rng(8)
    for p in random_plans(track, 0.05, 12, 4):
        view = plan_view(p)
        centers = _samples(view, CORRIDOR_SEGMENTS)
        for pts in (centers, np.clip(centers + rng.normal(0.0, 0.02, centers.shape), view.lower, view.upper)):
            t = np.maximum(hull_clearance(view.geom, pts, 4) - SEP, 0.0)
            want = np.array([t[max(k - 3, 0) : k + 1].min() for k in range(len(pts))])
            np.testing.assert_array_equal(corridor_radii(view.geom, pts, SEP), want)


def test_filtered_profile_on_merged_path_ends_is_the_full_grids() -> None:
    # the grid points clipped to the path's ends (at rest) are merged: the same motion as on the full grid
    from trajopt.timing import (
        _constant_acceleration_phases,
        _eroded_flat_top_profile,
        filtered_scaling,
        piece_limits,
        spline_path,
    )

    rng = np.random.default_rng(11)
    merged_some = 0
    for i in range(40):
        nodes = np.cumsum(rng.normal(0.0, [1e-3, 0.01, 0.05, 0.2][i % 4], (int(rng.integers(3, 40)), 2)), axis=0)
        path = spline_path(nodes)
        pl = piece_limits(path, LIMITS, 1.0 - 1e-9)
        tau = float(np.max(LIMITS.a / LIMITS.j))
        reach = tau * float(np.max(pl.v))
        full = _eroded_flat_top_profile(path, pl, tau, reach, 4, ends_once=False)
        once = _eroded_flat_top_profile(path, pl, tau, reach, 4)
        assert np.sum(once[0] == 0.0) == 1 and np.sum(once[0] == path.length) == 1
        merged_some += len(once[0]) < len(full[0])
        a, b = _constant_acceleration_phases(full[0], full[1]), _constant_acceleration_phases(*once)
        for x, y in zip(a, b, strict=True):
            np.testing.assert_array_equal(x, y)
        # the same values on the shared grid points, and the same boundary speeds
        np.testing.assert_array_equal(np.unique(full[0]), np.unique(once[0]))
        np.testing.assert_array_equal(
            np.interp(path.breaks, full[0], np.sqrt(full[1])), filtered_scaling(path, LIMITS).boundary_speed
        )
    assert merged_some > 10
