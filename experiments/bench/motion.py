"""Timing and verification of the baselines with ``trajopt``'s own stages, and a common motion sampler.

Every segment of a baseline's joint path (:func:`~bench.geometry.split_routes`) is a polyline in route
coordinates, so it goes through exactly the stages ``trajopt.TrajectoryGenerator`` uses:

- ``"rest"``: :func:`trajopt.timing.blend_polyline` without blends (every corner at rest) and
  :func:`trajopt.timing.jerk_limited_scaling`: each straight piece timed by one 1-DoF ruckig profile, i.e. the
  exact path, stopping at every waypoint (this is also how the raw plan is timed);
- ``"smooth"``: collision-checked quintic corner blends (:class:`mpa.geometry.RouteGeometry` gives the
  exact minimum separation), toppra's profile as speed caps, then ruckig, exactly as ``trajopt`` times its
  smoothed path.

Every segment is sampled at the controller rate and passed through :func:`trajopt.verify.gate.verify_setpoints`
(limits, separation at and between rows, endpoints at rest, route consistency, homotopy class of the rows). The
robots stop between segments (a robot turning back must stop).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from bench.geometry import RouteSegment
from mpa.errors import MPAError
from mpa.homotopy import path_word
from mpa.routes import Route
from mpa.tracks import Track
from trajopt import Limits, Trajectory, verify_setpoints
from trajopt.export import time_grid
from trajopt.path.planview import densify, route_geometry
from trajopt.timing import blend_polyline, jerk_limited_scaling, toppra_profile

__all__ = ["Motion", "TimedSegment", "time_segments"]

FloatArray = NDArray[np.float64]
Sampler = Callable[[FloatArray], tuple[FloatArray, FloatArray, FloatArray, FloatArray]]


@dataclass(frozen=True)
class TimedSegment:
    """One rest-to-rest piece of a motion.

    Attributes
    ----------
    t0 : float
        Start time in the whole motion (s).
    duration : float
        Motion time of the piece (s).
    sampler : callable
        ``sampler(t_local)`` -> ``s, v, a, j`` (route coordinates and derivatives, each shape (N, 2)).
    routes : tuple of Route
    """

    t0: float
    duration: float
    sampler: Sampler = field(repr=False)
    routes: tuple[Route, Route] = field(repr=False)


@dataclass(frozen=True)
class Motion:
    """A continuous motion of both robots made of rest-to-rest pieces; sampled at any time.

    Attributes
    ----------
    track : Track
    segments : tuple of TimedSegment
    duration : float
        Total motion time (s): the makespan every method is compared by.
    start, goal : ndarray, shape (2,)
    """

    track: Track
    segments: tuple[TimedSegment, ...]
    duration: float
    start: FloatArray
    goal: FloatArray

    @classmethod
    def from_trajectory(cls, traj: Trajectory) -> Motion:
        """The continuous motion behind a ``trajopt`` trajectory (ours or the raw plan)."""
        seg = TimedSegment(0.0, float(traj.motion_time), traj.sampler, traj.plan.routes)
        return cls(traj.plan.track, (seg,), float(traj.motion_time), traj.plan.start.copy(), traj.plan.goal.copy())

    def positions(self, t: FloatArray) -> FloatArray:
        """Track coordinates of both robots at times ``t`` (clipped to the motion). Shape (N, 2)."""
        tt = np.clip(np.asarray(t, dtype=float), 0.0, self.duration)
        out = np.empty((len(tt), 2))
        out[:] = self.goal
        if not self.segments:
            out[:] = self.start
            return out
        starts = np.array([s.t0 for s in self.segments])
        idx = np.clip(np.searchsorted(starts, tt, side="right") - 1, 0, len(starts) - 1)
        for i, seg in enumerate(self.segments):
            m = idx == i
            if not np.any(m):
                continue
            s = seg.sampler(np.clip(tt[m] - seg.t0, 0.0, seg.duration))[0]
            out[m, 0] = seg.routes[0].position(s[:, 0])
            out[m, 1] = seg.routes[1].position(s[:, 1])
        return out

    def normalized(self, n: int = 401) -> FloatArray:
        """Positions at ``n`` equally spaced fractions of the motion time. Shape (n, 2)."""
        return self.positions(np.linspace(0.0, self.duration, n))


@dataclass(frozen=True)
class TimingOutcome:
    """Result of :func:`time_segments`.

    Attributes
    ----------
    motion : Motion
    verified : bool
        Every segment passed the gate.
    min_separation : float
        Smallest separation at the rows of all segments (m).
    failures : tuple of str
    word : tuple of str
        Reduced skeleton word of the whole motion (rows refined along the chords).
    rests : int
        Number of intermediate stops (segment joins plus corners passed at rest).
    stats : dict
    """

    motion: Motion
    verified: bool
    min_separation: float
    failures: tuple[str, ...]
    word: tuple[str, ...]
    rests: int
    stats: dict[str, Any]


def merge_collinear(nodes: FloatArray, tol: float = 1e-9) -> NDArray[np.intp]:
    """Indices of the nodes to keep: drop interior nodes within ``tol`` (m) of the chord of their neighbours,
    when the path goes straight on through them (not when it turns back)."""
    keep = [0]
    for i in range(1, len(nodes) - 1):
        a, b, c = nodes[keep[-1]], nodes[i], nodes[i + 1]
        u, w = c - a, b - a
        nu = float(np.hypot(u[0], u[1]))
        if nu > 0:
            dev = abs(u[0] * w[1] - u[1] * w[0]) / nu
            t = float(u @ w) / (nu * nu)
            if dev <= tol and 0.0 < t < 1.0:
                continue
        keep.append(i)
    keep.append(len(nodes) - 1)
    return np.array(keep, dtype=np.intp)


def _refined_positions(routes: Sequence[Route], s: FloatArray, step: float) -> FloatArray:
    dense = densify(s, step)
    return np.stack([routes[0].position(dense[:, 0]), routes[1].position(dense[:, 1])], axis=1)


def time_segments(
    track: Track,
    segments: Sequence[RouteSegment],
    *,
    mode: str,
    limits: Limits,
    clearance: float,
    separation: float,
    rate: float,
    start: FloatArray,
    goal: FloatArray,
) -> TimingOutcome:
    """Time every segment (``mode`` "rest" or "smooth"), sample it, and verify it.

    Parameters
    ----------
    track : Track
    segments : sequence of RouteSegment
    mode : {"rest", "smooth"}
    limits : Limits
    clearance : float
        Required separation D (m) checked by the gate.
    separation : float
        Separation corner blends must keep (D plus the gate's between-rows margin).
    rate : float
        Setpoint rate (Hz).
    start, goal : ndarray, shape (2,)
        The query (used when the path does not move, and to check the ends).

    Returns
    -------
    TimingOutcome
        Never raises for a failed check: ``verified`` is False and ``failures`` says why.
    """
    timed: list[TimedSegment] = []
    fails: list[str] = []
    dmin = np.inf
    t_acc = 0.0
    rests = max(0, len(segments) - 1)
    word_pts: list[FloatArray] = []
    step = 0.004 * track.total_length
    stats: dict[str, Any] = {"segments": len(segments), "pieces": 0, "blends": 0}
    for i, seg in enumerate(segments):
        geom = route_geometry(track, seg.routes)
        d_ends = min(float(geom.distance(seg.nodes[0])), float(geom.distance(seg.nodes[-1])))
        keep = merge_collinear(seg.nodes)
        if len(keep) < len(seg.nodes) and geom.polyline_min_distance(seg.nodes[keep]) >= min(separation, d_ends):
            seg = RouteSegment(seg.routes, seg.nodes[keep], seg.states[keep])
        try:
            if mode == "smooth":
                path = blend_polyline(seg.nodes, geom.polyline_min_distance, min(separation, d_ends))
                caps = None
                if path.length > 0:
                    grid, sd, _dur = toppra_profile(path, limits)
                    caps = sd[np.searchsorted(grid, path.breaks).clip(0, len(grid) - 1)]
                scaling = jerk_limited_scaling(path, limits, caps)
            else:
                path = blend_polyline(seg.nodes)
                scaling = jerk_limited_scaling(path, limits)
        except MPAError as exc:
            fails.append(f"segment {i}: timing failed: {exc}")
            continue
        rests += int(np.sum(path.stop[1:-1]))
        stats["pieces"] += len(path.coef)
        stats["blends"] += int(np.sum(path.is_blend))
        t = time_grid(scaling.duration, rate)
        s, v, a, j = scaling.sample(t)
        tr = np.stack([seg.routes[0].position(s[:, 0]), seg.routes[1].position(s[:, 1])], axis=1)
        try:
            word = path_word(track, _refined_positions(seg.routes, seg.nodes, step))
        except MPAError as exc:
            fails.append(f"segment {i}: homotopy class of the path: {exc}")
            word = ()
        rep = verify_setpoints(
            track,
            seg.routes,
            t,
            tr,
            s,
            v,
            a,
            j,
            limits=limits,
            clearance=clearance,
            start=seg.states[0],
            goal=seg.states[-1],
            word=word,
            rate=rate,
        )
        if not rep.ok:
            fails.extend(f"segment {i}: {f}" for f in rep.failures)
        dmin = min(dmin, rep.min_separation)
        word_pts.append(_refined_positions(seg.routes, s, step))
        timed.append(TimedSegment(t_acc, scaling.duration, scaling.sample, seg.routes))
        t_acc += scaling.duration
    if segments:
        if float(np.max(track.distance(segments[0].states[0], start))) > 1e-9:
            fails.append("path does not start at the start")
        if float(np.max(track.distance(segments[-1].states[-1], goal))) > 1e-9:
            fails.append("path does not end at the goal")
    try:
        pts = np.vstack(word_pts) if word_pts else np.asarray(start, dtype=float)[None, :]
        whole = path_word(track, pts)
    except MPAError as exc:
        fails.append(f"homotopy class of the motion: {exc}")
        whole = ()
    if not segments:
        dmin = float(track.distance(start[0], start[1]))
    motion = Motion(track, tuple(timed), t_acc, np.asarray(start, dtype=float), np.asarray(goal, dtype=float))
    return TimingOutcome(motion, not fails, float(dmin), tuple(fails), tuple(whole), rests, stats)
