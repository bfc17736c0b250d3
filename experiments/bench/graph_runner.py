"""The graph-layout benchmark at the plan level: ours (``mpa.plan``, graph planner) against the grid and OMPL.

Parts (each a function returning records and a markdown table; :func:`run_graph_benchmark` runs them all):

- :func:`run_layouts`: seeded random queries per layout (a quarter of them swaps, clearances from four fractions
  of the median edge length), in one process, methods interleaved (their order rotates per query), warm (one
  unrecorded query per method, grid and free space built before timing). Per method: solved share of the feasible
  queries, compute time (median, p95), makespan at the speed limits, ratio to the grid per query, exactness (ours'
  exact minimum distance >= D), discontinuity rate of δ-twins; and the completeness check (grid solved, ours not).
- :func:`run_y_oracle`: seeded random Y junctions; two robots at the ends of the two longer branches can swap iff
  ``D <= b`` (``b`` the shortest branch): ours and the grid at ``D = b``, ``b (1 - 1e-6)`` and ``b (1 + 1e-6)``.
- :func:`run_completeness`: seeded random small multigraphs (loops, parallel edges): grid solved, ours not?
- :func:`run_price`: paper lollipops; the graph planner's ``fastest`` makespan against the paper plan's executed
  at the same speed limits (random queries and swaps separately).
- :func:`run_scaling`: free-space build and plan time on seeded grid-like building layouts of 10 to 150 edges.

Ours is also run through ``trajopt`` (:func:`bench.graph_baselines.ours_trajectory`): verified setpoints, timed.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

import mpa
from bench.graph_baselines import GraphGrid, GraphOmpl, GraphPath, leg_min_distance, ours_trajectory
from mpa.errors import NoMotionError
from mpa.freespace import FreeSpace, free_space
from mpa.graph_track import GraphTrack
from mpa.planners.graph import GraphPlan, _word

__all__ = [
    "LAYOUTS",
    "grid_layout",
    "load_layout",
    "run_completeness",
    "run_layouts",
    "run_price",
    "run_scaling",
    "run_y_oracle",
    "spanning_then_extra",
]

ROOT = Path(__file__).resolve().parents[2]
#: Example layouts known by name (``examples/tracks/NAME.json``).
LAYOUTS = ("y_junction", "passing_loop", "two_sidings", "theta", "figure_eight", "warehouse")
#: Clearances per layout, as fractions of its median edge length.
CLEARANCE_FRACTIONS = (0.05, 0.2, 0.5, 1.0)
#: Grid nodes per robot the automatic grid step aims at (step = total length / this).
GRID_NODES = 300
Pos = tuple[int, float]


def load_layout(name: str) -> tuple[str, GraphTrack]:
    """A layout by name (``examples/tracks/NAME.json``) or path: ``(label, track)``."""
    p = Path(name)
    if not p.suffix:
        p = ROOT / "examples" / "tracks" / f"{name}.json"
    return p.stem, GraphTrack.from_json(p)


def _pct(x: Sequence[float], q: float) -> float:
    a = np.asarray([v for v in x if v is not None and math.isfinite(v)], dtype=float)
    return float(np.percentile(a, q)) if len(a) else math.nan


def _sample_pos(track: GraphTrack, rng: np.random.Generator) -> Pos:
    L = track.lengths
    e = int(rng.choice(len(L), p=L / L.sum()))
    return e, float(rng.uniform(0.0, L[e]))


def make_graph_queries(track: GraphTrack, n: int, seed: int, clearances: Sequence[float]) -> list[dict[str, Any]]:
    """``n`` seeded queries with both ends valid (robots >= D apart); every fourth a swap (goal = reversed start)."""
    rng = np.random.default_rng(seed)
    g = track.geometry
    out = []
    for q in range(n):
        D = float(clearances[(q + q // 4) % len(clearances)])  # swaps (q % 4 == 0) get every clearance too
        swap = q % 4 == 0
        need = D + 1e-9 * max(1.0, track.total_length)
        for _ in range(10_000):
            a, b = _sample_pos(track, rng), _sample_pos(track, rng)
            if g.distance_scalar(*a, *b) < need:
                continue
            if swap:
                c, d = b, a
            else:
                c, d = _sample_pos(track, rng), _sample_pos(track, rng)
                if g.distance_scalar(*c, *d) < need:
                    continue
            break
        else:
            continue
        out.append(
            {"id": q, "clearance": D, "swap": swap, "start": (a, b), "goal": (c, d), "seed": 1 + seed * 7919 + q}
        )
    return out


def twin_query(track: GraphTrack, query: dict[str, Any], delta: float, rng: np.random.Generator) -> dict[str, Any]:
    """The query with every position moved by ``delta`` along its edge (inwards at an edge end)."""
    L = track.lengths

    def nudge(p: Pos) -> Pos:
        e, s = p
        sign = 1.0 if rng.random() < 0.5 else -1.0
        t = s + sign * delta
        if t < 0.0 or t > L[e]:
            t = s - sign * delta
        return e, float(min(max(t, 0.0), L[e]))

    return {**query, "start": tuple(nudge(p) for p in query["start"]), "goal": tuple(nudge(p) for p in query["goal"])}


# ---------------------------------------------------------------------------------------------- comparisons
def _ours_positions(plan: GraphPlan, u: np.ndarray) -> tuple[Any, Any, Any, Any]:
    (ea, sa), (eb, sb) = plan.positions(u)
    return ea, sa, eb, sb


def _gap(track: GraphTrack, p1: tuple[Any, ...], p2: tuple[Any, ...]) -> float:
    """Sup over the samples of the larger of the two robots' graph distances between two paths (metres)."""
    g = track.geometry
    da = g.distance(p1[0], p1[1], p2[0], p2[1])
    db = g.distance(p1[2], p1[3], p2[2], p2[3])
    return float(np.max(np.maximum(da, db)))


def _sampled_word(track: GraphTrack, pos: tuple[Any, ...]) -> tuple[str, ...]:
    ea, sa, eb, sb = pos
    cells = [(int(a), int(b), 0 if a != b or x > y else 1) for a, x, b, y in zip(ea, sa, eb, sb)]
    return _word(track, cells)


def _plan(track: GraphTrack, q: dict[str, Any], speeds: tuple[float, float]) -> GraphPlan | None:
    try:
        p = mpa.plan(track, q["start"], q["goal"], q["clearance"], planner="graph", objective="fastest", speeds=speeds)
        return p  # type: ignore[return-value]
    except NoMotionError:
        return None


# ------------------------------------------------------------------------------------------------- layouts
def run_layouts(
    layouts: Sequence[str],
    n: int,
    *,
    seed: int = 0,
    ompl_budget: float = 1.0,
    delta: float = 1e-6,
    threshold: float = 0.01,
    speeds: tuple[float, float] = (1.0, 1.0),
    grid_nodes: int = GRID_NODES,
    samples: int = 401,
    progress: Callable[[str], None] | None = None,
) -> list[dict[str, Any]]:
    """Per layout and query: one record per method (``ours``, ``grid``, ``ompl``); see the module docstring."""
    records: list[dict[str, Any]] = []
    u = np.linspace(0.0, 1.0, samples)
    for li, name in enumerate(layouts):
        label, track = load_layout(name)
        med = float(np.median(track.lengths))
        Ds = [round(f * med, 6) for f in CLEARANCE_FRACTIONS]
        h = track.total_length / grid_nodes
        queries = make_graph_queries(track, n, seed * 1000 + li, Ds)
        rng = np.random.default_rng(seed * 1000 + li + 500)
        grids, ompls, fs_build = {}, {}, {}
        for D in Ds:
            t0 = time.perf_counter()
            FreeSpace(track, D)
            fs_build[D] = time.perf_counter() - t0
            free_space(track, D)  # warm the cache the planner uses
            grids[D] = GraphGrid(track, D, h, speeds)
            ompls[D] = GraphOmpl(track, D, ompl_budget, speeds)
        # warm-up: one unrecorded query per method
        if queries:
            q = queries[0]
            _plan(track, q, speeds)
            grids[q["clearance"]].solve(q["start"], q["goal"])
            ompls[q["clearance"]].solve(q["start"], q["goal"], q["seed"])
        for qi, q in enumerate(queries):
            D = q["clearance"]
            twin = twin_query(track, q, delta, rng)
            g = track.geometry
            twin_ok = all(g.distance_scalar(*twin[k][0], *twin[k][1]) >= D for k in ("start", "goal"))
            order = ["ours", "grid", "ompl"]
            order = order[qi % 3 :] + order[: qi % 3]
            res: dict[str, dict[str, Any]] = {}
            for m in order:
                t0 = time.perf_counter()
                if m == "ours":
                    p = _plan(track, q, speeds)
                    dt = time.perf_counter() - t0
                    res[m] = {"solved": p is not None, "compute_time": dt, "obj": p}
                elif m == "grid":
                    r = grids[D].solve(q["start"], q["goal"])
                    res[m] = {"solved": r.solved, "compute_time": r.compute_time, "obj": r.path}
                else:
                    r2 = ompls[D].solve(q["start"], q["goal"], q["seed"])
                    res[m] = {"solved": r2.solved, "compute_time": r2.compute_time, "obj": r2.path}
            grid_ms = res["grid"]["obj"].makespan if res["grid"]["solved"] else math.nan
            feasible = res["ours"]["solved"]
            for m in ("ours", "grid", "ompl"):
                obj = res[m]["obj"]
                rec: dict[str, Any] = {
                    "layout": label,
                    "method": m,
                    "query": q["id"],
                    "clearance": D,
                    "swap": q["swap"],
                    "feasible": feasible,
                    "solved": res[m]["solved"],
                    "compute_time": res[m]["compute_time"],
                    "makespan": math.nan,
                    "ratio_to_grid": math.nan,
                    "min_distance": math.nan,
                    "start": [list(x) for x in q["start"]],
                    "goal": [list(x) for x in q["goal"]],
                    "word_changed": None,
                    "twin_gap": None,
                    "discontinuous": None,
                    "threshold": threshold,
                    "delta": delta,
                }
                if res[m]["solved"]:
                    if m == "ours":
                        rec["makespan"] = obj.makespan
                        rec["min_distance"] = obj.min_distance()
                        rec["trajectory"] = ours_trajectory(track, q)  # verified setpoints, timed
                    else:
                        rec["makespan"] = obj.makespan
                        rec["min_distance"] = min(
                            (leg_min_distance(track, a, b) for a, b in obj.legs), default=math.inf
                        )
                    rec["ratio_to_grid"] = rec["makespan"] / grid_ms if grid_ms > 0 else math.nan
                records.append(rec)
            # δ-twins: ours and OMPL (same seed); the grid is not continuous by construction and is skipped
            if twin_ok:
                _twins(track, q, twin, res, records[-3:], speeds, ompls[D], u, threshold)
            if progress:
                progress(f"{label} {qi + 1}/{len(queries)}")
        for r in records:
            if r["layout"] == label:
                r["fs_build"] = fs_build[r["clearance"]]
                r["grid_build"] = grids[r["clearance"]].build_time
                r["grid_h"] = h
    return records


def _twins(
    track: GraphTrack,
    q: dict[str, Any],
    twin: dict[str, Any],
    res: dict[str, dict[str, Any]],
    recs: list[dict[str, Any]],
    speeds: tuple[float, float],
    ompl: GraphOmpl,
    u: np.ndarray,
    threshold: float,
) -> None:
    by = {r["method"]: r for r in recs}
    p = res["ours"]["obj"]
    if p is not None:
        p2 = _plan(track, twin, speeds)
        if p2 is not None:
            gap = _gap(track, _ours_positions(p, u), _ours_positions(p2, u))
            changed = tuple(p.word) != tuple(p2.word)
            by["ours"].update(word_changed=changed, twin_gap=gap, discontinuous=bool(changed or gap > threshold))
    path: GraphPath | None = res["ompl"]["obj"]
    if path is not None and path.legs:
        pos1 = path.positions(u)
        w1 = _sampled_word(track, pos1)
        for suffix, seed in (("", q["seed"]), ("_reseeded", q["seed"] + 7919)):
            r2 = ompl.solve(twin["start"], twin["goal"], seed)
            if r2.solved and r2.path is not None and r2.path.legs:
                pos2 = r2.path.positions(u)
                gap = _gap(track, pos1, pos2)
                changed = w1 != _sampled_word(track, pos2)
                by["ompl"].update(
                    {
                        f"word_changed{suffix}": changed,
                        f"twin_gap{suffix}": gap,
                        f"discontinuous{suffix}": bool(changed or gap > threshold),
                    }
                )


def layouts_markdown(records: list[dict[str, Any]]) -> str:
    """Tables of :func:`run_layouts`."""
    lines = [
        "| layout | method | queries (feasible) | solved share | compute median / p95 (ms) | makespan median (s) |"
        " ratio to grid median / p95 / max | min distance ≥ D |",
        "|---|---|---|---|---|---|---|---|",
    ]
    layouts = list(dict.fromkeys(r["layout"] for r in records))
    for lay in layouts:
        for m in ("ours", "grid", "ompl"):
            rs = [r for r in records if r["layout"] == lay and r["method"] == m]
            feas = [r for r in rs if r["feasible"]]
            solved = [r for r in feas if r["solved"]]
            ct = [r["compute_time"] * 1e3 for r in rs]
            ms = [r["makespan"] for r in solved]
            rt = [r["ratio_to_grid"] for r in solved if r["ratio_to_grid"] == r["ratio_to_grid"]]
            exact = sum(1 for r in solved if r["min_distance"] >= r["clearance"] - 1e-9 * max(1.0, r["clearance"]))
            lines.append(
                f"| {lay} | {m} | {len(rs)} ({len(feas)}) | {len(solved)}/{len(feas)} | {_pct(ct, 50):.2f} / "
                f"{_pct(ct, 95):.2f} | {_pct(ms, 50):.3f} | {_pct(rt, 50):.4f} / {_pct(rt, 95):.4f} / "
                f"{max(rt) if rt else math.nan:.4f} | {exact}/{len(solved)} |"
            )
    lines += [
        "",
        "Discontinuous δ-twins: the plan of the query moved by δ changes its word or moves by more than the threshold"
        " at some normalised time; `n/N (word / gap)`; OMPL twins with the same seed and re-seeded.",
        "",
        "| layout | method | random queries | swaps |",
        "|---|---|---|---|",
    ]
    for lay in layouts:
        for m, suffix, label in (
            ("ours", "", "ours"),
            ("ompl", "", "ompl, same seed"),
            ("ompl", "_reseeded", "ompl, re-seeded"),
        ):
            rs = [r for r in records if r["layout"] == lay and r["method"] == m]
            cells = []
            for swap in (False, True):
                tw = [r for r in rs if r["swap"] == swap and r.get(f"discontinuous{suffix}") is not None]
                disc = sum(1 for r in tw if r[f"discontinuous{suffix}"])
                wc = sum(1 for r in tw if r[f"word_changed{suffix}"])
                gp = sum(1 for r in tw if r[f"twin_gap{suffix}"] > r.get("threshold", 0.01))
                cells.append(f"{disc}/{len(tw)} ({wc} / {gp})" if tw else "–")
            lines.append(f"| {lay} | {label} | {cells[0]} | {cells[1]} |")
    # completeness and grid details
    lines += [
        "",
        "| layout | grid step h (m) | clearances D (m) | free-space build median (ms) | grid build median (s) |"
        " grid solved, ours not (must be 0) | ours solved, grid not | infeasible queries (ours: no motion) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for lay in layouts:
        rs = [r for r in records if r["layout"] == lay]
        ours = {r["query"]: r for r in rs if r["method"] == "ours"}
        grid = {r["query"]: r for r in rs if r["method"] == "grid"}
        bad = sum(1 for k in grid if grid[k]["solved"] and not ours[k]["solved"])
        extra = sum(1 for k in grid if ours[k]["solved"] and not grid[k]["solved"])
        infeas = sum(1 for k in ours if not ours[k]["solved"])
        Ds = sorted({r["clearance"] for r in rs})
        fsb = [r["fs_build"] * 1e3 for r in ours.values()]
        gb = [r["grid_build"] for r in ours.values()]
        lines.append(
            f"| {lay} | {rs[0]['grid_h']:.4g} | {', '.join(f'{d:g}' for d in Ds)} | {_pct(fsb, 50):.2f} | "
            f"{_pct(gb, 50):.2f} | {bad} | {extra} | {infeas} |"
        )
    return "\n".join(lines) + "\n"


# -------------------------------------------------------------------------------------------------- Y oracle
def run_y_oracle(n: int, seed: int = 0, grid_h_fraction: float = 0.1) -> list[dict[str, Any]]:
    """Random Y junctions (branches b < b2 < b3): swap the ends of the two longer branches at D around b."""
    rng = np.random.default_rng(seed + 4242)
    out = []
    for k in range(n + 1):
        if k == 0:
            track = load_layout("y_junction")[1]
        else:
            ln = np.sort(rng.uniform(0.5, 3.0, 3))
            track = GraphTrack.from_layout({"edges": [["J", f"x{i}", float(x)] for i, x in enumerate(ln)]})
        L = track.lengths
        i0 = int(np.argmin(L))
        ends = [(e, float(L[e])) for e in range(3) if e != i0]  # the other branches' free ends (heads)
        b = float(L[i0])
        for label, D in (("b(1-1e-6)", b * (1 - 1e-6)), ("b", b), ("b(1+1e-6)", b * (1 + 1e-6))):
            expect = D <= b
            st, gl = (ends[0], ends[1]), (ends[1], ends[0])
            try:
                mpa.plan(track, st, gl, D, planner="graph")
                ours = True
            except NoMotionError:
                ours = False
            grid = GraphGrid(track, D, b * grid_h_fraction).solve(st, gl).solved
            out.append(
                {"layout": k, "b": b, "case": label, "clearance": D, "expect": expect, "ours": ours, "grid": grid}
            )
    return out


def y_oracle_markdown(records: list[dict[str, Any]]) -> str:
    lines = ["| D | layouts | expected swap | ours correct | grid correct |", "|---|---|---|---|---|"]
    for case in ("b(1-1e-6)", "b", "b(1+1e-6)"):
        rs = [r for r in records if r["case"] == case]
        lines.append(
            f"| {case} | {len(rs)} | {'yes' if rs[0]['expect'] else 'no'} | "
            f"{sum(r['ours'] == r['expect'] for r in rs)}/{len(rs)} | "
            f"{sum(r['grid'] == r['expect'] for r in rs)}/{len(rs)} |"
        )
    return "\n".join(lines) + "\n"


def random_small_graph(rng: np.random.Generator) -> GraphTrack:
    """A seeded connected multigraph of 2–5 vertices and 2–7 edges (loops and parallel edges allowed), 0.5–3 m."""
    nv = int(rng.integers(2, 6))
    edges: list[list[Any]] = [
        [f"v{i}", f"v{int(rng.integers(0, i))}", float(rng.uniform(0.5, 3.0))] for i in range(1, nv)
    ]
    for _ in range(int(rng.integers(1, 4))):
        a, b = int(rng.integers(0, nv)), int(rng.integers(0, nv))
        edges.append([f"v{a}", f"v{b}", float(rng.uniform(0.5, 3.0))])
    return GraphTrack.from_layout({"edges": edges})


def run_completeness(n_graphs: int, queries: int = 5, seed: int = 0, grid_nodes: int = 150) -> list[dict[str, Any]]:
    """Seeded random small graphs: does ours find a motion whenever the exact-edge grid finds a path?"""
    rng = np.random.default_rng(seed + 777)
    out = []
    for k in range(n_graphs):
        track = random_small_graph(rng)
        L = track.lengths
        D = float(rng.choice([0.3, 1.0, 2.0]) * rng.uniform(0.7, 1.3) * float(np.min(L)))
        grid = GraphGrid(track, D, track.total_length / grid_nodes)
        for q in make_graph_queries(track, queries, seed * 100_000 + k, [D]):
            ours = _plan(track, q, (1.0, 1.0))
            g = grid.solve(q["start"], q["goal"])
            out.append(
                {
                    "graph": k,
                    "edges": track.n_edges,
                    "clearance": D,
                    "swap": q["swap"],
                    "ours": ours is not None,
                    "grid": g.solved,
                    "ratio": ours.makespan / g.makespan if ours is not None and g.solved else None,
                    "exact": ours.min_distance() >= D - 1e-9 * max(1.0, D) if ours is not None else None,
                }
            )
    return out


def completeness_markdown(records: list[dict[str, Any]]) -> str:
    """Table of :func:`run_completeness`."""
    both = [r for r in records if r["ours"] and r["grid"]]
    rt = [r["ratio"] for r in both]
    return (
        "| graphs | queries | grid solved | ours solved | grid solved, ours not (must be 0) | ours solved, grid not |"
        " ours min distance ≥ D | ratio ours/grid median / max |\n|---|---|---|---|---|---|---|---|\n"
        f"| {len({r['graph'] for r in records})} | {len(records)} | {sum(r['grid'] for r in records)} | "
        f"{sum(r['ours'] for r in records)} | {sum(r['grid'] and not r['ours'] for r in records)} | "
        f"{sum(r['ours'] and not r['grid'] for r in records)} | {sum(bool(r['exact']) for r in records if r['ours'])}/"
        f"{sum(r['ours'] for r in records)} | {_pct(rt, 50):.4f} / {max(rt) if rt else math.nan:.4f} |\n"
    )


# ----------------------------------------------------------------------------------------------- paper price
PAPER_SIZES = ((1.0, 1.0), (2.0, 3.0), (1.0, 3.0), (100.0, 300.0))


def _paper_makespan(plan: Any, v: tuple[float, float]) -> float:
    d = np.abs(np.diff(np.asarray(plan.waypoints_s, dtype=float), axis=0))
    return float(np.sum(np.maximum(d[:, 0] / v[0], d[:, 1] / v[1]))) if len(d) else 0.0


def run_price(
    n: int, seed: int = 0, speeds: tuple[float, float] = (0.5, 0.5), sizes: Sequence[tuple[float, float]] = PAPER_SIZES
) -> list[dict[str, Any]]:
    """Graph planner (fastest) against the paper planner on lollipops, random queries and swaps (n each)."""
    out = []
    u = np.linspace(0.0, 1.0, 2001)
    for si, (ell, c) in enumerate(sizes):
        track = mpa.Lollipop(ell, c)
        gt = track.as_graph_track()
        scale = ell if ell >= 10 else 1.0
        D = 0.05 * scale
        rng = np.random.default_rng(seed * 100 + si)
        total = ell + c
        for kind in ("random", "swap"):
            k = 0
            while k < n:
                a, b = rng.uniform(0, total, 2)
                if track.distance_scalar(a, b) < D * (1 + 1e-9):
                    continue
                if kind == "swap":
                    goal = (b, a)
                else:
                    goal = tuple(rng.uniform(0, total, 2))
                    if track.distance_scalar(*goal) < D * (1 + 1e-9):
                        continue
                k += 1
                rec: dict[str, Any] = {"stick": ell, "loop": c, "kind": kind, "clearance": D}
                try:
                    pp = mpa.plan(track, (a, b), goal, D)
                    gp = mpa.plan(track, (a, b), goal, D, planner="graph", objective="fastest", speeds=speeds)
                except mpa.errors.MPAError as exc:
                    rec["error"] = f"{type(exc).__name__}: {exc}"
                    out.append(rec)
                    continue
                tp = _paper_makespan(pp, speeds)
                rec.update(paper=tp, graph=gp.makespan, ratio=gp.makespan / tp if tp > 0 else 1.0)
                pe, po = track.to_graph_position(pp.path(u))
                w_paper = _sampled_word(gt, (pe[:, 0], po[:, 0], pe[:, 1], po[:, 1]))
                w_graph = _sampled_word(gt, _ours_positions(gp, u))
                rec["other_word"] = w_paper != w_graph
                out.append(rec)
    return out


def price_markdown(records: list[dict[str, Any]]) -> str:
    lines = [
        "| stick/loop (m) | D (m) | queries | errors | other sampled word | graph faster by > 1 % |"
        " speed-up paper/graph median / p95 / max (of those) | ratio graph/paper max | > 1 % slower (target 0) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for ell, c in dict.fromkeys((r["stick"], r["loop"]) for r in records):
        for kind in ("random", "swap"):
            rs = [r for r in records if r["stick"] == ell and r["loop"] == c and r["kind"] == kind]
            ok = [r for r in rs if "ratio" in r]
            faster = [r for r in ok if r["ratio"] < 0.99]
            sp = [1.0 / r["ratio"] for r in faster]
            slower = sum(1 for r in ok if r["ratio"] > 1.01)
            lines.append(
                f"| {ell:g}/{c:g} {kind} | {rs[0]['clearance']:g} | {len(rs)} | {len(rs) - len(ok)} | "
                f"{sum(r['other_word'] for r in ok)} | {len(faster)} | "
                + (f"{_pct(sp, 50):.3f} / {_pct(sp, 95):.3f} / {max(sp):.3f}" if sp else "–")
                + f" | {max(r['ratio'] for r in ok):.4f} | {slower} |"
            )
    return "\n".join(lines) + "\n"


# ------------------------------------------------------------------------------------------------- scaling
def spanning_then_extra(
    n_vertices: int,
    cand: list[tuple[int, int]],
    n_edges: int,
    rng: np.random.Generator,
    extra_order: Callable[[tuple[int, int]], float] | None = None,
) -> list[tuple[int, int]]:
    """A random spanning forest of the candidate edges ``cand`` (vertices ``0 … n_vertices − 1``; Kruskal in the
    order of ``rng.permutation``), then the other candidates (in ``extra_order`` if given, else in that random
    order) up to ``n_edges`` edges."""
    parent = list(range(n_vertices))

    def find(x: int) -> int:
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    chosen, rest = [], []
    for k in rng.permutation(len(cand)):
        a, b = cand[k]
        ra, rb = find(a), find(b)
        if ra != rb:
            parent[ra] = rb
            chosen.append(cand[k])
        else:
            rest.append(cand[k])
    if extra_order is not None:
        rest.sort(key=extra_order)
    return chosen + rest[: max(0, n_edges - len(chosen))]


def grid_layout(n_edges: int, seed: int) -> GraphTrack:
    """A seeded building-like navigation graph with ``n_edges`` edges: a random spanning tree of a lattice with
    uneven spacings (4–12 m) plus random extra lattice edges (corridors); lengths are straight distances."""
    rng = np.random.default_rng(seed)
    side = 2
    while 2 * side * (side - 1) < n_edges:
        side += 1
    rows, cols = side, side
    while rows * cols - 1 > n_edges and cols > 2:  # the spanning tree must fit
        cols -= 1
    xs = np.concatenate([[0.0], np.cumsum(rng.uniform(4.0, 12.0, cols - 1))])
    ys = np.concatenate([[0.0], np.cumsum(rng.uniform(4.0, 12.0, rows - 1))])
    names = [f"v{i}_{j}" for i in range(rows) for j in range(cols)]
    cand = [(i * cols + j, i * cols + j + 1) for i in range(rows) for j in range(cols - 1)]
    cand += [(i * cols + j, (i + 1) * cols + j) for i in range(rows - 1) for j in range(cols)]
    chosen = spanning_then_extra(rows * cols, cand, n_edges, rng)
    verts = {names[v]: [float(xs[v % cols]), float(ys[v // cols])] for v in range(rows * cols)}
    used = {names[a] for a, _ in chosen} | {names[b] for _, b in chosen}
    verts = {k: v for k, v in verts.items() if k in used}
    return GraphTrack.from_layout({"vertices": verts, "edges": [[names[a], names[b]] for a, b in chosen]})


def timed_build(track: GraphTrack, clearance: float) -> tuple[float, int]:
    """Seconds one uncached :class:`~mpa.freespace.FreeSpace` build of ``track`` takes, and its polygons."""
    t0 = time.perf_counter()
    fs = FreeSpace(track, clearance)
    return time.perf_counter() - t0, len(fs.polygon_ids)


def plan_times(track: GraphTrack, qs: list[dict[str, Any]]) -> dict[str, Any]:
    """Plan time of the queries ``qs[1:]`` at unit speeds after one plan of ``qs[0]`` (warm: free space cached).

    Returns ``plan_median``, ``plan_p95``, ``plan_max`` (s), ``solved`` (plans found) and ``queries``.
    """
    _plan(track, qs[0], (1.0, 1.0))  # warm
    times, solved = [], 0
    for q in qs[1:]:
        t0 = time.perf_counter()
        p = _plan(track, q, (1.0, 1.0))
        times.append(time.perf_counter() - t0)
        solved += p is not None
    return {
        "plan_median": float(np.median(times)),
        "plan_p95": float(np.percentile(times, 95)),
        "plan_max": float(np.max(times)),
        "solved": solved,
        "queries": len(times),
    }


def run_scaling(
    sizes: Sequence[int] = (10, 30, 100, 150),
    layouts_per_size: int = 3,
    queries: int = 10,
    clearance: float = 1.0,
    seed: int = 0,
    progress: Callable[[str], None] | None = None,
) -> list[dict[str, Any]]:
    """Free-space build (uncached) and plan time (free space cached) on :func:`grid_layout` layouts."""
    out = []
    for n_e in sizes:
        for k in range(layouts_per_size):
            track = grid_layout(n_e, seed * 10_000 + n_e * 10 + k)
            build, polygons = timed_build(track, clearance)
            free_space(track, clearance)
            qs = make_graph_queries(track, queries + 1, seed + k, [clearance])
            rec = {"edges": track.n_edges, "vertices": track.graph.n_vertices, "layout": k, "build": build}
            out.append(rec | {"polygons": polygons, **plan_times(track, qs)})
            if progress:
                progress(f"scaling {n_e} edges, layout {k + 1}/{layouts_per_size}")
    return out


def scaling_markdown(records: list[dict[str, Any]]) -> str:
    lines = [
        "| edges | layouts | free-space build median / max (ms) | plan median (ms) | plan p95 (ms) | plan max (ms) |"
        " solved |",
        "|---|---|---|---|---|---|---|",
    ]
    for n_e in dict.fromkeys(r["edges"] for r in records):
        rs = [r for r in records if r["edges"] == n_e]
        lines.append(
            f"| {n_e} | {len(rs)} | {np.median([r['build'] for r in rs]) * 1e3:.1f} / "
            f"{max(r['build'] for r in rs) * 1e3:.1f} | {np.median([r['plan_median'] for r in rs]) * 1e3:.2f} | "
            f"{np.median([r['plan_p95'] for r in rs]) * 1e3:.2f} | {max(r['plan_max'] for r in rs) * 1e3:.1f} | "
            f"{sum(r['solved'] for r in rs)}/{sum(r['queries'] for r in rs)} |"
        )
    return "\n".join(lines) + "\n"


def trajectories_markdown(records: list[dict[str, Any]]) -> str:
    """Table of ours' verified trajectories per layout (``rec["trajectory"]`` of the ``ours`` records)."""
    rows = [
        "| layout | plans | verified | fallbacks | fast path | compute median / p95 (ms) | makespan median (s) | "
        "makespan / plan makespan median |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for label in dict.fromkeys(r["layout"] for r in records):
        recs = [r for r in records if r["layout"] == label and r["method"] == "ours" and r.get("trajectory")]
        if not recs:
            continue
        tr = [r["trajectory"] for r in recs]
        ok = [x for x in tr if x.get("verified")]
        ratio = [
            x["makespan"] / r["makespan"]
            for r, x in zip(recs, tr, strict=True)
            if x.get("verified") and r["makespan"] > 0
        ]
        rows.append(
            f"| {label} | {len(tr)} | {len(ok)}/{len(tr)} | {sum(bool(x.get('fallback')) for x in ok)} | "
            f"{sum(x.get('path') == 'fast' for x in ok)} | {_pct([x['compute_time'] * 1e3 for x in tr], 50):.2f} / "
            f"{_pct([x['compute_time'] * 1e3 for x in tr], 95):.2f} | {_pct([x['makespan'] for x in ok], 50):.3f} | "
            f"{_pct(ratio, 50):.3f} |"
        )
    return "\n".join(rows)
