"""Speed of the paper's planner: single queries (plan + 400 path samples) and batch throughput.

Usage::

    python experiments/bench_planner.py [--queries 5000] [--seed 0] [--out results.json]
    python experiments/bench_planner.py --batch [--queries 100000] [--seed 0]

``--batch`` times :func:`mpa.plan_many` (domain + word of every query, median of 5 runs) against
``plan(...).domain`` / ``.word`` one by one (on the first 5 000 queries), and checks the answers agree.

Medians and 95th percentiles over seeded random queries, per track, all in one process. Also reports where the
time goes (validation, preliminary traces, skeleton routing, assembling routes, sampling).
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from mpa import Circle, Interval, Lollipop, make_planner
from mpa.errors import NoMotionError


def _states(track, n: int, rng: np.random.Generator, gap: float) -> np.ndarray:  # type: ignore[no-untyped-def]
    out = np.empty((0, 2))
    while len(out) < n:
        c = rng.uniform(0, np.nextafter(track.total_length, 0), (2 * n, 2))
        out = np.vstack([out, c[track.distance(c[:, 0], c[:, 1]) >= gap]])
    return out[:n]


def _feasible_queries(track, n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:  # type: ignore[no-untyped-def]
    """``n`` random starts and goals (robots at least 1 mm apart); on the interval the goal keeps the start's
    order (the robots cannot pass each other there)."""
    s, g = _states(track, n, rng, 1e-3), _states(track, n, rng, 1e-3)
    if isinstance(track, Interval):
        flip = np.sign(s[:, 1] - s[:, 0]) != np.sign(g[:, 1] - g[:, 0])
        g[flip] = g[flip][:, ::-1]
    return s, g


def bench(track, n: int, seed: int, samples: int = 400) -> dict[str, float]:  # type: ignore[no-untyped-def]
    """Time ``n`` single queries (plan, then ``samples`` samples of the path) on ``track``."""
    rng = np.random.default_rng(seed)
    planner = make_planner(track, clearance=0.0)
    s, g = _feasible_queries(track, n, rng)
    for i in range(min(200, n)):  # warm-up
        planner.plan(s[i], g[i]).sample(samples)
    t_plan, t_total = np.empty(n), np.empty(n)
    domains: dict[int, int] = {}
    for i in range(n):
        t0 = time.perf_counter()
        try:
            p = planner.plan(s[i], g[i])
        except NoMotionError:
            t_plan[i] = t_total[i] = np.nan
            continue
        t1 = time.perf_counter()
        p.sample(samples)
        t2 = time.perf_counter()
        t_plan[i], t_total[i] = t1 - t0, t2 - t0
        domains[p.domain] = domains.get(p.domain, 0) + 1
    t0 = time.perf_counter()
    for i in range(n):
        planner.plan(s[i], g[i])
    batch = time.perf_counter() - t0
    return {
        "track": repr(track),
        "queries": n,
        "plan_median_us": float(np.nanmedian(t_plan) * 1e6),
        "plan_p95_us": float(np.nanpercentile(t_plan, 95) * 1e6),
        "plan_and_samples_median_us": float(np.nanmedian(t_total) * 1e6),
        "plan_and_samples_p95_us": float(np.nanpercentile(t_total, 95) * 1e6),
        "batch_queries_per_s": n / batch,
        "domains": {str(k): v for k, v in sorted(domains.items())},
    }


def profile_stages(track, n: int, seed: int) -> dict[str, float]:  # type: ignore[no-untyped-def]
    """Where the time goes, by cProfile cumulative time per stage (fractions of the total)."""
    import cProfile
    import pstats

    rng = np.random.default_rng(seed)
    planner = make_planner(track)
    s, g = _states(track, n, rng, 1e-3), _states(track, n, rng, 1e-3)
    pr = cProfile.Profile()
    pr.enable()
    for i in range(n):
        planner.plan(s[i], g[i]).sample(400)
    pr.disable()
    st = pstats.Stats(pr)
    total = max(st.total_tt, 1e-12)  # type: ignore[attr-defined]
    wanted = {
        "validation": "validate_query",
        "preliminary traces": "lollipop_trace_scalar",
        "skeleton routing": "route_in_skeleton",
        "routes (lift + geodesic)": "build_plan",
        "homotopy word": "word_from_points",
        "sampling the path": "sample",
    }
    out = {}
    for label, fn in wanted.items():
        cum = sum(v[3] for k, v in st.stats.items() if k[2] == fn)  # type: ignore[attr-defined]
        out[label] = round(cum / total, 3)
    return out


def bench_batch(track, n: int, seed: int, repeats: int = 5) -> dict[str, float]:  # type: ignore[no-untyped-def]
    """Queries per second of ``plan_many`` (domain + word) and of ``plan`` one by one; the answers must agree."""
    from mpa import plan_many

    rng = np.random.default_rng(seed)
    planner = make_planner(track, clearance=0.0)
    s, g = _feasible_queries(track, n, rng)
    plan_many(track, s[:1000], g[:1000])  # warm-up
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        b = plan_many(track, s, g)
        times.append(time.perf_counter() - t0)
    m = min(n, 5000)
    t0 = time.perf_counter()
    ref = [planner.plan(s[i], g[i]) for i in range(m)]
    one = time.perf_counter() - t0
    same = all((int(b.domain[i]), b.word[i]) == (p.domain, p.word) for i, p in enumerate(ref))
    return {
        "track": repr(track),
        "queries": n,
        "batch_queries_per_s": n / float(np.median(times)),
        "one_by_one_queries_per_s": m / one,
        "agree_on_first": m if same else -1,
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--queries", type=int, default=5000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default=None, help="write the results as JSON here")
    ap.add_argument("--batch", action="store_true", help="time mpa.plan_many instead (default 100 000 queries)")
    args = ap.parse_args()
    tracks = (Lollipop(1.0, 1.0), Lollipop(0.3, 1.0), Circle(1.0), Interval(1.0))
    if args.batch:
        n = args.queries if args.queries != 5000 else 100_000
        brows = [bench_batch(t, n, args.seed) for t in tracks]
        print(f"{'track':<32}{'plan_many q/s':>15}{'one by one q/s':>16}{'agree':>8}")
        for r in brows:
            print(
                f"{r['track']:<32}{r['batch_queries_per_s']:>15.0f}{r['one_by_one_queries_per_s']:>16.0f}"
                f"{r['agree_on_first']:>8}"
            )
        if args.out:
            with open(args.out, "w") as f:
                json.dump({"batch": brows}, f, indent=2)
        return
    rows = [bench(t, args.queries, args.seed) for t in tracks]
    print(f"{'track':<32}{'plan med':>10}{'p95':>9}{'+400 smp med':>14}{'p95':>9}{'batch q/s':>11}")
    for r in rows:
        print(
            f"{r['track']:<32}{r['plan_median_us']:>9.0f}µ{r['plan_p95_us']:>8.0f}µ"
            f"{r['plan_and_samples_median_us']:>13.0f}µ{r['plan_and_samples_p95_us']:>8.0f}µ{r['batch_queries_per_s']:>11.0f}"
        )
    stages = profile_stages(Lollipop(1.0, 1.0), min(args.queries, 2000), args.seed)
    print("where the time goes (lollipop, cumulative fraction under cProfile):", stages)
    if args.out:
        with open(args.out, "w") as f:
            json.dump({"rows": rows, "stages": stages}, f, indent=2)


if __name__ == "__main__":
    main()
