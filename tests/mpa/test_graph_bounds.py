"""The passing bound (``mpa.planners.graph.bounds``): admissible against the exact optimum, exact on its segments.

Admissible: at the start and at random configurations on the start's side, the bound is never above the cost of
the search's optimal motion from there (the search without the bound, which is the planner's). Exact: every passing
segment's points keep the clearance and are at equal distance from the bound's vertex, and ``W_k`` is the least
goal cost along the segment (a fine sampling never goes below it, and comes within its step of it). The search with
the bound finds a motion of the same cost.
"""

from __future__ import annotations

import dataclasses
import itertools
import json
import math
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mpa.errors import NoMotionError
from mpa.freespace import FreeSpace, free_space
from mpa.graph_track import GraphTrack, Position
from mpa.planners.graph.base import TIE_BREAK
from mpa.planners.graph.bounds import PassingBound, fastest_cost, passing_bound
from mpa.planners.graph.mesh import _mesh
from mpa.planners.graph.search import AnyAngleSearch
from mpa.planners.search_common import SearchQuery
from tests.helpers.graph_helpers import (
    makespans_with,
    random_free_query,
    random_layout,
    random_position,
    same_makespans,
)

Query = tuple[Position, Position]
ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ("y_junction", "passing_loop", "two_sidings", "theta", "lollipop", "figure_eight", "rail_yard")


def _layout(name: str) -> GraphTrack:
    return GraphTrack.from_layout(json.loads((ROOT / "examples" / "tracks" / f"{name}.json").read_text()))


def _fastest(track: GraphTrack, fs: FreeSpace, s: Query, g: Query, speeds: tuple[float, float]) -> SearchQuery:
    return SearchQuery(track, fs, s, g, "fastest", speeds)


def _queries(
    track: GraphTrack, fs: FreeSpace, rng: np.random.Generator, n: int, swap_every: int = 2, vertex_p: float = 0.0
) -> Iterator[tuple[int, Query, Query]]:
    """``(k, start, goal)`` of ``n`` draws of a random free query (:func:`random_free_query`; a draw without one gives
    none); when ``k % swap_every == 0`` a swap: the goal is the start with the robots' positions exchanged."""
    for k in range(n):
        q = random_free_query(track, fs, rng, vertex_p=vertex_p)
        if q is not None:
            s, g = q
            yield k, s, ((s[1], s[0]) if k % swap_every == 0 else g)


def _optimum(query: SearchQuery) -> float:
    """The exact optimum's cost of the fastest ``query`` (inf when start and goal are in different components)."""
    fs, s, g = query.free_space, query.start, query.goal
    comp = fs.component_of(*s)
    if comp is None or comp != fs.component_of(*g):
        return math.inf
    if s == g:
        return 0.0
    segs = AnyAngleSearch(_mesh(fs), query).run()
    assert segs is not None
    return fastest_cost(segs, query.va, query.vb)


def _check_query(query: SearchQuery, rng: np.random.Generator, extra: int) -> int:
    """Check the bound at the start and at ``extra`` random free configurations; the number of checks made."""
    track, fs, s, g, (va, vb) = query.track, query.free_space, query.start, query.goal, query.speeds
    opt = _optimum(query)
    if not math.isfinite(opt):
        return 0
    pb = PassingBound(_mesh(fs), s, g, va, vb)
    assert pb.at_start <= opt * (1.0 + 1e-12) + 1e-12, ("start", s, g, fs.clearance, va, vb, pb.at_start, opt)
    checks = 1
    for _ in range(extra):
        c = (random_position(track, rng), random_position(track, rng))
        if not fs.is_free(*c):
            continue
        oc = _optimum(dataclasses.replace(query, start=c))
        if not math.isfinite(oc):
            continue
        hc = pb.at(*c)
        assert hc <= oc * (1.0 + 1e-12) + 1e-12, ("config", c, s, g, fs.clearance, va, vb, hc, oc)
        checks += 1
    return checks


@pytest.mark.parametrize("name", EXAMPLES)
def test_the_bound_is_admissible_on_the_example_layouts(name: str) -> None:
    """Seeded swaps and random queries at four clearances: the bound <= the optimum at the start and elsewhere."""
    track = _layout(name)
    rng = np.random.default_rng(2500 + EXAMPLES.index(name))
    med = float(np.median(track.lengths))
    checks = 0
    for frac in (0.05, 0.2, 0.5, 1.0):
        fs = free_space(track, frac * med)
        for k, s, g in _queries(track, fs, rng, 12):
            va, vb = (1.0, 1.0) if k % 3 else (float(rng.uniform(0.4, 1.0)), float(rng.uniform(0.4, 1.0)))
            checks += _check_query(_fastest(track, fs, s, g, (va, vb)), rng, extra=2)
    assert checks >= 40, checks


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(8))
def test_the_bound_is_admissible_on_thousands_of_random_queries(seed: int) -> None:
    """Random small multigraphs (loops, parallel edges), random clearances and speeds, about 300 checks a seed."""
    rng = np.random.default_rng(25000 + seed)
    checks = 0
    for _ in range(30):
        track = random_layout(rng)
        fs = free_space(track, float(rng.uniform(0.05, 0.8)))
        for k, s, g in _queries(track, fs, rng, 4, vertex_p=0.15):
            va, vb = (1.0, 1.0) if k == 0 else (float(rng.uniform(0.3, 2.0)), float(rng.uniform(0.3, 2.0)))
            checks += _check_query(_fastest(track, fs, s, g, (va, vb)), rng, extra=2)
    assert checks >= 150, checks


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 2**31 - 1), st.floats(0.02, 0.9), st.floats(0.3, 2.0), st.floats(0.3, 2.0), st.booleans())
def test_the_bound_is_admissible_property(seed: int, clearance: float, va: float, vb: float, swap: bool) -> None:
    """Hypothesis over random layouts, clearances, speeds and queries (swaps or not; positions on vertices too)."""
    rng = np.random.default_rng(seed)
    track = random_layout(rng)
    fs = free_space(track, clearance)
    q = random_free_query(track, fs, rng, vertex_p=0.2)
    if q is None:
        return
    s, g = q
    if swap:
        g = (s[1], s[0])
    _check_query(_fastest(track, fs, s, g, (va, vb)), rng, extra=1)


def test_the_bound_closes_the_gap_of_a_swap_at_a_siding() -> None:
    """The passing loop's swap: the robots' distances alone bound the time by the corridor; the passing bound is
    the optimum at the start (one robot waits in the siding), and the search with it costs the same."""
    track = _layout("passing_loop")
    rng = np.random.default_rng(7)
    fs = free_space(track, 0.5 * float(np.median(track.lengths)))
    found = 0
    for _, s, g in _queries(track, fs, rng, 40, swap_every=1):
        opt = _optimum(_fastest(track, fs, s, g, (1.0, 1.0)))
        if not math.isfinite(opt):
            continue
        geo = track.geometry
        base = max(geo.distance_scalar(*s[0], *g[0]), geo.distance_scalar(*s[1], *g[1]))
        if opt <= base * (1.0 + 1e-3):
            continue  # no waiting needed
        pb = passing_bound(_mesh(fs), s, g, 1.0, 1.0)
        assert pb is not None
        assert pb.at_start > base + 0.5 * (opt - base), (s, base, pb.at_start, opt)
        segs = AnyAngleSearch(_mesh(fs), _fastest(track, fs, s, g, (1.0, 1.0)), bound=pb).run()
        assert segs is not None
        assert fastest_cost(segs, 1.0, 1.0) == pytest.approx(opt, rel=1e-9), (s, opt)
        found += 1
    assert found >= 3, found


@pytest.mark.parametrize("exact", [True, False])
@pytest.mark.parametrize("name", ["y_junction", "theta", "rail_yard"])
def test_passing_segments_are_free_at_equal_distance_and_their_least_goal_cost_is_exact(
    name: str, exact: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Sampled along every segment: clearance kept, ``φ(p) = φ(q)``; ``W_k`` <= every sample and, exact
    (``W_EXACT``), within the sampling step's change of the least sample, relaxed, within the segment's length over
    the slower speed (each robot may stand anywhere on its stretch)."""
    from mpa.planners.graph import bounds as graph_bounds

    monkeypatch.setattr(graph_bounds, "W_EXACT", exact)
    track = _layout(name)
    geo = track.geometry
    rng = np.random.default_rng(31)
    fs = free_space(track, 0.3 * float(np.median(track.lengths)))
    checked = 0
    for _, s, g in _queries(track, fs, rng, 10, swap_every=1):
        pb = PassingBound(_mesh(fs), s, g, 1.0, 0.7)
        if pb.vertex is None:
            continue
        x = pb.vertex
        e, u0, u1, f, _, _, w, al, be = pb._segs
        n = 201
        for k in range(len(e)):
            u = np.linspace(u0[k], u1[k], n)
            v = al[k] * u + be[k]
            ek, fk = np.full(n, int(e[k])), np.full(n, int(f[k]))
            d = geo.distance(ek, u, fk, v)
            assert np.all(d >= fs._dmin - 1e-9), (name, k, float(d.min()), fs._dmin)
            vx = np.zeros(n, dtype=np.int64) + x
            # φ(p) = d(x, p) through the edge's ends
            phi_p = np.minimum(u + geo.dv[x, geo.tails[ek]], geo.lengths[ek] - u + geo.dv[x, geo.heads[ek]])
            phi_q = np.minimum(v + geo.dv[x, geo.tails[fk]], geo.lengths[fk] - v + geo.dv[x, geo.heads[fk]])
            assert np.allclose(phi_p, phi_q, atol=1e-9), (name, k)
            del vx
            ta = np.array([geo.distance_scalar(int(e[k]), float(ui), g[0][0], g[0][1]) for ui in u]) / 1.0
            tb = np.array([geo.distance_scalar(int(f[k]), float(vi), g[1][0], g[1][1]) for vi in v]) / 0.7
            sampled = np.maximum(ta, tb) + TIE_BREAK * (ta + tb)
            step = (u1[k] - u0[k]) / (n - 1)
            assert w[k] <= sampled.min() + 1e-9, (name, k, w[k], sampled.min())
            slack = 2.0 * step / 0.7 if exact else (u1[k] - u0[k]) / 0.7 * (1.0 + 2.0 * TIE_BREAK)
            assert w[k] >= sampled.min() - slack - 1e-9, (name, k, w[k], sampled.min(), exact)
            checked += 1
    assert checked >= 20, checked


@pytest.mark.parametrize("name", ["passing_loop", "two_sidings", "y_junction", "rail_yard"])
def test_the_planner_with_the_bound_from_the_first_pop_plans_as_fast(
    name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``plan_graph`` with the passing bound on every search (``PASSING_BOUND_AFTER = 1``) and without it (None):
    the same makespans on seeded swaps and random queries, and the plans keep the clearance."""
    from mpa.planners.graph import query as graph_query

    track = _layout(name)
    rng = np.random.default_rng(99 + len(name))
    med = float(np.median(track.lengths))
    compared = 0
    for frac in (0.2, 0.5, 1.0):
        fs = free_space(track, frac * med)
        for _, s, g in _queries(track, fs, rng, 8):
            spans = makespans_with(monkeypatch, graph_query, "PASSING_BOUND_AFTER", (None, 1), track, s, g, frac * med)
            compared += same_makespans(spans, (name, s, g, frac))
    assert compared >= 10, compared


@pytest.mark.parametrize("name", ["y_junction", "passing_loop", "two_sidings", "rail_yard", "theta"])
def test_restricted_segments_leave_the_bound_unchanged_below_the_limit(name: str) -> None:
    """:meth:`PassingBound.restrict`: at random configurations ``p`` the bound with the kept segments is never below
    the bound with all of them, and equal to it wherever the cost of the robots' distances from the start to ``p``
    plus the bound there is at most the limit (the lemma that makes the limited search exact)."""
    from mpa.planners.search_common import cost_function

    track = _layout(name)
    geo = track.geometry
    rng = np.random.default_rng(7 + len(name))
    med = float(np.median(track.lengths))
    checked = equal = 0
    for frac in (0.2, 0.5):
        fs = free_space(track, frac * med)
        for _, s, g in _queries(track, fs, rng, 10, swap_every=1):
            va, vb = 1.0, float(rng.uniform(0.5, 1.5))
            cost = cost_function("fastest", va, vb)
            full = PassingBound(_mesh(fs), s, g, va, vb)
            if full.vertex is None:
                continue
            part = PassingBound(_mesh(fs), s, g, va, vb)
            limit = full.at_start * float(rng.uniform(1.0, 1.3))
            part.restrict(limit)
            assert part.n_segments <= full.n_segments
            for _ in range(30):
                c = (random_position(track, rng), random_position(track, rng))
                if not fs.is_free(*c):
                    continue
                b_full, b_part = full.at(*c), part.at(*c)
                assert b_part >= b_full * (1.0 - 1e-12), (name, s, g, c, b_full, b_part)
                reach = cost(geo.distance_scalar(*s[0], *c[0]), geo.distance_scalar(*s[1], *c[1]))
                if reach + b_full <= limit * (1.0 - 1e-9):
                    assert b_part == pytest.approx(b_full, rel=1e-12, abs=1e-12), (name, s, g, c, limit)
                    equal += 1
                checked += 1
    assert checked >= 100 and equal >= 20, (checked, equal)


@pytest.mark.parametrize("name", ["passing_loop", "two_sidings", "y_junction", "rail_yard", "lollipop"])
def test_the_limited_searches_plan_the_makespans_of_the_full_bound(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """``plan_graph`` with the bound from the first pop, its segments first restricted to tiny, medium and no slack
    above the bound at the start (``LIMIT_SLACKS``; a search that stops at its limit is done again with the next),
    against every segment at once: the same makespans, bit for bit up to rounding, on seeded swaps."""
    from mpa.planners.graph import query as graph_query

    monkeypatch.setattr(graph_query, "PASSING_BOUND_AFTER", 1)
    track = _layout(name)
    rng = np.random.default_rng(5 + len(name))
    med = float(np.median(track.lengths))
    compared = stopped = 0
    calls: list[float | None] = []
    real_run = AnyAngleSearch.run

    def run(self: AnyAngleSearch, budget: int | None = None, limit: float | None = None) -> object:
        out = real_run(self, budget, limit)
        if limit is not None:
            calls.append(None if out is None else limit)
        return out

    monkeypatch.setattr(AnyAngleSearch, "run", run)
    for frac in (0.2, 0.6):
        fs = free_space(track, frac * med)
        for _, s, g in _queries(track, fs, rng, 10, swap_every=1):
            calls.clear()
            spans = makespans_with(
                monkeypatch, graph_query, "LIMIT_SLACKS", ((), (1e-6, 0.01, 0.1)), track, s, g, frac * med
            )
            stopped += sum(1 for c in calls if c is None)
            compared += same_makespans(spans, (name, s, g, frac))
    assert compared >= 8, compared
    assert stopped >= 1, "no search stopped at its limit: the fallback was not exercised"


def test_the_limits_rise_and_admit_a_step_aside_and_a_wait() -> None:
    """``_limits``: rising, None last; the first admits ``LIMIT_STEP_ASIDE`` clearances of travel tie-break above
    ``(1 + LIMIT_SLACKS[0])`` times the bound, the second at least ``LIMIT_WAIT`` clearances of time (the slower
    robot's), and a slack whose limit would not rise is left out."""
    from mpa.planners.graph import query as graph_query
    from mpa.planners.graph.query import LIMIT_SLACKS, LIMIT_STEP_ASIDE, LIMIT_WAIT, _limits

    rng = np.random.default_rng(17)
    for _ in range(2000):
        at = float(10.0 ** rng.uniform(-3, 3))
        d = float(rng.choice([0.0, 10.0 ** rng.uniform(-3, 1)]))
        va, vb = (float(10.0 ** rng.uniform(-1, 1)) for _ in range(2))
        out = _limits(at, d, va, vb)
        assert out[-1] is None
        ls = [x for x in out[:-1] if x is not None]
        assert len(ls) == len(out) - 1 and all(b > a for a, b in itertools.pairwise(ls)), (at, d, va, vb, out)
        per_d = d / min(va, vb)
        assert ls[0] == at * (1.0 + LIMIT_SLACKS[0]) + LIMIT_STEP_ASIDE * TIE_BREAK * per_d, (at, d, out)
        wait = max(at * (1.0 + LIMIT_SLACKS[1]), at + LIMIT_WAIT * per_d)
        assert (wait in ls) == (wait > ls[0]), (at, d, out)
        assert all(x in ls for x in (at * (1.0 + s) for s in LIMIT_SLACKS[2:]) if x > max(ls[0], wait)), (at, d, out)
    assert len(_limits(20.0, 3.0, 1.0, 1.0)) == len(LIMIT_SLACKS)  # the hotel's case: D / v above the second slack
    assert graph_query.LIMIT_STEP_ASIDE > 2.15  # the largest step aside measured (docs/performance.md)


@pytest.mark.parametrize("name", ["y_junction", "passing_loop", "two_sidings", "rail_yard", "warehouse"])
def test_the_step_aside_and_wait_limits_leave_every_plan_unchanged(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """``plan_graph`` with the first two limits raised by a step aside and a wait (``LIMIT_STEP_ASIDE``,
    ``LIMIT_WAIT``) against the slacks alone, on seeded swaps and queries at two clearances and uneven speeds: the
    same plan (routes and corners, bit for bit: below a limit the search is the one with every segment, node for
    node), and fewer searches stopped at a limit."""
    from mpa.planners.graph import query as graph_query
    from mpa.planners.graph.query import plan_graph

    monkeypatch.setattr(graph_query, "PASSING_BOUND_AFTER", 1)
    track = _layout(name)
    rng = np.random.default_rng(29 + len(name))
    med = float(np.median(track.lengths))
    stops = {0: 0, 1: 0}
    arm = [0]
    real_run = AnyAngleSearch.run

    def run(self: AnyAngleSearch, budget: int | None = None, limit: float | None = None) -> object:
        out = real_run(self, budget, limit)
        if limit is not None and out is None:
            stops[arm[0]] += 1
        return out

    monkeypatch.setattr(AnyAngleSearch, "run", run)
    arms = ((0.0, 0.0), (graph_query.LIMIT_STEP_ASIDE, graph_query.LIMIT_WAIT))  # before any patch below
    assert min(arms[1]) > 0.0
    compared = 0
    for frac in (0.2, 0.6):
        fs = free_space(track, frac * med)
        for _, s, g in _queries(track, fs, rng, 12, swap_every=2):
            speeds = (1.0, float(rng.choice([1.0, rng.uniform(0.5, 2.0)])))
            plans = []
            for arm[0], (step, wait) in enumerate(arms):
                monkeypatch.setattr(graph_query, "LIMIT_STEP_ASIDE", step)
                monkeypatch.setattr(graph_query, "LIMIT_WAIT", wait)
                try:
                    p = plan_graph(track, s, g, frac * med, speeds=speeds)
                except NoMotionError:
                    plans.append(None)
                    continue
                plans.append((p.makespan, tuple(p.route_a.edges), tuple(p.route_b.edges), p.corner_offsets.tobytes()))
            assert plans[0] == plans[1], (name, s, g, frac, speeds)
            compared += plans[0] is not None
    assert compared >= 12, compared
    assert stops[1] < stops[0], stops  # measured: 12 -> 6, 15 -> 6, 32 -> 12, 13 -> 4, 10 -> 4


@pytest.mark.parametrize("name", ["y_junction", "passing_loop", "two_sidings", "rail_yard", "theta", "warehouse"])
def test_the_segments_within_the_reach_are_those_of_every_cell_that_a_limit_keeps(
    name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The passing geometry built per query within the bound's reach (``REACH_EDGES``, as on layouts of more than
    300 edges) against every segment: the same vertex and bound at the start, and after :meth:`restrict` to limits
    from the bound at the start to 1.6 times it and to no limit (beyond the first reach: the reach extended), the same
    segments as the full bound keeps, array for array up to their order."""
    from mpa.planners.graph import bounds as graph_bounds

    track = _layout(name)
    rng = np.random.default_rng(11 + len(name))
    med = float(np.median(track.lengths))
    compared = extended = fewer = 0
    for frac in (0.2, 0.6):
        fs = free_space(track, frac * med)
        for _, s, g in _queries(track, fs, rng, 12, swap_every=2):
            va, vb = 1.0, float(rng.uniform(0.5, 1.5))
            monkeypatch.setattr(graph_bounds, "REACH_EDGES", 10**9)
            full = PassingBound(_mesh(fs), s, g, va, vb)
            monkeypatch.setattr(graph_bounds, "REACH_EDGES", 0)
            part = PassingBound(_mesh(fs), s, g, va, vb)
            assert part.vertex == full.vertex, (name, s, g)
            if full.vertex is None:
                continue
            assert part.at_start == full.at_start, (name, s, g)
            fewer += len(part._all_segs[0]) < len(full._all_segs[0])
            for factor in (1.0, 1.01, 1.3, 1.6, math.inf):
                limit = full.at_start * factor
                reach = part._reach
                full.restrict(limit)
                part.restrict(limit)
                extended += part._reach > reach
                rows_full = sorted(zip(*(a.tolist() for a in full._segs[:9])))
                rows_part = sorted(zip(*(a.tolist() for a in part._segs[:9])))
                assert rows_part == rows_full, (name, s, g, factor)
                compared += 1
    assert compared >= 40 and extended >= 8, (compared, extended)
    if name == "warehouse":  # a layout large enough that the reach leaves cells out
        assert fewer >= 4, fewer


def test_the_reach_leaves_every_plan_unchanged(monkeypatch: pytest.MonkeyPatch) -> None:
    """``plan_graph`` with the passing geometry built within the reach (``REACH_EDGES = 0``) and with every segment,
    the bound from the first pop: the same makespans, routes and waypoints on seeded swaps and crossings."""
    from mpa.planners.graph import bounds as graph_bounds
    from mpa.planners.graph import query as graph_query
    from mpa.planners.graph.query import plan_graph

    monkeypatch.setattr(graph_query, "PASSING_BOUND_AFTER", 1)
    compared = 0
    for name in ("y_junction", "rail_yard", "two_sidings"):
        track = _layout(name)
        rng = np.random.default_rng(3 + len(name))
        med = float(np.median(track.lengths))
        fs = free_space(track, 0.4 * med)
        for _, s, g in _queries(track, fs, rng, 10, swap_every=2):
            out = []
            for edges in (10**9, 0):
                monkeypatch.setattr(graph_bounds, "REACH_EDGES", edges)
                try:
                    p = plan_graph(track, s, g, 0.4 * med, speeds=(1.0, 0.8))
                except NoMotionError:
                    out.append(None)
                    continue
                out.append((p.makespan, repr(p.route_a), repr(p.route_b), np.asarray(p.waypoints).tolist()))
            assert out[0] == out[1], (name, s, g)
            compared += out[0] is not None
    assert compared >= 15, compared


@pytest.mark.parametrize("name", ["rail_yard", "theta", "two_sidings", "warehouse"])
def test_the_cells_left_out_by_their_distance_ranges_hold_no_passing_segment(name: str) -> None:
    """The segments built from the cells whose edges' ranges of ``φ`` meet are those built from every cell, array
    for array, for every vertex."""
    from mpa.planners.graph import passing as graph_passing

    track = _layout(name)
    for frac in (0.2, 0.7):
        mesh = _mesh(free_space(track, frac * float(np.median(track.lengths))))
        for x in range(track.geometry.n_vertices):
            fast = graph_passing._build_passing_geometry(mesh, x)
            every = graph_passing._build_passing_geometry(mesh, x, every_cell=True)
            assert (fast is None) == (every is None), (name, x)
            if fast is not None and every is not None:
                for u, v in zip(fast, every, strict=True):
                    assert np.array_equal(u, v), (name, frac, x)


def test_the_passing_geometry_is_kept_per_vertex_within_its_budget(monkeypatch: pytest.MonkeyPatch) -> None:
    """The segments' geometry is built once per vertex and free space and reused (the same arrays), the cache holds
    at most ``GEOMETRY_CACHE`` segments (the oldest vertex dropped), and a bound built from the cache equals one
    built afresh."""
    from mpa.planners.graph import passing as graph_passing

    track = _layout("rail_yard")
    fs = free_space(track, 0.3 * float(np.median(track.lengths)))
    mesh = _mesh(fs)
    xs = [x for x in range(track.geometry.n_vertices) if graph_passing.passing_geometry(mesh, x) is not None]
    assert len(xs) >= 3
    a = graph_passing.passing_geometry(mesh, xs[0])
    assert graph_passing.passing_geometry(mesh, xs[0]) is a
    sizes = {x: len(graph_passing._build_passing_geometry(mesh, x)[0]) for x in xs}
    for x in xs:
        fresh = graph_passing._build_passing_geometry(mesh, x)
        cached = graph_passing.passing_geometry(mesh, x)
        for u, v in zip(fresh, cached, strict=True):
            assert np.array_equal(u, v)
    budget = sizes[xs[0]] + sizes[xs[1]]
    monkeypatch.setattr(graph_passing, "GEOMETRY_CACHE", budget)
    mesh._passing_geometry = {}  # type: ignore[attr-defined]
    for x in xs:
        graph_passing.passing_geometry(mesh, x)
        held = sum(len(v[0]) for v in mesh._passing_geometry.values() if v is not None)  # type: ignore[attr-defined]
        assert held <= budget, (x, held, budget)
    assert (xs[-1], graph_passing.PIECE_LENGTH) in mesh._passing_geometry  # type: ignore[attr-defined]
    assert (xs[0], graph_passing.PIECE_LENGTH) not in mesh._passing_geometry  # type: ignore[attr-defined]


@pytest.mark.parametrize("name", ["y_junction", "passing_loop", "rail_yard", "two_sidings"])
def test_the_bound_is_used_where_it_gains_only_the_travel_tie_break(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """Plateaus: where the robots' own motions already take the least time but one must step aside, the passing
    bound at the start exceeds the robots' own bound (with the travel tie-break) by less than 1e-4 of it and more
    than ``BOUND_GAIN``; ``plan_graph`` then searches with it, and plans the makespan of the search without it."""
    from mpa.errors import NoMotionError
    from mpa.planners.graph import query as graph_query
    from mpa.planners.graph.query import plan_graph

    track = _layout(name)
    geo = track.geometry
    rng = np.random.default_rng(3 + len(name))
    med = float(np.median(track.lengths))
    used: list[bool] = []
    real_init = AnyAngleSearch.__init__

    def init(self: AnyAngleSearch, mesh: object, query: SearchQuery, bound: PassingBound | None = None) -> None:
        used.append(bound is not None)
        real_init(self, mesh, query, bound=bound)  # type: ignore[arg-type]

    monkeypatch.setattr(AnyAngleSearch, "__init__", init)
    plateaus = 0
    for frac in (0.1, 0.3, 0.6):
        fs = free_space(track, frac * med)
        for _, s, g in _queries(track, fs, rng, 40, swap_every=1000):
            va, vb = 1.0, float(rng.uniform(0.4, 1.0))
            pb = PassingBound(_mesh(fs), s, g, va, vb)
            if pb.vertex is None:
                continue
            ta, tb = geo.distance_scalar(*s[0], *g[0]) / va, geo.distance_scalar(*s[1], *g[1]) / vb
            own = max(ta, tb) + TIE_BREAK * (ta + tb)
            if not own * (1.0 + 1e-8) < pb.at_start < own * (1.0 + 1e-4):
                continue
            spans = []
            searched = False
            for after in (None, 1):
                monkeypatch.setattr(graph_query, "PASSING_BOUND_AFTER", after)
                used.clear()
                try:
                    p = plan_graph(track, s, g, frac * med, speeds=(va, vb))
                except NoMotionError:
                    break
                spans.append(p.makespan)
                if after == 1:  # searched: stopped after one pop, then again with the bound (not resumed)
                    searched = bool(used)
                    if searched:
                        assert len(used) >= 2 and not used[0] and all(used[1:]), (name, s, g, used)
            if len(spans) == 2 and searched:
                assert spans[1] == pytest.approx(spans[0], rel=1e-9, abs=1e-12), (name, s, g, spans)
                plateaus += 1
    print(name, "plateaus", plateaus)
    assert plateaus >= 1, name


@pytest.mark.parametrize("name", ["passing_loop", "rail_yard", "two_sidings", "theta"])
def test_a_floor_leaves_every_useful_bound_as_it_was(name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """``passing_bound(..., floor=f)`` stops the least at the start once it is known not to exceed ``f``: it answers
    None exactly when the bound without a floor is at most ``f``, and otherwise the same bound (its value at the
    start, its vertex and segments), for floors below, at and above the bound and at the robots' own bound; with a
    floor at the bound it evaluates fewer segments exactly than without one."""
    from mpa.planners.graph import bounds as graph_bounds

    rows = [0]
    least = graph_bounds._least

    def counted(u0: Any, *args: Any) -> Any:
        rows[0] += len(u0)
        return least(u0, *args)

    monkeypatch.setattr(graph_bounds, "_least", counted)
    exact_rows = {"none": 0, "floor": 0}
    track = _layout(name)
    geo = track.geometry
    rng = np.random.default_rng(17 + len(name))
    med = float(np.median(track.lengths))
    checked = dropped = kept = 0
    for frac in (0.1, 0.3, 0.6):
        fs = free_space(track, frac * med)
        mesh = _mesh(fs)
        for _, s, g in _queries(track, fs, rng, 30, swap_every=3):
            va, vb = 1.0, float(rng.uniform(0.4, 1.0))
            rows[0] = 0
            whole = passing_bound(mesh, s, g, va, vb)
            exact_rows["none"] += rows[0]
            if whole is None:
                assert passing_bound(mesh, s, g, va, vb, floor=0.0) is None
                continue
            ta, tb = geo.distance_scalar(*s[0], *g[0]) / va, geo.distance_scalar(*s[1], *g[1]) / vb
            own = max(ta, tb) + TIE_BREAK * (ta + tb)
            h = whole.at_start
            rows[0] = 0
            assert passing_bound(mesh, s, g, va, vb, floor=h) is None
            exact_rows["floor"] += rows[0]
            for floor in (own, own * (1.0 + 1e-9), h, h * (1.0 - 1e-12), h * (1.0 + 1e-12), 0.5 * h, 2.0 * h):
                got = passing_bound(mesh, s, g, va, vb, floor=floor)
                if h <= floor:
                    assert got is None, (name, s, g, floor, h)
                    dropped += 1
                else:
                    assert got is not None, (name, s, g, floor, h)
                    assert (got.at_start, got.vertex, got.n_segments) == (h, whole.vertex, whole.n_segments)
                    for a, b in zip(got._segs, whole._segs):
                        assert np.array_equal(a, b)
                    kept += 1
                checked += 1
    print(name, checked, dropped, kept, exact_rows)
    assert dropped >= 20 and kept >= 20, (checked, dropped, kept)
    assert exact_rows["floor"] < exact_rows["none"], exact_rows
