"""Speed with footprints in the plane: free-space build, plan and verified trajectory on the example layouts.

``python experiments/bench_footprints.py [--queries N] [--seed S]``: per layout the build time of the planar free
space (:func:`mpa.planar_free_space`, a fresh build), then the median and 90th percentile of planning and of the
verified trajectory over N seeded random queries (refused queries, bodies overlapping at start or goal or no motion,
are counted, not timed). Times are the process's CPU time (single-threaded code: a shared machine inflates wall
times, not these); the first query of a layout includes the trajectory's own free space (bodies grown by the
gate's margin).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

import mpa
from mpa.planar import PlanarFreeSpace
from trajopt import generate_trajectory

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "tracks"
CASES = (("passing_loop.json", "2x1", 1.5), ("rail_yard.json", "2x0.8", 2.5), ("passing_loop.json", "0.5", 1.5))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--queries", type=int, default=20)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    for name, spec, clearance in CASES:
        tr = mpa.GraphTrack.from_json(EXAMPLES / name)
        t0 = time.process_time()
        space = PlanarFreeSpace(tr, clearance, spec)
        build = time.process_time() - t0
        plan_t, traj_t, refused = [], [], 0
        for _ in range(args.queries):
            q = []
            for _ in range(4):
                e = int(rng.integers(tr.n_edges))
                q.append((e, float(rng.uniform(0, tr.lengths[e]))))
            try:
                t0 = time.process_time()
                mpa.plan(tr, q[:2], q[2:], clearance, footprint=spec)
                plan_t.append(time.process_time() - t0)
                t0 = time.process_time()
                generate_trajectory(tr, q[:2], q[2:], clearance=clearance, footprint=spec)
                traj_t.append(time.process_time() - t0)
            except (mpa.InvalidInputError, mpa.NoMotionError):
                refused += 1
        pm = 1e3 * np.median(plan_t) if plan_t else float("nan")
        tm = 1e3 * np.median(traj_t) if traj_t else float("nan")
        print(
            f"{name:<18} {spec:<6} {tr.n_edges} edges, {len(space.pieces)} pieces: build {1e3 * build:.0f} ms; "
            f"plan median {pm:.1f} ms; trajectory median {tm:.0f} ms ({len(traj_t)} timed, {refused} refused)"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
