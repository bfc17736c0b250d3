"""The graph search's fast paths equal its generic form, bit for bit.

- :meth:`AnyAngleSearch.lower_bound` (goal distances and the objective's cost computed inline) against the
  composition of :class:`GoalDistance` and :func:`cost_function`, on random points (hypothesis);
- the search (unrolled cone, face ends named per side, costs inline, face entries queued inline) against
  :class:`tests.helpers.search_reference.ReferenceSearch` on seeded random layouts and queries, both objectives,
  unequal speeds, with and without the passing bound: the same nodes in the same order, the same costs and the same
  segments (floats compared by ``repr``, so ``-0.0`` differs from ``0.0``), and the queue's keys without its grid
  (the face entries' bounds computed inline against :meth:`AnyAngleSearch.face_lower_bound`);
- :meth:`_Mesh.side_ends` against :meth:`_Mesh.sides` and :meth:`_Mesh.point_key`;
- the cyclic garbage collector paused during a search is left as it was found.
"""

from __future__ import annotations

import dataclasses
import gc
import math
import types

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mpa.freespace import free_space
from mpa.planners.graph import search as search_module
from mpa.planners.graph.bounds import passing_bound
from mpa.planners.graph.mesh import _mesh
from mpa.planners.graph.search import AnyAngleSearch
from mpa.planners.search_common import SearchQuery, cost_function
from tests.helpers.graph_helpers import random_free_query, random_layout, random_position
from tests.helpers.search_reference import EagerBoundSearch, ReferenceSearch

SPEEDS = ((1.0, 1.0), (1.0, 0.55), (0.8, 1.3), (2.5, 0.4))


def _search(seed: int, objective: str, speeds: tuple[float, float]) -> SearchQuery | None:
    rng = np.random.default_rng(seed)
    track = random_layout(rng)
    fs = free_space(track, float(rng.uniform(0.05, 0.6)))
    q = random_free_query(track, fs, rng, vertex_p=0.2)
    if q is None:
        return None
    s, g = q
    if seed % 3 == 0:
        g = (s[1], s[0])  # a swap
    comp = fs.component_of(*s)
    if comp is None or comp != fs.component_of(*g):
        return None
    return SearchQuery(track, fs, s, g, objective, speeds)


def _seeded_query(seed: int, base: int) -> SearchQuery:
    """The query of ``_search(base + seed)``, "shortest" for every fourth seed, the speeds in turn; skips the test
    when the draw has none."""
    query = _search(base + seed, "shortest" if seed % 4 == 1 else "fastest", SPEEDS[seed % len(SPEEDS)])
    if query is None:
        pytest.skip("no query with start and goal in one component")
    return query


def _nodes(search: AnyAngleSearch) -> list[str]:
    return [f"{type(nd).__name__}{dataclasses.astuple(nd)!r}" for nd in search.nodes]


@pytest.mark.parametrize("seed", range(40))
def test_the_search_makes_the_reference_nodes_in_the_same_order(seed: int) -> None:
    query = _seeded_query(seed, 1000)
    objective, speeds = query.objective, query.speeds
    mesh = _mesh(query.free_space)
    bounds: list[object] = [None]
    if objective == "fastest":
        pb = passing_bound(mesh, query.start, query.goal, *speeds)
        if pb is not None:
            bounds.append(pb)
    for bound in bounds:
        fast = AnyAngleSearch(mesh, query, bound=bound)  # type: ignore[arg-type]
        ref = ReferenceSearch(mesh, query, bound=bound)  # type: ignore[arg-type]
        segs_fast, segs_ref = fast.run(), ref.run()
        where = (seed, objective, speeds, query.start, query.goal, bound is not None)
        assert len(fast.nodes) == len(ref.nodes), where
        got, want = _nodes(fast), _nodes(ref)
        first = next((i for i, (x, y) in enumerate(zip(got, want, strict=True)) if x != y), None)
        assert first is None, (where, first, got[first] if first is not None else None, want[first or 0])
        assert repr(fast.best) == repr(ref.best), where
        assert repr(segs_fast) == repr(segs_ref), where


@pytest.mark.parametrize("seed", range(40))
def test_the_passing_bound_taken_in_when_a_node_is_taken_expands_the_eager_nodes(seed: int) -> None:
    """The passing bound of a queued node taken into its key when the node is first taken from the queue (the search)
    against taken in when it is queued (:class:`EagerBoundSearch`): the same nodes in the same order, the same costs,
    the same path, and the queue's minimum taken in the same order (so a search stopped at a limit stops at the same
    node)."""
    found = None
    for k in range(50):  # the first seeded draw with a query that a vertex separates
        query = _search(7000 + 50 * seed + k, "fastest", SPEEDS[seed % len(SPEEDS)])
        if query is not None:
            mesh = _mesh(query.free_space)
            pb = passing_bound(mesh, query.start, query.goal, *query.speeds)
            if pb is not None:
                found = query, mesh, pb
                break
    assert found is not None, seed
    query, mesh, pb = found
    lazy, eager = AnyAngleSearch(mesh, query, bound=pb), EagerBoundSearch(mesh, query, bound=pb)
    segs_lazy, segs_eager = lazy.run(), eager.run()
    where = (seed, query.speeds, query.start, query.goal)
    assert _nodes(lazy) == _nodes(eager), where
    assert repr(lazy.best) == repr(eager.best), where
    assert repr(segs_lazy) == repr(segs_eager), where
    assert not eager.pending and len(lazy.nodes) > 0, where
    for limit in (pb.at_start * (1.0 + 1e-6), pb.at_start * 1.01):
        a, b = AnyAngleSearch(mesh, query, bound=pb), EagerBoundSearch(mesh, query, bound=pb)
        ra, rb = a.run(limit=limit), b.run(limit=limit)
        assert (ra is None) == (rb is None) and _nodes(a) == _nodes(b), (where, limit)


@pytest.mark.parametrize("seed", range(24))
def test_the_queue_keys_are_the_reference_keys_bit_for_bit(seed: int, monkeypatch: pytest.MonkeyPatch) -> None:
    """The queue's order without its grid (``math.floor`` the identity in the search's module): every key is the
    bound itself, so any difference in the last bit of an inline bound shows in the queue."""
    monkeypatch.setattr(search_module, "math", types.SimpleNamespace(**{**vars(math), "floor": lambda x: x}))
    query = _seeded_query(seed, 4000)
    mesh = _mesh(query.free_space)
    fast, ref = AnyAngleSearch(mesh, query), ReferenceSearch(mesh, query)
    fast.run(40)  # stopped with a full queue
    ref.run(40)
    where = (seed, query.objective, query.speeds, query.start, query.goal)
    assert len(fast.heap) > 0 and all(isinstance(k[0], float) for k in fast.heap), where
    assert repr(sorted(fast.heap)) == repr(sorted(ref.heap)), where
    assert _nodes(fast) == _nodes(ref), where


@pytest.mark.parametrize("seed", range(6))
def test_a_budgeted_search_resumes_to_the_reference_nodes(seed: int) -> None:
    query = _search(2000 + seed, "fastest", (1.0, 0.7))
    if query is None:
        pytest.skip("no query with start and goal in one component")
    mesh = _mesh(query.free_space)
    fast = AnyAngleSearch(mesh, query)
    while (segs := fast.run(3)) is None:
        pass
    ref = ReferenceSearch(mesh, query)
    assert repr(segs) == repr(ref.run()), (seed, query.start, query.goal)
    assert _nodes(fast) == _nodes(ref), (seed, query.start, query.goal)


def _random_search(seed: int, objective: str, speeds: tuple[float, float]) -> AnyAngleSearch:
    rng = np.random.default_rng(seed)
    track = random_layout(rng)
    fs = free_space(track, 0.1)
    s = (random_position(track, rng), random_position(track, rng))
    g = (random_position(track, rng), random_position(track, rng))
    return AnyAngleSearch(_mesh(fs), SearchQuery(track, fs, s, g, objective, speeds))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    seed=st.integers(0, 10_000),
    objective=st.sampled_from(["fastest", "shortest"]),
    va=st.floats(1e-3, 1e3),
    vb=st.floats(1e-3, 1e3),
    u=st.lists(st.floats(-0.2, 1.2), min_size=6, max_size=6),
)
def test_the_inline_lower_bound_equals_goal_distance_and_cost_function(
    seed: int, objective: str, va: float, vb: float, u: list[float]
) -> None:
    search = _random_search(seed, objective, (va, vb))
    track = search.mesh.fs.track
    ga, gb = search.to_goal
    cost = cost_function(objective, va, vb)
    rng = np.random.default_rng(seed)
    for k in range(10):
        ea, eb = int(rng.integers(track.n_edges)), int(rng.integers(track.n_edges))
        ya, yb = u[k % 6] * float(track.lengths[ea]), u[(k + 1) % 6] * float(track.lengths[eb])
        if k % 3 == 0:  # on the goals' edges
            ea, eb = ga.edge, gb.edge
            ya, yb = min(max(ya, 0.0), float(track.lengths[ea])), min(max(yb, 0.0), float(track.lengths[eb]))
        pid = (ea, eb, 0)
        want = cost(ga.at(ea, ya), gb.at(eb, yb))
        assert repr(search.lower_bound(pid, (ya, yb))) == repr(want), (seed, pid, ya, yb)


@pytest.mark.parametrize("seed", range(8))
def test_side_ends_are_the_sides_with_their_ends_named(seed: int) -> None:
    rng = np.random.default_rng(500 + seed)
    fs = free_space(random_layout(rng), 0.2)
    mesh = _mesh(fs)
    for pid in fs._index:
        ends = mesh.side_ends(pid)
        assert [x[:5] for x in ends] == list(mesh.sides(pid)), pid
        for ax, a, face, lo, hi, k_lo, p_lo, k_hi, p_hi in ends:
            assert (k_lo, k_hi) == (mesh.point_key(face, lo), mesh.point_key(face, hi)), (pid, face)
            assert (p_lo, p_hi) == (((a, lo), (a, hi)) if ax == 0 else ((lo, a), (hi, a))), (pid, face)
        assert mesh.side_ends(pid) is ends  # made once


def _a_search() -> AnyAngleSearch:
    for seed in range(50):
        query = _search(3000 + seed, "fastest", (1.0, 1.0))
        if query is not None:
            return AnyAngleSearch(_mesh(query.free_space), query)
    raise AssertionError("no query")


@pytest.mark.parametrize("enabled", [True, False])
def test_the_search_leaves_the_garbage_collector_as_it_found_it(enabled: bool) -> None:
    search = _a_search()
    was = gc.isenabled()
    (gc.enable if enabled else gc.disable)()
    try:
        assert search.run() is not None
        assert gc.isenabled() is enabled
    finally:
        (gc.enable if was else gc.disable)()
