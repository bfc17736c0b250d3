"""The compiled search (:mod:`trajopt.plan_kernel`) is the graph planner's search node for node.

- ``_py_hypot`` is Python's :func:`math.hypot` bit for bit on 300 000 seeded pairs (C's ``hypot`` is not: it
  differs on about 0.2 % of them, and the search's ties would then differ).
- :func:`mpa.planners.graph.query.plan_graph` with the compiled search plans what it plans with
  :class:`~mpa.planners.graph.search.AnyAngleSearch`, bit for bit (the cells, the segments' offsets, the waypoints
  and the makespan): seeded random layouts, the example tracks and an Open-RMF map; swaps and free queries, both
  objectives, unequal speeds, clearances from tiny to large. Failing queries are printed.
- A search run in budgets stops after the same pops and returns the same segments; searches with the passing bound,
  restricted to a limit, stop at the same limit or find the same path.
- Under settings the compiled search does not follow (a benchmark's "before" arms) the planner uses the reference.
- :func:`trajopt.plan_kernel.install` installs it in a process whose kernels are compiled, and not in the ``numpy``
  mode of a single command.
"""

from __future__ import annotations

import gc
import json
import math
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mpa.errors import NoMotionError
from mpa.freespace import free_space
from mpa.graph_track import GraphTrack
from mpa.planners import corners as graph_corners
from mpa.planners.graph import bounds as graph_bounds
from mpa.planners.graph import query as graph_query
from mpa.planners.graph.bounds import passing_bound
from mpa.planners.graph.mesh import _mesh
from mpa.planners.graph.search import AnyAngleSearch
from mpa.planners.search_common import SearchQuery, least_through_face
from tests.helpers.graph_helpers import random_face_case, random_free_query, random_layout
from trajopt import plan_kernel
from trajopt.plan_kernel import CompiledSearch, arith
from trajopt.plan_kernel import search as kernel_search
from trajopt.plan_kernel.corners import build_programme

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ("y_junction", "passing_loop", "two_sidings", "theta", "lollipop", "figure_eight", "rail_yard", "warehouse")


def _example(name: str) -> GraphTrack:
    return GraphTrack.from_layout(json.loads((ROOT / "examples" / "tracks" / f"{name}.json").read_text()))


def _signature(plan: Any) -> tuple[Any, ...]:
    return (plan.segment_cells, plan.segment_offsets.tobytes(), plan.waypoints.tobytes(), plan.makespan)


def _plan_both(track: GraphTrack, s: Any, g: Any, d: float, objective: str, speeds: Any) -> tuple[Any, Any]:
    """The plan's signature with the reference search and with the compiled one (None: no motion)."""
    out = []
    for cls in (None, CompiledSearch):
        graph_query.use_search(cls)
        graph_corners.use_programme(None if cls is None else build_programme)
        try:
            p = graph_query.plan_graph(track, s, g, d, objective=objective, speeds=speeds)
            out.append(_signature(p))
        except NoMotionError as e:
            out.append(("no motion", str(e)))
        finally:
            graph_query.use_search(None)
            graph_corners.use_programme(None)
    return out[0], out[1]


@pytest.fixture(autouse=True)
def _reference_after() -> Any:
    yield
    graph_query.use_search(None)
    graph_corners.use_programme(None)


def test_py_hypot_is_pythons_hypot_bit_for_bit() -> None:
    rng = np.random.default_rng(20261127)
    n = 100_000
    x = rng.random(n) * np.exp(rng.normal(0.0, 6.0, n))
    y = rng.random(n) * np.exp(rng.normal(0.0, 6.0, n))
    pairs = list(zip(x.tolist(), y.tolist()))
    pairs += [(a, a) for a in x[:50_000].tolist()]  # equal arguments
    pairs += [(a, a * 1e-9) for a in y[:50_000].tolist()]  # one tiny against the other (the tie-break's scale)
    pairs += [(a, 0.0) for a in x[:50_000].tolist()] + [(0.0, 0.0), (-3.0, 4.0), (3.0, -4.0), (1e300, 1e300)]
    pairs += [(a, b) for a, b in zip(rng.uniform(0, 1e3, 50_000).tolist(), rng.uniform(0, 1e3, 50_000).tolist())]
    got = arith._hypot_many(np.array(pairs))
    want = np.array([math.hypot(a, b) for a, b in pairs])
    bad = np.nonzero(got != want)[0]
    assert len(bad) == 0, [(pairs[i], got[i], want[i]) for i in bad[:5]]
    assert len(pairs) >= 300_000


def _queries(track: GraphTrack, d: float, rng: np.random.Generator, n: int) -> list[tuple[Any, Any]]:
    fs = free_space(track, d)
    out = []
    for k in range(n):
        q = random_free_query(track, fs, rng, vertex_p=0.2)
        if q is None:
            continue
        s, g = q
        if k % 3 == 0:
            g = (s[1], s[0])  # a swap
        out.append((s, g))
    return out


def _example_searches(names: tuple[str, ...], rng: np.random.Generator, n: int) -> Any:
    """``(name, mesh, s, g, query)`` of ``n`` random queries on each example track (D 0.3 of its median edge) whose
    start and goal lie in one component."""
    for name in names:
        track = _example(name)
        d = 0.3 * float(np.median(track.lengths))
        fs = free_space(track, d)
        mesh = _mesh(fs)
        for s, g in _queries(track, d, rng, n):
            if fs.component_of(*s) == fs.component_of(*g):
                yield name, mesh, s, g, SearchQuery(track, fs, s, g, "fastest", (1.0, 1.0))


def _check_many(cases: list[tuple[GraphTrack, float, Any, Any, str, Any]]) -> int:
    bad = []
    for track, d, s, g, objective, speeds in cases:
        ref, got = _plan_both(track, s, g, d, objective, speeds)
        if ref != got:
            bad.append((s, g, d, objective, speeds, ref[-1], got[-1]))
    assert not bad, f"{len(bad)} of {len(cases)} plans differ, e.g. {bad[:3]}"
    return len(cases)


def test_the_face_entries_bound_is_the_references_bit_for_bit() -> None:
    """The compiled :func:`~mpa.planners.search_common.least_through_face` (its candidate points in another order)
    equals the reference on 20 000 seeded cases, both objectives, unequal speeds, unreachable ends (``inf``)."""
    rng = np.random.default_rng(20261128)
    bad = []
    for _ in range(20_000):
        case = random_face_case(rng)
        want = least_through_face(*case)
        got = arith._least_through_face(*case)
        if repr(got) != repr(want):
            bad.append((case, got, want))
    assert not bad, bad[:5]


def test_plans_are_the_references_on_random_layouts() -> None:
    rng = np.random.default_rng(7)
    cases = []
    for _ in range(120):
        track = random_layout(rng)
        d = float(rng.choice([1e-3, 0.1, 0.3, 0.6])) * float(np.median(track.lengths))
        objective = "fastest" if rng.random() < 0.8 else "shortest"
        speeds = (1.0, 1.0) if rng.random() < 0.6 else (float(rng.uniform(0.3, 2.0)), float(rng.uniform(0.3, 2.0)))
        cases += [(track, d, s, g, objective, speeds) for s, g in _queries(track, d, rng, 10)]
    assert _check_many(cases) >= 1000


def test_plans_are_the_references_on_the_example_tracks() -> None:
    rng = np.random.default_rng(11)
    cases = []
    for name in EXAMPLES:
        track = _example(name)
        med = float(np.median(track.lengths))
        for frac in (0.05, 0.2, 0.5, 1.0):
            speeds = (1.0, 1.0) if frac < 0.5 else (1.0, 0.7)
            cases += [(track, frac * med, s, g, "fastest", speeds) for s, g in _queries(track, frac * med, rng, 12)]
    assert _check_many(cases) >= 300


def test_plans_are_the_references_on_an_openrmf_map() -> None:
    track = GraphTrack.from_file(ROOT / "tests" / "data" / "openrmf" / "hotel.building.yaml", level="L1")
    rng = np.random.default_rng(3)
    d = 0.2 * float(np.median(track.lengths))
    cases = [(track, d, s, g, "fastest", (1.0, 1.0)) for s, g in _queries(track, d, rng, 40)]
    assert _check_many(cases) >= 30


def _segments_in_steps(cls: type, mesh: Any, query: SearchQuery, bound: Any, budget: int) -> list[Any]:
    """Every answer of ``run(budget)`` until the path, then the path."""
    search = cls(mesh, query, bound=bound)
    answers = []
    for _ in range(100_000):
        segs = search.run(budget)
        answers.append(segs)
        if segs is not None:
            return answers
    raise AssertionError("no path")


def test_a_search_run_in_budgets_stops_where_the_reference_stops() -> None:
    rng = np.random.default_rng(5)
    compared = 0
    for name, mesh, s, g, query in _example_searches(("passing_loop", "theta", "rail_yard", "warehouse"), rng, 8):
        for budget in (1, 7, 50):
            ref = _segments_in_steps(AnyAngleSearch, mesh, query, None, budget)
            got = _segments_in_steps(CompiledSearch, mesh, query, None, budget)
            assert got == ref, (name, s, g, budget)
            compared += 1
    assert compared >= 40


def test_searches_with_the_passing_bound_and_limits_are_the_references() -> None:
    rng = np.random.default_rng(9)
    compared = 0
    for name in ("y_junction", "passing_loop", "two_sidings", "rail_yard", "warehouse"):
        track = _example(name)
        d = 0.3 * float(np.median(track.lengths))
        fs = free_space(track, d)
        mesh = _mesh(fs)
        for s, g in _queries(track, d, rng, 12):
            if fs.component_of(*s) != fs.component_of(*g):
                continue
            pb = passing_bound(mesh, s, g, 1.0, 1.0)
            if pb is None:
                continue
            query = SearchQuery(track, fs, s, g, "fastest", (1.0, 1.0))
            for slack in (1e-8, 0.05, None):
                limit = None if slack is None else pb.at_start * (1.0 + slack)
                pb.restrict(math.inf if limit is None else limit)
                ref = AnyAngleSearch(mesh, query, bound=pb).run(limit=limit)
                got = CompiledSearch(mesh, query, bound=pb).run(limit=limit)
                assert got == ref, (name, s, g, slack)
                compared += 1
    assert compared >= 30


def test_searches_of_a_class_of_motions_are_the_references() -> None:
    """With a class's goal distances (``mpa.planners.graph.corridor``), with and without the passing bound: the same
    answers, run by run."""
    from mpa.planners.graph.corridor import approach_distances
    from tests.mpa.test_graph_corridor import _corridor_queries, _subdivided

    rng = np.random.default_rng(31)
    compared = 0
    tracks = [(_example(n), f) for n in ("y_junction", "two_sidings", "passing_loop") for f in (0.1, 0.4)]
    tracks += [(_subdivided(rng), 0.15) for _ in range(12)]
    for track, frac in tracks:
        d = frac * float(np.median(track.lengths))
        fs = free_space(track, d)
        mesh = _mesh(fs)
        for s, g, _ in _corridor_queries(track, fs, rng, 3):
            query = SearchQuery(track, fs, s, g, "fastest", (1.0, 1.0))
            pb = passing_bound(mesh, s, g, 1.0, 1.0)
            pairs = approach_distances(track.geometry, s, g, mesh.eps)
            assert pairs
            for pair in pairs:
                for bound in (None, pb):
                    for budget in (5, None):
                        ref_search = AnyAngleSearch(mesh, query, bound=bound, to_goal=pair)
                        got_search = CompiledSearch(mesh, query, bound=bound, to_goal=pair)
                        assert got_search.fq == ref_search.fq
                        for _ in range(100_000):  # in budgets until the path
                            ref, got = ref_search.run(budget), got_search.run(budget)
                            assert got == ref, (s, g, bound is None, budget)
                            if ref is not None:
                                break
                        assert ref is not None
                        compared += 1
    assert compared >= 40, compared


def test_no_alloc_kernels_are_compiled_without_counts_and_refuse_to_allocate() -> None:
    """``no_alloc`` is numba's ``_nrt=False``; numba then refuses a kernel that allocates, or calls one that does."""
    from numba.core.errors import TypingError

    from trajopt._numba import _numba_options, njit

    assert _numba_options({"cache": True, "no_alloc": True}) == {"cache": True, "_nrt": False}
    assert _numba_options({"cache": True}) == {"cache": True}

    @njit(no_alloc=True)
    def reads(a: Any) -> float:
        return float(a[0] + a[-1])

    @njit
    def makes(n: int) -> Any:
        return np.zeros(n)

    @njit(no_alloc=True)
    def calls_one_that_makes(n: int) -> float:
        return float(makes(n)[0])

    assert reads(np.arange(4.0)) == 3.0
    with pytest.raises(TypingError):
        calls_one_that_makes(3)


def test_the_searches_arrays_are_all_freed() -> None:
    """The node functions run without numba's reference counts (``no_alloc``): a count missed where one is needed
    would leak the search's arrays or free them under it. numba's tally of its allocations balances over searches
    made (their tables grown, fronts made) and dropped."""
    from numba.core.runtime import _nrt_python, rtsys

    rng = np.random.default_rng(21)
    cases = [
        (mesh, query, passing_bound(mesh, s, g, 1.0, 1.0))
        for _, mesh, s, g, query in _example_searches(("passing_loop", "rail_yard", "warehouse"), rng, 12)
    ]
    for mesh, query, pb in cases:  # compiled and loaded, and the arrays each mesh and bound keep made, before
        CompiledSearch(mesh, query, bound=pb).run()
    _nrt_python.memsys_enable_stats()
    try:
        kernel_search._spare.clear()  # the node arrays a process keeps for its next search: none before, none after
        gc.collect()
        before = rtsys.get_allocation_stats()
        for mesh, query, pb in cases:
            search = CompiledSearch(mesh, query, bound=pb)
            search.run()
            del search
        kernel_search._spare.clear()
        gc.collect()
        after = rtsys.get_allocation_stats()
    finally:
        _nrt_python.memsys_disable_stats()
    made, freed = after.alloc - before.alloc, after.free - before.free
    infos, infos_freed = after.mi_alloc - before.mi_alloc, after.mi_free - before.mi_free
    assert len(cases) >= 20 and sum(pb is not None for _, _, pb in cases) >= 5
    assert made >= 10 * len(cases), made
    assert (made, infos) == (freed, infos_freed), (before, after)


def test_a_dropped_searchs_node_arrays_start_the_next_whatever_they_hold(monkeypatch: pytest.MonkeyPatch) -> None:
    """A dropped search leaves its node arrays to the process's next search (``search.SPARE_BYTES``), which writes
    every row before it reads it: with the spare arrays filled with garbage (NaN, huge integers, every flag set)
    before each search, every search still finds the reference's path; the next search starts with the very arrays
    the last one grew, and arrays above the limit are not kept."""
    rng = np.random.default_rng(29)
    cases = list(_example_searches(("y_junction", "passing_loop", "rail_yard", "warehouse"), rng, 10))
    kernel_search._spare.clear()
    compared = reused = 0
    for name, mesh, s, g, query in cases:
        for pb in (None, passing_bound(mesh, s, g, 1.0, 1.0)):
            for arrays in kernel_search._spare:
                for a in arrays:
                    if a.dtype == np.bool_:
                        a.fill(True)
                    elif a.dtype.kind == "f":
                        a.fill(np.nan)
                    else:
                        a[...] = rng.integers(-(2**62), 2**62, size=a.shape)
            kept = kernel_search._spare[0][0] if kernel_search._spare else None
            search = CompiledSearch(mesh, query, bound=pb)
            reused += kept is not None and search.N[0] is kept
            assert search.run() == AnyAngleSearch(mesh, query, bound=pb).run(), (name, s, g, pb is not None)
            grown = search.N[0]
            del search
            assert kernel_search._spare and kernel_search._spare[0][0].shape[0] >= grown.shape[0]
            compared += 1
    assert compared >= 40 and reused >= compared - 1, (compared, reused)
    monkeypatch.setattr(kernel_search, "SPARE_BYTES", 0)
    kernel_search._spare.clear()
    _, mesh, s, g, query = cases[0]
    search = CompiledSearch(mesh, query)
    search.run()
    del search
    assert not kernel_search._spare


def _tiny(a: Any, rows: int) -> Any:
    """``a``'s first ``rows`` rows (its fill kept: -1 in a hash table's values, zeros in its keys)."""
    return np.ascontiguousarray(a[:rows]).copy()


class _TinySearch(CompiledSearch):
    """The compiled search with every table of its own and of its mesh starting at a few rows, so that pops stop for
    room (``run._pops``: the bound's tables, a point's expansion, a face entry's) again and again."""

    def __init__(self, mesh: Any, query: Any, bound: Any = None) -> None:
        mesh._kernel_tables = None  # the mesh's points and polygons made anew, tiny
        super().__init__(mesh, query, bound=bound)
        t = self.tables
        t.pk, t.pv, t.pt, t.pty = _tiny(t.pk, 4), _tiny(t.pv, 4), _tiny(t.pt, 2), _tiny(t.pty, 2)
        t.C = (_tiny(t.C[0], 4), _tiny(t.C[1], 4), _tiny(t.C[2], 1), _tiny(t.C[3], 1), _tiny(t.C[4], 1))
        self.best, self.pbv = _tiny(self.best, 2), _tiny(self.pbv, 2)
        self.N = (*(_tiny(a, 1) for a in self.N[:5]), self.N[5])
        self.S = (_tiny(self.S[0], 4), _tiny(self.S[1], 4), _tiny(self.S[2], 1), _tiny(self.S[3], 1))
        bs = self.BS
        self.BS = (_tiny(bs[0], 4), _tiny(bs[1], 4), _tiny(bs[2], 1), _tiny(bs[3], 1), _tiny(bs[4], 4),
                   _tiny(bs[5], 4), _tiny(bs[6], 1), _tiny(bs[7], 1))  # fmt: skip


def test_searches_whose_tables_start_tiny_are_the_references() -> None:
    """Every table grown while a pop is in hand (the pop resumed after its table grew) gives the reference's nodes:
    the same paths, with and without the passing bound, run whole and in budgets."""
    rng = np.random.default_rng(13)
    compared = grown = bounded = 0
    for name, mesh, s, g, query in _example_searches(
        ("y_junction", "passing_loop", "two_sidings", "rail_yard"), rng, 10
    ):
        for pb in (None, passing_bound(mesh, s, g, 1.0, 1.0)):
            ref = AnyAngleSearch(mesh, query, bound=pb).run()
            tiny = _TinySearch(mesh, query, bound=pb)
            got = tiny.run(budget=7)
            while got is None:
                got = tiny.run(budget=7)
            assert got == ref, (name, s, g, pb is not None)
            grown += tiny.N[0].shape[0] > 8 and tiny.BS[2].shape[0] > (1 if pb is None else 8)
            compared += 1
            bounded += pb is not None
            mesh._kernel_tables = None
    assert compared >= 40 and bounded >= 15 and grown >= 30, (compared, bounded, grown)


def test_settings_it_does_not_follow_send_the_planner_to_the_reference(monkeypatch: pytest.MonkeyPatch) -> None:
    track = _example("passing_loop")
    fs = free_space(track, 0.3)
    mesh = _mesh(fs)
    s, g = ((0, 0.2), (0, 1.5)), ((0, 1.5), (0, 0.2))
    query = SearchQuery(track, fs, s, g, "fastest", (1.0, 1.0))
    graph_query.use_search(CompiledSearch)
    assert type(graph_query._new_search(mesh, query)) is CompiledSearch
    monkeypatch.setattr(graph_bounds, "POINTS_FROM_FRONTS", False)
    pb = graph_bounds.PassingBound(mesh, s, g, 1.0, 1.0)
    if pb.vertex is not None:
        assert type(graph_query._new_search(mesh, query, pb)) is AnyAngleSearch
    monkeypatch.setattr(graph_query, "AnyAngleSearch", type("Counting", (AnyAngleSearch,), {}))
    assert type(graph_query._new_search(mesh, query)).__name__ == "Counting"


def test_install_in_each_kernel_mode_and_its_switch() -> None:
    code = (
        "import sys; from trajopt import plan_kernel; from mpa.planners.graph import query; "
        "from mpa.planners import corners; "
        "print(plan_kernel.install(), query.compiled_search() is not None, corners.compiled_programme() is not None, "
        "'numba' in sys.modules)"
    )
    env = {k: v for k, v in os.environ.items() if k != plan_kernel.ENV}
    for mode, search, want in (
        ("numpy", "compiled", "False False False False"),
        ("numba", "compiled", "True True True True"),
        ("numba", "python", "False False False True"),
    ):
        out = subprocess.run(
            [sys.executable, "-c", code],
            capture_output=True,
            text=True,
            check=True,
            cwd=ROOT,
            env={**env, "TRAJOPT_KERNELS": mode, plan_kernel.ENV: search},
        )
        assert out.stdout.split("\n")[0] == want, (mode, search, out.stdout, out.stderr)


def test_warm_compiles_and_a_batch_installs_and_warms(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from trajopt.cli import batch

    plan_kernel.warm()
    assert plan_kernel.search._run.signatures, "the kernel was not compiled"
    assert plan_kernel.corners._programme_arrays.signatures, "the corners' programme was not compiled"
    calls: list[str] = []
    monkeypatch.setattr(plan_kernel, "install", lambda: calls.append("install") or True)
    monkeypatch.setattr(plan_kernel, "warm", lambda: calls.append("warm"))
    track = _example("y_junction")
    q = {"a_start": "left", "b_start": "right", "a_goal": "right", "b_goal": "left"}
    batch.run_batch(track, [q], tmp_path / "out", clearance=0.3, workers=1)
    assert calls[:2] == ["install", "warm"] and calls.count("install") == 2, calls


def test_searches_that_share_a_mesh_and_interleave_are_the_references() -> None:
    """The polygons and points a compiled search names are kept with the mesh and shared: a search paused while
    others run on the same mesh (and add to those tables) resumes to the reference's path."""
    rng = np.random.default_rng(13)
    track = _example("rail_yard")
    d = 0.2 * float(np.median(track.lengths))
    fs = free_space(track, d)
    mesh = _mesh(fs)
    queries = [(s, g) for s, g in _queries(track, d, rng, 30) if fs.component_of(*s) == fs.component_of(*g)][:12]
    assert len(queries) >= 8
    for i in range(0, len(queries) - 1, 2):
        qa = SearchQuery(track, fs, *queries[i], "fastest", (1.0, 1.0))
        qb = SearchQuery(track, fs, *queries[i + 1], "fastest", (1.0, 1.0))
        paused = CompiledSearch(mesh, qa)
        first = paused.run(3)
        other = CompiledSearch(mesh, qb).run()
        rest = first if first is not None else paused.run()
        assert other == AnyAngleSearch(mesh, qb).run(), queries[i + 1]
        assert rest == AnyAngleSearch(mesh, qa).run(), queries[i]


def _same_programme(a: Any, b: Any) -> bool:
    """Whether two :class:`~mpa.planners.corners.Programme` (or None) are equal bit for bit, arrays and types."""
    if a is None or b is None:
        return a is None and b is None
    for x, y in zip(a, b):
        if isinstance(x, np.ndarray) or isinstance(y, np.ndarray):
            if not (
                isinstance(x, np.ndarray)
                and isinstance(y, np.ndarray)
                and x.shape == y.shape
                and x.dtype == y.dtype
                and x.tobytes() == y.tobytes()
            ):
                return False
        elif x != y or repr(x) != repr(y):  # repr: 0 and 0.0, -0.0 and 0.0 differ
            return False
    return True


@pytest.mark.parametrize("drop", [True, False])
def test_the_corners_programme_is_the_references_bit_for_bit(drop: bool, monkeypatch: pytest.MonkeyPatch) -> None:
    """:func:`~trajopt.plan_kernel.corners.build_programme` builds every chain's programme (the search's and the
    widened ones) as :func:`mpa.planners.corners._programme` does, bit for bit: random layouts and the example tracks,
    equal and unequal speeds, with and without the implied rows."""
    monkeypatch.setattr(graph_corners, "DROP_IMPLIED_ROWS", drop)
    seen = {"chains": 0, "free": 0}
    bad: list[Any] = []

    def both(*args: Any) -> Any:
        ref = graph_corners._programme(*args[:-1], dict(args[-1]))
        got = build_programme(*args)
        seen["chains"] += 1
        seen["free"] += ref is not None
        if not _same_programme(ref, got):
            bad.append((args[1], args[2].tolist(), args[3].tolist(), args[4]))
        return ref

    rng = np.random.default_rng(29)
    cases = []
    for _ in range(40 if drop else 15):
        track = random_layout(rng)
        d = float(rng.choice([1e-3, 0.1, 0.3, 0.6])) * float(np.median(track.lengths))
        speeds = (1.0, 1.0) if rng.random() < 0.5 else (float(rng.uniform(0.3, 2.0)), float(rng.uniform(0.3, 2.0)))
        cases += [(track, d, s, g, speeds) for s, g in _queries(track, d, rng, 8)]
    for name in EXAMPLES if drop else EXAMPLES[:3]:
        track = _example(name)
        med = float(np.median(track.lengths))
        for frac in (0.05, 0.5):
            cases += [(track, frac * med, s, g, (1.0, 0.6)) for s, g in _queries(track, frac * med, rng, 6)]
    graph_query.use_search(CompiledSearch)
    graph_corners.use_programme(both)
    for track, d, s, g, speeds in cases:
        try:
            graph_query.plan_graph(track, s, g, d, speeds=speeds)
        except NoMotionError:
            pass
    assert not bad, f"{len(bad)} of {seen['chains']} programmes differ, e.g. {bad[:2]}"
    assert seen["free"] >= (400 if drop else 100), seen


@settings(max_examples=300, deadline=None)
@given(
    n=st.integers(1, 12),
    seed=st.integers(0, 2**32 - 1),
    drop=st.booleans(),
    speeds=st.sampled_from(((1.0, 1.0), (1.0, 0.37), (0.6, 1.0))),
)
def test_the_corners_programme_of_any_chain_is_the_references(
    n: int, seed: int, drop: bool, speeds: tuple[float, float]
) -> None:
    """Chains the search does not make (robots standing on stays, stays pinned to a fixed end, no free corner at all,
    cells of one edge on either piece) give the same programme compiled and in :mod:`mpa`, bit for bit."""
    track = _example("warehouse")
    fs = free_space(track, 0.3)
    rng = np.random.default_rng(seed)
    lengths = track.lengths
    edges = rng.choice(track.n_edges, size=3, replace=False).tolist()
    cells: list[tuple[int, int, int]] = []
    p0 = np.zeros((n, 2))
    p1 = np.zeros((n, 2))
    for i in range(n):
        e, f = (int(x) for x in rng.choice(edges, size=2))
        if i > 0 and rng.random() < 0.7:  # often one robot (or both) stays on its edge across the corner
            e = cells[-1][0] if rng.random() < 0.8 else e
            f = cells[-1][1] if rng.random() < 0.8 else f
        cells.append((e, f, int(rng.integers(0, 2)) if e == f else 0))
        for r, edge in enumerate((e, f)):
            shared = i > 0 and cells[-2][r] == edge and rng.random() < 0.8  # a free corner, unless pinned
            x0 = p1[i - 1, r] if shared else rng.uniform(0, lengths[edge])
            p0[i, r] = x0
            p1[i, r] = x0 if rng.random() < 0.3 else rng.uniform(0, lengths[edge])  # stands, or moves
    old = graph_corners.DROP_IMPLIED_ROWS
    graph_corners.DROP_IMPLIED_ROWS = drop
    try:
        args = (fs, cells, p0, p1, speeds, float(rng.uniform(1, 50)), float(rng.uniform(1, 80)))
        ref = graph_corners._programme(*args, {})
        got = build_programme(*args, {})
    finally:
        graph_corners.DROP_IMPLIED_ROWS = old
    assert _same_programme(ref, got), (cells, p0.tolist(), p1.tolist(), speeds, drop)
