"""The gate's compiled row pass (:mod:`trajopt.verify.kernels`) against mpa's own functions, numba or not.

- :func:`trajopt.verify.gate.skeleton_word` gives exactly :func:`mpa.homotopy.path_word` (the same word, or the same
  exception) on thousands of random paths on the paper tracks: dense collision-free ones, ones that pass within
  1e-6 m of a collision, coarse ones that path_word must refine, ones through collisions, and real trajectories'
  rows;
- :func:`trajopt.verify.gate.between_rows_separation` plus the deviation bound is the exact chord minimum of
  :meth:`mpa.geometry.GraphGeometry.route_min_distance` for every pair of consecutive rows, on plans of the paper
  tracks and of the example layouts and on random routes (junctions, robots head-on, robots following closely);
- the gate's reports are the same, to the last bit, with the kernels compiled and in plain Python (numba blocked in
  a subprocess), on good rows and on rows corrupted in every way the gate checks;
- every failure kind still has its message.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
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
from mpa.routes import directed_route
from mpa.skeleton import skeleton_of
from mpa.tracks import Track
from trajopt import Limits, TrajectoryGenerator
from trajopt.path.planview import plan_view
from trajopt.verify.gate import between_rows_separation, skeleton_word, verify_graph_setpoints, verify_setpoints

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples" / "tracks"
LAYOUTS = sorted(EXAMPLES.glob("*.json"))

#: The paper tracks of the word checks: ℓ = h, ℓ < h (a model lollipop, κ ≠ 1), ℓ = h exactly (I1, I2 points),
#: ℓ > h, and the circle.
TRACKS = [Lollipop(1.0, 1.0), Lollipop(0.3, 1.2), Lollipop(0.5, 1.0), Lollipop(1.5, 0.8), Circle(1.0)]
#: The two path-word comparisons (1 500 dense and 900 coarse paths a track, 4-7 s each) on three of the tracks in CI's
#: default run; on the other two with ``-m slow`` (the suite's ten minutes).
PATH_TRACKS = [
    pytest.param(t, marks=pytest.mark.slow) if t in (Lollipop(0.5, 1.0), Lollipop(1.5, 0.8)) else t for t in TRACKS
]
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
    """A dense random path (1-6 legs, samples 0.4 % of the track apart); with ``near`` one leg ends ``near`` m
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


@pytest.mark.parametrize("track", PATH_TRACKS, ids=repr)
def test_skeleton_word_is_path_word_on_dense_collision_free_paths(track: Track) -> None:
    rng = np.random.default_rng(100 + TRACKS.index(track))
    words: Counter[object] = Counter()
    checked = near = 0
    while checked < 1500:
        eps = float(rng.choice([1e-6, 1e-9, 1e-4])) if checked % 4 == 0 else 0.0
        p = _random_path(track, rng, eps)
        if not _collision_free(track, p):
            continue
        out = _assert_same_word(track, p, f"dense path {checked} (near {eps:g})")
        words[out[1] if out[0] == "word" else out] += 1
        near += eps > 0
        checked += 1
    assert near >= 300
    assert len(words) >= (8 if isinstance(track, Circle) else 40), words  # many classes, not one


@pytest.mark.parametrize("track", PATH_TRACKS, ids=repr)
def test_skeleton_word_is_path_word_on_coarse_paths_and_collisions(track: Track) -> None:
    # every k-th sample of a dense path (gaps path_word refines, or fails to), and paths through collisions
    rng = np.random.default_rng(200 + TRACKS.index(track))
    jumps = plain = collided = 0
    ell = getattr(track, "stick", 0.0)
    c = track.loop
    for i in range(900):
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
    assert collided >= 270
    if not isinstance(track, Circle):  # the circle's two skeleton edges share both vertices: no jumps
        assert jumps >= 80 and plain >= 60, (jumps, plain)


_COORD = st.floats(0.0, 1.0, allow_nan=False)


@settings(max_examples=500, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
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
    """The gate's bound of how far both robots leave the chord (module docstring of trajopt.verify.gate)."""
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


# ------------------------------------------------------------------------------------ numba or not
#: Run in a subprocess with numba blocked: the gate on the cases of ``argv[1]`` (JSON) and ``argv[2]`` (.npz),
#: each report's ``to_dict()`` as JSON (or the exception raised) into ``argv[3]``.
_PLAIN_PYTHON_GATE = r"""
import json, sys
sys.modules["numba"] = None  # import numba fails: trajopt.verify.kernels runs as plain Python
import numpy as np
import trajopt.verify.kernels as gk
from tests.trajopt.test_gate_kernels import run_gate_cases
assert not hasattr(gk.check_rows, "py_func"), "numba was not blocked"
meta = json.loads(open(sys.argv[1]).read())
with np.load(sys.argv[2]) as z:
    arrays = {k: z[k] for k in z.files}
open(sys.argv[3], "w").write(json.dumps(run_gate_cases(meta, arrays)))
"""

_PAPER_GATE_TRACKS = {"lollipop": Lollipop, "circle": Circle}
_FIELDS = ("t", "track", "edges", "offsets", "s", "v", "a", "j")


def _paper_track(spec: list[Any]) -> Track:
    return _PAPER_GATE_TRACKS[spec[0]](*spec[1:])


def run_gate_cases(meta: list[dict[str, Any]], arrays: dict[str, FloatArray]) -> list[list[Any]]:
    """The gate on every case: ``[report.to_dict() as JSON or "raises …", the routes' fingerprint]``.

    A paper case's plan is made again from its query (the planner is deterministic; the fingerprint, the routes'
    pieces and the plan's word, shows it is the same plan); a layout case carries its routes.
    """
    out: list[list[Any]] = []
    plans: dict[str, Any] = {}
    for i, case in enumerate(meta):
        x = {f: arrays[f"{i}_{f}"] for f in _FIELDS if f"{i}_{f}" in arrays}
        lim = Limits(*case["limits"])
        kw = {"limits": lim, "clearance": case["clearance"], "rate": case["rate"]}
        if case["kind"] == "paper":
            key = json.dumps([case["track"], case["plan_clearance"], case["query"]])
            if key not in plans:
                track = _paper_track(case["track"])
                plans[key] = make_planner(track, case["plan_clearance"]).plan(*case["query"])
            plan = plans[key]
            finger = [[directed_route(r).pieces_list for r in plan.routes], list(plan.word)]
            args: tuple[Any, ...] = (plan.track, plan.routes, x["t"], x["track"])
            kw.update(start=plan.start, goal=plan.goal, word=case["word"])
            gate: Any = verify_setpoints
        else:
            geo = GraphTrack.from_json(EXAMPLES / case["layout"]).geometry
            routes = tuple(
                DirectedRoute(*(arrays[f"{i}_route{r}_{k}"] for k in ("edges", "dirs", "entry", "breaks")))
                for r in range(2)
            )
            finger = []
            args = (geo, routes, x["t"], x["edges"], x["offsets"])
            kw.update(start=tuple(map(tuple, case["start"])), goal=tuple(map(tuple, case["goal"])))
            gate = verify_graph_setpoints
        try:
            rep = json.dumps(gate(*args, x["s"], x["v"], x["a"], x["j"], **kw).to_dict(), sort_keys=True)
        except Exception as exc:  # the exception type itself is compared
            rep = f"raises {type(exc).__name__}: {exc}"
        out.append([rep, finger])
    return json.loads(json.dumps(out))  # as the subprocess returns it


def _gate_bases(rng: np.random.Generator) -> list[tuple[dict[str, Any], dict[str, FloatArray], Any]]:
    """Good rows of real trajectories (25 Hz, a few hundred rows at most): ``(meta, arrays, trajectory)``."""
    out = []
    lim = Limits([0.5, 0.6], [1.0, 1.5], [5.0, 4.0])
    for track, spec in (
        (Lollipop(1.0, 1.0), ["lollipop", 1.0, 1.0]),
        (Lollipop(0.3, 1.2), ["lollipop", 0.3, 1.2]),
        (Lollipop(1.5, 0.8), ["lollipop", 1.5, 0.8]),
        (Circle(1.0), ["circle", 1.0]),
    ):
        gen = TrajectoryGenerator(track, clearance=0.05, limits=lim, rate=25.0)
        while sum(m["track"] == spec for m, _, _ in out) < 2:
            query = _waypoints(track, rng, 2).tolist()
            try:
                traj = gen.generate(*query)
            except MPAError:
                continue
            meta = {"kind": "paper", "track": spec, "plan_clearance": traj.clearance, "query": query}
            meta["word"] = list(traj.plan.word)
            arrays = {f: getattr(traj, f) for f in ("t", "track", "s", "v", "a", "j")}
            out.append((meta, arrays, traj))
    for layout in ("y_junction.json", "passing_loop.json", "theta.json", "warehouse.json"):
        graph = GraphTrack.from_json(EXAMPLES / layout)
        gen = TrajectoryGenerator(graph, clearance=0.05, limits=lim, rate=25.0)
        n = 0
        while n < 2:
            try:
                traj = gen.generate(*[[_position(graph.geometry, rng), _position(graph.geometry, rng)] for _ in "ab"])
            except MPAError:
                continue
            plan = traj.plan
            meta = {"kind": "graph", "layout": layout, "start": plan.start, "goal": plan.goal}
            arrays = {f: getattr(traj, f) for f in ("t", "s", "v", "a", "j", "edges", "offsets")}
            for r, route in enumerate((plan.route_a, plan.route_b)):
                for k in ("edges", "dirs", "entry", "breaks"):
                    arrays[f"route{r}_{k}"] = getattr(route, k)
            out.append((meta, arrays, traj))
            n += 1
    for meta, _, traj in out:
        meta.update(limits=[traj.limits.v.tolist(), traj.limits.a.tolist(), traj.limits.j.tolist()])
        meta.update(clearance=traj.clearance, rate=traj.rate)
    return out


def _variants(
    meta: dict[str, Any], arrays: dict[str, FloatArray], traj: Any, good: dict[str, Any], rng: np.random.Generator
) -> list[tuple[str, dict[str, Any], dict[str, FloatArray], str | None]]:
    """Copies of one good case, each broken in one way: ``(kind, meta, arrays, expected failure message part)``."""
    out: list[tuple[str, dict[str, Any], dict[str, FloatArray], str | None]] = []
    graph = meta["kind"] == "graph"
    n = len(arrays["t"])
    view = plan_view(traj.plan)
    pos_field = "offsets" if graph else "track"

    def add(kind: str, expect: str | None, meta_changes: dict[str, Any] | None = None, **changes: Any) -> None:
        arr = {k: np.array(v, copy=True) for k, v in arrays.items()}
        arr.update(changes)
        out.append((kind, {**meta, **(meta_changes or {})}, arr, expect))

    def row() -> tuple[int, int]:
        return int(rng.integers(0, n)), int(rng.integers(0, 2))

    def moved_row(k: int) -> dict[str, FloatArray]:
        # row k moved along the routes (still consistent with them)
        s = arrays["s"].copy()
        mag = float(rng.choice([0.01, 0.1]))
        s[k] = np.where(s[k] + mag <= view.upper, s[k] + mag, np.maximum(s[k] - mag, view.lower))
        if graph:
            e, o = view.positions(s, arrays["v"])
            return {"s": s, "edges": e, "offsets": o}
        return {"s": s, "track": view.track_coordinates(s)}

    add("good", None)
    for _ in range(2):
        for kind, value in (("nan", np.nan), ("inf", float(rng.choice([np.inf, -np.inf])))):
            field = str(rng.choice(["t", pos_field, "s", "v", "a", "j"]))
            x = arrays[field].copy()
            k, r = row()
            x[(k, r) if x.ndim == 2 else k] = value
            add(kind, "non-finite values in the setpoints", **{field: x})
        for q in "vaj":
            k, r = row()
            x = arrays[q].copy()
            lim = {"v": traj.limits.v, "a": traj.limits.a, "j": traj.limits.j}[q][r]
            over = float(rng.choice([1e-7, 1e-4, 0.3]))
            x[k, r] = float(rng.choice([-1.0, 1.0])) * lim * (1.0 + over)
            add(f"limit {q}", f"|{q}| of robot {'AB'[r]}" if over > 1e-6 else None, **{q: x})
        k, r = row()
        x = arrays[pos_field].copy()
        delta = float(rng.choice([-1.0, 1.0]) * rng.choice([1e-3, 0.05]))
        if graph:
            hi = float(traj.plan.track.lengths[arrays["edges"][k, r]])
        else:
            hi = traj.plan.track.total_length - 1e-6
        if abs(np.clip(x[k, r] + delta, 0.0, hi) - x[k, r]) > 1e-6:
            x[k, r] = np.clip(x[k, r] + delta, 0.0, hi)
            add("off route", "is not route.position(s)", **{pos_field: x})
        add("first row", "first row is", **moved_row(0))
        add("last row", "last row is", **moved_row(n - 1))
        k, r = row()
        t = arrays["t"].copy()
        t[k] += float(rng.choice([1e-4, -1e-6]))
        add("time grid", "time grid is not", t=t)
    for end, k in (("first", 0), ("last", n - 1)):
        q = str(rng.choice(["v", "a"]))
        x = arrays[q].copy()
        x[k, int(rng.integers(0, 2))] = float(rng.choice([1e-3, -1e-6]))
        add(f"{end} not at rest", f"{end} row is not at rest", **{q: x})
    add("time grid", "time grid is not", t=arrays["t"] * 1.001)
    add("rate", "time grid is not", {"rate": meta["rate"] * 2.0})
    field = str(rng.choice(["t", pos_field, "s", "v", "a", "j"]))
    add("shapes", "arrays have inconsistent shapes", **{field: arrays[field][:-1]})
    dmin, bmin = good["min_separation"], good["min_separation_between"]
    add("too close at the rows", "below the clearance", {"clearance": dmin * 1.01 + 1e-6})
    if bmin < dmin - 1e-8:
        add("too close between rows", "separation between rows may drop", {"clearance": 0.5 * (bmin + dmin)})
    if graph:
        k, r = row()
        e = arrays["edges"].copy()
        e[k, r] = int(rng.choice([-1, len(traj.plan.track.lengths), 10**6]))
        add("edge index", "edge indices out of range", edges=e)
        add("float edges", "edge indices out of range", edges=arrays["edges"].astype(float))
    else:
        add("word", "homotopy class", {"word": [*meta["word"], "+S1a"] if meta["word"] != ["+S1a"] else []})
        k, r = row()
        x = arrays["track"].copy()
        x[k, r] = float(rng.choice([-0.1, traj.plan.track.total_length + 0.1]))
        add("off the track", None, track=x)
    return out


def _gate_cases() -> tuple[list[dict[str, Any]], dict[str, FloatArray], list[tuple[str, str | None]], list[Any]]:
    """Every case of the numba-or-not comparison: meta (JSON), arrays (.npz), ``(kind, expected)``, trajectories."""
    rng = np.random.default_rng(600)
    metas: list[dict[str, Any]] = []
    arrays: dict[str, FloatArray] = {}
    kinds: list[tuple[str, str | None]] = []
    trajs: list[Any] = []

    for meta, arr, traj in _gate_bases(rng):
        good = json.loads(run_gate_cases([meta], {f"0_{k}": v for k, v in arr.items()})[0][0])
        for kind, m, a, expect in _variants(meta, arr, traj, good, rng):
            arrays.update({f"{len(metas)}_{k}": v for k, v in a.items()})
            metas.append(m)
            kinds.append((kind, expect))
            trajs.append(traj)
    return metas, arrays, kinds, trajs


@pytest.fixture(scope="module")
def gate_cases() -> tuple[list[dict[str, Any]], dict[str, FloatArray], list[tuple[str, str | None]], list[Any]]:
    return _gate_cases()


def test_gate_reports_are_the_same_with_and_without_numba(gate_cases: Any, tmp_path: Path) -> None:
    pytest.importorskip("numba")
    import trajopt.verify.kernels as gk

    assert hasattr(gk.check_rows, "py_func")  # compiled here
    metas, arrays, kinds, trajs = gate_cases
    assert len(metas) >= 300
    (tmp_path / "cases.json").write_text(json.dumps(metas))
    np.savez(tmp_path / "cases.npz", **arrays)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    files = [str(tmp_path / x) for x in ("cases.json", "cases.npz", "reports.json")]
    done = subprocess.run(
        [sys.executable, "-c", _PLAIN_PYTHON_GATE, *files], env=env, capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stderr[-3000:]
    plain = json.loads((tmp_path / "reports.json").read_text())
    compiled = run_gate_cases(metas, arrays)
    assert len(plain) == len(compiled) == len(metas)
    for i, (kind, _) in enumerate(kinds):
        assert compiled[i] == plain[i], f"case {i} ({kind}, {metas[i]}): compiled {compiled[i]} != plain {plain[i]}"
        if metas[i]["kind"] == "paper":  # the plan made again is the trajectory's
            plan = trajs[i].plan
            finger = [[list(directed_route(r).pieces_list) for r in plan.routes], list(plan.word)]
            assert compiled[i][1] == finger, (i, kind)
    outcomes = Counter(json.loads(c[0])["ok"] if c[0].startswith("{") else c[0] for c in compiled)
    assert outcomes[True] >= 16 and outcomes[False] >= 250, outcomes


def test_every_failure_kind_has_its_message(gate_cases: Any) -> None:
    metas, arrays, kinds, _ = gate_cases
    reports = run_gate_cases(metas, arrays)
    seen: Counter[str] = Counter()
    for i, (kind, expect) in enumerate(kinds):
        rep = json.loads(reports[i][0])
        if kind == "good":
            assert rep["ok"], (i, rep)
        if expect is not None:
            assert not rep["ok"] and any(expect in f for f in rep["failures"]), (i, kind, expect, rep["failures"])
            seen[kind] += 1
    assert set(seen) >= {
        "nan",
        "inf",
        "limit v",
        "limit a",
        "limit j",
        "off route",
        "first row",
        "last row",
        "time grid",
        "first not at rest",
        "last not at rest",
        "rate",
        "shapes",
        "too close at the rows",
        "too close between rows",
        "edge index",
        "float edges",
        "word",
    }, seen


def test_non_finite_values_are_reported_before_float_edge_indices() -> None:
    # the kernel reports non-finite values before edge indices; float edges are caught before it: same order
    from mpa.geometry import DirectedRoute, GraphGeometry
    from trajopt import Limits
    from trajopt.verify.gate import verify_graph_setpoints

    geo = GraphGeometry(2, [0], [1], [1.0])
    route = DirectedRoute.from_pieces([0], [1], [0.0], [1.0])
    z = np.zeros((3, 2))
    s = np.array([[0.1, 0.8], [0.1, 0.8], [0.1, 0.8]])
    args = dict(limits=Limits(), clearance=0.05, start=((0, 0.1), (0, 0.8)), goal=((0, 0.1), (0, 0.8)), rate=100.0)
    t = np.arange(3) / 100.0
    for edges, off, want in (
        (np.zeros((3, 2)), s.copy(), "edge indices out of range"),
        (np.zeros((3, 2)), np.where([[True, False], [False, False], [False, False]], np.nan, s), "non-finite"),
        (
            np.zeros((3, 2), dtype=np.int64),
            np.where([[True, False], [False, False], [False, False]], np.nan, s),
            "non-finite",
        ),
    ):
        rep = verify_graph_setpoints(geo, (route, route), t, edges, off, s, z, z, z, **args)
        assert not rep.ok and rep.failures[0].startswith(want), (edges.dtype, rep.failures)
