"""Benchmark of the trajectory pipeline on seeded random queries (headless).

For every query: wall time per stage (plan, smooth = corridor QPs, blend = spline, jerk = the timing: one ruckig
profile on the fast path, the filtered profile on the hard path, sample, verify), which path it took (``fast``:
the straight route-coordinate motion keeps the clearance; ``hard``: the corridor QP), and the makespan (motion
time, s) against

(a) the plan executed as is: every straight step of the plan rest to rest with 1-DoF ruckig along it
    (``TrajectoryGenerator(optimize=False)``, which is also the fallback),
(b) the lower bound: max over the robots of the jerk-limited rest-to-rest minimum time along its own shortest
    route, ignoring the other robot, and
(c) with ``--compare old.json`` (this script's JSON from another version, same seed and size): the per-query
    ratio new/old (the issue's goal: median and p99 <= 1.001).

``--pairs K`` also measures continuity on K seeded perturbation pairs per domain (:mod:`trajopt.analysis.stability`):
the
sup gap of the trajectories (normalised time) and of the motion times for δ = 1e-3 … 1e-7, and ``gap/δ``.

Usage::

    python experiments/bench_trajectory.py [--n 200] [--seed 0] [--track lollipop] [--pairs 0] [--json out.json]
    python experiments/bench_trajectory.py --leaks 1000      # memory and log handlers over 1 000 trajectories
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections.abc import Sequence

import numpy as np

from mpa import defaults
from mpa.errors import MPAError
from mpa.tracks import make_track
from trajopt import Limits, TrajectoryGenerator
from trajopt.testing import random_queries
from trajopt.timing import min_time_rest_to_rest

STAGES = ("plan", "smooth", "blend", "jerk", "sample", "verify")
DOMAINS = {"lollipop": (1, 2, 3), "circle": (1, 2), "interval": (1,)}
DELTAS = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7)


def _q(x: np.ndarray) -> tuple[float, float]:
    return (float(np.median(x)), float(np.percentile(x, 95))) if len(x) else (float("nan"), float("nan"))


def continuity(gen: TrajectoryGenerator, kind: str, pairs: int, seed: int) -> dict[str, object]:
    """Gaps on ``pairs`` seeded perturbation pairs per domain (see the module docstring)."""
    from trajopt.analysis.stability import perturbation_pairs, trajectory_gap

    out: dict[str, object] = {}
    for dom in DOMAINS.get(kind, (1,)):
        pp = perturbation_pairs(gen.planner, dom, pairs, np.random.default_rng(seed + dom))
        gaps = {d: [] for d in DELTAS}  # type: ignore[var-annotated]
        fallbacks, hard = 0, 0
        for i in range(pairs):
            base = gen.generate(pp.starts[i], pp.goals[i])
            fallbacks += base.fallback
            hard += base.solver_stats.get("path") == "hard"
            for d in DELTAS:
                s2, g2 = pp.perturbed(d)
                other = gen.generate(s2[i], g2[i])
                fallbacks += other.fallback
                gaps[d].append(max(trajectory_gap(base, other)))
        out[str(dom)] = {
            "pairs": pairs,
            "hard": hard,
            "fallbacks": fallbacks,
            "sup_gap": {str(d): float(np.max(v)) for d, v in gaps.items()},
            "max_gap_over_delta": {str(d): float(np.max(v)) / d for d, v in gaps.items()},
            "discontinuous_pairs": int(np.sum(np.array(gaps[1e-7]) > 1e-4)),
        }
    return out


def run(
    n: int = 120, seed: int = 0, kind: str = "lollipop", clearance: float = 0.05, pairs: int = 0
) -> dict[str, object]:
    """Run the benchmark and return the raw per-query numbers and the summary table."""
    track = make_track(kind)
    limits = Limits(0.5, 1.0, 5.0)
    t0 = time.perf_counter()
    gen = TrajectoryGenerator(track, clearance=clearance, limits=limits)
    base = TrajectoryGenerator(track, clearance=clearance, limits=limits, optimize=False)
    queries = random_queries(track, clearance, n, seed)
    for s, g in queries[:3]:  # warm up (solver objects are built on first use)
        try:
            gen.generate(s, g)
        except MPAError:
            pass
    build = time.perf_counter() - t0
    rows = []
    skipped = 0
    for s, g in queries:
        t1 = time.perf_counter()
        try:
            tr = gen.generate(s, g)
        except MPAError:
            skipped += 1  # no motion exists (only possible on tracks without a loop or with a large clearance)
            continue
        wall = time.perf_counter() - t1
        b = base.generate(s, g)
        lb = max(
            min_time_rest_to_rest(float(track.distance(s[r], g[r])), limits.v[r], limits.a[r], limits.j[r])
            for r in (0, 1)
        )
        rows.append(
            {
                "start": s.tolist(),
                "goal": g.tolist(),
                "domain": tr.domain,
                "path": tr.solver_stats.get("path", "plan"),
                "fallback": tr.fallback,
                "reason": tr.fallback_reason,
                "wall": wall,
                **{k: tr.timings.get(k, 0.0) for k in STAGES},
                "qp_time": tr.solver_stats.get("qp_time", 0.0),
                "motion_time": tr.motion_time,
                "plan_time": b.motion_time,
                "lower_bound": lb,
            }
        )
    arr = {k: np.array([r[k] for r in rows], dtype=float) for k in ("wall", *STAGES, "qp_time")}
    fast = np.array([r["path"] == "fast" for r in rows])
    mt = np.array([r["motion_time"] for r in rows])
    ptime = np.array([r["plan_time"] for r in rows])
    lb = np.array([r["lower_bound"] for r in rows])
    moving = ptime > 0
    ra = mt[moving] / ptime[moving]
    rb = mt[lb > 0] / lb[lb > 0]
    wall = arr["wall"]
    table = {
        "queries": len(rows),
        "skipped": skipped,
        "fallbacks": int(sum(r["fallback"] for r in rows)),
        "build_s": build,
        "fast_path": int(fast.sum()),
        "wall_ms": {
            "all": tuple(1e3 * x for x in _q(wall)),
            "fast": tuple(1e3 * x for x in _q(wall[fast])),
            "hard": tuple(1e3 * x for x in _q(wall[~fast])),
        },
        "time_ms": {k: tuple(1e3 * x for x in _q(v)) for k, v in arr.items() if k != "wall"},
        "ratio_vs_plan": (float(np.median(ra)), float(np.percentile(ra, 95)), float(np.max(ra))),
        "ratio_vs_lower_bound": (float(np.median(rb)), float(np.percentile(rb, 95)), float(np.max(rb))),
        "makespan_s": (float(np.median(mt)), float(np.percentile(mt, 95))),
    }
    res: dict[str, object] = {
        "track": track.to_dict(),
        "clearance": clearance,
        "seed": seed,
        "table": table,
        "rows": rows,
    }
    if pairs > 0:
        res["continuity"] = continuity(gen, kind, pairs, seed)
    return res


def compare(res: dict[str, object], old: dict[str, object]) -> dict[str, float]:
    """Per-query makespan ratio new/old on the queries both runs share (same seed)."""
    old_rows = {tuple(r["start"] + r["goal"]): r for r in old["rows"]}  # type: ignore[attr-defined]
    ratio, speed = [], []
    for r in res["rows"]:  # type: ignore[attr-defined]
        o = old_rows.get(tuple(r["start"] + r["goal"]))
        if o is None or o["motion_time"] <= 0:
            continue
        ratio.append(r["motion_time"] / o["motion_time"])
        speed.append(o["wall"] / r["wall"])
    x = np.array(ratio)
    return {
        "queries": len(x),
        "makespan_ratio_median": float(np.median(x)),
        "makespan_ratio_p99": float(np.percentile(x, 99)),
        "makespan_ratio_max": float(np.max(x)),
        "worse_than_1.001": int(np.sum(x > 1.001)),
        "wall_speedup_median": float(np.median(speed)),
    }


def format_table(res: dict[str, object]) -> str:
    """A plain-text report of :func:`run`'s summary."""
    t = res["table"]
    assert isinstance(t, dict)
    lines = [
        f"track {res['track']}, clearance {res['clearance']}, seed {res['seed']}: {t['queries']} queries, "
        f"{t['fallbacks']} fallbacks, {t['skipped']} without motion; build + warm-up {1e3 * t['build_s']:.0f} ms",
        f"fast path: {t['fast_path']} of {t['queries']} queries",
        f"{'wall':<10} {'median ms':>10} {'p95 ms':>10}",
    ]
    for k, (med, p95) in t["wall_ms"].items():
        lines.append(f"{k:<10} {med:>10.2f} {p95:>10.2f}")
    lines.append(f"{'stage':<10} {'median ms':>10} {'p95 ms':>10}")
    for k, (med, p95) in t["time_ms"].items():
        lines.append(f"{k:<10} {med:>10.2f} {p95:>10.2f}")
    a, b, m = t["ratio_vs_plan"], t["ratio_vs_lower_bound"], t["makespan_s"]
    lines.append("(smooth = corridor QPs; blend = spline; jerk = ruckig (fast) or the filtered profile (hard))")
    lines.append(f"makespan: median {m[0]:.2f} s, p95 {m[1]:.2f} s")
    lines.append(f"makespan / plan executed as is (a): median {a[0]:.3f}, p95 {a[1]:.3f}, max {a[2]:.3f}")
    lines.append(f"makespan / lower bound (b):         median {b[0]:.3f}, p95 {b[1]:.3f}, max {b[2]:.3f}")
    if "compare" in res:
        c = res["compare"]
        assert isinstance(c, dict)
        lines.append(
            f"makespan new/old (c) on {c['queries']} queries: median {c['makespan_ratio_median']:.4f}, "
            f"p99 {c['makespan_ratio_p99']:.4f}, max {c['makespan_ratio_max']:.4f}, "
            f"{c['worse_than_1.001']} above 1.001; wall speed-up median {c['wall_speedup_median']:.2f}x"
        )
    if "continuity" in res:
        cont = res["continuity"]
        assert isinstance(cont, dict)
        for dom, c in cont.items():
            gaps = ", ".join(f"{float(d):.0e}: {g:.2e}" for d, g in c["sup_gap"].items())
            ratios = ", ".join(f"{r:.2f}" for r in c["max_gap_over_delta"].values())
            lines.append(
                f"continuity, domain {dom} ({c['pairs']} pairs, {c['hard']} hard, {c['fallbacks']} fallbacks, "
                f"{c['discontinuous_pairs']} with gap > 1e-4 at 1e-7): sup gap {gaps}; max gap/δ {ratios}"
            )
    return "\n".join(lines)


def leaks(n: int, seed: int, kind: str, clearance: float) -> dict[str, float]:
    """Resident memory, log handlers and warnings filters over ``n`` trajectories in this process."""
    import logging
    import resource
    import warnings

    def rss_mb() -> float:
        try:
            with open("/proc/self/statm", encoding="ascii") as fh:
                return int(fh.read().split()[1]) * resource.getpagesize() / 2**20
        except OSError:  # not Linux: the peak instead
            return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024

    def handlers() -> int:
        loggers = [logging.getLogger(), *(logging.getLogger(k) for k in logging.root.manager.loggerDict)]
        return sum(len(lg.handlers) for lg in loggers)

    track = make_track(kind)
    gen = TrajectoryGenerator(track, clearance=clearance)
    qs = random_queries(track, clearance, n, seed)
    out: dict[str, float] = {}
    for i, (s, g) in enumerate(qs):
        gen.generate(s, g)
        if i + 1 == 50:
            out.update(rss_after_50=rss_mb(), handlers_after_50=handlers(), filters_after_50=len(warnings.filters))
    out.update(rss_end=rss_mb(), handlers_end=handlers(), filters_end=len(warnings.filters), n=n)
    return out


def main(argv: Sequence[str] | None = None) -> int:
    """Command line entry point."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=120, help="number of queries (default 120)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--track", default="lollipop", choices=["lollipop", "circle", "interval"])
    ap.add_argument("--clearance", type=float, default=defaults.CLEARANCE)
    ap.add_argument("--pairs", type=int, default=0, help="perturbation pairs per domain (continuity; default 0)")
    ap.add_argument("--compare", default=None, help="JSON of another version's run: per-query makespan ratios")
    ap.add_argument("--json", default=None, help="write the raw numbers to this file")
    ap.add_argument("--leaks", type=int, default=0, help="instead: memory and handlers over this many trajectories")
    args = ap.parse_args(argv)
    if args.leaks:
        lk = leaks(args.leaks, args.seed, args.track, args.clearance)
        print(
            f"{lk['n']:.0f} trajectories: resident memory {lk['rss_after_50']:.1f} MB after 50, {lk['rss_end']:.1f} MB "
            f"at the end ({lk['rss_end'] - lk['rss_after_50']:+.1f} MB); log handlers {lk['handlers_after_50']:.0f} -> "
            f"{lk['handlers_end']:.0f}; warnings filters {lk['filters_after_50']:.0f} -> {lk['filters_end']:.0f}"
        )
        return 0
    res = run(args.n, args.seed, args.track, args.clearance, args.pairs)
    if args.compare:
        with open(args.compare, encoding="utf-8") as fh:
            res["compare"] = compare(res, json.load(fh))
    print(format_table(res))
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(res, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
