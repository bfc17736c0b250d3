"""Measuring the stability of the whole pipeline: seeded perturbation pairs inside a domain and trajectory gaps.

A *perturbation pair* is a query ``(start, goal)`` and the query moved by ``δ`` (Euclidean norm of the move of the
four coordinates, metres) in a random direction, both valid and in the same domain of continuity. The *gap* of two
trajectories is the sup over the normalised time ``τ ∈ [0, 1]`` of the larger robot's graph distance between
their positions at ``τ·T`` (each at its own motion time ``T``); the makespan gap is ``|T₁ − T₂|``. A pipeline that
is continuous in the query has gaps that shrink with ``δ`` (``gap/δ`` bounded).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, cast

import numpy as np

from mpa._arrays import FloatArray
from mpa.errors import MPAError
from mpa.planners import Planner
from mpa.plans import Plan
from mpa.tracks import Interval
from trajopt.export import Trajectory

__all__ = [
    "LayoutTwin",
    "PerturbationPairs",
    "SwitchPoint",
    "layout_queries",
    "layout_twins",
    "perturbation_pairs",
    "route_coordinate_gap",
    "switch_points",
    "trajectory_gap",
]


@dataclass(frozen=True)
class PerturbationPairs:
    """Queries and their perturbed twins, all in one domain.

    Attributes
    ----------
    starts, goals : ndarray, shape (N, 2)
        The queries (track coordinates).
    directions : ndarray, shape (N, 4)
        Unit directions of the perturbation of ``(start, goal)``.
    domain : int
    """

    starts: FloatArray
    goals: FloatArray
    directions: FloatArray
    domain: int

    def perturbed(self, delta: float) -> tuple[FloatArray, FloatArray]:
        """Start and goal moved by ``delta`` (metres) along :attr:`directions`. Shapes (N, 2)."""
        return self.starts + delta * self.directions[:, :2], self.goals + delta * self.directions[:, 2:]


def _inside(planner: Planner, s: FloatArray, g: FloatArray, domain: int) -> bool:
    tr = planner.track
    hi = tr.total_length
    for p in (s, g):
        if np.any(p < 0) or np.any(p > hi) or (not isinstance(tr, Interval) and np.any(p >= hi)):
            return False
        if float(tr.distance(p[0], p[1])) < planner.clearance:
            return False
    try:
        return planner.plan(s, g).domain == domain
    except MPAError:
        return False


def perturbation_pairs(
    planner: Planner,
    domain: int,
    n: int,
    rng: np.random.Generator,
    max_delta: float = 1e-3,
    margin: float = 1e-6,
    max_tries: int = 200_000,
) -> PerturbationPairs:
    """``n`` seeded queries of ``domain`` whose moves by every ``δ ≤ max_delta`` stay valid and in the domain.

    The move is checked at ``max_delta`` and at ``max_delta·1e-4`` (a domain boundary between them is rare);
    queries whose robots are closer than ``clearance + margin + 2·max_delta`` at the start or goal are skipped.

    Raises
    ------
    MPAError
        If fewer than ``n`` queries were found within ``max_tries`` draws.
    """
    tr = planner.track
    hi = np.nextafter(tr.total_length, 0.0)
    s_l: list[FloatArray] = []
    g_l: list[FloatArray] = []
    d_l: list[FloatArray] = []
    tries = 0
    need = planner.clearance + margin + 2 * max_delta
    while len(s_l) < n:
        tries += 1
        if tries > max_tries:
            raise MPAError(f"found only {len(s_l)} of {n} pairs in domain {domain} after {max_tries} draws")
        s, g = rng.uniform(0.0, hi, 2), rng.uniform(0.0, hi, 2)
        if isinstance(tr, Interval) and np.sign(s[1] - s[0]) != np.sign(g[1] - g[0]):
            g = g[::-1]
        if float(tr.distance(s[0], s[1])) < need or float(tr.distance(g[0], g[1])) < need:
            continue
        try:
            if planner.plan(s, g).domain != domain:
                continue
        except MPAError:
            continue
        d = rng.normal(size=4)
        d /= np.linalg.norm(d)
        if not all(_inside(planner, s + f * d[:2], g + f * d[2:], domain) for f in (max_delta, max_delta * 1e-4)):
            continue
        s_l.append(s)
        g_l.append(g)
        d_l.append(d)
    return PerturbationPairs(np.array(s_l), np.array(g_l), np.array(d_l), domain)


def trajectory_gap(a: Trajectory, b: Trajectory, samples: int = 1001) -> tuple[float, float]:
    """Sup over normalised time of the larger robot's graph distance, and the motion-time gap (m, s)."""
    tau = np.linspace(0.0, 1.0, samples)
    pos = []
    for tr in (a, b):
        s = tr.sampler(tau * tr.motion_time)[0] if tr.motion_time > 0 else np.tile(tr.s[0], (samples, 1))
        routes = cast(Plan, tr.plan).routes  # paper plans (the stability measure, in track coordinates)
        pos.append(np.stack([routes[0].position(s[:, 0]), routes[1].position(s[:, 1])], axis=1))
    track = cast(Plan, a.plan).track
    gap = max(float(np.max(track.distance(pos[0][:, r], pos[1][:, r]))) for r in (0, 1))
    return gap, abs(a.motion_time - b.motion_time)


def route_coordinate_gap(a: Trajectory, b: Trajectory, samples: int = 1001) -> tuple[float, float]:
    """Sup over normalised time of the change of the exported route coordinates and of their speeds.

    The exported ``*_s`` and ``*_v`` columns (CSV, ROS positions, PVT rows) of two trajectories compared at the same
    normalised time ``τ·T`` (each at its own motion time ``T``), the larger robot's change: ``(m, m/s)``. Unlike
    :func:`trajectory_gap` (positions on the track) it also sees a flip of a route's orientation, which moves no
    cart but the columns a controller is fed.
    """
    tau = np.linspace(0.0, 1.0, samples)
    cols = []
    for tr in (a, b):
        if tr.motion_time > 0:
            s, v = tr.sampler(tau * tr.motion_time)[:2]
        else:
            s, v = np.tile(tr.s[0], (samples, 1)), np.zeros((samples, 2))
        cols.append((np.asarray(s, dtype=float), np.asarray(v, dtype=float)))
    ds = float(np.max(np.abs(cols[0][0] - cols[1][0])))
    dv = float(np.max(np.abs(cols[0][1] - cols[1][1])))
    return ds, dv


@dataclass(frozen=True)
class LayoutTwin:
    """One δ-twin of a query on a layout (plan level, the graph planner's ``fastest`` plans).

    Attributes
    ----------
    query : int
        Index of the query.
    clearance, delta : float
        D and the move of every position along its edge (metres).
    route_changed : bool
        The robots' routes (each robot's edges and directions, in order) differ between the query and its twin.
    gap : float
        Sup over the plans' common parameter ``u ∈ [0, 1]`` of the larger robot's graph distance between the two
        plans' positions (metres).
    makespan_gap : float
        Change of the plan's makespan (s).
    swap : bool
        The query is a swap (goal = start with the robots exchanged): with equal speeds every motion of it has a mirror
        image of the same makespan (the robots' roles exchanged and time reversed), so the query lies on a tie of the
        objective and its twin's move decides between the two by about δ.
    """

    query: int
    clearance: float
    delta: float
    route_changed: bool
    gap: float
    makespan_gap: float
    swap: bool = False


def layout_queries(
    track: Any, n: int, rng: np.random.Generator, clearances: tuple[float, ...], tries: int = 10_000
) -> list[tuple[float, tuple[Any, Any], tuple[Any, Any]]]:
    """Up to ``n`` seeded queries ``(D, start, goal)`` on a layout: positions uniform by length, robots at least
    ``D`` apart (plus 1e-6 m) at both ends, the clearances taken in turn; every fourth query a swap. A query whose
    clearance admits no such ends within ``tries`` draws is left out."""
    lengths = np.asarray(track.lengths, dtype=float)
    g = track.geometry
    out: list[tuple[float, tuple[Any, Any], tuple[Any, Any]]] = []

    def pos() -> tuple[int, float]:
        e = int(rng.choice(len(lengths), p=lengths / lengths.sum()))
        return e, float(rng.uniform(0.0, lengths[e]))

    for q in range(n):
        D = float(clearances[q % len(clearances)])
        for _ in range(tries):
            a, b = pos(), pos()
            c, d = (b, a) if q % 4 == 0 else (pos(), pos())
            if min(g.distance_scalar(*a, *b), g.distance_scalar(*c, *d)) >= D + 1e-6:
                out.append((D, (a, b), (c, d)))
                break
    return out


def _route_key(plan: Any) -> tuple[tuple[int, ...], ...]:
    ra, rb = plan.route_a, plan.route_b
    return (
        tuple(int(x) for x in ra.edges),
        tuple(int(x) for x in ra.dirs),
        tuple(int(x) for x in rb.edges),
        tuple(int(x) for x in rb.dirs),
    )


def layout_twins(
    track: Any,
    queries: list[tuple[float, tuple[Any, Any], tuple[Any, Any]]],
    deltas: tuple[float, ...],
    rng: np.random.Generator,
    speeds: tuple[float, float] = (1.0, 1.0),
    samples: int = 401,
) -> list[LayoutTwin]:
    """δ-twins of layout queries: each position moved by ``δ`` along its edge (a random side, inwards at an end).

    Queries without a motion, and twins whose ends come closer than the clearance, are skipped.
    """
    from mpa.errors import NoMotionError
    from mpa.planners.graph import plan_graph

    lengths = np.asarray(track.lengths, dtype=float)
    g = track.geometry
    u = np.linspace(0.0, 1.0, samples)
    out: list[LayoutTwin] = []

    def positions(p: Any) -> tuple[Any, Any, Any, Any]:
        (ea, sa), (eb, sb) = p.positions(u)
        return ea, sa, eb, sb

    for qi, (D, st, gl) in enumerate(queries):
        try:
            base = plan_graph(track, st, gl, D, "fastest", speeds)
        except NoMotionError:
            continue
        pb = positions(base)
        for delta in deltas:

            def nudge(p: tuple[int, float], delta: float = delta) -> tuple[int, float]:
                e, s = p
                t = s + (delta if rng.random() < 0.5 else -delta)
                if t < 0.0 or t > lengths[e]:
                    t = 2 * s - t
                return e, float(min(max(t, 0.0), lengths[e]))

            st2, gl2 = (nudge(st[0]), nudge(st[1])), (nudge(gl[0]), nudge(gl[1]))
            if min(g.distance_scalar(*st2[0], *st2[1]), g.distance_scalar(*gl2[0], *gl2[1])) < D:
                continue
            try:
                twin = plan_graph(track, st2, gl2, D, "fastest", speeds)
            except NoMotionError:
                continue
            p2 = positions(twin)
            gap = float(
                np.max(np.maximum(g.distance(pb[0], pb[1], p2[0], p2[1]), g.distance(pb[2], pb[3], p2[2], p2[3])))
            )
            out.append(
                LayoutTwin(
                    qi,
                    D,
                    delta,
                    _route_key(base) != _route_key(twin),
                    gap,
                    abs(base.makespan - twin.makespan),
                    swap=(tuple(gl[0]), tuple(gl[1])) == (tuple(st[1]), tuple(st[0])),
                )
            )
    return out


@dataclass(frozen=True)
class SwitchPoint:
    """A query on the fast/hard switch, bracketed to within ``width`` (metres, max-norm of the four coordinates).

    Attributes
    ----------
    fast_start, fast_goal, hard_start, hard_goal : ndarray, shape (2,)
        The queries on either side: the straight route-coordinate line keeps the separation (the line's side), or not.
    width : float
        Max-norm distance between the two queries (metres).
    gap : float
        :func:`trajectory_gap` of their trajectories (metres).
    time_gap : float
        Change of the motion time (s).
    paths : (str, str)
        ``solver_stats["path"]`` of the two trajectories (``"switch"``: the line's side, within the switch bands of
        :mod:`trajopt.path.switch`; ``"hard"``; another value if one fell back).
    """

    fast_start: FloatArray
    fast_goal: FloatArray
    hard_start: FloatArray
    hard_goal: FloatArray
    width: float
    gap: float
    time_gap: float
    paths: tuple[str, str]


def switch_points(
    gen: Any, n: int, rng: np.random.Generator, width: float = 1e-9, iterations: int = 80, reach: float = 0.1
) -> list[SwitchPoint]:
    """Bisection to the fast/hard switch on ``n`` seeded query pairs of a paper track, and the gap across it.

    Each draw is a start, a goal and a second goal moved from it by a normal step of standard deviation ``reach``
    (metres, per coordinate); when the straight line's clearance
    (:func:`trajopt.path.fastpath.straight_line_clearance`) is at least the separation the generator asks of it at one
    goal and below it at the other, with the same domain and word at both, the segment between the goals is bisected
    until the two sides are ``width`` apart (every midpoint must keep the domain and word, else the pair is
    dropped). The trajectories of the two sides are then generated and compared.

    Parameters
    ----------
    gen : TrajectoryGenerator
        Of a paper track.
    n : int
        Number of draws (each gives at most one switch point).
    rng : numpy.random.Generator
    width : float
        Bracket width at which the bisection stops (metres).

    Returns
    -------
    list of SwitchPoint
    """
    from trajopt.path.fastpath import straight_line_clearance
    from trajopt.verify.gate import separation_margin

    track = gen.track
    hi = np.nextafter(track.total_length, 0.0)
    sep = gen.clearance + separation_margin(gen.limits, gen.rate)

    def line(s: FloatArray, g: FloatArray) -> tuple[float, tuple[Any, ...]]:
        p = gen.plan(s, g)
        return straight_line_clearance(p), (p.domain, tuple(p.word))

    out: list[SwitchPoint] = []
    for _ in range(n):
        s, g0 = rng.uniform(0.0, hi, 2), rng.uniform(0.0, hi, 2)
        g1 = np.clip(g0 + rng.normal(scale=reach, size=2), 0.0, hi)
        try:
            (c0, k0), (c1, k1) = line(s, g0), line(s, g1)
        except MPAError:
            continue
        if k0 != k1 or (c0 >= sep) == (c1 >= sep) or min(c0, c1) == float("-inf"):
            continue
        if c0 < sep:
            g0, g1 = g1, g0
        lo_g, hi_g = g0, g1  # lo: fast side, hi: hard side
        ok = True
        for _ in range(iterations):
            if float(np.max(np.abs(hi_g - lo_g))) <= width:
                break
            mid = 0.5 * (lo_g + hi_g)
            try:
                c, k = line(s, mid)
            except MPAError:
                ok = False
                break
            if k != k0:
                ok = False
                break
            if c >= sep:
                lo_g = mid
            else:
                hi_g = mid
        if not ok:
            continue
        try:
            fast, hard = gen.generate(s, lo_g), gen.generate(s, hi_g)
        except MPAError:
            continue
        gap, dt = trajectory_gap(fast, hard)
        paths = (str(fast.solver_stats.get("path", "plan")), str(hard.solver_stats.get("path", "plan")))
        out.append(SwitchPoint(s, lo_g, s, hi_g, float(np.max(np.abs(hi_g - lo_g))), gap, dt, paths))
    return out
