"""Compute time against the lean OMPL pipeline, in one process, interleaved, warm.

For each track, the same seeded queries (:func:`bench.runner.make_queries`, with their δ-twins) go through

- ``ours``: ``trajopt.TrajectoryGenerator.generate`` (plan → fast path or corridor QP → filtered timing → ruckig →
  the full verification gate), and
- ``lean``: :class:`bench.lean.LeanOmpl` (RRTConnect, exact geodesic motion validator, simplification, one ruckig
  profile per straight segment rest to rest, dense check of the setpoints),

alternating which one runs first, after a warm-up of both on the first queries, in this one process; each call is
timed with :func:`time.perf_counter` from the query to verified setpoints. Reported per track: the medians and
p95 of both and their ratio (ratio of the medians, and the median of per-query ratios), the same on the
interacting queries (the naive motion collides), the makespan ratio ours ÷ lean (per query), the verified
shares, and the discontinuity rate of the δ-twins (sup distance over normalised time above the threshold).
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np

from bench.lean import LeanOmpl, LeanResult
from bench.motion import Motion
from bench.runner import BenchConfig, _interacting, make_queries, twin_distance
from mpa.errors import MPAError
from trajopt import Limits, TrajectoryGenerator
from trajopt.generator import separation_margin

__all__ = ["compare_compute", "compute_markdown"]

#: Tracks of the compute comparison: (label, track kind, stick, loop).
TRACKS = (
    ("lollipop 1/1", "lollipop", 1.0, 1.0),
    ("circle 1", "circle", None, 1.0),
    ("lollipop 1.5/0.8", "lollipop", 1.5, 0.8),
    ("lollipop 0.3/1.2", "lollipop", 0.3, 1.2),
    ("lollipop 1.3/0.9", "lollipop", 1.3, 0.9),
)


def _lean_normalized(res: LeanResult, n: int = 401) -> np.ndarray:
    """Setpoints at ``n`` normalised times (nearest row; rows are 1/rate apart). Shape (n, 2)."""
    idx = np.rint(np.linspace(0.0, 1.0, n) * (len(res.q) - 1)).astype(int)
    return res.q[idx]


def _lean_twin(track: Any, r1: LeanResult, r2: LeanResult) -> float:
    a, b = _lean_normalized(r1), _lean_normalized(r2)
    return float(max(np.max(track.distance(a[:, 0], b[:, 0])), np.max(track.distance(a[:, 1], b[:, 1]))))


def _ours(gen: TrajectoryGenerator, s: np.ndarray, g: np.ndarray) -> tuple[float, Any]:
    t0 = time.perf_counter()
    try:
        traj = gen.generate(s, g)
    except MPAError:
        return time.perf_counter() - t0, None
    return time.perf_counter() - t0, traj


def compare_compute(config: BenchConfig, n: int, warmup: int = 10) -> dict[str, Any]:
    """Run ours and the lean OMPL pipeline interleaved on ``n`` queries of ``config`` (see module docstring)."""
    track = config.make_track()
    limits = Limits(config.vmax, config.amax, config.jmax)
    sep = config.clearance + separation_margin(limits, config.rate)
    gen = TrajectoryGenerator(track, clearance=config.clearance, limits=limits, rate=config.rate)
    lean = LeanOmpl(track, config.clearance, sep, limits, config.rate, config.ompl_time)
    queries = make_queries(config, n)
    for q in queries[:warmup]:
        s, g = np.asarray(q["start"]), np.asarray(q["goal"])
        gen.generate(s, g)
        lean.solve(s, g)
    rows = []
    for i, q in enumerate(queries):
        s, g = np.asarray(q["start"]), np.asarray(q["goal"])
        ts, tg = np.asarray(q["twin_start"]), np.asarray(q["twin_goal"])
        if i % 2 == 0:
            t_ours, traj = _ours(gen, s, g)
            r = lean.solve(s, g)
        else:
            r = lean.solve(s, g)
            t_ours, traj = _ours(gen, s, g)
        _, ttraj = _ours(gen, ts, tg)
        rt = lean.solve(ts, tg)
        ok = traj is not None and bool(traj.verification["ok"]) and not traj.fallback
        row = {
            "query": i,
            "interacting": _interacting(track, s, g, config.clearance),
            "ours_time": t_ours,
            "ours_verified": ok,
            "ours_path": traj.solver_stats.get("path", "") if traj is not None else "",
            "ours_makespan": float(traj.motion_time) if traj is not None else math.nan,
            "lean_time": r.compute_time,
            "lean_verified": r.verified,
            "lean_makespan": r.makespan if r.verified else math.nan,
            "lean_waypoints": r.waypoints,
            "ours_twin": (
                twin_distance(track, Motion.from_trajectory(traj), Motion.from_trajectory(ttraj))
                if traj is not None and ttraj is not None
                else math.nan
            ),
            "lean_twin": _lean_twin(track, r, rt) if r.verified and rt.verified else math.nan,
        }
        rows.append(row)
    lean.close()
    return {"label": "", "config": config.to_dict(), "rows": rows, "summary": summarize(rows, config.threshold)}


def _stats(x: np.ndarray) -> tuple[float, float]:
    return (float(np.median(x)), float(np.percentile(x, 95))) if len(x) else (math.nan, math.nan)


def summarize(rows: list[dict[str, Any]], threshold: float) -> dict[str, Any]:
    """Medians, p95 and ratios of :func:`compare_compute`'s rows (times in ms)."""
    out: dict[str, Any] = {"n": len(rows)}
    for label, sel in (("all", rows), ("interacting", [r for r in rows if r["interacting"]])):
        to = np.array([r["ours_time"] for r in sel]) * 1e3
        tl = np.array([r["lean_time"] for r in sel]) * 1e3
        mo, po = _stats(to)
        ml, pl = _stats(tl)
        both = [r for r in sel if r["ours_verified"] and r["lean_verified"]]
        mk = np.array([r["ours_makespan"] / r["lean_makespan"] for r in both if r["lean_makespan"] > 0])
        out[label] = {
            "n": len(sel),
            "ours_median_ms": mo,
            "ours_p95_ms": po,
            "lean_median_ms": ml,
            "lean_p95_ms": pl,
            "ratio_median": mo / ml if ml > 0 else math.nan,
            "ratio_p95": po / pl if pl > 0 else math.nan,
            "per_query_ratio_median": float(np.median(to / tl)) if len(sel) else math.nan,
            "makespan_ours_over_lean_median": float(np.median(mk)) if len(mk) else math.nan,
            "makespan_ours_over_lean_p95": float(np.percentile(mk, 95)) if len(mk) else math.nan,
        }
    out["ours_verified"] = sum(r["ours_verified"] for r in rows) / max(1, len(rows))
    out["lean_verified"] = sum(r["lean_verified"] for r in rows) / max(1, len(rows))
    out["ours_fast"] = sum(r["ours_path"] == "fast" for r in rows)
    for m in ("ours", "lean"):
        tw = np.array([r[f"{m}_twin"] for r in rows], dtype=float)
        tw = tw[np.isfinite(tw)]
        out[f"{m}_discontinuity_rate"] = float(np.mean(tw > threshold)) if len(tw) else math.nan
        out[f"{m}_twins"] = len(tw)
    return out


def compute_markdown(results: list[dict[str, Any]]) -> str:
    """The tables of a ``--compute`` run."""
    lines = [
        "| track | n (interacting) | ours median (p95) ms | lean OMPL median (p95) ms | ratio median | "
        "ratio p95 | interacting: ours / lean median ms | ratio | makespan ours ÷ lean, median (interacting) | "
        "verified ours / lean | disc. rate ours / lean |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for res in results:
        s = res["summary"]
        a, i = s["all"], s["interacting"]
        lines.append(
            f"| {res['label']} | {a['n']} ({i['n']}) | {a['ours_median_ms']:.2f} ({a['ours_p95_ms']:.1f}) | "
            f"{a['lean_median_ms']:.2f} ({a['lean_p95_ms']:.1f}) | {a['ratio_median']:.2f}× | {a['ratio_p95']:.2f}× | "
            f"{i['ours_median_ms']:.2f} / {i['lean_median_ms']:.2f} | {i['ratio_median']:.2f}× | "
            f"{a['makespan_ours_over_lean_median']:.3f} ({i['makespan_ours_over_lean_median']:.3f}) | "
            f"{100 * s['ours_verified']:.0f} % / {100 * s['lean_verified']:.0f} % | "
            f"{100 * s['ours_discontinuity_rate']:.1f} % / {100 * s['lean_discontinuity_rate']:.1f} % |"
        )
    return "\n".join(lines) + "\n"
