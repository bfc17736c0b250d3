"""An independent checker of exported setpoints, for the test suite and the soak script (not the gate).

:func:`check_setpoints` re-checks what :func:`trajopt.verify.gate.verify_setpoints` promises, written separately
and with other means, so that a bug in the gate does not hide a bad file:

- the time grid: ``t_k = k / rate`` from 0, every array finite and of the right shape;
- endpoints: first row at the start and last row at the goal (exact track distance :meth:`mpa.Track.distance`
  ≤ :data:`POS_TOL`), both at rest (``v = a = 0``);
- limits: ``|v|, |a|, |j| ≤ limit · (1 + LIMIT_RTOL)`` per robot;
- kinematic consistency: ``s`` is the integral of ``v`` and ``v`` of ``a`` (trapezoid rules with the jerk bound
  as the error bound), and ``a`` changes by at most ``jmax · Δt`` between rows;
- the track column moves at most ``vmax · Δt`` per row (exact track distance), so it follows ``s``;
- separation: the exact track distance between the robots at every row, and on a grid ``fine`` times denser
  over the continuous motion when one is given, is at least ``D − SEP_TOL``;
- the homotopy class of the dense motion (:func:`mpa.path_word`) equals the plan's word when one is given.

On a layout (:class:`mpa.GraphTrack`), :func:`check_graph_setpoints` checks the rows in positions
``(edge, offset)`` with its own graph metric (:class:`GraphMetric`, Dijkstra): the same checks, plus offsets
within their edges, edge changes only between edges sharing a vertex, and the ``*_dir`` column.

Each check returns a message on failure; :func:`check_trajectory` applies them to a
:class:`~trajopt.result.Trajectory` (:func:`requirements`: what its rows must keep). For the tests and the
benchmark scripts: :func:`random_queries` draws seeded queries on a paper track, :func:`random_rules` seeded lane
rules on a layout; :func:`travel_curve` resamples a trajectory's path by route travel, to compare two motions'
paths (re-planning stability).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa._arrays import FloatArray
from mpa.graph_track import GraphTrack
from mpa.homotopy import path_word
from mpa.tracks import Track
from trajopt.verify.rows import Setpoints, rows_of

if TYPE_CHECKING:
    from trajopt.result import Trajectory

__all__ = [
    "LIMIT_RTOL",
    "POS_TOL",
    "SEP_TOL",
    "GraphMetric",
    "check_graph_setpoints",
    "check_graph_trajectory",
    "check_setpoints",
    "check_trajectory",
    "random_queries",
    "random_rules",
    "read_setpoint_rows",
    "requirements",
    "travel_curve",
]

#: Relative tolerance of the limit checks.
LIMIT_RTOL = 1e-6
#: Absolute tolerance of positions and rest (m, m/s, m/s²).
POS_TOL = 1e-9
#: Absolute tolerance of the separation checks (m).
SEP_TOL = 1e-9


def check_setpoints(
    track: Track,
    rows: Setpoints | ArrayLike,
    *arrays: ArrayLike,
    rate: float,
    clearance: float,
    vmax: ArrayLike,
    amax: ArrayLike,
    jmax: ArrayLike,
    start: ArrayLike,
    goal: ArrayLike,
) -> list[str]:
    """Check a setpoint grid (see the module docstring); returns the failures, empty when fine.

    Parameters
    ----------
    track : Track
    rows : Setpoints
        ``t`` (N,): times (s); ``track`` (N, 2): track coordinates of A and B (m); ``s, v, a, j`` (N, 2): route
        coordinates and their derivatives (m, m/s, m/s², m/s³). Or positionally the arrays ``t, track, s, v, a, j``.
    rate : float
        Row rate (Hz).
    clearance : float
        Required separation (m).
    vmax, amax, jmax : array_like, shape (2,)
        Per-robot limits.
    start, goal : array_like, shape (2,)
        Track coordinates of the query.
    """
    rows = rows_of(rows, arrays, ("t", "track", "s", "v", "a", "j"))
    arrs = _rows_or_failure(rows.t, (rows.track, *rows.svaj), shapes_of=())
    if isinstance(arrs, list):
        return arrs
    tt, (P, S, V, A, J) = arrs
    n = len(tt)
    dt = 1.0 / float(rate)
    V_, A_, J_ = _per_robot_limits(vmax, amax, jmax)
    fails = _time_grid_failures(tt, dt)
    for name, row, target in (("first", 0, start), ("last", n - 1, goal)):
        err = track.distance(P[row], np.asarray(target, dtype=float))
        if np.any(err > POS_TOL):
            fails.append(f"{name} row at {P[row].tolist()} is {err.tolist()} from {np.asarray(target).tolist()}")
        fails += _rest_failures(name, V[row], A[row])
    fails += _limit_failures((V, A, J), (V_, A_, J_))
    if n > 1:
        fails += _integration_failures(S, V, A, J_, dt)
        for r in (0, 1):
            step = track.distance(P[:-1, r], P[1:, r])
            if np.any(step > V_[r] * dt * (1 + LIMIT_RTOL) + POS_TOL):
                fails.append(f"robot {'AB'[r]} jumps {float(np.max(step))!r} m between rows")
    fails += _row_separation_failures(track.distance(P[:, 0], P[:, 1]), clearance)
    return fails


def read_setpoint_rows(path: str | os.PathLike[str]) -> tuple[FloatArray, ...]:
    """The rows of a setpoints CSV of a paper track in the order :func:`check_setpoints` takes them.

    Reads the first eleven columns (``time``, then ``track, s, v, a, j`` of A and of B; conventions: Command
    line and files) with numpy.

    Returns
    -------
    tuple of numpy.ndarray
        ``t`` of shape (N,), then ``track, s, v, a, j``, each of shape (N, 2) (A's column first).
    """
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2, usecols=range(11))
    return (data[:, 0], *(data[:, [k, k + 5]] for k in range(1, 6)))


def _rows_or_failure(
    t: ArrayLike, columns: Sequence[ArrayLike | None], shapes_of: Sequence[Any]
) -> list[str] | tuple[FloatArray, list[FloatArray]]:
    """The times and the (N, 2) columns as float arrays, or the one failure when shapes or values are off (or a
    column is missing).

    ``shapes_of`` are further arrays whose shapes the shape message names first (the edge indices on a layout).
    """
    if any(x is None for x in columns):
        return ["the rows miss the positions (track coordinates, or edges and offsets)"]
    tt = np.asarray(t, dtype=float)
    arrs = [np.asarray(x, dtype=float) for x in columns]
    n = len(tt)
    if n < 1 or any(x.shape != (n, 2) for x in (*shapes_of, *arrs)):
        named = "".join(f", {x.shape}" for x in shapes_of)
        return [f"shapes {tt.shape}{named} and {[x.shape for x in arrs]} are not (N,) and (N, 2)"]
    if not (np.all(np.isfinite(tt)) and all(np.all(np.isfinite(x)) for x in arrs)):
        return ["non-finite values"]
    return tt, arrs


def _per_robot_limits(vmax: ArrayLike, amax: ArrayLike, jmax: ArrayLike) -> tuple[FloatArray, ...]:
    """``vmax, amax, jmax`` as arrays of shape (2,) (a scalar applies to both robots)."""
    return tuple(np.broadcast_to(np.asarray(x, dtype=float), (2,)) for x in (vmax, amax, jmax))


def _time_grid_failures(tt: FloatArray, dt: float) -> list[str]:
    """The time grid is ``k·dt`` from 0."""
    if np.max(np.abs(tt - np.arange(len(tt)) * dt)) > 1e-9 * max(1.0, tt[-1]):
        return ["time grid is not k / rate"]
    return []


def _rest_failures(name: str, v_row: FloatArray, a_row: FloatArray) -> list[str]:
    """The ``name`` row (first or last) is at rest: ``v = a = 0``."""
    if np.any(np.abs(v_row) > POS_TOL) or np.any(np.abs(a_row) > POS_TOL):
        return [f"{name} row not at rest: v {v_row.tolist()}, a {a_row.tolist()}"]
    return []


def _limit_failures(values: Sequence[FloatArray], limits: Sequence[FloatArray]) -> list[str]:
    """``|v|, |a|, |j|`` (in that order) within their per-robot limits."""
    fails = []
    for name, x, lim in zip(("v", "a", "j"), values, limits):
        peak = np.max(np.abs(x), axis=0)
        if np.any(peak > lim * (1 + LIMIT_RTOL)):
            fails.append(f"|{name}| peaks {peak.tolist()} above {lim.tolist()}")
    return fails


def _integration_errors(S: FloatArray, V: FloatArray, A: FloatArray, dt: float) -> tuple[FloatArray, FloatArray]:
    """Per row step, the errors of ``s`` as the integral of ``v`` and ``a`` and of ``v`` as that of ``a``.

    ``s(t+dt) − s(t) = dt (v0 + v1)/2 + dt² (a0 − a1)/12 + O(J dt³)``; ``v(t+dt) − v(t) = dt (a0 + a1)/2 + O(J dt²)``.
    """
    ds_pred = dt * 0.5 * (V[:-1] + V[1:]) + dt * dt * (A[:-1] - A[1:]) / 12.0
    e_s = np.abs(np.diff(S, axis=0) - ds_pred)
    e_v = np.abs(np.diff(V, axis=0) - dt * 0.5 * (A[:-1] + A[1:]))
    return e_s, e_v


def _integration_failures(S: FloatArray, V: FloatArray, A: FloatArray, J_: FloatArray, dt: float) -> list[str]:
    """Kinematic consistency of the rows (the jerk bound ``J_`` bounds the trapezoid errors), with the rows named."""
    fails = []
    e_s, e_v = _integration_errors(S, V, A, dt)
    if np.any(e_s > J_ * dt**3 / 6.0 + 1e-9):
        r = int(np.argmax(np.max(e_s - J_ * dt**3 / 6.0, axis=1)))
        fails.append(f"rows {r}-{r + 1}: s is not the integral of v and a (error {e_s[r].tolist()})")
    if np.any(e_v > J_ * dt * dt / 4.0 + 1e-9):
        r = int(np.argmax(np.max(e_v - J_ * dt * dt / 4.0, axis=1)))
        fails.append(f"rows {r}-{r + 1}: v is not the integral of a (error {e_v[r].tolist()})")
    e_a = np.abs(np.diff(A, axis=0))
    if np.any(e_a > J_ * dt * (1 + LIMIT_RTOL) + 1e-9):
        fails.append("a changes faster than jmax between rows")
    return fails


def _row_separation_failures(d: FloatArray, clearance: float) -> list[str]:
    """The separation ``d`` (shape (N,)) at every row is at least the clearance."""
    if np.min(d) < clearance - SEP_TOL:
        r = int(np.argmin(d))
        return [f"row {r}: separation {float(d[r])!r} < clearance {float(clearance)!r}"]
    return []


def _makespan_failures(traj: Trajectory) -> list[str]:
    """The makespan is the motion time rounded up to the row grid."""
    if traj.makespan < traj.motion_time - 1e-12 or traj.makespan - traj.motion_time > 1.0 / traj.rate + 1e-12:
        return ["makespan is not the motion time rounded up to the grid"]
    return []


def _dense_separation_failures(tf: FloatArray, d: FloatArray, clearance: float) -> list[str]:
    """The separation ``d`` at the dense times ``tf`` is at least the clearance."""
    if np.min(d) < clearance - SEP_TOL:
        r = int(np.argmin(d))
        return [f"t = {tf[r]:.6f}: separation {float(d[r])!r} < clearance {float(clearance)!r}"]
    return []


def _dense_times(traj: Trajectory, fine: int) -> FloatArray:
    """A grid ``fine`` times denser than the rows over the whole motion."""
    return np.linspace(0.0, traj.makespan, max(2, fine * (len(traj.t) - 1) + 1))


def requirements(traj: Any) -> dict[str, Any]:
    """What the rows of ``traj`` must keep, as the keywords of :func:`check_setpoints` and
    :func:`check_graph_setpoints`: ``rate`` (Hz), ``clearance`` (m) and the per-robot limits ``vmax``, ``amax``,
    ``jmax`` (shape (2,); m/s, m/s², m/s³).

    Parameters
    ----------
    traj : Trajectory
        Its ``rate``, ``clearance`` and ``limits`` are read.
    """
    lim = traj.limits
    return {"rate": traj.rate, "clearance": traj.clearance, "vmax": lim.v, "amax": lim.a, "jmax": lim.j}


def check_trajectory(
    traj: Any, start: ArrayLike | None = None, goal: ArrayLike | None = None, *, fine: int = 8
) -> list[str]:
    """Check a :class:`~trajopt.result.Trajectory` (its rows, and its continuous motion ``fine`` times denser).

    Parameters
    ----------
    traj : Trajectory
    start, goal : array_like, shape (2,), optional
        The query (default: the plan's, already normalized).
    fine : int
        Density of the extra grid over the continuous motion (0: rows only).

    Returns
    -------
    list of str
        Failures (empty when fine).
    """
    if getattr(traj, "is_graph", False):
        return check_graph_trajectory(traj, fine=fine)
    plan = traj.plan
    track = plan.track
    st = plan.start if start is None else start
    gl = plan.goal if goal is None else goal
    fails = check_setpoints(
        track, traj.t, traj.track, traj.s, traj.v, traj.a, traj.j, start=st, goal=gl, **requirements(traj)
    )
    fails += _makespan_failures(traj)
    if fine > 0:
        tf = _dense_times(traj, fine)
        s, _v, _a, _j = traj.sampler(tf)
        routes: Sequence[Any] = plan.routes
        pos = np.stack([routes[0].position(s[:, 0]), routes[1].position(s[:, 1])], axis=1)
        fails += _dense_separation_failures(tf, track.distance(pos[:, 0], pos[:, 1]), traj.clearance)
        if np.max(np.abs(s[[0, -1]] - traj.s[[0, -1]])) > POS_TOL:
            fails.append("the continuous motion does not start and end at the rows")
        w = path_word(track, pos)
        if tuple(w) != tuple(plan.word):
            fails.append(f"homotopy class {w} differs from the plan's {tuple(plan.word)}")
    return fails


# ------------------------------------------------------------------------------------------- graph tracks
def _vertex_distances(n: int, tails: Sequence[int], heads: Sequence[int], lengths: Sequence[float]) -> FloatArray:
    """All-pairs vertex distances by Dijkstra from every vertex (written apart from :mod:`mpa.geometry`)."""
    import heapq

    adj: list[list[tuple[int, float]]] = [[] for _ in range(n)]
    for u, w, ln in zip(tails, heads, lengths):
        adj[u].append((w, float(ln)))
        adj[w].append((u, float(ln)))
    out = np.full((n, n), np.inf)
    for src in range(n):
        dist = out[src]
        dist[src] = 0.0
        heap = [(0.0, src)]
        while heap:
            d, u = heapq.heappop(heap)
            if d > dist[u]:
                continue
            for w, ln in adj[u]:
                if d + ln < dist[w]:
                    dist[w] = d + ln
                    heapq.heappush(heap, (d + ln, w))
    return out


class GraphMetric:
    """The exact graph distance between positions ``(edge, offset)`` of a layout (independent of the gate's code).

    Parameters
    ----------
    track : GraphTrack
    """

    def __init__(self, track: GraphTrack) -> None:
        self.tails = np.asarray(track.tails, dtype=np.int64)
        self.heads = np.asarray(track.heads, dtype=np.int64)
        self.lengths = np.asarray(track.lengths, dtype=float)
        n = int(max(self.tails.max(), self.heads.max())) + 1
        self.dv = _vertex_distances(n, self.tails.tolist(), self.heads.tolist(), self.lengths.tolist())

    def __call__(self, e0: ArrayLike, o0: ArrayLike, e1: ArrayLike, o1: ArrayLike) -> FloatArray:
        """Graph distance (m) between ``(e0, o0)`` and ``(e1, o1)`` (broadcast)."""
        e0, o0, e1, o1 = np.broadcast_arrays(
            np.asarray(e0, dtype=np.int64), np.asarray(o0, float), np.asarray(e1, dtype=np.int64), np.asarray(o1, float)
        )
        ends0 = [(self.tails[e0], o0), (self.heads[e0], self.lengths[e0] - o0)]
        ends1 = [(self.tails[e1], o1), (self.heads[e1], self.lengths[e1] - o1)]
        best = np.full(e0.shape, np.inf)
        for v0, r0 in ends0:
            for v1, r1 in ends1:
                best = np.minimum(best, r0 + self.dv[v0, v1] + r1)
        return np.where(e0 == e1, np.minimum(best, np.abs(o0 - o1)), best)


def check_graph_setpoints(
    track: GraphTrack,
    rows: Setpoints | ArrayLike,
    *arrays: ArrayLike,
    rate: float,
    clearance: float,
    vmax: ArrayLike,
    amax: ArrayLike,
    jmax: ArrayLike,
    start: Sequence[tuple[int, float]],
    goal: Sequence[tuple[int, float]],
    dirs: ArrayLike | None = None,
    metric: GraphMetric | None = None,
) -> list[str]:
    """Check a setpoint grid on a layout; returns the failures, empty when fine.

    Checks: the time grid; endpoints (graph distance to the start and goal positions <= :data:`POS_TOL`, at rest);
    limits; kinematic consistency of ``s, v, a`` (as :func:`check_setpoints`); offsets within ``[0, length]``; per
    row step a graph distance of at most ``min(|Δs|, vmax·Δt)`` (the robot follows its route); a change of edge
    between two rows only between edges that share a vertex; the exact graph distance between the robots at every
    row ``>= D − SEP_TOL``; with ``dirs``: ``dir`` is 0 exactly where ``|v| <= 1e-9`` and, between two rows on one
    edge moving the same way, the sign of the offset change.

    Parameters
    ----------
    track : GraphTrack
    rows : Setpoints
        ``t`` (N,): times (s); ``edges`` (N, 2): edge indices of A and B; ``offsets`` (N, 2): offsets from the
        edges' tails (m); ``s, v, a, j`` (N, 2); ``dirs`` (N, 2), optional: the directions of travel. Or
        positionally the arrays ``t, edges, offsets, s, v, a, j``.
    rate, clearance : float
    vmax, amax, jmax : array_like, shape (2,)
    start, goal : pair of (edge index, offset)
    dirs : array_like of int, shape (N, 2), optional
        The directions (instead of ``rows.dirs``).
    metric : GraphMetric, optional
        Re-used if given.
    """
    rows = rows_of(rows, arrays, ("t", "edges", "offsets", "s", "v", "a", "j"))
    dirs = rows.dirs if dirs is None else dirs
    if rows.edges is None:
        return ["the rows miss the positions (track coordinates, or edges and offsets)"]
    E = np.asarray(rows.edges, dtype=np.int64)
    arrs = _rows_or_failure(rows.t, (rows.offsets, *rows.svaj), shapes_of=(E,))
    if isinstance(arrs, list):
        return arrs
    tt, (OF, S, V, A, J) = arrs
    n = len(tt)
    m = metric or GraphMetric(track)
    L = m.lengths
    if np.any(E < 0) or np.any(E >= len(L)):
        return ["edge index out of range"]
    dt = 1.0 / float(rate)
    V_, A_, J_ = _per_robot_limits(vmax, amax, jmax)
    fails = _time_grid_failures(tt, dt)
    if np.any(OF < -POS_TOL) or np.any(OF > L[E] + POS_TOL):
        fails.append("offset outside [0, length] of its edge")
    for name, row, target in (("first", 0, start), ("last", n - 1, goal)):
        err = [float(m(E[row, r], OF[row, r], target[r][0], target[r][1])) for r in (0, 1)]
        if max(err) > POS_TOL:
            fails.append(f"{name} row is {err} from {list(target)}")
        fails += _rest_failures(name, V[row], A[row])
    fails += _limit_failures((V, A, J), (V_, A_, J_))
    if n > 1:
        e_s, e_v = _integration_errors(S, V, A, dt)
        if np.any(e_s > J_ * dt**3 / 6.0 + 1e-9):
            fails.append("s is not the integral of v and a")
        if np.any(e_v > J_ * dt * dt / 4.0 + 1e-9):
            fails.append("v is not the integral of a")
        for r in (0, 1):
            fails += _graph_step_failures(m, r, E[:, r], OF[:, r], S[:, r], V_[r] * dt)
    if dirs is not None:
        fails += _direction_failures(m, np.asarray(dirs, dtype=np.int64), E, OF, V)
    fails += _row_separation_failures(m(E[:, 0], OF[:, 0], E[:, 1], OF[:, 1]), clearance)
    return fails


def _graph_step_failures(
    m: GraphMetric, r: int, E: NDArray[np.int64], OF: FloatArray, S: FloatArray, vstep: float
) -> list[str]:
    """Robot ``r`` follows its route: per row step at most ``min(|Δs|, vstep)`` of graph distance, and a change of
    edge only between edges sharing a vertex. ``E, OF, S`` shape (N,); ``vstep = vmax·Δt`` (m)."""
    fails = []
    step = m(E[:-1], OF[:-1], E[1:], OF[1:])
    bound = np.minimum(np.abs(np.diff(S)), vstep * (1 + LIMIT_RTOL))
    if np.any(step > bound + POS_TOL):
        k = int(np.argmax(step - bound))
        fails.append(f"robot {'AB'[r]} moves {float(step[k])!r} m between rows {k}-{k + 1}, more than {bound[k]!r}")
    tails, heads = m.tails, m.heads
    ch = np.flatnonzero(E[:-1] != E[1:])
    e0, e1 = E[ch], E[ch + 1]
    shared = (tails[e0] == tails[e1]) | (tails[e0] == heads[e1]) | (heads[e0] == tails[e1]) | (heads[e0] == heads[e1])
    if not np.all(shared):
        k = int(ch[np.argmin(shared)])
        fails.append(f"robot {'AB'[r]} changes from edge {E[k]} to {E[k + 1]} (no shared vertex)")
    return fails


def _direction_failures(
    m: GraphMetric, Dr: NDArray[np.int64], E: NDArray[np.int64], OF: FloatArray, V: FloatArray
) -> list[str]:
    """The ``*_dir`` column: 0 exactly at rest, ±1 in motion, and between two rows on one edge moving the same way
    the sign of the offset change (modulo a loop edge's length). All arrays shape (N, 2)."""
    n = len(E)
    moving = np.abs(V) > 1e-9
    if Dr.shape != (n, 2) or np.any((Dr != 0) != moving) or np.any(np.abs(Dr) > 1):
        return ["dir is not 0 exactly at rest and ±1 in motion"]
    if n > 1:
        same = (E[:-1] == E[1:]) & (Dr[:-1] == Dr[1:]) & (Dr[:-1] != 0)
        dO = np.diff(OF, axis=0)
        ln = m.lengths[E[:-1]]
        loop = m.tails[E[:-1]] == m.heads[E[:-1]]  # a loop edge: the offset wraps at its vertex
        dO = np.where(loop, (dO + 0.5 * ln) % ln - 0.5 * ln, dO)
        bad = same & (np.abs(dO) > 1e-12) & (np.sign(dO) != Dr[:-1])
        if np.any(bad):
            k, r = (int(x[0]) for x in np.nonzero(bad))
            return [f"row {k}: robot {'AB'[r]} dir {Dr[k, r]} but its offset changes by {dO[k, r]!r}"]
    return []


def check_graph_trajectory(traj: Trajectory, *, fine: int = 8) -> list[str]:
    """Check a :class:`~trajopt.result.Trajectory` on its plan's layout (rows and the continuous motion ``fine``
    times denser); any plan (:class:`mpa.MotionPlan`: a paper track's trajectory on the track's graph form too).

    The rows' positions are the trajectory's (:attr:`~trajopt.result.Trajectory.edges`, ``offsets``,
    ``directions``); the dense grid follows the plan's routes (:meth:`mpa.geometry.DirectedRoute.positions`).
    """
    plan = traj.plan
    m = GraphMetric(plan.layout)
    rows = (traj.t, traj.edges, traj.offsets, traj.s, traj.v, traj.a, traj.j)
    fails = check_graph_setpoints(
        plan.layout,
        *rows,
        start=plan.layout_start,
        goal=plan.layout_goal,
        dirs=traj.directions,
        metric=m,
        **requirements(traj),
    )
    fails += _makespan_failures(traj)
    if fine > 0 and len(traj.t) > 1:
        tf = _dense_times(traj, fine)
        s, _v, _a, _j = traj.sampler(tf)
        ra, rb = plan.layout_routes
        (ea, oa), (eb, ob) = ra.positions(s[:, 0]), rb.positions(s[:, 1])
        fails += _dense_separation_failures(tf, m(ea, oa, eb, ob), traj.clearance)
    return fails


def travel_curve(traj: Any, t0: float, n: int = 600) -> FloatArray:
    """The path of ``traj`` from ``t0`` on: ``n`` points equally spaced in route travel, in track coordinates.

    The motion is sampled every 0.5 ms from ``t0`` to the end of the motion; travel is the larger of the two
    robots' route-coordinate steps, summed.

    Parameters
    ----------
    traj : Trajectory
        A trajectory on a paper track (its plan's ``routes`` map route to track coordinates).
    t0 : float
        Start time (s), in ``[0, traj.motion_time]``.
    n : int
        Number of points.

    Returns
    -------
    numpy.ndarray
        Shape (n, 2): robot A's and B's track coordinates (m).
    """
    t = np.append(np.arange(t0, traj.motion_time, 1 / 2000.0), traj.motion_time)
    s = traj.sampler(t)[0]
    c = np.concatenate([[0.0], np.cumsum(np.max(np.abs(np.diff(s, axis=0)), axis=1))])
    u = np.linspace(0.0, c[-1], n)
    ss = np.stack([np.interp(u, c, s[:, 0]), np.interp(u, c, s[:, 1])], axis=1)
    r = traj.plan.routes
    return np.stack([r[0].position(ss[:, 0]), r[1].position(ss[:, 1])], axis=1)


def random_queries(track: Track, clearance: float, n: int, seed: int) -> list[tuple[FloatArray, FloatArray]]:
    """``n`` seeded random queries on a paper track whose start and goal both keep the clearance.

    Parameters
    ----------
    track : Track
    clearance : float
        Least track distance between the robots at the start and at the goal (m).
    n : int
        Number of queries.
    seed : int
        Seed of :func:`numpy.random.default_rng`; states are drawn uniformly in ``[0, total_length)`` until ``n``
        pairs keep the clearance.

    Returns
    -------
    list of (numpy.ndarray, numpy.ndarray)
        ``(start, goal)`` pairs, each of shape (2,): track coordinates of A and B (m).
    """
    rng = np.random.default_rng(seed)
    out: list[tuple[FloatArray, FloatArray]] = []
    while len(out) < n:
        s, g = rng.uniform(0.0, track.total_length, 2), rng.uniform(0.0, track.total_length, 2)
        if track.distance(*s) >= clearance and track.distance(*g) >= clearance:
            out.append((s, g))
    return out


def random_rules(layout: dict[str, Any], rng: np.random.Generator, oneway: float, limited: float, speed: float) -> Any:
    """A layout with seeded lane rules: each edge in turn one-way (the direction of its ``from``/``to``) with
    probability ``oneway``, then limited to ``speed`` m/s with probability ``limited``.

    Parameters
    ----------
    layout : dict
        A layout dict (:meth:`mpa.GraphTrack.to_dict`); its edges are marked in place.
    rng : numpy.random.Generator
        Two draws per edge.
    oneway, limited : float
        Probabilities in [0, 1].
    speed : float
        Speed limit of the limited edges (m/s).

    Returns
    -------
    GraphTrack
        The layout read back (:meth:`mpa.GraphTrack.from_layout`).
    """
    from mpa.graph_track import GraphTrack

    for e in layout["edges"]:
        if rng.random() < oneway:
            e["oneway"] = True
        if rng.random() < limited:
            e["speed_limit"] = speed
    return GraphTrack.from_layout(layout)
