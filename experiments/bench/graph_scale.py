"""Scaling of the complete graph planner to large layouts: seeded warehouse aisle grids and planar road maps.

- :func:`warehouse_layout`: parallel aisles 3–6 m apart, racks every 4–8 m along them, joined by cross aisles at
  both ends and at random racks, trimmed to the asked number of edges while keeping it connected.
- :func:`road_map_layout`: a random planar road map: seeded points in a square (about 60 m² per point, jittered
  lattice cells: at least 3.1 m apart), the Delaunay triangulation's edges, a random spanning tree of them plus
  the shortest other edges up to the asked number (planar: triangulation edges never cross).
- :func:`run_scale`: per layout, the free space built uncached (CPU and wall time, the first build including the
  vertex distances; peak memory by ``tracemalloc`` in a second build; polygons), the plan time with the free space
  cached (seeded queries, every fourth a swap: median, p95, max, CPU and wall; optionally each stopped after a
  budget) and the verified trajectory (plan, timing, gate: median) of the first queries.
- :func:`scale_markdown`: the table, with the growth exponent fitted (least squares in log–log) per column.
- :func:`trajectory_above_plan`: what the verified trajectory costs above its plan (timing, sampling, gate), per
  query: the plan and the trajectory from it timed apart on the same seeded queries (not swaps), after one
  unrecorded trajectory that loads the compiled kernels; medians CPU and wall, and a SHA-256 of every setpoint row
  (the same queries give the same hash on two checkouts when the setpoints are identical).
"""

from __future__ import annotations

import signal
import time
import tracemalloc
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from bench.graph_runner import _plan, make_graph_queries, spanning_then_extra
from mpa.errors import MPAError
from mpa.freespace import FreeSpace, free_space
from mpa.graph_track import GraphTrack

__all__ = [
    "KINDS",
    "above_plan_markdown",
    "road_map_layout",
    "run_scale",
    "scale_markdown",
    "trajectory_above_plan",
    "warehouse_layout",
]


def warehouse_layout(n_edges: int, seed: int) -> GraphTrack:
    """A seeded warehouse aisle grid of ``n_edges`` edges (lengths: straight distances, metres).

    Aisles run along y at x spacing 3–6 m, racks (vertices) every 4–8 m along them; cross aisles join the aisles
    at both ends and at a random third of the racks. The aisle segments form the spanning structure first, so
    the layout is connected; cross aisles then fill up to ``n_edges``.
    """
    rng = np.random.default_rng(seed)
    racks = 4 if n_edges < 40 else 8
    aisles = max(2, -(-(n_edges + racks) // (2 * racks - 1)))  # enough edges: aisles·(racks−1) + (aisles−1)·racks
    xs = np.concatenate([[0.0], np.cumsum(rng.uniform(3.0, 6.0, aisles - 1))])
    ys = np.concatenate([[0.0], np.cumsum(rng.uniform(4.0, 8.0, racks - 1))])
    idx = {(i, j): i * racks + j for i in range(aisles) for j in range(racks)}
    along = [(idx[i, j], idx[i, j + 1]) for i in range(aisles) for j in range(racks - 1)]
    ends = [(idx[i, j], idx[i + 1, j]) for i in range(aisles - 1) for j in (0, racks - 1)]
    middle = [(idx[i, j], idx[i + 1, j]) for i in range(aisles - 1) for j in range(1, racks - 1)]
    rng.shuffle(middle)
    # spanning: the aisles plus the cross aisles at one end; then the other end, then the middle ones
    edges = along + ends[0::2] + ends[1::2] + middle
    edges = edges[:n_edges]
    names = [f"a{i}_r{j}" for i in range(aisles) for j in range(racks)]
    verts = {names[idx[i, j]]: [float(xs[i]), float(ys[j])] for i in range(aisles) for j in range(racks)}
    used = {names[u] for u, _ in edges} | {names[v] for _, v in edges}
    return GraphTrack.from_layout(
        {"vertices": {k: v for k, v in verts.items() if k in used}, "edges": [[names[u], names[v]] for u, v in edges]}
    )


def _jittered_points(n: int, rng: np.random.Generator, spacing: float = 7.75) -> np.ndarray:
    """``n`` random points, one in each of the first ``n`` cells of a square lattice (``spacing`` m), moved by up to
    30 % of the spacing: random, yet never closer than 40 % of the spacing (3.1 m). Shape (n, 2)."""
    side = int(np.ceil(np.sqrt(n)))
    cells = rng.permutation(side * side)[:n]
    base = np.column_stack([cells % side, cells // side]).astype(float)
    return (base + rng.uniform(-0.3, 0.3, size=(n, 2))) * spacing


def road_map_layout(n_edges: int, seed: int) -> GraphTrack:
    """A seeded random planar road map of ``n_edges`` edges (Delaunay edges of random points; metres)."""
    from scipy.spatial import Delaunay

    rng = np.random.default_rng(seed)
    n_pts = max(4, round(n_edges / 1.6))  # a spanning tree plus ~60 % more edges
    while True:  # a small triangulation may have fewer edges than asked: add points
        pts = _jittered_points(n_pts, rng)
        tri = Delaunay(pts)
        cand_set: set[tuple[int, int]] = set()
        for s in tri.simplices:
            for u, v in ((s[0], s[1]), (s[1], s[2]), (s[0], s[2])):
                cand_set.add((int(min(u, v)), int(max(u, v))))
        if len(cand_set) >= n_edges:
            break
        n_pts += 1
    cand = sorted(cand_set)

    def length(e: tuple[int, int]) -> float:
        return float(np.hypot(*(pts[e[0]] - pts[e[1]])))

    edges = spanning_then_extra(n_pts, cand, n_edges, rng, extra_order=length)
    names = [f"p{i}" for i in range(n_pts)]
    verts = {names[i]: [float(pts[i, 0]), float(pts[i, 1])] for i in range(n_pts)}
    return GraphTrack.from_layout({"vertices": verts, "edges": [[names[u], names[v]] for u, v in edges]})


KINDS: dict[str, Callable[[int, int], GraphTrack]] = {"warehouse": warehouse_layout, "road map": road_map_layout}


class _OverBudget(Exception):
    """A plan that did not finish within the benchmark's budget."""


def _budgeted_plans(track: GraphTrack, qs: list[dict[str, Any]], budget: float | None) -> dict[str, Any]:
    """Plan time (wall and CPU, s) of the queries ``qs[1:]`` after one plan of ``qs[0]`` (the free space cached).

    With ``budget`` (s, wall) a plan still running then is stopped (``SIGALRM``) and counted in ``over_budget``,
    its time counted as the budget (so the p95 and max are lower bounds when any is over).
    """

    def alarm(signum: int, frame: Any) -> None:
        raise _OverBudget

    use = budget is not None and hasattr(signal, "setitimer")
    old = signal.signal(signal.SIGALRM, alarm) if use else None
    wall, cpu, solved, over = [], [], 0, 0
    try:
        for i, q in enumerate(qs):
            w0, c0 = time.perf_counter(), time.process_time()
            if use:
                signal.setitimer(signal.ITIMER_REAL, float(budget))  # type: ignore[arg-type]
            try:
                p = _plan(track, q, (1.0, 1.0))
                done = True
            except _OverBudget:
                p, done = None, False
            finally:
                if use:
                    signal.setitimer(signal.ITIMER_REAL, 0.0)
            if i == 0:
                continue  # the warm-up
            wall.append(time.perf_counter() - w0)
            cpu.append(time.process_time() - c0)
            solved += p is not None
            over += not done
    finally:
        if use:
            signal.signal(signal.SIGALRM, old)
    return {
        "plan_median": float(np.median(wall)),
        "plan_p95": float(np.percentile(wall, 95)),
        "plan_max": float(np.max(wall)),
        "plan_cpu_median": float(np.median(cpu)),
        "plan_cpu_p95": float(np.percentile(cpu, 95)),
        "plan_cpu_max": float(np.max(cpu)),
        "solved": solved,
        "over_budget": over,
        "queries": len(wall),
    }


def run_scale(
    sizes: Sequence[int] = (10, 30, 100, 300, 1000, 3000),
    kinds: Sequence[str] = tuple(KINDS),
    queries: int = 20,
    trajectories: int = 5,
    clearance: float = 1.0,
    seed: int = 0,
    progress: Callable[[str], None] | None = None,
    budget: float | None = None,
) -> list[dict[str, Any]]:
    """One record per (kind, size): build time (s, wall and CPU) and peak memory (bytes), plan times (s, wall and
    CPU; ``budget``: see :func:`_budgeted_plans`), the verified trajectory's median (s, wall)."""
    from trajopt.generator import TrajectoryGenerator
    from trajopt.timing import Limits

    out = []
    for kind in kinds:
        for n_e in sizes:
            track = KINDS[kind](n_e, seed * 100_003 + n_e)
            w0, c0 = time.perf_counter(), time.process_time()
            fs = FreeSpace(track, clearance)
            build, build_cpu, polygons = time.perf_counter() - w0, time.process_time() - c0, len(fs.polygon_ids)
            del fs
            tracemalloc.start()  # a second build for the memory (tracemalloc slows it down)
            FreeSpace(track, clearance)
            _, peak = tracemalloc.get_traced_memory()
            tracemalloc.stop()
            free_space(track, clearance)
            qs = make_graph_queries(track, queries + 1, seed, [clearance])
            plans = _budgeted_plans(track, qs, budget)
            gen = TrajectoryGenerator(track, clearance=clearance, limits=Limits(1.0, 1.0, 4.0), rate=100.0)
            ttimes = []
            for q in qs[1 : 1 + trajectories]:
                t0 = time.perf_counter()
                try:
                    gen.generate(q["start"], q["goal"])
                except MPAError:  # no motion: not timed
                    continue
                ttimes.append(time.perf_counter() - t0)
            out.append(
                {
                    "kind": kind,
                    "edges": track.n_edges,
                    "vertices": track.graph.n_vertices,
                    "build": build,
                    "build_cpu": build_cpu,
                    "memory": int(peak),
                    "polygons": polygons,
                    **plans,
                    "trajectory_median": float(np.median(ttimes)) if ttimes else float("nan"),
                }
            )
            if progress:
                progress(scale_markdown(out[-1:]).splitlines()[2])
    return out


def _exponent(records: list[dict[str, Any]], key: str) -> float:
    """Slope of log(key) against log(edges), least squares."""
    x = np.log([r["edges"] for r in records])
    y = np.log([max(r[key], 1e-12) for r in records])
    return float(np.polyfit(x, y, 1)[0]) if len(records) >= 2 else float("nan")


def scale_markdown(records: list[dict[str, Any]]) -> str:
    """The scaling table per kind (CPU / wall where both are measured), and a row of fitted growth exponents
    (∝ edges^k, on the CPU times)."""
    lines = [
        "| layout | edges | free-space build (s, CPU / wall) | peak memory (MB) | polygons | "
        "plan median (ms, CPU / wall) | plan p95 (ms, CPU / wall) | plan max (ms, CPU / wall) | "
        "verified trajectory median (ms, wall) | solved |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for kind in dict.fromkeys(r["kind"] for r in records):
        rs = [r for r in records if r["kind"] == kind]
        for r in rs:
            over = f" ({r['over_budget']} over the budget)" if r.get("over_budget") else ""
            lines.append(
                f"| {kind} | {r['edges']} | {r['build_cpu']:.3f} / {r['build']:.3f} | {r['memory'] / 1e6:.1f} | "
                f"{r['polygons']} | {r['plan_cpu_median'] * 1e3:.2f} / {r['plan_median'] * 1e3:.2f} | "
                f"{r['plan_cpu_p95'] * 1e3:.1f} / {r['plan_p95'] * 1e3:.1f} | "
                f"{r['plan_cpu_max'] * 1e3:.1f} / {r['plan_max'] * 1e3:.1f} | "
                f"{r['trajectory_median'] * 1e3:.1f} | {r['solved']}/{r['queries']}{over} |"
            )
        lines.append(
            f"| {kind}: exponent k (∝ edges^k) | | {_exponent(rs, 'build_cpu'):.2f} | {_exponent(rs, 'memory'):.2f} | "
            f"{_exponent(rs, 'polygons'):.2f} | {_exponent(rs, 'plan_cpu_median'):.2f} | "
            f"{_exponent(rs, 'plan_cpu_p95'):.2f} | {_exponent(rs, 'plan_cpu_max'):.2f} | "
            f"{_exponent(rs, 'trajectory_median'):.2f} | |"
        )
    return "\n".join(lines) + "\n"


def trajectory_above_plan(
    track: GraphTrack, clearance: float = 1.0, queries: int = 20, seed: int = 0, rate: float = 100.0
) -> dict[str, Any]:
    """The verified trajectory's cost above its plan on ``track``, per seeded query that is not a swap.

    Each query is planned (:meth:`TrajectoryGenerator.plan`, timed) and then made into verified setpoints
    (:meth:`TrajectoryGenerator.generate_from_plan`: timing, sampling, the gate; timed apart), limits 1 m/s,
    1 m/s², 4 m/s³ at ``rate`` Hz, the free space built first; one trajectory before them is not recorded (it
    loads numba's compiled kernels, about 0.3-0.6 s once per process).

    Returns
    -------
    dict
        ``edges``, ``queries`` (timed), ``rows_median``; ``plan_median``, ``plan_cpu_median`` and
        ``above_median``, ``above_cpu_median``, ``above_max``, ``above_cpu_max`` (s): the trajectory minus its plan;
        ``sha256``: of the rows ``t, s, v, a, j`` of every timed query in order.
    """
    import hashlib

    from trajopt.generator import TrajectoryGenerator
    from trajopt.timing import Limits

    free_space(track, clearance)
    gen = TrajectoryGenerator(track, clearance=clearance, limits=Limits(1.0, 1.0, 4.0), rate=rate)
    rows: list[tuple[float, float, float, float, int]] = []
    digest = hashlib.sha256()
    warm = False
    for q in make_graph_queries(track, 4 * queries + 2, seed, [clearance]):
        if len(rows) >= queries:
            break
        if q["swap"]:
            continue
        try:
            w0, c0 = time.perf_counter(), time.process_time()
            plan = gen.plan(q["start"], q["goal"])
            w1, c1 = time.perf_counter(), time.process_time()
            traj = gen.generate_from_plan(plan)
            w2, c2 = time.perf_counter(), time.process_time()
        except MPAError:  # no motion: not timed
            continue
        if not warm:  # the kernels' first load, once per process
            warm = True
            continue
        for arr in (traj.t, traj.s, traj.v, traj.a, traj.j):
            digest.update(np.ascontiguousarray(arr).tobytes())
        rows.append((w1 - w0, c1 - c0, w2 - w1, c2 - c1, len(traj.t)))
    r = np.array(rows, dtype=float).reshape(-1, 5)
    med = np.median(r, axis=0) if len(r) else np.full(5, np.nan)
    top = np.max(r, axis=0) if len(r) else np.full(5, np.nan)
    return {
        "edges": track.n_edges,
        "queries": len(r),
        "rows_median": float(med[4]),
        "plan_median": float(med[0]),
        "plan_cpu_median": float(med[1]),
        "above_median": float(med[2]),
        "above_cpu_median": float(med[3]),
        "above_max": float(top[2]),
        "above_cpu_max": float(top[3]),
        "sha256": digest.hexdigest(),
    }


def above_plan_markdown(records: list[dict[str, Any]]) -> str:
    """The table of :func:`trajectory_above_plan` records (each with its ``kind``)."""
    lines = [
        "| layout | edges | queries | rows (median) | plan median (ms, CPU / wall) | "
        "trajectory minus plan, median (ms, CPU / wall) | max (ms, CPU / wall) | setpoints SHA-256 |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in records:
        lines.append(
            f"| {r['kind']} | {r['edges']} | {r['queries']} | {r['rows_median']:.0f} | "
            f"{r['plan_cpu_median'] * 1e3:.2f} / {r['plan_median'] * 1e3:.2f} | "
            f"{r['above_cpu_median'] * 1e3:.2f} / {r['above_median'] * 1e3:.2f} | "
            f"{r['above_cpu_max'] * 1e3:.1f} / {r['above_max'] * 1e3:.1f} | {r['sha256'][:16]} |"
        )
    return "\n".join(lines) + "\n"
