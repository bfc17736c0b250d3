"""Stage 4, verification: an independent check of a setpoint grid before anything leaves the library.

The gate only looks at the rows (times, track and route coordinates, their derivatives), the track metric, the
robots' routes and the limits; it does not use any of the generator's geometry. Checks:

- the grid: finite values, ``t`` starts at 0 with constant step ``1/rate``;
- consistency: ``track == route.position(s)`` for both robots (graph distance ≤ :data:`POSITION_TOL`);
- endpoints: first row at the start and last row at the goal, both at rest (``v = a = 0``);
- limits: ``|v|, |a|, |j| ≤ limit·(1 + LIMIT_RTOL)`` per robot at every row;
- separation at every row: ``d ≥ D − SEPARATION_TOL``;
- separation between rows: the chord between two rows (both robots linear in ``s``) is cut where a robot passes a
  junction of its route; on each piece both robots stay on one edge, the distance is the minimum of the cell's
  affine terms (and ``|s − t|`` on one edge), and its minimum is at an end unless the robots meet there
  (:meth:`mpa.geometry.GraphGeometry.segment_min`, exact; pieces where ``d_k + d_{k+1} > |Δs_A| + |Δs_B|``
  exclude meeting at once). The real motion deviates from the chord by at most ``a_int·Δt²/8`` per robot,
  ``a_int = min(amax, max(|a_k|, |a_k+1|) + jmax·Δt/2)``; the distance is 1-Lipschitz in each robot's
  coordinate, so ``min_chord − Σ dev ≥ D − SEPARATION_TOL`` is required;
- homotopy class: the reduced skeleton word of the motion (:func:`mpa.homotopy.path_word`, rows refined
  along the chords) equals the plan's.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa.errors import MPAError, PlanningError
from mpa.geometry import DirectedRoute, GraphGeometry, densify_polyline
from mpa.homotopy import path_word
from mpa.routes import Route, directed_route
from mpa.tracks import Track
from trajopt.timing import Limits

__all__ = [
    "CLASS_FAILURE_PREFIXES",
    "LIMIT_RTOL",
    "POSITION_TOL",
    "SEPARATION_TOL",
    "VerificationError",
    "VerificationReport",
    "between_rows_separation",
    "class_failures_only",
    "verify_graph_setpoints",
    "verify_setpoints",
]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
#: Relative tolerance of the limit checks.
LIMIT_RTOL = 1e-6
#: Absolute tolerance (metres) of the separation checks.
SEPARATION_TOL = 1e-9
#: Absolute tolerance (metres, m/s, m/s²) of positions, endpoints and rest.
POSITION_TOL = 1e-9
#: Time grid tolerance (s).
TIME_TOL = 1e-9


@dataclass(frozen=True)
class VerificationReport:
    """Outcome of :func:`verify_setpoints`.

    Attributes
    ----------
    ok : bool
        Every check passed.
    failures : tuple of str
        One message per failed check (empty when ``ok``).
    min_separation : float
        Smallest graph distance at the rows (metres).
    min_separation_between : float
        Lower bound of the distance between rows (metres).
    peak_ratio : dict
        ``{"v": (A, B), "a": …, "j": …}``: the largest ``|value| / limit`` per robot.
    word : tuple of str
        The motion's reduced skeleton word.
    """

    ok: bool
    failures: tuple[str, ...]
    min_separation: float
    min_separation_between: float
    peak_ratio: dict[str, tuple[float, float]]
    word: tuple[str, ...]

    def to_dict(self) -> dict[str, object]:
        """JSON-ready summary."""
        return {
            "ok": self.ok,
            "failures": list(self.failures),
            "min_separation": self.min_separation,
            "min_separation_between": self.min_separation_between,
            "peak_ratio": {k: list(v) for k, v in self.peak_ratio.items()},
            "word": list(self.word),
        }


class VerificationError(PlanningError):
    """A setpoint grid failed the verification gate (``report`` says which checks)."""

    def __init__(self, report: VerificationReport) -> None:
        super().__init__("verification failed: " + "; ".join(report.failures))
        self.report = report


def _chord_min(
    geometry: GraphGeometry,
    droutes: Sequence[DirectedRoute],
    s0: FloatArray,
    s1: FloatArray,
    d0: FloatArray,
    d1: FloatArray,
) -> FloatArray:
    """Exact minimum of the distance along chords ``s0 → s1`` (shape (M, 2)) on which each robot stays on one edge.

    On such a chord each robot's offset is affine in the chord parameter, so the distance is the minimum of the
    cell's affine terms (and ``|s − t|`` when both robots are on one edge): its minimum is at an end unless the
    robots meet on one edge (:meth:`mpa.geometry.GraphGeometry.segment_min`, exact). Meeting is excluded at once
    when ``d0 + d1 > |ΔsA| + |ΔsB|`` (the distance is 1-Lipschitz in each route coordinate) with a margin of
    1e-9 relative and 1e-12 m (head-on robots that meet have ``d0 + d1 = |ΔsA| + |ΔsB|`` exactly, which
    rounding can tip either way); the other chords (robots close together, heading at each other, or following
    each other on one edge) get the exact cell minimum.
    """
    out = np.minimum(d0, d1)
    span = np.abs(s1[:, 0] - s0[:, 0]) + np.abs(s1[:, 1] - s0[:, 1])
    # robots heading straight at each other have d0 + d1 == span exactly, and meet: exclude only with a margin
    open_ = np.flatnonzero(~(d0 + d1 > span * (1.0 + 1e-9) + 1e-12))
    if len(open_) == 0:
        return out
    q0, q1 = s0[open_], s1[open_]
    mid = 0.5 * (q0 + q1)
    edges: list[IntArray] = []
    off0: list[FloatArray] = []
    off1: list[FloatArray] = []
    for r, route in enumerate(droutes):
        i = route.piece_index(np.clip(mid[:, r], route.breaks[0], route.breaks[-1]))
        edges.append(route.edges[i])
        for q, off in ((q0, off0), (q1, off1)):
            x = np.clip(q[:, r], route.breaks[0], route.breaks[-1])
            off.append(route.offsets_on(i, x))
    exact = geometry.segment_min(edges[0], edges[1], np.stack(off0, axis=1), np.stack(off1, axis=1))
    out[open_] = np.minimum(out[open_], exact)
    return out


def _graph_form(track: Track, routes: Sequence[Route]) -> tuple[GraphGeometry, tuple[DirectedRoute, DirectedRoute]]:
    """A paper track's metric and routes in the graph form the gate works in (edges ``stick``/``loop``)."""
    return track.as_graph_track().geometry, (directed_route(routes[0]), directed_route(routes[1]))


def between_rows_separation(
    track: Track | GraphGeometry,
    routes: Sequence[Route] | Sequence[DirectedRoute],
    s: FloatArray,
    a: FloatArray,
    dt: float,
    limits: Limits,
) -> FloatArray:
    """Lower bound of the graph distance between consecutive rows. Shape (N−1,).

    Parameters
    ----------
    track : Track or GraphGeometry
        A paper track (its routes are :class:`~mpa.routes.Route`) or the metric of a track graph (its routes are
        :class:`~mpa.geometry.DirectedRoute`).
    routes : sequence of Route or DirectedRoute
        Route of A and of B.
    s : ndarray, shape (N, 2)
        Route coordinates at the rows.
    a : ndarray, shape (N, 2)
        Accelerations at the rows.
    dt : float
        Row step (s).
    limits : Limits
    """
    if isinstance(track, Track):
        geometry, droutes = _graph_form(track, routes)  # type: ignore[arg-type]
    else:
        geometry, droutes = track, (routes[0], routes[1])  # type: ignore[assignment]
    if len(s) < 2:
        return np.zeros(0)
    (ea, oa), (eb, ob) = droutes[0].positions(s[:, 0]), droutes[1].positions(s[:, 1])
    return _between_rows(geometry, droutes, s, geometry.distance(ea, oa, eb, ob), a, dt, limits)


def _between_rows(
    geometry: GraphGeometry,
    droutes: Sequence[DirectedRoute],
    s: FloatArray,
    d_rows: FloatArray,
    a: FloatArray,
    dt: float,
    limits: Limits,
) -> FloatArray:
    """:func:`between_rows_separation` given the distances at the rows' route positions ``d_rows`` (shape (N,))."""
    n = len(s)
    kk, p0, p1, inner0, inner1 = _chords_cut_at_junctions(droutes, s)

    def dist(q: FloatArray) -> FloatArray:
        if len(q) <= _FEW:  # a few points (the cuts): plain Python, the same positions and distances
            return np.array([_distance_at(geometry, droutes, qa, qb) for qa, qb in q.tolist()])
        (ea, oa), (eb, ob) = droutes[0].positions(q[:, 0]), droutes[1].positions(q[:, 1])
        return geometry.distance(ea, oa, eb, ob)

    d0, d1 = d_rows[kk], d_rows[kk + 1]  # a piece that starts (ends) at a row: the row's distance
    n0, n1 = int(np.count_nonzero(inner0)), int(np.count_nonzero(inner1))
    if n0 + n1:  # ends at cuts, in one call
        d_cut = dist(np.concatenate([p0[inner0], p1[inner1]]))
        d0[inner0], d1[inner1] = d_cut[:n0], d_cut[n0:]
    sub = _chord_min(geometry, droutes, p0, p1, d0, d1)
    if len(kk) == n - 1:  # no cut: piece k is row step k
        chord = sub
    else:
        chord = np.full(n - 1, np.inf)
        np.minimum.at(chord, kk, sub)
    return chord - _deviation_from_chords(a, dt, limits)


#: Up to this many points the gate evaluates distances in plain Python (:func:`_distance_at`).
_FEW = 16


def _distance_at(geometry: GraphGeometry, droutes: Sequence[DirectedRoute], qa: float, qb: float) -> float:
    """The graph distance at route coordinates ``(qa, qb)``, in plain Python (as ``positions`` + ``distance``)."""
    (ea, oa), (eb, ob) = droutes[0].position_scalar(qa), droutes[1].position_scalar(qb)
    return geometry.distance_scalar(ea, oa, eb, ob)


def _chords_cut_at_junctions(
    droutes: Sequence[DirectedRoute], s: FloatArray
) -> tuple[NDArray[np.int64], FloatArray, FloatArray, NDArray[np.bool_], NDArray[np.bool_]]:
    """The chords between consecutive rows ``s`` (shape (N, 2)), cut where a robot changes edge.

    Returns ``(kk, p0, p1, inner0, inner1)``: the row step ``k`` of each piece (shape (M,)), the piece's ends
    (shape (M, 2)), and whether each end lies inside the step (a cut) rather than on a row; on a piece both
    robots stay on one edge each. Rows without a cut are one chord (ends exactly the rows); without any cut the
    pieces are the row steps in order (``kk = 0 … N−2``). The few cut rows are split in plain Python.
    """
    n = len(s)
    cuts: dict[int, list[float]] = {}
    for r in (0, 1):
        junc = droutes[r].breaks[1:-1]
        if len(junc) == 0:
            continue
        col = s[:, r]
        lo, hi = np.minimum(col[:-1], col[1:]), np.maximum(col[:-1], col[1:])
        rows = np.flatnonzero(np.searchsorted(junc, hi, side="left") - np.searchsorted(junc, lo, side="right"))
        if len(rows) == 0:
            continue
        jl = junc.tolist()
        for k in rows.tolist():
            a, b = float(col[k]), float(col[k + 1])
            low, high = min(a, b), max(a, b)
            cuts.setdefault(k, []).extend((x - a) / (b - a) for x in jl if low < x < high)
    if not cuts:
        none = np.zeros(n - 1, dtype=bool)
        return np.arange(n - 1), s[:-1], s[1:], none, none
    # rows without a cut are one chord [0, 1]; a cut row is split at its cuts (ends as s_k + t·(s_k+1 − s_k))
    ks: list[int] = []
    ends0: list[list[float]] = []
    ends1: list[list[float]] = []
    in0: list[bool] = []
    in1: list[bool] = []
    for row in cuts:
        a, b = s[row].tolist(), s[row + 1].tolist()
        ds = (b[0] - a[0], b[1] - a[1])
        ts = [0.0, *sorted(cuts[row]), 1.0]
        for t0, t1 in itertools.pairwise(ts):
            ks.append(row)
            ends0.append(a if t0 == 0.0 else [a[0] + t0 * ds[0], a[1] + t0 * ds[1]])
            ends1.append(b if t1 == 1.0 else [a[0] + t1 * ds[0], a[1] + t1 * ds[1]])
            in0.append(t0 != 0.0)
            in1.append(t1 != 1.0)
    plain = np.ones(n - 1, dtype=bool)
    plain[list(cuts)] = False
    rows_plain = np.flatnonzero(plain)
    kk = np.concatenate([rows_plain, np.asarray(ks, dtype=np.int64)])
    p0 = np.concatenate([s[rows_plain], np.asarray(ends0)])
    p1 = np.concatenate([s[rows_plain + 1], np.asarray(ends1)])
    no = np.zeros(len(rows_plain), dtype=bool)
    return kk, p0, p1, np.concatenate([no, in0]), np.concatenate([no, in1])


def _deviation_from_chords(a: FloatArray, dt: float, limits: Limits) -> FloatArray:
    """Bound (m) of how far both robots together leave the chord between consecutive rows. Shape (N−1,).

    Per robot ``a_int·Δt²/8`` with ``a_int = min(amax, max(|a_k|, |a_k+1|) + jmax·Δt/2)``.
    """
    amax, jmax = limits.a, limits.j
    a_int = np.minimum(amax[None, :], np.maximum(np.abs(a[:-1]), np.abs(a[1:])) + jmax[None, :] * dt / 2)
    return (a_int[:, 0] + a_int[:, 1]) * (dt * dt / 8.0)  # (a sum over a length-2 axis is slow in numpy)


def verify_setpoints(
    track: Track,
    routes: Sequence[Route],
    t: ArrayLike,
    track_pos: ArrayLike,
    s: ArrayLike,
    v: ArrayLike,
    a: ArrayLike,
    j: ArrayLike,
    *,
    limits: Limits,
    clearance: float,
    start: ArrayLike,
    goal: ArrayLike,
    word: Sequence[str],
    rate: float,
) -> VerificationReport:
    """Check a setpoint grid on one of the paper's tracks (see the module docstring for the list of checks).

    The rows are checked in the graph form of the track (:meth:`mpa.tracks.Track.as_graph_track`, edges
    ``stick`` and ``loop``) by :func:`verify_graph_setpoints`, and the motion's skeleton word against ``word``.

    Parameters
    ----------
    track : Track
    routes : sequence of Route
        Route of A and of B (the plan's).
    t : array_like, shape (N,)
        Times (s).
    track_pos : array_like, shape (N, 2)
        Track coordinates of A and B (metres).
    s, v, a, j : array_like, shape (N, 2)
        Route coordinates (m) and their derivatives (m/s, m/s², m/s³).
    limits : Limits
    clearance : float
        Required separation D (metres).
    start, goal : array_like, shape (2,)
        Track coordinates.
    word : sequence of str
        The plan's reduced skeleton word.
    rate : float
        Row rate (Hz).

    Returns
    -------
    VerificationReport
        Never raises for a failed check; ``ok`` is False and ``failures`` lists them.
    """
    geometry, droutes = _graph_form(track, routes)
    P = np.asarray(track_pos, dtype=float)
    if P.ndim != 2 or P.shape[1:] != (2,):
        nan = float("nan")
        return VerificationReport(False, ("arrays have inconsistent shapes",), nan, nan, {}, ())
    edges, offsets = _graph_positions(track, P)
    rep = verify_graph_setpoints(
        geometry,
        droutes,
        t,
        edges,
        offsets,
        s,
        v,
        a,
        j,
        limits=limits,
        clearance=clearance,
        start=_graph_query_point(track, start),
        goal=_graph_query_point(track, goal),
        rate=rate,
    )
    if not np.isfinite(rep.min_separation):
        return rep
    w, word_fails = _word_check(track, routes, np.asarray(s, dtype=float), word, P)
    fails = [*rep.failures, *word_fails]
    return VerificationReport(
        not fails, tuple(fails), rep.min_separation, rep.min_separation_between, rep.peak_ratio, tuple(w)
    )


#: How :func:`verify_setpoints` words a failed homotopy-class check (the start of the failure's message).
CLASS_FAILURE_PREFIXES = ("homotopy class ", "cannot compute the homotopy class")


def class_failures_only(report: VerificationReport) -> bool:
    """Whether ``report`` failed on the homotopy class alone (every other check passed).

    Parameters
    ----------
    report : VerificationReport

    Returns
    -------
    bool
        False when ``report.ok`` or when any other check failed.
    """
    return bool(report.failures) and all(f.startswith(CLASS_FAILURE_PREFIXES) for f in report.failures)


def _graph_positions(track: Track, P: FloatArray) -> tuple[NDArray[np.int64], FloatArray]:
    """Track coordinates ``P`` (shape (N, 2)) as graph positions: edges and offsets, each shape (N, 2).

    If any coordinate is not finite every offset is NaN (the graph check then reports non-finite values).
    """
    finite = bool(np.isfinite(P).all())
    edges, offsets = track.to_graph_position(P if finite else np.where(np.isfinite(P), P, 0.0))
    return edges, offsets if finite else np.full(P.shape, np.nan)


def _graph_query_point(track: Track, q: ArrayLike) -> tuple[tuple[int, float], tuple[int, float]]:
    """Track coordinates of A and B (shape (2,)) as positions ``(edge, offset)`` of the track's graph form."""
    e, o = track.to_graph_position(np.asarray(q, dtype=float))
    return (int(e[0]), float(o[0])), (int(e[1]), float(o[1]))


def _word_check(
    track: Track, routes: Sequence[Route], S: FloatArray, word: Sequence[str], P: FloatArray | None = None
) -> tuple[tuple[str, ...], list[str]]:
    """The motion's reduced skeleton word, and the failure if not ``word``.

    The word is taken of the rows' track coordinates ``P`` (shape (N, 2), checked against the routes elsewhere)
    when consecutive rows are close enough (route coordinates ``S`` at most ``0.004 × track length`` apart),
    else of the route positions of ``S`` refined along the chords to that step.
    """
    try:
        step = 0.004 * track.total_length
        dense = densify_polyline(S, step)
        if P is not None and len(dense) == len(S):
            states = P
        else:
            states = np.stack([routes[0].position(dense[:, 0]), routes[1].position(dense[:, 1])], axis=1)
        w = path_word(track, states)
    except MPAError as exc:
        return (), [f"cannot compute the homotopy class: {exc}"]
    if tuple(w) != tuple(word):
        got, want = " ".join(w) or "(trivial)", " ".join(word) or "(trivial)"
        return tuple(w), [f"homotopy class {got} differs from the plan's {want}"]
    return tuple(w), []


def verify_graph_setpoints(
    geometry: GraphGeometry,
    routes: Sequence[DirectedRoute],
    t: ArrayLike,
    edges: ArrayLike,
    offsets: ArrayLike,
    s: ArrayLike,
    v: ArrayLike,
    a: ArrayLike,
    j: ArrayLike,
    *,
    limits: Limits,
    clearance: float,
    start: tuple[tuple[int, float], tuple[int, float]],
    goal: tuple[tuple[int, float], tuple[int, float]],
    rate: float,
) -> VerificationReport:
    """Check a setpoint grid on any track graph (see the module docstring; no skeleton word on a graph).

    Parameters
    ----------
    geometry : GraphGeometry
        The exact metric of the track graph.
    routes : sequence of DirectedRoute
        Route of A and of B.
    t : array_like, shape (N,)
        Times (s).
    edges, offsets : array_like, shape (N, 2)
        Positions of A and B: edge index and offset from the edge's tail (m).
    s, v, a, j : array_like, shape (N, 2)
        Route coordinates (m) and their derivatives (m/s, m/s², m/s³).
    limits : Limits
    clearance : float
        Required separation D (metres).
    start, goal : pair of (int, float)
        Positions ``(edge, offset)`` of A and B.
    rate : float
        Row rate (Hz).

    Returns
    -------
    VerificationReport
        Never raises for a failed check; ``ok`` is False and ``failures`` lists them; ``word`` is empty.
    """
    tt = np.asarray(t, dtype=float)
    E = np.asarray(edges)
    arrs = {k: np.asarray(x, dtype=float) for k, x in (("offset", offsets), ("s", s), ("v", v), ("a", a), ("j", j))}
    bad_input = _input_failure(tt, E, arrs, len(geometry.lengths))
    if bad_input:
        nan = float("nan")
        return VerificationReport(False, (bad_input,), nan, nan, {}, ())
    n = len(tt)
    dt = 1.0 / float(rate)
    fails: list[str] = []
    if abs(tt[0]) > TIME_TOL or np.any(np.abs(tt - dt * np.arange(n)) > TIME_TOL * max(1.0, n * dt)):
        fails.append(f"time grid is not 0, 1/{rate:g}, 2/{rate:g}, …")
    OFF, S, V, A, J = arrs["offset"], arrs["s"], arrs["v"], arrs["a"], arrs["j"]
    # every graph distance of the gate in one call: the rows' separation, each robot's row against its route
    # position (consistency), and the separation at the route positions (the chords' ends)
    (ra_e, ra_o), (rb_e, rb_o) = routes[0].positions(S[:, 0]), routes[1].positions(S[:, 1])
    all_d = geometry.distance(
        np.concatenate([E[:, 0], ra_e, rb_e, ra_e]),
        np.concatenate([OFF[:, 0], ra_o, rb_o, ra_o]),
        np.concatenate([E[:, 1], E[:, 0], E[:, 1], rb_e]),
        np.concatenate([OFF[:, 1], OFF[:, 0], OFF[:, 1], rb_o]),
    )
    d, err_a, err_b, d_route = all_d[:n], all_d[n : 2 * n], all_d[2 * n : 3 * n], all_d[3 * n :]
    fails += _route_consistency_failures(E, OFF, S, ((ra_e, ra_o, err_a), (rb_e, rb_o, err_b)))
    fails += _endpoint_failures(geometry, E, OFF, V, A, start, goal)
    peak, limit_fails = _limit_check(V, A, J, limits)
    fails += limit_fails
    between = _between_rows(geometry, routes, S, d_route, A, dt, limits)
    dmin, bmin, sep_fails = _separation_check(d, between, clearance)
    fails += sep_fails
    return VerificationReport(not fails, tuple(fails), dmin, bmin, peak, ())


def _input_failure(tt: FloatArray, E: NDArray[Any], arrs: dict[str, FloatArray], n_edges: int) -> str:
    """Why the arrays cannot be checked at all (shapes, non-finite values, edge indices), or ``""``."""
    n = len(tt)
    if n == 0 or tt.ndim != 1 or E.shape != (n, 2) or any(x.shape != (n, 2) for x in arrs.values()):
        return "arrays have inconsistent shapes"
    if not (np.isfinite(tt).all() and np.isfinite(np.stack(list(arrs.values()))).all()):
        return "non-finite values in the setpoints"
    if not np.issubdtype(E.dtype, np.integer) or E.min() < 0 or E.max() >= n_edges:
        return "edge indices out of range"
    return ""


def _route_consistency_failures(
    E: NDArray[Any],
    OFF: FloatArray,
    S: FloatArray,
    at_route: tuple[tuple[NDArray[Any], FloatArray, FloatArray], tuple[NDArray[Any], FloatArray, FloatArray]],
) -> list[str]:
    """Each row's position ``(E, OFF)`` is ``route.position(s)`` (graph distance ≤ :data:`POSITION_TOL`).

    ``at_route``: per robot the route's edges and offsets at ``S`` and their graph distance to the rows' positions.
    """
    fails = []
    for r, (re_, ro, err) in enumerate(at_route):
        if err.max() > POSITION_TOL:
            k = int(np.argmax(err))
            fails.append(
                f"row {k}: robot {'AB'[r]} position (edge {int(E[k, r])}, {OFF[k, r]!r}) is not route.position(s) = "
                f"(edge {int(re_[k])}, {float(ro[k])!r}) at s = {S[k, r]!r}"
            )
    return fails


def _endpoint_failures(
    geometry: GraphGeometry,
    E: NDArray[Any],
    OFF: FloatArray,
    V: FloatArray,
    A: FloatArray,
    start: tuple[tuple[int, float], tuple[int, float]],
    goal: tuple[tuple[int, float], tuple[int, float]],
) -> list[str]:
    """The first row at the start and the last at the goal, both at rest."""
    fails = []
    n = len(E)
    for name, row, target in (("first", 0, start), ("last", n - 1, goal)):
        gaps = [geometry.distance_scalar(int(E[row, r]), float(OFF[row, r]), *target[r]) for r in (0, 1)]
        end_err = max(float(g) for g in gaps)
        if end_err > POSITION_TOL:
            fails.append(f"{name} row is {end_err:.3g} m from {'the start' if row == 0 else 'the goal'}")
        if max(abs(x) for x in (*V[row].tolist(), *A[row].tolist())) > POSITION_TOL:
            fails.append(f"{name} row is not at rest (v = {V[row].tolist()}, a = {A[row].tolist()})")
    return fails


def _limit_check(
    V: FloatArray, A: FloatArray, J: FloatArray, limits: Limits
) -> tuple[dict[str, tuple[float, float]], list[str]]:
    """The peak ``|value| / limit`` of v, a, j per robot, and the failures where one exceeds ``1 + LIMIT_RTOL``."""
    X = np.abs(np.concatenate([V.T, A.T, J.T]))  # (6, N): v, a, j of A and B (contiguous rows: fast maxima)
    lims = np.concatenate([limits.v, limits.a, limits.j])  # (6,)
    r6 = (X.max(axis=1) / lims).tolist()
    ratios = [r6[0:2], r6[2:4], r6[4:6]]
    fails = []
    peak: dict[str, tuple[float, float]] = {}
    for q, name in enumerate(("v", "a", "j")):
        peak[name] = (float(ratios[q][0]), float(ratios[q][1]))
        for r in (0, 1):
            if ratios[q][r] > 1 + LIMIT_RTOL:
                i = 2 * q + r
                k = int(np.argmax(X[i]))
                fails.append(f"row {k}: |{name}| of robot {'AB'[r]} is {X[i, k]:.9g}, limit {lims[i]:g}")
    return peak, fails


def _separation_check(d: FloatArray, between: FloatArray, clearance: float) -> tuple[float, float, list[str]]:
    """Minimum separation at the rows ``d`` (shape (N,)) and between them (``between``, shape (N−1,)), with the
    failures where either is below the clearance."""
    fails = []
    dmin = float(np.min(d))
    if dmin < clearance - SEPARATION_TOL:
        k = int(np.argmin(d))
        fails.append(
            f"row {k}: separation {float(d[k])!r} below the clearance {float(clearance)!r} "
            f"(tolerance {SEPARATION_TOL:g} m)"
        )
    bmin = float(np.min(between)) if len(between) else dmin
    if bmin < clearance - SEPARATION_TOL:
        k = int(np.argmin(between))
        fails.append(
            f"rows {k}-{k + 1}: separation between rows may drop to {float(between[k])!r} < {float(clearance)!r} "
            f"(tolerance {SEPARATION_TOL:g} m)"
        )
    return dmin, bmin, fails
