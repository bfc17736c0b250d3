"""The corner re-solve of the graph planner (:mod:`mpa.planners.corners`): valid, unique, continuous in the query.

Reproducers: δ-twins of random queries (``experiments/stability_sweeps.py --parts layouts``, seed 21) whose plans
kept their routes but moved by 0.38 to 1 m before the re-solve (the search returned another corner of a plateau, or
turned a grid corner the other way). Seeded twins: random queries of the example layouts at δ = 1e-7, none may change
routes or move by more than 1e-3 m. Property tests: the re-solved plan keeps the clearance, the routes and the
search's makespan (within :data:`~mpa.planners.corners.CHECK_TOL`), and re-solving it again changes nothing.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mpa.errors import NoMotionError
from mpa.freespace import FreeSpace, free_space
from mpa.graph_track import GraphTrack
from mpa.planners import corners as corners_module
from mpa.planners import graph as graph_planner
from mpa.planners.corners import CHECK_TOL, RESOLVE_TOL, _routes, resolve_corners
from mpa.planners.graph import plan_graph
from mpa.planners.search_common import SearchQuery
from trajopt.analysis.stability import _route_key, layout_queries, layout_twins

TRACKS = Path(__file__).resolve().parents[2] / "examples" / "tracks"


def _track(name: str) -> GraphTrack:
    return GraphTrack.from_json(TRACKS / f"{name}.json")


def _gap(track: GraphTrack, p: object, q: object, samples: int = 401) -> float:
    """Sup over the common path parameter of the larger robot's graph distance between two plans (metres)."""
    u = np.linspace(0.0, 1.0, samples)
    (ea, sa), (eb, sb) = p.positions(u)  # type: ignore[attr-defined]
    (fa, ta), (fb, tb) = q.positions(u)  # type: ignore[attr-defined]
    g = track.geometry
    return float(np.max(np.maximum(g.distance(ea, sa, fa, ta), g.distance(eb, sb, fb, tb))))


# (layout, clearance, start, goal, δ, signs of the moves of A's start, B's start, A's goal, B's goal)
REPRODUCERS = [
    (
        "two_sidings",
        0.62832,
        ((3, 2.0669302434037813), (1, 1.6201403087969437)),
        ((1, 0.06737668365440493), (3, 1.9298591279795128)),
        1e-7,
        (1, 1, 1, -1),
    ),
    (
        "two_sidings",
        3.1416,
        ((1, 0.08274345411470023), (5, 0.5549810406084776)),
        ((5, 1.4117949044424625), (1, 2.2297608739297297)),
        1e-7,
        (1, 1, -1, 1),
    ),
    (
        "passing_loop",
        2.0,
        ((3, 1.3331473358019728), (2, 4.168787385537782)),
        ((0, 1.5176070714227157), (3, 1.0580957107332813)),
        1e-5,
        (1, 1, 1, 1),
    ),
    (
        "passing_loop",
        0.8,
        ((1, 3.611928765283127), (2, 2.5103827323911476)),
        ((2, 1.1467140050459115), (1, 3.230104599203963)),
        1e-7,
        (-1, 1, -1, 1),
    ),
]


@pytest.mark.parametrize(("name", "D", "start", "goal", "delta", "signs"), REPRODUCERS)
def test_twin_reproducers_keep_routes_and_move_continuously(
    name: str,
    D: float,
    start: tuple[tuple[int, float], ...],
    goal: tuple[tuple[int, float], ...],
    delta: float,
    signs: tuple[int, ...],
) -> None:
    track = _track(name)
    ends = [*start, *goal]
    moved = [(e, s + k * delta) for (e, s), k in zip(ends, signs)]
    base = plan_graph(track, start, goal, D)
    twin = plan_graph(track, (moved[0], moved[1]), (moved[2], moved[3]), D)
    gap = _gap(track, base, twin)
    assert _route_key(base) == _route_key(twin)
    assert gap <= 1e-3, (name, D, gap, base.word, twin.word)


SMALL_LAYOUTS = ("y_junction", "passing_loop", "two_sidings", "theta", "figure_eight", "lollipop", "circle")


def test_seeded_twins_of_random_queries_keep_routes_and_barely_move() -> None:
    """Per small example layout seeded queries (the swaps left out: they lie on the swap's tie) and a twin at
    δ = 1e-7 each: no route changes, no plan moves by more than 1e-3 m (about two hundred twins)."""
    t0 = time.perf_counter()
    checked = 0
    bad = []
    for name in SMALL_LAYOUTS:
        track = _track(name)
        med = float(np.median(track.lengths))
        ds = tuple(round(f * med, 6) for f in (0.05, 0.2, 0.5))  # 1 × the median admits no query on some
        qs = layout_queries(track, 48, np.random.default_rng(5), ds, tries=2000)
        for x in layout_twins(track, qs, (1e-7,), np.random.default_rng(6)):
            if x.swap:
                continue
            checked += 1
            if x.route_changed or x.gap > 1e-3:
                bad.append((name, qs[x.query], x))
    assert checked >= 200, checked
    assert not bad, bad
    print(f"{checked} twins in {time.perf_counter() - t0:.1f} s")


def _search_segments(track: GraphTrack, D: float, start: object, goal: object) -> tuple[object, list[list[object]]]:
    fs = free_space(track, D)
    mesh = graph_planner._mesh(fs)
    query = SearchQuery(track, fs, start, goal, "fastest", (1.0, 1.0))  # type: ignore[arg-type]
    segs = graph_planner.AnyAngleSearch(mesh, query).run()
    assert segs is not None
    return fs, graph_planner._merge_same_polygon([x for x in segs if x[1] != x[2]])


def _makespan(segs: list[list[object]]) -> float:
    if not segs:
        return 0.0
    d = np.array([np.subtract(x[2], x[1]) for x in segs], dtype=float)  # type: ignore[call-overload]
    return float(np.sum(np.max(np.abs(d), axis=1)))


_Pair = tuple[tuple[int, float], tuple[int, float]]


def _generated_query(
    name: str, fr: list[float], edges: list[int], dfrac: float, swap: bool
) -> tuple[GraphTrack, FreeSpace, _Pair, _Pair, float] | None:
    """``(track, free space, start, goal, D)`` of a generated query on an example layout: robots on ``edges`` (modulo
    the layout's) at fractions ``fr`` of them, the goal the start swapped when ``swap``, D a fraction ``dfrac`` of
    the median edge; None where the start or the goal is not free or they lie in different components."""
    track = _track(name)
    lengths = np.asarray(track.lengths)
    # Offsets closer to a vertex than 1e-9 of the edge are put on the vertex: below the planner's tolerance the
    # search's chain of cells there is degenerate (a segment of 1e-38 m from the start to the vertex) and the
    # re-solve of such a chain is not a fixed point (two equally fast corner sets; docs/graphs.md, "Stability").
    fr = [0.0 if f < 1e-9 else 1.0 if f > 1.0 - 1e-9 else f for f in fr]
    pos = [(e % len(lengths), float(f * lengths[e % len(lengths)])) for e, f in zip(edges, fr)]
    if swap:  # swaps make the robots negotiate: the search answers
        pos[2], pos[3] = pos[1], pos[0]
    D = round(dfrac * float(np.median(lengths)), 6)
    g = track.geometry
    if min(g.distance_scalar(*pos[0], *pos[1]), g.distance_scalar(*pos[2], *pos[3])) < D + 1e-6:
        return None
    start, goal = (pos[0], pos[1]), (pos[2], pos[3])
    fs = free_space(track, D)
    if fs.component_of(*start) is None or fs.component_of(*start) != fs.component_of(*goal):
        return None
    return track, fs, start, goal, D


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    name=st.sampled_from(("passing_loop", "two_sidings", "y_junction", "theta")),
    fr=st.lists(st.floats(0.0, 1.0), min_size=4, max_size=4),
    edges=st.lists(st.integers(0, 10), min_size=4, max_size=4),
    dfrac=st.sampled_from((0.05, 0.2, 0.5, 1.0)),
    swap=st.booleans(),
)
def test_resolved_corners_are_valid_and_a_fixed_point(
    name: str, fr: list[float], edges: list[int], dfrac: float, swap: bool
) -> None:
    got = _generated_query(name, fr, edges, dfrac, swap)
    if got is None:
        return
    track, fs, start, goal, D = got
    g = track.geometry
    if graph_planner._independent_motion(graph_planner._mesh(fs), start, goal) is not None:
        return  # the straight motion: no search, nothing to re-solve
    fs, segs = _search_segments(track, D, start, goal)
    out = resolve_corners(fs, segs, (1.0, 1.0))
    m0, m1 = _makespan(segs), _makespan(out)
    # the check's bound: the solve's rounding above its aim (RESOLVE_TOL / 2) is allowed
    assert m1 <= m0 * (1.0 + CHECK_TOL), (start, goal, D, m0, m1)
    assert _routes(out) == _routes(segs), (start, goal, D)
    for (e, f, _), a, b in out:
        assert g.segment_min_scalar(e, f, *a, *b) >= fs._dmin - 1e-15, (start, goal, D, a, b)
    # unique: re-solving the re-solved chain gives the same corners
    again = resolve_corners(fs, [x for x in out if x[1] != x[2]], (1.0, 1.0))
    pa = np.array([[*x[1], *x[2]] for x in out if x[1] != x[2]])
    pb = np.array([[*x[1], *x[2]] for x in again if x[1] != x[2]])
    assert pa.shape == pb.shape and np.max(np.abs(pa - pb), initial=0.0) <= 1e-6, (start, goal, D)
    plan = plan_graph(track, start, goal, D)
    assert plan.min_distance() >= D - 1e-9
    assert _route_key(plan) is not None


def test_the_check_allows_the_solves_rounding_and_no_more() -> None:
    """A re-solved chain whose makespan or travel is above the search's by the solve's rounding (a few times
    ``RESOLVE_TOL``, as measured on the airport map's chains) passes the check; one above by more than ``CHECK_TOL``
    does not."""
    track = _track("warehouse")
    start, goal = ((6, 8.964691608686666), (75, 5.243888656002149)), ((75, 5.243888656002149), (6, 8.964691608686666))
    fs, segs = _search_segments(track, 0.4, start, goal)
    out = [x for x in resolve_corners(fs, segs, (1.0, 1.0)) if x[1] != x[2]]
    d = np.array([np.subtract(x[2], x[1]) for x in out], dtype=float)  # type: ignore[call-overload]
    sig = tuple([int(np.sign(x)) for x in d[:, r]] for r in (0, 1))
    m, w = _makespan(out), float(np.sum(np.abs(d)))
    floor = fs._dmin - 1e-12

    def valid(m_search: float, w_search: float) -> bool:
        return corners_module._valid(fs, out, sig, (1.0, 1.0), m_search, w_search, floor)  # type: ignore[arg-type]

    assert valid(m, w)
    for over in (3.0 * RESOLVE_TOL, 0.5 * CHECK_TOL):  # rounding above the aim: kept
        assert valid(m / (1.0 + over), w) and valid(m, w / (1.0 + over)), over
    assert not valid(m / (1.0 + 2.0 * CHECK_TOL), w)
    assert not valid(m, w / (1.0 + 2.0 * CHECK_TOL))


def test_plan_keeps_the_search_makespan_on_the_warehouse() -> None:
    """A searched warehouse query: the re-solve moves corners by metres, the makespan stays within the tolerance."""
    track = _track("warehouse")
    start, goal = ((6, 8.964691608686666), (75, 5.243888656002149)), ((75, 5.243888656002149), (6, 8.964691608686666))
    try:
        fs, segs = _search_segments(track, 0.4, start, goal)
    except NoMotionError:  # pragma: no cover - the query has a motion
        pytest.fail("no motion")
    out = resolve_corners(fs, segs, (1.0, 1.0))
    assert _makespan(out) <= _makespan(segs) * (1.0 + CHECK_TOL)
    assert _routes(out) == _routes(segs)


@pytest.mark.parametrize("speeds", [(1.0, 1.0), (0.6, 1.0)])
def test_corners_do_not_depend_on_the_common_scale_of_the_speeds(speeds: tuple[float, float]) -> None:
    """Seeded queries of the small example layouts planned at ``k·(vA, vB)`` for k = 1, 1e-3, 3.5e-3 and 1e3: the
    same corners (within 1e-9 of the layout's length). The rule is solved in durations at the faster speed; in
    seconds, 65 of these 480 comparisons moved corners by up to 0.09 m at mm/s speeds (the re-solve refused by
    its own rounding)."""
    checked, bad = 0, []
    for name in SMALL_LAYOUTS:
        track = _track(name)
        med = float(np.median(track.lengths))
        ds = tuple(round(f * med, 6) for f in (0.05, 0.2, 0.5))
        for D, start, goal in layout_queries(track, 12, np.random.default_rng(28), ds, tries=2000):
            try:
                ref = np.asarray(plan_graph(track, start, goal, D, "fastest", speeds).route_waypoints)
            except NoMotionError:
                continue
            for k in (1e-3, 0.0035, 1e3):
                w = np.asarray(
                    plan_graph(track, start, goal, D, "fastest", (speeds[0] * k, speeds[1] * k)).route_waypoints
                )
                checked += 1
                tol = 1e-9 * max(1.0, float(track.total_length))
                if w.shape != ref.shape or np.max(np.abs(w - ref)) > tol:
                    bad.append((name, D, start, goal, k, ref.tolist(), w.tolist()))
    assert checked >= 200, checked
    assert not bad, bad


@pytest.mark.parametrize("v", [0.0005, 0.00175, 0.005, 0.5, 50.0])
def test_the_y_corner_moves_continuously_with_the_margin_at_any_speed(v: float) -> None:
    """The Y, A from b_left to b_right, B from b_right to b_short, planned for the clearance 0.05 m plus margins
    of 1e-9 to 1e-3 m (the pipeline's between-rows margins): the re-solved corner every time (A 1.25 m past the
    junction when B is back on it, moving with the margin by about the margin), never the search's corner
    (A 0.119 m past it), which the speeds of mm/s had returned for some margins and not for others."""
    track = _track("y_junction")
    start, goal = ((1, 1.5), (2, 2.0)), ((2, 2.5), (1, 1.0))
    corners = []
    for m in np.geomspace(1e-9, 1e-3, 13):
        w = np.asarray(plan_graph(track, start, goal, 0.05 + m, "fastest", (v, v)).route_waypoints)
        assert w.shape == (5, 2), w
        corners.append(w[3])
    c = np.array(corners)
    print(v, c.tolist())
    assert np.all(np.abs(c[:, 0] - 2.75) < 1e-4), c
    assert np.max(np.abs(np.diff(c, axis=0))) < 1e-2, c


@pytest.mark.parametrize("lean", ["DROP_IMPLIED_ROWS", "ACTIVE_SET_SEED"])
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    name=st.sampled_from(("passing_loop", "two_sidings", "y_junction", "theta", "warehouse")),
    fr=st.lists(st.floats(0.0, 1.0), min_size=4, max_size=4),
    edges=st.lists(st.integers(0, 200), min_size=4, max_size=4),
    dfrac=st.sampled_from((0.05, 0.2, 0.5, 1.0)),
    swap=st.booleans(),
    speeds=st.sampled_from(((1.0, 1.0), (1.0, 0.37), (0.6, 1.0))),
)
def test_the_lean_programme_gives_the_same_corners(
    lean: str, name: str, fr: list[float], edges: list[int], dfrac: float, swap: bool, speeds: tuple[float, float]
) -> None:
    """The programme without the rows that others imply (``DROP_IMPLIED_ROWS``), or solved first from the rows tight
    at the chain's own corners (``ACTIVE_SET_SEED``), has the same minimiser as the one solved with every row: the
    same cells, corners within rounding (1e-9 m), the same choice among the widened chains."""
    got = _generated_query(name, fr, edges, dfrac, swap)
    if got is None:
        return
    track, fs, start, goal, D = got
    try:
        fs, segs = _search_segments(track, D, start, goal)
    except NoMotionError:  # pragma: no cover - same component
        pytest.fail("no motion")
    assert getattr(corners_module, lean) is True
    got_lean = resolve_corners(fs, segs, speeds)
    try:
        setattr(corners_module, lean, False)
        full = resolve_corners(fs, segs, speeds)
    finally:
        setattr(corners_module, lean, True)
    assert [x[0] for x in got_lean] == [x[0] for x in full], (name, start, goal, D, speeds)
    pa = np.array([[*x[1], *x[2]] for x in got_lean])
    pb = np.array([[*x[1], *x[2]] for x in full])
    assert np.max(np.abs(pa - pb), initial=0.0) <= 1e-9, (name, start, goal, D, speeds)


@settings(max_examples=400, deadline=None)
@given(
    m=st.integers(1, 30),
    k=st.integers(1, 8),
    seed=st.integers(0, 2**32 - 1),
    keep=st.floats(0.0, 1.0),
)
def test_least_distance_from_a_subset_of_the_rows_is_the_whole_programmes(
    m: int, k: int, seed: int, keep: float
) -> None:
    """Random least-distance programmes (feasible and not, rows often tight at the minimiser), solved from a random
    subset of their rows: the same minimiser as with every row (1e-9), infeasible exactly when that is."""
    rng = np.random.default_rng(seed)
    g = rng.normal(size=(m, k))
    h = rng.normal(size=m) + (1.0 if rng.random() < 0.3 else 0.0)
    if m > 2 and rng.random() < 0.3:  # a row repeated and its negation: equalities, degenerate multipliers
        g[1], h[1] = -g[0], -h[0]
        g[2], h[2] = g[0], h[0]
    full = corners_module._least_distance(g, h, None)
    part = corners_module._least_distance(g, h, rng.random(m) < keep)
    assert (full is None) == (part is None), (m, k, seed, keep, full, part)
    if full is not None and part is not None:
        assert np.all(g @ part >= h - 1e-9), (m, k, seed, keep)
        assert np.max(np.abs(full - part)) <= 1e-9 * max(1.0, float(np.max(np.abs(full)))), (m, k, seed, keep)


def test_least_distance_solves_every_row_when_a_subsets_solve_stops(monkeypatch: pytest.MonkeyPatch) -> None:
    """The iteration limit hit on a subset of the rows: the whole programme is solved, with the same minimiser."""
    rng = np.random.default_rng(3)
    g = rng.normal(size=(12, 4))
    h = g @ rng.normal(size=4) - rng.random(12) * (rng.random(12) < 0.5)  # feasible, half the rows tight there
    full = corners_module._least_distance(g, h, None)
    assert full is not None
    real = corners_module.nnls

    def stops_on_subsets(a: np.ndarray, b: np.ndarray, maxiter: int | None = None) -> object:
        if a.shape[1] < len(h):
            raise RuntimeError("iteration limit")
        return real(a, b, maxiter=maxiter)

    monkeypatch.setattr(corners_module, "nnls", stops_on_subsets)
    got = corners_module._least_distance(g, h, np.arange(12) < 5)
    assert got is not None and np.array_equal(got, full)
