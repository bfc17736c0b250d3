"""The gate's bound between rows is the exact chord minimum minus the deviation bound (no budget, no false zero)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from mpa import Circle, GraphTrack, Lollipop, MPAError, make_planner
from trajopt import Limits, TrajectoryGenerator
from trajopt.path.planview import plan_view
from trajopt.verify.gate import between_rows_separation

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tracks"


def _deviation_from_chords(a: np.ndarray, dt: float, lim: Limits) -> np.ndarray:
    """The gate's bound of how far both robots leave the chord (module docstring of trajopt.verify.gate)."""
    a_int = np.minimum(lim.a, np.maximum(np.abs(a[:-1]), np.abs(a[1:])) + lim.j * dt / 2)
    return np.sum(a_int, axis=1) * dt * dt / 8.0


def _dense_chord_min(view, s: np.ndarray, n: int = 201) -> np.ndarray:  # type: ignore[no-untyped-def]
    lam = np.linspace(0.0, 1.0, n)[None, :, None]
    pts = s[:-1, None, :] + lam * (s[1:] - s[:-1])[:, None, :]
    return view.geom.distance(pts.reshape(-1, 2)).reshape(len(s) - 1, n).min(axis=1)


@pytest.mark.parametrize("track", [Lollipop(1.0, 1.0), Lollipop(0.3, 1.2), Circle(1.0)], ids=repr)
def test_chord_minimum_is_exact_on_random_grids(track) -> None:  # type: ignore[no-untyped-def]
    # rows anywhere on the plan's routes, also robots crossing and robots following each other closely
    rng = np.random.default_rng(21)
    pl = make_planner(track, 0.02)
    lim, dt, checked = Limits(0.5, 1.0, 5.0), 0.01, 0
    while checked < 150:
        try:
            plan = pl.plan(rng.uniform(0, track.total_length, 2), rng.uniform(0, track.total_length, 2))
        except MPAError:
            continue
        view = plan_view(plan)
        lo, hi = view.lower, view.upper
        s = rng.uniform(lo, hi, (30, 2))
        if checked % 3 == 1:  # side by side: B a tiny gap behind A on A's route coordinate
            s[:, 1] = np.clip(s[:, 0] - rng.uniform(0, 1e-4), lo[1], hi[1])
        a = rng.normal(size=s.shape)
        chord = between_rows_separation(view.graph.geometry, view.routes, s, a, dt, lim)
        chord = chord + _deviation_from_chords(a, dt, lim)
        dense = _dense_chord_min(view, s)
        span = np.abs(np.diff(s, axis=0)).sum(axis=1)
        assert np.all(chord <= dense + 1e-12), (checked, np.max(chord - dense))
        assert np.all(chord >= dense - span / 400 - 1e-12), (checked, np.min(chord - dense + span / 400))
        checked += 1


def test_robots_following_closely_for_many_rows_pass() -> None:
    # a regression (graph soak, query 45 988): both robots leave the warehouse's charger loop one behind the other,
    # D = 0, the plan keeps the rate's margin 3.56e-5 m; the bisection's budget ran out over thousands of such rows
    # and the gate bounded the separation by 0 (exit 4). The exact chord minimum keeps it.
    track = GraphTrack.from_json(EXAMPLES / "warehouse.json")
    lim = Limits([0.7797173158180324, 0.8046114738462136], 4.455488960939758, 43.485908310015894)
    gen = TrajectoryGenerator(track, clearance=0.0, limits=lim, rate=250)
    start = (("charge_loop", 3.998694846670637), ("charge_loop", 13.591497815459888))
    goal = (("dock3", 2.2898908694465927), ("cross3_1", 4.2535102444251685))
    traj = gen.generate(start, goal)
    rep = traj.verification
    assert rep["ok"] and rep["min_separation_between"] >= 0.0
    assert rep["min_separation"] >= 3.5e-5  # the plan's margin is kept at the rows


def test_robots_meeting_between_rows_are_caught() -> None:
    # A passes through B between two rows on one edge: the chord minimum is 0 even though both rows are far apart
    track = Lollipop(1.0, 1.0)
    plan = make_planner(track, 0.0).plan((0.1, 0.6), (0.3, 0.8))
    view = plan_view(plan)
    s = np.array([[0.0, 0.3], [0.4, 0.1]]) + view.lower  # A's coordinate overtakes B's between the rows
    geo = view.graph.geometry
    (ea, oa), (eb, ob) = view.routes[0].positions(s[:, 0]), view.routes[1].positions(s[:, 1])
    assert np.all(geo.distance(ea, oa, eb, ob) > 0.05)
    chord = between_rows_separation(geo, view.routes, s, np.zeros((2, 2)), 0.01, Limits()) + _deviation_from_chords(
        np.zeros((2, 2)), 0.01, Limits()
    )
    assert chord[0] == pytest.approx(0.0, abs=1e-12)


def test_head_on_robots_are_caught_when_rounding_hides_the_meeting() -> None:
    # Two robots heading straight at each other on one edge have d0 + d1 == |ΔsA| + |ΔsB| exactly; rounding can make
    # the sum come out larger, which the Lipschitz exclusion alone would take as "they cannot meet".
    from mpa.geometry import DirectedRoute, GraphGeometry

    geo = GraphGeometry(2, [0], [1], [1.0])
    fwd = DirectedRoute.from_pieces([0], [1], [0.0], [1.0])
    bwd = DirectedRoute.from_pieces([0], [-1], [1.0], [1.0])
    rng = np.random.default_rng(3)
    tipped = 0
    for _ in range(2000):
        a0, b0 = rng.uniform(0.0, 0.3, 2)
        a1, b1 = rng.uniform(0.7, 1.0, 2)
        s = np.array([[a0, b0], [a1, b1]])  # A forward from a0, B backwards from 1 - b0: they pass
        (ea, oa), (eb, ob) = fwd.positions(s[:, 0]), bwd.positions(s[:, 1])
        d = geo.distance(ea, oa, eb, ob)
        if d[0] + d[1] > abs(a1 - a0) + abs(b1 - b0):
            tipped += 1
        z = np.zeros((2, 2))
        lim = Limits()
        chord = between_rows_separation(geo, (fwd, bwd), s, z, 0.01, lim) + _deviation_from_chords(z, 0.01, lim)
        if min(oa[0] - ob[0], oa[1] - ob[1]) < 0 < max(oa[0] - ob[0], oa[1] - ob[1]):
            assert chord[0] == 0.0, (s, d)
    assert tipped > 0  # the case the margin is for did occur


def test_class_failures_only_tells_the_class_from_other_failures() -> None:
    from trajopt.verify.gate import VerificationReport, class_failures_only

    def rep(*fails: str) -> VerificationReport:
        return VerificationReport(not fails, fails, 0.1, 0.1, {}, ())

    assert not class_failures_only(rep())
    assert class_failures_only(rep("homotopy class +S1a differs from the plan's (trivial)"))
    assert class_failures_only(rep("cannot compute the homotopy class: path jumps"))
    assert not class_failures_only(
        rep("homotopy class +S1a differs from the plan's (trivial)", "row 3: |v| of robot A")
    )
    assert not class_failures_only(rep("rows 4-5: separation between rows may drop to 0.01 < 0.05"))
