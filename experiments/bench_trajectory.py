"""Benchmark of the trajectory pipeline on seeded random queries (headless).

For every query: wall time per stage (plan, smooth = IPOPT + shortcut, blend, retime = toppra, jerk = ruckig,
sample, verify), IPOPT iterations, and the makespan (motion time, s) against

(a) the plan executed as is: every straight step of the plan rest to rest with 1-DoF ruckig along it
    (``TrajectoryGenerator(optimize=False)``, which is also the fallback), and
(b) the lower bound: max over the robots of the jerk-limited rest-to-rest minimum time along its own shortest
    route, ignoring the other robot.

Usage::

    python experiments/bench_trajectory.py [--n 200] [--seed 0] [--track lollipop] [--json out.json]
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
from trajopt.smoothing import SIZE_CLASSES, problem_for
from trajopt.timing import min_time_rest_to_rest

STAGES = ("plan", "smooth", "blend", "retime", "jerk", "sample", "verify")


def random_queries(track, clearance: float, n: int, seed: int) -> list[tuple[np.ndarray, np.ndarray]]:  # type: ignore[no-untyped-def]
    """``n`` seeded random valid queries (both states at least the clearance apart)."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        s, g = rng.uniform(0.0, track.total_length, 2), rng.uniform(0.0, track.total_length, 2)
        if track.distance(*s) >= clearance and track.distance(*g) >= clearance:
            out.append((s, g))
    return out


def run(n: int = 120, seed: int = 0, kind: str = "lollipop", clearance: float = 0.05) -> dict[str, object]:
    """Run the benchmark and return the raw per-query numbers and the summary table."""
    track = make_track(kind)
    limits = Limits(0.5, 1.0, 5.0)
    t0 = time.perf_counter()
    for pieces in (1, *(s // 2 for s in SIZE_CLASSES[1:])):
        problem_for(pieces)  # build every NLP size class once, outside the timed loop
    build = time.perf_counter() - t0
    gen = TrajectoryGenerator(track, clearance=clearance, limits=limits)
    base = TrajectoryGenerator(track, clearance=clearance, limits=limits, optimize=False)
    rows = []
    skipped = 0
    for s, g in random_queries(track, clearance, n, seed):
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
                "fallback": tr.fallback,
                "reason": tr.fallback_reason,
                "wall": wall,
                **{k: tr.timings.get(k, 0.0) for k in STAGES},
                "ipopt_solve": tr.solver_stats.get("solve_time", 0.0),
                "shortcut": tr.solver_stats.get("shortcut_time", 0.0),
                "ipopt_iterations": tr.solver_stats.get("ipopt_iterations", 0),
                "corners": tr.solver_stats.get("n_corners", 0),
                "motion_time": tr.motion_time,
                "plan_time": b.motion_time,
                "lower_bound": lb,
                "toppra_duration": tr.solver_stats.get("toppra_duration", float("nan")),
            }
        )
    keys = ("wall", *STAGES, "ipopt_solve", "shortcut", "ipopt_iterations")
    arr = {k: np.array([r[k] for r in rows], dtype=float) for k in keys}
    mt = np.array([r["motion_time"] for r in rows])
    ptime = np.array([r["plan_time"] for r in rows])
    lb = np.array([r["lower_bound"] for r in rows])
    moving = ptime > 0
    ra = mt[moving] / ptime[moving]
    rb = mt[lb > 0] / lb[lb > 0]
    table = {
        "queries": len(rows),
        "skipped": skipped,
        "fallbacks": int(sum(r["fallback"] for r in rows)),
        "nlp_build_s": build,
        "time_ms": {
            k: (1e3 * float(np.median(v)), 1e3 * float(np.percentile(v, 95)))
            for k, v in arr.items()
            if k != "ipopt_iterations"
        },
        "ipopt_iterations": (
            float(np.median(arr["ipopt_iterations"])),
            float(np.percentile(arr["ipopt_iterations"], 95)),
        ),
        "ratio_vs_plan": (float(np.median(ra)), float(np.percentile(ra, 95)), float(np.max(ra))),
        "ratio_vs_lower_bound": (float(np.median(rb)), float(np.percentile(rb, 95)), float(np.max(rb))),
        "makespan_s": (float(np.median(mt)), float(np.percentile(mt, 95))),
    }
    return {"track": track.to_dict(), "clearance": clearance, "seed": seed, "table": table, "rows": rows}


def format_table(res: dict[str, object]) -> str:
    """A plain-text report of :func:`run`'s summary."""
    t = res["table"]
    assert isinstance(t, dict)
    lines = [
        f"track {res['track']}, clearance {res['clearance']}, seed {res['seed']}: {t['queries']} queries, "
        f"{t['fallbacks']} fallbacks, {t['skipped']} without motion; NLP builds {1e3 * t['nlp_build_s']:.0f} ms (once)",
        f"{'stage':<10} {'median ms':>10} {'p95 ms':>10}",
    ]
    for k, (med, p95) in t["time_ms"].items():
        lines.append(f"{k:<10} {med:>10.2f} {p95:>10.2f}")
    it = t["ipopt_iterations"]
    lines.append(f"IPOPT iterations: median {it[0]:.0f}, p95 {it[1]:.0f}")
    a, b, m = t["ratio_vs_plan"], t["ratio_vs_lower_bound"], t["makespan_s"]
    lines.append("(smooth = cells + ipopt_solve + checks + shortcut; retime = toppra; jerk = ruckig)")
    lines.append(f"makespan: median {m[0]:.2f} s, p95 {m[1]:.2f} s")
    lines.append(f"makespan / plan executed as is (a): median {a[0]:.3f}, p95 {a[1]:.3f}, max {a[2]:.3f}")
    lines.append(f"makespan / lower bound (b):         median {b[0]:.3f}, p95 {b[1]:.3f}, max {b[2]:.3f}")
    return "\n".join(lines)


def main(argv: Sequence[str] | None = None) -> int:
    """Command line entry point."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=120, help="number of queries (default 120)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--track", default="lollipop", choices=["lollipop", "circle"])
    ap.add_argument("--clearance", type=float, default=defaults.CLEARANCE)
    ap.add_argument("--json", default=None, help="write the raw numbers to this file")
    args = ap.parse_args(argv)
    res = run(args.n, args.seed, args.track, args.clearance)
    print(format_table(res))
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(res, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
