"""Planning and trajectories on the Open-RMF sample maps, with and without lane rules (docs/graphs.md, "Open-RMF maps").

For each map (the office, the hotel's three levels' graph 0) and each rule set (none; a seeded 30 % of the lanes
one-way and 30 % limited to 0.3 m/s) it plans ``--queries`` seeded random swaps and moves between named waypoints at
D = 0.3 m and reports: how many have a motion, the planner's wall time (median, 90th percentile), the plan's distance
from the optimum without the rules (``makespan / lower_bound - 1``: an upper bound of its distance from the optimum
under the rules), and the share of trajectories verified by the gate (rules checked on every row).

Usage: ``python experiments/bench_openrmf.py [--queries 20] [--seed 0]``.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

import mpa
from mpa.graph_track import GraphTrack
from trajopt import generate_trajectory
from trajopt.testing import random_rules

DATA = Path(__file__).resolve().parents[1] / "tests" / "data" / "openrmf"
MAPS = [("office", "office.building.yaml", "L1"), *[("hotel " + lv, "hotel.building.yaml", lv) for lv in ("L1", "L2")]]


def with_rules(track: GraphTrack, rng: np.random.Generator) -> GraphTrack:
    """The track with a seeded 30 % of its edges one-way (random direction kept) and 30 % limited to 0.3 m/s."""
    return random_rules(track.to_dict(), rng, oneway=0.3, limited=0.3, speed=0.3)


def run(track: GraphTrack, rng: np.random.Generator, queries: int, trajectories: bool) -> dict[str, float]:
    names = [str(v) for v in track.graph.vertices if not str(v).startswith("v")] or list(track.graph.vertices)
    times, gaps = [], []
    solved = verified = tried = 0
    for _ in range(queries):
        a, b, c, d = (names[i] for i in rng.choice(len(names), 4, replace=len(names) < 4))
        start, goal = ((a, b), (b, a)) if rng.random() < 0.5 else ((a, b), (c, d))
        try:
            t0 = time.perf_counter()
            plan = mpa.plan(track, start, goal, 0.3)
            times.append(time.perf_counter() - t0)
        except mpa.InvalidInputError:
            continue
        except mpa.NoMotionError:
            times.append(time.perf_counter() - t0)
            tried += 1
            continue
        tried += 1
        solved += 1
        if plan.lower_bound:
            gaps.append(plan.makespan / plan.lower_bound - 1.0)
        if trajectories:
            traj = generate_trajectory(track, start, goal, clearance=0.3)
            verified += bool(traj.verification["ok"])
    return {
        "queries": tried,
        "motion": solved,
        "median_ms": 1e3 * float(np.median(times)) if times else float("nan"),
        "p90_ms": 1e3 * float(np.percentile(times, 90)) if times else float("nan"),
        "gap_median": float(np.median(gaps)) if gaps else 0.0,
        "gap_max": float(np.max(gaps)) if gaps else 0.0,
        "verified": verified / solved if solved and trajectories else float("nan"),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--queries", type=int, default=20)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--no-trajectories", action="store_true")
    args = ap.parse_args()
    print("| map | rules | queries | motion | median ms | p90 ms | gap median | gap max | verified |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
    for label, file, level in MAPS:
        base = GraphTrack.from_file(DATA / file, level=level)
        rng = np.random.default_rng(args.seed)
        for rules, track in (("none", base), ("30 % one-way, 30 % at 0.3 m/s", with_rules(base, rng))):
            r = run(track, np.random.default_rng(args.seed), args.queries, not args.no_trajectories)
            print(
                f"| {label} | {rules} | {r['queries']} | {r['motion']} | {r['median_ms']:.1f} | {r['p90_ms']:.1f} | "
                f"{100 * r['gap_median']:.1f}% | {100 * r['gap_max']:.1f}% | {100 * r['verified']:.0f}% |"
            )


if __name__ == "__main__":
    main()
