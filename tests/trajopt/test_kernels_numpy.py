"""The numpy twins of the gate's row pass and of the sampling against the compiled kernels, bit for bit.

:mod:`trajopt.verify.kernels_numpy` (``check_rows``, ``between_rows``) and :mod:`trajopt.verify.sampling_numpy`
(``sample_rows``) stand in for the numba kernels in one-shot processes. Every output is compared with
``np.array_equal`` (NaN equal to NaN) and the sign of every zero, on

- the arguments the pipeline passes to the kernels, recorded while generating trajectories (and their margins) on
  the paper's tracks, every example layout and the Open-RMF maps, with and without clearance, among them the
  airport's 438 s motion of 43 829 rows;
- seeded random perturbations of the recorded rows (non-finite values in each array, edge indices out of range,
  broken time grids, rows moved off their routes, off the ends, over the limits, at each other, onto junctions,
  tied peaks, signed zeros, one or two rows) and of the recorded times (past the end, before the start, on the
  phases' starts and one ulp beside them, non-finite, unsorted, the path piece looked up);
- random long routes with many junctions (chords cut by one or several junctions, robots head-on and following);
- hypothesis's rows, routes, phases and paths;

and the gate's report on the good and broken cases of ``tests/trajopt/test_gate_kernels.py`` is the same with the
twins as with the kernels.
"""

from __future__ import annotations

import ast
import json
import math
import subprocess
import sys
from collections import Counter
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import trajopt.timing.scaling as scaling
import trajopt.verify.gate as gate
from mpa import Circle, GraphTrack, Interval, Lollipop, MPAError
from mpa.geometry import DirectedRoute, GraphGeometry
from tests.helpers.graph_helpers import random_layout, random_position
from tests.trajopt.test_gate_kernels import _gate_cases, _random_route, _reversed, _rows, _waypoints, run_gate_cases
from trajopt import TrajectoryGenerator
from trajopt.timing.curves import _FALLING_ARRAY
from trajopt.verify import kernels as compiled_kernels
from trajopt.verify import kernels_numpy, sampling_numpy
from trajopt.verify import sampling as compiled_sampling
from trajopt.verify.gate import LIMIT_RTOL, POSITION_TOL

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples" / "tracks"
OPENRMF = ROOT / "tests" / "data" / "openrmf"
FloatArray = np.ndarray

#: The arguments of the kernels, in order.
CHECK_ARGS = ("graph", "ra", "rb", "tt", "E", "OFF", "S", "V", "A", "J", "lims", "dt", "time_tol", "ends", "between")
SAMPLE_ARGS = ("tt", "t0", "p", "v", "a", "j", "duration", "length", "piece", "breaks", "coef", "degree", "falling")
RES_NAMES = {k: name for name, k in compiled_kernels.RES.items()}


# ------------------------------------------------------------------------------------------ comparisons
def _same(x: Any, y: Any) -> bool:
    """The same shape, dtype and values (NaN equal to NaN), and the same sign on every zero."""
    x, y = np.asarray(x), np.asarray(y)
    if x.shape != y.shape or x.dtype != y.dtype or not np.array_equal(x, y, equal_nan=x.dtype.kind == "f"):
        return False
    if x.dtype.kind != "f":
        return True
    num = ~np.isnan(x)
    return bool(np.array_equal(np.signbit(x[num]), np.signbit(y[num])))


def _copy(x: Any) -> Any:
    """A deep copy of a kernel's arguments (arrays, tuples of arrays, scalars)."""
    if isinstance(x, np.ndarray):
        return x.copy()
    if isinstance(x, tuple):
        return tuple(_copy(y) for y in x)
    return x


def _describe(args: tuple[Any, ...], names: tuple[str, ...]) -> str:
    """A failing case in full, for the message (arrays as lists)."""

    def text(x: Any) -> Any:
        if isinstance(x, np.ndarray):
            return x.tolist()
        if isinstance(x, tuple):
            return [text(y) for y in x]
        return x

    return json.dumps({n: text(a) for n, a in zip(names, args, strict=True)})[:6000]


def assert_check_rows_same(args: tuple[Any, ...], what: str) -> FloatArray:
    """Both ``check_rows`` on ``args`` (``between`` pre-filled with different values): the same result vector and
    the same ``between``. Returns the result vector."""
    args = _copy(args)
    n = len(args[3])
    b1, b2 = np.full(max(n - 1, 0), 1.25), np.full(max(n - 1, 0), -7.5)
    want = compiled_kernels.check_rows(*args[:-1], b1)
    got = kernels_numpy.check_rows(*_copy(args[:-1]), b2)
    if not _same(want, got):
        diff = [k for k in range(len(want)) if not _same(want[k], got[k])]
        pytest.fail(
            f"{what}: check_rows differs in {[(RES_NAMES[k], want[k], got[k]) for k in diff]}; "
            f"case {_describe(args, CHECK_ARGS)}"
        )
    if want[0] == 0.0 and not _same(b1, b2):
        rows = np.flatnonzero(~((b1 == b2) & (np.signbit(b1) == np.signbit(b2))))
        pytest.fail(
            f"{what}: between differs at rows {rows[:5].tolist()}: kernel {b1[rows[:5]].tolist()}, twin "
            f"{b2[rows[:5]].tolist()}; case {_describe(args, CHECK_ARGS)}"
        )
    return np.asarray(want)


def assert_between_rows_same(args: tuple[Any, ...], what: str) -> FloatArray:
    """Both ``between_rows`` on ``args``: the same bounds. Returns them."""
    want = compiled_kernels.between_rows(*_copy(args))
    got = kernels_numpy.between_rows(*_copy(args))
    if not _same(want, got):
        rows = np.flatnonzero(~(want == got)) if want.shape == got.shape else []
        pytest.fail(
            f"{what}: between_rows differs at rows {list(rows[:5])} (kernel {want[rows[:5]].tolist()}, twin "
            f"{got[rows[:5]].tolist()}); case {_describe(args, (*CHECK_ARGS[:5], 'A', 'dt', 'amax', 'jmax'))}"
        )
    return np.asarray(want)


def assert_sample_rows_same(args: tuple[Any, ...], what: str) -> None:
    """Both ``sample_rows`` on ``args`` (outputs pre-filled with different values): the same S, V, A, J."""
    n = len(args[0])
    out1 = [np.full((n, 2), 3.5) for _ in range(4)]
    out2 = [np.full((n, 2), -2.25) for _ in range(4)]
    compiled_sampling.sample_rows(*_copy(args), *out1)
    sampling_numpy.sample_rows(*_copy(args), *out2)
    for name, x, y in zip("SVAJ", out1, out2, strict=True):
        if not _same(x, y):
            rows = np.flatnonzero(~((x == y) | (np.isnan(x) & np.isnan(y))).all(axis=1))
            pytest.fail(
                f"{what}: sample_rows' {name} differs at rows {rows[:5].tolist()}: kernel {x[rows[:5]].tolist()}, "
                f"twin {y[rows[:5]].tolist()}; times {args[0][rows[:5]].tolist()}; case {_describe(args, SAMPLE_ARGS)}"
            )


# ------------------------------------------------------------------------------------------ the pipeline's arguments
@contextmanager
def recording() -> Iterator[dict[str, list[tuple[Any, ...]]]]:
    """Records a copy of the arguments of every call of the three kernels made by the gate and the timing."""
    calls: dict[str, list[tuple[Any, ...]]] = {"check_rows": [], "between_rows": [], "sample_rows": []}

    def wrap(name: str, f: Callable[..., Any]) -> Callable[..., Any]:
        def record(*args: Any) -> Any:
            calls[name].append(_copy(args[:-4] if name == "sample_rows" else args))  # not the sampler's outputs
            return f(*args)

        return record

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(gate, "check_rows", wrap("check_rows", gate.check_rows))
        mp.setattr(gate, "between_rows", wrap("between_rows", gate.between_rows))
        mp.setattr(scaling, "sample_rows", wrap("sample_rows", scaling.sample_rows))
        yield calls


def _trajectories(gen: TrajectoryGenerator, queries: Iterator[Any], count: int, margins: int) -> int:
    """Up to ``count`` trajectories of the queries (bad queries and no motions skipped), the margins of the first
    ``margins``. Returns how many were made."""
    made = 0
    for start, goal in queries:
        try:
            traj = gen.generate(start, goal)
        except MPAError:
            continue
        if made < margins:
            traj.margins()
        made += 1
        if made == count:
            break
    return made


def _layout_queries(track: GraphTrack, rng: np.random.Generator) -> Iterator[Any]:
    for _ in range(60):
        a0, b0, a1, b1 = (random_position(track, rng) for _ in range(4))
        yield [a0, b0], [a1, b1]


def _paper_queries(track: Any, rng: np.random.Generator) -> Iterator[Any]:
    for _ in range(60):
        w = _waypoints(track, rng, 2)
        yield w[0].tolist(), w[1].tolist()


@pytest.fixture(scope="module")
def captured() -> dict[str, list[tuple[str, tuple[Any, ...]]]]:
    """``{kernel: [(source, args)]}``: the kernels' arguments while making trajectories (and margins) of seeded
    queries on the paper's tracks, every example layout (D = 0.05 m and D = 0) and the Open-RMF maps (office and
    hotel at D = 0.3 m, the airport's issue-25 query at D = 0.6 m). At most 150 sampling calls and 60 bound calls
    per source, chosen at random (the margins' searches make thousands)."""
    rng = np.random.default_rng(2025)
    out: dict[str, list[tuple[str, tuple[Any, ...]]]] = {"check_rows": [], "between_rows": [], "sample_rows": []}

    def keep(source: str, calls: dict[str, list[tuple[Any, ...]]]) -> None:
        for name, cap in (("check_rows", 10**6), ("between_rows", 60), ("sample_rows", 150)):
            got = calls[name]
            pick = set(rng.choice(len(got), cap, replace=False).tolist()) if len(got) > cap else set(range(len(got)))
            if got:  # and the largest grid
                pick.add(max(range(len(got)), key=lambda i: len(got[i][0 if name == "sample_rows" else 3])))
            out[name] += [(source, got[i]) for i in sorted(pick)]

    for track, clearance in ((Lollipop(1.0, 1.0), 0.05), (Lollipop(0.3, 1.2), 0.0), (Circle(1.0), 0.1)):
        with recording() as calls:
            made = _trajectories(TrajectoryGenerator(track, clearance=clearance), _paper_queries(track, rng), 3, 1)
        assert made == 3, track
        keep(f"{track!r} D={clearance}", calls)
    with recording() as calls:  # the interval: the robots keep their order
        gen = TrajectoryGenerator(Interval(2.0), clearance=0.1)
        assert _trajectories(gen, iter([([0.2, 1.0], [0.9, 1.8]), ([1.5, 1.9], [0.1, 0.4])]), 2, 1) == 2
    keep("Interval(2.0)", calls)
    for layout in sorted(EXAMPLES.glob("*.json")):
        track = GraphTrack.from_json(layout)
        for clearance, rate in ((0.05, 100.0), (0.0, 25.0)):
            with recording() as calls:
                gen = TrajectoryGenerator(track, clearance=clearance, rate=rate)
                made = _trajectories(gen, _layout_queries(track, rng), 3, 1 if clearance else 0)
            assert made == 3, (layout.stem, clearance)
            keep(f"{layout.stem} D={clearance}", calls)
    for name, kw, clearance in (
        ("office", {"level": "L1"}, 0.3),
        ("hotel", {"level": "L1"}, 0.3),
    ):
        track = GraphTrack.from_file(OPENRMF / f"{name}.building.yaml", **kw)
        with recording() as calls:
            made = _trajectories(TrajectoryGenerator(track, clearance=clearance), _layout_queries(track, rng), 2, 1)
        assert made == 2, name
        keep(f"{name} D={clearance}", calls)
    track = GraphTrack.from_file(OPENRMF / "airport_terminal.building.yaml", level="L1", nav_graph=2)
    with recording() as calls:
        query = iter([(["lane70:3.102", "lane143:8.848"], ["lane87:1.237", "lane100:0.997"])])
        assert _trajectories(TrajectoryGenerator(track, clearance=0.6), query, 1, 1) == 1
    keep("airport D=0.6", calls)
    return out


def test_the_twins_equal_the_kernels_on_the_pipelines_arguments(captured: Any) -> None:
    counts = {name: len(calls) for name, calls in captured.items()}
    assert counts["check_rows"] >= 70 and counts["between_rows"] >= 500 and counts["sample_rows"] >= 1500, counts
    longest = 0
    for source, args in captured["check_rows"]:
        assert_check_rows_same(args, f"check_rows of {source}")
        longest = max(longest, len(args[3]))
    assert longest == 43829  # the airport's motion, in 11 blocks
    cut = 0
    for source, args in captured["between_rows"]:
        assert_between_rows_same(args, f"between_rows of {source}")
        cut += int(np.count_nonzero(_cuts(args[1], args[3][:, 0]) + _cuts(args[2], args[3][:, 1])))
    for source, args in captured["sample_rows"]:
        assert_sample_rows_same(args, f"sample_rows of {source}")
    assert cut >= 10000, cut  # chords a junction cuts (the rare case done one chord at a time)
    assert {args[11] for _, args in captured["sample_rows"]} >= {1, 5}  # straight and blended paths
    assert max(len(args[0]) for _, args in captured["sample_rows"]) >= 43829


@pytest.mark.parametrize("block", [1, 3, 100])
def test_the_twins_in_small_blocks(captured: Any, block: int) -> None:
    # the passes over the rows go block by block: the running minima and maxima (their first rows), the chords
    # across a block's end and the sampling are the same whatever the blocks
    rng = np.random.default_rng(block)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(kernels_numpy, "_BLOCK", block)
        mp.setattr(sampling_numpy, "_BLOCK", block)
        for kernel, check in (
            ("check_rows", assert_check_rows_same),
            ("between_rows", assert_between_rows_same),
            ("sample_rows", assert_sample_rows_same),
        ):
            calls = [c for c in captured[kernel] if 2 < len(c[1][0 if kernel == "sample_rows" else 3]) < 30 * block]
            for i in rng.choice(len(calls), min(len(calls), 25), replace=False):
                check(calls[i][1], f"{kernel} of {calls[i][0]} in blocks of {block}")
        bases = [args for _, args in captured["check_rows"] if len(args[3]) < 30 * block + 200]
        for i, args in enumerate(bases[:: max(1, len(bases) // 8)]):
            for kind, case in _check_variants(args, rng):
                if "peak" in kind or "constant" in kind or "tied" in kind or "rows" in kind:
                    assert_check_rows_same(case, f"base {i}, {kind}, in blocks of {block}")


# ------------------------------------------------------------------------------------------ perturbed rows
def _geometry(graph: Any) -> GraphGeometry:
    tails, heads, lengths, dv = graph
    geo = GraphGeometry(len(dv), tails, heads, lengths)
    assert np.array_equal(geo.dv, dv)
    return geo


def _route(r: Any) -> DirectedRoute:
    breaks, edges, dirs, entry = r
    return DirectedRoute(edges, dirs, entry, breaks)


def _with(args: tuple[Any, ...], **changes: Any) -> tuple[Any, ...]:
    """``args`` of ``check_rows`` with the named ones replaced (copied; ``between`` resized to the rows)."""
    new = dict(zip(CHECK_ARGS, _copy(args), strict=True))
    new.update({k: (np.ascontiguousarray(v) if isinstance(v, np.ndarray) else v) for k, v in changes.items()})
    new["between"] = np.empty(max(len(new["tt"]) - 1, 0))
    return tuple(new[k] for k in CHECK_ARGS)


def _check_variants(args: tuple[Any, ...], rng: np.random.Generator) -> Iterator[tuple[str, tuple[Any, ...]]]:
    """Copies of recorded ``check_rows`` arguments, each changed in one way the gate checks."""
    a = dict(zip(CHECK_ARGS, args, strict=True))
    n, ne = len(a["tt"]), len(a["graph"][2])
    routes = (_route(a["ra"]), _route(a["rb"]))
    geo = _geometry(a["graph"])

    def at(s: FloatArray) -> dict[str, FloatArray]:  # rows moved along the routes, positions consistent
        s = np.clip(s, [r.breaks[0] for r in routes], [r.breaks[-1] for r in routes])
        pos = [routes[r].positions(s[:, r]) for r in (0, 1)]
        edges = np.stack([pos[0][0], pos[1][0]], 1).astype(np.int64)
        return {"S": s, "E": edges, "OFF": np.stack([pos[0][1], pos[1][1]], 1)}

    def cell() -> tuple[int, int]:
        return int(rng.integers(0, n)), int(rng.integers(0, 2))

    for name in ("tt", "OFF", "S", "V", "A", "J"):
        for value in (np.nan, np.inf, -np.inf):
            x = a[name].copy()
            k, r = cell()
            x[(k, r) if x.ndim == 2 else k] = value
            yield f"{value} in {name}", _with(args, **{name: x})
    for value in (-1, ne, 10**6, -(2**40)):
        e = a["E"].copy()
        e[cell()] = value
        yield f"edge {value}", _with(args, E=e)
        off = a["OFF"].copy()
        off[cell()] = np.nan
        yield f"edge {value} and a NaN", _with(args, E=e, OFF=off)
    for delta in (1e-4, -1e-6, 1e-12):
        t = a["tt"].copy()
        t[int(rng.integers(0, n))] += delta
        yield f"time {delta}", _with(args, tt=t)
    yield "times stretched", _with(args, tt=a["tt"] * 1.001)
    yield "times late", _with(args, tt=a["tt"] + 2e-9)
    yield "rate doubled", _with(args, dt=a["dt"] / 2.0)
    yield "no time tolerance", _with(args, time_tol=0.0)
    for q in ("V", "A", "J"):
        lim = a["lims"][{"V": 0, "A": 2, "J": 4}[q] :][:2]
        x = a[q].copy()
        k, r = cell()
        x[k, r] = float(rng.choice([-1.0, 1.0])) * lim[r] * (1.0 + float(rng.choice([1e-7, 1e-4, 0.3])))
        yield f"{q} over its limit", _with(args, **{q: x})
        x = a[q].copy()
        peak = 1.5 * float(np.abs(x[:, r]).max()) + 1.0
        rows = sorted(rng.choice(n, min(n, 3), replace=False))
        x[rows, r] = peak * rng.choice([-1.0, 1.0], len(rows))
        yield f"{q} peak tied on rows {rows}", _with(args, **{q: x})
        yield f"{q} constant", _with(args, **{q: np.full_like(x, float(rng.uniform(-1, 1)))})
    for k in (0, n - 1, int(rng.integers(0, n))):
        s = a["S"].copy()
        s[k] += rng.choice([-1.0, 1.0], 2) * float(rng.choice([1e-6, 0.01, 0.5]))
        moved = at(s)
        yield f"row {k} moved", _with(args, **moved)
        yield f"row {k} moved, positions kept", _with(args, S=moved["S"])
    off = a["OFF"].copy()
    k, r = cell()
    off[k, r] = np.clip(off[k, r] + float(rng.choice([-1.0, 1.0])) * 1e-3, 0.0, geo.lengths[a["E"][k, r]])
    yield "off its route", _with(args, OFF=off)
    off = a["OFF"].copy()
    off[rng.random(off.shape) < 0.3] += 1e-9 * rng.choice([1.0, 2.0])  # many equal errors: the first row wins
    yield "errors tied", _with(args, OFF=off)
    for kind in ("close", "breaks", "walk", "uniform"):
        yield f"rows {kind}", _with(args, **at(_rows(geo, routes, rng, kind, n=max(n, 2))[:n]))
    s = at(a["S"])["S"]
    s[:, 1] = s[:, 0] + rng.choice([0.0, 1e-9, -1e-9], n)  # B on A's coordinate: on one route, at A
    yield "robots together", _with(args, **at(s))
    zeros = {name: a[name].copy() for name in ("OFF", "S", "V", "A", "J")}
    for x in zeros.values():
        x[rng.random(x.shape) < 0.2] = -0.0
        x[rng.random(x.shape) < 0.2] = 0.0
    t = a["tt"].copy()
    t[0] = -0.0
    yield "signed zeros", _with(args, tt=t, **zeros)
    for m in (1, 2):
        short = {k: a[k][:m] for k in ("tt", "E", "OFF", "S", "V", "A", "J")}
        yield f"{m} rows", _with(args, **short)
    yield "limits halved", _with(args, lims=a["lims"] * 0.5)
    yield "no jerk bound", _with(args, lims=np.concatenate([a["lims"][:4], [np.inf, np.inf]]))


def test_check_rows_twin_on_perturbed_rows(captured: Any) -> None:
    rng = np.random.default_rng(31)
    bases = [args for _, args in captured["check_rows"] if len(args[3]) < 5000]
    seen: Counter[str] = Counter()
    for i, args in enumerate(bases):
        for kind, case in _check_variants(args, rng):
            res = assert_check_rows_same(case, f"base {i}, {kind}")
            r = dict(zip(compiled_kernels.RES, res.tolist(), strict=True))
            lims = case[10]
            seen["non-finite"] += r["bad"] == 1.0
            seen["edge out of range"] += r["bad"] == 2.0
            if r["bad"]:
                continue
            seen["time grid"] += r["grid_ok"] == 0.0
            seen["off route"] += max(r["err_a"], r["err_b"]) > POSITION_TOL
            seen["ends"] += max(r["first_a"], r["first_b"], r["last_a"], r["last_b"]) > POSITION_TOL
            seen["rest"] += max(r["rest_first"], r["rest_last"]) > POSITION_TOL
            peaks = ("v_a", "v_b", "a_a", "a_b")
            seen["limits"] += any(r[q] > lims[m] * (1 + LIMIT_RTOL) for m, q in enumerate(peaks))
            seen["robots meet"] += r["dmin"] == 0.0 or r["bmin"] < 0.0
            seen["peak on a later row"] += r["v_a_row"] > 0 and r["a_b_row"] > 0
    assert len(bases) >= 60
    assert min(seen.values()) >= 100 and len(seen) == 9, seen


def _walk_route(geo: GraphGeometry, rng: np.random.Generator, pieces: int) -> DirectedRoute:
    """A route of about ``pieces`` pieces: from anywhere on an edge a random walk over whole edges, a partial last
    piece, now and then a piece of length 0 at a vertex passed; its route coordinate starts anywhere."""
    e, d = int(rng.integers(0, geo.n_edges)), int(rng.choice([1, -1]))
    start = float(rng.uniform(0.0, geo.lengths[e]))
    edges: list[int] = []
    dirs: list[int] = []
    entry: list[float] = []
    lengths: list[float] = []

    def step(v: int) -> tuple[int, int, float]:  # leave vertex v along a random incident edge
        inc = [(f, 1) for f in range(geo.n_edges) if geo.tails[f] == v]
        inc += [(f, -1) for f in range(geo.n_edges) if geo.heads[f] == v]
        f, df = inc[int(rng.integers(0, len(inc)))]
        return f, df, 0.0 if df == 1 else float(geo.lengths[f])

    while len(edges) < pieces:
        full = geo.lengths[e] - start if d == 1 else start
        last = len(edges) == pieces - 1
        edges.append(e)
        dirs.append(d)
        entry.append(start)
        lengths.append(float(rng.uniform(0.0, full)) if last else float(full))
        v = int(geo.heads[e] if d == 1 else geo.tails[e])
        e, d, start = step(v)
        if not last and len(edges) < pieces - 1 and rng.random() < 0.05:  # a piece of length 0 at v
            edges.append(e)
            dirs.append(d)
            entry.append(start)
            lengths.append(0.0)
            e, d, start = step(v)
    return DirectedRoute.from_pieces(edges, dirs, entry, lengths, origin=float(rng.uniform(-5.0, 5.0)))


def _cuts(route: Any, s: FloatArray) -> FloatArray:
    """How many junctions of ``route`` (its arrays) lie strictly inside each chord of the coordinates ``s`` (N,)."""
    inner = route[0][1:-1]
    lo, hi = np.minimum(s[:-1], s[1:]), np.maximum(s[:-1], s[1:])
    return np.searchsorted(inner, hi, "left") - np.searchsorted(inner, lo, "right")


def test_between_rows_twin_on_routes_with_many_junctions() -> None:
    rng = np.random.default_rng(47)
    geos = [GraphTrack.from_json(p).geometry for p in sorted(EXAMPLES.glob("*.json"))]
    geos += [random_layout(rng).geometry for _ in range(6)]
    cut = multi = met = 0
    for i in range(240):
        geo = geos[i % len(geos)]
        ra = _walk_route(geo, rng, int(rng.integers(1, 40))) if i % 4 else _random_route(geo, rng)
        rb = (_walk_route(geo, rng, int(rng.integers(1, 40))), _reversed(ra), ra)[i % 3]
        graph = (geo.tails, geo.heads, geo.lengths, geo.dv)
        for kind in ("walk", "close", "breaks", "uniform"):
            s = _rows(geo, (ra, rb), rng, kind, n=int(rng.integers(2, 80)))
            if i % 3 == 2 and kind == "walk":  # B a small gap behind A on the same route, sometimes overtaking
                s[:, 1] = np.clip(s[:, 0] - 1e-6 * rng.uniform(-0.2, 1.0, len(s)), ra.breaks[0], ra.breaks[-1])
            acc = rng.normal(scale=2.0, size=s.shape)
            dt = float(rng.choice([0.002, 0.01, 0.04, 0.5]))
            lim = rng.uniform(0.5, 5.0, 4)
            args = (graph, ra.arrays, rb.arrays, s, acc, dt, lim[:2].copy(), lim[2:].copy())
            b = assert_between_rows_same(args, f"routes {i}, {kind}")
            cuts = np.maximum(_cuts(ra.arrays, s[:, 0]), _cuts(rb.arrays, s[:, 1]))
            cut, multi = cut + int(np.count_nonzero(cuts)), multi + int(np.count_nonzero(cuts >= 2))
            met += int(np.count_nonzero(b < 0.0))
    assert cut >= 10000 and multi >= 8000 and met >= 10000, (cut, multi, met)


# ------------------------------------------------------------------------------------------ perturbed times
def _sample_variants(args: tuple[Any, ...], rng: np.random.Generator) -> Iterator[tuple[str, tuple[Any, ...]]]:
    """Copies of recorded ``sample_rows`` arguments with other times (and the path piece looked up)."""
    a = dict(zip(SAMPLE_ARGS, args, strict=True))
    t0, duration = a["t0"], float(a["duration"])

    def with_times(tt: FloatArray, **changes: Any) -> tuple[Any, ...]:
        new = {**a, "tt": np.ascontiguousarray(tt, dtype=float), **changes}
        return tuple(new[k] for k in SAMPLE_ARGS)

    yield "uniform", with_times(rng.uniform(-1.0, duration + 1.0, 50))
    edges = np.concatenate([t0, [duration]])
    yield "phase starts", with_times(edges)
    yield "beside phase starts", with_times(np.concatenate([np.nextafter(edges, -np.inf), np.nextafter(edges, np.inf)]))
    specials = [np.nan, np.inf, -np.inf, -0.0, 0.0, 1e300, -1e300, 5e-324, duration]
    yield "special times", with_times(np.array(specials + rng.uniform(0, duration, 5).tolist()))
    yield "unsorted", with_times(rng.permutation(rng.uniform(0.0, duration, 30)))
    yield "no times", with_times(np.zeros(0))
    yield (
        "piece looked up",
        with_times(rng.uniform(-0.1, duration + 0.1, 40), piece=np.zeros(0, dtype=a["piece"].dtype)),
    )


def test_sample_rows_twin_on_perturbed_times(captured: Any) -> None:
    rng = np.random.default_rng(59)
    sources: Counter[str] = Counter()
    for source, args in captured["sample_rows"][::4]:
        for kind, case in _sample_variants(args, rng):
            assert_sample_rows_same(case, f"{source}, {kind}")
        sources[source.split(" ")[0]] += 1
    assert len(sources) >= 15, sources


def test_float_power_is_the_c_librarys_pow() -> None:
    # the twins compute math.pow(x, 3.0) (the kernel's compiled call of the C library's pow) as numpy.float_power;
    # numpy.power may take a vectorised pow that differs in the last bit
    rng = np.random.default_rng(3)
    x = np.concatenate([rng.uniform(-5, 5, 20000), rng.uniform(0, 1e-3, 5000), rng.normal(scale=100, size=5000)])
    x = np.concatenate([x, [0.0, -0.0, 1e-310, -1e-310, 1e100, -1e100, 5e-324]])
    want = np.array([math.pow(v, 3.0) for v in x])
    assert _same(np.float_power(x, 3.0), want)


# ------------------------------------------------------------------------------------------ hypothesis
_HGEO = random_layout(np.random.default_rng(11), 5).geometry
_HROUTES = (_walk_route(_HGEO, np.random.default_rng(12), 9), _walk_route(_HGEO, np.random.default_rng(13), 4))
_HGRAPH = (_HGEO.tails, _HGEO.heads, _HGEO.lengths, _HGEO.dv)
_FINITE = st.floats(-1e3, 1e3, width=64) | st.sampled_from([0.0, -0.0, 5e-324, 1e-300, 0.5, 1.0])


def _coordinates(route: DirectedRoute) -> st.SearchStrategy[float]:
    """Route coordinates: anywhere a little beyond the route, on its junctions and one ulp beside them."""
    b = route.breaks
    near = [*b.tolist(), *np.nextafter(b, -np.inf).tolist(), *np.nextafter(b, np.inf).tolist()]
    return st.floats(float(b[0]) - 1.0, float(b[-1]) + 1.0) | st.sampled_from(near)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data(), n=st.integers(1, 9), dt=st.sampled_from([0.01, 0.04, 1.0 / 3.0]))
def test_check_rows_twin_hypothesis(data: st.DataObject, n: int, dt: float) -> None:
    ne = _HGEO.n_edges

    def rows(elements: st.SearchStrategy[Any] = _FINITE, dtype: Any = float) -> FloatArray:
        return np.ascontiguousarray(data.draw(hnp.arrays(dtype, (n, 2), elements=elements)))

    s = np.ascontiguousarray(np.stack([data.draw(hnp.arrays(float, n, elements=_coordinates(r))) for r in _HROUTES], 1))
    E = rows(st.integers(0, ne - 1), np.int64)
    OFF = rows(st.floats(-0.1, 2.7) | st.sampled_from([0.0, -0.0]))
    V, A, J = rows(), rows(), rows()
    tt = np.arange(n) * dt + data.draw(hnp.arrays(float, n, elements=st.sampled_from([0.0, 0.0, 1e-10, -1e-8])))
    broken = data.draw(st.sampled_from(["none", "nan", "inf", "edge"]))
    if broken != "none":
        k, r = data.draw(st.integers(0, n - 1)), data.draw(st.integers(0, 1))
        if broken == "edge":
            E[k, r] = data.draw(st.sampled_from([-1, ne, 2**31]))
        else:
            target = data.draw(st.sampled_from([OFF, s, V, A, J]))
            target[k, r] = np.nan if broken == "nan" else -np.inf
    lims = np.ascontiguousarray(data.draw(hnp.arrays(float, 6, elements=st.floats(0.1, 10.0))))
    ends = np.array([data.draw(st.integers(0, ne - 1)) if i % 2 == 0 else data.draw(st.floats(0, 1)) for i in range(8)])
    args = (_HGRAPH, *(r.arrays for r in _HROUTES), tt, E, OFF, s, V, A, J, lims, dt, 1e-9, ends, np.empty(n - 1))
    assert_check_rows_same(args, "hypothesis")


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data(), n=st.integers(0, 12), dt=st.floats(1e-3, 2.0), same=st.booleans())
def test_between_rows_twin_hypothesis(data: st.DataObject, n: int, dt: float, same: bool) -> None:
    # the routes walked both ways, or one route twice (the robots following or meeting on it)
    ra, rb = (_HROUTES[0], _HROUTES[0]) if same else _HROUTES
    s = np.stack([data.draw(hnp.arrays(float, n, elements=_coordinates(r))) for r in (ra, rb)], 1).reshape(n, 2)
    acc = data.draw(hnp.arrays(float, (n, 2), elements=_FINITE))
    lims = data.draw(hnp.arrays(float, 4, elements=st.floats(0.01, 20.0) | st.just(np.inf)))
    args = (_HGRAPH, ra.arrays, rb.arrays, np.ascontiguousarray(s), acc, dt, lims[:2].copy(), lims[2:].copy())
    assert_between_rows_same(args, "hypothesis")


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data(), q=st.integers(1, 6), pieces=st.integers(1, 4), degree=st.sampled_from([0, 1, 2, 3, 5]))
def test_sample_rows_twin_hypothesis(data: st.DataObject, q: int, pieces: int, degree: int) -> None:
    floats = st.floats(-50.0, 50.0) | st.sampled_from([0.0, -0.0, 1e-300])
    t0 = np.cumsum(data.draw(hnp.arrays(float, q, elements=st.floats(0.0, 3.0) | st.just(0.0)))) - data.draw(
        st.sampled_from([0.0, 0.5])
    )
    p, v, a, j = (np.ascontiguousarray(data.draw(hnp.arrays(float, q, elements=floats))) for _ in range(4))
    duration = float(t0[-1]) + data.draw(st.floats(0.0, 2.0))
    length = data.draw(st.floats(0.0, 30.0))
    lookup = data.draw(st.booleans())  # the path piece looked up from s
    drawn = data.draw(hnp.arrays(np.intp, q, elements=st.integers(0, pieces - 1)))
    piece = np.zeros(0, dtype=np.intp) if lookup else np.ascontiguousarray(drawn)
    breaks = np.concatenate([[0.0], np.cumsum(data.draw(hnp.arrays(float, pieces, elements=st.floats(0.0, 10.0))))])
    coef = np.ascontiguousarray(data.draw(hnp.arrays(float, (pieces, 6, 2), elements=floats)))
    tt = data.draw(
        hnp.arrays(
            float,
            data.draw(st.integers(0, 12)),
            elements=st.floats(-1.0, duration + 1.0) | st.sampled_from([*t0.tolist(), duration, np.nan, np.inf, -0.0]),
        )
    )
    args = (np.ascontiguousarray(tt), t0, p, v, a, j, duration, length, piece, breaks, coef, degree, _FALLING_ARRAY)
    assert_sample_rows_same(args, "hypothesis")


# ------------------------------------------------------------------------------------------ the gate's decisions
def test_the_gates_reports_are_the_same_with_the_twins() -> None:
    metas, arrays, kinds, _ = _gate_cases()
    compiled = run_gate_cases(metas, arrays)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(gate, "check_rows", kernels_numpy.check_rows)
        mp.setattr(gate, "between_rows", kernels_numpy.between_rows)
        twins = run_gate_cases(metas, arrays)
    assert len(twins) == len(compiled) == len(metas) >= 300
    for i, (kind, _) in enumerate(kinds):
        assert twins[i] == compiled[i], f"case {i} ({kind}, {metas[i]}): twins {twins[i]} != kernels {compiled[i]}"
    outcomes = Counter(json.loads(c[0])["ok"] if c[0].startswith("{") else c[0] for c in compiled)
    assert outcomes[True] >= 16 and outcomes[False] >= 250, outcomes


# ------------------------------------------------------------------------------------------ the modules
def test_the_twins_slots_are_the_kernels() -> None:
    assert kernels_numpy.RES == compiled_kernels.RES


def test_the_twins_import_neither_numba_nor_the_kernels() -> None:
    for module in (kernels_numpy, sampling_numpy):
        tree = ast.parse(Path(str(module.__file__)).read_text())
        names = {a.name for node in ast.walk(tree) if isinstance(node, ast.Import) for a in node.names}
        names |= {str(node.module) for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)}
        # the result vector's slots are shared with the kernels, the elementwise helpers with the other twins, through
        # modules that import neither numba nor the kernels
        allowed = {"__future__", "math", "numpy", "mpa"}
        shared = {"trajopt.verify.results", "trajopt.verify.elementwise"}
        assert all(n.split(".")[0] in allowed or n in shared for n in names), (module, names)
    code = (
        "import sys\n"
        "import trajopt.verify.kernels_numpy, trajopt.verify.sampling_numpy\n"
        "names = ('numba', 'llvmlite', 'trajopt.verify.kernels', 'trajopt.verify.sampling')\n"
        "bad = [m for m in names if m in sys.modules]\n"
        "print(bad)\n"
    )
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and done.stdout.strip() == "[]", (done.stdout, done.stderr[-2000:])
