"""One benchmark query, all methods, inside a worker: :func:`run_query`.

A worker builds its expensive objects once per configuration (:func:`context`: the ``trajopt`` generators with
their NLPs, the OMPL planners, the grid graph with its exact edge checks) and warms them up on a fixed query, so
no first-call costs (imports, NLP builds) land in the measured times. Every method call is timed inside the
worker with :func:`time.perf_counter` around the whole pipeline from the query to verified setpoints (planning,
smoothing, time parametrization, sampling at the rate, verification gate); metrics such as the stability twin
and the homotopy class of the result are computed outside the timed region.

Methods (:data:`METHODS`):

- ``ours``: ``trajopt.TrajectoryGenerator`` (plan → fast path: one ruckig profile on the straight route-coordinate
  line, or hard path: corridor QP in the plan's class, B-spline, filtered jerk-limited timing → the gate).
- ``raw_plan``: the paper's plan as is, every straight step rest to rest (``optimize=False``; the fallback).
- ``ompl_rest``: OMPL RRTConnect + shortcuts in track coordinates (SO(2)² on the circle), executed rest to rest
  at its waypoints. ``ompl_bspline``: the same path after ``smoothBSpline``, re-verified and timed like ours.
- ``ompl_geo``: lollipop only; RRTConnect whose motions take every robot along a shortest path of the track
  (so the robots can change order through the loop's seam), rest to rest at its waypoints.
- ``grid``: A* on the product of the discretized track graphs, shortcut, timed like ours.
"""

from __future__ import annotations

import json
import math
import threading
import time
from dataclasses import asdict, dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from bench.baselines import GridPlanner, OmplPlanner, OmplResult, shortcut_segment
from bench.geometry import JointPath, joint_move_min_distance, leg_moves_geodesic, split_routes
from bench.motion import Motion, TimingOutcome, time_segments
from mpa import defaults
from mpa.errors import MPAError
from mpa.tracks import Circle, Lollipop, Track, make_track
from trajopt import Limits, TrajectoryGenerator
from trajopt.generator import separation_margin
from trajopt.timing import min_time_rest_to_rest

__all__ = ["METHODS", "BenchConfig", "MethodOutcome", "context", "make_queries", "run_query", "twin_distance"]

FloatArray = NDArray[np.float64]
#: Every method, in table order.
METHODS = ("ours", "raw_plan", "ompl_rest", "ompl_bspline", "ompl_geo", "grid")
#: Methods that only exist on the lollipop.
LOLLIPOP_ONLY = ("ompl_geo",)


@dataclass(frozen=True)
class BenchConfig:
    """Everything a worker needs to reproduce a run (JSON-serializable).

    Attributes
    ----------
    track : {"lollipop", "circle"}
    stick, loop : float or None
        Track lengths (m); None = the paper's 1.
    clearance : float
        Required separation D (m).
    vmax, amax, jmax : float
        Per-robot limits.
    rate : float
        Setpoint rate (Hz).
    ompl_time : float
        RRTConnect time budget per query (s).
    grid : float
        Grid node spacing (m).
    methods : tuple of str
    seed : int
    delta : float
        Perturbation of the stability twin (m, per coordinate).
    threshold : float
        Twins farther apart than this (m) count as a discontinuity.
    query_margin : float
        Queries keep ``d ≥ D + query_margin`` at start and goal (m).
    twins : bool
        Run the perturbed twins (stability); the scaling sweep switches them off.
    """

    track: str = "lollipop"
    stick: float | None = None
    loop: float | None = None
    clearance: float = defaults.CLEARANCE
    vmax: float = defaults.VMAX
    amax: float = defaults.AMAX
    jmax: float = defaults.JMAX
    rate: float = defaults.RATE
    ompl_time: float = 1.0
    grid: float = 0.01
    methods: tuple[str, ...] = METHODS
    seed: int = 0
    delta: float = 1e-4
    threshold: float = 0.05
    query_margin: float = 0.01
    twins: bool = True

    def make_track(self) -> Track:
        """The track (paper defaults ℓ = c = 1)."""
        return make_track(self.track, self.stick, self.loop)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready."""
        d = asdict(self)
        d["methods"] = list(self.methods)
        return d

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> BenchConfig:
        """Inverse of :meth:`to_dict`."""
        return cls(**{**d, "methods": tuple(d["methods"])})

    def key(self) -> str:
        """Cache key of the worker context (everything but the seed and the twin settings)."""
        d = self.to_dict()
        for k in ("seed", "delta", "threshold", "query_margin", "twins"):
            d.pop(k)
        return json.dumps(d, sort_keys=True)

    def active_methods(self) -> tuple[str, ...]:
        """The requested methods that apply to this track."""
        return tuple(m for m in self.methods if self.track == "lollipop" or m not in LOLLIPOP_ONLY)


# ---------------------------------------------------------------------------------------------------
def make_queries(config: BenchConfig, n: int) -> list[dict[str, Any]]:
    """``n`` seeded random queries with their perturbed twins (start and goal moved by ±δ along the track).

    Start and goal keep ``d ≥ D + query_margin``; each coordinate of the twin moves by ``δ`` in a random
    direction (through P or round the loop's seam where it lies there).
    """
    track = config.make_track()
    rng = np.random.default_rng(config.seed)
    need = config.clearance + config.query_margin
    L = track.total_length
    out: list[dict[str, Any]] = []
    while len(out) < n:
        s, g = rng.uniform(0.0, L, 2), rng.uniform(0.0, L, 2)
        if track.distance(s[0], s[1]) < need or track.distance(g[0], g[1]) < need:
            continue
        signs = rng.choice([-1.0, 1.0], size=4)
        twin = [_nudge(track, float(x), config.delta * sg) for x, sg in zip([*s, *g], signs)]
        qid = len(out)
        out.append(
            {
                "query": qid,
                "start": s.tolist(),
                "goal": g.tolist(),
                "twin_start": twin[:2],
                "twin_goal": twin[2:],
                "ompl_seed": 1 + (config.seed * 1_000_003 + qid) % 2_000_000_000,
            }
        )
    return out


def _nudge(track: Track, p: float, d: float) -> float:
    L = track.total_length
    q = p + d
    if isinstance(track, Circle):
        return q % L
    if q >= L:  # round the seam of the loop
        return q - track.loop  # type: ignore[attr-defined]
    if q < 0.0:
        return p - d
    return q


def lower_bound(track: Track, start: FloatArray, goal: FloatArray, limits: Limits) -> float:
    """Max over the robots of the jerk-limited rest-to-rest time along its own shortest route (s)."""
    return max(
        min_time_rest_to_rest(float(track.distance(start[r], goal[r])), limits.v[r], limits.a[r], limits.j[r])
        for r in (0, 1)
    )


def twin_distance(track: Track, m1: Motion, m2: Motion, n: int = 401) -> float:
    """Sup over normalised time ``t/makespan`` of the larger robot's graph distance between two motions (m)."""
    a, b = m1.normalized(n), m2.normalized(n)
    return float(max(np.max(track.distance(a[:, 0], b[:, 0])), np.max(track.distance(a[:, 1], b[:, 1]))))


# ---------------------------------------------------------------------------------------------------
@dataclass
class MethodOutcome:
    """One method on one query (the motion is kept only inside the worker)."""

    success: bool
    verified: bool
    compute_time: float
    makespan: float = math.nan
    min_separation: float = math.nan
    word: tuple[str, ...] = ()
    rests: int = 0
    error: str = ""
    motion: Motion | None = None
    stats: dict[str, Any] = field(default_factory=dict)


@dataclass
class Context:
    """The per-worker objects of one configuration."""

    config: BenchConfig
    track: Track
    limits: Limits
    separation: float
    ours: TrajectoryGenerator
    raw: TrajectoryGenerator
    ompl: OmplPlanner | None = None
    ompl_geo: OmplPlanner | None = None
    grid: GridPlanner | None = None
    build_times: dict[str, float] = field(default_factory=dict)


_CONTEXTS: dict[str, Context] = {}
_LOCK = threading.Lock()
#: One query at a time per process (threads of a Dask worker would share the GIL and OMPL's global seeding).
_RUN_LOCK = threading.Lock()


def context(config: BenchConfig) -> Context:
    """The worker's context for ``config``, built (and warmed up) on first use."""
    key = config.key()
    with _LOCK:
        ctx = _CONTEXTS.get(key)
        if ctx is None:
            ctx = _build_context(config)
            _CONTEXTS[key] = ctx
        return ctx


def _build_context(config: BenchConfig) -> Context:
    t0 = time.perf_counter()
    track = config.make_track()
    limits = Limits(config.vmax, config.amax, config.jmax)
    sep = config.clearance + separation_margin(limits, config.rate)
    ours = TrajectoryGenerator(track, clearance=config.clearance, limits=limits, rate=config.rate)
    raw = TrajectoryGenerator(track, clearance=config.clearance, limits=limits, rate=config.rate, optimize=False)
    ctx = Context(config, track, limits, sep, ours, raw)
    methods = config.active_methods()
    if "ompl_rest" in methods or "ompl_bspline" in methods:
        ctx.ompl = OmplPlanner(track, sep, config.ompl_time)
    if "ompl_geo" in methods:
        ctx.ompl_geo = OmplPlanner(track, sep, config.ompl_time, geodesic=True)
    t1 = time.perf_counter()
    if "grid" in methods:
        ctx.grid = GridPlanner(track, sep, limits.v, config.grid)
    ctx.build_times = {"setup": t1 - t0, "grid_build": time.perf_counter() - t1}
    # warm up every method on a fixed query (imports, NLP size classes, first-call costs)
    warm = _warm_query(track, config.clearance + config.query_margin)
    for m in methods:
        _run_method(ctx, m, warm[0], warm[1], seed=1)
    ctx.build_times["warmup"] = time.perf_counter() - t1
    return ctx


def _warm_query(track: Track, need: float) -> tuple[FloatArray, FloatArray]:
    if isinstance(track, Lollipop):
        ell, c = track.stick, track.loop
        return np.array([0.5 * ell, ell + 0.5 * c]), np.array([ell + 0.5 * c, 0.5 * ell])
    c = track.loop  # type: ignore[attr-defined]
    return np.array([0.1 * c, 0.6 * c]), np.array([0.6 * c, 0.1 * c])


# ---------------------------------------------------------------------------------------------------
def _trajopt_outcome(gen: TrajectoryGenerator, start: FloatArray, goal: FloatArray, raw: bool) -> MethodOutcome:
    t0 = time.perf_counter()
    try:
        traj = gen.generate(start, goal)
    except MPAError as exc:
        return MethodOutcome(False, False, time.perf_counter() - t0, error=f"{type(exc).__name__}: {exc}")
    dt = time.perf_counter() - t0
    st = traj.solver_stats
    if raw:
        rests = max(0, int(st.get("fallback_pieces", 1)) - 1)
    else:
        radii = np.asarray(st.get("blend_radii", [0.0, 0.0]), dtype=float)
        rests = int(np.sum(radii[1:-1] <= 0.0))
    stats = {
        "fallback": traj.fallback,
        "corridor_segments": int(st.get("n_segments", 0)),
        "corridor_iterations": int(st.get("corridor_iterations", 0)),
        "qp_time": float(st.get("qp_time", 0.0)),
        "timings": {k: float(v) for k, v in traj.timings.items()},
        "domain": traj.domain,
        "path": str(st.get("path", "")),
    }
    return MethodOutcome(
        True,
        bool(traj.verification["ok"]),
        dt,
        float(traj.motion_time),
        float(traj.min_separation),
        tuple(traj.word),
        rests,
        traj.fallback_reason,
        Motion.from_trajectory(traj),
        stats,
    )


def _timed_outcome(out: TimingOutcome, compute: float, stats: dict[str, Any]) -> MethodOutcome:
    return MethodOutcome(
        True,
        out.verified,
        compute,
        out.motion.duration,
        out.min_separation,
        out.word,
        out.rests,
        "; ".join(out.failures[:3]),
        out.motion,
        {**stats, **out.stats},
    )


def _time_path(
    ctx: Context, path: JointPath, mode: str, start: FloatArray, goal: FloatArray, shortcut: bool = False
) -> TimingOutcome:
    segs = split_routes(path)
    if shortcut:
        segs = [shortcut_segment(ctx.track, s, ctx.separation) for s in segs]
    return time_segments(
        ctx.track,
        segs,
        mode=mode,
        limits=ctx.limits,
        clearance=ctx.config.clearance,
        separation=ctx.separation,
        rate=ctx.config.rate,
        start=start,
        goal=goal,
    )


def _ompl_outcomes(
    ctx: Context, planner: OmplPlanner, start: FloatArray, goal: FloatArray, seed: int, want: tuple[str, ...]
) -> dict[str, MethodOutcome]:
    """OMPL's shared planning, then the rest-to-rest and the B-spline variants (compute time: shared + own)."""
    t0 = time.perf_counter()
    res: OmplResult = planner.solve(start, goal, seed)
    shared = time.perf_counter() - t0 - res.times["bspline"]
    stats = {"ompl": {k: v for k, v in res.stats.items()}, "ompl_times": res.times}
    out: dict[str, MethodOutcome] = {}
    if not res.solved or res.simplified is None:
        for m in want:
            err = f"no exact solution in {planner.budget:g} s"
            out[m] = MethodOutcome(False, False, shared, error=err, stats=stats)
        return out
    for m in want:
        t1 = time.perf_counter()
        if m == "ompl_bspline":
            assert res.bspline is not None
            path = res.bspline
            if path.min_distance() < ctx.separation:  # re-verify the smoothed path exactly
                out[m] = MethodOutcome(False, False, shared + res.times["bspline"], error="B-spline path collides")
                continue
            timed = _time_path(ctx, path, "smooth", start, goal)
            out[m] = _timed_outcome(timed, shared + res.times["bspline"] + time.perf_counter() - t1, stats)
        else:
            timed = _time_path(ctx, res.simplified, "rest", start, goal)
            out[m] = _timed_outcome(timed, shared + time.perf_counter() - t1, stats)
    return out


def _run_method(ctx: Context, method: str, start: FloatArray, goal: FloatArray, seed: int) -> dict[str, MethodOutcome]:
    """Run one method (or the OMPL pair) and return its outcome(s) by method name."""
    if method == "ours":
        return {method: _trajopt_outcome(ctx.ours, start, goal, raw=False)}
    if method == "raw_plan":
        return {method: _trajopt_outcome(ctx.raw, start, goal, raw=True)}
    if method in ("ompl_rest", "ompl_bspline"):
        assert ctx.ompl is not None
        return _ompl_outcomes(ctx, ctx.ompl, start, goal, seed, (method,))
    if method == "ompl_geo":
        assert ctx.ompl_geo is not None
        return {method: _ompl_outcomes(ctx, ctx.ompl_geo, start, goal, seed, ("ompl_rest",))["ompl_rest"]}
    if method == "grid":
        assert ctx.grid is not None
        t0 = time.perf_counter()
        res = ctx.grid.solve(start, goal)
        if res.path is None:
            fail = MethodOutcome(False, False, time.perf_counter() - t0, error="no grid path", stats=res.stats)
            return {method: fail}
        try:
            timed = _time_path(ctx, res.path, "smooth", start, goal, shortcut=True)
        except MPAError as exc:  # e.g. a grid path that leaves its route at P in a way split_routes cannot cut
            err = f"grid path not timed: {type(exc).__name__}: {exc}"
            return {method: MethodOutcome(False, False, time.perf_counter() - t0, error=err, stats=res.stats)}
        return {method: _timed_outcome(timed, time.perf_counter() - t0, {"grid": res.stats, "grid_cost": res.cost})}
    raise ValueError(f"method is {method!r}, expected one of {METHODS}")


def _solve_all(ctx: Context, start: FloatArray, goal: FloatArray, seed: int) -> dict[str, MethodOutcome]:
    methods = ctx.config.active_methods()
    out: dict[str, MethodOutcome] = {}
    if "ompl_rest" in methods and "ompl_bspline" in methods:
        assert ctx.ompl is not None
        out.update(_ompl_outcomes(ctx, ctx.ompl, start, goal, seed, ("ompl_rest", "ompl_bspline")))
    for m in methods:
        if m not in out:
            out.update(_run_method(ctx, m, start, goal, seed))
    return out


def run_query(config_dict: dict[str, Any], query: dict[str, Any]) -> list[dict[str, Any]]:
    """All methods on one query and its perturbed twin; one JSON-ready record per method.

    Parameters
    ----------
    config_dict : dict
        :meth:`BenchConfig.to_dict`.
    query : dict
        One entry of :func:`make_queries`.

    Returns
    -------
    list of dict
        Records with ``method``, ``query``, ``track``, ``domain``, ``success``, ``verified``, ``compute_time``,
        ``makespan``, ``lower_bound``, ``makespan_ratio``, ``min_separation``, ``word``, ``discontinuity``, …
    """
    with _RUN_LOCK:
        return _run_query(BenchConfig.from_dict(config_dict), query)


def _run_query(config: BenchConfig, query: dict[str, Any]) -> list[dict[str, Any]]:
    ctx = context(config)
    track = ctx.track
    start, goal = np.asarray(query["start"], dtype=float), np.asarray(query["goal"], dtype=float)
    seed = int(query["ompl_seed"])
    main = _solve_all(ctx, start, goal, seed)
    twin: dict[str, MethodOutcome] = {}
    reseeded: dict[str, MethodOutcome] = {}
    if config.twins:
        ts, tg = np.asarray(query["twin_start"], dtype=float), np.asarray(query["twin_goal"], dtype=float)
        twin = _solve_all(ctx, ts, tg, seed)
        reseed = replace(config, methods=tuple(m for m in config.active_methods() if m.startswith("ompl")))
        if reseed.methods:
            reseeded = _solve_all(replace_ctx(ctx, reseed), ts, tg, seed + 7919)
    domain = main["ours"].stats.get("domain") if "ours" in main else None
    if domain is None:
        try:
            domain = ctx.ours.plan(start, goal).domain
        except MPAError:
            domain = None
    lb = lower_bound(track, start, goal, ctx.limits)
    order_change = bool(np.sign(goal[1] - goal[0]) != np.sign(start[1] - start[0]))
    interacting = _interacting(track, start, goal, config.clearance)
    records = []
    for m in config.active_methods():
        o = main[m]
        rec: dict[str, Any] = {
            "method": m,
            "query": int(query["query"]),
            "track": config.track,
            "track_params": track.to_dict(),
            "start": start.tolist(),
            "goal": goal.tolist(),
            "domain": domain,
            "order_change": order_change,
            "interacting": interacting,
            "success": o.success,
            "verified": o.verified,
            "compute_time": o.compute_time,
            "makespan": o.makespan if o.success else None,
            "lower_bound": lb,
            "makespan_ratio": (o.makespan / lb) if (o.success and lb > 0) else None,
            "min_separation": o.min_separation if o.success else None,
            "word": " ".join(o.word) if o.success else None,
            "rests": o.rests if o.success else None,
            "error": o.error,
            "stats": _jsonable(o.stats),
        }
        rec.update(_stability(track, o, twin.get(m), config, ""))
        if m in reseeded:
            rec.update(_stability(track, o, reseeded.get(m), config, "_reseeded"))
        records.append(rec)
    return records


def _interacting(track: Track, start: FloatArray, goal: FloatArray, clearance: float) -> bool:
    """Whether the naive motion collides: each robot along its own shortest path, both at proportional speed."""
    ma = leg_moves_geodesic(track, float(start[0]), float(goal[0]))
    mb = leg_moves_geodesic(track, float(start[1]), float(goal[1]))
    return joint_move_min_distance(track, ma, mb) < clearance


def replace_ctx(ctx: Context, config: BenchConfig) -> Context:
    """The same worker objects with another method list (for the reseeded OMPL twins)."""
    return Context(
        config,
        ctx.track,
        ctx.limits,
        ctx.separation,
        ctx.ours,
        ctx.raw,
        ctx.ompl,
        ctx.ompl_geo,
        ctx.grid,
        ctx.build_times,
    )


def _stability(
    track: Track, o: MethodOutcome, t: MethodOutcome | None, config: BenchConfig, suffix: str
) -> dict[str, Any]:
    """``discontinuity{suffix}`` (sup distance to the twin, m), ``discontinuous{suffix}`` (> threshold) and
    ``twin_success{suffix}``; None where the twin was not run or one of the two failed."""
    if t is None:
        return {f"discontinuity{suffix}": None, f"discontinuous{suffix}": None, f"twin_success{suffix}": None}
    ok = o.success and t.success and o.motion is not None and t.motion is not None
    dist = twin_distance(track, o.motion, t.motion) if ok else None  # type: ignore[arg-type]
    return {
        f"discontinuity{suffix}": dist,
        f"discontinuous{suffix}": (dist > config.threshold) if dist is not None else None,
        f"twin_success{suffix}": t.success,
    }


def _jsonable(x: Any) -> Any:
    if isinstance(x, dict):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, (np.generic,)):
        return x.item()
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x
