"""The reproducers of the stability audit: discrete choices that flipped on a hair inside a domain.

Each test is a query and its twin (the same domain and word, moved by about 1e-7 m) whose trajectories must agree
to within a small multiple of the move, in every exported quantity, and a property test over random queries of
the same kind.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mpa import Circle, Lollipop, MPAError
from trajopt import TrajectoryGenerator
from trajopt.analysis.stability import route_coordinate_gap, trajectory_gap

_GENS: dict[tuple[str, float], TrajectoryGenerator] = {}


def _gen(track: Lollipop | Circle, clearance: float) -> TrajectoryGenerator:
    key = (repr(track), clearance)
    if key not in _GENS:
        _GENS[key] = TrajectoryGenerator(track, clearance=clearance)
    return _GENS[key]


def test_route_direction_does_not_flip_with_a_vanishing_displacement() -> None:
    """Lollipop 1/1, clearance 0.15: robot A's goal 1e-7 m either side of its start (same domain and word).

    A leaves its start by about 0.45 m and comes back; its route's orientation follows that excursion, not the
    sign of the vanishing net displacement, so ``a_s`` moves by about 1e-7 m (orienting by the goal's sign moves
    it by 0.2 m).
    """
    gen = _gen(Lollipop(1.0, 1.0), 0.15)
    s = (1.052036977910553, 0.414122724838889)
    one = gen.generate(s, (1.0520370279105529, 1.6693713861170874))
    two = gen.generate(s, (1.052036927910553, 1.6693713861170874))
    assert (one.domain, one.word) == (two.domain, two.word)
    assert [r.direction for r in one.plan.routes] == [r.direction for r in two.plan.routes]
    ds, dv = route_coordinate_gap(one, two)
    gap, dt = trajectory_gap(one, two)
    assert ds <= 1e-5 and dv <= 1e-4 and gap <= 1e-5 and dt <= 1e-5, (ds, dv, gap, dt)
    n = min(len(one.t), len(two.t))  # the exported rows (CSV, ROS, PVT are made from them)
    for name in ("s", "v", "offsets"):
        x, y = getattr(one, name)[:n], getattr(two, name)[:n]
        assert float(np.max(np.abs(x - y))) <= 1e-4, name
    assert np.array_equal(one.edges[:n], two.edges[:n])


@pytest.mark.parametrize(
    ("track", "clearance"), [(Lollipop(1.0, 1.0), 0.15), (Lollipop(1.3, 0.9), 0.05), (Circle(1.0), 0.05)]
)
def test_exported_route_coordinates_continuous_as_the_net_displacement_vanishes(
    track: Lollipop | Circle, clearance: float
) -> None:
    """Seeded queries with robot A on the loop and its goal 1e-7 m either side of its start: where A makes an
    excursion (leaves its start by more than 1 cm and comes back), the exported ``*_s`` and ``*_v`` of both
    robots change by at most a small multiple of the move."""
    gen = _gen(track, clearance)
    rng = np.random.default_rng(21)
    stick = track.stick if isinstance(track, Lollipop) else 0.0
    delta, seen = 1e-7, 0
    for _ in range(400):
        a = stick + rng.uniform(0.02, 0.98) * track.loop
        b0, b1 = rng.uniform(0.0, track.total_length, 2)
        try:
            one = gen.generate((a, b0), (a + delta, b1))
            two = gen.generate((a, b0), (a - delta, b1))
        except MPAError:
            continue
        if (one.domain, one.word) != (two.domain, two.word) or float(np.max(np.abs(one.s[:, 0]))) < 1e-2:
            continue  # a domain boundary (a set of measure zero), or A does not leave its start
        ds, dv = route_coordinate_gap(one, two)
        gap, dt = trajectory_gap(one, two)
        case = f"{track} D={clearance}: ({a!r}, {b0!r}) -> ({a!r} ± {delta}, {b1!r})"
        assert gap <= 1e-4 and dt <= 1e-4, (case, gap, dt)
        assert ds <= 1e-4 and dv <= 1e-3, (case, ds, dv)
        seen += 1
        if seen >= 10:
            break
    assert seen >= 10, seen


@settings(max_examples=300, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(
    shape=st.sampled_from([(1.0, 1.0), (1.3, 0.9), (0.4, 1.7)]),
    clearance=st.sampled_from([0.05, 0.15]),
    q=st.lists(st.floats(0.0, 1.0), min_size=4, max_size=4),
    direction=st.lists(st.floats(-1.0, 1.0), min_size=4, max_size=4),
)
def test_plan_route_coordinates_of_twins(
    shape: tuple[float, float], clearance: float, q: list[float], direction: list[float]
) -> None:
    """300 plan-level δ-twins (δ = 1e-7) on the paper's lollipops: with the same domain and word, the plan's path in
    route coordinates (what the pipeline smooths and exports as ``*_s``) moves by at most 1e-4 m."""
    track = Lollipop(*shape)
    planner = _gen(track, clearance).planner
    x = np.asarray(q) * np.nextafter(track.total_length, 0.0)
    d = np.asarray(direction)
    if float(np.linalg.norm(d)) < 1e-3:
        return
    y = np.clip(x + 1e-7 * d / np.linalg.norm(d), 0.0, np.nextafter(track.total_length, 0.0))
    try:
        one, two = planner.plan(x[:2], x[2:]), planner.plan(y[:2], y[2:])
    except MPAError:
        return
    if (one.domain, tuple(one.word)) != (two.domain, tuple(two.word)):
        return  # a domain boundary (a set of measure zero)
    u = np.linspace(0.0, 1.0, 401)
    gap = float(np.max(np.abs(one.path_s(u) - two.path_s(u))))
    assert gap <= 1e-4, (track, clearance, x.tolist(), y.tolist(), gap)


def test_fast_hard_switch_reproducer() -> None:
    """Lollipop 1/1, clearance 0.05: the two sides of a switch point, same domain and word (the hard path against the
    hard path turned into the line, :mod:`trajopt.path.switch`; the hard path against the bare fast path differed by
    0.057 m and 2.398 s against 2.205 s). Gap <= 1e-4 m, motion time change <= 1e-3 s."""
    gen = _gen(Lollipop(1.0, 1.0), 0.05)
    one = gen.generate((1.934012862928031, 1.0823599379948243), (0.9203486504460147, 0.32972931268485045))
    two = gen.generate((1.9340128628729087, 1.0823599379523496), (0.9203486504535163, 0.32972931265931066))
    assert (one.domain, one.word) == (two.domain, two.word)
    assert (one.solver_stats["path"], two.solver_stats["path"]) == ("hard", "switch")
    gap, dt = trajectory_gap(one, two)
    assert gap <= 1e-4 and dt <= 1e-3, (one.solver_stats.get("path"), two.solver_stats.get("path"), gap, dt)


def test_graph_planner_tie_reproducer() -> None:
    """Warehouse, clearance 1.6, objective fastest: robot A's start moved by 1e-7 m changes robot B's route (two
    routes round a block, equally fast to 1e-14 s). Goal: the routes are locally constant in the query."""
    from pathlib import Path

    from mpa.graph_track import GraphTrack
    from mpa.planners.graph import plan_graph

    wh = GraphTrack.from_json(Path(__file__).resolve().parents[2] / "examples" / "tracks" / "warehouse.json")
    a, b, c, d = (
        ("cross4_9", 1.3585408961828644),
        ("aisle5_2", 4.357523406604219),
        ("aisle4_3", 4.152737269349741),
        ("gate_road", 34.70440272971876),
    )

    def routes(da: float) -> tuple[list[int], list[int]]:
        p = plan_graph(wh, (f"{a[0]}:{a[1] + da!r}", f"{b[0]}:{b[1]!r}"), (f"{c[0]}:{c[1]!r}", f"{d[0]}:{d[1]!r}"), 1.6)
        return p.route_a.edges.tolist(), p.route_b.edges.tolist()

    base = routes(0.0)
    assert routes(1e-7) == base and routes(-1e-7) == base
