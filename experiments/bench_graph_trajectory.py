"""Verified trajectories on the example layouts: time per query and which stage answered.

For every ``examples/tracks/*.json`` layout, seeded random queries (positions uniform on the edges; queries without
a motion or with robots closer than D are skipped) through :class:`trajopt.TrajectoryGenerator` (graph planner with
the gate's margin, then the fast path, the corridor, the blended plan or the re-timed plan, and the gate). The time
is the wall time of ``generate`` (plan included) after one warm-up query per layout (free space and QP built).

Usage::

    PYTHONPATH=. python experiments/bench_graph_trajectory.py [--queries 40] [--clearance 0.1] [--seed 0]

Prints a Markdown table: layout, edges, queries, verified share, median and 90th percentile time (ms), shares of
the fast path, corridor ("hard"), blended plan ("blend") and fallback.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from mpa import GraphTrack
from mpa.errors import InvalidInputError, NoMotionError
from trajopt import TrajectoryGenerator

ROOT = Path(__file__).resolve().parents[1]


def run(path: Path, queries: int, clearance: float, seed: int) -> dict[str, object]:
    """Time ``queries`` verified trajectories on one layout."""
    track = GraphTrack.from_json(path)
    gen = TrajectoryGenerator(track, clearance=clearance)
    rng = np.random.default_rng(seed)

    def position() -> tuple[int, float]:
        e = int(rng.integers(0, track.n_edges))
        return e, float(rng.uniform(0.0, track.lengths[e]))

    times: list[float] = []
    kinds: dict[str, int] = {"fast": 0, "hard": 0, "blend": 0, "fallback": 0}
    verified = 0
    warm = False
    tries = 0
    while len(times) < queries and tries < 50 * queries:
        tries += 1
        q = ((position(), position()), (position(), position()))
        t0 = time.perf_counter()
        try:
            traj = gen.generate(*q)
        except (NoMotionError, InvalidInputError):
            continue
        dt = time.perf_counter() - t0
        if not warm:  # the first query builds the free space and the QP
            warm = True
            continue
        times.append(dt)
        verified += bool(traj.verification["ok"])
        kinds["fallback" if traj.fallback else str(traj.solver_stats.get("path"))] += 1
    n = max(1, len(times))
    return {
        "layout": path.stem,
        "edges": track.n_edges,
        "queries": len(times),
        "verified": verified / n,
        "median_ms": 1e3 * float(np.median(times)) if times else float("nan"),
        "p90_ms": 1e3 * float(np.percentile(times, 90)) if times else float("nan"),
        **{k: v / n for k, v in kinds.items()},
    }


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark and print the table."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--queries", type=int, default=40)
    ap.add_argument("--clearance", type=float, default=0.1)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)
    rows = [
        run(p, args.queries, args.clearance, args.seed) for p in sorted((ROOT / "examples" / "tracks").glob("*.json"))
    ]
    print(f"clearance {args.clearance:g} m, {args.queries} queries per layout, seed {args.seed}, defaults otherwise\n")
    print("| layout | edges | queries | verified | median ms | p90 ms | fast | hard | blend | fallback |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print(
            f"| {r['layout']} | {r['edges']} | {r['queries']} | {r['verified']:.0%} | {r['median_ms']:.1f} | "
            f"{r['p90_ms']:.1f} | {r['fast']:.0%} | {r['hard']:.0%} | {r['blend']:.0%} | {r['fallback']:.0%} |"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
