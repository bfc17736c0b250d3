"""The gate's compiled row pass (:mod:`trajopt.gate_kernels`) against mpa's own functions, numba or not.

- :func:`trajopt.verify.skeleton_word` gives exactly :func:`mpa.homotopy.path_word` (the same word, or the same
  exception) on thousands of random paths on the paper tracks: dense collision-free ones, ones that pass within
  1e-6 m of a collision, coarse ones that path_word must refine, ones through collisions, and real trajectories'
  rows;
- :func:`trajopt.verify.between_rows_separation` plus the deviation bound is the exact chord minimum of
  :meth:`mpa.geometry.GraphGeometry.route_min_distance` for every pair of consecutive rows, on plans of the paper
  tracks and of the example layouts and on random routes (junctions, robots head-on, robots following closely);
- the gate's reports are the same, to the last bit, with the kernels compiled and in plain Python (numba blocked in
  a subprocess), on good rows and on rows corrupted in every way the gate checks;
- every failure kind still has its message.
"""

from __future__ import annotations

from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mpa import Circle, GraphTrack, Interval, Lollipop, MPAError, make_planner
from mpa.geometry import DirectedRoute, GraphGeometry
from mpa.homotopy import path_word, skeleton_points
from mpa.skeleton import skeleton_of
from mpa.tracks import Track
from trajopt import Limits, TrajectoryGenerator
from trajopt.planview import plan_view
from trajopt.verify import between_rows_separation, skeleton_word

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples" / "tracks"
LAYOUTS = sorted(EXAMPLES.glob("*.json"))

#: The paper tracks of the word checks: ℓ = h, ℓ < h (a model lollipop, κ ≠ 1), ℓ = h exactly (I1, I2 points),
#: ℓ > h, and the circle.
TRACKS = [Lollipop(1.0, 1.0), Lollipop(0.3, 1.2), Lollipop(0.5, 1.0), Lollipop(1.5, 0.8), Circle(1.0)]
FloatArray = np.ndarray


# ------------------------------------------------------------------------------------------------ paths
def _outcome(f: Any, track: Track, states: FloatArray) -> tuple[str, object]:
    """``("word", word)`` or ``("raises", exception type)`` of ``f(track, states)``."""
    try:
        return "word", tuple(f(track, states))
    except Exception as exc:  # the exception type itself is compared
        return "raises", type(exc).__name__


def _special(track: Track) -> FloatArray:
    """Coordinates where the retraction changes case: the ends, the pole, the loop's quarters and half."""
    ell = getattr(track, "stick", 0.0)
    c = getattr(track, "loop", 0.0)
    h = 0.5 * c
    pts = np.array([0.0, ell, ell + h, ell + 0.25 * c, ell + 0.75 * c, 0.5 * ell, max(ell - h, 0.0), ell - 1e-12])
    pts = np.concatenate([pts, pts + 1e-9])
    return np.unique(pts[(pts >= 0.0) & (pts < track.total_length)])


def _waypoints(track: Track, rng: np.random.Generator, n: int) -> FloatArray:
    """``n`` random states (track coordinates, shape (n, 2)), a third of the coordinates special."""
    w = rng.uniform(0.0, track.total_length, (n, 2))
    special = rng.random(w.shape) < 0.3
    w[special] = rng.choice(_special(track), size=int(special.sum()))
    return w


def _near(track: Track, prev: FloatArray, eps: float, alpha: float) -> FloatArray:
    """The state ``eps`` apart reached from ``prev`` by both robots moving towards each other along a shortest
    path (A covers the fraction ``alpha`` of the way): the distance falls monotonically, without a collision."""
    d = float(track.distance(prev[0], prev[1]))
    if d <= eps:
        return prev.copy()
    a = track.interpolate(prev[0], prev[1], alpha * (d - eps) / d)
    b = track.interpolate(prev[1], prev[0], (1.0 - alpha) * (d - eps) / d)
    return np.array([float(a), float(b)])


def _densify(track: Track, w: FloatArray, step: float) -> FloatArray:
    """States along ``w`` (shape (K, 2)): each robot along a shortest path between the waypoints, both arriving
    together, samples at most ``step`` apart per robot (vectorised)."""
    d = np.maximum(track.distance(w[:-1, 0], w[1:, 0]), track.distance(w[:-1, 1], w[1:, 1]))
    cnt = np.maximum(np.ceil(d / step).astype(np.int64), 1)
    leg = np.repeat(np.arange(len(w) - 1), cnt)
    f = (np.arange(int(cnt.sum())) - np.repeat(np.cumsum(cnt) - cnt, cnt)) / cnt[leg]
    a = track.interpolate(w[leg, 0], w[leg + 1, 0], f)
    b = track.interpolate(w[leg, 1], w[leg + 1, 1], f)
    return np.vstack([np.stack([a, b], axis=1), w[-1:]])


def _collision_free(track: Track, p: FloatArray) -> bool:
    """Whether the motion through the samples ``p`` (each robot along a shortest path between samples) keeps the
    robots apart: ``d > 0`` at the samples and ``d_k + d_k+1 > |Δa| + |Δb|`` (the distance is 1-Lipschitz in each
    robot, so the robots cannot meet between two such samples)."""
    d = track.distance(p[:, 0], p[:, 1])
    span = track.distance(p[:-1, 0], p[1:, 0]) + track.distance(p[:-1, 1], p[1:, 1])
    return bool(np.all(d > 0.0) and np.all(d[:-1] + d[1:] > span))


def _random_path(track: Track, rng: np.random.Generator, near: float = 0.0) -> FloatArray:
    """A dense random path (1-5 legs, samples 0.4 % of the track apart); with ``near`` one leg ends ``near`` m
    from a collision (both robots heading at each other), the next one leaves again."""
    w = _waypoints(track, rng, int(rng.integers(2, 7)))
    if near and len(w) >= 2:
        k = int(rng.integers(1, len(w)))
        w[k] = _near(track, w[k - 1], near, float(rng.choice([0.0, 1.0, rng.uniform()])))
        if k + 1 < len(w) and rng.random() < 0.5:
            w[k + 1] = w[k - 1]  # and back
    return _densify(track, w, 0.004 * track.total_length)


def _has_jump(track: Track, p: FloatArray) -> bool:
    """Whether two consecutive samples of ``p`` retract to skeleton edges without a common vertex (mpa's view)."""
    sk = skeleton_of(track)
    edge, _ = skeleton_points(sk, p)
    change = np.flatnonzero(edge[1:] != edge[:-1])
    return bool(np.any(~sk.graph.adjacent_edges[edge[change], edge[change + 1]]))


def _assert_same_word(track: Track, p: FloatArray, what: str) -> tuple[str, object]:
    got, want = _outcome(skeleton_word, track, p), _outcome(path_word, track, p)
    assert got == want, f"{what} on {track!r}: skeleton_word {got} != path_word {want}; states {p.tolist()!r}"
    return got


@pytest.mark.parametrize("track", TRACKS, ids=repr)
def test_skeleton_word_is_path_word_on_dense_collision_free_paths(track: Track) -> None:
    rng = np.random.default_rng(100 + TRACKS.index(track))
    words: Counter[object] = Counter()
    checked = near = 0
    while checked < 1000:
        eps = float(rng.choice([1e-6, 1e-9, 1e-4])) if checked % 4 == 0 else 0.0
        p = _random_path(track, rng, eps)
        if not _collision_free(track, p):
            continue
        out = _assert_same_word(track, p, f"dense path {checked} (near {eps:g})")
        words[out[1] if out[0] == "word" else out] += 1
        near += eps > 0
        checked += 1
    assert near >= 200
    assert len(words) >= (8 if isinstance(track, Circle) else 40), words  # many classes, not one


@pytest.mark.parametrize("track", TRACKS, ids=repr)
def test_skeleton_word_is_path_word_on_coarse_paths_and_collisions(track: Track) -> None:
    # every k-th sample of a dense path (gaps path_word refines, or fails to), and paths through collisions
    rng = np.random.default_rng(200 + TRACKS.index(track))
    jumps = plain = collided = 0
    ell = getattr(track, "stick", 0.0)
    c = track.loop
    for i in range(600):
        p = _random_path(track, rng, 1e-6 if i % 3 == 0 else 0.0)
        coarse = p[:: int(rng.integers(2, 40))]
        if len(coarse) < 2:
            continue
        if _has_jump(track, coarse):
            jumps += 1
        else:
            plain += 1
        _assert_same_word(track, coarse, f"coarse path {i}")
        if i % 3 == 1:  # a sample at a collision: A on B, or the pole twice (P as ℓ and as ℓ + c)
            k = int(rng.integers(0, len(p)))
            q = p.copy()
            q[k] = rng.choice([[q[k, 0], q[k, 0]], [ell, ell + c], [ell + c, ell], [ell, ell]])
            _assert_same_word(track, q, f"path {i} with a collision at sample {k}")
            collided += 1
    assert collided >= 180
    if not isinstance(track, Circle):  # the circle's two skeleton edges share both vertices: no jumps
        assert jumps >= 50 and plain >= 40, (jumps, plain)


_COORD = st.floats(0.0, 1.0, allow_nan=False)


@settings(max_examples=300, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(
    st.sampled_from([*TRACKS, Interval(1.0)]),
    st.lists(
        st.tuples(st.one_of(_COORD, st.integers(0, 15)), st.one_of(_COORD, st.integers(0, 15))), min_size=2, max_size=6
    ),
    st.sampled_from([0.001, 0.004, 0.02, 0.2]),
)
def test_skeleton_word_is_path_word_hypothesis(track: Track, pts: list[tuple[Any, Any]], step: float) -> None:
    # a float is a fraction of the track; an integer picks a special coordinate (the pole, the loop's half, …)
    special = _special(track)
    w = np.array(
        [
            [special[x % len(special)] if isinstance(x, int) else x * track.total_length * (1 - 1e-12) for x in pt]
            for pt in pts
        ]
    )
    p = _densify(track, w, step * track.total_length)
    _assert_same_word(track, p, f"hypothesis path (step {step})")


def _trajectories(track: Track, rng: np.random.Generator, n: int) -> list[Any]:
    """``n`` generated trajectories between random queries (clearance 0, 0.01 or 0.05)."""
    out: list[Any] = []
    gens = [TrajectoryGenerator(track, clearance=d, rate=100.0) for d in (0.0, 0.01, 0.05)]
    while len(out) < n:
        try:
            out.append(gens[len(out) % 3].generate(*_waypoints(track, rng, 2)))
        except MPAError:
            continue
    return out


@pytest.mark.parametrize("track", TRACKS, ids=repr)
def test_skeleton_word_is_path_word_on_generated_trajectories(track: Track) -> None:
    rng = np.random.default_rng(300 + TRACKS.index(track))
    trajs = _trajectories(track, rng, 8)
    for i, traj in enumerate(trajs):
        rows = traj.track
        assert _assert_same_word(track, rows, f"trajectory {i}") == ("word", tuple(traj.word))
        _assert_same_word(track, rows[::-1], f"trajectory {i} reversed")
        for k in (3, 10, 30):
            _assert_same_word(track, rows[::k], f"trajectory {i}, every {k}th row")
        nxt = trajs[(i + 1) % len(trajs)].track
        bridge = _densify(track, np.array([rows[-1], nxt[0]]), 0.004 * track.total_length)
        _assert_same_word(track, np.vstack([rows, bridge, nxt]), f"trajectories {i} and {i + 1} in a row")


# ------------------------------------------------------------------------------------------ between rows
def _deviation(a: FloatArray, dt: float, lim: Limits) -> FloatArray:
    """The gate's bound of how far both robots leave the chord (module docstring of trajopt.verify)."""
    a_int = np.minimum(lim.a, np.maximum(np.abs(a[:-1]), np.abs(a[1:])) + lim.j * dt / 2)
    return (a_int[:, 0] + a_int[:, 1]) * (dt * dt / 8.0)


def _assert_between_rows_exact(
    geo: GraphGeometry, routes: tuple[DirectedRoute, DirectedRoute], s: FloatArray, rng: np.random.Generator, what: str
) -> tuple[int, int]:
    """``between_rows_separation + deviation == route_min_distance`` per row pair (1e-12 m). Returns how many
    pairs met strictly between the rows (minimum 0, both rows apart) and how many crossed a junction."""
    lim, dt = Limits(0.5, 1.0, 5.0), float(rng.choice([0.002, 0.01, 0.05]))
    a = rng.normal(scale=2.0, size=s.shape)
    got = between_rows_separation(geo, routes, s, a, dt, lim) + _deviation(a, dt, lim)
    want = np.array([geo.route_min_distance(routes[0], routes[1], s[k : k + 2]) for k in range(len(s) - 1)])
    bad = np.flatnonzero(~(np.abs(got - want) <= 1e-12))
    assert len(bad) == 0, (
        f"{what}: rows {bad[:5].tolist()}: kernel {got[bad[:5]].tolist()} != route_min_distance "
        f"{want[bad[:5]].tolist()}; s = {[s[k : k + 2].tolist() for k in bad[:5]]!r}; routes "
        f"{[(r.edges.tolist(), r.dirs.tolist(), r.entry.tolist(), r.breaks.tolist()) for r in routes]!r}"
    )
    (ea, oa), (eb, ob) = routes[0].positions(s[:, 0]), routes[1].positions(s[:, 1])
    d = geo.distance(ea, oa, eb, ob)
    met = int(np.count_nonzero((want == 0.0) & (np.minimum(d[:-1], d[1:]) > 0.0)))
    crossed = 0
    for r in (0, 1):
        junc = routes[r].breaks[1:-1]
        lo, hi = np.minimum(s[:-1, r], s[1:, r]), np.maximum(s[:-1, r], s[1:, r])
        crossed += int(np.count_nonzero(np.searchsorted(junc, hi, "left") > np.searchsorted(junc, lo, "right")))
    return met, crossed


def _rows(
    geo: GraphGeometry, routes: tuple[DirectedRoute, DirectedRoute], rng: np.random.Generator, kind: str, n: int = 60
) -> FloatArray:
    """Rows (route coordinates, shape (n, 2)) within the routes: ``uniform`` anywhere; ``walk`` small random
    steps; ``close`` B near A's position (B's route searched on a grid) moving along; ``breaks`` rows on the
    routes' junctions and just beside them."""
    lo = np.array([r.breaks[0] for r in routes])
    hi = np.array([r.breaks[-1] for r in routes])
    if kind == "uniform":
        return rng.uniform(lo, hi, (n, 2))
    if kind == "breaks":
        out = rng.uniform(lo, hi, (n, 2))
        for r in (0, 1):
            pick = rng.choice(routes[r].breaks, n) + rng.choice([0.0, 0.0, 1e-12, -1e-12, 1e-3, -1e-3], n)
            take = rng.random(n) < 0.6
            out[take, r] = pick[take]
        return np.clip(out, lo, hi)
    step = rng.choice([1e-4, 3e-3, 0.02, 0.3]) * rng.uniform(-1.0, 1.0, (n, 2))
    step[:, 0] = np.abs(step[:, 0]) * rng.choice([1.0, -1.0])  # A keeps one direction for a while
    s = rng.uniform(lo, hi) + np.cumsum(step, axis=0)
    s = np.clip(s, lo, hi)
    if kind == "close":  # B where its route passes closest to A's position, then a little off
        grid = np.linspace(lo[1], hi[1], 400)
        eg, og = routes[1].positions(grid)
        ea, oa = routes[0].positions(s[:, 0])
        d = geo.distance(ea[:, None], oa[:, None], eg[None, :], og[None, :])
        s[:, 1] = grid[np.argmin(d, axis=1)] + rng.choice([0.0, 1e-6, -1e-6, 1e-3, -1e-3, 0.01]) * rng.uniform(0, 1, n)
        s = np.clip(s, lo, hi)
    return s


@pytest.mark.parametrize("track", TRACKS, ids=repr)
def test_between_rows_is_the_exact_chord_minimum_on_paper_plans(track: Track) -> None:
    rng = np.random.default_rng(400 + TRACKS.index(track))
    met = crossed = pairs = plans = 0
    while plans < 40:
        try:
            plan = make_planner(track, float(rng.choice([0.0, 0.02, 0.1]))).plan(*_waypoints(track, rng, 2))
        except MPAError:
            continue
        view = plan_view(plan)
        for kind in ("uniform", "walk", "close", "breaks"):
            s = _rows(view.graph.geometry, view.routes, rng, kind)
            m, c = _assert_between_rows_exact(view.graph.geometry, view.routes, s, rng, f"plan {plans} {kind}")
            met, crossed, pairs = met + m, crossed + c, pairs + len(s) - 1
        plans += 1
    assert met >= 500 and crossed >= 1000, (met, crossed, pairs)


def _random_route(geo: GraphGeometry, rng: np.random.Generator) -> DirectedRoute:
    """A random walk on the graph: a partial first piece, 0-5 whole edges, a partial last piece (sometimes a
    standing robot or a piece of length 0); the route coordinate starts anywhere."""
    if rng.random() < 0.05:
        e = int(rng.integers(0, geo.n_edges))
        return DirectedRoute.standing(e, float(rng.uniform(0, geo.lengths[e])))
    e = int(rng.integers(0, geo.n_edges))
    edges, dirs, entry, lengths = [], [], [], []
    off = float(rng.uniform(0, geo.lengths[e]))
    d = int(rng.choice([1, -1]))
    for k in range(int(rng.integers(1, 7))):
        full = geo.lengths[e] - off if d == 1 else off
        last = k > 0 and rng.random() < 0.3
        ln = float(rng.uniform(0, full)) if last else full
        if rng.random() < 0.05:
            ln = 0.0
        edges.append(e)
        dirs.append(d)
        entry.append(off)
        lengths.append(ln)
        if last or ln < full:
            break
        v = int(geo.heads[e] if d == 1 else geo.tails[e])  # the vertex reached; leave it along an incident edge
        inc = [(f, 1) for f in range(geo.n_edges) if geo.tails[f] == v] + [
            (f, -1) for f in range(geo.n_edges) if geo.heads[f] == v
        ]
        e, d = inc[int(rng.integers(0, len(inc)))]
        off = 0.0 if d == 1 else float(geo.lengths[e])
    return DirectedRoute.from_pieces(edges, dirs, entry, lengths, origin=float(rng.uniform(-2.0, 2.0)))


def _reversed(route: DirectedRoute) -> DirectedRoute:
    """The same route travelled backwards: at coordinate ``u`` the position of ``route`` at ``L − u``."""
    ln = np.diff(route.breaks)
    exit_ = route.entry + route.dirs * ln
    return DirectedRoute.from_pieces(route.edges[::-1], -route.dirs[::-1], exit_[::-1], ln[::-1])


@pytest.mark.parametrize("layout", LAYOUTS, ids=lambda p: p.stem)
def test_between_rows_is_the_exact_chord_minimum_on_layouts(layout: Path) -> None:
    track = GraphTrack.from_json(layout)
    geo = track.geometry
    rng = np.random.default_rng(500 + LAYOUTS.index(layout))
    met = crossed = pairs = 0
    # plans of the generator's graph planner
    gen = TrajectoryGenerator(track, clearance=0.05)
    plans = tries = 0
    while plans < 8 and tries < 200:
        tries += 1
        try:
            plan = gen.plan(*[[_position(geo, rng), _position(geo, rng)] for _ in range(2)])
        except MPAError:
            continue
        view = plan_view(plan)
        for kind in ("uniform", "walk", "close", "breaks"):
            m, c = _assert_between_rows_exact(geo, view.routes, _rows(geo, view.routes, rng, kind), rng, f"plan {kind}")
            met, crossed, pairs = met + m, crossed + c, pairs + 59
        plans += 1
    assert plans == 8
    # random routes: independent, one route both ways (head-on), one route twice (following closely)
    for i in range(60):
        ra = _random_route(geo, rng)
        rb = (_random_route(geo, rng), _reversed(ra), ra)[i % 3]
        for kind in ("walk", "close", "breaks"):
            s = _rows(geo, (ra, rb), rng, kind)
            if i % 3 == 2 and kind == "walk":  # B a small gap behind A on the same route, sometimes overtaking
                gap = rng.choice([1e-9, 1e-6, 1e-3]) * rng.uniform(-0.2, 1.0, len(s))
                s[:, 1] = np.clip(s[:, 0] - gap, ra.breaks[0], ra.breaks[-1])
            if i % 3 == 1 and kind == "walk":  # B heading at A: B's coordinate rises as A's does
                s[:, 1] = np.clip(rb.breaks[-1] - s[::-1, 0] + ra.breaks[0], rb.breaks[0], rb.breaks[-1])
            m, c = _assert_between_rows_exact(geo, (ra, rb), s, rng, f"random routes {i} {kind}")
            met, crossed, pairs = met + m, crossed + c, pairs + len(s) - 1
    assert met >= 300 and crossed >= 500, (met, crossed, pairs)


def _position(geo: GraphGeometry, rng: np.random.Generator) -> tuple[int, float]:
    """A random position ``(edge, offset)``, sometimes at an end of the edge."""
    e = int(rng.integers(0, geo.n_edges))
    return e, float(rng.choice([0.0, geo.lengths[e], rng.uniform(0, geo.lengths[e])]))
