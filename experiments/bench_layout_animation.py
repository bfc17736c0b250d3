"""Time per frame of the layout animation (``mpa animate --graph``) at the default size and dpi.

For each example query: the verified trajectory is made once, then the whole animation is written (GIF, 20 fps,
every frame of real time) and the wall and CPU time per frame are printed (the CPU time is what the animation
costs on an idle machine; the wall time also shows other processes sharing the cores).

Usage::

    python experiments/bench_layout_animation.py [--max-frames N]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from mpa import GraphTrack
from trajopt import TrajectoryGenerator
from trajopt.viz.layout_animation import animate_layout
from trajopt.viz.movie import frame_times

ROOT = Path(__file__).resolve().parents[1] / "examples" / "tracks"
QUERIES = [
    ("y_junction.json", 0.5, ("left", "right"), ("right", "left")),
    ("passing_loop.json", 0.3, ("W", "E"), ("E", "W")),
    ("two_sidings.json", 0.05, ("north_end", "south_end"), ("south_end", "north_end")),
    ("warehouse.json", 0.3, ("A1_X4", "dock6"), ("dock6", "A1_X4")),
]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max-frames", type=int, default=None, help="cap the frames (default: real time at 20 fps)")
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        for name, clearance, start, goal in QUERIES:
            track = GraphTrack.from_json(str(ROOT / name))
            traj = TrajectoryGenerator(track, clearance=clearance).generate(start, goal)
            p = traj.plan
            frames = len(frame_times(float(traj.t[0]), float(traj.t[-1]), 20.0, args.max_frames)[0])
            out = Path(tmp) / f"{name}.gif"
            w0, c0 = time.perf_counter(), time.process_time()
            animate_layout(
                track, p.route_a, p.route_b, traj.t, traj.s, out, clearance=clearance, max_frames=args.max_frames
            )
            wall, cpu = time.perf_counter() - w0, time.process_time() - c0
            from PIL import Image

            with Image.open(out) as im:
                size = im.size
            print(
                f"{name:<18} {frames:4d} frames {size[0]}x{size[1]} px: {1e3 * wall / frames:5.1f} ms/frame wall, "
                f"{1e3 * cpu / frames:5.1f} ms/frame CPU ({wall:.1f} s)"
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
