"""The planners a robotics engineer would pick instead of the topological plan: OMPL and a grid search.

Both return a :class:`~bench.geometry.JointPath` whose every leg was checked *exactly* against the separation
(:func:`~bench.geometry.joint_move_min_distance`: the graph distance is piecewise affine along a leg, so its
minimum is found at finitely many candidate points; no sampling, no corner cutting).

OMPL (:class:`OmplPlanner`, ``ompl`` 2.x from PyPI). The configuration space is the product of the robots'
coordinates: on the circle ``SO2 × SO2`` (angles in [−π, π), OMPL interpolates along the shorter arc); on the
lollipop a ``RealVectorStateSpace(2)`` of *track coordinates*, whose straight-line interpolation is a valid motion
(each robot moves monotonically along its coordinate, through P between stick and loop) but cannot pass the
loop's seam at ``ℓ + c``: a robot must go round instead. That is what a quick user gets. A Python validity
callable (``d ≥ separation``) and a :class:`ompl.base.MotionValidator` subclass with the exact leg check;
``RRTConnect`` with a fixed time budget; then OMPL's ``PathSimplifier`` shortcuts (``reduceVertices``,
``collapseCloseVertices``, ``partialShortcutPath``: what ``simplifyMax`` does before its B-spline step) and,
for the smoothed variant, ``smoothBSpline`` (every new chord checked by the same validator, and the result
re-checked exactly). Seeded per query: :func:`ompl.util.RNG.setSeed` re-seeds the generator of the RNG seeds
(OMPL logs an error when that happens after sampling started, but re-seeds; the log is silenced), and every
OMPL object is created afterwards, so a query's result does not depend on what ran before in the process.

Grid (:class:`GridPlanner`). The configuration space is the product of two copies of the discretized track
*graph* (stick nodes ``0, h, …, ℓ`` and loop nodes every ``≈ h`` with the loop closing at P, so paths pass P
along the loop and round the seam); each robot moves to a neighbour node or stays; every edge is checked
exactly (a vertex-only check would cut corners); edge cost ``max(|Δa|/vA, |Δb|/vB)`` (time-like L∞) plus
``1e-3`` times the sum (tie-break against free wiggles); A* with the admissible and consistent heuristic
``max_r d(node_r, goal_r)/v_r``. Start and goal connect to the four grid states around them. The edge set does
not depend on the query and is built once per planner.
"""

from __future__ import annotations

import heapq
import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from bench.geometry import (
    JointPath,
    RouteSegment,
    joint_move_min_distance,
    leg_moves_circle,
    leg_moves_geodesic,
    leg_moves_track_coordinates,
    single_edge_min_distance_vec,
)
from bench.ompl_tools import joint_state_space, simplify_vertices
from mpa.routes import RobotMove
from mpa.tracks import Circle, Lollipop, Track
from trajopt.path.planview import route_geometry

__all__ = ["GridPlanner", "GridResult", "OmplPlanner", "OmplResult", "shortcut_segment"]

FloatArray = NDArray[np.float64]
#: Weight of the tie-break term of the grid's edge cost.
TIE_BREAK = 1e-3


# ---------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class OmplResult:
    """Outcome of one OMPL query.

    Attributes
    ----------
    solved : bool
        RRTConnect found an exact solution within the budget.
    simplified : JointPath or None
        The shortcut path (OMPL's waypoints).
    bspline : JointPath or None
        The B-spline-smoothed path.
    times : dict
        Seconds spent in ``setup`` (spaces, validators, planner), ``solve``, ``simplify``, ``bspline``.
    stats : dict
        Validity and motion checks, state counts, planner status.
    """

    solved: bool
    simplified: JointPath | None
    bspline: JointPath | None
    times: dict[str, float]
    stats: dict[str, Any] = field(default_factory=dict)


class OmplPlanner:
    """RRTConnect in the robots' configuration space with an exact motion validator (see module docstring).

    Parameters
    ----------
    track : Track
        A lollipop or a circle.
    separation : float
        Separation every state and motion must keep (m).
    budget : float
        Time budget of ``RRTConnect`` per query (s).
    bspline_steps : int
        ``maxSteps`` of ``smoothBSpline`` (OMPL's ``simplifyMax`` uses 3).
    geodesic : bool
        Lollipop only. False: a motion between two states is the straight line in track coordinates (OMPL's own
        interpolation; the robots can then never change their coordinate order, see the module docstring).
        True: the motion validator and the executed path take every robot along a *shortest path of the track*
        between the two states (through the seam when shorter), while OMPL keeps sampling and extending in track
        coordinates; only vertex-to-vertex simplification (``reduceVertices``, ``collapseCloseVertices``) is
        used then, because OMPL's partial shortcuts and B-splines interpolate in coordinates. Its range is the
        space's maximum extent: a step must be able to span more than half the loop in coordinates to pass the
        seam (with OMPL's default range, 0.2 × the extent, it failed on 5 of 6 queries on a lollipop (0.3, 1.5)).
    """

    def __init__(
        self, track: Track, separation: float, budget: float = 1.0, bspline_steps: int = 3, geodesic: bool = False
    ) -> None:
        from ompl import util as ou

        ou.setLogLevel(ou.LOG_NONE)
        self.track = track
        self.separation = float(separation)
        self.budget = float(budget)
        self.bspline_steps = int(bspline_steps)
        self.circle = isinstance(track, Circle)
        self.geodesic = bool(geodesic) and not self.circle
        self._scale = track.loop / (2.0 * math.pi) if isinstance(track, Circle) else 1.0
        self._space: Any = None  # the joint state space of the query being solved

    # --- state conversion ------------------------------------------------------------------------
    def _to_track(self, state: Any) -> tuple[float, float]:
        if self.circle:
            # the angles read through the space, not as state[r].value: the bindings hand a component back as the
            # Python object they last made for its address, and a compound state's, freed and its memory reused
            # for an angle, came back without .value (once in about ten runs, in the path simplifier)
            c = self.track.loop  # type: ignore[attr-defined]
            read = self._space.getValueAddressAtIndex
            return (read(state, 0) * self._scale) % c, (read(state, 1) * self._scale) % c
        return state[0], state[1]

    def _set(self, state: Any, p: ArrayLike) -> None:
        p = np.asarray(p, dtype=float)
        if self.circle:
            for r in (0, 1):
                ang = float(p[r]) / self._scale
                state[r].value = (ang + math.pi) % (2.0 * math.pi) - math.pi
        else:
            state[0], state[1] = float(p[0]), float(p[1])

    def _legs(self, a: tuple[float, float], b: tuple[float, float]) -> tuple[tuple[RobotMove, ...], ...]:
        if self.circle:
            fn = leg_moves_circle
        else:
            fn = leg_moves_geodesic if self.geodesic else leg_moves_track_coordinates
        return fn(self.track, a[0], b[0]), fn(self.track, a[1], b[1])

    def _path(self, path: Any) -> JointPath:
        pts = np.array([self._to_track(s) for s in path.getStates()], dtype=float)
        return JointPath.from_states(self.track, pts, geodesic=self.geodesic)

    # --- one query -------------------------------------------------------------------------------
    def solve(self, start: ArrayLike, goal: ArrayLike, seed: int) -> OmplResult:
        """Plan one query (``seed`` ≥ 1 seeds OMPL's random numbers)."""
        from ompl import base as ob
        from ompl import geometric as og
        from ompl import util as ou

        t0 = time.perf_counter()
        ou.RNG.setSeed(int(seed))
        track, sep = self.track, self.separation
        dist = track.distance_scalar
        counts = {"states": 0, "motions": 0}
        space = self._space = joint_state_space(ob, track.total_length, circle=self.circle)
        ss = og.SimpleSetup(space)
        to_track = self._to_track

        def valid(state: Any) -> bool:
            counts["states"] += 1
            a, b = to_track(state)
            return dist(a, b) >= sep

        legs = self._legs

        class ExactMotionValidator(ob.MotionValidator):  # type: ignore[misc]
            def checkMotion(self, s1: Any, s2: Any, *_last: Any) -> bool:
                counts["motions"] += 1
                a, b = to_track(s1), to_track(s2)
                ma, mb = legs(a, b)
                return joint_move_min_distance(track, ma, mb) >= sep

        ss.setStateValidityChecker(valid)
        si = ss.getSpaceInformation()
        validator = ExactMotionValidator(si)
        si.setMotionValidator(validator)
        st, gl = space.allocState(), space.allocState()
        self._set(st, start)
        self._set(gl, goal)
        ss.setStartAndGoalStates(st, gl)
        planner = og.RRTConnect(si)
        if self.geodesic:
            # a step must be able to span more than half the loop in coordinates to pass the seam
            planner.setRange(space.getMaximumExtent())
        ss.setPlanner(planner)
        t1 = time.perf_counter()
        # a timed condition without a checking thread: OMPL's solve(t) starts one for t >= 1 s, and joining it
        # costs up to its 10 ms period per query (measured: p95 4.1 ms instead of 0.8 ms on the lean pipeline)
        status = ss.solve(ob.timedPlannerTerminationCondition(self.budget))
        t2 = time.perf_counter()
        times = {"setup": t1 - t0, "solve": t2 - t1, "simplify": 0.0, "bspline": 0.0}
        stats: dict[str, Any] = {"status": str(status)}
        if not ss.haveExactSolutionPath():
            stats.update(counts)
            return OmplResult(False, None, None, times, stats)
        path = og.PathGeometric(ss.getSolutionPath())
        stats["rrt_states"] = path.getStateCount()
        simp = og.PathSimplifier(si)
        simplify_vertices(simp, path)
        k = 0
        while not self.geodesic and simp.partialShortcutPath(path) and k < 5:
            k += 1
        t3 = time.perf_counter()
        times["simplify"] = t3 - t2
        simplified = self._path(path)
        bspline = None
        if not self.geodesic:
            smooth = og.PathGeometric(path)
            simp.smoothBSpline(smooth, self.bspline_steps, smooth.length() / 100.0)
            bspline = self._path(smooth)
            stats["bspline_waypoints"] = len(bspline.states)
        times["bspline"] = time.perf_counter() - t3
        stats.update(counts)
        stats["waypoints"] = len(simplified.states)
        # the planner's objects hold Python callbacks; drop the cycle explicitly
        del validator, ss, si
        return OmplResult(True, simplified, bspline, times, stats)


# ---------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class RobotGraph:
    """The discretized track graph of one robot: nodes and directed single-edge moves (stays included).

    Attributes
    ----------
    pos : ndarray, shape (N,)
        Track coordinate of every node.
    node_move : list of RobotMove
        The "stay" move of every node (edge-local coordinates).
    src, dst : ndarray of int, shape (M,)
        Move ends (``src == dst`` for stays).
    loop : ndarray of bool, shape (M,)
        Whether the move runs on the loop.
    x0, dx : ndarray, shape (M,)
        Edge-local start and signed length.
    """

    pos: FloatArray
    src: NDArray[np.intp]
    dst: NDArray[np.intp]
    loop: NDArray[np.bool_]
    x0: FloatArray
    dx: FloatArray
    step_stick: float
    step_loop: float
    ns: int
    nc: int


def robot_graph(track: Track, h: float) -> RobotGraph:
    """Discretize a lollipop or circle with node spacing about ``h`` (m); see the module docstring."""
    rows: list[tuple[int, int, bool, float, float]] = []
    if isinstance(track, Lollipop):
        ell, c = track.stick, track.loop
        ns = max(1, math.ceil(ell / h - 1e-9))
        nc = max(4, math.ceil(c / h - 1e-9))
        hs, hc = ell / ns, c / nc
        pos = np.concatenate([np.arange(ns + 1) * hs, ell + np.arange(1, nc) * hc])
        pos[ns] = ell
        P = ns

        def loop_node(k: int) -> int:
            return P if k % nc == 0 else ns + k

        for i in range(ns + 1):
            rows.append((i, i, False, float(pos[i]), 0.0))
        for k in range(1, nc):
            rows.append((ns + k, ns + k, True, k * hc, 0.0))
        for i in range(ns):
            rows.append((i, i + 1, False, float(pos[i]), hs))
            rows.append((i + 1, i, False, float(pos[i + 1]), -hs))
        for k in range(nc):
            rows.append((loop_node(k), loop_node(k + 1), True, k * hc, hc))
            rows.append((loop_node(k + 1), loop_node(k), True, (k + 1) * hc if k + 1 < nc else 0.0, -hc))
        steps = (hs, hc, ns, nc)
    elif isinstance(track, Circle):
        c = track.loop
        nc = max(4, math.ceil(c / h - 1e-9))
        hc = c / nc
        pos = np.arange(nc) * hc
        for k in range(nc):
            rows.append((k, k, True, k * hc, 0.0))
            rows.append((k, (k + 1) % nc, True, k * hc, hc))
            rows.append(((k + 1) % nc, k, True, (k + 1) * hc, -hc))
        steps = (hc, hc, 0, nc)
    else:
        raise ValueError(f"the grid baseline supports lollipop and circle tracks, not {type(track).__name__}")
    arr = list(zip(*rows))
    return RobotGraph(
        pos=pos.astype(float),
        src=np.array(arr[0], dtype=np.intp),
        dst=np.array(arr[1], dtype=np.intp),
        loop=np.array(arr[2], dtype=bool),
        x0=np.array(arr[3], dtype=float),
        dx=np.array(arr[4], dtype=float),
        step_stick=steps[0],
        step_loop=steps[1],
        ns=int(steps[2]),
        nc=int(steps[3]),
    )


@dataclass(frozen=True)
class GridResult:
    """Outcome of one grid query: the joint path (or None), its L∞ cost (s) and A* statistics."""

    path: JointPath | None
    cost: float
    stats: dict[str, Any]


class GridPlanner:
    """A* over the product of two discretized track graphs with exact edge checks (see module docstring).

    Parameters
    ----------
    track : Track
    separation : float
        Separation every state and edge keeps (m).
    vmax : array_like, shape (2,)
        Speed limits (m/s) for the time-like cost.
    h : float
        Node spacing (m).
    """

    def __init__(self, track: Track, separation: float, vmax: ArrayLike, h: float) -> None:
        t0 = time.perf_counter()
        self.track = track
        self.separation = float(separation)
        v = np.broadcast_to(np.asarray(vmax, dtype=float), (2,))
        self.v = (float(v[0]), float(v[1]))
        self.h = float(h)
        g = robot_graph(track, h)
        self.graph = g
        n = len(g.pos)
        self.n = n
        m = len(g.src)
        ia = np.repeat(np.arange(m), m)
        ib = np.tile(np.arange(m), m)
        stay_a, stay_b = g.dx[ia] == 0.0, g.dx[ib] == 0.0
        keep = ~(stay_a & stay_b)
        node_ok = track.distance(g.pos[:, None], g.pos[None, :]) >= self.separation
        keep &= node_ok[g.src[ia], g.src[ib]] & node_ok[g.dst[ia], g.dst[ib]]
        ia, ib = ia[keep], ib[keep]
        dmin = single_edge_min_distance_vec(track, g.loop[ia], g.x0[ia], g.dx[ia], g.loop[ib], g.x0[ib], g.dx[ib])
        ok = dmin >= self.separation
        ia, ib = ia[ok], ib[ok]
        ta, tb = np.abs(g.dx[ia]) / self.v[0], np.abs(g.dx[ib]) / self.v[1]
        cost = np.maximum(ta, tb) + TIE_BREAK * (ta + tb)
        src = g.src[ia] * n + g.src[ib]
        dst = g.dst[ia] * n + g.dst[ib]
        order = np.argsort(src, kind="stable")
        src, dst, cost, ia, ib = src[order], dst[order], cost[order], ia[order], ib[order]
        ptr = np.searchsorted(src, np.arange(n * n + 1))
        self._ptr: list[int] = ptr.tolist()
        self._dst: list[int] = dst.tolist()
        self._cost: list[float] = cost.tolist()
        self._ma = ia
        self._mb = ib
        self.node_ok = node_ok
        self.edges = len(dst)
        self.build_time = time.perf_counter() - t0

    # --- helpers ---------------------------------------------------------------------------------
    def _move(self, k: int) -> RobotMove:
        g = self.graph
        return RobotMove("loop" if g.loop[k] else "stick", float(g.x0[k]), float(g.dx[k]))

    def _attach(self, p: float) -> list[tuple[int, RobotMove]]:
        """The two grid nodes around track coordinate ``p`` and the straight move from ``p`` to each."""
        tr = self.track
        g = self.graph
        if isinstance(tr, Lollipop) and p <= tr.stick:
            i = min(int(p / g.step_stick), g.ns - 1)
            return [(j, RobotMove("stick", p, float(g.pos[j]) - p)) for j in (i, i + 1)]
        ell = tr.stick if isinstance(tr, Lollipop) else 0.0
        th = p - ell
        k = min(int(th / g.step_loop), g.nc - 1)
        out = []
        for kk in (k, k + 1):
            if isinstance(tr, Lollipop):
                node = g.ns if kk % g.nc == 0 else g.ns + kk
            else:
                node = kk % g.nc
            out.append((node, RobotMove("loop", th, kk * g.step_loop - th)))
        return out

    # --- one query -------------------------------------------------------------------------------
    def solve(self, start: ArrayLike, goal: ArrayLike) -> GridResult:
        """A* from ``start`` to ``goal`` (track coordinates)."""
        start_p = np.asarray(start, dtype=float)
        goal_p = np.asarray(goal, dtype=float)
        track, sep, n = self.track, self.separation, self.n
        va, vb = self.v
        g = self.graph

        def leg_cost(ma: RobotMove, mb: RobotMove) -> float:
            ta, tb = abs(ma.delta) / va, abs(mb.delta) / vb
            return max(ta, tb) + TIE_BREAK * (ta + tb)

        S, G = n * n, n * n + 1
        start_edges = []
        for na, ma in self._attach(float(start_p[0])):
            for nb, mb in self._attach(float(start_p[1])):
                if self.node_ok[na, nb] and joint_move_min_distance(track, (ma,), (mb,)) >= sep:
                    start_edges.append((na * n + nb, leg_cost(ma, mb), (ma, mb)))
        goal_edges: dict[int, tuple[float, tuple[RobotMove, RobotMove]]] = {}
        for na, ma in self._attach(float(goal_p[0])):
            for nb, mb in self._attach(float(goal_p[1])):
                ra = RobotMove(ma.edge, ma.start + ma.delta, -ma.delta)
                rb = RobotMove(mb.edge, mb.start + mb.delta, -mb.delta)
                if self.node_ok[na, nb] and joint_move_min_distance(track, (ra,), (rb,)) >= sep:
                    goal_edges[na * n + nb] = (leg_cost(ra, rb), (ra, rb))
        ha = (track.distance(g.pos, goal_p[0]) / va).tolist()
        hb = (track.distance(g.pos, goal_p[1]) / vb).tolist()
        gcost = [math.inf] * (n * n + 2)
        parent = [-1] * (n * n + 2)
        pedge: list[Any] = [None] * (n * n + 2)
        closed = bytearray(n * n + 2)
        heap: list[tuple[float, float, int]] = []
        gcost[S] = 0.0
        for v, c, mv in start_edges:
            if c < gcost[v]:
                gcost[v], parent[v], pedge[v] = c, S, mv
                heapq.heappush(heap, (c + max(ha[v // n], hb[v % n]), c, v))
        ptr, dst, cost = self._ptr, self._dst, self._cost
        expanded = 0
        while heap:
            _f, gu, u = heapq.heappop(heap)
            if closed[u]:
                continue
            closed[u] = 1
            if u == G:
                break
            expanded += 1
            ge = goal_edges.get(u)
            if ge is not None and gu + ge[0] < gcost[G]:
                gcost[G], parent[G], pedge[G] = gu + ge[0], u, ge[1]
                heapq.heappush(heap, (gcost[G], gcost[G], G))
            for e in range(ptr[u], ptr[u + 1]):
                v = dst[e]
                nv = gu + cost[e]
                if nv < gcost[v]:
                    gcost[v], parent[v], pedge[v] = nv, u, e
                    heapq.heappush(heap, (nv + max(ha[v // n], hb[v % n]), nv, v))
        stats = {"expanded": expanded, "nodes": n * n, "edges": self.edges, "h": self.h}
        if not closed[G]:
            return GridResult(None, math.inf, stats)
        chain = [G]
        while chain[-1] != S:
            chain.append(parent[chain[-1]])
        chain.reverse()
        states = [start_p]
        legs = []
        for v in chain[1:]:
            e = pedge[v]
            if isinstance(e, tuple):
                ma, mb = e
            else:
                ma, mb = self._move(int(self._ma[e])), self._move(int(self._mb[e]))
            legs.append(((ma,), (mb,)))
            states.append(goal_p if v == G else np.array([g.pos[v // n], g.pos[v % n]]))
        stats["grid_steps"] = len(legs)
        return GridResult(JointPath(track, np.array(states), tuple(legs)), float(gcost[G]), stats)


def _collinear(nodes: FloatArray, tol: float = 1e-12) -> list[int]:
    """Indices of the nodes to keep when runs of nodes on one straight line going on are merged."""
    sel = [0]
    for k in range(1, len(nodes) - 1):
        u, w = nodes[k] - nodes[sel[-1]], nodes[k + 1] - nodes[k]
        if abs(u[0] * w[1] - u[1] * w[0]) <= tol * max(1.0, float(np.linalg.norm(u) * np.linalg.norm(w))):
            if float(u @ w) > 0:
                continue
        sel.append(k)
    sel.append(len(nodes) - 1)
    return sel


def shortcut_segment(track: Track, seg: RouteSegment, separation: float, exhaustive_limit: int = 400) -> RouteSegment:
    """Replace runs of a segment's nodes by exactly collision-free straight σ-chords.

    The grid's staircase is first reduced to its corners (collinear runs merged); then, greedily from the
    start, the farthest later corner reachable by a chord that keeps ``separation`` (checked exactly with
    :meth:`mpa.geometry.RouteGeometry.polyline_min_distance`). Above ``exhaustive_limit`` corners the
    farthest corner is searched by doubling and bisection instead (a heuristic: reachability is not monotone
    in the end index). Collinear results are merged again.
    """
    geom = route_geometry(track, seg.routes)
    base = _collinear(seg.nodes)
    p = seg.nodes[base]
    states0 = seg.states[base]
    m = len(p)

    def ok(i: int, j: int) -> bool:
        return j == i + 1 or geom.polyline_min_distance(p[[i, j]]) >= separation

    keep = [0]
    i = 0
    while i < m - 1:
        if m <= exhaustive_limit:
            nxt = next(j for j in range(m - 1, i, -1) if ok(i, j))
        else:
            lo, step, hi = i + 1, 1, m - 1
            if ok(i, hi):
                lo = hi
            while lo + step < hi:
                if ok(i, lo + step):
                    lo += step
                    step *= 2
                else:
                    hi = lo + step
                    break
            while hi - lo > 1:
                mid = (lo + hi) // 2
                if ok(i, mid):
                    lo = mid
                else:
                    hi = mid
            nxt = lo
        keep.append(nxt)
        i = nxt
    nodes = p[keep]
    sel = _collinear(nodes)
    return RouteSegment(seg.routes, nodes[sel], states0[keep][sel])
