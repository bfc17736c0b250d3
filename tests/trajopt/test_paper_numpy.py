"""The numpy twins of the paper tracks' kernels against the compiled kernels, bit for bit.

:mod:`trajopt.verify.paper_numpy` (``track_positions``, ``dense_polyline``, ``needs_densify``, ``word_samples``,
``lollipop_skeleton_points``, ``circle_skeleton_points``) stands in for the numba kernels of
:mod:`trajopt.verify.kernels` in one-shot processes. Every output (returned or filled in place, from buffers
pre-filled with the same sentinel: a row one of them leaves unwritten shows) is compared with ``np.array_equal``
and the sign of every zero, and an exception must be the same type, on

- the arguments the pipeline passes to the kernels, recorded while making trajectories (and their margins) of
  seeded queries on Lollipop(1, 1), Lollipop(0.3, 1.2), Lollipop(1.5, 0.8), Circle(1) and Interval(2), with and
  without clearance, at several rates;
- seeded perturbations of them: coordinates on the routes' breaks and one ulp beside, past the routes' ends,
  non-finite, signed zeros; states at the pole P, on the loop's ends, at collisions, degenerate lollipops; legs of
  exactly one step and one ulp beside it, of zero length, non-finite or huge; empty inputs, one row; divisions by
  zero (the rows before filled, as by the kernel);
- hypothesis's;

and the gate's reports of the paper cases of ``tests/trajopt/test_gate_kernels.py`` are the same with the twins
patched in, and a process in the ``numpy`` mode with the twins patched in makes a lollipop trajectory without
importing numba, the same as numba's.
"""

from __future__ import annotations

import ast
import json
import os
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

import trajopt.path.planview as planview
import trajopt.verify.gate as gate
from mpa import Circle, Interval, Lollipop, MPAError
from mpa.skeleton import VERTEX_TOL, skeleton_of
from tests.trajopt.test_gate_kernels import _gate_cases, _waypoints, run_gate_cases
from tests.trajopt.test_kernels_numpy import _copy, _same
from trajopt import Limits, TrajectoryGenerator
from trajopt.verify import kernels as compiled
from trajopt.verify import paper_numpy

ROOT = Path(__file__).resolve().parents[2]
FloatArray = np.ndarray

#: The six kernels and the positions of their outputs filled in place.
KERNELS = {
    "track_positions": (12,),
    "dense_polyline": (),
    "needs_densify": (),
    "word_samples": (),
    "lollipop_skeleton_points": (5, 6),
    "circle_skeleton_points": (2, 3),
}
#: The sentinel every output buffer starts with (the same in both runs).
SENTINEL = {"i": -123456, "f": -777.25}


# ------------------------------------------------------------------------------------------ comparisons
def _describe(args: tuple[Any, ...]) -> str:
    """A failing case in full (arrays as lists), for the message."""

    def text(x: Any) -> Any:
        return x.tolist() if isinstance(x, np.ndarray) else x

    return json.dumps([text(a) for a in args])[:6000]


def _run(f: Callable[..., Any], name: str, args: tuple[Any, ...]) -> tuple[Any, list[FloatArray], str | None]:
    """``f(*args)`` on a copy, its outputs pre-filled with the sentinel: ``(returned, outputs, exception type)``."""
    args = _copy(args)
    outs = [args[i] for i in KERNELS[name]]
    for x in outs:
        x[...] = SENTINEL[x.dtype.kind]
    try:
        got, exc = f(*args), None
    except (ZeroDivisionError, IndexError) as e:
        got, exc = None, type(e).__name__
    return got, outs, exc


def assert_same(name: str, args: tuple[Any, ...], what: str) -> tuple[Any, str | None]:
    """The kernel ``name`` and its twin on ``args``: the same returned values, outputs and exception type.
    Returns the kernel's ``(returned, exception type)``."""
    want, want_out, want_exc = _run(getattr(compiled, name), name, args)
    got, got_out, got_exc = _run(getattr(paper_numpy, name), name, args)
    case = f"{what}: {name} on {_describe(args)}"
    assert want_exc == got_exc, f"kernel raises {want_exc}, twin {got_exc}; {case}"
    for x, y in zip(want_out, got_out, strict=True):
        if not _same(x, y):
            rows = np.flatnonzero(~((x == y) | (np.isnan(x) & np.isnan(y))).reshape(len(x), -1).all(axis=1))
            pytest.fail(
                f"outputs differ at rows {rows[:5].tolist()}: {x[rows[:5]].tolist()} vs {y[rows[:5]].tolist()}; {case}"
            )
    if isinstance(want, tuple):  # word_samples: (keep, jump)
        assert _same(want[0], got[0]) and type(want[1]) is type(got[1]) and want[1] == got[1], (want, got, case)
    elif isinstance(want, np.ndarray):
        assert _same(want, got), f"returned {want.tolist()[:5]} vs {got.tolist()[:5]}; {case}"
    else:
        assert type(want) is type(got) and want == got, (want, got, case)
    return want, want_exc


# ------------------------------------------------------------------------------------------ the pipeline's arguments
@contextmanager
def recording() -> Iterator[dict[str, list[tuple[Any, ...]]]]:
    """Records a copy of the arguments of every call of the six kernels made by the gate and the plan view."""
    calls: dict[str, list[tuple[Any, ...]]] = {name: [] for name in KERNELS}

    def wrap(name: str, f: Callable[..., Any]) -> Callable[..., Any]:
        def record(*args: Any) -> Any:
            calls[name].append(_copy(args))
            return f(*args)

        return record

    with pytest.MonkeyPatch.context() as mp:
        for name in KERNELS:
            mp.setattr(gate, name, wrap(name, getattr(gate, name)))
        mp.setattr(planview, "track_positions", wrap("track_positions", planview.track_positions))
        yield calls


TRACKS = (Lollipop(1.0, 1.0), Lollipop(0.3, 1.2), Lollipop(1.5, 0.8), Circle(1.0), Interval(2.0))


@pytest.fixture(scope="module")
def captured() -> dict[str, list[tuple[str, tuple[Any, ...]]]]:
    """``{kernel: [(source, args)]}``: the six kernels' arguments while making trajectories of seeded queries on
    the paper's tracks (D = 0.05 m at 100 Hz with margins, D = 0 at 25 Hz, D = 0.1 m at 250 Hz with other limits),
    at most 40 calls per kernel and source, chosen at random, and the longest."""
    rng = np.random.default_rng(77)
    out: dict[str, list[tuple[str, tuple[Any, ...]]]] = {name: [] for name in KERNELS}
    slow = Limits((0.5, 1.0), 2.0, 10.0)
    for track in TRACKS:
        for clearance, rate, lim, margins in (
            (0.05, 100.0, Limits(), 1),
            (0.0, 25.0, Limits(), 0),
            (0.1, 250.0, slow, 0),
        ):
            source = f"{track!r} D={clearance} {rate} Hz"
            with recording() as calls:
                gen = TrajectoryGenerator(track, clearance=clearance, rate=rate, limits=lim)
                made = 0
                for _ in range(40):
                    query = _waypoints(track, rng, 2).tolist()
                    try:
                        traj = gen.generate(*query)
                    except MPAError:
                        continue
                    if made < margins:
                        traj.margins()
                    made += 1
                    if made == 4:
                        break
            assert made == 4, source
            for name, got in calls.items():
                pick = set(rng.choice(len(got), 40, replace=False).tolist()) if len(got) > 40 else set(range(len(got)))
                if got:
                    pick.add(max(range(len(got)), key=lambda i: len(got[i][0])))
                out[name] += [(source, got[i]) for i in sorted(pick)]
    return out


def test_the_twins_equal_the_kernels_on_the_pipelines_arguments(captured: Any) -> None:
    counts = {name: len(calls) for name, calls in captured.items()}
    assert min(counts.values()) >= 12, counts
    for name, calls in captured.items():
        for source, args in calls:
            assert_same(name, args, source)
    sources = {name: {s.split(" ")[0] for s, _ in calls} for name, calls in captured.items()}
    assert len(sources["track_positions"]) == len(TRACKS), sources  # every track
    assert {s.split("(")[0] for s in sources["lollipop_skeleton_points"]} == {"Lollipop"}, sources
    assert len(sources["lollipop_skeleton_points"]) == 3 and len(sources["circle_skeleton_points"]) == 1, sources
    assert any(compiled.needs_densify(*args) for _, args in captured["needs_densify"])  # both answers seen
    assert not all(compiled.needs_densify(*args) for _, args in captured["needs_densify"])
    longest = max(len(compiled.dense_polyline(*args)) for _, args in captured["dense_polyline"])
    assert longest >= 300, longest  # legs cut into several points


# ------------------------------------------------------------------------------------------ perturbed and edge cases
def _specials(route_args: tuple[Any, ...]) -> FloatArray:
    """Route coordinates that matter for a route (its breaks, one ulp beside them, signed zeros, non-finite)."""
    breaks = np.asarray(route_args[0], dtype=float)
    return np.concatenate(
        [breaks, np.nextafter(breaks, -np.inf), np.nextafter(breaks, np.inf), [0.0, -0.0, np.nan, np.inf, -np.inf]]
    )


def _track_position_variants(args: tuple[Any, ...], rng: np.random.Generator) -> Iterator[tuple[str, tuple[Any, ...]]]:
    S = args[0]
    n = len(S)

    def with_rows(x: FloatArray) -> tuple[Any, ...]:
        x = np.ascontiguousarray(x, dtype=float)
        return (x, *args[1:12], np.empty(x.shape))

    lo = min(float(S.min()), 0.0) if n else 0.0
    hi = max(float(S.max()), 1.0) if n else 1.0
    yield "uniform beyond the ends", with_rows(rng.uniform(lo - 2.0, hi + 2.0, (200, 2)))
    specials = [_specials(args[1:5]), _specials(args[5:9])]
    m = max(len(s) for s in specials)
    yield "breaks and specials", with_rows(np.stack([rng.choice(s, m) for s in specials], 1))
    x = S.copy()
    x[rng.random(x.shape) < 0.2] = -0.0
    yield "signed zeros", with_rows(x)
    yield "no rows", with_rows(np.zeros((0, 2)))
    yield "one row", with_rows(S[:1] if n else np.zeros((1, 2)))
    huge = rng.choice([1e300, -1e300, 5e-324, 1e16, -1e16], (10, 2))
    yield "huge", with_rows(huge)
    # a loop of length 0: the kernel divides by zero on a loop piece (NaN coordinates on the route's first piece)
    for kind, case in (("recorded", args), ("specials", with_rows(np.stack([rng.choice(s, m) for s in specials], 1)))):
        yield f"loop 0, {kind} rows", (*case[:11], 0.0, case[12])


def test_track_positions_twin_on_perturbed_rows(captured: Any) -> None:
    rng = np.random.default_rng(5)
    raised: Counter[str] = Counter()
    for source, args in captured["track_positions"][::3]:
        for kind, case in _track_position_variants(args, rng):
            _, exc = assert_same("track_positions", case, f"{source}, {kind}")
            raised[str(exc)] += 1
    assert raised["ZeroDivisionError"] >= 10 and raised["None"] >= 100, raised


def _lollipop_args(track: Lollipop, P: FloatArray) -> tuple[Any, ...]:
    """``lollipop_skeleton_points``'s arguments for the states ``P`` (shape (N, 2)) as the gate passes them."""
    sk = skeleton_of(track)
    degenerate = bool(sk.graph.edges[0].length <= 1e-9)
    ell, c_model, kappa = float(sk.model.stick), float(sk.model.loop), float(sk.kappa)
    P = np.ascontiguousarray(P, dtype=float)
    return (P, ell, c_model, kappa, degenerate, np.empty(len(P), dtype=np.int64), np.empty(len(P)))


def _special_states(track: Any, rng: np.random.Generator, n: int) -> FloatArray:
    """``n`` states, most coordinates special: the ends, the pole P, the loop's ends and one ulp beside them."""
    ell = float(getattr(track, "stick", 0.0))
    total = float(track.total_length)
    points = np.array([0.0, -0.0, ell, total, total / 2, ell + (total - ell) / 2])
    points = np.concatenate([points, np.nextafter(points, -np.inf), np.nextafter(points, np.inf)])
    P = rng.uniform(0.0, total, (n, 2))
    special = rng.random(P.shape) < 0.6
    P[special] = rng.choice(points, int(special.sum()))
    together = rng.random(n) < 0.05
    P[together, 1] = P[together, 0]  # collisions
    return P


def test_lollipop_skeleton_points_twin_on_special_states() -> None:
    rng = np.random.default_rng(9)
    tracks = [Lollipop(1.0, 1.0), Lollipop(0.3, 1.2), Lollipop(1.5, 0.8), Lollipop(0.5, 1.0), Lollipop(2.0, 0.5)]
    tracks += [Lollipop(float(s), float(c)) for s, c in rng.uniform(0.05, 3.0, (10, 2))]
    seen: Counter[str] = Counter()
    for i, track in enumerate(tracks):
        for n in (0, 1, 2, 50, 9000):  # 9000: more than one block
            args = _lollipop_args(track, _special_states(track, rng, n))
            _, exc = assert_same("lollipop_skeleton_points", args, f"{track!r}, {n} special states")
            seen[f"raises {exc}"] += 1
            seen["degenerate"] += args[4]
        P = rng.uniform(-0.5, track.total_length + 0.5, (500, 2))  # off the track too
        assert_same("lollipop_skeleton_points", _lollipop_args(track, P), f"{track!r}, beyond the ends")
        P = rng.uniform(0.0, track.total_length, (300, 2))
        P[rng.random(P.shape) < 0.1] = rng.choice([np.nan, np.inf, -np.inf], 1)[0]
        assert_same("lollipop_skeleton_points", _lollipop_args(track, P), f"{track!r}, non-finite")
        if i < 3:  # scales of zero: the kernel divides by zero in a step
            for k in (2, 3):
                args = list(_lollipop_args(track, rng.uniform(0.0, track.total_length, (40, 2))))
                args[k] = 0.0
                assert_same("lollipop_skeleton_points", tuple(args), f"{track!r}, argument {k} zero")
    assert seen["degenerate"] >= 10 and seen["raises ZeroDivisionError"] >= 5 and seen["raises None"] >= 20, seen


def _model_values(ell: float, c: float) -> FloatArray:
    """Model coordinates where the scalar functions branch: the ends, P, ``ℓ ± VERTEX_TOL``, the half loop, the
    loop's end and ``VERTEX_TOL`` before it, each with its neighbours one ulp away; NaN."""
    h = 0.5 * c
    x = np.array([0.0, -0.0, ell, ell - h, ell + VERTEX_TOL, ell + h, ell + c, ell + (c - VERTEX_TOL), ell + c + h])
    return np.concatenate([x, np.nextafter(x, -np.inf), np.nextafter(x, np.inf), [np.nan]])


def test_the_vectorised_trace_and_point_index_equal_the_compiled_scalar_functions() -> None:
    # the two mpa functions the lollipop twin vectorises, on states at their branches (row by row against the
    # compiled scalar function; a ZeroDivisionError there is the twin's mask)
    rng = np.random.default_rng(23)
    hits: Counter[str] = Counter()
    for ell, c in ((1.0, 1.0), (0.5, 1.0), (0.3, 1.2), (1.5, 0.8), (2.0, 0.5), (0.7, 2.2), (1.0, 0.0)):
        h = 0.5 * c
        values = _model_values(ell, c)
        pairs = np.concatenate([rng.choice(values, (3000, 2)), rng.uniform(-0.2, ell + c + 0.2, (3000, 2))])
        pairs[::50, 1] = pairs[::50, 0]  # collisions
        a, b = np.ascontiguousarray(pairs[:, 0]), np.ascontiguousarray(pairs[:, 1])
        with np.errstate(all="ignore"):
            da, db, zero = paper_numpy._lollipop_trace(ell, c, a, b)
            edge, t, zero_p = paper_numpy._point_indices(h, ell, a, b)
        for k in range(len(a)):
            case = f"ell={ell} c={c} state=({a[k]!r}, {b[k]!r})"
            try:
                want = compiled._trace(ell, c, a[k], b[k])
                assert not zero[k] and _same(want[0], da[k]) and _same(want[1], db[k]), (case, want, da[k], db[k])
            except ZeroDivisionError:
                assert zero[k], case
                hits["trace divides by zero"] += 1
            try:
                e, tk = compiled._point_index(h, ell, a[k], b[k])
                assert not zero_p[k] and e == edge[k] and _same(tk, t[k]), (case, (e, tk), (edge[k], t[k]))
            except ZeroDivisionError:
                assert zero_p[k], case
                hits["point index divides by zero"] += 1
            if c and not a[k] <= ell + VERTEX_TOL and (a[k] - ell) % c == c - VERTEX_TOL:
                hits["phi at the loop's end"] += 1
    assert min(hits.values()) >= 1 and len(hits) == 3, hits


def test_collisions_raise_after_the_rows_before() -> None:
    # a state at a collision in the middle of the rows: the kernel fills the rows before it, then raises
    track = Lollipop(1.0, 1.0)
    sk = skeleton_of(track)
    ell, c = float(sk.model.stick), float(sk.model.loop)
    P = np.array([[0.2, 1.5], [0.4, 1.3], [ell, ell + c], [0.1, 0.9]])  # A at P, B at the loop's end: one place
    args = _lollipop_args(track, P)
    _, exc = assert_same("lollipop_skeleton_points", args, "a collision at the pole")
    assert exc == "ZeroDivisionError"
    edge, t = np.full(4, -1, dtype=np.int64), np.full(4, -1.0)
    with pytest.raises(ZeroDivisionError):
        paper_numpy.lollipop_skeleton_points(*args[:5], edge, t)
    assert (edge[:2] >= 0).all() and (edge[2:] == -1).all()


def test_circle_skeleton_points_twin_on_special_states() -> None:
    rng = np.random.default_rng(13)
    for c in (1.0, 0.7, 2.5, 1e-9, 1e9, 0.0):
        track = Circle(c if c > 0 else 1.0)
        for n in (0, 1, 3, 5000):
            P = _special_states(track, rng, n) * (c / track.loop)
            P[rng.random(P.shape) < 0.05] = np.nan
            P[rng.random(P.shape) < 0.05] = -rng.uniform(0.0, 3 * c)
            args = (np.ascontiguousarray(P), c, np.empty(n, dtype=np.int64), np.empty(n))
            _, exc = assert_same("circle_skeleton_points", args, f"circle {c}, {n} states")
            assert (exc is not None) == (c == 0.0 and n > 0)


def test_densify_twins_on_special_legs() -> None:
    rng = np.random.default_rng(17)
    seen: Counter[str] = Counter()
    for i in range(400):
        step = float(rng.choice([0.004, 0.008, 1e-3, 0.37, 1.0, 1e-9]))
        n = int(rng.choice([0, 1, 2, 3, 30, 300]))
        legs = rng.uniform(-2.5, 2.5, (max(n - 1, 0), 2)) * step
        exact = rng.random(legs.shape) < 0.3  # exactly a whole number of steps, and one ulp beside
        legs[exact] = rng.choice([-2.0, -1.0, 0.0, 1.0, 2.0], int(exact.sum())) * step
        legs[exact] = np.where(rng.random(int(exact.sum())) < 0.5, legs[exact], np.nextafter(legs[exact], np.inf))
        S = np.concatenate([rng.uniform(-3.0, 3.0, (min(n, 1), 2)), legs]).cumsum(axis=0)
        if i % 5 == 0 and n:
            S[rng.random(S.shape) < 0.1] = rng.choice([np.nan, np.inf, -np.inf, 1e300, -0.0])
        S = np.ascontiguousarray(S)
        cut, _ = assert_same("needs_densify", (S, step), f"case {i}")
        seen[f"cut {cut}"] += 1
        if n and (np.isfinite(S).all() or i % 10 == 0):
            dense, _ = assert_same("dense_polyline", (S, step), f"case {i}")
            seen["dense rows"] += len(dense)
    for n in (0, 1, 2, 5):  # step 0: a division by zero as soon as there is a leg
        S = np.ascontiguousarray(rng.uniform(0.0, 1.0, (n, 2)))
        assert_same("needs_densify", (S, 0.0), f"step 0, {n} rows")
        if n:
            assert_same("dense_polyline", (S, 0.0), f"step 0, {n} rows")
    assert seen["cut True"] >= 100 and seen["cut False"] >= 100 and seen["dense rows"] >= 20000, seen
    with pytest.raises(IndexError):  # no row: the kernel reads outside S (not called on it), the twin says so
        paper_numpy.dense_polyline(np.zeros((0, 2)), 0.1)


def test_word_samples_twin_on_random_edges() -> None:
    rng = np.random.default_rng(21)
    jumps = Counter[bool]()
    for track in (Lollipop(1.0, 1.0), Lollipop(0.3, 1.2), Circle(1.0)):
        adjacent = skeleton_of(track).graph.adjacent_edges
        ne = len(adjacent)
        for n in (0, 1, 2, 3, 10, 200, 5000):
            for p_change in (0.0, 0.02, 0.5, 1.0):
                edge = np.zeros(n, dtype=np.int64)
                change = rng.random(n) < p_change
                edge = np.cumsum(change * rng.integers(1, ne, n)) % ne
                (_, jump), _ = assert_same("word_samples", (edge.astype(np.int64), adjacent), f"{n} samples")
                jumps[jump] += 1
    assert jumps[True] >= 10 and jumps[False] >= 10, jumps


# ------------------------------------------------------------------------------------------ hypothesis
_HL = Lollipop(1.0, 1.0)
_FLOATS = st.floats(-1.0, 3.5) | st.sampled_from([0.0, -0.0, 1.0, 2.0, 0.5, 1.5, np.nextafter(1.0, 2.0), 5e-324])


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(P=hnp.arrays(float, st.tuples(st.integers(0, 12), st.just(2)), elements=_FLOATS), which=st.integers(0, 3))
def test_skeleton_points_twins_hypothesis(P: FloatArray, which: int) -> None:
    track = (Lollipop(1.0, 1.0), Lollipop(0.3, 1.2), Lollipop(1.5, 0.8), Circle(2.0))[which]
    P = np.ascontiguousarray(P)
    if isinstance(track, Circle):
        assert_same("circle_skeleton_points", (P, 2.0, np.empty(len(P), np.int64), np.empty(len(P))), "hypothesis")
    else:
        assert_same("lollipop_skeleton_points", _lollipop_args(track, P), "hypothesis")


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    S=hnp.arrays(float, st.tuples(st.integers(1, 12), st.just(2)), elements=_FLOATS),
    step=st.sampled_from([0.004, 0.1, 0.5, 1.0, 1e-300]),
)
def test_densify_twins_hypothesis(S: FloatArray, step: float) -> None:
    S = np.ascontiguousarray(S)
    assert_same("needs_densify", (S, step), "hypothesis")
    if step >= 1e-3:
        assert_same("dense_polyline", (S, step), "hypothesis")


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data(), n=st.integers(0, 15))
def test_word_samples_and_track_positions_twins_hypothesis(data: st.DataObject, n: int) -> None:
    adjacent = skeleton_of(_HL).graph.adjacent_edges
    edge = data.draw(hnp.arrays(np.int64, n, elements=st.integers(0, len(adjacent) - 1)))
    assert_same("word_samples", (np.ascontiguousarray(edge), adjacent), "hypothesis")
    plan_args = data.draw(st.sampled_from(_HROUTES))
    S = data.draw(hnp.arrays(float, (n, 2), elements=st.floats(-3.0, 6.0) | st.sampled_from(_HBREAKS)))
    assert_same("track_positions", (np.ascontiguousarray(S), *plan_args, np.empty((n, 2))), "hypothesis")


def _hypothesis_routes() -> list[tuple[Any, ...]]:
    """The routes' affine forms (without ``S`` and ``out``) of a few lollipop, circle and interval plans."""
    from mpa import make_planner

    out = []
    for track, queries in (
        (_HL, [((0.1, 1.6), (1.9, 0.3)), ((0.9, 1.2), (0.2, 1.7))]),
        (Circle(1.0), [((0.1, 0.6), (0.7, 0.2))]),
        (Interval(2.0), [((0.1, 1.0), (0.9, 1.9))]),
    ):
        planner = make_planner(track, 0.05)
        for start, goal in queries:
            ra, rb = (r.affine_form() for r in planner.plan(start, goal).routes)
            out.append((*ra[:4], *rb[:4], *ra[4:]))
    return out


_HROUTES = _hypothesis_routes()
_HBREAKS = sorted({float(x) for r in _HROUTES for br in (r[0], r[4]) for x in br} | {0.0, -0.0})


# ------------------------------------------------------------------------------------------ the gate's decisions
def test_the_gates_reports_are_the_same_with_the_twins() -> None:
    metas, arrays, kinds, _ = _gate_cases()
    paper = [i for i, m in enumerate(metas) if m["kind"] == "paper"]
    metas = [metas[i] for i in paper]
    renumber = {str(i): str(j) for j, i in enumerate(paper)}  # the paper cases' arrays, numbered again
    arrays = {
        f"{renumber[k.split('_', 1)[0]]}_{k.split('_', 1)[1]}": v
        for k, v in arrays.items()
        if k.split("_", 1)[0] in renumber
    }
    kernels = run_gate_cases(metas, arrays)
    with pytest.MonkeyPatch.context() as mp:
        for name in KERNELS:
            mp.setattr(gate, name, getattr(paper_numpy, name))
        mp.setattr(planview, "track_positions", paper_numpy.track_positions)
        twins = run_gate_cases(metas, arrays)
    assert len(twins) == len(kernels) == len(metas) >= 200
    for j, i in enumerate(paper):
        assert twins[j] == kernels[j], f"case {i} ({kinds[i][0]}, {metas[j]}): twins {twins[j]} != kernels {kernels[j]}"
    outcomes = Counter(json.loads(c[0])["ok"] if c[0].startswith("{") else c[0] for c in kernels)
    assert outcomes[True] >= 8 and outcomes[False] >= 150, outcomes
    words = Counter(f for c in kernels if c[0].startswith("{") for f in json.loads(c[0])["failures"] if "homotopy" in f)
    assert sum(words.values()) >= 5, words  # the word check decided some cases


# ------------------------------------------------------------------------------------------ a process without numba
_ONE_SHOT = """
import hashlib, json, sys
import numpy as np
import trajopt.path.planview as planview
import trajopt.verify.gate as gate
import trajopt.verify.kernels as kernels
from trajopt.verify import paper_numpy

names = {names}
if sys.argv[1] == "twins":
    for module in (kernels, gate):
        for name in names:
            setattr(module, name, getattr(paper_numpy, name))
    planview.track_positions = paper_numpy.track_positions
from mpa import Circle, Interval, Lollipop
from trajopt import TrajectoryGenerator

out = []
for track, clearance, rate, start, goal in {queries}:
    traj = TrajectoryGenerator(track, clearance=clearance, rate=rate).generate(start, goal)
    rows = np.concatenate([traj.t[:, None], traj.track, traj.s, traj.v, traj.a, traj.j], axis=1)
    out.append([hashlib.sha256(rows.tobytes()).hexdigest(), list(traj.plan.word), traj.verification["ok"], len(rows)])
print(json.dumps({{"numba": "numba" in sys.modules, "out": out}}))
"""

_QUERIES = (
    "[(Lollipop(1.0, 1.0), 0.05, 100.0, (0.1, 1.6), (1.9, 0.3)),"
    " (Lollipop(0.3, 1.2), 0.0, 25.0, (0.1, 0.9), (1.2, 0.2)),"
    " (Lollipop(1.5, 0.8), 0.1, 250.0, (2.0, 0.2), (0.4, 2.2)), (Circle(1.0), 0.1, 100.0, (0.1, 0.6), (0.7, 0.2)),"
    " (Interval(2.0), 0.1, 100.0, (0.1, 1.0), (0.9, 1.9))]"
)


def test_a_numpy_process_with_the_twins_makes_numbas_trajectories_without_numba() -> None:
    code = _ONE_SHOT.format(names=tuple(KERNELS), queries=_QUERIES)
    results = {}
    for mode, env_mode in (("twins", "numpy"), ("kernels", "numba")):
        env = {**os.environ, "PYTHONPATH": str(ROOT), "TRAJOPT_KERNELS": env_mode}
        done = subprocess.run(
            [sys.executable, "-c", code, mode], cwd=ROOT, env=env, capture_output=True, text=True, timeout=300
        )
        assert done.returncode == 0, done.stderr[-3000:]
        results[mode] = json.loads(done.stdout.strip().splitlines()[-1])
    assert results["twins"]["numba"] is False  # the paper's pipeline ran without importing numba
    assert results["kernels"]["numba"] is True
    assert results["twins"]["out"] == results["kernels"]["out"]
    assert all(ok for _, _, ok, _ in results["twins"]["out"]) and len(results["twins"]["out"]) == 5


_CLI = """
import sys
from trajopt._numba import use_numpy_twins
if sys.argv[1] == "twins":
    use_numpy_twins()
    import trajopt.path.planview as planview
    import trajopt.verify.gate as gate
    import trajopt.verify.kernels as kernels
    from trajopt.verify import paper_numpy
    for module in (kernels, gate):
        for name in paper_numpy.__all__:
            setattr(module, name, getattr(paper_numpy, name))
    planview.track_positions = paper_numpy.track_positions
from trajopt.cli.main import main
codes = [main(args) for args in ({commands})]
print(codes, "numba" in sys.modules)
"""


def _files(out: Path) -> dict[str, Any]:
    """Every file under ``out`` (bytes; ``summary.json`` parsed, without the times the run took)."""
    files: dict[str, Any] = {}
    for path in sorted(out.rglob("*")):
        if path.is_file():
            files[str(path.relative_to(out))] = path.read_bytes()
    for name in [n for n in files if n.endswith("summary.json")]:
        summary = json.loads(files[name])
        summary.pop("timings")
        summary["solver"].pop("jerk_time")
        files[name] = summary
    return files


def test_the_command_lines_files_are_numbas_with_the_twins(tmp_path: Path) -> None:
    # `mpa trajectory --track lollipop|circle` and `mpa demo` in a process in the numpy mode with the twins patched
    # in: numba never imported, every file the same as numba's (but the run's own times)
    files = {}
    for kind in ("twins", "numba"):
        out = tmp_path / kind
        lines = (
            f"trajectory --track lollipop --stick 0.3 --loop 1.2 --start 0.1 0.9 --goal 1.2 0.2 --out {out}/lollipop",
            f"trajectory --track circle --start 0.1 0.6 --goal 0.7 0.2 --rate 40 --clearance 0 --out {out}/circle",
            f"demo --out {out}/demo",
        )
        commands = [line.split() for line in lines]
        commands[0] += ["--format", "csv,ros2-yaml,pvt"]
        env = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
        env.pop("TRAJOPT_KERNELS", None)
        done = subprocess.run(
            [sys.executable, "-c", _CLI.format(commands=repr(commands)), kind],
            cwd=ROOT,
            env=env,
            capture_output=True,
            text=True,
            timeout=300,
        )
        assert done.returncode == 0, done.stderr[-3000:]
        assert done.stdout.split()[-4:] == ["[0,", "0,", "0]", str(kind == "numba")], done.stdout
        files[kind] = _files(out)
    assert len(files["twins"]) >= 10 and files["twins"].keys() == files["numba"].keys()
    for name, content in files["twins"].items():
        assert content == files["numba"][name], name


# ------------------------------------------------------------------------------------------ the module
def test_the_twins_import_neither_numba_nor_the_kernels() -> None:
    tree = ast.parse(Path(str(paper_numpy.__file__)).read_text())
    names = {a.name for node in ast.walk(tree) if isinstance(node, ast.Import) for a in node.names}
    names |= {str(node.module) for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)}
    shared = {"trajopt.verify.elementwise"}  # the twins' elementwise helpers (numpy only)
    assert all(n.split(".")[0] in {"__future__", "math", "numpy", "mpa"} or n in shared for n in names), names
    assert set(paper_numpy.__all__) == set(KERNELS)
    code = (
        "import sys\nimport trajopt.verify.paper_numpy\n"
        "print([m for m in ('numba', 'llvmlite', 'trajopt.verify.kernels') if m in sys.modules])\n"
    )
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and done.stdout.strip() == "[]", (done.stdout, done.stderr[-2000:])
