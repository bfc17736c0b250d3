"""Speed of the planar free space (footprints in the plane): build time per layout, plan median and tail.

``python experiments/bench_planar.py [--queries N] [--seed S] [--repeat R] [--random K]``: per layout and footprint
the build time of :class:`mpa.planar.PlanarFreeSpace` (a fresh build, the smallest of R), then the median and 95th
percentile of :func:`mpa.plan` with ``footprint=`` over N seeded random queries (the free space cached, as in a
session that plans many queries on one layout, and the search's sparse graph of moves with its landmarks built
beforehand: ``graph ms``, a cost paid once per layout and speeds by the first query that needs it); queries refused
(bodies overlapping at start or goal, no motion) are counted, not timed. The layouts: the Open-RMF office map (30
edges), the example layouts with many-point polylines (``circle``, ``lollipop``, ``figure_eight``,
``two_sidings``), the rail yard and the passing loop; with ``--random K`` also K seeded random layouts of 30 edges
of each kind of the scaling benchmark (``experiments/bench/graph_scale.py``: a warehouse aisle grid and a planar
road map, drawn in metres; seeds S, S+1, ...), each with a disc of 0.3 m and a 0.6 x 0.4 m rectangle. Times are
the process's CPU time (the code is single-threaded: the wall time on an idle machine; a shared machine inflates
wall times, not these).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

import mpa
from mpa.planar import PlanarFreeSpace

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench.graph_scale import KINDS

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples" / "tracks"
OFFICE = ROOT / "tests" / "data" / "openrmf" / "office.building.yaml"
CASES = (
    (OFFICE, "0.3", 0.5),
    (OFFICE, "0.6x0.4", 0.5),
    (EXAMPLES / "circle.json", "0.05", 0.2),
    (EXAMPLES / "lollipop.json", "0.05", 0.2),
    (EXAMPLES / "figure_eight.json", "0.5", 1.0),
    (EXAMPLES / "two_sidings.json", "1.5x0.8", 1.0),
    (EXAMPLES / "rail_yard.json", "2x0.8", 2.5),
    (EXAMPLES / "passing_loop.json", "2x1", 1.5),
)


def _query(tr: mpa.GraphTrack, rng: np.random.Generator) -> list[tuple[int, float]]:
    q = []
    for _ in range(4):
        e = int(rng.integers(tr.n_edges))
        q.append((e, float(rng.uniform(0, tr.lengths[e]))))
    return q


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--queries", type=int, default=100)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--random", type=int, default=0, help="also this many random 30-edge layouts (seeded)")
    args = ap.parse_args(argv)
    cases: list[tuple[str, mpa.GraphTrack, str, float]] = [
        (path.name.split(".")[0], mpa.GraphTrack.from_file(path), spec, clearance) for path, spec, clearance in CASES
    ]
    for k in range(args.random):
        for kind, make in KINDS.items():
            tr = make(30, args.seed + k)
            cases += [(f"{kind} 30 #{k}", tr, "0.3", 0.5), (f"{kind} 30 #{k}", tr, "0.6x0.4", 0.5)]
    print(
        f"{'layout':<22} {'footprint':<9} {'edges':>5} {'pieces':>6} {'build ms':>9} {'plan med':>9} "
        f"{'graph ms':>8} {'plan p95':>9} {'timed':>5} {'refused':>7}"
    )
    for name, tr, spec, clearance in cases:
        builds = []
        for _ in range(args.repeat):
            t0 = time.process_time()
            space = PlanarFreeSpace(tr, clearance, spec)
            builds.append(time.process_time() - t0)
        rng = np.random.default_rng(args.seed)
        plan_t, refused = [], 0
        cached = mpa.planar.planar_free_space(tr, clearance, spec)  # the cached build the queries use
        t0 = time.process_time()
        cached.search_graph("fastest", *mpa.planar._cell_speeds(tr, 1.0, 1.0)).landmarks()
        graph_ms = 1e3 * (time.process_time() - t0)
        for _ in range(args.queries):
            q = _query(tr, rng)
            try:
                t0 = time.process_time()
                mpa.plan(tr, q[:2], q[2:], clearance, footprint=spec)
                plan_t.append(time.process_time() - t0)
            except (mpa.InvalidInputError, mpa.NoMotionError):
                refused += 1
        med = 1e3 * float(np.median(plan_t)) if plan_t else float("nan")
        p95 = 1e3 * float(np.percentile(plan_t, 95)) if plan_t else float("nan")
        print(
            f"{name:<22} {spec:<9} {tr.n_edges:>5} {len(space.pieces):>6} "
            f"{1e3 * min(builds):>9.0f} {med:>9.1f} {graph_ms:>8.0f} {p95:>9.1f} {len(plan_t):>5} {refused:>7}",
            flush=True,
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
