"""Time of the margins (tracking margin, delay tolerance) and of ``mpa trajectory`` end to end on long motions.

Two carts swap ends of a 160 m layout (two 60 m spurs joined by a 40 m link and a 60 m siding) at a speed limit
chosen for the makespan (about 36 s, 360 s, 3 600 s), and two swaps on the example warehouse at 0.2 m/s. For each:
the makespan, the rows at 100 Hz, :func:`trajopt.analysis.margins.margins` in-process (median of ``--repeat``) and the
wall time of ``python -m trajopt.cli trajectory ... --out DIR`` (process start to files written, one run).

    python experiments/bench_margins.py [--repeat 3] [--no-cli]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from mpa.graph_track import GraphTrack  # noqa: E402
from trajopt.analysis.margins import margins  # noqa: E402
from trajopt.generator import TrajectoryGenerator  # noqa: E402
from trajopt.timing import Limits  # noqa: E402

LONG = {"edges": [["a0", "a1", 60.0], ["b0", "b1", 60.0], ["a1", "b1", 40.0], ["a1", "c", 30.0], ["c", "b1", 30.0]]}
WAREHOUSE = ROOT / "examples" / "tracks" / "warehouse.json"
CASES = [
    ("spurs, swap, vmax 5", "long", ("a0", "b0"), ("b0", "a0"), 5.0),
    ("spurs, swap, vmax 0.5", "long", ("a0", "b0"), ("b0", "a0"), 0.5),
    ("spurs, swap, vmax 0.05", "long", ("a0", "b0"), ("b0", "a0"), 0.05),
    ("warehouse, neighbours swap, vmax 0.2", "warehouse", ("A1_X1", "A2_X1"), ("A2_X1", "A1_X1"), 0.2),
    ("warehouse, corners swap, vmax 0.2", "warehouse", ("A1_X1", "A5_X4"), ("A5_X4", "A1_X1"), 0.2),
]
CLEARANCE = 0.6


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-cli", action="store_true", help="skip the command line's wall time")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        long_path = Path(tmp) / "spurs.json"
        long_path.write_text(json.dumps(LONG))
        files = {"long": long_path, "warehouse": WAREHOUSE}
        print("| motion | makespan (s) | rows | margins (s) | delay tolerance (s) | mpa trajectory wall (s) |")
        print("|---|---|---|---|---|---|")
        for name, layout, start, goal, vmax in CASES:
            track = GraphTrack.from_json(files[layout])
            gen = TrajectoryGenerator(track, clearance=CLEARANCE, limits=Limits(vmax, 0.5, 1.0), rate=100.0)
            traj = gen.generate(tuple(track.position(p) for p in start), tuple(track.position(p) for p in goal))
            times = []
            for _ in range(args.repeat):
                traj.__dict__.pop("_margins", None)
                t0 = time.perf_counter()
                m = margins(traj)
                times.append(time.perf_counter() - t0)
            wall = "-"
            if not args.no_cli:
                cmd = [sys.executable, "-m", "trajopt.cli", "trajectory", "--graph", str(files[layout])]
                cmd += ["--start", *start, "--goal", *goal, "--clearance", str(CLEARANCE), "--vmax", str(vmax)]
                cmd += ["--amax", "0.5", "--jmax", "1.0", "--out", str(Path(tmp) / "out")]
                t0 = time.perf_counter()
                env = {**os.environ, "PYTHONPATH": str(ROOT)}
                subprocess.run(cmd, check=True, capture_output=True, cwd=ROOT, env=env)
                wall = f"{time.perf_counter() - t0:.2f}"
            print(
                f"| {name} | {traj.makespan:.1f} | {len(traj.t)} | {statistics.median(times):.3f} | "
                f"{m.delay_tolerance:.4g} | {wall} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
