"""The rows' positions from one search of the route breaks (:meth:`PlanView.graph_rows`) are the numbers of the
three separate calls (positions, directions, track coordinates), also at the breaks and moving backwards; a
trajectory keeps them as the gate checked them."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mpa.errors import MPAError
from tests.helpers.graph_helpers import random_layout, random_position
from trajopt import Limits, TrajectoryGenerator
from trajopt.path.planview import REST_SPEED, plan_view


def _plan_and_trajectory(seed: int):  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(seed)
    for _ in range(40):
        track = random_layout(rng, int(rng.integers(3, 9)))
        gen = TrajectoryGenerator(track, clearance=0.2, limits=Limits(1.0, 1.0, 4.0), rate=50.0)
        try:
            traj = gen.generate(
                (random_position(track, rng), random_position(track, rng)),
                (random_position(track, rng), random_position(track, rng)),
            )
        except MPAError:
            continue
        if np.ptp(traj.s[:, 0]) > 0 or np.ptp(traj.s[:, 1]) > 0:
            return traj
    pytest.skip("no motion on 40 random layouts")


def _separately(view, s, v):  # type: ignore[no-untyped-def]
    e, o = view.positions(s, v)
    return e, o, view.directions(s, v), view.track_coordinates(s)


def _reference(view, s, v):  # type: ignore[no-untyped-def]
    """The rows' positions written out from the definition (both searches on every row)."""
    out = [np.empty(s.shape, dtype=np.int64), np.empty(s.shape), np.empty(s.shape, dtype=np.int64), np.empty(s.shape)]
    for r, route in enumerate(view.routes):
        br, last = route.breaks, len(route.edges) - 1
        x = np.clip(s[:, r], br[0], br[-1])
        right = np.searchsorted(br, x, side="right") - 1
        left = np.searchsorted(br, x, side="left") - 1
        for k, i in enumerate((np.where(v[:, r] < -REST_SPEED, left, right), right)):
            i = np.clip(i, 0, last)
            off = np.clip(route.entry[i] + route.dirs[i] * (x - br[i]), 0.0, view.graph.lengths[route.edges[i]])
            if k == 0:
                out[0][:, r], out[1][:, r] = route.edges[i], off
                sign = np.where(v[:, r] > REST_SPEED, 1, np.where(v[:, r] < -REST_SPEED, -1, 0))
                out[2][:, r] = sign * route.dirs[i]
            else:
                out[3][:, r] = off
    return tuple(out)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 10_000), extra=st.integers(0, 2**31 - 1))
def test_graph_rows_equal_the_separate_calls_at_breaks_and_backwards(seed: int, extra: int) -> None:
    traj = _plan_and_trajectory(seed)
    view = plan_view(traj.plan)
    rng = np.random.default_rng(extra)
    # the motion's own rows, then route coordinates on every break (and beyond the ends) with speeds of each sign
    breaks = [np.concatenate([r.breaks, [r.breaks[0] - 1.0, r.breaks[-1] + 1.0]]) for r in view.routes]
    n = 64
    s = np.stack([rng.choice(b, n) for b in breaks], axis=1)
    v = rng.choice([-1.0, -2 * REST_SPEED, -0.5 * REST_SPEED, 0.0, 0.5 * REST_SPEED, 1.0], size=(n, 2))
    for rows_s, rows_v in ((traj.s, traj.v), (s, v), (s, -v)):
        got = view.graph_rows(rows_s, rows_v)
        for want in (_separately(view, rows_s, rows_v), _reference(view, rows_s, rows_v)):
            for g, w in zip(got, want):
                assert g.dtype == w.dtype and g.shape == w.shape
                np.testing.assert_array_equal(g, w)


def test_a_layout_trajectory_keeps_the_positions_the_gate_checked() -> None:
    traj = _plan_and_trajectory(3)
    view = plan_view(traj.plan)
    e, o = view.positions(traj.s, traj.v)
    np.testing.assert_array_equal(traj.edges, e)
    np.testing.assert_array_equal(traj.offsets, o)
    np.testing.assert_array_equal(traj.directions, view.directions(traj.s, traj.v))
    np.testing.assert_array_equal(traj.track, view.track_coordinates(traj.s))
    # the same report when the gate searches the routes itself
    again = view.verify(
        traj.t,
        traj.s,
        traj.v,
        traj.a,
        traj.j,
        limits=traj.limits,
        clearance=traj.clearance,
        rate=traj.rate,
        limits_used=traj.limits_used,
    )
    assert again.ok and again.to_dict() == traj.verification
