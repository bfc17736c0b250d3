"""Stage 4, verification: an independent check of a setpoint grid before anything leaves the library.

The gate only looks at the rows (times, track and route coordinates, their derivatives), the track metric, the
robots' routes and the limits; it does not use any of the generator's geometry. Checks:

- the grid: finite values, ``t`` starts at 0 with constant step ``1/rate``;
- consistency: ``track == route.position(s)`` for both robots (graph distance ≤ :data:`POSITION_TOL`);
- endpoints: first row at the start and last row at the goal, both at rest (``v = a = 0``);
- limits: ``|v|, |a|, |j| ≤ limit·(1 + LIMIT_RTOL)`` per robot at every row, ``limit`` the limits the motion
  declares it was timed with (``limits_used``, each at most the limit asked for, which is checked too; default the
  limits asked for);
- separation at every row: ``d ≥ D − ε``, ``ε`` the tolerance of the layout's scale
  (:func:`mpa.tolerance.separation_tol`: 1e-9 m up to 125 m of track, ``8e-12·L`` beyond, shared with the planner);
- separation between rows: the chord between two rows (both robots linear in ``s``) is cut where a robot passes a
  junction of its route; on each piece both robots stay on one edge, the distance is the minimum of the cell's
  affine terms (and ``|s − t|`` on one edge), and its minimum is at an end unless the robots meet there
  (:meth:`mpa.geometry.GraphGeometry.segment_min`, exact; pieces where ``d_k + d_{k+1} > |Δs_A| + |Δs_B|``
  exclude meeting at once). The real motion deviates from the chord by at most ``a_int·Δt²/8`` per robot,
  ``a_int = min(amax, max(|a_k|, |a_k+1|) + jmax·Δt/2)`` with the declared ``amax`` and ``jmax`` (a controller that
  executes the rows within the declared limits stays inside this envelope); the distance is 1-Lipschitz in each
  robot's coordinate, so ``min_chord − Σ dev ≥ D − ε`` is required;
- homotopy class: the reduced skeleton word of the motion (:func:`skeleton_word`, the compiled twin of
  :func:`mpa.homotopy.path_word`; rows refined along the chords) equals the plan's.

The checks over the rows run as one compiled pass (:func:`trajopt.verify.kernels.check_rows`, numba); this module
validates the inputs, calls it and writes the messages from the numbers it returns.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa import tolerance
from mpa._arrays import FloatArray, IntArray
from mpa.errors import InvalidInputError, MPAError, PlanningError
from mpa.geometry import DirectedRoute, GraphGeometry
from mpa.homotopy import END_TOL, path_word, word_from_samples
from mpa.routes import Route, directed_route
from mpa.skeleton import CircleSkeleton, LollipopSkeleton, skeleton_of
from mpa.tracks import Track
from trajopt.timing import Limits
from trajopt.verify.kernels import (
    RES,
    between_rows,
    check_rows,
    circle_skeleton_points,
    dense_polyline,
    lollipop_skeleton_points,
    needs_densify,
    track_positions,
    word_samples,
)
from trajopt.verify.rows import Setpoints, rows_of

__all__ = [
    "CLASS_FAILURE_PREFIXES",
    "LIMIT_RTOL",
    "POSITION_TOL",
    "SEPARATION_TOL",
    "Setpoints",
    "VerificationError",
    "VerificationReport",
    "between_rows_separation",
    "class_failures_only",
    "declared_limit_failures",
    "lane_rule_failures",
    "separation_margin",
    "skeleton_word",
    "verify_graph_setpoints",
    "verify_setpoints",
]

#: Relative tolerance of the limit checks.
LIMIT_RTOL = 1e-6
#: Tolerance (metres) of the separation checks on layouts up to 125 m; on larger ones
#: :func:`mpa.tolerance.separation_tol` of the layout's scale (the model the planner shares).
SEPARATION_TOL = tolerance.GATE_FLOOR
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
    S, A = _rows(s), _rows(a)
    if len(S) < 2:
        return np.zeros(0)
    out: FloatArray = between_rows(
        _graph_arrays(geometry),
        droutes[0].arrays,
        droutes[1].arrays,
        S,
        A,
        float(dt),
        np.ascontiguousarray(limits.a, dtype=float),
        np.ascontiguousarray(limits.j, dtype=float),
    )
    return out


def _rows(x: ArrayLike) -> FloatArray:
    """``x`` as a C-contiguous float array (what the compiled kernels take; no copy when it already is)."""
    return np.ascontiguousarray(x, dtype=float)


def _graph_arrays(geometry: GraphGeometry) -> tuple[IntArray, IntArray, FloatArray, FloatArray]:
    """The graph as the kernels take it: ``tails``, ``heads``, ``lengths``, ``dv``."""
    return geometry.tails, geometry.heads, geometry.lengths, geometry.dv


def verify_setpoints(
    track: Track,
    routes: Sequence[Route],
    rows: Setpoints | ArrayLike,
    *arrays: ArrayLike,
    limits: Limits,
    clearance: float,
    start: ArrayLike,
    goal: ArrayLike,
    word: Sequence[str],
    rate: float,
    limits_used: Limits | None = None,
) -> VerificationReport:
    """Check a setpoint grid on one of the paper's tracks (see the module docstring for the list of checks).

    The rows are checked in the graph form of the track (:meth:`mpa.tracks.Track.as_graph_track`, edges
    ``stick`` and ``loop``) by :func:`verify_graph_setpoints`, and the motion's skeleton word against ``word``.

    Parameters
    ----------
    track : Track
    routes : sequence of Route
        Route of A and of B (the plan's).
    rows : Setpoints
        ``t`` (N,) in s; ``track`` (N, 2): track coordinates of A and B (m); ``s, v, a, j`` (N, 2): route
        coordinates (m) and their derivatives (m/s, m/s², m/s³). Or positionally the arrays
        ``t, track, s, v, a, j``.
    limits : Limits
        The limits asked for (m/s, m/s², m/s³ per robot).
    clearance : float
        Required separation D (metres).
    start, goal : array_like, shape (2,)
        Track coordinates.
    word : sequence of str
        The plan's reduced skeleton word.
    rate : float
        Row rate (Hz).
    limits_used : Limits, optional
        The limits the motion declares it was timed with (:attr:`trajopt.result.Trajectory.limits_used`): the rows
        are checked against them and the motion between rows is bounded with them; each must be at most the one
        in ``limits``. Default ``limits``.

    Returns
    -------
    VerificationReport
        Never raises for a failed check; ``ok`` is False and ``failures`` lists them.
    """
    rows = rows_of(rows, arrays, ("t", "track", "s", "v", "a", "j"))
    geometry, droutes = _graph_form(track, routes)
    P = np.asarray(rows.track, dtype=float)
    if P.ndim != 2 or P.shape[1:] != (2,):
        nan = float("nan")
        return VerificationReport(False, ("arrays have inconsistent shapes",), nan, nan, {}, ())
    edges, offsets = _graph_positions(track, P)
    rep = verify_graph_setpoints(
        geometry,
        droutes,
        dataclasses.replace(rows, edges=edges, offsets=offsets),
        limits=limits,
        clearance=clearance,
        start=_graph_query_point(track, start),
        goal=_graph_query_point(track, goal),
        rate=rate,
        limits_used=limits_used,
    )
    if not np.isfinite(rep.min_separation):
        return rep
    w, word_fails = _word_check(track, routes, np.asarray(rows.s, dtype=float), word, P)
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
        S = _rows(S)
        if P is not None and not needs_densify(S, step):
            states = P
        elif len(S):
            (br_a, A_a, B_a, ln_a, interval, stick, loop), (br_b, A_b, B_b, ln_b, *_) = (
                r.affine_form() for r in routes
            )
            dense = dense_polyline(S, step)
            states = np.empty(dense.shape)
            track_positions(dense, br_a, A_a, B_a, ln_a, br_b, A_b, B_b, ln_b, interval, stick, loop, states)
        else:
            states = np.zeros((0, 2))
        w = skeleton_word(track, states)
    except MPAError as exc:
        return (), [f"cannot compute the homotopy class: {exc}"]
    if tuple(w) != tuple(word):
        got, want = " ".join(w) or "(trivial)", " ".join(word) or "(trivial)"
        return tuple(w), [f"homotopy class {got} differs from the plan's {want}"]
    return tuple(w), []


def skeleton_word(track: Track, states: ArrayLike) -> tuple[str, ...]:
    """:func:`mpa.homotopy.path_word` of densely sampled states (track coordinates, shape (N, 2)), compiled.

    ``H₁`` of every state (:func:`trajopt.verify.kernels.lollipop_skeleton_points`, ``circle_skeleton_points``:
    mpa's own steps, one state at a time), then the word of the samples around the edge changes
    (:func:`mpa.homotopy.word_from_samples`). Where two consecutive samples retract to skeleton edges without a
    common vertex (a gap to refine), at a collision, and on the interval: :func:`mpa.homotopy.path_word` itself.
    """
    sk = skeleton_of(track)
    P = _rows(states)
    if P.ndim != 2 or P.shape[1] != 2 or len(P) == 0 or not isinstance(sk, (LollipopSkeleton, CircleSkeleton)):
        return path_word(track, P)
    edge, t = np.empty(len(P), dtype=np.int64), np.empty(len(P))
    try:
        if isinstance(sk, LollipopSkeleton):
            degenerate = bool(sk.graph.edges[0].length <= END_TOL)
            ell, c_model, kappa = float(sk.model.stick), float(sk.model.loop), float(sk.kappa)
            lollipop_skeleton_points(P, ell, c_model, kappa, degenerate, edge, t)
        else:  # (scalars as floats: another argument type would compile another specialization)
            circle_skeleton_points(P, float(sk.circumference), edge, t)
    except ZeroDivisionError:  # a state at a collision: the robots coincide
        return path_word(track, P)
    keep, jump = word_samples(edge, sk.graph.adjacent_edges)
    if jump:
        return path_word(track, P)
    return word_from_samples(sk.graph, edge[keep].tolist(), t[keep].tolist())


def verify_graph_setpoints(
    geometry: GraphGeometry,
    routes: Sequence[DirectedRoute],
    rows: Setpoints | ArrayLike,
    *arrays: ArrayLike,
    limits: Limits,
    clearance: float,
    start: tuple[tuple[int, float], tuple[int, float]],
    goal: tuple[tuple[int, float], tuple[int, float]],
    rate: float,
    oneway: Sequence[bool] | None = None,
    speed_limits: Sequence[float | None] | None = None,
    limits_used: Limits | None = None,
) -> VerificationReport:
    """Check a setpoint grid on any track graph (see the module docstring; no skeleton word on a graph).

    Parameters
    ----------
    geometry : GraphGeometry
        The exact metric of the track graph.
    routes : sequence of DirectedRoute
        Route of A and of B.
    rows : Setpoints
        ``t`` (N,) in s; ``edges``, ``offsets`` (N, 2): positions of A and B, edge index and offset from the
        edge's tail (m); ``s, v, a, j`` (N, 2): route coordinates (m) and their derivatives (m/s, m/s², m/s³). Or
        positionally the arrays ``t, edges, offsets, s, v, a, j``.
    limits : Limits
        The limits asked for (m/s, m/s², m/s³ per robot).
    clearance : float
        Required separation D (metres).
    start, goal : pair of (int, float)
        Positions ``(edge, offset)`` of A and B.
    rate : float
        Row rate (Hz).
    oneway : sequence of bool, optional
        Per edge: one-way from its tail to its head. On every row a robot on such an edge moves along it or stands
        (its offset's rate ``dir · v >= -1e-9`` m/s) and between rows its offset does not decrease (more than
        ``POSITION_TOL``).
    speed_limits : sequence of (float or None), optional
        Per edge: the speed limit (m/s). On every row ``|v|`` of a robot on (or at a vertex of) the edge its route
        piece runs on is at most the limit times ``1 + LIMIT_RTOL``.
    limits_used : Limits, optional
        The limits the motion declares it was timed with: the rows are checked against them and the motion
        between rows is bounded with them; each must be at most the one in ``limits``. Default ``limits``.

    Returns
    -------
    VerificationReport
        Never raises for a failed check; ``ok`` is False and ``failures`` lists them; ``word`` is empty.
    """
    rows = rows_of(rows, arrays, ("t", "edges", "offsets", "s", "v", "a", "j"))
    used = limits if limits_used is None else limits_used
    rep = _verify_graph_rows(geometry, routes, rows, used, clearance, start, goal, rate)
    fails = declared_limit_failures(limits, used)
    if oneway is not None or speed_limits is not None:
        fails += lane_rule_failures(routes, rows.s, rows.v, oneway, speed_limits)
    if not fails:
        return rep
    return dataclasses.replace(rep, ok=False, failures=(*rep.failures, *fails))


def declared_limit_failures(asked: Limits, used: Limits) -> list[str]:
    """The failures where a declared limit (``used``, the limits a motion was timed with) exceeds the one asked
    for (``asked``) by more than ``LIMIT_RTOL``, or is not a positive number.

    Parameters
    ----------
    asked, used : Limits
        Per-robot ``vmax`` (m/s), ``amax`` (m/s²), ``jmax`` (m/s³).

    Returns
    -------
    list of str
        One message per limit and robot; empty when every declared limit is within the one asked for.
    """
    if used is asked:
        return []
    fails = []
    for name, unit in (("vmax", "m/s"), ("amax", "m/s^2"), ("jmax", "m/s^3")):
        for r, (x, cap) in enumerate(zip(getattr(used, name), getattr(asked, name))):
            if not (0.0 < float(x) <= float(cap) * (1 + LIMIT_RTOL)):
                fails.append(
                    f"declared {name} of robot {'AB'[r]} is {float(x):.9g} {unit}, expected a positive number at "
                    f"most the {float(cap):g} {unit} asked for"
                )
    return fails


def lane_rule_failures(
    routes: Sequence[DirectedRoute],
    s: ArrayLike,
    v: ArrayLike,
    oneway: Sequence[bool] | None,
    speed_limits: Sequence[float | None] | None,
) -> list[str]:
    """The rows where a robot drives a one-way edge backwards or exceeds an edge's speed limit.

    Parameters
    ----------
    routes : sequence of DirectedRoute
        Route of A and of B.
    s, v : array_like, shape (N, 2)
        Route coordinates (m) and speeds along the routes (m/s).
    oneway, speed_limits : sequences, one entry per edge, or None
        See :func:`verify_graph_setpoints`.

    Returns
    -------
    list of str
        One failure per robot and rule (the first row), empty when every row keeps the rules.
    """
    S, V = _rows(s), _rows(v)
    fails: list[str] = []
    for r in (0, 1):
        route = routes[r]
        br = np.asarray(route.breaks, dtype=float)
        m = len(route.edges)
        after = np.clip(np.searchsorted(br, S[:, r], side="right") - 1, 0, m - 1)
        before = np.clip(np.searchsorted(br, S[:, r], side="left") - 1, 0, m - 1)
        e_after, e_before = np.asarray(route.edges)[after], np.asarray(route.edges)[before]
        rate_off = np.asarray(route.dirs)[after] * V[:, r]  # offset's rate on the edge moved onto (m/s)
        if oneway is not None:
            ow = np.asarray(oneway, dtype=bool)
            bad = np.nonzero(ow[e_after] & (rate_off < -1e-9))[0]
            # between rows: on one piece of a one-way edge the offset never decreases
            same = after[1:] == after[:-1]
            dr = np.asarray(route.dirs)[after[1:]] * np.diff(S[:, r])
            back = np.nonzero(same & ow[e_after[1:]] & (dr < -POSITION_TOL))[0]
            if len(bad) or len(back):
                k = int(bad[0]) if len(bad) else int(back[0]) + 1
                fails.append(
                    f"row {k}: robot {'AB'[r]} drives the one-way edge {int(e_after[k])} against its direction "
                    f"(offset rate {float(rate_off[k]):.6g} m/s)"
                )
        if speed_limits is not None:
            lim = np.array([np.inf if x is None else float(x) for x in speed_limits])
            cap = np.minimum(lim[e_after], lim[e_before])
            over = np.nonzero(np.abs(V[:, r]) > cap * (1 + LIMIT_RTOL))[0]
            if len(over):
                k = int(over[0])
                edge = int(e_after[k]) if lim[e_after[k]] <= lim[e_before[k]] else int(e_before[k])
                fails.append(
                    f"row {k}: |v| of robot {'AB'[r]} is {abs(float(V[k, r])):.9g} on edge {edge}, over its speed "
                    f"limit {float(cap[k]):g} m/s"
                )
    return fails


def _verify_graph_rows(
    geometry: GraphGeometry,
    routes: Sequence[DirectedRoute],
    rows: Setpoints,
    limits: Limits,
    clearance: float,
    start: tuple[tuple[int, float], tuple[int, float]],
    goal: tuple[tuple[int, float], tuple[int, float]],
    rate: float,
) -> VerificationReport:
    """:func:`verify_graph_setpoints` without the lane rules."""
    if rows.edges is None or rows.offsets is None:
        raise InvalidInputError("rows have no edges and offsets, expected the robots' positions on the layout")
    tt = np.ascontiguousarray(rows.t, dtype=float)
    E = np.asarray(rows.edges)
    OFF, S, V, A, J = (_rows(x) for x in (rows.offsets, *rows.svaj))
    n = len(tt)
    nan = float("nan")
    if n == 0 or tt.ndim != 1 or E.shape != (n, 2) or any(x.shape != (n, 2) for x in (OFF, S, V, A, J)):
        return VerificationReport(False, ("arrays have inconsistent shapes",), nan, nan, {}, ())
    if E.dtype.kind not in "iu":  # not integers (non-finite values are reported first, as by the kernel)
        finite = bool(np.isfinite(tt).all()) and all(bool(np.isfinite(x).all()) for x in (OFF, S, V, A, J))
        why = "edge indices out of range" if finite else "non-finite values in the setpoints"
        return VerificationReport(False, (why,), nan, nan, {}, ())
    E = np.ascontiguousarray(E, dtype=np.int64)
    dt = 1.0 / float(rate)
    lims = np.array([*limits.vmax, *limits.amax, *limits.jmax], dtype=float)  # (6,): v, a, j of A and B
    ends = np.array([*start[0], *start[1], *goal[0], *goal[1]], dtype=float)
    between = np.empty(n - 1)
    res = check_rows(
        _graph_arrays(geometry),
        routes[0].arrays,
        routes[1].arrays,
        tt,
        E,
        OFF,
        S,
        V,
        A,
        J,
        lims,
        dt,
        TIME_TOL,
        ends,
        between,
    ).tolist()
    if res[RES["bad"]]:
        why = "non-finite values in the setpoints" if res[RES["bad"]] == 1.0 else "edge indices out of range"
        return VerificationReport(False, (why,), nan, nan, {}, ())
    fails: list[str] = []
    if not res[RES["grid_ok"]]:
        fails.append(f"time grid is not 0, 1/{rate:g}, 2/{rate:g}, …")
    fails += _route_consistency_failures(routes, E, OFF, S, res)
    fails += _endpoint_failures(V, A, res)
    peak, limit_fails = _limit_check(res, lims.tolist())
    fails += limit_fails
    tol = tolerance.separation_tol(tolerance.layout_scale(geometry.lengths))
    fails += _separation_failures(res, between, clearance, tol)
    return VerificationReport(not fails, tuple(fails), res[RES["dmin"]], res[RES["bmin"]], peak, ())


def _route_consistency_failures(
    routes: Sequence[DirectedRoute], E: IntArray, OFF: FloatArray, S: FloatArray, res: list[float]
) -> list[str]:
    """Each row's position ``(E, OFF)`` is ``route.position(s)`` (graph distance ≤ :data:`POSITION_TOL`)."""
    fails = []
    for r, name in enumerate(("err_a", "err_b")):
        if res[RES[name]] > POSITION_TOL:
            k = int(res[RES[name + "_row"]])
            re_, ro = routes[r].position_scalar(float(S[k, r]))
            fails.append(
                f"row {k}: robot {'AB'[r]} position (edge {int(E[k, r])}, {float(OFF[k, r])!r}) is not "
                f"route.position(s) = (edge {re_}, {ro!r}) at s = {float(S[k, r])!r}"
            )
    return fails


def _endpoint_failures(V: FloatArray, A: FloatArray, res: list[float]) -> list[str]:
    """The first row at the start and the last at the goal, both at rest."""
    fails = []
    for name, row, target in (("first", 0, "the start"), ("last", len(V) - 1, "the goal")):
        end_err = max(res[RES[f"{name}_a"]], res[RES[f"{name}_b"]])
        if end_err > POSITION_TOL:
            fails.append(f"{name} row is {end_err:.3g} m from {target}")
        if res[RES[f"rest_{name}"]] > POSITION_TOL:
            fails.append(f"{name} row is not at rest (v = {V[row].tolist()}, a = {A[row].tolist()})")
    return fails


def _limit_check(res: list[float], lims: list[float]) -> tuple[dict[str, tuple[float, float]], list[str]]:
    """The peak ``|value| / limit`` of v, a, j per robot, and the failures where one exceeds ``1 + LIMIT_RTOL``.

    ``lims``: the six limits ``vA, vB, aA, aB, jA, jB``.
    """
    fails = []
    peak: dict[str, tuple[float, float]] = {}
    first = RES["v_a"]
    for q, name in enumerate(("v", "a", "j")):
        ratio = (res[first + 2 * q] / lims[2 * q], res[first + 2 * q + 1] / lims[2 * q + 1])
        peak[name] = ratio
        for r in (0, 1):
            if ratio[r] > 1 + LIMIT_RTOL:
                i = 2 * q + r
                fails.append(
                    f"row {int(res[first + 6 + i])}: |{name}| of robot {'AB'[r]} is {res[first + i]:.9g}, "
                    f"limit {lims[i]:g}"
                )
    return peak, fails


def _separation_failures(
    res: list[float], between: FloatArray, clearance: float, tol: float = SEPARATION_TOL
) -> list[str]:
    """The failures where the separation at a row or between rows is below the clearance by more than ``tol``
    (m, :func:`mpa.tolerance.separation_tol`)."""
    fails = []
    dmin, bmin = res[RES["dmin"]], res[RES["bmin"]]
    if dmin < clearance - tol:
        fails.append(
            f"row {int(res[RES['dmin_row']])}: separation {dmin!r} below the clearance {float(clearance)!r} "
            f"(tolerance {tol:g} m)"
        )
    if bmin < clearance - tol:
        k = int(res[RES["bmin_row"]])
        fails.append(
            f"rows {k}-{k + 1}: separation between rows may drop to {float(between[k])!r} < {float(clearance)!r} "
            f"(tolerance {tol:g} m)"
        )
    return fails


def separation_margin(limits: Limits, rate: float, gate: Limits | None = None) -> float:
    """Extra separation (m) the geometric path keeps so that the gate's between-rows bound holds.

    The motion deviates from the chord between rows by at most ``amax·Δt²/8`` per robot (``amax`` of ``limits``,
    the limits it is timed with); the gate subtracts ``a_int·Δt²/8`` with
    ``a_int = min(amax_gate, max(|a_k|, |a_k+1|) + jmax_gate·Δt/2) ≤ min(amax_gate, amax + jmax_gate·Δt/2)``
    (:func:`between_rows_separation`). The path keeps the sum of both over the two robots plus 1e-9 m.

    Parameters
    ----------
    limits : Limits
        The limits the motion is timed with (m/s, m/s², m/s³ per robot).
    rate : float
        Setpoint rate (Hz).
    gate : Limits, optional
        The limits the gate bounds the motion between rows with, when higher than ``limits``; default
        ``limits`` (what the generator passes: the trajectory declares the limits it is timed with,
        :attr:`trajopt.result.Trajectory.limits_used`, and the gate uses them): the margin is
        ``2·Σ amax·Δt²/8 + 1e-9``.

    Returns
    -------
    float
        The margin (m).
    """
    dt = 1.0 / rate
    a = np.asarray(limits.a, dtype=float)
    with np.errstate(over="ignore"):  # a tiny rate: jmax·Δt/2 is inf, the bound is amax_gate
        a_int = a if gate is None else np.minimum(np.asarray(gate.a, dtype=float), a + np.asarray(gate.j) * dt / 2.0)
    return float(np.sum(np.maximum(a_int, a) + a)) * dt * dt / 8.0 + 1e-9
