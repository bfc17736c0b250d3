"""An independent checker of exported setpoints, for the test suite and the soak script (not the gate).

:func:`check_setpoints` re-checks what :func:`trajopt.verify.verify_setpoints` promises, written separately
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
:class:`~trajopt.export.Trajectory`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa.homotopy import path_word
from mpa.tracks import Track

__all__ = [
    "LIMIT_RTOL",
    "POS_TOL",
    "SEP_TOL",
    "GraphMetric",
    "check_graph_setpoints",
    "check_graph_trajectory",
    "check_setpoints",
    "check_trajectory",
]

FloatArray = NDArray[np.float64]
#: Relative tolerance of the limit checks.
LIMIT_RTOL = 1e-6
#: Absolute tolerance of positions and rest (m, m/s, m/s²).
POS_TOL = 1e-9
#: Absolute tolerance of the separation checks (m).
SEP_TOL = 1e-9


def check_setpoints(
    track: Track,
    t: ArrayLike,
    pos: ArrayLike,
    s: ArrayLike,
    v: ArrayLike,
    a: ArrayLike,
    j: ArrayLike,
    *,
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
    t : array_like, shape (N,)
        Times (s).
    pos : array_like, shape (N, 2)
        Track coordinates of A and B (m).
    s, v, a, j : array_like, shape (N, 2)
        Route coordinates and their derivatives (m, m/s, m/s², m/s³).
    rate : float
        Row rate (Hz).
    clearance : float
        Required separation (m).
    vmax, amax, jmax : array_like, shape (2,)
        Per-robot limits.
    start, goal : array_like, shape (2,)
        Track coordinates of the query.
    """
    fails: list[str] = []
    tt = np.asarray(t, dtype=float)
    arrs = [np.asarray(x, dtype=float) for x in (pos, s, v, a, j)]
    n = len(tt)
    if n < 1 or any(x.shape != (n, 2) for x in arrs):
        return [f"shapes {tt.shape} and {[x.shape for x in arrs]} are not (N,) and (N, 2)"]
    if not (np.all(np.isfinite(tt)) and all(np.all(np.isfinite(x)) for x in arrs)):
        return ["non-finite values"]
    P, S, V, A, J = arrs
    dt = 1.0 / float(rate)
    V_, A_, J_ = (np.broadcast_to(np.asarray(x, dtype=float), (2,)) for x in (vmax, amax, jmax))
    k = np.arange(n)
    if np.max(np.abs(tt - k * dt)) > 1e-9 * max(1.0, tt[-1]):
        fails.append("time grid is not k / rate")
    for name, row, target in (("first", 0, start), ("last", n - 1, goal)):
        err = track.distance(P[row], np.asarray(target, dtype=float))
        if np.any(err > POS_TOL):
            fails.append(f"{name} row at {P[row].tolist()} is {err.tolist()} from {np.asarray(target).tolist()}")
        if np.any(np.abs(V[row]) > POS_TOL) or np.any(np.abs(A[row]) > POS_TOL):
            fails.append(f"{name} row not at rest: v {V[row].tolist()}, a {A[row].tolist()}")
    for name, x, lim in (("v", V, V_), ("a", A, A_), ("j", J, J_)):
        peak = np.max(np.abs(x), axis=0)
        if np.any(peak > lim * (1 + LIMIT_RTOL)):
            fails.append(f"|{name}| peaks {peak.tolist()} above {lim.tolist()}")
    if n > 1:
        # s(t+dt) - s(t) = dt (v0 + v1)/2 + dt² (a0 - a1)/12 + O(J dt³) ; v(t+dt) - v(t) = dt (a0 + a1)/2 + O(J dt²)
        ds_pred = dt * 0.5 * (V[:-1] + V[1:]) + dt * dt * (A[:-1] - A[1:]) / 12.0
        e_s = np.abs(np.diff(S, axis=0) - ds_pred)
        if np.any(e_s > J_ * dt**3 / 6.0 + 1e-9):
            r = int(np.argmax(np.max(e_s - J_ * dt**3 / 6.0, axis=1)))
            fails.append(f"rows {r}-{r + 1}: s is not the integral of v and a (error {e_s[r].tolist()})")
        e_v = np.abs(np.diff(V, axis=0) - dt * 0.5 * (A[:-1] + A[1:]))
        if np.any(e_v > J_ * dt * dt / 4.0 + 1e-9):
            r = int(np.argmax(np.max(e_v - J_ * dt * dt / 4.0, axis=1)))
            fails.append(f"rows {r}-{r + 1}: v is not the integral of a (error {e_v[r].tolist()})")
        e_a = np.abs(np.diff(A, axis=0))
        if np.any(e_a > J_ * dt * (1 + LIMIT_RTOL) + 1e-9):
            fails.append("a changes faster than jmax between rows")
        for r in (0, 1):
            step = track.distance(P[:-1, r], P[1:, r])
            if np.any(step > V_[r] * dt * (1 + LIMIT_RTOL) + POS_TOL):
                fails.append(f"robot {'AB'[r]} jumps {float(np.max(step))!r} m between rows")
    d = track.distance(P[:, 0], P[:, 1])
    if np.min(d) < clearance - SEP_TOL:
        r = int(np.argmin(d))
        fails.append(f"row {r}: separation {float(d[r])!r} < clearance {float(clearance)!r}")
    return fails


def check_trajectory(
    traj: Any, start: ArrayLike | None = None, goal: ArrayLike | None = None, *, fine: int = 8
) -> list[str]:
    """Check a :class:`~trajopt.export.Trajectory` (its rows, and its continuous motion ``fine`` times denser).

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
    lim = traj.limits
    fails = check_setpoints(
        track,
        traj.t,
        traj.track,
        traj.s,
        traj.v,
        traj.a,
        traj.j,
        rate=traj.rate,
        clearance=traj.clearance,
        vmax=lim.v,
        amax=lim.a,
        jmax=lim.j,
        start=st,
        goal=gl,
    )
    if traj.makespan < traj.motion_time - 1e-12 or traj.makespan - traj.motion_time > 1.0 / traj.rate + 1e-12:
        fails.append("makespan is not the motion time rounded up to the grid")
    if fine > 0:
        tf = np.linspace(0.0, traj.makespan, max(2, fine * (len(traj.t) - 1) + 1))
        s, _v, _a, _j = traj.sampler(tf)
        routes: Sequence[Any] = plan.routes
        pos = np.stack([routes[0].position(s[:, 0]), routes[1].position(s[:, 1])], axis=1)
        d = track.distance(pos[:, 0], pos[:, 1])
        if np.min(d) < traj.clearance - SEP_TOL:
            r = int(np.argmin(d))
            fails.append(f"t = {tf[r]:.6f}: separation {float(d[r])!r} < clearance {float(traj.clearance)!r}")
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

    def __init__(self, track: Any) -> None:
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
    track: Any,
    t: ArrayLike,
    edges: ArrayLike,
    offsets: ArrayLike,
    s: ArrayLike,
    v: ArrayLike,
    a: ArrayLike,
    j: ArrayLike,
    *,
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
    t : array_like, shape (N,)
    edges : array_like of int, shape (N, 2)
        Edge indices of A and B.
    offsets : array_like, shape (N, 2)
        Offsets from the edges' tails (m).
    s, v, a, j : array_like, shape (N, 2)
    rate, clearance : float
    vmax, amax, jmax : array_like, shape (2,)
    start, goal : pair of (edge index, offset)
    dirs : array_like of int, shape (N, 2), optional
    metric : GraphMetric, optional
        Re-used if given.
    """
    fails: list[str] = []
    tt = np.asarray(t, dtype=float)
    E = np.asarray(edges, dtype=np.int64)
    arrs = [np.asarray(x, dtype=float) for x in (offsets, s, v, a, j)]
    n = len(tt)
    if n < 1 or E.shape != (n, 2) or any(x.shape != (n, 2) for x in arrs):
        return [f"shapes {tt.shape}, {E.shape} and {[x.shape for x in arrs]} are not (N,) and (N, 2)"]
    if not (np.all(np.isfinite(tt)) and all(np.all(np.isfinite(x)) for x in arrs)):
        return ["non-finite values"]
    OF, S, V, A, J = arrs
    m = metric or GraphMetric(track)
    L = m.lengths
    if np.any(E < 0) or np.any(E >= len(L)):
        return ["edge index out of range"]
    dt = 1.0 / float(rate)
    V_, A_, J_ = (np.broadcast_to(np.asarray(x, dtype=float), (2,)) for x in (vmax, amax, jmax))
    if np.max(np.abs(tt - np.arange(n) * dt)) > 1e-9 * max(1.0, tt[-1]):
        fails.append("time grid is not k / rate")
    if np.any(OF < -POS_TOL) or np.any(OF > L[E] + POS_TOL):
        fails.append("offset outside [0, length] of its edge")
    for name, row, target in (("first", 0, start), ("last", n - 1, goal)):
        err = [float(m(E[row, r], OF[row, r], target[r][0], target[r][1])) for r in (0, 1)]
        if max(err) > POS_TOL:
            fails.append(f"{name} row is {err} from {list(target)}")
        if np.any(np.abs(V[row]) > POS_TOL) or np.any(np.abs(A[row]) > POS_TOL):
            fails.append(f"{name} row not at rest: v {V[row].tolist()}, a {A[row].tolist()}")
    for name, x, lim in (("v", V, V_), ("a", A, A_), ("j", J, J_)):
        peak = np.max(np.abs(x), axis=0)
        if np.any(peak > lim * (1 + LIMIT_RTOL)):
            fails.append(f"|{name}| peaks {peak.tolist()} above {lim.tolist()}")
    if n > 1:
        ds_pred = dt * 0.5 * (V[:-1] + V[1:]) + dt * dt * (A[:-1] - A[1:]) / 12.0
        if np.any(np.abs(np.diff(S, axis=0) - ds_pred) > J_ * dt**3 / 6.0 + 1e-9):
            fails.append("s is not the integral of v and a")
        if np.any(np.abs(np.diff(V, axis=0) - dt * 0.5 * (A[:-1] + A[1:])) > J_ * dt * dt / 4.0 + 1e-9):
            fails.append("v is not the integral of a")
        tails, heads = m.tails, m.heads
        for r in (0, 1):
            step = m(E[:-1, r], OF[:-1, r], E[1:, r], OF[1:, r])
            bound = np.minimum(np.abs(np.diff(S[:, r])), V_[r] * dt * (1 + LIMIT_RTOL))
            if np.any(step > bound + POS_TOL):
                k = int(np.argmax(step - bound))
                fails.append(
                    f"robot {'AB'[r]} moves {float(step[k])!r} m between rows {k}-{k + 1}, more than {bound[k]!r}"
                )
            ch = np.flatnonzero(E[:-1, r] != E[1:, r])
            e0, e1 = E[ch, r], E[ch + 1, r]
            shared = (
                (tails[e0] == tails[e1])
                | (tails[e0] == heads[e1])
                | (heads[e0] == tails[e1])
                | (heads[e0] == heads[e1])
            )
            if not np.all(shared):
                k = int(ch[np.argmin(shared)])
                fails.append(f"robot {'AB'[r]} changes from edge {E[k, r]} to {E[k + 1, r]} (no shared vertex)")
    if dirs is not None:
        Dr = np.asarray(dirs, dtype=np.int64)
        moving = np.abs(V) > 1e-9
        if Dr.shape != (n, 2) or np.any((Dr != 0) != moving) or np.any(np.abs(Dr) > 1):
            fails.append("dir is not 0 exactly at rest and ±1 in motion")
        elif n > 1:
            same = (E[:-1] == E[1:]) & (Dr[:-1] == Dr[1:]) & (Dr[:-1] != 0)
            dO = np.diff(OF, axis=0)
            ln = L[E[:-1]]
            loop = m.tails[E[:-1]] == m.heads[E[:-1]]  # a loop edge: the offset wraps at its vertex
            dO = np.where(loop, (dO + 0.5 * ln) % ln - 0.5 * ln, dO)
            bad = same & (np.abs(dO) > 1e-12) & (np.sign(dO) != Dr[:-1])
            if np.any(bad):
                k, r = (int(x[0]) for x in np.nonzero(bad))
                fails.append(f"row {k}: robot {'AB'[r]} dir {Dr[k, r]} but its offset changes by {dO[k, r]!r}")
    d = m(E[:, 0], OF[:, 0], E[:, 1], OF[:, 1])
    if np.min(d) < clearance - SEP_TOL:
        r = int(np.argmin(d))
        fails.append(f"row {r}: separation {float(d[r])!r} < clearance {float(clearance)!r}")
    return fails


def check_graph_trajectory(traj: Any, *, fine: int = 8) -> list[str]:
    """Check a :class:`~trajopt.export.Trajectory` on a layout (rows and the continuous motion ``fine`` times denser).

    The rows' positions are the trajectory's (:attr:`~trajopt.export.Trajectory.edges`, ``offsets``,
    ``directions``); the dense grid follows the plan's routes (:meth:`mpa.geometry.DirectedRoute.positions`).
    """
    plan = traj.plan
    m = GraphMetric(plan.track)
    lim = traj.limits
    fails = check_graph_setpoints(
        plan.track,
        traj.t,
        traj.edges,
        traj.offsets,
        traj.s,
        traj.v,
        traj.a,
        traj.j,
        rate=traj.rate,
        clearance=traj.clearance,
        vmax=lim.v,
        amax=lim.a,
        jmax=lim.j,
        start=plan.start,
        goal=plan.goal,
        dirs=traj.directions,
        metric=m,
    )
    if traj.makespan < traj.motion_time - 1e-12 or traj.makespan - traj.motion_time > 1.0 / traj.rate + 1e-12:
        fails.append("makespan is not the motion time rounded up to the grid")
    if fine > 0 and len(traj.t) > 1:
        tf = np.linspace(0.0, traj.makespan, max(2, fine * (len(traj.t) - 1) + 1))
        s, _v, _a, _j = traj.sampler(tf)
        (ea, oa), (eb, ob) = plan.route_a.positions(s[:, 0]), plan.route_b.positions(s[:, 1])
        d = m(ea, oa, eb, ob)
        if np.min(d) < traj.clearance - SEP_TOL:
            r = int(np.argmin(d))
            fails.append(f"t = {tf[r]:.6f}: separation {float(d[r])!r} < clearance {float(traj.clearance)!r}")
    return fails
