"""Time and peak memory of :func:`trajopt.io.ros.write_mcap` on a long layout motion.

Draws the longest of six seeded warehouse queries (``examples/tracks/warehouse.json``, default limits), then writes
its bag at each ``--rates`` Hz ``--repeat`` times: the median wall and CPU time, and the peak of the Python heap
(``tracemalloc``, one further write) beside the rows and the file's size. Run it at two commits to compare writers;
the bag's bytes do not depend on the writer (``tests/reliability/test_reliability_mcap.py``).

    python experiments/bench_mcap.py --rates 100 1000
"""

from __future__ import annotations

import argparse
import json
import statistics
import tempfile
import time
import tracemalloc
from pathlib import Path

import numpy as np

from mpa import GraphTrack
from mpa.errors import MPAError
from trajopt import generate_trajectory
from trajopt.io.ros import write_mcap

ROOT = Path(__file__).resolve().parents[1]


def long_motion(seed: int, queries: int = 6):  # type: ignore[no-untyped-def]
    """The longest verified motion of ``queries`` seeded random warehouse queries."""
    track = GraphTrack.from_layout(json.loads((ROOT / "examples" / "tracks" / "warehouse.json").read_text()))
    rng = np.random.default_rng(seed)
    best = None
    for _ in range(queries):
        e = rng.integers(0, track.n_edges, 4)
        o = rng.uniform(0.0, 1.0, 4) * track.lengths[e]
        try:
            t = generate_trajectory(track, ((e[0], o[0]), (e[1], o[1])), ((e[2], o[2]), (e[3], o[3])))
        except MPAError:
            continue
        if best is None or t.makespan > best.makespan:
            best = t
    return best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rates", type=float, nargs="+", default=[100.0, 1000.0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--seed", type=int, default=3)
    args = ap.parse_args()
    traj = long_motion(args.seed)
    print(f"motion: {traj.makespan:.2f} s")
    with tempfile.TemporaryDirectory() as tmp:
        write_mcap(traj, Path(tmp) / "warm", rate=args.rates[0])  # rosbags' imports and typestore
        for rate in args.rates:
            walls, cpus = [], []
            for k in range(args.repeat):
                t0, c0 = time.perf_counter(), time.process_time()
                path = write_mcap(traj, Path(tmp) / f"bag{k}", rate=rate)
                walls.append(time.perf_counter() - t0)
                cpus.append(time.process_time() - c0)
            tracemalloc.start()
            write_mcap(traj, Path(tmp) / "traced", rate=rate)
            peak = tracemalloc.get_traced_memory()[1]
            tracemalloc.stop()
            rows = len(traj.resample(rate)[0])
            print(
                f"{rate:g} Hz: {rows} rows, {path.stat().st_size / 1e6:.1f} MB file; wall median "
                f"{statistics.median(walls):.2f} s, CPU median {statistics.median(cpus):.2f} s, "
                f"peak Python heap {peak / 1e6:.1f} MB"
            )


if __name__ == "__main__":
    main()
